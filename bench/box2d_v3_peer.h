// bench/box2d_v3_peer.h — Box2D v3.2 as an optional benchmark peer of the 2D world.
//
// Owns: a Box2D v3 world built from the same scene JSON that scenes::loadScene2 reads, stepped the way its own
// benchmarks step it: 4 substeps, one worker (no threads), sleeping from the scene's "sleep" key (the benchmarks
// turn it off). Box2D v3 is not a dependency: its sources are an optional peer folder (PEER.md there), built by
// CMake only when the folder exists (bench/CMakeLists_box2d_v3.txt), and this file is the only one that includes
// its headers (box2d_v3_peer.cpp; this header names none of its types).
//
// The translation is one to one, with Box2D v3's own rules where they differ from Unison's: gravity; bodies
// (static / kinematic / dynamic, origin, rotation b2MakeRot(angle), velocities; Box2D v3 takes the origin's linear
// velocity, equal to the centre of mass's for the scenes that start moving, whose shapes are centred); shapes
// (circle; box -> b2MakeOffsetBox; polygon -> b2ComputeHull + b2MakePolygon with radius 0; segment) with density,
// friction and restitution; "restitution_threshold" -> b2WorldDef::restitutionThreshold. Box2D v3 mixes friction as
// sqrt(f1 f2) and restitution as max(e1, e2), as Unison does. Its solver is soft-step sequential impulses with
// relaxation, in float; its polygons have no skin.
#pragma once

#include "dim2.h"
#include "json_fields.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace unison::bench {

/// One 2D scene built in Box2D v3.2. Not copyable (owns the world).
class Box2dV3Peer {
public:
    /// Builds the world from scene JSON (`what` names the source in messages); throws jsonio::JsonError for a 3D
    /// or malformed scene. `subSteps`: Box2D v3's substep count per step.
    explicit Box2dV3Peer(const nlohmann::json& scene, const std::string& what = "scene", int subSteps = 4);
    ~Box2dV3Peer();
    Box2dV3Peer(const Box2dV3Peer&) = delete;
    Box2dV3Peer& operator=(const Box2dV3Peer&) = delete;

    /// Advances by one step: b2World_Step(world, 1 / hz, subSteps).
    void step();
    /// Number of bodies, equal to the scene's "bodies" array.
    int bodyCount() const;
    /// Body origin (m) of scene body `index`.
    Vec2 position(int index) const;
    /// Body angle (rad) of scene body `index`, in [-pi, pi].
    double angle(int index) const;

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

}  // namespace unison::bench
