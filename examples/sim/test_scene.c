/*
 * test_scene: the scene parser's error cases, the shipped scenes, and the energy balance of
 * a scene with every effect (field, dampers, a force port).
 *
 *   test_scene [SCENE...]   each SCENE given must parse and load; closes "N passed, N failed"
 *
 * Every malformed-line class must fail with "FILE:LINE: message" where the message names the
 * key, index or value at fault. Hosted C99.
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "edmi.h"
#include "scene.h"

/* |H_n+1 - H_n - (W - Ds - Dd)| per step, relative to the energies involved: the balance is
 * exact up to the Newton residual (tol_R 1e-10 of the predictor residual, here about
 * 1e-12 of H) and round-off in H (a few eps), so 1e-9 leaves a wide margin in double; in
 * float tol_R = 1e-5. */
#define BALANCE_TOL (edmi_is_double_precision() ? 1e-9 : 1e-3)

static long npass, nfail;
static sim_scene scn;
static edmi_system sys;
static edmi_workspace work;

static int check(int cond, const char *file, int line, const char *text)
{
    if (cond) {
        npass++;
    } else {
        nfail++;
        printf("FAIL %s:%d: %s\n", file, line, text);
    }
    return cond;
}
#define CHECK(cond) check((cond) ? 1 : 0, __FILE__, __LINE__, #cond)

/* The text must fail to parse with a message containing every one of the NULL-terminated
 * fragments (the first is normally "t.scene:LINE: "). */
static void expect_error_at(const char *file, int line, const char *text, ...)
{
    char err[SIM_ERR_MAX];
    va_list ap;
    const char *frag;
    int rc = sim_scene_parse(text, "t.scene", &scn, err, sizeof err);
    if (!check(rc != 0, file, line, "parse fails")) {
        printf("     scene text: %s\n", text);
        return;
    }
    va_start(ap, text);
    while ((frag = va_arg(ap, const char *)) != 0)
        if (!check(strstr(err, frag) != 0, file, line, "message contains fragment"))
            printf("     want \"%s\" in \"%s\"\n", frag, err);
    va_end(ap);
}
#define EXPECT_ERROR(text, ...) expect_error_at(__FILE__, __LINE__, text, __VA_ARGS__, (char *)0)

static int parse_ok(const char *text)
{
    char err[SIM_ERR_MAX];
    int rc = sim_scene_parse(text, "t.scene", &scn, err, sizeof err);
    if (rc != 0)
        printf("     unexpected error: %s\n", err);
    return rc == 0;
}

#define TWO "body 1 0 0 0 0 0 0\nbody 1 1 0 0 0 0 0\n"

static void test_keys_and_fields(void)
{
    EXPECT_ERROR("bodyy 1 0 0 0 0 0 0\n", "t.scene:1: ", "unknown key 'bodyy'");
    EXPECT_ERROR("# comment\n\n   \nspring 0 1\n", "t.scene:4: ", "unknown key 'spring'");
    EXPECT_ERROR("body 1 0 0 0 0 0\n", "t.scene:1: ", "body: missing pz");
    EXPECT_ERROR("body\n", "t.scene:1: ", "body: missing m");
    EXPECT_ERROR("body sun\n", "t.scene:1: ", "body: missing m");
    EXPECT_ERROR("body 1 0 0 0 0 0 0 9\n", "t.scene:1: ", "unexpected extra field '9'");
    EXPECT_ERROR("body 1 0 0 0 0 0 0 # fine\nbody 1 0 0 1 0 0 0 0 0\n", "t.scene:2: ",
                 "unexpected extra field '0'");
    EXPECT_ERROR(TWO "pair 0 1\n", "t.scene:3: ", "pair: missing potential");
    EXPECT_ERROR(TWO "pair 0\n", "t.scene:3: ", "pair: missing body B");
    EXPECT_ERROR(TWO "anchor 0 1 2\n", "t.scene:3: ", "anchor: missing z");
    EXPECT_ERROR(TWO "pair 0 1 lj 1\n", "t.scene:3: ", "missing sigma");
    EXPECT_ERROR(TWO "pair 0 1 lj 1 1 1\n", "t.scene:3: ", "unexpected extra field '1'");
    EXPECT_ERROR(TWO "field 0 0\n", "t.scene:3: ", "field: missing gz");
    EXPECT_ERROR(TWO "force 0 1 2\n", "t.scene:3: ", "force: missing fz");
    EXPECT_ERROR(TWO "pair 0 1 harmonic 1 1\ndamper 0\n", "t.scene:4: ", "damper: missing c");
    EXPECT_ERROR(TWO "set dt\n", "t.scene:3: ", "set dt: missing value");
    EXPECT_ERROR(TWO "set\n", "t.scene:3: ", "set: missing setting");
    EXPECT_ERROR(TWO "set dt 1 2\n", "t.scene:3: ", "set dt: unexpected extra field '2'");
    EXPECT_ERROR("body 1 0 0 0 0 0 0 a b c d e f g h i j k l m n o p q r s\n", "t.scene:1: ",
                 "too many fields");
    {
        static char longline[SIM_LINE_MAX + 64];
        memset(longline, ' ', sizeof longline - 1);
        memcpy(longline, "body 1 0 0 0 0 0 0", 18);
        longline[sizeof longline - 2] = '\n';
        longline[sizeof longline - 1] = '\0';
        EXPECT_ERROR(longline, "t.scene:1: ", "line too long");
    }
    EXPECT_ERROR("", "t.scene: ", "no bodies declared");
    EXPECT_ERROR("# only comments\nset dt 1\n", "t.scene: ", "no bodies declared");
}

static void test_numbers(void)
{
    EXPECT_ERROR("body 1 0 x 0 0 0 0\n", "t.scene:1: ", "bad number 'x' for qy");
    EXPECT_ERROR("body 1 0 0 0 0 0 1.5.2\n", "t.scene:1: ", "bad number '1.5.2' for pz");
    EXPECT_ERROR("body 1 0 0 0 0 0 3,5\n", "t.scene:1: ", "bad number '3,5' for pz");
    EXPECT_ERROR("body 1 nan 0 0 0 0 0\n", "t.scene:1: ", "qx = nan is not finite");
    EXPECT_ERROR("body 1 0 0 0 -inf 0 0\n", "t.scene:1: ", "px = -inf is not finite");
    EXPECT_ERROR("body 1 0 0 1e999 0 0 0\n", "t.scene:1: ", "qz = 1e999 is not finite");
    EXPECT_ERROR("body inf 0 0 0 0 0 0\n", "t.scene:1: ", "mass m = inf is not finite");
    EXPECT_ERROR("body 0 0 0 0 0 0 0\n", "t.scene:1: ", "mass m = 0 must be > 0");
    EXPECT_ERROR("body -2 0 0 0 0 0 0\n", "t.scene:1: ", "mass m = -2 must be > 0");
    EXPECT_ERROR("body sun -2 0 0 0 0 0 0\n", "t.scene:1: ", "mass m = -2 must be > 0");
    EXPECT_ERROR(TWO "field 0 nan 0\n", "t.scene:3: ", "field: gy = nan is not finite");
    EXPECT_ERROR(TWO "force 1 0 0 inf\n", "t.scene:3: ", "force: fz = inf is not finite");
    EXPECT_ERROR(TWO "anchor 0 0 inf 0 harmonic 1 1\n", "t.scene:3: ", "y = inf is not finite");
    if (!edmi_is_double_precision())
        EXPECT_ERROR("body 1e39 0 0 0 0 0 0\n", "t.scene:1: ", "does not fit in EDMI_REAL");
}

static void test_potentials(void)
{
    EXPECT_ERROR(TWO "pair 0 1 morse 1 2 3\n", "t.scene:3: ", "unknown potential 'morse'");
    EXPECT_ERROR(TWO "pair 0 1 harmonic -1 1\n", "t.scene:3: ", "harmonic k = -1 must be > 0");
    EXPECT_ERROR(TWO "pair 0 1 harmonic 1 -1\n", "t.scene:3: ", "harmonic r0 = -1 must be >= 0");
    EXPECT_ERROR(TWO "pair 0 1 quartic 0 1\n", "t.scene:3: ", "quartic k = 0 must be > 0");
    EXPECT_ERROR(TWO "pair 0 1 neo_hooke 1 0\n", "t.scene:3: ", "neo_hooke rbar = 0 must be > 0");
    EXPECT_ERROR(TWO "pair 0 1 lj 0 1\n", "t.scene:3: ", "lj eps = 0 must be > 0");
    EXPECT_ERROR(TWO "pair 0 1 lj 1 -1\n", "t.scene:3: ", "lj sigma = -1 must be > 0");
    EXPECT_ERROR(TWO "pair 0 1 inverse 0\n", "t.scene:3: ", "inverse k = 0 must be non-zero");
    EXPECT_ERROR(TWO "pair 0 1 lj nan 1\n", "t.scene:3: ", "lj eps = nan is not finite");
    EXPECT_ERROR(TWO "pairs all gravity -1\n", "t.scene:3: ", "gravity G = -1 must be > 0");
    EXPECT_ERROR(TWO "anchor 0 5 5 5 gravity 1\n", "t.scene:3: ", "gravity needs two bodies");
}

static void test_indices(void)
{
    EXPECT_ERROR(TWO "pair 0 5 lj 1 1\n", "t.scene:3: ",
                 "body index 5 out of range (2 bodies declared so far)");
    EXPECT_ERROR(TWO "pair -1 0 lj 1 1\n", "t.scene:3: ", "body index -1 out of range");
    EXPECT_ERROR(TWO "pair 0 earth lj 1 1\n", "t.scene:3: ", "unknown body 'earth'");
    EXPECT_ERROR(TWO "pair 0 harmonic 1 1\n", "t.scene:3: ",
                 "'harmonic' is a potential, found where the second body belongs (usage: pair A B");
    EXPECT_ERROR(TWO "chain lj 1 1 1\n", "t.scene:3: ",
                 "'lj' is a potential, found where the first body belongs (usage: chain FIRST");
    EXPECT_ERROR(TWO "pair 1 1 lj 1 1\n", "t.scene:3: ", "links body 1 to itself");
    EXPECT_ERROR(TWO "mass 1 1 0.1\n", "t.scene:3: ", "mass: couples body 1 to itself");
    EXPECT_ERROR(TWO "mass 0 1 0.1\nmass 1 0 0.2\n", "t.scene:4: ",
                 "mass: body 1 and body 0 are already coupled on an earlier line");
    EXPECT_ERROR(TWO "body 1 0 0 0 0 0 0\nmass 0 3 0.1\n", "t.scene:4: ", "mass: body index 3");
    EXPECT_ERROR(TWO "body 1 0 0 0 0 0 0\nbody 1 0 0 0 0 0 0\nmass 0 3 0.1\n", "t.scene:5: ",
                 "mass: body 0 and body 3 are 3 bodies apart; this build couples masses at most "
                 "EDMI_MAX_MASS_GAP = 2 apart");
    EXPECT_ERROR(TWO "mass 0 1\n", "t.scene:3: ", "mass: missing m_AB");
    EXPECT_ERROR("body a 1 0 0 0 0 0 0\nbody b 1 0 0 0 0 0 0\npair a b lj 1 1\n", "t.scene:3: ",
                 "body 0 (a) and body 1 (b) are at the same position");
    EXPECT_ERROR(TWO "anchor 1 1 0 0 harmonic 1 1\n", "t.scene:3: ", "sits on its anchor point");
    EXPECT_ERROR(TWO "anchor 2 1 0 0 harmonic 1 1\n", "t.scene:3: ", "body index 2 out of range");
    EXPECT_ERROR(TWO "force 3 0 0 1\n", "t.scene:3: ", "force: body index 3 out of range");
    EXPECT_ERROR(TWO "force 1 0 0 1\nforce 1 0 0 2\n", "t.scene:4: ",
                 "body 1 already has a force port (line 3)");
    EXPECT_ERROR(TWO "pair 0 1 harmonic 1 1\ndamper 1 0.5\n", "t.scene:4: ",
                 "damper: link index 1 out of range (1 links declared so far)");
    EXPECT_ERROR(TWO "pair 0 1 harmonic 1 1\ndamper x 0.5\n", "t.scene:4: ",
                 "damper: bad link index 'x'");
    EXPECT_ERROR(TWO "pair 0 1 harmonic 1 1\ndamper 0 -1\n", "t.scene:4: ",
                 "damper: c = -1 must be >= 0");
    CHECK(parse_ok(TWO "pair 0 1 harmonic 1 1\ndamper 0 0\n") && scn.n_dampers == 1 &&
          scn.damper[0].c == (edmi_real)0); /* as edmi_add_damper: c = 0 is a damper at rest */
    EXPECT_ERROR(TWO "damper all 1\n", "t.scene:3: ", "no links declared so far");
    EXPECT_ERROR(TWO "pairs some lj 1 1\n", "t.scene:3: ", "pairs: expected 'all', got 'some'");
    EXPECT_ERROR("body 1 0 0 0 0 0 0\npairs all lj 1 1\n", "t.scene:2: ",
                 "needs at least 2 bodies");
    EXPECT_ERROR(TWO "chain 1 0 harmonic 1 1\n", "t.scene:3: ", "last body 0 must come after");
    EXPECT_ERROR("body sun 1 0 0 0 0 0 0\nbody sun 1 1 0 0 0 0 0\n", "t.scene:2: ",
                 "name 'sun' already used by body 0 on line 1");
    EXPECT_ERROR("body 9abc 1 0 0 0 0 0 0\n", "t.scene:1: ", "bad name '9abc'");
    EXPECT_ERROR("body all 1 0 0 0 0 0 0\n", "t.scene:1: ", "'all' is reserved");
    EXPECT_ERROR(TWO "field 0 0 1\nfield 0 0 2\n", "t.scene:4: ", "field: already declared on line 3");
}

static void test_capacity(void)
{
    static char text[64 * (EDMI_MAX_LINKS + EDMI_MAX_BODIES + 8)];
    char line[80];
    int i;
    /* one body too many */
    text[0] = '\0';
    for (i = 0; i <= EDMI_MAX_BODIES; i++) {
        snprintf(line, sizeof line, "body 1 %d 0 0 0 0 0\n", i);
        strcat(text, line);
    }
    snprintf(line, sizeof line, "t.scene:%d: ", EDMI_MAX_BODIES + 1);
    EXPECT_ERROR(text, line, "body: too many bodies (EDMI_MAX_BODIES = ");
    /* one link too many, listed */
    strcpy(text, TWO);
    for (i = 0; i <= EDMI_MAX_LINKS; i++)
        strcat(text, "pair 0 1 harmonic 1 1\n");
    snprintf(line, sizeof line, "t.scene:%d: ", EDMI_MAX_LINKS + 3);
    EXPECT_ERROR(text, line, "pair: too many links (EDMI_MAX_LINKS = ");
    /* all pairs of the largest body count need more links than fit (16 bodies: 120 > 64) */
    text[0] = '\0';
    for (i = 0; i < EDMI_MAX_BODIES; i++) {
        snprintf(line, sizeof line, "body 1 %d 0 0 0 0 0\n", i);
        strcat(text, line);
    }
    strcat(text, "pairs all gravity 1\n");
    snprintf(line, sizeof line, "t.scene:%d: ", EDMI_MAX_BODIES + 1);
    if (EDMI_MAX_BODIES * (EDMI_MAX_BODIES - 1) / 2 > EDMI_MAX_LINKS)
        EXPECT_ERROR(text, line, "pairs: too many links");
    /* one damper too many */
    strcpy(text, TWO "pair 0 1 harmonic 1 1\n");
    for (i = 0; i <= EDMI_MAX_DAMPERS; i++)
        strcat(text, "damper 0 1\n");
    snprintf(line, sizeof line, "t.scene:%d: ", EDMI_MAX_DAMPERS + 4);
    EXPECT_ERROR(text, line, "damper: too many dampers (EDMI_MAX_DAMPERS = ");
}

static void test_settings(void)
{
    EXPECT_ERROR(TWO "set speed 3\n", "t.scene:3: ", "set: unknown setting 'speed'");
    EXPECT_ERROR(TWO "set scheme rk4\n", "t.scene:3: ", "set scheme: bad value 'rk4'");
    EXPECT_ERROR(TWO "set scheme PM\n", "t.scene:3: ", "set scheme: bad value 'PM'");
    EXPECT_ERROR(TWO "set lg_switch euler\n", "t.scene:3: ", "set lg_switch: bad value 'euler'");
    EXPECT_ERROR(TWO "set dt 0\n", "t.scene:3: ", "set dt: dt = 0 must be > 0");
    EXPECT_ERROR(TWO "set t_end -1\n", "t.scene:3: ", "set t_end: t_end = -1 must be > 0");
    EXPECT_ERROR(TWO "set tol_r nan\n", "t.scene:3: ", "set tol_r: tol_r = nan is not finite");
    EXPECT_ERROR(TWO "set tol_q 0\n", "t.scene:3: ", "tol_q = 0 must be > 0");
    EXPECT_ERROR(TWO "set tol_a 1e-99x\n", "t.scene:3: ", "bad number '1e-99x' for tol_a");
    EXPECT_ERROR(TWO "set l_max 2.5\n", "t.scene:3: ", "set l_max: bad integer '2.5'");
    EXPECT_ERROR(TWO "set l_max 0\n", "t.scene:3: ", "set l_max: 0 must be >= 1");
    EXPECT_ERROR(TWO "set every x\n", "t.scene:3: ", "set every: bad integer 'x'");
    EXPECT_ERROR(TWO "set guard yes\n", "t.scene:3: ", "set guard: bad value 'yes'");
    EXPECT_ERROR(TWO "set fallback 1\n", "t.scene:3: ", "set fallback: bad value '1'");
    EXPECT_ERROR(TWO "set dt 1\n# again\nset dt 2\n", "t.scene:5: ",
                 "set dt: already set on line 3");
    EXPECT_ERROR(TWO "title a\ntitle b\n", "t.scene:4: ", "title: already given on line 3");
}

static void test_valid(void)
{
    edmi_scene v;
    const char *text = "title  a   test\r\n"
                       "# comment line\r\n"
                       "body sun 2 0 0 0  0 0 0   # trailing comment\r\n"
                       "body   3 1 0 0  0 1 0\r\n"
                       "body p3 4 0 2 0  0 0 1\n"
                       "pairs all gravity 0.5\n"
                       "anchor p3 0 0 1 harmonic 10 0.5\n"
                       "chain 0 2 lj 1 0.5\n"
                       "field 0 0 -9.81\n"
                       "damper 3 0.25\n"
                       "damper all 0.5\n"
                       "force sun 1 2 3\n"
                       "set scheme pt\nset lg_switch ge\nset dt 1e-3\nset t_end 2\n"
                       "set tol_q 1e-6\nset tol_r 1e-11\nset tol_a 1e-14\nset l_max 30\n"
                       "set every 7\nset guard off\nset fallback on";
    if (!CHECK(parse_ok(text)))
        return;
    CHECK(strcmp(scn.title, "a test") == 0);
    CHECK(scn.n_bodies == 3);
    CHECK(strcmp(scn.body_name[0], "sun") == 0 && scn.body_name[1][0] == '\0');
    CHECK(scn.body[2].m == (edmi_real)4 && scn.body[2].q[1] == (edmi_real)2 &&
          scn.body[2].p[2] == (edmi_real)1);
    CHECK(scn.n_links == 3 + 1 + 2);
    /* gravity: k = G m_A m_B, pairs in order (0,1), (0,2), (1,2) */
    CHECK(scn.link[0].a == 0 && scn.link[0].b == 1 && scn.link[0].pot.kind == EDMI_POT_INVERSE &&
          scn.link[0].pot.a == (edmi_real)3.0);
    CHECK(scn.link[1].a == 0 && scn.link[1].b == 2 && scn.link[1].pot.a == (edmi_real)4.0);
    CHECK(scn.link[2].a == 1 && scn.link[2].b == 2 && scn.link[2].pot.a == (edmi_real)6.0);
    CHECK(scn.link[3].a == 2 && scn.link[3].b == EDMI_ANCHOR &&
          scn.link[3].anchor[2] == (edmi_real)1 && scn.link[3].pot.kind == EDMI_POT_HARMONIC);
    CHECK(scn.link[4].a == 0 && scn.link[4].b == 1 && scn.link[4].pot.kind == EDMI_POT_LJ &&
          scn.link[5].a == 1 && scn.link[5].b == 2);
    CHECK(scn.has_field && scn.g[2] == (edmi_real)-9.81);
    CHECK(scn.n_dampers == 1 + 6 && scn.damper[0].link == 3 && scn.damper[6].link == 5 &&
          scn.damper[6].c == (edmi_real)0.5);
    CHECK(scn.n_forces == 1 && scn.force_body[0] == 0 && scn.force[0][2] == (edmi_real)3);
    CHECK(scn.params.scheme == EDMI_SCHEME_PT && scn.params.lg_form == EDMI_LG_QUOTIENT &&
          scn.params.lg_alt == EDMI_LG_ALT_GE && scn.params.l_max == 30 &&
          scn.params.tol_q == (edmi_real)1e-6 && scn.params.tol_r == (edmi_real)1e-11 &&
          scn.params.tol_a == (edmi_real)1e-14);
    CHECK(scn.dt == 1e-3 && scn.t_end == 2.0 && scn.every == 7);
    CHECK(scn.params.guard == EDMI_GUARD_OFF && scn.params.fallback == 1);
    v = sim_scene_view(&scn);
    CHECK(edmi_load_scene(&sys, &v) == EDMI_OK);
    CHECK(sys.n_bodies == 3 && sys.n_links == 6 && sys.n_dampers == 7 && sys.has_field);
    /* defaults when nothing is set */
    if (CHECK(parse_ok("body 1 0 0 0 0 0 0"))) {
        edmi_params d = edmi_default_params();
        CHECK(scn.params.scheme == d.scheme && scn.params.lg_form == d.lg_form &&
              scn.params.tol_r == d.tol_r && scn.params.guard == EDMI_GUARD_AUTO &&
              scn.params.fallback == 0 && scn.dt == 0.0 && scn.t_end == 0.0 &&
              scn.every == 0 && !scn.has_field);
    }
    /* a name may look like a potential or key: it is just a name */
    CHECK(parse_ok("body lj 1 0 0 0 0 0 0\nbody set 1 1 0 0 0 0 0\npair lj set lj 1 1\n"));
}

static void test_files(void)
{
    char err[SIM_ERR_MAX], path[64];
    FILE *f;
    int fd;
    CHECK(sim_scene_load("/nonexistent/x.scene", &scn, err, sizeof err) != 0 &&
          strstr(err, "/nonexistent/x.scene: cannot open") != 0);
    strcpy(path, "/tmp/edmi_scene_XXXXXX");
    fd = mkstemp(path);
    if (!CHECK(fd >= 0))
        return;
    f = fdopen(fd, "wb");
    if (!CHECK(f != 0))
        return;
    fwrite("body 1 0 0 0 0 0 0\n\nbo\0dy\n", 1, 26, f);
    fclose(f);
    CHECK(sim_scene_load(path, &scn, err, sizeof err) != 0 && strstr(err, ":3: NUL byte") != 0);
    f = fopen(path, "wb");
    if (CHECK(f != 0)) {
        fputs("body 1 0 0 0 0 0 0\nbody 1 0 0 0 0 0 x\n", f);
        fclose(f);
        CHECK(sim_scene_load(path, &scn, err, sizeof err) != 0 && strstr(err, path) == err &&
              strstr(err, ":2: body: bad number 'x' for pz") != 0);
    }
    remove(path);
}

/* A hard case for Newton: the solar system at dt = 18.25 d (Mercury's orbit in 4.8 steps),
 * Newton to its floor, 200 steps. Full Newton needs up to 15 corrections per step here (before
 * the chord, measured with edmi.c of 7620207); a chord correction taken right after the first
 * one raised the residual 4e5-fold and PM failed at l_max = 20 on step 6. Every step must now
 * succeed within the default l_max, for PM and LG (MP has no solution near its predictor at
 * this dt: it fails at step 1, as it did before the chord, and is not checked). */
static void test_solar_big_dt(const char *path)
{
    static const edmi_scheme schemes[] = {EDMI_SCHEME_PM, EDMI_SCHEME_LG};
    char err[SIM_ERR_MAX];
    int s, k;
    for (s = 0; s < 2; s++) {
        edmi_scene v;
        edmi_step_result res;
        edmi_status st = EDMI_OK;
        int worst = 0;
        if (!CHECK(sim_scene_load(path, &scn, err, sizeof err) == 0))
            return;
        scn.params.scheme = schemes[s];
        scn.params.lg_form = EDMI_LG_CLOSED;
        scn.params.tol_r = 0;
        scn.params.tol_a = 0;
        v = sim_scene_view(&scn);
        if (!CHECK(edmi_load_scene(&sys, &v) == EDMI_OK))
            return;
        for (k = 0; k < 200 && st == EDMI_OK; k++) {
            st = edmi_step(&sys, &work, (edmi_real)18.25, &res);
            if (st == EDMI_OK && res.iterations > worst)
                worst = res.iterations;
        }
        if (!CHECK(st == EDMI_OK))
            printf("     %s at step %d: %s\n", sim_scheme_word(schemes[s]), k,
                   edmi_status_name(st));
        printf("     %s: 200 steps of 18.25 d, at most %d corrections per step\n",
               sim_scheme_word(schemes[s]), worst);
    }
}

/* Every effect at once: the discrete energy balance of each step must close. */
static void test_energy_balance(const char *path)
{
    char err[SIM_ERR_MAX];
    edmi_scene v;
    edmi_invariants i0, i1;
    double worst = 0.0, w = 0.0, dd = 0.0, dd_min = 0.0;
    int k, i, ok = 1;
    if (!CHECK(sim_scene_load(path, &scn, err, sizeof err) == 0)) {
        printf("     %s\n", err);
        return;
    }
    CHECK(scn.has_field && scn.n_dampers > 0 && scn.n_forces > 0);
    scn.params.energy_balance = 1;
    v = sim_scene_view(&scn);
    if (!CHECK(edmi_load_scene(&sys, &v) == EDMI_OK))
        return;
    for (i = 0; i < scn.n_forces; i++)
        CHECK(edmi_set_force(&sys, scn.force_body[i], scn.force[i]) == EDMI_OK);
    ok = edmi_invariants_of(&sys, &i0) == EDMI_OK;
    for (k = 0; k < 1000 && ok; k++) {
        edmi_step_result r;
        double mis, scale;
        ok = edmi_step(&sys, &work, (edmi_real)scn.dt, &r) == EDMI_OK &&
             edmi_invariants_of(&sys, &i1) == EDMI_OK;
        if (!ok)
            break;
        mis = fabs(((double)i1.h - (double)i0.h) -
                   ((double)r.work_ext - (double)r.diss_scheme - (double)r.diss_damping));
        scale = fabs((double)i0.h) + fabs((double)r.work_ext) + fabs((double)r.diss_scheme) +
                fabs((double)r.diss_damping);
        if (mis / scale > worst)
            worst = mis / scale;
        w += (double)r.work_ext;
        dd += (double)r.diss_damping;
        if ((double)r.diss_damping < dd_min)
            dd_min = (double)r.diss_damping;
        i0 = i1;
    }
    CHECK(ok);
    if (!CHECK(worst <= BALANCE_TOL))
        printf("     worst relative energy-balance mismatch %.3g\n", worst);
    /* dampers only remove energy; the run exercised both terms */
    CHECK(dd_min >= 0.0);
    CHECK(fabs(w) > 0.0 && dd > 0.0);
}

int main(int argc, char **argv)
{
    int i;
    printf("scene parser: error cases\n");
    test_keys_and_fields();
    test_numbers();
    test_potentials();
    test_indices();
    test_capacity();
    test_settings();
    printf("scene parser: valid scenes\n");
    test_valid();
    test_files();
    for (i = 1; i < argc; i++) {
        char err[SIM_ERR_MAX];
        edmi_scene v;
        printf("scene %s\n", argv[i]);
        if (!CHECK(sim_scene_load(argv[i], &scn, err, sizeof err) == 0)) {
            printf("     %s\n", err);
            continue;
        }
        v = sim_scene_view(&scn);
        CHECK(edmi_load_scene(&sys, &v) == EDMI_OK);
        CHECK(scn.dt > 0.0 && scn.t_end > 0.0);
        if (scn.has_field && scn.n_dampers > 0 && scn.n_forces > 0) {
            printf("energy balance with field, dampers and force port: %s\n", argv[i]);
            test_energy_balance(argv[i]);
        }
        if (strstr(argv[i], "solar_system.scene")) {
            printf("solar system at dt = 18.25 d, PM and LG: %s\n", argv[i]);
            test_solar_big_dt(argv[i]);
        }
    }
    printf("%ld passed, %ld failed\n", npass, nfail);
    return nfail != 0;
}
