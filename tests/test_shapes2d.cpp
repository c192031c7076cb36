// tests/test_shapes2d.cpp — resolver2d/shapes2d: rotations, validating constructors (every rejection names what is
// wrong and leaves the output untouched), mass properties against closed forms, and AABBs of placed shapes.
#include "det_math.h"
#include "shapes2d.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace unison;

namespace {

constexpr double kTol = 1e-12;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

Polygon polygonOf(const std::vector<Vec2>& pts) {
    Polygon p;
    const std::string err = makePolygon(pts, &p);
    REQUIRE_MESSAGE(err.empty(), err);
    return p;
}

// Rejects pts with a message containing `part`, and leaves the output polygon as it was.
void checkRejected(const std::vector<Vec2>& pts, const std::string& part) {
    Polygon p;
    p.count = 77;
    const std::string err = makePolygon(pts, &p);
    CHECK_MESSAGE(contains(err, part), err);
    CHECK(p.count == 77);
}

}  // namespace

TEST_SUITE("shapes2d") {

TEST_CASE("rotations: makeRot, rotate/invRotate, angleOf, integrateRotation") {
    const Rot2 q = makeRot(0.5);
    CHECK(q.c == dmath::cos(0.5));
    CHECK(q.s == dmath::sin(0.5));
    CHECK(angleOf(q) == doctest::Approx(0.5).epsilon(kTol));
    const Vec2 v{1.25, -0.75};
    const Vec2 back = invRotate(q, rotate(q, v));
    CHECK(back.x == doctest::Approx(v.x).epsilon(kTol));
    CHECK(back.y == doctest::Approx(v.y).epsilon(kTol));
    const Vec2 e = rotate(makeRot(dmath::kPi / 2), {1.0, 0.0});
    CHECK(std::fabs(e.x) < kTol);
    CHECK(e.y == doctest::Approx(1.0));
    CHECK(angleOf(Rot2{}) == 0.0);

    // Small-angle integration turns by atan(delta) and stays unit length; 100 steps of 0.01 ~ 1 rad.
    Rot2 r;
    for (int i = 0; i < 100; ++i) r = integrateRotation(r, 0.01);
    CHECK(r.c * r.c + r.s * r.s == doctest::Approx(1.0).epsilon(1e-15));
    CHECK(angleOf(r) == doctest::Approx(100 * std::atan(0.01)).epsilon(1e-12));
    CHECK(std::fabs(angleOf(r) - 1.0) < 1e-4);

    const Transform2 xf{{2.0, 3.0}, makeRot(1.0)};
    const Vec2 w = transformPoint(xf, v);
    const Vec2 l = invTransformPoint(xf, w);
    CHECK(l.x == doctest::Approx(v.x).epsilon(kTol));
    CHECK(l.y == doctest::Approx(v.y).epsilon(kTol));
}

TEST_CASE("mass: box is m (w^2 + h^2) / 12, centred or offset and rotated") {
    Polygon box;
    REQUIRE(makeBox(0.5, 0.25, {}, 0.0, &box).empty());
    Shape2 s = toShape(box);
    s.density = 2.0;
    MassData m = computeMass(s);
    CHECK(m.mass == doctest::Approx(2.0 * 1.0 * 0.5).epsilon(kTol));
    CHECK(m.inertia == doctest::Approx(m.mass * (1.0 + 0.25) / 12.0).epsilon(kTol));
    CHECK(std::fabs(m.center.x) < kTol);
    CHECK(std::fabs(m.center.y) < kTol);

    REQUIRE(makeBox(0.5, 0.25, {3.0, -1.0}, 0.7, &box).empty());
    s = toShape(box);
    s.density = 2.0;
    m = computeMass(s);
    CHECK(m.mass == doctest::Approx(1.0).epsilon(kTol));
    CHECK(m.inertia == doctest::Approx(1.25 / 12.0).epsilon(1e-10));
    CHECK(m.center.x == doctest::Approx(3.0).epsilon(kTol));
    CHECK(m.center.y == doctest::Approx(-1.0).epsilon(kTol));
    CHECK(box.centroid.x == 3.0);
    for (int i = 0; i < 4; ++i) CHECK(length(box.normals[i]) == doctest::Approx(1.0).epsilon(1e-15));
}

TEST_CASE("mass: circle is rho pi r^2 and m r^2 / 2") {
    Circle c;
    REQUIRE(makeCircle({1.0, 2.0}, 0.3, &c).empty());
    Shape2 s = toShape(c);
    s.density = 4.0;
    const MassData m = computeMass(s);
    CHECK(m.mass == doctest::Approx(4.0 * dmath::kPi * 0.09).epsilon(kTol));
    CHECK(m.inertia == doctest::Approx(0.5 * m.mass * 0.09).epsilon(kTol));
    CHECK(m.center.x == 1.0);
    CHECK(m.center.y == 2.0);
}

TEST_CASE("mass: triangles (I = m (a^2 + b^2 + c^2) / 36 about the centroid)") {
    // Right triangle with legs 3 and 2.
    Shape2 s = toShape(polygonOf({{0.0, 0.0}, {3.0, 0.0}, {0.0, 2.0}}));
    MassData m = computeMass(s);
    CHECK(m.mass == doctest::Approx(3.0).epsilon(kTol));
    CHECK(m.center.x == doctest::Approx(1.0).epsilon(kTol));
    CHECK(m.center.y == doctest::Approx(2.0 / 3.0).epsilon(kTol));
    CHECK(m.inertia == doctest::Approx(m.mass * (9.0 + 4.0) / 18.0).epsilon(kTol));
    CHECK(s.polygon.centroid.x == doctest::Approx(1.0).epsilon(kTol));

    // A scalene triangle away from the origin.
    const Vec2 a{10.0, 5.0}, b{13.0, 6.0}, c{11.0, 9.0};
    s = toShape(polygonOf({a, b, c}));
    s.density = 0.5;
    m = computeMass(s);
    const double area = 0.5 * cross(b - a, c - a);
    const double sides = lengthSquared(b - a) + lengthSquared(c - b) + lengthSquared(a - c);
    CHECK(m.mass == doctest::Approx(0.5 * area).epsilon(kTol));
    CHECK(m.center.x == doctest::Approx((a.x + b.x + c.x) / 3.0).epsilon(kTol));
    CHECK(m.center.y == doctest::Approx((a.y + b.y + c.y) / 3.0).epsilon(kTol));
    CHECK(m.inertia == doctest::Approx(m.mass * sides / 36.0).epsilon(1e-10));
}

TEST_CASE("mass: regular hexagon of side s has area 3 sqrt(3) s^2 / 2 and I = 5 m s^2 / 12") {
    const double side = 0.8, h = side * std::sqrt(3.0) / 2.0;
    const Vec2 o{-2.0, 1.0};
    const std::vector<Vec2> pts = {o + Vec2{side, 0.0},       o + Vec2{side / 2, h},  o + Vec2{-side / 2, h},
                                   o + Vec2{-side, 0.0},      o + Vec2{-side / 2, -h}, o + Vec2{side / 2, -h}};
    const Shape2 s = toShape(polygonOf(pts));
    const MassData m = computeMass(s);
    CHECK(m.mass == doctest::Approx(1.5 * std::sqrt(3.0) * side * side).epsilon(kTol));
    CHECK(m.inertia == doctest::Approx(5.0 / 12.0 * m.mass * side * side).epsilon(kTol));
    CHECK(m.center.x == doctest::Approx(o.x).epsilon(kTol));
    CHECK(m.center.y == doctest::Approx(o.y).epsilon(kTol));
    for (int i = 0; i < 6; ++i) {
        // Outward unit normals: perpendicular to the edge, pointing away from the centre.
        const Vec2 e = s.polygon.vertices[(i + 1) % 6] - s.polygon.vertices[i];
        CHECK(length(s.polygon.normals[i]) == doctest::Approx(1.0).epsilon(1e-15));
        CHECK(std::fabs(dot(e, s.polygon.normals[i])) < kTol);
        CHECK(dot(s.polygon.vertices[i] - o, s.polygon.normals[i]) > 0.0);
    }
}

TEST_CASE("mass: segments are massless") {
    Segment seg;
    REQUIRE(makeSegment({-1.0, 0.0}, {3.0, 0.0}, &seg).empty());
    const MassData m = computeMass(toShape(seg));
    CHECK(m.mass == 0.0);
    CHECK(m.inertia == 0.0);
    CHECK(m.center.x == 1.0);
}

TEST_CASE("polygon validation names the problem and never writes a half-valid polygon") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    checkRejected({{0, 0}, {0, 1}, {1, 0}}, "counter-clockwise");
    checkRejected({{0, 0}, {1, 1}, {2, 0}, {2, 2}, {0, 2}}, "reflex vertex");  // a dent at (1, 1)
    checkRejected({{0, 0}, {2, 0}, {2, 2}, {1, 1.5}, {0, 2}}, "reflex vertex");
    checkRejected({{0, 0}, {1, 0}, {2, 0}, {2, 1}, {0, 1}}, "collinear");
    checkRejected({{0, 0}, {1, 0}, {1, 1}, {1, 1 + 1e-12}, {0, 2}}, "coincide");  // within 1e-9 x size
    checkRejected({{0, 0}, {1, 0}, {1, 1}, {0.5, 1.0 + 1e-9}, {0, 1}}, "collinear");
    checkRejected({{0, 0}, {1, 0}, {2, 0}}, "area");
    checkRejected({{0, 0}, {1, 0}}, "3 to 8");
    checkRejected({}, "3 to 8");
    std::vector<Vec2> nine;
    for (int i = 0; i < 9; ++i) nine.push_back({dmath::cos(i * 2 * dmath::kPi / 9), dmath::sin(i * 2 * dmath::kPi / 9)});
    checkRejected(nine, "3 to 8");
    nine.pop_back();
    CHECK(polygonOf(nine).count == 8);
    checkRejected({{0, 0}, {1, nan}, {0, 1}}, "not finite");
    checkRejected({{0, 0}, {1, 0}, {inf, 1}}, "not finite");
    checkRejected({{0, 0}, {1, 0}, {1, 1}, {1, 0}}, "coincide");
    checkRejected({{0, 0}, {1, 0}, {1, 1}, {0, 0}}, "coincide");
    checkRejected({{1, 1}, {1, 1}, {1, 1}}, "coincide");
    checkRejected({{-1e300, 0}, {1e300, 0}, {0, 1e300}}, "too large");
    // A pentagram: every vertex turns left, yet the outline winds twice.
    std::vector<Vec2> star;
    for (int k = 0; k < 5; ++k) {
        const double t = (2 * k % 5) * 2 * dmath::kPi / 5;
        star.push_back({dmath::cos(t), dmath::sin(t)});
    }
    checkRejected(star, "winds more than once");

    // Errors of the other constructors.
    Circle c{{9, 9}, 9};
    CHECK(contains(makeCircle({0, 0}, 0.0, &c), "radius"));
    CHECK(contains(makeCircle({0, 0}, -1.0, &c), "radius"));
    CHECK(contains(makeCircle({0, 0}, nan, &c), "radius"));
    CHECK(contains(makeCircle({nan, 0}, 1.0, &c), "center"));
    CHECK(c.radius == 9.0);
    Polygon box;
    CHECK(contains(makeBox(0.0, 1.0, {}, 0.0, &box), "half extents"));
    CHECK(contains(makeBox(1.0, inf, {}, 0.0, &box), "half extents"));
    CHECK(contains(makeBox(1.0, 1.0, {}, nan, &box), "angle"));
    CHECK(contains(makeBox(1.0, 1.0, {inf, 0}, 0.0, &box), "center"));
    CHECK(box.count == 0);
    Segment seg{{7, 7}, {8, 8}};
    CHECK(contains(makeSegment({1, 1}, {1, 1}, &seg), "distinct"));
    CHECK(contains(makeSegment({1, nan}, {1, 1}, &seg), "finite"));
    CHECK(seg.p1.x == 7.0);
}

TEST_CASE("valid polygons keep their vertex order") {
    const Polygon p = polygonOf({{0, 0}, {4, 0}, {5, 2}, {2, 4}, {-1, 2}});
    CHECK(p.count == 5);
    CHECK(p.vertices[2].x == 5.0);
    CHECK(p.normals[0].x == 0.0);
    CHECK(p.normals[0].y == -1.0);
    // A tiny but well-shaped polygon is fine: tolerances scale with size.
    CHECK(polygonOf({{0, 0}, {1e-6, 0}, {0, 1e-6}}).count == 3);
}

TEST_CASE("AABBs of placed shapes") {
    Polygon box;
    REQUIRE(makeBox(1.0, 0.5, {}, 0.0, &box).empty());
    const Shape2 s = toShape(box);
    Aabb2 bb = computeAabb(s, {{10.0, 20.0}, makeRot(dmath::kPi / 2)});
    CHECK(bb.lower.x == doctest::Approx(9.5).epsilon(kTol));
    CHECK(bb.upper.x == doctest::Approx(10.5).epsilon(kTol));
    CHECK(bb.lower.y == doctest::Approx(19.0).epsilon(kTol));
    CHECK(bb.upper.y == doctest::Approx(21.0).epsilon(kTol));

    REQUIRE(makeBox(1.0, 1.0, {}, 0.0, &box).empty());
    bb = computeAabb(toShape(box), {{0.0, 0.0}, makeRot(dmath::kPi / 4)});
    CHECK(bb.upper.x == doctest::Approx(std::sqrt(2.0)).epsilon(kTol));
    CHECK(bb.lower.y == doctest::Approx(-std::sqrt(2.0)).epsilon(kTol));

    // A circle off the body origin moves with the rotation; its box does not grow.
    Circle c;
    REQUIRE(makeCircle({1.0, 0.0}, 0.25, &c).empty());
    bb = computeAabb(toShape(c), {{2.0, 0.0}, makeRot(dmath::kPi / 2)});
    CHECK(bb.lower.x == doctest::Approx(1.75).epsilon(kTol));
    CHECK(bb.upper.x == doctest::Approx(2.25).epsilon(kTol));
    CHECK(bb.lower.y == doctest::Approx(0.75).epsilon(kTol));
    CHECK(bb.upper.y == doctest::Approx(1.25).epsilon(kTol));

    Segment seg;
    REQUIRE(makeSegment({0.0, 0.0}, {2.0, 0.0}, &seg).empty());
    bb = computeAabb(toShape(seg), {{0.0, 0.0}, makeRot(dmath::kPi / 6)});
    CHECK(bb.lower.x == 0.0);
    CHECK(bb.upper.x == doctest::Approx(std::sqrt(3.0)).epsilon(kTol));
    CHECK(bb.upper.y == doctest::Approx(1.0).epsilon(kTol));
    CHECK(overlaps(bb, Aabb2{{1.0, 0.5}, {3.0, 3.0}}));
    CHECK(!overlaps(bb, Aabb2{{2.0, 0.0}, {3.0, 3.0}}));
    CHECK(overlaps(Aabb2{{0.0, 0.0}, {1.0, 1.0}}, Aabb2{{1.0, 1.0}, {2.0, 2.0}}));  // touching counts
}

}  // TEST_SUITE
