// resolver2d/query2d.cpp — see query2d.h: the exact ray and overlap tests on one shape, and World2's queries over
// its shape tree (core/scene_index.h).
//
// Rays are cast in the shape's frame (the origin and translation are taken into it), so a shape's answer does not
// depend on where its body stands beyond the rounding of that change of frame. Overlaps are decided by separating
// axes: two convex shapes without curved parts overlap exactly when no edge normal of either separates them; a
// circle overlaps a convex shape when its centre is strictly inside or closer than its radius to the boundary.
#include "query2d.h"

#include "world2d.h"

#include <algorithm>
#include <cmath>

namespace unison {

namespace {

// A shape placed in the world: circle (1 point, radius), polygon (vertices, edge normals) or segment (2 points,
// one normal).
struct Placed2 {
    int count = 0;
    std::array<Vec2, kMaxPolygonVertices> v{};
    int normalCount = 0;
    std::array<Vec2, kMaxPolygonVertices> n{};
    double radius = 0.0;
    bool circle = false;
    bool solid = false;  // has an interior (circle, polygon)
};

Placed2 place(const Shape2& s, const Transform2& xf) {
    Placed2 p;
    switch (s.type) {
        case ShapeType::circle:
            p.count = 1;
            p.v[0] = transformPoint(xf, s.circle.center);
            p.radius = s.circle.radius;
            p.circle = p.solid = true;
            break;
        case ShapeType::polygon:
            p.count = p.normalCount = s.polygon.count;
            for (int i = 0; i < p.count; ++i) {
                p.v[std::size_t(i)] = transformPoint(xf, s.polygon.vertices[std::size_t(i)]);
                p.n[std::size_t(i)] = rotate(xf.q, s.polygon.normals[std::size_t(i)]);
            }
            p.solid = true;
            break;
        case ShapeType::segment: {
            p.count = 2;
            p.v[0] = transformPoint(xf, s.segment.p1);
            p.v[1] = transformPoint(xf, s.segment.p2);
            const Vec2 e = p.v[1] - p.v[0];
            const double len = length(e);
            p.normalCount = 1;
            p.n[0] = {e.y / len, -e.x / len};
            break;
        }
    }
    return p;
}

// True when the projections of a and b on axis n are disjoint or only touch.
bool separatedAlong(const Placed2& a, const Placed2& b, Vec2 n) {
    double minA = dot(n, a.v[0]), maxA = minA, minB = dot(n, b.v[0]), maxB = minB;
    for (int i = 1; i < a.count; ++i) {
        const double d = dot(n, a.v[std::size_t(i)]);
        minA = std::min(minA, d);
        maxA = std::max(maxA, d);
    }
    for (int i = 1; i < b.count; ++i) {
        const double d = dot(n, b.v[std::size_t(i)]);
        minB = std::min(minB, d);
        maxB = std::max(maxB, d);
    }
    return maxA <= minB || maxB <= minA;
}

// Squared distance from p to the segment a-b.
double distanceSquaredToSegment(Vec2 p, Vec2 a, Vec2 b) {
    const Vec2 e = b - a;
    const double ee = dot(e, e);
    double t = ee > 0.0 ? dot(p - a, e) / ee : 0.0;
    t = std::min(1.0, std::max(0.0, t));
    const Vec2 d = p - (a + t * e);
    return dot(d, d);
}

// Circle (centre c, radius r) against a placed polygon or segment.
bool circleOverlaps(Vec2 c, double r, const Placed2& b) {
    if (b.solid) {
        bool inside = true;
        for (int i = 0; i < b.count; ++i) inside = inside && dot(b.n[std::size_t(i)], c - b.v[std::size_t(i)]) < 0.0;
        if (inside) return true;
    }
    const int edges = b.solid ? b.count : 1;
    for (int i = 0; i < edges; ++i)
        if (distanceSquaredToSegment(c, b.v[std::size_t(i)], b.v[std::size_t((i + 1) % b.count)]) < r * r) return true;
    return false;
}

}  // namespace

bool rayCastShape(const Shape2& s, const Transform2& xf, Vec2 origin, Vec2 translation, double* outFraction,
                  Vec2* outNormal) {
    const Vec2 o = invTransformPoint(xf, origin);
    const Vec2 d = invRotate(xf.q, translation);
    const double dd = dot(d, d);
    if (!(dd > 0.0)) return false;
    const Vec2 back = (-1.0 / std::sqrt(dd)) * d;  // the normal reported for a start inside a solid
    double t = 0.0;
    Vec2 n;
    switch (s.type) {
        case ShapeType::circle: {
            const Vec2 p = o - s.circle.center;
            const double r = s.circle.radius;
            const double c = dot(p, p) - r * r;
            if (c < 0.0) {
                n = back;
                break;
            }
            const double b = dot(p, d);
            const double disc = b * b - dd * c;
            if (b >= 0.0 || disc < 0.0) return false;  // moving away, or the line misses the circle
            t = c / (-b + std::sqrt(disc));              // the nearer root, without cancellation
            if (t > 1.0) return false;
            const Vec2 q = p + t * d;
            n = (1.0 / length(q)) * q;
            break;
        }
        case ShapeType::polygon: {
            // Cyrus-Beck: clip [0, 1] against every edge's half-plane.
            const Polygon& poly = s.polygon;
            double lower = 0.0, upper = 1.0;
            int face = -1;
            for (int i = 0; i < poly.count; ++i) {
                const Vec2 ni = poly.normals[std::size_t(i)];
                const double num = dot(ni, poly.vertices[std::size_t(i)] - o);  // > 0: origin inside this half-plane
                const double den = dot(ni, d);
                if (den == 0.0) {
                    if (num < 0.0) return false;  // parallel and outside
                } else if (den < 0.0 && num < lower * den) {
                    lower = num / den;  // entering
                    face = i;
                } else if (den > 0.0 && num < upper * den) {
                    upper = num / den;  // leaving
                }
                if (upper < lower) return false;
            }
            t = lower;
            n = face < 0 ? back : poly.normals[std::size_t(face)];
            break;
        }
        case ShapeType::segment: {
            const Vec2 p1 = s.segment.p1, e = s.segment.p2 - s.segment.p1;
            const double den = cross(d, e);
            if (den == 0.0) return false;  // parallel (a grazing ray along the segment does not hit it)
            const Vec2 w = p1 - o;
            t = cross(w, e) / den;
            const double u = cross(w, d) / den;
            if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return false;
            const double len = length(e);
            n = {e.y / len, -e.x / len};
            if (dot(n, d) > 0.0) n = -n;
            break;
        }
    }
    *outFraction = t;
    *outNormal = rotate(xf.q, n);
    return true;
}

bool shapesOverlap(const Shape2& a, const Transform2& xfA, const Shape2& b, const Transform2& xfB) {
    const Placed2 pa = place(a, xfA), pb = place(b, xfB);
    if (pa.circle && pb.circle) {
        const Vec2 d = pa.v[0] - pb.v[0];
        const double r = pa.radius + pb.radius;
        return dot(d, d) < r * r;
    }
    if (pa.circle) return circleOverlaps(pa.v[0], pa.radius, pb);
    if (pb.circle) return circleOverlaps(pb.v[0], pb.radius, pa);
    for (int i = 0; i < pa.normalCount; ++i)
        if (separatedAlong(pa, pb, pa.n[std::size_t(i)])) return false;
    for (int i = 0; i < pb.normalCount; ++i)
        if (separatedAlong(pa, pb, pb.n[std::size_t(i)])) return false;
    return true;
}

// ---- World2's queries ------------------------------------------------------------------------------------------

namespace {

QueryTree<2>::Box toBox(const Aabb2& b) { return {{b.lower.x, b.lower.y}, {b.upper.x, b.upper.y}}; }

bool finite(Vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }

}  // namespace

const SceneIndex<2>& World2::sceneIndex() const {
    mIndex->ensure([this](std::vector<ShapeRef>& items, std::vector<QueryTree<2>::Box>& boxes) {
        for (int d = 0; d < mBodies.size(); ++d) {
            const BodyState2& s = mBodies.hot(d);
            const Transform2 xf{s.position, s.rotation};
            const std::vector<Shape2>& shapes = mBodies.cold(d).shapes;
            for (int k = 0; k < int(shapes.size()); ++k) {
                items.push_back({mBodies.idAt(d), k});
                boxes.push_back(toBox(computeAabb(shapes[std::size_t(k)], xf)));
            }
        }
    });
    return *mIndex;
}

template <class Visit>
void World2::castRay(Vec2 origin, Vec2 translation, bool closest, Visit&& visit) const {
    if (!finite(origin) || !finite(translation) || !(dot(translation, translation) > 0.0)) return;
    const SceneIndex<2>& index = sceneIndex();
    index.tree().ray({origin.x, origin.y}, {translation.x, translation.y}, 1.0, [&](int item, double maxFraction) {
        const ShapeRef& ref = index.items()[std::size_t(item)];
        const auto [shape, xf] = placedShape(ref);
        RayHit2 hit;
        if (!rayCastShape(shape, xf, origin, translation, &hit.fraction, &hit.normal)) return maxFraction;
        hit.body = ref.body;
        hit.shape = ref.shape;
        hit.point = origin + hit.fraction * translation;
        visit(hit);
        return closest ? std::min(maxFraction, hit.fraction) : maxFraction;
    });
}

bool World2::rayCastClosest(Vec2 origin, Vec2 translation, RayHit2* out) const {
    return closestHit<RayHit2>([&](bool closest, auto&& visit) { castRay(origin, translation, closest, visit); }, out);
}

std::vector<RayHit2> World2::rayCastAll(Vec2 origin, Vec2 translation) const {
    return allHits<RayHit2>([&](bool closest, auto&& visit) { castRay(origin, translation, closest, visit); });
}

// The shape `ref` names and its body's transform.
std::pair<const Shape2&, Transform2> World2::placedShape(const ShapeRef& ref) const {
    const int d = mBodies.denseIndex(ref.body);
    const BodyState2& s = mBodies.hot(d);
    return {mBodies.cold(d).shapes[std::size_t(ref.shape)], Transform2{s.position, s.rotation}};
}

std::vector<ShapeRef> World2::overlapAabb(const Aabb2& box) const {
    if (!finite(box.lower) || !finite(box.upper)) return {};
    return sceneIndex().overlapping(toBox(box), [&](const ShapeRef& ref) {
        const auto [shape, xf] = placedShape(ref);
        return overlaps(computeAabb(shape, xf), box);
    });
}

std::vector<ShapeRef> World2::overlapShape(const Shape2& shape, const Transform2& xf) const {
    if (!finite(xf.p) || !std::isfinite(xf.q.c) || !std::isfinite(xf.q.s)) return {};
    return sceneIndex().overlapping(toBox(computeAabb(shape, xf)), [&](const ShapeRef& ref) {
        const auto [other, otherXf] = placedShape(ref);
        return shapesOverlap(shape, xf, other, otherXf);
    });
}

}  // namespace unison
