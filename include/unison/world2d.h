// unison/world2d.h — the 2D world of Unison's C++ API: rigid bodies with circles, boxes, convex polygons and
// segments, stepped at a fixed rate with every contact of an island resolved at once by one LCP (Lemke's method).
//
// Guarantees: every result (positions, velocities, events, query answers, the state hash) is the same bits on
// every machine and for any build of the library with the documented flags, given the same calls in the same
// order. A call with a bad argument (stale id, NaN, invalid shape) fails and leaves the world unchanged.
// Units: metres, seconds, kilograms, radians; impulses in N s. y is up (default gravity (0, -10)).
#pragma once

#include <unison/world.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace unison {

/// A 2D vector (m, m/s or a unit direction, by context).
struct Vec2D {
    double x = 0.0;
    double y = 0.0;
};

/// The shape kinds of the 2D world.
enum class ShapeKind2D : std::uint8_t { circle, box, polygon, segment };

/// A shape of a 2D body, in body coordinates, with its material. The named constructors set the geometry.
struct ShapeDef2D {
    ShapeKind2D kind = ShapeKind2D::circle;  ///< which geometry fields are used
    Vec2D center;                            ///< circle or box centre (m)
    double radius = 0.5;                     ///< circle radius (m), > 0
    Vec2D halfExtents{0.5, 0.5};             ///< box half width and half height (m), > 0
    double angle = 0.0;                      ///< box rotation in the body frame (rad)
    /// polygon: 3..8 counter-clockwise points of a strictly convex outline; segment: its two end points (m).
    std::vector<Vec2D> points;
    double density = 1.0;      ///< kg/m^2 (segments are massless: static ground)
    double friction = 0.6;     ///< Coulomb coefficient; a contact uses sqrt(f1 f2)
    double restitution = 0.0;  ///< coefficient of restitution; a contact uses max(e1, e2)

    /// A solid disc.
    static ShapeDef2D circle(Vec2D center, double radius);
    /// A solid box of half extents (hx, hy) centred at `center`, turned by `angle`.
    static ShapeDef2D box(double hx, double hy, Vec2D center = {}, double angle = 0.0);
    /// A solid convex polygon (3..8 counter-clockwise points).
    static ShapeDef2D polygon(std::vector<Vec2D> points);
    /// A two-sided segment without thickness, for static bodies.
    static ShapeDef2D segment(Vec2D a, Vec2D b);
};

/// How to create a body.
struct BodyDef2D {
    BodyType type = BodyType::dynamicBody;  ///< static, kinematic or dynamic
    Vec2D position;                         ///< origin of the body frame (m)
    double angle = 0.0;                     ///< rad
    Vec2D linearVelocity;                   ///< of the centre of mass (m/s)
    double angularVelocity = 0.0;           ///< rad/s
};

/// World settings; the defaults are the engine's tuned values.
struct WorldDef2D {
    Vec2D gravity{0.0, -10.0};  ///< m/s^2
    double hz = 60.0;           ///< steps per second (> 0)
    bool enableSleep = true;    ///< bodies of islands at rest for 0.5 s stop being simulated until touched
    /// Work units one step may spend (workUnitsFromMilliseconds(); 0 = unlimited). Part of the state.
    std::uint64_t stepBudget = 0;
    TaskSystem tasks;  ///< worker threads of the step (default: one, the caller's); not state
};

/// A body's state after the last step.
struct BodyState2D {
    BodyType type = BodyType::dynamicBody;
    Vec2D position;                ///< body origin (m)
    double angle = 0.0;            ///< rad, in [-pi, pi]
    Vec2D rotation{1.0, 0.0};      ///< (cos, sin) of the angle, as the engine stores it
    Vec2D center;                  ///< world centre of mass (m)
    Vec2D linearVelocity;          ///< m/s
    double angularVelocity = 0.0;  ///< rad/s
    double mass = 0.0;             ///< kg (0 for static and kinematic bodies)
    bool awake = true;             ///< false while the body sleeps
};

/// A contact point of the last step.
struct ContactPoint2D {
    BodyId a, b;                 ///< the normal points away from b towards a
    Vec2D point;                 ///< world point midway between the surfaces (m)
    Vec2D normal;                ///< unit normal from b towards a
    double separation = 0.0;     ///< gap along the normal (m), negative when overlapping
    double normalImpulse = 0.0;  ///< N s applied along the normal this step
    double tangentImpulse = 0.0; ///< N s of friction along (-normal.y, normal.x)
};

/// One shape hit by a ray.
struct RayHit2D {
    BodyId body;            ///< the body hit
    int shape = 0;          ///< index of the shape in the body
    Vec2D point;            ///< where the ray meets the shape (m)
    Vec2D normal;           ///< unit surface normal there, against the ray
    double fraction = 0.0;  ///< point = origin + fraction * translation, in [0, 1]
};

/// A 2D world: bodies, shapes, contacts and queries; ids, the step and the state are World's (unison/world.h).
class World2D : public World {
public:
    /// An empty world. Throws unison::Error for invalid settings or an unfit floating-point environment.
    explicit World2D(const WorldDef2D& def = {});

    /// Adds a body with its shapes; the null id and a message in *error when an argument is invalid.
    BodyId createBody(const BodyDef2D& def, const std::vector<ShapeDef2D>& shapes, std::string* error = nullptr);
    /// The body's state; false (and *out untouched) for an invalid id.
    bool getState(BodyId id, BodyState2D* out) const;

    /// Sets a kinematic or dynamic body's velocity (m/s, rad/s) and wakes it; false for bad arguments.
    bool setVelocity(BodyId id, Vec2D linear, double angular);
    /// Applies an impulse (N s) at a world point (m) to a dynamic body and wakes it; false for bad arguments.
    bool applyImpulse(BodyId id, Vec2D impulse, Vec2D point);
    /// Sets gravity (m/s^2); false for a non-finite value.
    bool setGravity(Vec2D gravity);
    /// Gravity (m/s^2).
    Vec2D gravity() const;

    /// Contact points of the last step, in the step's order.
    std::vector<ContactPoint2D> contacts() const;

    /// The first shape the segment origin -> origin + translation (m) meets; false when none (or bad arguments).
    bool rayCastClosest(Vec2D origin, Vec2D translation, RayHit2D* out) const;
    /// Every shape the segment meets, by (fraction, body slot, shape index).
    std::vector<RayHit2D> rayCastAll(Vec2D origin, Vec2D translation) const;
    /// Every shape whose bounding box overlaps the box [lower, upper] (m), by (body slot, shape index).
    std::vector<ShapeRef> overlapAabb(Vec2D lower, Vec2D upper) const;
    /// Every shape sharing interior points with `shape` placed at `position`, turned by `angle`, by (body slot,
    /// shape index); empty with a message in *error for an invalid shape.
    std::vector<ShapeRef> overlapShape(const ShapeDef2D& shape, Vec2D position, double angle,
                                       std::string* error = nullptr) const;
};

}  // namespace unison
