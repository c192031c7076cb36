// tests/test_query3d.cpp — 3D scene queries: closed-form ray casts and overlaps on sphere, box, hull, plane and mesh,
// the total order of the answers, the query tree against brute force on seeded random scenes (also after steps,
// destruction and restore), and the exact tests against independent ones (analytic point containment sampled along
// rays; vertex containment and edge-face crossings for overlaps of polytopes, meshes included).
#include "query_checks.h"

#include "query3d.h"
#include "world3d.h"

#include <algorithm>
#include <cmath>
#include <vector>

using namespace unison;
using query_checks::checkSameRefs;
using query_checks::Rng;

namespace {


// Braces: the draws happen left to right on every compiler (the order of function arguments is unspecified, and
// GCC and clang differ, which gave the two builds different random scenes).
Vec3 vec(Rng& rng, double lo, double hi) {
    return Vec3{rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi)};
}

Quat rotation(Rng& rng) {
    return normalized(Quat{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)});
}

Shape3 sphere(double r, const Vec3& c = Vec3::Zero()) {
    Shape3 s;
    REQUIRE(makeSphere(c, r, &s).empty());
    return s;
}

Shape3 box(const Vec3& h, const Vec3& c = Vec3::Zero()) {
    Shape3 s;
    REQUIRE(makeBox(h, c, &s).empty());
    return s;
}

Shape3 plane(const Vec3& n, double offset) {
    Shape3 s;
    REQUIRE(makePlane(n, offset, &s).empty());
    return s;
}

// The octahedron |x|/a + |y|/b + |z|/c <= 1 as a closed mesh (convex, so it doubles as a polytope in the checks).
Shape3 octahedron(const Vec3& size) {
    const std::vector<Vec3> v{Vec3(size.x(), 0, 0), Vec3(-size.x(), 0, 0), Vec3(0, size.y(), 0),
                              Vec3(0, -size.y(), 0), Vec3(0, 0, size.z()), Vec3(0, 0, -size.z())};
    std::vector<std::array<int, 3>> t;
    for (int sx = 0; sx < 2; ++sx)
        for (int sy = 0; sy < 2; ++sy)
            for (int sz = 0; sz < 2; ++sz) {
                std::array<int, 3> tri{sx, 2 + sy, 4 + sz};
                if ((sx + sy + sz) % 2 == 1) std::swap(tri[1], tri[2]);
                t.push_back(tri);
            }
    Shape3 s;
    REQUIRE(makeMesh(v, t, &s).empty());
    return s;
}

// The cube [-h, h]^3 as a closed mesh of 12 triangles.
Shape3 cubeMesh(double h) {
    std::vector<Vec3> v;
    for (int i = 0; i < 8; ++i) v.push_back(Vec3((i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h));
    const std::vector<std::array<int, 3>> t{{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                            {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    Shape3 s;
    REQUIRE(makeMesh(v, t, &s).empty());
    return s;
}

Shape3 randomHull(Rng& rng) {
    const Vec3 axes = vec(rng, 0.2, 0.9);
    std::vector<Vec3> pts;
    for (int i = 0; i < 12; ++i) {
        Vec3 d = vec(rng, -1, 1);
        d = d / d.norm();
        pts.push_back(Vec3(axes.x() * d.x(), axes.y() * d.y(), axes.z() * d.z()));
    }
    Shape3 s;
    REQUIRE(makeHull(pts, &s).empty());
    return s;
}

Shape3 randomConvex(Rng& rng) {
    switch (rng.below(3)) {
        case 0: {  // sequenced draws (see vec())
            const double r = rng.uniform(0.1, 0.8);
            return sphere(r, vec(rng, -0.2, 0.2));
        }
        case 1: {
            const Vec3 half = vec(rng, 0.1, 0.8);
            return box(half, vec(rng, -0.2, 0.2));
        }
        default: return randomHull(rng);
    }
}

Shape3 randomShape(Rng& rng) { return rng.below(4) == 0 ? octahedron(vec(rng, 0.3, 1.2)) : randomConvex(rng); }

Transform3 randomTransform(Rng& rng, double spread) { return {vec(rng, -spread, spread), toMatrix(rotation(rng))}; }

// Strictly inside, from each shape's own definition (octahedron meshes analytically).
bool inside(const Shape3& s, const Transform3& xf, const Vec3& w) {
    const Vec3 p = invTransformPoint(xf, w);
    switch (s.type) {
        case ShapeType3::sphere: return (p - s.center).squaredNorm() < s.radius * s.radius;
        case ShapeType3::plane: return s.normal.dot(p) < s.offset;
        case ShapeType3::mesh: {
            const auto& v = s.mesh->vertices;
            return std::fabs(p.x()) / v[0].x() + std::fabs(p.y()) / v[2].y() + std::fabs(p.z()) / v[4].z() < 1.0;
        }
        default:
            for (const auto& f : s.poly->faces)
                if (!(f.normal.dot(p) < f.offset)) return false;
            return true;
    }
}

World3 randomWorld(Rng& rng, int n) {
    WorldDef3 def;
    def.gravity = Vec3::Zero();
    World3 w(def);
    BodyDef3 ground;
    ground.type = BodyType::staticBody;
    REQUIRE(!w.createBody(ground, {plane(Vec3(0, 1, 0), -9.0)}).isNull());
    for (int i = 0; i < n; ++i) {
        BodyDef3 bd;
        bd.type = rng.below(5) == 0 ? BodyType::staticBody : BodyType::dynamicBody;
        bd.position = vec(rng, -5, 5);
        bd.orientation = rotation(rng);
        bd.linearVelocity = vec(rng, -3, 3);
        bd.angularVelocity = vec(rng, -2, 2);
        std::vector<Shape3> shapes{randomShape(rng)};
        if (rng.below(3) == 0) shapes.push_back(randomShape(rng));
        std::string error;
        REQUIRE_MESSAGE(!w.createBody(bd, shapes, &error).isNull(), error);
    }
    return w;
}

std::vector<RayHit3> bruteRay(const World3& w, const Vec3& o, const Vec3& d) {
    std::vector<RayHit3> out;
    for (BodyId id : w.bodyIds()) {
        const auto& shapes = w.info(id)->shapes;
        for (int k = 0; k < int(shapes.size()); ++k) {
            RayHit3 h;
            if (!rayCastShape(shapes[std::size_t(k)], w.transform(id), o, d, &h.fraction, &h.normal)) continue;
            h.body = id;
            h.shape = k;
            out.push_back(h);
        }
    }
    std::sort(out.begin(), out.end(), rayHitBefore<RayHit3>);
    return out;
}

template <class Pred>
std::vector<ShapeRef> bruteOverlap(const World3& w, Pred pred) {
    std::vector<ShapeRef> out;
    for (BodyId id : w.bodyIds()) {
        const auto& shapes = w.info(id)->shapes;
        for (int k = 0; k < int(shapes.size()); ++k)
            if (pred(shapes[std::size_t(k)], w.transform(id))) out.push_back({id, k});
    }
    std::sort(out.begin(), out.end(), shapeRefBefore);
    return out;
}

void checkSameHits(const std::vector<RayHit3>& a, const std::vector<RayHit3>& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        CHECK(a[i].body == b[i].body);
        CHECK(a[i].shape == b[i].shape);
        CHECK(a[i].fraction == b[i].fraction);
        CHECK(a[i].normal == b[i].normal);
    }
}

// Returns the number of ray hits and shape overlaps found (so that callers can see the checks were not vacuous).
std::pair<int, int> checkAgainstBruteForce(const World3& w, Rng& rng, int count) {
    int hits = 0, overlapCount = 0;
    for (int i = 0; i < count; ++i) {
        const Vec3 o = vec(rng, -8, 8), d = vec(rng, -16, 16);
        const std::vector<RayHit3> all = w.rayCastAll(o, d);
        checkSameHits(all, bruteRay(w, o, d));
        RayHit3 closest;
        REQUIRE(w.rayCastClosest(o, d, &closest) == !all.empty());
        if (!all.empty()) checkSameHits({closest}, {all[0]});
        hits += int(all.size());

        const Vec3 lo = vec(rng, -6, 5);
        const Aabb3 q{lo, lo + vec(rng, 0, 4)};
        checkSameRefs(w.overlapAabb(q), bruteOverlap(w, [&](const Shape3& s, const Transform3& xf) {
                          const Aabb3 b = computeAabb(s, xf);
                          return (b.lower.array() <= q.upper.array()).all() && (q.lower.array() <= b.upper.array()).all();
                      }));

        const Shape3 qs = randomConvex(rng);
        const Transform3 qxf = randomTransform(rng, 6.0);
        const std::vector<ShapeRef> found = w.overlapShape(qs, qxf);
        checkSameRefs(found, bruteOverlap(w, [&](const Shape3& s, const Transform3& xf) {
                          return shapesOverlap(qs, qxf, s, xf);
                      }));
        overlapCount += int(found.size());
    }
    return {hits, overlapCount};
}

// A polytope's world vertices, edges (vertex pairs) and faces (normal, loop) for the independent overlap test.
struct Poly {
    std::vector<Vec3> v;
    std::vector<std::array<int, 2>> edges;
    std::vector<std::pair<Vec3, std::vector<int>>> faces;
};

Poly polyOf(const Shape3& s, const Transform3& xf) {
    Poly p;
    if (s.type == ShapeType3::mesh) {
        for (const Vec3& v : s.mesh->vertices) p.v.push_back(transformPoint(xf, v));
        for (std::size_t t = 0; t < s.mesh->triangles.size(); ++t) {
            const auto& tri = s.mesh->triangles[t];
            p.faces.push_back({xf.r * s.mesh->triangleNormals[t], {tri[0], tri[1], tri[2]}});
            for (int k = 0; k < 3; ++k) p.edges.push_back({tri[std::size_t(k)], tri[std::size_t((k + 1) % 3)]});
        }
        return p;
    }
    for (const Vec3& v : s.poly->vertices) p.v.push_back(transformPoint(xf, v));
    for (const auto& f : s.poly->faces) p.faces.push_back({xf.r * f.normal, f.loop});
    for (const auto& e : s.poly->edges) p.edges.push_back({e.v0, e.v1});
    return p;
}

// Some edge of a properly crosses some face of b (end points strictly on both sides, crossing strictly inside).
bool edgeCrossesFace(const Poly& a, const Poly& b) {
    for (const auto& e : a.edges) {
        const Vec3 &p = a.v[std::size_t(e[0])], &q = a.v[std::size_t(e[1])];
        for (const auto& [n, loop] : b.faces) {
            const Vec3& o = b.v[std::size_t(loop[0])];
            const double dp = n.dot(p - o), dq = n.dot(q - o);
            if (!((dp < 0 && dq > 0) || (dp > 0 && dq < 0))) continue;
            const Vec3 x = p + (dp / (dp - dq)) * (q - p);
            bool in = true;
            for (std::size_t i = 0; i < loop.size(); ++i) {
                const Vec3 &u = b.v[std::size_t(loop[i])], &w = b.v[std::size_t(loop[(i + 1) % loop.size()])];
                in = in && (w - u).cross(x - u).dot(n) > 0.0;
            }
            if (in) return true;
        }
    }
    return false;
}

}  // namespace

TEST_SUITE("query3d") {

TEST_CASE("ray casts: closed forms on sphere, box, hull, plane and mesh") {
    double t = 0.0;
    Vec3 n;
    const Transform3 at{Vec3(1, 2, 3), Mat3::Identity()};
    REQUIRE(rayCastShape(sphere(1.0), at, Vec3(1, 2, -2), Vec3(0, 0, 10), &t, &n));
    CHECK(t == doctest::Approx(0.4));
    CHECK(n.z() == doctest::Approx(-1.0));
    REQUIRE(rayCastShape(sphere(1.0), at, Vec3(1.5, 2, 3), Vec3(0, 0, 10), &t, &n));
    CHECK(t == 0.0);  // starts inside
    CHECK_FALSE(rayCastShape(sphere(1.0), at, Vec3(1, 3.5, -2), Vec3(0, 0, 10), &t, &n));

    // A box turned 90 degrees about y: its half extents (1, 2, 3) become (3, 2, 1) along x, y, z.
    const Transform3 turned{Vec3::Zero(), toMatrix(axisAngle(Vec3(0, 1, 0), 3.141592653589793 / 2.0))};
    REQUIRE(rayCastShape(box(Vec3(1, 2, 3)), turned, Vec3(-10, 0.5, 0.5), Vec3(20, 0, 0), &t, &n));
    CHECK(t == doctest::Approx(7.0 / 20.0));
    CHECK(n.x() == doctest::Approx(-1.0));
    CHECK(std::fabs(n.z()) < 1e-12);

    // A hull: the tetrahedron x, y, z >= 0, x + y + z <= 1, hit on its slanted face along the diagonal.
    Shape3 tet;
    REQUIRE(makeHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}, &tet).empty());
    REQUIRE(rayCastShape(tet, {}, Vec3(1, 1, 1), Vec3(-1, -1, -1), &t, &n));
    CHECK(t == doctest::Approx(2.0 / 3.0));
    CHECK(n.x() == doctest::Approx(1.0 / std::sqrt(3.0)));

    // Plane y <= 0: entered from above, inside from below, missed when parallel.
    const Shape3 ground = plane(Vec3(0, 1, 0), 0.0);
    REQUIRE(rayCastShape(ground, {}, Vec3(0, 4, 0), Vec3(3, -8, 0), &t, &n));
    CHECK(t == doctest::Approx(0.5));
    CHECK(n.y() == doctest::Approx(1.0));
    REQUIRE(rayCastShape(ground, {}, Vec3(0, -1, 0), Vec3(0, 8, 0), &t, &n));
    CHECK(t == 0.0);
    CHECK_FALSE(rayCastShape(ground, {}, Vec3(0, 1, 0), Vec3(5, 0, 0), &t, &n));

    // The mesh cube [-1, 1]^3: from outside, from inside (fraction 0), and a miss.
    const Shape3 cube = cubeMesh(1.0);
    REQUIRE(rayCastShape(cube, {}, Vec3(-5, 0.3, 0.2), Vec3(10, 0, 0), &t, &n));
    CHECK(t == doctest::Approx(0.4));
    CHECK(n.x() == doctest::Approx(-1.0));
    REQUIRE(rayCastShape(cube, {}, Vec3(0.1, 0.3, 0.2), Vec3(10, 0, 0), &t, &n));
    CHECK(t == 0.0);
    REQUIRE(rayCastShape(cube, {}, Vec3(0.1, 0.3, 0.2), Vec3(0.1, 0, 0), &t, &n));  // ends inside too
    CHECK(t == 0.0);
    CHECK_FALSE(rayCastShape(cube, {}, Vec3(-5, 1.5, 0), Vec3(10, 0, 0), &t, &n));
}

TEST_CASE("overlaps: closed forms, containment, touching does not count") {
    const Shape3 b = box(Vec3(1, 1, 1));
    const double r3 = std::sqrt(3.0);  // (2, 2, 2) is sqrt(3) from the corner (1, 1, 1)
    CHECK_FALSE(shapesOverlap(sphere(r3 - 1e-9), {Vec3(2, 2, 2), Mat3::Identity()}, b, {}));
    CHECK(shapesOverlap(sphere(r3 + 1e-9), {Vec3(2, 2, 2), Mat3::Identity()}, b, {}));
    CHECK(shapesOverlap(b, {}, sphere(r3 + 1e-9), {Vec3(2, 2, 2), Mat3::Identity()}));  // either order
    CHECK(shapesOverlap(sphere(0.5), {Vec3(1.4, 0, 0), Mat3::Identity()}, b, {}));             // near a face
    CHECK_FALSE(shapesOverlap(b, {}, b, {Vec3(2, 0, 0), Mat3::Identity()}));                    // sharing a face
    CHECK(shapesOverlap(b, {}, b, {Vec3(1.999, 1.999, 1.999), Mat3::Identity()}));
    // Edge against edge: a cube turned 45 degrees about z reaches sqrt(2) along x.
    const Mat3 r45 = toMatrix(axisAngle(Vec3(0, 0, 1), 3.141592653589793 / 4.0));
    CHECK_FALSE(shapesOverlap(b, {Vec3(1 + std::sqrt(2.0) + 1e-9, 0, 0), r45}, b, {}));
    CHECK(shapesOverlap(b, {Vec3(1 + std::sqrt(2.0) - 1e-9, 0, 0), r45}, b, {}));
    // Plane y <= 0.
    const Shape3 ground = plane(Vec3(0, 1, 0), 0.0);
    CHECK_FALSE(shapesOverlap(sphere(1.0), {Vec3(0, 1, 0), Mat3::Identity()}, ground, {}));
    CHECK(shapesOverlap(sphere(1.0), {Vec3(0, 0.999, 0), Mat3::Identity()}, ground, {}));
    CHECK(shapesOverlap(b, {Vec3(0, 0.999, 0), Mat3::Identity()}, ground, {}));
    // Mesh cube [-2, 2]^3: a small box inside it (no triangle crossed), a sphere crossing a face, one outside, and a
    // big box that holds the whole mesh.
    const Shape3 cube = cubeMesh(2.0);
    CHECK(shapesOverlap(box(Vec3(0.1, 0.1, 0.1)), {Vec3(0.5, 0.5, 0.5), Mat3::Identity()}, cube, {}));
    CHECK(shapesOverlap(sphere(0.5), {Vec3(2.3, 0, 0), Mat3::Identity()}, cube, {}));
    CHECK_FALSE(shapesOverlap(sphere(0.5), {Vec3(2.5, 0, 0), Mat3::Identity()}, cube, {}));
    CHECK(shapesOverlap(box(Vec3(5, 5, 5)), {}, cube, {}));
    CHECK(shapesOverlap(sphere(9.0), {}, cube, {}));
    // Planes and meshes are not query shapes.
    CHECK_FALSE(shapesOverlap(ground, {}, b, {}));
    CHECK_FALSE(shapesOverlap(cube, {}, b, {}));
}

TEST_CASE("world queries: total order and bad arguments") {
    World3 w{WorldDef3{}};
    BodyDef3 bd;
    bd.type = BodyType::staticBody;
    bd.position = Vec3(5, 0, 0);
    const BodyId first = w.createBody(bd, {sphere(1.0)});
    const BodyId doomed = w.createBody(bd, {box(Vec3(0.5, 0.5, 0.5))});
    bd.position = Vec3(2, 0, 0);
    const BodyId near = w.createBody(bd, {box(Vec3(0.5, 0.5, 0.5)), cubeMesh(0.5)});
    REQUIRE(w.destroyBody(doomed));
    bd.position = Vec3(5, 0, 0);
    const BodyId twin = w.createBody(bd, {sphere(1.0)});
    REQUIRE(twin.index1 == 2);
    const std::vector<RayHit3> hits = w.rayCastAll(Vec3::Zero(), Vec3(10, 0, 0));
    REQUIRE(hits.size() == 4);
    CHECK(hits[0].body == near);
    CHECK(hits[0].shape == 0);
    CHECK(hits[1].shape == 1);
    CHECK(hits[0].fraction == hits[1].fraction);
    CHECK(hits[2].body == first);
    CHECK(hits[3].body == twin);
    CHECK(hits[2].point.x() == doctest::Approx(4.0));
    RayHit3 closest;
    REQUIRE(w.rayCastClosest(Vec3::Zero(), Vec3(10, 0, 0), &closest));
    CHECK(closest.body == near);
    CHECK(w.overlapShape(sphere(0.2), {Vec3(3.9, 0, 0), Mat3::Identity()}).size() == 2);
    CHECK(w.overlapShape(plane(Vec3(0, 1, 0), 0), {}).empty());
    CHECK_FALSE(w.rayCastClosest(Vec3::Zero(), Vec3::Zero(), &closest));
    CHECK(w.rayCastAll(Vec3(std::nan(""), 0, 0), Vec3(1, 0, 0)).empty());
    CHECK(w.overlapAabb({Vec3(0, 0, 0), Vec3(1, std::nan(""), 1)}).empty());
}

TEST_CASE("random scenes: the tree gives the brute-force answers, also after steps, changes and restore") {
    Rng rng{314159};
    query_checks::Tally tally;  // checks at the end that the scenes were dense enough
    for (int scene = 0; scene < 3; ++scene) {
        World3 w = randomWorld(rng, 50);
        tally.add(checkAgainstBruteForce(w, rng, 80));
        for (int s = 0; s < 3; ++s) w.step();
        tally.add(checkAgainstBruteForce(w, rng, 40));
        const std::vector<std::uint8_t> snap = w.snapshot();
        const std::vector<BodyId> ids = w.bodyIds();
        for (int k = 0; k < 8; ++k) w.destroyBody(ids[std::size_t(rng.below(int(ids.size())))]);
        tally.add(checkAgainstBruteForce(w, rng, 30));
        std::string error;
        REQUIRE_MESSAGE(w.restore(snap.data(), snap.size(), &error), error);
        tally.add(checkAgainstBruteForce(w, rng, 30));
    }
}

TEST_CASE("ray casts agree with point containment sampled along the ray") {
    Rng rng{2718};
    int hitsChecked = 0;
    for (int i = 0; i < 2500; ++i) {
        const Shape3 s = rng.below(6) == 0 ? plane(vec(rng, -1, 1), rng.uniform(-0.5, 0.5)) : randomShape(rng);
        const Transform3 xf = randomTransform(rng, 0.5);
        const Vec3 o = vec(rng, -2, 2), d = vec(rng, -5, 5);
        double t = 0.0;
        Vec3 n;
        if (!rayCastShape(s, xf, o, d, &t, &n)) {
            for (int k = 0; k <= 300; ++k) REQUIRE_FALSE(inside(s, xf, o + (k / 300.0) * d));
            continue;
        }
        CHECK(std::fabs(n.norm() - 1.0) < 1e-12);
        if (t == 0.0) {
            CHECK(inside(s, xf, o + 1e-9 * d));
            continue;
        }
        ++hitsChecked;
        CHECK(n.dot(d) <= 0.0);
        for (int k = 0; k < 300; ++k) REQUIRE_FALSE(inside(s, xf, o + (t * k / 300.0 * (1.0 - 1e-9)) * d));
        if (-n.dot(d) / d.norm() > 1e-3) CHECK(inside(s, xf, o + (t + 1e-7) * d));
    }
    CHECK(hitsChecked > 100);  // enough rays that enter a shape (145 of 2500 with this seed)
}

TEST_CASE("overlaps of polytopes and meshes agree with vertex containment and edge-face crossings") {
    Rng rng{1618};
    int yes = 0, no = 0;
    for (int i = 0; i < 2500; ++i) {
        Shape3 a = rng.below(2) ? box(vec(rng, 0.1, 0.8)) : randomHull(rng);
        Shape3 b = rng.below(3) == 0 ? octahedron(vec(rng, 0.3, 1.2)) : (rng.below(2) ? box(vec(rng, 0.1, 0.8)) : randomHull(rng));
        const Transform3 xa = randomTransform(rng, 0.8), xb = randomTransform(rng, 0.8);
        const Poly pa = polyOf(a, xa), pb = polyOf(b, xb);
        bool expected = edgeCrossesFace(pa, pb) || edgeCrossesFace(pb, pa);
        for (const Vec3& v : pa.v) expected = expected || inside(b, xb, v);
        for (const Vec3& v : pb.v) expected = expected || inside(a, xa, v);
        CHECK(shapesOverlap(a, xa, b, xb) == expected);
        if (b.type != ShapeType3::mesh) CHECK(shapesOverlap(b, xb, a, xa) == expected);
        (expected ? yes : no) += 1;
    }
    CHECK(yes > 300);
    CHECK(no > 300);
}

}  // TEST_SUITE
