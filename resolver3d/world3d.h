// resolver3d/world3d.h — the 3D world: bodies with shapes, and the step of DESIGN.md (the same step as World2).
//
// Owns: the body store (generational ids, hot state separate from cold data), the contacts found each step, their
// warm-start cache keyed by feature ids, islands, sleeping, and the per-step events and statistics.
// The step: gravity into velocities; broadphase (sort and sweep, index order); narrowphase manifolds (<= 4 points
// per pair, stable feature ids; meshes through sphere trees); islands by union-find over dynamic bodies (core/
// island); per island one Coulomb-pyramid LCP with >= 4 tangent directions per contact, built by the paper's
// resolver (core/contact_resolver) and solved by Lemke, warm-started from the previous step's basis; impulses
// applied; positions and unit quaternions integrated; events recorded.
// Invariants: every loop runs in body, shape or contact index order; no unordered containers; no libm
// transcendental function (quaternions are integrated and normalised with + - * / sqrt).
#pragma once

#include "body_store.h"
#include "collide3d.h"
#include "input_policy.h"
#include <unison/lcp.h>
#include "query3d.h"
#include "scene_index.h"
#include "shapes3d.h"
#include "state_io.h"
#include "step_support.h"
#include "world_step.h"

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace unison {

class CompactState;

/// How to create a body. Velocities in m/s and rad/s (world axes).
struct BodyDef3 {
    BodyType type = BodyType::dynamicBody;
    Vec3 position = Vec3::Zero();        ///< origin of the body frame (m)
    Quat orientation;                    ///< unit quaternion (normalised on creation)
    Vec3 linearVelocity = Vec3::Zero();  ///< of the centre of mass
    Vec3 angularVelocity = Vec3::Zero();
};

/// World settings (the same meaning as WorldDef2's).
struct WorldDef3 {
    Vec3 gravity{0.0, -10.0, 0.0};       ///< m/s^2 (y up, as in the 2D world)
    double hz = 60.0;                    ///< steps per second
    double restitutionThreshold = 1.0;   ///< approach speeds below this (m/s) use e = 0
    double linearSlop = 0.005;           ///< allowed penetration (m)
    double baumgarte = 0.2;              ///< fraction of the penetration beyond the slop removed per step
    double maxCorrectionSpeed = 3.0;     ///< cap of the position-correction velocity (m/s)
    double speculativeDistance = 0.02;   ///< contacts this far apart are already in the LCP (m)
    /// A speculative point (separation s > 0) enters the LCP, and joins its two bodies' islands, only when the
    /// bodies' relative normal speed u before the solve (< 0 when closing) brings it within this band in one
    /// step: s + min(u, 0) / hz < speculativeBand (m). Resting neighbours 1-2 cm apart, and the far points that
    /// a fast body's reach finds, stay out: without this the 25 columns of bench_world3d's cube pile fuse into
    /// 5 islands of about 100 contacts (and one of 660 during the landing). The solve may still push such bodies
    /// together; the contact then enters the next step (overlap is corrected as any other). 0.01 m is about 3.6
    /// g dt^2 at 60 Hz, what a body can fall relative to its support in one step. Set it >= speculativeDistance
    /// plus the reach to keep every point, as the 2D world does.
    double speculativeBand = 0.01;
    /// Tangential speeds below this (m/s) are exactly 0 in the friction LCP. The 2D world uses 1e-7 (its settled
    /// pyramid's creep crossed 1e-8 after ~20 s); here 1e-7 made the 100-cube column pile of bench_world3d slower
    /// (4.5 -> 7.6 ms/step), so 3D keeps 1e-8 until a 3D case shows the same creep.
    double tangentDeadZone = 1e-8;
    int frictionDirections = 4;          ///< tangent directions of the pyramid (even, >= 4)
    bool enableSleep = true;
    double linearSleepTolerance = 0.01;  ///< m/s
    double angularSleepTolerance = 2.0 / 180.0 * 3.141592653589793;  ///< rad/s
    double timeToSleep = 0.5;            ///< s
    /// A friction solve that ends `numerical_failure` is still used when its scaled residual is at most this, as
    /// in 2D (WorldDef2::acceptResidual); beyond it the island falls back to the frictionless LCP. It was 0 (never)
    /// until the cube piles of bench_world3d showed such answers at 1.1e-9 to 1.2e-8 dropping their friction.
    double acceptResidual = 1e-6;
    /// Per-island solver options; maxPivots 0 = 2n + 100 per island LCP. Unlike 2D, warm starts keep the
    /// `uniform` covering (LcpOptions::WarmCovering): on the cube piles of bench_world3d, `violated` took more
    /// pivots with 49-100 cubes (100: 11377 against 5818 over 300 steps, 5 failed islands against 0) and fewer
    /// only with 144 (65816 against 161656). No block principal rounds (LcpOptions::blockPivotRounds): on the
    /// 100-cube piles they repaired none of 673 refused guesses (column pile, 300 steps; heap, 150 steps), and
    /// without them the piles of 49-100 cubes take the same pivots; they cost a factorisation each.
    LcpOptions lcp = [] {
        LcpOptions o;
        o.blockPivotRounds = 0;
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
static_assert(sizeof(WorldDef3) == 224, "WorldDef3 changed: serialise the new field (world3d_state.cpp)");

/// Hot per-body state: the only thing the solver writes. 16 doubles, 128 bytes, no padding.
struct BodyState3 {
    Vec3 position = Vec3::Zero();         ///< body origin (m)
    Quat rotation;                        ///< unit quaternion, body to world
    Vec3 center = Vec3::Zero();           ///< world centre of mass (m)
    Vec3 velocity = Vec3::Zero();         ///< centre-of-mass velocity (m/s)
    Vec3 angularVelocity = Vec3::Zero();  ///< rad/s, world axes
};
static_assert(sizeof(BodyState3) == 128, "BodyState3 changed: serialise the new field (world3d_state.cpp)");

/// Cold per-body data.
struct BodyInfo3 {
    BodyType type = BodyType::dynamicBody;
    double mass = 0.0, invMass = 0.0;        ///< kg, 1/kg
    Mat3 inertia = Mat3::Zero();             ///< about the centre of mass, body axes (kg m^2)
    Mat3 invInertia = Mat3::Zero();          ///< its inverse (body axes)
    Vec3 localCenter = Vec3::Zero();         ///< centre of mass in the body frame (m)
    std::vector<Shape3> shapes;              ///< in body-frame coordinates
    double sleepTime = 0.0;                  ///< s spent below the sleep tolerances
    bool awake = true;
};
static_assert(sizeof(BodyInfo3) == 232, "BodyInfo3 changed: serialise the new field (world3d_state.cpp)");

/// A contact point after the step (for events, drawing and tests).
struct ContactPoint3 {
    BodyId a, b;                         ///< the normal points away from b towards a
    Vec3 point = Vec3::Zero(), normal = Vec3::Zero();
    double separation = 0.0;             ///< m, negative when overlapping
    double normalImpulse = 0.0;          ///< N s
    Vec3 tangentImpulse = Vec3::Zero();  ///< N s, world frame
    std::uint32_t featureId = 0;
};

/// Two bodies started (begin) or stopped (end) touching this step.
using ContactEvent3 = TouchEvent;

/// What the last step did (core/world_step.h).
using StepStats3 = StepStats;

class World3 {
public:
    explicit World3(const WorldDef3& def = {});

    /// Creates a body with its shapes (body frame). Returns a null id and a message when the definition is invalid
    /// (values outside core/input_policy.h's ranges, an inconsistent shape, a dynamic body without mass, a plane on
    /// a moving body, capacity); the world is unchanged.
    BodyId createBody(const BodyDef3& def, const std::vector<Shape3>& shapes, std::string* error = nullptr);
    /// Removes a body and its warm-start entries; false for a stale or null id. Its contacts end (end events next
    /// step).
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
    /// (world3d_checks.cpp).
    const std::string& fault() const { return mFault; }

    int bodyCount() const { return mBodies.size(); }
    bool valid(BodyId id) const { return mBodies.valid(id); }
    const BodyState3* state(BodyId id) const;
    const BodyInfo3* info(BodyId id) const;
    /// The body's transform (origin and rotation matrix); identity for an invalid id.
    Transform3 transform(BodyId id) const;
    /// Sets the velocity of a body (wakes it). False (nothing changes) for static bodies, invalid ids or values
    /// outside core/input_policy.h's ranges.
    bool setVelocity(BodyId id, const Vec3& v, const Vec3& w);
    /// Sets gravity (m/s^2); false (nothing changes) outside the policy's range.
    bool setGravity(const Vec3& g) {
        if (!policy::within(g.x(), policy::kMaxGravity) || !policy::within(g.y(), policy::kMaxGravity) ||
            !policy::within(g.z(), policy::kMaxGravity))
            return false;
        mDef.gravity = g;
        return true;
    }
    const WorldDef3& def() const { return mDef; }

    /// Keeps every narrowphase candidate point of the next steps (for drawing the paper's fig. 5).
    void captureCandidates(bool on) { mCapture = on; }
    const std::vector<ManifoldPoint3>& candidates() const { return mCandidates; }

    std::vector<BodyId> bodyIds() const;
    const std::vector<ContactPoint3>& contacts() const { return mContactPoints; }
    const std::vector<ContactEvent3>& beginEvents() const { return mStep.beginEvents(); }
    const std::vector<ContactEvent3>& endEvents() const { return mStep.endEvents(); }
    const StepStats3& stats() const { return mStep.stats(); }
    std::uint64_t stepCount() const { return mStepCount; }

    /// Applies an impulse (N s) at a world point: changes the linear and angular velocity and wakes the body.
    /// False (nothing changes) for invalid ids, non-dynamic bodies, a non-finite point or an impulse outside the
    /// policy's range.
    bool applyImpulse(BodyId id, const Vec3& impulse, const Vec3& worldPoint);

    /// 64-bit hash (XXH3) of the canonical serialisation of everything that affects the future: settings,
    /// step count, body store (slots, generations, free list, dense order, transforms, velocities, mass
    /// properties, shapes incl. mesh geometry, sleep state), warm-start cache and touching pairs. It is the hash
    /// of snapshot()'s payload (resolver3d/world3d_state.cpp).
    std::uint64_t stateHash() const;
    /// The whole state in the versioned snapshot container of core/state_io.h (world kind 3).
    std::vector<std::uint8_t> snapshot() const;
    /// Replaces this world's state with a snapshot. The data is parsed and checked into a fresh world first
    /// (meshes get their sphere trees rebuilt); on any problem (corrupt, truncated, a 2D snapshot, other build
    /// flags, invalid values) returns false with a reason in *error and this world is untouched. The last step's
    /// outputs (contacts, events, statistics) are not state: they are empty after a restore until the next step.
    bool restore(const std::uint8_t* data, std::size_t size, std::string* error = nullptr);
    /// Every state field with its name and body (for snapshot diffs and desync reports).
    std::vector<StateField> stateFields() const;
    /// Rollback state: only what a tick can change (core/compact_state.h), into `out` (its memory is reused).
    void saveCompact(CompactState& out) const;
    /// Restores a saveCompact() of this world while it holds the same bodies; false with *error (world untouched)
    /// otherwise. The last step's contacts, events and statistics stay those of the last step() call.
    bool restoreCompact(const std::uint8_t* data, std::size_t size, std::string* error = nullptr);

    // Scene queries (resolver3d/query3d.cpp): exact on every shape type, answers in a total order (core/
    // scene_index.h); a non-finite argument or a zero ray translation gives no answer.
    /// The first shape the segment origin -> origin + translation (m) meets; false when it meets none.
    bool rayCastClosest(const Vec3& origin, const Vec3& translation, RayHit3* out) const;
    /// Every shape the segment meets, by (fraction, body slot, shape index).
    std::vector<RayHit3> rayCastAll(const Vec3& origin, const Vec3& translation) const;
    /// Every shape whose bounding box overlaps `box` (touching counts; a plane's box is unbounded), by (body slot,
    /// shape index).
    std::vector<ShapeRef> overlapAabb(const Aabb3& box) const;
    /// Every shape that shares interior points with the convex `shape` (sphere, box or hull) placed by xf, by
    /// (body slot, shape index); empty for a plane or mesh query shape.
    std::vector<ShapeRef> overlapShape(const Shape3& shape, const Transform3& xf) const;

private:
    struct Hooks;  // what core/world_step.h needs of this world (world3d.cpp)
    const SceneIndex<3>& sceneIndex() const;
    std::pair<const Shape3&, Transform3> placedShape(const ShapeRef& ref) const;
    template <class Visit>
    void castRay(const Vec3& origin, const Vec3& translation, bool closest, Visit&& visit) const;
    /// The one canonical walk over the state (resolver3d/world3d_state.cpp); Self is World3 or const World3.
    template <class Io, class Self>
    static void transferState(Io& io, Self& world);

    /// The fault() message for the current state: empty when every hot body record is finite.
    std::string findFault() const;

    WorldDef3 mDef;
    BodyStore<BodyState3, BodyInfo3> mBodies;
    WorldStep<Dim3> mStep;  // the warm-start cache and touching pairs (state), the step's scratch and outputs
    std::vector<ContactPoint3> mContactPoints;
    bool mCapture = false;
    std::vector<ManifoldPoint3> mCandidates;
    std::uint64_t mStepCount = 0;
    std::string mFault;  // see fault(); not state (a state that is not finite cannot be snapshotted)
    std::unique_ptr<SceneIndex<3>> mIndex = std::make_unique<SceneIndex<3>>();  // derived from the bodies, never hashed
};

}  // namespace unison
