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

/* What solver_build needs of the build: the scheme and quartic links. */
static int solver_in(edmi_scheme scheme)
{
    return th_has_scheme(scheme) && th_has_pot(EDMI_POT_QUARTIC);
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
    TH_NEEDS(solver_in(scheme));
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
    TH_NEEDS(solver_in(EDMI_SCHEME_PT));
    solver_build(&sys_a, EDMI_SCHEME_PT, 1);
    solver_build(&sys_b, EDMI_SCHEME_PT, 1);
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
    TH_NEEDS(solver_in(EDMI_SCHEME_PM));
    solver_build(&sys_a, EDMI_SCHEME_PM, 0);
    solver_build(&sys_b, EDMI_SCHEME_PM, 0);
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

/* Factors kept from a system's last step (edmi.h, edmi_workspace). Ten unit masses, all 45
 * pairs V = -0.01/r (tests/lib/bench_scenes.h's all-pairs scene, dt = 0.05), PM: every step of
 * the system that keeps its factors in work_solver is checked against the same step from
 * the same state by a copy with its own workspace, which cannot reuse anything (its record
 * names another workspace), so that it solves from its own Newton matrix: the two solve the
 * same equations, so they may differ by their floors, not by more than 1e3 eps of the state's
 * scale (as the numbering test). Then the kept factors made stale or garbage: positions
 * written between steps (moved by 5 % and the momenta reversed), and the factors themselves
 * overwritten with a byte pattern as a stack-placed workspace might leave them; each step
 * must still agree with the fresh one. */
#define SOLVER_KEPT_N 10

static edmi_system sys_kept_copy;
static edmi_workspace work_fresh;

static void solver_kept_build(edmi_system *s)
{
    edmi_params prm = edmi_default_params();
    edmi_potential g = edmi_pot_inverse(EDMI_R(0.01));
    int a, b;
    prm.scheme = EDMI_SCHEME_PM;
    CHECK_STATUS(edmi_init(s, &prm), EDMI_OK);
    for (a = 0; a < SOLVER_KEPT_N; a++) {
        edmi_real q[3], p[3];
        q[0] = EDMI_R(10.0) * (edmi_real)(a % 7) + EDMI_R(0.1) * (edmi_real)a;
        q[1] = EDMI_R(10.0) * (edmi_real)(a / 7) + EDMI_R(0.05) * (edmi_real)(a % 3);
        q[2] = EDMI_R(0.2) * (edmi_real)(a % 5);
        p[0] = EDMI_R(0.01) * ((edmi_real)(a % 4) - EDMI_R(1.5));
        p[1] = EDMI_R(0.01) * ((edmi_real)(a % 3) - EDMI_R(1.0));
        p[2] = EDMI_R(0.0);
        CHECK_STATUS(edmi_add_body(s, EDMI_R(1.0), q, p, NULL), EDMI_OK);
    }
    for (a = 0; a < SOLVER_KEPT_N; a++)
        for (b = a + 1; b < SOLVER_KEPT_N; b++)
            CHECK_STATUS(edmi_add_pair(s, a, b, &g, NULL), EDMI_OK);
}

/* One step of sys_a with work_solver against its copy with work_fresh; the largest
 * difference relative to the scales (positions ~ 60, momenta ~ 0.02) into *worst. */
static int solver_kept_step(edmi_real *worst, int *its_kept, int *its_fresh)
{
    edmi_step_result rk, rf;
    int i, c;
    sys_kept_copy = sys_a;
    if (!CHECK_STATUS(edmi_step(&sys_kept_copy, &work_fresh, EDMI_R(0.05), &rf), EDMI_OK) ||
        !CHECK_STATUS(edmi_step(&sys_a, &work_solver, EDMI_R(0.05), &rk), EDMI_OK))
        return 0;
    *its_kept += rk.iterations;
    *its_fresh += rf.iterations;
    for (i = 0; i < SOLVER_KEPT_N; i++)
        for (c = 0; c < 3; c++) {
            edmi_real dq = solver_abs(sys_a.body[i].q[c] - sys_kept_copy.body[i].q[c]) /
                           EDMI_R(60.0);
            edmi_real dp = solver_abs(sys_a.body[i].p[c] - sys_kept_copy.body[i].p[c]) /
                           EDMI_R(0.02);
            *worst = dq > *worst ? dq : *worst;
            *worst = dp > *worst ? dp : *worst;
        }
    return 1;
}

static void solver_kept(void)
{
    static const edmi_real tol_rel = EDMI_R(1000.0) * EDMI_EPS;
    edmi_real worst = EDMI_R(0.0), worst_stale = EDMI_R(0.0);
    int k, i, c, its_kept = 0, its_fresh = 0, its_s = 0, its_sf = 0;
    TH_NEEDS(th_has_scheme(EDMI_SCHEME_PM) && th_has_pot(EDMI_POT_INVERSE));
    solver_kept_build(&sys_a);
    for (k = 0; k < 400; k++)
        if (!solver_kept_step(&worst, &its_kept, &its_fresh))
            return;
    /* the record says where the factors are: the system's own workspace, not the copy's */
    CHECK(sys_a.internal.kept_work == (const void *)&work_solver);
    CHECK(sys_kept_copy.internal.kept_work == (const void *)&work_fresh);
    th_note_real("kept factors: largest scaled difference from a fresh solve, 400 steps", worst);
    th_note_int("kept factors: Newton corrections in 400 steps (kept)", its_kept);
    th_note_int("kept factors: Newton corrections in 400 steps (fresh)", its_fresh);
    CHECK(worst <= tol_rel);
    for (k = 0; k < 20; k++) { /* stale: the state written between steps */
        if (k % 2 == 0)
            for (i = 0; i < SOLVER_KEPT_N; i++)
                for (c = 0; c < 3; c++) {
                    sys_a.body[i].q[c] *= EDMI_R(1.05);
                    sys_a.body[i].p[c] = -sys_a.body[i].p[c];
                }
        else
            memset(work_solver.mat, 0x5a, sizeof work_solver.mat); /* garbage factors */
        if (!solver_kept_step(&worst_stale, &its_s, &its_sf))
            return;
    }
    th_note_real("kept factors, stale or garbage: largest scaled difference", worst_stale);
    th_note_int("kept factors, stale or garbage: corrections in 20 steps (kept)", its_s);
    th_note_int("kept factors, stale or garbage: corrections in 20 steps (fresh)", its_sf);
    CHECK(worst_stale <= tol_rel);
}

void suite_solver(void)
{
    th_suite("solver: banded elimination, numbering, reproducibility");
    solver_numbering(EDMI_SCHEME_MP);
    solver_numbering(EDMI_SCHEME_LG);
    solver_numbering(EDMI_SCHEME_GE);
    solver_numbering(EDMI_SCHEME_PM);
    solver_numbering(EDMI_SCHEME_PT);
    solver_bitwise();
    solver_state_writes();
    solver_kept();
}
