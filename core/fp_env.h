// core/fp_env.h — start-up checks of the floating-point environment the deterministic simulation relies on.
//
// Owns: the run-time and compile-time checks behind DESIGN.md "Determinism rules": IEEE doubles evaluated at
// their own precision (FLT_EVAL_METHOD == 0, no -ffast-math), round-to-nearest, subnormals neither flushed to
// zero nor read as zero, and no fused multiply-add contraction in this translation unit (built with the same
// flags as the rest of the library). The checks only read the environment; they never change it.
// Invariant: an empty message from checkFloatingPointEnvironment() means every check passed.
#pragma once

#include <string>

namespace unison {

/// True when subnormal doubles survive arithmetic (no flush-to-zero, no denormals-are-zero).
bool denormalsPreserved();

/// Empty when the environment is fit for deterministic simulation, otherwise one line per problem found.
std::string checkFloatingPointEnvironment();

/// Throws std::runtime_error with the message of checkFloatingPointEnvironment() when it is not empty.
void requireDeterministicFloatingPoint();

}  // namespace unison
