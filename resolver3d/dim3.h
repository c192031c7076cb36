// resolver3d/dim3.h — the 3D body-math trait of the dimension-generic core (core/contact_resolver.h), on Eigen.
//
// Angular quantities are 3-vectors and the inverse inertia is a world-frame 3x3 matrix. Eigen's vectorisation is
// disabled for the simulation (EIGEN_DONT_VECTORIZE from unison_determinism) so that the order of every sum is the
// same in every build.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace unison {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

struct Dim3 {
    static constexpr int kDim = 3;
    using Vec = Vec3;
    using Ang = Vec3;
    using InvInertia = Mat3;

    static Vec zeroVec() { return Vec3::Zero(); }
    static Ang zeroAng() { return Vec3::Zero(); }
    static InvInertia zeroInvInertia() { return Mat3::Zero(); }

    static double dot(const Vec& a, const Vec& b) { return a.x() * b.x() + a.y() * b.y() + a.z() * b.z(); }
    /// r x n, eq. (17): r* n.
    static Ang cross(const Vec& r, const Vec& n) {
        return Vec3(r.y() * n.z() - r.z() * n.y(), r.z() * n.x() - r.x() * n.z(), r.x() * n.y() - r.y() * n.x());
    }
    static Vec angularVelocityAt(const Ang& w, const Vec& r) { return cross(w, r); }
    static Ang applyInvInertia(const InvInertia& invI, const Ang& a) {
        return Vec3(invI(0, 0) * a.x() + invI(0, 1) * a.y() + invI(0, 2) * a.z(),
                    invI(1, 0) * a.x() + invI(1, 1) * a.y() + invI(1, 2) * a.z(),
                    invI(2, 0) * a.x() + invI(2, 1) * a.y() + invI(2, 2) * a.z());
    }
    static double angDot(const Ang& a, const Ang& b) { return dot(a, b); }
    /// The angular parts of two rows couple as angDot(right_i, left_j) (core/contact_resolver_impl.h, Coupling).
    /// In 3D both halves are L^T a, L the Cholesky factor of I^-1 = L L^T (couplingFactor), so that the coupling
    /// term is one dot product of two vectors and A_ij equals A_ji bit for bit (r_i . I^-1 r_j and r_j . I^-1 r_i
    /// round differently): the LCP's contact block is then exactly symmetric and can be factorised by LDL^T.
    static InvInertia couplingFactor(const InvInertia& invI);
    /// The coupling block is symmetric bit for bit (SparseLcp::symmetricHint).
    static constexpr bool kExactCoupling = true;
    /// Warm guesses are checked from the guess's block of A and w = J M^-1 J^T z + ... formed per body
    /// (LemkeSolver::checkGuess with a product): the guessed columns of all the other rows are never built.
    static constexpr bool kMatrixFreeCheck = true;
    static void couplingHalves(const InvInertia& factor, const Ang& a, Ang& left, Ang& right) {
        // L^T a, L lower triangular.
        left = Vec3(factor(0, 0) * a.x() + factor(1, 0) * a.y() + factor(2, 0) * a.z(),
                    factor(1, 1) * a.y() + factor(2, 1) * a.z(), factor(2, 2) * a.z());
        right = left;
    }
    static Vec scale(double s, const Vec& v) { return Vec3(s * v.x(), s * v.y(), s * v.z()); }
    static Vec add(const Vec& a, const Vec& b) { return Vec3(a.x() + b.x(), a.y() + b.y(), a.z() + b.z()); }
    static Vec sub(const Vec& a, const Vec& b) { return Vec3(a.x() - b.x(), a.y() - b.y(), a.z() - b.z()); }
    static Ang angScale(double s, const Ang& a) { return scale(s, a); }
    static Ang angAdd(const Ang& a, const Ang& b) { return add(a, b); }
    static bool finite(const Vec& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }
    static bool angFinite(const Ang& a) { return finite(a); }
    /// Every component finite and within +-limit (core/input_policy.h ranges).
    static bool componentsWithin(const Vec& v, double limit) {
        return within(v.x(), limit) && within(v.y(), limit) && within(v.z(), limit);
    }
    static bool angComponentsWithin(const Ang& a, double limit) { return componentsWithin(a, limit); }
    static bool within(double x, double limit) { return std::isfinite(x) && std::fabs(x) <= limit; }
    /// |omega| <= tol (a world's sleep test), compared in squares.
    static bool angWithin(const Ang& a, double tol) { return dot(a, a) <= tol * tol; }
    /// |omega| (rad/s).
    static double angNorm(const Ang& a) { return std::sqrt(dot(a, a)); }
    /// (s, s, s).
    static Vec uniform(double s) { return Vec3(s, s, s); }
    /// The vector of kDim components at p (e.g. one contact's tangent impulse in Resolution::tangentImpulses).
    static Vec fromComponents(const double* p) { return Vec3(p[0], p[1], p[2]); }
    static bool invInertiaValid(const InvInertia& m) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                if (!std::isfinite(m(i, j))) return false;
            }
            if (m(i, i) < 0.0) return false;
        }
        return true;
    }
    static bool invInertiaZero(const InvInertia& m) { return m.isZero(0.0); }
    /// 3D pyramids use an even number k >= 4 of directions: k/2 evenly spaced tangents and their negatives.
    static int frictionDirectionCount(int requested) { return requested < 4 ? 4 : requested + (requested & 1); }
    static Vec tangentDirection(const Vec& n, int index, int k);
};

}  // namespace unison
