// samples/cli_lcp.cpp — `unison lcp FILE`: the LCP text format and the solver's JSON report.
#include "cli.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace unison::cli {

Lcp parseLcpText(const std::string& text, const std::string& what) {
    std::istringstream in(text);
    std::string token;
    std::size_t count = 0;
    auto next = [&](const char* expecting) -> double {
        if (!(in >> token)) {
            throw InputError(what + ": ended after " + std::to_string(count) + " numbers, expected " + expecting);
        }
        ++count;
        errno = 0;
        char* end = nullptr;
        const double v = std::strtod(token.c_str(), &end);
        if (end == token.c_str() || *end != '\0' || errno == ERANGE) {
            throw InputError(what + ": token " + std::to_string(count) + " (\"" + token + "\") is not a number");
        }
        if (!std::isfinite(v)) throw InputError(what + ": token " + std::to_string(count) + " is not finite");
        return v;
    };
    const double nd = next("the size n");
    if (nd != std::floor(nd) || nd < 0 || nd > 20000) throw InputError(what + ": n must be an integer in [0, 20000]");
    const int n = int(nd);
    Lcp lcp(n);
    for (auto& a : lcp.A) a = next("the n*n entries of A");
    for (auto& b : lcp.b) b = next("the n entries of b");
    if (in >> token) throw InputError(what + ": unexpected extra token \"" + token + "\" after b");
    return lcp;
}

CommandOutput runLcp(const Lcp& lcp, int maxPivots) {
    LcpOptions options;
    options.maxPivots = maxPivots;
    LemkeSolver solver;
    const LcpResult r = solver.solve(lcp, options);
    if (r.status == LcpStatus::invalid_input) throw InputError(r.message);
    CommandOutput out;
    out.json = {{"status", statusName(r.status)}, {"pivots", r.pivots}, {"z", r.z}, {"w", r.w}, {"residual", r.residual},
                {"scaled_residual", r.scaledResidual}, {"work", r.work}};
    if (!r.message.empty()) out.json["message"] = r.message;
    out.exitCode = r.status == LcpStatus::solved ? 0 : 1;
    return out;
}

}  // namespace unison::cli
