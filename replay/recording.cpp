// replay/recording.cpp — record, the .urec format, verify and desync reports (see recording.h).
#include "recording.h"

#include "snapshot_file.h"

#include <cstdio>
#include <cstring>

namespace unison::replay {
namespace {

constexpr std::uint8_t kMagic[8] = {'U', 'N', 'I', 'S', 'R', 'E', 'C', 0};
constexpr std::uint32_t kRecordingFormatVersion = 1;

bool snapshotTick(int tick, int steps, int every) { return tick % every == 0 || tick == steps; }

}  // namespace

std::string hexHash(std::uint64_t h) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

namespace {

template <class World>
void recordWith(Recording& rec) {
    Session<World> session(rec.scene, "scene");
    rec.hashes.push_back(session.world().stateHash());
    rec.snapshots.push_back({0, session.world().snapshot()});
    for (int t = 1; t <= rec.steps; ++t) {
        session.tick(t, rec.inputs);
        rec.hashes.push_back(session.world().stateHash());
        if (snapshotTick(t, rec.steps, rec.snapshotEvery)) rec.snapshots.push_back({t, session.world().snapshot()});
    }
}

}  // namespace

Recording record(const nlohmann::json& scene, const InputScript& inputs, int steps, int snapshotEvery,
                 const std::string& baseDir) {
    if (steps < 0 || steps > policy::kMaxTick)
        throw ReplayError("record: steps must be in [0, " + std::to_string(policy::kMaxTick) + "]");
    if (snapshotEvery < 1) throw ReplayError("record: the snapshot interval must be >= 1");
    const int dimension = sceneDimension(scene);
    if (!inputs.actions.empty() && inputs.dimension != dimension)
        throw ReplayError("record: the inputs were read for a " + std::to_string(inputs.dimension) + "D scene, the scene is " +
                          std::to_string(dimension) + "D");
    Recording rec;
    // A 3D scene's mesh files are read now and stored in the recording, so verify needs no files.
    rec.scene = dimension == 3 ? scenes::inlineMeshFiles3(scene, "scene", baseDir) : scene;
    rec.inputs = inputs;
    rec.inputs.dimension = dimension;
    rec.steps = steps;
    rec.snapshotEvery = snapshotEvery;
    if (dimension == 3) {
        recordWith<World3>(rec);
    } else {
        recordWith<World2>(rec);
    }
    return rec;
}

std::vector<std::uint8_t> serializeRecording(const Recording& rec) {
    ByteWriter w;
    w.bytes(kMagic, sizeof kMagic);
    w.u32(kRecordingFormatVersion);
    w.u64(resultAffectingBuildFlags());
    w.blob(rec.scene.dump());
    w.blob(inputsToJson(rec.inputs).dump());
    w.u32(std::uint32_t(rec.steps));
    w.u32(std::uint32_t(rec.snapshotEvery));
    w.u64(rec.hashes.size());
    for (std::uint64_t h : rec.hashes) w.u64(h);
    w.u64(rec.snapshots.size());
    for (const RecordedSnapshot& s : rec.snapshots) {
        w.u32(std::uint32_t(s.tick));
        w.u64(s.bytes.size());
        w.bytes(s.bytes.data(), s.bytes.size());
    }
    w.u64(hash64(w.data().data(), w.data().size()));
    return std::move(w.data());
}

Recording parseRecording(const std::vector<std::uint8_t>& bytes, const std::string& what) {
    auto fail = [&](const std::string& why) -> ReplayError { return ReplayError(what + ": recording rejected: " + why); };
    if (bytes.size() < sizeof kMagic + 4 + 8 + 8) throw fail("truncated (" + std::to_string(bytes.size()) + " bytes)");
    if (std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) throw fail("not a Unison recording (bad magic)");
    ByteReader tail(bytes.data() + bytes.size() - 8, 8);
    ByteReader r(bytes.data() + sizeof kMagic, bytes.size() - sizeof kMagic - 8);
    const std::uint32_t version = r.u32();
    if (version != kRecordingFormatVersion)
        throw fail("format version " + std::to_string(version) + ", this build reads " + std::to_string(kRecordingFormatVersion));
    if (tail.u64() != hash64(bytes.data(), bytes.size() - 8)) throw fail("checksum mismatch (corrupt or truncated)");
    const std::uint64_t flags = r.u64();
    if (flags != resultAffectingBuildFlags())
        throw fail("recorded by a build with result-affecting flags " + std::to_string(flags) + ", this build has " +
                   std::to_string(resultAffectingBuildFlags()));
    Recording rec;
    const std::string sceneText = r.blob("scene");
    const std::string inputsText = r.blob("inputs");
    rec.steps = int(r.u32());
    rec.snapshotEvery = int(r.u32());
    const std::size_t nh = r.count(8, "hash");
    for (std::size_t i = 0; i < nh && r.ok(); ++i) rec.hashes.push_back(r.u64());
    const std::size_t ns = r.count(12, "snapshot");
    for (std::size_t i = 0; i < ns && r.ok(); ++i) {
        RecordedSnapshot s;
        s.tick = int(r.u32());
        const std::size_t len = r.count(1, "snapshot byte");
        s.bytes.resize(len);
        for (std::size_t k = 0; k < len && r.ok(); ++k) s.bytes[k] = r.u8();
        if (r.ok() && (s.tick < 0 || s.tick > rec.steps || (!rec.snapshots.empty() && s.tick <= rec.snapshots.back().tick)))
            r.fail("snapshot ticks must ascend within [0, steps]");
        rec.snapshots.push_back(std::move(s));
    }
    if (r.ok() && !r.atEnd()) r.fail("unexpected bytes after the snapshots");
    if (r.ok() && (rec.steps < 0 || rec.steps > policy::kMaxTick || rec.snapshotEvery < 1 ||
                   rec.hashes.size() != std::size_t(rec.steps) + 1))
        r.fail("inconsistent steps, snapshot interval or hash count");
    if (!r.ok()) throw fail(r.error());
    rec.scene = jsonio::parseJson(sceneText, what + " (scene)");
    rec.inputs = parseInputs(jsonio::parseJson(inputsText, what + " (inputs)"), what + " (inputs)",
                             sceneDimension(rec.scene));
    return rec;
}

namespace {

template <class World>
VerifyReport verifyWith(const Recording& rec, bool keepGoing) {
    VerifyReport report;
    Session<World> session(rec.scene, "recording scene");
    std::size_t nextSnapshot = 0;
    for (int t = 0; t <= rec.steps; ++t) {
        if (t > 0) session.tick(t, rec.inputs);
        report.ticks = t;
        const std::uint64_t h = session.world().stateHash();
        if (report.match && h != rec.hashes[std::size_t(t)]) {
            report.match = false;
            report.firstTick = t;
            report.recordedHash = rec.hashes[std::size_t(t)];
            report.replayedHash = h;
        }
        while (nextSnapshot < rec.snapshots.size() && rec.snapshots[nextSnapshot].tick < t) ++nextSnapshot;
        const bool haveSnapshot = nextSnapshot < rec.snapshots.size() && rec.snapshots[nextSnapshot].tick == t;
        if (!report.match && !haveSnapshot && !keepGoing) break;  // a crafted file must not make us replay on
        if (!report.match && haveSnapshot) {
            // Locate the desync: the recorded state at this tick against the replayed one, field by field.
            World recorded;
            restoreOrThrow(recorded, rec.snapshots[nextSnapshot].bytes, "recorded snapshot at tick " + std::to_string(t));
            report.comparedTick = t;
            report.differences = diffFields(recorded.stateFields(), session.world().stateFields());
            for (const FieldDifference& d : report.differences) report.bodyNumbers.push_back(session.bodyNumber(d.body));
            break;
        }
    }
    return report;
}

}  // namespace

VerifyReport verify(const Recording& rec, bool keepGoing) {
    if (!rec.inputs.actions.empty() && rec.inputs.dimension != sceneDimension(rec.scene))
        throw ReplayError("verify: the inputs were read for a " + std::to_string(rec.inputs.dimension) +
                          "D scene, the recording's scene is " + std::to_string(sceneDimension(rec.scene)) + "D");
    return sceneDimension(rec.scene) == 3 ? verifyWith<World3>(rec, keepGoing) : verifyWith<World2>(rec, keepGoing);
}

nlohmann::json reportToJson(const VerifyReport& report, std::size_t limit) {
    nlohmann::json out = {{"status", report.match ? "match" : "desync"}, {"ticks", report.ticks}};
    if (report.match) return out;
    out["first_desync_tick"] = report.firstTick;
    out["recorded_hash"] = hexHash(report.recordedHash);
    out["replayed_hash"] = hexHash(report.replayedHash);
    out["compared_snapshot_tick"] = report.comparedTick;
    out["differing_fields"] = report.differences.size();
    nlohmann::json diffs = differencesToJson(report.differences, "recorded", "replayed", limit);
    for (std::size_t i = 0; i < diffs.size(); ++i) diffs[i]["body_number"] = report.bodyNumbers[i];
    out["differences"] = diffs;
    return out;
}

std::string reportSummary(const VerifyReport& report) {
    if (report.match) return "all " + std::to_string(report.ticks) + " ticks match";
    std::string s = "desync at tick " + std::to_string(report.firstTick) + " (recorded hash " +
                    hexHash(report.recordedHash) + ", replayed " + hexHash(report.replayedHash) + ")";
    if (report.comparedTick < 0) return s + "; no snapshot was recorded at that tick (--keep-going replays on to the next)";
    if (report.differences.empty()) return s + "; no recorded snapshot shows which field";
    const FieldDifference& d = report.differences.front();
    s += "; at snapshot tick " + std::to_string(report.comparedTick) + " " + std::to_string(report.differences.size()) +
         " fields differ, first: " + describeBody(d.body);
    if (report.bodyNumbers.front() >= 0) s += " (number " + std::to_string(report.bodyNumbers.front()) + ")";
    return s + " " + d.path + " recorded " + d.a + " replayed " + d.b;
}

}  // namespace unison::replay
