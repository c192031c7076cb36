// api/api_common.h — what the C++ API's files share: the start-up checks of a world, failures with a message, and
// the public step counts.
//
// Invariants: a public call either succeeds or leaves the engine's world untouched; every check of an argument
// happens before the first change.
#pragma once

#include <unison/types.h>

#include "fp_env.h"
#include "input_policy.h"
#include "task_system.h"
#include "world_step.h"

#include <cmath>
#include <string>
#include <vector>

namespace unison::api {

/// Throws Error when the floating-point environment would make results differ between machines, or when the
/// step rate is outside the input policy's range (docs/input-policy.md).
inline void checkWorldSettings(double hz) {
    const std::string problems = checkFloatingPointEnvironment();
    if (!problems.empty())
        throw Error("unison: the floating-point environment is unfit for deterministic simulation (results would "
                    "differ between machines):\n" + problems);
    if (!(hz >= policy::kMinHz && hz <= policy::kMaxHz)) throw Error("unison: hz must be in [1, 10000]");
}

/// True when every component of a public vector (Vec2D or Vec3D) is a gravity the input policy allows.
template <class V>
bool gravityInRange(const V& g) {
    bool ok = policy::within(g.x, policy::kMaxGravity) && policy::within(g.y, policy::kMaxGravity);
    if constexpr (sizeof(V) == 3 * sizeof(double)) ok = ok && policy::within(g.z, policy::kMaxGravity);
    return ok;
}

/// The engine's world settings for a public definition (WorldDef2D or WorldDef3D into WorldDef2 or WorldDef3),
/// after the checks both dimensions share; throws Error for invalid settings.
template <class EngineDef, class PublicDef, class ToEngine>
EngineDef engineDef(const PublicDef& def, ToEngine toEngine) {
    checkWorldSettings(def.hz);
    if (!gravityInRange(def.gravity)) throw Error("unison: gravity components must be finite and within 1e4 m/s^2");
    EngineDef engine;
    if (!setTaskFields(engine, def.tasks))
        throw Error("unison: tasks.workerCount must be >= 1, with both job-system callbacks or neither");
    engine.gravity = toEngine(def.gravity);
    engine.hz = def.hz;
    engine.enableSleep = def.enableSleep;
    engine.stepBudget = def.stepBudget;
    return engine;
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
    info.budget = s.budget;
    info.minimumWork = s.minimumWork;
    info.overrun = s.overrun;
    info.exactIslands = s.exactIslands;
    info.activeSetIslands = s.activeSetIslands;
    info.approximateIslands = s.approximateIslands;
    info.failedIslands = s.failedIslands;
    info.unsolvedIslands = s.unsolvedIslands;
    info.maxResidual = s.maxResidual;
    info.maxApproximateResidual = s.maxApproximateResidual;
    info.maxPenetration = s.maxPenetration;
    return info;
}

}  // namespace unison::api
