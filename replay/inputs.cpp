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

/// Reads a 2- or 3-vector with components in [-limit, limit] into the 2D and 3D fields (the other stays zero).
void vec(const json& obj, const std::string& path, const char* key, int dimension, double limit, Vec2& v2, Vec3& v3) {
    const std::vector<double> v = jsonio::numbersWithin(*jsonio::member(obj, path, key, true), path + "." + key,
                                                        std::size_t(dimension), limit);
    if (dimension == 3) {
        v3 = Vec3(v[0], v[1], v[2]);
    } else {
        v2 = {v[0], v[1]};
    }
}

json vecJson(int dimension, Vec2 v2, const Vec3& v3) {
    return dimension == 3 ? json::array({v3.x(), v3.y(), v3.z()}) : json::array({v2.x, v2.y});
}

std::string where(const InputAction& a, std::size_t index) {
    return "inputs[" + std::to_string(index) + "] (tick " + std::to_string(a.tick) + ")";
}

}  // namespace

int sceneDimension(const json& scene) {
    const auto it = scene.is_object() ? scene.find("dimension") : scene.end();
    return it != scene.end() && it->is_number_integer() && it->get<std::int64_t>() == 3 ? 3 : 2;
}

InputScript parseInputs(const json& js, const std::string& what, int dimension) {
    const json& list = jsonio::array(*jsonio::member(js, what, "inputs", true), what + ".inputs");
    InputScript script;
    script.dimension = dimension == 3 ? 3 : 2;
    const int dim = script.dimension;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string path = what + ".inputs[" + std::to_string(i) + "]";
        const json& item = list[i];
        InputAction a;
        a.tick = jsonio::integer(*jsonio::member(item, path, "tick", true), path + ".tick", 1, policy::kMaxTick);
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
                vec(item, path, "point", dim, policy::kMaxCoordinate, a.point, a.point3);
            }
        };
        switch (a.type) {
            case InputType::applyImpulse:
                body();
                vec(item, path, "impulse", dim, policy::kMaxImpulse, a.vector, a.vector3);
                point();
                break;
            case InputType::applyForce:
                body();
                vec(item, path, "force", dim, policy::kMaxForce, a.vector, a.vector3);
                point();
                break;
            case InputType::setVelocity:
                body();
                vec(item, path, "linear_velocity", dim, policy::kMaxSpeed, a.vector, a.vector3);
                if (dim == 3) {
                    if (jsonio::member(item, path, "angular_velocity", false))
                        vec(item, path, "angular_velocity", dim, policy::kMaxAngularSpeed, a.vector, a.angularVelocity3);
                } else {
                    a.angularVelocity = jsonio::numberInOr(item, path, "angular_velocity", -policy::kMaxAngularSpeed,
                                                           policy::kMaxAngularSpeed, 0.0);
                }
                break;
            case InputType::createBody:
                a.bodyDef = *jsonio::member(item, path, "body_def", true);
                if (dim == 3) {
                    scenes::readBody3(a.bodyDef, path + ".body_def");  // validate now, not at its tick
                } else {
                    scenes::readBody2(a.bodyDef, path + ".body_def");
                }
                break;
            case InputType::destroyBody:
                body();
                break;
            case InputType::setGravity:
                vec(item, path, "gravity", dim, policy::kMaxGravity, a.vector, a.vector3);
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
    const int dim = script.dimension;
    for (const InputAction& a : script.actions) {
        json j = {{"tick", a.tick}, {"type", kTypes[int(a.type)].name}};
        switch (a.type) {
            case InputType::applyImpulse:
            case InputType::applyForce:
                j["body"] = a.body;
                j[a.type == InputType::applyImpulse ? "impulse" : "force"] = vecJson(dim, a.vector, a.vector3);
                if (a.hasPoint) j["point"] = vecJson(dim, a.point, a.point3);
                break;
            case InputType::setVelocity:
                j["body"] = a.body;
                j["linear_velocity"] = vecJson(dim, a.vector, a.vector3);
                j["angular_velocity"] = dim == 3 ? vecJson(dim, {}, a.angularVelocity3) : json(a.angularVelocity);
                break;
            case InputType::createBody: j["body_def"] = a.bodyDef; break;
            case InputType::destroyBody: j["body"] = a.body; break;
            case InputType::setGravity: j["gravity"] = vecJson(dim, a.vector, a.vector3); break;
        }
        list.push_back(std::move(j));
    }
    return {{"inputs", list}};
}

template <>
Session<World2>::Session(const json& scene, const std::string& what) {
    scenes::LoadedScene2 loaded = scenes::loadScene2(scene, what);
    mWorld = std::move(loaded.world);
    mBodies = std::move(loaded.bodies);
}

template <>
Session<World3>::Session(const json& scene, const std::string& what) {
    scenes::LoadedScene3 loaded = scenes::loadScene3(scene, what);
    mWorld = std::move(loaded.world);
    mBodies = std::move(loaded.bodies);
}

template <class World>
void Session<World>::tick(int tick, const InputScript& script) {
    while (mNext < script.actions.size() && script.actions[mNext].tick <= tick) {
        apply(script.actions[mNext], mNext);
        ++mNext;
    }
    mWorld->step();
    if (!mWorld->fault().empty()) throw ReplayError("tick " + std::to_string(tick) + ": " + mWorld->fault());
}

template <class World>
int Session<World>::bodyNumber(BodyId id) const {
    for (std::size_t k = 0; k < mBodies.size(); ++k) {
        if (mBodies[k] == id && mWorld->valid(id)) return int(k);
    }
    return -1;
}

template <class World>
BodyId Session<World>::bodyOf(const InputAction& a, std::size_t index) const {
    if (a.body < 0 || std::size_t(a.body) >= mBodies.size())
        throw ReplayError(where(a, index) + ": no body number " + std::to_string(a.body) + " (" +
                          std::to_string(mBodies.size()) + " bodies created so far)");
    const BodyId id = mBodies[std::size_t(a.body)];
    if (!mWorld->valid(id)) throw ReplayError(where(a, index) + ": body " + std::to_string(a.body) + " was destroyed");
    return id;
}

namespace {

/// The parts of apply() that do not depend on the dimension; `impulse(id)` and `velocity(id)` do the rest.
template <class World, class Impulse, class Velocity, class ReadBody, class BodyOf>
void applyAction(World& w, const InputAction& a, std::size_t index, std::vector<BodyId>& bodies, BodyOf bodyOf,
                 Impulse impulse, Velocity velocity, ReadBody readBody) {
    switch (a.type) {
        case InputType::applyImpulse:
        case InputType::applyForce:
            if (!impulse(bodyOf()))
                throw ReplayError(where(a, index) + ": body " + std::to_string(a.body) + " is not dynamic");
            break;
        case InputType::setVelocity:
            if (!velocity(bodyOf())) throw ReplayError(where(a, index) + ": body " + std::to_string(a.body) + " is static");
            break;
        case InputType::createBody: {
            const auto spec = readBody(where(a, index) + ".body_def");
            std::string error;
            const BodyId id = w.createBody(spec.def, spec.shapes, &error);
            if (id.isNull()) throw ReplayError(where(a, index) + ": " + error);
            bodies.push_back(id);
            break;
        }
        case InputType::destroyBody: w.destroyBody(bodyOf()); break;
        case InputType::setGravity: break;  // done by the caller
    }
}

}  // namespace

template <>
void Session<World2>::apply(const InputAction& a, std::size_t index) {
    World2& w = *mWorld;
    if (a.type == InputType::setGravity) w.setGravity(a.vector);
    applyAction(
        w, a, index, mBodies, [&] { return bodyOf(a, index); },
        [&](BodyId id) {
            // A force acts for this one tick: its impulse is F dt.
            const Vec2 impulse = a.type == InputType::applyImpulse ? a.vector : (1.0 / w.def().hz) * a.vector;
            return w.applyImpulse(id, impulse, a.hasPoint ? a.point : w.state(id)->center);
        },
        [&](BodyId id) { return w.setVelocity(id, a.vector, a.angularVelocity); },
        [&](const std::string& path) { return scenes::readBody2(a.bodyDef, path); });
}

template <>
void Session<World3>::apply(const InputAction& a, std::size_t index) {
    World3& w = *mWorld;
    if (a.type == InputType::setGravity) w.setGravity(a.vector3);
    applyAction(
        w, a, index, mBodies, [&] { return bodyOf(a, index); },
        [&](BodyId id) {
            const Vec3 impulse = a.type == InputType::applyImpulse ? a.vector3 : Dim3::scale(1.0 / w.def().hz, a.vector3);
            const BodyState3* s = w.state(id);
            return w.applyImpulse(id, impulse, a.hasPoint ? a.point3 : s->center);
        },
        [&](BodyId id) { return w.setVelocity(id, a.vector3, a.angularVelocity3); },
        [&](const std::string& path) { return scenes::readBody3(a.bodyDef, path); });
}

template class Session<World2>;
template class Session<World3>;

}  // namespace unison::replay
