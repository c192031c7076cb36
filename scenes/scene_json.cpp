// scenes/scene_json.cpp — the 2D scene reader (see scene_json.h).
#include "scene_json.h"

#include <cmath>
#include <limits>

namespace unison::scenes {
namespace {

static_assert(int(BodyType::staticBody) == int(jsonio::BodyKind::staticBody) &&
                  int(BodyType::kinematicBody) == int(jsonio::BodyKind::kinematicBody) &&
                  int(BodyType::dynamicBody) == int(jsonio::BodyKind::dynamicBody),
              "scene body kinds cast to the world's body types");

using nlohmann::json;

using jsonio::fail;
using jsonio::member;
using jsonio::number;
using jsonio::numberOr;

Vec2 vec(const json& v, const std::string& path) {
    if (!v.is_array() || v.size() != 2) fail(path, "expected [x, y]");
    return {number(v[0], path + "[0]"), number(v[1], path + "[1]")};
}

Vec2 vecOr(const json& obj, const std::string& path, const char* key, Vec2 fallback) {
    const json* v = member(obj, path, key, false);
    return v ? vec(*v, path + "." + key) : fallback;
}

void check(const std::string& error, const std::string& path) {
    if (!error.empty()) fail(path, error);
}

Shape2 readShape(const json& js, const std::string& path) {
    const json* type = member(js, path, "type", true);
    if (!type->is_string()) fail(path + ".type", "expected a string");
    const std::string t = type->get<std::string>();
    Shape2 s;
    if (t == "circle") {
        s.type = ShapeType::circle;
        check(makeCircle(vecOr(js, path, "center", {}), number(*member(js, path, "radius", true), path + ".radius"), &s.circle), path);
    } else if (t == "box") {
        s.type = ShapeType::polygon;
        const Vec2 h = vec(*member(js, path, "half_extents", true), path + ".half_extents");
        check(makeBox(h.x, h.y, vecOr(js, path, "center", {}), numberOr(js, path, "angle", 0.0), &s.polygon), path);
    } else if (t == "polygon") {
        s.type = ShapeType::polygon;
        const json* vs = member(js, path, "vertices", true);
        if (!vs->is_array()) fail(path + ".vertices", "expected an array of [x, y]");
        std::vector<Vec2> pts;
        for (std::size_t i = 0; i < vs->size(); ++i) pts.push_back(vec((*vs)[i], path + ".vertices[" + std::to_string(i) + "]"));
        check(makePolygon(pts, &s.polygon), path);
    } else if (t == "segment") {
        s.type = ShapeType::segment;
        const json* ps = member(js, path, "points", true);
        if (!ps->is_array() || ps->size() != 2) fail(path + ".points", "expected two points");
        check(makeSegment(vec((*ps)[0], path + ".points[0]"), vec((*ps)[1], path + ".points[1]"), &s.segment), path);
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
    bd.type = static_cast<BodyType>(jsonio::bodyKind(jb, path));
    bd.position = vecOr(jb, path, "position", {});
    bd.angle = numberOr(jb, path, "angle", 0.0);
    bd.linearVelocity = vecOr(jb, path, "linear_velocity", {});
    bd.angularVelocity = numberOr(jb, path, "angular_velocity", 0.0);
    if (const json* js = member(jb, path, "shapes", false)) {
        if (!js->is_array()) fail(path + ".shapes", "expected an array");
        for (std::size_t k = 0; k < js->size(); ++k) spec.shapes.push_back(readShape((*js)[k], path + ".shapes[" + std::to_string(k) + "]"));
    }
    return spec;
}

LoadedScene2 loadScene2(const json& scene, const std::string& what, const WorldDef2& base) {
    const json* dim = member(scene, what, "dimension", true);
    if (!dim->is_number_integer()) fail(what + ".dimension", "expected 2 or 3");
    if (dim->get<int>() != 2) fail(what + ".dimension", "expected 2 here (3D scenes are read by loadScene3)");
    WorldDef2 def = base;
    def.gravity = vecOr(scene, what, "gravity", def.gravity);
    def.hz = numberOr(scene, what, "hz", def.hz);
    if (!(def.hz > 0.0)) fail(what + ".hz", "must be > 0");
    if (const json* t = member(scene, what, "restitution_threshold", false)) def.restitutionThreshold = number(*t, what + ".restitution_threshold");
    if (const json* sl = member(scene, what, "sleep", false)) {
        if (!sl->is_boolean()) fail(what + ".sleep", "expected true or false");
        def.enableSleep = sl->get<bool>();
    }
    if (const json* b = member(scene, what, "step_budget", false))  // work units per step (core/step_budget.h)
        def.stepBudget = std::uint64_t(jsonio::integer(*b, what + ".step_budget", 0, std::numeric_limits<int>::max()));
    LoadedScene2 out;
    out.world = std::make_unique<World2>(def);
    const json* bodies = member(scene, what, "bodies", true);
    if (!bodies->is_array()) fail(what + ".bodies", "expected an array");
    for (std::size_t i = 0; i < bodies->size(); ++i) {
        const std::string path = what + ".bodies[" + std::to_string(i) + "]";
        const BodySpec2 spec = readBody2((*bodies)[i], path);
        std::string error;
        const BodyId id = out.world->createBody(spec.def, spec.shapes, &error);
        if (id.isNull()) fail(path, error);
        out.bodies.push_back(id);
    }
    return out;
}

json readSceneFile(const std::string& path) { return jsonio::parseJson(jsonio::readFile(path), path); }

std::string sceneDir() { return UNISON_SCENE_DIR; }

}  // namespace unison::scenes
