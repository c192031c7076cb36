// resolver2d/world2d.cpp — the 2D step (see world2d.h).
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

#include <algorithm>
#include <cmath>

namespace unison {

struct World2::Contact {
    int bodyA = -1, bodyB = -1;    // dense indices; the normal points away from B towards A
    int shapeA = 0, shapeB = 0;
    Vec2 normal;
    ManifoldPoint2 point;
    double friction = 0.0, restitution = 0.0;
    double normalImpulse = 0.0, tangentImpulse = 0.0;
};

bool World2::CacheEntry::operator<(const CacheEntry& o) const {
    if (slotA != o.slotA) return slotA < o.slotA;
    if (slotB != o.slotB) return slotB < o.slotB;
    if (shapeA != o.shapeA) return shapeA < o.shapeA;
    if (shapeB != o.shapeB) return shapeB < o.shapeB;
    return feature < o.feature;
}

bool World2::CacheEntry::sameKey(const CacheEntry& o) const {
    return slotA == o.slotA && slotB == o.slotB && shapeA == o.shapeA && shapeB == o.shapeB && feature == o.feature;
}

World2::World2(const WorldDef2& def) : mDef(def) {}

namespace {

bool finiteVec(Vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }

std::uint64_t pairKey(BodyId id) { return (std::uint64_t(id.generation) << 32) | id.index1; }

}  // namespace

void World2::updateBodyCenter(BodyState2& s, const BodyInfo2& info) const {
    s.center = s.position + rotate(s.rotation, info.localCenter);
}

BodyId World2::createBody(const BodyDef2& def, const std::vector<Shape2>& shapes, std::string* error) {
    auto fail = [&](const std::string& why) {
        if (error) *error = why;
        return BodyId::null();
    };
    if (!finiteVec(def.position) || !std::isfinite(def.angle) || !finiteVec(def.linearVelocity) ||
        !std::isfinite(def.angularVelocity))
        return fail("body: position, angle and velocities must be finite");
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
    const BodyId id = mBodies.create(state, info);
    if (id.isNull()) return fail("world: body capacity reached");
    return id;
}

bool World2::destroyBody(BodyId id) {
    if (!mBodies.destroy(id)) return false;
    // Warm-start entries are keyed by slot: drop the ones of this body, or a body created later in the same slot
    // would inherit them.
    mCache.erase(std::remove_if(mCache.begin(), mCache.end(),
                                [&](const CacheEntry& e) { return e.slotA == id.index1 || e.slotB == id.index1; }),
                 mCache.end());
    return true;
}

const BodyState2* World2::state(BodyId id) const {
    const int d = mBodies.denseIndex(id);
    return d < 0 ? nullptr : &mBodies.hotArray()[std::size_t(d)];
}

const BodyInfo2* World2::info(BodyId id) const {
    const int d = mBodies.denseIndex(id);
    return d < 0 ? nullptr : &mBodies.coldArray()[std::size_t(d)];
}

double World2::angle(BodyId id) const {
    const BodyState2* s = state(id);
    return s ? angleOf(s->rotation) : 0.0;
}

bool World2::setVelocity(BodyId id, Vec2 v, double w) {
    const int d = mBodies.denseIndex(id);
    if (d < 0 || !finiteVec(v) || !std::isfinite(w)) return false;
    BodyInfo2& info = mBodies.cold(d);
    if (info.type == BodyType::staticBody) return false;
    mBodies.hot(d).velocity = v;
    mBodies.hot(d).angularVelocity = w;
    info.awake = true;
    info.sleepTime = 0.0;
    return true;
}

bool World2::applyImpulse(BodyId id, Vec2 impulse, Vec2 worldPoint) {
    const int d = mBodies.denseIndex(id);
    if (d < 0 || !finiteVec(impulse) || !finiteVec(worldPoint)) return false;
    BodyInfo2& info = mBodies.cold(d);
    if (info.type != BodyType::dynamicBody) return false;
    BodyState2& s = mBodies.hot(d);
    s.velocity = s.velocity + info.invMass * impulse;
    s.angularVelocity += info.invInertia * cross(worldPoint - s.center, impulse);
    info.awake = true;
    info.sleepTime = 0.0;
    return true;
}

std::vector<BodyId> World2::bodyIds() const {
    std::vector<BodyId> ids;
    for (int d = 0; d < mBodies.size(); ++d) ids.push_back(mBodies.idAt(d));
    return ids;
}

void World2::collideAll(std::vector<Contact>& out) const {
    const auto& hot = mBodies.hotArray();
    const auto& cold = mBodies.coldArray();
    struct Proxy {
        int body, shape;
        double reach;  // how far the shape can move this step (m): dt (|v| + |w| extent)
    };
    std::vector<Proxy> proxies;
    std::vector<Aabb2> boxes;
    std::vector<std::uint8_t> inactive;
    const double margin = mDef.speculativeDistance;
    const double dt = 1.0 / mDef.hz;
    for (int d = 0; d < int(hot.size()); ++d) {
        const BodyState2& st = hot[std::size_t(d)];
        const Transform2 xf{st.position, st.rotation};
        for (int s = 0; s < int(cold[std::size_t(d)].shapes.size()); ++s) {
            Aabb2 box = computeAabb(cold[std::size_t(d)].shapes[std::size_t(s)], xf);
            // Speculative reach: a contact that can close within this step must already be in this step's LCP,
            // or fast bodies sink deep before they are seen (and position correction then adds energy).
            const Vec2 half = 0.5 * (box.upper - box.lower);
            const Vec2 mid = 0.5 * (box.upper + box.lower);
            const double extent = length(half) + length(mid - st.center);
            const double reach = dt * (length(st.velocity) + std::fabs(st.angularVelocity) * extent);
            const double grow = margin + reach;
            box.lower = box.lower - Vec2{grow, grow};
            box.upper = box.upper + Vec2{grow, grow};
            proxies.push_back({d, s, reach});
            boxes.push_back(box);
            inactive.push_back(cold[std::size_t(d)].type == BodyType::dynamicBody ? 0 : 1);
        }
    }
    for (const auto& [p, q] : findPairs(boxes, inactive)) {
        const Proxy& pa = proxies[std::size_t(p)];
        const Proxy& pb = proxies[std::size_t(q)];
        if (pa.body == pb.body) continue;
        const BodyState2& sa = hot[std::size_t(pa.body)];
        const BodyState2& sb = hot[std::size_t(pb.body)];
        const Shape2& shA = cold[std::size_t(pa.body)].shapes[std::size_t(pa.shape)];
        const Shape2& shB = cold[std::size_t(pb.body)].shapes[std::size_t(pb.shape)];
        const Manifold2 m = collide(shA, Transform2{sa.position, sa.rotation}, shB, Transform2{sb.position, sb.rotation},
                                    margin + pa.reach + pb.reach);
        for (int k = 0; k < m.count; ++k) {
            Contact c;
            c.bodyA = pa.body;
            c.bodyB = pb.body;
            c.shapeA = pa.shape;
            c.shapeB = pb.shape;
            c.normal = m.normal;
            c.point = m.points[std::size_t(k)];
            c.friction = std::sqrt(shA.friction * shB.friction);  // mixing as in Box2D
            c.restitution = std::max(shA.restitution, shB.restitution);
            out.push_back(c);
        }
    }
}

void World2::solveIsland(const std::vector<int>& bodies, const std::vector<int>& contactIdx, std::vector<Contact>& contacts,
                         std::vector<CacheEntry>& newCache) {
    const double dt = 1.0 / mDef.hz;
    auto& hot = mBodies.hotArray();
    auto& cold = mBodies.coldArray();
    // Local numbering: the island's dynamic bodies, then every static or kinematic body its contacts touch.
    std::vector<int> local;
    std::vector<Body2> rb;
    if (mLocalIndex.size() < hot.size()) mLocalIndex.resize(hot.size(), -1);
    auto localOf = [&](int dense) {
        const int known = mLocalIndex[std::size_t(dense)];
        if (known >= 0) return known;
        mLocalIndex[std::size_t(dense)] = int(local.size());
        local.push_back(dense);
        Body2 b;
        const BodyInfo2& info = cold[std::size_t(dense)];
        const BodyState2& s = hot[std::size_t(dense)];
        if (info.type == BodyType::dynamicBody) {
            b.invMass = info.invMass;
            b.invInertia = info.invInertia;
        }
        b.position = s.center;
        b.velocity = s.velocity;
        b.angularVelocity = s.angularVelocity;
        rb.push_back(b);
        return int(local.size()) - 1;
    };
    for (int d : bodies) localOf(d);
    std::vector<Contact2> nodes;
    std::vector<double> positionBias;  // per node: the bias of the position solve (differs on bouncing contacts)
    bool split = false;                // some contact bounces this step: positions need their own solve
    std::vector<int> warm;
    const int nc = int(contactIdx.size());
    const int k = 2;  // 2D pyramid: +t and -t
    for (int ci = 0; ci < nc; ++ci) {
        const Contact& c = contacts[std::size_t(contactIdx[std::size_t(ci)])];
        Contact2 node = makeContact<Dim2>(localOf(c.bodyA), localOf(c.bodyB), c.point.point, c.normal, c.restitution,
                                          c.friction);
        const double sep = c.point.separation;
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
        const bool approachesFast = c.restitution > 0.0 && vrel < -mDef.restitutionThreshold;
        const bool bounces = approachesFast && sep + dt * vrel < 0.0;
        double moveBias;
        if (bounces) {
            node.bias = 0.0;
            moveBias = std::min(mDef.maxCorrectionSpeed, -(1.0 + c.restitution) * sep / dt);
            split = split || moveBias != 0.0;  // touching at the step's start (the cradle): one solve does both
        } else if (sep > 0.0) {
            if (approachesFast) node.restitution = 0.0;
            node.bias = -sep / dt;
            moveBias = node.bias;
        } else {
            node.bias = std::min(mDef.maxCorrectionSpeed, mDef.baumgarte * std::max(0.0, -sep - mDef.linearSlop) / dt);
            moveBias = node.bias;
        }
        positionBias.push_back(moveBias);
        nodes.push_back(node);
        // Warm start: which of this contact's unknowns were basic last step.
        CacheEntry key{mBodies.idAt(c.bodyA).index1, mBodies.idAt(c.bodyB).index1, std::uint16_t(c.shapeA),
                       std::uint16_t(c.shapeB), c.point.id, 0};
        const auto it = std::lower_bound(mCache.begin(), mCache.end(), key);
        if (it != mCache.end() && it->sameKey(key)) {
            if (it->basicMask & 1u) warm.push_back(ci);
            for (int m = 0; m < k; ++m) {
                if (it->basicMask & (2u << m)) warm.push_back(nc + ci * k + m);
            }
            if (it->basicMask & 8u) warm.push_back(nc + nc * k + ci);
        }
    }
    for (int d : local) mLocalIndex[std::size_t(d)] = -1;  // leave the map clean for the next island
    ResolverOptions options;
    options.restitutionThreshold = mDef.restitutionThreshold;
    options.frictionDirections = k;
    options.tangentDeadZone = mDef.tangentDeadZone;
    options.acceptResidual = mDef.acceptResidual;
    options.lcp = mDef.lcp;
    // The friction LCP; if it fails, the frictionless LCP keeps the island from falling through (it always has a
    // solution for approaching contacts between bodies that can move). A frame must not stall: a healthy path
    // takes about n/2 pivots, so 2n + 100 bounds a bad one (n = 4 nc unknowns). WorldDef2::lcp.maxPivots
    // overrides both caps.
    auto usable = [](const Resolution& res) { return res.status == LcpStatus::solved || res.approximate; };
    auto solve = [&](std::vector<Body2>& ioBodies, const std::vector<Contact2>& inNodes, const std::vector<int>* inWarm) {
        options.lcp.warmBasis = inWarm && !inWarm->empty() ? inWarm : nullptr;
        options.lcp.maxPivots = mDef.lcp.maxPivots > 0 ? mDef.lcp.maxPivots : 2 * 4 * nc + 100;
        Resolution res = resolveWithFriction(ioBodies, inNodes, options, mSolver);
        if (res.approximate) ++mStats.approximateIslands;
        if (!usable(res)) {
            ++mStats.failedIslands;
            options.lcp.warmBasis = nullptr;
            options.lcp.maxPivots = mDef.lcp.maxPivots > 0 ? mDef.lcp.maxPivots : 10 * nc + 1000;
            res = resolveCollisions(ioBodies, inNodes, options, mSolver);
        }
        mStats.pivots += res.pivots;
        mStats.maxIslandPivots = std::max(mStats.maxIslandPivots, res.pivots);
        mStats.work += res.work;
        mStats.maxResidual = std::max(mStats.maxResidual, res.residual);
        mStats.maxScaledResidual = std::max(mStats.maxScaledResidual, res.scaledResidual);
        return res;
    };
    const std::vector<Body2> before = split ? rb : std::vector<Body2>{};
    Resolution r = solve(rb, nodes, &warm);
    if (!warm.empty()) ++mStats.warmStartedIslands;
    if (split && usable(r)) {
        // The position solve (see the bias comment above), warm-started from the velocity solve's basis.
        std::vector<Body2> moved = before;
        for (int ci = 0; ci < nc; ++ci) nodes[std::size_t(ci)].bias = positionBias[std::size_t(ci)];
        const Resolution rp = solve(moved, nodes, &r.basis);
        if (usable(rp)) {
            for (int kk = 0; kk < int(local.size()); ++kk) {
                const int d = local[std::size_t(kk)];
                if (cold[std::size_t(d)].type != BodyType::dynamicBody) continue;
                mMove[std::size_t(d)] = {moved[std::size_t(kk)].velocity, moved[std::size_t(kk)].angularVelocity, true};
            }
        }
    }
    if (!usable(r)) return;  // no impulse at all this step: counted above
    for (int ci = 0; ci < nc; ++ci) {
        Contact& c = contacts[std::size_t(contactIdx[std::size_t(ci)])];
        c.normalImpulse = r.impulses[std::size_t(ci)];
        if (!r.tangentImpulses.empty()) {
            const Vec2 t{r.tangentImpulses[std::size_t(2 * ci)], r.tangentImpulses[std::size_t(2 * ci + 1)]};
            c.tangentImpulse = dot(t, Vec2{-c.normal.y, c.normal.x});
        }
        CacheEntry e{mBodies.idAt(c.bodyA).index1, mBodies.idAt(c.bodyB).index1, std::uint16_t(c.shapeA),
                     std::uint16_t(c.shapeB), c.point.id, 0};
        newCache.push_back(e);
    }
    // Basis bits per contact (a friction solve: normal ci, tangents nc + ci k + m, slack nc + nc k + ci).
    const std::size_t first = newCache.size() - std::size_t(nc);
    const bool friction = !r.tangentImpulses.empty();
    for (int idx : r.basis) {
        std::uint32_t bit = 0;
        int ci = idx;
        if (!friction || idx < nc) {
            bit = 1u;
        } else if (idx < nc + nc * k) {
            ci = (idx - nc) / k;
            bit = 2u << ((idx - nc) % k);
        } else {
            ci = idx - nc - nc * k;
            bit = 8u;
        }
        newCache[first + std::size_t(ci)].basicMask |= bit;
    }
    for (int kk = 0; kk < int(local.size()); ++kk) {
        const int d = local[std::size_t(kk)];
        if (cold[std::size_t(d)].type != BodyType::dynamicBody) continue;
        hot[std::size_t(d)].velocity = rb[std::size_t(kk)].velocity;
        hot[std::size_t(d)].angularVelocity = rb[std::size_t(kk)].angularVelocity;
    }
}

void World2::step() {
    const double dt = 1.0 / mDef.hz;
    auto& hot = mBodies.hotArray();
    auto& cold = mBodies.coldArray();
    const int nb = mBodies.size();
    mStats = StepStats2{};
    // 1. External forces into velocities (semi-implicit Euler).
    for (int d = 0; d < nb; ++d) {
        if (cold[std::size_t(d)].type == BodyType::dynamicBody && cold[std::size_t(d)].awake)
            hot[std::size_t(d)].velocity = hot[std::size_t(d)].velocity + dt * mDef.gravity;
    }
    // 2-3. Broadphase and narrowphase.
    std::vector<Contact> contacts;
    collideAll(contacts);
    mStats.contacts = int(contacts.size());
    // 4. Islands over dynamic bodies; every contact point joins its two bodies.
    std::vector<std::uint8_t> joins(std::size_t(nb), 0);
    for (int d = 0; d < nb; ++d) joins[std::size_t(d)] = cold[std::size_t(d)].type == BodyType::dynamicBody ? 1 : 0;
    std::vector<IslandEdge> edges;
    edges.reserve(contacts.size());
    for (const Contact& c : contacts) edges.push_back({c.bodyA, c.bodyB});
    const Islands islands = buildIslands(nb, joins, edges);
    mStats.islands = islands.count();
    // 5-7. Per island: wake or skip, solve, integrate, sleep.
    mMove.assign(std::size_t(nb), Move{});
    std::vector<CacheEntry> newCache;
    std::vector<int> ibodies, icontacts;
    for (int isl = 0; isl < islands.count(); ++isl) {
        ibodies.assign(islands.bodies.begin() + islands.bodyStart[std::size_t(isl)],
                       islands.bodies.begin() + islands.bodyStart[std::size_t(isl) + 1]);
        icontacts.assign(islands.edges.begin() + islands.edgeStart[std::size_t(isl)],
                         islands.edges.begin() + islands.edgeStart[std::size_t(isl) + 1]);
        bool anyAwake = false;
        for (int d : ibodies) anyAwake = anyAwake || cold[std::size_t(d)].awake;
        if (!anyAwake) {
            // A sleeping island keeps its warm-start data.
            for (int ci : icontacts) {
                const Contact& c = contacts[std::size_t(ci)];
                CacheEntry key{mBodies.idAt(c.bodyA).index1, mBodies.idAt(c.bodyB).index1, std::uint16_t(c.shapeA),
                               std::uint16_t(c.shapeB), c.point.id, 0};
                const auto it = std::lower_bound(mCache.begin(), mCache.end(), key);
                if (it != mCache.end() && it->sameKey(key)) newCache.push_back(*it);
            }
            continue;
        }
        ++mStats.awakeIslands;
        for (int d : ibodies) cold[std::size_t(d)].awake = true;
        if (!icontacts.empty()) solveIsland(ibodies, icontacts, contacts, newCache);
        double minSleep = 1e300;
        for (int d : ibodies) {
            BodyState2& s = hot[std::size_t(d)];
            BodyInfo2& info = cold[std::size_t(d)];
            const Move& move = mMove[std::size_t(d)];
            s.center = s.center + dt * (move.set ? move.velocity : s.velocity);
            s.rotation = integrateRotation(s.rotation, dt * (move.set ? move.angularVelocity : s.angularVelocity));
            s.position = s.center - rotate(s.rotation, info.localCenter);
            const bool slow = dot(s.velocity, s.velocity) <= mDef.linearSleepTolerance * mDef.linearSleepTolerance &&
                              std::fabs(s.angularVelocity) <= mDef.angularSleepTolerance;
            info.sleepTime = slow ? info.sleepTime + dt : 0.0;
            minSleep = std::min(minSleep, info.sleepTime);
        }
        if (mDef.enableSleep && minSleep >= mDef.timeToSleep) {
            for (int d : ibodies) {
                cold[std::size_t(d)].awake = false;
                hot[std::size_t(d)].velocity = Vec2{};
                hot[std::size_t(d)].angularVelocity = 0.0;
            }
        }
    }
    // Kinematic bodies move on their own.
    for (int d = 0; d < nb; ++d) {
        if (cold[std::size_t(d)].type != BodyType::kinematicBody) continue;
        BodyState2& s = hot[std::size_t(d)];
        s.center = s.center + dt * s.velocity;
        s.rotation = integrateRotation(s.rotation, dt * s.angularVelocity);
        s.position = s.center - rotate(s.rotation, cold[std::size_t(d)].localCenter);
    }
    std::sort(newCache.begin(), newCache.end());
    mCache.swap(newCache);
    // 8. Contact points, begin/end events (pairs of bodies touching with overlap), statistics.
    mContactPoints.clear();
    std::vector<std::pair<std::uint64_t, std::uint64_t>> touching;
    for (const Contact& c : contacts) {
        const BodyId a = mBodies.idAt(c.bodyA), b = mBodies.idAt(c.bodyB);
        mContactPoints.push_back({a, b, c.point.point, c.normal, c.point.separation, c.normalImpulse, c.tangentImpulse, c.point.id});
        if (c.point.separation < 0.0) {
            mStats.maxPenetration = std::max(mStats.maxPenetration, -c.point.separation);
            std::uint64_t ka = pairKey(a), kb = pairKey(b);
            if (kb < ka) std::swap(ka, kb);
            touching.emplace_back(ka, kb);
        }
    }
    std::sort(touching.begin(), touching.end());
    touching.erase(std::unique(touching.begin(), touching.end()), touching.end());
    mBegin.clear();
    mEnd.clear();
    auto idOf = [](std::uint64_t key) { return BodyId{std::uint32_t(key & 0xffffffffu), std::uint32_t(key >> 32)}; };
    std::vector<std::pair<std::uint64_t, std::uint64_t>> diff;
    std::set_difference(touching.begin(), touching.end(), mTouching.begin(), mTouching.end(), std::back_inserter(diff));
    for (const auto& p : diff) mBegin.push_back({idOf(p.first), idOf(p.second)});
    diff.clear();
    std::set_difference(mTouching.begin(), mTouching.end(), touching.begin(), touching.end(), std::back_inserter(diff));
    for (const auto& p : diff) mEnd.push_back({idOf(p.first), idOf(p.second)});
    mTouching.swap(touching);
    ++mStepCount;
}

}  // namespace unison
