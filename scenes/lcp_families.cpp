// scenes/lcp_families.cpp — see lcp_families.h.
//
// The pivot counts quoted here were checked with an exact rational (fractions) lexicographic Lemke, covering
// vector 1, counting every basis exchange including the one where z0 enters:
//   Murty lower-triangular, b = -1:   2, 4, 8, ..., 2^n  (n = 1..11 checked)
//   Murty upper-triangular, b = -1:   2 for every n (the lexicographic first pivot picks the last row, and z_n
//                                      alone solves it), so the upper form is *not* a hard case for lexico Lemke
//   Fathi L L^T, b = -1:              2^n (n = 1..11 checked); the solution is z = e_1
#include "lcp_families.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace unison::scenes {

namespace {

// ---- Materials of the settled scenes ----
constexpr double kBoxHalf = 0.25;                   // 2D boxes: 0.5 m x 0.5 m
constexpr double kBoxSize = 2.0 * kBoxHalf;
constexpr double kBoxMass = 1.0 * kBoxSize * kBoxSize;  // density 1 kg/m^2 -> 0.25 kg
constexpr double kFriction = 0.6;

int pow2OrUnknown(int n) { return (n >= 0 && n <= 30) ? (1 << n) : -1; }

// 2^n > the solver's default pivot cap?
bool exceedsDefaultCap(int n) { return n >= 31 || (1LL << n) > LcpOptions::kDefaultMaxPivots; }

std::string sizeName(const char* family, int size, const char* suffix = "") {
    return std::string(family) + std::to_string(size) + suffix;
}

// Restitution in names: "0.5" -> "e0.5", exact for the short decimals the benchmark uses.
std::string restitutionName(double e) {
    const long long milli = std::llround(e * 1000.0);
    std::string s = "e" + std::to_string(milli / 1000);
    long long frac = milli % 1000;
    if (frac != 0) {
        std::string digits = std::to_string(1000 + frac).substr(1);  // three digits, leading zeros kept
        while (!digits.empty() && digits.back() == '0') digits.pop_back();
        s += "." + digits;
    }
    return s;
}

ResolverBody<Dim2> staticBody2(Vec2 position) {
    ResolverBody<Dim2> b;
    b.position = position;
    return b;  // invMass = 0, invInertia = 0: the paper's dummy body of infinite mass
}

ResolverBody<Dim2> settledBox2(Vec2 position) {
    ResolverBody<Dim2> b;
    b.invMass = 1.0 / kBoxMass;
    b.invInertia = 12.0 / (kBoxMass * (kBoxSize * kBoxSize + kBoxSize * kBoxSize));  // box: I = m (w^2 + h^2) / 12
    b.position = position;
    b.velocity = Vec2{0.0, -kSettledFallSpeed};
    return b;
}

ContactNode<Dim2> node2(int a, int b, Vec2 point, Vec2 normal, double restitution, double friction) {
    return makeContact<Dim2>(a, b, point, normal, restitution, friction);
}

// Two contact points at the ends of the overlap of [upperX - h, upperX + h] and [lowerX - h, lowerX + h] (an
// infinite lower body when lowerIsGround), at height y, normal +y from `lower` to `upper`.
void addBoxInterface(Scene2& scene, int upper, int lower, double upperX, double lowerX, bool lowerIsGround, double y) {
    double lo = upperX - kBoxHalf;
    double hi = upperX + kBoxHalf;
    if (!lowerIsGround) {
        lo = std::max(lo, lowerX - kBoxHalf);
        hi = std::min(hi, lowerX + kBoxHalf);
    }
    scene.contacts.push_back(node2(upper, lower, Vec2{lo, y}, Vec2{0.0, 1.0}, 0.0, kFriction));
    scene.contacts.push_back(node2(upper, lower, Vec2{hi, y}, Vec2{0.0, 1.0}, 0.0, kFriction));
}

LcpCase fromScene2(std::string name, const Scene2& scene, bool friction, std::string expected) {
    LcpCase out;
    out.name = std::move(name);
    const ResolverOptions options{};
    out.lcp = friction ? assembleFrictionLcp(scene.bodies, scene.contacts, options)
                       : assembleCollisionLcp(scene.bodies, scene.contacts, options);
    out.expected = std::move(expected);
    return out;
}

void requirePositive(int value, const char* what) {
    if (value <= 0) throw std::invalid_argument(std::string("lcp_families: ") + what + " must be positive");
}

}  // namespace

// ---- Pure matrix families ----------------------------------------------------------------------------------

LcpCase murty(int n) {
    requirePositive(n, "murty size");
    // Murty (1978), "Computational complexity of complementary pivot methods": M lower triangular with 1 on the
    // diagonal and 2 below, q = -e. With q = -e the very first ratio test is an n-way tie, and which path Lemke
    // takes depends on its tie rule (the classical lexicographic rule walks all 2^n bases). b_i = -1 + 0.25 2^-(i+1)
    // resolves that tie exactly as the lexicographic rule does, so every correct Lemke now walks the same forced,
    // non-degenerate path of 2^n pivots (counting the one where z0 enters). The solution is z = (-b_0, 0, ..., 0):
    // w_i = 2 z_0 + b_i > 0 for i > 0. The steps of 0.25 2^-(i+1) stay above the solver's degeneracy perturbation
    // (1e-7 max|b| by default) up to n = 16, so the perturbation does not reorder the path.
    LcpCase out;
    out.name = sizeName("murty", n);
    out.lcp = Lcp(n);
    for (int i = 0; i < n; ++i) {
        out.lcp.at(i, i) = 1.0;
        for (int j = 0; j < i; ++j) out.lcp.at(i, j) = 2.0;
        out.lcp.b[std::size_t(i)] = -1.0 + 0.25 * std::ldexp(1.0, -(i + 1));
    }
    out.expected = "solved";
    out.expectedPivots = pow2OrUnknown(n);
    out.capAcceptable = exceedsDefaultCap(n);
    return out;
}

LcpCase lowerLLT(int n, bool mixedSigns) {
    requirePositive(n, "L L^T size");
    // Fathi (1979): A = L L^T with L = I + 2 (strict lower part of ones), symmetric positive definite, so the LCP
    // has exactly one solution for every b. Entries are small integers: (L L^T)_ij = 4 min(i, j) + 1 + [i != j]
    // (0-based), computed exactly in doubles.
    LcpCase out;
    out.name = sizeName("llt", n, mixedSigns ? "_mixed" : "");
    out.lcp = Lcp(n);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const int m = std::min(i, j);
            out.lcp.at(i, j) = 4.0 * double(m) + (i == j ? 1.0 : 2.0);
        }
    }
    if (mixedSigns) {
        // Knuth's MMIX LCG; high bits mapped to {-1.000, -0.999, ..., 1.000}. Integer arithmetic then one
        // correctly rounded division: identical on every platform and standard library.
        std::uint64_t s = 0x2545F4914F6CDD1DULL;
        for (int i = 0; i < n; ++i) {
            s = s * 6364136223846793005ULL + 1442695040888963407ULL;
            const int v = int((s >> 33) % 2001ULL) - 1000;
            out.lcp.b[std::size_t(i)] = double(v) / 1000.0;
        }
        out.expectedPivots = -1;
    } else {
        for (int i = 0; i < n; ++i) out.lcp.b[std::size_t(i)] = -1.0;
        // With b = -1 the solution is z = e_1 (A_00 = 1, A_i0 = 2), yet exact lexicographic Lemke walks 2^n bases.
        out.expectedPivots = pow2OrUnknown(n);
        out.capAcceptable = exceedsDefaultCap(n);
    }
    out.expected = "solved";
    return out;
}

// ---- 2D contact scenes ---------------------------------------------------------------------------------------

Scene2 pyramid2dScene(int rows) {
    requirePositive(rows, "pyramid rows");
    Scene2 scene;
    scene.bodies.push_back(staticBody2(Vec2{0.0, -kBoxHalf}));  // ground; its top face is y = 0
    // firstIndex[i] = body index of the leftmost box of row i; box (i, j) sits at x = (i/2 + j - (rows-1)/2) w.
    std::vector<int> firstIndex(static_cast<std::size_t>(rows));
    auto boxX = [rows](int i, int j) { return (0.5 * double(i) + double(j) - 0.5 * double(rows - 1)) * kBoxSize; };
    for (int i = 0; i < rows; ++i) {
        firstIndex[std::size_t(i)] = int(scene.bodies.size());
        for (int j = 0; j < rows - i; ++j) scene.bodies.push_back(settledBox2(Vec2{boxX(i, j), kBoxHalf + double(i) * kBoxSize}));
    }
    for (int i = 0; i < rows; ++i) {
        const double y = double(i) * kBoxSize;  // bottom face of row i
        for (int j = 0; j < rows - i; ++j) {
            const int box = firstIndex[std::size_t(i)] + j;
            if (i == 0) {
                addBoxInterface(scene, box, 0, boxX(0, j), 0.0, true, y);
            } else {
                const int below = firstIndex[std::size_t(i - 1)] + j;  // boxes j and j + 1 of the row below
                addBoxInterface(scene, box, below, boxX(i, j), boxX(i - 1, j), false, y);
                addBoxInterface(scene, box, below + 1, boxX(i, j), boxX(i - 1, j + 1), false, y);
            }
        }
    }
    return scene;
}

LcpCase pyramid2d(int rows, bool friction) {
    return fromScene2(sizeName("pyramid", rows, friction ? "_friction" : ""), pyramid2dScene(rows), friction, "solved");
}

Scene2 column2dScene(int count) {
    requirePositive(count, "column count");
    Scene2 scene;
    scene.bodies.push_back(staticBody2(Vec2{0.0, -kBoxHalf}));
    for (int k = 0; k < count; ++k) scene.bodies.push_back(settledBox2(Vec2{0.0, kBoxHalf + double(k) * kBoxSize}));
    for (int k = 0; k < count; ++k) addBoxInterface(scene, k + 1, k, 0.0, 0.0, k == 0, double(k) * kBoxSize);
    return scene;
}

LcpCase column2d(int count, bool friction) {
    return fromScene2(sizeName("column", count, friction ? "_friction" : ""), column2dScene(count), friction, "solved");
}

Scene2 cradleChainScene(int balls, double restitution) {
    if (balls < 2) throw std::invalid_argument("lcp_families: a cradle needs at least 2 balls");
    constexpr double radius = 0.5;
    constexpr double mass = 1.0;
    Scene2 scene;
    for (int i = 0; i < balls; ++i) {
        ResolverBody<Dim2> b;
        b.invMass = 1.0 / mass;
        b.invInertia = 2.0 / (mass * radius * radius);  // disc: I = m r^2 / 2
        b.position = Vec2{double(i) * 2.0 * radius, 0.0};
        b.velocity = Vec2{i == 0 ? 1.0 : 0.0, 0.0};
        scene.bodies.push_back(b);
    }
    // Node i joins ball i (B) and ball i + 1 (A); the normal points away from B towards A.
    for (int i = 0; i + 1 < balls; ++i)
        scene.contacts.push_back(node2(i + 1, i, Vec2{double(i) * 2.0 * radius + radius, 0.0}, Vec2{1.0, 0.0}, restitution, 0.0));
    return scene;
}

LcpCase cradleChain(int balls, double restitution) {
    return fromScene2(sizeName("cradle", balls, ("_" + restitutionName(restitution)).c_str()),
                      cradleChainScene(balls, restitution), false, "solved");
}

Scene2 jammedParticleScene(double restitution) {
    Scene2 scene;
    scene.bodies.push_back(staticBody2(Vec2{-1.0, 0.0}));  // 0: left wall, face at x = -0.5
    scene.bodies.push_back(staticBody2(Vec2{1.0, 0.0}));   // 1: right wall, face at x = +0.5
    ResolverBody<Dim2> p;                                   // 2: particle, radius 0.5, mass 1, centre at 0
    p.invMass = 1.0;
    p.invInertia = 8.0;
    p.velocity = Vec2{-1.0, 0.0};
    scene.bodies.push_back(p);
    scene.contacts.push_back(node2(2, 0, Vec2{-0.5, 0.0}, Vec2{1.0, 0.0}, restitution, 0.0));
    scene.contacts.push_back(node2(2, 1, Vec2{0.5, 0.0}, Vec2{-1.0, 0.0}, restitution, 0.0));
    return scene;
}

LcpCase jammedParticle(double restitution) {
    // Why no solution exists. Both contacts act on the same particle (mass m = 1) along opposite normals
    // n_0 = +x (left wall) and n_1 = -x (right wall), through its centre (no rotation), so eq. (20) gives
    //     A = [[ 1/m, -1/m ], [ -1/m, 1/m ]],   hence   w_0 + w_1 = b_0 + b_1   for every z.
    // The particle moves at v = 1 into the left wall: v_rel_0 = n_0 . v = -1 (approaching), v_rel_1 = +1
    // (separating). DESIGN.md step 5 applies restitution only to approaching contacts, so eq. (19) gives
    //     b_0 = (1 + e) v_rel_0 = -(1 + e),   b_1 = v_rel_1 = 1,   b_0 + b_1 = -e.
    // Any z >= 0 then has w_0 + w_1 = -e < 0, so w >= 0 is impossible: the LCP is infeasible for every e > 0.
    // Physically: bouncing off the left wall at e v needs room the right wall does not leave. Since A is
    // positive semidefinite (copositive-plus), Lemke is guaranteed to end on a secondary ray here.
    // (With the paper's literal eq. (19) on the separating contact too, b_1 = (1 + e) and b_0 + b_1 = 0: feasible.
    // The benchmark cross-checks that assembleCollisionLcp(jammedParticleScene(e)) reproduces this LCP.)
    LcpCase out;
    out.name = "jammed_" + restitutionName(restitution);
    out.lcp = Lcp(2);
    out.lcp.at(0, 0) = 1.0;
    out.lcp.at(0, 1) = -1.0;
    out.lcp.at(1, 0) = -1.0;
    out.lcp.at(1, 1) = 1.0;
    out.lcp.b = {-(1.0 + restitution), 1.0};
    out.expected = restitution > 0.0 ? "infeasible" : "solved";
    return out;
}

Scene2 squeezedParticleScene(double restitution) {
    Scene2 scene = jammedParticleScene(restitution);
    scene.bodies[0].velocity = Vec2{1.0, 0.0};   // kinematic walls (infinite mass) closing in at 1 m/s
    scene.bodies[1].velocity = Vec2{-1.0, 0.0};
    scene.bodies[2].velocity = Vec2{0.0, 0.0};
    return scene;
}

LcpCase squeezedParticle(double restitution) {
    // Same A as jammedParticle; now v_rel_0 = v_rel_1 = -1 (both approach), so b_0 + b_1 = -2 (1 + e) < 0 under
    // any restitution convention: w_0 + w_1 = b_0 + b_1 < 0 for every z, infeasible for every e >= 0.
    return fromScene2("squeezed_" + restitutionName(restitution), squeezedParticleScene(restitution), false, "infeasible");
}

// ---- 3D contact scenes ---------------------------------------------------------------------------------------

Scene3 cubeStack3dScene(int count) {
    requirePositive(count, "cube count");
    constexpr double mass = 1.0;
    constexpr double edge = 1.0;
    Scene3 scene;
    ResolverBody<Dim3> ground;
    ground.position = Vec3(0.0, 0.0, -0.5);
    scene.bodies.push_back(ground);
    for (int k = 0; k < count; ++k) {
        ResolverBody<Dim3> cube;
        cube.invMass = 1.0 / mass;
        cube.invInertia = Mat3::Identity() * (12.0 / (mass * (edge * edge + edge * edge)));  // I = m (a^2 + b^2) / 12
        cube.position = Vec3(0.0, 0.0, 0.5 + double(k));
        cube.velocity = Vec3(0.0, 0.0, -kSettledFallSpeed);
        scene.bodies.push_back(cube);
    }
    const double corners[4][2] = {{-0.5, -0.5}, {0.5, -0.5}, {-0.5, 0.5}, {0.5, 0.5}};
    for (int k = 0; k < count; ++k) {
        for (const auto& xy : corners) {
            ContactNode<Dim3> c;
            c.a = k + 1;
            c.b = k;
            c.point = Vec3(xy[0], xy[1], double(k));
            c.normal = Vec3(0.0, 0.0, 1.0);
            c.restitution = 0.0;
            c.friction = kFriction;
            scene.contacts.push_back(c);
        }
    }
    return scene;
}

LcpCase cubeStack3d(int count, bool friction) {
    const Scene3 scene = cubeStack3dScene(count);
    LcpCase out;
    out.name = sizeName("cubes", count, friction ? "_friction" : "");
    const ResolverOptions options{};
    out.lcp = friction ? assembleFrictionLcp(scene.bodies, scene.contacts, options)
                       : assembleCollisionLcp(scene.bodies, scene.contacts, options);
    out.expected = "solved";  // A is positive semidefinite and z = (m g dt per corner share) is feasible
    return out;
}

// ---- Helpers -------------------------------------------------------------------------------------------------

double scaledResidual(const Lcp& lcp, const std::vector<double>& z) {
    const std::size_t n = std::size_t(lcp.n);
    if (z.size() != n) return std::numeric_limits<double>::infinity();
    double scale = 0.0;
    for (double a : lcp.A) scale = std::max(scale, std::fabs(a));
    for (double b : lcp.b) scale = std::max(scale, std::fabs(b));
    if (scale == 0.0) scale = 1.0;
    double residual = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(z[i])) return std::numeric_limits<double>::infinity();
        double w = lcp.b[i];
        for (std::size_t j = 0; j < n; ++j) w += lcp.A[i * n + j] * z[j];
        residual = std::max(residual, std::fabs(std::min(z[i], w)));
    }
    return residual / scale;
}

LcpCase nondegenerate(LcpCase c, double delta) {
    double bMax = 0.0;
    for (double v : c.lcp.b) bMax = std::max(bMax, std::fabs(v));
    for (std::size_t i = 0; i < c.lcp.b.size(); ++i) {
        const double t = double(i + 1) * 0.7548776662466927;  // plastic-number fractions: distinct, in [0, 1)
        c.lcp.b[i] -= delta * bMax * (1.0 + (t - std::floor(t)));
    }
    c.name += "_nondegenerate";
    c.expectedPivots = -1;
    return c;
}

std::vector<LcpCase> standardCases(bool quick) {
    std::vector<LcpCase> cases;
    if (quick) {
        cases.push_back(pyramid2d(5, false));   // n = 50
        cases.push_back(pyramid2d(9, false));   // n = 162
        cases.push_back(pyramid2d(4, true));    // n = 128
        cases.push_back(column2d(10, false));   // n = 20
        cases.push_back(cubeStack3d(10));       // n = 40
        cases.push_back(cradleChain(10, 0.5));  // n = 9
        cases.push_back(murty(8));              // 256 pivots
        cases.push_back(lowerLLT(12, false));   // 4096 pivots on the exact path
        cases.push_back(lowerLLT(50, true));
        cases.push_back(jammedParticle(0.5));
        cases.push_back(squeezedParticle(0.5));
        return cases;
    }
    for (int rows : {9, 13, 17, 20}) cases.push_back(pyramid2d(rows, false));  // n = 162, 338, 578, 800
    cases.push_back(nondegenerate(pyramid2d(20, false)));                     // n = 800, ties removed
    for (int rows : {5, 7, 10}) cases.push_back(pyramid2d(rows, true));       // n = 200, 392, 800
    cases.push_back(column2d(20, false));                                      // n = 40
    cases.push_back(column2d(20, true));                                       // n = 160
    for (int count : {25, 50, 100}) cases.push_back(cubeStack3d(count));        // n = 100, 200, 400
    cases.push_back(nondegenerate(cubeStack3d(100)));
    cases.push_back(cubeStack3d(25, true));                                    // n = 600
    cases.push_back(cradleChain(10, 0.5));
    cases.push_back(cradleChain(50, 0.5));
    cases.push_back(murty(10));
    cases.push_back(murty(16));
    cases.push_back(lowerLLT(50, false));
    cases.push_back(lowerLLT(200, false));
    cases.push_back(lowerLLT(50, true));
    cases.push_back(lowerLLT(200, true));
    cases.push_back(jammedParticle(0.5));
    cases.push_back(squeezedParticle(0.5));
    return cases;
}

}  // namespace unison::scenes
