// scenes/obj_mesh.h — reads triangle meshes from Wavefront OBJ text (the 3D scenes' `obj` key, the bunny asset), and
// confines the files a scene may name to the scene's own folder.
//
// Owns: the subset of OBJ the project needs: `v x y z` vertices and `f` faces (indices 1-based or negative,
// `i`, `i/t`, `i//n`, `i/t/n` forms; polygons are fanned into triangles). Other statements (vn, vt, o, g, s,
// usemtl, mtllib, comments) are skipped. Errors name the file and line but never quote the file's text.
// Limits (core/input_policy.h): at most kMaxObjBytes of text, kMaxMeshVertices vertices, kMaxMeshTriangles
// triangles, coordinates (after scaling) within kMaxCoordinate.
#pragma once

#include "json_fields.h"
#include "shapes3d.h"

#include <array>
#include <string>
#include <vector>

namespace unison::scenes {

/// A mesh as read: vertices (m, after scaling) and triangles (0-based vertex indices).
struct ObjMesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<int, 3>> triangles;
};

/// Parses OBJ text; `what` names the source in messages. Throws jsonio::JsonError on malformed input.
ObjMesh parseObj(const std::string& text, const std::string& what, double scale = 1.0);
/// Reads and parses an OBJ file (at most policy::kMaxObjBytes).
ObjMesh readObj(const std::string& path, double scale = 1.0);

/// The mesh as the keys of an inline scene mesh: {"vertices", "triangles", "scale": 1} (the vertices are already
/// scaled, and 1.0 * v is exact, so a world loaded from it is the one the file gives).
nlohmann::json inlineMeshKeys(const ObjMesh& mesh);

/// The file `relative` (a scene's `obj` value) inside folder `baseDir`, after checking that it stays there: a
/// relative path without `..` components, that resolves (symbolic links followed) to a regular file under
/// baseDir. `key` names the scene key in messages. Throws jsonio::JsonError; an empty baseDir refuses every path
/// (scenes stored in recordings and inputs carry their meshes inline).
std::string confinedPath(const std::string& baseDir, const std::string& relative, const std::string& key);

}  // namespace unison::scenes
