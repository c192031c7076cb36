// resolver2d/broadphase2d.h — broadphase: which bounding boxes overlap (DESIGN.md step 2).
//
// Owns: findPairs, a sort-and-sweep along x, with a uniform grid for crowded layouts (the sweep meets more than 16
// boxes per box in x: pyramids in rows and columns, where each box meets every row's boxes). The sort key is
// (lower.x, index), a total order, and the output is sorted by (a, b), so the result is a pure function of the input
// boxes and flags, whichever method found it: no pointer or hash order, and the same on every machine and for every
// standard library's sort. A SweepCache (the step keeps one) lets the sort start from the previous call's order
// (core/sweep_order.h): the same answer, in about O(n) when boxes moved little; it also remembers a crowded layout,
// which then goes to the grid directly for 64 calls.
//
// Invariants: every reported pair has a < b, overlaps(boxes[a], boxes[b]) (touching counts), and not both static.
// A box that is not valid (NaN, or lower > upper on an axis) overlaps nothing.
#pragma once

#include "shapes2d.h"
#include "sweep_order.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace unison {

/// All pairs (a, b), a < b, of overlapping boxes except static–static ones, ascending by (a, b).
/// isStatic[i] != 0 marks box i static; isStatic must be empty (all dynamic) or as long as boxes
/// (std::invalid_argument otherwise). Cost O(n log n + s + k log k), s = pairs whose x-intervals overlap, or for a
/// crowded layout O(n + c + t + k log k), c = cells the boxes cover, t = pairs tested within cells.
/// `runner` (optional) sweeps ranges of the sorted boxes in parallel (sweepPairs); the answer does not change.
std::vector<std::pair<int, int>> findPairs(const std::vector<Aabb2>& boxes, const std::vector<std::uint8_t>& isStatic,
                                           SweepCache* cache = nullptr, const ChunkRunner* runner = nullptr);

}  // namespace unison
