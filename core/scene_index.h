// core/scene_index.h — what the scene queries of World2 and World3 share: the total orders their answers are
// sorted by, and the lazily rebuilt tree over the world's shape boxes.
//
// Owns: SceneIndex (a QueryTree plus the shape each item stands for, rebuilt on the first query after the world's
// bodies moved, were created or destroyed, or were restored).
// Invariants: answers are sorted by a total key (fraction, then body slot, then shape index; or body slot, then
// shape index), so they never depend on the tree, on threads or on the order items were visited. Queries on a
// const world may run on several threads at once (the rebuild is guarded); they must not overlap a step, a body's
// creation or destruction, or a restore.
#pragma once

#include "body_store.h"
#include "query_tree.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <vector>

namespace unison {

/// Overlap answers are sorted by (body slot, shape index): a total order over live shapes.
inline bool shapeRefBefore(const ShapeRef& a, const ShapeRef& b) {
    return a.body.index1 != b.body.index1 ? a.body.index1 < b.body.index1 : a.shape < b.shape;
}

/// Ray hits are sorted by (fraction, body slot, shape index): a total order (a shape is hit at most once).
template <class Hit>
bool rayHitBefore(const Hit& a, const Hit& b) {
    if (a.fraction != b.fraction) return a.fraction < b.fraction;
    if (a.body.index1 != b.body.index1) return a.body.index1 < b.body.index1;
    return a.shape < b.shape;
}

/// The first hit, by rayHitBefore, of those cast(true, visit) reports to visit(hit); false when there is none.
/// (cast's first argument tells it that only hits nearer than the best so far matter.)
template <class Hit, class Cast>
bool closestHit(Cast&& cast, Hit* out) {
    bool found = false;
    Hit best;
    cast(true, [&](const Hit& hit) {
        if (!found || rayHitBefore(hit, best)) best = hit;
        found = true;
    });
    if (found && out) *out = best;
    return found;
}

/// Every hit cast(false, visit) reports, sorted by rayHitBefore.
template <class Hit, class Cast>
std::vector<Hit> allHits(Cast&& cast) {
    std::vector<Hit> hits;
    cast(false, [&](const Hit& hit) { hits.push_back(hit); });
    std::sort(hits.begin(), hits.end(), rayHitBefore<Hit>);
    return hits;
}

/// The query tree of a world over the boxes of all its shapes, rebuilt lazily after the world changed.
template <int K>
class SceneIndex {
public:
    using Box = typename QueryTree<K>::Box;

    /// Marks the tree stale (called by every operation that moves, creates, destroys or restores bodies).
    void invalidate() { mValid.store(false, std::memory_order_release); }

    /// Rebuilds the tree when stale: fill(items, boxes) appends every shape with its world box in dense body order.
    template <class Fill>
    void ensure(Fill&& fill) const {
        if (mValid.load(std::memory_order_acquire)) return;
        const std::lock_guard<std::mutex> lock(mMutex);
        if (mValid.load(std::memory_order_relaxed)) return;
        mItems.clear();
        std::vector<Box> boxes;
        fill(mItems, boxes);
        mTree.build(boxes);
        mValid.store(true, std::memory_order_release);
    }

    const QueryTree<K>& tree() const { return mTree; }
    /// (items) the shape behind each tree item.
    const std::vector<ShapeRef>& items() const { return mItems; }

    /// The shapes whose boxes overlap `box` and that keep(ref) accepts, by shapeRefBefore.
    template <class Keep>
    std::vector<ShapeRef> overlapping(const Box& box, Keep&& keep) const {
        std::vector<ShapeRef> out;
        mTree.overlap(box, [&](int item) {
            const ShapeRef& ref = mItems[std::size_t(item)];
            if (keep(ref)) out.push_back(ref);
        });
        std::sort(out.begin(), out.end(), shapeRefBefore);
        return out;
    }

private:
    mutable std::mutex mMutex;
    mutable std::atomic<bool> mValid{false};
    mutable QueryTree<K> mTree;
    mutable std::vector<ShapeRef> mItems;
};

}  // namespace unison
