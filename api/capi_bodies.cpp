// api/capi_bodies.cpp — the C API (unison/unison.h), part 2: bodies, their state and velocities, contacts and touch
// events of the last step, and the scene queries, in 2D and 3D. Each call checks the world (id and dimension), its
// pointers, the body id and the values, in that order, before it changes anything.
#include "capi_internal.h"

#include <cmath>

using namespace unison;
using namespace unison::capi;

namespace {

// The world of dimension Dim and a live body of it, or an error code.
template <int Dim>
auto bodyWorld(unisonWorldId world, unisonBodyId body, unisonError* code) {
    auto* w = worldOf<Dim>(world, code);
    if (!*code && !w->isValid(fromC(body))) *code = fail(UNISON_ERROR_INVALID_BODY, "invalid body id");
    return w;
}

// Shapes from C for createBody; an error code on the first bad one.
template <class CShape, class Shape>
unisonError shapesFromC(const CShape* shapes, int count, std::vector<Shape>* out) {
    if (count < 0) return fail(UNISON_ERROR_INVALID_ARGUMENT, "shapeCount must be >= 0");
    if (count > 0 && !shapes) return fail(UNISON_ERROR_NULL_POINTER, "shapes is NULL");
    out->resize(std::size_t(count));
    for (int i = 0; i < count; ++i)
        if (const unisonError e = fromC(shapes[i], &(*out)[std::size_t(i)])) return e;
    return UNISON_OK;
}

// createBody of either world, its message mapped to a code.
template <class World, class Def, class Shape>
unisonError create(World& w, const Def& def, const std::vector<Shape>& shapes, unisonBodyId* outBody) {
    std::string error;
    const BodyId id = w.createBody(def, shapes, &error);
    if (id.isNull())
        return fail(error.find("capacity") != std::string::npos ? UNISON_ERROR_CAPACITY : UNISON_ERROR_INVALID_ARGUMENT,
                    error);
    *outBody = toC(id);
    return UNISON_OK;
}

unisonRayHit2 toC(const RayHit2D& h) { return {capi::toC(h.body), h.shape, capi::toC(h.point), capi::toC(h.normal), h.fraction}; }
unisonRayHit3 toC(const RayHit3D& h) { return {capi::toC(h.body), h.shape, capi::toC(h.point), capi::toC(h.normal), h.fraction}; }

bool finite(unisonVec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }
bool finite(unisonVec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool zero(unisonVec2 v) { return v.x == 0.0 && v.y == 0.0; }
bool zero(unisonVec3 v) { return v.x == 0.0 && v.y == 0.0 && v.z == 0.0; }

// Ray arguments: a finite origin and a finite, non-zero translation.
template <class V>
unisonError checkRay(V origin, V translation) {
    if (!finite(origin) || !finite(translation))
        return fail(UNISON_ERROR_INVALID_ARGUMENT, "ray: origin and translation must be finite");
    if (zero(translation)) return fail(UNISON_ERROR_INVALID_ARGUMENT, "ray: translation must not be zero");
    return UNISON_OK;
}

}  // namespace

extern "C" {

unisonError unisonCreateBody2(unisonWorldId world, const unisonBodyDef2* def, const unisonShapeDef2* shapes,
                              int shapeCount, unisonBodyId* outBody) {
    return guard([&] {
        unisonError code;
        World2D* w = worldOf<2>(world, &code);
        if (code) return code;
        if (!def || !outBody) return fail(UNISON_ERROR_NULL_POINTER, "def or outBody is NULL");
        std::vector<ShapeDef2D> list;
        if (const unisonError e = shapesFromC(shapes, shapeCount, &list)) return e;
        BodyDef2D d;
        if (!capi::fromC(def->type, &d.type)) return fail(UNISON_ERROR_INVALID_ARGUMENT, "body: unknown type");
        d.position = capi::fromC(def->position);
        d.angle = def->angle;
        d.linearVelocity = capi::fromC(def->linearVelocity);
        d.angularVelocity = def->angularVelocity;
        return create(*w, d, list, outBody);
    });
}

unisonError unisonCreateBody3(unisonWorldId world, const unisonBodyDef3* def, const unisonShapeDef3* shapes,
                              int shapeCount, unisonBodyId* outBody) {
    return guard([&] {
        unisonError code;
        World3D* w = worldOf<3>(world, &code);
        if (code) return code;
        if (!def || !outBody) return fail(UNISON_ERROR_NULL_POINTER, "def or outBody is NULL");
        std::vector<ShapeDef3D> list;
        if (const unisonError e = shapesFromC(shapes, shapeCount, &list)) return e;
        BodyDef3D d;
        if (!capi::fromC(def->type, &d.type)) return fail(UNISON_ERROR_INVALID_ARGUMENT, "body: unknown type");
        d.position = capi::fromC(def->position);
        d.orientation = capi::fromC(def->orientation);
        d.linearVelocity = capi::fromC(def->linearVelocity);
        d.angularVelocity = capi::fromC(def->angularVelocity);
        return create(*w, d, list, outBody);
    });
}

unisonError unisonDestroyBody(unisonWorldId world, unisonBodyId body) {
    return withWorld(world, [&](auto& w) {
        return w.destroyBody(capi::fromC(body)) ? UNISON_OK : fail(UNISON_ERROR_INVALID_BODY, "invalid body id");
    });
}

int unisonBodyIsValid(unisonWorldId world, unisonBodyId body) {
    const WorldRef ref = lookup(world);
    if (ref.w2) return ref.w2->isValid(capi::fromC(body)) ? 1 : 0;
    if (ref.w3) return ref.w3->isValid(capi::fromC(body)) ? 1 : 0;
    return 0;
}

unisonError unisonGetBodyCount(unisonWorldId world, int* outCount) {
    return withWorld(world, [&](auto& w) {
        if (!outCount) return fail(UNISON_ERROR_NULL_POINTER, "outCount is NULL");
        *outCount = w.bodyCount();
        return UNISON_OK;
    });
}

unisonError unisonGetBodyIds(unisonWorldId world, unisonBodyId* out, int capacity, int* outCount) {
    return withWorld(world, [&](auto& w) {
        return copyOut(w.bodyIds(), out, capacity, outCount, [](BodyId id) { return capi::toC(id); });
    });
}

unisonError unisonGetBodyState2(unisonWorldId world, unisonBodyId body, unisonBodyState2* outState) {
    return guard([&] {
        unisonError code;
        World2D* w = bodyWorld<2>(world, body, &code);
        if (code) return code;
        if (!outState) return fail(UNISON_ERROR_NULL_POINTER, "outState is NULL");
        BodyState2D s;
        w->getState(capi::fromC(body), &s);
        *outState = {unisonBodyType(s.type), capi::toC(s.position), s.angle, capi::toC(s.center),
                     capi::toC(s.linearVelocity), s.angularVelocity, s.mass, s.awake ? 1 : 0};
        return UNISON_OK;
    });
}

unisonError unisonGetBodyState3(unisonWorldId world, unisonBodyId body, unisonBodyState3* outState) {
    return guard([&] {
        unisonError code;
        World3D* w = bodyWorld<3>(world, body, &code);
        if (code) return code;
        if (!outState) return fail(UNISON_ERROR_NULL_POINTER, "outState is NULL");
        BodyState3D s;
        w->getState(capi::fromC(body), &s);
        *outState = {unisonBodyType(s.type), capi::toC(s.position), capi::toC(s.orientation), capi::toC(s.center),
                     capi::toC(s.linearVelocity), capi::toC(s.angularVelocity), s.mass, s.awake ? 1 : 0};
        return UNISON_OK;
    });
}

unisonError unisonSetBodyVelocity2(unisonWorldId world, unisonBodyId body, unisonVec2 linear, double angular) {
    return guard([&] {
        unisonError code;
        World2D* w = bodyWorld<2>(world, body, &code);
        if (code) return code;
        return w->setVelocity(capi::fromC(body), capi::fromC(linear), angular)
                   ? UNISON_OK
                   : fail(UNISON_ERROR_INVALID_ARGUMENT, "set velocity: a static body or a non-finite value");
    });
}

unisonError unisonSetBodyVelocity3(unisonWorldId world, unisonBodyId body, unisonVec3 linear, unisonVec3 angular) {
    return guard([&] {
        unisonError code;
        World3D* w = bodyWorld<3>(world, body, &code);
        if (code) return code;
        return w->setVelocity(capi::fromC(body), capi::fromC(linear), capi::fromC(angular))
                   ? UNISON_OK
                   : fail(UNISON_ERROR_INVALID_ARGUMENT, "set velocity: a static body or a non-finite value");
    });
}

unisonError unisonApplyImpulse2(unisonWorldId world, unisonBodyId body, unisonVec2 impulse, unisonVec2 point) {
    return guard([&] {
        unisonError code;
        World2D* w = bodyWorld<2>(world, body, &code);
        if (code) return code;
        return w->applyImpulse(capi::fromC(body), capi::fromC(impulse), capi::fromC(point))
                   ? UNISON_OK
                   : fail(UNISON_ERROR_INVALID_ARGUMENT, "apply impulse: not a dynamic body, or a non-finite value");
    });
}

unisonError unisonApplyImpulse3(unisonWorldId world, unisonBodyId body, unisonVec3 impulse, unisonVec3 point) {
    return guard([&] {
        unisonError code;
        World3D* w = bodyWorld<3>(world, body, &code);
        if (code) return code;
        return w->applyImpulse(capi::fromC(body), capi::fromC(impulse), capi::fromC(point))
                   ? UNISON_OK
                   : fail(UNISON_ERROR_INVALID_ARGUMENT, "apply impulse: not a dynamic body, or a non-finite value");
    });
}

unisonError unisonGetContacts2(unisonWorldId world, unisonContactPoint2* out, int capacity, int* outCount) {
    return guard([&] {
        unisonError code;
        World2D* w = worldOf<2>(world, &code);
        if (code) return code;
        return copyOut(w->contacts(), out, capacity, outCount, [](const ContactPoint2D& c) {
            return unisonContactPoint2{capi::toC(c.a), capi::toC(c.b), capi::toC(c.point), capi::toC(c.normal),
                                       c.separation, c.normalImpulse, c.tangentImpulse};
        });
    });
}

unisonError unisonGetContacts3(unisonWorldId world, unisonContactPoint3* out, int capacity, int* outCount) {
    return guard([&] {
        unisonError code;
        World3D* w = worldOf<3>(world, &code);
        if (code) return code;
        return copyOut(w->contacts(), out, capacity, outCount, [](const ContactPoint3D& c) {
            return unisonContactPoint3{capi::toC(c.a), capi::toC(c.b), capi::toC(c.point), capi::toC(c.normal),
                                       c.separation, c.normalImpulse, capi::toC(c.tangentImpulse)};
        });
    });
}

unisonError unisonGetBeginTouchEvents(unisonWorldId world, unisonTouchEvent* out, int capacity, int* outCount) {
    return withWorld(world, [&](auto& w) {
        return copyOut(w.beginTouchEvents(), out, capacity, outCount, [](const TouchEvent& e) { return capi::toC(e); });
    });
}

unisonError unisonGetEndTouchEvents(unisonWorldId world, unisonTouchEvent* out, int capacity, int* outCount) {
    return withWorld(world, [&](auto& w) {
        return copyOut(w.endTouchEvents(), out, capacity, outCount, [](const TouchEvent& e) { return capi::toC(e); });
    });
}

unisonError unisonRayCastClosest2(unisonWorldId world, unisonVec2 origin, unisonVec2 translation, unisonRayHit2* outHit,
                                  int* outHasHit) {
    return guard([&] {
        unisonError code;
        World2D* w = worldOf<2>(world, &code);
        if (code) return code;
        if (!outHit || !outHasHit) return fail(UNISON_ERROR_NULL_POINTER, "outHit or outHasHit is NULL");
        if (const unisonError e = checkRay(origin, translation)) return e;
        RayHit2D hit;
        *outHasHit = w->rayCastClosest(capi::fromC(origin), capi::fromC(translation), &hit) ? 1 : 0;
        if (*outHasHit) *outHit = toC(hit);
        return UNISON_OK;
    });
}

unisonError unisonRayCastClosest3(unisonWorldId world, unisonVec3 origin, unisonVec3 translation, unisonRayHit3* outHit,
                                  int* outHasHit) {
    return guard([&] {
        unisonError code;
        World3D* w = worldOf<3>(world, &code);
        if (code) return code;
        if (!outHit || !outHasHit) return fail(UNISON_ERROR_NULL_POINTER, "outHit or outHasHit is NULL");
        if (const unisonError e = checkRay(origin, translation)) return e;
        RayHit3D hit;
        *outHasHit = w->rayCastClosest(capi::fromC(origin), capi::fromC(translation), &hit) ? 1 : 0;
        if (*outHasHit) *outHit = toC(hit);
        return UNISON_OK;
    });
}

unisonError unisonRayCastAll2(unisonWorldId world, unisonVec2 origin, unisonVec2 translation, unisonRayHit2* out,
                              int capacity, int* outCount) {
    return guard([&] {
        unisonError code;
        World2D* w = worldOf<2>(world, &code);
        if (code) return code;
        if (const unisonError e = checkRay(origin, translation)) return e;
        return copyOut(w->rayCastAll(capi::fromC(origin), capi::fromC(translation)), out, capacity, outCount,
                       [](const RayHit2D& h) { return toC(h); });
    });
}

unisonError unisonRayCastAll3(unisonWorldId world, unisonVec3 origin, unisonVec3 translation, unisonRayHit3* out,
                              int capacity, int* outCount) {
    return guard([&] {
        unisonError code;
        World3D* w = worldOf<3>(world, &code);
        if (code) return code;
        if (const unisonError e = checkRay(origin, translation)) return e;
        return copyOut(w->rayCastAll(capi::fromC(origin), capi::fromC(translation)), out, capacity, outCount,
                       [](const RayHit3D& h) { return toC(h); });
    });
}

unisonError unisonOverlapAabb2(unisonWorldId world, unisonVec2 lower, unisonVec2 upper, unisonShapeRef* out,
                               int capacity, int* outCount) {
    return guard([&] {
        unisonError code;
        World2D* w = worldOf<2>(world, &code);
        if (code) return code;
        if (!(lower.x <= upper.x && lower.y <= upper.y) || !finite(lower) || !finite(upper))
            return fail(UNISON_ERROR_INVALID_ARGUMENT, "box: lower <= upper, finite");
        return copyOut(w->overlapAabb(capi::fromC(lower), capi::fromC(upper)), out, capacity, outCount,
                       [](const ShapeRef& r) { return capi::toC(r); });
    });
}

unisonError unisonOverlapAabb3(unisonWorldId world, unisonVec3 lower, unisonVec3 upper, unisonShapeRef* out,
                               int capacity, int* outCount) {
    return guard([&] {
        unisonError code;
        World3D* w = worldOf<3>(world, &code);
        if (code) return code;
        if (!(lower.x <= upper.x && lower.y <= upper.y && lower.z <= upper.z) || !finite(lower) || !finite(upper))
            return fail(UNISON_ERROR_INVALID_ARGUMENT, "box: lower <= upper, finite");
        return copyOut(w->overlapAabb(capi::fromC(lower), capi::fromC(upper)), out, capacity, outCount,
                       [](const ShapeRef& r) { return capi::toC(r); });
    });
}

unisonError unisonOverlapShape2(unisonWorldId world, const unisonShapeDef2* shape, unisonVec2 position, double angle,
                                unisonShapeRef* out, int capacity, int* outCount) {
    return guard([&] {
        unisonError code;
        World2D* w = worldOf<2>(world, &code);
        if (code) return code;
        if (!shape) return fail(UNISON_ERROR_NULL_POINTER, "shape is NULL");
        ShapeDef2D s;
        if (const unisonError e = capi::fromC(*shape, &s)) return e;
        std::string error;
        const std::vector<ShapeRef> found = w->overlapShape(s, capi::fromC(position), angle, &error);
        if (!error.empty()) return fail(UNISON_ERROR_INVALID_ARGUMENT, error);
        return copyOut(found, out, capacity, outCount, [](const ShapeRef& r) { return capi::toC(r); });
    });
}

unisonError unisonOverlapShape3(unisonWorldId world, const unisonShapeDef3* shape, unisonVec3 position,
                                unisonQuat orientation, unisonShapeRef* out, int capacity, int* outCount) {
    return guard([&] {
        unisonError code;
        World3D* w = worldOf<3>(world, &code);
        if (code) return code;
        if (!shape) return fail(UNISON_ERROR_NULL_POINTER, "shape is NULL");
        ShapeDef3D s;
        if (const unisonError e = capi::fromC(*shape, &s)) return e;
        std::string error;
        const std::vector<ShapeRef> found = w->overlapShape(s, capi::fromC(position), capi::fromC(orientation), &error);
        if (!error.empty()) return fail(UNISON_ERROR_INVALID_ARGUMENT, error);
        return copyOut(found, out, capacity, outCount, [](const ShapeRef& r) { return capi::toC(r); });
    });
}

}  // extern "C"
