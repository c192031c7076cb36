// resolver3d/world3d_checks.cpp — what a 3D world accepts (world3d_checks.h), and the check after every step that
// its numbers are still finite (World3::fault(); the reasons are those of resolver2d/world2d_checks.cpp).
#include "world3d_checks.h"

#include "hull3d.h"
#include "input_policy.h"

#include <Eigen/Cholesky>

#include <cmath>
#include <cstring>

namespace unison {

namespace {

using D3 = Dim3;

bool within(const Vec3& v, double limit) {
    return policy::within(v.x(), limit) && policy::within(v.y(), limit) && policy::within(v.z(), limit);
}

bool sameBits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0; }

/// True when a and b hold the same numbers bit for bit (a box's polyhedron is a function of its half extents).
bool samePolyhedron(const ConvexPolyhedron& a, const ConvexPolyhedron& b) {
    if (a.vertices.size() != b.vertices.size() || a.faces.size() != b.faces.size() || a.edges.size() != b.edges.size())
        return false;
    for (std::size_t i = 0; i < a.vertices.size(); ++i)
        if (!sameBits(a.vertices[i], b.vertices[i])) return false;
    for (std::size_t f = 0; f < a.faces.size(); ++f) {
        const auto &x = a.faces[f], &y = b.faces[f];
        if (!sameBits(x.normal, y.normal) || std::memcmp(&x.offset, &y.offset, sizeof x.offset) != 0 || x.loop != y.loop)
            return false;
    }
    for (std::size_t e = 0; e < a.edges.size(); ++e) {
        const auto &x = a.edges[e], &y = b.edges[e];
        if (x.v0 != y.v0 || x.v1 != y.v1 || x.face0 != y.face0 || x.face1 != y.face1) return false;
    }
    return sameBits(a.centroid, b.centroid);
}

}  // namespace

std::string checkShape3(const Shape3& s) {
    if (!policy::inRange(s.density, 0.0, policy::kMaxDensity) || !policy::inRange(s.friction, 0.0, policy::kMaxFriction) ||
        !policy::inRange(s.restitution, 0.0, 1.0))
        return "shape: density, friction or restitution out of range";
    switch (s.type) {
        case ShapeType3::sphere:
            if (!policy::inRange(s.radius, policy::kMinSize, policy::kMaxSize)) return "sphere: radius out of range";
            if (!within(s.center, policy::kMaxCoordinate)) return "sphere: centre out of range";
            return {};
        case ShapeType3::box: {
            if (!policy::inRange(s.halfExtents.minCoeff(), policy::kMinSize, policy::kMaxSize) ||
                !policy::inRange(s.halfExtents.maxCoeff(), policy::kMinSize, policy::kMaxSize))
                return "box: half extents out of range";
            if (!within(s.center, policy::kMaxCoordinate)) return "box: centre out of range";
            Shape3 box;
            if (!s.poly || !makeBox(s.halfExtents, s.center, &box).empty() || !samePolyhedron(*s.poly, *box.poly))
                return "box: its polyhedron is not the one its half extents and centre make";
            return {};
        }
        case ShapeType3::hull: {
            if (!s.poly) return "hull: no polyhedron";
            for (const Vec3& v : s.poly->vertices)
                if (!within(v, policy::kMaxCoordinate)) return "hull: vertices out of range";
            const std::string why = checkPolyhedron(*s.poly);
            return why.empty() ? why : "hull: " + why;
        }
        case ShapeType3::plane:
            if (!(std::fabs(D3::dot(s.normal, s.normal) - 1.0) < 1e-9)) return "plane: normal must have unit length";
            if (!policy::within(s.offset, policy::kMaxCoordinate)) return "plane: offset out of range";
            return {};
        case ShapeType3::mesh:
            if (!s.mesh) return "mesh: no mesh";
            if (s.mesh->vertices.size() > policy::kMaxMeshVertices || s.mesh->triangles.size() > policy::kMaxMeshTriangles)
                return "mesh: too many vertices or triangles";
            for (const Vec3& v : s.mesh->vertices)
                if (!within(v, policy::kMaxCoordinate)) return "mesh: vertices out of range";
            return {};
    }
    return "shape: unknown type";
}

std::string checkBodyDef3(const BodyDef3& def, const std::vector<Shape3>& shapes) {
    const Quat& q = def.orientation;
    if (!within(def.position, policy::kMaxCoordinate) || !within(def.linearVelocity, policy::kMaxSpeed) ||
        !within(def.angularVelocity, policy::kMaxAngularSpeed) || !policy::within(q.w, policy::kMaxCoordinate) ||
        !policy::within(q.x, policy::kMaxCoordinate) || !policy::within(q.y, policy::kMaxCoordinate) ||
        !policy::within(q.z, policy::kMaxCoordinate))
        return "body: position, orientation and velocities must be finite and within the input policy's ranges";
    if (shapes.size() > policy::kMaxShapesPerBody) return "body: too many shapes";
    for (std::size_t k = 0; k < shapes.size(); ++k) {
        const std::string why = checkShape3(shapes[k]);
        if (!why.empty()) return "body: shape " + std::to_string(k) + ": " + why;
    }
    return {};
}

std::string checkInertia3(const Mat3& I) {
    // A positive determinant alone also passes a tensor with two negative eigenvalues (a self-intersecting mesh
    // whose signed volume is still positive); a Cholesky factorisation only succeeds for positive definite ones.
    const double big = I.cwiseAbs().maxCoeff();
    if (!I.allFinite() || !((I - I.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * big) ||
        Eigen::LLT<Mat3>(I).info() != Eigen::Success || !(I.determinant() > 0.0))
        return "body: inertia tensor must be symmetric positive definite";
    return {};
}

std::string checkInverseInertia3(const Mat3& I, const Mat3& invI) {
    const Mat3 product = I * invI;
    if (!((product - Mat3::Identity()).cwiseAbs().maxCoeff() <= 1e-6)) return "body: invInertia is not the inverse of inertia";
    return {};
}

std::string checkMotion3(const BodyState3& s) {
    if (!within(s.position, policy::kMaxStateCoordinate) || !within(s.center, policy::kMaxStateCoordinate))
        return "position outside the supported range (|x| <= 1e9 m)";
    if (!within(s.velocity, policy::kMaxStateSpeed) || !within(s.angularVelocity, policy::kMaxStateSpeed))
        return "velocity outside the supported range (|v| <= 1e9)";
    const Quat& q = s.rotation;
    if (!std::isfinite(q.w) || !std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) return "rotation is not finite";
    return {};
}

std::string checkBodyRecord3(const BodyState3& s, const BodyInfo3& info) {
    const std::string motion = checkMotion3(s);
    if (!motion.empty()) return "body: " + motion;
    const Quat& q = s.rotation;
    if (!(std::fabs(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z - 1.0) <= 1e-6)) return "body: rotation is not a unit quaternion";
    if (info.type == BodyType::dynamicBody) {
        if (!(info.mass > 0.0) || info.invMass != 1.0 / info.mass) return "body: dynamic mass must be > 0 with invMass = 1/mass";
        const Mat3& I = info.inertia;
        const std::string inertia = checkInertia3(I);
        if (!inertia.empty()) return inertia;
        const std::string inverse = checkInverseInertia3(I, info.invInertia);
        if (!inverse.empty()) return inverse;
    } else if (info.mass != 0.0 || info.invMass != 0.0 || !info.inertia.isZero(0.0) || !info.invInertia.isZero(0.0)) {
        return "body: a static or kinematic body has no mass or inertia";
    }
    if (!(info.sleepTime >= 0.0)) return "body: sleep time must be >= 0";
    if (info.shapes.size() > policy::kMaxShapesPerBody) return "body: too many shapes";
    for (const Shape3& shape : info.shapes) {
        if (shape.type == ShapeType3::plane && info.type != BodyType::staticBody) return "body: planes must be static";
        const std::string why = checkShape3(shape);
        if (!why.empty()) return why;
    }
    return {};
}

std::string World3::findFault() const {
    return stepFault(mBodies, mStepCount, checkMotion3, [this] { return stateFields(); });
}

}  // namespace unison
