// scenes/json_fields.cpp — strict JSON readers with key-precise messages (see json_fields.h).
#include "json_fields.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

namespace unison::jsonio {

void fail(const std::string& path, const std::string& why) { throw JsonError(path + ": " + why); }

namespace {

using nlohmann::json;

// A printable, bounded copy of a key for messages (a hostile key may hold control characters).
std::string printable(const std::string& k) {
    std::string out = k.substr(0, 64);
    for (char& c : out)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    return out;
}

// Builds the DOM from nlohmann's SAX events, so that the parse stops before the stack or the memory grows without
// bound (nesting depth), a duplicate key is refused, and an error names the key it happened in. (nlohmann's own DOM
// parser throws out_of_range for a number like 1e999, and its messages quote the text they stopped at.)
class BoundedDomBuilder {
public:
    BoundedDomBuilder(json& root, const std::string& what) : mRoot(root), mWhat(what) {}

    bool null() { return put(json(nullptr)); }
    bool boolean(bool v) { return put(json(v)); }
    bool number_integer(json::number_integer_t v) { return put(json(v)); }
    bool number_unsigned(json::number_unsigned_t v) { return put(json(v)); }
    bool number_float(json::number_float_t v, const std::string&) { return put(json(v)); }
    bool string(std::string& v) { return put(json(std::move(v))); }
    bool binary(json::binary_t&) { return refuse("binary values are not JSON"); }
    bool start_object(std::size_t) { return open(json::object()); }
    bool key(std::string& k) {
        const bool duplicate = mStack.back()->contains(k);
        mKey = std::move(k);
        return duplicate ? refuse("duplicate key") : true;
    }
    bool end_object() { return close(); }
    bool start_array(std::size_t) { return open(json::array()); }
    bool end_array() { return close(); }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) {
        if (e.id == 406) return refuse("number out of the range of a double");
        // "[json.exception.parse_error.101] parse error at line 3, column 7: syntax error while parsing value -
        // invalid literal; last read: 'tru,'": keep the position and the reason, drop what was read.
        std::string msg = e.what();
        const std::size_t at = msg.find("at line ");
        msg = at == std::string::npos ? "malformed JSON" : "malformed JSON " + msg.substr(at);
        const std::size_t read = msg.find("; last read");
        if (read != std::string::npos) {
            const std::size_t expected = msg.rfind("; expected ");
            msg = msg.substr(0, read) + (expected != std::string::npos && expected > read ? msg.substr(expected) : "");
        }
        mError = mWhat + ": " + msg;
        return false;
    }

    const std::string& error() const { return mError; }

private:
    // Where the value being read goes: the root, the next array element, or the current key of an object.
    std::string path() const {
        std::string p = mWhat;
        for (std::size_t i = 0; i < mStack.size(); ++i) {
            const json& c = *mStack[i];
            const bool innermost = i + 1 == mStack.size();
            if (c.is_array()) {
                // An enclosing array is building its last element; the innermost one is about to add the next.
                p += "[" + std::to_string(innermost ? c.size() : c.size() - 1) + "]";
            } else {
                p += "." + printable(innermost ? mKey : mKeys[i + 1]);
            }
        }
        return p;
    }
    bool refuse(const std::string& why) {
        mError = path() + ": " + why;
        return false;
    }
    // Stores v where the next value goes and returns its address.
    json* place(json&& v) {
        if (mStack.empty()) {
            mRoot = std::move(v);
            return &mRoot;
        }
        json& c = *mStack.back();
        if (c.is_array()) {
            c.push_back(std::move(v));
            return &c.back();
        }
        json& slot = c[mKey];
        slot = std::move(v);
        return &slot;
    }
    bool put(json&& v) {
        place(std::move(v));
        return true;
    }
    bool open(json&& container) {
        if (mStack.size() >= policy::kMaxJsonDepth)
            return refuse("nested deeper than " + std::to_string(policy::kMaxJsonDepth) + " levels");
        json* c = place(std::move(container));
        mKeys.push_back(mKey);  // the key this container sits under, if its parent is an object
        mStack.push_back(c);
        return true;
    }
    bool close() {
        mStack.pop_back();
        mKey = mKeys.back();
        mKeys.pop_back();
        return true;
    }

    json& mRoot;
    const std::string& mWhat;
    std::vector<json*> mStack;       // open containers, outermost first
    std::vector<std::string> mKeys;  // mKeys[i]: the key under which mStack[i] was placed (its parent's key)
    std::string mKey;                // current key of the innermost open object
    std::string mError;
};

}  // namespace

nlohmann::json parseJson(const std::string& text, const std::string& what) {
    if (text.size() > policy::kMaxJsonBytes)
        throw JsonError(what + ": " + std::to_string(text.size()) + " bytes of JSON, more than the limit of " +
                        std::to_string(policy::kMaxJsonBytes));
    json root;
    BoundedDomBuilder builder(root, what);
    bool ok = false;
    try {
        ok = json::sax_parse(text, &builder, json::input_format_t::json, true, false);
    } catch (const nlohmann::json::exception&) {
        ok = false;  // nlohmann reports errors to the handler, not by throwing; this only keeps a surprise contained
    }
    if (!ok) throw JsonError(builder.error().empty() ? what + ": malformed JSON" : builder.error());
    return root;
}

std::string readFile(const std::string& path, std::size_t maxBytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw JsonError(path + ": cannot open file");
    std::string s;
    char buf[1 << 16];
    while (in) {
        in.read(buf, sizeof buf);
        s.append(buf, std::size_t(in.gcount()));
        if (s.size() > maxBytes)
            throw JsonError(path + ": larger than the limit of " + std::to_string(maxBytes) + " bytes");
    }
    if (in.bad()) throw JsonError(path + ": read error");
    return s;
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

std::string rangeText(double lo, double hi) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "[%.10g, %.10g]", lo, hi);
    return buf;
}

double numberIn(const nlohmann::json& v, const std::string& path, double lo, double hi) {
    const double x = number(v, path);
    if (!(x >= lo && x <= hi)) throw JsonError(path + ": must be in " + rangeText(lo, hi));
    return x;
}

double numberOr(const nlohmann::json& obj, const std::string& path, const char* key, double fallback) {
    const nlohmann::json* v = member(obj, path, key, false);
    return v ? number(*v, path + "." + key) : fallback;
}

double numberInOr(const nlohmann::json& obj, const std::string& path, const char* key, double lo, double hi,
                  double fallback) {
    const nlohmann::json* v = member(obj, path, key, false);
    return v ? numberIn(*v, path + "." + key, lo, hi) : fallback;
}

int integer(const nlohmann::json& v, const std::string& path, int lo, int hi) {
    const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (!v.is_number_integer()) throw JsonError(path + ": expected an integer in " + range);
    // Compared in 64 bits before any narrowing: 4294967298 is not 2.
    if (v.is_number_unsigned()) {
        const std::uint64_t u = v.get<std::uint64_t>();
        if (hi < 0 || u > std::uint64_t(hi) || (lo > 0 && u < std::uint64_t(lo)))
            throw JsonError(path + ": must be an integer in " + range);
        return int(u);
    }
    const std::int64_t x = v.get<std::int64_t>();
    if (x < lo || x > hi) throw JsonError(path + ": must be an integer in " + range);
    return int(x);
}

bool boolean(const nlohmann::json& v, const std::string& path) {
    if (!v.is_boolean()) throw JsonError(path + ": expected true or false");
    return v.get<bool>();
}

std::vector<double> numbers(const nlohmann::json& v, const std::string& path, std::size_t size) {
    return numbersWithin(v, path, size, HUGE_VAL);
}

std::vector<double> numbersWithin(const nlohmann::json& v, const std::string& path, std::size_t size, double limit) {
    if (!v.is_array() || v.size() != size)
        throw JsonError(path + ": expected an array of " + std::to_string(size) + " numbers");
    std::vector<double> out;
    for (std::size_t i = 0; i < size; ++i) out.push_back(numberIn(v[i], path + "[" + std::to_string(i) + "]", -limit, limit));
    return out;
}

bool allFinite(const nlohmann::json& v) {
    if (v.is_number_float()) return std::isfinite(v.get<double>());
    if (v.is_array() || v.is_object()) {
        for (const auto& e : v)
            if (!allFinite(e)) return false;
    }
    return true;
}

const nlohmann::json& array(const nlohmann::json& v, const std::string& path) {
    if (!v.is_array()) throw JsonError(path + ": expected an array");
    return v;
}

const nlohmann::json& arrayUpTo(const nlohmann::json& v, const std::string& path, std::size_t maxSize) {
    if (!v.is_array()) throw JsonError(path + ": expected an array");
    if (v.size() > maxSize) throw JsonError(path + ": more than " + std::to_string(maxSize) + " elements");
    return v;
}

Material material(const nlohmann::json& shape, const std::string& path) {
    Material m;
    m.density = numberInOr(shape, path, "density", 0.0, policy::kMaxDensity, m.density);
    m.friction = numberInOr(shape, path, "friction", 0.0, policy::kMaxFriction, m.friction);
    m.restitution = numberInOr(shape, path, "restitution", 0.0, 1.0, m.restitution);
    return m;
}

BodyType bodyType(const nlohmann::json& body, const std::string& path) {
    const nlohmann::json* t = member(body, path, "type", false);
    if (!t) return BodyType::dynamicBody;
    if (!t->is_string()) fail(path + ".type", "expected a string");
    const std::string type = t->get<std::string>();
    if (type == "static") return BodyType::staticBody;
    if (type == "kinematic") return BodyType::kinematicBody;
    if (type != "dynamic") fail(path + ".type", "expected \"static\", \"kinematic\" or \"dynamic\"");
    return BodyType::dynamicBody;
}

void readWorldSettings(const nlohmann::json& scene, const std::string& what, WorldSettings& def) {
    def.hz = numberInOr(scene, what, "hz", policy::kMinHz, policy::kMaxHz, def.hz);
    def.restitutionThreshold =
        numberInOr(scene, what, "restitution_threshold", 0.0, policy::kMaxRestitutionThreshold, def.restitutionThreshold);
    if (const nlohmann::json* sl = member(scene, what, "sleep", false)) def.enableSleep = boolean(*sl, what + ".sleep");
    if (const nlohmann::json* b = member(scene, what, "step_budget", false))
        def.stepBudget = std::uint64_t(integer(*b, what + ".step_budget", 0, std::numeric_limits<int>::max()));
}

}  // namespace unison::jsonio
