/* Issue 21 case 4: Newton cycling under a sign-flipping port.
 * (a) tests/lib/passive.c's "port flipping sign every tick" scene (body m 0.1 at (0.06, 0.01, 0),
 *     p (0, 0.02, 0.01), anchored at the origin by edmi_pot_harmonic(1e4, 0.05), dt 1e-3, PM)
 *     with the port A (3, 2, 1)/|(3, 2, 1)| flipping sign every step, A swept: the amplitude
 *     that drives the link to d ~ 0.003 is the case. 200,000 steps, fallback off and on.
 * (b) radial chatter through the anchor: body on the x axis at 0.0005, p 0, port A x flipping
 *     every step; rest length 0.05 (a kink at d = 0) and 0 (smooth), 200,000 steps.
 * (c) l_max = 1 with fallback on (a)'s hardest amplitude: does the body ever move again after
 *     a fallback? */
#include "hard_common.h"

static edmi_system sys;
static edmi_workspace work;

typedef struct { double dmin, dmax; long near, moved_after_fb, fb_after_first, cross; double q_span; } c4_stats;

/* radial 0: (a) geometry, port A dir (-1)^n; 1: radial, port A x (-1)^n; 2: held at d ~ 0.003
 * by a mean inward port F0 = k (r0 - 0.003) plus a flipping part: F = (-F0 + (-1)^n A) x, so
 * the port's sign flips every step once A > F0 */
static void run(const char *what, int radial, edmi_real r0, edmi_real amp, int fallback,
                int l_max, long steps, edmi_scheme sch)
{
    edmi_params prm = edmi_default_params();
    edmi_real q[3] = {EDMI_R(0.06), EDMI_R(0.01), 0}, p[3] = {0, EDMI_R(0.02), EDMI_R(0.01)};
    edmi_real x[3] = {0, 0, 0}, dir[3] = {EDMI_R(0.80178372573727319), EDMI_R(0.53452248382484879),
                                          EDMI_R(0.26726124191242440)};
    edmi_potential pot = edmi_pot_harmonic(EDMI_R(1e4), r0);
    edmi_step_result res;
    edmi_real qfb[3] = {0, 0, 0};
    hc_count c;
    c4_stats st;
    char buf[120];
    long n;
    int i, have_fb = 0;
    edmi_real f0 = 0, xprev;
    if (radial) {
        q[0] = EDMI_R(0.0005), q[1] = q[2] = 0;
        p[0] = p[1] = p[2] = 0;
        dir[0] = 1, dir[1] = dir[2] = 0;
    }
    if (radial == 2) {
        q[0] = EDMI_R(0.003), q[1] = EDMI_R(0.0003);
        f0 = EDMI_R(1e4) * (r0 - EDMI_R(0.003));
    }
    xprev = q[0];
    prm.scheme = sch;
    prm.fallback = fallback;
    prm.l_max = l_max;
    edmi_init(&sys, &prm);
    edmi_add_body(&sys, EDMI_R(0.1), q, p, 0);
    edmi_add_anchor(&sys, 0, x, &pot, 0);
    hc_reset(&c);
    memset(&st, 0, sizeof st);
    st.dmin = 1e30;
    for (n = 0; n < steps; n++) {
        edmi_real f[3];
        edmi_status s;
        double d;
        for (i = 0; i < 3; i++)
            f[i] = ((n & 1) ? -amp * dir[i] : amp * dir[i]) - f0 * dir[i];
        edmi_set_force(&sys, 0, f);
        s = hc_step(&sys, &work, EDMI_R(1e-3), &res, &c, 0, 0);
        d = hc_n3(sys.body[0].q);
        if (d < st.dmin) st.dmin = d;
        if (d > st.dmax) st.dmax = d;
        st.near += d < 0.01;
        st.cross += (sys.body[0].q[0] > 0) != (xprev > 0);
        xprev = sys.body[0].q[0];
        if (s == EDMI_OK && res.stop == EDMI_STOP_FALLBACK) {
            if (!have_fb) {
                have_fb = 1;
                memcpy(qfb, sys.body[0].q, sizeof qfb);
            } else {
                st.fb_after_first++;
            }
        }
        if (have_fb) {
            double dq = 0;
            for (i = 0; i < 3; i++)
                dq += fabs((double)sys.body[0].q[i] - (double)qfb[i]);
            if (dq > st.q_span) st.q_span = dq;
            st.moved_after_fb += s == EDMI_OK && res.stop != EDMI_STOP_FALLBACK;
        }
    }
    sprintf(buf, "%s %s A %g r0 %g lmax %d fb=%d", what, hc_scheme_name(sch), (double)amp,
            (double)r0, l_max, fallback);
    hc_print(buf, &c);
    printf("       d min %.3g max %.3g, steps with d < 0.01: %ld; after the first fallback: "
           "%ld solved steps, %ld more fallbacks, body moved up to %.3g; x crossed 0 %ld times\n",
           st.dmin, st.dmax, st.near, st.moved_after_fb, st.fb_after_first, st.q_span, st.cross);
    fflush(stdout);
}

int main(int argc, char **argv)
{
    static const edmi_real amps[] = {3, 30, 100, 300, 1000};
    static const edmi_real ramps[] = {20, 200, 2000, 20000};
    static const edmi_real hamps[] = {1, 10, 50, 235, 705, 940, 2000};
    long steps = argc > 1 ? atol(argv[1]) : 200000L;
    unsigned i;
    int fb;
    if (!EDMI_CONFIG_MATCHES()) return 2;
    for (i = 0; i < sizeof amps / sizeof amps[0]; i++)
        for (fb = 0; fb <= 1; fb++)
            run("(a) flip", 0, EDMI_R(0.05), amps[i], fb, 20, steps, EDMI_SCHEME_PM);
    for (i = 0; i < sizeof hamps / sizeof hamps[0]; i++)
        for (fb = 0; fb <= 1; fb++)
            run("(a2) held", 2, EDMI_R(0.05), hamps[i], fb, 20, steps, EDMI_SCHEME_PM);
    for (i = 0; i < sizeof ramps / sizeof ramps[0]; i++)
        for (fb = 0; fb <= 1; fb++) {
            run("(b) radial", 1, EDMI_R(0.05), ramps[i], fb, 20, steps, EDMI_SCHEME_PM);
            run("(b) radial", 1, EDMI_R(0.0), ramps[i], fb, 20, steps, EDMI_SCHEME_PM);
        }
    for (i = 0; i < sizeof amps / sizeof amps[0]; i += 2)
        run("(c) flip", 0, EDMI_R(0.05), amps[i], 1, 1, steps, EDMI_SCHEME_PM);
    for (i = 0; i < sizeof hamps / sizeof hamps[0]; i++)
        run("(c) held", 2, EDMI_R(0.05), hamps[i], 1, 1, steps, EDMI_SCHEME_PM);
    return 0;
}
