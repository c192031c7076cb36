// core/step_budget.h — the per-step budget in deterministic work units: what one unit is worth in time on the
// reference machine, what each stage of a step counts, and how a step's budget is split among its islands.
//
// Owns: the work-unit weights of the stages (collision, bookkeeping, assembly, the approximation), the one
// documented conversion from milliseconds, and the allocation (allocateShares). docs/budget.md gives the design.
// Invariants: every count is an integer computed from data known on every peer (sizes, counts, the solver's own
// work units, the warm-start cache); nothing is ever timed. The allocation is a pure function of its inputs, in
// island order with ties broken by island index, so every peer and every thread count gets the same shares.
#pragma once

#include <cstdint>
#include <vector>

namespace unison {

namespace work {

/// Nanoseconds one work unit takes on the reference machine (2-core x86-64 CI class, Release build), measured once
/// on the bench scenes (bench/bench_budget prints each scene's own ns per unit beside it). Never measured at run
/// time: it only converts a budget a user thinks of in milliseconds. It is the Lemke solver's unit (LcpResult::work)
/// as measured there; every weight below was fitted to the same scale (docs/budget.md has the fit).
constexpr double kNsPerUnit = 0.9;

/// Work units of `ms` milliseconds on the reference machine (kNsPerUnit), rounded down; 0 for ms <= 0.
std::uint64_t fromMilliseconds(double ms);
/// Milliseconds of `units` work units on the reference machine.
double toMilliseconds(std::uint64_t units);

// Weights of the stages (units per item). Lemke counts its own units (LcpResult::work); these put everything else
// on the same scale.
constexpr std::uint64_t kPerBody = 50;          ///< gravity, bounding box, integration, sleep test, per body
constexpr std::uint64_t kPerShape = 10;         ///< broadphase entry, per shape
constexpr std::uint64_t kPerPair = 20;          ///< broadphase pair bookkeeping (narrowphase: the world's pairWork)
constexpr std::uint64_t kNarrowPair2 = 110;     ///< 2D narrowphase, per pair
constexpr std::uint64_t kPerFeaturePair2 = 8;   ///< 2D narrowphase, per feature pair compared
constexpr std::uint64_t kNarrowPair3 = 60;      ///< 3D narrowphase, per pair
constexpr std::uint64_t kPerFeaturePair3 = 5;   ///< 3D narrowphase, per face-vertex or edge-edge test or candidate
constexpr std::uint64_t kPerContact = 80;       ///< contact record, island edge, cache lookups, touch event
constexpr std::uint64_t kPerIsland = 1300;      ///< an exact attempt's fixed cost (set-up, validation, buffers)
constexpr std::uint64_t kPerRow = 64;           ///< LCP assembly, per row (a normal or tangent direction)
/// An exact attempt's warm-start factorisation beyond what the solver counts (LcpResult::work counts the factor's
/// nonzeros, not the flops of finding it), per row times the square root of the rows: a settled 40-row pyramid
/// (9900 rows) spends about 5 ms there, a 5-row one (170 rows) 20 us.
constexpr std::uint64_t kPerRowRoot = 4;
/// Per Lemke pivot, beyond the solver's own units: the refactorisations its count leaves out (cold solves of 40
/// five-row pyramids: 5 us per pivot against 0.8 us counted; a warm path that gives its guess up pays up to 20 us).
constexpr std::uint64_t kPerPivot = 4000;
/// A one-contact 2D island's whole exact attempt, solved in closed form (no assembly, no solve): 2000 circles resting
/// on the ground take about 0.9 ms per step in all.
constexpr std::uint64_t kClosedFormIsland = 200;
constexpr std::uint64_t kPgsPerIsland = 100;    ///< approximation: fixed cost per island
constexpr std::uint64_t kPgsSetupPerRow = 16;   ///< approximation: Jacobians and effective masses, per row
constexpr std::uint64_t kPgsSweepPerRow = 13;   ///< approximation: one projected Gauss-Seidel update, per row

/// Sweeps every approximate island gets (its reserve) and the most it gets from leftover budget.
constexpr int kMinSweeps = 8;
constexpr int kMaxSweeps = 64;

/// Prior of an island's exact work for contacts not in the warm-start cache (or answered by the approximation last
/// step): its assembly, work::kPerPivot for each of about n / 4 pivots, and this per squared LCP unknown for the
/// solver's own units (pivots on blocks of up to about n / 2 unknowns).
constexpr std::uint64_t kColdPerUnknownSquared = 4;

}  // namespace work

/// What the allocation knows of one island before it is solved (island order).
struct IslandDemand {
    std::uint64_t need = 0;       ///< predicted work of its exact solve (0: nothing to solve)
    std::uint64_t sweepWork = 0;  ///< work of one approximation sweep
};

/// Max-min fair split of `pool` among demands: each gets min(demand, level) with the level as high as the pool
/// allows; demands are visited in ascending (demand, index) order, so the result is the same on every peer.
std::vector<std::uint64_t> fairShares(const std::vector<std::uint64_t>& demands, std::uint64_t pool);

}  // namespace unison
