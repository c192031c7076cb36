// core/body_store.h — generational body handles over dense, packed storage, shared by the 2D and 3D worlds.
//
// Owns: the slot table (BodyId, the public handle, is in unison/types.h) that maps handles to dense indices, the free list, and two
// dense arrays per body: Hot (what the solver reads and writes every step) and Cold (everything else). The solver
// iterates hotArray() directly, so live bodies are always packed at dense indices [0, size()).
// Invariants (checked by restore() and by tests/test_body_store.cpp after every operation):
//   - hotArray(), coldArray() and denseToSlot() all have size() entries;
//   - slots()[s].dense == -1 iff slot s is in freeList(), and each free slot appears there exactly once;
//   - for a live slot s: denseToSlot()[slots()[s].dense] == s, and for every dense d: slots()[denseToSlot()[d]].dense == d;
//   - every slot's generation is >= 1 (fresh slots start at 1; reuse increments it, skipping 0 on wrap-around);
//   - slots().size() <= capacity().
// Why the rules look like this: ids must be the same on every peer of a lockstep game, so slot reuse is
// last-in-first-out (the newest freed slot comes back first) and never depends on addresses or hash order.
// Removal swaps the last dense body into the hole, so a body's dense index can change when another is destroyed;
// hold BodyIds, not dense indices, across destroy() calls.
#pragma once

#include <unison/types.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace unison {

/// One entry of the slot table (8 bytes, no padding, so it can be hashed field by field or byte by byte).
struct BodySlot {
    std::uint32_t generation = 0;  ///< current generation of the slot (>= 1 once the slot exists)
    std::int32_t dense = -1;       ///< dense index of the live body, -1 when the slot is free
};
static_assert(sizeof(BodySlot) == 8, "BodySlot is hashed and stored as two 32-bit fields");

/// Dense storage of bodies with generational handles. Hot and Cold are copyable value types.
template <class Hot, class Cold>
class BodyStore {
public:
    /// Slot table entry; see BodySlot.
    using Slot = BodySlot;

    /// A store that holds at most maxBodies live bodies (negative counts as 0).
    explicit BodyStore(int maxBodies = 1 << 20) : mMaxBodies(maxBodies < 0 ? 0 : maxBodies) {}

    /// Adds a body at dense index size(). Reuses the most recently freed slot (generation + 1), else appends a
    /// fresh slot (generation 1). Returns the null id, and changes nothing, when capacity() bodies are live.
    BodyId create(const Hot& hot, const Cold& cold) {
        if (size() >= mMaxBodies) return BodyId::null();
        std::uint32_t slot;
        if (!mFree.empty()) {
            slot = mFree.back();
            mFree.pop_back();
            std::uint32_t& gen = mSlots[slot].generation;
            gen = gen + 1u == 0u ? 1u : gen + 1u;  // skip 0 on wrap-around: generations stay >= 1
        } else {
            slot = std::uint32_t(mSlots.size());
            mSlots.push_back(Slot{1u, -1});
        }
        mSlots[slot].dense = std::int32_t(mHot.size());
        mHot.push_back(hot);
        mCold.push_back(cold);
        mDenseToSlot.push_back(slot);
        return BodyId{slot + 1u, mSlots[slot].generation};
    }

    /// Removes a live body: the last dense body moves into its place and its slot is fixed up; the freed slot goes
    /// on top of the free list. Returns false (and changes nothing) for null or stale ids.
    bool destroy(BodyId id) {
        if (!valid(id)) return false;
        const std::uint32_t slot = id.index1 - 1u;
        const std::int32_t d = mSlots[slot].dense;
        const std::int32_t last = std::int32_t(mHot.size()) - 1;
        if (d != last) {
            mHot[std::size_t(d)] = std::move(mHot[std::size_t(last)]);
            mCold[std::size_t(d)] = std::move(mCold[std::size_t(last)]);
            mDenseToSlot[std::size_t(d)] = mDenseToSlot[std::size_t(last)];
            mSlots[mDenseToSlot[std::size_t(d)]].dense = d;
        }
        mHot.pop_back();
        mCold.pop_back();
        mDenseToSlot.pop_back();
        mSlots[slot].dense = -1;
        mFree.push_back(slot);
        return true;
    }

    /// True when id names a live body (not null, slot in range and live, generation matches).
    bool valid(BodyId id) const {
        if (id.index1 == 0u || id.index1 > mSlots.size()) return false;
        const Slot& s = mSlots[id.index1 - 1u];
        return s.dense >= 0 && s.generation == id.generation;
    }

    /// Dense index of a live body, -1 when id is null or stale.
    int denseIndex(BodyId id) const { return valid(id) ? int(mSlots[id.index1 - 1u].dense) : -1; }

    /// Handle of the body at a dense index; the null id when dense is outside [0, size()).
    BodyId idAt(int dense) const {
        if (dense < 0 || dense >= size()) return BodyId::null();
        const std::uint32_t slot = mDenseToSlot[std::size_t(dense)];
        return BodyId{slot + 1u, mSlots[slot].generation};
    }

    /// Hot record of a live body; nullptr when id is null or stale.
    const Hot* findHot(BodyId id) const {
        const int d = denseIndex(id);
        return d < 0 ? nullptr : &mHot[std::size_t(d)];
    }
    /// Cold record of a live body; nullptr when id is null or stale.
    const Cold* findCold(BodyId id) const {
        const int d = denseIndex(id);
        return d < 0 ? nullptr : &mCold[std::size_t(d)];
    }
    /// Handles of all live bodies, (size()), in dense order.
    std::vector<BodyId> ids() const {
        std::vector<BodyId> out;
        out.reserve(mHot.size());
        for (int d = 0; d < size(); ++d) out.push_back(idAt(d));
        return out;
    }

    /// Number of live bodies (the length of every dense array).
    int size() const { return int(mHot.size()); }
    /// Maximum number of live bodies.
    int capacity() const { return mMaxBodies; }

    /// Hot record at a dense index in [0, size()) (unchecked).
    Hot& hot(int dense) { return mHot[std::size_t(dense)]; }
    /// Hot record at a dense index in [0, size()) (unchecked).
    const Hot& hot(int dense) const { return mHot[std::size_t(dense)]; }
    /// Cold record at a dense index in [0, size()) (unchecked).
    Cold& cold(int dense) { return mCold[std::size_t(dense)]; }
    /// Cold record at a dense index in [0, size()) (unchecked).
    const Cold& cold(int dense) const { return mCold[std::size_t(dense)]; }

    /// All hot records, (size()), in dense order. Do not resize it: only its elements may be written.
    std::vector<Hot>& hotArray() { return mHot; }
    /// All hot records, (size()), in dense order.
    const std::vector<Hot>& hotArray() const { return mHot; }
    /// All cold records, (size()), in dense order. Do not resize it: only its elements may be written.
    std::vector<Cold>& coldArray() { return mCold; }
    /// All cold records, (size()), in dense order.
    const std::vector<Cold>& coldArray() const { return mCold; }

    /// The slot table, (number of slots ever used), for hashing and snapshots.
    const std::vector<Slot>& slots() const { return mSlots; }
    /// Free slots, (slots - size()); the back is the next slot create() reuses.
    const std::vector<std::uint32_t>& freeList() const { return mFree; }
    /// Slot of each dense body, (size()).
    const std::vector<std::uint32_t>& denseToSlot() const { return mDenseToSlot; }

    /// Replaces the whole state (e.g. from a snapshot) after checking every invariant listed at the top of this
    /// file. Returns an empty string on success; otherwise a description of the first problem found, and the
    /// store is left exactly as it was. Capacity is kept; a state with more slots than capacity() is rejected.
    std::string restore(std::vector<Slot> slots, std::vector<std::uint32_t> freeList, std::vector<Hot> hot,
                        std::vector<Cold> cold, std::vector<std::uint32_t> denseToSlot) {
        std::string error = check(slots, freeList, hot.size(), cold.size(), denseToSlot);
        if (!error.empty()) return error;
        mSlots = std::move(slots);
        mFree = std::move(freeList);
        mHot = std::move(hot);
        mCold = std::move(cold);
        mDenseToSlot = std::move(denseToSlot);
        return {};
    }

private:
    std::string check(const std::vector<Slot>& slots, const std::vector<std::uint32_t>& freeList,
                      std::size_t hotCount, std::size_t coldCount,
                      const std::vector<std::uint32_t>& denseToSlot) const {
        const std::size_t n = denseToSlot.size();
        if (hotCount != n || coldCount != n) return "hot, cold and denseToSlot sizes differ";
        if (slots.size() > std::size_t(mMaxBodies)) return "more slots than the store's capacity";
        for (std::size_t d = 0; d < n; ++d) {
            const std::uint32_t s = denseToSlot[d];
            if (s >= slots.size()) return "denseToSlot[" + std::to_string(d) + "] is out of range";
            if (slots[s].dense != std::int32_t(d))
                return "slots[denseToSlot[" + std::to_string(d) + "]].dense does not point back";
        }
        std::size_t freeSlots = 0;
        for (std::size_t s = 0; s < slots.size(); ++s) {
            if (slots[s].generation == 0u) return "slot " + std::to_string(s) + " has generation 0";
            const std::int32_t d = slots[s].dense;
            if (d == -1) {
                ++freeSlots;
            } else if (d < 0 || std::size_t(d) >= n || denseToSlot[std::size_t(d)] != s) {
                return "slot " + std::to_string(s) + " has an inconsistent dense index";
            }
        }
        if (freeList.size() != freeSlots) return "free list size differs from the number of free slots";
        std::vector<std::uint8_t> seen(slots.size(), 0);
        for (std::uint32_t s : freeList) {
            if (s >= slots.size()) return "free list entry " + std::to_string(s) + " is out of range";
            if (slots[s].dense != -1) return "free list holds live slot " + std::to_string(s);
            if (seen[s]) return "free list holds slot " + std::to_string(s) + " twice";
            seen[s] = 1;
        }
        return {};
    }

    int mMaxBodies;
    std::vector<Slot> mSlots;                // (slots) generation + dense index per slot
    std::vector<std::uint32_t> mFree;        // (slots - size) LIFO stack of free slots
    std::vector<Hot> mHot;                   // (size) packed, solver-facing
    std::vector<Cold> mCold;                 // (size) packed, same order as mHot
    std::vector<std::uint32_t> mDenseToSlot; // (size) slot of each dense body
};

}  // namespace unison
