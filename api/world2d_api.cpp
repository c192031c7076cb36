// api/world2d_api.cpp — unison::World2D (unison/world2d.h): the public 2D world over the engine's World2
// (resolver2d/world2d.h). Public value types are converted at the boundary; shapes are built and checked by the
// engine's validating constructors before the world is touched.
#include <unison/world2d.h>

#include "api_common.h"
#include "engine.h"
#include "world2d.h"

#include <cmath>
#include <utility>

namespace unison {

namespace {

World2& sim(api::Engine& e) { return api::engineWorld<World2>(e); }

Vec2 toEngine(Vec2D v) { return {v.x, v.y}; }
Vec2D toPublic(Vec2 v) { return {v.x, v.y}; }
bool finite(Vec2D v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// The engine's shape for a public definition; an error message (and *out untouched) when it is invalid.
std::string toEngine(const ShapeDef2D& def, Shape2* out) {
    if (!(std::isfinite(def.density) && def.density >= 0.0) || !(std::isfinite(def.friction) && def.friction >= 0.0) ||
        !(std::isfinite(def.restitution) && def.restitution >= 0.0))
        return "shape: density, friction and restitution must be finite and >= 0";
    Shape2 shape;
    std::string error;
    switch (def.kind) {
        case ShapeKind2D::circle:
            error = makeCircle(toEngine(def.center), def.radius, &shape.circle);
            shape.type = ShapeType::circle;
            break;
        case ShapeKind2D::box:
            error = makeBox(def.halfExtents.x, def.halfExtents.y, toEngine(def.center), def.angle, &shape.polygon);
            shape.type = ShapeType::polygon;
            break;
        case ShapeKind2D::polygon: {
            std::vector<Vec2> points;
            for (Vec2D p : def.points) points.push_back(toEngine(p));
            error = makePolygon(points, &shape.polygon);
            shape.type = ShapeType::polygon;
            break;
        }
        case ShapeKind2D::segment:
            if (def.points.size() != 2) return "segment: needs exactly 2 points";
            error = makeSegment(toEngine(def.points[0]), toEngine(def.points[1]), &shape.segment);
            shape.type = ShapeType::segment;
            break;
        default:
            return "shape: unknown kind";
    }
    if (!error.empty()) return error;
    shape.density = def.density;
    shape.friction = def.friction;
    shape.restitution = def.restitution;
    *out = shape;
    return {};
}

RayHit2D toPublic(const RayHit2& h) { return {h.body, h.shape, toPublic(h.point), toPublic(h.normal), h.fraction}; }

}  // namespace

ShapeDef2D ShapeDef2D::circle(Vec2D center, double radius) {
    ShapeDef2D s;
    s.kind = ShapeKind2D::circle;
    s.center = center;
    s.radius = radius;
    return s;
}

ShapeDef2D ShapeDef2D::box(double hx, double hy, Vec2D center, double angle) {
    ShapeDef2D s;
    s.kind = ShapeKind2D::box;
    s.halfExtents = {hx, hy};
    s.center = center;
    s.angle = angle;
    return s;
}

ShapeDef2D ShapeDef2D::polygon(std::vector<Vec2D> points) {
    ShapeDef2D s;
    s.kind = ShapeKind2D::polygon;
    s.points = std::move(points);
    return s;
}

ShapeDef2D ShapeDef2D::segment(Vec2D a, Vec2D b) {
    ShapeDef2D s;
    s.kind = ShapeKind2D::segment;
    s.points = {a, b};
    return s;
}

namespace {

// The engine of a new world, after checking its settings and the floating-point environment.
std::unique_ptr<api::Engine> makeEngine(const WorldDef2D& def) {
    const WorldDef2 engine = api::engineDef<WorldDef2>(def, [](Vec2D v) { return toEngine(v); });
    return std::make_unique<api::EngineOf<World2>>(engine);
}

}  // namespace

World2D::World2D(const WorldDef2D& def) : World(makeEngine(def)) {}

BodyId World2D::createBody(const BodyDef2D& def, const std::vector<ShapeDef2D>& shapes, std::string* error) {
    std::vector<Shape2> engineShapes(shapes.size());
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        const std::string why = toEngine(shapes[i], &engineShapes[i]);
        if (!why.empty()) return api::fail(error, "shape " + std::to_string(i) + ": " + why, BodyId::null());
    }
    if (def.type != BodyType::staticBody && def.type != BodyType::kinematicBody && def.type != BodyType::dynamicBody)
        return api::fail(error, "body: unknown type", BodyId::null());
    BodyDef2 engine;
    engine.type = def.type;
    engine.position = toEngine(def.position);
    engine.angle = def.angle;
    engine.linearVelocity = toEngine(def.linearVelocity);
    engine.angularVelocity = def.angularVelocity;
    return sim(*mEngine).createBody(engine, engineShapes, error);
}

bool World2D::getState(BodyId id, BodyState2D* out) const {
    const BodyState2* s = sim(*mEngine).state(id);
    if (!s || !out) return false;
    const BodyInfo2& info = *sim(*mEngine).info(id);
    out->type = info.type;
    out->position = toPublic(s->position);
    out->angle = sim(*mEngine).angle(id);
    out->rotation = {s->rotation.c, s->rotation.s};
    out->center = toPublic(s->center);
    out->linearVelocity = toPublic(s->velocity);
    out->angularVelocity = s->angularVelocity;
    out->mass = info.mass;
    out->awake = info.awake;
    return true;
}

bool World2D::setVelocity(BodyId id, Vec2D linear, double angular) {
    return sim(*mEngine).setVelocity(id, toEngine(linear), angular);
}

bool World2D::applyImpulse(BodyId id, Vec2D impulse, Vec2D point) {
    return sim(*mEngine).applyImpulse(id, toEngine(impulse), toEngine(point));
}

bool World2D::setGravity(Vec2D g) {
    if (!finite(g)) return false;
    sim(*mEngine).setGravity(toEngine(g));
    return true;
}

Vec2D World2D::gravity() const { return toPublic(sim(*mEngine).def().gravity); }

std::vector<ContactPoint2D> World2D::contacts() const {
    std::vector<ContactPoint2D> out;
    for (const ContactPoint2& c : sim(*mEngine).contacts())
        out.push_back({c.a, c.b, toPublic(c.point), toPublic(c.normal), c.separation, c.normalImpulse, c.tangentImpulse});
    return out;
}

bool World2D::rayCastClosest(Vec2D origin, Vec2D translation, RayHit2D* out) const {
    RayHit2 hit;
    if (!sim(*mEngine).rayCastClosest(toEngine(origin), toEngine(translation), &hit)) return false;
    if (out) *out = toPublic(hit);
    return true;
}

std::vector<RayHit2D> World2D::rayCastAll(Vec2D origin, Vec2D translation) const {
    std::vector<RayHit2D> out;
    for (const RayHit2& h : sim(*mEngine).rayCastAll(toEngine(origin), toEngine(translation))) out.push_back(toPublic(h));
    return out;
}

std::vector<ShapeRef> World2D::overlapAabb(Vec2D lower, Vec2D upper) const {
    if (!(lower.x <= upper.x && lower.y <= upper.y)) return {};  // also NaN
    return sim(*mEngine).overlapAabb({toEngine(lower), toEngine(upper)});
}

std::vector<ShapeRef> World2D::overlapShape(const ShapeDef2D& shape, Vec2D position, double angle,
                                            std::string* error) const {
    Shape2 engine;
    const std::string why = toEngine(shape, &engine);
    if (!why.empty()) return api::fail(error, why, std::vector<ShapeRef>{});
    if (!finite(position) || !std::isfinite(angle))
        return api::fail(error, "query: position and angle must be finite", std::vector<ShapeRef>{});
    return sim(*mEngine).overlapShape(engine, {toEngine(position), makeRot(angle)});
}

}  // namespace unison
