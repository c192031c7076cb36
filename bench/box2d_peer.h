// bench/box2d_peer.h — Box2D 2.4.1 (libbox2d-dev) as a benchmark and validation peer of the 2D world.
//
// Owns: a b2World built from the same scene JSON that scenes::loadScene2 reads (docs/formats.md), and the map
// from scene body index to b2Body*. The translation is one to one: gravity; bodies (static / kinematic / dynamic,
// origin, angle, centre-of-mass and angular velocity); shapes (circle -> b2CircleShape centred at `center`; box -> SetAsBox(hx, hy, center,
// angle); polygon -> Set(vertices); segment -> two-sided b2EdgeShape) with their density, friction and restitution;
// "sleep" -> SetAllowSleeping; "restitution_threshold" (default 1 m/s) -> every fixture's restitutionThreshold
// (Box2D mixes the per-fixture thresholds with min, so equal values give the scene's threshold). Friction and
// restitution mix in Box2D as sqrt(f1 f2) and max(e1, e2), the rules Unison follows.
//
// Differences that remain, by design of Box2D: it computes in float; polygons and edges carry a 1 cm skin
// (b2_polygonRadius), so boxes rest about 2 * 0.01 - 0.005 m apart where Unison's rest touching; its solver is
// sequential impulses (8 velocity, 3 position iterations by default, as in its testbed), not one LCP per island;
// it caps a body's motion per step (b2_maxTranslation 2 m, i.e. 120 m/s at 60 Hz; b2_maxRotation 0.5 pi).
// Box2D headers are only included by box2d_peer.cpp; this header forward-declares the two types it names.
#pragma once

#include "dim2.h"
#include "json_fields.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

class b2World;
class b2Body;

namespace unison::bench {

/// A scene the peer cannot build; what() names the key, like scenes::SceneError.
using Box2dSceneError = jsonio::JsonError;

/// One 2D scene built in Box2D 2.4.1. Not copyable (owns the b2World).
class Box2dPeer {
public:
    /// Builds the world from scene JSON (`what` names the source in messages). Throws Box2dSceneError for a 3D
    /// scene or a malformed one (the same keys loadScene2 reads; validation of geometry is left to loadScene2).
    explicit Box2dPeer(const nlohmann::json& scene, const std::string& what = "scene", int velocityIterations = 8,
                       int positionIterations = 3);
    ~Box2dPeer();
    Box2dPeer(const Box2dPeer&) = delete;
    Box2dPeer& operator=(const Box2dPeer&) = delete;

    /// Advances by one step: world->Step(1 / hz, velocityIterations, positionIterations).
    void step();

    /// Number of bodies, equal to the scene's "bodies" array.
    int bodyCount() const { return int(mBodies.size()); }
    /// Body origin (m) of scene body `index`.
    Vec2 position(int index) const;
    /// Body angle (rad) of scene body `index`, as Box2D accumulates it (not wrapped to [-pi, pi]).
    double angle(int index) const;
    /// Centre-of-mass velocity (m/s) of scene body `index`.
    Vec2 linearVelocity(int index) const;
    /// Angular velocity (rad/s) of scene body `index`.
    double angularVelocity(int index) const;
    /// False once Box2D has put the body to sleep.
    bool awake(int index) const;
    /// The Box2D body of scene body `index` (owned by the world).
    b2Body* body(int index) const { return mBodies.at(std::size_t(index)); }
    b2World& world() { return *mWorld; }
    const b2World& world() const { return *mWorld; }
    double hz() const { return mHz; }
    int stepCount() const { return mSteps; }

private:
    std::unique_ptr<b2World> mWorld;
    std::vector<b2Body*> mBodies;  // scene index -> body (owned by mWorld)
    double mHz = 60.0;
    int mVelocityIterations = 8;
    int mPositionIterations = 3;
    int mSteps = 0;
};

}  // namespace unison::bench
