/* Shared scenes and per-step law bookkeeping for the energy, orders, paper and hard suites.
 * No stdio, no malloc, no libm: the same sources run on the host and under QEMU. */
#ifndef EDMI_TEST_SCENES_H
#define EDMI_TEST_SCENES_H

#include "edmi.h"

/* ---- small maths in edmi_real --------------------------------------------------------- */
edmi_real ts_abs(edmi_real x);
edmi_real ts_max(edmi_real a, edmi_real b);
edmi_real ts_min(edmi_real a, edmi_real b);
edmi_real ts_norm3(const edmi_real v[3]);
int ts_finite(edmi_real x);
/* Natural and base-2 logarithms of x > 0 without libm (exponent by halving, then the atanh
 * series); relative accuracy a few eps. */
edmi_real ts_ln(edmi_real x);
edmi_real ts_log2(edmi_real x);
/* Observed order from two errors (or successive differences) whose step sizes differ by
 * the factor `ratio`: ln(e_coarse / e_fine) / ln(ratio). */
edmi_real ts_order(edmi_real e_coarse, edmi_real e_fine, edmi_real ratio);

/* "MP", "LG", "GE", "PM", "PT". */
const char *ts_scheme_name(edmi_scheme s);
/* "JANZ", "GONZALEZ", "GE", "PM", "PT". */
const char *ts_alt_name(edmi_lg_alt a);

/* "a b" for a log line (a skipped case's name), in a static buffer the next call reuses;
 * cut at 79 characters. */
const char *ts_label(const char *a, const char *b);

/* ---- scenes --------------------------------------------------------------------------- */
/* Parameters: the defaults with `scheme` set. */
edmi_params ts_params(edmi_scheme scheme);
/* The paper's stiff neo-Hookean spring (section 3.5): m = 10, q0 = (2,1,1),
 * p0 = (-30,15,45), anchor at the origin, c = 1e3, rbar = 4. */
edmi_status ts_spring(edmi_system *sys, const edmi_params *prm);
/* The paper's two Lennard-Jones bodies (section 4.3.1): m = 1, q = (0, -/+0.5612, 0),
 * p = (5,0,0) and (10,0,0), eps = 1e2, sigma = 1. */
edmi_status ts_lj2(edmi_system *sys, const edmi_params *prm);
/* A small gravitating system: a heavy body and three light ones in different planes,
 * G = 1, all six pairs linked with V = -m_A m_B / r, non-zero total momentum. */
edmi_status ts_gravity(edmi_system *sys, const edmi_params *prm);
/* One body of mass m on a circular orbit of radius r0 about an anchor at the origin with
 * V = -k/r: q0 = (r0,0,0), p0 = (0, sqrt(m k / r0), 0). */
edmi_status ts_orbit(edmi_system *sys, const edmi_params *prm, edmi_real m, edmi_real k,
                     edmi_real r0);

/* What a scene needs of the build (EDMI_WITH_*): 1 when prm's scheme (and LG form) and the
 * potential of the scene's links are compiled in. Ask before building: a build without them
 * refuses the scene (EDMI_ERR_DISABLED), and the test skips the case (th_skip). `build` is
 * ts_spring, ts_lj2 or ts_gravity; ts_orbit_in is ts_orbit's. */
typedef edmi_status (*ts_build)(edmi_system *sys, const edmi_params *prm);
int ts_scene_in(ts_build build, const edmi_params *prm);
int ts_orbit_in(const edmi_params *prm);

/* ---- one step with its conservation laws ----------------------------------------------- */
/* Everything measured about one accepted step n -> n+1. R_q, R_p are the scheme's residuals
 * at the accepted state (edmi_residual from the start state). Exact identities (derived in
 * scenes.c) relate the changes of H, J, L, C to these residuals:
 *   H1 - H0 = e_res - D,  e_res = sum_A (dq_A . R_p^A - R_q^A . dp_A) / dt,
 *   D = sum_links (Lambda (d1-d0) - (V(d1)-V(d0)))   (0 for LG, >= 0 for GE/PM/PT). */
typedef struct ts_law {
    edmi_step_result res; /* what edmi_step reported */
    edmi_real dh;         /* H1 - H0 */
    edmi_real e_res;      /* signed solver term of the energy identity */
    edmi_real e_solver;   /* sum_A (|dq_A| |R_p^A| + |R_q^A| |dp_A|) / dt >= |e_res| */
    edmi_real e_round;    /* round-off allowance of the energy balance (see scenes.c) */
    int has_law;          /* d_lo, d_hi valid: the scheme has a per-step dissipation law */
    edmi_real d_lo, d_hi; /* D must lie in [d_lo, d_hi] (mean-value points bracketed) */
    edmi_real dj, dj_bound; /* |J1 - J0| and its bound (anchors at the origin only) */
    edmi_real dl, dl_bound; /* |L1 - L0| and its bound (no anchors) */
    edmi_real dc, dc_bound; /* |C1 - C0| and its bound (no anchors) */
    edmi_real dmin;         /* smallest link distance at the end of the step */
} ts_law;

/* Step once and fill *law. Returns edmi_step's status (law->res valid as edmi_step says),
 * or the status of the bookkeeping calls if one of those fails. */
edmi_status ts_step_law(edmi_system *sys, edmi_workspace *work, edmi_real dt, ts_law *law);

/* 1 if the bodies and time of sys equal (==) the state ts_step_law saw before its last
 * edmi_step: after a failed step the library promises an untouched system. */
int ts_unchanged_by_last_step(const edmi_system *sys);

/* ---- a run of steps with statistics ---------------------------------------------------- */
typedef struct ts_run {
    long steps;              /* accepted steps */
    edmi_status status;      /* EDMI_OK, or the first failing status (the run stops there) */
    long iterations;         /* Newton corrections summed over accepted steps */
    int nonfinite;           /* a state component became inf/NaN after an accepted step */
    edmi_real h0, h_last, h_min, h_max; /* H at the start, end, and its extremes */
    edmi_real max_abs_dh;    /* largest |H_n+1 - H_n| */
    edmi_real j0[3], l0[3], c0[3];      /* invariants at the start */
    edmi_real sum_bound;     /* sum over steps of (e_solver + e_round) */
    edmi_real sum_round;     /* sum over steps of e_round */
    edmi_real sum_dj_bound;  /* sum over steps of the per-step |dJ| bound */
    edmi_real sum_dlo;       /* sum over steps of d_lo (dissipation the exact law guarantees) */
    edmi_real worst_cons;    /* max |dh| / (e_solver + e_round): conservation */
    edmi_real worst_up;      /* max dh / (e_solver + e_round): non-increase */
    edmi_real worst_law;     /* max violation of D in [d_lo, d_hi] / e_round (0 if none) */
    int law_steps;           /* steps on which the sharp law was available */
    long n_up, n_down;       /* steps with dh > +bound and dh < -bound */
    long switched_steps;     /* steps whose accepted state used an LG alternate force */
    edmi_real worst_j, worst_l, worst_c; /* max per-step |dX| / bound */
    edmi_real max_dj, max_dl, max_dc;    /* max |X_n - X_0| */
    edmi_real dmin;          /* smallest link distance seen */
} ts_run;

void ts_run_init(ts_run *run, const edmi_system *sys);
/* Take up to n steps of size dt; stops at the first non-OK status (kept in run->status). */
edmi_status ts_run_steps(ts_run *run, edmi_system *sys, edmi_workspace *work, edmi_real dt,
                         long n);

/* Take n plain steps (no bookkeeping); returns the first non-OK status. Adds the Newton
 * corrections to *iterations when it is not NULL. */
edmi_status ts_advance(edmi_system *sys, edmi_workspace *work, edmi_real dt, long n,
                       long *iterations);

/* |a - b| over the positions (which = 0) or momenta (which = 1) of all bodies, as one
 * 3n-vector norm; and the norm of that vector of `a` itself. */
edmi_real ts_state_diff(const edmi_system *a, const edmi_system *b, int which);
edmi_real ts_state_norm(const edmi_system *a, int which);

/* Shared scratch systems and workspace, defined in scenes.c as globals (not on the stack:
 * an edmi_system plus an edmi_workspace is ~40 kB in double, too much for a small target's
 * stack frame). Suites run one after another, so sharing is safe. */
extern edmi_system ts_sys[3];
extern edmi_workspace ts_work;

#endif
