// resolver2d/world2d_checks.h — what a 2D world accepts (internal to resolver2d/): the input policy of
// core/input_policy.h for new bodies, and the consistency of body records restored from a snapshot.
//
// Invariants: createBody() and restore() accept the same shapes (a world's own snapshot always restores); a
// restored body record is one createBody() and the step could have produced (mass and inertia signs and inverses,
// unit rotation, a convex counter-clockwise polygon with outward unit normals).
#pragma once

#include "world2d.h"

#include <string>
#include <vector>

namespace unison {

/// Why a shape breaks the policy (sizes, coordinates, materials, polygon consistency), or empty.
std::string checkShape2(const Shape2& shape);
/// Why a new body breaks the policy (position, angle, velocities, shape count, each shape), or empty.
std::string checkBodyDef2(const BodyDef2& def, const std::vector<Shape2>& shapes);
/// Why a body's motion is outside the state range of core/input_policy.h (not finite, |position| > 1e9 m,
/// |velocity| > 1e9), or empty: the check after every step and on restore.
std::string checkMotion2(const BodyState2& state);
/// Why a restored body record is inconsistent (rotation not unit; mass, inertia or their inverses not those of its
/// type; shapes), or empty.
std::string checkBodyRecord2(const BodyState2& state, const BodyInfo2& info);

}  // namespace unison
