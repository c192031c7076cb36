// fuzz/fuzz_lcp.cpp — the LCP text format and `unison lcp` (samples/cli_lcp.cpp): parse, solve (at most 2000
// pivots), and the answer printed never holds a NaN or an infinity.
#include "cli.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace unison;
    try {
        const cli::CommandOutput out = cli::runLcp(cli::parseLcpText(fuzz::text(data, size), "fuzz"), 2000);
        fuzz::require(jsonio::allFinite(out.json), "lcp output is finite");
        fuzz::require(out.exitCode == 0 || out.exitCode == 1, "lcp exit code is 0 or 1");
    } catch (const jsonio::JsonError&) {
    }
    return 0;
}
