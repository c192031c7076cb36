// bench/bench_world2d_scenes.h — the scenes bench_world2d runs: each a scene JSON from scenes/make_scenes2d, its
// step count, its budgets of step time and how it is judged.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace unison::bench {

enum class Judge { none, stands };

struct SceneSpec {
    std::string name;
    std::string description;
    nlohmann::json scene;
    int steps = 0;                // steps every engine runs at most
    double budgetSeconds = 0.0;   // step time Unison may use on this scene (>= what its targets need)
    double peerBudgetSeconds = 0.0;  // step time each peer may use (0: budgetSeconds)
    Judge judge = Judge::none;    // "stands" verdict on the last body
    double standingTopY = 0.0;    // centre height of the top body standing (m)
    double settleSeconds = 0.0;   // time from the start to the reference position (s)
    double standSeconds = 0.0;    // time it must stand after the settle step (s)
};

/// The default run's scenes (quick: ctest's smoke run). `settle` is the time a testbed pyramid gets to come to
/// rest after its top box lands; judged scenes run at least `standSeconds` after settling.
std::vector<SceneSpec> makeScenes(bool quick, double settle, double standSeconds);

}  // namespace unison::bench
