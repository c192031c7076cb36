// unison/types.h — value types shared by the 2D and 3D worlds: body handles, body kinds, touch events, references
// to one shape of a body, step counts, the per-step budget's units, the worker-thread interface, and the exception
// the C++ API throws when a world cannot be created.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace unison {

/// Handle of a body: slot + 1 and the slot's generation when the body was created. A zero index1 is the null id;
/// a destroyed body's id stays invalid even after its slot is reused (the generation differs).
struct BodyId {
    std::uint32_t index1 = 0;      ///< slot index + 1; 0 for the null id
    std::uint32_t generation = 0;  ///< generation of the slot at creation; a stale id has an older one

    /// True for the null id (index1 == 0).
    bool isNull() const { return index1 == 0; }
    /// The null id, returned when no body could be created.
    static BodyId null() { return BodyId{}; }
};

/// Handles are equal when slot and generation both match.
inline bool operator==(BodyId a, BodyId b) { return a.index1 == b.index1 && a.generation == b.generation; }
/// Negation of operator==.
inline bool operator!=(BodyId a, BodyId b) { return !(a == b); }

/// Static bodies never move; kinematic bodies move with their velocity and have infinite mass; dynamic bodies
/// respond to gravity, contacts and impulses.
enum class BodyType : std::uint8_t { staticBody, kinematicBody, dynamicBody };

/// Two bodies started (begin) or stopped (end) touching with overlap during the last step.
struct TouchEvent {
    BodyId a, b;  ///< a before b by (generation, slot)
};

/// One shape of one body: the answer of an overlap query.
struct ShapeRef {
    BodyId body;    ///< the body
    int shape = 0;  ///< index into the body's shapes, in the order they were given at creation
};

/// Counts of the last step (contacts, islands, solver work, budget); the same in 2D and 3D.
struct StepInfo {
    int islands = 0;                ///< islands of bodies joined by contacts
    int awakeIslands = 0;           ///< islands that were simulated (not asleep)
    int contacts = 0;               ///< contact points
    int pivots = 0;                 ///< Lemke pivots
    std::uint64_t work = 0;         ///< deterministic work units the step spent (collision, assembly, solves)
    std::uint64_t budget = 0;       ///< the step's budget in work units (0: unlimited)
    /// What no budget can cut (collision, bookkeeping, each awake island's minimum approximation); with a budget,
    /// work <= max(budget, minimumWork) + overrun.
    std::uint64_t minimumWork = 0;
    std::uint64_t overrun = 0;      ///< work of exact attempts beyond their share (the solver checks between pivots)
    int exactIslands = 0;           ///< islands with contacts whose LCP was solved exactly
    int activeSetIslands = 0;       ///< of which answered by the 2D active-set path (docs/solver.md), not Lemke
    int approximateIslands = 0;     ///< islands given the bounded approximation (by the budget, or a failed 3D solve)
    int failedIslands = 0;          ///< failed friction solves (then 2D: the frictionless LCP; 3D: the approximation)
    int unsolvedIslands = 0;        ///< islands that got no impulse at all
    double maxResidual = 0.0;       ///< largest complementarity residual of an exact answer the step applied
    double maxApproximateResidual = 0.0;  ///< largest residual of an approximate island's answer
    double maxPenetration = 0.0;    ///< deepest overlap among touching contacts (m)
};

/// Work units of `ms` milliseconds on the reference machine (a fixed constant, docs/budget.md), rounded down; 0 for
/// ms <= 0. Budgets are counted in work units, never timed, so every peer makes the same choices.
std::uint64_t workUnitsFromMilliseconds(double ms);

/// A task body: processes items [begin, end) on worker `worker` (0 <= worker < the world's workerCount).
using TaskCallback = void(int begin, int end, int worker, void* taskContext);
/// Starts `task` over `itemCount` items in ranges of at least `minRange` items on the embedding job system. Returns
/// a handle for FinishTaskCallback, or nullptr when the task already ran to completion before returning.
using EnqueueTaskCallback = void*(TaskCallback* task, int itemCount, int minRange, void* taskContext,
                                  void* userContext);
/// Waits until the task of `userTask` (never nullptr) has processed every item.
using FinishTaskCallback = void(void* userTask, void* userContext);

/// The threads of one world: the callbacks of an embedding job system, or none (the built-in std::thread pool).
/// Not state: results are the same bits for any worker count and any job system.
struct TaskSystem {
    int workerCount = 1;                        ///< threads the step may use, >= 1 (1: everything on the caller)
    EnqueueTaskCallback* enqueueTask = nullptr; ///< nullptr: the built-in pool
    FinishTaskCallback* finishTask = nullptr;   ///< must be set with enqueueTask
    void* userContext = nullptr;                ///< passed to both callbacks
};

/// Thrown by the constructors of World2D and World3D: invalid settings, or a floating-point environment in which
/// results would not be bit-identical (flush-to-zero, another rounding mode, excess precision).
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace unison
