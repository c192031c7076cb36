// core/query_tree.h — a bounding-volume hierarchy over the shape boxes of a world, for scene queries (ray casts
// and overlaps) in 2D and 3D.
//
// Owns: the tree (nodes with boxes, leaves with item ranges) and its two walks: items whose boxes overlap a box,
// and items whose boxes a ray segment crosses. The tree only prunes: a query's answer is decided by exact tests on
// the items it visits and sorted by a total key afterwards, so the answer never depends on the tree's shape.
// Invariants: node 0 is the root (when there are items); every node's box contains its items' boxes, each grown
// by a small relative margin so that a hit computed in a shape's own frame, which can round just outside the
// shape's box, is still visited; the build is a pure function of the boxes (splits sorted by a total key).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace unison {

template <int K>
class QueryTree {
public:
    /// An axis-aligned box in K dimensions (m).
    struct Box {
        std::array<double, K> lower{}, upper{};
    };

    /// Rebuilds the tree over `boxes` (item i is boxes[i]). Boxes with NaN are left out.
    void build(const std::vector<Box>& boxes) {
        mNodes.clear();
        mOrder.clear();
        mBoxes.clear();
        mBoxes.reserve(boxes.size());
        for (int i = 0; i < int(boxes.size()); ++i) {
            Box b = boxes[std::size_t(i)];
            bool finite = true;
            for (int k = 0; k < K; ++k) {
                finite = finite && b.lower[std::size_t(k)] == b.lower[std::size_t(k)] &&
                         b.upper[std::size_t(k)] == b.upper[std::size_t(k)];
                const double scale = 1.0 + std::max(std::fabs(b.lower[std::size_t(k)]), std::fabs(b.upper[std::size_t(k)]));
                b.lower[std::size_t(k)] -= kMargin * scale;
                b.upper[std::size_t(k)] += kMargin * scale;
            }
            mBoxes.push_back(b);
            if (finite) mOrder.push_back(i);
        }
        if (!mOrder.empty()) split(0, int(mOrder.size()));
    }

    /// Calls visit(item) for every item whose (grown) box overlaps `box`, in no particular order.
    template <class F>
    void overlap(const Box& box, F&& visit) const {
        if (mNodes.empty()) return;
        std::vector<int> stack{0};
        while (!stack.empty()) {
            const Node& n = mNodes[std::size_t(stack.back())];
            stack.pop_back();
            if (!overlaps(n.box, box)) continue;
            if (n.left < 0) {
                for (int i = n.first; i < n.first + n.count; ++i)
                    if (overlaps(mBoxes[std::size_t(mOrder[std::size_t(i)])], box)) visit(mOrder[std::size_t(i)]);
            } else {
                stack.push_back(n.left);
                stack.push_back(n.right);
            }
        }
    }

    /// Calls visit(item, maxFraction) for every item whose (grown) box the segment origin + t delta, t in
    /// [0, maxFraction], crosses; visit returns the new maxFraction (smaller to prune, e.g. a closest hit so far).
    template <class F>
    void ray(const std::array<double, K>& origin, const std::array<double, K>& delta, double maxFraction,
             F&& visit) const {
        if (mNodes.empty()) return;
        std::vector<int> stack{0};
        while (!stack.empty()) {
            const Node& n = mNodes[std::size_t(stack.back())];
            stack.pop_back();
            if (!(entry(n.box, origin, delta) <= maxFraction)) continue;
            if (n.left < 0) {
                for (int i = n.first; i < n.first + n.count; ++i) {
                    const int item = mOrder[std::size_t(i)];
                    if (entry(mBoxes[std::size_t(item)], origin, delta) <= maxFraction)
                        maxFraction = visit(item, maxFraction);
                }
            } else {
                stack.push_back(n.left);
                stack.push_back(n.right);
            }
        }
    }

    /// Fraction t in [0, 1] at which the segment origin + t delta enters `box`; 2 when it misses.
    static double entry(const Box& box, const std::array<double, K>& origin, const std::array<double, K>& delta) {
        double lo = 0.0, hi = 1.0;
        for (int k = 0; k < K; ++k) {
            const double o = origin[std::size_t(k)], d = delta[std::size_t(k)];
            const double l = box.lower[std::size_t(k)], u = box.upper[std::size_t(k)];
            if (d == 0.0) {
                if (o < l || o > u) return 2.0;
                continue;
            }
            double t1 = (l - o) / d, t2 = (u - o) / d;
            if (t1 > t2) std::swap(t1, t2);
            lo = std::max(lo, t1);
            hi = std::min(hi, t2);
            if (lo > hi) return 2.0;
        }
        return lo;
    }

    static bool overlaps(const Box& a, const Box& b) {
        for (int k = 0; k < K; ++k)
            if (a.lower[std::size_t(k)] > b.upper[std::size_t(k)] || b.lower[std::size_t(k)] > a.upper[std::size_t(k)])
                return false;
        return true;
    }

private:
    static constexpr double kMargin = 1e-9;  // relative growth of every item box
    static constexpr int kLeafSize = 4;

    struct Node {
        Box box;
        int left = -1, right = -1;  ///< children (-1 for a leaf)
        int first = 0, count = 0;   ///< leaf: items mOrder[first .. first + count)
    };

    // Builds the node for mOrder[first, last) and returns its index. Splits at the median of the box centres along
    // the longest axis of the centres' spread, sorted by (centre, item): a total order.
    int split(int first, int last) {
        const int index = int(mNodes.size());
        mNodes.emplace_back();
        Box box = mBoxes[std::size_t(mOrder[std::size_t(first)])];
        std::array<double, K> cmin, cmax;
        for (int k = 0; k < K; ++k) cmin[std::size_t(k)] = cmax[std::size_t(k)] = center(mOrder[std::size_t(first)], k);
        for (int i = first; i < last; ++i) {
            const Box& b = mBoxes[std::size_t(mOrder[std::size_t(i)])];
            for (int k = 0; k < K; ++k) {
                box.lower[std::size_t(k)] = std::min(box.lower[std::size_t(k)], b.lower[std::size_t(k)]);
                box.upper[std::size_t(k)] = std::max(box.upper[std::size_t(k)], b.upper[std::size_t(k)]);
                const double c = center(mOrder[std::size_t(i)], k);
                cmin[std::size_t(k)] = std::min(cmin[std::size_t(k)], c);
                cmax[std::size_t(k)] = std::max(cmax[std::size_t(k)], c);
            }
        }
        mNodes[std::size_t(index)].box = box;
        if (last - first <= kLeafSize) {
            mNodes[std::size_t(index)].first = first;
            mNodes[std::size_t(index)].count = last - first;
            return index;
        }
        int axis = 0;
        for (int k = 1; k < K; ++k)
            if (cmax[std::size_t(k)] - cmin[std::size_t(k)] > cmax[std::size_t(axis)] - cmin[std::size_t(axis)]) axis = k;
        std::sort(mOrder.begin() + first, mOrder.begin() + last, [&](int a, int b) {
            const double ca = center(a, axis), cb = center(b, axis);
            return ca < cb || (ca == cb && a < b);
        });
        const int mid = first + (last - first) / 2;
        const int left = split(first, mid);
        const int right = split(mid, last);
        mNodes[std::size_t(index)].left = left;
        mNodes[std::size_t(index)].right = right;
        return index;
    }

    double center(int item, int k) const {
        return 0.5 * mBoxes[std::size_t(item)].lower[std::size_t(k)] + 0.5 * mBoxes[std::size_t(item)].upper[std::size_t(k)];
    }

    std::vector<Node> mNodes;
    std::vector<int> mOrder;  // item indices grouped by leaf
    std::vector<Box> mBoxes;  // (items) grown boxes
};

}  // namespace unison
