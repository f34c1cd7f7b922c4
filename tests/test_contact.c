/* The one-sided potentials (edmi.h: EDMI_POT_CONTACT, EDMI_POT_TETHER): values, splits and
 * the divided difference against their closed forms in long double, bad parameters refused,
 * and collisions stepped by every scheme: contact beginning and ending inside a step, the
 * linear and angular momentum kept, and H judged on the stored states in tp_q
 * (tests/passive.c: every window of steps within the works and the tank). */
#include <math.h>
#include "harness.h"
#include "suites.h"
#include "passive.h"

static long double tc_abs(long double x) { return x < 0.0L ? -x : x; }

/* Derivative n of k/3 x^3, x = sg (d - b) > 0, else 0 (sg = -1 contact, +1 tether). */
static long double tc_deriv(long double sg, long double k, long double b, long double d, int n)
{
    long double x = sg * (d - b);
    if (!(x > 0.0L))
        return 0.0L;
    switch (n) {
    case 0: return k * x * x * x / 3.0L;
    case 1: return sg * k * x * x;
    case 2: return 2.0L * k * x;
    case 3: return 2.0L * sg * k;
    default: return 0.0L;
    }
}

static edmi_potential tc_pot(int contact, edmi_real k, edmi_real b)
{
    return contact ? edmi_pot_contact(k, b) : edmi_pot_tether(k, b);
}

/* Values on a grid through the kink (d = b among them), the parts V_c = V_+ = V, V_e = V_- = 0
 * exactly, and the divided difference with its d1-derivative (a central difference of the
 * long double quotient) for pairs on either side and across. */
static void tc_check_forms(int contact)
{
    const edmi_real k = EDMI_R(3.0), b = EDMI_R(1.25);
    const long double sg = contact ? -1.0L : 1.0L, eps = (long double)EDMI_EPS;
    const edmi_potential pot = tc_pot(contact, k, b);
    int i, j, n, bad = 0, bad_dd = 0, bad_t = 0;
    for (i = 0; i <= 40; i++) {
        edmi_real d = EDMI_R(0.5) + EDMI_R(0.03125) * (edmi_real)i; /* exact: 0.5 .. 1.75 */
        edmi_pot_parts p;
        if (!CHECK_STATUS(edmi_pot_eval(&pot, d, &p), EDMI_OK))
            return;
        for (n = 0; n < 5; n++) {
            long double want = tc_deriv(sg, k, b, d, n);
            if (tc_abs((long double)p.v[n] - want) > 8.0L * eps * tc_abs(want) ||
                p.c[n] != p.v[n] || p.sp[n] != p.v[n] || p.e[n] != EDMI_R(0.0) ||
                p.sm[n] != EDMI_R(0.0))
                bad++;
        }
    }
    CHECK(bad == 0);
    for (i = 0; i <= 12; i++)
        for (j = 0; j <= 12; j++) {
            edmi_real d0 = EDMI_R(0.7) + EDMI_R(0.09375) * (edmi_real)i;
            edmi_real d1 = EDMI_R(0.7) + EDMI_R(0.09375) * (edmi_real)j;
            long double h = 1e-4L, x0 = sg * ((long double)d0 - b), x1 = sg * ((long double)d1 - b);
            long double y0 = x0 > 0.0L ? x0 : 0.0L, y1 = x1 > 0.0L ? x1 : 0.0L;
            long double scale = (long double)k * (y0 + y1) * (y0 + y1), want, wantd;
            edmi_real dd, dd1;
            if (i == j || tc_abs((long double)d1 - b) < 4.0L * h)
                continue;
            if (!CHECK_STATUS(edmi_pot_divdiff(&pot, d0, d1, &dd, &dd1), EDMI_OK))
                return;
            want = (tc_deriv(sg, k, b, d1, 0) - tc_deriv(sg, k, b, d0, 0)) /
                   ((long double)d1 - (long double)d0);
            wantd = ((tc_deriv(sg, k, b, d1 + h, 0) - tc_deriv(sg, k, b, d0, 0)) /
                         ((long double)d1 + h - (long double)d0) -
                     (tc_deriv(sg, k, b, d1 - h, 0) - tc_deriv(sg, k, b, d0, 0)) /
                         ((long double)d1 - h - (long double)d0)) /
                    (2.0L * h);
            if (tc_abs((long double)dd - want) > 32.0L * eps * scale)
                bad_dd++;
            if (tc_abs((long double)dd1 - wantd) > 1e-5L * ((long double)k * (y0 + y1) + scale))
                bad_t++;
        }
    CHECK(bad_dd == 0);
    CHECK(bad_t == 0);
}

/* Parameters outside the documented domain: refused by edmi_add_pair, nothing added. */
static void tc_check_refused(void)
{
    edmi_system sys;
    edmi_params prm = edmi_default_params();
    const edmi_real q0[3] = {0, 0, 0}, q1[3] = {1, 0, 0}, z[3] = {0, 0, 0};
    edmi_real nan = (edmi_real)NAN, inf = (edmi_real)INFINITY;
    edmi_potential bad[9];
    int i, n = 0;
    bad[n++] = edmi_pot_contact(EDMI_R(0.0), EDMI_R(1.0));
    bad[n++] = edmi_pot_contact(EDMI_R(-1.0), EDMI_R(1.0));
    bad[n++] = edmi_pot_contact(EDMI_R(1.0), EDMI_R(0.0)); /* a radius <= 0 */
    bad[n++] = edmi_pot_contact(EDMI_R(1.0), EDMI_R(-2.0));
    bad[n++] = edmi_pot_contact(nan, EDMI_R(1.0));
    bad[n++] = edmi_pot_contact(EDMI_R(1.0), inf);
    bad[n++] = edmi_pot_tether(EDMI_R(0.0), EDMI_R(1.0));
    bad[n++] = edmi_pot_tether(EDMI_R(1.0), EDMI_R(-0.5));
    bad[n++] = edmi_pot_tether(EDMI_R(1.0), nan);
    if (!CHECK_STATUS(edmi_init(&sys, &prm), EDMI_OK) ||
        !CHECK_STATUS(edmi_add_body(&sys, EDMI_R(1.0), q0, z, 0), EDMI_OK) ||
        !CHECK_STATUS(edmi_add_body(&sys, EDMI_R(1.0), q1, z, 0), EDMI_OK))
        return;
    for (i = 0; i < n; i++) {
        int f0 = th_failed();
        CHECK_STATUS(edmi_add_pair(&sys, 0, 1, &bad[i], 0), EDMI_ERR_PARAM);
        CHECK(sys.n_links == 0);
        if (th_failed() > f0)
            th_note_int("refused potential number", i);
    }
    {
        edmi_potential ok = edmi_pot_tether(EDMI_R(2.0), EDMI_R(0.0)); /* L = 0 is a rope of 0 */
        CHECK_STATUS(edmi_add_pair(&sys, 0, 1, &ok, 0), EDMI_OK);
    }
}

/* A run's figures: steps, failures, guard moves, windows broken (tp_window_step), the largest
 * drifts of L and J relative to their scale, H's change (tp_h), the closest approach. */
typedef struct tc_run {
    long steps, failed, moves, broken, unchecked;
    long double dl, dj, dh, h0, dmin, dend, vn0, vn1, k0, k1, dsmin;
} tc_run;

static long double tc_len(const edmi_real a[3], const edmi_real b[3])
{
    long double x = (long double)a[0] - b[0], y = (long double)a[1] - b[1], z = (long double)a[2] - b[2];
    return sqrtl(x * x + y * y + z * z);
}

/* The kinetic energy of the relative motion of bodies 0 and 1, mu |v_1 - v_0|^2 / 2, and their
 * relative normal velocity (> 0: separating). */
static long double tc_krel(const edmi_system *s, long double *vn)
{
    long double r[3], v[3], d = 0.0L, dot = 0.0L, v2 = 0.0L;
    long double m0 = s->body[0].m, m1 = s->body[1].m;
    int i;
    for (i = 0; i < 3; i++) {
        r[i] = (long double)s->body[0].q[i] - (long double)s->body[1].q[i];
        v[i] = (long double)s->body[0].p[i] / m0 - (long double)s->body[1].p[i] / m1;
        d += r[i] * r[i];
        dot += r[i] * v[i];
        v2 += v[i] * v[i];
    }
    *vn = dot / sqrtl(d);
    return 0.5L * m0 * m1 / (m0 + m1) * v2;
}

/* L and J of the stored state, and their scales sum |p|, sum |q| |p|. */
static void tc_moments(const edmi_system *s, long double l[3], long double j[3], long double *ls,
                       long double *js)
{
    int a, i;
    *ls = *js = 0.0L;
    for (i = 0; i < 3; i++)
        l[i] = j[i] = 0.0L;
    for (a = 0; a < s->n_bodies; a++) {
        const edmi_real *q = s->body[a].q, *p = s->body[a].p;
        for (i = 0; i < 3; i++)
            l[i] += p[i];
        j[0] += (long double)q[1] * p[2] - (long double)q[2] * p[1];
        j[1] += (long double)q[2] * p[0] - (long double)q[0] * p[2];
        j[2] += (long double)q[0] * p[1] - (long double)q[1] * p[0];
        *ls += tc_len(p, (const edmi_real[3]){0, 0, 0});
        *js += tc_len(q, (const edmi_real[3]){0, 0, 0}) * tc_len(p, (const edmi_real[3]){0, 0, 0});
    }
}

/* pair 1: balls of masses 1 and 2, radii adding to 1, meeting off centre at 1.5 m/s; pair 0:
 * a body on a slack tether of length 1 to an anchor at the origin, caught and swung. k = 1e4
 * N/m^2 (cubic), dt = 1e-3, 3000 steps: contact of ~0.1 s begins and ends inside steps. */
static int tc_simulate(int pair, edmi_scheme scheme, tc_run *out)
{
    static edmi_system sys, prev;
    static edmi_workspace work;
    edmi_params prm = edmi_default_params();
    const edmi_real k = EDMI_R(1e4), dt = EDMI_R(1e-3);
    edmi_potential pot = pair ? edmi_pot_contact(k, EDMI_R(1.0)) : edmi_pot_tether(k, EDMI_R(1.0));
    long double l0[3], j0[3], l[3], j[3], ls, js;
    long n;
    int i;
    out->steps = out->failed = out->moves = out->broken = out->unchecked = 0;
    out->dl = out->dj = out->dh = out->h0 = out->dmin = out->dend = out->vn0 = out->vn1 = 0.0L;
    out->k0 = out->k1 = 0.0L;
    out->dsmin = 1e30L;
    prm.scheme = scheme;
    prm.fallback = 1;
    prm.substep_levels = 3;
    prm.energy_balance = 1; /* diss_scheme in double-word on every step */
    if (edmi_init(&sys, &prm) != EDMI_OK)
        return 0;
    if (pair) {
        const edmi_real qa[3] = {EDMI_R(-1.0), EDMI_R(0.15), EDMI_R(0.0)};
        const edmi_real pa[3] = {EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.02)};
        const edmi_real qb[3] = {EDMI_R(1.0), EDMI_R(-0.2), EDMI_R(0.05)};
        const edmi_real pb[3] = {EDMI_R(-1.0), EDMI_R(0.0), EDMI_R(0.0)}; /* m 2: 0.5 m/s */
        if (edmi_add_body(&sys, EDMI_R(1.0), qa, pa, 0) != EDMI_OK ||
            edmi_add_body(&sys, EDMI_R(2.0), qb, pb, 0) != EDMI_OK ||
            edmi_add_pair(&sys, 0, 1, &pot, 0) != EDMI_OK)
            return 0;
    } else {
        const edmi_real q[3] = {EDMI_R(0.5), EDMI_R(0.0), EDMI_R(0.0)}, x[3] = {0, 0, 0};
        const edmi_real p[3] = {EDMI_R(1.5), EDMI_R(1.0), EDMI_R(0.25)};
        if (edmi_add_body(&sys, EDMI_R(1.0), q, p, 0) != EDMI_OK ||
            edmi_add_anchor(&sys, 0, x, &pot, 0) != EDMI_OK)
            return 0;
    }
    out->h0 = tp_h(&sys);
    if (pair)
        out->k0 = tc_krel(&sys, &out->vn0);
    out->dmin = 1e30L;
    tc_moments(&sys, l0, j0, &ls, &js);
    tp_window_start(&sys);
    for (n = 0; n < 3000; n++) {
        edmi_step_result res;
        int w;
        prev = sys;
        if (edmi_step(&sys, &work, dt, &res) != EDMI_OK || res.fallbacks > 0) {
            out->failed++;
            tp_window_start(&sys);
            continue;
        }
        out->steps++;
        out->moves += res.guard_action != 0;
        out->dsmin = fminl(out->dsmin, (long double)res.diss_scheme);
        w = tp_window_step(&prev, &sys, &res);
        out->broken += w == 0;
        out->unchecked += w < 0;
        tc_moments(&sys, l, j, &ls, &js);
        for (i = 0; i < 3; i++) {
            if (pair)
                out->dl = fmaxl(out->dl, tc_abs(l[i] - l0[i]) / ls);
            out->dj = fmaxl(out->dj, tc_abs(j[i] - j0[i]) / js);
        }
        out->dmin = fminl(out->dmin, pair ? tc_len(sys.body[0].q, sys.body[1].q)
                                          : -tc_len(sys.body[0].q, (const edmi_real[3]){0, 0, 0}));
    }
    out->dh = tp_h(&sys) - out->h0;
    out->dend = pair ? tc_len(sys.body[0].q, sys.body[1].q) : 0.0L;
    if (pair)
        out->k1 = tc_krel(&sys, &out->vn1);
    return 1;
}

static const char *tc_name(edmi_scheme s)
{
    return s == EDMI_MP ? "MP" : s == EDMI_LG ? "LG" : s == EDMI_GE ? "GE" : s == EDMI_PM ? "PM" : "PT";
}

static void tc_check_runs(int pair)
{
    static const edmi_scheme schemes[5] = {EDMI_MP, EDMI_LG, EDMI_GE, EDMI_PM, EDMI_PT};
    const long double eps = (long double)EDMI_EPS;
    int s;
    for (s = 0; s < 5; s++) {
        tc_run r;
        int decaying = schemes[s] != EDMI_MP && schemes[s] != EDMI_LG;
        if (!th_has_scheme(schemes[s]))
            continue;
        if (!CHECK(tc_simulate(pair, schemes[s], &r)))
            return;
        th_puts(pair ? "  two balls " : "  tether ");
        th_puts(tc_name(schemes[s]));
        th_puts(": failed ");
        th_put_int(r.failed);
        th_puts(", guard moves ");
        th_put_int(r.moves);
        th_puts(", min diss_scheme/H0 ");
        th_put_ld(r.dsmin / r.h0, 3);
        th_puts(", windows broken ");
        th_put_int(r.broken);
        th_puts(", (H - H0)/H0 ");
        th_put_ld(r.dh / r.h0, 3);
        th_puts(pair ? ", restitution " : ", max |dJ|/scale ");
        th_put_ld(pair ? sqrtl(r.k1 / r.k0) : r.dj, 3);
        th_newline();
        CHECK(r.failed == 0 && r.unchecked == 0);
        /* the forces are central and opposite: L (pair) and J change by the rounding of the
         * stored q and p alone, at most a few units of their scale per step */
        CHECK(r.dl <= 8.0L * eps * (long double)r.steps && r.dj <= 8.0L * eps * (long double)r.steps);
        if (pair) /* they met (within 1 - 0.05) and parted again, with a restitution <= 1 */
            CHECK(r.dmin < 0.95L && r.dend > 1.0L && r.vn0 < 0.0L && r.vn1 > 0.0L &&
                  (!decaying || r.k1 <= r.k0));
        else /* caught by the rope: at 1 + 0.05 at the farthest */
            CHECK(-r.dmin > 1.02L);
        if (decaying) {
            /* the split keeps the decay across the kink: the scheme's own dissipation is never
             * below its force's rounding (the guard moves only on the first step, from an
             * empty tank, or to cover rounding), and no window of steps broken */
            CHECK(r.dsmin >= -64.0L * eps * r.h0);
            CHECK(r.broken == 0 && r.dh <= 0.0L);
        } else if (schemes[s] == EDMI_LG) { /* conserving: H to Newton's tolerance */
            CHECK(tc_abs(r.dh) <= 1e-6L * r.h0 + 4096.0L * eps * r.h0);
        }
    }
}

void suite_contact(void)
{
    th_suite("contact: one-sided potentials, collisions and tethers");
    TH_NEEDS(th_has_pot(EDMI_POT_CONTACT));
    tc_check_forms(1);
    tc_check_forms(0);
    tc_check_refused();
    tc_check_runs(1);
    tc_check_runs(0);
}
