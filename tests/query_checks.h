// tests/query_checks.h — what the 2D and 3D query tests share: a seeded random generator that gives the same
// sequence on every platform (splitmix64), the comparison of two overlap answers, and the tally that shows the
// random scenes were dense enough for the brute-force comparisons to mean something.
#pragma once

#include "test_support.h"

#include <unison/types.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace query_checks {

struct Rng {
    std::uint64_t s;
    /// Uniform in [lo, hi).
    double uniform(double lo, double hi) {
        s += 0x9E3779B97F4A7C15ull;
        std::uint64_t z = s;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        return lo + (hi - lo) * double(z >> 11) * 0x1.0p-53;
    }
    /// Uniform in 0..n-1.
    int below(int n) { return std::min(n - 1, int(uniform(0.0, double(n)))); }
};

inline void checkSameRefs(const std::vector<unison::ShapeRef>& a, const std::vector<unison::ShapeRef>& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        CHECK(a[i].body == b[i].body);
        CHECK(a[i].shape == b[i].shape);
    }
}

/// Ray hits and overlaps found over the queries of a test: each should be well above the number of queries.
struct Tally {
    int hits = 0, overlaps = 0, queries = 0;
    void add(std::pair<int, int> found) {
        hits += found.first;
        overlaps += found.second;
        ++queries;
    }
    ~Tally() {
        CHECK(hits > 10 * queries);
        CHECK(overlaps > queries);
    }
};

}  // namespace query_checks
