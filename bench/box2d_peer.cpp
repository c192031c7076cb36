// bench/box2d_peer.cpp — builds and steps a Box2D 2.4.1 world from scene JSON (see box2d_peer.h).
//
// Defaults for missing keys are loadScene2's (density 1, friction 0.6, restitution 0, hz 60, gravity (0, -10),
// sleep on, restitution threshold 1 m/s), not Box2D's own (its fixture friction defaults to 0.2), so both engines
// always simulate the same scene.
#include "box2d_peer.h"

#include <box2d/box2d.h>

#include <cmath>

namespace unison::bench {
namespace {

using nlohmann::json;

using jsonio::fail;
using jsonio::member;
using jsonio::number;
using jsonio::numberOr;

b2Vec2 vec(const json& v, const std::string& path) {
    if (!v.is_array() || v.size() != 2) fail(path, "expected [x, y]");
    return b2Vec2(float(number(v[0], path + "[0]")), float(number(v[1], path + "[1]")));
}

b2Vec2 vecOr(const json& obj, const std::string& path, const char* key, b2Vec2 fallback) {
    const json* v = member(obj, path, key, false);
    return v ? vec(*v, path + "." + key) : fallback;
}

// Creates the fixture of one scene shape on `body`.
void addFixture(b2Body* body, const json& js, const std::string& path, float restitutionThreshold) {
    const json* type = member(js, path, "type", true);
    if (!type->is_string()) fail(path + ".type", "expected a string");
    const std::string t = type->get<std::string>();

    b2CircleShape circle;
    b2PolygonShape polygon;
    b2EdgeShape edge;
    b2FixtureDef fd;
    if (t == "circle") {
        circle.m_p = vecOr(js, path, "center", b2Vec2(0.0f, 0.0f));
        circle.m_radius = float(number(*member(js, path, "radius", true), path + ".radius"));
        fd.shape = &circle;
    } else if (t == "box") {
        const b2Vec2 h = vec(*member(js, path, "half_extents", true), path + ".half_extents");
        polygon.SetAsBox(h.x, h.y, vecOr(js, path, "center", b2Vec2(0.0f, 0.0f)), float(numberOr(js, path, "angle", 0.0)));
        fd.shape = &polygon;
    } else if (t == "polygon") {
        const json* vs = member(js, path, "vertices", true);
        if (!vs->is_array() || vs->size() < 3 || vs->size() > b2_maxPolygonVertices)
            fail(path + ".vertices", "expected 3 to 8 points");
        b2Vec2 points[b2_maxPolygonVertices];
        for (std::size_t i = 0; i < vs->size(); ++i) points[i] = vec((*vs)[i], path + ".vertices[" + std::to_string(i) + "]");
        polygon.Set(points, int32(vs->size()));
        fd.shape = &polygon;
    } else if (t == "segment") {
        const json* ps = member(js, path, "points", true);
        if (!ps->is_array() || ps->size() != 2) fail(path + ".points", "expected two points");
        edge.SetTwoSided(vec((*ps)[0], path + ".points[0]"), vec((*ps)[1], path + ".points[1]"));
        fd.shape = &edge;
    } else {
        fail(path + ".type", "unknown 2D shape type \"" + t + "\" (circle, box, polygon, segment)");
    }
    fd.density = float(numberOr(js, path, "density", 1.0));
    fd.friction = float(numberOr(js, path, "friction", 0.6));
    fd.restitution = float(numberOr(js, path, "restitution", 0.0));
    fd.restitutionThreshold = restitutionThreshold;
    body->CreateFixture(&fd);
}

}  // namespace

Box2dPeer::Box2dPeer(const json& scene, const std::string& what, int velocityIterations, int positionIterations)
    : mVelocityIterations(velocityIterations), mPositionIterations(positionIterations) {
    const json* dim = member(scene, what, "dimension", true);
    if (!dim->is_number_integer() || dim->get<int>() != 2) fail(what + ".dimension", "the Box2D peer takes 2D scenes only");
    mHz = numberOr(scene, what, "hz", 60.0);
    if (!(mHz > 0.0)) fail(what + ".hz", "must be > 0");
    const float threshold = float(numberOr(scene, what, "restitution_threshold", 1.0));
    bool sleep = true;
    if (const json* sl = member(scene, what, "sleep", false)) {
        if (!sl->is_boolean()) fail(what + ".sleep", "expected true or false");
        sleep = sl->get<bool>();
    }
    mWorld = std::make_unique<b2World>(vecOr(scene, what, "gravity", b2Vec2(0.0f, -10.0f)));
    mWorld->SetAllowSleeping(sleep);

    const json* bodies = member(scene, what, "bodies", true);
    if (!bodies->is_array()) fail(what + ".bodies", "expected an array");
    mBodies.reserve(bodies->size());
    for (std::size_t i = 0; i < bodies->size(); ++i) {
        const std::string path = what + ".bodies[" + std::to_string(i) + "]";
        const json& jb = (*bodies)[i];
        b2BodyDef bd;
        std::string type = "dynamic";
        if (const json* t = member(jb, path, "type", false)) {
            if (!t->is_string()) fail(path + ".type", "expected a string");
            type = t->get<std::string>();
        }
        if (type == "static") bd.type = b2_staticBody;
        else if (type == "kinematic") bd.type = b2_kinematicBody;
        else if (type == "dynamic") bd.type = b2_dynamicBody;
        else fail(path + ".type", "expected \"static\", \"kinematic\" or \"dynamic\"");
        bd.position = vecOr(jb, path, "position", b2Vec2(0.0f, 0.0f));
        bd.angle = float(numberOr(jb, path, "angle", 0.0));
        bd.linearVelocity = vecOr(jb, path, "linear_velocity", b2Vec2(0.0f, 0.0f));
        bd.angularVelocity = float(numberOr(jb, path, "angular_velocity", 0.0));
        b2Body* body = mWorld->CreateBody(&bd);
        if (const json* js = member(jb, path, "shapes", false)) {
            if (!js->is_array()) fail(path + ".shapes", "expected an array");
            for (std::size_t k = 0; k < js->size(); ++k)
                addFixture(body, (*js)[k], path + ".shapes[" + std::to_string(k) + "]", threshold);
        }
        // The scene's linear_velocity is the centre of mass's (as in Unison's BodyDef2). Box2D reads
        // b2BodyDef::linearVelocity as the origin's and shifts it by w x (c - origin) when the fixtures move the
        // centre of mass, so set the centre-of-mass velocity again once the mass is known.
        if (bd.type != b2_staticBody) body->SetLinearVelocity(bd.linearVelocity);
        mBodies.push_back(body);
    }
}

Box2dPeer::~Box2dPeer() = default;

void Box2dPeer::step() {
    mWorld->Step(float(1.0 / mHz), mVelocityIterations, mPositionIterations);
    ++mSteps;
}

Vec2 Box2dPeer::position(int index) const {
    const b2Vec2 p = body(index)->GetPosition();
    return {double(p.x), double(p.y)};
}

double Box2dPeer::angle(int index) const { return double(body(index)->GetAngle()); }

Vec2 Box2dPeer::linearVelocity(int index) const {
    const b2Vec2 v = body(index)->GetLinearVelocity();
    return {double(v.x), double(v.y)};
}

double Box2dPeer::angularVelocity(int index) const { return double(body(index)->GetAngularVelocity()); }

bool Box2dPeer::awake(int index) const { return body(index)->IsAwake(); }

}  // namespace unison::bench
