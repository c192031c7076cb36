// samples/run_stats.h — what `unison run` adds up over a run's steps for its final "stats" (2D and 3D alike): the
// counts of StepStats, and the wall-clock time of each step (outside the hash: it is the only thing here that
// differs between machines and thread counts).
#pragma once

#include "world_step.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>

namespace unison::cli {

/// Step statistics summed (counts) or maximised (residuals, work) over a run.
struct RunStats {
    int totalPivots = 0, maxIslandPivots = 0, discardedGuesses = 0, basisChange = 0, failed = 0, unsolved = 0;
    long approximateIslands = 0, exactIslands = 0, activeSetIslands = 0, interiorPointRestarts = 0;
    double maxResidual = 0.0, maxPenetration = 0.0, maxApproximateResidual = 0.0;
    std::uint64_t maxStepWork = 0;
    double worstStepMs = 0.0, totalMs = 0.0;
    int steps = 0;

    /// Steps `world` once (world.step()), timing it, and adds its StepStats.
    template <class World>
    void step(World& world) {
        const auto t0 = std::chrono::steady_clock::now();
        world.step();
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        worstStepMs = std::max(worstStepMs, ms);
        totalMs += ms;
        ++steps;
        const StepStats& st = world.stats();
        totalPivots += st.pivots;
        maxIslandPivots = std::max(maxIslandPivots, st.maxIslandPivots);
        discardedGuesses += st.discardedGuesses;
        basisChange += st.basisChange;
        failed += st.failedIslands;
        unsolved += st.unsolvedIslands;
        approximateIslands += st.approximateIslands;
        exactIslands += st.exactIslands;
        activeSetIslands += st.activeSetIslands;
        interiorPointRestarts += st.interiorPointRestarts;
        maxResidual = std::max(maxResidual, st.maxResidual);
        maxPenetration = std::max(maxPenetration, st.maxPenetration);
        maxApproximateResidual = std::max(maxApproximateResidual, st.maxApproximateResidual);
        maxStepWork = std::max(maxStepWork, st.work);
    }

    /// The final JSON's "stats" object (last is the last step's StepStats, for contacts and islands).
    nlohmann::json toJson(const StepStats& last) const {
        return {{"total_pivots", totalPivots}, {"max_island_pivots", maxIslandPivots},
                {"discarded_guesses", discardedGuesses}, {"basis_change", basisChange}, {"failed_islands", failed},
                {"unsolved_islands", unsolved}, {"max_residual", maxResidual}, {"max_penetration", maxPenetration},
                {"contacts", last.contacts}, {"islands", last.islands}, {"worst_step_ms", worstStepMs},
                {"mean_step_ms", steps > 0 ? totalMs / steps : 0.0}, {"max_step_work", maxStepWork},
                {"approximate_islands", approximateIslands}, {"exact_islands", exactIslands},
                {"active_set_islands", activeSetIslands}, {"interior_point_restarts", interiorPointRestarts},
                {"max_approximate_residual", maxApproximateResidual}};
    }
};

}  // namespace unison::cli
