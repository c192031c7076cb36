// samples/json_read.h — strict readers for the command-line tool's JSON files.
//
// Owns: turning a nlohmann::json value into numbers and vectors with error messages that name the exact key
// ("bodies[2].mass: expected a finite number"). Every reader throws InputError, which the tool reports on stderr
// with exit code 2 (DESIGN.md "Command-line contract").
#pragma once

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace unison::cli {

/// Bad user input: the message names the file position or key. Exit code 2.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Parses JSON text; a syntax error becomes an InputError naming `what` (usually the file name).
nlohmann::json parseJson(const std::string& text, const std::string& what);
/// Reads a whole file; a missing or unreadable file is an InputError.
std::string readFile(const std::string& path);

/// The member `key` of object `obj` (which `path` names); an InputError when missing and required.
const nlohmann::json* member(const nlohmann::json& obj, const std::string& path, const char* key, bool required);
/// A finite number.
double number(const nlohmann::json& v, const std::string& path);
/// An integer in [lo, hi].
int integer(const nlohmann::json& v, const std::string& path, int lo, int hi);
/// A boolean.
bool boolean(const nlohmann::json& v, const std::string& path);
/// An array of exactly `size` finite numbers.
std::vector<double> numbers(const nlohmann::json& v, const std::string& path, std::size_t size);
/// An array (any length).
const nlohmann::json& array(const nlohmann::json& v, const std::string& path);

}  // namespace unison::cli
