// fuzz/fuzz_scene3d.cpp — 3D scene JSON (scenes/scene_json3d.cpp, no mesh files): parse, load, step, snapshot,
// restore.
#include "fuzz_support.h"
#include "scene_json3d.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace unison;
    try {
        scenes::LoadedScene3 loaded = scenes::loadScene3(jsonio::parseJson(fuzz::text(data, size), "fuzz"), "fuzz");
        fuzz::stepSnapshotRestore(*loaded.world, 3);
    } catch (const jsonio::JsonError&) {
    }
    return 0;
}
