// core/lcp_forms.cpp — the LCP data forms around the solver: status names, the complementarity residual, and the
// conversions between triplets, dense and compressed-row matrices.
#include <unison/lcp.h>

#include <algorithm>
#include <cmath>

namespace unison {

const char* statusName(LcpStatus status) {
    switch (status) {
        case LcpStatus::solved: return "solved";
        case LcpStatus::infeasible: return "infeasible";
        case LcpStatus::pivot_limit: return "pivot_limit";
        case LcpStatus::invalid_input: return "invalid_input";
        case LcpStatus::numerical_failure: return "numerical_failure";
    }
    return "unknown";
}

double complementarityResidual(const std::vector<double>& z, const std::vector<double>& w) {
    double r = 0.0;
    const std::size_t n = std::min(z.size(), w.size());
    for (std::size_t i = 0; i < n; ++i) r = std::max(r, std::fabs(std::min(z[i], w[i])));
    return r;
}

Lcp LcpTriplets::toDense() const {
    Lcp out(n);
    out.b = b;
    for (std::size_t e = 0; e < vals.size(); ++e) out.at(rows[e], cols[e]) += vals[e];
    return out;
}

SparseLcp LcpTriplets::toSparse() const {
    // Counting sort by row (stable), then a stable sort by column inside each row, then sum runs of equal (i, j)
    // in entry order: the same additions, in the same order, as toDense().
    SparseLcp out;
    out.n = n;
    out.b = b;
    std::vector<int> start(std::size_t(n) + 1, 0);
    for (int i : rows) ++start[std::size_t(i) + 1];
    for (int i = 0; i < n; ++i) start[std::size_t(i) + 1] += start[std::size_t(i)];
    std::vector<int> order(vals.size());
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t e = 0; e < vals.size(); ++e) order[std::size_t(fill[std::size_t(rows[e])]++)] = int(e);
    out.rowStart.assign(std::size_t(n) + 1, 0);
    for (int i = 0; i < n; ++i) {
        auto first = order.begin() + start[std::size_t(i)], last = order.begin() + start[std::size_t(i) + 1];
        std::stable_sort(first, last, [&](int x, int y) { return cols[std::size_t(x)] < cols[std::size_t(y)]; });
        for (auto it = first; it != last;) {
            const int j = cols[std::size_t(*it)];
            double sum = 0.0;
            for (; it != last && cols[std::size_t(*it)] == j; ++it) sum += vals[std::size_t(*it)];
            if (sum != 0.0) {
                out.cols.push_back(j);
                out.vals.push_back(sum);
            }
        }
        out.rowStart[std::size_t(i) + 1] = int(out.cols.size());
    }
    return out;
}

SparseLcp toSparse(const Lcp& lcp) {
    SparseLcp out;
    out.n = lcp.n;
    out.b = lcp.b;
    out.rowStart.assign(std::size_t(lcp.n) + 1, 0);
    for (int i = 0; i < lcp.n; ++i) {
        for (int j = 0; j < lcp.n; ++j) {
            if (lcp.at(i, j) != 0.0) {
                out.cols.push_back(j);
                out.vals.push_back(lcp.at(i, j));
            }
        }
        out.rowStart[std::size_t(i) + 1] = int(out.cols.size());
    }
    return out;
}

}  // namespace unison
