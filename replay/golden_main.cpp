// replay/golden_main.cpp — `unison_golden`: steps the golden scenes and prints one line per scene,
// "NAME STEPS FINAL_HASH CHAIN_HASH", where CHAIN_HASH is the XXH3 of every tick's hash (so one value covers the
// whole run). It also snapshots each scene at tick steps/3, restores it into a fresh world and continues; a tick
// whose hash then differs is an error (exit 1). scripts/determinism.sh runs it in every build (also aarch64 under
// qemu) and compares the lines.
// Usage: unison_golden [--cpp]   (--cpp prints the expected-hash table of tests/test_replay.cpp instead)
#include "fp_env.h"
#include "golden.h"
#include "recording.h"

#include <cstring>
#include <iostream>

int main(int argc, char** argv) {
    using namespace unison;
    const bool cpp = argc > 1 && std::strcmp(argv[1], "--cpp") == 0;
    const std::string env = checkFloatingPointEnvironment();
    if (!env.empty()) {
        std::cerr << "error: " << env << "\n";
        return 2;
    }
    try {
        for (const replay::GoldenScene& g : replay::goldenScenes()) {
            const std::vector<std::uint64_t> hashes = replay::goldenHashes(g);
            const std::uint64_t all = replay::chainHash(hashes);
            const int bad = replay::firstRestoreMismatch(g, hashes);
            if (bad >= 0) {
                std::cerr << "error: " << g.name << ": after a snapshot and restore, tick " << bad << " differs\n";
                return 1;
            }
            if (cpp) {
                std::cout << "    {\"" << g.name << "\", " << g.steps << ", 0x" << replay::hexHash(hashes.back())
                          << "ull, 0x" << replay::hexHash(all) << "ull},\n";
            } else {
                std::cout << g.name << " " << g.steps << " " << replay::hexHash(hashes.back()) << " "
                          << replay::hexHash(all) << "\n";
            }
        }
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 2;
    }
    return 0;
}
