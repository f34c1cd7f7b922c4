/* Arm semihosting for the emulated Cortex-M targets (QEMU -semihosting-config enable=on).
 * Output is line-buffered and written with SYS_WRITE0; the exit status reaches QEMU's own
 * exit status through SYS_EXIT_EXTENDED. Not part of the library: edmi.c never calls this. */
#ifndef TGT_SEMIHOST_H
#define TGT_SEMIHOST_H

/* Exit statuses the target programs use (QEMU exits with the same number). */
#define TGT_EXIT_OK 0
#define TGT_EXIT_FAILED 1        /* main() returned non-zero: a test failed */
#define TGT_EXIT_FAULT 3         /* HardFault, MemManage, BusFault or UsageFault */
#define TGT_EXIT_STACK 4         /* the stack's guard pattern at its bottom was overwritten */

/* Buffer one character; the line is written when it ends or the buffer fills. */
void tgt_putchar(int c);
void tgt_puts(const char *s);
/* Unsigned decimal and 0x-prefixed 8-digit hexadecimal. */
void tgt_put_uint(unsigned long v);
void tgt_put_hex(unsigned long v);
/* Write whatever is buffered. */
void tgt_flush(void);
/* Flush, then stop the emulator with this exit status. Does not return. */
void tgt_exit(int status) __attribute__((noreturn));

#endif
