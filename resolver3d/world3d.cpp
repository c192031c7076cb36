// resolver3d/world3d.cpp — the 3D world (see world3d.h): bodies, and the geometry and body math of its step. The
// step itself (islands, LCP solves, warm start, sleep, events) is core/world_step.h, shared with World2.
//
// Why one LCP per island with friction rows: the paper resolves all points of an island at once, and friction must
// live in the same problem or stacks creep. Why speculative contacts: a contact that is 2 cm apart now may touch
// before the next step; in the LCP with b_i += separation / dt it closes the gap exactly but not more.
#include "world3d.h"

#include "broadphase3d.h"
#include "contact_resolver.h"
#include "island.h"
#include "resolver3d.h"
#include "world3d_checks.h"
#include "world_base_step.h"

#include <algorithm>
#include <cmath>

namespace unison {

using D3 = Dim3;

BodyId World3::createBody(const BodyDef3& def, const std::vector<Shape3>& shapes, std::string* error) {
    auto fail = [&](const std::string& why) {
        if (error) *error = why;
        return BodyId::null();
    };
    const Quat& q = def.orientation;
    const std::string problem = checkBodyDef3(def, shapes);  // core/input_policy.h ranges, shape consistency
    if (!problem.empty()) return fail(problem);
    if (!(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z > 1e-12)) return fail("body: orientation must be non-zero");
    BodyInfo3 info;
    info.type = def.type;
    info.shapes = shapes;
    for (const Shape3& s : shapes)
        if (s.type == ShapeType3::plane && def.type != BodyType::staticBody) return fail("body: planes must be static");
    if (def.type == BodyType::dynamicBody) {
        // Mass, centre and inertia of the union: inertia about the body origin by the parallel axis theorem, then
        // moved to the centre of mass.
        double mass = 0.0;
        Vec3 moment = Vec3::Zero();
        Mat3 inertiaOrigin = Mat3::Zero();
        auto shift = [](double m, const Vec3& c) {
            return Mat3(m * (D3::dot(c, c) * Mat3::Identity() - c * c.transpose()));
        };
        for (const Shape3& s : shapes) {
            const MassData3 md = computeMass(s);
            if (!std::isfinite(md.mass) || md.mass < 0.0) return fail("body: shape density must be finite and >= 0");
            mass += md.mass;
            moment = D3::add(moment, D3::scale(md.mass, md.center));
            inertiaOrigin += md.inertia + shift(md.mass, md.center);
        }
        if (!(mass > 0.0)) return fail("body: a dynamic body needs at least one shape with positive mass");
        info.mass = mass;
        info.invMass = 1.0 / mass;
        info.localCenter = D3::scale(1.0 / mass, moment);
        info.inertia = inertiaOrigin - shift(mass, info.localCenter);
        const std::string inertia = checkInertia3(info.inertia);  // the checks restore() makes
        if (!inertia.empty()) return fail(inertia);
        info.invInertia = info.inertia.inverse();
        // An ill-conditioned tensor (a sliver of a mesh) inverts inaccurately: such a body could not be restored
        // from the world's own snapshot, so it is refused here.
        if (!checkInverseInertia3(info.inertia, info.invInertia).empty())
            return fail("body: inertia tensor too ill-conditioned to invert (I * I^-1 differs from the identity by "
                        "more than 1e-6)");
    }
    BodyState3 state;
    state.position = def.position;
    state.rotation = normalized(q);
    state.center = transformPoint(Transform3{state.position, toMatrix(state.rotation)}, info.localCenter);
    if (def.type != BodyType::staticBody) {
        state.velocity = def.linearVelocity;
        state.angularVelocity = def.angularVelocity;
    }
    return addBody(state, info, error);
}

Transform3 World3::transform(BodyId id) const {
    const BodyState3* s = state(id);
    return s ? Transform3{s->position, toMatrix(s->rotation)} : Transform3{};
}

Mat3 World3::worldInvInertia(const BodyState3& s, const BodyInfo3& info) {
    return rotateTensor(toMatrix(s.rotation), info.invInertia);
}

/// What the shared step (core/world_step.h) needs of the 3D world: its bodies and settings, the narrowphase
/// (meshes through sphere trees), and the body math of quaternions and inertia tensors.
struct World3::Hooks {
    World3& world;

    std::vector<ContactPoint3>& contactPoints() { return world.mContactPoints; }
    ContactPoint3 contactPoint(const StepContact<Dim3>& c) const { return world.contactPoint(c); }

    BodyStore<BodyState3, BodyInfo3>& bodies() { return world.mBodies; }
    const WorldDef3& def() const { return world.mDef; }
    int frictionDirections() const { return D3::frictionDirectionCount(world.mDef.frictionDirections); }
    double acceptResidual() const { return world.mDef.acceptResidual; }
    /// 2n + 100: at 8n + 100 the drop heap's fallbacks fell from 43 to 5 but its steps took 1.3x as long and its
    /// worst step 4x (9.9 s); the toppling heap's 7 fallbacks went to 0 at 1.3x the time.
    int frictionPivotsPerUnknown() const { return 2; }
    double speculativeBand() const { return world.mDef.speculativeBand; }
    Mat3 worldInvInertia(const BodyState3& s, const BodyInfo3& info) const { return World3::worldInvInertia(s, info); }
    /// The fastest a point within `extent` of the centre can move with the body's kinetic energy E: the largest
    /// |v + w x r| with m |v|^2 + w^T I w <= 2E and |r| <= extent is sqrt(2E (1/m + extent^2 / I_min)) (Cauchy-
    /// Schwarz), and 1 / I_min is at most the largest absolute row sum of the inverse inertia (Gershgorin; exact for
    /// a diagonal tensor).
    double speedBound(const BodyState3& s, const BodyInfo3& info, double extent) const {
        const Vec3 wBody = mulT(toMatrix(s.rotation), s.angularVelocity);
        const double twiceEnergy = info.mass * D3::dot(s.velocity, s.velocity) + D3::dot(wBody, mul(info.inertia, wBody));
        double invInertiaMax = 0.0;
        for (int i = 0; i < 3; ++i) {
            const double row = std::fabs(info.invInertia(i, 0)) + std::fabs(info.invInertia(i, 1)) + std::fabs(info.invInertia(i, 2));
            invInertiaMax = std::max(invInertiaMax, row);
        }
        return std::sqrt(std::max(0.0, twiceEnergy) * (info.invMass + extent * extent * invInertiaMax));
    }

    void integrate(int d, const Vec3& v, const Vec3& w, double dt) {
        BodyState3& s = world.mBodies.hot(d);
        s.center = D3::add(s.center, D3::scale(dt, v));
        s.rotation = integrateRotation(s.rotation, w, dt);
        s.position = D3::sub(s.center, mul(toMatrix(s.rotation), world.mBodies.cold(d).localCenter));
    }

    /// The state a step may leave is within the supported ranges (checkMotion3; the message comes from findFault).
    bool motionOk(const BodyState3& s) const { return checkMotion3(s).empty(); }

    Transform3 transform(const BodyState3& s) const { return {s.position, toMatrix(s.rotation)}; }

    Manifold3 narrowphase(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB,
                          double distance, StepStats& stats) const {
        const Manifold3 m = collide(a, xfA, b, xfB, distance, world.mCapture ? &world.mCandidates : nullptr);
        stats.candidates += m.candidates;
        return m;
    }
    Vec3 normalOf(const Manifold3& m, int k) const { return m.points[std::size_t(k)].normal; }
    /// The narrowphase's tests as work units: face-vertex and edge-edge pairs of two polyhedra, the vertices of a
    /// shape against a plane, and the candidate points of a mesh pair (its sphere trees find them).
    std::uint64_t pairWork(const Shape3& a, const Shape3& b, const Manifold3& m) const {
        auto poly = [](const Shape3& s) { return (s.type == ShapeType3::box || s.type == ShapeType3::hull) && s.poly; };
        std::uint64_t tests = 1;
        if (poly(a) && poly(b)) {
            const std::uint64_t fa = a.poly->faces.size(), va = a.poly->vertices.size(), ea = a.poly->edges.size();
            const std::uint64_t fb = b.poly->faces.size(), vb = b.poly->vertices.size(), eb = b.poly->edges.size();
            tests = fa * vb + fb * va + ea * eb;
        } else if (poly(a) || poly(b)) {
            tests = (poly(a) ? a : b).poly->vertices.size();
        }
        return work::kNarrowPair3 + work::kPerFeaturePair3 * (tests + std::uint64_t(m.candidates));
    }
    /// Polyhedra placed once per thread's range of pairs (collide3d's CollideBatch); the same bits without it.
    CollideBatch narrowphaseScope() const { return CollideBatch(); }
    /// captureCandidates() appends every pair's candidates to the world in pair order: one thread then.
    bool parallelNarrowphase() const { return !world.mCapture; }
};

// The shared step and body operations, instantiated here where Hooks is complete (core/world_base_step.h).
using WorldBase3 = WorldBase<World3, Dim3, WorldDef3, BodyState3, BodyInfo3, ContactPoint3>;
template bool WorldBase3::destroyBody(BodyId);
template BodyId WorldBase3::addBody(const BodyState3&, const BodyInfo3&, std::string*);
template void WorldBase3::step(std::uint64_t);
template bool WorldBase3::setVelocity(BodyId, const Vec3&, const Vec3&);
template bool WorldBase3::applyImpulse(BodyId, const Vec3&, const Vec3&);

}  // namespace unison
