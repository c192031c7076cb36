// replay/golden.cpp — the golden determinism scenes (see golden.h).
#include "golden.h"

#include "make_scenes2d.h"
#include "make_scenes3d.h"
#include "scene_json.h"
#include "scene_json3d.h"
#include "state_io.h"

namespace unison::replay {

std::vector<GoldenScene> goldenScenes() {
    const std::string dir = scenes::sceneDir() + "/";
    return {
        {"pyramid", scenes::pyramidScene(10, 0.5, false), 240},
        {"restitution_row", scenes::readSceneFile(dir + "restitution_row.json"), 240},
        {"mixed_pile", scenes::readSceneFile(dir + "mixed_pile.json"), 300},
        {"cradle", scenes::readSceneFile(dir + "cradle.json"), 120},
        // The 3D world (issue 5): boxes tilted so they land on edges and topple into one heap, spheres bouncing
        // with e = 0..1, and two sphere-tree bunnies sliding down the paper's ramps (the mesh path).
        {"box_heap3d", scenes::boxPile3Scene(12, true, false), 180},
        {"spheres3d", scenes::spheres3Scene(false), 180},
        {"bunnies3d", scenes::bunnies3Scene(dir + "../samples/assets/bunny.obj", 0.05, 2, false), 240},
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

std::vector<std::uint64_t> goldenHashes(const GoldenScene& scene) {
    if (scene.is3d()) {
        scenes::LoadedScene3 loaded = scenes::loadScene3(scene.scene, scene.name);
        std::vector<std::uint64_t> hashes{loaded.world->stateHash()};
        for (int t = 1; t <= scene.steps; ++t) {
            loaded.world->step();
            hashes.push_back(loaded.world->stateHash());
        }
        return hashes;
    }
    scenes::LoadedScene2 loaded = scenes::loadScene2(scene.scene, scene.name);
    std::vector<std::uint64_t> hashes{loaded.world->stateHash()};
    for (int t = 1; t <= scene.steps; ++t) {
        loaded.world->step();
        hashes.push_back(loaded.world->stateHash());
    }
    return hashes;
}

int firstRestoreMismatch(const GoldenScene& scene, const std::vector<std::uint64_t>& hashes) {
    if (scene.is3d()) return -1;  // snapshots of the 3D world are not implemented (README); nothing to compare
    scenes::LoadedScene2 loaded = scenes::loadScene2(scene.scene, scene.name);
    const int k = scene.steps / 3;
    for (int t = 1; t <= k; ++t) loaded.world->step();
    const std::vector<std::uint8_t> snap = loaded.world->snapshot();
    loaded.world.reset();
    World2 fresh;
    if (!fresh.restore(snap.data(), snap.size())) return k;
    for (int t = k; t <= scene.steps; ++t) {
        if (t > k) fresh.step();
        if (std::size_t(t) >= hashes.size() || fresh.stateHash() != hashes[std::size_t(t)]) return t;
    }
    return -1;
}

}  // namespace unison::replay
