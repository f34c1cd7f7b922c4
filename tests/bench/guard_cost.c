/* What the passivity guard costs on the host, in instructions: `make guard-cost` runs this
 * program under valgrind --tool=callgrind in both precisions and divides the inclusive counts
 * of the loops below by their steps. The paper's spring (m = 10, q0 = (2,1,1),
 * p0 = (-30,15,45), neo-Hookean c = 1e3, rbar = 4, dt = 1e-3), 2000 steps each of PM with the
 * guard (the default), PM without it (EDMI_GUARD_OFF), and velocity Verlet with one force
 * evaluation per step for reference. Then systems at rest, guard on: a body (m 0.1) on a
 * zero-rest-length spring (k 1e4) with a damper (c 5) to an anchor, PM, dt 1e-3, settled for
 * 60,000 steps from 0.01 away, then 2000 steps measured: the anchor at the origin (the body
 * ends on a subnormal distance: certified on scaled values) and at (0.25, -1, 3) (the body
 * rests a few units in the last place off it: the guard holds it, EDMI_MOVE_HOLD). The loops
 * are noinline and must stay distinct functions (build with -fno-ipa-icf, or GCC merges the
 * identical edmi loops). */
#include <stdio.h>
#include "edmi.h"

#define GC_STEPS 2000
#define GC_SETTLE 60000

static edmi_system gc_sys;
static edmi_workspace gc_work;
static edmi_real gc_q[3], gc_p[3], gc_f[3];
static long gc_iterations;

static int gc_build(edmi_guard_mode g)
{
    static const edmi_real q[3] = {EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0)};
    static const edmi_real p[3] = {EDMI_R(-30.0), EDMI_R(15.0), EDMI_R(45.0)};
    static const edmi_real o[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot = edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0));
    edmi_params prm = edmi_default_params();
    prm.scheme = EDMI_SCHEME_PM;
    prm.guard = g;
    gc_iterations = 0;
    return edmi_init(&gc_sys, &prm) == EDMI_OK &&
           edmi_add_body(&gc_sys, EDMI_R(10.0), q, p, NULL) == EDMI_OK &&
           edmi_add_anchor(&gc_sys, 0, o, &pot, NULL) == EDMI_OK;
}

static int gc_steps(void)
{
    int k;
    for (k = 0; k < GC_STEPS; k++) {
        edmi_step_result r;
        if (edmi_step(&gc_sys, &gc_work, EDMI_R(1e-3), &r) != EDMI_OK)
            return 0;
        gc_iterations += r.iterations;
    }
    return 1;
}

__attribute__((noinline)) static int gc_pm_guard_on(void) { return gc_steps(); }

/* The body settled onto its anchor at x (see the banner) */
static int gc_build_rest(edmi_real x0, edmi_real x1, edmi_real x2)
{
    const edmi_real x[3] = {x0, x1, x2}, p[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real q[3];
    edmi_potential pot = edmi_pot_harmonic(EDMI_R(1e4), EDMI_R(0.0));
    edmi_params prm = edmi_default_params();
    int link, k;
    q[0] = x0 + EDMI_R(0.01);
    q[1] = x1;
    q[2] = x2;
    prm.scheme = EDMI_SCHEME_PM;
    if (edmi_init(&gc_sys, &prm) != EDMI_OK ||
        edmi_add_body(&gc_sys, EDMI_R(0.1), q, p, NULL) != EDMI_OK ||
        edmi_add_anchor(&gc_sys, 0, x, &pot, &link) != EDMI_OK ||
        edmi_add_damper(&gc_sys, link, EDMI_R(5.0), NULL) != EDMI_OK)
        return 0;
    for (k = 0; k < GC_SETTLE; k++)
        if (edmi_step(&gc_sys, &gc_work, EDMI_R(1e-3), NULL) != EDMI_OK)
            return 0;
    gc_iterations = 0;
    return 1;
}

__attribute__((noinline)) static int gc_rest_origin(void) { return gc_steps(); }

__attribute__((noinline)) static int gc_rest_off(void)
{
    int ok = gc_steps();
    return ok;
}

__attribute__((noinline)) static int gc_pm_guard_off(void)
{
    int ok = gc_steps();
    return ok;
}

/* V = c rbar^2/6 ((r/rbar)^2 + 2 rbar/r - 3): V'(r) = c/3 (r - rbar^3/r^2), F = -V'(r) q/r. */
static void gc_force(const edmi_real q[3], edmi_real f[3])
{
    const edmi_real c = EDMI_R(1e3), rb = EDMI_R(4.0);
    edmi_real r2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2], r = EDMI_SQRT(r2);
    edmi_real s = -(c / EDMI_R(3.0)) * (r - rb * rb * rb / r2) / r;
    int i;
    for (i = 0; i < 3; i++)
        f[i] = s * q[i];
}

__attribute__((noinline)) static void gc_verlet(void)
{
    const edmi_real dt = EDMI_R(1e-3), m = EDMI_R(10.0);
    int k, i;
    for (k = 0; k < GC_STEPS; k++) {
        for (i = 0; i < 3; i++) {
            gc_p[i] += EDMI_R(0.5) * dt * gc_f[i];
            gc_q[i] += dt / m * gc_p[i];
        }
        gc_force(gc_q, gc_f);
        for (i = 0; i < 3; i++)
            gc_p[i] += EDMI_R(0.5) * dt * gc_f[i];
    }
}

int main(void)
{
    int i;
    if (!gc_build(EDMI_GUARD_AUTO) || !gc_pm_guard_on())
        return 1;
    printf("PM, guard on:  %d steps, %.2f Newton corrections per step\n", GC_STEPS,
           (double)gc_iterations / GC_STEPS);
    if (!gc_build(EDMI_GUARD_OFF) || !gc_pm_guard_off())
        return 1;
    printf("PM, guard off: %d steps, %.2f Newton corrections per step\n", GC_STEPS,
           (double)gc_iterations / GC_STEPS);
    for (i = 0; i < 3; i++) {
        gc_q[i] = i == 0 ? EDMI_R(2.0) : EDMI_R(1.0);
        gc_p[i] = i == 0 ? EDMI_R(-30.0) : i == 1 ? EDMI_R(15.0) : EDMI_R(45.0);
    }
    gc_force(gc_q, gc_f);
    gc_verlet();
    printf("velocity Verlet: %d steps\n", GC_STEPS);
    if (!gc_build_rest(EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)) || !gc_rest_origin())
        return 1;
    printf("at rest on an anchor at the origin: %d steps, %.2f Newton corrections per step\n",
           GC_STEPS, (double)gc_iterations / GC_STEPS);
    if (!gc_build_rest(EDMI_R(0.25), EDMI_R(-1.0), EDMI_R(3.0)) || !gc_rest_off())
        return 1;
    printf("at rest on an anchor at (0.25, -1, 3): %d steps, %.2f Newton corrections per step\n",
           GC_STEPS, (double)gc_iterations / GC_STEPS);
    return 0;
}
