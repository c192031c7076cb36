// resolver3d/query3d.cpp — see query3d.h: the exact ray, point and overlap tests on one shape, and World3's queries
// over its shape tree (core/scene_index.h).
//
// Rays are cast in the shape's frame. Boxes, hulls and planes are intersections of half-spaces, so a ray is clipped
// against each face plane (Cyrus-Beck); spheres solve their quadratic without cancellation; meshes are walked
// through their triangle sphere tree, and a ray whose first crossing leaves through a back face started inside.
// Overlaps of convex shapes are decided by separating axes (face normals of both and the cross products of their
// edges); a convex shape overlaps a mesh when its interior crosses a triangle, or when one holds the other.
#include "query3d.h"

#include "collide3d_detail.h"
#include "world3d.h"

#include <algorithm>
#include <cmath>

namespace unison {

using collide3d_detail::D3;
using collide3d_detail::closestOnTriangle;
using collide3d_detail::norm;
using collide3d_detail::walkTree;

namespace {

// Cyrus-Beck: the segment o + t d, t in [0, 1], against the half-spaces normal(i) . x <= offset(i), i < count.
// On a hit, *t is where it enters and *face the face it enters through (-1: o is already inside).
template <class Normal, class Offset>
bool clipHalfSpaces(int count, Normal normal, Offset offset, const Vec3& o, const Vec3& d, double* t, int* face) {
    double lower = 0.0, upper = 1.0;
    *face = -1;
    for (int i = 0; i < count; ++i) {
        const Vec3 n = normal(i);
        const double num = offset(i) - D3::dot(n, o);  // > 0: o inside this half-space
        const double den = D3::dot(n, d);
        if (den == 0.0) {
            if (num < 0.0) return false;
        } else if (den < 0.0 && num < lower * den) {
            lower = num / den;
            *face = i;
        } else if (den > 0.0 && num < upper * den) {
            upper = num / den;
        }
        if (upper < lower) return false;
    }
    *t = lower;
    return true;
}

// The nearest triangle of mesh m (its own frame) that the segment o + t d, t in [0, maxT], crosses (either side).
// Ties go to the lower triangle index. False when none.
bool meshRay(const TriangleMesh& m, const Vec3& o, const Vec3& d, double maxT, double* outT, int* outTri) {
    const double dd = D3::dot(d, d);
    int best = -1;
    double bestT = maxT;
    walkTree(m.triangleTree, Transform3{},
             [&](const Vec3& c, double r) {
                 const double tc = std::min(bestT, std::max(0.0, D3::dot(D3::sub(c, o), d) / dd));
                 const Vec3 q = D3::sub(D3::add(o, D3::scale(tc, d)), c);
                 const double grown = r * (1.0 + 1e-9) + 1e-12;
                 return D3::dot(q, q) <= grown * grown;
             },
             [&](int tri) {
                 const auto& idx = m.triangles[std::size_t(tri)];
                 const Vec3& a = m.vertices[std::size_t(idx[0])];
                 const Vec3 e1 = D3::sub(m.vertices[std::size_t(idx[1])], a);
                 const Vec3 e2 = D3::sub(m.vertices[std::size_t(idx[2])], a);
                 const Vec3 p = D3::cross(d, e2);
                 const double det = D3::dot(e1, p);
                 if (det == 0.0) return;
                 const Vec3 s = D3::sub(o, a);
                 const double u = D3::dot(s, p) / det;
                 if (u < 0.0 || u > 1.0) return;
                 const Vec3 q = D3::cross(s, e1);
                 const double v = D3::dot(d, q) / det;
                 if (v < 0.0 || u + v > 1.0) return;
                 const double t = D3::dot(e2, q) / det;
                 if (t < 0.0 || t > bestT) return;
                 if (t < bestT || best < 0 || tri < best) {
                     bestT = t;
                     best = tri;
                 }
             });
    if (best < 0) return false;
    *outT = bestT;
    *outTri = best;
    return true;
}

// A fixed direction no mesh of axis-aligned or simple geometry is likely to graze.
const Vec3 kProbe = Vec3(0.5773502691896258, 0.5773502691896257, 0.5773502691896259);

// p (mesh frame) strictly inside the closed mesh m: the first crossing of a ray from p leaves through a back face.
bool meshContains(const TriangleMesh& m, const Vec3& p) {
    const SphereNode& root = m.vertexTree.nodes[0];
    const double dc = norm(D3::sub(p, root.center));
    if (dc >= root.radius) return false;
    const double reach = 2.0 * root.radius + dc;
    double t = 0.0;
    int tri = -1;
    if (!meshRay(m, p, D3::scale(reach, kProbe), 1.0, &t, &tri)) return false;
    return t > 0.0 && D3::dot(m.triangleNormals[std::size_t(tri)], kProbe) > 0.0;
}

// A placed convex shape: a sphere (c, r) or a polytope's world vertices, face normals and edge directions.
struct Convex3 {
    bool sphere = false;
    Vec3 c = Vec3::Zero();  // sphere centre, or the polytope's centroid
    double r = 0.0;         // sphere radius, or the polytope's bounding radius about c
    std::vector<Vec3> v, faceNormals, edges;
};

Convex3 placeConvex(const Shape3& s, const Transform3& xf) {
    Convex3 out;
    if (s.type == ShapeType3::sphere) {
        out.sphere = true;
        out.c = transformPoint(xf, s.center);
        out.r = s.radius;
        return out;
    }
    const ConvexPolyhedron& poly = *s.poly;
    out.c = transformPoint(xf, poly.centroid);
    for (const Vec3& v : poly.vertices) {
        out.v.push_back(transformPoint(xf, v));
        out.r = std::max(out.r, norm(D3::sub(out.v.back(), out.c)));
    }
    for (const auto& f : poly.faces) out.faceNormals.push_back(mul(xf.r, f.normal));
    for (const auto& e : poly.edges)
        out.edges.push_back(D3::sub(out.v[std::size_t(e.v1)], out.v[std::size_t(e.v0)]));
    return out;
}

// True when the projections of point sets a and b on axis n are disjoint or only touch.
bool separatedAlong(const std::vector<Vec3>& a, const std::vector<Vec3>& b, const Vec3& n) {
    double minA = D3::dot(n, a[0]), maxA = minA, minB = D3::dot(n, b[0]), maxB = minB;
    for (const Vec3& p : a) {
        minA = std::min(minA, D3::dot(n, p));
        maxA = std::max(maxA, D3::dot(n, p));
    }
    for (const Vec3& p : b) {
        minB = std::min(minB, D3::dot(n, p));
        maxB = std::max(maxB, D3::dot(n, p));
    }
    return maxA <= minB || maxB <= minA;
}

// Separating axes of two polytopes given as vertices, face normals and edge directions.
bool polytopesOverlap(const std::vector<Vec3>& va, const std::vector<Vec3>& na, const std::vector<Vec3>& ea,
                      const std::vector<Vec3>& vb, const std::vector<Vec3>& nb, const std::vector<Vec3>& eb) {
    for (const Vec3& n : na)
        if (separatedAlong(va, vb, n)) return false;
    for (const Vec3& n : nb)
        if (separatedAlong(va, vb, n)) return false;
    for (const Vec3& a : ea) {
        for (const Vec3& b : eb) {
            const Vec3 n = D3::cross(a, b);
            // Parallel edges give no new axis (the face normals cover that direction).
            if (D3::dot(n, n) <= 1e-24 * D3::dot(a, a) * D3::dot(b, b)) continue;
            if (separatedAlong(va, vb, n)) return false;
        }
    }
    return true;
}

double distanceSquaredToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 e = D3::sub(b, a);
    const double ee = D3::dot(e, e);
    const double t = ee > 0.0 ? std::min(1.0, std::max(0.0, D3::dot(D3::sub(p, a), e) / ee)) : 0.0;
    const Vec3 q = D3::sub(p, D3::add(a, D3::scale(t, e)));
    return D3::dot(q, q);
}

// Sphere (c, r) against box or hull `poly` placed by xf: centre inside, or closer than r to some face polygon.
bool sphereOverlapsPolytope(const Vec3& c, double r, const Shape3& poly, const Transform3& xf) {
    if (containsPoint(poly, xf, c)) return true;
    const Vec3 p = invTransformPoint(xf, c);
    const ConvexPolyhedron& h = *poly.poly;
    for (const auto& f : h.faces) {
        const double height = D3::dot(f.normal, p) - f.offset;
        if (height >= r) return false;  // this face's plane separates them
    }
    for (const auto& f : h.faces) {
        const double height = D3::dot(f.normal, p) - f.offset;
        bool inside = true;
        const int n = int(f.loop.size());
        for (int i = 0; i < n; ++i) {
            const Vec3& a = h.vertices[std::size_t(f.loop[std::size_t(i)])];
            const Vec3& b = h.vertices[std::size_t(f.loop[std::size_t((i + 1) % n)])];
            inside = inside && D3::dot(D3::cross(D3::sub(b, a), D3::sub(p, a)), f.normal) >= 0.0;
        }
        if (inside && std::fabs(height) < r) return true;
        for (int i = 0; i < n; ++i)
            if (distanceSquaredToSegment(p, h.vertices[std::size_t(f.loop[std::size_t(i)])],
                                         h.vertices[std::size_t(f.loop[std::size_t((i + 1) % n)])]) < r * r)
                return true;
    }
    return false;
}

// Convex q (placed in the mesh's frame) against closed mesh m.
bool convexOverlapsMesh(const Convex3& q, const TriangleMesh& m) {
    bool hit = false;
    walkTree(m.triangleTree, Transform3{},
             [&](const Vec3& c, double r) { return !hit && norm(D3::sub(c, q.c)) < r + q.r + 1e-9 * (1.0 + q.r); },
             [&](int tri) {
                 if (hit) return;
                 const auto& idx = m.triangles[std::size_t(tri)];
                 const std::vector<Vec3> t{m.vertices[std::size_t(idx[0])], m.vertices[std::size_t(idx[1])],
                                           m.vertices[std::size_t(idx[2])]};
                 if (q.sphere) {
                     const Vec3 d = D3::sub(q.c, closestOnTriangle(q.c, t[0], t[1], t[2]));
                     hit = D3::dot(d, d) < q.r * q.r;
                     return;
                 }
                 const std::vector<Vec3> normal{D3::cross(D3::sub(t[1], t[0]), D3::sub(t[2], t[0]))};
                 const std::vector<Vec3> edges{D3::sub(t[1], t[0]), D3::sub(t[2], t[1]), D3::sub(t[0], t[2])};
                 hit = polytopesOverlap(q.v, q.faceNormals, q.edges, t, normal, edges);
             });
    if (hit) return true;
    // No triangle crosses the shape's interior: they overlap only if one holds the other.
    if (meshContains(m, q.sphere ? q.c : q.v[0])) return true;
    const Vec3& mv = m.vertices[0];
    if (q.sphere) return D3::dot(D3::sub(mv, q.c), D3::sub(mv, q.c)) < q.r * q.r;
    for (const Vec3& n : q.faceNormals) {
        double top = D3::dot(n, q.v[0]);
        for (const Vec3& v : q.v) top = std::max(top, D3::dot(n, v));
        if (!(D3::dot(n, mv) < top)) return false;
    }
    return true;
}

bool isConvex(const Shape3& s) {
    return s.type == ShapeType3::sphere || s.type == ShapeType3::box || s.type == ShapeType3::hull;
}

}  // namespace

bool containsPoint(const Shape3& s, const Transform3& xf, const Vec3& point) {
    const Vec3 p = invTransformPoint(xf, point);
    switch (s.type) {
        case ShapeType3::sphere: {
            const Vec3 d = D3::sub(p, s.center);
            return D3::dot(d, d) < s.radius * s.radius;
        }
        case ShapeType3::box:
        case ShapeType3::hull:
            for (const auto& f : s.poly->faces)
                if (!(D3::dot(f.normal, p) < f.offset)) return false;
            return true;
        case ShapeType3::plane:
            return D3::dot(s.normal, p) < s.offset;
        case ShapeType3::mesh:
            return meshContains(*s.mesh, p);
    }
    return false;
}

bool rayCastShape(const Shape3& s, const Transform3& xf, const Vec3& origin, const Vec3& translation,
                  double* outFraction, Vec3* outNormal) {
    const Vec3 o = invTransformPoint(xf, origin);
    const Vec3 d = mulT(xf.r, translation);
    const double dd = D3::dot(d, d);
    if (!(dd > 0.0)) return false;
    const Vec3 back = D3::scale(-1.0 / std::sqrt(dd), d);  // the normal reported for a start inside
    double t = 0.0;
    Vec3 n = back;
    switch (s.type) {
        case ShapeType3::sphere: {
            const Vec3 p = D3::sub(o, s.center);
            const double c = D3::dot(p, p) - s.radius * s.radius;
            if (c < 0.0) break;
            const double b = D3::dot(p, d);
            const double disc = b * b - dd * c;
            if (b >= 0.0 || disc < 0.0) return false;
            t = c / (-b + std::sqrt(disc));
            if (t > 1.0) return false;
            const Vec3 q = D3::add(p, D3::scale(t, d));
            n = D3::scale(1.0 / norm(q), q);
            break;
        }
        case ShapeType3::box:
        case ShapeType3::hull: {
            const auto& faces = s.poly->faces;
            int face = -1;
            if (!clipHalfSpaces(
                    int(faces.size()), [&](int i) { return faces[std::size_t(i)].normal; },
                    [&](int i) { return faces[std::size_t(i)].offset; }, o, d, &t, &face))
                return false;
            if (face >= 0) n = faces[std::size_t(face)].normal;
            break;
        }
        case ShapeType3::plane: {
            int face = -1;
            if (!clipHalfSpaces(
                    1, [&](int) { return s.normal; }, [&](int) { return s.offset; }, o, d, &t, &face))
                return false;
            if (face >= 0) n = s.normal;
            break;
        }
        case ShapeType3::mesh: {
            const TriangleMesh& m = *s.mesh;
            int tri = -1;
            if (meshRay(m, o, d, 1.0, &t, &tri)) {
                if (D3::dot(m.triangleNormals[std::size_t(tri)], d) > 0.0)
                    t = 0.0;  // the first crossing leaves the solid: the ray started inside
                else
                    n = m.triangleNormals[std::size_t(tri)];
            } else if (!meshContains(m, o)) {
                return false;
            }
            break;
        }
    }
    *outFraction = t;
    *outNormal = mul(xf.r, n);
    return true;
}

bool shapesOverlap(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB) {
    if (!isConvex(a)) return false;
    switch (b.type) {
        case ShapeType3::plane: {
            const Vec3 n = mul(xfB.r, b.normal);
            const double offset = b.offset + D3::dot(n, xfB.p);
            if (a.type == ShapeType3::sphere) return D3::dot(n, transformPoint(xfA, a.center)) - a.radius < offset;
            for (const Vec3& v : a.poly->vertices)
                if (D3::dot(n, transformPoint(xfA, v)) < offset) return true;
            return false;
        }
        case ShapeType3::mesh: {
            // a in the mesh's frame: x_mesh = R_b^T (R_a x + p_a - p_b).
            const Transform3 rel{mulT(xfB.r, D3::sub(xfA.p, xfB.p)), xfB.r.transpose() * xfA.r};
            return convexOverlapsMesh(placeConvex(a, rel), *b.mesh);
        }
        case ShapeType3::sphere: {
            const Vec3 c = transformPoint(xfB, b.center);
            if (a.type != ShapeType3::sphere) return sphereOverlapsPolytope(c, b.radius, a, xfA);
            const Vec3 d = D3::sub(transformPoint(xfA, a.center), c);
            const double r = a.radius + b.radius;
            return D3::dot(d, d) < r * r;
        }
        case ShapeType3::box:
        case ShapeType3::hull: {
            if (a.type == ShapeType3::sphere) return sphereOverlapsPolytope(transformPoint(xfA, a.center), a.radius, b, xfB);
            const Convex3 pa = placeConvex(a, xfA), pb = placeConvex(b, xfB);
            return polytopesOverlap(pa.v, pa.faceNormals, pa.edges, pb.v, pb.faceNormals, pb.edges);
        }
    }
    return false;
}

// ---- World3's queries ------------------------------------------------------------------------------------------

namespace {

QueryTree<3>::Box toBox(const Aabb3& b) {
    return {{b.lower.x(), b.lower.y(), b.lower.z()}, {b.upper.x(), b.upper.y(), b.upper.z()}};
}

bool finiteTransform(const Transform3& xf) { return D3::finite(xf.p) && xf.r.allFinite(); }

}  // namespace

const SceneIndex<3>& World3::sceneIndex() const {
    mIndex->ensure([this](std::vector<ShapeRef>& items, std::vector<QueryTree<3>::Box>& boxes) {
        for (int d = 0; d < mBodies.size(); ++d) {
            const BodyState3& s = mBodies.hot(d);
            const Transform3 xf{s.position, toMatrix(s.rotation)};
            const std::vector<Shape3>& shapes = mBodies.cold(d).shapes;
            for (int k = 0; k < int(shapes.size()); ++k) {
                items.push_back({mBodies.idAt(d), k});
                boxes.push_back(toBox(computeAabb(shapes[std::size_t(k)], xf)));
            }
        }
    });
    return *mIndex;
}

template <class Visit>
void World3::castRay(const Vec3& origin, const Vec3& translation, bool closest, Visit&& visit) const {
    if (!D3::finite(origin) || !D3::finite(translation) || !(D3::dot(translation, translation) > 0.0)) return;
    const SceneIndex<3>& index = sceneIndex();
    index.tree().ray({origin.x(), origin.y(), origin.z()}, {translation.x(), translation.y(), translation.z()}, 1.0,
                     [&](int item, double maxFraction) {
                         const ShapeRef& ref = index.items()[std::size_t(item)];
                         const auto [shape, xf] = placedShape(ref);
                         RayHit3 hit;
                         if (!rayCastShape(shape, xf, origin, translation, &hit.fraction, &hit.normal))
                             return maxFraction;
                         hit.body = ref.body;
                         hit.shape = ref.shape;
                         hit.point = D3::add(origin, D3::scale(hit.fraction, translation));
                         visit(hit);
                         return closest ? std::min(maxFraction, hit.fraction) : maxFraction;
                     });
}

bool World3::rayCastClosest(const Vec3& origin, const Vec3& translation, RayHit3* out) const {
    return closestHit<RayHit3>([&](bool closest, auto&& visit) { castRay(origin, translation, closest, visit); }, out);
}

std::vector<RayHit3> World3::rayCastAll(const Vec3& origin, const Vec3& translation) const {
    return allHits<RayHit3>([&](bool closest, auto&& visit) { castRay(origin, translation, closest, visit); });
}

// The shape `ref` names and its body's transform.
std::pair<const Shape3&, Transform3> World3::placedShape(const ShapeRef& ref) const {
    const int d = mBodies.denseIndex(ref.body);
    const BodyState3& s = mBodies.hot(d);
    return {mBodies.cold(d).shapes[std::size_t(ref.shape)], Transform3{s.position, toMatrix(s.rotation)}};
}

std::vector<ShapeRef> World3::overlapAabb(const Aabb3& box) const {
    if (!D3::finite(box.lower) || !D3::finite(box.upper)) return {};
    return sceneIndex().overlapping(toBox(box), [&](const ShapeRef& ref) {
        const auto [shape, xf] = placedShape(ref);
        const Aabb3 b = computeAabb(shape, xf);
        return (b.lower.array() <= box.upper.array()).all() && (box.lower.array() <= b.upper.array()).all();
    });
}

std::vector<ShapeRef> World3::overlapShape(const Shape3& shape, const Transform3& xf) const {
    if (!isConvex(shape) || !finiteTransform(xf)) return {};
    return sceneIndex().overlapping(toBox(computeAabb(shape, xf)), [&](const ShapeRef& ref) {
        const auto [other, otherXf] = placedShape(ref);
        return shapesOverlap(shape, xf, other, otherXf);
    });
}

}  // namespace unison
