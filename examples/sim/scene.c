/*
 * scene.c: parser of the edmi text scene format (host side; see scene.h and
 * docs/simulator.md for the format).
 *
 * The parser checks everything edmi_load_scene() would refuse, one line at a time, so that
 * the message can name the line: counts of fields, numbers, finiteness, signs, indices,
 * capacities, names, duplicates. It builds plain edmi data and never calls the library
 * except for edmi_default_params().
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "scene.h"

#define SIM__MAX_TOK 24
#define SIM__MAX_FILE (16L * 1024L * 1024L)

/* The `set` keys, in the order their "already set" lines are kept. */
enum {
    SIM__SET_SCHEME,
    SIM__SET_LG_SWITCH,
    SIM__SET_DT,
    SIM__SET_T_END,
    SIM__SET_TOL_Q,
    SIM__SET_TOL_R,
    SIM__SET_TOL_A,
    SIM__SET_L_MAX,
    SIM__SET_EVERY,
    SIM__SET_GUARD,
    SIM__SET_FALLBACK,
    SIM__SET_SUBSTEPS,
    SIM__N_SET
};
static const char *const sim__set_names[SIM__N_SET] = {
    "scheme", "lg_switch", "dt", "t_end", "tol_q", "tol_r", "tol_a", "l_max", "every",
    "guard", "fallback", "substeps"};

/* Parsing state of one file. */
typedef struct sim__ctx {
    const char *file;
    int line;
    char *err;
    size_t err_size;
    sim_scene *s;
    char key[32];                /* the line's key as named in messages ("body", "set dt") */
    char *tok[SIM__MAX_TOK];
    int ntok;
    int title_line;
    int field_line;
    int set_line[SIM__N_SET];
    int force_line[EDMI_MAX_BODIES]; /* by body: line of its force port, 0 if none */
} sim__ctx;

/* A potential as written: built-in kind and parameters; gravity is `inverse` with
 * k = G m_A m_B per pair. */
typedef struct sim__pot_spec {
    edmi_pot_kind kind;
    double a, b;
    int gravity;
} sim__pot_spec;

#if defined(__GNUC__) || defined(__clang__)
static int sim__fail(sim__ctx *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
#endif

/* Write "FILE:LINE: KEY: message" into c->err; return -1. */
static int sim__fail(sim__ctx *c, const char *fmt, ...)
{
    va_list ap;
    int n;
    if (!c->err || c->err_size == 0)
        return -1;
    if (c->line > 0)
        n = snprintf(c->err, c->err_size, "%s:%d: ", c->file, c->line);
    else
        n = snprintf(c->err, c->err_size, "%s: ", c->file);
    if (n < 0 || (size_t)n >= c->err_size)
        return -1;
    va_start(ap, fmt);
    vsnprintf(c->err + n, c->err_size - (size_t)n, fmt, ap);
    va_end(ap);
    return -1;
}

/* ---- words ------------------------------------------------------------------------------ */

int sim_parse_scheme(const char *w, edmi_scheme *out)
{
    static const char *const names[] = {"mp", "lg", "ge", "pm", "pt"};
    static const edmi_scheme values[] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcmp(w, names[i]) == 0) {
            *out = values[i];
            return 0;
        }
    return -1;
}

int sim_parse_lg_switch(const char *w, edmi_params *prm)
{
    static const char *const names[] = {"janz", "gonzalez", "ge", "pm", "pt"};
    static const edmi_lg_alt values[] = {EDMI_LG_ALT_JANZ, EDMI_LG_ALT_GONZALEZ, EDMI_LG_ALT_GE,
                                         EDMI_LG_ALT_PM, EDMI_LG_ALT_PT};
    size_t i;
    if (strcmp(w, "closed") == 0) {
        prm->lg_form = EDMI_LG_CLOSED;
        return 0;
    }
    for (i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcmp(w, names[i]) == 0) {
            prm->lg_form = EDMI_LG_QUOTIENT;
            prm->lg_alt = values[i];
            return 0;
        }
    return -1;
}

int sim_parse_guard(const char *w, edmi_guard_mode *out)
{
    static const char *const names[] = {"auto", "on", "off"};
    static const edmi_guard_mode values[] = {EDMI_GUARD_AUTO, EDMI_GUARD_ON, EDMI_GUARD_OFF};
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcmp(w, names[i]) == 0) {
            *out = values[i];
            return 0;
        }
    return -1;
}

int sim_parse_on_off(const char *w, int *out)
{
    if (strcmp(w, "on") == 0 || strcmp(w, "off") == 0) {
        *out = w[1] == 'n';
        return 0;
    }
    return -1;
}

const char *sim_guard_word(edmi_guard_mode g)
{
    switch (g) {
    case EDMI_GUARD_AUTO: return "auto";
    case EDMI_GUARD_ON: return "on";
    case EDMI_GUARD_OFF: return "off";
    default: return "?";
    }
}

const char *sim_scheme_word(edmi_scheme s)
{
    switch (s) {
    case EDMI_SCHEME_MP: return "mp";
    case EDMI_SCHEME_LG: return "lg";
    case EDMI_SCHEME_GE: return "ge";
    case EDMI_SCHEME_PM: return "pm";
    case EDMI_SCHEME_PT: return "pt";
    default: return "?";
    }
}

const char *sim_lg_switch_word(const edmi_params *prm)
{
    if (prm->lg_form == EDMI_LG_CLOSED)
        return "closed";
    switch (prm->lg_alt) {
    case EDMI_LG_ALT_JANZ: return "janz";
    case EDMI_LG_ALT_GONZALEZ: return "gonzalez";
    case EDMI_LG_ALT_GE: return "ge";
    case EDMI_LG_ALT_PM: return "pm";
    case EDMI_LG_ALT_PT: return "pt";
    default: return "?";
    }
}

/* ---- fields ----------------------------------------------------------------------------- */

/* Exactly `n` fields after the key's first `first` tokens, else a message naming the first
 * missing field or the first extra one. */
static int sim__count(sim__ctx *c, int first, int n, const char *const *names,
                      const char *usage)
{
    if (c->ntok < first + n)
        return sim__fail(c, "%s: missing %s (usage: %s)", c->key, names[c->ntok - first], usage);
    if (c->ntok > first + n)
        return sim__fail(c, "%s: unexpected extra field '%s' (usage: %s)", c->key,
                         c->tok[first + n], usage);
    return 0;
}

/* Token i as a finite real that edmi_real can hold, named `what` in messages. */
static int sim__real(sim__ctx *c, int i, const char *what, double *out)
{
    const char *t = c->tok[i];
    char *end;
    double v;
    errno = 0;
    v = strtod(t, &end);
    if (end == t || *end != '\0')
        return sim__fail(c, "%s: bad number '%s' for %s", c->key, t, what);
    if (!isfinite(v) || (errno == ERANGE && fabs(v) > 1.0))
        return sim__fail(c, "%s: %s = %s is not finite", c->key, what, t);
    if (fabs(v) > (double)EDMI_REAL_MAX)
        return sim__fail(c, "%s: %s = %s does not fit in EDMI_REAL (max %g)", c->key, what, t,
                         (double)EDMI_REAL_MAX);
    *out = v;
    return 0;
}

static int sim__positive(sim__ctx *c, int i, const char *what, double *out)
{
    if (sim__real(c, i, what, out))
        return -1;
    if (!(*out > 0.0))
        return sim__fail(c, "%s: %s = %s must be > 0", c->key, what, c->tok[i]);
    return 0;
}

static int sim__nonnegative(sim__ctx *c, int i, const char *what, double *out)
{
    if (sim__real(c, i, what, out))
        return -1;
    if (!(*out >= 0.0))
        return sim__fail(c, "%s: %s = %s must be >= 0", c->key, what, c->tok[i]);
    return 0;
}

/* A decimal integer token: 0 and *out set, 1 if the token is not an integer at all. */
static int sim__integer(const char *t, long *out)
{
    const char *p = t;
    char *end;
    if (*p == '-' || *p == '+')
        p++;
    if (*p < '0' || *p > '9')
        return 1;
    errno = 0;
    *out = strtol(t, &end, 10);
    if (*end != '\0')
        return 1;
    if (errno == ERANGE)
        *out = *t == '-' ? -1 : 2147483647L;
    return 0;
}

static int sim__int_setting(sim__ctx *c, int i, long *out)
{
    if (sim__integer(c->tok[i], out))
        return sim__fail(c, "%s: bad integer '%s'", c->key, c->tok[i]);
    if (*out < 1)
        return sim__fail(c, "%s: %s must be >= 1", c->key, c->tok[i]);
    return 0;
}

static int sim__name_ok(const char *t)
{
    size_t n = 0;
    if (!((*t >= 'a' && *t <= 'z') || (*t >= 'A' && *t <= 'Z') || *t == '_'))
        return 0;
    for (; t[n]; n++) {
        char ch = t[n];
        if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
              ch == '_' || ch == '-' || ch == '.'))
            return 0;
    }
    return n < SIM_NAME_MAX;
}

/* Whether a word names a potential (a line that left out a body reads one where a body
 * belongs). */
static int sim__is_pot_word(const char *t)
{
    static const char *const pots[] = {"harmonic", "quartic", "neo_hooke", "lj", "inverse",
                                       "gravity"};
    size_t i;
    for (i = 0; i < sizeof pots / sizeof pots[0]; i++)
        if (strcmp(t, pots[i]) == 0)
            return 1;
    return 0;
}

/* The usage line of a key that names bodies. */
static const char *sim__key_usage(const char *key)
{
    static const char *const use[][2] = {{"pair", "pair A B POTENTIAL PARAMS"},
                                         {"chain", "chain FIRST LAST POTENTIAL PARAMS"},
                                         {"anchor", "anchor BODY x y z POTENTIAL PARAMS"},
                                         {"mass", "mass A B m_AB"},
                                         {"force", "force BODY fx fy fz"}};
    size_t i;
    for (i = 0; i < sizeof use / sizeof use[0]; i++)
        if (strcmp(key, use[i][0]) == 0)
            return use[i][1];
    return key;
}

/* A body named by index (0-based, in order of declaration) or by name. */
static int sim__body_ref(sim__ctx *c, int i, int *out)
{
    const char *t = c->tok[i];
    long v;
    int b;
    if (!sim__integer(t, &v)) {
        if (v < 0 || v >= c->s->n_bodies)
            return sim__fail(c, "%s: body index %s out of range (%d bodies declared so far)",
                             c->key, t, c->s->n_bodies);
        *out = (int)v;
        return 0;
    }
    for (b = 0; b < c->s->n_bodies; b++)
        if (strcmp(c->s->body_name[b], t) == 0) {
            *out = b;
            return 0;
        }
    if (sim__is_pot_word(t))
        return sim__fail(c, "%s: '%s' is a potential, found where the %s body belongs (usage: %s)",
                         c->key, t, i == 1 ? "first" : "second", sim__key_usage(c->key));
    return sim__fail(c, "%s: unknown body '%s' (declare it with `body` before use)", c->key, t);
}

/* "body 3" or "body 3 (earth)" for messages. */
static const char *sim__body_label(const sim__ctx *c, int b, char *buf, size_t n)
{
    if (b < 0 || b >= EDMI_MAX_BODIES)
        snprintf(buf, n, "body %d", b);
    else if (c->s->body_name[b][0])
        snprintf(buf, n, "body %d (%s)", b, c->s->body_name[b]);
    else
        snprintf(buf, n, "body %d", b);
    return buf;
}

/* ---- potentials ------------------------------------------------------------------------- */

/* Parse "POT params..." starting at token i, which must end the line. */
static int sim__pot_spec_parse(sim__ctx *c, int i, int pair, sim__pot_spec *ps)
{
    static const char *const nm_harm[] = {"k", "r0"}, *const nm_quart[] = {"k", "L"},
                             *const nm_neo[] = {"c", "rbar"}, *const nm_lj[] = {"eps", "sigma"},
                             *const nm_inv[] = {"k"}, *const nm_grav[] = {"G"},
                             *const nm_contact[] = {"k", "R"}, *const nm_tether[] = {"k", "L"};
    static const char *const nm_pot[] = {"potential"};
    const char *w;
    if (c->ntok <= i)
        return sim__count(c, i, 1, nm_pot,
                          "... POTENTIAL PARAMS; potentials: harmonic k r0, quartic k L, "
                          "neo_hooke c rbar, lj eps sigma, inverse k, gravity G, contact k R, "
                          "tether k L");
    w = c->tok[i];
    ps->gravity = 0;
    ps->b = 0.0;
    if (strcmp(w, "harmonic") == 0) {
        ps->kind = EDMI_POT_HARMONIC;
        if (sim__count(c, i + 1, 2, nm_harm, "harmonic k r0") ||
            sim__positive(c, i + 1, "harmonic k", &ps->a) ||
            sim__nonnegative(c, i + 2, "harmonic r0", &ps->b))
            return -1;
    } else if (strcmp(w, "quartic") == 0) {
        ps->kind = EDMI_POT_QUARTIC;
        if (sim__count(c, i + 1, 2, nm_quart, "quartic k L") ||
            sim__positive(c, i + 1, "quartic k", &ps->a) ||
            sim__nonnegative(c, i + 2, "quartic L", &ps->b))
            return -1;
    } else if (strcmp(w, "neo_hooke") == 0) {
        ps->kind = EDMI_POT_NEO_HOOKE;
        if (sim__count(c, i + 1, 2, nm_neo, "neo_hooke c rbar") ||
            sim__positive(c, i + 1, "neo_hooke c", &ps->a) ||
            sim__positive(c, i + 2, "neo_hooke rbar", &ps->b))
            return -1;
    } else if (strcmp(w, "lj") == 0) {
        ps->kind = EDMI_POT_LJ;
        if (sim__count(c, i + 1, 2, nm_lj, "lj eps sigma") ||
            sim__positive(c, i + 1, "lj eps", &ps->a) ||
            sim__positive(c, i + 2, "lj sigma", &ps->b))
            return -1;
    } else if (strcmp(w, "inverse") == 0) {
        ps->kind = EDMI_POT_INVERSE;
        if (sim__count(c, i + 1, 1, nm_inv, "inverse k") || sim__real(c, i + 1, "inverse k", &ps->a))
            return -1;
        if (ps->a == 0.0)
            return sim__fail(c, "%s: inverse k = %s must be non-zero", c->key, c->tok[i + 1]);
    } else if (strcmp(w, "contact") == 0) {
        ps->kind = EDMI_POT_CONTACT;
        if (sim__count(c, i + 1, 2, nm_contact, "contact k R") ||
            sim__positive(c, i + 1, "contact k", &ps->a) ||
            sim__positive(c, i + 2, "contact R", &ps->b))
            return -1;
    } else if (strcmp(w, "tether") == 0) {
        ps->kind = EDMI_POT_TETHER;
        if (sim__count(c, i + 1, 2, nm_tether, "tether k L") ||
            sim__positive(c, i + 1, "tether k", &ps->a) ||
            sim__nonnegative(c, i + 2, "tether L", &ps->b))
            return -1;
    } else if (strcmp(w, "gravity") == 0) {
        if (!pair)
            return sim__fail(c, "%s: gravity needs two bodies (k = G m_A m_B); tie a body to a "
                             "fixed mass with `inverse k` instead", c->key);
        ps->kind = EDMI_POT_INVERSE;
        ps->gravity = 1;
        if (sim__count(c, i + 1, 1, nm_grav, "gravity G") ||
            sim__positive(c, i + 1, "gravity G", &ps->a))
            return -1;
    } else {
        return sim__fail(c, "%s: unknown potential '%s' (expected harmonic, quartic, neo_hooke, "
                         "lj, inverse, gravity, contact or tether)", c->key, w);
    }
    return 0;
}

/* Append a link from body a to body b, or (x != NULL) to the fixed point x. */
static int sim__add_link(sim__ctx *c, int a, int b, const double *x, const sim__pot_spec *ps)
{
    sim_scene *s = c->s;
    edmi_link lk;
    double k = ps->a, d2 = 0.0;
    char la[64], lb[64];
    int i;
    if (!x && b == a)
        return sim__fail(c, "%s: links %s to itself", c->key, sim__body_label(c, a, la, sizeof la));
    if (s->n_links >= EDMI_MAX_LINKS)
        return sim__fail(c, "%s: too many links (EDMI_MAX_LINKS = %d)", c->key, EDMI_MAX_LINKS);
    memset(&lk, 0, sizeof lk);
    lk.a = a;
    lk.b = x ? EDMI_ANCHOR : b;
    for (i = 0; i < 3; i++) {
        double di;
        lk.anchor[i] = x ? (edmi_real)x[i] : (edmi_real)0;
        di = (double)s->body[a].q[i] - (double)(x ? lk.anchor[i] : s->body[b].q[i]);
        d2 += di * di;
    }
    if (!(d2 > 0.0)) {
        if (x)
            return sim__fail(c, "%s: %s sits on its anchor point (a link needs distance > 0)",
                             c->key, sim__body_label(c, a, la, sizeof la));
        return sim__fail(c, "%s: %s and %s are at the same position (a link needs distance > 0)",
                         c->key, sim__body_label(c, a, la, sizeof la),
                         sim__body_label(c, b, lb, sizeof lb));
    }
    if (ps->gravity && !x) { /* gravity is refused for anchors by sim__pot_spec_parse */
        k = ps->a * (double)s->body[a].m * (double)s->body[b].m;
        if (!(k > 0.0) || !(k <= (double)EDMI_REAL_MAX) || !((edmi_real)k > (edmi_real)0))
            return sim__fail(c, "%s: gravity k = G m_A m_B = %g for bodies %d and %d is not a "
                             "positive EDMI_REAL", c->key, k, a, b);
    }
    lk.pot.kind = ps->kind;
    lk.pot.a = (edmi_real)k;
    lk.pot.b = (edmi_real)ps->b;
    lk.pot.fn = 0;
    lk.pot.dd = 0;
    lk.pot.ctx = 0;
    s->link_line[s->n_links] = c->line;
    s->link[s->n_links++] = lk;
    return 0;
}

/* ---- one key per line ------------------------------------------------------------------- */

static int sim__key_body(sim__ctx *c)
{
    static const char *const names[] = {"m", "qx", "qy", "qz", "px", "py", "pz"};
    static const char *const usage = "body [NAME] m qx qy qz px py pz";
    sim_scene *s = c->s;
    double v[7];
    int first = 1, i, b;
    if (c->ntok > 1) {
        /* a second field that is not a number (strtod also reads inf and nan) is a name */
        char *end;
        (void)strtod(c->tok[1], &end);
        if (end == c->tok[1] || *end != '\0') {
            if (!sim__name_ok(c->tok[1]))
                return sim__fail(c, "body: bad name '%s' (a name starts with a letter or _, "
                                 "then letters, digits, _ - .; at most %d characters)",
                                 c->tok[1], SIM_NAME_MAX - 1);
            first = 2;
        }
    }
    if (s->n_bodies >= EDMI_MAX_BODIES)
        return sim__fail(c, "body: too many bodies (EDMI_MAX_BODIES = %d)", EDMI_MAX_BODIES);
    if (sim__count(c, first, 7, names, usage))
        return -1;
    if (sim__positive(c, first, "mass m", &v[0]))
        return -1;
    for (i = 1; i < 7; i++)
        if (sim__real(c, first + i, names[i], &v[i]))
            return -1;
    b = s->n_bodies;
    if (first == 2) {
        int o;
        if (strcmp(c->tok[1], "all") == 0)
            return sim__fail(c, "body: 'all' is reserved and cannot name a body");
        for (o = 0; o < b; o++)
            if (strcmp(s->body_name[o], c->tok[1]) == 0)
                return sim__fail(c, "body: name '%s' already used by body %d on line %d",
                                 c->tok[1], o, s->body_line[o]);
        strcpy(s->body_name[b], c->tok[1]);
    } else {
        s->body_name[b][0] = '\0';
    }
    s->body[b].m = (edmi_real)v[0];
    if (!(s->body[b].m > (edmi_real)0))
        return sim__fail(c, "body: mass m = %s underflows EDMI_REAL", c->tok[first]);
    for (i = 0; i < 3; i++) {
        s->body[b].q[i] = (edmi_real)v[1 + i];
        s->body[b].p[i] = (edmi_real)v[4 + i];
    }
    s->body_line[b] = c->line;
    s->n_bodies++;
    return 0;
}

static int sim__key_anchor(sim__ctx *c)
{
    static const char *const names[] = {"BODY", "x", "y", "z", "potential"};
    sim__pot_spec ps;
    double x[3];
    int a, i;
    if (c->ntok < 6)
        return sim__count(c, 1, 5, names, "anchor BODY x y z POTENTIAL PARAMS");
    if (sim__body_ref(c, 1, &a))
        return -1;
    for (i = 0; i < 3; i++)
        if (sim__real(c, 2 + i, names[1 + i], &x[i]))
            return -1;
    if (sim__pot_spec_parse(c, 5, 0, &ps))
        return -1;
    return sim__add_link(c, a, EDMI_ANCHOR, x, &ps);
}

static int sim__key_pair(sim__ctx *c)
{
    static const char *const names[] = {"body A", "body B", "potential"};
    sim__pot_spec ps;
    int a, b;
    if (c->ntok < 4)
        return sim__count(c, 1, 3, names, "pair A B POTENTIAL PARAMS");
    if (sim__body_ref(c, 1, &a) || sim__body_ref(c, 2, &b))
        return -1;
    if (a == b) {
        char la[64];
        return sim__fail(c, "pair: links %s to itself", sim__body_label(c, a, la, sizeof la));
    }
    if (sim__pot_spec_parse(c, 3, 1, &ps))
        return -1;
    return sim__add_link(c, a, b, 0, &ps);
}

/* pairs all POT ...: every pair (a, b), a < b, of the bodies declared so far. */
static int sim__key_pairs(sim__ctx *c)
{
    static const char *const names[] = {"'all'", "potential"};
    sim__pot_spec ps;
    int n = c->s->n_bodies, a, b;
    long need = (long)n * (long)(n - 1) / 2;
    if (c->ntok < 3)
        return sim__count(c, 1, 2, names, "pairs all POTENTIAL PARAMS");
    if (strcmp(c->tok[1], "all") != 0)
        return sim__fail(c, "pairs: expected 'all', got '%s' (usage: pairs all POTENTIAL PARAMS; "
                         "list single links with `pair A B`)", c->tok[1]);
    if (n < 2)
        return sim__fail(c, "pairs: needs at least 2 bodies declared before it (%d so far)", n);
    if (sim__pot_spec_parse(c, 2, 1, &ps))
        return -1;
    if (need > EDMI_MAX_LINKS - c->s->n_links)
        return sim__fail(c, "pairs: too many links: all pairs of %d bodies are %ld links, %d left "
                         "(EDMI_MAX_LINKS = %d)", n, need, EDMI_MAX_LINKS - c->s->n_links,
                         EDMI_MAX_LINKS);
    for (a = 0; a < n; a++)
        for (b = a + 1; b < n; b++)
            if (sim__add_link(c, a, b, 0, &ps))
                return -1;
    return 0;
}

/* chain A B POT ...: links A-(A+1), ..., (B-1)-B by index. */
static int sim__key_chain(sim__ctx *c)
{
    static const char *const names[] = {"first body", "last body", "potential"};
    sim__pot_spec ps;
    int a, b, i;
    if (c->ntok < 4)
        return sim__count(c, 1, 3, names, "chain FIRST LAST POTENTIAL PARAMS");
    if (sim__body_ref(c, 1, &a) || sim__body_ref(c, 2, &b))
        return -1;
    if (b <= a)
        return sim__fail(c, "chain: last body %d must come after first body %d", b, a);
    if (sim__pot_spec_parse(c, 3, 1, &ps))
        return -1;
    if (b - a > EDMI_MAX_LINKS - c->s->n_links)
        return sim__fail(c, "chain: too many links: %d needed, %d left (EDMI_MAX_LINKS = %d)",
                         b - a, EDMI_MAX_LINKS - c->s->n_links, EDMI_MAX_LINKS);
    for (i = a; i < b; i++)
        if (sim__add_link(c, i, i + 1, 0, &ps))
            return -1;
    return 0;
}

static int sim__key_field(sim__ctx *c)
{
    static const char *const names[] = {"gx", "gy", "gz"};
    double g[3];
    int i;
    if (c->field_line)
        return sim__fail(c, "field: already declared on line %d", c->field_line);
    if (sim__count(c, 1, 3, names, "field gx gy gz"))
        return -1;
    for (i = 0; i < 3; i++)
        if (sim__real(c, 1 + i, names[i], &g[i]))
            return -1;
    for (i = 0; i < 3; i++)
        c->s->g[i] = (edmi_real)g[i];
    c->s->has_field = 1;
    c->field_line = c->line;
    return 0;
}

static int sim__add_damper(sim__ctx *c, int link, double cd)
{
    sim_scene *s = c->s;
    if (s->n_dampers >= EDMI_MAX_DAMPERS)
        return sim__fail(c, "damper: too many dampers (EDMI_MAX_DAMPERS = %d)", EDMI_MAX_DAMPERS);
    s->damper[s->n_dampers].link = link;
    s->damper[s->n_dampers].c = (edmi_real)cd;
    s->n_dampers++;
    return 0;
}

/* damper LINK c | damper all c (every link declared so far). */
static int sim__key_damper(sim__ctx *c)
{
    static const char *const names[] = {"LINK", "c"};
    long v;
    double cd;
    int i;
    if (sim__count(c, 1, 2, names, "damper LINK c  or  damper all c"))
        return -1;
    if (sim__nonnegative(c, 2, "c", &cd))
        return -1;
    if (strcmp(c->tok[1], "all") == 0) {
        if (c->s->n_links == 0)
            return sim__fail(c, "damper: 'all' but no links declared so far");
        if (c->s->n_links > EDMI_MAX_DAMPERS - c->s->n_dampers)
            return sim__fail(c, "damper: too many dampers: %d links, %d dampers left "
                             "(EDMI_MAX_DAMPERS = %d)", c->s->n_links,
                             EDMI_MAX_DAMPERS - c->s->n_dampers, EDMI_MAX_DAMPERS);
        for (i = 0; i < c->s->n_links; i++)
            if (sim__add_damper(c, i, cd))
                return -1;
        return 0;
    }
    if (sim__integer(c->tok[1], &v))
        return sim__fail(c, "damper: bad link index '%s' (links are numbered from 0 in the order "
                         "anchor/pair/pairs/chain declare them, or 'all')", c->tok[1]);
    if (v < 0 || v >= c->s->n_links)
        return sim__fail(c, "damper: link index %s out of range (%d links declared so far)",
                         c->tok[1], c->s->n_links);
    return sim__add_damper(c, (int)v, cd);
}

/* wall BODY nx ny nz c POTENTIAL ...  or  wall all nx ny nz c POTENTIAL ...: BODY (or every body
 * declared so far) against the plane n.x = c, the potential of its gap g = n.q - c: contact
 * k R (a ball of radius R on a rigid plane), tether k L or harmonic k g0 (edmi_add_wall). */
static int sim__key_wall(sim__ctx *c)
{
    static const char *const names[] = {"BODY", "nx", "ny", "nz", "c", "potential"};
    sim_scene *s = c->s;
    sim__pot_spec ps;
    double v[4];
    int a, i, first, last;
    if (c->ntok < 7)
        return sim__count(c, 1, 6, names, "wall BODY nx ny nz c POTENTIAL PARAMS  or  wall all ...");
    for (i = 0; i < 4; i++)
        if (sim__real(c, 2 + i, names[1 + i], &v[i]))
            return -1;
    if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0)
        return sim__fail(c, "wall: the normal (nx, ny, nz) is 0");
    if (sim__pot_spec_parse(c, 6, 0, &ps))
        return -1;
    if (ps.kind != EDMI_POT_CONTACT && ps.kind != EDMI_POT_TETHER && ps.kind != EDMI_POT_HARMONIC)
        return sim__fail(c, "wall: a wall takes contact, tether or harmonic, not '%s'", c->tok[6]);
    if (strcmp(c->tok[1], "all") == 0) {
        if (s->n_bodies == 0)
            return sim__fail(c, "wall: 'all' but no bodies declared so far");
        first = 0;
        last = s->n_bodies - 1;
    } else {
        if (sim__body_ref(c, 1, &a))
            return -1;
        first = last = a;
    }
    if (last - first + 1 > EDMI_MAX_WALLS - s->n_walls)
        return sim__fail(c, "wall: too many walls (EDMI_MAX_WALLS = %d)", EDMI_MAX_WALLS);
    for (a = first; a <= last; a++) {
        edmi_wall *w = &s->wall[s->n_walls++];
        w->a = a;
        for (i = 0; i < 3; i++)
            w->n[i] = (edmi_real)v[i];
        w->c = (edmi_real)v[3];
        w->pot.kind = ps.kind;
        w->pot.a = (edmi_real)ps.a;
        w->pot.b = (edmi_real)ps.b;
        w->pot.fn = 0;
        w->pot.dd = 0;
        w->pot.ctx = 0;
    }
    return 0;
}

/* mass A B m: the off-diagonal entry m_AB = m_BA of the mass matrix (edmi_set_mass_coupling;
 * the bodies' own masses are its diagonal). */
static int sim__key_mass(sim__ctx *c)
{
    static const char *const names[] = {"body A", "body B", "m_AB"};
    sim_scene *s = c->s;
    char la[64], lb[64];
    double m;
    int a, b, i, gap;
    if (sim__count(c, 1, 3, names, "mass A B m_AB"))
        return -1;
    if (sim__body_ref(c, 1, &a) || sim__body_ref(c, 2, &b))
        return -1;
    if (a == b)
        return sim__fail(c, "mass: couples %s to itself (a body's own mass is on its body line)",
                         sim__body_label(c, a, la, sizeof la));
    if (sim__real(c, 3, "m_AB", &m))
        return -1;
    gap = a > b ? a - b : b - a;
    if (gap > EDMI_MAX_MASS_GAP)
        return sim__fail(c, "mass: %s and %s are %d bodies apart; this build couples masses at "
                         "most EDMI_MAX_MASS_GAP = %d apart", sim__body_label(c, a, la, sizeof la),
                         sim__body_label(c, b, lb, sizeof lb), gap, EDMI_MAX_MASS_GAP);
    for (i = 0; i < s->n_mass; i++)
        if ((s->mass[i].a == a && s->mass[i].b == b) || (s->mass[i].a == b && s->mass[i].b == a))
            return sim__fail(c, "mass: %s and %s are already coupled on an earlier line",
                             sim__body_label(c, a, la, sizeof la),
                             sim__body_label(c, b, lb, sizeof lb));
    if (s->n_mass >= SIM_MAX_MASS)
        return sim__fail(c, "mass: too many couplings (%d)", SIM_MAX_MASS);
    s->mass[s->n_mass].a = a;
    s->mass[s->n_mass].b = b;
    s->mass[s->n_mass].m = (edmi_real)m;
    s->n_mass++;
    return 0;
}

static int sim__key_force(sim__ctx *c)
{
    static const char *const names[] = {"BODY", "fx", "fy", "fz"};
    sim_scene *s = c->s;
    double f[3];
    int b, i;
    if (sim__count(c, 1, 4, names, "force BODY fx fy fz"))
        return -1;
    if (sim__body_ref(c, 1, &b))
        return -1;
    if (c->force_line[b]) {
        char lb[64];
        return sim__fail(c, "force: %s already has a force port (line %d)",
                         sim__body_label(c, b, lb, sizeof lb), c->force_line[b]);
    }
    for (i = 0; i < 3; i++)
        if (sim__real(c, 2 + i, names[1 + i], &f[i]))
            return -1;
    s->force_body[s->n_forces] = b;
    for (i = 0; i < 3; i++)
        s->force[s->n_forces][i] = (edmi_real)f[i];
    s->n_forces++;
    c->force_line[b] = c->line;
    return 0;
}

static int sim__key_set(sim__ctx *c)
{
    static const char *const names[] = {"setting", "value"};
    sim_scene *s = c->s;
    double v;
    long n = 0;
    int k;
    if (c->ntok < 2)
        return sim__count(c, 1, 2, names, "set KEY VALUE");
    for (k = 0; k < SIM__N_SET; k++)
        if (strcmp(c->tok[1], sim__set_names[k]) == 0)
            break;
    if (k == SIM__N_SET)
        return sim__fail(c, "set: unknown setting '%s' (expected scheme, lg_switch, dt, t_end, "
                         "tol_q, tol_r, tol_a, l_max, every, guard, fallback or substeps)", c->tok[1]);
    snprintf(c->key, sizeof c->key, "set %s", sim__set_names[k]);
    if (sim__count(c, 1, 2, names, "set KEY VALUE"))
        return -1;
    if (c->set_line[k])
        return sim__fail(c, "%s: already set on line %d", c->key, c->set_line[k]);
    switch (k) {
    case SIM__SET_SCHEME:
        if (sim_parse_scheme(c->tok[2], &s->params.scheme))
            return sim__fail(c, "set scheme: bad value '%s' (expected mp, lg, ge, pm or pt)",
                             c->tok[2]);
        break;
    case SIM__SET_LG_SWITCH:
        if (sim_parse_lg_switch(c->tok[2], &s->params))
            return sim__fail(c, "set lg_switch: bad value '%s' (expected closed, janz, gonzalez, "
                             "ge, pm or pt)", c->tok[2]);
        break;
    case SIM__SET_DT:
        if (sim__positive(c, 2, "dt", &s->dt))
            return -1;
        break;
    case SIM__SET_T_END:
        if (sim__positive(c, 2, "t_end", &s->t_end))
            return -1;
        break;
    case SIM__SET_TOL_Q:
    case SIM__SET_TOL_R:
    case SIM__SET_TOL_A:
        if (sim__positive(c, 2, sim__set_names[k], &v))
            return -1;
        if (!((edmi_real)v > (edmi_real)0))
            return sim__fail(c, "%s: %s underflows EDMI_REAL", c->key, c->tok[2]);
        if (k == SIM__SET_TOL_Q)
            s->params.tol_q = (edmi_real)v;
        else if (k == SIM__SET_TOL_R)
            s->params.tol_r = (edmi_real)v;
        else
            s->params.tol_a = (edmi_real)v;
        break;
    case SIM__SET_L_MAX:
        if (sim__int_setting(c, 2, &n))
            return -1;
        if (n > 1000)
            return sim__fail(c, "set l_max: %s is more than 1000 Newton iterations", c->tok[2]);
        s->params.l_max = (int)n;
        break;
    case SIM__SET_EVERY:
        if (sim__int_setting(c, 2, &n))
            return -1;
        s->every = n;
        break;
    case SIM__SET_GUARD:
        if (sim_parse_guard(c->tok[2], &s->params.guard))
            return sim__fail(c, "set guard: bad value '%s' (expected auto, on or off)", c->tok[2]);
        break;
    case SIM__SET_FALLBACK:
        if (sim_parse_on_off(c->tok[2], &s->params.fallback))
            return sim__fail(c, "set fallback: bad value '%s' (expected on or off)", c->tok[2]);
        break;
    case SIM__SET_SUBSTEPS:
        if (sim__int_setting(c, 2, &n))
            return -1;
        if (n > EDMI_MAX_SUBSTEP_LEVELS)
            return sim__fail(c, "set substeps: %s is more than %d levels (2^%d substeps)",
                             c->tok[2], EDMI_MAX_SUBSTEP_LEVELS, EDMI_MAX_SUBSTEP_LEVELS);
        s->params.substep_levels = (int)n;
        break;
    default:
        break;
    }
    c->set_line[k] = c->line;
    return 0;
}

static int sim__key_title(sim__ctx *c)
{
    size_t used = 0;
    int i;
    if (c->title_line)
        return sim__fail(c, "title: already given on line %d", c->title_line);
    for (i = 1; i < c->ntok; i++) {
        size_t n = strlen(c->tok[i]);
        if (used + n + 2 > sizeof c->s->title)
            return sim__fail(c, "title: longer than %d characters", (int)sizeof c->s->title - 1);
        if (i > 1)
            c->s->title[used++] = ' ';
        memcpy(c->s->title + used, c->tok[i], n);
        used += n;
    }
    c->s->title[used] = '\0';
    c->title_line = c->line;
    return 0;
}

/* One line (without its newline), comments already possible. */
static int sim__line(sim__ctx *c, char *buf)
{
    static const struct {
        const char *key;
        int (*fn)(sim__ctx *);
    } keys[] = {{"body", sim__key_body},     {"anchor", sim__key_anchor},
                {"pair", sim__key_pair},     {"pairs", sim__key_pairs},
                {"chain", sim__key_chain},   {"field", sim__key_field},
                {"damper", sim__key_damper}, {"force", sim__key_force},
                {"mass", sim__key_mass},     {"wall", sim__key_wall},
                {"set", sim__key_set},       {"title", sim__key_title}};
    char *p = strchr(buf, '#');
    size_t i;
    if (p)
        *p = '\0';
    c->ntok = 0;
    p = buf;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\v' || *p == '\f')
            p++;
        if (!*p)
            break;
        if (c->ntok == SIM__MAX_TOK)
            return sim__fail(c, "too many fields (more than %d)", SIM__MAX_TOK);
        c->tok[c->ntok++] = p;
        while (*p && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\v' && *p != '\f')
            p++;
        if (*p)
            *p++ = '\0';
    }
    if (c->ntok == 0)
        return 0;
    for (i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (strcmp(c->tok[0], keys[i].key) == 0) {
            snprintf(c->key, sizeof c->key, "%s", keys[i].key);
            return keys[i].fn(c);
        }
    return sim__fail(c, "unknown key '%s' (expected body, anchor, pair, pairs, chain, field, "
                     "damper, force, set or title)", c->tok[0]);
}

int sim_scene_parse(const char *text, const char *file, sim_scene *out, char *err,
                    size_t err_size)
{
    static sim__ctx c; /* large (line tables): not on the stack */
    const char *p = text;
    char buf[SIM_LINE_MAX];
    memset(&c, 0, sizeof c);
    c.file = file ? file : "<scene>";
    c.err = err;
    c.err_size = err_size;
    c.s = out;
    if (err && err_size)
        err[0] = '\0';
    if (!out || !text) {
        c.line = 0;
        return sim__fail(&c, "no scene text");
    }
    memset(out, 0, sizeof *out);
    out->params = edmi_default_params();
    while (*p) {
        const char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        c.line++;
        if (n >= sizeof buf)
            return sim__fail(&c, "line too long (%lu characters, at most %d)", (unsigned long)n,
                             SIM_LINE_MAX - 1);
        memcpy(buf, p, n);
        buf[n] = '\0';
        if (sim__line(&c, buf))
            return -1;
        p += n;
        if (*p == '\n')
            p++;
    }
    c.line = 0;
    if (out->n_bodies == 0)
        return sim__fail(&c, "no bodies declared (a scene needs at least one `body` line)");
    return 0;
}

int sim_scene_load(const char *path, sim_scene *out, char *err, size_t err_size)
{
    FILE *f;
    char *text;
    long n;
    size_t got, i;
    int rc, line = 1;
    f = fopen(path, "rb");
    if (!f) {
        snprintf(err, err_size, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    /* a directory opens, but its first read fails (EISDIR): say so, not its "size" */
    if (fgetc(f) == EOF && ferror(f)) {
        snprintf(err, err_size, "%s: cannot read: %s", path, strerror(errno));
        fclose(f);
        return -1;
    }
    if (fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        snprintf(err, err_size, "%s: cannot read: %s", path, strerror(errno));
        fclose(f);
        return -1;
    }
    if (n > SIM__MAX_FILE) {
        snprintf(err, err_size, "%s: larger than %ld bytes: not a scene file", path,
                 SIM__MAX_FILE);
        fclose(f);
        return -1;
    }
    text = (char *)malloc((size_t)n + 1);
    if (!text) {
        snprintf(err, err_size, "%s: out of memory", path);
        fclose(f);
        return -1;
    }
    got = fread(text, 1, (size_t)n, f);
    fclose(f);
    text[got] = '\0';
    for (i = 0; i < got; i++) {
        if (text[i] == '\n')
            line++;
        else if (text[i] == '\0') {
            snprintf(err, err_size, "%s:%d: NUL byte in the text (not a scene file?)", path, line);
            free(text);
            return -1;
        }
    }
    rc = sim_scene_parse(text, path, out, err, err_size);
    free(text);
    return rc;
}

edmi_scene sim_scene_view(const sim_scene *s)
{
    edmi_scene v;
    int i;
    v.n_bodies = s->n_bodies;
    v.bodies = s->body;
    v.n_links = s->n_links;
    v.links = s->link;
    v.n_dampers = s->n_dampers;
    v.dampers = s->n_dampers ? s->damper : 0;
    v.has_field = s->has_field;
    for (i = 0; i < 3; i++)
        v.g[i] = s->g[i];
    v.params = &s->params;
    v.n_mass_couplings = s->n_mass;
    v.mass_couplings = s->n_mass ? s->mass : 0;
    return v;
}

edmi_status sim_scene_add_walls(const sim_scene *s, edmi_system *sys)
{
    int i;
    for (i = 0; i < s->n_walls; i++) {
        const edmi_wall *w = &s->wall[i];
        edmi_status st = edmi_add_wall(sys, w->a, w->n, w->c, &w->pot, 0);
        if (st != EDMI_OK)
            return st;
    }
    return EDMI_OK;
}
