// core/world_step.h — the world step of DESIGN.md written once for both dimensions: World2 and World3 differ only
// in geometry (shapes, narrowphase) and body math (rotation, inertia), which they supply through a small hooks
// object; everything else of the step is here, as named stages that run() calls in order:
//   findContacts       (core/world_step_contacts.h) in parallel over bodies: gravity into awake dynamic bodies'
//                      velocities, then proxies with their speculative reach; the broadphase, the narrowphase, and
//                      the gathering of its points in pair order with each contact's edge, cache entry and touch
//                      pair, each in parallel
//   planIslands        islands by union-find (core/island), then in parallel over islands: sleeping ones keep
//                      their cache entries, awake ones wake their bodies; each awake island with contacts becomes a
//                      job with its predicted work and reserve
//   solveIslands       the budget split (core/step_budget), then exact solves (core/world_step_island.h) in two
//                      passes and the bounded approximation (core/pgs.h) for what the budget left unsolved, each
//                      pass in parallel over islands; without a budget, each island is integrated (finishIsland)
//                      right after its solve, on the same thread
//   finishIslands      integration through the world's hook and sleeping, in parallel over the islands not yet
//                      integrated
//   mergeResults       the workers' statistics, the cache entries in contact order; kinematic bodies; touch events
//
// Owns: the dimension-free state and scratch of a step — the warm-start cache and the touching pairs (both part of
// a world's hashed state), per-worker scratch (a LemkeSolver, the island-local body numbering), the per-body
// position velocities of bounce islands, the built-in thread pool, and the last step's contacts and statistics.
// Invariants: every serial loop runs in dense body, island or contact order; a parallel pass writes only the
// outputs of its own item (a pair's slots, an island's bodies, contacts and job), and what a pass produces is
// merged afterwards in item order (per-worker counts are sums of integers and maxima, which merge in any order),
// so the answer, the cache and StepStats are the same for any thread count; no
// unordered containers; the cache comes out sorted by key; a worker's localIndex is all -1 between islands; move
// is reset every step and never hashed.
#pragma once

#include "body_space_solve.h"
#include "contact_resolver.h"
#include "island.h"
#include <unison/lcp.h>
#include "pgs.h"
#include "step_budget.h"
#include "step_support.h"
#include "sweep_order.h"
#include "symmetric_pattern_lu.h"
#include "task_system.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <tuple>
#include <type_traits>
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
    /// Work units of the whole step (core/step_budget.h): collision, bookkeeping, LCP assembly and solves, and the
    /// approximation. Counted, never timed: the same on every peer.
    std::uint64_t work = 0;
    std::uint64_t lcpWork = 0;        ///< of which the Lemke solver's own units (LcpResult::work)
    std::uint64_t budget = 0;         ///< the step's budget in work units (0: unlimited)
    /// What no budget can cut: collision and bookkeeping plus every awake island's reserve (the approximation's
    /// setup and work::kMinSweeps sweeps). With a budget, work <= max(budget, minimumWork) + overrun.
    std::uint64_t minimumWork = 0;
    /// Work of exact attempts beyond the share they were given (the solver checks its limit between pivots, so a
    /// warm start's factorisation can pass it); 0 when every attempt kept to its share.
    std::uint64_t overrun = 0;
    /// Largest complementarity residual of the exact answers the step applied (an island whose solves all failed
    /// applies nothing and is counted in unsolvedIslands or approximateIslands instead).
    double maxResidual = 0.0;
    int failedIslands = 0;            ///< friction solves that did not give a usable answer (then 2D tries the
                                      ///< frictionless LCP; 3D applies the approximation: approximateIslands)
    int acceptedInexact = 0;          ///< exact-solve answers accepted by the world's acceptResidual
    int unsolvedIslands = 0;          ///< islands that got no impulse at all (2D, unlimited budget, both LCPs failed)
    int exactIslands = 0;             ///< islands with contacts whose LCP was solved
    int activeSetIslands = 0;         ///< friction LCPs answered by the active-set path (resolveActiveSet)
    int interiorPointRestarts = 0;    ///< active-set solves that restarted from the interior-point answer
    int approximateIslands = 0;       ///< islands with contacts given the bounded approximation (core/pgs.h)
    double maxApproximateResidual = 0.0;  ///< largest PgsResult::residual of an approximate island
    double maxScaledResidual = 0.0;   ///< the same, scaled: residual / max(|A|, |b|)
    double maxPenetration = 0.0;      ///< m, deepest overlap among touching contacts
};

/// How one call of WorldStep::run may spend: its budget and its threads.
struct StepControl {
    std::uint64_t budget = 0;  ///< work units (core/step_budget.h), 0 = unlimited
    TaskSystem tasks;          ///< worker count and an embedding job system (none: the built-in pool)
};

/// The step shared by World2 (D = Dim2) and World3 (D = Dim3). A world owns one and calls run(hooks, control)
/// with a hooks object H that provides (all in dense body indices; every const member may be called from several
/// threads at once):
///   bodies()                       the BodyStore; hot records have center, velocity, angularVelocity; cold records
///                                  type (an enum with staticBody/kinematicBody/dynamicBody), invMass, awake,
///                                  sleepTime
///   def()                          settings: hz, gravity, restitutionThreshold, linearSlop, baumgarte,
///                                  maxCorrectionSpeed, tangentDeadZone, enableSleep, linearSleepTolerance,
///                                  angularSleepTolerance, timeToSleep, lcp
///   frictionDirections()           k of the pyramid; acceptResidual(): see WorldDef2::acceptResidual (0: never)
///   frictionPivotsPerUnknown()     c of the friction LCP's pivot cap c n + 100 (n unknowns) when def().lcp.maxPivots is 0
///   speculativeBand()              a point with separation s > 0 and closing speed u (< 0 closing) enters the LCP
///                                  only when s + dt min(u, 0) < band (WorldDef3::speculativeBand; infinity: all)
///   speedBound(state, info, extent)  the fastest a point within `extent` of the centre can move with the body's
///                                  kinetic energy (asked only when the band is finite; it widens the reach)
///   transform(state)               the body's placement, as computeAabb() and narrowphase() take it
///   narrowphase(shapeA, xfA, shapeB, xfB, distance, stats)
///                                  the manifold of points with separation < distance: count, points[k] with
///                                  point, separation and feature id; normalOf(manifold, k) its normal
///   pairWork(shapeA, shapeB, manifold)  the narrowphase's work units for that pair (core/step_budget.h)
///   narrowphaseScope()             an object that lives while one thread runs a range of narrowphase pairs
///   parallelNarrowphase()          false when narrowphase() must run on one thread (it records into the world)
///   worldInvInertia(state, info)   world-frame inverse inertia of a dynamic body
///   integrate(dense, v, w, dt)     moves a body by velocities v, w over dt (centre, rotation, origin)
///   contactPoints()                the world's public contact list, which the step sizes and fills in contact order
///   contactPoint(stepContact)      a step contact as an entry of that list
/// and the shapes (cold record `shapes`, each with friction and restitution) must have computeAabb(shape, xf)
/// (an Aabb with lower/upper) and findPairs(boxes, inactive, cache) (the broadphase, with a SweepCache) found by
/// argument lookup.
template <class D>
class WorldStep {
public:
    using Vec = typename D::Vec;
    using Ang = typename D::Ang;

    /// Advances the bodies of hooks.bodies() by one step of 1 / hz seconds within control's budget and threads.
    template <class H>
    void run(H& hooks, const StepControl& control = {});

    const std::vector<StepContact<D>>& contacts() const { return mContacts; }
    const std::vector<TouchEvent>& beginEvents() const { return mBegin; }
    const std::vector<TouchEvent>& endEvents() const { return mEnd; }
    const StepStats& stats() const { return mStats; }
    /// Some body the last run() moved left the supported ranges (hooks.motionOk): only then need the world scan its
    /// bodies for the fault message. Bodies a step does not move keep the state the API checked when it was set.
    bool motionFault() const { return mMotionFault; }
    /// Takes over `other`'s thread pool and per-worker buffers (not state: a world restored from a snapshot keeps
    /// its threads).
    void takeScratch(WorldStep& other) {
        mPool = std::move(other.mPool);
        mWorkers = std::move(other.mWorkers);
    }

    /// State (serialised by the worlds' transferState): previous-step contacts with their basis masks, impulses and
    /// predicted costs, and the body pairs (touchKey, a < b) that touched with overlap at the end of the last step.
    WarmStartCache cache;
    TouchPairs touching;

private:
    /// Velocities to integrate a body's position with when they differ from its velocity (bounce islands).
    struct Move {
        Vec velocity = D::zeroVec();
        Ang angularVelocity = D::zeroAng();
        bool set = false;
    };
    /// An island made ready for a solve (prepareIsland): local bodies, contact nodes and warm starts.
    struct IslandSetup {
        std::vector<int> local;                 // local index -> dense body: the island's dynamic bodies, then the rest
        std::vector<ResolverBody<D>> bodies;    // (local)
        std::vector<int> contacts;              // (contacts) indices into mContacts, island order
        std::vector<ContactNode<D>> nodes;      // (contacts)
        std::vector<double> positionBias;       // (contacts) the position solve's bias (differs on bouncing contacts)
        bool split = false;                     // some contact bounces this step: positions need their own solve
        std::vector<int> warm;                  // the friction LCP's guessed basis from the cache
        std::vector<PgsWarm<D>> impulses;       // (contacts) last step's impulses (zero for new contacts)
        std::vector<ContactKey> keys;           // (contacts) the answer's cache entries, being built
        int activeSetContacts = 0;              // contacts whose last answer came from the active-set path
        int settledContacts = 0;                // contacts marked settled with a full run (kSettledEntry)
        int settledRun = 3;                     // the shortest settled run (0-3) among its contacts; 0 for a new one
        int pathStallRun = 0;                   // the longest run of path answers off the warm face (kPathStallCount)
        bool declined = false;                  // a contact carries kDeclinedEntry
        void clear() {
            activeSetContacts = 0;
            settledContacts = 0;
            settledRun = 3;
            pathStallRun = 0;
            declined = false;
            local.clear();
            bodies.clear();
            contacts.clear();
            nodes.clear();
            positionBias.clear();
            split = false;
            warm.clear();
            impulses.clear();
            keys.clear();
        }
    };
    /// Scratch of one worker thread; nothing in it changes an answer: its buffers keep their capacity, and what it
    /// keeps of an island (pattern analyses, the active-set path's last systems) only saves work on a later one.
    /// Each on cache lines of its own: a worker writes its counts and flags for every item, and a neighbour's
    /// solver fields sharing a line with them would be invalidated in the other core's cache each time.
    struct alignas(64) Worker {
        LemkeSolver solver;
        std::vector<int> localIndex;  // dense body -> index in the island being solved (-1 outside)
        std::vector<double> incoming;  // per island body: the velocity it brought into the step (solveIsland)
        IslandSetup setup;            // the island being solved
        PgsScratch<D> pgs;            // the approximation's working arrays
        SymmetricPatternCache patterns;  // the active-set path's analyses of recent steps' system patterns
        ActiveSetScratch activeSet;      // the active-set path's buffers and last system
        StepStats collide;            // narrowphase counts (candidates) of this worker's pairs
        std::uint64_t narrowWork = 0;  // the narrowphase's work units of the pairs this worker gathered
        int kinematicBodies = 0;      // kinematic bodies this worker met in findContacts' body pass
        bool graphChanged = false;    // findContacts: a body's flag or a contact's edge this worker wrote differs
        bool sleepers = false;        // findContacts: this worker met a dynamic body that is asleep
        bool shapesChanged = false;   // findContacts: a body's shape count differs from mShapeCount's
        StepStats solved;             // counts of the island solves this worker ran (merged by accumulate())
    };
    /// One awake island with contacts: what the allocation knows of it, and what its solve produced.
    struct Job {
        enum class State : std::uint8_t { pending, exact, ranOut, skipped, failed, approximate, unsolved };
        int island = 0;
        int contactCount = 0;
        std::uint64_t raw = 0;        // predicted work of the exact solve (ContactKey::cost and the prior)
        std::uint64_t need = 0;       // what a share must cover to try it: raw and a margin
        std::uint64_t minimum = 0;    // reserve: the approximation's setup and kMinSweeps sweeps
        std::uint64_t sweepWork = 0;  // one approximation sweep
        std::uint64_t grant = 0;      // exact share of the current pass (0: unlimited when the step has no budget)
        std::uint64_t extra = 0;      // approximation share beyond the reserve
        std::uint64_t work = 0;       // spent so far
        State state = State::pending;
    };

    template <class H>
    void findContacts(H& hooks);
    template <class H>
    void planIslands(H& hooks);
    template <class H>
    void solveIslands(H& hooks);
    template <class H>
    void finishIslands(H& hooks);
    /// Integrates one awake island's bodies and updates their sleep timers (the island's bodies only), and writes
    /// its contacts into the public list.
    template <class H>
    void finishIsland(H& hooks, int island);
    /// The island's contacts, as they are now, into hooks.contactPoints() (their own entries only).
    template <class H>
    void publishContacts(H& hooks, int island) const;
    template <class H>
    void mergeResults(H& hooks);

    // The island solve unit (world_step_island.h): explicit inputs (the job, the hooks' bodies of its island) and
    // outputs (the job's statistics, its bodies' velocities, its contacts' impulses and new cache entries), on any
    // worker.
    template <class H>
    void prepareIsland(H& hooks, const Job& job, Worker& worker) const;
    template <class H>
    void solveIsland(H& hooks, Job& job, Worker& worker);
    template <class H>
    void approximateIsland(H& hooks, Job& job, Worker& worker, int sweeps);
    /// The island's answer (setup.bodies) into its dynamic bodies' velocities.
    template <class H>
    void writeVelocities(H& hooks, const IslandSetup& setup) const;
    template <class H>
    ContactKey keyOf(H& hooks, const StepContact<D>& c) const;
    template <class H>
    std::uint64_t predictedNeed(H& hooks, int island) const;

    /// Runs body(begin, end, worker) over ranges covering [0, count) on the step's threads.
    template <class Body>
    void forRanges(int count, int minRange, Body&& body);
    /// Runs body(item, worker) for every item in [0, count) on the step's threads.
    template <class Body>
    void forEach(int count, int minRange, Body&& body) {
        forRanges(count, minRange, [&](int begin, int end, Worker& worker) {
            for (int i = begin; i < end; ++i) body(i, worker);
        });
    }

    StepControl mControl;                 // this call's budget and threads
    std::unique_ptr<ThreadPool> mPool;    // the built-in pool (workerCount > 1 and no job system of the world's)
    std::vector<Worker> mWorkers;         // one per worker index
    SweepCache mSweep;                    // the broadphase's last sort order (speed only: not state)
    std::vector<std::uint8_t> mIslandFault;  // per island: a body it moved left the supported ranges
    bool mMotionFault = false;            // some body the step moved did (motionFault())
    std::vector<StepContact<D>> mContacts;
    std::vector<int> mHit;                // per contact: its warm-start cache entry, or -1
    std::vector<ContactKey> mNewEntry;    // per contact: its entry for the next step's cache (if mHasEntry)
    std::vector<std::uint8_t> mHasEntry;  // per contact: 1 when its island wrote mNewEntry
    std::vector<StepContact<D>> mSlots;   // the narrowphase's points, kSlots per broadphase pair
    std::vector<int> mShapeCount;         // per body: its shape count when mFirst was made (findContacts)
    std::vector<int> mFirst;              // per body: its first broadphase proxy (prefix sums of mShapeCount)
    Islands mIslands;
    std::vector<int> mIslandScratch;      // buildIslands' union-find, kept for its capacity
    bool mIslandsBuilt = false;           // mIslands is buildIslands(mJoins, mEdges) (kept while neither changes)
    bool mGraphChanged = true;            // this step's mJoins or mEdges differ from the last step's
    bool mJobsKept = false;               // mJobs were built with every island awake and no budget (see planIslands)
    bool mJobsDescending = true;          // mJobs' contact counts never increase (then they are in solve order)
    bool mAllAwake = false;               // every dynamic body was awake when the step began (findContacts)
    std::vector<std::uint8_t> mAwake;     // per island: solved and integrated this step
    std::vector<int> mBareIslands;        // awake islands without contacts (no job), island order
    bool mFinishedInSolve = false;        // this step integrated each job's island right after its solve
    std::vector<std::uint64_t> mIslandNeed;  // per awake island with contacts, with a budget: predictedNeed()
    std::vector<std::uint8_t> mJoins;     // per body: 1 when it joins islands (dynamic), from findContacts
    std::vector<IslandEdge> mEdges;       // per contact: its two bodies (mJoins and mEdges are rewritten in place, so
                                          // each write can compare with the last step's value)
    std::vector<std::pair<std::uint64_t, std::uint64_t>> mTouch;  // per contact: its touch pair, {0, 0} if none
    std::vector<Job> mJobs;               // awake islands with contacts, island order
    std::uint64_t mFixedWork = 0;         // collision and bookkeeping of this step
    std::vector<Move> mMove;              // dense body -> position velocities of this step (unset between steps)
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

/// Work units of an exact attempt on an LCP of `rows` coupling rows beyond the solver's own (core/step_budget.h):
/// set-up, assembly and the warm start's factorisation.
inline std::uint64_t assemblyWork(std::uint64_t rows) {
    const std::uint64_t root = std::uint64_t(std::sqrt(double(rows)));  // correctly rounded, so the same everywhere
    return work::kPerIsland + work::kPerRow * rows + work::kPerRowRoot * rows * root;
}

/// Adds a worker's counts to the step's: sums of integers and maxima, so the result does not depend on which worker
/// solved which island, nor on the order of merging.
inline void accumulate(StepStats& into, const StepStats& from) {
    into.candidates += from.candidates;
    into.pivots += from.pivots;
    into.maxIslandPivots = std::max(into.maxIslandPivots, from.maxIslandPivots);
    into.warmStartedIslands += from.warmStartedIslands;
    into.discardedGuesses += from.discardedGuesses;
    into.basisChange += from.basisChange;
    into.work += from.work;
    into.lcpWork += from.lcpWork;
    into.overrun += from.overrun;
    into.maxResidual = std::max(into.maxResidual, from.maxResidual);
    into.failedIslands += from.failedIslands;
    into.acceptedInexact += from.acceptedInexact;
    into.unsolvedIslands += from.unsolvedIslands;
    into.exactIslands += from.exactIslands;
    into.approximateIslands += from.approximateIslands;
    into.activeSetIslands += from.activeSetIslands;
    into.interiorPointRestarts += from.interiorPointRestarts;
    into.maxApproximateResidual = std::max(into.maxApproximateResidual, from.maxApproximateResidual);
    into.maxScaledResidual = std::max(into.maxScaledResidual, from.maxScaledResidual);
}

}  // namespace world_step_detail

template <class D>
template <class Body>
void WorldStep<D>::forRanges(int count, int minRange, Body&& body) {
    const int workers = std::max(1, mControl.tasks.workerCount);
    if (workers > 1 && !mControl.tasks.enqueueTask && (!mPool || mPool->workerCount() != workers))
        mPool = std::make_unique<ThreadPool>(workers);
    if (int(mWorkers.size()) < workers) mWorkers.resize(std::size_t(workers));
    parallelFor(mControl.tasks, mPool.get(), count, minRange,
                [&](int begin, int end, int worker) { body(begin, end, mWorkers[std::size_t(worker)]); });
}

template <class D>
template <class H>
void WorldStep<D>::planIslands(H& hooks) {
    auto& cold = hooks.bodies().coldArray();
    const int nb = int(cold.size());
    // Bodies' dynamic flags and contacts' edges come from findContacts. The islands are a function of them alone,
    // so when neither changed since the last build (a resting scene), last step's islands are this step's.
    const bool islandsKept = mIslandsBuilt && !mGraphChanged;
    if (!islandsKept) buildIslands(nb, mJoins, mEdges, mIslands, mIslandScratch);
    mIslandsBuilt = true;
    const int ni = mIslands.count();
    mStats.islands = ni;
    mFixedWork += work::kPerContact * mContacts.size();
    // Each island in parallel: a sleeping one keeps its warm-start data; an awake one wakes all its bodies and, with
    // a budget, gets its predicted need. Without a budget and with every body awake (always so when sleeping is off),
    // that pass would only mark every island awake.
    if (mAllAwake && mControl.budget == 0) {
        mAwake.assign(std::size_t(ni), 1);
    } else {
        mAwake.assign(std::size_t(ni), 0);
        if (mControl.budget > 0) mIslandNeed.resize(std::size_t(ni));
        forEach(ni, 64, [&](int isl, Worker&) {
            const int b0 = mIslands.bodyStart[std::size_t(isl)], b1 = mIslands.bodyStart[std::size_t(isl) + 1];
            const int e0 = mIslands.edgeStart[std::size_t(isl)], e1 = mIslands.edgeStart[std::size_t(isl) + 1];
            bool anyAwake = false;
            for (int j = b0; j < b1 && !anyAwake; ++j)
                anyAwake = cold[std::size_t(mIslands.bodies[std::size_t(j)])].awake;
            if (!anyAwake) {
                for (int j = e0; j < e1; ++j) {
                    const int ci = mIslands.edges[std::size_t(j)];
                    if (mHit[std::size_t(ci)] < 0) continue;
                    mNewEntry[std::size_t(ci)] = cache.at(mHit[std::size_t(ci)]);
                    mHasEntry[std::size_t(ci)] = 1;
                }
                publishContacts(hooks, isl);  // a sleeping island's contacts, as found
                return;
            }
            mAwake[std::size_t(isl)] = 1;
            for (int j = b0; j < b1; ++j) cold[std::size_t(mIslands.bodies[std::size_t(j)])].awake = true;
            if (mControl.budget > 0 && e1 > e0) mIslandNeed[std::size_t(isl)] = predictedNeed(hooks, isl);
        });
    }
    // The jobs: awake islands with contacts, in island order. Without a budget, with every island awake and the
    // islands kept, they are last step's (built under the same conditions): a job holds only what the island and
    // its contact count give, and the solve pass resets the fields a solve writes.
    const bool allAwakeUnbudgeted = mAllAwake && mControl.budget == 0;
    if (allAwakeUnbudgeted && islandsKept && mJobsKept) {
        mStats.awakeIslands = ni;
        return;
    }
    mJobsKept = allAwakeUnbudgeted;
    mJobs.clear();
    mBareIslands.clear();
    mJobsDescending = true;
    constexpr std::uint64_t kRows = std::uint64_t(pgsTangentRows<D>() + 1);
    for (int isl = 0; isl < ni; ++isl) {
        if (!mAwake[std::size_t(isl)]) continue;
        ++mStats.awakeIslands;
        const int count = mIslands.edgeCount(isl);
        if (count == 0) {
            mBareIslands.push_back(isl);
            continue;
        }
        mJobsDescending = mJobsDescending && (mJobs.empty() || mJobs.back().contactCount >= count);
        Job& job = mJobs.emplace_back();
        job.island = isl;
        job.contactCount = count;
        const std::uint64_t rows = kRows * std::uint64_t(count);
        job.sweepWork = work::kPgsSweepPerRow * rows;
        job.minimum = work::kPgsPerIsland + work::kPgsSetupPerRow * rows + std::uint64_t(work::kMinSweeps) * job.sweepWork;
        if (mControl.budget > 0) {
            job.raw = mIslandNeed[std::size_t(isl)];
            job.need = job.raw + job.raw / 4;  // a quarter more as margin
        }
    }
}

template <class D>
template <class H>
std::uint64_t WorldStep<D>::predictedNeed(H& hooks, int isl) const {
    // Last step's exact work of these contacts (ContactKey::cost, per contact), and a cold solve's prior for the
    // contacts the cache does not know.
    const int e0 = mIslands.edgeStart[std::size_t(isl)], e1 = mIslands.edgeStart[std::size_t(isl) + 1];
    // An island with contacts the approximation answered last step solves cold (its guess is dropped), so its need
    // is at least the cold prior of all its unknowns.
    const std::uint64_t n = std::uint64_t(e1 - e0) * std::uint64_t(D::frictionDirectionCount(hooks.frictionDirections()) + 2);
    std::uint64_t known = 0;
    int unknown = 0;
    bool approximate = false;
    for (int j = e0; j < e1; ++j) {
        const int hit = mHit[std::size_t(mIslands.edges[std::size_t(j)])];
        approximate = approximate || (hit >= 0 && (cache.at(hit).basicMask & kApproximateEntry) != 0);
        if (hit >= 0 && cache.at(hit).cost > 0)
            known += cache.at(hit).cost;
        else
            ++unknown;
    }
    // A cold solve: its assembly, about n / 4 pivots with their factorisations, and the solver's own units.
    const std::uint64_t rows = std::uint64_t(e1 - e0) * std::uint64_t(D::frictionDirectionCount(hooks.frictionDirections()) + 1);
    const std::uint64_t prior = world_step_detail::assemblyWork(rows) + work::kPerPivot * (n / 4 + 1) +
                                work::kColdPerUnknownSquared * n * n;
    if (approximate) return std::max(known, prior);
    return known + prior * std::uint64_t(unknown) / std::uint64_t(e1 - e0);
}

template <class D>
template <class H>
void WorldStep<D>::solveIslands(H& hooks) {
    using State = typename Job::State;
    const int nj = int(mJobs.size());
    // Big islands first, so that one long solve does not start last on a thread (any order gives the same answer).
    // A counting sort by contact count, descending, jobs of equal count in job order (as a sort by (count desc,
    // job) would give, in O(jobs + largest count)).
    // (Jobs already in that order, as when every island has the same count, are taken as they are.)
    std::vector<int> order(mJobsDescending ? 0 : static_cast<std::size_t>(nj));
    if (!mJobsDescending) {
        int most = 0;
        for (const Job& job : mJobs) most = std::max(most, job.contactCount);
        std::vector<int> at(std::size_t(most) + 2, 0);  // at[most - c + 1]: jobs with more contacts than c
        for (const Job& job : mJobs) ++at[std::size_t(most - job.contactCount) + 1];
        for (std::size_t i = 1; i < at.size(); ++i) at[i] += at[i - 1];
        for (int j = 0; j < nj; ++j) order[std::size_t(at[std::size_t(most - mJobs[std::size_t(j)].contactCount)]++)] = j;
    }
    auto runPass = [&](auto&& fn) {
        forEach(nj, 1, [&](int i, Worker& worker) {
            fn(mJobs[std::size_t(mJobsDescending ? i : order[std::size_t(i)])], worker);
        });
    };
    // A new generation of the pattern caches: analyses unused for their keeping time are dropped (found or not, an
    // analysis never changes an answer).
    if (mWorkers.empty()) mWorkers.resize(1);
    for (Worker& w : mWorkers) {
        w.patterns.nextGeneration();
        w.solved = StepStats{};
    }
    std::uint64_t reserve = 0;
    for (const Job& job : mJobs) reserve += job.minimum;
    mStats.minimumWork = mFixedWork + reserve;
    mIslandFault.assign(std::size_t(mIslands.count()), 0);
    mFinishedInSolve = mControl.budget == 0;
    if (mControl.budget == 0) {  // unlimited: every island exact, as far as its LCP can be solved
        // Each island is integrated right after its solve, on the same thread, while its bodies are in its cache
        // (the integration reads nothing of other islands).
        runPass([&](Job& job, Worker& worker) {
            job.work = 0;  // kept jobs (planIslands) come with last step's
            job.state = State::pending;
            solveIsland(hooks, job, worker);
            // A 3D island whose friction solve failed: the approximation with kFailedIslandSweeps3 sweeps.
            if (job.state == State::failed) approximateIsland(hooks, job, worker, kFailedIslandSweeps3);
            worker.solved.work += job.work;  // (the budgeted passes' jobs are summed in mergeResults)
            finishIsland(hooks, job.island);
        });
        return;
    }
    // The budget: what collision and bookkeeping left, minus every island's reserve, is the exact pool.
    const std::uint64_t budget = mControl.budget;
    const std::uint64_t avail = budget > mFixedWork ? budget - mFixedWork : 0;
    std::uint64_t pool = avail > reserve ? avail - reserve : 0;
    // Pass 1: a max-min fair split of the pool by predicted need; an island tries its exact solve only when its
    // share covers its need (a share below it would most likely be spent for nothing).
    std::vector<std::uint64_t> demand(static_cast<std::size_t>(nj));
    for (int j = 0; j < nj; ++j) demand[std::size_t(j)] = mJobs[std::size_t(j)].need;
    std::vector<std::uint64_t> share = fairShares(demand, pool);
    for (int j = 0; j < nj; ++j) {
        Job& job = mJobs[std::size_t(j)];
        job.grant = share[std::size_t(j)] >= job.need ? job.need : 0;
        job.state = job.grant > 0 ? State::pending : State::skipped;
    }
    auto exactPass = [&] {
        runPass([&](Job& job, Worker& worker) {
            if (job.state == State::pending && job.grant > 0) solveIsland(hooks, job, worker);
        });
    };
    auto spent = [&] {
        std::uint64_t s = 0;
        for (const Job& job : mJobs) s += job.work;
        return s;
    };
    exactPass();
    // Pass 2: what pass 1 left goes to the islands it skipped, whole needs first-fit in ascending (need, island)
    // order: a fair split would give each of many equal islands too little to finish, and none would.
    std::uint64_t used = spent();
    pool = pool > used ? pool - used : 0;
    std::vector<int> skipped;
    for (int j = 0; j < nj; ++j)
        if (mJobs[std::size_t(j)].state == State::skipped) skipped.push_back(j);
    std::sort(skipped.begin(), skipped.end(), [&](int a, int b) {
        const std::uint64_t na = mJobs[std::size_t(a)].need, nb = mJobs[std::size_t(b)].need;
        return na != nb ? na < nb : a < b;
    });
    bool second = false;
    for (int j : skipped) {
        Job& job = mJobs[std::size_t(j)];
        if (job.need == 0 || job.need > pool) continue;
        pool -= job.need;
        job.grant = job.need;
        job.state = State::pending;
        second = true;
    }
    if (second) exactPass();
    // The approximation for every island left without an exact answer: its reserve, plus a fair part of what is
    // left (pool and the reserves of exact islands) as more sweeps, up to kMaxSweeps.
    used = spent();
    std::uint64_t approxReserve = 0;
    for (const Job& job : mJobs) approxReserve += job.state == State::exact ? 0 : job.minimum;
    const std::uint64_t after = avail > used ? avail - used : 0;
    const std::uint64_t left = after > approxReserve ? after - approxReserve : 0;
    for (int j = 0; j < nj; ++j) {
        const Job& job = mJobs[std::size_t(j)];
        demand[std::size_t(j)] = job.state == State::exact ? 0
                                 : std::uint64_t(work::kMaxSweeps - work::kMinSweeps) * job.sweepWork;
    }
    share = fairShares(demand, left);
    for (int j = 0; j < nj; ++j) mJobs[std::size_t(j)].extra = share[std::size_t(j)];
    runPass([&](Job& job, Worker& worker) {
        if (job.state == State::exact) return;
        const std::uint64_t extraSweeps = job.sweepWork > 0 ? job.extra / job.sweepWork : 0;
        const int more = int(std::min<std::uint64_t>(extraSweeps, work::kMaxSweeps - work::kMinSweeps));
        approximateIsland(hooks, job, worker, work::kMinSweeps + more);
    });
}

template <class D>
template <class H>
void WorldStep<D>::finishIsland(H& hooks, int isl) {
    publishContacts(hooks, isl);  // the island's contacts are solved (or left as found) by now
    const auto& def = hooks.def();
    const double dt = 1.0 / def.hz;
    auto& hot = hooks.bodies().hotArray();
    auto& cold = hooks.bodies().coldArray();
    const int b0 = mIslands.bodyStart[std::size_t(isl)], b1 = mIslands.bodyStart[std::size_t(isl) + 1];
    double minSleep = 1e300;
    for (int j = b0; j < b1; ++j) {
        const int d = mIslands.bodies[std::size_t(j)];
        auto& s = hot[std::size_t(d)];
        auto& info = cold[std::size_t(d)];
        Move& move = mMove[std::size_t(d)];
        if (move.set) {
            hooks.integrate(d, move.velocity, move.angularVelocity, dt);
            move.set = false;  // used: the next step starts with every entry unset
        } else {
            hooks.integrate(d, s.velocity, s.angularVelocity, dt);
        }
        const bool slow = D::dot(s.velocity, s.velocity) <= def.linearSleepTolerance * def.linearSleepTolerance &&
                          D::angWithin(s.angularVelocity, def.angularSleepTolerance);
        info.sleepTime = slow ? info.sleepTime + dt : 0.0;
        if (!hooks.motionOk(s)) mIslandFault[std::size_t(isl)] = 1;
        minSleep = std::min(minSleep, info.sleepTime);
    }
    if (def.enableSleep && minSleep >= def.timeToSleep) {
        for (int j = b0; j < b1; ++j) {
            const int d = mIslands.bodies[std::size_t(j)];
            cold[std::size_t(d)].awake = false;
            hot[std::size_t(d)].velocity = D::zeroVec();
            hot[std::size_t(d)].angularVelocity = D::zeroAng();
        }
    }
}

template <class D>
template <class H>
void WorldStep<D>::publishContacts(H& hooks, int isl) const {
    auto& out = hooks.contactPoints();
    const int e0 = mIslands.edgeStart[std::size_t(isl)], e1 = mIslands.edgeStart[std::size_t(isl) + 1];
    for (int j = e0; j < e1; ++j) {
        const std::size_t ci = std::size_t(mIslands.edges[std::size_t(j)]);
        out[ci] = hooks.contactPoint(mContacts[ci]);
    }
}

template <class D>
template <class H>
void WorldStep<D>::finishIslands(H& hooks) {
    if (mFinishedInSolve) {  // the islands with jobs were finished right after their solves
        forEach(int(mBareIslands.size()), 64, [&](int k, Worker&) { finishIsland(hooks, mBareIslands[std::size_t(k)]); });
        return;
    }
    forEach(mIslands.count(), 64, [&](int isl, Worker&) {
        if (mAwake[std::size_t(isl)]) finishIsland(hooks, isl);
    });
}

template <class D>
template <class H>
void WorldStep<D>::mergeResults(H& hooks) {
    using world_step_detail::isKinematic;
    const double dt = 1.0 / hooks.def().hz;
    auto& store = hooks.bodies();
    auto& hot = store.hotArray();
    const auto& cold = store.coldArray();
    mMotionFault = false;
    for (std::uint8_t f : mIslandFault) mMotionFault = mMotionFault || f != 0;
    int kinematic = 0;
    for (const Worker& w : mWorkers) kinematic += w.kinematicBodies;
    for (int d = 0; d < store.size() && kinematic > 0; ++d)  // kinematic bodies move on their own
        if (isKinematic(cold[std::size_t(d)])) {
            hooks.integrate(d, hot[std::size_t(d)].velocity, hot[std::size_t(d)].angularVelocity, dt);
            mMotionFault = mMotionFault || !hooks.motionOk(hot[std::size_t(d)]);
        }
    for (const Worker& w : mWorkers) world_step_detail::accumulate(mStats, w.solved);
    if (!mFinishedInSolve)  // without a budget each job's work was summed by its worker
        for (const Job& job : mJobs) mStats.work += job.work;
    // The next cache in contact order: contacts come in body-pair order, which is nearly the key order, so the sort
    // in replace() has little to do (in island order, each island's contacts with the ground would be far apart).
    // When every contact wrote its entry (the usual case), the entries are handed over as they are, without a copy;
    // the old cache's buffer becomes the next step's mNewEntry, whose entries are all written before they are read.
    if (std::find(mHasEntry.begin(), mHasEntry.end(), std::uint8_t(0)) == mHasEntry.end()) {
        cache.replace(mNewEntry);
    } else {
        std::vector<ContactKey> newCache;
        newCache.reserve(mContacts.size());
        for (std::size_t ci = 0; ci < mContacts.size(); ++ci)
            if (mHasEntry[ci]) newCache.push_back(mNewEntry[ci]);
        cache.replace(newCache);
    }
    mStats.work += mFixedWork;
    // Begin/end events (pairs of bodies touching with overlap) and the deepest overlap.
    TouchPairs now;
    for (std::size_t ci = 0; ci < mContacts.size(); ++ci) {
        if (mTouch[ci].first != 0) {
            mStats.maxPenetration = std::max(mStats.maxPenetration, -mContacts[ci].separation);
            now.push_back(mTouch[ci]);
        }
    }
    touchEvents(now, touching, mBegin, mEnd);
    touching.swap(now);
}

template <class D>
template <class H>
void WorldStep<D>::run(H& hooks, const StepControl& control) {
    mControl = control;
    mStats = StepStats{};
    mStats.budget = control.budget;
    mFixedWork = 0;
    findContacts(hooks);
    mStats.contacts = int(mContacts.size());
    // The public contact list: each island writes its own contacts' entries (a sleeping one in planIslands, an awake
    // one when it is finished), so the list is written in the parallel passes, while each contact is in the cache of
    // the thread that solved it.
    hooks.contactPoints().resize(mContacts.size());
    planIslands(hooks);
    // Every entry is unset here: finishIsland unsets what a solve set, and a body's entry is set only by the solve of
    // its own island, which is then finished in this step.
    if (mMove.size() != hooks.bodies().hotArray().size()) mMove.assign(hooks.bodies().hotArray().size(), Move{});
    solveIslands(hooks);
    finishIslands(hooks);
    mergeResults(hooks);
    // Every contact has a dynamic body (the broadphase pairs no two others), so every contact is an edge of some
    // island and was written above. Should one not be, the whole list is written again here.
    if (mIslands.edges.size() != mContacts.size()) {
        auto& out = hooks.contactPoints();
        for (std::size_t ci = 0; ci < mContacts.size(); ++ci) out[ci] = hooks.contactPoint(mContacts[ci]);
    }
}

}  // namespace unison

#include "world_step_contacts.h"
#include "world_step_island.h"
