// resolver2d/collide2d.cpp — see collide2d.h.
//
// Polygon pairs use the separating axis test with reference-face clipping as Erin Catto describes it for Box2D
// ("Contact Manifolds", GDC 2007; Gottschalk's SAT): in the frame of A,
//   1. for each edge of A, the separation of B along its outward normal is min_j n_i . (vB_j - vA_i); the axis of
//      least penetration is the edge maximising it (and the same for B against A);
//   2. the reference face is A's best edge unless B's is better by more than kReferenceTolerance, so two nearly
//      equal faces (a box resting on a box) do not swap from step to step;
//   3. the incident edge is the edge of the other shape whose normal is most anti-parallel to the reference normal;
//   4. the incident edge is clipped to the slab between the reference face's two side planes, and each of its two
//      ends gets its height above the reference face as separation;
//   5. when either edge is shorter than kMergeDistance (a thin card's end), only the deeper end is kept.
// A segment is the two-vertex polygon p1 -> p2 -> p1 whose two "edges" face opposite ways, so the same routine gives
// a box resting on a long segment its two corners. Circles use the closest point on the other shape.
#include "collide2d.h"

#include <cmath>

namespace unison {
namespace {

// Reference-face hysteresis (m): 0.1 x a 5 mm linear slop, the value Box2D uses.
constexpr double kReferenceTolerance = 0.0005;

// Where the reference face or the incident edge is shorter than this (m, the 5 mm linear slop), its two clipped
// points become one: the deeper. Two points d apart have rows in the LCP that differ only by a lever arm of d, so
// on a body of size L their 2 x 2 block of A has a condition number of about (L / d)^2 (1e4 for the 2 mm end of a
// 40 cm card), and the pair resists a rotation that the slop already allows.
// A card house whose every card end carried two such points needed 4542 Lemke pivots for its first friction LCP
// (n = 704); with one point per end, 713 (n = 376).
constexpr double kMergeDistance = 0.005;

// A convex vertex loop in some frame: a polygon, or a segment as two vertices with opposite normals. It reads
// vertices and normals held elsewhere (a polygon's own arrays, or a HullStore), so a polygon is not copied.
struct Hull {
    int count = 0;
    const Vec2* v = nullptr;
    const Vec2* n = nullptr;
};

// Storage for a hull of up to N vertices that is computed, not read off a shape.
template <int N>
struct HullStore {
    int count = 0;
    Vec2 v[N];
    Vec2 n[N];
    Hull view() const { return {count, v, n}; }
};

Hull hullOf(const Polygon& p) { return {p.count, p.vertices.data(), p.normals.data()}; }

// Right-hand normal of p1 -> p2 (the outward normal of a counter-clockwise edge).
Vec2 rightNormal(const Segment& s) {
    const Vec2 e = s.p2 - s.p1;
    const double len = length(e);
    return {e.y / len, -e.x / len};
}

HullStore<2> hullOf(const Segment& s) {
    HullStore<2> h;
    h.count = 2;
    h.v[0] = s.p1;
    h.v[1] = s.p2;
    h.n[0] = rightNormal(s);
    h.n[1] = -h.n[0];
    return h;
}

// The transform taking B's frame to A's frame: inv(xfA) * xfB.
Transform2 relative(const Transform2& xfA, const Transform2& xfB) {
    Transform2 r;
    r.q = {xfA.q.c * xfB.q.c + xfA.q.s * xfB.q.s, xfA.q.c * xfB.q.s - xfA.q.s * xfB.q.c};
    r.p = invRotate(xfA.q, xfB.p - xfA.p);
    return r;
}

HullStore<kMaxPolygonVertices> transformed(const Hull& h, const Transform2& xf) {
    HullStore<kMaxPolygonVertices> out;
    out.count = h.count;
    for (int i = 0; i < h.count; ++i) {
        out.v[i] = transformPoint(xf, h.v[i]);
        out.n[i] = rotate(xf.q, h.n[i]);
    }
    return out;
}

struct AxisResult {
    int edge = 0;
    double separation = 0.0;
};

// Edge of `ref` along whose normal `other` is farthest out; the first such edge on exact ties.
AxisResult findMaxSeparation(const Hull& ref, const Hull& other) {
    AxisResult best;
    for (int i = 0; i < ref.count; ++i) {
        double s = dot(ref.n[i], other.v[0] - ref.v[i]);
        for (int j = 1; j < other.count; ++j) {
            const double d = dot(ref.n[i], other.v[j] - ref.v[i]);
            if (d < s) s = d;
        }
        if (i == 0 || s > best.separation) best = {i, s};
    }
    return best;
}

// Manifold of two hulls given in the same frame (A's), returned in that frame.
Manifold2 collideHulls(const Hull& a, const Hull& b, double speculativeDistance) {
    Manifold2 m;
    const AxisResult axisA = findMaxSeparation(a, b);
    if (axisA.separation > speculativeDistance) return m;
    const AxisResult axisB = findMaxSeparation(b, a);
    if (axisB.separation > speculativeDistance) return m;

    const bool flip = axisB.separation > axisA.separation + kReferenceTolerance;
    const Hull& ref = flip ? b : a;
    const Hull& inc = flip ? a : b;
    const int refEdge = flip ? axisB.edge : axisA.edge;
    const int refNext = (refEdge + 1) % ref.count;
    const Vec2 nRef = ref.n[refEdge];

    int incEdge = 0;
    double minDot = dot(nRef, inc.n[0]);
    for (int i = 1; i < inc.count; ++i) {
        const double d = dot(nRef, inc.n[i]);
        if (d < minDot) {
            minDot = d;
            incEdge = i;
        }
    }
    const int incNext = (incEdge + 1) % inc.count;

    // Clip the incident edge to the reference face's slab. Coordinates along the reference tangent t (t = n turned
    // +90 degrees, running from r1 = ref.v[refEdge] to r2 = ref.v[refNext]); the incident edge runs against t
    // (dot(nRef, nInc) <= 0), so its vertex `lo` = inc.v[incNext] sits at the r1 end and `hi` = inc.v[incEdge] at
    // the r2 end. Each end keeps its id whether or not it was cut, so ids do not flicker when an incident vertex
    // crosses a side plane (two equal boxes stacked flush).
    const Vec2 r1 = ref.v[refEdge];
    const Vec2 r2 = ref.v[refNext];
    const Vec2 t{-nRef.y, nRef.x};
    const double faceLength = dot(t, r2 - r1);
    const Vec2 lo = inc.v[incNext];
    const Vec2 hi = inc.v[incEdge];
    const double tLo = dot(t, lo - r1);
    const double tHi = dot(t, hi - r1);
    Vec2 ends[2] = {lo, hi};
    bool keep[2] = {true, true};
    if (tHi > tLo) {
        if (tHi < 0.0 || tLo > faceLength) return m;  // no overlap with the face's slab
        const Vec2 d = hi - lo;
        if (tLo < 0.0) ends[0] = lo + ((0.0 - tLo) / (tHi - tLo)) * d;
        if (tHi > faceLength) ends[1] = lo + ((faceLength - tLo) / (tHi - tLo)) * d;
    } else {
        // Incident edge perpendicular to the face (a segment standing on end): keep the ends inside the slab.
        keep[0] = tLo >= 0.0 && tLo <= faceLength;
        keep[1] = tHi >= 0.0 && tHi <= faceLength;
    }
    const std::uint32_t ids[2] = {makeFeatureId(FeatureKind::faceEdge, refEdge, incNext, refEdge, flip),
                                  makeFeatureId(FeatureKind::faceEdge, refEdge, incEdge, refNext, flip)};

    m.normal = flip ? nRef : -nRef;
    const double seps[2] = {dot(nRef, ends[0] - r1), dot(nRef, ends[1] - r1)};
    const bool shortFace = faceLength < kMergeDistance || lengthSquared(hi - lo) < kMergeDistance * kMergeDistance;
    if (keep[0] && keep[1] && shortFace) keep[seps[1] < seps[0] ? 0 : 1] = false;  // the deeper stays; on a tie, the first
    for (int i = 0; i < 2; ++i) {
        if (!keep[i]) continue;
        const double sep = seps[i];
        if (sep < speculativeDistance) {
            // ends[i] is on the incident surface; the reference surface is sep below it along nRef.
            m.points[m.count++] = {ends[i] - (0.5 * sep) * nRef, sep, ids[i]};
        }
    }
    return m;
}

// Moves a manifold computed in the frame xf into world space.
Manifold2 toWorld(const Manifold2& local, const Transform2& xf) {
    Manifold2 m = local;
    m.normal = rotate(xf.q, local.normal);
    for (int i = 0; i < local.count; ++i) m.points[i].point = transformPoint(xf, local.points[i].point);
    return m;
}

Manifold2 collideHullsWorld(const Hull& a, const Transform2& xfA, const Hull& b, const Transform2& xfB,
                            double speculativeDistance) {
    return toWorld(collideHulls(a, transformed(b, relative(xfA, xfB)).view(), speculativeDistance), xfA);
}

// One-point manifold from a surface point q of B (B's frame), the unit normal n (B's frame, towards A), the gap
// sep, and B's transform.
Manifold2 singlePoint(Vec2 q, Vec2 n, double sep, std::uint32_t id, const Transform2& xfB) {
    Manifold2 m;
    m.normal = rotate(xfB.q, n);
    m.count = 1;
    m.points[0] = {transformPoint(xfB, q + (0.5 * sep) * n), sep, id};
    return m;
}

}  // namespace

Manifold2 swapped(const Manifold2& m) {
    Manifold2 out = m;
    out.normal = -m.normal;
    return out;
}

Manifold2 collideCircles(const Circle& a, const Transform2& xfA, const Circle& b, const Transform2& xfB,
                         double speculativeDistance) {
    Manifold2 m;
    const Vec2 ca = transformPoint(xfA, a.center);
    const Vec2 cb = transformPoint(xfB, b.center);
    const Vec2 d = ca - cb;
    const double dist = length(d);
    const double sep = dist - a.radius - b.radius;
    if (!(sep < speculativeDistance)) return m;
    const Vec2 n = dist > 0.0 ? (1.0 / dist) * d : Vec2{0.0, 1.0};
    const Vec2 surfA = ca - a.radius * n;
    const Vec2 surfB = cb + b.radius * n;
    m.normal = n;
    m.count = 1;
    m.points[0] = {0.5 * (surfA + surfB), sep, makeFeatureId(FeatureKind::circles, 0, 0, 0, false)};
    return m;
}

Manifold2 collideCircleAndPolygon(const Circle& a, const Transform2& xfA, const Polygon& b, const Transform2& xfB,
                                  double speculativeDistance) {
    const Vec2 c = invTransformPoint(xfB, transformPoint(xfA, a.center));
    const double r = a.radius;
    const int n = b.count;
    // Face of greatest separation of the centre.
    int face = 0;
    double sMax = dot(b.normals[0], c - b.vertices[0]);
    for (int i = 1; i < n; ++i) {
        const double s = dot(b.normals[i], c - b.vertices[i]);
        if (s > sMax) {
            sMax = s;
            face = i;
        }
    }
    if (!(sMax - r < speculativeDistance)) return {};
    if (sMax <= 0.0) {
        // Centre inside (or on) the polygon: push out through the face of least penetration.
        const Vec2 nf = b.normals[face];
        return singlePoint(c - sMax * nf, nf, sMax - r, makeFeatureId(FeatureKind::circleFace, face, 0, 0, false),
                           xfB);
    }
    // Centre outside: the closest boundary point lies on an edge facing the centre (s_i > 0). Search those edges
    // in index order, first strictly closest wins; classify it as the edge's interior or one of its vertices.
    double bestD2 = 0.0;
    Vec2 bestQ;
    int bestEdge = -1;
    int bestVertex = -1;  // -1: interior of bestEdge
    for (int i = 0; i < n; ++i) {
        if (!(dot(b.normals[i], c - b.vertices[i]) > 0.0)) continue;
        const Vec2 v1 = b.vertices[i];
        const Vec2 v2 = b.vertices[(i + 1) % n];
        const Vec2 e = v2 - v1;
        const double u = dot(c - v1, e);
        Vec2 q;
        int vertex = -1;
        if (u <= 0.0) {
            q = v1;
            vertex = i;
        } else if (u >= dot(e, e)) {
            q = v2;
            vertex = (i + 1) % n;
        } else {
            q = v1 + (u / dot(e, e)) * e;
        }
        const double d2 = lengthSquared(c - q);
        if (bestEdge < 0 || d2 < bestD2) {
            bestD2 = d2;
            bestQ = q;
            bestEdge = i;
            bestVertex = vertex;
        }
    }
    if (bestVertex < 0) {
        const Vec2 nf = b.normals[bestEdge];
        const double s = dot(nf, c - b.vertices[bestEdge]);
        if (!(s - r < speculativeDistance)) return {};
        return singlePoint(c - s * nf, nf, s - r, makeFeatureId(FeatureKind::circleFace, bestEdge, 0, 0, false), xfB);
    }
    const double dist = std::sqrt(bestD2);
    if (!(dist - r < speculativeDistance)) return {};
    const Vec2 nv = dist > 0.0 ? (1.0 / dist) * (c - bestQ) : b.normals[face];
    return singlePoint(bestQ, nv, dist - r, makeFeatureId(FeatureKind::circleVertex, 0, bestVertex, 0, false), xfB);
}

Manifold2 collideCircleAndSegment(const Circle& a, const Transform2& xfA, const Segment& b, const Transform2& xfB,
                                  double speculativeDistance) {
    const Vec2 c = invTransformPoint(xfB, transformPoint(xfA, a.center));
    const double r = a.radius;
    const Vec2 e = b.p2 - b.p1;
    const double u = dot(c - b.p1, e);
    const Vec2 right = rightNormal(b);
    if (u > 0.0 && u < dot(e, e)) {
        // Interior: the face on the centre's side (edge 0 faces right of p1 -> p2, edge 1 left; on the line: left).
        const double s = dot(right, c - b.p1);
        const bool rightSide = s > 0.0;
        const Vec2 nf = rightSide ? right : -right;
        const double gap = rightSide ? s : -s;
        if (!(gap - r < speculativeDistance)) return {};
        return singlePoint(c - gap * nf, nf, gap - r,
                           makeFeatureId(FeatureKind::circleFace, rightSide ? 0 : 1, 0, 0, false), xfB);
    }
    const int vertex = u <= 0.0 ? 0 : 1;
    const Vec2 q = vertex == 0 ? b.p1 : b.p2;
    const double dist = length(c - q);
    if (!(dist - r < speculativeDistance)) return {};
    const Vec2 nv = dist > 0.0 ? (1.0 / dist) * (c - q) : -right;
    return singlePoint(q, nv, dist - r, makeFeatureId(FeatureKind::circleVertex, 0, vertex, 0, false), xfB);
}

Manifold2 collidePolygons(const Polygon& a, const Transform2& xfA, const Polygon& b, const Transform2& xfB,
                          double speculativeDistance) {
    return collideHullsWorld(hullOf(a), xfA, hullOf(b), xfB, speculativeDistance);
}

Manifold2 collidePolygonAndSegment(const Polygon& a, const Transform2& xfA, const Segment& b, const Transform2& xfB,
                                   double speculativeDistance) {
    return collideHullsWorld(hullOf(a), xfA, hullOf(b).view(), xfB, speculativeDistance);
}

Manifold2 collide(const Shape2& a, const Transform2& xfA, const Shape2& b, const Transform2& xfB,
                  double speculativeDistance) {
    const double d = speculativeDistance;
    switch (a.type) {
        case ShapeType::circle:
            switch (b.type) {
                case ShapeType::circle: return collideCircles(a.circle, xfA, b.circle, xfB, d);
                case ShapeType::polygon: return collideCircleAndPolygon(a.circle, xfA, b.polygon, xfB, d);
                case ShapeType::segment: return collideCircleAndSegment(a.circle, xfA, b.segment, xfB, d);
            }
            break;
        case ShapeType::polygon:
            switch (b.type) {
                case ShapeType::circle: return swapped(collideCircleAndPolygon(b.circle, xfB, a.polygon, xfA, d));
                case ShapeType::polygon: return collidePolygons(a.polygon, xfA, b.polygon, xfB, d);
                case ShapeType::segment: return collidePolygonAndSegment(a.polygon, xfA, b.segment, xfB, d);
            }
            break;
        case ShapeType::segment:
            switch (b.type) {
                case ShapeType::circle: return swapped(collideCircleAndSegment(b.circle, xfB, a.segment, xfA, d));
                case ShapeType::polygon: return collideHullsWorld(hullOf(a.segment).view(), xfA, hullOf(b.polygon), xfB, d);
                case ShapeType::segment: return {};  // static ground never collides with static ground
            }
            break;
    }
    return {};
}

}  // namespace unison
