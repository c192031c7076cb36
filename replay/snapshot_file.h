// replay/snapshot_file.h — snapshot files (.usnap) and their diff.
//
// Owns: atomic file writing (a temporary file in the same folder, flushed to disk, then renamed over the target, so
// a reader sees the old file or the new one, never half of one), reading whole binary files, and the field-level
// diff of two snapshots. The bytes of a .usnap file are exactly World2::snapshot() or World3::snapshot()
// (core/state_io.h container; its world kind says which).
#pragma once

#include "inputs.h"
#include "state_io.h"

#include <cstdint>
#include <string>
#include <vector>

namespace unison::replay {

/// Writes `bytes` to `path` atomically. Throws ReplayError (the target is untouched then).
void writeFileAtomic(const std::string& path, const std::vector<std::uint8_t>& bytes);
/// Reads a whole file of at most policy::kMaxBinaryBytes. Throws ReplayError.
std::vector<std::uint8_t> readBinaryFile(const std::string& path);

/// Restores a snapshot into `world`; a rejected snapshot throws ReplayError naming `what` and leaves world untouched.
void restoreOrThrow(World2& world, const std::vector<std::uint8_t>& bytes, const std::string& what);
void restoreOrThrow(World3& world, const std::vector<std::uint8_t>& bytes, const std::string& what);

/// The fields that differ between two snapshots of the same dimension (each restored into a fresh world, 2D or 3D
/// by the container's world kind). Throws ReplayError (also for a 2D and a 3D snapshot).
std::vector<FieldDifference> diffSnapshots(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                                           const std::string& whatA, const std::string& whatB);

/// JSON of a difference list: [{"body", "field", "a", "b"}] ("body" is "world" for world-level fields).
nlohmann::json differencesToJson(const std::vector<FieldDifference>& diffs, const char* nameA, const char* nameB,
                                 std::size_t limit);

}  // namespace unison::replay
