/* Issue 21 case 2: is the fallback taken for every failure? params.fallback set, coupled mass
 * matrices (build with -DEDMI_MAX_MASS_GAP=1), PM, 2000 steps: statuses, fallbacks, and the
 * residual at the stored state of every OK non-fallback step (hard_common.h).
 *   A: 3 bodies, M = [1 .6 0; .6 1 .6; 0 .6 1], harmonic springs (k 10, r0 1) 0-1, 1-2
 *   B: the same with k 1000 and dt 0.05 (stiff: Newton/guard under stress)
 *   C: 3 bodies, off-diagonal 0.4999995 (rows barely dominant), springs as A
 *   D: 2 bodies, masses 0.5, coupling 0.4999995 (M nearly singular, eigenvalue 5e-7)
 * each with fallback on and off. */
#include "hard_common.h"

static edmi_system sys;
static edmi_workspace work;

static void run(const char *label, int nb, edmi_real m, edmi_real mc, edmi_real k, edmi_real dt,
                int fallback, long steps)
{
    edmi_params prm = edmi_default_params();
    edmi_real q[3][3] = {{0, 0, 0}, {EDMI_R(1.1), EDMI_R(0.1), 0}, {EDMI_R(2.0), EDMI_R(-0.1), EDMI_R(0.2)}};
    edmi_real p[3][3] = {{0, 1, 0}, {EDMI_R(0.5), 0, EDMI_R(-0.3)}, {0, -1, EDMI_R(0.4)}};
    edmi_potential sp = edmi_pot_harmonic(k, 1);
    edmi_step_result res;
    hc_count c;
    edmi_status s;
    char buf[96];
    int i;
    long n;
    prm.scheme = EDMI_SCHEME_PM;
    prm.fallback = fallback;
    edmi_init(&sys, &prm);
    for (i = 0; i < nb; i++)
        edmi_add_body(&sys, m, q[i], p[i], 0);
    for (i = 0; i + 1 < nb; i++)
        edmi_add_pair(&sys, i, i + 1, &sp, 0);
    for (i = 0; i + 1 < nb; i++) {
        s = edmi_set_mass_coupling(&sys, i, i + 1, mc);
        if (s != EDMI_OK) {
            printf("%-6s %s fallback %d: edmi_set_mass_coupling(%d, %d, %.9g) -> %s\n", hc_prec(),
                   label, fallback, i, i + 1, (double)mc, edmi_status_name(s));
            return;
        }
    }
    hc_reset(&c);
    for (n = 0; n < steps; n++)
        hc_step(&sys, &work, dt, &res, &c, 0, 0);
    sprintf(buf, "%s fb=%d", label, fallback);
    hc_print(buf, &c);
}

int main(void)
{
    int fb;
    if (!EDMI_CONFIG_MATCHES()) return 2;
    for (fb = 1; fb >= 0; fb--) {
        run("A M[1 .6 0;.6 1 .6;0 .6 1] k10 dt1e-2", 3, 1, EDMI_R(0.6), 10, EDMI_R(0.01), fb, 2000);
        run("A' same, dt 1e-3", 3, 1, EDMI_R(0.6), 10, EDMI_R(0.001), fb, 2000);
        run("B same, k 1000 dt 0.05", 3, 1, EDMI_R(0.6), 1000, EDMI_R(0.05), fb, 2000);
        run("C 3 bodies off .4999995 k10 dt1e-2", 3, 1, EDMI_R(0.4999995), 10, EDMI_R(0.01), fb, 2000);
        run("D 2 bodies m .5 off .4999995 dt1e-2", 2, EDMI_R(0.5), EDMI_R(0.4999995), 10, EDMI_R(0.01), fb, 2000);
        run("D' 2 bodies m .5 off .49999 dt1e-2", 2, EDMI_R(0.5), EDMI_R(0.49999), 10, EDMI_R(0.01), fb, 2000);
    }
    return 0;
}
