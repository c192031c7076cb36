// core/lcp_warm.h — what the Lemke solver's entry points (lcp.cpp) share with its run: option checks, the guess as
// a set, and the warm-start check (lcp_warm.cpp), which accepts a guessed basis with one factorisation of A
// restricted to it, or corrects it by block principal pivoting, before any pivoting state exists.
// Invariants: an accepted guess gives the same bits as solve() would from it; a refused one changes nothing but
// the workspace's factorisation and its refusal record.
#pragma once

#include <unison/lcp.h>

#include "lcp_workspace.h"

#include <vector>

namespace unison::lcp_detail {

/// Options a solve accepts (NaN fails every comparison, so it is out of range too).
bool optionsInRange(const LcpOptions& o);

/// A warm basis as a set: ascending, without repeats.
std::vector<int> sortedUnique(std::vector<int> v);

/// Checks `guess` as the basis of the workspace's LCP: true when `out` holds the solution; else `corrected` is the
/// guess a block principal pivot would try next. `scale` is max(max|A|, max|b|).
bool trySparseBasis(LemkeSolver::Workspace& ws, const std::vector<int>& guess, const LcpOptions& options,
                    double scale, LcpResult& out, std::vector<int>& corrected);

/// The guess, corrected up to options.blockPivotRounds times by block principal pivoting; true when `out` holds
/// the solution. Takes over a refusal checkGuess() recorded for the same guess and b.
bool trySparseWarmStart(LemkeSolver::Workspace& ws, const std::vector<int>& guess, const LcpOptions& options,
                        double scale, LcpResult& out);

}  // namespace unison::lcp_detail
