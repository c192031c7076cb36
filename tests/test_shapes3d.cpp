// tests/test_shapes3d.cpp — 3D shapes: mass properties of known solids (closed forms), hull construction, meshes
// and their sphere trees, quaternion integration, and bad input.
#include "test_support.h"

#include "det_math.h"
#include "shapes3d.h"

#include <cmath>

using namespace unison;

namespace {

// The unit cube [-h, h]^3 as 12 outward triangles.
void cubeMesh(double h, std::vector<Vec3>* v, std::vector<std::array<int, 3>>* t) {
    v->clear();
    for (int i = 0; i < 8; ++i) v->push_back(Vec3((i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h));
    *t = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
          {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
}

void checkMat(const Mat3& a, const Mat3& b, double tol) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) CHECK(a(i, j) == doctest::Approx(b(i, j)).epsilon(tol).scale(1.0));
}

}  // namespace

TEST_SUITE("shapes3d") {

TEST_CASE("box, sphere: closed-form mass properties") {
    Shape3 box;
    REQUIRE(makeBox(Vec3(0.5, 1.0, 1.5), Vec3(1.0, 2.0, 3.0), &box).empty());
    box.density = 2.0;
    const MassData3 mb = computeMass(box);
    CHECK(mb.mass == doctest::Approx(2.0 * 1.0 * 2.0 * 3.0));
    CHECK(mb.center.isApprox(Vec3(1.0, 2.0, 3.0)));
    CHECK(mb.inertia(0, 0) == doctest::Approx(12.0 / 12.0 * (4.0 + 9.0)));
    CHECK(mb.inertia(1, 1) == doctest::Approx(12.0 / 12.0 * (1.0 + 9.0)));
    CHECK(mb.inertia(2, 2) == doctest::Approx(12.0 / 12.0 * (1.0 + 4.0)));
    Shape3 ball;
    REQUIRE(makeSphere(Vec3::Zero(), 0.5, &ball).empty());
    const MassData3 ms = computeMass(ball);
    const double m = 4.0 / 3.0 * dmath::kPi * 0.125;
    CHECK(ms.mass == doctest::Approx(m).epsilon(1e-14));
    CHECK(ms.inertia(1, 1) == doctest::Approx(0.4 * m * 0.25).epsilon(1e-14));
}

TEST_CASE("volume integration: a hull and a mesh of a box agree with the box's closed form") {
    Shape3 box, hull, mesh;
    REQUIRE(makeBox(Vec3(0.5, 0.5, 0.5), Vec3::Zero(), &box).empty());
    std::vector<Vec3> v;
    std::vector<std::array<int, 3>> t;
    cubeMesh(0.5, &v, &t);
    REQUIRE(makeHull(v, &hull).empty());
    REQUIRE(makeMesh(v, t, &mesh).empty());
    CHECK(hull.poly->faces.size() == 6);
    CHECK(hull.poly->edges.size() == 12);
    const MassData3 mb = computeMass(box), mh = computeMass(hull), mm = computeMass(mesh);
    CHECK(mh.mass == doctest::Approx(1.0).epsilon(1e-14));
    CHECK(mm.mass == doctest::Approx(1.0).epsilon(1e-14));
    checkMat(mh.inertia, mb.inertia, 1e-12);
    checkMat(mm.inertia, mb.inertia, 1e-12);
    CHECK(mm.center.norm() < 1e-15);
}

TEST_CASE("volume integration: tetrahedron and an offset, rotated cube") {
    // Tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1): V = 1/6, centroid 1/4, and about the origin
    // integral x^2 dV = 1/60, integral x y dV = 1/120.
    const std::vector<Vec3> v{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    const std::vector<std::array<int, 3>> t{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const MassData3 md = integrateSolid(v, t);
    CHECK(md.mass == doctest::Approx(1.0 / 6.0).epsilon(1e-14));
    CHECK(md.center.isApprox(Vec3(0.25, 0.25, 0.25), 1e-14));
    const double v6 = 1.0 / 6.0, c = 0.25;
    const double ixx = 2.0 / 60.0 - v6 * 2.0 * c * c;  // (y^2 + z^2) about the centre
    const double ixy = -(1.0 / 120.0 - v6 * c * c);
    CHECK(md.inertia(0, 0) == doctest::Approx(ixx).epsilon(1e-12));
    CHECK(md.inertia(0, 1) == doctest::Approx(ixy).epsilon(1e-12));
    // A cube moved and rotated: the same mass, the centre moves, the eigenvalues stay 1/6 m a^2.
    std::vector<Vec3> cv;
    std::vector<std::array<int, 3>> ct;
    cubeMesh(0.5, &cv, &ct);
    const Mat3 r = toMatrix(axisAngle(Vec3(1, 2, 3), 0.7));
    for (Vec3& p : cv) p = Dim3::add(mul(r, p), Vec3(3, -2, 5));
    const MassData3 mc = integrateSolid(cv, ct);
    CHECK(mc.mass == doctest::Approx(1.0).epsilon(1e-12));
    CHECK((mc.center - Vec3(3, -2, 5)).norm() < 1e-12);
    const Mat3 back = r.transpose() * mc.inertia * r;
    checkMat(back, Mat3::Identity() / 6.0, 1e-10);
}

TEST_CASE("hull: interior points are dropped; coplanar points are rejected") {
    std::vector<Vec3> pts;
    std::vector<std::array<int, 3>> t;
    cubeMesh(1.0, &pts, &t);
    pts.push_back(Vec3(0.1, 0.2, 0.3));
    pts.push_back(Vec3(1.0, 0.0, 0.0));  // on a face, not a vertex
    Shape3 hull;
    REQUIRE(makeHull(pts, &hull).empty());
    CHECK(hull.poly->vertices.size() == 8);
    Shape3 flat;
    const std::string err = makeHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)}, &flat);
    CHECK(err.find("volume") != std::string::npos);
    CHECK(flat.poly == nullptr);
}

TEST_CASE("mesh: open or inverted meshes and bad sizes are rejected and leave the shape untouched") {
    std::vector<Vec3> v;
    std::vector<std::array<int, 3>> t;
    cubeMesh(0.5, &v, &t);
    Shape3 s;
    s.radius = 7.0;
    auto open = t;
    open.pop_back();
    CHECK(makeMesh(v, open, &s).find("closed") != std::string::npos);
    auto inverted = t;
    for (auto& tri : inverted) std::swap(tri[1], tri[2]);
    CHECK(makeMesh(v, inverted, &s).find("volume") != std::string::npos);
    auto bad = t;
    bad[0][0] = 99;
    CHECK(makeMesh(v, bad, &s).find("range") != std::string::npos);
    CHECK(makeBox(Vec3(-1, 1, 1), Vec3::Zero(), &s).find("> 0") != std::string::npos);
    CHECK(makeSphere(Vec3(NAN, 0, 0), 1.0, &s).find("finite") != std::string::npos);
    CHECK(makePlane(Vec3::Zero(), 0.0, &s).find("non-zero") != std::string::npos);
    CHECK(s.type == ShapeType3::sphere);
    CHECK(s.radius == 7.0);
    CHECK(s.mesh == nullptr);
}

TEST_CASE("mesh sphere trees: every node's sphere holds its vertices (triangles), leaves cover each once") {
    // A UV sphere of 16 x 8 quads (closed).
    std::vector<Vec3> v{Vec3(0, 0, 1), Vec3(0, 0, -1)};
    const int nu = 16, nv = 8;
    for (int j = 1; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            double st, ct, sp, cp;
            dmath::sincos(dmath::kPi * j / nv, &st, &ct);
            dmath::sincos(2.0 * dmath::kPi * i / nu, &sp, &cp);
            v.push_back(Vec3(st * cp, st * sp, ct));
        }
    auto ring = [&](int j, int i) { return 2 + (j - 1) * nu + (i % nu); };
    std::vector<std::array<int, 3>> t;
    for (int i = 0; i < nu; ++i) {
        t.push_back({0, ring(1, i), ring(1, i + 1)});
        t.push_back({1, ring(nv - 1, i + 1), ring(nv - 1, i)});
        for (int j = 1; j + 1 < nv; ++j) {
            t.push_back({ring(j, i), ring(j + 1, i), ring(j + 1, i + 1)});
            t.push_back({ring(j, i), ring(j + 1, i + 1), ring(j, i + 1)});
        }
    }
    Shape3 s;
    REQUIRE(makeMesh(v, t, &s, 4).empty());
    const TriangleMesh& m = *s.mesh;
    std::vector<int> seen(v.size(), 0);
    for (const SphereNode& node : m.vertexTree.nodes) {
        for (int k = node.first; k < node.first + node.count; ++k) {
            const Vec3& p = m.vertices[std::size_t(m.vertexTree.order[std::size_t(k)])];
            CHECK((p - node.center).norm() <= node.radius * (1.0 + 1e-12));
            if (node.left < 0) ++seen[std::size_t(m.vertexTree.order[std::size_t(k)])];
        }
        if (node.left < 0) CHECK(node.count <= 4);
    }
    std::vector<int> seenTri(t.size(), 0);
    for (const SphereNode& node : m.triangleTree.nodes) {
        for (int k = node.first; k < node.first + node.count; ++k) {
            const int tri = m.triangleTree.order[std::size_t(k)];
            for (int c = 0; c < 3; ++c)
                CHECK((m.vertices[std::size_t(t[std::size_t(tri)][std::size_t(c)])] - node.center).norm() <= node.radius * (1.0 + 1e-12));
            if (node.left < 0) ++seenTri[std::size_t(tri)];
        }
    }
    for (int c : seenTri) CHECK(c == 1);
    for (int c : seen) CHECK(c == 1);
    // The volume approaches 4/3 pi from below; the normals point outwards.
    CHECK(computeMass(s).mass < 4.0 / 3.0 * dmath::kPi);
    CHECK(computeMass(s).mass > 0.8 * 4.0 / 3.0 * dmath::kPi);
    for (std::size_t i = 0; i < v.size(); ++i) CHECK(m.vertexNormals[i].dot(v[i]) > 0.9);
}

TEST_CASE("quaternion integration: constant spin about z turns by w t without libm") {
    Quat q;
    const Vec3 w(0.0, 0.0, 2.0);
    const double dt = 1.0 / 600.0;
    for (int i = 0; i < 600; ++i) q = integrateRotation(q, w, dt);
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    CHECK(n == doctest::Approx(1.0).epsilon(1e-15));
    // The explicit step q + dt/2 (0,w) q, normalised, advances the angle by 2 atan(w dt / 2) per step.
    const double angle = 2.0 * dmath::atan2(q.z, q.w);
    CHECK(angle == doctest::Approx(600.0 * 2.0 * dmath::atan(0.5 * 2.0 * dt)).epsilon(1e-12));
    CHECK(std::fabs(angle - 2.0) < 1e-5);
}

}  // TEST_SUITE
