// samples/cli_run.cpp — `unison run SCENE.json [--steps N] [--hash-every K] [--threads T] [--budget W]`: steps a
// scene and prints {"step", "hash"} lines every K steps, then one JSON object with every body's final state and
// step statistics.
#include "cli.h"
#include "run_stats.h"
#include "scene_json.h"
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

int runScene(const nlohmann::json& scene, const std::string& what, int steps, int hashEvery, std::ostream& out,
             const RunSnapshot& snapshot, const RunBudget& budget) {
    const nlohmann::json* dim = scene.is_object() && scene.contains("dimension") ? &scene["dimension"] : nullptr;
    if (snapshot.at > steps) throw InputError("--snapshot-at " + std::to_string(snapshot.at) + " is after the last step");
    if (budget.threads < 1) throw InputError("--threads must be >= 1");
    if (dim && dim->is_number_integer() && dim->get<int>() == 3) return runScene3(scene, what, steps, hashEvery, out, snapshot, budget);
    scenes::LoadedScene2 loaded = scenes::loadScene2(scene, what);  // throws InputError (a JsonError) on a bad scene
    World2& world = *loaded.world;
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
    nlohmann::json bodies = nlohmann::json::array();
    for (std::size_t i = 0; i < loaded.bodies.size(); ++i) {
        const BodyId id = loaded.bodies[i];
        const BodyState2* s = world.state(id);
        const BodyInfo2* info = world.info(id);
        bodies.push_back({{"index", i},
                          {"position", {s->position.x, s->position.y}},
                          {"angle", world.angle(id)},
                          {"linear_velocity", {s->velocity.x, s->velocity.y}},
                          {"angular_velocity", s->angularVelocity},
                          {"awake", info->awake}});
    }
    const nlohmann::json final = {
        {"steps", steps},
        {"hash", hashHex(world.stateHash())},
        {"bodies", bodies},
        {"stats", run.toJson(world.stats())}};
    out << final.dump() << "\n";
    return run.failed == 0 ? 0 : 1;
}

}  // namespace unison::cli
