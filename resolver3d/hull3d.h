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

}  // namespace unison
