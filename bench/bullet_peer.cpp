// bench/bullet_peer.cpp — see bullet_peer.h.
#include "bullet_peer.h"

#include <BulletDynamics/MLCPSolvers/btLemkeSolver.h>
#include <BulletDynamics/MLCPSolvers/btMLCPSolver.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace unison::bench {

struct BulletPeer::Impl {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    std::unique_ptr<btLemkeSolver> lemke;
    std::unique_ptr<btConstraintSolver> solver;
    std::unique_ptr<btDiscreteDynamicsWorld> world;
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btDefaultMotionState>> motions;
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    double dt = 1.0 / 60.0;
    ~Impl() {
        for (auto& b : bodies) world->removeRigidBody(b.get());
    }
};

namespace {

using nlohmann::json;

btVector3 vec3(const json& v) { return btVector3(v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>()); }
btVector3 vec3Or(const json& o, const char* key, const btVector3& fallback) { return o.contains(key) ? vec3(o[key]) : fallback; }

}  // namespace

BulletPeer::BulletPeer(const json& scene, BulletSolver solverKind) : mImpl(std::make_unique<Impl>()) {
    Impl& m = *mImpl;
    if (solverKind == BulletSolver::mlcpLemke) {
        m.lemke = std::make_unique<btLemkeSolver>();
        m.solver = std::make_unique<btMLCPSolver>(m.lemke.get());
    } else {
        m.solver = std::make_unique<btSequentialImpulseConstraintSolver>();
    }
    m.world = std::make_unique<btDiscreteDynamicsWorld>(&m.dispatcher, &m.broadphase, m.solver.get(), &m.config);
    m.world->setGravity(vec3Or(scene, "gravity", btVector3(0, -10, 0)));
    m.dt = 1.0 / scene.value("hz", 60.0);
    const bool sleep = scene.value("sleep", true);
    for (const json& jb : scene.at("bodies")) {
        const bool dynamic = jb.value("type", std::string("dynamic")) == "dynamic";
        const json& shapes = jb.at("shapes");
        auto compound = std::make_unique<btCompoundShape>();
        double mass = 0.0, friction = 0.6, restitution = 0.0;
        btVector3 localInertia(0, 0, 0);
        std::vector<btScalar> masses;
        for (const json& js : shapes) {
            const std::string type = js.at("type").get<std::string>();
            std::unique_ptr<btCollisionShape> shape;
            btVector3 center = vec3Or(js, "center", btVector3(0, 0, 0));
            double volume = 0.0;
            if (type == "box") {
                const btVector3 h = vec3(js.at("half_extents"));
                shape = std::make_unique<btBoxShape>(h);
                volume = 8.0 * h.x() * h.y() * h.z();
            } else if (type == "sphere") {
                const double r = js.at("radius").get<double>();
                shape = std::make_unique<btSphereShape>(r);
                volume = 4.0 / 3.0 * 3.141592653589793 * r * r * r;
            } else if (type == "plane") {
                shape = std::make_unique<btStaticPlaneShape>(vec3(js.at("normal")).normalized(), js.value("offset", 0.0));
            } else if (type == "hull") {
                auto hull = std::make_unique<btConvexHullShape>();
                for (const json& p : js.at("vertices")) hull->addPoint(vec3(p), false);
                hull->recalcLocalAabb();
                shape = std::move(hull);
                volume = 0.0;  // mass from the scene's density is not needed for the bench scenes
            } else {
                throw std::runtime_error("bullet peer: shape type \"" + type + "\" is not supported");
            }
            friction = js.value("friction", 0.6);
            restitution = js.value("restitution", 0.0);
            masses.push_back(js.value("density", 1.0) * volume);
            mass += masses.back();
            btTransform local;
            local.setIdentity();
            local.setOrigin(center);
            compound->addChildShape(local, shape.get());
            m.shapes.push_back(std::move(shape));
        }
        btCollisionShape* bodyShape = compound.get();
        btTransform principal;
        principal.setIdentity();
        if (shapes.size() == 1 && !shapes[0].contains("center")) {
            bodyShape = m.shapes.back().get();  // one centred shape: no compound needed
        } else if (dynamic) {
            // Bullet wants the body frame at the centre of mass with principal axes.
            compound->calculatePrincipalAxisTransform(masses.data(), principal, localInertia);
            for (int c = 0; c < compound->getNumChildShapes(); ++c)
                compound->updateChildTransform(c, principal.inverse() * compound->getChildTransform(c), false);
            compound->recalculateLocalAabb();
        }
        m.shapes.push_back(std::move(compound));
        if (!dynamic) mass = 0.0;
        if (dynamic && bodyShape != m.shapes.back().get()) bodyShape->calculateLocalInertia(mass, localInertia);
        btTransform xf;
        xf.setIdentity();
        xf.setOrigin(vec3Or(jb, "position", btVector3(0, 0, 0)));
        if (jb.contains("orientation")) {
            const json& q = jb["orientation"];
            xf.setRotation(btQuaternion(q.at(1).get<double>(), q.at(2).get<double>(), q.at(3).get<double>(), q.at(0).get<double>()).normalized());
        }
        xf = xf * principal;
        m.motions.push_back(std::make_unique<btDefaultMotionState>(xf));
        btRigidBody::btRigidBodyConstructionInfo info(mass, m.motions.back().get(), bodyShape, localInertia);
        info.m_friction = std::sqrt(friction);
        info.m_restitution = dynamic ? restitution : 1.0;
        m.bodies.push_back(std::make_unique<btRigidBody>(info));
        btRigidBody* body = m.bodies.back().get();
        if (dynamic) {
            body->setLinearVelocity(vec3Or(jb, "linear_velocity", btVector3(0, 0, 0)));
            body->setAngularVelocity(vec3Or(jb, "angular_velocity", btVector3(0, 0, 0)));
            if (!sleep) body->setActivationState(DISABLE_DEACTIVATION);
        }
        m.world->addRigidBody(body);
    }
}

BulletPeer::~BulletPeer() = default;

void BulletPeer::step() { mImpl->world->stepSimulation(mImpl->dt, 1, mImpl->dt); }

int BulletPeer::bodyCount() const { return int(mImpl->bodies.size()); }

std::array<double, 3> BulletPeer::center(int i) const {
    const btVector3 p = mImpl->bodies[std::size_t(i)]->getCenterOfMassPosition();
    return {p.x(), p.y(), p.z()};
}

std::array<double, 3> BulletPeer::velocity(int i) const {
    const btVector3 v = mImpl->bodies[std::size_t(i)]->getLinearVelocity();
    return {v.x(), v.y(), v.z()};
}

double BulletPeer::maxPenetration() const {
    double deepest = 0.0;
    const btDispatcher& d = mImpl->dispatcher;
    for (int m = 0; m < d.getNumManifolds(); ++m) {
        const btPersistentManifold* manifold = const_cast<btDispatcher&>(d).getManifoldByIndexInternal(m);
        for (int k = 0; k < manifold->getNumContacts(); ++k) deepest = std::max(deepest, -double(manifold->getContactPoint(k).getDistance()));
    }
    return deepest;
}

int BulletPeer::fallbacks() const {
    const auto* mlcp = dynamic_cast<const btMLCPSolver*>(mImpl->solver.get());
    return mlcp ? mlcp->getNumFallbacks() : 0;
}

const char* BulletPeer::solverName(BulletSolver s) {
    return s == BulletSolver::mlcpLemke ? "Bullet MLCP (btLemkeSolver)" : "Bullet sequential impulse";
}

}  // namespace unison::bench
