/* edmi test runner: the same sources run on the host and on emulated targets. */
#include "harness.h"
#include "suites.h"

int main(void)
{
    th_puts(edmi_is_double_precision() ? "edmi tests, EDMI_REAL=double\n"
                                       : "edmi tests, EDMI_REAL=float\n");
    suite_potentials();
    suite_contact();
    suite_invalid();
    suite_fuzz_findings();
    suite_tangent();
    suite_energy();
    suite_orders();
    suite_paper();
    suite_hard();
    suite_solver();
    suite_effects();
    suite_guard();
    suite_track();
    suite_orbits();
    return th_finish() == 0 ? 0 : 1;
}
