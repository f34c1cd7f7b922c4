/* tool_on_wall.c: a hand presses a tool into a wall through the README's virtual coupling
 * (`make haptic-wall`; docs/contact.md, "A tool pressed into a wall").
 *
 * The coupling and the hand are examples/haptic.c's (examples/haptic_hand.h): a tool of
 * 0.1 kg on a zero-rest-length spring of 3000 N/m with a 0.5 N s/m damper to an anchor that
 * follows the hand, 1 kHz, 6 s, one axis. Here a wall stands at x = 40 mm (normal -x, the
 * contact potential k/3 (-g)^3 of the gap g = 0.04 - x, k = 1e8 N/m^2): the hand reaches up to
 * 57 mm, so it presses the tool into the wall with up to 51 N, and its flicks throw the tool
 * against it. Each scheme, with the fallback and three levels of substeps on; the anchor is
 * moved to the hand's position at the tick's end (what edmi's promise is stated on: the
 * environment is passive with respect to its anchors' paths; README, Recipe 3, for what a
 * device's loop adds).
 *
 * Printed per scheme: ticks that failed, were split into substeps or fell back; the guard's
 * moves; the largest E_inj = H_n - H_0 - (the hand's work up to n), H of the stored states in
 * long double (the tool's K, the spring's and the wall's V; the works as reported, which are
 * rounded down) over ticks 1 to 6,000; the deepest the tool went into the wall and the
 * largest force on it. E_inj must stay <= 0 for GE, PM and PT (within long double's rounding of
 * the terms, 1e-15 J): the program fails otherwise, or on a failed tick. Needs the library built with walls
 * (-DEDMI_MAX_WALLS=1 or more). */
#include <math.h>
#include <stdio.h>
#include "edmi.h"
#include "haptic_hand.h"

#define TW_WALL ((long double)HH_WALL_X) /* the wall's position [m] */
#define TW_K ((long double)HH_WALL_K)    /* its contact stiffness [N/m^2] */

static edmi_system tw_sys;
static edmi_workspace tw_work;

/* H of the stored state in long double: the tool's K, the coupling's and the wall's V. */
static long double tw_h(const edmi_system *s)
{
    long double p = s->body[0].p[0], e = (long double)s->body[0].q[0] - s->link[0].anchor[0];
    long double pen = (long double)s->body[0].q[0] - TW_WALL, h;
    h = p * p / (2.0L * HH_MASS) + 0.5L * HH_STIFFNESS * e * e;
    return pen > 0.0L ? h + TW_K / 3.0L * pen * pen * pen : h;
}

typedef struct tw_run {
    long failed, split, fallbacks, moves, iterations;
    long double e_max, depth, force;
} tw_run;

static int tw_simulate(edmi_scheme scheme, tw_run *r)
{
    edmi_params prm = edmi_default_params();
    edmi_potential spring = edmi_pot_harmonic(HH_STIFFNESS, EDMI_R(0.0));
    edmi_potential wall = edmi_pot_contact(HH_WALL_K, EDMI_R(0.0));
    const edmi_real n[3] = {EDMI_R(-1.0), 0, 0}, zero[3] = {0, 0, 0};
    long double h0, work = 0.0L;
    long t;
    r->failed = r->split = r->fallbacks = r->moves = r->iterations = 0;
    r->e_max = r->depth = r->force = 0.0L;
    prm.scheme = scheme;
    prm.fallback = 1;
    prm.substep_levels = 3;
    if (edmi_init(&tw_sys, &prm) != EDMI_OK ||
        edmi_add_body(&tw_sys, HH_MASS, zero, zero, NULL) != EDMI_OK ||
        edmi_add_anchor(&tw_sys, 0, zero, &spring, NULL) != EDMI_OK ||
        edmi_add_damper(&tw_sys, 0, HH_DAMPING, NULL) != EDMI_OK ||
        edmi_add_wall(&tw_sys, 0, n, -HH_WALL_X, &wall, NULL) != EDMI_OK)
        return 0;
    h0 = tw_h(&tw_sys);
    for (t = 1; t <= HH_TICKS; t++) {
        edmi_real x[3] = {0, 0, 0};
        edmi_step_result res;
        long double e;
        x[0] = hh_position((edmi_real)t * HH_DT);
        if (edmi_move_anchor(&tw_sys, 0, x) != EDMI_OK ||
            edmi_step(&tw_sys, &tw_work, HH_DT, &res) != EDMI_OK) {
            r->failed++;
            continue;
        }
        r->split += res.substeps > 1;
        r->fallbacks += res.fallbacks;
        r->moves += res.guard_action != 0;
        r->iterations += res.iterations;
        work += (long double)res.work_anchor;
        e = tw_h(&tw_sys) - h0 - work;
        r->e_max = t == 1 ? e : fmaxl(r->e_max, e);
        r->depth = fmaxl(r->depth, (long double)tw_sys.body[0].q[0] - TW_WALL);
#if EDMI_MAX_WALLS > 0 /* (a build without walls compiles this program, and says so in main) */
        r->force = fmaxl(r->force, (long double)tw_sys.wall_force[0][0]); /* along -n on the tool */
#endif
    }
    return 1;
}

int main(void)
{
    static const edmi_scheme schemes[5] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    static const char *const names[5] = {"MP", "LG", "GE", "PM", "PT"};
    int s, bad = 0;
    if (!EDMI_CONFIG_MATCHES() || EDMI_MAX_WALLS < 1) {
        fprintf(stderr, "tool_on_wall: needs the library built with -DEDMI_MAX_WALLS=1 or more\n");
        return 2;
    }
    printf("A hand presses a tool into a wall at x = 40 mm through the README's coupling (%s):\n"
           "%ld ticks of 1 ms, the fallback and 3 levels of substeps on.\n\n",
           edmi_is_double_precision() ? "double" : "float", HH_TICKS);
    printf("| scheme | failed | split | fallbacks | guard moves | Newton iterations/tick |"
           " max E_inj [J] | deepest [mm] | largest wall force [N] |\n"
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (s = 0; s < 5; s++) {
        tw_run r;
        int decaying = schemes[s] != EDMI_SCHEME_MP && schemes[s] != EDMI_SCHEME_LG;
        if (!tw_simulate(schemes[s], &r)) {
            printf("| %s | could not build the scene |\n", names[s]);
            bad = 1;
            continue;
        }
        printf("| %s | %ld | %ld | %ld | %ld | %.2f | %.3Le | %.3Lf | %.1Lf |\n", names[s],
               r.failed, r.split, r.fallbacks, r.moves, (double)r.iterations / (double)HH_TICKS,
               r.e_max, 1e3L * r.depth, r.force);
        if (r.failed > 0 || (decaying && r.e_max > 1e-15L))
            bad = 1;
    }
    printf("\nE_inj = H_n - H_0 - the hand's work: GE, PM and PT keep it <= 0 (the program fails"
           " otherwise);\nMP and LG are not guarded by default.\n");
    return bad;
}
