// core/step_support.cpp — see step_support.h.
#include "step_support.h"

#include <algorithm>
#include <iterator>

namespace unison {

bool ContactKey::operator<(const ContactKey& o) const {
    if (slotA != o.slotA) return slotA < o.slotA;
    if (slotB != o.slotB) return slotB < o.slotB;
    if (shapeA != o.shapeA) return shapeA < o.shapeA;
    if (shapeB != o.shapeB) return shapeB < o.shapeB;
    return feature < o.feature;
}

bool ContactKey::sameKey(const ContactKey& o) const { return !(*this < o) && !(o < *this); }

const ContactKey* WarmStartCache::find(const ContactKey& key) const {
    const auto it = std::lower_bound(mEntries.begin(), mEntries.end(), key);
    return it != mEntries.end() && it->sameKey(key) ? &*it : nullptr;
}

void WarmStartCache::replace(std::vector<ContactKey>& entries) {
    std::sort(entries.begin(), entries.end());
    mEntries.swap(entries);
}

void WarmStartCache::forgetSlot(std::uint32_t slot1) {
    mEntries.erase(std::remove_if(mEntries.begin(), mEntries.end(),
                                  [&](const ContactKey& e) { return e.slotA == slot1 || e.slotB == slot1; }),
                   mEntries.end());
}

void appendWarmBasis(std::uint32_t mask, int ci, int nc, int k, std::vector<int>& outBasis) {
    if (mask & 1u) outBasis.push_back(ci);
    for (int m = 0; m < k; ++m)
        if (mask & (2u << m)) outBasis.push_back(nc + ci * k + m);
    if (mask & (2u << k)) outBasis.push_back(nc + nc * k + ci);
}

void storeBasis(const std::vector<int>& basis, int nc, int k, bool friction, ContactKey* first) {
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

std::uint64_t touchKey(BodyId id) { return (std::uint64_t(id.generation) << 32) | id.index1; }

BodyId touchId(std::uint64_t key) { return BodyId{std::uint32_t(key & 0xffffffffu), std::uint32_t(key >> 32)}; }

void touchEvents(TouchPairs& now, const TouchPairs& before, std::vector<TouchEvent>& outBegin,
                 std::vector<TouchEvent>& outEnd) {
    std::sort(now.begin(), now.end());
    now.erase(std::unique(now.begin(), now.end()), now.end());
    outBegin.clear();
    outEnd.clear();
    TouchPairs diff;
    std::set_difference(now.begin(), now.end(), before.begin(), before.end(), std::back_inserter(diff));
    for (const auto& p : diff) outBegin.push_back({touchId(p.first), touchId(p.second)});
    diff.clear();
    std::set_difference(before.begin(), before.end(), now.begin(), now.end(), std::back_inserter(diff));
    for (const auto& p : diff) outEnd.push_back({touchId(p.first), touchId(p.second)});
}

}  // namespace unison
