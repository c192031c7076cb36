// scenes/json_fields.cpp — strict JSON readers with key-precise messages (see json_fields.h).
#include "json_fields.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace unison::jsonio {

void fail(const std::string& path, const std::string& why) { throw JsonError(path + ": " + why); }

nlohmann::json parseJson(const std::string& text, const std::string& what) {
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw JsonError(what + ": malformed JSON: " + e.what());
    }
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw JsonError(path + ": cannot open file");
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) throw JsonError(path + ": read error");
    return s.str();
}

const nlohmann::json* member(const nlohmann::json& obj, const std::string& path, const char* key, bool required) {
    if (!obj.is_object()) throw JsonError(path + ": expected an object");
    const auto it = obj.find(key);
    if (it == obj.end()) {
        if (required) throw JsonError(path + "." + key + ": missing");
        return nullptr;
    }
    return &*it;
}

double number(const nlohmann::json& v, const std::string& path) {
    if (!v.is_number()) throw JsonError(path + ": expected a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) throw JsonError(path + ": expected a finite number");
    return x;
}

double numberOr(const nlohmann::json& obj, const std::string& path, const char* key, double fallback) {
    const nlohmann::json* v = member(obj, path, key, false);
    return v ? number(*v, path + "." + key) : fallback;
}

int integer(const nlohmann::json& v, const std::string& path, int lo, int hi) {
    if (!v.is_number_integer()) throw JsonError(path + ": expected an integer");
    const long long x = v.get<long long>();
    if (x < lo || x > hi) throw JsonError(path + ": must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(x);
}

bool boolean(const nlohmann::json& v, const std::string& path) {
    if (!v.is_boolean()) throw JsonError(path + ": expected true or false");
    return v.get<bool>();
}

std::vector<double> numbers(const nlohmann::json& v, const std::string& path, std::size_t size) {
    if (!v.is_array() || v.size() != size)
        throw JsonError(path + ": expected an array of " + std::to_string(size) + " numbers");
    std::vector<double> out;
    for (std::size_t i = 0; i < size; ++i) out.push_back(number(v[i], path + "[" + std::to_string(i) + "]"));
    return out;
}

const nlohmann::json& array(const nlohmann::json& v, const std::string& path) {
    if (!v.is_array()) throw JsonError(path + ": expected an array");
    return v;
}

Material material(const nlohmann::json& shape, const std::string& path) {
    Material m;
    m.density = numberOr(shape, path, "density", m.density);
    m.friction = numberOr(shape, path, "friction", m.friction);
    m.restitution = numberOr(shape, path, "restitution", m.restitution);
    if (m.density < 0.0) fail(path + ".density", "must be >= 0");
    if (m.friction < 0.0) fail(path + ".friction", "must be >= 0");
    if (m.restitution < 0.0 || m.restitution > 1.0) fail(path + ".restitution", "must be in [0, 1]");
    return m;
}

BodyKind bodyKind(const nlohmann::json& body, const std::string& path) {
    const nlohmann::json* t = member(body, path, "type", false);
    if (!t) return BodyKind::dynamicBody;
    if (!t->is_string()) fail(path + ".type", "expected a string");
    const std::string type = t->get<std::string>();
    if (type == "static") return BodyKind::staticBody;
    if (type == "kinematic") return BodyKind::kinematicBody;
    if (type != "dynamic") fail(path + ".type", "expected \"static\", \"kinematic\" or \"dynamic\"");
    return BodyKind::dynamicBody;
}

}  // namespace unison::jsonio
