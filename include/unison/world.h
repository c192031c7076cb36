// unison/world.h — what the 2D and 3D worlds of the C++ API share: bodies by id, the step, the last step's touch
// events and counts, the state hash, snapshots and rollback states. World2D (unison/world2d.h) and World3D
// (unison/world3d.h) add their bodies' geometry, state and queries.
//
// Guarantees: every result is the same bits on every machine for the same calls in the same order (builds with
// the documented flags, docs/determinism.md). A call with a bad argument fails and leaves the world unchanged.
// Calls on one world must not run concurrently, except const queries between steps.
#pragma once

#include <unison/types.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace unison {

namespace api {
struct Engine;  // the engine's world behind a public one (private to the library)
}  // namespace api

/// A world of either dimension. Not copyable; movable.
class World {
public:
    virtual ~World();
    World(World&&) noexcept;
    World& operator=(World&&) noexcept;

    /// Removes a body; false for a stale or null id. Its touches end (end events after the next step).
    bool destroyBody(BodyId id);
    /// True when id names a live body of this world.
    bool isValid(BodyId id) const;
    /// Number of live bodies.
    int bodyCount() const;
    /// Live bodies in the order the step visits them.
    std::vector<BodyId> bodyIds() const;

    /// Advances the world by 1/hz seconds within its step budget (stepBudget()). A world whose state stopped
    /// being finite does not step: see fault().
    void step();
    /// Advances by one step within `budget` work units for this call only (0 = unlimited). Not state: a recording
    /// replays with the world's own stepBudget(), so lockstep peers should use setStepBudget() instead.
    void step(std::uint64_t budget);
    /// Sets the per-step budget in work units (workUnitsFromMilliseconds(); 0 = unlimited). Part of the state:
    /// every peer must step with the same budget. Islands the budget cannot solve exactly get a bounded, flagged
    /// approximation (StepInfo::approximateIslands); the same on every peer.
    void setStepBudget(std::uint64_t budget);
    /// The per-step budget in work units (0 = unlimited).
    std::uint64_t stepBudget() const;
    /// Sets the threads of the next steps (the built-in pool, or the embedding job system's callbacks); results
    /// are the same bits for any of them. False (nothing changes) for workerCount < 1 or only one callback.
    bool setTaskSystem(const TaskSystem& tasks);
    /// Empty while every number of the state is finite; otherwise why step() stopped (the step, body and field,
    /// e.g. a body flung to infinity). restore() of a good state clears it.
    std::string fault() const;
    /// Steps taken since creation (restored with a snapshot).
    std::uint64_t stepCount() const;
    /// What the last step did.
    StepInfo stepInfo() const;
    /// Pairs of bodies that started touching during the last step, sorted.
    std::vector<TouchEvent> beginTouchEvents() const;
    /// Pairs of bodies that stopped touching during the last step, sorted.
    std::vector<TouchEvent> endTouchEvents() const;

    /// 64-bit hash of everything that affects the future (equal hashes: equal futures).
    std::uint64_t stateHash() const;
    /// The whole state as bytes; restore() of it into a world of the same dimension continues bit-identically.
    std::vector<std::uint8_t> snapshot() const;
    /// Replaces the state with a snapshot; false with a reason (world unchanged) for bad or foreign data. The last
    /// step's contacts, events and counts are not state: they are empty until the next step.
    bool restore(const std::uint8_t* data, std::size_t size, std::string* error = nullptr);
    /// Rollback state: only what a step can change, written into `out` (its memory is reused).
    void saveCompact(std::vector<std::uint8_t>& out) const;
    /// Restores saveCompact() bytes while the world holds the same bodies; false with a reason otherwise.
    bool restoreCompact(const std::uint8_t* data, std::size_t size, std::string* error = nullptr);

protected:
    explicit World(std::unique_ptr<api::Engine> engine);
    std::unique_ptr<api::Engine> mEngine;
};

}  // namespace unison
