// core/lcp.cpp — Lemke's method on a compact basis block, kept as a sparse LU plus a small dense border.
//
// Why not the textbook tableau: a tableau carries all n rows of B^-1 [b | I | A | d] and every pivot touches
// n x 2n entries. Contact LCPs are sparse (A = J M^-1 J^T couples contacts that share a body) and most of the
// basis is slack variables w_i that need no factorisation at all. With w = b + A z + d z0, write
//     R    = indices whose w is nonbasic (those rows must hold w_i = 0),
//     cols = basic z's plus z0 when it is basic.
// Lemke's basis is almost complementary, so |R| = |cols| = m and the basic values solve the m x m system
//     M y = -b_R,   M = [A_{R,alpha} | d_R],        (the "block")
// while every basic w_i, i not in R, is an explicit sum w_i = b_i + A_{i,alpha} z_alpha + d_i z0.
// M is never inverted. It is kept as the block of the last refactorisation (a sparse LU) plus a border of the
// rows and columns that changed since, through the inverse of a small Schur complement (see
// Workspace::pivotBorder): a pivot costs one or two sparse solves plus O(q (q + k0)) for a border of size q, and
// O(nnz(A restricted to alpha)) for the basic w's, instead of the O(n^2) of a tableau or the O(m^2) of an explicit
// inverse (this solver's first form, which a 400-unknown pyramid block made the bulk of a landing's cost).
//
// The solver's entry points are at the top; one Lemke path (LemkeSolver::Run) is below them, one function per phase.
// The warm-start check that runs before any pivoting state exists is lcp_warm.cpp.
//
// Determinism: every loop runs in a fixed index order; the only reductions are sums in that order; nothing reads
// the clock. The lexicographic rule compares the rows of [value | d value / d b_0 ... d value / d b_{n-1}]
// divided by the pivot entry — the rows of B^-1 [b | I] of the full tableau — so it is the classical
// anti-cycling rule, evaluated lazily (one solve per block row it reaches) and only for candidates whose ratios tie.
#include <unison/lcp.h>

#include "lcp_warm.h"
#include "lcp_workspace.h"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <utility>

namespace unison {

using lcp_detail::optionsInRange;
using lcp_detail::sortedUnique;
using lcp_detail::trySparseBasis;
using lcp_detail::trySparseWarmStart;

namespace {

// Zobrist keys of the basis: the hash of a basis is the XOR of the keys of its column variables (basic z's and z0)
// and of its block rows (nonbasic w's), so one pivot updates it with two XORs.
std::uint64_t basisKey(int index, bool isRow) {
    std::uint64_t x = (std::uint64_t(index) << 1 | (isRow ? 1u : 0u)) + 0x9e3779b97f4a7c15ull;  // splitmix64
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

}  // namespace

LemkeSolver::LemkeSolver() = default;
LemkeSolver::~LemkeSolver() = default;
LemkeSolver::LemkeSolver(LemkeSolver&&) noexcept = default;
LemkeSolver& LemkeSolver::operator=(LemkeSolver&&) noexcept = default;

LemkeSolver::Workspace& LemkeSolver::workspace() {
    if (!mWorkspace) mWorkspace = std::make_unique<Workspace>();
    return *mWorkspace;
}

LcpResult LemkeSolver::solve(const Lcp& problem, const LcpOptions& options) {
    if (problem.n < 0 || problem.A.size() != std::size_t(problem.n) * std::size_t(problem.n) ||
        problem.b.size() != std::size_t(problem.n)) {
        LcpResult r;
        r.status = LcpStatus::invalid_input;
        r.message = "LCP sizes do not match: A must be n x n and b must have n entries";
        return r;
    }
    return solve(problem.n, problem.A.data(), problem.b.data(), options);
}

LcpResult LemkeSolver::solve(int n, const double* A, const double* b, const LcpOptions& options) {
    if (n < 0 || (n > 0 && (A == nullptr || b == nullptr))) {
        LcpResult result;
        result.message = "LCP size must be >= 0 with A and b given";
        return result;
    }
    Workspace& ws = workspace();
    ws.n = n;
    const long long bad = ws.loadDense(A);
    if (bad >= 0) {
        LcpResult result;
        result.message = "A has a non-finite entry at (" + std::to_string(bad / n) + ", " + std::to_string(bad % n) + ")";
        return result;
    }
    return runRobust(ws, b, options);
}

LcpResult LemkeSolver::solve(const SparseLcp& problem, const LcpOptions& options) {
    SparseLcp copy = problem;  // the solver keeps its own compressed rows either way
    return solve(std::move(copy), options);
}

LcpResult LemkeSolver::solve(SparseLcp&& problem, const LcpOptions& options) {
    LcpResult result;
    if (problem.n < 0 || problem.b.size() != std::size_t(problem.n)) {
        result.message = "LCP sizes do not match: b must have n entries";
        return result;
    }
    Workspace& ws = workspace();
    ws.n = problem.n;
    result.message = ws.takeSparse(problem);
    if (!result.message.empty()) return result;
    ws.bStore.swap(problem.b);
    return runRobust(ws, ws.bStore.data(), options);
}

LcpResult LemkeSolver::checkGuess(SparseLcp&& guessBlock, const LcpOptions& options, const Product& product) {
    Workspace& ws = workspace();
    ws.product = &product;
    LcpResult result = checkGuess(std::move(guessBlock), options);
    ws.product = nullptr;
    return result;
}

LcpResult LemkeSolver::checkGuess(SparseLcp&& guessColumns, const LcpOptions& options) {
    LcpResult result;
    result.status = LcpStatus::pivot_limit;
    const int n = guessColumns.n;
    if (n <= 0 || guessColumns.b.size() != std::size_t(n) || !(guessColumns.maxAbs >= 0.0) || !options.warmBasis ||
        options.warmBasis->empty() || !optionsInRange(options)) {  // solve() reports what is wrong
        result.message = "checkGuess needs a guess and a vouched-for matrix";
        return result;
    }
    const std::vector<int> guess = sortedUnique(*options.warmBasis);
    if (guess.front() < 0 || guess.back() >= n) {
        result.message = "guess out of range";
        return result;
    }
    Workspace& ws = workspace();
    ws.n = n;
    const std::string why = ws.takeSparse(guessColumns);
    if (!why.empty()) {
        result.message = why;
        return result;
    }
    ws.bStore.swap(guessColumns.b);
    // The same preparation as run() up to its warm-start check.
    const double* b = ws.bStore.data();
    if (ws.loadB(b) >= 0) {
        result.message = "b has a non-finite entry";
        return result;
    }
    const double scale = std::max({ws.aMax, ws.bMax, kTiny});
    result.z.assign(std::size_t(n), 0.0);
    result.w.assign(b, b + n);
    std::vector<int> corrected;
    ws.refusal.valid = false;
    if (trySparseBasis(ws, guess, options, scale, result, corrected)) return result;
    // Kept for the solve that follows on the full matrix (trySparseWarmStart), so it need not repeat this round.
    ws.refusal.valid = true;
    ws.refusal.guess = guess;
    ws.refusal.corrected.swap(corrected);
    ws.refusal.b.assign(b, b + n);
    ws.refusal.residualTolerance = options.residualTolerance;
    result.status = LcpStatus::pivot_limit;
    result.message = "the guess does not check out";
    return result;
}
// One call of run(): the state of a Lemke path and the phases it goes through, in the order execute() runs them —
// validate the input; try the warm guess without pivoting state; set the state up (cold, or from the guess); take
// a start that is already the answer; perturb b; choose the warm covering vector; then pivot: a direction, the
// ratio test, the leaving variable, the move along the direction and the basis exchange, until z0 leaves (the
// answer with the true b, continued with smaller perturbations when it misses the tolerance), a ray, a cap or a
// cycle (a restart).
struct LemkeSolver::Run {
    Run(LemkeSolver& solverIn, Workspace& wsIn, const double* bIn, const LcpOptions& optionsIn, int restarts)
        : solver(solverIn), ws(wsIn), b(bIn), options(optionsIn), restartsLeft(restarts), n(wsIn.n),
          nn(std::size_t(wsIn.n)) {}

    LcpResult execute();

private:
    /// What the ratio test found besides its candidates (ws.tied) and needs again when there is none.
    struct RatioTest {
        bool z0Tied = false;
        double zeroY = 0.0, zeroW = 0.0;
    };

    LcpResult finishWith(LcpStatus s, const char* msg);
    void resetPivotingState();
    void installWarmBasis();
    LcpResult assembleSolution();
    bool startIsAnswer() const;
    void perturbB();
    void warmCoveringVector();
    LcpResult pivot();
    LcpResult restart(bool wandered);
    LcpResult complementary();
    void direction(int m);
    RatioTest ratioTest(int m);
    LcpResult noLeavingVariable(int m, const RatioTest& test);
    Candidate chooseLeaving(const RatioTest& test) const;
    void move(int m, double theta, double theta2);
    void exchange(int m, const Candidate& leave);
    void refactorIfDue();

    LemkeSolver& solver;
    Workspace& ws;
    const double* b;
    const LcpOptions& options;
    int restartsLeft;
    int n;
    std::size_t nn;
    LcpResult result;
    int maxPivots = 0;
    double scale = 0.0;
    std::vector<int> guess;
    bool inRange = false;
    bool warm = false;       // pivoting starts from the guess
    bool perturbed = false;  // pivoting runs on b + delta max|b| p
    std::uint64_t basisHash = 0;
    std::set<std::uint64_t> seenBases;
    int warmCap = 0;
    int enterVar = 0;          // a column variable (z_e, or z0 = n) or a slack w_e leaving the block rows
    bool enterIsColumn = true;
    bool startStep = true;     // the first pivot: z0 enters, the most negative basic value leaves
    int sinceRefactor = 0;
};

LcpResult LemkeSolver::run(Workspace& ws, const double* b, const LcpOptions& options, int restartsLeft) {
    return Run(*this, ws, b, options, restartsLeft).execute();
}

LcpResult LemkeSolver::Run::execute() {
    ws.m = 0;
    ws.basicEntries = 0;
    const int badB = ws.loadB(b);
    if (badB >= 0) {
        result.message = "b has a non-finite entry at " + std::to_string(badB);
        return result;
    }
    if (!optionsInRange(options)) {
        result.message = "LCP options out of range: need 0 <= pivotTolerance < 1, residualTolerance >= 0, "
                         "0 <= degeneracyPerturbation <= 1e-2, maxPivots >= 0, 0 <= blockPivotRounds <= 8";
        return result;
    }
    maxPivots = options.maxPivots > 0 ? options.maxPivots : LcpOptions::kDefaultMaxPivots;
    scale = std::max({ws.aMax, ws.bMax, kTiny});
    result.z.assign(nn, 0.0);
    result.w.assign(b, b + n);
    if (n == 0) return finishWith(LcpStatus::solved, nullptr);

    ws.aMax = std::max(ws.aMax, 1.0);  // d = 1 is part of the column space

    // A guess that checks out needs none of the pivoting state, so it is tried before that state is set up.
    if (options.warmBasis && !options.warmBasis->empty()) {
        guess = sortedUnique(*options.warmBasis);
        inRange = guess.front() >= 0 && guess.back() < n;
        if (inRange && trySparseWarmStart(ws, guess, options, scale, result)) return result;
    }
    ws.refusal.valid = false;  // a refused check is for the solve right after it only
    resetPivotingState();
    installWarmBasis();
    result.warmStarted = warm;
    ws.ensureColumns();
    if (startIsAnswer()) return assembleSolution();
    perturbed = options.degeneracyPerturbation > 0.0;
    if (perturbed) perturbB();
    if (warm) warmCoveringVector();
    return pivot();
}

LcpResult LemkeSolver::Run::finishWith(LcpStatus s, const char* msg) {
    result.status = s;
    if (msg) result.message = msg;
    result.residual = complementarityResidual(result.z, result.w);
    result.scaledResidual = result.residual / scale;
    return result;
}

// The all-slack basis: no block, every w basic at its b.
void LemkeSolver::Run::resetPivotingState() {
    ws.rowIdx.assign(nn + 1, -1);
    ws.colVar.assign(nn + 1, -1);
    ws.posRow.assign(nn, -1);
    ws.posCol.assign(nn + 1, -1);
    ws.zval.assign(nn + 1, 0.0);
    ws.wval.assign(b, b + n);
    // p_i = 1 + frac((i + 1) * golden ratio): positive, pairwise distinct, and generic enough that no ratio tie of
    // the unperturbed problem survives in the eps coefficients (the classical lexicographic rule backs it up).
    ws.p.resize(nn);
    for (std::size_t i = 0; i < nn; ++i) {
        const double t = double(i + 1) * 0.6180339887498949;
        ws.p[i] = 1.0 + (t - std::floor(t));
    }
    ws.zval2.assign(nn + 1, 0.0);
    ws.wval2 = ws.p;
    ws.dy.assign(nn + 1, 0.0);
    ws.dw.assign(nn, 0.0);
    ws.d.assign(nn, 1.0);
    ws.resetBlock();
}

// The guess as the block (rows = columns = the guessed z's) when it is in range and its block factorises.
void LemkeSolver::Run::installWarmBasis() {
    if (!options.warmBasis || options.warmBasis->empty()) return;
    ws.ensureColumns();
    if (!inRange) return;
    ws.m = int(guess.size());
    for (int q = 0; q < ws.m; ++q) {
        const int j = guess[std::size_t(q)];
        ws.rowIdx[std::size_t(q)] = j;
        ws.posRow[std::size_t(j)] = q;
        ws.colVar[std::size_t(q)] = j;
        ws.posCol[std::size_t(j)] = q;
        ws.basicEntries += ws.columnEntries(j);
    }
    if (ws.refactor()) {
        warm = true;
        ws.recomputeValues();
    } else {
        for (int q = 0; q < ws.m; ++q) {
            ws.posRow[std::size_t(ws.rowIdx[std::size_t(q)])] = -1;
            ws.posCol[std::size_t(ws.colVar[std::size_t(q)])] = -1;
        }
        ws.m = 0;
        ws.basicEntries = 0;
        ws.wval.assign(b, b + n);
        ws.wval2 = ws.p;
    }
}

// The answer of a complementary block (rows == columns as index sets, no z0), with the true b.
LcpResult LemkeSolver::Run::assembleSolution() {
    std::fill(result.z.begin(), result.z.end(), 0.0);
    for (int q = 0; q < ws.m; ++q) result.z[std::size_t(ws.colVar[std::size_t(q)])] = ws.zval[std::size_t(q)];
    auto recomputeW = [&]() {
        std::copy(b, b + n, result.w.begin());
        for (int q = 0; q < ws.m; ++q) ws.addColumn(ws.colVar[std::size_t(q)], result.z[std::size_t(ws.colVar[std::size_t(q)])], result.w.data());
    };
    recomputeW();
    // One step of iterative refinement on the final block: z_alpha -= B^-1 w_R (w_R should be exactly 0).
    ws.blockSolve(result.w.data(), ws.dy.data());
    for (int q = 0; q < ws.m; ++q) result.z[std::size_t(ws.colVar[std::size_t(q)])] -= ws.dy[std::size_t(q)];
    // Degenerate basic z's come out as +-1e-17: an impulse must never be negative, so rounding-level negatives
    // become exact zeros (larger ones stay and fail the residual check below).
    double zMax = 0.0;
    for (double z : result.z) zMax = std::max(zMax, std::fabs(z));
    for (double& z : result.z) {
        if (z < 0.0 && z >= -1e-12 * zMax) z = 0.0;
    }
    recomputeW();
    result.basis.clear();
    for (int q = 0; q < ws.m; ++q) result.basis.push_back(ws.colVar[std::size_t(q)]);
    std::sort(result.basis.begin(), result.basis.end());
    result.residual = complementarityResidual(result.z, result.w);
    result.scaledResidual = result.residual / scale;
    if (result.scaledResidual <= options.residualTolerance) {
        result.status = LcpStatus::solved;
    } else {
        result.status = LcpStatus::numerical_failure;
        result.message = "Lemke terminated but the complementarity residual " + std::to_string(result.scaledResidual) +
                         " (scaled) exceeds the tolerance";
    }
    return result;
}

// Is the start basis already the answer? (all basic values >= 0, up to the rounding the ratio test ignores)
bool LemkeSolver::Run::startIsAnswer() const {
    double zMax = 0.0;
    for (int q = 0; q < ws.m; ++q) zMax = std::max(zMax, std::fabs(ws.zval[std::size_t(q)]));
    const double zeroY = 1e-13 * std::max(zMax, kTiny);
    const double zeroW = 1e-13 * (ws.bMax + ws.aMax * zMax);
    bool feasible = true;
    for (int q = 0; q < ws.m && feasible; ++q) feasible = ws.zval[std::size_t(q)] >= -zeroY;
    for (int i = 0; i < n && feasible; ++i) feasible = ws.posRow[std::size_t(i)] >= 0 || ws.wval[std::size_t(i)] >= -zeroW;
    return feasible;
}

// Pivot on b + delta max|b| p instead of b (p_i in [1, 2), the generic vector of the tie rule). Settled contact
// scenes are massively degenerate (b_i = 0 on every resting contact; friction rows come in exact +t/-t pairs), and
// in floating point even a sound tie rule can cycle there. A real, if tiny, perturbation makes the ties real
// differences. Raising b never makes a feasible problem infeasible (z* stays feasible). The answer is then
// recomputed from the final basis with the true b (assembleSolution), and checked like every answer.
void LemkeSolver::Run::perturbB() {
    ws.bPerturbed.resize(nn);
    for (std::size_t i = 0; i < nn; ++i) ws.bPerturbed[i] = b[i] + options.degeneracyPerturbation * ws.bMax * ws.p[i];
    ws.b = ws.bPerturbed.data();
    if (ws.m > 0) {
        ws.recomputeValues();
    } else {
        ws.wval.assign(ws.b, ws.b + n);
    }
}

// Covering vector chosen so that basic variable v rises at rate r(v) with z0: d_alpha = -A_{alpha,alpha} r and
// d_i = r_i - A_{i,alpha} r for the basic w's (LcpOptions::WarmCovering gives r).
void LemkeSolver::Run::warmCoveringVector() {
    const bool onlyViolated = options.warmCovering == LcpOptions::WarmCovering::violated;
    auto rate = [&](double v) { return !onlyViolated || v < 0.0 ? 1.0 : 0.0; };
    std::vector<double> Ar(nn, 0.0);
    for (int q = 0; q < ws.m; ++q) ws.addColumn(ws.colVar[std::size_t(q)], rate(ws.zval[std::size_t(q)]), Ar.data());
    for (int i = 0; i < n; ++i)
        ws.d[std::size_t(i)] = ws.posRow[std::size_t(i)] >= 0 ? -Ar[std::size_t(i)] : rate(ws.wval[std::size_t(i)]) - Ar[std::size_t(i)];
    for (int i = 0; i < n; ++i) ws.aMax = std::max(ws.aMax, std::fabs(ws.d[std::size_t(i)]));
}

// The pivoting loop.
LcpResult LemkeSolver::Run::pivot() {
    // Lemke's path never revisits a basis, so a repeated basis means rounding has made the pivot path cycle (seen
    // on landing piles whose friction rows tie by the hundred). The basis hashes seen so far catch that within one
    // turn of the cycle instead of at the pivot cap.
    for (int q = 0; q < ws.m; ++q) basisHash ^= basisKey(ws.colVar[std::size_t(q)], false) ^ basisKey(ws.rowIdx[std::size_t(q)], true);
    seenBases.insert(basisHash);
    // A warm path gets at most twice as many pivots as the guess has basic unknowns (and at least 100, at most a
    // quarter of the budget): a path that needs more is wandering, not repairing the guess, and a cold start does
    // better.
    warmCap = std::max(100, std::min(maxPivots / 4, 2 * ws.m));
    enterVar = n;  // z0 first
    enterIsColumn = true;
    startStep = true;
    sinceRefactor = 0;
    for (;;) {
        const std::uint64_t cost = ws.pivotCost();
        if (result.pivots >= maxPivots) return finishWith(LcpStatus::pivot_limit, lcp_detail::kPivotCapMessage);
        // A warm path that wanders (the special covering vector can lead far from the guess) is cut off at warmCap;
        // the rest of the budget goes to a cold start.
        if (warm && result.pivots >= warmCap) return restart(true);
        if (options.maxWork && result.work + cost > options.maxWork) return finishWith(LcpStatus::pivot_limit, lcp_detail::kWorkBudgetMessage);
        const int m = ws.m;
        direction(m);
        const RatioTest test = ratioTest(m);
        if (ws.tied.empty()) return noLeavingVariable(m, test);
        const Candidate leave = chooseLeaving(test);
        move(m, leave.ratio, leave.ratio2);
        exchange(m, leave);
        ++result.pivots;
        result.work += cost;
        ++sinceRefactor;
        startStep = false;
        // The entering variable joins (a column) or its row leaves the block; the leaving one the other way round.
        basisHash ^= basisKey(enterVar, !enterIsColumn) ^ basisKey(leave.isColumn ? leave.var : leave.pos, !leave.isColumn);
        if (!seenBases.insert(basisHash).second) return restart(false);

        if (leave.isColumn && leave.var == n) return complementary();  // z0 left: complementary basis
        // The complement of the leaving variable enters next.
        enterVar = leave.var;
        enterIsColumn = !leave.isColumn;
        refactorIfDue();
    }
}

// Cycling (or a wandering warm path): restart with the remaining budget, at most `restartsLeft` times: cold from a
// warm run, else with a 10x larger perturbation, at most 1e-2 (separating the ties that rounding confused).
LcpResult LemkeSolver::Run::restart(bool wandered) {
    if (restartsLeft <= 0)
        return finishWith(LcpStatus::pivot_limit, wandered ? lcp_detail::kPivotCapMessage : "the pivot path cycles (rounding on a degenerate problem)");
    LcpOptions retry = options;
    retry.warmBasis = nullptr;
    retry.degeneracyPerturbation =
        warm ? options.degeneracyPerturbation : std::min(1e-2, std::max(options.degeneracyPerturbation, 1e-8) * 10.0);
    retry.maxPivots = std::max(1, maxPivots - result.pivots);
    if (options.maxWork) retry.maxWork = options.maxWork > result.work ? options.maxWork - result.work : 1;
    LcpResult r = solver.run(ws, b, retry, restartsLeft - 1);
    r.pivots += result.pivots;
    r.work += result.work;
    ++r.restarts;
    return r;
}

// The block is complementary (z0 left, or a warm start needed no pivot at all): the answer with the true b, and the
// continuation when the perturbation it was found under leaves it short of the tolerance.
LcpResult LemkeSolver::Run::complementary() {
    assembleSolution();
    if (result.status == LcpStatus::numerical_failure && perturbed) {
        // The perturbed problem's basis is not exactly right for the true b: continue from it with a 10x smaller
        // perturbation (still breaking ties), down to none below 1e-9. A continuation is a local repair: it never
        // restarts and gets at most max(100, k / 2) pivots (a cycle or a longer path ends it, and this answer
        // stands); unbounded, it could spend thousands of pivots to improve a residual of 3e-9.
        LcpOptions exact = options;
        exact.degeneracyPerturbation = options.degeneracyPerturbation > 1e-9 ? options.degeneracyPerturbation * 0.1 : 0.0;
        exact.maxPivots = std::max(1, std::min(maxPivots - result.pivots, std::max(100, ws.m / 2)));
        if (options.maxWork) exact.maxWork = options.maxWork > result.work ? options.maxWork - result.work : 1;
        const std::vector<int> basis = result.basis;
        exact.warmBasis = &basis;
        LcpResult r = solver.run(ws, b, exact, 0);
        r.pivots += result.pivots;
        r.work += result.work;
        if (r.status != LcpStatus::solved && !(r.status == LcpStatus::numerical_failure && r.scaledResidual <= result.scaledResidual)) {
            // The continuation did not do better (it can cycle on the ties the larger perturbation had separated):
            // return this answer, marked numerical_failure with its residual, for the caller to judge.
            result.pivots = r.pivots;
            result.work = r.work;
            result.restarts = r.restarts;
            return result;
        }
        return r;
    }
    return result;
}

// Direction of the basic variables per unit of the entering variable: dy = -B^-1 (its column on the block rows) for
// a column variable, dy = B^-1 e_p when w of block row p enters; and dw for the basic w's.
void LemkeSolver::Run::direction(int m) {
    if (enterIsColumn) {
        if (enterVar < n) {
            for (int k = ws.colStart[std::size_t(enterVar)]; k < ws.colStart[std::size_t(enterVar) + 1]; ++k)
                ws.rhs[std::size_t(ws.colRow[std::size_t(k)])] = ws.colVal[std::size_t(k)];
            ws.blockSolve(ws.rhs.data(), ws.dy.data());
            for (int k = ws.colStart[std::size_t(enterVar)]; k < ws.colStart[std::size_t(enterVar) + 1]; ++k)
                ws.rhs[std::size_t(ws.colRow[std::size_t(k)])] = 0.0;
        } else {
            ws.blockSolve(ws.d.data(), ws.dy.data());
        }
        for (int q = 0; q < m; ++q) ws.dy[std::size_t(q)] = -ws.dy[std::size_t(q)];
        ws.computeDw(enterVar);
    } else {
        ws.rhs[std::size_t(enterVar)] = 1.0;
        ws.blockSolve(ws.rhs.data(), ws.dy.data());
        ws.rhs[std::size_t(enterVar)] = 0.0;
        ws.computeDw(-1);
    }
}

// The ratio test: the candidates to leave the basis with the smallest ratio (the start step: the largest, so that
// every basic value becomes >= 0) into ws.tied.
LemkeSolver::Run::RatioTest LemkeSolver::Run::ratioTest(int m) {
    double yMax = 0.0, zMax = 0.0;
    for (int q = 0; q < m; ++q) {
        yMax = std::max(yMax, std::fabs(ws.dy[std::size_t(q)]));
        zMax = std::max(zMax, std::fabs(ws.zval[std::size_t(q)]));
    }
    double enterMax = 0.0;
    if (enterIsColumn) {
        if (enterVar < n) {
            for (int k = ws.colStart[std::size_t(enterVar)]; k < ws.colStart[std::size_t(enterVar) + 1]; ++k)
                enterMax = std::max(enterMax, std::fabs(ws.colVal[std::size_t(k)]));
        } else {
            for (int i = 0; i < n; ++i) enterMax = std::max(enterMax, std::fabs(ws.d[std::size_t(i)]));
        }
    }
    const double tolY = options.pivotTolerance * yMax;
    const double tolW = options.pivotTolerance * (yMax * ws.aMax + enterMax);
    RatioTest test;
    test.zeroY = 1e-13 * std::max(zMax, kTiny);
    test.zeroW = 1e-13 * (ws.bMax + ws.aMax * zMax);
    const double zeroY = test.zeroY, zeroW = test.zeroW;
    std::vector<Candidate>& cands = ws.cands;
    std::vector<Candidate>& tied = ws.tied;
    // The start test (once per path) collects every candidate; the min test of the pivots that follow scans twice
    // without storing them: once for the smallest ratio, once for the ties. The ratio is computed only where it can
    // matter: v > limit * -dv means v / -dv > limit (the 1 + 1e-9 margin covers the rounding of both sides), so the
    // division is skipped. Same candidates, same ratios, same order as collecting them all.
    double best = std::numeric_limits<double>::infinity();
    tied.clear();
    if (startStep) {
        cands.clear();
        // z0 rises until every basic value is >= 0: the leaving variable is the one that needs the most.
        for (int q = 0; q < m; ++q) {
            const double v = ws.zval[std::size_t(q)], dv = ws.dy[std::size_t(q)];
            if (v < -zeroY && dv > tolY)
                cands.push_back({true, q, -v / dv, -ws.zval2[std::size_t(q)] / dv, dv, ws.colVar[std::size_t(q)]});
        }
        for (int i = 0; i < n; ++i) {
            if (ws.posRow[std::size_t(i)] >= 0) continue;
            const double v = ws.wval[std::size_t(i)], dv = ws.dw[std::size_t(i)];
            if (v < -zeroW && dv > tolW) cands.push_back({false, i, -v / dv, -ws.wval2[std::size_t(i)] / dv, dv, i});
        }
        if (!cands.empty()) {
            best = cands[0].ratio;
            for (const Candidate& c : cands) best = std::max(best, c.ratio);
            const double tieTol = 1e-12 * best;
            for (const Candidate& c : cands) {
                if (std::fabs(c.ratio - best) <= tieTol) tied.push_back(c);
            }
        }
        return test;
    }
    constexpr double kMargin = 1.0 + 1e-9;
    const double* const zv = ws.zval.data();
    const double* const dyv = ws.dy.data();
    const double* const wv = ws.wval.data();
    const double* const dwv = ws.dw.data();
    const int* const posRow = ws.posRow.data();
    auto zValue = [&](int q) { return zv[q] > zeroY ? zv[q] : 0.0; };
    auto wValue = [&](int i) { return wv[i] > zeroW ? wv[i] : 0.0; };
    for (int q = 0; q < m; ++q) {
        const double dv = dyv[q];
        if (dv < -tolY) {
            const double v = zValue(q);
            if (v <= best * -dv * kMargin) best = std::min(best, v / -dv);
        }
    }
    for (int i = 0; i < n; ++i) {
        const double dv = dwv[i];
        if (posRow[i] < 0 && dv < -tolW) {
            const double v = wValue(i);
            if (v <= best * -dv * kMargin) best = std::min(best, v / -dv);
        }
    }
    const double tieTol = 1e-12 * best;
    const double limit = best + tieTol;
    for (int q = 0; q < m; ++q) {
        const double dv = dyv[q];
        if (dv < -tolY) {
            const double v = zValue(q);
            if (v <= limit * -dv * kMargin && std::fabs(v / -dv - best) <= tieTol) {
                tied.push_back({true, q, v / -dv, ws.zval2[std::size_t(q)] / -dv, dv, ws.colVar[std::size_t(q)]});
                test.z0Tied = test.z0Tied || ws.colVar[std::size_t(q)] == n;
            }
        }
    }
    for (int i = 0; i < n; ++i) {
        const double dv = dwv[i];
        if (posRow[i] < 0 && dv < -tolW) {
            const double v = wValue(i);
            if (v <= limit * -dv * kMargin && std::fabs(v / -dv - best) <= tieTol)
                tied.push_back({false, i, v / -dv, ws.wval2[std::size_t(i)] / -dv, dv, i});
        }
    }
    return test;
}

// No candidate leaves: a start that needs no pivot, a warm guess z0 cannot repair, or a secondary ray.
LcpResult LemkeSolver::Run::noLeavingVariable(int m, const RatioTest& test) {
    if (startStep) {
        // No basic value is below zero: the warm basis is already complementary and feasible for the perturbed b
        // (the perturbation lifted what the true b left a little short, e.g. a rocking box's tangential creep at the
        // dead zone). Take it as found, as if z0 had left, rather than start cold.
        bool feasible = true;
        for (int q = 0; q < m && feasible; ++q) feasible = ws.zval[std::size_t(q)] >= -test.zeroY;
        for (int i = 0; i < n && feasible; ++i) feasible = ws.posRow[std::size_t(i)] >= 0 || ws.wval[std::size_t(i)] >= -test.zeroW;
        if (feasible && ws.posCol[std::size_t(n)] < 0) return complementary();
        // The warm basis could not be repaired by z0 along this covering vector: start cold.
        LcpOptions cold = options;
        cold.warmBasis = nullptr;
        LcpResult r = solver.run(ws, b, cold, restartsLeft);
        r.pivots += result.pivots;
        r.work += result.work;
        return r;
    }
    // A warm path has no termination guarantee (its covering vector is not the classical one): its ray proves
    // nothing, so the rest of the budget goes to a cold start, which has the guarantee.
    if (warm) return restart(true);
    return finishWith(LcpStatus::infeasible, "secondary ray: Lemke found no solution (the LCP may have none)");
}

// The leaving variable among the tied candidates: z0 whenever it ties (after the start step); then the eps
// coefficient of the perturbed ratio; then the classical lexicographic rows (Workspace::breakTie).
Candidate LemkeSolver::Run::chooseLeaving(const RatioTest& test) const {
    const std::vector<Candidate>& tied = ws.tied;
    Candidate leave = tied[0];
    if (test.z0Tied && !startStep) {
        for (const Candidate& c : tied) {
            if (c.isColumn && c.var == n) leave = c;
        }
    } else if (tied.size() > 1) {
        // The eps coefficients grow along a long degenerate path and can overflow (a 40-row pyramid's 4760-contact
        // fallback LCP reached inf and NaN after a few hundred pivots): where any is not finite the key says nothing,
        // and the lexicographic rule decides among all the ties.
        bool finite2 = true;
        for (const Candidate& c : tied) finite2 = finite2 && std::isfinite(c.ratio2);
        std::vector<Candidate> tied2;
        if (finite2) {
            double best2 = tied[0].ratio2, mag2 = 0.0;
            for (const Candidate& c : tied) {
                best2 = startStep ? std::max(best2, c.ratio2) : std::min(best2, c.ratio2);
                mag2 = std::max(mag2, std::fabs(c.ratio2));
            }
            for (const Candidate& c : tied) {
                if (std::fabs(c.ratio2 - best2) <= 1e-9 * mag2) tied2.push_back(c);
            }
        }
        if (tied2.empty()) tied2 = tied;
        leave = tied2.size() == 1 ? tied2[0] : tied2[std::size_t(ws.breakTie(tied2, startStep))];
    }
    return leave;
}

// Move along the direction: every basic value changes by theta times its rate.
void LemkeSolver::Run::move(int m, double theta, double theta2) {
    for (int q = 0; q < m; ++q) {
        ws.zval[std::size_t(q)] += theta * ws.dy[std::size_t(q)];
        ws.zval2[std::size_t(q)] += theta2 * ws.dy[std::size_t(q)];
    }
    for (int i = 0; i < n; ++i) {
        if (ws.posRow[std::size_t(i)] < 0) {
            ws.wval[std::size_t(i)] += theta * ws.dw[std::size_t(i)];
            ws.wval2[std::size_t(i)] += theta2 * ws.dw[std::size_t(i)];
        }
    }
}

// Basis exchange: the border of the block changes by one column and one row (Workspace::pivotBorder); the block's
// bookkeeping changes in one of four ways.
void LemkeSolver::Run::exchange(int m, const Candidate& leave) {
    const double theta = leave.ratio;
    const double theta2 = leave.ratio2;
    ws.pivotBorder(enterIsColumn, enterVar, leave.isColumn, leave.isColumn ? leave.var : leave.pos);
    if (enterIsColumn && !leave.isColumn) {
        // (1) grow: row i joins the block rows, the entering column joins the block columns.
        const int i = leave.pos;
        ws.rowIdx[std::size_t(m)] = i;
        ws.posRow[std::size_t(i)] = m;
        ws.colVar[std::size_t(m)] = enterVar;
        ws.posCol[std::size_t(enterVar)] = m;
        ws.basicEntries += ws.columnEntries(enterVar);
        ws.zval[std::size_t(m)] = theta;
        ws.zval2[std::size_t(m)] = theta2;
        ws.wval[std::size_t(i)] = 0.0;
        ws.m = m + 1;
    } else if (enterIsColumn && leave.isColumn) {
        // (2) column swap at block position qL.
        const int qL = leave.pos;
        ws.posCol[std::size_t(leave.var)] = -1;
        ws.colVar[std::size_t(qL)] = enterVar;
        ws.posCol[std::size_t(enterVar)] = qL;
        ws.basicEntries += ws.columnEntries(enterVar) - ws.columnEntries(leave.var);
        ws.zval[std::size_t(qL)] = theta;
        ws.zval2[std::size_t(qL)] = theta2;
    } else if (!enterIsColumn && !leave.isColumn) {
        // (3) row swap: row e leaves the block rows (w_e becomes basic), row i takes its place.
        const int i = leave.pos;
        const int pe = ws.posRow[std::size_t(enterVar)];
        ws.posRow[std::size_t(enterVar)] = -1;
        ws.wval[std::size_t(enterVar)] = theta;
        ws.wval2[std::size_t(enterVar)] = theta2;
        ws.rowIdx[std::size_t(pe)] = i;
        ws.posRow[std::size_t(i)] = pe;
        ws.wval[std::size_t(i)] = 0.0;
    } else {
        // (4) shrink: row e and the leaving column leave the block; the last row and column move into the holes.
        const int qL = leave.pos;
        const int pe = ws.posRow[std::size_t(enterVar)];
        const int lastQ = m - 1, lastP = m - 1;
        if (qL != lastQ) {
            ws.colVar[std::size_t(qL)] = ws.colVar[std::size_t(lastQ)];
            ws.posCol[std::size_t(ws.colVar[std::size_t(qL)])] = qL;
            ws.zval[std::size_t(qL)] = ws.zval[std::size_t(lastQ)];
            ws.zval2[std::size_t(qL)] = ws.zval2[std::size_t(lastQ)];
        }
        if (pe != lastP) {
            ws.rowIdx[std::size_t(pe)] = ws.rowIdx[std::size_t(lastP)];
            ws.posRow[std::size_t(ws.rowIdx[std::size_t(pe)])] = pe;
        }
        ws.posCol[std::size_t(leave.var)] = -1;
        ws.basicEntries -= ws.columnEntries(leave.var);
        ws.posRow[std::size_t(enterVar)] = -1;
        ws.wval[std::size_t(enterVar)] = theta;
        ws.wval2[std::size_t(enterVar)] = theta2;
        ws.m = m - 1;
    }
}

// Fold the border into a fresh B0 when it has grown past its limit, or after many updates (rank-one updates of
// Sinv accumulate rounding even while the border stays small). A failed refactorisation keeps the current
// representation and raises the limit, so it is not retried every pivot.
void LemkeSolver::Run::refactorIfDue() {
    if (ws.qb > ws.maxBorder() || sinceRefactor >= std::max(256, 4 * ws.m)) {
        sinceRefactor = 0;
        if (ws.refactor()) {
            ws.recomputeValues();
        } else {
            ws.borderLimit = 2 * ws.qb;
        }
    }
}

}  // namespace unison
