// unison/world3d.h — the 3D world of Unison's C++ API: rigid bodies with spheres, boxes, convex hulls, static
// planes and closed triangle meshes, stepped at a fixed rate with every contact of an island resolved at once by
// one LCP (Lemke's method). The same guarantees as the 2D world (unison/world2d.h): bit-identical results on every
// machine, and a bad argument changes nothing. Units: metres, seconds, kilograms, radians; y is up.
#pragma once

#include <unison/world.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace unison {

/// A 3D vector (m, m/s, rad/s or a unit direction, by context).
struct Vec3D {
    double x = 0.0;
    double y = 0.0;
    double z = 0.0;
};

/// A rotation as a unit quaternion w + xi + yj + zk (the identity by default).
struct Quat3D {
    double w = 1.0;
    double x = 0.0;
    double y = 0.0;
    double z = 0.0;
};

/// The shape kinds of the 3D world.
enum class ShapeKind3D : std::uint8_t { sphere, box, hull, plane, mesh };

/// A shape of a 3D body, in body coordinates, with its material. The named constructors set the geometry.
struct ShapeDef3D {
    ShapeKind3D kind = ShapeKind3D::sphere;  ///< which geometry fields are used
    Vec3D center;                            ///< sphere or box centre (m)
    double radius = 0.5;                     ///< sphere radius (m), > 0
    Vec3D halfExtents{0.5, 0.5, 0.5};        ///< box half extents (m), > 0
    Vec3D normal{0.0, 1.0, 0.0};             ///< plane: the solid side is normal . x <= offset
    double offset = 0.0;                     ///< plane offset (m)
    std::vector<Vec3D> points;               ///< hull: 4..256 points; mesh: its vertices (m)
    std::vector<std::array<int, 3>> triangles;  ///< mesh: closed, counter-clockwise seen from outside
    double density = 1.0;      ///< kg/m^3
    double friction = 0.6;     ///< Coulomb coefficient; a contact uses sqrt(f1 f2)
    double restitution = 0.0;  ///< coefficient of restitution; a contact uses max(e1, e2)

    /// A solid ball.
    static ShapeDef3D sphere(Vec3D center, double radius);
    /// A solid box of half extents h centred at `center` (axis-aligned in the body frame).
    static ShapeDef3D box(Vec3D halfExtents, Vec3D center = {});
    /// The convex hull of 4..256 points, not all in one plane.
    static ShapeDef3D hull(std::vector<Vec3D> points);
    /// The half-space normal . x <= offset, for static bodies.
    static ShapeDef3D plane(Vec3D normal, double offset);
    /// A closed, consistently oriented triangle mesh with positive volume (collides through sphere trees).
    static ShapeDef3D mesh(std::vector<Vec3D> vertices, std::vector<std::array<int, 3>> triangles);
};

/// How to create a body.
struct BodyDef3D {
    BodyType type = BodyType::dynamicBody;  ///< static, kinematic or dynamic
    Vec3D position;                         ///< origin of the body frame (m)
    Quat3D orientation;                     ///< normalised on creation
    Vec3D linearVelocity;                   ///< of the centre of mass (m/s)
    Vec3D angularVelocity;                  ///< rad/s, world axes
};

/// World settings; the defaults are the engine's tuned values.
struct WorldDef3D {
    Vec3D gravity{0.0, -10.0, 0.0};  ///< m/s^2
    double hz = 60.0;                ///< steps per second (> 0)
    bool enableSleep = true;         ///< bodies of islands at rest for 0.5 s stop being simulated until touched
    /// Work units one step may spend (workUnitsFromMilliseconds(); 0 = unlimited). Part of the state.
    std::uint64_t stepBudget = 0;
    TaskSystem tasks;  ///< worker threads of the step (default: one, the caller's); not state
};

/// A body's state after the last step.
struct BodyState3D {
    BodyType type = BodyType::dynamicBody;
    Vec3D position;         ///< body origin (m)
    Quat3D orientation;     ///< body to world
    Vec3D center;           ///< world centre of mass (m)
    Vec3D linearVelocity;   ///< m/s
    Vec3D angularVelocity;  ///< rad/s, world axes
    double mass = 0.0;      ///< kg (0 for static and kinematic bodies)
    bool awake = true;      ///< false while the body sleeps
};

/// A contact point of the last step.
struct ContactPoint3D {
    BodyId a, b;                 ///< the normal points away from b towards a
    Vec3D point;                 ///< world point midway between the surfaces (m)
    Vec3D normal;                ///< unit normal from b towards a
    double separation = 0.0;     ///< gap along the normal (m), negative when overlapping
    double normalImpulse = 0.0;  ///< N s applied along the normal this step
    Vec3D tangentImpulse;        ///< N s of friction, world frame
};

/// One shape hit by a ray.
struct RayHit3D {
    BodyId body;            ///< the body hit
    int shape = 0;          ///< index of the shape in the body
    Vec3D point;            ///< where the ray meets the shape (m)
    Vec3D normal;           ///< unit surface normal there, against the ray
    double fraction = 0.0;  ///< point = origin + fraction * translation, in [0, 1]
};

/// A 3D world: bodies, shapes, contacts and queries; ids, the step and the state are World's (unison/world.h).
class World3D : public World {
public:
    /// An empty world. Throws unison::Error for invalid settings or an unfit floating-point environment.
    explicit World3D(const WorldDef3D& def = {});

    /// Adds a body with its shapes; the null id and a message in *error when an argument is invalid (planes only
    /// on static bodies).
    BodyId createBody(const BodyDef3D& def, const std::vector<ShapeDef3D>& shapes, std::string* error = nullptr);
    /// The body's state; false (and *out untouched) for an invalid id.
    bool getState(BodyId id, BodyState3D* out) const;

    /// Sets a kinematic or dynamic body's velocity (m/s, rad/s) and wakes it; false for bad arguments.
    bool setVelocity(BodyId id, Vec3D linear, Vec3D angular);
    /// Applies an impulse (N s) at a world point (m) to a dynamic body and wakes it; false for bad arguments.
    bool applyImpulse(BodyId id, Vec3D impulse, Vec3D point);
    /// Sets gravity (m/s^2); false for a non-finite value.
    bool setGravity(Vec3D gravity);
    /// Gravity (m/s^2).
    Vec3D gravity() const;

    /// Contact points of the last step, in the step's order.
    std::vector<ContactPoint3D> contacts() const;

    /// The first shape the segment origin -> origin + translation (m) meets; false when none (or bad arguments).
    bool rayCastClosest(Vec3D origin, Vec3D translation, RayHit3D* out) const;
    /// Every shape the segment meets, by (fraction, body slot, shape index).
    std::vector<RayHit3D> rayCastAll(Vec3D origin, Vec3D translation) const;
    /// Every shape whose bounding box overlaps the box [lower, upper] (m; a plane's box is unbounded), by (body
    /// slot, shape index).
    std::vector<ShapeRef> overlapAabb(Vec3D lower, Vec3D upper) const;
    /// Every shape sharing interior points with the sphere, box or hull `shape` placed at `position` with
    /// `orientation`, by (body slot, shape index); empty with a message in *error for another or invalid shape.
    std::vector<ShapeRef> overlapShape(const ShapeDef3D& shape, Vec3D position, Quat3D orientation,
                                       std::string* error = nullptr) const;
};

}  // namespace unison
