// scenes/make_scenes3d.h — generators of the shared 3D scenes, returned as scene JSON (docs/formats.md).
//
// Owns: the layouts that tests, bench_world3d (Unison and Bullet 3.24 side by side) and samples run: a box stack,
// a box pile, a row of bouncing spheres, a box on a ramp, the bunnies on two ramps. JSON lets the same scene be
// loaded by scenes::loadScene3 and by bench/bullet_peer, and written to a file for `unison run`.
//
// Invariants: pure functions of their arguments (no randomness, no libm transcendental: angles go through
// dmath::sincos). Every scene has "dimension" 3, gravity (0, -10, 0) (y up), "hz" 60 and "sleep": the `sleep`
// argument. Body 0 is the static ground (a plane y = 0 with friction 0.6), dynamic bodies follow in a documented
// order.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace unison::scenes {

/// A vertical stack of `count` 1 m cubes (density 1, friction 0.6) on the ground, bottom centre at y = 0.5, 0.05 m
/// gaps between cubes (centres 1.05 m apart). Bodies: ground, then bottom to top.
nlohmann::json boxStack3Scene(int count, bool sleep = true);

/// `count` cubes of 0.5 m (density 1, friction 0.6) dropped in layers of 5 x 5 onto the ground inside a static
/// 4-wall pen (boxes, friction 0.6) 3.6 m wide inside: cubes 0.65 m apart in x and z from -1.3, layers 0.75 m apart
/// from y = 0.4, odd layers shifted by 0.1 m in x and z, every cube turned about y by 0.1 rad times its layer.
/// tumble = false: the cubes land flat and form 25 separate columns (25 small islands). tumble = true: every cube is
/// also tilted 0.3 rad about x, lands on an edge and topples, and the cubes form one heap (one island of ~800
/// contacts). Nothing overlaps at the start. Bodies: ground, pen (one static body of 4 boxes), then the cubes layer
/// by layer (x fastest, then z).
nlohmann::json boxPile3Scene(int count, bool tumble, bool sleep = true);

/// `count` cubes of 0.5 m (density 1, friction 0.6) dropped from several metres into the pen of boxPile3Scene, each
/// tilted so that it lands on a corner (or, for a few, near an edge): layers of 5 x 5 cubes 0.65 m apart in x and z
/// from -1.3 (odd layers shifted by 0.1 m in x and z), layer L centred at y = 0.4 + 2 L (4 layers: up to 6.4 m);
/// cube i is turned by 0.3 rad about the horizontal axis (cos a_i, 0, sin a_i), a_i = 0.7 + 1.1 i rad. No yaw, so a
/// cube reaches at most 0.313 m from its centre in x and z (0.343 m in y) and nothing overlaps at the start. The
/// cubes form one heap (one island) once they have landed. Bodies: ground, pen, then the cubes layer by layer
/// (x fastest, then z).
nlohmann::json dropHeap3Scene(int count, bool sleep = true);

/// 5 spheres of radius 0.5 (density 1, friction 0.6) at x = -4, -2, ..., 4, bottom 4 m above the ground
/// (centre y = 4.5), with restitution e = k/4 for k = 0..4 (the ground has 0; mixing takes the max);
/// "restitution_threshold": 0.
nlohmann::json spheres3Scene(bool sleep = true);

/// A static ramp (a box 20 x 1 x 10 m turned by angleRad about z, top surface through (0, 4, 0), friction 1)
/// and a 0.5 m cube (density 1, friction mu^2 so the mixed coefficient is mu) resting on its middle, turned with it.
nlohmann::json ramp3Scene(double angleRad, double mu, bool sleep = true);

/// The paper's figs. 4-5: two ramps (static boxes tilted by +-0.35 rad about z, one above and to the left of the
/// other) over the ground, and `bunnies` copies of the mesh `objPath` (scaled by `scale`, density 1, friction 0.5)
/// dropped above the upper ramp, each turned a little differently about y. The program reads `objPath` here and
/// the scene carries the scaled mesh inline (vertices and triangles), so loading it opens no file.
nlohmann::json bunnies3Scene(const std::string& objPath, double scale, int bunnies, bool sleep = true);

}  // namespace unison::scenes
