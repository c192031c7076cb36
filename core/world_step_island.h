// core/world_step_island.h — the island solve unit of core/world_step.h (included at its end): how one awake island
// with contacts is made ready (local bodies, the paper's contact nodes with their bias, warm starts from the cache),
// solved exactly (one Coulomb-pyramid LCP, eq. (19)/(20) plus friction, with the frictionless LCP as the 2D fallback
// and a second, position-only solve for bounces at the time of impact) within a work limit, or approximated
// (core/pgs.h) when the budget left it unsolved or a 3D friction solve failed, and how its answer is written back.
//
// Owns no state. Every function here reads the hooks' bodies and the step's contacts, writes only the island's own
// bodies, contacts and Job, and keeps its scratch in the Worker it is given, so islands run on any thread.
// Invariants: a worker's localIndex is all -1 when a function returns; an island that got no answer leaves its
// bodies untouched.
#pragma once

#include "world_step.h"

namespace unison {

template <class D>
template <class H>
ContactKey WorldStep<D>::keyOf(H& hooks, const StepContact<D>& c) const {
    const auto& bodies = hooks.bodies();
    return ContactKey{bodies.idAt(c.bodyA).index1, bodies.idAt(c.bodyB).index1, std::uint16_t(c.shapeA),
                      std::uint16_t(c.shapeB), c.feature, 0};
}

template <class D>
template <class H>
void WorldStep<D>::prepareIsland(H& hooks, const Job& job, Worker& worker) const {
    using world_step_detail::isDynamic;
    const auto& def = hooks.def();
    const double dt = 1.0 / def.hz;
    const auto& hot = hooks.bodies().hotArray();
    const auto& cold = hooks.bodies().coldArray();
    std::vector<int>& localIndex = worker.localIndex;
    if (localIndex.size() < hot.size()) localIndex.resize(hot.size(), -1);
    IslandSetup& out = worker.setup;
    out.clear();
    std::vector<int>& local = out.local;
    std::vector<ResolverBody<D>>& rb = out.bodies;
    // Local numbering: the island's dynamic bodies, then every static or kinematic body its contacts touch.
    auto localOf = [&](int dense) {
        const int known = localIndex[std::size_t(dense)];
        if (known >= 0) return known;
        localIndex[std::size_t(dense)] = int(local.size());
        local.push_back(dense);
        ResolverBody<D> b;
        const auto& info = cold[std::size_t(dense)];
        const auto& s = hot[std::size_t(dense)];
        if (isDynamic(info)) {
            b.invMass = info.invMass;
            b.invInertia = hooks.worldInvInertia(s, info);
        }
        b.position = s.center;
        b.velocity = s.velocity;
        b.angularVelocity = s.angularVelocity;
        rb.push_back(b);
        return int(local.size()) - 1;
    };
    const int b0 = mIslands.bodyStart[std::size_t(job.island)], b1 = mIslands.bodyStart[std::size_t(job.island) + 1];
    const int e0 = mIslands.edgeStart[std::size_t(job.island)], e1 = mIslands.edgeStart[std::size_t(job.island) + 1];
    for (int j = b0; j < b1; ++j) localOf(mIslands.bodies[std::size_t(j)]);
    const int k = hooks.frictionDirections();
    const int nc = e1 - e0;
    out.contacts.assign(mIslands.edges.begin() + e0, mIslands.edges.begin() + e1);
    out.impulses.assign(std::size_t(nc), PgsWarm<D>{});
    bool approximateGuess = false;
    for (int ci = 0; ci < nc; ++ci) {
        const StepContact<D>& c = mContacts[std::size_t(out.contacts[std::size_t(ci)])];
        ContactNode<D> node = makeContact<D>(localOf(c.bodyA), localOf(c.bodyB), c.point, c.normal, c.restitution,
                                             c.friction);
        const double sep = c.separation;
        // Bounces are resolved at the time of impact (split into a velocity and a position answer):
        //   - A contact that will not close within this step at its current approach speed is only speculative:
        //     e = 0 and bias -sep/dt keep its gap >= 0 without any early rebound (it bounces in the step it closes).
        //   - A contact that closes within the step bounces: the velocity solve targets v+ = e u (bias 0, no
        //     position correction, which would add energy). With constant speed u over the step the surfaces
        //     meet at t* = sep/u and then separate at e u, so the gap at the end of the step is e (u dt - sep);
        //     moving the bodies by dt v+ would leave it sep + e u dt, (1 + e) sep too wide, and the apex up to
        //     (1 + e) u dt too high. The positions therefore move by a second solve of the same island whose
        //     bouncing contacts get bias -(1 + e) sep / dt (for sep < 0, a push-out of the overshoot, capped like
        //     position correction); the velocities stay those of the first solve.
        const double vrel = relativeNormalVelocity(rb, node);
        const bool approachesFast = c.restitution > 0.0 && vrel < -def.restitutionThreshold;
        const bool bounces = approachesFast && sep + dt * vrel < 0.0;
        double moveBias;
        if (bounces) {
            node.bias = 0.0;
            moveBias = std::min(def.maxCorrectionSpeed, -(1.0 + c.restitution) * sep / dt);
            out.split = out.split || moveBias != 0.0;  // touching at the step's start (the cradle): one solve does both
        } else if (sep > 0.0) {
            if (approachesFast) node.restitution = 0.0;
            node.bias = -sep / dt;
            moveBias = node.bias;
        } else {
            node.bias = std::min(def.maxCorrectionSpeed, def.baumgarte * std::max(0.0, -sep - def.linearSlop) / dt);
            moveBias = node.bias;
        }
        out.positionBias.push_back(moveBias);
        out.nodes.push_back(node);
        // Warm start: which of this contact's unknowns were basic last step, and the impulses they carried.
        if (const int at = mHit[std::size_t(out.contacts[std::size_t(ci)])]; at >= 0) {
            const ContactKey& hit = cache.at(at);
            appendWarmBasis(hit.basicMask, ci, nc, k, out.warm);
            if (hit.basicMask & kActiveSetEntry) ++out.activeSetContacts;
            const int run = (hit.basicMask & kSettledEntry) ? int((hit.basicMask & kSettledCount) >> kSettledShift) : 0;
            if (run == 3) ++out.settledContacts;
            out.settledRun = std::min(out.settledRun, run);
            out.pathStallRun = std::max(out.pathStallRun, int((hit.basicMask & kPathStallCount) >> kPathStallShift));
            out.declined = out.declined || (hit.basicMask & kDeclinedEntry) != 0;
            approximateGuess = approximateGuess || (hit.basicMask & kApproximateEntry) != 0;
            out.impulses[std::size_t(ci)].normal = hit.normalImpulse;
            out.impulses[std::size_t(ci)].tangent = D::fromComponents(hit.tangentImpulse);
        } else {
            out.settledRun = 0;  // a new contact: the island's quiet run starts again
        }
    }
    if (approximateGuess) out.warm.clear();  // cold (see kApproximateEntry)
    for (int d : local) localIndex[std::size_t(d)] = -1;  // leave the map clean for the next island
}

namespace world_step_detail {

/// ceil(total / count) as a cache cost, saturated at the largest 32-bit value.
inline std::uint32_t perContactCost(std::uint64_t total, int count) {
    const std::uint64_t c = count > 0 ? (total + std::uint64_t(count) - 1) / std::uint64_t(count) : 0;
    return c > 0xffffffffu ? 0xffffffffu : std::uint32_t(c);
}

}  // namespace world_step_detail

template <class D>
template <class H>
void WorldStep<D>::solveIsland(H& hooks, Job& job, Worker& worker) {
    using world_step_detail::isDynamic;
    const auto& def = hooks.def();
    const auto& cold = hooks.bodies().coldArray();
    prepareIsland(hooks, job, worker);
    IslandSetup& setup = worker.setup;
    std::vector<ResolverBody<D>>& rb = setup.bodies;
    std::vector<ContactNode<D>>& nodes = setup.nodes;
    const int nc = int(nodes.size());
    const int k = hooks.frictionDirections();
    const int pivotsPerUnknown = hooks.frictionPivotsPerUnknown();
    const bool budgeted = mControl.budget > 0;
    StepStats& stats = worker.solved;  // sums and maxima: the same whichever worker counts them
    ResolverOptions options;
    options.restitutionThreshold = def.restitutionThreshold;
    options.frictionDirections = k;
    options.tangentDeadZone = def.tangentDeadZone;
    options.acceptResidual = hooks.acceptResidual();
    options.lcp = def.lcp;
    // Work of this attempt: each LCP's assembly (counted here) and the solver's own units. With a budget, every
    // solve gets what is left of the island's grant as its work limit.
    std::uint64_t spent = 0;
    const std::uint64_t kDirs = std::uint64_t(D::frictionDirectionCount(k));
    // Lemke checks its limit between pivots, so a solve is started only when what is left also covers its first
    // factorisation: a warm start's block of g unknowns costs at most g^2 + n units (LcpResult::work: the factor's
    // nonzeros), a cold start none.
    // Each pivot is also charged work::kPerPivot for the factorisations around it that the solver does not count.
    // With a budget, what is left of the grant is split between a pivot cap (at that charge plus about 6 units per
    // unknown, the solver's own count of a pivot on a sparse block of half the unknowns) and the solver's work
    // limit, so that the two together stay within the grant.
    // Lemke's limits for `left` work units: a pivot cap (never above the current one) and the solver's work limit
    // (never above `workCap`, 0: none).
    auto limitLemke = [&](std::uint64_t left, std::uint64_t unknowns, std::uint64_t workCap) {
        std::uint64_t pivots = std::max<std::uint64_t>(1, left / (work::kPerPivot + 6 * unknowns));
        pivots = std::min(pivots, std::uint64_t(options.lcp.maxPivots));
        options.lcp.maxPivots = int(pivots);
        const std::uint64_t lemke = left > work::kPerPivot * pivots ? left - work::kPerPivot * pivots : 1;
        options.lcp.maxWork = workCap > 0 ? std::min(workCap, lemke) : lemke;
    };
    auto limitFor = [&](std::uint64_t assembly, std::uint64_t firstFactor, std::uint64_t unknowns) -> bool {
        if (budgeted && spent + assembly + firstFactor >= job.grant) return false;
        spent += assembly;
        if (!budgeted) return true;
        limitLemke(job.grant - spent, unknowns, def.lcp.maxWork);
        return true;
    };
    auto charge = [&](const Resolution& res) {
        spent += res.work + work::kPerPivot * std::uint64_t(res.pivots);
        stats.lcpWork += res.work;
    };
    // The friction LCP; if it fails, in 2D the frictionless LCP keeps the island from falling through (it always has
    // a solution for approaching contacts between bodies that can move), and in 3D the approximation follows
    // (kFailedIslandSweeps3 sweeps without a budget, the budget's sweeps with one): a failing 3D island is a landing
    // heap whose frictionless answers let it spread, where the approximation keeps it together.
    // A frame must not stall, so the friction solve gets at most c n + 100 pivots (n = (k + 2) nc unknowns,
    // c = hooks.frictionPivotsPerUnknown(): 8 in 2D, 2 in 3D; kPathLemkePivotsPerUnknown = 2, and a quarter of the
    // path's work (kPathLemkeWorkShare), behind a path answer that did not certify on an island of kPathFirstContacts
    // or more, in 3D kPathLemkeWorkCap3, a held near miss included). A settled island takes about n/2, but a tall
    // structure that stands by friction alone takes 2-5n while it lands (cold starts of the card house, n = 400-700),
    // and a cut-off path there is not a stalled one: the frictionless answer lets the structure slide, the next step
    // starts farther from rest, and the island keeps failing until it has collapsed. def.lcp.maxPivots overrides both
    // caps. With a budget, a friction solve that ran out of work ends the attempt (the island is approximated
    // instead); only a 2D failure of another kind tries the frictionless LCP (on a big island the active-set path
    // first, then Lemke).
    // A settled island (every contact marked kSettledEntry with a full run) goes to the active-set path, which sees
    // tangential velocities exactly, unless the path gave it back before (kDeclinedEntry).
    const bool handedOver = D::kDim == 2 && nc > 0 && setup.settledRun == 3 && !setup.declined;
    auto usable = [](const Resolution& res) { return res.status == LcpStatus::solved || res.approximate; };
    std::vector<ResolverBody<D>> pathBodies;  // 3D: the bodies after a path near miss held in reserve
    Resolution pathNearMiss;
    // approximateInstead: a failed friction solve ends the attempt, and the bounded approximation follows instead of
    // the frictionless LCP (3D velocity solves; a failed 3D position solve keeps the frictionless fallback).
    auto solve = [&](std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& inNodes,
                     const std::vector<int>* inWarm, bool approximateInstead) {
        bool reserved = false;
        bool pathFailed = false;     // a big island whose path answer did not certify (3D: kPathLemkeWorkCap3 or more
                                     // contacts; a held near miss did not certify either)
        std::uint64_t pathWork = 0;  // the path's own work units on this island
        Resolution res;
        res.status = LcpStatus::pivot_limit;
        const std::uint64_t frictionRows = (kDirs + 1) * std::uint64_t(nc);
        const std::uint64_t guess = inWarm ? std::uint64_t(inWarm->size()) : 0;
        const std::uint64_t firstFactor = guess > 0 ? guess * guess + (kDirs + 2) * std::uint64_t(nc) : 0;
        options.lcp.maxPivots = def.lcp.maxPivots > 0 ? def.lcp.maxPivots : pivotsPerUnknown * (k + 2) * nc + 100;
        // One 2D contact: resolveWithFriction's closed form, which assembles nothing (charged the rest of an
        // assembly below if it hands over to Lemke).
        const bool closedForm = D::kDim == 2 && nc == 1;
        const std::uint64_t assembly = world_step_detail::assemblyWork(frictionRows);
        if (!limitFor(closedForm ? work::kClosedFormIsland : assembly, firstFactor, (kDirs + 2) * std::uint64_t(nc)))
            return res;
        options.lcp.warmBasis = inWarm && !inWarm->empty() ? inWarm : nullptr;
        bool done = false;
        // The active-set path (2D) answers islands that start cold or that it answered last step; an island that
        // Lemke answered goes on with Lemke's warm start (its basis is a vertex, usually right as it stands). The
        // active-set path's own answers are interior points of a pile's degenerate face (more positive impulses than
        // the bodies have degrees of freedom), so Lemke's check of them as a basis is refused; it is not tried first
        // (measured on the 40-row large pyramid: refused on every step, 200 ms each).
        const bool activeSetFirst = !options.lcp.warmBasis || 2 * setup.activeSetContacts >= nc || handedOver;
        // A big island goes to the path even when Lemke answered it last step: while a pile lands, Lemke's warm
        // starts take thousands of pivots of O(n) each (minutes on the 40-row testbed pyramid), where the path with
        // its interior-point restart takes a few factorisations (kPathFirstContacts, step_support.h).
        // 3D islands take the path with the pyramid of four directions only (its friction set is a box in the path's
        // coordinates, core/active_set3_impl.h).
        const bool pathFits = D::kDim == 2 || D::frictionDirectionCount(k) == 4;
        const int pathFirst = D::kDim == 2 ? kPathFirstContacts : kPathFirstContacts3;
        const bool bigIsland = nc >= pathFirst && !setup.declined;
        const bool hugeIsland = nc >= kHugeIslandContacts && !setup.declined;
        const int pathMin = D::kDim == 2 ? kActiveSetMinContacts : kPathFirstContacts3;
        // The path's warm start, per contact: the normal impulse, then the friction impulse's components (0 with
        // `friction` false).
        auto pathWarm = [&](bool friction) {
            std::vector<double> warm;
            warm.reserve(std::size_t(nc) * std::size_t(1 + D::kDim));
            for (const PgsWarm<D>& w : setup.impulses) {
                warm.push_back(w.normal);
                for (int d = 0; d < D::kDim; ++d) warm.push_back(friction ? w.tangent[d] : 0.0);
            }
            return warm;
        };
        // What every path solve of this island shares.
        auto pathSettings = [&]() {
            ActiveSetOptions o;
            o.patternCache = &worker.patterns;
            o.scratch = &worker.activeSet;
            // A big island's cold first step takes the primal-dual iteration from zero impulses: from the
            // interior-point answer Box2D v3's 100-row large pyramid's first step took 1.4-2.0 s instead of 3.6-4.2,
            // but its next 149 steps 16 % more work (docs/solver-notes.md).
            o.coldInteriorPoint = false;
            // A big island's iterations are factorisations of thousands of unknowns: a near miss at the floor of
            // the warm start's face ends there (kFloorExit, step_support.h).
            if (hugeIsland) {
                o.floorExit = kFloorExit;
                o.reuseSupersetPattern = true;
            }
            // With a budget the path stops at what is left of the island's grant, as Lemke does.
            if (budgeted) o.maxWork = job.grant > spent ? job.grant - spent : 1;
            return o;
        };
        if (pathFits && nc >= pathMin && (activeSetFirst || bigIsland)) {
            const std::vector<double> warmImpulses = pathWarm(true);
            ActiveSetOptions fastOptions = pathSettings();
            fastOptions.interiorPoint = bigIsland;  // smaller islands have Lemke behind the path (kPathFirstContacts)
            // 3D landings start farther from their answer (cubes sliding on edges): phase 1 gets more iterations.
            if (D::kDim == 3) fastOptions.maxIterations = kPathIterations3;
            if (hugeIsland) fastOptions.stickWrongWaySlip = true;
            // The cache carries this answer's prediction for the next step (ActiveSetOptions::incomingVelocity), which
            // needs the velocity each body brought into the step: its velocity before this step's gravity (dynamic
            // bodies; the others keep moving as they do). Islands of kHugeIslandContacts or more carry the answer
            // itself: on Box2D v3's 40-row large pyramid the prediction cost 12 % more instructions over 300 steps
            // (docs/solver-notes.md).
            // Per body: the linear components, then the angular ones (2D: vx, vy, omega; 3D: 6).
            std::vector<double>& incoming = worker.incoming;
            if (D::kDim == 3 || !hugeIsland) {
                constexpr std::size_t stride = D::kDim == 2 ? 3 : 6;
                incoming.resize(stride * ioBodies.size());
                for (std::size_t kk = 0; kk < ioBodies.size(); ++kk) {
                    const ResolverBody<D>& B = ioBodies[kk];
                    const bool dynamic = isDynamic(cold[std::size_t(setup.local[kk])]);
                    const typename D::Vec v =
                        dynamic ? D::sub(B.velocity, D::scale(1.0 / def.hz, def.gravity)) : B.velocity;
                    double* out = &incoming[stride * kk];
                    for (int a = 0; a < D::kDim; ++a) out[a] = v[a];
                    if constexpr (D::kDim == 2)
                        out[2] = B.angularVelocity;
                    else
                        for (int a = 0; a < 3; ++a) out[3 + a] = B.angularVelocity[a];
                }
                fastOptions.incomingVelocity = &incoming;
            }
            ResolverOptions pathOptions = options;
            // The path resolves creep below the dead zone (kSettledEntry). An island that lands on the path is never
            // handed over, so below kHugeIslandContacts it takes tangential velocities exactly from the start: with the
            // 1e-7 m/s dead zone the settled 20-row testbed pyramid moved 2.2e-8 m from 5 s to 25 s, without 4.4e-10,
            // and the settled 30-row one re-solved its face on every other step.
            if (handedOver || (bigIsland && !hugeIsland)) pathOptions.tangentDeadZone = 0.0;
            // A 3D near miss of the path above kPathAccept3 (scaled) is held in reserve: Lemke tries the island, and
            // the near miss is applied only if Lemke fails too (instead of the frictionless fallback).
            const bool reserveNearMiss = D::kDim == 3;
            if (reserveNearMiss) pathBodies = ioBodies;
            Resolution fast = resolveActiveSet(ioBodies, inNodes, warmImpulses, pathOptions, fastOptions);
            charge(fast);
            pathWork = fast.work;
            if (fast.interiorPoint) ++stats.interiorPointRestarts;
            if (usable(fast) && reserveNearMiss && fast.approximate && fast.scaledResidual > kPathAccept3) {
                ioBodies.swap(pathBodies);  // the bodies before the path; pathBodies holds its near miss
                pathNearMiss = std::move(fast);
                reserved = true;
            } else if (usable(fast)) {
                res = std::move(fast);
                done = true;
                ++stats.activeSetIslands;
            }
            pathFailed = bigIsland && !done && (D::kDim == 2 || nc >= kPathLemkeWorkCap3);
        }
        auto useReserve = [&]() {
            ioBodies.swap(pathBodies);
            res = std::move(pathNearMiss);
            reserved = false;
            done = true;
            ++stats.activeSetIslands;
        };
        if (!done && reserved && budgeted && spent >= job.grant) useReserve();
        if (!done && budgeted && spent >= job.grant) return res;  // the path used the grant: the approximation follows
        if (!done) {
            // Lemke behind a path answer that did not certify on a big island (3D: of kPathLemkeWorkCap3 contacts or
            // more): the smaller cap (the frame must not stall on a solve that measured runs never saw finish;
            // kPathLemkePivotsPerUnknown, the 3D world's own cap in 3D) and a quarter of the work the path spent
            // (kPathLemkeWorkShare), never above what a budget left it (limitFor).
            const std::uint64_t maxWorkBefore = options.lcp.maxWork;
            if (pathFailed && def.lcp.maxPivots <= 0) {
                options.lcp.maxPivots =
                    std::min(options.lcp.maxPivots, kPathLemkePivotsPerUnknown * (k + 2) * nc + 100);
                // ... and at most a quarter of the work the path spent, split between pivots and the solver's own
                // units as a budget's grant is (limitFor): on the 2000-circle pile's landing such a Lemke run cost
                // 17-30 times the path's work (0.3-1.3 s on islands of 450-930 contacts, 18 s on one of 5450) and
                // never finished; on the 3D drop heap's islands of 373-900 contacts, 0.5-3 s a step, it never
                // finished either, nor with the whole of the path's work (kPathLemkeWorkShare).
                limitLemke(pathWork / kPathLemkeWorkShare, (kDirs + 2) * std::uint64_t(nc), options.lcp.maxWork);
            }
            res = resolveWithFriction(ioBodies, inNodes, options, worker.solver);
            options.lcp.maxWork = maxWorkBefore;
            charge(res);
            if (closedForm && !res.fastPath && assembly > work::kClosedFormIsland) spent += assembly - work::kClosedFormIsland;
            if (reserved && !usable(res)) useReserve();
        }
        if (options.lcp.warmBasis) {
            if (!res.warmStarted) ++stats.discardedGuesses;
            if (usable(res)) stats.basisChange += basisDistance(*options.lcp.warmBasis, res.basis);
        }
        if (res.approximate) ++stats.acceptedInexact;
        if (!usable(res) && !(budgeted && res.status == LcpStatus::pivot_limit)) {
            ++stats.failedIslands;
            const int spentPivots = res.pivots;  // the failed friction solve's pivots count too
            const std::uint64_t spentWork = res.work;
            bool answered = false;
            // A big 2D island's frictionless LCP goes to the active-set path first, from last step's normal
            // impulses: it is convex (the interior point's relaxation is the problem itself), and a pile's
            // frictionless Lemke takes thousands of pivots of O(n) each (a 5500-contact circle pile: 1-46 thousand,
            // up to 14 s). Its answer is certified against the frictionless LCP by the same residual rule; when it
            // is not, the frictionless Lemke follows as before.
            if (D::kDim == 2 && bigIsland && !(budgeted && spent >= job.grant)) {
                std::vector<ContactNode<D>> frictionless = inNodes;
                for (ContactNode<D>& node : frictionless) node.friction = 0.0;
                ResolverOptions smoothPath = options;
                smoothPath.tangentDeadZone = 0.0;
                Resolution smooth = resolveActiveSet(ioBodies, frictionless, pathWarm(false), smoothPath, pathSettings());
                charge(smooth);
                if (usable(smooth)) {
                    // Written back as a frictionless answer: no friction impulses, the normal unknowns' basis.
                    smooth.tangentImpulses.clear();
                    smooth.predictedImpulses.clear();
                    smooth.basis.clear();
                    for (int c = 0; c < nc; ++c)
                        if (smooth.impulses[std::size_t(c)] > 0.0) smooth.basis.push_back(c);
                    res = std::move(smooth);
                    res.pivots += spentPivots;
                    res.work += spentWork;
                    answered = true;
                    ++stats.activeSetIslands;
                }
            }
            options.lcp.maxPivots = def.lcp.maxPivots > 0 ? def.lcp.maxPivots : 10 * nc + 1000;
            if (!answered && !approximateInstead &&
                limitFor(world_step_detail::assemblyWork(std::uint64_t(nc)), 0, std::uint64_t(nc))) {
                options.lcp.warmBasis = nullptr;
                res = resolveCollisions(ioBodies, inNodes, options, worker.solver);
                charge(res);
                res.pivots += spentPivots;
                res.work += spentWork;
            }
        }
        stats.pivots += res.pivots;
        stats.maxIslandPivots = std::max(stats.maxIslandPivots, res.pivots);
        if (usable(res)) {  // the answers the step applies
            stats.maxResidual = std::max(stats.maxResidual, res.residual);
            stats.maxScaledResidual = std::max(stats.maxScaledResidual, res.scaledResidual);
        }
        return res;
    };
    const std::vector<ResolverBody<D>> before = setup.split ? rb : std::vector<ResolverBody<D>>{};
    Resolution r = solve(rb, nodes, &setup.warm, D::kDim == 3);
    if (!setup.warm.empty()) ++stats.warmStartedIslands;
    if (setup.split && usable(r)) {
        // The position solve (see the bias comment in prepareIsland), warm-started from the velocity solve's basis.
        std::vector<ResolverBody<D>> moved = before;
        for (int ci = 0; ci < nc; ++ci) nodes[std::size_t(ci)].bias = setup.positionBias[std::size_t(ci)];
        const Resolution rp = solve(moved, nodes, &r.basis, false);
        if (usable(rp)) {
            for (int kk = 0; kk < int(setup.local.size()); ++kk) {
                const int d = setup.local[std::size_t(kk)];
                if (!isDynamic(cold[std::size_t(d)])) continue;
                mMove[std::size_t(d)] = {moved[std::size_t(kk)].velocity, moved[std::size_t(kk)].angularVelocity, true};
            }
        }
    }
    job.work += spent;
    if (budgeted && spent > job.grant) stats.overrun += spent - job.grant;
    if (!usable(r)) {  // no impulse this step: the approximation follows when there is a budget, and in 3D
        job.state = budgeted ? (r.status == LcpStatus::pivot_limit ? Job::State::ranOut : Job::State::failed)
                             : D::kDim == 3 ? Job::State::failed : Job::State::unsolved;
        if (job.state == Job::State::unsolved) ++stats.unsolvedIslands;
        return;
    }
    job.state = Job::State::exact;
    ++stats.exactIslands;
    const bool friction = !r.tangentImpulses.empty();
    // (Only a budgeted step predicts costs: without one they stay 0, so an unbudgeted world's state does not depend
    // on the work-unit weights.)
    const std::uint32_t cost = budgeted ? world_step_detail::perContactCost(spent, nc) : 0;
    std::vector<ContactKey>& keys = setup.keys;
    for (int ci = 0; ci < nc; ++ci) {
        StepContact<D>& c = mContacts[std::size_t(setup.contacts[std::size_t(ci)])];
        c.normalImpulse = r.impulses[std::size_t(ci)];
        if (friction) c.tangentImpulse = D::fromComponents(&r.tangentImpulses[std::size_t(D::kDim * ci)]);
        ContactKey key = keyOf(hooks, c);
        key.cost = cost;
        key.normalImpulse = c.normalImpulse;
        for (int d = 0; d < D::kDim; ++d) key.tangentImpulse[d] = c.tangentImpulse[d];
        if (!r.predictedImpulses.empty()) {  // the next step's warm start: the answer's prediction for it
            const double* next = &r.predictedImpulses[std::size_t(ci) * std::size_t(1 + D::kDim)];
            key.normalImpulse = next[0];
            for (int d = 0; d < D::kDim; ++d) key.tangentImpulse[d] = next[1 + d];
        }
        keys.push_back(key);
    }
    storeBasis(r.basis, nc, k, friction, keys.data());
    std::uint32_t mark = setup.declined ? kDeclinedEntry : 0u;
    if (r.activeSet) {
        // Marked: the island's next solve starts with the active-set path too (see the solve lambda).
        // A settled island keeps its mark while the path answers it, also on a step where a new contact joined
        // (most of its contacts settled): the dead zone is off again from the next step. A handed-over island whose
        // path answers left the warm start's face kPathStallLimit times in a row goes back to Lemke for good
        // (kDeclinedEntry).
        const bool staysSettled = !setup.declined && (handedOver || (D::kDim == 2 && 2 * setup.settledContacts > nc));
        const int stall = handedOver && !r.warmFace ? setup.pathStallRun + 1 : 0;
        if (stall >= kPathStallLimit)
            mark = kDeclinedEntry;
        else
            mark |= kActiveSetEntry | (staysSettled ? kSettledEntry | kSettledCount | (std::uint32_t(stall) << kPathStallShift) : 0u);
    } else if (D::kDim == 2 && friction && !setup.declined && r.warmStarted && r.pivots == 0 &&
               nc >= kActiveSetMinContacts) {
        mark |= kSettledEntry | (std::uint32_t(std::min(3, setup.settledRun + 1)) << kSettledShift);
    }
    for (int ci = 0; ci < nc; ++ci) keys[std::size_t(ci)].basicMask |= mark;
    for (int ci = 0; ci < nc; ++ci) {
        mNewEntry[std::size_t(setup.contacts[std::size_t(ci)])] = keys[std::size_t(ci)];
        mHasEntry[std::size_t(setup.contacts[std::size_t(ci)])] = 1;
    }
    writeVelocities(hooks, setup);
}

template <class D>
template <class H>
void WorldStep<D>::approximateIsland(H& hooks, Job& job, Worker& worker, int sweeps) {
    const auto& def = hooks.def();
    prepareIsland(hooks, job, worker);
    IslandSetup& setup = worker.setup;
    const int nc = int(setup.nodes.size());
    const PgsResult<D> p = solvePgs(setup.bodies, setup.nodes, setup.impulses, sweeps, def.restitutionThreshold, worker.pgs);
    job.work += job.minimum - std::uint64_t(work::kMinSweeps) * job.sweepWork + std::uint64_t(sweeps) * job.sweepWork;
    job.state = Job::State::approximate;
    ++worker.solved.approximateIslands;
    worker.solved.maxApproximateResidual = std::max(worker.solved.maxApproximateResidual, p.residual);
    // What the exact solve is predicted to cost next step: twice the share it ran out of; an island that was not
    // tried keeps each contact's last prediction (0 for new ones: the cold prior, see predictedNeed).
    const std::uint32_t doubled = job.grant > 0 ? world_step_detail::perContactCost(2 * job.grant, nc) : 0;
    const int k = D::frictionDirectionCount(hooks.frictionDirections());
    for (int ci = 0; ci < nc; ++ci) {
        StepContact<D>& c = mContacts[std::size_t(setup.contacts[std::size_t(ci)])];
        c.normalImpulse = p.normal[std::size_t(ci)];
        c.tangentImpulse = p.tangent[std::size_t(ci)];
        ContactKey key = keyOf(hooks, c);
        const int hit = mHit[std::size_t(setup.contacts[std::size_t(ci)])];
        key.cost = job.grant > 0 ? doubled : hit >= 0 ? cache.at(hit).cost : 0;
        key.normalImpulse = c.normalImpulse;
        for (int d = 0; d < D::kDim; ++d) key.tangentImpulse[d] = c.tangentImpulse[d];
        // What the impulses say about the basis (the normal where it pushes, the (at most two) pyramid directions
        // nearest the friction impulse, the slack where the impulse is on the cone's rim), marked approximate.
        key.basicMask = kApproximateEntry;
        if (c.normalImpulse > 0.0) {
            key.basicMask |= 1u;
            double best[2] = {0.0, 0.0};
            int which[2] = {-1, -1};
            for (int m = 0; m < k; ++m) {
                const double dp = D::dot(D::tangentDirection(c.normal, m, k), c.tangentImpulse);
                const int slot = dp > best[0] ? 0 : dp > best[1] ? 1 : 2;
                if (slot == 0) {
                    best[1] = best[0];
                    which[1] = which[0];
                }
                if (slot < 2) {
                    best[slot] = dp;
                    which[slot] = m;
                }
            }
            for (int w : which)
                if (w >= 0) key.basicMask |= 2u << w;
            const double t = std::sqrt(D::dot(c.tangentImpulse, c.tangentImpulse));
            if (t >= c.friction * c.normalImpulse * (1.0 - 1e-9) && t > 0.0) key.basicMask |= 2u << k;
        }
        mNewEntry[std::size_t(setup.contacts[std::size_t(ci)])] = key;
        mHasEntry[std::size_t(setup.contacts[std::size_t(ci)])] = 1;
    }
    writeVelocities(hooks, setup);
}

template <class D>
template <class H>
void WorldStep<D>::writeVelocities(H& hooks, const IslandSetup& setup) const {
    auto& hot = hooks.bodies().hotArray();
    const auto& cold = hooks.bodies().coldArray();
    for (int kk = 0; kk < int(setup.local.size()); ++kk) {
        const int d = setup.local[std::size_t(kk)];
        if (!world_step_detail::isDynamic(cold[std::size_t(d)])) continue;
        hot[std::size_t(d)].velocity = setup.bodies[std::size_t(kk)].velocity;
        hot[std::size_t(d)].angularVelocity = setup.bodies[std::size_t(kk)].angularVelocity;
    }
}

}  // namespace unison
