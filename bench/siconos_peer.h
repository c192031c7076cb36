// bench/siconos_peer.h — Siconos numerics' lexicographic Lemke (lcp_lexicolemke, Siconos 4.4) as a benchmark peer.
//
// Owns: the conversion of a row-major unison::Lcp to Siconos' column-major dense NumericsMatrix, the solver
// options (iteration cap), and one call of lcp_lexicolemke. Siconos headers stay inside siconos_peer.cpp so the
// benchmark's other files never see their C macros.
//
// Caveat measured, not assumed: lcp_lexicolemke reports info = 0 both when z0 leaves the basis and when the
// driving column has no positive entry (a secondary ray), so `info` alone does not say "solved". Judge its answer
// with a residual recomputed from (A, b, z), as the benchmark does.
#pragma once

#include <unison/lcp.h>

#include <vector>

namespace unison::bench {

/// Outcome of one Siconos lexicographic Lemke solve.
struct SiconosResult {
    int info = -1;               ///< Siconos termination code: 0 = stopped (solution or ray), 1 = iteration cap
    int iterations = 0;          ///< pivots after z0 entered (iparam[SICONOS_IPARAM_ITER_DONE]); 0 for b >= 0
    std::vector<double> z;       ///< (n)
    std::vector<double> w;       ///< (n) as Siconos returns it (not recomputed)
    double seconds = 0.0;        ///< wall-clock time of the lcp_lexicolemke call alone
};

/// One problem prepared for Siconos: the column-major copy and the options are built once, so repeated solve()
/// calls time only the solver. Not copyable (owns Siconos allocations).
class SiconosPeer {
public:
    /// `maxIterations` 0 selects max(100000, 10 n).
    explicit SiconosPeer(const Lcp& problem, int maxIterations = 0);
    ~SiconosPeer();
    SiconosPeer(const SiconosPeer&) = delete;
    SiconosPeer& operator=(const SiconosPeer&) = delete;

    SiconosResult solve();
    int size() const { return mN; }

private:
    int mN = 0;
    int mMaxIterations = 0;
    void* mMatrix = nullptr;   // NumericsMatrix*, dense column-major copy of A
    void* mOptions = nullptr;  // SolverOptions*
    std::vector<double> mQ;    // b
};

/// Convenience: prepare and solve once.
SiconosResult solveWithSiconos(const Lcp& problem, int maxIterations = 0);

}  // namespace unison::bench
