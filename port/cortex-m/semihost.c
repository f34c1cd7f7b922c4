/* Arm semihosting glue (see semihost.h). The semihosting call is BKPT 0xAB on M-profile:
 * r0 = operation, r1 = argument; QEMU implements it with -semihosting-config enable=on. */
#include "semihost.h"

#define TGT_SYS_WRITE0 0x04
#define TGT_SYS_EXIT 0x18
#define TGT_SYS_EXIT_EXTENDED 0x20
#define TGT_ADP_STOPPED_APPLICATION_EXIT 0x20026
#define TGT_ADP_STOPPED_RUNTIME_ERROR 0x20023

/* One line per SYS_WRITE0 trap: each trap leaves the emulator, so per-character traps
 * would dominate the run time of a chatty test. */
#define TGT_LINE 128

static char tgt_line[TGT_LINE + 1];
static unsigned tgt_len;

static int tgt_semihost(int op, unsigned long arg)
{
    register int r0 __asm__("r0") = op;
    register unsigned long r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void tgt_flush(void)
{
    if (tgt_len == 0)
        return;
    tgt_line[tgt_len] = '\0';
    (void)tgt_semihost(TGT_SYS_WRITE0, (unsigned long)tgt_line);
    tgt_len = 0;
}

void tgt_putchar(int c)
{
    if (c == '\0')
        return; /* SYS_WRITE0 would end the line there */
    tgt_line[tgt_len++] = (char)c;
    if (c == '\n' || tgt_len == TGT_LINE)
        tgt_flush();
}

void tgt_puts(const char *s)
{
    while (*s)
        tgt_putchar(*s++);
}

void tgt_put_uint(unsigned long v)
{
    char buf[12];
    int n = 0;
    do {
        buf[n++] = (char)('0' + (int)(v % 10UL));
        v /= 10UL;
    } while (v != 0UL);
    while (n > 0)
        tgt_putchar(buf[--n]);
}

void tgt_put_hex(unsigned long v)
{
    int shift;
    tgt_puts("0x");
    for (shift = 28; shift >= 0; shift -= 4)
        tgt_putchar("0123456789abcdef"[(v >> shift) & 0xFUL]);
}

void tgt_exit(int status)
{
    /* SYS_EXIT_EXTENDED takes {reason, subcode}; QEMU exits with the subcode for an
     * application exit. The plain SYS_EXIT that follows (only reached if the host lacks the
     * extended call) can only say 0 or "error", which QEMU maps to 1. */
    static unsigned long block[2];
    tgt_flush();
    block[0] = TGT_ADP_STOPPED_APPLICATION_EXIT;
    block[1] = (unsigned long)status;
    (void)tgt_semihost(TGT_SYS_EXIT_EXTENDED, (unsigned long)block);
    (void)tgt_semihost(TGT_SYS_EXIT, status == 0 ? TGT_ADP_STOPPED_APPLICATION_EXIT
                                                 : TGT_ADP_STOPPED_RUNTIME_ERROR);
    for (;;) {
    }
}
