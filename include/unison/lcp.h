// unison/lcp.h — the linear complementarity problem and Unison's bounded, deterministic Lemke solver.
//
// Owns: the LCP data type (dense A, b), solver options, the explicit outcome of a solve, and LemkeSolver, a
// reusable workspace. Problem (the paper's eqs. (12)-(14); b is "q" in textbooks):
//     find z >= 0 with w = A z + b >= 0 and z.w = 0.
// Contract (docs/solver.md):
//   - the pivot sequence is a pure function of (A, b, options, warm basis): lexicographic minimum-ratio test,
//     z0 leaves first on ties, remaining ties by lowest index; entries below a relative tolerance never pivot;
//   - every solve ends with an explicit status, and `solved` is only reported after the complementarity
//     residual of the returned (z, w) has been checked;
//   - work is counted in deterministic units, never wall-clock time, so a frame budget gives the same answer on
//     every machine;
//   - a run that fails (not by the caller's caps) continues on a regularised robust path; solves that succeed
//     never reach it.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace unison {

/// A dense LCP: A is n x n, row-major (A[i*n + j]); b has n entries.
struct Lcp {
    int n = 0;
    std::vector<double> A;  ///< (n x n), row-major
    std::vector<double> b;  ///< (n)

    Lcp() = default;
    explicit Lcp(int size) : n(size), A(std::size_t(size) * std::size_t(size), 0.0), b(std::size_t(size), 0.0) {}
    double& at(int i, int j) { return A[std::size_t(i) * std::size_t(n) + std::size_t(j)]; }
    double at(int i, int j) const { return A[std::size_t(i) * std::size_t(n) + std::size_t(j)]; }
};

/// A sparse LCP in compressed rows: row i holds A(i, cols[k]) = vals[k] for k in [rowStart[i], rowStart[i+1]),
/// columns strictly increasing within a row. Contact LCPs are sparse (nodes couple only through shared bodies);
/// this form skips the O(n^2) scan of a dense matrix.
struct SparseLcp {
    int n = 0;
    std::vector<int> rowStart;  ///< (n + 1)
    std::vector<int> cols;      ///< (nnz)
    std::vector<double> vals;   ///< (nnz)
    std::vector<double> b;      ///< (n)
    /// Set (>= 0) only by an assembler that built the rows itself and vouches for them: columns strictly increasing
    /// and in range, every value finite, and maxAbs the scale of A for the solver's tolerances in place of
    /// max |A_ij|: either that, or a value an assembler can compute without building all of A (the contact
    /// assemblers use the largest of the diagonal entries, the friction coefficients and 1, which for their
    /// matrices is max |A_ij| up to rounding). The solver then skips its O(nnz) check of A (it still checks sizes
    /// and b). Leave it at -1 for matrices built any other way.
    double maxAbs = -1.0;
    /// A hint from an assembler whose A is symmetric bit for bit except in a few rows and columns (the 3D friction
    /// LCP: its coupling block J M^-1 J^T is formed so, and only the friction slacks break the symmetry). A warm
    /// start then factorises a guessed block of more than 48 unknowns by LDL^T instead of LU. It changes answers
    /// only by rounding; a wrong hint costs time, never correctness (an asymmetric block falls back to the LU).
    bool symmetricHint = false;
};

/// The nonzeros of a dense LCP in compressed rows.
SparseLcp toSparse(const Lcp& lcp);

/// An LCP under assembly: entries (i, j, v) in the order they were added; entries with the same (i, j) are summed
/// in that order, so the dense and the sparse result hold bit-identical values.
struct LcpTriplets {
    int n = 0;
    std::vector<int> rows, cols;  ///< (entries)
    std::vector<double> vals;     ///< (entries)
    std::vector<double> b;        ///< (n)

    explicit LcpTriplets(int size = 0) : n(size), b(std::size_t(size), 0.0) {}
    void add(int i, int j, double v) {
        rows.push_back(i);
        cols.push_back(j);
        vals.push_back(v);
    }
    /// Dense form (n x n).
    Lcp toDense() const;
    /// Compressed rows; sums that are exactly zero are dropped, as a dense scan would skip them.
    SparseLcp toSparse() const;
};

/// How a solve ended. Only `solved` carries a usable z.
enum class LcpStatus {
    solved,            ///< z0 left the basis and the residual check passed
    infeasible,        ///< secondary ray: no solution exists, or Lemke cannot reach one from this start
    pivot_limit,       ///< the pivot cap or the work budget ran out first
    invalid_input,     ///< NaN/Inf entries, negative size or mismatched sizes
    numerical_failure  ///< an answer that failed the residual check even after refinement (z and its residual kept)
};

/// Stable lower-case name of a status ("solved", "infeasible", ...), as printed by the command-line tool.
const char* statusName(LcpStatus status);

struct LcpOptions {
    /// Hard cap on pivots for this call; 0 selects the default, kDefaultMaxPivots.
    int maxPivots = 0;
    /// Work budget in work units (see LcpResult::work); 0 means unlimited. Exceeding it ends with pivot_limit.
    std::uint64_t maxWork = 0;
    /// Relative pivot tolerance: a direction entry smaller than this times the largest entry of its kind never
    /// becomes a pivot. Entries below it are treated as exact zeros, which is what keeps degenerate contact
    /// problems (coplanar corners, singular A) on a consistent pivot path.
    double pivotTolerance = 1e-9;
    /// A solve is `solved` when max_i |min(z_i, w_i)| <= residualTolerance * max(max|A_ij|, max|b_i|).
    double residualTolerance = 1e-9;
    /// Degenerate problems are pivoted on b + degeneracyPerturbation * max|b| * p (p_i in [1, 2), fixed), then the
    /// answer is recomputed from the final basis with the true b and checked. 0 pivots on b itself.
    double degeneracyPerturbation = 1e-7;
    /// Optional warm start: the indices i whose z_i are guessed to be basic (positive) at the solution, e.g.
    /// the previous step's basis. Invalid or singular guesses fall back to a cold start; never an error.
    const std::vector<int>* warmBasis = nullptr;
    /// How a warm basis that is not already the answer is repaired: the covering vector of its Lemke path, given
    /// by the rate at which each basic unknown of the guess rises with z0.
    ///   uniform:  every basic unknown rises at rate 1 (the guess is lifted as a whole, then lowered back).
    ///   violated: only the unknowns the guess leaves negative rise; the others stay where the guess puts them.
    /// Neither has Lemke's termination guarantee (the classical d = 1 from the all-slack basis has it): a warm path
    /// that wanders or ends in a ray hands the rest of the budget to a cold start. Which is shorter depends on the
    /// problem family (docs/solver.md).
    enum class WarmCovering { uniform, violated };
    WarmCovering warmCovering = WarmCovering::uniform;
    /// Block principal pivoting rounds of a warm start (0 to 8): when the guess does not check out, drop its basic
    /// unknowns that came out negative, add the rows whose w came out negative, and check again, this many times
    /// before Lemke's path starts from the guess. Each round is one factorisation; they pay off when the basis
    /// changes by a few unknowns.
    int blockPivotRounds = 3;

    static constexpr int kDefaultMaxPivots = 100000;
};

struct LcpResult {
    LcpStatus status = LcpStatus::invalid_input;
    int pivots = 0;              ///< basis exchanges performed (warm-start factorisation counts as none)
    std::uint64_t work = 0;      ///< deterministic work units: sum over pivots of 2 nz(B0) + q (q + 2 k0) + nz(A_B)
                                 ///< + n + 1 (B0: the factorised block, k0 x k0, nz = k0^2 when dense; q: border size;
                                 ///< A_B: A's columns of the basic unknowns, which give the change of w)
    std::vector<double> z;       ///< (n) impulses / unknowns; meaningful when solved
    std::vector<double> w;       ///< (n) w = A z + b for the returned z
    double residual = 0.0;       ///< max_i |min(z_i, w_i)| of the returned (z, w)
    double scaledResidual = 0.0; ///< residual / max(max|A_ij|, max|b_i|)
    std::vector<int> basis;      ///< ascending indices with z_i basic at the end: feed back as a warm start
    bool warmStarted = false;    ///< true when the warm basis was used (not discarded for a cold start)
    int restarts = 0;            ///< times the pivot path cycled (a basis repeated) and the solve restarted
    std::string message;         ///< human-readable detail for invalid_input / failures
};

/// Complementarity residual max_i |min(z_i, w_i)| (0 for n = 0).
double complementarityResidual(const std::vector<double>& z, const std::vector<double>& w);

/// Lemke's complementary pivoting method with covering vector d = 1, run on a compact basis representation:
/// only the block of the basis that couples basic z's with the rows whose w is nonbasic is kept, as a sparse LU
/// of the block at its last refactorisation plus a small dense Schur complement for the rows and columns that
/// changed since, and A is walked through its sparsity pattern. For contact problems, where A = J M^-1 J^T
/// couples only contacts that share a body, a pivot costs a sparse solve, O(q (q + k)) for a border of q changes
/// on a k-unknown block, and O(nnz) for the basic w's, instead of the O(n^2) of a full tableau.
///
/// The object keeps its buffers between calls, so a game loop can reuse one solver per thread without
/// allocating once the buffers have grown to the largest island. It holds no other state: the result of solve()
/// depends only on its arguments (tested bit for bit).
class LemkeSolver {
public:
    LemkeSolver();
    ~LemkeSolver();
    LemkeSolver(LemkeSolver&&) noexcept;
    LemkeSolver& operator=(LemkeSolver&&) noexcept;

    LcpResult solve(const Lcp& problem, const LcpOptions& options = {});
    /// Same, on raw arrays: A is (n x n) row-major, b is (n).
    LcpResult solve(int n, const double* A, const double* b, const LcpOptions& options = {});
    /// Same, on a compressed-row matrix. Gives bit-identical results to the dense call on the same matrix.
    LcpResult solve(const SparseLcp& problem, const LcpOptions& options = {});
    /// Same, taking the problem's storage over instead of copying it (`problem` is left in an unspecified state).
    LcpResult solve(SparseLcp&& problem, const LcpOptions& options = {});

    /// Checks the guess `options.warmBasis` without pivoting, on a matrix that holds only the guess's columns:
    /// `guessColumns` has every row of A but only its entries in the guessed columns, and must carry the same
    /// maxAbs voucher as the full matrix would (see SparseLcp::maxAbs). An assembler can build that much of A far
    /// more cheaply than all of it. Returns `solved` exactly when solve() on the full matrix would accept the
    /// guess as it stands, with bit for bit the same answer. Otherwise the status is pivot_limit with no pivots
    /// done, and the caller solves the full problem (whose warm start may still correct the guess).
    /// `guessColumns` is taken over.
    LcpResult checkGuess(SparseLcp&& guessColumns, const LcpOptions& options);

    /// w = A z + b for every row, given z (n entries, zero outside the guess), written to w (n entries).
    using Product = std::function<void(const double* z, double* w)>;
    /// The same check from still less of A: `guessBlock` needs only the guessed rows' entries in the guessed
    /// columns (its other rows may be empty; maxAbs vouched for as above), and `product` gives w on every row
    /// (an assembler can form it as J (M^-1 (J^T z)) in O(nnz(J))). z comes from the same factorisation as in
    /// solve(), but w is the product's: answers agree with solve()'s up to the rounding of w, and a guess whose
    /// w is within rounding of the tolerances may be accepted or refused differently.
    LcpResult checkGuess(SparseLcp&& guessBlock, const LcpOptions& options, const Product& product);

    /// Per-solve buffers (private to the library; declared here so that the solver's helpers can name them).
    struct Workspace;

private:
    struct Run;  // one Lemke path by its phases (lcp.cpp)
    /// One Lemke run; `restartsLeft` bounds the restarts after a cycling pivot path.
    LcpResult run(Workspace& ws, const double* b, const LcpOptions& options, int restartsLeft = 2);
    /// A Lemke run, continued by the robust path (lcp_robust.cpp) when it does not end `solved`.
    LcpResult runRobust(Workspace& ws, const double* b, const LcpOptions& options);
    /// The robust path: proximal-point regularisation of the loaded problem after `failed`, its first run.
    LcpResult proximal(Workspace& ws, const double* b, const LcpOptions& options, LcpResult failed);
    Workspace& workspace();
    std::unique_ptr<Workspace> mWorkspace;  // buffers reused between solves; no state carries over
};

}  // namespace unison
