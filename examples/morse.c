/* A user potential, worked through: the Morse bond V(r) = D (1 - E)^2, E = exp(-a (r - re)),
 * of a diatomic molecule (docs/api.md, "A user potential"). `morse` runs a vibrating,
 * rotating molecule with PM and LG; `morse --check` checks the callbacks as the test suite
 * checks the built-in potentials and the runs' energy and momenta (make test runs it in
 * both precisions; exit 1 on a failed check).
 *
 * What edmi needs from a potential: V and four derivatives of each part of two splits.
 *   GE:     V = V_c + V_e with V_c'' >= 0 (convex) and V_e'' <= 0 (concave);
 *   PM, PT: V = V_+ + V_- with V_+'''' >= 0 and V_-'''' <= 0.
 * Morse's V = D + D E^2 - 2 D E is a sum of exponentials whose every derivative has one sign:
 * (E^2)^(k) = (-2a)^k E^2 and E^(k) = (-a)^k E. D + D E^2 has V'' = 4 a^2 D E^2 >= 0 and
 * V'''' = 16 a^4 D E^2 >= 0; -2 D E has -2 a^2 D E <= 0 and -2 a^4 D E <= 0. So one split
 * serves both: V_c = V_+ = D + D E^2, V_e = V_- = -2 D E.
 * LG also wants the divided difference [V(d1) - V(d0)] / (d1 - d0) in a form finite at
 * d1 = d0: with h = d1 - d0 and g(h) = -expm1(-a h) / h (-> a as h -> 0),
 *   dd = D E0 (2 - E0 - E1) g(h),   d dd / d d1 = D E0 [a E1 g(h) + (2 - E0 - E1) g'(h)].
 * Without it LG falls back to the quotient form (EDMI_LG_QUOTIENT). The callbacks compute in
 * double whatever EDMI_REAL is (the program's arithmetic, not the library's). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "edmi.h"

typedef struct morse {
    double depth, a, re; /* D [energy], a [1/length], re [length] */
} morse;

static int morse_fn(void *ctx, edmi_real r, edmi_pot_parts *out)
{
    const morse *m = (const morse *)ctx;
    double e = exp(-m->a * ((double)r - m->re)), e2 = e * e, k1 = 1.0, k2 = 1.0;
    int j;
    if (!(r > 0))
        return 1;
    for (j = 0; j < 5; j++) { /* k1 = (-a)^j, k2 = (-2a)^j */
        out->c[j] = (edmi_real)(m->depth * k2 * e2 + (j == 0 ? m->depth : 0.0));
        out->e[j] = (edmi_real)(-2.0 * m->depth * k1 * e);
        out->sp[j] = out->c[j];
        out->sm[j] = out->e[j];
        k1 *= -m->a;
        k2 *= -2.0 * m->a;
    }
    return 0;
}

/* g(h) = -expm1(-a h) / h and g'(h), by the series where |a h| is small (the closed forms
 * cancel there): with x = -a h and t_k = x^k / (k+1)!,
 *   g = a sum_k t_k,   g' = -a^2 sum_k (k+1) t_k / (k+2)   (g(0) = a, g'(0) = -a^2 / 2). */
static void morse_g(double a, double h, double *g, double *gd)
{
    double x = -a * h;
    if (fabs(x) < 0.5) { /* 20 terms: the rest below 0.5^20 / 21!, far under an ulp */
        double t = 1.0, s = 0.0, sd = 0.0;
        int k;
        for (k = 0; k < 20; k++) {
            s += t;
            sd += (double)(k + 1) * t / (double)(k + 2);
            t *= x / (double)(k + 2);
        }
        *g = a * s;
        *gd = -a * a * sd;
    } else {
        *g = -expm1(x) / h;
        *gd = (a * h * exp(x) + expm1(x)) / (h * h);
    }
}

static int morse_dd(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd, edmi_real *dd_d1)
{
    const morse *m = (const morse *)ctx;
    double e0 = exp(-m->a * ((double)d0 - m->re)), e1 = exp(-m->a * ((double)d1 - m->re));
    double g, gd;
    morse_g(m->a, (double)d1 - (double)d0, &g, &gd);
    *dd = (edmi_real)(m->depth * e0 * (2.0 - e0 - e1) * g);
    *dd_d1 = (edmi_real)(m->depth * e0 * (m->a * e1 * g + (2.0 - e0 - e1) * gd));
    return 0;
}

/* ---- the run: a molecule of two atoms of mass 1 on a bond of D = 1, a = 2, re = 1, stretched to
 * r = 1.6 and spinning; 20,000 steps of 0.01 ---------------------------------------------------- */

static edmi_system sys;
static edmi_workspace work;
static morse bond = {1.0, 2.0, 1.0};

/* H of the stored state in long double (its own exp: an independent evaluation). */
static long double morse_h(const edmi_system *s)
{
    long double r2 = 0.0L, k = 0.0L, d, e;
    int i, b;
    for (i = 0; i < 3; i++) {
        long double x = (long double)s->body[0].q[i] - (long double)s->body[1].q[i];
        r2 += x * x;
    }
    for (b = 0; b < 2; b++)
        for (i = 0; i < 3; i++)
            k += (long double)s->body[b].p[i] * s->body[b].p[i] / (2.0L * (long double)s->body[b].m);
    d = sqrtl(r2);
    e = expl(-(long double)bond.a * (d - (long double)bond.re));
    return k + (long double)bond.depth * (1.0L - e) * (1.0L - e);
}

typedef struct morse_run {
    long failed;
    long double h0, rise, drift, dl, dj, scale;
} morse_run;

static int morse_simulate(edmi_scheme scheme, morse_run *out)
{
    const edmi_real q0[3] = {EDMI_R(-0.8), 0, 0}, q1[3] = {EDMI_R(0.8), 0, 0};
    const edmi_real p0[3] = {0, EDMI_R(-0.5), 0}, p1[3] = {0, EDMI_R(0.5), 0};
    edmi_potential pot = edmi_pot_user(morse_fn, morse_dd, &bond);
    edmi_params prm = edmi_default_params();
    long double l0[3], j0[3];
    long n;
    int i;
    prm.scheme = scheme;
    if (edmi_init(&sys, &prm) != EDMI_OK || edmi_add_body(&sys, 1, q0, p0, NULL) != EDMI_OK ||
        edmi_add_body(&sys, 1, q1, p1, NULL) != EDMI_OK ||
        edmi_add_pair(&sys, 0, 1, &pot, NULL) != EDMI_OK)
        return 0;
    memset(out, 0, sizeof *out);
    out->h0 = morse_h(&sys);
    for (i = 0; i < 3; i++) {
        l0[i] = (long double)sys.body[0].p[i] + sys.body[1].p[i];
        j0[i] = 0.0L;
    }
    j0[2] = (long double)sys.body[0].q[0] * sys.body[0].p[1] + (long double)sys.body[1].q[0] * sys.body[1].p[1];
    out->scale = 2.0L; /* |q| |p| and |p| of the start, roughly */
    for (n = 0; n < 20000; n++) {
        long double h, l, jz = 0.0L;
        int b;
        if (edmi_step(&sys, &work, EDMI_R(0.01), NULL) != EDMI_OK) {
            out->failed++;
            continue;
        }
        h = morse_h(&sys) - out->h0;
        if (h > out->rise)
            out->rise = h;
        out->drift = h;
        for (i = 0; i < 3; i++) {
            l = (long double)sys.body[0].p[i] + sys.body[1].p[i] - l0[i];
            if (fabsl(l) > out->dl)
                out->dl = fabsl(l);
        }
        for (b = 0; b < 2; b++)
            jz += (long double)sys.body[b].q[0] * sys.body[b].p[1] -
                  (long double)sys.body[b].q[1] * sys.body[b].p[0];
        if (fabsl(jz - j0[2]) > out->dj)
            out->dj = fabsl(jz - j0[2]);
    }
    return 1;
}

/* ---- the checks (--check) ------------------------------------------------------------------- */

static int morse_failed;

static void morse_expect(int ok, const char *what, double r, double got, double want)
{
    if (!ok) {
        printf("FAIL %s at r = %.17g: %.17g, want %.17g\n", what, r, got, want);
        morse_failed++;
    }
}

/* Part w (0 V, 1 V_c = V_+, 2 V_e = V_-) of derivative j at r in long double, and the scale S_j
 * of the terms it sums (what round-off is proportional to). */
static long double morse_ref(int w, int j, long double r, long double *scale)
{
    long double e = expl(-(long double)bond.a * (r - (long double)bond.re));
    long double a1 = powl(-(long double)bond.a, (long double)j);
    long double a2 = powl(-2.0L * (long double)bond.a, (long double)j), d = (long double)bond.depth;
    long double c = d * a2 * e * e + (j == 0 ? d : 0.0L), v = -2.0L * d * a1 * e;
    *scale = fabsl(c) + fabsl(v) + (j == 0 ? d : 0.0L);
    return w == 0 ? c + v : w == 1 ? c : v;
}

static void morse_check_values(void)
{
    edmi_potential pot = edmi_pot_user(morse_fn, morse_dd, &bond);
    const long double tol = 64.0L * (long double)EDMI_EPS;
    int i, j;
    for (i = 0; i < 24; i++) {
        edmi_real r = (edmi_real)(0.6 + 0.125 * i); /* 0.6 to 3.5: E from 2.2 to 7e-3 */
        edmi_pot_parts p;
        long double s;
        if (edmi_pot_eval(&pot, r, &p) != EDMI_OK) {
            morse_expect(0, "edmi_pot_eval", (double)r, 0, 0);
            continue;
        }
        for (j = 0; j < 5; j++) {
            long double v = morse_ref(0, j, r, &s), c = morse_ref(1, j, r, &s);
            long double e = morse_ref(2, j, r, &s);
            morse_expect(fabsl(p.v[j] - v) <= 2.0L * tol * s, "V^(j)", (double)r, (double)p.v[j], (double)v);
            morse_expect(fabsl(p.c[j] - c) <= tol * s && fabsl(p.sp[j] - c) <= tol * s, "V_c^(j)",
                         (double)r, (double)p.c[j], (double)c);
            morse_expect(fabsl(p.e[j] - e) <= tol * s && fabsl(p.sm[j] - e) <= tol * s, "V_e^(j)",
                         (double)r, (double)p.e[j], (double)e);
        }
        /* the splits' conditions, exactly */
        morse_expect(p.c[2] >= 0 && p.e[2] <= 0 && p.sp[4] >= 0 && p.sm[4] <= 0, "split signs",
                     (double)r, 0, 0);
    }
}

static void morse_check_divdiff(void)
{
    edmi_potential pot = edmi_pot_user(morse_fn, morse_dd, &bond);
    const long double tol = 64.0L * (long double)EDMI_EPS;
    const edmi_real near = sizeof(edmi_real) == sizeof(float) ? EDMI_R(0.000244140625)
                                                             : EDMI_R(9.31322574615478515625e-10);
    int i;
    for (i = 0; i < 24; i++) {
        edmi_real d0 = (edmi_real)(0.6 + 0.125 * i), d1 = (edmi_real)(0.6 + 0.125 * ((i + 7) % 24));
        edmi_real dd, ddd, dn = d0 + d0 * near;
        long double s0, s1, s2, s3, v0, v1, h = (long double)d1 - (long double)d0, q;
        long double e0 = expl(-(long double)bond.a * ((long double)d0 - bond.re));
        long double e1 = expl(-(long double)bond.a * ((long double)d1 - bond.re));
        long double g = -expm1l(-(long double)bond.a * h) / h;
        long double gd = ((long double)bond.a * h * expl(-(long double)bond.a * h) +
                          expm1l(-(long double)bond.a * h)) / (h * h), want;
        /* separated: the long double quotient and the closed derivative */
        v0 = morse_ref(0, 0, d0, &s0);
        v1 = morse_ref(0, 0, d1, &s1);
        q = (v1 - v0) / h;
        (void)morse_ref(0, 1, d0 < d1 ? d0 : d1, &s1); /* S_1 is largest at the smaller r */
        (void)morse_ref(0, 2, d0 < d1 ? d0 : d1, &s2);
        (void)morse_ref(0, 3, d0 < d1 ? d0 : d1, &s3);
        if (morse_dd(&bond, d0, d1, &dd, &ddd) != 0 || edmi_pot_divdiff(&pot, d0, d1, &dd, &ddd) != EDMI_OK) {
            morse_expect(0, "divided difference refused", (double)d0, 0, 0);
            continue;
        }
        morse_expect(fabsl(dd - q) <= tol * s1, "dd", (double)d0, (double)dd, (double)q);
        want = (long double)bond.depth * e0 * ((long double)bond.a * e1 * g + (2.0L - e0 - e1) * gd);
        morse_expect(fabsl(ddd - want) <= tol * s2, "dd_d1", (double)d0, (double)ddd, (double)want);
        /* confluent: V'(d0) and V''(d0) / 2 */
        (void)morse_ref(0, 1, d0, &s1);
        (void)morse_ref(0, 2, d0, &s2);
        (void)morse_ref(0, 3, d0, &s3);
        if (edmi_pot_divdiff(&pot, d0, d0, &dd, &ddd) == EDMI_OK) {
            morse_expect(fabsl(dd - morse_ref(0, 1, d0, &s0)) <= tol * s1, "dd(d, d)", (double)d0,
                         (double)dd, 0);
            morse_expect(fabsl(ddd - morse_ref(0, 2, d0, &s0) / 2.0L) <= tol * s2, "dd_d1(d, d)",
                         (double)d0, (double)ddd, 0);
        }
        /* near: dd = V' + D V''/2 + O(D^2 S_3), where a plain quotient loses eps |V| / D */
        if (edmi_pot_divdiff(&pot, d0, dn, &dd, &ddd) == EDMI_OK) {
            long double dl = (long double)dn - (long double)d0;
            long double w = morse_ref(0, 1, d0, &s0) + dl * morse_ref(0, 2, d0, &s0) / 2.0L;
            morse_expect(fabsl(dd - w) <= dl * dl / 6.0L * s3 + 2.0L * tol * s1, "dd near d0",
                         (double)d0, (double)dd, (double)w);
        }
    }
}

int main(int argc, char **argv)
{
    static const edmi_scheme schemes[2] = {EDMI_SCHEME_PM, EDMI_SCHEME_LG};
    static const char *const names[2] = {"PM", "LG"};
    const int check = argc == 2 && strcmp(argv[1], "--check") == 0;
    int s;
    if (argc > 2 || (argc == 2 && !check)) {
        fprintf(stderr, "usage: morse [--check]\n");
        return 2;
    }
    if (check) {
        morse_check_values();
        morse_check_divdiff();
    }
    printf("A Morse molecule (D = 1, a = 2, re = 1, two atoms of mass 1) stretched to 1.6 and\n"
           "spinning, 20,000 steps of 0.01 (%s):\n", edmi_is_double_precision() ? "double" : "float");
    for (s = 0; s < 2; s++) {
        morse_run r;
        if (!morse_simulate(schemes[s], &r)) {
            printf("%s: could not build the molecule\n", names[s]);
            return 1;
        }
        printf("  %s: failed steps %ld, (H - H0)/H0 at the end %+.3Le, largest rise %.3Le, "
               "|dL| %.2Le, |dJ| %.2Le\n", names[s], r.failed, r.drift / r.h0, r.rise, r.dl, r.dj);
        if (check) {
            /* momenta: the pair's forces are equal, opposite and central (rounding alone) */
            const long double eps = (long double)EDMI_EPS;
            morse_expect(r.failed == 0, "failed steps", 0, (double)r.failed, 0);
            morse_expect(r.dl <= 8.0L * eps * 20000.0L && r.dj <= 8.0L * eps * 20000.0L * r.scale,
                         "momenta", 0, (double)r.dl, (double)r.dj);
            if (schemes[s] == EDMI_SCHEME_PM) /* the guard: never above H0 (the tank starts empty) */
                morse_expect(r.rise <= 64.0L * LDBL_EPSILON * 4.0L, "PM's rise", 0, (double)r.rise, 0);
            else /* LG: conserved to round-off, a walk of 2e4 steps of a few eps H0 */
                morse_expect(fabsl(r.drift) <= 4096.0L * eps * r.h0, "LG's drift", 0,
                             (double)r.drift, 0);
        }
    }
    if (check)
        printf("%d passed, %d failed\n", morse_failed ? 0 : 1, morse_failed);
    return morse_failed ? 1 : 0;
}
