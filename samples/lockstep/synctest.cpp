// samples/lockstep/synctest.cpp — GGPO's sync test on one machine (see roles.h): every tick is simulated, its
// compact state saved, then the state `distance` ticks back is restored and those ticks are simulated again;
// the state hash must come out the same. A difference means the compact state misses something a tick changes
// (or the step is not deterministic), and the report names the field. Also measures what rollback costs.
#include "roles.h"

#include "desync_report.h"
#include "recording.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ostream>

namespace unison::lockstep {
namespace {

using Clock = std::chrono::steady_clock;

double usSince(Clock::time_point t) { return std::chrono::duration<double, std::micro>(Clock::now() - t).count(); }

/// v rounded to a multiple of unit (for printing).
double roundTo(double v, double unit) { return std::round(v / unit) * unit; }

/// Median, mean and largest of a series. Timings on a shared machine have rare long outliers (the process was
/// descheduled); the median is the figure to compare.
struct Series {
    std::vector<double> values;
    void add(double v) { values.push_back(v); }
    double mean() const {
        double sum = 0.0;
        for (double v : values) sum += v;
        return values.empty() ? 0.0 : sum / double(values.size());
    }
    double median() const {
        if (values.empty()) return 0.0;
        std::vector<double> sorted = values;
        std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
        return sorted[sorted.size() / 2];
    }
    double max() const { return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end()); }
    nlohmann::json json(double unit = 0.01) const {
        return {{"median", roundTo(median(), unit)}, {"mean", roundTo(mean(), unit)}, {"max", roundTo(max(), unit)}};
    }
};

}  // namespace

int runSynctest(const SynctestOptions& options, std::ostream& out, std::ostream& err) {
    const int distance = options.distance;
    if (distance < 1 || options.ticks < 1) {
        err << "synctest: --ticks and --distance must be >= 1\n";
        return 2;
    }
    MatchWorld match(options.match);
    World2& world = match.world();
    const int bodies = world.bodyCount();
    std::vector<CompactState> ring(std::size_t(distance) + 1);  // the state after tick t at t % (distance + 1)
    std::vector<std::vector<PlayerInput>> frames(std::size_t(options.ticks) + 1);
    world.saveCompact(ring[0]);
    Series step, save, restore, resim, stateBytes;
    for (int t = 1; t <= options.ticks; ++t) {
        std::vector<PlayerInput>& frame = frames[std::size_t(t)];
        for (int p = 0; p < options.match.players; ++p) frame.push_back(botInput(options.match, p, t));
        Clock::time_point start = Clock::now();
        match.tick(frame);
        step.add(usSince(start));
        if (t == options.desyncAt) flipVelocityBit(world);  // first pass only: the check must catch it
        CompactState& mine = ring[std::size_t(t) % ring.size()];
        start = Clock::now();
        world.saveCompact(mine);
        save.add(usSince(start));
        stateBytes.add(double(mine.size()));
        const std::uint64_t first = world.stateHash();
        if (t < distance) continue;
        const CompactState& back = ring[std::size_t(t - distance) % ring.size()];
        start = Clock::now();
        std::string error;
        if (!world.restoreCompact(back.data(), back.size(), &error)) {
            err << "synctest: restore failed at tick " << t << ": " << error << "\n";
            return 1;
        }
        restore.add(usSince(start));
        start = Clock::now();
        for (int u = t - distance + 1; u <= t; ++u) match.tick(frames[std::size_t(u)]);
        resim.add(usSince(start) / distance);
        if (world.stateHash() == first) continue;
        // Name the difference: the state of the first pass (restored from its compact state) against this one.
        const std::vector<std::uint8_t> again = world.snapshot();
        world.restoreCompact(mine.data(), mine.size());
        const nlohmann::json report = replay::snapshotDesyncReport(
            t, world.snapshot(), again, "first_pass", "resimulated", [&](BodyId id) {
                const auto& ids = match.bodies();
                const auto it = std::find(ids.begin(), ids.end(), id);
                return it == ids.end() ? -1 : int(it - ids.begin());
            }, 50);
        out << nlohmann::json{{"synctest", "fail"}, {"tick", t}, {"distance", distance}, {"report", report}}.dump()
            << std::endl;
        err << "synctest: " << replay::desyncSummary(report) << "\n";
        return 1;
    }
    const double percent = step.median() > 0.0 ? 100.0 * (save.median() + restore.median()) / step.median() : 0.0;
    Series perBody;
    for (double b : stateBytes.values) perBody.add(b / bodies);
    out << nlohmann::json{{"synctest", "pass"},
                          {"ticks", options.ticks},
                          {"bodies", bodies},
                          {"distance", distance},
                          {"step_us", step.json()},
                          {"save_us", save.json()},
                          {"restore_us", restore.json()},
                          {"resimulate_us_per_tick", resim.json()},
                          {"save_plus_restore_percent_of_step_median", roundTo(percent, 0.01)},
                          {"state_bytes", stateBytes.json(1.0)},
                          {"bytes_per_body", perBody.json(0.1)},
                          {"full_snapshot_bytes", world.snapshot().size()},
                          {"final_hash", replay::hexHash(world.stateHash())}}
               .dump()
        << std::endl;
    return 0;
}

}  // namespace unison::lockstep
