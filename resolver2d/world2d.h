// resolver2d/world2d.h — the 2D world: bodies with shapes, and the step of DESIGN.md.
//
// Owns: the body store (generational ids, hot state separate from cold data), the contacts found each step, their
// warm-start cache keyed by feature ids, islands, sleeping, and the per-step events and statistics.
// The step: gravity into velocities; broadphase (sort and sweep, index order); narrowphase manifolds (<= 2 points
// per pair, stable feature ids); islands by union-find over dynamic bodies (statics never join); per island one
// Coulomb-pyramid LCP built by the paper's resolver and solved by Lemke, warm-started from the previous step's
// basis matched through feature ids; impulses applied; positions integrated; events recorded.
// Invariants: every loop runs in body, shape or contact index order; no unordered containers; no libm
// transcendental function (rotations are stored as cosine/sine and integrated without trigonometry).
#pragma once

#include "body_store.h"
#include "collide2d.h"
#include "dim2.h"
#include "input_policy.h"
#include <unison/lcp.h>
#include "query2d.h"
#include "scene_index.h"
#include "shapes2d.h"
#include "state_io.h"
#include "world_step.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace unison {

class CompactState;

/// How to create a body. Angles in radians, velocities in m/s and rad/s.
struct BodyDef2 {
    BodyType type = BodyType::dynamicBody;
    Vec2 position;           ///< origin of the body frame (m)
    double angle = 0.0;      ///< rad
    Vec2 linearVelocity;     ///< of the centre of mass (m/s)
    double angularVelocity = 0.0;
};

/// World settings. Defaults follow Box2D 2.4.1 where it has the same notion.
struct WorldDef2 {
    Vec2 gravity{0.0, -10.0};           ///< m/s^2
    double hz = 60.0;                    ///< steps per second
    double restitutionThreshold = 1.0;   ///< approach speeds below this (m/s) use e = 0
    double linearSlop = 0.005;           ///< allowed penetration (m)
    double baumgarte = 0.2;              ///< fraction of the penetration beyond the slop removed per step
    double maxCorrectionSpeed = 3.0;     ///< cap of the position-correction velocity (m/s)
    double speculativeDistance = 0.02;   ///< contacts this far apart are already in the LCP (m)
    /// Tangential speeds below this (m/s) are exactly 0 in the friction LCP. Resting piles creep at rounding level
    /// (1e-10 to 1e-8 m/s); once that creep crossed a 1e-8 dead zone, a settled 20-row pyramid needed thousands of
    /// Lemke pivots per step from about 20 s on. At 1e-7 it stays at 0 pivots for 60 s (top box drift 2e-8 m).
    double tangentDeadZone = 1e-7;
    bool enableSleep = true;
    double linearSleepTolerance = 0.01;  ///< m/s
    double angularSleepTolerance = 2.0 / 180.0 * 3.141592653589793;  ///< rad/s
    double timeToSleep = 0.5;            ///< s
    /// A friction solve that ends `numerical_failure` (the answer of the solver's tie-breaking perturbation misses
    /// the true problem by more than lcp.residualTolerance, and no continuation did better) is still used when its
    /// scaled residual is at most this; only beyond it does the island fall back to the frictionless LCP.
    /// StepStats2 counts such islands and reports the largest scaled residual.
    double acceptResidual = 1e-6;
    /// Per-island solver options; maxPivots 0 = 2n + 100 per island LCP. Warm starts are repaired with the
    /// `violated` covering (LcpOptions::WarmCovering): on the 16- to 22-row pyramids it takes 2.5-4x fewer landing
    /// pivots than `uniform` (20 rows: 2578 against 6558 pivots over 300 steps; bench_world2d), and the same on
    /// 40 separate pyramids.
    LcpOptions lcp = [] {
        LcpOptions o;
        o.warmCovering = LcpOptions::WarmCovering::violated;
        return o;
    }();
    /// Work units one step may spend (core/step_budget.h; work::fromMilliseconds converts a time on the reference
    /// machine), 0 = unlimited. Islands the budget cannot solve exactly get a bounded approximation (StepStats
    /// counts them). Part of the state: every peer must step with the same budget.
    std::uint64_t stepBudget = 0;
    /// Threads a step may use (>= 1). Not state: the answer is the same bits for any count.
    int workerCount = 1;
    /// An embedding job system (core/task_system.h), both or neither; none: the world's own std::thread pool when
    /// workerCount > 1. Not state.
    EnqueueTaskCallback* enqueueTask = nullptr;
    FinishTaskCallback* finishTask = nullptr;
    void* userTaskContext = nullptr;  ///< passed to enqueueTask and finishTask
};
static_assert(sizeof(WorldDef2) == 208, "WorldDef2 changed: serialise the new field (world2d_state.cpp)");

/// Hot per-body state: the only thing the solver writes. 80 bytes, no implicit padding.
struct BodyState2 {
    Vec2 position;       ///< body origin (m)
    Rot2 rotation;       ///< cosine/sine of the body angle
    Vec2 center;         ///< world centre of mass (m)
    Vec2 velocity;       ///< centre-of-mass velocity (m/s)
    double angularVelocity = 0.0;  ///< rad/s
    double pad = 0.0;    ///< keeps the struct free of implicit padding (always 0)
};
static_assert(sizeof(BodyState2) == 80, "BodyState2 changed: serialise the new field (world2d_state.cpp)");

/// Cold per-body data.
struct BodyInfo2 {
    BodyType type = BodyType::dynamicBody;
    double mass = 0.0, invMass = 0.0, inertia = 0.0, invInertia = 0.0;  ///< kg, 1/kg, kg m^2, 1/(kg m^2)
    Vec2 localCenter;                  ///< centre of mass in the body frame (m)
    std::vector<Shape2> shapes;        ///< in body-frame coordinates
    double sleepTime = 0.0;            ///< s spent below the sleep tolerances
    bool awake = true;
};
static_assert(sizeof(BodyInfo2) == 96, "BodyInfo2 changed: serialise the new field (world2d_state.cpp)");

/// A contact point after the step (for events, drawing and tests).
struct ContactPoint2 {
    BodyId a, b;               ///< the normal points away from b towards a
    Vec2 point, normal;
    double separation = 0.0;   ///< m, negative when overlapping
    double normalImpulse = 0.0, tangentImpulse = 0.0;  ///< N s (tangent along perp(normal))
    std::uint32_t featureId = 0;
};

/// Two bodies started (begin) or stopped (end) touching this step.
using ContactEvent2 = TouchEvent;

/// What the last step did (core/world_step.h; `candidates` stays 0 in 2D).
using StepStats2 = StepStats;

class World2 {
public:
    explicit World2(const WorldDef2& def = {});

    /// Creates a body with its shapes (body-frame coordinates). Returns a null id and an error message when the
    /// definition is invalid (values outside core/input_policy.h's ranges, an inconsistent polygon, a dynamic body
    /// without mass, too many bodies); the world is unchanged then.
    BodyId createBody(const BodyDef2& def, const std::vector<Shape2>& shapes, std::string* error = nullptr);
    /// Removes a body; false for a stale or null id. Its contacts end (end events next step).
    bool destroyBody(BodyId id);

    /// Advances by one step of 1/hz seconds within def().stepBudget. A world whose state is no longer finite
    /// (fault()) does not step.
    void step();
    /// Advances by one step with `budget` work units (0 = unlimited) instead of def().stepBudget, for this call only
    /// (not recorded in the state: a replay steps with def().stepBudget).
    void step(std::uint64_t budget);
    /// Sets def().stepBudget (work units, 0 = unlimited).
    void setStepBudget(std::uint64_t budget) { mDef.stepBudget = budget; }
    /// Sets the threads of the next steps: def().workerCount and the job-system callbacks (none: the built-in pool).
    /// False (and nothing changes) for workerCount < 1 or only one of the two callbacks.
    bool setTaskSystem(const TaskSystem& tasks);
    /// Empty while every number of the state is finite. When a step overflows (a body flung to infinity), the
    /// message names the step, the body and the field, and step() does nothing until restore() replaces the state
    /// (world2d_checks.cpp).
    const std::string& fault() const { return mFault; }

    int bodyCount() const { return mBodies.size(); }
    bool valid(BodyId id) const { return mBodies.valid(id); }
    /// Body state; nullptr for an invalid id.
    const BodyState2* state(BodyId id) const;
    const BodyInfo2* info(BodyId id) const;
    /// Body angle (rad) from its rotation, through the deterministic atan2.
    double angle(BodyId id) const;
    /// Sets the velocity of a body (wakes it). False (nothing changes) for an invalid id, a static body or a
    /// velocity outside core/input_policy.h's ranges.
    bool setVelocity(BodyId id, Vec2 v, double w);
    /// Adds an impulse (N s) at a world point (wakes the body). False (nothing changes) for an invalid id, a body
    /// that is not dynamic, or an impulse outside the policy's range.
    bool applyImpulse(BodyId id, Vec2 impulse, Vec2 worldPoint);
    /// Sets gravity (m/s^2); false (nothing changes) outside the policy's range.
    bool setGravity(Vec2 g) {
        if (!policy::within(g.x, policy::kMaxGravity) || !policy::within(g.y, policy::kMaxGravity)) return false;
        mDef.gravity = g;
        return true;
    }
    const WorldDef2& def() const { return mDef; }

    /// Body ids in dense order (the order every loop of the step uses).
    std::vector<BodyId> bodyIds() const;
    const std::vector<ContactPoint2>& contacts() const { return mContactPoints; }
    const std::vector<ContactEvent2>& beginEvents() const { return mStep.beginEvents(); }
    const std::vector<ContactEvent2>& endEvents() const { return mStep.endEvents(); }
    const StepStats2& stats() const { return mStep.stats(); }
    std::uint64_t stepCount() const { return mStepCount; }

    /// 64-bit hash (XXH3) of the canonical serialisation of everything that affects the future: settings, step
    /// count, bodies (ids, transforms, velocities, mass, shapes, sleep state and timers), id pools, warm-start
    /// cache, touching pairs. It is the hash of snapshot()'s payload (resolver2d/world2d_state.cpp).
    std::uint64_t stateHash() const;
    /// The whole state in the versioned snapshot container of core/state_io.h. restore() of it into any World2
    /// (of any build with the same result-affecting flags) continues bit-identically.
    std::vector<std::uint8_t> snapshot() const;
    /// Replaces this world's state with a snapshot. The data is parsed and checked into a fresh world first; on any
    /// problem (truncated, corrupt, other version or build flags, inconsistent ids) it returns false with a reason
    /// in *error and this world is untouched. The last step's contacts, events and statistics are not part of the
    /// state: they are empty after a restore until the next step.
    bool restore(const std::uint8_t* data, std::size_t size, std::string* error = nullptr);
    /// The canonical state as named fields (same order and values as the hash), for diffs and desync reports.
    std::vector<StateField> stateFields() const;
    /// Rollback state: only what a tick can change (core/compact_state.h), into `out` (its memory is reused).
    void saveCompact(CompactState& out) const;
    /// Restores a saveCompact() of this world while it holds the same bodies; false with *error (world untouched)
    /// otherwise. The last step's contacts, events and statistics stay those of the last step() call.
    bool restoreCompact(const std::uint8_t* data, std::size_t size, std::string* error = nullptr);

    // Scene queries (resolver2d/query2d.cpp): exact on every shape type, answers in a total order (core/
    // scene_index.h); a non-finite argument or a zero ray translation gives no answer.
    /// The first shape the segment origin -> origin + translation (m) meets; false when it meets none.
    bool rayCastClosest(Vec2 origin, Vec2 translation, RayHit2* out) const;
    /// Every shape the segment meets, by (fraction, body slot, shape index).
    std::vector<RayHit2> rayCastAll(Vec2 origin, Vec2 translation) const;
    /// Every shape whose bounding box overlaps `box` (touching counts), by (body slot, shape index).
    std::vector<ShapeRef> overlapAabb(const Aabb2& box) const;
    /// Every shape that shares interior points with `shape` placed by xf, by (body slot, shape index).
    std::vector<ShapeRef> overlapShape(const Shape2& shape, const Transform2& xf) const;

private:
    struct Hooks;  // what core/world_step.h needs of this world (world2d.cpp)
    const SceneIndex<2>& sceneIndex() const;
    std::pair<const Shape2&, Transform2> placedShape(const ShapeRef& ref) const;
    template <class Visit>
    void castRay(Vec2 origin, Vec2 translation, bool closest, Visit&& visit) const;
    void updateBodyCenter(BodyState2& s, const BodyInfo2& info) const;
    // The one canonical serialiser (world2d_state.cpp): writes the state of a const World2 into a sink, or reads it
    // into a non-const one.
    template <class Io, class Self>
    static void transferState(Io& io, Self& world);

    /// The fault() message for the current state: empty when every hot body record is finite.
    std::string findFault() const;

    WorldDef2 mDef;
    BodyStore<BodyState2, BodyInfo2> mBodies;
    WorldStep<Dim2> mStep;  // the warm-start cache and touching pairs (state), the step's scratch and outputs
    std::vector<ContactPoint2> mContactPoints;
    std::uint64_t mStepCount = 0;
    std::string mFault;  // see fault(); not state (a state that is not finite cannot be snapshotted)
    std::unique_ptr<SceneIndex<2>> mIndex = std::make_unique<SceneIndex<2>>();  // derived from the bodies, never hashed
};

}  // namespace unison
