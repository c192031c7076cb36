// bench/box2d_v3_peer.cpp — builds and steps a Box2D v3.2 world from scene JSON (see box2d_v3_peer.h).
//
// Compiled only when the optional peer folder exists, with its include/ ahead of the system's, so <box2d/box2d.h>
// here is Box2D v3's C API (Box2D 2.4.1's header of the same name is never included in this file). Defaults for
// missing keys are loadScene2's (density 1, friction 0.6, restitution 0, hz 60, gravity (0, -10), sleep on,
// restitution threshold 1 m/s).
#include "box2d_v3_peer.h"

#include <box2d/box2d.h>

#include <vector>

namespace unison::bench {
namespace {

using nlohmann::json;
using jsonio::fail;
using jsonio::member;
using jsonio::number;
using jsonio::numberOr;

b2Vec2 vec(const json& v, const std::string& path) {
    if (!v.is_array() || v.size() != 2) fail(path, "expected [x, y]");
    return b2Vec2{float(number(v[0], path + "[0]")), float(number(v[1], path + "[1]"))};
}

b2Vec2 vecOr(const json& obj, const std::string& path, const char* key, b2Vec2 fallback) {
    const json* v = member(obj, path, key, false);
    return v ? vec(*v, path + "." + key) : fallback;
}

void addShape(b2BodyId body, const json& js, const std::string& path) {
    const json* type = member(js, path, "type", true);
    if (!type->is_string()) fail(path + ".type", "expected a string");
    const std::string t = type->get<std::string>();
    b2ShapeDef def = b2DefaultShapeDef();
    def.density = float(numberOr(js, path, "density", 1.0));
    def.material.friction = float(numberOr(js, path, "friction", 0.6));
    def.material.restitution = float(numberOr(js, path, "restitution", 0.0));
    const b2Vec2 center = vecOr(js, path, "center", b2Vec2{0.0f, 0.0f});
    if (t == "circle") {
        b2Circle circle{center, float(number(*member(js, path, "radius", true), path + ".radius"))};
        b2CreateCircleShape(body, &def, &circle);
    } else if (t == "box") {
        const b2Vec2 h = vec(*member(js, path, "half_extents", true), path + ".half_extents");
        const b2Polygon box = b2MakeOffsetBox(h.x, h.y, center, b2MakeRot(float(numberOr(js, path, "angle", 0.0))));
        b2CreatePolygonShape(body, &def, &box);
    } else if (t == "polygon") {
        const json* vs = member(js, path, "vertices", true);
        if (!vs->is_array() || vs->size() < 3 || vs->size() > B2_MAX_POLYGON_VERTICES)
            fail(path + ".vertices", "expected 3 to 8 points");
        b2Vec2 points[B2_MAX_POLYGON_VERTICES];
        for (std::size_t i = 0; i < vs->size(); ++i) points[i] = vec((*vs)[i], path + ".vertices[" + std::to_string(i) + "]");
        const b2Hull hull = b2ComputeHull(points, int(vs->size()));
        if (hull.count == 0) fail(path + ".vertices", "Box2D v3 cannot make a hull of these points");
        const b2Polygon polygon = b2MakePolygon(&hull, 0.0f);
        b2CreatePolygonShape(body, &def, &polygon);
    } else if (t == "segment") {
        const json* ps = member(js, path, "points", true);
        if (!ps->is_array() || ps->size() != 2) fail(path + ".points", "expected two points");
        b2Segment segment{vec((*ps)[0], path + ".points[0]"), vec((*ps)[1], path + ".points[1]")};
        b2CreateSegmentShape(body, &def, &segment);
    } else {
        fail(path + ".type", "unknown 2D shape type \"" + t + "\" (circle, box, polygon, segment)");
    }
}

}  // namespace

struct Box2dV3Peer::Impl {
    b2WorldId world = b2_nullWorldId;
    std::vector<b2BodyId> bodies;  // scene index -> body
    float dt = 1.0f / 60.0f;
    int subSteps = 4;
    ~Impl() {
        if (B2_IS_NON_NULL(world)) b2DestroyWorld(world);
    }
};

Box2dV3Peer::Box2dV3Peer(const json& scene, const std::string& what, int subSteps) : mImpl(std::make_unique<Impl>()) {
    const json* dim = member(scene, what, "dimension", true);
    if (!dim->is_number_integer() || dim->get<int>() != 2) fail(what + ".dimension", "the Box2D v3 peer takes 2D scenes only");
    const double hz = numberOr(scene, what, "hz", 60.0);
    if (!(hz > 0.0)) fail(what + ".hz", "must be > 0");
    b2WorldDef wd = b2DefaultWorldDef();
    wd.gravity = vecOr(scene, what, "gravity", b2Vec2{0.0f, -10.0f});
    wd.restitutionThreshold = float(numberOr(scene, what, "restitution_threshold", 1.0));
    wd.enableSleep = true;
    if (const json* sl = member(scene, what, "sleep", false)) {
        if (!sl->is_boolean()) fail(what + ".sleep", "expected true or false");
        wd.enableSleep = sl->get<bool>();
    }
    wd.workerCount = 1;
    mImpl->dt = float(1.0 / hz);
    mImpl->subSteps = subSteps;
    mImpl->world = b2CreateWorld(&wd);

    const json* bodies = member(scene, what, "bodies", true);
    if (!bodies->is_array()) fail(what + ".bodies", "expected an array");
    for (std::size_t i = 0; i < bodies->size(); ++i) {
        const std::string path = what + ".bodies[" + std::to_string(i) + "]";
        const json& jb = (*bodies)[i];
        b2BodyDef bd = b2DefaultBodyDef();
        const BodyType kind = jsonio::bodyType(jb, path);
        bd.type = kind == BodyType::staticBody      ? b2_staticBody
                  : kind == BodyType::kinematicBody ? b2_kinematicBody
                                                    : b2_dynamicBody;
        bd.position = vecOr(jb, path, "position", b2Vec2{0.0f, 0.0f});
        bd.rotation = b2MakeRot(float(numberOr(jb, path, "angle", 0.0)));
        bd.linearVelocity = vecOr(jb, path, "linear_velocity", b2Vec2{0.0f, 0.0f});
        bd.angularVelocity = float(numberOr(jb, path, "angular_velocity", 0.0));
        const b2BodyId body = b2CreateBody(mImpl->world, &bd);
        if (const json* js = member(jb, path, "shapes", false)) {
            if (!js->is_array()) fail(path + ".shapes", "expected an array");
            for (std::size_t k = 0; k < js->size(); ++k) addShape(body, (*js)[k], path + ".shapes[" + std::to_string(k) + "]");
        }
        mImpl->bodies.push_back(body);
    }
}

Box2dV3Peer::~Box2dV3Peer() = default;

void Box2dV3Peer::step() { b2World_Step(mImpl->world, mImpl->dt, mImpl->subSteps); }

int Box2dV3Peer::bodyCount() const { return int(mImpl->bodies.size()); }

Vec2 Box2dV3Peer::position(int index) const {
    const b2Vec2 p = b2Body_GetPosition(mImpl->bodies.at(std::size_t(index)));
    return {double(p.x), double(p.y)};
}

double Box2dV3Peer::angle(int index) const { return double(b2Rot_GetAngle(b2Body_GetRotation(mImpl->bodies.at(std::size_t(index))))); }

}  // namespace unison::bench
