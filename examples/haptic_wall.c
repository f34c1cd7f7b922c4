/* haptic_wall.c: a model haptic device touching a stiff wall in a 1 kHz loop, with the wall
 * rendered explicitly (F = K x each tick, as most haptic code does) and with an edmi wall
 * behind a virtual coupling (`make haptic-wall`; docs/contact.md, "The haptic loop").
 *
 * The device is a mass md = 0.1 kg with viscous damping b, driven by the force the loop
 * renders, held over each tick of T = 1 ms (zero-order hold); between ticks its motion is
 * the exact solution of md v' = -b v + F. It enters the wall x = 0 at 0.1 m/s and
 * bounces out, or comes to rest in it. The closed loop is passive when the device leaves the wall with no more kinetic
 * energy than it arrived with: e^2 = KE_out / KE_in <= 1, both taken where it crosses x = 0
 * (found within 1/200 of a tick). Colgate and Schenkel: a sampled wall of stiffness K is
 * passive only if b > K T / 2.
 *   explicit: F_k = K max(0, -x_k), x_k the position at the tick's start;
 *   edmi:     a tool of 0.02 kg (PM, guard on) tied to the device's position at the tick's
 *             start by a spring Kc = 3000 N/m and a damper of 0.5 N s/m (the README's
 *             coupling), against an edmi wall x = 0 with the contact potential k/3 (-g)^3;
 *             the device feels the coupling's mean force of the last tick.
 * Prints e^2 for each (stiffness, b); with --csv FILE also a table for the figure
 * (examples/plots/haptic_wall.gp). Needs a library built with walls (-DEDMI_MAX_WALLS=1). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "edmi.h"

#define HW_T 1e-3   /* tick [s] */
#define HW_MD 0.1   /* device mass [kg] */
#define HW_SUB 200  /* substeps of a tick to find the crossings */
#define HW_TICKS 4000

static edmi_system hw_sys;
static edmi_workspace hw_work;

/* The device's exact motion over time h under the constant force f with damping b. */
static void hw_move(double *x, double *v, double f, double b, double h)
{
    if (b > 0.0) {
        double a = b / HW_MD, e = exp(-a * h), vinf = f / b;
        *x += vinf * h + (*v - vinf) * (1.0 - e) / a;
        *v = vinf + (*v - vinf) * e;
    } else {
        *x += *v * h + 0.5 * f / HW_MD * h * h;
        *v += f / HW_MD * h;
    }
}

/* One bounce: the device from the wall's surface, x = 0, at -0.1 m/s into it. kind 0: explicit wall of stiffness k;
 * kind 1: edmi, wall stiffness k. Returns e^2, or -1 if the device did not leave the wall
 * within HW_TICKS (at rest in it: passive), -2 if edmi failed. */
static double hw_bounce(int kind, double k, double b)
{
    double x = 0.0, v = -0.1, f = 0.0, ke_in = -1.0;
    long t;
    int s, in = 0;
    if (kind == 1) {
        edmi_params prm = edmi_default_params();
        edmi_real q[3] = {0, 0, 0}, p[3] = {0, 0, 0}, n[3] = {1, 0, 0};
        edmi_potential spring = edmi_pot_harmonic((edmi_real)3000.0, (edmi_real)0.0);
        edmi_potential wall = edmi_pot_contact((edmi_real)k, (edmi_real)0.0);
        int link;
        q[0] = (edmi_real)x;
        p[0] = (edmi_real)(0.02 * v);
        prm.fallback = 1;
        prm.substep_levels = 3;
        if (edmi_init(&hw_sys, &prm) != EDMI_OK ||
            edmi_add_body(&hw_sys, (edmi_real)0.02, q, p, NULL) != EDMI_OK ||
            edmi_add_anchor(&hw_sys, 0, q, &spring, &link) != EDMI_OK ||
            edmi_add_damper(&hw_sys, link, (edmi_real)0.5, NULL) != EDMI_OK ||
            edmi_add_wall(&hw_sys, 0, n, (edmi_real)0.0, &wall, NULL) != EDMI_OK)
            return -2.0;
    }
    for (t = 0; t < HW_TICKS; t++) {
        if (kind == 0) {
            f = x < 0.0 ? -k * x : 0.0; /* sampled at the tick's start, held */
        } else {
            edmi_real a[3] = {0, 0, 0};
            edmi_step_result res;
            a[0] = (edmi_real)x; /* the device as measured now: the anchor gets there */
            if (edmi_move_anchor(&hw_sys, 0, a) != EDMI_OK ||
                edmi_step(&hw_sys, &hw_work, (edmi_real)HW_T, &res) != EDMI_OK)
                return -2.0;
            f = (double)hw_sys.link_force[0][0]; /* the coupling's pull on the device */
        }
        for (s = 0; s < HW_SUB; s++) {
            double x0 = x, v0 = v;
            hw_move(&x, &v, f, b, HW_T / HW_SUB);
            if (!in && x0 >= 0.0 && x < 0.0) { /* arrives: interpolate the crossing */
                double w = x0 / (x0 - x), vc = v0 + w * (v - v0);
                ke_in = 0.5 * HW_MD * vc * vc;
                in = 1;
            } else if (in && x0 < 0.0 && x >= 0.0) { /* leaves */
                double w = x0 / (x0 - x), vc = v0 + w * (v - v0);
                return 0.5 * HW_MD * vc * vc / ke_in;
            }
        }
    }
    return -1.0;
}

int main(int argc, char **argv)
{
    static const double bs[] = {0.0,  0.1, 0.25, 0.5, 1.0, 1.5, 2.0, 2.5,
                                3.0, 5.0, 7.5,  10., 15., 20.};
    static const double ks[] = {300.0, 1000.0, 3000.0, 10000.0, 30000.0};
    static const double kw[] = {1e6, 1e8, 1e10, 1e12};
    const int nb = (int)(sizeof bs / sizeof bs[0]);
    FILE *csv = NULL;
    int i, j, bad = 0;
    if (argc == 3 && strcmp(argv[1], "--csv") == 0) {
        csv = fopen(argv[2], "w");
        if (!csv) {
            fprintf(stderr, "haptic_wall: cannot write %s\n", argv[2]);
            return 2;
        }
        fprintf(csv, "kind,stiffness,b,e2\n");
    } else if (argc != 1) {
        fprintf(stderr, "usage: haptic_wall [--csv FILE]\n");
        return 2;
    }
    if (!EDMI_CONFIG_MATCHES() || EDMI_MAX_WALLS < 1) {
        fprintf(stderr, "haptic_wall: needs the library built with -DEDMI_MAX_WALLS=1 or more\n");
        return 2;
    }
    printf("A device of 0.1 kg with damping b [N s/m] bounces on a wall at 1 kHz: e^2 = KE out /"
           " KE in\n(> 1: the loop created energy; Colgate and Schenkel: passive only if"
           " b > K T / 2).\n\n");
    printf("| b | explicit K = 300 | 1e3 | 3e3 | 1e4 | 3e4 N/m | edmi, Kc = 3e3 N/m, wall k = 1e6 |"
           " 1e8 | 1e10 | 1e12 N/m^2 |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (i = 0; i < nb; i++) {
        printf("| %.2f |", bs[i]);
        for (j = 0; j < 9; j++) {
            int kind = j < 5 ? 0 : 1;
            double k = kind == 0 ? ks[j] : kw[j - 5], e2 = hw_bounce(kind, k, bs[i]);
            if (e2 == -2.0)
                bad = 1;
            if (e2 < 0.0)
                printf(" %s |", e2 == -1.0 ? "stays" : "FAILED");
            else
                printf(" %.3f%s |", e2, e2 > 1.0 ? " A" : "");
            if (csv)
                fprintf(csv, "%d,%g,%g,%.6f\n", kind, k, bs[i], e2);
        }
        printf("\n");
    }
    printf("\nA: active (the loop returned more energy than the device brought); stays: the device"
           " came to\nrest in the wall. Colgate and Schenkel's bound b > K T / 2 + B (B the wall's"
           " damping): explicit\n0.15, 0.5, 1.5, 5, 15 N s/m, growing with the wall; behind the"
           " coupling it is set by the\ncoupling (Kc T / 2 + c = 2 N s/m), not by the edmi wall's"
           " stiffness.\n");
    if (csv)
        fclose(csv);
    return bad;
}
