// replay/golden.cpp — the golden determinism scenes (see golden.h).
#include "golden.h"

#include "make_scenes2d.h"
#include "make_scenes3d.h"
#include "scene_dir.h"
#include "scene_json.h"
#include "scene_json3d.h"
#include "state_io.h"

namespace unison::replay {

namespace {

// Work units, not milliseconds: the golden hashes must not move when the ms conversion is recalibrated.
constexpr std::uint64_t kPyramidBudget = 400000;
constexpr std::uint64_t kHeapBudget = 300000;

}  // namespace

std::vector<GoldenScene> goldenScenes() {
    const std::string dir = scenes::sceneDir() + "/";
    return {
        {"pyramid", scenes::pyramidScene(10, 0.5, false), 240},
        {"restitution_row", scenes::readSceneFile(dir + "restitution_row.json"), 240},
        {"mixed_pile", scenes::readSceneFile(dir + "mixed_pile.json"), 300},
        {"cradle", scenes::readSceneFile(dir + "cradle.json"), 120},
        // A 16-row pyramid through its landing: blocks of 250-300 unknowns, so the solver's large-block paths
        // (the LDL^T of the symmetric core, sparse LU, the Schur border of Lemke's block) are covered too.
        {"pyramid16", scenes::pyramidScene(16, 0.5, false), 120},
        // Box2D v3's large pyramid at base 24 (1704 contacts in one island, every box touching from the start): the
        // active-set path from its cold first step on (its symmetric-pattern LU, GMRES, the pivoting LU behind them).
        {"large_pyramid24", scenes::largePyramidScene(24, false), 30},
        // The 24-row testbed pyramid through its landing: from step 42 one island of 1024+ contacts, which goes to
        // the active-set path and its interior-point restart (Mehrotra's iteration, the L D L^T of M + J^T H^-1 J).
        {"pyramid24_landing", scenes::pyramidScene(24, 0.5, false), 100},
        // The 3D world: boxes tilted so they land on edges and topple into one heap, spheres bouncing
        // with e = 0..1, and two sphere-tree bunnies sliding down the paper's ramps (the mesh path).
        {"box_heap3d", scenes::boxPile3Scene(12, true, false), 180},
        {"spheres3d", scenes::spheres3Scene(false), 180},
        {"bunnies3d", scenes::bunnies3Scene(dir + "bunny.obj", 0.05, 2, false), 240},
        // bench_world3d's heap of 100 cubes through its landing: islands of about 100 contacts on the 3D active-set
        // path (its interior point following de Saxce's shift, the normalised body-space systems).
        {"box_heap3d_path", scenes::boxPile3Scene(100, true, false), 90},
        // Per-step budgets (core/step_budget.h) below what the landings need, on 2 threads: exact islands, islands
        // approximated by projected Gauss-Seidel, the allocation and the parallel passes all enter the hashes.
        {"pyramid16_budget", scenes::pyramidScene(16, 0.5, false), 120, kPyramidBudget, 2},
        {"box_heap3d_budget", scenes::boxPile3Scene(12, true, false), 180, kHeapBudget, 2},
    };
}

bool GoldenScene::is3d() const {
    const auto it = scene.find("dimension");
    return it != scene.end() && it->is_number_integer() && it->get<int>() == 3;
}

std::uint64_t chainHash(const std::vector<std::uint64_t>& hashes) {
    ByteWriter w;
    for (std::uint64_t h : hashes) w.u64(h);
    return hash64(w.data().data(), w.data().size());
}

namespace {

/// Sets a golden scene's budget and threads on its freshly loaded world.
template <class World>
World& configured(World& world, const GoldenScene& scene) {
    world.setStepBudget(scene.budget);
    world.setTaskSystem(TaskSystem{scene.threads});
    return world;
}

template <class World>
std::vector<std::uint64_t> stepHashes(World& world, int steps) {
    std::vector<std::uint64_t> hashes{world.stateHash()};
    for (int t = 1; t <= steps; ++t) {
        world.step();
        hashes.push_back(world.stateHash());
    }
    return hashes;
}

/// Steps `world` (just loaded) to steps/3, snapshots it, drops it, restores into a fresh World and continues.
template <class World>
int restoreMismatch(std::unique_ptr<World> world, int steps, const std::vector<std::uint64_t>& hashes) {
    const int k = steps / 3;
    for (int t = 1; t <= k; ++t) world->step();
    const std::vector<std::uint8_t> snap = world->snapshot();
    world.reset();
    World fresh;
    if (!fresh.restore(snap.data(), snap.size())) return k;
    for (int t = k; t <= steps; ++t) {
        if (t > k) fresh.step();
        if (std::size_t(t) >= hashes.size() || fresh.stateHash() != hashes[std::size_t(t)]) return t;
    }
    return -1;
}

}  // namespace

std::vector<std::uint64_t> goldenHashes(const GoldenScene& scene) {
    if (scene.is3d()) return stepHashes(configured(*scenes::loadScene3(scene.scene, scene.name).world, scene), scene.steps);
    return stepHashes(configured(*scenes::loadScene2(scene.scene, scene.name).world, scene), scene.steps);
}

int firstRestoreMismatch(const GoldenScene& scene, const std::vector<std::uint64_t>& hashes) {
    // The restored world steps on one thread: its budget comes with the snapshot, its threads do not matter.
    if (scene.is3d()) {
        auto world = scenes::loadScene3(scene.scene, scene.name).world;
        configured(*world, scene);
        return restoreMismatch(std::move(world), scene.steps, hashes);
    }
    auto world = scenes::loadScene2(scene.scene, scene.name).world;
    configured(*world, scene);
    return restoreMismatch(std::move(world), scene.steps, hashes);
}

}  // namespace unison::replay
