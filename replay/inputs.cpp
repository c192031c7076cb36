// replay/inputs.cpp — input scripts and the session that applies them (see inputs.h).
#include "inputs.h"

#include <algorithm>

namespace unison::replay {
namespace {

using nlohmann::json;

struct TypeName {
    InputType type;
    const char* name;
};
constexpr TypeName kTypes[] = {{InputType::applyImpulse, "apply_impulse"}, {InputType::applyForce, "apply_force"},
                               {InputType::setVelocity, "set_velocity"},   {InputType::createBody, "create_body"},
                               {InputType::destroyBody, "destroy_body"},   {InputType::setGravity, "set_gravity"}};

Vec2 vec(const json& obj, const std::string& path, const char* key) {
    const std::vector<double> v = jsonio::numbers(*jsonio::member(obj, path, key, true), path + "." + key, 2);
    return {v[0], v[1]};
}

json vecJson(Vec2 v) { return json::array({v.x, v.y}); }

std::string where(const InputAction& a, std::size_t index) {
    return "inputs[" + std::to_string(index) + "] (tick " + std::to_string(a.tick) + ")";
}

}  // namespace

InputScript parseInputs(const json& js, const std::string& what) {
    const json& list = jsonio::array(*jsonio::member(js, what, "inputs", true), what + ".inputs");
    InputScript script;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string path = what + ".inputs[" + std::to_string(i) + "]";
        const json& item = list[i];
        InputAction a;
        a.tick = jsonio::integer(*jsonio::member(item, path, "tick", true), path + ".tick", 1, 1 << 30);
        const json* type = jsonio::member(item, path, "type", true);
        const std::string t = type->is_string() ? type->get<std::string>() : std::string();
        const auto it = std::find_if(std::begin(kTypes), std::end(kTypes), [&](const TypeName& n) { return t == n.name; });
        if (it == std::end(kTypes))
            jsonio::fail(path + ".type", "expected apply_impulse, apply_force, set_velocity, create_body, destroy_body "
                                         "or set_gravity");
        a.type = it->type;
        auto body = [&] { a.body = jsonio::integer(*jsonio::member(item, path, "body", true), path + ".body", 0, 1 << 30); };
        auto point = [&] {
            if (jsonio::member(item, path, "point", false)) {
                a.hasPoint = true;
                a.point = vec(item, path, "point");
            }
        };
        switch (a.type) {
            case InputType::applyImpulse:
                body();
                a.vector = vec(item, path, "impulse");
                point();
                break;
            case InputType::applyForce:
                body();
                a.vector = vec(item, path, "force");
                point();
                break;
            case InputType::setVelocity:
                body();
                a.vector = vec(item, path, "linear_velocity");
                a.angularVelocity = jsonio::numberOr(item, path, "angular_velocity", 0.0);
                break;
            case InputType::createBody:
                a.bodyDef = *jsonio::member(item, path, "body_def", true);
                scenes::readBody2(a.bodyDef, path + ".body_def");  // validate now, not at its tick
                break;
            case InputType::destroyBody:
                body();
                break;
            case InputType::setGravity:
                a.vector = vec(item, path, "gravity");
                break;
        }
        script.actions.push_back(std::move(a));
    }
    std::stable_sort(script.actions.begin(), script.actions.end(),
                     [](const InputAction& x, const InputAction& y) { return x.tick < y.tick; });
    return script;
}

json inputsToJson(const InputScript& script) {
    json list = json::array();
    for (const InputAction& a : script.actions) {
        json j = {{"tick", a.tick}, {"type", kTypes[int(a.type)].name}};
        switch (a.type) {
            case InputType::applyImpulse:
            case InputType::applyForce:
                j["body"] = a.body;
                j[a.type == InputType::applyImpulse ? "impulse" : "force"] = vecJson(a.vector);
                if (a.hasPoint) j["point"] = vecJson(a.point);
                break;
            case InputType::setVelocity:
                j["body"] = a.body;
                j["linear_velocity"] = vecJson(a.vector);
                j["angular_velocity"] = a.angularVelocity;
                break;
            case InputType::createBody: j["body_def"] = a.bodyDef; break;
            case InputType::destroyBody: j["body"] = a.body; break;
            case InputType::setGravity: j["gravity"] = vecJson(a.vector); break;
        }
        list.push_back(std::move(j));
    }
    return {{"inputs", list}};
}

Session2::Session2(const json& scene, const std::string& what) {
    scenes::LoadedScene2 loaded = scenes::loadScene2(scene, what);
    mWorld = std::move(loaded.world);
    mBodies = std::move(loaded.bodies);
}

void Session2::tick(int tick, const InputScript& script) {
    while (mNext < script.actions.size() && script.actions[mNext].tick <= tick) {
        apply(script.actions[mNext], mNext);
        ++mNext;
    }
    mWorld->step();
}

int Session2::bodyNumber(BodyId id) const {
    for (std::size_t k = 0; k < mBodies.size(); ++k) {
        if (mBodies[k] == id && mWorld->valid(id)) return int(k);
    }
    return -1;
}

BodyId Session2::bodyOf(const InputAction& a, std::size_t index) const {
    if (a.body < 0 || std::size_t(a.body) >= mBodies.size())
        throw ReplayError(where(a, index) + ": no body number " + std::to_string(a.body) + " (" +
                          std::to_string(mBodies.size()) + " bodies created so far)");
    const BodyId id = mBodies[std::size_t(a.body)];
    if (!mWorld->valid(id)) throw ReplayError(where(a, index) + ": body " + std::to_string(a.body) + " was destroyed");
    return id;
}

void Session2::apply(const InputAction& a, std::size_t index) {
    World2& w = *mWorld;
    switch (a.type) {
        case InputType::applyImpulse:
        case InputType::applyForce: {
            const BodyId id = bodyOf(a, index);
            // A force acts for this one tick: its impulse is F dt.
            const Vec2 impulse = a.type == InputType::applyImpulse ? a.vector : (1.0 / w.def().hz) * a.vector;
            const Vec2 at = a.hasPoint ? a.point : w.state(id)->center;
            if (!w.applyImpulse(id, impulse, at))
                throw ReplayError(where(a, index) + ": body " + std::to_string(a.body) + " is not dynamic");
            break;
        }
        case InputType::setVelocity:
            if (!w.setVelocity(bodyOf(a, index), a.vector, a.angularVelocity))
                throw ReplayError(where(a, index) + ": body " + std::to_string(a.body) + " is static");
            break;
        case InputType::createBody: {
            const scenes::BodySpec2 spec = scenes::readBody2(a.bodyDef, where(a, index) + ".body_def");
            std::string error;
            const BodyId id = w.createBody(spec.def, spec.shapes, &error);
            if (id.isNull()) throw ReplayError(where(a, index) + ": " + error);
            mBodies.push_back(id);
            break;
        }
        case InputType::destroyBody: w.destroyBody(bodyOf(a, index)); break;
        case InputType::setGravity: w.setGravity(a.vector); break;
    }
}

}  // namespace unison::replay
