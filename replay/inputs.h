// replay/inputs.h — the per-tick inputs of a recorded match (docs/formats.md) and the session that applies
// them to a 2D or 3D world, tick by tick, identically when recording and when verifying.
//
// Owns: InputAction (one input), InputScript (all inputs of a match, ordered by tick, file order within a tick),
// their JSON form, and Session2 / Session3 (a world loaded from a scene plus the table of body numbers the inputs
// use). 3D inputs carry 3-vectors (impulse, force, point, velocities, gravity) and 3D body definitions.
// Body numbers: the scene's bodies are 0..n-1 in file order; each create_body input appends the next number.
// A number keeps naming its body after other bodies are destroyed; naming a destroyed body is an error.
// Tick t means: apply the inputs of tick t, then step once; hash t is the state hash after that step (t >= 1).
#pragma once

#include "scene_json.h"
#include "scene_json3d.h"
#include "world2d.h"
#include "world3d.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace unison::replay {

/// Bad input of any replay file or command (exit code 2); what() says which file, key or tick.
using ReplayError = jsonio::JsonError;

enum class InputType { applyImpulse, applyForce, setVelocity, createBody, destroyBody, setGravity };

/// One input, applied before the step of its tick.
struct InputAction {
    int tick = 1;                 ///< >= 1
    InputType type = InputType::applyImpulse;
    int body = -1;                ///< body number (apply_*, set_velocity, destroy_body)
    Vec2 vector;                  ///< impulse (N s), force (N), linear velocity (m/s) or gravity (m/s^2)
    bool hasPoint = false;        ///< apply_*: world point given (else the centre of mass)
    Vec2 point;                   ///< apply_*: world point (m)
    double angularVelocity = 0.0; ///< set_velocity (rad/s)
    nlohmann::json bodyDef;       ///< create_body: a scene body object
    // 3D scripts use these instead of vector, point and angularVelocity:
    Vec3 vector3 = Vec3::Zero();           ///< impulse, force, linear velocity or gravity
    Vec3 point3 = Vec3::Zero();            ///< apply_*: world point (m)
    Vec3 angularVelocity3 = Vec3::Zero();  ///< set_velocity (rad/s, world axes)
};

/// Every input of a match, sorted by tick (stable: file order within a tick).
struct InputScript {
    int dimension = 2;  ///< 2 or 3: which vectors the actions carry
    std::vector<InputAction> actions;
};

/// 3 for a scene with "dimension": 3, else 2.
int sceneDimension(const nlohmann::json& scene);

/// Parses {"inputs": [{"tick", "type", ...}]} (docs/formats.md) for a scene of `dimension` (2 or 3: the size of
/// every vector; in 3D angular_velocity is a 3-vector and body_def a 3D scene body); `what` names the source.
/// Throws ReplayError.
InputScript parseInputs(const nlohmann::json& js, const std::string& what, int dimension = 2);
/// The JSON form parseInputs reads (numbers written with round-trip precision).
nlohmann::json inputsToJson(const InputScript& script);

/// A scene being stepped with inputs: what record and verify both run. World is World2 or World3.
template <class World>
class Session {
public:
    /// Loads the scene (3D: no `obj` files; a recording's scene carries its meshes inline). Throws ReplayError on a
    /// bad scene.
    Session(const nlohmann::json& scene, const std::string& what);
    /// Applies the inputs of tick `tick` (script.actions[next..] with that tick), then steps. Throws ReplayError
    /// when an input cannot be applied (unknown or destroyed body, static body, bad body definition) or when the
    /// step overflows (World::fault()).
    void tick(int tick, const InputScript& script);
    World& world() { return *mWorld; }
    const World& world() const { return *mWorld; }
    /// Body number of a live id, or -1.
    int bodyNumber(BodyId id) const;

private:
    void apply(const InputAction& a, std::size_t index);
    BodyId bodyOf(const InputAction& a, std::size_t index) const;
    std::unique_ptr<World> mWorld;
    std::vector<BodyId> mBodies;  // body number -> id (stale once destroyed)
    std::size_t mNext = 0;        // first action not yet applied
};
template <>
Session<World2>::Session(const nlohmann::json& scene, const std::string& what);
template <>
Session<World3>::Session(const nlohmann::json& scene, const std::string& what);
template <>
void Session<World2>::apply(const InputAction& a, std::size_t index);
template <>
void Session<World3>::apply(const InputAction& a, std::size_t index);
using Session2 = Session<World2>;
using Session3 = Session<World3>;
extern template class Session<World2>;
extern template class Session<World3>;

}  // namespace unison::replay
