// resolver3d/broadphase3d.cpp — see broadphase3d.h. Sort the boxes by lower x; each box walks forward through the
// boxes that start before it ends in x and keeps those that also overlap in y and z. Every unordered pair is met
// once, from the box that comes first in the sort; the final sort makes the output independent of x ties.
#include "broadphase3d.h"

#include <algorithm>
#include <stdexcept>

namespace unison {

std::vector<std::pair<int, int>> findPairs3(const std::vector<Aabb3>& boxes, const std::vector<std::uint8_t>& inactive,
                                            SweepCache* cache, const ChunkRunner* runner) {
    if (!inactive.empty() && inactive.size() != boxes.size())
        throw std::invalid_argument("findPairs3: inactive must be empty or have one flag per box");
    const int n = int(boxes.size());
    std::vector<SweepEntry> order;  // (lower.x, index): a strict total order for valid boxes
    auto valid = [&](int i) {
        const Aabb3& b = boxes[std::size_t(i)];
        return b.lower.x() <= b.upper.x() && b.lower.y() <= b.upper.y() && b.lower.z() <= b.upper.z();
    };
    sweepSort(n, valid, [&](int i) { return boxes[std::size_t(i)].lower.x(); }, order, cache, runner);
    auto isInactive = [&](int i) { return !inactive.empty() && inactive[std::size_t(i)] != 0; };
    return sweepPairs(
        order, [&](int a) { return boxes[std::size_t(a)].upper.x(); },
        [&](int a, int b) {
            // The overlap tests first: they reject most of the boxes that overlap in x.
            const Aabb3& ba = boxes[std::size_t(a)];
            const Aabb3& bb = boxes[std::size_t(b)];
            return ba.lower.y() <= bb.upper.y() && bb.lower.y() <= ba.upper.y() && ba.lower.z() <= bb.upper.z() &&
                   bb.lower.z() <= ba.upper.z() && !(isInactive(a) && isInactive(b));
        },
        runner);
}

}  // namespace unison
