// resolver2d/shapes2d.cpp — see shapes2d.h.
//
// Polygon mass properties use the classic triangle-fan integration (as in Box2D's b2ComputePolygonMass and any
// rigid-body text): split the polygon into triangles (r, v_i, v_{i+1}) about a reference point r inside it, and
// for each triangle with edge vectors e1 = v_i - r, e2 = v_{i+1} - r and D = e1 x e2:
//     area = D / 2,   first moment = area (e1 + e2) / 3,
//     integral of (x^2 + y^2) dA about r = D / 12 (e1x^2 + e1x e2x + e2x^2 + e1y^2 + e1y e2y + e2y^2).
// The inertia about the centroid c then follows from the parallel-axis theorem: I_c = I_r - m |c - r|^2. I take r as
// the vertex mean, which keeps |c - r| small, so the subtraction loses little; for a box centred at r the sums are
// exact up to rounding and give m (w^2 + h^2) / 12.
#include "shapes2d.h"

#include "det_math.h"

#include <algorithm>
#include <cmath>

namespace unison {
namespace {

// Validation tolerances, all relative to the polygon's size (the larger side of its bounding box, `scale`):
// two vertices closer than kDuplicateTolerance * scale coincide; an area below kAreaTolerance * scale^2 is zero;
// a turn whose sine is below kTurnTolerance (about a micro-radian) is a straight (collinear) vertex.
constexpr double kDuplicateTolerance = 1.0e-9;
constexpr double kAreaTolerance = 1.0e-9;
constexpr double kTurnTolerance = 1.0e-6;

bool finite(Vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// Outward normal of the counter-clockwise edge a -> b: the edge rotated by -90 degrees, normalised.
Vec2 edgeNormal(Vec2 a, Vec2 b) {
    const Vec2 e = b - a;
    const double len = length(e);
    return {e.y / len, -e.x / len};
}

struct PolygonIntegrals {
    double area = 0.0;
    Vec2 centroid;          // absolute (body frame)
    double polarAbout = 0.0;  // integral of |x - centroid|^2 dA
};

PolygonIntegrals integratePolygon(const Polygon& poly) {
    const int n = poly.count;
    Vec2 r;
    for (int i = 0; i < n; ++i) r = r + poly.vertices[i];
    r = (1.0 / n) * r;
    double area = 0.0;
    Vec2 moment;
    double polar = 0.0;
    for (int i = 0; i < n; ++i) {
        const Vec2 e1 = poly.vertices[i] - r;
        const Vec2 e2 = poly.vertices[(i + 1) % n] - r;
        const double d = cross(e1, e2);
        const double triArea = 0.5 * d;
        area += triArea;
        moment = moment + (triArea / 3.0) * (e1 + e2);
        const double ix = e1.x * e1.x + e1.x * e2.x + e2.x * e2.x;
        const double iy = e1.y * e1.y + e1.y * e2.y + e2.y * e2.y;
        polar += (d / 12.0) * (ix + iy);
    }
    PolygonIntegrals out;
    out.area = area;
    const Vec2 c = (1.0 / area) * moment;
    out.centroid = r + c;
    out.polarAbout = polar - area * dot(c, c);  // parallel-axis theorem
    return out;
}

}  // namespace

Rot2 makeRot(double angle) {
    Rot2 q;
    dmath::sincos(angle, &q.s, &q.c);
    return q;
}

// Box2D v3's b2IntegrateRotation: move (c, s) along its tangent (-s, c) by deltaAngle and renormalise. This turns q
// by atan(deltaAngle) rather than deltaAngle (relative error about deltaAngle^2 / 3, negligible for omega dt
// below a few hundredths), needs no trigonometry and keeps |q| = 1 to rounding every step.
Rot2 integrateRotation(Rot2 q, double deltaAngle) {
    const double c = q.c - deltaAngle * q.s;
    const double s = q.s + deltaAngle * q.c;
    const double mag = std::sqrt(c * c + s * s);
    const double inv = mag > 0.0 ? 1.0 / mag : 0.0;
    return {c * inv, s * inv};
}

double angleOf(Rot2 q) { return dmath::atan2(q.s, q.c); }

Shape2 toShape(const Circle& c) {
    Shape2 s;
    s.type = ShapeType::circle;
    s.circle = c;
    return s;
}

Shape2 toShape(const Polygon& p) {
    Shape2 s;
    s.type = ShapeType::polygon;
    s.polygon = p;
    return s;
}

Shape2 toShape(const Segment& seg) {
    Shape2 s;
    s.type = ShapeType::segment;
    s.segment = seg;
    return s;
}

std::string makeCircle(Vec2 center, double radius, Circle* out) {
    if (!finite(center)) return "circle: center must be finite";
    if (!std::isfinite(radius) || !(radius > 0.0)) return "circle: radius must be finite and > 0";
    out->center = center;
    out->radius = radius;
    return {};
}

std::string makeBox(double hx, double hy, Vec2 center, double angle, Polygon* out) {
    if (!std::isfinite(hx) || !std::isfinite(hy) || !(hx > 0.0) || !(hy > 0.0))
        return "box: half extents must be finite and > 0";
    if (!finite(center)) return "box: center must be finite";
    if (!std::isfinite(angle)) return "box: angle must be finite";
    const Rot2 q = makeRot(angle);
    const Vec2 local[4] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
    const Vec2 normals[4] = {{0.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}};
    Polygon p;
    p.count = 4;
    for (int i = 0; i < 4; ++i) {
        p.vertices[i] = center + rotate(q, local[i]);
        p.normals[i] = rotate(q, normals[i]);
    }
    p.centroid = center;
    *out = p;
    return {};
}

std::string makePolygon(const std::vector<Vec2>& points, Polygon* out) {
    const int n = static_cast<int>(points.size());
    if (n < 3 || n > kMaxPolygonVertices)
        return "polygon: needs 3 to " + std::to_string(kMaxPolygonVertices) + " vertices, got " +
               std::to_string(points.size());
    for (int i = 0; i < n; ++i)
        if (!finite(points[i])) return "polygon: vertex " + std::to_string(i) + " is not finite";
    Vec2 lo = points[0], hi = points[0];
    for (int i = 1; i < n; ++i) {
        lo = {std::min(lo.x, points[i].x), std::min(lo.y, points[i].y)};
        hi = {std::max(hi.x, points[i].x), std::max(hi.y, points[i].y)};
    }
    const double scale = std::max(hi.x - lo.x, hi.y - lo.y);
    if (!std::isfinite(scale * scale)) return "polygon: coordinates are too large";
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            if (length(points[j] - points[i]) <= kDuplicateTolerance * scale)
                return "polygon: vertices " + std::to_string(i) + " and " + std::to_string(j) + " coincide";
    // Shoelace formula relative to points[0]: twice the signed area, positive for counter-clockwise order.
    double twiceArea = 0.0;
    for (int i = 1; i + 1 < n; ++i) twiceArea += cross(points[i] - points[0], points[i + 1] - points[0]);
    if (std::fabs(0.5 * twiceArea) <= kAreaTolerance * scale * scale) return "polygon: area is (nearly) zero";
    if (twiceArea < 0.0) return "polygon: vertices must be counter-clockwise";
    // Strict convexity: every vertex turns left by more than the tolerance ...
    for (int i = 0; i < n; ++i) {
        const Vec2 ein = points[i] - points[(i + n - 1) % n];
        const Vec2 eout = points[(i + 1) % n] - points[i];
        const double turn = cross(ein, eout);
        const double limit = kTurnTolerance * length(ein) * length(eout);
        if (turn <= limit) {
            if (turn >= -limit) return "polygon: vertex " + std::to_string(i) + " is collinear with its neighbours";
            return "polygon: not convex (reflex vertex " + std::to_string(i) + ")";
        }
    }
    // ... and every vertex lies strictly inside every edge's half-plane (rejects a star that winds twice).
    for (int i = 0; i < n; ++i) {
        const Vec2 a = points[i];
        const Vec2 e = points[(i + 1) % n] - a;
        for (int j = 0; j < n; ++j) {
            if (j == i || j == (i + 1) % n) continue;
            if (!(cross(e, points[j] - a) > 0.0))
                return "polygon: not convex (edges cross; the outline winds more than once)";
        }
    }
    Polygon p;
    p.count = n;
    for (int i = 0; i < n; ++i) {
        p.vertices[i] = points[i];
        p.normals[i] = edgeNormal(points[i], points[(i + 1) % n]);
    }
    p.centroid = integratePolygon(p).centroid;
    *out = p;
    return {};
}

std::string makeSegment(Vec2 p1, Vec2 p2, Segment* out) {
    if (!finite(p1) || !finite(p2)) return "segment: points must be finite";
    const double len = length(p2 - p1);
    if (!(len > 0.0) || !std::isfinite(len)) return "segment: points must be distinct (and not absurdly far apart)";
    out->p1 = p1;
    out->p2 = p2;
    return {};
}

MassData computeMass(const Shape2& s) {
    MassData m;
    switch (s.type) {
        case ShapeType::circle: {
            // Solid disc: m = rho pi r^2, I = m r^2 / 2 about its centre.
            const double r = s.circle.radius;
            m.mass = s.density * dmath::kPi * r * r;
            m.center = s.circle.center;
            m.inertia = 0.5 * m.mass * r * r;
            break;
        }
        case ShapeType::polygon: {
            const PolygonIntegrals in = integratePolygon(s.polygon);
            m.mass = s.density * in.area;
            m.center = in.centroid;
            m.inertia = s.density * in.polarAbout;
            break;
        }
        case ShapeType::segment:
            m.mass = 0.0;
            m.center = 0.5 * (s.segment.p1 + s.segment.p2);
            m.inertia = 0.0;
            break;
    }
    return m;
}

Aabb2 computeAabb(const Shape2& s, const Transform2& xf) {
    switch (s.type) {
        case ShapeType::circle: {
            const Vec2 c = transformPoint(xf, s.circle.center);
            const Vec2 r{s.circle.radius, s.circle.radius};
            return {c - r, c + r};
        }
        case ShapeType::polygon: {
            const Polygon& p = s.polygon;
            Vec2 lo = transformPoint(xf, p.vertices[0]);
            Vec2 hi = lo;
            for (int i = 1; i < p.count; ++i) {
                const Vec2 v = transformPoint(xf, p.vertices[i]);
                lo = {std::min(lo.x, v.x), std::min(lo.y, v.y)};
                hi = {std::max(hi.x, v.x), std::max(hi.y, v.y)};
            }
            return {lo, hi};
        }
        case ShapeType::segment: {
            const Vec2 a = transformPoint(xf, s.segment.p1);
            const Vec2 b = transformPoint(xf, s.segment.p2);
            return {{std::min(a.x, b.x), std::min(a.y, b.y)}, {std::max(a.x, b.x), std::max(a.y, b.y)}};
        }
    }
    return {};
}

}  // namespace unison
