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
#include "world_base.h"
#include "world_settings.h"
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

/// World settings of the 2D world: the shared ones (core/world_settings.h) and gravity.
struct WorldDef2 : WorldSettings {
    Vec2 gravity{0.0, -10.0};  ///< m/s^2

    WorldDef2() {
        // Resting piles creep at rounding level (1e-10 to 1e-8 m/s); once that creep crossed a 1e-8 dead zone, a
        // settled 20-row pyramid needed thousands of Lemke pivots per step from about 20 s on. At 1e-7 it stays at
        // 0 pivots for 60 s (top box drift 2e-8 m).
        tangentDeadZone = 1e-7;
        // Warm starts are repaired with the `violated` covering (LcpOptions::WarmCovering): on the 16- to 22-row
        // pyramids it takes 2.5-4x fewer landing pivots than `uniform` (docs/solver.md), and the same on 40
        // separate pyramids.
        lcp.warmCovering = LcpOptions::WarmCovering::violated;
    }
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

class World2 : public WorldBase<World2, Dim2, WorldDef2, BodyState2, BodyInfo2, ContactPoint2> {
public:
    explicit World2(const WorldDef2& def = {}) : WorldBase(def) {}

    /// Creates a body with its shapes (body-frame coordinates). Returns a null id and an error message when the
    /// definition is invalid (values outside core/input_policy.h's ranges, an inconsistent polygon, a dynamic body
    /// without mass, too many bodies); the world is unchanged then.
    BodyId createBody(const BodyDef2& def, const std::vector<Shape2>& shapes, std::string* error = nullptr);
    /// Body angle (rad) from its rotation, through the deterministic atan2.
    double angle(BodyId id) const;

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
    friend class WorldBase<World2, Dim2, WorldDef2, BodyState2, BodyInfo2, ContactPoint2>;
    struct Hooks;  // what core/world_step.h needs of this world (world2d.cpp)
    static constexpr SnapshotKind kSnapshotKind = SnapshotKind::world2;
    struct CompactFields;  // the doubles a tick can change (world2d_state.cpp)

    const SceneIndex<2>& sceneIndex() const;
    std::pair<const Shape2&, Transform2> placedShape(const ShapeRef& ref) const;
    template <class Visit>
    void castRay(Vec2 origin, Vec2 translation, bool closest, Visit&& visit) const;
    void updateBodyCenter(BodyState2& s, const BodyInfo2& info) const;
    void beforeStep() {}
    ContactPoint2 contactPoint(const StepContact<Dim2>& c) const {
        const Vec2 perp{-c.normal.y, c.normal.x};  // the 2D tangent impulse is a scalar along perp(normal)
        return {mBodies.idAt(c.bodyA), mBodies.idAt(c.bodyB), c.point, c.normal, c.separation, c.normalImpulse,
                dot(c.tangentImpulse, perp), c.feature};
    }
    static double worldInvInertia(const BodyState2&, const BodyInfo2& info) { return info.invInertia; }
    void keepOnRestore(World2&) const {}
    // The one canonical serialiser (world2d_state.cpp): writes the state of a const World2 into a sink, or reads it
    // into a non-const one.
    template <class Io, class Self>
    static void transferState(Io& io, Self& world);
    /// The fault() message for the current state: empty when every hot body record is finite (world2d_checks.cpp).
    std::string findFault() const;
};

}  // namespace unison
