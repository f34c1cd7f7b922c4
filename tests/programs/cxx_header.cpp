// edmi.h from C++: the header compiles as C++11 (extern "C", no C-only syntax) and its
// declarations link against the library compiled as C. Closes with "N passed, N failed".
#include <cstdio>
#include <cstring>
#include "edmi.h"

static int passed, failed;

static void check(bool ok, const char *what)
{
    if (ok) {
        passed++;
    } else {
        failed++;
        std::printf("FAIL %s\n", what);
    }
}

int main()
{
    edmi_params prm = edmi_default_params();
    check(prm.scheme == EDMI_SCHEME_PM && prm.l_max == 20, "edmi_default_params(): PM, l_max 20");
    check(prm.tol_r == 0 && prm.tol_a == 0 && prm.tol_q > 0 && prm.guard == EDMI_GUARD_AUTO,
          "edmi_default_params(): Newton to its floor, guard auto");
    check(edmi_is_double_precision() == (sizeof(edmi_real) == sizeof(double) ? 1 : 0),
          "edmi_is_double_precision() agrees with the header");
    check(std::strcmp(edmi_status_name(EDMI_OK), "EDMI_OK") == 0, "edmi_status_name(EDMI_OK)");

    static edmi_system sys;
    static edmi_workspace work;
    const edmi_real q[3] = {1, 0, 0}, p[3] = {0, 1, 0}, origin[3] = {0, 0, 0};
    edmi_potential spring = edmi_pot_harmonic(1, 0);
    edmi_step_result res;
    prm.scheme = EDMI_SCHEME_PM;
    check(edmi_init(&sys, &prm) == EDMI_OK, "edmi_init");
    check(edmi_add_body(&sys, 1, q, p, NULL) == EDMI_OK, "edmi_add_body");
    check(edmi_add_anchor(&sys, 0, origin, &spring, NULL) == EDMI_OK, "edmi_add_anchor");
    check(edmi_step(&sys, &work, EDMI_R(0.01), &res) == EDMI_OK, "edmi_step");

    std::printf("C++: sizeof(edmi_system) = %lu, sizeof(edmi_workspace) = %lu\n",
                (unsigned long)sizeof(edmi_system), (unsigned long)sizeof(edmi_workspace));
    std::printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
