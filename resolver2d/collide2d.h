// resolver2d/collide2d.h — narrowphase: contact manifolds between two placed 2D shapes.
//
// Owns: Manifold2 / ManifoldPoint2 and the pairwise routines behind collide(): circle–circle, circle–polygon,
// polygon–polygon (separating axes plus clipping of the incident edge, Gottschalk / Catto), circle–segment and
// polygon–segment (the segment treated as a two-vertex polygon without thickness).
//
// Conventions (the seed paper's contact node, DESIGN.md step 5):
//   - `normal` is a world-space unit vector pointing AWAY FROM shape B TOWARDS shape A, so body A receives +f n.
//   - Each point lies midway between the two surfaces; `separation` is their gap along the normal (m), < 0 when
//     they overlap. Only points with separation < speculativeDistance are returned (at most 2).
//   - `id` names the pair of features that made the point (see makeFeatureId) and does not change from step to
//     step while the same features touch; the world matches warm starts through it.
// Invariants: the result is a pure function of the inputs (index-order loops, fixed tie-breaking, no libm
// transcendental); segment–segment pairs never collide (static ground against static ground).
#pragma once

#include "shapes2d.h"

#include <array>
#include <cstdint>

namespace unison {

/// One contact point of a manifold.
struct ManifoldPoint2 {
    Vec2 point;               ///< world position midway between the two surfaces (m)
    double separation = 0.0;  ///< gap along the normal (m); negative when overlapping
    std::uint32_t id = 0;     ///< stable feature id (makeFeatureId)
};

/// The contact manifold of one shape pair.
struct Manifold2 {
    Vec2 normal;                            ///< world unit normal, from shape B towards shape A
    int count = 0;                          ///< number of valid points, 0..2
    std::array<ManifoldPoint2, 2> points{};  ///< points[0 .. count-1]
};

/// What kind of feature pair produced a manifold point (bits 24..30 of its id).
enum class FeatureKind : std::uint8_t {
    circles = 1,       ///< circle against circle
    circleFace = 2,    ///< circle against the face `reference` of a polygon or segment
    circleVertex = 3,  ///< circle against the vertex `incident` of a polygon or segment
    faceEdge = 4,      ///< the end of the incident edge at reference vertex `side` of reference face `reference`;
                       ///< `incident` is the incident vertex at that end (the point is it, or it cut by the side plane)
};

/// Packs a feature id: bit 31 flip (1 when the reference face belongs to shape B), bits 24..30 kind,
/// bits 16..23 reference feature (face index, 0 for circles), bits 8..15 incident feature (vertex index),
/// bits 0..7 side vertex (reference vertex at that end of the face, faceEdge only).
constexpr std::uint32_t makeFeatureId(FeatureKind kind, int reference, int incident, int side, bool flip) {
    return (flip ? 0x80000000u : 0u) | (static_cast<std::uint32_t>(kind) << 24) |
           ((static_cast<std::uint32_t>(reference) & 0xFFu) << 16) |
           ((static_cast<std::uint32_t>(incident) & 0xFFu) << 8) | (static_cast<std::uint32_t>(side) & 0xFFu);
}

/// The kind packed in a feature id.
constexpr FeatureKind featureKind(std::uint32_t id) { return static_cast<FeatureKind>((id >> 24) & 0x7Fu); }

/// Contact manifold of shape a placed by xfA against shape b placed by xfB; points with separation below
/// speculativeDistance (m, >= 0) are kept, so contacts about to close are included.
Manifold2 collide(const Shape2& a, const Transform2& xfA, const Shape2& b, const Transform2& xfB,
                  double speculativeDistance);

/// Circle a against circle b (normal from b to a). Coincident centres use the normal (0, 1).
Manifold2 collideCircles(const Circle& a, const Transform2& xfA, const Circle& b, const Transform2& xfB,
                         double speculativeDistance);

/// Circle a against polygon b (normal from the polygon to the circle).
Manifold2 collideCircleAndPolygon(const Circle& a, const Transform2& xfA, const Polygon& b, const Transform2& xfB,
                                  double speculativeDistance);

/// Circle a against segment b (normal from the segment to the circle). A centre on the segment uses its left normal.
Manifold2 collideCircleAndSegment(const Circle& a, const Transform2& xfA, const Segment& b, const Transform2& xfB,
                                  double speculativeDistance);

/// Polygon a against polygon b by separating axes and clipping (up to 2 points).
Manifold2 collidePolygons(const Polygon& a, const Transform2& xfA, const Polygon& b, const Transform2& xfB,
                          double speculativeDistance);

/// Polygon a against segment b, the segment taken as a two-vertex polygon (up to 2 points).
Manifold2 collidePolygonAndSegment(const Polygon& a, const Transform2& xfA, const Segment& b, const Transform2& xfB,
                                   double speculativeDistance);

/// The same manifold seen from the other shape: the normal is negated, points, separations and ids are kept.
Manifold2 swapped(const Manifold2& m);

}  // namespace unison
