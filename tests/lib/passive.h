/* The passivity inequality checked on stored states, by arithmetic independent of the
 * library's, and the adversarial scenes the guard is tested and soaked on (tests/lib/passive.c).
 * No stdio, no malloc: the same sources run on the host and under QEMU. */
#ifndef EDMI_TEST_PASSIVE_H
#define EDMI_TEST_PASSIVE_H

#include "edmi.h"

/* The check's arithmetic, tp_q: __float128 on the x86-64 host (GCC, clang), long double
 * elsewhere (the Arm targets, where it is double) or with TP_NO_FLOAT128. Its name and
 * epsilon, for reports (2^-112 for binary128). */
const char *tp_q_name(void);
long double tp_q_eps(void);

/* H(s1) - H(s0) of two stored states of the same system (anchors where each state has them),
 * evaluated term by term in tp_q: dh, with err a bound on its rounding error (the check's
 * own resolution), and w = work_ext + work_anchor + T(s0) - T(s1), the reported works plus
 * what the energy tank gave (edmi_system.tank before and after): the guard's inequality is
 * dh <= w. The values are reported in long double, each rounded once from tp_q; the
 * inequality is decided in tp_q before that rounding (broken, unresolved): compare those,
 * not dh - w with err, which loses what binary128 resolved. A user potential is evaluated
 * as the built-in one its callback computes (tp_user_register). Returns 0 if a term cannot
 * be evaluated. */
typedef struct tp_delta {
    long double dh;   /* H(s1) - H(s0) */
    long double w;    /* res.work_ext + res.work_anchor + s0->tank - s1->tank */
    long double err;  /* |computed dh - exact dh| <= err */
    long double mag;  /* the magnitude of dh's terms (what a plain evaluation errs by, per
                         unit of round-off) */
    long double diff; /* dh - w, evaluated in tp_q and then rounded: the inequality's margin */
    int broken;       /* dh - w > err in tp_q: the inequality broken beyond the check's
                         resolution */
    int unresolved;   /* |dh - w| <= err in tp_q: below the check's resolution */
    int rose;         /* dh > err in tp_q: H rose beyond the check's resolution */
    int quad;         /* 1: evaluated in tp_q (tp_delta_h); 0: by tp_delta_dw, whose dh, w,
                         diff, err (its threshold T) and mag (its M) these are */
} tp_delta;

int tp_delta_h(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res,
               tp_delta *d);

/* tp_delta_h's decisions at a fraction of its cost (tests/lib/passive.c proves the bound).
 * tp_h_dw: H of one stored state in binary64 double-word arithmetic, hi + lo, with the
 * magnitude mag and count n of its terms that bound its error; ok 0 where it is not evaluated
 * (a coupled M, a potential it does not cover, an underflow or overflow on the way, a build
 * without __float128, where tp_q is no slower). tp_delta_dw: dh = H(s1) - H(s0) and dh - w
 * from two of them, decided against a threshold T >= their error + 2 x tp_delta_h's err;
 * 1 where that settles broken, unresolved and rose (then equal to tp_delta_h's), 0 where it
 * does not (a change within T of 0, either state not evaluated, masses or field that differ
 * between the states); where it returns 1, and where only T left a decision open, *d holds
 * this evaluation's dh, w, diff, T as err and its magnitude as mag, with quad 0 (its flags
 * mean something only where it returns 1). tp_delta_h_fast: tp_delta_dw, else tp_delta_h (quad 1); its return value
 * and decisions are tp_delta_h's. A run evaluates each state once: the h1 of one step is
 * the h0 of the next. */
typedef struct tp_hdw {
    double hi, lo; /* H(s) = hi + lo */
    double mag;    /* the sum of its terms' magnitudes (the bound's M) */
    int n, ok;     /* its number of terms; 1 if evaluated */
} tp_hdw;

void tp_h_dw(const edmi_system *s, tp_hdw *h);
int tp_delta_dw(const edmi_system *s0, const tp_hdw *h0, const edmi_system *s1,
                const tp_hdw *h1, const edmi_step_result *res, tp_delta *d);
int tp_delta_h_fast(const edmi_system *s0, const tp_hdw *h0, const edmi_system *s1,
                    const tp_hdw *h1, const edmi_step_result *res, tp_delta *d);

/* The tank's statement on every window of consecutive steps, H_n - H_m <= the works in
 * between + T_m for every m < n, checked as a run goes (in tp_q: A_n = H_n - sum of the works
 * before n, from each step's tp_delta_h change, must stay below min over m of A_m + T_m, the
 * accumulated rounding of A allowed). tp_window_start begins a run at state s (after a change
 * no step made: a build call, a write into the system); tp_window_step adds the step from s0
 * to s1 and returns 1 if every window ending at s1 holds, 0 if one is broken beyond the
 * check's resolution, -1 if the step cannot be evaluated (then it starts a new run at s1).
 * One run at a time. */
void tp_window_start(const edmi_system *s);
int tp_window_step(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res);
/* The largest H_n - H_0 - (the works from 0 to n) over the steps n >= 1 of the run since
 * tp_window_start (0 before a step), evaluated in tp_q: at most T_0 plus the check's rounding
 * while no window is broken. */
long double tp_window_rise(void);
/* 1 if the step's reported work_ext is at most the exact work of its ports on the stored
 * numbers, sum F . (q_n+1 - q_n) in tp_q (a split step's too: its ports hold F, so the
 * substeps' exact works add up to it). */
int tp_port_work_below(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res);

/* H of a stored state, evaluated in tp_q and rounded to long double (for drifts relative to
 * H0); LDBL_MAX for a coupled M that is not positive definite to long double's resolution
 * (not evaluated). */
long double tp_h(const edmi_system *s);

/* How far the stored state s is from solving the scheme's equations for the step dt from s0
 * (edmi_residual() at s), in units of the magnitudes of the residual's terms as edmi.h states
 * them for EDMI_SOLVED, evaluated here in long double from public data, per body a:
 *   Q_a = |q_n| + |q1| + dt/m (|p_n| + |p1|) (+ the coupled masses' |m_ab|/m_a (|q_n,b| + |q1_b|))
 *         + 16 x the smallest normal (the subnormal grid),
 *   P_a = |p_n| + |p1| + dt |F_a| + dt |M 1|_a |g| + 16 x the smallest normal
 *         + per link 4 (dt |link_force| + 3 k (|r_m| + Q_a + Q_b)), k the largest entry of that
 *           link's own tangent (edmi_tangent() of a copy holding it alone), Q_b = |x_n+1| for
 *           an anchor
 *         + per damper 4 c (|r_n| + |r1| + Q_a + Q_b) + the LG quotient's dt |V| / |d1 - d0|
 *           (V from this file's own formulas, |d1 - d0| less the rounding of the lengths in
 *           the library's precision, 4 eps (d0 + d1): unbounded where that leaves nothing);
 * returns max over bodies of |R_q,a| / (eps Q_a) and |R_p,a| / (eps P_a), *body and *which
 * (0: R_q, 1: R_p) where; -1 with *status the error if the residual cannot be evaluated.
 * A solved step is at most EDMI_SOLVED here, up to the rounding of the magnitudes; a step
 * Newton never solved is off by 1e10 to 1e30. */
long double tp_solved(const edmi_system *s0, const edmi_system *s, edmi_real dt,
                      edmi_workspace *work, edmi_status *status, int *body, int *which);

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

/* What scene s needs of the build beyond its parameters (EDMI_WITH_*, EDMI_MAX_DAMPERS): 1 when
 * its potentials, dampers, field and ports are compiled in. Ask it, with the parameters'
 * th_has_params (tests/lib/harness.h), before tp_build or tp_run: a build without them refuses
 * the scene (EDMI_ERR_DISABLED), and tp_control's port forces would be refused too. */
int tp_scene_in(tp_scene s);

/* The scene's controller before step n: port forces and anchor moves for the next tick. */
void tp_control(tp_scene s, edmi_system *sys, long n);

/* What a run measured. */
typedef struct tp_stats {
    long steps;              /* accepted steps */
    edmi_status status;      /* EDMI_OK or the first failing status */
    long violations;         /* steps with dh > w + err: the inequality broken (in tp_q) */
    long rises;              /* steps with dh > err (H rose; legitimate only with work) */
    long uncertain;          /* steps where |dh - w| <= err: below the check's resolution */
    long fallbacks;          /* steps that took the fallback state */
    long guarded;            /* steps the guard changed */
    long iterations;         /* Newton corrections summed */
    long works_above;        /* steps (not split, not fallen back) whose reported work_ext or
                                work_anchor exceeded the exact work on the stored forces and
                                positions (tp_q): both are rounded down (edmi.h) */
    /* the rest accumulated in tp_q, reported in long double */
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
    int window_beyond_cap;   /* max_window > max_cap + window_err, decided in tp_q: some
                                window rose by more than the largest capacity (a violation
                                where no work is done) */
} tp_stats;

/* Take n steps of scene s (built with prm), checking the inequality after every step. */
void tp_run(tp_scene s, const edmi_params *prm, long n, tp_stats *st);

/* ---- Rest is a fixed point; user potentials are guarded as the built-ins are ----------------
 * Scenes that settle to rest (energies that underflow, distances down to the subnormal range,
 * a body exactly on its anchor) and a user potential identical to a built-in one, run with
 * the inequality checked after every step by tp_rest_delta (below), which evaluates both
 * stored states in tp_q on values scaled by a power of two: exact where tp_q has no wider
 * range than double (long double on the Arm targets), where H's terms would underflow. */
typedef enum tp_rest {
    TP_REST_ANCHOR = 0, /* zero-rest-length spring edmi_pot_harmonic(1e4, 0) from m 0.1 to an
                           anchor at the origin, dt 1e-3, from q (0.01, 0, 0), p 0 */
    TP_REST_ON_ANCHOR,  /* the same spring, the body exactly on its anchor (0.25, -1, 3), p 0 */
    TP_REST_NEO_HOOKE,  /* edmi_pot_neo_hooke(1e3, 1) to the origin, m 0.1, from (1.2, 0.3,
                           -0.1) at rest: settles onto its rest length */
    TP_REST_PAIR,       /* two bodies of m 0.1 at (+-0.005, 0, 0) at rest on a zero-rest-length
                           pair spring edmi_pot_harmonic(1e4, 0), no anchor: they settle
                           together at the origin */
    TP_REST_OFF_ANCHOR, /* TP_REST_ANCHOR's spring and body with the anchor at (0.25, -1, 3),
                           from (0.26, -1, 3): the body rests where the grid of positions
                           around its anchor (units of ~eps 3) lets it */
    TP_REST_PAIR_OFF,   /* the pair spring with masses 0.1 at (0.0075, 0, 0) and 0.3 at
                           (-0.0025, 0, 0): they meet at their centre of mass, ~1e-19 from
                           the origin (0.0075 and 0.0025 are not on the grid) */
    TP_REST_USER,       /* a user potential identical to edmi_pot_harmonic(50, 1), m 1, from
                           (1.3, 0, 0), p (0, 2, 0), anchor at the origin (tp_rest_run also
                           steps the built-in one alongside: the reference) */
    TP_NREST
} tp_rest;

const char *tp_rest_name(tp_rest s);

/* The user potential of TP_REST_USER: V = k/2 (r - r0)^2 with k and r0 from ctx (a
 * tp_user_harmonic), split as the built-in is (V_c = V_+ = V, V_e = V_- = 0);
 * tp_user_harmonic_dd its closed-form divided difference. */
typedef struct tp_user_harmonic {
    edmi_real k, r0;
} tp_user_harmonic;
int tp_user_harmonic_fn(void *ctx, edmi_real r, edmi_pot_parts *out);
int tp_user_harmonic_dd(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd, edmi_real *dd_d1);

/* A built-in potential written as a user one: its callbacks call edmi_pot_eval and
 * edmi_pot_divdiff on the edmi_potential that ctx points to (a potential whose V' the
 * built-in gives to a few units in the last place, as a user potential must: the harmonic
 * and inverse ones everywhere, the others away from V' = 0). */
int tp_user_builtin_fn(void *ctx, edmi_real r, edmi_pot_parts *out);
int tp_user_builtin_dd(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd, edmi_real *dd_d1);

/* The check (tp_delta_h, tp_h, tp_window_step, tp_rest_delta) evaluates a user potential as
 * the built-in one its callback computes: tp_user_harmonic_fn and tp_user_builtin_fn here,
 * and a test's own callbacks through a map it registers (1 and the built-in in *b, or 0 for
 * a callback it does not know; such a link makes the check return 0). */
typedef int (*tp_user_map)(const edmi_potential *user, edmi_potential *b);
void tp_user_register(tp_user_map map);

/* Build scene s with parameters prm (fallback as prm has it); damper: a damper of c 5 on
 * every link. user_dd: TP_REST_USER's potential with its divided difference (else without:
 * LG falls back to the quotient). *dt its time step. */
edmi_status tp_rest_build(tp_rest s, const edmi_params *prm, int damper, int user_dd,
                          edmi_system *sys, edmi_real *dt);

/* The same question for tp_rest_build(s, prm, damper, user_dd, ...) and tp_rest_run (whose
 * TP_REST_USER reference is the built-in harmonic): the potentials, the dampers, and for LG
 * without user_dd its quotient form (EDMI_WITH_LG_QUOTIENT). prm's scheme is th_has_params'. */
int tp_rest_in(tp_rest s, const edmi_params *prm, int damper, int user_dd);

/* The per-step inequality H_n+1 - H_n <= W + T_n - T_n+1 on two stored states of a system
 * with no field whose links are zero-rest-length harmonic springs (evaluated on p and the
 * link vectors scaled by 2^s, with T and W by 2^2s: H is homogeneous of degree 2 there, and s
 * is chosen to bring the largest to ~1, so nothing underflows that matters), harmonic springs
 * with r0 > 0, neo-Hookean springs and tp_user_harmonic_fn (evaluated unscaled). *excess:
 * dh - w - err in units of 2^-2s (evaluated in tp_q, then rounded to long double: its sign
 * kept), *exponent: -2s. 1 if the inequality holds (decided in tp_q), 0 if it is broken or a
 * term cannot be evaluated. */
int tp_rest_delta(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res,
                  long double *excess, int *exponent);

/* What tp_rest_run measured. */
typedef struct tp_rest_stats {
    long steps;            /* successful steps */
    edmi_status status;    /* EDMI_OK or the first failing step's status (the run stops there) */
    long fail_step;        /* that step's index, -1 */
    edmi_real fail_q[3], fail_p[3], fail_tank; /* body 0 and the tank before it */
    long fallbacks;        /* res.stop == EDMI_STOP_FALLBACK */
    long scaled;           /* res.certificate == EDMI_CERT_SCALED */
    long stops;            /* res.guard_action & EDMI_MOVE_STOP */
    long guarded;          /* res.guard_action != 0 */
    long uncertified;      /* guard on and res.certificate == EDMI_CERT_NONE */
    long violations;       /* tp_rest_delta refused the step */
    long tank_violations;  /* T < 0, T > res.tank_cap or T != res.tank */
    long last_change;      /* the last step that changed a body's q or p (bits), -1: none */
    long double dist;      /* at the end: how far the scene is from rest (link length, or its
                              distance from the rest length) */
    long double tail_dist; /* the largest of it over the last quarter of the steps */
    long double qmax;      /* the largest |coordinate| of a body or anchor over the last
                              quarter: the grid where the scene rests (tp_rest_bound) */
    long double ref_diff;  /* TP_REST_USER: max |q - q_ref| over the run, q_ref the built-in's */
    long double ref_amp;   /* TP_REST_USER: max |q_ref| over the run */
    edmi_status ref_status; /* TP_REST_USER: the reference's status (the run stops if not OK) */
    long ref_guarded;      /* TP_REST_USER: steps the guard changed in the reference */
    long double h0, h_end, h_ref_end; /* TP_REST_USER: H at the start, at the end, and the
                                         reference's at the end (tp_q, own formulas) */
} tp_rest_stats;

/* The bounds the suite (tests/test_guard.c, where they are justified) and the soak assert:
 * a scene at rest is within tp_rest_bound(s) of rest (64 units of the smallest subnormal
 * for the zero-rest-length springs plus 16 eps qmax, 8 units in the last place of the largest
 * coordinate where the scene rests off the origin; 4 eps from the neo-Hookean spring's rest
 * length); the
 * user potential's run after n steps has |H - H_ref| <= TP_USER_DH eps n H0 and
 * |q - q_ref| <= TP_USER_DQ eps n^2 max |q_ref|. */
#define TP_USER_DH 2.0L
#define TP_USER_DQ (1.0L / 4096.0L)
long double tp_rest_bound(tp_rest s, long double qmax);

/* Take n steps of scene s, checking after every step. */
void tp_rest_run(tp_rest s, const edmi_params *prm, int damper, int user_dd, long n,
                 tp_rest_stats *st);

#endif
