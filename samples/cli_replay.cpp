// samples/cli_replay.cpp — `unison record`, `unison verify` and `unison diff` (docs/replay.md): thin wrappers that
// read files, call replay/, print JSON and choose the exit code.
#include "cli.h"
#include "desync_report.h"
#include "recording.h"
#include "snapshot_file.h"

#include <ostream>

namespace unison::cli {

namespace {
constexpr std::size_t kReportedDifferences = 50;  // a report lists at most this many fields (the count is exact)
constexpr std::size_t kFileDifferences = 1000;     // ... and a report file this many

replay::InputScript readInputs(const std::string& file, const nlohmann::json& scene) {
    const int dimension = replay::sceneDimension(scene);
    if (file.empty()) return replay::InputScript{dimension, {}};
    return replay::parseInputs(parseJson(readFile(file), file), file, dimension);
}
}  // namespace

int recordCommand(const std::string& sceneFile, const std::string& inputsFile, int steps, int snapshotEvery,
                  const std::string& outFile, std::ostream& out) {
    const nlohmann::json scene = parseJson(readFile(sceneFile), sceneFile);
    const std::size_t slash = sceneFile.find_last_of('/');
    const std::string baseDir = slash == std::string::npos ? "." : sceneFile.substr(0, slash);
    const replay::Recording rec = replay::record(scene, readInputs(inputsFile, scene), steps, snapshotEvery, baseDir);
    const std::vector<std::uint8_t> bytes = replay::serializeRecording(rec);
    replay::writeFileAtomic(outFile, bytes);
    out << nlohmann::json{{"steps", rec.steps},
                          {"final_hash", replay::hexHash(rec.hashes.back())},
                          {"inputs", rec.inputs.actions.size()},
                          {"snapshots", rec.snapshots.size()},
                          {"bytes", bytes.size()}}
               .dump()
        << "\n";
    return 0;
}

int verifyCommand(const std::string& recordingFile, const std::string& inputsFile, bool keepGoing, std::ostream& out,
                  std::ostream& err, const std::string& reportFile) {
    replay::Recording rec = replay::parseRecording(replay::readBinaryFile(recordingFile), recordingFile);
    if (!inputsFile.empty()) rec.inputs = readInputs(inputsFile, rec.scene);
    const replay::VerifyReport report = replay::verify(rec, keepGoing);
    out << replay::reportToJson(report, kReportedDifferences).dump() << "\n";
    if (!reportFile.empty()) replay::writeJsonFile(reportFile, replay::reportToJson(report, kFileDifferences));
    if (report.match) return 0;
    err << replay::reportSummary(report) << "\n";
    return 1;
}

int diffCommand(const std::string& fileA, const std::string& fileB, std::ostream& out) {
    const std::vector<FieldDifference> diffs =
        replay::diffSnapshots(replay::readBinaryFile(fileA), replay::readBinaryFile(fileB), fileA, fileB);
    out << nlohmann::json{{"equal", diffs.empty()},
                          {"differing_fields", diffs.size()},
                          {"differences", replay::differencesToJson(diffs, "a", "b", kReportedDifferences)}}
               .dump()
        << "\n";
    return diffs.empty() ? 0 : 1;
}

}  // namespace unison::cli
