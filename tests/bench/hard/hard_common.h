/* tests/bench/hard/hard_common.h: measurement helpers for issue 21's hard cases (public API only).
 * hc_step() steps a system and, on an EDMI_OK step that is not a fallback, evaluates the
 * scheme's residual at the STORED state with edmi_residual() from a copy of the system taken
 * before the step (an independent check: it does not trust res.residual). Scales:
 *   relp  = max over bodies |R_p| / |p_n|   (as the issue reports it; bodies with p_n = 0 skipped)
 *   rob   = max over bodies of |R_p| / (|p_n| + |p_n+1|) and
 *           |R_q| / (|q_n| + |q_n+1| + dt (|p_n| + |p_n+1|) / m)  (robust: a solved step has
 *           p_n+1 - p_n = dt F, so both ends bound the impulse; nothing huge can inflate it)
 *   flr   = max over bodies |R_p| / floor, floor = EDMI_EPS (|p_n| + |p_n+1| + sum_j |K_ij|
 *           |q1_j|) with K = dR_p/dq1 from edmi_tangent() at the stored state: the residual
 *           that rounding q_n+1 and p_n+1 to the working grid alone can leave (stiff links,
 *           cancelling terms); R_q against EDMI_EPS (|q_n| + |q_n+1| + dt (|p_n|+|p_n+1|)/m)
 *   doc   = the bound edmi.h states (EDMI_SOLVED), by tests/lib/passive.c's tp_solved (the
 *           fuzzer's check): a solved step is within 2 EDMI_SOLVED
 * Steps split into substeps (res.substeps > 1) and fallbacks solve no single step of dt and
 * are not checked. HC_SUBSTEPS=k and HC_FB=1 in the environment set params.substep_levels and
 * params.fallback on every step (tests/bench/hard/run.sh).
 * An OK step with rob > 1e3 EDMI_EPS counts as "OK but unsolved" (unsolved); one with
 * flr > 1e3 as unsolved beyond the rounding floor (unsolved_fl), and of those the steps where
 * the guard did not move the state by an impulse or drag (unsolved_ng). hc_print shows
 * "unsolved a/b/c" = unsolved/unsolved_fl/unsolved_ng. */
#ifndef HARD_COMMON_H
#define HARD_COMMON_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "edmi.h"
#include "passive.h"

#if defined(__GNUC__)
#define HC_UNUSED __attribute__((unused))
#else
#define HC_UNUSED
#endif

#define HC_NST 14
typedef struct hc_count {
    long steps, ok, fallback, unsolved, unsolved_fl, unsolved_ng, resid_fail, guard_moved;
    long st[HC_NST];
    double max_relp, max_rob, max_flr, max_doc;
    long beyond_doc; /* OK steps beyond 2 EDMI_SOLVED of the documented bound */
    long first_fail; /* step index of the first non-OK status, -1 if none */
    long split, substeps, fb_substeps, max_iter; /* steps split into substeps, their count, fallbacks */
    long first_fb;
} hc_count;

static edmi_system hc_before;
static edmi_real hc_q1[EDMI_MAX_BODIES][3], hc_p1[EDMI_MAX_BODIES][3];
static edmi_real hc_rq[EDMI_MAX_BODIES][3], hc_rp[EDMI_MAX_BODIES][3];
static edmi_real hc_k[9 * EDMI_MAX_BODIES * EDMI_MAX_BODIES];
static double hc_last_flr, hc_last_doc;

static void hc_reset(hc_count *c)
{
    memset(c, 0, sizeof *c);
    c->first_fail = c->first_fb = -1;
}

static double hc_n3(const edmi_real *v)
{
    return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
}

/* residual at the stored state of sys (after) from hc_before; returns status of edmi_residual */
static edmi_status hc_check(const edmi_system *sys, edmi_workspace *w, edmi_real dt,
                            double *relp, double *rob)
{
    int i, n = sys->n_bodies, sw;
    edmi_status s;
    *relp = *rob = 0.0;
    for (i = 0; i < n; i++) {
        memcpy(hc_q1[i], sys->body[i].q, sizeof hc_q1[i]);
        memcpy(hc_p1[i], sys->body[i].p, sizeof hc_p1[i]);
    }
    s = edmi_residual(&hc_before, w, dt, (const edmi_real(*)[3])hc_q1,
                      (const edmi_real(*)[3])hc_p1, hc_rq, hc_rp, &sw);
    if (s != EDMI_OK)
        return s;
    for (i = 0; i < n; i++) {
        double pn = hc_n3(hc_before.body[i].p), p1 = hc_n3(hc_p1[i]);
        double qn = hc_n3(hc_before.body[i].q), q1 = hc_n3(hc_q1[i]);
        double rp = hc_n3(hc_rp[i]), rq = hc_n3(hc_rq[i]);
        double a = pn > 0 ? rp / pn : 0.0; /* |p_n| = 0 (a start from rest): not measured */
        double sp = pn + p1, sq = qn + q1 + (double)dt * sp / (double)hc_before.body[i].m;
        double b1 = sp > 0 ? rp / sp : (rp > 0 ? INFINITY : 0.0);
        double b2 = sq > 0 ? rq / sq : (rq > 0 ? INFINITY : 0.0);
        if (!(a <= *relp)) *relp = a;      /* NaN propagates */
        if (!(b1 <= *rob)) *rob = b1;
        if (!(b2 <= *rob)) *rob = b2;
    }
    hc_last_flr = hc_last_doc = -1.0;
    if (edmi_tangent(&hc_before, w, dt, (const edmi_real(*)[3])hc_q1,
                     (const edmi_real(*)[3])hc_p1, hc_k) == EDMI_OK) {
        double f = 0.0;
        int N = 3 * n, r, j;
        for (i = 0; i < n; i++) {
            double pn = hc_n3(hc_before.body[i].p), p1 = hc_n3(hc_p1[i]), kq = 0.0;
            double qn = hc_n3(hc_before.body[i].q), q1 = hc_n3(hc_q1[i]), fl, x;
            for (r = 3 * i; r < 3 * i + 3; r++)
                for (j = 0; j < N; j++)
                    kq += fabs((double)hc_k[r * N + j]) * fabs((double)hc_q1[j / 3][j % 3]);
            fl = (double)EDMI_EPS * (pn + p1 + kq);
            x = fl > 0 ? hc_n3(hc_rp[i]) / fl : 0.0;
            if (!(x <= f)) f = x;
            fl = (double)EDMI_EPS * (qn + q1 + (double)dt * (pn + p1) / (double)hc_before.body[i].m);
            x = fl > 0 ? hc_n3(hc_rq[i]) / fl : 0.0;
            if (!(x <= f)) f = x;
        }
        hc_last_flr = f;
        /* the bound edmi.h documents (EDMI_SOLVED), by tests/lib/passive.c's tp_solved (the
         * fuzzer's check): max |R| / (eps M) over bodies; <= 2 EDMI_SOLVED is within it */
        {
            edmi_status ts;
            int tb, tw;
            long double g = tp_solved(&hc_before, sys, dt, w, &ts, &tb, &tw);
            hc_last_doc = ts == EDMI_OK ? (double)g : -1.0;
        }
    }
    return EDMI_OK;
}

/* one step with counting; returns the status and relp, rob of the check (-1: not checked) */
static edmi_status hc_step(edmi_system *sys, edmi_workspace *w, edmi_real dt,
                           edmi_step_result *res, hc_count *c, double *relp, double *rob)
{
    double a = -1.0, b = -1.0;
    edmi_status s;
    static int lev = -2;
    if (lev == -2)
        lev = getenv("HC_SUBSTEPS") ? atoi(getenv("HC_SUBSTEPS")) : -1;
    if (lev >= 0)
        sys->params.substep_levels = lev;
    if (getenv("HC_FB"))
        sys->params.fallback = atoi(getenv("HC_FB"));
    hc_before = *sys;
    s = edmi_step(sys, w, dt, res);
    if (s == EDMI_OK) {
        c->split += res->substeps > 1;
        c->substeps += res->substeps;
        c->fb_substeps += res->fallbacks;
    }
    if (res->iterations > c->max_iter)
        c->max_iter = res->iterations;
    if ((int)s >= 0 && (int)s < HC_NST)
        c->st[s]++;
    if (s == EDMI_OK) {
        c->ok++;
        if (res->stop == EDMI_STOP_FALLBACK) {
            if (c->first_fb < 0) c->first_fb = c->steps;
            c->fallback++;
        } else if (res->substeps == 1) { /* a split step solves each substep, not dt */
            if (res->guard_action & (EDMI_MOVE_IMPULSE | EDMI_MOVE_DRAG))
                c->guard_moved++;
            if (hc_check(sys, w, dt, &a, &b) != EDMI_OK) {
                c->resid_fail++;
            } else {
                if (!(a <= c->max_relp)) c->max_relp = a;
                if (!(b <= c->max_rob)) c->max_rob = b;
                if (!(b <= 1e3 * (double)EDMI_EPS)) c->unsolved++;
                if (!(hc_last_flr <= c->max_flr)) c->max_flr = hc_last_flr;
                if (!(hc_last_doc <= c->max_doc)) c->max_doc = hc_last_doc;
                if (!(hc_last_doc <= 2.0 * EDMI_SOLVED) &&
                    !(res->guard_action & (EDMI_MOVE_IMPULSE | EDMI_MOVE_DRAG)))
                    c->beyond_doc++;
                if (!(hc_last_flr <= 1e3)) {
                    c->unsolved_fl++;
                    if (!(res->guard_action & (EDMI_MOVE_IMPULSE | EDMI_MOVE_DRAG)))
                        c->unsolved_ng++;
                }
            }
        }
    } else if (c->first_fail < 0) {
        c->first_fail = c->steps;
    }
    c->steps++;
    if (relp) *relp = a;
    if (rob) *rob = b;
    return s;
}

HC_UNUSED static const char *hc_prec(void) { return edmi_is_double_precision() ? "double" : "float"; }

HC_UNUSED static const char *hc_stop_name(edmi_stop s)
{
    static const char *n[] = {"CONVERGED", "STALLED", "TOL_R", "TOL_A", "FALLBACK"};
    return (unsigned)s < 5u ? n[s] : "?";
}

HC_UNUSED static const char *hc_scheme_name(edmi_scheme s)
{
    static const char *n[] = {"MP", "LG", "GE", "PM", "PT"};
    return (unsigned)s < 5u ? n[s] : "?";
}

HC_UNUSED static void hc_print(const char *label, const hc_count *c)
{
    int i;
    printf("%-6s %-40s steps %7ld ok %7ld fb %6ld unsolved %ld/%ld/%ld maxRp/|p| %.2e rob %.2e "
           "flr %.2e", hc_prec(), label, c->steps, c->ok, c->fallback, c->unsolved,
           c->unsolved_fl, c->unsolved_ng, c->max_relp, c->max_rob, c->max_flr);
    for (i = 1; i < HC_NST; i++)
        if (c->st[i])
            printf(" %s %ld", edmi_status_name((edmi_status)i) + 9, c->st[i]);
    if (c->first_fail >= 0) printf(" firstfail@%ld", c->first_fail);
    if (c->first_fb >= 0) printf(" firstfb@%ld", c->first_fb);
    if (c->guard_moved) printf(" guardmoves %ld", c->guard_moved);
    if (c->resid_fail) printf(" residERR %ld", c->resid_fail);
    if (c->split) printf(" split %ld (substeps %ld, fallback substeps %ld)", c->split, c->substeps, c->fb_substeps);
    printf(" maxit %ld doc %.2g beyond %ld", c->max_iter, c->max_doc, c->beyond_doc);
    printf("\n");
}
#endif
