// core/island.h — the contact graph and the island splitter (DESIGN.md step 4), shared by both worlds.
//
// Owns: IslandEdge (one touching body pair, by dense body index), Islands (the partition of dynamic bodies and
// of the edges that couple them, in compressed form) and buildIslands(), a union-find over dynamic bodies.
// Invariants of a built Islands (tested in tests/test_island.cpp):
//   - every body whose joinsIslands entry is 1 is in exactly one island, including dynamic bodies that touch
//     nothing: those form singleton islands, because they still have to be integrated;
//   - static/kinematic bodies (joinsIslands 0) are in no island and never join two islands together;
//   - an edge with one joining endpoint belongs to that body's island; an edge with no joining endpoint (two
//     statics, or an endpoint outside [0, bodyCount)) belongs to no island and is dropped;
//   - islands are numbered by their smallest body index; bodies and edges inside an island are ascending.
// Why: each island becomes one LCP, and lockstep peers must build the same LCPs in the same order. The result is a
// pure function of the partition, so it does not depend on the order the edges are listed in (apart from the
// edge indices themselves, which point into the caller's list). No unordered containers, no pointer order.
#pragma once

#include <cstdint>
#include <vector>

namespace unison {

/// One edge of the contact graph: two dense body indices that touch (e.g. a contact manifold or a joint).
struct IslandEdge {
    int a = 0;  ///< dense index of the first body
    int b = 0;  ///< dense index of the second body
};

/// Islands in compressed form. Island k owns bodies[bodyStart[k] .. bodyStart[k+1]) and
/// edges[edgeStart[k] .. edgeStart[k+1]) (indices into the edge list given to buildIslands()).
struct Islands {
    std::vector<int> bodyStart;  ///< (count() + 1) offsets into bodies; bodyStart[0] == 0
    std::vector<int> bodies;     ///< (number of joining bodies) dense body indices, ascending within an island
    std::vector<int> edgeStart;  ///< (count() + 1) offsets into edges; edgeStart[0] == 0
    std::vector<int> edges;      ///< (number of kept edges) input edge indices, ascending within an island
    std::vector<int> islandOf;   ///< (bodyCount) island of each body, -1 for bodies that join no island

    /// Number of islands.
    int count() const { return bodyStart.empty() ? 0 : int(bodyStart.size()) - 1; }
    /// Number of bodies in island k.
    int bodyCount(int k) const { return bodyStart[std::size_t(k) + 1] - bodyStart[std::size_t(k)]; }
    /// Number of edges in island k.
    int edgeCount(int k) const { return edgeStart[std::size_t(k) + 1] - edgeStart[std::size_t(k)]; }
};

/// Splits bodies [0, bodyCount) into islands. joinsIslands (bodyCount) is 1 for dynamic bodies and 0 for static
/// or kinematic ones; missing entries count as 0. Union-find with path halving and union by index (the root of a
/// set is always its smallest body index). O(bodyCount + edges) up to the inverse Ackermann factor.
Islands buildIslands(int bodyCount, const std::vector<std::uint8_t>& joinsIslands,
                     const std::vector<IslandEdge>& edges);

/// buildIslands into `out`, reusing its buffers and `scratch` (a world step calls it every step); the same result.
void buildIslands(int bodyCount, const std::vector<std::uint8_t>& joinsIslands, const std::vector<IslandEdge>& edges,
                  Islands& out, std::vector<int>& scratch);

/// True when every body of island `island` has sleepTime (indexed by dense body index, seconds) >= timeToSleep.
/// False for an island index out of range, a body without a sleepTime entry, or a NaN sleep time.
bool islandCanSleep(const Islands& islands, int island, const std::vector<double>& sleepTime, double timeToSleep);

}  // namespace unison
