/* The square root for a core without a floating-point unit and without a C library
 * (RISC-V rv32imac, -nostdlib): sqrtf() and sqrt(), correctly rounded (round to nearest),
 * in integer arithmetic only.
 *
 * Why these two names and not a macro. edmi.c's default EDMI_SQRT is __builtin_sqrtf /
 * __builtin_sqrt; on a core with no FPU GCC lowers it to a call to sqrtf / sqrt, which is
 * what a C library would supply. Supplying exactly those two functions keeps edmi.c and
 * edmi.h untouched (no macro to define, no config header), works for either EDMI_REAL, and
 * leaves a firmware team free to link their own libm instead. Correct rounding matters: with
 * it, a float build on rv32imac takes bit-for-bit the same square roots as a Cortex-M4F's
 * VSQRT.F32 (IEEE 754 requires sqrt to be correctly rounded), so results match across targets.
 *
 * Method: digit-by-digit (restoring) square root, two radicand bits per step. For a finite
 * x > 0 write x = m 2^(e-p+1) with the integer significand m in [2^(p-1), 2^p) (subnormals
 * normalised first) and p = 24 or 53. If e is odd, double m and decrement e. Then
 * sqrt(x) = floor-or-ceil(sqrt(m 2^(p-1))) 2^(e/2 - p + 1): the integer root R of
 * m 2^(p-1) has exactly p bits. The remainder rem = m 2^(p-1) - R^2 decides the rounding:
 * sqrt > R + 1/2 exactly when rem > R (rem, R integers; (R + 1/2)^2 = R^2 + R + 1/4 is never
 * an integer, so there are no ties). R + 1 = 2^p carries into the exponent by itself.
 * The remainder stays below 2^(p+2), so 64-bit integers suffice for double.
 * Special cases as IEEE 754: sqrt(+-0) = +-0, sqrt(+inf) = +inf, sqrt(NaN) = quiet NaN,
 * sqrt(x < 0) = the default NaN. There are no FP exception flags in software and errno is
 * not set (edmi is built with -fno-math-errno and never passes a negative argument).
 *
 * Checked against the host's libm (IEEE-correct) by port/sqrtcheck.c (`make check-port`).
 * Compile with -DTGT_SQRTF_NAME=... -DTGT_SQRT_NAME=... to give the functions other names
 * (the host check does, so that they do not collide with libm). */
#include <stdint.h>

#ifndef TGT_SQRTF_NAME
#define TGT_SQRTF_NAME sqrtf
#endif
#ifndef TGT_SQRT_NAME
#define TGT_SQRT_NAME sqrt
#endif

float TGT_SQRTF_NAME(float x);
double TGT_SQRT_NAME(double x);

/* floor(sqrt(m 2^k)) for m 2^k < 4^pairs; *rem = m 2^k - root^2. */
static uint64_t tgt_isqrt(uint64_t m, int k, int pairs, uint64_t *rem_out)
{
    uint64_t rem = 0, root = 0;
    int i;
    for (i = pairs - 1; i >= 0; i--) {
        int j = 2 * i - k; /* position in m of the lower bit of radicand pair i */
        uint64_t pair, trial;
        if (j >= 0)
            pair = (m >> j) & 3u;
        else if (j == -1)
            pair = (m << 1) & 2u;
        else
            pair = 0;
        rem = (rem << 2) | pair;
        trial = (root << 2) | 1u;
        root <<= 1;
        if (rem >= trial) {
            rem -= trial;
            root |= 1u;
        }
    }
    *rem_out = rem;
    return root;
}

/* Significand m (p bits, leading bit set) and unbiased exponent e of a finite non-zero
 * magnitude given by its biased exponent field and fraction field. */
static void tgt_normalise(uint64_t frac, int bexp, int p, int bias, uint64_t *m, int *e)
{
    if (bexp == 0) { /* subnormal: frac 2^(1-bias-p+1) */
        *e = 1 - bias;
        while ((frac >> (p - 1)) == 0) {
            frac <<= 1;
            (*e)--;
        }
        *m = frac;
    } else {
        *m = frac | ((uint64_t)1 << (p - 1));
        *e = bexp - bias;
    }
}

/* sqrt of the positive finite value (m, e); returns the result's bit pattern without sign. */
static uint64_t tgt_sqrt_bits(uint64_t m, int e, int p, int bias)
{
    uint64_t root, rem;
    if (e & 1) { /* odd, also for negative e in two's complement */
        m <<= 1;
        e -= 1;
    }
    root = tgt_isqrt(m, p - 1, p, &rem);
    if (rem > root)
        root++;
    /* root = 1.f 2^(p-1) (or 2^p after the carry): the leading bit adds 1 to the field. */
    return ((uint64_t)(e / 2 + bias - 1) << (p - 1)) + root;
}

float TGT_SQRTF_NAME(float x)
{
    union {
        float f;
        uint32_t u;
    } v;
    uint64_t m;
    int e, bexp;
    v.f = x;
    bexp = (int)((v.u >> 23) & 0xFFu);
    if ((v.u & 0x7FFFFFFFu) == 0)
        return x; /* +-0 */
    if (bexp == 0xFF) {
        if (v.u & 0x007FFFFFu) { /* NaN: quiet it */
            v.u |= 0x00400000u;
            return v.f;
        }
        if ((v.u >> 31) == 0)
            return x; /* +inf */
    }
    if (v.u >> 31) { /* x < 0 (incl. -inf): default NaN */
        v.u = 0x7FC00000u;
        return v.f;
    }
    tgt_normalise(v.u & 0x007FFFFFu, bexp, 24, 127, &m, &e);
    v.u = (uint32_t)tgt_sqrt_bits(m, e, 24, 127);
    return v.f;
}

double TGT_SQRT_NAME(double x)
{
    union {
        double f;
        uint64_t u;
    } v;
    uint64_t m;
    int e, bexp;
    v.f = x;
    bexp = (int)((v.u >> 52) & 0x7FFu);
    if ((v.u & 0x7FFFFFFFFFFFFFFFull) == 0)
        return x;
    if (bexp == 0x7FF) {
        if (v.u & 0x000FFFFFFFFFFFFFull) {
            v.u |= 0x0008000000000000ull;
            return v.f;
        }
        if ((v.u >> 63) == 0)
            return x;
    }
    if (v.u >> 63) {
        v.u = 0x7FF8000000000000ull;
        return v.f;
    }
    tgt_normalise(v.u & 0x000FFFFFFFFFFFFFull, bexp, 53, 1023, &m, &e);
    v.u = tgt_sqrt_bits(m, e, 53, 1023);
    return v.f;
}
