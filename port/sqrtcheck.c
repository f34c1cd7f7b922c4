/* Host check of port/riscv/sqrt.c (`make check-port`): the integer square roots must equal
 * the host's IEEE 754 sqrtf/sqrt (correctly rounded in hardware on x86-64 and AArch64) bit
 * for bit. float: every significand of the binades [1, 4) (both exponent parities), every
 * 4099th bit pattern over all 2^32, and the subnormal range densely. double: special values,
 * 2 million random bit patterns, exact squares and the neighbours of midpoints (R + 1/2)^2.
 * Closes with "N passed, N failed" (one check per group). Hosted C. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

float tgt_sqrtf(float x);
double tgt_sqrt(double x);

static long n_pass, n_fail;

static uint32_t f2u(float f) { uint32_t u; memcpy(&u, &f, sizeof u); return u; }
static float u2f(uint32_t u) { float f; memcpy(&f, &u, sizeof f); return f; }
static uint64_t d2u(double d) { uint64_t u; memcpy(&u, &d, sizeof u); return u; }
static double u2d(uint64_t u) { double d; memcpy(&d, &u, sizeof d); return d; }

/* Equal bit patterns, or both NaN (any payload). */
static int same_f(float a, float b) { return (a != a && b != b) || f2u(a) == f2u(b); }
static int same_d(double a, double b) { return (a != a && b != b) || d2u(a) == d2u(b); }

static long bad_f, bad_d;

static void try_f(uint32_t u)
{
    float x = u2f(u), got = tgt_sqrtf(x), want = sqrtf(x);
    if (!same_f(got, want) && bad_f++ < 5)
        printf("  sqrtf(%a = 0x%08x): got 0x%08x, want 0x%08x\n", (double)x, (unsigned)u,
               (unsigned)f2u(got), (unsigned)f2u(want));
}

static void try_d(uint64_t u)
{
    double x = u2d(u), got = tgt_sqrt(x), want = sqrt(x);
    if (!same_d(got, want) && bad_d++ < 5)
        printf("  sqrt(%a): got 0x%016llx, want 0x%016llx\n", x,
               (unsigned long long)d2u(got), (unsigned long long)d2u(want));
}

static void group(const char *name, long *bad, long count)
{
    if (*bad == 0) {
        n_pass++;
        printf("ok   %s (%ld values)\n", name, count);
    } else {
        n_fail++;
        printf("FAIL %s: %ld of %ld values differ\n", name, *bad, count);
    }
    *bad = 0;
}

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint64_t rng(void) /* xorshift64* */
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 0x2545F4914F6CDD1Dull;
}

int main(void)
{
    static const double dspecial[] = {0.0, -0.0, 1.0, 2.0, 4.0, 0.25, -1.0, 1e-310, 4.9e-324,
                                      2.2250738585072014e-308, 1.7976931348623157e308};
    uint64_t u, i;
    long count;

    for (u = 0x3F800000u; u < 0x40800000u; u++) /* [1, 4): all 2^24 significands */
        try_f((uint32_t)u);
    group("sqrtf on [1, 4), every value", &bad_f, 0x01000000L);
    count = 0;
    for (u = 0; u <= 0xFFFFFFFFu; u += 251u, count++)
        try_f((uint32_t)u);
    try_f(0x7F800000u); try_f(0xFF800000u); try_f(0x7FC00000u); try_f(0x7F800001u);
    try_f(0x80000000u); try_f(0x00000001u); try_f(0x007FFFFFu); try_f(0x7F7FFFFFu);
    group("sqrtf, every 251st pattern and specials", &bad_f, count + 8);
    for (u = 0; u < 0x00800000u; u += 7u)
        try_f((uint32_t)u);
    group("sqrtf on subnormals, every 7th", &bad_f, 0x00800000L / 7);

    for (i = 0; i < sizeof dspecial / sizeof dspecial[0]; i++) {
        try_d(d2u(dspecial[i]));
        try_d(d2u(-dspecial[i]));
    }
    try_d(0x7FF0000000000000ull); try_d(0xFFF0000000000000ull);
    try_d(0x7FF8000000000000ull); try_d(0x7FF0000000000001ull);
    for (i = 1; i < 5000; i++)
        try_d(i); /* smallest subnormals */
    group("sqrt, specials and smallest subnormals", &bad_d, 5026);
    for (i = 0; i < 2000000; i++)
        try_d(rng());
    group("sqrt, 2e6 random bit patterns", &bad_d, 2000000);
    for (i = 0; i < 1000000; i++) {
        /* R an integer < 2^26: R^2 exact; (R + 1/2)^2 = R^2 + R + 1/4 needs 54 bits, so its
         * double neighbours are the hardest roundings. */
        double r = (double)(rng() >> 38) + 1.0, h = r + 0.5;
        double sq = r * r, mid = h * h;
        try_d(d2u(sq));
        try_d(d2u(mid));
        try_d(d2u(mid) + 1u);
        try_d(d2u(mid) - 1u);
    }
    group("sqrt, exact squares and midpoint neighbours", &bad_d, 4000000);
    printf("%ld passed, %ld failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
