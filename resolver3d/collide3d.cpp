// resolver3d/collide3d.cpp — see collide3d.h: convex pairs (spheres, SAT with clipping), planes, the reduction to four
// points and the dispatch; meshes are in collide_mesh3d.cpp, shared internals in collide3d_detail.h.
#include "collide3d_detail.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <tuple>
#include <cmath>

namespace unison {

using namespace collide3d_detail;

namespace {

constexpr double kTouchBand = 0.005;  // m: see reduceToFour

// A polyhedron placed in the world.
struct WorldPoly {
    const ConvexPolyhedron* poly = nullptr;
    std::vector<Vec3> v;        // world vertices
    std::vector<Vec3> n;        // world face normals
    std::vector<double> d;      // world face offsets
    Vec3 centroid;
};

// Places p into w, reusing w's storage (polyPoly keeps one per thread: a pile calls it hundreds of times a step).
void place(const ConvexPolyhedron& p, const Transform3& xf, WorldPoly& w) {
    w.poly = &p;
    w.v.clear();
    w.n.clear();
    w.d.clear();
    for (const Vec3& v : p.vertices) w.v.push_back(transformPoint(xf, v));
    for (const auto& f : p.faces) {
        const Vec3 nw = mul(xf.r, f.normal);
        w.n.push_back(nw);
        w.d.push_back(f.offset + D3::dot(nw, xf.p));
    }
    w.centroid = transformPoint(xf, p.centroid);
}

Manifold3 swapped(Manifold3 m) {
    for (int i = 0; i < m.count; ++i) {
        m.points[std::size_t(i)].normal = neg(m.points[std::size_t(i)].normal);
        m.points[std::size_t(i)].id ^= kFlip;
    }
    return m;
}

// ---- spheres ------------------------------------------------------------------------------------------------

Manifold3 sphereSphere(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB, double margin) {
    const Vec3 ca = transformPoint(xfA, a.center), cb = transformPoint(xfB, b.center);
    const Vec3 d = D3::sub(ca, cb);
    const double dist = norm(d);
    const double sep = dist - a.radius - b.radius;
    Manifold3 m;
    if (sep >= margin) return m;
    const Vec3 n = dist > 0.0 ? D3::scale(1.0 / dist, d) : Vec3::UnitZ();
    const Vec3 pa = D3::sub(ca, D3::scale(a.radius, n)), pb = D3::add(cb, D3::scale(b.radius, n));
    m.count = 1;
    m.candidates = 1;
    m.points[0] = {D3::scale(0.5, D3::add(pa, pb)), n, sep, convexId(kSpheres, 0, 0, 0)};
    return m;
}

// Closest point of segment [p, q] to x.
Vec3 closestOnSegment(const Vec3& p, const Vec3& q, const Vec3& x) {
    const Vec3 e = D3::sub(q, p);
    const double ee = D3::dot(e, e);
    double t = ee > 0.0 ? D3::dot(D3::sub(x, p), e) / ee : 0.0;
    t = std::min(1.0, std::max(0.0, t));
    return D3::add(p, D3::scale(t, e));
}

// Sphere a against polyhedron b (normal from b to a): the closest feature of b to the sphere centre.
Manifold3 spherePoly(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB, double margin) {
    const ConvexPolyhedron& p = *b.poly;
    const Vec3 c = invTransformPoint(xfB, transformPoint(xfA, a.center));  // in b's frame
    int best = 0;
    double bestSep = -1e300;
    for (int f = 0; f < int(p.faces.size()); ++f) {
        const double s = D3::dot(p.faces[std::size_t(f)].normal, c) - p.faces[std::size_t(f)].offset;
        if (s > bestSep) {
            bestSep = s;
            best = f;
        }
    }
    Manifold3 m;
    if (bestSep - a.radius >= margin) return m;
    Vec3 q, n;
    std::uint32_t id;
    double sep;
    if (bestSep <= 0.0) {  // centre inside: push out through the least-penetrated face
        n = p.faces[std::size_t(best)].normal;
        q = D3::sub(c, D3::scale(bestSep, n));
        sep = bestSep - a.radius;
        id = convexId(kSphereFeature, best, 0, 2);
    } else {
        double bestD = 1e300;
        int feature = -1, side = 0;
        for (int f = 0; f < int(p.faces.size()); ++f) {
            const auto& face = p.faces[std::size_t(f)];
            const double s = D3::dot(face.normal, c) - face.offset;
            if (s <= 0.0) continue;
            const Vec3 proj = D3::sub(c, D3::scale(s, face.normal));
            bool inside = true;
            for (std::size_t k = 0; k < face.loop.size() && inside; ++k) {
                const Vec3& v0 = p.vertices[std::size_t(face.loop[k])];
                const Vec3& v1 = p.vertices[std::size_t(face.loop[(k + 1) % face.loop.size()])];
                inside = D3::dot(D3::cross(D3::sub(v1, v0), face.normal), D3::sub(proj, v0)) <= 0.0;
            }
            if (inside && s < bestD) {
                bestD = s;
                q = proj;
                feature = f;
                side = 0;
            }
        }
        for (int e = 0; e < int(p.edges.size()); ++e) {
            const auto& edge = p.edges[std::size_t(e)];
            const Vec3 x = closestOnSegment(p.vertices[std::size_t(edge.v0)], p.vertices[std::size_t(edge.v1)], c);
            const double dd = norm(D3::sub(c, x));
            if (dd < bestD) {
                bestD = dd;
                q = x;
                feature = e;
                side = 1;
            }
        }
        sep = bestD - a.radius;
        if (sep >= margin || feature < 0) return m;
        n = D3::scale(1.0 / bestD, D3::sub(c, q));
        id = convexId(kSphereFeature, feature, 0, side);
    }
    const Vec3 surfA = D3::sub(c, D3::scale(a.radius, n));
    const Vec3 mid = D3::scale(0.5, D3::add(q, surfA));
    m.count = 1;
    m.candidates = 1;
    m.points[0] = {transformPoint(xfB, mid), mul(xfB.r, n), sep, id};
    return m;
}

// ---- polyhedra (SAT + clipping) ---------------------------------------------------------------------------

struct FaceQuery {
    int face = -1;
    double sep = -1e300;
};

// Largest separation of q's vertices from a face plane of p.
FaceQuery queryFaces(const WorldPoly& p, const WorldPoly& q) {
    FaceQuery best;
    for (int f = 0; f < int(p.n.size()); ++f) {
        double minD = 1e300;
        for (const Vec3& v : q.v) minD = std::min(minD, D3::dot(p.n[std::size_t(f)], v));
        const double s = minD - p.d[std::size_t(f)];
        if (s > best.sep) {
            best.sep = s;
            best.face = f;
        }
    }
    return best;
}

struct EdgeQuery {
    int ea = -1, eb = -1;
    double sep = -1e300;
    Vec3 axis = Vec3::Zero();  // outward of A
};

// Edge pairs whose Gauss-map arcs cross (they form a face of the Minkowski difference; Gregorius, GDC 2013).
// B's arcs on the Gauss map of the Minkowski difference: per edge the negated face normals c, d and d x c (computed
// once per edge, not once per edge pair).
struct Arc {
    Vec3 c, d, dxc;
};

EdgeQuery queryEdges(const WorldPoly& A, const WorldPoly& B) {
    EdgeQuery best;
    const auto& ea = A.poly->edges;
    const auto& eb = B.poly->edges;
    thread_local std::vector<Arc> arcs;
    arcs.clear();
    for (const auto& e : eb) {
        const Vec3 c = neg(B.n[std::size_t(e.face0)]);
        const Vec3 d = neg(B.n[std::size_t(e.face1)]);
        arcs.push_back({c, d, D3::cross(d, c)});
    }
    for (int i = 0; i < int(ea.size()); ++i) {
        const Vec3& a = A.n[std::size_t(ea[std::size_t(i)].face0)];
        const Vec3& b = A.n[std::size_t(ea[std::size_t(i)].face1)];
        const Vec3 pa0 = A.v[std::size_t(ea[std::size_t(i)].v0)], pa1 = A.v[std::size_t(ea[std::size_t(i)].v1)];
        const Vec3 da = D3::sub(pa1, pa0);
        const Vec3 bxa = D3::cross(b, a);
        for (int j = 0; j < int(eb.size()); ++j) {
            const Vec3& c = arcs[std::size_t(j)].c;
            const Vec3& d = arcs[std::size_t(j)].d;
            const Vec3& dxc = arcs[std::size_t(j)].dxc;
            const double cba = D3::dot(c, bxa), dba = D3::dot(d, bxa);
            if (!(cba * dba < 0.0)) continue;  // most pairs end here; the other two products are not needed
            const double adc = D3::dot(a, dxc), bdc = D3::dot(b, dxc);
            if (!(adc * bdc < 0.0 && cba * bdc > 0.0)) continue;
            const Vec3 pb0 = B.v[std::size_t(eb[std::size_t(j)].v0)], pb1 = B.v[std::size_t(eb[std::size_t(j)].v1)];
            const Vec3 db = D3::sub(pb1, pb0);
            Vec3 axis = D3::cross(da, db);
            const double len = norm(axis);
            if (!(len > 1e-6 * norm(da) * norm(db))) continue;  // parallel edges: the face queries cover them
            axis = D3::scale(1.0 / len, axis);
            if (D3::dot(axis, D3::sub(pa0, A.centroid)) < 0.0) axis = neg(axis);
            const double s = D3::dot(axis, D3::sub(pb0, pa0));
            if (s > best.sep) {
                best.sep = s;
                best.ea = i;
                best.eb = j;
                best.axis = axis;
            }
        }
    }
    return best;
}

struct ClipVertex {
    Vec3 p;
    int inc;   // incident vertex this point started from
    int side;  // side plane that cut it (0xFF: none)
};

// Clips the incident face of `inc` against the side planes of face `refFace` of `ref`. Points below
// the reference plane by less than margin become contacts; `flip` says the reference face belongs to B.
Manifold3 clipFaces(const WorldPoly& ref, int refFace, const WorldPoly& inc, bool flip, double margin,
                    std::vector<ManifoldPoint3>* outCandidates) {
    const Vec3 nRef = ref.n[std::size_t(refFace)];
    int incFace = 0;
    double minDot = 1e300;
    for (int f = 0; f < int(inc.n.size()); ++f) {
        const double dd = D3::dot(inc.n[std::size_t(f)], nRef);
        if (dd < minDot) {
            minDot = dd;
            incFace = f;
        }
    }
    thread_local std::vector<ClipVertex> poly, next;
    poly.clear();
    for (int vi : inc.poly->faces[std::size_t(incFace)].loop) poly.push_back({inc.v[std::size_t(vi)], vi, 0xFF});
    const auto& loop = ref.poly->faces[std::size_t(refFace)].loop;
    for (std::size_t k = 0; k < loop.size() && !poly.empty(); ++k) {
        const Vec3& v0 = ref.v[std::size_t(loop[k])];
        const Vec3& v1 = ref.v[std::size_t(loop[(k + 1) % loop.size()])];
        const Vec3 side = D3::cross(D3::sub(v1, v0), nRef);  // outward side-plane normal (not unit)
        next.clear();
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const ClipVertex& s = poly[i];
            const ClipVertex& e = poly[(i + 1) % poly.size()];
            const double ds = D3::dot(side, D3::sub(s.p, v0)), de = D3::dot(side, D3::sub(e.p, v0));
            if (ds <= 0.0) next.push_back(s);
            if ((ds <= 0.0) != (de <= 0.0)) {
                const double t = ds / (ds - de);
                next.push_back({D3::add(s.p, D3::scale(t, D3::sub(e.p, s.p))), s.inc, int(k)});
            }
        }
        poly.swap(next);
    }
    thread_local std::vector<ManifoldPoint3> cands;
    cands.clear();
    const Vec3 normal = flip ? nRef : neg(nRef);  // from B towards A
    for (const ClipVertex& cv : poly) {
        const double sep = D3::dot(nRef, cv.p) - ref.d[std::size_t(refFace)];
        if (sep >= margin) continue;
        const Vec3 mid = D3::sub(cv.p, D3::scale(0.5 * sep, nRef));
        std::uint32_t id = cv.side == 0xFF ? convexId(kFaceVertex, refFace, cv.inc, 0xFF)
                                           : convexId(kFaceClip, refFace, cv.inc, cv.side);
        if (flip) id |= kFlip;
        // A clip point is named by the incident vertex its edge started from and the side plane that cut it; on a
        // face of more than 4 sides two points can get the same name (an edge that starts at an earlier clip point
        // keeps that point's vertex). Ids must be unique within a manifold (they key the warm-start cache), so a
        // repeated one takes the next free side value from the top of the byte, in clipping order.
        for (std::uint32_t spare = 0xFE; std::any_of(cands.begin(), cands.end(), [&](const ManifoldPoint3& c) { return c.id == id; });
             --spare)
            id = (id & ~0xFFu) | spare;
        cands.push_back({mid, normal, sep, id});
    }
    return finish(cands, outCandidates);
}

// Closest points of segments p0-p1 and q0-q1 (their midpoint is returned).
Vec3 segmentsMidpoint(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
    const Vec3 d1 = D3::sub(p1, p0), d2 = D3::sub(q1, q0), r = D3::sub(p0, q0);
    const double a = D3::dot(d1, d1), e = D3::dot(d2, d2), f = D3::dot(d2, r), c = D3::dot(d1, r), b = D3::dot(d1, d2);
    const double den = a * e - b * b;
    double s = den > 0.0 ? std::min(1.0, std::max(0.0, (b * f - c * e) / den)) : 0.0;
    double t = e > 0.0 ? (b * s + f) / e : 0.0;
    if (t < 0.0) {
        t = 0.0;
        s = a > 0.0 ? std::min(1.0, std::max(0.0, -c / a)) : 0.0;
    } else if (t > 1.0) {
        t = 1.0;
        s = a > 0.0 ? std::min(1.0, std::max(0.0, (b - c) / a)) : 0.0;
    }
    const Vec3 pa = D3::add(p0, D3::scale(s, d1)), pb = D3::add(q0, D3::scale(t, d2));
    return D3::scale(0.5, D3::add(pa, pb));
}

// The last few polyhedra placed (per thread, while a CollideBatch lives): a body meets several neighbours in a row
// of broadphase pairs, and a pile's cube is placed once for all of them. An entry is reused only for the same
// polyhedron and the same transform bits, so it holds exactly what place() would compute; the batch empties it, so
// a polyhedron freed and another allocated at its address in a later step is never mistaken for it.
class PlacedCache {
public:
    void clear() {
        for (Slot& s : mSlots) s.placed.poly = nullptr;
        mNext = 0;
    }

    /// The placed polyhedron; never evicts `keep` (the other polyhedron of the pair, still in use).
    const WorldPoly& get(const ConvexPolyhedron& p, const Transform3& xf, const WorldPoly* keep = nullptr) {
        for (Slot& s : mSlots) {
            if (s.placed.poly == &p && std::memcmp(&s.xf, &xf, sizeof xf) == 0) return s.placed;
        }
        if (&mSlots[mNext].placed == keep) mNext = (mNext + 1) % kSlots;
        Slot& s = mSlots[mNext];
        mNext = (mNext + 1) % kSlots;
        s.xf = xf;
        place(p, xf, s.placed);
        return s.placed;
    }

private:
    static constexpr std::size_t kSlots = 8;
    struct Slot {
        Transform3 xf;
        WorldPoly placed;
    };
    std::array<Slot, kSlots> mSlots{};
    std::size_t mNext = 0;
};

thread_local PlacedCache* tBatchCache = nullptr;  // set while a CollideBatch lives on this thread

Manifold3 polyPoly(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB, double margin,
                   std::vector<ManifoldPoint3>* outCandidates) {
    thread_local WorldPoly placedA, placedB;
    if (!tBatchCache) {
        place(*a.poly, xfA, placedA);
        place(*b.poly, xfB, placedB);
    }
    const WorldPoly& A = tBatchCache ? tBatchCache->get(*a.poly, xfA) : placedA;
    const WorldPoly& B = tBatchCache ? tBatchCache->get(*b.poly, xfB, &A) : placedB;
    Manifold3 m;
    const FaceQuery fa = queryFaces(A, B);
    if (fa.sep >= margin) return m;
    const FaceQuery fb = queryFaces(B, A);
    if (fb.sep >= margin) return m;
    const EdgeQuery eq = queryEdges(A, B);
    if (eq.sep >= margin) return m;
    // Faces are preferred (they give up to 4 points and stable ids); an edge pair must be clearly better. A face of
    // B must beat A's by a small tolerance too, so resting contacts do not flip reference faces between steps.
    const double kTol = 1e-3;
    const double faceSep = std::max(fa.sep, fb.sep);
    if (eq.ea >= 0 && eq.sep > faceSep + kTol) {
        const auto& ea = A.poly->edges[std::size_t(eq.ea)];
        const auto& eb = B.poly->edges[std::size_t(eq.eb)];
        const Vec3 mid = segmentsMidpoint(A.v[std::size_t(ea.v0)], A.v[std::size_t(ea.v1)], B.v[std::size_t(eb.v0)],
                                          B.v[std::size_t(eb.v1)]);
        m.count = 1;
        m.candidates = 1;
        m.points[0] = {mid, neg(eq.axis), eq.sep, convexId(kEdges, eq.ea, eq.eb, 0)};
        if (outCandidates) outCandidates->push_back(m.points[0]);
        // The best faces' points within the margin come too: a body that lands on an edge turns about it, and the
        // corners of its face then close faster than anything moved before the step (the edge point alone let
        // a tilted cube's next corner sink 4-12 cm into the heap below). They keep their own normals and ids. The
        // farthest from the edge point come first; one within kTouchBand of it repeats it and is left out.
        const Manifold3 faces = fb.sep > fa.sep + 0.5 * kTol ? clipFaces(B, fb.face, A, true, margin, outCandidates)
                                                             : clipFaces(A, fa.face, B, false, margin, outCandidates);
        m.candidates += faces.candidates;
        std::array<bool, 4> used{};
        while (m.count < int(m.points.size())) {
            int best = -1;
            double bestD = kTouchBand * kTouchBand;
            for (int k = 0; k < faces.count; ++k) {
                const Vec3 d = D3::sub(faces.points[std::size_t(k)].point, mid);
                if (!used[std::size_t(k)] && D3::dot(d, d) > bestD) {
                    bestD = D3::dot(d, d);
                    best = k;
                }
            }
            if (best < 0) break;
            used[std::size_t(best)] = true;
            m.points[std::size_t(m.count++)] = faces.points[std::size_t(best)];
        }
        return m;
    }
    if (fb.sep > fa.sep + 0.5 * kTol) return clipFaces(B, fb.face, A, true, margin, outCandidates);
    return clipFaces(A, fa.face, B, false, margin, outCandidates);
}

// ---- planes ---------------------------------------------------------------------------------------------------

// Shape a (not a plane) against plane b; normal from the plane to a.
Manifold3 againstPlane(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB, double margin,
                       std::vector<ManifoldPoint3>* outCandidates) {
    const Vec3 n = mul(xfB.r, b.normal);
    const double off = b.offset + D3::dot(n, xfB.p);
    std::vector<ManifoldPoint3> cands;
    auto addPoint = [&](const Vec3& surface, std::uint32_t id) {
        const double sep = D3::dot(n, surface) - off;
        if (sep < margin) cands.push_back({D3::sub(surface, D3::scale(0.5 * sep, n)), n, sep, id});
    };
    switch (a.type) {
    case ShapeType3::sphere:
        addPoint(D3::sub(transformPoint(xfA, a.center), D3::scale(a.radius, n)), convexId(kVertexPlane, 0, 0, 0));
        break;
    case ShapeType3::box:
    case ShapeType3::hull:
        for (int v = 0; v < int(a.poly->vertices.size()); ++v)
            addPoint(transformPoint(xfA, a.poly->vertices[std::size_t(v)]), convexId(kVertexPlane, 0, v, 0));
        break;
    case ShapeType3::mesh:
        walkTree(a.mesh->vertexTree, xfA, [&](const Vec3& c, double r) { return D3::dot(n, c) - off - r < margin; },
                 [&](int v) { addPoint(transformPoint(xfA, a.mesh->vertices[std::size_t(v)]), vertexId(kTreeVertex, v)); });
        break;
    case ShapeType3::plane:
        break;
    }
    return finish(cands, outCandidates);
}

bool isPoly(const Shape3& s) { return s.type == ShapeType3::box || s.type == ShapeType3::hull; }

}  // namespace

CollideBatch::CollideBatch() {
    thread_local PlacedCache cache;
    cache.clear();
    tBatchCache = &cache;
}

CollideBatch::~CollideBatch() { tBatchCache = nullptr; }

Manifold3 collide3d_detail::finish(const std::vector<ManifoldPoint3>& cands, std::vector<ManifoldPoint3>* outCandidates) {
    Manifold3 m;
    m.candidates = int(cands.size());
    if (outCandidates) outCandidates->insert(outCandidates->end(), cands.begin(), cands.end());
    if (cands.size() <= 4) {  // nothing to reduce (reduceToFour would return a copy)
        m.count = int(cands.size());
        for (int i = 0; i < m.count; ++i) m.points[std::size_t(i)] = cands[std::size_t(i)];
        return m;
    }
    const std::vector<ManifoldPoint3> kept = reduceToFour(cands);
    m.count = int(kept.size());
    for (int i = 0; i < m.count; ++i) m.points[std::size_t(i)] = kept[std::size_t(i)];
    return m;
}

std::vector<ManifoldPoint3> reduceToFour(const std::vector<ManifoldPoint3>& c) {
    if (c.size() <= 4) return c;
    const int n = int(c.size());
    int i0 = 0;  // deepest (lowest index on ties)
    for (int i = 1; i < n; ++i)
        if (c[std::size_t(i)].separation < c[std::size_t(i0)].separation) i0 = i;
    const Vec3 p0 = c[std::size_t(i0)].point;
    // Points that touch (overlap) or lie within kTouchBand of the deepest one span the area first: with four
    // slots spent on speculative points 2 cm away, a resting body would rock on the one or two that hold it. A
    // slot they leave (one touching corner, or an edge) goes to the speculative points: a cube that lands on a
    // corner or an edge turns about it, and its next corners must be in the LCP before they close.
    const double limit = std::max(0.0, c[std::size_t(i0)].separation + kTouchBand);
    auto argmax = [&](auto score, bool touching) {
        int best = i0;
        double bestS = -1e300;
        for (int i = 0; i < n; ++i) {
            if (touching && c[std::size_t(i)].separation > limit) continue;
            const double s = score(c[std::size_t(i)]);
            if (s > bestS) {
                bestS = s;
                best = i;
            }
        }
        return std::make_pair(best, bestS);
    };
    auto far = [&](const ManifoldPoint3& p) {
        const Vec3 d = D3::sub(p.point, p0);
        return D3::dot(d, d);
    };
    auto [i1, d1] = argmax(far, true);
    if (!(d1 > 0.0)) std::tie(i1, d1) = argmax(far, false);
    std::vector<ManifoldPoint3> out{c[std::size_t(i0)]};
    if (!(d1 > 0.0)) return out;
    out.push_back(c[std::size_t(i1)]);
    const Vec3 p1 = c[std::size_t(i1)].point;
    auto area = [](const Vec3& a, const Vec3& b, const Vec3& x) { return norm(D3::cross(D3::sub(b, a), D3::sub(x, a))); };
    auto spread = [&](const ManifoldPoint3& p) { return area(p0, p1, p.point); };
    auto [i2, a2] = argmax(spread, true);
    if (!(a2 > 0.0)) std::tie(i2, a2) = argmax(spread, false);
    if (!(a2 > 0.0)) return out;
    out.push_back(c[std::size_t(i2)]);
    const Vec3 p2 = c[std::size_t(i2)].point;
    // The point outside the triangle by the most: the three sub-triangles add up to more than the triangle.
    auto outside = [&](const ManifoldPoint3& p) {
        return area(p0, p1, p.point) + area(p1, p2, p.point) + area(p2, p0, p.point);
    };
    auto [i3, a3] = argmax(outside, true);
    if (!(a3 > a2 * (1.0 + 1e-9))) std::tie(i3, a3) = argmax(outside, false);
    if (a3 > a2 * (1.0 + 1e-9)) out.push_back(c[std::size_t(i3)]);
    return out;
}

Manifold3 collide(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB, double margin,
                  std::vector<ManifoldPoint3>* outCandidates) {
    using T = ShapeType3;
    if (a.type == T::plane && b.type == T::plane) return {};
    if (b.type == T::plane) return againstPlane(a, xfA, b, xfB, margin, outCandidates);
    if (a.type == T::plane) return swapped(againstPlane(b, xfB, a, xfA, margin, outCandidates));
    if (a.type == T::sphere && b.type == T::sphere) return sphereSphere(a, xfA, b, xfB, margin);
    if (a.type == T::sphere && isPoly(b)) return spherePoly(a, xfA, b, xfB, margin);
    if (isPoly(a) && b.type == T::sphere) return swapped(spherePoly(b, xfB, a, xfA, margin));
    if (isPoly(a) && isPoly(b)) return polyPoly(a, xfA, b, xfB, margin, outCandidates);
    if (a.type == T::mesh && b.type == T::mesh) return meshMesh(a, xfA, b, xfB, margin, outCandidates);
    if (a.type == T::mesh) return meshConvex(a, xfA, b, xfB, margin, outCandidates);
    return swapped(meshConvex(b, xfB, a, xfA, margin, outCandidates));
}

}  // namespace unison
