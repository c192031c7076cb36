// bench/bullet_peer.h — the Bullet 3.24 (double precision) side of bench_world3d: builds a btDiscreteDynamicsWorld
// from the same 3D scene JSON that scenes::loadScene3 reads, with either Bullet's sequential-impulse solver or its
// MLCP solver driven by btLemkeSolver.
//
// Mapping: plane -> btStaticPlaneShape, box -> btBoxShape, sphere -> btSphereShape, hull -> btConvexHullShape; a
// body with several shapes or an offset centre becomes a btCompoundShape. Meshes are not supported (throws).
// Bullet multiplies the two bodies' friction and restitution, Unison mixes friction as sqrt(f1 f2) and restitution
// as max(e1, e2): each Bullet body gets friction sqrt(f) (so the product is sqrt(f1 f2)), and static bodies get
// restitution 1 (so a dynamic body against the ground gets exactly its own e; two dynamic bodies get e1 e2, not the
// max — documented difference). Sleeping follows the scene's "sleep" key. One step = stepSimulation(dt, 1, dt).
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <memory>
#include <string>

namespace unison::bench {

enum class BulletSolver { sequentialImpulse, mlcpLemke };

class BulletPeer {
public:
    /// Builds the world; throws std::runtime_error for scenes it cannot map (meshes, bad JSON).
    BulletPeer(const nlohmann::json& scene, BulletSolver solver);
    ~BulletPeer();
    BulletPeer(const BulletPeer&) = delete;
    BulletPeer& operator=(const BulletPeer&) = delete;

    void step();
    int bodyCount() const;
    /// Centre of mass of scene body i (m) and its linear velocity (m/s).
    std::array<double, 3> center(int i) const;
    std::array<double, 3> velocity(int i) const;
    /// Deepest penetration (m, >= 0) among the contact points of the last step's manifolds.
    double maxPenetration() const;
    /// MLCP solves that fell back to sequential impulses so far (0 for the SI solver).
    int fallbacks() const;
    static const char* solverName(BulletSolver s);

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

}  // namespace unison::bench
