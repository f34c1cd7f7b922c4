/*
 * bench_solver: what the coupled-body Newton solve costs, measured (`make bench`).
 *
 * edmi solves the Newton system of N bodies by Gaussian elimination with partial pivoting
 * restricted to the band that the links occupy (half-bandwidth 3 w + 2, w the largest body-
 * index gap of a pair link). This program times one step per scene for
 *   chain:  N bodies, N-1 springs between neighbours (w = 1: banded, cost ~ N),
 *   ring:   the same chain closed by one spring from body 0 to body N-1 (w = N-1: the band
 *           is the whole matrix, so this is what a dense solve of the same system costs),
 *   pairs:  N bodies with all N(N-1)/2 gravity links (dense by nature),
 * and prints microseconds per step, Newton iterations per step and link evaluations per
 * step. Build with large capacities (the Makefile passes -DEDMI_MAX_BODIES=128).
 * Hosted C: stdio and clock_gettime are fine here, not in the library.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "edmi.h"

static edmi_system sys;
static edmi_workspace work;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A chain of n unit masses along x at spacing 1, quartic springs of rest length 1, every
 * body given a small transverse momentum so that the springs stretch nonlinearly. */
static int build_chain(int n, int ring)
{
    edmi_params prm = edmi_default_params();
    edmi_potential spring = edmi_pot_quartic(EDMI_R(50.0), EDMI_R(1.0));
    int a;
    prm.scheme = EDMI_SCHEME_PM;
    if (edmi_init(&sys, &prm) != EDMI_OK)
        return 1;
    for (a = 0; a < n; a++) {
        edmi_real q[3], p[3];
        q[0] = (edmi_real)a;
        q[1] = EDMI_R(0.0);
        q[2] = EDMI_R(0.0);
        p[0] = EDMI_R(0.0);
        p[1] = (a % 2) ? EDMI_R(0.3) : EDMI_R(-0.3);
        p[2] = (a % 3) ? EDMI_R(0.1) : EDMI_R(-0.2);
        if (edmi_add_body(&sys, EDMI_R(1.0), q, p, NULL) != EDMI_OK)
            return 1;
    }
    for (a = 0; a + 1 < n; a++)
        if (edmi_add_pair(&sys, a, a + 1, &spring, NULL) != EDMI_OK)
            return 1;
    if (ring) {
        /* closing spring at its rest length n-1: forces the full bandwidth */
        edmi_potential close = edmi_pot_quartic(EDMI_R(50.0), (edmi_real)(n - 1));
        if (edmi_add_pair(&sys, 0, n - 1, &close, NULL) != EDMI_OK)
            return 1;
    }
    return 0;
}

/* n bodies on a loose grid (spacing 10), all pairs attracting weakly with -0.01/r so that
 * the run has no close encounter (a step across one needs a smaller dt). */
static int build_pairs(int n)
{
    edmi_params prm = edmi_default_params();
    int a, b;
    prm.scheme = EDMI_SCHEME_PM;
    if (edmi_init(&sys, &prm) != EDMI_OK)
        return 1;
    for (a = 0; a < n; a++) {
        edmi_real q[3], p[3];
        q[0] = (edmi_real)(10.0 * (double)(a % 7) + 0.1 * a);
        q[1] = (edmi_real)(10.0 * (double)(a / 7) + 0.05 * (a % 3));
        q[2] = (edmi_real)(0.2 * (a % 5));
        p[0] = (edmi_real)(0.01 * ((a % 4) - 1.5));
        p[1] = (edmi_real)(0.01 * ((a % 3) - 1.0));
        p[2] = EDMI_R(0.0);
        if (edmi_add_body(&sys, EDMI_R(1.0), q, p, NULL) != EDMI_OK)
            return 1;
    }
    for (a = 0; a < n; a++)
        for (b = a + 1; b < n; b++) {
            edmi_potential g = edmi_pot_inverse(EDMI_R(0.01));
            if (edmi_add_pair(&sys, a, b, &g, NULL) != EDMI_OK)
                return 1;
        }
    return 0;
}

/* Time `steps` steps; print one row. */
static int run(const char *scene, int n, edmi_real dt, int steps)
{
    long its = 0;
    int k;
    double t0, t1;
    edmi_step_result res;
    t0 = now_s();
    for (k = 0; k < steps; k++) {
        edmi_status st = edmi_step(&sys, &work, dt, &res);
        if (st != EDMI_OK) {
            fprintf(stderr, "bench_solver: %s n=%d step %d: %s\n", scene, n, k,
                    edmi_status_name(st));
            return 1;
        }
        its += res.iterations;
    }
    t1 = now_s();
    printf("| %-5s | %4d | %5d | %9.2f | %5.2f | %11.3f |\n", scene, n, sys.n_links,
           1e6 * (t1 - t0) / steps, (double)its / steps, 1e6 * (t1 - t0) / (double)its);
    return 0;
}

int main(void)
{
    static const int sizes[] = {8, 16, 32, 64, 128};
    size_t i;
    printf("edmi solver cost, EDMI_REAL=%s, PM scheme, host (-O2)\n",
           edmi_is_double_precision() ? "double" : "float");
    printf("| scene | N    | links | us/step   | it/st | us/iteration |\n");
    printf("|-------|------|-------|-----------|-------|--------------|\n");
    for (i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        int n = sizes[i];
        if (n > EDMI_MAX_BODIES)
            break;
        if (build_chain(n, 0) || run("chain", n, EDMI_R(0.01), 2000))
            return 1;
        if (build_chain(n, 1) || run("ring", n, EDMI_R(0.01), n > 64 ? 200 : 2000))
            return 1;
        if (n * (n - 1) / 2 <= EDMI_MAX_LINKS &&
            (build_pairs(n) || run("pairs", n, EDMI_R(0.05), n > 64 ? 100 : 1000)))
            return 1;
    }
    return 0;
}
