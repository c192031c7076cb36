// tests/test_view.cpp — the replay viewer's data (samples/view_capture.h, view_page.h) and `unison view` /
// `unison verify --report`: the capture replays to the recorded hashes and holds the world's own poses, contacts
// and islands tick by tick (bodies created and destroyed by inputs included); the page's packed arrays unpack to
// exactly the captured ones and the page refers to nothing outside itself; bad files exit 2. The page itself runs
// in a real browser in scripts/browser_test.sh.
#include "test_support.h"

#include "cli.h"
#include "process_run.h"
#include "recording.h"
#include "scene_dir.h"
#include "scene_json.h"
#include "snapshot_file.h"
#include "view_page.h"

#include <zlib.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <regex>

using namespace unison;

namespace {

const replay::Recording& pileRecording() {
    static const replay::Recording rec = [] {
        const char* text = R"({"inputs": [
            {"tick": 5, "type": "apply_impulse", "body": 3, "impulse": [2, 5]},
            {"tick": 20, "type": "destroy_body", "body": 7},
            {"tick": 24, "type": "create_body", "body_def": {"position": [0, 8], "shapes": [{"type": "circle", "radius": 0.3}]}}
        ]})";
        const nlohmann::json scene = scenes::readSceneFile(scenes::sceneDir() + "/mixed_pile.json");
        return replay::record(scene, replay::parseInputs(nlohmann::json::parse(text), "inputs"), 60, 10);
    }();
    return rec;
}

/// Undoes view_page.cpp's packing of one array: base64, inflate, then the byte grouping.
template <class T>
std::vector<T> unpack(const std::string& page, const std::string& name, std::size_t count) {
    const std::string open = "<script type=\"application/octet-stream\" id=\"b-" + name + "\">";
    const std::size_t from = page.find(open) + open.size();
    const std::string text = page.substr(from, page.find("</script>", from) - from);
    std::vector<unsigned char> packed;
    unsigned bits = 0;
    int have = 0;
    for (char c : text) {
        const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        const char* at = std::strchr(digits, c);
        if (c == '=' || !at) continue;
        bits = bits << 6 | unsigned(at - digits);
        have += 6;
        if (have >= 8) {
            have -= 8;
            packed.push_back((unsigned char)(bits >> have));
        }
    }
    std::vector<unsigned char> grouped(count * sizeof(T));
    uLongf size = uLongf(grouped.size());
    REQUIRE(uncompress(grouped.data(), &size, packed.data(), uLong(packed.size())) == Z_OK);
    REQUIRE(size == grouped.size());
    std::vector<unsigned char> bytes(grouped.size());
    for (std::size_t b = 0; b < sizeof(T); ++b)
        for (std::size_t i = 0; i < count; ++i) bytes[i * sizeof(T) + b] = grouped[b * count + i];
    std::vector<T> out(count);
    std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
}

nlohmann::json metaOf(const std::string& page) {
    const std::string open = "<script type=\"application/json\" id=\"meta\">";
    const std::size_t from = page.find(open) + open.size();
    return nlohmann::json::parse(page.substr(from, page.find("</script>", from) - from));
}

}  // namespace

TEST_SUITE("view") {

TEST_CASE("capture: replayed hashes, the world's poses, contacts and islands at every tick") {
    const replay::Recording& rec = pileRecording();
    const view::Capture cap = view::captureRecording(rec);
    REQUIRE(cap.ticks == 60);
    REQUIRE(cap.hashes.size() == 61);
    CHECK(cap.hashes == cap.recordedHashes);
    CHECK(cap.hashes.back() == replay::hexHash(rec.hashes.back()));
    // The scene's 31 bodies plus one created at tick 24.
    const int sceneBodies = int(rec.scene["bodies"].size());
    REQUIRE(cap.bodyCount == sceneBodies + 1);
    REQUIRE(cap.poses.size() == std::size_t(61 * cap.bodyCount * 3));
    auto pose = [&](int t, int n, int k) { return cap.poses[std::size_t((t * cap.bodyCount + n) * 3 + k)]; };
    CHECK(std::isnan(pose(19, sceneBodies, 0)));   // not created yet
    CHECK(std::isfinite(pose(24, sceneBodies, 0)));
    CHECK(std::isfinite(pose(19, 7, 0)));
    CHECK(std::isnan(pose(20, 7, 0)));             // destroyed at tick 20
    // Step a session alongside and compare what the world says with what was captured.
    replay::Session2 session(rec.scene, "scene");
    for (int t = 1; t <= rec.steps; ++t) {
        session.tick(t, rec.inputs);
        const World2& w = session.world();
        CHECK(cap.contactStart[std::size_t(t) + 1] - cap.contactStart[std::size_t(t)] == w.contacts().size());
        for (BodyId id : w.bodyIds()) {
            const int n = session.bodyNumber(id);
            CHECK(pose(t, n, 0) == float(w.state(id)->position.x));
            CHECK(pose(t, n, 2) == float(w.angle(id)));
            const std::uint16_t key = cap.islands[std::size_t(t * cap.bodyCount + n)];
            if (w.info(id)->type != BodyType::dynamicBody) {
                CHECK(key == 0xFFFF);
            } else {
                // A body's island key is a body number no larger than its own, and that body shares the key.
                const int root = key & 0x7FFF;
                CHECK(root <= n);
                CHECK((cap.islands[std::size_t(t * cap.bodyCount + root)] & 0x7FFF) == root);
                CHECK(((key & 0x8000) != 0) == !w.info(id)->awake);
            }
        }
        // Both bodies of a contact between dynamic bodies are in one island.
        for (std::uint32_t c = cap.contactStart[std::size_t(t)]; c < cap.contactStart[std::size_t(t) + 1]; ++c) {
            const std::uint16_t a = cap.islands[std::size_t(t * cap.bodyCount + cap.contactBodies[2 * c])];
            const std::uint16_t b = cap.islands[std::size_t(t * cap.bodyCount + cap.contactBodies[2 * c + 1])];
            if (a != 0xFFFF && b != 0xFFFF) CHECK(a == b);
        }
    }
    CHECK(cap.stats["contacts"].size() == 61);
}

TEST_CASE("page: the packed arrays unpack to the captured ones; nothing outside the file is referenced") {
    const view::Capture cap = view::captureRecording(pileRecording());
    const nlohmann::json report = {{"status", "desync"}, {"first_desync_tick", 12},
                                   {"differences", {{{"body", "body 4:1"}, {"body_number", 3}, {"field", "velocity.x"}}}}};
    const std::string page = view::renderPage(cap, report, "pile </script> test");
    const nlohmann::json meta = metaOf(page);
    CHECK(meta["title"] == "pile </script> test");  // escaped inside the element, intact after parsing
    CHECK(meta["report"]["first_desync_tick"] == 12);
    CHECK(meta["hashes"] == cap.hashes);
    const std::vector<float> poses = unpack<float>(page, "poses", cap.poses.size());  // with NaNs: compare bits
    CHECK(std::memcmp(poses.data(), cap.poses.data(), poses.size() * sizeof(float)) == 0);
    CHECK(unpack<std::uint16_t>(page, "islands", cap.islands.size()) == cap.islands);
    CHECK(unpack<std::uint32_t>(page, "contact_start", cap.contactStart.size()) == cap.contactStart);
    CHECK(unpack<std::uint16_t>(page, "contact_bodies", cap.contactBodies.size()) == cap.contactBodies);
    const std::vector<float> contacts = unpack<float>(page, "contacts", cap.contacts.size());
    CHECK(std::memcmp(contacts.data(), cap.contacts.data(), contacts.size() * sizeof(float)) == 0);
    // Self-contained: no URL, no external script, style or image.
    CHECK_FALSE(std::regex_search(page, std::regex(R"((src|href)\s*=\s*["']?(https?:|//))", std::regex::icase)));
    CHECK(page.find("http://") == std::string::npos);
    CHECK(page.find("https://") == std::string::npos);
    CHECK(page.find("<!--UNISON-DATA-->") == std::string::npos);
}

TEST_CASE("3D capture: hashes match and a mesh shared by bodies is stored once") {
    nlohmann::json scene = scenes::readSceneFile(scenes::sceneDir() + "/mixed3d.json");
    const replay::Recording rec = replay::record(scene, replay::InputScript{3, {}}, 20, 10, scenes::sceneDir());
    const view::Capture cap = view::captureRecording(rec);
    CHECK(cap.dimension == 3);
    CHECK(cap.poseStride == 7);
    CHECK(cap.hashes == cap.recordedHashes);
    int meshes = 0;
    for (const auto& g : cap.geometry) meshes += g.contains("f") ? 1 : 0;
    int meshShapes = 0;
    for (const auto& b : cap.bodies)
        for (const auto& s : b["shapes"]) meshShapes += s["t"] == "mesh" ? 1 : 0;
    CHECK(meshes >= 1);
    CHECK(meshes <= meshShapes);
}

TEST_CASE("unison view and verify --report: files written; bad input exits 2") {
    const std::string dir = test::tempFile("unison_view", "");
    const std::string rec = dir + "pile.urec", page = dir + "pile.html", reportFile = dir + "report.json";
    replay::writeFileAtomic(rec, replay::serializeRecording(pileRecording()));
    // A replay with a changed input: verify exits 1 and writes the same report as it prints.
    nlohmann::json changed = replay::inputsToJson(pileRecording().inputs);
    changed["inputs"][0]["impulse"][1] = 5.001;
    const std::string inputs = dir + "changed.json";
    std::ofstream(inputs) << changed.dump();
    const test::ProcessRun verify =
        test::runProgram(UNISON_CLI_PATH, "verify " + rec + " --inputs " + inputs + " --keep-going --report " + reportFile);
    REQUIRE(verify.exitCode == 1);
    const nlohmann::json printed = nlohmann::json::parse(verify.out);
    const nlohmann::json written = nlohmann::json::parse(test::readWhole(reportFile));
    CHECK(written["first_desync_tick"] == 5);
    CHECK(written["first_desync_tick"] == printed["first_desync_tick"]);
    CHECK(written["differences"][0] == printed["differences"][0]);
    const test::ProcessRun view = test::runProgram(UNISON_CLI_PATH, "view " + rec + " -o " + page + " --report " + reportFile);
    REQUIRE_MESSAGE(view.exitCode == 0, view.err);
    CHECK(nlohmann::json::parse(view.out)["ticks_differing_from_recording"] == 0);
    const std::string html = test::readWhole(page);
    CHECK(metaOf(html)["report"]["first_desync_tick"] == 5);
    // Bad input: no recording, a report that is not JSON or not a report, no output file.
    const std::string notJson = dir + "bad.json", notReport = dir + "notreport.json";
    std::ofstream(notJson) << "{not json";
    std::ofstream(notReport) << R"({"first_desync_tick": 3})";
    CHECK(test::runProgram(UNISON_CLI_PATH, "view " + dir + "missing.urec -o " + page).exitCode == 2);
    CHECK(test::runProgram(UNISON_CLI_PATH, "view " + rec + " -o " + page + " --report " + notJson).exitCode == 2);
    CHECK(test::runProgram(UNISON_CLI_PATH, "view " + rec + " -o " + page + " --report " + notReport).exitCode == 2);
    CHECK(test::runProgram(UNISON_CLI_PATH, "view " + rec).exitCode == 2);
    for (const std::string& f : {rec, page, reportFile, inputs, notJson, notReport}) std::remove(f.c_str());
}

}  // TEST_SUITE
