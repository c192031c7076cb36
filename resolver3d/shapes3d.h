// resolver3d/shapes3d.h — rotations, transforms, bounding boxes and the shapes of the 3D world.
//
// Owns: Quat helpers (unit quaternions integrated and normalised with + - * / sqrt only), Transform3, Aabb3, the
// shapes (sphere, box, convex hull, static plane, closed triangle mesh with its sphere tree), their validating
// constructors and their mass properties by exact volume integration.
//
// Invariants:
//   - A shape made by makeSphere / makeBox / makeHull / makePlane / makeMesh is fully valid or the call fails with
//     a message and leaves *out untouched (finite coordinates, positive sizes, non-degenerate hulls, closed meshes
//     with positive volume).
//   - Geometry is in the body frame (metres). Boxes and hulls share one representation (ConvexPolyhedron: faces
//     with outward unit normals and counter-clockwise vertex loops seen from outside), so one SAT serves both.
//   - Built data is immutable and shared (shared_ptr<const ...>): copying a shape never copies a mesh.
#pragma once

#include "dim3.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace unison {

/// A unit quaternion stored as w, x, y, z (32 bytes, no padding). The identity by default.
struct Quat {
    double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
};
static_assert(sizeof(Quat) == 32, "Quat is four doubles");

/// The rotation matrix of q (q need not be exactly unit: it is used as stored).
Mat3 toMatrix(const Quat& q);
/// q / |q| (sqrt only); the identity for a zero or non-finite q.
Quat normalized(const Quat& q);
/// q advanced by angular velocity w (rad/s) over dt: q + dt/2 (0, w) q, then normalised (no libm transcendental).
Quat integrateRotation(const Quat& q, const Vec3& w, double dt);
/// Rotation by `angle` radians about the unit axis (deterministic dmath::sincos).
Quat axisAngle(const Vec3& axis, double angle);
/// Product a b (rotation b first, then a).
Quat multiply(const Quat& a, const Quat& b);

/// m v with a fixed summation order.
inline Vec3 mul(const Mat3& m, const Vec3& v) { return Dim3::applyInvInertia(m, v); }
/// m^T v.
inline Vec3 mulT(const Mat3& m, const Vec3& v) {
    return Vec3(m(0, 0) * v.x() + m(1, 0) * v.y() + m(2, 0) * v.z(), m(0, 1) * v.x() + m(1, 1) * v.y() + m(2, 1) * v.z(),
                m(0, 2) * v.x() + m(1, 2) * v.y() + m(2, 2) * v.z());
}
/// R M R^T with a fixed summation order (a body-frame tensor in world axes).
Mat3 rotateTensor(const Mat3& r, const Mat3& m);

/// A rigid transform: x_world = p + R x_local.
struct Transform3 {
    Vec3 p = Vec3::Zero();  ///< translation (m)
    Mat3 r = Mat3::Identity();  ///< rotation matrix
};
inline Vec3 transformPoint(const Transform3& xf, const Vec3& v) { return Dim3::add(xf.p, mul(xf.r, v)); }
inline Vec3 invTransformPoint(const Transform3& xf, const Vec3& v) { return mulT(xf.r, Dim3::sub(v, xf.p)); }

/// An axis-aligned box (m); valid when lower <= upper componentwise.
struct Aabb3 {
    Vec3 lower = Vec3::Zero();
    Vec3 upper = Vec3::Zero();
};

/// A convex polyhedron in the body frame: the geometry of boxes and hulls.
struct ConvexPolyhedron {
    struct Face {
        Vec3 normal;              ///< outward unit normal
        double offset = 0.0;      ///< normal . x = offset on the face plane
        std::vector<int> loop;    ///< vertex indices, counter-clockwise seen from outside
    };
    struct Edge {
        int v0 = 0, v1 = 0;       ///< vertex indices, v0 < v1
        int face0 = 0, face1 = 0; ///< the two faces that share it
    };
    std::vector<Vec3> vertices;
    std::vector<Face> faces;
    std::vector<Edge> edges;
    Vec3 centroid = Vec3::Zero();  ///< mean of the vertices (an interior point)
};
static_assert(sizeof(ConvexPolyhedron) == 96, "ConvexPolyhedron changed: serialise the new field (world3d_state.cpp)");

/// A node of a bounding-sphere hierarchy. Every node owns the items order[first .. first + count) of its tree.
struct SphereNode {
    Vec3 center = Vec3::Zero();
    double radius = 0.0;
    int left = -1, right = -1;  ///< children (-1 for a leaf)
    int first = 0, count = 0;   ///< item range in the tree's order
};

/// A bounding-sphere hierarchy over items (vertices or triangles): node 0 is the root.
struct SphereTree {
    std::vector<SphereNode> nodes;
    std::vector<int> order;  ///< item indices grouped by leaf
};

/// A closed triangle mesh with sphere trees (the paper's sphere-tree collision model): one over its vertices (mesh
/// points against other shapes) and one over its triangles (other shapes' corners and spheres against its faces).
struct TriangleMesh {
    std::vector<Vec3> vertices;                 ///< (nv) body frame
    std::vector<std::array<int, 3>> triangles;  ///< (nt) counter-clockwise seen from outside
    std::vector<Vec3> vertexNormals;            ///< (nv) area-weighted outward unit normals
    std::vector<Vec3> triangleNormals;          ///< (nt) outward unit normals
    SphereTree vertexTree;                      ///< leaves hold <= leafSize vertices
    SphereTree triangleTree;                    ///< leaves hold <= leafSize triangles
    double meanEdge = 0.0;                      ///< mean edge length (m): the surface's sampling spacing
    int leafSize = 8;                           ///< makeMesh's leafSize (snapshots rebuild the trees with it)
};
static_assert(sizeof(TriangleMesh) == 208, "TriangleMesh changed: serialise the new field (world3d_state.cpp)");

enum class ShapeType3 : std::uint8_t { sphere, box, hull, plane, mesh };

/// One shape of a body. Which fields matter depends on type.
struct Shape3 {
    ShapeType3 type = ShapeType3::sphere;
    Vec3 center = Vec3::Zero();       ///< sphere centre; box centre
    double radius = 0.0;              ///< sphere radius (m)
    Vec3 halfExtents = Vec3::Zero();  ///< box half extents (m)
    Vec3 normal = Vec3::UnitZ();      ///< plane: unit normal; the solid side is normal . x <= offset
    double offset = 0.0;              ///< plane offset (m)
    std::shared_ptr<const ConvexPolyhedron> poly;  ///< box and hull
    std::shared_ptr<const TriangleMesh> mesh;      ///< mesh
    double density = 1.0;             ///< kg / m^3
    double friction = 0.6;
    double restitution = 0.0;
};
static_assert(sizeof(Shape3) == 152, "Shape3 changed: serialise the new field (world3d_state.cpp)");

/// Shape builders: an empty string on success, else a message (and *out untouched).
std::string makeSphere(const Vec3& center, double radius, Shape3* out);
std::string makeBox(const Vec3& halfExtents, const Vec3& center, Shape3* out);
/// Most points makeHull takes.
constexpr std::size_t kMaxHullPoints = 256;
/// The convex hull of 4..kMaxHullPoints points (not all coplanar). Points inside the hull are dropped.
std::string makeHull(const std::vector<Vec3>& points, Shape3* out);
/// A static half-space normal . x <= offset (normal is normalised here).
std::string makePlane(const Vec3& normal, double offset, Shape3* out);
/// A closed, consistently oriented triangle mesh (every edge shared by exactly two triangles in opposite
/// directions) with positive volume. leafSize: vertices per sphere-tree leaf.
std::string makeMesh(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles, Shape3* out,
                     int leafSize = 8);

/// Mass properties of a shape in its body frame: mass (kg), centre of mass, inertia tensor about the centre.
struct MassData3 {
    double mass = 0.0;
    Vec3 center = Vec3::Zero();
    Mat3 inertia = Mat3::Zero();
};

/// Mass, centre and inertia of a closed triangle surface with unit density, by exact volume integration
/// (divergence theorem over tetrahedra from the origin). Volume is `mass` of the result.
MassData3 integrateSolid(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles);
/// Mass properties of a shape (planes have none).
MassData3 computeMass(const Shape3& shape);
/// World bounding box of a shape placed by xf (a plane gets a huge box).
Aabb3 computeAabb(const Shape3& shape, const Transform3& xf);

}  // namespace unison
