// samples/cli_resolve.cpp — `unison resolve FILE.json`: reads bodies and contact nodes, runs the paper's resolver
// (with Coulomb friction when any node has "friction" > 0) and reports impulses and post-impact velocities.
#include "cli.h"
#include "resolver2d.h"
#include "resolver3d.h"

#include <Eigen/LU>

#include <cmath>

namespace unison::cli {
namespace {

Vec2 readVec(const nlohmann::json& v, const std::string& path, Dim2) {
    const auto x = numbers(v, path, 2);
    return {x[0], x[1]};
}
Vec3 readVec(const nlohmann::json& v, const std::string& path, Dim3) {
    const auto x = numbers(v, path, 3);
    return Vec3(x[0], x[1], x[2]);
}
double readAng(const nlohmann::json& v, const std::string& path, Dim2) { return number(v, path); }
Vec3 readAng(const nlohmann::json& v, const std::string& path, Dim3) { return readVec(v, path, Dim3{}); }

double readInvInertia(const nlohmann::json& v, const std::string& path, Dim2) {
    const double I = number(v, path);
    if (!(I > 0.0)) throw InputError(path + ": inertia must be > 0");
    return 1.0 / I;
}
Mat3 readInvInertia(const nlohmann::json& v, const std::string& path, Dim3) {
    if (!v.is_array() || v.size() != 3) throw InputError(path + ": expected 3 rows of 3 numbers");
    Mat3 I;
    for (int r = 0; r < 3; ++r) {
        const auto row = numbers(v[std::size_t(r)], path + "[" + std::to_string(r) + "]", 3);
        for (int c = 0; c < 3; ++c) I(r, c) = row[std::size_t(c)];
    }
    if ((I - I.transpose()).cwiseAbs().maxCoeff() > 1e-9 * I.cwiseAbs().maxCoeff())
        throw InputError(path + ": inertia tensor must be symmetric");
    Eigen::LLT<Mat3> llt(I);
    if (llt.info() != Eigen::Success || !(I.diagonal().minCoeff() > 0.0))
        throw InputError(path + ": inertia tensor must be positive definite");
    return I.inverse();
}

nlohmann::json vecJson(const Vec2& v) { return {v.x, v.y}; }
nlohmann::json vecJson(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
nlohmann::json angJson(double w) { return w; }
nlohmann::json angJson(const Vec3& w) { return vecJson(w); }

template <class D>
CommandOutput resolveDim(const nlohmann::json& input, const std::string& what) {
    std::vector<ResolverBody<D>> bodies;
    const auto& jb = array(*member(input, what, "bodies", true), what + ".bodies");
    for (std::size_t i = 0; i < jb.size(); ++i) {
        const std::string path = what + ".bodies[" + std::to_string(i) + "]";
        const auto& b = jb[i];
        ResolverBody<D> body;
        const auto* st = member(b, path, "static", false);
        const bool isStatic = st ? boolean(*st, path + ".static") : false;
        if (!isStatic) {
            const double mass = number(*member(b, path, "mass", true), path + ".mass");
            if (!(mass > 0.0)) throw InputError(path + ".mass: must be > 0 for a dynamic body (use \"static\": true)");
            body.invMass = 1.0 / mass;
            body.invInertia = readInvInertia(*member(b, path, "inertia", true), path + ".inertia", D{});
        }
        body.position = readVec(*member(b, path, "position", true), path + ".position", D{});
        if (const auto* v = member(b, path, "velocity", false)) body.velocity = readVec(*v, path + ".velocity", D{});
        if (const auto* w = member(b, path, "angular_velocity", false))
            body.angularVelocity = readAng(*w, path + ".angular_velocity", D{});
        bodies.push_back(body);
    }
    std::vector<ContactNode<D>> contacts;
    bool friction = false;
    const auto& jc = array(*member(input, what, "contacts", true), what + ".contacts");
    const int nb = int(bodies.size());
    for (std::size_t i = 0; i < jc.size(); ++i) {
        const std::string path = what + ".contacts[" + std::to_string(i) + "]";
        const auto& c = jc[i];
        ContactNode<D> node;
        node.a = integer(*member(c, path, "a", true), path + ".a", 0, nb - 1);
        node.b = integer(*member(c, path, "b", true), path + ".b", 0, nb - 1);
        node.point = readVec(*member(c, path, "point", true), path + ".point", D{});
        node.normal = readVec(*member(c, path, "normal", true), path + ".normal", D{});
        if (const auto* e = member(c, path, "restitution", false)) node.restitution = number(*e, path + ".restitution");
        if (const auto* f = member(c, path, "friction", false)) node.friction = number(*f, path + ".friction");
        friction = friction || node.friction > 0.0;
        contacts.push_back(node);
    }
    ResolverOptions options;
    if (const auto* t = member(input, what, "restitution_threshold", false)) {
        options.restitutionThreshold = number(*t, what + ".restitution_threshold");
        if (options.restitutionThreshold < 0.0) throw InputError(what + ".restitution_threshold: must be >= 0");
    }
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
    } else {
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
