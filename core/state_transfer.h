// core/state_transfer.h — the sinks and the source of a world's canonical state walk (World2::transferState,
// World3::transferState): one function per world walks every field that affects the future in a fixed order, and
// these objects either write the fields as bytes (state hash, snapshot payload), record them with their names
// (diffs, desync reports) or read them back from bytes (restore), so the three can never disagree.
// Header-only because the walks are templates over these types; internal to the world state files.
#pragma once

#include "input_policy.h"
#include "state_io.h"
#include "step_support.h"
#include "task_system.h"

#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace unison::state_transfer {

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

/// The body store's parts: fresh arrays when reading, references to the live arrays when writing.
template <class Hot, class Cold>
struct StoreCopy {
    std::vector<BodySlot> slots;
    std::vector<std::uint32_t> freeList, denseToSlot;
    std::vector<Hot> hot;
    std::vector<Cold> cold;
};
template <class Hot, class Cold>
struct StoreRefs {
    const std::vector<BodySlot>& slots;
    const std::vector<std::uint32_t>& freeList;
    const std::vector<std::uint32_t>& denseToSlot;
    const std::vector<Hot>& hot;
    const std::vector<Cold>& cold;
};

/// Slot table, free list and dense order, then every body in dense order through perBody(io, hot, cold), scoped
/// by its id.
template <class Io, class Parts, class PerBody>
void storeParts(Io& io, Parts& p, PerBody& perBody) {
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
        perBody(p.hot[d], p.cold[d]);
        io.pop();
    }
}

/// A whole body store (BodyStore<Hot, Cold>, const when writing). Reading fills fresh arrays and hands them to
/// BodyStore::restore(), which checks every invariant; a failure there fails the read.
template <class Io, class Store, class PerBody>
void bodyStore(Io& io, Store& store, PerBody perBody) {
    using Hot = std::decay_t<decltype(store.hotArray()[0])>;
    using Cold = std::decay_t<decltype(store.coldArray()[0])>;
    if constexpr (Io::kReading) {
        StoreCopy<Hot, Cold> parts;
        storeParts(io, parts, perBody);
        if (io.ok()) {
            const std::string error = store.restore(std::move(parts.slots), std::move(parts.freeList),
                                                    std::move(parts.hot), std::move(parts.cold),
                                                    std::move(parts.denseToSlot));
            if (!error.empty()) io.fail("body store: " + error);
        }
    } else {
        StoreRefs<Hot, Cold> parts{store.slots(), store.freeList(), store.denseToSlot(), store.hotArray(),
                                   store.coldArray()};
        storeParts(io, parts, perBody);
    }
}

/// A strictly ascending list (the steps binary-search the warm-start cache and merge touching lists).
template <class Io, class Vec>
void requireSorted(Io& io, const Vec& v, const char* what) {
    if constexpr (Io::kReading) {
        for (std::size_t i = 1; i < v.size() && io.ok(); ++i) {
            if (!(v[i - 1] < v[i])) io.fail(std::string(what) + " are not strictly sorted");
        }
    }
}

/// Parses a framed snapshot of `kind` into `fresh` (a default-constructed world) through transfer(source, fresh),
/// then checks that the payload was consumed exactly and that the header's body count matches. On failure returns
/// false with the reason in *error; the caller swaps `fresh` in only on success.
template <class World, class Transfer>
bool readSnapshot(const std::uint8_t* data, std::size_t size, SnapshotKind kind, World& fresh, std::string* error,
                  Transfer transfer) {
    SnapshotView view;
    if (!unframeSnapshot(data, size, kind, &view, error)) return false;
    ByteSource source{ByteReader(view.payload, view.payloadSize)};
    transfer(source, fresh);
    if (source.ok() && !source.in.atEnd()) source.in.fail("unexpected bytes after the state");
    if (source.ok() && std::uint64_t(fresh.bodyCount()) != view.bodyCount)
        source.in.fail("header announces " + std::to_string(view.bodyCount) + " bodies, payload holds " +
                       std::to_string(fresh.bodyCount()));
    if (!source.ok()) {
        if (error) *error = "snapshot rejected: " + source.in.error();
        return false;
    }
    return true;
}

/// The settings both worlds have, in the order both write them (inside their "def" scope, after the gravity): step
/// settings, then extra() (the world's own fields), then sleep and LCP options. Reading checks the ranges the step
/// and the solver can run with (a pivot tolerance >= 1 leaves no admissible pivot and crashed Lemke).
template <class Io, class Def, class Extra>
void worldSettings(Io& io, Def& def, Extra extra) {
    io.f64("hz", def.hz);
    io.f64("restitutionThreshold", def.restitutionThreshold);
    io.f64("linearSlop", def.linearSlop);
    io.f64("baumgarte", def.baumgarte);
    io.f64("maxCorrectionSpeed", def.maxCorrectionSpeed);
    io.f64("speculativeDistance", def.speculativeDistance);
    io.f64("tangentDeadZone", def.tangentDeadZone);
    extra();
    boolean(io, "enableSleep", def.enableSleep);
    io.f64("linearSleepTolerance", def.linearSleepTolerance);
    io.f64("angularSleepTolerance", def.angularSleepTolerance);
    io.f64("timeToSleep", def.timeToSleep);
    io.i32("lcp.maxPivots", def.lcp.maxPivots);
    io.u64("lcp.maxWork", def.lcp.maxWork);
    io.f64("lcp.pivotTolerance", def.lcp.pivotTolerance);
    io.f64("lcp.residualTolerance", def.lcp.residualTolerance);
    io.f64("lcp.degeneracyPerturbation", def.lcp.degeneracyPerturbation);
    enumeration(io, "lcp.warmCovering", def.lcp.warmCovering, int(LcpOptions::WarmCovering::violated));
    io.i32("lcp.blockPivotRounds", def.lcp.blockPivotRounds);
    io.u64("stepBudget", def.stepBudget);  // (workerCount and the task callbacks are not state)
    if constexpr (Io::kReading) {
        def.lcp.warmBasis = nullptr;  // per-call input of the solver, never state
        // The ranges a scene file may set (core/input_policy.h); the rest must be >= 0 and not absurd.
        if (!policy::inRange(def.hz, policy::kMinHz, policy::kMaxHz)) io.fail("def.hz out of range");
        if (!policy::inRange(def.restitutionThreshold, 0.0, policy::kMaxRestitutionThreshold))
            io.fail("def.restitutionThreshold out of range");
        for (double x : {def.linearSlop, def.baumgarte, def.maxCorrectionSpeed, def.speculativeDistance,
                         def.tangentDeadZone, def.linearSleepTolerance, def.angularSleepTolerance, def.timeToSleep})
            if (!policy::inRange(x, 0.0, 1.0e6)) io.fail("def: step or sleep settings out of range");
        if (def.lcp.maxPivots < 0 || !(def.lcp.pivotTolerance >= 0.0 && def.lcp.pivotTolerance < 1.0) ||
            def.lcp.residualTolerance < 0.0 || def.lcp.degeneracyPerturbation < 0.0 || def.lcp.blockPivotRounds < 0 ||
            def.lcp.blockPivotRounds > 8)
            io.fail("def.lcp: options out of range");
    }
}

/// One warm-start cache entry.
template <class Io, class E>
void cacheEntry(Io& io, E& e) {
    io.u32("slotA", e.slotA);
    io.u32("slotB", e.slotB);
    io.u16("shapeA", e.shapeA);
    io.u16("shapeB", e.shapeB);
    io.u32("feature", e.feature);
    io.u32("basicMask", e.basicMask);
    io.u32("cost", e.cost);
    io.f64("normalImpulse", e.normalImpulse);
    io.f64("tangentImpulse.x", e.tangentImpulse[0]);
    io.f64("tangentImpulse.y", e.tangentImpulse[1]);
    io.f64("tangentImpulse.z", e.tangentImpulse[2]);
}

/// The state of core/world_step.h: the warm-start cache (WarmStartCache) and the touching pairs (TouchPairs), both
/// sorted (checked when reading).
template <class Io, class Cache, class Pairs>
void stepState(Io& io, Cache& cache, Pairs& touching) {
    if constexpr (Io::kReading) {
        std::vector<ContactKey> entries;
        sequence(io, "cache", entries, 56, [&](auto& e) { cacheEntry(io, e); });
        requireSorted(io, entries, "warm-start cache entries");
        if (io.ok()) cache.replace(entries);
    } else {
        sequence(io, "cache", cache.entries(), 56, [&](auto& e) { cacheEntry(io, e); });
    }
    sequence(io, "touching", touching, 16, [&](auto& pair) {
        io.u64("a", pair.first);
        io.u64("b", pair.second);
    });
    requireSorted(io, touching, "touching pairs");
}

/// What a world keeps of itself when it restores a snapshot: the settings that are not state (its threads) and the
/// step's thread pool and buffers. Called on the freshly read world before it replaces the live one.
template <class Def>
void keepExecution(const Def& live, Def& fresh) {
    setTaskFields(fresh, taskFieldsOf(live));
}

/// Reading only: every cache entry names two different body slots of the table (index1 in 1..slotCount; a destroyed
/// body's entries are dropped with it, its slot stays in the table) and every touching pair is ordered a < b, as the
/// step makes them.
template <class Io, class Cache, class Pairs>
void checkStepState(Io& io, const Cache& cache, std::size_t slotCount, const Pairs& touching) {
    for (const ContactKey& e : cache.entries()) {
        if (e.slotA == 0 || e.slotB == 0 || e.slotA > slotCount || e.slotB > slotCount || e.slotA == e.slotB) {
            io.fail("warm-start cache: an entry names no pair of body slots");
            return;
        }
    }
    for (const auto& pair : touching) {
        if (!(pair.first < pair.second)) {
            io.fail("touching pairs: a pair is not ordered");
            return;
        }
    }
}

/// The bytes a state walk writes (walk(ByteSink&)).
template <class Walk>
std::vector<std::uint8_t> stateBytes(Walk walk) {
    ByteSink sink;
    walk(sink);
    return std::move(sink.out.data());
}

/// The named fields a state walk visits (walk(FieldSink&)).
template <class Walk>
std::vector<StateField> namedFields(Walk walk) {
    FieldSink sink;
    walk(sink);
    return std::move(sink.fields);
}

}  // namespace unison::state_transfer
