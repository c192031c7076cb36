// tests/test_resolver.cpp — the paper's resolver against the closed forms of DESIGN.md (simultaneous model,
// frictionless unless stated), conservation laws, the single-contact fast path, friction and bad input.
#include "test_support.h"

#include "resolver2d.h"
#include "resolver3d.h"
#include "lcp_families.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace unison;

namespace {

constexpr double kTol = 1e-12;

Body2 ball2(double mass, double radius, Vec2 position, Vec2 velocity) {
    Body2 b;
    b.invMass = 1.0 / mass;
    b.invInertia = 1.0 / (0.5 * mass * radius * radius);
    b.position = position;
    b.velocity = velocity;
    return b;
}

Body2 ground2() { return Body2{}; }  // zero inverse mass and inertia: the paper's infinite-mass dummy body

Contact2 node2(int a, int b, Vec2 point, Vec2 normal, double e) { return makeContact<Dim2>(a, b, point, normal, e); }

double kinetic(const std::vector<Body2>& bodies) {
    double k = 0.0;
    for (const auto& b : bodies) {
        if (b.invMass > 0.0) k += 0.5 * dot(b.velocity, b.velocity) / b.invMass;
        if (b.invInertia > 0.0) k += 0.5 * b.angularVelocity * b.angularVelocity / b.invInertia;
    }
    return k;
}

Vec2 momentum(const std::vector<Body2>& bodies) {
    Vec2 p;
    for (const auto& b : bodies) {
        if (b.invMass > 0.0) p = p + (1.0 / b.invMass) * b.velocity;
    }
    return p;
}

Resolution resolve2(std::vector<Body2>& bodies, const std::vector<Contact2>& contacts) {
    LemkeSolver solver;
    return resolveCollisions(bodies, contacts, ResolverOptions{}, solver);
}

// N equal balls (radius 0.5, mass 1) touching along x; ball 0 moves at v into the rest. A = ball k, B = ball k+1:
// the normal points away from B towards A, i.e. -x.
std::vector<Body2> cradleBodies(int n, double v) {
    std::vector<Body2> bodies;
    for (int k = 0; k < n; ++k) bodies.push_back(ball2(1.0, 0.5, {double(k), 0.0}, {k == 0 ? v : 0.0, 0.0}));
    return bodies;
}

std::vector<Contact2> cradleContacts(int n, double e) {
    std::vector<Contact2> contacts;
    for (int k = 0; k + 1 < n; ++k) contacts.push_back(node2(k, k + 1, {k + 0.5, 0.0}, {-1.0, 0.0}, e));
    return contacts;
}

// Deterministic LCG giving doubles in [-1, 1).
struct Lcg {
    std::uint64_t state;
    double operator()() {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return double(state >> 11) / double(1ULL << 52) - 1.0;
    }
};

}  // namespace

TEST_SUITE("resolver") {

TEST_CASE("Newton's cradle reproduces the simultaneous closed form, not sequential impulses") {
    for (int n : {3, 5}) {
        for (double e : {1.0, 0.5}) {
            CAPTURE(n);
            CAPTURE(e);
            const double v = 2.0;
            auto bodies = cradleBodies(n, v);
            const Vec2 p0 = momentum(bodies);
            const double k0 = kinetic(bodies);
            const Resolution r = resolve2(bodies, cradleContacts(n, e));
            REQUIRE(r.status == LcpStatus::solved);
            CHECK_FALSE(r.fastPath);
            CHECK(bodies[0].velocity.x == doctest::Approx(v * (1.0 - (1.0 + e) * (n - 1) / n)).epsilon(kTol));
            for (int k = 1; k < n; ++k) CHECK(bodies[std::size_t(k)].velocity.x == doctest::Approx(v * (1.0 + e) / n).epsilon(kTol));
            for (const auto& b : bodies) CHECK(b.velocity.y == 0.0);
            CHECK(momentum(bodies).x == doctest::Approx(p0.x).epsilon(kTol));
            if (e == 1.0) {
                CHECK(kinetic(bodies) == doctest::Approx(k0).epsilon(kTol));
            } else {
                CHECK(kinetic(bodies) < k0);
            }
            // The fingerprint: sequential impulses would leave 0, ..., 0, v for e = 1; this is far from it.
            if (e == 1.0) CHECK(bodies[0].velocity.x < -0.3 * v);
        }
    }
}

TEST_CASE("a ball dropped on a resting column: the top ball rebounds at e v, the column stays at rest") {
    for (double e : {1.0, 0.5, 0.0}) {
        CAPTURE(e);
        const int column = 4;
        const double v = 3.0;
        std::vector<Body2> bodies{ground2()};
        for (int k = 0; k < column; ++k) bodies.push_back(ball2(1.0 + k, 0.5, {0.0, 0.5 + k}, {0.0, 0.0}));
        bodies.push_back(ball2(2.0, 0.5, {0.0, 0.5 + column}, {0.0, -v}));
        std::vector<Contact2> contacts{node2(1, 0, {0.0, 0.0}, {0.0, 1.0}, e)};
        for (int k = 1; k <= column; ++k) contacts.push_back(node2(k + 1, k, {0.0, double(k)}, {0.0, 1.0}, e));
        const Resolution r = resolve2(bodies, contacts);
        REQUIRE(r.status == LcpStatus::solved);
        CHECK(bodies.back().velocity.y == doctest::Approx(e * v).epsilon(kTol));
        for (int k = 1; k <= column; ++k) CHECK(std::fabs(bodies[std::size_t(k)].velocity.y) < 1e-12);
        // Every contact carries the same impulse m (1 + e) v down to the ground.
        for (double f : r.impulses) CHECK(f == doctest::Approx(2.0 * (1.0 + e) * v).epsilon(kTol));
    }
}

TEST_CASE("two-ball stack (10:1 masses) falling together onto the ground: both leave at e v") {
    for (double e : {1.0, 0.5}) {
        CAPTURE(e);
        const double v = 1.5;
        std::vector<Body2> bodies{ground2(), ball2(10.0, 0.5, {0.0, 0.5}, {0.0, -v}), ball2(1.0, 0.5, {0.0, 1.5}, {0.0, -v})};
        const std::vector<Contact2> contacts{node2(1, 0, {0.0, 0.0}, {0.0, 1.0}, e), node2(2, 1, {0.0, 1.0}, {0.0, 1.0}, e)};
        const Resolution r = resolve2(bodies, contacts);
        REQUIRE(r.status == LcpStatus::solved);
        CHECK(bodies[1].velocity.y == doctest::Approx(e * v).epsilon(kTol));
        CHECK(bodies[2].velocity.y == doctest::Approx(e * v).epsilon(kTol));
        CHECK(r.impulses[0] == doctest::Approx(11.0 * (1.0 + e) * v).epsilon(kTol));
        CHECK(r.impulses[1] == doctest::Approx(1.0 * (1.0 + e) * v).epsilon(kTol));
    }
}

TEST_CASE("uniform rod landing flat on both ends: equal impulses m (1 + e) v / 2, no rotation") {
    for (double e : {1.0, 0.5, 0.0}) {
        CAPTURE(e);
        const double m = 3.0, L = 2.0, v = 2.0;
        Body2 rod;
        rod.invMass = 1.0 / m;
        rod.invInertia = 12.0 / (m * L * L);
        rod.position = {0.0, 0.0};
        rod.velocity = {0.0, -v};
        std::vector<Body2> bodies{ground2(), rod};
        const std::vector<Contact2> contacts{node2(1, 0, {-1.0, 0.0}, {0.0, 1.0}, e), node2(1, 0, {1.0, 0.0}, {0.0, 1.0}, e)};
        const Resolution r = resolve2(bodies, contacts);
        REQUIRE(r.status == LcpStatus::solved);
        CHECK(r.impulses[0] == doctest::Approx(m * (1.0 + e) * v / 2.0).epsilon(kTol));
        CHECK(r.impulses[1] == doctest::Approx(m * (1.0 + e) * v / 2.0).epsilon(kTol));
        CHECK(bodies[1].velocity.y == doctest::Approx(e * v).epsilon(kTol));
        CHECK(std::fabs(bodies[1].angularVelocity) < 1e-12);
    }
}

TEST_CASE("billiard: A hits touching B and C at +-30 degrees") {
    for (double e : {1.0, 0.5, 0.0}) {
        CAPTURE(e);
        const double v = 1.0, R = 0.5;
        const double c30 = std::sqrt(3.0) / 2.0, s30 = 0.5;
        // A at the origin moving +x; B and C at distance 2R along +-30 degrees, touching each other at (2R c30, 0).
        std::vector<Body2> bodies{ball2(1.0, R, {0.0, 0.0}, {v, 0.0}), ball2(1.0, R, {2 * R * c30, 2 * R * s30}, {}),
                                  ball2(1.0, R, {2 * R * c30, -2 * R * s30}, {})};
        const std::vector<Contact2> contacts{
            node2(1, 0, {R * c30, R * s30}, {c30, s30}, e),    // B (A of the node) away from A (B of the node)
            node2(2, 0, {R * c30, -R * s30}, {c30, -s30}, e),
            node2(1, 2, {2 * R * c30, 0.0}, {0.0, 1.0}, e)};   // B-C touch; their normal is across the line of motion
        const double k0 = kinetic(bodies);
        const Resolution r = resolve2(bodies, contacts);
        REQUIRE(r.status == LcpStatus::solved);
        CHECK(bodies[0].velocity.x == doctest::Approx(v * (2.0 - 3.0 * e) / 5.0).epsilon(kTol));
        CHECK(std::fabs(bodies[0].velocity.y) < 1e-12);
        CHECK(length(bodies[1].velocity) == doctest::Approx(std::sqrt(3.0) * (1.0 + e) * v / 5.0).epsilon(kTol));
        CHECK(length(bodies[2].velocity) == doctest::Approx(std::sqrt(3.0) * (1.0 + e) * v / 5.0).epsilon(kTol));
        CHECK(r.impulses[2] == doctest::Approx(0.0));  // B and C separate: no impulse between them
        if (e == 1.0) CHECK(kinetic(bodies) == doctest::Approx(k0).epsilon(kTol));
        if (e < 1.0) CHECK(kinetic(bodies) < k0);
    }
}

TEST_CASE("three bodies meeting at one point: one node per colliding pair") {
    // Ball A hits a point particle P that touches ball B at the same point: nodes (A, P) and (P, B) share the
    // point. With both nodes active: v_P = v_B = (1 + e) v / (2 + m_P), v_A = v_P - e v.
    for (double e : {1.0, 0.5}) {
        const double v = 1.0, mp = 0.5;
        Body2 particle;
        particle.invMass = 1.0 / mp;
        particle.position = {0.5, 0.0};
        std::vector<Body2> bodies{ball2(1.0, 0.5, {0.0, 0.0}, {v, 0.0}), particle, ball2(1.0, 0.5, {1.0, 0.0}, {})};
        const std::vector<Contact2> contacts{node2(0, 1, {0.5, 0.0}, {-1.0, 0.0}, e), node2(1, 2, {0.5, 0.0}, {-1.0, 0.0}, e)};
        const Resolution r = resolve2(bodies, contacts);
        REQUIRE(r.status == LcpStatus::solved);
        const double u = (1.0 + e) * v / (2.0 + mp);
        CHECK(bodies[1].velocity.x == doctest::Approx(u).epsilon(kTol));
        CHECK(bodies[2].velocity.x == doctest::Approx(u).epsilon(kTol));
        CHECK(bodies[0].velocity.x == doctest::Approx(u - e * v).epsilon(kTol));
    }
}

TEST_CASE("cube landing flat on 4 corners: impulses are not unique, velocities are (v+ = e v, no spin)") {
    for (double e : {1.0, 0.5, 0.0}) {
        CAPTURE(e);
        const double v = 2.0, m = 2.0, s = 1.0;  // edge 1 m
        Body3 cube;
        cube.invMass = 1.0 / m;
        cube.invInertia = Mat3::Identity() * (6.0 / (m * s * s));
        cube.position = Vec3(0.0, 0.0, 0.5);
        cube.velocity = Vec3(0.0, 0.0, -v);
        std::vector<Body3> bodies{Body3{}, cube};
        std::vector<Contact3> contacts;
        for (double x : {-0.5, 0.5}) {
            for (double y : {-0.5, 0.5}) {
                Contact3 c;
                c.a = 1;
                c.b = 0;
                c.point = Vec3(x, y, 0.0);
                c.normal = Vec3(0.0, 0.0, 1.0);
                c.restitution = e;
                contacts.push_back(c);
            }
        }
        LemkeSolver solver;
        const Resolution r = resolveCollisions(bodies, contacts, ResolverOptions{}, solver);
        REQUIRE(r.status == LcpStatus::solved);
        CHECK(bodies[1].velocity.z() == doctest::Approx(e * v).epsilon(kTol));
        CHECK(std::fabs(bodies[1].velocity.x()) < 1e-12);
        CHECK(std::fabs(bodies[1].velocity.y()) < 1e-12);
        CHECK(bodies[1].angularVelocity.norm() < 1e-12);
        double total = 0.0;
        for (double f : r.impulses) {
            CHECK(f >= 0.0);
            total += f;
        }
        CHECK(total == doctest::Approx(m * (1.0 + e) * v).epsilon(kTol));
    }
}

TEST_CASE("tilted cube landing on one corner agrees with the single-point closed form") {
    // One node: f = -(1 + e) v_rel / (1/m + (r x n) . I^-1 (r x n)) (end of the paper's section 5).
    const double m = 1.0, e = 0.5;
    Body3 cube;
    cube.invMass = 1.0 / m;
    cube.invInertia = Mat3::Identity() * 6.0;
    cube.position = Vec3(0.0, 0.0, 0.0);
    cube.velocity = Vec3(0.3, -0.2, -1.0);
    cube.angularVelocity = Vec3(0.1, 0.2, -0.3);
    Contact3 c;
    c.a = 1;
    c.b = 0;
    c.point = Vec3(0.4, -0.3, -0.7);
    c.normal = Vec3(0.0, 0.0, 1.0);
    c.restitution = e;
    std::vector<Body3> bodies{Body3{}, cube};
    const double vrel = relativeNormalVelocity(bodies, c);
    const Vec3 r = c.point - cube.position;
    const Vec3 rn = r.cross(c.normal);
    const double expected = -(1.0 + e) * vrel / (1.0 / m + rn.dot(cube.invInertia * rn));
    LemkeSolver solver;
    const Resolution res = resolveCollisions(bodies, {c}, ResolverOptions{}, solver);
    REQUIRE(res.status == LcpStatus::solved);
    CHECK(res.fastPath);
    CHECK(res.impulses[0] == doctest::Approx(expected).epsilon(1e-14));
    CHECK(relativeNormalVelocity(bodies, c) == doctest::Approx(-e * vrel).epsilon(1e-12));
}

TEST_CASE("single-contact fast path agrees with the LCP solve") {
    LemkeSolver solver;
    Lcg rnd{7};
    for (int trial = 0; trial < 200; ++trial) {
        Body2 a = ball2(0.5 + std::fabs(rnd()), 0.3, {rnd(), rnd()}, {rnd(), rnd()});
        a.angularVelocity = rnd();
        Body2 b = ball2(0.5 + std::fabs(rnd()), 0.3, {rnd(), rnd()}, {rnd(), rnd()});
        const double ang = rnd() * 3.0;
        const Vec2 n{std::cos(ang), std::sin(ang)};
        const Contact2 c = node2(0, 1, {rnd(), rnd()}, n, 0.5 * (rnd() + 1.0));
        std::vector<Body2> fast{a, b};
        const Resolution rf = resolveCollisions(fast, {c}, ResolverOptions{}, solver);
        const Lcp lcp = assembleCollisionLcp(std::vector<Body2>{a, b}, {c});
        const LcpResult rl = solver.solve(lcp);
        REQUIRE(rf.status == LcpStatus::solved);
        REQUIRE(rl.status == LcpStatus::solved);
        CHECK(rf.fastPath);
        CHECK(rf.impulses[0] == doctest::Approx(rl.z[0]).epsilon(1e-13));
        CHECK(rf.impulses[0] >= 0.0);
    }
}

TEST_CASE("single 2D contact with friction: the closed form agrees with Lemke on the assembled LCP") {
    // Random pairs of spinning bodies (and bodies on static ground) with random normals, friction, restitution and
    // position bias: every case of the closed form (separating, sticking, slipping either way) is met.
    LemkeSolver solver;
    Lcg rnd{11};
    int separated = 0, stuck = 0, slipped = 0, ambiguous = 0;
    for (int trial = 0; trial < 400; ++trial) {
        CAPTURE(trial);
        Body2 a = ball2(0.5 + std::fabs(rnd()), 0.3, {rnd(), rnd()}, {2.0 * rnd(), 2.0 * rnd()});
        a.angularVelocity = 3.0 * rnd();
        Body2 b = trial % 3 == 0 ? ground2() : ball2(0.5 + std::fabs(rnd()), 0.4, {rnd(), rnd()}, {rnd(), rnd()});
        b.angularVelocity = trial % 3 == 0 ? 0.0 : rnd();
        const double ang = rnd() * 3.2;
        Contact2 c = node2(0, 1, {rnd(), rnd()}, {std::cos(ang), std::sin(ang)}, trial % 2 ? 0.0 : 0.5 * (rnd() + 1.0));
        c.friction = 0.8 * (rnd() + 1.0);
        c.bias = 0.1 * rnd();
        ResolverOptions options;
        options.frictionDirections = 2;
        std::vector<Body2> fast{a, b};
        const Resolution rf = resolveWithFriction(fast, {c}, options, solver);
        REQUIRE(rf.status == LcpStatus::solved);
        CHECK(rf.fastPath);
        CHECK(rf.pivots == 0);
        CHECK(rf.scaledResidual <= options.lcp.residualTolerance);
        // The answer solves the assembled LCP (z = p_n, beta+, beta-, lambda; lambda as the LCP needs it).
        FrictionLayout layout;
        const Lcp lcp = assembleFrictionLcp(std::vector<Body2>{a, b}, {c}, options, &layout);
        const Vec2 t = Dim2::tangentDirection(c.normal, 0, 2);
        const Vec2 ft{rf.tangentImpulses[0], rf.tangentImpulses[1]};
        CHECK(std::fabs(dot(ft, c.normal)) <= 1e-15);
        const double pf = dot(ft, t);
        std::vector<double> z{rf.impulses[0], std::max(pf, 0.0), std::max(-pf, 0.0), 0.0};
        double ut = lcp.b[1];
        for (int j = 0; j < 3; ++j) ut += lcp.at(1, j) * z[std::size_t(j)];
        z[3] = z[0] > 0.0 && std::fabs(pf) < c.friction * z[0] * (1.0 - 1e-12) ? 0.0 : std::fabs(ut);
        std::vector<double> w(4, 0.0);
        double scale = 1.0;
        for (int i = 0; i < 4; ++i) {
            w[std::size_t(i)] = lcp.b[std::size_t(i)];
            scale = std::max(scale, std::fabs(lcp.b[std::size_t(i)]));
            for (int j = 0; j < 4; ++j) {
                w[std::size_t(i)] += lcp.at(i, j) * z[std::size_t(j)];
                scale = std::max(scale, std::fabs(lcp.at(i, j)));
            }
        }
        CHECK(complementarityResidual(z, w) <= 1e-9 * scale);
        // Lemke on the same LCP. With mu |a_nt| < a_nn (the slipping normal equation is regular both ways) the
        // answer is unique in p_n and p_t and the two agree; beyond it a frictional contact can have two answers
        // (for a separating one, also none at all), and the closed form takes the first case that holds.
        const LcpResult rl = solver.solve(lcp);
        REQUIRE(rl.status == LcpStatus::solved);
        const double pn = rl.z[0], pt = rl.z[1] - rl.z[2];
        if (c.friction * std::fabs(lcp.at(0, 1)) >= lcp.at(0, 0)) {
            ++ambiguous;
            continue;
        }
        CHECK(rf.impulses[0] == doctest::Approx(pn).epsilon(1e-9));
        CHECK(pf == doctest::Approx(pt).epsilon(1e-9));
        // Applied to the bodies as Lemke's answer would be.
        std::vector<Body2> slow{a, b};
        std::vector<Vec2> tangent{pt * t};
        applyImpulses(slow, {c}, {pn}, &tangent);
        for (int k = 0; k < 2; ++k) {
            CHECK(fast[std::size_t(k)].velocity.x == doctest::Approx(slow[std::size_t(k)].velocity.x).epsilon(1e-9));
            CHECK(fast[std::size_t(k)].velocity.y == doctest::Approx(slow[std::size_t(k)].velocity.y).epsilon(1e-9));
            CHECK(fast[std::size_t(k)].angularVelocity == doctest::Approx(slow[std::size_t(k)].angularVelocity).epsilon(1e-9));
        }
        if (pn == 0.0) ++separated;
        else if (std::fabs(pt) < c.friction * pn * (1.0 - 1e-12)) ++stuck;
        else ++slipped;
    }
    CHECK(separated > 20);
    CHECK(stuck > 20);
    CHECK(slipped > 20);
    CHECK(separated + stuck + slipped + ambiguous == 400);
    CHECK(ambiguous < 100);  // the rest (300+) compared with Lemke
}

TEST_CASE("A is symmetric J M^-1 J^T: eq. (20) for nodes sharing one or two bodies") {
    // Three boxes in an L: node 0 and 1 share both bodies, node 2 shares only body 1 with them.
    std::vector<Body2> bodies{ball2(2.0, 0.4, {0.0, 0.0}, {0.1, 1.0}), ball2(1.0, 0.7, {0.2, 1.0}, {0.0, 0.0}),
                              ball2(3.0, 0.2, {1.1, 1.2}, {-1.0, 0.0})};
    const std::vector<Contact2> contacts{node2(1, 0, {-0.2, 0.5}, {0.0, 1.0}, 0.3), node2(1, 0, {0.3, 0.5}, {0.0, 1.0}, 0.3),
                                         node2(2, 1, {0.9, 1.1}, {1.0, 0.0}, 0.3)};
    const Lcp lcp = assembleCollisionLcp(bodies, contacts);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) CHECK(lcp.at(i, j) == doctest::Approx(lcp.at(j, i)).epsilon(1e-15));
    }
    // The paper's eq. (20) written out for i = 0, j = 1 (same pair A = 1, B = 0).
    const Body2& A = bodies[1];
    const Body2& B = bodies[0];
    const Vec2 n{0.0, 1.0};
    const Vec2 rA0 = contacts[0].point - A.position, rA1 = contacts[1].point - A.position;
    const Vec2 rB0 = contacts[0].point - B.position, rB1 = contacts[1].point - B.position;
    const double Aa = dot(n, n) * A.invMass + A.invInertia * cross(rA1, n) * cross(rA0, n);
    const double Ab = -dot(n, n) * B.invMass + B.invInertia * cross(rB1, -n) * cross(rB0, n);
    CHECK(lcp.at(0, 1) == doctest::Approx(Aa - Ab).epsilon(1e-15));
    // i = 0, j = 2: only body 1 is shared; it is A of node 0 and B of node 2, so the coupling changes sign.
    const Vec2 r2 = contacts[2].point - A.position;
    const double expected02 = A.invMass * dot(n, -Vec2{1.0, 0.0}) + A.invInertia * cross(rA0, n) * cross(r2, -Vec2{1.0, 0.0});
    CHECK(lcp.at(0, 2) == doctest::Approx(expected02).epsilon(1e-15));
    // b per eq. (19): (1 + e) v_rel for approaching nodes.
    CHECK(lcp.b[0] == doctest::Approx(1.3 * relativeNormalVelocity(bodies, contacts[0])).epsilon(1e-15));
}

TEST_CASE("restitution threshold and separating contacts use e = 0") {
    std::vector<Body2> bodies{ground2(), ball2(1.0, 0.5, {0.0, 0.5}, {0.0, -0.5})};
    const std::vector<Contact2> contacts{node2(1, 0, {0.0, 0.0}, {0.0, 1.0}, 1.0)};
    ResolverOptions options;
    options.restitutionThreshold = 1.0;  // Box2D's default: 0.5 m/s is below it, so the ball stops
    LemkeSolver solver;
    REQUIRE(resolveCollisions(bodies, contacts, options, solver).status == LcpStatus::solved);
    CHECK(bodies[1].velocity.y == doctest::Approx(0.0));
    bodies[1].velocity = {0.0, 0.5};  // separating: no impulse at all
    REQUIRE(resolveCollisions(bodies, contacts, options, solver).status == LcpStatus::solved);
    CHECK(bodies[1].velocity.y == 0.5);
}

TEST_CASE("friction: a point mass hitting the ground sticks or slides by Coulomb's law, in 2D and 3D") {
    // No rotation (inverse inertia 0): normal impulse m v_n (e = 0), tangential min(m v_t, mu f_n).
    for (double mu : {0.2, 1.0}) {
        CAPTURE(mu);
        const double m = 2.0, vn = 1.0, vt = 0.5;
        Body2 p;
        p.invMass = 1.0 / m;
        p.velocity = {vt, -vn};
        std::vector<Body2> bodies{ground2(), p};
        Contact2 c = node2(1, 0, {0.0, 0.0}, {0.0, 1.0}, 0.0);
        c.friction = mu;
        LemkeSolver solver;
        const Resolution r = resolveWithFriction(bodies, {c}, ResolverOptions{}, solver);
        REQUIRE(r.status == LcpStatus::solved);
        CHECK(r.impulses[0] == doctest::Approx(m * vn).epsilon(1e-12));
        const double ft = std::min(m * vt, mu * m * vn);
        CHECK(bodies[1].velocity.x == doctest::Approx(vt - ft / m).epsilon(1e-12));
        CHECK(std::fabs(bodies[1].velocity.y) < 1e-12);

        Body3 q;
        q.invMass = 1.0 / m;
        q.velocity = Vec3(vt, 0.0, -vn);
        std::vector<Body3> bodies3{Body3{}, q};
        Contact3 c3;
        c3.a = 1;
        c3.b = 0;
        c3.normal = Vec3(0.0, 0.0, 1.0);
        c3.friction = mu;
        const Resolution r3 = resolveWithFriction(bodies3, {c3}, ResolverOptions{}, solver);
        REQUIRE(r3.status == LcpStatus::solved);
        CHECK(bodies3[1].velocity.x() == doctest::Approx(vt - ft / m).epsilon(1e-12));
        CHECK(std::fabs(bodies3[1].velocity.y()) < 1e-12);
        CHECK(std::fabs(bodies3[1].velocity.z()) < 1e-12);
    }
}

TEST_CASE("bad input is rejected with a message and the bodies are untouched") {
    auto bodies = cradleBodies(3, 1.0);
    const auto before = bodies;
    LemkeSolver solver;
    auto expectRejected = [&](std::vector<Body2> bs, std::vector<Contact2> cs, const char* fragment) {
        const auto copy = bs;
        const Resolution r = resolveCollisions(bs, cs, ResolverOptions{}, solver);
        CHECK(r.status == LcpStatus::invalid_input);
        CHECK(r.message.find(fragment) != std::string::npos);
        for (std::size_t k = 0; k < bs.size(); ++k) {
            CHECK(bs[k].velocity.x == copy[k].velocity.x);
            CHECK(bs[k].angularVelocity == copy[k].angularVelocity);
        }
    };
    auto contacts = cradleContacts(3, 1.0);
    auto nanMass = bodies;
    nanMass[1].invMass = std::nan("");
    expectRejected(nanMass, contacts, "inverse mass");
    auto negMass = bodies;
    negMass[1].invMass = -1.0;
    expectRejected(negMass, contacts, "inverse mass");
    auto badNormal = contacts;
    badNormal[0].normal = {2.0, 0.0};
    expectRejected(bodies, badNormal, "unit length");
    auto badIndex = contacts;
    badIndex[1].b = 7;
    expectRejected(bodies, badIndex, "out of range");
    auto self = contacts;
    self[0].b = self[0].a;
    expectRejected(bodies, self, "differ");
    auto badE = contacts;
    badE[0].restitution = 1.5;
    expectRejected(bodies, badE, "restitution");
    auto infVel = bodies;
    infVel[2].velocity.x = INFINITY;
    expectRejected(infVel, contacts, "finite");
    CHECK(bodies[0].velocity.x == before[0].velocity.x);
}

TEST_CASE("two runs give bit-identical impulses and velocities") {
    auto run = [] {
        auto bodies = cradleBodies(5, 1.0);
        bodies[2].angularVelocity = 0.25;
        LemkeSolver solver;
        const Resolution r = resolveCollisions(bodies, cradleContacts(5, 0.7), ResolverOptions{}, solver);
        std::vector<double> out = r.impulses;
        for (const auto& b : bodies) {
            out.push_back(b.velocity.x);
            out.push_back(b.velocity.y);
            out.push_back(b.angularVelocity);
        }
        return out;
    };
    const auto a = run();
    const auto b = run();
    REQUIRE(a.size() == b.size());
    for (std::size_t k = 0; k < a.size(); ++k) CHECK(std::memcmp(&a[k], &b[k], sizeof(double)) == 0);
}


namespace {

// Entry by entry (columns and bit patterns of the values), the compressed-row assembly against toSparse of the
// dense assembly: the world solves the former, tests and the CLI often the latter.
template <class D>
void checkSparseEqualsDense(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                            const ResolverOptions& options) {
    const SparseLcp pairs[2][2] = {
        {toSparse(assembleCollisionLcp(bodies, contacts, options)), assembleCollisionLcpSparse(bodies, contacts, options)},
        {toSparse(assembleFrictionLcp(bodies, contacts, options)), assembleFrictionLcpSparse(bodies, contacts, options)}};
    for (const auto& pair : pairs) {
        const SparseLcp& dense = pair[0];
        const SparseLcp& sparse = pair[1];
        REQUIRE(sparse.n == dense.n);
        CHECK(sparse.rowStart == dense.rowStart);
        CHECK(sparse.cols == dense.cols);
        REQUIRE(sparse.vals.size() == dense.vals.size());
        CHECK(std::memcmp(sparse.vals.data(), dense.vals.data(), dense.vals.size() * sizeof(double)) == 0);
        CHECK(std::memcmp(sparse.b.data(), dense.b.data(), dense.b.size() * sizeof(double)) == 0);
        // The assembler vouches for its rows (SparseLcp::maxAbs), so the solver skips its own check. The voucher
        // is the largest diagonal entry, friction coefficient or 1; for these matrices that is exactly the largest
        // |A_ij|, and solving with or without the voucher gives the same bits.
        double maxAbs = 0.0;
        for (double v : dense.vals) maxAbs = std::max(maxAbs, std::fabs(v));
        CHECK(sparse.maxAbs == maxAbs);
        SparseLcp unvouched = sparse;
        unvouched.maxAbs = -1.0;
        LemkeSolver solver;
        const LcpResult a = solver.solve(sparse), b = solver.solve(unvouched);
        CHECK(a.status == b.status);
        CHECK(a.z == b.z);
        CHECK(a.pivots == b.pivots);
    }
}

// checkGuess on the guess's columns only against solve() on the whole matrix with the same warm start.
void checkGuessAgainstSolve(const SparseLcp& full) {
    LemkeSolver solver;
    const LcpResult cold = solver.solve(full);
    REQUIRE(cold.status == LcpStatus::solved);
    REQUIRE(!cold.basis.empty());
    auto columnsOf = [&](const std::vector<int>& guess) {
        std::vector<char> keep(std::size_t(full.n), 0);
        for (int j : guess) keep[std::size_t(j)] = 1;
        SparseLcp part;
        part.n = full.n;
        part.b = full.b;
        part.maxAbs = full.maxAbs;
        part.rowStart.push_back(0);
        for (int i = 0; i < full.n; ++i) {
            for (int t = full.rowStart[std::size_t(i)]; t < full.rowStart[std::size_t(i) + 1]; ++t) {
                if (!keep[std::size_t(full.cols[std::size_t(t)])]) continue;
                part.cols.push_back(full.cols[std::size_t(t)]);
                part.vals.push_back(full.vals[std::size_t(t)]);
            }
            part.rowStart.push_back(int(part.cols.size()));
        }
        return part;
    };
    LcpOptions options;
    SUBCASE("the right guess: the same bits as the full solve, no pivots") {
        options.warmBasis = &cold.basis;
        const LcpResult whole = solver.solve(full, options);
        const LcpResult part = solver.checkGuess(columnsOf(cold.basis), options);
        REQUIRE(part.status == LcpStatus::solved);
        CHECK(whole.pivots == 0);
        CHECK(part.pivots == 0);
        REQUIRE(part.z.size() == whole.z.size());
        CHECK(std::memcmp(part.z.data(), whole.z.data(), whole.z.size() * sizeof(double)) == 0);
        CHECK(std::memcmp(part.w.data(), whole.w.data(), whole.w.size() * sizeof(double)) == 0);
        CHECK(part.basis == whole.basis);
        CHECK(part.scaledResidual == whole.scaledResidual);
    }
    SUBCASE("a wrong guess is refused without pivoting; the full solve still finds an answer") {
        std::vector<int> wrong(cold.basis.begin(), cold.basis.begin() + std::ptrdiff_t(cold.basis.size() / 2));
        options.warmBasis = &wrong;
        const LcpResult part = solver.checkGuess(columnsOf(wrong), options);
        CHECK(part.status == LcpStatus::pivot_limit);
        CHECK(part.pivots == 0);
        const LcpResult whole = solver.solve(full, options);
        CHECK(whole.status == LcpStatus::solved);  // a pile has many solutions: any one will do
        CHECK(whole.scaledResidual <= options.residualTolerance);
        // The solve after a refused check starts from the check's own correction instead of repeating it: the
        // same bits as a solver that never saw the check, with every number of block principal rounds.
        for (int rounds = 0; rounds <= 3; ++rounds) {
            CAPTURE(rounds);
            options.blockPivotRounds = rounds;
            LemkeSolver fresh;
            const LcpResult reference = fresh.solve(full, options);
            CHECK(solver.checkGuess(columnsOf(wrong), options).status == LcpStatus::pivot_limit);
            const LcpResult after = solver.solve(full, options);
            CHECK(after.status == reference.status);
            CHECK(after.pivots == reference.pivots);
            REQUIRE(after.z.size() == reference.z.size());
            CHECK(std::memcmp(after.z.data(), reference.z.data(), after.z.size() * sizeof(double)) == 0);
            CHECK(after.scaledResidual <= options.residualTolerance);
        }
    }
    SUBCASE("from the guess's block and a product for w: the same z; a product that breaks a row refuses") {
        options.warmBasis = &cold.basis;
        const LcpResult whole = solver.solve(full, options);
        std::vector<char> inGuess(std::size_t(full.n), 0);
        for (int j : cold.basis) inGuess[std::size_t(j)] = 1;
        auto blockOnly = [&]() {
            SparseLcp block = columnsOf(cold.basis);
            SparseLcp out = block;
            out.cols.clear();
            out.vals.clear();
            out.rowStart.assign(1, 0);
            for (int i = 0; i < full.n; ++i) {
                for (int t = block.rowStart[std::size_t(i)]; t < block.rowStart[std::size_t(i) + 1] && inGuess[std::size_t(i)]; ++t) {
                    out.cols.push_back(block.cols[std::size_t(t)]);
                    out.vals.push_back(block.vals[std::size_t(t)]);
                }
                out.rowStart.push_back(int(out.cols.size()));
            }
            return out;
        };
        double shift = 0.0;  // added to one non-basic row's w: a large negative shift makes the guess wrong
        const LemkeSolver::Product product = [&](const double* z, double* w) {
            for (int i = 0; i < full.n; ++i) {
                double s = full.b[std::size_t(i)];
                for (int t = full.rowStart[std::size_t(i)]; t < full.rowStart[std::size_t(i) + 1]; ++t)
                    s += full.vals[std::size_t(t)] * z[full.cols[std::size_t(t)]];
                w[i] = s;
            }
            for (int i = 0; i < full.n; ++i) {
                if (!inGuess[std::size_t(i)]) {
                    w[i] += shift;
                    break;
                }
            }
        };
        const LcpResult part = solver.checkGuess(blockOnly(), options, product);
        REQUIRE(part.status == LcpStatus::solved);
        CHECK(std::memcmp(part.z.data(), whole.z.data(), whole.z.size() * sizeof(double)) == 0);
        CHECK(part.basis == whole.basis);
        shift = -1.0;
        CHECK(solver.checkGuess(blockOnly(), options, product).status == LcpStatus::pivot_limit);
    }
    SUBCASE("no voucher, no guess or a guess out of range: refused, nothing solved") {
        SparseLcp unvouched = columnsOf(cold.basis);
        unvouched.maxAbs = -1.0;
        options.warmBasis = &cold.basis;
        CHECK(solver.checkGuess(std::move(unvouched), options).status == LcpStatus::pivot_limit);
        options.warmBasis = nullptr;
        CHECK(solver.checkGuess(columnsOf(cold.basis), options).status == LcpStatus::pivot_limit);
        const std::vector<int> outOfRange{0, full.n};
        options.warmBasis = &outOfRange;
        CHECK(solver.checkGuess(columnsOf(cold.basis), options).status == LcpStatus::pivot_limit);
    }
}

// The world's path (resolveWithFriction with a warm basis: the guess checked on its columns first) against
// solving the assembled LCP with the same warm start.
template <class D>
void checkWarmResolveMatchesSolve(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                                  ResolverOptions options) {
    LemkeSolver solver;
    const SparseLcp full = assembleFrictionLcpSparse(bodies, contacts, options);
    const LcpResult cold = solver.solve(full);
    REQUIRE(cold.status == LcpStatus::solved);
    options.lcp.warmBasis = &cold.basis;
    const LcpResult direct = solver.solve(full, options.lcp);
    std::vector<ResolverBody<D>> io = bodies;
    const Resolution r = resolveWithFriction(io, contacts, options, solver);
    REQUIRE(r.status == LcpStatus::solved);
    CHECK(r.pivots == 0);
    REQUIRE(r.impulses.size() <= direct.z.size());
    CHECK(std::memcmp(r.impulses.data(), direct.z.data(), r.impulses.size() * sizeof(double)) == 0);
    CHECK(r.basis == direct.basis);
}

}  // namespace

TEST_CASE("a guess checked on its columns alone gives the full solve's answer bit for bit") {
    ResolverOptions options;
    options.frictionDirections = 4;
    SUBCASE("2D pyramid, friction LCP") {
        const scenes::Scene2 s = scenes::pyramid2dScene(6);
        checkGuessAgainstSolve(assembleFrictionLcpSparse(s.bodies, s.contacts, options));
    }
    SUBCASE("3D cube stack, friction LCP") {
        const scenes::Scene3 s = scenes::cubeStack3dScene(4);
        checkGuessAgainstSolve(assembleFrictionLcpSparse(s.bodies, s.contacts, options));
    }
    SUBCASE("resolveWithFriction with a warm basis, 2D and 3D") {
        const scenes::Scene2 s2 = scenes::pyramid2dScene(6);
        checkWarmResolveMatchesSolve(s2.bodies, s2.contacts, options);
        const scenes::Scene3 s3 = scenes::cubeStack3dScene(4);
        checkWarmResolveMatchesSolve(s3.bodies, s3.contacts, options);
    }
}

TEST_CASE("compressed-row assembly holds exactly the entries of the dense assembly") {
    ResolverOptions options;
    options.frictionDirections = 4;
    SUBCASE("2D pyramid: two points per box pair, a static ground") {
        const scenes::Scene2 s = scenes::pyramid2dScene(6);
        checkSparseEqualsDense(s.bodies, s.contacts, options);
    }
    SUBCASE("2D pyramid with a frictionless contact (mu = 0 leaves no entry in its slack row)") {
        scenes::Scene2 s = scenes::pyramid2dScene(4);
        s.contacts[3].friction = 0.0;
        checkSparseEqualsDense(s.bodies, s.contacts, options);
    }
    SUBCASE("3D cube stack") {
        const scenes::Scene3 s = scenes::cubeStack3dScene(4);
        checkSparseEqualsDense(s.bodies, s.contacts, options);
    }
}

}  // TEST_SUITE
