// core/world_base_state.h — WorldBase's state entry points (core/world_base.h): the state hash, snapshots, restore,
// named fields and rollback states, all over the derived world's one canonical walk, transferState(). Included by a
// world's state file, where they are explicitly instantiated next to that walk.
#pragma once

#include "compact_state.h"
#include "state_transfer.h"
#include "world_base.h"

#include <utility>

namespace unison {

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
std::uint64_t WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::stateHash() const {
    const std::vector<std::uint8_t> bytes =
        state_transfer::stateBytes([&](state_transfer::ByteSink& sink) { Derived::transferState(sink, self()); });
    return hash64(bytes.data(), bytes.size());
}

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
std::vector<std::uint8_t> WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::snapshot() const {
    return frameSnapshot(
        Derived::kSnapshotKind, std::uint64_t(mBodies.size()),
        state_transfer::stateBytes([&](state_transfer::ByteSink& sink) { Derived::transferState(sink, self()); }));
}

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
bool WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::restore(const std::uint8_t* data, std::size_t size,
                                                                 std::string* error) {
    Derived fresh;
    if (!state_transfer::readSnapshot(data, size, Derived::kSnapshotKind, fresh, error,
                                      [](state_transfer::ByteSource& source, Derived& w) { Derived::transferState(source, w); }))
        return false;
    self().keepOnRestore(fresh);
    state_transfer::keepExecution(mDef, fresh.mDef);
    fresh.mStep.takeScratch(mStep);
    self() = std::move(fresh);  // only now is the live world replaced
    return true;
}

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
std::vector<StateField> WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::stateFields() const {
    return state_transfer::namedFields([&](state_transfer::FieldSink& sink) { Derived::transferState(sink, self()); });
}

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
void WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::saveCompact(CompactState& out) const {
    unison::saveCompact<typename Derived::CompactFields>(out, mStepCount, mDef, mBodies, mStep.cache, mStep.touching);
}

template <class Derived, class D, class Def, class Hot, class Cold, class ContactPoint>
bool WorldBase<Derived, D, Def, Hot, Cold, ContactPoint>::restoreCompact(const std::uint8_t* data, std::size_t size,
                                                                        std::string* error) {
    mIndex->invalidate();
    if (!unison::restoreCompact<typename Derived::CompactFields>(data, size, mStepCount, mDef, mBodies, mStep.cache,
                                                                mStep.touching, error))
        return false;
    // A compact state is checked by its checksum only (it is this process's own rollback state); should its values
    // still be out of range, the world says so and does not step on them.
    mFault = self().findFault();
    return true;
}

}  // namespace unison
