// scenes/obj_mesh.h — reads triangle meshes from Wavefront OBJ text (the 3D scenes' `obj` key, the bunny asset).
//
// Owns: the subset of OBJ the project needs: `v x y z` vertices and `f` faces (indices 1-based or negative,
// `i`, `i/t`, `i//n`, `i/t/n` forms; polygons are fanned into triangles). Other statements (vn, vt, o, g, s,
// usemtl, mtllib, comments) are skipped. Errors name the file and line.
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
/// Reads and parses an OBJ file.
ObjMesh readObj(const std::string& path, double scale = 1.0);

}  // namespace unison::scenes
