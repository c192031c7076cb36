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
                                           SweepCache* cache, const ChunkRunner* runner) {
    if (!isStatic.empty() && isStatic.size() != boxes.size())
        throw std::invalid_argument("findPairs: isStatic must be empty or have one flag per box");
    const int n = static_cast<int>(boxes.size());
    auto staticBox = [&](int i) { return !isStatic.empty() && isStatic[i] != 0; };

    // Valid boxes have non-NaN lower.x, so (lower.x, index) is a strict total order.
    std::vector<SweepEntry> order;
    sweepSort(
        n, [&](int i) { return validBox(boxes[std::size_t(i)]); }, [&](int i) { return boxes[std::size_t(i)].lower.x; },
        order, cache, runner);

    return sweepPairs(
        order, [&](int a) { return boxes[std::size_t(a)].upper.x; },
        [&](int a, int b) {
            // The y test first: it rejects most of the boxes that overlap in x.
            const Aabb2& ba = boxes[std::size_t(a)];
            const Aabb2& bb = boxes[std::size_t(b)];
            return ba.lower.y <= bb.upper.y && bb.lower.y <= ba.upper.y && !(staticBox(a) && staticBox(b));
        },
        runner);
}

}  // namespace unison
