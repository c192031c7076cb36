// samples/cli_run3d.cpp — `unison run` for 3D scenes (dimension 3): the same output contract as the 2D run, with
// quaternions [w, x, y, z] and 3-vectors (DESIGN.md "Command-line contract"), and --snapshot-at.
#include "cli.h"
#include "scene_json3d.h"
#include "snapshot_file.h"

#include <algorithm>
#include <ostream>

namespace unison::cli {

int runScene3(const nlohmann::json& scene, const std::string& what, int steps, int hashEvery, std::ostream& out,
              const RunSnapshot& snapshot) {
    const std::size_t slash = what.find_last_of('/');
    const std::string baseDir = slash == std::string::npos ? "." : what.substr(0, slash);
    scenes::LoadedScene3 loaded = scenes::loadScene3(scene, what, baseDir);  // throws InputError on a bad scene
    World3& world = *loaded.world;
    if (snapshot.at == 0) replay::writeFileAtomic(snapshot.path, world.snapshot());
    int totalPivots = 0, maxIslandPivots = 0, discardedGuesses = 0, basisChange = 0, failed = 0, unsolved = 0;
    double maxResidual = 0.0, maxPenetration = 0.0;
    for (int s = 1; s <= steps; ++s) {
        world.step();
        if (!world.fault().empty()) throw InputError(what + ": " + world.fault());
        const StepStats3& st = world.stats();
        totalPivots += st.pivots;
        maxIslandPivots = std::max(maxIslandPivots, st.maxIslandPivots);
        discardedGuesses += st.discardedGuesses;
        basisChange += st.basisChange;
        failed += st.failedIslands;
        unsolved += st.unsolvedIslands;
        maxResidual = std::max(maxResidual, st.maxResidual);
        maxPenetration = std::max(maxPenetration, st.maxPenetration);
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
        {"stats", {{"total_pivots", totalPivots}, {"max_island_pivots", maxIslandPivots},
                   {"discarded_guesses", discardedGuesses}, {"basis_change", basisChange}, {"failed_islands", failed},
                   {"unsolved_islands", unsolved}, {"max_residual", maxResidual}, {"max_penetration", maxPenetration},
                   {"contacts", world.stats().contacts}, {"islands", world.stats().islands}}}};
    out << final.dump() << "\n";
    return failed == 0 ? 0 : 1;
}

}  // namespace unison::cli
