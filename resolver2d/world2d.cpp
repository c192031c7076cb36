// resolver2d/world2d.cpp — the 2D world (see world2d.h): bodies, and the geometry and body math of its step. The
// step itself (islands, LCP solves, warm start, bounces, sleep, events) is core/world_step.h, shared with World3.
//
// Why one LCP per island with friction rows: the paper resolves all points of an island at once, and friction must
// live in the same problem or stacks creep (a separate friction pass would undo part of the normal solution).
// Why speculative contacts: a contact that is 1 cm apart now may touch before the next step; putting it in the LCP
// with b_i += separation / dt lets it close the gap exactly but not more, so fast bodies do not tunnel into stacks.
#include "world2d.h"

#include "broadphase2d.h"
#include "contact_resolver.h"
#include "det_math.h"
#include "island.h"
#include "resolver2d.h"
#include "world2d_checks.h"
#include "world_base_step.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace unison {

void World2::updateBodyCenter(BodyState2& s, const BodyInfo2& info) const {
    s.center = s.position + rotate(s.rotation, info.localCenter);
}

BodyId World2::createBody(const BodyDef2& def, const std::vector<Shape2>& shapes, std::string* error) {
    auto fail = [&](const std::string& why) {
        if (error) *error = why;
        return BodyId::null();
    };
    const std::string problem = checkBodyDef2(def, shapes);  // core/input_policy.h ranges, polygon consistency
    if (!problem.empty()) return fail(problem);
    BodyInfo2 info;
    info.type = def.type;
    info.shapes = shapes;
    if (def.type == BodyType::dynamicBody) {
        // Mass properties from the shapes: total mass, centre of mass, inertia about it (parallel axis theorem).
        double mass = 0.0, inertiaOrigin = 0.0;
        Vec2 moment;
        for (const Shape2& s : shapes) {
            const MassData md = computeMass(s);
            if (!std::isfinite(md.mass) || md.mass < 0.0) return fail("body: shape density must be finite and >= 0");
            mass += md.mass;
            moment = moment + md.mass * md.center;
            inertiaOrigin += md.inertia + md.mass * dot(md.center, md.center);
        }
        if (!(mass > 0.0)) return fail("body: a dynamic body needs at least one shape with positive mass");
        info.mass = mass;
        info.invMass = 1.0 / mass;
        info.localCenter = (1.0 / mass) * moment;
        info.inertia = inertiaOrigin - mass * dot(info.localCenter, info.localCenter);
        // Shapes far from the body origin lose the inertia about their centre in this difference: refuse rather than
        // keep a negative inertia that restore() (rightly) refuses.
        if (!(info.inertia >= 0.0)) return fail("body: inertia lost to rounding (move the body origin to its shapes)");
        info.invInertia = info.inertia > 0.0 ? 1.0 / info.inertia : 0.0;
    }
    BodyState2 state;
    state.position = def.position;
    state.rotation = makeRot(def.angle);
    updateBodyCenter(state, info);
    if (def.type != BodyType::staticBody) {
        state.velocity = def.linearVelocity;
        state.angularVelocity = def.angularVelocity;
    }
    return addBody(state, info, error);
}

double World2::angle(BodyId id) const {
    const BodyState2* s = state(id);
    return s ? angleOf(s->rotation) : 0.0;
}

/// What the shared step (core/world_step.h) needs of the 2D world: its bodies and settings, the narrowphase, and
/// the planar body math.
struct World2::Hooks {
    World2& world;

    std::vector<ContactPoint2>& contactPoints() { return world.mContactPoints; }
    ContactPoint2 contactPoint(const StepContact<Dim2>& c) const { return world.contactPoint(c); }

    BodyStore<BodyState2, BodyInfo2>& bodies() { return world.mBodies; }
    const WorldDef2& def() const { return world.mDef; }
    int frictionDirections() const { return Dim2::frictionDirectionCount(2); }  // +t and -t: the exact 2D pyramid
    double acceptResidual() const { return world.mDef.acceptResidual; }
    /// A structure that stands by friction alone (Box2D v3's card house) takes 2-5n pivots while it lands, and a
    /// cut-off landing never recovers (see solveIsland): 8n + 100 keeps a 7-level house up; 2n + 100 fells 5 levels.
    int frictionPivotsPerUnknown() const { return 8; }
    /// 2D keeps every speculative point the narrowphase returns (its targets were measured that way).
    double speculativeBand() const { return std::numeric_limits<double>::infinity(); }
    double worldInvInertia(const BodyState2& s, const BodyInfo2& info) const { return World2::worldInvInertia(s, info); }
    /// The fastest a point within `extent` of the centre can move with the body's kinetic energy (see World3's);
    /// the step asks only with a finite speculativeBand(), so the 2D world never does.
    double speedBound(const BodyState2& s, const BodyInfo2& info, double extent) const {
        const double twiceEnergy = info.mass * Dim2::dot(s.velocity, s.velocity) + info.inertia * s.angularVelocity * s.angularVelocity;
        return std::sqrt(std::max(0.0, twiceEnergy) * (info.invMass + extent * extent * info.invInertia));
    }

    void integrate(int d, Vec2 v, double w, double dt) {
        BodyState2& s = world.mBodies.hot(d);
        s.center = s.center + dt * v;
        s.rotation = integrateRotation(s.rotation, dt * w);
        s.position = s.center - rotate(s.rotation, world.mBodies.cold(d).localCenter);
    }

    /// The state a step may leave is within the supported ranges (checkMotion2; the message comes from findFault).
    bool motionOk(const BodyState2& s) const { return checkMotion2(s).empty(); }

    Transform2 transform(const BodyState2& s) const { return {s.position, s.rotation}; }

    Manifold2 narrowphase(const Shape2& a, const Transform2& xfA, const Shape2& b, const Transform2& xfB,
                          double distance, StepStats&) const {
        return collide(a, xfA, b, xfB, distance);
    }
    Vec2 normalOf(const Manifold2& m, int) const { return m.normal; }  // one normal per 2D manifold
    /// Feature pairs the narrowphase compares (vertices or the circle of each shape), as work units.
    std::uint64_t pairWork(const Shape2& a, const Shape2& b, const Manifold2&) const {
        auto features = [](const Shape2& s) {
            return s.type == ShapeType::polygon ? std::uint64_t(s.polygon.count) : s.type == ShapeType::segment ? 2u : 1u;
        };
        return work::kNarrowPair2 + work::kPerFeaturePair2 * features(a) * features(b);
    }
    int narrowphaseScope() const { return 0; }  // the 2D narrowphase keeps nothing between pairs
    bool parallelNarrowphase() const { return true; }
};

// The shared step and body operations, instantiated here where Hooks is complete (core/world_base_step.h).
using WorldBase2 = WorldBase<World2, Dim2, WorldDef2, BodyState2, BodyInfo2, ContactPoint2>;
template bool WorldBase2::destroyBody(BodyId);
template BodyId WorldBase2::addBody(const BodyState2&, const BodyInfo2&, std::string*);
template void WorldBase2::step(std::uint64_t);
template bool WorldBase2::setVelocity(BodyId, const Vec2&, const double&);
template bool WorldBase2::applyImpulse(BodyId, const Vec2&, const Vec2&);

}  // namespace unison
