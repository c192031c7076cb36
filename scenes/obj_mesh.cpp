// scenes/obj_mesh.cpp — see obj_mesh.h.
#include "obj_mesh.h"

#include <cmath>
#include <sstream>

namespace unison::scenes {
namespace {

// One face corner: the vertex index before the first '/', 1-based, or negative (relative to the end).
int cornerIndex(const std::string& token, int vertexCount, const std::string& where) {
    const std::string head = token.substr(0, token.find('/'));
    std::size_t used = 0;
    long v = 0;
    try {
        v = std::stol(head, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != head.size()) jsonio::fail(where, "bad face index \"" + token + "\"");
    const long index = v > 0 ? v - 1 : vertexCount + v;
    if (v == 0 || index < 0 || index >= vertexCount) jsonio::fail(where, "face index " + head + " out of range");
    return int(index);
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
            double c[3];
            for (double& x : c) {
                std::string tok;
                if (!(ls >> tok)) jsonio::fail(where, "vertex needs x y z");
                std::size_t used = 0;
                try {
                    x = std::stod(tok, &used);
                } catch (const std::exception&) {
                    used = 0;
                }
                if (used != tok.size() || used == 0 || !std::isfinite(x)) jsonio::fail(where, "bad coordinate \"" + tok + "\"");
            }
            mesh.vertices.push_back(Vec3(scale * c[0], scale * c[1], scale * c[2]));
        } else if (tag == "f") {
            std::vector<int> corners;
            std::string tok;
            while (ls >> tok) corners.push_back(cornerIndex(tok, int(mesh.vertices.size()), where));
            if (corners.size() < 3) jsonio::fail(where, "a face needs at least 3 vertices");
            for (std::size_t k = 1; k + 1 < corners.size(); ++k) mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
        }
    }
    if (mesh.vertices.empty() || mesh.triangles.empty()) jsonio::fail(what, "no vertices or faces");
    return mesh;
}

ObjMesh readObj(const std::string& path, double scale) { return parseObj(jsonio::readFile(path), path, scale); }

}  // namespace unison::scenes
