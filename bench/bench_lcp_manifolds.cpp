// bench/bench_lcp_manifolds.cpp — bench_lcp's second table: the contact LCPs assembled from Box2D 2.4.1's own
// manifolds of settled testbed pyramids (bench/box2d_manifold_lcps), solved by Unison's fast path, Unison's Lemke and
// Siconos' lexicographic Lemke, with the targets every island solver must meet on them:
//   double data  `solved` with scaled residual <= 1e-9 (A is PSD to rounding and b in its range: a solution exists);
//   float data   an answer with scaled residual <= 1e-6 (the data's noise level) and an honest status: `solved`
//                only within 1e-9, the reported residual equal to the recomputed one;
//   cold frictionless 20-row pyramid (n = 800) <= 2 ms.
// Residuals are recomputed here from (A, b, z). Siconos works on a dense n x 2(n + 1) tableau and is skipped above
// kSiconosMaxN unknowns.
#include "bench_lcp_manifolds.h"

#include "box2d_manifold_lcps.h"
#include "siconos_peer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

namespace unison::bench {

// ---- Unison's fast path ------------------------------------------------------------------------------------------
// The "fast" column is the active-set path (resolveActiveSet with its default options) from a cold start on the
// snapshot's bodies and contact nodes, which begins with the interior-point answer of the convex relaxation
// (ActiveSetOptions::coldInteriorPoint), then Lemke (with its robust path) when the path does not certify its
// answer. The active-set path works on the bodies, so a float-assembled member, which has none, goes to Lemke
// directly. The answer is returned as the member's z (friction: [normals | +t, -t per contact | slacks]).
LcpResult unisonFastPath(LemkeSolver& solver, const ManifoldLcp& m, const ManifoldSnapshot& snap,
                         const LcpOptions& options, bool* usedActiveSet) {
    *usedActiveSet = false;
    if (m.data == ManifoldData::floatData) return solver.solve(m.lcp, options);
    std::vector<ResolverBody<Dim2>> bodies;
    std::vector<ContactNode<Dim2>> contacts;
    toResolverInput(snap, &bodies, &contacts);
    if (!m.friction)
        for (auto& c : contacts) c.friction = 0.0;
    ResolverOptions ro;  // as assembleManifoldLcp: threshold 0, e = 0, no tangent dead zone
    ro.frictionDirections = 2;
    ro.lcp = options;
    const std::vector<double> cold(contacts.size() * 3, 0.0);
    const Resolution r = resolveActiveSet(bodies, contacts, cold, ro, ActiveSetOptions{});
    if (r.status != LcpStatus::solved) return solver.solve(m.lcp, options);
    *usedActiveSet = true;
    const int nc = int(contacts.size()), n = m.lcp.n;
    LcpResult out;
    out.status = r.status;
    out.z.assign(std::size_t(n), 0.0);
    for (int c = 0; c < nc; ++c) out.z[std::size_t(c)] = r.impulses[std::size_t(c)];
    if (m.friction) {
        for (int c = 0; c < nc; ++c) {
            const Vec2 t{r.tangentImpulses[std::size_t(2 * c)], r.tangentImpulses[std::size_t(2 * c + 1)]};
            // The answer's friction impulse is p_t times the tangent direction, which is as long as the normal:
            // Box2D's float normals are unit only to ~1e-7, so p_t = (t . d) / (d . d), not t . d.
            const Vec2 dir = frictionDirections(contacts[std::size_t(c)], 2)[0];
            const double pt = dot(t, dir) / dot(dir, dir);
            out.z[std::size_t(nc + 2 * c)] = std::max(pt, 0.0);
            out.z[std::size_t(nc + 2 * c + 1)] = std::max(-pt, 0.0);
        }
        // lambda: the smallest slack that makes both tangent rows non-negative (|u_t| at an answer).
        for (int c = 0; c < nc; ++c) {
            double lambda = 0.0;
            for (int m2 = 0; m2 < 2; ++m2) {
                const int i = nc + 2 * c + m2;
                double w = m.lcp.b[std::size_t(i)];
                for (int e = m.lcp.rowStart[std::size_t(i)]; e < m.lcp.rowStart[std::size_t(i) + 1]; ++e)
                    w += m.lcp.vals[std::size_t(e)] * out.z[std::size_t(m.lcp.cols[std::size_t(e)])];
                lambda = std::max(lambda, -w);
            }
            out.z[std::size_t(3 * nc + c)] = lambda;
        }
    }
    out.scaledResidual = r.scaledResidual;
    return out;
}

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kSiconosMaxN = 1200;

// Fastest of repeated runs filling `budgetMs` (at least one run; one long run is enough).
template <class F>
double bestMs(F&& run, double budgetMs) {
    double best = 1e300, total = 0.0;
    for (int reps = 0; reps < 1000 && (reps == 0 || total < budgetMs); ++reps) {
        const auto t0 = Clock::now();
        run();
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        best = std::min(best, ms);
        total += ms;
    }
    return best;
}

struct Solve {
    std::string status;
    int pivots = 0;
    double ms = 0.0;
    double residual = 0.0;  // recomputed, scaled; +inf without an answer
    bool met = false;       // the member's target
    std::string why;        // what missed the target
};

// The target of one member for an answer (status, reported residual, z).
void judge(const ManifoldLcp& m, Solve& s, bool solved, double reported) {
    if (m.data == ManifoldData::doubleData) {
        s.met = solved && s.residual <= 1e-9;
        if (!s.met) s.why = solved ? "residual > 1e-9" : "not solved";
        return;
    }
    const bool honest = (solved ? s.residual <= 1.01e-9 : true) && std::fabs(reported - s.residual) <= 1e-3 * s.residual + 1e-15;
    s.met = s.residual <= 1e-6 && honest && s.status != "infeasible" && s.status != "pivot_limit";
    if (!s.met) s.why = s.residual > 1e-6 ? "residual > 1e-6" : !honest ? "dishonest status or residual" : "status " + s.status;
}

Solve runUnison(const ManifoldLcp& m, const ManifoldSnapshot& snap, bool fast, double budgetMs) {
    LemkeSolver solver;
    bool activeSet = false;
    auto call = [&] {
        return fast ? unisonFastPath(solver, m, snap, LcpOptions{}, &activeSet) : solver.solve(m.lcp, LcpOptions{});
    };
    const LcpResult r = call();
    Solve s;
    s.status = std::string(activeSet ? "as:" : "") + statusName(r.status);
    s.pivots = r.pivots;
    s.residual = scaledResidual(m.lcp, r.z);
    s.ms = bestMs([&] { (void)call(); }, budgetMs);
    judge(m, s, r.status == LcpStatus::solved, r.scaledResidual);
    return s;
}

Solve runSiconos(const ManifoldLcp& m, double budgetMs) {
    const Lcp dense = toDense(m.lcp);
    // The iteration cap bench_lcp gives Siconos on the standard cases: at least 20 n, at most ~10 s of cycling.
    const double perIteration = double(dense.n) * 2.0 * double(dense.n + 1);
    const int cap = int(std::min(double(LcpOptions::kDefaultMaxPivots), std::max(20.0 * dense.n, 1e10 / perIteration)));
    SiconosPeer peer(dense, cap);
    const SiconosResult r = peer.solve();
    Solve s;
    s.pivots = r.iterations;
    s.residual = scaledResidual(m.lcp, r.z);
    // lexicolemke's info 0 also ends a secondary ray: "solved" only with the residual checked here.
    s.status = r.info == 1 ? "pivot_limit" : s.residual <= 1e-9 ? "solved" : "infeasible";
    s.ms = r.seconds * 1e3 >= budgetMs ? r.seconds * 1e3 : std::min(r.seconds * 1e3, bestMs([&] { (void)peer.solve(); }, budgetMs));
    // Siconos reports no residual of its own: judged as if it reported the recomputed one.
    judge(m, s, s.status == "solved", s.residual);
    return s;
}

std::string cell(const Solve& s) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%-17s %6d %9.3f %8.1e %-4s", s.status.c_str(), s.pivots, s.ms, s.residual, s.met ? "met" : "MISS");
    return buf;
}

nlohmann::json toJson(const Solve& s) {
    return {{"status", s.status}, {"pivots", s.pivots}, {"ms", s.ms}, {"scaled_residual", s.residual},
            {"target_met", s.met}, {"miss", s.why}};
}

}  // namespace

nlohmann::json runManifoldFamily(bool quick, double budgetMs, const std::string& filter) {
    const std::vector<int> sizes = quick ? std::vector<int>{12} : std::vector<int>{12, 20, 30};
    std::printf("\nBox2D-manifold LCPs: contact LCPs assembled from Box2D 2.4.1's own manifolds of settled testbed "
                "pyramids\n(double data: target solved <= 1e-9; float data: target <= 1e-6 with an honest status); "
                "fast = the active-set path from a cold start on the bodies (as:), Lemke where it does not certify or where "
                "the member has no bodies (float data)\n");
    std::printf("%-34s %5s | %-17s %6s %9s %8s %-4s | %-17s %6s %9s %8s %-4s | %-17s %6s %9s %8s %-4s\n", "case", "n",
                "fast", "piv", "ms", "sres", "tgt", "lemke", "piv", "ms", "sres", "tgt", "siconos", "iter", "ms", "sres", "tgt");
    nlohmann::json out = nlohmann::json::array();
    int met[2][2] = {{0, 0}, {0, 0}}, total[2] = {0, 0};  // [double, float][fast, lemke]
    double fast20 = -1.0, lemke20 = -1.0;
    bool fast20Met = false;
    for (int rows : sizes) {
        const ManifoldSnapshot snap = settledPyramidSnapshot(rows);
        std::vector<ManifoldLcp> family = manifoldLcpsOf(snap, rows);
        for (const ManifoldLcp& m : family) {
            if (quick && m.friction) continue;
            if (!filter.empty() && m.name.find(filter) == std::string::npos) continue;
            const Solve fast = runUnison(m, snap, true, budgetMs);
            const Solve lemke = runUnison(m, snap, false, budgetMs);
            const bool siconosRuns = m.lcp.n <= kSiconosMaxN;
            const Solve siconos = siconosRuns ? runSiconos(m, budgetMs) : Solve{"skipped(n)", 0, 0.0, 0.0, false, ""};
            const int d = m.data == ManifoldData::doubleData ? 0 : 1;
            ++total[d];
            met[d][0] += fast.met ? 1 : 0;
            met[d][1] += lemke.met ? 1 : 0;
            if (rows == 20 && !m.friction && m.data == ManifoldData::doubleData) {
                fast20 = fast.ms;
                lemke20 = lemke.ms;
                fast20Met = fast.met;
            }
            std::printf("%-34s %5d | %s | %s | %s\n", m.name.c_str(), m.lcp.n, cell(fast).c_str(), cell(lemke).c_str(),
                        siconosRuns ? cell(siconos).c_str() : "skipped (dense tableau too large)");
            std::fflush(stdout);
            nlohmann::json j = {{"case", m.name}, {"n", m.lcp.n}, {"contacts", m.contacts}, {"data", dataName(m.data)},
                                {"friction", m.friction}, {"fast", toJson(fast)}, {"lemke", toJson(lemke)}};
            if (siconosRuns) j["siconos"] = toJson(siconos);
            out.push_back(j);
        }
    }
    std::printf("\nBox2D-manifold targets\n");
    std::printf("  from double data, solved <= 1e-9: fast %d/%d, lemke %d/%d: %s\n", met[0][0], total[0], met[0][1],
                total[0], total[0] > 0 && met[0][0] == total[0] ? "PASS" : "FAIL");
    std::printf("  from float data, <= 1e-6 with an honest status: fast %d/%d, lemke %d/%d: %s\n", met[1][0], total[1],
                met[1][1], total[1], total[1] > 0 && met[1][0] == total[1] ? "PASS" : "FAIL");
    if (fast20 >= 0.0)
        std::printf("  cold frictionless 20-row pyramid LCP (n = 800) <= 2 ms with its target met: fast %.2f ms (%s), "
                    "lemke %.2f ms: %s\n", fast20, fast20Met ? "met" : "target missed", lemke20,
                    fast20 <= 2.0 && fast20Met ? "PASS" : "FAIL");
    else
        std::printf("  cold frictionless 20-row pyramid LCP (n = 800) <= 2 ms: n/a (not run%s)\n", quick ? " in --quick" : "");
    return out;
}

}  // namespace unison::bench
