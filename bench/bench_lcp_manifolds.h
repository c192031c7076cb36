// bench/bench_lcp_manifolds.h — bench_lcp's table of contact LCPs from Box2D 2.4.1's manifolds (see the .cpp).
#pragma once

#include <unison/lcp.h>

#include <nlohmann/json.hpp>

#include <string>

namespace unison::bench {

struct ManifoldLcp;
struct ManifoldSnapshot;

/// Unison's fast path on one member, as bench_lcp's "fast" columns call it: the active-set path from a cold start on
/// the snapshot's bodies and contacts, then Lemke where the path does not certify its answer or where the member has
/// no bodies (float data). *usedActiveSet tells which answered.
LcpResult unisonFastPath(LemkeSolver& solver, const ManifoldLcp& m, const ManifoldSnapshot& snap,
                         const LcpOptions& options, bool* usedActiveSet);

/// Runs and prints the family (quick: the 12-row frictionless members only; `filter`: names containing it), timing
/// each solver as the fastest of repeats within `budgetMs`, and returns the rows as JSON.
nlohmann::json runManifoldFamily(bool quick, double budgetMs, const std::string& filter);

}  // namespace unison::bench
