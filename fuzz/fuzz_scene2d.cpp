// fuzz/fuzz_scene2d.cpp — 2D scene JSON (scenes/scene_json.cpp): parse, load, step, snapshot, restore.
#include "fuzz_support.h"
#include "scene_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace unison;
    try {
        scenes::LoadedScene2 loaded = scenes::loadScene2(jsonio::parseJson(fuzz::text(data, size), "fuzz"), "fuzz");
        fuzz::stepSnapshotRestore(*loaded.world, 3);
    } catch (const jsonio::JsonError&) {
    }
    return 0;
}
