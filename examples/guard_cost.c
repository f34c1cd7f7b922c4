/* What the passivity guard costs on the host, in instructions: `make guard-cost` runs this
 * program under valgrind --tool=callgrind in both precisions and divides the inclusive counts
 * of the three loops below by their steps. The paper's spring (m = 10, q0 = (2,1,1),
 * p0 = (-30,15,45), neo-Hookean c = 1e3, rbar = 4, dt = 1e-3), 1000 steps each of PM with the
 * guard (the default), PM without it (EDMI_GUARD_OFF), and velocity Verlet with one force
 * evaluation per step for reference. The loops are noinline and must stay distinct functions
 * (build with -fno-ipa-icf, or GCC merges the two identical edmi loops). */
#include <stdio.h>
#include "edmi.h"

#define GC_STEPS 1000

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
    prm.scheme = EDMI_PM;
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
    return 0;
}
