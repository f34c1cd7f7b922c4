/* C runtime start and fault report for the emulated Cortex-M targets (see startup.S).
 * tgt_start: enable the configurable faults, copy .data, zero .bss, paint the stack, run
 * main(), report the stack high-water mark and exit through semihosting with main's status.
 * tgt_fault_report: print the faulting PC from the stacked exception frame and exit 3 (4 when
 * the stack pointer has left the stack: an overflow). */
#include "semihost.h"
#include "stack.h"

extern unsigned long tgt_data_load[], tgt_data_start[], tgt_data_end[];
extern unsigned long tgt_bss_start[], tgt_bss_end[];
extern unsigned long tgt_stack_lo[], tgt_stack_hi[];

int main(void);
void tgt_start(void) __attribute__((noreturn));
void tgt_fault_report(const unsigned long *frame, unsigned long exc_return)
    __attribute__((noreturn));

#define TGT_REG(addr) (*(volatile unsigned long *)(addr))
#define TGT_SCB_CCR TGT_REG(0xE000ED14UL)
#define TGT_SCB_SHCSR TGT_REG(0xE000ED24UL)
#define TGT_SCB_CFSR TGT_REG(0xE000ED28UL)
#define TGT_SCB_HFSR TGT_REG(0xE000ED2CUL)
#define TGT_SCB_MMFAR TGT_REG(0xE000ED34UL)
#define TGT_SCB_BFAR TGT_REG(0xE000ED38UL)

unsigned long tgt_stack_bottom(void) { return (unsigned long)tgt_stack_lo; }
unsigned long tgt_stack_top(void) { return (unsigned long)tgt_stack_hi; }

void tgt_stack_paint(void)
{
    /* Leaf function: nothing of ours lives below the stack pointer. */
    volatile unsigned long *w = tgt_stack_lo;
    unsigned long *end = (unsigned long *)(tgt_sp() & ~7UL);
    while (w < end)
        *w++ = TGT_STACK_PATTERN;
}

unsigned long tgt_stack_lowest(void)
{
    const volatile unsigned long *w = tgt_stack_lo;
    while (w < tgt_stack_hi && *w == TGT_STACK_PATTERN)
        w++;
    return (unsigned long)w;
}

void tgt_start(void)
{
    unsigned long *src = tgt_data_load, *dst = tgt_data_start;
    volatile unsigned long *z = tgt_bss_start;
    unsigned long low;
    int rc;

    /* MemManage, BusFault and UsageFault get their own report instead of escalating; an
     * integer division by zero traps (UsageFault) instead of yielding 0. */
    TGT_SCB_SHCSR |= (1UL << 16) | (1UL << 17) | (1UL << 18);
    TGT_SCB_CCR |= 1UL << 4;

    while (dst < tgt_data_end)
        *dst++ = *src++;
    while (z < tgt_bss_end)
        *z++ = 0;
    tgt_stack_paint();

    rc = main();

    low = tgt_stack_lowest();
    tgt_puts("[target] stack high-water mark: ");
    tgt_put_uint(tgt_stack_top() - low);
    tgt_puts(" of ");
    tgt_put_uint(tgt_stack_top() - tgt_stack_bottom());
    tgt_puts(" bytes\n");
    if (low == tgt_stack_bottom()) {
        tgt_puts("[target] STACK OVERFLOW: the guard pattern at the stack's bottom is gone\n");
        tgt_exit(TGT_EXIT_STACK);
    }
    tgt_exit(rc == 0 ? TGT_EXIT_OK : TGT_EXIT_FAILED);
}

static const char *tgt_exception_name(unsigned long n)
{
    switch (n) {
    case 2: return "NMI";
    case 3: return "HardFault";
    case 4: return "MemManage";
    case 5: return "BusFault";
    case 6: return "UsageFault";
    case 11: return "SVCall";
    case 12: return "DebugMonitor";
    case 14: return "PendSV";
    case 15: return "SysTick";
    default: return "exception";
    }
}

void tgt_fault_report(const unsigned long *frame, unsigned long exc_return)
{
    unsigned long ipsr;
    __asm__ volatile("mrs %0, ipsr" : "=r"(ipsr));
    ipsr &= 0x1FFUL;
    tgt_flush(); /* the interrupted line, if any, stays separate from the report */
    tgt_putchar('\n');
    tgt_puts("[target] FAULT: ");
    tgt_puts(tgt_exception_name(ipsr));
    tgt_puts(" (exception ");
    tgt_put_uint(ipsr);
    tgt_puts(") at pc=");
    tgt_put_hex(frame[6]);
    tgt_puts(" lr=");
    tgt_put_hex(frame[5]);
    tgt_puts(" sp=");
    tgt_put_hex((unsigned long)frame);
    tgt_puts(" xpsr=");
    tgt_put_hex(frame[7]);
    tgt_puts("\n[target] CFSR=");
    tgt_put_hex(TGT_SCB_CFSR);
    tgt_puts(" HFSR=");
    tgt_put_hex(TGT_SCB_HFSR);
    tgt_puts(" MMFAR=");
    tgt_put_hex(TGT_SCB_MMFAR);
    tgt_puts(" BFAR=");
    tgt_put_hex(TGT_SCB_BFAR);
    tgt_puts(" EXC_RETURN=");
    tgt_put_hex(exc_return);
    tgt_putchar('\n');
    if ((unsigned long)frame < tgt_stack_bottom()) {
        /* The frame was pushed below the stack: into the unmapped, read-as-zero region under
         * the RAM, which is why pc and lr read as 0. */
        tgt_puts("[target] STACK OVERFLOW: sp is below the stack's bottom ");
        tgt_put_hex(tgt_stack_bottom());
        tgt_putchar('\n');
        tgt_exit(TGT_EXIT_STACK);
    }
    tgt_exit(TGT_EXIT_FAULT);
}
