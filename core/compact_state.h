// core/compact_state.h — compact (rollback) states of a world: only what can change from one tick to the next.
//
// Owns: CompactState (a reusable byte buffer), its little-endian writer and bounds-checked reader with LEB128
// varints, and the dimension-free encoding shared by World2 and World3 (saveCompact / restoreCompact in
// resolver2d/world2d_state.cpp and resolver3d/world3d_state.cpp).
//
// What a compact state holds: the step count, the gravity, the ids of the bodies in dense order (to check that the
// world still holds the same bodies), per non-static body its pose, velocities and sleep state, the warm-start
// cache and the touching pairs. What it leaves out, because no tick can change it: settings other than the
// gravity, shapes, meshes, masses and inertia, and every field of a static body. So a compact state can only be
// restored into the world it was saved from (or a copy of it) while the same bodies exist: restoring it after a
// body was created or destroyed is refused (use World2/World3::snapshot() across such changes).
//
// Encoding (all little-endian; "v" = LEB128 varint):
//   u8 format, v stepCount, f64 gravity (D components),
//   v slot count, v free-list length + v slot each, v body count + (v slot, v generation) per dense body,
//   per non-static body in dense order: u8 flags (bit 0 awake, bit 1 some velocity is not +0.0, bit 2 sleepTime is
//   not +0.0), the pose doubles, then the velocity doubles if bit 1, then sleepTime if bit 2,
//   v cache entries + per entry (v slotA delta, v slotB (delta when slotA repeats), v shapeA, v shapeB, u32 feature,
//   v basicMask), v touching pairs + per pair (v a delta, v b delta from the previous b when a repeats, else from a).
// Invariants: a zero flag means the value is exactly +0.0 (bits 0), so every bit is restored; keys come out in the
// order the step keeps them (cache by key, touching pairs ascending), which the reader checks.
#pragma once

#include "step_support.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace unison {

/// The bytes of a compact state. Saving into the same object again reuses its memory (no allocation once grown).
class CompactState {
public:
    /// The encoded bytes, (size()).
    const std::uint8_t* data() const { return mBytes.data(); }
    /// Number of encoded bytes.
    std::size_t size() const { return mSize; }
    /// Copies external bytes in (e.g. received over a network).
    void assign(const std::uint8_t* data, std::size_t size) {
        if (mBytes.size() < size) mBytes.resize(size);
        if (size) std::memcpy(mBytes.data(), data, size);
        mSize = size;
    }

private:
    friend class CompactWriter;
    std::vector<std::uint8_t> mBytes;  // capacity; only [0, mSize) is meaningful
    std::size_t mSize = 0;
};

/// Writes into a CompactState through a raw pointer; the caller announces an upper bound of the bytes first.
class CompactWriter {
public:
    explicit CompactWriter(CompactState& out) : mOut(out) { mOut.mSize = 0; }
    ~CompactWriter() { finish(); }
    /// Makes room for at least `bytes` more bytes.
    void reserve(std::size_t bytes) {
        const std::size_t used = std::size_t(mP - base());
        if (mOut.mBytes.size() < used + bytes) mOut.mBytes.resize(used + bytes);
        mP = base() + used;
        mOut.mSize = used;
    }
    void u8(std::uint8_t v) { *mP++ = v; }
    void u32(std::uint32_t v) {
        for (int i = 0; i < 4; ++i) *mP++ = std::uint8_t(v >> (8 * i));
    }
    void u64(std::uint64_t v) {
        for (int i = 0; i < 8; ++i) *mP++ = std::uint8_t(v >> (8 * i));
    }
    /// A double as its IEEE-754 bit pattern.
    void f64(double v) {
        std::uint64_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        u64(bits);
    }
    /// LEB128: 7 bits per byte, low bits first (at most 10 bytes).
    void varint(std::uint64_t v) {
        while (v >= 0x80u) {
            *mP++ = std::uint8_t(v | 0x80u);
            v >>= 7;
        }
        *mP++ = std::uint8_t(v);
    }
    /// Records the number of bytes written in the CompactState.
    void finish() { mOut.mSize = std::size_t(mP - base()); }

private:
    std::uint8_t* base() { return mOut.mBytes.data(); }
    CompactState& mOut;
    std::uint8_t* mP = mOut.mBytes.data();
};

/// Reads what CompactWriter wrote, never past the end; after the first failure every read returns 0.
class CompactReader {
public:
    CompactReader(const std::uint8_t* data, std::size_t size) : mP(data), mEnd(data + size) {}
    std::uint8_t u8() { return have(1) ? *mP++ : 0; }
    std::uint32_t u32() {
        if (!have(4)) return 0;
        std::uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v |= std::uint32_t(*mP++) << (8 * i);
        return v;
    }
    std::uint64_t u64() {
        if (!have(8)) return 0;
        std::uint64_t v = 0;
        for (int i = 0; i < 8; ++i) v |= std::uint64_t(*mP++) << (8 * i);
        return v;
    }
    double f64() {
        const std::uint64_t bits = u64();
        double v;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }
    std::uint64_t varint() {
        std::uint64_t v = 0;
        for (int shift = 0; shift < 64; shift += 7) {
            if (!have(1)) return 0;
            const std::uint8_t b = *mP++;
            v |= std::uint64_t(b & 0x7Fu) << shift;
            if (!(b & 0x80u)) return v;
        }
        fail("varint longer than 64 bits");
        return 0;
    }
    void fail(const std::string& why) {
        if (mError.empty()) mError = why;
        mP = mEnd;
    }
    bool ok() const { return mError.empty(); }
    bool atEnd() const { return mP == mEnd; }
    const std::string& error() const { return mError; }
    std::size_t remaining() const { return std::size_t(mEnd - mP); }

private:
    bool have(std::size_t n) {
        if (std::size_t(mEnd - mP) >= n) return true;
        fail("truncated compact state");
        return false;
    }
    const std::uint8_t* mP;
    const std::uint8_t* mEnd;
    std::string mError;
};

namespace compact_detail {

constexpr std::uint8_t kFormat = 1;
constexpr std::uint8_t kAwake = 1, kMoving = 2, kSleeping = 4;  // body flags (kSleeping: sleepTime != +0.0)

inline bool isPositiveZero(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return bits == 0;
}

template <class Info>
bool isStatic(const Info& info) {
    return info.type == decltype(info.type)::staticBody;
}

}  // namespace compact_detail

/// Encodes a world's dynamic state (see the top of this file). F is the world's field list: static function
/// templates pose(hot, f), velocity(hot, f) and gravity(def, f) call f(value) on each double of a hot record or
/// the settings (const or not) in a fixed order, and kPose, kVelocity, kGravity count them.
template <class F, class Def, class Store>
void saveCompact(CompactState& out, std::uint64_t stepCount, const Def& def, const Store& store,
                 const WarmStartCache& cache, const TouchPairs& touching) {
    using namespace compact_detail;
    CompactWriter w(out);
    const auto& slots = store.slots();
    const auto& freeList = store.freeList();
    const std::size_t n = store.denseToSlot().size();
    // Upper bound: header, ids (10 + 5 bytes each), bodies, cache entries (5 + 5 + 3 + 3 + 4 + 5), pairs (2 x 10).
    w.reserve(1 + 10 + 8 * F::kGravity + 30 + 5 * freeList.size() + 15 * n + n * (1 + 8 * (F::kPose + F::kVelocity + 1)) +
              10 + 25 * cache.entries().size() + 10 + 20 * touching.size());
    w.u8(kFormat);
    w.varint(stepCount);
    F::gravity(def, [&](double v) { w.f64(v); });
    w.varint(slots.size());
    w.varint(freeList.size());
    for (std::uint32_t s : freeList) w.varint(s);
    w.varint(n);
    for (std::size_t d = 0; d < n; ++d) {
        const std::uint32_t slot = store.denseToSlot()[d];
        w.varint(slot);
        w.varint(slots[slot].generation);
    }
    const auto& hot = store.hotArray();
    const auto& cold = store.coldArray();
    for (std::size_t d = 0; d < n; ++d) {
        if (isStatic(cold[d])) continue;  // nothing of a static body changes
        const auto& s = hot[d];
        bool moving = false;
        F::velocity(s, [&](double v) { moving = moving || !isPositiveZero(v); });
        const bool sleeping = !isPositiveZero(cold[d].sleepTime);
        w.u8(std::uint8_t((cold[d].awake ? kAwake : 0) | (moving ? kMoving : 0) | (sleeping ? kSleeping : 0)));
        F::pose(s, [&](double v) { w.f64(v); });
        if (moving) F::velocity(s, [&](double v) { w.f64(v); });
        if (sleeping) w.f64(cold[d].sleepTime);
    }
    w.varint(cache.entries().size());
    std::uint32_t prevA = 0, prevB = 0;
    for (const ContactKey& e : cache.entries()) {
        w.varint(e.slotA - prevA);
        w.varint(e.slotA == prevA ? e.slotB - prevB : e.slotB);
        w.varint(e.shapeA);
        w.varint(e.shapeB);
        w.u32(e.feature);
        w.varint(e.basicMask);
        prevA = e.slotA;
        prevB = e.slotB;
    }
    w.varint(touching.size());
    std::uint64_t prevFirst = 0, prevSecond = 0;
    for (const auto& [a, b] : touching) {
        w.varint(a - prevFirst);
        w.varint(a == prevFirst ? b - prevSecond : b - a);
        prevFirst = a;
        prevSecond = b;
    }
    w.finish();
}

/// Restores what saveCompact() wrote into the same world. Everything is checked before anything is written:
/// on failure the world is untouched and the reason is returned; on success the result is empty.
template <class F, class Def, class Store>
std::string restoreCompact(const std::uint8_t* data, std::size_t size, std::uint64_t& ioStepCount, Def& ioDef,
                           Store& ioStore, WarmStartCache& ioCache, TouchPairs& ioTouching) {
    using namespace compact_detail;
    CompactReader r(data, size);
    if (r.u8() != kFormat && r.ok()) return "compact state: unknown format";
    const std::uint64_t stepCount = r.varint();
    double gravity[F::kGravity];
    for (double& g : gravity) g = r.f64();
    // The bodies must be the ones the state was saved with.
    const auto& slots = ioStore.slots();
    const auto& freeList = ioStore.freeList();
    const auto& denseToSlot = ioStore.denseToSlot();
    bool same = r.varint() == slots.size() && r.varint() == freeList.size();
    for (std::size_t i = 0; same && i < freeList.size(); ++i) same = r.varint() == freeList[i];
    same = same && r.varint() == denseToSlot.size();
    for (std::size_t d = 0; same && d < denseToSlot.size(); ++d) {
        const std::uint32_t slot = denseToSlot[d];
        same = r.varint() == slot;
        same = same && r.varint() == slots[slot].generation;
    }
    if (!r.ok()) return r.error();
    if (!same)
        return "compact state: the world's bodies differ from the saved ones (a body was created or destroyed "
               "since): restore a full snapshot instead";
    // Pass 1: check the body section's length and flags, remembering where it starts.
    auto& cold = ioStore.coldArray();
    const CompactReader bodies = r;
    for (std::size_t d = 0; d < denseToSlot.size() && r.ok(); ++d) {
        if (isStatic(cold[d])) continue;
        const std::uint8_t flags = r.u8();
        if (flags > (kAwake | kMoving | kSleeping)) r.fail("compact state: bad body flags");
        const int count = F::kPose + ((flags & kMoving) ? F::kVelocity : 0) + ((flags & kSleeping) ? 1 : 0);
        for (int i = 0; i < count; ++i) {
            const double v = r.f64();
            if (r.ok() && !std::isfinite(v)) r.fail("compact state: a non-finite body value");
        }
    }
    std::vector<ContactKey> entries(r.ok() ? std::size_t(r.varint()) : 0);
    if (entries.size() > r.remaining() / 8) return "compact state: cache entry count exceeds the data";
    std::uint32_t prevA = 0, prevB = 0;
    for (std::size_t i = 0; i < entries.size() && r.ok(); ++i) {
        ContactKey& e = entries[i];
        e.slotA = prevA + std::uint32_t(r.varint());
        e.slotB = e.slotA == prevA ? prevB + std::uint32_t(r.varint()) : std::uint32_t(r.varint());
        e.shapeA = std::uint16_t(r.varint());
        e.shapeB = std::uint16_t(r.varint());
        e.feature = r.u32();
        e.basicMask = std::uint32_t(r.varint());
        if (i > 0 && !(entries[i - 1] < e)) r.fail("compact state: cache entries are not strictly sorted");
        prevA = e.slotA;
        prevB = e.slotB;
    }
    TouchPairs pairs(r.ok() ? std::size_t(r.varint()) : 0);
    if (pairs.size() > r.remaining() / 2) return "compact state: touching pair count exceeds the data";
    std::uint64_t prevFirst = 0, prevSecond = 0;
    for (std::size_t i = 0; i < pairs.size() && r.ok(); ++i) {
        const std::uint64_t a = prevFirst + r.varint();
        const std::uint64_t b = a == prevFirst ? prevSecond + r.varint() : a + r.varint();
        pairs[i] = {a, b};
        if (i > 0 && !(pairs[i - 1] < pairs[i])) r.fail("compact state: touching pairs are not strictly sorted");
        prevFirst = a;
        prevSecond = b;
    }
    if (r.ok() && !r.atEnd()) r.fail("compact state: unexpected bytes at the end");
    if (!r.ok()) return r.error();
    // Pass 2: everything is valid; write it.
    CompactReader b = bodies;
    auto& hot = ioStore.hotArray();
    for (std::size_t d = 0; d < denseToSlot.size(); ++d) {
        if (isStatic(cold[d])) continue;
        const std::uint8_t flags = b.u8();
        F::pose(hot[d], [&](double& v) { v = b.f64(); });
        F::velocity(hot[d], [&](double& v) { v = (flags & kMoving) ? b.f64() : 0.0; });
        cold[d].sleepTime = (flags & kSleeping) ? b.f64() : 0.0;
        cold[d].awake = (flags & kAwake) != 0;
    }
    ioStepCount = stepCount;
    int k = 0;
    F::gravity(ioDef, [&](double& v) { v = gravity[k++]; });
    ioCache.replace(entries);
    ioTouching.swap(pairs);
    return {};
}

}  // namespace unison
