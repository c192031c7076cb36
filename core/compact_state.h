// core/compact_state.h — compact (rollback) states of a world: only what can change from one tick to the next.
//
// Owns: CompactState (a reusable byte buffer), its little-endian writer and bounds-checked reader with LEB128
// varints, and the dimension-free encoding shared by World2 and World3 (saveCompact / restoreCompact in
// resolver2d/world2d_state.cpp and resolver3d/world3d_state.cpp).
//
// What a compact state holds: the step count, the gravity and the step budget, the ids of the bodies in dense order (to check that the
// world still holds the same bodies), per non-static body its pose, velocities and sleep state, the warm-start
// cache and the touching pairs. What it leaves out, because no tick can change it: settings other than the
// gravity and the step budget, shapes, meshes, masses and inertia, and every field of a static body. So a compact state can only be
// restored into the world it was saved from (or a copy of it) while the same bodies exist: restoring it after a
// body was created or destroyed is refused (use World2/World3::snapshot() across such changes).
//
// Encoding (all little-endian; "v" = LEB128 varint):
//   u8 format, v stepCount, f64 gravity (D components), v stepBudget,
//   v slot count, v free-list length + v slot each, v body count + (z slot delta from the previous dense body,
//   v generation) per dense body ("z": a signed delta as a zigzag varint),
//   per non-static body in dense order: u8 flags (bit 0 awake, bit 1 some velocity is not +0.0, bit 2 sleepTime is
//   not +0.0, bit 3 the centre of mass has the bits of the position), the pose doubles (position, rotation, then the
//   centre unless bit 3), then the velocity doubles if bit 1, then sleepTime if bit 2,
//   v cache entries + per entry (v slotA delta, then v slotB delta when slotA repeats, else z slotB - slotA; u8
//   shapeA << 4 | shapeB when both < 15, else 0xFF, v shapeA, v shapeB; the feature as z (its delta from the
//   previous entry's) when the entry has the previous entry's two slots, else as u32; the basicMask as v (bits 0-22
//   << 1 | 1 when any of bits 23-31 is set) and then, when set, v (bits 23-31 in reverse order, so that the flags
//   of core/step_support.h that most entries carry take one byte); v cost; u8 impulse codes (2 bits each for the
//   normal impulse and the tangent impulse's 3 components, from bit 0: 0 = +0.0, 1 = -0.0, 2 = a double follows)
//   and those doubles),
//   v touching pairs + per pair (v a delta, v b delta from the previous b when a repeats, else from a).
// Small deltas keep almost every varint at one byte, which is also what makes decoding fast.
//   then u64 XXH3 of every byte before it.
// Invariants: a zero's code says which zero it is (a 2D tangent impulse has a -0.0 component whenever it points
// along -x or -y), so every bit is restored; keys come out in the
// order the step keeps them (cache by key, touching pairs ascending; the reader checks the pairs and the cache sorts
// entries that are not). Values are restored
// as saved: the checksum, the ids and the layout are checked, not the numbers (a state saved from a world is as
// valid as that world was).
#pragma once

#include "state_io.h"
#include "step_support.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#if defined(__GNUC__)
#define UNISON_COMPACT_INLINE __attribute__((always_inline)) inline
#else
#define UNISON_COMPACT_INLINE inline
#endif

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

namespace compact_detail {

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
constexpr bool kLittleEndian = true;
#else
constexpr bool kLittleEndian = false;
#endif

/// Stores / loads an n-byte little-endian integer (n = 4 or 8) at p: one move on little-endian machines.
template <class U>
inline void storeLE(std::uint8_t* p, U v) {
    if constexpr (kLittleEndian) {
        std::memcpy(p, &v, sizeof v);
    } else {
        for (std::size_t i = 0; i < sizeof v; ++i) p[i] = std::uint8_t(v >> (8 * i));
    }
}
template <class U>
inline U loadLE(const std::uint8_t* p) {
    U v = 0;
    if constexpr (kLittleEndian) {
        std::memcpy(&v, p, sizeof v);
    } else {
        for (std::size_t i = 0; i < sizeof v; ++i) v |= U(p[i]) << (8 * i);
    }
    return v;
}

}  // namespace compact_detail

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
        compact_detail::storeLE(mP, v);
        mP += 4;
    }
    void u64(std::uint64_t v) {
        compact_detail::storeLE(mP, v);
        mP += 8;
    }
    /// A double as its IEEE-754 bit pattern.
    void f64(double v) {
        std::uint64_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        compact_detail::storeLE(mP, bits);
        mP += 8;
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

/// Reads what CompactWriter wrote, never past the end; after the first failure every read returns 0. The
/// unchecked reads (suffix U) are for bytes a need() call has already vouched for.
class CompactReader {
public:
    CompactReader(const std::uint8_t* data, std::size_t size) : mP(data), mEnd(data + size) {}
    /// True when n more bytes are there; otherwise fails.
    bool need(std::size_t n) {
        if (std::size_t(mEnd - mP) >= n) return true;
        fail("truncated compact state");
        return false;
    }
    std::uint8_t u8() { return need(1) ? *mP++ : 0; }
    std::uint32_t u32() { return need(4) ? u32U() : 0; }
    double f64() { return need(8) ? f64U() : 0.0; }
    std::uint32_t u32U() {
        const std::uint32_t v = compact_detail::loadLE<std::uint32_t>(mP);
        mP += 4;
        return v;
    }
    std::uint64_t u64U() {
        const std::uint64_t v = compact_detail::loadLE<std::uint64_t>(mP);
        mP += 8;
        return v;
    }
    void skipU(std::size_t n) { mP += n; }
    double f64U() {
        const std::uint64_t bits = compact_detail::loadLE<std::uint64_t>(mP);
        mP += 8;
        double v;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }
    UNISON_COMPACT_INLINE std::uint64_t varint() {
        if (mP < mEnd && *mP < 0x80u) return *mP++;  // the common one-byte case, inlined
        return varintLong();
    }
    std::uint64_t varintLong() {
        std::uint64_t v = 0;
        const bool roomy = mEnd - mP >= 10;  // a varint has at most 10 bytes: no check per byte then
        for (int shift = 0; shift < 64; shift += 7) {
            if (!roomy && !need(1)) return 0;
            const std::uint8_t b = *mP++;
            v |= std::uint64_t(b & 0x7Fu) << shift;
            if (!(b & 0x80u)) return v;
        }
        fail("varint longer than 64 bits");
        return 0;
    }
    void fail(const char* why) {
        if (!mError) mError = why;
        mP = mEnd;
    }
    bool ok() const { return mError == nullptr; }
    bool atEnd() const { return mP == mEnd; }
    std::string error() const { return mError ? mError : ""; }
    std::size_t remaining() const { return std::size_t(mEnd - mP); }

private:
    const std::uint8_t* mP;
    const std::uint8_t* mEnd;
    const char* mError = nullptr;  // a string literal: the reader never allocates
};

namespace compact_detail {

constexpr std::uint8_t kFormat = 3;
// Body flags (kSleeping: sleepTime != +0.0; kCentered: the centre of mass has the position's bits, as for every body
// whose centre of mass is its origin, and is not written).
constexpr std::uint8_t kAwake = 1, kMoving = 2, kSleeping = 4, kCentered = 8;

/// Signed deltas as varints: 0, -1, 1, -2, ... -> 0, 1, 2, 3, ...
inline std::uint64_t zigzag(std::int64_t v) { return (std::uint64_t(v) << 1) ^ std::uint64_t(v >> 63); }
inline std::int64_t unzigzag(std::uint64_t v) { return std::int64_t(v >> 1) ^ -std::int64_t(v & 1u); }

/// The 9-bit values in reverse bit order, a table built at compile time (one load per cache entry: a loop over the
/// bits was a fifth of a save and restore).
struct ReversedNineBits {
    std::uint16_t value[512] = {};
    constexpr ReversedNineBits() {
        for (unsigned h = 0; h < 512; ++h) {
            unsigned r = 0;
            for (unsigned b = 0; b < 9; ++b) r |= ((h >> b) & 1u) << (8 - b);
            value[h] = std::uint16_t(r);
        }
    }
};
inline constexpr ReversedNineBits kReversedNineBits{};

/// Bits 23-31 of a warm-start entry's basicMask (`high` < 512) in reverse order (its own inverse): the flags most
/// entries carry (kActiveSetEntry, kSettledEntry and its run) land in bits 1-4.
inline std::uint32_t reverseHighBits(std::uint32_t high) { return kReversedNineBits.value[high & 0x1FFu]; }

/// An impulse's 2-bit code: 0 = +0.0, 1 = -0.0, 2 = the double is written.
constexpr unsigned kImpulsePlusZero = 0, kImpulseMinusZero = 1, kImpulseValue = 2;
inline unsigned impulseCode(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return bits == 0 ? kImpulsePlusZero : bits == (std::uint64_t(1) << 63) ? kImpulseMinusZero : kImpulseValue;
}

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
    // Upper bound: header, ids (10 + 5 bytes each), bodies, cache entries (5 + 5 + 3 + 3 + 5 + 4 + 2 + 5 + 1 + 32),
    // pairs (2 x 10).
    w.reserve(1 + 10 + 8 * F::kGravity + 10 + 30 + 5 * freeList.size() + 15 * n +
              n * (1 + 8 * (F::kPose + F::kVelocity + 1)) + 10 + 65 * cache.entries().size() + 10 +
              20 * touching.size() + 8);
    w.u8(kFormat);
    w.varint(stepCount);
    F::gravity(def, [&](double v) { w.f64(v); });
    w.varint(def.stepBudget);
    w.varint(slots.size());
    w.varint(freeList.size());
    for (std::uint32_t s : freeList) w.varint(s);
    w.varint(n);
    std::uint32_t prevSlot = 0;
    for (std::size_t d = 0; d < n; ++d) {
        const std::uint32_t slot = store.denseToSlot()[d];
        w.varint(zigzag(std::int64_t(slot) - std::int64_t(prevSlot)));
        w.varint(slots[slot].generation);
        prevSlot = slot;
    }
    const auto& hot = store.hotArray();
    const auto& cold = store.coldArray();
    static_assert(2 * F::kCenter <= F::kPose, "the pose starts with the position and ends with the centre");
    for (std::size_t d = 0; d < n; ++d) {
        if (isStatic(cold[d])) continue;  // nothing of a static body changes
        const auto& s = hot[d];
        bool moving = false;
        F::velocity(s, [&](double v) { moving = moving || !isPositiveZero(v); });
        const bool sleeping = !isPositiveZero(cold[d].sleepTime);
        double pose[F::kPose];
        int at = 0;
        F::pose(s, [&](double v) { pose[at++] = v; });
        const bool centered = std::memcmp(pose, pose + F::kPose - F::kCenter, sizeof(double) * F::kCenter) == 0;
        w.u8(std::uint8_t((cold[d].awake ? kAwake : 0) | (moving ? kMoving : 0) | (sleeping ? kSleeping : 0) |
                          (centered ? kCentered : 0)));
        for (int i = 0; i < F::kPose - (centered ? F::kCenter : 0); ++i) w.f64(pose[i]);
        if (moving) F::velocity(s, [&](double v) { w.f64(v); });
        if (sleeping) w.f64(cold[d].sleepTime);
    }
    w.varint(cache.entries().size());
    std::uint32_t prevA = 0, prevB = 0, prevFeature = 0;
    for (const ContactKey& e : cache.entries()) {
        w.varint(e.slotA - prevA);
        w.varint(e.slotA == prevA ? e.slotB - prevB : zigzag(std::int64_t(e.slotB) - std::int64_t(e.slotA)));
        if (e.shapeA < 15 && e.shapeB < 15) {
            w.u8(std::uint8_t(e.shapeA << 4 | e.shapeB));
        } else {
            w.u8(0xFF);
            w.varint(e.shapeA);
            w.varint(e.shapeB);
        }
        if (e.slotA == prevA && e.slotB == prevB) w.varint(zigzag(std::int64_t(e.feature) - std::int64_t(prevFeature)));
        else w.u32(e.feature);
        prevFeature = e.feature;
        const std::uint32_t high = e.basicMask >> 23;
        w.varint(std::uint64_t(e.basicMask & 0x7FFFFFu) << 1 | (high != 0 ? 1u : 0u));
        if (high != 0) w.varint(reverseHighBits(high));
        w.varint(e.cost);
        const double impulses[4] = {e.normalImpulse, e.tangentImpulse[0], e.tangentImpulse[1], e.tangentImpulse[2]};
        unsigned codes = 0;
        for (int i = 0; i < 4; ++i) codes |= impulseCode(impulses[i]) << (2 * i);
        w.u8(std::uint8_t(codes));
        for (int i = 0; i < 4; ++i)
            if (((codes >> (2 * i)) & 3u) == kImpulseValue) w.f64(impulses[i]);
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
    w.u64(hash64(out.data(), out.size()));
    w.finish();
}

/// Restores what saveCompact() wrote into the same world. Everything is checked before anything is written:
/// on failure the world is untouched and the reason is returned; on success the result is empty.
template <class F, class Def, class Store>
std::string restoreCompactState(const std::uint8_t* data, std::size_t size, std::uint64_t& ioStepCount, Def& ioDef,
                           Store& ioStore, WarmStartCache& ioCache, TouchPairs& ioTouching) {
    using namespace compact_detail;
    if (data == nullptr || size < 9) return "compact state: truncated";
    CompactReader tail(data + size - 8, 8);
    if (tail.u64U() != hash64(data, size - 8)) return "compact state: checksum mismatch (corrupt or truncated)";
    CompactReader r(data, size - 8);
    if (r.u8() != kFormat && r.ok()) return "compact state: unknown format";
    const std::uint64_t stepCount = r.varint();
    double gravity[F::kGravity];
    for (double& g : gravity) g = r.f64();
    for (double g : gravity)
        if (!std::isfinite(g)) r.fail("compact state: the gravity is not finite");
    const std::uint64_t stepBudget = r.varint();
    // The bodies must be the ones the state was saved with.
    const auto& slots = ioStore.slots();
    const auto& freeList = ioStore.freeList();
    const auto& denseToSlot = ioStore.denseToSlot();
    bool same = r.varint() == slots.size() && r.varint() == freeList.size();
    for (std::size_t i = 0; same && i < freeList.size(); ++i) same = r.varint() == freeList[i];
    same = same && r.varint() == denseToSlot.size();
    std::uint32_t prevSlot = 0;
    for (std::size_t d = 0; same && d < denseToSlot.size(); ++d) {
        const std::uint32_t slot = denseToSlot[d];
        same = r.varint() == zigzag(std::int64_t(slot) - std::int64_t(prevSlot));
        same = same && r.varint() == slots[slot].generation;
        prevSlot = slot;
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
        if (flags > (kAwake | kMoving | kSleeping | kCentered)) r.fail("compact state: bad body flags");
        const int count = F::kPose - ((flags & kCentered) ? F::kCenter : 0) + ((flags & kMoving) ? F::kVelocity : 0) +
                          ((flags & kSleeping) ? 1 : 0);
        if (r.need(8 * std::size_t(count))) {
            for (int i = 0; i < count; ++i) {
                if (!std::isfinite(r.f64U())) {
                    r.fail("compact state: a body's pose, velocity or sleep time is not finite");
                    break;
                }
            }
        }
    }
    // Decoded into buffers kept between calls (after the swaps below they hold the world's previous arrays).
    static thread_local std::vector<ContactKey> entries;
    static thread_local TouchPairs pairs;
    const std::size_t entryCount = r.ok() ? std::size_t(r.varint()) : 0;
    if (entryCount > r.remaining() / 8) return "compact state: cache entry count exceeds the data";
    entries.resize(entryCount);
    std::uint32_t prevA = 0, prevB = 0, prevFeature = 0;
    for (std::size_t i = 0; i < entries.size() && r.ok(); ++i) {
        ContactKey& e = entries[i];
        e.slotA = prevA + std::uint32_t(r.varint());
        const std::uint64_t b = r.varint();  // read either way: the choice below compiles without a branch
        e.slotB = e.slotA == prevA ? prevB + std::uint32_t(b) : std::uint32_t(std::int64_t(e.slotA) + unzigzag(b));
        const std::uint8_t shapes = r.u8();
        if (shapes != 0xFF) {
            e.shapeA = shapes >> 4;
            e.shapeB = shapes & 15u;
        } else {
            e.shapeA = std::uint16_t(r.varint());
            e.shapeB = std::uint16_t(r.varint());
        }
        const bool samePair = e.slotA == prevA && e.slotB == prevB;
        e.feature = samePair ? std::uint32_t(std::int64_t(prevFeature) + unzigzag(r.varint())) : r.u32();
        prevFeature = e.feature;
        const std::uint64_t low = r.varint();  // (WarmStartCache::replace() sorts entries that come unsorted)
        const std::uint64_t high = (low & 1u) ? r.varint() : 0;
        if (low > (std::uint64_t(0x7FFFFFu) << 1 | 1u) || ((low & 1u) != 0 && (high == 0 || high > 0x1FFu)))
            r.fail("compact state: bad basis mask");
        e.basicMask = std::uint32_t(low >> 1) | reverseHighBits(std::uint32_t(high)) << 23;
        e.cost = std::uint32_t(r.varint());
        const unsigned codes = r.u8();
        double* impulses[4] = {&e.normalImpulse, &e.tangentImpulse[0], &e.tangentImpulse[1], &e.tangentImpulse[2]};
        for (int k = 0; k < 4; ++k) {
            const unsigned code = (codes >> (2 * k)) & 3u;
            if (code > kImpulseValue) r.fail("compact state: bad impulse code");
            *impulses[k] = code == kImpulseValue ? r.f64() : code == kImpulseMinusZero ? -0.0 : 0.0;
        }
        if (!(std::isfinite(e.normalImpulse) && std::isfinite(e.tangentImpulse[0]) &&
              std::isfinite(e.tangentImpulse[1]) && std::isfinite(e.tangentImpulse[2])))
            r.fail("compact state: a cached impulse is not finite");
        if (e.slotA == 0 || e.slotB == 0 || e.slotA > slots.size() || e.slotB > slots.size() || e.slotA == e.slotB)
            r.fail("compact state: a cache entry names no pair of body slots");
        prevA = e.slotA;
        prevB = e.slotB;
    }
    const std::size_t pairCount = r.ok() ? std::size_t(r.varint()) : 0;
    if (pairCount > r.remaining() / 2) return "compact state: touching pair count exceeds the data";
    pairs.resize(pairCount);
    std::uint64_t prevFirst = 0, prevSecond = 0;
    bool ascending = true;
    for (std::size_t i = 0; i < pairs.size() && r.ok(); ++i) {
        const std::uint64_t a = prevFirst + r.varint();
        const std::uint64_t delta = r.varint();
        const std::uint64_t b = a == prevFirst ? prevSecond + delta : a + delta;
        ascending &= i == 0 || a > prevFirst || (a == prevFirst && b > prevSecond);
        pairs[i] = {a, b};
        prevFirst = a;
        prevSecond = b;
    }
    if (!ascending) r.fail("compact state: touching pairs are not strictly sorted");
    if (r.ok() && !r.atEnd()) r.fail("compact state: unexpected bytes at the end");
    if (!r.ok()) return r.error();
    // Pass 2: everything is valid; write it.
    CompactReader b = bodies;
    auto& hot = ioStore.hotArray();
    for (std::size_t d = 0; d < denseToSlot.size(); ++d) {
        if (isStatic(cold[d])) continue;
        const std::uint8_t flags = b.u8();
        double pose[F::kPose];
        const int stored = F::kPose - ((flags & kCentered) ? F::kCenter : 0);
        for (int i = 0; i < stored; ++i) pose[i] = b.f64U();
        for (int i = stored; i < F::kPose; ++i) pose[i] = pose[i - (F::kPose - F::kCenter)];
        int at = 0;
        F::pose(hot[d], [&](double& v) { v = pose[at++]; });
        F::velocity(hot[d], [&](double& v) { v = (flags & kMoving) ? b.f64U() : 0.0; });
        cold[d].sleepTime = (flags & kSleeping) ? b.f64U() : 0.0;
        cold[d].awake = (flags & kAwake) != 0;
    }
    ioStepCount = stepCount;
    int k = 0;
    F::gravity(ioDef, [&](double& v) { v = gravity[k++]; });
    ioDef.stepBudget = stepBudget;
    ioCache.replace(entries);
    ioTouching.swap(pairs);
    return {};
}

/// restoreCompactState() with the reason in *error (if given): true on success.
template <class F, class Def, class Store>
bool restoreCompact(const std::uint8_t* data, std::size_t size, std::uint64_t& ioStepCount, Def& ioDef, Store& ioStore,
                    WarmStartCache& ioCache, TouchPairs& ioTouching, std::string* error) {
    const std::string why = restoreCompactState<F>(data, size, ioStepCount, ioDef, ioStore, ioCache, ioTouching);
    if (!why.empty() && error) *error = why;
    return why.empty();
}

}  // namespace unison
