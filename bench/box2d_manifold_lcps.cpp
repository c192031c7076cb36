// bench/box2d_manifold_lcps.cpp — contact LCPs from Box2D 2.4.1's manifolds (see box2d_manifold_lcps.h).
//
// The float assembler follows the row picture of core/contact_resolver_impl.h: every LCP row is a direction l at a
// point, +l on body a and -l on body b, and A_ij sums, over the movable bodies k the two rows share (in body index
// order), l_i.l_j / m_k + (r_ki x l_i) I_k^-1 (r_kj x l_j). Here every one of those operations rounds to float.
#include "box2d_manifold_lcps.h"

#include "box2d_peer.h"
#include "make_scenes2d.h"

#include <box2d/box2d.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

namespace unison::bench {
namespace {

// One LCP row in arithmetic T: direction `l` acting +l on body[0] and -l on body[1].
template <class T>
struct Row {
    int body[2] = {-1, -1};
    T lx[2] = {0, 0}, ly[2] = {0, 0};  // +l, -l
    T ang[2] = {0, 0};                 // r_a x l, r_b x (-l)
};

template <class T>
struct Body {
    T cx, cy, vx, vy, w, invMass, invI;
};

template <class T>
Body<T> bodyIn(const ManifoldBody& b) {
    return {T(b.cx), T(b.cy), T(b.vx), T(b.vy), T(b.w), T(b.invMass), T(b.invI)};
}

template <class T>
Row<T> makeRow(const std::vector<Body<T>>& bodies, const ManifoldPoint& p, T dx, T dy) {
    Row<T> row;
    row.body[0] = p.a;
    row.body[1] = p.b;
    const T px = T(p.px), py = T(p.py);
    for (int s = 0; s < 2; ++s) {
        const Body<T>& k = bodies[std::size_t(row.body[s])];
        const T lx = s == 0 ? dx : -dx, ly = s == 0 ? dy : -dy;
        const T rx = px - k.cx, ry = py - k.cy;
        row.lx[s] = lx;
        row.ly[s] = ly;
        row.ang[s] = rx * ly - ry * lx;
    }
    return row;
}

// l . (v + w x r) summed over both bodies: the row's relative velocity (w = A z + b at z = 0).
template <class T>
T rowVelocity(const std::vector<Body<T>>& bodies, const Row<T>& row) {
    T sum = T(0);
    for (int s = 0; s < 2; ++s) {
        const Body<T>& k = bodies[std::size_t(row.body[s])];
        sum = sum + (row.lx[s] * k.vx + row.ly[s] * k.vy + row.ang[s] * k.w);
    }
    return sum;
}

// A_ij of two rows, summed over their shared movable bodies in body index order, in arithmetic T.
template <class T>
bool coupling(const std::vector<Body<T>>& bodies, const Row<T>& ri, const Row<T>& rj, T* out) {
    bool any = false;
    T sum = T(0);
    int order[2] = {0, 1};
    if (ri.body[1] < ri.body[0]) std::swap(order[0], order[1]);
    for (int si : order) {
        const int k = ri.body[si];
        const Body<T>& b = bodies[std::size_t(k)];
        if (b.invMass == T(0) && b.invI == T(0)) continue;
        for (int sj = 0; sj < 2; ++sj) {
            if (rj.body[sj] != k) continue;
            const T term = (ri.lx[si] * rj.lx[sj] + ri.ly[si] * rj.ly[sj]) * b.invMass + (b.invI * ri.ang[si]) * rj.ang[sj];
            sum = any ? sum + term : term;
            any = true;
        }
    }
    *out = sum;
    return any;
}

// The LCP of `snap` in arithmetic T (float: Box2D's precision; double: the same roundings' order in double).
template <class T>
SparseLcp assembleRows(const ManifoldSnapshot& snap, bool friction) {
    std::vector<Body<T>> bodies;
    bodies.reserve(snap.bodies.size());
    for (const ManifoldBody& b : snap.bodies) bodies.push_back(bodyIn<T>(b));
    const int nc = int(snap.points.size());
    const int k = 2;  // 2D friction directions: +t, -t
    std::vector<Row<T>> rows;
    rows.reserve(std::size_t(friction ? nc * (k + 1) : nc));
    for (const ManifoldPoint& p : snap.points) rows.push_back(makeRow(bodies, p, T(p.nx), T(p.ny)));
    if (friction) {
        for (const ManifoldPoint& p : snap.points) {
            const T tx = -T(p.ny), ty = T(p.nx);  // t = perp(n), as Dim2::tangentDirection
            rows.push_back(makeRow(bodies, p, tx, ty));
            rows.push_back(makeRow(bodies, p, -tx, -ty));
        }
    }
    const int coupled = int(rows.size());
    const int n = friction ? nc * (k + 2) : nc;
    // Rows meeting each body, in row order.
    std::vector<std::vector<int>> byBody(bodies.size());
    for (int i = 0; i < coupled; ++i) {
        for (int s = 0; s < 2; ++s) byBody[std::size_t(rows[std::size_t(i)].body[s])].push_back(i);
    }
    LcpTriplets trip(n);
    for (int i = 0; i < coupled; ++i) {
        const Row<T>& ri = rows[std::size_t(i)];
        std::vector<int> partners;
        for (int s = 0; s < 2; ++s) {
            const Body<T>& b = bodies[std::size_t(ri.body[s])];
            if (b.invMass == T(0) && b.invI == T(0)) continue;
            const std::vector<int>& list = byBody[std::size_t(ri.body[s])];
            partners.insert(partners.end(), list.begin(), list.end());
        }
        std::sort(partners.begin(), partners.end());
        partners.erase(std::unique(partners.begin(), partners.end()), partners.end());
        for (int j : partners) {
            T value;
            if (coupling(bodies, ri, rows[std::size_t(j)], &value)) trip.add(i, j, double(value));
        }
        // Friction: the tangent rows' slack column (E), after their coupling entries as in the resolver.
        if (friction && i >= nc) trip.add(i, nc * (k + 1) + (i - nc) / k, 1.0);
        trip.b[std::size_t(i)] = double(rowVelocity(bodies, ri));
    }
    if (friction) {
        for (int c = 0; c < nc; ++c) {
            const int slack = nc * (k + 1) + c;
            trip.add(slack, c, double(T(snap.points[std::size_t(c)].friction)));  // mu f_n - sum beta >= 0
            for (int m = 0; m < k; ++m) trip.add(slack, nc + c * k + m, -1.0);
        }
    }
    return trip.toSparse();
}

}  // namespace

ManifoldSnapshot captureManifolds(const Box2dPeer& peer, double gravityY) {
    ManifoldSnapshot snap;
    std::map<const b2Body*, int> index;  // lookup only; never iterated
    const float h = float(1.0 / peer.hz()), g = float(gravityY);
    for (int i = 0; i < peer.bodyCount(); ++i) {
        const b2Body* body = peer.body(i);
        index[body] = i;
        ManifoldBody mb;
        const b2Vec2 c = body->GetWorldCenter();
        mb.cx = c.x;
        mb.cy = c.y;
        if (body->GetType() == b2_dynamicBody && body->GetMass() > 0.0f) {
            b2MassData md;
            body->GetMassData(&md);
            const float iCentre = md.I - md.mass * b2Dot(md.center, md.center);  // as b2Body::ResetMassData
            mb.invMass = 1.0f / md.mass;
            mb.invI = iCentre > 0.0f ? 1.0f / iCentre : 0.0f;
            const b2Vec2 v = body->GetLinearVelocity();
            mb.vx = v.x;
            mb.vy = v.y + h * g;  // Box2D's b2Island::Solve: v += h * gravity * gravityScale (scale 1)
            mb.w = body->GetAngularVelocity();
            ++snap.dynamicBodies;
        }
        snap.bodies.push_back(mb);
    }
    std::vector<std::tuple<int, int, int, ManifoldPoint>> found;
    for (const b2Contact* c = peer.world().GetContactList(); c; c = c->GetNext()) {
        if (!c->IsTouching() || !c->IsEnabled()) continue;
        const b2Body* bodyA = c->GetFixtureA()->GetBody();
        const b2Body* bodyB = c->GetFixtureB()->GetBody();
        b2WorldManifold wm;
        c->GetWorldManifold(&wm);
        const int ia = index.at(bodyA), ib = index.at(bodyB);
        for (int k = 0; k < c->GetManifold()->pointCount; ++k) {
            ManifoldPoint p;
            p.a = ib;  // Box2D's normal points from A to B: away from Unison's b (= Box2D's A)
            p.b = ia;
            p.px = wm.points[k].x;
            p.py = wm.points[k].y;
            p.nx = wm.normal.x;
            p.ny = wm.normal.y;
            p.friction = c->GetFriction();
            found.emplace_back(ia, ib, k, p);
        }
    }
    std::sort(found.begin(), found.end(), [](const auto& x, const auto& y) {
        return std::tie(std::get<0>(x), std::get<1>(x), std::get<2>(x)) < std::tie(std::get<0>(y), std::get<1>(y), std::get<2>(y));
    });
    for (const auto& f : found) snap.points.push_back(std::get<3>(f));
    return snap;
}

void toResolverInput(const ManifoldSnapshot& snap, std::vector<ResolverBody<Dim2>>* outBodies,
                     std::vector<ContactNode<Dim2>>* outContacts) {
    outBodies->clear();
    for (const ManifoldBody& b : snap.bodies) {
        ResolverBody<Dim2> rb;
        rb.invMass = b.invMass;
        rb.invInertia = b.invI;
        rb.position = {b.cx, b.cy};
        rb.velocity = {b.vx, b.vy};
        rb.angularVelocity = b.w;
        outBodies->push_back(rb);
    }
    outContacts->clear();
    for (const ManifoldPoint& p : snap.points)
        outContacts->push_back(makeContact<Dim2>(p.a, p.b, {p.px, p.py}, {p.nx, p.ny}, 0.0, p.friction));
}

SparseLcp assembleManifoldLcp(const ManifoldSnapshot& snap, bool friction, ManifoldData data) {
    if (data == ManifoldData::floatData) return assembleRows<float>(snap, friction);
    std::vector<ResolverBody<Dim2>> bodies;
    std::vector<ContactNode<Dim2>> contacts;
    toResolverInput(snap, &bodies, &contacts);
    ResolverOptions options;  // restitution threshold 0 and e = 0: b = N v; no tangent dead zone: b = D v exactly
    options.frictionDirections = 2;
    return friction ? assembleFrictionLcpSparse<Dim2>(bodies, contacts, options)
                    : assembleCollisionLcpSparse<Dim2>(bodies, contacts, options);
}

SparseLcp assembleManifoldLcpRowsInDouble(const ManifoldSnapshot& snap, bool friction) {
    return assembleRows<double>(snap, friction);
}

ManifoldSnapshot settledPyramidSnapshot(int rows, int settleSteps) {
    const nlohmann::json scene = scenes::pyramidScene(rows, 0.5, false);
    Box2dPeer peer(scene, "pyramid" + std::to_string(rows));
    for (int s = 0; s < settleSteps; ++s) peer.step();
    return captureManifolds(peer, scene["gravity"][1].get<double>());
}

const char* dataName(ManifoldData data) { return data == ManifoldData::doubleData ? "double" : "float"; }

std::vector<ManifoldLcp> manifoldLcpsOf(const ManifoldSnapshot& snap, int rows) {
    std::vector<ManifoldLcp> out;
    for (bool friction : {false, true}) {
        for (ManifoldData data : {ManifoldData::doubleData, ManifoldData::floatData}) {
            ManifoldLcp m;
            m.name = "b2m_pyramid" + std::to_string(rows) + (friction ? "_friction_" : "_frictionless_") + dataName(data);
            m.rows = rows;
            m.friction = friction;
            m.data = data;
            m.contacts = int(snap.points.size());
            m.dynamicBodies = snap.dynamicBodies;
            m.lcp = assembleManifoldLcp(snap, friction, data);
            out.push_back(std::move(m));
        }
    }
    return out;
}

std::vector<ManifoldLcp> box2dManifoldLcps(const std::vector<int>& rows, int settleSteps) {
    std::vector<ManifoldLcp> out;
    for (int r : rows) {
        std::vector<ManifoldLcp> four = manifoldLcpsOf(settledPyramidSnapshot(r, settleSteps), r);
        for (ManifoldLcp& m : four) out.push_back(std::move(m));
    }
    return out;
}

double scaledResidual(const SparseLcp& lcp, const std::vector<double>& z) {
    const double inf = std::numeric_limits<double>::infinity();
    if (int(z.size()) != lcp.n) return inf;
    double scale = 0.0, worst = 0.0;
    for (double v : lcp.vals) scale = std::max(scale, std::fabs(v));
    for (double v : lcp.b) scale = std::max(scale, std::fabs(v));
    for (int i = 0; i < lcp.n; ++i) {
        if (!std::isfinite(z[std::size_t(i)])) return inf;
        double w = lcp.b[std::size_t(i)];
        for (int e = lcp.rowStart[std::size_t(i)]; e < lcp.rowStart[std::size_t(i) + 1]; ++e)
            w += lcp.vals[std::size_t(e)] * z[std::size_t(lcp.cols[std::size_t(e)])];
        worst = std::max(worst, std::fabs(std::min(z[std::size_t(i)], w)));
    }
    return scale > 0.0 ? worst / scale : worst;
}

Lcp toDense(const SparseLcp& lcp) {
    Lcp dense(lcp.n);
    for (int i = 0; i < lcp.n; ++i) {
        for (int e = lcp.rowStart[std::size_t(i)]; e < lcp.rowStart[std::size_t(i) + 1]; ++e)
            dense.at(i, lcp.cols[std::size_t(e)]) = lcp.vals[std::size_t(e)];
    }
    dense.b = lcp.b;
    return dense;
}

}  // namespace unison::bench
