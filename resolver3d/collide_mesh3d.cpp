// resolver3d/collide_mesh3d.cpp — meshes in the narrowphase, through their sphere trees (the seed paper's model):
// mesh vertices against convex shapes, convex corners against mesh triangles, mesh against mesh. See collide3d.h for
// the conventions and collide3d_detail.h for the feature ids.
#include "collide3d_detail.h"

#include <algorithm>

namespace unison {
namespace collide3d_detail {

// Closest point of triangle (a, b, c) to p (Voronoi regions of vertices, edges, face).
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = D3::sub(b, a), ac = D3::sub(c, a), ap = D3::sub(p, a);
    const double d1 = D3::dot(ab, ap), d2 = D3::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    const Vec3 bp = D3::sub(p, b);
    const double d3 = D3::dot(ab, bp), d4 = D3::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return D3::add(a, D3::scale(d1 / (d1 - d3), ab));
    const Vec3 cp = D3::sub(p, c);
    const double d5 = D3::dot(ab, cp), d6 = D3::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return D3::add(a, D3::scale(d2 / (d2 - d6), ac));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
        return D3::add(b, D3::scale((d4 - d3) / ((d4 - d3) + (d5 - d6)), D3::sub(c, b)));
    const double den = 1.0 / (va + vb + vc);
    return D3::add(a, D3::add(D3::scale(vb * den, ab), D3::scale(vc * den, ac)));
}

namespace {

// Corners of polyhedron b (or sphere b) against the triangles of mesh a, through a's triangle tree: the part of the
// contact the mesh's own vertices cannot see (a box corner on a big flat triangle). Each point meets only its nearest
// triangle (nearest surface point), and counts while it is at most `depth` inside, so the far side of the mesh is
// never taken for the near one. Normals point from b towards a (into the mesh).
void convexOnTriangles(const TriangleMesh& mesh, const Transform3& xfA, const Shape3& b, const Transform3& xfB,
                       double margin, std::vector<ManifoldPoint3>& cands) {
    const double depth = std::max(4.0 * mesh.meanEdge, 0.05);
    std::vector<Vec3> points;
    double radius = 0.0;
    if (b.type == ShapeType3::sphere) {
        points.push_back(transformPoint(xfB, b.center));
        radius = b.radius;
    } else {
        for (const Vec3& v : b.poly->vertices) points.push_back(transformPoint(xfB, v));
    }
    const double reach = radius + std::max(margin, depth);
    for (int k = 0; k < int(points.size()); ++k) {
        const Vec3& p = points[std::size_t(k)];
        int bestT = -1;
        double bestDist = reach;
        Vec3 bestQ = Vec3::Zero();
        walkTree(mesh.triangleTree, xfA, [&](const Vec3& c, double r) { return norm(D3::sub(c, p)) - r < bestDist; },
                 [&](int t) {
                     const auto& tri = mesh.triangles[std::size_t(t)];
                     const Vec3 q = closestOnTriangle(p, transformPoint(xfA, mesh.vertices[std::size_t(tri[0])]),
                                                      transformPoint(xfA, mesh.vertices[std::size_t(tri[1])]),
                                                      transformPoint(xfA, mesh.vertices[std::size_t(tri[2])]));
                     const double dist = norm(D3::sub(p, q));
                     if (dist < bestDist) {  // strict: the lower triangle index in tree order wins ties
                         bestDist = dist;
                         bestT = t;
                         bestQ = q;
                     }
                 });
        if (bestT < 0) continue;
        const Vec3 n = mul(xfA.r, mesh.triangleNormals[std::size_t(bestT)]);
        const Vec3 d = D3::sub(p, bestQ);
        const double height = D3::dot(n, d);
        // Inside the triangle's prism the gap is the signed height; outside it, the distance to its boundary along
        // the direction to it (the point is outside the mesh there unless it is below the plane).
        const bool inPrism = bestDist <= std::fabs(height) * (1.0 + 1e-9) + 1e-12;
        if (!inPrism && height < 0.0) continue;
        const Vec3 out = inPrism || !(bestDist > 0.0) ? n : D3::scale(1.0 / bestDist, d);
        const double gap = inPrism ? height : bestDist;
        const double sep = gap - radius;
        if (sep >= margin || gap < -depth) continue;
        const Vec3 surfB = D3::sub(p, D3::scale(radius, out));
        const Vec3 mid = D3::sub(surfB, D3::scale(0.5 * sep, out));
        cands.push_back({mid, neg(out), sep, (std::uint32_t(bestT) & 0xFFFFFu) << 8 | (std::uint32_t(k) & 0xFFu)});
    }
}

}  // namespace

// Mesh a against polyhedron or sphere b: mesh vertices that are inside b or within margin of it, and b's corners (or
// centre) against a's triangles.
Manifold3 meshConvex(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB, double margin,
                     std::vector<ManifoldPoint3>* outCandidates) {
    std::vector<ManifoldPoint3> cands;
    const TriangleMesh& mesh = *a.mesh;
    convexOnTriangles(mesh, xfA, b, xfB, margin, cands);
    if (b.type == ShapeType3::sphere) {
        const Vec3 c = transformPoint(xfB, b.center);
        walkTree(mesh.vertexTree, xfA, [&](const Vec3& nc, double r) { return norm(D3::sub(nc, c)) - r - b.radius < margin; },
                 [&](int v) {
                     const Vec3 p = transformPoint(xfA, mesh.vertices[std::size_t(v)]);
                     const Vec3 d = D3::sub(p, c);
                     const double dist = norm(d);
                     const double sep = dist - b.radius;
                     if (sep >= margin || !(dist > 0.0)) return;
                     const Vec3 n = D3::scale(1.0 / dist, d);
                     cands.push_back({D3::sub(p, D3::scale(0.5 * sep, n)), n, sep, vertexId(kTreeVertex, v)});
                 });
        return finish(cands, outCandidates);
    }
    const ConvexPolyhedron& p = *b.poly;
    // Largest face-plane separation of a point in b's frame: exact inside, a lower bound of the distance outside.
    auto faceSep = [&](const Vec3& local, int* outFace) {
        double best = -1e300;
        for (int f = 0; f < int(p.faces.size()); ++f) {
            const double s = D3::dot(p.faces[std::size_t(f)].normal, local) - p.faces[std::size_t(f)].offset;
            if (s > best) {
                best = s;
                *outFace = f;
            }
        }
        return best;
    };
    walkTree(mesh.vertexTree, xfA,
             [&](const Vec3& c, double r) {
                 int f;
                 return faceSep(invTransformPoint(xfB, c), &f) - r < margin;
             },
             [&](int v) {
                 const Vec3 pw = transformPoint(xfA, mesh.vertices[std::size_t(v)]);
                 int f = 0;
                 const double sep = faceSep(invTransformPoint(xfB, pw), &f);
                 if (sep >= margin) return;
                 const Vec3 n = mul(xfB.r, p.faces[std::size_t(f)].normal);
                 cands.push_back({D3::sub(pw, D3::scale(0.5 * sep, n)), n, sep, vertexId(kTreeVertex, v)});
             });
    return finish(cands, outCandidates);
}

namespace {

// Vertices of mesh `a` in leaves that overlap leaves of mesh `b`, measured along the normal of b's nearest vertex
// in that leaf. `flip` marks the pass with the roles swapped (normals are negated by the caller's convention).
void meshMeshPass(const TriangleMesh& a, const Transform3& xfA, const TriangleMesh& b, const Transform3& xfB,
                  double margin, bool flip, std::vector<ManifoldPoint3>& cands) {
    std::vector<std::pair<int, int>> stack{{0, 0}};
    while (!stack.empty()) {
        const auto [ia, ib] = stack.back();
        stack.pop_back();
        const SphereNode& na = a.vertexTree.nodes[std::size_t(ia)];
        const SphereNode& nb = b.vertexTree.nodes[std::size_t(ib)];
        const Vec3 ca = transformPoint(xfA, na.center), cb = transformPoint(xfB, nb.center);
        if (norm(D3::sub(ca, cb)) - na.radius - nb.radius >= margin) continue;
        const bool leafA = na.left < 0, leafB = nb.left < 0;
        if (!leafA && (leafB || na.radius >= nb.radius)) {
            stack.push_back({na.right, ib});
            stack.push_back({na.left, ib});
            continue;
        }
        if (!leafB) {
            stack.push_back({ia, nb.right});
            stack.push_back({ia, nb.left});
            continue;
        }
        for (int k = na.first; k < na.first + na.count; ++k) {
            const int va = a.vertexTree.order[std::size_t(k)];
            const Vec3 pa = transformPoint(xfA, a.vertices[std::size_t(va)]);
            int nearest = -1;
            double bestD = 1e300;
            for (int q = nb.first; q < nb.first + nb.count; ++q) {
                const int vb = b.vertexTree.order[std::size_t(q)];
                const double dd = norm(D3::sub(pa, transformPoint(xfB, b.vertices[std::size_t(vb)])));
                if (dd < bestD) {
                    bestD = dd;
                    nearest = vb;
                }
            }
            if (nearest < 0) continue;
            // The vertex counts only when it lies over b's surface near `nearest` (within about one edge sideways)
            // and not deeper than a few edges: otherwise the nearest vertex of this leaf is not the surface it meets.
            const Vec3 n = mul(xfB.r, b.vertexNormals[std::size_t(nearest)]);
            const Vec3 d = D3::sub(pa, transformPoint(xfB, b.vertices[std::size_t(nearest)]));
            const double sep = D3::dot(n, d);
            const Vec3 lateral = D3::sub(d, D3::scale(sep, n));
            if (sep >= margin || sep < -4.0 * b.meanEdge || D3::dot(lateral, lateral) > b.meanEdge * b.meanEdge) continue;
            const std::uint32_t id = vertexId(kTreeVertex, va);
            cands.push_back({D3::sub(pa, D3::scale(0.5 * sep, n)), flip ? neg(n) : n, sep, flip ? id | kFlip : id});
        }
    }
}

}  // namespace

Manifold3 meshMesh(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB, double margin,
                   std::vector<ManifoldPoint3>* outCandidates) {
    std::vector<ManifoldPoint3> cands;
    meshMeshPass(*a.mesh, xfA, *b.mesh, xfB, margin, false, cands);
    meshMeshPass(*b.mesh, xfB, *a.mesh, xfA, margin, true, cands);
    return finish(cands, outCandidates);
}

}  // namespace collide3d_detail
}  // namespace unison
