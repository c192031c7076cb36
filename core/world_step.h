// core/world_step.h — the world step of DESIGN.md written once for both dimensions: World2 and World3 differ only
// in geometry (shapes, narrowphase) and body math (rotation, inertia), which they supply through a small hooks
// object; everything else of the step is here.
//
// Owns: the dimension-free state and scratch of a step — the warm-start cache and the touching pairs (both part
// of a world's hashed state), the island-local body numbering, the per-body position velocities of bounce
// islands, the Lemke workspace and the last step's contacts and statistics.
// The step: gravity into velocities; broadphase proxies with their speculative reach and the world's narrowphase;
// islands by union-find (core/island); per awake island one Coulomb-pyramid LCP (core/contact_resolver,
// eq. (19)/(20) plus friction), warm-started from the previous step's basis matched through feature ids, with the
// frictionless LCP as fallback; a second, position-only solve for islands with a bounce at the time of impact;
// integration through the world's hook; sleeping; begin/end touch events.
// Invariants: every loop runs in dense body, island or contact order; no unordered containers; the cache comes
// out sorted by key; localIndex is all -1 between islands; move is reset every step and never hashed.
#pragma once

#include "contact_resolver.h"
#include "island.h"
#include "lcp.h"
#include "step_support.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace unison {

/// One contact point of a step: what the narrowphase found and the impulses the solve gave it.
template <class D>
struct StepContact {
    int bodyA = -1, bodyB = -1;   ///< dense body indices; the normal points away from B towards A
    int shapeA = 0, shapeB = 0;   ///< shape indices within the bodies
    typename D::Vec point = D::zeroVec();   ///< world position midway between the surfaces (m)
    typename D::Vec normal = D::zeroVec();  ///< world unit normal from B towards A
    double separation = 0.0;      ///< gap along the normal (m), negative when overlapping
    std::uint32_t feature = 0;    ///< stable feature id of the narrowphase
    double friction = 0.0, restitution = 0.0;      ///< mixed coefficients of the two shapes
    double normalImpulse = 0.0;                     ///< N s
    typename D::Vec tangentImpulse = D::zeroVec();  ///< N s, world frame
};

/// What the last step did.
struct StepStats {
    int islands = 0, awakeIslands = 0, contacts = 0;
    int candidates = 0;               ///< 3D: narrowphase points before the reduction to <= 4 per pair
    /// Lemke pivots of the step and of its costliest island, a failed friction solve's included (not only the
    /// frictionless fallback's that follows it).
    int pivots = 0, maxIslandPivots = 0;
    int warmStartedIslands = 0;       ///< islands whose friction LCP got a guessed basis (contacts matched to last step's)
    /// Friction solves whose guess was abandoned for a cold start (Lemke from the guess wandered past its cap, or
    /// the guess's block was singular): the cost of a guess gone stale.
    int discardedGuesses = 0;
    /// Sum over the friction solves that had a guess and gave a usable answer of |guess symmetric-difference
    /// answer| (unknowns basic in one and not the other): how far the active set moved since last step. A Lemke
    /// pivot changes at most two, so pivots >= basisChange / 2 unless a guess was discarded or corrected by block
    /// principal pivoting (LcpOptions::blockPivotRounds; 0 in 3D).
    int basisChange = 0;
    std::uint64_t work = 0;
    /// Largest complementarity residual of the answers the step applied (an island whose solves all failed applies
    /// nothing and is counted in unsolvedIslands instead).
    double maxResidual = 0.0;
    int failedIslands = 0;            ///< friction solves that did not give a usable answer (frictionless LCP used)
    int approximateIslands = 0;       ///< answers accepted by the world's acceptResidual
    int unsolvedIslands = 0;          ///< islands that got no impulse at all (both LCPs failed)
    double maxScaledResidual = 0.0;   ///< the same, scaled: residual / max(|A|, |b|)
    double maxPenetration = 0.0;      ///< m, deepest overlap among touching contacts
};

/// The step shared by World2 (D = Dim2) and World3 (D = Dim3). A world owns one and calls run(hooks) with a hooks
/// object H that provides (all in dense body indices):
///   bodies()                       the BodyStore; hot records have center, velocity, angularVelocity; cold records
///                                  type (an enum with staticBody/kinematicBody/dynamicBody), invMass, awake,
///                                  sleepTime
///   def()                          settings: hz, gravity, restitutionThreshold, linearSlop, baumgarte,
///                                  maxCorrectionSpeed, tangentDeadZone, enableSleep, linearSleepTolerance,
///                                  angularSleepTolerance, timeToSleep, lcp
///   frictionDirections()           k of the pyramid; acceptResidual(): see WorldDef2::acceptResidual (0: never)
///   speculativeBand()              a point with separation s > 0 and closing speed u (< 0 closing) enters the LCP
///                                  only when s + dt min(u, 0) < band (WorldDef3::speculativeBand; infinity: all)
///   transform(state)               the body's placement, as computeAabb() and narrowphase() take it
///   narrowphase(shapeA, xfA, shapeB, xfB, distance, stats)
///                                  the manifold of points with separation < distance: count, points[k] with
///                                  point, separation and feature id; normalOf(manifold, k) its normal
///   worldInvInertia(state, info)   world-frame inverse inertia of a dynamic body
///   integrate(dense, v, w, dt)     moves a body by velocities v, w over dt (centre, rotation, origin)
/// and the shapes (cold record `shapes`, each with friction and restitution) must have computeAabb(shape, xf)
/// (an Aabb with lower/upper) and findPairs(boxes, inactive) (the broadphase) found by argument lookup.
template <class D>
class WorldStep {
public:
    using Vec = typename D::Vec;
    using Ang = typename D::Ang;

    /// Advances the bodies of hooks.bodies() by one step of 1 / hz seconds.
    template <class H>
    void run(H& hooks);

    const std::vector<StepContact<D>>& contacts() const { return mContacts; }
    const std::vector<TouchEvent>& beginEvents() const { return mBegin; }
    const std::vector<TouchEvent>& endEvents() const { return mEnd; }
    const StepStats& stats() const { return mStats; }

    /// State (serialised by the worlds' transferState): previous-step contacts with their basis masks, and the
    /// body pairs (touchKey, a < b) that touched with overlap at the end of the last step.
    WarmStartCache cache;
    TouchPairs touching;

private:
    /// Velocities to integrate a body's position with when they differ from its velocity (bounce islands).
    struct Move {
        Vec velocity = D::zeroVec();
        Ang angularVelocity = D::zeroAng();
        bool set = false;
    };

    template <class H>
    void findContacts(H& hooks);
    template <class H>
    void solveIsland(H& hooks, const std::vector<int>& bodies, const std::vector<int>& contactIdx,
                     std::vector<ContactKey>& newCache);
    template <class H>
    ContactKey keyOf(H& hooks, const StepContact<D>& c) const;

    LemkeSolver mSolver;
    std::vector<StepContact<D>> mContacts;
    std::vector<int> mLocalIndex;  // dense body -> index in the island being solved (-1 outside)
    std::vector<Move> mMove;       // dense body -> position velocities of this step
    std::vector<TouchEvent> mBegin, mEnd;
    StepStats mStats;
};

namespace world_step_detail {

template <class Info>
bool isDynamic(const Info& info) {
    return info.type == decltype(info.type)::dynamicBody;
}

template <class Info>
bool isStatic(const Info& info) {
    return info.type == decltype(info.type)::staticBody;
}

template <class Info>
bool isKinematic(const Info& info) {
    return info.type == decltype(info.type)::kinematicBody;
}

}  // namespace world_step_detail

template <class D>
template <class H>
void WorldStep<D>::findContacts(H& hooks) {
    const auto& def = hooks.def();
    const auto& hot = hooks.bodies().hotArray();
    const auto& cold = hooks.bodies().coldArray();
    struct Proxy {
        int body, shape;
        double reach;  // how far the shape can move this step (m): dt (|v| + |w| extent)
    };
    std::vector<Proxy> proxies;
    std::vector<decltype(computeAabb(cold[0].shapes[0], hooks.transform(hot[0])))> boxes;
    std::vector<std::uint8_t> inactive;
    std::vector<decltype(hooks.transform(hot[0]))> xfs;
    xfs.reserve(hot.size());
    const double margin = def.speculativeDistance;
    const double band = hooks.speculativeBand();
    const double dt = 1.0 / def.hz;
    // Relative normal speed of two bodies at a point (A minus B along n; < 0 when closing), before the solve.
    auto closingSpeed = [](const auto& sa, const auto& sb, const Vec& p, const Vec& n) {
        const Vec va = D::add(sa.velocity, D::angularVelocityAt(sa.angularVelocity, D::sub(p, sa.center)));
        const Vec vb = D::add(sb.velocity, D::angularVelocityAt(sb.angularVelocity, D::sub(p, sb.center)));
        return D::dot(n, D::sub(va, vb));
    };
    auto length = [](const Vec& v) { return std::sqrt(D::dot(v, v)); };
    for (int d = 0; d < int(hot.size()); ++d) {
        const auto& st = hot[std::size_t(d)];
        const auto& info = cold[std::size_t(d)];
        xfs.push_back(hooks.transform(st));
        for (int s = 0; s < int(info.shapes.size()); ++s) {
            auto box = computeAabb(info.shapes[std::size_t(s)], xfs.back());
            // Speculative reach: a contact that can close within this step must already be in this step's LCP, or
            // fast bodies sink deep before they are seen (and position correction then adds energy). Static bodies
            // do not move (and a 3D plane's box is unbounded).
            double reach = 0.0;
            if (!world_step_detail::isStatic(info)) {
                const Vec half = D::scale(0.5, D::sub(box.upper, box.lower));
                const Vec mid = D::scale(0.5, D::add(box.upper, box.lower));
                const double extent = length(half) + length(D::sub(mid, st.center));
                reach = dt * (length(st.velocity) + D::angNorm(st.angularVelocity) * extent);
            }
            const double grow = margin + reach;
            box.lower = D::sub(box.lower, D::uniform(grow));
            box.upper = D::add(box.upper, D::uniform(grow));
            proxies.push_back({d, s, reach});
            boxes.push_back(box);
            inactive.push_back(world_step_detail::isDynamic(info) ? 0 : 1);
        }
    }
    for (const auto& [p, q] : findPairs(boxes, inactive)) {
        const Proxy& pa = proxies[std::size_t(p)];
        const Proxy& pb = proxies[std::size_t(q)];
        if (pa.body == pb.body) continue;
        const auto& shA = cold[std::size_t(pa.body)].shapes[std::size_t(pa.shape)];
        const auto& shB = cold[std::size_t(pb.body)].shapes[std::size_t(pb.shape)];
        const auto m = hooks.narrowphase(shA, xfs[std::size_t(pa.body)], shB, xfs[std::size_t(pb.body)],
                                         margin + pa.reach + pb.reach, mStats);
        for (int k = 0; k < m.count; ++k) {
            const auto& mp = m.points[std::size_t(k)];
            // A gap that the bodies' present motion cannot bring within `band` this step stays out of the LCP:
            // it adds no rows and joins no islands (the isotropic reach above finds such points for fast bodies,
            // and resting neighbours 1-2 cm apart would otherwise fuse separate stacks into one big island).
            if (mp.separation > 0.0 &&
                mp.separation + dt * std::min(0.0, closingSpeed(hot[std::size_t(pa.body)], hot[std::size_t(pb.body)],
                                                                 mp.point, hooks.normalOf(m, k))) >= band)
                continue;
            StepContact<D> c;
            c.point = mp.point;
            c.normal = hooks.normalOf(m, k);
            c.separation = mp.separation;
            c.feature = mp.id;
            c.bodyA = pa.body;
            c.bodyB = pb.body;
            c.shapeA = pa.shape;
            c.shapeB = pb.shape;
            c.friction = std::sqrt(shA.friction * shB.friction);  // mixing as in Box2D
            c.restitution = std::max(shA.restitution, shB.restitution);
            mContacts.push_back(c);
        }
    }
}

template <class D>
template <class H>
ContactKey WorldStep<D>::keyOf(H& hooks, const StepContact<D>& c) const {
    const auto& bodies = hooks.bodies();
    return ContactKey{bodies.idAt(c.bodyA).index1, bodies.idAt(c.bodyB).index1, std::uint16_t(c.shapeA),
                      std::uint16_t(c.shapeB), c.feature, 0};
}

template <class D>
template <class H>
void WorldStep<D>::solveIsland(H& hooks, const std::vector<int>& bodies, const std::vector<int>& contactIdx,
                               std::vector<ContactKey>& newCache) {
    using world_step_detail::isDynamic;
    const auto& def = hooks.def();
    const double dt = 1.0 / def.hz;
    auto& hot = hooks.bodies().hotArray();
    auto& cold = hooks.bodies().coldArray();
    // Local numbering: the island's dynamic bodies, then every static or kinematic body its contacts touch.
    std::vector<int> local;
    std::vector<ResolverBody<D>> rb;
    if (mLocalIndex.size() < hot.size()) mLocalIndex.resize(hot.size(), -1);
    auto localOf = [&](int dense) {
        const int known = mLocalIndex[std::size_t(dense)];
        if (known >= 0) return known;
        mLocalIndex[std::size_t(dense)] = int(local.size());
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
    for (int d : bodies) localOf(d);
    const int k = hooks.frictionDirections();
    std::vector<ContactNode<D>> nodes;
    std::vector<double> positionBias;  // per node: the bias of the position solve (differs on bouncing contacts)
    bool split = false;                // some contact bounces this step: positions need their own solve
    std::vector<int> warm;
    const int nc = int(contactIdx.size());
    for (int ci = 0; ci < nc; ++ci) {
        const StepContact<D>& c = mContacts[std::size_t(contactIdx[std::size_t(ci)])];
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
            split = split || moveBias != 0.0;  // touching at the step's start (the cradle): one solve does both
        } else if (sep > 0.0) {
            if (approachesFast) node.restitution = 0.0;
            node.bias = -sep / dt;
            moveBias = node.bias;
        } else {
            node.bias = std::min(def.maxCorrectionSpeed, def.baumgarte * std::max(0.0, -sep - def.linearSlop) / dt);
            moveBias = node.bias;
        }
        positionBias.push_back(moveBias);
        nodes.push_back(node);
        // Warm start: which of this contact's unknowns were basic last step.
        if (const ContactKey* hit = cache.find(keyOf(hooks, c))) appendWarmBasis(hit->basicMask, ci, nc, k, warm);
    }
    for (int d : local) mLocalIndex[std::size_t(d)] = -1;  // leave the map clean for the next island
    ResolverOptions options;
    options.restitutionThreshold = def.restitutionThreshold;
    options.frictionDirections = k;
    options.tangentDeadZone = def.tangentDeadZone;
    options.acceptResidual = hooks.acceptResidual();
    options.lcp = def.lcp;
    // The friction LCP; if it fails, the frictionless LCP keeps the island from falling through (it always has a
    // solution for approaching contacts between bodies that can move). A frame must not stall: a healthy path
    // takes about n/2 pivots, so 2n + 100 bounds a bad one (n = (k + 2) nc unknowns). def.lcp.maxPivots
    // overrides both caps.
    auto usable = [](const Resolution& res) { return res.status == LcpStatus::solved || res.approximate; };
    auto solve = [&](std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& inNodes,
                     const std::vector<int>* inWarm) {
        options.lcp.warmBasis = inWarm && !inWarm->empty() ? inWarm : nullptr;
        options.lcp.maxPivots = def.lcp.maxPivots > 0 ? def.lcp.maxPivots : 2 * (k + 2) * nc + 100;
        Resolution res = resolveWithFriction(ioBodies, inNodes, options, mSolver);
        if (options.lcp.warmBasis) {
            if (!res.warmStarted) ++mStats.discardedGuesses;
            if (usable(res)) mStats.basisChange += basisDistance(*options.lcp.warmBasis, res.basis);
        }
        if (res.approximate) ++mStats.approximateIslands;
        if (!usable(res)) {
            ++mStats.failedIslands;
            const int spentPivots = res.pivots;  // the failed friction solve's pivots count too
            const std::uint64_t spentWork = res.work;
            options.lcp.warmBasis = nullptr;
            options.lcp.maxPivots = def.lcp.maxPivots > 0 ? def.lcp.maxPivots : 10 * nc + 1000;
            res = resolveCollisions(ioBodies, inNodes, options, mSolver);
            res.pivots += spentPivots;
            res.work += spentWork;
        }
        mStats.pivots += res.pivots;
        mStats.maxIslandPivots = std::max(mStats.maxIslandPivots, res.pivots);
        mStats.work += res.work;
        if (usable(res)) {
            mStats.maxResidual = std::max(mStats.maxResidual, res.residual);
            mStats.maxScaledResidual = std::max(mStats.maxScaledResidual, res.scaledResidual);
        }
        return res;
    };
    const std::vector<ResolverBody<D>> before = split ? rb : std::vector<ResolverBody<D>>{};
    Resolution r = solve(rb, nodes, &warm);
    if (!warm.empty()) ++mStats.warmStartedIslands;
    if (split && usable(r)) {
        // The position solve (see the bias comment above), warm-started from the velocity solve's basis.
        std::vector<ResolverBody<D>> moved = before;
        for (int ci = 0; ci < nc; ++ci) nodes[std::size_t(ci)].bias = positionBias[std::size_t(ci)];
        const Resolution rp = solve(moved, nodes, &r.basis);
        if (usable(rp)) {
            for (int kk = 0; kk < int(local.size()); ++kk) {
                const int d = local[std::size_t(kk)];
                if (!isDynamic(cold[std::size_t(d)])) continue;
                mMove[std::size_t(d)] = {moved[std::size_t(kk)].velocity, moved[std::size_t(kk)].angularVelocity, true};
            }
        }
    }
    if (!usable(r)) {  // no impulse at all this step
        ++mStats.unsolvedIslands;
        return;
    }
    const bool friction = !r.tangentImpulses.empty();
    for (int ci = 0; ci < nc; ++ci) {
        StepContact<D>& c = mContacts[std::size_t(contactIdx[std::size_t(ci)])];
        c.normalImpulse = r.impulses[std::size_t(ci)];
        if (friction) c.tangentImpulse = D::fromComponents(&r.tangentImpulses[std::size_t(D::kDim * ci)]);
        newCache.push_back(keyOf(hooks, c));
    }
    storeBasis(r.basis, nc, k, friction, &newCache[newCache.size() - std::size_t(nc)]);
    for (int kk = 0; kk < int(local.size()); ++kk) {
        const int d = local[std::size_t(kk)];
        if (!isDynamic(cold[std::size_t(d)])) continue;
        hot[std::size_t(d)].velocity = rb[std::size_t(kk)].velocity;
        hot[std::size_t(d)].angularVelocity = rb[std::size_t(kk)].angularVelocity;
    }
}

template <class D>
template <class H>
void WorldStep<D>::run(H& hooks) {
    using world_step_detail::isDynamic;
    using world_step_detail::isKinematic;
    const auto& def = hooks.def();
    const double dt = 1.0 / def.hz;
    auto& store = hooks.bodies();
    auto& hot = store.hotArray();
    auto& cold = store.coldArray();
    const int nb = store.size();
    mStats = StepStats{};
    // 1. External forces into velocities (semi-implicit Euler).
    for (int d = 0; d < nb; ++d) {
        if (isDynamic(cold[std::size_t(d)]) && cold[std::size_t(d)].awake)
            hot[std::size_t(d)].velocity = D::add(hot[std::size_t(d)].velocity, D::scale(dt, def.gravity));
    }
    // 2-3. Broadphase and narrowphase (the world's geometry).
    mContacts.clear();
    findContacts(hooks);
    mStats.contacts = int(mContacts.size());
    // 4. Islands over dynamic bodies; every contact point joins its two bodies.
    std::vector<std::uint8_t> joins(std::size_t(nb), 0);
    for (int d = 0; d < nb; ++d) joins[std::size_t(d)] = isDynamic(cold[std::size_t(d)]) ? 1 : 0;
    std::vector<IslandEdge> edges;
    edges.reserve(mContacts.size());
    for (const StepContact<D>& c : mContacts) edges.push_back({c.bodyA, c.bodyB});
    const Islands islands = buildIslands(nb, joins, edges);
    mStats.islands = islands.count();
    // 5-7. Per island: wake or skip, solve, integrate, sleep.
    mMove.assign(std::size_t(nb), Move{});
    std::vector<ContactKey> newCache;
    std::vector<int> ibodies, icontacts;
    for (int isl = 0; isl < islands.count(); ++isl) {
        ibodies.assign(islands.bodies.begin() + islands.bodyStart[std::size_t(isl)],
                       islands.bodies.begin() + islands.bodyStart[std::size_t(isl) + 1]);
        icontacts.assign(islands.edges.begin() + islands.edgeStart[std::size_t(isl)],
                         islands.edges.begin() + islands.edgeStart[std::size_t(isl) + 1]);
        bool anyAwake = false;
        for (int d : ibodies) anyAwake = anyAwake || cold[std::size_t(d)].awake;
        if (!anyAwake) {  // a sleeping island keeps its warm-start data
            for (int ci : icontacts) {
                const ContactKey* hit = cache.find(keyOf(hooks, mContacts[std::size_t(ci)]));
                if (hit) newCache.push_back(*hit);
            }
            continue;
        }
        ++mStats.awakeIslands;
        for (int d : ibodies) cold[std::size_t(d)].awake = true;
        if (!icontacts.empty()) solveIsland(hooks, ibodies, icontacts, newCache);
        double minSleep = 1e300;
        for (int d : ibodies) {
            auto& s = hot[std::size_t(d)];
            auto& info = cold[std::size_t(d)];
            const Move& move = mMove[std::size_t(d)];
            if (move.set)
                hooks.integrate(d, move.velocity, move.angularVelocity, dt);
            else
                hooks.integrate(d, s.velocity, s.angularVelocity, dt);
            const bool slow = D::dot(s.velocity, s.velocity) <= def.linearSleepTolerance * def.linearSleepTolerance &&
                              D::angWithin(s.angularVelocity, def.angularSleepTolerance);
            info.sleepTime = slow ? info.sleepTime + dt : 0.0;
            minSleep = std::min(minSleep, info.sleepTime);
        }
        if (def.enableSleep && minSleep >= def.timeToSleep) {
            for (int d : ibodies) {
                cold[std::size_t(d)].awake = false;
                hot[std::size_t(d)].velocity = D::zeroVec();
                hot[std::size_t(d)].angularVelocity = D::zeroAng();
            }
        }
    }
    for (int d = 0; d < nb; ++d)  // kinematic bodies move on their own
        if (isKinematic(cold[std::size_t(d)]))
            hooks.integrate(d, hot[std::size_t(d)].velocity, hot[std::size_t(d)].angularVelocity, dt);
    cache.replace(newCache);
    // 8. Begin/end events (pairs of bodies touching with overlap) and the deepest overlap.
    TouchPairs now;
    for (const StepContact<D>& c : mContacts) {
        if (c.separation < 0.0) {
            mStats.maxPenetration = std::max(mStats.maxPenetration, -c.separation);
            std::uint64_t ka = touchKey(store.idAt(c.bodyA)), kb = touchKey(store.idAt(c.bodyB));
            if (kb < ka) std::swap(ka, kb);
            now.emplace_back(ka, kb);
        }
    }
    touchEvents(now, touching, mBegin, mEnd);
    touching.swap(now);
}

}  // namespace unison
