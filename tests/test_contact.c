/* The one-sided potentials (edmi.h: EDMI_POT_CONTACT, EDMI_POT_TETHER): values, splits and
 * the divided difference against their closed forms in long double, bad parameters refused,
 * and collisions stepped by every scheme: contact beginning and ending inside a step, the
 * linear and angular momentum kept, and H judged on the stored states in tp_q
 * (tests/lib/passive.c: every window of steps within the works and the tank). */
#include <math.h>
#include "harness.h"
#include "suites.h"
#include "passive.h"
#include "scenes.h"

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
    static edmi_system sys;
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

/* Every scheme (the runs that compare them all). */
static const edmi_scheme tc_all[5] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};

static void tc_check_runs(int pair)
{
    const edmi_scheme *schemes = tc_all;
    const long double eps = (long double)EDMI_EPS;
    int s;
    for (s = 0; s < 5; s++) {
        tc_run r;
        int decaying = schemes[s] != EDMI_SCHEME_MP && schemes[s] != EDMI_SCHEME_LG;
        if (!th_has_scheme(schemes[s]))
            continue;
        if (!CHECK(tc_simulate(pair, schemes[s], &r)))
            return;
        th_puts(pair ? "  two balls " : "  tether ");
        th_puts(ts_scheme_name(schemes[s]));
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
        } else if (schemes[s] == EDMI_SCHEME_LG) { /* conserving: H to Newton's tolerance */
            CHECK(tc_abs(r.dh) <= 1e-6L * r.h0 + 4096.0L * eps * r.h0);
        }
    }
}

#if EDMI_MAX_WALLS > 0
/* ---- walls ------------------------------------------------------------------------------ */

/* The schemes whose energy decays: the hard cases against walls. */
static const edmi_scheme tc_decaying[3] = {EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};

/* What a run of steps did, as the hard cases report it: steps that failed, were split
 * into substeps or fell back, windows broken (or not evaluated), guard moves, and the largest
 * H_n - H_0 - (the works from 0 to n) on the stored states (tp_window_rise, __float128). */
typedef struct tc_tally {
    long steps, failed, split, fallbacks, broken, unchecked, moves;
} tc_tally;

static void tc_tally_start(tc_tally *t, const edmi_system *s)
{
    t->steps = t->failed = t->split = t->fallbacks = t->broken = t->unchecked = t->moves = 0;
    tp_window_start(s);
}

/* Count the step from prev to s that returned st with res; 1 if it succeeded. */
static int tc_tally_step(tc_tally *t, edmi_status st, const edmi_system *prev,
                         const edmi_system *s, const edmi_step_result *res)
{
    int w;
    t->steps++;
    if (st != EDMI_OK) {
        t->failed++;
        tp_window_start(s);
        return 0;
    }
    t->split += res->substeps > 1;
    t->fallbacks += res->fallbacks;
    t->moves += res->guard_action != 0;
    w = tp_window_step(prev, s, res);
    t->broken += w == 0;
    t->unchecked += w < 0;
    return 1;
}

/* Print the tally after the case's label; 1 if no step failed, fell back or broke a window,
 * and every step was evaluated (a split step is counted, not refused: substeps are what a
 * step takes where one Newton solve cannot). */
static int tc_tally_put(const tc_tally *t, const char *label, edmi_scheme scheme)
{
    th_puts(label);
    th_puts(ts_scheme_name(scheme));
    th_puts(": steps ");
    th_put_int(t->steps);
    th_puts(", failed ");
    th_put_int(t->failed);
    th_puts(", split ");
    th_put_int(t->split);
    th_puts(", fallbacks ");
    th_put_int(t->fallbacks);
    th_puts(", windows broken ");
    th_put_int(t->broken);
    th_puts(", guard moves ");
    th_put_int(t->moves);
    th_puts(", max H_n - H_0 - sum W ");
    th_put_ld(tp_window_rise(), 3);
    return t->failed == 0 && t->fallbacks == 0 && t->broken == 0 && t->unchecked == 0;
}

/* Refused walls: no body, a normal of length 0 or not finite, an offset not finite, a
 * potential a wall does not take or outside its domain; nothing added. */
static void tc_check_wall_refused(void)
{
    static edmi_system sys;
    edmi_params prm = edmi_default_params();
    const edmi_real q[3] = {0, 0, 1}, z[3] = {0, 0, 0}, up[3] = {0, 0, 2};
    const edmi_real zero[3] = {0, 0, 0}, nan3[3] = {0, (edmi_real)NAN, 1};
    edmi_potential ok = edmi_pot_contact(EDMI_R(1e4), EDMI_R(0.0)); /* a point on a floor */
    edmi_potential bad_k = edmi_pot_contact(EDMI_R(0.0), EDMI_R(0.1));
    edmi_potential bad_r = edmi_pot_contact(EDMI_R(1.0), EDMI_R(-0.1));
    edmi_potential other = edmi_pot_inverse(EDMI_R(1.0));
    int idx = -1;
    if (!CHECK_STATUS(edmi_init(&sys, &prm), EDMI_OK) ||
        !CHECK_STATUS(edmi_add_body(&sys, EDMI_R(1.0), q, z, 0), EDMI_OK))
        return;
    CHECK_STATUS(edmi_add_wall(&sys, 1, up, EDMI_R(0.0), &ok, 0), EDMI_ERR_INDEX);
    CHECK_STATUS(edmi_add_wall(&sys, 0, zero, EDMI_R(0.0), &ok, 0), EDMI_ERR_PARAM);
    CHECK_STATUS(edmi_add_wall(&sys, 0, nan3, EDMI_R(0.0), &ok, 0), EDMI_ERR_NONFINITE);
    CHECK_STATUS(edmi_add_wall(&sys, 0, up, (edmi_real)INFINITY, &ok, 0), EDMI_ERR_NONFINITE);
    CHECK_STATUS(edmi_add_wall(&sys, 0, up, EDMI_R(0.0), &bad_k, 0), EDMI_ERR_PARAM);
    CHECK_STATUS(edmi_add_wall(&sys, 0, up, EDMI_R(0.0), &bad_r, 0), EDMI_ERR_PARAM);
    CHECK_STATUS(edmi_add_wall(&sys, 0, up, EDMI_R(0.0), &other, 0), EDMI_ERR_PARAM);
    CHECK_STATUS(edmi_add_wall(&sys, 0, up, EDMI_R(0.0), 0, 0), EDMI_ERR_NULL);
    CHECK(sys.n_walls == 0);
    /* accepted: the normal stored as a unit vector */
    if (CHECK_STATUS(edmi_add_wall(&sys, 0, up, EDMI_R(0.0), &ok, &idx), EDMI_OK))
        CHECK(idx == 0 && sys.n_walls == 1 && sys.wall[0].n[2] == EDMI_R(1.0) &&
              sys.wall[0].n[0] == EDMI_R(0.0));
}

/* A ball of 0.1 kg and radius 0.05 m (contact k = 1e6 N/m^2 against the plane) under gravity,
 * thrown sideways from 0.5 m: 4 s in steps of 1e-3 s, several bounces. tilt 1: the floor's
 * normal (0.6, 0, 0.8) and gravity along -n (the same motion, turned), else n = z; tilt 2:
 * the level floor a thousand times stiffer (k = 1e9 N/m^2), a penetration whose stiffness
 * V'' = 2 k x reaches 2.2e6 N/m (omega dt = 4.7 at the deepest: the contact is not resolved),
 * and the weight a force port instead of the field: its work, work_ext, is at most the exact
 * m g . (q_n+1 - q_n) on every step, split ones included (tp_port_work_below). */
typedef struct tc_bounce {
    tc_tally t;
    long bounces, works_above;
    long double h0, dh, dpt, rest1, pmax, solved;
} tc_bounce;

static int tc_ball(edmi_scheme scheme, int tilt, tc_bounce *out)
{
    static edmi_system sys, prev;
    static edmi_workspace work, work2;
    edmi_params prm = edmi_default_params();
    const edmi_real dt = EDMI_R(1e-3), m = EDMI_R(0.1);
    edmi_real n[3] = {0, 0, 1}, t1[3] = {1, 0, 0}, t2[3] = {0, 1, 0}, g[3], w[3], q[3], p[3];
    edmi_potential pot = edmi_pot_contact(tilt == 2 ? EDMI_R(1e9) : EDMI_R(1e6), EDMI_R(0.05));
    long double pt0[2], e_up = 0.0L, gap, port_work = 0.0L;
    long k;
    int i, falling = 1;
    out->bounces = out->works_above = 0;
    out->h0 = out->dh = out->dpt = out->rest1 = out->pmax = out->solved = 0.0L;
    if (tilt == 1) {
        n[0] = EDMI_R(0.6), n[2] = EDMI_R(0.8);
        t1[0] = EDMI_R(0.8), t1[2] = EDMI_R(-0.6);
    }
    for (i = 0; i < 3; i++) {
        g[i] = EDMI_R(-9.81) * n[i];
        q[i] = EDMI_R(0.5) * n[i] + EDMI_R(0.2) * t2[i];
        p[i] = m * (EDMI_R(1.0) * t1[i] + EDMI_R(0.5) * t2[i]);
    }
    prm.scheme = scheme;
    prm.fallback = 1;
    prm.substep_levels = 3;
    prm.energy_balance = 1;
    if (edmi_init(&sys, &prm) != EDMI_OK || edmi_add_body(&sys, m, q, p, 0) != EDMI_OK ||
        edmi_add_wall(&sys, 0, n, EDMI_R(0.0), &pot, 0) != EDMI_OK)
        return 0;
    for (i = 0; i < 3; i++) /* the weight, as a port */
        w[i] = m * g[i];
    if ((tilt == 2 ? edmi_set_force(&sys, 0, w) : edmi_set_field(&sys, g)) != EDMI_OK)
        return 0;
    out->h0 = tp_h(&sys);
    pt0[0] = (long double)sys.body[0].p[0] * t1[0] + (long double)sys.body[0].p[1] * t1[1] +
             (long double)sys.body[0].p[2] * t1[2];
    pt0[1] = (long double)sys.body[0].p[0] * t2[0] + (long double)sys.body[0].p[1] * t2[1] +
             (long double)sys.body[0].p[2] * t2[2];
    tc_tally_start(&out->t, &sys);
    for (k = 0; k < 4000; k++) {
        edmi_step_result res;
        long double pt[2], pn;
        prev = sys;
        if (!tc_tally_step(&out->t, edmi_step(&sys, &work, dt, &res), &prev, &sys, &res))
            continue;
        out->works_above += !tp_port_work_below(&prev, &sys, &res);
        port_work += (long double)res.work_ext;
        if (res.guard_action == 0 && res.substeps == 1) { /* OK means solved (edmi.h) */
            edmi_status st;
            int body, which;
            long double x = tp_solved(&prev, &sys, dt, &work2, &st, &body, &which);
            out->solved = fmaxl(out->solved, x < 0.0L ? 1e30L : x);
        }
        pt[0] = (long double)sys.body[0].p[0] * t1[0] + (long double)sys.body[0].p[1] * t1[1] +
                (long double)sys.body[0].p[2] * t1[2];
        pt[1] = (long double)sys.body[0].p[0] * t2[0] + (long double)sys.body[0].p[1] * t2[1] +
                (long double)sys.body[0].p[2] * t2[2];
        out->dpt = fmaxl(out->dpt, fmaxl(tc_abs(pt[0] - pt0[0]), tc_abs(pt[1] - pt0[1])));
        out->pmax = fmaxl(out->pmax, tc_len(sys.body[0].p, (const edmi_real[3]){0, 0, 0}));
        pn = (long double)sys.body[0].p[0] * n[0] + (long double)sys.body[0].p[1] * n[1] +
             (long double)sys.body[0].p[2] * n[2];
        gap = (long double)sys.body[0].q[0] * n[0] + (long double)sys.body[0].q[1] * n[1] +
              (long double)sys.body[0].q[2] * n[2];
        if (falling && gap < 0.05L) { /* contact */
            falling = 0;
        } else if (!falling && gap >= 0.05L && pn > 0.0L) { /* left the floor: a bounce */
            falling = 1;
            if (++out->bounces == 1)
                e_up = pn * pn; /* the first rebound's speed, times m, squared */
        }
    }
    out->dh = tp_h(&sys) - out->h0 - port_work; /* H - H0 less the port's work */
    /* the first impact at sqrt(2 g (0.5 - R)): restitution = rebound / impact speed (the
     * rebound measured where the ball leaves the floor, within a step of it) */
    out->rest1 = sqrtl(e_up) / (long double)m / sqrtl(2.0L * 9.81L * 0.45L);
    return 1;
}

static void tc_check_ball(int tilt)
{
    const edmi_scheme *schemes = tc_all;
    const long double eps = (long double)EDMI_EPS;
    int s;
    for (s = 0; s < 5; s++) {
        tc_bounce r;
        int clean, decaying = schemes[s] != EDMI_SCHEME_MP && schemes[s] != EDMI_SCHEME_LG;
        if (!th_has_scheme(schemes[s]))
            continue;
        if (!CHECK(tc_ball(schemes[s], tilt, &r)))
            return;
        clean = tc_tally_put(&r.t, tilt == 1   ? "  ball on a tilted floor " :
                                   tilt == 2 ? "  ball on a stiff floor (k 1e9) " :
                                               "  ball on a floor ",
                             schemes[s]);
        th_puts(", bounces ");
        th_put_int(r.bounces);
        th_puts(", first restitution ");
        th_put_ld(r.rest1, 4);
        th_puts(", (H - H0)/H0 ");
        th_put_ld(r.dh / r.h0, 3);
        th_puts(", max |dp along the floor| ");
        th_put_ld(r.dpt, 3);
        th_puts(", worst residual/bound ");
        th_put_ld(r.solved / (long double)EDMI_SOLVED, 3);
        if (tilt == 2) {
            th_puts(", steps whose work_ext exceeds the exact work ");
            th_put_int(r.works_above);
        }
        th_newline();
        CHECK(r.works_above == 0);
        CHECK(r.t.failed == 0 && r.t.fallbacks == 0 && r.t.unchecked == 0 && r.bounces >= 3);
        CHECK(r.solved <= (long double)EDMI_SOLVED);
        /* the wall's force is along n: the momentum along the floor is kept, exactly where
         * n is an axis (its other components are 0; the guard's moves, where free fall
         * drained the tank, are impulses along n too), else to the rounding of each step */
        if (tilt != 0) /* a port: the guard's rounding moves touch every component */
            CHECK(r.dpt <= 8.0L * eps * r.pmax * 4000.0L);
        else
            CHECK(r.dpt == 0.0L);
        if (decaying) {
            CHECK(clean && r.dh <= 0.0L && r.rest1 <= 1.0L);
        } else if (schemes[s] == EDMI_SCHEME_LG) { /* energy kept: a rebound within a step's
                                               fall, g dt, of the impact speed */
            CHECK(tc_abs(r.dh) <= 1e-6L * r.h0 + 4096.0L * eps * r.h0);
            CHECK(tc_abs(r.rest1 - 1.0L) <= 9.81e-3L / sqrtl(2.0L * 9.81L * 0.45L));
        }
    }
}

/* Hard cases against walls, both precisions, every decaying scheme, 3,000 steps of 1e-3 s
 * with substeps and the fallback on: a ball (0.1 kg, R = 0.05, k = 1e6) dropped into the
 * corner of a floor and a wall tilted 60 degrees, where it wedges and settles (GE loses most
 * of its energy, PM and PT keep rocking); a ball rolling along the floor exactly at the
 * contact distance, g = R, without gravity (grazing: the kink under it every step). Each:
 * no failed or fallback step, every window within the works and the tank (__float128), the
 * body never through a wall (its gap above 0), and grazing: nothing happens (the stored
 * momentum changes only where the guard moved, on the first step from an empty tank). */
static int tc_same_p(const edmi_system *a, const edmi_system *b)
{
    return a->body[0].p[0] == b->body[0].p[0] && a->body[0].p[1] == b->body[0].p[1] &&
           a->body[0].p[2] == b->body[0].p[2];
}

static void tc_check_wall_cases(void)
{
    const edmi_scheme *schemes = tc_decaying;
    static edmi_system sys, prev;
    static edmi_workspace work;
    int s, c;
    for (c = 0; c < 2; c++)
        for (s = 0; s < 3; s++) {
            edmi_params prm = edmi_default_params();
            edmi_potential pot = edmi_pot_contact(EDMI_R(1e6), EDMI_R(0.05));
            const edmi_real up[3] = {0, 0, 1}, slope[3] = {EDMI_R(-0.8660254), 0, EDMI_R(0.5)};
            edmi_real q[3] = {EDMI_R(-0.1), 0, EDMI_R(0.3)}, p[3] = {0, 0, 0};
            const edmi_real g[3] = {0, 0, EDMI_R(-9.81)};
            long k, moved = 0;
            long double gmin = 1e30L;
            tc_tally t;
            int clean;
            if (!th_has_scheme(schemes[s]))
                continue;
            prm.scheme = schemes[s];
            prm.fallback = 1;
            prm.substep_levels = 3;
            if (c == 1) { /* grazing */
                q[0] = 0, q[2] = EDMI_R(0.05);
                p[0] = EDMI_R(0.1), p[1] = EDMI_R(0.03);
            }
            if (!CHECK(edmi_init(&sys, &prm) == EDMI_OK &&
                       edmi_add_body(&sys, EDMI_R(0.1), q, p, 0) == EDMI_OK &&
                       edmi_add_wall(&sys, 0, up, EDMI_R(0.0), &pot, 0) == EDMI_OK))
                return;
            if (c == 0 && !CHECK(edmi_add_wall(&sys, 0, slope, EDMI_R(0.0), &pot, 0) == EDMI_OK &&
                                 edmi_set_field(&sys, g) == EDMI_OK))
                return;
            tc_tally_start(&t, &sys);
            for (k = 0; k < 3000; k++) {
                edmi_step_result res;
                int j;
                prev = sys;
                if (!tc_tally_step(&t, edmi_step(&sys, &work, EDMI_R(1e-3), &res), &prev, &sys,
                                   &res))
                    continue;
                for (j = 0; j < sys.n_walls; j++) {
                    long double gap = (long double)sys.wall[j].n[0] * sys.body[0].q[0] +
                                      (long double)sys.wall[j].n[1] * sys.body[0].q[1] +
                                      (long double)sys.wall[j].n[2] * sys.body[0].q[2] -
                                      (long double)sys.wall[j].c;
                    gmin = fminl(gmin, gap);
                }
                if (c == 1 && !tc_same_p(&prev, &sys))
                    moved++;
            }
            clean = tc_tally_put(&t, c == 0 ? "  wedged in a corner " : "  grazing a floor ",
                                 schemes[s]);
            th_puts(", smallest gap ");
            th_put_ld(gmin, 3);
            if (c == 1) {
                th_puts(", momentum changed on ");
                th_put_int(moved);
                th_puts(" steps");
            }
            th_newline();
            CHECK(clean && gmin > 0.0L);
            if (c == 1) /* the scheme changes nothing; the guard fills its tank once */
                CHECK(moved <= t.moves && t.moves <= 1);
        }
}
/* Rest on a floor is a fixed point, as on an anchor (tests/test_guard.c, (7)): a ball of
 * 0.1 kg (R = 0.05, k = 1e6 N/m^2) under gravity, placed at rest where the floor carries it,
 * gap R - sqrt(m g / k) (rounded), with every scheme and the guard on; and dropped from 1 cm
 * above contact with GE, which settles it by its own dissipation. Each: every step EDMI_OK,
 * none split or fallen back, every window within the works and the tank (__float128). It
 * rests where a step cannot move q by half a unit in its last place: from rest a step moves
 * it by (omega dt)^2 x / 2 for an offset x from the balance (omega^2 = 2 k sqrt(m g / k) / m,
 * (omega dt)^2 about 0.02 at dt = 1e-3), so within A = 2 ulp(gap) / (omega dt)^2 of the
 * balance, about 100 units. Placed at rest, the state is bit for bit unchanged from the first
 * step (the guard's hold keeps p at 0 where the force's rounding would start the
 * oscillation of a grid unit that an empty tank cannot pay for). Dropped, it settles within
 * A with a kinetic energy within m omega^2 A^2 / 2 over the last quarter, and no further: the
 * stored gap is not the balance, so the exact motion is an oscillation about it of a few
 * units in the last place, which GE's dissipation (of third order in the motion) no longer
 * damps and the tank, filled by the fall, pays for (measured: double, q fixed for tens of
 * steps while p swings through +-2e-16, K ~ 1e-31 J; float: a fixed point by step 3,917). */
static void tc_check_rest(void)
{
    static const edmi_scheme schemes[6] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT, EDMI_SCHEME_GE};
    static edmi_system sys, prev;
    static edmi_workspace work;
    const long double m = 0.1L, grav = 9.81L, k = 1e6L, radius = 0.05L, dt = 1e-3L;
    const long double depth = sqrtl(m * grav / k), w2 = 2.0L * k * depth / m;
    int s;
    for (s = 0; s < 6; s++) {
        edmi_params prm = edmi_default_params();
        edmi_potential pot = edmi_pot_contact((edmi_real)k, (edmi_real)radius);
        const edmi_real up[3] = {0, 0, 1}, g[3] = {0, 0, (edmi_real)-grav}, p[3] = {0, 0, 0};
        const int dropped = s == 5;
        const long n = dropped ? 16000 : 6000;
        edmi_real q[3] = {0, 0, 0};
        long i, last = 0;
        long double off = 0.0L, kin = 0.0L, bound, kmax;
        tc_tally t;
        int clean;
        if (!th_has_scheme(schemes[s]))
            continue;
        prm.scheme = schemes[s];
        prm.guard = EDMI_GUARD_ON;
        prm.fallback = 1;
        prm.substep_levels = 3;
        q[2] = (edmi_real)(dropped ? radius + 0.01L : radius - depth);
        if (!CHECK(edmi_init(&sys, &prm) == EDMI_OK &&
                   edmi_add_body(&sys, (edmi_real)m, q, p, 0) == EDMI_OK &&
                   edmi_set_field(&sys, g) == EDMI_OK &&
                   edmi_add_wall(&sys, 0, up, EDMI_R(0.0), &pot, 0) == EDMI_OK))
            return;
        tc_tally_start(&t, &sys);
        for (i = 0; i < n; i++) {
            edmi_step_result res;
            prev = sys;
            tc_tally_step(&t, edmi_step(&sys, &work, (edmi_real)dt, &res), &prev, &sys, &res);
            if (!tc_same_p(&prev, &sys) || prev.body[0].q[0] != sys.body[0].q[0] ||
                prev.body[0].q[1] != sys.body[0].q[1] || prev.body[0].q[2] != sys.body[0].q[2])
                last = i + 1;
            if (i >= n - n / 4) {
                off = fmaxl(off, tc_abs((long double)sys.body[0].q[2] - (radius - depth)));
                kin = fmaxl(kin, (long double)sys.body[0].p[2] * sys.body[0].p[2] / (2.0L * m));
            }
        }
        bound = 2.0L * (long double)EDMI_EPS * radius / (w2 * dt * dt);
        kmax = 0.5L * m * w2 * bound * bound;
        clean = tc_tally_put(&t, dropped ? "  dropped onto a floor, settling, " :
                                           "  at rest on a floor ", schemes[s]);
        th_puts(", last change at step ");
        th_put_int(last);
        th_puts(", last quarter: offset from the balance ");
        th_put_ld(off, 3);
        th_puts(" (A ");
        th_put_ld(bound, 3);
        th_puts("), K ");
        th_put_ld(kin, 3);
        th_puts(" J");
        th_newline();
        CHECK(clean && t.split == 0 && off <= bound && kin <= kmax);
        if (!dropped) /* a fixed point from the first step */
            CHECK(last == 0 && t.broken == 0);
        CHECK(sys.body[0].q[0] == EDMI_R(0.0) && sys.body[0].q[1] == EDMI_R(0.0));
    }
}

/* Sixteen balls in a box (as examples/scenes/balls_in_box.scene, in a plane so that it fits
 * the suite's capacities: 64 walls and 120 contacts): balls of 0.1 kg and radius 0.05 in
 * the square [0, 1]^2 at z = 0.5, under gravity along -y, thrown at up to 0.8 m/s; k = 1e6
 * N/m^2 for walls and pairs, 1,000 steps of 1e-3 s with substeps and the fallback, GE, PM
 * and PT. The motion stays in the plane exactly (every force and guard impulse is along a
 * link or a wall's normal, whose z components are 0). Each: every step EDMI_OK, every window
 * within the works and the tank (__float128), no ball through a wall, none through another
 * (their distance above 0.1 - the overlap a cubic of k = 1e6 allows at these speeds, 0.02),
 * and the total momentum along z exactly 0. Failed, split and fallback steps are reported. */
#if EDMI_MAX_BODIES >= 16 && EDMI_MAX_LINKS >= 120 && EDMI_MAX_WALLS >= 64
static void tc_check_box(void)
{
    const edmi_scheme *schemes = tc_decaying;
    static edmi_system sys, prev;
    static edmi_workspace work;
    /* initial velocities (m/s), fixed: a deterministic run on every target */
    static const signed char vel[16][2] = {{-4, -7}, {-8, 1}, {-8, 0}, {-1, -8}, {-1, 6}, {-5, 2},
                                           {1, -2}, {-8, 7}, {-7, -7}, {6, -6}, {2, -2}, {-8, -8},
                                           {3, -1}, {1, -1}, {5, 3}, {1, 0}};
    int s;
    for (s = 0; s < 3; s++) {
        edmi_params prm = edmi_default_params();
        edmi_potential pair = edmi_pot_contact(EDMI_R(1e6), EDMI_R(0.1));
        edmi_potential face = edmi_pot_contact(EDMI_R(1e6), EDMI_R(0.05));
        static const edmi_real nrm[4][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
        static const edmi_real off[4] = {0, -1, 0, -1};
        const edmi_real g[3] = {0, EDMI_R(-9.81), 0};
        long k;
        long double gmin = 1e30L, dmin = 1e30L, pz = 0.0L;
        int a, b, ok = 1, clean;
        tc_tally t;
        if (!th_has_scheme(schemes[s]))
            continue;
        prm.scheme = schemes[s];
        prm.fallback = 1;
        prm.substep_levels = 3;
        ok = edmi_init(&sys, &prm) == EDMI_OK && edmi_set_field(&sys, g) == EDMI_OK;
        for (a = 0; a < 16 && ok; a++) {
            const edmi_real q[3] = {EDMI_R(0.2) * (edmi_real)(1 + a / 4),
                                    EDMI_R(0.2) * (edmi_real)(1 + a % 4), EDMI_R(0.5)};
            const edmi_real p[3] = {EDMI_R(0.01) * (edmi_real)vel[a][0],
                                    EDMI_R(0.01) * (edmi_real)vel[a][1], 0};
            ok = edmi_add_body(&sys, EDMI_R(0.1), q, p, 0) == EDMI_OK;
            for (b = 0; b < 4 && ok; b++)
                ok = edmi_add_wall(&sys, a, nrm[b], off[b], &face, 0) == EDMI_OK;
            for (b = 0; b < a && ok; b++)
                ok = edmi_add_pair(&sys, b, a, &pair, 0) == EDMI_OK;
        }
        if (!CHECK(ok))
            return;
        tc_tally_start(&t, &sys);
        for (k = 0; k < 1000; k++) {
            edmi_step_result res;
            int j;
            prev = sys;
            if (!tc_tally_step(&t, edmi_step(&sys, &work, EDMI_R(1e-3), &res), &prev, &sys, &res))
                continue;
            for (j = 0; j < sys.n_walls; j++) {
                const edmi_real *q = sys.body[sys.wall[j].a].q, *n = sys.wall[j].n;
                gmin = fminl(gmin, (long double)n[0] * q[0] + (long double)n[1] * q[1] -
                                       (long double)sys.wall[j].c);
            }
            for (j = 0; j < sys.n_links; j++)
                dmin = fminl(dmin, tc_len(sys.body[sys.link[j].a].q, sys.body[sys.link[j].b].q));
        }
        for (a = 0; a < 16; a++)
            pz += (long double)sys.body[a].p[2] + tc_abs((long double)sys.body[a].q[2] - 0.5L);
        clean = tc_tally_put(&t, "  16 balls in a box ", schemes[s]);
        th_puts(", smallest gap to a wall ");
        th_put_ld(gmin, 3);
        th_puts(", between balls ");
        th_put_ld(dmin, 3);
        th_newline();
        CHECK(t.failed == 0 && t.broken == 0 && t.unchecked == 0 && tp_window_rise() <= 0.0L);
        CHECK(gmin > 0.05L - 0.02L && dmin > 0.1L - 0.02L && pz == 0.0L);
        (void)clean;
    }
}
#endif

/* A floor driven into a resting ball (a piston, edmi_move_wall): the floor rises at 0.5 m/s
 * for 0.2 s into a ball of 0.1 kg (R = 0.05, k = 1e6) touching it at rest, no gravity, then
 * stops; 1,000 steps of 1e-3 s, GE, PM, PT in both precisions. No failed or fallback step;
 * every window within the works and the tank (__float128), the wall's work reported in
 * work_anchor; the ball thrown upwards (faster than the floor: it leaves it), its momentum
 * along the floor 0; and the ball's kinetic energy at the end within the work the floor did
 * (plus the tank), and at least 90 % of it (GE dissipates). */
static void tc_check_piston(void)
{
    const edmi_scheme *schemes = tc_decaying;
    static edmi_system sys, prev;
    static edmi_workspace work;
    int s;
    for (s = 0; s < 3; s++) {
        edmi_params prm = edmi_default_params();
        edmi_potential pot = edmi_pot_contact(EDMI_R(1e6), EDMI_R(0.05));
        const edmi_real up[3] = {0, 0, 1}, q[3] = {0, 0, EDMI_R(0.05)}, p[3] = {0, 0, 0};
        long k;
        long double work_sum = 0.0L, ke;
        tc_tally t;
        int clean;
        if (!th_has_scheme(schemes[s]))
            continue;
        prm.scheme = schemes[s];
        prm.fallback = 1;
        prm.substep_levels = 3;
        if (!CHECK(edmi_init(&sys, &prm) == EDMI_OK &&
                   edmi_add_body(&sys, EDMI_R(0.1), q, p, 0) == EDMI_OK &&
                   edmi_add_wall(&sys, 0, up, EDMI_R(0.0), &pot, 0) == EDMI_OK))
            return;
        tc_tally_start(&t, &sys);
        for (k = 0; k < 1000; k++) {
            edmi_step_result res;
            if (k < 200 && !CHECK(edmi_move_wall(&sys, 0, EDMI_R(5e-4) * (edmi_real)(k + 1)) ==
                                  EDMI_OK))
                return;
            prev = sys;
            if (tc_tally_step(&t, edmi_step(&sys, &work, EDMI_R(1e-3), &res), &prev, &sys, &res))
                work_sum += (long double)res.work_anchor;
        }
        ke = ((long double)sys.body[0].p[2] * sys.body[0].p[2]) / (2.0L * 0.1L);
        clean = tc_tally_put(&t, "  floor driven into a ball ", schemes[s]);
        th_puts(", work of the floor ");
        th_put_ld(work_sum, 4);
        th_puts(" J, ball's K ");
        th_put_ld(ke, 4);
        th_puts(" J, speed ");
        th_put_ld((long double)sys.body[0].p[2] / 0.1L, 4);
        th_newline();
        CHECK(clean);
        CHECK(sys.body[0].p[0] == EDMI_R(0.0) && sys.body[0].p[1] == EDMI_R(0.0));
        CHECK((long double)sys.body[0].p[2] / 0.1L > 0.5L && sys.wall[0].c == EDMI_R(0.1));
        CHECK(ke <= work_sum + (long double)sys.tank && ke >= 0.9L * work_sum);
    }
}

#endif

void suite_contact(void)
{
    th_suite("contact: one-sided potentials, collisions and tethers");
    TH_NEEDS(th_has_pot(EDMI_POT_CONTACT));
    tc_check_forms(1);
    tc_check_forms(0);
    tc_check_refused();
    tc_check_runs(1);
    tc_check_runs(0);
#if EDMI_MAX_WALLS > 0
    tc_check_wall_refused();
    tc_check_ball(0);
    tc_check_ball(1);
    tc_check_ball(2);
    tc_check_wall_cases();
    tc_check_rest();
    tc_check_piston();
#if EDMI_MAX_BODIES >= 16 && EDMI_MAX_LINKS >= 120 && EDMI_MAX_WALLS >= 64
    tc_check_box();
#else
    (void)th_skip(0, "16 balls in a box (the capacities hold fewer than 16 bodies, 120 links, 64 walls)");
#endif
#else
    (void)th_skip(0, "walls (EDMI_MAX_WALLS = 0)");
#endif
}
