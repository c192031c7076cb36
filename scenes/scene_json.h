// scenes/scene_json.h — reads the scene JSON of DESIGN.md into a World2, and lists the shared example scenes.
//
// Owns: the scene file contract ({"dimension", "gravity", "hz", "bodies": [{"type", "position", "angle",
// "linear_velocity", "angular_velocity", "shapes": [...]}]}) for 2D, with error messages that name the exact key.
// Invariants: a scene that fails to load leaves no partial world behind (the caller gets an error, not a world).
#pragma once

#include "json_fields.h"
#include "world2d.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace unison::scenes {

/// A malformed or invalid scene; what() names the key, e.g. "bodies[3].shapes[0].radius: must be > 0".
using SceneError = jsonio::JsonError;

/// A loaded 2D scene: the world and the ids of its bodies in file order.
struct LoadedScene2 {
    std::unique_ptr<World2> world;
    std::vector<BodyId> bodies;
};

/// One body of a scene: how to create it and its shapes.
struct BodySpec2 {
    BodyDef2 def;
    std::vector<Shape2> shapes;
};

/// Reads one scene body object ({"type", "position", "angle", "linear_velocity", "angular_velocity", "shapes"});
/// `path` names it in messages. Throws SceneError. (Also used by replay/ inputs that create bodies.)
BodySpec2 readBody2(const nlohmann::json& body, const std::string& path);

/// Builds a 2D world from scene JSON (`what` names the source in messages). Throws SceneError.
LoadedScene2 loadScene2(const nlohmann::json& scene, const std::string& what, const WorldDef2& base = {});

/// Reads and parses a scene file. Throws SceneError.
nlohmann::json readSceneFile(const std::string& path);

}  // namespace unison::scenes
