// scenes/make_scenes2d.h — generators of the shared 2D scenes, returned as scene JSON (docs/formats.md).
//
// Owns: the layouts that tests, benchmarks and samples all run (the Box2D 2.4.1 testbed pyramid, many separate
// pyramids, a grid of falling circles in a container, a box stack, a restitution row, a box on a ramp), and the
// layouts of Box2D v3's public benchmarks and stacking samples (large pyramid, many pyramids, card house, arch,
// vertical stack, double domino), rebuilt from their published positions and sizes. Returning
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

// ---- Box2D v3's benchmark and stacking-sample layouts ---------------------------------------------------------
// Box2D v3 defaults where its layout does not say otherwise: density 1, friction 0.6, restitution 0. Its rounded
// boxes become plain boxes of the same outer size (Unison has no rounded polygons). Sleep is the `sleep` argument
// (Box2D v3's benchmarks run with sleep off).

/// Box2D v3's "large pyramid" benchmark: a static box ground (half extents (100, 1), centre (0, -1), top at y = 0)
/// and `baseCount` rows of 1 m boxes (half size 0.5) touching side by side and stacked with no gap: row i (from
/// 0 at the bottom) holds baseCount - i boxes with centres y = i + 0.5 and x = (i + 1) / 2 + (j - i) -
/// baseCount / 2 for j = i .. baseCount - 1. Every coordinate is a multiple of 0.5 (exact). Bodies: ground, then
/// row by row bottom-up, left to right; the last body is the top box, centred at (0, baseCount - 0.5).
/// 40 rows: 820 boxes; 100 rows: 5050 boxes.
nlohmann::json largePyramidScene(int baseCount, bool sleep = false);

/// Box2D v3's "many pyramids" benchmark: `rowCount` x `columnCount` pyramids of base `baseCount` (1 m boxes as in
/// largePyramidScene), each row of pyramids on its own ground segment, g = baseCount + 1 m above the previous one:
/// segments at y = g r (r = 0 .. rowCount - 1) from x = -W/2 to W/2 with W = g columnCount, all shapes of one
/// static body. Pyramid (r, c) has its first box centred at x = -W/2 + g c + 1, y = g r + 0.5 (boxes touching, no
/// gaps). Bodies: ground, then pyramids row by row (bottom segment first), left to right, each bottom-up; the last
/// body is the top box of the last pyramid. 5 x 5 of base 10: 1375 boxes; 20 x 20: 22000.
nlohmann::json pyramidGridScene(int rowCount, int columnCount, int baseCount = 10, bool sleep = false);

/// Box2D v3's "card house" sample: a static box ground (half extents (40, 2), centre (0, -2)), and `levels` levels
/// of cards 0.4 m long and 2 mm thick (half extents (0.001, 0.2), density 1, friction 0.7 as the ground): level L
/// (0 at the bottom) has Nb = levels - L pairs of cards leaning on each other at -25 and +25 degrees (centres at
/// y_L = 0.18 + 0.37 L, x = z and z + 0.175, z = 0.175 (L + 2 i)), and a flat card (turned 90 degrees, centre
/// (z + 0.25, y_L + 0.185)) on each pair but the last. As in the sample, a pair's tops start 6 mm apart and a flat
/// card 2 mm above the tops it rests on, the bottom cards reach 1.7 mm into the ground, and the flat cards of a
/// level (0.4 m long, 0.35 m apart) overlap their neighbours by 5 cm through their 2 mm thickness.
/// Bodies: ground, then level by level, for each pair: flat card (when there is one), left card, right card; the
/// last body is the right card of the top pair. 5 levels: 40 cards.
nlohmann::json cardHouseScene(int levels = 5, bool sleep = true);

/// Box2D v3's "arch" sample (scaled by 0.25 as in the sample): a ground segment (-100, 0)-(100, 0), 8 quadrilateral
/// stones up each side and a keystone (convex polygons given in world coordinates, body origins at 0), friction 0.6,
/// all touching their neighbours exactly, and 4 boxes of half extents (2, 0.5) stacked on the keystone (no gaps).
/// Bodies: ground, the 8 right stones bottom-up, the 8 left stones bottom-up, the keystone, then the boxes
/// bottom-up; the last body is the top box. 21 dynamic bodies.
nlohmann::json archScene(bool sleep = true);

/// Box2D v3's "vertical stack" sample: a static ground body with a segment (-30, 0)-(30, 0) and a wall (10, 0)-(10,
/// 20); `columns` columns (x = 8 - 3 c) of `rows` 1 m boxes (Box2D's rounded 0.45 + 0.05 box; here a plain box of
/// half size 0.5) of friction 0.3, stacked with no gap (centres y = 0.5 + i), each box shifted by -0.01 (even i) or
/// +0.01 m (odd i) in x. Bodies: ground, then column by column, bottom-up; the last body is the top box of the last
/// column.
nlohmann::json verticalStackScene(int rows = 12, int columns = 1, bool sleep = true);

/// Box2D v3's "double domino" sample: a static box ground (half extents (100, 1), centre (0, -1)) and `count`
/// dominoes of half extents (0.125, 0.5) (mass 0.25 kg) standing 1 m apart from x = -count / 2, centre y = 0.5. The
/// first domino starts with the velocity of the sample's impulse (0.2, 0) N s at the point (x0, 1) (0.5 m above its
/// centre): v = (0.8, 0) m/s and w = -0.1 / I rad/s, I = m (0.25^2 + 1^2) / 12. Bodies: ground, then the dominoes
/// left to right.
nlohmann::json doubleDominoScene(int count = 15, bool sleep = true);

}  // namespace unison::scenes
