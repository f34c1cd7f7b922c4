/*
 * edmi-sim: run a scene file on the host and report how well each invariant held.
 *
 *   edmi-sim SCENE [--scheme mp|lg|ge|pm|pt] [--dt X] [--t-end X] [--tol-q X] [--tol-r X]
 *            [--tol-a X] [--l-max N] [--lg-switch closed|janz|gonzalez|ge|pm|pt]
 *            [--guard auto|on|off] [--fallback on|off] [--substeps K] [--every K] [--csv FILE]
 *            [--energy-balance] [--balance-tol X] [--ref FILE|converged] [--row]
 *            [--label TEXT] [--h-check FILE] [--quiet] [--emit-c]
 *
 * Prints a summary (steps, time, wall time, Newton iterations, final and maximum
 * |H - H0|/|H0|, maximum |J - J0|, |L - L0|, |C - C0|, the steps where H of the stored state
 * rose, evaluated by tests/lib/passive.c) or, with --row, one Markdown table row; optionally a CSV
 * trace; with --ref, the trajectory error against an earlier trace or a converged run of its
 * own. Exit status: 0 success, 1 a step or invariant evaluation failed, 2 a usage or scene
 * error, 3 the energy balance missed its tolerance. Hosted C99 (stdio, POSIX clock and isatty); builds in double or
 * float (EDMI_REAL).
 */
#define _POSIX_C_SOURCE 200112L
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "edmi.h"
#include "scene.h"
/* The energy check uses the shared exact-H helper, tests/lib/passive.h (-Itests/lib). */
#include "passive.h"

#define SIM_PROGRESS_AFTER 2.0 /* seconds before the first progress report */
#define SIM_PROGRESS_EVERY 1.0 /* seconds between reports on a terminal */
#define SIM_PROGRESS_LOG 10.0  /* seconds between reports when stderr is not a terminal */

static const char *const usage_text =
    "usage: edmi-sim SCENE [options]\n"
    "  --scheme mp|lg|ge|pm|pt   algorithmic force (default: the scene's, else pm)\n"
    "  --dt X                    time step (default: the scene's `set dt`)\n"
    "  --t-end X                 end time; runs round(t_end/dt) steps (default: `set t_end`)\n"
    "  --tol-q X, --tol-r X, --tol-a X, --l-max N   Newton and LG quotient settings\n"
    "                            (--tol-r 0 --tol-a 0: no early stop, Newton to its floor)\n"
    "  --lg-switch closed|janz|gonzalez|ge|pm|pt\n"
    "                            LG: closed-form divided difference, or the quotient with\n"
    "                            that alternate force below tol_Q\n"
    "  --guard auto|on|off       passivity guard (default: the scene's, else auto: on for\n"
    "                            GE, PM, PT)\n"
    "  --fallback on|off         store the fallback state when a step still fails\n"
    "                            (default: the scene's, else off)\n"
    "  --substeps K              a failed step retries as substeps down to dt/2^K\n"
    "                            (default: the scene's, else 0)\n"
    "  --tank-cap X              the guard's energy tank capacity in eps times H's terms\n"
    "                            (default 256; 0: H never rises beyond each step's work)\n"
    "  --csv FILE                write a trace: t, H, J, L, C, iterations, every q and p\n"
    "                            (FILE '-' is stdout)\n"
    "  --every K                 one CSV row every K steps (default: `set every`, else 1)\n"
    "  --digits N                significant digits of q and p in the CSV (default 17)\n"
    "  --energy-balance          check H_n+1 - H_n = W_ext + W_anchor - D_scheme - D_damping\n"
    "                            - D_guard each step (H of the stored states, tests/lib/passive.c),\n"
    "                            relative to the magnitude of H's terms and the reported ones;\n"
    "                            exit 3 if the largest mismatch exceeds the tolerance\n"
    "  --balance-tol X           that tolerance (implies --energy-balance; default 256 eps:\n"
    "                            3.1e-5 in float, 5.7e-14 in double)\n"
    "  --ref FILE                trajectory error against a trace FILE written earlier by\n"
    "                            --csv (any scheme, dt, --every or precision): at every time\n"
    "                            FILE has a row for (within 1e-9 of the step), the largest\n"
    "                            |q - q_ref| and |p - p_ref| over bodies, and |H - H_ref|\n"
    "  --ref converged           the error at t_end against the same run at dt/2, dt/4, ...\n"
    "                            (Newton to its floor) until two halvings agree to 1e-3 of it\n"
    "                            (at most 6, or 10^8 steps); prints the reference's own error;\n"
    "                            exit 1 if a halved run fails or the halvings still differ by\n"
    "                            more than a tenth of the error\n"
    "  --row                     print one Markdown table row instead of the summary\n"
    "  --label TEXT              the row's scheme column (default: derived from the options)\n"
    "  --h-check FILE            write the H check's counts to FILE, one line: steps N checked\n"
    "                            C rose R beyond E quad Q guard on|off (C = N, or 0 where a\n"
    "                            state could not be evaluated; E: beyond the work and the\n"
    "                            tank; Q: steps evaluated in __float128)\n"
    "  --quiet                   no progress report on stderr\n"
    "  --emit-c                  print the scene as C99 static data (a static const edmi_scene\n"
    "                            NAME_scene, NAME from the file name, with NAME_DT and a\n"
    "                            compile-time capacity check) and exit\n"
    "  --help\n";

static edmi_system sys;
static edmi_workspace work;
static sim_scene scn;

typedef struct sim_opts {
    const char *scene;
    const char *csv;
    const char *label;
    const char *ref; /* --ref FILE, or "converged" */
    const char *h_check; /* --h-check FILE */
    int has_scheme, has_switch, has_tol_q, has_tol_r, has_tol_a, has_l_max, has_guard,
        has_fallback, has_tank_cap, has_substeps;
    double tank_cap;
    edmi_scheme scheme;
    edmi_guard_mode guard;
    int fallback, substeps;
    edmi_params sw; /* lg_form / lg_alt from --lg-switch */
    double dt, t_end, tol_q, tol_r, tol_a, balance_tol;
    long l_max, every, digits;
    int energy_balance, row, quiet, emit_c;
} sim_opts;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A bad command line: what is wrong, in one line, and where the options are listed. */
static void usage_error(const char *fmt, const char *a, const char *b)
{
    fprintf(stderr, "edmi-sim: ");
    fprintf(stderr, fmt, a, b);
    fprintf(stderr, "\n(edmi-sim --help lists the options)\n");
    exit(2);
}

static double opt_positive(const char *opt, const char *v)
{
    char *end;
    double x;
    errno = 0;
    x = strtod(v, &end);
    if (end == v || *end != '\0')
        usage_error("%s: bad number '%s'", opt, v);
    if (!isfinite(x) || (errno == ERANGE && fabs(x) > 1.0))
        usage_error("%s: '%s' is not finite", opt, v);
    if (!(x > 0.0))
        usage_error("%s: '%s' must be > 0", opt, v);
    if (x > (double)EDMI_REAL_MAX || !((edmi_real)x > (edmi_real)0))
        usage_error("%s: '%s' does not fit in EDMI_REAL", opt, v);
    return x;
}

static long opt_count(const char *opt, const char *v)
{
    char *end;
    long n;
    errno = 0;
    n = strtol(v, &end, 10);
    if (end == v || *end != '\0' || errno == ERANGE)
        usage_error("%s: bad integer '%s'", opt, v);
    if (n < 1)
        usage_error("%s: '%s' must be >= 1", opt, v);
    return n;
}

static void parse_args(int argc, char **argv, sim_opts *o)
{
    int i;
    memset(o, 0, sizeof *o);
    o->sw = edmi_default_params();
    for (i = 1; i < argc; i++) {
        const char *a = argv[i], *v = 0;
        char name[32];
        const char *eq = strchr(a, '=');
        if (a[0] != '-' || a[1] == '\0') {
            if (o->scene)
                usage_error("more than one scene: '%s' and '%s'", o->scene, a);
            o->scene = a;
            continue;
        }
        /* --opt=value or --opt value */
        if (eq && a[1] == '-') {
            size_t n = (size_t)(eq - a);
            if (n >= sizeof name)
                usage_error("unknown option '%s'%s", a, "");
            memcpy(name, a, n);
            name[n] = '\0';
            v = eq + 1;
        } else {
            snprintf(name, sizeof name, "%s", a);
        }
        if (strcmp(name, "--help") == 0 || strcmp(name, "-h") == 0) {
            fputs(usage_text, stdout);
            exit(0);
        }
        if (strcmp(name, "--energy-balance") == 0 || strcmp(name, "--row") == 0 ||
            strcmp(name, "--quiet") == 0 || strcmp(name, "--emit-c") == 0) {
            if (v)
                usage_error("%s takes no value (got '%s')", name, v);
            if (strcmp(name, "--energy-balance") == 0)
                o->energy_balance = 1;
            else if (strcmp(name, "--row") == 0)
                o->row = 1;
            else if (strcmp(name, "--quiet") == 0)
                o->quiet = 1;
            else
                o->emit_c = 1;
            continue;
        }
        if (strcmp(name, "--scheme") && strcmp(name, "--lg-switch") && strcmp(name, "--guard") &&
            strcmp(name, "--fallback") && strcmp(name, "--dt") && strcmp(name, "--t-end") &&
            strcmp(name, "--tol-q") && strcmp(name, "--tol-r") && strcmp(name, "--tol-a") &&
            strcmp(name, "--l-max") && strcmp(name, "--csv") && strcmp(name, "--ref") &&
            strcmp(name, "--every") && strcmp(name, "--digits") && strcmp(name, "--label") &&
            strcmp(name, "--balance-tol") && strcmp(name, "--tank-cap") &&
            strcmp(name, "--substeps") && strcmp(name, "--h-check"))
            usage_error("unknown option '%s'%s", a, "");
        if (!v) {
            if (i + 1 >= argc)
                usage_error("%s needs a value%s", name, "");
            v = argv[++i];
        }
        if (strcmp(name, "--scheme") == 0) {
            if (sim_parse_scheme(v, &o->scheme))
                usage_error("--scheme: bad value '%s' (expected mp, lg, ge, pm or pt)%s", v, "");
            o->has_scheme = 1;
        } else if (strcmp(name, "--lg-switch") == 0) {
            if (sim_parse_lg_switch(v, &o->sw))
                usage_error("--lg-switch: bad value '%s' (expected closed, janz, gonzalez, ge, "
                            "pm or pt)%s", v, "");
            o->has_switch = 1;
        } else if (strcmp(name, "--guard") == 0) {
            if (sim_parse_guard(v, &o->guard))
                usage_error("--guard: bad value '%s' (expected auto, on or off)%s", v, "");
            o->has_guard = 1;
        } else if (strcmp(name, "--fallback") == 0) {
            if (sim_parse_on_off(v, &o->fallback))
                usage_error("--fallback: bad value '%s' (expected on or off)%s", v, "");
            o->has_fallback = 1;
        } else if (strcmp(name, "--substeps") == 0) {
            long k = strcmp(v, "0") == 0 ? 0 : opt_count(name, v); /* 0: no substeps */
            if (k > EDMI_MAX_SUBSTEP_LEVELS)
                usage_error("--substeps: %s is more than the largest, EDMI_MAX_SUBSTEP_LEVELS%s",
                            v, "");
            o->substeps = (int)k;
            o->has_substeps = 1;
        } else if (strcmp(name, "--tank-cap") == 0) {
            o->tank_cap = strcmp(v, "0") == 0 ? 0.0 : opt_positive(name, v); /* 0: no tank */
            o->has_tank_cap = 1;
        } else if (strcmp(name, "--dt") == 0) {
            o->dt = opt_positive(name, v);
        } else if (strcmp(name, "--t-end") == 0) {
            o->t_end = opt_positive(name, v);
        } else if (strcmp(name, "--tol-q") == 0) {
            o->tol_q = opt_positive(name, v);
            o->has_tol_q = 1;
        } else if (strcmp(name, "--tol-r") == 0) {
            o->tol_r = strcmp(v, "0") == 0 ? 0.0 : opt_positive(name, v); /* 0: off */
            o->has_tol_r = 1;
        } else if (strcmp(name, "--tol-a") == 0) {
            o->tol_a = strcmp(v, "0") == 0 ? 0.0 : opt_positive(name, v);
            o->has_tol_a = 1;
        } else if (strcmp(name, "--l-max") == 0) {
            o->l_max = opt_count(name, v);
            if (o->l_max > 1000)
                usage_error("--l-max: '%s' is more than 1000%s", v, "");
            o->has_l_max = 1;
        } else if (strcmp(name, "--balance-tol") == 0) {
            o->balance_tol = opt_positive(name, v);
            o->energy_balance = 1;
        } else if (strcmp(name, "--every") == 0) {
            o->every = opt_count(name, v);
        } else if (strcmp(name, "--digits") == 0) {
            o->digits = opt_count(name, v);
            if (o->digits > 17)
                usage_error("--digits: '%s' is more than 17%s", v, "");
        } else if (strcmp(name, "--csv") == 0) {
            o->csv = v;
        } else if (strcmp(name, "--h-check") == 0) {
            o->h_check = v;
        } else if (strcmp(name, "--ref") == 0) {
            o->ref = v;
        } else if (strcmp(name, "--label") == 0) {
            o->label = v;
        } else {
            usage_error("unknown option '%s'%s", name, "");
        }
    }
    if (!o->scene)
        usage_error("no scene file given%s%s", "", "");
}

/* ---- --emit-c: the scene as C99 static data ----------------------------------------------- */

/* The shortest decimal that reads back as x, valid after EDMI_R()'s f-suffix pasting (it
 * always has a '.' or an exponent). */
static const char *lit(double x, char *buf, size_t n)
{
    int prec;
    for (prec = 1; prec <= 17; prec++) {
        snprintf(buf, n, "%.*g", prec, x);
        if (strtod(buf, 0) == x)
            break;
    }
    if (!strpbrk(buf, ".en"))
        strncat(buf, ".0", n - strlen(buf) - 1);
    return buf;
}

static const char *pot_kind_name(edmi_pot_kind k)
{
    switch (k) {
    case EDMI_POT_HARMONIC: return "EDMI_POT_HARMONIC";
    case EDMI_POT_QUARTIC: return "EDMI_POT_QUARTIC";
    case EDMI_POT_NEO_HOOKE: return "EDMI_POT_NEO_HOOKE";
    case EDMI_POT_LJ: return "EDMI_POT_LJ";
    case EDMI_POT_INVERSE: return "EDMI_POT_INVERSE";
    case EDMI_POT_CONTACT: return "EDMI_POT_CONTACT";
    case EDMI_POT_TETHER: return "EDMI_POT_TETHER";
    default: return "EDMI_POT_USER";
    }
}

/* The scene's C name: the file's base name without its extension, as a C identifier
 * ("examples/scenes/lj_two_body.scene" -> "lj_two_body"; a leading digit gets "s_"). */
static void emit_name(const char *path, char *out, size_t n)
{
    const char *b = strrchr(path, '/');
    size_t k = 0;
    b = b ? b + 1 : path;
    if (*b >= '0' && *b <= '9' && n > 3) {
        out[k++] = 's';
        out[k++] = '_';
    }
    for (; *b && *b != '.' && k + 1 < n; b++)
        out[k++] = (char)((*b >= 'a' && *b <= 'z') || (*b >= 'A' && *b <= 'Z') ||
                                  (*b >= '0' && *b <= '9')
                              ? *b
                              : '_');
    out[k] = '\0';
    if (k == 0)
        snprintf(out, n, "scene");
}

/* A tolerance: the scene's value in a double build; in a float build the library's float
 * default (tol_R and tol_A below float resolution only stop Newton at its floor anyway). */
static void emit_tol(const char *field, double v, const char *float_value)
{
    char b[40];
    printf("    .%s = sizeof(edmi_real) == sizeof(float) ? EDMI_R(%s) : EDMI_R(%s),\n", field,
           float_value, lit(v, b, sizeof b));
}

static void emit_c(const sim_scene *s, const char *path)
{
    static const char *const scheme_c[] = {"EDMI_SCHEME_MP", "EDMI_SCHEME_LG", "EDMI_SCHEME_GE", "EDMI_SCHEME_PM", "EDMI_SCHEME_PT"};
    static const char *const alt_c[] = {"EDMI_LG_ALT_JANZ", "EDMI_LG_ALT_GONZALEZ", "EDMI_LG_ALT_GE",
                                        "EDMI_LG_ALT_PM", "EDMI_LG_ALT_PT"};
    static const char *const guard_c[] = {"EDMI_GUARD_AUTO", "EDMI_GUARD_ON", "EDMI_GUARD_OFF"};
    char b0[40], b1[40], b2[40], b3[40], b4[40], b5[40], b6[40], nm[64];
    int i;
    emit_name(path, nm, sizeof nm);
    printf("/* Generated by `edmi-sim %s --emit-c`%s%s.\n", path, s->title[0] ? ": " : "",
           s->title);
    printf(" * C99 constant data (it can live in flash), all static and named %s_*, so that\n"
           " * several scenes can live in one program. Load it with\n"
           " *     edmi_load_scene(&sys, &%s_scene);\n", nm, nm);
    if (s->n_forces)
        printf(" * then set the force ports with\n"
               " *     for (i = 0; i < %s_N_PORTS; i++)\n"
               " *         edmi_set_force(&sys, %s_port_body[i], %s_port_force[i]);\n",
               nm, nm, nm);
    printf(" * and step it with %s_DT. In a float build the tolerances are float's defaults. */\n",
           nm);
    printf("#include \"edmi.h\"\n\n");
    printf("#if EDMI_MAX_BODIES < %d || EDMI_MAX_LINKS < %d || EDMI_MAX_DAMPERS < %d\n"
           "#error \"scene %s needs EDMI_MAX_BODIES >= %d, EDMI_MAX_LINKS >= %d, "
           "EDMI_MAX_DAMPERS >= %d\"\n#endif\n\n",
           s->n_bodies, s->n_links, s->n_dampers, nm, s->n_bodies, s->n_links, s->n_dampers);
    if (s->n_mass) {
        int g = 0;
        for (i = 0; i < s->n_mass; i++) {
            int d = s->mass[i].a > s->mass[i].b ? s->mass[i].a - s->mass[i].b
                                                : s->mass[i].b - s->mass[i].a;
            g = d > g ? d : g;
        }
        printf("#if EDMI_MAX_MASS_GAP < %d\n#error \"scene %s couples masses %d bodies apart: it "
               "needs EDMI_MAX_MASS_GAP >= %d\"\n#endif\n\n", g, nm, g, g);
    }
    printf("static const edmi_body %s_bodies[%d] = {\n", nm, s->n_bodies);
    for (i = 0; i < s->n_bodies; i++) {
        const edmi_body *bd = &s->body[i];
        printf("    {EDMI_R(%s), {EDMI_R(%s), EDMI_R(%s), EDMI_R(%s)}, "
               "{EDMI_R(%s), EDMI_R(%s), EDMI_R(%s)}}, /* %d%s%s */\n",
               lit((double)bd->m, b0, sizeof b0), lit((double)bd->q[0], b1, sizeof b1),
               lit((double)bd->q[1], b2, sizeof b2), lit((double)bd->q[2], b3, sizeof b3),
               lit((double)bd->p[0], b4, sizeof b4), lit((double)bd->p[1], b5, sizeof b5),
               lit((double)bd->p[2], b6, sizeof b6), i, s->body_name[i][0] ? " " : "",
               s->body_name[i]);
    }
    printf("};\n\nstatic const edmi_link %s_links[%d] = {\n", nm, s->n_links > 0 ? s->n_links : 1);
    for (i = 0; i < s->n_links; i++) {
        const edmi_link *lk = &s->link[i];
        char bb[16];
        if (lk->b == EDMI_ANCHOR)
            snprintf(bb, sizeof bb, "EDMI_ANCHOR");
        else
            snprintf(bb, sizeof bb, "%d", lk->b);
        printf("    {.a = %d, .b = %s, .anchor = {EDMI_R(%s), EDMI_R(%s), EDMI_R(%s)},\n"
               "     .pot = {.kind = %s, .a = EDMI_R(%s), .b = EDMI_R(%s)}}, /* link %d */\n",
               lk->a, bb, lit((double)lk->anchor[0], b0, sizeof b0),
               lit((double)lk->anchor[1], b1, sizeof b1), lit((double)lk->anchor[2], b2, sizeof b2),
               pot_kind_name(lk->pot.kind), lit((double)lk->pot.a, b3, sizeof b3),
               lit((double)lk->pot.b, b4, sizeof b4), i);
    }
    if (s->n_links == 0)
        printf("    {0}\n");
    printf("};\n\n");
    if (s->n_dampers) {
        printf("static const edmi_damper %s_dampers[%d] = {\n", nm, s->n_dampers);
        for (i = 0; i < s->n_dampers; i++)
            printf("    {.link = %d, .c = EDMI_R(%s)},\n", s->damper[i].link,
                   lit((double)s->damper[i].c, b0, sizeof b0));
        printf("};\n\n");
    }
    if (s->n_mass) {
        printf("static const edmi_mass_coupling %s_masses[%d] = {\n", nm, s->n_mass);
        for (i = 0; i < s->n_mass; i++)
            printf("    {%d, %d, EDMI_R(%s)},\n", s->mass[i].a, s->mass[i].b,
                   lit((double)s->mass[i].m, b0, sizeof b0));
        printf("};\n\n");
    }
    printf("static const edmi_params %s_params = {\n"
           "    .scheme = %s, .lg_form = %s, .lg_alt = %s,\n", nm,
           scheme_c[s->params.scheme],
           s->params.lg_form == EDMI_LG_CLOSED ? "EDMI_LG_CLOSED" : "EDMI_LG_QUOTIENT",
           alt_c[s->params.lg_alt]);
    emit_tol("tol_q", (double)s->params.tol_q, "1e-3");
    emit_tol("tol_r", (double)s->params.tol_r, "0.0");
    emit_tol("tol_a", (double)s->params.tol_a, "0.0");
    printf("    .l_max = %d, .energy_balance = 0, .guard = %s, .tank_cap = %.17g,\n"
           "    .substep_levels = %d, .fallback = %d};\n\n",
           s->params.l_max, guard_c[s->params.guard], (double)s->params.tank_cap,
           s->params.substep_levels, s->params.fallback);
    printf("static const edmi_scene %s_scene = {\n"
           "    .n_bodies = %d, .bodies = %s_bodies,\n"
           "    .n_links = %d, .links = %s_links,\n"
           "    .n_dampers = %d, .dampers = %s%s,\n"
           "    .has_field = %d, .g = {EDMI_R(%s), EDMI_R(%s), EDMI_R(%s)},\n"
           "    .params = &%s_params",
           nm, s->n_bodies, nm, s->n_links, nm, s->n_dampers, s->n_dampers ? nm : "0",
           s->n_dampers ? "_dampers" : "", s->has_field, lit((double)s->g[0], b0, sizeof b0),
           lit((double)s->g[1], b1, sizeof b1), lit((double)s->g[2], b2, sizeof b2), nm);
    if (s->n_mass)
        printf(",\n    .n_mass_couplings = %d, .mass_couplings = %s_masses", s->n_mass, nm);
    printf("};\n");
    if (s->n_forces) {
        printf("\n#define %s_N_PORTS %d\n", nm, s->n_forces);
        printf("static const int %s_port_body[%s_N_PORTS] = {", nm, nm);
        for (i = 0; i < s->n_forces; i++)
            printf("%s%d", i ? ", " : "", s->force_body[i]);
        printf("};\nstatic const edmi_real %s_port_force[%s_N_PORTS][3] = {\n", nm, nm);
        for (i = 0; i < s->n_forces; i++)
            printf("    {EDMI_R(%s), EDMI_R(%s), EDMI_R(%s)},\n",
                   lit((double)s->force[i][0], b0, sizeof b0),
                   lit((double)s->force[i][1], b1, sizeof b1),
                   lit((double)s->force[i][2], b2, sizeof b2));
        printf("};\n");
    }
    if (s->dt > 0.0)
        printf("\n#define %s_DT EDMI_R(%s) /* the scene's step */\n", nm,
               lit(s->dt, b0, sizeof b0));
    if (s->t_end > 0.0)
        printf("#define %s_T_END EDMI_R(%s) /* its end time */\n", nm,
               lit(s->t_end, b0, sizeof b0));
}

/* ---- the run ------------------------------------------------------------------------------ */

static double norm3d(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

static double diff3(const edmi_real a[3], const edmi_real b[3])
{
    double d[3];
    int i;
    for (i = 0; i < 3; i++)
        d[i] = (double)a[i] - (double)b[i];
    return norm3d(d);
}

static double norm3r(const edmi_real a[3])
{
    double d[3];
    int i;
    for (i = 0; i < 3; i++)
        d[i] = (double)a[i];
    return norm3d(d);
}

/* Running totals of one run. */
typedef struct sim_stats {
    long steps, iterations, stalled, lg_switch_steps;
    long guard_steps, guard_impulse, guard_drag, guard_round, guard_stop, fallbacks;
    long cert[4];        /* steps per edmi_certificate */
    double max_tank, max_cap; /* the largest tank and capacity, relative to h_scale */
    int max_iterations;
    double wall;
    double h0, h_scale, max_dh, final_dh; /* dh relative to h_scale (|H0|, or 1 if H0 = 0) */
    double max_dj, max_dl, max_dc;
    double w_ext, w_anchor, d_scheme, d_damping, d_guard; /* sums over the run */
    double max_balance;       /* max over steps of |dH - (W + Wa - Ds - Dd - Dg)| / scale, */
    long max_balance_step;    /* scale = |H_n| + |W| + |Wa| + |Ds| + |Dd| + |Dg|; its step */
    /* H of the stored states in tp_q (tests/lib/passive.c: __float128 on the x86-64 host, long
     * double elsewhere; independent of the library):
     * steps where it rose, where it rose by more than the work supplied (beyond the
     * evaluation's own error bound), and the largest one-step rise relative to h_scale */
    long h_rises, h_excess, max_rise_step;
    long h_quad;   /* steps evaluated in tp_q: where double-word arithmetic could not decide
                      (tp_delta_h_fast), and a rise that may be the largest (its value) */
    double max_rise;
    int h_checked; /* 0: a potential tests/lib/passive.c cannot evaluate */
} sim_stats;

static void csv_header(FILE *f, const sim_scene *s)
{
    int b;
    fprintf(f, "t,H,dH_rel,Jx,Jy,Jz,Lx,Ly,Lz,Cx,Cy,Cz,dJ,dL,dC,iters,W_ext,D_scheme,D_damping");
    for (b = 0; b < s->n_bodies; b++) {
        char nm[SIM_NAME_MAX + 8];
        if (s->body_name[b][0])
            snprintf(nm, sizeof nm, "%s", s->body_name[b]);
        else
            snprintf(nm, sizeof nm, "b%d", b);
        fprintf(f, ",%s_qx,%s_qy,%s_qz,%s_px,%s_py,%s_pz", nm, nm, nm, nm, nm, nm);
    }
    fputc('\n', f);
}

static void csv_row(FILE *f, const edmi_invariants *inv, const sim_stats *st, double dj,
                    double dl, double dc, int iters, int digits)
{
    int b, i;
    fprintf(f, "%.17g,%.17g,%.17g", (double)sys.t, (double)inv->h,
            ((double)inv->h - st->h0) / st->h_scale);
    for (i = 0; i < 3; i++)
        fprintf(f, ",%.17g", (double)inv->j[i]);
    for (i = 0; i < 3; i++)
        fprintf(f, ",%.17g", (double)inv->l[i]);
    for (i = 0; i < 3; i++)
        fprintf(f, ",%.17g", (double)inv->c[i]);
    fprintf(f, ",%.6g,%.6g,%.6g,%d,%.17g,%.17g,%.17g", dj, dl, dc, iters, st->w_ext, st->d_scheme,
            st->d_damping);
    for (b = 0; b < sys.n_bodies; b++) {
        const edmi_body *bd = &sys.body[b];
        fprintf(f, ",%.*g,%.*g,%.*g,%.*g,%.*g,%.*g", digits, (double)bd->q[0], digits,
                (double)bd->q[1], digits, (double)bd->q[2], digits, (double)bd->p[0], digits,
                (double)bd->p[1], digits, (double)bd->p[2]);
    }
    fputc('\n', f);
}

/* The scheme as a short label: "PM", "LG", "LG-Q/Janz 1e-08". */
static void scheme_label(const edmi_params *p, char *buf, size_t n)
{
    static const char *const up[] = {"MP", "LG", "GE", "PM", "PT"};
    static const char *const alt[] = {"Janz", "Gonzalez", "GE", "PM", "PT"};
    if (p->scheme == EDMI_SCHEME_LG && p->lg_form == EDMI_LG_QUOTIENT)
        snprintf(buf, n, "LG-Q/%s %.0e", alt[p->lg_alt], (double)p->tol_q);
    else
        snprintf(buf, n, "%s", up[p->scheme]);
}

static const char *base_name(const char *path, char *buf, size_t n)
{
    const char *s = strrchr(path, '/');
    char *dot;
    snprintf(buf, n, "%s", s ? s + 1 : path);
    dot = strrchr(buf, '.');
    if (dot && strcmp(dot, ".scene") == 0)
        *dot = '\0';
    return buf;
}

/* Which momenta the scene conserves: L and C(t) need no anchors, no field and no force
 * ports; J needs no field and no ports, and every anchor at the origin (sections 2 and 4.1
 * of the paper). why names what the scene has of these. */
static void conserved(const sim_scene *s, int *j_ok, int *lc_ok, char *why, size_t n)
{
    int i, anchors = 0, off_origin = 0;
    int field = s->has_field && (s->g[0] != 0 || s->g[1] != 0 || s->g[2] != 0);
    for (i = 0; i < s->n_links; i++)
        if (s->link[i].b == EDMI_ANCHOR) {
            anchors = 1;
            if (s->link[i].anchor[0] != 0 || s->link[i].anchor[1] != 0 ||
                s->link[i].anchor[2] != 0)
                off_origin = 1;
        }
    *lc_ok = !anchors && !field && s->n_forces == 0 && s->n_walls == 0;
    *j_ok = !off_origin && !field && s->n_forces == 0 && s->n_walls == 0;
    snprintf(why, n, "%s%s%s%s%s%s%s", anchors ? "anchors" : "",
             anchors && (field || s->n_forces) ? ", " : "", field ? "field" : "",
             field && s->n_forces ? ", " : "", s->n_forces ? "force ports" : "",
             s->n_walls && (anchors || field || s->n_forces) ? ", " : "",
             s->n_walls ? "walls" : "");
}

/* ---- --ref: trajectory error against a reference ------------------------------------------ */

/* Errors of the current state against one reference state. */
typedef struct sim_err {
    long matched;          /* reference times compared */
    double t_last;         /* the last of them */
    double q_max, q_final; /* max over bodies of |q - q_ref|: largest over the matched times,
                              and at the last one */
    double p_max, p_final; /* the same for p */
    double h_max;          /* max |H - H_ref| / |H_ref at the first matched time| */
    double h_scale;
} sim_err;

/* A trace written by --csv, read one row at a time as the run reaches its times. */
typedef struct sim_ref {
    FILE *f;
    const char *path;
    long line;
    int have;                 /* row below holds an unread reference row */
    double t, h;
    double q[EDMI_MAX_BODIES][3], p[EDMI_MAX_BODIES][3];
} sim_ref;

#define SIM_REF_COLUMNS 19 /* t .. D_damping before the bodies (csv_header) */

static void ref_fail(const sim_ref *r, const char *what)
{
    if (r->line > 0)
        fprintf(stderr, "edmi-sim: %s:%ld: %s\n", r->path, r->line, what);
    else
        fprintf(stderr, "edmi-sim: %s: %s\n", r->path, what);
    exit(2);
}

static void ref_open(sim_ref *r, const char *path, int n_bodies)
{
    char line[SIM_LINE_MAX * 8];
    int commas = 0;
    const char *c;
    memset(r, 0, sizeof *r);
    r->path = path;
    r->f = fopen(path, "r");
    if (!r->f) {
        fprintf(stderr, "edmi-sim: --ref %s: %s\n", path, strerror(errno));
        exit(2);
    }
    if (!fgets(line, sizeof line, r->f) || strncmp(line, "t,H,dH_rel,", 11) != 0)
        ref_fail(r, "not an edmi-sim --csv trace (no header line \"t,H,dH_rel,...\")");
    r->line = 1;
    for (c = line; *c; c++)
        commas += *c == ',';
    if (commas + 1 != SIM_REF_COLUMNS + 6 * n_bodies) {
        char msg[160];
        snprintf(msg, sizeof msg, "the trace has %d bodies, the scene %d",
                 (commas + 1 - SIM_REF_COLUMNS) / 6, n_bodies);
        ref_fail(r, msg);
    }
}

/* Read the next row into r; 0 at the end of the file. */
static int ref_next(sim_ref *r, int n_bodies)
{
    char line[SIM_LINE_MAX * 8], *s, *e;
    int col, b, i;
    do {
        if (!fgets(line, sizeof line, r->f))
            return 0;
        r->line++;
    } while (line[0] == '\n');
    if (!strchr(line, '\n') && !feof(r->f))
        ref_fail(r, "line too long");
    s = line;
    for (col = 0; col < SIM_REF_COLUMNS + 6 * n_bodies; col++) {
        double x = strtod(s, &e);
        if (e == s || (*e != ',' && *e != '\n' && *e != '\0') ||
            (col + 1 < SIM_REF_COLUMNS + 6 * n_bodies && *e != ',') || !isfinite(x))
            ref_fail(r, "bad number or too few columns");
        if (col == 0)
            r->t = x;
        else if (col == 1)
            r->h = x;
        else if (col >= SIM_REF_COLUMNS) {
            b = (col - SIM_REF_COLUMNS) / 6;
            i = (col - SIM_REF_COLUMNS) % 6;
            if (i < 3)
                r->q[b][i] = x;
            else
                r->p[b][i - 3] = x;
        }
        s = e + 1;
    }
    r->have = 1;
    return 1;
}

/* Largest |q - q_ref| (from_p: |p - p_ref|) over the bodies of the current state. */
static double state_err(const double (*xr)[3], int from_p)
{
    double worst = 0;
    int b;
    for (b = 0; b < sys.n_bodies; b++) {
        const edmi_real *v = from_p ? sys.body[b].p : sys.body[b].q;
        double d[3];
        int i;
        for (i = 0; i < 3; i++)
            d[i] = (double)v[i] - xr[b][i];
        if (norm3d(d) > worst)
            worst = norm3d(d);
    }
    return worst;
}

static void err_add(sim_err *e, double t, double dq, double dp, double dh_abs, double h_ref)
{
    if (e->matched == 0)
        e->h_scale = h_ref != 0.0 ? fabs(h_ref) : 1.0;
    e->matched++;
    e->t_last = t;
    e->q_final = dq;
    e->p_final = dp;
    e->q_max = dq > e->q_max ? dq : e->q_max;
    e->p_max = dp > e->p_max ? dp : e->p_max;
    if (dh_abs / e->h_scale > e->h_max)
        e->h_max = dh_abs / e->h_scale;
}

/* After a step (or at t = 0): compare with every reference row at this time, skipping the
 * rows before it. Times match within 1e-9 of dt (t itself is compensated-summed). */
static void ref_compare(sim_ref *r, sim_err *e, double t, double dt, double h)
{
    double tol = 1e-9 * dt;
    while (r->have || ref_next(r, sys.n_bodies)) {
        if (r->t < t - tol) { /* a reference time this run steps over */
            r->have = 0;
            continue;
        }
        if (r->t <= t + tol) {
            err_add(e, t, state_err((const double(*)[3])r->q, 0),
                    state_err((const double(*)[3])r->p, 1), fabs(h - r->h), r->h);
            r->have = 0;
        }
        return;
    }
}

/* The stiffest link at the start: omega = sqrt(k / mu), k the larger of |V''(d)| (along the
 * link) and |V'(d)| / d (across it, what makes gravity stiff) at the start length d, mu the
 * reduced mass (a body's own mass on an anchor; the diagonal masses where the mass matrix is
 * coupled). omega dt far above 1 means a step spans many periods of that link: the schemes
 * stay stable and, with the guard, never raise H, but they resolve none of that motion. */
#define SIM_STIFF 2.0 /* omega dt above this: warn (mid-point's phase error ~20 % per step) */

typedef struct sim_stiff {
    int link;        /* the stiffest link, -1 if no link */
    double omega;    /* its frequency [1/T] */
    double omega_dt; /* omega dt */
} sim_stiff;

static void stiffest_link(double dt, sim_stiff *sf)
{
    int j;
    sf->link = -1;
    sf->omega = sf->omega_dt = 0.0;
    for (j = 0; j < sys.n_links; j++) {
        const edmi_link *lk = &sys.link[j];
        const edmi_real *qb = lk->b == EDMI_ANCHOR ? lk->anchor : sys.body[lk->b].q;
        double r[3], d, k, mu, ma = (double)sys.body[lk->a].m, w;
        edmi_pot_parts pp;
        int i;
        for (i = 0; i < 3; i++)
            r[i] = (double)sys.body[lk->a].q[i] - (double)qb[i];
        d = norm3d(r);
        if (!(d > 0.0) || edmi_pot_eval(&lk->pot, (edmi_real)d, &pp) != EDMI_OK)
            continue;
        k = fabs((double)pp.v[2]);
        if (fabs((double)pp.v[1]) / d > k)
            k = fabs((double)pp.v[1]) / d;
        mu = lk->b == EDMI_ANCHOR ? ma
                                  : ma * (double)sys.body[lk->b].m /
                                        (ma + (double)sys.body[lk->b].m);
        w = sqrt(k / mu);
        if (isfinite(w) && w > sf->omega) {
            sf->link = j;
            sf->omega = w;
        }
    }
    sf->omega_dt = sf->omega * dt;
}

/* "link 3 (line 12: body 2 (earth) - body 3)" for messages; without "line 12: " where the
 * message starts with the line. */
static const char *link_label(int j, int with_line, char *buf, size_t n)
{
    const edmi_link *lk = &sys.link[j];
    char a[SIM_NAME_MAX + 16], b[SIM_NAME_MAX + 16];
    snprintf(a, sizeof a, scn.body_name[lk->a][0] ? "body %d (%s)" : "body %d", lk->a,
             scn.body_name[lk->a]);
    if (lk->b == EDMI_ANCHOR)
        snprintf(b, sizeof b, "its anchor");
    else
        snprintf(b, sizeof b, scn.body_name[lk->b][0] ? "body %d (%s)" : "body %d", lk->b,
                 scn.body_name[lk->b]);
    if (with_line)
        snprintf(buf, n, "link %d (line %d: %s - %s)", j, scn.link_line[j], a, b);
    else
        snprintf(buf, n, "link %d (%s - %s)", j, a, b);
    return buf;
}

/* The warning for omega dt > SIM_STIFF, naming the fixes. */
static void warn_stiff(const char *scene, const sim_stiff *sf)
{
    char lbl[128];
    if (sf->link < 0 || !(sf->omega_dt > SIM_STIFF))
        return;
    fprintf(stderr, "edmi-sim: warning: %s: the stiffest link, %s, has omega = %.3g at the "
            "start, so omega dt = %.3g (%.2g of its periods per step): the steps resolve none "
            "of its motion, and the run can be far from the converged answer although H "
            "behaves. Take --dt %.3g or less (omega dt <= %g); --ref converged measures the "
            "error of this dt.\n", scene, link_label(sf->link, 1, lbl, sizeof lbl), sf->omega,
            sf->omega_dt, sf->omega_dt / (2.0 * 3.14159265358979323846),
            SIM_STIFF / sf->omega, SIM_STIFF);
}

/* Why the scene's initial state was refused (EDMI_ERR_RANGE, EDMI_ERR_OVERFLOW and the like
 * from edmi_load_scene or edmi_invariants_of): the first body or link whose own energy or momentum
 * is beyond EDMI_REAL's range, with the line that declared it; else the sum. */
static void explain_state(const char *scene, const char *what, edmi_status s)
{
    int a, j, i;
    for (a = 0; a < scn.n_bodies; a++) {
        const edmi_body *bd = &scn.body[a];
        edmi_real pp = bd->p[0] * bd->p[0] + bd->p[1] * bd->p[1] + bd->p[2] * bd->p[2];
        edmi_real k = pp / bd->m / (edmi_real)2, l[3];
        l[0] = bd->q[1] * bd->p[2] - bd->q[2] * bd->p[1];
        l[1] = bd->q[2] * bd->p[0] - bd->q[0] * bd->p[2];
        l[2] = bd->q[0] * bd->p[1] - bd->q[1] * bd->p[0];
        if (!isfinite(k) || !isfinite(l[0]) || !isfinite(l[1]) || !isfinite(l[2])) {
            fprintf(stderr, "edmi-sim: %s:%d: body %d%s%s%s: its %s is beyond the range of "
                    "EDMI_REAL (largest %.3g): %s refused the state (%s)\n", scene,
                    scn.body_line[a], a, scn.body_name[a][0] ? " (" : "", scn.body_name[a],
                    scn.body_name[a][0] ? ")" : "",
                    isfinite(k) ? "angular momentum q x p" : "kinetic energy |p|^2/(2m)",
                    (double)EDMI_REAL_MAX, what, edmi_status_name(s));
            return;
        }
    }
    for (j = 0; j < scn.n_links; j++) {
        const edmi_link *lk = &scn.link[j];
        const edmi_real *qb = lk->b == EDMI_ANCHOR ? lk->anchor : scn.body[lk->b].q;
        edmi_real r[3], d;
        edmi_pot_parts pp;
        char lbl[128];
        for (i = 0; i < 3; i++)
            r[i] = scn.body[lk->a].q[i] - qb[i];
        d = (edmi_real)norm3r(r);
        if (edmi_pot_eval(&lk->pot, d, &pp) != EDMI_OK || !isfinite(pp.v[0]) ||
            !isfinite(pp.v[1])) {
            fprintf(stderr, "edmi-sim: %s:%d: %s: its energy or force at the start length "
                    "%.6g is beyond the range of EDMI_REAL: %s refused the state (%s)\n", scene,
                    scn.link_line[j], link_label(j, 0, lbl, sizeof lbl), (double)d, what,
                    edmi_status_name(s));
            return;
        }
    }
    fprintf(stderr, "edmi-sim: %s: %s: %s%s\n", scene, what, edmi_status_name(s),
            s == EDMI_ERR_OVERFLOW ? " (every body's and link's own terms are in range: their sum "
                                  "is not)" : "");
}

/* Load the scene (and its ports) with the run's parameters, Newton to its floor. */
static int load_for_reference(void)
{
    edmi_scene view = sim_scene_view(&scn);
    edmi_params prm = scn.params;
    int i;
    prm.tol_r = 0;
    prm.tol_a = 0;
    view.params = &prm;
    if (edmi_load_scene(&sys, &view) != EDMI_OK || sim_scene_add_walls(&scn, &sys) != EDMI_OK)
        return -1;
    for (i = 0; i < scn.n_forces; i++)
        if (edmi_set_force(&sys, scn.force_body[i], scn.force[i]) != EDMI_OK)
            return -1;
    return 0;
}

/* Where a halved run failed (--ref converged). */
typedef struct sim_fail {
    long step;                /* the failed step, 1-based; 0: the load failed */
    double t;                 /* the time it started from */
    edmi_status status;
    edmi_step_result res;
} sim_fail;

/* The state at t_end, n steps of dt; -1 if a step fails (where and why in *f). */
static int final_state(double dt, long n, double q[][3], double p[][3], sim_fail *f)
{
    long k;
    int b, i;
    memset(f, 0, sizeof *f);
    if (load_for_reference()) {
        f->status = EDMI_ERR_PARAM;
        return -1;
    }
    for (k = 0; k < n; k++) {
        f->t = (double)sys.t;
        f->status = edmi_step(&sys, &work, (edmi_real)dt, &f->res);
        if (f->status != EDMI_OK) {
            f->step = k + 1;
            return -1;
        }
    }
    for (b = 0; b < sys.n_bodies; b++)
        for (i = 0; i < 3; i++) {
            q[b][i] = (double)sys.body[b].q[i];
            p[b][i] = (double)sys.body[b].p[i];
        }
    return 0;
}

static double states_diff(const double (*a)[3], const double (*b)[3])
{
    double worst = 0;
    int k;
    for (k = 0; k < scn.n_bodies; k++) {
        double d[3];
        d[0] = a[k][0] - b[k][0];
        d[1] = a[k][1] - b[k][1];
        d[2] = a[k][2] - b[k][2];
        if (norm3d(d) > worst)
            worst = norm3d(d);
    }
    return worst;
}

#define SIM_REF_HALVINGS 6
#define SIM_REF_STEPS 1e8
#define SIM_REF_AGREE 1e-3

typedef struct sim_conv {
    int halvings;     /* dt / 2^halvings is the reference */
    double q_err, p_err; /* the run's error at t_end against it */
    double q_own;     /* the reference's own error: its last two halvings' difference */
    int failed;       /* a halving's step failed: no reference (where: fail) */
    int agreed;       /* the last two halvings agreed to SIM_REF_AGREE of q_err */
    long n;           /* the run's steps */
    sim_fail fail;
} sim_conv;

/* --ref converged: halve dt until two successive halvings agree to SIM_REF_AGREE of the run's
 * own error. q1, p1: the run's final state. The run's scene and system are reloaded. */
static void converged_reference(double dt, long n, const double (*q1)[3],
                                const double (*p1)[3], sim_conv *c)
{
    static double q[2][EDMI_MAX_BODIES][3], p[2][EDMI_MAX_BODIES][3];
    int k, cur = 0;
    memset(c, 0, sizeof *c);
    c->n = n;
    for (k = 1; k <= SIM_REF_HALVINGS && (double)n * (double)(1L << k) <= SIM_REF_STEPS; k++) {
        cur = k & 1;
        if (final_state(dt / (double)(1L << k), n << k, q[cur], p[cur], &c->fail)) {
            c->failed = 1;
            c->halvings = k;
            return;
        }
        c->halvings = k;
        c->q_err = states_diff(q1, (const double(*)[3])q[cur]);
        c->p_err = states_diff(p1, (const double(*)[3])p[cur]);
        if (k >= 2) {
            c->q_own = states_diff((const double(*)[3])q[cur], (const double(*)[3])q[!cur]);
            c->agreed = c->q_own <= SIM_REF_AGREE * c->q_err;
            if (c->agreed)
                return;
        }
    }
}

/* --ref converged where the halvings never agreed to SIM_REF_AGREE of the run's error. */
#define SIM_REF_LOOSE 0.1 /* the reference's own error above this share of the run's: unknown */

static const char *ref_verdict(const sim_conv *c)
{
    return c->q_own > SIM_REF_LOOSE * c->q_err
               ? ": NOT CONVERGED, the error is unknown: the halvings still differ by more "
                 "than a tenth of it. Take a smaller --dt"
               : ": the halvings agreed to less than 1e-3 of the error, so its figure holds "
                 "to about the reference's own error";
}

static void print_ref(const sim_opts *o, const sim_err *e, const sim_conv *c, double dt)
{
    if (!o->ref)
        return;
    if (strcmp(o->ref, "converged") == 0) {
        double h = dt / (double)(1L << c->halvings);
        if (c->failed && c->fail.step == 0)
            printf("vs ref    converged: no reference: the scene did not load again\n");
        else if (c->failed)
            printf("vs ref    converged: no reference: the run at dt/%ld = %.6g (Newton to its "
                   "floor) failed at step %ld of %ld (from t = %.10g): %s after %d Newton "
                   "iterations, scaled residual %.3g. The halved steps did not converge "
                   "either: raise --l-max, allow --substeps, or start from a smaller --dt\n",
                   1L << c->halvings, h, c->fail.step, c->n << c->halvings, c->fail.t,
                   edmi_status_name(c->fail.status), c->fail.res.iterations,
                   (double)c->fail.res.residual);
        else
            printf("vs ref    converged (dt/%ld = %.6g, Newton to its floor): at t_end "
                   "max |q - q_ref| %.3e, max |p - p_ref| %.3e; the reference's own error "
                   "%.1e (its last two halvings)%s\n", 1L << c->halvings, h, c->q_err, c->p_err,
                   c->q_own, c->agreed ? "" : ref_verdict(c));
        return;
    }
    printf("vs ref    %s: %ld times compared (the last t = %.10g): max |q - q_ref| %.3e "
           "(final %.3e), max |p - p_ref| %.3e (final %.3e), max |H - H_ref|/|H_ref| %.3e\n",
           o->ref, e->matched, e->t_last, e->q_max, e->q_final, e->p_max, e->p_final,
           e->h_max);
}

/* The identity holds for the exact solution of the step's equations; the stored one solves
 * them to Newton's floor, a few units of |q| in the last place, where the net force on each
 * body, (p_n+1 - p_n)/dt, does work the identity does not count: sum over bodies of
 * (|q_n| + |q_n+1|) |p_n+1 - p_n| / dt, the scale that error is relative to. It matters
 * where every other term is small (a body released at rest on a slack rope, under a field). */
static long double newton_work(const edmi_system *s0, const edmi_system *s1, double dt)
{
    long double sum = 0.0L;
    int a;
    for (a = 0; a < s1->n_bodies; a++) {
        edmi_real dp[3];
        int i;
        for (i = 0; i < 3; i++)
            dp[i] = s1->body[a].p[i] - s0->body[a].p[i];
        sum += ((long double)norm3r(s0->body[a].q) + (long double)norm3r(s1->body[a].q)) *
               (long double)norm3r(dp) / (long double)dt;
    }
    return sum;
}

/* --energy-balance's tolerance on the largest relative mismatch of a step. */
static double balance_tol(const sim_opts *o)
{
    if (o->balance_tol > 0.0)
        return o->balance_tol;
    /* 256 units of rounding of edmi_real: ~180x the worst seen on the shipped scenes with
     * every scheme (1.4 eps in both precisions, on the spring) */
    return 256.0 * (edmi_is_double_precision() ? DBL_EPSILON : (double)FLT_EPSILON);
}

/* Whether the passivity guard runs: on, or auto with an energy-safe scheme. */
static int guard_runs(const edmi_params *p)
{
    return p->guard == EDMI_GUARD_ON ||
           (p->guard == EDMI_GUARD_AUTO &&
            (p->scheme == EDMI_SCHEME_GE || p->scheme == EDMI_SCHEME_PM || p->scheme == EDMI_SCHEME_PT));
}

static void print_summary(const sim_opts *o, const sim_stats *st, double dt, long n_steps,
                          const edmi_invariants *inv0, const sim_stiff *sf)
{
    char lnk[128];
    const edmi_params *p = &sys.params;
    char why[48], lbl[64];
    int j_ok, lc_ok;
    int guard_on = guard_runs(p);
    scheme_label(p, lbl, sizeof lbl);
    printf("scene     %s%s%s\n", o->scene, scn.title[0] ? ": " : "", scn.title);
    printf("          %d bodies, %d links, %d dampers, field %s, %d force ports", scn.n_bodies,
           scn.n_links, scn.n_dampers, scn.has_field ? "yes" : "no", scn.n_forces);
    if (scn.n_walls > 0)
        printf(", %d walls", scn.n_walls);
    printf("\n");
    printf("scheme    %s", lbl);
    if (p->scheme == EDMI_SCHEME_LG)
        printf(" (%s)", p->lg_form == EDMI_LG_CLOSED ? "closed-form divided difference"
                                                     : "quotient, alternate below tol_Q");
    printf(", tol_R %.3g, tol_A %.3g, l_max %d%s\n", (double)p->tol_r, (double)p->tol_a,
           p->l_max, o->energy_balance ? ", energy balance on" : "");
    printf("steps     %ld of %ld, dt %.6g, t = %.10g\n", st->steps, n_steps, dt, (double)sys.t);
    if (sf->link >= 0)
        printf("stiffest  %s: omega dt %.3g at the start%s\n", link_label(sf->link, 1, lnk, sizeof lnk),
               sf->omega_dt, sf->omega_dt > SIM_STIFF ? ": FAR ABOVE 1, this dt resolves none "
                                                        "of its motion (see the warning)" : "");
    printf("wall      %.3f s (%.3g us/step)\n", st->wall,
           st->steps ? 1e6 * st->wall / (double)st->steps : 0.0);
    printf("Newton    %.3f iterations/step (max %d); %ld steps stopped at the round-off floor\n",
           st->steps ? (double)st->iterations / (double)st->steps : 0.0, st->max_iterations,
           st->stalled);
    if (p->scheme == EDMI_SCHEME_LG && p->lg_form == EDMI_LG_QUOTIENT)
        printf("LG switch %ld steps used the alternate force on some link\n", st->lg_switch_steps);
    printf("H0        %.17g\n", st->h0);
    printf("%s  final %.3e, max %.3e\n",
           st->h0 != 0.0 ? "|H-H0|/|H0|" : "|H-H0| (H0=0)", st->final_dh, st->max_dh);
    conserved(&scn, &j_ok, &lc_ok, why, sizeof why);
    printf("max |J - J0| %.3e   (|J0| = %.6g)%s%s\n", st->max_dj, norm3r(inv0->j),
           j_ok ? "" : "  not an invariant here: ", j_ok ? "" : why);
    printf("max |L - L0| %.3e   (|L0| = %.6g)%s%s\n", st->max_dl, norm3r(inv0->l),
           lc_ok ? "" : "  not an invariant here: ", lc_ok ? "" : why);
    printf("max |C - C0| %.3e   (|C0| = %.6g)%s%s\n", st->max_dc, norm3r(inv0->c),
           lc_ok ? "" : "  not an invariant here: ", lc_ok ? "" : why);
    if (guard_on) {
        printf("guard     on (%s): changed %ld steps (impulse %ld, drag %ld, rounding %ld", 
               sim_guard_word(p->guard), st->guard_steps, st->guard_impulse, st->guard_drag,
               st->guard_round);
        if (st->guard_stop)
            printf(", stop %ld", st->guard_stop);
        printf("), D_guard %.3e in all\n", st->d_guard);
        printf("tank      capacity %g eps of H's terms: held at most %.3e%s (capacity at most "
               "%.3e); certified plainly %ld, in double-word %ld, scaled %ld steps\n",
               (double)p->tank_cap, st->max_tank, st->h0 != 0.0 ? " |H0|" : "", st->max_cap,
               st->cert[EDMI_CERT_PLAIN], st->cert[EDMI_CERT_DOUBLE_WORD],
               st->cert[EDMI_CERT_SCALED]);
    }
    else
        printf("guard     off (%s)\n", sim_guard_word(p->guard));
    if (p->fallback)
        printf("fallback  on: %ld steps stored the fallback state\n", st->fallbacks);
    if (scn.n_forces || scn.n_dampers || o->energy_balance) {
        printf("energy    W_ext %.6e, D_damping %.6e", st->w_ext, st->d_damping);
        if (st->w_anchor != 0.0)
            printf(", W_anchor %.6e", st->w_anchor);
        if (o->energy_balance)
            printf(", D_scheme %.6e", st->d_scheme);
        printf("\n");
    }
    if (st->h_checked && st->max_rise_step > 0)
        printf("H steps   H rose in %ld of %ld steps, by more than the work and the tank supplied "
               "in %ld (%s on the stored states); largest one-step rise %+.3e%s at "
               "step %ld\n",
               st->h_rises, st->steps, st->h_excess, tp_q_name(), st->max_rise,
               st->h0 != 0.0 ? " |H0|" : "", st->max_rise_step);
    else if (st->h_checked)
        printf("H steps   H rose in 0 of %ld steps, by more than the work and the tank supplied in "
               "0 (%s on the stored states): it never rose\n", st->steps, tp_q_name());
    else
        printf("H steps   not checked: a state tests/lib/passive.c cannot evaluate (a "
               "coupled M that is not diagonally dominant)\n");
    if (o->energy_balance && st->h_checked)
        printf("balance   max |H_n+1 - H_n - (W_ext + W_anchor - D_scheme - D_damping - D_guard)| "
               "= %.3e x the terms involved (step %ld); tolerance %.3g: %s\n",
               st->max_balance, st->max_balance_step, balance_tol(o),
               st->max_balance <= balance_tol(o) ? "ok" : "EXCEEDED");
    else if (o->energy_balance)
        printf("balance   not checked (see H steps)\n");
}

/* "%9.2e", or "n/a" when the quantity is not an invariant of the scene. */
static const char *cell(double v, int ok, char *buf, size_t n)
{
    if (ok)
        snprintf(buf, n, "%9.2e", v);
    else
        snprintf(buf, n, "%9s", "n/a");
    return buf;
}

/* With --ref, two more cells: the largest and the final position error. */
static void print_row(const sim_opts *o, const sim_stats *st, double q_max, double q_final)
{
    char lbl[64], nm[64], cj[16], cl[16], cc[16], why[48];
    int j_ok, lc_ok;
    conserved(&scn, &j_ok, &lc_ok, why, sizeof why);
    if (o->label)
        snprintf(lbl, sizeof lbl, "%s", o->label);
    else
        scheme_label(&sys.params, lbl, sizeof lbl);
    printf("| %-13s | %-15s | %7ld | %7.3g | %5.2f | %9.2e | %10.2e | %s | %s | %s |",
           base_name(o->scene, nm, sizeof nm), lbl, st->steps,
           st->steps ? 1e6 * st->wall / (double)st->steps : 0.0,
           st->steps ? (double)st->iterations / (double)st->steps : 0.0, st->max_dh, st->final_dh,
           cell(st->max_dj, j_ok, cj, sizeof cj), cell(st->max_dl, lc_ok, cl, sizeof cl),
           cell(st->max_dc, lc_ok, cc, sizeof cc));
    if (o->ref)
        printf(" %9.2e | %9.2e |", q_max, q_final);
    printf("\n");
}

/* --h-check FILE: the H check's counts, one line (examples/run_examples.sh adds them up). */
static int write_h_check(const char *path, const sim_stats *st)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "edmi-sim: cannot write %s: %s\n", path, strerror(errno));
        return 1;
    }
    fprintf(f, "steps %ld checked %ld rose %ld beyond %ld quad %ld guard %s\n", st->steps,
            st->h_checked ? st->steps : 0L, st->h_rises, st->h_excess, st->h_quad,
            guard_runs(&sys.params) ? "on" : "off");
    if (fclose(f) != 0) {
        fprintf(stderr, "edmi-sim: writing %s: %s\n", path, strerror(errno));
        return 1;
    }
    return 0;
}

static void progress(const sim_opts *o, long k, long n, double t0, double *next, int tty)
{
    double el = now_s() - t0;
    if (o->quiet || el < *next)
        return;
    fprintf(stderr, "%sedmi-sim: %3.0f%% (step %ld of %ld, t = %.6g, %.0f s, about %.0f s left)%s",
            tty ? "\r" : "", 100.0 * (double)k / (double)n, k, n, (double)sys.t, el,
            el * (double)(n - k) / (double)k, tty ? "" : "\n");
    fflush(stderr);
    *next = el + (tty ? SIM_PROGRESS_EVERY : SIM_PROGRESS_LOG);
}

int main(int argc, char **argv)
{
    sim_opts o;
    sim_stats st;
    char err[SIM_ERR_MAX];
    edmi_scene view;
    edmi_invariants inv0, inv, prev;
    edmi_status s;
    FILE *csv = 0;
    static sim_ref ref;
    static edmi_system run_sys, prev_sys; /* prev_sys: bodies and anchors of the last state */
    tp_hdw h_prev;                        /* H of prev_sys in double-word (tests/lib/passive.c) */
    sim_err rerr;
    sim_conv conv;
    sim_stiff stiff;
    int file_ref;
    double dt, t_end, t0, next_report = SIM_PROGRESS_AFTER;
    long n_steps, every, k;
    int i, tty, reported = 0, failed = 0, digits;

    parse_args(argc, argv, &o);
    if (sim_scene_load(o.scene, &scn, err, sizeof err)) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    /* command line over scene settings */
    if (o.has_scheme)
        scn.params.scheme = o.scheme;
    if (o.has_switch) {
        scn.params.lg_form = o.sw.lg_form;
        scn.params.lg_alt = o.sw.lg_alt;
    }
    if (o.has_tol_q)
        scn.params.tol_q = (edmi_real)o.tol_q;
    if (o.has_tol_r)
        scn.params.tol_r = (edmi_real)o.tol_r;
    if (o.has_tol_a)
        scn.params.tol_a = (edmi_real)o.tol_a;
    if (o.has_l_max)
        scn.params.l_max = (int)o.l_max;
    if (o.has_guard)
        scn.params.guard = o.guard;
    if (o.has_fallback)
        scn.params.fallback = o.fallback;
    if (o.has_substeps)
        scn.params.substep_levels = o.substeps;
    if (o.has_tank_cap)
        scn.params.tank_cap = (edmi_real)o.tank_cap;
    scn.params.energy_balance = o.energy_balance;
    if (o.emit_c) {
        if (scn.n_walls > 0) {
            fprintf(stderr, "edmi-sim: %s: --emit-c: walls are not scene data (an edmi_scene "
                    "holds none); add them with edmi_add_wall() after edmi_load_scene()\n",
                    o.scene);
            return 1;
        }
        emit_c(&scn, o.scene);
        return 0;
    }
    dt = o.dt > 0.0 ? o.dt : scn.dt;
    t_end = o.t_end > 0.0 ? o.t_end : scn.t_end;
    every = o.every > 0 ? o.every : (scn.every > 0 ? scn.every : 1);
    digits = o.digits > 0 ? (int)o.digits : 17;
    if (!(dt > 0.0)) {
        fprintf(stderr, "edmi-sim: %s: no time step: give `set dt X` in the scene or --dt X\n",
                o.scene);
        return 2;
    }
    if (!(t_end > 0.0)) {
        fprintf(stderr, "edmi-sim: %s: no end time: give `set t_end X` in the scene or "
                "--t-end X\n", o.scene);
        return 2;
    }
    if (t_end / dt > 1e12) {
        fprintf(stderr, "edmi-sim: t_end / dt = %.3g steps is too many\n", t_end / dt);
        return 2;
    }
    n_steps = (long)floor(t_end / dt + 0.5);
    if (n_steps < 1) {
        fprintf(stderr, "edmi-sim: t_end = %g is less than dt/2 = %g: no step to take\n", t_end,
                0.5 * dt);
        return 2;
    }
    if (fabs((double)n_steps * dt - t_end) > 1e-9 * t_end)
        fprintf(stderr, "edmi-sim: note: t_end = %.10g is not a multiple of dt = %.10g; "
                "running %ld steps to t = %.10g\n", t_end, dt, n_steps, (double)n_steps * dt);
    if (o.has_switch && scn.params.scheme != EDMI_SCHEME_LG)
        fprintf(stderr, "edmi-sim: note: --lg-switch has no effect with --scheme %s\n",
                sim_scheme_word(scn.params.scheme));

    view = sim_scene_view(&scn);
    s = edmi_load_scene(&sys, &view);
    if (s != EDMI_OK) {
        explain_state(o.scene, "edmi_load_scene", s);
        return 2;
    }
    s = sim_scene_add_walls(&scn, &sys);
    if (s != EDMI_OK) {
        fprintf(stderr, "edmi-sim: %s: edmi_add_wall: %s\n", o.scene, edmi_status_name(s));
        return 2;
    }
    for (i = 0; i < scn.n_forces; i++) {
        s = edmi_set_force(&sys, scn.force_body[i], scn.force[i]);
        if (s != EDMI_OK) {
            fprintf(stderr, "edmi-sim: %s: edmi_set_force(%d): %s\n", o.scene, scn.force_body[i],
                    edmi_status_name(s));
            return 2;
        }
    }
    s = edmi_invariants_of(&sys, &inv0);
    if (s != EDMI_OK) {
        explain_state(o.scene, "edmi_invariants_of", s);
        return 2;
    }
    stiffest_link(dt, &stiff);
    warn_stiff(o.scene, &stiff);

    memset(&rerr, 0, sizeof rerr);
    memset(&conv, 0, sizeof conv);
    file_ref = o.ref && strcmp(o.ref, "converged") != 0;
    if (file_ref) {
        ref_open(&ref, o.ref, scn.n_bodies);
        ref_compare(&ref, &rerr, 0.0, dt, (double)inv0.h);
    }
    memset(&st, 0, sizeof st);
    st.h_checked = 1;
    tp_h_dw(&sys, &h_prev);
    prev_sys = sys;
    st.h0 = (double)inv0.h;
    st.h_scale = st.h0 != 0.0 ? fabs(st.h0) : 1.0;
    if (o.csv) {
        csv = strcmp(o.csv, "-") == 0 ? stdout : fopen(o.csv, "w");
        if (!csv) {
            fprintf(stderr, "edmi-sim: cannot write %s: %s\n", o.csv, strerror(errno));
            return 2;
        }
        csv_header(csv, &scn);
        csv_row(csv, &inv0, &st, 0.0, 0.0, 0.0, 0, digits);
    }

    tty = isatty(2);
    prev = inv0;
    t0 = now_s();
    for (k = 1; k <= n_steps; k++) {
        edmi_step_result res;
        double dh, dj, dl, dc;
        s = edmi_step(&sys, &work, (edmi_real)dt, &res);
        if (s != EDMI_OK) {
            fprintf(stderr, "%sedmi-sim: step %ld of %ld (from t = %.10g) failed: %s after %d "
                    "Newton iterations (scaled residual %.3g, last correction %.3g)%s\n",
                    reported && tty ? "\n" : "", k, n_steps, (double)sys.t, edmi_status_name(s),
                    res.iterations, (double)res.residual, (double)res.correction,
                    stiff.omega_dt > SIM_STIFF ? "; omega dt is far above 1 (the warning above): "
                                                 "take a smaller --dt" : "");
            failed = 1;
            break;
        }
        s = edmi_invariants_of(&sys, &inv);
        if (s != EDMI_OK) {
            fprintf(stderr, "edmi-sim: invariants after step %ld: %s\n", k, edmi_status_name(s));
            st.steps = k;
            failed = 1;
            break;
        }
        st.steps = k;
        st.iterations += res.iterations;
        if (res.iterations > st.max_iterations)
            st.max_iterations = res.iterations;
        if (res.stop == EDMI_STOP_CONVERGED || res.stop == EDMI_STOP_STALLED)
            st.stalled++;
        if (res.lg_switches > 0)
            st.lg_switch_steps++;
        if (res.stop == EDMI_STOP_FALLBACK)
            st.fallbacks++;
        if (res.guard_action) {
            st.guard_steps++;
            st.guard_impulse += (res.guard_action & EDMI_MOVE_IMPULSE) != 0;
            st.guard_drag += (res.guard_action & EDMI_MOVE_DRAG) != 0;
            st.guard_round += (res.guard_action & EDMI_MOVE_ROUND) != 0;
            st.guard_stop += (res.guard_action & EDMI_MOVE_STOP) != 0;
        }
        if ((unsigned)res.certificate < 4u)
            st.cert[res.certificate]++;
        if ((double)res.tank / st.h_scale > st.max_tank)
            st.max_tank = (double)res.tank / st.h_scale;
        if ((double)res.tank_cap / st.h_scale > st.max_cap)
            st.max_cap = (double)res.tank_cap / st.h_scale;
        st.w_ext += (double)res.work_ext;
        st.w_anchor += (double)res.work_anchor;
        st.d_scheme += (double)res.diss_scheme;
        st.d_damping += (double)res.diss_damping;
        st.d_guard += (double)res.diss_guard;
        dh = fabs((double)inv.h - st.h0) / st.h_scale;
        dj = diff3(inv.j, inv0.j);
        dl = diff3(inv.l, inv0.l);
        dc = diff3(inv.c, inv0.c);
        if (dh > st.max_dh)
            st.max_dh = dh;
        if (dj > st.max_dj)
            st.max_dj = dj;
        if (dl > st.max_dl)
            st.max_dl = dl;
        if (dc > st.max_dc)
            st.max_dc = dc;
        if (st.h_checked) {
            /* tp_delta_h's decisions, in double-word arithmetic where that settles them
             * (tests/lib/passive.c); the energy balance needs tp_q's dh and mag themselves */
            tp_delta d;
            tp_hdw h;
            int ok;
            if (o.energy_balance) {
                ok = tp_delta_h(&prev_sys, &sys, &res, &d);
            } else {
                tp_h_dw(&sys, &h);
                ok = tp_delta_h_fast(&prev_sys, &h_prev, &sys, &h, &res, &d);
                h_prev = h;
            }
            /* a rise that may be the run's largest: the summary prints tp_q's value */
            if (ok && !d.quad && !o.row &&
                (d.dh + d.err) / (long double)st.h_scale >=
                    (long double)st.max_rise * (1.0L - 0x1p-30L))
                ok = tp_delta_h(&prev_sys, &sys, &res, &d);
            if (ok) {
                st.h_quad += d.quad;
                if (o.energy_balance) {
                    /* H's change from the stored states (tp_q, rounded to long double),
                     * against the reported terms, relative to the magnitude of both: H itself
                     * can be ~0 (a cable released at rest at the origin) while its terms are
                     * not */
                    long double w = (long double)res.work_ext, wa = (long double)res.work_anchor,
                                ds = (long double)res.diss_scheme,
                                dd = (long double)res.diss_damping,
                                dg = (long double)res.diss_guard;
                    long double mis = fabsl(d.dh - (w + wa - ds - dd - dg));
                    long double scale = d.mag + fabsl(w) + fabsl(wa) + fabsl(ds) + fabsl(dd) +
                                        fabsl(dg) + newton_work(&prev_sys, &sys, dt);
                    double rel = (double)(scale > 0.0L ? mis / scale : mis);
                    if (rel > st.max_balance) {
                        st.max_balance = rel;
                        st.max_balance_step = k;
                    }
                }
                double rise = (double)(d.dh / (long double)st.h_scale);
                st.h_rises += d.rose;     /* dh > err, decided in tp_q */
                st.h_excess += d.broken; /* dh > w + err, decided in tp_q */
                if (rise > st.max_rise) {
                    st.max_rise = rise;
                    st.max_rise_step = k;
                }
                for (i = 0; i < sys.n_bodies; i++)
                    prev_sys.body[i] = sys.body[i];
                prev_sys.tank = sys.tank;
                for (i = 0; i < sys.n_links; i++)
                    memcpy(prev_sys.link[i].anchor, sys.link[i].anchor, sizeof sys.link[i].anchor);
            } else {
                st.h_checked = 0;
            }
        }
        prev = inv;
        if (file_ref)
            ref_compare(&ref, &rerr, (double)sys.t, dt, (double)inv.h);
        if (csv && (k % every == 0 || k == n_steps))
            csv_row(csv, &inv, &st, dj, dl, dc, res.iterations, digits);
        if ((k & 63) == 0) {
            double before = next_report;
            progress(&o, k, n_steps, t0, &next_report, tty);
            if (next_report != before)
                reported = 1;
        }
    }
    st.wall = now_s() - t0;
    if (reported && tty && !o.quiet)
        fprintf(stderr, "\r%60s\r", "");
    st.final_dh = ((double)prev.h - st.h0) / st.h_scale;
    if (csv && csv != stdout && fclose(csv) != 0) {
        fprintf(stderr, "edmi-sim: writing %s: %s\n", o.csv, strerror(errno));
        return 1;
    }
    if (file_ref) {
        fclose(ref.f);
        if (rerr.matched == 0) {
            fprintf(stderr, "edmi-sim: %s: no row at a time of this run (t = 0 to %.10g, dt "
                    "%.6g)\n", o.ref, (double)sys.t, dt);
            return 2;
        }
    }
    if (o.ref && !file_ref && !failed) {
        static double q1[EDMI_MAX_BODIES][3], p1[EDMI_MAX_BODIES][3];
        int b, c;
        for (b = 0; b < sys.n_bodies; b++)
            for (c = 0; c < 3; c++) {
                q1[b][c] = (double)sys.body[b].q[c];
                p1[b][c] = (double)sys.body[b].p[c];
            }
        run_sys = sys;
        converged_reference(dt, n_steps, (const double(*)[3])q1, (const double(*)[3])p1,
                            &conv);
        sys = run_sys;
        failed |= conv.failed || (!conv.agreed && conv.q_own > SIM_REF_LOOSE * conv.q_err);
    }
    if (o.row) {
        print_row(&o, &st, file_ref ? rerr.q_max : conv.q_err,
                  file_ref ? rerr.q_final : conv.q_err);
    } else {
        print_summary(&o, &st, dt, n_steps, &inv0, &stiff);
        print_ref(&o, &rerr, &conv, dt);
    }
    if (o.h_check && write_h_check(o.h_check, &st))
        return 2;
    if (failed)
        return 1;
    if (o.energy_balance && st.h_checked && !(st.max_balance <= balance_tol(&o))) {
        fprintf(stderr, "edmi-sim: energy balance: largest mismatch %.3e x the terms involved "
                "(step %ld) exceeds the tolerance %.3g\n", st.max_balance, st.max_balance_step,
                balance_tol(&o));
        return 3;
    }
    return 0;
}
