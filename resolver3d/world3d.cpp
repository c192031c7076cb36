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

#include <algorithm>
#include <cmath>

namespace unison {

using D3 = Dim3;

World3::World3(const WorldDef3& def) : mDef(def) {}

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
        const std::string inertia = checkInertia3(info.inertia);  // the check restore() makes
        if (!inertia.empty()) return fail(inertia);
        info.invInertia = info.inertia.inverse();
    }
    BodyState3 state;
    state.position = def.position;
    state.rotation = normalized(q);
    state.center = transformPoint(Transform3{state.position, toMatrix(state.rotation)}, info.localCenter);
    if (def.type != BodyType::staticBody) {
        state.velocity = def.linearVelocity;
        state.angularVelocity = def.angularVelocity;
    }
    const BodyId id = mBodies.create(state, info);
    if (id.isNull()) return fail("world: body capacity reached");
    mIndex->invalidate();
    return id;
}

bool World3::destroyBody(BodyId id) {
    if (!mBodies.destroy(id)) return false;
    mStep.cache.forgetSlot(id.index1);
    mIndex->invalidate();
    return true;
}

const BodyState3* World3::state(BodyId id) const { return mBodies.findHot(id); }

const BodyInfo3* World3::info(BodyId id) const { return mBodies.findCold(id); }

Transform3 World3::transform(BodyId id) const {
    const BodyState3* s = state(id);
    return s ? Transform3{s->position, toMatrix(s->rotation)} : Transform3{};
}

bool World3::setVelocity(BodyId id, const Vec3& v, const Vec3& w) {
    const int d = mBodies.denseIndex(id);
    const auto within = [](const Vec3& x, double limit) {
        return policy::within(x.x(), limit) && policy::within(x.y(), limit) && policy::within(x.z(), limit);
    };
    if (d < 0 || !within(v, policy::kMaxSpeed) || !within(w, policy::kMaxAngularSpeed)) return false;
    BodyInfo3& info = mBodies.cold(d);
    if (info.type == BodyType::staticBody) return false;
    mBodies.hot(d).velocity = v;
    mBodies.hot(d).angularVelocity = w;
    info.awake = true;
    info.sleepTime = 0.0;
    return true;
}

bool World3::applyImpulse(BodyId id, const Vec3& impulse, const Vec3& worldPoint) {
    const int d = mBodies.denseIndex(id);
    const bool small = policy::within(impulse.x(), policy::kMaxImpulse) && policy::within(impulse.y(), policy::kMaxImpulse) &&
                       policy::within(impulse.z(), policy::kMaxImpulse);
    if (d < 0 || !small || !D3::finite(worldPoint)) return false;
    BodyInfo3& info = mBodies.cold(d);
    if (info.type != BodyType::dynamicBody) return false;
    BodyState3& s = mBodies.hot(d);
    const Mat3 invI = rotateTensor(toMatrix(s.rotation), info.invInertia);  // world-frame I^-1 = R I_b^-1 R^T
    s.velocity = D3::add(s.velocity, D3::scale(info.invMass, impulse));
    s.angularVelocity = D3::add(s.angularVelocity, mul(invI, D3::cross(D3::sub(worldPoint, s.center), impulse)));
    info.awake = true;
    info.sleepTime = 0.0;
    return true;
}

std::vector<BodyId> World3::bodyIds() const { return mBodies.ids(); }

/// What the shared step (core/world_step.h) needs of the 3D world: its bodies and settings, the narrowphase
/// (meshes through sphere trees), and the body math of quaternions and inertia tensors.
struct World3::Hooks {
    World3& world;

    BodyStore<BodyState3, BodyInfo3>& bodies() { return world.mBodies; }
    const WorldDef3& def() const { return world.mDef; }
    int frictionDirections() const { return D3::frictionDirectionCount(world.mDef.frictionDirections); }
    double acceptResidual() const { return world.mDef.acceptResidual; }
    double speculativeBand() const { return world.mDef.speculativeBand; }
    /// World-frame I^-1 = R I_b^-1 R^T.
    Mat3 worldInvInertia(const BodyState3& s, const BodyInfo3& info) const {
        return rotateTensor(toMatrix(s.rotation), info.invInertia);
    }

    void integrate(int d, const Vec3& v, const Vec3& w, double dt) {
        BodyState3& s = world.mBodies.hot(d);
        s.center = D3::add(s.center, D3::scale(dt, v));
        s.rotation = integrateRotation(s.rotation, w, dt);
        s.position = D3::sub(s.center, mul(toMatrix(s.rotation), world.mBodies.cold(d).localCenter));
    }

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

bool World3::setTaskSystem(const TaskSystem& tasks) { return setTaskFields(mDef, tasks); }

void World3::step() { step(mDef.stepBudget); }

void World3::step(std::uint64_t budget) {
    if (!mFault.empty()) return;  // never step a state that holds NaN or infinity
    mIndex->invalidate();
    mCandidates.clear();
    Hooks hooks{*this};
    mStep.run(hooks, StepControl{budget, taskFieldsOf(mDef)});
    mContactPoints.clear();
    for (const StepContact<Dim3>& c : mStep.contacts())
        mContactPoints.push_back({mBodies.idAt(c.bodyA), mBodies.idAt(c.bodyB), c.point, c.normal, c.separation,
                                  c.normalImpulse, c.tangentImpulse, c.feature});
    ++mStepCount;
    mFault = findFault();
}

}  // namespace unison
