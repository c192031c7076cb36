// core/step_support.cpp — see step_support.h.
#include "step_support.h"

#include <algorithm>
#include <cassert>
#include <iterator>

namespace unison {

namespace {

/// Sorts a sequence stably (equal elements keep their order). The step hands over sequences that are nearly sorted
/// already (contacts come in body order, a manifold's points perhaps swapped): an insertion sort takes those in
/// O(n + inversions); one that moves more than 8 elements per element on average is finished by std::stable_sort.
/// Same result either way.
template <class It>
void sortNearlySorted(It first, It last) {
    const std::size_t budget = 8 * std::size_t(last - first);
    std::size_t moves = 0;
    for (It it = first; it != last; ++it) {
        if (it == first || !(*it < *std::prev(it))) continue;
        auto value = std::move(*it);
        It hole = it;
        for (; hole != first && value < *std::prev(hole); --hole, ++moves) *hole = std::move(*std::prev(hole));
        *hole = std::move(value);
        if (moves > budget) {
            std::stable_sort(first, last);
            return;
        }
    }
}

}  // namespace

void WarmStartCache::replace(std::vector<ContactKey>& entries) {
    // Two contacts of one step can share a key (the same feature id reported twice, or a sleeping island copying
    // its hit for each contact). The sort is stable, so step order decides among equal keys, and only the first of
    // them is kept: the cache is strictly sorted and the same on every platform. The next cache comes in contact
    // order, which is nearly key order, and a restored state hands the entries over sorted: the insertion sort
    // costs O(n) then.
    sortNearlySorted(entries.begin(), entries.end());
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
    sortNearlySorted(now.begin(), now.end());
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
