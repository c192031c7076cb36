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

#include <cmath>
#include <cstring>

namespace unison {

// If one of these fails, a field was added to a struct that is part of the state: add it to transferState() below
// (and to the snapshot format version if old snapshots can no longer be read), then update the size here.
static_assert(sizeof(WorldDef2) == 160, "WorldDef2 changed: serialise the new field in transferState()");
static_assert(sizeof(BodyState2) == 80, "BodyState2 changed: serialise the new field in transferState()");
static_assert(sizeof(BodyInfo2) == 96, "BodyInfo2 changed: serialise the new field in transferState()");
static_assert(sizeof(Shape2) == 368, "Shape2 changed: serialise the new field in transferState()");
static_assert(sizeof(World2::CacheEntry) == 20, "CacheEntry changed: serialise the new field in transferState()");

namespace {

// ---- Sinks and the source ---------------------------------------------------------------------------------------
// Each has kReading, and takes (name, value) per field; writers take values, the reader takes references.

/// Writes the fields as little-endian bytes; names are ignored.
struct ByteSink {
    static constexpr bool kReading = false;
    ByteWriter out;
    void push(const char*, long long = -1) {}
    void pushBody(BodyId) {}
    void pop() {}
    void u8(const char*, std::uint8_t v) { out.u8(v); }
    void u16(const char*, std::uint16_t v) { out.u16(v); }
    void u32(const char*, std::uint32_t v) { out.u32(v); }
    void i32(const char*, std::int32_t v) { out.i32(v); }
    void u64(const char*, std::uint64_t v) { out.u64(v); }
    void f64(const char*, double v) { out.f64(v); }
    std::size_t count(const char*, std::size_t n, std::size_t) {
        out.u64(n);
        return n;
    }
    void fail(const std::string&) {}
    bool ok() const { return true; }
};

/// Records every field with its path and body (slower; for reports only).
struct FieldSink {
    static constexpr bool kReading = false;
    std::vector<StateField> fields;
    std::vector<std::string> scope;  // path components; a body scope is recorded in `body` instead
    std::vector<BodyId> bodies;      // body of each scope level (null when not a body scope)
    void push(const char* name, long long index = -1) {
        scope.push_back(index < 0 ? std::string(name) : std::string(name) + "[" + std::to_string(index) + "]");
        bodies.push_back(BodyId::null());
    }
    void pushBody(BodyId id) {
        scope.emplace_back();
        bodies.push_back(id);
    }
    void pop() {
        scope.pop_back();
        bodies.pop_back();
    }
    void add(const char* name, bool real, std::uint64_t bits) {
        StateField f;
        for (std::size_t i = 0; i < scope.size(); ++i) {
            if (!bodies[i].isNull()) {
                f.body = bodies[i];
                f.path.clear();  // fields of a body are named relative to it
                continue;
            }
            f.path += scope[i] + ".";
        }
        f.path += name;
        f.real = real;
        f.bits = bits;
        fields.push_back(std::move(f));
    }
    void u8(const char* n, std::uint8_t v) { add(n, false, v); }
    void u16(const char* n, std::uint16_t v) { add(n, false, v); }
    void u32(const char* n, std::uint32_t v) { add(n, false, v); }
    void i32(const char* n, std::int32_t v) { add(n, false, std::uint64_t(std::int64_t(v))); }
    void u64(const char* n, std::uint64_t v) { add(n, false, v); }
    void f64(const char* n, double v) {
        std::uint64_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        add(n, true, bits);
    }
    std::size_t count(const char* n, std::size_t size, std::size_t) {
        add((std::string(n) + ".count").c_str(), false, size);
        return size;
    }
    void fail(const std::string&) {}
    bool ok() const { return true; }
};

/// Reads the fields back from bytes; every double must be finite.
struct ByteSource {
    static constexpr bool kReading = true;
    ByteReader in;
    void push(const char*, long long = -1) {}
    void pushBody(BodyId) {}
    void pop() {}
    void u8(const char*, std::uint8_t& v) { v = in.u8(); }
    void u16(const char*, std::uint16_t& v) { v = in.u16(); }
    void u32(const char*, std::uint32_t& v) { v = in.u32(); }
    void i32(const char*, std::int32_t& v) { v = in.i32(); }
    void u64(const char*, std::uint64_t& v) { v = in.u64(); }
    void f64(const char* name, double& v) {
        v = in.f64();
        if (in.ok() && !std::isfinite(v)) in.fail(std::string("non-finite value in ") + name);
    }
    std::size_t count(const char* name, std::size_t, std::size_t minBytesEach) { return in.count(minBytesEach, name); }
    void fail(const std::string& why) { in.fail(why); }
    bool ok() const { return in.ok(); }
};

// ---- Field helpers shared by the sinks and the source ---------------------------------------------------------

template <class Io, class T>
void boolean(Io& io, const char* name, T& b) {
    std::uint8_t v = b ? 1 : 0;
    io.u8(name, v);
    if constexpr (Io::kReading) {
        if (v > 1) io.fail(std::string(name) + ": not a boolean");
        b = v == 1;
    }
}

template <class Io, class E>
void enumeration(Io& io, const char* name, E& e, int maxValue) {
    std::uint8_t v = std::uint8_t(e);
    io.u8(name, v);
    if constexpr (Io::kReading) {
        if (v > maxValue) io.fail(std::string(name) + ": value " + std::to_string(v) + " out of range");
        e = E(v);
    }
}

template <class Io, class V>
void vec2(Io& io, const char* name, V& v) {
    io.push(name);
    io.f64("x", v.x);
    io.f64("y", v.y);
    io.pop();
}

/// A vector: its count, then each element through `each` (resized first when reading).
template <class Io, class Vec, class Each>
void sequence(Io& io, const char* name, Vec& v, std::size_t minBytesEach, Each each) {
    const std::size_t n = io.count(name, v.size(), minBytesEach);
    if constexpr (Io::kReading) v.resize(n);
    for (std::size_t i = 0; i < n && io.ok(); ++i) {
        io.push(name, (long long)i);
        each(v[i]);
        io.pop();
    }
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

/// The body store's parts: references to the live arrays when writing, fresh arrays when reading.
struct StoreCopy {
    std::vector<BodySlot> slots;
    std::vector<std::uint32_t> freeList, denseToSlot;
    std::vector<BodyState2> hot;
    std::vector<BodyInfo2> cold;
};
struct StoreRefs {
    const std::vector<BodySlot>& slots;
    const std::vector<std::uint32_t>& freeList;
    const std::vector<std::uint32_t>& denseToSlot;
    const std::vector<BodyState2>& hot;
    const std::vector<BodyInfo2>& cold;
};

template <class Io, class Parts>
void bodyStore(Io& io, Parts& p) {
    sequence(io, "slots", p.slots, 8, [&](auto& slot) {
        io.u32("generation", slot.generation);
        io.i32("dense", slot.dense);
    });
    sequence(io, "freeList", p.freeList, 4, [&](auto& s) { io.u32("slot", s); });
    sequence(io, "denseToSlot", p.denseToSlot, 4, [&](auto& s) { io.u32("slot", s); });
    const std::size_t n = p.denseToSlot.size();
    if constexpr (Io::kReading) {
        p.hot.resize(n);
        p.cold.resize(n);
    }
    for (std::size_t d = 0; d < n && io.ok(); ++d) {
        const std::uint32_t slot = p.denseToSlot[d];
        io.pushBody(slot < p.slots.size() ? BodyId{slot + 1u, p.slots[slot].generation} : BodyId::null());
        auto& s = p.hot[d];
        auto& info = p.cold[d];
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
        io.pop();
    }
}

}  // namespace

template <class Io, class Self>
void World2::transferState(Io& io, Self& world) {
    auto& def = world.mDef;
    io.push("def");
    vec2(io, "gravity", def.gravity);
    io.f64("hz", def.hz);
    io.f64("restitutionThreshold", def.restitutionThreshold);
    io.f64("linearSlop", def.linearSlop);
    io.f64("baumgarte", def.baumgarte);
    io.f64("maxCorrectionSpeed", def.maxCorrectionSpeed);
    io.f64("speculativeDistance", def.speculativeDistance);
    io.f64("tangentDeadZone", def.tangentDeadZone);
    io.f64("acceptResidual", def.acceptResidual);
    boolean(io, "enableSleep", def.enableSleep);
    io.f64("linearSleepTolerance", def.linearSleepTolerance);
    io.f64("angularSleepTolerance", def.angularSleepTolerance);
    io.f64("timeToSleep", def.timeToSleep);
    io.i32("lcp.maxPivots", def.lcp.maxPivots);
    io.u64("lcp.maxWork", def.lcp.maxWork);
    io.f64("lcp.pivotTolerance", def.lcp.pivotTolerance);
    io.f64("lcp.residualTolerance", def.lcp.residualTolerance);
    io.f64("lcp.degeneracyPerturbation", def.lcp.degeneracyPerturbation);
    io.pop();
    if constexpr (Io::kReading) {
        def.lcp.warmBasis = nullptr;  // per-call input of the solver, never state
        if (!(def.hz > 0.0)) io.fail("def.hz must be > 0");
        // Ranges the solver can run with (a pivot tolerance >= 1 leaves no admissible pivot and crashed Lemke).
        if (def.lcp.maxPivots < 0 || !(def.lcp.pivotTolerance >= 0.0 && def.lcp.pivotTolerance < 1.0) ||
            def.lcp.residualTolerance < 0.0 || def.lcp.degeneracyPerturbation < 0.0 || !(def.acceptResidual >= 0.0))
            io.fail("def.lcp: options out of range");
    }
    io.u64("stepCount", world.mStepCount);

    if constexpr (Io::kReading) {
        StoreCopy parts;
        bodyStore(io, parts);
        if (io.ok()) {
            const std::string error = world.mBodies.restore(std::move(parts.slots), std::move(parts.freeList),
                                                            std::move(parts.hot), std::move(parts.cold),
                                                            std::move(parts.denseToSlot));
            if (!error.empty()) io.fail("body store: " + error);
        }
    } else {
        StoreRefs parts{world.mBodies.slots(), world.mBodies.freeList(), world.mBodies.denseToSlot(),
                        world.mBodies.hotArray(), world.mBodies.coldArray()};
        bodyStore(io, parts);
    }

    sequence(io, "cache", world.mCache, 20, [&](auto& e) {
        io.u32("slotA", e.slotA);
        io.u32("slotB", e.slotB);
        io.u16("shapeA", e.shapeA);
        io.u16("shapeB", e.shapeB);
        io.u32("feature", e.feature);
        io.u32("basicMask", e.basicMask);
    });
    sequence(io, "touching", world.mTouching, 16, [&](auto& pair) {
        io.u64("a", pair.first);
        io.u64("b", pair.second);
    });
    if constexpr (Io::kReading) {
        // The step looks entries up by binary search and merges touching lists: both must be strictly sorted.
        for (std::size_t i = 1; i < world.mCache.size() && io.ok(); ++i) {
            if (!(world.mCache[i - 1] < world.mCache[i])) io.fail("warm-start cache is not strictly sorted");
        }
        for (std::size_t i = 1; i < world.mTouching.size() && io.ok(); ++i) {
            if (!(world.mTouching[i - 1] < world.mTouching[i])) io.fail("touching pairs are not strictly sorted");
        }
    }
}

std::uint64_t World2::stateHash() const {
    ByteSink sink;
    transferState(sink, *this);
    return hash64(sink.out.data().data(), sink.out.data().size());
}

std::vector<std::uint8_t> World2::snapshot() const {
    ByteSink sink;
    transferState(sink, *this);
    return frameSnapshot(SnapshotKind::world2, std::uint64_t(mBodies.size()), sink.out.data());
}

bool World2::restore(const std::uint8_t* data, std::size_t size, std::string* error) {
    SnapshotView view;
    if (!unframeSnapshot(data, size, SnapshotKind::world2, &view, error)) return false;
    World2 fresh;
    ByteSource source{ByteReader(view.payload, view.payloadSize)};
    transferState(source, fresh);
    if (source.ok() && !source.in.atEnd()) source.in.fail("unexpected bytes after the state");
    if (source.ok() && std::uint64_t(fresh.mBodies.size()) != view.bodyCount)
        source.in.fail("header announces " + std::to_string(view.bodyCount) + " bodies, payload holds " +
                       std::to_string(fresh.mBodies.size()));
    if (!source.ok()) {
        if (error) *error = "snapshot rejected: " + source.in.error();
        return false;
    }
    *this = std::move(fresh);  // only now is the live world replaced
    return true;
}

std::vector<StateField> World2::stateFields() const {
    FieldSink sink;
    transferState(sink, *this);
    return std::move(sink.fields);
}

}  // namespace unison
