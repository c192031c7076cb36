// tests/test_island.cpp — the island splitter (core/island.h): chains, static ground that must not merge stacks,
// singletons, dropped static-static edges, ordering rules, independence from edge order, and a 10k-body random
// graph against a plain breadth-first-search reference.
#include <doctest/doctest.h>

#include "island.h"

#include <algorithm>
#include <limits>
#include <cstdint>
#include <utility>
#include <vector>

using namespace unison;

namespace {

struct Lcg {
    std::uint64_t s;
    std::uint32_t next() {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return std::uint32_t(s >> 33);
    }
};

std::vector<int> islandBodies(const Islands& is, int k) {
    return {is.bodies.begin() + is.bodyStart[std::size_t(k)], is.bodies.begin() + is.bodyStart[std::size_t(k) + 1]};
}
std::vector<int> islandEdges(const Islands& is, int k) {
    return {is.edges.begin() + is.edgeStart[std::size_t(k)], is.edges.begin() + is.edgeStart[std::size_t(k) + 1]};
}

// Structural checks that hold for every result: sizes, ordering, membership.
void checkWellFormed(const Islands& is, int bodyCount, const std::vector<std::uint8_t>& joins,
                     const std::vector<IslandEdge>& edges) {
    const int n = is.count();
    REQUIRE(is.bodyStart.size() == std::size_t(n) + 1);
    REQUIRE(is.edgeStart.size() == std::size_t(n) + 1);
    CHECK(is.bodyStart.front() == 0);
    CHECK(is.edgeStart.front() == 0);
    CHECK(is.bodyStart.back() == int(is.bodies.size()));
    CHECK(is.edgeStart.back() == int(is.edges.size()));
    REQUIRE(is.islandOf.size() == std::size_t(bodyCount));
    int joining = 0;
    for (int i = 0; i < bodyCount; ++i) joining += joins[std::size_t(i)] ? 1 : 0;
    CHECK(int(is.bodies.size()) == joining);
    for (int k = 0; k < n; ++k) {
        const std::vector<int> b = islandBodies(is, k), e = islandEdges(is, k);
        REQUIRE_FALSE(b.empty());
        CHECK(std::is_sorted(b.begin(), b.end()));
        CHECK(std::adjacent_find(b.begin(), b.end()) == b.end());
        CHECK(std::is_sorted(e.begin(), e.end()));
        if (k > 0) CHECK(is.bodies[std::size_t(is.bodyStart[std::size_t(k) - 1])] < b.front());
        for (int body : b) {
            CHECK(joins[std::size_t(body)] == 1);
            CHECK(is.islandOf[std::size_t(body)] == k);
        }
        for (int ei : e) {
            const IslandEdge& edge = edges[std::size_t(ei)];
            const bool aIn = joins[std::size_t(edge.a)] && is.islandOf[std::size_t(edge.a)] == k;
            const bool bIn = joins[std::size_t(edge.b)] && is.islandOf[std::size_t(edge.b)] == k;
            CHECK((aIn || bIn));
        }
    }
    for (int i = 0; i < bodyCount; ++i)
        if (!joins[std::size_t(i)]) CHECK(is.islandOf[std::size_t(i)] == -1);
}

// Reference: BFS over dynamic-dynamic edges, components numbered in ascending order of their smallest body.
Islands bfsReference(int bodyCount, const std::vector<std::uint8_t>& joins, const std::vector<IslandEdge>& edges) {
    std::vector<std::vector<int>> adj(static_cast<std::size_t>(bodyCount));
    for (const IslandEdge& e : edges) {
        if (!joins[std::size_t(e.a)] || !joins[std::size_t(e.b)]) continue;
        adj[std::size_t(e.a)].push_back(e.b);
        adj[std::size_t(e.b)].push_back(e.a);
    }
    Islands ref;
    ref.islandOf.assign(std::size_t(bodyCount), -1);
    ref.bodyStart.push_back(0);
    int count = 0;
    for (int i = 0; i < bodyCount; ++i) {
        if (!joins[std::size_t(i)] || ref.islandOf[std::size_t(i)] >= 0) continue;
        std::vector<int> comp{i}, queue{i};
        ref.islandOf[std::size_t(i)] = count;
        for (std::size_t q = 0; q < queue.size(); ++q)
            for (int nb : adj[std::size_t(queue[q])])
                if (ref.islandOf[std::size_t(nb)] < 0) {
                    ref.islandOf[std::size_t(nb)] = count;
                    queue.push_back(nb);
                    comp.push_back(nb);
                }
        std::sort(comp.begin(), comp.end());
        ref.bodies.insert(ref.bodies.end(), comp.begin(), comp.end());
        ref.bodyStart.push_back(int(ref.bodies.size()));
        ++count;
    }
    ref.edgeStart.push_back(0);
    for (int k = 0; k < count; ++k) {
        for (std::size_t e = 0; e < edges.size(); ++e) {
            const IslandEdge& edge = edges[e];
            const int owner = joins[std::size_t(edge.a)] ? edge.a : joins[std::size_t(edge.b)] ? edge.b : -1;
            if (owner >= 0 && ref.islandOf[std::size_t(owner)] == k) ref.edges.push_back(int(e));
        }
        ref.edgeStart.push_back(int(ref.edges.size()));
    }
    return ref;
}

void checkEqual(const Islands& a, const Islands& b) {
    CHECK(a.bodyStart == b.bodyStart);
    CHECK(a.bodies == b.bodies);
    CHECK(a.edgeStart == b.edgeStart);
    CHECK(a.edges == b.edges);
    CHECK(a.islandOf == b.islandOf);
}

}  // namespace

TEST_SUITE("island") {

TEST_CASE("a chain of dynamic bodies is one island") {
    const std::vector<std::uint8_t> joins(4, 1);
    const std::vector<IslandEdge> edges{{2, 3}, {0, 1}, {1, 2}};
    const Islands is = buildIslands(4, joins, edges);
    checkWellFormed(is, 4, joins, edges);
    REQUIRE(is.count() == 1);
    CHECK(islandBodies(is, 0) == std::vector<int>{0, 1, 2, 3});
    CHECK(islandEdges(is, 0) == std::vector<int>{0, 1, 2});
}

TEST_CASE("two stacks on one static ground stay separate islands") {
    // Body 0 is the ground; stack A = {1, 2}, stack B = {3, 4}; edges interleaved on purpose.
    const std::vector<std::uint8_t> joins{0, 1, 1, 1, 1};
    const std::vector<IslandEdge> edges{{3, 0}, {0, 1}, {4, 3}, {1, 2}};
    const Islands is = buildIslands(5, joins, edges);
    checkWellFormed(is, 5, joins, edges);
    REQUIRE(is.count() == 2);
    CHECK(islandBodies(is, 0) == std::vector<int>{1, 2});
    CHECK(islandEdges(is, 0) == std::vector<int>{1, 3});
    CHECK(islandBodies(is, 1) == std::vector<int>{3, 4});
    CHECK(islandEdges(is, 1) == std::vector<int>{0, 2});
    CHECK(is.islandOf == std::vector<int>{-1, 0, 0, 1, 1});
}

TEST_CASE("dynamic bodies that touch nothing are singleton islands; statics are in none") {
    const std::vector<std::uint8_t> joins{1, 0, 1, 1, 0};
    const Islands is = buildIslands(5, joins, {});
    checkWellFormed(is, 5, joins, {});
    REQUIRE(is.count() == 3);
    CHECK(is.bodies == std::vector<int>{0, 2, 3});
    CHECK(is.bodyStart == std::vector<int>{0, 1, 2, 3});
    CHECK(is.edgeStart == std::vector<int>{0, 0, 0, 0});
    CHECK(is.edges.empty());

    const Islands empty = buildIslands(0, {}, {});
    CHECK(empty.count() == 0);
    CHECK(empty.bodyStart == std::vector<int>{0});
    CHECK(Islands{}.count() == 0);
}

TEST_CASE("edges between non-joining bodies belong to no island") {
    const std::vector<std::uint8_t> joins{0, 0, 1, 0};
    // {0,1} and {3,0} are static-static; {1,1} a static self-edge; {2,9} and {-1,2} have one endpoint out of range.
    const std::vector<IslandEdge> edges{{0, 1}, {2, 3}, {3, 0}, {1, 1}, {2, 2}, {2, 9}, {-1, 2}, {9, 9}};
    const Islands is = buildIslands(4, joins, edges);
    checkWellFormed(is, 4, joins, {{0, 1}, {2, 3}, {3, 0}, {1, 1}, {2, 2}, {2, 2}, {2, 2}, {0, 0}});
    REQUIRE(is.count() == 1);
    CHECK(islandBodies(is, 0) == std::vector<int>{2});
    CHECK(islandEdges(is, 0) == std::vector<int>{1, 4, 5, 6});
}

TEST_CASE("islands are ordered by smallest body and edges ascend inside each island") {
    // Components {1,5,8}, {0,9}, {2}, {3,4,6,7}; listed so that first appearance in the edge list differs.
    const std::vector<std::uint8_t> joins(10, 1);
    const std::vector<IslandEdge> edges{{8, 5}, {6, 7}, {9, 0}, {4, 3}, {5, 1}, {7, 3}, {8, 1}, {6, 4}};
    const Islands is = buildIslands(10, joins, edges);
    checkWellFormed(is, 10, joins, edges);
    REQUIRE(is.count() == 4);
    CHECK(islandBodies(is, 0) == std::vector<int>{0, 9});
    CHECK(islandBodies(is, 1) == std::vector<int>{1, 5, 8});
    CHECK(islandBodies(is, 2) == std::vector<int>{2});
    CHECK(islandBodies(is, 3) == std::vector<int>{3, 4, 6, 7});
    CHECK(islandEdges(is, 0) == std::vector<int>{2});
    CHECK(islandEdges(is, 1) == std::vector<int>{0, 4, 6});
    CHECK(islandEdges(is, 2).empty());
    CHECK(islandEdges(is, 3) == std::vector<int>{1, 3, 5, 7});
}

TEST_CASE("the partition does not depend on the order edges are given in") {
    Lcg rng{42};
    const int n = 300;
    std::vector<std::uint8_t> joins(static_cast<std::size_t>(n));
    for (auto& j : joins) j = rng.next() % 5 == 0 ? 0 : 1;
    std::vector<IslandEdge> edges(400);
    for (auto& e : edges) e = {int(rng.next() % n), int(rng.next() % n)};
    const Islands base = buildIslands(n, joins, edges);
    checkWellFormed(base, n, joins, edges);

    for (int trial = 0; trial < 8; ++trial) {
        // Deterministic Fisher-Yates permutation; perm[newIndex] = oldIndex. Also flip some edges' a/b.
        std::vector<int> perm(edges.size());
        for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = int(i);
        for (std::size_t i = perm.size() - 1; i > 0; --i) std::swap(perm[i], perm[rng.next() % (i + 1)]);
        std::vector<IslandEdge> shuffled(edges.size());
        for (std::size_t i = 0; i < perm.size(); ++i) {
            const IslandEdge e = edges[std::size_t(perm[i])];
            shuffled[i] = rng.next() % 2 ? IslandEdge{e.b, e.a} : e;
        }
        const Islands is = buildIslands(n, joins, shuffled);
        checkWellFormed(is, n, joins, shuffled);
        CHECK(is.bodyStart == base.bodyStart);
        CHECK(is.bodies == base.bodies);
        CHECK(is.islandOf == base.islandOf);
        CHECK(is.edgeStart == base.edgeStart);
        // Same edges per island once mapped back to their original indices.
        for (int k = 0; k < is.count(); ++k) {
            std::vector<int> mapped;
            for (int e : islandEdges(is, k)) mapped.push_back(perm[std::size_t(e)]);
            std::sort(mapped.begin(), mapped.end());
            CHECK(mapped == islandEdges(base, k));
        }
    }
}

TEST_CASE("10k-body random graph agrees with a BFS reference") {
    Lcg rng{7};
    const int n = 10000;
    std::vector<std::uint8_t> joins(static_cast<std::size_t>(n));
    for (auto& j : joins) j = rng.next() % 10 == 0 ? 0 : 1;
    // About 0.45 edges per body: many small islands, a few large ones, singletons, static-static edges.
    std::vector<IslandEdge> edges(4500);
    for (auto& e : edges) e = {int(rng.next() % n), int(rng.next() % n)};
    // A long chain makes one deep tree for the union-find.
    for (int i = 0; i + 1 < 2000; ++i) edges.push_back({i * 5 % n, (i + 1) * 5 % n});
    const Islands is = buildIslands(n, joins, edges);
    checkWellFormed(is, n, joins, edges);
    checkEqual(is, bfsReference(n, joins, edges));
    CHECK(is.count() > 100);
}

TEST_CASE("building into reused buffers gives the fresh build's islands, whatever the buffers held before") {
    // A world step builds its islands every step into the same Islands and scratch: graphs of different sizes one
    // after another (a big one, an empty one, small ones) must each come out as a fresh build does.
    Lcg rng{11};
    Islands out;
    std::vector<int> scratch;
    for (int n : {3000, 0, 7, 2500, 1, 40, 3000}) {
        std::vector<std::uint8_t> joins(static_cast<std::size_t>(n));
        for (auto& j : joins) j = rng.next() % 6 == 0 ? 0 : 1;
        std::vector<IslandEdge> edges(static_cast<std::size_t>(n) / 2 + 1);
        for (auto& e : edges) e = n > 0 ? IslandEdge{int(rng.next() % n), int(rng.next() % n)} : IslandEdge{0, 0};
        if (n == 0) edges.clear();
        buildIslands(n, joins, edges, out, scratch);
        const Islands fresh = buildIslands(n, joins, edges);
        CAPTURE(n);
        checkWellFormed(out, n, joins, edges);
        CHECK(out.bodyStart == fresh.bodyStart);
        CHECK(out.bodies == fresh.bodies);
        CHECK(out.edgeStart == fresh.edgeStart);
        CHECK(out.edges == fresh.edges);
        CHECK(out.islandOf == fresh.islandOf);
    }
}

TEST_CASE("an island can sleep only when all its bodies have rested long enough") {
    const std::vector<std::uint8_t> joins{1, 1, 0, 1};
    const Islands is = buildIslands(4, joins, {{0, 1}, {1, 2}});
    REQUIRE(is.count() == 2);  // {0, 1} and {3}
    CHECK(islandCanSleep(is, 0, {0.6, 0.5, 0.0, 0.1}, 0.5));
    CHECK_FALSE(islandCanSleep(is, 0, {0.6, 0.4, 9.0, 9.0}, 0.5));
    CHECK_FALSE(islandCanSleep(is, 1, {0.6, 0.5, 0.0, 0.1}, 0.5));
    CHECK(islandCanSleep(is, 1, {0.0, 0.0, 0.0, 0.5}, 0.5));
    CHECK_FALSE(islandCanSleep(is, 0, {std::numeric_limits<double>::quiet_NaN(), 1.0, 1.0, 1.0}, 0.5));
    CHECK_FALSE(islandCanSleep(is, 1, {1.0, 1.0}, 0.5));  // no entry for body 3
    CHECK_FALSE(islandCanSleep(is, 2, {1.0, 1.0, 1.0, 1.0}, 0.5));
    CHECK_FALSE(islandCanSleep(is, -1, {1.0, 1.0, 1.0, 1.0}, 0.5));
}

}  // TEST_SUITE
