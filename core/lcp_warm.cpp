// core/lcp_warm.cpp — the warm-start check of the Lemke solver (see lcp_warm.h): a guessed basis is checked by
// factorising A restricted to it, corrected by block principal pivoting, and accepted when it solves the LCP to the
// residual tolerance, before any of the pivoting state is set up.
#include "lcp_warm.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace unison::lcp_detail {

// Options a solve accepts (NaN fails every comparison, so it is out of range too).
bool optionsInRange(const LcpOptions& o) {
    return o.pivotTolerance >= 0.0 && o.pivotTolerance < 1.0 && o.residualTolerance >= 0.0 &&
           o.degeneracyPerturbation >= 0.0 && o.degeneracyPerturbation <= 1e-2 && o.maxPivots >= 0 &&
           o.blockPivotRounds >= 0 && o.blockPivotRounds <= 8;
}

// A warm basis as a set: ascending, without repeats.
std::vector<int> sortedUnique(std::vector<int> v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return v;
}

// The guessed basis is usually exactly right (the previous step's basis, matched through contact ids). Checking it
// needs only A_{alpha,alpha}^-1 b_alpha (BlockFactor); the dense block inverse that further pivots would need is
// built only when the guess turns out wrong. True when `out` holds the solution; else `corrected` is the guess a
// block principal pivot would try next.
bool trySparseBasis(LemkeSolver::Workspace& ws, const std::vector<int>& guess, const LcpOptions& options,
                    double scale, LcpResult& out, std::vector<int>& corrected) {
    corrected.clear();
    const int n = ws.n;
    const int k = int(guess.size());
    std::vector<int> pos(std::size_t(n), -1);
    for (int q = 0; q < k; ++q) pos[std::size_t(guess[std::size_t(q)])] = q;
    BlockFactor& lu = ws.blockFactor;
    lu.symmetricMin = ws.symmetricHint ? BlockFactor::kDenseMax + 1 : BlockFactor::kSymmetricMin;
    if (!lu.factor(ws.rowStart, ws.rowCol, ws.rowVal, guess, pos)) return false;
    std::vector<double> z(static_cast<std::size_t>(k));
    for (int q = 0; q < k; ++q) z[std::size_t(q)] = -ws.b[guess[std::size_t(q)]];
    lu.solve(z);
    std::vector<double> w(static_cast<std::size_t>(n), 0.0);
    auto rowW = [&](int i) {
        // Adding in ascending column order: the same sum as adding the basic columns one by one.
        double s = ws.b[i];
        for (int t = ws.rowStart[std::size_t(i)]; t < ws.rowStart[std::size_t(i) + 1]; ++t) {
            const int q = pos[std::size_t(ws.rowCol[std::size_t(t)])];
            if (q >= 0) s += ws.rowVal[std::size_t(t)] * z[std::size_t(q)];
        }
        return s;
    };
    std::vector<double> zFull;
    auto computeW = [&]() {
        if (ws.product) {
            zFull.assign(std::size_t(n), 0.0);
            for (int q = 0; q < k; ++q) zFull[std::size_t(guess[std::size_t(q)])] = z[std::size_t(q)];
            (*ws.product)(zFull.data(), w.data());
            return;
        }
        for (int i = 0; i < n; ++i) w[std::size_t(i)] = rowW(i);
    };
    // One step of iterative refinement: w_alpha should be exactly 0 (only those rows are needed for it).
    std::vector<double> r(static_cast<std::size_t>(k));
    for (int q = 0; q < k; ++q) r[std::size_t(q)] = rowW(guess[std::size_t(q)]);
    lu.solve(r);
    for (int q = 0; q < k; ++q) z[std::size_t(q)] -= r[std::size_t(q)];
    computeW();
    double zMax = 0.0;
    for (int q = 0; q < k; ++q) {
        if (!std::isfinite(z[std::size_t(q)])) return false;
        zMax = std::max(zMax, std::fabs(z[std::size_t(q)]));
    }
    const double zeroY = 1e-13 * std::max(zMax, kTiny);
    const double zeroW = 1e-13 * (ws.bMax + ws.aMax * zMax);
    bool feasible = true;
    for (int i = 0; i < n; ++i) {
        // The corrected guess of a block principal pivot: keep the basic z's that are >= 0, add the w's that are < 0.
        const int q = pos[std::size_t(i)];
        const bool negative = q >= 0 ? z[std::size_t(q)] < -zeroY : w[std::size_t(i)] < -zeroW;
        feasible = feasible && !negative;
        if ((q >= 0) != negative) corrected.push_back(i);
    }
    if (!feasible) {
        // Degenerate unknowns of a resting pile come out a little below zero when b moved since the basis was
        // found (Lemke's own answers are held to the residual tolerance, not to zero). Accept the basis when every
        // violation is below that tolerance: clamp, recompute w, and let the residual check below decide.
        const double tolAbs = options.residualTolerance * scale;
        for (int i = 0; i < n; ++i) {
            const int q = pos[std::size_t(i)];
            if ((q >= 0 ? z[std::size_t(q)] : w[std::size_t(i)]) < -tolAbs) return false;
        }
        for (int q = 0; q < k; ++q) z[std::size_t(q)] = std::max(z[std::size_t(q)], 0.0);
        computeW();
    }
    std::fill(out.z.begin(), out.z.end(), 0.0);
    for (int q = 0; q < k; ++q) out.z[std::size_t(guess[std::size_t(q)])] = z[std::size_t(q)];
    out.w.swap(w);
    out.residual = complementarityResidual(out.z, out.w);
    out.scaledResidual = out.residual / scale;
    if (!(out.scaledResidual <= options.residualTolerance)) return false;
    out.status = LcpStatus::solved;
    out.basis = guess;
    out.warmStarted = true;
    out.work = lu.work() + std::uint64_t(n);
    return true;
}

// The guess, corrected up to options.blockPivotRounds times by block principal pivoting (drop basic z's that came
// out negative, add rows whose w came out negative): a small scene's basis often differs from last step's by a few
// degenerate unknowns that flipped sign by rounding, and a sparse solve per round is cheaper than Lemke pivots.
bool trySparseWarmStart(LemkeSolver::Workspace& ws, const std::vector<int>& guess, const LcpOptions& options,
                        double scale, LcpResult& out) {
    std::vector<int> current = guess, corrected;
    int first = 0;
    LemkeSolver::Workspace::Refusal& refused = ws.refusal;
    if (refused.valid && refused.guess == guess && refused.residualTolerance == options.residualTolerance &&
        refused.b.size() == std::size_t(ws.n) && std::memcmp(refused.b.data(), ws.b, refused.b.size() * sizeof(double)) == 0) {
        // checkGuess already did round 0 on this guess and b, with the same bits (its contract; with a product, up
        // to the rounding of w): take its result.
        refused.valid = false;
        if (refused.corrected.empty() || refused.corrected == current) return false;
        current.swap(refused.corrected);
        first = 1;
    }
    refused.valid = false;
    for (int round = first; round <= options.blockPivotRounds; ++round) {
        if (trySparseBasis(ws, current, options, scale, out, corrected)) return true;
        if (corrected.empty() || corrected == current) return false;
        current.swap(corrected);
    }
    return false;
}

}  // namespace unison::lcp_detail
