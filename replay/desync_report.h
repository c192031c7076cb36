// replay/desync_report.h — desync reports as JSON files: the report of two states of one tick that should be
// equal (from two peers of a networked match, or a recording and its replay), and writing a report to a file.
//
// The JSON has the shape of `unison verify`'s report (recording.h reportToJson), so one reader (the replay
// viewer, `unison view --report`) understands both: {"status": "desync", "first_desync_tick",
// "compared_snapshot_tick", "differing_fields", "differences": [{"body", "body_number", "field", <nameA>,
// <nameB>}]}, values with 17 significant digits.
#pragma once

#include "state_io.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace unison::replay {

/// Diffs two full snapshots (World2/World3::snapshot()) of tick `tick` field by field and returns the report
/// above; `bodyNumber` maps a body id to its number in the match (-1: none). Throws ReplayError for a rejected
/// snapshot.
nlohmann::json snapshotDesyncReport(int tick, const std::vector<std::uint8_t>& snapshotA,
                                    const std::vector<std::uint8_t>& snapshotB, const std::string& nameA,
                                    const std::string& nameB, const std::function<int(BodyId)>& bodyNumber,
                                    std::size_t limit);

/// One line for a person: "desync at tick 42: body 3:1 (number 2) velocity.x peer_0 0.1 peer_2 0.10000000000000002"
/// (the first listed difference), or "no desync".
std::string desyncSummary(const nlohmann::json& report);

/// Writes a JSON document (indented) to `path` atomically. Throws ReplayError.
void writeJsonFile(const std::string& path, const nlohmann::json& document);

}  // namespace unison::replay
