/* The passivity inequality on stored states, checked in tp_q (__float128 on the x86-64 host,
 * long double elsewhere), and the adversarial scenes of the guard's suite and soak (see
 * passive.h).
 *
 * Independence. The library certifies H(q_n+1, p_n+1) - H(q_n, p_n) <= work_ext +
 * work_anchor with its own double-word evaluation. The check here shares none of that code:
 * it evaluates each link's V(|q_a - x_b|) of both stored states in tp_q from the potentials'
 * textbook formulas and each body's kinetic change as (p1 - p0).(p1 + p0)/2m, subtracts term
 * by term, and bounds its own rounding by TP_ERR_ULPS units of tp_q's epsilon times the
 * terms' magnitudes M (tp_pot: M u bounds a term's error, u = eps/2; the factor 16 eps = 32 u
 * covers the dozen roundings along each formula and the sums over terms).
 *
 * Resolution. The library's double-word certificates leave a double state margins of ~eps^2
 * of H's terms (1e-32), so the check must resolve below that to judge a double step. On the
 * x86-64 host tp_q is __float128 (113-bit significand, libgcc's soft arithmetic, no
 * libquadmath): 16 eps = 3e-33 of the terms, below both float's grid (~6e-8 of the terms per
 * unit of a coordinate) and the double certificates' margins. Where there is no __float128
 * tp_q is long double: on the Arm targets that is double, so float states are still resolved
 * (~4e-15) but double states only to about their own grid, which is what the counts of
 * unresolved steps report. Define TP_NO_FLOAT128 for long double on the host too (x87: 64
 * bits, ~1e-18 of the terms). The public interface (passive.h) reports in long double:
 * values are rounded once at the end (binary128 to x87 keeps the sign and the exponent
 * range), and every comparison of the inequality is made in tp_q before that (tp_delta's
 * broken and unresolved).
 *
 * Cost. Soft binary128 costs about as much as a ten-body step; tp_h_dw and tp_delta_dw (the
 * fast path, below) give tp_delta_h's decisions from binary64 double-word arithmetic with a
 * proved error bound wherever that bound settles them, for edmi-sim's check of every step. */
#include "passive.h"

#include <float.h>
#include <string.h>
#if defined(__SIZEOF_FLOAT128__) && defined(__x86_64__) /* the fast path's flags (TP_FAST) */
#include <fenv.h>
#endif

/* ---- the check's arithmetic: tp_q -----------------------------------------------------------
 * __float128 where GCC or clang offers it on x86-64 with an x87 long double (the seed of
 * tp_sqrtq, and a range as wide as binary128's: 2^-16382 is both types' smallest normal);
 * long double otherwise. TP_Q_EPS: the type's epsilon (2^-112, FLT128_EPSILON, built from
 * exact powers of two: C99 has no Q suffix); TP_Q_MIN: its smallest normal. */
#if defined(__SIZEOF_FLOAT128__) && defined(__x86_64__) && LDBL_MANT_DIG == 64 && \
    LDBL_MIN_EXP == -16381 && !defined(TP_NO_FLOAT128)
__extension__ typedef __float128 tp_q;
#define TP_QUAD 1
#define TP_Q_EPS ((tp_q)1.0 / ((tp_q)72057594037927936.0 * (tp_q)72057594037927936.0))
#define TP_Q_MIN ((tp_q)LDBL_MIN)
#else
typedef long double tp_q;
#define TP_QUAD 0
#define TP_Q_EPS LDBL_EPSILON
#define TP_Q_MIN LDBL_MIN
#endif

#define TP_ERR_ULPS ((tp_q)16.0)

/* The fast path (tp_delta_dw): binary64 double-word arithmetic, round to nearest, no excess
 * precision (SSE2 on x86-64), and the floating-point status flags of <fenv.h> to see that no
 * operation underflowed or overflowed; where tp_q is __float128 only (elsewhere tp_q is fast
 * already, or double itself). */
#if TP_QUAD && FLT_EVAL_METHOD == 0 && DBL_MANT_DIG == 53 && defined(FE_UNDERFLOW) && \
    defined(FE_OVERFLOW) && defined(FE_INVALID) && defined(FE_DIVBYZERO) && defined(FE_TONEAREST)
#define TP_FAST 1
#else
#define TP_FAST 0
#endif

const char *tp_q_name(void) { return TP_QUAD ? "__float128" : "long double"; }

long double tp_q_eps(void) { return (long double)TP_Q_EPS; }

static long double tp_absl(long double x) { return x < 0.0L ? -x : x; }

static tp_q tp_absq(tp_q x) { return x < (tp_q)0.0 ? -x : x; }

static long double tp_sqrtl(long double x) { return x > 0.0L ? __builtin_sqrtl(x) : 0.0L; }

/* sqrt(x) in tp_q, 0 for x <= 0. Long double: sqrtl, correctly rounded (within u = eps/2 of
 * the result). binary128: faithfully rounded, within 0.5001 units in the last place (so
 * within u of the result): the seed y = sqrtl(x) has 64 bits and errs by e <= 1.5 2^-64 (x
 * rounded to 64 bits, then sqrtl); split (Veltkamp, in long double: y (2^32 + 1) does not
 * overflow) into h + l of at most 32 bits each, h^2, 2hl and l^2 are exact in 113 bits and
 * so is the residual r = ((x - h^2) - 2hl) - l^2 = x - y^2 (with y in [2^k, 2^k+1), every
 * partial difference is a multiple of 2^(2k-126) below 2^(2k-29): at most 97 bits). One
 * Newton step y + r/2y then errs by e^2/2 < 2^-127 relative before rounding, r/2y by u of
 * itself (< 2^-175 of the result), and the final sum by half a unit. Below 2^-16000, x is
 * scaled by 2^256 first (exact), so that the seed and the split stay normal. */
static tp_q tp_sqrtq(tp_q x)
{
#if TP_QUAD
    tp_q f = (tp_q)1.0, r, hq, lq;
    long double y, c, h, l;
    if (!(x > (tp_q)0.0))
        return (tp_q)0.0;
    if (x < (tp_q)LDBL_MIN * (tp_q)0x1p382) { /* 2^-16000 */
        x *= (tp_q)0x1p256;
        f = (tp_q)0x1p-128;
    }
    y = __builtin_sqrtl((long double)x);
    c = y * 4294967297.0L; /* 2^32 + 1 */
    h = c - (c - y);
    l = y - h;
    hq = (tp_q)h;
    lq = (tp_q)l;
    r = ((x - hq * hq) - (tp_q)2.0 * hq * lq) - lq * lq;
    return f * ((tp_q)y + r / ((tp_q)2.0 * (tp_q)y));
#else
    return x > 0.0L ? __builtin_sqrtl(x) : 0.0L;
#endif
}

/* V(d) of a built-in potential in tp_q, with s = d^2, and a magnitude M with
 * |computed V - V| <= M u (u = TP_Q_EPS/2) for the formula as written: each of its roundings
 * is at most u times an intermediate that M bounds, and the rounding of d itself (at most 4u
 * d after the link vector's difference, the sum of squares and the square root: 2.5u + u,
 * tp_sqrtq) moves V by |V'| 4u d, which M also bounds. Near a rest length V is small but
 * the rounding of d - rb is not, hence terms like |d - rb| (d + rb), with |d - rb| taken as
 * |x| + 4 eps (d + rb), x as computed: where the rounding of d hides all of x (x computed 0,
 * the true one ~1e-34 at d = 1 in binary128, ~1e-20 in x87 long double: V = k/2 x^2 seen as
 * 0), V's error is second order in it, a (4 eps d)^2, and M still bounds it. Only + - * / (no libm): LJ's t^6 by products.
 * A user potential is evaluated as the built-in one its callback computes (tp_user_builtin:
 * this file's callbacks and one a test registers); 0 for any other. */
static int tp_user_builtin(const edmi_potential *p, edmi_potential *b);

static int tp_pot(const edmi_potential *p, tp_q s, tp_q d, tp_q *v, tp_q *mag)
{
    tp_q a = (tp_q)p->a, b = (tp_q)p->b, x, t, xe;
    edmi_potential bp;
    switch (p->kind) {
    case EDMI_POT_HARMONIC: /* V' d = a |x| d (|a|: a user potential's k may be < 0) */
        x = d - b;
        xe = tp_absq(x) + (tp_q)4.0 * TP_Q_EPS * (d + tp_absq(b));
        *v = (tp_q)0.5 * a * x * x;
        *mag = (tp_q)4.0 * tp_absq(a) * xe * (d + tp_absq(b)) + (tp_q)4.0 * tp_absq(*v);
        return 1;
    case EDMI_POT_QUARTIC: /* V' d = a |x| s */
        x = s - b * b;
        xe = tp_absq(x) + (tp_q)8.0 * TP_Q_EPS * (s + b * b);
        *v = (tp_q)0.25 * a * x * x;
        *mag = (tp_q)4.0 * tp_absq(a) * xe * (s + b * b) + (tp_q)4.0 * tp_absq(*v);
        return 1;
    case EDMI_POT_NEO_HOOKE: /* V' d = a/3 |x| (d^2 + d b + b^2) / d */
        if (!(d > (tp_q)0.0))
            return 0;
        x = d - b;
        xe = tp_absq(x) + (tp_q)4.0 * TP_Q_EPS * (d + b);
        *v = a * x * x * (d + (tp_q)2.0 * b) / ((tp_q)6.0 * d);
        *mag = (tp_q)2.0 * a * xe * (d + b) * (d + (tp_q)2.0 * b) / d + (tp_q)8.0 * *v;
        return 1;
    case EDMI_POT_LJ: /* V' d = 4 a (12 t^12 + 6 t^6) */
        if (!(d > (tp_q)0.0))
            return 0;
        t = b / d;
        t = t * t * t * t * t * t;
        *v = (tp_q)4.0 * a * t * (t - (tp_q)1.0);
        *mag = (tp_q)4.0 * a * t * (t + (tp_q)1.0) * (tp_q)64.0;
        return 1;
    case EDMI_POT_INVERSE: /* V' d = |V| */
        if (!(d > (tp_q)0.0))
            return 0;
        *v = -a / d;
        *mag = (tp_q)8.0 * tp_absq(a) / d;
        return 1;
    case EDMI_POT_CONTACT: /* a/3 x^3 for x > 0, x = b - d (contact) or d - b (tether) */
    case EDMI_POT_TETHER:  /* V' d = a x^2 d */
        x = p->kind == EDMI_POT_CONTACT ? b - d : d - b;
        xe = tp_absq(x) + (tp_q)4.0 * TP_Q_EPS * (d + b);
        *v = x > (tp_q)0.0 ? a * x * x * x / (tp_q)3.0 : (tp_q)0.0;
        *mag = x > (tp_q)-8.0 * TP_Q_EPS * (d + b) /* else V = 0 exactly */
                   ? (tp_q)4.0 * a * xe * xe * (d + b + xe) + (tp_q)4.0 * *v
                   : (tp_q)0.0;
        return 1;
    case EDMI_POT_USER: /* the built-in whose V its callback gives (tp_user_builtin) */
        return tp_user_builtin(p, &bp) && bp.kind != EDMI_POT_USER && tp_pot(&bp, s, d, v, mag);
    default:
        return 0;
    }
}

/* The link vector of link j in state s, in tp_q (each component the difference of two stored
 * reals: exact, or within u of itself). */
static void tp_link_vec(const edmi_system *s, int j, tp_q r[3])
{
    const edmi_link *lk = &s->link[j];
    const edmi_real *xb = lk->b == EDMI_ANCHOR ? lk->anchor : s->body[lk->b].q;
    int i;
    for (i = 0; i < 3; i++)
        r[i] = (tp_q)s->body[lk->a].q[i] - (tp_q)xb[i];
}

/* The walls of state s (none where the build compiles them out: no wall members). */
#if EDMI_MAX_WALLS > 0
#define TP_N_WALLS(s) ((s)->n_walls)
#else
#define TP_N_WALLS(s) 0
#endif

#if EDMI_MAX_WALLS > 0
/* V of wall j in state s, from its gap g = n.q - c in tp_q (each product of two stored reals
 * exact, their sum within a few tp_q units of G = sum |n_i q_i| + |c|), and its magnitude *mag
 * as tp_pot's: harmonic a/2 x^2, one-sided a/3 x^3 for x > 0 (x = g - b, or b - g for
 * contact). 0 for another kind. */
static int tp_wall_v(const edmi_system *s, int j, tp_q *v, tp_q *mag)
{
    const edmi_wall *wl = &s->wall[j];
    tp_q g = -(tp_q)wl->c, big = tp_absq((tp_q)wl->c), a = (tp_q)wl->pot.a, b = (tp_q)wl->pot.b;
    tp_q x, xe;
    int i;
    for (i = 0; i < 3; i++) {
        tp_q t = (tp_q)wl->n[i] * (tp_q)s->body[wl->a].q[i];
        g += t;
        big += tp_absq(t);
    }
    x = wl->pot.kind == EDMI_POT_CONTACT ? b - g : g - b;
    xe = tp_absq(x) + (tp_q)8.0 * TP_Q_EPS * (big + b);
    switch (wl->pot.kind) {
    case EDMI_POT_HARMONIC:
        *v = (tp_q)0.5 * a * x * x;
        *mag = (tp_q)4.0 * a * xe * (big + b + xe) + (tp_q)4.0 * *v;
        return 1;
    case EDMI_POT_CONTACT:
    case EDMI_POT_TETHER:
        *v = x > (tp_q)0.0 ? a * x * x * x / (tp_q)3.0 : (tp_q)0.0;
        *mag = x > (tp_q)-16.0 * TP_Q_EPS * (big + b)
                   ? (tp_q)4.0 * a * xe * xe * (big + b + xe) + (tp_q)4.0 * *v
                   : (tp_q)0.0;
        return 1;
    default:
        return 0;
    }
}
#endif

/* The squared length of link j in state s, and the length *d, in tp_q. */
static tp_q tp_link_sq(const edmi_system *s, int j, tp_q *d)
{
    tp_q r[3], sq;
    tp_link_vec(s, j, r);
    sq = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    *d = tp_sqrtq(sq);
    return sq;
}

#if EDMI_MAX_MASS_GAP > 0
/* m_ab of a coupled mass matrix (issue 12), a != b; 0 beyond the gap. Exact in long double
 * (a stored real). */
static long double tp_mass_ab(const edmi_system *s, int a, int b)
{
    int hi = a > b ? a : b, k = (a > b ? a - b : b - a) - 1;
    return k < EDMI_MAX_MASS_GAP ? (long double)s->mass_off[hi][k] : 0.0L;
}

static int tp_coupled(const edmi_system *s)
{
    int a, k;
    for (a = 1; a < s->n_bodies; a++)
        for (k = 0; k < EDMI_MAX_MASS_GAP && k < a; k++)
            if (s->mass_off[a][k] != 0)
                return 1;
    return 0;
}

/* The extreme eigenvalues of the symmetric n x n matrix m, by cyclic Jacobi rotations on a
 * copy (no library code), each within 8 n eps ||m||_F of its computed value (Jacobi is
 * backward stable): *lmin is the lower end of that interval, *lmax the upper. In long double
 * (eps = LDBL_EPSILON), not tp_q: m's entries are stored reals (exact in long double), and
 * the range serves only as a bound with its own margin, kappa = lmax / lmin >= kappa(M) in
 * the solve's error bound (tp_delta_k_coupled), and lmin > 0 as the proof that M is
 * definite. A coarser kappa widens that bound by a factor of at most 1 + 16 n eps kappa, not
 * its validity; the inequality's terms themselves are solved in tp_q. */
static void tp_eig_range(long double m[EDMI_MAX_BODIES][EDMI_MAX_BODIES], int n,
                         long double *lmin, long double *lmax)
{
    static long double a[EDMI_MAX_BODIES][EDMI_MAX_BODIES];
    long double fro = 0.0L, off;
    int i, j, k, p, q, sweep;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) {
            a[i][j] = m[i][j];
            fro += m[i][j] * m[i][j];
        }
    for (sweep = 0; sweep < 64; sweep++) {
        for (off = 0.0L, i = 0; i < n; i++)
            for (j = 0; j < n; j++)
                off += i != j ? a[i][j] * a[i][j] : 0.0L;
        if (!(off > LDBL_EPSILON * LDBL_EPSILON * fro))
            break;
        for (p = 0; p < n; p++)
            for (q = p + 1; q < n; q++) {
                long double th, t, c, s;
                if (a[p][q] == 0.0L)
                    continue;
                th = (a[q][q] - a[p][p]) / (2.0L * a[p][q]);
                t = (th >= 0.0L ? 1.0L : -1.0L) / (tp_absl(th) + tp_sqrtl(th * th + 1.0L));
                c = 1.0L / tp_sqrtl(t * t + 1.0L);
                s = t * c;
                for (k = 0; k < n; k++) { /* columns p, q */
                    long double kp = a[k][p], kq = a[k][q];
                    a[k][p] = c * kp - s * kq;
                    a[k][q] = s * kp + c * kq;
                }
                for (k = 0; k < n; k++) { /* rows p, q */
                    long double pk = a[p][k], qk = a[q][k];
                    a[p][k] = c * pk - s * qk;
                    a[q][k] = s * pk + c * qk;
                }
            }
    }
    *lmin = LDBL_MAX;
    *lmax = -LDBL_MAX;
    for (i = 0; i < n; i++) {
        if (a[i][i] < *lmin)
            *lmin = a[i][i];
        if (a[i][i] > *lmax)
            *lmax = a[i][i];
    }
    fro = tp_sqrtl(fro) * 8.0L * (long double)n * LDBL_EPSILON;
    *lmin -= fro;
    *lmax += fro;
}

/* K(p1) - K(p0) = 1/2 (p1 - p0) . M^-1 (p1 + p0) of a coupled M, by Gaussian elimination on
 * the dense M in tp_q (no library code), and a bound on its error: a few units of tp_q times
 * kappa(M) times the terms, kappa from M's extreme eigenvalues (Jacobi, tp_eig_range). 0 if
 * M is not positive definite to long double's resolution (tp_eig_range). */
static int tp_delta_k_coupled(const edmi_system *s0, const edmi_system *s1, tp_q *dk,
                              tp_q *mag) /* s0 NULL: K(p1) itself */
{
    static long double ml[EDMI_MAX_BODIES][EDMI_MAX_BODIES];
    static tp_q m[EDMI_MAX_BODIES][EDMI_MAX_BODIES], x[EDMI_MAX_BODIES][3];
    long double lmin, lmax;
    tp_q kappa, t;
    int n = s1->n_bodies, a, b, c, k;
#define TP_P0(a, c) (s0 ? (tp_q)s0->body[a].p[c] : (tp_q)0.0)
    for (a = 0; a < n; a++) {
        for (b = 0; b < n; b++) {
            ml[a][b] = a == b ? (long double)s1->body[a].m : tp_mass_ab(s1, a, b);
            m[a][b] = (tp_q)ml[a][b];
        }
        for (c = 0; c < 3; c++)
            x[a][c] = (tp_q)s1->body[a].p[c] + TP_P0(a, c);
    }
    tp_eig_range(ml, n, &lmin, &lmax);
    if (!(lmin > 0.0L))
        return 0;
    kappa = (tp_q)(lmax / lmin);
    for (k = 0; k < n; k++) /* positive definite: no pivoting needed */
        for (a = k + 1; a < n; a++) {
            tp_q f = m[a][k] / m[k][k];
            if (f == (tp_q)0.0)
                continue;
            for (b = k; b < n; b++)
                m[a][b] -= f * m[k][b];
            for (c = 0; c < 3; c++)
                x[a][c] -= f * x[k][c];
        }
    for (a = n - 1; a >= 0; a--)
        for (c = 0; c < 3; c++) {
            t = x[a][c];
            for (b = a + 1; b < n; b++)
                t -= m[a][b] * x[b][c];
            x[a][c] = t / m[a][a];
        }
    *dk = (tp_q)0.0;
    *mag = (tp_q)0.0;
    for (a = 0; a < n; a++)
        for (c = 0; c < 3; c++) {
            tp_q d = (tp_q)s1->body[a].p[c] - TP_P0(a, c);
            *dk += (tp_q)0.5 * d * x[a][c];
            *mag += (tp_q)8.0 * (tp_q)(n + 2) * kappa * tp_absq(d * x[a][c]);
        }
#undef TP_P0
    return 1;
}
#endif

/* tp_delta in tp_q: what tp_delta_h reports before rounding, and tp_run accumulates. */
typedef struct tp_qdelta {
    tp_q dh, w, err, mag;
} tp_qdelta;

static int tp_delta_q(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res,
                      tp_qdelta *out)
{
    tp_q dh = (tp_q)0.0, mag = (tp_q)0.0;
    int a, i, j, coupled = 0;
#if EDMI_MAX_MASS_GAP > 0
    if (tp_coupled(s0)) {
        coupled = 1;
        if (!tp_delta_k_coupled(s0, s1, &dh, &mag))
            return 0;
        if (s0->has_field) /* V = -sum_ab m_ab g . q_a: the off-diagonal masses' part */
            for (a = 0; a < s0->n_bodies; a++) {
                int b;
                for (b = 0; b < s0->n_bodies; b++)
                    for (i = 0; i < 3 && b != a; i++) {
                        tp_q g = (tp_q)s0->g[i], m = (tp_q)tp_mass_ab(s0, a, b);
                        tp_q dq = (tp_q)s1->body[a].q[i] - (tp_q)s0->body[a].q[i];
                        dh -= m * g * dq;
                        mag += (tp_q)8.0 * tp_absq(m * g * dq);
                    }
            }
    }
#endif
    for (a = 0; a < s0->n_bodies; a++) {
        tp_q m2 = (tp_q)2.0 * (tp_q)s0->body[a].m, k = (tp_q)0.0, km = (tp_q)0.0;
        /* K1 - K0 = sum (p1 - p0)(p1 + p0) / 2m: p1 - p0 exact or within u of itself (two
         * stored values, at most 53 significant bits, in tp_q's 53 to 113), so the error is a
         * few u times the terms of the change, not of K */
        for (i = 0; i < 3 && !coupled; i++) {
            tp_q p0 = (tp_q)s0->body[a].p[i], p1 = (tp_q)s1->body[a].p[i];
            k += (p1 - p0) * (p1 + p0);
            km += tp_absq(p1 - p0) * (tp_absq(p1) + tp_absq(p0));
        }
        dh += k / m2;
        mag += (tp_q)8.0 * km / m2;
        if (s0->has_field) /* V = -m g . q, changed by -m g . (q1 - q0) */
            for (i = 0; i < 3; i++) {
                tp_q g = (tp_q)s0->g[i], m = (tp_q)s0->body[a].m;
                tp_q dq = (tp_q)s1->body[a].q[i] - (tp_q)s0->body[a].q[i];
                dh -= m * g * dq;
                mag += (tp_q)8.0 * tp_absq(m * g * dq);
            }
    }
    for (j = 0; j < s0->n_links; j++) {
        tp_q d0, d1, sq0 = tp_link_sq(s0, j, &d0), sq1 = tp_link_sq(s1, j, &d1);
        tp_q v0, v1, m0, m1;
        if (!tp_pot(&s0->link[j].pot, sq0, d0, &v0, &m0) ||
            !tp_pot(&s1->link[j].pot, sq1, d1, &v1, &m1))
            return 0;
        dh += v1 - v0;
        mag += m0 + m1;
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < s0->n_walls; j++) {
        tp_q v0, v1, m0, m1;
        if (!tp_wall_v(s0, j, &v0, &m0) || !tp_wall_v(s1, j, &v1, &m1))
            return 0;
        dh += v1 - v0;
        mag += m0 + m1;
    }
#endif
    out->dh = dh;
    out->w = (tp_q)res->work_ext + (tp_q)res->work_anchor + ((tp_q)s0->tank - (tp_q)s1->tank);
    out->err = TP_ERR_ULPS * TP_Q_EPS *
               (mag + tp_absq((tp_q)res->work_ext) + tp_absq((tp_q)res->work_anchor) +
                (tp_q)s0->tank + (tp_q)s1->tank);
    out->mag = mag;
    return dh - dh == (tp_q)0.0 && out->err - out->err == (tp_q)0.0;
}

int tp_delta_h(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res,
               tp_delta *out)
{
    tp_qdelta q;
    tp_q diff;
    if (!tp_delta_q(s0, s1, res, &q))
        return 0;
    diff = q.dh - q.w;
    out->dh = (long double)q.dh;
    out->w = (long double)q.w;
    out->err = (long double)q.err;
    out->mag = (long double)q.mag;
    out->diff = (long double)diff;
    out->broken = diff > q.err;
    out->unresolved = !(diff > q.err) && !(diff < -q.err);
    out->rose = q.dh > q.err;
    out->quad = 1;
    return 1;
}

/* ---- the fast path: tp_delta_h's decisions in double-word arithmetic -------------------------
 * tp_delta_h spends nearly all its time in libgcc's soft binary128 (on the ten bodies about
 * as much as the step itself). tp_h_dw evaluates H of one stored state term by term in
 * binary64 double-word arithmetic (a real held as hi + lo, about 106 bits) with an a-priori
 * bound on its error; tp_delta_dw takes two of them, one step's works and tanks, and gives
 * tp_delta_h's three decisions where that bound settles them. A run evaluates each state
 * once (the end of one step is the start of the next); tp_delta_h_fast calls tp_delta_h where
 * tp_delta_dw does not decide.
 *
 * What is decided. tp_delta_h decides on its computed dh_q, diff_q = dh_q - w_q and err_q:
 * broken = diff_q > err_q, unresolved = |diff_q| <= err_q, rose = dh_q > err_q. Its own
 * rounding, |dh_q - dh| and |diff_q - diff| for the exact dh and diff of the stored numbers,
 * is within 16 eps (mag + |work_ext| + |work_anchor| + |T0| + |T1|) (its comment: w's three
 * roundings and the subtraction's are a few units of tp_q of these), and so is |err_q|; call
 * E a bound on that. With this path's dh_f and diff_f within e of dh and diff: diff_f > e + 2E
 * gives diff > 2E, so diff_q > E >= |err_q| (broken, and resolved); diff_f < -(e + 2E) gives
 * diff_q < -E (not broken, resolved); dh_f > e + 2E gives dh_q > E (rose), dh_f < -(e + 2E)
 * gives dh_q < -E (not rose). Anything between goes to tp_delta_h. The threshold T >= e + 2E
 * is compared with the double-word values through the sign of diff_f -+ T by DWPlusFP, whose
 * relative error (below) keeps the sign of the exact difference.
 *
 * The operations (u = 2^-53) and their relative errors, from Joldes, Muller, Popescu, "Tight
 * and rigorous error bounds for basic building blocks of double-word arithmetic", ACM TOMS
 * 44(2), 2017 (valid without underflow and overflow): 2Sum, Fast2Sum and Dekker's TwoProd
 * (Veltkamp's split) exact; DWPlusFP 2u^2; AccurateDWPlusDW 3u^2 + 13u^3 < 3.01u^2;
 * DWTimesFP1 1.5u^2 + 4u^3 < 2u^2; DWTimesDW1 7u^2 (5u^2: Muller and Rideau, ACM TOMS 48(1),
 * 2022); DWDivFP3 3u^2; DWDivDW2 15u^2 + 56u^3 < 16u^2. The square root, one Newton step from
 * y = RN(sqrt(xh)) (Dekker's): y^2 is within (1 +- u)^2 of xh, so xh - RN(y^2) is exact
 * (Sterbenz); subtracting TwoProd's low part errs by u |xh - y^2| <= 2.01u^2 xh, adding xl by
 * u (3.01u xh) <= 3.01u^2 xh, the quotient by 2y (exact) by u |r|/2y <= 1.51u^2 y, and the
 * Newton step's own error is (y - sqrt(x))^2 / 2y <= (1.5u)^2 xh / 2y <= 1.13u^2 y: in all
 * (2.01 + 3.01) / 2 + 1.51 + 1.13 < 5.2u^2 of sqrt(x), taken as 6u^2. Relative errors
 * compose as (1 + a)(1 + b): their sum and a product of order u^4 (< 2^-100 u^2), which
 * rounding each constant up absorbs; so do the few units of u by which the magnitudes M,
 * evaluated in plain double from the hi parts, may fall short of the exact ones.
 *
 * Underflow and overflow: tp_h_dw runs with the status flags of <fenv.h> cleared, and a
 * raised FE_UNDERFLOW, FE_OVERFLOW, FE_INVALID or FE_DIVBYZERO (or a rounding mode other than
 * to nearest) marks its value unusable (then tp_delta_h decides). Under IEEE 754's default
 * handling a result that is tiny and inexact raises the underflow flag, so without it every
 * operation returned what it would with an unbounded exponent range, where the bounds above
 * hold (a tiny result that is exact is the same in both). Its results are stored before the
 * flags are read and the flag functions are called through volatile pointers, so that the
 * compiler moves no operation across them (GCC does not honour FENV_ACCESS). tp_delta_dw
 * itself only adds (2Sum, Fast2Sum and the DW sums, exact or normal where a result is tiny)
 * and forms T by one product, kept above 2^-960 (normal).
 *
 * The terms of H(s), each with its error against the exact value in units of u^2 times a
 * magnitude M that the computed term never exceeds in absolute value:
 *  - a body's |p|^2/2m: three TwoProd squares (exact), two AccurateDWPlusDW of non-negative
 *    terms, over 2m (DWDivFP3): 2 (3.01) + 3 < 9.1 of M = the term itself.
 *  - the field's -m g_i q_i (TwoProd of m and g_i, exact; DWTimesFP1): 2 of M = |m g_i q_i|.
 *  - a link vector: 2Sum per component, exact. Its squared length s: three DWTimesDW1
 *    squares and two AccurateDWPlusDW of non-negative terms, 7 + 2 (3.01) < 13.1u^2
 *    relative; its length d = sqrt(s): 13.1/2 + 6 < 13u^2 relative.
 *  - harmonic, b = 0: a/2 s (DWTimesFP1, a/2 exact), 13.1 + 2 < 16 of M = |a| s/2.
 *  - harmonic: x = d - b (DWPlusFP) within 13u^2 d + 2u^2 |d - b| <= 15.1u^2 D of x*,
 *    D = d + |b|; x^2 (DWTimesDW1), times a/2 (DWTimesFP1): the error is at most
 *    |a|/2 (|x - x*| |x + x*| + 9.01u^2 x^2) <= |a|/2 (15.1 (3) + 9.01)u^2 D xe < 28 of
 *    M = |a| D xe, xe = |x| + 2^-40 D >= max(|x|, |x*|) + |x - x*|.
 *  - quartic: x = s - b^2 (b^2 by TwoProd; AccurateDWPlusDW) within 13.1u^2 s + 3.01u^2
 *    |s - b^2| <= 16.2u^2 S of x*, S = s + b^2; then as the harmonic one, with a/4:
 *    |a|/4 (16.2 (3) + 9.01) < 15 of M = |a| S xe, xe = |x| + 2^-40 S.
 *  - neo-Hookean (d > 0, b >= 0, else tp_delta_h): a x^2 (d + 2b) / 6d, x as the harmonic
 *    one's; (d + 2b)/d within 13 + 2 + 13 = 28u^2 of its exact value (d + 2b, DWPlusFP, does
 *    not cancel for b >= 0), the two products, the factor a, 6d and the quotient 7 + 7 + 2 +
 *    2 + 16 = 34u^2: |a| (d + 2b)/6d (15.1 (3) + 62.1) u^2 D xe < 18 of
 *    M = |a| D xe (d + 2b)/d.
 *  - Lennard-Jones (d > 0): w = b^2/s (TwoProd, DWDivDW2) within 13.1 + 16 < 29.2u^2,
 *    t = w^3 (two DWTimesDW1) within 3 (29.2) + 14 < 102u^2, t - 1 (DWPlusFP) within
 *    102u^2 t + 2u^2 |t - 1|; the product and 4a (7 + 2): the error is at most
 *    4 |a| (102 + 102 + 2 + 9.01)u^2 t (t + 1) < 54 of M = 16 |a| t (t + 1).
 *  - inverse (d > 0): -a/d (DWDivDW2) within 13 + 16 < 30 of M = |a|/d.
 * H(s) is the sum of its n terms by AccurateDWPlusDW, each addition erring by 3.01u^2 of a
 * partial sum, itself at most the sum of the M's (to a factor 1 + 3.01u^2 per addition): its
 * error is at most (54 + 3.01 n) u^2 M(s), M(s) the sum of its terms' M. Then dh = H(s1) -
 * H(s0) adds 3.01u^2 (M(s0) + M(s1)), w = work_ext + work_anchor + T0 - T1 (2Sum, two
 * DWPlusFP) errs by 4.01u^2 M_w, M_w = |work_ext| + |work_anchor| + |T0| + |T1|, and
 * diff = dh - w by 3.01u^2 of all: e <= (64.1 + 3.01 n) u^2 M_all, n the larger count and
 * M_all = M(s0) + M(s1) + M_w.
 *
 * tp_delta_h's bound is 16 (2^-112) (mag + |work_ext| + |work_anchor| + |T0| + |T1|), its mag
 * summing tp_pot's magnitude of each link in both states (at most 32 of that link's M here:
 * the harmonic's 4 |a| xe D + 4 |V| is 6 of it, 12 for b = 0, quartic 5, neo-Hookean 2 + 8/6,
 * LJ 16, inverse 8), 8 |p1 - p0| (|p1| + |p0|)/2m per body, at most 16 of K(s0) + K(s1) (since
 * |p1 - p0| (|p1| + |p0|) <= 2 (p1^2 + p0^2)), and the field's 8 |m g_i (q1_i - q0_i)|, at
 * most 8 of the two states' M: so E = 2^-108 (32) M_all = 8u^2 M_all, and
 * T = (96 + 4n) u^2 M_all >= (64.1 + 3.01 n + 16) u^2 M_all, the difference covering the
 * rounding of M_all and of T itself. On the ten bodies (n = 55) T is 3.9e-30 of M_all, where
 * one step changes the stored states' H by 1e-25 of it and more (measured; LG's steps are
 * the closest). A step whose dH - W the guard's tank took up to its last unit, or a scene at
 * rest (dH = 0), goes to tp_delta_h. */
#if TP_FAST
typedef struct tp_dw {
    double hi, lo;
} tp_dw;

static int (*volatile tp_fe_clear)(int) = feclearexcept;
static int (*volatile tp_fe_test)(int) = fetestexcept;
static int (*volatile tp_fe_get)(fexcept_t *, int) = fegetexceptflag;
static int (*volatile tp_fe_set)(const fexcept_t *, int) = fesetexceptflag;
#define TP_FE_BAD (FE_UNDERFLOW | FE_OVERFLOW | FE_INVALID | FE_DIVBYZERO)

static double tp_absd(double x) { return x < 0.0 ? -x : x; }

static tp_dw tp_dw_of(double x)
{
    tp_dw r;
    r.hi = x;
    r.lo = 0.0;
    return r;
}

static tp_dw tp_dw_neg(tp_dw x)
{
    x.hi = -x.hi;
    x.lo = -x.lo;
    return x;
}

/* a + b exactly (2Sum). */
static tp_dw tp_two_sum(double a, double b)
{
    tp_dw r;
    double a1, b1;
    r.hi = a + b;
    a1 = r.hi - b;
    b1 = r.hi - a1;
    r.lo = (a - a1) + (b - b1);
    return r;
}

/* a + b exactly, |a| >= |b| (Fast2Sum). */
static tp_dw tp_fast_two_sum(double a, double b)
{
    tp_dw r;
    r.hi = a + b;
    r.lo = b - (r.hi - a);
    return r;
}

/* a b exactly (Dekker's TwoProd, split by 2^27 + 1). */
static tp_dw tp_two_prod(double a, double b)
{
    tp_dw r;
    double ca = 134217729.0 * a, cb = 134217729.0 * b;
    double ah = ca - (ca - a), al = a - ah, bh = cb - (cb - b), bl = b - bh;
    r.hi = a * b;
    r.lo = ((ah * bh - r.hi) + ah * bl + al * bh) + al * bl;
    return r;
}

static tp_dw tp_dw_add(tp_dw x, tp_dw y) /* AccurateDWPlusDW */
{
    tp_dw s = tp_two_sum(x.hi, y.hi), t = tp_two_sum(x.lo, y.lo), v;
    v = tp_fast_two_sum(s.hi, s.lo + t.hi);
    return tp_fast_two_sum(v.hi, t.lo + v.lo);
}

static tp_dw tp_dw_add_d(tp_dw x, double y) /* DWPlusFP */
{
    tp_dw s = tp_two_sum(x.hi, y);
    return tp_fast_two_sum(s.hi, x.lo + s.lo);
}

static tp_dw tp_dw_mul(tp_dw x, tp_dw y) /* DWTimesDW1 */
{
    tp_dw c = tp_two_prod(x.hi, y.hi);
    return tp_fast_two_sum(c.hi, c.lo + (x.hi * y.lo + x.lo * y.hi));
}

static tp_dw tp_dw_mul_d(tp_dw x, double y) /* DWTimesFP1 */
{
    tp_dw c = tp_two_prod(x.hi, y), t = tp_fast_two_sum(c.hi, x.lo * y);
    return tp_fast_two_sum(t.hi, t.lo + c.lo);
}

static tp_dw tp_dw_div_d(tp_dw x, double y) /* DWDivFP3 */
{
    double th = x.hi / y;
    tp_dw p = tp_two_prod(th, y);
    return tp_fast_two_sum(th, (((x.hi - p.hi) - p.lo) + x.lo) / y);
}

static tp_dw tp_dw_div(tp_dw x, tp_dw y) /* DWDivDW2 */
{
    double th = x.hi / y.hi;
    tp_dw r = tp_dw_mul_d(y, th);
    return tp_fast_two_sum(th, ((x.hi - r.hi) + (x.lo - r.lo)) / y.hi);
}

/* sqrt(x), x >= 0: one Newton step from sqrt(x.hi); 0 exactly for x = 0. */
static tp_dw tp_dw_sqrt(tp_dw x)
{
    double y;
    tp_dw p;
    if (!(x.hi > 0.0))
        return tp_dw_of(0.0);
    y = __builtin_sqrt(x.hi);
    p = tp_two_prod(y, y);
    return tp_fast_two_sum(y, (((x.hi - p.hi) - p.lo) + x.lo) / (2.0 * y));
}

/* The sign of x - y, exactly (DWPlusFP's relative error is below 1). */
static int tp_dw_above(tp_dw x, double y) { return tp_dw_add_d(x, -y).hi > 0.0; }

static int tp_dw_below(tp_dw x, double y) { return tp_dw_add_d(x, -y).hi < 0.0; }

/* Link j's squared length in state s (the link vector exact, by 2Sum). */
static tp_dw tp_link_sq_dw(const edmi_system *s, int j)
{
    const edmi_link *lk = &s->link[j];
    const edmi_real *xa = s->body[lk->a].q;
    const edmi_real *xb = lk->b == EDMI_ANCHOR ? lk->anchor : s->body[lk->b].q;
    tp_dw r = tp_two_sum((double)xa[0], -(double)xb[0]), sq = tp_dw_mul(r, r);
    int i;
    for (i = 1; i < 3; i++) {
        r = tp_two_sum((double)xa[i], -(double)xb[i]);
        sq = tp_dw_add(sq, tp_dw_mul(r, r));
    }
    return sq;
}

/* V of a built-in potential at the squared length s, and its magnitude *mag (the comment
 * above); 0 where tp_pot does not evaluate it (d = 0 where V divides by d) or the bound does
 * not cover it (a neo-Hookean b < 0). */
static int tp_pot_dw(const edmi_potential *p, tp_dw s, tp_dw *v, double *mag)
{
    double a = (double)p->a, b = (double)p->b, big, xe;
    tp_dw d, x, t;
    edmi_potential bp;
    switch (p->kind) {
    case EDMI_POT_HARMONIC:
        if (b == 0.0) {
            *v = tp_dw_mul_d(s, 0.5 * a);
            *mag = 0.5 * tp_absd(a) * s.hi;
            return 1;
        }
        d = tp_dw_sqrt(s);
        x = tp_dw_add_d(d, -b);
        big = d.hi + tp_absd(b);
        xe = tp_absd(x.hi) + 0x1p-40 * big;
        *v = tp_dw_mul_d(tp_dw_mul(x, x), 0.5 * a);
        *mag = tp_absd(a) * big * xe;
        return 1;
    case EDMI_POT_QUARTIC:
        x = tp_dw_add(s, tp_dw_neg(tp_two_prod(b, b)));
        big = s.hi + b * b;
        xe = tp_absd(x.hi) + 0x1p-40 * big;
        *v = tp_dw_mul_d(tp_dw_mul(x, x), 0.25 * a);
        *mag = tp_absd(a) * big * xe;
        return 1;
    case EDMI_POT_NEO_HOOKE:
        if (!(s.hi > 0.0) || !(b >= 0.0))
            return 0;
        d = tp_dw_sqrt(s);
        x = tp_dw_add_d(d, -b);
        big = d.hi + b;
        xe = tp_absd(x.hi) + 0x1p-40 * big;
        t = tp_dw_mul(tp_dw_mul(x, x), tp_dw_add_d(d, 2.0 * b));
        *v = tp_dw_div(tp_dw_mul_d(t, a), tp_dw_mul_d(d, 6.0));
        *mag = tp_absd(a) * big * xe * ((d.hi + 2.0 * b) / d.hi);
        return 1;
    case EDMI_POT_LJ:
        if (!(s.hi > 0.0))
            return 0;
        x = tp_dw_div(tp_two_prod(b, b), s);
        t = tp_dw_mul(tp_dw_mul(x, x), x);
        *v = tp_dw_mul_d(tp_dw_mul(t, tp_dw_add_d(t, -1.0)), 4.0 * a);
        *mag = 16.0 * tp_absd(a) * t.hi * (t.hi + 1.0);
        return 1;
    case EDMI_POT_INVERSE:
        if (!(s.hi > 0.0))
            return 0;
        d = tp_dw_sqrt(s);
        *v = tp_dw_div(tp_dw_of(-a), d);
        *mag = tp_absd(a) / d.hi;
        return 1;
    case EDMI_POT_CONTACT:
    case EDMI_POT_TETHER:
        d = tp_dw_sqrt(s);
        x = tp_dw_add_d(d, -b);
        if (p->kind == EDMI_POT_CONTACT)
            x = tp_dw_neg(x);
        big = d.hi + b;
        xe = tp_absd(x.hi) + 0x1p-40 * big;
        t = tp_dw_mul_d(tp_dw_mul(tp_dw_mul(x, x), x), a);
        *v = x.hi > 0.0 ? tp_dw_div(t, tp_dw_of(3.0)) : tp_dw_of(0.0);
        *mag = x.hi > -0x1p-39 * big ? a * big * xe * xe : 0.0; /* else V = 0 exactly */
        return 1;
    case EDMI_POT_USER: /* the built-in whose V its callback gives (tp_user_builtin) */
        return tp_user_builtin(p, &bp) && bp.kind != EDMI_POT_USER && tp_pot_dw(&bp, s, v, mag);
    default:
        return 0;
    }
}

#if EDMI_MAX_WALLS > 0
/* V of wall j in double-word (as tp_wall_v), and its magnitude as tp_pot_dw's: the gap's
 * products exact, their sum within a few u^2 of G, taken as 2^-40 of it (as the lengths). */
static int tp_wall_v_dw(const edmi_system *s, int j, tp_dw *v, double *mag)
{
    const edmi_wall *wl = &s->wall[j];
    double a = (double)wl->pot.a, b = (double)wl->pot.b, big = tp_absd((double)wl->c) + b, xe;
    tp_dw g = tp_dw_of(-(double)wl->c), x;
    int i;
    for (i = 0; i < 3; i++) {
        tp_dw t = tp_two_prod((double)wl->n[i], (double)s->body[wl->a].q[i]);
        g = tp_dw_add(g, t);
        big += tp_absd(t.hi);
    }
    x = tp_dw_add_d(g, -b);
    if (wl->pot.kind == EDMI_POT_CONTACT)
        x = tp_dw_neg(x);
    xe = tp_absd(x.hi) + 0x1p-40 * big;
    switch (wl->pot.kind) {
    case EDMI_POT_HARMONIC:
        *v = tp_dw_mul_d(tp_dw_mul(x, x), 0.5 * a);
        *mag = a * big * xe;
        return 1;
    case EDMI_POT_CONTACT:
    case EDMI_POT_TETHER:
        *v = x.hi > 0.0 ? tp_dw_div(tp_dw_mul_d(tp_dw_mul(tp_dw_mul(x, x), x), a), tp_dw_of(3.0))
                        : tp_dw_of(0.0);
        *mag = x.hi > -0x1p-39 * big ? a * big * xe * xe : 0.0;
        return 1;
    default:
        return 0;
    }
}
#endif

/* H(s), its magnitude and count of terms (tp_h_dw's work, flags aside); 0 if a term is not
 * evaluated here (a coupled M, or what tp_pot_dw refuses). */
static int tp_h_dw_eval(const edmi_system *s, tp_hdw *h)
{
    tp_dw sum = tp_dw_of(0.0), t;
    double mag = 0.0;
    int a, i, j, n = 0;
#if EDMI_MAX_MASS_GAP > 0
    if (tp_coupled(s))
        return 0;
#endif
    for (a = 0; a < s->n_bodies; a++) {
        const edmi_real *p = s->body[a].p;
        double m = (double)s->body[a].m;
        t = tp_two_prod((double)p[0], (double)p[0]);
        for (i = 1; i < 3; i++)
            t = tp_dw_add(t, tp_two_prod((double)p[i], (double)p[i]));
        t = tp_dw_div_d(t, 2.0 * m);
        sum = n++ ? tp_dw_add(sum, t) : t;
        mag += t.hi;
        if (s->has_field) /* V = -m g . q */
            for (i = 0; i < 3; i++) {
                double g = (double)s->g[i], q = (double)s->body[a].q[i];
                if (g == 0.0 || q == 0.0)
                    continue;
                t = tp_dw_neg(tp_dw_mul_d(tp_two_prod(m, g), q));
                sum = tp_dw_add(sum, t);
                n++;
                mag += tp_absd(t.hi);
            }
    }
    for (j = 0; j < s->n_links; j++) {
        double mj;
        if (!tp_pot_dw(&s->link[j].pot, tp_link_sq_dw(s, j), &t, &mj))
            return 0;
        sum = n++ ? tp_dw_add(sum, t) : t;
        mag += mj;
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < s->n_walls; j++) {
        double mj;
        if (!tp_wall_v_dw(s, j, &t, &mj))
            return 0;
        sum = n++ ? tp_dw_add(sum, t) : t;
        mag += mj;
    }
#endif
    h->hi = sum.hi;
    h->lo = sum.lo;
    h->mag = mag;
    h->n = n;
    return 1;
}
#endif

void tp_h_dw(const edmi_system *s, tp_hdw *h)
{
#if TP_FAST
    fexcept_t saved;
    int ok;
    h->hi = h->lo = h->mag = 0.0;
    h->n = h->ok = 0;
    if (fegetround() != FE_TONEAREST)
        return;
    tp_fe_get(&saved, FE_ALL_EXCEPT);
    tp_fe_clear(TP_FE_BAD);
    ok = tp_h_dw_eval(s, h); /* stores into *h: done before the flags are read */
    ok = ok && !tp_fe_test(TP_FE_BAD) && h->mag - h->mag == 0.0;
    tp_fe_set(&saved, FE_ALL_EXCEPT);
    h->ok = ok;
#else
    (void)s;
    h->hi = h->lo = h->mag = 0.0;
    h->n = h->ok = 0;
#endif
}

int tp_delta_dw(const edmi_system *s0, const tp_hdw *h0, const edmi_system *s1,
                const tp_hdw *h1, const edmi_step_result *res, tp_delta *out)
{
#if TP_FAST
    tp_dw dh, w, diff, x0, x1;
    double we = (double)res->work_ext, wa = (double)res->work_anchor;
    double t0 = (double)s0->tank, t1 = (double)s1->tank, mag, thr;
    int a, i;
    if (!h0->ok || !h1->ok || s0->n_bodies != s1->n_bodies || s0->n_links != s1->n_links ||
        TP_N_WALLS(s0) != TP_N_WALLS(s1) || s0->has_field != s1->has_field)
        return 0;
    for (a = 0; a < s0->n_bodies; a++) /* tp_delta_h takes s0's masses and field for both */
        if (s0->body[a].m != s1->body[a].m)
            return 0;
    for (i = 0; i < 3 && s0->has_field; i++)
        if (s0->g[i] != s1->g[i])
            return 0;
    x0.hi = h0->hi, x0.lo = h0->lo, x1.hi = h1->hi, x1.lo = h1->lo;
    dh = tp_dw_add(x1, tp_dw_neg(x0));
    w = tp_dw_add_d(tp_dw_add_d(tp_two_sum(we, wa), t0), -t1);
    diff = tp_dw_add(dh, tp_dw_neg(w));
    mag = h0->mag + h1->mag + (tp_absd(we) + tp_absd(wa) + tp_absd(t0) + tp_absd(t1));
    thr = (96.0 + 4.0 * (double)(h0->n > h1->n ? h0->n : h1->n)) * 0x1p-106 * mag;
    if (!(thr >= 0x1p-960 && thr <= 0x1p960) || dh.hi - dh.hi != 0.0 || diff.hi - diff.hi != 0.0)
        return 0;
    out->broken = tp_dw_above(diff, thr);
    out->unresolved = !out->broken && !tp_dw_below(diff, -thr);
    out->rose = tp_dw_above(dh, thr);
    out->dh = (long double)dh.hi + (long double)dh.lo;
    out->w = (long double)w.hi + (long double)w.lo;
    out->diff = (long double)diff.hi + (long double)diff.lo;
    out->err = (long double)thr;
    out->mag = (long double)mag;
    out->quad = 0;
    return !out->unresolved && (out->rose || tp_dw_below(dh, -thr));
#else
    (void)s0, (void)h0, (void)s1, (void)h1, (void)res, (void)out;
    return 0;
#endif
}

int tp_delta_h_fast(const edmi_system *s0, const tp_hdw *h0, const edmi_system *s1,
                    const tp_hdw *h1, const edmi_step_result *res, tp_delta *out)
{
    return tp_delta_dw(s0, h0, s1, h1, res, out) || tp_delta_h(s0, s1, res, out);
}

/* A run of steps under the window check: A_n = H_n - sum_{k<n} W_k (H_n = H_n-1 + dh, not a
 * fresh H: its rounding is in the deltas' err, accumulated in a_err), the smallest A_m + T_m
 * and A_m so far, and the largest rise of A over its lowest (in units of H's scale). */
typedef struct tp_win {
    tp_q h_last, sum_w, a_min, a_low, a_err, max_window, a_max;
    long steps;
} tp_win;

static void tp_win_start(tp_win *w, tp_q h, tp_q tank)
{
    w->h_last = h;
    w->sum_w = w->a_err = w->max_window = (tp_q)0.0;
    w->a_max = h;
    w->steps = 0;
    w->a_min = h + tank;
    w->a_low = h;
}

/* Add a step (its delta d, the tank after it); 1 if every window ending there holds. */
static int tp_win_add(tp_win *w, const tp_qdelta *d, const edmi_step_result *res, tp_q tank,
                      tp_q scale)
{
    tp_q a_n;
    int ok;
    w->sum_w += (tp_q)res->work_ext + (tp_q)res->work_anchor; /* d->w holds the tank's too */
    a_n = w->h_last + d->dh - w->sum_w;
    w->a_err += d->err + TP_Q_EPS * (tp_absq(w->sum_w) + tp_absq(a_n));
    if ((a_n - w->a_low) / scale > w->max_window)
        w->max_window = (a_n - w->a_low) / scale;
    if (w->steps++ == 0 || a_n > w->a_max)
        w->a_max = a_n;
    ok = !(a_n - w->a_min > w->a_err);
    w->h_last += d->dh;
    if (a_n + tank < w->a_min)
        w->a_min = a_n + tank;
    if (a_n < w->a_low)
        w->a_low = a_n;
    return ok;
}

static tp_win tp_window;

void tp_window_start(const edmi_system *s)
{
    tp_win_start(&tp_window, (tp_q)0.0, (tp_q)s->tank); /* A relative to H at the start */
}

int tp_window_step(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res)
{
    tp_qdelta d;
    if (!tp_delta_q(s0, s1, res, &d)) {
        tp_window_start(s1);
        return -1;
    }
    return tp_win_add(&tp_window, &d, res, (tp_q)s1->tank, (tp_q)1.0);
}

long double tp_window_rise(void) { return (long double)tp_window.a_max; }

/* H of a stored state in tp_q; 0 if a coupled M is not provably definite (not evaluated). */
static int tp_hq(const edmi_system *s, tp_q *out)
{
    tp_q h = (tp_q)0.0;
    int a, i, j, coupled = 0;
#if EDMI_MAX_MASS_GAP > 0
    if (tp_coupled(s)) {
        tp_q mag;
        coupled = 1;
        if (!tp_delta_k_coupled(0, s, &h, &mag))
            return 0;
        if (s->has_field)
            for (a = 0; a < s->n_bodies; a++) {
                int b;
                for (b = 0; b < s->n_bodies; b++)
                    for (i = 0; i < 3 && b != a; i++)
                        h -= (tp_q)tp_mass_ab(s, a, b) * (tp_q)s->g[i] * (tp_q)s->body[a].q[i];
            }
    }
#endif
    for (a = 0; a < s->n_bodies; a++) {
        tp_q k = (tp_q)0.0;
        for (i = 0; i < 3 && !coupled; i++)
            k += (tp_q)s->body[a].p[i] * (tp_q)s->body[a].p[i];
        h += k / ((tp_q)2.0 * (tp_q)s->body[a].m);
        if (s->has_field)
            for (i = 0; i < 3; i++)
                h -= (tp_q)s->body[a].m * (tp_q)s->g[i] * (tp_q)s->body[a].q[i];
    }
    for (j = 0; j < s->n_links; j++) {
        tp_q d, sq = tp_link_sq(s, j, &d), v, m;
        if (tp_pot(&s->link[j].pot, sq, d, &v, &m))
            h += v;
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < s->n_walls; j++) {
        tp_q v, m;
        if (tp_wall_v(s, j, &v, &m))
            h += v;
    }
#endif
    *out = h;
    return 1;
}

long double tp_h(const edmi_system *s)
{
    tp_q h;
    return tp_hq(s, &h) ? (long double)h : LDBL_MAX;
}

/* ---- scenes ------------------------------------------------------------------------------ */

const char *tp_scene_name(tp_scene s)
{
    static const char *const names[TP_NSCENES] = {
        "paper spring",          "virtual spring, pumping port F = +c v",
        "virtual spring, random port", "virtual spring, port flipping sign every tick",
        "stiff harmonic, omega dt = 100", "LJ near-collisions on tethers",
        "virtual coupling through d = 0", "hanging chain, field, dampers, random port"};
    return (unsigned)s < (unsigned)TP_NSCENES ? names[s] : "?";
}

/* A deterministic uniform random number in [-1, 1) (a 32-bit LCG; the state is per run). */
static unsigned long tp_seed;

static edmi_real tp_rand(void)
{
    tp_seed = (tp_seed * 1664525UL + 1013904223UL) & 0xffffffffUL;
    return (edmi_real)((long)(tp_seed >> 8) - 0x800000L) / (edmi_real)0x800000L;
}

/* sin x for the hand below, without libm. This file's own: tests/lib is shared by tests,
 * benchmarks and the simulator and includes nothing from examples/ (issue 33), so it does not
 * borrow the haptic example's sine. x is reduced by the nearest whole number k of half turns
 * to r = x - k pi in [-pi/2, pi/2], where sin x = (-1)^k sin r; sin r is the odd series
 * r (1 - r^2/(2 3) (1 - r^2/(4 5) (1 - ...))) to the r^21 term, nested from the inside
 * (truncation below 3e-16 at pi/2). The hand needs a smooth, reproducible path, not the last
 * bit; the checks on it are inequalities, not a stored trajectory. */
static edmi_real tp_sin(edmi_real x)
{
    static const edmi_real pi = EDMI_R(3.14159265358979323846);
    edmi_real h = x / pi, r, r2, s = 1;
    long k = (long)(h < 0 ? h - EDMI_R(0.5) : h + EDMI_R(0.5));
    int i;
    r = x - (edmi_real)k * pi;
    r2 = r * r;
    for (i = 21; i > 1; i -= 2)
        s = 1 - r2 / (edmi_real)((i - 1) * i) * s;
    s *= r;
    return (k % 2 != 0) ? -s : s;
}

/* The hand of TP_COUPLING at time t: through the origin (where the body starts) at t = 0,
 * 20-60 mm excursions at 1, 3 and 7 Hz. */
static void tp_hand(edmi_real t, edmi_real x[3])
{
    static const edmi_real w = EDMI_R(6.283185307179586);
    x[0] = EDMI_R(0.05) * tp_sin(w * t) + EDMI_R(0.02) * tp_sin(EDMI_R(7.0) * w * t);
    x[1] = EDMI_R(0.03) * tp_sin(EDMI_R(3.0) * w * t);
    x[2] = EDMI_R(0.01) * tp_sin(EDMI_R(2.0) * w * t);
}

static edmi_status tp_body(edmi_system *sys, edmi_real m, edmi_real x, edmi_real y, edmi_real z,
                           edmi_real px, edmi_real py, edmi_real pz)
{
    edmi_real q[3], p[3];
    q[0] = x, q[1] = y, q[2] = z;
    p[0] = px, p[1] = py, p[2] = pz;
    return edmi_add_body(sys, m, q, p, 0);
}

static edmi_status tp_anchor(edmi_system *sys, int a, edmi_real x, edmi_real y, edmi_real z,
                             edmi_potential pot)
{
    edmi_real p[3];
    p[0] = x, p[1] = y, p[2] = z;
    return edmi_add_anchor(sys, a, p, &pot, 0);
}

edmi_status tp_build(tp_scene s, const edmi_params *prm, edmi_system *sys, edmi_real *dt)
{
    edmi_params p = *prm;
    edmi_status st;
    p.fallback = 1; /* as a control loop runs it: a failed solve stores the fallback state */
    st = edmi_init(sys, &p);
    static const edmi_real gz[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-9.81)};
    int i;
    tp_seed = 12345UL + (unsigned long)s;
    if (st != EDMI_OK)
        return st;
    switch (s) {
    case TP_SPRING:
        *dt = EDMI_R(1e-3);
        st = tp_body(sys, EDMI_R(10.0), EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0), EDMI_R(-30.0),
                     EDMI_R(15.0), EDMI_R(45.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0)));
        return st;
    case TP_PUMP:
    case TP_RANDOM:
    case TP_FLIP:
        *dt = EDMI_R(1e-3);
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.06), EDMI_R(0.01), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.02), EDMI_R(0.01));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_harmonic(EDMI_R(1e4), EDMI_R(0.05)));
        if (st == EDMI_OK && s == TP_PUMP)
            st = edmi_add_damper(sys, 0, EDMI_R(0.05), 0);
        return st;
    case TP_STIFF: /* float Newton fails here once in a few thousand steps */
        *dt = EDMI_R(0.1);
        st = tp_body(sys, EDMI_R(1.0), EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(300.0), EDMI_R(100.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_harmonic(EDMI_R(1e6), EDMI_R(0.5)));
        return st;
    case TP_COLLIDE: {
        edmi_potential lj = edmi_pot_lj(EDMI_R(100.0), EDMI_R(1.0));
        edmi_potential tether = edmi_pot_harmonic(EDMI_R(50.0), EDMI_R(0.0));
        *dt = EDMI_R(5e-4);
        st = tp_body(sys, EDMI_R(1.0), EDMI_R(-1.5), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(30.0),
                     EDMI_R(0.3), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_body(sys, EDMI_R(1.0), EDMI_R(1.5), EDMI_R(0.05), EDMI_R(0.0),
                         EDMI_R(-30.0), EDMI_R(-0.2), EDMI_R(0.1));
        if (st == EDMI_OK)
            st = edmi_add_pair(sys, 0, 1, &lj, 0);
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(-1.5), EDMI_R(0.0), EDMI_R(0.0), tether);
        if (st == EDMI_OK)
            st = tp_anchor(sys, 1, EDMI_R(1.5), EDMI_R(0.0), EDMI_R(0.0), tether);
        return st;
    }
    case TP_COUPLING:
        *dt = EDMI_R(1e-3);
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_harmonic(EDMI_R(1e3), EDMI_R(0.0)));
        if (st == EDMI_OK)
            st = edmi_add_damper(sys, 0, EDMI_R(0.5), 0);
        return st;
    case TP_CHAIN:
    default: {
        static const edmi_real mass[4] = {EDMI_R(1.0), EDMI_R(2.0), EDMI_R(1.5), EDMI_R(0.5)};
        edmi_potential spring = edmi_pot_neo_hooke(EDMI_R(500.0), EDMI_R(1.0));
        *dt = EDMI_R(1e-3);
        for (i = 0; i < 4 && st == EDMI_OK; i++)
            st = tp_body(sys, mass[i], EDMI_R(0.3) * (edmi_real)(i + 1), EDMI_R(0.0),
                         -EDMI_R(0.9) * (edmi_real)(i + 1), EDMI_R(0.0),
                         EDMI_R(0.5) * (edmi_real)i, EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0), spring);
        for (i = 1; i < 4 && st == EDMI_OK; i++)
            st = edmi_add_pair(sys, i - 1, i, &spring, 0);
        for (i = 0; i < 4 && st == EDMI_OK; i++)
            st = edmi_add_damper(sys, i, EDMI_R(0.2), 0);
        if (st == EDMI_OK)
            st = edmi_set_field(sys, gz);
        return st;
    }
    }
}

int tp_scene_in(tp_scene s)
{
    switch (s) {
    case TP_SPRING:
        return EDMI_WITH_NEO_HOOKE;
    case TP_PUMP:
        return EDMI_WITH_HARMONIC && EDMI_MAX_DAMPERS > 0 && EDMI_WITH_PORTS;
    case TP_RANDOM:
    case TP_FLIP:
        return EDMI_WITH_HARMONIC && EDMI_WITH_PORTS;
    case TP_STIFF:
        return EDMI_WITH_HARMONIC;
    case TP_COLLIDE:
        return EDMI_WITH_LJ && EDMI_WITH_HARMONIC;
    case TP_COUPLING:
        return EDMI_WITH_HARMONIC && EDMI_MAX_DAMPERS > 0;
    case TP_CHAIN:
    default:
        return EDMI_WITH_NEO_HOOKE && EDMI_MAX_DAMPERS > 0 && EDMI_WITH_FIELD &&
               EDMI_WITH_PORTS;
    }
}

void tp_control(tp_scene s, edmi_system *sys, long n)
{
    edmi_real f[3], x[3];
    int i;
    switch (s) {
    case TP_PUMP: { /* F = +c v, |F| <= 2 N: a controller that pumps energy in */
        edmi_real c = EDMI_R(0.3) / sys->body[0].m, mag;
        for (i = 0; i < 3; i++)
            f[i] = c * sys->body[0].p[i];
        mag = EDMI_SQRT(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        if (mag > EDMI_R(2.0))
            for (i = 0; i < 3; i++)
                f[i] *= EDMI_R(2.0) / mag;
        (void)edmi_set_force(sys, 0, f);
        break;
    }
    case TP_RANDOM:
        for (i = 0; i < 3; i++)
            f[i] = EDMI_R(5.0) * tp_rand();
        (void)edmi_set_force(sys, 0, f);
        break;
    case TP_FLIP:
        f[0] = EDMI_R(3.0), f[1] = EDMI_R(2.0), f[2] = EDMI_R(1.0);
        if (n & 1)
            for (i = 0; i < 3; i++)
                f[i] = -f[i];
        (void)edmi_set_force(sys, 0, f);
        break;
    case TP_COUPLING:
        tp_hand((edmi_real)(n + 1) * EDMI_R(1e-3), x);
        (void)edmi_move_anchor(sys, 0, x);
        break;
    case TP_CHAIN:
        for (i = 0; i < 3; i++)
            f[i] = EDMI_R(2.0) * tp_rand();
        (void)edmi_set_force(sys, 3, f);
        break;
    default:
        break;
    }
}

/* Snapshots: systems are tens of kB, too large for a target's stack. */
static edmi_system tp_sys, tp_old;
static edmi_workspace tp_work;

static void tp_j(const edmi_system *s, long double j[3])
{
    int a;
    j[0] = j[1] = j[2] = 0.0L;
    for (a = 0; a < s->n_bodies; a++) {
        long double q0 = (long double)s->body[a].q[0], q1 = (long double)s->body[a].q[1],
                    q2 = (long double)s->body[a].q[2];
        long double p0 = (long double)s->body[a].p[0], p1 = (long double)s->body[a].p[1],
                    p2 = (long double)s->body[a].p[2];
        j[0] += q1 * p2 - q2 * p1;
        j[1] += q2 * p0 - q0 * p2;
        j[2] += q0 * p1 - q1 * p0;
    }
}

/* Whether the reported works of the step from s0 to s1 are at most the exact ones on the
 * stored numbers: work_ext <= sum F . (q1 - q0) (the ports' forces of s0) and work_anchor <=
 * -sum f . (x1 - x0) over the moving anchors of s0 (f the stored link force of s1), each
 * evaluated in tp_q (a product of two stored reals exact) within 8 units of its magnitude. */
static int tp_works_below(const edmi_system *s0, const edmi_system *s1,
                          const edmi_step_result *res)
{
    tp_q wx = (tp_q)0.0, wa = (tp_q)0.0, mx = (tp_q)0.0, ma = (tp_q)0.0;
    int k, i;
    for (k = 0; k < s0->internal.n_forced; k++) {
        int b = s0->internal.forced[k];
        for (i = 0; i < 3; i++) {
            tp_q f = (tp_q)s0->force[b][i], dq = (tp_q)s1->body[b].q[i] - (tp_q)s0->body[b].q[i];
            wx += f * dq;
            mx += tp_absq(f) * (tp_absq((tp_q)s1->body[b].q[i]) + tp_absq((tp_q)s0->body[b].q[i]));
        }
    }
    for (k = 0; k < s0->internal.n_moving; k++) {
        int j = s0->internal.moving[k];
        for (i = 0; i < 3; i++) {
            tp_q f = (tp_q)s1->link_force[j][i];
            tp_q dx = (tp_q)s1->link[j].anchor[i] - (tp_q)s0->link[j].anchor[i];
            wa -= f * dx;
            ma += tp_absq(f) * (tp_absq((tp_q)s1->link[j].anchor[i]) +
                                tp_absq((tp_q)s0->link[j].anchor[i]));
        }
    }
    return (tp_q)res->work_ext <= wx + (tp_q)8.0 * TP_Q_EPS * mx &&
           (tp_q)res->work_anchor <= wa + (tp_q)8.0 * TP_Q_EPS * ma;
}

int tp_port_work_below(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res)
{
    tp_q wx = (tp_q)0.0;
    int k, i;
    for (k = 0; k < s0->internal.n_forced; k++) {
        int b = s0->internal.forced[k];
        for (i = 0; i < 3; i++) /* each product exact in tp_q, the sum of few terms too */
            wx += (tp_q)s0->force[b][i] * ((tp_q)s1->body[b].q[i] - (tp_q)s0->body[b].q[i]);
    }
    return (tp_q)res->work_ext <= wx;
}

void tp_run(tp_scene s, const edmi_params *prm, long n, tp_stats *st)
{
    edmi_real dt;
    long double j0[3], jn;
    long k;
    int track_j = s == TP_SPRING || s == TP_STIFF;
    /* in tp_q: H0 and its scale, the largest (dH - W) / scale, the works and H accumulated
     * (H_n = H_n-1 + dh), and over the steps m so far: min of A_m + T_m and of A_m,
     * A_m = H_m - sum_{k<m} W_k, and the accumulated error of A */
    tp_q h0, scale, worst = (tp_q)-1.0, h_last, max_cap = (tp_q)0.0;
    tp_win win;
    st->steps = st->violations = st->rises = st->uncertain = 0;
    st->fallbacks = st->guarded = st->iterations = st->works_above = 0;
    st->window_violations = st->tank_violations = st->window_beyond_cap = 0;
    st->worst = -1.0L;
    st->sum_w = st->max_dj = st->max_window = st->max_cap = st->window_err = 0.0L;
    st->status = tp_build(s, prm, &tp_sys, &dt);
    if (st->status != EDMI_OK)
        return;
    if (!tp_hq(&tp_sys, &h0))
        h0 = (tp_q)LDBL_MAX;
    scale = tp_absq(h0) > (tp_q)0.0 ? tp_absq(h0) : (tp_q)1.0;
    tp_win_start(&win, h0, (tp_q)tp_sys.tank);
    tp_j(&tp_sys, j0);
    jn = tp_sqrtl(j0[0] * j0[0] + j0[1] * j0[1] + j0[2] * j0[2]);
    for (k = 0; k < n; k++) {
        edmi_step_result res;
        tp_qdelta d;
        tp_q diff;
        tp_control(s, &tp_sys, k);
        tp_old = tp_sys;
        st->status = edmi_step(&tp_sys, &tp_work, dt, &res);
        if (st->status != EDMI_OK)
            break;
        st->steps++;
        st->iterations += res.iterations;
        st->fallbacks += res.stop == EDMI_STOP_FALLBACK;
        st->guarded += res.guard_action != 0;
        if (res.substeps == 1 && res.stop != EDMI_STOP_FALLBACK)
            st->works_above += !tp_works_below(&tp_old, &tp_sys, &res);
        if (!tp_delta_q(&tp_old, &tp_sys, &res, &d)) {
            st->violations++; /* a state the check cannot evaluate is not accepted */
            continue;
        }
        diff = d.dh - d.w;
        st->violations += diff > d.err;
        st->uncertain += tp_absq(diff) <= d.err;
        st->rises += d.dh > d.err;
        if (diff / scale > worst)
            worst = diff / scale;
        st->tank_violations += !(tp_sys.tank >= 0 && tp_sys.tank <= res.tank_cap &&
                                 tp_sys.tank == res.tank);
        if ((tp_q)res.tank_cap / scale > max_cap)
            max_cap = (tp_q)res.tank_cap / scale;
        st->window_violations += !tp_win_add(&win, &d, &res, (tp_q)tp_sys.tank, scale);
        if (track_j && (k & 63) == 0) {
            long double j[3], dj;
            tp_j(&tp_sys, j);
            dj = tp_sqrtl((j[0] - j0[0]) * (j[0] - j0[0]) + (j[1] - j0[1]) * (j[1] - j0[1]) +
                          (j[2] - j0[2]) * (j[2] - j0[2])) / jn;
            if (dj > st->max_dj)
                st->max_dj = dj;
        }
    }
    h_last = win.h_last;
    if (st->status == EDMI_OK) {
        if (!tp_hq(&tp_sys, &h_last))
            h_last = (tp_q)LDBL_MAX;
        st->window_err = (long double)(win.a_err / scale);
        st->window_beyond_cap = win.max_window > max_cap + win.a_err / scale;
    }
    st->h0 = (long double)h0;
    st->h_last = (long double)h_last;
    st->worst = (long double)worst;
    st->sum_w = (long double)win.sum_w;
    st->max_window = (long double)win.max_window;
    st->max_cap = (long double)max_cap;
}

/* ---- rest is a fixed point; user potentials guarded as the built-ins are ------------------- */

const char *tp_rest_name(tp_rest s)
{
    static const char *const names[TP_NREST] = {
        "zero-rest-length spring settling onto its anchor", "body exactly on its anchor, p = 0",
        "neo-Hookean spring settling at its rest length", "pair spring, two bodies settling together",
        "zero-rest-length spring settling onto an anchor at (0.25, -1, 3)",
        "pair spring, masses 0.1 and 0.3, meeting off the origin",
        "user potential = harmonic(50, 1)"};
    return (unsigned)s < (unsigned)TP_NREST ? names[s] : "?";
}

int tp_user_harmonic_fn(void *ctx, edmi_real r, edmi_pot_parts *out)
{
    const tp_user_harmonic *u = (const tp_user_harmonic *)ctx;
    edmi_real x = r - u->r0;
    int j;
    out->c[0] = EDMI_R(0.5) * u->k * x * x;
    out->c[1] = u->k * x;
    out->c[2] = u->k;
    out->c[3] = EDMI_R(0.0);
    out->c[4] = EDMI_R(0.0);
    for (j = 0; j < 5; j++) {
        out->sp[j] = out->c[j];
        out->e[j] = out->sm[j] = EDMI_R(0.0);
    }
    return 0;
}

int tp_user_harmonic_dd(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd, edmi_real *dd_d1)
{
    const tp_user_harmonic *u = (const tp_user_harmonic *)ctx;
    *dd = EDMI_R(0.5) * u->k * ((d1 - u->r0) + (d0 - u->r0));
    *dd_d1 = EDMI_R(0.5) * u->k;
    return 0;
}

int tp_user_builtin_fn(void *ctx, edmi_real r, edmi_pot_parts *out)
{
    return edmi_pot_eval((const edmi_potential *)ctx, r, out) != EDMI_OK;
}

int tp_user_builtin_dd(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd, edmi_real *dd_d1)
{
    return edmi_pot_divdiff((const edmi_potential *)ctx, d0, d1, dd, dd_d1) != EDMI_OK;
}

static tp_user_map tp_user_extra;

void tp_user_register(tp_user_map map) { tp_user_extra = map; }

/* The built-in potential whose V the user potential p's callback computes: 1 and *b, or 0. */
static int tp_user_builtin(const edmi_potential *p, edmi_potential *b)
{
    if (p->fn == tp_user_harmonic_fn) {
        const tp_user_harmonic *u = (const tp_user_harmonic *)p->ctx;
        *b = edmi_pot_harmonic(u->k, u->r0);
        return 1;
    }
    if (p->fn == tp_user_builtin_fn) {
        *b = *(const edmi_potential *)p->ctx;
        return 1;
    }
    return tp_user_extra != 0 && tp_user_extra(p, b);
}

/* TP_REST_USER's potential: the built-in edmi_pot_harmonic(50, 1) written as a user one */
static tp_user_harmonic tp_user_ctx = {EDMI_R(50.0), EDMI_R(1.0)};

edmi_status tp_rest_build(tp_rest s, const edmi_params *prm, int damper, int user_dd,
                          edmi_system *sys, edmi_real *dt)
{
    edmi_potential zero = edmi_pot_harmonic(EDMI_R(1e4), EDMI_R(0.0));
    edmi_status st = edmi_init(sys, prm);
    int j;
    *dt = EDMI_R(1e-3);
    if (st != EDMI_OK)
        return st;
    switch (s) {
    case TP_REST_ANCHOR:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.01), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0), zero);
        break;
    case TP_REST_ON_ANCHOR:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.25), EDMI_R(-1.0), EDMI_R(3.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.25), EDMI_R(-1.0), EDMI_R(3.0), zero);
        break;
    case TP_REST_NEO_HOOKE:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(1.2), EDMI_R(0.3), EDMI_R(-0.1), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(1.0)));
        break;
    case TP_REST_PAIR:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.005), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_body(sys, EDMI_R(0.1), -EDMI_R(0.005), EDMI_R(0.0), EDMI_R(0.0),
                         EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = edmi_add_pair(sys, 0, 1, &zero, 0);
        break;
    case TP_REST_OFF_ANCHOR:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.26), EDMI_R(-1.0), EDMI_R(3.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.25), EDMI_R(-1.0), EDMI_R(3.0), zero);
        break;
    case TP_REST_PAIR_OFF:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.0075), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_body(sys, EDMI_R(0.3), -EDMI_R(0.0025), EDMI_R(0.0), EDMI_R(0.0),
                         EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = edmi_add_pair(sys, 0, 1, &zero, 0);
        break;
    case TP_REST_USER:
    default:
        st = tp_body(sys, EDMI_R(1.0), EDMI_R(1.3), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(2.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_user(tp_user_harmonic_fn, user_dd ? tp_user_harmonic_dd : 0,
                                         &tp_user_ctx));
        break;
    }
    for (j = 0; damper && j < sys->n_links && st == EDMI_OK; j++)
        st = edmi_add_damper(sys, j, EDMI_R(5.0), 0);
    return st;
}

int tp_rest_in(tp_rest s, const edmi_params *prm, int damper, int user_dd)
{
    int pot;
    switch (s) {
    case TP_REST_NEO_HOOKE:
        pot = EDMI_WITH_NEO_HOOKE;
        break;
    case TP_REST_USER:
        pot = EDMI_WITH_USER && EDMI_WITH_HARMONIC &&
              (user_dd || prm->scheme != EDMI_SCHEME_LG || EDMI_WITH_LG_QUOTIENT);
        break;
    default:
        pot = EDMI_WITH_HARMONIC;
        break;
    }
    return pot && (!damper || EDMI_MAX_DAMPERS > 0);
}

/* x 2^e in tp_q, in steps of 2^60, 2^8 and 2: exact wherever the result and the steps are
 * normal (a few operations even where tp_q is soft-float, as on the Cortex-M4F or in
 * binary128) */
static tp_q tp_ldexp(tp_q x, int e)
{
    static const tp_q big = (tp_q)1152921504606846976.0; /* 2^60 */
    while (e >= 60 && x != (tp_q)0.0) {
        x *= big;
        e -= 60;
    }
    while (e <= -60 && x != (tp_q)0.0) {
        x /= big;
        e += 60;
    }
    for (; e >= 8; e -= 8)
        x *= (tp_q)256.0;
    for (; e <= -8; e += 8)
        x *= (tp_q)(1.0 / 256.0);
    for (; e > 0; e--)
        x *= (tp_q)2.0;
    for (; e < 0; e++)
        x *= (tp_q)0.5;
    return x;
}

/* e with 2^(e-1) <= x < 2^e, for x > 0 (exact: only powers of two multiply it) */
static int tp_exponent(tp_q x)
{
    static const tp_q big = (tp_q)1152921504606846976.0, small = (tp_q)(1.0 / 1152921504606846976.0);
    int e = 0;
    while (x >= big) {
        x *= small;
        e += 60;
    }
    while (x < small) {
        x *= big;
        e -= 60;
    }
    for (; x >= (tp_q)256.0; e += 8)
        x *= (tp_q)(1.0 / 256.0);
    for (; x < (tp_q)(1.0 / 256.0); e -= 8)
        x *= (tp_q)256.0;
    for (; x >= (tp_q)1.0; e++)
        x *= (tp_q)0.5;
    for (; x < (tp_q)0.5; e--)
        x *= (tp_q)2.0;
    return e;
}

/* A zero-rest-length harmonic spring: H's part in it is homogeneous of degree 2 in (r, p). */
static int tp_homogeneous(const edmi_potential *p)
{
    return p->kind == EDMI_POT_HARMONIC && p->b == 0;
}

/* V of a link that is not homogeneous, unscaled (tp_pot) */
static int tp_rest_pot(const edmi_potential *p, const tp_q r[3], tp_q *v, tp_q *mag)
{
    tp_q s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    return tp_pot(p, s, tp_sqrtq(s), v, mag);
}

int tp_rest_delta(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res,
                  long double *excess, int *exponent)
{
    const edmi_system *st[2];
    tp_q big = (tp_q)0.0, hs = (tp_q)0.0, ms = (tp_q)0.0, hu = (tp_q)0.0, mu = (tp_q)0.0;
    tp_q f1, f2, t[3], wt, r[3], x;
    int a, i, j, k, s, e;
    st[0] = s0;
    st[1] = s1;
    if (s0->has_field || s0->n_bodies != s1->n_bodies || s0->n_links != s1->n_links)
        return 0;
    /* s: the largest |p| and |r| of the homogeneous links, and sqrt of T and |W|, to ~1 */
    for (k = 0; k < 2; k++) {
        for (a = 0; a < st[k]->n_bodies; a++)
            for (i = 0; i < 3; i++)
                if (tp_absq((tp_q)st[k]->body[a].p[i]) > big)
                    big = tp_absq((tp_q)st[k]->body[a].p[i]);
        for (j = 0; j < st[k]->n_links; j++)
            if (tp_homogeneous(&st[k]->link[j].pot)) {
                tp_link_vec(st[k], j, r);
                for (i = 0; i < 3; i++)
                    if (tp_absq(r[i]) > big)
                        big = tp_absq(r[i]);
            }
    }
    e = big > (tp_q)0.0 ? tp_exponent(big) : INT_MIN / 4;
    t[0] = (tp_q)s0->tank;
    t[1] = (tp_q)s1->tank;
    t[2] = tp_absq((tp_q)res->work_ext + (tp_q)res->work_anchor);
    wt = t[0] > t[1] ? t[0] : t[1];
    wt = wt > t[2] ? wt : t[2];
    if (wt > (tp_q)0.0) {
        int et = tp_exponent(wt);
        et = et > 0 ? (et + 1) / 2 : et / 2; /* ceil(et / 2) */
        e = et > e ? et : e;
    }
    s = e == INT_MIN / 4 ? 0 : -e;
    /* 2^s as two factors within double's exponent range (|s| <= 1075 + 60) */
    f1 = tp_ldexp((tp_q)1.0, s / 2);
    f2 = tp_ldexp((tp_q)1.0, s - s / 2);
    /* the scaled part: K, the homogeneous links, T and W, in units of 2^-2s */
    for (a = 0; a < s0->n_bodies; a++) {
        tp_q k2 = (tp_q)0.0, km = (tp_q)0.0, m2 = (tp_q)2.0 * (tp_q)s0->body[a].m;
        for (i = 0; i < 3; i++) {
            tp_q p0 = (tp_q)s0->body[a].p[i] * f1 * f2;
            tp_q p1 = (tp_q)s1->body[a].p[i] * f1 * f2;
            k2 += (p1 - p0) * (p1 + p0);
            km += tp_absq(p1 - p0) * (tp_absq(p1) + tp_absq(p0));
        }
        hs += k2 / m2;
        ms += (tp_q)8.0 * km / m2;
    }
    for (j = 0; j < s0->n_links; j++) {
        const edmi_potential *p = &s0->link[j].pot;
        if (tp_homogeneous(p)) {
            tp_q v[2];
            for (k = 0; k < 2; k++) {
                tp_link_vec(st[k], j, r);
                for (i = 0; i < 3; i++)
                    r[i] = r[i] * f1 * f2;
                v[k] = (tp_q)0.5 * (tp_q)p->a * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            }
            hs += v[1] - v[0];
            ms += (tp_q)16.0 * (v[0] + v[1]);
        } else {
            tp_q v0, v1, m0, m1;
            tp_link_vec(s0, j, r);
            if (!tp_rest_pot(p, r, &v0, &m0))
                return 0;
            tp_link_vec(s1, j, r);
            if (!tp_rest_pot(&s1->link[j].pot, r, &v1, &m1))
                return 0;
            hu += v1 - v0;
            mu += m0 + m1;
        }
    }
    for (i = 0; i < 3; i++)
        t[i] = t[i] * f1 * f1 * f2 * f2;
    hs -= ((tp_q)res->work_ext + (tp_q)res->work_anchor) * f1 * f1 * f2 * f2 + (t[0] - t[1]);
    ms += t[0] + t[1] + t[2];
    /* the check's own rounding (as tp_delta_h: 16 eps of the terms), and what underflowed */
    ms = TP_ERR_ULPS * TP_Q_EPS * ms + TP_Q_MIN;
    mu = TP_ERR_ULPS * TP_Q_EPS * mu;
    if (hu == (tp_q)0.0 && mu == (tp_q)0.0) {
        x = hs - ms;
        *exponent = -2 * s;
    } else { /* an unscaled part: combine in unscaled units */
        x = hu - mu + tp_ldexp(hs - ms, -2 * s) - TP_Q_MIN;
        *exponent = 0;
    }
    *excess = (long double)x;
    return x - x == (tp_q)0.0 && x <= (tp_q)0.0;
}

/* |r| without underflow: the largest component times the norm of r over it */
static tp_q tp_norm_scaled(const tp_q r[3])
{
    tp_q m = tp_absq(r[0]), x, y, z;
    m = tp_absq(r[1]) > m ? tp_absq(r[1]) : m;
    m = tp_absq(r[2]) > m ? tp_absq(r[2]) : m;
    if (m == (tp_q)0.0)
        return (tp_q)0.0;
    x = r[0] / m, y = r[1] / m, z = r[2] / m;
    return m * tp_sqrtq(x * x + y * y + z * z);
}

/* How far scene s is from rest: its link's length, or that length's distance from the rest
 * length (neo-Hookean spring, user potential). */
static long double tp_rest_dist(tp_rest s, const edmi_system *sys)
{
    tp_q r[3], d;
    tp_link_vec(sys, 0, r);
    d = tp_norm_scaled(r);
    if (s == TP_REST_NEO_HOOKE || s == TP_REST_USER)
        d = tp_absq(d - (tp_q)1.0); /* both rest lengths are 1 */
    return (long double)d;
}

/* H of a state of a tp_rest scene (no field), in tp_q: for the user potential's energies,
 * O(1) (no scaling) */
static long double tp_rest_h(const edmi_system *s)
{
    tp_q h = (tp_q)0.0, r[3], v, m;
    int a, i, j;
    for (a = 0; a < s->n_bodies; a++)
        for (i = 0; i < 3; i++)
            h += (tp_q)s->body[a].p[i] * (tp_q)s->body[a].p[i] / ((tp_q)2.0 * (tp_q)s->body[a].m);
    for (j = 0; j < s->n_links; j++) {
        tp_link_vec(s, j, r);
        if (tp_homogeneous(&s->link[j].pot))
            h += (tp_q)0.5 * (tp_q)s->link[j].pot.a * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        else if (tp_rest_pot(&s->link[j].pot, r, &v, &m))
            h += v;
    }
    return (long double)h;
}

long double tp_rest_bound(tp_rest s, long double qmax)
{
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
    const long double sigma = 4.9406564584124654e-324L; /* 2^-1074 */
#else
    const long double sigma = 1.4012984643248171e-45L; /* 2^-149 */
#endif
    if (s == TP_REST_NEO_HOOKE)
        return 4.0L * (long double)EDMI_EPS;
    return s == TP_REST_USER ? LDBL_MAX : 64.0L * sigma + 16.0L * (long double)EDMI_EPS * qmax;
}

static int tp_guard_on(const edmi_params *p)
{
    return p->guard == EDMI_GUARD_ON ||
           (p->guard == EDMI_GUARD_AUTO && p->scheme != EDMI_SCHEME_MP && p->scheme != EDMI_SCHEME_LG);
}

static edmi_system tp_ref;

void tp_rest_run(tp_rest s, const edmi_params *prm, int damper, int user_dd, long n,
                 tp_rest_stats *st)
{
    edmi_real dt;
    long k;
    int i, guard = tp_guard_on(prm);
    st->steps = st->fallbacks = st->scaled = st->stops = st->guarded = 0;
    st->uncertified = st->violations = st->tank_violations = 0;
    st->fail_step = st->last_change = -1;
    st->dist = st->tail_dist = st->qmax = st->ref_diff = st->ref_amp = 0.0L;
    st->ref_status = EDMI_OK;
    st->ref_guarded = 0;
    st->status = tp_rest_build(s, prm, damper, user_dd, &tp_sys, &dt);
    if (st->status != EDMI_OK)
        return;
    if (s == TP_REST_USER) { /* the reference: the built-in potential, the same parameters */
        edmi_potential h = edmi_pot_harmonic(tp_user_ctx.k, tp_user_ctx.r0);
        tp_ref = tp_sys;
        tp_ref.link[0].pot = h;
    }
    st->h0 = tp_rest_h(&tp_sys);
    tp_old = tp_sys; /* then only what a step changes and tp_rest_delta reads: bodies, tank */
    for (k = 0; k < n; k++) {
        edmi_step_result res;
        long double excess, d;
        int exponent;
        memcpy(tp_old.body, tp_sys.body, (size_t)tp_sys.n_bodies * sizeof tp_sys.body[0]);
        tp_old.tank = tp_sys.tank;
        st->status = edmi_step(&tp_sys, &tp_work, dt, &res);
        if (st->status != EDMI_OK) {
            st->fail_step = k;
            for (i = 0; i < 3; i++) {
                st->fail_q[i] = tp_sys.body[0].q[i];
                st->fail_p[i] = tp_sys.body[0].p[i];
            }
            st->fail_tank = tp_sys.tank;
            break;
        }
        st->steps++;
        st->fallbacks += res.stop == EDMI_STOP_FALLBACK;
        st->scaled += res.certificate == EDMI_CERT_SCALED;
        st->stops += (res.guard_action & EDMI_MOVE_STOP) != 0;
        st->guarded += res.guard_action != 0;
        if (memcmp(tp_old.body, tp_sys.body, (size_t)tp_sys.n_bodies * sizeof tp_sys.body[0]))
            st->last_change = k;
        if (guard) {
            st->uncertified += res.certificate == EDMI_CERT_NONE;
            st->tank_violations += !(tp_sys.tank >= 0 && tp_sys.tank <= res.tank_cap &&
                                     tp_sys.tank == res.tank);
        }
        st->violations += !tp_rest_delta(&tp_old, &tp_sys, &res, &excess, &exponent);
        d = tp_rest_dist(s, &tp_sys);
        if (k >= n - n / 4) {
            int a, j;
            st->tail_dist = d > st->tail_dist ? d : st->tail_dist;
            for (a = 0; a < tp_sys.n_bodies; a++)
                for (i = 0; i < 3; i++)
                    if (tp_absl((long double)tp_sys.body[a].q[i]) > st->qmax)
                        st->qmax = tp_absl((long double)tp_sys.body[a].q[i]);
            for (j = 0; j < tp_sys.n_links; j++)
                for (i = 0; tp_sys.link[j].b == EDMI_ANCHOR && i < 3; i++)
                    if (tp_absl((long double)tp_sys.link[j].anchor[i]) > st->qmax)
                        st->qmax = tp_absl((long double)tp_sys.link[j].anchor[i]);
        }
        if (s == TP_REST_USER) {
            tp_q r[3];
            long double x;
            edmi_step_result rr;
            st->ref_status = edmi_step(&tp_ref, &tp_work, dt, &rr);
            st->ref_guarded += rr.guard_action != 0;
            if (st->ref_status != EDMI_OK)
                break;
            for (i = 0; i < 3; i++)
                r[i] = (tp_q)tp_sys.body[0].q[i] - (tp_q)tp_ref.body[0].q[i];
            x = (long double)tp_norm_scaled(r);
            st->ref_diff = x > st->ref_diff ? x : st->ref_diff;
            for (i = 0; i < 3; i++)
                r[i] = (tp_q)tp_ref.body[0].q[i];
            x = (long double)tp_norm_scaled(r);
            st->ref_amp = x > st->ref_amp ? x : st->ref_amp;
        }
    }
    st->dist = tp_rest_dist(s, &tp_sys);
    st->h_end = tp_rest_h(&tp_sys);
    st->h_ref_end = s == TP_REST_USER ? tp_rest_h(&tp_ref) : st->h_end;
}

/* ---- OK means solved: the scheme's residual at a stored state --------------------------- */

static edmi_system tp_one;
static edmi_real tp_q1[EDMI_MAX_BODIES][3], tp_p1[EDMI_MAX_BODIES][3];
static edmi_real tp_rq[EDMI_MAX_BODIES][3], tp_rp[EDMI_MAX_BODIES][3];
static edmi_real tp_kmat[9 * EDMI_MAX_BODIES * EDMI_MAX_BODIES];
static long double tp_qm[EDMI_MAX_BODIES], tp_pm[EDMI_MAX_BODIES];

static long double tp_n3l(const edmi_real *v)
{
    long double x = v[0], y = v[1], z = v[2];
    return tp_sqrtl(x * x + y * y + z * z);
}

/* Row a of M summed (m_a plus the off-diagonal masses). */
static long double tp_mass_row(const edmi_system *s, int a)
{
    long double m = s->body[a].m;
#if EDMI_MAX_MASS_GAP > 0
    int b;
    for (b = 0; b < s->n_bodies; b++) {
        int hi = a > b ? a : b, k = (a > b ? a - b : b - a) - 1;
        if (b != a && k < EDMI_MAX_MASS_GAP)
            m += s->mass_off[hi][k];
    }
#endif
    return m;
}

/* Link j's far end before (s0) and after (s: the anchor where s has it). */
static void tp_ends(const edmi_system *s0, const edmi_system *s, int j, edmi_real r0[3],
                    edmi_real r1[3], const edmi_real **xb1)
{
    const edmi_link *lk = &s0->link[j];
    const edmi_real *xb0 = lk->b == EDMI_ANCHOR ? lk->anchor : s0->body[lk->b].q;
    int i;
    *xb1 = lk->b == EDMI_ANCHOR ? s->link[j].anchor : tp_q1[lk->b];
    for (i = 0; i < 3; i++) {
        r0[i] = s0->body[lk->a].q[i] - xb0[i];
        r1[i] = tp_q1[lk->a][i] - (*xb1)[i];
    }
}

/* The largest entry of the tangent of tp_one (one link or wall of a system of n bodies) at
 * the trial state tp_q1, tp_p1 into *k; 0 if edmi_tangent refuses it. */
static int tp_kmax(edmi_workspace *work, edmi_real dt, int n, long double *k)
{
    int i;
    if (edmi_tangent(&tp_one, work, dt, (const edmi_real (*)[3])tp_q1,
                     (const edmi_real (*)[3])tp_p1, tp_kmat) != EDMI_OK)
        return 0;
    for (i = 0; i < 9 * n * n; i++)
        if (tp_absl((long double)tp_kmat[i]) > *k)
            *k = tp_absl((long double)tp_kmat[i]);
    return 1;
}

long double tp_solved(const edmi_system *s0, const edmi_system *s, edmi_real dt,
                      edmi_workspace *work, edmi_status *status, int *body, int *which)
{
    const long double eps = (long double)EDMI_EPS;
    const long double tiny = 16.0L * (sizeof(edmi_real) == sizeof(float) ? (long double)FLT_MIN
                                                                            : (long double)DBL_MIN);
    long double ldt = (long double)dt, worst = 0.0L;
    int n = s0->n_bodies, a, i, j, sw;
    *body = -1;
    *which = 0;
    for (a = 0; a < n; a++)
        for (i = 0; i < 3; i++) {
            tp_q1[a][i] = s->body[a].q[i];
            tp_p1[a][i] = s->body[a].p[i];
        }
    *status = edmi_residual(s0, work, dt, (const edmi_real (*)[3])tp_q1,
                            (const edmi_real (*)[3])tp_p1, tp_rq, tp_rp, &sw);
    if (*status != EDMI_OK)
        return -1.0L;
    for (a = 0; a < n; a++) {
        long double pn = tp_n3l(s0->body[a].p) + tp_n3l(tp_p1[a]);
        tp_qm[a] = tp_n3l(s0->body[a].q) + tp_n3l(tp_q1[a]) + ldt / s0->body[a].m * pn + tiny;
        tp_pm[a] = pn + ldt * tp_absl(tp_mass_row(s0, a)) * (s0->has_field ? tp_n3l(s0->g) : 0) +
                   tiny;
    }
#if EDMI_MAX_MASS_GAP > 0
    for (a = 0; a < n; a++)
        for (j = 0; j < n; j++) {
            int hi = a > j ? a : j, k = (a > j ? a - j : j - a) - 1;
            if (j != a && k < EDMI_MAX_MASS_GAP)
                tp_qm[a] += tp_absl((long double)s0->mass_off[hi][k]) / s0->body[a].m *
                            (tp_n3l(s0->body[j].q) + tp_n3l(tp_q1[j]));
        }
#endif
    for (i = 0; i < s0->internal.n_forced; i++)
        tp_pm[s0->internal.forced[i]] += ldt * tp_n3l(s0->force[s0->internal.forced[i]]);
    for (j = 0; j < s0->n_links; j++) { /* the impulse, and each link's tangent alone */
        const edmi_link *lk = &s0->link[j];
        const edmi_real *xb1;
        edmi_real r0[3], r1[3];
        long double f = 4.0L * ldt * tp_n3l(s->link_force[j]), k = 0.0L, rm[3], x;
        tp_pm[lk->a] += f;
        if (lk->b != EDMI_ANCHOR)
            tp_pm[lk->b] += f;
        tp_one = *s0;
        tp_one.link[0] = *lk;
        tp_one.n_links = 1;
        tp_one.n_dampers = 0;
#if EDMI_MAX_WALLS > 0
        tp_one.n_walls = 0;
#endif
        tp_one.internal.n_moving = 0;
        for (i = 0; i < s0->internal.n_moving; i++)
            if (s0->internal.moving[i] == j) {
                tp_one.internal.n_moving = 1;
                tp_one.internal.moving[0] = 0;
                for (a = 0; a < 3; a++)
                    tp_one.internal.anchor_next[0][a] = s0->internal.anchor_next[j][a];
            }
        if (!tp_kmax(work, dt, n, &k))
            continue;
        if (lk->pot.kind == EDMI_POT_HARMONIC && lk->pot.b == 0 && /* V = k/2 r^2: its GE */
            ldt * tp_absl((long double)lk->pot.a) > k)              /* split's kink at r = 0 */
            k = ldt * tp_absl((long double)lk->pot.a);
        tp_ends(s0, s, j, r0, r1, &xb1);
        for (i = 0; i < 3; i++)
            rm[i] = 0.5L * ((long double)r0[i] + (long double)r1[i]);
        x = 12.0L * k * (tp_sqrtl(rm[0] * rm[0] + rm[1] * rm[1] + rm[2] * rm[2]) + tp_qm[lk->a] +
                         (lk->b == EDMI_ANCHOR ? tp_n3l(xb1) : tp_qm[lk->b]));
        tp_pm[lk->a] += x;
        if (lk->b != EDMI_ANCHOR)
            tp_pm[lk->b] += x;
    }
#if EDMI_MAX_WALLS > 0
    for (j = 0; j < s0->n_walls; j++) { /* as a link to the plane */
        const edmi_wall *wl = &s0->wall[j];
        long double k = 0.0L;
        a = wl->a;
        tp_pm[a] += 4.0L * ldt * tp_n3l(s->wall_force[j]);
        tp_one = *s0;
        tp_one.wall[0] = *wl;
        tp_one.n_walls = 1;
        tp_one.n_links = 0;
        tp_one.n_dampers = 0;
        tp_one.internal.n_moving = 0;
        if (!tp_kmax(work, dt, n, &k))
            continue;
        if (wl->pot.kind == EDMI_POT_HARMONIC && ldt * (long double)wl->pot.a > k)
            k = ldt * (long double)wl->pot.a;
        tp_pm[a] += 12.0L * k * (tp_n3l(tp_q1[a]) + tp_absl((long double)wl->c) + tp_qm[a]);
    }
#endif
    for (j = 0; j < s0->n_dampers && j < EDMI_DAMPER_SLOTS_; j++) {
        const edmi_link *lk = &s0->link[s0->damper[j].link];
        const edmi_real *xb1;
        edmi_real r0[3], r1[3];
        long double x;
        tp_ends(s0, s, s0->damper[j].link, r0, r1, &xb1);
        x = 4.0L * (long double)s0->damper[j].c *
            (tp_n3l(r0) + tp_n3l(r1) + tp_qm[lk->a] +
             (lk->b == EDMI_ANCHOR ? tp_n3l(xb1) : tp_qm[lk->b]));
        tp_pm[lk->a] += x;
        if (lk->b != EDMI_ANCHOR)
            tp_pm[lk->b] += x;
    }
    if (s0->params.scheme == EDMI_SCHEME_LG)
        for (j = 0; j < s0->n_links; j++) { /* the quotient's cancellation, where it is used */
            const edmi_link *lk = &s0->link[j];
            const edmi_real *xb1;
            edmi_real r0[3], r1[3];
            edmi_pot_parts v0, v1;
            long double d0, d1, gap, vv = LDBL_MAX, x = LDBL_MAX;
            tp_q w0, w1, m;
            if ((lk->pot.kind != EDMI_POT_USER || lk->pot.dd != 0) &&
                s0->params.lg_form == EDMI_LG_CLOSED)
                continue;
            tp_ends(s0, s, j, r0, r1, &xb1);
            d0 = tp_n3l(r0);
            d1 = tp_n3l(r1);
            /* the library forms d1 - d0 from lengths rounded in its precision */
            gap = tp_absl(d1 - d0) - 4.0L * eps * (d0 + d1);
            if (lk->pot.kind != EDMI_POT_USER) { /* V here: its parts can overflow where V not */
                if (tp_pot(&lk->pot, (tp_q)d0 * (tp_q)d0, (tp_q)d0, &w0, &m) &&
                    tp_pot(&lk->pot, (tp_q)d1 * (tp_q)d1, (tp_q)d1, &w1, &m))
                    vv = (long double)(tp_absq(w0) + tp_absq(w1));
            } else if (edmi_pot_eval(&lk->pot, (edmi_real)d0, &v0) == EDMI_OK &&
                       edmi_pot_eval(&lk->pot, (edmi_real)d1, &v1) == EDMI_OK) {
                vv = tp_absl((long double)v0.v[0]) + tp_absl((long double)v1.v[0]);
            }
            if (gap > 0.0L && vv < LDBL_MAX) /* else unbounded: nothing to judge by */
                x = ldt * vv / gap;
            tp_pm[lk->a] += x;
            if (lk->b != EDMI_ANCHOR)
                tp_pm[lk->b] += x;
        }
    for (a = 0; a < n; a++) {
        long double xq = tp_n3l(tp_rq[a]) / (eps * tp_qm[a]);
        long double xp = tp_n3l(tp_rp[a]) / (eps * tp_pm[a]);
        if (!(xq <= worst)) {
            worst = xq;
            *body = a;
            *which = 0;
        }
        if (!(xp <= worst)) {
            worst = xp;
            *body = a;
            *which = 1;
        }
    }
    return worst;
}
