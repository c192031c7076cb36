// scenes/scene_json3d.cpp — the 3D scene reader (see scene_json3d.h).
#include "scene_json3d.h"

#include "obj_mesh.h"

#include <limits>

namespace unison::scenes {
namespace {

static_assert(int(BodyType3::staticBody) == int(jsonio::BodyKind::staticBody) &&
                  int(BodyType3::kinematicBody) == int(jsonio::BodyKind::kinematicBody) &&
                  int(BodyType3::dynamicBody) == int(jsonio::BodyKind::dynamicBody),
              "scene body kinds cast to the world's body types");

using nlohmann::json;
using jsonio::fail;
using jsonio::member;
using jsonio::number;
using jsonio::numberOr;

Vec3 vec3(const json& v, const std::string& path) {
    const std::vector<double> n = jsonio::numbers(v, path, 3);
    return Vec3(n[0], n[1], n[2]);
}

Vec3 vec3Or(const json& obj, const std::string& path, const char* key, const Vec3& fallback) {
    const json* v = member(obj, path, key, false);
    return v ? vec3(*v, path + "." + key) : fallback;
}

std::vector<Vec3> points(const json& v, const std::string& path) {
    const json& arr = jsonio::array(v, path);
    std::vector<Vec3> out;
    for (std::size_t i = 0; i < arr.size(); ++i) out.push_back(vec3(arr[i], path + "[" + std::to_string(i) + "]"));
    return out;
}

void check(const std::string& error, const std::string& path) {
    if (!error.empty()) fail(path, error);
}

}  // namespace

Shape3 readShape3(const json& js, const std::string& path, const std::string& baseDir) {
    const json* type = member(js, path, "type", true);
    if (!type->is_string()) fail(path + ".type", "expected a string");
    const std::string t = type->get<std::string>();
    Shape3 s;
    if (t == "sphere") {
        check(makeSphere(vec3Or(js, path, "center", Vec3::Zero()), number(*member(js, path, "radius", true), path + ".radius"), &s), path);
    } else if (t == "box") {
        check(makeBox(vec3(*member(js, path, "half_extents", true), path + ".half_extents"), vec3Or(js, path, "center", Vec3::Zero()), &s), path);
    } else if (t == "hull") {
        check(makeHull(points(*member(js, path, "vertices", true), path + ".vertices"), &s), path);
    } else if (t == "plane") {
        check(makePlane(vec3(*member(js, path, "normal", true), path + ".normal"), numberOr(js, path, "offset", 0.0), &s), path);
    } else if (t == "mesh") {
        const double scale = numberOr(js, path, "scale", 1.0);
        if (!(scale > 0.0)) fail(path + ".scale", "must be > 0");
        std::vector<Vec3> vertices;
        std::vector<std::array<int, 3>> triangles;
        if (const json* obj = member(js, path, "obj", false)) {
            if (!obj->is_string()) fail(path + ".obj", "expected a file path");
            std::string file = obj->get<std::string>();
            if (!baseDir.empty() && !file.empty() && file[0] != '/') file = baseDir + "/" + file;
            ObjMesh m = readObj(file, scale);
            vertices = std::move(m.vertices);
            triangles = std::move(m.triangles);
        } else {
            for (const Vec3& v : points(*member(js, path, "vertices", true), path + ".vertices")) vertices.push_back(scale * v);
            const json& tris = jsonio::array(*member(js, path, "triangles", true), path + ".triangles");
            for (std::size_t i = 0; i < tris.size(); ++i) {
                const std::string tp = path + ".triangles[" + std::to_string(i) + "]";
                const json& tri = jsonio::array(tris[i], tp);
                if (tri.size() != 3) fail(tp, "expected [i, j, k]");
                std::array<int, 3> idx{};
                for (int k = 0; k < 3; ++k) idx[std::size_t(k)] = jsonio::integer(tri[std::size_t(k)], tp, 0, 1 << 30);
                triangles.push_back(idx);
            }
        }
        check(makeMesh(vertices, triangles, &s), path);
    } else {
        fail(path + ".type", "unknown 3D shape type \"" + t + "\" (sphere, box, hull, plane, mesh)");
    }
    const jsonio::Material mat = jsonio::material(js, path);
    s.density = mat.density;
    s.friction = mat.friction;
    s.restitution = mat.restitution;
    return s;
}

BodySpec3 readBody3(const json& jb, const std::string& path, const std::string& baseDir) {
    BodySpec3 spec;
    BodyDef3& bd = spec.def;
    bd.type = static_cast<BodyType3>(jsonio::bodyKind(jb, path));
    bd.position = vec3Or(jb, path, "position", Vec3::Zero());
    if (const json* q = member(jb, path, "orientation", false)) {
        const std::vector<double> n = jsonio::numbers(*q, path + ".orientation", 4);
        bd.orientation = Quat{n[0], n[1], n[2], n[3]};
    }
    bd.linearVelocity = vec3Or(jb, path, "linear_velocity", Vec3::Zero());
    bd.angularVelocity = vec3Or(jb, path, "angular_velocity", Vec3::Zero());
    if (const json* js = member(jb, path, "shapes", false)) {
        const json& arr = jsonio::array(*js, path + ".shapes");
        for (std::size_t k = 0; k < arr.size(); ++k)
            spec.shapes.push_back(readShape3(arr[k], path + ".shapes[" + std::to_string(k) + "]", baseDir));
    }
    return spec;
}

json inlineMeshFiles3(const json& scene, const std::string& what, const std::string& baseDir) {
    json out = scene;
    if (!out.is_object() || !out.contains("bodies") || !out["bodies"].is_array()) return out;
    json& bodies = out["bodies"];
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        json& jb = bodies[i];
        if (!jb.is_object() || !jb.contains("shapes") || !jb["shapes"].is_array()) continue;
        for (std::size_t k = 0; k < jb["shapes"].size(); ++k) {
            json& js = jb["shapes"][k];
            if (!js.is_object() || !js.contains("obj") || !js["obj"].is_string()) continue;
            const std::string path = what + ".bodies[" + std::to_string(i) + "].shapes[" + std::to_string(k) + "]";
            const double scale = numberOr(js, path, "scale", 1.0);
            if (!(scale > 0.0)) fail(path + ".scale", "must be > 0");
            std::string file = js["obj"].get<std::string>();
            if (!baseDir.empty() && !file.empty() && file[0] != '/') file = baseDir + "/" + file;
            const ObjMesh m = readObj(file, scale);
            json vertices = json::array(), triangles = json::array();
            for (const Vec3& v : m.vertices) vertices.push_back({v.x(), v.y(), v.z()});
            for (const auto& t : m.triangles) triangles.push_back({t[0], t[1], t[2]});
            js.erase("obj");
            js["scale"] = 1.0;  // the vertices are already scaled (1.0 * v is exact)
            js["vertices"] = std::move(vertices);
            js["triangles"] = std::move(triangles);
        }
    }
    return out;
}

LoadedScene3 loadScene3(const json& scene, const std::string& what, const std::string& baseDir, const WorldDef3& base) {
    const json* dim = member(scene, what, "dimension", true);
    if (!dim->is_number_integer() || dim->get<int>() != 3) fail(what + ".dimension", "expected 3");
    WorldDef3 def = base;
    def.gravity = vec3Or(scene, what, "gravity", def.gravity);
    def.hz = numberOr(scene, what, "hz", def.hz);
    if (!(def.hz > 0.0)) fail(what + ".hz", "must be > 0");
    def.restitutionThreshold = numberOr(scene, what, "restitution_threshold", def.restitutionThreshold);
    if (def.restitutionThreshold < 0.0) fail(what + ".restitution_threshold", "must be >= 0");
    if (const json* sl = member(scene, what, "sleep", false)) def.enableSleep = jsonio::boolean(*sl, what + ".sleep");
    if (const json* b = member(scene, what, "step_budget", false))  // work units per step (core/step_budget.h)
        def.stepBudget = std::uint64_t(jsonio::integer(*b, what + ".step_budget", 0, std::numeric_limits<int>::max()));
    if (const json* k = member(scene, what, "friction_directions", false))
        def.frictionDirections = jsonio::integer(*k, what + ".friction_directions", 4, 16);
    LoadedScene3 out;
    out.world = std::make_unique<World3>(def);
    const json& bodies = jsonio::array(*member(scene, what, "bodies", true), what + ".bodies");
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const std::string path = what + ".bodies[" + std::to_string(i) + "]";
        const BodySpec3 spec = readBody3(bodies[i], path, baseDir);
        std::string error;
        const BodyId id = out.world->createBody(spec.def, spec.shapes, &error);
        if (id.isNull()) fail(path, error);
        out.bodies.push_back(id);
    }
    return out;
}

}  // namespace unison::scenes
