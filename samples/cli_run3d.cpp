// samples/cli_run3d.cpp — `unison run` for 3D scenes (dimension 3): the same output contract as the 2D run, with
// quaternions [w, x, y, z] and 3-vectors (DESIGN.md "Command-line contract"), and --snapshot-at.
#include "cli.h"
#include "run_stats.h"
#include "scene_json3d.h"
#include "snapshot_file.h"

#include <ostream>

namespace unison::cli {

int runScene3(const nlohmann::json& scene, const std::string& what, int steps, int hashEvery, std::ostream& out,
              const RunSnapshot& snapshot, const RunBudget& budget) {
    const std::size_t slash = what.find_last_of('/');
    const std::string baseDir = slash == std::string::npos ? "." : what.substr(0, slash);
    scenes::LoadedScene3 loaded = scenes::loadScene3(scene, what, baseDir);  // throws InputError on a bad scene
    World3& world = *loaded.world;
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
    auto v3 = [](const Vec3& v) { return nlohmann::json{v.x(), v.y(), v.z()}; };
    nlohmann::json bodies = nlohmann::json::array();
    for (std::size_t i = 0; i < loaded.bodies.size(); ++i) {
        const BodyState3* s = world.state(loaded.bodies[i]);
        bodies.push_back({{"index", i},
                          {"position", v3(s->position)},
                          {"orientation", {s->rotation.w, s->rotation.x, s->rotation.y, s->rotation.z}},
                          {"linear_velocity", v3(s->velocity)},
                          {"angular_velocity", v3(s->angularVelocity)},
                          {"awake", world.info(loaded.bodies[i])->awake}});
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
