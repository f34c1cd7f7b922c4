/* bench_target: what one edmi_step() costs on an emulated Cortex-M (`make bench-target`).
 *
 * 1. Per scene and scheme, each run for BT_MEAN_STEPS steps from its initial state with
 *    edmi_default_params() and one scheme (and PM with the guard off, for the guard's share):
 *      spring: the paper's: m = 10, q0 = (2, 1, 1), p0 = (-30, 15, 45), neo-Hookean c = 1e3,
 *              rbar = 4 to an anchor at the origin, dt = 1e-3;
 *      lj2:    the paper's: m = 1, q = (0, -0.5612, 0) and (0, 0.5612, 0), p = (5, 0, 0) and
 *              (10, 0, 0), Lennard-Jones eps = 100, sigma = 1, dt = 1e-3 (needs 2 bodies);
 *      stiff:  m = 1, q0 = (1, 0, 0), p0 = (0, 300, 100), harmonic k = 1e6, r0 = 0.5 to an
 *              anchor at the origin, dt = 0.1 (omega dt = 100), params.fallback = 1: in float
 *              Newton cycles on some steps and the fallback state is stored;
 *      all10:  10 unit masses, all 45 pairs V = -0.01/r, dt = 0.05 (tests/lib/bench_scenes.h);
 *      solar:  the Sun and nine planets, all 45 pairs of gravity, dt = 5 days
 *              (tests/lib/bench_scenes.h; all10 and solar need 10 bodies and 45 links).
 *    Each scene but stiff also with a velocity-Verlet step of the same system
 *    (bs_verlet_step: one closed-form force evaluation per step), for scale.
 *    Printed: instructions per step, mean over the run and worst single step; Newton
 *    iterations per step, mean and maximum; fallback steps; the stack high-water mark of
 *    edmi_step() (bytes below the caller's stack pointer that the calls wrote, found by
 *    painting the stack before the run and scanning it after).
 * 2. Bounded time at this build's capacity. One residual evaluation per built-in potential
 *    and scheme (1 body, 1 anchor link). Then runs of four scenes in the guarded schemes GE,
 *    PM, PT: a capacity scene that fills this build's capacity (EDMI_MAX_BODIES bodies,
 *    EDMI_MAX_LINKS Lennard-Jones links, EDMI_MAX_DAMPERS dampers, a field, a port force on
 *    every body, every anchor moved every step, fallback on; bt_full) and spring, lj2,
 *    stiff. Before each step the same state is also stepped with l_max = 1, 2 and the
 *    step's iterations - 1 (failing, so nothing changes), with l_max = 1 and the fallback,
 *    with the guard off, and its residual evaluated once: the differences are the pieces of
 *    a step, and their largest values give the bound for params.l_max = L (bt_bound()).
 * 3. Forced worst cases: a state from which Newton does not stop within BT_LMAX_SEARCH
 *    corrections (searched for by running the capacity scene at dt = 0.3 and the stiff
 *    scene), stepped with params.fallback = 1 and l_max = 4, 8, 20: each step must return
 *    EDMI_OK with EDMI_STOP_FALLBACK after exactly l_max corrections; and with
 *    params.substep_levels = 1, 2, 3 (l_max = 4), against the substeps' bound. The program
 *    checks that every step it timed lies within its bound.
 *
 * Counting. QEMU does not model the DWT cycle counter, so the count comes from SysTick
 * under `-icount shift=0`: every guest instruction advances virtual time by 1 ns and SysTick
 * ticks at the board's 25 MHz, i.e. once per 40 instructions. The program calibrates this
 * with a loop of known length and refuses to print numbers when the ratio is not exact
 * (not run under -icount shift=0). These are instruction counts from an emulator, not
 * cycles: a real Cortex-M4F takes 14 cycles for a VDIV.F32 or VSQRT.F32 and more than one
 * for loads, taken branches and multi-register transfers.
 * - Means over a run: the run is timed as a whole and the loop's own cost (calling through
 *   a pointer, counting iterations) is measured with a no-op step and subtracted: exact to
 *   +-0.2 instructions per step.
 * - Single calls (the worst step, the pieces of the bound): one tick is too coarse, so the
 *   call starts on a tick edge (a spin loop waits for one) and the time from its end to the
 *   next edge is counted in iterations of a 4-instruction spin loop (bt_span_raw, with
 *   cortex-m/span.h's tgt_spin). Loops of
 *   known length calibrate the error, which is printed (a few instructions).
 * On real Cortex-M3/M4/M7 silicon (semihosting through a debugger) the DWT cycle counter
 * runs, and the program counts cycles with it instead and says so. */
#include <stddef.h>

#include "edmi.h"
#include "bench_scenes.h"
#include "cortex-m/counter.h"
#include "cortex-m/span.h"
#include "cortex-m/semihost.h"
#include "cortex-m/stack.h"

#define BT_STEPS 200
/* Section 1's means: over this many steps (costs change as a run goes on: the first 200
 * steps of the spring understated the old guard's cost by 18-23 %), timed in chunks of
 * BT_CHUNK steps so that SysTick (24 bits, 671 million instructions) never wraps. */
#define BT_MEAN_STEPS 2000
#define BT_CHUNK 100
/* The calibration loop: BT_CAL_ITERS iterations of SUBS + BNE. */
#define BT_CAL_ITERS 1000000UL
#define BT_CAL_INSNS (2UL * BT_CAL_ITERS)
#define BT_INSNS_PER_TICK TGT_INSNS_PER_TICK /* 25 MHz SysTick, 1 ns per instruction */
/* Single-call calibration: loops of 2n instructions, n = 1..BT_SPAN_CAL. A spread of the
 * measured minus the known count above BT_SPAN_MAX_ERR means the method does not work here. */
#define BT_SPAN_CAL 80UL
#define BT_SPAN_MAX_ERR 8L
/* The search for a state where Newton does not stop: run the scene with this l_max (the
 * largest forced below) and fallback on until a step exhausts it, at most BT_SEARCH_STEPS. */
#define BT_LMAX_SEARCH 20
#define BT_SEARCH_STEPS 400
/* The capacity scene: its normal step and the step of the forced search. */
#define BT_FULL_DT EDMI_R(0.01)
#define BT_FULL_FORCE_DT EDMI_R(0.3)
/* edmi.c's EDMI__MAX_HALVINGS: a Newton correction that leaves the potentials' domain is
 * halved at most this many times, each halving one more residual evaluation. */
#define BT_MAX_HALVINGS 8UL

typedef edmi_status (*bt_step_fn)(edmi_system *, edmi_workspace *, edmi_real,
                                  edmi_step_result *);
typedef edmi_status (*bt_build_fn)(edmi_scheme);

typedef struct bt_run {
    unsigned long ticks; /* counter units (see bt_unit) for the whole run */
    long iterations;     /* Newton corrections, summed */
    int max_iterations;
    int steps_done;
    unsigned long stack; /* bytes below the caller's SP written during the run */
    edmi_status status;  /* first failure, or EDMI_OK */
    long certified_plain; /* steps the guard certified in working precision */
    long guard_steps;     /* steps the guard changed */
} bt_run;

/* The same run again, each step timed on its own. */
typedef struct bt_steps {
    long worst;    /* instructions (or cycles) of the costliest step */
    int worst_at;  /* its index */
    int fallbacks; /* steps that stored the fallback state */
    int halvings;  /* halvings summed */
    edmi_status status;
} bt_steps;

static edmi_system bt_sys, bt_snap, bt_after;
static edmi_workspace bt_work;
/* The variants of a step (section 2) run in their own workspace: nothing they factor is
 * kept for the run's next step, and the factors its steps keep are not theirs. */
static edmi_workspace bt_work_variant;


static edmi_status bt_null_step(edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                edmi_step_result *res)
{
    (void)sys;
    (void)work;
    (void)dt;
    res->iterations = 0;
    return EDMI_OK;
}

/* A velocity-Verlet step of the same system (tests/lib/bench_scenes.h): one force evaluation. */
static edmi_status bt_verlet(edmi_system *sys, edmi_workspace *work, edmi_real dt,
                             edmi_step_result *res)
{
    (void)work;
    bs_verlet_step(sys, dt);
    res->iterations = 0;
    res->stop = EDMI_STOP_CONVERGED;
    return EDMI_OK;
}

/* All steppers are called through this pointer, so their call sequences are identical. */
static bt_step_fn volatile bt_step;

/* The counter: DWT CYCCNT in cycles on silicon, else SysTick ticks of 40 instructions. */
static int bt_cycles;
static unsigned long bt_unit = BT_INSNS_PER_TICK;

static unsigned long bt_now(void) { return bt_cycles ? tgt_cyccnt() : tgt_ticks(); }

/* Scenes that move anchors do it before every step (bt_full). */
static void (*bt_before_step)(void);

static void bt_measure(int steps, edmi_real dt, bt_run *out)
{
    edmi_step_result res;
    unsigned long sp0, t0, t1;
    int k;
    out->iterations = 0;
    out->max_iterations = 0;
    out->status = EDMI_OK;
    out->steps_done = 0;
    int c, wrapped = 0;
    tgt_stack_paint();
    sp0 = tgt_sp();
    out->ticks = 0;
    out->certified_plain = out->guard_steps = 0;
    for (k = 0; k < steps && out->status == EDMI_OK;) {
        tgt_ticks_start();
        t0 = bt_now();
        for (c = 0; c < BT_CHUNK && k < steps; c++, k++) {
            edmi_status st = bt_step(&bt_sys, &bt_work, dt, &res);
            if (st != EDMI_OK) {
                out->status = st;
                break;
            }
            out->iterations += res.iterations;
            if (res.iterations > out->max_iterations)
                out->max_iterations = res.iterations;
            out->certified_plain += res.certificate == EDMI_CERT_PLAIN;
            out->guard_steps += res.guard_action != 0U;
        }
        t1 = bt_now();
        wrapped |= !bt_cycles && tgt_ticks_wrapped();
        out->ticks += t1 - t0;
    }
    out->steps_done = k;
    if (wrapped)
        out->ticks = 0UL;
    out->stack = sp0 - tgt_stack_lowest();
}

/* ---- single calls ------------------------------------------------------------------------ */


/* What a timed call does; its arguments are globals so every call has the same sequence. */
typedef edmi_status (*bt_call_fn)(void);
static bt_call_fn volatile bt_call;
static edmi_real bt_dt;
static edmi_step_result bt_res;
static edmi_real bt_q1[EDMI_MAX_BODIES][3], bt_p1[EDMI_MAX_BODIES][3];
static edmi_real bt_rq[EDMI_MAX_BODIES][3], bt_rp[EDMI_MAX_BODIES][3];
static unsigned long bt_loop_n;

static edmi_status bt_call_loop(void)
{
    tgt_cal_loop(bt_loop_n);
    return EDMI_OK;
}
/* A step through bt_step: with bt_null_step it is the no-op whose count is subtracted. */
static edmi_workspace *bt_work_now = &bt_work; /* the workspace bt_call_step uses */
static edmi_status bt_call_step(void) { return bt_step(&bt_sys, bt_work_now, bt_dt, &bt_res); }
/* edmi_residual: validation and the start-of-step link set-up, then one evaluation of the
 * residual and the links' tangent blocks; with rq == NULL it stops after the first part. */
static edmi_status bt_call_residual(void)
{
    return edmi_residual(&bt_sys, &bt_work, bt_dt, (const edmi_real (*)[3])bt_q1,
                         (const edmi_real (*)[3])bt_p1, bt_rq, bt_rp, NULL);
}
static edmi_status bt_call_residual_setup(void)
{
    return edmi_residual(&bt_sys, &bt_work, bt_dt, (const edmi_real (*)[3])bt_q1,
                         (const edmi_real (*)[3])bt_p1, NULL, bt_rp, NULL);
}

/* Raw count of one call of bt_call: from the tick edge it starts on to the next edge after
 * it returns, minus the spin up to that edge. */
static unsigned long bt_span_raw(edmi_status *st)
{
    unsigned long a, b, n;
    if (bt_cycles) {
        a = tgt_cyccnt();
        *st = bt_call();
        b = tgt_cyccnt();
        return b - a;
    }
    (void)tgt_spin(&a);
    *st = bt_call();
    n = tgt_spin(&b);
    return ((a - b) & TGT_SYST_MASK) * TGT_INSNS_PER_TICK - n * TGT_SPIN_INSNS;
}

static unsigned long bt_span_null; /* raw count of a no-op step */
static long bt_span_err;           /* +- this many instructions (calibrated) */

/* Instructions (or cycles) of one call of f. */
static long bt_span(bt_call_fn f, edmi_status *st)
{
    bt_call = f;
    return (long)bt_span_raw(st) - (long)bt_span_null;
}

/* One step of bt_sys by bt_timed (edmi_step unless a table row says otherwise), timed. */
static bt_step_fn bt_timed = edmi_step;

static long bt_time_step(edmi_real dt, edmi_status *st)
{
    bt_dt = dt;
    bt_step = bt_timed;
    return bt_span(bt_call_step, st);
}

/* Calibrate single-call counts with loops of 2n instructions; 0 if they do not work. */
static int bt_span_calibrate(void)
{
    long lo = 0, hi = 0, d;
    unsigned long n;
    edmi_status st;
    tgt_ticks_start();
    bt_call = bt_call_step;
    bt_step = bt_null_step;
    bt_span_null = bt_span_raw(&st);
    for (n = 1; n <= BT_SPAN_CAL; n++) {
        bt_loop_n = n;
        d = bt_span(bt_call_loop, &st) - (long)(2UL * n);
        if (n == 1 || d < lo)
            lo = d;
        if (n == 1 || d > hi)
            hi = d;
    }
    bt_span_err = hi - lo;
    return bt_span_err <= BT_SPAN_MAX_ERR;
}

/* ---- output ------------------------------------------------------------------------------ */

/* v / d with `dec` decimals, rounded half up (v, d > 0). */
static void bt_put_ratio(unsigned long long v, unsigned long long d, int dec)
{
    unsigned long long scale = 1, x;
    int i;
    for (i = 0; i < dec; i++)
        scale *= 10ULL;
    x = (v * scale + d / 2ULL) / d;
    tgt_put_uint((unsigned long)(x / scale));
    if (dec > 0) {
        unsigned long long frac = x % scale;
        tgt_putchar('.');
        for (i = dec - 1; i >= 0; i--) {
            unsigned long long p = 1;
            int j;
            for (j = 0; j < i; j++)
                p *= 10ULL;
            tgt_putchar('0' + (int)((frac / p) % 10ULL));
        }
    }
}

static void bt_put_long(long v)
{
    if (v < 0) {
        tgt_putchar('-');
        tgt_put_uint((unsigned long)-v);
    } else {
        tgt_put_uint((unsigned long)v);
    }
}

static const char *bt_unit_name(void) { return bt_cycles ? "cycles" : "instructions"; }

static const char *const bt_scheme_name[] = {"MP", "LG", "GE", "PM", "PT"};
#define BT_PM_OFF (EDMI_SCHEME_PT + 1) /* section 1's row: PM with the guard off */

/* ---- scenes ------------------------------------------------------------------------------ */

static edmi_status bt_spring(edmi_scheme scheme) { return bs_spring(&bt_sys, scheme); }

static edmi_status bt_lj2(edmi_scheme scheme) { return bs_lj2(&bt_sys, scheme); }

static edmi_status bt_all10(edmi_scheme scheme) { return bs_pairs(&bt_sys, 10, scheme); }

static edmi_status bt_solar(edmi_scheme scheme) { return bs_solar(&bt_sys, scheme); }

static edmi_status bt_stiff(edmi_scheme scheme)
{
    static const edmi_real q[3] = {EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.0)};
    static const edmi_real p[3] = {EDMI_R(0.0), EDMI_R(300.0), EDMI_R(100.0)};
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot = edmi_pot_harmonic(EDMI_R(1e6), EDMI_R(0.5));
    edmi_params prm = edmi_default_params();
    edmi_status s;
    prm.scheme = scheme;
    prm.fallback = 1;
    s = edmi_init(&bt_sys, &prm);
    if (s == EDMI_OK)
        s = edmi_add_body(&bt_sys, EDMI_R(1.0), q, p, NULL);
    if (s == EDMI_OK)
        s = edmi_add_anchor(&bt_sys, 0, origin, &pot, NULL);
    return s;
}

/* A deterministic number in [-1, 1) (32-bit LCG). */
static unsigned long bt_seed;

static edmi_real bt_rand(void)
{
    bt_seed = (bt_seed * 1664525UL + 1013904223UL) & 0xffffffffUL;
    return (edmi_real)((long)(bt_seed >> 8) - 0x800000L) / EDMI_R(8388608.0);
}

/* Every anchor moves 1e-4 along x per step (the moving-anchor path of a haptic loop). */
static void bt_full_move(void)
{
    int j;
    for (j = 0; j < bt_sys.n_links; j++)
        if (bt_sys.link[j].b == EDMI_ANCHOR) {
            edmi_real x[3];
            x[0] = bt_sys.link[j].anchor[0] + EDMI_R(1e-4);
            x[1] = bt_sys.link[j].anchor[1];
            x[2] = bt_sys.link[j].anchor[2];
            (void)edmi_move_anchor(&bt_sys, j, x);
        }
}

/* The capacity scene: EDMI_MAX_BODIES bodies of mass 1 in a zig-zag row 1.12 apart (the
 * Lennard-Jones minimum of eps = 100, sigma = 1), small random momenta; EDMI_MAX_LINKS
 * Lennard-Jones links: a pair from the first to the last body (so the Newton matrix's band
 * is the whole matrix: the dense solve), pairs of neighbours, next neighbours and so on,
 * and the last eighth (all, for one body) anchor links to points 1.1 below a body;
 * EDMI_MAX_DAMPERS dampers c = 0.5 on the first links; a field; a port force on every
 * body; every anchor moved before every step. */
static edmi_status bt_full(edmi_scheme scheme)
{
    static const edmi_real g[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-9.81)};
    static const edmi_real f[3] = {EDMI_R(0.5), EDMI_R(-0.25), EDMI_R(1.0)};
    edmi_potential pot = edmi_pot_lj(EDMI_R(100.0), EDMI_R(1.0));
    edmi_params prm = edmi_default_params();
    int n = EDMI_MAX_BODIES, l = EDMI_MAX_LINKS, n_anchor, i, gap, links = 0;
    edmi_status s;
    prm.scheme = scheme;
    prm.fallback = 1;
    bt_seed = 7UL;
    s = edmi_init(&bt_sys, &prm);
    for (i = 0; i < n && s == EDMI_OK; i++) {
        edmi_real q[3], p[3];
        q[0] = EDMI_R(1.12) * (edmi_real)i;
        q[1] = EDMI_R(0.15) * (edmi_real)(i % 2);
        q[2] = EDMI_R(0.1) * (edmi_real)(i % 3);
        p[0] = bt_rand();
        p[1] = bt_rand();
        p[2] = bt_rand();
        s = edmi_add_body(&bt_sys, EDMI_R(1.0), q, p, NULL);
    }
    n_anchor = n == 1 ? l : (l / 8 > 0 ? l / 8 : 1);
    if (n > 1 && links < l - n_anchor && s == EDMI_OK) {
        s = edmi_add_pair(&bt_sys, 0, n - 1, &pot, NULL);
        links++;
    }
    for (gap = 1; gap < n - 1 && links < l - n_anchor && s == EDMI_OK; gap++)
        for (i = 0; i + gap < n && links < l - n_anchor && s == EDMI_OK; i++, links++)
            s = edmi_add_pair(&bt_sys, i, i + gap, &pot, NULL);
    for (i = 0; links < l && s == EDMI_OK; i++, links++) {
        const edmi_real *q = bt_sys.body[i % n].q;
        edmi_real x[3];
        x[0] = q[0];
        x[1] = q[1] - EDMI_R(1.1);
        x[2] = q[2];
        s = edmi_add_anchor(&bt_sys, i % n, x, &pot, NULL);
    }
    for (i = 0; i < EDMI_MAX_DAMPERS && s == EDMI_OK; i++)
        s = edmi_add_damper(&bt_sys, i % bt_sys.n_links, EDMI_R(0.5), NULL);
    if (s == EDMI_OK)
        s = edmi_set_field(&bt_sys, g);
    for (i = 0; i < n && s == EDMI_OK; i++)
        s = edmi_set_force(&bt_sys, i, f);
    return s;
}

/* ---- 1. per scene and scheme ------------------------------------------------------------- */

/* The run again, each step timed on its own. */
static void bt_measure_steps(int steps, edmi_real dt, bt_steps *out)
{
    int k;
    out->worst = 0;
    out->worst_at = 0;
    out->fallbacks = 0;
    out->halvings = 0;
    out->status = EDMI_OK;
    tgt_ticks_start();
    for (k = 0; k < steps; k++) {
        edmi_status st;
        long c;
        if (bt_before_step)
            bt_before_step();
        c = bt_time_step(dt, &st);
        if (st != EDMI_OK) {
            out->status = st;
            return;
        }
        if (c > out->worst) {
            out->worst = c;
            out->worst_at = k;
        }
        out->fallbacks += bt_res.stop == EDMI_STOP_FALLBACK;
        out->halvings += bt_res.halvings;
    }
}

static int bt_scene_table(void)
{
    static const char *const scene_name[] = {"spring", "lj2", "stiff", "all10", "solar"};
    static const bt_build_fn build[] = {bt_spring, bt_lj2, bt_stiff, bt_all10, bt_solar};
    static const int bodies[] = {1, 2, 1, 10, 10}, links[] = {1, 1, 1, 45, 45};
    static const int verlet[] = {1, 1, 0, 1, 1}; /* stiff: omega dt = 100, Verlet blows up */
    const edmi_real dts[] = {EDMI_R(1e-3), EDMI_R(1e-3), EDMI_R(0.1), BS_PAIRS_DT, BS_SOLAR_DT};
    bt_run base, run;
    bt_steps each;
    int scene, scheme, failed = 0;
    each.status = EDMI_OK;
    each.worst = 0;
    each.fallbacks = 0;

    /* Loop overhead: the same loop around a no-op step. */
    if (bt_spring(EDMI_SCHEME_MP) != EDMI_OK)
        tgt_exit(TGT_EXIT_FAILED);
    bt_step = bt_null_step;
    bt_measure(BT_MEAN_STEPS, EDMI_R(1e-3), &base);
    tgt_puts("loop overhead of the mean: ");
    bt_put_ratio((unsigned long long)base.ticks * bt_unit, BT_MEAN_STEPS, 1);
    tgt_puts(" ");
    tgt_puts(bt_unit_name());
    tgt_puts(" per step (subtracted)\n\n");

    tgt_puts(bt_cycles ? "| scene | scheme | cycles/step: mean | worst step | Newton iterations/step "
                         "(max) | cycles/iteration | fallback steps | stack high-water (bytes) "
                         "| guard: plain certificates, steps changed |\n"
                       : "| scene | scheme | instructions/step: mean | worst step | Newton "
                         "iterations/step (max) | instructions/iteration | fallback steps | "
                         "stack high-water (bytes) | guard: plain certificates, steps changed |\n");
    tgt_puts("|---|---|---:|---:|---:|---:|---:|---:|---|\n");
    /* the five schemes, PM with the guard off (BT_PM_OFF), then Verlet */
    for (scene = 0; scene < 5; scene++)
        for (scheme = EDMI_SCHEME_MP; scheme <= BT_PM_OFF + verlet[scene]; scheme++) {
            unsigned long long insns;
            edmi_status s = EDMI_OK;
            int vv = scheme > BT_PM_OFF, off = scheme == BT_PM_OFF;
            edmi_scheme sch = vv ? EDMI_SCHEME_MP : off ? EDMI_SCHEME_PM : (edmi_scheme)scheme;
            tgt_puts("| ");
            tgt_puts(scene_name[scene]);
            tgt_puts(" | ");
            tgt_puts(vv ? "Verlet" : off ? "PM, guard off" : bt_scheme_name[scheme]);
            tgt_puts(" | ");
            if (bodies[scene] > EDMI_MAX_BODIES || links[scene] > EDMI_MAX_LINKS) {
                tgt_puts("n/a: needs EDMI_MAX_BODIES >= ");
                tgt_put_uint((unsigned long)bodies[scene]);
                tgt_puts(", EDMI_MAX_LINKS >= ");
                tgt_put_uint((unsigned long)links[scene]);
                tgt_puts(" | | | | | | |\n");
                continue;
            }
            bt_step = vv ? bt_verlet : edmi_step;
            s = build[scene](sch);
            if (off)
                bt_sys.params.guard = EDMI_GUARD_OFF;
            if (s == EDMI_OK) {
                bs_verlet_start(&bt_sys);
                bt_measure(BT_MEAN_STEPS, dts[scene], &run);
            }
            if (s == EDMI_OK && run.status == EDMI_OK && run.ticks != 0) {
                s = build[scene](sch);
                if (off)
                    bt_sys.params.guard = EDMI_GUARD_OFF;
                bs_verlet_start(&bt_sys);
                bt_timed = vv ? bt_verlet : edmi_step;
                if (s == EDMI_OK)
                    bt_measure_steps(BT_STEPS, dts[scene], &each);
                bt_timed = edmi_step;
            }
            if (s != EDMI_OK || run.status != EDMI_OK || run.ticks == 0 ||
                each.status != EDMI_OK) {
                tgt_puts("FAILED: ");
                tgt_puts(edmi_status_name(s != EDMI_OK            ? s
                                          : run.status != EDMI_OK ? run.status
                                                                  : each.status));
                tgt_puts(" at step ");
                tgt_put_uint((unsigned long)run.steps_done);
                tgt_puts(" | | | | | | |\n");
                failed++;
                continue;
            }
            insns = (unsigned long long)(run.ticks - base.ticks) * bt_unit;
            bt_put_ratio(insns, BT_MEAN_STEPS, 0);
            tgt_puts(" | ");
            bt_put_long(each.worst);
            tgt_puts(" | ");
            if (vv) {
                tgt_puts("- | - | ");
            } else {
                bt_put_ratio((unsigned long long)run.iterations, BT_MEAN_STEPS, 2);
                tgt_puts(" (");
                tgt_put_uint((unsigned long)run.max_iterations);
                tgt_puts(") | ");
                bt_put_ratio(insns, (unsigned long long)run.iterations, 0);
                tgt_puts(" | ");
            }
            tgt_put_uint((unsigned long)each.fallbacks);
            tgt_puts(" | ");
            tgt_put_uint(run.stack);
            tgt_puts(" | ");
            if (vv || off || scheme <= EDMI_SCHEME_LG) {
                tgt_puts("-");
            } else {
                tgt_put_uint((unsigned long)run.certified_plain);
                tgt_puts(", ");
                tgt_put_uint((unsigned long)run.guard_steps);
            }
            tgt_puts(" |\n");
        }
    tgt_puts("\n(mean: the whole run timed over ");
    tgt_put_uint(BT_MEAN_STEPS);
    tgt_puts(" steps, exact to +-0.2 per step; worst step: the first ");
    tgt_put_uint(BT_STEPS);
    tgt_puts(" steps, each timed on its own, +-");
    bt_put_long(bt_span_err);
    tgt_puts("; ");
    tgt_puts(bt_unit_name());
    tgt_puts("/iteration = mean divided by Newton iterations/step, set-up and guard "
             "included)\n");
    return failed;
}

/* ---- 2. the pieces of the bound ---------------------------------------------------------- */

static long bt_eval_cost(edmi_real dt, edmi_status *st);

/* One residual evaluation per built-in potential and scheme: one body (m = 1,
 * q = (0.3, 1.05, 0.2), p = (1, 0.5, -0.2)) tied to the origin, trial state q + dt p, p,
 * dt = 0.01. Harmonic k = 1e4, r0 = 1; quartic k = 1e4, L = 1; neo-Hooke c = 1e4, rbar = 1;
 * Lennard-Jones eps = 100, sigma = 1; inverse k = -10. */
static int bt_eval_table(void)
{
    static const char *const pot_name[] = {"harmonic", "quartic", "neo-Hooke", "Lennard-Jones",
                                           "inverse"};
    static const edmi_real q[3] = {EDMI_R(0.3), EDMI_R(1.05), EDMI_R(0.2)};
    static const edmi_real p[3] = {EDMI_R(1.0), EDMI_R(0.5), EDMI_R(-0.2)};
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    int kind, scheme, failed = 0;
    tgt_puts("One residual evaluation with its tangent block, 1 body + 1 anchor link (");
    tgt_puts(bt_unit_name());
    tgt_puts("):\n\n| potential | MP | LG | GE | PM | PT |\n|---|---:|---:|---:|---:|---:|\n");
    tgt_ticks_start();
    for (kind = 0; kind < 5; kind++) {
        edmi_potential pot;
        switch (kind) {
        case 0:
            pot = edmi_pot_harmonic(EDMI_R(1e4), EDMI_R(1.0));
            break;
        case 1:
            pot = edmi_pot_quartic(EDMI_R(1e4), EDMI_R(1.0));
            break;
        case 2:
            pot = edmi_pot_neo_hooke(EDMI_R(1e4), EDMI_R(1.0));
            break;
        case 3:
            pot = edmi_pot_lj(EDMI_R(100.0), EDMI_R(1.0));
            break;
        default:
            pot = edmi_pot_inverse(EDMI_R(-10.0));
            break;
        }
        tgt_puts("| ");
        tgt_puts(pot_name[kind]);
        tgt_puts(" |");
        for (scheme = EDMI_SCHEME_MP; scheme <= EDMI_SCHEME_PT; scheme++) {
            edmi_params prm = edmi_default_params();
            edmi_status st;
            long e = 0;
            prm.scheme = (edmi_scheme)scheme;
            st = edmi_init(&bt_sys, &prm);
            if (st == EDMI_OK)
                st = edmi_add_body(&bt_sys, EDMI_R(1.0), q, p, NULL);
            if (st == EDMI_OK)
                st = edmi_add_anchor(&bt_sys, 0, origin, &pot, NULL);
            if (st == EDMI_OK)
                e = bt_eval_cost(EDMI_R(0.01), &st);
            tgt_puts(" ");
            if (st == EDMI_OK) {
                bt_put_long(e);
            } else {
                tgt_puts("FAILED: ");
                tgt_puts(edmi_status_name(st));
                failed++;
            }
            tgt_puts(" |");
        }
        tgt_puts("\n");
    }
    return failed;
}

/* The largest observed value of one piece of a step, and where it was observed. */
typedef struct bt_piece {
    long max;
    int n;             /* samples */
    const char *scene; /* scene and scheme of the largest */
    int scheme;
} bt_piece;

/* The pieces of a step (see bt_bound()). */
typedef struct bt_pieces {
    bt_piece first;    /* a step failing after 1 correction (l_max = 1, no fallback):
                          validation, link set-up, predictor evaluation, 1 correction, tests */
    bt_piece iter;     /* one more correction: F(l_max = k+1) - F(l_max = k), both failing */
    bt_piece eval;     /* one residual evaluation with the tangent blocks (edmi_residual
                          minus its validation and link set-up) */
    bt_piece guard;    /* energy balance + guard: T(guard on) - T(guard off), same state */
    bt_piece last;     /* a step's last correction and everything after Newton (energy
                          balance, guard, commit): T(step) - F(l_max = its iterations - 1) */
    bt_piece fallback; /* fallback state + commit: F(l_max = 1, fallback) - F(l_max = 1) */
} bt_pieces;

static const char *bt_scene_now; /* the scene the pieces are being taken from */
static int bt_scheme_now;

static void bt_max(bt_piece *p, long v)
{
    if (p->n == 0 || v > p->max) {
        p->max = v;
        p->scene = bt_scene_now;
        p->scheme = bt_scheme_now;
    }
    p->n++;
}

/* Step bt_sys (a copy of bt_snap) with l_max, fallback and guard changed; the state is
 * restored to bt_snap. */
static int bt_levels; /* params.substep_levels of bt_variant's steps (0 but in section 3) */

static long bt_variant(edmi_real dt, int l_max, int fallback, edmi_guard_mode guard,
                       edmi_status *st)
{
    long c;
    bt_sys = bt_snap;
    bt_sys.params.substep_levels = bt_levels;
    bt_sys.params.l_max = l_max;
    bt_sys.params.fallback = fallback;
    bt_sys.params.guard = guard;
    bt_work_now = &bt_work_variant;
    c = bt_time_step(dt, st);
    bt_work_now = &bt_work;
    bt_sys = bt_snap;
    return c;
}

/* One residual evaluation at the trial state q + dt p/m, p. */
static long bt_eval_cost(edmi_real dt, edmi_status *st)
{
    edmi_status st2;
    long full, setup;
    int a, i;
    for (a = 0; a < bt_sys.n_bodies; a++)
        for (i = 0; i < 3; i++) {
            bt_q1[a][i] = bt_sys.body[a].q[i] + dt / bt_sys.body[a].m * bt_sys.body[a].p[i];
            bt_p1[a][i] = bt_sys.body[a].p[i];
        }
    bt_dt = dt;
    full = bt_span(bt_call_residual, st);
    setup = bt_span(bt_call_residual_setup, &st2);
    if (*st == EDMI_OK && st2 != EDMI_ERR_NULL)
        *st = st2;
    return full - setup;
}

/* Normal steps of one scene: mean and worst, Newton iterations. */
typedef struct bt_normal {
    long long sum;
    long worst;
    int iterations_max;
    long iterations;
    int fallbacks;
    int halvings;
} bt_normal;

/* Run a scene for BT_STEPS steps; before each step, time its variants from the same state
 * and add them to the pieces. 0 if a step failed. */
static int bt_pieces_run(bt_pieces *pc, const char *name, bt_build_fn build, edmi_scheme scheme,
                         edmi_real dt, void (*move)(void), bt_normal *nm)
{
    int k;
    edmi_status st;
    bt_scene_now = name;
    bt_scheme_now = (int)scheme;
    nm->sum = 0;
    nm->worst = 0;
    nm->iterations_max = 0;
    nm->iterations = 0;
    nm->fallbacks = 0;
    nm->halvings = 0;
    if (build(scheme) != EDMI_OK)
        return 0;
    tgt_ticks_start();
    for (k = 0; k < BT_STEPS; k++) {
        long t_on, t_off, f1, f2, fl, fb, e;
        int l, fell_back;
        if (move)
            move();
        bt_snap = bt_sys;
        t_on = bt_time_step(dt, &st);
        if (st != EDMI_OK)
            return 0;
        l = bt_res.iterations;
        fell_back = bt_res.stop == EDMI_STOP_FALLBACK;
        bt_after = bt_sys;
        nm->sum += t_on;
        if (t_on > nm->worst)
            nm->worst = t_on;
        if (l > nm->iterations_max)
            nm->iterations_max = l;
        nm->iterations += l;
        nm->fallbacks += fell_back;
        nm->halvings += bt_res.halvings;
        t_off = bt_variant(dt, bt_snap.params.l_max, bt_snap.params.fallback, EDMI_GUARD_OFF,
                           &st);
        if (!fell_back && st == EDMI_OK && bt_res.stop != EDMI_STOP_FALLBACK &&
            bt_res.iterations == l)
            bt_max(&pc->guard, t_on - t_off);
        f1 = bt_variant(dt, 1, 0, bt_snap.params.guard, &st);
        if (st == EDMI_ERR_NO_CONVERGENCE) {
            bt_max(&pc->first, f1);
            fb = bt_variant(dt, 1, 1, bt_snap.params.guard, &st);
            if (st == EDMI_OK && bt_res.stop == EDMI_STOP_FALLBACK)
                bt_max(&pc->fallback, fb - f1);
            if (l >= 3) {
                f2 = bt_variant(dt, 2, 0, bt_snap.params.guard, &st);
                if (st == EDMI_ERR_NO_CONVERGENCE && bt_res.halvings == 0)
                    bt_max(&pc->iter, f2 - f1);
            }
            if (l >= 2 && !fell_back) {
                fl = bt_variant(dt, l - 1, 0, bt_snap.params.guard, &st);
                if (st == EDMI_ERR_NO_CONVERGENCE)
                    bt_max(&pc->last, t_on - fl);
            }
        }
        e = bt_eval_cost(dt, &st);
        if (st == EDMI_OK)
            bt_max(&pc->eval, e);
        bt_sys = bt_after;
    }
    return 1;
}

/* ---- 3. forced worst cases --------------------------------------------------------------- */

/* Search: step the scene (PM, fallback on, l_max = BT_LMAX_SEARCH) until a step exhausts
 * l_max; bt_snap is the state before it. Newton's iterates do not depend on l_max, so from
 * there every smaller l_max is exhausted too. Time F(l_max = k) for k = 1..BT_LMAX_SEARCH
 * without fallback (one correction at a time, into pc->iter), then the forced steps with
 * fallback at l_max = 4, 8, BT_LMAX_SEARCH into forced[] (-1: not forced). */
/* Forced steps with substeps (section 3): from the forced state, PM, fallback on,
 * l_max = BT_SUB_LMAX, substep_levels = 1..BT_SUB_LEVELS: instructions, substeps stored,
 * fallbacks among them, Newton corrections; -1: not forced. */
#define BT_SUB_LEVELS 3
#define BT_SUB_LMAX 4
typedef struct bt_sub {
    long insns[BT_SUB_LEVELS];
    int substeps[BT_SUB_LEVELS], fallbacks[BT_SUB_LEVELS], iterations[BT_SUB_LEVELS];
} bt_sub;
static bt_sub bt_sub_full, bt_sub_stiff;

static int bt_forced(const char *name, bt_build_fn build, edmi_real dt, void (*move)(void),
                     bt_pieces *pc, long forced[3], bt_sub *sub)
{
    static const int lmax[3] = {4, 8, BT_LMAX_SEARCH};
    edmi_status st;
    long prev = 0;
    int k, found = -1, prev_ok = 0;
    forced[0] = forced[1] = forced[2] = -1;
    for (k = 0; k < BT_SUB_LEVELS; k++)
        sub->insns[k] = -1;
    bt_scene_now = name;
    bt_scheme_now = (int)EDMI_SCHEME_PM;
    tgt_puts("| ");
    tgt_puts(name);
    tgt_puts(" | ");
    if (build(EDMI_SCHEME_PM) != EDMI_OK) {
        tgt_puts("FAILED: the scene does not build | | | | |\n");
        return 0;
    }
    tgt_ticks_start();
    for (k = 0; k < BT_SEARCH_STEPS && found < 0; k++) {
        if (move)
            move();
        bt_snap = bt_sys;
        bt_sys.params.l_max = BT_LMAX_SEARCH;
        bt_sys.params.fallback = 1;
        bt_dt = dt;
        st = bt_call_step();
        if (st != EDMI_OK) {
            tgt_puts("FAILED: ");
            tgt_puts(edmi_status_name(st));
            tgt_puts(" | | | | |\n");
            return 0;
        }
        if (bt_res.stop == EDMI_STOP_FALLBACK && bt_res.iterations == BT_LMAX_SEARCH)
            found = k;
    }
    if (found < 0) {
        tgt_puts("Newton stopped within l_max = ");
        tgt_put_uint(BT_LMAX_SEARCH);
        tgt_puts(" on each of ");
        tgt_put_uint(BT_SEARCH_STEPS);
        tgt_puts(" steps: nothing to force | | | | |\n");
        return 1;
    }
    tgt_puts("before step ");
    tgt_put_uint((unsigned long)found);
    for (k = 1; k <= BT_LMAX_SEARCH; k++) {
        long c = bt_variant(dt, k, 0, EDMI_GUARD_AUTO, &st);
        int ok = st == EDMI_ERR_NO_CONVERGENCE && bt_res.iterations == k && bt_res.halvings == 0;
        if (ok && prev_ok)
            bt_max(&pc->iter, c - prev);
        prev = c;
        prev_ok = ok;
    }
    tgt_puts(" |");
    for (k = 0; k < 3; k++) {
        edmi_status st_nf;
        long nf = bt_variant(dt, lmax[k], 0, EDMI_GUARD_AUTO, &st_nf);
        long c = bt_variant(dt, lmax[k], 1, EDMI_GUARD_AUTO, &st);
        tgt_puts(" ");
        bt_put_long(c);
        if (st == EDMI_OK && bt_res.stop == EDMI_STOP_FALLBACK && bt_res.iterations == lmax[k] &&
            bt_res.halvings == 0) {
            forced[k] = c;
            if (st_nf == EDMI_ERR_NO_CONVERGENCE) /* the fallback from Newton's last iterate */
                bt_max(&pc->fallback, c - nf);
        } else {
            tgt_puts(" (FAILED: ");
            tgt_puts(edmi_status_name(st));
            tgt_puts(st == EDMI_OK ? ", not a fallback after l_max corrections)" : ")");
        }
        tgt_puts(" |");
    }
    tgt_puts(forced[0] >= 0 && forced[1] >= 0 && forced[2] >= 0
                 ? " EDMI_OK, EDMI_STOP_FALLBACK, iterations = l_max, 0 halvings |\n"
                 : " |\n");
    for (k = 0; k < BT_SUB_LEVELS; k++) {
        bt_levels = k + 1;
        sub->insns[k] = bt_variant(dt, BT_SUB_LMAX, 1, EDMI_GUARD_AUTO, &st);
        sub->substeps[k] = bt_res.substeps;
        sub->fallbacks[k] = bt_res.fallbacks;
        sub->iterations[k] = bt_res.iterations;
        if (st != EDMI_OK)
            sub->insns[k] = -1;
    }
    bt_levels = 0;
    return forced[0] >= 0 && forced[1] >= 0 && forced[2] >= 0;
}

/* ---- the bound ----------------------------------------------------------------------------- */

/* A step with l_max = L >= 2 takes: validation, link set-up, the predictor's evaluation,
 * L corrections (each a linear solve and an evaluation), each possibly halved
 * BT_MAX_HALVINGS times (one evaluation each: 1 + L (1 + 8) evaluations in all), then
 * either the fallback (Newton failed) or the energy balance and the guard, and if the
 * guard cannot certify, the fallback. Before them, where the system's last step kept its
 * factors (edmi_workspace), one chord correction from them, never halved, which, where it
 * does not halve the residual, is undone by evaluating the predictor again: a linear solve
 * without its factorisation and two evaluations, within kept = iter + eval. With the
 * observed maxima (the pieces are timed in a workspace that keeps nothing for them):
 *   T(L) <= first + (L - 2) iter + last + 8 L halving + fallback + kept,
 * where `first` holds the first correction, `last` the L-th with everything after Newton
 * (guard, commit) and `fallback` the fallback state and a second commit. A halving moves
 * the iterate and evaluates the residual: a subset of a correction (halving <= iter, the
 * bound), or about one evaluation (halving ~ eval + the move, the estimate). */
static unsigned long bt_bound(const bt_pieces *pc, unsigned long L, long halving)
{
    return (unsigned long)pc->first.max + (L - 2UL) * (unsigned long)pc->iter.max +
           (unsigned long)pc->last.max + L * BT_MAX_HALVINGS * (unsigned long)halving +
           (unsigned long)pc->fallback.max + (unsigned long)pc->iter.max +
           (unsigned long)pc->eval.max;
}

static void bt_put_piece(const char *what, const bt_piece *p, const char *how)
{
    tgt_puts("| ");
    tgt_puts(what);
    tgt_puts(" | ");
    if (p->n == 0) {
        tgt_puts("not observed | 0 | |");
    } else {
        bt_put_long(p->max);
        tgt_puts(" | ");
        tgt_put_uint((unsigned long)p->n);
        tgt_puts(" | ");
        tgt_puts(p->scene);
        tgt_puts(", ");
        tgt_puts(bt_scheme_name[p->scheme]);
        tgt_puts(" |");
    }
    tgt_puts(" ");
    tgt_puts(how);
    tgt_puts(" |\n");
}

/* Scenes the pieces are taken from, in the energy-decaying schemes (guard on). */
typedef struct bt_piece_scene {
    const char *name;
    bt_build_fn build;
    edmi_real dt;
    void (*move)(void);
    int bodies;
} bt_piece_scene;

static int bt_bound_section(void)
{
    static const unsigned long lmax[3] = {4UL, 8UL, (unsigned long)BT_LMAX_SEARCH};
    static const edmi_scheme guarded[3] = {EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    static bt_pieces pc;
    const bt_piece_scene scenes[4] = {{"capacity", bt_full, BT_FULL_DT, bt_full_move, 1},
                                      {"spring", bt_spring, EDMI_R(1e-3), NULL, 1},
                                      {"lj2", bt_lj2, EDMI_R(1e-3), NULL, 2},
                                      {"stiff", bt_stiff, EDMI_R(0.1), NULL, 1}};
    long forced_full[3], forced_stiff[3], worst = 0;
    int ok = 1, k, s, failed, halvings = 0, l_max = edmi_default_params().l_max;

    tgt_puts("\n## Bounded time at this build's capacity: EDMI_MAX_BODIES = ");
    tgt_put_uint(EDMI_MAX_BODIES);
    tgt_puts(", EDMI_MAX_LINKS = ");
    tgt_put_uint(EDMI_MAX_LINKS);
    tgt_puts(", EDMI_MAX_DAMPERS = ");
    tgt_put_uint(EDMI_MAX_DAMPERS);
    tgt_puts("\n\n");
    failed = bt_eval_table();

    tgt_puts("\nThe capacity scene fills the capacity: every body, link and damper in use "
             "(Lennard-Jones links, a first-to-last pair making the Newton matrix dense), a "
             "field, port forces, every anchor moving, fallback on, dt = 0.01. Each step of "
             "each run below is also timed from the same state with l_max = 1, 2 and its "
             "iterations - 1 (no fallback), with l_max = 1 and the fallback, and with the "
             "guard off; those differences are the pieces of the bound.\n\n| scene | scheme | ");
    tgt_puts(bt_unit_name());
    tgt_puts("/step: mean | worst step | Newton iterations/step (max) | fallback steps |\n"
             "|---|---|---:|---:|---:|---:|\n");
    for (s = 0; s < 4; s++)
        for (k = 0; k < 3; k++) {
            bt_normal nm;
            if (scenes[s].bodies > EDMI_MAX_BODIES)
                continue;
            tgt_puts("| ");
            tgt_puts(scenes[s].name);
            tgt_puts(" | ");
            tgt_puts(bt_scheme_name[guarded[k]]);
            tgt_puts(" | ");
            if (!bt_pieces_run(&pc, scenes[s].name, scenes[s].build, guarded[k], scenes[s].dt,
                               scenes[s].move, &nm)) {
                tgt_puts("FAILED | | | |\n");
                failed++;
                continue;
            }
            if (nm.worst > worst)
                worst = nm.worst;
            halvings += nm.halvings;
            bt_put_ratio((unsigned long long)nm.sum, BT_STEPS, 0);
            tgt_puts(" | ");
            bt_put_long(nm.worst);
            tgt_puts(" | ");
            bt_put_ratio((unsigned long long)nm.iterations, BT_STEPS, 2);
            tgt_puts(" (");
            tgt_put_uint((unsigned long)nm.iterations_max);
            tgt_puts(") | ");
            tgt_put_uint((unsigned long)nm.fallbacks);
            tgt_puts(" |\n");
        }

    tgt_puts("\n| forced worst case (PM, fallback on) | state | l_max = 4 | l_max = 8 | l_max = ");
    tgt_put_uint(BT_LMAX_SEARCH);
    tgt_puts(" | result |\n|---|---|---:|---:|---:|---|\n");
    ok &= bt_forced("capacity, dt = 0.3", bt_full, BT_FULL_FORCE_DT, bt_full_move, &pc,
                    forced_full, &bt_sub_full);
    ok &= bt_forced("stiff (1 body), dt = 0.1", bt_stiff, EDMI_R(0.1), NULL, &pc, forced_stiff,
                    &bt_sub_stiff);

    tgt_puts("\n| piece | ");
    tgt_puts(bt_unit_name());
    tgt_puts(" (max) | samples | largest in | how |\n|---|---:|---:|---|---|\n");
    bt_put_piece("first: set-up, predictor evaluation, 1 correction", &pc.first,
                 "step with l_max = 1, no fallback (fails)");
    bt_put_piece("iter: one more correction (linear solve + evaluation)", &pc.iter,
                 "F(l_max = k+1) - F(l_max = k), both failing");
    bt_put_piece("eval: one residual evaluation", &pc.eval,
                 "edmi_residual minus its validation and set-up");
    bt_put_piece("guard: energy balance + guard", &pc.guard, "step with guard on - guard off");
    bt_put_piece("last: last correction + all after Newton", &pc.last,
                 "step - F(l_max = its iterations - 1)");
    bt_put_piece("fallback: fallback state + commit", &pc.fallback,
                 "F(l_max = L, fallback) - F(l_max = L), L = 1 and the forced states'");
    if (pc.first.n == 0 || pc.iter.n == 0 || pc.last.n == 0 || pc.fallback.n == 0 ||
        pc.eval.n == 0) {
        tgt_puts("FAILED: a piece was not observed\n");
        return failed + 1;
    }
    tgt_puts("\nT(L) <= first + (L-2) iter + last + 8 L halving + fallback + kept, kept = iter + "
             "eval (3 + 9 L evaluations, L + 1 linear solves: the last step's factors tried "
             "first)\n\n| l_max = L | bound, halving <= iter "
             "| estimate, halving ~ eval | no halvings | forced, capacity | forced, stiff |\n"
             "|---:|---:|---:|---:|---:|---:|\n");
    for (k = 0; k < 3; k++) {
        tgt_puts("| ");
        tgt_put_uint(lmax[k]);
        tgt_puts(" | ");
        tgt_put_uint(bt_bound(&pc, lmax[k], pc.iter.max));
        tgt_puts(" | ");
        tgt_put_uint(bt_bound(&pc, lmax[k], pc.eval.max));
        tgt_puts(" | ");
        tgt_put_uint(bt_bound(&pc, lmax[k], 0));
        tgt_puts(" | ");
        if (forced_full[k] >= 0)
            bt_put_long(forced_full[k]);
        else
            tgt_puts("-");
        tgt_puts(" | ");
        if (forced_stiff[k] >= 0)
            bt_put_long(forced_stiff[k]);
        else
            tgt_puts("-");
        tgt_puts(" |\n");
    }
    /* Substeps (params.substep_levels = k): a failed step is taken again as substeps, at
     * worst 2^(k+1) - 1 Newton solves that all fail (the step's own and 2^(k+1) - 2 more)
     * and 2^k fallbacks: T_k(L) <= (2^(k+1) - 1) (T(L) - fallback) + 2^k fallback. */
    tgt_puts("\nSubsteps from the forced states (PM, fallback on, l_max = ");
    tgt_put_uint(BT_SUB_LMAX);
    tgt_puts("): T_k(L) <= (2^(k+1) - 1) (T(L) - fallback) + 2^k fallback, T(L) the no-"
             "halvings bound above\n\n| substep_levels = k | bound | forced, capacity: ");
    tgt_puts(bt_unit_name());
    tgt_puts(" (substeps, fallbacks, corrections) | forced, stiff |\n|---:|---:|---:|---:|\n");
    for (k = 0; k < BT_SUB_LEVELS; k++) {
        unsigned long t = bt_bound(&pc, BT_SUB_LMAX, 0L) - (unsigned long)pc.fallback.max;
        unsigned long b = ((2UL << (k + 1)) - 1UL) * t + (1UL << (k + 1)) * (unsigned long)pc.fallback.max;
        const bt_sub *sb[2] = {&bt_sub_full, &bt_sub_stiff};
        tgt_puts("| ");
        tgt_put_uint((unsigned long)k + 1UL);
        tgt_puts(" | ");
        tgt_put_uint(b);
        for (s = 0; s < 2; s++) {
            tgt_puts(" | ");
            if (sb[s]->insns[k] < 0) {
                tgt_puts("-");
                continue;
            }
            bt_put_long(sb[s]->insns[k]);
            tgt_puts(" (");
            tgt_put_uint((unsigned long)sb[s]->substeps[k]);
            tgt_puts(", ");
            tgt_put_uint((unsigned long)sb[s]->fallbacks[k]);
            tgt_puts(", ");
            tgt_put_uint((unsigned long)sb[s]->iterations[k]);
            tgt_puts(")");
            ok &= sb[s]->insns[k] <= (long)b;
        }
        tgt_puts(" |\n");
    }
    /* The bound must hold for every step timed here (l_max = the default). */
    tgt_puts("\ncheck: the worst normal step (");
    bt_put_long(worst);
    tgt_puts(", l_max = ");
    tgt_put_uint((unsigned long)l_max);
    tgt_puts(halvings == 0 ? ", no halvings) and the forced steps are within the no-halvings bound: "
                           : ") and the forced steps are within the bound: ");
    k = worst <= (long)bt_bound(&pc, (unsigned long)l_max, halvings == 0 ? 0L : pc.iter.max);
    for (s = 0; s < 3; s++)
        k = k && (forced_full[s] < 0 || forced_full[s] <= (long)bt_bound(&pc, lmax[s], 0L)) &&
            (forced_stiff[s] < 0 || forced_stiff[s] <= (long)bt_bound(&pc, lmax[s], 0L));
    tgt_puts(k ? "ok\n" : "FAILED\n");
    ok &= k;
    tgt_puts("\n(the largest values observed in these scenes, not a static analysis: "
             "data-dependent branches (pivoting, potential branches, the guard's searches) can "
             "take longer paths elsewhere; user potentials are not covered; single-call "
             "counts +-");
    bt_put_long(bt_span_err);
    tgt_puts(")\n");
    return failed + (ok ? 0 : 1);
}

/* ---- main -------------------------------------------------------------------------------- */

int main(void)
{
    unsigned long cal1, cal2;
    int failed;

    tgt_puts("edmi bench_target: EDMI_REAL=");
    tgt_puts(edmi_is_double_precision() ? "double" : "float");
    tgt_puts(", capacity ");
    tgt_put_uint(EDMI_MAX_BODIES);
    tgt_puts("/");
    tgt_put_uint(EDMI_MAX_LINKS);
    tgt_puts("/");
    tgt_put_uint(EDMI_MAX_DAMPERS);
    tgt_puts(", ");
    tgt_put_uint(BT_STEPS);
    tgt_puts(" steps per run, edmi_default_params()\n");
    bt_cycles = tgt_cyccnt_start();
    if (bt_cycles) {
        bt_unit = 1;
        tgt_puts("DWT CYCCNT counts: real silicon. The numbers below are CYCLES per step.\n");
    } else {
        tgt_puts("DWT CYCCNT does not count here (QEMU does not model it): using SysTick\n");
        /* Calibration: twice, to see that the count is deterministic. */
        tgt_ticks_start();
        cal1 = tgt_ticks();
        tgt_cal_loop(BT_CAL_ITERS);
        cal1 = tgt_ticks() - cal1;
        cal2 = tgt_ticks();
        tgt_cal_loop(BT_CAL_ITERS);
        cal2 = tgt_ticks() - cal2;
        tgt_puts("calibration: ");
        tgt_put_uint(BT_CAL_INSNS);
        tgt_puts(" instructions = ");
        tgt_put_uint(cal1);
        tgt_puts(" and ");
        tgt_put_uint(cal2);
        tgt_puts(" SysTick ticks\n");
        /* Exact up to the reads around the loop, which can fall on either side of a tick. */
        if (cal1 != cal2 || cal1 * BT_INSNS_PER_TICK + BT_INSNS_PER_TICK < BT_CAL_INSNS ||
            cal1 * BT_INSNS_PER_TICK > BT_CAL_INSNS + BT_INSNS_PER_TICK) {
            tgt_puts("FAIL: SysTick is not 1 tick per 40 instructions: run under QEMU with "
                     "-icount shift=0\n");
            tgt_exit(TGT_EXIT_FAILED);
        }
        tgt_puts("=> 1 SysTick tick = 40 instructions (QEMU -icount shift=0, 25 MHz SysTick). "
                 "These are INSTRUCTION counts, not cycles.\n");
    }
    if (!bt_span_calibrate()) {
        tgt_puts("FAIL: single-call counts of loops of known length spread by ");
        bt_put_long(bt_span_err);
        tgt_puts(" instructions\n");
        tgt_exit(TGT_EXIT_FAILED);
    }
    tgt_puts("single calls: loops of 2n instructions, n = 1..");
    tgt_put_uint(BT_SPAN_CAL);
    tgt_puts(", measure 2n + a constant within a spread of ");
    bt_put_long(bt_span_err);
    tgt_puts(" => single-call counts are exact to +-");
    bt_put_long(bt_span_err);
    tgt_puts("\n\n");

    failed = bt_scene_table();
    bt_before_step = NULL;
    failed += bt_bound_section();
    return failed == 0 ? 0 : 1;
}
