// fuzz/fuzz_resolve.cpp — the resolve JSON and `unison resolve` (samples/cli_resolve.cpp): parse, resolve, and the
// answer printed never holds a NaN or an infinity.
#include "cli.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace unison;
    try {
        const cli::CommandOutput out = cli::runResolve(jsonio::parseJson(fuzz::text(data, size), "fuzz"), "fuzz");
        fuzz::require(jsonio::allFinite(out.json), "resolve output is finite");
    } catch (const jsonio::JsonError&) {
    }
    return 0;
}
