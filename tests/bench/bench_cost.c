/* bench_cost: one case of the host cost benchmark, for callgrind (`make bench`, driven by
 * tests/bench/bench_cost.sh, which runs this program under
 * valgrind --tool=callgrind --toggle-collect=bc_run and divides the instructions counted
 * inside bc_run() by the steps).
 *
 *   bench_cost SCENE METHOD N STEPS
 *     SCENE   spring | lj2 | solar | pairs (N bodies, all pairs: tests/lib/bench_scenes.h)
 *     METHOD  mp | lg | ge | pm | pt (edmi_step, edmi_default_params() with that scheme)
 *             | verlet (bs_verlet_step: one closed-form force evaluation per step)
 * Prints "corrections C links L" (Newton corrections summed over the steps, the scene's
 * link count) for the driver. Exit 1 on a failed step or bad arguments. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "edmi.h"
#include "bench_scenes.h"

static edmi_system bc_sys;
static edmi_workspace bc_work;

/* The measured loop: kept out of line so that callgrind can count it alone. */
__attribute__((noinline)) static long bc_run(int verlet, edmi_real dt, int steps)
{
    long its = 0;
    int k;
    for (k = 0; k < steps; k++) {
        edmi_step_result r;
        if (verlet) {
            bs_verlet_step(&bc_sys, dt);
            continue;
        }
        if (edmi_step(&bc_sys, &bc_work, dt, &r) != EDMI_OK)
            return -1;
        its += r.iterations;
    }
    return its;
}

int main(int argc, char **argv)
{
    static const char *const methods[] = {"mp", "lg", "ge", "pm", "pt", "verlet"};
    edmi_scheme scheme = EDMI_SCHEME_MP;
    edmi_status s;
    edmi_real dt;
    int m, n, steps, verlet;
    long its;
    if (argc != 5) {
        fprintf(stderr, "usage: bench_cost spring|lj2|solar|pairs METHOD N STEPS\n");
        return 1;
    }
    for (m = 0; m < 6 && strcmp(argv[2], methods[m]) != 0; m++)
        ;
    n = atoi(argv[3]);
    steps = atoi(argv[4]);
    if (m == 6 || steps < 1) {
        fprintf(stderr, "bench_cost: bad method or steps\n");
        return 1;
    }
    verlet = m == 5;
    if (!verlet)
        scheme = (edmi_scheme)m;
    if (strcmp(argv[1], "spring") == 0) {
        s = bs_spring(&bc_sys, scheme);
        dt = EDMI_R(1e-3);
    } else if (strcmp(argv[1], "lj2") == 0) {
        s = bs_lj2(&bc_sys, scheme);
        dt = EDMI_R(1e-3);
    } else if (strcmp(argv[1], "solar") == 0) {
        s = bs_solar(&bc_sys, scheme);
        dt = BS_SOLAR_DT;
    } else if (strcmp(argv[1], "pairs") == 0 && n >= 2 && n <= EDMI_MAX_BODIES &&
               n * (n - 1) / 2 <= EDMI_MAX_LINKS) {
        s = bs_pairs(&bc_sys, n, scheme);
        dt = BS_PAIRS_DT;
    } else {
        fprintf(stderr, "bench_cost: bad scene or N\n");
        return 1;
    }
    if (s != EDMI_OK) {
        fprintf(stderr, "bench_cost: scene: %s\n", edmi_status_name(s));
        return 1;
    }
    bs_verlet_start(&bc_sys);
    its = bc_run(verlet, dt, steps);
    if (its < 0) {
        fprintf(stderr, "bench_cost: %s %s: a step failed\n", argv[1], argv[2]);
        return 1;
    }
    printf("corrections %ld links %d\n", its, bc_sys.n_links);
    return 0;
}
