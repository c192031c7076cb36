// core/fp_env.cpp — see fp_env.h. Every probe goes through volatile variables so the compiler cannot fold it at
// build time: I want what the processor does now, not what the compiler assumed.
#include "fp_env.h"

#include <cfenv>
#include <cfloat>
#include <stdexcept>

#if defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2)
#include <xmmintrin.h>
#define UNISON_HAS_MXCSR 1
#endif

namespace unison {
namespace {

#if defined(UNISON_HAS_MXCSR)
constexpr unsigned kMxcsrFlushToZero = 0x8000u;        // FTZ, bit 15: subnormal results become 0
constexpr unsigned kMxcsrDenormalsAreZero = 0x0040u;   // DAZ, bit 6: subnormal inputs read as 0
constexpr unsigned kMxcsrRoundingControl = 0x6000u;    // RC, bits 13-14: 00 = round to nearest
#endif

// a * b - c with a = 1 + 2^-30: rounding a*b first gives 0, a fused multiply-add gives 2^-60.
bool multiplyAddIsContracted() {
    volatile double a = 1.0 + 0x1p-30;
    volatile double c = 1.0 + 0x1p-29;
    const double va = a;
    const double vc = c;
    volatile double r = va * va - vc;
    return r != 0.0;
}

}  // namespace

bool denormalsPreserved() {
    volatile double smallest = DBL_MIN;  // smallest normal, 2^-1022
    volatile double half = smallest / 2.0;  // flushed to 0 under FTZ
    volatile double back = half * 2.0;      // 0 under DAZ, which reads `half` as 0
    bool ok = half != 0.0 && back == DBL_MIN;
#if defined(UNISON_HAS_MXCSR)
    ok = ok && (_mm_getcsr() & (kMxcsrFlushToZero | kMxcsrDenormalsAreZero)) == 0;
#endif
    return ok;
}

std::string checkFloatingPointEnvironment() {
    std::string problems;
#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
    problems += "FLT_EVAL_METHOD is not 0: intermediates carry excess precision (x87?); build with SSE2 math "
                "(-msse2 -mfpmath=sse) so results do not depend on register spills.\n";
#endif
#if defined(__FAST_MATH__)
    problems += "built with -ffast-math: the compiler may reorder and contract floating-point operations.\n";
#endif
    if (multiplyAddIsContracted())
        problems += "a*b-c was fused into one multiply-add: build with -ffp-contract=off.\n";
    if (std::fegetround() != FE_TONEAREST)
        problems += "the rounding mode is not round-to-nearest (fegetround).\n";
#if defined(UNISON_HAS_MXCSR)
    if ((_mm_getcsr() & kMxcsrRoundingControl) != 0)
        problems += "the SSE rounding mode (MXCSR.RC) is not round-to-nearest.\n";
#endif
    if (!denormalsPreserved())
        problems += "subnormal numbers are flushed to zero (FTZ/DAZ, e.g. set by -ffast-math or a library); "
                    "results would differ from machines that keep them.\n";
    return problems;
}

void requireDeterministicFloatingPoint() {
    const std::string problems = checkFloatingPointEnvironment();
    if (!problems.empty()) throw std::runtime_error("unison: floating-point environment unfit for deterministic "
                                                    "simulation:\n" + problems);
}

}  // namespace unison
