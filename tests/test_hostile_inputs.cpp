// tests/test_hostile_inputs.cpp — the input policy (docs/input-policy.md) held against crafted inputs: every reader
// (scene 2D/3D, resolve, LCP text, inputs, recordings, snapshots, OBJ) answers each with exit code 2 and a message
// naming the key, never a crash, a hang, a huge allocation or `null` in the output. The first cases are the inputs
// that once crashed, hung, allocated gigabytes, printed null or were silently accepted; the rest are more of the
// same spirit per reader. Restore refuses inconsistent states and leaves the world as it was.
#include "cli_runner.h"

#include <doctest/doctest.h>

#include "compact_state.h"
#include "recording.h"
#include "scene_json.h"
#include "snapshot_file.h"
#include "state_io.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

using namespace unison;

namespace {


struct Case {
    const char* text;      // file contents
    const char* fragment;  // must appear in the error message
};

/// Writes each case to a file, runs `unison COMMAND FILE ARGS` and expects exit 2, nothing on stdout and the fragment
/// on stderr.
void expectRefused(const char* command, const std::vector<Case>& cases, const std::string& args = "") {
    for (const Case& c : cases) {
        const std::string text = c.text, fragment = c.fragment;
        CAPTURE(text);
        CAPTURE(fragment);
        const std::string f = writeTemp("hostile.in", text);
        const Run r = cli(std::string(command) + " " + f + " " + args);
        CHECK(r.exitCode == 2);
        CHECK(r.out.empty());
        CHECK(r.err.find(fragment) != std::string::npos);
        CHECK(r.err.find("null") == std::string::npos);
        std::remove(f.c_str());
    }
}

std::string scene2(const std::string& bodyKeys, const std::string& topKeys = "") {
    return "{\"dimension\": 2, " + topKeys + "\"bodies\": [{" + bodyKeys +
           "\"shapes\": [{\"type\": \"circle\", \"radius\": 0.5}]}]}";
}

std::string scene3(const std::string& shape, const std::string& topKeys = "") {
    return "{\"dimension\": 3, " + topKeys + "\"bodies\": [{\"shapes\": [" + shape + "]}]}";
}

const char* kResolveBodies =
    "\"bodies\": [{\"static\": true, \"position\": [0, 0]}, {\"mass\": 1, \"inertia\": 1, \"position\": [0, 1]}]";

std::string resolve2(const std::string& contactKeys, const std::string& bodies = kResolveBodies) {
    return "{\"dimension\": 2, " + bodies + ", \"contacts\": [{\"a\": 1, \"b\": 0, \"point\": [0, 0.5], \"normal\": [0, 1]" +
           contactKeys + "}]}";
}

void putU64(std::vector<std::uint8_t>& out, std::size_t at, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out[at + std::size_t(i)] = std::uint8_t(v >> (8 * i));
}

/// A recording's bytes with the JSON blob `from` replaced by `to`, its length prefix and the checksum rewritten: a
/// crafted file that passes the checksum, so the reader behind it is what gets tested.
std::vector<std::uint8_t> withBlob(const std::vector<std::uint8_t>& bytes, const std::string& from, const std::string& to) {
    const auto at = std::search(bytes.begin(), bytes.end() - 8, from.begin(), from.end());
    REQUIRE(at != bytes.end() - 8);
    const std::size_t start = std::size_t(at - bytes.begin());
    std::vector<std::uint8_t> out(bytes.begin(), bytes.begin() + std::ptrdiff_t(start));
    putU64(out, start - 8, to.size());
    out.insert(out.end(), to.begin(), to.end());
    out.insert(out.end(), bytes.begin() + std::ptrdiff_t(start + from.size()), bytes.end() - 8);
    const std::uint64_t sum = hash64(out.data(), out.size());
    out.resize(out.size() + 8);
    putU64(out, out.size() - 8, sum);
    return out;
}

/// Restores bytes into a world (the reason of a refusal in *error).
template <class World>
bool restoreFrom(World& w, const std::vector<std::uint8_t>& bytes, std::string* error) {
    return w.restore(bytes.data(), bytes.size(), error);
}

/// A snapshot with the first double equal to `from` in its payload set to `to`, framed again with a valid checksum.
std::vector<std::uint8_t> patchDouble(const std::vector<std::uint8_t>& snap, SnapshotKind kind, double from, double to) {
    SnapshotView view;
    std::string error;
    REQUIRE(unframeSnapshot(snap.data(), snap.size(), kind, &view, &error));
    std::vector<std::uint8_t> payload(view.payload, view.payload + view.payloadSize);
    std::uint8_t a[8], b[8];
    ByteWriter wa, wb;
    wa.f64(from);
    wb.f64(to);
    std::memcpy(a, wa.data().data(), 8);
    std::memcpy(b, wb.data().data(), 8);
    const auto it = std::search(payload.begin(), payload.end(), a, a + 8);
    REQUIRE(it != payload.end());
    std::memcpy(&*it, b, 8);
    return frameSnapshot(kind, view.bodyCount, payload);
}

}  // namespace

TEST_SUITE("hostile_inputs") {

TEST_CASE("numbers that overflow a double are a clean error naming the key, in every JSON reader") {
    expectRefused("run", {{"{\"dimension\": 2, \"bodies\": [], \"ignored\": 1e999}", "ignored: number out of the range"},
                          {"{\"dimension\": 2, \"bodies\": [{\"position\": [0, -1e400]}]}", "bodies[0].position[1]: number out"}});
    expectRefused("resolve", {{"{\"dimension\": 2, \"bodies\": [], \"contacts\": [], \"x\": [1, 2, 1e999]}", "x[2]: number out"}});
    const std::string scene = writeTemp("plain.json", scene2(""));
    expectRefused(("record " + scene + " --inputs").c_str(),
                  {{"{\"inputs\": [{\"tick\": 1, \"type\": \"set_gravity\", \"gravity\": [0, -1e999]}]}",
                    "inputs[0].gravity[1]: number out"}},
                  "--steps 1 -o " + tempPath("x.urec"));
    std::remove(scene.c_str());
}

TEST_CASE("nesting deeper than 64 levels is refused at parse time, also by record (which copies and dumps JSON)") {
    const std::string deep(200000, '[');
    expectRefused("record", {{deep.c_str(), "nested deeper than 64 levels"}}, "--steps 1 -o " + tempPath("d.urec"));
    std::string nested = "{\"dimension\": 2, \"bodies\": [], \"x\": ";
    for (int i = 0; i < 65; ++i) nested += "[";
    for (int i = 0; i < 65; ++i) nested += "]";
    expectRefused("run", {{(nested + "}").c_str(), "x[0][0]"}});
    std::string ok = "{\"dimension\": 2, \"bodies\": [], \"x\": ";
    for (int i = 0; i < 60; ++i) ok += "[";
    for (int i = 0; i < 60; ++i) ok += "]";
    const std::string f = writeTemp("ok.json", ok + "}");
    CHECK(cli("run " + f + " --steps 1").exitCode == 0);  // deep but within the limit: fine
    std::remove(f.c_str());
}

TEST_CASE("files over the size limit are refused before they are parsed; /dev/zero is not read without bound") {
    std::string big = "{\"dimension\": 2, \"bodies\": [], \"pad\": \"";
    big.append(std::size_t(9) << 20, 'x');
    big += "\"}";
    expectRefused("run", {{big.c_str(), "larger than the limit of 8388608 bytes"}});
    CHECK(cli("run /dev/zero").exitCode == 2);
    CHECK(cli("lcp /dev/zero").exitCode == 2);
    CHECK(cli("verify /dev/zero").exitCode == 2);
}

TEST_CASE("a scene at the edges of every range runs, and run --snapshot-at writes a snapshot its own diff reads") {
    // Velocities, gravity and the step length at their limits (the inputs that once made run print null and write a
    // snapshot diff refused): now either a clean run or a clean fault, never a non-finite number.
    const std::string scene = writeTemp("edge.json",
        "{\"dimension\": 2, \"hz\": 1, \"gravity\": [10000, -10000], \"bodies\": ["
        "{\"type\": \"static\", \"shapes\": [{\"type\": \"segment\", \"points\": [[-1000000, 0], [1000000, 0]]}]},"
        "{\"position\": [0, 1000], \"linear_velocity\": [10000, -10000], \"angular_velocity\": 10000,"
        " \"shapes\": [{\"type\": \"circle\", \"radius\": 0.0001, \"density\": 1000000}]}]}");
    const std::string snap = tempPath("edge.usnap");
    const Run r = cli("run " + scene + " --steps 30 --snapshot-at 30 -o " + snap);
    CAPTURE(r.err);
    CHECK((r.exitCode == 0 || r.exitCode == 2));
    CHECK(r.out.find("null") == std::string::npos);
    if (r.exitCode == 0) CHECK(cli("diff " + snap + " " + snap).exitCode == 0);
    if (r.exitCode == 2) CHECK(r.err.find("supported range") != std::string::npos);
    std::remove(scene.c_str());
    std::remove(snap.c_str());
}

TEST_CASE("malformed JSON is named by line and column, never quoted") {
    expectRefused("run", {{"{\"dimension\": 2,\n \"bodies\": [SECRET]}", "line 2"},
                          {"{\"dimension\": 2, \"bodies\": [], \"bodies\": []}", "bodies: duplicate key"}});
    const std::string f = writeTemp("secret.json", "{\"dimension\": 2, \"bodies\": [tSECRET]}");
    const Run r = cli("run " + f);
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("SECRET") == std::string::npos);
    std::remove(f.c_str());
}

TEST_CASE("2D scenes: every number within its documented range, exact integer types") {
    expectRefused("run", {
        {scene2("\"linear_velocity\": [1e308, 0], ").c_str(), "linear_velocity[0]: must be in [-10000, 10000]"},
        {scene2("", "\"gravity\": [0, 1.7e308], ").c_str(), "gravity[1]: must be in"},
        {scene2("", "\"hz\": 1e-300, ").c_str(), "hz: must be in [1, 10000]"},
        {scene2("", "\"hz\": 0, ").c_str(), "hz: must be in"},
        {scene2("", "\"restitution_threshold\": -1, ").c_str(), "restitution_threshold: must be in [0, 1000]"},
        {scene2("\"angular_velocity\": 1e300, ").c_str(), "angular_velocity: must be in"},
        {scene2("\"position\": [1e7, 0], ").c_str(), "position[0]: must be in [-1000000, 1000000]"},
        {scene2("\"angle\": 1e9, ").c_str(), "angle: must be in"},
        {"{\"dimension\": 4294967298, \"bodies\": []}", "dimension: must be an integer in [2, 3]"},
        {"{\"dimension\": 2.0, \"bodies\": []}", "dimension: expected an integer"},
        {"{\"dimension\": \"2\", \"bodies\": []}", "dimension: expected an integer"},
        {"{\"dimension\": 2, \"bodies\": [{\"shapes\": [{\"type\": \"circle\", \"radius\": 1e150}]}]}", "radius: must be in"},
        {"{\"dimension\": 2, \"bodies\": [{\"shapes\": [{\"type\": \"circle\", \"radius\": 1e-9}]}]}", "radius: must be in"},
        {"{\"dimension\": 2, \"bodies\": [{\"shapes\": [{\"type\": \"circle\", \"radius\": 1, \"density\": -1}]}]}", "density: must be in"},
        {"{\"dimension\": 2, \"bodies\": [{\"shapes\": [{\"type\": \"circle\", \"radius\": 1, \"friction\": 1e9}]}]}", "friction: must be in"},
        {"{\"dimension\": 2, \"bodies\": [{\"shapes\": [{\"type\": \"box\", \"half_extents\": [1, 0]}]}]}", "half_extents: must be in"},
        {"{\"dimension\": 2, \"bodies\": [{\"shapes\": [{\"type\": \"polygon\", \"vertices\": [[0,0],[1,0],[1,1],[0,1],[0,2],[1,2],[2,2],[2,1],[2,0]]}]}]}",
         "vertices: more than 8 elements"},
        {"{\"dimension\": 2, \"sleep\": 1, \"bodies\": []}", "sleep: expected true or false"},
        {"{\"dimension\": 2, \"bodies\": {}}", "bodies: expected an array"},
    });
}

TEST_CASE("3D scenes: ranges, even friction directions, bounded hulls and meshes") {
    const char* sphere = "{\"type\": \"sphere\", \"radius\": 0.5}";
    expectRefused("run", {
        {scene3(sphere, "\"friction_directions\": 5, ").c_str(), "friction_directions: must be even"},
        {scene3(sphere, "\"friction_directions\": 64, ").c_str(), "friction_directions: must be an integer in [4, 16]"},
        {scene3(sphere, "\"gravity\": [0, -1e5, 0], ").c_str(), "gravity[1]: must be in"},
        {scene3("{\"type\": \"sphere\", \"radius\": 1e150}").c_str(), "radius: must be in"},
        {scene3("{\"type\": \"box\", \"half_extents\": [1, 1, 1e-7]}").c_str(), "half_extents: must be in"},
        {scene3("{\"type\": \"mesh\", \"scale\": 0, \"vertices\": [], \"triangles\": []}").c_str(), "scale: must be in"},
        {scene3("{\"type\": \"mesh\", \"vertices\": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], \"triangles\": [[0,1,2],[0,3,1],[1,3,2],[0,2,9]]}").c_str(),
         "triangles[3]: must be an integer in [0, 3]"},
        {scene3("{\"type\": \"plane\", \"normal\": [0, 1, 0], \"offset\": 1e300}").c_str(), "offset: must be in"},
        {"{\"dimension\": 3, \"bodies\": [{\"angular_velocity\": [0, 1e300, 0]}]}", "angular_velocity[1]: must be in"},
        {"{\"dimension\": 3, \"bodies\": [{\"orientation\": [0, 0, 0, 0]}]}", "orientation must be non-zero"},
    });
    std::string hull = "{\"type\": \"hull\", \"vertices\": [";
    for (int i = 0; i < 257; ++i) hull += std::string(i ? "," : "") + "[" + std::to_string(i) + ", " + std::to_string(i * i % 7) + ", 1]";
    expectRefused("run", {{scene3(hull + "]}").c_str(), "vertices: more than 256 elements"}});
}

TEST_CASE("OBJ files stay inside the scene's folder, are regular files, and are never quoted") {
    namespace fs = std::filesystem;
    const fs::path dir = tempPath("objdir");
    fs::create_directories(dir / "sub");
    auto write = [&](const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; };
    write(dir / "secret.obj", "v 0 0 SECRETTOKEN\n");
    write(dir.parent_path() / "outside.obj", "v 0 0 0\n");
    fs::remove(dir / "link.obj");
    fs::create_symlink("/etc/hostname", dir / "link.obj");
    const std::pair<std::string, std::string> cases[] = {
        {"../outside.obj", "must not leave the scene's folder"},
        {"sub/../../outside.obj", "must not leave the scene's folder"},
        {"/dev/zero", "must be a relative path"},
        {"/etc/passwd", "must be a relative path"},
        {"link.obj", "leads outside the scene's folder"},
        {"sub", "not a regular file"},
        {"missing.obj", "not a regular file"},
        {"secret.obj", "secret.obj:1: bad coordinate"},
    };
    for (const auto& item : cases) {
        const std::string& obj = item.first;  // no structured binding: clang 14 cannot CAPTURE one
        const std::string& fragment = item.second;
        CAPTURE(obj);
        const fs::path scene = dir / "scene.json";
        write(scene, scene3("{\"type\": \"mesh\", \"obj\": \"" + obj + "\"}"));
        for (const std::string& command : {"run " + scene.string(), "record " + scene.string() + " -o " + tempPath("o.urec")}) {
            const Run r = cli(command);
            CHECK(r.exitCode == 2);
            CHECK(r.err.find(fragment) != std::string::npos);
            CHECK(r.err.find("SECRETTOKEN") == std::string::npos);
        }
    }
    fs::remove_all(dir);
    fs::remove(dir.parent_path() / "outside.obj");
}

TEST_CASE("a self-intersecting mesh with positive volume but an indefinite inertia tensor is refused at creation") {
    // Found by fuzz_obj: det(I) > 0 with two negative eigenvalues passed creation, and the world's own snapshot was
    // then refused by restore. Creation now makes restore's check (a Cholesky factorisation).
    namespace fs = std::filesystem;
    const fs::path dir = tempPath("inertiadir");
    fs::create_directories(dir);
    std::ofstream(dir / "bad.obj") << "v -2 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -18\nv -1 10 1\nv 1 1 1\nv 1 1 1\nv -1 1 1\n"
                                     "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf -8 -4 -1 -5\n";
    std::ofstream(dir / "scene.json") << scene3("{\"type\": \"mesh\", \"obj\": \"bad.obj\", \"scale\": 0.5}");
    const Run r = cli("run " + (dir / "scene.json").string());
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("inertia tensor must be symmetric positive definite") != std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("resolve: ranges, both-static contacts, bounded counts, and no null in the answer") {
    const std::string fastBodies =
        "\"bodies\": [{\"static\": true, \"position\": [0, 0]}, {\"mass\": 1, \"inertia\": 1, \"position\": [0, 1], "
        "\"velocity\": [0, -1e308]}]";
    const std::string twoStatics =
        "\"bodies\": [{\"static\": true, \"position\": [0, 0]}, {\"static\": true, \"position\": [0, 1]}]";
    std::string many = "{\"dimension\": 2, " + std::string(kResolveBodies) + ", \"contacts\": [";
    for (int i = 0; i < 257; ++i) many += std::string(i ? "," : "") + "{\"a\": 1, \"b\": 0, \"point\": [0, 0.5], \"normal\": [0, 1]}";
    many += "]}";
    expectRefused("resolve", {
        {resolve2("", fastBodies).c_str(), "bodies[1].velocity[1]: must be in"},
        {resolve2("", twoStatics).c_str(), "contacts[0]: bodies a and b are both static"},
        {resolve2(", \"restitution\": 2").c_str(), "restitution: must be in [0, 1]"},
        {resolve2(", \"friction\": -0.5").c_str(), "friction: must be in"},
        {resolve2("", "\"bodies\": [{\"static\": true, \"position\": [0, 0]}, {\"mass\": 1e-9, \"inertia\": 1, \"position\": [0, 1]}]").c_str(),
         "bodies[1].mass: must be in"},
        {resolve2("", "\"bodies\": [{\"static\": true, \"position\": [0, 0]}, {\"mass\": 1, \"inertia\": 1e30, \"position\": [0, 1]}]").c_str(),
         "bodies[1].inertia: must be in"},
        {"{\"dimension\": 2, \"bodies\": [], \"contacts\": [], \"restitution_threshold\": -1}", "restitution_threshold: must be in"},
        {many.c_str(), "contacts: more than 256 elements"},
    });
}

TEST_CASE("lcp: sizes checked against the file before allocating, bounded entries") {
    expectRefused("lcp", {
        {"20000 1 2 3", "n must be an integer in [0, 1000]"},
        {"1000 1 2 3", "ended after 4 numbers, expected the n*n entries of A"},
        {"2 1e308 0 0 1 -1 -1", "token 2 must be in"},
        {"1 1 -1e308", "token 3 must be in"},
        {"1 1 1e400", "token 3 is not a number"},
        {"1 inf -1", "token 2 is not finite"},
        {"-1", "n must be an integer"},
        {"1 1 SECRET", "token 3 is not a number"},
        {"", "ended after 0 numbers"},
    });
    const std::string f = writeTemp("secret.txt", "1 1 SECRET");
    CHECK(cli("lcp " + f).err.find("SECRET") == std::string::npos);
    std::remove(f.c_str());
}

TEST_CASE("inputs: ticks, bodies and vectors within range; no files from inputs") {
    const std::string scene = writeTemp("scene_for_inputs.json", scene2(""));
    const std::string command = "record " + scene + " --inputs";
    expectRefused(command.c_str(), {
        {"{\"inputs\": [{\"tick\": 1, \"type\": \"apply_impulse\", \"body\": 0, \"impulse\": [1e308, 0]}]}", "impulse[0]: must be in"},
        {"{\"inputs\": [{\"tick\": 1, \"type\": \"apply_force\", \"body\": 0, \"force\": [0, 1e12]}]}", "force[1]: must be in"},
        {"{\"inputs\": [{\"tick\": 0, \"type\": \"set_gravity\", \"gravity\": [0, 1]}]}", "tick: must be an integer in [1, 10000000]"},
        {"{\"inputs\": [{\"tick\": 4294967297, \"type\": \"set_gravity\", \"gravity\": [0, 1]}]}", "tick: must be an integer"},
        {"{\"inputs\": [{\"tick\": 1, \"type\": \"set_velocity\", \"body\": 0, \"linear_velocity\": [0, 0], \"angular_velocity\": 1e300}]}",
         "angular_velocity: must be in"},
        {"{\"inputs\": [{\"tick\": 1, \"type\": \"set_gravity\", \"gravity\": [0, -1e5]}]}", "gravity[1]: must be in"},
        {"{\"inputs\": [{\"tick\": 1, \"type\": \"destroy_body\", \"body\": -1}]}", "body: must be an integer"},
        {"{\"inputs\": [{\"tick\": 1, \"type\": 5}]}", "type: expected apply_impulse"},
    }, "--steps 2 -o " + tempPath("i.urec"));
    std::remove(scene.c_str());
    const std::string scene3d = writeTemp("scene3_for_inputs.json", scene3("{\"type\": \"sphere\", \"radius\": 0.5}"));
    const std::string inputs = writeTemp("objinputs.json",
        "{\"inputs\": [{\"tick\": 1, \"type\": \"create_body\", \"body_def\": {\"shapes\": [{\"type\": \"mesh\", \"obj\": \"/dev/zero\"}]}}]}");
    const Run r = cli("record " + scene3d + " --inputs " + inputs + " --steps 2 -o " + tempPath("j.urec"));
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("mesh files are read only for a scene file") != std::string::npos);
    std::remove(scene3d.c_str());
    std::remove(inputs.c_str());
}

TEST_CASE("recordings: crafted files that pass the checksum are still refused or bounded") {
    const nlohmann::json scene = nlohmann::json::parse(scene2("\"position\": [0, 1], "));
    const replay::Recording rec = replay::record(scene, replay::InputScript{2, {}}, 4, 2);
    const std::vector<std::uint8_t> bytes = replay::serializeRecording(rec);
    const std::string sceneText = rec.scene.dump();
    auto runOn = [&](const std::vector<std::uint8_t>& b, const std::string& extra = "") {
        const std::string f = tempPath("crafted.urec");
        replay::writeFileAtomic(f, b);
        const Run r = cli("verify " + f + extra);
        std::remove(f.c_str());
        return r;
    };
    CHECK(runOn(bytes).exitCode == 0);
    std::string overflow = sceneText;
    overflow.insert(overflow.size() - 1, ",\"x\":1e999");
    Run r = runOn(withBlob(bytes, sceneText, overflow));
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("x: number out of the range of a double") != std::string::npos);
    r = runOn(withBlob(bytes, sceneText, std::string(100, '[') + std::string(100, ']')));
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("nested deeper") != std::string::npos);
    // A 3D scene in a recording names an OBJ file: recordings carry meshes inline and never open files.
    const std::string objScene = scene3("{\"type\": \"mesh\", \"obj\": \"/dev/zero\"}");
    r = runOn(withBlob(bytes, sceneText, objScene));
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("mesh files are read only for a scene file") != std::string::npos);
}

TEST_CASE("verify stops at the first mismatch of a recording that claims 200,000 ticks") {
    const nlohmann::json scene = nlohmann::json::parse(scene2("\"position\": [0, 1], "));
    replay::Recording rec = replay::record(scene, replay::InputScript{2, {}}, 1, 1);
    const std::uint64_t start = rec.hashes[0];
    rec.steps = 200000;
    rec.snapshotEvery = 200000;
    rec.hashes.assign(200001, 0);
    rec.hashes[0] = start;  // tick 0 matches, tick 1 does not; the last snapshot is 200,000 ticks away
    rec.snapshots = {rec.snapshots[0], {200000, rec.snapshots[0].bytes}};
    const std::string f = tempPath("long.urec");
    replay::writeFileAtomic(f, replay::serializeRecording(rec));
    const Run r = cli("verify " + f);
    CHECK(r.exitCode == 1);
    const nlohmann::json report = nlohmann::json::parse(r.out);
    CHECK(report["first_desync_tick"] == 1);
    CHECK(report["ticks"] == 1);
    std::remove(f.c_str());
}

TEST_CASE("restore refuses inconsistent states as strictly as creation, and leaves the world unchanged") {
    // 2D: a negative mass, a rotation that is not unit.
    World2 w2;
    std::vector<Shape2> circle(1);
    REQUIRE(makeCircle({0.0, 0.0}, 0.375, &circle[0].circle).empty());
    const BodyId b = w2.createBody(BodyDef2{BodyType::dynamicBody, {0.0, 1.0}, 0.0, {}, 0.0}, circle);
    REQUIRE_FALSE(b.isNull());
    const std::vector<std::uint8_t> snap2 = w2.snapshot();
    const double mass = w2.info(b)->mass;
    const std::uint64_t hash2 = w2.stateHash();
    std::string error;
    CHECK_FALSE(restoreFrom(w2, patchDouble(snap2, SnapshotKind::world2, mass, -mass), &error));
    CHECK(error.find("mass") != std::string::npos);
    CHECK_FALSE(restoreFrom(w2, patchDouble(snap2, SnapshotKind::world2, 0.375, 1e300), &error));
    CHECK(w2.stateHash() == hash2);
    // 3D: a hull whose face offsets disagree with its vertices (the crafted snapshot that restored, and two steps
    // later produced a snapshot the world itself refused).
    World3 w3;
    std::vector<Shape3> hull(1);
    REQUIRE(makeHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 0.8125)}, &hull[0]).empty());
    BodyDef3 def;
    def.position = Vec3(0.0, 2.0, 0.0);
    REQUIRE_FALSE(w3.createBody(def, hull).isNull());
    const std::vector<std::uint8_t> snap3 = w3.snapshot();
    const std::uint64_t hash3 = w3.stateHash();
    CHECK_FALSE(restoreFrom(w3, patchDouble(snap3, SnapshotKind::world3, 0.8125, 0.9), &error));
    CHECK(error.find("hull") != std::string::npos);
    CHECK(w3.stateHash() == hash3);
    World3 fresh;
    CHECK(fresh.restore(snap3.data(), snap3.size(), &error));  // the untouched snapshot restores
    CHECK(fresh.stateHash() == hash3);
}

TEST_CASE("a step that overflows stops the world with a message naming the body and field") {
    WorldDef2 def;
    def.hz = 1e-300;  // outside the policy; only the C++ API can set it
    World2 w(def);
    std::vector<Shape2> circle(1);
    REQUIRE(makeCircle({0.0, 0.0}, 0.5, &circle[0].circle).empty());
    REQUIRE_FALSE(w.createBody(BodyDef2{}, circle).isNull());
    w.step();
    REQUIRE_FALSE(w.fault().empty());
    CHECK(w.fault().find("step 1: body 1:1 position.y is -inf (overflow)") != std::string::npos);
    const std::uint64_t steps = w.stepCount();
    w.step();
    CHECK(w.stepCount() == steps);  // it does not go on with NaN
    World2 ok;
    REQUIRE_FALSE(ok.createBody(BodyDef2{}, circle).isNull());
    const std::vector<std::uint8_t> snap = ok.snapshot();
    REQUIRE(w.restore(snap.data(), snap.size()));
    CHECK(w.fault().empty());  // a restored state is finite again
}

TEST_CASE("a compact rollback state that holds an out-of-range value faults instead of being stepped") {
    World2 w;
    std::vector<Shape2> circle(1);
    REQUIRE(makeCircle({0.0, 0.0}, 0.5, &circle[0].circle).empty());
    REQUIRE_FALSE(w.createBody(BodyDef2{BodyType::dynamicBody, {0.0, 0.8125}, 0.0, {}, 0.0}, circle).isNull());
    CompactState saved;
    w.saveCompact(saved);
    std::vector<std::uint8_t> bytes(saved.data(), saved.data() + saved.size());
    ByteWriter from, to;
    from.f64(0.8125);
    to.f64(1e300);
    const auto at = std::search(bytes.begin(), bytes.end() - 8, from.data().begin(), from.data().end());
    REQUIRE(at != bytes.end() - 8);
    std::copy(to.data().begin(), to.data().end(), at);
    const std::uint64_t sum = hash64(bytes.data(), bytes.size() - 8);
    putU64(bytes, bytes.size() - 8, sum);  // the checksum of a compact state is its only check
    REQUIRE(w.restoreCompact(bytes.data(), bytes.size()));
    CHECK(w.fault().find("position outside the supported range") != std::string::npos);
    const std::uint64_t steps = w.stepCount();
    w.step();
    CHECK(w.stepCount() == steps);
    REQUIRE(w.restoreCompact(saved.data(), saved.size()));  // the saved state is fine again
    CHECK(w.fault().empty());
}

}  // TEST_SUITE
