// replay/golden.h — the golden determinism scenes: which scenes, how many ticks, and how their hashes are taken.
//
// Owns: the one list of golden scenes that tests/test_replay.cpp (expected hashes), `unison_golden` and
// scripts/determinism.sh (the cross-build matrix) all run, so the three can never step different things.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace unison::replay {

struct GoldenScene {
    std::string name;     ///< "pyramid", "restitution_row", "mixed_pile", "cradle"
    nlohmann::json scene; ///< scene JSON (from scenes/)
    int steps = 0;        ///< ticks stepped
    std::uint64_t budget = 0;  ///< per-step budget in work units (core/step_budget.h), 0 = unlimited
    int threads = 1;           ///< worker threads it is stepped with (the hashes must not depend on it)
    /// "dimension": 3 (World3).
    bool is3d() const;
};

/// The golden scenes: a 10-row testbed pyramid (sleep off, so every tick solves its LCP warm-started), the
/// restitution row, a pile of circles, boxes and polygons in a box, the 5-ball cradle, a 16-row pyramid's landing
/// (the solver's large-block paths), Box2D v3's large pyramid at base 24 (the 2D active-set path); in 3D a toppling
/// box heap, bouncing spheres and two sphere-tree bunnies on the paper's ramps; and two of them again with a budget
/// that leaves some islands to the approximation, stepped on 2 threads. Throws on a missing scene file.
std::vector<GoldenScene> goldenScenes();

/// XXH3 of a run's tick hashes (each as little-endian u64): one value that covers every tick.
std::uint64_t chainHash(const std::vector<std::uint64_t>& hashes);

/// Steps a golden scene and returns the state hash after every tick: (steps + 1) values, [0] before the first step.
std::vector<std::uint64_t> goldenHashes(const GoldenScene& scene);

/// Snapshots a golden scene at tick steps/3, restores it into a fresh world, steps that one to the end and returns
/// the first tick whose hash differs from `hashes` (goldenHashes' result), or -1 when every tick matches (2D and 3D).
int firstRestoreMismatch(const GoldenScene& scene, const std::vector<std::uint64_t>& hashes);

}  // namespace unison::replay
