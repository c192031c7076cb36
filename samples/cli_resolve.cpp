// samples/cli_resolve.cpp — `unison resolve FILE.json`: reads bodies and contact nodes, runs the paper's resolver
// (with Coulomb friction when any node has "friction" > 0) and reports impulses and post-impact velocities.
#include "cli.h"
#include "resolver2d.h"
#include "resolver3d.h"

#include <Eigen/LU>

#include <cmath>

namespace unison::cli {
namespace {

Vec2 readVec(const nlohmann::json& v, const std::string& path, double limit, Dim2) {
    const auto x = jsonio::numbersWithin(v, path, 2, limit);
    return {x[0], x[1]};
}
Vec3 readVec(const nlohmann::json& v, const std::string& path, double limit, Dim3) {
    const auto x = jsonio::numbersWithin(v, path, 3, limit);
    return Vec3(x[0], x[1], x[2]);
}
double readAng(const nlohmann::json& v, const std::string& path, Dim2) {
    return jsonio::numberIn(v, path, -policy::kMaxAngularSpeed, policy::kMaxAngularSpeed);
}
Vec3 readAng(const nlohmann::json& v, const std::string& path, Dim3) {
    return readVec(v, path, policy::kMaxAngularSpeed, Dim3{});
}

double readInvInertia(const nlohmann::json& v, const std::string& path, Dim2) {
    const double I = number(v, path);
    if (!(I > 0.0)) throw InputError(path + ": inertia must be > 0");
    if (!(I >= policy::kMinInertia && I <= policy::kMaxInertia))
        throw InputError(path + ": must be in " + jsonio::rangeText(policy::kMinInertia, policy::kMaxInertia));
    return 1.0 / I;
}
Mat3 readInvInertia(const nlohmann::json& v, const std::string& path, Dim3) {
    if (!v.is_array() || v.size() != 3) throw InputError(path + ": expected 3 rows of 3 numbers");
    Mat3 I;
    for (int r = 0; r < 3; ++r) {
        const auto row = jsonio::numbersWithin(v[std::size_t(r)], path + "[" + std::to_string(r) + "]", 3, policy::kMaxInertia);
        for (int c = 0; c < 3; ++c) I(r, c) = row[std::size_t(c)];
    }
    if ((I - I.transpose()).cwiseAbs().maxCoeff() > 1e-9 * I.cwiseAbs().maxCoeff())
        throw InputError(path + ": inertia tensor must be symmetric");
    Eigen::LLT<Mat3> llt(I);
    if (llt.info() != Eigen::Success || !(I.diagonal().minCoeff() > 0.0))
        throw InputError(path + ": inertia tensor must be positive definite");
    if (!(I.diagonal().minCoeff() >= policy::kMinInertia))
        throw InputError(path + ": diagonal entries must be in " + jsonio::rangeText(policy::kMinInertia, policy::kMaxInertia));
    const Mat3 inv = I.inverse();
    if (!inv.allFinite()) throw InputError(path + ": inertia tensor is too close to singular");
    return inv;
}

nlohmann::json vecJson(const Vec2& v) { return {v.x, v.y}; }
nlohmann::json vecJson(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
nlohmann::json angJson(double w) { return w; }
nlohmann::json angJson(const Vec3& w) { return vecJson(w); }

template <class D>
CommandOutput resolveDim(const nlohmann::json& input, const std::string& what) {
    std::vector<ResolverBody<D>> bodies;
    std::vector<bool> statics;  // per body
    const auto& jb = jsonio::arrayUpTo(*member(input, what, "bodies", true), what + ".bodies", policy::kMaxResolveBodies);
    for (std::size_t i = 0; i < jb.size(); ++i) {
        const std::string path = what + ".bodies[" + std::to_string(i) + "]";
        const auto& b = jb[i];
        ResolverBody<D> body;
        const auto* st = member(b, path, "static", false);
        const bool isStatic = st ? boolean(*st, path + ".static") : false;
        if (!isStatic) {
            const double mass = number(*member(b, path, "mass", true), path + ".mass");
            if (!(mass > 0.0)) throw InputError(path + ".mass: must be > 0 for a dynamic body (use \"static\": true)");
            if (!(mass >= policy::kMinMass && mass <= policy::kMaxMass))
                throw InputError(path + ".mass: must be in " + jsonio::rangeText(policy::kMinMass, policy::kMaxMass));
            body.invMass = 1.0 / mass;
            body.invInertia = readInvInertia(*member(b, path, "inertia", true), path + ".inertia", D{});
        }
        body.position = readVec(*member(b, path, "position", true), path + ".position", policy::kMaxCoordinate, D{});
        if (const auto* v = member(b, path, "velocity", false))
            body.velocity = readVec(*v, path + ".velocity", policy::kMaxSpeed, D{});
        if (const auto* w = member(b, path, "angular_velocity", false))
            body.angularVelocity = readAng(*w, path + ".angular_velocity", D{});
        bodies.push_back(body);
        statics.push_back(isStatic);
    }
    std::vector<ContactNode<D>> contacts;
    bool friction = false;
    const auto& jc = jsonio::arrayUpTo(*member(input, what, "contacts", true), what + ".contacts", policy::kMaxResolveContacts);
    const int nb = int(bodies.size());
    for (std::size_t i = 0; i < jc.size(); ++i) {
        const std::string path = what + ".contacts[" + std::to_string(i) + "]";
        const auto& c = jc[i];
        ContactNode<D> node;
        node.a = integer(*member(c, path, "a", true), path + ".a", 0, nb - 1);
        node.b = integer(*member(c, path, "b", true), path + ".b", 0, nb - 1);
        if (node.a != node.b && statics[std::size_t(node.a)] && statics[std::size_t(node.b)])
            throw InputError(path + ": bodies a and b are both static (a contact needs a dynamic body)");
        node.point = readVec(*member(c, path, "point", true), path + ".point", policy::kMaxCoordinate, D{});
        node.normal = readVec(*member(c, path, "normal", true), path + ".normal", 2.0, D{});
        node.restitution = jsonio::numberInOr(c, path, "restitution", 0.0, 1.0, node.restitution);
        node.friction = jsonio::numberInOr(c, path, "friction", 0.0, policy::kMaxFriction, node.friction);
        friction = friction || node.friction > 0.0;
        contacts.push_back(node);
    }
    ResolverOptions options;
    if (const auto* t = member(input, what, "restitution_threshold", false)) {
        options.restitutionThreshold =
            jsonio::numberIn(*t, what + ".restitution_threshold", 0.0, policy::kMaxRestitutionThreshold);
    }
    // Bounded work: at most 4 pivots per unknown of the (friction) LCP.
    const int unknowns = int(contacts.size()) * (friction ? 2 + D::frictionDirectionCount(options.frictionDirections) : 1);
    options.lcp.maxPivots = policy::kResolvePivotsPerUnknown * unknowns + 100;
    const std::string problem = validate(bodies, contacts);
    if (!problem.empty()) throw InputError(what + ": " + problem);

    LemkeSolver solver;
    const Resolution r = friction ? resolveWithFriction(bodies, contacts, options, solver)
                                  : resolveCollisions(bodies, contacts, options, solver);
    if (r.status == LcpStatus::invalid_input) throw InputError(what + ": " + r.message);
    CommandOutput out;
    out.json = {{"status", statusName(r.status)}, {"pivots", r.pivots}, {"residual", r.residual}, {"fast_path", r.fastPath}};
    if (r.status == LcpStatus::solved) {
        out.json["impulses"] = r.impulses;
        if (friction) out.json["tangent_impulses"] = r.tangentImpulses;
        nlohmann::json jbodies = nlohmann::json::array();
        for (const auto& b : bodies) jbodies.push_back({{"velocity", vecJson(b.velocity)}, {"angular_velocity", angJson(b.angularVelocity)}});
        out.json["bodies"] = jbodies;
    }
    if (r.status == LcpStatus::solved && !jsonio::allFinite(out.json)) {
        // Bounded inputs keep this from happening; if it does, say so instead of printing null.
        out.json = {{"status", statusName(LcpStatus::numerical_failure)}, {"pivots", r.pivots},
                    {"message", "the answer overflowed (non-finite impulses or velocities)"}};
        out.exitCode = 1;
    } else if (r.status != LcpStatus::solved) {
        out.json["message"] = r.message;
        out.exitCode = 1;
    }
    return out;
}

}  // namespace

CommandOutput runResolve(const nlohmann::json& input, const std::string& what) {
    const int dim = integer(*member(input, what, "dimension", true), what + ".dimension", 2, 3);
    return dim == 2 ? resolveDim<Dim2>(input, what) : resolveDim<Dim3>(input, what);
}

}  // namespace unison::cli
