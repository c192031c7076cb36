// samples/cli_run.cpp — `unison run SCENE.json [--steps N] [--hash-every K] [--threads T] [--budget W]`: steps a 2D
// or 3D scene and prints {"step", "hash"} lines every K steps, then one JSON object with every body's final state
// (2D: position, angle; 3D: position, quaternion [w, x, y, z]; velocities) and step statistics. Both dimensions
// share one loop; they differ only in how a body's state is written.
#include "cli.h"
#include "run_stats.h"
#include "scene_json.h"
#include "scene_json3d.h"
#include "snapshot_file.h"

#include <algorithm>
#include <cstdio>
#include <ostream>

namespace unison::cli {

std::string hashHex(std::uint64_t hash) {
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
    return hex;
}

namespace {

nlohmann::json vec(const Vec2& v) { return {v.x, v.y}; }
nlohmann::json vec(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

// The final state of one body: what both dimensions print, then the rotation in the dimension's form.
nlohmann::json bodyJson(const World2& world, BodyId id, std::size_t index) {
    const BodyState2* s = world.state(id);
    return {{"index", index},
            {"position", vec(s->position)},
            {"angle", world.angle(id)},
            {"linear_velocity", vec(s->velocity)},
            {"angular_velocity", s->angularVelocity},
            {"awake", world.info(id)->awake}};
}

nlohmann::json bodyJson(const World3& world, BodyId id, std::size_t index) {
    const BodyState3* s = world.state(id);
    return {{"index", index},
            {"position", vec(s->position)},
            {"orientation", {s->rotation.w, s->rotation.x, s->rotation.y, s->rotation.z}},
            {"linear_velocity", vec(s->velocity)},
            {"angular_velocity", vec(s->angularVelocity)},
            {"awake", world.info(id)->awake}};
}

// Steps a loaded scene of either dimension and prints the run's output; 1 when an island stayed unsolved.
template <class World>
int runWorld(World& world, const std::vector<BodyId>& bodies, const std::string& what, int steps, int hashEvery,
             std::ostream& out, const RunSnapshot& snapshot, const RunBudget& budget) {
    world.setStepBudget(budget.budget);
    world.setTaskSystem(TaskSystem{budget.threads});
    if (snapshot.at == 0) replay::writeFileAtomic(snapshot.path, world.snapshot());
    RunStats run;
    for (int s = 1; s <= steps; ++s) {
        run.step(world);
        if (!world.fault().empty()) throw InputError(what + ": " + world.fault());
        if (s == snapshot.at) replay::writeFileAtomic(snapshot.path, world.snapshot());
        if (hashEvery > 0 && s % hashEvery == 0) out << nlohmann::json{{"step", s}, {"hash", hashHex(world.stateHash())}}.dump() << "\n";
    }
    nlohmann::json states = nlohmann::json::array();
    for (std::size_t i = 0; i < bodies.size(); ++i) states.push_back(bodyJson(world, bodies[i], i));
    const nlohmann::json final = {
        {"steps", steps}, {"hash", hashHex(world.stateHash())}, {"bodies", states}, {"stats", run.toJson(world.stats())}};
    out << final.dump() << "\n";
    return run.failed == 0 ? 0 : 1;
}

}  // namespace

int runScene(const nlohmann::json& scene, const std::string& what, int steps, int hashEvery, std::ostream& out,
             const RunSnapshot& snapshot, const RunBudget& budget) {
    const nlohmann::json* dim = scene.is_object() && scene.contains("dimension") ? &scene["dimension"] : nullptr;
    if (snapshot.at > steps) throw InputError("--snapshot-at " + std::to_string(snapshot.at) + " is after the last step");
    if (budget.threads < 1) throw InputError("--threads must be >= 1");
    // The scene readers throw InputError (a JsonError) on a bad scene.
    if (dim && dim->is_number_integer() && dim->get<int>() == 3) {
        const std::size_t slash = what.find_last_of('/');
        const std::string baseDir = slash == std::string::npos ? "." : what.substr(0, slash);  // where OBJ paths start
        scenes::LoadedScene3 loaded = scenes::loadScene3(scene, what, baseDir);
        return runWorld(*loaded.world, loaded.bodies, what, steps, hashEvery, out, snapshot, budget);
    }
    scenes::LoadedScene2 loaded = scenes::loadScene2(scene, what);
    return runWorld(*loaded.world, loaded.bodies, what, steps, hashEvery, out, snapshot, budget);
}

}  // namespace unison::cli
