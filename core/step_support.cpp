// core/step_support.cpp — see step_support.h.
#include "step_support.h"

#include <algorithm>
#include <iterator>

namespace unison {

void WarmStartCache::replace(std::vector<ContactKey>& entries) {
    // A restored compact state hands the entries over in order: checking is O(n), sorting them again is not.
    if (!std::is_sorted(entries.begin(), entries.end())) std::sort(entries.begin(), entries.end());
    mEntries.swap(entries);
}

void WarmStartCache::forgetSlot(std::uint32_t slot1) {
    mEntries.erase(std::remove_if(mEntries.begin(), mEntries.end(),
                                  [&](const ContactKey& e) { return e.slotA == slot1 || e.slotB == slot1; }),
                   mEntries.end());
}

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
