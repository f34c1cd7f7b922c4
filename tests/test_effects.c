/* Effects beyond links: uniform field, link dampers, force ports, scenes as constant data.
 *
 * The discrete energy balance. With R_q, R_p the residuals of the accepted step,
 *   q1 - q0 = dt (p0+p1)/(2m) + R_q,   p1 - p0 = R_p - sum f - sum I + dt F + dt m g,
 * so dt (K1 - K0) = sum (q1-q0 - R_q) . (p1-p0) and, after the algebra of the paper's
 * many-body energy proof,
 *   H1 - H0 = W_ext - D_scheme - D_damping + (sum (q1-q0).R_p - R_q.(p1-p0)) / dt.
 * The last term is computed here from edmi_residual at the accepted state, so the test
 * bound is that term plus the round-off of evaluating H twice and the three reported terms. */
#include <string.h>
#include "harness.h"
#include "suites.h"

static edmi_system eff_sys, eff_old, eff_snap;
static edmi_workspace eff_work;
static edmi_real eff_rq[EDMI_MAX_BODIES][3], eff_rp[EDMI_MAX_BODIES][3];

/* Round-off factor for sums of O(10) terms each a few operations deep (bound on H's error
 * in units of eps times the sum of the magnitudes of the terms). */
#define EFF_RND EDMI_R(32.0)

static edmi_real eff_abs(edmi_real x) { return x < EDMI_R(0.0) ? -x : x; }

static edmi_real eff_norm(const edmi_real v[3])
{
    edmi_real s = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    return EDMI_SQRT(s);
}

/* Sum of the magnitudes entering H and the reported balance: kinetic energies, |V| of every
 * link, |m g.q|, and |V'(d)| d per link (D_scheme sums beta |r|^2 / 2 ~ V'(d) d / 2 terms,
 * much larger than V for a stretched spring). */
static edmi_real eff_h_magnitude(const edmi_system *s)
{
    edmi_real m = EDMI_R(0.0);
    int a, j;
    for (a = 0; a < s->n_bodies; a++) {
        const edmi_body *b = &s->body[a];
        m += (b->p[0] * b->p[0] + b->p[1] * b->p[1] + b->p[2] * b->p[2]) / (EDMI_R(2.0) * b->m);
        if (s->has_field)
            m += b->m * eff_abs(s->g[0] * b->q[0] + s->g[1] * b->q[1] + s->g[2] * b->q[2]);
    }
    for (j = 0; j < s->n_links; j++) {
        const edmi_link *lk = &s->link[j];
        const edmi_real *xb = lk->b == EDMI_ANCHOR ? lk->anchor : s->body[lk->b].q;
        edmi_real r[3];
        edmi_pot_parts pp;
        r[0] = s->body[lk->a].q[0] - xb[0];
        r[1] = s->body[lk->a].q[1] - xb[1];
        r[2] = s->body[lk->a].q[2] - xb[2];
        if (edmi_pot_eval(&lk->pot, eff_norm(r), &pp) == EDMI_OK)
            m += eff_abs(pp.v[0]) + eff_abs(pp.v[1]) * eff_norm(r);
    }
    return m;
}

/* What eff_build_chain needs of the build: the scheme, neo-Hookean links, dampers, the
 * field. */
static int eff_chain_in(edmi_scheme scheme)
{
    return th_has_scheme(scheme) && th_has_pot(EDMI_POT_NEO_HOOKE) && EDMI_MAX_DAMPERS > 0 &&
           EDMI_WITH_FIELD;
}

/* A hanging chain: anchor at the origin, four bodies of different mass on neo-Hookean
 * springs, a damper on every link, gravity, and a port force on the last body. */
static void eff_build_chain(edmi_scheme scheme)
{
    edmi_params prm = edmi_default_params();
    edmi_potential sp = edmi_pot_neo_hooke(EDMI_R(200.0), EDMI_R(1.0));
    edmi_real x[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real g[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-9.81)};
    int a, l;
    prm.scheme = scheme;
    prm.energy_balance = 1;
    CHECK_STATUS(edmi_init(&eff_sys, &prm), EDMI_OK);
    for (a = 0; a < 4; a++) {
        edmi_real q[3], p[3];
        q[0] = EDMI_R(0.3) * (edmi_real)a;
        q[1] = EDMI_R(0.1);
        q[2] = -(edmi_real)(a + 1);
        p[0] = EDMI_R(0.2) * (edmi_real)a;
        p[1] = EDMI_R(-0.1);
        p[2] = EDMI_R(0.0);
        CHECK_STATUS(edmi_add_body(&eff_sys, EDMI_R(1.0) + EDMI_R(0.5) * (edmi_real)a, q, p, NULL),
                     EDMI_OK);
    }
    CHECK_STATUS(edmi_add_anchor(&eff_sys, 0, x, &sp, &l), EDMI_OK);
    CHECK_STATUS(edmi_add_damper(&eff_sys, l, EDMI_R(0.5), NULL), EDMI_OK);
    for (a = 0; a < 3; a++) {
        CHECK_STATUS(edmi_add_pair(&eff_sys, a, a + 1, &sp, &l), EDMI_OK);
        CHECK_STATUS(edmi_add_damper(&eff_sys, l, EDMI_R(0.3), NULL), EDMI_OK);
    }
    CHECK_STATUS(edmi_set_field(&eff_sys, g), EDMI_OK);
}

/* Per step: H1 - H0 = W - Ds - Dd within the solver term plus round-off; Dd >= 0; and for
 * GE/PM/PT Ds >= 0 (the split schemes dissipate) up to the same round-off. */
static void eff_balance(edmi_scheme scheme)
{
    static const edmi_real dt = EDMI_R(0.005);
    edmi_real worst = EDMI_R(0.0), dd_total = EDMI_R(0.0), w_total = EDMI_R(0.0);
    int k, a, bad = 0, neg_damp = 0, neg_scheme = 0;
    TH_NEEDS(eff_chain_in(scheme) && EDMI_WITH_PORTS);
    eff_build_chain(scheme);
    for (k = 0; k < 400; k++) {
        edmi_invariants i0, i1;
        edmi_step_result res;
        edmi_real f[3], solver = EDMI_R(0.0), rnd, err;
        f[0] = EDMI_R(2.0) * (edmi_real)(k % 7) / EDMI_R(7.0) - EDMI_R(1.0);
        f[1] = EDMI_R(0.0);
        f[2] = EDMI_R(1.0);
        CHECK_STATUS(edmi_set_force(&eff_sys, 3, f), EDMI_OK);
        eff_old = eff_sys;
        CHECK_STATUS(edmi_invariants_of(&eff_old, &i0), EDMI_OK);
        if (!CHECK_STATUS(edmi_step(&eff_sys, &eff_work, dt, &res), EDMI_OK))
            return;
        CHECK_STATUS(edmi_invariants_of(&eff_sys, &i1), EDMI_OK);
        {
            edmi_real q1[EDMI_MAX_BODIES][3], p1[EDMI_MAX_BODIES][3];
            for (a = 0; a < eff_sys.n_bodies; a++) {
                memcpy(q1[a], eff_sys.body[a].q, sizeof q1[a]);
                memcpy(p1[a], eff_sys.body[a].p, sizeof p1[a]);
            }
            CHECK_STATUS(edmi_residual(&eff_old, &eff_work, dt, (const edmi_real (*)[3])q1,
                                       (const edmi_real (*)[3])p1, eff_rq, eff_rp, NULL),
                         EDMI_OK);
            for (a = 0; a < eff_sys.n_bodies; a++) {
                edmi_real dq[3], dp[3];
                int c;
                for (c = 0; c < 3; c++) {
                    dq[c] = q1[a][c] - eff_old.body[a].q[c];
                    dp[c] = p1[a][c] - eff_old.body[a].p[c];
                }
                solver += (eff_norm(dq) * eff_norm(eff_rp[a]) + eff_norm(eff_rq[a]) * eff_norm(dp)) / dt;
            }
        }
        rnd = EFF_RND * EDMI_EPS *
              (eff_h_magnitude(&eff_old) + eff_h_magnitude(&eff_sys) + eff_abs(res.work_ext) +
               eff_abs(res.diss_scheme) + eff_abs(res.diss_damping));
        err = eff_abs((i1.h - i0.h) - (res.work_ext - res.diss_scheme - res.diss_damping));
        if (err / (solver + rnd) > worst)
            worst = err / (solver + rnd);
        bad += err > solver + rnd;
        neg_damp += res.diss_damping < EDMI_R(0.0);
        if (scheme == EDMI_SCHEME_GE || scheme == EDMI_SCHEME_PM || scheme == EDMI_SCHEME_PT)
            neg_scheme += res.diss_scheme < -rnd;
        dd_total += res.diss_damping;
        w_total += res.work_ext;
    }
    th_note_real("balance: worst |error| / (solver + round-off bound)", worst);
    CHECK(bad == 0);
    CHECK(neg_damp == 0);
    CHECK(neg_scheme == 0);
    /* the effects were really there */
    CHECK(dd_total > EDMI_R(0.1));
    CHECK(eff_abs(w_total) > EDMI_R(1e-3));
}

/* Dampers conserve L, J and C: a free LJ triangle with a damper on every edge. Sum_A R_p^A =
 * L1 - L0 exactly (every link and damper force cancels in pairs), so |L1 - L0| is bounded by
 * the residual; J and C likewise to the solver tolerance. The energy must fall. */
static void eff_damped_momentum(edmi_scheme scheme)
{
    static const edmi_real qs[3][3] = {{EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)},
                                       {EDMI_R(1.2), EDMI_R(0.1), EDMI_R(0.0)},
                                       {EDMI_R(0.5), EDMI_R(1.1), EDMI_R(0.3)}};
    static const edmi_real ps[3][3] = {{EDMI_R(0.3), EDMI_R(-0.2), EDMI_R(0.1)},
                                       {EDMI_R(-0.5), EDMI_R(0.4), EDMI_R(0.0)},
                                       {EDMI_R(0.1), EDMI_R(0.2), EDMI_R(-0.3)}};
    /* solver tolerance on the scaled residual times the momentum/position scales (~1),
     * over 1000 steps, plus accumulated round-off: 1e4 eps in double dominates 1e-10 r0 */
    const edmi_real tol = EDMI_R(1e4) * EDMI_EPS + (edmi_is_double_precision()
                                                        ? EDMI_R(1e-10) : EDMI_R(0.0));
    edmi_params prm = edmi_default_params();
    edmi_potential lj = edmi_pot_lj(EDMI_R(1.0), EDMI_R(1.0));
    edmi_invariants i0, i1;
    edmi_real dj = EDMI_R(0.0), dl = EDMI_R(0.0), dc = EDMI_R(0.0);
    int a, l, k, c;
    prm.scheme = scheme;
    TH_NEEDS(th_has_params(&prm) && th_has_pot(EDMI_POT_LJ) && EDMI_MAX_DAMPERS > 0);
    CHECK_STATUS(edmi_init(&eff_sys, &prm), EDMI_OK);
    for (a = 0; a < 3; a++)
        CHECK_STATUS(edmi_add_body(&eff_sys, (edmi_real)(a + 1), qs[a], ps[a], NULL), EDMI_OK);
    for (a = 0; a < 3; a++) {
        CHECK_STATUS(edmi_add_pair(&eff_sys, a, (a + 1) % 3, &lj, &l), EDMI_OK);
        CHECK_STATUS(edmi_add_damper(&eff_sys, l, EDMI_R(0.7), NULL), EDMI_OK);
    }
    CHECK_STATUS(edmi_invariants_of(&eff_sys, &i0), EDMI_OK);
    for (k = 0; k < 1000; k++) {
        if (!CHECK_STATUS(edmi_step(&eff_sys, &eff_work, EDMI_R(0.002), NULL), EDMI_OK))
            return;
        CHECK_STATUS(edmi_invariants_of(&eff_sys, &i1), EDMI_OK);
        for (c = 0; c < 3; c++) {
            if (eff_abs(i1.j[c] - i0.j[c]) > dj)
                dj = eff_abs(i1.j[c] - i0.j[c]);
            if (eff_abs(i1.l[c] - i0.l[c]) > dl)
                dl = eff_abs(i1.l[c] - i0.l[c]);
            if (eff_abs(i1.c[c] - i0.c[c]) > dc)
                dc = eff_abs(i1.c[c] - i0.c[c]);
        }
    }
    th_note_real("damped LJ: max |J - J0|", dj);
    CHECK(dj <= tol);
    CHECK(dl <= tol);
    CHECK(dc <= tol);
    CHECK(i1.h < i0.h - EDMI_R(0.1)); /* dampers remove ~0.7 of ~2 here */
}

/* A free body in a uniform field: the force is constant, every scheme integrates it
 * exactly, q(t) = q0 + t p0/m + t^2 g/2 and p(t) = p0 + t m g, to round-off. */
static void eff_free_fall(edmi_scheme scheme)
{
    edmi_params prm = edmi_default_params();
    edmi_real q0[3] = {EDMI_R(1.0), EDMI_R(2.0), EDMI_R(3.0)};
    edmi_real p0[3] = {EDMI_R(0.5), EDMI_R(0.0), EDMI_R(4.0)};
    edmi_real g[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-9.81)};
    edmi_real m = EDMI_R(2.0), t;
    int k, c;
    prm.scheme = scheme;
    TH_NEEDS(th_has_params(&prm) && EDMI_WITH_FIELD);
    CHECK_STATUS(edmi_init(&eff_sys, &prm), EDMI_OK);
    CHECK_STATUS(edmi_add_body(&eff_sys, m, q0, p0, NULL), EDMI_OK);
    CHECK_STATUS(edmi_set_field(&eff_sys, g), EDMI_OK);
    for (k = 0; k < 100; k++)
        if (!CHECK_STATUS(edmi_step(&eff_sys, &eff_work, EDMI_R(0.01), NULL), EDMI_OK))
            return;
    t = eff_sys.t;
    for (c = 0; c < 3; c++) {
        /* 100 steps of round-off on magnitudes ~5: 1e3 eps absolute */
        CHECK_NEAR(eff_sys.body[0].q[c], q0[c] + t * p0[c] / m + EDMI_R(0.5) * t * t * g[c],
                   EDMI_R(1e3) * EDMI_EPS * EDMI_R(10.0), EDMI_R(0.0));
        CHECK_NEAR(eff_sys.body[0].p[c], p0[c] + t * m * g[c], EDMI_R(1e3) * EDMI_EPS * EDMI_R(20.0),
                   EDMI_R(0.0));
    }
}

/* Bad effect inputs return their status and leave the system bit-identical. */
static void eff_invalid(void)
{
    edmi_real nan3[3], ok3[3] = {EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real zero = EDMI_R(0.0);
    TH_NEEDS(eff_chain_in(EDMI_SCHEME_PM) && EDMI_WITH_PORTS);
    eff_build_chain(EDMI_SCHEME_PM);
    nan3[0] = zero / zero;
    nan3[1] = nan3[2] = EDMI_R(0.0);
    eff_snap = eff_sys;
    CHECK_STATUS(edmi_add_damper(&eff_sys, eff_sys.n_links, EDMI_R(1.0), NULL), EDMI_ERR_INDEX);
    CHECK_STATUS(edmi_add_damper(&eff_sys, -1, EDMI_R(1.0), NULL), EDMI_ERR_INDEX);
    CHECK_STATUS(edmi_add_damper(&eff_sys, 0, EDMI_R(-1.0), NULL), EDMI_ERR_PARAM);
    CHECK_STATUS(edmi_add_damper(&eff_sys, 0, nan3[0], NULL), EDMI_ERR_PARAM);
    CHECK_STATUS(edmi_add_damper(NULL, 0, EDMI_R(1.0), NULL), EDMI_ERR_NULL);
    CHECK_STATUS(edmi_set_force(&eff_sys, 4, ok3), EDMI_ERR_INDEX);
    CHECK_STATUS(edmi_set_force(&eff_sys, 0, nan3), EDMI_ERR_NONFINITE);
    CHECK_STATUS(edmi_set_force(&eff_sys, 0, NULL), EDMI_ERR_NULL);
    CHECK_STATUS(edmi_set_field(&eff_sys, nan3), EDMI_ERR_NONFINITE);
    CHECK_STATUS(edmi_set_field(NULL, ok3), EDMI_ERR_NULL);
    CHECK(memcmp(&eff_snap, &eff_sys, sizeof eff_sys) == 0);
    /* damper capacity */
    {
        int i;
        for (i = eff_sys.n_dampers; i < EDMI_MAX_DAMPERS; i++)
            CHECK_STATUS(edmi_add_damper(&eff_sys, 0, EDMI_R(0.1), NULL), EDMI_OK);
        eff_snap = eff_sys;
        CHECK_STATUS(edmi_add_damper(&eff_sys, 0, EDMI_R(0.1), NULL),
                     EDMI_MAX_DAMPERS > 0 ? EDMI_ERR_CAPACITY : EDMI_ERR_DISABLED);
        CHECK(memcmp(&eff_snap, &eff_sys, sizeof eff_sys) == 0);
    }
    /* a corrupted port force is caught by the step, which changes nothing */
    eff_build_chain(EDMI_SCHEME_PM);
    CHECK_STATUS(edmi_set_force(&eff_sys, 2, ok3), EDMI_OK);
    eff_sys.force[2][1] = nan3[0];
    eff_snap = eff_sys;
    CHECK_STATUS(edmi_step(&eff_sys, &eff_work, EDMI_R(0.01), NULL), EDMI_ERR_NONFINITE);
    CHECK(memcmp(&eff_snap, &eff_sys, sizeof eff_sys) == 0);
}

/* A scene as constant data: loads, steps like the same system built by calls, and a bad
 * scene changes nothing. */
static void eff_scene(void)
{
    static const edmi_body bodies[2] = {
        {EDMI_R(1.0), {EDMI_R(0.0), EDMI_R(-0.5612), EDMI_R(0.0)}, {EDMI_R(5.0), EDMI_R(0.0), EDMI_R(0.0)}},
        {EDMI_R(1.0), {EDMI_R(0.0), EDMI_R(0.5612), EDMI_R(0.0)}, {EDMI_R(10.0), EDMI_R(0.0), EDMI_R(0.0)}}};
    static edmi_link links[1];
    static const edmi_damper dampers[1] = {{0, EDMI_R(0.25)}};
    edmi_scene sc;
    edmi_params prm = edmi_default_params();
    edmi_potential lj = edmi_pot_lj(EDMI_R(100.0), EDMI_R(1.0));
    int k;
    prm.scheme = EDMI_SCHEME_PT;
    TH_NEEDS(th_has_params(&prm) && th_has_pot(EDMI_POT_LJ) && EDMI_MAX_DAMPERS > 0 &&
             EDMI_WITH_SCENE);
    links[0].a = 0;
    links[0].b = 1;
    links[0].anchor[0] = links[0].anchor[1] = links[0].anchor[2] = EDMI_R(0.0);
    links[0].pot = lj;
    memset(&sc, 0, sizeof sc);
    sc.n_bodies = 2;
    sc.bodies = bodies;
    sc.n_links = 1;
    sc.links = links;
    sc.n_dampers = 1;
    sc.dampers = dampers;
    sc.params = &prm;
    CHECK_STATUS(edmi_load_scene(&eff_sys, &sc), EDMI_OK);
    CHECK_STATUS(edmi_init(&eff_old, &prm), EDMI_OK);
    CHECK_STATUS(edmi_add_body(&eff_old, bodies[0].m, bodies[0].q, bodies[0].p, NULL), EDMI_OK);
    CHECK_STATUS(edmi_add_body(&eff_old, bodies[1].m, bodies[1].q, bodies[1].p, NULL), EDMI_OK);
    CHECK_STATUS(edmi_add_pair(&eff_old, 0, 1, &lj, NULL), EDMI_OK);
    CHECK_STATUS(edmi_add_damper(&eff_old, 0, EDMI_R(0.25), NULL), EDMI_OK);
    CHECK(memcmp(&eff_sys, &eff_old, sizeof eff_sys) == 0);
    for (k = 0; k < 50; k++) {
        CHECK_STATUS(edmi_step(&eff_sys, &eff_work, EDMI_R(1e-3), NULL), EDMI_OK);
        CHECK_STATUS(edmi_step(&eff_old, &eff_work, EDMI_R(1e-3), NULL), EDMI_OK);
    }
    CHECK(memcmp(&eff_sys, &eff_old, sizeof eff_sys) == 0);
    /* invalid scenes: nothing changes */
    eff_snap = eff_sys;
    links[0].b = 2;
    CHECK_STATUS(edmi_load_scene(&eff_sys, &sc), EDMI_ERR_INDEX);
    links[0].b = 1;
    sc.n_bodies = EDMI_MAX_BODIES + 1;
    CHECK_STATUS(edmi_load_scene(&eff_sys, &sc), EDMI_ERR_CAPACITY);
    sc.n_bodies = 2;
    sc.dampers = NULL;
    CHECK_STATUS(edmi_load_scene(&eff_sys, &sc), EDMI_ERR_NULL);
    CHECK(memcmp(&eff_snap, &eff_sys, sizeof eff_sys) == 0);
}

void suite_effects(void)
{
    th_suite("effects: field, dampers, ports, energy balance, scenes");
    eff_balance(EDMI_SCHEME_MP);
    eff_balance(EDMI_SCHEME_LG);
    eff_balance(EDMI_SCHEME_GE);
    eff_balance(EDMI_SCHEME_PM);
    eff_balance(EDMI_SCHEME_PT);
    eff_damped_momentum(EDMI_SCHEME_MP);
    eff_damped_momentum(EDMI_SCHEME_LG);
    eff_damped_momentum(EDMI_SCHEME_PT);
    eff_free_fall(EDMI_SCHEME_MP);
    eff_free_fall(EDMI_SCHEME_GE);
    eff_free_fall(EDMI_SCHEME_PT);
    eff_invalid();
    eff_scene();
}
