/* The passivity inequality checked on stored states, by arithmetic independent of the
 * library's, and the adversarial scenes the guard is tested and soaked on (tests/passive.c).
 * No stdio, no malloc: the same sources run on the host and under QEMU. */
#ifndef EDMI_TEST_PASSIVE_H
#define EDMI_TEST_PASSIVE_H

#include "../edmi.h"

/* H(s1) - H(s0) of two stored states of the same system (anchors where each state has them),
 * evaluated term by term in long double: dh, with err a bound on its rounding error (the
 * check's own resolution), and w = work_ext + work_anchor + T(s0) - T(s1), the reported works
 * plus what the energy tank gave (edmi_system.tank before and after): the guard's inequality
 * is dh <= w. Built-in potentials other than user ones. Returns 0 if a term cannot be
 * evaluated. */
typedef struct tp_delta {
    long double dh;  /* H(s1) - H(s0) */
    long double w;   /* res.work_ext + res.work_anchor + s0->tank - s1->tank */
    long double err; /* |computed dh - exact dh| <= err */
    long double mag; /* the magnitude of dh's terms (what a plain evaluation errs by, per unit
                        of round-off) */
} tp_delta;

int tp_delta_h(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res,
               tp_delta *d);

/* H of a stored state in long double (for drifts relative to H0); LDBL_MAX for a coupled M
 * that is not positive definite to long double's resolution (not evaluated). */
long double tp_h(const edmi_system *s);

/* The scenes. */
typedef enum tp_scene {
    TP_SPRING = 0,  /* the paper's neo-Hookean spring, dt = 1e-3 */
    TP_PUMP,        /* 1 kHz virtual spring (m 0.1, k 1e4, r0 0.05), port F = +c v (saturated) */
    TP_RANDOM,      /* the same spring, port force uniformly random in a cube each tick */
    TP_FLIP,        /* the same spring, port force flipping sign every tick */
    TP_STIFF,       /* harmonic k = 1e6 about an anchor, m = 1, dt = 0.1: omega dt = 100 */
    TP_COLLIDE,     /* two LJ bodies on soft tethers colliding head on, again and again */
    TP_COUPLING,    /* zero-rest-length spring + damper to a hand moving through the body */
    TP_CHAIN,       /* hanging chain: field, dampers, a random port on the last body */
    TP_NSCENES
} tp_scene;

const char *tp_scene_name(tp_scene s);

/* Build scene s with parameters prm (scheme, guard, ...) and fallback on, as a control loop
 * runs it, into sys; *dt its time step. */
edmi_status tp_build(tp_scene s, const edmi_params *prm, edmi_system *sys, edmi_real *dt);

/* The scene's controller before step n: port forces and anchor moves for the next tick. */
void tp_control(tp_scene s, edmi_system *sys, long n);

/* What a run measured. */
typedef struct tp_stats {
    long steps;              /* accepted steps */
    edmi_status status;      /* EDMI_OK or the first failing status */
    long violations;         /* steps with dh > w + err: the inequality broken */
    long rises;              /* steps with dh > err (H rose; legitimate only with work) */
    long uncertain;          /* steps where |dh - w| <= err: below the check's resolution */
    long fallbacks;          /* steps that took the fallback state */
    long guarded;            /* steps the guard changed */
    long iterations;         /* Newton corrections summed */
    long double worst;       /* max over steps of (dh - w) / H scale: the passivity margin */
    long double h0, h_last;  /* H at start and end */
    long double sum_w;       /* sum of w: the work supplied */
    long double max_dj;      /* max |J - J0| / |J0| (anchors at the origin and no field only) */
    /* The tank's statement on every window m < n of the run: H_n - H_m <= sum of the works
     * in between + T_m, with 0 <= T <= res.tank_cap after every step. */
    long window_violations;  /* steps n at which some window ending there broke it */
    long tank_violations;    /* steps whose tank was negative, above its capacity or not the
                                reported one */
    long double max_window;  /* max over windows of H_n - H_m - sum W, over H0 */
    long double max_cap;     /* the largest capacity reported, over H0 */
    long double window_err;  /* the window check's own accumulated rounding bound, over H0 */
} tp_stats;

/* Take n steps of scene s (built with prm), checking the inequality after every step. */
void tp_run(tp_scene s, const edmi_params *prm, long n, tp_stats *st);

#endif
