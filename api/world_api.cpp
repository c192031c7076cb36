// api/world_api.cpp — unison::World (unison/world.h): what both public worlds do the same way, through api::Engine.
// Checks that are not the engine's (null data with a size) happen here, before the engine is called.
#include <unison/world.h>

#include "api_common.h"
#include "engine.h"

#include "step_budget.h"

#include <utility>

namespace unison {

std::uint64_t workUnitsFromMilliseconds(double ms) { return work::fromMilliseconds(ms); }

World::World(std::unique_ptr<api::Engine> engine) : mEngine(std::move(engine)) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

bool World::destroyBody(BodyId id) { return mEngine->destroyBody(id); }
bool World::isValid(BodyId id) const { return mEngine->valid(id); }
int World::bodyCount() const { return mEngine->bodyCount(); }
std::vector<BodyId> World::bodyIds() const { return mEngine->bodyIds(); }

void World::step() { mEngine->step(); }
void World::step(std::uint64_t budget) { mEngine->step(budget); }
void World::setStepBudget(std::uint64_t budget) { mEngine->setStepBudget(budget); }
std::uint64_t World::stepBudget() const { return mEngine->stepBudget(); }
bool World::setTaskSystem(const TaskSystem& tasks) { return mEngine->setTaskSystem(tasks); }
std::string World::fault() const { return mEngine->fault(); }
std::uint64_t World::stepCount() const { return mEngine->stepCount(); }
StepInfo World::stepInfo() const { return api::toStepInfo(mEngine->stats()); }
std::vector<TouchEvent> World::beginTouchEvents() const { return mEngine->beginEvents(); }
std::vector<TouchEvent> World::endTouchEvents() const { return mEngine->endEvents(); }

std::uint64_t World::stateHash() const { return mEngine->stateHash(); }
std::vector<std::uint8_t> World::snapshot() const { return mEngine->snapshot(); }

bool World::restore(const std::uint8_t* data, std::size_t size, std::string* error) {
    if (!data && size > 0) return api::fail(error, "snapshot: null data", false);
    return mEngine->restore(data, size, error);
}

void World::saveCompact(std::vector<std::uint8_t>& out) const {
    mEngine->saveCompact(mEngine->compact);
    out.assign(mEngine->compact.data(), mEngine->compact.data() + mEngine->compact.size());
}

bool World::restoreCompact(const std::uint8_t* data, std::size_t size, std::string* error) {
    if (!data && size > 0) return api::fail(error, "compact state: null data", false);
    return mEngine->restoreCompact(data, size, error);
}

}  // namespace unison
