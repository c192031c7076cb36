// samples/cli_lcp.cpp — `unison lcp FILE`: the LCP text format and the solver's JSON report.
#include "cli.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace unison::cli {

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

// The whitespace-separated tokens of a text, one at a time, without copying the text.
class Tokens {
public:
    explicit Tokens(const std::string& text) : mPos(text.data()), mEnd(text.data() + text.size()) {}
    /// The next token as [begin, end), or false at the end.
    bool next(const char** begin, const char** end) {
        while (mPos < mEnd && isSpace(*mPos)) ++mPos;
        if (mPos == mEnd) return false;
        *begin = mPos;
        while (mPos < mEnd && !isSpace(*mPos)) ++mPos;
        *end = mPos;
        return true;
    }

private:
    const char* mPos;
    const char* mEnd;
};

}  // namespace

Lcp parseLcpText(const std::string& text, const std::string& what) {
    // Count first, allocate after: a 12-byte file declaring n = 20000 must not reserve 3 GB.
    std::size_t total = 0;
    {
        Tokens scan(text);
        const char *b, *e;
        while (scan.next(&b, &e)) ++total;
    }
    Tokens in(text);
    std::size_t count = 0;
    auto next = [&](double limit) -> double {
        const char *b = nullptr, *e = nullptr;
        in.next(&b, &e);
        ++count;
        const std::string token(b, e);  // short: a number
        errno = 0;
        char* end = nullptr;
        const double v = std::strtod(token.c_str(), &end);
        const std::string where = what + ": token " + std::to_string(count);
        if (token.size() > 64 || end != token.c_str() + token.size() || errno == ERANGE)
            throw InputError(where + " is not a number");
        if (!std::isfinite(v)) throw InputError(where + " is not finite");
        if (std::fabs(v) > limit) throw InputError(where + " must be in " + jsonio::rangeText(-limit, limit));
        return v;
    };
    if (total == 0) throw InputError(what + ": ended after 0 numbers, expected the size n");
    const double nd = next(HUGE_VAL);
    const std::size_t maxN = policy::kMaxLcpSize;
    if (nd != std::floor(nd) || nd < 0 || nd > double(maxN))
        throw InputError(what + ": n must be an integer in [0, " + std::to_string(maxN) + "]");
    const std::size_t n = std::size_t(nd);
    const std::size_t needed = 1 + n * n + n;
    if (total < needed)
        throw InputError(what + ": ended after " + std::to_string(total) + " numbers, expected " +
                         (total < 1 + n * n ? "the n*n entries of A" : "the n entries of b"));
    if (total > needed)
        throw InputError(what + ": unexpected extra token (number " + std::to_string(needed + 1) + ") after b");
    Lcp lcp{int(n)};
    for (auto& a : lcp.A) a = next(policy::kMaxLcpEntry);
    for (auto& b : lcp.b) b = next(policy::kMaxLcpEntry);
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
    if (!jsonio::allFinite(out.json)) {
        // Bounded entries keep this from happening; if it does, say so instead of printing null.
        out.json = {{"status", statusName(LcpStatus::numerical_failure)}, {"pivots", r.pivots},
                    {"message", "the answer overflowed (non-finite z, w or residual)"}};
        out.exitCode = 1;
    }
    return out;
}

}  // namespace unison::cli
