// resolver2d/query2d.h — scene queries of the 2D world: ray casts and overlaps, exact on every shape type.
//
// Owns: RayHit2 and the exact tests on one placed shape that World2's queries (query2d.cpp) run on the shapes
// their tree visits: rayCastShape (segment against circle, polygon or segment) and shapesOverlap.
// Conventions: circles and polygons are solid: a ray that starts inside one hits it at fraction 0 with the normal
// against the ray; a segment is hit from either side, its normal facing the ray's origin. Two shapes overlap when
// they share interior points (touching does not count); a segment overlaps what it crosses the interior of, and
// two segments overlap when they cross at one point.
// Invariants: pure functions of their arguments (no libm transcendental, fixed evaluation order).
#pragma once

#include "body_store.h"
#include "shapes2d.h"

namespace unison {

/// One shape hit by a ray.
struct RayHit2 {
    BodyId body;             ///< the body hit
    int shape = 0;           ///< index of the shape in the body
    Vec2 point;              ///< world point where the ray meets the shape (m)
    Vec2 normal;             ///< unit surface normal there, against the ray
    double fraction = 0.0;   ///< point = origin + fraction * translation, in [0, 1]
};

/// The segment origin + t translation, t in [0, 1], against shape s placed by xf: the smallest t where it meets
/// the shape and the unit normal there. False when it misses (also for a zero translation).
bool rayCastShape(const Shape2& s, const Transform2& xf, Vec2 origin, Vec2 translation, double* outFraction,
                  Vec2* outNormal);

/// True when shape a placed by xfA and shape b placed by xfB share interior points (see the conventions above).
bool shapesOverlap(const Shape2& a, const Transform2& xfA, const Shape2& b, const Transform2& xfB);

}  // namespace unison
