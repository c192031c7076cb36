// resolver2d/broadphase2d.cpp — see broadphase2d.h.
//
// Sort and sweep (Baraff's "sweep and prune" without the incremental part): sort the boxes by lower x, then for
// each box walk forward through the boxes that start before it ends in x, test y, and keep the pair. Each unordered
// pair is met at most once (from the box that comes first in the sort), so no de-duplication is needed; a final
// sort by (a, b) makes the output independent of how ties in x were broken.
//
// A layout where many boxes share an x-interval (pyramids in rows and columns: a box meets every row's boxes in x)
// makes the sweep meet far more boxes than it keeps. When it meets more than kSweepCandidatesPerBox per box, the
// pairs come from a uniform grid instead (gridPairs): the same pairs, sorted the same way.
#include "broadphase2d.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace unison {
namespace {

bool validBox(const Aabb2& b) { return b.lower.x <= b.upper.x && b.lower.y <= b.upper.y; }

// Boxes met in x per box beyond which the sweep gives way to the grid (a settled pile meets about 4, a pyramid
// grid of 5 rows about 47).
constexpr std::size_t kSweepCandidatesPerBox = 16;
// Boxes the grid tests against every box (each covers more cells than it allows) beyond which it gives way to the
// sweep: each costs a pass over all boxes.
constexpr std::size_t kMaxEverywhere = 64;
// Calls that go to the grid directly once the sweep ran past its budget.
constexpr int kGridCalls = 64;
// The grid's cell is this many times the median box extent.
constexpr double kCellPerExtent = 2.0;

// The pairs of the valid boxes `valid` (ascending indices) by a uniform grid. Each box is entered in every cell it
// covers; a pair is tested only in the cell of the larger of the two lower corners, which both boxes cover (they
// overlap), so it is met once. A box covering more than maxCells cells (a long ground segment in a small-box
// scene) is tested against every box instead. Returns false (pairs untouched) when the boxes' extents give no
// usable cell (a median extent of 0 or not finite, more than kMaxEverywhere such boxes, or cells beyond 2^31 in a
// row); the sweep answers then. accept(a, b) says whether two boxes that overlap make a pair (the flags).
template <class Accept>
bool gridPairs(const std::vector<Aabb2>& boxes, const std::vector<int>& valid, Accept accept,
               std::vector<std::pair<int, int>>& pairs) {
    const std::size_t n = valid.size();
    if (n < 2) return false;
    std::vector<double> extent(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Aabb2& b = boxes[std::size_t(valid[k])];
        extent[k] = std::max(b.upper.x - b.lower.x, b.upper.y - b.lower.y);
    }
    std::nth_element(extent.begin(), extent.begin() + std::ptrdiff_t(n / 2), extent.end());
    const double cell = kCellPerExtent * extent[n / 2];
    if (!(cell > 0.0) || !std::isfinite(cell)) return false;
    const double inv = 1.0 / cell;
    // Cell ranges per box: [x0, x1] x [y0, y1], as doubles first (a box far out would overflow an integer).
    constexpr double kReach = 1073741824.0;  // 2^30
    const std::int64_t maxCells = std::max<std::int64_t>(64, std::int64_t(n / 8));
    struct Range {
        std::int64_t x0, y0, x1, y1;
    };
    std::vector<Range> range(boxes.size());
    std::vector<int> everywhere;                          // boxes tested against every box
    std::vector<std::uint8_t> inGrid(boxes.size(), 0);  // the others
    std::int64_t minX = 0, minY = 0, maxX = 0, maxY = 0;
    bool first = true;
    std::size_t entries = 0;
    for (int i : valid) {
        const Aabb2& b = boxes[std::size_t(i)];
        const double fx0 = std::floor(b.lower.x * inv), fy0 = std::floor(b.lower.y * inv);
        const double fx1 = std::floor(b.upper.x * inv), fy1 = std::floor(b.upper.y * inv);
        if (!(std::fabs(fx0) < kReach && std::fabs(fy0) < kReach && std::fabs(fx1) < kReach && std::fabs(fy1) < kReach)) {
            everywhere.push_back(i);
            continue;
        }
        const Range r{std::int64_t(fx0), std::int64_t(fy0), std::int64_t(fx1), std::int64_t(fy1)};
        const std::int64_t cells = (r.x1 - r.x0 + 1) * (r.y1 - r.y0 + 1);
        if (cells > maxCells) {
            everywhere.push_back(i);
            continue;
        }
        range[std::size_t(i)] = r;
        inGrid[std::size_t(i)] = 1;
        entries += std::size_t(cells);
        minX = first ? r.x0 : std::min(minX, r.x0);
        minY = first ? r.y0 : std::min(minY, r.y0);
        maxX = first ? r.x1 : std::max(maxX, r.x1);
        maxY = first ? r.y1 : std::max(maxY, r.y1);
        first = false;
    }
    if (everywhere.size() > kMaxEverywhere) return false;
    if (maxX - minX >= (std::int64_t(1) << 31) || maxY - minY >= (std::int64_t(1) << 31)) return false;
    // Each cell's key: column * height + row over the cells the grid's boxes cover. The entries are made in
    // ascending box order and sorted stably by key (a counting sort when the cells are not many more than the
    // entries), so the boxes of a cell stay ascending.
    const std::uint64_t height = std::uint64_t(maxY - minY + 1);
    const std::uint64_t cellCount = std::uint64_t(maxX - minX + 1) * height;
    struct Entry {
        std::uint64_t key;
        int index;
    };
    std::vector<Entry> cells;
    cells.reserve(entries);
    for (int i : valid) {
        if (!inGrid[std::size_t(i)]) continue;
        const Range& r = range[std::size_t(i)];
        for (std::int64_t x = r.x0; x <= r.x1; ++x)
            for (std::int64_t y = r.y0; y <= r.y1; ++y)
                cells.push_back({std::uint64_t(x - minX) * height + std::uint64_t(y - minY), i});
    }
    if (cellCount <= 4 * std::uint64_t(cells.size()) + 4096) {
        std::vector<std::uint32_t> start(std::size_t(cellCount) + 1, 0);
        for (const Entry& e : cells) ++start[std::size_t(e.key) + 1];
        for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
        std::vector<Entry> sorted(cells.size());
        for (const Entry& e : cells) sorted[start[std::size_t(e.key)]++] = e;
        cells.swap(sorted);
    } else {
        std::stable_sort(cells.begin(), cells.end(), [](const Entry& l, const Entry& r) { return l.key < r.key; });
    }
    pairs.clear();
    for (std::size_t g0 = 0; g0 < cells.size();) {
        std::size_t g1 = g0 + 1;
        while (g1 < cells.size() && cells[g1].key == cells[g0].key) ++g1;
        const std::int64_t cx = std::int64_t(cells[g0].key / height) + minX;
        const std::int64_t cy = std::int64_t(cells[g0].key % height) + minY;
        for (std::size_t p = g0; p < g1; ++p) {
            const int a = cells[p].index;
            const Range& ra = range[std::size_t(a)];
            for (std::size_t q = p + 1; q < g1; ++q) {
                const int b = cells[q].index;
                const Range& rb = range[std::size_t(b)];
                // The pair's own cell: the larger lower corner, which both boxes cover.
                if (std::max(ra.x0, rb.x0) != cx || std::max(ra.y0, rb.y0) != cy) continue;
                if (overlaps(boxes[std::size_t(a)], boxes[std::size_t(b)]) && accept(a, b)) pairs.emplace_back(a, b);
            }
        }
        g0 = g1;
    }
    // Boxes tested against every box: against the grid's boxes, and against each other once.
    for (std::size_t e = 0; e < everywhere.size(); ++e) {
        const int a = everywhere[e];
        for (int b : valid) {
            if (b == a || (!inGrid[std::size_t(b)] && b < a)) continue;
            if (overlaps(boxes[std::size_t(a)], boxes[std::size_t(b)]) && accept(a, b))
                pairs.emplace_back(std::min(a, b), std::max(a, b));
        }
    }
    sortPairs(pairs);
    return true;
}

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

    // A pair needs not both boxes static. The sweep has the x overlap and tests y first: it rejects most of the
    // boxes that overlap in x.
    auto accept = [&](int a, int b) { return !(staticBox(a) && staticBox(b)); };
    auto keep = [&](int a, int b) {
        const Aabb2& ba = boxes[std::size_t(a)];
        const Aabb2& bb = boxes[std::size_t(b)];
        return ba.lower.y <= bb.upper.y && bb.lower.y <= ba.upper.y && accept(a, b);
    };
    auto upperX = [&](int a) { return boxes[std::size_t(a)].upper.x; };
    std::vector<std::pair<int, int>> pairs;
    // A layout the sweep found crowded goes to the grid for the next kGridCalls calls, then the sweep is tried
    // again (a pile that spread out is swept faster than gridded).
    const bool crowded = cache && cache->gridCalls > 0;
    if (crowded) --cache->gridCalls;
    if (!crowded && sweepPairsWithin(order, upperX, keep, runner, kSweepCandidatesPerBox * order.size() + 1024, pairs))
        return pairs;
    std::vector<int> valid;
    valid.reserve(order.size());
    for (int i = 0; i < n; ++i)
        if (validBox(boxes[std::size_t(i)])) valid.push_back(i);
    if (gridPairs(boxes, valid, accept, pairs)) {
        if (cache && !crowded) cache->gridCalls = kGridCalls;
        return pairs;
    }
    if (cache) cache->gridCalls = 0;
    sweepPairsWithin(order, upperX, keep, runner, 0, pairs);
    return pairs;
}

}  // namespace unison
