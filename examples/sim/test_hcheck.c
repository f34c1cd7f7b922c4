/*
 * test_hcheck: edmi-sim's H check in double-word arithmetic against its __float128
 * evaluation. tests/lib/passive.c decides each step's "H rose" and "H rose beyond the work and
 * the tank" in binary64 double-word arithmetic (tp_h_dw, tp_delta_dw) where its error bound
 * settles them, and in __float128 (tp_delta_h) where it does not; every decision the first
 * settles must be the second's.
 *
 *   test_hcheck SCENE_DIR   closes "N passed, N failed"
 *
 * On steps of the shipped scenes and of one with what they lack (quartic, harmonic with and
 * without a rest length, inverse, a moving anchor; each scene's link 0 also as a user
 * potential), with the scene's scheme and with MP (no guard: H rises), and on each step
 *  - as taken;
 *  - with the works and the tanks set so that dH - W lands at c T from 0, T the fast path's
 *    threshold, c = 0, +-1/2, +-1, +-2, +-4, +-64 (as far as edmi_real holds it: four
 *    edmi_reals of W, about 2^-96 of dH in float);
 *  - with every q and p of the end state moved by a random millionth of itself (a state no
 *    scheme took), as taken and at the same c T;
 *  - with the end state the start rotated a quarter turn about z (anchors included; the
 *    field is along z): H is exactly the start's, so the double-word dH must lie within T of
 *    0, and no rise can be settled.
 * Each settled decision must be tp_delta_h's, with |diff_f - diff_q| within T (and the
 * rounding of both to long double); the steps as taken must nearly all be settled (else the
 * check is no faster). Hosted C99; both precisions (`make test`).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "edmi.h"
#include "scene.h"
/* The energy check uses the shared exact-H helper, tests/lib/passive.h (-Itests/lib). */
#include "passive.h"

/* Steps per scene and scheme (the ten bodies: fewer, each __float128 evaluation costs ~0.1 ms). */
#define HC_STEPS 120
#define HC_STEPS_BIG 30
/* The share of steps as taken that the fast path must settle: all of them, measured, on
 * every shipped scene but the coupled-mass cable (which always goes to __float128). */
#define HC_SETTLED 0.9
#define HC_NC 13

static const long double hc_c[HC_NC] = {0.0L, 0.5L, -0.5L, 1.0L, -1.0L, 2.0L, -2.0L,
                                        4.0L, -4.0L, 64.0L, -64.0L, 1e6L, -1e6L};

static long npass, nfail;
static sim_scene scn;
static edmi_system sys, s0, s1, a0, a1;
static edmi_workspace work;
static edmi_potential user_ctx; /* link 0's potential, behind tp_user_builtin_fn */
static unsigned long seed = 2024UL;

/* Counts of one scene and scheme. */
typedef struct hc_count {
    long taken, taken_fast, near, near_fast, moved, moved_fast, rotated, compared;
} hc_count;

static int check(int cond, const char *text, const char *where)
{
    if (cond) {
        npass++;
    } else {
        nfail++;
        printf("FAIL %s: %s\n", where, text);
    }
    return cond;
}
#define CHECK(cond, where) check((cond) ? 1 : 0, #cond, where)

static double hc_rand(void) /* uniform in [-1, 1) */
{
    seed = (seed * 1664525UL + 1013904223UL) & 0xffffffffUL;
    return (double)((long)(seed >> 8) - 0x800000L) / (double)0x800000L;
}

/* tp_delta_dw and tp_delta_h on (x0, x1, r): the fast decisions, where settled, must be the
 * __float128 ones, and tp_delta_h_fast's are; returns whether the fast path settled them,
 * *df its evaluation (df->quad = -1 where it has none). */
static int compare(const edmi_system *x0, const edmi_system *x1, const edmi_step_result *r,
                   tp_delta *df, const char *where)
{
    tp_hdw h0, h1;
    tp_delta dq, dx;
    int f, q, x;
    tp_h_dw(x0, &h0);
    tp_h_dw(x1, &h1);
    df->quad = -1;
    f = tp_delta_dw(x0, &h0, x1, &h1, r, df);
    q = tp_delta_h(x0, x1, r, &dq);
    x = tp_delta_h_fast(x0, &h0, x1, &h1, r, &dx);
    CHECK(x == q && (!q || (dx.broken == dq.broken && dx.unresolved == dq.unresolved &&
                           dx.rose == dq.rose)), where);
    if (f) {
        long double tol = df->err + 0x1p-62L * (fabsl(dq.diff) + fabsl(df->diff));
        if (!CHECK(q && df->broken == dq.broken && df->unresolved == dq.unresolved &&
                       df->rose == dq.rose && fabsl(df->diff - dq.diff) <= tol, where))
            printf("     fast: broken %d unresolved %d rose %d dh %.21Lg diff %.21Lg T %.3Lg\n"
                   "     quad: broken %d unresolved %d rose %d dh %.21Lg diff %.21Lg err %.3Lg\n",
                   df->broken, df->unresolved, df->rose, df->dh, df->diff, df->err, dq.broken,
                   dq.unresolved, dq.rose, dq.dh, dq.diff, dq.err);
    }
    return f;
}

/* The tanks of x0, x1 and r's works such that dh - w = ct, to what edmi_real holds: w is built
 * greedily from tp_delta_h's diff, an edmi_real at a time (work_ext and work_anchor from the
 * first two calls: set keeps them; then T0 - T1, both >= 0). */
static edmi_real up(long double x) /* the least edmi_real >= x >= 0 (up to one unit) */
{
    edmi_real t = (edmi_real)x;
    return (long double)t < x ? t + t * EDMI_EPS : t;
}

static void aim(edmi_system *x0, edmi_system *x1, edmi_step_result *r, long double ct, int set)
{
    tp_delta d;
    x0->tank = x1->tank = (edmi_real)0;
    if (set) {
        r->work_ext = r->work_anchor = (edmi_real)0;
        if (!tp_delta_h(x0, x1, r, &d))
            return;
        r->work_ext = (edmi_real)d.diff;
        if (!tp_delta_h(x0, x1, r, &d))
            return;
        r->work_anchor = (edmi_real)d.diff;
    }
    if (!tp_delta_h(x0, x1, r, &d))
        return;
    if (d.diff - ct >= 0.0L) { /* T0 just above it, then T1 takes the rest */
        x0->tank = up(d.diff - ct);
        if (tp_delta_h(x0, x1, r, &d))
            x1->tank = (edmi_real)(ct - d.diff);
    } else {
        x1->tank = up(ct - d.diff);
        if (tp_delta_h(x0, x1, r, &d))
            x0->tank = (edmi_real)(d.diff - ct);
    }
}

/* Every c T boundary of the step (x0 -> x1, r), T from the fast evaluation df. */
static void near_boundaries(const edmi_system *x0, const edmi_system *x1,
                            const edmi_step_result *r, const tp_delta *df, long *n, long *fast,
                            const char *where)
{
    edmi_step_result rr = *r;
    tp_delta d;
    int k;
    if (df->quad != 0)
        return;
    a0 = *x0;
    a1 = *x1;
    for (k = 0; k < HC_NC; k++) {
        aim(&a0, &a1, &rr, hc_c[k] * df->err, k == 0);
        *n += 1;
        *fast += compare(&a0, &a1, &rr, &d, where);
    }
}

/* x rotated a quarter turn about z: (x, y, z) -> (-y, x, z), exact. */
static void rot(edmi_real v[3])
{
    edmi_real t = v[0];
    v[0] = -v[1];
    v[1] = t;
}

/* The checks on one step s0 -> s1 with result r. */
static void check_step(const edmi_step_result *r, hc_count *c, const char *where)
{
    tp_delta df;
    edmi_step_result rr;
    int a, i, j;
    c->taken++;
    c->taken_fast += compare(&s0, &s1, r, &df, where);
    near_boundaries(&s0, &s1, r, &df, &c->near, &c->near_fast, where);
    /* link 0 as a user potential (the built-in behind tp_user_builtin_fn) */
    if (s0.n_links > 0) {
        a0 = s0;
        a1 = s1;
        user_ctx = s0.link[0].pot;
        a0.link[0].pot = a1.link[0].pot = edmi_pot_user(tp_user_builtin_fn, 0, &user_ctx);
        (void)compare(&a0, &a1, r, &df, where);
        c->compared++;
    }
    /* the end state moved by a random millionth */
    a1 = s1;
    for (a = 0; a < a1.n_bodies; a++)
        for (i = 0; i < 3; i++) {
            a1.body[a].q[i] *= (edmi_real)(1.0 + 1e-6 * hc_rand());
            a1.body[a].p[i] *= (edmi_real)(1.0 + 1e-6 * hc_rand());
        }
    s1 = a1; /* near_boundaries works on copies in a0, a1 */
    c->moved++;
    c->moved_fast += compare(&s0, &s1, r, &df, where);
    near_boundaries(&s0, &s1, r, &df, &c->near, &c->near_fast, where);
    /* the start rotated: H exactly the same, no work, the same tank */
    a1 = s0;
    for (a = 0; a < a1.n_bodies; a++) {
        rot(a1.body[a].q);
        rot(a1.body[a].p);
    }
    for (j = 0; j < a1.n_links; j++)
        if (a1.link[j].b == EDMI_ANCHOR)
            rot(a1.link[j].anchor);
    if (!s0.has_field || (s0.g[0] == 0 && s0.g[1] == 0)) {
        rr = *r;
        rr.work_ext = rr.work_anchor = (edmi_real)0;
        c->rotated++;
        CHECK(!compare(&s0, &a1, &rr, &df, where), where);
        if (df.quad == 0)
            CHECK(fabsl(df.dh) <= df.err, where);
    }
}

/* Steps of the loaded scene (scn) with scheme sch; the mix scene moves its anchor 0. */
static void run(const char *name, edmi_scheme sch, int move_anchor)
{
    hc_count c;
    edmi_scene view;
    char where[96];
    long k, n = scn.n_bodies > 6 ? HC_STEPS_BIG : HC_STEPS;
    int i;
    memset(&c, 0, sizeof c);
    scn.params.scheme = sch;
    snprintf(where, sizeof where, "%s, %s", name, sim_scheme_word(sch));
    view = sim_scene_view(&scn);
    if (!CHECK(edmi_load_scene(&sys, &view) == EDMI_OK &&
                   sim_scene_add_walls(&scn, &sys) == EDMI_OK, where))
        return;
    for (i = 0; i < scn.n_forces; i++)
        (void)edmi_set_force(&sys, scn.force_body[i], scn.force[i]);
    for (k = 0; k < n; k++) {
        edmi_step_result r;
        if (move_anchor) {
            edmi_real x[3];
            x[0] = (edmi_real)(0.05 * sin(0.01 * (double)k));
            x[1] = (edmi_real)(0.03 * cos(0.02 * (double)k));
            x[2] = (edmi_real)0;
            (void)edmi_move_anchor(&sys, 0, x);
        }
        s0 = sys;
        if (!CHECK(edmi_step(&sys, &work, (edmi_real)scn.dt, &r) == EDMI_OK, where))
            return;
        s1 = sys;
        check_step(&r, &c, where);
    }
    printf("ok   %s: %ld steps, the double-word bound settled %ld as taken, %ld of %ld moved, "
           "%ld of %ld at c T from the inequality's boundary; %ld rotated, none settled\n",
           where, c.taken, c.taken_fast, c.moved_fast, c.moved, c.near_fast, c.near, c.rotated);
    npass++;
    if (scn.n_mass == 0)
        CHECK((double)c.taken_fast >= HC_SETTLED * (double)c.taken, where);
}

/* What the shipped scenes lack: quartic, harmonic with rest length 0 and > 0, inverse, a field
 * and an anchor that moves (run moves link 0's). */
static const char *const mix_scene =
    "title hcheck mix\n"
    "body a 1 0.1 0 0 0 0.3 0\n"
    "body b 2 1.2 0 0 0 0.2 0.1\n"
    "body c 0.5 0 1 0.3 0.4 0 0\n"
    "anchor a 0 0 0 harmonic 50 0\n"
    "pair a b quartic 20 1\n"
    "pair b c harmonic 30 0.8\n"
    "pair a c inverse 0.5\n"
    "anchor c 0 1 0 harmonic 10 0.2\n"
    "field 0 0 -9.81\n"
    "set dt 1e-3\n";

int main(int argc, char **argv)
{
    static const char *const names[] = {"neo_hookean", "lj_two_body", "lj_cluster8",
                                        "solar_system", "hanging_chain", "cable_lumped",
                                        "cable_consistent"};
    char path[512], err[SIM_ERR_MAX];
    size_t i;
    if (argc != 2) {
        fprintf(stderr, "usage: test_hcheck SCENE_DIR\n");
        return 2;
    }
    printf("double-word H check against %s (%s build)\n", tp_q_name(),
           edmi_is_double_precision() ? "double" : "float");
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        edmi_scheme own;
        snprintf(path, sizeof path, "%s/%s.scene", argv[1], names[i]);
        if (!CHECK(sim_scene_load(path, &scn, err, sizeof err) == 0, path)) {
            printf("     %s\n", err);
            continue;
        }
        own = scn.params.scheme;
        run(names[i], own, 0);
        if (own != EDMI_SCHEME_MP)
            run(names[i], EDMI_SCHEME_MP, 0);
    }
    if (CHECK(sim_scene_parse(mix_scene, "mix.scene", &scn, err, sizeof err) == 0, "mix")) {
        run("mix", EDMI_SCHEME_PM, 1);
        run("mix", EDMI_SCHEME_MP, 1);
    }
    printf("%ld passed, %ld failed\n", npass, nfail);
    return nfail ? 1 : 0;
}
