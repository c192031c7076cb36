// resolver2d/world2d_state.cpp — the 2D world's state: its canonical serialisation, the state hash, snapshots,
// restore and the named field list used by diffs and desync reports.
//
// One function, transferState(), walks every field that affects the future in one fixed order. Three sinks write
// it (bytes for the hash and snapshots, named fields for reports) and one source reads it back, so the hash, the
// snapshot and the restore can never disagree about what the state is.
//
// What is state: the settings (WorldDef2, gravity included, since setGravity() changes it), the step count, the body
// store (slot table with generations, LIFO free list, dense order, hot and cold records with shapes, mass and sleep
// timers), the warm-start cache (which LCP unknowns were basic per contact feature) and the touching pairs that
// begin/end events are computed from. What is not: LemkeSolver's workspace (every buffer is re-initialised at the
// start of each solve before it is read; see core/lcp.cpp run()), the island-local index map (all -1 between
// islands), and the last step's outputs (contact points, events, statistics), which the next step recomputes.
#include "world2d.h"

#include "compact_state.h"
#include "state_transfer.h"
#include "world_base_state.h"
#include "world2d_checks.h"

#include <cmath>
#include <cstring>

namespace unison {

// Each struct that is part of the state has a static_assert of its size next to it: when one fails, a field was
// added; add it to transferState() below (and to the snapshot format version if old snapshots can no longer be
// read), and to World2::CompactFields if a tick can change it, then update the size there.

namespace {

using namespace state_transfer;

template <class Io, class V>
void vec2(Io& io, const char* name, V& v) {
    io.push(name);
    io.f64("x", v.x);
    io.f64("y", v.y);
    io.pop();
}

template <class Io, class S>
void shape(Io& io, S& s) {
    enumeration(io, "type", s.type, int(ShapeType::segment));
    switch (s.type) {
        case ShapeType::circle:
            vec2(io, "center", s.circle.center);
            io.f64("radius", s.circle.radius);
            if constexpr (Io::kReading) {
                if (!(s.circle.radius > 0.0)) io.fail("circle radius must be > 0");
            }
            break;
        case ShapeType::polygon: {
            std::uint8_t count = std::uint8_t(s.polygon.count);
            io.u8("count", count);
            if constexpr (Io::kReading) {
                if (count < 3 || count > kMaxPolygonVertices) {
                    io.fail("polygon vertex count " + std::to_string(count) + " out of range");
                    return;
                }
                s.polygon.count = count;
            }
            for (int i = 0; i < count; ++i) {
                io.push("vertices", i);
                vec2(io, "point", s.polygon.vertices[std::size_t(i)]);
                vec2(io, "normal", s.polygon.normals[std::size_t(i)]);
                io.pop();
            }
            vec2(io, "centroid", s.polygon.centroid);
            break;
        }
        case ShapeType::segment:
            vec2(io, "p1", s.segment.p1);
            vec2(io, "p2", s.segment.p2);
            break;
    }
    io.f64("density", s.density);
    io.f64("friction", s.friction);
    io.f64("restitution", s.restitution);
}

/// One body's hot and cold records.
template <class Io, class Hot, class Cold>
void body(Io& io, Hot& s, Cold& info) {
    vec2(io, "position", s.position);
    io.push("rotation");
    io.f64("c", s.rotation.c);
    io.f64("s", s.rotation.s);
    io.pop();
    vec2(io, "center", s.center);
    vec2(io, "velocity", s.velocity);
    io.f64("angularVelocity", s.angularVelocity);
    enumeration(io, "type", info.type, int(BodyType::dynamicBody));
    io.f64("mass", info.mass);
    io.f64("invMass", info.invMass);
    io.f64("inertia", info.inertia);
    io.f64("invInertia", info.invInertia);
    vec2(io, "localCenter", info.localCenter);
    io.f64("sleepTime", info.sleepTime);
    boolean(io, "awake", info.awake);
    sequence(io, "shapes", info.shapes, 8, [&](auto& sh) { shape(io, sh); });
    if constexpr (Io::kReading) {
        if (io.ok()) {
            const std::string why = checkBodyRecord2(s, info);  // as strict as createBody()
            if (!why.empty()) io.fail(why);
        }
    }
}

}  // namespace

template <class Io, class Self>
void World2::transferState(Io& io, Self& world) {
    auto& def = world.mDef;
    io.push("def");
    vec2(io, "gravity", def.gravity);
    worldSettings(io, def, [&] {
        io.f64("acceptResidual", def.acceptResidual);
        if constexpr (Io::kReading) {
            if (!(def.acceptResidual >= 0.0)) io.fail("def.acceptResidual must be >= 0");
        }
    });
    io.pop();
    if constexpr (Io::kReading) {
        if (!policy::within(def.gravity.x, policy::kMaxGravity) || !policy::within(def.gravity.y, policy::kMaxGravity)) io.fail("def.gravity out of range");
    }
    io.u64("stepCount", world.mStepCount);

    bodyStore(io, world.mBodies, [&](auto& hot, auto& cold) { body(io, hot, cold); });

    stepState(io, world.mStep.cache, world.mStep.touching);
    if constexpr (Io::kReading) {
        if (io.ok()) checkStepState(io, world.mStep.cache, world.mBodies.slots().size(), world.mStep.touching);
    }
}

// ---- Compact (rollback) state: core/compact_state.h ---------------------------------------------------------

/// The doubles of the 2D world that a tick can change, in the compact state's order.
struct World2::CompactFields {
    static constexpr int kPose = 6, kVelocity = 3, kGravity = 2, kCenter = 2;  // pose: position, rotation, centre
    template <class H, class Fn>
    static void pose(H& s, Fn f) {
        f(s.position.x);
        f(s.position.y);
        f(s.rotation.c);
        f(s.rotation.s);
        f(s.center.x);
        f(s.center.y);
    }
    template <class H, class Fn>
    static void velocity(H& s, Fn f) {
        f(s.velocity.x);
        f(s.velocity.y);
        f(s.angularVelocity);
    }
    template <class D, class Fn>
    static void gravity(D& def, Fn f) {
        f(def.gravity.x);
        f(def.gravity.y);
    }
};

// The state entry points (core/world_base_state.h) over transferState(), instantiated here next to it.
using WorldBase2 = WorldBase<World2, Dim2, WorldDef2, BodyState2, BodyInfo2, ContactPoint2>;
template std::uint64_t WorldBase2::stateHash() const;
template std::vector<std::uint8_t> WorldBase2::snapshot() const;
template bool WorldBase2::restore(const std::uint8_t*, std::size_t, std::string*);
template std::vector<StateField> WorldBase2::stateFields() const;
template void WorldBase2::saveCompact(CompactState&) const;
template bool WorldBase2::restoreCompact(const std::uint8_t*, std::size_t, std::string*);

}  // namespace unison
