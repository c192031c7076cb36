// scenes/obj_mesh.cpp — see obj_mesh.h.
#include "obj_mesh.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace unison::scenes {
namespace {

// One face corner: the vertex index before the first '/', 1-based, or negative (relative to the end).
int cornerIndex(const std::string& token, int vertexCount, const std::string& where) {
    const std::string head = token.substr(0, token.find('/'));
    errno = 0;
    char* end = nullptr;
    const long long v = head.empty() ? 0 : std::strtoll(head.c_str(), &end, 10);
    if (head.empty() || end != head.c_str() + head.size() || errno == ERANGE) jsonio::fail(where, "bad face index");
    const long long index = v > 0 ? v - 1 : vertexCount + v;
    if (v == 0 || index < 0 || index >= vertexCount) jsonio::fail(where, "face index out of range");
    return int(index);
}

// A printable, bounded copy of a user-given path for messages.
std::string shown(const std::string& s) {
    std::string out = s.substr(0, 200);
    for (char& c : out)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    return "\"" + out + "\"";
}

}  // namespace

ObjMesh parseObj(const std::string& text, const std::string& what, double scale) {
    if (!std::isfinite(scale) || !(scale > 0.0)) jsonio::fail(what, "scale must be finite and > 0");
    ObjMesh mesh;
    std::istringstream in(text);
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        const std::string where = what + ":" + std::to_string(lineNo);
        std::istringstream ls(line);
        std::string tag;
        if (!(ls >> tag) || tag[0] == '#') continue;
        if (tag == "v") {
            if (mesh.vertices.size() >= policy::kMaxMeshVertices)
                jsonio::fail(where, "more than " + std::to_string(policy::kMaxMeshVertices) + " vertices");
            double c[3];
            for (double& x : c) {
                std::string tok;
                if (!(ls >> tok)) jsonio::fail(where, "vertex needs x y z");
                errno = 0;
                char* end = nullptr;
                x = std::strtod(tok.c_str(), &end);
                if (end != tok.c_str() + tok.size() || tok.empty() || errno == ERANGE || !std::isfinite(x))
                    jsonio::fail(where, "bad coordinate");
                x *= scale;
                if (!policy::within(x, policy::kMaxCoordinate))
                    jsonio::fail(where, "coordinate (after scaling) outside " +
                                            jsonio::rangeText(-policy::kMaxCoordinate, policy::kMaxCoordinate));
            }
            mesh.vertices.push_back(Vec3(c[0], c[1], c[2]));
        } else if (tag == "f") {
            std::vector<int> corners;
            std::string tok;
            while (ls >> tok) corners.push_back(cornerIndex(tok, int(mesh.vertices.size()), where));
            if (corners.size() < 3) jsonio::fail(where, "a face needs at least 3 vertices");
            if (mesh.triangles.size() + corners.size() - 2 > policy::kMaxMeshTriangles)
                jsonio::fail(where, "more than " + std::to_string(policy::kMaxMeshTriangles) + " triangles");
            for (std::size_t k = 1; k + 1 < corners.size(); ++k) mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
        }
    }
    if (mesh.vertices.empty() || mesh.triangles.empty()) jsonio::fail(what, "no vertices or faces");
    return mesh;
}

ObjMesh readObj(const std::string& path, double scale) {
    return parseObj(jsonio::readFile(path, policy::kMaxObjBytes), path, scale);
}

nlohmann::json inlineMeshKeys(const ObjMesh& mesh) {
    nlohmann::json vertices = nlohmann::json::array(), triangles = nlohmann::json::array();
    for (const Vec3& v : mesh.vertices) vertices.push_back({v.x(), v.y(), v.z()});
    for (const auto& t : mesh.triangles) triangles.push_back({t[0], t[1], t[2]});
    return {{"vertices", std::move(vertices)}, {"triangles", std::move(triangles)}, {"scale", 1.0}};
}

std::string confinedPath(const std::string& baseDir, const std::string& relative, const std::string& key) {
    namespace fs = std::filesystem;
    if (baseDir.empty())
        jsonio::fail(key, "mesh files are read only for a scene file; give the mesh's vertices and triangles here");
    if (relative.empty() || relative.size() > 4096 || relative.find('\0') != std::string::npos)
        jsonio::fail(key, "expected a relative file path");
    const fs::path rel(relative);
    if (rel.is_absolute() || rel.has_root_path())
        jsonio::fail(key, shown(relative) + " must be a relative path inside the scene's folder");
    for (const fs::path& part : rel)
        if (part == "..") jsonio::fail(key, shown(relative) + " must not leave the scene's folder (no ..)");
    std::error_code ec;
    const fs::path base = fs::canonical(fs::path(baseDir), ec);
    if (ec) jsonio::fail(key, "the scene's folder cannot be resolved");
    const fs::path target = fs::weakly_canonical(base / rel, ec);
    if (ec) jsonio::fail(key, shown(relative) + " cannot be resolved");
    // Compared component by component: the target's leading components must be exactly the base's.
    auto t = target.begin();
    for (auto b = base.begin(); b != base.end(); ++b, ++t)
        if (t == target.end() || *t != *b) jsonio::fail(key, shown(relative) + " leads outside the scene's folder");
    if (t == target.end()) jsonio::fail(key, shown(relative) + " is not a file");
    if (!fs::is_regular_file(target, ec)) jsonio::fail(key, shown(relative) + " is not a regular file (or does not exist)");
    return target.string();
}

}  // namespace unison::scenes
