/* Tick and cycle counters on Cortex-M3/M4/M7 (ARMv7-M), for measuring edmi_step().
 *
 * - DWT CYCCNT counts core clock cycles on real M3/M4/M7 silicon (when the DWT is present;
 *   Cortex-M0/M0+ have none). QEMU does not model the DWT: its registers read as zero, and
 *   tgt_cyccnt_start() returns 0 there.
 * - SysTick, clocked from the processor clock (CLKSOURCE = 1), exists on every ARMv7-M core
 *   and counts down 24 bits. On real silicon it counts cycles. In QEMU's mps2 boards it runs
 *   at a fixed 25 MHz of *virtual* time; with -icount shift=0 each guest instruction advances
 *   virtual time by exactly 1 ns, so one SysTick tick is 40 instructions (calibrated at run
 *   time by bench_target.c, which also checks it).
 * SysTick is used without its interrupt: an interval must stay below 2^24 ticks (671 million
 * instructions under -icount shift=0), and tgt_ticks_wrapped() says when it did not. */
#ifndef TGT_COUNTER_H
#define TGT_COUNTER_H

#define TGT_SYST_CSR (*(volatile unsigned long *)0xE000E010UL)
#define TGT_SYST_RVR (*(volatile unsigned long *)0xE000E014UL)
#define TGT_SYST_CVR (*(volatile unsigned long *)0xE000E018UL)
#define TGT_DEMCR (*(volatile unsigned long *)0xE000EDFCUL)
#define TGT_DWT_CTRL (*(volatile unsigned long *)0xE0001000UL)
#define TGT_DWT_CYCCNT (*(volatile unsigned long *)0xE0001004UL)

#define TGT_SYST_MASK 0xFFFFFFUL

/* (Re)start SysTick free-running from the processor clock, interrupt off. */
static inline void tgt_ticks_start(void)
{
    TGT_SYST_CSR = 0;
    TGT_SYST_RVR = TGT_SYST_MASK;
    TGT_SYST_CVR = 0;     /* clears the counter and COUNTFLAG; it reloads on the next tick */
    TGT_SYST_CSR = 0x5UL; /* ENABLE | CLKSOURCE = processor clock */
    while (TGT_SYST_CVR == 0) {
    }
    (void)TGT_SYST_CSR;   /* reading clears COUNTFLAG */
}

/* Ticks elapsed since the reload (differences of two readings are what count). */
static inline unsigned long tgt_ticks(void) { return TGT_SYST_MASK - TGT_SYST_CVR; }

/* 1 if SysTick wrapped since the last tgt_ticks_start() or tgt_ticks_wrapped(). */
static inline int tgt_ticks_wrapped(void) { return (int)((TGT_SYST_CSR >> 16) & 1UL); }

/* Enable DWT CYCCNT; return 1 if it is counting (real silicon), 0 if not (QEMU, M0+). */
static inline int tgt_cyccnt_start(void)
{
    unsigned long a, b;
    TGT_DEMCR |= 1UL << 24; /* TRCENA */
    TGT_DWT_CYCCNT = 0;
    TGT_DWT_CTRL |= 1UL;    /* CYCCNTENA */
    a = TGT_DWT_CYCCNT;
    __asm__ volatile("nop\n nop\n nop\n nop");
    b = TGT_DWT_CYCCNT;
    return b != a;
}

static inline unsigned long tgt_cyccnt(void) { return TGT_DWT_CYCCNT; }

#endif
