/* The CMake consumer (examples/cmake/CMakeLists.txt): the paper's spring, PM, 1000 steps of
 * 1e-3; checks EDMI_CONFIG_MATCHES() and that H never rose (PM's guard) above any earlier H
 * plus the energy tank then (sys.tank), by more than the rounding of its own evaluation here:
 * edmi_invariants_of() sums H in edmi_real, good to a few eps |H| (the guard's bound is on
 * the exact H of the stored state; tests/ and make soak check it in long double). Exit status
 * 0 when both hold. On the Cortex-M4F it prints through semihosting. */
#include <stddef.h>
#include "edmi.h"
#ifdef EDMI_CONSUMER_TARGET
#include "semihost.h"
#define SAY(s) tgt_puts(s)
#else
#include <stdio.h>
#define SAY(s) fputs(s, stdout)
#endif

static edmi_system sys;
static edmi_workspace work;

int main(void)
{
    const edmi_real q[3] = {2, 1, 1}, p[3] = {-30, 15, 45}, origin[3] = {0, 0, 0};
    edmi_potential spring = edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0));
    edmi_invariants inv;
    edmi_real h_low; /* the least H_m + T_m so far: no later H may exceed it */
    int n, rises = 0;
    if (!EDMI_CONFIG_MATCHES()) {
        SAY("consumer: compiled with another edmi configuration than the library\n");
        return 1;
    }
    if (edmi_init(&sys, NULL) != EDMI_OK || edmi_add_body(&sys, 10, q, p, NULL) != EDMI_OK ||
        edmi_add_anchor(&sys, 0, origin, &spring, NULL) != EDMI_OK ||
        edmi_invariants_of(&sys, &inv) != EDMI_OK)
        return 1;
    h_low = inv.h + sys.tank;
    for (n = 0; n < 1000; n++) {
        if (edmi_step(&sys, &work, EDMI_R(1e-3), NULL) != EDMI_OK ||
            edmi_invariants_of(&sys, &inv) != EDMI_OK)
            return 1;
        rises += inv.h - h_low > EDMI_R(8.0) * EDMI_EPS * inv.h;
        if (inv.h + sys.tank < h_low)
            h_low = inv.h + sys.tank;
    }
    SAY(edmi_is_double_precision() ? "consumer: double, " : "consumer: float, ");
    SAY(rises == 0 ? "1000 PM steps, H never rose\n" : "H rose\n");
    return rises != 0;
}
