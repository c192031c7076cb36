// scenes/lcp_families.h — named LCP test problems shared by tests, benchmarks and samples.
//
// Owns: generators of the "known hard inputs" of DESIGN.md (Murty's matrix, L L^T, coplanar cube stacks, friction
// LCPs from settled stacks, a jammed particle) and of the everyday contact problems they are measured against
// (settled 2D box pyramids and columns, Newton's cradle). Contact scenes are returned twice: as bodies + contact
// nodes (for resolver tests) and as the LCP that core/contact_resolver assembles from them (for solver tests).
//
// Invariants: every generator is a pure function of its arguments. No <random> distributions (their output differs
// between standard libraries), no unordered containers; positions are multiples of 0.25 m, so exact in binary.
// Static bodies come first (body 0 is the ground of every stack); dynamic bodies follow in row-major order, bottom
// row first, left to right. Contacts are listed in the same order; the upper (or struck) body is A.
#pragma once

#include "contact_resolver.h"
#include "dim2.h"
#include "dim3.h"
#include <unison/lcp.h>

#include <string>
#include <vector>

namespace unison::scenes {

/// A named LCP with the outcome a correct Lemke solver must report.
struct LcpCase {
    std::string name;          ///< e.g. "murty10", "pyramid20", "pyramid10_friction"
    Lcp lcp;                   ///< the problem: find z >= 0, w = A z + b >= 0, z.w = 0
    std::string expected;      ///< "solved" or "infeasible" (a mathematical fact about the LCP, not a guess)
    int expectedPivots = -1;   ///< pivots of cold Lemke with covering vector 1 when known in closed form, else -1
    /// True when the exact lexicographic pivot path is longer than LcpOptions::kDefaultMaxPivots (2^n paths for
    /// n >= 17): ending with `pivot_limit` is then an honest answer, not a failure.
    bool capAcceptable = false;
};

/// Bodies and contact nodes of a 2D contact scene.
struct Scene2 {
    std::vector<ResolverBody<Dim2>> bodies;
    std::vector<ContactNode<Dim2>> contacts;
};

/// Bodies and contact nodes of a 3D contact scene.
struct Scene3 {
    std::vector<ResolverBody<Dim3>> bodies;
    std::vector<ContactNode<Dim3>> contacts;
};

/// Gravity over one 60 Hz step (m/s): the downward speed every dynamic body of a "settled" scene carries.
constexpr double kSettledFallSpeed = 9.8 / 60.0;

// ---- Pure matrix families ----------------------------------------------------------------------------------

/// Murty's (1978) matrix: A_ii = 1, A_ij = 2 for j < i (lower triangular), A_ij = 0 above; b_i = -1 + 0.25 2^-(i+1),
/// i.e. Murty's b = -1 with its n-way first tie resolved the way the lexicographic rule resolves it, so the path
/// no longer depends on the tie rule. A is a P-matrix; the unique solution is z = (-b_0, 0, ..., 0). Lemke with
/// covering vector 1 walks 2^n bases: expectedPivots = 2^n counting the pivot where z0 enters (2^n - 1 after it);
/// -1 when n > 30. The transposed (upper-triangular) form is easy: 2 pivots for every n.
LcpCase murty(int n);

/// Fathi's symmetric positive definite family A = L L^T, L = I + 2 * (strict lower part of ones). b = -1, or,
/// when `mixedSigns`, a deterministic mixed-sign b in [-1, 1] from a 64-bit integer LCG. Always solvable (unique
/// solution). With b = -1 the solution is z = e_1 but exact lexicographic Lemke needs 2^n pivots (expectedPivots,
/// -1 when n > 30), so for large n an honest solver ends at its pivot cap; the mixed-sign b are easy.
LcpCase lowerLLT(int n, bool mixedSigns = false);

// ---- 2D contact scenes ---------------------------------------------------------------------------------------

/// Box2D-testbed pyramid of `rows` rows of 0.5 m boxes (density 1, mass 0.25 kg) resting exactly on a static
/// ground (top at y = 0): row i holds rows - i boxes, touching side by side, each resting on two boxes below.
/// Every touching interface has 2 contact points (the ends of the overlap), normal (0, 1), e = 0, mu = 0.6, and
/// every box falls at kSettledFallSpeed. Contacts: 2 rows (ground) + 4 per box above the bottom row = 2 rows^2.
Scene2 pyramid2dScene(int rows);

/// The pyramid's collision LCP (frictionless: n = 2 rows^2, e.g. 800 for 20 rows) or its Coulomb-pyramid LCP
/// (`friction`: n = 4 * contacts = 8 rows^2, e.g. 800 for 10 rows), as core/contact_resolver assembles them.
LcpCase pyramid2d(int rows, bool friction);

/// A vertical column of `count` 0.5 m boxes on the ground, same materials and velocities as the pyramid.
/// Contacts: 2 per interface = 2 count.
Scene2 column2dScene(int count);
LcpCase column2d(int count, bool friction = false);

/// Newton's cradle: `balls` equal balls (radius 0.5 m, mass 1 kg) touching in a row along x, the first moving at
/// 1 m/s into the others, restitution e, frictionless. n = balls - 1. Closed form (DESIGN.md): the first ball
/// leaves at 1 - (1 + e)(N - 1)/N, every other ball at (1 + e)/N.
Scene2 cradleChainScene(int balls, double restitution);
LcpCase cradleChain(int balls, double restitution);

/// A particle (mass 1) touching two static walls, moving at 1 m/s into the left one, restitution e on both
/// contacts. The scene is what a world step would hand the resolver; the LCP is built by hand in the DESIGN.md
/// convention (restitution only on approaching contacts) and is infeasible for every e > 0: see the .cpp proof.
Scene2 jammedParticleScene(double restitution);
LcpCase jammedParticle(double restitution = 0.5);

/// A particle at rest squeezed by two kinematic walls that both move towards it at 1 m/s. Assembled through
/// assembleCollisionLcp; infeasible for every e >= 0 and every convention for separating contacts (both
/// contacts approach).
Scene2 squeezedParticleScene(double restitution);
LcpCase squeezedParticle(double restitution = 0.5);

// ---- 3D contact scenes ---------------------------------------------------------------------------------------

/// `count` unit cubes (edge 1 m, mass 1 kg) stacked on a static ground, each interface touching at its 4 coplanar
/// corners (normal +z, e = 0, mu = 0.6), every cube falling at kSettledFallSpeed. A = J M^-1 J^T has rank 3 per
/// interface (singular), and b is degenerate (zero on every cube-cube row). Contacts: 4 count.
Scene3 cubeStack3dScene(int count);
/// Frictionless: n = 4 count. With friction (4 directions): n = 6 * 4 count.
LcpCase cubeStack3d(int count, bool friction = false);

// ---- Helpers -------------------------------------------------------------------------------------------------

/// The same LCP with every b_i lowered by a tiny index-dependent amount, delta * max|b| * (1 + frac(0.7548... i)).
/// Resting contacts (b_i = 0) then approach very slowly instead of not at all, which removes the exact ratio ties
/// of settled scenes. The benchmark uses it to time a peer that cannot solve the degenerate original. The
/// default delta stays far above the solver's own degeneracy perturbation (1e-7) so the two do not interact.
LcpCase nondegenerate(LcpCase c, double delta = 1e-4);

/// max_i |min(z_i, w_i)| with w = A z + b recomputed here, divided by max(max|A_ij|, max|b_i|) (1 if both are 0).
/// Returns +infinity when z has the wrong size or a non-finite entry.
double scaledResidual(const Lcp& lcp, const std::vector<double>& z);

/// The benchmark and test suite: every family above at the sizes bench/bench_lcp.cpp reports (`quick`: only the
/// small ones, for CI smoke runs). Order is fixed.
std::vector<LcpCase> standardCases(bool quick);

}  // namespace unison::scenes
