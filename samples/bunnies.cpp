// samples/bunnies.cpp — the paper's figures 4 and 5: Stanford bunnies falling onto two ramps, every contact of an
// island resolved at once by one LCP. The bunny is a closed triangle mesh (scenes/bunny.obj) collided
// through its sphere tree: many candidate points per touching pair (drawn yellow) are reduced to at most 4 (red).
//
// Prints one line per step: step, contacts, candidate points, Lemke pivots, islands, the largest residual; then a
// summary with the wall-clock time of the simulation alone (drawing excluded). Writes SVG frames from a fixed camera
// every --frame-every steps into --out.
//
// Usage: bunnies [--seconds 10] [--bunnies 2] [--frame-every 30] [--out out/bunnies] [--quiet]
#include "fp_env.h"
#include "make_scenes3d.h"
#include "scene_json3d.h"
#include "svg.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace {

using namespace unison;

// A fixed camera: orthographic, looking along -dir, with `up` roughly up. Picture coordinates are (right, up).
struct Camera {
    Vec3 right, up, dir;
    Camera() {
        dir = Vec3(0.35, 0.45, 1.0).normalized();  // from the scene towards the eye
        right = Vec3(0, 1, 0).cross(dir).normalized();
        up = dir.cross(right);
    }
    double x(const Vec3& p) const { return p.dot(right); }
    double y(const Vec3& p) const { return p.dot(up); }
    double depth(const Vec3& p) const { return p.dot(dir); }  // larger is nearer
};

std::string grey(double shade, int r, int g, int b) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", int(r * shade), int(g * shade), int(b * shade));
    return buf;
}

struct Face {
    int layer;  // 0 static bodies, 1 moving bodies: the bunnies are above the ramps, so they are drawn after them
    double depth;
    std::vector<Vec3> pts;
    std::string color;
};

void drawFrame(const World3& world, const Camera& cam, const std::string& path, int step) {
    svg::Picture pic(-3.6, -1.4, 3.4, 3.6, 900);
    const Vec3 light = Vec3(0.3, 1.0, 0.6).normalized();
    std::vector<Face> faces;
    int layer = 0;
    auto addFace = [&](std::vector<Vec3> pts, const Vec3& n, int r, int g, int b) {
        if (n.dot(cam.dir) <= 0.0) return;  // back face
        double depth = 0.0;
        for (const Vec3& p : pts) depth += cam.depth(p) / double(pts.size());
        const double shade = 0.35 + 0.65 * std::max(0.0, n.dot(light));
        faces.push_back({layer, depth, std::move(pts), grey(shade, r, g, b)});
    };
    for (const BodyId id : world.bodyIds()) {
        const Transform3 xf = world.transform(id);
        layer = world.info(id)->type == BodyType::staticBody ? 0 : 1;
        for (const Shape3& s : world.info(id)->shapes) {
            if (s.type == ShapeType3::mesh) {
                const TriangleMesh& m = *s.mesh;
                for (const auto& t : m.triangles) {
                    std::vector<Vec3> pts;
                    for (int k = 0; k < 3; ++k) pts.push_back(transformPoint(xf, m.vertices[std::size_t(t[std::size_t(k)])]));
                    const Vec3 n = (pts[1] - pts[0]).cross(pts[2] - pts[0]).normalized();
                    addFace(pts, n, 235, 220, 190);
                }
            } else if (s.poly) {
                for (const auto& f : s.poly->faces) {
                    std::vector<Vec3> pts;
                    for (int v : f.loop) pts.push_back(transformPoint(xf, s.poly->vertices[std::size_t(v)]));
                    addFace(pts, mul(xf.r, f.normal), 150, 170, 200);
                }
            }
        }
    }
    // The ground: a grey quad under everything.
    const double g = 3.5;
    std::vector<Vec3> ground{Vec3(-g, 0, -g), Vec3(-g, 0, g), Vec3(g, 0, g), Vec3(g, 0, -g)};
    double gx[4], gy[4];
    for (int i = 0; i < 4; ++i) {
        gx[i] = cam.x(ground[std::size_t(i)]);
        gy[i] = cam.y(ground[std::size_t(i)]);
    }
    pic.polygon(gx, gy, 4, "#d8d8d0", "#d8d8d0");
    std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) {
        return a.layer != b.layer ? a.layer < b.layer : a.depth < b.depth;
    });
    for (const Face& f : faces) {
        std::vector<double> xs, ys;
        for (const Vec3& p : f.pts) {
            xs.push_back(cam.x(p));
            ys.push_back(cam.y(p));
        }
        pic.polygon(xs.data(), ys.data(), int(xs.size()), f.color, f.color);
    }
    for (const ManifoldPoint3& c : world.candidates()) pic.circle(cam.x(c.point), cam.y(c.point), 0.012, "#f2d500", "none");
    for (const ContactPoint3& c : world.contacts()) pic.circle(cam.x(c.point), cam.y(c.point), 0.025, "#e01010", "#600");
    char label[160];
    std::snprintf(label, sizeof label, "t = %.2f s   contacts %d (red), sphere-tree candidates %d (yellow)", step / 60.0,
                  world.stats().contacts, world.stats().candidates);
    pic.text(-3.5, 3.4, label, 16.0);
    pic.save(path);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bunnies: Stanford bunnies falling onto two ramps (the seed paper's figs. 4-5)"};
    double seconds = 10.0;
    int bunnies = 2, frameEvery = 30;
    std::string outDir = "out/bunnies";
    std::string obj = std::string(UNISON_SOURCE_DIR) + "/scenes/bunny.obj";
    bool quiet = false;
    app.add_option("--seconds", seconds, "simulated time (s)")->check(CLI::PositiveNumber);
    app.add_option("--bunnies", bunnies, "number of bunnies")->check(CLI::Range(1, 8));
    app.add_option("--frame-every", frameEvery, "steps between SVG frames (0: none)")->check(CLI::NonNegativeNumber);
    app.add_option("--out", outDir, "folder for the frames");
    app.add_option("--obj", obj, "bunny OBJ file");
    app.add_flag("--quiet", quiet, "no per-step lines");
    CLI11_PARSE(app, argc, argv);
    const std::string env = checkFloatingPointEnvironment();
    if (!env.empty()) {
        std::cerr << "error: " << env << "\n";
        return 2;
    }
    scenes::LoadedScene3 loaded;
    try {
        loaded = scenes::loadScene3(scenes::bunnies3Scene(obj, 0.05, bunnies), "bunnies");
    } catch (const jsonio::JsonError& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 2;
    }
    World3& world = *loaded.world;
    if (frameEvery > 0) std::filesystem::create_directories(outDir);
    world.captureCandidates(frameEvery > 0);
    const Camera cam;
    const int steps = int(std::lround(seconds * world.def().hz));
    double simSeconds = 0.0, maxResidual = 0.0;
    long long pivots = 0, candidates = 0, contacts = 0;
    int frames = 0, failed = 0, maxContacts = 0;
    if (!quiet) std::printf("step contacts candidates pivots islands residual\n");
    for (int s = 1; s <= steps; ++s) {
        const auto t0 = std::chrono::steady_clock::now();
        world.step();
        simSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const StepStats3& st = world.stats();
        pivots += st.pivots;
        candidates += st.candidates;
        contacts += st.contacts;
        failed += st.failedIslands;
        maxContacts = std::max(maxContacts, st.contacts);
        maxResidual = std::max(maxResidual, st.maxResidual);
        if (!quiet) std::printf("%d %d %d %d %d %.1e\n", s, st.contacts, st.candidates, st.pivots, st.awakeIslands, st.maxResidual);
        if (frameEvery > 0 && (s % frameEvery == 0 || s == 1)) {
            char name[64];
            std::snprintf(name, sizeof name, "/frame_%04d.svg", s);
            drawFrame(world, cam, outDir + name, s);
            ++frames;
        }
    }
    std::printf("summary: %d bunnies, %.1f s simulated in %d steps, step time %.3f s total (%.2f ms/step), "
                "contacts %lld (max %d per step), sphere-tree candidates %lld, pivots %lld, failed islands %d, "
                "max residual %.1e, %d frames in %s\n",
                bunnies, seconds, steps, simSeconds, 1e3 * simSeconds / steps, contacts, maxContacts, candidates, pivots,
                failed, maxResidual, frames, frameEvery > 0 ? outDir.c_str() : "-");
    for (std::size_t i = 3; i < loaded.bodies.size(); ++i) {
        const BodyState3* st = world.state(loaded.bodies[i]);
        std::printf("bunny %zu: centre (%.3f, %.3f, %.3f) m, speed %.2e m/s, spin %.2e rad/s, %s\n", i - 2, st->center.x(),
                    st->center.y(), st->center.z(), st->velocity.norm(), st->angularVelocity.norm(),
                    world.info(loaded.bodies[i])->awake ? "awake" : "asleep");
    }
    return 0;
}
