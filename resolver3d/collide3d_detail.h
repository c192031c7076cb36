// resolver3d/collide3d_detail.h — internals shared by the two narrowphase files: collide3d.cpp (convex pairs,
// planes, the reduction to four points, dispatch) and collide_mesh3d.cpp (meshes through their sphere trees).
//
// Feature ids: bit 31 flip (the roles of the shapes were swapped to reach the routine), bits 28..30 the kind below,
// then for convex pairs the reference feature (bits 18..27), the incident feature (bits 8..17) and a side plane
// (bits 0..7); for sphere-tree points the vertex index (bits 0..27). Kind 0: a convex shape's corner (bits 0..7)
// against a mesh triangle (bits 8..27).
#pragma once

#include "collide3d.h"

#include <cmath>
#include <vector>

namespace unison {
namespace collide3d_detail {

using D3 = Dim3;

enum Kind : std::uint32_t {
    kSpheres = 1,     // sphere against sphere
    kFaceVertex = 2,  // incident vertex inside the reference face
    kFaceClip = 3,    // incident edge cut by a side plane of the reference face
    kEdges = 4,       // edge against edge (reference edge of A, incident edge of B)
    kSphereFeature = 5,  // sphere against a face (side 0), edge (1) or the inside (2) of a polyhedron
    kVertexPlane = 6,    // a polyhedron vertex or a sphere against a plane
    kTreeVertex = 7,     // a mesh vertex found through the sphere tree
};

constexpr std::uint32_t kFlip = 0x80000000u;

inline std::uint32_t convexId(Kind kind, int ref, int inc, int side) {
    return (std::uint32_t(kind) << 28) | ((std::uint32_t(ref) & 0x3FFu) << 18) | ((std::uint32_t(inc) & 0x3FFu) << 8) |
           (std::uint32_t(side) & 0xFFu);
}
inline std::uint32_t vertexId(Kind kind, int vertex) { return (std::uint32_t(kind) << 28) | (std::uint32_t(vertex) & 0x0FFFFFFFu); }

inline double norm(const Vec3& v) { return std::sqrt(D3::dot(v, v)); }
inline Vec3 neg(const Vec3& v) { return D3::scale(-1.0, v); }
/// Closest point of triangle (a, b, c) to p.
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Reduces candidates to at most 4 (reduceToFour) and fills a manifold; appends them to outCandidates if given.
Manifold3 finish(const std::vector<ManifoldPoint3>& cands, std::vector<ManifoldPoint3>* outCandidates);

// Calls visit(item) for every item in sphere-tree leaves whose sphere (placed by xf) passes `keep(center, radius)`;
// children are visited left first, so the order is fixed.
template <class Keep, class Visit>
void walkTree(const SphereTree& tree, const Transform3& xf, Keep keep, Visit visit) {
    std::vector<int> stack{0};
    while (!stack.empty()) {
        const SphereNode& node = tree.nodes[std::size_t(stack.back())];
        stack.pop_back();
        if (!keep(transformPoint(xf, node.center), node.radius)) continue;
        if (node.left >= 0) {
            stack.push_back(node.right);
            stack.push_back(node.left);
            continue;
        }
        for (int k = node.first; k < node.first + node.count; ++k) visit(tree.order[std::size_t(k)]);
    }
}


/// Mesh a against polyhedron or sphere b (normal from b towards a).
Manifold3 meshConvex(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB, double margin,
                     std::vector<ManifoldPoint3>* outCandidates);
/// Mesh a against mesh b (normal from b towards a).
Manifold3 meshMesh(const Shape3& a, const Transform3& xfA, const Shape3& b, const Transform3& xfB, double margin,
                   std::vector<ManifoldPoint3>* outCandidates);

}  // namespace collide3d_detail
}  // namespace unison
