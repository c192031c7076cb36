// tests/test_collide2d.cpp — resolver2d/collide2d and resolver2d/broadphase2d: manifold geometry against hand-worked
// answers (normal from B towards A, points midway, separations), speculative contacts, feature ids that survive tiny
// motions, and the sort-and-sweep broadphase against brute force.
#include "broadphase2d.h"
#include "collide2d.h"
#include "det_math.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

using namespace unison;

namespace {

constexpr double kTol = 1e-12;
constexpr double kSpec = 0.02;  // speculative distance (m)

Shape2 box(double hx, double hy) {
    Polygon p;
    REQUIRE(makeBox(hx, hy, {}, 0.0, &p).empty());
    return toShape(p);
}

Shape2 circle(double r) {
    Circle c;
    REQUIRE(makeCircle({}, r, &c).empty());
    return toShape(c);
}

Shape2 segment(Vec2 p1, Vec2 p2) {
    Segment s;
    REQUIRE(makeSegment(p1, p2, &s).empty());
    return toShape(s);
}

Transform2 at(double x, double y, double angle = 0.0) { return {{x, y}, makeRot(angle)}; }

void checkVec(Vec2 v, double x, double y, double tol = kTol) {
    CHECK(v.x == doctest::Approx(x).epsilon(tol).scale(1.0));
    CHECK(v.y == doctest::Approx(y).epsilon(tol).scale(1.0));
}

// Lowest y of a box of half extents (h, h) rotated by angle about its centre.
double lowestCorner(double h, double angle) {
    const Rot2 q = makeRot(angle);
    double lo = 0.0;
    const Vec2 corners[4] = {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
    for (const Vec2& c : corners) lo = std::min(lo, rotate(q, c).y);
    return lo;
}

}  // namespace

TEST_SUITE("collide2d") {

TEST_CASE("circle-circle: separation, normal from B to A, midpoint") {
    Manifold2 m = collide(circle(1.0), at(0.0, 1.9), circle(1.0), at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.0, 1.0);
    CHECK(m.points[0].separation == doctest::Approx(-0.1).epsilon(kTol));
    checkVec(m.points[0].point, 0.0, 0.95);

    m = collide(circle(0.5), at(3.0, 4.0), circle(1.5), at(0.0, 0.0), kSpec);  // distance 5, gap 3
    CHECK(m.count == 0);
    m = collide(circle(0.5), at(3.0, 4.0), circle(4.49), at(0.0, 0.0), kSpec);  // gap 0.01: speculative
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.6, 0.8);
    CHECK(m.points[0].separation == doctest::Approx(0.01).epsilon(1e-9));
    // Coincident centres still give a unit normal.
    m = collide(circle(1.0), at(1.0, 1.0), circle(1.0), at(1.0, 1.0), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.0, 1.0);
    CHECK(m.points[0].separation == -2.0);
}

TEST_CASE("box resting on a box: 2 points at the top box's corners, normal (0,1) for A above B") {
    const Shape2 top = box(0.5, 0.5), ground = box(5.0, 0.5);
    Manifold2 m = collide(top, at(0.3, 0.99), ground, at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 2);
    checkVec(m.normal, 0.0, 1.0);
    for (int i = 0; i < 2; ++i) {
        CHECK(m.points[i].separation == doctest::Approx(-0.01).epsilon(1e-9));
        CHECK(m.points[i].point.y == doctest::Approx(0.495).epsilon(1e-9));
    }
    CHECK(std::fmin(m.points[0].point.x, m.points[1].point.x) == doctest::Approx(-0.2).epsilon(1e-9));
    CHECK(std::fmax(m.points[0].point.x, m.points[1].point.x) == doctest::Approx(0.8).epsilon(1e-9));
    CHECK(m.points[0].id != m.points[1].id);

    // Same pair in the other order: the normal flips (still from B to A), the points stay.
    const Manifold2 r = collide(ground, at(0.0, 0.0), top, at(0.3, 0.99), kSpec);
    REQUIRE(r.count == 2);
    checkVec(r.normal, 0.0, -1.0);
    CHECK(r.points[0].separation == doctest::Approx(-0.01).epsilon(1e-9));

    // Gap inside the speculative distance: 2 points with positive separation; beyond it: none.
    m = collide(top, at(0.0, 1.005), ground, at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 2);
    CHECK(m.points[0].separation == doctest::Approx(0.005).epsilon(1e-9));
    CHECK(collide(top, at(0.0, 1.05), ground, at(0.0, 0.0), kSpec).count == 0);
    CHECK(collide(top, at(7.0, 0.0), ground, at(0.0, 0.0), kSpec).count == 0);
}

TEST_CASE("box on a long segment ground: 2 points at the corners, either shape order") {
    const Shape2 top = box(0.5, 0.25), ground = segment({-10.0, 0.0}, {10.0, 0.0});
    Manifold2 m = collide(top, at(2.0, 0.25 - 0.003), ground, at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 2);
    checkVec(m.normal, 0.0, 1.0);
    checkVec(m.points[0].point, 1.5, -0.0015, 1e-9);
    checkVec(m.points[1].point, 2.5, -0.0015, 1e-9);
    CHECK(m.points[0].separation == doctest::Approx(-0.003).epsilon(1e-9));

    m = collide(ground, at(0.0, 0.0), top, at(2.0, 0.25 - 0.003), kSpec);
    REQUIRE(m.count == 2);
    checkVec(m.normal, 0.0, -1.0);
    CHECK(std::fmin(m.points[0].point.x, m.points[1].point.x) == doctest::Approx(1.5).epsilon(1e-9));
    CHECK(std::fmax(m.points[0].point.x, m.points[1].point.x) == doctest::Approx(2.5).epsilon(1e-9));

    // The segment is two-sided: a box hanging below it is pushed down, and a segment reversed in direction works.
    m = collide(top, at(0.0, -0.25 + 0.003), segment({10.0, 0.0}, {-10.0, 0.0}), at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 2);
    checkVec(m.normal, 0.0, -1.0);
    // A box resting on a tilted segment ground (placed by its transform) gets the tilted normal.
    const double tilt = 0.3;
    m = collide(top, {rotate(makeRot(tilt), {1.0, 0.25 - 0.003}), makeRot(tilt)}, ground, at(0.0, 0.0, tilt), kSpec);
    REQUIRE(m.count == 2);
    checkVec(m.normal, -dmath::sin(tilt), dmath::cos(tilt));
    CHECK(m.points[1].separation == doctest::Approx(-0.003).epsilon(1e-9));
}

TEST_CASE("rotated box: 1 corner point within the speculative distance, 2 points when flat") {
    const Shape2 ground = segment({-10.0, 0.0}, {10.0, 0.0});
    const Shape2 groundBox = box(10.0, 1.0);
    const double angle = dmath::kPi / 6;
    const double y = -lowestCorner(0.5, angle) + 0.001;
    const Transform2 xf = at(0.0, y, angle);
    for (int k = 0; k < 2; ++k) {
        const Manifold2 m = k == 0 ? collide(box(0.5, 0.5), xf, ground, at(0.0, 0.0), kSpec)
                                   : collide(box(0.5, 0.5), xf, groundBox, at(0.0, -1.0), kSpec);
        REQUIRE(m.count == 1);
        checkVec(m.normal, 0.0, 1.0);
        CHECK(m.points[0].separation == doctest::Approx(0.001).epsilon(1e-9));
        // The lowest corner of a box rotated by 30 degrees is the local corner (-h, -h) turned: x = -h c + h s.
        CHECK(m.points[0].point.x == doctest::Approx(-0.5 * dmath::cos(angle) + 0.5 * dmath::sin(angle)));
        CHECK(m.points[0].point.y == doctest::Approx(0.0005).epsilon(1e-9));
    }
    CHECK(collide(box(0.5, 0.5), at(0.0, 0.501), ground, at(0.0, 0.0), kSpec).count == 2);
    // Corner pressed into the ground: still one point, now overlapping.
    const Manifold2 deep = collide(box(0.5, 0.5), at(0.0, y - 0.011, angle), ground, at(0.0, 0.0), kSpec);
    REQUIRE(deep.count == 1);
    CHECK(deep.points[0].separation == doctest::Approx(-0.01).epsilon(1e-9));
}

TEST_CASE("thin card: one point at the deeper corner of a face shorter than 5 mm, two on its long face") {
    // A card 2 mm thick and 40 cm long. Standing on its end, leaning 25 degrees, it touches the ground at the lower
    // corner of its 2 mm end (the other corner is 0.85 mm higher): one point, not two rows 2 mm apart.
    const Shape2 card = box(0.001, 0.2), ground = box(10.0, 1.0);
    const double lean = 25.0 * dmath::kPi / 180.0;
    const Rot2 q = makeRot(lean);
    const Vec2 lower = rotate(q, {-0.001, -0.2}), upper = rotate(q, {0.001, -0.2});  // the end's two corners
    REQUIRE(lower.y < upper.y);
    const double y = -lower.y - 0.001;  // the lower corner 1 mm deep
    for (int order = 0; order < 2; ++order) {
        const Manifold2 m = order == 0 ? collide(card, at(0.0, y, lean), ground, at(0.0, -1.0), kSpec)
                                       : collide(ground, at(0.0, -1.0), card, at(0.0, y, lean), kSpec);
        REQUIRE(m.count == 1);
        checkVec(m.normal, 0.0, order == 0 ? 1.0 : -1.0);
        CHECK(m.points[0].separation == doctest::Approx(-0.001).epsilon(1e-9));
        CHECK(m.points[0].point.x == doctest::Approx(lower.x).epsilon(1e-9));
    }
    // Standing upright, both corners equally deep: the first stays.
    const Manifold2 upright = collide(card, at(0.0, 0.2 - 0.001), ground, at(0.0, -1.0), kSpec);
    REQUIRE(upright.count == 1);
    CHECK(upright.points[0].separation == doctest::Approx(-0.001).epsilon(1e-9));
    // The card lying flat on its long face keeps both corners, and so does a 1 cm box (faces longer than 5 mm).
    CHECK(collide(card, at(0.0, 0.001 - 0.0005, 0.5 * dmath::kPi), ground, at(0.0, -1.0), kSpec).count == 2);
    CHECK(collide(box(0.005, 0.005), at(0.0, 0.005 - 0.001), ground, at(0.0, -1.0), kSpec).count == 2);
}

TEST_CASE("feature ids stay the same under tiny motions (warm starts match)") {
    struct Case {
        Shape2 a;
        Shape2 b;
        Transform2 xfA;
        Transform2 xfB;
    };
    const std::vector<Case> cases = {
        {box(0.5, 0.5), box(5.0, 0.5), at(0.3, 0.99), at(0.0, 0.0)},                // small on big
        {box(5.0, 0.5), box(0.5, 0.5), at(0.0, 0.0), at(0.3, 0.99)},                // big on small (other order)
        {box(0.5, 0.5), box(0.5, 0.5), at(0.0, 0.999), at(0.0, 0.0)},               // equal faces: no flip-flop
        {box(0.5, 0.5), box(0.5, 0.5), at(0.25, 0.999), at(0.0, 0.0)},              // equal boxes, offset
        {box(0.5, 0.25), segment({-10, 0}, {10, 0}), at(1.0, 0.249), at(0.0, 0.0)},  // box on segment
        {segment({-10, 0}, {10, 0}), box(0.5, 0.25), at(0.0, 0.0), at(1.0, 0.249)},  // segment first
        {box(0.5, 0.5), box(5.0, 0.5), at(0.0, 0.199 - lowestCorner(0.5, 0.3), 0.3), at(0.0, -0.3)},  // corner
        {circle(0.5), box(1.0, 1.0), at(0.2, 1.49), at(0.0, 0.0)},                   // circle on face
        {circle(0.5), box(1.0, 1.0), at(1.3, 1.3), at(0.0, 0.0)},                    // circle on vertex
    };
    const Vec2 nudges[4] = {{1e-6, 0.0}, {-1e-6, 1e-6}, {0.0, -1e-6}, {1e-6, 1e-6}};
    for (size_t c = 0; c < cases.size(); ++c) {
        CAPTURE(c);
        const Case& k = cases[c];
        const Manifold2 m0 = collide(k.a, k.xfA, k.b, k.xfB, kSpec);
        REQUIRE(m0.count >= 1);
        for (const Vec2& d : nudges) {
            for (int tiltSign = -1; tiltSign <= 1; ++tiltSign) {
                Transform2 moved = k.xfA;
                moved.p = moved.p + d;
                moved.q = integrateRotation(moved.q, tiltSign * 1e-7);
                const Manifold2 m1 = collide(k.a, moved, k.b, k.xfB, kSpec);
                REQUIRE(m1.count == m0.count);
                for (int i = 0; i < m0.count; ++i) CHECK(m1.points[i].id == m0.points[i].id);
            }
        }
    }
}

TEST_CASE("separated shapes beyond the speculative distance give no points, for every pair type") {
    const Shape2 shapes[3] = {circle(0.5), box(0.5, 0.5), segment({-0.5, 0.0}, {0.5, 0.0})};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            CAPTURE(i);
            CAPTURE(j);
            CHECK(collide(shapes[i], at(0.0, 1.0 + 1.5 * kSpec + (i == 2 ? 0.5 : 0.0) + (j == 2 ? 0.5 : 0.0)),
                          shapes[j], at(0.0, 0.0), kSpec)
                      .count == 0);
            CHECK(collide(shapes[i], at(3.0, 3.0, 0.7), shapes[j], at(0.0, 0.0), kSpec).count == 0);
        }
    }
    // Static ground never collides with static ground, even crossing.
    CHECK(collide(shapes[2], at(0.0, 0.0), shapes[2], at(0.0, 0.0, 1.0), kSpec).count == 0);
    // Corner to corner: the separating axes say 0.015 (< kSpec) but the faces do not face each other and the true
    // gap is 0.021: no points. Side by side with the same axis gap, the faces overlap in y: 2 points at 0.015.
    CHECK(collide(box(0.5, 0.5), at(1.015, 1.015), box(0.5, 0.5), at(0.0, 0.0), kSpec).count == 0);
    const Manifold2 side = collide(box(0.5, 0.5), at(1.015, 0.9), box(0.5, 0.5), at(0.0, 0.0), kSpec);
    REQUIRE(side.count == 2);
    checkVec(side.normal, 1.0, 0.0);
    CHECK(side.points[0].separation == doctest::Approx(0.015).epsilon(1e-9));
}

TEST_CASE("circle against a polygon: face region, vertex region, centre inside, both orders") {
    const Shape2 b = box(1.0, 1.0);
    // Face region above the top face.
    Manifold2 m = collide(circle(0.5), at(0.2, 1.48), b, at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.0, 1.0);
    CHECK(m.points[0].separation == doctest::Approx(-0.02).epsilon(1e-9));
    checkVec(m.points[0].point, 0.2, 0.99, 1e-9);
    CHECK(featureKind(m.points[0].id) == FeatureKind::circleFace);

    // Vertex region of the corner (1, 1), along the diagonal.
    const double s = std::sqrt(0.5);
    m = collide(circle(0.5), at(1.0 + 0.49 * s, 1.0 + 0.49 * s), b, at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, s, s, 1e-9);
    CHECK(m.points[0].separation == doctest::Approx(-0.01).epsilon(1e-9));
    checkVec(m.points[0].point, 1.0 - 0.005 * s, 1.0 - 0.005 * s, 1e-9);
    CHECK(featureKind(m.points[0].id) == FeatureKind::circleVertex);
    // Outside the corner's reach (diagonal gap 0.1): none.
    CHECK(collide(circle(0.5), at(1.0 + 0.6 * s, 1.0 + 0.6 * s), b, at(0.0, 0.0), kSpec).count == 0);

    // Centre inside near the right face: pushed out through it.
    m = collide(circle(0.25), at(0.9, 0.0), b, at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, 1.0, 0.0);
    CHECK(m.points[0].separation == doctest::Approx(-0.35).epsilon(1e-9));

    // Polygon first: the normal points from the circle to the polygon.
    m = collide(b, at(0.0, 0.0), circle(0.5), at(0.2, 1.48), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.0, -1.0);
    checkVec(m.points[0].point, 0.2, 0.99, 1e-9);

    // A rotated polygon: a circle resting on a diamond's upper-right face.
    m = collide(circle(0.5), at(1.49 * s, 1.49 * s), b, at(0.0, 0.0, dmath::kPi / 4), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, s, s, 1e-9);
    CHECK(m.points[0].separation == doctest::Approx(-0.01).epsilon(1e-9));
    checkVec(m.points[0].point, 0.995 * s, 0.995 * s, 1e-9);
}

TEST_CASE("circle against a segment: either side, the ends, both orders") {
    const Shape2 g = segment({-1.0, 0.0}, {1.0, 0.0});
    Manifold2 m = collide(circle(0.5), at(0.3, 0.49), g, at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.0, 1.0);
    CHECK(m.points[0].separation == doctest::Approx(-0.01).epsilon(1e-9));
    checkVec(m.points[0].point, 0.3, -0.005, 1e-9);
    m = collide(circle(0.5), at(0.3, -0.49), g, at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.0, -1.0);
    m = collide(circle(0.5), at(1.3, 0.4), g, at(0.0, 0.0), kSpec);  // beyond the end: distance 0.5
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.6, 0.8, 1e-9);
    CHECK(m.points[0].separation == doctest::Approx(0.0).scale(1.0));
    m = collide(g, at(0.0, 0.0), circle(0.5), at(0.3, 0.49), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.0, -1.0);
    CHECK(collide(circle(0.5), at(0.3, 0.6), g, at(0.0, 0.0), kSpec).count == 0);
}

TEST_CASE("polygon pairs: hexagon on a box, box against a box side, slightly tilted resting box") {
    const double side = 0.5, h = side * std::sqrt(3.0) / 2.0;
    Polygon hex;
    REQUIRE(makePolygon({{side, 0}, {side / 2, h}, {-side / 2, h}, {-side, 0}, {-side / 2, -h}, {side / 2, -h}}, &hex)
                .empty());
    Manifold2 m = collide(toShape(hex), at(0.0, 0.5 + h - 0.004), box(2.0, 0.5), at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 2);
    checkVec(m.normal, 0.0, 1.0);
    CHECK(m.points[0].separation == doctest::Approx(-0.004).epsilon(1e-9));
    CHECK(std::fabs(m.points[0].point.x) == doctest::Approx(side / 2).epsilon(1e-9));

    // A box pushed into a wall from the left: normal (-1, 0) (from the wall B towards the box A).
    m = collide(box(0.5, 0.5), at(-0.99, 0.2), box(0.5, 3.0), at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 2);
    checkVec(m.normal, -1.0, 0.0);
    CHECK(m.points[1].separation == doctest::Approx(-0.01).epsilon(1e-9));

    // A box tilted by 1e-3 rad resting on a box: 2 points with separations that differ by 1e-3 m.
    m = collide(box(0.5, 0.5), at(0.0, 1.0, 1e-3), box(5.0, 0.5), at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 2);
    CHECK(std::fabs(m.points[0].separation - m.points[1].separation) == doctest::Approx(1e-3).epsilon(1e-3));
    CHECK(lengthSquared(m.normal) == doctest::Approx(1.0).epsilon(1e-15));

    // A box balanced on the top of a vertical segment (a pole): one point at the pole's tip.
    m = collide(box(0.5, 0.5), at(0.2, 1.499), segment({0.0, 0.0}, {0.0, 1.0}), at(0.0, 0.0), kSpec);
    REQUIRE(m.count == 1);
    checkVec(m.normal, 0.0, 1.0);
    checkVec(m.points[0].point, 0.0, 0.9995, 1e-9);
    CHECK(m.points[0].separation == doctest::Approx(-0.001).epsilon(1e-9));
}

TEST_CASE("broadphase: small cases") {
    const std::vector<Aabb2> boxes = {
        {{0, 0}, {1, 1}},  // 0
        {{1, 1}, {2, 2}},  // 1 touches 0 at a corner
        {{5, 5}, {6, 6}},  // 2 alone
        {{0.5, 0.5}, {0.6, 0.6}},  // 3 inside 0
        {{0, 0}, {1, 1}},  // 4 static, equal to 0
        {{0.5, -1}, {0.7, 3}},  // 5 static, crosses 0 and 3 (not 1)
        {{std::numeric_limits<double>::quiet_NaN(), 0}, {1, 1}},  // 6 invalid
        {{3, 3}, {2, 2}},  // 7 inverted: invalid
    };
    const std::vector<std::uint8_t> isStatic = {0, 0, 0, 0, 1, 1, 0, 0};
    const std::vector<std::pair<int, int>> expected = {{0, 1}, {0, 3}, {0, 4}, {0, 5}, {1, 4}, {3, 4}, {3, 5}};
    CHECK(findPairs(boxes, isStatic) == expected);
    CHECK(findPairs(boxes, {}).size() == expected.size() + 1);  // 4-5 too when nothing is static
    CHECK(findPairs({}, {}).empty());
    CHECK_THROWS_AS(findPairs(boxes, {0, 1}), std::invalid_argument);
}

TEST_CASE("broadphase: 2000 random boxes, sort-and-sweep equals brute force") {
    std::uint64_t state = 0x2545F4914F6CDD1Dull;
    auto next = [&]() {  // Knuth's MMIX linear congruential generator, top 53 bits as a double in [0, 1)
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
    };
    const int n = 2000;
    std::vector<Aabb2> boxes(n);
    std::vector<std::uint8_t> isStatic(n);
    for (int i = 0; i < n; ++i) {
        Vec2 lo{100.0 * next(), 100.0 * next()};
        if (i % 7 == 3) lo.x = boxes[i - 3].lower.x;  // exact ties in the sort key
        const Vec2 size{0.2 + 2.0 * next(), 0.2 + 2.0 * next()};
        boxes[i] = {lo, lo + size};
        isStatic[i] = next() < 0.2 ? 1 : 0;
    }
    std::vector<std::pair<int, int>> brute;
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b)
            if (!(isStatic[a] && isStatic[b]) && overlaps(boxes[a], boxes[b])) brute.push_back({a, b});
    const std::vector<std::pair<int, int>> pairs = findPairs(boxes, isStatic);
    CHECK(pairs.size() > 1000);
    CHECK(pairs == brute);
    // Swept in chunks (as the step does on its threads), here run last chunk first: the same pairs.
    int calls = 0;
    const ChunkRunner backwards = [&](int chunks, const std::function<void(int)>& fn) {
        calls = chunks;
        for (int c = chunks - 1; c >= 0; --c) fn(c);
    };
    CHECK(findPairs(boxes, isStatic, nullptr, &backwards) == brute);
    CHECK(calls == 15);  // 2000 boxes in chunks of about 128 sorted boxes
}

TEST_CASE("broadphase: the pairs' counting sort orders as std::sort does, with a ground met by every box, sorted or not") {
    std::uint64_t state = 0x9E3779B97F4A7C15ull;
    auto next = [&](int n) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return int((state >> 33) % std::uint64_t(n));
    };
    for (int size : {0, 1, 63, 64, 65, 3000}) {
        CAPTURE(size);
        std::vector<std::pair<int, int>> pairs;
        for (int i = 0; i < size; ++i) {
            const int b = 1 + next(5000);
            pairs.push_back(i % 3 == 0 ? std::make_pair(0, b) : std::make_pair(next(b), b));  // a < b; a third on box 0
        }
        std::sort(pairs.begin(), pairs.end());
        pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
        std::vector<std::pair<int, int>> shuffled = pairs;
        std::reverse(shuffled.begin(), shuffled.end());
        for (std::size_t i = 1; i < shuffled.size(); i += 2) std::swap(shuffled[i], shuffled[i / 2]);
        sortPairs(shuffled);
        CHECK(shuffled == pairs);
        std::vector<std::pair<int, int>> sorted = pairs;  // already sorted: left as it is
        sortPairs(sorted);
        CHECK(sorted == pairs);
        if (pairs.size() >= 2) {  // sorted but for the last two
            std::vector<std::pair<int, int>> nearly = pairs;
            std::swap(nearly[nearly.size() - 1], nearly[nearly.size() - 2]);
            sortPairs(nearly);
            CHECK(nearly == pairs);
        }
    }
}

TEST_CASE("broadphase: a sweep cache kept between calls changes the cost, never the pairs") {
    std::uint64_t state = 0x9E3779B97F4A7C15ull;
    auto next = [&]() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
    };
    const int n = 600;
    std::vector<Aabb2> boxes(n);
    std::vector<std::uint8_t> isStatic(n, 0);
    for (int i = 0; i < n; ++i) {
        const Vec2 lo{50.0 * next(), 50.0 * next()};
        boxes[std::size_t(i)] = {lo, lo + Vec2{0.5 + next(), 0.5 + next()}};
    }
    SweepCache cache;
    for (int call = 0; call < 40; ++call) {
        CHECK(findPairs(boxes, isStatic, &cache) == findPairs(boxes, isStatic));
        CHECK(cache.order.size() == std::size_t(n));
        // Most boxes move a little (the cache's order stays nearly sorted); every 10th call they are shuffled (the
        // insertion sort runs out of moves and std::sort finishes); some become invalid, some ties appear.
        for (int i = 0; i < n; ++i) {
            Aabb2& b = boxes[std::size_t(i)];
            const double dx = call % 10 == 9 ? 40.0 * (next() - 0.5) : 0.05 * (next() - 0.5);
            b.lower.x += dx;
            b.upper.x += dx;
            if (i % 50 == call % 50) b.lower.x = b.upper.x + 1.0;  // invalid this call
            else if (b.lower.x > b.upper.x) b.lower.x = b.upper.x - 0.7;
            if (i % 97 == 5 && i > 0) b.lower.x = boxes[std::size_t(i - 1)].lower.x;  // an exact tie
        }
    }
    // Every box valid again, then left in place: the later calls find the cache's order sorted, move nothing and
    // keep that order as it is, and it must be the boxes' sorted order.
    for (Aabb2& b : boxes)
        if (b.lower.x > b.upper.x) b.lower.x = b.upper.x - 0.7;
    for (int call = 0; call < 3; ++call) {
        CHECK(findPairs(boxes, isStatic, &cache) == findPairs(boxes, isStatic));
        REQUIRE(cache.order.size() == std::size_t(n));
        for (int k = 1; k < n; ++k) {
            const int i = cache.order[std::size_t(k - 1)], j = cache.order[std::size_t(k)];
            const double xi = boxes[std::size_t(i)].lower.x, xj = boxes[std::size_t(j)].lower.x;
            CHECK((xi < xj || (xi == xj && i < j)));
        }
    }
    std::vector<Aabb2> fewer(boxes.begin(), boxes.begin() + n / 2);  // another count: the cache starts over
    CHECK(findPairs(fewer, {}, &cache) == findPairs(fewer, {}));
    CHECK(cache.order.size() == std::size_t(n / 2));
}

TEST_CASE("broadphase: a crowded layout goes to the grid, with the sweep's pairs") {
    // Rows of pyramids of touching unit boxes (Box2D v3's many-pyramids layout): every box meets every row's boxes
    // in x, past the sweep's budget of 16 per box, so the pairs come from the grid.
    auto brute = [](const std::vector<Aabb2>& boxes, const std::vector<std::uint8_t>& isStatic) {
        std::vector<std::pair<int, int>> out;
        for (int a = 0; a < int(boxes.size()); ++a)
            for (int b = a + 1; b < int(boxes.size()); ++b) {
                const bool bothStatic = !isStatic.empty() && isStatic[std::size_t(a)] && isStatic[std::size_t(b)];
                const Aabb2& A = boxes[std::size_t(a)];
                const Aabb2& B = boxes[std::size_t(b)];
                const bool valid = A.lower.x <= A.upper.x && A.lower.y <= A.upper.y && B.lower.x <= B.upper.x &&
                                   B.lower.y <= B.upper.y;
                if (valid && !bothStatic && overlaps(A, B)) out.push_back({a, b});
            }
        return out;
    };
    std::vector<Aabb2> boxes;
    std::vector<std::uint8_t> isStatic;
    for (int row = 0; row < 6; ++row) {
        boxes.push_back({{-40.0, 11.0 * row - 0.1}, {40.0, 11.0 * row}});  // a ground segment per row, static
        isStatic.push_back(1);
        for (int column = 0; column < 5; ++column)
            for (int level = 0; level < 10; ++level)
                for (int k = 0; k < 10 - level; ++k) {
                    const double x = -30.0 + 11.0 * column + 0.5 * level + k, y = 11.0 * row + level;
                    boxes.push_back({{x, y}, {x + 1.0, y + 1.0}});  // touching on every side
                    isStatic.push_back(0);
                }
    }
    boxes[7].lower.x = boxes[7].upper.x + 1.0;  // one invalid box
    const std::vector<std::pair<int, int>> expected = brute(boxes, isStatic);
    REQUIRE(expected.size() > 3000);
    SweepCache cache;
    CHECK(findPairs(boxes, isStatic, &cache) == expected);
    CHECK(cache.gridCalls == 64);  // the sweep ran past its budget; the next 64 calls go to the grid directly
    CHECK(findPairs(boxes, isStatic, &cache) == expected);
    CHECK(cache.gridCalls == 63);
    const ChunkRunner backwards = [](int chunks, const std::function<void(int)>& fn) {
        for (int c = chunks - 1; c >= 0; --c) fn(c);
    };
    CHECK(findPairs(boxes, isStatic, nullptr, &backwards) == expected);  // the chunked sweep gives way too
    CHECK(findPairs(boxes, {}) == brute(boxes, {}));                     // the grounds pair with each other too

    SUBCASE("boxes the grid cannot place are tested against every box") {
        // Far out (beyond 2^30 cells) and long (more cells than the grid allows per box), a few of each.
        for (int k = 0; k < 5; ++k) {
            boxes.push_back({{1e300, 0.0}, {1e300, 1.0}});
            boxes.push_back({{-1e300, 3.0 + k}, {1e300, 3.5 + k}});
            boxes.push_back({{-1e12, -1e12}, {1e12, 1e12}});
            for (int i = 0; i < 3; ++i) isStatic.push_back(k == 2 ? 1 : 0);
        }
        SweepCache fresh;
        CHECK(findPairs(boxes, isStatic, &fresh) == brute(boxes, isStatic));
        CHECK(fresh.gridCalls == 64);
    }
    SUBCASE("too many such boxes, or boxes of no extent: the sweep answers") {
        for (int k = 0; k < 70; ++k) {  // more than the grid tests against every box
            boxes.push_back({{-1e300, 0.5 * k}, {1e300, 0.5 * k + 0.1}});
            isStatic.push_back(0);
        }
        SweepCache fresh;
        CHECK(findPairs(boxes, isStatic, &fresh) == brute(boxes, isStatic));
        CHECK(fresh.gridCalls == 0);
        std::vector<Aabb2> points;  // a column of 3000 points: crowded in x, median extent 0
        for (int i = 0; i < 3000; ++i) points.push_back({{1.0, 0.001 * (i / 2)}, {1.0, 0.001 * (i / 2)}});
        SweepCache column;
        CHECK(findPairs(points, {}, &column) == brute(points, {}));
        CHECK(column.gridCalls == 0);
    }
}

}  // TEST_SUITE
