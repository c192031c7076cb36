// core/step_support.h — dimension-free pieces of a world step: the warm-start cache keyed by contact features, the
// mapping between a friction LCP's basis and per-contact bit masks, and begin/end touch events. (World3's state
// hash and snapshots are in resolver3d/world3d_state.cpp, on core/state_transfer.h.)
//
// Owns no world state; core/world_step.h (the step of World2 and World3) uses it.
// Invariants: the cache is strictly sorted by key (a total order on plain integers; no key twice); events come out
// sorted by body-id key.
#pragma once

#include "body_store.h"
#include "state_io.h"

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace unison {

/// One warm-start cache entry: a contact (body slots, shape indices, feature id), which of its LCP unknowns were
/// basic at the end of the step that made it (see appendWarmBasis), the impulses it got (the approximation's warm
/// start, core/pgs.h) and its share of its island's predicted exact work (core/step_budget.h). 16 bytes of keys,
/// 8 of mask and cost, 32 of impulses: 56 bytes.
struct ContactKey {
    std::uint32_t slotA = 0, slotB = 0;
    std::uint16_t shapeA = 0, shapeB = 0;
    std::uint32_t feature = 0;
    std::uint32_t basicMask = 0;
    /// Work units of its island's exact solve per contact, as the budget allocation predicts it for next step (0:
    /// unknown; always 0 after a step without a budget).
    std::uint32_t cost = 0;
    /// The next step's warm impulses: those applied, or for an island the active-set path answered (2D, fewer
    /// than kPathFirstContacts contacts) its prediction for the next step (Resolution::predictedImpulses).
    double normalImpulse = 0.0;               ///< N s
    double tangentImpulse[3] = {0.0, 0.0, 0.0};  ///< N s, world frame (2D: z is 0)
    /// Order by (slotA, slotB, shapeA, shapeB, feature); the mask is not part of the key.
    bool operator<(const ContactKey& o) const {
        if (slotA != o.slotA) return slotA < o.slotA;
        if (slotB != o.slotB) return slotB < o.slotB;
        if (shapeA != o.shapeA) return shapeA < o.shapeA;
        if (shapeB != o.shapeB) return shapeB < o.shapeB;
        return feature < o.feature;
    }
    bool sameKey(const ContactKey& o) const {
        return slotA == o.slotA && slotB == o.slotB && shapeA == o.shapeA && shapeB == o.shapeB && feature == o.feature;
    }
};
static_assert(sizeof(ContactKey) == 56, "ContactKey changed: serialise the new field in both worlds' state files");

/// Previous-step contacts, sorted by key.
class WarmStartCache {
public:
    /// The entry with the same key, or nullptr. (Inline: the step looks up every contact.)
    const ContactKey* find(const ContactKey& key) const {
        const auto it = std::lower_bound(mEntries.begin(), mEntries.end(), key);
        return it != mEntries.end() && it->sameKey(key) ? &*it : nullptr;
    }
    /// Index of the entry with the same key, or -1. Looks at the few entries around `hint` first (a step asks in
    /// nearly ascending key order, so the previous answer + 1 is usually close; -1: no hint), then binary-searches.
    int findFrom(const ContactKey& key, int hint) const {
        const int n = int(mEntries.size());
        for (int i = hint < 0 ? n : std::max(0, hint - 2), end = std::min(n, i + 6); i < end; ++i) {
            if (mEntries[std::size_t(i)].sameKey(key)) return i;
            if (key < mEntries[std::size_t(i)]) break;
        }
        const ContactKey* hit = find(key);
        return hit ? int(hit - mEntries.data()) : -1;
    }
    /// The entry at an index findFrom() returned.
    const ContactKey& at(int index) const { return mEntries[std::size_t(index)]; }
    /// Replaces the contents with `entries`, sorted here by key; of entries with equal keys only the first (in the
    /// given order) is kept, so the cache never holds a key twice (checked by an assert in debug builds).
    void replace(std::vector<ContactKey>& entries);
    /// Drops the entries of body slot `slot1` (BodyId::index1), keeping the order of the rest. A destroyed body's
    /// entries must go: they are keyed by slot, and a body created later in the slot would inherit them.
    void forgetSlot(std::uint32_t slot1);
    const std::vector<ContactKey>& entries() const { return mEntries; }

private:
    std::vector<ContactKey> mEntries;
};

/// Set in ContactKey::basicMask on entries the approximation wrote (core/pgs.h): their basis bits are a guess read
/// off approximate impulses, and the next exact solve of their island starts cold instead (a wrong guess costs
/// several factorisations before Lemke gives it up). appendWarmBasis reads only bits 0..k+1 (k <= 29 here).
constexpr std::uint32_t kApproximateEntry = 1u << 31;
/// Set in ContactKey::basicMask on entries whose island the active-set path answered (2D, k = 2, and 3D, k = 4: the
/// bit never meets a basis bit): the island's next solve tries that path first (core/world_step_island.h).
constexpr std::uint32_t kActiveSetEntry = 1u << 30;
/// Set in ContactKey::basicMask on entries whose island Lemke answered with its warm guess as it stood (no pivot: the
/// island is settled; 2D only). An island of kActiveSetMinContacts or more whose every contact carries it with a full
/// run goes to the active-set path next, with tangential velocities taken exactly (no dead zone): on Lemke, whose
/// tie-breaking perturbation hides tangential speeds below ~1e-9, a settled pile's sub-dead-zone creep grows
/// (docs/solver-notes.md). The path's answers of such an island keep the mark.
constexpr std::uint32_t kSettledEntry = 1u << 29;
/// With kSettledEntry: how many steps in a row (1-3, saturating) Lemke answered the island without a pivot, in bits
/// 27-28. The hand-over waits for 3: a landing pile has single quiet steps between its pivoting ones.
constexpr int kSettledShift = 27;
constexpr std::uint32_t kSettledCount = 3u << kSettledShift;
/// With kSettledEntry on a handed-over island's path answer: how many of its path answers in a row (0-7) needed the
/// active-set iteration proper because the face of the warm start did not hold (bits 24-26). At kPathStallLimit the
/// island goes back to Lemke (kDeclinedEntry): for such an island the path costs more than Lemke's warm check (the
/// five-level card house: 1.0 against 0.32 ms per step).
constexpr int kPathStallShift = 24;
constexpr std::uint32_t kPathStallCount = 7u << kPathStallShift;
constexpr int kPathStallLimit = 7;
/// Set on every contact of an island that the path gave back (above), and kept by its answers while any of its
/// contacts carries it: such an island is not handed over again.
constexpr std::uint32_t kDeclinedEntry = 1u << 23;
/// 2D islands with fewer contacts always go to Lemke (3D: kPathFirstContacts3): its warm start costs one
/// factorisation of the guessed block, and a cold start about n/2 pivots of O(n) each, which the active-set
/// iterations beat only on big islands (measured:
/// 290-contact pyramids 5.3 ms/step with Lemke against 107-325 ms/step; a 4760-contact pyramid started cold 0.18 s/step
/// against more than 15 s/step).
constexpr int kActiveSetMinContacts = 64;
/// Islands of at least this many contacts go to the active-set path first even when Lemke answered them last step,
/// and the path restarts them from its interior-point answer when their warm face breaks (2D). While a testbed pyramid
/// lands, each step adds a row of contacts to one island of 400-900, and Lemke's warm start repairs the guess in
/// 50-180 pivots of O(n) each, where the restart takes one interior-point solve (20-25 factorisations of the bodies'
/// system). Against 1024: the 20-row pyramid's first 120 steps 238 -> 164 ms (300 steps 0.98 -> 0.72 ms/step), the
/// 40-row's 300 steps 6.3 -> 5.7 ms/step. Since the interior point ends at its face step (a few factorisations),
/// 128 rather than 384 (callgrind, scratch driver): the five-level card house (136 contacts) 630 steps 3.63e9 ->
/// 0.98e9 instructions, Box2D v3's 5 x 5 pyramids (islands of ~150-200 contacts) 200 steps 7.68e9 -> 6.76e9, the
/// 20-row testbed pyramid's first 120 steps 1.129e9 -> 1.064e9, the 30- and 40-row ones within 1 %; 64 and 96 as 128
/// but the 20-row pyramid +0.7 %; 192 and 256 send its landing islands of that size back to Lemke (2575-3076 pivots
/// in its first 120 steps against 454).
constexpr int kPathFirstContacts = 128;
/// Pivots per unknown of the friction LCP's Lemke solve (the c of its cap c n + 100) for a 2D island of
/// kPathFirstContacts or more whose path answer did not certify: the 3D world's cap, not the 2D one (8, for Lemke's
/// own landings of small tall structures). In every 2D benchmark scene and test, Lemke finished none of those solves:
/// on the 2000-circle container pile (islands of 450-730 contacts whose sliding contacts the path does not certify)
/// it ran out at 8 pivots per unknown on every such step, at 1.1-3.0 s each (the frictionless fallback that followed:
/// 8-16 ms), and at 60 per unknown (10 s for one step) as well. Such a solve also gets no more work units than the
/// path spent on the island (core/world_step_island.h).
constexpr int kPathLemkePivotsPerUnknown = 2;
/// The same for 3D islands (pyramid of four directions), and the smallest 3D island the path takes at all (2D:
/// kActiveSetMinContacts): every island of 32 or more. On the toppling 100-cube heap (callgrind, scratch driver)
/// 32 instead of 64: its landing's first 34 steps -11 % instructions, 200 steps -7 %; 16 instead of 32: +24 % over
/// the 34 steps (+16 % measured again with the kept island systems; Lemke answers islands of a few cubes in fewer
/// instructions). The column pile and the drop heap: no change.
constexpr int kPathFirstContacts3 = 32;
/// The smallest 3D island whose friction Lemke behind an uncertified path answer also gets no more work units than
/// the path spent (2D: every island of kPathFirstContacts or more). Behind the 3D path, in the drop heap's first 80
/// steps, the toppling heap's 300 and every test, Lemke finished on islands of 82-192 contacts (251-1722 pivots) and
/// on none of 373 contacts or more (each at its cap of 2 pivots per unknown: 4576-10,228 pivots, 0.5-3 s a step).
constexpr int kPathLemkeWorkCap3 = 256;
/// The share of the path's work units that Lemke gets behind an uncertified path answer on those islands (2D: of
/// kPathFirstContacts or more, 3D: of kPathLemkeWorkCap3 or more, a held near miss included): a quarter. With the
/// whole of the path's work, none of 101 such solves finished (the 100-cube drop heap's 300 steps: 54 at the limit,
/// 1 on a secondary ray; the 2000-circle pile's first 65 steps: 22; every test: 24; no other benchmark scene has
/// one), and they were half of those steps' time: the drop heap 17.8 ms/step, the pile's 65 steps 146 ms/step. With
/// a quarter, the same answers to the bit, 13.0 and 106 ms/step, and Lemke still has the pivots to repair a warm
/// start a few hundred basis changes from an answer (225-400 on the drop heap's islands of 339-718 contacts; an
/// eighth: 150-240, 11.8 ms/step).
constexpr int kPathLemkeWorkShare = 4;
/// Sweeps of the bounded approximation (core/pgs.h, warm from last step's impulses) that a 3D island gets when its
/// friction solve fails with no budget, in place of the frictionless LCP (with a budget the budget's approximation
/// follows, as for an island that ran out of work). On the 100-cube drop heap the frictionless answers let the heap
/// spread (its one big island failed on 253 of 300 steps) and peaked at 3.3 cm penetration; with the approximation the
/// heap keeps its friction, comes to rest, and its island certifies on the path again: 34 failed islands, 1.7 cm
/// (with 100-1000 sweeps; 64 sweeps: 4.1 cm).
constexpr int kFailedIslandSweeps3 = 200;
/// Iterations of the active-set phase for 3D islands (ActiveSetOptions::maxIterations; 2D keeps its default 12).
/// 30 rather than 12: on the drop heap's landing islands of ~200 contacts phase 1 was still converging after 12
/// (traced residuals 0.6 -> 5e-3 over its 12 iterations, then certified in phase 2).
constexpr int kPathIterations3 = 30;
/// The largest scaled residual of a 3D path answer applied as a near miss at once. A poorer near miss (within the
/// world's acceptResidual) is held while Lemke tries the island and applied only if Lemke fails. On the toppling
/// 100-cube heap the world's 1e-6 alone let near misses of 7.6e-6 m/s through (Lemke's answers stay below 1e-7),
/// for about 12 % less CPU time over 300 steps (1.64-1.75 s against 1.90-1.94 s).
constexpr double kPathAccept3 = 1e-8;
/// Islands of at least this many contacts (Box2D v3's 40- and 100-row large pyramids) keep their answers, not a
/// prediction, for the next step, end a near miss at the floor (kFloorExit), and keep the tangential dead zone;
/// smaller path islands take tangential velocities exactly. Against 1024 (instructions, scratch driver): the 30-row
/// testbed pyramid's 300 steps -9.5 %, Box2D v3's base-24 large pyramid's 150 steps -36 %, the 40-row testbed
/// pyramid's 200 steps -2 %; at 2048 the 40-row one's landing islands of 1024-2047 contacts took 7 % more and had 4
/// near misses (docs/solver-notes.md).
constexpr int kHugeIslandContacts = 4096;
/// On those islands a solve whose warm face ends within this many tolerances of the certificate is a near miss
/// there (ActiveSetOptions::floorExit): on the 100-row large pyramid no such solve was certified by the 20 more
/// factorisations of the later phases (0 of 8 in 300 steps), each ~60 ms.
constexpr double kFloorExit = 10.0;

/// Friction-LCP layout of DESIGN.md (FrictionLayout): unknowns [normals (nc) | tangents (nc x k) | slacks (nc)].
/// Mask bits of one contact: bit 0 normal, bits 1..k its tangents, bit k + 1 its slack (k <= 30).
/// Appends the LCP indices that `mask` marks basic for contact ci to `outBasis`.
inline void appendWarmBasis(std::uint32_t mask, int ci, int nc, int k, std::vector<int>& outBasis) {
    if (mask & 1u) outBasis.push_back(ci);
    for (int m = 0; m < k; ++m)
        if (mask & (2u << m)) outBasis.push_back(nc + ci * k + m);
    if (mask & (2u << k)) outBasis.push_back(nc + nc * k + ci);
}
/// |guess symmetric-difference basis|: the unknowns basic in one and not the other (indices >= 0, each list
/// without repeats, in any order). O(entries + largest index): no sort on the step's path.
inline int basisDistance(const std::vector<int>& guess, const std::vector<int>& basis) {
    if (guess.size() * basis.size() <= 64) {  // small islands (one contact: 1-3 each), without a table
        int common = 0;
        for (int j : guess) common += std::find(basis.begin(), basis.end(), j) != basis.end() ? 1 : 0;
        return int(guess.size() + basis.size()) - 2 * common;
    }
    int size = 0;
    for (int j : basis) size = std::max(size, j + 1);
    std::vector<char> inBasis(std::size_t(size), 0);
    for (int j : basis) inBasis[std::size_t(j)] = 1;
    int common = 0;
    for (int j : guess) common += j < size && inBasis[std::size_t(j)] ? 1 : 0;
    return int(guess.size() + basis.size()) - 2 * common;
}
/// Sets the mask bits of the contacts [first, first + nc) of `entries` from a solved basis. `friction` false: the
/// basis belongs to the frictionless LCP (indices are contacts).
inline void storeBasis(const std::vector<int>& basis, int nc, int k, bool friction, ContactKey* first) {
    for (int idx : basis) {
        std::uint32_t bit = 1u;
        int ci = idx;
        if (friction && idx >= nc + nc * k) {
            ci = idx - nc - nc * k;
            bit = 2u << k;
        } else if (friction && idx >= nc) {
            ci = (idx - nc) / k;
            bit = 2u << ((idx - nc) % k);
        }
        if (ci >= 0 && ci < nc) first[ci].basicMask |= bit;
    }
}

/// The fault of a world after its step `step` (World2/3::fault()): empty when motionProblem(hot record) is empty
/// for every body, else "step N: " and the first non-finite field of fields() (the slow named walk, run only then)
/// or, for a finite value out of range, the body and the problem.
template <class Store, class Check, class Fields>
std::string stepFault(const Store& bodies, std::uint64_t step, Check motionProblem, Fields fields) {
    const auto& hot = bodies.hotArray();
    for (std::size_t d = 0; d < hot.size(); ++d) {
        const std::string why = motionProblem(hot[d]);
        if (why.empty()) continue;
        const std::string field = firstNonFinite(fields());
        return "step " + std::to_string(step) + ": " + (field.empty() ? describeBody(bodies.idAt(int(d))) + " " + why : field);
    }
    return {};
}

/// Key of a body id for touch pairs: generation in the high half, slot + 1 in the low half.
inline std::uint64_t touchKey(BodyId id) { return (std::uint64_t(id.generation) << 32) | id.index1; }
/// Body id of a touchKey.
BodyId touchId(std::uint64_t key);

/// Touching body pairs (a < b by touchKey), sorted and unique.
using TouchPairs = std::vector<std::pair<std::uint64_t, std::uint64_t>>;
/// Sorts and de-duplicates pairs; writes the pairs in `now` but not in `before` to outBegin and the reverse to outEnd.
void touchEvents(TouchPairs& now, const TouchPairs& before, std::vector<TouchEvent>& outBegin,
                 std::vector<TouchEvent>& outEnd);

}  // namespace unison
