// fuzz/fuzz_support.h — what every fuzz target shares: the input as text, the invariant check that turns a broken
// promise into a crash libFuzzer reports, and the snapshot round trip every accepted state must survive.
//
// The promise under test (docs/input-policy.md): a reader either builds something or throws jsonio::JsonError (exit
// code 2 for the tool); never a crash, an unbounded allocation, a hang, or NaN printed as null. A state a world
// accepts steps, snapshots and restores again to the same hash; a refused restore leaves the world's hash unchanged.
#pragma once

#include "json_fields.h"
#include "state_io.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace unison::fuzz {

/// The fuzzer's bytes as a string (JSON and LCP text targets).
inline std::string text(const std::uint8_t* data, std::size_t size) {
    return std::string(reinterpret_cast<const char*>(data), size);
}

/// Aborts (a finding) with a message when `ok` is false.
inline void require(bool ok, const char* what) {
    if (ok) return;
    std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
    std::abort();
}

/// A world that was accepted (loaded or restored): steps it `steps` times; unless a step faulted (a clear error, the
/// world stops), its snapshot must restore into a fresh world with the same hash, which must then step to the same
/// hash as the original.
template <class World>
void stepSnapshotRestore(World& world, int steps) {
    for (int i = 0; i < steps && world.fault().empty(); ++i) world.step();
    if (!world.fault().empty()) return;
    const std::vector<std::uint8_t> snap = world.snapshot();
    World back;
    std::string error;
    if (!back.restore(snap.data(), snap.size(), &error)) {
        std::fprintf(stderr, "restore of the world's own snapshot refused: %s\n", error.c_str());
        require(false, "a world's own snapshot restores");
    }
    require(back.stateHash() == world.stateHash(), "a restored world has the original's hash");
    world.step();
    back.step();
    require(back.fault() == world.fault(), "a restored world faults like the original");
    if (world.fault().empty()) require(back.stateHash() == world.stateHash(), "a restored world steps like the original");
}

}  // namespace unison::fuzz
