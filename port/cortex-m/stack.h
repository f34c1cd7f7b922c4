/* Stack painting on the emulated Cortex-M targets: how deep did the stack go?
 * crt.c paints the whole stack before main() and reports the high-water mark at exit;
 * bench_target.c repaints around one edmi_step() to measure that call alone. */
#ifndef TGT_STACK_H
#define TGT_STACK_H

#define TGT_STACK_PATTERN 0xA5A5A5A5UL

/* The current stack pointer. */
static inline unsigned long tgt_sp(void)
{
    unsigned long sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

/* Fill the stack from its bottom up to just below the caller's frame with the pattern. */
void tgt_stack_paint(void);
/* Address of the lowest stack word that no longer holds the pattern (the stack's top if
 * none was touched). */
unsigned long tgt_stack_lowest(void);
/* Bounds of the stack from the linker script. */
unsigned long tgt_stack_bottom(void);
unsigned long tgt_stack_top(void);

#endif
