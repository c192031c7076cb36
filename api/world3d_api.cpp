// api/world3d_api.cpp — unison::World3D (unison/world3d.h): the public 3D world over the engine's World3
// (resolver3d/world3d.h). Eigen stays on this side: public vectors and quaternions are converted at the boundary;
// shapes are built and checked by the engine's validating constructors before the world is touched.
#include <unison/world3d.h>

#include "api_common.h"
#include "engine.h"
#include "world3d.h"

#include <cmath>
#include <utility>

namespace unison {

namespace {

World3& sim(api::Engine& e) { return api::engineWorld<World3>(e); }

Vec3 toEngine(const Vec3D& v) { return Vec3(v.x, v.y, v.z); }
Vec3D toPublic(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
Quat toEngine(const Quat3D& q) { return {q.w, q.x, q.y, q.z}; }
Quat3D toPublic(const Quat& q) { return {q.w, q.x, q.y, q.z}; }
bool finite(const Vec3D& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::vector<Vec3> toEngine(const std::vector<Vec3D>& points) {
    std::vector<Vec3> out;
    out.reserve(points.size());
    for (const Vec3D& p : points) out.push_back(toEngine(p));
    return out;
}

// The engine's shape for a public definition; an error message (and *out untouched) when it is invalid.
std::string toEngine(const ShapeDef3D& def, Shape3* out) {
    if (!(std::isfinite(def.density) && def.density >= 0.0) || !(std::isfinite(def.friction) && def.friction >= 0.0) ||
        !(std::isfinite(def.restitution) && def.restitution >= 0.0))
        return "shape: density, friction and restitution must be finite and >= 0";
    Shape3 shape;
    std::string error;
    switch (def.kind) {
        case ShapeKind3D::sphere: error = makeSphere(toEngine(def.center), def.radius, &shape); break;
        case ShapeKind3D::box: error = makeBox(toEngine(def.halfExtents), toEngine(def.center), &shape); break;
        case ShapeKind3D::hull: error = makeHull(toEngine(def.points), &shape); break;
        case ShapeKind3D::plane: error = makePlane(toEngine(def.normal), def.offset, &shape); break;
        case ShapeKind3D::mesh: error = makeMesh(toEngine(def.points), def.triangles, &shape); break;
        default: return "shape: unknown kind";
    }
    if (!error.empty()) return error;
    shape.density = def.density;
    shape.friction = def.friction;
    shape.restitution = def.restitution;
    *out = std::move(shape);
    return {};
}

RayHit3D toPublic(const RayHit3& h) { return {h.body, h.shape, toPublic(h.point), toPublic(h.normal), h.fraction}; }

}  // namespace

ShapeDef3D ShapeDef3D::sphere(Vec3D center, double radius) {
    ShapeDef3D s;
    s.kind = ShapeKind3D::sphere;
    s.center = center;
    s.radius = radius;
    return s;
}

ShapeDef3D ShapeDef3D::box(Vec3D halfExtents, Vec3D center) {
    ShapeDef3D s;
    s.kind = ShapeKind3D::box;
    s.halfExtents = halfExtents;
    s.center = center;
    return s;
}

ShapeDef3D ShapeDef3D::hull(std::vector<Vec3D> points) {
    ShapeDef3D s;
    s.kind = ShapeKind3D::hull;
    s.points = std::move(points);
    return s;
}

ShapeDef3D ShapeDef3D::plane(Vec3D normal, double offset) {
    ShapeDef3D s;
    s.kind = ShapeKind3D::plane;
    s.normal = normal;
    s.offset = offset;
    return s;
}

ShapeDef3D ShapeDef3D::mesh(std::vector<Vec3D> vertices, std::vector<std::array<int, 3>> triangles) {
    ShapeDef3D s;
    s.kind = ShapeKind3D::mesh;
    s.points = std::move(vertices);
    s.triangles = std::move(triangles);
    return s;
}

namespace {

// The engine of a new world, after checking its settings and the floating-point environment.
std::unique_ptr<api::Engine> makeEngine(const WorldDef3D& def) {
    const WorldDef3 engine = api::engineDef<WorldDef3>(def, [](Vec3D v) { return toEngine(v); });
    return std::make_unique<api::EngineOf<World3>>(engine);
}

}  // namespace

World3D::World3D(const WorldDef3D& def) : World(makeEngine(def)) {}

BodyId World3D::createBody(const BodyDef3D& def, const std::vector<ShapeDef3D>& shapes, std::string* error) {
    std::vector<Shape3> engineShapes(shapes.size());
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        const std::string why = toEngine(shapes[i], &engineShapes[i]);
        if (!why.empty()) return api::fail(error, "shape " + std::to_string(i) + ": " + why, BodyId::null());
    }
    if (def.type != BodyType::staticBody && def.type != BodyType::kinematicBody && def.type != BodyType::dynamicBody)
        return api::fail(error, "body: unknown type", BodyId::null());
    BodyDef3 engine;
    engine.type = def.type;
    engine.position = toEngine(def.position);
    engine.orientation = toEngine(def.orientation);
    engine.linearVelocity = toEngine(def.linearVelocity);
    engine.angularVelocity = toEngine(def.angularVelocity);
    return sim(*mEngine).createBody(engine, engineShapes, error);
}

bool World3D::getState(BodyId id, BodyState3D* out) const {
    const BodyState3* s = sim(*mEngine).state(id);
    if (!s || !out) return false;
    const BodyInfo3& info = *sim(*mEngine).info(id);
    out->type = info.type;
    out->position = toPublic(s->position);
    out->orientation = toPublic(s->rotation);
    out->center = toPublic(s->center);
    out->linearVelocity = toPublic(s->velocity);
    out->angularVelocity = toPublic(s->angularVelocity);
    out->mass = info.mass;
    out->awake = info.awake;
    return true;
}

bool World3D::setVelocity(BodyId id, Vec3D linear, Vec3D angular) {
    return sim(*mEngine).setVelocity(id, toEngine(linear), toEngine(angular));
}

bool World3D::applyImpulse(BodyId id, Vec3D impulse, Vec3D point) {
    return sim(*mEngine).applyImpulse(id, toEngine(impulse), toEngine(point));
}

bool World3D::setGravity(Vec3D g) {
    if (!finite(g)) return false;
    sim(*mEngine).setGravity(toEngine(g));
    return true;
}

Vec3D World3D::gravity() const { return toPublic(sim(*mEngine).def().gravity); }

std::vector<ContactPoint3D> World3D::contacts() const {
    std::vector<ContactPoint3D> out;
    for (const ContactPoint3& c : sim(*mEngine).contacts())
        out.push_back({c.a, c.b, toPublic(c.point), toPublic(c.normal), c.separation, c.normalImpulse,
                       toPublic(c.tangentImpulse)});
    return out;
}

bool World3D::rayCastClosest(Vec3D origin, Vec3D translation, RayHit3D* out) const {
    RayHit3 hit;
    if (!sim(*mEngine).rayCastClosest(toEngine(origin), toEngine(translation), &hit)) return false;
    if (out) *out = toPublic(hit);
    return true;
}

std::vector<RayHit3D> World3D::rayCastAll(Vec3D origin, Vec3D translation) const {
    std::vector<RayHit3D> out;
    for (const RayHit3& h : sim(*mEngine).rayCastAll(toEngine(origin), toEngine(translation))) out.push_back(toPublic(h));
    return out;
}

std::vector<ShapeRef> World3D::overlapAabb(Vec3D lower, Vec3D upper) const {
    if (!(lower.x <= upper.x && lower.y <= upper.y && lower.z <= upper.z)) return {};  // also NaN
    return sim(*mEngine).overlapAabb({toEngine(lower), toEngine(upper)});
}

std::vector<ShapeRef> World3D::overlapShape(const ShapeDef3D& shape, Vec3D position, Quat3D orientation,
                                            std::string* error) const {
    if (shape.kind != ShapeKind3D::sphere && shape.kind != ShapeKind3D::box && shape.kind != ShapeKind3D::hull)
        return api::fail(error, "query: the shape must be a sphere, box or hull", std::vector<ShapeRef>{});
    Shape3 engine;
    const std::string why = toEngine(shape, &engine);
    if (!why.empty()) return api::fail(error, why, std::vector<ShapeRef>{});
    const Quat q = toEngine(orientation);
    if (!finite(position) || !std::isfinite(q.w) || !std::isfinite(q.x) || !std::isfinite(q.y) ||
        !std::isfinite(q.z) || !(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z > 1e-12))
        return api::fail(error, "query: position and orientation must be finite (orientation non-zero)",
                         std::vector<ShapeRef>{});
    return sim(*mEngine).overlapShape(engine, {toEngine(position), toMatrix(normalized(q))});
}

}  // namespace unison
