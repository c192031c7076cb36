// core/island.cpp — union-find island splitting; see island.h for the contract.
#include "island.h"

namespace unison {

namespace {

// Root of x with path halving: every other node on the path is re-pointed to its grandparent. The roots it finds
// do not depend on how much of the path was compressed before, so the result is independent of edge order.
int findRoot(std::vector<int>& parent, int x) {
    while (parent[std::size_t(x)] != x) {
        parent[std::size_t(x)] = parent[std::size_t(parent[std::size_t(x)])];
        x = parent[std::size_t(x)];
    }
    return x;
}

// Turns per-island counts (count) into offsets (count + 1) starting at 0.
std::vector<int> prefixSums(const std::vector<int>& counts) {
    std::vector<int> start(counts.size() + 1, 0);
    for (std::size_t k = 0; k < counts.size(); ++k) start[k + 1] = start[k] + counts[k];
    return start;
}

}  // namespace

Islands buildIslands(int bodyCount, const std::vector<std::uint8_t>& joinsIslands,
                     const std::vector<IslandEdge>& edges) {
    const int n = bodyCount < 0 ? 0 : bodyCount;
    auto joins = [&](int i) {
        return i >= 0 && i < n && std::size_t(i) < joinsIslands.size() && joinsIslands[std::size_t(i)] != 0;
    };

    // Union by index: the smaller root wins, so every root is the smallest body of its set.
    std::vector<int> parent(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) parent[std::size_t(i)] = i;
    for (const IslandEdge& e : edges) {
        if (!joins(e.a) || !joins(e.b)) continue;  // statics never merge islands
        const int ra = findRoot(parent, e.a);
        const int rb = findRoot(parent, e.b);
        if (ra < rb) parent[std::size_t(rb)] = ra;
        else if (rb < ra) parent[std::size_t(ra)] = rb;
    }

    // Number islands in ascending order of their root. A root is its set's smallest index, so it is met before
    // any other member in this ascending scan, and islands come out ordered by smallest body index.
    Islands out;
    out.islandOf.assign(std::size_t(n), -1);
    std::vector<int> bodyCounts;
    for (int i = 0; i < n; ++i) {
        if (!joins(i)) continue;
        const int root = findRoot(parent, i);
        if (root == i) {
            out.islandOf[std::size_t(i)] = int(bodyCounts.size());
            bodyCounts.push_back(0);
        } else {
            out.islandOf[std::size_t(i)] = out.islandOf[std::size_t(root)];
        }
        ++bodyCounts[std::size_t(out.islandOf[std::size_t(i)])];
    }

    // Counting sort of bodies by island; the ascending scan keeps bodies ascending inside each island.
    out.bodyStart = prefixSums(bodyCounts);
    out.bodies.resize(std::size_t(out.bodyStart.back()));
    std::vector<int> cursor(out.bodyStart.begin(), out.bodyStart.end() - 1);
    for (int i = 0; i < n; ++i) {
        const int k = out.islandOf[std::size_t(i)];
        if (k >= 0) out.bodies[std::size_t(cursor[std::size_t(k)]++)] = i;
    }

    // Each edge goes to the island of a joining endpoint (both endpoints agree when both join), or is dropped.
    std::vector<int> edgeIsland(edges.size(), -1);
    std::vector<int> edgeCounts(bodyCounts.size(), 0);
    for (std::size_t e = 0; e < edges.size(); ++e) {
        const IslandEdge& edge = edges[e];
        const int k = joins(edge.a) ? out.islandOf[std::size_t(edge.a)]
                                    : joins(edge.b) ? out.islandOf[std::size_t(edge.b)] : -1;
        edgeIsland[e] = k;
        if (k >= 0) ++edgeCounts[std::size_t(k)];
    }
    out.edgeStart = prefixSums(edgeCounts);
    out.edges.resize(std::size_t(out.edgeStart.back()));
    cursor.assign(out.edgeStart.begin(), out.edgeStart.end() - 1);
    for (std::size_t e = 0; e < edges.size(); ++e) {
        const int k = edgeIsland[e];
        if (k >= 0) out.edges[std::size_t(cursor[std::size_t(k)]++)] = int(e);
    }
    return out;
}

bool islandCanSleep(const Islands& islands, int island, const std::vector<double>& sleepTime, double timeToSleep) {
    if (island < 0 || island >= islands.count()) return false;
    for (int i = islands.bodyStart[std::size_t(island)]; i < islands.bodyStart[std::size_t(island) + 1]; ++i) {
        const int body = islands.bodies[std::size_t(i)];
        if (std::size_t(body) >= sleepTime.size()) return false;
        if (!(sleepTime[std::size_t(body)] >= timeToSleep)) return false;  // written so that NaN keeps it awake
    }
    return true;
}

}  // namespace unison
