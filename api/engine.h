// api/engine.h — the engine's world behind a public one: api::Engine is what unison::World (unison/world.h) calls
// for the operations both dimensions share, and EngineOf<World2> / EngineOf<World3> implement it over the engine's
// worlds. World2D and World3D reach their engine world through engineWorld<W>() for the rest.
#pragma once

#include <unison/world.h>

#include "compact_state.h"
#include "world_step.h"

#include <cstdint>
#include <string>
#include <vector>

namespace unison::api {

struct Engine {
    virtual ~Engine() = default;
    virtual bool destroyBody(BodyId id) = 0;
    virtual bool valid(BodyId id) const = 0;
    virtual int bodyCount() const = 0;
    virtual std::vector<BodyId> bodyIds() const = 0;
    virtual void step() = 0;
    virtual void step(std::uint64_t budget) = 0;
    virtual void setStepBudget(std::uint64_t budget) = 0;
    virtual std::uint64_t stepBudget() const = 0;
    virtual bool setTaskSystem(const TaskSystem& tasks) = 0;
    virtual std::string fault() const = 0;
    virtual std::uint64_t stepCount() const = 0;
    virtual const StepStats& stats() const = 0;
    virtual const std::vector<TouchEvent>& beginEvents() const = 0;
    virtual const std::vector<TouchEvent>& endEvents() const = 0;
    virtual std::uint64_t stateHash() const = 0;
    virtual std::vector<std::uint8_t> snapshot() const = 0;
    virtual bool restore(const std::uint8_t* data, std::size_t size, std::string* error) = 0;
    virtual void saveCompact(CompactState& out) const = 0;
    virtual bool restoreCompact(const std::uint8_t* data, std::size_t size, std::string* error) = 0;

    CompactState compact;  // reused by World::saveCompact
};

/// An engine world (World2 or World3) as an Engine.
template <class W>
struct EngineOf final : Engine {
    template <class Def>
    explicit EngineOf(const Def& def) : world(def) {}

    bool destroyBody(BodyId id) override { return world.destroyBody(id); }
    bool valid(BodyId id) const override { return world.valid(id); }
    int bodyCount() const override { return world.bodyCount(); }
    std::vector<BodyId> bodyIds() const override { return world.bodyIds(); }
    void step() override { world.step(); }
    void step(std::uint64_t budget) override { world.step(budget); }
    void setStepBudget(std::uint64_t budget) override { world.setStepBudget(budget); }
    std::uint64_t stepBudget() const override { return world.def().stepBudget; }
    bool setTaskSystem(const TaskSystem& tasks) override { return world.setTaskSystem(tasks); }
    std::string fault() const override { return world.fault(); }
    std::uint64_t stepCount() const override { return world.stepCount(); }
    const StepStats& stats() const override { return world.stats(); }
    const std::vector<TouchEvent>& beginEvents() const override { return world.beginEvents(); }
    const std::vector<TouchEvent>& endEvents() const override { return world.endEvents(); }
    std::uint64_t stateHash() const override { return world.stateHash(); }
    std::vector<std::uint8_t> snapshot() const override { return world.snapshot(); }
    bool restore(const std::uint8_t* data, std::size_t size, std::string* error) override {
        return world.restore(data, size, error);
    }
    void saveCompact(CompactState& out) const override { world.saveCompact(out); }
    bool restoreCompact(const std::uint8_t* data, std::size_t size, std::string* error) override {
        return world.restoreCompact(data, size, error);
    }

    W world;
};

/// The engine world behind a public world whose engine is an EngineOf<W>.
template <class W>
W& engineWorld(Engine& engine) {
    return static_cast<EngineOf<W>&>(engine).world;
}

}  // namespace unison::api
