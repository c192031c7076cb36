// scenes/scene_json3d.cpp — the 3D scene reader (see scene_json3d.h).
#include "scene_json3d.h"

#include "obj_mesh.h"

#include <algorithm>
#include <limits>

namespace unison::scenes {
namespace {


using nlohmann::json;
using jsonio::fail;
using jsonio::member;

// A 3-vector whose components lie in [-limit, limit].
Vec3 vec3(const json& v, const std::string& path, double limit) {
    const std::vector<double> n = jsonio::numbersWithin(v, path, 3, limit);
    return Vec3(n[0], n[1], n[2]);
}

Vec3 vec3Or(const json& obj, const std::string& path, const char* key, double limit, const Vec3& fallback) {
    const json* v = member(obj, path, key, false);
    return v ? vec3(*v, path + "." + key, limit) : fallback;
}

std::vector<Vec3> points(const json& v, const std::string& path, std::size_t maxCount, double scale = 1.0) {
    const json& arr = jsonio::arrayUpTo(v, path, maxCount);
    std::vector<Vec3> out;
    for (std::size_t i = 0; i < arr.size(); ++i) {
        const std::string p = path + "[" + std::to_string(i) + "]";
        const Vec3 x = scale * vec3(arr[i], p, policy::kMaxCoordinate);
        if (!policy::within(x.cwiseAbs().maxCoeff(), policy::kMaxCoordinate))
            fail(p, "scaled coordinates must be in " + jsonio::rangeText(-policy::kMaxCoordinate, policy::kMaxCoordinate));
        out.push_back(x);
    }
    return out;
}

double meshScale(const json& js, const std::string& path) {
    return jsonio::numberInOr(js, path, "scale", 1.0 / policy::kMaxMeshScale, policy::kMaxMeshScale, 1.0);
}

// The OBJ file a mesh shape names, read from inside the scene's folder only.
ObjMesh meshFile(const json& js, const std::string& path, const std::string& baseDir, double scale) {
    const json* obj = member(js, path, "obj", true);
    if (!obj->is_string()) fail(path + ".obj", "expected a file path");
    return readObj(confinedPath(baseDir, obj->get<std::string>(), path + ".obj"), scale);
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
    constexpr double kMaxC = policy::kMaxCoordinate;
    if (t == "sphere") {
        const double radius = jsonio::numberIn(*member(js, path, "radius", true), path + ".radius", policy::kMinSize, policy::kMaxSize);
        check(makeSphere(vec3Or(js, path, "center", kMaxC, Vec3::Zero()), radius, &s), path);
    } else if (t == "box") {
        const Vec3 h = vec3(*member(js, path, "half_extents", true), path + ".half_extents", policy::kMaxSize);
        if (!(h.minCoeff() >= policy::kMinSize))
            fail(path + ".half_extents", "must be in " + jsonio::rangeText(policy::kMinSize, policy::kMaxSize));
        check(makeBox(h, vec3Or(js, path, "center", kMaxC, Vec3::Zero()), &s), path);
    } else if (t == "hull") {
        check(makeHull(points(*member(js, path, "vertices", true), path + ".vertices", kMaxHullPoints), &s), path);
    } else if (t == "plane") {
        const double offset = jsonio::numberInOr(js, path, "offset", -kMaxC, kMaxC, 0.0);
        check(makePlane(vec3(*member(js, path, "normal", true), path + ".normal", kMaxC), offset, &s), path);
    } else if (t == "mesh") {
        const double scale = meshScale(js, path);
        std::vector<Vec3> vertices;
        std::vector<std::array<int, 3>> triangles;
        if (member(js, path, "obj", false)) {
            ObjMesh m = meshFile(js, path, baseDir, scale);
            vertices = std::move(m.vertices);
            triangles = std::move(m.triangles);
        } else {
            vertices = points(*member(js, path, "vertices", true), path + ".vertices", policy::kMaxMeshVertices, scale);
            const json& tris = jsonio::arrayUpTo(*member(js, path, "triangles", true), path + ".triangles", policy::kMaxMeshTriangles);
            const int maxIndex = std::max(0, int(vertices.size()) - 1);
            for (std::size_t i = 0; i < tris.size(); ++i) {
                const std::string tp = path + ".triangles[" + std::to_string(i) + "]";
                const json& tri = jsonio::array(tris[i], tp);
                if (tri.size() != 3) fail(tp, "expected [i, j, k]");
                std::array<int, 3> idx{};
                for (int k = 0; k < 3; ++k) idx[std::size_t(k)] = jsonio::integer(tri[std::size_t(k)], tp, 0, maxIndex);
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
    bd.type = jsonio::bodyType(jb, path);
    bd.position = vec3Or(jb, path, "position", policy::kMaxCoordinate, Vec3::Zero());
    if (const json* q = member(jb, path, "orientation", false)) {
        const std::vector<double> n = jsonio::numbersWithin(*q, path + ".orientation", 4, policy::kMaxCoordinate);
        bd.orientation = Quat{n[0], n[1], n[2], n[3]};
    }
    bd.linearVelocity = vec3Or(jb, path, "linear_velocity", policy::kMaxSpeed, Vec3::Zero());
    bd.angularVelocity = vec3Or(jb, path, "angular_velocity", policy::kMaxAngularSpeed, Vec3::Zero());
    if (const json* js = member(jb, path, "shapes", false)) {
        const json& arr = jsonio::arrayUpTo(*js, path + ".shapes", policy::kMaxShapesPerBody);
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
            if (!js.is_object() || !js.contains("obj")) continue;
            const std::string path = what + ".bodies[" + std::to_string(i) + "].shapes[" + std::to_string(k) + "]";
            const ObjMesh m = meshFile(js, path, baseDir, meshScale(js, path));
            js.erase("obj");
            js.update(inlineMeshKeys(m));
        }
    }
    return out;
}

LoadedScene3 loadScene3(const json& scene, const std::string& what, const std::string& baseDir, const WorldDef3& base) {
    if (jsonio::integer(*member(scene, what, "dimension", true), what + ".dimension", 2, 3) != 3)
        fail(what + ".dimension", "expected 3");
    WorldDef3 def = base;
    def.gravity = vec3Or(scene, what, "gravity", policy::kMaxGravity, def.gravity);
    jsonio::readWorldSettings(scene, what, def);
    if (const json* k = member(scene, what, "friction_directions", false)) {
        // Odd counts would be rounded up by the step (the pyramid needs +t and -t): refuse them instead.
        def.frictionDirections = jsonio::integer(*k, what + ".friction_directions", policy::kMinFrictionDirections,
                                                 policy::kMaxFrictionDirections);
        if (def.frictionDirections % 2 != 0) fail(what + ".friction_directions", "must be even");
    }
    LoadedScene3 out;
    out.world = std::make_unique<World3>(def);
    out.bodies = jsonio::createBodies(*out.world, scene, what,
                                      [&](const json& body, const std::string& path) { return readBody3(body, path, baseDir); });
    return out;
}

}  // namespace unison::scenes
