// core/lcp_robust.cpp — the robust path of LemkeSolver: what a solve does when its Lemke run does not end `solved`.
//
// Why: contact LCPs with redundant rows (a settled pile has more contact rows than body degrees of freedom) have a
// singular A, and in floating point Lemke's path on them cycles, meets a block it cannot factorise or ends on a ray
// that exists only by rounding. Such an LCP (A copositive: z^T A z >= 0 for z >= 0) is solved here by the proximal
// point method: z_{k+1} solves the regularised LCP
//     (A + eps_k I) z + (b - eps_k z_k) >= 0,   z >= 0,   complementary,          z_0 = 0,
// whose matrix is strictly copositive (Lemke's path ends on a solution, never on a ray) and whose blocks are
// nonsingular. Its w differs from the true problem's by eps_k (z_{k+1} - z_k), so the iterates' true residual falls
// as they settle and eps_k shrinks; for a PSD A with b in its range they converge to a solution of the true LCP.
// eps_0 is large (well-conditioned first, cold sub-solve) and shrinks 10x per iteration to a floor. Every sub-solve
// is a Lemke run of this solver, warm-started from the previous one's basis (once the basis settles, one
// factorisation and no pivot). Each new basis is also checked on the true problem (the ordinary warm-start check: z
// recomputed from the basis with the true b), which gives the exact answer once the basis is a nonsingular block
// of the true A; else the best iterate stands, judged by its residual on the true (A, b).
//
// Honesty: `solved` only within options.residualTolerance on the true problem; an answer between that and
// kAcceptResidual is `numerical_failure` carrying its z; anything worse returns the first run's own result (so a
// truly infeasible LCP stays `infeasible`). Pivots and work of every sub-solve count against the caller's caps.
// Determinism: fixed iteration cap, fixed index order everywhere, no sorting, no transcendental functions.
#include <unison/lcp.h>

#include "lcp_warm.h"
#include "lcp_workspace.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace unison {

namespace {

/// eps of the first regularised sub-solve relative to max |A_ii|, the factor it shrinks by per iteration, and its
/// floor.
constexpr double kRegularisation = 1e-3;
constexpr double kShrink = 0.1;
constexpr double kRegularisationMin = 1e-8;
/// Proximal iterations (each one Lemke sub-solve) at most.
constexpr int kMaxIterations = 32;
/// Iterations without a better true residual after which the iteration stops (the data's noise floor).
constexpr int kMaxStalled = 3;
/// Largest scaled residual of an answer returned as `numerical_failure` (else the first run's result stands).
constexpr double kAcceptResidual = 1e-6;

/// A compressed-row matrix (the workspace's row form).
struct Rows {
    std::vector<int> start, col;
    std::vector<double> val;
};

/// A + eps I in compressed rows, the diagonal entry inserted where A's pattern lacks it; columns stay ascending.
Rows shiftedDiagonal(int n, const std::vector<int>& start, const std::vector<int>& col, const std::vector<double>& val,
                     double eps) {
    Rows out;
    out.start.assign(std::size_t(n) + 1, 0);
    out.col.reserve(col.size() + std::size_t(n));
    out.val.reserve(col.size() + std::size_t(n));
    for (int i = 0; i < n; ++i) {
        bool placed = false;
        for (int k = start[std::size_t(i)]; k < start[std::size_t(i) + 1]; ++k) {
            const int j = col[std::size_t(k)];
            if (!placed && j >= i) {
                placed = true;
                if (j == i) {
                    out.col.push_back(i);
                    out.val.push_back(val[std::size_t(k)] + eps);
                    continue;
                }
                out.col.push_back(i);
                out.val.push_back(eps);
            }
            out.col.push_back(j);
            out.val.push_back(val[std::size_t(k)]);
        }
        if (!placed) {
            out.col.push_back(i);
            out.val.push_back(eps);
        }
        out.start[std::size_t(i) + 1] = int(out.col.size());
    }
    return out;
}

/// w = A z + b by rows (columns in ascending order), and the complementarity residual of (z, w).
double trueResidual(int n, const Rows& a, const std::vector<double>& b, const std::vector<double>& z,
                    std::vector<double>& w) {
    w.assign(b.begin(), b.end());
    for (int i = 0; i < n; ++i) {
        double s = b[std::size_t(i)];
        for (int k = a.start[std::size_t(i)]; k < a.start[std::size_t(i) + 1]; ++k)
            s += a.val[std::size_t(k)] * z[std::size_t(a.col[std::size_t(k)])];
        w[std::size_t(i)] = s;
    }
    return complementarityResidual(z, w);
}


}  // namespace

LcpResult LemkeSolver::runRobust(Workspace& ws, const double* b, const LcpOptions& options) {
    LcpResult first = run(ws, b, options);
    if (first.status == LcpStatus::solved || first.status == LcpStatus::invalid_input || ws.n == 0) return first;
    // A near miss (numerical_failure within kAcceptResidual, an answer a world accepts) stands: on the landing piles
    // where it happens the sub-problems meet the same rounding and cost 2-6x the run's pivots for nothing.
    if (first.status == LcpStatus::numerical_failure && first.scaledResidual <= kAcceptResidual) return first;
    // A run that the caller's pivot cap or work budget stopped gets no more: the budget is spent.
    if (first.status == LcpStatus::pivot_limit &&
        (first.message == lcp_detail::kPivotCapMessage || first.message == lcp_detail::kWorkBudgetMessage))
        return first;
    return proximal(ws, b, options, std::move(first));
}

LcpResult LemkeSolver::proximal(Workspace& ws, const double* b, const LcpOptions& options, LcpResult failed) {
    const int n = ws.n;
    const std::size_t nn = std::size_t(n);
    const int maxPivots = options.maxPivots > 0 ? options.maxPivots : LcpOptions::kDefaultMaxPivots;
    // The true problem, kept aside while the workspace holds the regularised one.
    Rows truth;
    truth.start = ws.rowStart;
    truth.col = ws.rowCol;
    truth.val = ws.rowVal;
    const std::vector<double> bTrue(b, b + n);
    const double aMaxTrue = ws.aMaxA;
    double bMax = 0.0, diagMax = 0.0;
    for (int i = 0; i < n; ++i) bMax = std::max(bMax, std::fabs(bTrue[std::size_t(i)]));
    for (int i = 0; i < n; ++i) {
        for (int k = truth.start[std::size_t(i)]; k < truth.start[std::size_t(i) + 1]; ++k) {
            if (truth.col[std::size_t(k)] == i) diagMax = std::max(diagMax, std::fabs(truth.val[std::size_t(k)]));
        }
    }
    const double scale = std::max({aMaxTrue, bMax, kTiny});
    // One evaluation of the true residual: a pass over A and b.
    const std::uint64_t checkWork = std::uint64_t(truth.col.size()) + std::uint64_t(n);
    // The most a warm-start check can count (its block's nonzeros, at most A's plus the diagonal, or a dense 48 x 48
    // LU, plus n). A run counts an accepted check without testing it against maxWork, and a sub-solve may run up to
    // four (its own and its continuations'), so that much is held back from every sub-solve's budget.
    const std::uint64_t checkBound =
        std::max<std::uint64_t>(std::uint64_t(lcp_detail::BlockFactor::kDenseMax) * lcp_detail::BlockFactor::kDenseMax,
                                checkWork) + std::uint64_t(n);
    const std::uint64_t reserve = 4 * checkBound + checkWork;
    LcpResult total = failed;  // counts every pivot and unit of work from here on
    auto budgetLeft = [&]() {
        return total.pivots < maxPivots && (!options.maxWork || total.work + reserve + checkWork < options.maxWork);
    };
    if (!(diagMax > 0.0) || !budgetLeft()) return failed;

    double eps = kRegularisation * diagMax;
    double epsFloor = kRegularisationMin * diagMax;
    // Loads A + e I into the workspace (its rows; the columns are rebuilt when a run needs them).
    auto loadShifted = [&](double e) {
        Rows shifted = shiftedDiagonal(n, truth.start, truth.col, truth.val, e);
        double aMaxShifted = 0.0;
        for (double v : shifted.val) aMaxShifted = std::max(aMaxShifted, std::fabs(v));
        ws.rowStart.swap(shifted.start);
        ws.rowCol.swap(shifted.col);
        ws.rowVal.swap(shifted.val);
        ws.aMaxA = aMaxShifted;
        ws.columnsReady = false;
    };
    double aMaxHeld = aMaxTrue;  // max |A_ij| of the true A while the workspace holds the shifted one

    // The ordinary warm-start check of a basis on the true problem (z recomputed from the basis with the true b):
    // true, with the answer in `check`, when it passes. The true rows visit the workspace for it.
    std::vector<int> checkedBasis;
    LcpResult check;
    auto checkOnTruth = [&](const std::vector<int>& guess) {
        if (guess.empty() || guess == checkedBasis || (options.maxWork && total.work + checkBound > options.maxWork))
            return false;
        checkedBasis = guess;
        ws.rowStart.swap(truth.start);
        ws.rowCol.swap(truth.col);
        ws.rowVal.swap(truth.val);
        std::swap(ws.aMaxA, aMaxHeld);
        ws.columnsReady = false;
        check = LcpResult();
        check.z.assign(nn, 0.0);
        check.w.assign(bTrue.begin(), bTrue.end());
        ws.loadB(bTrue.data());
        ws.refusal.valid = false;
        LcpOptions one = options;  // one factorisation: block principal rounds never rescued a basis here
        one.blockPivotRounds = 0;
        const bool passed = lcp_detail::trySparseWarmStart(ws, guess, one, scale, check);
        ws.rowStart.swap(truth.start);
        ws.rowCol.swap(truth.col);
        ws.rowVal.swap(truth.val);
        std::swap(ws.aMaxA, aMaxHeld);
        ws.columnsReady = false;
        total.work += passed ? check.work : ws.blockFactor.work() + std::uint64_t(n);
        return passed && (!options.maxWork || total.work <= options.maxWork);
    };
    std::vector<double> z(nn, 0.0), bk(nn), w;
    std::vector<int> basis;
    LcpResult best;
    best.scaledResidual = failed.scaledResidual;
    bool haveBest = false;
    int stalled = 0;
    double goodEps = 0.0;    // the eps of the last usable sub-solve (0: none yet)
    double loadedEps = 0.0;  // the eps of the matrix in the workspace (0: the true A)
    bool answered = false;   // a basis passed the check on the true problem (`check` holds the answer)
    for (int k = 0; k < kMaxIterations && budgetLeft() && stalled < kMaxStalled; ++k) {
        if (eps != loadedEps) {
            loadShifted(eps);
            loadedEps = eps;
            total.work += checkWork;
        }
        for (std::size_t i = 0; i < nn; ++i) bk[i] = bTrue[i] - eps * z[i];
        LcpOptions sub = options;
        sub.maxPivots = maxPivots - total.pivots;
        if (options.maxWork) sub.maxWork = options.maxWork - total.work - reserve;
        sub.warmBasis = basis.empty() ? nullptr : &basis;
        LcpResult r = run(ws, bk.data(), sub);
        total.pivots += r.pivots;
        total.work += r.work;
        total.restarts += r.restarts;
        // A sub-solve within kAcceptResidual is an inexact proximal step, still a usable iterate.
        const bool subSolved = r.status == LcpStatus::solved ||
                               (r.status == LcpStatus::numerical_failure && r.scaledResidual <= kAcceptResidual);
        if (!subSolved) {
            // Too small an eps for this data (a float-assembled A is indefinite at ~1e-8 of its scale, and the
            // sub-problem loses its guarantee): go back to the last eps that worked and stay there.
            if (goodEps > eps) {
                eps = goodEps;
                epsFloor = goodEps;
                continue;
            }
            break;
        }
        goodEps = eps;
        const bool moved = r.z != z;
        z.swap(r.z);
        basis.swap(r.basis);
        const double res = trueResidual(n, truth, bTrue, z, w) / scale;
        total.work += checkWork;
        if (!haveBest || res < best.scaledResidual) {
            haveBest = true;
            stalled = 0;
            best.z = z;
            best.w = w;
            best.basis = basis;
            best.residual = res * scale;
            best.scaledResidual = res;
        } else {
            ++stalled;
        }
        // Once the sub-solves' basis is a nonsingular block of the true A, it may be the true answer's basis.
        if (checkOnTruth(basis)) {
            answered = true;
            break;
        }
        if (res <= options.residualTolerance || !moved) break;
        eps = std::max(epsFloor, eps * kShrink);
    }

    // The true problem back in the workspace.
    ws.rowStart.swap(truth.start);
    ws.rowCol.swap(truth.col);
    ws.rowVal.swap(truth.val);
    ws.aMaxA = aMaxTrue;
    ws.columnsReady = false;
    // A factorisation is not split: one that overran the caller's budget ends the solve with pivot_limit, whatever
    // it found (LcpOptions::maxWork).
    const bool overrun = (options.maxWork && total.work > options.maxWork) || total.pivots > maxPivots;
    if (!haveBest || overrun) {
        failed.pivots = total.pivots;
        failed.work = total.work;
        failed.restarts = total.restarts;
        if (overrun) {
            failed.status = LcpStatus::pivot_limit;
            failed.message = lcp_detail::kWorkBudgetMessage;
        }
        return failed;
    }

    LcpResult out;
    out.pivots = total.pivots;
    out.work = total.work;
    out.restarts = total.restarts;
    if (answered) {
        check.pivots = out.pivots;
        check.work = out.work;
        check.restarts = out.restarts;
        check.warmStarted = false;
        return check;
    }
    if (best.scaledResidual <= options.residualTolerance) {
        out.status = LcpStatus::solved;
    } else if (best.scaledResidual <= kAcceptResidual) {
        out.status = LcpStatus::numerical_failure;
        char buf[96];
        std::snprintf(buf, sizeof buf, "robust path: best proximal iterate, scaled residual %.3g", best.scaledResidual);
        out.message = buf;
    } else {
        failed.pivots = out.pivots;
        failed.work = out.work;
        failed.restarts = out.restarts;
        return failed;
    }
    out.z.swap(best.z);
    out.w.swap(best.w);
    out.basis.swap(best.basis);
    out.residual = best.residual;
    out.scaledResidual = best.scaledResidual;
    return out;
}

}  // namespace unison
