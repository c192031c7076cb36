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
#include "world_base.h"
#include "world_settings.h"
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

/// World settings of the 3D world: the shared ones (core/world_settings.h), gravity, the pyramid's directions and
/// the speculative band.
struct WorldDef3 : WorldSettings {
    Vec3 gravity{0.0, -10.0, 0.0};  ///< m/s^2 (y up, as in the 2D world)
    /// A speculative point (separation s > 0) enters the LCP, and joins its two bodies' islands, only when the
    /// bodies' relative normal speed u before the solve (< 0 when closing) brings it within this band in one
    /// step: s + min(u, 0) / hz < speculativeBand (m). Resting neighbours 1-2 cm apart, and the far points that
    /// a fast body's reach finds, stay out: without this the 25 columns of bench_world3d's cube pile fuse into
    /// 5 islands of about 100 contacts (and one of 660 during the landing). The solve may still push such bodies
    /// together; the contact then enters the next step (overlap is corrected as any other). 0.01 m is about 3.6
    /// g dt^2 at 60 Hz, what a body can fall relative to its support in one step. Set it >= speculativeDistance
    /// plus the reach to keep every point, as the 2D world does.
    double speculativeBand = 0.01;
    int frictionDirections = 4;  ///< tangent directions of the pyramid (even, >= 4)

    WorldDef3() {
        // The 2D world uses 1e-7 (its settled pyramid's creep crossed 1e-8 after ~20 s); here 1e-7 made the
        // 100-cube column pile of bench_world3d slower (4.5 -> 7.6 ms/step), so 3D keeps 1e-8 until a 3D case
        // shows the same creep.
        tangentDeadZone = 1e-8;
        // Warm starts keep the `uniform` covering (LcpOptions::WarmCovering): on the cube piles of bench_world3d,
        // `violated` took more pivots with 49-100 cubes (100: 11377 against 5818 over 300 steps, 5 failed islands
        // against 0) and fewer only with 144. No block principal rounds (LcpOptions::blockPivotRounds): on the
        // 100-cube piles they repaired none of 673 refused guesses, and without them the piles of 49-100 cubes
        // take the same pivots; they cost a factorisation each.
        lcp.blockPivotRounds = 0;
    }
};
static_assert(sizeof(WorldDef3) == 232, "WorldDef3 changed: serialise the new field (world3d_state.cpp)");

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

class World3 : public WorldBase<World3, Dim3, WorldDef3, BodyState3, BodyInfo3, ContactPoint3> {
public:
    explicit World3(const WorldDef3& def = {}) : WorldBase(def) {}

    /// Creates a body with its shapes (body frame). Returns a null id and a message when the definition is invalid
    /// (values outside core/input_policy.h's ranges, an inconsistent shape, a dynamic body without mass, a plane on
    /// a moving body, capacity); the world is unchanged.
    BodyId createBody(const BodyDef3& def, const std::vector<Shape3>& shapes, std::string* error = nullptr);
    /// The body's transform (origin and rotation matrix); identity for an invalid id.
    Transform3 transform(BodyId id) const;

    /// Keeps every narrowphase candidate point of the next steps (for drawing the paper's fig. 5).
    void captureCandidates(bool on) { mCapture = on; }
    const std::vector<ManifoldPoint3>& candidates() const { return mCandidates; }

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
    friend class WorldBase<World3, Dim3, WorldDef3, BodyState3, BodyInfo3, ContactPoint3>;
    struct Hooks;  // what core/world_step.h needs of this world (world3d.cpp)
    static constexpr SnapshotKind kSnapshotKind = SnapshotKind::world3;
    struct CompactFields;  // the doubles a tick can change (world3d_state.cpp)

    const SceneIndex<3>& sceneIndex() const;
    std::pair<const Shape3&, Transform3> placedShape(const ShapeRef& ref) const;
    template <class Visit>
    void castRay(const Vec3& origin, const Vec3& translation, bool closest, Visit&& visit) const;
    void beforeStep() { mCandidates.clear(); }
    ContactPoint3 contactPoint(const StepContact<Dim3>& c) const {
        return {mBodies.idAt(c.bodyA), mBodies.idAt(c.bodyB), c.point, c.normal, c.separation, c.normalImpulse,
                c.tangentImpulse, c.feature};
    }
    /// World-frame I^-1 = R I_b^-1 R^T.
    static Mat3 worldInvInertia(const BodyState3& s, const BodyInfo3& info);
    void keepOnRestore(World3& fresh) const { fresh.mCapture = mCapture; }  // a viewing switch, not state
    /// The one canonical walk over the state (resolver3d/world3d_state.cpp); Self is World3 or const World3.
    template <class Io, class Self>
    static void transferState(Io& io, Self& world);
    /// The fault() message for the current state: empty when every hot body record is finite (world3d_checks.cpp).
    std::string findFault() const;

    bool mCapture = false;
    std::vector<ManifoldPoint3> mCandidates;
};

}  // namespace unison
