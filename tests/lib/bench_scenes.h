/* bench_scenes.h: the scenes the two cost benchmarks share, and a velocity-Verlet step on
 * the same system data (`make bench` on the host under callgrind, tests/bench/bench_cost.c;
 * `make bench-target` under QEMU, tests/bench/bench_target.c), so that both count the same work.
 *
 *   bs_spring(sys, scheme):    the paper's spring: m = 10, q0 = (2, 1, 1), p0 = (-30, 15, 45),
 *                              neo-Hookean c = 1e3, rbar = 4 to an anchor at the origin,
 *                              dt = 1e-3;
 *   bs_lj2(sys, scheme):       the paper's Lennard-Jones pair: m = 1, q = (0, -+0.5612, 0),
 *                              p = (5, 0, 0) and (10, 0, 0), eps = 100, sigma = 1, dt = 1e-3;
 *   bs_pairs(sys, n, scheme):  n unit masses on a loose grid (spacing 10), all n(n-1)/2
 *                              pairs attracting with V = -0.01/r, dt = BS_PAIRS_DT (0.05):
 *                              the all-pairs scene (n = 10: 45 pairs);
 *   bs_solar(sys, scheme):     the Sun and nine planets of examples/scenes/solar_system.scene
 *                              (JPL DE430 at JD 2440400.5; solar masses, AU, days), all 45
 *                              pairs V = -G m_A m_B / r, dt = BS_SOLAR_DT (5 days).
 * Both use edmi_default_params() with the given scheme (Newton to convergence).
 *
 * bs_verlet_step(sys, dt): one velocity-Verlet step of the system's bodies and links (pair
 * and anchor links of the built-in potentials, forces F = -V'(r) r/|r| in closed form, no
 * field, ports or dampers), one force evaluation per step: the forces at the end of a step
 * are kept (bs_verlet_f) for the next. bs_verlet_start(sys) evaluates them once first.
 * Freestanding C99: no library calls beyond EDMI_SQRT. Include in one translation unit. */
#ifndef EDMI_BENCH_SCENES_H
#define EDMI_BENCH_SCENES_H

#include "edmi.h"

#define BS_PAIRS_DT EDMI_R(0.05)
#define BS_SOLAR_DT EDMI_R(5.0)

static edmi_status bs_spring(edmi_system *sys, edmi_scheme scheme)
{
    static const edmi_real q[3] = {EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0)};
    static const edmi_real p[3] = {EDMI_R(-30.0), EDMI_R(15.0), EDMI_R(45.0)};
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot = edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0));
    edmi_params prm = edmi_default_params();
    edmi_status s;
    prm.scheme = scheme;
    s = edmi_init(sys, &prm);
    if (s == EDMI_OK)
        s = edmi_add_body(sys, EDMI_R(10.0), q, p, NULL);
    if (s == EDMI_OK)
        s = edmi_add_anchor(sys, 0, origin, &pot, NULL);
    return s;
}

static edmi_status bs_lj2(edmi_system *sys, edmi_scheme scheme)
{
    static const edmi_real q1[3] = {EDMI_R(0.0), EDMI_R(-0.5612), EDMI_R(0.0)};
    static const edmi_real q2[3] = {EDMI_R(0.0), EDMI_R(0.5612), EDMI_R(0.0)};
    static const edmi_real p1[3] = {EDMI_R(5.0), EDMI_R(0.0), EDMI_R(0.0)};
    static const edmi_real p2[3] = {EDMI_R(10.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot = edmi_pot_lj(EDMI_R(100.0), EDMI_R(1.0));
    edmi_params prm = edmi_default_params();
    edmi_status s;
    prm.scheme = scheme;
    s = edmi_init(sys, &prm);
    if (s == EDMI_OK)
        s = edmi_add_body(sys, EDMI_R(1.0), q1, p1, NULL);
    if (s == EDMI_OK)
        s = edmi_add_body(sys, EDMI_R(1.0), q2, p2, NULL);
    if (s == EDMI_OK)
        s = edmi_add_pair(sys, 0, 1, &pot, NULL);
    return s;
}

static edmi_status bs_pairs(edmi_system *sys, int n, edmi_scheme scheme)
{
    edmi_params prm = edmi_default_params();
    edmi_potential g = edmi_pot_inverse(EDMI_R(0.01));
    edmi_status s;
    int a, b;
    prm.scheme = scheme;
    s = edmi_init(sys, &prm);
    for (a = 0; a < n && s == EDMI_OK; a++) {
        edmi_real q[3], p[3];
        q[0] = EDMI_R(10.0) * (edmi_real)(a % 7) + EDMI_R(0.1) * (edmi_real)a;
        q[1] = EDMI_R(10.0) * (edmi_real)(a / 7) + EDMI_R(0.05) * (edmi_real)(a % 3);
        q[2] = EDMI_R(0.2) * (edmi_real)(a % 5);
        p[0] = EDMI_R(0.01) * ((edmi_real)(a % 4) - EDMI_R(1.5));
        p[1] = EDMI_R(0.01) * ((edmi_real)(a % 3) - EDMI_R(1.0));
        p[2] = EDMI_R(0.0);
        s = edmi_add_body(sys, EDMI_R(1.0), q, p, NULL);
    }
    for (a = 0; a < n && s == EDMI_OK; a++)
        for (b = a + 1; b < n && s == EDMI_OK; b++)
            s = edmi_add_pair(sys, a, b, &g, NULL);
    return s;
}

static edmi_status bs_solar(edmi_system *sys, edmi_scheme scheme)
{
    /* m, q, p per body, copied from examples/scenes/solar_system.scene */
    static const edmi_real body[10][7] = {
        {EDMI_R(0.9999999999986181), EDMI_R(0.0045025087846405545), EDMI_R(0.0007670764270910071),
         EDMI_R(0.00026605791776697764), EDMI_R(-3.517495360750339e-07),
         EDMI_R(5.177626409826255e-06), EDMI_R(2.22910217890895e-06)},
        {EDMI_R(1.6601141530520544e-07), EDMI_R(0.36176271656028197),
         EDMI_R(-0.09078197215676599), EDMI_R(-0.08571497256275117),
         EDMI_R(5.590424403244238e-10), EDMI_R(4.132774591125559e-09),
         EDMI_R(2.1492336539813373e-09)},
        {EDMI_R(2.447838287781389e-06), EDMI_R(0.6127519408350721), EDMI_R(-0.3483653690336222),
         EDMI_R(-0.19527828667594382), EDMI_R(2.680889241751397e-08),
         EDMI_R(3.822956551736756e-08), EDMI_R(1.549752294374032e-08)},
        {EDMI_R(3.04043264801844e-06), EDMI_R(0.12051741410138465), EDMI_R(-0.9258384747691486),
         EDMI_R(-0.40154022645315224), EDMI_R(5.111352902366442e-08),
         EDMI_R(5.3156164639567046e-09), EDMI_R(2.3052648430258408e-09)},
        {EDMI_R(3.2271560375505375e-07), EDMI_R(-0.11018607714879824),
         EDMI_R(-1.327599450302983), EDMI_R(-0.6058891404842914), EDMI_R(4.673455409676325e-09),
         EDMI_R(7.824661822958896e-11), EDMI_R(-9.08511316816652e-11)},
        {EDMI_R(0.000954791915209921), EDMI_R(-5.379706768553937), EDMI_R(-0.8304813265633979),
         EDMI_R(-0.22482887442656543), EDMI_R(1.0426447962852219e-06),
         EDMI_R(-6.223445044303965e-06), EDMI_R(-2.693260576006287e-06)},
        {EDMI_R(0.00028588567272184664), EDMI_R(7.894390682909531), EDMI_R(4.596478055171273),
         EDMI_R(1.5586958428319), EDMI_R(-9.198533092404258e-07),
         EDMI_R(1.2395460563445738e-06), EDMI_R(5.513723497380773e-07)},
        {EDMI_R(4.366243735825236e-05), EDMI_R(-18.26540225387236), EDMI_R(-1.16195541867587),
         EDMI_R(-0.25010605772133804), EDMI_R(9.65771159196662e-09),
         EDMI_R(-1.6427882935354247e-07), EDMI_R(-7.20873402126935e-08)},
        {EDMI_R(5.151383772621555e-05), EDMI_R(-16.055035780233368), EDMI_R(-23.94219155985471),
         EDMI_R(-9.400157968802395), EDMI_R(1.3613921709657993e-07),
         EDMI_R(-7.718382959172005e-08), EDMI_R(-3.4980057378092493e-08)},
        {EDMI_R(7.361781606079295e-09), EDMI_R(-30.48331376718384), EDMI_R(-0.87240555684105),
         EDMI_R(8.91157617249955), EDMI_R(2.372020315559084e-12),
         EDMI_R(-2.3142322872043263e-11), EDMI_R(-7.935630712481096e-12)}};
    const edmi_real G = EDMI_R(2.95912208286e-4);
    edmi_params prm = edmi_default_params();
    edmi_status s;
    int a, b;
    prm.scheme = scheme;
    s = edmi_init(sys, &prm);
    for (a = 0; a < 10 && s == EDMI_OK; a++)
        s = edmi_add_body(sys, body[a][0], &body[a][1], &body[a][4], NULL);
    for (a = 0; a < 10 && s == EDMI_OK; a++)
        for (b = a + 1; b < 10 && s == EDMI_OK; b++) {
            edmi_potential pot = edmi_pot_inverse(G * body[a][0] * body[b][0]);
            s = edmi_add_pair(sys, a, b, &pot, NULL);
        }
    return s;
}

/* V'(r) / r of a built-in potential, in closed form (0 for a user potential). */
static edmi_real bs_dv_over_r(const edmi_potential *pot, edmi_real r2)
{
    edmi_real r = EDMI_SQRT(r2), x;
    switch (pot->kind) {
    case EDMI_POT_HARMONIC:
        return pot->a * (r - pot->b) / r;
    case EDMI_POT_QUARTIC:
        return pot->a * (r2 - pot->b * pot->b);
    case EDMI_POT_NEO_HOOKE:
        return pot->a / EDMI_R(3.0) * (EDMI_R(1.0) - pot->b * pot->b * pot->b / (r2 * r));
    case EDMI_POT_LJ:
        x = pot->b * pot->b / r2;
        x = x * x * x;
        return EDMI_R(24.0) * pot->a * x * (EDMI_R(1.0) - EDMI_R(2.0) * x) / r2;
    case EDMI_POT_INVERSE:
        return pot->a / (r2 * r);
    case EDMI_POT_USER:
    default:
        return EDMI_R(0.0);
    }
}

static edmi_real bs_verlet_f[EDMI_MAX_BODIES][3];

static void bs_verlet_forces(const edmi_system *sys)
{
    int a, j, i;
    for (a = 0; a < sys->n_bodies; a++)
        for (i = 0; i < 3; i++)
            bs_verlet_f[a][i] = EDMI_R(0.0);
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        const edmi_real *qb = lk->b == EDMI_ANCHOR ? lk->anchor : sys->body[lk->b].q;
        edmi_real r[3], s;
        for (i = 0; i < 3; i++)
            r[i] = sys->body[lk->a].q[i] - qb[i];
        s = bs_dv_over_r(&lk->pot, r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        for (i = 0; i < 3; i++) {
            bs_verlet_f[lk->a][i] -= s * r[i];
            if (lk->b != EDMI_ANCHOR)
                bs_verlet_f[lk->b][i] += s * r[i];
        }
    }
}

static void bs_verlet_start(const edmi_system *sys) { bs_verlet_forces(sys); }

static void bs_verlet_step(edmi_system *sys, edmi_real dt)
{
    edmi_real h = EDMI_R(0.5) * dt;
    int a, i;
    for (a = 0; a < sys->n_bodies; a++) {
        edmi_body *bd = &sys->body[a];
        edmi_real c = dt / bd->m;
        for (i = 0; i < 3; i++) {
            bd->p[i] += h * bs_verlet_f[a][i];
            bd->q[i] += c * bd->p[i];
        }
    }
    bs_verlet_forces(sys);
    for (a = 0; a < sys->n_bodies; a++)
        for (i = 0; i < 3; i++)
            sys->body[a].p[i] += h * bs_verlet_f[a][i];
}

#endif
