// resolver3d/world3d_checks.h — what a 3D world accepts (internal to resolver3d/): the input policy of
// core/input_policy.h for new bodies, and the consistency of body records restored from a snapshot.
//
// Invariants: createBody() and restore() accept the same shapes (a world's own snapshot always restores); a
// restored body record is one createBody() and the step could have produced: a box's polyhedron is exactly the one
// its half extents and centre make, a hull's passes checkPolyhedron (closed, convex, faces on their vertices), mass
// and inertia have the signs and inverses of the body's type, the rotation is a unit quaternion.
#pragma once

#include "world3d.h"

#include <string>
#include <vector>

namespace unison {

/// Why a shape breaks the policy or is inconsistent (sizes, coordinates, materials, polyhedron, mesh counts), or
/// empty.
std::string checkShape3(const Shape3& shape);
/// Why a new body breaks the policy (position, orientation, velocities, shape count, each shape), or empty.
std::string checkBodyDef3(const BodyDef3& def, const std::vector<Shape3>& shapes);
/// Why an inertia tensor (kg m^2) is not symmetric positive definite, or empty.
std::string checkInertia3(const Mat3& inertia);
/// Why invInertia is not inertia's inverse to 1e-6 (|I I^-1 - 1| entrywise), or empty: checked at creation and on
/// restore alike (an ill-conditioned tensor fails it even when it is positive definite).
std::string checkInverseInertia3(const Mat3& inertia, const Mat3& invInertia);
/// Why a body's motion is outside the state range of core/input_policy.h (not finite, |position| > 1e9 m,
/// |velocity| > 1e9), or empty: the check after every step and on restore.
std::string checkMotion3(const BodyState3& state);
/// Why a restored body record is inconsistent, or empty.
std::string checkBodyRecord3(const BodyState3& state, const BodyInfo3& info);

}  // namespace unison
