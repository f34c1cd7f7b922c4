/* Observed convergence orders: GE is first order, MP, LG, PM and PT second order
 * (propositions convex-concave-accuracy, perturbed-mid-point-accuracy,
 * perturbed-trapezoidal-accuracy), on the paper's neo-Hookean spring and its two
 * Lennard-Jones bodies. The order comes from successive differences of three runs with
 * steps h, h/2, h/4 to the same T:  p = log2(|y_h - y_h/2| / |y_h/2 - y_h/4|), separately
 * for all positions and all momenta, so no reference solution is needed.
 *
 * Truncation: with y_h = y + c_p h^p + c_p+1 h^(p+1) + ..., the estimate is p + O(h); the
 * steps below are chosen where that O(h) term, measured by halving h once more, is at most
 * half of the tolerance. */
#include "harness.h"
#include "suites.h"
#include "scenes.h"

/* |p_observed - p| allowed in double. Measured deviations at the chosen steps (the next
 * halving shrinks each by about 2, as an O(h) term should):
 *   spring T = 1, h = 2.5e-3: GE 0.053 (q) 0.027 (p); MP, LG <= 0.002; PM 0.005; PT 0.010;
 *   LJ2 T = 1, h = 2.5e-4: MP, LG, PM, PT 0.000 (q) 0.048 (p);
 *   LJ2 T = 0.1, h = 1.25e-4: GE 0.068 (q) 0.059 (p).
 * 0.1 leaves about twice the largest; a first-order GE or a first-order MP would miss the
 * band by 0.9. */
#define ORD_TOL EDMI_R(0.1)

/* Float, spring: the successive differences must stand well above float round-off, which
 * over N steps accumulates to at most about N eps_f |y|. At the double step h = 2.5e-3 the
 * finest second-order difference (1e-4 |y|, N = 1600) is below that bound (1.9e-4 |y|), so
 * float uses h = 1e-2: differences 1.5e-3 |y| and 4e-4 |y| (measured in double) against at
 * most 4.8e-5 |y| (N = 400), which can move the estimate by up to ~0.1 and moves it by 0.02
 * (measured against double); the truncation deviation at this coarser h is 0.05 (PT, q, in
 * double). 0.15 covers both. GE's first-order differences (3e-2 |y|, 2e-2 |y|) are 50 times
 * larger, so it keeps the double step and ORD_TOL (float moves it by 0.01). */
#define ORD_TOL_FLOAT2 EDMI_R(0.15)

static const edmi_scheme ord_schemes[5] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};

typedef edmi_status (*ord_build)(edmi_system *, const edmi_params *);

/* Orders of positions and momenta from runs with h, h/2, h/4 to time t_end. */
static edmi_status ord_estimate(ord_build build, edmi_params prm, edmi_real t_end, edmi_real h,
                                edmi_real *oq, edmi_real *op)
{
    edmi_real hh = h;
    edmi_status st = EDMI_OK;
    int lv;
    for (lv = 0; lv < 3 && st == EDMI_OK; lv++, hh *= EDMI_R(0.5)) {
        long n = (long)(t_end / hh + EDMI_R(0.5));
        st = build(&ts_sys[lv], &prm);
        if (st == EDMI_OK)
            st = ts_advance(&ts_sys[lv], &ts_work, hh, n, 0);
    }
    if (st != EDMI_OK) {
        *oq = *op = EDMI_R(0.0);
        return st;
    }
    *oq = ts_log2(ts_state_diff(&ts_sys[0], &ts_sys[1], 0) /
                  ts_state_diff(&ts_sys[1], &ts_sys[2], 0));
    *op = ts_log2(ts_state_diff(&ts_sys[0], &ts_sys[1], 1) /
                  ts_state_diff(&ts_sys[1], &ts_sys[2], 1));
    return EDMI_OK;
}

static void ord_log(const char *scene, edmi_scheme s, edmi_real h, edmi_real oq, edmi_real op)
{
    th_puts("  ");
    th_puts(scene);
    th_puts(" ");
    th_puts(ts_scheme_name(s));
    th_puts(" h = ");
    th_put_real(h, 3);
    th_puts(": order q ");
    th_put_real(oq, 4);
    th_puts(", p ");
    th_put_real(op, 4);
    th_newline();
}

/* Estimate and check one scheme. */
static void ord_case(const char *scene, ord_build build, edmi_scheme s, edmi_real tol_r,
                     edmi_real t_end, edmi_real h, edmi_real tol)
{
    edmi_params prm = ts_params(s);
    edmi_real want = s == EDMI_SCHEME_GE ? EDMI_R(1.0) : EDMI_R(2.0), oq, op;
    prm.tol_r = tol_r;
    if (th_skip(ts_scene_in(build, &prm), ts_label(scene, ts_scheme_name(s))))
        return;
    CHECK_STATUS(ord_estimate(build, prm, t_end, h, &oq, &op), EDMI_OK);
    CHECK_NEAR(oq, want, tol, EDMI_R(0.0));
    CHECK_NEAR(op, want, tol, EDMI_R(0.0));
    ord_log(scene, s, h, oq, op);
}

/* The spring at T = 1 with the paper's tol_R = 1e-10 (float: its default). */
static void ord_spring(void)
{
    const edmi_real tol_r = edmi_default_params().tol_r;
    int i;
    for (i = 0; i < 5; i++) {
        edmi_scheme s = ord_schemes[i];
        if (edmi_is_double_precision() || s == EDMI_SCHEME_GE)
            ord_case("spring T=1", ts_spring, s, tol_r, EDMI_R(1.0), EDMI_R(2.5e-3), ORD_TOL);
        else
            ord_case("spring T=1", ts_spring, s, tol_r, EDMI_R(1.0), EDMI_R(1e-2),
                     ORD_TOL_FLOAT2);
    }
}

/* The two Lennard-Jones bodies with the paper's tol_R = 1e-12. The pair oscillates with
 * omega ~ 107 about the well: the second-order schemes are asymptotic at T = 1 from
 * h = 2.5e-4; GE's first-order error constant grows like omega^2 T, so at T = 1 its estimate
 * is still 0.88 at h = 2e-5 (measured): GE is measured at T = 0.1 instead.
 * Double only: the finest successive differences are 1.5e-7 |y| (q) to 9e-7 |y| (p), GE
 * 1.3e-5 to 3.3e-4 |y| (measured in double), against up to N eps_f |y| = 1.9e-3 |y| of float
 * round-off over the finest run's N = 16000 steps (4e-4 |y| for GE's 3200): float cannot
 * resolve them. */
static void ord_lj2(void)
{
    int i;
    if (!edmi_is_double_precision()) {
        th_puts("  LJ2 orders: double only (float round-off exceeds the differences)\n");
        return;
    }
    for (i = 0; i < 5; i++) {
        edmi_scheme s = ord_schemes[i];
        if (s == EDMI_SCHEME_GE)
            ord_case("LJ2 T=0.1", ts_lj2, s, EDMI_R(1e-12), EDMI_R(0.1), EDMI_R(1.25e-4),
                     ORD_TOL);
        else
            ord_case("LJ2 T=1", ts_lj2, s, EDMI_R(1e-12), EDMI_R(1.0), EDMI_R(2.5e-4),
                     ORD_TOL);
    }
}

void suite_orders(void)
{
    th_suite("orders: GE first order, MP/LG/PM/PT second order");
    ord_spring();
    ord_lj2();
}
