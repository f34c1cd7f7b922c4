/* haptic_target: the 1 kHz virtual coupling of examples/haptic.c on an emulated Cortex-M4F
 * (`make haptic-target`): what one haptic tick costs.
 *
 * The model and the hand are the host example's edmi PM row, in float: a tool of 0.1 kg on a
 * zero-rest-length spring of 3000 N/m with a 0.5 N s/m damper to an anchor that follows the
 * hand of examples/haptic_hand.h (its sine is a series: no libm), dt = 1 ms, 6000 ticks,
 * edmi_default_params() with scheme PM (passivity guard on) and fallback on.
 *
 * A tick is what a device's control interrupt does once it has the hand's position:
 * edmi_move_anchor(), edmi_step() and reading link_force. Only that is timed. Computing the
 * trajectory (a stand-in for reading the encoder) and the energy bookkeeping are not.
 *
 * Counting, as tests/bench/bench_target.c does it: QEMU models no DWT cycle counter, so SysTick
 * counts virtual time under -icount shift=0, one tick per 40 instructions, checked against a
 * loop of known length (no numbers are printed otherwise). A single tick's reading is
 * therefore good to +-40 instructions; the mean over all ticks is exact to well under one.
 * The cost of the two counter reads around a tick is measured around an empty region and
 * subtracted. These are instruction counts, not cycles (see bench_target.c). On silicon the
 * DWT cycle counter runs and the program prints cycles instead.
 *
 * Also printed: Newton iterations, the ticks on which the guard changed the state (by kind),
 * fallbacks and failed ticks, the ticks on which H rose by more than the hand's work
 * (checked in double from the stored states: H_n+1 - H_n - work_anchor > 0; a tick may rise
 * by what the energy tank held, sys.tank), the ticks beyond the tank (H_n+1 - H_n -
 * work_anchor - (T_n - T_n+1) above 32 double epsilons of the terms: the program fails on
 * any), the largest E_inj, and the bits of the final state, which examples/haptic.c prints
 * too (float: build/float/haptic after `make EDMI_REAL=float`).
 *
 * Built with -DHT_WALL=1 (and the library with -DEDMI_MAX_WALLS=1): the same coupling with
 * the wall of examples/tool_on_wall.c, into which the hand presses the tool (HH_WALL_X,
 * HH_WALL_K): what a tick costs when the coupling touches a wall; H then includes the
 * wall's V. */
#include <float.h>
#include <stddef.h>

#include "edmi.h"
/* The example's own hand model (examples/haptic_hand.h, public example code a user copies with
 * examples/haptic.c): this benchmark measures that model, found with -Iexamples. */
#include "haptic_hand.h"
#include "cortex-m/counter.h"
#include "cortex-m/semihost.h"
#include "cortex-m/stack.h"

#ifndef HT_WALL
#define HT_WALL 0
#endif

/* The model, from haptic_hand.h (examples/haptic.c runs the same). */
#define HT_M HH_MASS
#define HT_K HH_STIFFNESS
#define HT_B HH_DAMPING
#define HT_DT HH_DT
#define HT_TICKS HH_TICKS
/* The calibration loop: HT_CAL_ITERS iterations of SUBS + BNE (as bench_target.c). */
#define HT_CAL_ITERS 1000000UL
#define HT_CAL_INSNS (2UL * HT_CAL_ITERS)
#define HT_INSNS_PER_TICK 40UL /* 25 MHz SysTick, 1 ns per instruction */

static edmi_system ht_sys;
static edmi_workspace ht_work;
static int ht_cycles;                       /* 1: DWT cycles (silicon), 0: SysTick ticks */
static unsigned long ht_unit = HT_INSNS_PER_TICK; /* instructions (or cycles) per count */

static void ht_cal_loop(unsigned long n)
{
    __asm__ volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n) : : "cc");
}

/* The counter; SysTick counts down 24 bits, so differences are taken modulo 2^24. */
static unsigned long ht_now(void) { return ht_cycles ? tgt_cyccnt() : tgt_ticks(); }

static unsigned long ht_elapsed(unsigned long t0, unsigned long t1)
{
    return ht_cycles ? t1 - t0 : (t1 - t0) & TGT_SYST_MASK;
}

/* A single tick's count in instructions (or cycles), less the mean cost of the counter
 * reads (base: their count summed over HT_TICKS empty regions). */
static unsigned long ht_worst(unsigned long count, unsigned long long base)
{
    unsigned long long b = (base * ht_unit + (unsigned long long)HT_TICKS / 2ULL) /
                           (unsigned long long)HT_TICKS;
    return (unsigned long)((unsigned long long)count * ht_unit - b);
}

/* x in scientific notation with `sig` significant digits (sig >= 1), in double. */
static void ht_put_sci(double x, int sig)
{
    double scale = 1.0;
    int e = 0, i;
    unsigned long digits;
    if (x < 0.0) {
        tgt_putchar('-');
        x = -x;
    }
    if (x == 0.0) {
        tgt_puts("0");
        return;
    }
    while (x >= 10.0) {
        x /= 10.0;
        e++;
    }
    while (x < 1.0) {
        x *= 10.0;
        e--;
    }
    for (i = 1; i < sig; i++)
        scale *= 10.0;
    digits = (unsigned long)(x * scale + 0.5);
    if ((double)digits >= 10.0 * scale) { /* 9.995 rounded up to 10.00 */
        digits /= 10UL;
        e++;
    }
    for (i = sig - 1; i >= 0; i--) {
        unsigned long p = 1;
        int j;
        for (j = 0; j < i; j++)
            p *= 10UL;
        tgt_putchar('0' + (int)((digits / p) % 10UL));
        if (i == sig - 1 && sig > 1)
            tgt_putchar('.');
    }
    tgt_putchar('e');
    if (e < 0) {
        tgt_putchar('-');
        e = -e;
    }
    tgt_put_uint((unsigned long)e);
}

/* v / d with one decimal, rounded half up (d > 0). */
static void ht_put_ratio1(unsigned long long v, unsigned long long d)
{
    unsigned long long x = (v * 10ULL + d / 2ULL) / d;
    tgt_put_uint((unsigned long)(x / 10ULL));
    tgt_putchar('.');
    tgt_putchar('0' + (int)(x % 10ULL));
}

/* The bits of an edmi_real in hexadecimal, most significant byte first (both the host and
 * the Cortex-M are little-endian), as examples/haptic.c prints them. */
static void ht_put_bits(edmi_real x)
{
    union {
        edmi_real r;
        unsigned char b[sizeof(edmi_real)];
    } u;
    int i;
    u.r = x;
    tgt_puts("0x");
    for (i = (int)sizeof(edmi_real) - 1; i >= 0; i--) {
        tgt_putchar("0123456789abcdef"[u.b[i] >> 4]);
        tgt_putchar("0123456789abcdef"[u.b[i] & 0xFU]);
    }
}

/* H_n+1 - H_n of two stored states in double (float values: their differences and products
 * are exact or within one double rounding, far below float's grid). */
#if HT_WALL
/* The wall's V at tool position q, in double (q - HH_WALL_X exact). */
static double ht_vwall(edmi_real q)
{
    double pen = (double)q - (double)HH_WALL_X;
    return pen > 0.0 ? (double)HH_WALL_K / 3.0 * pen * pen * pen : 0.0;
}
#else
static double ht_vwall(edmi_real q) { return (void)q, 0.0; }
#endif

static double ht_dh(edmi_real q0, edmi_real p0, edmi_real x0, edmi_real q1, edmi_real p1,
                    edmi_real x1)
{
    double dp = (double)p1 - (double)p0, sp = (double)p1 + (double)p0;
    double e0 = (double)q0 - (double)x0, e1 = (double)q1 - (double)x1;
    return dp * sp / (2.0 * (double)HT_M) + 0.5 * (double)HT_K * (e1 - e0) * (e1 + e0) +
           (ht_vwall(q1) - ht_vwall(q0));
}

/* H of a stored state in double, and |x|: the magnitude of ht_dh's terms (its resolution) */
static double ht_h(edmi_real q, edmi_real p, edmi_real x)
{
    double e = (double)q - (double)x;
    return (double)p * (double)p / (2.0 * (double)HT_M) + 0.5 * (double)HT_K * e * e +
           ht_vwall(q);
}

static double ht_abs(double x) { return x < 0.0 ? -x : x; }

static edmi_status ht_build(int *tool, int *link)
{
    edmi_params prm = edmi_default_params();
    edmi_potential spring = edmi_pot_harmonic(HT_K, EDMI_R(0.0));
    edmi_real q[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real p[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_status s;
    prm.scheme = EDMI_SCHEME_PM;
    prm.fallback = 1;
    prm.substep_levels = HT_WALL ? 3 : 0; /* PM's force jumps where a contact begins */
    q[0] = hh_position(EDMI_R(0.0));
    s = edmi_init(&ht_sys, &prm);
    if (s == EDMI_OK)
        s = edmi_add_body(&ht_sys, HT_M, q, p, tool);
    if (s == EDMI_OK)
        s = edmi_add_anchor(&ht_sys, *tool, q, &spring, link);
    if (s == EDMI_OK)
        s = edmi_add_damper(&ht_sys, *link, HT_B, NULL);
#if HT_WALL
    if (s == EDMI_OK) {
        const edmi_real n[3] = {EDMI_R(-1.0), EDMI_R(0.0), EDMI_R(0.0)};
        edmi_potential wall = edmi_pot_contact(HH_WALL_K, EDMI_R(0.0));
        s = edmi_add_wall(&ht_sys, *tool, n, -HH_WALL_X, &wall, NULL);
    }
#endif
    return s;
}

int main(void)
{
    static const char *const unit[2] = {"instructions", "cycles"};
    edmi_real x[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    volatile edmi_real sink = EDMI_R(0.0);
    static const char *const class_name[4] = {"guard idle", "guard: rounding only",
                                              "guard: impulse", "guard: drag"};
    unsigned long long sum = 0ULL, base = 0ULL, class_sum[4] = {0ULL, 0ULL, 0ULL, 0ULL};
    unsigned long class_max[4] = {0UL, 0UL, 0UL, 0UL};
    long class_n[4] = {0, 0, 0, 0};
    int c;
    unsigned long worst = 0UL, t0, t1, sp0, stack;
    long n, worst_tick = 0, guarded = 0, by_action[3] = {0, 0, 0}, fallbacks = 0, failed = 0;
    long rises = 0, beyond_tank = 0, iterations = 0, touching = 0, splits = 0;
    unsigned long long touch_sum = 0ULL;
    unsigned long touch_max = 0UL;
    int tool = 0, link = 0, max_iterations = 0;
    double e_inj = 0.0, e_max = 0.0, worst_excess = 0.0;
    edmi_status s;

    tgt_puts("edmi haptic_target: EDMI_REAL=");
    tgt_puts(edmi_is_double_precision() ? "double" : "float");
    tgt_puts(HT_WALL ? ", the 1 kHz virtual coupling of examples/haptic.c pressed into the wall "
                       "of examples/tool_on_wall.c (edmi PM, guard on, fallback on, 3 levels of "
                       "substeps), "
                     : ", the 1 kHz virtual coupling of examples/haptic.c (edmi PM, guard on, "
                       "fallback on), ");
    tgt_put_uint((unsigned long)HT_TICKS);
    tgt_puts(" ticks\n");
    ht_cycles = tgt_cyccnt_start();
    if (ht_cycles) {
        ht_unit = 1UL;
        tgt_puts("DWT CYCCNT counts: real silicon. The numbers below are CYCLES per tick.\n");
    } else {
        unsigned long cal1, cal2;
        tgt_ticks_start();
        cal1 = tgt_ticks();
        ht_cal_loop(HT_CAL_ITERS);
        cal1 = tgt_ticks() - cal1;
        cal2 = tgt_ticks();
        ht_cal_loop(HT_CAL_ITERS);
        cal2 = tgt_ticks() - cal2;
        tgt_puts("calibration: ");
        tgt_put_uint(HT_CAL_INSNS);
        tgt_puts(" instructions = ");
        tgt_put_uint(cal1);
        tgt_puts(" and ");
        tgt_put_uint(cal2);
        tgt_puts(" SysTick ticks\n");
        if (cal1 != cal2 || cal1 * HT_INSNS_PER_TICK + HT_INSNS_PER_TICK < HT_CAL_INSNS ||
            cal1 * HT_INSNS_PER_TICK > HT_CAL_INSNS + HT_INSNS_PER_TICK) {
            tgt_puts("FAIL: SysTick is not 1 tick per 40 instructions: run under QEMU with "
                     "-icount shift=0\n");
            tgt_exit(TGT_EXIT_FAILED);
        }
        tgt_puts("=> 1 SysTick tick = 40 instructions (QEMU -icount shift=0, 25 MHz SysTick). "
                 "These are INSTRUCTION counts, not cycles.\n");
    }

    /* The counter reads around an empty region, as many times as there are ticks. */
    tgt_ticks_start();
    for (n = 0; n < HT_TICKS; n++) {
        t0 = ht_now();
        __asm__ volatile("" ::: "memory");
        t1 = ht_now();
        base += ht_elapsed(t0, t1);
    }

    s = ht_build(&tool, &link);
    if (s != EDMI_OK) {
        tgt_puts("FAIL: building the coupling: ");
        tgt_puts(edmi_status_name(s));
        tgt_puts("\n");
        tgt_exit(TGT_EXIT_FAILED);
    }
    tgt_stack_paint();
    sp0 = tgt_sp();
    tgt_ticks_start();
    for (n = 1; n <= HT_TICKS; n++) {
        edmi_step_result res;
        edmi_real q0 = ht_sys.body[tool].q[0], p0 = ht_sys.body[tool].p[0];
        edmi_real a0 = ht_sys.link[link].anchor[0], tank0 = ht_sys.tank;
        unsigned long dt_count;
        double excess;
        x[0] = hh_position((edmi_real)n * HT_DT); /* the encoder, in a device */

        t0 = ht_now();
        s = edmi_move_anchor(&ht_sys, link, x);
        if (s == EDMI_OK)
            s = edmi_step(&ht_sys, &ht_work, HT_DT, &res);
        sink = ht_sys.link_force[link][0]; /* the force for the motor */
        t1 = ht_now();

        dt_count = ht_elapsed(t0, t1);
        sum += dt_count;
        if (dt_count > worst) {
            worst = dt_count;
            worst_tick = n;
        }
        if (s != EDMI_OK) {
            if (failed == 0) {
                tgt_puts("tick ");
                tgt_put_uint((unsigned long)n);
                tgt_puts(" failed: ");
                tgt_puts(edmi_status_name(s));
                tgt_puts("\n");
            }
            failed++;
            continue;
        }
        iterations += res.iterations;
        splits += res.substeps > 1;
        if (ht_vwall(q0) > 0.0 || ht_vwall(ht_sys.body[tool].q[0]) > 0.0) { /* in contact */
            touching++;
            touch_sum += dt_count;
            if (dt_count > touch_max)
                touch_max = dt_count;
        }
        if (res.iterations > max_iterations)
            max_iterations = res.iterations;
        fallbacks += res.stop == EDMI_STOP_FALLBACK;
        guarded += res.guard_action != 0U;
        by_action[0] += (res.guard_action & EDMI_MOVE_ROUND) != 0U;
        by_action[1] += (res.guard_action & EDMI_MOVE_IMPULSE) != 0U;
        by_action[2] += (res.guard_action & EDMI_MOVE_DRAG) != 0U;
        c = (res.guard_action & EDMI_MOVE_DRAG) != 0U      ? 3
            : (res.guard_action & EDMI_MOVE_IMPULSE) != 0U ? 2
            : res.guard_action != 0U                        ? 1
                                                            : 0;
        class_n[c]++;
        class_sum[c] += dt_count;
        if (dt_count > class_max[c])
            class_max[c] = dt_count;
        excess = ht_dh(q0, p0, a0, ht_sys.body[tool].q[0], ht_sys.body[tool].p[0],
                       ht_sys.link[link].anchor[0]) - (double)res.work_anchor;
        rises += excess > 0.0;
        beyond_tank += excess - ((double)tank0 - (double)ht_sys.tank) >
                       32.0 * DBL_EPSILON *
                           (ht_h(q0, p0, a0) +
                            ht_h(ht_sys.body[tool].q[0], ht_sys.body[tool].p[0],
                                 ht_sys.link[link].anchor[0]) +
                            ht_abs((double)res.work_anchor) + (double)tank0 + (double)ht_sys.tank);
        if (n == 1 || excess > worst_excess)
            worst_excess = excess;
        e_inj += excess;
        if (n == 1 || e_inj > e_max)
            e_max = e_inj;
    }
    stack = sp0 - tgt_stack_lowest();
    (void)sink;

    tgt_puts("counter reads around an empty region: ");
    ht_put_ratio1(base * ht_unit, (unsigned long long)HT_TICKS);
    tgt_puts(" ");
    tgt_puts(unit[ht_cycles]);
    tgt_puts(" (subtracted)\n\n| ");
    tgt_puts(unit[ht_cycles]);
    tgt_puts(" per tick (move_anchor + step + link_force) | ticks | mean | worst (+-");
    tgt_put_uint(ht_unit);
    tgt_puts(") |\n|---|---:|---:|---:|\n| all | ");
    tgt_put_uint((unsigned long)HT_TICKS);
    tgt_puts(" | ");
    ht_put_ratio1(sum * ht_unit - base * ht_unit, (unsigned long long)HT_TICKS);
    tgt_puts(" | ");
    tgt_put_uint(ht_worst(worst, base));
    tgt_puts(" (tick ");
    tgt_put_uint((unsigned long)worst_tick);
    tgt_puts(") |\n");
    for (c = 0; c < 4; c++) {
        if (class_n[c] == 0)
            continue;
        tgt_puts("| ");
        tgt_puts(class_name[c]);
        tgt_puts(" | ");
        tgt_put_uint((unsigned long)class_n[c]);
        tgt_puts(" | ");
        ht_put_ratio1(class_sum[c] * ht_unit - (unsigned long long)class_n[c] * base * ht_unit /
                          (unsigned long long)HT_TICKS,
                      (unsigned long long)class_n[c]);
        tgt_puts(" | ");
        tgt_put_uint(ht_worst(class_max[c], base));
        tgt_puts(" |\n");
    }
    if (HT_WALL && touching > 0) {
        tgt_puts("| in contact with the wall at the tick's start or end | ");
        tgt_put_uint((unsigned long)touching);
        tgt_puts(" | ");
        ht_put_ratio1(touch_sum * ht_unit - (unsigned long long)touching * base * ht_unit /
                          (unsigned long long)HT_TICKS,
                      (unsigned long long)touching);
        tgt_puts(" | ");
        tgt_put_uint(ht_worst(touch_max, base));
        tgt_puts(" |\n");
    }
    tgt_puts("\nNewton iterations per tick ");
    ht_put_ratio1((unsigned long long)iterations, (unsigned long long)HT_TICKS);
    tgt_puts(" (max ");
    tgt_put_uint((unsigned long)max_iterations);
    tgt_puts("); stack high-water mark of the tick loop ");
    tgt_put_uint(stack);
    tgt_puts(" bytes\nthe guard changed the state on ");
    tgt_put_uint((unsigned long)guarded);
    tgt_puts(" of ");
    tgt_put_uint((unsigned long)HT_TICKS);
    tgt_puts(" ticks (rounding ");
    tgt_put_uint((unsigned long)by_action[0]);
    tgt_puts(", impulse ");
    tgt_put_uint((unsigned long)by_action[1]);
    tgt_puts(", drag ");
    tgt_put_uint((unsigned long)by_action[2]);
    tgt_puts("); ticks split into substeps ");
    tgt_put_uint((unsigned long)splits);
    tgt_puts("; fallbacks ");
    tgt_put_uint((unsigned long)fallbacks);
    tgt_puts("; failed ticks ");
    tgt_put_uint((unsigned long)failed);
    tgt_puts("\nticks with H_n+1 - H_n > work_anchor (in double, from the stored states): ");
    tgt_put_uint((unsigned long)rises);
    tgt_puts(" (all within the energy tank: beyond it ");
    tgt_put_uint((unsigned long)beyond_tank);
    tgt_puts("); largest H_n+1 - H_n - work_anchor: ");
    ht_put_sci(worst_excess, 3);
    tgt_puts(" J\nE_inj: max ");
    ht_put_sci(e_max, 4);
    tgt_puts(" J, final ");
    ht_put_sci(e_inj, 5);
    tgt_puts(" J\nfinal state bits (the host build in the same precision prints them too): q ");
    ht_put_bits(ht_sys.body[tool].q[0]);
    tgt_puts(", p ");
    ht_put_bits(ht_sys.body[tool].p[0]);
    tgt_puts("\n");
    return failed == 0 && beyond_tank == 0 && e_max <= 0.0 ? 0 : 1;
}
