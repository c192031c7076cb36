// scenes/json_fields.h — strict readers for every JSON file of the project (resolver input, scenes, the Box2D peer).
//
// Owns: the one place JSON text is parsed (parseJson: bounded size and nesting depth, numbers that overflow a double
// and syntax errors turned into JsonError naming the key or the line, never echoing the text), bounded file reads,
// and turning a nlohmann::json value into numbers and vectors with error messages that name the exact key
// ("bodies[2].mass: expected a finite number"). Every reader throws JsonError; the command-line tool reports it on
// stderr with exit code 2 (DESIGN.md "Command-line contract"). The ranges are core/input_policy.h's.
#pragma once

#include "input_policy.h"
#include "world_settings.h"

#include <unison/types.h>

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace unison::jsonio {

/// Bad JSON input: the message names the file position or key.
struct JsonError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Throws JsonError("path: why").
[[noreturn]] void fail(const std::string& path, const std::string& why);

/// Parses JSON text of at most policy::kMaxJsonBytes, nested at most policy::kMaxJsonDepth deep, without duplicate
/// object keys. A syntax error (named by line and column), a number that overflows a double (named by its key) or a
/// limit becomes a JsonError naming `what` (usually the file name); the text itself is never quoted.
nlohmann::json parseJson(const std::string& text, const std::string& what);
/// Reads a whole file of at most `maxBytes` bytes (reading stops there, so /dev/zero is refused quickly); a
/// missing, unreadable or larger file is a JsonError.
std::string readFile(const std::string& path, std::size_t maxBytes = policy::kMaxJsonBytes);

/// The member `key` of object `obj` (which `path` names); an JsonError when missing and required.
const nlohmann::json* member(const nlohmann::json& obj, const std::string& path, const char* key, bool required);
/// A finite number.
double number(const nlohmann::json& v, const std::string& path);
/// A finite number in [lo, hi].
double numberIn(const nlohmann::json& v, const std::string& path, double lo, double hi);
/// The finite number obj[key], or `fallback` when the key is absent.
double numberOr(const nlohmann::json& obj, const std::string& path, const char* key, double fallback);
/// The number obj[key] in [lo, hi], or `fallback` when the key is absent.
double numberInOr(const nlohmann::json& obj, const std::string& path, const char* key, double lo, double hi,
                  double fallback);
/// An integer in [lo, hi] (a JSON integer: 2.0 and 4294967298 are not an int in [2, 3]).
int integer(const nlohmann::json& v, const std::string& path, int lo, int hi);
/// A boolean.
bool boolean(const nlohmann::json& v, const std::string& path);
/// An array of exactly `size` finite numbers.
std::vector<double> numbers(const nlohmann::json& v, const std::string& path, std::size_t size);
/// An array of exactly `size` numbers, each in [-limit, limit].
std::vector<double> numbersWithin(const nlohmann::json& v, const std::string& path, std::size_t size, double limit);
/// An array (any length).
const nlohmann::json& array(const nlohmann::json& v, const std::string& path);
/// An array of at most `maxSize` elements.
const nlohmann::json& arrayUpTo(const nlohmann::json& v, const std::string& path, std::size_t maxSize);
/// True when every number in v (a value this program built, at most a few levels deep) is finite: output must
/// never print NaN or infinity as null.
bool allFinite(const nlohmann::json& v);
/// "[lo, hi]" with the bounds in shortest form (for messages).
std::string rangeText(double lo, double hi);

/// The material keys of a scene shape.
struct Material {
    double density = 1.0;      ///< kg per m^2 (2D) or m^3 (3D), in [0, policy::kMaxDensity]
    double friction = 0.6;     ///< in [0, policy::kMaxFriction]
    double restitution = 0.0;  ///< in [0, 1]
};
/// Reads "density", "friction" and "restitution" of a shape object (defaults above), checking their ranges.
Material material(const nlohmann::json& shape, const std::string& path);

/// Reads a body's "type" ("static", "kinematic", "dynamic"; default dynamic).
BodyType bodyType(const nlohmann::json& body, const std::string& path);

/// Reads the scene keys both dimensions share into `def`: "hz", "restitution_threshold", "sleep" and "step_budget"
/// (work units per step, core/step_budget.h); absent keys keep def's values.
void readWorldSettings(const nlohmann::json& scene, const std::string& what, WorldSettings& def);

/// Creates the scene's "bodies" in `world` in file order; readBody(json, path) returns a spec with .def and
/// .shapes. A body the world refuses fails with its path and the world's reason.
template <class World, class ReadBody>
std::vector<BodyId> createBodies(World& world, const nlohmann::json& scene, const std::string& what, ReadBody readBody) {
    const nlohmann::json& bodies = arrayUpTo(*member(scene, what, "bodies", true), what + ".bodies", policy::kMaxBodies);
    std::vector<BodyId> ids;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const std::string path = what + ".bodies[" + std::to_string(i) + "]";
        const auto spec = readBody(bodies[i], path);
        std::string error;
        const BodyId id = world.createBody(spec.def, spec.shapes, &error);
        if (id.isNull()) fail(path, error);
        ids.push_back(id);
    }
    return ids;
}

}  // namespace unison::jsonio
