/*
 * edmi.c: energy-decaying, momentum-conserving integrators (see edmi.h).
 * SPDX-License-Identifier: MIT
 * Copyright (c) 2026 the edmi authors (licence text: LICENSE).
 *
 * One file in sections, in the order a step flows (the contents list below the pragmas):
 * helpers, potentials, the paper's forces, the residual, the linear solves, Newton, the
 * passivity guard, the fallback, the step, building, invariants. Freestanding: includes only
 * edmi.h (and through it <float.h> and <limits.h>).
 */
#include "edmi.h"

/* edmi validates its input with NaN and infinity tests (x != x, |x| <= EDMI_REAL_MAX) and the
 * passivity guard's double-word arithmetic needs every operation evaluated as written:
 * -ffast-math (or -Ofast, -ffinite-math-only) would silently drop both (docs/porting.md). */
#if defined(__FAST_MATH__) || (defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__)
#error "edmi.c needs IEEE semantics: compile it without -ffast-math, -Ofast or -ffinite-math-only"
#endif
/* Every a * b + c is rounded twice, as written: a fused multiply-add would change results (the
 * host simulator and a target would disagree) and break the guard's exact products. GCC fuses
 * by default in its GNU modes (-std=gnu99, what Arduino, ESP-IDF and CMake's default pass)
 * and ignores the standard pragma; Clang fuses within
 * expressions by default. So edmi.c turns contraction off for itself, whatever the build
 * passes; -std=c99 builds (GCC contracts nothing there) are unchanged. */
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__) && !defined(__STRICT_ANSI__)
#pragma GCC optimize("fp-contract=off")
#endif

/* Contents, in the order a step flows (each section starts with a ==== banner):
 *   Configuration and helpers     internal constants, finite tests, 3-vectors
 *   Double-word arithmetic        sums and products to twice the precision (the guard's)
 *   Potentials                    everything about a potential: values and derivatives, the
 *                                 splits, divided differences, double-word values, the public
 *                                 constructors and evaluators (a new potential's code is here)
 *   The paper's algorithmic forces  beta and Lambda per scheme, and their tangents
 *   The mass matrix               M's products, its Cholesky factor and solves with it, the
 *                                 residual of M x = s in double-word (EDMI_MAX_MASS_GAP > 0)
 *   Residual and consistent tangent  links, then each effect (dampers, ports, the field)
 *   Linear solves                 3x3, one link, two bodies, banded LU; the Newton update
 *   Newton                        scales, the solved test, the predictor multi-corrector
 *   The passivity guard           the change of H and its bound, the energy tank, the
 *                                 certificate, the rounding, impulse, drag and stop, the choice
 *                                 of moves
 *   A step's end                  the end checks, works and forces, the energy balance and the
 *                                 guard's verdict (edmi__finish), the fallback state (freeze)
 *   One attempt, the fallback and substeps
 *   The step                      edmi_step, edmi_residual, edmi_tangent
 *   Building a system, and scenes the validator, edmi_init, edmi_add_*, edmi_load_scene
 *   Invariants                    H, K, V, J, L, C(t)
 *   Misc                          status names, the configuration check
 */

/* ==========================================================================================
 * Configuration and helpers
 * ======================================================================================== */

#define EDMI__ZERO EDMI_R(0.0)
#define EDMI__ONE EDMI_R(1.0)
#define EDMI__HALF EDMI_R(0.5)

/* At most this many halvings of a Newton correction that left the domain (down to 1/256). */
#define EDMI__MAX_HALVINGS 8
/* Dampers in use. EDMI_MAX_DAMPERS = 0 makes it the constant 0, so every loop over dampers
 * and the damper code it calls fold away (a validated system has n_dampers <= the capacity).
 * The three loops that touch work->kd are also inside #if EDMI_MAX_DAMPERS > 0: GCC 12 warns
 * of an out-of-bounds kd[] access in the unreachable body otherwise. */
#define EDMI__N_DAMPERS(s) (EDMI_MAX_DAMPERS > 0 ? (s)->n_dampers : 0)
/* Walls in use: the constant 0 when compiled out (EDMI_MAX_WALLS = 0), where the system and
 * the workspace have no wall members and the code that reads them is inside #if. */
#if EDMI_MAX_WALLS > 0
#define EDMI__N_WALLS(s) ((s)->n_walls)
#else
#define EDMI__N_WALLS(s) 0
#endif
/* The schemes and potential kinds this build carries (edmi.h, EDMI_WITH_*): bit k is scheme
 * or kind k. EDMI__HAS_SCHEME and EDMI__HAS_POT of a constant are constants, so a test such as
 * EDMI__HAS_SCHEME(EDMI_SCHEME_LG) && p->scheme == EDMI_SCHEME_LG drops the code behind it
 * when LG is out; with every one in (all five schemes, all eight kinds) they are 1 for any
 * value, so the validators test nothing more than the default build needs.
 * The decaying Lambdas are needed by their schemes and by LG's alternates. */
#define EDMI__SCHEMES                                                                      \
    ((unsigned)EDMI_WITH_MP << EDMI_SCHEME_MP | (unsigned)EDMI_WITH_LG << EDMI_SCHEME_LG |      \
     (unsigned)EDMI_WITH_GE << EDMI_SCHEME_GE | (unsigned)EDMI_WITH_PM << EDMI_SCHEME_PM |      \
     (unsigned)EDMI_WITH_PT << EDMI_SCHEME_PT)
#define EDMI__HAS_SCHEME(x) (EDMI__SCHEMES == 31u || (EDMI__SCHEMES >> (x) & 1u) != 0)
#define EDMI__DECAYING                                                                     \
    (EDMI__SCHEMES |                                                                       \
     (EDMI_WITH_LG_QUOTIENT ? 1u << EDMI_SCHEME_GE | 1u << EDMI_SCHEME_PM | 1u << EDMI_SCHEME_PT \
                            : 0u))
#define EDMI__HAS_DECAYING(x) ((EDMI__DECAYING >> (x) & 1u) != 0)
#define EDMI__POTS                                                                         \
    ((unsigned)EDMI_WITH_HARMONIC << EDMI_POT_HARMONIC |                                   \
     (unsigned)EDMI_WITH_QUARTIC << EDMI_POT_QUARTIC |                                     \
     (unsigned)EDMI_WITH_NEO_HOOKE << EDMI_POT_NEO_HOOKE | (unsigned)EDMI_WITH_LJ << EDMI_POT_LJ | \
     (unsigned)EDMI_WITH_INVERSE << EDMI_POT_INVERSE | (unsigned)EDMI_WITH_USER << EDMI_POT_USER | \
     (unsigned)EDMI_WITH_CONTACT << EDMI_POT_CONTACT |                                     \
     (unsigned)EDMI_WITH_CONTACT << EDMI_POT_TETHER)
#define EDMI__HAS_POT(k) (EDMI__POTS == 255u || (EDMI__POTS >> (k) & 1u) != 0)
/* The field and the force ports in use: the constant 0 when compiled out (as dampers). */
#define EDMI__HAS_FIELD(s) (EDMI_WITH_FIELD && (s)->has_field)
#define EDMI__N_FORCED(s) (EDMI_WITH_PORTS ? (s)->internal.n_forced : 0)
/* Whether the mass matrix has off-diagonal entries (the constant 0 when compiled out). */
#if EDMI_MAX_MASS_GAP > 0
#define EDMI__COUPLED(s) (edmi__mass_gap(s) > 0)
#else
#define EDMI__COUPLED(s) 0
#endif

/* sqrt(eps): a residual reduced this far below the predictor's is in Newton's quadratic
 * regime, where (the tangent being exact) only round-off stops it from shrinking. */
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define EDMI__SQRT_EPS EDMI_R(1.4901161193847656e-8)
#else
#define EDMI__SQRT_EPS EDMI_R(3.4526698e-4)
#endif

/* The smallest helpers the energy balance and the guard call hundreds of times per step are
 * inlined where edmi_real arithmetic is hardware, where the instructions they save per step
 * outweigh their flash (docs/porting.md, EDMI_NO_INLINE, gives both). Where every operation
 * is a soft-float call (Cortex-M0+, rv32imac) inlining only copies calls, so the compiler
 * decides there, as with -DEDMI_NO_INLINE. */
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define EDMI__ARM_FP_BIT 8 /* __ARM_FP: bit 3 double precision, bit 2 single */
#define EDMI__RISCV_FLEN 64
#else
#define EDMI__ARM_FP_BIT 4
#define EDMI__RISCV_FLEN 32
#endif
#if defined(__x86_64__) || defined(__aarch64__)
#define EDMI__HW_REAL 1
#elif defined(__ARM_FP)
#define EDMI__HW_REAL ((__ARM_FP & EDMI__ARM_FP_BIT) != 0)
#elif defined(__riscv_flen)
#define EDMI__HW_REAL (__riscv_flen >= EDMI__RISCV_FLEN)
#else
#define EDMI__HW_REAL 0
#endif
#if defined(__GNUC__) && !defined(EDMI_NO_INLINE) && EDMI__HW_REAL
#define EDMI__INLINE __inline__ __attribute__((always_inline))
#else
#define EDMI__INLINE
#endif

static int edmi__finite(edmi_real x)
{
    /* x - x is 0 for finite x and NaN for inf/NaN (no fast-math: this is not folded). */
    return (x - x) == EDMI__ZERO;
}

static int edmi__finite3(const edmi_real v[3])
{
    /* a sum of zeros is 0; a NaN among the differences makes it NaN: one test, no branches */
    return ((v[0] - v[0]) + (v[1] - v[1]) + (v[2] - v[2])) == EDMI__ZERO;
}

/* |x|: the compiler's built-in clears the sign bit in one instruction (VABS on an Arm FPU),
 * where the comparison takes a compare, a flag transfer and a conditional negation. */
#if defined(__GNUC__) || defined(__clang__)
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
static edmi_real edmi__abs(edmi_real x) { return __builtin_fabs(x); }
#else
static edmi_real edmi__abs(edmi_real x) { return __builtin_fabsf(x); }
#endif
#else
static edmi_real edmi__abs(edmi_real x) { return x < EDMI__ZERO ? -x : x; }
#endif

static edmi_real edmi__max(edmi_real a, edmi_real b) { return a > b ? a : b; }

static EDMI__INLINE edmi_real edmi__dot(const edmi_real a[3], const edmi_real b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Power-of-two scales (exact) for the norm's rare path: a sum of squares beyond the
 * precision's range is formed from the vector scaled down (big) or up (small) instead. */
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define EDMI__NORM_BIG EDMI_R(0x1p-600)
#define EDMI__NORM_SMALL EDMI_R(0x1p+600)
#define EDMI__NORM_SAFE_MIN EDMI_R(0x1p-968) /* 2^54 x the smallest normal */
#define EDMI__REAL_MIN DBL_MIN
#else
#define EDMI__NORM_BIG EDMI_R(0x1p-70)
#define EDMI__NORM_SMALL EDMI_R(0x1p+100)
#define EDMI__NORM_SAFE_MIN EDMI_R(0x1p-100) /* 2^26 x the smallest normal */
#define EDMI__REAL_MIN FLT_MIN
#endif

/* |a|. The plain sqrt(a . a) whenever a . a is finite and far enough above the subnormals
 * that the squares it dropped are below its rounding; otherwise from a scaled copy, so
 * that a vector of any finite size has a norm (inf only when the norm itself overflows) and
 * a non-zero vector a non-zero one (a . a overflows from 1.8e19 in float, 1.3e154 in
 * double, and underflows to 0 below 1e-23 and 1e-162: Newton's scaled residual was then
 * NaN or 0 and a step "converged" unsolved). */
static edmi_real edmi__norm(const edmi_real a[3])
{
    edmi_real s = edmi__dot(a, a), b[3], k;
    if (s >= EDMI__NORM_SAFE_MIN && s <= EDMI_REAL_MAX)
        return EDMI_SQRT(s);
    if (a[0] == EDMI__ZERO && a[1] == EDMI__ZERO && a[2] == EDMI__ZERO)
        return EDMI__ZERO;
    k = s > EDMI__ONE ? EDMI__NORM_BIG : EDMI__NORM_SMALL;
    b[0] = a[0] * k;
    b[1] = a[1] * k;
    b[2] = a[2] * k;
    return EDMI_SQRT(edmi__dot(b, b)) / k;
}

static void edmi__sub(const edmi_real a[3], const edmi_real b[3], edmi_real out[3])
{
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

static void edmi__cross(const edmi_real a[3], const edmi_real b[3], edmi_real out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void edmi__copy3(const edmi_real a[3], edmi_real out[3])
{
    out[0] = a[0];
    out[1] = a[1];
    out[2] = a[2];
}

/* The hot loops over a vector's three components, written out: at -Os a loop of 3 pays a
 * compare and a branch per component (y += s x; y += x; y -= x; out = s x). */
static EDMI__INLINE void edmi__axpy3(edmi_real s, const edmi_real x[3], edmi_real y[3])
{
    y[0] += s * x[0];
    y[1] += s * x[1];
    y[2] += s * x[2];
}

static EDMI__INLINE void edmi__add3(const edmi_real x[3], edmi_real y[3])
{
    y[0] += x[0];
    y[1] += x[1];
    y[2] += x[2];
}

static EDMI__INLINE void edmi__sub_from3(const edmi_real x[3], edmi_real y[3])
{
    y[0] -= x[0];
    y[1] -= x[1];
    y[2] -= x[2];
}

static EDMI__INLINE void edmi__scale3(edmi_real s, const edmi_real x[3], edmi_real out[3])
{
    out[0] = s * x[0];
    out[1] = s * x[1];
    out[2] = s * x[2];
}

static EDMI__INLINE void edmi__zero5(edmi_real a[5])
{
    a[0] = a[1] = a[2] = a[3] = a[4] = EDMI__ZERO;
}

static EDMI__INLINE void edmi__copy5(const edmi_real a[5], edmi_real out[5])
{
    /* written out: at -Os a loop of 5 costs a compare and a branch per element */
    out[0] = a[0];
    out[1] = a[1];
    out[2] = a[2];
    out[3] = a[3];
    out[4] = a[4];
}

/* The validator (section "Building a system, and scenes") is what every entry point calls
 * first; the step needs it before its definition. */
static edmi_status edmi__validate(const edmi_system *sys, edmi_real dt);

/* ==========================================================================================
 * Double-word arithmetic
 *
 * A real number held as the unevaluated sum hi + lo of two edmi_reals (|lo| <= ulp(hi)/2),
 * about twice the working precision's digits. The passivity guard evaluates the change of H in
 * it, and the potentials their values. Algorithms and error bounds (u = eps/2): Joldes,
 * Muller, Popescu, "Tight and rigorous error bounds for basic building blocks of double-word
 * arithmetic", ACM TOMS 44 (2017): 2Sum and Fast2Sum exact; TwoProd exact (fused multiply-
 * add, or Veltkamp/Dekker splitting, exact barring overflow and underflow); DW+DW <= 3u^2
 * (the sloppy sum of two of the same sign too), DW+FP <= 2u^2, DW*FP <= 2u^2, DW*DW <= 7u^2,
 * DW/FP <= 3u^2, DW/DW <= 15u^2 + 56u^3 relative; the square root one Newton step from
 * sqrt(hi), <= 4u^2 relative.
 * ======================================================================================== */

typedef struct edmi__dw {
    edmi_real hi, lo;
} edmi__dw;

#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define EDMI__SPLIT EDMI_R(134217729.0) /* 2^27 + 1 */
#else
#define EDMI__SPLIT EDMI_R(4097.0) /* 2^12 + 1 */
#endif

static edmi__dw edmi__dw_of(edmi_real x)
{
    edmi__dw r;
    r.hi = x;
    r.lo = EDMI__ZERO;
    return r;
}

/* The double-word pair stored as x[0] (hi), x[1] (lo). */
static edmi__dw edmi__dw_pair(const edmi_real x[2])
{
    edmi__dw r;
    r.hi = x[0];
    r.lo = x[1];
    return r;
}

/* a + b exactly, for |a| >= |b| (or a == 0). */
static EDMI__INLINE edmi__dw edmi__fast_two_sum(edmi_real a, edmi_real b)
{
    edmi__dw r;
    r.hi = a + b;
    r.lo = b - (r.hi - a);
    return r;
}

/* a + b exactly (Knuth's 2Sum). */
static EDMI__INLINE edmi__dw edmi__two_sum(edmi_real a, edmi_real b)
{
    edmi__dw r;
    edmi_real a1, b1;
    r.hi = a + b;
    a1 = r.hi - b;
    b1 = r.hi - a1;
    r.lo = (a - a1) + (b - b1);
    return r;
}

/* a * b exactly. */
static EDMI__INLINE edmi__dw edmi__two_prod(edmi_real a, edmi_real b)
{
    edmi__dw r;
    r.hi = a * b;
#ifdef EDMI_FMA
    r.lo = EDMI_FMA(a, b, -r.hi);
#else
    {
        edmi_real ca = EDMI__SPLIT * a, cb = EDMI__SPLIT * b;
        edmi_real ah = ca - (ca - a), al = a - ah, bh = cb - (cb - b), bl = b - bh;
        r.lo = ((ah * bh - r.hi) + ah * bl + al * bh) + al * bl;
    }
#endif
    return r;
}

static EDMI__INLINE edmi__dw edmi__dw_add(edmi__dw x, edmi__dw y)
{
    edmi__dw s = edmi__two_sum(x.hi, y.hi), t = edmi__two_sum(x.lo, y.lo), v;
    v = edmi__fast_two_sum(s.hi, s.lo + t.hi);
    return edmi__fast_two_sum(v.hi, t.lo + v.lo);
}

/* x + y, x.hi and y.hi of the same sign (JMP's SloppyDWPlusDW: 11 operations, not 20). */
static EDMI__INLINE edmi__dw edmi__dw_add_same(edmi__dw x, edmi__dw y)
{
    edmi__dw s = edmi__two_sum(x.hi, y.hi);
    return edmi__fast_two_sum(s.hi, s.lo + (x.lo + y.lo));
}

/* x + y for a real y (JMP's DWPlusFP). */
static EDMI__INLINE edmi__dw edmi__dw_add_r(edmi__dw x, edmi_real y)
{
    edmi__dw s = edmi__two_sum(x.hi, y);
    return edmi__fast_two_sum(s.hi, x.lo + s.lo);
}

static EDMI__INLINE edmi__dw edmi__dw_neg(edmi__dw x)
{
    x.hi = -x.hi;
    x.lo = -x.lo;
    return x;
}

static EDMI__INLINE edmi__dw edmi__dw_sub(edmi__dw x, edmi__dw y) { return edmi__dw_add(x, edmi__dw_neg(y)); }

/* x + y where one of them is often exactly 0 (a sum's first term, a step without work): then
 * the other, which is what edmi__dw_add returns for finite x and y but for the sign of a zero.
 * A double-word number (hi = fl(hi + lo), as every operation here returns one) whose hi is 0
 * has lo = 0, and with an operand (0, 0) each TwoSum and Fast2Sum in edmi__dw_add returns its
 * other operand exactly. */
static EDMI__INLINE edmi__dw edmi__dw_add_z(edmi__dw x, edmi__dw y)
{
    return y.hi == EDMI__ZERO ? x : x.hi == EDMI__ZERO ? y : edmi__dw_add(x, y);
}

static EDMI__INLINE edmi__dw edmi__dw_mul_r(edmi__dw x, edmi_real y)
{
    edmi__dw c = edmi__two_prod(x.hi, y), t = edmi__fast_two_sum(c.hi, x.lo * y);
    return edmi__fast_two_sum(t.hi, t.lo + c.lo);
}

static EDMI__INLINE edmi__dw edmi__dw_mul(edmi__dw x, edmi__dw y)
{
    edmi__dw c = edmi__two_prod(x.hi, y.hi);
    return edmi__fast_two_sum(c.hi, c.lo + (x.hi * y.lo + x.lo * y.hi));
}

#if EDMI_WITH_NEO_HOOKE || EDMI_WITH_LJ || EDMI_WITH_INVERSE /* their V in double-word */
/* x / y (JMP's DWDivDW1). A numerator below 2^(2p) REAL_MIN (p the precision's bits) is scaled
 * up by 2^(2p) first, and the quotient back down, both exactly (but for a subnormal result's
 * last unit, which EDMI__DW_TINY covers): the residual x - y q would otherwise fall below the
 * normal range, where TwoProd loses bits that the division by y then magnifies beyond the
 * error bound (a potential's tiny coefficient over a small length; docs/testing.md). */
#define EDMI__DIV_UP (EDMI_R(4.0) / (EDMI_EPS * EDMI_EPS)) /* 2^(2p) */
static edmi__dw edmi__dw_div(edmi__dw x, edmi__dw y)
{
    edmi_real th, k = EDMI__ONE;
    edmi__dw r, q;
    if (edmi__abs(x.hi) < EDMI__REAL_MIN * EDMI__DIV_UP) {
        x.hi *= EDMI__DIV_UP;
        x.lo *= EDMI__DIV_UP;
        k = EDMI__ONE / EDMI__DIV_UP;
    }
    th = x.hi / y.hi;
    r = edmi__dw_mul_r(y, th);
    q = edmi__fast_two_sum(th, ((x.hi - r.hi) + (x.lo - r.lo)) / y.hi);
    q.hi *= k;
    q.lo *= k;
    return q;
}
#endif

/* x / y for a real y (JMP's DWDivFP3). */
static edmi__dw edmi__dw_div_r(edmi__dw x, edmi_real y)
{
    edmi_real th = x.hi / y;
    edmi__dw p = edmi__two_prod(th, y);
    return edmi__fast_two_sum(th, (((x.hi - p.hi) - p.lo) + x.lo) / y);
}

static edmi__dw edmi__dw_sqrt(edmi__dw x)
{
    edmi_real s;
    edmi__dw p;
    if (!(x.hi > EDMI__ZERO))
        return edmi__dw_of(EDMI__ZERO);
    s = EDMI_SQRT(x.hi);
    p = edmi__two_prod(s, s);
    return edmi__fast_two_sum(s, (((x.hi - p.hi) - p.lo) + x.lo) / (EDMI_R(2.0) * s));
}

static edmi_real edmi__dw_real(edmi__dw x) { return x.hi + x.lo; }

/* |v|^2 of a double-word vector (a sum of squares: sloppy sums). */
static edmi__dw edmi__dw_sq3(const edmi__dw v[3])
{
    edmi__dw s = edmi__dw_mul(v[0], v[0]);
    s = edmi__dw_add_same(s, edmi__dw_mul(v[1], v[1]));
    return edmi__dw_add_same(s, edmi__dw_mul(v[2], v[2]));
}

/* a - b exactly, per component. */
static void edmi__dw_diff3(const edmi_real a[3], const edmi_real b[3], edmi__dw out[3])
{
    out[0] = edmi__two_sum(a[0], -b[0]);
    out[1] = edmi__two_sum(a[1], -b[1]);
    out[2] = edmi__two_sum(a[2], -b[2]);
}

/* |a|^2 of a real vector, exactly up to the final double-word roundings. */
static edmi__dw edmi__dw_norm2(const edmi_real a[3])
{
    edmi__dw s = edmi__two_prod(a[0], a[0]);
    s = edmi__dw_add_same(s, edmi__two_prod(a[1], a[1]));
    return edmi__dw_add_same(s, edmi__two_prod(a[2], a[2]));
}

/* f . (a - b) k^2 with a - b formed exactly and k a power of two (exact). */
static edmi__dw edmi__dw_work(const edmi_real f[3], const edmi_real a[3], const edmi_real b[3],
                              edmi_real k)
{
    edmi__dw d[3], s;
    int i;
    edmi__dw_diff3(a, b, d);
    s = edmi__dw_of(EDMI__ZERO);
    for (i = 0; i < 3; i++) {
        d[i].hi = d[i].hi * k * k;
        d[i].lo = d[i].lo * k * k;
        s = edmi__dw_add(s, edmi__dw_mul_r(d[i], f[i]));
    }
    return s;
}

/* Error bound of a double-word energy term: |computed - exact| <= EDMI__DW_ERR * M, with M
 * the term's magnitude (the sum of the absolute values its formula adds). Each term below
 * passes through at most a dozen double-word operations of <= 15u^2 each; with the growth
 * of relative errors through the powers (LJ's (s/d)^6 multiplies the error of s/d by 6) the
 * worst is about 350 u^2 (LJ), so 1024 u^2 = 256 eps^2 leaves a factor 3. Underflow makes
 * TwoProd inexact below ~2^p REAL_MIN, by at most a few subnormal units per product:
 * EDMI__DW_TINY covers that in a quantity, and each term adds it times every factor the
 * quantity is multiplied or divided by afterwards (1/2m for a kinetic energy, m for the
 * field's work, a potential's coefficient and |dV/ds| <= 8 M / s for the squared length s
 * it is evaluated from). Tiny masses, lengths or momenta thus make the bound large and the
 * step uncertifiable (EDMI_ERR_PASSIVITY), never wrongly certified (a tiny body whose p^2
 * underflows to 0: docs/testing.md lists the case). */
#define EDMI__DW_ERR (EDMI_R(256.0) * EDMI_EPS * EDMI_EPS)
#define EDMI__DW_TINY (EDMI_R(1024.0) * EDMI__REAL_MIN)
/* The double-word length's error, relative: 32 u^2 = 8 eps^2 (18 u^2 of the squared length and
 * its square root, with room). */
#define EDMI__DW_X (EDMI_R(8.0) * EDMI_EPS * EDMI_EPS)

/* ==========================================================================================
 * Potentials
 *
 * The built-in potentials V(d) of a link length d, each with its convex/concave and
 * super-convex/super-concave splits (eqs. convex-split, super-convex-split) and derivatives
 * 0..4 in closed form (no pow(), no numeric differentiation); the dispatch over kinds
 * (validity, parts, magnitude), the closed-form divided differences [V(d1)-V(d0)]/(d1-d0) LG
 * uses, V in double-word arithmetic for the guard, and the public constructors and
 * evaluators. A new potential touches this section: its kind's case, under #if
 * EDMI_WITH_<NAME>, in edmi__pot_valid, edmi__pot_parts, edmi__divdiff, edmi__pot_span and
 * edmi__pot_dw, and its constructor; besides, its bit in EDMI__POTS and its option in edmi.h.
 * ======================================================================================== */

/* A harmonic spring of rest length 0, V = k/2 d^2 = k/2 |r|^2, is a quadratic function of
 * the link vector, smooth at d = 0 (a haptic virtual coupling): the only potential a link of
 * length 0 may have. The forces take its closed forms (edmi__beta_linear). */
static EDMI__INLINE int edmi__is_linear(const edmi_potential *pot)
{
    return EDMI__HAS_POT(EDMI_POT_HARMONIC) && pot->kind == EDMI_POT_HARMONIC &&
           pot->b == EDMI__ZERO;
}

/* A user potential (callbacks): never, when compiled out. */
static int edmi__is_user(const edmi_potential *pot)
{
    return EDMI__HAS_POT(EDMI_POT_USER) && pot->kind == EDMI_POT_USER;
}

#if EDMI_WITH_HARMONIC || EDMI_WITH_NEO_HOOKE || EDMI_WITH_INVERSE || EDMI_WITH_CONTACT
/* The parts of a convex and super-convex V: V_c = V_+ = V, V_e = V_- = 0. */
static void edmi__parts_convex(edmi_pot_parts *o)
{
    edmi__copy5(o->v, o->c);
    edmi__copy5(o->v, o->sp);
    edmi__zero5(o->e);
    edmi__zero5(o->sm);
}

#endif

#if EDMI_WITH_HARMONIC
/* V = k/2 (r - r0)^2: convex and super-convex (V'''' = 0), so V_c = V_+ = V. */
static void edmi__pot_harmonic(edmi_real k, edmi_real r0, edmi_real r, edmi_pot_parts *o,
                               int split)
{
    edmi_real x = r - r0;
    o->v[0] = EDMI__HALF * k * x * x;
    o->v[1] = k * x;
    o->v[2] = k;
    o->v[3] = EDMI__ZERO;
    o->v[4] = EDMI__ZERO;
    if (!split)
        return;
    edmi__parts_convex(o);
}

#endif

#if EDMI_WITH_QUARTIC
/* V = k/4 (r^2 - L^2)^2 (Gonzalez's quartic spring). Not convex for r < L/sqrt(3):
 * V_c = k/4 (r^4 + L^4), V_e = -k L^2 r^2 / 2. V'''' = 6k >= 0, so V_+ = V. */
static void edmi__pot_quartic(edmi_real k, edmi_real len, edmi_real r, edmi_pot_parts *o,
                              int split)
{
    edmi_real l2 = len * len, r2 = r * r, u = r2 - l2;
    o->v[0] = EDMI_R(0.25) * k * u * u;
    o->v[1] = k * r * u;
    o->v[2] = k * (EDMI_R(3.0) * r2 - l2);
    o->v[3] = EDMI_R(6.0) * k * r;
    o->v[4] = EDMI_R(6.0) * k;
    if (!split)
        return;
    o->c[0] = EDMI_R(0.25) * k * (r2 * r2 + l2 * l2);
    o->c[1] = k * r2 * r;
    o->c[2] = EDMI_R(3.0) * k * r2;
    o->c[3] = o->v[3];
    o->c[4] = o->v[4];
    o->e[0] = -EDMI__HALF * k * l2 * r2;
    o->e[1] = -k * l2 * r;
    o->e[2] = -k * l2;
    o->e[3] = EDMI__ZERO;
    o->e[4] = EDMI__ZERO;
    edmi__copy5(o->v, o->sp);
    edmi__zero5(o->sm);
}

#endif

#if EDMI_WITH_NEO_HOOKE
/* The paper's neo-Hookean spring (section 3.4): V = c rb^2/6 ((r/rb)^2 + 2 rb/r - 3)
 * = c (r - rb)^2 (r + 2 rb) / (6 r), the factored form being exact near the rest length.
 * V'' = c/3 (1 + 2 rb^3/r^3) > 0 and V'''' = 8 c rb^3 / r^5 > 0: V_c = V_+ = V. */
static void edmi__pot_neo_hooke(edmi_real c, edmi_real rb, edmi_real r, edmi_pot_parts *o,
                                int split)
{
    edmi_real ir = EDMI__ONE / r, x = r - rb;
    edmi_real b3 = rb * rb * rb * ir * ir * ir; /* (rb/r)^3 */
    edmi_real third = c / EDMI_R(3.0);
    o->v[0] = third * EDMI__HALF * x * x * (r + EDMI_R(2.0) * rb) * ir;
    o->v[1] = third * x * (r * r + r * rb + rb * rb) * ir * ir;
    o->v[2] = third * (EDMI__ONE + EDMI_R(2.0) * b3);
    o->v[3] = -EDMI_R(2.0) * c * b3 * ir;
    o->v[4] = EDMI_R(8.0) * c * b3 * ir * ir;
    if (!split)
        return;
    edmi__parts_convex(o);
}

#endif

#if EDMI_WITH_LJ || EDMI_WITH_INVERSE
/* Derivatives 0..4 of a * r^-n given t = a r^-n, ir = 1/r and the rising factorials of n. */
static void edmi__inv_pow_derivs(edmi_real t, edmi_real ir, edmi_real n1, edmi_real n2,
                                 edmi_real n3, edmi_real n4, edmi_real o[5])
{
    o[0] = t;
    o[1] = -n1 * t * ir;
    o[2] = n2 * t * ir * ir;
    o[3] = -n3 * t * ir * ir * ir;
    o[4] = n4 * t * ir * ir * ir * ir;
}

#endif

#if EDMI_WITH_LJ
/* Lennard-Jones 12-6 (eq. lennard_jones_12_6), split as in section 4.3.1:
 * V_c = V_+ = 4 eps (s/r)^12, V_e = V_- = -4 eps (s/r)^6. */
static void edmi__pot_lj(edmi_real eps, edmi_real sigma, edmi_real r, edmi_pot_parts *o,
                         int split)
{
    edmi_real ir = EDMI__ONE / r, s = sigma * ir;
    edmi_real s6 = s * s * s * s * s * s;
    int i;
    edmi__inv_pow_derivs(EDMI_R(4.0) * eps * s6 * s6, ir, EDMI_R(12.0), EDMI_R(156.0),
                         EDMI_R(2184.0), EDMI_R(32760.0), o->c);
    edmi__inv_pow_derivs(-EDMI_R(4.0) * eps * s6, ir, EDMI_R(6.0), EDMI_R(42.0),
                         EDMI_R(336.0), EDMI_R(3024.0), o->e);
    for (i = 0; i < 5; i++)
        o->v[i] = o->c[i] + o->e[i];
    o->v[0] = EDMI_R(4.0) * eps * s6 * (s6 - EDMI__ONE); /* exact zero at r = sigma */
    if (!split)
        return;
    edmi__copy5(o->c, o->sp);
    edmi__copy5(o->e, o->sm);
}

#endif

#if EDMI_WITH_INVERSE
/* V = -k/r. Gravity (k > 0) is concave and super-concave: V_e = V_- = V (section 4.3.2);
 * a repulsive Coulomb pair (k < 0) is convex and super-convex: V_c = V_+ = V. */
static void edmi__pot_inverse(edmi_real k, edmi_real r, edmi_pot_parts *o, int split)
{
    edmi_real ir = EDMI__ONE / r;
    edmi__inv_pow_derivs(-k * ir, ir, EDMI_R(1.0), EDMI_R(2.0), EDMI_R(6.0), EDMI_R(24.0),
                         o->v);
    if (!split)
        return;
    if (k > EDMI__ZERO) {
        edmi__copy5(o->v, o->e);
        edmi__copy5(o->v, o->sm);
        edmi__zero5(o->c);
        edmi__zero5(o->sp);
    } else {
        edmi__parts_convex(o);
    }
}

#endif

#if EDMI_WITH_CONTACT
/* The one-sided cubic forms, V = a/3 x^3 for x = sg (r - b) > 0, else 0: compression only
 * (contact, sg = -1, x = R - r) or tension only (tether, sg = +1, x = r - L). V'' = 2 a x >= 0
 * and V''' = 2 sg a (x > 0), a step that rises with r: V is convex and super-convex, V_c =
 * V_+ = V, and GE, PM and PT keep their energy decay across the step where contact begins
 * or ends (docs/contact.md). The quadratic k/2 x^2 has no such split (its V''' jumps down by
 * k: no sum of a rising and a falling V''' gives that), nor has Hertz's x^(5/2) (V''' is
 * unbounded at x = 0). */
static void edmi__pot_contact(edmi_real a, edmi_real b, edmi_real sg, edmi_real r,
                              edmi_pot_parts *o, int split)
{
    edmi_real x = sg * (r - b);
    if (!(x > EDMI__ZERO)) {
        edmi__zero5(o->v);
    } else {
        o->v[0] = a / EDMI_R(3.0) * x * x * x;
        o->v[1] = sg * a * x * x;
        o->v[2] = EDMI_R(2.0) * a * x;
        o->v[3] = EDMI_R(2.0) * sg * a;
        o->v[4] = EDMI__ZERO;
    }
    if (!split)
        return;
    edmi__parts_convex(o);
}

#endif

static int edmi__pot_valid(const edmi_potential *pot)
{
    edmi_real a = pot->a, b = pot->b;
    if (pot->kind == EDMI_POT_USER)
        return pot->fn != 0;
    if (!edmi__finite(a) || !edmi__finite(b))
        return 0;
    switch (pot->kind) {
    case EDMI_POT_HARMONIC:
    case EDMI_POT_QUARTIC:
        return a > EDMI__ZERO && b >= EDMI__ZERO;
    case EDMI_POT_NEO_HOOKE:
    case EDMI_POT_LJ:
        return a > EDMI__ZERO && b > EDMI__ZERO;
    case EDMI_POT_INVERSE:
        return a != EDMI__ZERO;
    case EDMI_POT_CONTACT:
        return a > EDMI__ZERO && b > EDMI__ZERO;
    case EDMI_POT_TETHER:
        return a > EDMI__ZERO && b >= EDMI__ZERO;
    case EDMI_POT_USER:
    default:
        return 0;
    }
}

/* A potential a link or an evaluator may take: valid, and its kind built in. */
static edmi_status edmi__pot_check(const edmi_potential *pot)
{
    if (!edmi__pot_valid(pot))
        return EDMI_ERR_PARAM;
    return EDMI__HAS_POT(pot->kind) ? EDMI_OK : EDMI_ERR_DISABLED;
}

/* Evaluate a validated potential at r > 0: V in o->v and, with `split`, its convex/concave
 * and super-convex/super-concave parts (a user potential's always). Where only V is read (the
 * mid-point's and PM's mean lengths) the parts are not copied. EDMI_ERR_DOMAIN if a user
 * callback refuses r. */
static edmi_status edmi__pot_parts(const edmi_potential *pot, edmi_real r, edmi_pot_parts *o,
                                   int split)
{
    int i;
    switch (pot->kind) {
#if EDMI_WITH_HARMONIC
    case EDMI_POT_HARMONIC:
        edmi__pot_harmonic(pot->a, pot->b, r, o, split);
        break;
#endif
#if EDMI_WITH_QUARTIC
    case EDMI_POT_QUARTIC:
        edmi__pot_quartic(pot->a, pot->b, r, o, split);
        break;
#endif
#if EDMI_WITH_NEO_HOOKE
    case EDMI_POT_NEO_HOOKE:
        edmi__pot_neo_hooke(pot->a, pot->b, r, o, split);
        break;
#endif
#if EDMI_WITH_LJ
    case EDMI_POT_LJ:
        edmi__pot_lj(pot->a, pot->b, r, o, split);
        break;
#endif
#if EDMI_WITH_INVERSE
    case EDMI_POT_INVERSE:
        edmi__pot_inverse(pot->a, r, o, split);
        break;
#endif
#if EDMI_WITH_CONTACT
    case EDMI_POT_CONTACT:
    case EDMI_POT_TETHER:
        edmi__pot_contact(pot->a, pot->b, pot->kind == EDMI_POT_CONTACT ? -EDMI__ONE : EDMI__ONE,
                          r, o, split);
        break;
#endif
#if EDMI_WITH_USER
    case EDMI_POT_USER:
    default:
        if (pot->fn(pot->ctx, r, o) != 0)
            return EDMI_ERR_DOMAIN;
        for (i = 0; i < 5; i++)
            o->v[i] = o->c[i] + o->e[i];
        break;
#else
    default: /* a kind compiled out: refused by edmi__pot_check */
        (void)i;
        return EDMI_ERR_DISABLED;
#endif
    }
    return EDMI_OK;
}

/* The magnitude M of a built-in potential's V at d, from its parts there: |V_c| + |V_e| +
 * |V'| d + |V''| eps d^2. V as edmi__pot_parts computes it (v[0]) at a length d^ within 4 u
 * of d (a link vector's difference and norm, u = EDMI_EPS / 2) errs from V(d) by at most
 * 128 u M, barring underflow (edmi__pot_tiny): counting each formula's roundings and the
 * error of d^ through V', harmonic 8 u M, quartic 43 u M, neo-Hooke 17 u M, Lennard-Jones
 * 86 u M (its (s/d)^6 by five products of a quotient), inverse 6 u M; and through V''
 * (16 u^2 d^2 |V''| / 2), which matters where V'(d^) vanishes while V'(d) does not: a spring
 * whose rounded length is its rest length exactly (a body a few units in the last place off
 * it: docs/testing.md lists the case). |V_c| + |V_e| carries V's own size where it is the small
 * difference of two large terms (Lennard-Jones near its minimum, the quartic below its rest
 * length). */
static edmi_real edmi__pot_mag(const edmi_potential *pot, const edmi_pot_parts *pp, edmi_real d)
{
    edmi_real m = edmi__abs(pp->c[0]) + edmi__abs(pp->e[0]) +
                  (edmi__abs(pp->v[1]) + edmi__abs(pp->v[2]) * EDMI_EPS * d) * d;
#if EDMI_WITH_CONTACT
    /* a one-sided form within d's error of its kink: d^ may lie on the other side, where V',
     * V'' and V''' as evaluated are 0; V there is below a d e^2, e = |x| + 8 eps (d + b) */
    if (pot->kind == EDMI_POT_CONTACT || pot->kind == EDMI_POT_TETHER) {
        edmi_real e = EDMI_R(8.0) * EDMI_EPS * (d + pot->b);
        edmi_real x = pot->kind == EDMI_POT_CONTACT ? pot->b - d : d - pot->b;
        if (x > -e) {
            x = edmi__max(x, EDMI__ZERO) + e;
            m += pot->a * d * x * x;
        }
    }
#else
    (void)pot;
#endif
    return m;
}

#if EDMI_WITH_LJ
/* Complete homogeneous polynomial h = sum_{j=0..m} a^j b^(m-j) and dh/da, by Horner in a
 * (all terms positive for a, b > 0: no cancellation). */
static void edmi__homog(int m, edmi_real a, edmi_real b, edmi_real *h, edmi_real *ha)
{
    edmi_real hh = EDMI__ONE, hd = EDMI__ZERO, bp = EDMI__ONE;
    int j;
    for (j = 0; j < m; j++) {
        bp *= b;
        hd = hd * a + hh;
        hh = hh * a + bp;
    }
    *h = hh;
    *ha = hd;
}

/* Divided difference of (sigma/r)^n between d0 and d1, and its d1-derivative:
 * with a = sigma/d1, b = sigma/d0, dd = -(a b / sigma) h_{n-1}(a, b). */
static void edmi__dd_inv_pow(int n, edmi_real sigma, edmi_real d0, edmi_real d1, edmi_real *dd,
                             edmi_real *dd_d1)
{
    edmi_real a = sigma / d1, b = sigma / d0, h, ha;
    edmi__homog(n - 1, a, b, &h, &ha);
    *dd = -(a * b / sigma) * h;
    *dd_d1 = (a * a * b / (sigma * sigma)) * (h + a * ha);
}

#endif

/* Closed-form [V(d1)-V(d0)]/(d1-d0) for the built-ins (the paper's eq. solar_flg_2 for
 * gravity, generalised). */
static edmi_status edmi__divdiff(const edmi_potential *pot, edmi_real d0, edmi_real d1,
                                 edmi_real *dd, edmi_real *dd_d1)
{
    edmi_real a = pot->a, b = pot->b;
    switch (pot->kind) {
#if EDMI_WITH_HARMONIC
    case EDMI_POT_HARMONIC:
        *dd = EDMI__HALF * a * ((d1 - b) + (d0 - b));
        *dd_d1 = EDMI__HALF * a;
        return EDMI_OK;
#endif
#if EDMI_WITH_QUARTIC
    case EDMI_POT_QUARTIC: {
        edmi_real w = d1 * d1 + d0 * d0 - EDMI_R(2.0) * b * b;
        *dd = EDMI_R(0.25) * a * (d1 + d0) * w;
        *dd_d1 = EDMI_R(0.25) * a * (w + EDMI_R(2.0) * d1 * (d1 + d0));
        return EDMI_OK;
    }
#endif
#if EDMI_WITH_NEO_HOOKE
    case EDMI_POT_NEO_HOOKE: {
        edmi_real b3 = EDMI_R(2.0) * b * b * b / (d0 * d1);
        *dd = a / EDMI_R(6.0) * ((d1 + d0) - b3);
        *dd_d1 = a / EDMI_R(6.0) * (EDMI__ONE + b3 / d1);
        return EDMI_OK;
    }
#endif
#if EDMI_WITH_LJ
    case EDMI_POT_LJ: {
        edmi_real q12, q12d, q6, q6d;
        edmi__dd_inv_pow(12, b, d0, d1, &q12, &q12d);
        edmi__dd_inv_pow(6, b, d0, d1, &q6, &q6d);
        *dd = EDMI_R(4.0) * a * (q12 - q6);
        *dd_d1 = EDMI_R(4.0) * a * (q12d - q6d);
        return EDMI_OK;
    }
#endif
#if EDMI_WITH_INVERSE
    case EDMI_POT_INVERSE:
        *dd = a / (d0 * d1);
        *dd_d1 = -a / (d0 * d1 * d1);
        return EDMI_OK;
#endif
#if EDMI_WITH_CONTACT
    case EDMI_POT_CONTACT:
    case EDMI_POT_TETHER: { /* a/3 (y1^3 - y0^3) / (sg (x1 - x0)), y = max(x, 0), dx/dd = sg */
        edmi_real sg = pot->kind == EDMI_POT_CONTACT ? -EDMI__ONE : EDMI__ONE;
        edmi_real x0 = sg * (d0 - b), x1 = sg * (d1 - b), q, q1, g;
        if (x0 > EDMI__ZERO && x1 > EDMI__ZERO) { /* both in: no division */
            q = x1 * x1 + x1 * x0 + x0 * x0;
            q1 = EDMI_R(2.0) * x1 + x0;
        } else if (x1 > EDMI__ZERO) { /* x1 - x0 >= x1 > 0: no cancellation */
            g = x1 / (x1 - x0);
            q = x1 * x1 * g;
            q1 = g * g * (EDMI_R(2.0) * x1 - EDMI_R(3.0) * x0);
        } else if (x0 > EDMI__ZERO) {
            g = x0 / (x0 - x1);
            q = x0 * x0 * g;
            q1 = x0 * g * g;
        } else {
            q = q1 = EDMI__ZERO;
        }
        *dd = sg * (a / EDMI_R(3.0)) * q;
        *dd_d1 = a / EDMI_R(3.0) * q1;
        return EDMI_OK;
    }
#endif
#if EDMI_WITH_USER
    case EDMI_POT_USER:
    default:
        if (pot->dd == 0)
            return EDMI_ERR_PARAM;
        return pot->dd(pot->ctx, d0, d1, dd, dd_d1) == 0 ? EDMI_OK : EDMI_ERR_DOMAIN;
#else
    default: /* a kind compiled out: refused by edmi__pot_check */
        return EDMI_ERR_DISABLED;
#endif
    }
}

/* What a potential's coefficient (a/2, a/4, a/6, 4a) multiplies at length d (s = d^2): the
 * coefficient's own underflow (a near the smallest subnormals, whose a/2 rounds to 0) errs by
 * this many subnormal units. */
static edmi_real edmi__pot_span(const edmi_potential *pot, edmi_real d, edmi_real s)
{
    edmi_real b = pot->b, t;
    switch (pot->kind) {
#if EDMI_WITH_HARMONIC
    case EDMI_POT_HARMONIC:
        return b == EDMI__ZERO ? s : (d + b) * (d + b);
#endif
#if EDMI_WITH_QUARTIC
    case EDMI_POT_QUARTIC:
        return (s + b * b) * (s + b * b);
#endif
#if EDMI_WITH_NEO_HOOKE
    case EDMI_POT_NEO_HOOKE:
        return (d + b) * (d + b) * (d + EDMI_R(2.0) * b) / d;
#endif
#if EDMI_WITH_LJ
    case EDMI_POT_LJ:
        t = b / d;
        t = t * t * t;
        return t * t * (t * t + EDMI__ONE);
#endif
#if EDMI_WITH_CONTACT
    case EDMI_POT_CONTACT:
    case EDMI_POT_TETHER:
        return (d + b) * (d + b) * (d + b);
#endif
    default:
        (void)b, (void)t, (void)d, (void)s;
        return EDMI__ZERO; /* inverse: a itself, exact */
    }
}

/* The underflow allowance of V at length d (s = d^2) whose magnitude is m, for the double-word
 * evaluation and the plain one alike (each formula is a chain of the same products):
 * underflow in s, amplified by |dV/ds| = |V'| / 2d <= m / s (none for V = a s / 2, whose s
 * may be 0), in the products after it (the coefficient a, over d for neo-Hooke and inverse)
 * and in the coefficient (edmi__pot_span). EDMI__DW_TINY is 2^10 of the smallest normal, far
 * above one product's subnormal unit. */
static edmi_real edmi__pot_tiny(const edmi_potential *pot, edmi_real d, edmi_real s, edmi_real m)
{
    edmi_real a = edmi__abs(pot->a), r = edmi__pot_span(pot, d, s);
    edmi_real u = edmi__is_linear(pot) ? a + r
                                       : a * (EDMI__ONE + EDMI__ONE / d) + EDMI_R(8.0) * m / s + r;
    return EDMI__DW_TINY * (EDMI__ONE + EDMI_R(16.0) * u);
}

/* V of a built-in link whose squared length is s (and length d = sqrt s), in double-word,
 * with the bound *err on its error. The zero-rest-length harmonic spring needs no square
 * root. m, the term's magnitude, is |V| + |V'| d (or the sum of its parts' sizes, where
 * those cancel): near a rest length V and V' vanish, and so does the error, which comes
 * from the square root's ~18 u^2 d in d - b (u = eps/2); |d - b| is taken as |x| + 32 u^2
 * (d + b), x as computed, so that where x is that error alone (computed 0) its square, the
 * error of V, is still covered. */
static void edmi__pot_dw(const edmi_potential *pot, edmi__dw s, edmi__dw d, edmi__dw *v,
                         edmi_real *err)
{
    edmi_real a = pot->a, b = pot->b, m, xe = EDMI__ZERO;
    edmi__dw x, t;
    (void)xe; /* read only by the kinds with a rest length */
    switch (pot->kind) {
#if EDMI_WITH_HARMONIC
    case EDMI_POT_HARMONIC:
        if (b == EDMI__ZERO) {
            *v = edmi__dw_mul_r(s, EDMI__HALF * a);
            m = EDMI__HALF * a * s.hi;
        } else {
            x = edmi__dw_add_r(d, -b);
            *v = edmi__dw_mul_r(edmi__dw_mul(x, x), EDMI__HALF * a);
            xe = edmi__abs(x.hi) + EDMI__DW_X * (d.hi + b);
            m = a * xe * (xe + d.hi);
        }
        break;
#endif
#if EDMI_WITH_QUARTIC
    case EDMI_POT_QUARTIC:
        x = edmi__dw_sub(s, edmi__two_prod(b, b));
        *v = edmi__dw_mul_r(edmi__dw_mul(x, x), EDMI_R(0.25) * a);
        m = a * (edmi__abs(x.hi) + EDMI_R(2.0) * EDMI__DW_X * (s.hi + b * b)) * (s.hi + b * b);
        break;
#endif
#if EDMI_WITH_NEO_HOOKE
    case EDMI_POT_NEO_HOOKE: /* c (d - rb)^2 (d + 2 rb) / (6 d) */
        x = edmi__dw_add_r(d, -b);
        t = edmi__dw_mul(edmi__dw_mul(x, x), edmi__dw_add_r(d, EDMI_R(2.0) * b));
        *v = edmi__dw_div(edmi__dw_mul_r(t, a), edmi__dw_mul_r(d, EDMI_R(6.0)));
        xe = edmi__abs(x.hi) + EDMI__DW_X * (d.hi + b);
        m = edmi__abs(v->hi) + a * xe * (xe + d.hi + EDMI_R(2.0) * b) / EDMI_R(3.0);
        break;
#endif
#if EDMI_WITH_LJ
    case EDMI_POT_LJ: /* 4 eps t^6 (t^6 - 1), t = sigma / d */
        t = edmi__dw_div(edmi__dw_of(b), d);
        t = edmi__dw_mul(t, t);
        t = edmi__dw_mul(edmi__dw_mul(t, t), t);
        *v = edmi__dw_mul_r(edmi__dw_mul(t, edmi__dw_add_r(t, -EDMI__ONE)),
                            EDMI_R(4.0) * a);
        m = EDMI_R(4.0) * a * t.hi * (t.hi + EDMI__ONE);
        break;
#endif
#if EDMI_WITH_CONTACT
    case EDMI_POT_CONTACT: /* a/3 x^3 for x = sg (d - b) > 0: as the harmonic spring's x */
    case EDMI_POT_TETHER:
        x = edmi__dw_add_r(d, -b);
        if (pot->kind == EDMI_POT_CONTACT)
            x = edmi__dw_neg(x);
        xe = edmi__abs(x.hi) + EDMI__DW_X * (d.hi + b);
        t = edmi__dw_mul_r(edmi__dw_mul(edmi__dw_mul(x, x), x), a);
        *v = x.hi > EDMI__ZERO ? edmi__dw_div_r(t, EDMI_R(3.0)) : edmi__dw_of(EDMI__ZERO);
        /* beyond d's error from the kink, on the free side: V = 0 exactly, and no error */
        m = x.hi > -EDMI_R(2.0) * EDMI__DW_X * (d.hi + b) ? a * xe * xe * (xe + d.hi) : EDMI__ZERO;
        break;
#endif
#if EDMI_WITH_INVERSE
    case EDMI_POT_INVERSE:
    default: /* user potentials are bounded by edmi__user_dv instead */
        *v = edmi__dw_div(edmi__dw_of(-a), d);
        m = edmi__abs(a) / d.hi;
        break;
#else
    default: /* user potentials are bounded by edmi__user_dv instead */
        (void)t;
        *v = edmi__dw_of(EDMI__ZERO);
        m = EDMI__ZERO;
        break;
#endif
    }
    *err = EDMI__DW_ERR * m + edmi__pot_tiny(pot, d.hi, s.hi, m);
}

/* Every derivative of every part finite (a result beyond the range is not a result). */
static int edmi__parts_finite(const edmi_pot_parts *o)
{
    int i;
    for (i = 0; i < 5; i++)
        if (!edmi__finite(o->v[i]) || !edmi__finite(o->c[i]) || !edmi__finite(o->e[i]) ||
            !edmi__finite(o->sp[i]) || !edmi__finite(o->sm[i]))
            return 0;
    return 1;
}

edmi_status edmi_pot_eval(const edmi_potential *pot, edmi_real r, edmi_pot_parts *out)
{
    edmi_pot_parts pp;
    edmi_status st;
    if (!pot || !out)
        return EDMI_ERR_NULL;
    st = edmi__pot_check(pot);
    if (st != EDMI_OK)
        return st;
    if (!edmi__finite(r) || !(r > EDMI__ZERO))
        return EDMI_ERR_PARAM;
    st = edmi__pot_parts(pot, r, &pp, 1);
    if (st != EDMI_OK)
        return st;
    if (!edmi__parts_finite(&pp))
        return EDMI_ERR_OVERFLOW;
    edmi__copy5(pp.v, out->v); /* part by part: a struct copy would need memcpy */
    edmi__copy5(pp.c, out->c);
    edmi__copy5(pp.e, out->e);
    edmi__copy5(pp.sp, out->sp);
    edmi__copy5(pp.sm, out->sm);
    return EDMI_OK;
}

edmi_status edmi_pot_divdiff(const edmi_potential *pot, edmi_real d0, edmi_real d1,
                             edmi_real *dd, edmi_real *dd_d1)
{
    edmi_real x, x1;
    edmi_status st;
    if (!pot || !dd || !dd_d1)
        return EDMI_ERR_NULL;
    st = edmi__pot_check(pot);
    if (st != EDMI_OK)
        return st;
    if (!edmi__finite(d0) || !edmi__finite(d1) || !(d0 > EDMI__ZERO) || !(d1 > EDMI__ZERO))
        return EDMI_ERR_PARAM;
    st = edmi__divdiff(pot, d0, d1, &x, &x1);
    if (st != EDMI_OK)
        return st;
    if (!edmi__finite(x) || !edmi__finite(x1))
        return EDMI_ERR_OVERFLOW;
    *dd = x;
    *dd_d1 = x1;
    return EDMI_OK;
}

static edmi_potential edmi__pot(edmi_pot_kind kind, edmi_real a, edmi_real b)
{
    edmi_potential p;
    p.kind = kind;
    p.a = a;
    p.b = b;
    p.fn = 0;
    p.dd = 0;
    p.ctx = 0;
    return p;
}

edmi_potential edmi_pot_harmonic(edmi_real k, edmi_real r0)
{
    return edmi__pot(EDMI_POT_HARMONIC, k, r0);
}

edmi_potential edmi_pot_quartic(edmi_real k, edmi_real len)
{
    return edmi__pot(EDMI_POT_QUARTIC, k, len);
}

edmi_potential edmi_pot_neo_hooke(edmi_real c, edmi_real rbar)
{
    return edmi__pot(EDMI_POT_NEO_HOOKE, c, rbar);
}

edmi_potential edmi_pot_lj(edmi_real eps, edmi_real sigma)
{
    return edmi__pot(EDMI_POT_LJ, eps, sigma);
}

edmi_potential edmi_pot_inverse(edmi_real k) { return edmi__pot(EDMI_POT_INVERSE, k, EDMI__ZERO); }

edmi_potential edmi_pot_contact(edmi_real k, edmi_real radius)
{
    return edmi__pot(EDMI_POT_CONTACT, k, radius);
}

edmi_potential edmi_pot_tether(edmi_real k, edmi_real len)
{
    return edmi__pot(EDMI_POT_TETHER, k, len);
}

edmi_potential edmi_pot_user(edmi_user_pot_fn fn, edmi_user_dd_fn dd, void *ctx)
{
    edmi_potential p = edmi__pot(EDMI_POT_USER, EDMI__ZERO, EDMI__ZERO);
    p.fn = fn;
    p.dd = dd;
    p.ctx = ctx;
    return p;
}

/* ==========================================================================================
 * The paper's algorithmic forces
 *
 * Section 4.1. Every pair force has the form
 *     f = dt * beta * r_m,   r_m = q_A,n+1/2 - q_B,n+1/2,
 * which conserves L, J and C (lemma many-body-momentum). MP has beta = V'(d_m)/d_m; the
 * others have beta = 2 Lambda / (d_n + d_n+1) with a scalar Lambda(d_n+1) per scheme. Each
 * Lambda function returns Lambda and dLambda/dd_n+1 for the consistent tangent. A new scheme
 * adds its Lambda here (and its name to edmi_scheme and edmi__params_valid, its bit to
 * EDMI__SCHEMES and its EDMI_WITH_<NAME> option to edmi.h).
 * ======================================================================================== */

/* Everything a Lambda needs at the end of the step. */
typedef struct edmi__at_end {
    edmi_real d1;       /* d_n+1 */
    edmi_pot_parts p1;  /* potential parts at d_n+1 (when the scheme needs them) */
    edmi_pot_parts pavg; /* potential parts at d_avg = (d_n + d_n+1)/2 (when needed) */
    const edmi_pot_parts *pa; /* pavg, or p1 where d_avg = d_n+1 */
} edmi__at_end;

/* LG (eq. LaBudde-Greenspan-approximation): the quotient as written. Its cancellation error
 * eps (|V(d_n+1)| + |V(d_n)|) / |d_n+1 - d_n| is returned in *err. The exact tangent
 * (V'(d_n+1) - Lambda)/(d_n+1 - d_n) has error eps |V| / (d_n+1 - d_n)^2; its limit
 * V''(d_n+1)/2 has error |d_n+1 - d_n| |V'''| / 6: use whichever is smaller (the tangent only
 * steers Newton, the solution is set by the residual). */
static void edmi__lambda_lg_quotient(const edmi_link_ws *w, const edmi__at_end *e,
                                     edmi_real *lam, edmi_real *dlam, edmi_real *err)
{
    edmi_real dd = e->d1 - w->d0, ad = edmi__abs(dd);
    edmi_real verr = EDMI_EPS * (edmi__abs(e->p1.v[0]) + edmi__abs(w->v0));
    *lam = (e->p1.v[0] - w->v0) / dd;
    *err = verr / ad;
    if (verr > ad * ad * ad * edmi__abs(e->p1.v[3]) / EDMI_R(6.0))
        *dlam = EDMI__HALF * e->p1.v[2];
    else
        *dlam = (e->p1.v[1] - *lam) / dd;
}

/* Janz's alternate (eq. janz-mid-point-rescue): V'(||q||_n+1/2). */
static void edmi__lambda_janz(const edmi__at_end *e, edmi_real *lam, edmi_real *dlam)
{
    *lam = e->pa->v[1];
    *dlam = EDMI__HALF * e->pa->v[2];
}

/* Gonzalez's alternate (eq. gonzalez-mid-point-rescue). */
static void edmi__lambda_gonzalez(const edmi_link_ws *w, const edmi__at_end *e, edmi_real *lam,
                                  edmi_real *dlam)
{
    edmi_real dd = e->d1 - w->d0;
    *lam = e->pa->v[1] + dd * dd / EDMI_R(24.0) * e->pa->v[3];
    *dlam = EDMI__HALF * e->pa->v[2] + dd / EDMI_R(12.0) * e->pa->v[3] +
            dd * dd / EDMI_R(48.0) * e->pa->v[4];
}

/* f_ge (eq. convex-concave-scheme-p): V_c'(d_n+1) + V_e'(d_n). */
static void edmi__lambda_ge(const edmi_link_ws *w, const edmi__at_end *e, edmi_real *lam,
                            edmi_real *dlam)
{
    *lam = e->p1.c[1] + w->dve0;
    *dlam = e->p1.c[2];
}

/* f_pm (eq. super-convex-concave-scheme-p):
 * V'(d_avg) + (d_n+1 - d_n)^2/24 (V_+'''(d_n+1) + V_-'''(d_n)). */
static void edmi__lambda_pm(const edmi_link_ws *w, const edmi__at_end *e, edmi_real *lam,
                            edmi_real *dlam)
{
    edmi_real dd = e->d1 - w->d0, s3 = e->p1.sp[3] + w->d3m0;
    *lam = e->pa->v[1] + dd * dd / EDMI_R(24.0) * s3;
    *dlam = EDMI__HALF * e->pa->v[2] + dd / EDMI_R(12.0) * s3 + dd * dd / EDMI_R(24.0) * e->p1.sp[4];
}

/* f_pt (eq. super-convex-concave-trapezoidal-scheme-p):
 * (V'(d_n) + V'(d_n+1))/2 - (d_n+1 - d_n)^2/12 (V_+'''(d_n) + V_-'''(d_n+1)). */
static void edmi__lambda_pt(const edmi_link_ws *w, const edmi__at_end *e, edmi_real *lam,
                            edmi_real *dlam)
{
    edmi_real dd = e->d1 - w->d0, s3 = w->d3p0 + e->p1.sm[3];
    *lam = EDMI__HALF * (e->p1.v[1] + w->dv0) - dd * dd / EDMI_R(12.0) * s3;
    *dlam = EDMI__HALF * e->p1.v[2] - dd / EDMI_R(6.0) * s3 - dd * dd / EDMI_R(12.0) * e->p1.sm[4];
}

/* Which evaluations a Lambda needs: at d_n+1 and/or at d_avg (GE, PT: end; PM: both). */
enum { EDMI__NEED_END = 1, EDMI__NEED_AVG = 2 };

static int edmi__needs_decaying(edmi_scheme s)
{
    return s == EDMI_SCHEME_PM ? EDMI__NEED_END | EDMI__NEED_AVG : EDMI__NEED_END;
}

/* The energy-decaying scheme an LG alternate borrows its force from. */
static edmi_scheme edmi__alt_scheme(edmi_lg_alt alt)
{
    return alt == EDMI_LG_ALT_GE   ? EDMI_SCHEME_GE
           : alt == EDMI_LG_ALT_PM ? EDMI_SCHEME_PM
                                   : EDMI_SCHEME_PT;
}

/* Lambda of an energy-decaying scheme, used by GE/PM/PT and by LG's decaying alternates. */
static void edmi__lambda_decaying(edmi_scheme s, const edmi_link_ws *w, const edmi__at_end *e,
                                  edmi_real *lam, edmi_real *dlam)
{
    if (EDMI__HAS_DECAYING(EDMI_SCHEME_GE) && s == EDMI_SCHEME_GE)
        edmi__lambda_ge(w, e, lam, dlam);
    else if (EDMI__HAS_DECAYING(EDMI_SCHEME_PM) && s == EDMI_SCHEME_PM)
        edmi__lambda_pm(w, e, lam, dlam);
    else if (EDMI__HAS_DECAYING(EDMI_SCHEME_PT))
        edmi__lambda_pt(w, e, lam, dlam);
}

/* LG's alternate force in the singular limit |d_n+1 - d_n| <= tol_Q (section 3.4). */
static void edmi__lambda_lg_alt(edmi_lg_alt alt, const edmi_link_ws *w, const edmi__at_end *e,
                                edmi_real *lam, edmi_real *dlam)
{
    switch (alt) {
    case EDMI_LG_ALT_GONZALEZ:
        edmi__lambda_gonzalez(w, e, lam, dlam);
        break;
    case EDMI_LG_ALT_GE:
    case EDMI_LG_ALT_PM:
    case EDMI_LG_ALT_PT:
        edmi__lambda_decaying(edmi__alt_scheme(alt), w, e, lam, dlam);
        break;
    case EDMI_LG_ALT_JANZ:
    default:
        edmi__lambda_janz(e, lam, dlam);
        break;
    }
}

/* Each force below writes the link's beta and its tangent d f / d r_n+1 = dt (beta/2 I +
 * gamma r_m (x) u) into its workspace, where edmi__link_force has put r_m (w->rm); the linear
 * GE force also scales r_m (its *rm_div, 1 otherwise) to keep the tangent's factors within
 * range, once the force itself is formed. */

/* The forces of a harmonic spring of rest length 0 (edmi__is_linear). The general forms
 * divide by d_m or d_n + d_n+1; their limits are closed forms. With dd = d_n+1 - d_n:
 *   MP  V'(d_m)/d_m                                   = k;
 *   LG  2 [k/2 (d_n + d_n+1)] / (d_n + d_n+1)         = k;
 *   PM  2 [k d_avg + dd^2/24 (0 + 0)] / (d_n + d_n+1)  = k   (V''' = 0);
 *   PT  2 [k (d_n + d_n+1)/2 - 0] / (d_n + d_n+1)     = k;
 * so each gives f = dt k r_m, the linear force, with tangent dt k/2 I (gamma = 0);
 *   GE  2 [V_c'(d_n+1) + V_e'(d_n)] / (d_n + d_n+1) = 2 k d_n+1 / (d_n + d_n+1) in [0, 2k]
 *       (V_c = V, V_e = 0): bounded; at d_n = d_n+1 = 0 r_m = 0 and f = 0 whatever beta
 *       (take k); d beta / d r_n+1 = 2 k d_n / (d_n + d_n+1)^2 r_n+1/d_n+1, bounded by 2k/d_n
 *       and taken as 0 at d_n+1 = 0 (where |r_n+1| has no derivative). Its tangent term
 *       gamma r_m (x) u is at most k, but gamma alone grows like 1/d^2: it is formed as
 *       2k (d_n/s) (r_m/s) (x) (r_n+1/d_n+1), s = d_n + d_n+1, each factor at most 2k or 1,
 *       so that a body settling onto its anchor (d ~ 1e-20 in float) keeps a finite tangent. */
static void edmi__beta_linear(edmi_scheme scheme, edmi_real k, edmi_link_ws *w,
                              const edmi_real r1[3], edmi_real *rm_div)
{
    w->beta = k;
    w->gamma = EDMI__ZERO;
    edmi__copy3(r1, w->u);
    if (EDMI__HAS_SCHEME(EDMI_SCHEME_GE) && scheme == EDMI_SCHEME_GE) {
        edmi_real d1 = edmi__norm(r1), s = w->d0 + d1;
        int i;
        if (!(s > EDMI__ZERO))
            return;
        w->beta = EDMI_R(2.0) * k * (d1 / s);
        if (d1 > EDMI__ZERO) {
            w->gamma = EDMI_R(2.0) * k * (w->d0 / s);
            *rm_div = s;
            for (i = 0; i < 3; i++)
                w->u[i] = r1[i] / d1;
        }
    }
}

/* f_mp: beta = V'(d_m)/d_m with d_m = |r_m| (one-point Gauss, section 3.2). */
static edmi_status edmi__beta_mp(const edmi_potential *pot, edmi_link_ws *w)
{
    edmi_pot_parts pm;
    edmi_real dm = edmi__norm(w->rm);
    edmi_status st;
    if (!(dm > EDMI__ZERO) || !edmi__finite(dm))
        return EDMI_ERR_DOMAIN;
    st = edmi__pot_parts(pot, dm, &pm, 0); /* V only */
    if (st != EDMI_OK)
        return st;
    w->beta = pm.v[1] / dm;
    /* d beta / d r_n+1 = (V'' - beta)/d_m * r_m/(2 d_m) */
    w->gamma = (pm.v[2] - w->beta) / (EDMI_R(2.0) * dm * dm);
    edmi__copy3(w->rm, w->u);
    return EDMI_OK;
}

/* f_lg, f_ge, f_pm, f_pt: beta = 2 Lambda / (d_n + d_n+1). */
static edmi_status edmi__beta_split(const edmi_params *prm, const edmi_potential *pot,
                                    edmi_link_ws *w, const edmi_real r1[3], edmi_real dt,
                                    int *switched)
{
    edmi__at_end e;
    edmi_real lam = EDMI__ZERO, dlam = EDMI__ZERO, lam_err = EDMI__ZERO, s;
    edmi_status st;
    int need, lg_closed = 0, lg_switch = 0;
    e.d1 = edmi__norm(r1);
    if (!(e.d1 > EDMI__ZERO) || !edmi__finite(e.d1))
        return EDMI_ERR_DOMAIN;
    if (EDMI__HAS_SCHEME(EDMI_SCHEME_LG) && prm->scheme == EDMI_SCHEME_LG) {
        /* without the quotient form, a user potential under LG has its divided difference
         * (edmi__validate_system) */
        lg_closed = !EDMI_WITH_LG_QUOTIENT ||
                    (prm->lg_form == EDMI_LG_CLOSED && (!edmi__is_user(pot) || pot->dd != 0));
        lg_switch = !lg_closed && edmi__abs(e.d1 - w->d0) <= prm->tol_q;
    }
    if (lg_closed) {
        st = edmi__divdiff(pot, w->d0, e.d1, &lam, &dlam);
        if (st != EDMI_OK)
            return st;
    } else {
        if (!EDMI_WITH_LG_QUOTIENT || prm->scheme != EDMI_SCHEME_LG)
            need = edmi__needs_decaying(prm->scheme);
        else if (!lg_switch)
            need = EDMI__NEED_END; /* the quotient needs V(d_n+1), V'(d_n+1) */
        else if (prm->lg_alt == EDMI_LG_ALT_JANZ || prm->lg_alt == EDMI_LG_ALT_GONZALEZ)
            need = EDMI__NEED_AVG;
        else
            need = edmi__needs_decaying(edmi__alt_scheme(prm->lg_alt));
        if (need & EDMI__NEED_END) {
            st = edmi__pot_parts(pot, e.d1, &e.p1, 1);
            if (st != EDMI_OK)
                return st;
            w->have1 = 1; /* kept for the guard's plain certificate */
            w->d1 = e.d1;
            w->v1 = e.p1.v[0];
            w->m1 = edmi__pot_mag(pot, &e.p1, e.d1);
        }
        e.pa = &e.p1; /* d_avg = d_n+1 = d_n (PM's predictor): the values at d_n+1 */
        if ((need & EDMI__NEED_AVG) &&
            !((need & EDMI__NEED_END) && e.d1 == w->d0 && edmi__finite(w->d0 + w->d0))) {
            st = edmi__pot_parts(pot, EDMI__HALF * (w->d0 + e.d1), &e.pavg, 0); /* V only */
            if (st != EDMI_OK)
                return st;
            e.pa = &e.pavg;
        }
        if (!EDMI_WITH_LG_QUOTIENT || prm->scheme != EDMI_SCHEME_LG)
            edmi__lambda_decaying(prm->scheme, w, &e, &lam, &dlam);
        else if (lg_switch)
            edmi__lambda_lg_alt(prm->lg_alt, w, &e, &lam, &dlam);
        else
            edmi__lambda_lg_quotient(w, &e, &lam, &dlam, &lam_err);
    }
    s = w->d0 + e.d1;
    w->beta = EDMI_R(2.0) * lam / s;
    lam_err = EDMI_R(2.0) * lam_err / s; /* the error of beta */
    if (lam_err != EDMI__ZERO)
        w->noise = dt * edmi__norm(w->rm) * lam_err;
    /* d beta / d r_n+1 = (2 Lambda' - beta)/s * r_n+1/d_n+1 */
    w->gamma = (EDMI_R(2.0) * dlam - w->beta) / (s * e.d1);
    edmi__copy3(r1, w->u);
    *switched = lg_switch;
    return EDMI_OK;
}

/* ==========================================================================================
 * The mass matrix
 *
 * Section 2: diagonal entries body[a].m, and with EDMI_MAX_MASS_GAP > 0 off-diagonal entries
 * m_ab within that gap of the diagonal (sys->mass_off). The kinetic energy is
 * K = 1/2 p . M^-1 p and the time finite element gives M (q_n+1 - q_n) = dt p_n+1/2. The step
 * needs M itself (a banded product, no solve); K needs M^-1, through a Cholesky factorisation
 * M = L L^T streamed row by row: nothing is stored, so a body's mass written between steps is
 * taken as it is (the state access contract).
 * ======================================================================================== */

#if EDMI_MAX_MASS_GAP > 0
/* m_ab, a != b (0 beyond the gap). */
static edmi_real edmi__mass_ab(const edmi_system *sys, int a, int b)
{
    int hi = a > b ? a : b, k = (a > b ? a - b : b - a) - 1;
    return k < EDMI_MAX_MASS_GAP ? sys->mass_off[hi][k] : EDMI__ZERO;
}

/* The largest body-index gap of a non-zero off-diagonal mass (0: M is diagonal). */
static int edmi__mass_gap(const edmi_system *sys)
{
    int a, k, g = 0;
    for (a = 1; a < sys->n_bodies; a++)
        for (k = 0; k < EDMI_MAX_MASS_GAP && k < a; k++)
            if (sys->mass_off[a][k] != EDMI__ZERO && k + 1 > g)
                g = k + 1;
    return g;
}

/* An off-diagonal mass m_ab (a != b) of a system or of a scene's list. */
typedef edmi_real (*edmi__off_fn)(const void *ctx, int a, int b);

static edmi_real edmi__off_sys(const void *ctx, int a, int b)
{
    return edmi__mass_ab((const edmi_system *)ctx, a, b);
}

#if EDMI_WITH_SCENE
static edmi_real edmi__off_scene(const void *ctx, int a, int b)
{
    const edmi_scene *sc = (const edmi_scene *)ctx;
    int i;
    for (i = 0; i < sc->n_mass_couplings; i++) {
        const edmi_mass_coupling *c = &sc->mass_couplings[i];
        if ((c->a == a && c->b == b) || (c->a == b && c->b == a))
            return c->m;
    }
    return EDMI__ZERO;
}
#endif

/* Cholesky M - shift I = L L^T row by row (M's diagonal from body[], its off-diagonal masses
 * from off), L's rows within the gap G kept in a ring of G + 1 rows (row r in
 * ring[r % (G + 1)], its column i at index i - r + G), or with band, all n rows there (row r
 * at band[r (G + 1)], as edmi__mass_solve reads it). With k, also the forward substitution
 * y = L^-1 p of the bodies' momenta (per component) and *k = 1/2 |y|^2 = 1/2 p . M^-1 p; with
 * dmin, the smallest pivot (L_aa^2). Returns 0 if a pivot is not positive or not finite. */
static int edmi__cholesky(int n, const edmi_body *body, edmi__off_fn off, const void *ctx,
                          const edmi_real (*p)[3], edmi_real *k, edmi_real shift,
                          edmi_real *dmin, edmi_real *band)
{
    edmi_real ring[EDMI_MAX_MASS_GAP + 1][EDMI_MAX_MASS_GAP + 1], y[EDMI_MAX_MASS_GAP + 1][3];
    const int g = EDMI_MAX_MASS_GAP, w = EDMI_MAX_MASS_GAP + 1;
    edmi_real kin = EDMI__ZERO;
    int a, i, j, c;
    for (a = 0; a < n; a++) {
        edmi_real *la = band ? band + a * w : ring[a % w], d = body[a].m - shift;
        int lo = a - g > 0 ? a - g : 0;
        for (j = lo; j < a; j++) {
            const edmi_real *lj = band ? band + j * w : ring[j % w];
            edmi_real x = off(ctx, a, j);
            for (i = lo; i < j; i++)
                x -= la[i - a + g] * lj[i - j + g];
            la[j - a + g] = x / lj[g];
            d -= la[j - a + g] * la[j - a + g];
        }
        if (!edmi__finite(d) || !(d > EDMI__ZERO))
            return 0;
        if (dmin && (a == 0 || d < *dmin))
            *dmin = d;
        la[g] = EDMI_SQRT(d);
        if (k)
            for (c = 0; c < 3; c++) {
                edmi_real x = p ? p[a][c] : body[a].p[c];
                for (j = lo; j < a; j++)
                    x -= la[j - a + g] * y[j % w][c];
                y[a % w][c] = x / la[g];
                kin += EDMI__HALF * y[a % w][c] * y[a % w][c];
            }
    }
    if (k)
        *k = kin;
    return 1;
}

static int edmi__mass_cholesky(const edmi_system *sys, edmi_real *k)
{
    return edmi__cholesky(sys->n_bodies, sys->body, edmi__off_sys, sys, 0, k, EDMI__ZERO, 0, 0);
}

/* A lower bound on M's smallest eigenvalue, proved in floating point (Rump, "Verification of
 * positive definiteness", BIT 46, 2006): if the Cholesky factorisation of A = fl(M - s I)
 * runs to completion, then R^T R = A + E with |E| <= gamma_n+1 |R^T| |R| (Higham, Accuracy
 * and Stability, Thm 10.3), so ||E||_2 <= || |R| ||_F^2 gamma_n+1 <= tr(A) gamma_n+1 /
 * (1 - gamma_n+1), and A differs from M - s I by u m_aa on its diagonal: lambda_min(M) >=
 * s - (n + 2) eps tr(M) - eps max m_aa. The shift s is tried at 2^-1, 2^-5, 2^-9 and 2^-13
 * of the smallest pivot of M's own factorisation (an upper bound on lambda_min). Needs no
 * diagonal dominance: a consistent triangle's (m/12)[2 1 1; 1 2 1; 1 1 2] gets ~m/24. 0 if
 * no bound is positive: M is not positive definite to a degree working precision proves. */
static edmi_real edmi__mass_lambda_min(int n, const edmi_body *body, edmi__off_fn off,
                                       const void *ctx)
{
    edmi_real dmin = EDMI__ZERO, tr = EDMI__ZERO, mmax = EDMI__ZERO, s, lam;
    int a, k;
    if (!edmi__cholesky(n, body, off, ctx, 0, 0, EDMI__ZERO, &dmin, 0))
        return EDMI__ZERO;
    for (a = 0; a < n; a++) {
        tr += body[a].m;
        mmax = edmi__max(mmax, body[a].m);
    }
    for (k = 1, s = EDMI__HALF * dmin; k <= 13; k += 4, s *= EDMI_R(0.0625)) {
        if (!edmi__cholesky(n, body, off, ctx, 0, 0, s, 0, 0))
            continue;
        lam = (s - (edmi_real)(n + 2) * EDMI_EPS * tr - EDMI_EPS * mmax -
               (edmi_real)((n + 1) * (n + 1)) * EDMI_R(1024.0) * EDMI__REAL_MIN) *
              (EDMI__ONE - EDMI_R(4.0) * EDMI_EPS);
        return lam > EDMI__ZERO ? lam : EDMI__ZERO; /* a smaller s cannot do better */
    }
    return EDMI__ZERO;
}

static int edmi__mass_provable(const edmi_system *sys)
{
    return edmi__mass_lambda_min(sys->n_bodies, sys->body, edmi__off_sys, sys) > EDMI__ZERO;
}
#endif

/* (M 1)_a: body a's row sum of M, the mass the field pulls on and the centre of mass counts. */
static edmi_real edmi__mass_row(const edmi_system *sys, int a)
{
    edmi_real m = sys->body[a].m;
#if EDMI_MAX_MASS_GAP > 0
    int b;
    for (b = a - EDMI_MAX_MASS_GAP; b <= a + EDMI_MAX_MASS_GAP; b++)
        if (b >= 0 && b < sys->n_bodies && b != a)
            m += edmi__mass_ab(sys, a, b);
#endif
    return m;
}

/* R_q of the coupled masses: row a of M (q1 - q_n), divided by m_aa, minus its diagonal
 * part (already in R_q): sum over b != a of m_ab / m_aa (q1_b - q_n,b). */
static void edmi__mass_residual(const edmi_system *sys, const edmi_real (*q1)[3],
                                edmi_real (*rq)[3])
{
#if EDMI_MAX_MASS_GAP > 0
    int a, b, k, i;
    for (a = 1; a < sys->n_bodies; a++)
        for (k = 0; k < EDMI_MAX_MASS_GAP && k < a; k++) {
            edmi_real m = sys->mass_off[a][k];
            if (m == EDMI__ZERO)
                continue;
            b = a - 1 - k;
            for (i = 0; i < 3; i++) {
                rq[a][i] += m / sys->body[a].m * (q1[b][i] - sys->body[b].q[i]);
                rq[b][i] += m / sys->body[b].m * (q1[a][i] - sys->body[a].q[i]);
            }
        }
#else
    (void)sys;
    (void)q1;
    (void)rq;
#endif
}

#if EDMI_MAX_MASS_GAP > 0
/* Solve M x = b (3 columns, x and b laid out [3 a + c]) with the band Cholesky factor L of M
 * in f (row a at f[a (g + 1)], its column j at index j - a + g): forward, then backward. */
static void edmi__mass_solve(const edmi_real *f, int n, int g, const edmi_real *b, edmi_real *x)
{
    int a, j, c;
    for (a = 0; a < n; a++) {
        const edmi_real *la = f + a * (g + 1);
        int lo = a - g > 0 ? a - g : 0;
        for (c = 0; c < 3; c++) {
            edmi_real t = b[3 * a + c];
            for (j = lo; j < a; j++)
                t -= la[j - a + g] * x[3 * j + c];
            x[3 * a + c] = t / la[g];
        }
    }
    for (a = n - 1; a >= 0; a--)
        for (c = 0; c < 3; c++) {
            edmi_real t = x[3 * a + c];
            for (j = a + 1; j <= a + g && j < n; j++)
                t -= f[j * (g + 1) + (a - j + g)] * x[3 * j + c];
            x[3 * a + c] = t / f[a * (g + 1) + g];
        }
}

/* rho = s - M (x + y) for body a, component c, in double-word (the products exact), and the
 * sum of the magnitudes of its terms. s = s_hi + s_lo exactly; y may be NULL. */
static edmi__dw edmi__mass_residual_dw(const edmi_system *sys, int a, int c, edmi__dw s,
                                       const edmi_real *x, const edmi_real *y, edmi_real *mag)
{
    int b, g = EDMI_MAX_MASS_GAP;
    edmi__dw r = s;
    *mag = edmi__abs(s.hi);
    for (b = a - g; b <= a + g; b++) {
        edmi_real m;
        if (b < 0 || b >= sys->n_bodies)
            continue;
        m = b == a ? sys->body[a].m : edmi__mass_ab(sys, a, b);
        r = edmi__dw_sub(r, edmi__two_prod(m, x[3 * b + c]));
        *mag += edmi__abs(m * x[3 * b + c]);
        if (y) {
            r = edmi__dw_sub(r, edmi__two_prod(m, y[3 * b + c]));
            *mag += edmi__abs(m * y[3 * b + c]);
        }
    }
    return r;
}
#endif

/* ==========================================================================================
 * Residual and consistent tangent
 *
 * Section 3.4, many-body form of section 4.1: the start-of-step quantities of each link, a
 * link's force and tangent block, then the effects beyond links (dampers, force ports, the
 * field), then the residual R_q, R_p that sums them.
 * ======================================================================================== */

/* Second end of a link at the end of the step: body b in the configuration q (rows per
 * body), or the anchor where it is at the end of the step (work->lw[j].x1). */
static const edmi_real *edmi__end_b(const edmi_link *lk, const edmi_link_ws *w,
                                    const edmi_real (*q)[3])
{
    return lk->b == EDMI_ANCHOR ? w->x1 : q[lk->b];
}

/* Link vector q_A - q_B (or q_A - anchor) of the system's current state. */
static void edmi__link_vector(const edmi_system *sys, const edmi_link *lk, edmi_real r[3])
{
    edmi__sub(sys->body[lk->a].q, lk->b == EDMI_ANCHOR ? lk->anchor : sys->body[lk->b].q, r);
}

#if EDMI_MAX_WALLS > 0
/* The gap of body position q to wall wl placed at offset c (wl->c at the step's start, its
 * workspace's x1[0] at the end). */
static edmi_real edmi__wall_gap(const edmi_wall *wl, const edmi_real q[3], edmi_real c)
{
    return edmi__dot(wl->n, q) - c;
}

/* 1 if a one-sided wall potential is 0 with its derivatives at gap g as evaluated: g on
 * its free side or at its kink (edmi__pot_contact). */
static int edmi__wall_off(const edmi_potential *pot, edmi_real g)
{
    return (pot->kind == EDMI_POT_CONTACT && g >= pot->b) ||
           (pot->kind == EDMI_POT_TETHER && g <= pot->b);
}

/* 1 if wall wl's V is exactly 0 at body position q (the wall at offset c) whose gap g was
 * evaluated in working precision: a one-sided form with g on its free side by more than g's
 * rounding (a dot of three products less c: 4 u of G = sum |n_i q_i| + |c|, taken as 8 eps
 * of G + b, and what underflow lost). Its V and its force are 0 at both ends of such a step. */
static int edmi__wall_free(const edmi_wall *wl, const edmi_real q[3], edmi_real c, edmi_real g)
{
    const edmi_potential *pot = &wl->pot;
    edmi_real big = edmi__abs(c) + pot->b, x;
    int i;
    if (pot->kind != EDMI_POT_CONTACT && pot->kind != EDMI_POT_TETHER)
        return 0;
    for (i = 0; i < 3; i++)
        big += edmi__abs(wl->n[i] * q[i]);
    x = pot->kind == EDMI_POT_CONTACT ? pot->b - g : g - pot->b;
    return x < -(EDMI_R(8.0) * EDMI_EPS * big + EDMI__DW_TINY);
}
#endif

/* Start-of-step quantities of every link: r_n, d_n and the values at d_n the forces use, and
 * where each anchor is at the end of the step (edmi_move_anchor); of every wall, g_n and the
 * values there. */
static edmi_status edmi__prepare_links(const edmi_system *sys, edmi_workspace *work)
{
    int i, back = sys->n_links;
    work->n_pair = 0;
    for (i = 0; i < sys->n_links; i++) /* pair links first, anchor links after them */
        if (sys->link[i].b == EDMI_ANCHOR)
            work->order[--back] = i;
        else
            work->order[work->n_pair++] = i;
    for (i = 0; i < sys->n_links; i++) {
        const edmi_link *lk = &sys->link[i];
        edmi_link_ws *w = &work->lw[i];
        edmi_pot_parts p0;
        edmi_status st;
        edmi__link_vector(sys, lk, w->r0);
        edmi__copy3(lk->anchor, w->x1);
        w->d0 = edmi__norm(w->r0);
        if (!(w->d0 > EDMI__ZERO) && !(w->d0 == EDMI__ZERO && edmi__is_linear(&lk->pot)))
            return EDMI_ERR_COINCIDENT;
        st = edmi__pot_parts(&lk->pot, w->d0, &p0, 1);
        if (st != EDMI_OK)
            return st;
        if (!edmi__finite(p0.v[0]) || !edmi__finite(p0.v[1]))
            return EDMI_ERR_RANGE; /* the start's energy or force beyond the range: refused */
        w->v0 = p0.v[0];
        w->m0 = edmi__pot_mag(&lk->pot, &p0, w->d0);
        w->dv0 = p0.v[1];
        w->dve0 = p0.e[1];
        w->d3p0 = p0.sp[3];
        w->d3m0 = p0.sm[3];
    }
    for (i = 0; i < sys->internal.n_moving; i++) {
        int j = sys->internal.moving[i];
        edmi__copy3(sys->internal.anchor_next[j], work->lw[j].x1);
    }
#if EDMI_MAX_WALLS > 0
    for (i = 0; i < EDMI__N_WALLS(sys); i++) {
        const edmi_wall *wl = &sys->wall[i];
        edmi_link_ws *w = &work->ww[i];
        edmi_pot_parts p0;
        w->x1[0] = sys->internal.wall_next[i]; /* where it is at the step's end */
        w->d0 = edmi__wall_gap(wl, sys->body[wl->a].q, wl->c);
        if (edmi__pot_parts(&wl->pot, w->d0, &p0, 1) != EDMI_OK || !edmi__finite(w->d0) ||
            !edmi__finite(p0.v[0]) || !edmi__finite(p0.v[1]))
            return EDMI_ERR_RANGE; /* the start's energy or force beyond the range: refused */
        w->v0 = p0.v[0];
        w->dv0 = p0.v[1];
        w->dve0 = p0.e[1];
        w->d3p0 = p0.sp[3];
        w->d3m0 = p0.sm[3];
    }
#endif
    return EDMI_OK;
}

/* One link's algorithmic force f = dt beta r_m for the end-of-step link vector r1 and its
 * tangent block (into work->lw[j]). */
static edmi_status edmi__link_force(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                    int j, const edmi_real r1[3], edmi_real f[3], int *switched)
{
    const edmi_link *lk = &sys->link[j];
    edmi_link_ws *w = &work->lw[j];
    edmi_real rm_div = EDMI__ONE;
    edmi_status st = EDMI_OK;
    int i;
    w->rm[0] = EDMI__HALF * (w->r0[0] + r1[0]);
    w->rm[1] = EDMI__HALF * (w->r0[1] + r1[1]);
    w->rm[2] = EDMI__HALF * (w->r0[2] + r1[2]);
    w->have1 = 0;
    w->noise = EDMI__ZERO;
    *switched = 0;
    if (edmi__is_linear(&lk->pot))
        edmi__beta_linear(sys->params.scheme, lk->pot.a, w, r1, &rm_div);
    else if (EDMI__HAS_SCHEME(EDMI_SCHEME_MP) && sys->params.scheme == EDMI_SCHEME_MP)
        st = edmi__beta_mp(&lk->pot, w);
    else
        st = edmi__beta_split(&sys->params, &lk->pot, w, r1, dt, switched);
    if (st != EDMI_OK)
        return st;
    edmi__scale3(dt * w->beta, w->rm, f);
    if (rm_div != EDMI__ONE)
        for (i = 0; i < 3; i++)
            w->rm[i] /= rm_div;
    return EDMI_OK;
}

/* The link's tangent block k = d f / d r_n+1 = dt (beta/2 I + gamma r_m (x) u) at its last
 * evaluation, row-major. Built where a correction (or edmi_tangent) needs it, so the final
 * evaluation of a step, whose tangent no correction uses, does not build it. */
static void edmi__link_tangent(const edmi_link_ws *w, edmi_real dt, edmi_real k[9])
{
    int i, c;
    for (i = 0; i < 3; i++)
        for (c = 0; c < 3; c++)
            k[3 * i + c] = dt * (w->gamma * w->rm[i] * w->u[c] +
                                 (i == c ? EDMI__HALF * w->beta : EDMI__ZERO));
}

/* ---- walls --------------------------------------------------------------------------------
 * A wall is a link whose length is the body's gap g = n.q - c to a plane (edmi_wall): g is
 * linear in q, so the schemes' Lambda (section 3.4) of the gap is the wall's discrete
 * derivative and its force on the body is -Lambda n, whose work over a step is exactly
 * -Lambda (g_n+1 - g_n). Every Lambda above applies with d_n, d_n+1 read as g_n, g_n+1 (and
 * MP's mid-point as the mean gap); LG takes the closed-form divided difference, which every
 * potential a wall takes has. docs/contact.md. */

#if EDMI_MAX_WALLS > 0
/* The wall's discrete force f = dt Lambda n for the body's end-of-step position q1, with
 * Lambda and d Lambda / d g_n+1 kept in its workspace (beta, gamma). */
static edmi_status edmi__wall_force(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                    int j, const edmi_real q1[3], edmi_real f[3])
{
    const edmi_wall *wl = &sys->wall[j];
    const edmi_potential *pot = &wl->pot;
    edmi_scheme s = sys->params.scheme;
    edmi_link_ws *w = &work->ww[j];
    edmi__at_end e;
    edmi_real lam = EDMI__ZERO, dlam = EDMI__ZERO;
    edmi_status st = EDMI_OK;
    e.d1 = edmi__wall_gap(wl, q1, w->x1[0]);
    if (!edmi__finite(e.d1))
        return EDMI_ERR_DOMAIN;
    if (edmi__wall_off(pot, w->d0) && edmi__wall_off(pot, e.d1)) {
        /* off the body at both ends: every scheme's Lambda and its slope are 0 (V, V', V''
         * and V''' vanish on the free side and at the kink, and every mean of the two gaps
         * the schemes take lies between them) */
    } else if (EDMI__HAS_SCHEME(EDMI_SCHEME_MP) && s == EDMI_SCHEME_MP) {
        st = edmi__pot_parts(pot, EDMI__HALF * w->d0 + EDMI__HALF * e.d1, &e.pavg, 0);
        lam = e.pavg.v[1];
        dlam = EDMI__HALF * e.pavg.v[2];
    } else if (EDMI__HAS_SCHEME(EDMI_SCHEME_LG) && s == EDMI_SCHEME_LG) {
        st = edmi__divdiff(pot, w->d0, e.d1, &lam, &dlam);
    } else {
        st = edmi__pot_parts(pot, e.d1, &e.p1, 1);
        e.pa = &e.p1;
        if (st == EDMI_OK && s == EDMI_SCHEME_PM && e.d1 != w->d0) {
            st = edmi__pot_parts(pot, EDMI__HALF * w->d0 + EDMI__HALF * e.d1, &e.pavg, 0);
            e.pa = &e.pavg;
        }
        if (st == EDMI_OK)
            edmi__lambda_decaying(s, w, &e, &lam, &dlam);
    }
    if (st != EDMI_OK)
        return st;
    w->beta = lam;
    w->gamma = dlam;
    edmi__scale3(dt * lam, wl->n, f);
    return EDMI_OK;
}

/* The wall's tangent block d f / d q_n+1 = dt (d Lambda / d g) n n^T. */
static void edmi__wall_tangent(const edmi_wall *wl, const edmi_link_ws *w, edmi_real dt,
                               edmi_real k[9])
{
    int i, c;
    for (i = 0; i < 3; i++)
        for (c = 0; c < 3; c++)
            k[3 * i + c] = dt * w->gamma * wl->n[i] * wl->n[c];
}
#endif

/* Linear viscous damper along a link (docs/api.md, "Features"): impulse
 *     I = c (dr . n) n,   dr = r_n+1 - r_n,   n = r_m / |r_m|,
 * is parallel to r_m, so L, J and C are conserved (lemma many-body-momentum), and it removes
 * exactly dr . I / dt = c (dr . n)^2 / dt >= 0 per step (*loss = (c s) s with s = dr . n, so
 * that its sign survives rounding). Its tangent k = dI / dr_n+1 follows from d r_m =
 * dr_n+1 / 2 and dn = (I - n n^T) d r_m / |r_m|:
 *     k = c [n (n + (dr/2 - s n) / |r_m|)^T + s / (2 |r_m|) I].
 * On one axis (dr parallel to r_m) this is k = c, the linear damper's. An error in the
 * 1/|r_m| terms grows like c |dr| / |r_m|, and stalls Newton whenever a body crosses its
 * anchor (tests/test_tangent.c, part 6). Formed from the unit vector n, not from |r_m|^2:
 * a body settling onto its anchor has |r_m|^2 below the smallest normal (float, d < 1e-19),
 * where c / |r_m|^2 overflowed. */
static edmi_status edmi__damper(const edmi_link_ws *w, edmi_real c, const edmi_real r1[3],
                                edmi_real imp[3], edmi_real k[9], edmi_real *loss)
{
    edmi_real dr[3], n[3], rho, s, cs;
    int i, j;
    edmi__sub(r1, w->r0, dr);
    for (i = 0; i < 3; i++)
        n[i] = EDMI__HALF * (w->r0[i] + r1[i]);
    rho = edmi__norm(n);
    if (rho == EDMI__ZERO) { /* a zero-length link at mid-step: no direction, no impulse */
        for (i = 0; i < 3; i++)
            imp[i] = EDMI__ZERO;
        for (i = 0; i < 9; i++)
            k[i] = EDMI__ZERO;
        *loss = EDMI__ZERO;
        return EDMI_OK;
    }
    if (!(rho > EDMI__ZERO) || !edmi__finite(rho))
        return EDMI_ERR_DOMAIN;
    for (i = 0; i < 3; i++)
        n[i] /= rho;
    s = edmi__dot(dr, n);
    cs = c * s;
    *loss = cs * s; /* dr . I = c s^2, >= 0 as computed (cs has the sign of s) */
    for (i = 0; i < 3; i++) {
        imp[i] = cs * n[i];
        for (j = 0; j < 3; j++)
            k[3 * i + j] = c * n[i] * (n[j] + (EDMI__HALF * dr[j] - s * n[j]) / rho) +
                           (i == j ? EDMI__HALF * cs / rho : EDMI__ZERO);
    }
    return EDMI_OK;
}

/* Add the effects beyond links to R_p: force ports (-dt F), the uniform field (-dt m g),
 * dampers (+I on a, -I on b). Each is a loop over its own list: absent effects cost nothing. */
static edmi_status edmi__effects_residual(const edmi_system *sys, edmi_workspace *work,
                                          edmi_real dt, const edmi_real (*q1)[3],
                                          edmi_real (*rp)[3])
{
    int a, i;
    for (a = 0; a < EDMI__N_FORCED(sys); a++) {
        int b = sys->internal.forced[a];
        for (i = 0; i < 3; i++)
            rp[b][i] -= dt * sys->force[b][i];
    }
    if (EDMI__HAS_FIELD(sys))
        for (a = 0; a < sys->n_bodies; a++) {
            edmi_real mdt = dt * edmi__mass_row(sys, a);
            for (i = 0; i < 3; i++)
                rp[a][i] -= mdt * sys->g[i];
        }
#if EDMI_MAX_DAMPERS > 0
    for (a = 0; a < EDMI__N_DAMPERS(sys); a++) {
        int j = sys->damper[a].link;
        const edmi_link *lk = &sys->link[j];
        edmi_real r1[3], imp[3], loss;
        edmi_status st;
        edmi__sub(q1[lk->a], edmi__end_b(lk, &work->lw[j], q1), r1);
        st = edmi__damper(&work->lw[j], sys->damper[a].c, r1, imp, work->kd[a], &loss);
        if (st != EDMI_OK)
            return st;
        for (i = 0; i < 3; i++)
            rp[lk->a][i] += imp[i];
        if (lk->b != EDMI_ANCHOR)
            for (i = 0; i < 3; i++)
                rp[lk->b][i] -= imp[i];
    }
#else
    (void)work;
    (void)q1;
#endif
    return EDMI_OK;
}

static edmi_status edmi__residual(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                  const edmi_real (*q1)[3], const edmi_real (*p1)[3],
                                  edmi_real (*rq)[3], edmi_real (*rp)[3], int *switches)
{
    int a, k, nsw = 0, sw;
    edmi_real r1[3], f[3];
    edmi_status st;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi_real h = dt / bd->m * EDMI__HALF;
        rq[a][0] = q1[a][0] - bd->q[0] - h * (bd->p[0] + p1[a][0]);
        rq[a][1] = q1[a][1] - bd->q[1] - h * (bd->p[1] + p1[a][1]);
        rq[a][2] = q1[a][2] - bd->q[2] - h * (bd->p[2] + p1[a][2]);
        edmi__sub(p1[a], bd->p, rp[a]);
    }
    edmi__mass_residual(sys, q1, rq);
    /* Pair links, then anchor links (work->order, set once per step): no per-link branch. */
    for (k = 0; k < work->n_pair; k++) {
        const edmi_link *lk = &sys->link[work->order[k]];
        edmi__sub(q1[lk->a], q1[lk->b], r1);
        st = edmi__link_force(sys, work, dt, work->order[k], r1, f, &sw);
        if (st != EDMI_OK)
            return st;
        nsw += sw;
        edmi__add3(f, rp[lk->a]);
        edmi__sub_from3(f, rp[lk->b]);
    }
    for (k = work->n_pair; k < sys->n_links; k++) {
        const edmi_link *lk = &sys->link[work->order[k]];
        edmi__sub(q1[lk->a], work->lw[work->order[k]].x1, r1);
        st = edmi__link_force(sys, work, dt, work->order[k], r1, f, &sw);
        if (st != EDMI_OK)
            return st;
        nsw += sw;
        edmi__add3(f, rp[lk->a]);
    }
#if EDMI_MAX_WALLS > 0
    for (k = 0; k < EDMI__N_WALLS(sys); k++) {
        st = edmi__wall_force(sys, work, dt, k, q1[sys->wall[k].a], f);
        if (st != EDMI_OK)
            return st;
        edmi__add3(f, rp[sys->wall[k].a]);
    }
#endif
    st = edmi__effects_residual(sys, work, dt, q1, rp);
    if (st != EDMI_OK)
        return st;
    for (a = 0; a < sys->n_bodies; a++)
        if (!edmi__finite3(rq[a]) || !edmi__finite3(rp[a]))
            return EDMI_ERR_OVERFLOW;
    if (switches)
        *switches = nsw;
    return EDMI_OK;
}

/* ==========================================================================================
 * Linear solves
 *
 * The segregated Newton system (I + dt/(2m) C) dq = -R_q - dt/(2m) R_p. One body: a
 * hand-written 3x3 solve. Several: Gaussian elimination with partial pivoting, restricted to
 * the band the links occupy (bodies linked to bodies far away in index widen it; all-pairs
 * scenes are dense). Exact solves keep Newton quadratic.
 * ======================================================================================== */

/* Solve A x = b (3x3, row-major) by the adjugate. Singular when the condition number, as
 * estimated by max|A| max|adj A| / |det A| (>= ||A|| ||A^-1|| / 9 in the max norm), exceeds
 * 1/(16 eps); catches NaN. (Hadamard's bound |det| <= prod of row norms, used before, rejects
 * well-conditioned matrices dominated by one direction: a stiff link at omega dt = 100 gives
 * A ~ I + 1e4 u u^T, condition ~1e4, whose det falls below 8 eps of the bound in float.) */
static edmi_status edmi__solve3(const edmi_real m[9], const edmi_real b[3], edmi_real x[3])
{
    edmi_real adj[9], det, id, amax = EDMI__ZERO, cmax = EDMI__ZERO;
    int i;
    adj[0] = m[4] * m[8] - m[5] * m[7];
    adj[3] = m[5] * m[6] - m[3] * m[8];
    adj[6] = m[3] * m[7] - m[4] * m[6];
    adj[1] = m[2] * m[7] - m[1] * m[8];
    adj[4] = m[0] * m[8] - m[2] * m[6];
    adj[7] = m[1] * m[6] - m[0] * m[7];
    adj[2] = m[1] * m[5] - m[2] * m[4];
    adj[5] = m[2] * m[3] - m[0] * m[5];
    adj[8] = m[0] * m[4] - m[1] * m[3];
    det = m[0] * adj[0] + m[1] * adj[3] + m[2] * adj[6];
    for (i = 0; i < 9; i++) {
        amax = edmi__max(amax, edmi__abs(m[i]));
        cmax = edmi__max(cmax, edmi__abs(adj[i]));
    }
    if (!(edmi__abs(det) > EDMI_R(16.0) * EDMI_EPS * amax * cmax))
        return EDMI_ERR_SINGULAR;
    id = EDMI__ONE / det;
    for (i = 0; i < 3; i++)
        x[i] = (adj[3 * i] * b[0] + adj[3 * i + 1] * b[1] + adj[3 * i + 2] * b[2]) * id;
    return EDMI_OK;
}

/* One body on one link (no damper): G = I + h k = alpha I + c r_m u^T, k the link's tangent
 * block dt (beta/2 I + gamma r_m u^T) and h = dt / (2m), solved by Sherman-Morrison:
 * x = (b - c (u.b) / (alpha + c u.r_m) r_m) / alpha. det G = alpha^2 (alpha + c u.r_m) and
 * ||G^-1|| <= (1 + |c| |r_m| |u| / |den|) / |alpha|, so with N = |alpha| + |c| |r_m|_1 |u|_1 >= ||G||
 * the condition number is below 2 N^2 / (|alpha| |den|): singular, as edmi__solve3 judges it,
 * beyond 1/(16 eps). A virtual spring's step at a tenth of the general solve's cost. */
static edmi_status edmi__solve_one_link(const edmi_link_ws *w, edmi_real h, edmi_real dt,
                                        edmi_real b[3])
{
    edmi_real alpha = EDMI__ONE + h * dt * EDMI__HALF * w->beta, c = h * dt * w->gamma;
    edmi_real t = edmi__dot(w->u, w->rm), den = alpha + c * t, r1 = EDMI__ZERO, u1 = EDMI__ZERO;
    edmi_real nrm, f;
    int i;
    for (i = 0; i < 3; i++) { /* 1-norms: no root, no overflow of a square */
        r1 += edmi__abs(w->rm[i]);
        u1 += edmi__abs(w->u[i]);
    }
    nrm = edmi__abs(alpha) + edmi__abs(c) * r1 * u1;
    if (!((edmi__abs(alpha) / nrm) * (edmi__abs(den) / nrm) > EDMI_R(32.0) * EDMI_EPS))
        return EDMI_ERR_SINGULAR; /* NaN too */
    f = c * edmi__dot(w->u, b) / den;
    for (i = 0; i < 3; i++)
        b[i] = (b[i] - f * w->rm[i]) / alpha;
    return EDMI_OK;
}

/* The largest body-index gap of a pair link. */
static int edmi__max_gap(const edmi_system *sys)
{
#if EDMI_MAX_MASS_GAP > 0
    int j, w = edmi__mass_gap(sys);
#else
    int j, w = 0;
#endif
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        if (lk->b != EDMI_ANCHOR) {
            int g = lk->a > lk->b ? lk->a - lk->b : lk->b - lk->a;
            if (g > w)
                w = g;
        }
    }
    return w;
}

/* Scalar half-bandwidth of the Newton matrix: 3 * (largest body-index gap of a pair link or
 * a coupled mass) + 2. */
static int edmi__bandwidth(const edmi_system *sys) { return 3 * edmi__max_gap(sys) + 2; }

/* Width of a stored row of the Newton matrix of n unknowns, half-bandwidth kb: the band
 * i - kb .. i + 2 kb (fill-in from row exchanges included), or the whole row. */
static int edmi__row_width(int n, int kb) { return 3 * kb + 1 < n ? 3 * kb + 1 : n; }

/* Whether the Newton matrix of n_bodies bodies, largest pair gap `gap`, fits EDMI_MAX_MATRIX
 * (one body needs none: its 3x3 system is solved in closed form). */
static int edmi__matrix_fits(int n_bodies, int gap)
{
    long n = 3L * n_bodies;
    return n_bodies <= 1 || n * (long)edmi__row_width((int)n, 3 * gap + 2) <= (long)EDMI_MAX_MATRIX;
}

/* Row offsets of the band storage: row i holds W entries from column
 * s_i = max(0, min(i - kb, n - W)), so element (i, j) is mat[row[i] + j], row[i] = i W - s_i
 * (>= 0). With W = n (a dense band) row[i] = i n: the plain row-major matrix. */
static void edmi__band_rows(int *row, int n, int kb)
{
    int w = edmi__row_width(n, kb), i;
    for (i = 0; i < n; i++) {
        int s0 = i - kb < n - w ? i - kb : n - w;
        row[i] = i * w - (s0 > 0 ? s0 : 0);
    }
}

/* Add the tangent block k = d(force on a)/d(q_a - q_b) of a force acting + on body a and -
 * on body b into the matrix g (element (i, j) at g[row[i] + j]), rows of a scaled by ha, of
 * b by hb. */
static void edmi__scatter_pair(edmi_real *g, const int *row, int a, int b, const edmi_real k[9],
                               edmi_real ha, edmi_real hb)
{
    int r, c, ra = 3 * a, rb = 3 * b;
    for (r = 0; r < 3; r++) {
        edmi_real *ga = g + row[ra + r], *gb = g + row[rb + r];
        for (c = 0; c < 3; c++) {
            edmi_real v = k[3 * r + c];
            ga[ra + c] += ha * v;
            ga[rb + c] -= ha * v;
            gb[ra + c] -= hb * v;
            gb[rb + c] += hb * v;
        }
    }
}

/* The same for a force on body a from a fixed anchor: only the (a, a) block. */
static void edmi__scatter_anchor(edmi_real *g, const int *row, int a, const edmi_real k[9],
                                 edmi_real ha)
{
    int r, c, ra = 3 * a;
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++)
            g[row[ra + r] + ra + c] += ha * k[3 * r + c];
}

/* A damper acts along a link that may be a pair or an anchor link. */
static void edmi__scatter(edmi_real *g, const int *row, const edmi_link *lk, const edmi_real k[9],
                          edmi_real ha, edmi_real hb)
{
    if (lk->b == EDMI_ANCHOR)
        edmi__scatter_anchor(g, row, lk->a, k, ha);
    else
        edmi__scatter_pair(g, row, lk->a, lk->b, k, ha, hb);
}

/* Assemble G = I + dt/(2 m_A) dR_p/dq1 (rows of body A) into the band storage of work->mat
 * (work->row). */
static void edmi__assemble(const edmi_system *sys, edmi_workspace *work, edmi_real dt, int n,
                           int kb)
{
    edmi_real *g = work->mat, k[9];
    const int *row = work->row;
    int i, j, size = n * edmi__row_width(n, kb);
    edmi__band_rows(work->row, n, kb);
    for (i = 0; i < size; i++)
        g[i] = EDMI__ZERO;
    for (i = 0; i < n; i++)
        g[row[i] + i] = EDMI__ONE;
#if EDMI_MAX_MASS_GAP > 0
    for (i = 1; i < sys->n_bodies; i++) /* coupled masses: m_ab / m_aa I in block (a, b) */
        for (j = 0; j < EDMI_MAX_MASS_GAP && j < i; j++) {
            edmi_real m = sys->mass_off[i][j];
            int b = i - 1 - j, c;
            for (c = 0; c < 3 && m != EDMI__ZERO; c++) {
                g[row[3 * i + c] + 3 * b + c] += m / sys->body[i].m;
                g[row[3 * b + c] + 3 * i + c] += m / sys->body[b].m;
            }
        }
#endif
    for (j = 0; j < work->n_pair; j++) {
        const edmi_link *lk = &sys->link[work->order[j]];
        edmi__link_tangent(&work->lw[work->order[j]], dt, k);
        edmi__scatter_pair(g, row, lk->a, lk->b, k, work->h[lk->a], work->h[lk->b]);
    }
    for (j = work->n_pair; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[work->order[j]];
        edmi__link_tangent(&work->lw[work->order[j]], dt, k);
        edmi__scatter_anchor(g, row, lk->a, k, work->h[lk->a]);
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++) {
        if (work->ww[j].gamma == EDMI__ZERO)
            continue; /* a wall off its body */
        edmi__wall_tangent(&sys->wall[j], &work->ww[j], dt, k);
        edmi__scatter_anchor(g, row, sys->wall[j].a, k, work->h[sys->wall[j].a]);
    }
#endif
#if EDMI_MAX_DAMPERS > 0
    for (j = 0; j < EDMI__N_DAMPERS(sys); j++) {
        const edmi_link *lk = &sys->link[sys->damper[j].link];
        edmi_real ha = work->h[lk->a];
        edmi_real hb = lk->b == EDMI_ANCHOR ? EDMI__ZERO : work->h[lk->b];
        edmi__scatter(g, row, lk, work->kd[j], ha, hb);
    }
#endif
}

/* x[0..m-1] -= f y[0..m-1], m >= 1: the elimination's inner loop, tested at its bottom (a
 * Cortex-M4F at -Os then takes 6 instructions per entry instead of 8). */
static void edmi__axpy_neg(edmi_real *x, const edmi_real *y, edmi_real f, int m)
{
    do {
        *x -= f * *y;
        x++;
        y++;
    } while (--m > 0);
}

/* Factor G = L U in place by banded Gaussian elimination with partial pivoting: lower
 * bandwidth kb, upper bandwidth kb, and 2 kb once a row exchange has brought a row's fill-in
 * (until then every row of U ends at its diagonal + kb: in the chain and solar profiles no
 * exchange ever happens, and the wider loops only multiplied zeros). Step k's multipliers
 * are kept where they eliminated (g[i][k], i > k) and its pivot row in piv[k]: later
 * exchanges move only columns > k, so edmi__lu_solve replays the elimination on a right-hand
 * side in the same order, with the same operations as a fused solve. *upper: U's bandwidth. */
static edmi_status edmi__lu_band(edmi_real *g, const int *row, int n, int kb, int *piv,
                                 int *upper)
{
    edmi_real amax = EDMI__ZERO;
    int i, j, k, up = kb;
    for (i = 0; i < n; i++) {
        const edmi_real *gi = g + row[i];
        int lo = i - kb < 0 ? 0 : i - kb, hi = i + kb >= n ? n - 1 : i + kb;
        for (j = lo; j <= hi; j++)
            amax = edmi__max(amax, edmi__abs(gi[j]));
    }
    if (!(amax > EDMI__ZERO) || !edmi__finite(amax))
        return EDMI_ERR_SINGULAR;
    for (k = 0; k < n; k++) {
        edmi_real *gk = g + row[k], best = edmi__abs(gk[k]), piv_k;
        int last = k + kb >= n ? n - 1 : k + kb, p = k, cmax;
        for (i = k + 1; i <= last; i++)
            if (edmi__abs(g[row[i] + k]) > best) {
                best = edmi__abs(g[row[i] + k]);
                p = i;
            }
        if (!(best > EDMI_R(4.0) * EDMI_EPS * amax))
            return EDMI_ERR_SINGULAR;
        piv[k] = p;
        if (p != k) {
            edmi_real *gp = g + row[p], t;
            up = 2 * kb;
            cmax = k + up >= n ? n - 1 : k + up;
            for (j = k; j <= cmax; j++) {
                t = gk[j];
                gk[j] = gp[j];
                gp[j] = t;
            }
        }
        cmax = k + up >= n ? n - 1 : k + up;
        piv_k = gk[k];
        for (i = k + 1; i <= last; i++) {
            edmi_real *gi = g + row[i], f = gi[k] / piv_k;
            gi[k] = f;
            if (f != EDMI__ZERO && cmax > k)
                edmi__axpy_neg(gi + k + 1, gk + k + 1, f, cmax - k);
        }
    }
    *upper = up;
    return EDMI_OK;
}

/* Solve L U x = rhs in place with edmi__lu_band's factors. Without a row exchange (upper ==
 * kb) L's rows are applied as dot products, each in the column order the elimination used
 * (the same sums: a zero multiplier subtracts 0), at half the instructions of the
 * column-by-column replay exchanges need. */
static void edmi__lu_solve(const edmi_real *g, const int *row, edmi_real *rhs, int n, int kb,
                           int upper, const int *piv)
{
    int i, j, k;
    for (i = 1; upper == kb && i < n; i++) {
        const edmi_real *gi = g + row[i];
        edmi_real s = rhs[i];
        for (k = i - kb < 0 ? 0 : i - kb; k < i; k++)
            s -= gi[k] * rhs[k];
        rhs[i] = s;
    }
    for (k = 0; upper != kb && k < n; k++) {
        int last = k + kb >= n ? n - 1 : k + kb;
        if (piv[k] != k) {
            edmi_real t = rhs[k];
            rhs[k] = rhs[piv[k]];
            rhs[piv[k]] = t;
        }
        for (i = k + 1; i <= last; i++) {
            edmi_real f = g[row[i] + k];
            if (f != EDMI__ZERO)
                rhs[i] -= f * rhs[k];
        }
    }
    for (i = n - 1; i >= 0; i--) {
        const edmi_real *gi = g + row[i];
        int cmax = i + upper >= n ? n - 1 : i + upper;
        edmi_real s = rhs[i];
        for (j = i + 1; j <= cmax; j++)
            s -= gi[j] * rhs[j];
        rhs[i] = s / gi[i];
    }
}

/* Two bodies joined only by pair links (and dampers on them): every tangent block k acts on
 * x = dq_0 - dq_1, so G dq = rhs reads (I + (h_0 + h_1) K) x = rhs_0 - rhs_1, K the sum of
 * the blocks, then dq_0 = rhs_0 - h_0 K x, dq_1 = rhs_1 + h_1 K x: one 3x3 solve in place of
 * a 6x6 elimination (the paper's Lennard-Jones pair). */
static edmi_status edmi__solve_two_body(const edmi_system *sys, edmi_workspace *work,
                                        edmi_real dt)
{
    edmi_real kk[9], g[9], k[9], b[3], x[3], hs = work->h[0] + work->h[1];
    edmi_status st;
    int i, j;
    for (i = 0; i < 9; i++)
        kk[i] = EDMI__ZERO;
    for (j = 0; j < sys->n_links; j++) {
        edmi__link_tangent(&work->lw[j], dt, k);
        for (i = 0; i < 9; i++)
            kk[i] += k[i];
    }
    for (j = 0; j < EDMI__N_DAMPERS(sys); j++)
        for (i = 0; i < 9; i++)
            kk[i] += work->kd[j][i];
    for (i = 0; i < 9; i++)
        g[i] = hs * kk[i];
    g[0] += EDMI__ONE;
    g[4] += EDMI__ONE;
    g[8] += EDMI__ONE;
    for (i = 0; i < 3; i++)
        b[i] = work->rhs[i] - work->rhs[3 + i];
    st = edmi__solve3(g, b, x);
    if (st != EDMI_OK)
        return st;
    for (i = 0; i < 3; i++) {
        edmi_real kx = edmi__dot(kk + 3 * i, x);
        work->rhs[i] -= work->h[0] * kx;
        work->rhs[3 + i] += work->h[1] * kx;
    }
    return EDMI_OK;
}

/* Whether the kept factors' bookkeeping fits this system (edmi_step): its bandwidth, U's
 * bandwidth, and every pivot row within the band; the row offsets are set again. A
 * workspace that lives on a stack between calls may keep the record and lose the rest: its
 * numbers then only cost a correction (edmi__newton goes back to the predictor), and no index
 * they hold is used. */
static int edmi__kept_sane(const edmi_system *sys, edmi_workspace *work)
{
    int n = 3 * sys->n_bodies, k;
    if (work->kb != edmi__bandwidth(sys) ||
        (work->upper != work->kb && work->upper != 2 * work->kb))
        return 0;
    for (k = 0; k < n; k++)
        if (work->piv[k] < k || work->piv[k] > k + work->kb || work->piv[k] >= n)
            return 0;
    edmi__band_rows(work->row, n, work->kb);
    return 1;
}

/* One Newton correction: solve for dq (into work->rhs), recover dp = 2m/dt (R_q + dq). With
 * `reuse` (several bodies, edmi__newton) the factors of the last correction's matrix are
 * used again (a chord correction) instead of assembling and factoring the current one. */
static edmi_status edmi__newton_update(const edmi_system *sys, edmi_workspace *work,
                                       edmi_real dt, int reuse)
{
    int nb = sys->n_bodies, n = 3 * nb, a, i;
    edmi_status st;
    for (a = 0; a < nb; a++) {
        edmi_real h = dt / (EDMI_R(2.0) * sys->body[a].m), *rhs = work->rhs + 3 * a;
        work->h[a] = h;
        rhs[0] = -work->rq[a][0] - h * work->rp[a][0];
        rhs[1] = -work->rq[a][1] - h * work->rp[a][1];
        rhs[2] = -work->rq[a][2] - h * work->rp[a][2];
    }
    /* (a one-body capacity compiles the one-body solves alone) */
    if (nb == 1 && sys->n_links == 1 && EDMI__N_DAMPERS(sys) == 0 && EDMI__N_WALLS(sys) == 0) {
        st = edmi__solve_one_link(&work->lw[0], work->h[0], dt, work->rhs);
        if (st != EDMI_OK)
            return st;
    } else if (EDMI_MAX_BODIES == 1 || nb == 1) {
        edmi_real g[9], x[3], k[9];
        edmi_real h = work->h[0];
        int j;
        for (i = 0; i < 9; i++)
            g[i] = EDMI__ZERO;
        for (j = 0; j < sys->n_links; j++) { /* one body: every link is an anchor link */
            edmi__link_tangent(&work->lw[j], dt, k);
            for (i = 0; i < 9; i++)
                g[i] += h * k[i];
        }
        for (j = 0; j < EDMI__N_DAMPERS(sys); j++)
            for (i = 0; i < 9; i++)
                g[i] += h * work->kd[j][i];
#if EDMI_MAX_WALLS > 0
        for (j = 0; j < EDMI__N_WALLS(sys); j++) {
            if (work->ww[j].gamma == EDMI__ZERO)
                continue; /* a wall off its body */
            edmi__wall_tangent(&sys->wall[j], &work->ww[j], dt, k);
            for (i = 0; i < 9; i++)
                g[i] += h * k[i];
        }
#endif
        g[0] += EDMI__ONE;
        g[4] += EDMI__ONE;
        g[8] += EDMI__ONE;
        st = edmi__solve3(g, work->rhs, x);
        if (st != EDMI_OK)
            return st;
        edmi__copy3(x, work->rhs);
    } else if (nb == 2 && work->n_pair == sys->n_links && !EDMI__COUPLED(sys) &&
               EDMI__N_WALLS(sys) == 0) {
        work->kb = 0; /* nothing factored to reuse */
        st = edmi__solve_two_body(sys, work, dt);
        if (st != EDMI_OK)
            return st;
    } else {
        if (!reuse) {
            work->kept = 0;
            work->kb = edmi__bandwidth(sys);
            edmi__assemble(sys, work, dt, n, work->kb);
            st = edmi__lu_band(work->mat, work->row, n, work->kb, work->piv, &work->upper);
            work->fresh = st == EDMI_OK;
            if (st != EDMI_OK)
                return st;
        }
        edmi__lu_solve(work->mat, work->row, work->rhs, n, work->kb, work->upper, work->piv);
    }
    for (a = 0; a < nb; a++) {
        edmi_real c = EDMI_R(2.0) * sys->body[a].m / dt, *rhs = work->rhs + 3 * a;
        work->dp[a][0] = c * (work->rq[a][0] + rhs[0]);
        work->dp[a][1] = c * (work->rq[a][1] + rhs[1]);
        work->dp[a][2] = c * (work->rq[a][2] + rhs[2]);
    }
#if EDMI_MAX_MASS_GAP > 0
    for (a = 1; a < nb; a++) { /* dp = 2/dt (M_diag (R_q + dq) + M_off dq) */
        int k;
        for (k = 0; k < EDMI_MAX_MASS_GAP && k < a; k++) {
            edmi_real c = EDMI_R(2.0) * sys->mass_off[a][k] / dt;
            int b = a - 1 - k;
            for (i = 0; i < 3; i++) {
                work->dp[a][i] += c * work->rhs[3 * b + i];
                work->dp[b][i] += c * work->rhs[3 * a + i];
            }
        }
    }
#endif
    return EDMI_OK;
}

/* ==========================================================================================
 * Newton
 *
 * The predictor multi-corrector with a scale-aware stopping test. R_q and R_p carry
 * different units and bodies differ by orders of magnitude (the Sun and Mercury), so each
 * body's residual blocks are measured against that body's own scales:
 *   S_p = |p_n| + |R_p at the predictor| (momentum plus the impulse of one step),
 *   S_q = |q_n| + dt/m S_p               (position plus the motion of one step),
 * and the scaled residual is the largest |R_q|/S_q, |R_p|/S_p over bodies. A step is solved
 * when every body's residual is within EDMI_SOLVED units of its round-off noise.
 * ======================================================================================== */

/* Move the iterate by lambda times the Newton correction (dq in work->rhs, dp in work->dp). */
static void edmi__move(const edmi_system *sys, edmi_workspace *work, edmi_real lambda)
{
    int a;
    for (a = 0; a < sys->n_bodies; a++) {
        edmi__axpy3(lambda, work->rhs + 3 * a, work->q1[a]);
        edmi__axpy3(lambda, work->dp[a], work->p1[a]);
    }
}

static edmi_status edmi__set_scales(const edmi_system *sys, edmi_workspace *work, edmi_real dt)
{
    int a;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi_real sp = edmi__norm(bd->p) + edmi__norm(work->rp[a]);
        edmi_real sq = edmi__norm(bd->q) + dt / bd->m * sp;
        /* A scale that overflows would make every residual look like 0 against it. */
        if (!edmi__finite(sq))
            return EDMI_ERR_OVERFLOW;
        work->sp[a] = sp > EDMI__ZERO ? sp : EDMI__ONE;
        work->sq[a] = sq > EDMI__ZERO ? sq : EDMI__ONE;
    }
    return EDMI_OK;
}

/* The scaled norm of a pair of per-body position and momentum blocks (dq in rows of 3). */
static edmi_real edmi__scaled_norm(const edmi_system *sys, const edmi_workspace *work,
                                   const edmi_real *dq, const edmi_real (*dp)[3])
{
    edmi_real r = EDMI__ZERO;
    int a;
    for (a = 0; a < sys->n_bodies; a++) {
        r = edmi__max(r, edmi__norm(dq + 3 * a) / work->sq[a]);
        r = edmi__max(r, edmi__norm(dp[a]) / work->sp[a]);
    }
    return r;
}

static edmi_real edmi__scaled_residual(const edmi_system *sys, const edmi_workspace *work)
{
    return edmi__scaled_norm(sys, work, work->rq[0], (const edmi_real (*)[3])work->rp);
}

/* Residual, tangent and scaled residual at the current iterate. */
static edmi_status edmi__evaluate(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                  edmi_real *r, edmi_step_result *res)
{
    edmi_status st = edmi__residual(sys, work, dt, (const edmi_real (*)[3])work->q1,
                                    (const edmi_real (*)[3])work->p1, work->rq, work->rp,
                                    &res->lg_switches);
    if (st == EDMI_OK)
        *r = edmi__scaled_residual(sys, work);
    return st;
}

/* Take the Newton correction; halve it while the trial leaves the potentials' domain (a link
 * distance of 0 or a non-finite residual, e.g. a near-collision overshoot). No descent test:
 * at omega dt >> 1 plain Newton reaches the solution along a non-monotone path that a
 * monotone line search blocks. */
static edmi_status edmi__line_search(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                     edmi_real *r, edmi_step_result *res, edmi_real *moved)
{
    edmi_real lambda = EDMI__ONE;
    edmi_status st;
    int h;
    edmi__move(sys, work, lambda);
    st = edmi__evaluate(sys, work, dt, r, res);
    for (h = 0; h < EDMI__MAX_HALVINGS && (st == EDMI_ERR_DOMAIN || st == EDMI_ERR_OVERFLOW);
         h++) {
        lambda *= EDMI__HALF;
        edmi__move(sys, work, -lambda);
        st = edmi__evaluate(sys, work, dt, r, res);
        res->halvings++;
    }
    *moved = lambda;
    return st == EDMI_ERR_DOMAIN || st == EDMI_ERR_OVERFLOW ? EDMI_ERR_DIVERGED : st;
}

/* Every stop that returns EDMI_OK has each body's residual within this factor of its
 * round-off noise (edmi__solved; edmi.h states the bound). */
#define EDMI__SOLVED ((edmi_real)EDMI_SOLVED)

/* The round-off noise of each body's residual at the current iterate, into work->rhs (which
 * the next correction overwrites): rhs[2a] for R_q, rhs[2a + 1] for R_p, EDMI_EPS times the
 * magnitudes summed into them. R_q = q1 - q0 - h (p0 + p1) (plus the coupled masses' rows):
 * |q_n| + |q1| + dt/m (|p_n| + |p1|) =: Q_a. R_p = p1 - p0 + the impulses: |p_n| + |p1|, the
 * ports' and the field's dt |F|, and per link the impulse dt |beta r_m| and its tangent block
 * (d f / d r_n+1, ~dt V'') times 3 (|r_m| + Q_a + Q_b): the grid of the iterate's own
 * positions and the resolution Newton stops at (a correction below eps of the motion), which
 * near rest away from the origin (|r| ~ 1e-15 at |q| ~ 1) and on a stiff step (omega dt =
 * 100, dt |p| / m >> |q|) is far above the force's own rounding; plus the potential's
 * cancelling terms (LJ's two parts, GE's convex and concave halves, the LG quotient's
 * eps |V| / |d1 - d0|: edmi_link_ws.noise), and per damper c (|r_n| + |r1| + Q_a + Q_b). All
 * of it from the iterate and the step's start: nothing a far predictor inflates. */
static void edmi__noise(const edmi_system *sys, edmi_workspace *work, edmi_real dt)
{
    const edmi_real (*q1)[3] = (const edmi_real (*)[3])work->q1;
    edmi_real *acc = work->rhs;
    int a, j, i;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi_real np = edmi__norm(bd->p) + edmi__norm(work->p1[a]);
        /* the subnormal unit REAL_MIN eps too: below the smallest normal, rounding is absolute
         * (a body settling onto its anchor in float reaches q ~ 1e-41, where Newton's
         * residual cannot fall below ~1e-4 of its scales) */
        acc[2 * a] = EDMI_EPS * (edmi__norm(bd->q) + edmi__norm(q1[a]) + dt / bd->m * np) +
                     EDMI_R(16.0) * EDMI__REAL_MIN * EDMI_EPS;
        acc[2 * a + 1] = EDMI_EPS * np + EDMI_R(16.0) * EDMI__REAL_MIN * EDMI_EPS;
        if (EDMI__HAS_FIELD(sys))
            acc[2 * a + 1] += EDMI_EPS * dt * edmi__abs(edmi__mass_row(sys, a)) *
                              edmi__norm(sys->g);
    }
#if EDMI_MAX_MASS_GAP > 0
    for (a = 1; a < sys->n_bodies; a++) /* R_q's coupled terms m_ab / m_aa (q1_b - q_n,b) */
        for (j = 0; j < EDMI_MAX_MASS_GAP && j < a; j++) {
            edmi_real m = edmi__abs(sys->mass_off[a][j]);
            int b = a - 1 - j;
            acc[2 * a] += EDMI_EPS * m / sys->body[a].m *
                          (edmi__norm(q1[b]) + edmi__norm(sys->body[b].q));
            acc[2 * b] += EDMI_EPS * m / sys->body[b].m *
                          (edmi__norm(q1[a]) + edmi__norm(sys->body[a].q));
        }
#endif
    for (i = 0; i < EDMI__N_FORCED(sys); i++) {
        int b = sys->internal.forced[i];
        acc[2 * b + 1] += EDMI_EPS * dt * edmi__norm(sys->force[b]);
    }
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        const edmi_link_ws *w = &work->lw[j];
        edmi_real r1[3], rm[3], k[9], kmax = EDMI__ZERO, x, nrm, qb;
        edmi__sub(q1[lk->a], edmi__end_b(lk, w, q1), r1);
        for (i = 0; i < 3; i++)
            rm[i] = EDMI__HALF * (w->r0[i] + r1[i]);
        edmi__link_tangent(w, dt, k);
        for (i = 0; i < 9; i++)
            kmax = edmi__max(kmax, edmi__abs(k[i]));
        if (edmi__is_linear(&lk->pot)) /* GE's tangent is 0 where d_n+1 = 0, its kink; the
                                          force's slope around it is up to dt k */
            kmax = edmi__max(kmax, dt * edmi__abs(lk->pot.a));
        nrm = edmi__norm(rm);
        qb = lk->b == EDMI_ANCHOR ? EDMI_EPS * edmi__norm(w->x1) : acc[2 * lk->b];
        x = EDMI_R(4.0) * (EDMI_EPS * dt * edmi__abs(w->beta) * nrm +
                           EDMI_R(3.0) * kmax * (EDMI_EPS * nrm + acc[2 * lk->a] + qb)) +
            w->noise;
        acc[2 * lk->a + 1] += x;
        if (lk->b != EDMI_ANCHOR)
            acc[2 * lk->b + 1] += x;
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++) { /* a link to the plane, of slope dt Lambda' */
        const edmi_wall *wl = &sys->wall[j];
        const edmi_link_ws *w = &work->ww[j];
        edmi_real k = dt * edmi__abs(w->gamma);
        if (wl->pot.kind == EDMI_POT_HARMONIC) /* as a linear spring: its slope everywhere */
            k = edmi__max(k, dt * edmi__abs(wl->pot.a));
        acc[2 * wl->a + 1] +=
            EDMI_R(4.0) * (EDMI_EPS * dt * edmi__abs(w->beta) +
                           EDMI_R(3.0) * k * (EDMI_EPS * (edmi__norm(q1[wl->a]) + edmi__abs(wl->c)) +
                                              acc[2 * wl->a]));
    }
#endif
#if EDMI_MAX_DAMPERS > 0
    for (j = 0; j < EDMI__N_DAMPERS(sys); j++) {
        const edmi_link *lk = &sys->link[sys->damper[j].link];
        const edmi_link_ws *w = &work->lw[sys->damper[j].link];
        edmi_real r1[3], x, qb;
        edmi__sub(q1[lk->a], edmi__end_b(lk, w, q1), r1);
        qb = lk->b == EDMI_ANCHOR ? EDMI_EPS * edmi__norm(w->x1) : acc[2 * lk->b];
        x = EDMI_R(4.0) * sys->damper[j].c *
            (EDMI_EPS * (edmi__norm(w->r0) + edmi__norm(r1)) + acc[2 * lk->a] + qb);
        acc[2 * lk->a + 1] += x;
        if (lk->b != EDMI_ANCHOR)
            acc[2 * lk->b + 1] += x;
    }
#endif
}

/* The largest noise of edmi__noise over the bodies' scales: what the scaled residual cannot
 * fall below. Computed only when Newton's residual stopped halving. */
static edmi_real edmi__noise_floor(const edmi_system *sys, edmi_workspace *work, edmi_real dt)
{
    edmi_real fl = EDMI__ZERO;
    int a;
    edmi__noise(sys, work, dt);
    for (a = 0; a < sys->n_bodies; a++)
        fl = edmi__max(fl, edmi__max(work->rhs[2 * a] / work->sq[a],
                                     work->rhs[2 * a + 1] / work->sp[a]));
    return fl;
}

/* Whether the iterate solves the scheme's equations to within f times its round-off noise,
 * body by body: |R_q,a| <= f noise_q,a and |R_p,a| <= f noise_p,a (edmi__noise). The test
 * every successful step passes (edmi.h, EDMI_STOP_CONVERGED): judged by the terms' own
 * magnitudes, not by the predictor's residual, which deep in a repulsive wall is 1e30 and
 * made an untouched iterate look converged. */
#ifdef EDMI_DEBUG_ACCEPT
void edmi_debug_accept(edmi_real x); /* measurement hook: the largest |R| / noise of a stop */
#endif
/* The test above from lower bounds of the magnitudes alone, |q_n| + |q1| and |p_n| + |p1|
 * by their largest components, and |R| <= 2 max |R_i|: where it holds the full test holds
 * too. Newton's floor is a few eps of these, so a converged step rarely needs the full sum
 * (half of a float spring step's Newton cost otherwise). */
static edmi_real edmi__max_abs3(const edmi_real v[3])
{
    return edmi__max(edmi__abs(v[0]), edmi__max(edmi__abs(v[1]), edmi__abs(v[2])));
}

static int edmi__solved_below(const edmi_system *sys, const edmi_workspace *work, edmi_real f)
{
    int a;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi_real q = edmi__max_abs3(bd->q) + edmi__max_abs3(work->q1[a]);
        edmi_real p = edmi__max_abs3(bd->p) + edmi__max_abs3(work->p1[a]);
        if (!(EDMI_R(2.0) * edmi__max_abs3(work->rq[a]) <= f * EDMI_EPS * q) ||
            !(EDMI_R(2.0) * edmi__max_abs3(work->rp[a]) <= f * EDMI_EPS * p) ||
            !edmi__finite(q) || !edmi__finite(p))
            return 0;
    }
    return 1;
}

static int edmi__solved(const edmi_system *sys, edmi_workspace *work, edmi_real dt, edmi_real f)
{
    int a;
#ifndef EDMI_DEBUG_ACCEPT
    if (edmi__solved_below(sys, work, f))
        return 1;
#endif
    edmi__noise(sys, work, dt);
#ifdef EDMI_DEBUG_ACCEPT
    {
        edmi_real x = EDMI__ZERO;
        for (a = 0; a < sys->n_bodies; a++)
            x = edmi__max(x, edmi__max(edmi__norm(work->rq[a]) / work->rhs[2 * a],
                                       edmi__norm(work->rp[a]) / work->rhs[2 * a + 1]));
        if (f == EDMI__SOLVED)
            edmi_debug_accept(x);
    }
#endif
    for (a = 0; a < sys->n_bodies; a++) /* a noise beyond the range judges nothing */
        if (!(edmi__norm(work->rq[a]) <= f * work->rhs[2 * a]) ||
            !(edmi__norm(work->rp[a]) <= f * work->rhs[2 * a + 1]) ||
            !edmi__finite(work->rhs[2 * a]) || !edmi__finite(work->rhs[2 * a + 1]))
            return 0;
    return 1;
}

/* The paper's predictor q_n+1,(0) = q_n, p_n+1,(0) = p_n, and its residual. */
static edmi_status edmi__predictor(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                   edmi_step_result *res)
{
    int a;
    for (a = 0; a < sys->n_bodies; a++) {
        edmi__copy3(sys->body[a].q, work->q1[a]);
        edmi__copy3(sys->body[a].p, work->p1[a]);
    }
    return edmi__residual(sys, work, dt, (const edmi_real (*)[3])work->q1,
                          (const edmi_real (*)[3])work->p1, work->rq, work->rp,
                          &res->lg_switches);
}

/* The explicit predictor (edmi__newton): from the residual at (q_n, p_n), R_p = the impulse
 * of the forces over the step with the sign of R_p, p = p_n - R_p, q = q_n + dt/(2m)(p_n + p);
 * evaluated, with *r its scaled residual. */
static edmi_status edmi__explicit_predictor(const edmi_system *sys, edmi_workspace *work,
                                            edmi_real dt, edmi_real *r, edmi_step_result *res)
{
    int a, i;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        for (i = 0; i < 3; i++) {
            work->p1[a][i] = bd->p[i] - work->rp[a][i];
            work->q1[a][i] = bd->q[i] + dt / (EDMI_R(2.0) * bd->m) * (bd->p[i] + work->p1[a][i]);
        }
    }
    return edmi__evaluate(sys, work, dt, r, res);
}

/* Whether a chord correction (the last factors of the Newton matrix used again) pays: when
 * factoring, ~n kb^2 multiply-adds for n = 3 N unknowns and half-bandwidth kb, costs more
 * than a residual evaluation, a few hundred operations per link. A chord correction
 * contracts linearly (the next correction ~ c_l^2 / c_l-1, not c_l^3 / c_l-1^2), which the
 * rate below keeps close to Newton's count of corrections (docs/api.md, "Solver"). One-body
 * systems solve 3x3 in closed form and never reuse. */
#define EDMI__CHORD_RATE (EDMI_R(1.0) / EDMI_R(8.0))

static int edmi__chord_pays(const edmi_system *sys, const edmi_workspace *work)
{
    long n = 3L * sys->n_bodies, kb = work->kb;
    return n * kb * kb > 256L * sys->n_links;
}

/* A residual that stopped halving within this factor of its round-off noise is there. */
#define EDMI__NOISE_FACTOR EDMI_R(8.0)

/* Newton's record of its iterations, for its choice of correction and its stop tests. */
typedef struct edmi__newton_log {
    int l;                /* the iteration, from 1 */
    int chord;            /* its correction reused old factors */
    int halvings_before;  /* res->halvings before its line search */
    edmi_real r, rprev;   /* the scaled residual after and before it */
    edmi_real c;          /* its scaled correction, before the line search halved it */
    edmi_real cprev;      /* the correction taken at the iteration before (c moved) */
    edmi_real cprev2;     /* and at the one before that */
    edmi_real moved;      /* the fraction of c taken */
    int contracted;       /* c contracted by EDMI__CHORD_RATE on the one before */
    int refreshed;        /* the kept factors were factored anew at an iterate of this step */
    int chord_ok;         /* chords still allowed in this step */
} edmi__newton_log;

/* Whether iteration g->l + 1 takes a chord correction (the last factors again), where
 * factoring costs more than it saves (edmi__chord_pays): at l = 1 from the factors the last
 * step kept; later only once a contracting correction has brought the residual into Newton's
 * quadratic tail, below sqrt(eps) r_0, because the first tangent at a far predictor is a poor
 * one, or once the last step's factors stopped contracting and were factored anew at an
 * iterate their chord corrections had brought near. With tol_r or tol_a too: a chord stops
 * just below the tolerance where Newton's quadratic last step lands far below it. A chord
 * correction that does not contract by 8, or raises the residual, ends the chord for the
 * step. docs/api.md ("Solver") gives the measured cases behind each rule. */
static int edmi__chord_now(const edmi_system *sys, const edmi_workspace *work,
                           const edmi__newton_log *g, edmi_real residual0, int l)
{
    return g->chord_ok && sys->n_bodies > 1 && g->moved == EDMI__ONE &&
           (l == 1 ? work->kept
                   : g->contracted && (work->kept || g->refreshed ||
                                       g->r <= EDMI__SQRT_EPS * residual0)) &&
           edmi__chord_pays(sys, work);
}

/* The stops at a solution, tested after each correction (edmi_stop): the optional tol_r and
 * tol_a; CONVERGED when the next correction, predicted from the last two in Newton's
 * quadratic regime (c_l+1 = C c_l^2 with C = c_l / c_l-1^2, so c_l+1 = c_l^3 / c_l-1^2,
 * taken only when the last two corrections each contracted by 4 or more and the residual is
 * in its quadratic tail too, not risen and below sqrt(eps) r_0: at omega dt = 100 the Newton
 * matrix is ~1e4 I, and a small correction can follow a large one far from the root), would
 * be below eps in the scaled norm, so that it could not move the iterate by a unit
 * roundoff, or when a full correction (or the residual) is exactly 0. 1 where Newton stops,
 * with its status in *st. */
static int edmi__newton_solved(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                               const edmi__newton_log *g, edmi_step_result *res,
                               edmi_status *st)
{
    const edmi_params *prm = &sys->params;
    edmi_real r = g->r, c = g->c;
    *st = EDMI_OK;
    if (prm->tol_r > EDMI__ZERO && r <= prm->tol_r * res->residual0 &&
        edmi__solved(sys, work, dt, edmi__max(EDMI__SOLVED, prm->tol_r / EDMI_EPS))) {
        res->stop = EDMI_STOP_TOL_R;
        return 1;
    }
    if (prm->tol_a > EDMI__ZERO && r <= prm->tol_a &&
        edmi__solved(sys, work, dt, edmi__max(EDMI__SOLVED, prm->tol_a / EDMI_EPS))) {
        res->stop = EDMI_STOP_TOL_A;
        return 1;
    }
    if (g->moved == EDMI__ONE &&
        (c == EDMI__ZERO || r == EDMI__ZERO ||
         (g->l >= 2 && r <= g->rprev && r <= EDMI__SQRT_EPS * res->residual0 &&
          c <= EDMI_R(0.25) * g->cprev && g->cprev <= EDMI_R(0.25) * g->cprev2 &&
          (g->chord ? c * c <= EDMI_EPS * g->cprev
                    : c * c * c <= EDMI_EPS * g->cprev * g->cprev)))) {
        if (r == EDMI__ZERO || edmi__solved(sys, work, dt, EDMI__SOLVED)) {
            res->stop = EDMI_STOP_CONVERGED;
            return 1;
        }
        if (c == EDMI__ZERO) { /* the iterate cannot move: every further correction is 0 */
            *st = EDMI_ERR_NO_CONVERGENCE;
            return 1;
        }
    }
    return 0;
}

/* The stops short of the tolerances: STALLED when the residual's noise is above eps: it
 * stopped halving, without more than doubling, after the quadratic regime (two residuals
 * below sqrt(eps) r_0; a residual that grew more is a stiff step's detour), or it stopped
 * halving within EDMI__NOISE_FACTOR of its estimated round-off noise (edmi__noise_floor: the
 * LG quotient on a near-circular orbit, GE's cancelling halves, where Newton otherwise cycles
 * between two iterates for ever; docs/api.md, "Solver"). Unlike a floor estimate that
 * accepts any residual below it, this stops only once the residual has stopped falling. At
 * l_max: EDMI_ERR_DIVERGED if the last line search still halved, else NO_CONVERGENCE. */
static int edmi__newton_stalled(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                const edmi__newton_log *g, edmi_step_result *res,
                                edmi_status *st)
{
    edmi_real r = g->r, rprev = g->rprev, r0 = res->residual0;
    *st = EDMI_OK;
    if (g->l >= 2 && r > EDMI__HALF * rprev &&
        ((rprev <= EDMI__SQRT_EPS * r0 && r <= EDMI__SQRT_EPS * r0 && r <= EDMI_R(2.0) * rprev) ||
         r <= EDMI__NOISE_FACTOR * edmi__noise_floor(sys, work, dt)) &&
        edmi__solved(sys, work, dt, EDMI__SOLVED)) {
        res->stop = EDMI_STOP_STALLED;
        return 1;
    }
    if (g->l >= sys->params.l_max) { /* still pushed out of the domain, or just slow */
        *st = res->halvings > g->halvings_before ? EDMI_ERR_DIVERGED : EDMI_ERR_NO_CONVERGENCE;
        return 1;
    }
    return 0;
}

/* The multi-corrector from the evaluated predictor: a correction (a chord where
 * edmi__chord_now says so), the line search, then the stop tests (edmi__newton_solved,
 * edmi__newton_stalled). On the paper's spring it stops after 2 corrections in float, 2-3 in
 * double (docs/api.md, "Solver"). */
static edmi_status edmi__newton(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                edmi_step_result *res)
{
    edmi__newton_log g;
    edmi_real r = res->residual0, moved = EDMI__ONE; /* g.r and g.moved, whose addresses the
                                                     * evaluations take: g stays in registers */
    edmi_status st;
    int l, switches_before;
    g.r = res->residual0;
    g.moved = EDMI__ONE;
    g.cprev = EDMI__ZERO;
    g.cprev2 = EDMI_REAL_MAX;
    g.contracted = 0;
    g.refreshed = 0;
    g.chord_ok = 1;
    if (!(g.r > EDMI__ZERO))
        return EDMI_OK;
    for (l = 1;; l++) {
        g.chord = edmi__chord_now(sys, work, &g, res->residual0, l);
        g.l = l;
        switches_before = res->lg_switches;
        st = edmi__newton_update(sys, work, dt, g.chord);
        if (st == EDMI_ERR_SINGULAR && l == 1) {
            /* Singular at the paper's predictor (q_n, p_n): a compressed link at dt beyond
             * 2 sqrt(m / |beta|) can make the transverse stiffness cancel the identity exactly
             * there, and a body at rest would stay on that point for ever. Start once more
             * from the explicit predictor p = p_n - R_p(q_n, p_n) (the forces' impulse),
             * q = q_n + dt/(2m) (p_n + p). */
            st = edmi__explicit_predictor(sys, work, dt, &r, res);
            g.r = r;
            if (st == EDMI_OK)
                st = edmi__newton_update(sys, work, dt, 0);
        }
        if (st != EDMI_OK)
            return st;
        g.c = edmi__scaled_norm(sys, work, work->rhs, (const edmi_real (*)[3])work->dp);
        g.rprev = g.r;
        g.halvings_before = res->halvings;
        if (l == 1 && g.chord) { /* the last step's factors, taken once, never halved */
            edmi__move(sys, work, EDMI__ONE);
            st = edmi__evaluate(sys, work, dt, &r, res);
            moved = EDMI__ONE;
        } else {
            st = edmi__line_search(sys, work, dt, &r, res, &moved);
        }
        g.r = r;
        g.moved = moved;
        if (l == 1 && g.chord && !(st == EDMI_OK && g.r <= EDMI__HALF * g.rprev)) {
            /* the last step's factors did not halve the predictor's residual (or left the
             * domain): back to the predictor, and the correction with its own matrix. At
             * most one linear solve and two evaluations more than a step without them. */
            res->lg_switches = switches_before;
            st = edmi__predictor(sys, work, dt, res);
            if (st != EDMI_OK)
                return st;
            g.r = r = edmi__scaled_residual(sys, work);
            work->kept = 0;
            l = 0;
            continue;
        }
        if (st != EDMI_OK)
            return st;
        res->iterations = l;
        res->residual = g.r;
        res->correction = g.c * g.moved;
        if (edmi__newton_solved(sys, work, dt, &g, res, &st))
            return st;
        g.contracted = l == 1 || g.c <= EDMI__CHORD_RATE * g.cprev;
        if (g.chord && (!g.contracted || g.r > g.rprev)) {
            if (work->kept) { /* the last step's matrix is too old here: factor anew, */
                work->kept = 0;
                g.refreshed = 1; /* at an iterate the chord already brought near */
            } else {
                g.chord_ok = 0;
            }
        }
        g.cprev2 = l >= 2 ? g.cprev : EDMI_REAL_MAX;
        g.cprev = res->correction;
        if (edmi__newton_stalled(sys, work, dt, &g, res, &st))
            return st;
    }
}

/* ==========================================================================================
 * The passivity guard
 *
 * docs/energy-safe.md and docs/guard.md. With the guard on, every stored step satisfies, T
 * being the energy tank (sys->tank),
 *     H(q_n+1, p_n+1) - H(q_n, p_n) <= work_ext + work_anchor + T_n - T_n+1,
 *     0 <= T_n+1 <= cap_n+1 = tank_cap eps S_n+1        (S: the magnitude of H's terms)
 * exactly, for the stored values and the reported works. Summed over any window m..n of
 * steps, H rises by at most the work supplied plus T_m <= cap_m: passivity as Colgate states
 * it, with an energy tank as time-domain passivity controllers keep one (Hannaford and Ryu;
 * Franken, Stramigioli et al.). tank_cap = 0 is the per-step inequality H_n+1 - H_n <= work.
 *
 * Rounding Newton's solution to the grid moves H by ~eps S either way, every step: a guard
 * that removed every rise would drain energy whether the scheme dissipates or not. The tank
 * absorbs that noise, so the guard changes the state only when the tank cannot cover a rise.
 * The step's change is certified by the cheapest evaluation that settles it:
 *  1. plain: working precision with an a-priori bound relative to each term's size (Higham,
 *     ch. 3), taken when the step dissipates more than the bound and the tank stays full;
 *  2. double-word (Joldes, Muller, Popescu): error ~eps^2 S; near the bottom of the range on
 *     values scaled by a power of two (exact), so that a system coming to rest stays
 *     certified with the same relative resolution;
 *  3. only if the tank cannot cover the rise: the guard moves the state (an impulse along a
 *     link, energy-aware rounding, a drag) to one whose rise it covers, one ordered list.
 * The subsections follow that order: the change of H and its bound, the tank, the
 * certificate, the rounding, impulse, drag and stop, and the choice of moves (edmi__guard_move).
 * The next section, a step's end, applies them.
 * ======================================================================================== */

static int edmi__guard_on(const edmi_params *p)
{
    if (!EDMI_WITH_GUARD) /* a build of MP and LG alone without it (edmi.h) */
        return 0;
    return p->guard == EDMI_GUARD_ON ||
           (p->guard == EDMI_GUARD_AUTO &&
            ((EDMI__HAS_SCHEME(EDMI_SCHEME_GE) && p->scheme == EDMI_SCHEME_GE) ||
             (EDMI__HAS_SCHEME(EDMI_SCHEME_PM) && p->scheme == EDMI_SCHEME_PM) ||
             (EDMI__HAS_SCHEME(EDMI_SCHEME_PT) && p->scheme == EDMI_SCHEME_PT)));
}

/* The tank a step may spend, T_n: sys->tank, or 0 with tank_cap 0, the per-step form, which
 * neither spends a tank nor keeps one (whatever a caller stored in sys->tank before). */
static edmi_real edmi__tank_n(const edmi_system *sys)
{
    return sys->params.tank_cap > EDMI__ZERO ? sys->tank : EDMI__ZERO;
}

/* The tank's capacity after a step whose end has H's terms of magnitude s: cap eps s (cap =
 * params.tank_cap with the guard on), EDMI_REAL_MAX where that overflows, and 0 with cap 0
 * whatever s (an infinite s beyond the range, where 0 x inf would be NaN). */
static edmi_real edmi__tank_cap(edmi_real cap, edmi_real s)
{
    edmi_real c = cap * EDMI_EPS * s;
    if (!(cap > EDMI__ZERO))
        return EDMI__ZERO;
    return c < EDMI_REAL_MAX ? c : c >= EDMI_REAL_MAX ? EDMI_REAL_MAX : EDMI__ZERO;
}

/* ---- the change of H and its bound ------------------------------------------------------ */

/* The energy bookkeeping of one step in double-word arithmetic. Every energy here is scale^2
 * times the real one (edmi__set_scale: 1 unless the energies are near the bottom of the
 * range). */
typedef struct edmi__balance {
    edmi__dw dv;       /* V(q_n+1) - V(q_n): links (anchors where they are) and field */
    edmi__dw dk;       /* K(p_n+1) - K(p_n) */
    edmi__dw w;        /* work_ext + work_anchor as reported (their exact sum) */
    edmi__dw scheme;   /* diss_scheme: sum over links of beta (d_n+1^2 - d_n^2)/2 - dV */
    edmi_real err_v;   /* bound on |error| of dv (and of scheme) */
    edmi_real err_k;   /* bound on |error| of dk */
    edmi_real size_v;  /* sum over the changed V terms of |V| + |V'| d at both ends (|V'| d as
                          |beta| d^2), and m |g| |q| for the field: what a plain evaluation
                          of dv errs by, per unit of round-off */
    edmi_real size_k;  /* K_n + K_n+1 over the bodies whose momentum changed: the same for dk */
    edmi_real scale;   /* 2^j, j >= 0: momenta and zero-rest-length link vectors are scaled by
                          it, every other energy term twice (both exact; scale^2 itself may
                          exceed the range) */
    int scheme_on;     /* evaluate scheme (energy_balance) */
} edmi__balance;

/* The plain (working-precision) evaluation of the step's excess, and the magnitudes the tank's
 * capacity and the scaling are set from. */
typedef struct edmi__plain {
    edmi_real e, m;    /* H_n+1 - H_n - work as computed, and a bound on its error */
    edmi_real scheme;  /* diss_scheme as computed */
    edmi_real s1;      /* the magnitude S of H's terms at the step's end (the tank's capacity) */
    int ok;            /* e and m hold (not with a coupled M: its K needs a solve) */
} edmi__plain;

static int edmi__same3(const edmi_real a[3], const edmi_real b[3])
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* Whether a link's ends stayed where they were: its V term's change is then exactly 0. */
static int edmi__link_still(const edmi_system *sys, const edmi_link_ws *w, const edmi_link *lk,
                            const edmi_real (*q1)[3])
{
    const edmi_real *b0 = lk->b == EDMI_ANCHOR ? lk->anchor : sys->body[lk->b].q;
    return edmi__same3(sys->body[lk->a].q, q1[lk->a]) && edmi__same3(b0, edmi__end_b(lk, w, q1));
}

/* A user potential's V change, bounded above from its derivatives alone: the perturbed
 * mid-point quadrature of the paper's lemma, applied to V_+' and V_-', gives exactly
 *     V(d1) - V(d0) = Lambda_pm dd - dd^4/48 (V_+''''(xi) - V_-''''(xi')) <= Lambda_pm dd,
 *     Lambda_pm = V'(d0 + dd/2) + dd^2/24 (V_+'''(d1) + V_-'''(d0)),   dd = d1 - d0,
 * for any split with V_+'''' >= 0 >= V_-'''' (the one PM's energy decay needs). Its slack is
 * PM's own dissipation, 0 for a quadratic V. dd is formed as ds / (d0 + d1) from the change
 * of the squared length ds = |r1|^2 - |r0|^2, evaluated in double-word from the link vectors
 * formed exactly (edmi__dw_diff3), so that dd is known to a few eps of itself however the
 * vector turns (a body crossing to its anchor's other side ends with r1 ~ -r0, where r1 + r0
 * formed from the rounded vectors carries eps |r| of error, not eps |r1 + r0|). *err bounds
 * the evaluation's error: relative to the change |dd| (the callback's own error, assumed
 * 8 eps of |V'|; the rounding of the evaluation points through V''; of dd and of the
 * products, each doubled for the neglected second-order terms), plus |Lambda_pm| times the
 * double-word error of ds over d0 + d1, plus the callback's values lost to underflow
 * (EDMI__USER_TINY). *ds = d1^2 - d0^2 and *mag1, the magnitude of V's
 * terms at d1, are returned too. */
/* What a callback's value may lose to underflow, flush to zero included: V' at the mid-length
 * and the two V''' the perturbation reads, each up to this, enter the bound through |dd| and
 * |dd|^3 / 24: a V''' the callback flushes to 0 on a long step can otherwise be the bound's
 * whole margin over V's true change (docs/testing.md lists the fuzzer's case). */
#define EDMI__USER_TINY (EDMI_R(2.0) * EDMI__REAL_MIN)

static edmi_status edmi__user_dv(const edmi_system *sys, const edmi_link_ws *w,
                                 const edmi_link *lk, const edmi_real (*q1)[3], edmi_real *ub,
                                 edmi_real *err, edmi_real *ds, edmi_real *mag1)
{
    const edmi_real *b0 = lk->b == EDMI_ANCHOR ? lk->anchor : sys->body[lk->b].q;
    edmi__dw r0[3], r1[3], s0 = edmi__dw_of(EDMI__ZERO), s1 = edmi__dw_of(EDMI__ZERO);
    edmi_real d1, den, dd, eds, pert, lam, ddu, add;
    edmi_pot_parts pa, p1;
    edmi_status st;
    int i;
    edmi__dw_diff3(sys->body[lk->a].q, b0, r0);
    edmi__dw_diff3(q1[lk->a], edmi__end_b(lk, w, q1), r1);
    /* |r0|^2 and |r1|^2: edmi__dw_sq3's sums, written out here so that edmi__dw_sq3 keeps
     * one caller (edmi__link_v_dw, on every step) and stays inlined there: a second caller
     * made GCC -Os call it out of line, 35 instructions more per Cortex-M4F step */
    for (i = 0; i < 3; i++) {
        s0 = edmi__dw_add_same(s0, edmi__dw_mul(r0[i], r0[i]));
        s1 = edmi__dw_add_same(s1, edmi__dw_mul(r1[i], r1[i]));
    }
    *ds = edmi__dw_real(edmi__dw_sub(s1, s0));
    eds = EDMI__DW_ERR * (s0.hi + s1.hi) + EDMI__DW_TINY; /* ds's error, its rounding aside */
    d1 = EDMI_SQRT(s1.hi);
    den = w->d0 + d1;
    dd = *ds / den;
    st = edmi__pot_parts(&lk->pot, w->d0 + EDMI__HALF * dd, &pa, 1);
    if (st == EDMI_OK)
        st = edmi__pot_parts(&lk->pot, d1, &p1, 1);
    if (st != EDMI_OK)
        return st;
    pert = dd * dd / EDMI_R(24.0) * (p1.sp[3] + w->d3m0);
    lam = pa.v[1] + pert;
    *ub = lam * dd;
    /* dd is known to ddu (ds's error over d0 + d1): where ds rounds to 0 at a length far
     * beyond the step (a body 1e17 from its anchor in float), every term below scales with
     * |dd| + ddu, not with the computed |dd|, and V' at the mid-length errs by V'' ddu */
    ddu = eds / den;
    add = edmi__abs(dd) + ddu;
    *err = EDMI_EPS * add *
               (EDMI_R(16.0) * (edmi__abs(lam) + edmi__abs(pa.v[1]) + edmi__abs(pert)) +
                EDMI_R(8.0) * edmi__abs(pa.v[2]) * den) +
           EDMI_R(2.0) * edmi__abs(lam) * ddu + edmi__abs(pa.v[2]) * add * ddu + EDMI__DW_TINY +
           add * EDMI__USER_TINY * (EDMI__ONE + add * add / EDMI_R(12.0));
    *mag1 = edmi__pot_mag(&lk->pot, &p1, d1);
    return edmi__finite(*ub) && edmi__finite(*err) ? EDMI_OK : EDMI_ERR_OVERFLOW;
}

/* The plain certificate (step 1 above): H_n+1 - H_n - work evaluated term by term in working
 * precision with u = eps/2, each term with its a-priori error bound, relative to the size of
 * its change where the formula allows: a body's kinetic change sum (p1 - p0)(p1 + p0) / 2m
 * (8 eps of |p1 - p0| |p1 + p0| / 2m), the field's -m g.(q1 - q0), a link's V(d1) - V(d0)
 * (64 eps of the magnitudes at both ends, edmi__pot_mag, or a user potential's bound), the
 * works; the sum's own rounding adds (n + 2) eps of its terms. Also the magnitudes of H's
 * terms (S at the end for the tank's capacity, all of them for the scaling) and
 * diss_scheme, both as computed. */
static edmi_status edmi__plain_excess(const edmi_system *sys, edmi_workspace *work,
                                      const edmi_step_result *res, edmi__plain *pl)
{
    const edmi_real (*q1)[3] = (const edmi_real (*)[3])work->q1;
    const edmi_real (*p1)[3] = (const edmi_real (*)[3])work->p1;
    edmi_real e = EDMI__ZERO, sum = EDMI__ZERO, err = EDMI__ZERO;
    edmi_real s1 = EDMI__ZERO, sch = EDMI__ZERO;
    edmi_real gn = EDMI__HAS_FIELD(sys) ? edmi__norm(sys->g) : EDMI__ZERO;
    int a, i, j, n = 2;
    pl->ok = !EDMI__COUPLED(sys);
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++) { /* their share of S, for the tank's capacity */
        const edmi_wall *wl = &sys->wall[j];
        edmi_pot_parts pp;
        edmi_real g1 = edmi__wall_gap(wl, q1[wl->a], work->ww[j].x1[0]);
        if (edmi__pot_parts(&wl->pot, g1, &pp, 0) == EDMI_OK)
            s1 += edmi__abs(pp.v[0]) + edmi__abs(pp.v[1]) * (edmi__abs(g1) + edmi__abs(wl->c));
        /* a wall off its body at both ends adds exactly 0; one touching: double-word alone */
        if (!edmi__wall_free(wl, sys->body[wl->a].q, wl->c, work->ww[j].d0) ||
            !edmi__wall_free(wl, q1[wl->a], work->ww[j].x1[0], g1))
            pl->ok = 0;
    }
#endif
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi_real m2 = EDMI_R(2.0) * bd->m, t = EDMI__ZERO, mag = EDMI__ZERO;
        for (i = 0; i < 3; i++) {
            edmi_real d = p1[a][i] - bd->p[i], s = p1[a][i] + bd->p[i], ds = d * s;
            t += ds;
            mag += edmi__abs(ds); /* |d| |s| (rounding is symmetric) */
        }
        e += t / m2;
        sum += mag / m2;
        err += EDMI_R(8.0) * EDMI_EPS * mag / m2 + EDMI__DW_TINY * (EDMI__ONE + EDMI__ONE / m2);
        s1 += edmi__dot(p1[a], p1[a]) / m2; /* a coupled M's K is near this (a magnitude) */
        if (EDMI__HAS_FIELD(sys)) { /* V = -(M 1)_a g . q_a (a coupled M's row sum < 0?) */
            edmi_real mr = edmi__mass_row(sys, a), m = edmi__abs(mr), dq[3], fv;
            for (i = 0, mag = EDMI__ZERO; i < 3; i++) {
                dq[i] = q1[a][i] - bd->q[i];
                mag += edmi__abs(sys->g[i]) * edmi__abs(dq[i]);
            }
            fv = mr * edmi__dot(sys->g, dq);
            e -= fv;
            sum += m * mag;
            err += EDMI_R(8.0) * EDMI_EPS * m * mag + EDMI__DW_TINY * (EDMI__ONE + m);
            s1 += m * gn * edmi__norm(q1[a]);
            n++;
        }
        n++;
    }
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        edmi_link_ws *w = &work->lw[j];
        edmi_real r1[3], d1, v1, m1, dv, ds, e1;
        edmi_pot_parts pp;
        edmi_status st;
        if (edmi__is_user(&lk->pot)) {
            st = edmi__user_dv(sys, w, lk, q1, &dv, &e1, &ds, &m1);
            if (st != EDMI_OK)
                return st;
            w->m1 = m1; /* for edmi__scale_inputs */
        } else {
            v1 = w->v1;
            m1 = w->m1;
            d1 = w->d1;
            if (!w->have1) { /* kept for edmi__plain_tiny */
                edmi__sub(q1[lk->a], edmi__end_b(lk, w, q1), r1);
                d1 = edmi__norm(r1);
                st = edmi__pot_parts(&lk->pot, d1, &pp, 1);
                if (st != EDMI_OK)
                    return st;
                v1 = pp.v[0];
                m1 = edmi__pot_mag(&lk->pot, &pp, d1);
                w->d1 = d1;
                w->m1 = m1;
            }
            dv = v1 - w->v0;
            e1 = EDMI_R(64.0) * EDMI_EPS * (w->m0 + m1); /* + edmi__plain_tiny */
            ds = (d1 - w->d0) * (d1 + w->d0);
        }
        s1 += m1;
        w->bal_on = !edmi__link_still(sys, w, lk, q1); /* for edmi__delta_v too */
        if (!w->bal_on)
            continue; /* exactly 0 */
        e += dv;
        sum += edmi__abs(dv);
        err += e1;
        sch += EDMI__HALF * w->beta * ds - dv;
        n++;
    }
    e -= res->work_ext + res->work_anchor;
    sum += edmi__abs(res->work_ext) + edmi__abs(res->work_anchor) + edmi__abs(e);
    /* the sums above are of non-negative terms: relative error below n eps, covered twice */
    pl->m = (err + (edmi_real)(n + 2) * EDMI_EPS * sum) *
                (EDMI__ONE + (edmi_real)(2 * n + 4) * EDMI_EPS) +
            EDMI__DW_TINY;
    pl->e = e;
    pl->scheme = sch;
    pl->s1 = s1;
    if (!edmi__finite(pl->m) || !edmi__finite(e))
        pl->ok = 0;
    return edmi__finite(s1) ? EDMI_OK : EDMI_ERR_OVERFLOW;
}

/* What edmi__set_scale needs for the step's double-word evaluation: the largest momentum
 * component and zero-rest-length link vector component at either end (*x, what the terms
 * homogeneous of degree two, K and k/2 |r|^2, are formed from), and the magnitude of the
 * other terms at both ends, the works and the tank (*so). */
static void edmi__scale_inputs(const edmi_system *sys, const edmi_workspace *work,
                               const edmi_step_result *res, edmi_real *x, edmi_real *so)
{
    const edmi_real (*q1)[3] = (const edmi_real (*)[3])work->q1;
    edmi_real gn = EDMI__HAS_FIELD(sys) ? edmi__norm(sys->g) : EDMI__ZERO;
    int a, i, j;
    *x = EDMI__ZERO;
    *so = edmi__tank_n(sys) + edmi__abs(res->work_ext) + edmi__abs(res->work_anchor);
    for (a = 0; a < sys->n_bodies; a++) {
        for (i = 0; i < 3; i++)
            *x = edmi__max(*x, edmi__max(edmi__abs(work->p1[a][i]), edmi__abs(sys->body[a].p[i])));
        *so += edmi__abs(edmi__mass_row(sys, a)) * gn *
               (edmi__norm(sys->body[a].q) + edmi__norm(q1[a]));
    }
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        const edmi_link_ws *w = &work->lw[j];
        edmi_real r1[3];
        if (!edmi__is_linear(&lk->pot)) {
            *so += w->m0 + w->m1;
            continue;
        }
        edmi__sub(q1[lk->a], edmi__end_b(lk, w, q1), r1);
        for (i = 0; i < 3; i++)
            *x = edmi__max(*x, edmi__max(edmi__abs(r1[i]), edmi__abs(w->r0[i])));
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++) { /* V and V' times the gap's terms, both ends */
        const edmi_wall *wl = &sys->wall[j];
        const edmi_link_ws *w = &work->ww[j];
        edmi_real g1 = edmi__wall_gap(wl, q1[wl->a], work->ww[j].x1[0]);
        edmi_pot_parts pp;
        if (edmi__pot_parts(&wl->pot, g1, &pp, 0) == EDMI_OK)
            *so += edmi__abs(pp.v[0]) + edmi__abs(w->v0) +
                   (edmi__abs(pp.v[1]) + edmi__abs(w->dv0)) *
                       (edmi__norm(q1[wl->a]) + edmi__norm(sys->body[wl->a].q) + edmi__abs(wl->c));
    }
#endif
}

/* The links' underflow allowance the plain certificate adds (edmi__pot_tiny at both ends),
 * formed only where the certificate holds without it (after edmi__plain_excess: bal_on). */
static edmi_real edmi__plain_tiny(const edmi_system *sys, const edmi_workspace *work)
{
    edmi_real t = EDMI__ZERO;
    int j;
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        const edmi_link_ws *w = &work->lw[j];
        if (edmi__is_user(&lk->pot) || !w->bal_on)
            continue;
        t += edmi__pot_tiny(&lk->pot, w->d0, w->d0 * w->d0, w->m0) +
             edmi__pot_tiny(&lk->pot, w->d1, w->d1 * w->d1, w->m1);
    }
    return t * (EDMI__ONE + EDMI_R(4.0) * (edmi_real)sys->n_links * EDMI_EPS);
}

/* Energies below this are scaled up before the double-word evaluation: there its error bound's
 * underflow allowance (EDMI__DW_TINY times a potential's coefficients) would exceed eps^2 of
 * them. 2^(3p) above the smallest normal, p the precision's bits: 2^-54 in float, 2^-863 in
 * double. */
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define EDMI__SCALE_BELOW EDMI_R(0x1p-863)
#define EDMI__SCALE_MAX_J 1022 /* the largest power of two */
#else
#define EDMI__SCALE_BELOW EDMI_R(0x1p-54)
#define EDMI__SCALE_MAX_J 126
#endif

/* The power-of-two scale of a step's double-word evaluation: 1 (almost always) unless every
 * term is near the bottom of the range, the terms homogeneous of degree two (kinetic
 * energies, zero-rest-length springs) formed from momenta and link vectors of at most x,
 * the others (and the works and the tank) of magnitude s_other, x^2 and s_other below
 * EDMI__SCALE_BELOW. Then 2^j, the largest with 2^j x <= 1/2 and 2^2j s_other <= 1/16 (at
 * most 2^EDMI__SCALE_MAX_J): the homogeneous terms are evaluated from momenta and vectors
 * scaled by 2^j, the others multiplied by 2^2j, both exact, so that their products do not
 * underflow: a body settling onto its anchor (energies of 1e-300 and below) is certified as
 * one with energies of 1. */
static void edmi__set_scale(edmi__balance *bal, edmi_real x, edmi_real s_other)
{
    int j = 0;
    bal->scale = EDMI__ONE;
    if (!(x * x < EDMI__SCALE_BELOW && s_other < EDMI__SCALE_BELOW))
        return;
    for (; j + 16 <= EDMI__SCALE_MAX_J && x < EDMI_R(0x1p-18) && s_other < EDMI_R(0x1p-38);
         j += 16) {
        x *= EDMI_R(65536.0);
        s_other *= EDMI_R(65536.0) * EDMI_R(65536.0);
        bal->scale *= EDMI_R(65536.0);
    }
    for (; j < EDMI__SCALE_MAX_J && x < EDMI_R(0.25) && s_other < EDMI_R(0.015625); j++) {
        x *= EDMI_R(2.0);
        s_other *= EDMI_R(4.0);
        bal->scale *= EDMI_R(2.0);
    }
}

/* x scale^2 (exact barring overflow) and x / scale^2 (rounded where the quotient is
 * subnormal), for the balance's scale. */
static edmi_real edmi__up2(const edmi__balance *bal, edmi_real x)
{
    return x * bal->scale * bal->scale;
}

static edmi_real edmi__down2(const edmi__balance *bal, edmi_real x)
{
    return x / bal->scale / bal->scale;
}

/* x times a power of two (exact barring overflow). */
static edmi__dw edmi__dw_pow2(edmi__dw x, edmi_real k)
{
    x.hi *= k;
    x.lo *= k;
    return x;
}

static edmi__dw edmi__dw_up2(const edmi__balance *bal, edmi__dw x)
{
    return edmi__dw_pow2(edmi__dw_pow2(x, bal->scale), bal->scale);
}

/* V and |r|^2 of a built-in link at one end of the step, from its exact link vector r (changed
 * in place when scaled), in double-word, with its error bound, in the balance's units. */
static void edmi__link_v_dw(const edmi_potential *pot, edmi__dw r[3], const edmi__balance *bal,
                            edmi__dw *s, edmi__dw *v, edmi_real *e)
{
    int i, lin = edmi__is_linear(pot);
    if (lin && bal->scale != EDMI__ONE) /* V = a/2 |r|^2: from the scaled vector */
        for (i = 0; i < 3; i++)
            r[i] = edmi__dw_pow2(r[i], bal->scale);
    *s = edmi__dw_sq3(r);
    edmi__pot_dw(pot, *s, lin ? *s : edmi__dw_sqrt(*s), v, e); /* linear: no length needed */
    if (!lin && bal->scale != EDMI__ONE) {
        *s = edmi__dw_up2(bal, *s);
        *v = edmi__dw_up2(bal, *v);
        *e = edmi__up2(bal, *e);
    }
}

#if EDMI_MAX_WALLS > 0
/* A wall's gap g = n.q - c at body position q (the wall at offset c) and V(g), in double-word
 * with the bound *err on V's error, in the balance's units (V times scale^2). The products
 * n_i q_i are exact and their sum errs by a few u^2 of G = sum |n_i q_i| + |c| (taken as
 * EDMI__DW_X G), which reaches V through V' (the gap's harmonic k x or one-sided k x^2,
 * x = g - b or b - g): m = a xe^(p-1) (xe + G + b), xe = |x| + EDMI__DW_X (G + b), p = 2 or
 * 3; a one-sided form more than twice that from its kink on the free side is 0 exactly, with
 * no error. */
static void edmi__wall_v_dw(const edmi_wall *wl, const edmi_real q[3], edmi_real c,
                            const edmi__balance *bal, edmi__dw *g, edmi__dw *v, edmi_real *err)
{
    const edmi_potential *pot = &wl->pot;
    edmi_real a = pot->a, b = pot->b, big = edmi__abs(c), xe, m;
    edmi__dw x;
    int i;
    *g = edmi__dw_of(-c);
    for (i = 0; i < 3; i++) {
        *g = edmi__dw_add(*g, edmi__two_prod(wl->n[i], q[i]));
        big += edmi__abs(wl->n[i] * q[i]);
    }
    x = edmi__dw_add_r(*g, -b);
    if (pot->kind == EDMI_POT_CONTACT)
        x = edmi__dw_neg(x);
    big += b;
    xe = edmi__abs(x.hi) + EDMI__DW_X * big;
    if (pot->kind == EDMI_POT_HARMONIC) {
        *v = edmi__dw_mul_r(edmi__dw_mul(x, x), EDMI__HALF * a);
        m = a * xe * (xe + big);
    } else {
        *v = x.hi > EDMI__ZERO
                 ? edmi__dw_div_r(edmi__dw_mul_r(edmi__dw_mul(edmi__dw_mul(x, x), x), a), EDMI_R(3.0))
                 : edmi__dw_of(EDMI__ZERO);
        m = x.hi > -EDMI_R(2.0) * EDMI__DW_X * big ? a * xe * xe * (xe + big) : EDMI__ZERO;
    }
    *err = EDMI__DW_ERR * m +
           EDMI__DW_TINY * (EDMI__ONE + EDMI_R(16.0) * a * (EDMI__ONE + (xe + big) * (xe + big)));
    if (bal->scale != EDMI__ONE) {
        *v = edmi__dw_up2(bal, *v);
        *err = edmi__up2(bal, *err);
    }
}
#endif

/* The start of a step is the end of the last one: unless the caller changed the state (or the
 * workspace served another system), a link's V at d_n was evaluated then. Reused only when the
 * link's two ends and its potential are exactly the ones it was evaluated for, so that the
 * result is bit for bit the fresh evaluation's (about half of the double-word work). */
static int edmi__end_cached(const edmi_link_ws *w, const edmi_potential *pot,
                            const edmi_real qa[3], const edmi_real xb[3])
{
    return w->end_kind == (int)pot->kind && w->end_pot[0] == pot->a &&
           w->end_pot[1] == pot->b && edmi__same3(w->end_ends, qa) &&
           edmi__same3(w->end_ends + 3, xb);
}

/* One link's terms of the balance (stored in its workspace: edmi__delta_v). A link whose ends
 * did not move (!w->bal_on) is skipped: its change is exactly 0 (a body at rest certifies
 * exactly). */
static edmi_status edmi__delta_v_link(const edmi_system *sys, edmi_link_ws *w,
                                      const edmi_link *lk, const edmi_real (*q1)[3],
                                      const edmi__balance *bal)
{
    edmi__dw r0[3], r1[3], s0, s1, v0, v1, dv, sc;
    edmi_real e0, e1;
    const edmi_real *b0 = lk->b == EDMI_ANCHOR ? lk->anchor : sys->body[lk->b].q;
    if (!w->bal_on)
        return EDMI_OK;
    if (edmi__is_user(&lk->pot)) {
        edmi_real ub, err, dsr, mag;
        edmi_status st = edmi__user_dv(sys, w, lk, q1, &ub, &err, &dsr, &mag);
        if (st != EDMI_OK)
            return st;
        dv = edmi__dw_of(edmi__up2(bal, ub));
        sc = edmi__dw_sub(edmi__dw_of(edmi__up2(bal, EDMI__HALF * w->beta * dsr)), dv);
        e0 = EDMI__ZERO;
        e1 = edmi__up2(bal, err);
        v0 = edmi__dw_of(edmi__up2(bal, w->m0));
        v1 = edmi__dw_of(edmi__up2(bal, mag));
        s0 = s1 = edmi__dw_of(EDMI__ZERO);
    } else {
        const edmi_real *b1 = edmi__end_b(lk, w, q1);
        if (bal->scale == EDMI__ONE && edmi__end_cached(w, &lk->pot, sys->body[lk->a].q, b0)) {
            s0 = edmi__dw_pair(w->end_s);
            v0 = edmi__dw_pair(w->end_v);
            e0 = w->end_e;
        } else {
            edmi__dw_diff3(sys->body[lk->a].q, b0, r0);
            edmi__link_v_dw(&lk->pot, r0, bal, &s0, &v0, &e0);
        }
        if (bal->scale == EDMI__ONE) { /* what the next step starts from, if it is stored */
            w->end_kind = (int)lk->pot.kind;
            w->end_pot[0] = lk->pot.a;
            w->end_pot[1] = lk->pot.b;
            edmi__copy3(q1[lk->a], w->end_ends);
            edmi__copy3(b1, w->end_ends + 3);
        }
        edmi__dw_diff3(q1[lk->a], b1, r1);
        edmi__link_v_dw(&lk->pot, r1, bal, &s1, &v1, &e1);
        if (bal->scale == EDMI__ONE) {
            w->end_s[0] = s1.hi;
            w->end_s[1] = s1.lo;
            w->end_v[0] = v1.hi;
            w->end_v[1] = v1.lo;
            w->end_e = e1;
        }
        dv = edmi__dw_sub(v1, v0);
        /* the scheme's dissipation (energy_balance): the work of f = dt beta r_m over the
         * step, per dt, beta (d_n+1^2 - d_n^2) / 2, less dv */
        sc = bal->scheme_on
                 ? edmi__dw_sub(edmi__dw_mul_r(edmi__dw_sub(s1, s0), EDMI__HALF * w->beta), dv)
                 : edmi__dw_of(EDMI__ZERO);
    }
    w->bal_dv[0] = dv.hi;
    w->bal_dv[1] = dv.lo;
    w->bal_sc[0] = sc.hi;
    w->bal_sc[1] = sc.lo;
    w->bal_err = e0 + e1;
    w->bal_size = edmi__abs(v0.hi) + edmi__abs(v1.hi) + edmi__abs(w->beta) * (s0.hi + s1.hi);
    return EDMI_OK;
}

/* V's change over the step into bal (dv, scheme, err_v, size_v), the links' terms kept in
 * their workspaces: with moved = -1 every link is evaluated (each link's bal_on set for q1 by
 * edmi__plain_excess or edmi__freeze), with moved = a >= 0 (the guard moved body a's position
 * since the last call) only the links at body a, the others' terms summed again as stored, in
 * the same order: the sums are the full evaluation's. */
static edmi_status edmi__delta_v(const edmi_system *sys, edmi_workspace *work,
                                 const edmi_real (*q1)[3], edmi__balance *bal, int moved)
{
    int j, a;
    bal->dv = edmi__dw_of(EDMI__ZERO);
    bal->scheme = edmi__dw_of(EDMI__ZERO);
    bal->err_v = EDMI__ZERO;
    bal->size_v = EDMI__ZERO;
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        edmi_link_ws *w = &work->lw[j];
        if (moved < 0 || lk->a == moved || lk->b == moved) {
            edmi_status st;
            if (moved >= 0)
                w->bal_on = !edmi__link_still(sys, w, lk, q1);
            st = edmi__delta_v_link(sys, w, lk, q1, bal);
            if (st != EDMI_OK)
                return st;
        }
        if (!w->bal_on)
            continue;
        bal->dv = edmi__dw_add_z(bal->dv, edmi__dw_pair(w->bal_dv));
        bal->err_v += w->bal_err;
        bal->size_v += w->bal_size;
        if (bal->scheme_on)
            bal->scheme = edmi__dw_add_z(bal->scheme, edmi__dw_pair(w->bal_sc));
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++) { /* every call: a moved body's walls too */
        const edmi_wall *wl = &sys->wall[j];
        edmi__dw g0, g1, v0, v1, dv;
        edmi_real e0, e1;
        edmi_real c1 = work->ww[j].x1[0];
        if (edmi__same3(q1[wl->a], sys->body[wl->a].q) && c1 == wl->c)
            continue; /* exactly 0 */
        edmi__wall_v_dw(wl, sys->body[wl->a].q, wl->c, bal, &g0, &v0, &e0);
        edmi__wall_v_dw(wl, q1[wl->a], c1, bal, &g1, &v1, &e1);
        dv = edmi__dw_sub(v1, v0);
        bal->dv = edmi__dw_add_z(bal->dv, dv);
        bal->err_v += e0 + e1;
        bal->size_v += edmi__abs(v0.hi) + edmi__abs(v1.hi) +
                       edmi__up2(bal, edmi__abs(work->ww[j].beta) *
                                          (edmi__abs(g0.hi) + edmi__abs(g1.hi) + edmi__abs(wl->c) +
                                           edmi__abs(c1)));
        if (bal->scheme_on) /* the work of f = dt Lambda n per dt, Lambda (g_n+1 - g_n), less dv */
            bal->scheme = edmi__dw_add_z(
                bal->scheme,
                edmi__dw_sub(edmi__dw_up2(bal, edmi__dw_mul_r(edmi__dw_sub(g1, g0), work->ww[j].beta)),
                             dv));
    }
#endif
    if (EDMI__HAS_FIELD(sys)) /* V = -sum (M 1)_a g . q_a, each mass entry exact */
        for (a = 0; a < sys->n_bodies; a++) {
            edmi__dw wg;
            edmi_real mag, x;
            int b;
            if (edmi__same3(q1[a], sys->body[a].q))
                continue;
            wg = edmi__dw_work(sys->g, q1[a], sys->body[a].q, bal->scale);
            x = edmi__up2(bal, edmi__norm(sys->g) * (edmi__norm(q1[a]) + edmi__norm(sys->body[a].q)));
            for (b = a - EDMI_MAX_MASS_GAP; b <= a + EDMI_MAX_MASS_GAP; b++) {
                edmi_real m;
                if (b < 0 || b >= sys->n_bodies)
                    continue;
#if EDMI_MAX_MASS_GAP > 0
                m = b == a ? sys->body[a].m : edmi__mass_ab(sys, a, b);
#else
                m = sys->body[a].m;
#endif
                bal->dv = edmi__dw_sub(bal->dv, edmi__dw_mul_r(wg, m));
                mag = edmi__abs(m) * (edmi__abs(wg.hi) + x);
                bal->err_v += EDMI__DW_ERR * mag +
                              EDMI__DW_TINY * EDMI_R(4.0) * (edmi__abs(m) + EDMI__ONE);
                bal->size_v += mag;
            }
        }
    return EDMI_OK;
}

#if EDMI_MAX_MASS_GAP > 0
/* dk = K(p1) - K(p_n) = 1/2 d . M^-1 s (d = p1 - p_n, s = p1 + p_n, both exact double-words,
 * times bal->scale) for a coupled M. x + y ~ M^-1 s, held as two working-precision vectors:
 * x from M's band Cholesky factor (in work->mat, free once Newton is done), y =
 * M^-1 (s - M x) its correction; dk = 1/2 d . (x + y) in double-word. What x misses is
 * bounded through the residual rho = s - M x, evaluated in double-word: |1/2 d . M^-1 rho|
 * <= 1/2 |d| |rho| / lambda_min(M), with lambda_min(M) bounded below by a shifted Cholesky
 * factorisation (edmi__mass_lambda_min): any M that bound proves definite (the validation
 * refuses the others). */
static void edmi__delta_k_coupled(const edmi_system *sys, edmi_workspace *work,
                                  const edmi_real (*p1)[3], edmi__balance *bal)
{
    int n = sys->n_bodies, g = EDMI_MAX_MASS_GAP, a, c, pass;
    edmi_real *f = work->mat, *x = work->rhs, *y = work->dp[0], k = bal->scale;
    edmi_real lam = edmi__mass_lambda_min(n, sys->body, edmi__off_sys, sys);
    edmi_real nd = EDMI__ZERO, nr = EDMI__ZERO, mag_d = EDMI__ZERO;
    edmi_real nfac = EDMI__ONE + EDMI_R(8.0) * (edmi_real)(3 * n + 2 * g + 2) * EDMI_EPS;
    /* the whole factor (M was validated positive definite: its pivots are) */
    (void)edmi__cholesky(n, sys->body, edmi__off_sys, sys, 0, 0, EDMI__ZERO, 0, f);
    for (a = 0; a < n; a++)
        for (c = 0; c < 3; c++)
            y[3 * a + c] = (p1[a][c] + sys->body[a].p[c]) * k;
    edmi__mass_solve(f, n, g, y, x);
    for (pass = 0; pass < 2; pass++) { /* the residual of x, then of x + y */
        nr = EDMI__ZERO;
        for (a = 0; a < n; a++)
            for (c = 0; c < 3; c++) {
                edmi_real mag;
                edmi__dw r = edmi__mass_residual_dw(
                    sys, a, c, edmi__dw_pow2(edmi__two_sum(p1[a][c], sys->body[a].p[c]), k), x,
                    pass ? y : 0, &mag);
                if (pass == 0)
                    y[3 * a + c] = r.hi;
                nr += edmi__abs(r.hi) + edmi__abs(r.lo) + EDMI__DW_ERR * mag + EDMI__DW_TINY;
            }
        if (pass == 0) /* y = M^-1 rho.hi, solved in place */
            edmi__mass_solve(f, n, g, y, y);
    }
    bal->dk = edmi__dw_of(EDMI__ZERO);
    bal->size_k = EDMI__ZERO;
    for (a = 0; a < n; a++)
        for (c = 0; c < 3; c++) {
            edmi__dw d = edmi__dw_pow2(edmi__two_sum(p1[a][c], -sys->body[a].p[c]), k);
            edmi_real t = edmi__abs(d.hi * x[3 * a + c]) + edmi__abs(d.hi * y[3 * a + c]);
            bal->dk = edmi__dw_add(bal->dk, edmi__dw_mul_r(d, EDMI__HALF * x[3 * a + c]));
            bal->dk = edmi__dw_add(bal->dk, edmi__dw_mul_r(d, EDMI__HALF * y[3 * a + c]));
            mag_d += t;
            nd += edmi__abs(d.hi) + edmi__abs(d.lo);
            bal->size_k += edmi__abs((p1[a][c] + sys->body[a].p[c]) * k * x[3 * a + c]);
        }
    /* 1-norms bound the 2-norms; nfac covers their own rounding */
    bal->err_k = EDMI__DW_ERR * mag_d + EDMI__DW_TINY * (edmi_real)(3 * n + 1);
    if (lam > EDMI__ZERO)
        bal->err_k += EDMI__HALF * nd * nfac * (nr * nfac) / lam * nfac;
    else
        bal->err_k = EDMI_REAL_MAX * EDMI_R(2.0); /* inf: no bound, nothing certified */
}
#endif

/* dk and err_k for the end momenta p1. */
static void edmi__delta_k(const edmi_system *sys, edmi_workspace *work, const edmi_real (*p1)[3],
                          edmi__balance *bal)
{
    int a;
#if EDMI_MAX_MASS_GAP > 0
    if (EDMI__COUPLED(sys)) {
        edmi__delta_k_coupled(sys, work, p1, bal);
        return;
    }
#endif
    bal->dk = edmi__dw_of(EDMI__ZERO);
    bal->err_k = EDMI__ZERO;
    bal->size_k = EDMI__ZERO;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi__dw s1, s0;
        edmi_real m2;
        edmi_real x1[3], x0[3];
        int i;
        if (edmi__same3(p1[a], bd->p))
            continue;
        if (bal->scale == EDMI__ONE) {
            s1 = edmi__dw_norm2(p1[a]);
            /* |p_n|^2 as the last step evaluated it at its end (edmi__end_cached) */
            s0 = edmi__same3(work->kend[a], bd->p) ? edmi__dw_pair(work->kend[a] + 3)
                                                   : edmi__dw_norm2(bd->p);
            edmi__copy3(p1[a], work->kend[a]);
            work->kend[a][3] = s1.hi;
            work->kend[a][4] = s1.lo;
        } else {
            for (i = 0; i < 3; i++) { /* K = |p|^2 / 2m from the scaled momenta (exact) */
                x1[i] = p1[a][i] * bal->scale;
                x0[i] = bd->p[i] * bal->scale;
            }
            s1 = edmi__dw_norm2(x1);
            s0 = edmi__dw_norm2(x0);
        }
        m2 = EDMI_R(2.0) * bd->m;
        bal->dk = edmi__dw_add_z(bal->dk, edmi__dw_div_r(edmi__dw_sub(s1, s0), m2));
        bal->size_k += (s1.hi + s0.hi) / m2;
        bal->err_k += EDMI__DW_ERR * (s1.hi + s0.hi) / m2 + EDMI__DW_TINY / m2 + EDMI__DW_TINY;
    }
}

/* ---- the energy tank -------------------------------------------------------------------- */

/* t - e - m rounded down (a lower bound on the exact value): the tank t >= 0 after a step whose
 * excess over the work is at most e + m, m >= 0. Its two roundings err by at most 1.01 eps and
 * the last subtraction by 1.5 eps of A = t + |e| + m: 4 eps A covers them. */
static edmi_real edmi__tank_after(edmi_real t, edmi_real e, edmi_real m)
{
    edmi_real d = (t - e) - m;
    return d - (EDMI_R(4.0) * EDMI_EPS * (t + edmi__abs(e) + m) + EDMI__REAL_MIN);
}

/* The default capacity of the energy tank (edmi_params.tank_cap), in units of eps times the
 * magnitude S of H's terms: 256, i.e. 3.1e-5 S in float and 5.7e-14 S in double. The tank holds
 * the rounding noise of Newton's solution as a random walk between 0 and its capacity, and the
 * guard acts (and removes energy) only where it would run dry; a walk between two walls C apart
 * loses ~sigma^2 / (2 C) per step at the upper one, a drift linear in the steps, so C is chosen
 * to keep it below the noise's own ~sigma sqrt(N) for long runs (docs/guard.md, "Why a tank",
 * gives sigma, the run lengths and the orbits measured at 256 and 64). */
#define EDMI__TANK_CAP EDMI_R(256.0)

/* Where the guard must move the state, it aims to leave this fraction of the capacity in the
 * tank (and takes any state within as much of that): 1/128, 2 eps S at the default capacity,
 * so that the next steps' noise does not empty it again at once; leaving more would cost short
 * runs more than their own drift (docs/guard.md gives the replayed noise behind the choice). */
#define EDMI__TANK_LIFT (EDMI_R(1.0) / EDMI_R(128.0))

/* ---- the certificate -------------------------------------------------------------------- */

/* The guard's state between its moves: the excess e of the stored state's H change over the
 * work, its certification margin, the tank it may draw on, and where to aim. All in the
 * balance's (scaled) units. */
typedef struct edmi__aim {
    edmi__dw h;          /* H's change dv + dk */
    edmi_real e, margin; /* H change - work <= e + margin, exactly */
    edmi_real tank;      /* T_n: the step is certified when e + margin <= tank */
    edmi_real after;     /* T_n - e - margin rounded down (edmi__tank_after) */
    edmi_real goal, hi;  /* the K change sought, and the largest one that settles the step */
    edmi_real tol;       /* how close to goal is close enough (0: the search's own window) */
    edmi_real lift;      /* what a move leaves in the tank, about (EDMI__TANK_LIFT) */
    edmi_real strict;    /* how far below the tank the guard keeps the excess (tank_cap 0) */
} edmi__aim;

/* Excess e = (dv + dk) - w of the stored state over the work, a margin such that e + margin
 * >= the exact excess, and the tank after it (t->tank set). Both finite, or the state is
 * beyond what the guard covers. */
static int edmi__excess(const edmi__balance *bal, edmi__aim *t)
{
    edmi__dw x;
    edmi_real m;
    t->h = edmi__dw_add(bal->dv, bal->dk);
    x = edmi__dw_add_z(t->h, edmi__dw_neg(bal->w));
    m = bal->err_v + bal->err_k + edmi__abs(x.lo) +
        EDMI__DW_ERR * (edmi__abs(bal->dv.hi) + edmi__abs(bal->dk.hi) + edmi__abs(bal->w.hi));
    /* rounded upwards: the three sums above have relative error < 4 eps (0 stays 0: a state
     * whose every term is unchanged has an exactly zero change) */
    t->margin = m > EDMI__ZERO ? m + m * (EDMI_R(4.0) * EDMI_EPS) + EDMI__REAL_MIN : EDMI__ZERO;
    t->e = x.hi;
    t->after = edmi__tank_after(t->tank, t->e, t->margin);
    /* m NaN (an error bound 0/0 or inf - inf at the edge of the range) is no margin of 0 */
    return edmi__finite(x.hi) && edmi__finite(m) && edmi__finite(t->margin);
}

/* ---- the rounding ----------------------------------------------------------------------- */

/* One stored momentum component the energy-aware rounding may move: body a, axis i, value
 * p, grid spacing u (one unit in the last place) and 2m. */
typedef struct edmi__comp {
    int a, i;
    edmi_real p, u, m2;
#if EDMI_MAX_MASS_GAP > 0
    edmi_real pk; /* the momentum K's slope sees, dK/dp = pk / (m2 / 2): m_aa (M^-1 p1)_a for
                     a coupled M, p itself otherwise */
#endif
    edmi_real jq[3]; /* J's change per unit of momentum: q_a x e_i */
} edmi__comp;
#if EDMI_MAX_MASS_GAP > 0
#define EDMI__PK(c) ((c)->pk)
#else
#define EDMI__PK(c) ((c)->p) /* one mass per body: K's slope is p / m */
#endif

/* Unit in the last place of a normal x (0 for zero, subnormal, inf, NaN). */
static edmi_real edmi__ulp(edmi_real x)
{
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
    union {
        double r;
        unsigned long long u;
    } v;
    unsigned long long e;
    v.r = x;
    e = (v.u >> 52) & 0x7ffULL;
    if (e == 0 || e == 0x7ffULL)
        return EDMI__ZERO;
    v.u = e > 52 ? (e - 52) << 52 : 1ULL << (e - 1);
    return v.r;
#else
    union {
        float r;
        unsigned long u;
    } v;
    unsigned long e;
    v.u = 0;
    v.r = x;
    e = (v.u >> 23) & 0xffUL;
    if (e == 0 || e == 0xffUL)
        return EDMI__ZERO;
    v.u = e > 23 ? (e - 23) << 23 : 1UL << (e - 1);
    return v.r;
#endif
}

/* K's change when component c moves by k units: ((p + k u)^2 - p^2) / 2m. */
static EDMI__INLINE edmi_real edmi__comp_dk(const edmi__comp *c, int k)
{
#if EDMI_MAX_MASS_GAP > 0
    /* k u (2 pk + k u) / 2m: pk need not lie on p's grid (|pk| in a higher binade than |p|
     * would round pk + k u by half a unit of its own, doubling or cancelling the step);
     * bit for bit the expression below when pk = p */
    return (edmi_real)k * c->u * (EDMI_R(2.0) * EDMI__PK(c) + (edmi_real)k * c->u) / c->m2;
#else
    edmi_real v = EDMI__PK(c) + (edmi_real)k * c->u;
    return (v - EDMI__PK(c)) * (v + EDMI__PK(c)) / c->m2;
#endif
}

/* How far the energy-aware rounding moves the picked components (energy steps s0 >= s1 >=
 * s2 per unit in the last place): the coarsest is solved within k0 units for each offset
 * pair of the two finer ones, whose ranges cover the next coarser step, |k1| <= s0/(2 s1),
 * |k2| <= s1/(2 s2), but at least EDMI__ROUND_MIN (81 pairs, energies interleaving ~80x
 * finer than s0) and at most EDMI__ROUND_MAX. A unit of a finer component is a smaller
 * momentum, so each moves the momentum by a few units of its largest component: J and L
 * change like a few roundings. k0 <= EDMI__ROUND_K0 finishes almost every move; the wide
 * EDMI__ROUND_WIDE_K0 serves when nothing lies that near (a circular orbit about an anchor). */
#define EDMI__ROUND_MIN 1
#define EDMI__ROUND_MAX 4
#define EDMI__ROUND_K0 8
#define EDMI__ROUND_WINDOW (EDMI_R(1.0) / EDMI_R(32.0))
#define EDMI__ROUND_WIDE_K0 64
/* The guard's time is counted, not searched for: each of the three rounding searches of
 * the guard's moves tries at most EDMI__ROUND_BUDGET candidates (keeping the best it found
 * when they run out), and the last resort, which asks for any candidate below the
 * certificate, tries the 27 position variants with the finer components left where they
 * are: at most 3 EDMI__ROUND_BUDGET + 27 = 411 candidates an attempt, where there were 2,835
 * (what the budget changes, measured: docs/guard.md, "The guard's worst case"). */
#define EDMI__ROUND_BUDGET 128

/* The (up to) three momentum components whose units move K the most, coarsest first. */
static int edmi__pick_comps(const edmi_system *sys, edmi_workspace *work, edmi__comp c[3])
{
    const edmi_real (*p1)[3] = (const edmi_real (*)[3])work->p1;
    edmi_real s[3] = {EDMI__ZERO, EDMI__ZERO, EDMI__ZERO};
    int a, i, n = 0, k;
#if EDMI_MAX_MASS_GAP > 0
    int coupled = EDMI__COUPLED(sys);
    if (coupled) /* velocities M^-1 p1 into work->rhs, with the factor edmi__reaim left */
        edmi__mass_solve(work->mat, sys->n_bodies, EDMI_MAX_MASS_GAP, work->p1[0], work->rhs);
#endif
    for (a = 0; a < sys->n_bodies; a++)
        for (i = 0; i < 3; i++) {
            edmi__comp x;
            edmi_real sx;
            x.a = a;
            x.i = i;
            x.p = p1[a][i];
            x.u = edmi__ulp(x.p);
            x.m2 = EDMI_R(2.0) * sys->body[a].m;
#if EDMI_MAX_MASS_GAP > 0
            x.pk = coupled ? sys->body[a].m * work->rhs[3 * a + i] : x.p;
#endif
            x.jq[i] = EDMI__ZERO; /* q x e_i */
            x.jq[(i + 1) % 3] = work->q1[a][(i + 2) % 3];
            x.jq[(i + 2) % 3] = -work->q1[a][(i + 1) % 3];
            /* |p| >= 2^14 units: the offsets never cross zero or leave the binade by far */
            if (!(x.u > EDMI__ZERO) || edmi__abs(x.p) < EDMI_R(16384.0) * x.u ||
                !edmi__finite(edmi__abs(x.p) + EDMI_R(128.0) * x.u)) /* offsets overflow */
                continue;
            sx = edmi__abs(EDMI__PK(&x)) * x.u / sys->body[a].m;
            if (n == 3 && sx <= s[2])
                continue;
            k = n < 3 ? n++ : 2; /* insertion into the list sorted by reach */
            for (; k > 0 && s[k - 1] < sx; k--) {
                c[k] = c[k - 1];
                s[k] = s[k - 1];
            }
            c[k] = x;
            s[k] = sx;
        }
    return n;
}

/* The offset of the coarsest component c, within k3 units, bringing base + dk closest to
 * goal without exceeding hi; returns 0 if none within range. With `clamp` (the wide search,
 * the last resort) an offset beyond the range is clamped to its end: the candidate is then
 * far from goal but may still be below hi, which is all the certificate needs (at a turning
 * point of a stiff link the rounding of a position can exceed the whole kinetic energy, and
 * only a position move can take it back). */
static int edmi__solve_coarse(const edmi__comp *c, int k3, int clamp, edmi_real base,
                              edmi_real goal, edmi_real hi, int *k, edmi_real *got)
{
    edmi_real slope = EDMI_R(2.0) * EDMI__PK(c) * c->u / c->m2, x = (goal - base) / slope, v;
    int kk, dir = slope > EDMI__ZERO ? 1 : -1, step;
    if (!(x - x == EDMI__ZERO) ||
        (!clamp && !(x > (edmi_real)(-k3 - 1) && x < (edmi_real)(k3 + 1))))
        return 0;
    kk = x >= (edmi_real)k3 ? k3
         : x <= (edmi_real)-k3 ? -k3
                                : (int)(x + (x >= EDMI__ZERO ? EDMI__HALF : -EDMI__HALF));
    for (step = 0; step < 3; step++) {
        if (kk < -k3 || kk > k3)
            return 0;
        v = base + edmi__comp_dk(c, kk);
        if (v <= hi) {
            *k = kk;
            *got = v;
            return 1;
        }
        kk -= dir; /* one unit towards less kinetic energy */
    }
    return 0;
}

/* Range of a finer component: enough units to cover one unit of the next coarser one. */
static int edmi__round_range(const edmi__comp *coarse, const edmi__comp *fine)
{
    edmi_real r = edmi__abs(EDMI__PK(coarse) * coarse->u / coarse->m2) /
                  edmi__abs(EDMI__PK(fine) * fine->u / fine->m2);
    return r >= (edmi_real)(2 * EDMI__ROUND_MAX)   ? EDMI__ROUND_MAX
           : !(r > (edmi_real)(2 * EDMI__ROUND_MIN)) ? EDMI__ROUND_MIN /* and NaN: 0/0 */
                                                     : (int)(EDMI__HALF * r) + 1;
}

/* The position moves of the energy-aware rounding: body a's components by -1, 0 or +1 unit
 * in the last place (27 variants). Their energy steps, gradient of V - work_ext times the
 * unit, are unrelated to the momentum steps: they break the momentum lattice's
 * commensurability (two components of similar size make its energies cluster, leaving gaps
 * of a whole momentum unit), and a unit of q changes J about as much as a unit of p. */
typedef struct edmi__qmoves {
    int a, n;          /* body; number of variants (1: positions not moved) */
    edmi_real u[3];    /* units in the last place of q_a (0: component not moved) */
    edmi_real g[3];    /* d(V - work_ext)/dq_a at q_n+1 */
    edmi_real h;       /* a bound on V's curvature there (the links' max(|V''|, |V'|/d)): a
                          variant's energy is g.dq + h |dq|^2 / 2, to second order (near a
                          minimum g vanishes and a unit of q is all the change: a body resting
                          off the origin, 2 units from its anchor) */
    edmi_real jp[3];   /* p_a, for J's change dq x p_a */
} edmi__qmoves;

/* Variant v in 0..26 as offsets -1, 0, +1 per component (0 is no move). */
static void edmi__qvariant(int v, int o[3])
{
    static const signed char off[27][3] = {
        {0, 0, 0},   {1, 0, 0},   {-1, 0, 0},   {0, 1, 0},   {1, 1, 0},   {-1, 1, 0},
        {0, -1, 0},  {1, -1, 0},  {-1, -1, 0},  {0, 0, 1},   {1, 0, 1},   {-1, 0, 1},
        {0, 1, 1},   {1, 1, 1},   {-1, 1, 1},   {0, -1, 1},  {1, -1, 1},  {-1, -1, 1},
        {0, 0, -1},  {1, 0, -1},  {-1, 0, -1},  {0, 1, -1},  {1, 1, -1},  {-1, 1, -1},
        {0, -1, -1}, {1, -1, -1}, {-1, -1, -1}};
    o[0] = off[v][0];
    o[1] = off[v][1];
    o[2] = off[v][2];
}

/* x - floor(x) for |x| < 2^30; 0 beyond (and for NaN), where the residue the rounding
 * search orders its variants by carries no information (it only orders the search: the
 * guard certifies whatever state it stores). */
static EDMI__INLINE edmi_real edmi__frac(edmi_real x)
{
    edmi_real f;
    if (!(edmi__abs(x) < EDMI_R(1073741824.0)))
        return EDMI__ZERO;
    f = (edmi_real)(long)x;
    return f > x ? x - f + EDMI__ONE : x - f;
}

/* order[0..n-1] = 0..n-1 sorted by r[] ascending, stably (equal residues in index order),
 * r in [0, 1] (edmi__frac): a counting pass into EDMI__BUCKETS buckets of the residue's
 * leading bits, each filled in index order, then insertion, which only has the few
 * inversions within a bucket left to undo (2,300 instead of 2,500 instructions per step on
 * the Cortex-M4F for the 27 variants). n <= 27. */
#define EDMI__BUCKETS 16

static void edmi__sort_residues(const edmi_real *r, int n, int *order)
{
    int start[EDMI__BUCKETS + 1], b[27], v, j;
    for (j = 0; j <= EDMI__BUCKETS; j++)
        start[j] = 0;
    for (v = 0; v < n; v++) {
        int k = (int)(r[v] * (edmi_real)EDMI__BUCKETS); /* exact scaling: monotone in r */
        b[v] = k < EDMI__BUCKETS - 1 ? k : EDMI__BUCKETS - 1;
        start[b[v] + 1]++;
    }
    for (j = 1; j <= EDMI__BUCKETS; j++)
        start[j] += start[j - 1];
    for (v = 0; v < n; v++)
        order[start[b[v]]++] = v;
    for (v = 1; v < n; v++) {
        int x = order[v];
        for (j = v; j > 0 && r[order[j - 1]] > r[x]; j--)
            order[j] = order[j - 1];
        order[j] = x;
    }
}

/* Energy-aware rounding: position variant qv and momentum offsets k whose change of H - work
 * is closest to goal (any within tol count as equal) and <= hi (the coarsest component within
 * |k3| units, clamped there when k3 < 0: edmi__solve_coarse), and among those the one
 * changing the momenta least: |dJ|^2 (J about the origin) plus, without anchor links,
 * |dL|^2 l2 (l2 a squared length, so both are angular momenta). Without that second
 * criterion the choice is blind to the directions the energy does not see, and J drifts
 * over long runs. The coarsest momentum component is solved for each candidate; for each offset
 * pair of the two finer ones only the position variants whose energies fall nearest the
 * gap (modulo the coarsest unit: the variants are kept sorted by that residue) are tried.
 * At most *budget candidates, each counted off it (EDMI__ROUND_BUDGET). Returns 0 if none. */
static int edmi__round_search(const edmi__comp *c, int n, const edmi__qmoves *qm, int k3,
                              edmi_real goal, edmi_real hi, edmi_real tol, edmi_real l2, int k[3],
                              int *qv, int *budget)
{
    edmi_real best = EDMI_REAL_MAX, best_m = EDMI_REAL_MAX, got, m_ok, bq[27], jq[27][3], rq[27];
    edmi_real unit = EDMI_R(2.0) * EDMI__PK(&c[0]) * c[0].u / c[0].m2; /* K per unit of c[0], signed */
    int order[27], v, j1, j2, lim1, lim2, k0, found = 0, j, lo, hi_i, w;
    if (n == 0)
        return 0;
    /* the last resort (k3 < 0) leaves the finer components where they are */
    lim1 = n >= 2 && k3 > 0 ? edmi__round_range(&c[0], &c[1]) : 0;
    lim2 = n >= 3 && k3 > 0 ? edmi__round_range(&c[1], &c[2]) : 0;
    /* good enough to stop: within tol, and J moved by at most twice what a one-unit move of
     * any component does (plain rounding moves each by up to half a unit) */
    m_ok = EDMI__ZERO;
    for (j = 0; j < n; j++)
        m_ok = edmi__max(m_ok, c[j].u * c[j].u * edmi__dot(c[j].jq, c[j].jq));
    for (v = 0; v < qm->n; v++) { /* the position variants: energy, J change, residue */
        edmi_real dq[3];
        int o[3];
        edmi__qvariant(v, o);
        bq[v] = EDMI__ZERO;
        for (j = 0; j < 3; j++) {
            dq[j] = (edmi_real)o[j] * qm->u[j];
            bq[v] += (qm->g[j] + EDMI__HALF * qm->h * dq[j]) * dq[j];
        }
        edmi__cross(dq, qm->jp, jq[v]);
        if (v < 7) /* the single-unit moves */
            m_ok = edmi__max(m_ok, edmi__dot(jq[v], jq[v]));
        rq[v] = edmi__frac(bq[v] / unit);
    }
    edmi__sort_residues(rq, qm->n, order);
    m_ok *= EDMI_R(4.0);
    /* fine offsets in order of size, 0, 1, -1, 2, -2, ...: the first candidate good enough is
     * about the smallest move */
    for (j1 = 0; j1 <= 2 * lim1; j1++) {
        int i1 = (j1 & 1 ? 1 : -1) * ((j1 + 1) / 2);
        edmi_real e1 = lim1 ? edmi__comp_dk(&c[1], i1) : EDMI__ZERO;
        for (j2 = 0; j2 <= 2 * lim2; j2++) {
            int i2 = (j2 & 1 ? 1 : -1) * ((j2 + 1) / 2);
            edmi_real e12 = e1 + (lim2 ? edmi__comp_dk(&c[2], i2) : EDMI__ZERO);
            edmi_real ft = edmi__frac((goal - e12) / unit);
            /* the variants whose residue brackets ft, two on each side (cyclic); the last
             * resort (k3 < 0, the finer components unmoved) tries all 27: where a unit of q
             * moves H by more than the coarsest momentum component's whole range (a body
             * near rest off the origin), the residue says nothing about which one fits */
            for (lo = 0, hi_i = qm->n; lo < hi_i;) {
                int mid = (lo + hi_i) / 2;
                if (rq[order[mid]] <= ft)
                    lo = mid + 1;
                else
                    hi_i = mid;
            }
            for (w = k3 < 0 ? -qm->n : -2; w < (k3 < 0 ? 0 : 2) && w < qm->n - 2; w++) {
                edmi_real err, dj[3], dl[3], m;
                int kk[3], at = k3 < 0 ? w + qm->n : lo + w; /* cyclic: lo in [0, n] */
                v = order[at < 0 ? at + qm->n : at >= qm->n ? at - qm->n : at];
                if (*budget <= 0)
                    return found; /* the best so far (EDMI__ROUND_BUDGET) */
                --*budget;
                if (!edmi__solve_coarse(&c[0], k3 < 0 ? -k3 : k3, k3 < 0, e12 + bq[v], goal, hi,
                                        &k0, &got))
                    continue;
                err = edmi__max(edmi__abs(got - goal), tol);
                if (err > best)
                    continue;
                kk[0] = k0;
                kk[1] = i1;
                kk[2] = i2;
                edmi__copy3(jq[v], dj);
                for (j = 0; j < 3; j++)
                    dl[j] = EDMI__ZERO;
                for (j = 0; j < n; j++) {
                    edmi_real x = (edmi_real)kk[j] * c[j].u;
                    dj[0] += x * c[j].jq[0];
                    dj[1] += x * c[j].jq[1];
                    dj[2] += x * c[j].jq[2];
                    dl[c[j].i] += x;
                }
                m = edmi__dot(dj, dj) + l2 * edmi__dot(dl, dl);
                if (err < best || m < best_m) {
                    best = err;
                    best_m = m;
                    found = 1;
                    k[0] = k0;
                    k[1] = i1;
                    k[2] = i2;
                    *qv = v;
                    if (err <= tol && m <= m_ok) {
                        return 1;
                    }
                }
            }
        }
    }
    return found;
}

/* Apply offsets k to the picked components of p1. */
static void edmi__round_apply(edmi_workspace *work, const edmi__comp *c, int n, const int k[3])
{
    int j;
    for (j = 0; j < n; j++)
        work->p1[c[j].a][c[j].i] = c[j].p + (edmi_real)k[j] * c[j].u;
}

/* ---- impulse, drag and stop ------------------------------------------------------------- */

/* Change K by about `goal` with one impulse along the link that can best do it: equal and
 * opposite on a pair's two bodies (keeps L, J, C), radial on an anchored body (keeps J about
 * its anchor), along a wall's normal on its body (keeps the momentum along the wall and J
 * about the normal). The impulse lambda along the unit vector u changes K by
 * -lambda w + lambda^2 / (2 mu), w the ends' relative velocity along u, mu their reduced
 * mass: it can remove at most mu w^2 / 2. Returns 0 if no link or wall can. */
static int edmi__guard_impulse(const edmi_system *sys, edmi_workspace *work, edmi_real goal)
{
    edmi_real best = EDMI__ZERO, u[3] = {EDMI__ZERO, EDMI__ZERO, EDMI__ZERO}, bw = EDMI__ZERO;
    edmi_real bmu = EDMI__ZERO, disc, lam;
    int j, i, bj = -1, ba = -1, bb = EDMI_ANCHOR;
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        const edmi_real (*q1)[3] = (const edmi_real (*)[3])work->q1;
        edmi_real r[3], d, v[3], w, mu, cap;
        edmi__sub(q1[lk->a], edmi__end_b(lk, &work->lw[j], q1), r);
        d = edmi__norm(r);
        if (!(d > EDMI__ZERO))
            continue;
        mu = sys->body[lk->a].m;
        for (i = 0; i < 3; i++)
            v[i] = work->p1[lk->a][i] / mu;
        if (lk->b != EDMI_ANCHOR) {
            edmi_real mb = sys->body[lk->b].m;
            for (i = 0; i < 3; i++)
                v[i] -= work->p1[lk->b][i] / mb;
            mu = mu * mb / (mu + mb);
        }
        w = edmi__dot(v, r) / d;
        cap = EDMI__HALF * mu * w * w;
        /* removing more than half of what the link holds would reverse its motion */
        if (goal < EDMI__ZERO && cap < -goal * EDMI_R(2.0))
            continue;
        if (bj < 0 || cap > best) {
            best = cap;
            bj = j;
            ba = lk->a;
            bb = lk->b;
            bw = w;
            bmu = mu;
            for (i = 0; i < 3; i++)
                u[i] = r[i] / d;
        }
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < sys->n_walls; j++) { /* a wall: along its normal, as an anchor link */
        const edmi_wall *wl = &sys->wall[j];
        edmi_real mu = sys->body[wl->a].m, w = edmi__dot(work->p1[wl->a], wl->n) / mu;
        edmi_real cap = EDMI__HALF * mu * w * w;
        if (goal < EDMI__ZERO && cap < -goal * EDMI_R(2.0))
            continue;
        if (bj < 0 || cap > best) {
            best = cap;
            bj = sys->n_links + j;
            ba = wl->a;
            bb = EDMI_ANCHOR;
            bw = w;
            bmu = mu;
            edmi__copy3(wl->n, u);
        }
    }
#endif
    if (bj < 0)
        return 0;
    /* the root of lambda^2/(2 mu) - lambda w - goal = 0 nearer 0, without cancellation */
    disc = EDMI_SQRT(bw * bw + EDMI_R(2.0) * goal / bmu);
    lam = -EDMI_R(2.0) * goal / (bw >= EDMI__ZERO ? bw + disc : bw - disc);
    if (!edmi__finite(lam))
        return 0;
    for (i = 0; i < 3; i++) {
        work->p1[ba][i] -= lam * u[i];
        if (bb != EDMI_ANCHOR)
            work->p1[bb][i] += lam * u[i];
    }
    return 1;
}


/* The frame the fallback and the drag keep: the centre of mass's velocity L/M when L is
 * conserved (no anchor links, field or ports), else the anchors' rest frame (0). */
static void edmi__frame_velocity(const edmi_system *sys, const edmi_workspace *work,
                                 const edmi_real (*p)[3], edmi_real v[3])
{
    edmi_real mass = EDMI__ZERO;
    int a, i;
    for (i = 0; i < 3; i++)
        v[i] = EDMI__ZERO;
    if (work->n_pair < sys->n_links || EDMI__HAS_FIELD(sys) || EDMI__N_FORCED(sys) > 0)
        return;
    for (a = 0; a < sys->n_bodies; a++) {
        mass += edmi__mass_row(sys, a); /* the mass a uniform velocity carries: (M 1)_a */
        for (i = 0; i < 3; i++)
            v[i] += p[a][i];
    }
    for (i = 0; i < 3; i++)
        v[i] /= mass;
}

/* Remove kinetic energy -goal > 0 relative to the frame by a uniform drag
 * p_A -= alpha (p_A - m_A v): the relative K scales by (1 - alpha)^2. Keeps L (no anchors),
 * not J. Returns 0 if the relative K is less than -goal. */
static int edmi__guard_drag(const edmi_system *sys, edmi_workspace *work, edmi_real goal)
{
    edmi_real v[3], krel = EDMI__ZERO, alpha;
    int a, i;
    edmi__frame_velocity(sys, work, (const edmi_real (*)[3])work->p1, v);
    for (a = 0; a < sys->n_bodies; a++) /* the frame's momentum is (M 1)_a v */
        for (i = 0; i < 3; i++) {
            edmi_real x = work->p1[a][i] - edmi__mass_row(sys, a) * v[i];
            krel += EDMI__HALF * x * x / sys->body[a].m;
        }
#if EDMI_MAX_MASS_GAP > 0
    if (EDMI__COUPLED(sys)) { /* krel = 1/2 x . M^-1 x (x in work->dp: free in the guard) */
        for (a = 0; a < sys->n_bodies; a++)
            for (i = 0; i < 3; i++)
                work->dp[a][i] = work->p1[a][i] - edmi__mass_row(sys, a) * v[i];
        if (!edmi__cholesky(sys->n_bodies, sys->body, edmi__off_sys, sys,
                            (const edmi_real (*)[3])work->dp, &krel, EDMI__ZERO, 0, 0))
            return 0;
    }
#endif
    if (!(goal < EDMI__ZERO) || !(krel > -goal))
        return 0;
    alpha = EDMI__ONE - EDMI_SQRT(EDMI__ONE + goal / krel);
    for (a = 0; a < sys->n_bodies; a++)
        for (i = 0; i < 3; i++)
            work->p1[a][i] -= alpha * (work->p1[a][i] - edmi__mass_row(sys, a) * v[i]);
    return 1;
}

/* ---- the choice of moves ---------------------------------------------------------------- */

/* Re-evaluate K's change for the current work->p1, and the aim. 0 if beyond range. */
static int edmi__reaim(const edmi_system *sys, edmi_workspace *work, edmi__balance *bal,
                       edmi__aim *t)
{
    edmi__delta_k(sys, work, (const edmi_real (*)[3])work->p1, bal);
    if (!edmi__excess(bal, t))
        return 0;
    t->hi = t->tank - t->e - t->margin - t->strict;
    t->goal = t->hi - t->strict - t->lift; /* about the least change that settles the step */
    return 1;
}

/* Certified: the exact excess, at most e + margin, is <= T_n. The sign test is exact (a
 * rounded sum has its exact sum's sign), so an unchanged state (every term exactly 0)
 * certifies with an empty tank; else T_n - e - margin rounded down must be >= 0. */
static int edmi__certified(const edmi__aim *t)
{
    return t->e + t->margin <= EDMI__ZERO || t->after >= EDMI__ZERO;
}

/* Settled: certified, and with tank_cap = 0 at least strict below the work. */
static int edmi__settled(const edmi__aim *t)
{
    return t->strict > EDMI__ZERO ? t->e + t->margin <= -t->strict : edmi__certified(t);
}

/* d(V - work_ext)/dq_a at the end of the step, from each link's V'(d_n+1) (working
 * precision: the rounding search only needs its candidates' energies to ~eps relative), and
 * *h, a bound on the curvature (edmi__qmoves). */
static void edmi__grad_q(const edmi_system *sys, const edmi_workspace *work, int a,
                         edmi_real g[3], edmi_real *h)
{
    const edmi_real (*q1)[3] = (const edmi_real (*)[3])work->q1;
    int j, i;
    *h = EDMI__ZERO;
    for (i = 0; i < 3; i++)
#if EDMI_MAX_MASS_GAP > 0 /* the field pulls body a with (M 1)_a g */
        g[i] = EDMI__HAS_FIELD(sys) ? -edmi__mass_row(sys, a) * sys->g[i] : EDMI__ZERO;
#else
        g[i] = EDMI__HAS_FIELD(sys) ? -sys->body[a].m * sys->g[i] : EDMI__ZERO;
#endif
    for (j = 0; j < EDMI__N_FORCED(sys); j++)
        if (sys->internal.forced[j] == a)
            for (i = 0; i < 3; i++)
                g[i] -= sys->force[a][i];
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        edmi_real r1[3], d1, f;
        edmi_pot_parts pp;
        if (lk->a != a && lk->b != a)
            continue;
        edmi__sub(q1[lk->a], edmi__end_b(lk, &work->lw[j], q1), r1);
        d1 = edmi__norm(r1);
        if (edmi__is_linear(&lk->pot)) {
            f = lk->pot.a;
            *h += f;
        } else if (d1 > EDMI__ZERO && edmi__pot_parts(&lk->pot, d1, &pp, 1) == EDMI_OK) {
            f = pp.v[1] / d1;
            *h += edmi__max(edmi__abs(pp.v[2]), edmi__abs(f));
        } else {
            continue;
        }
        if (lk->a != a)
            f = -f;
        for (i = 0; i < 3; i++)
            g[i] += f * r1[i];
    }
}

/* The position moves for the rounding search: body a of the coarsest momentum component. */
static void edmi__pick_qmoves(const edmi_system *sys, const edmi_workspace *work, int a,
                              edmi__qmoves *qm)
{
    int i;
    qm->a = a;
    qm->n = 27;
    edmi__grad_q(sys, work, a, qm->g, &qm->h);
    edmi__copy3(work->p1[a], qm->jp);
    for (i = 0; i < 3; i++) {
        qm->u[i] = edmi__ulp(work->q1[a][i]);
        if (edmi__abs(work->q1[a][i]) < EDMI_R(16384.0) * qm->u[i] || !edmi__finite(qm->g[i]) ||
            !edmi__finite(edmi__abs(work->q1[a][i]) + EDMI_R(2.0) * qm->u[i])) /* near the top */
            qm->u[i] = EDMI__ZERO;
    }
}

/* x rounded downwards (x.hi is x rounded to nearest; one unit down where x.lo < 0). */
static edmi_real edmi__dw_down(edmi__dw x)
{
    return x.lo < EDMI__ZERO ? x.hi - edmi__max(edmi__ulp(x.hi), EDMI__REAL_MIN * EDMI_EPS) : x.hi;
}

/* A reported work, accumulated: its double-word sum and a bound on that sum's error. */
typedef struct edmi__work {
    edmi__dw w;
    edmi_real err;
} edmi__work;

/* acc += t, whose error is at most err. */
static void edmi__work_add_dw(edmi__work *acc, edmi__dw t, edmi_real err)
{
    acc->w = edmi__dw_add(acc->w, t);
    acc->err += err;
}

/* acc += sign f . (a - b): the products of exactly formed differences, summed in double-word
 * (JMP's accurate sum: 3 u^2 of the result each), err grown by EDMI__DW_ERR times the terms'
 * magnitude and EDMI__DW_TINY for the products' underflow. */
static void edmi__work_add(edmi__work *acc, const edmi_real f[3], const edmi_real a[3],
                           const edmi_real b[3], int sign)
{
    edmi_real m = EDMI__ZERO, fm = EDMI__ZERO;
    int i;
    for (i = 0; i < 3; i++) {
        m += edmi__abs(f[i]) * edmi__abs(a[i] - b[i]);
        fm += edmi__abs(f[i]);
    }
    edmi__work_add_dw(acc, sign > 0 ? edmi__dw_work(f, a, b, EDMI__ONE)
                                    : edmi__dw_neg(edmi__dw_work(f, a, b, EDMI__ONE)),
                      EDMI_R(2.0) * EDMI__DW_ERR * m + EDMI__DW_TINY * (EDMI__ONE + fm));
}

/* The work as reported: rounded down, a real no larger than any value within err of the sum
 * (so no larger than the exact work on the stored numbers; issue 32, item 5). The subtraction
 * errs by ~u^2 of the sum, far inside err (of its terms' magnitudes), taken twice. */
static edmi_real edmi__work_down(const edmi__work *acc)
{
    if (acc->err == EDMI__ZERO) /* no term: no port, no moving anchor or wall */
        return acc->w.hi;
    return edmi__dw_down(edmi__dw_add_r(acc->w, -EDMI_R(2.0) * acc->err));
}

/* work_ext for the current work->q1, rounded down (edmi__step_work); updates bal->w. */
static void edmi__port_work(const edmi_system *sys, const edmi_workspace *work,
                            edmi_step_result *res, edmi__balance *bal)
{
    edmi__work wx;
    int a;
    wx.w = edmi__dw_of(EDMI__ZERO);
    wx.err = EDMI__ZERO;
    for (a = 0; a < EDMI__N_FORCED(sys); a++) {
        int b = sys->internal.forced[a];
        edmi__work_add(&wx, sys->force[b], work->q1[b], sys->body[b].q, 1);
    }
    res->work_ext = edmi__work_down(&wx);
    bal->w = edmi__dw_up2(bal, edmi__two_sum(res->work_ext, res->work_anchor));
}

/* One energy-aware rounding, the coarsest momentum component within k3 units. Returns 0 if
 * nothing was in range, -1 if a moved position left the potentials' domain. */
static int edmi__guard_round(const edmi_system *sys, edmi_workspace *work, edmi__balance *bal,
                             const edmi__aim *t, int k3, edmi_step_result *res)
{
    edmi__comp c[3];
    edmi__qmoves qm;
    int k[3], n = edmi__pick_comps(sys, work, c), o[3], qv = 0, j;
    int budget = k3 < 0 ? 27 : EDMI__ROUND_BUDGET;
    edmi_real l2 = EDMI__ZERO, tol, goal;
    if (n == 0)
        return 0;
    if (work->n_pair == sys->n_links) /* no anchors: L is conserved too */
        for (j = 0; j < n; j++)
            l2 = edmi__max(l2, edmi__dot(work->q1[c[j].a], work->q1[c[j].a]));
    edmi__pick_qmoves(sys, work, c[0].a, &qm);
    tol = edmi__max(t->tol, EDMI__ROUND_WINDOW * edmi__abs(EDMI__PK(&c[0]) * c[0].u / c[0].m2));
    /* with a coupled M the search's model of K is exact to first order only (the cross terms
     * of M^-1 between the moved components are left out): aim two units of the coarsest
     * component below the edge, or its misses need a drag (the hanging cable's first
     * steps from rest, with the tank empty) */
    goal = t->goal - (EDMI__COUPLED(sys) ? edmi__abs(edmi__comp_dk(&c[0], 2)) : EDMI__ZERO);
    if (!edmi__round_search(c, n, &qm, k3, goal, t->hi, tol, l2, k, &qv, &budget))
        return 0;
    if ((k[0] | k[1] | k[2]) != 0) {
        edmi__round_apply(work, c, n, k);
        res->guard_action |= EDMI_MOVE_ROUND;
    }
    if (qv != 0) {
        edmi__qvariant(qv, o);
        for (j = 0; j < 3; j++)
            work->q1[qm.a][j] += (edmi_real)o[j] * qm.u[j];
        res->guard_action |= EDMI_MOVE_ROUND;
        edmi__port_work(sys, work, res, bal);
        if (edmi__delta_v(sys, work, (const edmi_real (*)[3])work->q1, bal, qm.a) != EDMI_OK)
            return -1;
    }
    return 1;
}

/* With tank_cap = 0 (no tank), how far below the work the guard keeps H's change, relative to
 * the size of the changed terms (balance size_v + size_k): 2^-58. An H change of 0 to -1e-18
 * of them satisfies the per-step guarantee, but a plain evaluation of H in a 64-bit
 * significand (x87 long double), whose error is a few 2^-64 of them, cannot tell its sign and
 * sees the energy rise on some steps. The search looks below this margin first; where nothing
 * lies there (a body at rest in its minimum), the certificate is all that is asked. */
#define EDMI__GUARD_STRICT (EDMI_R(1.0) / EDMI_R(288230376151711744.0))

/* The last move: every momentum set to the frame's (edmi__frame_velocity), Newton's positions
 * kept; K relative to the frame becomes 0. */
static void edmi__guard_stop(const edmi_system *sys, edmi_workspace *work)
{
    edmi_real v[3];
    int a, i;
    edmi__frame_velocity(sys, work, (const edmi_real (*)[3])work->p1, v);
    for (a = 0; a < sys->n_bodies; a++) {
        edmi_real m = edmi__mass_row(sys, a);
        for (i = 0; i < 3; i++)
            work->p1[a][i] = m * v[i];
    }
}

/* The guard's moves where the tank cannot cover Newton's iterate, in the order they are
 * tried (docs/guard.md, "Moves"). Each acts only while the step is not certified (the
 * rounding: not settled), aims at t->goal, and is certified again once it acted:
 *   HOLD     no position moved: each momentum component no larger than it was, with the sign
 *            the scheme gave it: K_n+1 <= K_n (a diagonal M), V and the works unchanged
 *            exactly (a body at a turning point, or held a few units in the last place off an
 *            anchor away from the origin, whose spring pulls on p while q cannot move by less
 *            than a unit); q_n+1 = q_n stays the scheme's position at a turning point;
 *   IMPULSE  an impulse along the link that can best take it (keeps L, J and C; J about the
 *            anchor on an anchor link), or along a wall's normal (keeps the momentum along
 *            the wall, J about the normal), where more than a couple of units are needed: the
 *            bulk of a real rise (MP or LG under EDMI_GUARD_ON), which a drag would take
 *            with J;
 *   ROUND    energy-aware rounding of the momenta (and of one body's position) within
 *            EDMI__ROUND_K0 units of the aim, else within EDMI__ROUND_WIDE_K0;
 *   DRAG     a drag relative to the frame (keeps L, not J), then the rounding again;
 *   CLAMPED  any rounding candidate below the certificate, however far from the aim (a
 *            position's rounding larger than the kinetic energy left);
 *   STOP     every momentum to the frame's, Newton's positions kept.
 * At the bottom of the range (scaled) the search's working-precision model of the candidates'
 * energies underflows, and the fallback's quick certificate (quick) counts no search: there
 * HOLD and STOP alone. What each move buys, over 10^6 steps of `make orbits`' scenes in both
 * precisions, with the default tank and tank_cap = 0, and on the coupled-mass scenes of
 * tests/programs/mass_spd.c, is in docs/guard.md; four one-unit nudges after the searches, tried
 * before, bought nothing measurable there. */
enum { EDMI__MOVE_HOLD, EDMI__MOVE_IMPULSE, EDMI__MOVE_ROUND, EDMI__MOVE_DRAG,
       EDMI__MOVE_CLAMPED, EDMI__MOVE_STOP, EDMI__MOVES };

/* Whether the step moved nothing: every body's q_n+1 is q_n and no anchor moves, so V, the
 * field's energy and the works are exactly what they were. */
static int edmi__held(const edmi_system *sys, const edmi_workspace *work)
{
    int a;
    if (sys->internal.n_moving > 0 || EDMI__COUPLED(sys))
        return 0;
    for (a = 0; a < sys->n_bodies; a++)
        if (!edmi__same3(sys->body[a].q, work->q1[a]))
            return 0;
    return 1;
}

/* Each momentum component no larger than it was at the start of the step. */
static void edmi__guard_hold(const edmi_system *sys, edmi_workspace *work)
{
    int a, i;
    for (a = 0; a < sys->n_bodies; a++)
        for (i = 0; i < 3; i++) {
            edmi_real p0 = edmi__abs(sys->body[a].p[i]);
            if (edmi__abs(work->p1[a][i]) > p0)
                work->p1[a][i] = work->p1[a][i] < EDMI__ZERO ? -p0 : p0;
        }
}

/* Move `move` of the list on the state t describes (search: the rounding searches may run).
 * 1 if it acted (the caller certifies again), 0 if it does not apply, -1 if a moved position
 * left the potentials' domain or the balance its range. */
static int edmi__guard_move(const edmi_system *sys, edmi_workspace *work, edmi__balance *bal,
                            edmi__aim *t, int move, int search, edmi_step_result *res)
{
    edmi__comp c[3];
    int r, n;
    switch (move) {
    case EDMI__MOVE_HOLD:
        if (!edmi__held(sys, work))
            return 0;
        edmi__guard_hold(sys, work);
        res->guard_action |= EDMI_MOVE_HOLD;
        return 1;
    case EDMI__MOVE_IMPULSE: /* the bulk, when more than a couple of units are needed */
        if (!search)
            return 0;
        n = edmi__pick_comps(sys, work, c);
        if (n > 0 && !(edmi__abs(t->goal) > EDMI__HALF * edmi__abs(edmi__comp_dk(&c[0], 4))))
            return 0;
        if (!edmi__guard_impulse(sys, work, t->goal))
            return 0;
        res->guard_action |= EDMI_MOVE_IMPULSE;
        return 1;
    case EDMI__MOVE_ROUND:
        if (!search)
            return 0;
        r = edmi__guard_round(sys, work, bal, t, EDMI__ROUND_K0, res);
        return r != 0 ? r : edmi__guard_round(sys, work, bal, t, EDMI__ROUND_WIDE_K0, res);
    case EDMI__MOVE_DRAG:
        if (!search || edmi__certified(t) || !edmi__guard_drag(sys, work, t->goal))
            return 0;
        res->guard_action |= EDMI_MOVE_DRAG;
        if (!edmi__reaim(sys, work, bal, t))
            return -1;
        if (!edmi__settled(t) && edmi__guard_round(sys, work, bal, t, EDMI__ROUND_K0, res) < 0)
            return -1;
        return 1;
    case EDMI__MOVE_CLAMPED:
        if (!search || edmi__certified(t))
            return 0;
        return edmi__guard_round(sys, work, bal, t, -EDMI__ROUND_WIDE_K0, res);
    default: /* EDMI__MOVE_STOP: a drag all the way (reported as one) */
        if (edmi__certified(t))
            return 0;
        edmi__guard_stop(sys, work);
        res->guard_action |= EDMI_MOVE_DRAG;
        return 1;
    }
}

/* The passivity guard on Newton's iterate work->p1 (bal: dv and w filled, in its scaled units;
 * cap: the tank's capacity after the step). Certifies H_n+1 - H_n - work <= T_n exactly,
 * moving the state only where the tank cannot cover the step, and sets res->tank to T_n+1 =
 * min(cap, T_n - (H_n+1 - H_n - work)), rounded down. */
static edmi_status edmi__guard(const edmi_system *sys, edmi_workspace *work, edmi__balance *bal,
                               edmi_real cap, int quick, edmi_step_result *res)
{
    edmi__dw h_newton;
    edmi__aim t;
    edmi_real after;
    int m;
    t.tank = edmi__up2(bal, edmi__tank_n(sys));
    t.strict = t.tol = t.lift = EDMI__ZERO;
    if (!edmi__reaim(sys, work, bal, &t))
        return EDMI_ERR_PASSIVITY;
    if (!(sys->params.tank_cap > EDMI__ZERO)) {
        t.strict = EDMI__GUARD_STRICT * (bal->size_v + bal->size_k);
        if (!edmi__finite(t.strict))
            t.strict = EDMI__ZERO;
        t.hi -= t.strict;
    }
    if (!edmi__settled(&t)) {
        h_newton = t.h;
        /* leave a little in the tank: the next steps' noise then rarely needs a move */
        t.lift = t.tol = edmi__up2(bal, cap) * EDMI__TANK_LIFT;
        t.goal = t.hi - t.strict - t.lift;
        for (m = 0; m < EDMI__MOVES && !edmi__settled(&t); m++) {
            int r = edmi__guard_move(sys, work, bal, &t, m, bal->scale == EDMI__ONE && !quick, res);
            if (r < 0 || (r > 0 && !edmi__reaim(sys, work, bal, &t)))
                return EDMI_ERR_PASSIVITY;
        }
        res->diss_guard = edmi__down2(bal, edmi__dw_real(edmi__dw_sub(h_newton, t.h)));
        if (!edmi__certified(&t))
            return EDMI_ERR_PASSIVITY;
    } /* else settled, hence certified */
    after = edmi__down2(bal, t.after);
    res->dh = edmi__down2(bal, edmi__dw_real(t.h));
    /* a subnormal quotient may have been rounded up: drop it */
    res->tank = after >= EDMI__REAL_MIN ? (after < cap ? after : cap) : EDMI__ZERO;
    return EDMI_OK;
}

/* ==========================================================================================
 * A step's end
 *
 * After Newton: the end state checked as the next step's start (links and walls), the works
 * and forces (edmi__step_work), the energy balance with the guard's verdict and moves
 * (edmi__finish), and the fallback state a step stores where it cannot be solved
 * (edmi__freeze, passive by construction).
 * ======================================================================================== */

/* A link's end state is one the next step starts from (edmi__prepare_links): a distance
 * > 0 (or 0 on a linear spring), a user potential that accepts it, and V and V' finite there.
 * MP evaluates only the mid-point, and LG's alternate forces only d_n and the mean length, so
 * Newton's solution can end a link at length 0 (a body landing exactly on its anchor),
 * outside a user potential's domain or where V' overflows: EDMI_ERR_END_STATE, a failure of
 * the step (substeps, the fallback), not a state the next call would refuse. */
static edmi_status edmi__end_valid(const edmi_link *lk, const edmi_real r1[3])
{
    edmi_pot_parts pp;
    if (r1[0] == EDMI__ZERO && r1[1] == EDMI__ZERO && r1[2] == EDMI__ZERO)
        return edmi__is_linear(&lk->pot) ? EDMI_OK : EDMI_ERR_END_STATE;
    /* a linear spring too: k/2 d^2 overflows first (a body pushed 1e164 far by a field) */
    if (edmi__pot_parts(&lk->pot, edmi__norm(r1), &pp, 1) != EDMI_OK ||
        !(edmi__finite(pp.v[0]) && edmi__finite(pp.v[1])))
        return EDMI_ERR_END_STATE; /* the next step could not start there */
    return EDMI_OK;
}

/* The same where Newton's last evaluation already had V and its magnitude M at this d_n+1
 * (GE, PM, PT, the LG quotient): V finite and M finite (so V' is) settle it without a second
 * evaluation; else (MP, LG's alternates, linear springs, parts beyond the range) the full one. */
static edmi_status edmi__end_valid_known(const edmi_link *lk, const edmi_link_ws *w,
                                         const edmi_real r1[3])
{
    if (w->have1 && w->d1 > EDMI__ZERO && edmi__finite(w->v1) && edmi__finite(w->m1) &&
        edmi__norm(r1) == w->d1)
        return EDMI_OK;
    return edmi__end_valid(lk, r1);
}

#if EDMI_MAX_WALLS > 0
/* A wall's end state is one the next step starts from (edmi__prepare_links): the gap, V and
 * V' finite there. Only the force's Lambda enters Newton's equations, so a body can end far
 * through a wall, where V overflows (a strong field; docs/testing.md lists the fuzzer's
 * case): EDMI_ERR_END_STATE, a failure of the step (substeps, the fallback), not a start the
 * next call would refuse. */
static edmi_status edmi__wall_end_valid(const edmi_system *sys, const edmi_workspace *work,
                                        int j)
{
    const edmi_wall *wl = &sys->wall[j];
    edmi_real g1 = edmi__wall_gap(wl, work->q1[wl->a], work->ww[j].x1[0]);
    edmi_pot_parts pp;
    if (!edmi__finite(g1) || edmi__pot_parts(&wl->pot, g1, &pp, 0) != EDMI_OK ||
        !edmi__finite(pp.v[0]) || !edmi__finite(pp.v[1]))
        return EDMI_ERR_END_STATE;
    return EDMI_OK;
}
#endif

/* Every link's end valid at the stored positions (edmi__end_valid), after the guard moved
 * them: a position rounded by a unit can cross a user potential's domain edge. */
static edmi_status edmi__ends_valid(const edmi_system *sys, const edmi_workspace *work)
{
    const edmi_real (*q1)[3] = (const edmi_real (*)[3])work->q1;
    int j;
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        edmi_real r1[3];
        edmi_status st;
        edmi__sub(q1[lk->a], edmi__end_b(lk, &work->lw[j], q1), r1);
        st = edmi__end_valid(lk, r1);
        if (st != EDMI_OK)
            return st;
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < sys->n_walls; j++)
        if (edmi__wall_end_valid(sys, work, j) != EDMI_OK)
            return EDMI_ERR_END_STATE;
#endif
    return EDMI_OK;
}

/* What the converged step did to energy: the ports' and anchors' (and walls') work, each
 * rounded down from its exact value on the stored numbers (F . (q_n+1 - q_n), -f . (x_n+1 -
 * x_n) with f the stored link force, -Lambda (c_n+1 - c_n)), each link's mean force on its
 * second end (work->lw[j].f: algorithmic force plus dampers), the dampers' dissipation, and
 * bal->w, the reported works' exact sum, which the guard certifies against. */
static edmi_status edmi__step_work(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                   edmi_step_result *res, edmi__balance *bal)
{
    const edmi_real (*q1)[3] = (const edmi_real (*)[3])work->q1;
    edmi__work wx, wa;
    int a, i, j;
    wx.w = wa.w = edmi__dw_of(EDMI__ZERO);
    wx.err = wa.err = EDMI__ZERO;
    for (a = 0; a < EDMI__N_FORCED(sys); a++) {
        int b = sys->internal.forced[a];
        edmi__work_add(&wx, sys->force[b], q1[b], sys->body[b].q, 1);
    }
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        edmi_link_ws *w = &work->lw[j];
        edmi_real r1[3];
        edmi_status st;
        edmi__sub(q1[lk->a], edmi__end_b(lk, w, q1), r1);
        st = edmi__end_valid_known(lk, w, r1);
        if (st != EDMI_OK)
            return st;
        for (i = 0; i < 3; i++)
            w->f[i] = w->beta * (EDMI__HALF * (w->r0[i] + r1[i]));
    }
    for (j = 0; j < EDMI__N_DAMPERS(sys); j++) {
        int l = sys->damper[j].link;
        const edmi_link *lk = &sys->link[l];
        edmi_link_ws *w = &work->lw[l];
        edmi_real r1[3], imp[3], k[9], loss;
        edmi_status st;
        edmi__sub(q1[lk->a], edmi__end_b(lk, w, q1), r1);
        st = edmi__damper(w, sys->damper[j].c, r1, imp, k, &loss);
        if (st != EDMI_OK)
            return st;
        res->diss_damping += loss / dt;
        for (i = 0; i < 3; i++)
            w->f[i] += imp[i] / dt;
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++) { /* its force, and a moving wall's work */
        edmi_real c0 = sys->wall[j].c, c1 = work->ww[j].x1[0];
        edmi__scale3(work->ww[j].beta, sys->wall[j].n, work->ww[j].f);
        if (!edmi__finite3(work->ww[j].f))
            return EDMI_ERR_OVERFLOW;
        if (edmi__wall_end_valid(sys, work, j) != EDMI_OK)
            return EDMI_ERR_END_STATE;
        if (c1 != c0) /* -Lambda (c_n+1 - c_n), the difference exact */
            edmi__work_add_dw(&wa,
                              edmi__dw_neg(edmi__dw_mul_r(edmi__two_sum(c1, -c0),
                                                          work->ww[j].beta)),
                              EDMI_R(2.0) * EDMI__DW_ERR * edmi__abs(work->ww[j].beta) *
                                      edmi__abs(c1 - c0) +
                                  EDMI__DW_TINY * (EDMI__ONE + edmi__abs(work->ww[j].beta)));
    }
#endif
    for (i = 0; i < sys->internal.n_moving; i++) {
        j = sys->internal.moving[i];
        edmi__work_add(&wa, work->lw[j].f, work->lw[j].x1, sys->link[j].anchor, -1);
    }
    res->work_ext = edmi__work_down(&wx);
    res->work_anchor = edmi__work_down(&wa);
    bal->w = edmi__two_sum(res->work_ext, res->work_anchor);
    for (j = 0; j < sys->n_links; j++)
        if (!edmi__finite3(work->lw[j].f))
            return EDMI_ERR_OVERFLOW; /* a link force beyond the range */
    return EDMI_OK;
}

/* The fallback state's forces at the kept positions: each link's V'(d) r/d (V'(d_n) where
 * both ends are kept) and each wall's V'(g) n, adding their magnitudes to *s1 (the tank's
 * capacity) and *so (the balance's scale), their components to *xh, and counting the walls
 * that move into *moved_walls. */
static edmi_status edmi__freeze_forces(const edmi_system *sys, edmi_workspace *work,
                                       edmi_real *s1, edmi_real *so, edmi_real *xh,
                                       int *moved_walls)
{
    int i, j;
    edmi_status st;
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        edmi_link_ws *w = &work->lw[j];
        edmi_real r1[3], d1, dv = EDMI__ZERO;
        edmi_pot_parts pp;
        edmi__sub(sys->body[lk->a].q, edmi__end_b(lk, w, (const edmi_real (*)[3])work->q1), r1);
        st = edmi__end_valid(lk, r1); /* an anchor moved onto its body, or out of a domain */
        if (st != EDMI_OK)
            return st;
        d1 = edmi__norm(r1);
        w->bal_on = !edmi__link_still(sys, w, lk, (const edmi_real (*)[3])work->q1);
        w->beta = EDMI__ZERO;
        if (edmi__is_linear(&lk->pot)) {
            w->beta = lk->pot.a;
            *s1 += EDMI_R(1.5) * lk->pot.a * d1 * d1;
            for (i = 0; i < 3; i++)
                *xh = edmi__max(*xh, edmi__max(edmi__abs(r1[i]), edmi__abs(w->r0[i])));
        } else if (!w->bal_on) { /* both ends kept: V'(d_n), finite (edmi__prepare_links) */
            dv = w->dv0;
            w->beta = dv / d1;
            *s1 += w->m0;
            *so += EDMI_R(2.0) * w->m0;
        } else if (d1 > EDMI__ZERO && edmi__pot_parts(&lk->pot, d1, &pp, 1) == EDMI_OK) {
            dv = pp.v[1];
            w->beta = dv / d1;
            *s1 += edmi__pot_mag(&lk->pot, &pp, d1);
            *so += w->m0 + edmi__pot_mag(&lk->pot, &pp, d1);
        }
        for (i = 0; i < 3; i++) /* V'(d) times the unit vector: finite where V' is */
            w->f[i] = edmi__is_linear(&lk->pot) ? w->beta * r1[i] : dv * (r1[i] / d1);
        if (!edmi__finite3(w->f))
            return EDMI_ERR_OVERFLOW; /* a moved anchor's force (the kept links' are V'(d_n)) */
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++) { /* positions kept: V'(g) n at the step's end */
        const edmi_wall *wl = &sys->wall[j];
        edmi_link_ws *w = &work->ww[j];
        edmi_pot_parts pp;
        edmi_real g1 = edmi__wall_gap(wl, sys->body[wl->a].q, w->x1[0]), m1;
        if (edmi__pot_parts(&wl->pot, g1, &pp, 0) != EDMI_OK || !edmi__finite(pp.v[0]) ||
            !edmi__finite(pp.v[1]))
            return EDMI_ERR_OVERFLOW; /* a moved wall's energy beyond the range */
        w->beta = pp.v[1];
        edmi__scale3(w->beta, wl->n, w->f);
        m1 = edmi__abs(pp.v[0]) + edmi__abs(pp.v[1]) * (edmi__abs(g1) + edmi__abs(w->x1[0]));
        *s1 += m1;
        *so += m1 + edmi__abs(w->v0) + edmi__abs(w->dv0) * (edmi__abs(w->d0) + edmi__abs(wl->c));
        *moved_walls += w->x1[0] != wl->c;
    }
#else
    (void)moved_walls;
#endif
    return EDMI_OK;
}

/* The fallback state's work_anchor: the moved anchors' (walls') change of V at the kept
 * positions, rounded upwards (0 where nothing moved), into res and the balance's work. */
static edmi_status edmi__freeze_work(const edmi_system *sys, edmi_workspace *work,
                                     edmi__balance *bal, int moved_walls, edmi_step_result *res)
{
    edmi_real wa;
    res->work_anchor = EDMI__ZERO;
    if (sys->internal.n_moving > 0 || moved_walls > 0) {
        if (edmi__delta_v(sys, work, (const edmi_real (*)[3])work->q1, bal, -1) != EDMI_OK)
            return EDMI_ERR_OVERFLOW; /* the moved anchors' (walls') energy beyond the range */
        /* dv + |dv.lo| + err_v >= the exact change, its two sums rounded up: each errs by
         * at most eps/2 of its terms (not of the sum, which can cancel), so 4 eps of them
         * covers both, the division by scale^2 and a subnormal quotient (REAL_MIN) */
        wa = bal->dv.hi + (edmi__abs(bal->dv.lo) + bal->err_v);
        wa += (edmi__abs(bal->dv.hi) + edmi__abs(bal->dv.lo) + bal->err_v) *
              (EDMI_R(4.0) * EDMI_EPS);
        res->work_anchor = edmi__down2(bal, wa) + EDMI__REAL_MIN;
        if (!edmi__finite(res->work_anchor))
            return EDMI_ERR_OVERFLOW;
    } else { /* nothing moved: every link term is exactly 0 (edmi__delta_v) */
        bal->dv = edmi__dw_of(EDMI__ZERO);
        bal->err_v = bal->size_v = EDMI__ZERO;
    }
    bal->w = edmi__dw_up2(bal, edmi__dw_of(res->work_anchor));
    return EDMI_OK;
}

/* The fallback state's certificate and tank: the frame's momenta where certified, else
 * momenta 0 (K_n+1 = 0 <= K_n), whose own margin is the construction's when even that is not
 * certified; s1 the state's magnitudes for the tank's capacity. */
static void edmi__freeze_certify(const edmi_system *sys, edmi_workspace *work,
                                 edmi__balance *bal, edmi_real s1, edmi_step_result *res)
{
    edmi__aim t;
    edmi_real after;
    int a, i, pass;
    t.tank = edmi__guard_on(&sys->params) ? edmi__up2(bal, edmi__tank_n(sys)) : EDMI__ZERO;
    res->tank = sys->tank;
    for (pass = 0;; pass++) {
        int evaluated;
        edmi__delta_k(sys, work, (const edmi_real (*)[3])work->p1, bal);
        evaluated = edmi__excess(bal, &t);
        res->dh = evaluated ? edmi__down2(bal, edmi__dw_real(t.h)) : EDMI__ZERO;
        if (evaluated && edmi__certified(&t)) {
            res->certificate = bal->scale == EDMI__ONE ? EDMI_CERT_DOUBLE_WORD : EDMI_CERT_SCALED;
            after = edmi__down2(bal, t.after);
            break;
        }
        if (pass == 1) {
            /* K_n+1 = 0 and still no certificate: its own margin where the tank is empty
             * and nothing is left to remove (a second substep of a frozen body whose anchor
             * moves), or K beyond the range. With the positions kept, H_n+1 - H_n = dV - K_n
             * <= work_anchor (an upper bound of dV, above) exactly, by construction; the
             * tank keeps its level */
            res->certificate = EDMI_CERT_NONE;
            after = edmi__tank_n(sys);
            break;
        }
        for (a = 0; a < sys->n_bodies; a++) /* the frame's momenta not certified: K_n+1 = 0 */
            for (i = 0; i < 3; i++)
                work->p1[a][i] = EDMI__ZERO;
    }
    if (edmi__guard_on(&sys->params)) {
        res->tank_cap = edmi__tank_cap(sys->params.tank_cap, s1);
        res->tank = after >= EDMI__REAL_MIN ? (after < res->tank_cap ? after : res->tank_cap)
                                            : EDMI__ZERO;
    }
}

/* The fallback state (params.fallback, where a step or substep failed; and the guard's stop
 * at the bottom of the range): positions kept, momenta set to the frame's (edmi__guard_stop),
 * or to 0 where those are not certified. Passive by construction: K does not grow, V changes
 * only where an anchor moved, and work_anchor is that change rounded upwards (the work a hand
 * does moving its end of a frozen link); with the guard on it fills the tank by what a
 * certificate shows it removed, up to the capacity (with the momenta 0 and no certificate the
 * tank keeps its level). link_force is each link's force V'(d) r/d at the end of the
 * step. Where no anchor moves nothing can fail: H changes by K's change alone, and where even
 * that cannot be evaluated (beyond the range) the momenta are set to 0, K_n+1 = 0 <= K_n. A
 * moved anchor that ends on its body or where its energy is beyond the range fails the call
 * (EDMI_ERR_END_STATE, EDMI_ERR_OVERFLOW): no state with the bodies kept is passive then. */
static edmi_status edmi__freeze(const edmi_system *sys, edmi_workspace *work,
                                edmi_step_result *res)
{
    edmi__balance bal;
    edmi_real s1 = EDMI__ZERO, so = edmi__tank_n(sys), xh = EDMI__ZERO;
    int a, i, moved_walls = 0;
    edmi_status st;
    for (a = 0; a < sys->n_bodies; a++) {
        edmi__copy3(sys->body[a].q, work->q1[a]);
        edmi__copy3(sys->body[a].p, work->p1[a]);
        for (i = 0; i < 3; i++)
            xh = edmi__max(xh, edmi__abs(sys->body[a].p[i]));
    }
    edmi__guard_stop(sys, work);
    for (a = 0; a < sys->n_bodies; a++) { /* magnitudes: the tank's capacity and the scale */
        edmi_real m = edmi__mass_row(sys, a);
        s1 += EDMI__HALF * edmi__dot(work->p1[a], work->p1[a]) / sys->body[a].m;
        if (EDMI__HAS_FIELD(sys)) {
            edmi_real f = edmi__abs(m) * edmi__norm(sys->g) * edmi__norm(sys->body[a].q);
            s1 += f;
            so += EDMI_R(2.0) * f;
        }
    }
    st = edmi__freeze_forces(sys, work, &s1, &so, &xh, &moved_walls);
    if (st != EDMI_OK)
        return st;
    res->work_ext = EDMI__ZERO;
    res->diss_damping = EDMI__ZERO;
    res->diss_scheme = EDMI__ZERO;
    res->diss_guard = EDMI__ZERO;
    res->guard_action = 0;
    edmi__set_scale(&bal, xh, so);
    bal.scheme_on = 0;
    st = edmi__freeze_work(sys, work, &bal, moved_walls, res);
    if (st != EDMI_OK)
        return st;
    edmi__freeze_certify(sys, work, &bal, s1, res);
    return EDMI_OK;
}

/* After Newton converged: work, forces, and with the guard (or energy_balance) the step's
 * energy change, certified by the cheapest evaluation that settles it (see this section's
 * head): the plain one where the step dissipates more than its bound and the tank stays
 * full, else double-word, then the guard's moves where the tank cannot cover the step. */
static edmi_status edmi__finish(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                int quick, edmi_step_result *res)
{
    edmi__balance bal;
    edmi__plain pl;
    edmi_real cap, x, so, tank;
    edmi_status st = edmi__step_work(sys, work, dt, res, &bal);
    int guard = edmi__guard_on(&sys->params), exact = sys->params.energy_balance;
    if (st == EDMI_OK && !(edmi__finite(res->work_ext) && edmi__finite(res->work_anchor) &&
                           edmi__finite(res->diss_damping)))
        st = EDMI_ERR_OVERFLOW; /* a port's work F . dq or a damper's loss beyond the range */
    if (st != EDMI_OK || (!guard && !exact))
        return st;
    st = edmi__plain_excess(sys, work, res, &pl);
    if (st != EDMI_OK)
        return st;
    cap = res->tank_cap = edmi__tank_cap(guard ? sys->params.tank_cap : EDMI__ZERO, pl.s1);
    res->dh = pl.e + (res->work_ext + res->work_anchor);
    tank = edmi__tank_n(sys);
    if (guard && !exact && pl.ok && edmi__finite(pl.scheme) && edmi__finite(res->dh) &&
        edmi__tank_after(tank, pl.e, pl.m) >= cap &&
        edmi__tank_after(tank, pl.e, pl.m + edmi__plain_tiny(sys, work)) >= cap) {
        res->certificate = EDMI_CERT_PLAIN;
        res->tank = res->tank_cap;
        res->diss_scheme = pl.scheme;
        return EDMI_OK;
    }
    x = so = EDMI_REAL_MAX;
    if (pl.s1 < EDMI__SCALE_BELOW) /* every term small at the end: perhaps at both ends */
        edmi__scale_inputs(sys, work, res, &x, &so);
    edmi__set_scale(&bal, x, so);
    bal.w = edmi__dw_up2(&bal, bal.w);
    bal.scheme_on = exact;
    st = edmi__delta_v(sys, work, (const edmi_real (*)[3])work->q1, &bal, -1);
    if (st != EDMI_OK)
        return st;
    res->diss_scheme = exact ? edmi__down2(&bal, edmi__dw_real(bal.scheme)) : pl.scheme;
    if (!edmi__finite(res->diss_scheme) || !edmi__finite(edmi__dw_real(bal.dv)))
        return EDMI_ERR_OVERFLOW; /* a link energy (|r|^2, V) beyond the range */
    res->certificate = bal.scale == EDMI__ONE ? EDMI_CERT_DOUBLE_WORD : EDMI_CERT_SCALED;
    if (guard) {
        st = edmi__guard(sys, work, &bal, res->tank_cap, quick, res);
        if (st == EDMI_ERR_PASSIVITY && bal.scale != EDMI__ONE) {
            /* at the bottom of the range a position's rounding can exceed what every move
             * of the momenta covers (double, |q| ~ 1e-321): the bodies stop where they were */
            st = edmi__freeze(sys, work, res);
            res->guard_action |= EDMI_MOVE_STOP;
            return st;
        }
        if (st != EDMI_OK)
            return st;
        if (res->guard_action != 0) {
            st = edmi__ends_valid(sys, work);
            if (st != EDMI_OK)
                return st;
        }
    } else {
        edmi__delta_k(sys, work, (const edmi_real (*)[3])work->p1, &bal);
        res->dh = edmi__down2(&bal, edmi__dw_real(edmi__dw_add(bal.dv, bal.dk)));
    }
    return edmi__finite(res->dh) ? EDMI_OK : EDMI_ERR_PASSIVITY;
}

/* ==========================================================================================
 * One attempt, the fallback and substeps
 *
 * An attempt is the predictor, Newton and the step's end (the energy balance and the guard).
 * A failed attempt (SINGULAR, NO_CONVERGENCE, DIVERGED, PASSIVITY, RANGE) is retried as
 * substeps (params.substep_levels), and where that still fails stores the fallback state
 * (params.fallback): every step then ends in bounded time with a passive state.
 * ======================================================================================== */

/* t += dt with Kahan's compensation: after n steps t is off by ~eps t, not ~n eps t, which
 * keeps the centre-of-mass invariant C(t) = (sum m q - t L)/M free of clock drift. */
static void edmi__advance_clock(edmi_system *sys, edmi_real dt)
{
    edmi_real y = dt - sys->internal.t_carry, t = sys->t + y;
    sys->internal.t_carry = (t - sys->t) - y;
    sys->t = t;
}

static void edmi__clear_result(edmi_step_result *res)
{
    res->iterations = 0;
    res->stop = EDMI_STOP_CONVERGED;
    res->residual = EDMI__ZERO;
    res->residual0 = EDMI__ZERO;
    res->correction = EDMI__ZERO;
    res->lg_switches = 0;
    res->halvings = 0;
    res->work_ext = EDMI__ZERO;
    res->work_anchor = EDMI__ZERO;
    res->diss_damping = EDMI__ZERO;
    res->diss_scheme = EDMI__ZERO;
    res->dh = EDMI__ZERO;
    res->diss_guard = EDMI__ZERO;
    res->guard_action = 0;
    res->certificate = EDMI_CERT_NONE;
    res->tank = EDMI__ZERO;
    res->tank_cap = EDMI__ZERO;
    res->substeps = 0;
    res->fallbacks = 0;
    res->cause = EDMI_OK;
}

/* The failures after the input was accepted: substeps and the fallback take them over. */
static int edmi__is_step_failure(edmi_status st)
{
    return st == EDMI_ERR_SINGULAR || st == EDMI_ERR_NO_CONVERGENCE || st == EDMI_ERR_DIVERGED ||
           st == EDMI_ERR_PASSIVITY || st == EDMI_ERR_OVERFLOW || st == EDMI_ERR_END_STATE;
}

/* One step of dt from the system's state (its links prepared), into work and *res; nothing
 * stored: the predictor q_n+1,(0) = q_n, p_n+1,(0) = p_n, Newton, then the work, the energy
 * balance and the guard (edmi__finish). */
static edmi_status edmi__attempt(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                 edmi_step_result *res)
{
    edmi_status st;
    edmi__clear_result(res);
    res->tank = sys->tank; /* the guard sets the tank after the step */
    st = edmi__predictor(sys, work, dt, res);
    if (st != EDMI_OK) /* the predictor's residual outside the domain: a failed step */
        return st == EDMI_ERR_DOMAIN || st == EDMI_ERR_OVERFLOW ? EDMI_ERR_DIVERGED : st;
    st = edmi__set_scales(sys, work, dt); /* the predictor's residual sets the scales, */
    if (st != EDMI_OK)
        return st;
    res->residual0 = edmi__scaled_residual(sys, work); /* then is measured with them */
    res->residual = res->residual0;
    if (!edmi__finite(res->residual0)) /* beyond the precision's range: nothing to solve */
        return EDMI_ERR_OVERFLOW;
    st = edmi__newton(sys, work, dt, res);
    if (st == EDMI_ERR_DOMAIN) /* an iterate outside the domain that halving never reached */
        return EDMI_ERR_DIVERGED;
    if (st != EDMI_OK)
        return st;
    st = edmi__finish(sys, work, dt, 0, res);
    /* a user potential refusing the solution's end, met by the energy balance before the
     * end checks: the solution ends where the next step could not start */
    return st == EDMI_ERR_DOMAIN ? EDMI_ERR_END_STATE : st;
}

/* The fallback after a failed attempt (edmi_params.fallback): with the guard on, Newton's last
 * iterate where l_max stopped it closer than the predictor (by half, in the scaled residual),
 * certified by the guard's quick path (the tank, or the momenta set to the frame's: no
 * search, so that its time stays that of a certificate), so that a run of hard steps keeps
 * moving; else the frozen state (edmi__freeze). */
static edmi_status edmi__fallback(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                  edmi_step_result *res, edmi_status failure)
{
    edmi_status st;
    if (failure == EDMI_ERR_NO_CONVERGENCE && edmi__guard_on(&sys->params) &&
        res->residual <= EDMI__HALF * res->residual0) {
        st = edmi__finish(sys, work, dt, 1, res);
        if (st == EDMI_OK) {
            res->stop = EDMI_STOP_FALLBACK;
            return EDMI_OK;
        }
    }
    st = edmi__freeze(sys, work, res);
    res->stop = EDMI_STOP_FALLBACK;
    return st;
}

/* Store the attempt in work as the system's state (the clock advances in edmi_step). */
static void edmi__commit(edmi_system *sys, const edmi_workspace *work, edmi_real tank)
{
    int a, i;
    for (a = 0; a < sys->n_bodies; a++) {
        edmi__copy3(work->q1[a], sys->body[a].q);
        edmi__copy3(work->p1[a], sys->body[a].p);
    }
    for (i = 0; i < sys->internal.n_moving; i++) {
        int j = sys->internal.moving[i];
        edmi__copy3(sys->internal.anchor_next[j], sys->link[j].anchor);
    }
    sys->internal.n_moving = 0;
#if EDMI_MAX_WALLS > 0
    for (i = 0; i < sys->n_walls; i++) /* a moved wall rests where it got to */
        sys->wall[i].c = sys->internal.wall_next[i];
#endif
    sys->tank = tank;
}

/* x rounded upwards (x.hi is x rounded to nearest; one unit up where x.lo > 0). */
static edmi_real edmi__dw_up(edmi__dw x)
{
    return x.lo > EDMI__ZERO ? x.hi + edmi__max(edmi__ulp(x.hi), EDMI__REAL_MIN * EDMI_EPS) : x.hi;
}

/* Add a stored substep's result *sub into the step's *res. The works are summed exactly
 * (double-word, in *wx and *wa) and reported rounded upwards, so that the step's inequality
 * H_n+1 - H_n <= work_ext + work_anchor + T_n - T_n+1 is the sum of the substeps' (until
 * edmi__split_works rounds them down at the step's end). */
static void edmi__add_substep(edmi_step_result *res, const edmi_step_result *sub, edmi__dw *wx,
                              edmi__dw *wa)
{
    *wx = edmi__dw_add(*wx, edmi__dw_of(sub->work_ext));
    *wa = edmi__dw_add(*wa, edmi__dw_of(sub->work_anchor));
    res->work_ext = edmi__dw_up(*wx);
    res->work_anchor = edmi__dw_up(*wa);
    res->diss_damping += sub->diss_damping;
    res->diss_scheme += sub->diss_scheme;
    res->dh += sub->dh;
    res->diss_guard += sub->diss_guard;
    res->guard_action |= sub->guard_action;
    res->certificate = sub->certificate > res->certificate ? sub->certificate : res->certificate;
    res->residual = edmi__max(res->residual, sub->residual);
    res->correction = sub->correction;
    res->lg_switches = sub->lg_switches > res->lg_switches ? sub->lg_switches : res->lg_switches;
    res->tank = sub->tank;
    res->tank_cap = sub->tank_cap;
    res->stop = res->stop == EDMI_STOP_FALLBACK ? res->stop : sub->stop;
    res->substeps++;
    res->fallbacks += sub->stop == EDMI_STOP_FALLBACK;
}

/* The works of a split step as reported: the substeps' sums *wx, *wa rounded down (never
 * above the exact works, each substep's being rounded down), where the tank at the end holds
 * what that takes from the step's inequality, at most a unit of each work: T_n+1 is lowered
 * by it (rounded down), so H_n+1 - H_n <= work_ext + work_anchor + T_n - T_n+1 still holds of
 * the reported numbers. With less in the tank (tank_cap 0, or a tank drained to 0) the
 * works stay rounded up (edmi__add_substep), at most a unit above their exact sum. */
static void edmi__split_works(edmi_system *sys, edmi_step_result *res, edmi__dw wx, edmi__dw wa)
{
    edmi_real wx_down = edmi__dw_down(wx), wa_down = edmi__dw_down(wa), tank;
    /* each difference is exact (a unit or 0); twice the larger is at least their sum */
    edmi_real cut = EDMI_R(2.0) * edmi__max(res->work_ext - wx_down, res->work_anchor - wa_down);
    if (cut == EDMI__ZERO || !edmi__guard_on(&sys->params))
        return; /* exact already, or no tank to take it from (untouched with the guard off) */
    tank = edmi__dw_down(edmi__dw_add_r(edmi__dw_of(sys->tank), -cut));
    if (!(tank >= EDMI__ZERO))
        return;
    res->work_ext = wx_down;
    res->work_anchor = wa_down;
    sys->tank = res->tank = tank >= EDMI__REAL_MIN ? tank : EDMI__ZERO;
}

/* Whether the step's sums stay within the range with substep *sub added (each substep's
 * work is finite, their sum need not be: a port's work that overflows over dt). */
static int edmi__sums_fit(const edmi_step_result *res, const edmi_step_result *sub, edmi__dw wx,
                          edmi__dw wa)
{
    wx = edmi__dw_add(wx, edmi__dw_of(sub->work_ext));
    wa = edmi__dw_add(wa, edmi__dw_of(sub->work_anchor));
    return edmi__finite(edmi__dw_up(wx)) && edmi__finite(edmi__dw_up(wa)) &&
           edmi__finite(res->diss_damping + sub->diss_damping) &&
           edmi__finite(res->diss_scheme + sub->diss_scheme) && edmi__finite(res->dh + sub->dh) &&
           edmi__finite(res->diss_guard + sub->diss_guard);
}

/* The step's mean link and wall forces into the system's outputs (from each one's f, or with
 * substeps from fsum, their sum over the substeps). */
static void edmi__store_forces(edmi_system *sys, const edmi_workspace *work, int summed)
{
    int j;
    for (j = 0; j < sys->n_links; j++)
        edmi__copy3(summed ? work->lw[j].fsum : work->lw[j].f, sys->link_force[j]);
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++)
        edmi__copy3(summed ? work->ww[j].fsum : work->ww[j].f, sys->wall_force[j]);
#endif
}

/* Put the step's start back (the bodies, the tank and the moving anchors), after substeps
 * that failed: the system is then bit-identical to before the call. */
static void edmi__restore(edmi_system *sys, const edmi_workspace *work, edmi_real tank,
                          int n_moving)
{
    int a, i;
    for (a = 0; a < sys->n_bodies; a++) {
        edmi__copy3(work->q0[a], sys->body[a].q);
        edmi__copy3(work->p0[a], sys->body[a].p);
    }
    sys->tank = tank;
    sys->internal.n_moving = n_moving;
    for (i = 0; i < n_moving; i++) {
        int j = sys->internal.moving[i];
        edmi__copy3(work->lw[j].xs, sys->link[j].anchor);
        edmi__copy3(work->lw[j].xt, sys->internal.anchor_next[j]);
    }
#if EDMI_MAX_WALLS > 0
    for (i = 0; i < sys->n_walls; i++) {
        sys->wall[i].c = work->ww[i].xs[0];
        sys->internal.wall_next[i] = work->ww[i].xt[0];
    }
#endif
}

/* A moving anchor where the substep that starts at pos (of 2^k units of dt) starts or ends:
 * straight from xs to xt. */
static void edmi__anchor_at(const edmi_link_ws *w, int pos, int k, edmi_real x[3])
{
    edmi_real f = (edmi_real)pos / (edmi_real)(1L << k);
    int i;
    for (i = 0; i < 3; i++)
        x[i] = pos == (1 << k) ? w->xt[i] : w->xs[i] + f * (w->xt[i] - w->xs[i]);
}

/* Before the substeps: the step's start (work->q0, p0), the links' and walls' summed forces
 * cleared, and where each moving anchor and wall starts and ends (xs, xt). */
static void edmi__substeps_start(const edmi_system *sys, edmi_workspace *work)
{
    int a, i, j;
    work->kept = 0; /* the kept factors are of dt's matrix: substeps factor their own */
    for (a = 0; a < sys->n_bodies; a++) {
        edmi__copy3(sys->body[a].q, work->q0[a]);
        edmi__copy3(sys->body[a].p, work->p0[a]);
    }
    for (j = 0; j < sys->n_links; j++)
        for (i = 0; i < 3; i++)
            work->lw[j].fsum[i] = EDMI__ZERO;
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++) /* and a wall's offsets, as an anchor's x */
        for (i = 0; i < 3; i++) {
            work->ww[j].fsum[i] = EDMI__ZERO;
            work->ww[j].xs[i] = i == 0 ? sys->wall[j].c : EDMI__ZERO;
            work->ww[j].xt[i] = i == 0 ? sys->internal.wall_next[j] : EDMI__ZERO;
        }
#endif
    for (i = 0; i < sys->internal.n_moving; i++) {
        j = sys->internal.moving[i];
        edmi__copy3(sys->link[j].anchor, work->lw[j].xs);
        edmi__copy3(sys->internal.anchor_next[j], work->lw[j].xt);
    }
}

/* The moving anchors and walls where the substep from pos to pos + units (of 2^k units of
 * dt) starts and ends. */
static void edmi__substep_place(edmi_system *sys, const edmi_workspace *work, int n_moving,
                                int pos, int units, int k)
{
    int i, j;
    sys->internal.n_moving = n_moving;
    for (i = 0; i < n_moving; i++) {
        j = sys->internal.moving[i];
        edmi__anchor_at(&work->lw[j], pos, k, sys->link[j].anchor);
        edmi__anchor_at(&work->lw[j], pos + units, k, sys->internal.anchor_next[j]);
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < sys->n_walls; j++) {
        edmi_real x[3];
        edmi__anchor_at(&work->ww[j], pos, k, x);
        sys->wall[j].c = x[0];
        edmi__anchor_at(&work->ww[j], pos + units, k, x);
        sys->internal.wall_next[j] = x[0];
    }
#endif
}

/* The failed step again as substeps (edmi_params.substep_levels = k): two of dt/2, a substep
 * that fails as two of half its size, down to dt/2^k, each taken, stored and certified as a
 * step; after a stored substep the next is as long as its start's alignment allows (a hard
 * moment passed, the rest goes back to longer substeps). A substep of dt/2^k that fails
 * stores the fallback state (params.fallback) or fails the call, which then restores the
 * start. Worst case (every attempt failing down to dt/2^k): 2^(k+1) - 2 attempts after the
 * step's own and 2^k fallbacks. With k = 0 the step's own attempt falls back at once. */
static edmi_status edmi__substeps(edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                  edmi_step_result *res, edmi_status cause)
{
    edmi_step_result sub;
    edmi__dw wx = edmi__dw_of(EDMI__ZERO), wa = edmi__dw_of(EDMI__ZERO);
    edmi_real tank0 = sys->tank, h;
    edmi_status st = cause;
    int k = sys->params.substep_levels, n_moving = sys->internal.n_moving, level, pos = 0, i, j;
    int iterations = res->iterations, halvings = res->halvings;
    edmi_real residual0 = res->residual0;
    for (h = dt, i = 0; i < k; i++) /* the finest substep stays a normal number */
        if (!((h *= EDMI__HALF) >= EDMI__REAL_MIN))
            k = i;
    if (k == 0) { /* the step's own attempt (in work) falls back as it is */
        st = sys->params.fallback ? edmi__fallback(sys, work, dt, res, cause) : cause;
        if (st != EDMI_OK)
            return st;
        res->iterations = iterations;
        res->halvings = halvings;
        res->substeps = res->fallbacks = 1;
        res->cause = cause;
        edmi__commit(sys, work, res->tank);
        edmi__store_forces(sys, work, 0);
        return EDMI_OK;
    }
    edmi__substeps_start(sys, work);
    edmi__clear_result(res);
    res->cause = cause;
    res->residual0 = residual0;
    level = 1;
    while (pos < (1 << k)) {
        int units = 1 << (k - level);
        edmi_real frac = (edmi_real)units / (edmi_real)(1L << k); /* a power of two */
        edmi__substep_place(sys, work, n_moving, pos, units, k);
        st = edmi__prepare_links(sys, work);
        if (st != EDMI_OK) { /* a substep's start the potentials refuse: no retry */
            edmi__restore(sys, work, tank0, n_moving);
            res->iterations = iterations;
            res->halvings = halvings;
            return st;
        }
        st = edmi__attempt(sys, work, dt * frac, &sub);
        iterations += sub.iterations;
        halvings += sub.halvings;
        if (st != EDMI_OK && edmi__is_step_failure(st) && level < k) {
            level++; /* the same start, half as far */
            continue;
        }
        if (st != EDMI_OK && edmi__is_step_failure(st) && sys->params.fallback)
            st = edmi__fallback(sys, work, dt * frac, &sub, st);
        if (st == EDMI_OK && !edmi__sums_fit(res, &sub, wx, wa)) {
            /* the step's work or balance beyond the range: this substep falls back (the
             * frozen state does no work but a moved anchor's) or the call fails */
            st = sys->params.fallback ? edmi__freeze(sys, work, &sub) : EDMI_ERR_OVERFLOW;
            sub.stop = EDMI_STOP_FALLBACK;
            if (st == EDMI_OK && !edmi__sums_fit(res, &sub, wx, wa))
                st = EDMI_ERR_OVERFLOW;
        }
        if (st != EDMI_OK) {
            edmi__restore(sys, work, tank0, n_moving);
            res->iterations = iterations;
            res->halvings = halvings;
            return st;
        }
        edmi__add_substep(res, &sub, &wx, &wa);
        for (j = 0; j < sys->n_links; j++)
            for (i = 0; i < 3; i++)
                work->lw[j].fsum[i] += frac * work->lw[j].f[i];
#if EDMI_MAX_WALLS > 0
        for (j = 0; j < EDMI__N_WALLS(sys); j++)
            for (i = 0; i < 3; i++)
                work->ww[j].fsum[i] += frac * work->ww[j].f[i];
#endif
        edmi__commit(sys, work, sub.tank);
        pos += units;
        while (level > 1 && pos % (2 * units) == 0) { /* back to longer substeps */
            level--;
            units *= 2;
        }
    }
    res->iterations = iterations;
    res->halvings = halvings;
    edmi__split_works(sys, res, wx, wa);
    edmi__store_forces(sys, work, 1);
    return EDMI_OK;
}

/* ==========================================================================================
 * The step
 *
 * edmi_step validates, prepares the links, attempts, and commits only on success: a failing
 * call leaves the system bit-identical. edmi_residual and edmi_tangent expose what Newton
 * evaluates, for tests.
 * ======================================================================================== */

edmi_status edmi_step(edmi_system *sys, edmi_workspace *work, edmi_real dt,
                      edmi_step_result *res)
{
    edmi_step_result local;
    edmi_status st;
    if (!res)
        res = &local;
    edmi__clear_result(res);
    if (!sys || !work)
        return EDMI_ERR_NULL;
    st = edmi__validate(sys, dt);
    if (st != EDMI_OK)
        return st;
    st = edmi__prepare_links(sys, work); /* the start state's links: refused as input */
    if (st != EDMI_OK)
        return st;
    /* the factors this system's last step kept here (work->kept_sys is read only where this
     * system wrote it); nothing a later call trusts unless this one stores the step */
    work->kept = sys->internal.kept_work == (const void *)work &&
                 work->kept_sys == (const void *)sys && sys->internal.kept_dt == dt &&
                 sys->internal.kept_bodies == sys->n_bodies &&
                 sys->internal.kept_links == sys->n_links && edmi__kept_sane(sys, work);
    work->fresh = 0;
    work->kept_sys = 0;
    st = edmi__attempt(sys, work, dt, res);
    if (st == EDMI_OK) {
        edmi__commit(sys, work, res->tank);
        edmi__store_forces(sys, work, 0);
        res->substeps = 1;
        if (work->kept || work->fresh) {
            work->kept_sys = sys;
            sys->internal.kept_work = work;
            sys->internal.kept_dt = dt;
            sys->internal.kept_bodies = sys->n_bodies;
            sys->internal.kept_links = sys->n_links;
        }
    } else {
        if (!edmi__is_step_failure(st) ||
            (sys->params.substep_levels == 0 && !sys->params.fallback))
            return st;
        st = edmi__substeps(sys, work, dt, res, st);
        if (st != EDMI_OK)
            return st;
    }
    edmi__advance_clock(sys, dt);
    return EDMI_OK;
}

static edmi_status edmi__check_trial(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                     const void *q1, const void *p1)
{
    edmi_status st;
    if (!sys || !work || !q1 || !p1)
        return EDMI_ERR_NULL;
    st = edmi__validate(sys, dt);
    if (st != EDMI_OK)
        return st;
    return edmi__prepare_links(sys, work);
}

edmi_status edmi_residual(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                          const edmi_real (*q1)[3], const edmi_real (*p1)[3],
                          edmi_real (*rq)[3], edmi_real (*rp)[3], int *lg_switches)
{
    int a;
    edmi_status st = edmi__check_trial(sys, work, dt, q1, p1);
    if (st != EDMI_OK)
        return st;
    if (!rq || !rp)
        return EDMI_ERR_NULL;
    st = edmi__residual(sys, work, dt, q1, p1, work->rq, work->rp, lg_switches);
    if (st != EDMI_OK) /* the caller's arrays stay untouched */
        return st;
    for (a = 0; a < sys->n_bodies; a++) {
        edmi__copy3(work->rq[a], rq[a]);
        edmi__copy3(work->rp[a], rp[a]);
    }
    return EDMI_OK;
}

edmi_status edmi_tangent(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                         const edmi_real (*q1)[3], const edmi_real (*p1)[3], edmi_real *kmat)
{
    edmi_real lim, kl[9];
    int n, i, j;
    edmi_status st = edmi__check_trial(sys, work, dt, q1, p1);
    if (st != EDMI_OK)
        return st;
    if (!kmat)
        return EDMI_ERR_NULL;
    st = edmi__residual(sys, work, dt, q1, p1, work->rq, work->rp, 0);
    if (st != EDMI_OK)
        return st;
    /* every block within REAL_MAX / (number of blocks), so no sum of them overflows: kmat is
     * written only when all of it is finite */
    lim = EDMI_REAL_MAX / (EDMI_R(2.0) * (edmi_real)(sys->n_links + EDMI__N_DAMPERS(sys) +
                                                      EDMI__N_WALLS(sys) + 1));
    for (j = 0; j < sys->n_links + EDMI__N_DAMPERS(sys) + EDMI__N_WALLS(sys); j++) {
        const edmi_real *k = kl;
        if (j < sys->n_links)
            edmi__link_tangent(&work->lw[j], dt, kl);
        else if (j < sys->n_links + EDMI__N_DAMPERS(sys))
            k = work->kd[j - sys->n_links];
#if EDMI_MAX_WALLS > 0
        else
            edmi__wall_tangent(&sys->wall[j - sys->n_links - EDMI__N_DAMPERS(sys)],
                               &work->ww[j - sys->n_links - EDMI__N_DAMPERS(sys)], dt, kl);
#endif
        for (i = 0; i < 9; i++)
            if (!(edmi__abs(k[i]) <= lim))
                return EDMI_ERR_OVERFLOW;
    }
    n = 3 * sys->n_bodies;
    work->kept_sys = 0; /* work->row is overwritten */
    for (i = 0; i < n * n; i++)
        kmat[i] = EDMI__ZERO;
    for (i = 0; i < n; i++) /* kmat is dense, row-major */
        work->row[i] = i * n;
    for (j = 0; j < sys->n_links; j++) {
        edmi__link_tangent(&work->lw[j], dt, kl);
        edmi__scatter(kmat, work->row, &sys->link[j], kl, EDMI__ONE, EDMI__ONE);
    }
#if EDMI_MAX_DAMPERS > 0
    for (j = 0; j < EDMI__N_DAMPERS(sys); j++)
        edmi__scatter(kmat, work->row, &sys->link[sys->damper[j].link], work->kd[j], EDMI__ONE,
                      EDMI__ONE);
#endif
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < EDMI__N_WALLS(sys); j++) {
        edmi__wall_tangent(&sys->wall[j], &work->ww[j], dt, kl);
        edmi__scatter_anchor(kmat, work->row, sys->wall[j].a, kl, EDMI__ONE);
    }
#endif
    return EDMI_OK;
}

/* ==========================================================================================
 * Building a system, and scenes
 *
 * The validator every entry point calls first (edmi_step, edmi_invariants_of, edmi_residual,
 * edmi_tangent, and the builders before they write), then the builders and the scene loader.
 * ======================================================================================== */

/* Parameters in range (else EDMI_ERR_PARAM) and a scheme and LG form this build carries. */
static edmi_status edmi__params_valid(const edmi_params *p)
{
    int ok = (p->scheme == EDMI_SCHEME_MP || p->scheme == EDMI_SCHEME_LG ||
              p->scheme == EDMI_SCHEME_GE || p->scheme == EDMI_SCHEME_PM ||
              p->scheme == EDMI_SCHEME_PT) &&
           (p->lg_form == EDMI_LG_CLOSED || p->lg_form == EDMI_LG_QUOTIENT) &&
           (p->lg_alt == EDMI_LG_ALT_JANZ || p->lg_alt == EDMI_LG_ALT_GONZALEZ ||
            p->lg_alt == EDMI_LG_ALT_GE || p->lg_alt == EDMI_LG_ALT_PM ||
            p->lg_alt == EDMI_LG_ALT_PT) &&
           edmi__finite(p->tol_q) && p->tol_q > EDMI__ZERO && edmi__finite(p->tol_r) &&
           p->tol_r >= EDMI__ZERO && edmi__finite(p->tol_a) && p->tol_a >= EDMI__ZERO &&
           p->l_max >= 1 && edmi__finite(p->tank_cap) && p->tank_cap >= EDMI__ZERO &&
           p->substep_levels >= 0 && p->substep_levels <= EDMI_MAX_SUBSTEP_LEVELS &&
           (p->guard == EDMI_GUARD_AUTO || p->guard == EDMI_GUARD_ON ||
            p->guard == EDMI_GUARD_OFF);
    if (!ok)
        return EDMI_ERR_PARAM;
    if (!EDMI__HAS_SCHEME(p->scheme) ||
        (!EDMI_WITH_LG_QUOTIENT && p->scheme == EDMI_SCHEME_LG && p->lg_form == EDMI_LG_QUOTIENT) ||
        (!EDMI_WITH_GUARD && p->guard == EDMI_GUARD_ON))
        return EDMI_ERR_DISABLED;
    return EDMI_OK;
}

/* Body a exists; b is an anchor or another existing body. */
static int edmi__link_ends_valid(int n_bodies, int a, int b)
{
    return a >= 0 && a < n_bodies && (b == EDMI_ANCHOR || (b >= 0 && b < n_bodies && b != a));
}

/* The rules for one body, one link and one damper, shared by every path that takes them in:
 * the builders (edmi_add_*), the scene loader and the check of a system before a step. */
static EDMI__INLINE edmi_status edmi__body_valid(edmi_real m, const edmi_real q[3],
                                                 const edmi_real p[3])
{
    if (!edmi__finite(m) || !(m > EDMI__ZERO))
        return EDMI_ERR_MASS;
    return edmi__finite3(q) && edmi__finite3(p) ? EDMI_OK : EDMI_ERR_NONFINITE;
}

static EDMI__INLINE edmi_status edmi__link_valid(int n_bodies, int a, int b,
                                                 const edmi_potential *pot,
                                                 const edmi_real x[3])
{
    edmi_status st;
    if (!edmi__link_ends_valid(n_bodies, a, b))
        return EDMI_ERR_INDEX;
    st = edmi__pot_check(pot);
    if (st != EDMI_OK)
        return st;
    return edmi__finite3(x) ? EDMI_OK : EDMI_ERR_NONFINITE;
}

static edmi_status edmi__damper_valid(int n_links, int link, edmi_real c)
{
    if (link < 0 || link >= n_links)
        return EDMI_ERR_INDEX;
    return edmi__finite(c) && c >= EDMI__ZERO ? EDMI_OK : EDMI_ERR_PARAM;
}

/* The bodies, then the links, of a system or a scene: the first refusal. */
static edmi_status edmi__bodies_links_valid(int n_bodies, const edmi_body *body, int n_links,
                                            const edmi_link *link)
{
    int i;
    for (i = 0; i < n_bodies; i++) {
        edmi_status st = edmi__body_valid(body[i].m, body[i].q, body[i].p);
        if (st != EDMI_OK)
            return st;
    }
    for (i = 0; i < n_links; i++) {
        const edmi_link *lk = &link[i];
        edmi_status st = edmi__link_valid(n_bodies, lk->a, lk->b, &lk->pot, lk->anchor);
        if (st != EDMI_OK)
            return st;
    }
    return EDMI_OK;
}

#if EDMI_MAX_WALLS > 0
/* A wall body a may take: a body, n finite and not 0 (unit once stored), c finite, and a
 * potential of the gap (edmi_wall): harmonic, contact or tether, a > 0 and b >= 0 finite. */
static edmi_status edmi__wall_valid(int n_bodies, int a, const edmi_real n[3], edmi_real c,
                                    const edmi_potential *pot)
{
    if (a < 0 || a >= n_bodies)
        return EDMI_ERR_INDEX;
    if (!edmi__finite3(n) || !edmi__finite(c))
        return EDMI_ERR_NONFINITE;
    if ((n[0] == EDMI__ZERO && n[1] == EDMI__ZERO && n[2] == EDMI__ZERO) ||
        (pot->kind != EDMI_POT_HARMONIC && pot->kind != EDMI_POT_CONTACT &&
         pot->kind != EDMI_POT_TETHER) ||
        !edmi__finite(pot->a) || !edmi__finite(pot->b) || !(pot->a > EDMI__ZERO) ||
        !(pot->b >= EDMI__ZERO))
        return EDMI_ERR_PARAM;
    return EDMI__HAS_POT(pot->kind) ? EDMI_OK : EDMI_ERR_DISABLED;
}
#endif

/* The effects beyond links: dampers on existing links, ports on existing bodies, finite. */
static edmi_status edmi__validate_effects(const edmi_system *sys)
{
    int i;
    for (i = 0; i < EDMI__N_DAMPERS(sys); i++) {
        edmi_status st = edmi__damper_valid(sys->n_links, sys->damper[i].link, sys->damper[i].c);
        if (st != EDMI_OK)
            return st;
    }
#if EDMI_MAX_WALLS > 0
    for (i = 0; i < EDMI__N_WALLS(sys); i++) {
        const edmi_wall *wl = &sys->wall[i];
        edmi_status st = edmi__wall_valid(sys->n_bodies, wl->a, wl->n, wl->c, &wl->pot);
        if (st != EDMI_OK)
            return st;
        if (!edmi__finite(sys->internal.wall_next[i]))
            return EDMI_ERR_NONFINITE;
    }
#endif
    if ((!EDMI_WITH_PORTS && sys->internal.n_forced != 0) || (!EDMI_WITH_FIELD && sys->has_field))
        return EDMI_ERR_DISABLED;
    for (i = 0; i < EDMI__N_FORCED(sys); i++) {
        int b = sys->internal.forced[i];
        if (b < 0 || b >= sys->n_bodies)
            return EDMI_ERR_INDEX;
        if (!edmi__finite3(sys->force[b]))
            return EDMI_ERR_NONFINITE;
    }
    for (i = 0; i < sys->internal.n_moving; i++) {
        int j = sys->internal.moving[i];
        if (j < 0 || j >= sys->n_links || sys->link[j].b != EDMI_ANCHOR)
            return EDMI_ERR_INDEX;
        if (!edmi__finite3(sys->internal.anchor_next[j]))
            return EDMI_ERR_NONFINITE;
    }
    if (EDMI__HAS_FIELD(sys) && !edmi__finite3(sys->g))
        return EDMI_ERR_NONFINITE;
    if (!edmi__finite(sys->t) || !edmi__finite(sys->internal.t_carry) || !edmi__finite(sys->tank))
        return EDMI_ERR_NONFINITE;
    return sys->tank >= EDMI__ZERO ? EDMI_OK : EDMI_ERR_PARAM;
}

/* The counts every entry point relies on before it indexes an array: a caller that wrote
 * sys->n_bodies etc. out of range gets EDMI_ERR_CORRUPT, not an access out of bounds. */
static int edmi__counts_valid(const edmi_system *sys)
{
    return sys->n_bodies >= 0 && sys->n_bodies <= EDMI_MAX_BODIES && sys->n_links >= 0 &&
           sys->n_links <= EDMI_MAX_LINKS && sys->n_dampers >= 0 &&
           sys->n_dampers <= EDMI_MAX_DAMPERS && EDMI__N_WALLS(sys) >= 0 &&
           EDMI__N_WALLS(sys) <= EDMI_MAX_WALLS && sys->internal.n_forced >= 0 &&
           sys->internal.n_forced <= sys->n_bodies && sys->internal.n_moving >= 0 &&
           sys->internal.n_moving <= sys->n_links;
}

/* A Newton matrix store smaller than the dense one of EDMI_MAX_BODIES is checked where the
 * system can outgrow it; the default (dense) holds every system and is never checked. */
#define EDMI__MATRIX_BOUNDED (EDMI_MAX_MATRIX < 9L * EDMI_MAX_BODIES * EDMI_MAX_BODIES)

/* The system as a whole: what edmi_step and edmi_invariants_of check before they read it. */
static edmi_status edmi__validate_system(const edmi_system *sys)
{
    edmi_status st;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    if (EDMI__MATRIX_BOUNDED && !edmi__matrix_fits(sys->n_bodies, edmi__max_gap(sys)))
        return EDMI_ERR_CAPACITY;
    st = edmi__params_valid(&sys->params);
    if (st != EDMI_OK)
        return st;
    st = edmi__bodies_links_valid(sys->n_bodies, sys->body, sys->n_links, sys->link);
    if (st != EDMI_OK)
        return st;
    if (!EDMI_WITH_LG_QUOTIENT && EDMI__HAS_SCHEME(EDMI_SCHEME_LG) &&
        EDMI__HAS_POT(EDMI_POT_USER) && sys->params.scheme == EDMI_SCHEME_LG) {
        int j; /* LG's closed form needs a user potential's divided difference */
        for (j = 0; j < sys->n_links; j++)
            if (sys->link[j].pot.kind == EDMI_POT_USER && sys->link[j].pot.dd == 0)
                return EDMI_ERR_DISABLED;
    }
#if EDMI_MAX_MASS_GAP > 0
    {
        int i, k;
        for (i = 1; i < sys->n_bodies; i++)
            for (k = 0; k < EDMI_MAX_MASS_GAP && k < i; k++)
                if (!edmi__finite(sys->mass_off[i][k]))
                    return EDMI_ERR_NONFINITE;
    }
    if (EDMI__COUPLED(sys) && !edmi__mass_provable(sys))
        return EDMI_ERR_MASS; /* a mass written since: M no longer provably definite */
#endif
    return edmi__validate_effects(sys);
}

/* Everything edmi_step checks before it touches anything: the system, and a dt the clock
 * can take (t + dt finite: a clock at +inf would refuse every later step). */
static edmi_status edmi__validate(const edmi_system *sys, edmi_real dt)
{
    edmi_status st;
    if (!edmi__finite(dt) || !(dt > EDMI__ZERO))
        return EDMI_ERR_DT;
    st = edmi__validate_system(sys);
    if (st != EDMI_OK)
        return st;
    return edmi__finite(sys->t + (dt - sys->internal.t_carry)) ? EDMI_OK : EDMI_ERR_DT;
}

edmi_params edmi_default_params(void)
{
    edmi_params p;
    /* energy-safe: decays, never gains (docs/energy-safe.md); or the first decaying, then
     * conserving, scheme the build carries */
    p.scheme = EDMI_WITH_PM   ? EDMI_SCHEME_PM
               : EDMI_WITH_PT ? EDMI_SCHEME_PT
               : EDMI_WITH_GE ? EDMI_SCHEME_GE
               : EDMI_WITH_LG ? EDMI_SCHEME_LG
                              : EDMI_SCHEME_MP;
    p.lg_form = EDMI_LG_CLOSED;
    p.lg_alt = EDMI_LG_ALT_JANZ;
    p.l_max = 20;
    p.energy_balance = 0;
    p.guard = EDMI_GUARD_AUTO;
    p.tank_cap = EDMI__TANK_CAP;
    p.fallback = 0;
    p.substep_levels = 0;
    /* No tolerance to tune: Newton stops at its round-off floor in either precision
     * (edmi__newton). tol_r and tol_a are early stops for studies, off by default. */
    p.tol_r = EDMI__ZERO;
    p.tol_a = EDMI__ZERO;
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
    p.tol_q = EDMI_R(1e-8); /* the paper's section 3.4 value */
#else
    /* The LG quotient [V(d1)-V(d0)]/(d1-d0) loses eps |V| / |d1 - d0| to cancellation;
     * tol_q = 1e-3 keeps that below ~1e-4 relative for distances and potentials of order
     * one (the double default 1e-8 would let the quotient be pure round-off in float). */
    p.tol_q = EDMI_R(1e-3);
#endif
    return p;
}

edmi_status edmi_set_params(edmi_system *sys, const edmi_params *params)
{
    edmi_status st;
    if (!sys || !params)
        return EDMI_ERR_NULL;
    st = edmi__params_valid(params);
    if (st != EDMI_OK)
        return st;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    sys->params = *params;
    return EDMI_OK;
}

edmi_status edmi_init(edmi_system *sys, const edmi_params *params)
{
    edmi_params p = params ? *params : edmi_default_params();
    unsigned char *bytes;
    unsigned long i;
    edmi_status st;
    if (!sys)
        return EDMI_ERR_NULL;
    st = edmi__params_valid(&p);
    if (st != EDMI_OK)
        return st;
    /* Zero every byte (padding included) so that snapshots compare with memcmp. */
    bytes = (unsigned char *)sys;
    for (i = 0; i < (unsigned long)sizeof *sys; i++)
        bytes[i] = 0;
    sys->n_bodies = 0;
    sys->n_links = 0;
    sys->t = EDMI__ZERO;
    sys->params = p;
    return EDMI_OK;
}

/* Whether sys was set up by edmi_init or edmi_load_scene: its parameters are valid (a system
 * never set up, static or zeroed, has l_max 0 and tol_q 0). The builders refuse any other. */
static int edmi__set_up(const edmi_system *sys)
{
    return edmi__params_valid(&sys->params) != EDMI_ERR_PARAM;
}

edmi_status edmi_add_body(edmi_system *sys, edmi_real m, const edmi_real q[3],
                          const edmi_real p[3], int *index)
{
    edmi_body *bd;
    edmi_status st;
    if (!sys || !q || !p)
        return EDMI_ERR_NULL;
    if (!edmi__set_up(sys))
        return EDMI_ERR_UNINIT;
    st = edmi__body_valid(m, q, p);
    if (st != EDMI_OK)
        return st;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    if (sys->n_bodies >= EDMI_MAX_BODIES ||
        (EDMI__MATRIX_BOUNDED && !edmi__matrix_fits(sys->n_bodies + 1, edmi__max_gap(sys))))
        return EDMI_ERR_CAPACITY;
    bd = &sys->body[sys->n_bodies];
    bd->m = m;
    edmi__copy3(q, bd->q);
    edmi__copy3(p, bd->p);
    if (index)
        *index = sys->n_bodies;
    sys->n_bodies++;
    return EDMI_OK;
}

/* *src into *dst, member by member (a struct copy may become a call to memcpy). */
static void edmi__copy_pot(const edmi_potential *src, edmi_potential *dst)
{
    dst->kind = src->kind;
    dst->a = src->a;
    dst->b = src->b;
    dst->fn = src->fn;
    dst->dd = src->dd;
    dst->ctx = src->ctx;
}

/* Write a link field by field into zeroed storage: never copy a caller's padding bytes, so
 * that equal systems compare equal with memcmp (edmi_init zeroes every byte). */
static void edmi__write_link(edmi_link *dst, int a, int b, const edmi_real x[3],
                             const edmi_potential *pot)
{
    dst->a = a;
    dst->b = b;
    edmi__copy3(x, dst->anchor);
    edmi__copy_pot(pot, &dst->pot);
}

#if EDMI_MAX_WALLS > 0
/* A validated wall into dst, its normal stored as n / |n|. */
static void edmi__write_wall(edmi_wall *dst, int a, const edmi_real n[3], edmi_real c,
                             const edmi_potential *pot)
{
    edmi_real l = edmi__norm(n);
    int i;
    dst->a = a;
    for (i = 0; i < 3; i++)
        dst->n[i] = n[i] / l;
    dst->c = c;
    edmi__copy_pot(pot, &dst->pot);
}
#endif

static edmi_status edmi__add_link(edmi_system *sys, int a, int b, const edmi_real x[3],
                                  const edmi_potential *pot, int *index)
{
    static const edmi_real origin[3] = {EDMI__ZERO, EDMI__ZERO, EDMI__ZERO};
    edmi_status st;
    if (!sys || !pot || (b == EDMI_ANCHOR && !x))
        return EDMI_ERR_NULL;
    if (!edmi__set_up(sys))
        return EDMI_ERR_UNINIT;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    st = edmi__link_valid(sys->n_bodies, a, b, pot, x ? x : origin);
    if (st != EDMI_OK)
        return st;
    if (edmi__same3(sys->body[a].q, b == EDMI_ANCHOR ? x : sys->body[b].q) &&
        !edmi__is_linear(pot))
        return EDMI_ERR_COINCIDENT; /* the first step could not start */
    if (sys->n_links >= EDMI_MAX_LINKS)
        return EDMI_ERR_CAPACITY;
    if (EDMI__MATRIX_BOUNDED && b != EDMI_ANCHOR) {
        int gap = edmi__max_gap(sys), g = a > b ? a - b : b - a;
        if (!edmi__matrix_fits(sys->n_bodies, g > gap ? g : gap))
            return EDMI_ERR_CAPACITY;
    }
    edmi__write_link(&sys->link[sys->n_links], a, b, x ? x : origin, pot);
    if (index)
        *index = sys->n_links;
    sys->n_links++;
    return EDMI_OK;
}

edmi_status edmi_add_pair(edmi_system *sys, int a, int b, const edmi_potential *pot,
                          int *index)
{
    if (b == EDMI_ANCHOR)
        return sys ? EDMI_ERR_INDEX : EDMI_ERR_NULL;
    return edmi__add_link(sys, a, b, 0, pot, index);
}

edmi_status edmi_add_anchor(edmi_system *sys, int a, const edmi_real x[3],
                            const edmi_potential *pot, int *index)
{
    if (!x)
        return EDMI_ERR_NULL;
    return edmi__add_link(sys, a, EDMI_ANCHOR, x, pot, index);
}

edmi_status edmi_set_field(edmi_system *sys, const edmi_real g[3])
{
    if (!sys || !g)
        return EDMI_ERR_NULL;
    if (!EDMI_WITH_FIELD)
        return EDMI_ERR_DISABLED;
    if (!edmi__finite3(g))
        return EDMI_ERR_NONFINITE;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    edmi__copy3(g, sys->g);
    sys->has_field = 1;
    return EDMI_OK;
}

edmi_status edmi_add_damper(edmi_system *sys, int link, edmi_real c, int *index)
{
    edmi_status st;
    if (!sys)
        return EDMI_ERR_NULL;
    if (!edmi__set_up(sys))
        return EDMI_ERR_UNINIT;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    st = edmi__damper_valid(sys->n_links, link, c);
    if (st != EDMI_OK)
        return st;
    if (EDMI_MAX_DAMPERS == 0)
        return EDMI_ERR_DISABLED; /* dampers compiled out */
    if (EDMI__N_DAMPERS(sys) >= EDMI_MAX_DAMPERS)
        return EDMI_ERR_CAPACITY;
    sys->damper[sys->n_dampers].link = link;
    sys->damper[sys->n_dampers].c = c;
    if (index)
        *index = sys->n_dampers;
    sys->n_dampers++;
    return EDMI_OK;
}


edmi_status edmi_add_wall(edmi_system *sys, int a, const edmi_real n[3], edmi_real c,
                          const edmi_potential *pot, int *index)
{
    if (!sys || !n || !pot)
        return EDMI_ERR_NULL;
    if (!edmi__set_up(sys))
        return EDMI_ERR_UNINIT;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
#if EDMI_MAX_WALLS > 0
    {
        edmi_status st = edmi__wall_valid(sys->n_bodies, a, n, c, pot);
        if (st != EDMI_OK)
            return st;
    }
    if (sys->n_walls >= EDMI_MAX_WALLS)
        return EDMI_ERR_CAPACITY;
    edmi__write_wall(&sys->wall[sys->n_walls], a, n, c, pot);
    sys->internal.wall_next[sys->n_walls] = c;
    if (index)
        *index = sys->n_walls;
    sys->n_walls++;
    return EDMI_OK;
#else
    (void)a, (void)c, (void)index;
    return EDMI_ERR_DISABLED; /* walls compiled out */
#endif
}

edmi_status edmi_move_wall(edmi_system *sys, int w, edmi_real c_next)
{
    if (!sys)
        return EDMI_ERR_NULL;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
#if EDMI_MAX_WALLS > 0
    if (w < 0 || w >= sys->n_walls)
        return EDMI_ERR_INDEX;
    if (!edmi__finite(c_next))
        return EDMI_ERR_NONFINITE;
    sys->internal.wall_next[w] = c_next;
    return EDMI_OK;
#else
    (void)w, (void)c_next;
    return EDMI_ERR_DISABLED; /* walls compiled out */
#endif
}

edmi_status edmi_set_mass_coupling(edmi_system *sys, int a, int b, edmi_real m_ab)
{
#if EDMI_MAX_MASS_GAP > 0
    int hi, k, gap;
    edmi_real old;
    if (!sys)
        return EDMI_ERR_NULL;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    if (a < 0 || b < 0 || a >= sys->n_bodies || b >= sys->n_bodies || a == b)
        return EDMI_ERR_INDEX;
    if (!edmi__finite(m_ab))
        return EDMI_ERR_NONFINITE;
    gap = a > b ? a - b : b - a;
    if (gap > EDMI_MAX_MASS_GAP)
        return EDMI_ERR_CAPACITY;
    if (EDMI__MATRIX_BOUNDED && !edmi__matrix_fits(sys->n_bodies, gap))
        return EDMI_ERR_CAPACITY;
    hi = a > b ? a : b;
    k = gap - 1;
    old = sys->mass_off[hi][k];
    sys->mass_off[hi][k] = m_ab;
    if (!edmi__mass_provable(sys)) { /* not provably definite: put the old entry back */
        sys->mass_off[hi][k] = old;
        return EDMI_ERR_MASS;
    }
    return EDMI_OK;
#else
    (void)a;
    (void)b;
    (void)m_ab;
    return sys ? EDMI_ERR_CAPACITY : EDMI_ERR_NULL;
#endif
}

edmi_status edmi_set_tank(edmi_system *sys, edmi_real t)
{
    if (!sys)
        return EDMI_ERR_NULL;
    if (!edmi__finite(t))
        return EDMI_ERR_NONFINITE;
    if (t < EDMI__ZERO)
        return EDMI_ERR_PARAM;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    if (t > EDMI__ZERO && !(sys->params.tank_cap > EDMI__ZERO))
        return EDMI_ERR_PARAM; /* the per-step form keeps no tank */
    sys->tank = t;
    return EDMI_OK;
}

edmi_status edmi_move_anchor(edmi_system *sys, int link, const edmi_real x[3])
{
    int i;
    if (!sys || !x)
        return EDMI_ERR_NULL;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    if (link < 0 || link >= sys->n_links || sys->link[link].b != EDMI_ANCHOR)
        return EDMI_ERR_INDEX;
    if (!edmi__finite3(x))
        return EDMI_ERR_NONFINITE;
    for (i = 0; i < sys->internal.n_moving && sys->internal.moving[i] != link; i++)
        ;
    if (i == sys->internal.n_moving && i >= EDMI_MAX_LINKS) /* a list the caller overwrote */
        return EDMI_ERR_CORRUPT;
    if (i == sys->internal.n_moving)
        sys->internal.moving[sys->internal.n_moving++] = link;
    edmi__copy3(x, sys->internal.anchor_next[link]);
    return EDMI_OK;
}

edmi_status edmi_set_force(edmi_system *sys, int a, const edmi_real f[3])
{
    int i;
    if (!sys || !f)
        return EDMI_ERR_NULL;
    if (!EDMI_WITH_PORTS)
        return EDMI_ERR_DISABLED;
    if (!edmi__counts_valid(sys))
        return EDMI_ERR_CORRUPT;
    if (a < 0 || a >= sys->n_bodies)
        return EDMI_ERR_INDEX;
    if (!edmi__finite3(f))
        return EDMI_ERR_NONFINITE;
    for (i = 0; i < sys->internal.n_forced && sys->internal.forced[i] != a; i++)
        ;
    if (i == sys->internal.n_forced && i >= EDMI_MAX_BODIES) /* a list the caller overwrote */
        return EDMI_ERR_CORRUPT;
    if (i == sys->internal.n_forced)
        sys->internal.forced[sys->internal.n_forced++] = a;
    edmi__copy3(f, sys->force[a]);
    return EDMI_OK;
}

#if EDMI_WITH_SCENE
/* Everything edmi_load_scene checks before it writes: counts, parameters, bodies, links (a
 * link whose ends meet with a potential undefined there is refused, as edmi_add_pair does),
 * the mass couplings, the Newton matrix's store and the dampers. */
static edmi_status edmi__scene_valid(const edmi_scene *scene, const edmi_params *p)
{
    edmi_status st;
    int i, gap = 0;
    if (scene->n_bodies < 0 || scene->n_links < 0 || scene->n_dampers < 0 ||
        scene->n_mass_couplings < 0)
        return EDMI_ERR_PARAM;
    if (scene->n_bodies > EDMI_MAX_BODIES || scene->n_links > EDMI_MAX_LINKS ||
        scene->n_dampers > EDMI_MAX_DAMPERS)
        return EDMI_ERR_CAPACITY;
    st = edmi__params_valid(p);
    if (st != EDMI_OK)
        return st;
    if (scene->has_field && !EDMI_WITH_FIELD)
        return EDMI_ERR_DISABLED;
    if (scene->has_field && !edmi__finite3(scene->g))
        return EDMI_ERR_NONFINITE;
    st = edmi__bodies_links_valid(scene->n_bodies, scene->bodies, scene->n_links, scene->links);
    if (st != EDMI_OK)
        return st;
    for (i = 0; i < scene->n_links; i++) {
        const edmi_link *lk = &scene->links[i];
        const edmi_real *xb = lk->b == EDMI_ANCHOR ? lk->anchor : scene->bodies[lk->b].q;
        if (edmi__same3(scene->bodies[lk->a].q, xb) && !edmi__is_linear(&lk->pot))
            return EDMI_ERR_COINCIDENT; /* the first step could not start */
        if (lk->b != EDMI_ANCHOR && (lk->a > lk->b ? lk->a - lk->b : lk->b - lk->a) > gap)
            gap = lk->a > lk->b ? lk->a - lk->b : lk->b - lk->a;
    }
    /* at most one entry per pair within the gap: N G of them */
    if (scene->n_mass_couplings > EDMI_MAX_BODIES * EDMI_MAX_MASS_GAP)
        return EDMI_ERR_CAPACITY;
#if EDMI_MAX_MASS_GAP > 0
    if (scene->n_mass_couplings > 0 && !scene->mass_couplings)
        return EDMI_ERR_NULL;
    for (i = 0; i < scene->n_mass_couplings; i++) {
        const edmi_mass_coupling *c = &scene->mass_couplings[i];
        int j, d;
        if (c->a < 0 || c->b < 0 || c->a >= scene->n_bodies || c->b >= scene->n_bodies ||
            c->a == c->b)
            return EDMI_ERR_INDEX;
        d = c->a > c->b ? c->a - c->b : c->b - c->a;
        if (!edmi__finite(c->m))
            return EDMI_ERR_NONFINITE;
        if (d > EDMI_MAX_MASS_GAP)
            return EDMI_ERR_CAPACITY;
        for (j = 0; j < i; j++) { /* each pair once */
            const edmi_mass_coupling *e = &scene->mass_couplings[j];
            if ((e->a == c->a && e->b == c->b) || (e->a == c->b && e->b == c->a))
                return EDMI_ERR_PARAM;
        }
        gap = d > gap ? d : gap;
    }
#endif
    if (EDMI__MATRIX_BOUNDED && !edmi__matrix_fits(scene->n_bodies, gap))
        return EDMI_ERR_CAPACITY;
#if EDMI_MAX_MASS_GAP > 0
    if (scene->n_mass_couplings > 0 &&
        !(edmi__mass_lambda_min(scene->n_bodies, scene->bodies, edmi__off_scene, scene) >
          EDMI__ZERO))
        return EDMI_ERR_MASS; /* M not provably positive definite */
#endif
    for (i = 0; i < EDMI__N_DAMPERS(scene); i++) {
        st = edmi__damper_valid(scene->n_links, scene->dampers[i].link, scene->dampers[i].c);
        if (st != EDMI_OK)
            return st;
    }
    return EDMI_OK;
}

/* Replace the system by a validated scene. */
static void edmi__scene_write(edmi_system *sys, const edmi_scene *scene, const edmi_params *p)
{
    int i;
    (void)edmi_init(sys, p);
    for (i = 0; i < scene->n_bodies; i++) {
        const edmi_body *bd = &scene->bodies[i];
        sys->body[i].m = bd->m;
        edmi__copy3(bd->q, sys->body[i].q);
        edmi__copy3(bd->p, sys->body[i].p);
    }
    for (i = 0; i < scene->n_links; i++) {
        const edmi_link *lk = &scene->links[i];
        edmi__write_link(&sys->link[i], lk->a, lk->b, lk->anchor, &lk->pot);
    }
    for (i = 0; i < EDMI__N_DAMPERS(scene); i++) {
        sys->damper[i].link = scene->dampers[i].link;
        sys->damper[i].c = scene->dampers[i].c;
    }
    sys->n_bodies = scene->n_bodies;
    sys->n_links = scene->n_links;
    sys->n_dampers = scene->n_dampers;
#if EDMI_MAX_MASS_GAP > 0
    for (i = 0; i < scene->n_mass_couplings; i++) {
        const edmi_mass_coupling *c = &scene->mass_couplings[i];
        int hi = c->a > c->b ? c->a : c->b;
        sys->mass_off[hi][(c->a > c->b ? c->a - c->b : c->b - c->a) - 1] = c->m;
    }
#endif
    if (EDMI_WITH_FIELD && scene->has_field) {
        sys->has_field = 1;
        edmi__copy3(scene->g, sys->g);
    }
}
#endif

edmi_status edmi_load_scene(edmi_system *sys, const edmi_scene *scene)
{
#if !EDMI_WITH_SCENE
    if (!sys || !scene)
        return EDMI_ERR_NULL;
    return EDMI_ERR_DISABLED;
#else
    edmi_params p;
    edmi_status st;
    if (!sys || !scene || (scene->n_bodies > 0 && !scene->bodies) ||
        (scene->n_links > 0 && !scene->links) || (scene->n_dampers > 0 && !scene->dampers))
        return EDMI_ERR_NULL;
    p = scene->params ? *scene->params : edmi_default_params();
    st = edmi__scene_valid(scene, &p);
    if (st != EDMI_OK)
        return st;
    edmi__scene_write(sys, scene, &p);
    return EDMI_OK;
#endif
}

/* ==========================================================================================
 * Invariants
 *
 * H = K + V, J, L, C(t) (sections 2 and 4.1).
 * ======================================================================================== */

static int edmi__invariants_finite(const edmi_invariants *v)
{
    return edmi__finite(v->h) && edmi__finite(v->k) && edmi__finite(v->v) &&
           edmi__finite3(v->j) && edmi__finite3(v->l) && edmi__finite3(v->c);
}

edmi_status edmi_invariants_of(const edmi_system *sys, edmi_invariants *out)
{
    edmi_invariants iv;
    edmi_real mass = EDMI__ZERO, mq[3] = {EDMI__ZERO, EDMI__ZERO, EDMI__ZERO};
    edmi_status st;
    int a, i;
    if (!sys || !out)
        return EDMI_ERR_NULL;
    st = edmi__validate_system(sys);
    if (st != EDMI_OK)
        return st;
    iv.k = EDMI__ZERO;
    iv.v = EDMI__ZERO;
    for (i = 0; i < 3; i++)
        iv.j[i] = iv.l[i] = EDMI__ZERO;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi_real jq[3];
        edmi_real mrow = edmi__mass_row(sys, a);
        iv.k += EDMI__HALF * edmi__dot(bd->p, bd->p) / bd->m;
        edmi__cross(bd->q, bd->p, jq);
        for (i = 0; i < 3; i++) {
            iv.j[i] += jq[i];
            iv.l[i] += bd->p[i];
            mq[i] += mrow * bd->q[i]; /* sum over a of (M q)_a, M symmetric */
        }
        mass += mrow;
    }
#if EDMI_MAX_MASS_GAP > 0
    if (EDMI__COUPLED(sys) && !edmi__mass_cholesky(sys, &iv.k))
        return EDMI_ERR_MASS;
#endif
    for (a = 0; a < sys->n_links; a++) {
        const edmi_link *lk = &sys->link[a];
        edmi_real r[3], d;
        edmi_pot_parts pp;
        edmi__link_vector(sys, lk, r);
        d = edmi__norm(r);
        if (!(d > EDMI__ZERO) && !(d == EDMI__ZERO && edmi__is_linear(&lk->pot)))
            return EDMI_ERR_COINCIDENT;
        st = edmi__pot_parts(&lk->pot, d, &pp, 1);
        if (st != EDMI_OK)
            return st;
        iv.v += pp.v[0];
    }
#if EDMI_MAX_WALLS > 0
    for (a = 0; a < EDMI__N_WALLS(sys); a++) {
        const edmi_wall *wl = &sys->wall[a];
        edmi_pot_parts pp;
        st = edmi__pot_parts(&wl->pot, edmi__wall_gap(wl, sys->body[wl->a].q, wl->c), &pp, 0);
        if (st != EDMI_OK)
            return st;
        iv.v += pp.v[0];
    }
#endif
    if (EDMI__HAS_FIELD(sys))
        for (a = 0; a < sys->n_bodies; a++)
            iv.v -= edmi__mass_row(sys, a) * edmi__dot(sys->g, sys->body[a].q);
    iv.h = iv.k + iv.v;
    for (i = 0; i < 3; i++)
        iv.c[i] = mass > EDMI__ZERO ? (mq[i] - sys->t * iv.l[i]) / mass : EDMI__ZERO;
    if (!edmi__invariants_finite(&iv)) /* beyond the precision's range */
        return EDMI_ERR_OVERFLOW;
    out->h = iv.h; /* field by field: a struct copy would need memcpy from the C library */
    out->k = iv.k;
    out->v = iv.v;
    edmi__copy3(iv.j, out->j);
    edmi__copy3(iv.l, out->l);
    edmi__copy3(iv.c, out->c);
    return EDMI_OK;
}

/* ==========================================================================================
 * Misc
 * ======================================================================================== */

const char *edmi_status_name(edmi_status s)
{
    switch (s) {
    case EDMI_OK: return "EDMI_OK";
    case EDMI_ERR_NULL: return "EDMI_ERR_NULL";
    case EDMI_ERR_DT: return "EDMI_ERR_DT";
    case EDMI_ERR_MASS: return "EDMI_ERR_MASS";
    case EDMI_ERR_NONFINITE: return "EDMI_ERR_NONFINITE";
    case EDMI_ERR_CAPACITY: return "EDMI_ERR_CAPACITY";
    case EDMI_ERR_INDEX: return "EDMI_ERR_INDEX";
    case EDMI_ERR_PARAM: return "EDMI_ERR_PARAM";
    case EDMI_ERR_COINCIDENT: return "EDMI_ERR_COINCIDENT";
    case EDMI_ERR_SINGULAR: return "EDMI_ERR_SINGULAR";
    case EDMI_ERR_NO_CONVERGENCE: return "EDMI_ERR_NO_CONVERGENCE";
    case EDMI_ERR_DIVERGED: return "EDMI_ERR_DIVERGED";
    case EDMI_ERR_PASSIVITY: return "EDMI_ERR_PASSIVITY";
    case EDMI_ERR_RANGE: return "EDMI_ERR_RANGE";
    case EDMI_ERR_DISABLED: return "EDMI_ERR_DISABLED";
    case EDMI_ERR_UNINIT: return "EDMI_ERR_UNINIT";
    case EDMI_ERR_CORRUPT: return "EDMI_ERR_CORRUPT";
    case EDMI_ERR_OVERFLOW: return "EDMI_ERR_OVERFLOW";
    case EDMI_ERR_END_STATE: return "EDMI_ERR_END_STATE";
    case EDMI_ERR_DOMAIN: return "EDMI_ERR_DOMAIN";
    default: return "EDMI_ERR_UNKNOWN";
    }
}

int edmi_is_double_precision(void) { return EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_; }

int edmi_config_matches(unsigned long system_size, unsigned long workspace_size)
{
    return system_size == (unsigned long)sizeof(edmi_system) &&
           workspace_size == (unsigned long)sizeof(edmi_workspace);
}
