/* The smallest firmware that uses edmi: the paper's spring, stepped with PM, its energy left
 * in a volatile. `make cross` links it for every target, without start-up files, entry point
 * main, with newlib and libgcc on the Arm cores and with only libgcc and port/riscv on
 * rv32imac (-nostdlib). The link succeeding is the proof that edmi.o plus port/ leave no
 * symbol undefined; the ELF's text is what a complete use of the library costs in flash.
 * It is never run. */
#include <stddef.h>

#include "edmi.h"

static edmi_system fw_sys;
static edmi_workspace fw_work;
volatile edmi_real fw_energy;

int main(void)
{
    static const edmi_real q[3] = {EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0)};
    static const edmi_real p[3] = {EDMI_R(-30.0), EDMI_R(15.0), EDMI_R(45.0)};
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential spring = edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0));
    edmi_params prm = edmi_default_params();
    edmi_invariants inv;
    int k;
    prm.scheme = EDMI_SCHEME_PM;
    if (edmi_init(&fw_sys, &prm) != EDMI_OK ||
        edmi_add_body(&fw_sys, EDMI_R(10.0), q, p, NULL) != EDMI_OK ||
        edmi_add_anchor(&fw_sys, 0, origin, &spring, NULL) != EDMI_OK)
        return 1;
    for (k = 0; k < 1000; k++)
        if (edmi_step(&fw_sys, &fw_work, EDMI_R(1e-3), NULL) != EDMI_OK)
            return 2;
    if (edmi_invariants_of(&fw_sys, &inv) != EDMI_OK)
        return 3;
    fw_energy = inv.h;
    return 0;
}
