// api/api_common.h — what the C++ API's files share: the start-up checks of a world, failures with a message, and
// the public step counts.
//
// Invariants: a public call either succeeds or leaves the engine's world untouched; every check of an argument
// happens before the first change.
#pragma once

#include <unison/types.h>

#include "fp_env.h"
#include "world_step.h"

#include <cmath>
#include <string>
#include <vector>

namespace unison::api {

/// Throws Error when the floating-point environment would make results differ between machines, or when the
/// step rate is not a finite positive number.
inline void checkWorldSettings(double hz) {
    const std::string problems = checkFloatingPointEnvironment();
    if (!problems.empty())
        throw Error("unison: the floating-point environment is unfit for deterministic simulation (results would "
                    "differ between machines):\n" + problems);
    if (!(std::isfinite(hz) && hz > 0.0)) throw Error("unison: hz must be a finite number > 0");
}

/// Stores a message for the caller when it asked for one; returns `result` (for one-line failure returns).
template <class T>
T fail(std::string* error, const std::string& message, T result) {
    if (error) *error = message;
    return result;
}

/// The public counts of the last step.
inline StepInfo toStepInfo(const StepStats& s) {
    StepInfo info;
    info.islands = s.islands;
    info.awakeIslands = s.awakeIslands;
    info.contacts = s.contacts;
    info.pivots = s.pivots;
    info.work = s.work;
    info.failedIslands = s.failedIslands;
    info.unsolvedIslands = s.unsolvedIslands;
    info.maxPenetration = s.maxPenetration;
    return info;
}

}  // namespace unison::api
