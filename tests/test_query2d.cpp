// tests/test_query2d.cpp — 2D scene queries: closed-form ray casts and overlaps on every shape type, the total
// order of the answers, the query tree against brute force on seeded random scenes (also after steps, creation,
// destruction and restore), and the exact tests against independent ones (point sampling along rays, vertex
// containment and edge crossings for overlaps).
#include "query_checks.h"

#include "query2d.h"
#include "world2d.h"

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

using namespace unison;
using query_checks::checkSameRefs;
using query_checks::Rng;

namespace {

// splitmix64: the same sequence on every platform.

Shape2 circle(Vec2 c, double r) {
    Circle k;
    REQUIRE(makeCircle(c, r, &k).empty());
    return toShape(k);
}

Shape2 box(double hx, double hy, Vec2 c = {}, double angle = 0.0) {
    Polygon p;
    REQUIRE(makeBox(hx, hy, c, angle, &p).empty());
    return toShape(p);
}

Shape2 segment(Vec2 a, Vec2 b) {
    Segment s;
    REQUIRE(makeSegment(a, b, &s).empty());
    return toShape(s);
}

// A random convex polygon: 3..8 points on an ellipse at increasing angles.
Shape2 randomPolygon(Rng& rng) {
    const int n = 3 + rng.below(6);
    const double rx = rng.uniform(0.2, 1.0), ry = rng.uniform(0.2, 1.0);
    std::vector<Vec2> pts;
    for (int i = 0; i < n; ++i) {
        const Rot2 q = makeRot((double(i) + rng.uniform(0.1, 0.9)) * 2.0 * 3.141592653589793 / n);
        pts.push_back({rx * q.c, ry * q.s});
    }
    Polygon p;
    REQUIRE(makePolygon(pts, &p).empty());
    return toShape(p);
}

Shape2 randomShape(Rng& rng, bool allowSegment) {
    switch (rng.below(allowSegment ? 4 : 3)) {
        // The draws are sequenced (function arguments are evaluated in an unspecified order: GCC and clang differ).
        case 0: {
            const Vec2 c{rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)};
            return circle(c, rng.uniform(0.1, 0.8));
        }
        case 1: {
            const double hx = rng.uniform(0.1, 0.8), hy = rng.uniform(0.1, 0.8);
            const Vec2 c{rng.uniform(-0.3, 0.3), 0.0};
            return box(hx, hy, c, rng.uniform(-1, 1));
        }
        case 2: return randomPolygon(rng);
        default: {
            const Vec2 a{rng.uniform(-1, 1), rng.uniform(-1, 1)};
            return segment(a, {rng.uniform(-1, 1), rng.uniform(1.1, 2)});
        }
    }
}

// Strictly inside a solid shape (circle, polygon) placed by xf; never for a segment.
bool inside(const Shape2& s, const Transform2& xf, Vec2 w) {
    const Vec2 p = invTransformPoint(xf, w);
    if (s.type == ShapeType::circle) return lengthSquared(p - s.circle.center) < s.circle.radius * s.circle.radius;
    if (s.type == ShapeType::segment) return false;
    for (int i = 0; i < s.polygon.count; ++i)
        if (!(dot(s.polygon.normals[std::size_t(i)], p - s.polygon.vertices[std::size_t(i)]) < 0.0)) return false;
    return true;
}

// A world of n random bodies (some static with segments), moving without gravity so that steps change poses.
World2 randomWorld(Rng& rng, int n) {
    WorldDef2 def;
    def.gravity = {0.0, 0.0};
    World2 w(def);
    for (int i = 0; i < n; ++i) {
        BodyDef2 bd;
        const bool isStatic = rng.below(5) == 0;
        bd.type = isStatic ? BodyType::staticBody : BodyType::dynamicBody;
        bd.position = {rng.uniform(-10, 10), rng.uniform(-10, 10)};
        bd.angle = rng.uniform(-3, 3);
        bd.linearVelocity = {rng.uniform(-3, 3), rng.uniform(-3, 3)};
        bd.angularVelocity = rng.uniform(-2, 2);
        std::vector<Shape2> shapes{randomShape(rng, isStatic)};
        if (rng.below(3) == 0) shapes.push_back(randomShape(rng, isStatic));
        std::string error;
        REQUIRE_MESSAGE(!w.createBody(bd, shapes, &error).isNull(), error);
    }
    return w;
}

Transform2 transformOf(const World2& w, BodyId id) { return {w.state(id)->position, w.state(id)->rotation}; }

// Brute force: every shape of every body, sorted by the same total key.
std::vector<RayHit2> bruteRay(const World2& w, Vec2 o, Vec2 d) {
    std::vector<RayHit2> out;
    for (BodyId id : w.bodyIds()) {
        const auto& shapes = w.info(id)->shapes;
        for (int k = 0; k < int(shapes.size()); ++k) {
            RayHit2 h;
            if (!rayCastShape(shapes[std::size_t(k)], transformOf(w, id), o, d, &h.fraction, &h.normal)) continue;
            h.body = id;
            h.shape = k;
            h.point = o + h.fraction * d;
            out.push_back(h);
        }
    }
    std::sort(out.begin(), out.end(), rayHitBefore<RayHit2>);
    return out;
}

template <class Pred>
std::vector<ShapeRef> bruteOverlap(const World2& w, Pred pred) {
    std::vector<ShapeRef> out;
    for (BodyId id : w.bodyIds()) {
        const auto& shapes = w.info(id)->shapes;
        for (int k = 0; k < int(shapes.size()); ++k)
            if (pred(shapes[std::size_t(k)], transformOf(w, id))) out.push_back({id, k});
    }
    std::sort(out.begin(), out.end(), shapeRefBefore);
    return out;
}

void checkSameHits(const std::vector<RayHit2>& a, const std::vector<RayHit2>& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        CHECK(a[i].body == b[i].body);
        CHECK(a[i].shape == b[i].shape);
        CHECK(a[i].fraction == b[i].fraction);  // bit for bit: the same exact test on the same inputs
        CHECK(a[i].normal.x == b[i].normal.x);
        CHECK(a[i].normal.y == b[i].normal.y);
    }
}

// All queries of a world against brute force, with `count` random rays, boxes and query shapes. Returns the number of ray hits and shape overlaps found (so that callers can see the checks were not vacuous).
std::pair<int, int> checkAgainstBruteForce(const World2& w, Rng& rng, int count) {
    int hits = 0, overlapCount = 0;
    for (int i = 0; i < count; ++i) {
        const Vec2 o{rng.uniform(-14, 14), rng.uniform(-14, 14)};
        const Vec2 d{rng.uniform(-25, 25), rng.uniform(-25, 25)};
        const std::vector<RayHit2> all = w.rayCastAll(o, d);
        checkSameHits(all, bruteRay(w, o, d));
        RayHit2 closest;
        REQUIRE(w.rayCastClosest(o, d, &closest) == !all.empty());
        if (!all.empty()) checkSameHits({closest}, {all[0]});
        hits += int(all.size());

        const Vec2 lo{rng.uniform(-12, 10), rng.uniform(-12, 10)};
        const Aabb2 q{lo, lo + Vec2{rng.uniform(0, 4), rng.uniform(0, 4)}};
        checkSameRefs(w.overlapAabb(q), bruteOverlap(w, [&](const Shape2& s, const Transform2& xf) {
                          return overlaps(computeAabb(s, xf), q);
                      }));

        const Shape2 qs = randomShape(rng, true);
        const Transform2 qxf{{rng.uniform(-11, 11), rng.uniform(-11, 11)}, makeRot(rng.uniform(-3, 3))};
        const std::vector<ShapeRef> found = w.overlapShape(qs, qxf);
        checkSameRefs(found, bruteOverlap(w, [&](const Shape2& s, const Transform2& xf) {
                          return shapesOverlap(qs, qxf, s, xf);
                      }));
        overlapCount += int(found.size());
    }
    return {hits, overlapCount};
}

// Placed shape as world vertices (circle: none) for the independent overlap test.
std::vector<Vec2> worldVertices(const Shape2& s, const Transform2& xf) {
    std::vector<Vec2> v;
    if (s.type == ShapeType::polygon)
        for (int i = 0; i < s.polygon.count; ++i) v.push_back(transformPoint(xf, s.polygon.vertices[std::size_t(i)]));
    if (s.type == ShapeType::segment) v = {transformPoint(xf, s.segment.p1), transformPoint(xf, s.segment.p2)};
    return v;
}

// Proper crossing of segments a0-a1 and b0-b1 (each strictly separates the other's end points).
bool properCross(Vec2 a0, Vec2 a1, Vec2 b0, Vec2 b1) {
    const double s1 = cross(a1 - a0, b0 - a0), s2 = cross(a1 - a0, b1 - a0);
    const double s3 = cross(b1 - b0, a0 - b0), s4 = cross(b1 - b0, a1 - b0);
    return ((s1 < 0 && s2 > 0) || (s1 > 0 && s2 < 0)) && ((s3 < 0 && s4 > 0) || (s3 > 0 && s4 < 0));
}

}  // namespace

TEST_SUITE("query2d") {

TEST_CASE("ray casts: closed forms on circle, box, rotated box and segment") {
    double t = 0.0;
    Vec2 n;
    const Shape2 c = circle({}, 1.0);
    REQUIRE(rayCastShape(c, {{2.0, 1.0}, {}}, {-1.0, 1.0}, {6.0, 0.0}, &t, &n));
    CHECK(t == doctest::Approx(2.0 / 6.0));
    CHECK(n.x == doctest::Approx(-1.0));
    CHECK(rayCastShape(c, {{2.0, 1.0}, {}}, {2.5, 1.0}, {6.0, 0.0}, &t, &n));  // starts inside: fraction 0
    CHECK(t == 0.0);
    CHECK(n.x == doctest::Approx(-1.0));
    CHECK_FALSE(rayCastShape(c, {}, {-3.0, 0.0}, {1.9, 0.0}, &t, &n));   // ends short of it
    CHECK_FALSE(rayCastShape(c, {}, {-3.0, 1.5}, {6.0, 0.0}, &t, &n));   // passes above
    CHECK_FALSE(rayCastShape(c, {}, {3.0, 0.0}, {6.0, 0.0}, &t, &n));    // points away
    CHECK_FALSE(rayCastShape(c, {}, {3.0, 0.0}, {0.0, 0.0}, &t, &n));    // zero translation

    // A 2 x 2 box turned by 45 degrees: the edge from (-sqrt2, 0) to (0, sqrt2) is x = y - sqrt2.
    const Shape2 b = box(1.0, 1.0);
    const Transform2 xf{{}, makeRot(3.141592653589793 / 4.0)};
    REQUIRE(rayCastShape(b, xf, {-5.0, 0.5}, {10.0, 0.0}, &t, &n));
    CHECK(t == doctest::Approx((5.5 - std::sqrt(2.0)) / 10.0));
    CHECK(n.x == doctest::Approx(-std::sqrt(0.5)));
    CHECK(n.y == doctest::Approx(std::sqrt(0.5)));
    REQUIRE(rayCastShape(b, {}, {0.0, 5.0}, {0.0, -10.0}, &t, &n));  // from above onto the top face
    CHECK(t == doctest::Approx(0.4));
    CHECK(n.y == doctest::Approx(1.0));

    // A segment is hit from both sides, the normal facing the origin; a ray along it misses.
    const Shape2 s = segment({0.0, -1.0}, {0.0, 1.0});
    REQUIRE(rayCastShape(s, {}, {2.0, 0.5}, {-4.0, 0.0}, &t, &n));
    CHECK(t == doctest::Approx(0.5));
    CHECK(n.x == doctest::Approx(1.0));
    REQUIRE(rayCastShape(s, {}, {-2.0, 0.5}, {4.0, 0.0}, &t, &n));
    CHECK(n.x == doctest::Approx(-1.0));
    CHECK_FALSE(rayCastShape(s, {}, {0.0, -3.0}, {0.0, 6.0}, &t, &n));
}

TEST_CASE("overlaps: closed forms, touching does not count") {
    const Shape2 b = box(1.0, 1.0);
    // A circle at (2, 2) is sqrt(2) from the box's corner.
    CHECK_FALSE(shapesOverlap(circle({2.0, 2.0}, std::sqrt(2.0) - 1e-9), {}, b, {}));
    CHECK(shapesOverlap(circle({2.0, 2.0}, std::sqrt(2.0) + 1e-9), {}, b, {}));
    CHECK(shapesOverlap(circle({0.2, 0.1}, 0.1), {}, b, {}));  // wholly inside
    CHECK_FALSE(shapesOverlap(circle({0.0, 0.0}, 1.0), {}, circle({2.0, 0.0}, 1.0), {}));  // touching
    CHECK(shapesOverlap(circle({0.0, 0.0}, 1.0), {}, circle({1.999, 0.0}, 1.0), {}));
    CHECK_FALSE(shapesOverlap(b, {}, b, {{2.0, 0.0}, {}}));  // boxes sharing an edge
    CHECK(shapesOverlap(b, {}, b, {{1.999, 1.999}, {}}));
    // A box turned by 45 degrees reaches sqrt(2) from its centre.
    CHECK_FALSE(shapesOverlap(b, {{1.0 + std::sqrt(2.0) + 1e-9, 0.0}, makeRot(3.141592653589793 / 4.0)}, b, {}));
    CHECK(shapesOverlap(b, {{1.0 + std::sqrt(2.0) - 1e-9, 0.0}, makeRot(3.141592653589793 / 4.0)}, b, {}));
    // Segments: crossing the interior counts, lying along an edge does not; crossing segments overlap.
    CHECK(shapesOverlap(segment({-3.0, 0.5}, {3.0, 0.5}), {}, b, {}));
    CHECK_FALSE(shapesOverlap(segment({-3.0, 1.0}, {3.0, 1.0}), {}, b, {}));
    CHECK(shapesOverlap(segment({-1.0, -1.0}, {1.0, 1.0}), {}, segment({-1.0, 1.0}, {1.0, -1.0}), {}));
    CHECK_FALSE(shapesOverlap(segment({0.0, 0.0}, {1.0, 0.0}), {}, segment({0.5, 0.0}, {2.0, 0.0}), {}));
    CHECK(shapesOverlap(circle({0.0, 0.5}, 0.6), {}, segment({-1.0, 0.0}, {1.0, 0.0}), {}));
    CHECK_FALSE(shapesOverlap(circle({0.0, 0.5}, 0.5), {}, segment({-1.0, 0.0}, {1.0, 0.0}), {}));
}

TEST_CASE("world queries: order by fraction, then body slot, then shape index") {
    World2 w(WorldDef2{});
    BodyDef2 bd;
    bd.type = BodyType::staticBody;
    bd.position = {5.0, 0.0};
    const BodyId first = w.createBody(bd, {circle({}, 1.0)});
    const BodyId doomed = w.createBody(bd, {box(0.5, 0.5)});
    bd.position = {2.0, 0.0};
    const BodyId near = w.createBody(bd, {box(0.5, 0.5), circle({}, 0.5)});  // two shapes hit at one fraction
    REQUIRE(w.destroyBody(doomed));
    bd.position = {5.0, 0.0};
    const BodyId twin = w.createBody(bd, {circle({}, 1.0)});  // reuses the freed slot 2: between first and near
    REQUIRE(twin.index1 == 2);
    const std::vector<RayHit2> hits = w.rayCastAll({0.0, 0.0}, {10.0, 0.0});
    REQUIRE(hits.size() == 4);
    CHECK(hits[0].body == near);
    CHECK(hits[0].shape == 0);
    CHECK(hits[1].body == near);
    CHECK(hits[1].shape == 1);
    CHECK(hits[0].fraction == hits[1].fraction);
    CHECK(hits[0].fraction == doctest::Approx(0.15));
    CHECK(hits[2].body == first);  // equal fractions: slot 1 before slot 2
    CHECK(hits[3].body == twin);
    CHECK(hits[2].fraction == hits[3].fraction);
    CHECK(hits[2].point.x == doctest::Approx(4.0));
    RayHit2 closest;
    REQUIRE(w.rayCastClosest({0.0, 0.0}, {10.0, 0.0}, &closest));
    CHECK(closest.body == near);
    CHECK(closest.shape == 0);
    // The other way round the far circles come first.
    CHECK(w.rayCastAll({10.0, 0.0}, {-10.0, 0.0})[0].body == first);

    const std::vector<ShapeRef> refs = w.overlapAabb({{1.0, -0.1}, {4.5, 0.1}});
    REQUIRE(refs.size() == 4);
    CHECK(refs[0].body == first);
    CHECK(refs[1].body == twin);
    CHECK(refs[2].body == near);
    CHECK(refs[3].shape == 1);
    CHECK(w.overlapShape(circle({}, 0.2), {{3.0, 3.0}, {}}).empty());
    CHECK(w.overlapShape(circle({}, 0.2), {{3.9, 0.0}, {}}).size() == 2);

    // Bad arguments give no answer.
    CHECK_FALSE(w.rayCastClosest({0.0, 0.0}, {0.0, 0.0}, &closest));
    CHECK(w.rayCastAll({std::nan(""), 0.0}, {1.0, 0.0}).empty());
    CHECK(w.overlapAabb({{std::nan(""), 0.0}, {1.0, 1.0}}).empty());
}

TEST_CASE("random scenes: the tree gives the brute-force answers, also after steps, changes and restore") {
    Rng rng{20240611};
    query_checks::Tally tally;  // checks at the end that the scenes were dense enough
    for (int scene = 0; scene < 4; ++scene) {
        World2 w = randomWorld(rng, 80);
        tally.add(checkAgainstBruteForce(w, rng, 120));
        for (int s = 0; s < 5; ++s) w.step();  // poses change: the tree must follow
        tally.add(checkAgainstBruteForce(w, rng, 60));
        const std::vector<std::uint8_t> snap = w.snapshot();
        const std::vector<BodyId> ids = w.bodyIds();
        for (int k = 0; k < 10; ++k) w.destroyBody(ids[std::size_t(rng.below(int(ids.size())))]);
        tally.add(checkAgainstBruteForce(w, rng, 40));
        REQUIRE(w.restore(snap.data(), snap.size()));
        tally.add(checkAgainstBruteForce(w, rng, 40));
    }
}

TEST_CASE("queries from several threads at once after a step give the one-thread answers") {
    Rng rng{4242};
    World2 w = randomWorld(rng, 120);
    std::vector<std::pair<Vec2, Vec2>> rays;
    for (int i = 0; i < 200; ++i)
        rays.push_back({{rng.uniform(-14, 14), rng.uniform(-14, 14)}, {rng.uniform(-25, 25), rng.uniform(-25, 25)}});
    for (int round = 0; round < 3; ++round) {
        w.step();  // the tree is stale: the first query of each thread races to rebuild it
        std::vector<std::vector<RayHit2>> answers(4);
        std::vector<std::thread> threads;
        for (int t = 0; t < 4; ++t)
            threads.emplace_back([&, t] {
                for (const auto& [o, d] : rays)
                    for (const RayHit2& h : w.rayCastAll(o, d)) answers[std::size_t(t)].push_back(h);
            });
        for (std::thread& t : threads) t.join();
        std::vector<RayHit2> expected;
        for (const auto& [o, d] : rays)
            for (const RayHit2& h : bruteRay(w, o, d)) expected.push_back(h);
        CHECK(expected.size() > rays.size());
        for (const auto& a : answers) checkSameHits(a, expected);
    }
}

TEST_CASE("ray casts agree with point sampling along the ray") {
    Rng rng{7};
    int hitsChecked = 0;
    for (int i = 0; i < 3000; ++i) {
        const Shape2 s = randomShape(rng, true);
        const Transform2 xf{{rng.uniform(-1, 1), rng.uniform(-1, 1)}, makeRot(rng.uniform(-3, 3))};
        const Vec2 o{rng.uniform(-3, 3), rng.uniform(-3, 3)};
        const Vec2 d{rng.uniform(-6, 6), rng.uniform(-6, 6)};
        double t = 0.0;
        Vec2 n;
        const bool hit = rayCastShape(s, xf, o, d, &t, &n);
        if (s.type == ShapeType::segment) continue;  // no interior to sample
        if (!hit) {
            for (int k = 0; k <= 400; ++k) REQUIRE_FALSE(inside(s, xf, o + (k / 400.0) * d));
            continue;
        }
        CHECK(std::fabs(length(n) - 1.0) < 1e-12);
        if (t == 0.0) {
            CHECK(inside(s, xf, o + 1e-9 * d));  // started inside (or on the surface going in)
            continue;
        }
        ++hitsChecked;
        CHECK(dot(n, d) <= 0.0);
        // Everything before the hit is outside; just past it (unless the ray only grazes) is inside.
        for (int k = 0; k < 400; ++k) REQUIRE_FALSE(inside(s, xf, o + (t * k / 400.0 * (1.0 - 1e-9)) * d));
        const double grazing = -dot(n, d) / length(d);
        if (grazing > 1e-3) CHECK(inside(s, xf, o + (t + 1e-7) * d));
    }
    CHECK(hitsChecked > 150);
}

TEST_CASE("overlaps agree with vertex containment and edge crossings") {
    Rng rng{99};
    int yes = 0, no = 0;
    for (int i = 0; i < 6000; ++i) {
        Shape2 a = randomShape(rng, true), b = randomShape(rng, true);
        if (a.type == ShapeType::circle || b.type == ShapeType::circle) continue;  // closed forms above
        const Transform2 xa{{rng.uniform(-1, 1), rng.uniform(-1, 1)}, makeRot(rng.uniform(-3, 3))};
        const Transform2 xb{{rng.uniform(-1, 1), rng.uniform(-1, 1)}, makeRot(rng.uniform(-3, 3))};
        const std::vector<Vec2> va = worldVertices(a, xa), vb = worldVertices(b, xb);
        bool expected = false;
        for (Vec2 v : va) expected = expected || inside(b, xb, v);
        for (Vec2 v : vb) expected = expected || inside(a, xa, v);
        const std::size_t ea = a.type == ShapeType::segment ? 1 : va.size();
        const std::size_t eb = b.type == ShapeType::segment ? 1 : vb.size();
        for (std::size_t p = 0; p < ea; ++p)
            for (std::size_t q = 0; q < eb; ++q)
                expected = expected || properCross(va[p], va[(p + 1) % va.size()], vb[q], vb[(q + 1) % vb.size()]);
        CHECK(shapesOverlap(a, xa, b, xb) == expected);
        CHECK(shapesOverlap(b, xb, a, xa) == expected);
        (expected ? yes : no) += 1;
    }
    CHECK(yes > 500);
    CHECK(no > 500);
}

}  // TEST_SUITE
