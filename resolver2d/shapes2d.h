// resolver2d/shapes2d.h — planar rotations, transforms, bounding boxes and the convex shapes of the 2D world.
//
// Owns: Rot2 (a rotation stored as cosine/sine, never as an angle), Transform2, Aabb2, the shapes (circle, convex
// polygon of 3..8 vertices, two-sided segment), their validating constructors, mass properties and AABBs.
//
// Invariants:
//   - A shape made by makeCircle / makeBox / makePolygon / makeSegment is fully valid or the call fails with a
//     message and leaves *out untouched: finite coordinates, radius > 0, polygon vertices counter-clockwise and
//     strictly convex, normals[i] the outward unit normal of the edge vertices[i] -> vertices[(i + 1) % count].
//   - Shape geometry is in the body frame (metres); MassData::center is in the body frame too.
//   - No libm transcendental is called: angles go through core/det_math (DESIGN.md "Determinism rules").
#pragma once

#include "dim2.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace unison {

/// A rotation about z stored as (cos, sin); |(c, s)| = 1 up to rounding. The identity by default.
struct Rot2 {
    double c = 1.0;  ///< cosine of the angle
    double s = 0.0;  ///< sine of the angle
};

/// The rotation by `angle` radians (deterministic dmath::sincos).
Rot2 makeRot(double angle);

/// q applied to v: (c x - s y, s x + c y).
inline Vec2 rotate(Rot2 q, Vec2 v) { return {q.c * v.x - q.s * v.y, q.s * v.x + q.c * v.y}; }

/// The inverse of q applied to v: (c x + s y, -s x + c y).
inline Vec2 invRotate(Rot2 q, Vec2 v) { return {q.c * v.x + q.s * v.y, -q.s * v.x + q.c * v.y}; }

/// q advanced by a small angle: (c, s) + deltaAngle (-s, c), then normalised (Box2D v3's integration).
Rot2 integrateRotation(Rot2 q, double deltaAngle);

/// The angle of q in [-pi, pi] (deterministic dmath::atan2).
double angleOf(Rot2 q);

/// A rigid transform: x_world = p + q x_local.
struct Transform2 {
    Vec2 p;  ///< translation (m)
    Rot2 q;  ///< rotation
};

/// The body-frame point `local` in world coordinates.
inline Vec2 transformPoint(const Transform2& xf, Vec2 local) { return xf.p + rotate(xf.q, local); }

/// The world point `world` in the frame of xf.
inline Vec2 invTransformPoint(const Transform2& xf, Vec2 world) { return invRotate(xf.q, world - xf.p); }

/// An axis-aligned box (m); valid when lower <= upper componentwise.
struct Aabb2 {
    Vec2 lower;  ///< minimum corner
    Vec2 upper;  ///< maximum corner
};

/// True when a and b share at least one point (touching boxes overlap).
inline bool overlaps(const Aabb2& a, const Aabb2& b) {
    return a.lower.x <= b.upper.x && b.lower.x <= a.upper.x && a.lower.y <= b.upper.y && b.lower.y <= a.upper.y;
}

/// A solid disc.
struct Circle {
    Vec2 center;          ///< body frame (m)
    double radius = 0.0;  ///< m, > 0
};

/// Largest vertex count of a polygon.
constexpr int kMaxPolygonVertices = 8;

/// A solid convex polygon: counter-clockwise vertices, outward unit edge normals.
struct Polygon {
    int count = 0;                                      ///< number of vertices, 3..kMaxPolygonVertices
    std::array<Vec2, kMaxPolygonVertices> vertices{};   ///< body frame (m), counter-clockwise
    std::array<Vec2, kMaxPolygonVertices> normals{};    ///< normals[i]: outward unit normal of edge i -> i+1
    Vec2 centroid;                                      ///< area centroid, body frame (m)
};

/// A two-sided line segment without thickness; massless, meant for static ground.
struct Segment {
    Vec2 p1;  ///< first end point, body frame (m)
    Vec2 p2;  ///< second end point, body frame (m)
};

/// Which member of Shape2 is meaningful.
enum class ShapeType : std::uint8_t { circle, polygon, segment };

/// A shape with its material; only the geometry member named by `type` is meaningful.
struct Shape2 {
    ShapeType type = ShapeType::circle;  ///< selects circle, polygon or segment
    Circle circle;                       ///< geometry when type == circle
    Polygon polygon;                     ///< geometry when type == polygon
    Segment segment;                     ///< geometry when type == segment
    double density = 1.0;                ///< kg / m^2
    double friction = 0.6;               ///< Coulomb coefficient
    double restitution = 0.0;            ///< coefficient of restitution e
};
static_assert(sizeof(Shape2) == 368, "Shape2 changed: serialise the new field (world2d_state.cpp)");

/// A Shape2 holding `c` with default material.
Shape2 toShape(const Circle& c);
/// A Shape2 holding `p` with default material.
Shape2 toShape(const Polygon& p);
/// A Shape2 holding `s` with default material.
Shape2 toShape(const Segment& s);

/// Builds a circle; error (and *out untouched) unless center is finite and radius finite and > 0.
std::string makeCircle(Vec2 center, double radius, Circle* out);

/// Builds the box of half extents hx, hy (m) centred at `center`, rotated by `angle`; hx, hy finite > 0.
std::string makeBox(double hx, double hy, Vec2 center, double angle, Polygon* out);

/// Builds a polygon from 3..8 counter-clockwise, strictly convex, distinct finite points (kept in the given order).
std::string makePolygon(const std::vector<Vec2>& points, Polygon* out);

/// Builds a segment from two distinct finite points.
std::string makeSegment(Vec2 p1, Vec2 p2, Segment* out);

/// Mass properties of a shape.
struct MassData {
    double mass = 0.0;     ///< kg
    Vec2 center;           ///< centre of mass, body frame (m)
    double inertia = 0.0;  ///< moment of inertia about the centre of mass (kg m^2)
};

/// Mass, centre of mass and inertia of s at its density; segments have zero mass (static ground only).
MassData computeMass(const Shape2& s);

/// World-space bounding box of s placed by xf.
Aabb2 computeAabb(const Shape2& s, const Transform2& xf);

}  // namespace unison
