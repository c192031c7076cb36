// core/sweep_order.h — the sort of a sort-and-sweep broadphase, kept between steps: boxes move little from one step to
// the next, so last step's order is nearly sorted and an insertion sort finishes it in about O(n). The key
// (lower x, index) is a strict total order, so the result is the one sorted sequence whatever order the sort starts
// from: the cache changes the cost, never the answer (and is not state).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
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

/// Runs fn(chunk) for every chunk in [0, chunks), in any order and possibly on several threads (each chunk writes
/// only its own outputs). A broadphase takes one to sweep ranges of its sorted order in parallel.
using ChunkRunner = std::function<void(int chunks, const std::function<void(int chunk)>& fn)>;

/// The order of the last sort: every box index of that call, valid ones first in sorted order; and how many more
/// calls go to a broadphase's crowded-layout method directly (after a sweep ran past its candidate budget).
struct SweepCache {
    std::vector<int> order;
    int gridCalls = 0;
};

/// The valid boxes (valid(i)) of [0, n) sorted by (lowerX(i), i) into `out`. With a cache from a call of the same n,
/// it starts from that call's order and sorts by insertion with a budget of moves (about 8 per box), then falls
/// back to std::sort; the cache is updated. Without one (nullptr), std::sort. With a runner, the entries are read
/// in parallel chunks (each writes its own part of `out`; the result is the same).
template <class Valid, class LowerX>
void sweepSort(int n, Valid valid, LowerX lowerX, std::vector<SweepEntry>& out, SweepCache* cache,
               const ChunkRunner* runner = nullptr) {
    const bool warm = cache && int(cache->order.size()) == n;
    // Every box's entry in the starting order; an invalid box i is marked by index -1 - i and then set aside.
    out.resize(std::size_t(n));
    const int chunks = runner ? std::min(64, n / 256) : 0;
    std::vector<std::uint8_t> chunkInvalid(std::size_t(std::max(chunks, 1)), 0);  // a chunk met an invalid box
    auto fill = [&](int begin, int end, int chunk) {
        bool any = false;
        for (int k = begin; k < end; ++k) {
            const int i = warm ? cache->order[std::size_t(k)] : k;
            const bool ok = valid(i);
            out[std::size_t(k)] = ok ? SweepEntry{lowerX(i), i} : SweepEntry{0.0, -1 - i};
            any = any || !ok;
        }
        chunkInvalid[std::size_t(chunk)] = any ? 1 : 0;
    };
    if (chunks < 2) {
        fill(0, n, 0);
    } else {
        (*runner)(chunks, [&](int c) { fill(int(std::int64_t(n) * c / chunks), int(std::int64_t(n) * (c + 1) / chunks), c); });
    }
    std::vector<int> invalid;
    const bool anyInvalid = std::find(chunkInvalid.begin(), chunkInvalid.end(), std::uint8_t(1)) != chunkInvalid.end();
    if (anyInvalid)
        for (const SweepEntry& e : out)
            if (e.index < 0) invalid.push_back(-1 - e.index);
    if (!invalid.empty()) {
        out.erase(std::remove_if(out.begin(), out.end(), [](const SweepEntry& e) { return e.index < 0; }), out.end());
        std::sort(invalid.begin(), invalid.end());
    }
    bool sorted = false, moved = false;
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
                moved = true;
            }
            out[j] = e;
        }
    }
    if (!sorted) std::sort(out.begin(), out.end(), sweepLess);
    if (!cache) return;
    // Started from the cache's order with every box valid and nothing moved: out's indices are that order already.
    if (warm && sorted && !moved && !anyInvalid) return;
    cache->order.clear();
    cache->order.reserve(std::size_t(n));
    for (const SweepEntry& e : out) cache->order.push_back(e.index);
    cache->order.insert(cache->order.end(), invalid.begin(), invalid.end());
}

/// Sorts distinct (a, b) pairs of non-negative indices by (a, b): a least-significant-digit radix sort, one stable
/// counting pass on b and one on a. The order is a total one, so the result is the same as std::sort's, in
/// O(pairs + largest index) instead of O(pairs log pairs) (a static ground met by every box made one long run).
/// Pairs that come sorted (bodies numbered along x, as in a row of circles) cost one comparison each.
inline void sortPairs(std::vector<std::pair<int, int>>& pairs) {
    if (std::is_sorted(pairs.begin(), pairs.end())) return;
    if (pairs.size() < 64) {
        std::sort(pairs.begin(), pairs.end());
        return;
    }
    int top = 0;
    for (const auto& p : pairs) top = std::max(top, std::max(p.first, p.second));
    std::vector<int> at(std::size_t(top) + 2);
    std::vector<std::pair<int, int>> other(pairs.size());
    auto pass = [&](const std::vector<std::pair<int, int>>& from, std::vector<std::pair<int, int>>& to, bool byFirst) {
        std::fill(at.begin(), at.end(), 0);
        for (const auto& p : from) ++at[std::size_t(byFirst ? p.first : p.second) + 1];
        for (std::size_t i = 1; i < at.size(); ++i) at[i] += at[i - 1];
        for (const auto& p : from) to[std::size_t(at[std::size_t(byFirst ? p.first : p.second)]++)] = p;
    };
    pass(pairs, other, false);
    pass(other, pairs, true);
}

/// The sweep over sorted boxes: for every position i of `order`, the boxes j > i that start before box i ends in x
/// (order[j].lowerX <= upperX(order[i].index)) and pass keep(a, b) (the other axes, flags), as (min, max) pairs,
/// sorted by (a, b), into `pairs`. With a runner, ranges of i are swept as separate chunks and their pairs joined:
/// the sorted result is the same whatever the chunks and their order. maxCandidates > 0 bounds the boxes met in x
/// (a chunk of c of the m boxes gets maxCandidates * c / m of them): false, and `pairs` incomplete, when a sweep ran
/// past it. Boxes laid out in a grid (rows of pyramids) meet every row's boxes in x, which is what the bound catches.
template <class UpperX, class Keep>
bool sweepPairsWithin(const std::vector<SweepEntry>& order, UpperX upperX, Keep keep, const ChunkRunner* runner,
                      std::size_t maxCandidates, std::vector<std::pair<int, int>>& pairs) {
    const int m = int(order.size());
    auto sweep = [&](int begin, int end, std::vector<std::pair<int, int>>& out) {
        const std::size_t budget =
            maxCandidates > 0 && m > 0 ? std::size_t(double(maxCandidates) * double(end - begin) / double(m)) + 1 : 0;
        std::size_t met = 0;
        for (int i = begin; i < end; ++i) {
            const int a = order[std::size_t(i)].index;
            const double ax = upperX(a);
            int j = i + 1;
            for (; j < m && order[std::size_t(j)].lowerX <= ax; ++j) {
                const int b = order[std::size_t(j)].index;
                if (keep(a, b)) out.emplace_back(std::min(a, b), std::max(a, b));
            }
            met += std::size_t(j - i - 1);
            if (budget > 0 && met > budget) return false;
        }
        return true;
    };
    pairs.clear();
    const int chunks = runner ? std::min(64, m / 128) : 0;
    if (chunks < 2) {
        if (!sweep(0, m, pairs)) return false;
    } else {
        std::vector<std::vector<std::pair<int, int>>> parts(static_cast<std::size_t>(chunks));
        std::vector<std::uint8_t> within(static_cast<std::size_t>(chunks), 1);
        (*runner)(chunks, [&](int c) {
            within[std::size_t(c)] = sweep(int(std::int64_t(m) * c / chunks), int(std::int64_t(m) * (c + 1) / chunks),
                                           parts[std::size_t(c)])
                                         ? 1
                                         : 0;
        });
        if (std::find(within.begin(), within.end(), std::uint8_t(0)) != within.end()) return false;
        std::size_t total = 0;
        for (const auto& p : parts) total += p.size();
        pairs.reserve(total);
        for (const auto& p : parts) pairs.insert(pairs.end(), p.begin(), p.end());
    }
    sortPairs(pairs);
    return true;
}

/// sweepPairsWithin without a bound.
template <class UpperX, class Keep>
std::vector<std::pair<int, int>> sweepPairs(const std::vector<SweepEntry>& order, UpperX upperX, Keep keep,
                                            const ChunkRunner* runner) {
    std::vector<std::pair<int, int>> pairs;
    sweepPairsWithin(order, upperX, keep, runner, 0, pairs);
    return pairs;
}

}  // namespace unison
