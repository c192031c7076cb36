// fuzz/fuzz_recording.cpp — recordings (replay/recording.cpp). The fuzzer's bytes are a recording without its
// checksum; the target appends the right one, so mutations reach the parser behind it (counts, blobs, the scene and
// inputs JSON, snapshots) instead of stopping at "checksum mismatch". Short recordings are then verified.
#include "fuzz_support.h"
#include "recording.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace unison;
    std::vector<std::uint8_t> bytes(data, data + size);
    const std::uint64_t sum = hash64(bytes.data(), bytes.size());
    for (int i = 0; i < 8; ++i) bytes.push_back(std::uint8_t(sum >> (8 * i)));
    try {
        const replay::Recording rec = replay::parseRecording(bytes, "fuzz");
        if (rec.steps <= 40) {
            replay::verify(rec, false);
            replay::verify(rec, true);
        }
    } catch (const jsonio::JsonError&) {
    }
    return 0;
}
