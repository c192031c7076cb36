// tests/test_cli.cpp — the `unison` tool's contract: formats, JSON output and exit codes (0 solved, 1 unsolved,
// 2 bad input), run as a real process on files written to a temporary folder.
#include "cli_runner.h"

#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

TEST_SUITE("cli") {

TEST_CASE("lcp: solves a text file and prints the contract's JSON") {
    const std::string f = writeTemp("a.txt", "2\n2 1\n1 2\n-5 -6\n");
    const Run r = cli("lcp " + f);
    REQUIRE(r.exitCode == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["status"] == "solved");
    CHECK(j["pivots"].get<int>() >= 2);
    CHECK(j["z"][0].get<double>() == doctest::Approx(4.0 / 3.0));
    CHECK(j["z"][1].get<double>() == doctest::Approx(7.0 / 3.0));
    CHECK(std::fabs(j["w"][0].get<double>()) < 1e-12);
    CHECK(j["residual"].get<double>() < 1e-12);
    std::remove(f.c_str());
}

TEST_CASE("lcp: unsolved problems exit 1 with their status") {
    const std::string f = writeTemp("inf.txt", "2  1 -1 -1 1  -1 -1");
    const Run r = cli("lcp " + f);
    CHECK(r.exitCode == 1);
    CHECK(nlohmann::json::parse(r.out)["status"] == "infeasible");
    // Murty's matrix n = 8 (b_i = -1 + 0.25 2^-(i+1), see scenes::murty) needs 256 pivots: a cap of 10 stops it.
    std::string murty = "8\n";
    for (int i = 0; i < 8; ++i) {
        for (int j = 0; j < 8; ++j) murty += i == j ? "1 " : (j < i ? "2 " : "0 ");
    }
    for (int i = 0; i < 8; ++i) murty += std::to_string(-1.0 + 0.25 * std::ldexp(1.0, -(i + 1))) + " ";
    const std::string g = writeTemp("murty.txt", murty);
    const Run capped = cli("lcp " + g + " --max-pivots 10");
    CHECK(capped.exitCode == 1);
    CHECK(nlohmann::json::parse(capped.out)["status"] == "pivot_limit");
    CHECK(cli("lcp " + g).exitCode == 0);
    std::remove(f.c_str());
    std::remove(g.c_str());
}

TEST_CASE("lcp: malformed files exit 2 with a message on stderr") {
    const std::pair<const char*, const char*> cases[] = {
        {"2 1 1 1", "ended after 4 numbers"},
        {"2 1 x 1 1 0 0", "is not a number"},
        {"1.5 1 1", "n must be an integer"},
        {"1 1 -1 7", "unexpected extra token"},
        {"1 nan -1", "not finite"},
    };
    for (const auto& item : cases) {
        const auto& text = item.first;  // no structured binding: clang 14 cannot CAPTURE one
        const auto& fragment = item.second;
        CAPTURE(text);
        const std::string f = writeTemp("bad.txt", text);
        const Run r = cli("lcp " + f);
        CHECK(r.exitCode == 2);
        CHECK(r.out.empty());
        CHECK(r.err.find(fragment) != std::string::npos);
        std::remove(f.c_str());
    }
    const Run missing = cli("lcp " + tempPath("does_not_exist.txt"));
    CHECK(missing.exitCode == 2);
    CHECK(missing.err.find("cannot open") != std::string::npos);
    CHECK(cli("lcp").exitCode == 2);
    CHECK(cli("frobnicate").exitCode == 2);
}

TEST_CASE("resolve: a 2D cradle through the command line matches the closed form") {
    const nlohmann::json in = {
        {"dimension", 2},
        {"bodies", {{{"mass", 1}, {"inertia", 0.125}, {"position", {0, 0}}, {"velocity", {1, 0}}, {"angular_velocity", 0}},
                    {{"mass", 1}, {"inertia", 0.125}, {"position", {1, 0}}},
                    {{"mass", 1}, {"inertia", 0.125}, {"position", {2, 0}}}}},
        {"contacts", {{{"a", 0}, {"b", 1}, {"point", {0.5, 0}}, {"normal", {-1, 0}}, {"restitution", 1}},
                      {{"a", 1}, {"b", 2}, {"point", {1.5, 0}}, {"normal", {-1, 0}}, {"restitution", 1}}}}};
    const std::string f = writeTemp("cradle.json", in.dump());
    const Run r = cli("resolve " + f);
    REQUIRE(r.exitCode == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["status"] == "solved");
    CHECK(j["impulses"].size() == 2);
    CHECK(j["bodies"][0]["velocity"][0].get<double>() == doctest::Approx(-1.0 / 3.0));
    CHECK(j["bodies"][1]["velocity"][0].get<double>() == doctest::Approx(2.0 / 3.0));
    CHECK(j["bodies"][2]["velocity"][0].get<double>() == doctest::Approx(2.0 / 3.0));
    std::remove(f.c_str());
}

TEST_CASE("resolve: a 3D cube on four corners through the command line") {
    nlohmann::json contacts = nlohmann::json::array();
    for (double x : {-0.5, 0.5}) {
        for (double y : {-0.5, 0.5}) {
            contacts.push_back({{"a", 1}, {"b", 0}, {"point", {x, y, 0}}, {"normal", {0, 0, 1}}, {"restitution", 0.5}});
        }
    }
    const double I = 1.0 / 6.0;
    const nlohmann::json in = {
        {"dimension", 3},
        {"bodies", {{{"static", true}, {"position", {0, 0, 0}}},
                    {{"mass", 1}, {"inertia", {{I, 0, 0}, {0, I, 0}, {0, 0, I}}}, {"position", {0, 0, 0.5}}, {"velocity", {0, 0, -2}},
                     {"angular_velocity", {0, 0, 0}}}}},
        {"contacts", contacts}};
    const std::string f = writeTemp("cube.json", in.dump());
    const Run r = cli("resolve " + f);
    REQUIRE(r.exitCode == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["bodies"][1]["velocity"][2].get<double>() == doctest::Approx(1.0));
    for (int k = 0; k < 3; ++k) CHECK(std::fabs(j["bodies"][1]["angular_velocity"][std::size_t(k)].get<double>()) < 1e-12);
    std::remove(f.c_str());
}

TEST_CASE("resolve: bad JSON and bad values exit 2 naming the key") {
    const std::pair<const char*, const char*> cases[] = {
        {"{\"dimension\": 2, \"bodies\": [", "malformed JSON"},
        {"{\"bodies\": [], \"contacts\": []}", "dimension: missing"},
        {"{\"dimension\": 4, \"bodies\": [], \"contacts\": []}", "dimension: must be an integer in [2, 3]"},
        {"{\"dimension\": 2, \"bodies\": [{\"mass\": -1, \"inertia\": 1, \"position\": [0,0]}], \"contacts\": []}",
         "bodies[0].mass: must be > 0"},
        {"{\"dimension\": 2, \"bodies\": [{\"mass\": \"x\", \"inertia\": 1, \"position\": [0,0]}], \"contacts\": []}",
         "bodies[0].mass: expected a number"},
        {"{\"dimension\": 2, \"bodies\": [{\"mass\": 1, \"inertia\": 1, \"position\": [0]}], \"contacts\": []}",
         "bodies[0].position: expected an array of 2 numbers"},
        {"{\"dimension\": 2, \"bodies\": [{\"static\": true, \"position\": [0,0]}, {\"mass\": 1, \"inertia\": 1, "
         "\"position\": [0,1]}], \"contacts\": [{\"a\": 1, \"b\": 3, \"point\": [0,0], \"normal\": [0,1]}]}",
         "contacts[0].b: must be an integer in [0, 1]"},
        {"{\"dimension\": 2, \"bodies\": [{\"static\": true, \"position\": [0,0]}, {\"mass\": 1, \"inertia\": 1, "
         "\"position\": [0,1]}], \"contacts\": [{\"a\": 1, \"b\": 0, \"point\": [0,0], \"normal\": [0,2]}]}",
         "unit length"},
        {"{\"dimension\": 3, \"bodies\": [{\"mass\": 1, \"inertia\": [[1,0,0],[0,-1,0],[0,0,1]], \"position\": [0,0,0]}], "
         "\"contacts\": []}",
         "positive definite"},
    };
    for (const auto& item : cases) {
        const auto& text = item.first;  // no structured binding: clang 14 cannot CAPTURE one
        const auto& fragment = item.second;
        CAPTURE(text);
        const std::string f = writeTemp("bad.json", text);
        const Run r = cli("resolve " + f);
        CHECK(r.exitCode == 2);
        CHECK(r.err.find(fragment) != std::string::npos);
        std::remove(f.c_str());
    }
}

TEST_CASE("run: steps a scene, prints hash lines then the final state; bad scenes exit 2") {
    const std::string scene = std::string(UNISON_SOURCE_DIR) + "/scenes/cradle.json";
    const Run r = cli("run " + scene + " --steps 4 --hash-every 2");
    REQUIRE(r.exitCode == 0);
    const std::vector<nlohmann::json> lines = jsonLines(r.out);
    REQUIRE(lines.size() == 3);
    CHECK(lines[0]["step"] == 2);
    CHECK(lines[1]["step"] == 4);
    CHECK(lines[0]["hash"].get<std::string>().size() == 16);
    CHECK(lines[2]["bodies"].size() == 5);
    CHECK(lines[2]["hash"] == lines[1]["hash"]);
    CHECK(lines[2]["bodies"][0]["linear_velocity"][0].get<double>() == doctest::Approx(-1.2));  // 2 (1 - 2 * 4/5)
    // Same command, same bytes.
    CHECK(withoutTimes(cli("run " + scene + " --steps 4 --hash-every 2").out) == withoutTimes(r.out));
    const std::pair<const char*, const char*> bad[] = {
        {"{\"dimension\": 2, \"bodies\": [{\"shapes\": [{\"type\": \"circle\", \"radius\": -1}]}]}", "radius"},
        {"{\"dimension\": 2, \"bodies\": [{\"shapes\": [{\"type\": \"polygon\", \"vertices\": [[0,0],[0,1],[1,0]]}]}]}",
         "counter-clockwise"},
        {"{\"dimension\": 2, \"bodies\": [{\"type\": \"wobbly\"}]}", "bodies[0].type"},
        {"{\"dimension\": 2, \"bodies\": [{\"position\": [0, 0]}]}", "positive mass"},
        {"{\"dimension\": 2, \"hz\": 0, \"bodies\": []}", "hz"},
        {"[1, 2", "malformed JSON"},
    };
    for (const auto& item : bad) {
        const auto& text = item.first;  // no structured binding: clang 14 cannot CAPTURE one
        const auto& fragment = item.second;
        CAPTURE(text);
        const std::string f = writeTemp("bad_scene.json", text);
        const Run b = cli("run " + f);
        CHECK(b.exitCode == 2);
        CHECK(b.err.find(fragment) != std::string::npos);
        std::remove(f.c_str());
    }
}

TEST_CASE("record, verify, diff and run --snapshot-at: files, reports and exit codes") {
    const std::string scene = std::string(UNISON_SOURCE_DIR) + "/scenes/cradle.json";
    const std::string inputs = writeTemp("inputs.json", R"({"inputs": [
        {"tick": 3, "type": "apply_impulse", "body": 4, "impulse": [-0.5, 0]},
        {"tick": 6, "type": "set_gravity", "gravity": [0, -1]}]})");
    const std::string changed = writeTemp("inputs2.json", R"({"inputs": [
        {"tick": 3, "type": "apply_impulse", "body": 4, "impulse": [-0.5, 0]},
        {"tick": 6, "type": "set_gravity", "gravity": [0, -1.5]}]})");
    const std::string rec = tempPath("m.urec"), a = tempPath("a.usnap"), b = tempPath("b.usnap");
    const Run r = cli("record " + scene + " --inputs " + inputs + " --steps 12 --snapshot-every 4 -o " + rec);
    REQUIRE(r.exitCode == 0);
    const auto summary = nlohmann::json::parse(r.out);
    CHECK(summary["steps"] == 12);
    CHECK(summary["snapshots"] == 4);  // ticks 0, 4, 8, 12
    const Run v = cli("verify " + rec);
    CHECK(v.exitCode == 0);
    CHECK(nlohmann::json::parse(v.out)["status"] == "match");
    // Replaying with a changed input: exit 1 at tick 6; with --keep-going the report names a differing field at the
    // next snapshot.
    const Run stop = cli("verify " + rec + " --inputs " + changed);
    CHECK(stop.exitCode == 1);
    CHECK(nlohmann::json::parse(stop.out)["first_desync_tick"] == 6);
    CHECK(nlohmann::json::parse(stop.out)["ticks"] == 6);
    const Run d = cli("verify " + rec + " --inputs " + changed + " --keep-going");
    CHECK(d.exitCode == 1);
    const auto report = nlohmann::json::parse(d.out);
    CHECK(report["first_desync_tick"] == 6);
    CHECK(report["compared_snapshot_tick"] == 8);
    CHECK(report["differences"].size() > 0);
    CHECK(d.err.find("desync at tick 6") != std::string::npos);
    // `run` and `record` (without inputs) hash the same state.
    const Run s5 = cli("run " + scene + " --steps 5 --snapshot-at 5 -o " + a);
    REQUIRE(s5.exitCode == 0);
    const Run r5 = cli("record " + scene + " --steps 5 -o " + rec);
    REQUIRE(r5.exitCode == 0);
    CHECK(nlohmann::json::parse(r5.out)["final_hash"] ==
          nlohmann::json::parse(s5.out)["hash"]);  // one line: the final object
    REQUIRE(cli("run " + scene + " --steps 5 --snapshot-at 4 -o " + b).exitCode == 0);
    CHECK(cli("diff " + a + " " + a).exitCode == 0);
    const Run df = cli("diff " + a + " " + b);
    CHECK(df.exitCode == 1);
    CHECK(nlohmann::json::parse(df.out)["differences"][0]["field"] == "stepCount");
    // Bad input: exit 2 with a message.
    const std::string junk = writeTemp("junk.urec", "this is not a recording, only some text that is long enough to hold a header");
    const std::pair<std::string, const char*> bad[] = {
        {"verify " + junk, "bad magic"},
        {"diff " + junk + " " + a, "snapshot rejected"},
        {"verify " + rec + "-missing", "cannot open"},
        {"run " + scene + " --steps 2 --snapshot-at 3 -o " + b, "after the last step"},
        {"record " + scene + " --inputs " + junk + " -o " + b, "malformed JSON"},
    };
    for (const auto& item : bad) {
        const auto& args = item.first;  // no structured binding: clang 14 cannot CAPTURE one
        const auto& fragment = item.second;
        CAPTURE(args);
        const Run e = cli(args);
        CHECK(e.exitCode == 2);
        CHECK(e.err.find(fragment) != std::string::npos);
    }
    for (const std::string& f : {inputs, changed, rec, a, b, junk}) std::remove(f.c_str());
}

TEST_CASE("record, verify, diff and run --snapshot-at for a 3D scene (OBJ mesh inlined into the recording)") {
    const std::string scene = std::string(UNISON_SOURCE_DIR) + "/scenes/mixed3d.json";
    const std::string inputs = writeTemp("inputs3.json", R"({"inputs": [
        {"tick": 4, "type": "apply_impulse", "body": 3, "impulse": [0.2, 0.5, -0.1], "point": [0.8, 1.6, 0]},
        {"tick": 7, "type": "set_gravity", "gravity": [0, -9, 0.5]}]})");
    const std::string changed = writeTemp("inputs3b.json", R"({"inputs": [
        {"tick": 4, "type": "apply_impulse", "body": 3, "impulse": [0.2, 0.5, -0.1], "point": [0.8, 1.6, 0]},
        {"tick": 7, "type": "set_gravity", "gravity": [0, -9, 0.6]}]})");
    const std::string flat = writeTemp("inputs3flat.json", R"({"inputs": [{"tick": 1, "type": "set_gravity", "gravity": [0, -9]}]})");
    const std::string rec = tempPath("m3.urec"), a = tempPath("a3.usnap"), b = tempPath("b3.usnap");
    const Run r = cli("record " + scene + " --inputs " + inputs + " --steps 12 --snapshot-every 4 -o " + rec);
    REQUIRE_MESSAGE(r.exitCode == 0, r.err);
    CHECK(nlohmann::json::parse(r.out)["snapshots"] == 4);
    const Run v = cli("verify " + rec);
    CHECK(v.exitCode == 0);
    CHECK(nlohmann::json::parse(v.out)["status"] == "match");
    const Run d = cli("verify " + rec + " --inputs " + changed + " --keep-going");
    CHECK(d.exitCode == 1);
    const auto report = nlohmann::json::parse(d.out);
    CHECK(report["first_desync_tick"] == 7);
    CHECK(report["compared_snapshot_tick"] == 8);
    CHECK(report["differences"].size() > 0);
    CHECK(d.err.find("desync at tick 7") != std::string::npos);
    // `run --snapshot-at` and `record` hash the same 3D state; diff names the step count first.
    const Run s5 = cli("run " + scene + " --steps 5 --snapshot-at 5 -o " + a);
    REQUIRE(s5.exitCode == 0);
    const Run r5 = cli("record " + scene + " --steps 5 -o " + rec);
    REQUIRE(r5.exitCode == 0);
    CHECK(nlohmann::json::parse(r5.out)["final_hash"] == nlohmann::json::parse(s5.out)["hash"]);
    REQUIRE(cli("run " + scene + " --steps 5 --snapshot-at 4 -o " + b).exitCode == 0);
    CHECK(cli("diff " + a + " " + a).exitCode == 0);
    const Run df = cli("diff " + a + " " + b);
    CHECK(df.exitCode == 1);
    CHECK(nlohmann::json::parse(df.out)["differences"][0]["field"] == "stepCount");
    // 2D inputs for a 3D scene, and a 2D snapshot against a 3D one: exit 2.
    const std::string flatSnap = tempPath("flat.usnap");
    REQUIRE(cli("run " + std::string(UNISON_SOURCE_DIR) + "/scenes/cradle.json --steps 1 --snapshot-at 1 -o " + flatSnap).exitCode == 0);
    const std::pair<std::string, const char*> bad[] = {
        {"record " + scene + " --inputs " + flat + " -o " + b, "gravity"},
        {"diff " + a + " " + flatSnap, "kind"},
    };
    for (const auto& item : bad) {
        const std::string& args = item.first;
        CAPTURE(args);
        const Run e = cli(args);
        CHECK(e.exitCode == 2);
        CHECK(e.err.find(item.second) != std::string::npos);
    }
    for (const std::string& f : {inputs, changed, flat, rec, a, b, flatSnap}) std::remove(f.c_str());
}

TEST_CASE("run: a 3D scene (box, hull, sphere, OBJ bunny) prints quaternions; bad 3D scenes exit 2") {
    const std::string scene = std::string(UNISON_SOURCE_DIR) + "/scenes/mixed3d.json";
    const Run r = cli("run " + scene + " --steps 120 --hash-every 60");
    REQUIRE(r.exitCode == 0);
    const std::vector<nlohmann::json> lines = jsonLines(r.out);
    REQUIRE(lines.size() == 3);
    const nlohmann::json& fin = lines[2];
    REQUIRE(fin["bodies"].size() == 5);
    CHECK(fin["bodies"][1]["orientation"].size() == 4);
    // The cube rests on the plane (centre 0.5 up) and the pyramid hull on the cube (base 0.3 below its origin).
    CHECK(fin["bodies"][1]["position"][1].get<double>() == doctest::Approx(0.5).epsilon(0.01));
    CHECK(fin["bodies"][2]["position"][1].get<double>() == doctest::Approx(1.3).epsilon(0.01));
    CHECK(fin["stats"]["failed_islands"] == 0);
    // The landing moves the active set (basis_change > 0); with no guess discarded, Lemke paid at least one pivot
    // per two changed unknowns.
    const nlohmann::json& st = fin["stats"];
    CHECK(st["basis_change"].get<int>() > 0);
    if (st["discarded_guesses"].get<int>() == 0) CHECK(2 * st["total_pivots"].get<int>() >= st["basis_change"].get<int>());
    CHECK(withoutTimes(cli("run " + scene + " --steps 120 --hash-every 60").out) == withoutTimes(r.out));
    const std::pair<const char*, const char*> bad[] = {
        {"{\"dimension\": 3, \"bodies\": [{\"shapes\": [{\"type\": \"sphere\", \"radius\": 0}]}]}", "radius"},
        {"{\"dimension\": 3, \"bodies\": [{\"shapes\": [{\"type\": \"circle\", \"radius\": 1}]}]}", "unknown 3D shape"},
        {"{\"dimension\": 3, \"bodies\": [{\"position\": [0, 0]}]}", "bodies[0].position"},
        {"{\"dimension\": 3, \"bodies\": [{\"shapes\": [{\"type\": \"mesh\", \"obj\": \"/nonexistent.obj\"}]}]}",
         "nonexistent.obj"},
        {"{\"dimension\": 3, \"bodies\": [{\"type\": \"dynamic\", \"shapes\": [{\"type\": \"plane\", \"normal\": [0, 1, 0]}]}]}",
         "planes must be static"},
    };
    for (const auto& item : bad) {
        const char* text = item.first;  // not a structured binding: clang 14 cannot capture those in CAPTURE
        const char* fragment = item.second;
        CAPTURE(text);
        const std::string f = writeTemp("bad_scene3d.json", text);
        const Run b = cli("run " + f);
        CHECK(b.exitCode == 2);
        CHECK(b.err.find(fragment) != std::string::npos);
        std::remove(f.c_str());
    }
}

}  // TEST_SUITE
