// core/det_math.cpp — see det_math.h. Everything here is + - * /, floor, fabs, signbit, ilogb and ldexp on
// doubles, evaluated in a fixed order, so the bits depend only on the input (given what fp_env.h checks).
#include "det_math.h"

#include <cmath>

namespace unison {
namespace dmath {
namespace {

// An unevaluated sum hi + lo, |lo| no larger than about an ulp of hi.
struct DoubleDouble {
    double hi;
    double lo;
};

// Knuth's TwoSum: s + e == a + b exactly, s = fl(a + b). No precondition on the magnitudes.
DoubleDouble twoSum(double a, double b) {
    const double s = a + b;
    const double bv = s - a;
    const double av = s - bv;
    return {s, (a - av) + (b - bv)};
}

// ---- constants -------------------------------------------------------------------------------------------------
// pi/2 and pi as double-doubles (hi = nearest double, lo = nearest double to the rest).
constexpr double kPio2Hi = 1.5707963267948966;
constexpr double kPio2Lo = 6.123233995736766e-17;
constexpr double kPiHi = 3.141592653589793;
constexpr double kPiLo = 1.2246467991473532e-16;
constexpr double kPio4Hi = 0.7853981633974483;  // just below pi/4
constexpr double k3Pio4 = 2.356194490192345;    // nearest double to 3 pi/4
constexpr double kTwoOverPi = 0.6366197723675814;

// Cody–Waite split of pi/2 into three 33-bit pieces plus a tail (the values fdlibm uses as pio2_1..pio2_3t).
// Because each piece has 33 significant bits, k * piece is exact for integer |k| < 2^20.
constexpr double kPio2Part1 = 1.5707963267341256;
constexpr double kPio2Part2 = 6.077100506303966e-11;
constexpr double kPio2Part3 = 2.0222662487111665e-21;
constexpr double kPio2Part3Tail = 8.4784276603689e-32;

// Taylor coefficients. Every factorial up to 22! is exact in a double, so 1.0 / n! is correctly rounded and
// identical on every compiler.
constexpr double kSin3 = -1.0 / 6.0;
constexpr double kSin5 = 1.0 / 120.0;
constexpr double kSin7 = -1.0 / 5040.0;
constexpr double kSin9 = 1.0 / 362880.0;
constexpr double kSin11 = -1.0 / 39916800.0;
constexpr double kSin13 = 1.0 / 6227020800.0;
constexpr double kSin15 = -1.0 / 1307674368000.0;
constexpr double kSin17 = 1.0 / 355687428096000.0;
constexpr double kSin19 = -1.0 / 121645100408832000.0;

constexpr double kCos4 = 1.0 / 24.0;
constexpr double kCos6 = -1.0 / 720.0;
constexpr double kCos8 = 1.0 / 40320.0;
constexpr double kCos10 = -1.0 / 3628800.0;
constexpr double kCos12 = 1.0 / 479001600.0;
constexpr double kCos14 = -1.0 / 87178291200.0;
constexpr double kCos16 = 1.0 / 20922789888000.0;
constexpr double kCos18 = -1.0 / 6402373705728000.0;
constexpr double kCos20 = 1.0 / 2432902008176640000.0;

// atan(i/8) for i = 2..16 as double-doubles, computed with 300-bit arithmetic (mpmath).
constexpr DoubleDouble kAtanTable[15] = {
    {0.24497866312686414, 1.0698755618734451e-17},   // atan(2/8)
    {0.35877067027057225, -2.4623815582638635e-17},  // atan(3/8)
    {0.4636476090008061, 2.2698777452961687e-17},    // atan(4/8)
    {0.5585993153435624, -5.4556305485916264e-18},   // atan(5/8)
    {0.6435011087932844, 1.5834785051444286e-17},    // atan(6/8)
    {0.7188299996216245, -2.1478388444456983e-17},   // atan(7/8)
    {0.7853981633974483, 3.061616997868383e-17},     // atan(8/8)
    {0.844153986113171, -4.841337011934917e-17},     // atan(9/8)
    {0.8960553845713439, 2.923876285774305e-17},     // atan(10/8)
    {0.9420000403794636, 5.4608374858466876e-17},    // atan(11/8)
    {0.982793723247329, 1.3903311031230998e-17},     // atan(12/8)
    {1.0191413442663497, 1.0004018869366799e-17},    // atan(13/8)
    {1.0516502125483738, -9.650564731467514e-17},    // atan(14/8)
    {1.0808390005411683, -1.5676322511359073e-17},   // atan(15/8)
    {1.1071487177940904, 9.40447137356638e-17},      // atan(16/8)
};

// ---- sine and cosine ---------------------------------------------------------------------------------------------

// x = quadrant * pi/2 + (hi + lo) (mod 2 pi), |hi| <= about pi/4.
struct Reduced {
    double hi;
    double lo;
    int quadrant;  // 0..3
};

// k mod 4 for an integer-valued double k of any size; every step is exact.
int quadrantOf(double k) { return static_cast<int>(k - 4.0 * std::floor(k * 0.25)); }

// a is finite and >= 0. One Cody–Waite pass is exact up to the final double-double rounding while k < 2^20
// (a <= kTrigAccurateLimit): t = a - k*part1 is exact (Sterbenz), k*part2 and k*part3 are exact and TwoSum keeps
// their rounding errors. For larger a the product k*part1 rounds (error about ulp(a)/2) and the remainder may
// exceed pi/4; I then reduce the remainder again, which converges in about 21 passes even at DBL_MAX. The answer
// then carries the error of the first pass, but stays deterministic and in [-1, 1].
Reduced reduce(double a) {
    if (a <= kPio4Hi) return {a, 0.0, 0};
    double x = a;
    int quadrant = 0;
    DoubleDouble r{0.0, 0.0};
    for (int pass = 0; pass < 64; ++pass) {
        const double k = std::floor(x * kTwoOverPi + 0.5);
        const double t = x - k * kPio2Part1;
        const DoubleDouble s1 = twoSum(t, -(k * kPio2Part2));
        const DoubleDouble s2 = twoSum(s1.hi, -(k * kPio2Part3));
        r = twoSum(s2.hi, (s1.lo + s2.lo) - k * kPio2Part3Tail);
        quadrant += quadrantOf(k);
        if (std::fabs(r.hi) <= 1.0) return {r.hi, r.lo, quadrant & 3};
        x = r.hi;
    }
    return {0.0, 0.0, quadrant & 3};  // unreachable for finite input; keeps the result bounded regardless
}

// sin(y + e) for |y| <= 1, |e| <= ulp(y): y + y^3 P(y^2) + e (1 - y^2/2), Taylor to y^19 (remainder < 2e-20 y).
double sinKernel(double y, double e) {
    const double z = y * y;
    const double p =
        kSin3 + z * (kSin5 + z * (kSin7 + z * (kSin9 + z * (kSin11 + z * (kSin13 + z * (kSin15 + z * (kSin17 +
        z * kSin19)))))));
    return y + ((y * z) * p + (e - 0.5 * z * e));
}

// cos(y + e) for |y| <= 1: 1 - y^2/2 + y^4 Q(y^2) - e y, Taylor to y^20. w = fl(1 - z/2) and (1 - w) - z/2 is its
// exact rounding error, which I add back with the small terms (the fdlibm trick).
double cosKernel(double y, double e) {
    const double z = y * y;
    const double q =
        kCos4 + z * (kCos6 + z * (kCos8 + z * (kCos10 + z * (kCos12 + z * (kCos14 + z * (kCos16 + z * (kCos18 +
        z * kCos20)))))));
    const double hz = 0.5 * z;
    const double w = 1.0 - hz;
    return w + (((1.0 - w) - hz) + ((z * z) * q - y * e));
}

double sinOfReduced(const Reduced& r) {
    switch (r.quadrant) {
        case 0: return sinKernel(r.hi, r.lo);
        case 1: return cosKernel(r.hi, r.lo);
        case 2: return -sinKernel(r.hi, r.lo);
        default: return -cosKernel(r.hi, r.lo);
    }
}

double cosOfReduced(const Reduced& r) {
    switch (r.quadrant) {
        case 0: return cosKernel(r.hi, r.lo);
        case 1: return -sinKernel(r.hi, r.lo);
        case 2: return -cosKernel(r.hi, r.lo);
        default: return sinKernel(r.hi, r.lo);
    }
}

// ---- arc tangent -----------------------------------------------------------------------------------------------

// Dekker's TwoProduct without FMA: p + e == a * b exactly as long as nothing overflows or underflows in the
// Veltkamp splits. Callers keep |a|, |b| <= 4 and each of them 0 or above 2^-900.
DoubleDouble twoProduct(double a, double b) {
    const double sa = 134217729.0 * a;  // 2^27 + 1
    const double ah = sa - (sa - a);
    const double al = a - ah;
    const double sb = 134217729.0 * b;
    const double bh = sb - (sb - b);
    const double bl = b - bh;
    const double p = a * b;
    return {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
}

// num / den as q + qLo for 0 <= num <= 2 den or den < num / 2 (so q <= 2). Scaling by a power of two is exact,
// and ns - q ds is exact once q ds is split (Sterbenz). Below 2^-900 I skip the tail: atan(q) then rounds to q.
DoubleDouble divide(double num, double den) {
    const double q = num / den;
    if (!(q >= 0x1p-900)) return {q, 0.0};
    const int e = std::ilogb(den);
    const double ds = std::ldexp(den, -e);
    const double ns = std::ldexp(num, -e);
    const DoubleDouble p = twoProduct(q, ds);
    return {q, ((ns - p.hi) - p.lo) / ds};
}

// atan(t + tLo) for |t| <= 3/16 as t + c, with c = t^3 R(t^2) + tLo / (1 + t^2) (Taylor to t^25, remainder
// < 1e-20 |t|), returned unrounded so callers can add it to a table value with one rounding.
DoubleDouble atanSmall(double t, double tLo) {
    const double z = t * t;
    const double p = -1.0 / 3.0 + z * (1.0 / 5.0 + z * (-1.0 / 7.0 + z * (1.0 / 9.0 + z * (-1.0 / 11.0 +
                     z * (1.0 / 13.0 + z * (-1.0 / 15.0 + z * (1.0 / 17.0 + z * (-1.0 / 19.0 + z * (1.0 / 21.0 +
                     z * (-1.0 / 23.0 + z * (1.0 / 25.0)))))))))));
    return {t, (t * z) * p + tLo / (1.0 + z)};
}

// atan(u + uLo) for 0 <= u <= 2 as a double-double. Below 3/16 the series is used directly; above, with c = i/8
// the nearest table point, atan(u) = atan(c) + atan((u - c) / (1 + c u)) and |(u - c) / (1 + c u)| <= 1/16.
// u - c is exact (Sterbenz, c >= 1/4), and I form 1 + c u and the quotient as double-doubles, so the only
// rounding that reaches the answer is the last addition.
DoubleDouble atanReduced(double u, double uLo) {
    const int i = static_cast<int>(std::floor(u * 8.0 + 0.5));
    if (i < 2) return atanSmall(u, uLo);
    const double c = 0.125 * i;
    const DoubleDouble n = twoSum(u - c, uLo);
    const DoubleDouble cu = twoProduct(c, u);
    const DoubleDouble d = twoSum(1.0, cu.hi);
    const double dLo = d.lo + cu.lo;
    const double t = n.hi / d.hi;
    const DoubleDouble td = twoProduct(t, d.hi);
    const double tLo = ((((n.hi - td.hi) - td.lo) + n.lo) - t * dLo) / d.hi;  // (n - t d) / d
    const DoubleDouble p = atanSmall(t, tLo);
    const DoubleDouble& base = kAtanTable[i - 2];
    const DoubleDouble s = twoSum(base.hi, p.hi);
    return {s.hi, s.lo + (p.lo + base.lo)};
}

// atan(num / den) for num, den >= 0, not both zero and not both infinite. Above a ratio of 2 I use
// atan(q) = pi/2 - atan(1/q) and divide the other way round.
DoubleDouble atanOfRatio(double num, double den) {
    if (!std::isinf(num) && num <= den * 2.0) {  // den * 2 may overflow to inf; the test still holds then
        const DoubleDouble q = divide(num, den);
        return atanReduced(q.hi, q.lo);
    }
    const DoubleDouble q = divide(den, num);
    const DoubleDouble p = atanReduced(q.hi, q.lo);
    const DoubleDouble s = twoSum(kPio2Hi, -p.hi);
    return {s.hi, s.lo + (kPio2Lo - p.lo)};
}

}  // namespace

double sin(double x) {
    const double a = std::fabs(x);
    if (!(a <= 1.7976931348623157e308)) return x - x;  // NaN for NaN and ±inf
    const double s = sinOfReduced(reduce(a));
    return std::signbit(x) ? -s : s;
}

double cos(double x) {
    const double a = std::fabs(x);
    if (!(a <= 1.7976931348623157e308)) return x - x;
    return cosOfReduced(reduce(a));
}

void sincos(double x, double* outSin, double* outCos) {
    const double a = std::fabs(x);
    if (!(a <= 1.7976931348623157e308)) {
        *outSin = x - x;
        *outCos = x - x;
        return;
    }
    const Reduced r = reduce(a);
    const double s = sinOfReduced(r);
    *outSin = std::signbit(x) ? -s : s;
    *outCos = cosOfReduced(r);
}

double atan(double x) {
    if (x != x) return x + x;
    const DoubleDouble r = atanOfRatio(std::fabs(x), 1.0);
    const double a = r.hi + r.lo;
    return std::signbit(x) ? -a : a;
}

double atan2(double y, double x) {
    if (x != x || y != y) return x + y;
    const double ax = std::fabs(x);
    const double ay = std::fabs(y);
    const bool xNegative = std::signbit(x);
    double angle;  // in [0, pi]; the sign of y is applied last
    if (ay == 0.0) {
        angle = xNegative ? kPiHi : 0.0;  // atan2(±0, -0) = ±pi, atan2(±0, +0) = ±0
    } else if (std::isinf(ax) && std::isinf(ay)) {
        angle = xNegative ? k3Pio4 : kPio4Hi;
    } else {
        const DoubleDouble r = atanOfRatio(ay, ax);
        if (xNegative) {
            const DoubleDouble s = twoSum(kPiHi, -r.hi);
            angle = s.hi + (s.lo + (kPiLo - r.lo));
        } else {
            angle = r.hi + r.lo;
        }
    }
    return std::signbit(y) ? -angle : angle;
}

}  // namespace dmath
}  // namespace unison
