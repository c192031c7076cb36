// resolver3d/hull3d.cpp — see hull3d.h.
//
// Why two stages: the faces of a polyhedron are defined (and were first computed) triple by triple: a triple of
// points spans a face when every point lies on or below its plane, and the face keeps that triple's normal and
// offset, rounding included. Checking all n^3/6 triples against all n points took 20 s for 100 hulls of 256 points.
// An incremental hull finds the face planes in O(n F); for each of its triangles only the few points lying on its
// plane are then tried as triples, in index order, against the same definition. Faces, vertices, loops and edges
// are therefore bit-identical to the brute force (tests/test_hull3d.cpp compares them on thousands of point sets),
// and the work is bounded: at most kMaxTrials triples are tried in all.
#include "hull3d.h"

#include "det_math.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace unison {

using D3 = Dim3;

namespace {

constexpr int kMaxTrials = 20000;  // triples tried by all faces together (bounded work on crafted input)

double norm(const Vec3& v) { return std::sqrt(D3::dot(v, v)); }

}  // namespace

namespace hull_detail {

Tolerance toleranceOf(const std::vector<Vec3>& pts) {
    Tolerance t;
    for (const Vec3& p : pts) t.scale = std::max(t.scale, std::max(std::fabs(p.x()), std::max(std::fabs(p.y()), std::fabs(p.z()))));
    t.eps = 1e-9 * std::max(t.scale, 1e-3);
    return t;
}

bool tripleFace(const std::vector<Vec3>& pts, int i, int j, int k, const Tolerance& tol, ConvexPolyhedron::Face* out) {
    const std::size_t si = std::size_t(i);
    Vec3 nn = D3::cross(D3::sub(pts[std::size_t(j)], pts[si]), D3::sub(pts[std::size_t(k)], pts[si]));
    const double len = norm(nn);
    if (!(len > tol.eps * std::max(tol.scale, 1e-3))) return false;
    nn = D3::scale(1.0 / len, nn);
    const double d = D3::dot(nn, pts[si]);
    int above = 0, below = 0;
    for (std::size_t m = 0; m < pts.size() && !(above && below); ++m) {
        const double s = D3::dot(nn, pts[m]) - d;
        if (s > tol.eps) ++above;
        if (s < -tol.eps) ++below;
    }
    if ((above && below) || (!above && !below)) return false;
    if (above) nn = D3::scale(-1.0, nn);
    out->normal = nn;
    out->offset = D3::dot(nn, pts[si]);
    return true;
}

void mergeFace(std::vector<ConvexPolyhedron::Face>& faces, const ConvexPolyhedron::Face& f, const Tolerance& tol) {
    bool known = false;
    for (const auto& g : faces)
        known = known || (norm(D3::sub(g.normal, f.normal)) < 1e-7 && std::fabs(g.offset - f.offset) < 10.0 * tol.eps);
    if (!known) faces.push_back(f);
}

}  // namespace hull_detail

namespace {

using hull_detail::Tolerance;
using hull_detail::tripleFace;

/// An incremental convex hull in triangles: only a source of candidate face planes (see the file comment).
class TriangleHull {
public:
    TriangleHull(const std::vector<Vec3>& pts, const Tolerance& tol)
        : mPts(pts), mN(int(pts.size())), mTol(tol), mEdge(std::size_t(mN) * std::size_t(mN), -1) {}

    /// Builds the hull; false (with *why) for points that span no volume or break its topology.
    bool build(std::string* why) {
        if (!simplex(why)) return false;
        for (int p = 0; p < mN; ++p) {
            if (p == mS[0] || p == mS[1] || p == mS[2] || p == mS[3]) continue;
            if (!add(p)) {
                *why = "hull: numerically degenerate points";
                return false;
            }
        }
        return true;
    }
    /// The live triangles (vertex triples, counter-clockwise seen from outside).
    std::vector<std::array<int, 3>> triangles() const {
        std::vector<std::array<int, 3>> out;
        for (const Tri& t : mTris)
            if (t.alive) out.push_back(t.v);
        return out;
    }

private:
    struct Tri {
        std::array<int, 3> v;
        Vec3 n;
        double d;
        bool alive;
    };

    const Vec3& at(int i) const { return mPts[std::size_t(i)]; }
    int& edge(int a, int b) { return mEdge[std::size_t(a) * std::size_t(mN) + std::size_t(b)]; }

    // The first point, the farthest from it, the farthest from their line, the farthest from their plane.
    bool simplex(std::string* why) {
        auto argmax = [&](auto measure) {
            int best = 0;
            double bestValue = -1.0;
            for (int i = 0; i < mN; ++i) {
                const double v = measure(at(i));
                if (v > bestValue) best = i, bestValue = v;
            }
            return std::make_pair(best, bestValue);
        };
        const Vec3 p0 = at(0);
        const int i1 = argmax([&](const Vec3& p) { return D3::dot(D3::sub(p, p0), D3::sub(p, p0)); }).first;
        const Vec3 axis = D3::sub(at(i1), p0);
        const auto [i2, area] = argmax([&](const Vec3& p) { return norm(D3::cross(axis, D3::sub(p, p0))); });
        const Vec3 n = D3::cross(axis, D3::sub(at(i2), p0));
        const auto [i3, height] = argmax([&](const Vec3& p) { return std::fabs(D3::dot(n, D3::sub(p, p0))); });
        const double length = norm(axis);
        if (!(length > 0.0) || !(area / length > mTol.eps) || !(height / area > mTol.eps)) {
            *why = "hull: points must span a volume";
            return false;
        }
        mS = {0, i1, i2, i3};
        const int faces[4][3] = {{0, i1, i2}, {0, i3, i1}, {i1, i3, i2}, {i2, i3, 0}};
        const int opposite[4] = {i3, i2, 0, i1};
        for (int f = 0; f < 4; ++f) {
            std::array<int, 3> v{faces[f][0], faces[f][1], faces[f][2]};
            if (D3::dot(plane(v).n, D3::sub(at(opposite[f]), at(v[0]))) > 0.0) std::swap(v[1], v[2]);
            insert(v);
        }
        return true;
    }

    Tri plane(const std::array<int, 3>& v) const {
        Vec3 n = D3::cross(D3::sub(at(v[1]), at(v[0])), D3::sub(at(v[2]), at(v[0])));
        const double len = norm(n);
        n = len > 0.0 ? D3::scale(1.0 / len, n) : Vec3::Zero();
        return {v, n, D3::dot(n, at(v[0])), true};
    }

    bool insert(const std::array<int, 3>& v) {
        const int t = int(mTris.size());
        for (int e = 0; e < 3; ++e) {
            int& slot = edge(v[std::size_t(e)], v[std::size_t((e + 1) % 3)]);
            if (slot >= 0) return false;  // a directed edge used twice: not a manifold
            slot = t;
        }
        mTris.push_back(plane(v));
        return true;
    }

    // Adds point p: removes the triangles it sees and fans it to their horizon (which must be one simple cycle).
    bool add(int p) {
        std::vector<int> visible;
        for (int t = 0; t < int(mTris.size()); ++t) {
            const Tri& tri = mTris[std::size_t(t)];
            if (tri.alive && D3::dot(tri.n, at(p)) - tri.d > mTol.eps) visible.push_back(t);
        }
        if (visible.empty()) return true;  // inside, or on the surface
        std::vector<char> seen(mTris.size(), 0);
        for (int t : visible) seen[std::size_t(t)] = 1;
        std::vector<std::pair<int, int>> horizon;
        std::vector<int> next(std::size_t(mN), -1);
        for (int t : visible) {
            const auto& v = mTris[std::size_t(t)].v;
            for (int e = 0; e < 3; ++e) {
                const int a = v[std::size_t(e)], b = v[std::size_t((e + 1) % 3)];
                const int twin = edge(b, a);
                if (twin < 0) return false;
                if (seen[std::size_t(twin)]) continue;
                if (next[std::size_t(a)] >= 0) return false;  // the horizon touches itself
                next[std::size_t(a)] = b;
                horizon.emplace_back(a, b);
            }
        }
        // One cycle through every horizon edge.
        std::size_t steps = 0;
        for (int a = horizon.front().first; steps <= horizon.size();) {
            a = next[std::size_t(a)];
            ++steps;
            if (a < 0) return false;
            if (a == horizon.front().first) break;
        }
        if (steps != horizon.size()) return false;
        for (int t : visible) {
            Tri& tri = mTris[std::size_t(t)];
            tri.alive = false;
            for (int e = 0; e < 3; ++e) edge(tri.v[std::size_t(e)], tri.v[std::size_t((e + 1) % 3)]) = -1;
        }
        for (const auto& h : horizon)
            if (!insert({h.first, h.second, p})) return false;
        return true;
    }

    const std::vector<Vec3>& mPts;
    int mN;
    Tolerance mTol;
    std::vector<int> mEdge;  // (n x n): the triangle that has directed edge a -> b, or -1
    std::vector<Tri> mTris;
    std::array<int, 4> mS{};
};

/// For a triangle of the hull, the face the definition gives its plane: the first triple (in index order) of points
/// lying on that plane that spans a face through the triangle's corners. False when none does within `trials`.
bool definingTriple(const std::vector<Vec3>& pts, const std::array<int, 3>& tri, const Tolerance& tol, int* trials,
                    std::array<int, 3>* out) {
    const Vec3& a = pts[std::size_t(tri[0])];
    Vec3 n = D3::cross(D3::sub(pts[std::size_t(tri[1])], a), D3::sub(pts[std::size_t(tri[2])], a));
    const double len = norm(n);
    if (!(len > 0.0)) return false;
    n = D3::scale(1.0 / len, n);
    const double d = D3::dot(n, a);
    const double on = 10.0 * tol.eps;
    std::vector<int> coplanar;
    for (int m = 0; m < int(pts.size()); ++m)
        if (std::fabs(D3::dot(n, pts[std::size_t(m)]) - d) <= on) coplanar.push_back(m);
    const std::size_t c = coplanar.size();
    for (std::size_t i = 0; i < c; ++i) {
        for (std::size_t j = i + 1; j < c; ++j) {
            for (std::size_t k = j + 1; k < c; ++k) {
                if (++*trials > kMaxTrials) return false;
                ConvexPolyhedron::Face f;
                if (!tripleFace(pts, coplanar[i], coplanar[j], coplanar[k], tol, &f)) continue;
                bool through = true;  // the face of this triangle, not a neighbour's
                for (int v : tri) through = through && std::fabs(D3::dot(f.normal, pts[std::size_t(v)]) - f.offset) <= on;
                if (!through) continue;
                *out = {coplanar[i], coplanar[j], coplanar[k]};
                return true;
            }
        }
    }
    return false;
}

}  // namespace

std::string hull_detail::finishPolyhedron(const std::vector<Vec3>& pts, std::vector<ConvexPolyhedron::Face> faces,
                                          const Tolerance& tol, ConvexPolyhedron* out) {
    const double eps = tol.eps;
    const int n = int(pts.size());
    // Vertices: points on at least three face planes (extreme points); loops sorted by angle about the face centre.
    ConvexPolyhedron poly;
    for (int m = 0; m < n; ++m) {
        int on = 0;
        for (const auto& f : faces) on += std::fabs(D3::dot(f.normal, pts[std::size_t(m)]) - f.offset) <= 10.0 * eps ? 1 : 0;
        bool dup = false;
        for (const Vec3& v : poly.vertices) dup = dup || norm(D3::sub(v, pts[std::size_t(m)])) <= 10.0 * eps;
        if (on >= 3 && !dup) poly.vertices.push_back(pts[std::size_t(m)]);
    }
    for (auto& f : faces) {
        std::vector<int> on;
        Vec3 c = Vec3::Zero();
        for (int v = 0; v < int(poly.vertices.size()); ++v) {
            if (std::fabs(D3::dot(f.normal, poly.vertices[std::size_t(v)]) - f.offset) <= 10.0 * eps) {
                on.push_back(v);
                c = D3::add(c, poly.vertices[std::size_t(v)]);
            }
        }
        if (on.size() < 3) return "hull: degenerate face";
        c = D3::scale(1.0 / double(on.size()), c);
        Vec3 u = D3::sub(poly.vertices[std::size_t(on[0])], c);
        u = D3::scale(1.0 / norm(u), u);
        const Vec3 w = D3::cross(f.normal, u);
        std::vector<std::pair<double, int>> ang;
        for (int v : on) {
            const Vec3 r = D3::sub(poly.vertices[std::size_t(v)], c);
            ang.emplace_back(dmath::atan2(D3::dot(r, w), D3::dot(r, u)), v);
        }
        std::sort(ang.begin(), ang.end());  // (angle, index): a total order
        for (const auto& a : ang) f.loop.push_back(a.second);
    }
    poly.faces = std::move(faces);
    // Edges with their two faces (each directed edge of a loop appears once; its reverse belongs to the neighbour).
    std::map<std::pair<int, int>, int> edgeIndex;
    for (int fi = 0; fi < int(poly.faces.size()); ++fi) {
        const auto& loop = poly.faces[std::size_t(fi)].loop;
        for (std::size_t e = 0; e < loop.size(); ++e) {
            const int a = loop[e], b = loop[(e + 1) % loop.size()];
            const std::pair<int, int> key(std::min(a, b), std::max(a, b));
            const auto it = edgeIndex.find(key);
            if (it == edgeIndex.end()) {
                edgeIndex.emplace(key, int(poly.edges.size()));
                poly.edges.push_back({key.first, key.second, fi, -1});
            } else {
                poly.edges[std::size_t(it->second)].face1 = fi;
            }
        }
    }
    for (const auto& e : poly.edges)
        if (e.face1 < 0) return "hull: open surface (numerically degenerate points)";
    for (const Vec3& v : poly.vertices) poly.centroid = D3::add(poly.centroid, v);
    poly.centroid = D3::scale(1.0 / double(poly.vertices.size()), poly.centroid);
    *out = std::move(poly);
    return {};
}

std::string buildPolyhedron(const std::vector<Vec3>& pts, ConvexPolyhedron* out) {
    if (pts.size() < 4 || pts.size() > kMaxHullPoints) return "hull: needs 4.." + std::to_string(kMaxHullPoints) + " points";
    const Tolerance tol = hull_detail::toleranceOf(pts);
    TriangleHull hull(pts, tol);
    std::string why;
    if (!hull.build(&why)) return why;
    // The defining triple of every triangle's face, in index order; coplanar triples merge into the first.
    std::vector<std::array<int, 3>> triples;
    int trials = 0;
    for (const auto& tri : hull.triangles()) {
        std::array<int, 3> t{};
        if (!definingTriple(pts, tri, tol, &trials, &t)) return "hull: numerically degenerate points";
        triples.push_back(t);
    }
    std::sort(triples.begin(), triples.end());
    triples.erase(std::unique(triples.begin(), triples.end()), triples.end());
    std::vector<ConvexPolyhedron::Face> faces;
    for (const auto& t : triples) {
        ConvexPolyhedron::Face f;
        tripleFace(pts, t[0], t[1], t[2], tol, &f);
        hull_detail::mergeFace(faces, f, tol);
    }
    if (faces.size() < 4) return "hull: points must span a volume";
    ConvexPolyhedron poly;
    const std::string err = hull_detail::finishPolyhedron(pts, std::move(faces), tol, &poly);
    if (!err.empty()) return err;
    const std::string bad = checkPolyhedron(poly);
    if (!bad.empty()) return "hull: numerically degenerate points (" + bad + ")";
    *out = std::move(poly);
    return {};
}

std::string checkPolyhedron(const ConvexPolyhedron& poly) {
    const std::size_t nv = poly.vertices.size(), nf = poly.faces.size();
    if (nv < 4 || nv > kMaxHullPoints) return "polyhedron: needs 4.." + std::to_string(kMaxHullPoints) + " vertices";
    if (nf < 4 || nf > 2 * nv) return "polyhedron: face count out of range";
    for (const Vec3& v : poly.vertices)
        if (!D3::finite(v)) return "polyhedron: vertices must be finite";
    const double tol = 1e-7 * std::max(hull_detail::toleranceOf(poly.vertices).scale, 1e-3);
    // Directed loop edges (a, b, face), sorted: each must be unique and have its reverse in another face.
    std::vector<std::array<int, 3>> directed;
    std::vector<int> facesOfVertex(nv, 0);
    for (std::size_t f = 0; f < nf; ++f) {
        const ConvexPolyhedron::Face& face = poly.faces[f];
        if (!D3::finite(face.normal) || !std::isfinite(face.offset) || std::fabs(D3::dot(face.normal, face.normal) - 1.0) > 1e-9)
            return "polyhedron: face " + std::to_string(f) + " has no unit normal";
        const std::size_t m = face.loop.size();
        if (m < 3 || m > nv) return "polyhedron: face " + std::to_string(f) + " loop size out of range";
        Vec3 area = Vec3::Zero();
        for (std::size_t i = 0; i < m; ++i) {
            const int a = face.loop[i], b = face.loop[(i + 1) % m];
            if (a < 0 || std::size_t(a) >= nv) return "polyhedron: face " + std::to_string(f) + " vertex index out of range";
            ++facesOfVertex[std::size_t(a)];
            if (std::fabs(D3::dot(face.normal, poly.vertices[std::size_t(a)]) - face.offset) > tol)
                return "polyhedron: face " + std::to_string(f) + " has a vertex off its plane";
            directed.push_back({a, b, int(f)});
            if (b >= 0 && std::size_t(b) < nv)
                area = D3::add(area, D3::cross(D3::sub(poly.vertices[std::size_t(a)], poly.vertices[std::size_t(face.loop[0])]),
                                               D3::sub(poly.vertices[std::size_t(b)], poly.vertices[std::size_t(face.loop[0])])));
        }
        if (!(D3::dot(area, face.normal) > 0.0)) return "polyhedron: face " + std::to_string(f) + " is not counter-clockwise";
        for (const Vec3& v : poly.vertices)
            if (D3::dot(face.normal, v) - face.offset > tol) return "polyhedron: not convex (a vertex above face " + std::to_string(f) + ")";
    }
    for (int k : facesOfVertex)
        if (k < 3) return "polyhedron: a vertex lies on fewer than three faces";
    std::sort(directed.begin(), directed.end());
    for (std::size_t i = 1; i < directed.size(); ++i)
        if (directed[i][0] == directed[i - 1][0] && directed[i][1] == directed[i - 1][1])
            return "polyhedron: an edge is used twice in the same direction";
    auto faceOf = [&](int a, int b) {
        const auto it = std::lower_bound(directed.begin(), directed.end(), std::array<int, 3>{a, b, -1});
        return it != directed.end() && (*it)[0] == a && (*it)[1] == b ? (*it)[2] : -1;
    };
    for (const auto& d : directed)
        if (faceOf(d[1], d[0]) < 0) return "polyhedron: not closed (an edge has one face)";
    if (poly.edges.size() * 2 != directed.size()) return "polyhedron: the edge list does not match the faces";
    std::vector<std::pair<int, int>> listed;
    for (const ConvexPolyhedron::Edge& e : poly.edges) {
        if (!(e.v0 < e.v1) || e.v0 < 0 || std::size_t(e.v1) >= nv) return "polyhedron: bad edge vertices";
        const int f0 = faceOf(e.v0, e.v1), f1 = faceOf(e.v1, e.v0);
        if (f0 < 0 || !((e.face0 == f0 && e.face1 == f1) || (e.face0 == f1 && e.face1 == f0)))
            return "polyhedron: an edge's faces do not match the loops";
        listed.emplace_back(e.v0, e.v1);
    }
    std::sort(listed.begin(), listed.end());
    if (std::adjacent_find(listed.begin(), listed.end()) != listed.end()) return "polyhedron: an edge is listed twice";
    if (long(nv) - long(poly.edges.size()) + long(nf) != 2) return "polyhedron: V - E + F is not 2";
    Vec3 mean = Vec3::Zero();
    for (const Vec3& v : poly.vertices) mean = D3::add(mean, v);
    mean = D3::scale(1.0 / double(nv), mean);
    if (!D3::finite(poly.centroid) || norm(D3::sub(mean, poly.centroid)) > tol) return "polyhedron: centroid is not the vertex mean";
    return {};
}

}  // namespace unison
