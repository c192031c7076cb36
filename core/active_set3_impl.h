// core/active_set3_impl.h — the 3D body of resolveActiveSet (core/contact_resolver.h), for the world's pyramid of four
// directions (t1, t2, -t1, -t2). Included by core/active_set_impl.h only.
//
// Four directions make the friction set of a contact the diamond |f1| + |f2| <= mu p_n (f_i the impulse along t_i).
// In the coordinates g1 = f1 + f2, g2 = f1 - f2 it is the box |g1| <= mu p_n, |g2| <= mu p_n, and the
// Stewart–Trinkle conditions (the sliding velocity in the normal cone of the diamond at f) become, per component,
// those of a 2D contact: g_r sticks (u_r = 0 along the row (t1 +- t2) / 2) or sits on a bound and slides against it.
// So each contact has a normal unknown and two independent friction components, and the path is the 2D one's
// (core/active_set_impl.h) with two components instead of one:
//   - the bodies' degrees of freedom are normalised, v = sqrt(1/m) phi and omega = L theta with L L^T = I^-1
//     (Dim3::couplingFactor), so that the mass matrix is the identity and J M^-1 J^T = J~ J~^T; a component whose
//     inverse mass or inertia is zero has zero entries;
//   - the interior-point restart (core/interior_point3_impl.h) has four constraints per contact, mu p_n -+ g1 >= 0
//     and mu p_n -+ g2 >= 0; their Newton block C^T (Y/S) C is an arrow matrix whose inverse has a closed form in
//     e = s / y (no cancellation when the e span many orders);
//   - the relaxation lets sliding contacts separate at mu times their sliding speed, and 3D landings slide more than
//     the 2D piles the restart was made for: the restart raises b_n by that amount, taken from each iteration's own
//     iterate (de Saxce's fixed point followed inside the interior point);
//   - the active-set iteration, its phases (0: warm face, 1: semismooth Newton with a proximal term from the warm
//     start or from the restart's answer, 2: best face) and the certification against the Stewart–Trinkle LCP itself
//     are the 2D path's, except that phase 1 moves its centre when the states repeat those of one or two iterations
//     before (3D faces alternate between two states of degenerate contacts, which would hold the proximal term), and
//     that every warm start gets its face and a short trial of phase 1 before the restart (the 2D path sends a warm
//     start far from its answer to the restart at once).
// Every loop runs in index order and the orderings are pure functions of the patterns: the same bits everywhere.
#pragma once

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "body_space_solve.h"
#include "interior_point3_impl.h"
#include "symmetric_pattern_lu.h"

namespace unison {
namespace detail {

template <class D>
Resolution resolveActiveSetBox(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& contacts,
                               const std::vector<double>& warm, const ResolverOptions& options,
                               const ActiveSetOptions& settings) {
    Resolution out;
    out.status = LcpStatus::pivot_limit;
    out.message = validate(ioBodies, contacts);
    if (!out.message.empty()) {
        out.status = LcpStatus::invalid_input;
        return out;
    }
    const int nc = int(contacts.size());
    const int nb = int(ioBodies.size());
    if (D::frictionDirectionCount(options.frictionDirections) != 4) {
        out.message = "active-set path: 3D needs the pyramid of four directions";
        return out;
    }
    if (nc == 0 || warm.size() != std::size_t(nc) * std::size_t(1 + D::kDim)) {
        out.message = "active-set path: no contacts or warm impulses of the wrong size";
        return out;
    }
    const FrictionSystem<D> sys = buildFrictionSystem(ioBodies, contacts, options);
    const FrictionLayout& layout = sys.layout;
    const int k = layout.directions;  // 4: t1, t2, -t1, -t2
    std::vector<int> dof(std::size_t(nb), -1);
    int ndof = 0;
    for (int b = 0; b < nb; ++b) {
        if (!isImmovable(ioBodies[std::size_t(b)])) {
            dof[std::size_t(b)] = ndof;
            ndof += 6;
        }
    }
    // Per body the normalisation: sqrt(1/m) and L with L L^T = I^-1.
    std::vector<double> rootInvMass(std::size_t(nb), 0.0);
    std::vector<typename D::InvInertia> factorL(static_cast<std::size_t>(nb));
    for (int b = 0; b < nb; ++b) {
        if (dof[std::size_t(b)] < 0) continue;
        rootInvMass[std::size_t(b)] = std::sqrt(ioBodies[std::size_t(b)].invMass);
        factorL[std::size_t(b)] = D::couplingFactor(ioBodies[std::size_t(b)].invInertia);
    }
    // A row's side in the normalised degrees of freedom.
    auto normalised = [&](const JacobianRow<D>& row, int s, double outRow[6]) {
        const int b = row.body[s];
        const double rm = rootInvMass[std::size_t(b)];
        typename D::Ang left, right;
        D::couplingHalves(factorL[std::size_t(b)], row.ang[s], left, right);
        for (int a = 0; a < 3; ++a) {
            outRow[a] = rm * row.lin[s][a];
            outRow[3 + a] = left[a];
        }
    };
    std::vector<BoxContactRows> rows(static_cast<std::size_t>(nc));
    std::vector<double> bRow(std::size_t(3 * nc)), diag(std::size_t(3 * nc), 0.0), mu(static_cast<std::size_t>(nc));
    std::vector<std::uint8_t> frictional(static_cast<std::size_t>(nc), 0);
    double maxAbs = 1.0, bMax = 0.0;
    auto sq6 = [](const double* v) {
        double s = 0.0;
        for (int a = 0; a < 6; ++a) s += v[a] * v[a];
        return s;
    };
    for (int c = 0; c < nc; ++c) {
        BoxContactRows& q = rows[std::size_t(c)];
        const JacobianRow<D>& rn = sys.rows[std::size_t(c)];
        const JacobianRow<D>& r1 = sys.rows[std::size_t(layout.tangentOffset() + c * k)];
        const JacobianRow<D>& r2 = sys.rows[std::size_t(layout.tangentOffset() + c * k + 1)];
        double gRow[3] = {0.0, 0.0, 0.0};  // diagonals of the normal, t1 and t2 rows (the LCP's scale)
        for (int s = 0; s < 2; ++s) {
            q.d[s] = dof[std::size_t(rn.body[s])];
            double jn[6], j1[6], j2[6];
            if (q.d[s] < 0) {
                std::fill(jn, jn + 6, 0.0);
                std::fill(j1, j1 + 6, 0.0);
                std::fill(j2, j2 + 6, 0.0);
            } else {
                normalised(rn, s, jn);
                normalised(r1, s, j1);
                normalised(r2, s, j2);
            }
            gRow[0] += sq6(jn);
            gRow[1] += sq6(j1);
            gRow[2] += sq6(j2);
            for (int a = 0; a < 6; ++a) {
                q.j[0][s][a] = jn[a];
                q.j[1][s][a] = 0.5 * (j1[a] + j2[a]);
                q.j[2][s][a] = 0.5 * (j1[a] - j2[a]);
            }
        }
        for (int r = 0; r < 3; ++r) diag[std::size_t(3 * c + r)] = sq6(q.j[r][0]) + sq6(q.j[r][1]);
        const double b1 = sys.b[std::size_t(layout.tangentOffset() + c * k)];
        const double b2 = sys.b[std::size_t(layout.tangentOffset() + c * k + 1)];
        bRow[std::size_t(3 * c)] = sys.b[std::size_t(c)];
        bRow[std::size_t(3 * c + 1)] = 0.5 * (b1 + b2);
        bRow[std::size_t(3 * c + 2)] = 0.5 * (b1 - b2);
        mu[std::size_t(c)] = sys.mu[std::size_t(c)];
        frictional[std::size_t(c)] =
            mu[std::size_t(c)] > 0.0 && diag[std::size_t(3 * c + 1)] > 0.0 && diag[std::size_t(3 * c + 2)] > 0.0;
        maxAbs = std::max({maxAbs, gRow[0], gRow[1], gRow[2], mu[std::size_t(c)]});
        bMax = std::max({bMax, std::fabs(sys.b[std::size_t(c)]), std::fabs(b1), std::fabs(b2)});
        if (!(diag[std::size_t(3 * c)] > 0.0)) {
            out.message = "active-set path: a contact between immovable bodies";
            return out;
        }
    }
    const double scale = std::max(maxAbs, bMax);
    const double tolAbs = options.lcp.residualTolerance * scale;
    std::uint64_t work = 0;
    const std::uint64_t rowWork = std::uint64_t(60 * nc + 12 * nb);

    // u = b + J~ J~^T x per contact (p_n, g1, g2).
    std::vector<double> mom(std::size_t(std::max(ndof, 1)));
    auto velocities = [&](const std::vector<double>& x, std::vector<double>& u) {
        std::fill(mom.begin(), mom.end(), 0.0);
        for (int c = 0; c < nc; ++c) addBoxRows(rows[std::size_t(c)], &x[std::size_t(3 * c)], mom.data());
        for (int c = 0; c < nc; ++c)
            for (int r = 0; r < 3; ++r)
                u[std::size_t(3 * c + r)] = bRow[std::size_t(3 * c + r)] + boxRowDot(rows[std::size_t(c)], r, mom.data());
    };
    // The Stewart–Trinkle LCP's complementarity residual: f1 = (g1 + g2) / 2, f2 = (g1 - g2) / 2 on the directions
    // t1, t2, -t1, -t2 (beta = their positive and negative parts), u1 = u_g1 + u_g2 and u2 = u_g1 - u_g2 along t1 and
    // t2, lambda = max(|u1|, |u2|) or 0, whichever is closer.
    auto lcpResidual = [&](const std::vector<double>& x, const std::vector<double>& u) {
        double res = 0.0;
        for (int c = 0; c < nc; ++c) {
            const double pn = x[std::size_t(3 * c)], g1 = x[std::size_t(3 * c + 1)], g2 = x[std::size_t(3 * c + 2)];
            const double f1 = 0.5 * (g1 + g2), f2 = 0.5 * (g1 - g2);
            const double u1 = u[std::size_t(3 * c + 1)] + u[std::size_t(3 * c + 2)];
            const double u2 = u[std::size_t(3 * c + 1)] - u[std::size_t(3 * c + 2)];
            const double beta[4] = {std::max(f1, 0.0), std::max(f2, 0.0), std::max(-f1, 0.0), std::max(-f2, 0.0)};
            const double along[4] = {u1, u2, -u1, -u2};
            const double slack = mu[std::size_t(c)] * pn - beta[0] - beta[1] - beta[2] - beta[3];
            auto frictionTerms = [&](double lam) {
                double r = std::fabs(std::min(lam, slack));
                for (int m = 0; m < 4; ++m) r = std::max(r, std::fabs(std::min(beta[m], along[m] + lam)));
                return r;
            };
            res = std::max(res, std::fabs(std::min(pn, u[std::size_t(3 * c)])));
            res = std::max(res, std::min(frictionTerms(std::max(std::fabs(u1), std::fabs(u2))), frictionTerms(0.0)));
        }
        return res;
    };
    auto merit = [&](const std::vector<double>& x, const std::vector<double>& u) {
        double total = 0.0;
        for (int c = 0; c < nc; ++c) {
            const double pn = x[std::size_t(3 * c)];
            const double fn = std::min(pn * diag[std::size_t(3 * c)], u[std::size_t(3 * c)]);
            total += fn * fn;
            const double bound = mu[std::size_t(c)] * pn;
            for (int r = 1; r < 3; ++r) {
                const double gt = diag[std::size_t(3 * c + r)];
                if (!(gt > 0.0)) continue;
                const double pt = x[std::size_t(3 * c + r)];
                const double yt = pt - u[std::size_t(3 * c + r)] / gt;
                const double ft = (pt - std::min(bound, std::max(-bound, yt))) * gt;
                total += ft * ft;
            }
        }
        return total;
    };
    auto project = [&](std::vector<double>& x) {
        for (int c = 0; c < nc; ++c) {
            double& pn = x[std::size_t(3 * c)];
            pn = std::max(pn, 0.0);
            const double bound = frictional[std::size_t(c)] ? mu[std::size_t(c)] * pn : 0.0;
            for (int r = 1; r < 3; ++r) {
                double& pt = x[std::size_t(3 * c + r)];
                pt = std::min(bound, std::max(-bound, pt));
            }
        }
    };

    std::vector<double> x(std::size_t(3 * nc)), u(std::size_t(3 * nc));
    for (int c = 0; c < nc; ++c) {
        const double* w = &warm[std::size_t(c) * std::size_t(1 + D::kDim)];
        const typename D::Vec t = D::fromComponents(w + 1);
        const double f1 = D::dot(t, sys.dirs[std::size_t(c * k)]), f2 = D::dot(t, sys.dirs[std::size_t(c * k + 1)]);
        x[std::size_t(3 * c)] = w[0];
        x[std::size_t(3 * c + 1)] = f1 + f2;
        x[std::size_t(3 * c + 2)] = f1 - f2;
    }
    // The interior-point restart: the answer of the convex relaxation with de Saxce's fixed point followed inside the
    // iteration. The relaxation lets a sliding contact separate at mu lambda (lambda = |u_g1| + |u_g2| = max(|u1|,
    // |u2|), its sliding speed); raising b_n by mu lambda removes that, and where the shift and the answer agree every
    // loaded contact has u_n = 0, the LCP's. From the interior point's fourth iteration on, each iteration sets the
    // shift from its own iterate's sliding speeds before it computes its residuals (the first iterations' speeds are
    // those of a point far inside the cones). Solving the relaxation again with the shift of the last answer (rounds,
    // each convex) converges only linearly, 2-3x a round on the toppling heap's landing islands (solver-notes.md).
    constexpr int kShiftFixedIterations = 3;
    std::vector<double> shift(static_cast<std::size_t>(nc), 0.0), unshifted(x.size());
    int velocityCalls = 0;
    auto shiftedVelocities = [&](const std::vector<double>& xx, std::vector<double>& uu) {
        velocities(xx, uu);
        const bool follow = ++velocityCalls > kShiftFixedIterations;
        for (int c = 0; c < nc; ++c) {
            if (follow && frictional[std::size_t(c)])
                shift[std::size_t(c)] = mu[std::size_t(c)] * (std::fabs(uu[std::size_t(3 * c + 1)]) +
                                                              std::fabs(uu[std::size_t(3 * c + 2)]));
            uu[std::size_t(3 * c)] += shift[std::size_t(c)];
        }
    };
    auto shiftedResidual = [&](const std::vector<double>& xx, const std::vector<double>& uu) {
        unshifted = uu;
        for (int c = 0; c < nc; ++c) unshifted[std::size_t(3 * c)] -= shift[std::size_t(c)];
        return lcpResidual(xx, unshifted);
    };
    auto interiorPoint = [&](std::vector<double>& xOut) {
        std::fill(shift.begin(), shift.end(), 0.0);
        velocityCalls = 0;
        return boxInteriorPoint(rows, mu, frictional, diag, ndof, bMax, shiftedVelocities, shiftedResidual, tolAbs,
                                rowWork, settings.patternCache, settings.maxWork, work, xOut);
    };
    project(x);
    velocities(x, u);
    work += rowWork;
    double currentMerit = merit(x, u);

    // Per contact: separated, or touching with each friction component sticking (0) or on its bound (+1: kPlus,
    // -1: kMinus).
    enum : std::uint8_t { kStick = 0, kPlus = 1, kMinus = 2 };
    std::vector<std::uint8_t> touching(static_cast<std::size_t>(nc), 0), comp(std::size_t(2 * nc), 0);
    std::vector<std::uint8_t> lastState, lastState2;
    // freeIndex: an unknown's own index where it is free (its column in the system is ndof + it), -1 where not.
    std::vector<int> freeIndex(std::size_t(3 * nc)), freeUnknown;
    std::vector<Eigen::Triplet<double>> triplets;
    ColumnAssembly assembly;
    // The island's system: kept in the scratch (ActiveSetOptions::scratch) for the next call with the same pattern.
    BoxSystem ownSystem;
    BoxSystem* islandSystem = &ownSystem;
    if (settings.scratch) {
        std::vector<int> sides(std::size_t(2 * nc));
        for (int c = 0; c < nc; ++c)
            for (int s = 0; s < 2; ++s) sides[std::size_t(2 * c + s)] = rows[std::size_t(c)].d[s];
        islandSystem = &settings.scratch->boxSystem(ndof, sides);
    }
    Eigen::SparseMatrix<double>& K = islandSystem->K;
    SymmetricPatternLu& factor = islandSystem->factor;
    std::vector<int>& systemPattern = islandSystem->planSlot;
    GmresWorkspace gmres;
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
    std::vector<double> dx(x.size()), xt(x.size()), ut(x.size()), xp(x.size()), up(x.size()), rhs;
    constexpr double kEps0 = 1e-4, kShrink = 0.1, kFloor = 1e-7, kPolishEps = 1e-6;
    constexpr int kPolish = 8, kHalvings = 3;
    // A warm start whose face does not hold gets kWarmTrial iterations of phase 1 before the interior-point restart:
    // most of a toppling heap's landing islands certify from the warm start within them (without the trial 342 of 430
    // islands took the restart). Measured on the toppling 100-cube heap with the restart as it is (solver-notes.md):
    // 10 iterations 7.6 % fewer instructions than 15, 5 and 7 about 4.5 % fewer, 12 6 %. An island the face leaves
    // more than kTrialGate tolerances off goes to the restart without the trial: on the heap 6.8 % fewer instructions
    // (its trials from that far rarely certify), on the column pile 2.9 % more (some of its flat landings would have).
    constexpr double kInteriorGate = 10.0, kTrialGate = 1e5;
    constexpr int kWarmTrial = 10;
    double epsRel = kEps0;
    std::vector<double> center = x, ue(x.size());
    std::vector<double> bestX = x, bestU = u, warmX = x, warmU = u;
    bool interiorTried = false, solved = false, warmTrial = false;
    int iterations = 0;
    // The last iteration's step came from `factor`: K, factor, the states and freeIndex describe its system
    // (ActiveSetOptions::incomingVelocity uses them once more).
    bool lastFactored = false;
    double bestResidual = lcpResidual(x, u);
    const bool cold = std::all_of(x.begin(), x.end(), [](double v) { return v == 0.0; });
    const bool coldInterior = cold && settings.interiorPoint && settings.coldInteriorPoint;
    int phase = cold && !coldInterior ? 1 : 0;
    bool polish = !cold || coldInterior;
    int limit = coldInterior ? 0 : cold ? settings.maxIterations : kPolish;
    epsRel = cold && !coldInterior ? kEps0 : kPolishEps;
    double knownResidual = bestResidual;
    std::vector<std::uint8_t> state(std::size_t(3 * nc));
    // The bound a slipping component keeps: +-mu p_n (0 without friction).
    auto slipSignOf = [&](int c, int r) -> double {
        if (!frictional[std::size_t(c)]) return 0.0;
        return comp[std::size_t(2 * c + r - 1)] == kPlus ? mu[std::size_t(c)] : -mu[std::size_t(c)];
    };
    // Phase 1 from warmX (the warm start, or the restart's answer) for `count` iterations.
    auto phase1FromWarm = [&](int count) {
        phase = 1;
        polish = false;
        limit = iterations + count;
        x = warmX;
        u = warmU;
        center = x;
        epsRel = kEps0;
        lastState.clear();
        lastState2.clear();
    };
    for (;;) {
        if ((knownResidual >= 0.0 ? knownResidual : lcpResidual(x, u)) <= tolAbs) {
            solved = true;
            break;
        }
        if (settings.maxWork > 0 && work >= settings.maxWork) break;
        if (iterations >= limit) {
            if (phase == 2) break;
            // Far from an answer after the warm face (phase 0) or the warm start's trial of phase 1: first the trial
            // (unless the face left the island more than kTrialGate tolerances off), then the interior-point restart.
            const bool far = settings.interiorPoint && !interiorTried && bestResidual > kInteriorGate * tolAbs;
            if (phase == 0 && far && !warmTrial && !cold && bestResidual <= kTrialGate * tolAbs) {
                warmTrial = true;
                phase1FromWarm(kWarmTrial);
                currentMerit = merit(x, u);
                knownResidual = -1.0;
                continue;
            }
            if ((phase == 0 || warmTrial) && far) {
                interiorTried = true;
                phase = 0;  // phase 1 from the restart's answer follows
                std::vector<double> xi(x.size(), 0.0);
                if (interiorPoint(xi)) {
                    out.interiorPoint = true;
                    lastFactored = false;  // the factors describe the warm face, not this answer's
                    x.swap(xi);
                    project(x);
                    velocities(x, u);
                    work += rowWork;
                    warmX = x;
                    warmU = u;
                    center = x;
                    currentMerit = merit(x, u);
                    limit = iterations;  // phase 1 from this answer: its face rarely holds (sliding contacts)
                    const double r0 = lcpResidual(x, u);
                    knownResidual = r0;
                    if (r0 < bestResidual) {
                        bestResidual = r0;
                        bestX = x;
                        bestU = u;
                    }
                    continue;
                }
            }
            if (phase == 0) {
                phase1FromWarm(settings.maxIterations);
            } else {
                phase = 2;
                polish = true;
                limit = iterations + kPolish;
                x = bestX;
                u = bestU;
                epsRel = kPolishEps;
                currentMerit = merit(x, u);
            }
        }
        if (polish) center = x;
        ++iterations;
        for (std::size_t i = 0; i < x.size(); ++i) ue[i] = u[i] + epsRel * diag[i] * (x[i] - center[i]);
        // States and free unknowns.
        freeUnknown.clear();
        for (int c = 0; c < nc; ++c) {
            const double pn = x[std::size_t(3 * c)];
            const double gn = diag[std::size_t(3 * c)];
            const double yn = polish ? (pn > 0.0 || u[std::size_t(3 * c)] < -tolAbs ? 1.0 : -1.0)
                                     : pn - ue[std::size_t(3 * c)] / gn;
            for (int r = 0; r < 3; ++r) freeIndex[std::size_t(3 * c + r)] = -1;
            touching[std::size_t(c)] = yn >= -tolAbs / gn ? 1 : 0;
            if (!touching[std::size_t(c)]) continue;
            freeIndex[std::size_t(3 * c)] = 3 * c;
            freeUnknown.push_back(3 * c);
            const double bound = mu[std::size_t(c)] * (polish ? pn : yn);
            for (int r = 1; r < 3; ++r) {
                const double gt = diag[std::size_t(3 * c + r)];
                const double pt = x[std::size_t(3 * c + r)];
                const double yt = polish ? pt : pt - ue[std::size_t(3 * c + r)] / gt;
                const bool sticks = frictional[std::size_t(c)] &&
                                    (polish ? std::fabs(pt) < mu[std::size_t(c)] * pn : std::fabs(yt) <= bound + tolAbs / gt);
                std::uint8_t& st = comp[std::size_t(2 * c + r - 1)];
                if (sticks) {
                    st = kStick;
                    freeIndex[std::size_t(3 * c + r)] = 3 * c + r;
                    freeUnknown.push_back(3 * c + r);
                } else {
                    st = yt >= 0.0 ? kPlus : kMinus;
                }
            }
        }
        const int n = ndof + 3 * nc;
        rhs.assign(std::size_t(n), 0.0);
        // Known parts: separated contacts let go, slipping components move onto their bound.
        for (int c = 0; c < nc; ++c) {
            double h[3] = {0.0, 0.0, 0.0};
            const double pn = x[std::size_t(3 * c)];
            if (!touching[std::size_t(c)]) {
                for (int r = 0; r < 3; ++r) h[r] = -x[std::size_t(3 * c + r)];
            } else {
                for (int r = 1; r < 3; ++r)
                    if (freeIndex[std::size_t(3 * c + r)] < 0) h[r] = slipSignOf(c, r) * pn - x[std::size_t(3 * c + r)];
            }
            addBoxRows(rows[std::size_t(c)], h, rhs.data());
        }
        for (const int unknown : freeUnknown) rhs[std::size_t(ndof + unknown)] = -ue[std::size_t(unknown)];
        // K [v; q] = [I, J~^T; J~, D] [v; q] = [known momentum; -u'] with q = -dp over every unknown of the island: a
        // free one has its rows and D = -eps G, one that is not (a separated contact, a slipping component) zeros and
        // D = -1, so q = 0 there. A slipping component's bound adds +-mu times its row to the normal column
        // (non-symmetric values). The pattern is the island's whatever the states: analysed once (kept in the scratch
        // and found there on the next steps while the contacts stay), its values written in place.
        if (systemPattern.empty()) {
            triplets.clear();
            for (int i = 0; i < ndof; ++i) triplets.emplace_back(i, i, 1.0);
            for (int unknown = 0; unknown < 3 * nc; ++unknown) {
                const BoxContactRows& q = rows[std::size_t(unknown / 3)];
                const int col = ndof + unknown;
                for (int s = 0; s < 2; ++s) {
                    if (q.d[s] < 0) continue;
                    for (int a = 0; a < 6; ++a) {
                        triplets.emplace_back(col, q.d[s] + a, 0.0);
                        triplets.emplace_back(q.d[s] + a, col, 0.0);
                    }
                }
                triplets.emplace_back(col, col, 0.0);
            }
            assembleColumns<true>(n, triplets, K, assembly);
            systemPattern = assembly.planSlot;  // each entry's place in K's values, in the order above
            factor.analyzePattern(K, settings.patternCache);
            ++out.patternAnalyses;
        }
        bool slips = false;
        {
            double* values = K.valuePtr();
            const int* slot = systemPattern.data();
            for (int i = 0; i < ndof; ++i) values[*slot++] = 1.0;
            for (int unknown = 0; unknown < 3 * nc; ++unknown) {
                const int c = unknown / 3, r = unknown % 3;
                const BoxContactRows& q = rows[std::size_t(c)];
                const bool isFree = freeIndex[std::size_t(unknown)] >= 0;
                double sl[3] = {0.0, 0.0, 0.0};  // the slipping components' bounds, on the normal column
                if (isFree && r == 0)
                    for (int t = 1; t < 3; ++t)
                        if (freeIndex[std::size_t(3 * c + t)] < 0) sl[t] = slipSignOf(c, t);
                for (int s = 0; s < 2; ++s) {
                    if (q.d[s] < 0) continue;
                    for (int a = 0; a < 6; ++a) {
                        const double v = isFree ? q.j[r][s][a] : 0.0;
                        values[*slot++] = v;
                        double w = v;
                        for (int t = 1; t < 3; ++t) {
                            if (sl[t] != 0.0) {
                                w += sl[t] * q.j[t][s][a];
                                slips = true;
                            }
                        }
                        values[*slot++] = w;
                    }
                }
                values[*slot++] = isFree ? -epsRel * diag[std::size_t(unknown)] : -1.0;
            }
        }
        Eigen::VectorXd sol;
        bool stepFound = false;
        lastFactored = false;
        if (factor.factorize(K, !slips)) {
            const std::uint64_t nnzL = std::uint64_t(factor.factorNonZeros());
            work += std::uint64_t(K.nonZeros()) + 8 * nnzL;
            Eigen::Map<const Eigen::VectorXd> rv(rhs.data(), n);
            stepFound = gmresRight(K, factor, Eigen::VectorXd(rv), sol, gmres, std::uint64_t(K.nonZeros()) + 4 * nnzL, work);
            lastFactored = stepFound;
        }
        if (!stepFound) {
            lu.analyzePattern(K);
            lu.factorize(K);
            if (lu.info() != Eigen::Success) break;
            Eigen::Map<const Eigen::VectorXd> rv(rhs.data(), n);
            sol = lu.solve(Eigen::VectorXd(rv));
            work += std::uint64_t(K.nonZeros()) + 2 * std::uint64_t(lu.nnzL() + lu.nnzU());
        }
        work += rowWork;
        for (int c = 0; c < nc; ++c) {
            if (!touching[std::size_t(c)]) {
                for (int r = 0; r < 3; ++r) dx[std::size_t(3 * c + r)] = -x[std::size_t(3 * c + r)];
                continue;
            }
            const double pn = x[std::size_t(3 * c)];
            const double dn = -sol[ndof + freeIndex[std::size_t(3 * c)]];
            dx[std::size_t(3 * c)] = dn;
            for (int r = 1; r < 3; ++r) {
                const int fi = freeIndex[std::size_t(3 * c + r)];
                dx[std::size_t(3 * c + r)] =
                    fi >= 0 ? -sol[ndof + fi] : slipSignOf(c, r) * (pn + dn) - x[std::size_t(3 * c + r)];
            }
        }
        bool finite = true;
        for (double v : dx) finite = finite && std::isfinite(v);
        if (!finite) break;
        const int halvings = polish ? 0 : kHalvings;
        double stepMerit = 0.0;
        for (int h = 0, ok = 0; h <= halvings && !ok; ++h) {
            const double alpha = std::ldexp(1.0, -h);
            for (std::size_t i = 0; i < x.size(); ++i) xt[i] = x[i] + alpha * dx[i];
            velocities(xt, ut);
            work += rowWork;
            stepMerit = merit(xt, ut);
            ok = stepMerit < currentMerit || h == halvings;
        }
        xp = xt;
        project(xp);
        const bool moved = std::memcmp(xp.data(), xt.data(), xt.size() * sizeof(double)) != 0;
        if (moved)
            velocities(xp, up);
        else
            up = ut;
        work += rowWork;
        const double res = lcpResidual(xp, up);
        knownResidual = moved ? -1.0 : res;
        if (res <= tolAbs) {
            x.swap(xp);
            u.swap(up);
            solved = true;
            break;
        }
        // The warm face ends at its first step that does not improve on the best: on the toppling 100-cube heap the
        // warm faces that hold fall by 10-100x a step, and those that do not wander for their 8 iterations.
        if (phase == 0 && !interiorTried && res >= bestResidual) limit = iterations;
        if (res < bestResidual) {
            bestResidual = res;
            bestX = xp;
            bestU = up;
        }
        x.swap(xt);
        u.swap(ut);
        currentMerit = stepMerit;
        for (int c = 0; c < nc; ++c) {
            state[std::size_t(3 * c)] = touching[std::size_t(c)];
            state[std::size_t(3 * c + 1)] = comp[std::size_t(2 * c)];
            state[std::size_t(3 * c + 2)] = comp[std::size_t(2 * c + 1)];
        }
        // States of one or two iterations before: the sub-problem is solved (or alternates between two faces of
        // degenerate contacts); move the centre, tighten eps.
        if (state == lastState || state == lastState2) {
            center = x;
            epsRel = std::max(kFloor, epsRel * kShrink);
        }
        lastState2.swap(lastState);
        lastState = state;
    }
    // The Stewart–Trinkle basis an iterate stands on (the next step's warm guess), in increasing order: p_n > 0, the directions with beta > 0, and lambda where the contact slides on the
    // diamond's rim.
    auto basisOf = [&](const std::vector<double>& xs, const std::vector<double>& us, std::vector<int>& basis) {
        basis.clear();
        for (int c = 0; c < nc; ++c)
            if (xs[std::size_t(3 * c)] > 0.0) basis.push_back(c);
        for (int c = 0; c < nc; ++c) {
            const double g1 = xs[std::size_t(3 * c + 1)], g2 = xs[std::size_t(3 * c + 2)];
            const double f1 = 0.5 * (g1 + g2), f2 = 0.5 * (g1 - g2);
            const int t0 = layout.tangentOffset() + c * k;
            if (f1 > 0.0) basis.push_back(t0);
            if (f2 > 0.0) basis.push_back(t0 + 1);
            if (f1 < 0.0) basis.push_back(t0 + 2);
            if (f2 < 0.0) basis.push_back(t0 + 3);
        }
        for (int c = 0; c < nc; ++c) {
            const double pn = xs[std::size_t(3 * c)];
            const double g1 = xs[std::size_t(3 * c + 1)], g2 = xs[std::size_t(3 * c + 2)];
            const double f1 = 0.5 * (g1 + g2), f2 = 0.5 * (g1 - g2);
            const bool sliding = us[std::size_t(3 * c + 1)] != 0.0 || us[std::size_t(3 * c + 2)] != 0.0;
            if (pn > 0.0 && std::fabs(f1) + std::fabs(f2) >= mu[std::size_t(c)] * pn && sliding)
                basis.push_back(layout.slackOffset() + c);
        }
    };
    out.pivots = 0;
    out.work = work;
    out.residual = lcpResidual(x, u);
    out.scaledResidual = out.residual / scale;
    if (!solved) {
        if (bestResidual / scale <= options.acceptResidual) {
            x.swap(bestX);
            u.swap(bestU);
            out.residual = bestResidual;
            out.scaledResidual = bestResidual / scale;
            out.status = LcpStatus::numerical_failure;
            out.approximate = true;
        } else {
            out.message = "active-set path: not certified after " + std::to_string(iterations) + " iterations";
            return out;
        }
    } else {
        out.status = LcpStatus::solved;
    }
    out.activeSet = true;
    // ActiveSetOptions::incomingVelocity (3D: vx, vy, vz, wx, wy, wz per body), as in 2D: the impulses the next step
    // needs on the same face if only the velocities change. One more solve with the last factors takes the velocity
    // error J (v+ - v_in) of the answer carried unchanged out of it.
    if (settings.incomingVelocity && solved && lastFactored &&
        settings.incomingVelocity->size() == std::size_t(6 * nb)) {
        const std::vector<double>& vin = *settings.incomingVelocity;
        velocities(x, up);  // mom: J~^T p per normalised degree of freedom
        work += rowWork;
        std::vector<typename D::Vec> dLin(static_cast<std::size_t>(nb), D::zeroVec());
        std::vector<typename D::Ang> dAng(static_cast<std::size_t>(nb), D::zeroAng());  // v+ - v_in, world frame
        for (int b = 0; b < nb; ++b) {
            const int d = dof[std::size_t(b)];
            if (d < 0) continue;
            const ResolverBody<D>& B = ioBodies[std::size_t(b)];
            const typename D::Ang theta(mom[std::size_t(d + 3)], mom[std::size_t(d + 4)], mom[std::size_t(d + 5)]);
            const typename D::InvInertia& L = factorL[std::size_t(b)];
            const typename D::Ang dw(L(0, 0) * theta[0], L(1, 0) * theta[0] + L(1, 1) * theta[1],
                                     L(2, 0) * theta[0] + L(2, 1) * theta[1] + L(2, 2) * theta[2]);
            for (int a = 0; a < 3; ++a) {
                dLin[std::size_t(b)][a] = B.velocity[a] + rootInvMass[std::size_t(b)] * mom[std::size_t(d + a)] -
                                          vin[std::size_t(6 * b + a)];
                dAng[std::size_t(b)][a] = B.angularVelocity[a] + dw[a] - vin[std::size_t(6 * b + 3 + a)];
            }
        }
        auto rowChange = [&](const JacobianRow<D>& row) {
            double sum = 0.0;
            for (int sd = 0; sd < 2; ++sd) {
                if (dof[std::size_t(row.body[sd])] < 0) continue;
                sum += D::dot(row.lin[sd], dLin[std::size_t(row.body[sd])]) +
                       D::angDot(row.ang[sd], dAng[std::size_t(row.body[sd])]);
            }
            return sum;
        };
        Eigen::VectorXd rv = Eigen::VectorXd::Zero(ndof + 3 * nc);
        for (const int unknown : freeUnknown) {
            const int c = unknown / 3, r = unknown % 3;
            double jd = 0.0;
            if (r == 0) {
                jd = rowChange(sys.rows[std::size_t(c)]);
            } else {
                const double j1 = rowChange(sys.rows[std::size_t(layout.tangentOffset() + c * k)]);
                const double j2 = rowChange(sys.rows[std::size_t(layout.tangentOffset() + c * k + 1)]);
                jd = r == 1 ? 0.5 * (j1 + j2) : 0.5 * (j1 - j2);
            }
            rv[ndof + unknown] = -(u[std::size_t(unknown)] + jd);
        }
        const std::uint64_t nnzL = std::uint64_t(factor.factorNonZeros());
        Eigen::VectorXd ss;
        if (gmresRight(K, factor, rv, ss, gmres, std::uint64_t(K.nonZeros()) + 4 * nnzL, work)) {
            // Only a prediction that keeps the face (as in 2D).
            std::vector<double> next(x.size(), 0.0);
            bool keepsFace = true;
            for (int c = 0; c < nc && keepsFace; ++c) {
                if (!touching[std::size_t(c)]) continue;
                const double pn = x[std::size_t(3 * c)] - ss[ndof + freeIndex[std::size_t(3 * c)]];
                next[std::size_t(3 * c)] = pn;
                keepsFace = pn > 0.0 || x[std::size_t(3 * c)] <= tolAbs / diag[std::size_t(3 * c)];
                for (int r = 1; r < 3 && keepsFace; ++r) {
                    const int fi = freeIndex[std::size_t(3 * c + r)];
                    const double g = fi >= 0 ? x[std::size_t(3 * c + r)] - ss[ndof + fi] : slipSignOf(c, r) * pn;
                    next[std::size_t(3 * c + r)] = g;
                    keepsFace = fi < 0 ||
                                std::fabs(g) <= mu[std::size_t(c)] * pn + tolAbs / diag[std::size_t(3 * c + r)];
                }
            }
            if (keepsFace) {
                project(next);
                out.predictedImpulses.reserve(std::size_t(nc) * std::size_t(1 + D::kDim));
                for (int c = 0; c < nc; ++c) {
                    const double g1 = next[std::size_t(3 * c + 1)], g2 = next[std::size_t(3 * c + 2)];
                    const typename D::Vec t = D::add(D::scale(0.5 * (g1 + g2), sys.dirs[std::size_t(c * k)]),
                                                     D::scale(0.5 * (g1 - g2), sys.dirs[std::size_t(c * k + 1)]));
                    out.predictedImpulses.push_back(next[std::size_t(3 * c)]);
                    for (int d = 0; d < D::kDim; ++d) out.predictedImpulses.push_back(t[d]);
                }
            }
        }
    }
    out.warmFace = solved && phase == 0 && !out.interiorPoint;
    out.message.clear();
    out.impulses.resize(std::size_t(nc));
    std::vector<typename D::Vec> tangent(static_cast<std::size_t>(nc), D::zeroVec());
    for (int c = 0; c < nc; ++c) {
        const double g1 = x[std::size_t(3 * c + 1)], g2 = x[std::size_t(3 * c + 2)];
        const double f1 = 0.5 * (g1 + g2), f2 = 0.5 * (g1 - g2);
        out.impulses[std::size_t(c)] = x[std::size_t(3 * c)];
        tangent[std::size_t(c)] =
            D::add(D::scale(f1, sys.dirs[std::size_t(c * k)]), D::scale(f2, sys.dirs[std::size_t(c * k + 1)]));
    }
    basisOf(x, u, out.basis);
    for (const auto& t : tangent) {
        for (int d = 0; d < D::kDim; ++d) out.tangentImpulses.push_back(t[d]);
    }
    applyImpulses(ioBodies, contacts, out.impulses, &tangent);
    return out;
}

}  // namespace detail
}  // namespace unison
