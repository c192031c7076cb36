// core/det_math.h — deterministic sine, cosine and arc tangent for the simulation.
//
// Owns: the only trigonometric functions the simulation may call (DESIGN.md "Determinism rules": no libm
// transcendental in the simulation). They are built from + - * / and exact operations (floor, fabs, signbit,
// ilogb, ldexp) only, so with IEEE-754 doubles, round-to-nearest, no flushed denormals, no FMA contraction and
// no excess precision (see core/fp_env.h) every machine and every optimisation level returns the same bits.
//
// Invariants and accuracy (measured against long-double libm in tests/test_det_math.cpp):
//   - sin(-x) == -sin(x) and cos(-x) == cos(x) bit for bit; sin(±0) = ±0; NaN or ±inf in gives NaN out.
//   - sin, cos: below 1 ulp for |x| <= kTrigAccurateLimit (about 1.6e6). Beyond that the argument reduction
//     loses bits: the absolute error grows like |x| * 2^-53 (no worse than the spacing of doubles near x), and
//     above 2^53 the answer is an arbitrary but deterministic value in [-1, 1].
//   - atan, atan2: below 1 ulp for every finite input; atan2 follows the IEEE/C99 conventions for signed zeros
//     and infinities (atan2(±0, -0) = ±pi, atan2(±inf, -inf) = ±3pi/4, ...).
#pragma once

namespace unison {
namespace dmath {

/// pi rounded to the nearest double.
constexpr double kPi = 3.141592653589793;

/// Largest |x| for which sin/cos keep their sub-ulp accuracy: 2^19 * pi (the reduction multiple stays < 2^20).
constexpr double kTrigAccurateLimit = 524288.0 * kPi;

/// Sine of x (radians).
double sin(double x);

/// Cosine of x (radians).
double cos(double x);

/// Sine and cosine of x with one argument reduction; bit-identical to sin(x) and cos(x).
void sincos(double x, double* outSin, double* outCos);

/// Arc tangent of x, in [-pi/2, pi/2].
double atan(double x);

/// Angle of the point (x, y) from the +x axis, in [-pi, pi]; same quadrant and signed-zero rules as C99 atan2.
double atan2(double y, double x);

}  // namespace dmath
}  // namespace unison
