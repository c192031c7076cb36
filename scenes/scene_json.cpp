// scenes/scene_json.cpp — the 2D scene reader (see scene_json.h).
#include "scene_json.h"

#include <cmath>
#include <limits>

namespace unison::scenes {
namespace {


using nlohmann::json;

using jsonio::fail;
using jsonio::member;

// A 2-vector whose components lie in [-limit, limit].
Vec2 vec(const json& v, const std::string& path, double limit) {
    if (!v.is_array() || v.size() != 2) fail(path, "expected [x, y]");
    return {jsonio::numberIn(v[0], path + "[0]", -limit, limit), jsonio::numberIn(v[1], path + "[1]", -limit, limit)};
}

Vec2 vecOr(const json& obj, const std::string& path, const char* key, double limit, Vec2 fallback) {
    const json* v = member(obj, path, key, false);
    return v ? vec(*v, path + "." + key, limit) : fallback;
}

double size(const json& obj, const std::string& path, const char* key) {
    return jsonio::numberIn(*member(obj, path, key, true), path + "." + key, policy::kMinSize, policy::kMaxSize);
}

void check(const std::string& error, const std::string& path) {
    if (!error.empty()) fail(path, error);
}

Shape2 readShape(const json& js, const std::string& path) {
    const json* type = member(js, path, "type", true);
    if (!type->is_string()) fail(path + ".type", "expected a string");
    const std::string t = type->get<std::string>();
    Shape2 s;
    constexpr double kMaxC = policy::kMaxCoordinate;
    if (t == "circle") {
        s.type = ShapeType::circle;
        check(makeCircle(vecOr(js, path, "center", kMaxC, {}), size(js, path, "radius"), &s.circle), path);
    } else if (t == "box") {
        s.type = ShapeType::polygon;
        const Vec2 h = vec(*member(js, path, "half_extents", true), path + ".half_extents", policy::kMaxSize);
        if (!(h.x >= policy::kMinSize && h.y >= policy::kMinSize))
            fail(path + ".half_extents", "must be in " + jsonio::rangeText(policy::kMinSize, policy::kMaxSize));
        const double angle = jsonio::numberInOr(js, path, "angle", -policy::kMaxAngle, policy::kMaxAngle, 0.0);
        check(makeBox(h.x, h.y, vecOr(js, path, "center", kMaxC, {}), angle, &s.polygon), path);
    } else if (t == "polygon") {
        s.type = ShapeType::polygon;
        const json& vs = jsonio::arrayUpTo(*member(js, path, "vertices", true), path + ".vertices", kMaxPolygonVertices);
        std::vector<Vec2> pts;
        for (std::size_t i = 0; i < vs.size(); ++i) pts.push_back(vec(vs[i], path + ".vertices[" + std::to_string(i) + "]", kMaxC));
        check(makePolygon(pts, &s.polygon), path);
    } else if (t == "segment") {
        s.type = ShapeType::segment;
        const json* ps = member(js, path, "points", true);
        if (!ps->is_array() || ps->size() != 2) fail(path + ".points", "expected two points");
        check(makeSegment(vec((*ps)[0], path + ".points[0]", kMaxC), vec((*ps)[1], path + ".points[1]", kMaxC), &s.segment), path);
    } else {
        fail(path + ".type", "unknown 2D shape type \"" + t + "\" (circle, box, polygon, segment)");
    }
    const jsonio::Material mat = jsonio::material(js, path);
    s.density = mat.density;
    s.friction = mat.friction;
    s.restitution = mat.restitution;
    return s;
}

}  // namespace

BodySpec2 readBody2(const json& jb, const std::string& path) {
    BodySpec2 spec;
    BodyDef2& bd = spec.def;
    bd.type = jsonio::bodyType(jb, path);
    bd.position = vecOr(jb, path, "position", policy::kMaxCoordinate, {});
    bd.angle = jsonio::numberInOr(jb, path, "angle", -policy::kMaxAngle, policy::kMaxAngle, 0.0);
    bd.linearVelocity = vecOr(jb, path, "linear_velocity", policy::kMaxSpeed, {});
    bd.angularVelocity =
        jsonio::numberInOr(jb, path, "angular_velocity", -policy::kMaxAngularSpeed, policy::kMaxAngularSpeed, 0.0);
    if (const json* js = member(jb, path, "shapes", false)) {
        const json& arr = jsonio::arrayUpTo(*js, path + ".shapes", policy::kMaxShapesPerBody);
        for (std::size_t k = 0; k < arr.size(); ++k) spec.shapes.push_back(readShape(arr[k], path + ".shapes[" + std::to_string(k) + "]"));
    }
    return spec;
}

LoadedScene2 loadScene2(const json& scene, const std::string& what, const WorldDef2& base) {
    if (jsonio::integer(*member(scene, what, "dimension", true), what + ".dimension", 2, 3) != 2)
        fail(what + ".dimension", "expected 2 here (3D scenes are read by loadScene3)");
    WorldDef2 def = base;
    def.gravity = vecOr(scene, what, "gravity", policy::kMaxGravity, def.gravity);
    jsonio::readWorldSettings(scene, what, def);
    LoadedScene2 out;
    out.world = std::make_unique<World2>(def);
    out.bodies = jsonio::createBodies(*out.world, scene, what, readBody2);
    return out;
}

json readSceneFile(const std::string& path) { return jsonio::parseJson(jsonio::readFile(path), path); }

}  // namespace unison::scenes
