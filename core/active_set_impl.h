// core/active_set_impl.h — template body of resolveActiveSet (core/contact_resolver.h): the fast path of an island's
// friction LCP. Included at the end of core/contact_resolver_impl.h, so only the resolver's instantiation files see it.
//
// The problem is the one of resolveWithFriction (the paper's normal rows and the Stewart–Trinkle pyramid), written in
// the unknowns a game engine thinks in: per contact a normal impulse p_n >= 0 and, in 2D, one signed tangent impulse
// p_t along +t with |p_t| <= mu p_n (the 2D pyramid's two directions are +t and -t, so the pyramid is exactly this
// interval). The method is an active-set (primal-dual, semismooth Newton) iteration that may change every contact's
// state at once:
//   - a contact is separated (p_n = p_t = 0), sticking (u_n = u_t = 0) or slipping (u_n = 0, p_t = +-mu p_n), u the
//     post-impulse velocities of the LCP's rows;
//   - the step for those equations is one sparse linear system in body space: unknowns are the bodies' velocity
//     changes v (3 per movable body) and the free impulses, equations M v + J~^T q = known momentum (q = -dp, J~
//     the rows of the free impulses, a slipping contact's normal column carrying +-mu times its tangent row) and
//     J v - eps G q = -u' (G the diagonal of J M^-1 J^T). It is factored without pivoting in the AMD order of its
//     symmetric pattern (core/symmetric_pattern_lu.h) and checked by GMRES with those factors as preconditioner, a
//     pivoting sparse LU behind them. The proximal term eps keeps the system regular:
//     piles have more rows than degrees of freedom, so J M^-1 J^T is singular, and without it a step follows the
//     singular directions arbitrarily far;
//   - phase 0 (8 iterations) keeps the face of the warm start: contacts pushing stay active, contacts inside their
//     cone stick, the rest slip, and only a separated contact that approaches faster than the tolerance joins. A
//     resting island's face rarely changes, so this is usually 1-4 factorisations;
//   - when phase 0 does not certify and its best residual is above 10 tolerances, or at once when the warm start's
//     residual is above 1000 (ActiveSetOptions::interiorPoint: a landing, not a settled island at the tolerance's
//     floor), the path restarts once from the interior-point answer of the convex relaxation (Mehrotra's
//     predictor-corrector on the cones |p_t| <= mu p_n from the warm start's impulses, its Newton systems
//     M + J^T H^-1 J in the bodies' degrees of freedom; core/interior_point_impl.h), on that answer's face first;
//     that answer is then the start of phase 1. Where no contact slides the relaxation's answer is the LCP's, and
//     it usually certifies as it stands;
//   - phase 1 (ActiveSetOptions::maxIterations) restarts from the warm start and reads the states off the
//     augmented quantities y_n = p_n - u'_n / G_nn and y_t = p_t - u'_t / G_tt (ties within the tolerance count as
//     touching and sticking), with u' the velocities of the proximal sub-problem u + eps G_ii (p - centre): eps
//     starts at 1e-4 and the centre moves, with eps 10x smaller, whenever the states repeat; a step whose summed
//     squared natural residual is not below the previous iterate's (for the first: phase 0's last, or the start's
//     when cold) is halved up to 3 times;
//   - phase 2 (8 iterations) keeps the face of phase 1's best iterate: degenerate contacts of a pile (no load, no
//     approach) make the states of phase 1 alternate, and fixing them lets the iterate settle on the face.
// It starts from the impulses the contacts carried last step (matched through feature ids), or from zero (a cold start,
// which skips phase 0).
//
// Certification: an iterate is the answer only when the Stewart–Trinkle LCP itself holds: z = (p_n, max(p_t, 0),
// max(-p_t, 0), lambda = |u_t| or 0, whichever is closer) and w = A z + b evaluated from the same rows (matrix-free,
// per body) have max |min(z_i, w_i)| <= options.lcp.residualTolerance * max(max |A_ij|, max |b_i|), the rule every
// Lemke answer passes; each step is also checked after projecting it onto p_n >= 0, |p_t| <= mu p_n (degenerate
// contacts end a rounding step outside). A best iterate within options.acceptResidual is a near miss, applied and
// flagged as Lemke's are; otherwise the caller goes on with Lemke (the guarantee). Every loop runs in index order,
// and the AMD and COLAMD orderings are pure functions of the pattern, so the answer is the same bits everywhere.
#pragma once

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <cstring>

#include "active_set3_impl.h"
#include "body_space_solve.h"
#include "interior_point_impl.h"
#include "symmetric_pattern_lu.h"

namespace unison {


template <class D>
Resolution resolveActiveSet(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& contacts,
                            const std::vector<double>& warm, const ResolverOptions& options,
                            const ActiveSetOptions& settings) {
    Resolution out;
    out.status = LcpStatus::pivot_limit;
    if constexpr (D::kDim != 2) {
        return detail::resolveActiveSetBox(ioBodies, contacts, warm, options, settings);
    } else {
        out.message = validate(ioBodies, contacts);
        if (!out.message.empty()) {
            out.status = LcpStatus::invalid_input;
            return out;
        }
        const int nc = int(contacts.size());
        const int nb = int(ioBodies.size());
        if (nc == 0 || warm.size() != std::size_t(nc) * std::size_t(1 + D::kDim)) {
            out.message = "active-set path: no contacts or warm impulses of the wrong size";
            return out;
        }
        ResolverOptions rowOptions = options;
        rowOptions.frictionDirections = 2;
        // Only the +t rows are read: the -t row of contact c, tOff + 2c + 1, is the exact negation and left empty.
        const detail::FrictionSystem<D> sys = detail::buildFrictionSystem(ioBodies, contacts, rowOptions, true);
        const int tOff = nc;  // +t row of contact c: tOff + 2c
        // Degrees of freedom: 3 per movable body (vx, vy, omega).
        std::vector<int> dof(std::size_t(nb), -1);
        int ndof = 0;
        for (int k = 0; k < nb; ++k) {
            if (!detail::isImmovable(ioBodies[std::size_t(k)])) {
                dof[std::size_t(k)] = ndof;
                ndof += 3;
            }
        }
        auto rowAt = [&](int c, int r) -> const detail::JacobianRow<D>& {
            return sys.rows[std::size_t(r == 0 ? c : tOff + 2 * c)];
        };
        auto bAt = [&](int c, int r) { return sys.b[std::size_t(r == 0 ? c : tOff + 2 * c)]; };
        // Diagonal of J M^-1 J^T per unknown, and the LCP's scale (as writeFrictionRows: 1, every mu, every diagonal;
        // then max |b|).
        std::vector<double> diag(std::size_t(2 * nc), 0.0);
        double maxAbs = 1.0, bMax = 0.0;
        for (int c = 0; c < nc; ++c) {
            for (int r = 0; r < 2; ++r) {
                const detail::JacobianRow<D>& row = rowAt(c, r);
                double g = 0.0;
                for (int s = 0; s < 2; ++s) {
                    const ResolverBody<D>& B = ioBodies[std::size_t(row.body[s])];
                    if (dof[std::size_t(row.body[s])] < 0) continue;
                    g += B.invMass * D::dot(row.lin[s], row.lin[s]) + B.invInertia * row.ang[s] * row.ang[s];
                }
                diag[std::size_t(2 * c + r)] = g;
                maxAbs = std::max(maxAbs, g);
                bMax = std::max(bMax, std::fabs(bAt(c, r)));
            }
            maxAbs = std::max(maxAbs, sys.mu[std::size_t(c)]);
            if (!(diag[std::size_t(2 * c)] > 0.0)) {
                out.message = "active-set path: a contact between immovable bodies";
                return out;
            }
        }
        const double scale = std::max(maxAbs, bMax);
        const double tolAbs = options.lcp.residualTolerance * scale;
        std::uint64_t work = 0;
        const std::uint64_t rowWork = std::uint64_t(16 * nc + 4 * nb);  // one matrix-free product and its residuals

        // u = b + J M^-1 J^T x, per body (x: p_n, p_t of contact c at 2c, 2c + 1). The rows are packed once in the
        // order of x (per row: each side's body slot 3k, -1 where the body is immovable, its components and b), so
        // that the product, the innermost loop of every phase, reads one contiguous array.
        struct PackedRow {
            int slot[2];
            double lx[2], ly[2], ang[2];
            double b;
        };
        std::vector<PackedRow> packed(std::size_t(2 * nc));
        for (int c = 0; c < nc; ++c) {
            for (int r = 0; r < 2; ++r) {
                const detail::JacobianRow<D>& row = rowAt(c, r);
                PackedRow& q = packed[std::size_t(2 * c + r)];
                for (int s = 0; s < 2; ++s) {
                    const int k = row.body[s];
                    q.slot[s] = dof[std::size_t(k)] < 0 ? -1 : 3 * k;
                    q.lx[s] = row.lin[s].x;
                    q.ly[s] = row.lin[s].y;
                    q.ang[s] = row.ang[s];
                }
                q.b = bAt(c, r);
            }
        }
        std::vector<double> mom(std::size_t(3 * nb));
        std::vector<double> invMassOf(std::size_t(3 * nb), 0.0);
        for (int k = 0; k < nb; ++k) {
            const ResolverBody<D>& B = ioBodies[std::size_t(k)];
            invMassOf[std::size_t(3 * k)] = B.invMass;
            invMassOf[std::size_t(3 * k + 1)] = B.invMass;
            invMassOf[std::size_t(3 * k + 2)] = B.invInertia;
        }
        auto velocities = [&](const std::vector<double>& x, std::vector<double>& u) {
            std::fill(mom.begin(), mom.end(), 0.0);
            double* m = mom.data();
            const PackedRow* rows = packed.data();
            const double* xp = x.data();
            const int nr = 2 * nc;
            for (int i = 0; i < nr; ++i) {
                const double p = xp[i];
                if (p == 0.0) continue;
                const PackedRow& q = rows[i];
                for (int s = 0; s < 2; ++s) {
                    const int k = q.slot[s];
                    if (k < 0) continue;
                    m[k] += p * q.lx[s];
                    m[k + 1] += p * q.ly[s];
                    m[k + 2] += p * q.ang[s];
                }
            }
            // An immovable body's slots are never written or read (their inverse masses need not be 0).
            const double* im = invMassOf.data();
            for (int j = 0; j < 3 * nb; ++j) m[j] *= im[j];
            double* up = u.data();
            for (int i = 0; i < nr; ++i) {
                const PackedRow& q = rows[i];
                double v = q.b;
                for (int s = 0; s < 2; ++s) {
                    const int k = q.slot[s];
                    if (k < 0) continue;
                    v += q.lx[s] * m[k] + q.ly[s] * m[k + 1] + q.ang[s] * m[k + 2];
                }
                up[i] = v;
            }
        };
        // The Stewart–Trinkle LCP's complementarity residual of (x, u) (see the header comment).
        auto lcpResidual = [&](const std::vector<double>& x, const std::vector<double>& u) {
            double res = 0.0;
            for (int c = 0; c < nc; ++c) {
                const double pn = x[std::size_t(2 * c)], pt = x[std::size_t(2 * c + 1)];
                const double un = u[std::size_t(2 * c)], ut = u[std::size_t(2 * c + 1)];
                const double bp = std::max(pt, 0.0), bm = std::max(-pt, 0.0);
                const double slack = sys.mu[std::size_t(c)] * pn - bp - bm;
                // lambda is the LCP's own unknown: |u_t| (exact for a contact that slides against its friction) or 0
                // (better for one on the cone's rim that slides along it by a rounding amount), whichever is closer.
                auto frictionTerms = [&](double lam) {
                    return std::max({std::fabs(std::min(bp, ut + lam)), std::fabs(std::min(bm, -ut + lam)),
                                     std::fabs(std::min(lam, slack))});
                };
                res = std::max(res, std::fabs(std::min(pn, un)));
                res = std::max(res, std::min(frictionTerms(std::fabs(ut)), frictionTerms(0.0)));
            }
            return res;
        };
        // Sum of squared natural residuals, in velocity units.
        auto merit = [&](const std::vector<double>& x, const std::vector<double>& u) {
            double m = 0.0;
            for (int c = 0; c < nc; ++c) {
                const double gn = diag[std::size_t(2 * c)], gt = diag[std::size_t(2 * c + 1)];
                const double pn = x[std::size_t(2 * c)], pt = x[std::size_t(2 * c + 1)];
                const double fn = std::min(pn * gn, u[std::size_t(2 * c)]);
                const double bound = sys.mu[std::size_t(c)] * pn;
                double ft = 0.0;
                if (gt > 0.0) {
                    const double yt = pt - u[std::size_t(2 * c + 1)] / gt;
                    ft = (pt - std::min(bound, std::max(-bound, yt))) * gt;
                }
                m += fn * fn + ft * ft;
            }
            return m;
        };
        auto project = [&](std::vector<double>& x) {
            for (int c = 0; c < nc; ++c) {
                double& pn = x[std::size_t(2 * c)];
                double& pt = x[std::size_t(2 * c + 1)];
                pn = std::max(pn, 0.0);
                const double bound = sys.mu[std::size_t(c)] * pn;
                pt = std::min(bound, std::max(-bound, pt));
            }
        };

        std::vector<double> x(std::size_t(2 * nc)), u(std::size_t(2 * nc));
        for (int c = 0; c < nc; ++c) {
            const double* w = &warm[std::size_t(c) * std::size_t(1 + D::kDim)];
            x[std::size_t(2 * c)] = w[0];
            x[std::size_t(2 * c + 1)] = D::dot(D::fromComponents(w + 1), sys.dirs[std::size_t(2 * c)]);
        }
        // Buffers and the last system, kept across solves when the caller provides a scratch (ActiveSetScratch).
        ActiveSetScratch localScratch;
        ActiveSetScratch& scratch = settings.scratch ? *settings.scratch : localScratch;
        auto interiorPoint = [&](std::vector<double>& xOut, const std::vector<double>* warmStart) {
            return detail::interiorPointStart<D>(ioBodies, sys.mu, diag, dof, ndof, bMax, rowAt, velocities,
                                                 lcpResidual, tolAbs, rowWork,
                                                 settings.patternCache, &scratch.interiorPoint, settings.maxWork, work,
                                                 xOut, warmStart);
        };
        project(x);
        velocities(x, u);
        work += rowWork;
        double currentMerit = merit(x, u);

        enum : std::uint8_t { kSeparated, kStick, kSlipPlus, kSlipMinus };
        std::vector<std::uint8_t> state(static_cast<std::size_t>(nc), std::uint8_t(0));
        std::vector<int> freeIndex(std::size_t(2 * nc));
        std::vector<int> freeUnknown;
        std::vector<Eigen::Triplet<double>>& triplets = scratch.triplets;
        std::vector<double> dx(std::size_t(2 * nc)), xt(std::size_t(2 * nc)), ut(std::size_t(2 * nc));
        std::vector<double> xp(std::size_t(2 * nc)), up(std::size_t(2 * nc)), rhs;  // projected trial; right-hand side
        Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
        SymmetricPatternLu& factor = scratch.factor;
        std::vector<int> analysedFree;  // the free unknowns factor's ordering was computed for
        std::vector<int> systemPos;     // each free unknown's place among the system's unknowns
        std::vector<Eigen::Triplet<double>>& slipTriplets = scratch.slipTriplets;
        Eigen::SparseMatrix<double>& K = scratch.K;  // the body-space system of the current iterate
        // The values of the system `factor` holds (empty: none). A face kept from one iteration to the next (phases 0
        // and 2 at the same proximal term) gives the same system to the bit; its factors are then reused as they are.
        std::vector<double> factoredValues;
        std::vector<std::uint8_t> locked(std::size_t(ndof), std::uint8_t(0));
        detail::GmresWorkspace gmres;
        int iterations = 0;
        bool solved = false;
        // The last iteration's step came from `factor` (not from the pivoting LU): K, factor, state, freeUnknown and
        // systemPos still describe its system (ActiveSetOptions::incomingVelocity uses them once more).
        bool lastFactored = false;
        // Proximal term of phase 1, relative to each row's diagonal: 1e-4 at first, 10x smaller each time the states
        // repeat (the sub-problem is solved), down to 1e-7; phases 0 and 2 use 1e-6 with the centre at the iterate.
        constexpr double kEps0 = 1e-4, kShrink = 0.1, kFloor = 1e-7, kPolishEps = 1e-6;
        // Iterations of each refining phase, and step halvings of phase 1 while the merit does not fall.
        constexpr int kPolish = 8, kHalvings = 3;
        // Systems of at least this many entries are remembered for a refill (ActiveSetScratch).
        constexpr std::size_t kPlanEntries = 4096;
        // An analysed pattern is reused for a subset of its unknowns with at most one in this many more (see below).
        constexpr std::size_t kPatternSlack = 16;
        // The interior-point restart is tried once, after phase 0, when phase 0's best residual is above this many tolerances.
        constexpr double kInteriorGate = 10.0;
        // ... and tried before phase 0 when the warm start's residual is above this many.
        constexpr double kInteriorFirstGate = 1000.0;
        double epsRel = kEps0;
        std::vector<double> center = x, ue(x.size());
        std::vector<std::uint8_t> lastState(static_cast<std::size_t>(nc), std::uint8_t(255));
        std::vector<double> bestX = x, bestU = u;
        std::vector<double> warmX = x, warmU = u;
        bool interiorTried = false;
        bool warmFaceTried = false;  // phase 0 has iterated from warmX (its face refined from that point)
        double bestResidual = lcpResidual(x, u);
        // Phases: 0 refines on the face of the warm start (a resting pile's face rarely changes), 1 is the
        // active-set iteration proper, 2 refines on the face of the best iterate of phase 1. A cold start (no
        // impulse) has no face worth refining (every touching contact would slip at p = 0) and begins with phase 1.
        const bool cold = std::all_of(x.begin(), x.end(), [](double v) { return v == 0.0; });
        // ActiveSetOptions::coldInteriorPoint: a cold start goes to the interior-point answer before anything else
        // (limit 0 ends phase 0 at once). The primal-dual iteration from zero impulses takes 12-16 factorisations of
        // the whole system on a resting pile; the interior-point answer takes 10-13 of the bodies' system and usually
        // certifies as it stands.
        const bool coldInterior = cold && settings.interiorPoint && settings.coldInteriorPoint;
        int phase = cold && !coldInterior ? 1 : 0;
        bool polish = !cold || coldInterior;
        int limit = coldInterior ? 0 : cold ? settings.maxIterations : kPolish;
        // A warm start this far from an answer (new contacts, impacts: a landing) goes to the interior-point restart
        // without phase 0, whose face would not hold (measured on the 40-row testbed pyramid: the landing's worst
        // step 181 -> 48 ms, the same from 100 to 10000 tolerances).
        if (!cold && settings.interiorPoint && bestResidual > kInteriorFirstGate * tolAbs) limit = 0;
        epsRel = cold && !coldInterior ? kEps0 : kPolishEps;
        // The residual of the current (x, u) when it is already known (a step whose projection changed nothing),
        // else negative.
        double knownResidual = bestResidual;
        for (;;) {
            if ((knownResidual >= 0.0 ? knownResidual : lcpResidual(x, u)) <= tolAbs) {
                solved = true;
                break;
            }
            if (settings.maxWork > 0 && work >= settings.maxWork) break;
            if (iterations >= limit) {
                if (phase == 2) break;
                if (phase == 0 && settings.interiorPoint && !interiorTried && bestResidual > kInteriorGate * tolAbs) {
                    // The warm start's face does not hold and its best iterate is far from an answer (a landing, not
                    // a settled island at the tolerance's floor): restart from the interior-point answer of the
                    // convex relaxation (from the warm start's impulses), on its face first.
                    interiorTried = true;
                    std::vector<double> xi(x.size(), 0.0);
                    if (interiorPoint(xi, cold ? nullptr : &warmX)) {
                        out.interiorPoint = true;
                        lastFactored = false;  // the factors describe the warm face, not this answer's
                        x.swap(xi);
                        project(x);
                        velocities(x, u);
                        work += rowWork;
                        warmX = x;
                        warmU = u;
                        warmFaceTried = false;
                        center = x;
                        currentMerit = merit(x, u);
                        limit = iterations + kPolish;
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
                if (phase == 0 && settings.floorExit > 0.0 && bestResidual <= settings.floorExit * tolAbs &&
                    bestResidual / scale <= options.acceptResidual)
                    break;  // a near miss at the face's floor (ActiveSetOptions::floorExit)
                if (phase == 0) {
                    // The active-set iteration from the warm start.
                    phase = 1;
                    polish = false;
                    limit = iterations + settings.maxIterations;
                    x = warmX;
                    u = warmU;
                    center = x;
                    epsRel = kEps0;
                    // currentMerit stays phase 0's last: phase 1's first steps are halved unless they reach the level
                    // phase 0 got to (measured: 11 near misses in 90 steps of the base-20 large pyramid, 21 when
                    // compared with the warm start's own merit).
                    std::fill(lastState.begin(), lastState.end(), std::uint8_t(255));
                } else {
                    // Phase 1 found nothing better than the point phase 0 started from, whose face phase 0 has
                    // refined already: phase 2 would repeat it (on the 2000-circle pile's failed landing steps, 8
                    // more factorisations of the same face from the same point).
                    if (warmFaceTried && bestX == warmX) break;
                    // The states oscillate among degenerate contacts: fix the face of the best iterate (its positive
                    // impulses, its sticking and slipping contacts) and refine on it.
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
            if (phase == 0) warmFaceTried = true;
            ++iterations;
            // The proximal sub-problem's velocities: u + eps G_ii (x - center).
            for (std::size_t i = 0; i < x.size(); ++i) ue[i] = u[i] + epsRel * diag[i] * (x[i] - center[i]);
            // The contacts' states, and the free unknowns (velocity equations).
            freeUnknown.clear();
            for (int c = 0; c < nc; ++c) {
                const double pn = x[std::size_t(2 * c)], pt = x[std::size_t(2 * c + 1)];
                const double yn = polish ? (pn > 0.0 || u[std::size_t(2 * c)] < -tolAbs ? 1.0 : -1.0)
                                         : pn - ue[std::size_t(2 * c)] / diag[std::size_t(2 * c)];
                freeIndex[std::size_t(2 * c)] = freeIndex[std::size_t(2 * c + 1)] = -1;
                // Ties within the tolerance count as touching: a resting contact's u_n is 0 up to rounding.
                if (!(yn >= -tolAbs / diag[std::size_t(2 * c)])) {
                    state[std::size_t(c)] = kSeparated;
                    continue;
                }
                freeIndex[std::size_t(2 * c)] = int(freeUnknown.size());
                freeUnknown.push_back(2 * c);
                const double gt = diag[std::size_t(2 * c + 1)];
                const double bound = sys.mu[std::size_t(c)] * (polish ? pn : yn);
                const double yt = gt > 0.0 ? (polish ? pt : pt - ue[std::size_t(2 * c + 1)] / gt) : 0.0;
                // ActiveSetOptions::stickWrongWaySlip: a rim contact of a kept face that slides along its friction
                // impulse sticks (its slip was the face's error).
                const bool wrongWay = polish && settings.stickWrongWaySlip && pn > 0.0 &&
                                      pt * u[std::size_t(2 * c + 1)] > 0.0 &&
                                      std::fabs(u[std::size_t(2 * c + 1)]) > 0.5 * tolAbs;
                const bool sticks = gt > 0.0 && (polish ? std::fabs(pt) < sys.mu[std::size_t(c)] * pn || wrongWay
                                                        : std::fabs(yt) <= bound + tolAbs / gt);
                if (sticks) {
                    state[std::size_t(c)] = kStick;
                    freeIndex[std::size_t(2 * c + 1)] = int(freeUnknown.size());
                    freeUnknown.push_back(2 * c + 1);
                } else {
                    state[std::size_t(c)] = yt >= 0.0 ? kSlipPlus : kSlipMinus;
                }
            }
            // Known parts of the step: separated contacts let go, slipping ones keep p_t = +-mu p_n.
            rhs.assign(std::size_t(ndof + int(freeUnknown.size())), 0.0);
            auto addMomentum = [&](int c, int r, double p) {  // rhs body rows += J_r^T p
                if (p == 0.0) return;
                const detail::JacobianRow<D>& row = rowAt(c, r);
                for (int s = 0; s < 2; ++s) {
                    const int d = dof[std::size_t(row.body[s])];
                    if (d < 0) continue;
                    rhs[std::size_t(d)] += p * row.lin[s].x;
                    rhs[std::size_t(d + 1)] += p * row.lin[s].y;
                    rhs[std::size_t(d + 2)] += p * row.ang[s];
                }
            };
            for (int c = 0; c < nc; ++c) {
                const double pn = x[std::size_t(2 * c)], pt = x[std::size_t(2 * c + 1)];
                const double mu = sys.mu[std::size_t(c)];
                if (state[std::size_t(c)] == kSeparated) {
                    addMomentum(c, 0, -pn);
                    addMomentum(c, 1, -pt);
                } else if (state[std::size_t(c)] != kStick) {
                    const double sgn = state[std::size_t(c)] == kSlipPlus ? 1.0 : -1.0;
                    addMomentum(c, 1, sgn * mu * pn - pt);
                }
            }
            const int nf = int(freeUnknown.size());
            const int n = ndof + nf;
            // The body-space system. With v = M^-1 y (the bodies' velocity changes) and q = -dp it reads
            //   K [v; q] = [M, J~^T; J, -eps G] [v; q] = [known momentum; -u'].
            // Its pattern is symmetric (a slipping contact's tangent column touches its normal row's bodies), and
            // without slipping contacts it is quasi-definite, which has an LDL^T in any symmetric order: K is factored
            // as L D U without pivoting in the AMD order of its pattern (a tenth of the fill of a pivoting LU), and
            // GMRES with those factors as preconditioner checks the step (usually with no product). The pivoting LU
            // of [I, -J~^T; J M^-1, eps G] takes over when GMRES does not converge. A component whose inverse mass or
            // inertia is zero does not move (v = 0).
            // +-mu for the normal column of a slipping contact (its tangent row's share), 0 otherwise.
            auto slipFactor = [&](int c, int r) {
                const std::uint8_t st = state[std::size_t(c)];
                if (r != 0 || (st != kSlipPlus && st != kSlipMinus)) return 0.0;
                return (st == kSlipPlus ? 1.0 : -1.0) * sys.mu[std::size_t(c)];
            };
            triplets.clear();
            slipTriplets.clear();
            for (int k = 0; k < nb; ++k) {
                const int d = dof[std::size_t(k)];
                if (d < 0) continue;
                const ResolverBody<D>& B = ioBodies[std::size_t(k)];
                const double inv[3] = {B.invMass, B.invMass, B.invInertia};
                for (int a = 0; a < 3; ++a) {
                    const bool moves = inv[a] > 0.0;
                    locked[std::size_t(d + a)] = moves ? 0 : 1;
                    triplets.emplace_back(d + a, d + a, moves ? 1.0 / inv[a] : 1.0);
                }
            }
            for (int f = 0; f < nf; ++f) rhs[std::size_t(ndof + f)] = -ue[std::size_t(freeUnknown[std::size_t(f)])];
            // The system's unknowns: the free ones or, in the refining phases (0 and 2) with
            // ActiveSetOptions::reuseSupersetPattern, the unknowns of the pattern analysed last when the free ones are
            // a subset of those with at most one in kPatternSlack more. An unknown of the pattern that is not free
            // keeps its entries as stored zeros and a diagonal of its own: its row reads q = 0, and the analysis
            // (ordering, elimination tree) is reused. A refining iteration on a settled pile at the tolerance's floor
            // releases a few contacts; each would otherwise need a new analysis, which on a large island costs about
            // as much as the factorisation. (Phase 1's oscillating states keep the exact pattern: there the answer
            // reached depends on the rounding of every step, and a pile that ends on a poorer face pays for it on
            // every later step.)
            const bool onAnalysed = freeUnknown == analysedFree ||
                                  (settings.reuseSupersetPattern && polish && !analysedFree.empty() &&
                                   analysedFree.size() >= freeUnknown.size() &&
                                   (analysedFree.size() - freeUnknown.size()) * kPatternSlack <= analysedFree.size() &&
                                   std::includes(analysedFree.begin(), analysedFree.end(), freeUnknown.begin(),
                                                 freeUnknown.end()));
            const std::vector<int>& systemUnknown = onAnalysed ? analysedFree : freeUnknown;
            const int ns = int(systemUnknown.size());
            systemPos.resize(std::size_t(nf));
            for (int f = 0, j = 0; f < nf; ++f, ++j) {
                while (systemUnknown[std::size_t(j)] != freeUnknown[std::size_t(f)]) ++j;
                systemPos[std::size_t(f)] = j;
            }
            for (int f = 0; f < ns; ++f) {
                const int unknown = systemUnknown[std::size_t(f)];
                const int c = unknown / 2, r = unknown % 2;
                const int col = ndof + f;
                const bool isFree = freeIndex[std::size_t(unknown)] >= 0;
                const double slip = isFree ? slipFactor(c, r) : 0.0;
                const detail::JacobianRow<D>& row = rowAt(c, r);
                const detail::JacobianRow<D>& trow = rowAt(c, 1);
                for (int s = 0; s < 2; ++s) {
                    const int d = dof[std::size_t(row.body[s])];
                    if (d < 0) continue;
                    const double j[3] = {row.lin[s].x, row.lin[s].y, row.ang[s]};
                    const double t[3] = {trow.lin[s].x, trow.lin[s].y, trow.ang[s]};
                    for (int a = 0; a < 3; ++a) {
                        if (locked[std::size_t(d + a)]) continue;
                        const double v = isFree ? j[a] : 0.0;
                        triplets.emplace_back(col, d + a, v);
                        triplets.emplace_back(d + a, col, v);
                        if (slip != 0.0) slipTriplets.emplace_back(d + a, col, slip * t[a]);
                    }
                }
                const double g = diag[std::size_t(unknown)];
                triplets.emplace_back(col, col, isFree || g > 0.0 ? -epsRel * g : -1.0);
            }
            Eigen::VectorXd sol;
            bool stepFound = false;
            lastFactored = false;
            {
                triplets.insert(triplets.end(), slipTriplets.begin(), slipTriplets.end());
                // Duplicates (a body twice in a row, a slipping contact's share) are summed. A system of the last
                // one's entry sequence (a settled island's next step, a kept face's next iteration) has its pattern:
                // its values are refilled in place. Big systems record the plan for that.
                const bool refilled = detail::assembleOrRefill(ndof + ns, triplets, K, scratch.assembly, kPlanEntries);
                if (refilled) ++scratch.refills;
                if (!onAnalysed) {
                    // A pure function of the pattern: the factor's analysis stands when K kept its pattern (and its
                    // cache entry stays, as if looked up).
                    if (refilled && scratch.factorHoldsK)
                        factor.keepAnalysis(settings.patternCache);
                    else
                        factor.analyzePattern(K, settings.patternCache);
                    scratch.factorHoldsK = true;
                    analysedFree = freeUnknown;
                    factoredValues.clear();
                    ++out.patternAnalyses;
                }
                // The same pattern (the same system unknowns) with the same values, compared as bits (a -0.0 is not
                // a 0.0 here): the factors held are K's.
                const double* kv = K.valuePtr();
                const bool factored = !factoredValues.empty() && factoredValues.size() == std::size_t(K.nonZeros()) &&
                                      std::memcmp(factoredValues.data(), kv, factoredValues.size() * sizeof(double)) == 0;
                // Without slipping contacts K's values are symmetric too: the L D L^T variant computes the same
                // factors (the same operations on the same values, U = L^T) with a third less work.
                const bool factorOk = factored || factor.factorize(K, slipTriplets.empty());
                if (!factored) factoredValues.assign(kv, kv + (factorOk ? K.nonZeros() : 0));
                if (!factored && ns > nf) ++out.supersetFactorizations;
                if (factorOk) {
                    const std::uint64_t nnzL = std::uint64_t(factor.factorNonZeros());
                    work += std::uint64_t(K.nonZeros()) + (factored ? 0 : 8 * nnzL);
                    Eigen::VectorXd rv = Eigen::VectorXd::Zero(ndof + ns);
                    for (int i = 0; i < ndof; ++i) rv[i] = locked[std::size_t(i)] ? 0.0 : rhs[std::size_t(i)];
                    for (int f = 0; f < nf; ++f) rv[ndof + systemPos[std::size_t(f)]] = rhs[std::size_t(ndof + f)];
                    Eigen::VectorXd ss;
                    stepFound = detail::gmresRight(K, factor, rv, ss, gmres, std::uint64_t(K.nonZeros()) + 4 * nnzL,
                                                   work);
                    if (stepFound) {
                        lastFactored = true;
                        sol.resize(n);
                        for (int i = 0; i < ndof; ++i) sol[i] = ss[i];
                        for (int f = 0; f < nf; ++f) sol[ndof + f] = -ss[ndof + systemPos[std::size_t(f)]];
                    }
                }
            }
            if (!stepFound) {
                // The pivoting LU of [I, -J~^T; J M^-1, eps G] [y; dp] = [known momentum; -u'].
                triplets.clear();
                for (int i = 0; i < ndof; ++i) triplets.emplace_back(i, i, 1.0);
                for (int f = 0; f < nf; ++f) {
                    const int unknown = freeUnknown[std::size_t(f)];
                    const int c = unknown / 2, r = unknown % 2;
                    const int col = ndof + f;
                    const double slip = slipFactor(c, r);
                    const detail::JacobianRow<D>& row = rowAt(c, r);
                    const detail::JacobianRow<D>& trow = rowAt(c, 1);
                    for (int s = 0; s < 2; ++s) {
                        const int k = row.body[s];
                        const int d = dof[std::size_t(k)];
                        if (d < 0) continue;
                        const ResolverBody<D>& B = ioBodies[std::size_t(k)];
                        // Column: -(row + slip * tangent row) on the body's momentum rows; row: J_r M^-1.
                        triplets.emplace_back(d, col, -(row.lin[s].x + slip * trow.lin[s].x));
                        triplets.emplace_back(d + 1, col, -(row.lin[s].y + slip * trow.lin[s].y));
                        triplets.emplace_back(d + 2, col, -(row.ang[s] + slip * trow.ang[s]));
                        triplets.emplace_back(col, d, row.lin[s].x * B.invMass);
                        triplets.emplace_back(col, d + 1, row.lin[s].y * B.invMass);
                        triplets.emplace_back(col, d + 2, row.ang[s] * B.invInertia);
                    }
                    triplets.emplace_back(col, col, epsRel * diag[std::size_t(unknown)]);
                }
                Eigen::SparseMatrix<double> K(n, n);
                K.setFromTriplets(triplets.begin(), triplets.end());
                lu.analyzePattern(K);
                lu.factorize(K);
                if (lu.info() != Eigen::Success) break;
                Eigen::Map<const Eigen::VectorXd> rv(rhs.data(), n);
                sol = lu.solve(rv);
                work += std::uint64_t(K.nonZeros()) + 2 * std::uint64_t(lu.nnzL() + lu.nnzU());
            }
            work += rowWork;
            // The whole step.
            for (int c = 0; c < nc; ++c) {
                const double pn = x[std::size_t(2 * c)], pt = x[std::size_t(2 * c + 1)];
                const std::uint8_t st = state[std::size_t(c)];
                if (st == kSeparated) {
                    dx[std::size_t(2 * c)] = -pn;
                    dx[std::size_t(2 * c + 1)] = -pt;
                    continue;
                }
                const double dn = sol[ndof + freeIndex[std::size_t(2 * c)]];
                dx[std::size_t(2 * c)] = dn;
                if (st == kStick) {
                    dx[std::size_t(2 * c + 1)] = sol[ndof + freeIndex[std::size_t(2 * c + 1)]];
                } else {
                    const double sgn = st == kSlipPlus ? 1.0 : -1.0;
                    dx[std::size_t(2 * c + 1)] = sgn * sys.mu[std::size_t(c)] * (pn + dn) - pt;
                }
            }
            bool finite = true;
            for (double v : dx) finite = finite && std::isfinite(v);
            if (!finite) break;
            // The full step (a primal-dual active-set iteration: the next states are read off the unprojected
            // iterate; infeasible iterates are never certified).
            const int halvings = polish ? 0 : kHalvings;
            double bestMerit = 0.0;
            for (int h = 0, alphaOk = 0; h <= halvings && !alphaOk; ++h) {
                const double alpha = std::ldexp(1.0, -h);
                for (std::size_t i = 0; i < x.size(); ++i) xt[i] = x[i] + alpha * dx[i];
                velocities(xt, ut);
                work += rowWork;
                bestMerit = merit(xt, ut);
                alphaOk = bestMerit < currentMerit || h == halvings;
            }
            {
                // The step's projection onto p_n >= 0, |p_t| <= mu p_n: degenerate contacts end a little outside.
                // A projection that changed no bit leaves the velocities as they are (charged all the same: the
                // work count does not depend on it).
                xp = xt;
                project(xp);
                const bool moved = std::memcmp(xp.data(), xt.data(), xt.size() * sizeof(double)) != 0;
                if (moved)
                    velocities(xp, up);
                else
                    up = ut;
                work += rowWork;
                const double r = lcpResidual(xp, up);
                knownResidual = moved ? -1.0 : r;
                if (r <= tolAbs) {
                    x.swap(xp);
                    u.swap(up);
                    solved = true;
                    break;
                }
                if (r < bestResidual) {
                    bestResidual = r;
                    bestX = xp;
                    bestU = up;
                }
            }
            x.swap(xt);
            u.swap(ut);
            currentMerit = bestMerit;
            // States unchanged: the sub-problem is solved (its Newton step was exact); move the centre, tighten eps.
            if (state == lastState) {
                center = x;
                epsRel = std::max(kFloor, epsRel * kShrink);
            }
            lastState = state;
        }
        out.pivots = 0;
        out.work = work;
        out.residual = lcpResidual(x, u);
        out.scaledResidual = out.residual / scale;
        if (!solved) {
            // A near miss, as Lemke's: the best iterate is applied when the caller accepts its residual.
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
        out.warmFace = solved && phase == 0 && !out.interiorPoint;
        // ActiveSetOptions::incomingVelocity: the impulses the next step needs on the same face if nothing but the
        // velocities changes. Its LCP has b' = b + J (v+ - v_in) (the bodies come in with this answer's velocities
        // v+ = v + M^-1 J^T p instead of v_in), so this answer carried unchanged reads u' = u + J (v+ - v_in); one
        // more step of the last system (its factors, centre at the answer) takes that back.
        if (settings.incomingVelocity && solved && lastFactored && settings.incomingVelocity->size() == std::size_t(3 * nb)) {
            const std::vector<double>& vin = *settings.incomingVelocity;
            velocities(x, up);  // mom: M^-1 J^T p per body
            work += rowWork;
            std::vector<double> change(std::size_t(3 * nb), 0.0);  // v+ - v_in
            for (int k = 0; k < nb; ++k) {
                if (dof[std::size_t(k)] < 0) continue;
                const ResolverBody<D>& B = ioBodies[std::size_t(k)];
                const double now[3] = {B.velocity.x, B.velocity.y, B.angularVelocity};
                for (int a = 0; a < 3; ++a) {
                    const std::size_t i = std::size_t(3 * k + a);
                    change[i] = now[a] + mom[i] - vin[i];
                }
            }
            const int nf = int(freeUnknown.size());
            const int ns = int(K.rows()) - ndof;
            Eigen::VectorXd rv = Eigen::VectorXd::Zero(ndof + ns);
            for (int f = 0; f < nf; ++f) {
                const int unknown = freeUnknown[std::size_t(f)];
                const detail::JacobianRow<D>& row = rowAt(unknown / 2, unknown % 2);
                double jd = 0.0;
                for (int s = 0; s < 2; ++s) {
                    const int k = row.body[s];
                    if (dof[std::size_t(k)] < 0) continue;
                    jd += row.lin[s].x * change[std::size_t(3 * k)] + row.lin[s].y * change[std::size_t(3 * k + 1)] +
                          row.ang[s] * change[std::size_t(3 * k + 2)];
                }
                rv[ndof + systemPos[std::size_t(f)]] = -(u[std::size_t(unknown)] + jd);
            }
            const std::uint64_t nnzL = std::uint64_t(factor.factorNonZeros());
            Eigen::VectorXd ss;
            if (detail::gmresRight(K, factor, rv, ss, gmres, std::uint64_t(K.nonZeros()) + 4 * nnzL, work)) {
                // Only a prediction that keeps the face: a loaded contact that would let go, or a sticking one that
                // would leave its cone, by more than the impulse that moves its row by the tolerance, is the next
                // step's iteration to find, and a warm start off the face costs more than the answer itself.
                std::vector<double> next(x.size(), 0.0);
                bool keepsFace = true;
                for (int c = 0; c < nc && keepsFace; ++c) {
                    const std::uint8_t st = state[std::size_t(c)];
                    if (st == kSeparated) continue;
                    // ss holds q = -dp at each free unknown's place in the system; a slipping contact's p_t follows p_n.
                    auto step = [&](int unknown) {
                        return ss[ndof + systemPos[std::size_t(freeIndex[std::size_t(unknown)])]];
                    };
                    const double pn = x[std::size_t(2 * c)] - step(2 * c);
                    const double pt = st == kStick ? x[std::size_t(2 * c + 1)] - step(2 * c + 1)
                                                   : (st == kSlipPlus ? 1.0 : -1.0) * sys.mu[std::size_t(c)] * pn;
                    next[std::size_t(2 * c)] = pn;
                    next[std::size_t(2 * c + 1)] = pt;
                    const double gt = diag[std::size_t(2 * c + 1)];
                    keepsFace = (pn > 0.0 || x[std::size_t(2 * c)] <= tolAbs / diag[std::size_t(2 * c)]) &&
                                (st != kStick || gt <= 0.0 ||
                                 std::fabs(pt) <= sys.mu[std::size_t(c)] * pn + tolAbs / gt);
                }
                if (keepsFace) {
                    project(next);
                    out.predictedImpulses.reserve(std::size_t(nc) * std::size_t(1 + D::kDim));
                    for (int c = 0; c < nc; ++c) {
                        out.predictedImpulses.push_back(next[std::size_t(2 * c)]);
                        const typename D::Vec t = D::scale(next[std::size_t(2 * c + 1)], sys.dirs[std::size_t(2 * c)]);
                        for (int d = 0; d < D::kDim; ++d) out.predictedImpulses.push_back(t[d]);
                    }
                }
            }
        }
        out.message.clear();
        // The Stewart–Trinkle basis the answer stands on (the next step's warm guess), in increasing order: p_n > 0
        // (unknowns c), the pushing tangent direction (nc + 2c or nc + 2c + 1), and the slack where the contact slips
        // on the cone's rim (3 nc + c).
        out.impulses.resize(std::size_t(nc));
        std::vector<typename D::Vec> tangent(static_cast<std::size_t>(nc), D::zeroVec());
        for (int c = 0; c < nc; ++c) {
            const double pn = x[std::size_t(2 * c)], pt = x[std::size_t(2 * c + 1)];
            out.impulses[std::size_t(c)] = pn;
            tangent[std::size_t(c)] = D::scale(pt, sys.dirs[std::size_t(2 * c)]);
            if (pn > 0.0) out.basis.push_back(c);
        }
        for (int c = 0; c < nc; ++c) {
            const double pt = x[std::size_t(2 * c + 1)];
            if (pt > 0.0) out.basis.push_back(nc + 2 * c);
            if (pt < 0.0) out.basis.push_back(nc + 2 * c + 1);
        }
        for (int c = 0; c < nc; ++c) {
            const double pn = x[std::size_t(2 * c)], pt = x[std::size_t(2 * c + 1)];
            if (pn > 0.0 && std::fabs(pt) >= sys.mu[std::size_t(c)] * pn && u[std::size_t(2 * c + 1)] != 0.0)
                out.basis.push_back(3 * nc + c);
        }
        for (const auto& t : tangent) {
            for (int d = 0; d < D::kDim; ++d) out.tangentImpulses.push_back(t[d]);
        }
        applyImpulses(ioBodies, contacts, out.impulses, &tangent);
        return out;
    }
}

}  // namespace unison
