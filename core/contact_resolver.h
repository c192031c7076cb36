// core/contact_resolver.h — the paper's multiple-point collision resolver, written once for 2D and 3D.
//
// Owns: contact nodes (the paper's section 3: point, body A, body B, normal pointing away from B towards A,
// restitution), the assembly of the collision LCP (A per eq. (20), b per eq. (19)), its Coulomb-friction
// extension (a Stewart–Trinkle / Anitescu–Potra pyramid in the same LCP), the single-contact closed form and the
// application of the impulses to body velocities (eq. (15)).
//
// The dimension enters only through a trait `D` (resolver2d/dim2.h, resolver3d/dim3.h) that says what a vector,
// an angular quantity and an inverse inertia are, and how r x n and I^-1 act. Static and kinematic bodies are
// bodies with zero inverse mass and zero inverse inertia: the paper's "dummy rigid body of infinite mass".
//
// Invariants: rows are numbered in input order; every loop runs in index order, so the assembled LCP is a pure
// function of the input (no pointer order, no hash order).
#pragma once

#include <unison/lcp.h>

#include <cstdint>
#include <string>
#include <vector>

namespace unison {

class SymmetricPatternCache;  // core/symmetric_pattern_lu.h
struct ActiveSetScratch;      // core/body_space_solve.h

/// State of one body as the resolver sees it (SI units). For a static body set invMass = 0 and invInertia = 0.
template <class D>
struct ResolverBody {
    double invMass = 0.0;                            ///< 1 / kg (0 = infinite mass)
    typename D::InvInertia invInertia = D::zeroInvInertia();  ///< world-frame inverse inertia, 1 / (kg m^2)
    typename D::Vec position = D::zeroVec();         ///< centre of mass x (m)
    typename D::Vec velocity = D::zeroVec();         ///< v (m/s)
    typename D::Ang angularVelocity = D::zeroAng();  ///< omega (rad/s)
};

/// The paper's contact node. When more than two bodies meet at one point, make one node per colliding pair.
template <class D>
struct ContactNode {
    int a = -1;                          ///< body A (receives +f n)
    int b = -1;                          ///< body B (receives -f n)
    typename D::Vec point = D::zeroVec();   ///< common contact point p (m), world frame
    typename D::Vec normal = D::zeroVec();  ///< unit normal, pointing away from B towards A
    double restitution = 0.0;            ///< coefficient of restitution e of this point, in [0, 1]
    double friction = 0.0;               ///< Coulomb coefficient mu (used only by the friction LCP)
    double bias = 0.0;                   ///< separation speed the node must reach (m/s): b_i -= bias. Positive
                                         ///< pushes apart (position correction), negative lets a speculative
                                         ///< contact still close its gap (-separation / dt)
};

/// A node from its parts (the paper's section 3 list): bodies a and b, point, normal away from b, e and mu.
template <class D>
ContactNode<D> makeContact(int a, int b, const typename D::Vec& point, const typename D::Vec& normal,
                           double restitution = 0.0, double friction = 0.0) {
    ContactNode<D> c;
    c.a = a;
    c.b = b;
    c.point = point;
    c.normal = normal;
    c.restitution = restitution;
    c.friction = friction;
    return c;
}

struct ResolverOptions {
    /// Approach speeds (m/s) at or below this use e = 0: "slower or resting contacts" of DESIGN.md step 5.
    /// The paper's pure impulse model is threshold 0.
    double restitutionThreshold = 0.0;
    /// Tangent directions per contact in the friction pyramid (2D: always 2, +t and -t; 3D: even, >= 4).
    int frictionDirections = 4;
    /// Tangential relative speeds at or below this (m/s) count as exactly zero in the friction LCP. Resting stacks
    /// carry rounding-level creep (~1e-9 m/s) that makes Lemke end on a secondary ray; a world sets ~1e-8.
    double tangentDeadZone = 0.0;
    /// Also apply an answer whose solve ended `numerical_failure` when its scaled complementarity residual is at
    /// most this (0: never). The Lemke solver ends that way when the answer of its tie-breaking perturbation misses
    /// the true problem by more than LcpOptions::residualTolerance and no continuation did better; such an answer
    /// is still an exact solution of an LCP within ~1e-7 of the given one.
    double acceptResidual = 0.0;
    LcpOptions lcp;
};

/// Layout of a friction LCP built by assembleFrictionLcp: for nc contacts and k directions,
/// unknowns are [normal impulses (nc) | tangential impulses (nc*k, contact-major) | slacks lambda (nc)].
struct FrictionLayout {
    int contacts = 0;
    int directions = 0;
    int normalOffset() const { return 0; }
    int tangentOffset() const { return contacts; }
    int slackOffset() const { return contacts + contacts * directions; }
    int size() const { return contacts * (directions + 2); }
};

struct Resolution {
    LcpStatus status = LcpStatus::invalid_input;
    int pivots = 0;
    std::uint64_t work = 0;
    double residual = 0.0;
    double scaledResidual = 0.0;
    bool approximate = false;      ///< the impulses are a `numerical_failure` answer accepted by acceptResidual
    bool fastPath = false;         ///< true when the single-contact closed form was used
    bool warmStarted = false;      ///< a guess was given and the answer came from it (not from a cold restart)
    bool activeSet = false;        ///< the answer came from the active-set path (resolveActiveSet)
    bool interiorPoint = false;    ///< resolveActiveSet restarted from the interior-point answer (ActiveSetOptions)
    bool warmFace = false;         ///< active-set answers: certified on the face of the warm start (its phase 0)
    /// Active-set path: the system patterns it analysed (an ordering and elimination tree each; found in the
    /// pattern cache or computed), and the factorisations it ran on a larger analysed pattern instead
    /// (ActiveSetOptions::reuseSupersetPattern).
    int patternAnalyses = 0, supersetFactorizations = 0;
    std::vector<double> impulses;  ///< normal impulse magnitude f_i per contact node (N s)
    std::vector<double> tangentImpulses;  ///< friction solves only: (contacts x dimension) world-frame vectors
    std::vector<int> basis;        ///< Lemke basis, to warm-start the next solve
    /// Active-set answers with ActiveSetOptions::incomingVelocity: per contact the normal impulse, then the D::kDim
    /// friction-impulse components (world frame), that the next step needs on the same face if only the bodies'
    /// velocities change (empty when not computed). What a world carries to the next step's warm start.
    std::vector<double> predictedImpulses;
    std::string message;
};

/// Relative normal velocity of contact c before the impulses, eq. (4): v_rel = n . (p'_A - p'_B), with
/// p' = v + omega x r (eq. (2)). Negative means approaching.
template <class D>
double relativeNormalVelocity(const std::vector<ResolverBody<D>>& bodies, const ContactNode<D>& c);

/// Checks bodies and nodes (indices in range, A != B, finite values, unit normals, 0 <= e <= 1, mu >= 0,
/// non-negative inverse masses). Returns an empty string when valid, else a message naming the bad item.
template <class D>
std::string validate(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts);

/// Builds the frictionless collision LCP: A per eq. (20) and b per eq. (19), so that w = A f + b is
/// v_rel^+ + e v_rel^- of every node (eq. (18), (21)).
template <class D>
Lcp assembleCollisionLcp(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                         const ResolverOptions& options = {});

/// The same LCP in compressed rows (bit-identical values): what the resolver and the worlds solve.
template <class D>
SparseLcp assembleCollisionLcpSparse(const std::vector<ResolverBody<D>>& bodies,
                                     const std::vector<ContactNode<D>>& contacts, const ResolverOptions& options = {});

/// Builds the Coulomb-pyramid LCP (normal rows as in assembleCollisionLcp, tangent rows D^T v^+ + lambda,
/// slack rows mu f_n - sum beta). The matrix is not symmetric. See FrictionLayout for the unknowns.
template <class D>
Lcp assembleFrictionLcp(const std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                        const ResolverOptions& options, FrictionLayout* outLayout = nullptr);

/// The friction LCP in compressed rows (bit-identical values).
template <class D>
SparseLcp assembleFrictionLcpSparse(const std::vector<ResolverBody<D>>& bodies,
                                    const std::vector<ContactNode<D>>& contacts, const ResolverOptions& options,
                                    FrictionLayout* outLayout = nullptr);

/// Tangent directions used by the friction LCP for contact c (k unit vectors, in pairs +t, -t).
template <class D>
std::vector<typename D::Vec> frictionDirections(const ContactNode<D>& c, int k);

/// Applies impulse f_i n_i to A and -f_i n_i to B of every node (eq. (15)); `tangent` (optional, contacts x
/// vectors) adds friction impulses the same way.
template <class D>
void applyImpulses(std::vector<ResolverBody<D>>& bodies, const std::vector<ContactNode<D>>& contacts,
                   const std::vector<double>& impulses,
                   const std::vector<typename D::Vec>* tangent = nullptr);

/// The paper's resolver: validate, assemble eq. (19)/(20), solve with Lemke (one node: the closed form
/// f = max(0, -b/A)), and on success apply the impulses to `ioBodies`. On failure the bodies are untouched.
template <class D>
Resolution resolveCollisions(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& contacts,
                             const ResolverOptions& options, LemkeSolver& solver);

/// Same with Coulomb friction: normal and tangential impulses from one friction LCP.
template <class D>
Resolution resolveWithFriction(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& contacts,
                               const ResolverOptions& options, LemkeSolver& solver);

/// Caps of the active-set fast path (resolveActiveSet).
struct ActiveSetOptions {
    int maxIterations = 12;          ///< iterations of the active-set phase (one sparse factorisation each)
    std::uint64_t maxWork = 0;       ///< stop once this many work units are spent (0: no limit)
    /// Analyses of system patterns kept between calls (nullptr: none); it changes the cost, never the answer.
    SymmetricPatternCache* patternCache = nullptr;
    /// Buffers and systems kept between calls (nullptr: none): 2D the last system, 3D the 8 most recently used island
    /// systems (core/body_space_solve.h). It changes the cost, never the answer or the work units.
    ActiveSetScratch* scratch = nullptr;
    /// When the warm start's face does not hold and its best iterate is far from an answer (more than 10 tolerances),
    /// or (2D) the warm start itself is (more than 1000), restart once from the interior-point answer of the problem's
    /// convex relaxation (docs/solver.md; in 3D a trial of phase 1 comes first unless the face left the island more
    /// than 1e5 tolerances off).
    bool interiorPoint = true;
    /// With interiorPoint: a cold start (every warm impulse 0) begins with the interior-point answer instead of the
    /// primal-dual iteration from zero impulses. It certifies contact LCPs that the iteration from zero does not
    /// (Box2D's manifolds of settled pyramids); a world's islands go without it (docs/solver.md, "Landing piles").
    bool coldInteriorPoint = true;
    /// When > 0: a solve whose phase 0 (the warm start's face) ends uncertified with its best iterate within this
    /// many tolerances, and within options.acceptResidual, ends there as a near miss instead of running phases 1
    /// and 2 (which change the face; a miss this close is the face's numerical floor, not a wrong face).
    double floorExit = 0.0;
    /// On a kept face (phases 0 and 2), a contact on its cone's rim that slides the way its friction impulse pushes
    /// (u_t of p_t's sign beyond half a tolerance, which the LCP forbids) sticks in the next step instead of
    /// slipping on.
    bool stickWrongWaySlip = false;
    /// On a kept face (phases 0 and 2), factor the system of a subset of the unknowns last analysed (at most 1/16
    /// fewer) on that analysed pattern, with the dropped unknowns' entries stored as zeros, instead of analysing the
    /// subset's own pattern. Same step up to rounding; saves the analysis (ordering, elimination tree), which on a
    /// large island costs about as much as the factorisation.
    bool reuseSupersetPattern = false;
    /// Per body (ioBodies' order) the velocity it brought into the step, before this step's external forces (2D:
    /// vx, vy, omega; for a body the step does not accelerate, its velocity). When set and the answer is certified
    /// after an iteration factored its system, Resolution::predictedImpulses predicts the next step's impulses: the
    /// answer also stops the velocity v_in the bodies came in with, so carried unchanged it meets the next step's
    /// problem (bodies at v+) with the velocity error J (v+ - v_in), and a settled pile then alternates between
    /// accepting its warm start and re-solving. One more solve with the last factors takes that share out; a
    /// prediction that would release a contact or leave a cone is not made (docs/solver.md, "Settled islands").
    const std::vector<double>* incomingVelocity = nullptr;
};

/// The friction LCP of resolveWithFriction by an active-set (semismooth Newton) iteration in body space, started
/// from the impulses each contact carried last step: `warm` holds per contact its normal impulse and then its
/// D::kDim friction-impulse components (world frame). `solved` only when the Stewart–Trinkle LCP holds to
/// options.lcp.residualTolerance (the rule of every Lemke answer), with the bodies updated as resolveWithFriction
/// would; a best iterate within options.acceptResidual is applied as `numerical_failure` with `approximate` set (a
/// near miss, as Lemke's); otherwise `pivot_limit` and the bodies untouched, for Lemke to take over. `activeSet` is
/// set on every applied answer. 3D takes the pyramid of four directions (core/active_set3_impl.h: a box per contact
/// in the path's coordinates); other 3D pyramids are declined.
template <class D>
Resolution resolveActiveSet(std::vector<ResolverBody<D>>& ioBodies, const std::vector<ContactNode<D>>& contacts,
                            const std::vector<double>& warm, const ResolverOptions& options,
                            const ActiveSetOptions& settings);

}  // namespace unison
