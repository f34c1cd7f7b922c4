/* Does the passivity guard steer conservative orbits? One body about a fixed anchor at the
 * origin, on circular orbits; PM with the guard (the default), PM with EDMI_GUARD_OFF, and
 * MP and LG (guard off by default) for reference. `make orbits` builds this program in both
 * precisions and prints one markdown table: energy drift, angular-momentum drift, radius
 * drift, the steps the guard changed and the fallbacks, per scene, precision and variant.
 *
 * The truth is independent of the library: H = |p|^2/2m + V(|q|) and J = q x p of every
 * stored state are evaluated here in long double (64-bit significand on x86-64) from the
 * potentials' textbook formulas, as tests/lib/passive.c does (tp_h). The stored states have 24
 * (float) or 53 (double) significant bits: products of float values are exact in long double,
 * and every formula here errs by a few dozen 2^-64 of its terms at most, so the truth resolves
 * ~1e-17 of H's and J's terms, far below every figure printed (tests/test_orbits.c bounds the
 * same formulas' rounding term by term).
 *
 * Scenes (m = 1, anchor at the origin, q0 = (r0, 0, 0), p0 = (0, m v, 0)):
 *   a  Lennard-Jones V = 4 (r^-12 - r^-6), circular r0 = 1.2 (m v^2 / r0 = V'(r0)),
 *      dt = 1.4e-3: period 4.63, 3300 steps per revolution, about 30 revolutions in 10^5
 *      steps; in float also 10^6 steps (300 revolutions: the case of the issue) and 10^7,
 *      where what is left of the guard's steering shows: each action moves H from its
 *      ceiling (H0 less what the tank has lost) to 1/128 of the tank's capacity below it,
 *      2 eps S (S the magnitude of H's terms, ~2.4e-7 S in float), and those steps add up;
 *   b  gravity V = -1/r, r0 = 1, v = 1, dt = 1e-3: 6283 steps per revolution;
 *   c  the same LJ, r0 = 1.5, dt = 1.4e-3: the unstable circular orbit (V'' + 3 V'/r < 0
 *      there): round-off grows into a capture (r stays below 3) or an escape.
 * Every run sets params.fallback, as a control loop would, and counts the fallback steps.
 *
 * Usage: orbits [--no-header] [--diag] [--steps N] [--tank-cap C]
 *   --no-header: rows only (make orbits appends the double rows to the float table);
 *   --diag: a second table of what the guard did, with signed and largest drifts;
 *   --steps N: every scene for N steps (once; tests/test_orbits.c's figures: --steps 20000);
 *   --tank-cap C: params.tank_cap = C for every variant (default 256). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "edmi.h"

typedef enum orb_scene { ORB_LJ12 = 0, ORB_GRAV, ORB_LJ15 } orb_scene;

typedef struct orb_variant {
    const char *name;
    edmi_scheme scheme;
    edmi_guard_mode guard;
} orb_variant;

static const orb_variant orb_variants[4] = {
    {"PM (guard on)", EDMI_SCHEME_PM, EDMI_GUARD_AUTO},
    {"PM guard off", EDMI_SCHEME_PM, EDMI_GUARD_OFF},
    {"MP", EDMI_SCHEME_MP, EDMI_GUARD_AUTO},
    {"LG", EDMI_SCHEME_LG, EDMI_GUARD_AUTO},
};

/* What one run measured (all relative figures over the scene's own |H0|, |J0|, r0). */
typedef struct orb_stats {
    long steps;
    edmi_status status;       /* EDMI_OK or the first failing status (the run stops) */
    long double dh_end;       /* |H_N - H_0| / |H_0| */
    long double dh_max;       /* max_n |H_n - H_0| / |H_0| */
    long double dj_end;       /* |J_N - J_0| / |J_0| */
    long double dj_max;       /* max_n |J_n - J_0| / |J_0| */
    long double dh_sig;       /* (H_N - H_0) / |H_0|, signed */
    long double dr_max;       /* max_n |r_n - r_0| / r_0 */
    long double r_end;        /* r_N */
    long guarded;             /* steps with res.guard_action != 0 */
    long act[4];              /* ... with each bit: impulse, drag, round, stop */
    long first_act, last_act; /* first and last such step (-1: none) */
    long fallbacks;           /* steps that stored the fallback state */
    long double diss_guard;   /* sum of res.diss_guard, over |H0| */
    long double tank_max;     /* largest tank level, over |H0| */
    long double cap_max;      /* largest reported capacity, over |H0| */
    double seconds;
} orb_stats;

static edmi_system orb_sys;
static edmi_workspace orb_work;
static edmi_real orb_tank_cap = EDMI_R(-1.0); /* < 0: the default */

static long double orb_absl(long double x) { return x < 0.0L ? -x : x; }

static long double orb_maxl(long double a, long double b) { return a > b ? a : b; }

/* V(r) of the scene's potential in long double. */
static long double orb_v(orb_scene s, long double r)
{
    long double t, t6;
    if (s == ORB_GRAV)
        return -1.0L / r;
    t = 1.0L / r;
    t6 = t * t * t * t * t * t;
    return 4.0L * t6 * (t6 - 1.0L);
}

/* H, J = q x p and r of the stored state, in long double. */
static long double orb_h(orb_scene s, const edmi_system *sys, long double j[3], long double *r)
{
    const edmi_body *b = &sys->body[0];
    long double q0 = (long double)b->q[0], q1 = (long double)b->q[1], q2 = (long double)b->q[2];
    long double p0 = (long double)b->p[0], p1 = (long double)b->p[1], p2 = (long double)b->p[2];
    long double m = (long double)b->m;
    *r = sqrtl(q0 * q0 + q1 * q1 + q2 * q2);
    j[0] = q1 * p2 - q2 * p1;
    j[1] = q2 * p0 - q0 * p2;
    j[2] = q0 * p1 - q1 * p0;
    return (p0 * p0 + p1 * p1 + p2 * p2) / (2.0L * m) + orb_v(s, *r);
}

/* The circular speeds v = sqrt(r0 V'(r0) / m) = sqrt(24 r0^-6 - 48 r0^-12) of the LJ scenes,
 * to 21 digits (mpmath): a literal rounds correctly in either precision, so every build,
 * host or target, starts from the same state. */
#define ORB_V12 EDMI_R(1.62912001113106890164)
#define ORB_V15 EDMI_R(1.31796936480679757167)

static int orb_build(orb_scene s, const orb_variant *var, edmi_real *dt)
{
    static const edmi_real o[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_params prm = edmi_default_params();
    edmi_potential pot = s == ORB_GRAV ? edmi_pot_inverse(EDMI_R(1.0))
                                       : edmi_pot_lj(EDMI_R(1.0), EDMI_R(1.0));
    edmi_real q[3], p[3];
    q[0] = s == ORB_LJ12 ? EDMI_R(1.2) : s == ORB_LJ15 ? EDMI_R(1.5) : EDMI_R(1.0);
    q[1] = q[2] = EDMI_R(0.0);
    p[0] = p[2] = EDMI_R(0.0);
    p[1] = s == ORB_LJ12 ? ORB_V12 : s == ORB_LJ15 ? ORB_V15 : EDMI_R(1.0);
    prm.scheme = var->scheme;
    prm.guard = var->guard;
    prm.fallback = 1;
    if (orb_tank_cap >= EDMI_R(0.0))
        prm.tank_cap = orb_tank_cap;
    *dt = s == ORB_GRAV ? EDMI_R(1e-3) : EDMI_R(1.4e-3);
    return edmi_init(&orb_sys, &prm) == EDMI_OK &&
           edmi_add_body(&orb_sys, EDMI_R(1.0), q, p, NULL) == EDMI_OK &&
           edmi_add_anchor(&orb_sys, 0, o, &pot, NULL) == EDMI_OK;
}

static void orb_run(orb_scene s, const orb_variant *var, long n, orb_stats *st)
{
    long double h0, j0[3], r0, h, j[3], r, jn0;
    edmi_real dt;
    clock_t c0 = clock();
    long k;
    memset(st, 0, sizeof *st);
    st->first_act = st->last_act = -1;
    st->status = EDMI_OK;
    if (!orb_build(s, var, &dt)) {
        st->status = EDMI_ERR_PARAM;
        return;
    }
    h0 = orb_h(s, &orb_sys, j0, &r0);
    jn0 = sqrtl(j0[0] * j0[0] + j0[1] * j0[1] + j0[2] * j0[2]);
    h = h0;
    j[0] = j0[0];
    j[1] = j0[1];
    j[2] = j0[2];
    r = r0;
    for (k = 0; k < n; k++) {
        edmi_step_result res;
        edmi_status e = edmi_step(&orb_sys, &orb_work, dt, &res);
        long double dh, dr, dj;
        int b;
        if (e != EDMI_OK) {
            st->status = e;
            break;
        }
        st->steps++;
        if (res.stop == EDMI_STOP_FALLBACK)
            st->fallbacks++;
        if (res.guard_action != 0u) {
            st->guarded++;
            if (st->first_act < 0)
                st->first_act = k;
            st->last_act = k;
            for (b = 0; b < 4; b++)
                if (res.guard_action & (1u << b))
                    st->act[b]++;
        }
        st->diss_guard += (long double)res.diss_guard;
        if ((long double)orb_sys.tank > st->tank_max)
            st->tank_max = (long double)orb_sys.tank;
        if ((long double)res.tank_cap > st->cap_max)
            st->cap_max = (long double)res.tank_cap;
        h = orb_h(s, &orb_sys, j, &r);
        dh = orb_absl(h - h0);
        dr = orb_absl(r - r0);
        if (dh > st->dh_max)
            st->dh_max = dh;
        if (dr > st->dr_max)
            st->dr_max = dr;
        dj = sqrtl((j[0] - j0[0]) * (j[0] - j0[0]) + (j[1] - j0[1]) * (j[1] - j0[1]) +
                   (j[2] - j0[2]) * (j[2] - j0[2]));
        if (dj > st->dj_max)
            st->dj_max = dj;
    }
    st->dj_max /= jn0;
    st->dh_sig = (h - h0) / orb_absl(h0);
    st->dh_end = orb_absl(h - h0) / orb_absl(h0);
    st->dh_max /= orb_absl(h0);
    st->dj_end = sqrtl((j[0] - j0[0]) * (j[0] - j0[0]) + (j[1] - j0[1]) * (j[1] - j0[1]) +
                       (j[2] - j0[2]) * (j[2] - j0[2])) / jn0;
    st->dr_max /= r0;
    st->r_end = r;
    st->diss_guard /= orb_absl(h0);
    st->tank_max /= orb_absl(h0);
    st->cap_max /= orb_absl(h0);
    st->seconds = (double)(clock() - c0) / CLOCKS_PER_SEC;
}

static const char *orb_scene_name(orb_scene s)
{
    return s == ORB_LJ12 ? "a: LJ circular r=1.2" : s == ORB_GRAV ? "b: gravity r=1 v=1"
                                                                  : "c: LJ unstable r=1.5";
}

/* The unstable orbit's fate: captured if the body ends within r < 3 (the well's range). */
static int orb_captured(const orb_stats *s) { return s->r_end < 3.0L; }

#define ORB_MAX_RUNS 20

typedef struct orb_case {
    orb_scene scene;
    long steps;
} orb_case;

int main(int argc, char **argv)
{
    const char *prec = edmi_is_double_precision() ? "double" : "float";
    static const orb_case cases_d[] = {{ORB_LJ12, 100000L}, {ORB_GRAV, 100000L},
                                       {ORB_LJ15, 100000L}};
    static const orb_case cases_f[] = {{ORB_LJ12, 100000L}, {ORB_LJ12, 1000000L},
                                       {ORB_LJ12, 10000000L}, {ORB_GRAV, 100000L},
                                       {ORB_LJ15, 100000L}};
    const orb_case *cases = edmi_is_double_precision() ? cases_d : cases_f;
    static orb_case cases_n[] = {{ORB_LJ12, 0L}, {ORB_GRAV, 0L}, {ORB_LJ15, 0L}};
    int n_cases = edmi_is_double_precision() ? 3 : 5, header = 1, diag = 0, i, v, n = 0;
    static orb_stats st[ORB_MAX_RUNS];
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--no-header") == 0)
            header = 0;
        else if (strcmp(argv[i], "--diag") == 0)
            diag = 1;
        else if (strcmp(argv[i], "--steps") == 0 && i + 1 < argc && atol(argv[i + 1]) > 0) {
            long steps = atol(argv[++i]);
            for (v = 0; v < 3; v++)
                cases_n[v].steps = steps;
            cases = cases_n;
            n_cases = 3;
        } else if (strcmp(argv[i], "--tank-cap") == 0 && i + 1 < argc && atof(argv[i + 1]) >= 0.0) {
            orb_tank_cap = (edmi_real)atof(argv[++i]);
        } else {
            fprintf(stderr, "usage: %s [--no-header] [--diag] [--steps N] [--tank-cap C]\n",
                    argv[0]);
            return 2;
        }
    }
    if (!EDMI_CONFIG_MATCHES()) {
        fprintf(stderr, "orbits: edmi.o built with another configuration\n");
        return 2;
    }
    if (header) {
        printf("| scene | precision | variant | steps | \\|H_N - H_0\\|/\\|H_0\\| | "
               "max \\|H_n - H_0\\|/\\|H_0\\| | \\|J_N - J_0\\|/\\|J_0\\| | "
               "max \\|r_n - r_0\\|/r_0 | steps guard changed | fallbacks | "
               "guarded PM / reference: \\|dH_N\\|, max \\|dH\\|, \\|dJ_N\\| |\n");
        printf("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|\n");
    }
    for (i = 0; i < n_cases; i++) {
        const orb_stats *g = &st[n], *r1, *r2;
        for (v = 0; v < 4; v++)
            orb_run(cases[i].scene, &orb_variants[v], cases[i].steps, &st[n + v]);
        /* the reference: in double unguarded PM; in float the larger of MP's and LG's */
        r1 = edmi_is_double_precision() ? &st[n + 1] : &st[n + 2];
        r2 = edmi_is_double_precision() ? &st[n + 1] : &st[n + 3];
        for (v = 0; v < 4; v++, n++) {
            const orb_stats *s = &st[n];
            char end[48] = "", ratio[96] = "";
            if (cases[i].scene == ORB_LJ15)
                snprintf(end, sizeof end, " (%s, r_N = %.3Lg)",
                         orb_captured(s) ? "captured" : "escaped", s->r_end);
            if (v == 0) /* on the unstable orbit a different fate makes the ratio moot */
                snprintf(ratio, sizeof ratio, "%.2Lf, %.2Lf, %.2Lf (%s)%s",
                         g->dh_end / orb_maxl(r1->dh_end, r2->dh_end),
                         g->dh_max / orb_maxl(r1->dh_max, r2->dh_max),
                         g->dj_end / orb_maxl(r1->dj_end, r2->dj_end),
                         edmi_is_double_precision() ? "PM guard off" : "max of MP, LG",
                         orb_captured(g) != orb_captured(r1) || orb_captured(g) != orb_captured(r2)
                             ? "; fates differ"
                             : "");
            printf("| %s | %s | %s | %ld%s%s | %.2Le | %.2Le | %.2Le | %.2Le%s | %ld | %ld "
                   "| %s |\n",
                   orb_scene_name(cases[i].scene), prec, orb_variants[v].name, s->steps,
                   s->status == EDMI_OK ? "" : " ",
                   s->status == EDMI_OK ? "" : edmi_status_name(s->status), s->dh_end, s->dh_max,
                   s->dj_end, s->dr_max, end, s->guarded, s->fallbacks, ratio);
        }
        fflush(stdout);
    }
    if (diag) {
        printf("\n| scene | precision | variant | steps | (H_N - H_0)/\\|H_0\\| | "
               "max \\|J_n - J_0\\|/\\|J_0\\| | guard actions (impulse/drag/round/stop) | "
               "first, last action | sum diss_guard/\\|H0\\| | max tank/\\|H0\\| | "
               "max cap/\\|H0\\| | s |\n");
        printf("|---|---|---|---:|---:|---:|---|---|---:|---:|---:|---:|\n");
        for (n = 0, i = 0; i < n_cases; i++)
            for (v = 0; v < 4; v++, n++) {
                const orb_stats *s = &st[n];
                int b;
                printf("| %s | %s | %s | %ld | %.2Le | %.2Le | ", orb_scene_name(cases[i].scene),
                       prec, orb_variants[v].name, s->steps, s->dh_sig, s->dj_max);
                for (b = 0; b < 4; b++)
                    printf("%s%ld", b ? "/" : "", s->act[b]);
                printf(" | %ld, %ld | %.2Le | %.2Le | %.2Le | %.2f |\n", s->first_act, s->last_act,
                       s->diss_guard, s->tank_max, s->cap_max, s->seconds);
            }
    }
    return 0;
}
