// scenes/scene_json3d.h — reads 3D scene JSON (DESIGN.md keys) into a World3.
//
// Owns: the 3D side of the scene contract: {"dimension": 3, "gravity": [x, y, z], "hz", "restitution_threshold",
// "sleep", "friction_directions", "bodies": [{"type", "position": [x, y, z], "orientation": [w, x, y, z],
// "linear_velocity", "angular_velocity", "shapes": [...]}]}. Shapes: sphere (radius, center), box (half_extents,
// center), hull (vertices), plane (normal, offset), mesh (vertices + triangles, or obj: a relative path to a file
// inside the scene file's folder; optional scale), each with density, friction, restitution.
// Invariants: a scene that fails to load leaves no partial world behind; messages name the exact key; every number
// is in the range of core/input_policy.h; no file outside the scene's folder is ever opened (an `obj` with `..`, an
// absolute path, a symbolic link that leads outside, or anything but a regular file is refused), and without a
// folder (recordings, inputs) no file at all.
#pragma once

#include "json_fields.h"
#include "world3d.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace unison::scenes {

/// A loaded 3D scene: the world and the ids of its bodies in file order.
struct LoadedScene3 {
    std::unique_ptr<World3> world;
    std::vector<BodyId> bodies;
};

/// Builds a 3D world from scene JSON. `what` names the source in messages; `baseDir` is the folder `obj` paths are
/// confined to (empty: `obj` is refused). Throws jsonio::JsonError.
LoadedScene3 loadScene3(const nlohmann::json& scene, const std::string& what, const std::string& baseDir = "",
                        const WorldDef3& base = {});

/// A body read from JSON, not yet created.
struct BodySpec3 {
    BodyDef3 def;
    std::vector<Shape3> shapes;
};

/// Reads one scene body object ({"type", "position", "orientation", "linear_velocity", "angular_velocity",
/// "shapes"}); `path` names it in messages. Throws jsonio::JsonError. (Also used by replay/ inputs that create bodies.)
BodySpec3 readBody3(const nlohmann::json& body, const std::string& path, const std::string& baseDir = "");

/// The scene with every mesh shape that names an `obj` file replaced by its vertices and triangles (already
/// scaled), so that the scene no longer depends on files or the working directory (recordings store it).
/// Throws jsonio::JsonError on a missing or bad file.
nlohmann::json inlineMeshFiles3(const nlohmann::json& scene, const std::string& what, const std::string& baseDir);

/// Reads one 3D shape object (exposed for tools that build bodies themselves).
Shape3 readShape3(const nlohmann::json& js, const std::string& path, const std::string& baseDir);

}  // namespace unison::scenes
