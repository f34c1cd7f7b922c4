/* mass_spd: consistent mass matrices that are positive definite but NOT diagonally dominant
 * (issue 20: Rump's certified bound on lambda_min(M) in the guard and in the validation).
 *
 * Built by the Makefile with MASS_SPD_CFG (EDMI_MAX_BODIES = 4, EDMI_MAX_MASS_GAP = 3: every
 * pair of 4 bodies may be coupled; the dense 12 x 12 Newton matrix fits the default
 * EDMI_MAX_MATRIX), on the host under ASan+UBSan in both precisions and on the emulated
 * Cortex-M4F (float) and M7 (double) (port/target.mk). Two scenes, free in space (no
 * anchors, no field, no work), vibrating and rotating, with the consistent mass matrix of a
 * linear element:
 *   TRI  3 bodies, 3 harmonic springs (k 100, r0 1) on an equilateral triangle of side 1,
 *        M = (m/12) [2 1 1; 1 2 1; 1 1 2], m = 1.2: eigenvalues m/12 x {4, 1, 1}, kappa 4;
 *        the rows are not dominant (0.2 = 0.1 + 0.1).
 *   TET  4 bodies, 6 neo-Hookean springs (c 100, rb 1) on a regular tetrahedron of side 1,
 *        M = (m/20) [2 1 1 1; ...], m = 1.2: eigenvalues m/20 x {5, 1, 1, 1}, kappa 5;
 *        0.12 < 3 x 0.06.
 * Linearised about the regular shapes, the vibration frequencies (the generalized eigenproblem
 * K v = w^2 (M x I3) v, solved with mpmath) are 38.7 (x2) and 54.8 rad/s for TRI, 40.8 (x2),
 * 57.7 (x3) and 81.6 rad/s for TET: at dt = 2e-3, omega dt = 0.08 to 0.16. Both spin at
 * 6 rad/s about a tilted axis and drift. TRI's harmonic springs make LG, PM and PT one
 * energy-conserving force (V''' = 0: no perturbation, and the divided difference of a
 * quadratic in d is V' at the mean distance), so three of its runs stress the tank with
 * round-off alone; TET's neo-Hookean springs tell all five schemes apart.
 *
 * Each scene runs 4000 steps with every scheme (MP and LG with EDMI_GUARD_ON, GE, PM and PT
 * with the guard on by default), and every stored step is checked against a truth evaluated
 * here, independently of the library (no edmi code, no tests/lib/passive.c, whose coupled K needs
 * a dominant M): K(p1) - K(p0) = 1/2 (p1 - p0) . M^-1 (p1 + p0) by Gaussian elimination on
 * the dense M, V by the potentials' textbook formulas, in MS_Q: __float128 on the host (GCC's
 * quad type, libgcc's soft arithmetic; a square root by Newton's iteration), long double
 * elsewhere (= double on Arm EABI), with a bound on the truth's own rounding (MS_Q_U units
 * times the terms' magnitudes, kappa(M) in closed form). Checked:
 *   - every step returns EDMI_OK (no fallback: params.fallback is 0, so a failed solve, a
 *     PASSIVITY included, would be returned), reported with its step and status;
 *   - the tank identity H_n+1 - H_n <= T_n - T_n+1 (no work is done) on every step, beyond
 *     the truth's resolution; steps within it are counted as unresolved (on the M7 the
 *     truth is double like the states, and most steps are);
 *   - windows: H_n - H_m <= T_m for every m < n (H from each state afresh, the running
 *     minimum of H_m + T_m), and 0 <= T_n <= res.tank_cap, T_n == res.tank;
 *   - L = sum p, the centre-of-mass invariant C = (1^T M q - t L) / 1^T M 1 and
 *     J = sum q x p conserved to round-off on every step, every scheme (each pair force acts
 *     along r_n+1/2; the guard's impulses keep all three, its rounding moves them by a few
 *     units, its drags, counted and never seen here, would keep L and C only);
 *   - refusals: a symmetric M that is indefinite, and one that is definite but too nearly
 *     singular for a working-precision Cholesky to prove it, are refused by
 *     edmi_set_mass_coupling (system bit-identical) and edmi_load_scene (EDMI_ERR_MASS).
 * Reported per run: failures, steps H rose (within the tank), unresolved steps, steps the
 * guard changed, the largest window rise against the tank's capacity, L, C and J drifts.
 * No stdio (the harness's output hook): the same source runs under QEMU. Closing line
 * "N passed, N failed". */
#include <float.h>
#include <string.h>

#include "harness.h"

#if EDMI_MAX_MASS_GAP < 3 || EDMI_MAX_BODIES < 4
#error "mass_spd needs EDMI_MAX_BODIES >= 4 and EDMI_MAX_MASS_GAP >= 3 (MASS_SPD_CFG)"
#endif

/* ---- the truth's arithmetic --------------------------------------------------------------- */

/* MS_Q: __float128 where GCC offers it with libgcc's soft arithmetic (x86-64), else long
 * double. MS_Q_U is its unit roundoff: 2^-113 for binary128, LDBL_EPSILON/2 otherwise (2^-64
 * on x87, 2^-53 on Arm EABI where long double is double). */
#if defined(__SIZEOF_FLOAT128__) && defined(__x86_64__) && !defined(MS_NO_FLOAT128)
__extension__ typedef __float128 ms_q;
#define MS_QUAD 1
/* 2^-113, built from exact powers of two (no Q literal suffix in C99) */
#define MS_Q_U ((ms_q)1.0 / ((ms_q)72057594037927936.0 * (ms_q)144115188075855872.0))
#else
typedef long double ms_q;
#define MS_QUAD 0
#define MS_Q_U ((ms_q)LDBL_EPSILON / (ms_q)2.0)
#endif

/* The truth's rounding bounds, in units of MS_Q_U times a magnitude:
 * MS_V_ULPS for a potential's value: the link vector's components are differences of stored
 * reals (exact in binary128, within u of themselves in long double), their sum of squares
 * errs by 4u of itself and the square root adds 2u (Newton's iteration from a long double
 * seed, or a correctly rounded sqrtl): d within 8u d; V's formulas then err by |V'(d)| 8u d
 * plus a few u of V, both inside the magnitude ms_pot returns (which bounds |V'| d and V);
 * 32 u of it leaves a factor 2 over the dozen roundings, as tests/lib/passive.c does.
 * MS_K_ULPS(n, kappa) for K's change 1/2 d . x, x = M^-1 s by Gaussian elimination without
 * pivoting on the symmetric positive definite M (n bodies, 3 right-hand sides): the computed
 * x solves (M + E) x = s with |E| <= gamma_3n |L| |U| (Higham, Accuracy and Stability of
 * Numerical Algorithms, 2nd ed., Thm 9.4), and for a symmetric M without pivoting |L| |U| =
 * (|L| D^1/2) (|L| D^1/2)^T, whose 2-norm is at most ||L D^1/2||_F^2 = tr(M) (1 + O(u)) <=
 * n lambda_max (the argument of Thm 10.3), so ||x - M^-1 s|| <= 3 n^2 u kappa ||x|| (1 + O(u));
 * d and s carry u of themselves each and the dot product's n-term sums 3n u: all within
 * (4 n^2 kappa + 8 n) u ||d|| ||x|| / 2, the magnitude ms_kin reports being ||d|| ||x|| / 2. */
#define MS_V_ULPS 32
#define MS_K_ULPS(n, kappa) (4.0L * (long double)((n) * (n)) * (kappa) + 8.0L * (long double)(n))
/* Summing the terms of H or of its change (at most 1 + 6 + 6 = 13 terms) and comparing with
 * the tank's change: 16 u of every term's magnitude and of both tank levels. */
#define MS_SUM_ULPS 16

static ms_q ms_abs(ms_q x) { return x < (ms_q)0.0 ? -x : x; }

/* sqrt(x), x >= 0: a long double seed, then (binary128) two Newton steps, each squaring the
 * seed's relative error (2^-64 -> 2^-127) and adding ~1.5 u of rounding: within 2u. */
static ms_q ms_sqrt(ms_q x)
{
    ms_q y;
    if (!(x > (ms_q)0.0))
        return (ms_q)0.0;
    y = (ms_q)__builtin_sqrtl((long double)x);
#if MS_QUAD
    y = (ms_q)0.5 * (y + x / y);
    y = (ms_q)0.5 * (y + x / y);
#endif
    return y;
}

/* ---- the scenes --------------------------------------------------------------------------- */

typedef enum ms_scene_id { MS_TRI = 0, MS_TET, MS_NSCENES } ms_scene_id;

#define MS_M EDMI_R(1.2)          /* element mass */
#define MS_K EDMI_R(100.0)        /* spring constant (harmonic k, neo-Hooke c) */
#define MS_DT EDMI_R(2e-3)        /* omega dt 0.08 to 0.16 (the frequencies above) */
#define MS_STEPS 4000             /* 8 s: 49 periods of the slowest mode, 7.7 turns of the spin */

static const char *const ms_scene_names[MS_NSCENES] = {"TRI", "TET"};
static const char *const ms_scheme_names[] = {"MP", "LG", "GE", "PM", "PT"};
static const int ms_nb[MS_NSCENES] = {3, 4};
/* kappa(M) in closed form (above), with a margin for the stored entries' rounding: each is
 * within eps/2 of m/12 or m/20 in relative terms, which moves an eigenvalue by at most
 * n eps/2 max|m_ab|, a relative 1e-6 in float: 1 % is ample. */
static const long double ms_kappa[MS_NSCENES] = {4.0L * 1.01L, 5.0L * 1.01L};

/* Positions near the regular shapes of side 1 (off them by up to 3 %: the springs start
 * stretched and vibrate), drift velocity and spin about the centroid. */
static const edmi_real ms_q0[MS_NSCENES][4][3] = {
    {{EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)},
     {EDMI_R(1.02), EDMI_R(0.0), EDMI_R(0.01)},
     {EDMI_R(0.5), EDMI_R(0.85), EDMI_R(-0.01)},
     {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)}},
    {{EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)},
     {EDMI_R(1.0), EDMI_R(0.02), EDMI_R(0.0)},
     {EDMI_R(0.49), EDMI_R(0.87), EDMI_R(-0.01)},
     {EDMI_R(0.5), EDMI_R(0.28), EDMI_R(0.84)}}};
static const edmi_real ms_drift[3] = {EDMI_R(0.3), EDMI_R(-0.2), EDMI_R(0.1)};
static const edmi_real ms_spin[3] = {EDMI_R(0.5), EDMI_R(-0.3), EDMI_R(6.0)}; /* rad/s */

static edmi_system ms_sys, ms_old, ms_copy, ms_built;
static edmi_workspace ms_work;

/* The consistent mass of a linear simplex element of mass m with n nodes: m_aa = 2 m/(n (n+1))
 * and m_ab = m/(n (n+1)), m/12 x {2, 1} for the triangle (n = 3) and m/20 x {2, 1} for the
 * tetrahedron (n = 4); each row sums to m/n. */
static edmi_real ms_diag(int n) { return EDMI_R(2.0) * MS_M / (edmi_real)(n * (n + 1)); }
static edmi_real ms_off(int n) { return MS_M / (edmi_real)(n * (n + 1)); }

/* The scene with scheme s: bodies, springs on every pair, the consistent couplings (each
 * call must succeed: *refused counts those that did not), momenta p = M v of the drift plus
 * the spin about the centroid. */
static edmi_status ms_build(ms_scene_id sc, edmi_scheme s, int *refused)
{
    edmi_params prm = edmi_default_params();
    const int n = ms_nb[sc];
    edmi_potential pot = sc == MS_TRI ? edmi_pot_harmonic(MS_K, EDMI_R(1.0))
                                      : edmi_pot_neo_hooke(MS_K, EDMI_R(1.0));
    edmi_real v[4][3], cen[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    const edmi_real md = ms_diag(n), mo = ms_off(n);
    edmi_status st;
    int a, b, c;
    prm.scheme = s;
    if (s == EDMI_SCHEME_MP || s == EDMI_SCHEME_LG)
        prm.guard = EDMI_GUARD_ON;
    *refused = 0;
    st = edmi_init(&ms_sys, &prm);
    for (a = 0; a < n; a++)
        for (c = 0; c < 3; c++)
            cen[c] += ms_q0[sc][a][c] / (edmi_real)n;
    for (a = 0; a < n; a++) {
        edmi_real r[3];
        for (c = 0; c < 3; c++)
            r[c] = ms_q0[sc][a][c] - cen[c];
        v[a][0] = ms_drift[0] + ms_spin[1] * r[2] - ms_spin[2] * r[1];
        v[a][1] = ms_drift[1] + ms_spin[2] * r[0] - ms_spin[0] * r[2];
        v[a][2] = ms_drift[2] + ms_spin[0] * r[1] - ms_spin[1] * r[0];
    }
    for (a = 0; a < n && st == EDMI_OK; a++) {
        edmi_real p[3];
        for (c = 0; c < 3; c++) {
            p[c] = md * v[a][c];
            for (b = 0; b < n; b++)
                if (b != a)
                    p[c] += mo * v[b][c];
        }
        st = edmi_add_body(&ms_sys, md, ms_q0[sc][a], p, NULL);
    }
    for (a = 0; a < n && st == EDMI_OK; a++)
        for (b = a + 1; b < n && st == EDMI_OK; b++)
            st = edmi_add_pair(&ms_sys, a, b, &pot, NULL);
    for (a = 0; a < n && st == EDMI_OK; a++)
        for (b = a + 1; b < n; b++)
            *refused += edmi_set_mass_coupling(&ms_sys, a, b, mo) != EDMI_OK;
    return st;
}

/* ---- the truth ---------------------------------------------------------------------------- */

/* m_ab of a system (a != b), read from the stored band. */
static ms_q ms_mab(const edmi_system *s, int a, int b)
{
    int hi = a > b ? a : b, k = (a > b ? a - b : b - a) - 1;
    if (a == b)
        return (ms_q)s->body[a].m;
    return k < EDMI_MAX_MASS_GAP ? (ms_q)s->mass_off[hi][k] : (ms_q)0.0;
}

/* K(p1) - K(p0) = 1/2 (p1 - p0) . M^-1 (p1 + p0) (s0 NULL: K(p1)), M from s1, by Gaussian
 * elimination without pivoting (M symmetric positive definite); *mag = ||d|| ||x|| / 2. */
static ms_q ms_kin(const edmi_system *s0, const edmi_system *s1, ms_q *mag)
{
    ms_q m[EDMI_MAX_BODIES][EDMI_MAX_BODIES], x[EDMI_MAX_BODIES][3], d[EDMI_MAX_BODIES][3];
    ms_q dk = (ms_q)0.0, nd = (ms_q)0.0, nx = (ms_q)0.0;
    int n = s1->n_bodies, a, b, c, k;
    for (a = 0; a < n; a++) {
        for (b = 0; b < n; b++)
            m[a][b] = ms_mab(s1, a, b);
        for (c = 0; c < 3; c++) {
            ms_q p1 = (ms_q)s1->body[a].p[c], p0 = s0 ? (ms_q)s0->body[a].p[c] : (ms_q)0.0;
            d[a][c] = p1 - p0;
            x[a][c] = p1 + p0;
        }
    }
    for (k = 0; k < n; k++)
        for (a = k + 1; a < n; a++) {
            ms_q f = m[a][k] / m[k][k];
            for (b = k; b < n; b++)
                m[a][b] -= f * m[k][b];
            for (c = 0; c < 3; c++)
                x[a][c] -= f * x[k][c];
        }
    for (a = n - 1; a >= 0; a--)
        for (c = 0; c < 3; c++) {
            ms_q t = x[a][c];
            for (b = a + 1; b < n; b++)
                t -= m[a][b] * x[b][c];
            x[a][c] = t / m[a][a];
        }
    for (a = 0; a < n; a++)
        for (c = 0; c < 3; c++) {
            dk += (ms_q)0.5 * d[a][c] * x[a][c];
            nd += d[a][c] * d[a][c];
            nx += x[a][c] * x[a][c];
        }
    *mag = (ms_q)0.5 * ms_sqrt(nd) * ms_sqrt(nx) * (ms_q)1.001; /* the sqrts' rounding */
    return dk;
}

/* V of link j in state s by its textbook formula, and a magnitude bounding |V'(d)| d and V. */
static ms_q ms_pot(const edmi_system *s, int j, ms_q *mag)
{
    const edmi_link *lk = &s->link[j];
    const ms_q k = (ms_q)lk->pot.a, r0 = (ms_q)lk->pot.b;
    ms_q sq = (ms_q)0.0, d, x, v;
    int c;
    for (c = 0; c < 3; c++) {
        ms_q r = (ms_q)s->body[lk->a].q[c] - (ms_q)s->body[lk->b].q[c];
        sq += r * r;
    }
    d = ms_sqrt(sq);
    x = d - r0;
    if (lk->pot.kind == EDMI_POT_HARMONIC) { /* k/2 x^2: |V'| d = k |x| d */
        v = (ms_q)0.5 * k * x * x;
        *mag = k * ms_abs(x) * d + v;
    } else { /* neo-Hooke c rb^2/6 ((d/rb)^2 + 2 rb/d - 3) = c x^2 (d + 2 rb) / (6 d):
                |V'| d = c/3 |x| (d^2 + d rb + rb^2) / d */
        v = k * x * x * (d + (ms_q)2.0 * r0) / ((ms_q)6.0 * d);
        *mag = k * ms_abs(x) * (d + r0) * (d + (ms_q)2.0 * r0) / d + v;
    }
    return v;
}

/* H(s1) - H(s0) (s0 NULL: H(s1)) and a bound on its rounding. */
static ms_q ms_energy(const edmi_system *s0, const edmi_system *s1, long double kappa, ms_q *err)
{
    ms_q magk, magv = (ms_q)0.0, m, h = ms_kin(s0, s1, &magk);
    int j;
    for (j = 0; j < s1->n_links; j++) {
        h += ms_pot(s1, j, &m);
        magv += m;
        if (s0) {
            h -= ms_pot(s0, j, &m);
            magv += m;
        }
    }
    *err = MS_Q_U * ((ms_q)MS_V_ULPS * magv +
                     ((ms_q)MS_K_ULPS(s1->n_bodies, kappa) + (ms_q)MS_SUM_ULPS) * magk +
                     (ms_q)MS_SUM_ULPS * magv);
    return h;
}

/* L = sum p, C = (1^T M q - t L) / 1^T M 1 (t = steps dt) and J = sum q x p. */
static void ms_momenta(const edmi_system *s, long steps, ms_q l[3], ms_q cm[3], ms_q j[3])
{
    ms_q mass = (ms_q)0.0, mq[3] = {(ms_q)0.0, (ms_q)0.0, (ms_q)0.0};
    ms_q t = (ms_q)steps * (ms_q)MS_DT;
    int a, b, c, n = s->n_bodies;
    for (c = 0; c < 3; c++)
        l[c] = j[c] = (ms_q)0.0;
    for (a = 0; a < n; a++) {
        const edmi_real *q = s->body[a].q, *p = s->body[a].p;
        ms_q row = (ms_q)0.0;
        for (b = 0; b < n; b++)
            row += ms_mab(s, a, b);
        mass += row;
        for (c = 0; c < 3; c++) {
            l[c] += (ms_q)p[c];
            mq[c] += row * (ms_q)q[c];
        }
        j[0] += (ms_q)q[1] * (ms_q)p[2] - (ms_q)q[2] * (ms_q)p[1];
        j[1] += (ms_q)q[2] * (ms_q)p[0] - (ms_q)q[0] * (ms_q)p[2];
        j[2] += (ms_q)q[0] * (ms_q)p[1] - (ms_q)q[1] * (ms_q)p[0];
    }
    for (c = 0; c < 3; c++)
        cm[c] = (mq[c] - t * l[c]) / mass;
}

/* ---- reporting ---------------------------------------------------------------------------- */

/* One check with what it measured: counted by the harness (a FAIL line with file:line when
 * !ok) and printed as "ok|FAIL WHO: TEXT: v0, v1, ..." either way; line < 0: a measurement
 * only, printed as "     WHO: TEXT: ..." and not counted. */
static void ms_report(int ok, int line, const char *who, const char *text, int nv,
                      const long double *v)
{
    char buf[240];
    const char *part[3];
    size_t n = 0;
    int i;
    part[0] = who;
    part[1] = ": ";
    part[2] = text;
    for (i = 0; i < 3; i++) {
        const char *c = part[i];
        while (*c != '\0' && n + 1 < sizeof buf)
            buf[n++] = *c++;
    }
    buf[n] = '\0';
    if (line >= 0)
        ok = th_check(ok, __FILE__, line, buf);
    th_puts(line < 0 ? "     " : ok ? "ok   " : "FAIL ");
    th_puts(buf);
    for (i = 0; i < nv; i++) {
        th_puts(i > 0 ? ", " : ": ");
        th_put_ld(v[i], 3);
    }
    th_newline();
}
#define MS_REPORT_AT(line, ok, who, text, ...)                                               \
    do {                                                                                     \
        const long double ms_v_[] = {__VA_ARGS__};                                           \
        ms_report((ok) ? 1 : 0, (line), (who), (text), (int)(sizeof ms_v_ / sizeof ms_v_[0]),   \
                  ms_v_);                                                                    \
    } while (0)
#define MS_REPORT(ok, who, text, ...) MS_REPORT_AT(__LINE__, ok, who, text, __VA_ARGS__)
#define MS_NOTE(who, text, ...) MS_REPORT_AT(-1, 1, who, text, __VA_ARGS__)

/* "TRI PM double" */
static const char *ms_who(ms_scene_id sc, edmi_scheme s)
{
    static char buf[32];
    const char *part[5];
    size_t n = 0;
    int i;
    part[0] = ms_scene_names[sc];
    part[1] = " ";
    part[2] = ms_scheme_names[s];
    part[3] = " ";
    part[4] = edmi_is_double_precision() ? "double" : "float";
    for (i = 0; i < 5; i++) {
        const char *c = part[i];
        while (*c != '\0' && n + 1 < sizeof buf)
            buf[n++] = *c++;
    }
    buf[n] = '\0';
    return buf;
}

static long double ms_ld(ms_q x) { return (long double)x; }

/* ---- the runs ----------------------------------------------------------------------------- */

/* L, C and J move only by rounding: per step by at most MS_STEP_ULPS eps of their terms (the
 * stored q and p rounded, half a unit each, and Newton stopped at its round-off floor, a
 * correction below eps in the scaled norm), and on a step the guard changed by at most
 * MS_GUARD_ULPS eps more: its impulses along a link keep all three, its energy-aware rounding
 * moves the coarsest momentum component by at most EDMI__ROUND_WIDE_K0 = 64 units and each
 * finer one by at most 4 (edmi.c), its position variants a unit; its drags (counted, never
 * seen here) would keep L and C but not J. The terms: sum |p| for L, max |q| for C,
 * sum_a |q_a|_1 |p_a|_1 for J, taken at every step (the scenes drift away from the origin). */
#define MS_STEP_ULPS 4
#define MS_GUARD_ULPS 80

/* The tank identity's check resolves every step on the host: the library certifies
 * H_n+1 - H_n <= T_n - T_n+1 by an evaluation of error ~eps^2 of H's terms (double-word) and
 * sets T_n+1 below T_n - (H_n+1 - H_n) by its bound on that error (rounded down), while the
 * binary128 truth resolves 3.5e-32 H0 (TRI) and 3e-31 H0 (TET) (printed per run). Measured, the
 * least slack T_n - T_n+1 - (H_n+1 - H_n) of a run is 558 times the truth's resolution (TET LG
 * double; 3240 for TRI LG, > 1e20 in float): a step within the resolution would mean the check
 * lost its power, so on the host it fails the run. Where the truth is long double (the
 * emulated targets: double, no finer than a double build's states) such steps are counted. */
#define MS_ASSERT_RESOLVED MS_QUAD

static ms_q ms_max(ms_q a, ms_q b) { return a > b ? a : b; }

/* The scales of L, C and J (above) of a state. */
static void ms_scales(const edmi_system *s, ms_q *sl, ms_q *sc, ms_q *sj)
{
    int a, c;
    *sl = *sc = *sj = (ms_q)0.0;
    for (a = 0; a < s->n_bodies; a++) {
        ms_q q1 = (ms_q)0.0, p1 = (ms_q)0.0;
        for (c = 0; c < 3; c++) {
            q1 += ms_abs((ms_q)s->body[a].q[c]);
            p1 += ms_abs((ms_q)s->body[a].p[c]);
            *sc = ms_max(*sc, ms_abs((ms_q)s->body[a].q[c]));
        }
        *sl += p1;
        *sj += q1 * p1;
    }
}

static void ms_run(ms_scene_id sc, edmi_scheme s)
{
    const char *who = ms_who(sc, s);
    const long double kappa = ms_kappa[sc];
    const ms_q eps = (ms_q)EDMI_EPS;
    ms_q l0[3], c0[3], j0[3], h0, herr, hmin, herr_max, amin, amin_err, sl0, sc0, sj0;
    ms_q mass = (ms_q)0.0;
    ms_q dl = (ms_q)0.0, dc = (ms_q)0.0, dj = (ms_q)0.0, bl = (ms_q)0.0, bc = (ms_q)0.0,
         bj = (ms_q)0.0;
    ms_q worst = -(ms_q)1.0, margin = (ms_q)-1.0, max_rise = (ms_q)0.0, max_cap = (ms_q)0.0;
    long n, rises = 0, unresolved = 0, violations = 0, windows = 0, tank_bad = 0, guarded = 0;
    long drags = 0, fallbacks = 0, iters = 0, drift_bad = 0;
    edmi_status st;
    int refused, a, b, c;
    st = ms_build(sc, s, &refused);
    MS_REPORT(st == EDMI_OK && refused == 0, who,
              "built; edmi_set_mass_coupling accepted every consistent coupling (refused)",
              (long double)refused);
    if (st != EDMI_OK || refused != 0)
        return;
    ms_momenta(&ms_sys, 0, l0, c0, j0);
    ms_scales(&ms_sys, &sl0, &sc0, &sj0);
    for (a = 0; a < ms_sys.n_bodies; a++)
        for (b = 0; b < ms_sys.n_bodies; b++)
            mass += ms_mab(&ms_sys, a, b);
    h0 = ms_energy(NULL, &ms_sys, kappa, &herr);
    hmin = h0;
    herr_max = herr;
    amin = h0 + (ms_q)ms_sys.tank;
    amin_err = herr;
    for (n = 0; n < MS_STEPS; n++) {
        edmi_step_result res;
        ms_q dh, err, w, h, l[3], cm[3], j[3], sl, scq, sj, ulps, tl, tc, tj;
        ms_old = ms_sys;
        st = edmi_step(&ms_sys, &ms_work, MS_DT, &res);
        if (st != EDMI_OK)
            break;
        iters += res.iterations;
        fallbacks += res.stop == EDMI_STOP_FALLBACK;
        guarded += res.guard_action != 0u;
        drags += (res.guard_action & EDMI_MOVE_DRAG) != 0u;
        /* the step: H_n+1 - H_n <= T_n - T_n+1 (no work) */
        dh = ms_energy(&ms_old, &ms_sys, kappa, &err);
        w = (ms_q)ms_old.tank - (ms_q)ms_sys.tank;
        err += (ms_q)MS_SUM_ULPS * MS_Q_U * ((ms_q)ms_old.tank + (ms_q)ms_sys.tank);
        violations += dh - w > err;
        unresolved += ms_abs(dh - w) <= err;
        rises += dh > err;
        worst = ms_max(worst, (dh - w) / h0);
        if (dh - w < (ms_q)0.0 && (margin < (ms_q)0.0 || (w - dh) / err < margin))
            margin = (w - dh) / err;
        tank_bad += !(ms_sys.tank >= EDMI_R(0.0) && ms_sys.tank <= res.tank_cap &&
                      ms_sys.tank == res.tank);
        max_cap = ms_max(max_cap, (ms_q)res.tank_cap);
        /* windows: H_n - H_m <= T_m for every m < n, H from each state afresh, against the
         * running minimum of H_m + T_m, each side within its own rounding bound */
        h = ms_energy(NULL, &ms_sys, kappa, &herr);
        windows += h - amin > herr + amin_err;
        max_rise = ms_max(max_rise, h - hmin);
        hmin = h < hmin ? h : hmin;
        herr_max = ms_max(herr_max, herr);
        if (h + (ms_q)ms_sys.tank < amin) {
            amin = h + (ms_q)ms_sys.tank;
            amin_err = herr + MS_Q_U * ms_abs(amin);
        }
        /* L, C, J against the rounding allowed so far */
        ms_momenta(&ms_sys, n + 1, l, cm, j);
        ms_scales(&ms_sys, &sl, &scq, &sj);
        ulps = (ms_q)(res.guard_action != 0u ? MS_STEP_ULPS + MS_GUARD_ULPS : MS_STEP_ULPS) * eps;
        bl += ulps * sl;
        bc += ulps * scq;
        bj += ulps * sj;
        /* plus the truth's own rounding of both ends: MS_SUM_ULPS u of the terms (C's
         * include t L / 1^T M 1) */
        tl = (ms_q)MS_SUM_ULPS * MS_Q_U * (sl0 + sl);
        tc = (ms_q)MS_SUM_ULPS * MS_Q_U * (sc0 + scq + (ms_q)(n + 1) * (ms_q)MS_DT * sl / mass);
        tj = (ms_q)MS_SUM_ULPS * MS_Q_U * (sj0 + sj);
        for (c = 0; c < 3; c++) {
            dl = ms_max(dl, ms_abs(l[c] - l0[c]));
            dc = ms_max(dc, ms_abs(cm[c] - c0[c]));
            dj = ms_max(dj, ms_abs(j[c] - j0[c]));
            drift_bad += ms_abs(l[c] - l0[c]) > bl + tl || ms_abs(cm[c] - c0[c]) > bc + tc ||
                         ms_abs(j[c] - j0[c]) > bj + tj;
        }
    }
    if (st != EDMI_OK) { /* the reproducer: scene, scheme, precision, step, status */
        th_puts("  ");
        th_puts(who);
        th_puts(" failed at step ");
        th_put_int(n);
        th_puts(": ");
        th_puts(edmi_status_name(st));
        th_newline();
    }
    MS_REPORT(st == EDMI_OK && n == MS_STEPS && fallbacks == 0, who,
              "every step EDMI_OK, no fallback (steps, fallbacks, Newton corrections per step)",
              (long double)n, (long double)fallbacks,
              (long double)iters / (long double)(n > 0 ? n : 1));
    MS_REPORT(violations == 0 && (!MS_ASSERT_RESOLVED || unresolved == 0), who,
              "H_n+1 - H_n <= T_n - T_n+1 on every step (violations; steps H rose; unresolved; "
              "max (dH - dT) / H0; least slack / resolution)",
              (long double)violations, (long double)rises, (long double)unresolved,
              ms_ld(worst), ms_ld(margin));
    MS_REPORT(windows == 0 && tank_bad == 0, who,
              "H_n - H_m <= T_m for all m < n, 0 <= T <= tank_cap (violations; tank violations; "
              "max window rise / max cap; max cap / H0; resolution / H0)",
              (long double)windows, (long double)tank_bad,
              max_cap > (ms_q)0.0 ? ms_ld(max_rise / max_cap) : 0.0L, ms_ld(max_cap / h0),
              ms_ld(herr_max / h0));
    MS_NOTE(who, "steps the guard changed (of them drags)", (long double)guarded,
            (long double)drags);
    MS_REPORT(drift_bad == 0, who,
              "L, C, J conserved to round-off on every step; |dL|, |dC|, |dJ| in eps of their "
              "initial terms",
              ms_ld(dl / (eps * sl0)), ms_ld(dc / (eps * sc0)), ms_ld(dj / (eps * sj0)));
}

/* ---- refusals ----------------------------------------------------------------------------- */

/* n bodies of mass md on the scene's positions, at rest, springs on every pair, M diagonal. */
static edmi_status ms_plain(ms_scene_id sc, edmi_real md)
{
    edmi_potential pot = edmi_pot_harmonic(MS_K, EDMI_R(1.0));
    const edmi_real p[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_status st = edmi_init(&ms_sys, NULL);
    int a, b, n = ms_nb[sc];
    for (a = 0; a < n && st == EDMI_OK; a++)
        st = edmi_add_body(&ms_sys, md, ms_q0[sc][a], p, NULL);
    for (a = 0; a < n && st == EDMI_OK; a++)
        for (b = a + 1; b < n && st == EDMI_OK; b++)
            st = edmi_add_pair(&ms_sys, a, b, &pot, NULL);
    return st;
}

/* The scene of ms_sys's bodies and links with every pair coupled by mc (static storage). */
static void ms_scene_of(const edmi_system *s, edmi_real mc, edmi_scene *out)
{
    static edmi_body bodies[4];
    static edmi_link links[6];
    static edmi_mass_coupling cpl[6];
    static edmi_params prm;
    int a, b, k = 0;
    memset(out, 0, sizeof *out);
    prm = s->params;
    for (a = 0; a < s->n_bodies; a++)
        bodies[a] = s->body[a];
    for (a = 0; a < s->n_links; a++)
        links[a] = s->link[a];
    for (a = 0; a < s->n_bodies; a++)
        for (b = a + 1; b < s->n_bodies; b++) {
            cpl[k].a = b; /* either order */
            cpl[k].b = a;
            cpl[k].m = mc;
            k++;
        }
    out->n_bodies = s->n_bodies;
    out->bodies = bodies;
    out->n_links = s->n_links;
    out->links = links;
    out->params = &prm;
    out->n_mass_couplings = k;
    out->mass_couplings = cpl;
}

/* Couple every pair of scene sc's bodies (mass md) by mc, in ms_build's order: every call
 * but the last must succeed (the partial matrices are definite) and the last must return
 * EDMI_ERR_MASS with the system bit-identical; then edmi_load_scene of the whole matrix must
 * return EDMI_ERR_MASS with the system unchanged. */
static void ms_refuse(ms_scene_id sc, edmi_real md, edmi_real mc, const char *what)
{
    edmi_scene scene;
    int a, b, k = 0, ok = 1, last = 1, npairs = ms_nb[sc] * (ms_nb[sc] - 1) / 2;
    ok = ms_plain(sc, md) == EDMI_OK;
    for (a = 0; a < ms_nb[sc] && ok; a++)
        for (b = a + 1; b < ms_nb[sc] && ok; b++) {
            if (++k < npairs) {
                ok = edmi_set_mass_coupling(&ms_sys, a, b, mc) == EDMI_OK;
                continue;
            }
            ms_copy = ms_sys;
            last = edmi_set_mass_coupling(&ms_sys, a, b, mc) == EDMI_ERR_MASS &&
                   memcmp(&ms_sys, &ms_copy, sizeof ms_sys) == 0;
        }
    MS_REPORT(ok && last, what,
              "every coupling but the last accepted, the last refused with EDMI_ERR_MASS, the "
              "system bit-identical (m_aa, m_ab)",
              (long double)md, (long double)mc);
    ms_scene_of(&ms_sys, mc, &scene);
    ms_copy = ms_sys;
    MS_REPORT(edmi_load_scene(&ms_sys, &scene) == EDMI_ERR_MASS &&
                  memcmp(&ms_sys, &ms_copy, sizeof ms_sys) == 0,
              what, "edmi_load_scene of the whole matrix: EDMI_ERR_MASS, system unchanged",
              (long double)mc);
}

static void ms_refusals(void)
{
    edmi_scene scene;
    int sc, refused;
    /* Symmetric, indefinite. TRI with m_aa 0.2, m_ab -0.11: eigenvalues a - c = 0.31 (x2) and
     * a + 2c = -0.02. The first two couplings leave a tridiagonal M with eigenvalues 0.2 and
     * 0.2 -+ 0.11 sqrt 2 (least 0.044): definite. */
    ms_refuse(MS_TRI, EDMI_R(0.2), EDMI_R(-0.11), "TRI indefinite");
    /* TET with m_aa 0.12, m_ab -0.042: a - c = 0.162 (x3), a + 3c = -0.006; the five first
     * couplings leave least eigenvalues 0.078, 0.061, 0.047, 0.029, 0.012 (mpmath). */
    ms_refuse(MS_TET, EDMI_R(0.12), EDMI_R(-0.042), "TET indefinite");
    /* Definite, but not provably so in working precision. TRI with m_aa 1/4 and m_ab =
     * -(1/8)(1 - eps/2), the negated largest real below 1/8 (exact in both precisions): the
     * eigenvalues are a - c = 3/8 - eps/16 (x2) and a + 2c = eps/8 exactly, so M is positive
     * definite with kappa = 3/eps (1.4e16 in double, 2.5e7 in float). A working-precision
     * Cholesky factorisation of M - s I is M - s I + E with ||E|| up to (n + 2) eps tr(M) =
     * 3.75 eps (Rump's and Higham's bound; plus eps max m_aa = 0.25 eps for the shifted
     * diagonal's rounding): a certificate from it can prove lambda_min >= s - 4 eps at best,
     * and no valid certificate exceeds lambda_min = eps/8, 1/32 of that error term. (The
     * library's shifts, s = dmin/2, /32, /512, /8192, certify from about 64 eps on: measured,
     * a + 2c = 16 eps is refused, 64 eps accepted with a bound 2 eps.) The first two
     * couplings: eigenvalues 1/4 and 1/4 -+ sqrt 2 / 8, least 0.073. */
    ms_refuse(MS_TRI, EDMI_R(0.25), -(EDMI_R(0.125) - EDMI_R(0.125) * (EDMI_EPS / EDMI_R(2.0))),
              "TRI definite, lambda_min = eps/8");
    /* The consistent matrices are accepted by edmi_load_scene too: the scene loads into the
     * system edmi_set_mass_coupling built, byte for byte. */
    for (sc = 0; sc < MS_NSCENES; sc++) {
        int ok = ms_build((ms_scene_id)sc, EDMI_SCHEME_PM, &refused) == EDMI_OK && refused == 0;
        ms_built = ms_sys;
        ms_scene_of(&ms_built, ms_off(ms_nb[sc]), &scene);
        memset(&ms_sys, 0, sizeof ms_sys);
        ok = ok && edmi_load_scene(&ms_sys, &scene) == EDMI_OK &&
             memcmp(&ms_sys, &ms_built, sizeof ms_sys) == 0;
        MS_REPORT(ok, ms_scene_names[sc],
                  "the consistent M accepted by edmi_set_mass_coupling and edmi_load_scene "
                  "alike, the same system (m_aa, m_ab)",
                  (long double)ms_diag(ms_nb[sc]), (long double)ms_off(ms_nb[sc]));
    }
}

int main(void)
{
    int sc;
    edmi_scheme s;
    th_puts(edmi_is_double_precision() ? "mass_spd: EDMI_REAL double" : "mass_spd: EDMI_REAL float");
    th_puts(", EDMI_MAX_BODIES ");
    th_put_int(EDMI_MAX_BODIES);
    th_puts(", EDMI_MAX_MASS_GAP ");
    th_put_int(EDMI_MAX_MASS_GAP);
    th_puts(MS_QUAD ? ", truth in __float128, u " : ", truth in long double, u ");
    th_put_ld(ms_ld(MS_Q_U), 3);
    th_newline();
    ms_refusals();
    for (sc = 0; sc < MS_NSCENES; sc++)
        for (s = EDMI_SCHEME_MP; s <= EDMI_SCHEME_PT; s = (edmi_scheme)(s + 1))
            ms_run((ms_scene_id)sc, s);
    return th_finish() == 0 ? 0 : 1;
}
