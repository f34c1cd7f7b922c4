/* suite_potentials: the built-in potentials and a user potential, checked against
 * (1) their closed formulas, written here independently of edmi.c,
 * (2) finite differences of the library's own lower derivatives,
 * (3) the split conditions of the paper's eqs. convex-split and super-convex-split,
 * (4) the divided difference [V(d1)-V(d0)]/(d1-d0) and its d1-derivative, and
 * (5) the documented error statuses of edmi_pot_eval / edmi_pot_divdiff.
 *
 * Every potential here is a finite sum of power terms a_i r^n_i (integer n_i), so its j-th
 * derivative and the "term scale" S_j(r) = sum_i |a_i n_i (n_i - 1) ... (n_i - j + 1) r^(n_i - j)|
 * are exact closed forms for any j. S_j bounds |V^(j)| and, because every split of the
 * paper (sections 3.4, 4.3) regroups these same terms, the j-th derivative of every split
 * part too; it is also the magnitude round-off is proportional to when terms cancel (a
 * spring near its rest length, LJ near sigma). All tolerances below are built from it. */
#include "harness.h"
#include "suites.h"

/* ------------------------------------------------------------------------------------------
 * Tolerances
 * ---------------------------------------------------------------------------------------- */

/* Relative round-off of one evaluation of a potential derivative, measured against the term
 * scale S_j: the longest chain in edmi.c is LJ's (sigma/r)^12 times up to four factors 1/r and
 * a rising factorial, about 20 roundings; 64 leaves room for another operation order. */
#define TP_U_EVAL (EDMI_R(64.0) * EDMI_EPS)

/* Finite-difference step relative to r, for the 4th-order central stencil
 *   f'(r) ~ [f(r-2h) - 8 f(r-h) + 8 f(r+h) - f(r+2h)] / (12 h),
 * whose error is h^4/30 |f^(5)| (truncation) + 1.5 u |f| / h (round-off). For the steepest
 * case here (LJ, r^-12, derivative 3 -> 4: |f^(5)| ~ 15*16*17*18*19 |f| / r^5) the two balance
 * at h/r = (u / (4 * 3100))^(1/5): 1.6e-4 in double (u = 64 eps), 8e-3 in float. Powers of two
 * near those values, so that h = r * TP_FD_REL is exact. */
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define TP_FD_REL EDMI_R(0.000244140625) /* 2^-12 */
/* d1 = d0 (1 + TP_NEAR_REL) for the continuity check of the divided difference: the naive
 * quotient would lose eps/2^-30 ~ 2e-7 (relative) there, far above the 64 eps allowed. */
#define TP_NEAR_REL EDMI_R(9.31322574615478515625e-10) /* 2^-30 */
#else
#define TP_FD_REL EDMI_R(0.0078125) /* 2^-7 */
/* float: eps / 2^-12 ~ 5e-4 lost by a naive quotient, against 64 eps = 7.6e-6 allowed. */
#define TP_NEAR_REL EDMI_R(0.000244140625) /* 2^-12 */
#endif

/* Radii per potential (the brief: LJ 0.8..3 sigma, springs 0.3..3 r0, inverse 0.5..30). */
#define TP_NR 24

/* ------------------------------------------------------------------------------------------
 * Small helpers (no libm)
 * ---------------------------------------------------------------------------------------- */

static edmi_real tp_abs(edmi_real x) { return x < EDMI_R(0.0) ? -x : x; }

static edmi_real tp_max(edmi_real a, edmi_real b) { return a > b ? a : b; }

static edmi_real tp_inf(void)
{
    volatile edmi_real big = EDMI_REAL_MAX;
    return big * EDMI_R(2.0);
}

static edmi_real tp_nan(void)
{
    edmi_real inf = tp_inf();
    return inf - inf;
}

/* r^m for integer m (exact product chain, no pow). */
static edmi_real tp_ipow(edmi_real r, int m)
{
    edmi_real y = EDMI_R(1.0);
    if (m < 0) {
        r = EDMI_R(1.0) / r;
        m = -m;
    }
    while (m-- > 0)
        y *= r;
    return y;
}

/* n (n-1) ... (n-j+1): the factor the j-th derivative of r^n carries. */
static edmi_real tp_falling(int n, int j)
{
    edmi_real f = EDMI_R(1.0);
    int i;
    for (i = 0; i < j; i++)
        f *= (edmi_real)(n - i);
    return f;
}

/* ------------------------------------------------------------------------------------------
 * The potentials under test, each with its power-term expansion
 * ---------------------------------------------------------------------------------------- */

#define TP_MAX_TERMS 4

typedef struct tp_model {
    const char *name;
    edmi_potential pot;
    int nt;                    /* number of power terms */
    edmi_real a[TP_MAX_TERMS]; /* V = sum a_i r^n_i */
    int n[TP_MAX_TERMS];
    edmi_real lo, hi; /* radii tested */
} tp_model;

/* j-th derivative of the expansion at r. */
static edmi_real tp_deriv(const tp_model *m, int j, edmi_real r)
{
    edmi_real s = EDMI_R(0.0);
    int i;
    for (i = 0; i < m->nt; i++)
        s += m->a[i] * tp_falling(m->n[i], j) * tp_ipow(r, m->n[i] - j);
    return s;
}

/* Term scale of the j-th derivative, maximised over [lo, hi] (each |term| is monotonic in r,
 * so its maximum over the interval is at an end). */
static edmi_real tp_scale(const tp_model *m, int j, edmi_real lo, edmi_real hi)
{
    edmi_real s = EDMI_R(0.0);
    int i;
    for (i = 0; i < m->nt; i++) {
        edmi_real c = tp_abs(m->a[i] * tp_falling(m->n[i], j));
        s += c * tp_max(tp_ipow(lo, m->n[i] - j), tp_ipow(hi, m->n[i] - j));
    }
    return s;
}

/* The user potential: V = a r^4 - b r^3 + g r^-2 - w r^-1 (a, b, g, w > 0), with
 *   V_c = a r^4 + g r^-2 (V_c'' = 12 a r^2 + 6 g r^-4 >= 0),  V_e = -b r^3 - w r^-1
 *   (V_e'' = -6 b r - 2 w r^-3 <= 0), V_+ = a r^4 - b r^3 + g r^-2 (V_+'''' = 24 a + 120 g r^-6
 *   >= 0), V_- = -w r^-1 (V_-'''' = -24 w r^-5 <= 0). ctx->fail makes the callbacks refuse. */
typedef struct tp_user {
    edmi_real a, b, g, w;
    int fail;
} tp_user;

static void tp_term5(edmi_real coef, int n, edmi_real r, edmi_real out[5])
{
    int j;
    for (j = 0; j < 5; j++)
        out[j] = coef * tp_falling(n, j) * tp_ipow(r, n - j);
}

static int tp_user_fn(void *ctx, edmi_real r, edmi_pot_parts *out)
{
    const tp_user *u = (const tp_user *)ctx;
    edmi_real t4[5], t3[5], tm2[5], tm1[5];
    int j;
    if (u->fail)
        return 1;
    tp_term5(u->a, 4, r, t4);
    tp_term5(-u->b, 3, r, t3);
    tp_term5(u->g, -2, r, tm2);
    tp_term5(-u->w, -1, r, tm1);
    for (j = 0; j < 5; j++) {
        out->c[j] = t4[j] + tm2[j];
        out->e[j] = t3[j] + tm1[j];
        out->sp[j] = t4[j] + t3[j] + tm2[j];
        out->sm[j] = tm1[j];
    }
    return 0;
}

/* Closed-form divided differences of the user terms (no division by d1 - d0):
 *   r^4: d1^3 + d1^2 d0 + d1 d0^2 + d0^3      r^3: d1^2 + d1 d0 + d0^2
 *   r^-2: -(d0 + d1)/(d0^2 d1^2)              r^-1: -1/(d0 d1)
 * and their d1-derivatives 3 d1^2 + 2 d1 d0 + d0^2, 2 d1 + d0, (d1 + 2 d0)/(d0^2 d1^3),
 * 1/(d0 d1^2). */
static int tp_user_dd(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd, edmi_real *dd_d1)
{
    const tp_user *u = (const tp_user *)ctx;
    edmi_real q4, q3, qm2, qm1, s4, s3, sm2, sm1;
    if (u->fail)
        return 1;
    q4 = d1 * d1 * d1 + d1 * d1 * d0 + d1 * d0 * d0 + d0 * d0 * d0;
    q3 = d1 * d1 + d1 * d0 + d0 * d0;
    qm2 = -(d0 + d1) / (d0 * d0 * d1 * d1);
    qm1 = -EDMI_R(1.0) / (d0 * d1);
    s4 = EDMI_R(3.0) * d1 * d1 + EDMI_R(2.0) * d1 * d0 + d0 * d0;
    s3 = EDMI_R(2.0) * d1 + d0;
    sm2 = (d1 + EDMI_R(2.0) * d0) / (d0 * d0 * d1 * d1 * d1);
    sm1 = EDMI_R(1.0) / (d0 * d1 * d1);
    *dd = u->a * q4 - u->b * q3 + u->g * qm2 - u->w * qm1;
    *dd_d1 = u->a * s4 - u->b * s3 + u->g * sm2 - u->w * sm1;
    return 0;
}

static tp_user tp_user_ctx = {EDMI_R(0.25), EDMI_R(1.0), EDMI_R(0.5), EDMI_R(2.0), 0};

/* V written as the documentation writes it, independently of the power-term expansion. */
static edmi_real tp_closed_v(const tp_model *m, edmi_real r)
{
    const edmi_potential *p = &m->pot;
    edmi_real a = p->a, b = p->b;
    switch (p->kind) {
    case EDMI_POT_HARMONIC:
        return a / EDMI_R(2.0) * (r - b) * (r - b);
    case EDMI_POT_QUARTIC:
        return a / EDMI_R(4.0) * (r * r - b * b) * (r * r - b * b);
    case EDMI_POT_NEO_HOOKE:
        return a * b * b / EDMI_R(6.0) * ((r / b) * (r / b) + EDMI_R(2.0) * b / r - EDMI_R(3.0));
    case EDMI_POT_LJ: {
        edmi_real x = b / r, x6 = x * x * x * x * x * x;
        return EDMI_R(4.0) * a * (x6 * x6 - x6);
    }
    case EDMI_POT_INVERSE:
        return -a / r;
    case EDMI_POT_USER:
    default: {
        const tp_user *u = (const tp_user *)p->ctx;
        return u->a * r * r * r * r - u->b * r * r * r + u->g / (r * r) - u->w / r;
    }
    }
}

static void tp_set(tp_model *m, const char *name, edmi_potential pot, edmi_real lo,
                   edmi_real hi)
{
    m->name = name;
    m->pot = pot;
    m->nt = 0;
    m->lo = lo;
    m->hi = hi;
}

static void tp_add_term(tp_model *m, edmi_real a, int n)
{
    m->a[m->nt] = a;
    m->n[m->nt] = n;
    m->nt++;
}

#define TP_NMODELS 9

/* The potentials: parameters include the paper's (neo-Hooke c = 1e3, rb = 4; LJ eps = 100,
 * sigma = 1) and others so that no parameter is 1 by accident. */
static int tp_models(tp_model *m)
{
    edmi_real k, r0, L, c, rb, e, s, kg, kc;
    int i = 0;

    k = EDMI_R(3.0), r0 = EDMI_R(1.5); /* V = k/2 r^2 - k r0 r + k r0^2/2 */
    tp_set(&m[i], "harmonic", edmi_pot_harmonic(k, r0), EDMI_R(0.3) * r0, EDMI_R(3.0) * r0);
    tp_add_term(&m[i], k / EDMI_R(2.0), 2);
    tp_add_term(&m[i], -k * r0, 1);
    tp_add_term(&m[i], k * r0 * r0 / EDMI_R(2.0), 0);
    i++;

    k = EDMI_R(2.0); /* r0 = 0: V = k/2 r^2 */
    tp_set(&m[i], "harmonic r0=0", edmi_pot_harmonic(k, EDMI_R(0.0)), EDMI_R(0.3), EDMI_R(3.0));
    tp_add_term(&m[i], k / EDMI_R(2.0), 2);
    i++;

    k = EDMI_R(2.0), L = EDMI_R(1.25); /* V = k/4 r^4 - k L^2/2 r^2 + k L^4/4 */
    tp_set(&m[i], "quartic", edmi_pot_quartic(k, L), EDMI_R(0.3) * L, EDMI_R(3.0) * L);
    tp_add_term(&m[i], k / EDMI_R(4.0), 4);
    tp_add_term(&m[i], -k * L * L / EDMI_R(2.0), 2);
    tp_add_term(&m[i], k * L * L * L * L / EDMI_R(4.0), 0);
    i++;

    c = EDMI_R(1000.0), rb = EDMI_R(4.0); /* V = c/6 r^2 + c rb^3/3 r^-1 - c rb^2/2 */
    tp_set(&m[i], "neo-Hooke", edmi_pot_neo_hooke(c, rb), EDMI_R(0.3) * rb, EDMI_R(3.0) * rb);
    tp_add_term(&m[i], c / EDMI_R(6.0), 2);
    tp_add_term(&m[i], c * rb * rb * rb / EDMI_R(3.0), -1);
    tp_add_term(&m[i], -c * rb * rb / EDMI_R(2.0), 0);
    i++;

    e = EDMI_R(100.0), s = EDMI_R(1.0); /* V = 4 e s^12 r^-12 - 4 e s^6 r^-6 */
    tp_set(&m[i], "LJ", edmi_pot_lj(e, s), EDMI_R(0.8) * s, EDMI_R(3.0) * s);
    tp_add_term(&m[i], EDMI_R(4.0) * e * tp_ipow(s, 12), -12);
    tp_add_term(&m[i], -EDMI_R(4.0) * e * tp_ipow(s, 6), -6);
    i++;

    e = EDMI_R(0.5), s = EDMI_R(2.5);
    tp_set(&m[i], "LJ sigma=2.5", edmi_pot_lj(e, s), EDMI_R(0.8) * s, EDMI_R(3.0) * s);
    tp_add_term(&m[i], EDMI_R(4.0) * e * tp_ipow(s, 12), -12);
    tp_add_term(&m[i], -EDMI_R(4.0) * e * tp_ipow(s, 6), -6);
    i++;

    kg = EDMI_R(2.5); /* gravity: V = -k/r */
    tp_set(&m[i], "inverse (gravity)", edmi_pot_inverse(kg), EDMI_R(0.5), EDMI_R(30.0));
    tp_add_term(&m[i], -kg, -1);
    i++;

    kc = EDMI_R(-1.5); /* Coulomb repulsion: V = |k|/r */
    tp_set(&m[i], "inverse (Coulomb)", edmi_pot_inverse(kc), EDMI_R(0.5), EDMI_R(30.0));
    tp_add_term(&m[i], -kc, -1);
    i++;

    tp_set(&m[i], "user", edmi_pot_user(tp_user_fn, tp_user_dd, &tp_user_ctx), EDMI_R(0.4),
           EDMI_R(4.0));
    tp_add_term(&m[i], tp_user_ctx.a, 4);
    tp_add_term(&m[i], -tp_user_ctx.b, 3);
    tp_add_term(&m[i], tp_user_ctx.g, -2);
    tp_add_term(&m[i], -tp_user_ctx.w, -1);
    i++;
    return i;
}

static edmi_real tp_radius(const tp_model *m, int i)
{
    return m->lo + (m->hi - m->lo) * (edmi_real)i / (edmi_real)(TP_NR - 1);
}

/* The five arrays of a parts struct: v, c, e, sp, sm. */
static const edmi_real *tp_part(const edmi_pot_parts *p, int which)
{
    switch (which) {
    case 0:
        return p->v;
    case 1:
        return p->c;
    case 2:
        return p->e;
    case 3:
        return p->sp;
    default:
        return p->sm;
    }
}

/* ------------------------------------------------------------------------------------------
 * (1) + (3): values against the closed forms; splits add up; split sign conditions
 * ---------------------------------------------------------------------------------------- */

static void tp_check_values(const tp_model *m)
{
    int i, k, bad = 0;
    for (i = 0; i < TP_NR; i++) {
        edmi_real r = tp_radius(m, i);
        edmi_pot_parts p;
        int f0 = th_failed();
        if (!CHECK_STATUS(edmi_pot_eval(&m->pot, r, &p), EDMI_OK)) {
            bad++;
            continue;
        }
        /* V against the documented formula: both sides within TP_U_EVAL S_0. */
        CHECK_NEAR(p.v[0], tp_closed_v(m, r), TP_U_EVAL * tp_scale(m, 0, r, r), EDMI_R(0.0));
        for (k = 0; k < 5; k++) {
            edmi_real sk = tp_scale(m, k, r, r);
            /* V^(k) against the power-term expansion. */
            CHECK_NEAR(p.v[k], tp_deriv(m, k, r), TP_U_EVAL * sk, EDMI_R(0.0));
            /* Both splits add up to the same V (two evaluations, one addition each). */
            CHECK_NEAR(p.c[k] + p.e[k], p.v[k], EDMI_R(2.0) * TP_U_EVAL * sk, EDMI_R(0.0));
            CHECK_NEAR(p.sp[k] + p.sm[k], p.v[k], EDMI_R(2.0) * TP_U_EVAL * sk, EDMI_R(0.0));
            CHECK_NEAR(p.c[k] + p.e[k], p.sp[k] + p.sm[k], EDMI_R(2.0) * TP_U_EVAL * sk,
                       EDMI_R(0.0));
        }
        /* eq. convex-split and eq. super-convex-split: exact, the parts are closed forms. */
        CHECK(p.c[2] >= EDMI_R(0.0));
        CHECK(p.e[2] <= EDMI_R(0.0));
        CHECK(p.sp[4] >= EDMI_R(0.0));
        CHECK(p.sm[4] <= EDMI_R(0.0));
        if (th_failed() > f0)
            th_note_real("values: failures above at r", r);
    }
    CHECK(bad == 0);
}

/* ------------------------------------------------------------------------------------------
 * (2): derivative k of every part against the 4th-order central difference of derivative k-1
 * ---------------------------------------------------------------------------------------- */

static edmi_real tp_fd4(edmi_real fm2, edmi_real fm1, edmi_real fp1, edmi_real fp2, edmi_real h)
{
    return ((fm2 - fp2) + EDMI_R(8.0) * (fp1 - fm1)) / (EDMI_R(12.0) * h);
}

static void tp_check_fd(const tp_model *m)
{
    int i, k, w;
    for (i = 0; i < TP_NR; i++) {
        edmi_real r = tp_radius(m, i), h = r * TP_FD_REL;
        edmi_real lo = r - EDMI_R(2.0) * h, hi = r + EDMI_R(2.0) * h;
        edmi_pot_parts p0, pm2, pm1, pp1, pp2;
        int f0 = th_failed();
        if (edmi_pot_eval(&m->pot, r, &p0) != EDMI_OK ||
            edmi_pot_eval(&m->pot, lo, &pm2) != EDMI_OK ||
            edmi_pot_eval(&m->pot, r - h, &pm1) != EDMI_OK ||
            edmi_pot_eval(&m->pot, r + h, &pp1) != EDMI_OK ||
            edmi_pot_eval(&m->pot, hi, &pp2) != EDMI_OK) {
            CHECK(0 && "edmi_pot_eval failed inside the radius range");
            continue;
        }
        for (k = 1; k <= 4; k++) {
            /* Error bound of the stencil applied to the computed f = X^(k-1):
             *   truncation h^4/30 max|X^(k+4)|  (X^(k+4) bounded by the term scale S_(k+4));
             *   round-off 1.5/h (u max|X^(k-1)| + eps (r+2h) max|X^(k)|), the second part from
             *   r +- h not being exactly representable;
             *   plus the library's own error in X^(k), u S_k. */
            edmi_real h4 = h * h * h * h;
            edmi_real tol = h4 / EDMI_R(30.0) * tp_scale(m, k + 4, lo, hi) +
                            EDMI_R(1.5) / h *
                                (TP_U_EVAL * tp_scale(m, k - 1, lo, hi) +
                                 EDMI_EPS * hi * tp_scale(m, k, lo, hi)) +
                            TP_U_EVAL * tp_scale(m, k, r, r);
            for (w = 0; w < 5; w++) {
                edmi_real fd = tp_fd4(tp_part(&pm2, w)[k - 1], tp_part(&pm1, w)[k - 1],
                                      tp_part(&pp1, w)[k - 1], tp_part(&pp2, w)[k - 1], h);
                if (!CHECK_NEAR(tp_part(&p0, w)[k], fd, tol, EDMI_R(0.0))) {
                    th_note_int("  part (0 v, 1 c, 2 e, 3 sp, 4 sm)", w);
                    th_note_int("  derivative", k);
                }
            }
        }
        if (th_failed() > f0)
            th_note_real("finite differences: failures above at r", r);
    }
}

/* ------------------------------------------------------------------------------------------
 * (4): divided differences
 * ---------------------------------------------------------------------------------------- */

static void tp_check_divdiff(const tp_model *m)
{
    int i;
    for (i = 0; i < TP_NR; i++) {
        edmi_real d0 = tp_radius(m, i), d1 = tp_radius(m, (i + 7) % TP_NR);
        edmi_real lo = d0 < d1 ? d0 : d1, hi = d0 < d1 ? d1 : d0;
        edmi_real dd = EDMI_R(0.0), ddd = EDMI_R(0.0), dd_r = EDMI_R(0.0), ddd_r = EDMI_R(0.0);
        edmi_pot_parts p0, p1;
        int f0 = th_failed();
        if (!CHECK_STATUS(edmi_pot_divdiff(&m->pot, d0, d1, &dd, &ddd), EDMI_OK) ||
            !CHECK_STATUS(edmi_pot_eval(&m->pot, d0, &p0), EDMI_OK) ||
            !CHECK_STATUS(edmi_pot_eval(&m->pot, d1, &p1), EDMI_OK))
            continue;

        /* Well conditioned (|d1 - d0| >= 7/23 of the range): the direct quotient loses
         * u (S_0(d0) + S_0(d1)) / |d1 - d0| to cancellation; the library's closed form is
         * within u max S_1 on [d0, d1] (its terms are mean values of V' terms), and the
         * quotient's own division, 2 eps. */
        {
            edmi_real q = (p1.v[0] - p0.v[0]) / (d1 - d0);
            edmi_real tol = TP_U_EVAL * (tp_scale(m, 0, d0, d0) + tp_scale(m, 0, d1, d1)) /
                                tp_abs(d1 - d0) +
                            TP_U_EVAL * tp_scale(m, 1, lo, hi) +
                            EDMI_R(2.0) * EDMI_EPS * tp_abs(q);
            CHECK_NEAR(dd, q, tol, EDMI_R(0.0));
        }
        /* Symmetry of the divided difference: dd(d0, d1) = dd(d1, d0). */
        if (CHECK_STATUS(edmi_pot_divdiff(&m->pot, d1, d0, &dd_r, &ddd_r), EDMI_OK))
            CHECK_NEAR(dd_r, dd, EDMI_R(2.0) * TP_U_EVAL * tp_scale(m, 1, lo, hi), EDMI_R(0.0));

        /* dd_d1 against the 4th-order central difference of dd in d1. The m-th d1-derivative
         * of dd is V^(m+1)(xi)/(m+1), so truncation is h^4/30 max|V^(6)|/6; round-off
         * 1.5/h (u max|dd| + eps (d1+2h) max|dd_d1|) with |dd| <= S_1, |dd_d1| <= S_2/2. */
        {
            edmi_real h = d1 * TP_FD_REL, f[4], h4 = h * h * h * h, junk;
            edmi_real flo = d1 - EDMI_R(2.0) * h, fhi = d1 + EDMI_R(2.0) * h;
            edmi_real slo = flo < d0 ? flo : d0, shi = fhi > d0 ? fhi : d0;
            int ok = edmi_pot_divdiff(&m->pot, d0, flo, &f[0], &junk) == EDMI_OK &&
                     edmi_pot_divdiff(&m->pot, d0, d1 - h, &f[1], &junk) == EDMI_OK &&
                     edmi_pot_divdiff(&m->pot, d0, d1 + h, &f[2], &junk) == EDMI_OK &&
                     edmi_pot_divdiff(&m->pot, d0, fhi, &f[3], &junk) == EDMI_OK;
            edmi_real tol = h4 / EDMI_R(30.0) * tp_scale(m, 6, slo, shi) / EDMI_R(6.0) +
                            EDMI_R(1.5) / h *
                                (TP_U_EVAL * tp_scale(m, 1, slo, shi) +
                                 EDMI_EPS * fhi * tp_scale(m, 2, slo, shi) / EDMI_R(2.0)) +
                            TP_U_EVAL * tp_scale(m, 2, lo, hi);
            if (CHECK(ok))
                CHECK_NEAR(ddd, tp_fd4(f[0], f[1], f[2], f[3], h), tol, EDMI_R(0.0));
        }

        /* Confluent limit d1 == d0: dd = V'(d0), dd_d1 = V''(d0)/2. */
        if (CHECK_STATUS(edmi_pot_divdiff(&m->pot, d0, d0, &dd, &ddd), EDMI_OK)) {
            CHECK_NEAR(dd, p0.v[1], EDMI_R(2.0) * TP_U_EVAL * tp_scale(m, 1, d0, d0),
                       EDMI_R(0.0));
            CHECK_NEAR(ddd, p0.v[2] / EDMI_R(2.0),
                       EDMI_R(2.0) * TP_U_EVAL * tp_scale(m, 2, d0, d0), EDMI_R(0.0));
        }

        /* Continuity as d1 -> d0: with D = d1 - d0 (exact, Sterbenz),
         *   dd    = V'(d0)   + D V''(d0)/2  + R,  |R| <= D^2/6 max|V'''|,
         *   dd_d1 = V''(d0)/2 + D V'''(d0)/3 + R', |R'| <= D^2/4 max|V''''|,
         * plus round-off of both sides. A naive quotient fails this by eps |V| / D. */
        {
            edmi_real dn = d0 + d0 * TP_NEAR_REL, dl = dn - d0;
            if (CHECK_STATUS(edmi_pot_divdiff(&m->pot, d0, dn, &dd, &ddd), EDMI_OK)) {
                edmi_real t1 = dl * dl / EDMI_R(6.0) * tp_scale(m, 3, d0, dn) +
                               EDMI_R(2.0) * TP_U_EVAL * tp_scale(m, 1, d0, dn);
                edmi_real t2 = dl * dl / EDMI_R(4.0) * tp_scale(m, 4, d0, dn) +
                               EDMI_R(2.0) * TP_U_EVAL * tp_scale(m, 2, d0, dn);
                CHECK_NEAR(dd, p0.v[1] + dl * p0.v[2] / EDMI_R(2.0), t1, EDMI_R(0.0));
                CHECK_NEAR(ddd, p0.v[2] / EDMI_R(2.0) + dl * p0.v[3] / EDMI_R(3.0), t2,
                           EDMI_R(0.0));
            }
        }
        if (th_failed() > f0) {
            th_note_real("divided differences: failures above at d0", d0);
            th_note_real("                                     d1", d1);
        }
    }
}

/* ------------------------------------------------------------------------------------------
 * (5): error statuses
 * ---------------------------------------------------------------------------------------- */

static void tp_check_errors(void)
{
    edmi_real nan = tp_nan(), inf = tp_inf(), dd = EDMI_R(0.0), ddd = EDMI_R(0.0);
    edmi_potential good = edmi_pot_lj(EDMI_R(1.0), EDMI_R(1.0));
    edmi_potential bad[26];
    edmi_pot_parts p;
    tp_user failing = {EDMI_R(0.25), EDMI_R(1.0), EDMI_R(0.5), EDMI_R(2.0), 1};
    edmi_potential user_fail = edmi_pot_user(tp_user_fn, tp_user_dd, &failing);
    edmi_potential user_nodd = edmi_pot_user(tp_user_fn, 0, &tp_user_ctx);
    int i, nbad = 0;

    /* NULL pointers: EDMI_ERR_NULL (the header's list for both functions). */
    CHECK_STATUS(edmi_pot_eval(0, EDMI_R(1.0), &p), EDMI_ERR_NULL);
    CHECK_STATUS(edmi_pot_eval(&good, EDMI_R(1.0), 0), EDMI_ERR_NULL);
    CHECK_STATUS(edmi_pot_divdiff(0, EDMI_R(1.0), EDMI_R(2.0), &dd, &ddd), EDMI_ERR_NULL);
    CHECK_STATUS(edmi_pot_divdiff(&good, EDMI_R(1.0), EDMI_R(2.0), 0, &ddd), EDMI_ERR_NULL);
    CHECK_STATUS(edmi_pot_divdiff(&good, EDMI_R(1.0), EDMI_R(2.0), &dd, 0), EDMI_ERR_NULL);

    /* r <= 0 or not a number: EDMI_ERR_PARAM (for a potential this build carries). */
    if (!th_skip(th_has_pot(EDMI_POT_LJ), "LJ: r <= 0 refused")) {
        CHECK_STATUS(edmi_pot_eval(&good, EDMI_R(0.0), &p), EDMI_ERR_PARAM);
        CHECK_STATUS(edmi_pot_eval(&good, EDMI_R(-1.0), &p), EDMI_ERR_PARAM);
        CHECK_STATUS(edmi_pot_eval(&good, nan, &p), EDMI_ERR_PARAM);
        CHECK_STATUS(edmi_pot_divdiff(&good, EDMI_R(0.0), EDMI_R(1.0), &dd, &ddd),
                     EDMI_ERR_PARAM);
        CHECK_STATUS(edmi_pot_divdiff(&good, EDMI_R(1.0), EDMI_R(0.0), &dd, &ddd),
                     EDMI_ERR_PARAM);
        CHECK_STATUS(edmi_pot_divdiff(&good, EDMI_R(-1.0), EDMI_R(1.0), &dd, &ddd),
                     EDMI_ERR_PARAM);
        CHECK_STATUS(edmi_pot_divdiff(&good, EDMI_R(1.0), EDMI_R(-2.0), &dd, &ddd),
                     EDMI_ERR_PARAM);
        CHECK_STATUS(edmi_pot_divdiff(&good, nan, EDMI_R(1.0), &dd, &ddd), EDMI_ERR_PARAM);
        CHECK_STATUS(edmi_pot_divdiff(&good, EDMI_R(1.0), nan, &dd, &ddd), EDMI_ERR_PARAM);
    }

    /* Invalid parameters (edmi_pot_kind's documented ranges), NaN and inf parameters. */
    bad[nbad++] = edmi_pot_harmonic(EDMI_R(0.0), EDMI_R(1.0));
    bad[nbad++] = edmi_pot_harmonic(EDMI_R(-1.0), EDMI_R(1.0));
    bad[nbad++] = edmi_pot_harmonic(EDMI_R(1.0), EDMI_R(-0.5));
    bad[nbad++] = edmi_pot_harmonic(nan, EDMI_R(1.0));
    bad[nbad++] = edmi_pot_harmonic(EDMI_R(1.0), nan);
    bad[nbad++] = edmi_pot_harmonic(inf, EDMI_R(1.0));
    bad[nbad++] = edmi_pot_quartic(EDMI_R(0.0), EDMI_R(1.0));
    bad[nbad++] = edmi_pot_quartic(EDMI_R(-2.0), EDMI_R(1.0));
    bad[nbad++] = edmi_pot_quartic(EDMI_R(2.0), EDMI_R(-1.0));
    bad[nbad++] = edmi_pot_quartic(nan, EDMI_R(1.0));
    bad[nbad++] = edmi_pot_quartic(EDMI_R(2.0), nan);
    bad[nbad++] = edmi_pot_neo_hooke(EDMI_R(0.0), EDMI_R(4.0));
    bad[nbad++] = edmi_pot_neo_hooke(EDMI_R(-1.0), EDMI_R(4.0));
    bad[nbad++] = edmi_pot_neo_hooke(EDMI_R(1000.0), EDMI_R(0.0));
    bad[nbad++] = edmi_pot_neo_hooke(EDMI_R(1000.0), EDMI_R(-4.0));
    bad[nbad++] = edmi_pot_neo_hooke(nan, EDMI_R(4.0));
    bad[nbad++] = edmi_pot_lj(EDMI_R(0.0), EDMI_R(1.0));
    bad[nbad++] = edmi_pot_lj(EDMI_R(-1.0), EDMI_R(1.0));
    bad[nbad++] = edmi_pot_lj(EDMI_R(1.0), EDMI_R(0.0));
    bad[nbad++] = edmi_pot_lj(EDMI_R(1.0), EDMI_R(-1.0));
    bad[nbad++] = edmi_pot_lj(EDMI_R(1.0), nan);
    bad[nbad++] = edmi_pot_inverse(EDMI_R(0.0));
    bad[nbad++] = edmi_pot_inverse(nan);
    bad[nbad++] = edmi_pot_inverse(inf);
    bad[nbad++] = edmi_pot_user(0, tp_user_dd, &tp_user_ctx); /* fn is required */
    bad[nbad] = good;
    bad[nbad++].kind = (edmi_pot_kind)42; /* not a kind */
    for (i = 0; i < nbad; i++) {
        int f0 = th_failed();
        CHECK_STATUS(edmi_pot_eval(&bad[i], EDMI_R(1.0), &p), EDMI_ERR_PARAM);
        CHECK_STATUS(edmi_pot_divdiff(&bad[i], EDMI_R(1.0), EDMI_R(1.5), &dd, &ddd),
                     EDMI_ERR_PARAM);
        if (th_failed() > f0)
            th_note_int("invalid potential number (order in tp_check_errors)", i);
    }

    /* A user potential without a divided-difference callback: divdiff is a parameter error
     * (eval still works); a callback that refuses: EDMI_ERR_DOMAIN. */
    if (th_skip(th_has_pot(EDMI_POT_USER), "user potential statuses"))
        return;
    CHECK_STATUS(edmi_pot_eval(&user_nodd, EDMI_R(1.0), &p), EDMI_OK);
    CHECK_STATUS(edmi_pot_divdiff(&user_nodd, EDMI_R(1.0), EDMI_R(1.5), &dd, &ddd),
                 EDMI_ERR_PARAM);
    CHECK_STATUS(edmi_pot_eval(&user_fail, EDMI_R(1.0), &p), EDMI_ERR_DOMAIN);
    CHECK_STATUS(edmi_pot_divdiff(&user_fail, EDMI_R(1.0), EDMI_R(1.5), &dd, &ddd),
                 EDMI_ERR_DOMAIN);

    /* The user potential's v is c + e (header). */
    if (CHECK_STATUS(edmi_pot_eval(&user_nodd, EDMI_R(1.25), &p), EDMI_OK))
        for (i = 0; i < 5; i++)
            CHECK(p.v[i] == p.c[i] + p.e[i]);
}

void suite_potentials(void)
{
    tp_model models[TP_NMODELS];
    int nm = tp_models(models), i;
    th_suite("potentials: derivatives, splits, divided differences, statuses");
    CHECK(nm == TP_NMODELS);
    for (i = 0; i < nm; i++) {
        if (th_skip(th_has_pot(models[i].pot.kind), models[i].name))
            continue;
        th_puts("  ");
        th_puts(models[i].name);
        th_newline();
        tp_check_values(&models[i]);
        tp_check_fd(&models[i]);
        tp_check_divdiff(&models[i]);
    }
    tp_check_errors();
}
