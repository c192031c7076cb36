// resolver3d/query3d.h — scene queries of the 3D world: ray casts and overlaps, exact on every shape type.
//
// Owns: RayHit3 and the exact tests on one placed shape that World3's queries (query3d.cpp) run on the shapes
// their tree visits: rayCastShape (segment against sphere, box, hull, plane or mesh) and shapesOverlap.
// Conventions: every shape is solid (a plane is the half-space normal . x <= offset, a closed mesh the volume it
// bounds): a ray that starts inside one hits it at fraction 0 with the normal against the ray. Two shapes overlap
// when they share interior points (touching does not count). The query shape of an overlap is convex (sphere, box
// or hull); the shapes it is tested against may be of any type.
// Invariants: pure functions of their arguments (no libm transcendental, fixed evaluation order).
#pragma once

#include "body_store.h"
#include "shapes3d.h"

namespace unison {

/// One shape hit by a ray.
struct RayHit3 {
    BodyId body;                  ///< the body hit
    int shape = 0;                ///< index of the shape in the body
    Vec3 point = Vec3::Zero();    ///< world point where the ray meets the shape (m)
    Vec3 normal = Vec3::UnitY();  ///< unit surface normal there, against the ray
    double fraction = 0.0;        ///< point = origin + fraction * translation, in [0, 1]
};

/// The segment origin + t translation, t in [0, 1], against shape s placed by xf: the smallest t where it meets
/// the shape and the unit normal there. False when it misses (also for a zero translation).
bool rayCastShape(const Shape3& s, const Transform3& xf, const Vec3& origin, const Vec3& translation,
                  double* outFraction, Vec3* outNormal);

/// True when the convex shape a (sphere, box or hull) placed by xfA and shape b placed by xfB share interior
/// points; false when a is a plane or a mesh.
bool shapesOverlap(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB);

/// True when the world point p is strictly inside shape s placed by xf (used by the overlap tests and their tests).
bool containsPoint(const Shape3& s, const Transform3& xf, const Vec3& p);

}  // namespace unison
