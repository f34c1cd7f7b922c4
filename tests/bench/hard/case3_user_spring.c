/* Issue 21 case 3: stuck for ever where smaller steps would pass? A user potential
 * V = k/2 (r - r0)^2 (k 50, r0 1) split as docs/energy-safe.md asks (V_c = V_+ = V, V_e = V_- = 0, so
 * V_+ >= 0 >= V_-; exact divided difference), one body m 1 at (1.3, 0, 0), p (0, 2, 0),
 * anchored at the origin, dt 1e-3, PT and GE (guard AUTO = on), with and without fallback;
 * against edmi_pot_harmonic(50, 1). Counts statuses, fallbacks, OK-but-unsolved steps, and
 * reports H at the end against H0 (a frozen body shows as H falling to V alone). */
#include "hard_common.h"
#include "passive.h"

static tp_user_harmonic ctx = {50, 1}; /* tests/lib/passive.c's user harmonic */
static edmi_system sys;
static edmi_workspace work;

static void run(edmi_scheme sch, int user, int with_dd, int fallback, long steps)
{
    edmi_params prm = edmi_default_params();
    edmi_real q[3] = {EDMI_R(1.3), 0, 0}, p[3] = {0, 2, 0}, x[3] = {0, 0, 0};
    edmi_potential pot = user ? edmi_pot_user(tp_user_harmonic_fn, with_dd ? tp_user_harmonic_dd : 0, &ctx)
                              : edmi_pot_harmonic(50, 1);
    edmi_step_result res;
    edmi_invariants iv0, iv1;
    hc_count c;
    char buf[96];
    long n, fb_run = 0, fb_run_max = 0, moved_after_fb = 0;
    prm.scheme = sch;
    prm.fallback = fallback;
    edmi_init(&sys, &prm);
    edmi_add_body(&sys, 1, q, p, 0);
    edmi_add_anchor(&sys, 0, x, &pot, 0);
    edmi_invariants_of(&sys, &iv0);
    hc_reset(&c);
    for (n = 0; n < steps; n++) {
        edmi_status s = hc_step(&sys, &work, EDMI_R(1e-3), &res, &c, 0, 0);
        if (s == EDMI_OK && res.stop == EDMI_STOP_FALLBACK) {
            if (++fb_run > fb_run_max) fb_run_max = fb_run;
        } else {
            if (s == EDMI_OK && fb_run) moved_after_fb++;
            fb_run = 0;
        }
    }
    edmi_invariants_of(&sys, &iv1);
    sprintf(buf, "%s %s%s fb=%d n=%ld", hc_scheme_name(sch), user ? "user" : "builtin",
            user ? (with_dd ? "+dd" : "-dd") : "", fallback, steps);
    hc_print(buf, &c);
    printf("       H0 %.6g H_end %.6g K_end %.6g  longest fallback run %ld, recoveries %ld\n",
           (double)iv0.h, (double)iv1.h, (double)iv1.k, fb_run_max, moved_after_fb);
}

int main(void)
{
    static const edmi_scheme sch[] = {EDMI_SCHEME_PT, EDMI_SCHEME_GE, EDMI_SCHEME_PM};
    unsigned i;
    int fb;
    if (!EDMI_CONFIG_MATCHES()) return 2;
    for (i = 0; i < 3; i++)
        for (fb = 0; fb <= 1; fb++) {
            run(sch[i], 1, 1, fb, 2000);
            run(sch[i], 1, 0, fb, 2000);
            run(sch[i], 0, 0, fb, 2000);
            run(sch[i], 1, 1, fb, 100000);
            run(sch[i], 0, 0, fb, 100000);
        }
    return 0;
}
