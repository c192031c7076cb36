// resolver3d/shapes3d.cpp — see shapes3d.h.
#include "shapes3d.h"

#include "det_math.h"
#include "hull3d.h"

#include <algorithm>
#include <cmath>

namespace unison {

using D3 = Dim3;

Mat3 toMatrix(const Quat& q) {
    const double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    const double xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    const double wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    Mat3 m;
    m << 1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy),
         2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx),
         2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy);
    return m;
}

Quat normalized(const Quat& q) {
    const double n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
    if (!(n2 > 0.0) || !std::isfinite(n2)) return Quat{};
    const double inv = 1.0 / std::sqrt(n2);
    return Quat{q.w * inv, q.x * inv, q.y * inv, q.z * inv};
}

Quat multiply(const Quat& a, const Quat& b) {
    return Quat{a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Quat integrateRotation(const Quat& q, const Vec3& w, double dt) {
    // dq/dt = 1/2 (0, w) q (w in world axes); one explicit step, then back onto the unit sphere.
    const Quat dq = multiply(Quat{0.0, w.x(), w.y(), w.z()}, q);
    const double h = 0.5 * dt;
    return normalized(Quat{q.w + h * dq.w, q.x + h * dq.x, q.y + h * dq.y, q.z + h * dq.z});
}

Quat axisAngle(const Vec3& axis, double angle) {
    const double n = std::sqrt(D3::dot(axis, axis));
    if (!(n > 0.0)) return Quat{};
    double s = 0.0, c = 1.0;
    dmath::sincos(0.5 * angle, &s, &c);
    const double k = s / n;
    return Quat{c, k * axis.x(), k * axis.y(), k * axis.z()};
}

Mat3 rotateTensor(const Mat3& r, const Mat3& m) {
    Mat3 rm, out;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) rm(i, j) = r(i, 0) * m(0, j) + r(i, 1) * m(1, j) + r(i, 2) * m(2, j);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out(i, j) = rm(i, 0) * r(j, 0) + rm(i, 1) * r(j, 1) + rm(i, 2) * r(j, 2);
    return out;
}

namespace {

bool finite3(const Vec3& v) { return D3::finite(v); }
double norm(const Vec3& v) { return std::sqrt(D3::dot(v, v)); }

// Fan triangulation of the faces of a polyhedron (for volume integration).
std::vector<std::array<int, 3>> fanTriangles(const ConvexPolyhedron& p) {
    std::vector<std::array<int, 3>> tris;
    for (const auto& f : p.faces)
        for (std::size_t k = 1; k + 1 < f.loop.size(); ++k) tris.push_back({f.loop[0], f.loop[k], f.loop[k + 1]});
    return tris;
}

// Top-down sphere tree over items [first, first + count) of tree.order, each a ball (centres[i], radii[i]): split
// at the median of the longest axis of the range's centre box (ties by item index), until at most leafSize remain.
int buildTree(SphereTree& tree, const std::vector<Vec3>& centres, const std::vector<double>& radii, int first, int count,
              int leafSize) {
    auto at = [&](int k) { return tree.order[std::size_t(k)]; };
    Vec3 lo = centres[std::size_t(at(first))], hi = lo, c = Vec3::Zero();
    for (int k = first; k < first + count; ++k) {
        const Vec3& v = centres[std::size_t(at(k))];
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
        c = D3::add(c, v);
    }
    SphereNode node;
    node.center = D3::scale(1.0 / double(count), c);
    for (int k = first; k < first + count; ++k)
        node.radius = std::max(node.radius, norm(D3::sub(centres[std::size_t(at(k))], node.center)) + radii[std::size_t(at(k))]);
    node.first = first;
    node.count = count;
    const int index = int(tree.nodes.size());
    tree.nodes.push_back(node);
    if (count <= leafSize) return index;
    const Vec3 ext = D3::sub(hi, lo);
    const int axis = ext.x() >= ext.y() && ext.x() >= ext.z() ? 0 : (ext.y() >= ext.z() ? 1 : 2);
    std::sort(tree.order.begin() + first, tree.order.begin() + first + count, [&](int a, int b) {
        const double ca = centres[std::size_t(a)][axis], cb = centres[std::size_t(b)][axis];
        return ca < cb || (ca == cb && a < b);
    });
    const int half = count / 2;
    const int l = buildTree(tree, centres, radii, first, half, leafSize);
    const int r = buildTree(tree, centres, radii, first + half, count - half, leafSize);
    tree.nodes[std::size_t(index)].left = l;
    tree.nodes[std::size_t(index)].right = r;
    return index;
}

}  // namespace

std::string makeSphere(const Vec3& center, double radius, Shape3* out) {
    if (!finite3(center) || !std::isfinite(radius)) return "sphere: centre and radius must be finite";
    if (!(radius > 0.0)) return "sphere: radius must be > 0";
    Shape3 s = *out;
    s.type = ShapeType3::sphere;
    s.center = center;
    s.radius = radius;
    *out = s;
    return {};
}

std::string makeBox(const Vec3& h, const Vec3& center, Shape3* out) {
    if (!finite3(h) || !finite3(center)) return "box: half extents and centre must be finite";
    if (!(h.x() > 0.0 && h.y() > 0.0 && h.z() > 0.0)) return "box: half extents must be > 0";
    std::vector<Vec3> corners;
    for (int i = 0; i < 8; ++i)
        corners.push_back(Vec3(center.x() + ((i & 1) ? h.x() : -h.x()), center.y() + ((i & 2) ? h.y() : -h.y()),
                               center.z() + ((i & 4) ? h.z() : -h.z())));
    auto poly = std::make_shared<ConvexPolyhedron>();
    const std::string err = buildPolyhedron(corners, poly.get());
    if (!err.empty()) return "box: " + err;
    Shape3 s = *out;
    s.type = ShapeType3::box;
    s.halfExtents = h;
    s.center = center;
    s.poly = poly;
    *out = s;
    return {};
}

std::string makeHull(const std::vector<Vec3>& points, Shape3* out) {
    if (points.size() < 4 || points.size() > kMaxHullPoints)
        return "hull: needs 4.." + std::to_string(kMaxHullPoints) + " points";
    for (const Vec3& p : points)
        if (!finite3(p)) return "hull: points must be finite";
    auto poly = std::make_shared<ConvexPolyhedron>();
    const std::string err = buildPolyhedron(points, poly.get());
    if (!err.empty()) return err;
    Shape3 s = *out;
    s.type = ShapeType3::hull;
    s.poly = poly;
    *out = s;
    return {};
}

std::string makePlane(const Vec3& normal, double offset, Shape3* out) {
    if (!finite3(normal) || !std::isfinite(offset)) return "plane: normal and offset must be finite";
    const double n = norm(normal);
    if (!(n > 1e-12)) return "plane: normal must be non-zero";
    Shape3 s = *out;
    s.type = ShapeType3::plane;
    s.normal = D3::scale(1.0 / n, normal);
    s.offset = offset;
    *out = s;
    return {};
}

std::string makeMesh(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles, Shape3* out,
                     int leafSize) {
    const int nv = int(vertices.size());
    if (nv < 4 || triangles.size() < 4) return "mesh: needs at least 4 vertices and 4 triangles";
    for (const Vec3& v : vertices)
        if (!finite3(v)) return "mesh: vertices must be finite";
    // Directed edges as sorted 64-bit keys (8 bytes each, not a tree node each: a 2-million-triangle mesh from a
    // 16 MiB OBJ file is checked in 48 MB).
    std::vector<std::uint64_t> directed;
    directed.reserve(3 * triangles.size());
    auto key = [](int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); };
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        for (int k = 0; k < 3; ++k) {
            if (tri[std::size_t(k)] < 0 || tri[std::size_t(k)] >= nv)
                return "mesh: triangle " + std::to_string(t) + " has a vertex index out of range";
        }
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
            return "mesh: triangle " + std::to_string(t) + " repeats a vertex";
        for (int k = 0; k < 3; ++k) directed.push_back(key(tri[std::size_t(k)], tri[std::size_t((k + 1) % 3)]));
    }
    std::sort(directed.begin(), directed.end());
    if (std::adjacent_find(directed.begin(), directed.end()) != directed.end())
        return "mesh: edge used twice in the same direction (inconsistent orientation or non-manifold)";
    for (std::uint64_t e : directed)
        if (!std::binary_search(directed.begin(), directed.end(), (e << 32) | (e >> 32)))
            return "mesh: not closed (an edge has one triangle)";
    const MassData3 md = integrateSolid(vertices, triangles);
    if (!(md.mass > 0.0)) return "mesh: volume must be > 0 (triangles counter-clockwise seen from outside)";
    auto mesh = std::make_shared<TriangleMesh>();
    mesh->leafSize = std::max(1, leafSize);
    mesh->vertices = vertices;
    mesh->triangles = triangles;
    mesh->vertexNormals.assign(std::size_t(nv), Vec3::Zero());
    for (const auto& tri : triangles) {
        const Vec3 a = vertices[std::size_t(tri[0])], b = vertices[std::size_t(tri[1])], c = vertices[std::size_t(tri[2])];
        const Vec3 an = D3::cross(D3::sub(b, a), D3::sub(c, a));  // twice the area times the unit normal
        for (int k = 0; k < 3; ++k) mesh->vertexNormals[std::size_t(tri[std::size_t(k)])] = D3::add(mesh->vertexNormals[std::size_t(tri[std::size_t(k)])], an);
    }
    double edgeSum = 0.0;
    for (const auto& tri : triangles)
        for (int k = 0; k < 3; ++k)
            edgeSum += norm(D3::sub(vertices[std::size_t(tri[std::size_t(k)])], vertices[std::size_t(tri[std::size_t((k + 1) % 3)])]));
    mesh->meanEdge = edgeSum / double(3 * triangles.size());
    std::vector<int> used(std::size_t(nv), 0);
    for (const auto& tri : triangles)
        for (int k = 0; k < 3; ++k) used[std::size_t(tri[std::size_t(k)])] = 1;
    for (int v = 0; v < nv; ++v) {
        const double l = norm(mesh->vertexNormals[std::size_t(v)]);
        mesh->vertexNormals[std::size_t(v)] = l > 0.0 ? D3::scale(1.0 / l, mesh->vertexNormals[std::size_t(v)]) : Vec3::UnitZ();
        if (used[std::size_t(v)]) mesh->vertexTree.order.push_back(v);  // unused vertices never collide
    }
    buildTree(mesh->vertexTree, vertices, std::vector<double>(std::size_t(nv), 0.0), 0, int(mesh->vertexTree.order.size()),
              std::max(1, leafSize));
    // Triangles as balls around their centroids.
    std::vector<Vec3> centroids;
    std::vector<double> radii;
    for (int t = 0; t < int(triangles.size()); ++t) {
        const auto& tri = triangles[std::size_t(t)];
        const Vec3 a = vertices[std::size_t(tri[0])], b = vertices[std::size_t(tri[1])], c = vertices[std::size_t(tri[2])];
        const Vec3 n = D3::cross(D3::sub(b, a), D3::sub(c, a));
        const double l = norm(n);
        mesh->triangleNormals.push_back(l > 0.0 ? D3::scale(1.0 / l, n) : Vec3::UnitZ());
        const Vec3 g = D3::scale(1.0 / 3.0, D3::add(D3::add(a, b), c));
        centroids.push_back(g);
        radii.push_back(std::max(norm(D3::sub(a, g)), std::max(norm(D3::sub(b, g)), norm(D3::sub(c, g)))));
        mesh->triangleTree.order.push_back(t);
    }
    buildTree(mesh->triangleTree, centroids, radii, 0, int(triangles.size()), std::max(1, leafSize));
    Shape3 s = *out;
    s.type = ShapeType3::mesh;
    s.mesh = mesh;
    *out = s;
    return {};
}

MassData3 integrateSolid(const std::vector<Vec3>& v, const std::vector<std::array<int, 3>>& tris) {
    // Each triangle (a, b, c) and the origin bound a signed tetrahedron of volume a . (b x c) / 6. Over a
    // tetrahedron with one vertex at the origin, integral of x x^T dV = V/20 (a a^T + b b^T + c c^T + s s^T),
    // s = a + b + c, and its centroid is s / 4. Summing signed tetrahedra integrates over the enclosed solid.
    double vol = 0.0;
    Vec3 first = Vec3::Zero();
    Mat3 second = Mat3::Zero();
    for (const auto& t : tris) {
        const Vec3& a = v[std::size_t(t[0])];
        const Vec3& b = v[std::size_t(t[1])];
        const Vec3& c = v[std::size_t(t[2])];
        const double tv = D3::dot(a, D3::cross(b, c)) / 6.0;
        const Vec3 s = D3::add(D3::add(a, b), c);
        vol += tv;
        first = D3::add(first, D3::scale(tv / 4.0, s));
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                second(i, j) += tv / 20.0 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
    }
    MassData3 md;
    md.mass = vol;
    if (!(vol > 0.0)) return md;
    md.center = D3::scale(1.0 / vol, first);
    // Inertia about the origin is tr(C) 1 - C; shift to the centre (parallel axis theorem).
    const double tr = second(0, 0) + second(1, 1) + second(2, 2);
    const Vec3& c = md.center;
    const double cc = D3::dot(c, c);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const double delta = i == j ? 1.0 : 0.0;
            md.inertia(i, j) = (tr * delta - second(i, j)) - vol * (cc * delta - c[i] * c[j]);
        }
    return md;
}

MassData3 computeMass(const Shape3& s) {
    MassData3 md;
    switch (s.type) {
    case ShapeType3::sphere: {
        const double r = s.radius;
        md.mass = s.density * 4.0 / 3.0 * dmath::kPi * r * r * r;
        md.center = s.center;
        md.inertia = Mat3::Identity() * (0.4 * md.mass * r * r);
        return md;
    }
    case ShapeType3::box: {
        const Vec3 e = D3::scale(2.0, s.halfExtents);
        md.mass = s.density * e.x() * e.y() * e.z();
        md.center = s.center;
        md.inertia = Mat3::Zero();
        md.inertia(0, 0) = md.mass / 12.0 * (e.y() * e.y() + e.z() * e.z());
        md.inertia(1, 1) = md.mass / 12.0 * (e.x() * e.x() + e.z() * e.z());
        md.inertia(2, 2) = md.mass / 12.0 * (e.x() * e.x() + e.y() * e.y());
        return md;
    }
    case ShapeType3::hull:
        md = integrateSolid(s.poly->vertices, fanTriangles(*s.poly));
        break;
    case ShapeType3::mesh:
        md = integrateSolid(s.mesh->vertices, s.mesh->triangles);
        break;
    case ShapeType3::plane:
        return md;
    }
    md.mass *= s.density;
    md.inertia *= s.density;
    return md;
}

Aabb3 computeAabb(const Shape3& s, const Transform3& xf) {
    Aabb3 box;
    auto addPoints = [&](const std::vector<Vec3>& pts) {
        box.lower = box.upper = transformPoint(xf, pts[0]);
        for (const Vec3& p : pts) {
            const Vec3 w = transformPoint(xf, p);
            box.lower = box.lower.cwiseMin(w);
            box.upper = box.upper.cwiseMax(w);
        }
    };
    switch (s.type) {
    case ShapeType3::sphere: {
        const Vec3 c = transformPoint(xf, s.center);
        const Vec3 r(s.radius, s.radius, s.radius);
        box.lower = D3::sub(c, r);
        box.upper = D3::add(c, r);
        break;
    }
    case ShapeType3::box:
    case ShapeType3::hull:
        addPoints(s.poly->vertices);
        break;
    case ShapeType3::mesh: {
        const SphereNode& root = s.mesh->vertexTree.nodes[0];
        const Vec3 c = transformPoint(xf, root.center);
        const Vec3 r(root.radius, root.radius, root.radius);
        box.lower = D3::sub(c, r);
        box.upper = D3::add(c, r);
        break;
    }
    case ShapeType3::plane: {
        const double big = 1e18;
        box.lower = Vec3(-big, -big, -big);
        box.upper = Vec3(big, big, big);
        break;
    }
    }
    return box;
}

}  // namespace unison
