// resolver3d/world3d.cpp — the 3D step (see world3d.h). It follows World2 stage by stage; the LCP assembly, the
// Lemke solve and the island split are core/'s, only geometry and body math are 3D here.
//
// Why one LCP per island with friction rows: the paper resolves all points of an island at once, and friction must
// live in the same problem or stacks creep. Why speculative contacts: a contact that is 2 cm apart now may touch
// before the next step; in the LCP with b_i += separation / dt it closes the gap exactly but not more.
#include "world3d.h"

#include "broadphase3d.h"
#include "contact_resolver.h"
#include "island.h"
#include "resolver3d.h"

#include <algorithm>
#include <cmath>

namespace unison {

using D3 = Dim3;

struct World3::Contact {
    int bodyA = -1, bodyB = -1;  // dense indices; the normal points away from B towards A
    int shapeA = 0, shapeB = 0;
    ManifoldPoint3 point;
    double friction = 0.0, restitution = 0.0;
    double normalImpulse = 0.0;
    Vec3 tangentImpulse = Vec3::Zero();
};

World3::World3(const WorldDef3& def) : mDef(def) {}

namespace {

double length(const Vec3& v) { return std::sqrt(D3::dot(v, v)); }

}  // namespace

ContactKey World3::keyOf(const Contact& c) const {
    return ContactKey{mBodies.idAt(c.bodyA).index1, mBodies.idAt(c.bodyB).index1, std::uint16_t(c.shapeA),
                      std::uint16_t(c.shapeB), c.point.id, 0};
}

BodyId World3::createBody(const BodyDef3& def, const std::vector<Shape3>& shapes, std::string* error) {
    auto fail = [&](const std::string& why) {
        if (error) *error = why;
        return BodyId::null();
    };
    const Quat& q = def.orientation;
    if (!D3::finite(def.position) || !D3::finite(def.linearVelocity) || !D3::finite(def.angularVelocity) ||
        !std::isfinite(q.w) || !std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
        return fail("body: position, orientation and velocities must be finite");
    if (!(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z > 1e-12)) return fail("body: orientation must be non-zero");
    BodyInfo3 info;
    info.type = def.type;
    info.shapes = shapes;
    for (const Shape3& s : shapes)
        if (s.type == ShapeType3::plane && def.type != BodyType3::staticBody) return fail("body: planes must be static");
    if (def.type == BodyType3::dynamicBody) {
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
        if (!(info.inertia.determinant() > 0.0)) return fail("body: inertia tensor must be positive definite");
        info.invInertia = info.inertia.inverse();
    }
    BodyState3 state;
    state.position = def.position;
    state.rotation = normalized(q);
    state.center = transformPoint(Transform3{state.position, toMatrix(state.rotation)}, info.localCenter);
    if (def.type != BodyType3::staticBody) {
        state.velocity = def.linearVelocity;
        state.angularVelocity = def.angularVelocity;
    }
    const BodyId id = mBodies.create(state, info);
    if (id.isNull()) return fail("world: body capacity reached");
    return id;
}

bool World3::destroyBody(BodyId id) { return mBodies.destroy(id); }

const BodyState3* World3::state(BodyId id) const {
    const int d = mBodies.denseIndex(id);
    return d < 0 ? nullptr : &mBodies.hotArray()[std::size_t(d)];
}

const BodyInfo3* World3::info(BodyId id) const {
    const int d = mBodies.denseIndex(id);
    return d < 0 ? nullptr : &mBodies.coldArray()[std::size_t(d)];
}

Transform3 World3::transform(BodyId id) const {
    const BodyState3* s = state(id);
    return s ? Transform3{s->position, toMatrix(s->rotation)} : Transform3{};
}

bool World3::setVelocity(BodyId id, const Vec3& v, const Vec3& w) {
    const int d = mBodies.denseIndex(id);
    if (d < 0 || !D3::finite(v) || !D3::finite(w)) return false;
    BodyInfo3& info = mBodies.cold(d);
    if (info.type == BodyType3::staticBody) return false;
    mBodies.hot(d).velocity = v;
    mBodies.hot(d).angularVelocity = w;
    info.awake = true;
    info.sleepTime = 0.0;
    return true;
}

bool World3::applyImpulse(BodyId id, const Vec3& impulse, const Vec3& worldPoint) {
    const int d = mBodies.denseIndex(id);
    if (d < 0 || !D3::finite(impulse) || !D3::finite(worldPoint)) return false;
    BodyInfo3& info = mBodies.cold(d);
    if (info.type != BodyType3::dynamicBody) return false;
    BodyState3& s = mBodies.hot(d);
    const Mat3 invI = rotateTensor(toMatrix(s.rotation), info.invInertia);  // world-frame I^-1 = R I_b^-1 R^T
    s.velocity = D3::add(s.velocity, D3::scale(info.invMass, impulse));
    s.angularVelocity = D3::add(s.angularVelocity, mul(invI, D3::cross(D3::sub(worldPoint, s.center), impulse)));
    info.awake = true;
    info.sleepTime = 0.0;
    return true;
}

std::vector<BodyId> World3::bodyIds() const {
    std::vector<BodyId> ids;
    for (int d = 0; d < mBodies.size(); ++d) ids.push_back(mBodies.idAt(d));
    return ids;
}

void World3::collideAll(std::vector<Contact>& out) {
    const auto& hot = mBodies.hotArray();
    const auto& cold = mBodies.coldArray();
    struct Proxy {
        int body, shape;
        double reach;  // how far the shape can move this step (m): dt (|v| + |w| extent)
    };
    std::vector<Proxy> proxies;
    std::vector<Aabb3> boxes;
    std::vector<std::uint8_t> inactive;
    std::vector<Transform3> xfs(hot.size());
    const double margin = mDef.speculativeDistance;
    const double dt = 1.0 / mDef.hz;
    for (int d = 0; d < int(hot.size()); ++d) {
        const BodyState3& st = hot[std::size_t(d)];
        xfs[std::size_t(d)] = Transform3{st.position, toMatrix(st.rotation)};
        for (int s = 0; s < int(cold[std::size_t(d)].shapes.size()); ++s) {
            const Shape3& shape = cold[std::size_t(d)].shapes[std::size_t(s)];
            Aabb3 box = computeAabb(shape, xfs[std::size_t(d)]);
            double reach = 0.0;
            if (shape.type != ShapeType3::plane) {
                const Vec3 half = D3::scale(0.5, D3::sub(box.upper, box.lower));
                const Vec3 mid = D3::scale(0.5, D3::add(box.upper, box.lower));
                const double extent = length(half) + length(D3::sub(mid, st.center));
                reach = dt * (length(st.velocity) + length(st.angularVelocity) * extent);
            }
            const double grow = margin + reach;
            box.lower = D3::sub(box.lower, Vec3(grow, grow, grow));
            box.upper = D3::add(box.upper, Vec3(grow, grow, grow));
            proxies.push_back({d, s, reach});
            boxes.push_back(box);
            inactive.push_back(cold[std::size_t(d)].type == BodyType3::dynamicBody ? 0 : 1);
        }
    }
    mCandidates.clear();
    for (const auto& [p, q] : findPairs3(boxes, inactive)) {
        const Proxy& pa = proxies[std::size_t(p)];
        const Proxy& pb = proxies[std::size_t(q)];
        if (pa.body == pb.body) continue;
        const Shape3& shA = cold[std::size_t(pa.body)].shapes[std::size_t(pa.shape)];
        const Shape3& shB = cold[std::size_t(pb.body)].shapes[std::size_t(pb.shape)];
        const Manifold3 m = collide(shA, xfs[std::size_t(pa.body)], shB, xfs[std::size_t(pb.body)],
                                    margin + pa.reach + pb.reach, mCapture ? &mCandidates : nullptr);
        mStats.candidates += m.candidates;
        for (int k = 0; k < m.count; ++k) {
            Contact c;
            c.bodyA = pa.body;
            c.bodyB = pb.body;
            c.shapeA = pa.shape;
            c.shapeB = pb.shape;
            c.point = m.points[std::size_t(k)];
            c.friction = std::sqrt(shA.friction * shB.friction);  // mixing as in Box2D
            c.restitution = std::max(shA.restitution, shB.restitution);
            out.push_back(c);
        }
    }
}

void World3::solveIsland(const std::vector<int>& bodies, const std::vector<int>& contactIdx,
                         std::vector<Contact>& contacts, std::vector<ContactKey>& newCache) {
    const double dt = 1.0 / mDef.hz;
    auto& hot = mBodies.hotArray();
    auto& cold = mBodies.coldArray();
    // Local numbering: the island's dynamic bodies, then every static or kinematic body its contacts touch.
    std::vector<int> local;
    std::vector<Body3> rb;
    if (mLocalIndex.size() < hot.size()) mLocalIndex.resize(hot.size(), -1);
    auto localOf = [&](int dense) {
        const int known = mLocalIndex[std::size_t(dense)];
        if (known >= 0) return known;
        mLocalIndex[std::size_t(dense)] = int(local.size());
        local.push_back(dense);
        Body3 b;
        const BodyInfo3& info = cold[std::size_t(dense)];
        const BodyState3& s = hot[std::size_t(dense)];
        if (info.type == BodyType3::dynamicBody) {
            b.invMass = info.invMass;
            b.invInertia = rotateTensor(toMatrix(s.rotation), info.invInertia);  // world-frame I^-1 = R I_b^-1 R^T
        }
        b.position = s.center;
        b.velocity = s.velocity;
        b.angularVelocity = s.angularVelocity;
        rb.push_back(b);
        return int(local.size()) - 1;
    };
    for (int d : bodies) localOf(d);
    const int k = D3::frictionDirectionCount(mDef.frictionDirections);
    std::vector<Contact3> nodes;
    std::vector<int> warm;
    const int nc = int(contactIdx.size());
    for (int ci = 0; ci < nc; ++ci) {
        const Contact& c = contacts[std::size_t(contactIdx[std::size_t(ci)])];
        Contact3 node = makeContact<Dim3>(localOf(c.bodyA), localOf(c.bodyB), c.point.point, c.point.normal,
                                          c.restitution, c.friction);
        const double sep = c.point.separation;
        // As in World2: no position-correction velocity on a bouncing contact (it would add energy); a speculative
        // contact that closes within this step and bounces gets plain restitution, one that does not close only
        // keeps its gap >= 0.
        const double vrel = relativeNormalVelocity(rb, node);
        const bool bounces = c.restitution > 0.0 && vrel < -mDef.restitutionThreshold;
        if (sep > 0.0) {
            node.bias = bounces && sep + dt * vrel < 0.0 ? 0.0 : -sep / dt;
        } else {
            node.bias = bounces ? 0.0
                                : std::min(mDef.maxCorrectionSpeed,
                                           mDef.baumgarte * std::max(0.0, -sep - mDef.linearSlop) / dt);
        }
        nodes.push_back(node);
        if (const ContactKey* hit = mCache.find(keyOf(c))) appendWarmBasis(hit->basicMask, ci, nc, k, warm);
    }
    for (int d : local) mLocalIndex[std::size_t(d)] = -1;
    ResolverOptions options;
    options.restitutionThreshold = mDef.restitutionThreshold;
    options.frictionDirections = k;
    options.tangentDeadZone = mDef.tangentDeadZone;
    options.lcp = mDef.lcp;
    options.lcp.warmBasis = warm.empty() ? nullptr : &warm;
    if (options.lcp.maxPivots <= 0) options.lcp.maxPivots = 2 * (k + 2) * nc + 100;
    Resolution r = resolveWithFriction(rb, nodes, options, mSolver);
    if (r.status != LcpStatus::solved) {
        ++mStats.failedIslands;
        options.lcp.warmBasis = nullptr;
        options.lcp.maxPivots = mDef.lcp.maxPivots > 0 ? mDef.lcp.maxPivots : 10 * nc + 1000;
        r = resolveCollisions(rb, nodes, options, mSolver);
    }
    mStats.pivots += r.pivots;
    mStats.maxIslandPivots = std::max(mStats.maxIslandPivots, r.pivots);
    mStats.work += r.work;
    mStats.maxResidual = std::max(mStats.maxResidual, r.residual);
    if (!warm.empty()) ++mStats.warmStartedIslands;
    if (r.status != LcpStatus::solved) {
        ++mStats.unsolvedIslands;
        return;
    }
    const bool friction = !r.tangentImpulses.empty();
    for (int ci = 0; ci < nc; ++ci) {
        Contact& c = contacts[std::size_t(contactIdx[std::size_t(ci)])];
        c.normalImpulse = r.impulses[std::size_t(ci)];
        if (friction)
            c.tangentImpulse = Vec3(r.tangentImpulses[std::size_t(3 * ci)], r.tangentImpulses[std::size_t(3 * ci + 1)],
                                    r.tangentImpulses[std::size_t(3 * ci + 2)]);
        newCache.push_back(keyOf(c));
    }
    storeBasis(r.basis, nc, k, friction, &newCache[newCache.size() - std::size_t(nc)]);
    for (int kk = 0; kk < int(local.size()); ++kk) {
        const int d = local[std::size_t(kk)];
        if (cold[std::size_t(d)].type != BodyType3::dynamicBody) continue;
        hot[std::size_t(d)].velocity = rb[std::size_t(kk)].velocity;
        hot[std::size_t(d)].angularVelocity = rb[std::size_t(kk)].angularVelocity;
    }
}

void World3::integrate(int d, double dt) {
    BodyState3& s = mBodies.hot(d);
    s.center = D3::add(s.center, D3::scale(dt, s.velocity));
    s.rotation = integrateRotation(s.rotation, s.angularVelocity, dt);
    s.position = D3::sub(s.center, mul(toMatrix(s.rotation), mBodies.cold(d).localCenter));
}

void World3::step() {
    const double dt = 1.0 / mDef.hz;
    auto& hot = mBodies.hotArray();
    auto& cold = mBodies.coldArray();
    const int nb = mBodies.size();
    mStats = StepStats3{};
    // 1. External forces into velocities (semi-implicit Euler).
    for (int d = 0; d < nb; ++d) {
        if (cold[std::size_t(d)].type == BodyType3::dynamicBody && cold[std::size_t(d)].awake)
            hot[std::size_t(d)].velocity = D3::add(hot[std::size_t(d)].velocity, D3::scale(dt, mDef.gravity));
    }
    // 2-3. Broadphase and narrowphase.
    std::vector<Contact> contacts;
    collideAll(contacts);
    mStats.contacts = int(contacts.size());
    // 4. Islands over dynamic bodies (core/island).
    std::vector<std::uint8_t> joins(std::size_t(nb), 0);
    for (int d = 0; d < nb; ++d) joins[std::size_t(d)] = cold[std::size_t(d)].type == BodyType3::dynamicBody ? 1 : 0;
    std::vector<IslandEdge> edges;
    edges.reserve(contacts.size());
    for (const Contact& c : contacts) edges.push_back({c.bodyA, c.bodyB});
    const Islands islands = buildIslands(nb, joins, edges);
    mStats.islands = islands.count();
    // 5-7. Per island: wake or skip, solve, integrate, sleep.
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
            for (int ci : icontacts)
                if (const ContactKey* hit = mCache.find(keyOf(contacts[std::size_t(ci)]))) newCache.push_back(*hit);
            continue;
        }
        ++mStats.awakeIslands;
        for (int d : ibodies) cold[std::size_t(d)].awake = true;
        if (!icontacts.empty()) solveIsland(ibodies, icontacts, contacts, newCache);
        double minSleep = 1e300;
        for (int d : ibodies) {
            integrate(d, dt);
            const BodyState3& s = hot[std::size_t(d)];
            BodyInfo3& info = cold[std::size_t(d)];
            const double lin = mDef.linearSleepTolerance, ang = mDef.angularSleepTolerance;
            const bool slow = D3::dot(s.velocity, s.velocity) <= lin * lin &&
                              D3::dot(s.angularVelocity, s.angularVelocity) <= ang * ang;
            info.sleepTime = slow ? info.sleepTime + dt : 0.0;
            minSleep = std::min(minSleep, info.sleepTime);
        }
        if (mDef.enableSleep && minSleep >= mDef.timeToSleep) {
            for (int d : ibodies) {
                cold[std::size_t(d)].awake = false;
                hot[std::size_t(d)].velocity = Vec3::Zero();
                hot[std::size_t(d)].angularVelocity = Vec3::Zero();
            }
        }
    }
    for (int d = 0; d < nb; ++d)  // kinematic bodies move on their own
        if (cold[std::size_t(d)].type == BodyType3::kinematicBody) integrate(d, dt);
    mCache.replace(newCache);
    // 8. Contact points, begin/end events (pairs of bodies touching with overlap), statistics.
    mContactPoints.clear();
    TouchPairs touching;
    for (const Contact& c : contacts) {
        const BodyId a = mBodies.idAt(c.bodyA), b = mBodies.idAt(c.bodyB);
        mContactPoints.push_back({a, b, c.point.point, c.point.normal, c.point.separation, c.normalImpulse,
                                  c.tangentImpulse, c.point.id});
        if (c.point.separation < 0.0) {
            mStats.maxPenetration = std::max(mStats.maxPenetration, -c.point.separation);
            std::uint64_t ka = touchKey(a), kb = touchKey(b);
            if (kb < ka) std::swap(ka, kb);
            touching.emplace_back(ka, kb);
        }
    }
    touchEvents(touching, mTouching, mBegin, mEnd);
    mTouching.swap(touching);
    ++mStepCount;
}

}  // namespace unison
