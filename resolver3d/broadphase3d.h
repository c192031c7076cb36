// resolver3d/broadphase3d.h — broadphase of the 3D world: which bounding boxes overlap (DESIGN.md step 2).
//
// Owns: findPairs3, a sort and sweep along x with y and z tested per candidate. The sort key is (lower.x, index), a
// total order, and the output is sorted by (a, b): a pure function of the boxes and flags (no pointer or hash order).
// Invariants: every pair has a < b, the boxes overlap (touching counts) and not both are inactive (static or
// kinematic). A box with NaN or lower > upper overlaps nothing.
#pragma once

#include "shapes3d.h"
#include "sweep_order.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace unison {

/// All pairs (a, b), a < b, of overlapping boxes except inactive–inactive ones, ascending by (a, b). inactive must
/// be empty (all active) or as long as boxes (std::invalid_argument otherwise).
/// `runner` (optional) sweeps ranges of the sorted boxes in parallel (sweepPairs); the answer does not change.
std::vector<std::pair<int, int>> findPairs3(const std::vector<Aabb3>& boxes, const std::vector<std::uint8_t>& inactive,
                                            SweepCache* cache = nullptr, const ChunkRunner* runner = nullptr);
/// The same under the 2D name, for the dimension-generic step (core/world_step.h).
inline std::vector<std::pair<int, int>> findPairs(const std::vector<Aabb3>& boxes, const std::vector<std::uint8_t>& inactive,
                                                  SweepCache* cache = nullptr, const ChunkRunner* runner = nullptr) {
    return findPairs3(boxes, inactive, cache, runner);
}

}  // namespace unison
