// core/world_settings.h — the settings the 2D and 3D worlds share (WorldDef2 and WorldDef3 derive from it and add
// gravity and what only one dimension has). Every field but the thread settings is part of the state: the state
// walk (core/state_transfer.h worldSettings) hashes and snapshots them in one fixed order.
#pragma once

#include <unison/lcp.h>
#include <unison/types.h>

#include <cstdint>

namespace unison {

/// World settings both dimensions have. Defaults follow Box2D 2.4.1 where it has the same notion; a world's own
/// definition sets the few that differ (tangentDeadZone, lcp).
struct WorldSettings {
    double hz = 60.0;                    ///< steps per second
    double restitutionThreshold = 1.0;   ///< approach speeds below this (m/s) use e = 0
    double linearSlop = 0.005;           ///< allowed penetration (m)
    double baumgarte = 0.2;              ///< fraction of the penetration beyond the slop removed per step
    double maxCorrectionSpeed = 3.0;     ///< cap of the position-correction velocity (m/s)
    double speculativeDistance = 0.02;   ///< contacts this far apart are already in the LCP (m)
    /// Tangential speeds below this (m/s) are exactly 0 in Lemke's friction LCP (resting piles creep at rounding
    /// level, below what its tie-breaking perturbation resolves). A settled 2D island on the active-set path takes
    /// them exactly instead (docs/solver.md, "Settled islands").
    double tangentDeadZone = 1e-7;
    bool enableSleep = true;
    double linearSleepTolerance = 0.01;  ///< m/s
    double angularSleepTolerance = 2.0 / 180.0 * 3.141592653589793;  ///< rad/s
    double timeToSleep = 0.5;            ///< s
    /// A friction solve that ends `numerical_failure` (the answer of the solver's tie-breaking perturbation misses
    /// the true problem by more than lcp.residualTolerance, and no continuation did better) is still used when its
    /// scaled residual is at most this; only beyond it does the island fall back to the frictionless LCP.
    /// StepStats counts such islands and reports the largest scaled residual.
    double acceptResidual = 1e-6;
    /// Per-island solver options; maxPivots 0 = 8n + 100 (2D) or 2n + 100 (3D) for the friction LCP (n unknowns),
    /// 10 nc + 1000 for the frictionless fallback (nc contacts).
    LcpOptions lcp;
    /// Work units one step may spend (core/step_budget.h; work::fromMilliseconds converts a time on the reference
    /// machine), 0 = unlimited. Islands the budget cannot solve exactly get a bounded approximation (StepStats
    /// counts them). Part of the state: every peer must step with the same budget.
    std::uint64_t stepBudget = 0;
    /// Threads a step may use (>= 1). Not state: the answer is the same bits for any count.
    int workerCount = 1;
    /// An embedding job system (core/task_system.h), both or neither; none: the world's own std::thread pool when
    /// workerCount > 1. Not state.
    EnqueueTaskCallback* enqueueTask = nullptr;
    FinishTaskCallback* finishTask = nullptr;
    void* userTaskContext = nullptr;  ///< passed to enqueueTask and finishTask
};
static_assert(sizeof(WorldSettings) == 192, "WorldSettings changed: serialise the new field (state_transfer.h)");

}  // namespace unison
