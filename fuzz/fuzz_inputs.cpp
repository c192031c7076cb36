// fuzz/fuzz_inputs.cpp — the inputs JSON (replay/inputs.cpp): the first byte picks 2D or 3D, the rest is parsed and
// the inputs of ticks 1..4 are applied to a small scene of that dimension, which must then snapshot and restore.
#include "fuzz_support.h"
#include "inputs.h"

namespace {

const char* kScene2 = R"({"dimension": 2, "bodies": [
  {"type": "static", "shapes": [{"type": "segment", "points": [[-5, 0], [5, 0]]}]},
  {"position": [0, 0.5], "shapes": [{"type": "box", "half_extents": [0.5, 0.5]}]},
  {"position": [0, 1.6], "shapes": [{"type": "circle", "radius": 0.5}]}]})";
const char* kScene3 = R"({"dimension": 3, "bodies": [
  {"type": "static", "shapes": [{"type": "plane", "normal": [0, 1, 0]}]},
  {"position": [0, 0.5, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
  {"position": [0, 1.6, 0], "shapes": [{"type": "sphere", "radius": 0.5}]}]})";

template <class World>
void run(const nlohmann::json& scene, const unison::replay::InputScript& script) {
    unison::replay::Session<World> session(scene, "scene");
    for (int t = 1; t <= 4; ++t) session.tick(t, script);
    unison::fuzz::stepSnapshotRestore(session.world(), 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace unison;
    if (size == 0) return 0;
    const int dimension = data[0] % 2 == 0 ? 2 : 3;
    try {
        const replay::InputScript script =
            replay::parseInputs(jsonio::parseJson(fuzz::text(data + 1, size - 1), "fuzz"), "fuzz", dimension);
        if (dimension == 2) {
            run<World2>(nlohmann::json::parse(kScene2), script);
        } else {
            run<World3>(nlohmann::json::parse(kScene3), script);
        }
    } catch (const jsonio::JsonError&) {
    }
    return 0;
}
