/* A body on a stiff spring tied to the origin, stepped with the perturbed mid-point scheme. */
#include <stdio.h>
#include "edmi.h"

static edmi_system sys;     /* caller-owned memory: the library never allocates */
static edmi_workspace work; /* Newton's workspace, kept between steps */

int main(void)
{
    const edmi_real q[3] = {2, 1, 1}, p[3] = {-30, 15, 45}, origin[3] = {0, 0, 0};
    edmi_potential spring = edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0));
    edmi_params prm = edmi_default_params();
    edmi_invariants inv;
    int n;

    prm.scheme = EDMI_SCHEME_PM; /* the default: 2nd order, H never above the work and the tank */
    if (edmi_init(&sys, &prm) != EDMI_OK || edmi_add_body(&sys, 10, q, p, NULL) != EDMI_OK ||
        edmi_add_anchor(&sys, 0, origin, &spring, NULL) != EDMI_OK)
        return 1;
    for (n = 1; n <= 1000; n++) {
        edmi_status s = edmi_step(&sys, &work, EDMI_R(1e-3), NULL);
        if (s != EDMI_OK) {
            printf("step %d: %s\n", n, edmi_status_name(s));
            return 1;
        }
        if (n % 100 == 0 && edmi_invariants_of(&sys, &inv) == EDMI_OK)
            printf("t = %4.2f  H = %.10g\n", (double)sys.t, (double)inv.h);
    }
    return 0;
}
