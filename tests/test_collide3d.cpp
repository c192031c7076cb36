// tests/test_collide3d.cpp — 3D narrowphase: manifold sizes, normals, separations and stable feature ids, the
// reduction to four points, and the broadphase contract.
#include "test_support.h"

#include "broadphase3d.h"
#include "collide3d.h"

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

using namespace unison;

namespace {

Shape3 box(double h) {
    Shape3 s;
    REQUIRE(makeBox(Vec3(h, h, h), Vec3::Zero(), &s).empty());
    return s;
}

Transform3 at(const Vec3& p, const Quat& q = Quat{}) { return Transform3{p, toMatrix(q)}; }

}  // namespace

TEST_SUITE("collide3d") {

TEST_CASE("box resting flat on a box: 4 face points, normal from B to A, ids stable under small motion") {
    const Shape3 a = box(0.5), b = box(1.0);
    const Manifold3 m = collide(a, at(Vec3(0.1, 1.49, 0.2)), b, at(Vec3::Zero()), 0.02);
    REQUIRE(m.count == 4);
    for (int i = 0; i < 4; ++i) {
        CHECK(m.points[std::size_t(i)].normal.isApprox(Vec3(0, 1, 0)));
        CHECK(m.points[std::size_t(i)].separation == doctest::Approx(-0.01));
        CHECK(m.points[std::size_t(i)].point.y() == doctest::Approx(0.995));
    }
    const Manifold3 m2 = collide(a, at(Vec3(0.11, 1.488, 0.19)), b, at(Vec3::Zero()), 0.02);
    REQUIRE(m2.count == 4);
    for (int i = 0; i < 4; ++i) CHECK(m2.points[std::size_t(i)].id == m.points[std::size_t(i)].id);
    // Beyond the speculative distance: nothing.
    CHECK(collide(a, at(Vec3(0, 1.53, 0)), b, at(Vec3::Zero()), 0.02).count == 0);
}

TEST_CASE("box on a plane: the four lowest corners; a tilted box: one corner") {
    Shape3 plane;
    REQUIRE(makePlane(Vec3(0, 1, 0), 0.0, &plane).empty());
    const Shape3 a = box(0.5);
    CHECK(collide(a, at(Vec3(0, 0.499, 0)), plane, at(Vec3::Zero()), 0.0).count == 4);
    const Quat tilt = multiply(axisAngle(Vec3(1, 0, 0), 0.3), axisAngle(Vec3(0, 0, 1), 0.4));
    const Manifold3 m = collide(a, at(Vec3(0, 0.7, 0), tilt), plane, at(Vec3::Zero()), 0.02);
    REQUIRE(m.count == 1);
    const Mat3 r = toMatrix(tilt);
    double lowest = 1e9;
    for (const Vec3& v : a.poly->vertices) lowest = std::min(lowest, 0.7 + mul(r, v).y());
    CHECK(m.points[0].separation == doctest::Approx(lowest));
    // Swapped roles: the normal flips.
    const Manifold3 s = collide(plane, at(Vec3::Zero()), a, at(Vec3(0, 0.7, 0), tilt), 0.02);
    REQUIRE(s.count == 1);
    CHECK(s.points[0].normal.isApprox(Vec3(0, -1, 0)));
}

TEST_CASE("edge against edge: crossed boxes touch at one point") {
    const Shape3 a = box(0.5), b = box(0.5);
    // A turned 45 degrees about x sits on B turned 45 degrees about z: their edges cross.
    const double h = 0.5 * std::sqrt(2.0);
    const Manifold3 m = collide(a, at(Vec3(0, 2.0 * h - 0.01, 0), axisAngle(Vec3(1, 0, 0), 0.25 * 3.141592653589793)), b,
                                at(Vec3::Zero(), axisAngle(Vec3(0, 0, 1), 0.25 * 3.141592653589793)), 0.02);
    REQUIRE(m.count == 1);
    CHECK(m.points[0].normal.isApprox(Vec3(0, 1, 0), 1e-9));
    CHECK(m.points[0].separation == doctest::Approx(-0.01).epsilon(1e-9));
    CHECK(m.points[0].point.isApprox(Vec3(0, h - 0.005, 0), 1e-9));
}

TEST_CASE("edge against edge with a wide margin: the edge point, then the best face's corners within the margin") {
    // A's lowest edge (A turned 0.3 rad about x) crosses B's highest edge (B turned 0.3 rad about z), 5 mm deep.
    const Shape3 a = box(0.25), b = box(0.25);
    const Transform3 xfA = at(Vec3(0, 0.62, 0), axisAngle(Vec3(1, 0, 0), 0.3));
    const Transform3 xfB = at(Vec3::Zero(), axisAngle(Vec3(0, 0, 1), 0.3));
    // Within 2 cm only the crossing itself: the face corner at the same place repeats the edge point.
    const Manifold3 near = collide(a, xfA, b, xfB, 0.02);
    REQUIRE(near.count == 1);
    CHECK((near.points[0].id >> 28) == 4u);  // edge against edge
    CHECK(near.points[0].normal.isApprox(Vec3(0, 1, 0), 1e-9));
    // Within 30 cm (a fast body's reach) the corners that A turns onto when it lands on the edge come too, with
    // the face's normal; the edge point stays first.
    const Manifold3 wide = collide(a, xfA, b, xfB, 0.3);
    REQUIRE(wide.count == 4);
    CHECK(wide.points[0].id == near.points[0].id);
    CHECK(wide.points[0].separation == near.points[0].separation);
    for (int i = 1; i < 4; ++i) {
        const ManifoldPoint3& p = wide.points[std::size_t(i)];
        CHECK((p.id >> 28) != 4u);
        CHECK(p.separation > 0.05);
        CHECK(p.separation < 0.3);
        CHECK(std::fabs(p.normal.norm() - 1.0) < 1e-12);
        CHECK(p.normal.dot(Vec3(0, 1, 0)) > 0.9);
        CHECK((p.point - wide.points[0].point).norm() > 0.1);
        for (int j = 0; j < i; ++j) CHECK(p.id != wide.points[std::size_t(j)].id);
    }
}

TEST_CASE("spheres: sphere-sphere and sphere-box (face, edge) distances") {
    Shape3 s1, s2;
    REQUIRE(makeSphere(Vec3::Zero(), 0.5, &s1).empty());
    REQUIRE(makeSphere(Vec3::Zero(), 0.25, &s2).empty());
    const Manifold3 ss = collide(s1, at(Vec3(0.7, 0, 0)), s2, at(Vec3::Zero()), 0.0);
    REQUIRE(ss.count == 1);
    CHECK(ss.points[0].separation == doctest::Approx(-0.05));
    CHECK(ss.points[0].normal.isApprox(Vec3(1, 0, 0)));
    const Shape3 b = box(1.0);
    const Manifold3 face = collide(s1, at(Vec3(0.2, 1.4, 0.3)), b, at(Vec3::Zero()), 0.0);
    REQUIRE(face.count == 1);
    CHECK(face.points[0].separation == doctest::Approx(-0.1));
    CHECK(face.points[0].normal.isApprox(Vec3(0, 1, 0)));
    const Manifold3 edge = collide(b, at(Vec3::Zero()), s1, at(Vec3(1.3, 1.3, 0)), 0.0);
    REQUIRE(edge.count == 1);
    CHECK(edge.points[0].separation == doctest::Approx(0.3 * std::sqrt(2.0) - 0.5));
    CHECK(edge.points[0].normal.isApprox(Vec3(-1, -1, 0).normalized()));
}

TEST_CASE("reduceToFour keeps the deepest point and spans the largest area") {
    std::vector<ManifoldPoint3> c;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) c.push_back({Vec3(i, 0, j), Vec3::UnitY(), -0.01 * (i == 2 && j == 3 ? 2 : 1), std::uint32_t(5 * i + j)});
    const auto r = reduceToFour(c);
    REQUIRE(r.size() == 4);
    CHECK(r[0].id == 13);  // deepest
    // The other three are corners of the 5 x 5 grid: farthest from (2,3) is (0,0); then the quad spans the most area.
    for (std::size_t i = 1; i < 4; ++i) {
        const Vec3& p = r[i].point;
        CHECK(((p.x() == 0 || p.x() == 4) && (p.z() == 0 || p.z() == 4)));
    }
}

TEST_CASE("reduceToFour: touching points span first; the slots they leave go to speculative points") {
    // One corner touches and the face's other corners are 5-25 cm away (a tilted cube landing on a corner): all of
    // them are kept, the touching one first, since the cube turns onto them.
    std::vector<ManifoldPoint3> corner;
    corner.push_back({Vec3(0, 0, 0), Vec3::UnitY(), -0.001, 1});
    corner.push_back({Vec3(0.5, 0, 0), Vec3::UnitY(), 0.05, 2});
    corner.push_back({Vec3(0, 0, 0.5), Vec3::UnitY(), 0.10, 3});
    corner.push_back({Vec3(0.5, 0, 0.5), Vec3::UnitY(), 0.25, 4});
    corner.push_back({Vec3(0.25, 0, 0.25), Vec3::UnitY(), 0.12, 5});  // inside: spans nothing
    const auto r = reduceToFour(corner);
    REQUIRE(r.size() == 4);
    CHECK(r[0].id == 1);
    for (std::size_t i = 1; i < 4; ++i) CHECK(r[i].id != 5);
    // Five touching points and two speculative ones farther out: the four kept all touch (with speculative
    // points spanning, a resting body would rock on the one or two that hold it).
    std::vector<ManifoldPoint3> rest;
    for (int i = 0; i < 5; ++i) rest.push_back({Vec3(0.1 * i, 0, 0.05 * (i % 2)), Vec3::UnitY(), -0.002, std::uint32_t(10 + i)});
    rest.push_back({Vec3(2, 0, 2), Vec3::UnitY(), 0.02, 20});
    rest.push_back({Vec3(-2, 0, 2), Vec3::UnitY(), 0.03, 21});
    const auto k = reduceToFour(rest);
    REQUIRE(k.size() == 4);
    for (const ManifoldPoint3& p : k) CHECK(p.separation < 0.0);
}

TEST_CASE("a CollideBatch reuses placements without changing a bit; a new batch forgets the old shapes") {
    // A row of pairs that share boxes (as a pile's broadphase gives them), with and without a batch.
    const Shape3 small = box(0.5), big = box(1.0);
    const Quat turn = axisAngle(Vec3(0, 1, 0), 0.1);
    std::vector<Transform3> xf;
    for (int i = 0; i < 12; ++i) xf.push_back(at(Vec3(0.3 * i, 0.99 * (i % 3), 0.05 * i), i % 2 ? turn : Quat{}));
    auto runAll = [&](std::vector<Manifold3>& out) {
        for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 12; ++j)
                if (i != j) out.push_back(collide(i % 4 ? small : big, xf[std::size_t(i)], j % 4 ? small : big, xf[std::size_t(j)], 0.02));
    };
    std::vector<Manifold3> plain, batched;
    runAll(plain);
    {
        const CollideBatch batch;
        runAll(batched);
    }
    REQUIRE(plain.size() == batched.size());
    int touching = 0;
    for (std::size_t k = 0; k < plain.size(); ++k) {
        REQUIRE(plain[k].count == batched[k].count);
        touching += plain[k].count > 0 ? 1 : 0;
        for (int p = 0; p < plain[k].count; ++p) {
            const ManifoldPoint3& u = plain[k].points[std::size_t(p)];
            const ManifoldPoint3& v = batched[k].points[std::size_t(p)];
            CHECK(std::memcmp(&u.point, &v.point, sizeof u.point) == 0);
            CHECK(std::memcmp(&u.normal, &v.normal, sizeof u.normal) == 0);
            CHECK(u.separation == v.separation);
            CHECK(u.id == v.id);
        }
    }
    CHECK(touching > 0);
    // A shape destroyed after one batch and another built at the same place in the next: never taken for it.
    {
        const CollideBatch batch;
        auto first = std::make_unique<Shape3>(box(0.5));
        CHECK(collide(*first, at(Vec3(0, 1.6, 0)), big, at(Vec3::Zero()), 0.02).count == 0);
    }
    {
        const CollideBatch batch;
        const Shape3 larger = box(0.8);  // overlaps the big box from the same transform
        CHECK(collide(larger, at(Vec3(0, 1.6, 0)), big, at(Vec3::Zero()), 0.02).count == 4);
    }
}

TEST_CASE("feature ids are unique within a manifold (they key the warm-start cache), also for many-sided hull faces") {
    // Pairs of random 12-point hulls in random poses: clipping a face of five or more sides used to name two points
    // alike, and a world holding such a contact wrote a snapshot its own restore refused.
    std::uint64_t state = 12345;
    auto uniform = [&](double lo, double hi) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * double(state >> 11) * 0x1.0p-53;
    };
    auto hull = [&] {
        std::vector<Vec3> pts;
        for (int i = 0; i < 12; ++i) {
            const Vec3 d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            pts.push_back(d / d.norm());
        }
        Shape3 s;
        REQUIRE(makeHull(pts, &s).empty());
        return s;
    };
    int points = 0;
    for (int i = 0; i < 2000; ++i) {
        const Shape3 a = hull(), b = hull();
        const Transform3 xa{Vec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)),
                            toMatrix(normalized(Quat{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)}))};
        const Manifold3 m = collide(a, xa, b, Transform3{}, 0.02);
        for (int p = 0; p < m.count; ++p)
            for (int q = 0; q < p; ++q) CHECK(m.points[std::size_t(p)].id != m.points[std::size_t(q)].id);
        points += m.count;
    }
    CHECK(points > 2000);
}

TEST_CASE("broadphase: sorted pairs, inactive pairs skipped, invalid boxes ignored") {
    std::vector<Aabb3> boxes{{Vec3(0, 0, 0), Vec3(1, 1, 1)}, {Vec3(0.5, 0.5, 0.5), Vec3(2, 2, 2)},
                             {Vec3(0.9, 0.9, 5), Vec3(3, 3, 6)}, {Vec3(-1, -1, -1), Vec3(5, 5, 5)},
                             {Vec3(NAN, 0, 0), Vec3(1, 1, 1)}};
    const auto pairs = findPairs3(boxes, {0, 0, 0, 1, 0});
    const std::vector<std::pair<int, int>> want{{0, 1}, {0, 3}, {1, 3}, {2, 3}};
    CHECK(pairs == want);
    CHECK_THROWS(findPairs3(boxes, {0}));
}

}  // TEST_SUITE
