// resolver2d/broadphase2d.cpp — see broadphase2d.h.
//
// Sort and sweep (Baraff's "sweep and prune" without the incremental part): sort the boxes by lower x, then for
// each box walk forward through the boxes that start before it ends in x, test y, and keep the pair. Each unordered
// pair is met at most once (from the box that comes first in the sort), so no de-duplication is needed; a final
// sort by (a, b) makes the output independent of how ties in x were broken.
#include "broadphase2d.h"

#include <algorithm>
#include <stdexcept>

namespace unison {
namespace {

bool validBox(const Aabb2& b) { return b.lower.x <= b.upper.x && b.lower.y <= b.upper.y; }

}  // namespace

std::vector<std::pair<int, int>> findPairs(const std::vector<Aabb2>& boxes, const std::vector<std::uint8_t>& isStatic,
                                           SweepCache* cache) {
    if (!isStatic.empty() && isStatic.size() != boxes.size())
        throw std::invalid_argument("findPairs: isStatic must be empty or have one flag per box");
    const int n = static_cast<int>(boxes.size());
    auto staticBox = [&](int i) { return !isStatic.empty() && isStatic[i] != 0; };

    // Valid boxes have non-NaN lower.x, so (lower.x, index) is a strict total order.
    std::vector<SweepEntry> order;
    sweepSort(
        n, [&](int i) { return validBox(boxes[std::size_t(i)]); }, [&](int i) { return boxes[std::size_t(i)].lower.x; },
        order, cache);

    std::vector<std::pair<int, int>> pairs;
    const int m = static_cast<int>(order.size());
    for (int i = 0; i < m; ++i) {
        const int a = order[i].index;
        const Aabb2& ba = boxes[a];
        const bool staticA = staticBox(a);
        for (int j = i + 1; j < m && order[j].lowerX <= ba.upper.x; ++j) {
            const int b = order[j].index;
            if (staticA && staticBox(b)) continue;
            const Aabb2& bb = boxes[b];
            if (ba.lower.y <= bb.upper.y && bb.lower.y <= ba.upper.y)
                pairs.push_back(a < b ? std::make_pair(a, b) : std::make_pair(b, a));
        }
    }
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

}  // namespace unison
