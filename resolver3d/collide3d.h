// resolver3d/collide3d.h — narrowphase: contact manifolds between two placed 3D shapes.
//
// Owns: Manifold3 / ManifoldPoint3 and collide(): sphere–sphere, sphere–polyhedron (closest feature), polyhedron–
// polyhedron (separating axes over face normals and Gauss-map-pruned edge pairs, then clipping of the incident face
// against the reference face's side planes), anything–plane, and meshes through their sphere trees (the seed
// paper's model: many candidate points from the tree's leaves, reduced to at most 4).
//
// Conventions (the paper's contact node, DESIGN.md step 5):
//   - every point carries a world unit normal pointing AWAY FROM shape B TOWARDS shape A (convex pairs share one
//     normal; sphere-tree points keep the normal of the surface they were found against);
//   - the point lies midway between the two surfaces; `separation` is the gap along the normal (m), < 0 when
//     overlapping; only points with separation < speculativeDistance are returned, at most 4;
//   - `id` names the features that made the point and stays the same from step to step while they touch.
// Invariants: a pure function of its inputs (index-order loops, total tie-breaking, no libm transcendental);
// plane–plane and plane-only pairs never collide.
#pragma once

#include "shapes3d.h"

#include <array>
#include <cstdint>
#include <vector>

namespace unison {

/// One contact point.
struct ManifoldPoint3 {
    Vec3 point = Vec3::Zero();   ///< world position midway between the surfaces (m)
    Vec3 normal = Vec3::UnitZ(); ///< world unit normal from B towards A
    double separation = 0.0;     ///< gap along the normal (m); negative when overlapping
    std::uint32_t id = 0;        ///< stable feature id
};

/// The contact manifold of one shape pair (at most 4 points).
struct Manifold3 {
    int count = 0;
    int candidates = 0;  ///< points considered before the reduction to 4 (sphere-tree pairs can find hundreds)
    std::array<ManifoldPoint3, 4> points{};
};

/// Contact manifold of shape a placed by xfA against shape b placed by xfB. When outCandidates is given, every
/// candidate point considered before the reduction to 4 is appended to it (for drawing, as in the paper's fig. 5).
Manifold3 collide(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB,
                  double speculativeDistance, std::vector<ManifoldPoint3>* outCandidates = nullptr);

/// While one of these lives (at most one per thread at a time), collide() remembers the last few polyhedra it
/// placed in the world and reuses a placement for the same polyhedron and the same transform bits: a pile's cube
/// meets several neighbours in a row of broadphase pairs. World3::step opens one per step (shapes do not change
/// within a step). The answers are the same bits with or without it.
class CollideBatch {
public:
    CollideBatch();
    ~CollideBatch();
    CollideBatch(const CollideBatch&) = delete;
    CollideBatch& operator=(const CollideBatch&) = delete;
};

/// The paper's reduction: of many candidate points keep at most 4 — the deepest, then the one farthest from it,
/// then the one that makes the largest triangle, then the one that adds the most area. Only points that overlap or
/// lie within 5 mm of the deepest compete for the area (speculative points farther out would span a support that
/// holds nothing yet). Ties go to the lower index.
std::vector<ManifoldPoint3> reduceToFour(const std::vector<ManifoldPoint3>& candidates);

}  // namespace unison
