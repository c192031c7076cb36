// api/replay_api.cpp — the public recording functions (unison/replay.h) over replay/recording.h. Every error of the
// replay module (ReplayError, with the file position or key) comes back as a message; nothing throws out.
#include <unison/replay.h>

#include "recording.h"

#include <exception>

namespace unison {

namespace {

replay::Recording parse(const std::uint8_t* data, std::size_t size) {
    if (!data && size > 0) throw replay::ReplayError("recording: null data");
    return replay::parseRecording(std::vector<std::uint8_t>(data, data + size), "recording");
}

template <class F, class T>
T guarded(std::string* error, T failed, F&& body) {
    try {
        return body();
    } catch (const std::exception& e) {
        if (error) *error = e.what();
        return failed;
    }
}

}  // namespace

std::vector<std::uint8_t> recordMatch(const std::string& sceneJson, const std::string& inputsJson, int steps,
                                      int snapshotEvery, std::string* error) {
    return guarded(error, std::vector<std::uint8_t>{}, [&] {
        const nlohmann::json scene = jsonio::parseJson(sceneJson, "scene");
        const int dimension = replay::sceneDimension(scene);
        replay::InputScript inputs;
        inputs.dimension = dimension;
        if (!inputsJson.empty()) inputs = replay::parseInputs(jsonio::parseJson(inputsJson, "inputs"), "inputs", dimension);
        return replay::serializeRecording(replay::record(scene, inputs, steps, snapshotEvery));
    });
}

bool verifyRecording(const std::uint8_t* data, std::size_t size, VerifyResult* out, std::string* error) {
    return guarded(error, false, [&] {
        const replay::VerifyReport report = replay::verify(parse(data, size));
        if (out) {
            out->match = report.match;
            out->ticks = report.ticks;
            out->firstDesyncTick = report.firstTick;
            out->recordedHash = report.recordedHash;
            out->replayedHash = report.replayedHash;
            out->differingFields = int(report.differences.size());
            out->summary = replay::reportSummary(report);
            out->reportJson = replay::reportToJson(report, 100).dump(2);
        }
        return true;
    });
}

bool recordingHashes(const std::uint8_t* data, std::size_t size, std::vector<std::uint64_t>* out, std::string* error) {
    return guarded(error, false, [&] {
        const replay::Recording rec = parse(data, size);
        if (out) *out = rec.hashes;
        return true;
    });
}

}  // namespace unison
