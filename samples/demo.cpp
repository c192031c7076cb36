// samples/demo.cpp — what Unison does, in three pictures (SVG files) and a table on stdout.
//
//  1. cradle.svg   Newton's cradle, five balls, e = 1: the paper's simultaneous resolver (one LCP for all contacts)
//                  against one-contact-at-a-time sequential impulses. Only the simultaneous model gives the
//                  closed form of DESIGN.md; sequential impulses give the textbook 0, 0, 0, 0, v.
//  2. billiard.svg A cue ball hitting two touching balls at +-30 degrees, e = 0.9.
//  3. pyramid.svg  A settled 20-row box pyramid: all 800 contact impulses from one Lemke solve, drawn as bars.
//                  The same solve is repeated warm-started from its own basis, as the next frame would be.
//  4. world_pyramid.svg  The 2D world: the Box2D testbed pyramid (scenes/pyramid20.json)
//                  dropped, landed and stepped for 5 s, with its contact impulses.
// Usage: unison_demo [OUTPUT_DIR]   (default: out)
#include "lcp_families.h"
#include "scene_dir.h"
#include "scene_json.h"
#include "resolver2d.h"
#include "svg.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <sys/stat.h>

using namespace unison;

namespace {

// One contact at a time, repeated until no contact approaches: the "sequential impulses" of most game engines.
void sequentialImpulses(std::vector<Body2>& bodies, const std::vector<Contact2>& contacts) {
    LemkeSolver solver;
    for (int sweep = 0; sweep < 100; ++sweep) {
        bool any = false;
        for (const Contact2& c : contacts) {
            if (relativeNormalVelocity(bodies, c) < -1e-12) {
                resolveCollisions(bodies, {c}, ResolverOptions{}, solver);
                any = true;
            }
        }
        if (!any) break;
    }
}

void drawCradleRow(svg::Picture& pic, const std::vector<Body2>& bodies, double y, const std::string& label,
                   const std::string& color) {
    pic.text(-0.6, y + 0.8, label, 16);
    for (const Body2& b : bodies) pic.circle(b.position.x, y, 0.5, "#dde6f0");
    for (const Body2& b : bodies) {
        if (std::fabs(b.velocity.x) > 1e-9) pic.arrow(b.position.x, y, 1.2 * b.velocity.x, 0.0, color);
        char buf[32];
        std::snprintf(buf, sizeof buf, "%+.3f", b.velocity.x);
        pic.text(b.position.x - 0.35, y - 0.75, buf, 12);
    }
}

bool cradle(const std::string& dir) {
    const int n = 5;
    const scenes::Scene2 scene = scenes::cradleChainScene(n, 1.0);
    auto simultaneous = scene.bodies;
    LemkeSolver solver;
    const Resolution r = resolveCollisions(simultaneous, scene.contacts, ResolverOptions{}, solver);
    auto sequential = scene.bodies;
    sequentialImpulses(sequential, scene.contacts);
    svg::Picture pic(-1.0, -6.0, 6.5, 1.2, 900);
    pic.text(-0.6, 0.9, "Newton's cradle, 5 balls, e = 1 (arrows: velocity in m/s)", 18);
    drawCradleRow(pic, scene.bodies, -0.8, "before", "#333");
    drawCradleRow(pic, simultaneous, -3.0, "Unison: one LCP for all contacts (paper's method)", "#c0392b");
    drawCradleRow(pic, sequential, -5.2, "sequential impulses, one contact at a time", "#2471a3");
    std::printf("cradle    5 balls e=1   simultaneous first ball %+.4f others %+.4f (closed form %+.4f / %+.4f), "
                "%d pivots; sequential: first %+.4f last %+.4f\n",
                simultaneous[0].velocity.x, simultaneous[1].velocity.x, 1.0 - 2.0 * (n - 1) / n, 2.0 / n, r.pivots,
                sequential[0].velocity.x, sequential.back().velocity.x);
    return pic.save(dir + "/cradle.svg");
}

bool billiard(const std::string& dir) {
    const double R = 0.5, e = 0.9, c30 = std::sqrt(3.0) / 2.0;
    std::vector<Body2> bodies(3);
    for (auto& b : bodies) {
        b.invMass = 1.0;
        b.invInertia = 1.0 / (0.5 * R * R);
    }
    bodies[0].velocity = {1.0, 0.0};
    bodies[1].position = {2 * R * c30, R};
    bodies[2].position = {2 * R * c30, -R};
    const auto node = [](int a, int b, Vec2 p, Vec2 n, double rest) { return makeContact<Dim2>(a, b, p, n, rest); };
    const std::vector<Contact2> contacts{node(1, 0, {R * c30, 0.5 * R}, {c30, 0.5}, e),
                                         node(2, 0, {R * c30, -0.5 * R}, {c30, -0.5}, e),
                                         node(1, 2, {2 * R * c30, 0.0}, {0.0, 1.0}, e)};
    const auto before = bodies;
    LemkeSolver solver;
    const Resolution r = resolveCollisions(bodies, contacts, ResolverOptions{}, solver);
    svg::Picture pic(-1.5, -2.0, 4.5, 2.0, 700);
    pic.text(-1.4, 1.7, "Billiard: A hits touching B and C at +-30 deg, e = 0.9", 16);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        pic.circle(bodies[k].position.x, bodies[k].position.y, R, k == 0 ? "#f5e6c8" : "#dde6f0");
        pic.arrow(before[k].position.x, before[k].position.y, before[k].velocity.x, before[k].velocity.y, "#999");
        pic.arrow(bodies[k].position.x, bodies[k].position.y, 1.5 * bodies[k].velocity.x, 1.5 * bodies[k].velocity.y, "#c0392b");
    }
    pic.text(-1.4, -1.8, "grey: before, red: after (x1.5). v_A+ = v(2-3e)/5, |v_B+| = sqrt(3)(1+e)v/5", 13);
    std::printf("billiard  e=0.9         v_A+ %+.4f (closed form %+.4f), |v_B+| %.4f (closed form %.4f), %d pivots\n",
                bodies[0].velocity.x, (2.0 - 3.0 * e) / 5.0, length(bodies[1].velocity), std::sqrt(3.0) * (1.0 + e) / 5.0,
                r.pivots);
    return pic.save(dir + "/billiard.svg");
}

bool pyramid(const std::string& dir) {
    const int rows = 20;
    const scenes::Scene2 scene = scenes::pyramid2dScene(rows);
    const SparseLcp lcp = assembleCollisionLcpSparse(scene.bodies, scene.contacts);
    LemkeSolver solver;
    const auto t0 = std::chrono::steady_clock::now();
    const LcpResult cold = solver.solve(lcp);
    const auto t1 = std::chrono::steady_clock::now();
    LcpOptions warmOptions;
    warmOptions.warmBasis = &cold.basis;
    const LcpResult warm = solver.solve(lcp, warmOptions);
    const auto t2 = std::chrono::steady_clock::now();
    const double coldMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
    const double warmMs = std::chrono::duration<double, std::milli>(t2 - t1).count();

    double fMax = 0.0;
    for (double f : cold.z) fMax = std::max(fMax, f);
    svg::Picture pic(-5.6, -0.6, 5.6, 10.6, 900);
    for (std::size_t k = 1; k < scene.bodies.size(); ++k) {
        const Vec2 p = scene.bodies[k].position;
        pic.rect(p.x, p.y, 0.25, 0.25, "#eef1f5", "#8899aa");
    }
    pic.line(-5.5, 0.0, 5.5, 0.0, "#222", 3.0);
    for (std::size_t i = 0; i < scene.contacts.size(); ++i) {
        const double f = cold.z[i];
        if (f <= 0.0) continue;
        const Vec2 p = scene.contacts[i].point;
        const double h = 0.45 * f / fMax;
        pic.line(p.x, p.y, p.x, p.y + h, "#c0392b", 2.5);
    }
    char title[256];
    std::snprintf(title, sizeof title, "20-row pyramid: %d contacts, one Lemke solve: %s, %d pivots, residual %.1e",
                  lcp.n, statusName(cold.status), cold.pivots, cold.scaledResidual);
    pic.text(-5.4, 10.2, title, 15);
    std::snprintf(title, sizeof title, "red bars: contact impulses (largest %.3f N s); warm start from the basis: %d pivots",
                  fMax, warm.pivots);
    pic.text(-5.4, 9.7, title, 13);
    pic.text(-5.4, 9.3, "A has rank 3 per box, so the impulses are one of many valid sets; the velocities are unique: all zero", 13);
    std::printf("pyramid   20 rows n=%d  cold: %s %d pivots %.2f ms residual %.1e | warm: %s %d pivots %.3f ms\n", lcp.n,
                statusName(cold.status), cold.pivots, coldMs, cold.scaledResidual, statusName(warm.status), warm.pivots, warmMs);
    return cold.status == LcpStatus::solved && pic.save(dir + "/pyramid.svg");
}

bool worldPyramid(const std::string& dir) {
    nlohmann::json scene = scenes::readSceneFile(scenes::sceneDir() + "/pyramid20.json");
    scene["sleep"] = false;  // keep every island solving, so the picture shows this step's impulses
    scenes::LoadedScene2 loaded = scenes::loadScene2(scene, "pyramid20.json");
    World2& world = *loaded.world;
    const auto t0 = std::chrono::steady_clock::now();
    int failed = 0;
    for (int i = 0; i < 300; ++i) {
        world.step();
        failed += world.stats().failedIslands;
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    svg::Picture pic(-8.5, -0.8, 16.5, 21.5, 900);
    pic.line(-8.5, 0.0, 16.5, 0.0, "#222", 3.0);
    for (std::size_t k = 1; k < loaded.bodies.size(); ++k) {
        const BodyState2* s = world.state(loaded.bodies[k]);
        const Polygon& poly = world.info(loaded.bodies[k])->shapes[0].polygon;
        double xs[kMaxPolygonVertices], ys[kMaxPolygonVertices];
        for (int v = 0; v < poly.count; ++v) {
            const Vec2 p = transformPoint(Transform2{s->position, s->rotation}, poly.vertices[std::size_t(v)]);
            xs[v] = p.x;
            ys[v] = p.y;
        }
        pic.polygon(xs, ys, poly.count, "#eef1f5", "#8899aa");
    }
    double fMax = 0.0;
    for (const ContactPoint2& c : world.contacts()) fMax = std::max(fMax, c.normalImpulse);
    for (const ContactPoint2& c : world.contacts()) {
        if (c.normalImpulse > 0.0 && fMax > 0.0) pic.line(c.point.x, c.point.y, c.point.x, c.point.y + 0.9 * c.normalImpulse / fMax, "#c0392b", 2.0);
    }
    const BodyState2* top = world.state(loaded.bodies.back());
    char title[256];
    std::snprintf(title, sizeof title, "2D world: Box2D testbed pyramid (210 boxes) after 5 s: %zu contacts, failed islands %d",
                  world.contacts().size(), failed);
    pic.text(-8.2, 21.0, title, 15);
    std::snprintf(title, sizeof title, "top box at (%.4f, %.4f) (it started at x = 3.6875); sleeping off; red bars: last step's contact impulses", top->position.x,
                  top->position.y);
    pic.text(-8.2, 20.2, title, 13);
    std::printf("world     pyramid20 300 steps (sleep off) %.0f ms, failed islands %d, top box at (%.4f, %.4f)\n", ms, failed,
                top->position.x, top->position.y);
    return pic.save(dir + "/world_pyramid.svg");
}

}  // namespace

int main(int argc, char** argv) {
    const std::string dir = argc > 1 ? argv[1] : "out";
    ::mkdir(dir.c_str(), 0755);
    bool ok = cradle(dir);
    ok = billiard(dir) && ok;
    ok = pyramid(dir) && ok;
    ok = worldPyramid(dir) && ok;
    if (!ok) {
        std::fprintf(stderr, "demo: a scene failed or a picture could not be written to %s\n", dir.c_str());
        return 1;
    }
    std::printf("pictures: %s/cradle.svg %s/billiard.svg %s/pyramid.svg %s/world_pyramid.svg\n", dir.c_str(), dir.c_str(),
                dir.c_str(), dir.c_str());
    return 0;
}
