// bench/bench_lcp_manifolds.h — bench_lcp's table of contact LCPs from Box2D 2.4.1's manifolds (see the .cpp).
#pragma once

#include <unison/lcp.h>

#include <nlohmann/json.hpp>

#include <string>

namespace unison::bench {

/// Unison's island fast path on one LCP, as bench_lcp's "fast" columns call it (the hook where the fast path's
/// entry point is wired; until then the same LemkeSolver::solve).
LcpResult unisonFastPath(LemkeSolver& solver, const SparseLcp& lcp, const LcpOptions& options);

/// Runs and prints the family (quick: the 12-row frictionless members only; `filter`: names containing it), timing
/// each solver as the fastest of repeats within `budgetMs`, and returns the rows as JSON.
nlohmann::json runManifoldFamily(bool quick, double budgetMs, const std::string& filter);

}  // namespace unison::bench
