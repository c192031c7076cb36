// core/step_budget.cpp — see step_budget.h.
#include "step_budget.h"

#include <algorithm>
#include <numeric>

namespace unison {

std::uint64_t work::fromMilliseconds(double ms) {
    if (!(ms > 0.0)) return 0;
    const double units = ms * 1e6 / kNsPerUnit;
    return units >= 1.8e19 ? ~std::uint64_t(0) : std::uint64_t(units);
}

double work::toMilliseconds(std::uint64_t units) { return double(units) * kNsPerUnit * 1e-6; }

std::vector<std::uint64_t> fairShares(const std::vector<std::uint64_t>& demands, std::uint64_t pool) {
    const std::size_t n = demands.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    // (demand, index) is a total order: no two entries compare equal.
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return demands[a] != demands[b] ? demands[a] < demands[b] : a < b;
    });
    std::vector<std::uint64_t> shares(n, 0);
    std::uint64_t left = pool;
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = order[k];
        const std::uint64_t level = left / std::uint64_t(n - k);  // an equal split of what is left
        const std::uint64_t give = std::min(demands[i], level);
        shares[i] = give;
        left -= give;
    }
    return shares;
}

}  // namespace unison
