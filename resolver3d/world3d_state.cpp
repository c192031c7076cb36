// resolver3d/world3d_state.cpp — the 3D world's state: its canonical serialisation, the state hash, snapshots,
// restore and the named field list used by diffs and desync reports (the 3D twin of resolver2d/world2d_state.cpp,
// on the same sinks and source: core/state_transfer.h).
//
// What is state: the settings (WorldDef3 incl. gravity, friction directions and LCP options), the step count, the
// body store (slot table with generations, LIFO free list, dense order, hot records with quaternions, cold records
// with mass properties, shapes and sleep timers), the warm-start cache and the touching pairs. Shapes carry their
// geometry: a box's or hull's polyhedron (vertices, faces, edges) and a mesh's vertices, triangles and leaf size.
// A mesh's normals and sphere trees are derived data: restore rebuilds them with makeMesh(), which is
// deterministic, so the restored mesh is bit-identical. Shapes that share one polyhedron or mesh (bodies loaded
// from the same file) share it in the snapshot too: the first use writes it, later ones refer to it by index.
// What is not state: LemkeSolver's workspace (re-initialised by every solve), the island-local index map (all -1
// between steps), the captureCandidates() switch, and the last step's outputs (contacts, events, statistics).
#include "world3d.h"

#include "compact_state.h"
#include "state_transfer.h"
#include "world_base_state.h"
#include "world3d_checks.h"

#include <cmath>

namespace unison {

// Each struct that is part of the state has a static_assert of its size next to it: when one fails, a field was
// added; add it to transferState() below (and to the snapshot format version if old snapshots can no longer be
// read), and to World3::CompactFields if a tick can change it, then update the size there.

namespace {

using namespace state_transfer;

template <class Io, class V>
void vec3(Io& io, const char* name, V& v) {
    io.push(name);
    io.f64("x", v.x());
    io.f64("y", v.y());
    io.f64("z", v.z());
    io.pop();
}

template <class Io, class M>
void mat3(Io& io, const char* name, M& m) {
    static const char* const kNames[3][3] = {{"xx", "xy", "xz"}, {"yx", "yy", "yz"}, {"zx", "zy", "zz"}};
    io.push(name);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) io.f64(kNames[i][j], m(i, j));
    io.pop();
}

template <class Io, class Q>
void quat(Io& io, const char* name, Q& q) {
    io.push(name);
    io.f64("w", q.w);
    io.f64("x", q.x);
    io.f64("y", q.y);
    io.f64("z", q.z);
    io.pop();
}

/// Polyhedra and meshes already written or read, in first-use order (shapes refer to them by index).
struct SharedGeometry {
    std::vector<std::shared_ptr<const ConvexPolyhedron>> polys;
    std::vector<std::shared_ptr<const TriangleMesh>> meshes;
};

/// A shared geometry object: its index in `table`; when it is new (index == table size) its content follows,
/// written by write(object) or read by read() (which returns the built object, or null after io.fail()).
template <class Io, class Ptr, class Table, class Write, class Read>
void sharedObject(Io& io, const char* name, Ptr& p, Table& table, Write write, Read read) {
    io.push(name);
    std::uint32_t ref = 0;
    if constexpr (!Io::kReading) {
        while (ref < table.size() && table[ref] != p) ++ref;
    }
    io.u32("ref", ref);
    if constexpr (Io::kReading) {
        if (ref < table.size()) {
            p = table[ref];
        } else if (ref == table.size()) {
            p = read();
            if (p) table.push_back(p);
        } else {
            io.fail(std::string(name) + ": reference " + std::to_string(ref) + " to an object not yet defined");
        }
    } else {
        if (ref == table.size()) {
            table.push_back(p);
            write(*p);
        }
    }
    io.pop();
}

template <class Io, class P>
void polyhedron(Io& io, P& poly) {
    const auto index = [&](const char* n, auto& i, std::size_t bound) {
        io.i32(n, i);
        if constexpr (Io::kReading) {
            if (i < 0 || std::size_t(i) >= bound) io.fail(std::string("polyhedron: ") + n + " index out of range");
        }
    };
    sequence(io, "vertices", poly.vertices, 24, [&](auto& v) { vec3(io, "p", v); });
    const std::size_t nv = poly.vertices.size();
    sequence(io, "faces", poly.faces, 40, [&](auto& f) {
        vec3(io, "normal", f.normal);
        io.f64("offset", f.offset);
        sequence(io, "loop", f.loop, 4, [&](auto& i) { index("vertex", i, nv); });
        if constexpr (Io::kReading) {
            if (f.loop.size() < 3) io.fail("polyhedron: a face has fewer than 3 vertices");
        }
    });
    const std::size_t nf = poly.faces.size();
    sequence(io, "edges", poly.edges, 16, [&](auto& e) {
        index("v0", e.v0, nv);
        index("v1", e.v1, nv);
        index("face0", e.face0, nf);
        index("face1", e.face1, nf);
    });
    vec3(io, "centroid", poly.centroid);
    if constexpr (Io::kReading) {
        if (nv < 4 || nf < 4) io.fail("polyhedron: needs at least 4 vertices and 4 faces");
    }
}

/// A mesh's defining data; its normals and sphere trees are rebuilt from it on reading.
template <class Io, class Vs, class Ts, class L>
void meshData(Io& io, Vs& vertices, Ts& triangles, L& leafSize) {
    sequence(io, "vertices", vertices, 24, [&](auto& v) { vec3(io, "p", v); });
    sequence(io, "triangles", triangles, 12, [&](auto& t) {
        io.i32("a", t[0]);
        io.i32("b", t[1]);
        io.i32("c", t[2]);
    });
    io.i32("leafSize", leafSize);
}

template <class Io, class S>
void shape(Io& io, S& s, SharedGeometry& shared) {
    enumeration(io, "type", s.type, int(ShapeType3::mesh));
    vec3(io, "center", s.center);
    io.f64("radius", s.radius);
    vec3(io, "halfExtents", s.halfExtents);
    vec3(io, "normal", s.normal);
    io.f64("offset", s.offset);
    io.f64("density", s.density);
    io.f64("friction", s.friction);
    io.f64("restitution", s.restitution);
    if (!io.ok()) return;
    if (s.type == ShapeType3::box || s.type == ShapeType3::hull) {
        sharedObject(
            io, "poly", s.poly, shared.polys, [&](const auto& p) { polyhedron(io, p); },
            [&]() -> std::shared_ptr<const ConvexPolyhedron> {
                auto p = std::make_shared<ConvexPolyhedron>();
                polyhedron(io, *p);
                return io.ok() ? p : nullptr;
            });
    } else if (s.type == ShapeType3::mesh) {
        sharedObject(
            io, "mesh", s.mesh, shared.meshes,
            [&](const auto& m) { meshData(io, m.vertices, m.triangles, m.leafSize); },
            [&]() -> std::shared_ptr<const TriangleMesh> {
                std::vector<Vec3> vertices;
                std::vector<std::array<int, 3>> triangles;
                int leafSize = 0;
                meshData(io, vertices, triangles, leafSize);
                if (!io.ok()) return nullptr;
                if (leafSize < 1) {
                    io.fail("mesh: leaf size must be >= 1");
                    return nullptr;
                }
                Shape3 built;
                const std::string error = makeMesh(vertices, triangles, &built, leafSize);
                if (!error.empty()) io.fail(error);
                return error.empty() ? built.mesh : nullptr;
            });
    }
    if constexpr (Io::kReading) {
        const bool ok = s.type == ShapeType3::sphere  ? s.radius > 0.0
                        : s.type == ShapeType3::box   ? s.halfExtents.minCoeff() > 0.0 && s.poly != nullptr
                        : s.type == ShapeType3::hull  ? s.poly != nullptr
                        : s.type == ShapeType3::plane ? std::fabs(Dim3::dot(s.normal, s.normal) - 1.0) < 1e-9
                                                      : s.mesh != nullptr;
        if (io.ok() && !ok) io.fail("shape: invalid dimensions for its type");
        if (io.ok() && !(s.density >= 0.0 && s.friction >= 0.0 && s.restitution >= 0.0))
            io.fail("shape: density, friction and restitution must be >= 0");
    }
}

/// One body's hot and cold records.
template <class Io, class Hot, class Cold>
void body(Io& io, Hot& s, Cold& info, SharedGeometry& shared) {
    vec3(io, "position", s.position);
    quat(io, "rotation", s.rotation);
    vec3(io, "center", s.center);
    vec3(io, "velocity", s.velocity);
    vec3(io, "angularVelocity", s.angularVelocity);
    enumeration(io, "type", info.type, int(BodyType::dynamicBody));
    io.f64("mass", info.mass);
    io.f64("invMass", info.invMass);
    mat3(io, "inertia", info.inertia);
    mat3(io, "invInertia", info.invInertia);
    vec3(io, "localCenter", info.localCenter);
    io.f64("sleepTime", info.sleepTime);
    boolean(io, "awake", info.awake);
    sequence(io, "shapes", info.shapes, 100, [&](auto& sh) { shape(io, sh, shared); });
    if constexpr (Io::kReading) {
        if (io.ok()) {
            const std::string why = checkBodyRecord3(s, info);  // as strict as createBody()
            if (!why.empty()) io.fail(why);
        }
    }
}

}  // namespace

template <class Io, class Self>
void World3::transferState(Io& io, Self& world) {
    auto& def = world.mDef;
    io.push("def");
    vec3(io, "gravity", def.gravity);
    worldSettings(io, def, [&] {
        io.i32("frictionDirections", def.frictionDirections);
        io.f64("acceptResidual", def.acceptResidual);
        io.f64("speculativeBand", def.speculativeBand);
        if constexpr (Io::kReading) {
            if (!(def.acceptResidual >= 0.0)) io.fail("def.acceptResidual must be >= 0");
            if (std::isnan(def.speculativeBand)) io.fail("def.speculativeBand must not be NaN");
            // The warm-start masks hold k + 2 bits per contact in 32 (core/step_support.h): k <= 30.
            if (def.frictionDirections < 1 || def.frictionDirections > 30) io.fail("def.frictionDirections out of range");
        }
    });
    io.pop();
    if constexpr (Io::kReading) {
        if (!policy::within(def.gravity.x(), policy::kMaxGravity) || !policy::within(def.gravity.y(), policy::kMaxGravity) || !policy::within(def.gravity.z(), policy::kMaxGravity)) io.fail("def.gravity out of range");
    }
    io.u64("stepCount", world.mStepCount);

    SharedGeometry shared;
    bodyStore(io, world.mBodies, [&](auto& hot, auto& cold) { body(io, hot, cold, shared); });

    stepState(io, world.mStep.cache, world.mStep.touching);
    if constexpr (Io::kReading) {
        if (io.ok()) checkStepState(io, world.mStep.cache, world.mBodies.slots().size(), world.mStep.touching);
    }
}

// ---- Compact (rollback) state: core/compact_state.h ---------------------------------------------------------

/// The doubles of the 3D world that a tick can change, in the compact state's order.
struct World3::CompactFields {
    static constexpr int kPose = 10, kVelocity = 6, kGravity = 3, kCenter = 3;  // pose: position, rotation, centre
    template <class V, class Fn>
    static void vec(V& v, Fn& f) {
        f(v.x());
        f(v.y());
        f(v.z());
    }
    template <class H, class Fn>
    static void pose(H& s, Fn f) {
        vec(s.position, f);
        f(s.rotation.w);
        f(s.rotation.x);
        f(s.rotation.y);
        f(s.rotation.z);
        vec(s.center, f);
    }
    template <class H, class Fn>
    static void velocity(H& s, Fn f) {
        vec(s.velocity, f);
        vec(s.angularVelocity, f);
    }
    template <class D, class Fn>
    static void gravity(D& def, Fn f) {
        vec(def.gravity, f);
    }
};

// The state entry points (core/world_base_state.h) over transferState(), instantiated here next to it.
using WorldBase3 = WorldBase<World3, Dim3, WorldDef3, BodyState3, BodyInfo3, ContactPoint3>;
template std::uint64_t WorldBase3::stateHash() const;
template std::vector<std::uint8_t> WorldBase3::snapshot() const;
template bool WorldBase3::restore(const std::uint8_t*, std::size_t, std::string*);
template std::vector<StateField> WorldBase3::stateFields() const;
template void WorldBase3::saveCompact(CompactState&) const;
template bool WorldBase3::restoreCompact(const std::uint8_t*, std::size_t, std::string*);

}  // namespace unison
