/* Cortex-M4F / M7 startup for the emulated MPS2 boards: the vector table, the reset entry
 * (FPU on, then C) and the fault entry (find the stacked frame, switch to a private stack,
 * then C). Everything else is in crt.c. Symbols come from mps2.ld. */
    .syntax unified
    .thumb

    .section .vectors, "a"
    .align 2
    .global tgt_vectors
tgt_vectors:
    .word tgt_stack_hi           /*  0 initial main stack pointer */
    .word tgt_reset             /*  1 reset */
    .word tgt_fault             /*  2 NMI */
    .word tgt_fault             /*  3 HardFault */
    .word tgt_fault             /*  4 MemManage */
    .word tgt_fault             /*  5 BusFault */
    .word tgt_fault             /*  6 UsageFault */
    .word 0, 0, 0, 0            /*  7-10 reserved */
    .word tgt_fault             /* 11 SVCall */
    .word tgt_fault             /* 12 DebugMonitor */
    .word 0                     /* 13 reserved */
    .word tgt_fault             /* 14 PendSV */
    .word tgt_systick           /* 15 SysTick (weak: a fault unless a program defines it) */

    .text
    .thumb_func
    .global tgt_reset
    .type tgt_reset, %function
tgt_reset:
#if defined(__ARM_FP)
    /* CPACR: full access to CP10 and CP11 before any floating-point instruction, which the
     * compiler may emit anywhere in C code (hard-float ABI). */
    ldr r0, =0xE000ED88
    ldr r1, [r0]
    orr r1, r1, #(0xF << 20)
    str r1, [r0]
    dsb
    isb
#endif
    bl tgt_start                /* crt.c: never returns */
    b .
    .size tgt_reset, . - tgt_reset

    /* Any fault or unexpected exception. EXC_RETURN bit 2 says which stack holds the frame
     * (r0-r3, r12, lr, pc, xPSR at +0..+28). A stack overflow may be the cause, so the C
     * report runs on its own small stack. */
    .thumb_func
    .global tgt_fault
    .type tgt_fault, %function
tgt_fault:
    tst lr, #4
    ite eq
    mrseq r0, msp
    mrsne r0, psp
    mov r1, lr
    ldr r2, =tgt_fault_stack_hi
    mov sp, r2
    bl tgt_fault_report         /* crt.c: never returns */
    b .
    .size tgt_fault, . - tgt_fault

    .weak tgt_systick
    .thumb_set tgt_systick, tgt_fault
