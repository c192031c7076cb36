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

// Turns per-island counts (counts[0..k)) into offsets (k + 1 entries, starting at 0) in place.
void prefixSumsInPlace(std::vector<int>& counts) {
    int sum = 0;
    for (int& c : counts) {
        const int n = c;
        c = sum;
        sum += n;
    }
    counts.push_back(sum);
}

}  // namespace

Islands buildIslands(int bodyCount, const std::vector<std::uint8_t>& joinsIslands,
                     const std::vector<IslandEdge>& edges) {
    Islands out;
    std::vector<int> scratch;
    buildIslands(bodyCount, joinsIslands, edges, out, scratch);
    return out;
}

void buildIslands(int bodyCount, const std::vector<std::uint8_t>& joinsIslands, const std::vector<IslandEdge>& edges,
                  Islands& out, std::vector<int>& scratch) {
    const int n = bodyCount < 0 ? 0 : bodyCount;
    auto joins = [&](int i) {
        return i >= 0 && i < n && std::size_t(i) < joinsIslands.size() && joinsIslands[std::size_t(i)] != 0;
    };

    // Union by index: the smaller root wins, so every root is the smallest body of its set.
    std::vector<int>& parent = scratch;
    parent.resize(std::size_t(n));
    for (int i = 0; i < n; ++i) parent[std::size_t(i)] = i;
    for (const IslandEdge& e : edges) {
        if (!joins(e.a) || !joins(e.b)) continue;  // statics never merge islands
        const int ra = findRoot(parent, e.a);
        const int rb = findRoot(parent, e.b);
        if (ra < rb) parent[std::size_t(rb)] = ra;
        else if (rb < ra) parent[std::size_t(ra)] = rb;
    }

    // Number islands in ascending order of their root. A root is its set's smallest index, so it is met before
    // any other member in this ascending scan, and islands come out ordered by smallest body index. bodyStart holds
    // each island's body count until the prefix sums.
    out.islandOf.assign(std::size_t(n), -1);
    std::vector<int>& bodyCounts = out.bodyStart;
    bodyCounts.clear();
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
    const std::size_t islands = bodyCounts.size();

    // Counting sort of bodies by island; the ascending scan keeps bodies ascending inside each island. The union-find
    // is done, so its buffer becomes the cursors.
    prefixSumsInPlace(out.bodyStart);
    out.bodies.resize(std::size_t(out.bodyStart.back()));
    std::vector<int>& cursor = scratch;
    cursor.assign(out.bodyStart.begin(), out.bodyStart.end() - 1);
    for (int i = 0; i < n; ++i) {
        const int k = out.islandOf[std::size_t(i)];
        if (k >= 0) out.bodies[std::size_t(cursor[std::size_t(k)]++)] = i;
    }

    // Each edge goes to the island of a joining endpoint (both endpoints agree when both join), or is dropped.
    auto edgeIsland = [&](const IslandEdge& edge) {
        return joins(edge.a) ? out.islandOf[std::size_t(edge.a)] : joins(edge.b) ? out.islandOf[std::size_t(edge.b)] : -1;
    };
    out.edgeStart.assign(islands, 0);
    for (const IslandEdge& edge : edges) {
        const int k = edgeIsland(edge);
        if (k >= 0) ++out.edgeStart[std::size_t(k)];
    }
    prefixSumsInPlace(out.edgeStart);
    out.edges.resize(std::size_t(out.edgeStart.back()));
    cursor.assign(out.edgeStart.begin(), out.edgeStart.end() - 1);
    for (std::size_t e = 0; e < edges.size(); ++e) {
        const int k = edgeIsland(edges[e]);
        if (k >= 0) out.edges[std::size_t(cursor[std::size_t(k)]++)] = int(e);
    }
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
