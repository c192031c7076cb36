// core/interior_point_start.h — the starting point of the 2D interior-point restart (core/interior_point_impl.h):
// cold, or from the impulses the contacts carried last step. Included by core/interior_point_impl.h only.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace unison {
namespace detail {

/// Sets the interior point's start p (p_n, p_t of contact c at 2c, 2c + 1), its slacks s and multipliers y (contact
/// c's one or two constraints at 2c, 2c + 1; two[c] tells which) and returns the cold start's gap per constraint,
/// which the iteration's gap thresholds are relative to, so they mean the same velocities from either start.
///   Cold (warmStart nullptr): p = 0, s = v0 / G_nn and y = v0 per constraint.
///   Warm: p the impulses of warmStart (xOut's layout) in the cone with each normal raised by kWarmLift v0 / G_nn
///   (strictly inside, so s = C p exactly), and y the multipliers that zero the velocity residual at p, at least
///   kWarmLift v0; velocities(p, uu) is called once (uu is left at p's velocities). Measured against the cold
///   start: the landing 20-row testbed pyramid's first 120 steps 208 -> 156 iterations (-10 % instructions), the
///   30-row one's 300 steps 294 -> 215 (-16 %); lifts of 0.003 to 1 tried, 0.03 the best on both.
template <class Velocities>
double interiorPointStartingPoint(const std::vector<double>& friction, const std::vector<std::uint8_t>& two,
                                  const std::vector<double>& diag, double v0, int m,
                                  const std::vector<double>* warmStart, const Velocities& velocities,
                                  std::vector<double>& p, std::vector<double>& s, std::vector<double>& y,
                                  std::vector<double>& uu) {
    constexpr double kWarmLift = 0.03;
    const int nc = int(friction.size());
    double mu0Cold = 0.0;
    for (int c = 0; c < nc; ++c) mu0Cold += double(two[std::size_t(c)] ? 2 : 1) * v0 * v0 / diag[std::size_t(2 * c)];
    mu0Cold /= double(m);
    if (!warmStart) {
        std::fill(p.begin(), p.end(), 0.0);
        for (int c = 0; c < nc; ++c) {
            const int cnt = two[std::size_t(c)] ? 2 : 1;
            for (int i = 0; i < cnt; ++i) {
                s[std::size_t(2 * c + i)] = v0 / diag[std::size_t(2 * c)];
                y[std::size_t(2 * c + i)] = v0;
            }
        }
        return mu0Cold;
    }
    for (int c = 0; c < nc; ++c) {
        const double mu = friction[std::size_t(c)];
        const double pn = std::max((*warmStart)[std::size_t(2 * c)], 0.0);
        const double pt = two[std::size_t(c)] ? (*warmStart)[std::size_t(2 * c + 1)] : 0.0;
        p[std::size_t(2 * c)] = pn + kWarmLift * v0 / diag[std::size_t(2 * c)];
        p[std::size_t(2 * c + 1)] = std::min(mu * pn, std::max(-mu * pn, pt));
    }
    velocities(p, uu);
    for (int c = 0; c < nc; ++c) {
        const double un = uu[std::size_t(2 * c)], ut = uu[std::size_t(2 * c + 1)];
        const double yMin = kWarmLift * v0;
        if (two[std::size_t(c)]) {
            // C p = (mu p_n - p_t, mu p_n + p_t); rd = 0: mu (y0 + y1) = u_n, y1 - y0 = u_t.
            const double mu = friction[std::size_t(c)];
            const double pn = p[std::size_t(2 * c)], pt = p[std::size_t(2 * c + 1)];
            s[std::size_t(2 * c)] = mu * pn - pt;
            s[std::size_t(2 * c + 1)] = mu * pn + pt;
            y[std::size_t(2 * c)] = std::max(0.5 * (un / mu - ut), yMin);
            y[std::size_t(2 * c + 1)] = std::max(0.5 * (un / mu + ut), yMin);
        } else {
            s[std::size_t(2 * c)] = p[std::size_t(2 * c)];
            y[std::size_t(2 * c)] = std::max(un, yMin);
        }
    }
    return mu0Cold;
}

}  // namespace detail
}  // namespace unison
