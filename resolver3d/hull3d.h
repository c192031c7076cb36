// resolver3d/hull3d.h — the convex polyhedron of a point set (the geometry of boxes and hulls) and the consistency
// check that every polyhedron, built or restored from a snapshot, must pass.
//
// Owns: buildPolyhedron (an incremental hull finds the faces in O(n F) = O(n^2) for n <= kMaxHullPoints, instead
// of trying every triple of points against every point, O(n^4)) and checkPolyhedron.
// Invariants:
//   - The output is the one the original triple-by-triple definition gives: each face is spanned by the first
//     triple of points (in index order) whose plane has every point on or below it (tolerance eps), faces come in
//     the order of those triples, and coplanar triples merge into the first. The incremental hull only proposes the
//     candidate planes; that definition then picks the triple, its rounding included, so hashes of existing
//     scenes do not change.
//   - A polyhedron that passes checkPolyhedron is closed and convex: unit outward face normals, every vertex on or
//     below every face plane, counter-clockwise loops of distinct vertices lying on their planes, each edge listed
//     once with the two faces that share it, and Euler's V - E + F = 2.
#pragma once

#include "shapes3d.h"

#include <string>
#include <vector>

namespace unison {

/// The convex polyhedron of `pts` (4..kMaxHullPoints finite points, in the body frame). An empty string on
/// success, else why not (and *out untouched).
std::string buildPolyhedron(const std::vector<Vec3>& pts, ConvexPolyhedron* out);

/// An empty string when `poly` is a consistent closed convex polyhedron of at most kMaxHullPoints vertices (see the
/// invariants above; plane tolerances scale with the largest coordinate), else the first problem found.
std::string checkPolyhedron(const ConvexPolyhedron& poly);

/// The pieces of the definition, shared by buildPolyhedron and the brute-force reference of tests/test_hull3d.cpp.
namespace hull_detail {

/// The definition's tolerances: a point is above a plane when it is more than eps above it, on a face within 10 eps.
struct Tolerance {
    double scale = 0.0;  ///< largest |coordinate| (m)
    double eps = 0.0;    ///< 1e-9 max(scale, 1e-3) (m)
};
/// The tolerances of a point set.
Tolerance toleranceOf(const std::vector<Vec3>& pts);
/// The face triple (i, j, k) spans: the unit normal of (pj - pi) x (pk - pi) turned outward and its offset. False
/// when the triple spans none (degenerate, points on both sides, or every point on its plane).
bool tripleFace(const std::vector<Vec3>& pts, int i, int j, int k, const Tolerance& tol, ConvexPolyhedron::Face* out);
/// Appends `face` unless a face with the same plane (normals within 1e-7, offsets within 10 eps) is already there.
void mergeFace(std::vector<ConvexPolyhedron::Face>& faces, const ConvexPolyhedron::Face& face, const Tolerance& tol);
/// Vertices (points on three or more face planes), counter-clockwise loops, edges and centroid from the faces.
std::string finishPolyhedron(const std::vector<Vec3>& pts, std::vector<ConvexPolyhedron::Face> faces,
                             const Tolerance& tol, ConvexPolyhedron* out);

}  // namespace hull_detail

}  // namespace unison
