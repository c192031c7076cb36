// resolver2d/world2d_checks.cpp — what a 2D world accepts (world2d_checks.h), and the check after every step that its
// numbers are still finite (World2::fault()).
//
// Why the step check: inputs within core/input_policy.h keep every number many orders of magnitude below overflow,
// but a world built through the C++ API with settings outside it (dt = 1e300, say) could be flung to infinity. A
// NaN must not then travel on silently: the next step would sort bounding boxes of NaN (undefined behaviour in
// std::sort) and print `null` for positions. The check is the state range of restore() (finite, positions within
// 1e9 m, speeds within 1e9), so every state a step leaves behind without a fault restores from its snapshot. It
// reads the hot records only (9 doubles per body), so it costs nothing next to the step; the slow named-field walk
// runs only once something is wrong, to say which field.
#include "world2d_checks.h"

#include "input_policy.h"

#include <cmath>

namespace unison {

namespace {

bool within(Vec2 v, double limit) { return policy::within(v.x, limit) && policy::within(v.y, limit); }

std::string checkPolygon(const Polygon& p) {
    if (p.count < 3 || p.count > kMaxPolygonVertices) return "polygon: vertex count out of range";
    const std::size_t n = std::size_t(p.count);
    double scale = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!within(p.vertices[i], policy::kMaxCoordinate)) return "polygon: vertices must be within the coordinate range";
        scale = std::max(scale, std::max(std::fabs(p.vertices[i].x), std::fabs(p.vertices[i].y)));
    }
    const double tol = 1e-9 * std::max(scale, 1e-3);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2 a = p.vertices[i], e = p.vertices[(i + 1) % n] - a, nrm = p.normals[i];
        const double len = length(e);
        if (!(len > 0.0)) return "polygon: repeated vertex";
        if (!(std::fabs(dot(nrm, nrm) - 1.0) <= 1e-9) || !(std::fabs(dot(nrm, e)) <= 1e-9 * len) || !(cross(e, nrm) < 0.0))
            return "polygon: normal " + std::to_string(i) + " is not the outward unit normal of its edge";
        for (std::size_t j = 0; j < n; ++j)
            if (dot(nrm, p.vertices[j] - a) > tol) return "polygon: not convex and counter-clockwise";
        if (!(dot(nrm, p.centroid - a) < 0.0)) return "polygon: centroid outside";
    }
    return {};
}

}  // namespace

std::string checkShape2(const Shape2& s) {
    if (!policy::inRange(s.density, 0.0, policy::kMaxDensity) || !policy::inRange(s.friction, 0.0, policy::kMaxFriction) ||
        !policy::inRange(s.restitution, 0.0, 1.0))
        return "shape: density, friction or restitution out of range";
    switch (s.type) {
        case ShapeType::circle:
            if (!policy::inRange(s.circle.radius, policy::kMinSize, policy::kMaxSize)) return "circle: radius out of range";
            if (!within(s.circle.center, policy::kMaxCoordinate)) return "circle: centre out of range";
            return {};
        case ShapeType::polygon: return checkPolygon(s.polygon);
        case ShapeType::segment:
            if (!within(s.segment.p1, policy::kMaxCoordinate) || !within(s.segment.p2, policy::kMaxCoordinate))
                return "segment: points out of range";
            if (!(length(s.segment.p2 - s.segment.p1) > 0.0)) return "segment: points must be distinct";
            return {};
    }
    return "shape: unknown type";
}

std::string checkBodyDef2(const BodyDef2& def, const std::vector<Shape2>& shapes) {
    if (!within(def.position, policy::kMaxCoordinate) || !policy::within(def.angle, policy::kMaxAngle) ||
        !within(def.linearVelocity, policy::kMaxSpeed) || !policy::within(def.angularVelocity, policy::kMaxAngularSpeed))
        return "body: position, angle and velocities must be finite and within the input policy's ranges";
    if (shapes.size() > policy::kMaxShapesPerBody) return "body: too many shapes";
    for (std::size_t k = 0; k < shapes.size(); ++k) {
        const std::string why = checkShape2(shapes[k]);
        if (!why.empty()) return "body: shape " + std::to_string(k) + ": " + why;
    }
    return {};
}

std::string checkMotion2(const BodyState2& s) {
    if (!within(s.position, policy::kMaxStateCoordinate) || !within(s.center, policy::kMaxStateCoordinate))
        return "position outside the supported range (|x| <= 1e9 m)";
    if (!within(s.velocity, policy::kMaxStateSpeed) || !policy::within(s.angularVelocity, policy::kMaxStateSpeed))
        return "velocity outside the supported range (|v| <= 1e9)";
    if (!std::isfinite(s.rotation.c) || !std::isfinite(s.rotation.s)) return "rotation is not finite";
    return {};
}

std::string checkBodyRecord2(const BodyState2& s, const BodyInfo2& info) {
    const std::string motion = checkMotion2(s);
    if (!motion.empty()) return "body: " + motion;
    if (!(std::fabs(s.rotation.c * s.rotation.c + s.rotation.s * s.rotation.s - 1.0) <= 1e-6))
        return "body: rotation is not a unit (cos, sin) pair";
    if (info.type == BodyType::dynamicBody) {
        if (!(info.mass > 0.0) || info.invMass != 1.0 / info.mass) return "body: dynamic mass must be > 0 with invMass = 1/mass";
        if (!(info.inertia >= 0.0) || info.invInertia != (info.inertia > 0.0 ? 1.0 / info.inertia : 0.0))
            return "body: inertia must be >= 0 with invInertia = 1/inertia";
    } else if (info.mass != 0.0 || info.invMass != 0.0 || info.inertia != 0.0 || info.invInertia != 0.0) {
        return "body: a static or kinematic body has no mass or inertia";
    }
    if (!(info.sleepTime >= 0.0)) return "body: sleep time must be >= 0";
    if (info.shapes.size() > policy::kMaxShapesPerBody) return "body: too many shapes";
    for (const Shape2& shape : info.shapes) {
        const std::string why = checkShape2(shape);
        if (!why.empty()) return why;
    }
    return {};
}

std::string World2::findFault() const {
    return stepFault(mBodies, mStepCount, checkMotion2, [this] { return stateFields(); });
}

}  // namespace unison
