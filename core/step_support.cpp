// core/step_support.cpp — see step_support.h.
#include "step_support.h"

#include <algorithm>
#include <cassert>
#include <iterator>

namespace unison {

void WarmStartCache::replace(std::vector<ContactKey>& entries) {
    // Two contacts of one step can share a key (the same feature id reported twice, or a sleeping island copying
    // its hit for each contact). std::sort would leave their order, and so which mask find() returns and whether the
    // state holds both, to the standard library: a stable sort keeps step order among equal keys, and only the
    // first of them is kept, so the cache is strictly sorted and the same on every platform. A restored compact
    // state hands the entries over in order: checking is O(n), sorting them again is not.
    if (!std::is_sorted(entries.begin(), entries.end())) std::stable_sort(entries.begin(), entries.end());
    entries.erase(std::unique(entries.begin(), entries.end(),
                              [](const ContactKey& a, const ContactKey& b) { return a.sameKey(b); }),
                  entries.end());
    assert(std::adjacent_find(entries.begin(), entries.end(),
                              [](const ContactKey& a, const ContactKey& b) { return !(a < b); }) == entries.end());
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
