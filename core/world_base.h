// core/world_base.h — what the 2D and 3D worlds share, written once: their state (settings, body store, the shared
// step, the last step's contact points, step count, fault), the body operations that differ only in the dimension's
// vector types (destroy, velocity, impulse, gravity), the step itself and the state entry points (hash, snapshot,
// restore, named fields, rollback states).
//
// World2 and World3 derive from WorldBase<World2, Dim2, ...> and WorldBase<World3, Dim3, ...> and add their
// geometry: shapes, body creation (mass properties), narrowphase and queries. A world provides, privately (the base
// is its friend):
//   struct Hooks                 what core/world_step.h needs of it, constructed from the world;
//   contactPoint(c)              the public contact point of a step contact;
//   beforeStep()                 work of its own before each step (3D: clears the captured candidates);
//   findFault()                  the fault() message of the current state (core/step_support.h stepFault);
//   worldInvInertia(hot, cold)   the world-frame inverse inertia (static);
//   transferState(io, world)     the one canonical walk over its state (static template; its state file);
//   kSnapshotKind, CompactFields the snapshot container's kind and the doubles a tick can change;
//   keepOnRestore(fresh)         what a restore keeps of the live object that is not state (3D: capture switch).
// Member definitions are in world_base_step.h (step and body operations, instantiated in the world's .cpp) and
// world_base_state.h (state entry points, instantiated in the world's state file), so that Hooks and
// transferState stay private to those files.
#pragma once

#include <unison/types.h>

#include "body_store.h"
#include "input_policy.h"
#include "scene_index.h"
#include "state_io.h"
#include "task_system.h"
#include "world_step.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace unison {

class CompactState;

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
class WorldBase {
public:
    using Vec = typename D::Vec;
    using Ang = typename D::Ang;

    explicit WorldBase(const Def& def) : mDef(def) {}

    /// Removes a body and its warm-start entries; false for a stale or null id. Its contacts end (end events next
    /// step).
    bool destroyBody(BodyId id);

    /// Advances by one step of 1/hz seconds within def().stepBudget. A world whose state is no longer finite
    /// (fault()) does not step.
    void step() { step(mDef.stepBudget); }
    /// Advances by one step with `budget` work units (0 = unlimited) instead of def().stepBudget, for this call only
    /// (not recorded in the state: a replay steps with def().stepBudget).
    void step(std::uint64_t budget);
    /// Sets def().stepBudget (work units, 0 = unlimited).
    void setStepBudget(std::uint64_t budget) { mDef.stepBudget = budget; }
    /// Sets the threads of the next steps: def().workerCount and the job-system callbacks (none: the built-in pool).
    /// False (and nothing changes) for workerCount < 1 or only one of the two callbacks.
    bool setTaskSystem(const TaskSystem& tasks) { return setTaskFields(mDef, tasks); }
    /// Empty while every number of the state is finite. When a step overflows (a body flung to infinity), the
    /// message names the step, the body and the field, and step() does nothing until restore() replaces the state.
    const std::string& fault() const { return mFault; }

    int bodyCount() const { return mBodies.size(); }
    bool valid(BodyId id) const { return mBodies.valid(id); }
    /// Body state; nullptr for an invalid id.
    const Hot* state(BodyId id) const { return mBodies.findHot(id); }
    /// Body data that the solver does not write (type, mass, shapes, sleep); nullptr for an invalid id.
    const Cold* info(BodyId id) const { return mBodies.findCold(id); }
    /// Body ids in dense order (the order every loop of the step uses).
    std::vector<BodyId> bodyIds() const { return mBodies.ids(); }

    /// Sets the velocity of a body (m/s, rad/s) and wakes it. False (nothing changes) for an invalid id, a static
    /// body or a velocity outside core/input_policy.h's ranges.
    bool setVelocity(BodyId id, const Vec& linear, const Ang& angular);
    /// Applies an impulse (N s) at a world point (m) to a dynamic body and wakes it. False (nothing changes) for an
    /// invalid id, a body that is not dynamic, a non-finite point or an impulse outside the policy's range.
    bool applyImpulse(BodyId id, const Vec& impulse, const Vec& worldPoint);
    /// Sets gravity (m/s^2); false (nothing changes) outside the policy's range.
    bool setGravity(const Vec& g) {
        if (!D::componentsWithin(g, policy::kMaxGravity)) return false;
        mDef.gravity = g;
        return true;
    }
    const Def& def() const { return mDef; }

    const std::vector<ContactPoint>& contacts() const { return mContactPoints; }
    /// Pairs of bodies that started touching with overlap during the last step, sorted.
    const std::vector<TouchEvent>& beginEvents() const { return mStep.beginEvents(); }
    /// Pairs of bodies that stopped touching during the last step, sorted.
    const std::vector<TouchEvent>& endEvents() const { return mStep.endEvents(); }
    /// What the last step did (core/world_step.h).
    const StepStats& stats() const { return mStep.stats(); }
    std::uint64_t stepCount() const { return mStepCount; }

    /// 64-bit hash (XXH3) of the canonical serialisation of everything that affects the future: settings, step
    /// count, body store (slots, generations, free list, dense order, transforms, velocities, mass properties,
    /// shapes, sleep state and timers), warm-start cache and touching pairs. It is the hash of snapshot()'s payload.
    std::uint64_t stateHash() const;
    /// The whole state in the versioned snapshot container of core/state_io.h. restore() of it into any world of
    /// the same dimension (of any build with the same result-affecting flags) continues bit-identically.
    std::vector<std::uint8_t> snapshot() const;
    /// Replaces this world's state with a snapshot. The data is parsed and checked into a fresh world first; on any
    /// problem (truncated, corrupt, the other dimension, other build flags, inconsistent ids or values) it returns
    /// false with a reason in *error and this world is untouched. The last step's contacts, events and statistics
    /// are not state: they are empty after a restore until the next step.
    bool restore(const std::uint8_t* data, std::size_t size, std::string* error = nullptr);
    /// The canonical state as named fields (same order and values as the hash), for diffs and desync reports.
    std::vector<StateField> stateFields() const;
    /// Rollback state: only what a tick can change (core/compact_state.h), into `out` (its memory is reused).
    void saveCompact(CompactState& out) const;
    /// Restores a saveCompact() of this world while it holds the same bodies; false with *error (world untouched)
    /// otherwise. The last step's contacts, events and statistics stay those of the last step() call.
    bool restoreCompact(const std::uint8_t* data, std::size_t size, std::string* error = nullptr);

protected:
    /// Adds a checked body record (the derived world's createBody() has computed its mass properties); the null id
    /// and a message when the store is full.
    BodyId addBody(const Hot& hot, const Cold& cold, std::string* error);

    Derived& self() { return static_cast<Derived&>(*this); }
    const Derived& self() const { return static_cast<const Derived&>(*this); }

    Def mDef;
    BodyStore<Hot, Cold> mBodies;
    WorldStep<D> mStep;  // the warm-start cache and touching pairs (state), the step's scratch and outputs
    std::vector<ContactPoint> mContactPoints;
    std::uint64_t mStepCount = 0;
    std::string mFault;  // see fault(); not state (a state that is not finite cannot be snapshotted)
    std::unique_ptr<SceneIndex<D::kDim>> mIndex = std::make_unique<SceneIndex<D::kDim>>();  // derived, never hashed
};

}  // namespace unison
