// fuzz/fuzz_snapshot.cpp — World2::restore and World3::restore (resolver2d/world2d_state.cpp,
// resolver3d/world3d_state.cpp). The fuzzer's bytes are [u8 kind: even 2D, odd 3D][u16 body count][payload]; the
// target frames them with a valid header and checksum (core/state_io.h), so every mutation reaches the state reader.
// Invariants: a refused restore leaves the world's hash unchanged; an accepted state steps, snapshots and restores
// again to the same hash.
#include "fuzz_support.h"
#include "scene_json.h"
#include "scene_json3d.h"

namespace {

/// A live world with bodies, contacts and a warm-start cache, restored into.
template <class World>
void restoreInto(World& world, const std::vector<std::uint8_t>& framed) {
    const std::uint64_t before = world.stateHash();
    std::string error;
    if (!world.restore(framed.data(), framed.size(), &error)) {
        unison::fuzz::require(world.stateHash() == before, "a refused restore leaves the world unchanged");
        return;
    }
    unison::fuzz::stepSnapshotRestore(world, 2);
}

const char* kScene2 = R"({"dimension": 2, "bodies": [
  {"type": "static", "shapes": [{"type": "segment", "points": [[-5, 0], [5, 0]]}]},
  {"position": [0, 0.5], "shapes": [{"type": "box", "half_extents": [0.5, 0.5]}]}]})";
const char* kScene3 = R"({"dimension": 3, "bodies": [
  {"type": "static", "shapes": [{"type": "plane", "normal": [0, 1, 0]}]},
  {"position": [0, 0.5, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]}]})";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace unison;
    if (size < 3) return 0;
    const bool is3d = data[0] % 2 == 1;
    const std::uint64_t bodies = std::uint64_t(data[1]) | (std::uint64_t(data[2]) << 8);
    const std::vector<std::uint8_t> payload(data + 3, data + size);
    const std::vector<std::uint8_t> framed =
        frameSnapshot(is3d ? SnapshotKind::world3 : SnapshotKind::world2, bodies, payload);
    // The live world: the base scene after one step (bodies, contacts, a warm-start cache), restored afresh from
    // its own snapshot for every input.
    if (is3d) {
        static const std::vector<std::uint8_t> base = [] {
            scenes::LoadedScene3 loaded = scenes::loadScene3(nlohmann::json::parse(kScene3), "base");
            loaded.world->step();
            return loaded.world->snapshot();
        }();
        World3 world;
        fuzz::require(world.restore(base.data(), base.size()), "the base world restores");
        restoreInto(world, framed);
    } else {
        static const std::vector<std::uint8_t> base = [] {
            scenes::LoadedScene2 loaded = scenes::loadScene2(nlohmann::json::parse(kScene2), "base");
            loaded.world->step();
            return loaded.world->snapshot();
        }();
        World2 world;
        fuzz::require(world.restore(base.data(), base.size()), "the base world restores");
        restoreInto(world, framed);
    }
    return 0;
}
