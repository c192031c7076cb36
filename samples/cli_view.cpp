// samples/cli_view.cpp — `unison view RECORDING -o PAGE.html [--report REPORT.json]`: replays a recording, captures
// what the viewer draws (view_capture.h) and writes the self-contained viewer page (view_page.h).
#include "cli.h"
#include "recording.h"
#include "snapshot_file.h"
#include "view_page.h"

#include <ostream>

namespace unison::cli {

int viewCommand(const std::string& recordingFile, const std::string& outFile, const std::string& reportFile,
                std::ostream& out) {
    const replay::Recording rec = replay::parseRecording(replay::readBinaryFile(recordingFile), recordingFile);
    nlohmann::json report;
    if (!reportFile.empty()) {
        report = parseJson(readFile(reportFile), reportFile);
        if (!report.is_object() || !report.contains("status"))
            throw InputError(reportFile + ": not a desync report (no \"status\")");
        if (report["status"] == "desync" && !report.value("first_desync_tick", nlohmann::json()).is_number_integer())
            throw InputError(reportFile + ": a desync report needs an integer \"first_desync_tick\"");
    }
    const view::Capture capture = view::captureRecording(rec);
    const std::size_t slash = recordingFile.find_last_of('/');
    const std::string page =
        view::renderPage(capture, report, slash == std::string::npos ? recordingFile : recordingFile.substr(slash + 1));
    replay::writeFileAtomic(outFile, std::vector<std::uint8_t>(page.begin(), page.end()));
    std::size_t mismatches = 0;
    for (std::size_t t = 0; t < capture.hashes.size(); ++t) mismatches += capture.hashes[t] != capture.recordedHashes[t];
    out << nlohmann::json{{"ticks", capture.ticks},
                          {"bodies", capture.bodyCount},
                          {"contacts", capture.contactStart.back()},
                          {"ticks_differing_from_recording", mismatches},
                          {"bytes", page.size()}}
               .dump()
        << "\n";
    return 0;
}

}  // namespace unison::cli
