/* A tiny harness-driven program for checking the target runner itself (`make smoke-target`):
 * a few checks on the paper's spring, closing "N passed, N failed". Built with
 * -DTGT_SMOKE_FAIL it reports one failed check (main returns 1); with -DTGT_SMOKE_FAULT it
 * executes a permanently undefined instruction (UsageFault) after the checks; with
 * -DTGT_SMOKE_HANG it never returns; with -DTGT_SMOKE_STACK it recurses through more than the
 * whole stack. The runner must turn these into a failure (exit 1, 3, the timeout's 124 and 4)
 * and a clean run (-DTGT_SMOKE_OK or nothing) into a pass. */
#include <stddef.h>

#include "harness.h"

static edmi_system sm_sys;
static edmi_workspace sm_work;

#ifdef TGT_SMOKE_STACK
static volatile int sm_sink;

/* 1 KiB per level, 400 levels: more than the 256 KiB stack. */
static int sm_deep(int n)
{
    volatile char buf[1024];
    buf[0] = (char)n;
    sm_sink = buf[0];
    return n > 0 ? sm_deep(n - 1) + buf[0] : 0;
}
#endif

int main(void)
{
    static const edmi_real q[3] = {EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0)};
    static const edmi_real p[3] = {EDMI_R(-30.0), EDMI_R(15.0), EDMI_R(45.0)};
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential spring = edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0));
    edmi_params prm = edmi_default_params();
    edmi_invariants inv0, inv1;
    edmi_step_result res;
    int k, ok = 1;

    th_suite("smoke: the paper's spring, 100 PM steps");
    prm.scheme = EDMI_SCHEME_PM;
    CHECK_STATUS(edmi_init(&sm_sys, &prm), EDMI_OK);
    CHECK_STATUS(edmi_add_body(&sm_sys, EDMI_R(10.0), q, p, NULL), EDMI_OK);
    CHECK_STATUS(edmi_add_anchor(&sm_sys, 0, origin, &spring, NULL), EDMI_OK);
    CHECK_STATUS(edmi_invariants_of(&sm_sys, &inv0), EDMI_OK);
    for (k = 0; k < 100 && ok; k++)
        ok = edmi_step(&sm_sys, &sm_work, EDMI_R(1e-3), &res) == EDMI_OK;
    CHECK(ok);
    CHECK_STATUS(edmi_invariants_of(&sm_sys, &inv1), EDMI_OK);
    /* PM never gains energy beyond the solver tolerance: 1e-6 relative covers float. */
    CHECK(inv1.h <= inv0.h * EDMI_R(1.000001));
    th_note_real("H0", inv0.h);
    th_note_real("H100", inv1.h);
    th_note_int("iterations of the last step", res.iterations);
#ifdef TGT_SMOKE_FAIL
    CHECK(inv1.h > inv0.h * EDMI_R(2.0)); /* deliberately false */
#endif
#ifdef TGT_SMOKE_FAULT
    __asm__ volatile("udf #0");
#endif
#ifdef TGT_SMOKE_STACK
    CHECK(sm_deep(400) != 12345);
#endif
#ifdef TGT_SMOKE_HANG
    for (;;)
        __asm__ volatile("");
#endif
    return th_finish() == 0 ? 0 : 1;
}
