// tests/test_det_math.cpp — accuracy, symmetry, special values and bit-exactness of core/det_math, and the
// start-up checks of core/fp_env. The reference is libm in long double (on x86-64 a 64-bit mantissa, so the
// measured error is the error of our functions, not of libm's); where long double is just double, the bounds
// get half an ulp of slack for libm's own rounding.
#include "det_math.h"
#include "fp_env.h"

#include <doctest/doctest.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <string>

#if defined(__SSE2__) || defined(_M_X64)
#include <xmmintrin.h>
#endif

namespace dm = unison::dmath;

TEST_SUITE_BEGIN("det_math");

namespace {

constexpr double kRefSlack = LDBL_MANT_DIG > DBL_MANT_DIG ? 0.0 : 0.5;  // ulps
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::uint64_t bitsOf(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

// Spacing of doubles at the reference value (2^-1074 in the subnormal range).
double ulpAt(long double ref) {
    const double d = std::fabs(static_cast<double>(ref));
    if (d < DBL_MIN) return std::ldexp(1.0, -1074);
    return std::ldexp(1.0, std::ilogb(d) - 52);
}

struct ErrorStats {
    double maxUlp = 0.0;
    double maxAbs = 0.0;
    double worstX = 0.0;
    void add(double x, double got, long double ref) {
        const long double diff = std::fabs(static_cast<long double>(got) - ref);
        const double ulps = static_cast<double>(diff / ulpAt(ref));
        if (ulps > maxUlp) {
            maxUlp = ulps;
            worstX = x;
        }
        if (static_cast<double>(diff) > maxAbs) maxAbs = static_cast<double>(diff);
    }
};

// Measures sin and cos on n + 1 evenly spaced points of [-range, range]; counts the points where sincos differs
// from sin/cos, a symmetry is not bit-exact, or sin^2 + cos^2 is off by more than 4e-16.
int sweepSinCos(double range, int n, ErrorStats& sinStats, ErrorStats& cosStats) {
    int failures = 0;
    for (int i = 0; i <= n; ++i) {
        const double x = -range + (2.0 * range) * i / n;
        const double s = dm::sin(x);
        const double c = dm::cos(x);
        sinStats.add(x, s, std::sin(static_cast<long double>(x)));
        cosStats.add(x, c, std::cos(static_cast<long double>(x)));
        double s2 = 0.0, c2 = 0.0;
        dm::sincos(x, &s2, &c2);
        const bool ok = bitsOf(s2) == bitsOf(s) && bitsOf(c2) == bitsOf(c) && bitsOf(dm::sin(-x)) == bitsOf(-s) &&
                        bitsOf(dm::cos(-x)) == bitsOf(c) && std::fabs(s * s + c * c - 1.0) <= 4e-16;
        if (!ok) ++failures;
    }
    return failures;
}

// FNV-1a over the bits of every result: a golden value pins the exact outputs on every platform and build.
struct BitHash {
    std::uint64_t h = 1469598103934665603ull;
    void add(double v) {
        const std::uint64_t b = bitsOf(v);
        for (int i = 0; i < 8; ++i) h = (h ^ ((b >> (8 * i)) & 0xffu)) * 1099511628211ull;
    }
};

}  // namespace

TEST_CASE("det_math: sin and cos within 1 ulp on [-100, 100] and [-1e5, 1e5]") {
    ErrorStats s100, c100, s1e5, c1e5;
    CHECK(sweepSinCos(100.0, 200000, s100, c100) == 0);
    CHECK(sweepSinCos(1e5, 200000, s1e5, c1e5) == 0);
    MESSAGE("[-100,100]: sin " << s100.maxUlp << " ulp (abs " << s100.maxAbs << "), cos " << c100.maxUlp
                               << " ulp (abs " << c100.maxAbs << ")");
    MESSAGE("[-1e5,1e5]: sin " << s1e5.maxUlp << " ulp (abs " << s1e5.maxAbs << "), cos " << c1e5.maxUlp
                               << " ulp (abs " << c1e5.maxAbs << ")");
    // Measured on x86-64: at most 0.78 ulp and 8.6e-17 absolute.
    for (const ErrorStats* e : {&s100, &c100, &s1e5, &c1e5}) {
        CHECK(e->maxUlp <= 1.0 + kRefSlack);
        CHECK(e->maxAbs <= 1.2e-16);
    }
}

TEST_CASE("det_math: sin and cos near multiples of pi/2 and at the edge of the accurate range") {
    ErrorStats s, c;
    for (int k = -100000; k <= 100000; k += 7) {
        double x = k * (dm::kPi / 2);
        for (int step = 0; step < 4; ++step, x = std::nextafter(x, kInf)) {
            s.add(x, dm::sin(x), std::sin(static_cast<long double>(x)));
            c.add(x, dm::cos(x), std::cos(static_cast<long double>(x)));
        }
    }
    ErrorStats edge;
    for (int i = 0; i <= 20000; ++i) {
        const double x = dm::kTrigAccurateLimit * (1.0 - i * 1e-6);
        edge.add(x, dm::sin(x), std::sin(static_cast<long double>(x)));
        edge.add(x, dm::cos(x), std::cos(static_cast<long double>(x)));
    }
    MESSAGE("near k pi/2: sin " << s.maxUlp << " ulp, cos " << c.maxUlp << " ulp; near 1.6e6: " << edge.maxUlp);
    CHECK(s.maxUlp <= 1.0 + kRefSlack);  // relative accuracy even where the result is tiny
    CHECK(c.maxUlp <= 1.0 + kRefSlack);
    CHECK(edge.maxUlp <= 1.0 + kRefSlack);
}

TEST_CASE("det_math: beyond the accurate range sin and cos degrade gracefully and stay in [-1, 1]") {
    double worstRelative = 0.0;  // absolute error / |x|
    for (int i = 0; i <= 20000; ++i) {
        const double x = std::ldexp(1.0 + i / 20000.0, 21 + i % 31);  // 2^21 .. 2^52
        const double ref = static_cast<double>(std::sin(static_cast<long double>(x)));
        worstRelative = std::fmax(worstRelative, std::fabs(dm::sin(x) - ref) / x);
    }
    MESSAGE("|x| in [2^21, 2^53): max |error| / |x| = " << worstRelative);
    CHECK(worstRelative <= 0x1p-52);
    for (double x : {1e16, 1e100, 1e300, DBL_MAX, -DBL_MAX, 0x1p1023 * 1.5}) {
        const double s = dm::sin(x), c = dm::cos(x);
        CHECK(std::fabs(s) <= 1.0);
        CHECK(std::fabs(c) <= 1.0);
        CHECK(bitsOf(dm::sin(-x)) == bitsOf(-s));
    }
}

TEST_CASE("det_math: sin and cos special values") {
    CHECK(bitsOf(dm::sin(0.0)) == bitsOf(0.0));
    CHECK(bitsOf(dm::sin(-0.0)) == bitsOf(-0.0));
    CHECK(dm::cos(0.0) == 1.0);
    CHECK(dm::cos(-0.0) == 1.0);
    for (double tiny : {1e-300, DBL_MIN, std::numeric_limits<double>::denorm_min(), 1e-9}) {
        CHECK(dm::sin(tiny) == std::sin(tiny));
        CHECK(dm::sin(-tiny) == -std::sin(tiny));
        CHECK(dm::cos(tiny) == std::cos(tiny));
    }
    CHECK(dm::sin(dm::kPi) == std::sin(dm::kPi));  // 1.2246e-16, the error of kPi itself
    CHECK(dm::cos(dm::kPi) == -1.0);
    CHECK(dm::sin(dm::kPi / 2) == 1.0);
    for (double bad : {kInf, -kInf, kNaN}) {
        CHECK(std::isnan(dm::sin(bad)));
        CHECK(std::isnan(dm::cos(bad)));
        double s = 0.0, c = 0.0;
        dm::sincos(bad, &s, &c);
        CHECK((std::isnan(s) && std::isnan(c)));
    }
}

TEST_CASE("det_math: atan within 0.6 ulp, odd, with exact special values") {
    ErrorStats stats;
    int oddFailures = 0;
    for (int i = 0; i <= 200000; ++i) {
        const double x = std::ldexp(1.0 + (i / 80) / 2500.0, -40 + i % 80);  // 2^-40 .. 2^40
        const double a = dm::atan(x);
        stats.add(x, a, std::atan(static_cast<long double>(x)));
        if (bitsOf(dm::atan(-x)) != bitsOf(-a)) ++oddFailures;
    }
    CHECK(oddFailures == 0);
    for (int i = 0; i <= 200000; ++i) {
        const double x = -10.0 + 20.0 * i / 200000;
        stats.add(x, dm::atan(x), std::atan(static_cast<long double>(x)));
    }
    MESSAGE("atan: " << stats.maxUlp << " ulp (abs " << stats.maxAbs << ") worst at " << stats.worstX);
    CHECK(stats.maxUlp <= 0.6 + kRefSlack);  // measured 0.52
    CHECK(bitsOf(dm::atan(0.0)) == bitsOf(0.0));
    CHECK(bitsOf(dm::atan(-0.0)) == bitsOf(-0.0));
    CHECK(dm::atan(kInf) == dm::kPi / 2);
    CHECK(dm::atan(-kInf) == -dm::kPi / 2);
    CHECK(dm::atan(1.0) == dm::kPi / 4);
    CHECK(dm::atan(1e-300) == 1e-300);
    CHECK(dm::atan(std::numeric_limits<double>::denorm_min()) == std::numeric_limits<double>::denorm_min());
    CHECK(dm::atan(DBL_MAX) == dm::kPi / 2);
    CHECK(std::isnan(dm::atan(kNaN)));
}

TEST_CASE("det_math: atan2 within 0.6 ulp over all quadrants and scales") {
    ErrorStats stats;
    std::uint64_t state = 88172645463325252ull;  // xorshift64: a fixed, portable sequence
    auto next = [&state] {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        return state;
    };
    auto draw = [&next] {
        const double mantissa = static_cast<double>(static_cast<std::int64_t>(next() % 2000001) - 1000000) / 1e6;
        return std::ldexp(mantissa, static_cast<int>(next() % 64) - 32);
    };
    for (int i = 0; i < 400000; ++i) {
        const double y = draw(), x = draw();
        stats.add(y, dm::atan2(y, x), std::atan2(static_cast<long double>(y), static_cast<long double>(x)));
    }
    MESSAGE("atan2: " << stats.maxUlp << " ulp (abs " << stats.maxAbs << ")");
    CHECK(stats.maxUlp <= 0.6 + kRefSlack);  // measured 0.53

    // Quadrants: the angle of (cos t, sin t) comes back as t, with the right sign.
    double worstRoundTrip = 0.0;
    int signFailures = 0;
    for (int i = -3141; i <= 3141; ++i) {
        const double t = i * 1e-3;
        const double back = dm::atan2(dm::sin(t), dm::cos(t));
        worstRoundTrip = std::fmax(worstRoundTrip, std::fabs(back - t));
        if (std::signbit(back) != std::signbit(t)) ++signFailures;
    }
    CHECK(worstRoundTrip <= 1e-15);
    CHECK(signFailures == 0);
}

TEST_CASE("det_math: atan2 special values follow C99 / libm") {
    const double values[] = {0.0, -0.0, std::numeric_limits<double>::denorm_min(), -1e-300, 0.5, -1.0, 3.0,
                             -1e300, DBL_MAX, kInf, -kInf, kNaN};
    for (double y : values) {
        for (double x : values) {
            const double got = dm::atan2(y, x);
            const double ref = std::atan2(y, x);
            CAPTURE(y);
            CAPTURE(x);
            if (std::isnan(ref)) {
                CHECK(std::isnan(got));
                continue;
            }
            CHECK(std::signbit(got) == std::signbit(ref));
            const bool exactCase = y == 0.0 || x == 0.0 || std::isinf(x) || std::isinf(y);
            if (exactCase) CHECK(bitsOf(got) == bitsOf(ref));
            else CHECK(std::fabs(got - ref) <= 2.0 * ulpAt(ref));
        }
    }
    CHECK(dm::atan2(0.0, -0.0) == dm::kPi);
    CHECK(dm::atan2(-0.0, -0.0) == -dm::kPi);
    CHECK(bitsOf(dm::atan2(-0.0, 0.0)) == bitsOf(-0.0));
    CHECK(dm::atan2(kInf, -kInf) == 3 * dm::kPi / 4);
    CHECK(dm::atan2(-1.0, -1.0) == -3 * dm::kPi / 4);
    CHECK(dm::atan2(1.0, 0.0) == dm::kPi / 2);
}

TEST_CASE("det_math: golden hash of outputs (same bits on every platform and optimisation level)") {
    BitHash hash;
    for (int i = 0; i <= 100000; ++i) {
        const double x = -1e4 + 0.2 * i + 1e-7 * (i % 13);
        double s = 0.0, c = 0.0;
        dm::sincos(x, &s, &c);
        hash.add(s);
        hash.add(c);
        hash.add(dm::atan(x * 1e-3));
        hash.add(dm::atan2(s, x * 1e-4));
    }
    MESSAGE("det_math golden hash: " << hash.h);
    CHECK(hash.h == 13878176604028143169ull);
}

TEST_CASE("fp_env: this machine is fit for deterministic simulation") {
    CHECK(unison::denormalsPreserved());
    CHECK(unison::checkFloatingPointEnvironment() == "");
    CHECK_NOTHROW(unison::requireDeterministicFloatingPoint());
}

#if defined(__SSE2__) || defined(_M_X64)
TEST_CASE("fp_env: flush-to-zero and denormals-are-zero are detected") {
    const unsigned saved = _mm_getcsr();
    for (unsigned bits : {0x8000u, 0x0040u, 0x8040u}) {  // FTZ, DAZ, both
        _mm_setcsr(saved | bits);
        const bool preserved = unison::denormalsPreserved();
        const std::string message = unison::checkFloatingPointEnvironment();
        bool threw = false;
        try {
            unison::requireDeterministicFloatingPoint();
        } catch (const std::runtime_error&) {
            threw = true;
        }
        _mm_setcsr(saved);
        CAPTURE(bits);
        CHECK_FALSE(preserved);
        CHECK(message.find("subnormal") != std::string::npos);
        CHECK(threw);
    }
    CHECK(unison::denormalsPreserved());
}
#endif

TEST_SUITE_END();
