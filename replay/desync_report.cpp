// replay/desync_report.cpp — desync reports of two snapshots, their summary line, and report files.
#include "desync_report.h"

#include "snapshot_file.h"

namespace unison::replay {

nlohmann::json snapshotDesyncReport(int tick, const std::vector<std::uint8_t>& snapshotA,
                                    const std::vector<std::uint8_t>& snapshotB, const std::string& nameA,
                                    const std::string& nameB, const std::function<int(BodyId)>& bodyNumber,
                                    std::size_t limit) {
    const std::vector<FieldDifference> diffs = diffSnapshots(snapshotA, snapshotB, nameA, nameB);
    nlohmann::json report = {{"status", diffs.empty() ? "match" : "desync"},
                             {"first_desync_tick", tick},
                             {"compared_snapshot_tick", tick},
                             {"differing_fields", diffs.size()}};
    nlohmann::json list = differencesToJson(diffs, nameA.c_str(), nameB.c_str(), limit);
    for (std::size_t i = 0; i < list.size(); ++i) list[i]["body_number"] = bodyNumber ? bodyNumber(diffs[i].body) : -1;
    report["differences"] = list;
    return report;
}

std::string desyncSummary(const nlohmann::json& report) {
    if (report.value("status", "") != "desync") return "no desync";
    std::string s = "desync at tick " + std::to_string(report.value("first_desync_tick", -1));
    const nlohmann::json& diffs = report.value("differences", nlohmann::json::array());
    if (diffs.empty()) return s + "; no field-level difference available";
    const nlohmann::json& d = diffs.front();
    s += ": " + d.value("body", std::string("?"));
    if (d.value("body_number", -1) >= 0) s += " (number " + std::to_string(d.value("body_number", -1)) + ")";
    s += " " + d.value("field", std::string("?"));
    for (const auto& [key, value] : d.items()) {
        if (key == "body" || key == "body_number" || key == "field") continue;
        s += " " + key + " " + (value.is_string() ? value.get<std::string>() : value.dump());
    }
    const std::size_t count = report.value("differing_fields", std::size_t(0));
    if (count > 1) s += " (" + std::to_string(count) + " fields differ)";
    return s;
}

void writeJsonFile(const std::string& path, const nlohmann::json& document) {
    const std::string text = document.dump(2) + "\n";
    writeFileAtomic(path, std::vector<std::uint8_t>(text.begin(), text.end()));
}

}  // namespace unison::replay
