// core/sweep_order.h — the sort of a sort-and-sweep broadphase, kept between steps: boxes move little from one step to
// the next, so last step's order is nearly sorted and an insertion sort finishes it in about O(n). The key
// (lower x, index) is a strict total order, so the result is the one sorted sequence whatever order the sort starts
// from: the cache changes the cost, never the answer (and is not state).
#pragma once

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace unison {

/// (lower x, box index) of one valid box.
struct SweepEntry {
    double lowerX;
    int index;
};

inline bool sweepLess(const SweepEntry& l, const SweepEntry& r) {
    return l.lowerX < r.lowerX || (l.lowerX == r.lowerX && l.index < r.index);
}

/// The order of the last sort: every box index of that call, valid ones first in sorted order.
struct SweepCache {
    std::vector<int> order;
};

/// The valid boxes (valid(i)) of [0, n) sorted by (lowerX(i), i) into `out`. With a cache from a call of the same n,
/// it starts from that call's order and sorts by insertion with a budget of moves (about 8 per box), then falls
/// back to std::sort; the cache is updated. Without one (nullptr), std::sort.
template <class Valid, class LowerX>
void sweepSort(int n, Valid valid, LowerX lowerX, std::vector<SweepEntry>& out, SweepCache* cache) {
    out.clear();
    out.reserve(std::size_t(n));
    const bool warm = cache && int(cache->order.size()) == n;
    for (int k = 0; k < n; ++k) {
        const int i = warm ? cache->order[std::size_t(k)] : k;
        if (valid(i)) out.push_back({lowerX(i), i});
    }
    bool sorted = false;
    if (warm) {
        std::size_t budget = 8 * out.size() + 64;
        sorted = true;
        for (std::size_t k = 1; k < out.size() && sorted; ++k) {
            const SweepEntry e = out[k];
            std::size_t j = k;
            while (j > 0 && sweepLess(e, out[j - 1])) {
                if (budget-- == 0) {
                    sorted = false;
                    break;
                }
                out[j] = out[j - 1];
                --j;
            }
            out[j] = e;
        }
    }
    if (!sorted) std::sort(out.begin(), out.end(), sweepLess);
    if (!cache) return;
    cache->order.clear();
    cache->order.reserve(std::size_t(n));
    for (const SweepEntry& e : out) cache->order.push_back(e.index);
    for (int i = 0; i < n; ++i)
        if (!valid(i)) cache->order.push_back(i);
}

}  // namespace unison
