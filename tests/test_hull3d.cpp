// tests/test_hull3d.cpp — resolver3d/hull3d: the fast hull builder gives bit-identical polyhedra to the brute-force
// definition on thousands of point sets (general position, box corners with points on faces and edges, lattices with
// many coplanar and collinear points, duplicates), builds 256 points in bounded work, and checkPolyhedron refuses
// every kind of inconsistency a crafted snapshot could hold.
#include "test_support.h"

#include "det_math.h"
#include "hull3d.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

using namespace unison;

namespace {

using D3 = Dim3;

double norm(const Vec3& v) { return std::sqrt(D3::dot(v, v)); }

// The definition by brute force: every triple of points against every point (O(n^4)), faces merged in triple order,
// the way the project first built hulls. The fast builder must give the same polyhedron bit for bit.
std::string referencePolyhedron(const std::vector<Vec3>& pts, ConvexPolyhedron* out) {
    const hull_detail::Tolerance tol = hull_detail::toleranceOf(pts);
    const int n = int(pts.size());
    std::vector<ConvexPolyhedron::Face> faces;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            for (int k = j + 1; k < n; ++k) {
                ConvexPolyhedron::Face f;
                if (hull_detail::tripleFace(pts, i, j, k, tol, &f)) hull_detail::mergeFace(faces, f, tol);
            }
    if (faces.size() < 4) return "hull: points must span a volume";
    return hull_detail::finishPolyhedron(pts, std::move(faces), tol, out);
}

// Deterministic pseudo-random numbers in [0, 1) (splitmix64), so every run tests the same point sets.
struct Rng {
    std::uint64_t s;
    double next() {
        std::uint64_t z = (s += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        z ^= z >> 31;
        return double(z >> 11) * (1.0 / 9007199254740992.0);
    }
};

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(const Vec3& a, const Vec3& b) { return sameBits(a.x(), b.x()) && sameBits(a.y(), b.y()) && sameBits(a.z(), b.z()); }

/// Empty when the polyhedra are identical bit for bit, else what differs first.
std::string difference(const ConvexPolyhedron& a, const ConvexPolyhedron& b) {
    if (a.vertices.size() != b.vertices.size()) return "vertex count";
    for (std::size_t i = 0; i < a.vertices.size(); ++i)
        if (!sameBits(a.vertices[i], b.vertices[i])) return "vertex " + std::to_string(i);
    if (a.faces.size() != b.faces.size()) return "face count";
    for (std::size_t f = 0; f < a.faces.size(); ++f) {
        if (!sameBits(a.faces[f].normal, b.faces[f].normal) || !sameBits(a.faces[f].offset, b.faces[f].offset))
            return "face plane " + std::to_string(f);
        if (a.faces[f].loop != b.faces[f].loop) return "face loop " + std::to_string(f);
    }
    if (a.edges.size() != b.edges.size()) return "edge count";
    for (std::size_t e = 0; e < a.edges.size(); ++e) {
        const auto &x = a.edges[e], &y = b.edges[e];
        if (x.v0 != y.v0 || x.v1 != y.v1 || x.face0 != y.face0 || x.face1 != y.face1) return "edge " + std::to_string(e);
    }
    return sameBits(a.centroid, b.centroid) ? "" : "centroid";
}

struct Outcome {
    int built = 0, refused = 0, differ = 0;
};

/// Builds `pts` both ways and counts agreement (both refuse, or both build the same polyhedron).
void compare(const std::vector<Vec3>& pts, Outcome& o) {
    ConvexPolyhedron fast, slow;
    const std::string ef = buildPolyhedron(pts, &fast), es = referencePolyhedron(pts, &slow);
    if (ef.empty() && es.empty()) {
        const std::string d = difference(fast, slow);
        if (!d.empty()) {
            ++o.differ;
            MESSAGE("differs at " << d << " for " << pts.size() << " points");
        } else {
            ++o.built;
        }
    } else if (!ef.empty() && !es.empty()) {
        ++o.refused;
    } else {
        ++o.differ;
        MESSAGE("one refused: fast \"" << ef << "\" reference \"" << es << "\"");
    }
}

}  // namespace

TEST_SUITE("hull3d") {

TEST_CASE("random clouds and sphere samples: bit-identical to the brute-force definition") {
    Rng rng{1};
    Outcome o;
    for (int trial = 0; trial < 600; ++trial) {
        const int n = 4 + int(rng.next() * 40);
        const double scale = std::pow(10.0, -2.0 + 5.0 * rng.next());
        std::vector<Vec3> pts;
        const bool sphere = trial % 2 == 0;
        for (int i = 0; i < n; ++i) {
            Vec3 p(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
            if (sphere) p = D3::scale(0.5 / norm(p), p);
            pts.push_back(D3::scale(scale, p));
        }
        compare(pts, o);
    }
    CHECK(o.differ == 0);
    CHECK(o.built == 600);
}

TEST_CASE("boxes, points on faces and edges, lattices and duplicates: identical, or refused by both") {
    Rng rng{2};
    Outcome o;
    for (int trial = 0; trial < 400; ++trial) {
        std::vector<Vec3> pts;
        const double hx = 0.1 + rng.next(), hy = 0.1 + rng.next(), hz = 0.1 + rng.next();
        const int kind = trial % 4;
        if (kind == 0) {
            // Box corners in a shuffled order, plus points in the middle of faces and edges.
            for (int i = 0; i < 8; ++i) pts.push_back(Vec3((i & 1) ? hx : -hx, (i & 2) ? hy : -hy, (i & 4) ? hz : -hz));
            for (int extra = int(rng.next() * 6); extra > 0; --extra)
                pts.push_back(Vec3(hx, (rng.next() < 0.5 ? 0.0 : hy), 0.0));
            for (std::size_t i = pts.size(); i > 1; --i) std::swap(pts[i - 1], pts[std::size_t(rng.next() * double(i))]);
        } else if (kind == 1) {
            // A small integer lattice: many coplanar and collinear points.
            const int m = 2 + int(rng.next() * 3);
            for (int x = 0; x < m; ++x)
                for (int y = 0; y < m; ++y)
                    for (int z = 0; z < 2; ++z)
                        if (rng.next() < 0.8) pts.push_back(Vec3(x * hx, y * hy, z * hz));
        } else if (kind == 2) {
            // Random points with duplicates.
            for (int i = 0; i < 12; ++i) pts.push_back(Vec3(rng.next(), rng.next(), rng.next()));
            for (int i = 0; i < 6; ++i) pts.push_back(pts[std::size_t(rng.next() * 12.0)]);
        } else {
            // A prism: two parallel regular-ish polygons (large coplanar faces) plus an apex.
            const int sides = 3 + int(rng.next() * 10);
            for (int i = 0; i < sides; ++i) {
                double s = 0.0, c = 1.0;
                dmath::sincos(2.0 * dmath::kPi * i / sides, &s, &c);
                pts.push_back(Vec3(c, s, 0.0));
                pts.push_back(Vec3(c, s, hz));
            }
            pts.push_back(Vec3(0.0, 0.0, 2.0 + hz));
        }
        if (pts.size() < 4) continue;
        compare(pts, o);
    }
    CHECK(o.differ == 0);
    CHECK(o.built > 300);
}

TEST_CASE("256 points on a sphere: every point a vertex, a closed convex polyhedron") {
    Rng rng{3};
    std::vector<Vec3> pts;
    for (int i = 0; i < 256; ++i) {
        Vec3 p(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
        pts.push_back(D3::scale(1.0 / norm(p), p));
    }
    ConvexPolyhedron poly;
    REQUIRE(buildPolyhedron(pts, &poly).empty());
    CHECK(poly.vertices.size() == 256);
    CHECK(poly.faces.size() == 2 * 256 - 4);  // points in general position: all faces are triangles
    CHECK(checkPolyhedron(poly).empty());
    pts.push_back(Vec3(0.0, 0.0, 0.0));
    CHECK_FALSE(buildPolyhedron(pts, &poly).empty());  // 257 points: over the limit
}

TEST_CASE("checkPolyhedron refuses every inconsistency of a box") {
    std::vector<Vec3> corners;
    for (int i = 0; i < 8; ++i) corners.push_back(Vec3((i & 1) ? 1.0 : -1.0, (i & 2) ? 2.0 : -2.0, (i & 4) ? 0.5 : -0.5));
    ConvexPolyhedron box;
    REQUIRE(buildPolyhedron(corners, &box).empty());
    REQUIRE(checkPolyhedron(box).empty());
    const std::pair<const char*, void (*)(ConvexPolyhedron&)> cases[] = {
        {"off its plane", [](ConvexPolyhedron& p) { p.vertices[0] = D3::scale(1.01, p.vertices[0]); }},
        {"unit normal", [](ConvexPolyhedron& p) { p.faces[0].normal = D3::scale(2.0, p.faces[0].normal); }},
        {"off its plane", [](ConvexPolyhedron& p) { p.faces[1].offset += 0.1; }},
        {"counter-clockwise", [](ConvexPolyhedron& p) { std::reverse(p.faces[2].loop.begin(), p.faces[2].loop.end()); }},
        {"out of range", [](ConvexPolyhedron& p) { p.faces[0].loop[0] = 99; }},
        {"loop size", [](ConvexPolyhedron& p) { p.faces[0].loop.resize(2); }},
        {"faces do not match", [](ConvexPolyhedron& p) { p.edges[0].face0 = p.edges[0].face1; }},
        {"edge list", [](ConvexPolyhedron& p) { p.edges.pop_back(); }},
        {"bad edge vertices", [](ConvexPolyhedron& p) { std::swap(p.edges[0].v0, p.edges[0].v1); }},
        {"centroid", [](ConvexPolyhedron& p) { p.centroid = Vec3(0.3, 0.0, 0.0); }},
        {"4..", [](ConvexPolyhedron& p) { p.vertices.resize(3); }},
        {"face count", [](ConvexPolyhedron& p) { p.faces.resize(3); }},
        {"finite", [](ConvexPolyhedron& p) { p.vertices[2].x() = HUGE_VAL; }},
    };
    for (const auto& item : cases) {
        ConvexPolyhedron bad = box;
        item.second(bad);
        const std::string why = checkPolyhedron(bad);
        const std::string expected = item.first;
        CAPTURE(expected);
        CAPTURE(why);
        CHECK(why.find(expected) != std::string::npos);
    }
}

}  // TEST_SUITE
