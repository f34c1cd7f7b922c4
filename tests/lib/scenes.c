/* Shared scenes and per-step law bookkeeping (see scenes.h).
 *
 * The identities the bounds come from. For one step with dq_A = q1_A - q0_A,
 * dp_A = p1_A - p0_A, p_m = (p0 + p1)/2, q_m = (q0 + q1)/2 and the scheme's residuals
 *   R_q^A = dq_A - dt/m_A p_m,A,   R_p^A = dp_A + F_A,   F_A = sum over links of +-f,
 *   f = dt beta r_m (r_m = link vector at the mid-point state, beta symmetric in A, B):
 *
 * Energy. dt (K1 - K0) = sum_A (dq_A - R_q^A) . dp_A and
 *   sum_A dq_A . F_A = sum_links dr . f = dt beta (d1^2 - d0^2)/2 = dt Lambda (d1 - d0)
 * (beta = 2 Lambda/(d0 + d1)), so
 *   H1 - H0 = e_res - D,  e_res = sum_A (dq_A . R_p^A - R_q^A . dp_A)/dt,
 *   D = sum_links [Lambda (d1 - d0) - (V(d1) - V(d0))].
 * |e_res| <= e_solver = sum_A (|dq_A| |R_p^A| + |R_q^A| |dp_A|)/dt: the solver bound.
 * D per link, from the quadrature lemmas applied to V_c', V_e' (GE), V_+', V_- ' (PM, PT),
 * valid for either sign of d1 - d0 and with each link counted once:
 *   LG: D = 0 (the divided difference is exact);
 *   GE: D = (d1-d0)^2/2  (V_c''(xi1) - V_e''(xi2))      >= 0;
 *   PM: D = (d1-d0)^4/48 (V_+''''(xi3) - V_-''''(xi4))  >= 0;
 *   PT: D = (d1-d0)^4/24 (V_+''''(xi5) - V_-''''(xi6))  >= 0,
 * with xi between d0 and d1. (The paper's single-particle statements print 1/2 for PM and PT
 * and its many-body ones 1/96 and 1/48 over ordered pairs; the proofs give 1/48 and 1/24 per
 * link.) Every built-in potential used by these suites has V_c'', V_e'', V_+'''', V_-''''
 * monotone in r (constants and powers of r), so the values at xi lie between the values at
 * d0 and d1: that brackets D in [d_lo, d_hi].
 *
 * Angular momentum. J1 - J0 = sum_A (q_m,A x dp_A + dq_A x p_m,A)
 *   = sum_A (q_m,A x R_p^A + R_q^A x p_m,A) - sum_links r_m x f - sum_anchors x_anchor x f,
 * and r_m x f = 0: |J1 - J0| <= sum_A (|q_m,A| |R_p^A| + |R_q^A| |p_m,A|) for anchors at the
 * origin.
 * Linear momentum (no anchors). L1 - L0 = sum_A R_p^A - sum_A F_A and sum_A F_A = 0.
 * Centre of mass (no anchors). M C = sum m q - t L gives
 *   M (C1 - C0) = sum_A m_A R_q^A - (t0 + dt/2)(L1 - L0).
 *
 * Round-off. The identities hold in exact arithmetic for the floating-point states. Computing
 * H (a sum of K and V terms), the link distances (|V'| times the error of d, which is a few
 * eps times |q_A| + |q_B|), the residuals (eps times |p0| + |p1| + |dp| for R_p, eps times
 * |q0| + |q1| for R_q, entering e_res multiplied by |dq|/dt and |dp|/dt) each carries a few
 * rounding errors of relative size eps. TS_C_ROUND = 16 allows for up to 16 roundings along
 * the longest path (a 3-term dot product, a square root, a division and the sums in H and in
 * the residual) on each of these magnitudes. Measured: the pure round-off checks (LG's
 * |dH - e_res|, the dissipation brackets) use at most 0.04 of this allowance in either
 * precision, i.e. the actual errors stay below one eps on these magnitudes. */
#include "scenes.h"
#include "harness.h"

#define TS_C_ROUND EDMI_R(16.0)

edmi_system ts_sys[3];
edmi_workspace ts_work;

/* ---- small maths ------------------------------------------------------------------------ */

edmi_real ts_abs(edmi_real x) { return x < EDMI_R(0.0) ? -x : x; }
edmi_real ts_max(edmi_real a, edmi_real b) { return a > b ? a : b; }
edmi_real ts_min(edmi_real a, edmi_real b) { return a < b ? a : b; }

edmi_real ts_norm3(const edmi_real v[3])
{
    return EDMI_SQRT(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

int ts_finite(edmi_real x) { return (x - x) == EDMI_R(0.0); }

#define TS_LN2 EDMI_R(0.693147180559945309417)

edmi_real ts_ln(edmi_real x)
{
    edmi_real y, y2, term, sum;
    int e = 0, k;
    if (!(x > EDMI_R(0.0)) || !ts_finite(x))
        return -EDMI_REAL_MAX;
    while (x >= EDMI_R(2.0)) {
        x *= EDMI_R(0.5);
        e++;
    }
    while (x < EDMI_R(1.0)) {
        x *= EDMI_R(2.0);
        e--;
    }
    /* ln x = 2 atanh(y), y = (x-1)/(x+1) in [0, 1/3): terms shrink by y^2 <= 1/9. */
    y = (x - EDMI_R(1.0)) / (x + EDMI_R(1.0));
    y2 = y * y;
    term = y;
    sum = EDMI_R(0.0);
    for (k = 1; k < 80; k += 2) {
        edmi_real add = term / (edmi_real)k;
        sum += add;
        if (add <= EDMI_EPS * sum)
            break;
        term *= y2;
    }
    return (edmi_real)e * TS_LN2 + EDMI_R(2.0) * sum;
}

edmi_real ts_log2(edmi_real x) { return ts_ln(x) / TS_LN2; }

edmi_real ts_order(edmi_real e_coarse, edmi_real e_fine, edmi_real ratio)
{
    return ts_ln(e_coarse / e_fine) / ts_ln(ratio);
}

const char *ts_scheme_name(edmi_scheme s)
{
    static const char *const names[5] = {"MP", "LG", "GE", "PM", "PT"};
    return (unsigned)s < 5u ? names[s] : "?";
}

const char *ts_alt_name(edmi_lg_alt a)
{
    static const char *const names[5] = {"JANZ", "GONZALEZ", "GE", "PM", "PT"};
    return (unsigned)a < 5u ? names[a] : "?";
}

const char *ts_label(const char *a, const char *b)
{
    static char buf[80];
    int n = 0;
    while (*a && n < 79)
        buf[n++] = *a++;
    if (n < 79)
        buf[n++] = ' ';
    while (*b && n < 79)
        buf[n++] = *b++;
    buf[n] = '\0';
    return buf;
}

/* ---- scenes ----------------------------------------------------------------------------- */

edmi_params ts_params(edmi_scheme scheme)
{
    edmi_params p = edmi_default_params();
    p.scheme = scheme;
    return p;
}

edmi_status ts_spring(edmi_system *sys, const edmi_params *prm)
{
    const edmi_real q[3] = {EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0)};
    const edmi_real p[3] = {EDMI_R(-30.0), EDMI_R(15.0), EDMI_R(45.0)};
    const edmi_real x[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot = edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0));
    edmi_status st = edmi_init(sys, prm);
    if (st == EDMI_OK)
        st = edmi_add_body(sys, EDMI_R(10.0), q, p, 0);
    if (st == EDMI_OK)
        st = edmi_add_anchor(sys, 0, x, &pot, 0);
    return st;
}

edmi_status ts_lj2(edmi_system *sys, const edmi_params *prm)
{
    const edmi_real q1[3] = {EDMI_R(0.0), EDMI_R(-0.5612), EDMI_R(0.0)};
    const edmi_real q2[3] = {EDMI_R(0.0), EDMI_R(0.5612), EDMI_R(0.0)};
    const edmi_real p1[3] = {EDMI_R(5.0), EDMI_R(0.0), EDMI_R(0.0)};
    const edmi_real p2[3] = {EDMI_R(10.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot = edmi_pot_lj(EDMI_R(1e2), EDMI_R(1.0));
    edmi_status st = edmi_init(sys, prm);
    if (st == EDMI_OK)
        st = edmi_add_body(sys, EDMI_R(1.0), q1, p1, 0);
    if (st == EDMI_OK)
        st = edmi_add_body(sys, EDMI_R(1.0), q2, p2, 0);
    if (st == EDMI_OK)
        st = edmi_add_pair(sys, 0, 1, &pot, 0);
    return st;
}

edmi_status ts_gravity(edmi_system *sys, const edmi_params *prm)
{
    /* Masses, positions, momenta: roughly circular speeds sqrt(1/r) about the heavy body,
     * orbits in three different planes, and a drift of the heavy body so that L != 0. */
    static const edmi_real m[4] = {EDMI_R(1.0), EDMI_R(1e-3), EDMI_R(2e-3), EDMI_R(5e-4)};
    static const edmi_real q[4][3] = {{EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)},
                                      {EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.0)},
                                      {EDMI_R(0.0), EDMI_R(1.6), EDMI_R(0.0)},
                                      {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.5)}};
    static const edmi_real p[4][3] = {{EDMI_R(0.01), EDMI_R(-0.002), EDMI_R(0.001)},
                                      {EDMI_R(0.0), EDMI_R(1e-3), EDMI_R(0.0)},
                                      {EDMI_R(-1.58e-3), EDMI_R(0.0), EDMI_R(0.0)},
                                      {EDMI_R(7.07e-4), EDMI_R(0.0), EDMI_R(0.0)}};
    edmi_status st = edmi_init(sys, prm);
    int a, b;
    for (a = 0; a < 4 && st == EDMI_OK; a++)
        st = edmi_add_body(sys, m[a], q[a], p[a], 0);
    for (a = 0; a < 4 && st == EDMI_OK; a++)
        for (b = a + 1; b < 4 && st == EDMI_OK; b++) {
            edmi_potential pot = edmi_pot_inverse(m[a] * m[b]);
            st = edmi_add_pair(sys, a, b, &pot, 0);
        }
    return st;
}

edmi_status ts_orbit(edmi_system *sys, const edmi_params *prm, edmi_real m, edmi_real k,
                     edmi_real r0)
{
    edmi_real q[3], p[3];
    const edmi_real x[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot = edmi_pot_inverse(k);
    edmi_status st = edmi_init(sys, prm);
    q[0] = r0;
    q[1] = q[2] = EDMI_R(0.0);
    p[0] = p[2] = EDMI_R(0.0);
    p[1] = EDMI_SQRT(m * k / r0);
    if (st == EDMI_OK)
        st = edmi_add_body(sys, m, q, p, 0);
    if (st == EDMI_OK)
        st = edmi_add_anchor(sys, 0, x, &pot, 0);
    return st;
}

int ts_scene_in(ts_build build, const edmi_params *prm)
{
    edmi_pot_kind kind;
    if (build == ts_spring)
        kind = EDMI_POT_NEO_HOOKE;
    else if (build == ts_lj2)
        kind = EDMI_POT_LJ;
    else if (build == ts_gravity)
        kind = EDMI_POT_INVERSE;
    else
        return 0; /* not a scene of this file */
    return th_has_params(prm) && th_has_pot(kind);
}

int ts_orbit_in(const edmi_params *prm)
{
    return th_has_params(prm) && th_has_pot(EDMI_POT_INVERSE);
}

/* ---- one step with its laws ------------------------------------------------------------- */

static edmi_system ts__prev;
static edmi_real ts__q1[EDMI_MAX_BODIES][3], ts__p1[EDMI_MAX_BODIES][3];
static edmi_real ts__rq[EDMI_MAX_BODIES][3], ts__rp[EDMI_MAX_BODIES][3];

static void ts__link_vec(const edmi_system *sys, const edmi_link *lk, edmi_real r[3])
{
    const edmi_real *b = lk->b == EDMI_ANCHOR ? lk->anchor : sys->body[lk->b].q;
    int i;
    for (i = 0; i < 3; i++)
        r[i] = sys->body[lk->a].q[i] - b[i];
}

static edmi_real ts__end_norms(const edmi_system *sys, const edmi_link *lk)
{
    return ts_norm3(sys->body[lk->a].q) +
           ts_norm3(lk->b == EDMI_ANCHOR ? lk->anchor : sys->body[lk->b].q);
}

/* Per-link energy magnitudes for the round-off allowance and the dissipation bracket. */
static edmi_status ts__links(const edmi_system *s0, const edmi_system *s1, ts_law *law,
                             edmi_real *mag)
{
    const edmi_params *prm = &s0->params;
    int j;
    law->has_law = prm->scheme != EDMI_SCHEME_MP &&
                   !(prm->scheme == EDMI_SCHEME_LG && prm->lg_form != EDMI_LG_CLOSED);
    law->d_lo = law->d_hi = EDMI_R(0.0);
    law->dmin = EDMI_REAL_MAX;
    for (j = 0; j < s0->n_links; j++) {
        const edmi_link *lk = &s0->link[j];
        edmi_real r0[3], r1[3], d0, d1, dd, w, lo = EDMI_R(0.0), hi = EDMI_R(0.0);
        edmi_pot_parts a, b;
        edmi_status st;
        ts__link_vec(s0, lk, r0);
        ts__link_vec(s1, lk, r1);
        d0 = ts_norm3(r0);
        d1 = ts_norm3(r1);
        law->dmin = ts_min(law->dmin, d1);
        st = edmi_pot_eval(&lk->pot, d0, &a);
        if (st == EDMI_OK)
            st = edmi_pot_eval(&lk->pot, d1, &b);
        if (st != EDMI_OK)
            return st;
        *mag += ts_abs(a.v[0]) + ts_abs(b.v[0]) + ts_abs(a.v[1]) * ts__end_norms(s0, lk) +
                ts_abs(b.v[1]) * ts__end_norms(s1, lk);
        dd = d1 - d0;
        switch (prm->scheme) {
        case EDMI_SCHEME_GE:
            w = EDMI_R(0.5) * dd * dd;
            lo = w * (ts_min(a.c[2], b.c[2]) - ts_max(a.e[2], b.e[2]));
            hi = w * (ts_max(a.c[2], b.c[2]) - ts_min(a.e[2], b.e[2]));
            break;
        case EDMI_SCHEME_PM:
        case EDMI_SCHEME_PT:
            w = dd * dd * dd * dd / (prm->scheme == EDMI_SCHEME_PM ? EDMI_R(48.0) : EDMI_R(24.0));
            lo = w * (ts_min(a.sp[4], b.sp[4]) - ts_max(a.sm[4], b.sm[4]));
            hi = w * (ts_max(a.sp[4], b.sp[4]) - ts_min(a.sm[4], b.sm[4]));
            break;
        default:
            break;
        }
        law->d_lo += lo;
        law->d_hi += hi;
    }
    return EDMI_OK;
}

static edmi_real ts__dist3(const edmi_real a[3], const edmi_real b[3])
{
    edmi_real d[3];
    d[0] = a[0] - b[0];
    d[1] = a[1] - b[1];
    d[2] = a[2] - b[2];
    return ts_norm3(d);
}

edmi_status ts_step_law(edmi_system *sys, edmi_workspace *work, edmi_real dt, ts_law *law)
{
    edmi_invariants i0, i1;
    edmi_real eps = EDMI_EPS, mag_h, mag_j = EDMI_R(0.0), mag_l = EDMI_R(0.0);
    edmi_real mag_c = EDMI_R(0.0), sum_mrq = EDMI_R(0.0), sum_rp = EDMI_R(0.0);
    edmi_real mass = EDMI_R(0.0), tm;
    edmi_status st;
    int a, i;
    st = edmi_invariants_of(sys, &i0);
    if (st != EDMI_OK)
        return st;
    ts__prev = *sys;
    st = edmi_step(sys, work, dt, &law->res);
    if (st != EDMI_OK)
        return st;
    st = edmi_invariants_of(sys, &i1);
    if (st != EDMI_OK)
        return st;
    for (a = 0; a < sys->n_bodies; a++)
        for (i = 0; i < 3; i++) {
            ts__q1[a][i] = sys->body[a].q[i];
            ts__p1[a][i] = sys->body[a].p[i];
        }
    st = edmi_residual(&ts__prev, work, dt, (const edmi_real (*)[3])ts__q1,
                       (const edmi_real (*)[3])ts__p1, ts__rq, ts__rp, 0);
    if (st != EDMI_OK)
        return st;

    law->dh = i1.h - i0.h;
    law->e_res = law->e_solver = EDMI_R(0.0);
    law->dj_bound = EDMI_R(0.0);
    mag_h = ts_abs(i0.k) + ts_abs(i1.k);
    tm = ts__prev.t + EDMI_R(0.5) * dt;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *b0 = &ts__prev.body[a], *b1 = &sys->body[a];
        edmi_real dq[3], dp[3], qm[3], pm[3], ndq, ndp, nrq, nrp, nq0, nq1, np0, np1;
        for (i = 0; i < 3; i++) {
            dq[i] = b1->q[i] - b0->q[i];
            dp[i] = b1->p[i] - b0->p[i];
            qm[i] = EDMI_R(0.5) * (b0->q[i] + b1->q[i]);
            pm[i] = EDMI_R(0.5) * (b0->p[i] + b1->p[i]);
            law->e_res += (dq[i] * ts__rp[a][i] - ts__rq[a][i] * dp[i]) / dt;
        }
        ndq = ts_norm3(dq);
        ndp = ts_norm3(dp);
        nrq = ts_norm3(ts__rq[a]);
        nrp = ts_norm3(ts__rp[a]);
        nq0 = ts_norm3(b0->q);
        nq1 = ts_norm3(b1->q);
        np0 = ts_norm3(b0->p);
        np1 = ts_norm3(b1->p);
        law->e_solver += (ndq * nrp + nrq * ndp) / dt;
        mag_h += ((nq0 + nq1) * ndp + (np0 + np1 + ndp) * ndq) / dt;
        law->dj_bound += ts_norm3(qm) * nrp + nrq * ts_norm3(pm);
        mag_j += (nq0 + nq1) * (np0 + np1 + ndp);
        sum_rp += nrp;
        sum_mrq += b0->m * nrq;
        mag_l += np0 + np1 + ndp;
        mag_c += b0->m * (nq0 + nq1);
        mass += b0->m;
    }
    st = ts__links(&ts__prev, sys, law, &mag_h);
    if (st != EDMI_OK)
        return st;
    law->e_round = TS_C_ROUND * eps * mag_h;
    law->dj = ts__dist3(i1.j, i0.j);
    law->dj_bound += TS_C_ROUND * eps * mag_j;
    law->dl = ts__dist3(i1.l, i0.l);
    law->dl_bound = sum_rp + TS_C_ROUND * eps * mag_l;
    law->dc = ts__dist3(i1.c, i0.c);
    law->dc_bound = (sum_mrq + tm * sum_rp +
                     TS_C_ROUND * eps * (mag_c + (sys->t + dt) * mag_l)) / mass;
    return EDMI_OK;
}

int ts_unchanged_by_last_step(const edmi_system *sys)
{
    int a, i;
    if (sys->n_bodies != ts__prev.n_bodies || !(sys->t == ts__prev.t))
        return 0;
    for (a = 0; a < sys->n_bodies; a++)
        for (i = 0; i < 3; i++)
            if (!(sys->body[a].q[i] == ts__prev.body[a].q[i]) ||
                !(sys->body[a].p[i] == ts__prev.body[a].p[i]))
                return 0;
    return 1;
}

/* ---- runs ------------------------------------------------------------------------------- */

void ts_run_init(ts_run *run, const edmi_system *sys)
{
    edmi_invariants iv;
    int i;
    run->steps = 0;
    run->status = edmi_invariants_of(sys, &iv);
    run->iterations = 0;
    run->nonfinite = 0;
    run->h0 = run->h_last = run->h_min = run->h_max = iv.h;
    run->max_abs_dh = EDMI_R(0.0);
    for (i = 0; i < 3; i++) {
        run->j0[i] = iv.j[i];
        run->l0[i] = iv.l[i];
        run->c0[i] = iv.c[i];
    }
    run->sum_bound = run->sum_round = run->sum_dlo = run->sum_dj_bound = EDMI_R(0.0);
    run->worst_cons = run->worst_up = run->worst_law = EDMI_R(0.0);
    run->law_steps = 0;
    run->n_up = run->n_down = 0;
    run->switched_steps = 0;
    run->worst_j = run->worst_l = run->worst_c = EDMI_R(0.0);
    run->max_dj = run->max_dl = run->max_dc = EDMI_R(0.0);
    run->dmin = EDMI_REAL_MAX;
}

static int ts__state_finite(const edmi_system *sys)
{
    int a, i;
    for (a = 0; a < sys->n_bodies; a++)
        for (i = 0; i < 3; i++)
            if (!ts_finite(sys->body[a].q[i]) || !ts_finite(sys->body[a].p[i]))
                return 0;
    return 1;
}

edmi_status ts_run_steps(ts_run *run, edmi_system *sys, edmi_workspace *work, edmi_real dt,
                         long n)
{
    long s;
    if (run->status != EDMI_OK)
        return run->status;
    for (s = 0; s < n; s++) {
        ts_law law;
        edmi_invariants iv;
        edmi_real bound, excess;
        edmi_status st = ts_step_law(sys, work, dt, &law);
        if (st != EDMI_OK) {
            run->status = st;
            return st;
        }
        run->steps++;
        run->iterations += law.res.iterations;
        if (law.res.lg_switches > 0)
            run->switched_steps++;
        if (!ts__state_finite(sys)) {
            run->nonfinite = 1;
            run->status = EDMI_ERR_DIVERGED;
            return run->status;
        }
        bound = law.e_solver + law.e_round;
        run->max_abs_dh = ts_max(run->max_abs_dh, ts_abs(law.dh));
        run->sum_bound += bound;
        run->sum_round += law.e_round;
        run->sum_dj_bound += law.dj_bound;
        run->worst_cons = ts_max(run->worst_cons, ts_abs(law.dh) / bound);
        run->worst_up = ts_max(run->worst_up, law.dh / bound);
        if (law.dh > bound)
            run->n_up++;
        if (law.dh < -bound)
            run->n_down++;
        if (law.has_law) {
            /* D = e_res - dh must lie in [d_lo, d_hi] up to the round-off allowance. */
            edmi_real d = law.e_res - law.dh;
            run->law_steps++;
            run->sum_dlo += law.d_lo;
            excess = ts_max(law.d_lo - d, d - law.d_hi);
            run->worst_law = ts_max(run->worst_law, excess / law.e_round);
        }
        run->worst_j = ts_max(run->worst_j, law.dj / law.dj_bound);
        run->worst_l = ts_max(run->worst_l, law.dl / law.dl_bound);
        run->worst_c = ts_max(run->worst_c, law.dc / law.dc_bound);
        run->dmin = ts_min(run->dmin, law.dmin);
        st = edmi_invariants_of(sys, &iv);
        if (st != EDMI_OK) {
            run->status = st;
            return st;
        }
        run->h_last = iv.h;
        run->h_min = ts_min(run->h_min, iv.h);
        run->h_max = ts_max(run->h_max, iv.h);
        run->max_dj = ts_max(run->max_dj, ts__dist3(iv.j, run->j0));
        run->max_dl = ts_max(run->max_dl, ts__dist3(iv.l, run->l0));
        run->max_dc = ts_max(run->max_dc, ts__dist3(iv.c, run->c0));
    }
    return EDMI_OK;
}

edmi_status ts_advance(edmi_system *sys, edmi_workspace *work, edmi_real dt, long n,
                       long *iterations)
{
    long s;
    for (s = 0; s < n; s++) {
        edmi_step_result r;
        edmi_status st = edmi_step(sys, work, dt, &r);
        if (st != EDMI_OK)
            return st;
        if (iterations)
            *iterations += r.iterations;
    }
    return EDMI_OK;
}

edmi_real ts_state_diff(const edmi_system *a, const edmi_system *b, int which)
{
    edmi_real s = EDMI_R(0.0);
    int k, i;
    for (k = 0; k < a->n_bodies; k++)
        for (i = 0; i < 3; i++) {
            edmi_real d = which ? a->body[k].p[i] - b->body[k].p[i]
                                : a->body[k].q[i] - b->body[k].q[i];
            s += d * d;
        }
    return EDMI_SQRT(s);
}

edmi_real ts_state_norm(const edmi_system *a, int which)
{
    edmi_real s = EDMI_R(0.0);
    int k, i;
    for (k = 0; k < a->n_bodies; k++)
        for (i = 0; i < 3; i++) {
            edmi_real v = which ? a->body[k].p[i] : a->body[k].q[i];
            s += v * v;
        }
    return EDMI_SQRT(s);
}
