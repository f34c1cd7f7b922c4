/* The coupled-body Newton solve and reproducibility.
 *
 * edmi eliminates only inside the band the links occupy, so the body numbering changes the
 * work but must not change the answer: a chain numbered 0,1,2,... (half-bandwidth 5) and the
 * same chain numbered so that neighbours are far apart in index (the band is the whole
 * matrix) must move identically up to round-off. And the same inputs must give bit-identical
 * results (no fast-math, -ffp-contract=off). */
#include <string.h>
#include "harness.h"
#include "suites.h"

#define SOLVER_N 8 /* bodies in the chain; fits the default EDMI_MAX_BODIES */

static edmi_system sys_a, sys_b;
static edmi_workspace work_solver;

/* Body number of chain position i: identity, or an interleaving that puts neighbours
 * SOLVER_N/2 apart (0,4,1,5,2,6,3,7 -> positions). */
static int solver_slot(int i, int scrambled)
{
    if (!scrambled)
        return i;
    return (i % 2) ? SOLVER_N / 2 + i / 2 : i / 2;
}

/* A quartic-spring chain (nonlinear, with a non-trivial convex/concave split) whose bodies
 * get different transverse momenta; body masses vary so the Newton rows are scaled unevenly. */
static void solver_build(edmi_system *s, edmi_scheme scheme, int scrambled)
{
    edmi_params prm = edmi_default_params();
    edmi_potential spring = edmi_pot_quartic(EDMI_R(40.0), EDMI_R(1.0));
    int slot_of[SOLVER_N], i;
    prm.scheme = scheme;
    CHECK_STATUS(edmi_init(s, &prm), EDMI_OK);
    for (i = 0; i < SOLVER_N; i++)
        slot_of[solver_slot(i, scrambled)] = i;
    for (i = 0; i < SOLVER_N; i++) {
        int pos = slot_of[i]; /* chain position of body number i */
        edmi_real q[3], p[3];
        q[0] = (edmi_real)pos;
        q[1] = EDMI_R(0.05) * (edmi_real)(pos % 3);
        q[2] = EDMI_R(0.0);
        p[0] = EDMI_R(0.1) * (edmi_real)(pos % 2);
        p[1] = (pos % 2) ? EDMI_R(0.4) : EDMI_R(-0.3);
        p[2] = EDMI_R(0.1) * (edmi_real)(pos % 4) - EDMI_R(0.15);
        CHECK_STATUS(edmi_add_body(s, EDMI_R(1.0) + EDMI_R(0.25) * (edmi_real)pos, q, p, NULL),
                     EDMI_OK);
    }
    for (i = 0; i + 1 < SOLVER_N; i++)
        CHECK_STATUS(edmi_add_pair(s, solver_slot(i, scrambled), solver_slot(i + 1, scrambled),
                                   &spring, NULL),
                     EDMI_OK);
}

static edmi_real solver_abs(edmi_real x) { return x < EDMI_R(0.0) ? -x : x; }

/* Numbering independence: 200 steps of dt = 0.01 in both numberings. The two runs solve
 * the same equations with eliminations of different order, so they differ only by round-off
 * amplified by the solve: allow 1e3 eps relative to the state's scale (positions ~ 8,
 * momenta ~ 1), far below the ~1e-2 that a wrong solve would produce. */
static void solver_numbering(edmi_scheme scheme)
{
    static const edmi_real tol_rel = EDMI_R(1000.0) * EDMI_EPS;
    edmi_real worst = EDMI_R(0.0);
    int k, i, c, iters_max = 0;
    edmi_step_result ra, rb;
    solver_build(&sys_a, scheme, 0);
    solver_build(&sys_b, scheme, 1);
    for (k = 0; k < 200; k++) {
        if (!CHECK_STATUS(edmi_step(&sys_a, &work_solver, EDMI_R(0.01), &ra), EDMI_OK) ||
            !CHECK_STATUS(edmi_step(&sys_b, &work_solver, EDMI_R(0.01), &rb), EDMI_OK))
            return;
        if (ra.iterations > iters_max)
            iters_max = ra.iterations;
        if (rb.iterations > iters_max)
            iters_max = rb.iterations;
    }
    for (i = 0; i < SOLVER_N; i++) {
        const edmi_body *ba = &sys_a.body[i], *bb = &sys_b.body[solver_slot(i, 1)];
        for (c = 0; c < 3; c++) {
            edmi_real dq = solver_abs(ba->q[c] - bb->q[c]) / EDMI_R(8.0);
            edmi_real dp = solver_abs(ba->p[c] - bb->p[c]);
            if (dq > worst)
                worst = dq;
            if (dp > worst)
                worst = dp;
        }
    }
    th_note_real("numbering: largest scaled difference", worst);
    CHECK(worst <= tol_rel);
    /* Quadratic Newton with an exact solve: a chain at dt = 0.01 needs few corrections. */
    th_note_int("numbering: most Newton iterations in a step", iters_max);
    CHECK(iters_max <= 4);
}

/* Same inputs, same bits: two independent runs compared with memcmp. */
static void solver_bitwise(void)
{
    int k;
    solver_build(&sys_a, EDMI_PT, 1);
    solver_build(&sys_b, EDMI_PT, 1);
    for (k = 0; k < 100; k++) {
        if (!CHECK_STATUS(edmi_step(&sys_a, &work_solver, EDMI_R(0.01), NULL), EDMI_OK))
            return;
    }
    memset(&work_solver, 0x5a, sizeof work_solver); /* stale scratch must not matter */
    for (k = 0; k < 100; k++) {
        if (!CHECK_STATUS(edmi_step(&sys_b, &work_solver, EDMI_R(0.01), NULL), EDMI_OK))
            return;
    }
    CHECK(memcmp(&sys_a, &sys_b, sizeof sys_a) == 0);
}

/* The state contract (edmi.h, edmi_body): between steps a firmware may write body[i].q and
 * .p (a tracked object, a reset); the next step starts from what was written exactly as a
 * system built with that state would, and a non-finite write is refused with the system
 * unchanged. */
static void solver_state_writes(void)
{
    static edmi_system before;
    int k, i;
    solver_build(&sys_a, EDMI_PM, 0);
    solver_build(&sys_b, EDMI_PM, 0);
    for (k = 0; k < 50; k++)
        if (!CHECK_STATUS(edmi_step(&sys_a, &work_solver, EDMI_R(0.01), NULL), EDMI_OK))
            return;
    for (i = 0; i < sys_a.n_bodies; i++) { /* b is built fresh; a has stepped: copy a's state */
        memcpy(sys_b.body[i].q, sys_a.body[i].q, sizeof sys_b.body[i].q);
        memcpy(sys_b.body[i].p, sys_a.body[i].p, sizeof sys_b.body[i].p);
    }
    CHECK_STATUS(edmi_set_tank(&sys_b, sys_a.tank), EDMI_OK); /* the tank is state too */
    for (k = 0; k < 50; k++) {
        if (!CHECK_STATUS(edmi_step(&sys_a, &work_solver, EDMI_R(0.01), NULL), EDMI_OK) ||
            !CHECK_STATUS(edmi_step(&sys_b, &work_solver, EDMI_R(0.01), NULL), EDMI_OK))
            return;
    }
    CHECK(memcmp(sys_a.body, sys_b.body, sizeof sys_a.body) == 0);
    sys_b.body[2].p[1] = sys_b.body[2].p[1] / EDMI_R(0.0) * EDMI_R(0.0); /* NaN */
    before = sys_b;
    CHECK_STATUS(edmi_step(&sys_b, &work_solver, EDMI_R(0.01), NULL), EDMI_ERR_NONFINITE);
    CHECK(memcmp(&before, &sys_b, sizeof sys_b) == 0);
}

void suite_solver(void)
{
    th_suite("solver: banded elimination, numbering, reproducibility");
    solver_numbering(EDMI_MP);
    solver_numbering(EDMI_LG);
    solver_numbering(EDMI_GE);
    solver_numbering(EDMI_PM);
    solver_numbering(EDMI_PT);
    solver_bitwise();
    solver_state_writes();
}
