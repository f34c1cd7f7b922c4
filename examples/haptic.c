/* A 1 kHz virtual coupling, the loop a haptic device runs (`make haptic`).
 *
 * The model, on one axis. A virtual tool of mass M = 0.1 kg is tied to the user's hand x(t)
 * by a zero-rest-length spring K = 3000 N/m (3 N/mm) with a damper B = 0.5 N s/m across it:
 *     M q'' = F = -K (q - x) - B (q' - x'),
 * resonance sqrt(K/M)/(2 pi) = 27.6 Hz, damping ratio B / (2 sqrt(K M)) = 0.014. The hand is
 * examples/haptic_hand.h: a slow reach, a 3 Hz wobble and five fast flicks over 6 s. The tool
 * starts at rest on the hand. Each method integrates the same model with dt = 1 ms
 * (omega dt = 0.17) for 6000 ticks, in edmi_real (float or double, as the library is built):
 *
 *   edmi PM    the library's perturbed mid-point scheme, passivity guard on (the default),
 *              fallback on: a body on edmi_pot_harmonic(K, 0) to an anchor moved to the
 *              hand's next position before each step, and edmi_add_damper(B) on that link.
 *              The hand is read at tick ends only; the damper acts on the step's
 *              displacement, so no hand velocity is needed. edmi's damper acts along its
 *              link: on one axis that is exactly B (q' - x'); in 3-D it would damp only the
 *              coupling's stretching, which is why this example keeps to one axis. For a
 *              harmonic spring PM is the mid-point rule (V'''' = 0: no scheme dissipation).
 *   explicit   forward Euler: f = F(q_n, v_n, x_n, x'_n); q += dt v_n; p += dt f.
 *   semi-impl. symplectic Euler: f = F(q_n, v_n, x_n, x'_n); p += dt f; q += dt p/M.
 *   Verlet     velocity Verlet, one force per tick: p_half = p + dt/2 f; q += dt p_half/M;
 *              f = F(q_n+1, p_half/M, x_n+1, x'_n+1); p = p_half + dt/2 f. The damper sees
 *              the half-step velocity, the usual explicit choice.
 * The explicit methods get the hand's exact velocity x'(t) for their dampers (a device would
 * have a filtered finite difference, which only adds lag).
 *
 * Energy bookkeeping. H = p^2/(2M) + K/2 (q - x)^2, the tool's kinetic energy plus the
 * spring's, evaluated in long double from the stored (edmi_real) values. The work the hand
 * does on the simulation in tick n is
 *     W_n = Fbar_n (x_n+1 - x_n),   Fbar_n = (p_n+1 - p_n) / dt,
 * where Fbar_n is the mean force the coupling put on the tool over the tick, so -Fbar_n is the
 * force it put on the hand: the force the method renders. For forward and semi-implicit Euler
 * Fbar_n = f_n, for Verlet the mean of its two half-kicks, and for edmi res.work_anchor
 * (= -link_force . (x_n+1 - x_n), correctly rounded; link_force is the same mean force).
 * Why this is the right bookkeeping: the coupling is the tool's only force, so the tool's
 * momentum change is the only impulse that crosses the port; rendering anything else would
 * let the user feel a force the tool never felt. With it, the continuous identity
 *     dH/dt = F x' - B (q' - x')^2
 * has the discrete analogue H_n+1 - H_n = W_n - (what the method dissipated), and
 *     E_inj(n) = (H_n - H_0) - sum_{k<n} W_k
 * is the energy the method created beyond the work it took from the hand. The exact model has
 * E_inj = -(energy the damper dissipated) <= 0 at all times; a passive simulation keeps it
 * <= 0 too.
 * The column "ticks with dH > W" counts ticks on which H_n+1 - H_n > W_n, i.e. the method was
 * active on its own. edmi's guarantee lets a tick rise by what its energy tank T (sys.tank)
 * held, H_n+1 - H_n <= W_n + T_n - T_n+1 with T_0 = 0, so E_inj(n) <= -T_n <= 0 at all times:
 * its ticks with dH > W (float: a few dozen) are covered by the tank, and the program checks
 * the tank inequality in long double on every tick (failing if it is broken by more than the
 * check's own resolution, 32 long double epsilons of the terms; a double state's tank margin
 * can lie below that resolution: such ticks are counted as unresolved, not as passed).
 *
 * What this bookkeeping does not cover: edmi (like Verlet) needs the hand's position at the
 * END of the tick to compute the tick's force, and a device knows it only then. A causal
 * loop either extrapolates the hand one tick (x_n+1 ~ 2 x_n - x_n-1, the anchor goes there,
 * the force is rendered while the real hand moves) or renders each tick's force one tick
 * late. Both are measured too, with W from the real hand's displacement and the force
 * actually rendered: the difference is the sample-and-hold leak every sampled haptic loop
 * has (Colgate and Schenkel: the device's physical damping b must exceed K T / 2), which no
 * integrator removes. Forward and semi-implicit Euler are causal as written: their rows
 * already are what the device's port sees.
 *
 * Usage: haptic [--csv FILE]    a CSV row per tick for examples/plots/haptic.gp.
 * Hosted code: stdio and long double are fine here (not in the library). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "edmi.h"
#include "haptic_hand.h"

/* The model, from haptic_hand.h (tests/bench/haptic_target.c runs the same). */
#define HP_M HH_MASS
#define HP_K HH_STIFFNESS
#define HP_B HH_DAMPING
#define HP_DT HH_DT
#define HP_TICKS HH_TICKS

/* The methods: the four of the comparison, then edmi in the two causal loops. */
typedef enum hp_kind { HP_EDMI = 0, HP_FE, HP_SE, HP_VV, HP_EXTRAP, HP_LATE, HP_N } hp_kind;
#define HP_N_MAIN 4
static const char *const hp_name[HP_N] = {
    "edmi PM (guard on)", "explicit Euler", "semi-implicit Euler", "velocity Verlet",
    "edmi PM, hand extrapolated one tick", "edmi PM, force rendered one tick late"};
static const char *const hp_tag[HP_N] = {"edmi", "fe", "se", "vv", "edmi_extrap", "edmi_late"};

/* One method's state and what the run measured. */
typedef struct hp_run {
    edmi_real q, p;       /* tool position [m] and momentum [kg m/s] after the last tick */
    edmi_real f;          /* Verlet: the force at the end of the last tick (reused) */
    edmi_real f_render;   /* the force on the hand over the last tick [N] */
    long double e_inj;    /* E_inj after the last tick [J] */
    long double excess;   /* H_n+1 - H_n - W_n of the last tick [J] */
    long double excess_max; /* max over ticks of it: the closest call [J] */
    long double e_max;    /* max over ticks of E_inj */
    long t_max;           /* the tick it was reached at */
    long double h_peak;   /* max over ticks of H */
    long rises;           /* ticks with H_n+1 - H_n > W_n */
} hp_run;

/* An edmi system for the coupling and what its steps reported. */
typedef struct hp_edmi {
    edmi_system sys;
    int tool, link;
    long guarded, by_action[3], fallbacks, failed, iterations, off_axis;
    long beyond_tank, unresolved; /* ticks with H_n+1 - H_n - W_n - (T_n - T_n+1) above the
                                     check's resolution, and within it but above 0 */
    long double tank_excess_max;  /* max over ticks of that excess [J] */
    int max_iterations;
} hp_edmi;

static hp_edmi ed_own, ed_extrap; /* static: a system is tens of kB */
static edmi_workspace work;
static hp_run run[HP_N];

/* The coupling force on the tool. */
static edmi_real hp_force(edmi_real q, edmi_real p, edmi_real x, edmi_real v)
{
    return -HP_K * (q - x) - HP_B * (p / HP_M - v);
}

/* H of a stored state, in long double (x: where the spring's other end is). */
static long double hp_h(edmi_real q, edmi_real p, edmi_real x)
{
    long double e = (long double)q - (long double)x, pl = (long double)p;
    return pl * pl / (2.0L * (long double)HP_M) + 0.5L * (long double)HP_K * e * e;
}

/* The magnitude of hp_dh's terms: its evaluation errs by a few long double epsilons of it. */
static long double hp_dh_mag(edmi_real q0, edmi_real p0, edmi_real x0, edmi_real q1,
                             edmi_real p1, edmi_real x1)
{
    return hp_h(q0, p0, x0) + hp_h(q1, p1, x1);
}

/* H_n+1 - H_n of two stored states, term by term (no cancellation of H itself). */
static long double hp_dh(edmi_real q0, edmi_real p0, edmi_real x0, edmi_real q1, edmi_real p1,
                         edmi_real x1)
{
    long double dp = (long double)p1 - (long double)p0, sp = (long double)p1 + (long double)p0;
    long double e0 = (long double)q0 - (long double)x0, e1 = (long double)q1 - (long double)x1;
    return dp * sp / (2.0L * (long double)HP_M) +
           0.5L * (long double)HP_K * (e1 - e0) * (e1 + e0);
}

static void hp_die(const char *what, edmi_status s)
{
    printf("error: %s: %s\n", what, edmi_status_name(s));
    exit(1);
}

/* The tool at rest at x0 on a zero-rest-length spring to an anchor at x0, a damper on it. */
static void hp_edmi_init(hp_edmi *e, edmi_real x0)
{
    edmi_params prm = edmi_default_params();
    edmi_potential spring = edmi_pot_harmonic(HP_K, EDMI_R(0.0));
    edmi_real q[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real p[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_status st;
    prm.scheme = EDMI_SCHEME_PM;
    prm.fallback = 1; /* a 1 kHz loop must have a force every tick: a failed Newton solve
                         stores the passive fallback state instead (counted) */
    q[0] = x0;
    if ((st = edmi_init(&e->sys, &prm)) != EDMI_OK)
        hp_die("edmi_init", st);
    if ((st = edmi_add_body(&e->sys, HP_M, q, p, &e->tool)) != EDMI_OK)
        hp_die("edmi_add_body", st);
    if ((st = edmi_add_anchor(&e->sys, e->tool, q, &spring, &e->link)) != EDMI_OK)
        hp_die("edmi_add_anchor", st);
    if ((st = edmi_add_damper(&e->sys, e->link, HP_B, NULL)) != EDMI_OK)
        hp_die("edmi_add_damper", st);
}

/* One tick: the anchor (the hand) moves to `target` while the step runs. A failed step keeps
 * the state (and reports no work). The tool's state goes to r. */
static void hp_edmi_tick(hp_edmi *e, long tick, edmi_real target, edmi_step_result *res,
                         hp_run *r)
{
    edmi_real x[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    const edmi_body *b = &e->sys.body[e->tool];
    edmi_status st;
    x[0] = target;
    if ((st = edmi_move_anchor(&e->sys, e->link, x)) != EDMI_OK)
        hp_die("edmi_move_anchor", st);
    st = edmi_step(&e->sys, &work, HP_DT, res);
    if (st != EDMI_OK) {
        printf("tick %ld: edmi_step: %s (state kept)\n", tick, edmi_status_name(st));
        e->failed++;
        res->work_anchor = EDMI_R(0.0);
    } else {
        e->iterations += res->iterations;
        if (res->iterations > e->max_iterations)
            e->max_iterations = res->iterations;
        e->fallbacks += res->stop == EDMI_STOP_FALLBACK;
        e->guarded += res->guard_action != 0;
        e->by_action[0] += (res->guard_action & EDMI_MOVE_ROUND) != 0;
        e->by_action[1] += (res->guard_action & EDMI_MOVE_IMPULSE) != 0;
        e->by_action[2] += (res->guard_action & EDMI_MOVE_DRAG) != 0;
    }
    e->off_axis += b->q[1] != EDMI_R(0.0) || b->q[2] != EDMI_R(0.0) ||
                   b->p[1] != EDMI_R(0.0) || b->p[2] != EDMI_R(0.0);
    r->q = b->q[0];
    r->p = b->p[0];
    r->f_render = e->sys.link_force[e->link][0];
}

/* One tick of an explicit method from hand x0 (velocity v0) to x1 (v1). */
static void hp_explicit(hp_kind k, hp_run *r, edmi_real x0, edmi_real v0, edmi_real x1,
                        edmi_real v1)
{
    edmi_real f, ph;
    switch (k) {
    case HP_FE:
        f = hp_force(r->q, r->p, x0, v0);
        r->q += HP_DT * r->p / HP_M;
        r->p += HP_DT * f;
        break;
    case HP_SE:
        f = hp_force(r->q, r->p, x0, v0);
        r->p += HP_DT * f;
        r->q += HP_DT * r->p / HP_M;
        break;
    case HP_VV:
    default:
        ph = r->p + EDMI_R(0.5) * HP_DT * r->f;
        r->q += HP_DT * ph / HP_M;
        r->f = hp_force(r->q, ph, x1, v1);
        r->p = ph + EDMI_R(0.5) * HP_DT * r->f;
        break;
    }
}

/* Book one tick of run r, whose state went from (q0, p0) to (r->q, r->p) while the spring's
 * other end went from a0 to a1: H_n+1 - H_n - W_n into its sums. */
static void hp_book(hp_run *r, long tick, edmi_real q0, edmi_real p0, edmi_real a0,
                    edmi_real a1, long double w)
{
    long double h = hp_h(r->q, r->p, a1);
    r->excess = hp_dh(q0, p0, a0, r->q, r->p, a1) - w;
    r->e_inj += r->excess;
    r->rises += r->excess > 0.0L;
    if (tick == 1 || r->excess > r->excess_max)
        r->excess_max = r->excess;
    if (tick == 1 || r->e_inj > r->e_max) {
        r->e_max = r->e_inj;
        r->t_max = tick;
    }
    if (h > r->h_peak)
        r->h_peak = h;
}

/* The work the hand does moving from x0 to x1 against a rendered force f (on the hand). */
static long double hp_work(edmi_real f, edmi_real x0, edmi_real x1)
{
    return -(long double)f * ((long double)x1 - (long double)x0);
}

/* The bits of an edmi_real in hexadecimal, most significant byte first (little-endian
 * host), as tests/bench/haptic_target.c prints them: the two runs can be compared bit for bit. */
static void hp_put_bits(edmi_real x)
{
    unsigned char b[sizeof x];
    size_t i;
    memcpy(b, &x, sizeof x);
    printf("0x");
    for (i = sizeof x; i-- > 0;)
        printf("%02x", b[i]);
}

static void hp_csv_row(FILE *csv, long tick, edmi_real x)
{
    int k;
    fprintf(csv, "%.4f,%.9e", (double)tick * 1e-3, (double)x);
    for (k = 0; k < HP_N; k++)
        fprintf(csv, ",%.9e,%.6e,%.9e,%.3e", (double)run[k].q, (double)run[k].f_render,
                (double)run[k].e_inj, (double)run[k].excess);
    fputc('\n', csv);
}

static void hp_table(int from, int to)
{
    int k;
    printf("| method | peak H [J] | max E_inj [J] | at t [s] | max E_inj / peak H "
           "| final E_inj [J] | final / peak H | ticks with dH > W |\n");
    printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (k = from; k < to; k++) {
        const hp_run *r = &run[k];
        printf("| %s | %.4g | %+.3e | %.3f | %+.2e | %+.4e | %+.3f | %ld |\n", hp_name[k],
               (double)r->h_peak, (double)r->e_max, (double)r->t_max * 1e-3,
               (double)(r->e_max / r->h_peak), (double)r->e_inj, (double)(r->e_inj / r->h_peak),
               r->rises);
    }
}

int main(int argc, char **argv)
{
    edmi_real x_prev, x0, v0, x1, v1, f_late = EDMI_R(0.0);
    long double gap[2] = {0.0L, 0.0L}, f_peak = 0.0L, w_sum = 0.0L;
    long n;
    int k;
    FILE *csv = NULL;
    double omega = sqrt((double)HP_K / (double)HP_M);
    hp_edmi *e = &ed_own;

    if (argc == 3 && strcmp(argv[1], "--csv") == 0) {
        csv = fopen(argv[2], "w");
        if (!csv) {
            printf("error: cannot write %s\n", argv[2]);
            return 1;
        }
    } else if (argc != 1) {
        printf("usage: haptic [--csv FILE]\n");
        return 2;
    }

    x0 = x_prev = hh_position(EDMI_R(0.0));
    v0 = hh_velocity(EDMI_R(0.0));
    hp_edmi_init(&ed_own, x0);
    hp_edmi_init(&ed_extrap, x0);
    for (k = 0; k < HP_N; k++) {
        run[k].q = x0;
        run[k].p = EDMI_R(0.0);
        run[k].f = hp_force(x0, EDMI_R(0.0), x0, v0);
        run[k].h_peak = hp_h(x0, EDMI_R(0.0), x0);
    }
    if (csv) {
        fprintf(csv, "t,x_hand");
        for (k = 0; k < HP_N; k++)
            fprintf(csv, ",q_%s,F_%s,Einj_%s,excess_%s", hp_tag[k], hp_tag[k], hp_tag[k],
                    hp_tag[k]);
        fputc('\n', csv);
        hp_csv_row(csv, 0, x0);
    }

    for (n = 1; n <= HP_TICKS; n++) {
        edmi_step_result res;
        edmi_real q0, p0, a0, t0;
        x1 = hh_position((edmi_real)n * HP_DT);
        v1 = hh_velocity((edmi_real)n * HP_DT);

        /* edmi, the method's own port: the anchor goes to where the hand is at the END of
         * this tick; the hand's work is res.work_anchor. */
        q0 = run[HP_EDMI].q;
        p0 = run[HP_EDMI].p;
        a0 = e->sys.link[e->link].anchor[0];
        t0 = e->sys.tank;
        hp_edmi_tick(e, n, x1, &res, &run[HP_EDMI]);
        w_sum += (long double)res.work_anchor;
        hp_book(&run[HP_EDMI], n, q0, p0, a0, e->sys.link[e->link].anchor[0],
                (long double)res.work_anchor);
        { /* the guarantee: H_n+1 - H_n <= W_n + T_n - T_n+1 */
            long double x = run[HP_EDMI].excess - ((long double)t0 - (long double)e->sys.tank);
            long double res_ld = 32.0L * LDBL_EPSILON *
                                 (hp_dh_mag(q0, p0, a0, run[HP_EDMI].q, run[HP_EDMI].p,
                                            e->sys.link[e->link].anchor[0]) +
                                  fabsl((long double)res.work_anchor) + (long double)t0 +
                                  (long double)e->sys.tank);
            if (n == 1 || x > e->tank_excess_max)
                e->tank_excess_max = x;
            e->beyond_tank += x > res_ld;
            e->unresolved += x > 0.0L && x <= res_ld;
        }
        if (e->failed == 0) { /* the force on the hand is the tool's momentum change */
            long double d = (long double)run[HP_EDMI].f_render +
                            ((long double)run[HP_EDMI].p - (long double)p0) / (long double)HP_DT;
            int g = res.guard_action != 0U;
            if (fabsl(d) > gap[g])
                gap[g] = fabsl(d);
            if (fabsl((long double)run[HP_EDMI].f_render) > f_peak)
                f_peak = fabsl((long double)run[HP_EDMI].f_render);
        }

        /* ... the same states, each tick's force rendered one tick late. */
        run[HP_LATE].q = run[HP_EDMI].q;
        run[HP_LATE].p = run[HP_EDMI].p;
        run[HP_LATE].f_render = f_late;
        hp_book(&run[HP_LATE], n, q0, p0, a0, e->sys.link[e->link].anchor[0],
                hp_work(f_late, x0, x1));
        f_late = run[HP_EDMI].f_render;

        /* ... and a causal loop that extrapolates the hand: the anchor goes to 2 x_n - x_n-1,
         * the force is rendered while the real hand goes from x_n to x_n+1. */
        q0 = run[HP_EXTRAP].q;
        p0 = run[HP_EXTRAP].p;
        a0 = ed_extrap.sys.link[ed_extrap.link].anchor[0];
        hp_edmi_tick(&ed_extrap, n, EDMI_R(2.0) * x0 - x_prev, &res, &run[HP_EXTRAP]);
        hp_book(&run[HP_EXTRAP], n, q0, p0, a0, ed_extrap.sys.link[ed_extrap.link].anchor[0],
                hp_work(run[HP_EXTRAP].f_render, x0, x1));

        /* The explicit methods: the force on the hand is minus the tool's momentum change. */
        for (k = HP_FE; k <= HP_VV; k++) {
            hp_run *r = &run[k];
            edmi_real qa = r->q, pa = r->p;
            long double dp;
            hp_explicit((hp_kind)k, r, x0, v0, x1, v1);
            dp = (long double)r->p - (long double)pa;
            r->f_render = (edmi_real)(-dp / (long double)HP_DT);
            hp_book(r, n, qa, pa, x0, x1, dp * ((long double)x1 - (long double)x0) /
                                              (long double)HP_DT);
        }
        if (csv)
            hp_csv_row(csv, n, x1);
        x_prev = x0;
        x0 = x1;
        v0 = v1;
    }
    if (csv && fclose(csv) != 0) {
        printf("error: writing %s failed\n", argv[2]);
        return 1;
    }

    printf("edmi %d.%d.%d, EDMI_REAL = %s. A 1 kHz virtual coupling: tool M = %g kg on a "
           "zero-rest-length spring\nK = %g N/m with a damper B = %g N s/m to the hand "
           "(examples/haptic_hand.h), dt = %g s, %ld ticks.\nResonance %.1f Hz, damping ratio "
           "%.3f, omega dt = %.3f; forward Euler needs B > K dt = %g N s/m to be stable.\n",
           EDMI_VERSION_MAJOR, EDMI_VERSION_MINOR, EDMI_VERSION_PATCH,
           edmi_is_double_precision() ? "double" : "float", (double)HP_M, (double)HP_K,
           (double)HP_B, (double)HP_DT, HP_TICKS, omega / (2.0 * 3.141592653589793),
           (double)HP_B / (2.0 * sqrt((double)HP_K * (double)HP_M)), omega * (double)HP_DT,
           (double)HP_K * (double)HP_DT);
    printf("E_inj(n) = H_n - H_0 - sum_{k<n} W_k: the energy a method created beyond the "
           "hand's work W (passive: <= 0 at all\ntimes; H_0 = 0, the tool at rest on the "
           "hand). W_k: minus the force on the hand times the hand's displacement in tick k.\n"
           "\nEach method's own port (the force is the tool's momentum change over the "
           "tick):\n\n");
    hp_table(0, HP_N_MAIN);
    printf("\nedmi: the guard changed %ld of %ld ticks (rounding %ld, impulse %ld, drag %ld); "
           "%ld fallbacks; %ld failed ticks;\n      %.2f Newton iterations per tick (max %d); "
           "tool off the axis on %ld ticks; the hand put in %.4f J.\n", e->guarded, HP_TICKS,
           e->by_action[0], e->by_action[1], e->by_action[2], e->fallbacks, e->failed,
           (double)e->iterations / (double)HP_TICKS, e->max_iterations, e->off_axis,
           (double)w_sum);
    printf("edmi: max over ticks of H_n+1 - H_n - W_n = %+.3e J, in long double from the "
           "stored states (long double epsilon %.1e);\n      with the energy tank, max of "
           "H_n+1 - H_n - W_n - (T_n - T_n+1) = %+.3e J: %ld ticks beyond the tank, %ld "
           "unresolved.\n", (double)run[HP_EDMI].excess_max, (double)LDBL_EPSILON,
           (double)e->tank_excess_max, e->beyond_tank, e->unresolved);
    printf("edmi: the force on the hand is the tool's momentum change: max |link_force + dp/dt| "
           "= %.2e N where the guard was idle", (double)gap[0]);
    if (e->guarded > 0)
        printf(",\n      %.2e N where it acted (its corrections are not rendered)",
               (double)gap[1]);
    printf("; peak force %.3g N.\n", (double)f_peak);
    printf("\nedmi in a causal device loop (the hand's next position is not known yet; W from "
           "the real hand and the force rendered):\n\n");
    hp_table(HP_N_MAIN, HP_N);
    printf("\nextrapolating run: %ld fallbacks, %ld failed ticks. Both causal rows are the "
           "sample-and-hold leak of a sampled loop,\nnot the integrator's: the device's "
           "physical damping must exceed K dt / 2 = %g N s/m to absorb it.\n",
           ed_extrap.fallbacks, ed_extrap.failed, (double)HP_K * (double)HP_DT / 2.0);
    printf("\nedmi PM final state bits (tests/bench/haptic_target.c prints them too): q ");
    hp_put_bits(run[HP_EDMI].q);
    printf(", p ");
    hp_put_bits(run[HP_EDMI].p);
    printf("\n");
    return e->beyond_tank == 0 && run[HP_EDMI].e_max <= 0.0L && e->failed == 0 &&
                   ed_extrap.failed == 0
               ? 0
               : 1;
}
