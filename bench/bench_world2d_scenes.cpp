// bench/bench_world2d_scenes.cpp — the scenes of bench_world2d (bench_world2d_scenes.h).
#include "bench_world2d_scenes.h"

#include "make_scenes2d.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace unison::bench {
namespace {

// A testbed pyramid of `rows` rows: its top box stands at rows - 0.5 m and falls rows * 0.25 m before it lands.
SceneSpec testbedPyramid(std::string name, std::string description, int rows, int steps, double budget, double settle) {
    SceneSpec s{std::move(name), std::move(description), unison::scenes::pyramidScene(rows, 0.5, false), steps, budget};
    s.judge = Judge::stands;
    s.standingTopY = rows - 0.5;
    s.settleSeconds = std::sqrt(2.0 * 0.25 * rows / 10.0) + settle;
    return s;
}

// A scene laid out touching (Box2D v3's layouts): judged from 0.5 s on against the top body's start height, and
// run for at least `standSeconds` after that.
SceneSpec touchingScene(std::string name, std::string description, nlohmann::json scene, int steps, double budget,
                        double standSeconds) {
    SceneSpec s{std::move(name), std::move(description), std::move(scene), steps, budget};
    s.judge = Judge::stands;
    s.standingTopY = s.scene["bodies"].back()["position"][1].get<double>();
    s.settleSeconds = 0.5;
    s.standSeconds = standSeconds;
    s.steps = std::max(steps, int(std::lround((s.settleSeconds + standSeconds) * 60.0)));
    return s;
}

SceneSpec plainScene(std::string name, std::string description, nlohmann::json scene, int steps, double budget) {
    return {std::move(name), std::move(description), std::move(scene), steps, budget};
}

}  // namespace

std::vector<SceneSpec> makeScenes(bool quick, double settle, double standSeconds) {
    namespace sc = unison::scenes;
    std::vector<SceneSpec> s;
    if (quick) {
        // ctest smoke run: a few seconds in all.
        s.push_back(testbedPyramid("pyramid20", "Box2D testbed pyramid, 20 rows (210 boxes)", 20, 60, 5.0, settle));
        s.push_back(testbedPyramid("pyramids40x5", "40 separate 5-row pyramids (600 boxes)", 5, 60, 5.0, settle));
        s.back().scene = sc::manyPyramidsScene(40, 5, false);
        s.push_back(touchingScene("v3_arch", "Box2D v3 arch sample (21 bodies)", sc::archScene(false), 60, 2.0, 0.5));
        s.push_back(touchingScene("v3_vstack", "Box2D v3 vertical stack, 12 boxes", sc::verticalStackScene(12, 1, false), 60, 2.0, 0.5));
        s.push_back(touchingScene("v3_cardhouse", "Box2D v3 card house, 5 levels (40 cards, friction 0.7)",
                                  sc::cardHouseScene(5, false), 60, 2.0, 0.5));
        s.push_back(plainScene("v3_domino", "Box2D v3 double domino, 15 dominoes", sc::doubleDominoScene(15, false), 60, 2.0));
        return s;
    }
    // Budgets are seconds of step time per engine, each at least what the scene's target needs (e.g. 600 steps at
    // 100 ms); their sum, with the kill limit of a step that overruns, bounds a default run to about 8 minutes.
    s.push_back(testbedPyramid("pyramid20", "Box2D testbed pyramid, 20 rows (210 boxes)", 20, 300, 20.0, settle));
    // The same pyramid left standing for 40 s: what a settled pile costs per step later on (summary: "settled cost").
    s.push_back(testbedPyramid("pyramid20_long", "Box2D testbed pyramid, 20 rows, 40 s", 20, 2400, 30.0, settle));
    s.push_back(testbedPyramid("pyramid30", "testbed layout, 30 rows (465 boxes)", 30, 300, 30.0, settle));
    {
        SceneSpec p40 = testbedPyramid("pyramid40", "testbed layout, 40 rows (820 boxes)", 40, 300, 60.0, settle);
        p40.standSeconds = standSeconds;
        p40.steps = std::max(300, int(std::lround((p40.settleSeconds + standSeconds) * 60.0)));
        s.push_back(std::move(p40));
    }
    s.push_back(testbedPyramid("pyramids40x5", "40 separate 5-row pyramids (600 boxes)", 5, 300, 15.0, settle));
    s.back().scene = sc::manyPyramidsScene(40, 5, false);
    s.push_back(plainScene("circles2000", "2000 circles r 0.25 dropped side by side (2000 one-contact islands)",
                           sc::scatteredCirclesScene(2000, false), 300, 15.0));
    s.push_back(plainScene("circlepile2000", "2000 circles r 0.25 falling into a container (one pile)",
                           sc::fallingCirclesScene(2000, false), 300, 30.0));
    s.push_back(touchingScene("v3_pyramid40", "Box2D v3 large pyramid, 40 rows (820 boxes, touching)",
                              sc::largePyramidScene(40, false), 600, 45.0, standSeconds));
    // 300 steps at the target's 100 ms need 30 s; Unison's first step alone takes minutes today (killed at 65 s).
    s.push_back(touchingScene("v3_pyramid100", "Box2D v3 large pyramid, 100 rows (5050 boxes)",
                              sc::largePyramidScene(100, false), 300, 35.0, 0.0));
    s.push_back(touchingScene("v3_pyramids5x5", "Box2D v3 many pyramids, 5 x 5 of base 10 (1375 boxes)",
                              sc::pyramidGridScene(5, 5, 10, false), 600, 60.0, 0.0));
    s.push_back(touchingScene("v3_pyramids20x20", "Box2D v3 many pyramids, 20 x 20 of base 10 (22000 boxes)",
                              sc::pyramidGridScene(20, 20, 10, false), 600, 75.0, 0.0));
    s.back().peerBudgetSeconds = 20.0;  // Box2D 2.4.1 takes ~0.8 s per step here
    s.push_back(touchingScene("v3_cardhouse", "Box2D v3 card house, 5 levels (40 cards, friction 0.7)",
                              sc::cardHouseScene(5, false), 600, 30.0, standSeconds));
    s.push_back(touchingScene("v3_arch", "Box2D v3 arch sample (17 stones, 4 boxes)", sc::archScene(false), 600, 15.0,
                              standSeconds));
    s.push_back(touchingScene("v3_vstack", "Box2D v3 vertical stack, 12 boxes", sc::verticalStackScene(12, 1, false), 600,
                              15.0, standSeconds));
    s.push_back(plainScene("v3_domino", "Box2D v3 double domino, 15 dominoes", sc::doubleDominoScene(15, false), 300, 10.0));
    return s;
}

}  // namespace unison::bench
