// scenes/json_fields.h — strict readers for every JSON file of the project (resolver input, scenes, the Box2D peer).
//
// Owns: turning a nlohmann::json value into numbers and vectors with error messages that name the exact key
// ("bodies[2].mass: expected a finite number"). Every reader throws JsonError; the command-line tool reports it on
// stderr with exit code 2 (DESIGN.md "Command-line contract").
#pragma once

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

/// Parses JSON text; a syntax error becomes an JsonError naming `what` (usually the file name).
nlohmann::json parseJson(const std::string& text, const std::string& what);
/// Reads a whole file; a missing or unreadable file is an JsonError.
std::string readFile(const std::string& path);

/// The member `key` of object `obj` (which `path` names); an JsonError when missing and required.
const nlohmann::json* member(const nlohmann::json& obj, const std::string& path, const char* key, bool required);
/// A finite number.
double number(const nlohmann::json& v, const std::string& path);
/// The finite number obj[key], or `fallback` when the key is absent.
double numberOr(const nlohmann::json& obj, const std::string& path, const char* key, double fallback);
/// An integer in [lo, hi].
int integer(const nlohmann::json& v, const std::string& path, int lo, int hi);
/// A boolean.
bool boolean(const nlohmann::json& v, const std::string& path);
/// An array of exactly `size` finite numbers.
std::vector<double> numbers(const nlohmann::json& v, const std::string& path, std::size_t size);
/// An array (any length).
const nlohmann::json& array(const nlohmann::json& v, const std::string& path);

/// The material keys of a scene shape.
struct Material {
    double density = 1.0;      ///< kg per m^2 (2D) or m^3 (3D), >= 0
    double friction = 0.6;     ///< >= 0
    double restitution = 0.0;  ///< in [0, 1]
};
/// Reads "density", "friction" and "restitution" of a shape object (defaults above), checking their ranges.
Material material(const nlohmann::json& shape, const std::string& path);

/// Body kinds of the scene files, in the order of BodyType / BodyType3 (static_cast between them is exact).
enum class BodyKind { staticBody = 0, kinematicBody = 1, dynamicBody = 2 };
/// Reads a body's "type" ("static", "kinematic", "dynamic"; default dynamic).
BodyKind bodyKind(const nlohmann::json& body, const std::string& path);

}  // namespace unison::jsonio
