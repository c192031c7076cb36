// resolver2d/dim2.h — the 2D body-math trait of the dimension-generic core (core/contact_resolver.h).
//
// In the plane an angular quantity is a scalar (rotation about z) and the inverse inertia is a scalar too:
// r x n = r.x n.y - r.y n.x, and omega x r = (-omega r.y, omega r.x).
#pragma once

#include <cmath>

namespace unison {

/// A 2D vector (metres, m/s, or a unit direction, by context). 16 bytes, no padding.
struct Vec2 {
    double x = 0.0;
    double y = 0.0;
    double operator[](int i) const { return i == 0 ? x : y; }
};
static_assert(sizeof(Vec2) == 16, "Vec2 is two doubles");

inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator-(Vec2 a) { return {-a.x, -a.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline Vec2 operator*(Vec2 a, double s) { return {s * a.x, s * a.y}; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
/// omega x r for a scalar angular velocity omega about z.
inline Vec2 cross(double w, Vec2 r) { return {-w * r.y, w * r.x}; }
inline double lengthSquared(Vec2 a) { return dot(a, a); }
inline double length(Vec2 a) { return std::sqrt(dot(a, a)); }

struct Dim2 {
    static constexpr int kDim = 2;
    using Vec = Vec2;
    using Ang = double;         ///< angular velocity or r x f about z
    using InvInertia = double;  ///< 1 / (kg m^2)

    static Vec zeroVec() { return {}; }
    static Ang zeroAng() { return 0.0; }
    static InvInertia zeroInvInertia() { return 0.0; }

    static double dot(const Vec& a, const Vec& b) { return unison::dot(a, b); }
    static Ang cross(const Vec& r, const Vec& n) { return unison::cross(r, n); }
    /// omega x r: velocity of a point at offset r due to rotation.
    static Vec angularVelocityAt(const Ang& w, const Vec& r) { return unison::cross(w, r); }
    static Ang applyInvInertia(const InvInertia& invI, const Ang& a) { return invI * a; }
    static double angDot(const Ang& a, const Ang& b) { return a * b; }
    /// The angular parts of two rows couple as angDot(right_i, left_j) (core/contact_resolver_impl.h, Coupling):
    /// in 2D left = a and right = I^-1 a with the factor I^-1 itself.
    static InvInertia couplingFactor(const InvInertia& invI) { return invI; }
    /// (I^-1 a_i) a_j and (I^-1 a_j) a_i round differently: the 2D coupling block is not symmetric bit for bit.
    static constexpr bool kExactCoupling = false;
    /// Warm guesses are checked on A's guessed columns (LemkeSolver::checkGuess without a product): the 2D targets
    /// were measured so, and the answers are those of solve() bit for bit.
    static constexpr bool kMatrixFreeCheck = false;
    static void couplingHalves(const InvInertia& factor, const Ang& a, Ang& left, Ang& right) {
        left = a;
        right = factor * a;
    }
    static Vec scale(double s, const Vec& v) { return s * v; }
    static Vec add(const Vec& a, const Vec& b) { return a + b; }
    static Vec sub(const Vec& a, const Vec& b) { return a - b; }
    static Ang angScale(double s, const Ang& a) { return s * a; }
    static Ang angAdd(const Ang& a, const Ang& b) { return a + b; }
    static bool finite(const Vec& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
    static bool angFinite(const Ang& a) { return std::isfinite(a); }
    /// Every component finite and within +-limit (core/input_policy.h ranges).
    static bool componentsWithin(const Vec& v, double limit) { return within(v.x, limit) && within(v.y, limit); }
    static bool angComponentsWithin(const Ang& a, double limit) { return within(a, limit); }
    static bool within(double x, double limit) { return std::isfinite(x) && std::fabs(x) <= limit; }
    /// |omega| <= tol (a world's sleep test).
    static bool angWithin(const Ang& a, double tol) { return std::fabs(a) <= tol; }
    /// |omega| (rad/s).
    static double angNorm(const Ang& a) { return std::fabs(a); }
    /// (s, s).
    static Vec uniform(double s) { return {s, s}; }
    /// The vector of kDim components at p (e.g. one contact's tangent impulse in Resolution::tangentImpulses).
    static Vec fromComponents(const double* p) { return {p[0], p[1]}; }
    static bool invInertiaValid(const InvInertia& i) { return std::isfinite(i) && i >= 0.0; }
    static bool invInertiaZero(const InvInertia& i) { return i == 0.0; }
    /// The k friction directions of a 2D contact: always +t and -t with t = perp(n) (the 2D pyramid is exact).
    static int frictionDirectionCount(int) { return 2; }
    static Vec tangentDirection(const Vec& n, int index, int) {
        Vec t{-n.y, n.x};
        return index == 0 ? t : -t;
    }
};

}  // namespace unison
