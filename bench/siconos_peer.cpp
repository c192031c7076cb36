// bench/siconos_peer.cpp — see siconos_peer.h.
#include "siconos_peer.h"

#include <LCP_Solvers.h>
#include <LinearComplementarityProblem.h>
#include <NumericsMatrix.h>
#include <SolverOptions.h>
#include <lcp_cst.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <stdexcept>

namespace unison::bench {

namespace {
NumericsMatrix* asMatrix(void* p) { return static_cast<NumericsMatrix*>(p); }
SolverOptions* asOptions(void* p) { return static_cast<SolverOptions*>(p); }
}  // namespace

SiconosPeer::SiconosPeer(const Lcp& problem, int maxIterations) : mN(problem.n), mQ(problem.b) {
    if (problem.n <= 0 || problem.A.size() != std::size_t(problem.n) * std::size_t(problem.n) ||
        problem.b.size() != std::size_t(problem.n)) {
        throw std::invalid_argument("SiconosPeer: malformed LCP");
    }
    mMaxIterations = maxIterations > 0 ? maxIterations : std::max(100000, 10 * mN);

    // Siconos dense matrices are column-major: matrix0[i + j n] = A_ij.
    NumericsMatrix* m = NM_create(NM_DENSE, mN, mN);
    for (int j = 0; j < mN; ++j) {
        for (int i = 0; i < mN; ++i) m->matrix0[std::size_t(i) + std::size_t(j) * std::size_t(mN)] = problem.at(i, j);
    }
    mMatrix = m;

    SolverOptions* options = solver_options_create(SICONOS_LCP_LEMKE);
    if (!options) throw std::runtime_error("SiconosPeer: solver_options_create(SICONOS_LCP_LEMKE) failed");
    options->iparam[SICONOS_IPARAM_MAX_ITER] = mMaxIterations;
    mOptions = options;
}

SiconosPeer::~SiconosPeer() {
    if (mOptions) {
        // Siconos 4.4's solver_options_delete releases the members but not the struct itself.
        solver_options_delete(asOptions(mOptions));
        std::free(mOptions);
    }
    if (mMatrix) NM_free(asMatrix(mMatrix));
}

SiconosResult SiconosPeer::solve() {
    SiconosResult out;
    out.z.assign(std::size_t(mN), 0.0);
    out.w.assign(std::size_t(mN), 0.0);

    LinearComplementarityProblem lcp;
    lcp.size = mN;
    lcp.M = asMatrix(mMatrix);
    lcp.q = mQ.data();

    SolverOptions* options = asOptions(mOptions);
    options->iparam[SICONOS_IPARAM_MAX_ITER] = mMaxIterations;
    options->iparam[SICONOS_IPARAM_ITER_DONE] = 0;

    int info = -1;
    const auto start = std::chrono::steady_clock::now();
    lcp_lexicolemke(&lcp, out.z.data(), out.w.data(), &info, options);
    const auto stop = std::chrono::steady_clock::now();

    out.info = info;
    out.iterations = options->iparam[SICONOS_IPARAM_ITER_DONE];
    out.seconds = std::chrono::duration<double>(stop - start).count();
    return out;
}

SiconosResult solveWithSiconos(const Lcp& problem, int maxIterations) {
    SiconosPeer peer(problem, maxIterations);
    return peer.solve();
}

}  // namespace unison::bench
