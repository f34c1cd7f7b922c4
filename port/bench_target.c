/* bench_target: what one edmi_step() costs on an emulated Cortex-M (`make bench-target`).
 *
 * Scenes (the paper's, as in tests/scenes.h), each run for BT_STEPS steps from its initial
 * state with edmi_default_params() and one scheme:
 *   spring: m = 10, q0 = (2, 1, 1), p0 = (-30, 15, 45), neo-Hookean c = 1e3, rbar = 4 to an
 *           anchor at the origin, dt = 1e-3;
 *   lj2:    m = 1, q = (0, -0.5612, 0) and (0, 0.5612, 0), p = (5, 0, 0) and (10, 0, 0),
 *           Lennard-Jones eps = 100, sigma = 1, dt = 1e-3.
 * Printed per scene and scheme: instructions per step, Newton iterations per step (mean and
 * maximum) and the stack high-water mark of edmi_step() (bytes below the caller's stack
 * pointer that the call wrote, found by painting the stack before the run and scanning it
 * after).
 *
 * Counting. QEMU does not model the DWT cycle counter, so the count comes from SysTick
 * under `-icount shift=0`: every guest instruction advances virtual time by 1 ns and SysTick
 * ticks at the board's 25 MHz, i.e. once per 40 instructions. The program calibrates this
 * with a loop of known length and refuses to print numbers when the ratio is not exact
 * (not run under -icount shift=0). These are instruction counts from an emulator, not
 * cycles: a real Cortex-M4F takes 14 cycles for a VDIV.F32 or VSQRT.F32 and more than one
 * for loads, taken branches and multi-register transfers. The loop's own cost (calling
 * through a pointer, counting iterations) is measured with a no-op step and subtracted.
 * On real Cortex-M3/M4/M7 silicon (semihosting through a debugger) the DWT cycle counter
 * runs, and the program counts cycles with it instead and says so. */
#include <stddef.h>

#include "../edmi.h"
#include "cortex-m/counter.h"
#include "cortex-m/semihost.h"
#include "cortex-m/stack.h"

#define BT_STEPS 200
/* The calibration loop: BT_CAL_ITERS iterations of SUBS + BNE. */
#define BT_CAL_ITERS 1000000UL
#define BT_CAL_INSNS (2UL * BT_CAL_ITERS)
#define BT_INSNS_PER_TICK 40UL /* 25 MHz SysTick, 1 ns per instruction */

typedef edmi_status (*bt_step_fn)(edmi_system *, edmi_workspace *, edmi_real,
                                  edmi_step_result *);

typedef struct bt_run {
    unsigned long ticks; /* counter units (see bt_unit) for the whole run */
    long iterations;     /* Newton corrections, summed */
    int max_iterations;
    int steps_done;
    unsigned long stack; /* bytes below the caller's SP written during the run */
    edmi_status status;  /* first failure, or EDMI_OK */
} bt_run;

static edmi_system bt_sys;
static edmi_workspace bt_work;

static void bt_cal_loop(unsigned long n)
{
    __asm__ volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n) : : "cc");
}

static edmi_status bt_null_step(edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                edmi_step_result *res)
{
    (void)sys;
    (void)work;
    (void)dt;
    res->iterations = 0;
    return EDMI_OK;
}

/* Both steppers are called through this pointer, so their call sequences are identical. */
static bt_step_fn volatile bt_step;

/* The counter: DWT CYCCNT in cycles on silicon, else SysTick ticks of 40 instructions. */
static int bt_cycles;
static unsigned long bt_unit = BT_INSNS_PER_TICK;

static unsigned long bt_now(void) { return bt_cycles ? tgt_cyccnt() : tgt_ticks(); }

static void bt_measure(int steps, edmi_real dt, bt_run *out)
{
    edmi_step_result res;
    unsigned long sp0, t0, t1;
    int k;
    out->iterations = 0;
    out->max_iterations = 0;
    out->status = EDMI_OK;
    out->steps_done = 0;
    tgt_stack_paint();
    sp0 = tgt_sp();
    tgt_ticks_start();
    t0 = bt_now();
    for (k = 0; k < steps; k++) {
        edmi_status st = bt_step(&bt_sys, &bt_work, dt, &res);
        if (st != EDMI_OK) {
            out->status = st;
            break;
        }
        out->iterations += res.iterations;
        if (res.iterations > out->max_iterations)
            out->max_iterations = res.iterations;
    }
    t1 = bt_now();
    out->steps_done = k;
    out->ticks = !bt_cycles && tgt_ticks_wrapped() ? 0UL : t1 - t0;
    out->stack = sp0 - tgt_stack_lowest();
}

static edmi_status bt_spring(edmi_scheme scheme)
{
    static const edmi_real q[3] = {EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0)};
    static const edmi_real p[3] = {EDMI_R(-30.0), EDMI_R(15.0), EDMI_R(45.0)};
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot = edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0));
    edmi_params prm = edmi_default_params();
    edmi_status s;
    prm.scheme = scheme;
    s = edmi_init(&bt_sys, &prm);
    if (s == EDMI_OK)
        s = edmi_add_body(&bt_sys, EDMI_R(10.0), q, p, NULL);
    if (s == EDMI_OK)
        s = edmi_add_anchor(&bt_sys, 0, origin, &pot, NULL);
    return s;
}

static edmi_status bt_lj2(edmi_scheme scheme)
{
    static const edmi_real q1[3] = {EDMI_R(0.0), EDMI_R(-0.5612), EDMI_R(0.0)};
    static const edmi_real q2[3] = {EDMI_R(0.0), EDMI_R(0.5612), EDMI_R(0.0)};
    static const edmi_real p1[3] = {EDMI_R(5.0), EDMI_R(0.0), EDMI_R(0.0)};
    static const edmi_real p2[3] = {EDMI_R(10.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot = edmi_pot_lj(EDMI_R(100.0), EDMI_R(1.0));
    edmi_params prm = edmi_default_params();
    edmi_status s;
    prm.scheme = scheme;
    s = edmi_init(&bt_sys, &prm);
    if (s == EDMI_OK)
        s = edmi_add_body(&bt_sys, EDMI_R(1.0), q1, p1, NULL);
    if (s == EDMI_OK)
        s = edmi_add_body(&bt_sys, EDMI_R(1.0), q2, p2, NULL);
    if (s == EDMI_OK)
        s = edmi_add_pair(&bt_sys, 0, 1, &pot, NULL);
    return s;
}

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

int main(void)
{
    static const char *const scheme_name[] = {"MP", "LG", "GE", "PM", "PT"};
    static const char *const scene_name[] = {"spring", "lj2"};
    unsigned long cal1, cal2;
    bt_run base, run;
    int scene, scheme, failed = 0;

    tgt_puts("edmi bench_target: EDMI_REAL=");
    tgt_puts(edmi_is_double_precision() ? "double" : "float");
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
        bt_cal_loop(BT_CAL_ITERS);
        cal1 = tgt_ticks() - cal1;
        cal2 = tgt_ticks();
        bt_cal_loop(BT_CAL_ITERS);
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

    /* Loop overhead: the same loop around a no-op step. */
    if (bt_spring(EDMI_MP) != EDMI_OK)
        tgt_exit(TGT_EXIT_FAILED);
    bt_step = bt_null_step;
    bt_measure(BT_STEPS, EDMI_R(1e-3), &base);
    tgt_puts("loop overhead: ");
    bt_put_ratio((unsigned long long)base.ticks * bt_unit, BT_STEPS, 1);
    tgt_puts(bt_cycles ? " cycles" : " instructions");
    tgt_puts(" per step (subtracted)\n\n");

    tgt_puts(bt_cycles ? "| scene | scheme | cycles/step | Newton iterations/step (max) "
                         "| cycles/iteration | stack high-water (bytes) |\n"
                       : "| scene | scheme | instructions/step | Newton iterations/step (max) "
                         "| instructions/iteration | stack high-water (bytes) |\n");
    tgt_puts("|---|---|---:|---:|---:|---:|\n");
    bt_step = edmi_step;
    for (scene = 0; scene < 2; scene++)
        for (scheme = EDMI_MP; scheme <= EDMI_PT; scheme++) {
            unsigned long long insns;
            edmi_status s = scene == 0 ? bt_spring((edmi_scheme)scheme)
                                       : bt_lj2((edmi_scheme)scheme);
            if (s == EDMI_OK)
                bt_measure(BT_STEPS, EDMI_R(1e-3), &run);
            tgt_puts("| ");
            tgt_puts(scene_name[scene]);
            tgt_puts(" | ");
            tgt_puts(scheme_name[scheme]);
            tgt_puts(" | ");
            if (s != EDMI_OK || run.status != EDMI_OK || run.ticks == 0) {
                tgt_puts("FAILED: ");
                tgt_puts(edmi_status_name(s != EDMI_OK ? s : run.status));
                tgt_puts(" at step ");
                tgt_put_uint((unsigned long)run.steps_done);
                tgt_puts(" |\n");
                failed++;
                continue;
            }
            insns = (unsigned long long)(run.ticks - base.ticks) * bt_unit;
            bt_put_ratio(insns, BT_STEPS, 0);
            tgt_puts(" | ");
            bt_put_ratio((unsigned long long)run.iterations, BT_STEPS, 2);
            tgt_puts(" (");
            tgt_put_uint((unsigned long)run.max_iterations);
            tgt_puts(") | ");
            bt_put_ratio(insns, (unsigned long long)run.iterations, 0);
            tgt_puts(" | ");
            tgt_put_uint(run.stack);
            tgt_puts(" |\n");
        }
    tgt_puts(bt_cycles ? "\n(cycles/iteration = cycles/step divided by Newton iterations/step;"
                         " it includes the per-step set-up)\n"
                       : "\n(instructions/iteration = instructions/step divided by Newton "
                         "iterations/step; it includes the per-step set-up)\n");
    return failed == 0 ? 0 : 1;
}
