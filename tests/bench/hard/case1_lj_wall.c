/* Issue 21 case 1: EDMI_OK with nothing solved? Two bodies 1.12 apart in the repulsive wall of
 * an LJ link (eps 100, sigma 3..236), masses 1, p (5,0,0) and (10,0,0), bodies on the y axis;
 * one step per (scheme, sigma, dt) with default parameters; the residual checked at the
 * stored state (hard_common.h). Also LG quotient + Janz, and one body on an LJ anchor (MP). */
#include "hard_common.h"

static edmi_system sys;
static edmi_workspace work;
static long n_cases, n_ok, n_unsolved, n_unsolved_fl, n_unsolved_ng, n_fail, n_doc, n_split, n_fb;
static double max_doc;

static void one(const char *what, edmi_scheme sch, int quotient, int anchor, edmi_real sigma,
                edmi_real dt)
{
    edmi_params prm = edmi_default_params();
    edmi_real q0[3] = {0, 0, 0}, q1[3] = {0, EDMI_R(1.12), 0};
    edmi_real p0[3] = {5, 0, 0}, p1[3] = {10, 0, 0};
    edmi_potential lj = edmi_pot_lj(100, sigma);
    edmi_step_result res;
    hc_count c;
    double relp, rob;
    edmi_status s;
    prm.scheme = sch;
    if (quotient) {
        prm.lg_form = EDMI_LG_QUOTIENT;
        prm.lg_alt = EDMI_LG_ALT_JANZ;
    }
    edmi_init(&sys, &prm);
    if (anchor) {
        edmi_add_body(&sys, 1, q1, p1, 0);
        s = edmi_add_anchor(&sys, 0, q0, &lj, 0);
    } else {
        edmi_add_body(&sys, 1, q0, p0, 0);
        edmi_add_body(&sys, 1, q1, p1, 0);
        s = edmi_add_pair(&sys, 0, 1, &lj, 0);
    }
    if (s != EDMI_OK) {
        printf("%-6s %-10s sigma %5g dt %-6g build %s\n", hc_prec(), what, (double)sigma,
               (double)dt, edmi_status_name(s));
        return;
    }
    hc_reset(&c);
    memset(&res, 0, sizeof res);
    s = hc_step(&sys, &work, dt, &res, &c, &relp, &rob);
    n_cases++;
    n_ok += s == EDMI_OK;
    n_unsolved += c.unsolved;
    printf("%-6s %-10s sigma %5g dt %-6g %-24s %-9s it %2d res %.2e res0 %.2e corr %.2e "
           "|Rp|/|pn| %.2e rob %.2e flr %.2e doc %.2e sub %d fb %d g%u%s\n",
           hc_prec(), what, (double)sigma, (double)dt, edmi_status_name(s),
           s == EDMI_OK ? hc_stop_name(res.stop) : "-", res.iterations, (double)res.residual,
           (double)res.residual0, (double)res.correction, relp, rob, s == EDMI_OK ? hc_last_flr : -1.0,
           s == EDMI_OK ? hc_last_doc : -1.0, res.substeps, res.fallbacks, res.guard_action, c.unsolved ? (c.unsolved_fl ? "  <== OK but unsolved" : "  <- rob>1e3eps, within floor") : "");
    n_unsolved_fl += c.unsolved_fl;
    n_fail += s != EDMI_OK;
    n_doc += c.beyond_doc;
    n_split += s == EDMI_OK && res.substeps > 1;
    n_fb += s == EDMI_OK && res.stop == EDMI_STOP_FALLBACK;
    if (c.max_doc > max_doc) max_doc = c.max_doc;
    if (c.unsolved_fl && !(res.guard_action & (EDMI_MOVE_IMPULSE | EDMI_MOVE_DRAG)))
        n_unsolved_ng++;
}

int main(void)
{
    static const edmi_real sig[] = {3, 10, 50, 100, 150, 236};
    static const edmi_real dts[] = {EDMI_R(1e-3), EDMI_R(1e-2), EDMI_R(0.1), EDMI_R(0.26)};
    static const edmi_scheme sch[] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    unsigned i, j, k;
    if (!EDMI_CONFIG_MATCHES()) return 2;
    for (k = 0; k < 5; k++)
        for (i = 0; i < sizeof sig / sizeof sig[0]; i++)
            for (j = 0; j < sizeof dts / sizeof dts[0]; j++)
                one(hc_scheme_name(sch[k]), sch[k], 0, 0, sig[i], dts[j]);
    for (k = 0; k < 5; k++)
        one(hc_scheme_name(sch[k]), sch[k], 0, 0, 236, EDMI_R(0.2588));
    for (i = 0; i < sizeof sig / sizeof sig[0]; i++) {
        one("LGq+Janz", EDMI_SCHEME_LG, 1, 0, sig[i], EDMI_R(0.2588));
        for (j = 0; j < sizeof dts / sizeof dts[0]; j++)
            one("LGq+Janz", EDMI_SCHEME_LG, 1, 0, sig[i], dts[j]);
    }
    for (i = 0; i < sizeof sig / sizeof sig[0]; i++)
        for (j = 0; j < sizeof dts / sizeof dts[0]; j++)
            one("MP-anchor", EDMI_SCHEME_MP, 0, 1, sig[i], dts[j]);
    printf("%-6s case1 summary: %ld single steps, %ld EDMI_OK (%ld split into substeps, %ld fallbacks), "
           "%ld OK but unsolved (rob > 1e3 eps), "
           "%ld beyond 1e3 x the rounding floor (%ld of them without a guard impulse/drag), "
           "%ld beyond the documented bound (max |R| / eps M %.3g), %ld failed\n",
           hc_prec(), n_cases, n_ok, n_split, n_fb, n_unsolved, n_unsolved_fl, n_unsolved_ng,
           n_doc, max_doc, n_fail);
    return 0;
}
