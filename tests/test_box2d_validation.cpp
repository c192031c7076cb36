// tests/test_box2d_validation.cpp — the same 2D scenes built in Unison's World2 and in Box2D 2.4.1
// (bench/box2d_peer), stepped side by side and compared, and where a closed form exists, compared with it too.
//
// Box2D differs from Unison by design in ways the tolerances must allow for, and each case says how:
//   - Skin. Box2D gives polygons and edges a radius b2_polygonRadius (0.01 m) and lets contacts rest b2_linearSlop
//     (0.005 m) into it, so two polygons rest 2 * 0.01 - 0.005 = 0.015 m apart, a circle rests 0.01 - 0.005 m
//     above an edge. Unison's shapes have no skin and rest touching. Every vertical comparison first removes this
//     per-layer allowance, computed from Box2D's own constants.
//   - Floats. Box2D computes in float (about 1e-7 relative; 1e-6 m at 10 m), far below every tolerance here.
//   - Solver. Box2D runs sequential impulses (8 velocity, 3 position iterations, its testbed's setting); Unison
//     solves one LCP per island. The Newton's cradle case is where this shows, and is meant to.
//
// `UNISON_VERBOSE=1 build/tests/unison_tests --test-suite=box2d_validation` prints every measured number (the
// table in docs/benchmarks.md).
#include "test_support.h"

#include "box2d_peer.h"
#include "det_math.h"
#include "make_scenes2d.h"
#include "scene_dir.h"
#include "scene_json.h"
#include "world2d.h"

#include <box2d/box2d.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

using namespace unison;
using nlohmann::json;

namespace {

// Box2D's skin between two polygons at rest (m): two radii, less the overlap its position solver allows.
const double kPolygonLayer = 2.0 * double(b2_polygonRadius) - double(b2_linearSlop);
// Box2D's skin between a circle and an edge at rest (m): only the edge has a skin radius.
const double kCircleLayer = double(b2_polygonRadius) - double(b2_linearSlop);

bool verbose() {
    const char* v = std::getenv("UNISON_VERBOSE");
    return v != nullptr && *v != '\0' && *v != '0';
}

// Prints one line of the measured numbers when UNISON_VERBOSE is set.
void report(const char* format, ...) {
    if (!verbose()) return;
    va_list args;
    va_start(args, format);
    std::vfprintf(stdout, format, args);
    va_end(args);
    std::fputc('\n', stdout);
    std::fflush(stdout);
}

// Resting piles are compared after kRestSeconds. Box2D's pile is built with sleeping off: landing compresses its skins
// (its 10-box stack first rests with 1.0-1.4 cm layers instead of 1.5 cm) and the pile then decompresses for tens of
// seconds (its 20-row pyramid's top box rises 7.7 cm between 5 s and 60 s, 0.1 mm in the last 5 s);
// with sleeping on it falls asleep half-way through that and keeps the compressed heights. Unison's pile keeps its
// default sleeping: it comes to rest within 2 s and sleeping does not move it.
constexpr double kRestSeconds = 60.0;

// The scene with its "sleep" flag set.
json withSleep(json scene, bool sleep) {
    scene["sleep"] = sleep;
    return scene;
}

// The same scene in both engines; body i of the scene JSON is body i of each.
struct Both {
    scenes::LoadedScene2 unison;
    std::unique_ptr<bench::Box2dPeer> box2d;

    /// `box2dSleep` false builds Box2D's copy with sleeping off (see kRestSeconds).
    Both(const json& scene, const std::string& name, bool box2dSleep = true)
        : unison(scenes::loadScene2(scene, name)), box2d(std::make_unique<bench::Box2dPeer>(withSleep(scene, box2dSleep), name)) {}

    void step() {
        unison.world->step();
        box2d->step();
    }
    void run(int steps) {
        for (int i = 0; i < steps; ++i) step();
    }
    const BodyState2& u(int i) const { return *unison.world->state(unison.bodies[std::size_t(i)]); }
    Vec2 uPos(int i) const { return u(i).position; }
    Vec2 uVel(int i) const { return u(i).velocity; }
    Vec2 bPos(int i) const { return box2d->position(i); }
    Vec2 bVel(int i) const { return box2d->linearVelocity(i); }
};

}  // namespace

TEST_SUITE("box2d_validation") {

TEST_CASE("vertical stack of 10 boxes: both rest, heights agree within 1 cm after Box2D's skin") {
    // Tolerance 1 cm: Unison rests boxes touching, with at most the 5 mm slop of penetration per
    // contact that position correction leaves; Box2D rests them kPolygonLayer apart. After removing
    // (layer count) * kPolygonLayer from Box2D's heights the two differ only by Unison's slop and Box2D's
    // remaining overlap error, which must stay below 1 cm even for the top box (10 layers).
    Both both(scenes::stackScene(10, true), "stack10", false);
    both.run(int(kRestSeconds * 60.0));
    double worst = 0.0;
    for (int i = 1; i <= 10; ++i) {
        const Vec2 pU = both.uPos(i), pB = both.bPos(i);
        const double yBcore = pB.y - i * kPolygonLayer;  // box i rests on i contact layers (the ground's included)
        report("stack10 box %2d: unison y %.5f  box2d y %.5f  box2d - skin %.5f  diff %+.5f  |dx| u %.1e b %.1e", i, pU.y,
               pB.y, yBcore, pU.y - yBcore, std::fabs(pU.x), std::fabs(pB.x));
        worst = std::max(worst, std::fabs(pU.y - yBcore));
        CHECK(std::fabs(pU.y - yBcore) <= 0.01);
        CHECK(std::fabs(pU.x) <= 0.01);  // rests: no sideways drift
        CHECK(std::fabs(pU.y - (0.5 + (i - 1))) <= 0.005 * i);  // at most the slop per layer below it
    }
    report("stack10 worst |dy| %.5f m (tolerance 0.01)", worst);
    CHECK_FALSE(both.unison.world->info(both.unison.bodies[10])->awake);  // came to rest and fell asleep
}

TEST_CASE("20-row pyramid at the testbed spacing: both rest; columns and heights against Box2D") {
    // The Box2D 2.4.1 testbed pyramid (0.5 m boxes, rows 0.25 m apart, so it lands), in Box2D at the testbed's
    // 8 velocity iterations for kRestSeconds, and at 64 for 10 s (its columns are settled by then: the same to
    // 0.1 mm at 30 s). Tolerances:
    //   - Vertically every box within 2 cm of Box2D's resting height after removing (row + 1) * kPolygonLayer of
    //     skin. Unison rests touching (at most the 5 mm slop per layer; measured 0), Box2D decompresses to its
    //     skin (see kRestSeconds); 2 cm leaves room for Box2D's remaining compression of its 20 layers. Asserted
    //     against the 8-iteration run.
    //   - Horizontally every box within 2 cm of Box2D. Against the testbed's 8 iterations this is NOT met, and
    //     not asserted: that pile spreads as it lands (30 of 210 boxes end 2 to 7 cm from their columns,
    //     measured). The spread is Box2D's unconverged solver: it shrinks to 3.1 cm at 16 iterations, 1.7 cm at
    //     32 and 1.3 cm at 64. All contacts of the settled pile are horizontal faces, so its equilibrium needs no
    //     horizontal force and the testbed columns are the exact answer; Unison keeps every box on its column to
    //     3e-11 m (asserted within 1 mm), and within 2 cm of Box2D at 64 iterations (asserted).
    const int rows = 20;
    const json scene = scenes::pyramidScene(rows, 0.5, true);
    const int steps = int(kRestSeconds * 60.0);
    Both both(scene, "pyramid20", false);
    bench::Box2dPeer converged(withSleep(scene, false), "pyramid20", 64, 3);
    both.run(steps);
    for (int i = 0; i < 600; ++i) converged.step();
    auto compare = [&](const bench::Box2dPeer& peer, const char* label, bool assertHeights, bool assertColumns) {
        double worstDx = 0.0, worstDy = 0.0, worstColumnB = 0.0;
        int beyond = 0, body = 1;
        for (int r = 0; r < rows; ++r) {
            for (int j = 0; j < rows - r; ++j, ++body) {
                const Vec2 pU = both.uPos(body), pB = peer.position(body);
                const double column = scene["bodies"][std::size_t(body)]["position"][0].get<double>();
                const double dx = std::fabs(pU.x - pB.x), dy = pU.y - (pB.y - (r + 1) * kPolygonLayer);
                if (dx > 0.02) ++beyond;
                worstDx = std::max(worstDx, dx);
                worstDy = std::max(worstDy, std::fabs(dy));
                worstColumnB = std::max(worstColumnB, std::fabs(pB.x - column));
                if (assertHeights) CHECK(std::fabs(dy) <= 0.02);
                if (assertColumns) CHECK(dx <= 0.02);
            }
        }
        report("pyramid20 vs box2d %s: max |y_u - (y_b - skin)| %.4f m%s; max |x_u - x_b| %.4f m%s, %d of %d boxes "
               "beyond 2 cm; box2d's largest distance from its column %.4f m",
               label, worstDy, assertHeights ? " (tolerance 0.02)" : "", worstDx, assertColumns ? " (tolerance 0.02)" : "",
               beyond, body - 1, worstColumnB);
    };
    compare(*both.box2d, "8 iterations (testbed), 60 s", true, false);
    compare(converged, "64 iterations, 10 s", false, true);
    double worstColumnU = 0.0, worstHeightU = 0.0;
    int body = 1;
    for (int r = 0; r < rows; ++r) {
        for (int j = 0; j < rows - r; ++j, ++body) {
            const Vec2 pU = both.uPos(body);
            worstColumnU = std::max(worstColumnU, std::fabs(pU.x - scene["bodies"][std::size_t(body)]["position"][0].get<double>()));
            worstHeightU = std::max(worstHeightU, std::fabs(pU.y - (0.5 + r)));
            CHECK(std::fabs(pU.y - (0.5 + r)) <= 0.005 * (r + 1));
        }
    }
    report("pyramid20 unison: largest distance from the testbed column %.1e m, from the stacked height %.1e m",
           worstColumnU, worstHeightU);
    CHECK(worstColumnU <= 1e-3);
    CHECK_FALSE(both.unison.world->info(both.unison.bodies.back())->awake);  // came to rest and fell asleep
}

namespace {

// The first rebound apex of a body: the highest centre height between its first bounce (vertical velocity turning
// from down to up) and the moment it starts to fall again; < 0 until then.
struct ApexTracker {
    double prevVy = -1.0, apex = -1.0, highest = -1.0;
    int bounces = 0;
    void update(double y, double vy) {
        if (prevVy < 0.0 && vy > 0.0) ++bounces;
        if (bounces == 1) {
            highest = std::max(highest, y);
            if (prevVy > 0.0 && vy <= 0.0 && apex < 0.0) apex = highest;
        }
        prevVy = vy;
    }
};

}  // namespace

TEST_CASE("restitution row: rebound apexes within 3 % of Box2D and of e^2 h") {
    // 7 circles of radius 0.5 dropped from y = 5 onto the ground, e = k/6. The rebound rises e^2 h above the resting
    // height (energy e^2 of the impact's), h = 5 - rest height: 4.5 m for Unison, 4.5 - kCircleLayer for Box2D.
    // Tolerance 3 % of e^2 h and of Box2D's rise. Both engines integrate gravity by semi-implicit Euler
    // at 60 Hz, so neither reaches e^2 h exactly, and the slowest rebound (e = 1/6, 1.6 m/s) is the hardest case:
    // measured Unison +0.56 % (e = 1) to +2.2 % (e = 1/6), Box2D +0.54 % to +1.2 %. World2 bounces at the time of
    // impact inside the step; before it did, the apex was +3.5 % (e = 1) to +64 % (e = 1/6).
    // e = 0 must not bounce: its apex is measured as the highest point after landing, and must be below 1 mm.
    const json scene = scenes::restitutionRowScene(false);
    Both both(scene, "restitution_row");
    std::vector<ApexTracker> trackU(8), trackB(8);
    double highestU0 = 0.0, highestB0 = 0.0;
    for (int step = 0; step < 300; ++step) {
        both.step();
        for (int k = 1; k < 8; ++k) {
            trackU[std::size_t(k)].update(both.uPos(k).y, both.uVel(k).y);
            trackB[std::size_t(k)].update(both.bPos(k).y, both.bVel(k).y);
        }
        if (step > 90) {  // ball 1 (e = 0) has landed by 1 s (it falls 4.5 m in 0.95 s)
            highestU0 = std::max(highestU0, both.uPos(1).y - 0.5);
            highestB0 = std::max(highestB0, both.bPos(1).y - (0.5 + kCircleLayer));
        }
    }
    report("restitution e = 0: highest point after landing above rest: unison %.2e m, box2d %.2e m", highestU0, highestB0);
    CHECK(trackU[1].bounces == 0);
    CHECK(highestU0 < 1e-3);
    for (int k = 2; k < 8; ++k) {
        const double e = (k - 1) / 6.0;
        const double hU = 4.5, hB = 4.5 - kCircleLayer;
        const double riseU = trackU[std::size_t(k)].apex - 0.5;
        const double riseB = trackB[std::size_t(k)].apex - (0.5 + kCircleLayer);
        CAPTURE(e);
        report("restitution e = %.3f: apex rise unison %.4f m (e^2 h %.4f, %+.2f %%), box2d %.4f m (e^2 h %.4f, %+.2f %%), "
               "unison vs box2d %+.2f %%",
               e, riseU, e * e * hU, 100.0 * (riseU / (e * e * hU) - 1.0), riseB, e * e * hB,
               100.0 * (riseB / (e * e * hB) - 1.0), 100.0 * (riseU / riseB - 1.0));
        CHECK(std::fabs(riseU - e * e * hU) <= 0.03 * e * e * hU);
        CHECK(std::fabs(riseU - riseB) <= 0.03 * riseB);
    }
}

namespace {

// A box on the ramp of scenes::rampScene (angle theta, effective friction mu), launched along the ramp at `speed`
// (m/s, > 0 up the ramp); returns its displacement along the ramp (m, > 0 up) in each engine after `steps`.
struct RampRun {
    double unison = 0.0, box2d = 0.0;
};
RampRun runRamp(double theta, double mu, double speed, int steps) {
    json scene = scenes::rampScene(theta, mu, false);
    double s = 0.0, c = 1.0;
    dmath::sincos(theta, &s, &c);
    scene["bodies"][1]["linear_velocity"] = json::array({speed * c, speed * s});
    Both both(scene, "ramp");
    const Vec2 startU = both.uPos(1), startB = both.bPos(1), along{c, s};
    both.run(steps);
    return {dot(both.uPos(1) - startU, along), dot(both.bPos(1) - startB, along)};
}

}  // namespace

TEST_CASE("friction ramp: mu above tan(theta) stays, below slides, as in Box2D") {
    // theta = 30 degrees, tan(theta) = 0.577. Over 1 s a box at rest slides down by a t (t + dt) / 2 with
    // a = g (sin(theta) - mu cos(theta)) (the semi-implicit Euler sum of the Coulomb closed form) when
    // mu < tan(theta), and does not move when mu > tan(theta). Tolerances: a staying box moves < 1 mm in either
    // engine (Box2D's skin and float rounding allow a little creep, Unison's LCP none); a sliding one is within
    // 5 % of the closed form and of Box2D (the ramp's tolerance).
    const double theta = 3.141592653589793 / 6.0, g = 10.0, t = 1.0, dt = 1.0 / 60.0;
    for (double mu : {0.3, 0.5, 0.65, 0.8}) {
        CAPTURE(mu);
        const RampRun run = runRamp(theta, mu, 0.0, 60);
        const double a = g * (0.5 - mu * std::sqrt(0.75));
        const double expected = a > 0.0 ? -0.5 * a * t * (t + dt) : 0.0;
        report("ramp 30 deg, mu %.2f: displacement after 1 s unison %+.5f m, box2d %+.5f m, closed form %+.5f m", mu,
               run.unison, run.box2d, expected);
        if (a > 0.0) {
            CHECK(std::fabs(run.unison - expected) <= 0.05 * std::fabs(expected));
            CHECK(std::fabs(run.unison - run.box2d) <= 0.05 * std::fabs(run.box2d));
        } else {
            CHECK(std::fabs(run.unison) < 1e-3);
            CHECK(std::fabs(run.box2d) < 1e-3);
        }
    }
}

TEST_CASE("friction ramp: stopping distances within 5 % of Box2D") {
    // theta = 20 degrees, mu = 0.6 > tan(theta) = 0.364: a box launched along the ramp at 3 m/s decelerates at
    // g (mu cos(theta) -+ sin(theta)) and stops after v^2 / (2 a) (continuous closed form: 2.03 m downhill, 0.50 m
    // uphill; the semi-implicit Euler sum is about v dt / 2 = 2.5 cm shorter), then stays. Tolerance 5 % of
    // Box2D's distance; the closed form is printed for reference.
    const double theta = 20.0 / 180.0 * 3.141592653589793, mu = 0.6, g = 10.0, v = 3.0;
    double s = 0.0, c = 1.0;
    dmath::sincos(theta, &s, &c);
    for (double dir : {-1.0, 1.0}) {
        CAPTURE(dir);
        const RampRun run = runRamp(theta, mu, dir * v, 180);
        const double a = g * (mu * c + dir * s);
        report("ramp 20 deg, mu 0.6, launched %s at 3 m/s: stopping distance unison %.4f m, box2d %.4f m (%+.2f %%), "
               "closed form %.4f m",
               dir < 0.0 ? "down" : "up", std::fabs(run.unison), std::fabs(run.box2d),
               100.0 * (std::fabs(run.unison) / std::fabs(run.box2d) - 1.0), v * v / (2.0 * a));
        CHECK(dir * run.unison > 0.0);
        CHECK(std::fabs(run.unison - run.box2d) <= 0.05 * std::fabs(run.box2d));
    }
}

TEST_CASE("heavy box (100:1) on a stack of light boxes stays up") {
    // Three 1 m boxes of density 1 with a box of density 100 on top (stackScene's 5 cm gaps, so it lands). The
    // stack must stand: after 5 s the heavy box is above the light ones (|x| < 1 cm) at the height of 3 boxes
    // less at most the 5 mm slop per contact layer, and nothing moves. Box2D's numbers are printed for reference
    // (sequential impulses converge slowly at large mass ratios, so its layers are compressed more).
    json scene = scenes::stackScene(4, true);
    scene["bodies"][4]["shapes"][0]["density"] = 100.0;
    Both both(scene, "heavy_on_light");
    both.run(300);
    const Vec2 pU = both.uPos(4), pB = both.bPos(4);
    const double penetration = both.unison.world->stats().maxPenetration;
    double lightB = 0.0;
    for (int i = 1; i <= 3; ++i) lightB = std::max(lightB, std::fabs(both.bPos(i).x));
    report("heavy on light: heavy box y unison %.5f (stacked 3.5), box2d %.5f (minus skin %.5f), |x| u %.1e b %.4f, "
           "light boxes' largest |x| box2d %.4f, unison max penetration %.2e m",
           pU.y, pB.y, pB.y - 4 * kPolygonLayer, std::fabs(pU.x), std::fabs(pB.x), lightB, penetration);
    CHECK(std::fabs(pU.x) < 0.01);
    CHECK(pU.y <= 3.5 + 1e-6);
    CHECK(pU.y >= 3.5 - 4 * 0.005);
    for (int i = 1; i <= 3; ++i) CHECK(std::fabs(both.uPos(i).x) < 0.01);
    CHECK(penetration <= 0.005 + 1e-6);
    CHECK(length(both.uVel(4)) < 1e-3);
}

TEST_CASE("Newton's cradle: Unison gives the simultaneous closed form, Box2D does not") {
    // scenes/cradle.json: 5 touching balls (e = 1, no friction, no gravity), the first arriving at v = 2 m/s. The
    // simultaneous model (DESIGN.md) gives v1 = v (1 - (1 + e)(N - 1)/N) = -0.6 v and v/N (1 + e) = 0.4 v for the
    // others, leaving together; Unison's LCP reproduces it to 1e-9 relative. Box2D puts restitution only on the
    // contact that approaches at the start of the step and runs 8 sequential-impulse sweeps, which stop short of
    // that answer; the impacts it leaves between the other balls resolve over the next steps and spread the row
    // (measured: -0.573, 0.357, 0.371, 0.402, 0.443 v). The test asserts that Box2D's answer differs from the
    // closed form by more than 2 % of v on some ball, so the comparison can tell the two models apart.
    const json scene = scenes::readSceneFile(scenes::sceneDir() + "/cradle.json");
    Both both(scene, "cradle");
    const double v = 2.0, e = 1.0, n = 5.0;
    both.step();
    for (int k = 0; k < 5; ++k) {
        const double expected = k == 0 ? v * (1.0 - (1.0 + e) * (n - 1.0) / n) : v * (1.0 + e) / n;
        CHECK(both.uVel(k).x == doctest::Approx(expected).epsilon(1e-9));
    }
    both.run(59);  // 1 s: every ball has separated in both engines
    std::string lineU, lineB;
    double box2dOff = 0.0;
    for (int k = 0; k < 5; ++k) {
        const double expected = k == 0 ? v * (1.0 - (1.0 + e) * (n - 1.0) / n) : v * (1.0 + e) / n;
        CHECK(both.uVel(k).x == doctest::Approx(expected).epsilon(1e-9));
        box2dOff = std::max(box2dOff, std::fabs(both.bVel(k).x - expected));
        char buf[64];
        std::snprintf(buf, sizeof buf, " %+.4f", both.uVel(k).x / v);
        lineU += buf;
        std::snprintf(buf, sizeof buf, " %+.4f", both.bVel(k).x / v);
        lineB += buf;
    }
    report("cradle after 1 s, velocities / v: unison%s; box2d%s; closed form -0.6 0.4 0.4 0.4 0.4; box2d's largest "
           "deviation %.4f v", lineU.c_str(), lineB.c_str(), box2dOff / v);
    CHECK(box2dOff > 0.02 * v);
}

}  // TEST_SUITE
