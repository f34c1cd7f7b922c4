/* One call timed on its own, for the benchmarks on the emulated Cortex-M (tests/bench/bench_target.c,
 * tests/bench/worst_target.c).
 *
 * QEMU models no DWT cycle counter, so under -icount shift=0 (one guest instruction per ns of
 * virtual time) SysTick's 25 MHz counts 40 instructions per tick. One tick is too coarse for
 * a single call, so the call starts on a tick edge (a spin loop waits for one) and the time
 * from its end to the next edge is counted in iterations of a 4-instruction spin loop: the
 * raw count is exact but for a constant (the spins and the call around f), which the caller
 * measures with an empty f and subtracts, and checks with loops of known length
 * (tgt_span_calibrate). On silicon (tgt_cyccnt_start() returned 1) the DWT cycle counter
 * runs, and the count is in cycles. A call must stay below 2^24 ticks (671 million
 * instructions). */
#ifndef TGT_SPAN_H
#define TGT_SPAN_H

#include "counter.h"

#define TGT_INSNS_PER_TICK 40UL /* 25 MHz SysTick, 1 ns per instruction */
#define TGT_SPIN_INSNS 4UL      /* instructions per iteration of tgt_spin's loop */

/* Spin until SysTick's current value changes: *first is the value it left, the result the
 * number of loop iterations. */
static inline unsigned long tgt_spin(unsigned long *first)
{
    unsigned long n = 0, a, b;
    __asm__ volatile("ldr %1, [%3]\n\t"
                     "1: adds %0, %0, #1\n\t"
                     "ldr %2, [%3]\n\t"
                     "cmp %1, %2\n\t"
                     "beq 1b"
                     : "+r"(n), "=&r"(a), "=&r"(b)
                     : "r"(&TGT_SYST_CVR)
                     : "cc", "memory");
    *first = a;
    return n;
}

/* Raw count of one call of f: cycles (cycles != 0), else instructions from the tick edge it
 * starts on to the next edge after it returns, minus the spin up to that edge. */
static inline unsigned long tgt_span_raw(void (*f)(void), int cycles)
{
    unsigned long a, b, n;
    if (cycles) {
        a = tgt_cyccnt();
        f();
        b = tgt_cyccnt();
        return b - a;
    }
    (void)tgt_spin(&a);
    f();
    n = tgt_spin(&b);
    return ((a - b) & TGT_SYST_MASK) * TGT_INSNS_PER_TICK - n * TGT_SPIN_INSNS;
}

/* n iterations of SUBS + BNE: 2n instructions. */
static inline void tgt_cal_loop(unsigned long n)
{
    __asm__ volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n) : : "cc");
}

static unsigned long tgt_span_loop_n;
static void tgt_span_loop(void) { tgt_cal_loop(tgt_span_loop_n); }
static void tgt_span_nothing(void) {}

/* The count of an empty call (*null, to subtract) and the spread of the counts of loops of
 * 2n instructions, n = 1..n_max, around their known length (the counts' error, +-). SysTick
 * must be running (tgt_ticks_start). */
static inline long tgt_span_calibrate(unsigned long n_max, int cycles, unsigned long *null)
{
    long lo = 0, hi = 0, d;
    unsigned long n;
    *null = tgt_span_raw(tgt_span_nothing, cycles);
    for (n = 1; n <= n_max; n++) {
        tgt_span_loop_n = n;
        d = (long)tgt_span_raw(tgt_span_loop, cycles) - (long)*null - (long)(2UL * n);
        if (n == 1 || d < lo)
            lo = d;
        if (n == 1 || d > hi)
            hi = d;
    }
    return hi - lo;
}

#endif
