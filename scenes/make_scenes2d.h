// scenes/make_scenes2d.h — generators of the shared 2D scenes, returned as scene JSON (README "Scene format").
//
// Owns: the layouts that tests, benchmarks and samples all run (the Box2D 2.4.1 testbed pyramid, many separate
// pyramids, a grid of falling circles in a container, a box stack, a restitution row, a box on a ramp). Returning
// JSON rather than a World2 lets the same scene be loaded by scenes::loadScene2 and by the Box2D peer of bench/,
// and written to a file for `unison run`.
//
// Invariants: every generator is a pure function of its arguments; no randomness, no libm transcendental (the ramp
// angle goes through dmath::sincos), so the JSON is bit-identical on every machine. Every scene has "dimension" 2,
// gravity (0, -10), "hz" 60 and "sleep": the `sleep` argument. Body 0 is the static ground (or container); the
// dynamic bodies follow in a documented order, and the last body is the one a test watches (the top box of a
// pyramid or stack, the box on the ramp).
#pragma once

#include <nlohmann/json.hpp>

namespace unison::scenes {

/// The Box2D 2.4.1 testbed "Pyramid": ground segment (-40, 0)-(40, 0); `rows` rows of boxes of half size `halfSize`
/// (density 5, friction 0.6, ground friction 0.6). Row 0 starts at (-7, 0.75); within a row each box is
/// (1.125, 0) further; each row starts (0.5625, 1.25) after the previous one; for halfSize != 0.5 the whole layout
/// is scaled by halfSize / 0.5. Boxes start 0.25 (scaled) apart, so the pile lands. Bodies: ground, then row by row
/// bottom-up, left to right; the last body is the top box. pyramidScene(20) reproduces scenes/pyramid20.json
/// (plus "sleep").
nlohmann::json pyramidScene(int rows, double halfSize = 0.5, bool sleep = true);

/// `count` separate testbed pyramids of `rows` rows (half size 0.5, same start height 0.75 and spacing as
/// pyramidScene) side by side on one ground segment reaching 10 m beyond them, their bases 2.125 m apart (far
/// enough that a settling pyramid never touches its neighbour), the row centred on x = 0. Bodies: ground, then
/// pyramid by pyramid (left to right), each in pyramidScene's order.
nlohmann::json manyPyramidsScene(int count, int rows, bool sleep = true);

/// `count` circles of radius 0.25 (density 1, friction 0.6, restitution 0) in a grid above the floor of a static
/// container made of 3 segments (floor and two walls, one static body). The grid has ceil(sqrt(count)) columns
/// 0.75 m apart; rows are 0.75 m apart from y = 1, odd rows shifted right by 0.375 m so the pile does not form
/// unstable columns. The walls are 0.5 m beyond the outermost circles and reach 2 m above the top row.
nlohmann::json fallingCirclesScene(int count, bool sleep = true);

/// `count` circles of radius 0.25 (density 1, friction 0.6, restitution 0) dropped side by side onto one long
/// ground segment: circle i at x = i - (count - 1) / 2 (1 m apart, so neighbours never touch), from height
/// 1 + 0.25 (i mod 8), so they land over several steps. Every circle is its own island with one contact: the
/// "many small islands" case of the benchmark. Bodies: ground, then the circles left to right.
nlohmann::json scatteredCirclesScene(int count, bool sleep = true);

/// A vertical stack of `count` 1 m boxes (density 1, friction 0.6) on the ground segment, the bottom box resting
/// on it (centre y = 0.5) and 0.05 m gaps between boxes (centres 1.05 m apart). stackScene(10) reproduces
/// scenes/stack10.json (plus "sleep").
nlohmann::json stackScene(int count, bool sleep = true);

/// 7 circles of radius 0.5 (density 1, friction 0.6) at x = -6, -4, ..., 6, y = 5, restitution e = k/6 for
/// k = 0..6, dropped onto the ground segment; "restitution_threshold": 0 so small bounces still bounce (restitution
/// mixes as max, the ground has 0). Reproduces scenes/restitution_row.json (plus "sleep").
nlohmann::json restitutionRowScene(bool sleep = true);

/// A static ramp (a segment of length 10 from the origin up at `angleRad`, friction 1) next to the ground segment
/// (-40, 0)-(40, 0) (friction 1), both shapes of body 0, and one 1 m box (density 1) resting on the middle of the
/// ramp, rotated by `angleRad`. `mu` is the effective contact friction: friction mixes as sqrt(f1 f2), so the box
/// gets friction mu^2 and sqrt(mu^2 * 1) = mu (exactly, for a correctly rounded square root). In the Coulomb
/// model the box stays put when tan(angleRad) <= mu and slides otherwise.
nlohmann::json rampScene(double angleRad, double mu, bool sleep = true);

}  // namespace unison::scenes
