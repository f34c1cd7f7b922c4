/* suite_invalid: bad input gets a clear status and changes nothing.
 *
 * Every case builds a valid system, takes a byte snapshot, makes the bad call, and checks
 * the exact status edmi.h documents and memcmp(snapshot, system) == 0 (GSL odeiv2's
 * "y must be restored on failure"). edmi_init zeroes padding, so byte equality is
 * meaningful. The Newton failures (singular matrix, no convergence, divergence) are built
 * so that they happen for a reason derived below, not by chance. */
#include <string.h>

#include "harness.h"
#include "suites.h"

/* Static: the system and workspace are tens of kB, too much for a Cortex-M stack. */
static edmi_system ti_sys;
static edmi_system ti_snap;
static edmi_workspace ti_work;
static edmi_step_result ti_res;

static edmi_real ti_inf(void)
{
    volatile edmi_real big = EDMI_REAL_MAX;
    return big * EDMI_R(2.0);
}

static edmi_real ti_nan(void)
{
    edmi_real inf = ti_inf();
    return inf - inf;
}

static void ti_snapshot(void) { memcpy(&ti_snap, &ti_sys, sizeof ti_sys); }

static int ti_unchanged(void) { return memcmp(&ti_snap, &ti_sys, sizeof ti_sys) == 0; }

/* Garbage in the result, so that "zeroed on input errors" is observable. */
static void ti_dirty_res(void)
{
    ti_res.iterations = 77;
    ti_res.stop = EDMI_STOP_STALLED;
    ti_res.residual = EDMI_R(5.0);
    ti_res.residual0 = EDMI_R(6.0);
    ti_res.lg_switches = 9;
}

static int ti_res_zeroed(void)
{
    return ti_res.iterations == 0 && ti_res.residual == EDMI_R(0.0) &&
           ti_res.residual0 == EDMI_R(0.0) && ti_res.lg_switches == 0;
}

/* The bad call, its exact status, and the system bit-identical afterwards. */
#define TI_EXPECT(call, want)                                                      \
    do {                                                                           \
        ti_snapshot();                                                             \
        CHECK_STATUS(call, want);                                                  \
        th_check(ti_unchanged(), __FILE__, __LINE__, "system unchanged after " #call); \
    } while (0)

/* A step that must fail on its input: exact status, system unchanged, result zeroed. */
#define TI_STEP_INPUT(dt, want)                                                    \
    do {                                                                           \
        ti_dirty_res();                                                            \
        TI_EXPECT(edmi_step(&ti_sys, &ti_work, (dt), &ti_res), want);              \
        th_check(ti_res_zeroed(), __FILE__, __LINE__, "result zeroed on input error"); \
    } while (0)

static const edmi_real ti_zero3[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};

/* The potential pot, or where the build left its kind out (EDMI_WITH_*) a harmonic spring of
 * rest length 1.3 (or, without that, a potential the build carries), for the tests of the
 * input checks: which force acts does not change a status they expect. */
static edmi_potential ti_pot_in(edmi_potential pot)
{
    if (th_has_pot(pot.kind))
        return pot;
    if (th_has_pot(EDMI_POT_HARMONIC))
        return edmi_pot_harmonic(EDMI_R(50.0), EDMI_R(1.3));
    if (th_has_pot(EDMI_POT_QUARTIC))
        return edmi_pot_quartic(EDMI_R(50.0), EDMI_R(1.3));
    if (th_has_pot(EDMI_POT_NEO_HOOKE))
        return edmi_pot_neo_hooke(EDMI_R(50.0), EDMI_R(1.3));
    if (th_has_pot(EDMI_POT_LJ))
        return edmi_pot_lj(EDMI_R(1.0), EDMI_R(1.0));
    return edmi_pot_inverse(EDMI_R(-1.0)); /* (a build with user potentials alone: not run) */
}

/* A valid 3-body system: LJ pair 0-1, harmonic pair 1-2, neo-Hookean anchor on body 0. With
 * `any`, for the tests of the input checks, each part the build left out is replaced: the
 * scheme by the default one, a potential by ti_pot_in's (the default build is unchanged). */
static int ti_build_with(edmi_scheme scheme, int any)
{
    edmi_params prm = edmi_default_params();
    edmi_real q0[3] = {EDMI_R(0.0), EDMI_R(-0.5612), EDMI_R(0.0)};
    edmi_real q1[3] = {EDMI_R(0.0), EDMI_R(0.5612), EDMI_R(0.0)};
    edmi_real q2[3] = {EDMI_R(0.5), EDMI_R(1.8), EDMI_R(0.25)};
    edmi_real p0[3] = {EDMI_R(5.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real p1[3] = {EDMI_R(10.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real p2[3] = {EDMI_R(-1.0), EDMI_R(2.0), EDMI_R(0.5)};
    edmi_real x[3] = {EDMI_R(0.0), EDMI_R(-3.0), EDMI_R(0.0)};
    edmi_potential lj = edmi_pot_lj(EDMI_R(100.0), EDMI_R(1.0));
    edmi_potential hs = edmi_pot_harmonic(EDMI_R(50.0), EDMI_R(1.3));
    edmi_potential nh = edmi_pot_neo_hooke(EDMI_R(1000.0), EDMI_R(2.5));
    prm.scheme = any && !th_has_scheme(scheme) ? edmi_default_params().scheme : scheme;
    if (any) {
        lj = ti_pot_in(lj);
        hs = ti_pot_in(hs);
        nh = ti_pot_in(nh);
    }
    return edmi_init(&ti_sys, &prm) == EDMI_OK &&
           edmi_add_body(&ti_sys, EDMI_R(1.0), q0, p0, 0) == EDMI_OK &&
           edmi_add_body(&ti_sys, EDMI_R(1.0), q1, p1, 0) == EDMI_OK &&
           edmi_add_body(&ti_sys, EDMI_R(2.0), q2, p2, 0) == EDMI_OK &&
           edmi_add_pair(&ti_sys, 0, 1, &lj, 0) == EDMI_OK &&
           edmi_add_pair(&ti_sys, 1, 2, &hs, 0) == EDMI_OK &&
           edmi_add_anchor(&ti_sys, 0, x, &nh, 0) == EDMI_OK;
}

static int ti_build(edmi_scheme scheme) { return ti_build_with(scheme, 0); }

/* ti_build_with(scheme, 1), for the input checks: skipped (1) in a build with user potentials
 * alone; else 1 when it failed. */
static int ti_build_any_fails(edmi_scheme scheme)
{
    return th_skip(th_has_pot(EDMI_POT_HARMONIC) || th_has_pot(EDMI_POT_QUARTIC) ||
                       th_has_pot(EDMI_POT_NEO_HOOKE) || th_has_pot(EDMI_POT_LJ) ||
                       th_has_pot(EDMI_POT_INVERSE),
                   "a built-in potential") ||
           !CHECK(ti_build_with(scheme, 1));
}

/* ti_build's needs (EDMI_WITH_*): the scheme, LJ, harmonic and neo-Hookean links. */
static int ti_build_in(edmi_scheme scheme)
{
    return th_has_scheme(scheme) && th_has_pot(EDMI_POT_LJ) &&
           th_has_pot(EDMI_POT_HARMONIC) && th_has_pot(EDMI_POT_NEO_HOOKE);
}

/* A single body with one anchor link of potential *pot at the origin. */
static int ti_build_one(edmi_real m, const edmi_real q[3], const edmi_real p[3],
                        const edmi_potential *pot, const edmi_params *prm)
{
    return edmi_init(&ti_sys, prm) == EDMI_OK && edmi_add_body(&ti_sys, m, q, p, 0) == EDMI_OK &&
           edmi_add_anchor(&ti_sys, 0, ti_zero3, pot, 0) == EDMI_OK;
}

/* ------------------------------------------------------------------------------------------
 * User potentials for the Newton failures. ctx points at a ti_upot.
 * ---------------------------------------------------------------------------------------- */

/* V = a2 r^2 + a1 r, refused (non-zero return) for r > r_max. Its splits: V_c = V_+ = a1 r
 * (second and fourth derivatives 0) and V_e = V_- = a2 r^2 (a2 <= 0 here), or the other way
 * round when a2 > 0. */
typedef struct ti_upot {
    edmi_real a2, a1, r_max;
} ti_upot;

static int ti_upot_fn(void *ctx, edmi_real r, edmi_pot_parts *out)
{
    const ti_upot *u = (const ti_upot *)ctx;
    edmi_real quad[5], lin[5];
    int j;
    if (!(r <= u->r_max))
        return 1;
    quad[0] = u->a2 * r * r;
    quad[1] = EDMI_R(2.0) * u->a2 * r;
    quad[2] = EDMI_R(2.0) * u->a2;
    quad[3] = quad[4] = EDMI_R(0.0);
    lin[0] = u->a1 * r;
    lin[1] = u->a1;
    lin[2] = lin[3] = lin[4] = EDMI_R(0.0);
    for (j = 0; j < 5; j++) {
        if (u->a2 > EDMI_R(0.0)) {
            out->c[j] = out->sp[j] = quad[j] + lin[j];
            out->e[j] = out->sm[j] = EDMI_R(0.0);
        } else {
            out->c[j] = out->sp[j] = lin[j];
            out->e[j] = out->sm[j] = quad[j];
        }
    }
    return 0;
}

/* A ti_upot link (no divided difference) under prm (NULL: the defaults): user potentials,
 * and for LG its quotient form. */
static int ti_upot_in(const edmi_params *prm)
{
    edmi_params def = edmi_default_params();
    if (!prm)
        prm = &def;
    return th_has_params(prm) && th_has_pot(EDMI_POT_USER) &&
           (prm->scheme != EDMI_SCHEME_LG || EDMI_WITH_LG_QUOTIENT);
}

/* ------------------------------------------------------------------------------------------
 * Status names
 * ---------------------------------------------------------------------------------------- */

static void ti_status_names(void)
{
    static const char *const want[] = {
        "EDMI_OK",           "EDMI_ERR_NULL",          "EDMI_ERR_DT",
        "EDMI_ERR_MASS",     "EDMI_ERR_NONFINITE",     "EDMI_ERR_CAPACITY",
        "EDMI_ERR_INDEX",    "EDMI_ERR_PARAM",         "EDMI_ERR_COINCIDENT",
        "EDMI_ERR_SINGULAR", "EDMI_ERR_NO_CONVERGENCE", "EDMI_ERR_DIVERGED",
        "EDMI_ERR_PASSIVITY", "EDMI_ERR_RANGE",   "EDMI_ERR_DISABLED",
        "EDMI_ERR_UNINIT",   "EDMI_ERR_CORRUPT",       "EDMI_ERR_OVERFLOW",
        "EDMI_ERR_END_STATE", "EDMI_ERR_DOMAIN"};
    int n = (int)(sizeof want / sizeof want[0]), i, j;
    CHECK(n == (int)EDMI_ERR_DOMAIN + 1);
    /* the names before 0.2.0 are aliases of the new ones (edmi.h, EDMI_NO_OLD_NAMES) */
    CHECK(EDMI_MP == EDMI_SCHEME_MP && EDMI_LG == EDMI_SCHEME_LG && EDMI_GE == EDMI_SCHEME_GE &&
          EDMI_PM == EDMI_SCHEME_PM && EDMI_PT == EDMI_SCHEME_PT);
    CHECK(EDMI_ALT_JANZ == EDMI_LG_ALT_JANZ && EDMI_ALT_GONZALEZ == EDMI_LG_ALT_GONZALEZ &&
          EDMI_ALT_GE == EDMI_LG_ALT_GE && EDMI_ALT_PM == EDMI_LG_ALT_PM &&
          EDMI_ALT_PT == EDMI_LG_ALT_PT);
    CHECK(EDMI_GUARD_IMPULSE == EDMI_MOVE_IMPULSE && EDMI_GUARD_DRAG == EDMI_MOVE_DRAG &&
          EDMI_GUARD_ROUND == EDMI_MOVE_ROUND && EDMI_GUARD_STOP == EDMI_MOVE_STOP &&
          EDMI_GUARD_HOLD == EDMI_MOVE_HOLD);
    for (i = 0; i < n; i++) {
        const char *s = edmi_status_name((edmi_status)i);
        if (!CHECK(s != 0))
            continue;
        CHECK(s[0] != '\0');
        CHECK(strcmp(s, want[i]) == 0); /* the header: "EDMI_OK", ... */
        for (j = 0; j < i; j++) {
            const char *t = edmi_status_name((edmi_status)j);
            CHECK(t == 0 || strcmp(s, t) != 0);
        }
    }
    CHECK(edmi_status_name((edmi_status)99) != 0); /* out of range: still a string */
}

/* ------------------------------------------------------------------------------------------
 * edmi_init / edmi_set_params
 * ---------------------------------------------------------------------------------------- */

static void ti_params(void)
{
    edmi_params def = edmi_default_params(), bad[24], good;
    edmi_real nan = ti_nan(), inf = ti_inf();
    int nb = 0, i;

    CHECK_STATUS(edmi_init(0, 0), EDMI_ERR_NULL);
    CHECK_STATUS(edmi_init(0, &def), EDMI_ERR_NULL);
    CHECK_STATUS(edmi_set_params(0, &def), EDMI_ERR_NULL);

    for (i = 0; i < 24; i++)
        bad[i] = def;
    bad[nb++].tol_r = EDMI_R(-1e-10);
    bad[nb++].tol_r = nan;
    bad[nb++].tol_r = inf;
    bad[nb++].tol_a = EDMI_R(-1.0);
    bad[nb++].tol_a = nan;
    bad[nb++].tol_q = EDMI_R(0.0);
    bad[nb++].tol_q = EDMI_R(-1e-8);
    bad[nb++].tol_q = nan;
    bad[nb++].l_max = 0;
    bad[nb++].l_max = -3;
    bad[nb++].scheme = (edmi_scheme)5;
    bad[nb++].scheme = (edmi_scheme)-1;
    bad[nb++].lg_form = (edmi_lg_form)2;
    bad[nb++].lg_alt = (edmi_lg_alt)5;
    bad[nb++].guard = (edmi_guard_mode)3;
    bad[nb++].guard = (edmi_guard_mode)-1;
    bad[nb++].tank_cap = EDMI_R(-1.0);
    bad[nb++].tank_cap = nan;
    bad[nb++].tank_cap = inf;

    if (ti_build_any_fails(EDMI_SCHEME_PM))
        return;
    for (i = 0; i < nb; i++) {
        int f0 = th_failed();
        TI_EXPECT(edmi_init(&ti_sys, &bad[i]), EDMI_ERR_PARAM);
        TI_EXPECT(edmi_set_params(&ti_sys, &bad[i]), EDMI_ERR_PARAM);
        if (th_failed() > f0)
            th_note_int("invalid params number (order in ti_params)", i);
    }
    TI_EXPECT(edmi_set_params(&ti_sys, 0), EDMI_ERR_NULL);

    /* Success paths change what they should. */
    if (th_skip(th_has_scheme(EDMI_SCHEME_GE), "GE"))
        return;
    good = def;
    good.scheme = EDMI_SCHEME_GE;
    good.l_max = 7;
    ti_snapshot();
    CHECK_STATUS(edmi_set_params(&ti_sys, &good), EDMI_OK);
    CHECK(!ti_unchanged());
    CHECK(ti_sys.params.scheme == EDMI_SCHEME_GE && ti_sys.params.l_max == 7);
    CHECK(ti_sys.n_bodies == 3 && ti_sys.n_links == 3); /* set_params keeps the bodies */
    CHECK_STATUS(edmi_init(&ti_sys, 0), EDMI_OK);
    CHECK(ti_sys.n_bodies == 0 && ti_sys.n_links == 0 && ti_sys.t == EDMI_R(0.0));
    CHECK(ti_sys.params.scheme == def.scheme && ti_sys.params.tol_r == def.tol_r &&
          ti_sys.params.tol_a == def.tol_a && ti_sys.params.tol_q == def.tol_q &&
          ti_sys.params.l_max == def.l_max && ti_sys.params.lg_form == def.lg_form &&
          ti_sys.params.lg_alt == def.lg_alt);
}

/* ------------------------------------------------------------------------------------------
 * edmi_add_body / edmi_add_pair / edmi_add_anchor
 * ---------------------------------------------------------------------------------------- */

static void ti_add_body(void)
{
    edmi_real nan = ti_nan(), inf = ti_inf();
    edmi_real q[3] = {EDMI_R(1.0), EDMI_R(2.0), EDMI_R(3.0)};
    edmi_real p[3] = {EDMI_R(-1.0), EDMI_R(0.5), EDMI_R(0.25)};
    edmi_real bq[3], bp[3];
    int i, idx = -5;

    if (ti_build_any_fails(EDMI_SCHEME_MP))
        return;
    CHECK_STATUS(edmi_add_body(0, EDMI_R(1.0), q, p, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_add_body(&ti_sys, EDMI_R(1.0), 0, p, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_add_body(&ti_sys, EDMI_R(1.0), q, 0, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_add_body(&ti_sys, EDMI_R(0.0), q, p, 0), EDMI_ERR_MASS);
    TI_EXPECT(edmi_add_body(&ti_sys, EDMI_R(-2.0), q, p, 0), EDMI_ERR_MASS);
    TI_EXPECT(edmi_add_body(&ti_sys, nan, q, p, 0), EDMI_ERR_MASS);
    TI_EXPECT(edmi_add_body(&ti_sys, inf, q, p, 0), EDMI_ERR_MASS);
    for (i = 0; i < 3; i++) {
        memcpy(bq, q, sizeof q);
        memcpy(bp, p, sizeof p);
        bq[i] = i == 1 ? inf : nan;
        TI_EXPECT(edmi_add_body(&ti_sys, EDMI_R(1.0), bq, p, &idx), EDMI_ERR_NONFINITE);
        bp[i] = i == 2 ? -inf : nan;
        TI_EXPECT(edmi_add_body(&ti_sys, EDMI_R(1.0), q, bp, &idx), EDMI_ERR_NONFINITE);
    }
    CHECK(idx == -5); /* the index output is only written on success */

    /* A system edmi_init never set up (zeroed, as a static one is): every builder refuses it
     * where the mistake is made, the system unchanged. */
    memset(&ti_sys, 0, sizeof ti_sys);
    {
        const edmi_potential h = edmi_pot_harmonic(EDMI_R(1.0), EDMI_R(0.0));
        const edmi_real n[3] = {0, 0, 1};
        TI_EXPECT(edmi_add_body(&ti_sys, EDMI_R(1.0), q, p, &idx), EDMI_ERR_UNINIT);
        TI_EXPECT(edmi_add_anchor(&ti_sys, 0, q, &h, &idx), EDMI_ERR_UNINIT);
        TI_EXPECT(edmi_add_pair(&ti_sys, 0, 1, &h, &idx), EDMI_ERR_UNINIT);
        TI_EXPECT(edmi_add_damper(&ti_sys, 0, EDMI_R(1.0), &idx), EDMI_ERR_UNINIT);
        TI_EXPECT(edmi_add_wall(&ti_sys, 0, n, EDMI_R(0.0), &h, &idx), EDMI_ERR_UNINIT);
        CHECK(idx == -5);
    }

    /* Capacity: EDMI_MAX_BODIES fit, one more does not. */
    CHECK_STATUS(edmi_init(&ti_sys, 0), EDMI_OK);
    for (i = 0; i < EDMI_MAX_BODIES; i++) {
        q[0] = (edmi_real)i;
        if (!CHECK_STATUS(edmi_add_body(&ti_sys, EDMI_R(1.0), q, p, &idx), EDMI_OK))
            break;
        CHECK(idx == i);
    }
    CHECK(ti_sys.n_bodies == EDMI_MAX_BODIES);
    CHECK(ti_sys.body[3].q[0] == EDMI_R(3.0) && ti_sys.body[3].p[1] == p[1] &&
          ti_sys.body[3].m == EDMI_R(1.0));
    TI_EXPECT(edmi_add_body(&ti_sys, EDMI_R(1.0), q, p, &idx), EDMI_ERR_CAPACITY);
}

static void ti_add_links(void)
{
    edmi_real nan = ti_nan(), inf = ti_inf();
    edmi_real x[3] = {EDMI_R(1.0), EDMI_R(1.0), EDMI_R(1.0)}, bx[3];
    edmi_potential good = ti_pot_in(edmi_pot_harmonic(EDMI_R(1.0), EDMI_R(1.0)));
    edmi_potential badpot[6];
    int i, nbp = 0, idx = -5;

    badpot[nbp++] = edmi_pot_lj(EDMI_R(0.0), EDMI_R(1.0));
    badpot[nbp++] = edmi_pot_harmonic(nan, EDMI_R(1.0));
    badpot[nbp++] = edmi_pot_quartic(EDMI_R(1.0), EDMI_R(-1.0));
    badpot[nbp++] = edmi_pot_neo_hooke(EDMI_R(1.0), EDMI_R(0.0));
    badpot[nbp++] = edmi_pot_inverse(EDMI_R(0.0));
    badpot[nbp++] = edmi_pot_user(0, 0, 0);

    if (ti_build_any_fails(EDMI_SCHEME_LG))
        return;
    /* NULL */
    CHECK_STATUS(edmi_add_pair(0, 0, 1, &good, 0), EDMI_ERR_NULL);
    CHECK_STATUS(edmi_add_anchor(0, 0, x, &good, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_add_pair(&ti_sys, 0, 1, 0, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_add_anchor(&ti_sys, 0, x, 0, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_add_anchor(&ti_sys, 0, 0, &good, 0), EDMI_ERR_NULL);
    /* Indices: out of range, negative, the anchor marker in add_pair, a body to itself. */
    TI_EXPECT(edmi_add_pair(&ti_sys, 3, 1, &good, &idx), EDMI_ERR_INDEX);
    TI_EXPECT(edmi_add_pair(&ti_sys, 0, 3, &good, &idx), EDMI_ERR_INDEX);
    TI_EXPECT(edmi_add_pair(&ti_sys, -1, 1, &good, &idx), EDMI_ERR_INDEX);
    TI_EXPECT(edmi_add_pair(&ti_sys, 0, -2, &good, &idx), EDMI_ERR_INDEX);
    TI_EXPECT(edmi_add_pair(&ti_sys, 0, EDMI_ANCHOR, &good, &idx), EDMI_ERR_INDEX);
    TI_EXPECT(edmi_add_pair(&ti_sys, 2, 2, &good, &idx), EDMI_ERR_INDEX);
    TI_EXPECT(edmi_add_pair(&ti_sys, 1000000, 0, &good, &idx), EDMI_ERR_INDEX);
    TI_EXPECT(edmi_add_anchor(&ti_sys, 3, x, &good, &idx), EDMI_ERR_INDEX);
    TI_EXPECT(edmi_add_anchor(&ti_sys, -1, x, &good, &idx), EDMI_ERR_INDEX);
    /* Invalid potentials. */
    for (i = 0; i < nbp; i++) {
        TI_EXPECT(edmi_add_pair(&ti_sys, 0, 2, &badpot[i], &idx), EDMI_ERR_PARAM);
        TI_EXPECT(edmi_add_anchor(&ti_sys, 2, x, &badpot[i], &idx), EDMI_ERR_PARAM);
    }
    /* Non-finite anchor point. */
    for (i = 0; i < 3; i++) {
        memcpy(bx, x, sizeof x);
        bx[i] = i == 0 ? inf : nan;
        TI_EXPECT(edmi_add_anchor(&ti_sys, 1, bx, &good, &idx), EDMI_ERR_NONFINITE);
    }
    CHECK(idx == -5);

    /* Success, then capacity: fill to EDMI_MAX_LINKS with pairs and anchors. */
    ti_snapshot();
    CHECK_STATUS(edmi_add_anchor(&ti_sys, 2, x, &good, &idx), EDMI_OK);
    CHECK(idx == 3 && ti_sys.n_links == 4 && ti_sys.link[3].b == EDMI_ANCHOR &&
          ti_sys.link[3].a == 2 && ti_sys.link[3].anchor[1] == x[1]);
    CHECK(!ti_unchanged());
    for (i = ti_sys.n_links; i < EDMI_MAX_LINKS; i++) {
        edmi_status st = (i % 2) ? edmi_add_pair(&ti_sys, i % 3, (i + 1) % 3, &good, &idx)
                                 : edmi_add_anchor(&ti_sys, i % 3, x, &good, &idx);
        if (!CHECK(st == EDMI_OK))
            break;
        CHECK(idx == i);
    }
    CHECK(ti_sys.n_links == EDMI_MAX_LINKS);
    TI_EXPECT(edmi_add_pair(&ti_sys, 0, 1, &good, &idx), EDMI_ERR_CAPACITY);
    TI_EXPECT(edmi_add_anchor(&ti_sys, 0, x, &good, &idx), EDMI_ERR_CAPACITY);
}

/* ------------------------------------------------------------------------------------------
 * edmi_step, edmi_residual, edmi_tangent, edmi_invariants_of on bad state
 * ---------------------------------------------------------------------------------------- */

#define TI_C3(x) ((const edmi_real (*)[3])(x))

static void ti_step_input(void)
{
    edmi_real nan = ti_nan(), inf = ti_inf(), dt = EDMI_R(1e-3), save;
    edmi_real q1[EDMI_MAX_BODIES][3], p1[EDMI_MAX_BODIES][3];
    edmi_real rq[EDMI_MAX_BODIES][3], rp[EDMI_MAX_BODIES][3];
    static edmi_real kmat[9 * EDMI_MAX_BODIES * EDMI_MAX_BODIES];
    edmi_potential savepot;
    edmi_params saveprm;
    edmi_invariants inv;
    int a, i, sa, sb;

    if (ti_build_any_fails(EDMI_SCHEME_PT))
        return;
    for (a = 0; a < 3; a++)
        for (i = 0; i < 3; i++) {
            q1[a][i] = ti_sys.body[a].q[i] + EDMI_R(0.01) * (edmi_real)(a + i);
            p1[a][i] = ti_sys.body[a].p[i];
        }

    /* NULL system or workspace (a NULL result is allowed, see the success path). */
    ti_dirty_res();
    CHECK_STATUS(edmi_step(0, &ti_work, dt, &ti_res), EDMI_ERR_NULL);
    CHECK(ti_res_zeroed());
    ti_dirty_res();
    TI_EXPECT(edmi_step(&ti_sys, 0, dt, &ti_res), EDMI_ERR_NULL);
    CHECK(ti_res_zeroed());

    /* dt <= 0 or not finite. */
    TI_STEP_INPUT(EDMI_R(0.0), EDMI_ERR_DT);
    TI_STEP_INPUT(-dt, EDMI_ERR_DT);
    TI_STEP_INPUT(nan, EDMI_ERR_DT);
    TI_STEP_INPUT(inf, EDMI_ERR_DT);
    TI_STEP_INPUT(-inf, EDMI_ERR_DT);
    TI_EXPECT(edmi_step(&ti_sys, &ti_work, EDMI_R(0.0), 0), EDMI_ERR_DT);

    /* A position or momentum made non-finite by the caller after adding. */
    for (a = 0; a < 3; a++)
        for (i = 0; i < 3; i++) {
            edmi_real *q = &ti_sys.body[a].q[i], *p = &ti_sys.body[(a + 1) % 3].p[i];
            save = *q;
            *q = (a + i) % 2 ? nan : -inf;
            TI_STEP_INPUT(dt, EDMI_ERR_NONFINITE);
            *q = save;
            save = *p;
            *p = (a + i) % 2 ? inf : nan;
            TI_STEP_INPUT(dt, EDMI_ERR_NONFINITE);
            *p = save;
        }
    /* The tank: a corrupted value is refused, edmi_set_tank validates before it writes. */
    save = ti_sys.tank;
    ti_sys.tank = nan;
    TI_STEP_INPUT(dt, EDMI_ERR_NONFINITE);
    ti_sys.tank = inf;
    TI_STEP_INPUT(dt, EDMI_ERR_NONFINITE);
    ti_sys.tank = EDMI_R(-1e-30);
    TI_STEP_INPUT(dt, EDMI_ERR_PARAM);
    ti_sys.tank = save;
    CHECK_STATUS(edmi_set_tank(0, EDMI_R(0.0)), EDMI_ERR_NULL);
    TI_EXPECT(edmi_set_tank(&ti_sys, nan), EDMI_ERR_NONFINITE);
    TI_EXPECT(edmi_set_tank(&ti_sys, -inf), EDMI_ERR_NONFINITE);
    TI_EXPECT(edmi_set_tank(&ti_sys, EDMI_R(-1.0)), EDMI_ERR_PARAM);
    CHECK_STATUS(edmi_set_tank(&ti_sys, EDMI_R(2.5)), EDMI_OK);
    CHECK(ti_sys.tank == EDMI_R(2.5));
    CHECK_STATUS(edmi_set_tank(&ti_sys, save), EDMI_OK);
    /* A mass corrupted after adding. */
    for (a = 0; a < 3; a++) {
        save = ti_sys.body[a].m;
        ti_sys.body[a].m = EDMI_R(0.0);
        TI_STEP_INPUT(dt, EDMI_ERR_MASS);
        ti_sys.body[a].m = -save;
        TI_STEP_INPUT(dt, EDMI_ERR_MASS);
        ti_sys.body[a].m = nan;
        TI_STEP_INPUT(dt, EDMI_ERR_MASS);
        ti_sys.body[a].m = inf;
        TI_STEP_INPUT(dt, EDMI_ERR_MASS);
        ti_sys.body[a].m = save;
    }
    /* An anchor point corrupted after adding. */
    save = ti_sys.link[2].anchor[1];
    ti_sys.link[2].anchor[1] = nan;
    TI_STEP_INPUT(dt, EDMI_ERR_NONFINITE);
    ti_sys.link[2].anchor[1] = save;
    /* Link indices corrupted after adding. */
    sa = ti_sys.link[0].a;
    sb = ti_sys.link[0].b;
    ti_sys.link[0].b = 3;
    TI_STEP_INPUT(dt, EDMI_ERR_INDEX);
    ti_sys.link[0].b = sa;
    TI_STEP_INPUT(dt, EDMI_ERR_INDEX);
    ti_sys.link[0].b = sb;
    ti_sys.link[0].a = -1;
    TI_STEP_INPUT(dt, EDMI_ERR_INDEX);
    ti_sys.link[0].a = sa;
    sa = ti_sys.link[2].a;
    ti_sys.link[2].a = 7;
    TI_STEP_INPUT(dt, EDMI_ERR_INDEX);
    ti_sys.link[2].a = sa;
    /* A potential parameter corrupted after adding. */
    savepot = ti_sys.link[0].pot;
    ti_sys.link[0].pot.a = EDMI_R(0.0);
    TI_STEP_INPUT(dt, EDMI_ERR_PARAM);
    ti_sys.link[0].pot.b = nan;
    TI_STEP_INPUT(dt, EDMI_ERR_PARAM);
    ti_sys.link[0].pot = savepot;
    ti_sys.link[1].pot.kind = (edmi_pot_kind)42;
    TI_STEP_INPUT(dt, EDMI_ERR_PARAM);
    ti_sys.link[1].pot = savepot;
    ti_sys.link[1].pot = ti_pot_in(edmi_pot_harmonic(EDMI_R(50.0), EDMI_R(1.3)));
    /* Parameters corrupted by writing the struct directly. */
    saveprm = ti_sys.params;
    ti_sys.params.scheme = (edmi_scheme)9;
    TI_STEP_INPUT(dt, EDMI_ERR_PARAM);
    ti_sys.params = saveprm;
    ti_sys.params.tol_r = nan;
    TI_STEP_INPUT(dt, EDMI_ERR_PARAM);
    ti_sys.params = saveprm;
    ti_sys.params.l_max = 0;
    TI_STEP_INPUT(dt, EDMI_ERR_PARAM);
    ti_sys.params = saveprm;
    /* Corrupted counts: the header names no code for this, but it must fail untouched. */
    ti_sys.n_bodies = EDMI_MAX_BODIES + 1;
    ti_snapshot();
    CHECK(edmi_step(&ti_sys, &ti_work, dt, &ti_res) != EDMI_OK);
    CHECK(ti_unchanged());
    ti_sys.n_bodies = 3;
    ti_sys.n_links = -1;
    ti_snapshot();
    CHECK(edmi_step(&ti_sys, &ti_work, dt, &ti_res) != EDMI_OK);
    CHECK(ti_unchanged());
    ti_sys.n_links = 3;

    /* edmi_residual / edmi_tangent / edmi_invariants_of: NULL arguments and bad dt. */
    CHECK_STATUS(edmi_residual(0, &ti_work, dt, TI_C3(q1), TI_C3(p1), rq, rp, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_residual(&ti_sys, 0, dt, TI_C3(q1), TI_C3(p1), rq, rp, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_residual(&ti_sys, &ti_work, dt, 0, TI_C3(p1), rq, rp, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_residual(&ti_sys, &ti_work, dt, TI_C3(q1), 0, rq, rp, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_residual(&ti_sys, &ti_work, dt, TI_C3(q1), TI_C3(p1), 0, rp, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_residual(&ti_sys, &ti_work, dt, TI_C3(q1), TI_C3(p1), rq, 0, 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_residual(&ti_sys, &ti_work, EDMI_R(0.0), TI_C3(q1), TI_C3(p1), rq, rp, 0),
              EDMI_ERR_DT);
    TI_EXPECT(edmi_residual(&ti_sys, &ti_work, nan, TI_C3(q1), TI_C3(p1), rq, rp, 0), EDMI_ERR_DT);
    CHECK_STATUS(edmi_tangent(0, &ti_work, dt, TI_C3(q1), TI_C3(p1), kmat), EDMI_ERR_NULL);
    TI_EXPECT(edmi_tangent(&ti_sys, 0, dt, TI_C3(q1), TI_C3(p1), kmat), EDMI_ERR_NULL);
    TI_EXPECT(edmi_tangent(&ti_sys, &ti_work, dt, 0, TI_C3(p1), kmat), EDMI_ERR_NULL);
    TI_EXPECT(edmi_tangent(&ti_sys, &ti_work, dt, TI_C3(q1), 0, kmat), EDMI_ERR_NULL);
    TI_EXPECT(edmi_tangent(&ti_sys, &ti_work, dt, TI_C3(q1), TI_C3(p1), 0), EDMI_ERR_NULL);
    TI_EXPECT(edmi_tangent(&ti_sys, &ti_work, -dt, TI_C3(q1), TI_C3(p1), kmat), EDMI_ERR_DT);
    TI_EXPECT(edmi_tangent(&ti_sys, &ti_work, inf, TI_C3(q1), TI_C3(p1), kmat), EDMI_ERR_DT);
    CHECK_STATUS(edmi_invariants_of(0, &inv), EDMI_ERR_NULL);
    TI_EXPECT(edmi_invariants_of(&ti_sys, 0), EDMI_ERR_NULL);
    /* ... and their success paths leave the system alone too. */
    TI_EXPECT(edmi_residual(&ti_sys, &ti_work, dt, TI_C3(q1), TI_C3(p1), rq, rp, 0), EDMI_OK);
    TI_EXPECT(edmi_tangent(&ti_sys, &ti_work, dt, TI_C3(q1), TI_C3(p1), kmat), EDMI_OK);
    TI_EXPECT(edmi_invariants_of(&ti_sys, &inv), EDMI_OK);
}

/* Two linked bodies at one point, or a body at its anchor: EDMI_ERR_COINCIDENT before
 * Newton starts, in every scheme (the link direction r/d is undefined at d = 0). The
 * builders refuse such a link where it is made (the system unchanged); a caller who writes
 * the positions there afterwards meets the step's refusal. Two coincident bodies that are
 * not linked are fine. */
static void ti_coincident(void)
{
    static const edmi_scheme schemes[6] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    edmi_real q[3] = {EDMI_R(1.0), EDMI_R(2.0), EDMI_R(3.0)};
    edmi_real qo[3] = {EDMI_R(1.0), EDMI_R(2.0), EDMI_R(4.5)};
    edmi_real pa[3] = {EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real pb[3] = {EDMI_R(0.0), EDMI_R(-1.0), EDMI_R(0.5)};
    edmi_real q1[2][3], p1[2][3], rq[2][3], rp[2][3];
    edmi_potential lj = edmi_pot_lj(EDMI_R(1.0), EDMI_R(1.0));
    edmi_potential nh = edmi_pot_neo_hooke(EDMI_R(1000.0), EDMI_R(4.0));
    edmi_invariants inv;
    int s, i;
    for (s = 0; s < 6; s++) {
        edmi_params prm = edmi_default_params();
        int f0 = th_failed();
        prm.scheme = schemes[s];
        if (s == 2)
            prm.lg_form = EDMI_LG_QUOTIENT;
        if (th_skip(th_has_params(&prm) && th_has_pot(EDMI_POT_LJ) &&
                        th_has_pot(EDMI_POT_NEO_HOOKE),
                    "coincident: scheme, LJ, neo-Hooke"))
            continue;
        /* linked pair at one point: refused by edmi_add_pair, then written by the caller */
        if (!CHECK(edmi_init(&ti_sys, &prm) == EDMI_OK &&
                   edmi_add_body(&ti_sys, EDMI_R(1.0), q, pa, 0) == EDMI_OK &&
                   edmi_add_body(&ti_sys, EDMI_R(2.0), q, pb, 0) == EDMI_OK))
            continue;
        TI_EXPECT(edmi_add_pair(&ti_sys, 0, 1, &lj, 0), EDMI_ERR_COINCIDENT);
        TI_EXPECT(edmi_add_anchor(&ti_sys, 0, q, &nh, 0), EDMI_ERR_COINCIDENT);
        if (EDMI_WITH_SCENE) { /* and by edmi_load_scene, the system unchanged */
            edmi_body bs[2];
            edmi_link ls;
            edmi_scene sc;
            memcpy(bs, ti_sys.body, sizeof bs);
            memset(&ls, 0, sizeof ls);
            ls.a = 0;
            ls.b = 1;
            ls.pot = lj;
            memset(&sc, 0, sizeof sc);
            sc.n_bodies = 2;
            sc.bodies = bs;
            sc.n_links = 1;
            sc.links = &ls;
            sc.params = &prm;
            TI_EXPECT(edmi_load_scene(&ti_sys, &sc), EDMI_ERR_COINCIDENT);
            ls.pot = edmi_pot_harmonic(EDMI_R(1.0), EDMI_R(0.0)); /* defined at d = 0 */
            if (th_has_pot(EDMI_POT_HARMONIC))
                CHECK_STATUS(edmi_load_scene(&ti_sys, &sc), EDMI_OK);
            if (!CHECK(edmi_init(&ti_sys, &prm) == EDMI_OK &&
                       edmi_add_body(&ti_sys, EDMI_R(1.0), q, pa, 0) == EDMI_OK &&
                       edmi_add_body(&ti_sys, EDMI_R(2.0), q, pb, 0) == EDMI_OK))
                continue;
        }
        ti_sys.body[1].q[2] = qo[2];
        if (!CHECK(edmi_add_pair(&ti_sys, 0, 1, &lj, 0) == EDMI_OK))
            continue;
        ti_sys.body[1].q[2] = q[2];
        TI_STEP_INPUT(EDMI_R(1e-3), EDMI_ERR_COINCIDENT);
        for (i = 0; i < 3; i++) {
            q1[0][i] = q[i];
            q1[1][i] = qo[i];
            p1[0][i] = pa[i];
            p1[1][i] = pb[i];
        }
        TI_EXPECT(edmi_residual(&ti_sys, &ti_work, EDMI_R(1e-3), TI_C3(q1), TI_C3(p1), rq, rp, 0),
                  EDMI_ERR_COINCIDENT);
        TI_EXPECT(edmi_invariants_of(&ti_sys, &inv), EDMI_ERR_COINCIDENT);
        /* body at its anchor */
        if (!CHECK(ti_build_one(EDMI_R(10.0), q, pa, &nh, &prm)))
            continue;
        ti_sys.link[0].anchor[0] = q[0];
        ti_sys.link[0].anchor[1] = q[1];
        ti_sys.link[0].anchor[2] = q[2];
        TI_STEP_INPUT(EDMI_R(1e-3), EDMI_ERR_COINCIDENT);
        if (th_failed() > f0)
            th_note_int("coincident: scheme (3 = LG quotient)", s);
    }
    /* Coincident but unlinked: bodies 1 and 2 share a point, links 0-1 and 0-anchor. */
    if (th_skip(th_has_pot(EDMI_POT_LJ) && th_has_pot(EDMI_POT_NEO_HOOKE),
                "coincident: LJ, neo-Hooke"))
        return;
    if (CHECK(edmi_init(&ti_sys, 0) == EDMI_OK &&
              edmi_add_body(&ti_sys, EDMI_R(1.0), qo, pa, 0) == EDMI_OK &&
              edmi_add_body(&ti_sys, EDMI_R(1.0), q, pb, 0) == EDMI_OK &&
              edmi_add_body(&ti_sys, EDMI_R(1.0), q, pa, 0) == EDMI_OK &&
              edmi_add_pair(&ti_sys, 0, 1, &lj, 0) == EDMI_OK &&
              edmi_add_anchor(&ti_sys, 2, ti_zero3, &nh, 0) == EDMI_OK))
        CHECK_STATUS(edmi_step(&ti_sys, &ti_work, EDMI_R(1e-3), &ti_res), EDMI_OK);
}

/* A Newton matrix that is exactly singular.
 * MP on an anchor link at the predictor (q1 = q0, so r_m = r_n, d_m = d_n = d) has the
 * tangent dR_p/dq1 = dt (beta/2 I + (V''(d) - beta)/(2 d^2) r r^T), beta = V'(d)/d, and the
 * segregated matrix I + dt/(2m) dR_p/dq1 has the radial eigenvalue 1 + dt^2 V''(d)/(4m) and
 * the tangential one 1 + dt^2 beta/(4m). With V = -8 r^2 + 8 r, m = 1, dt = 1/2, body at
 * (2,0,0): V'' = -16, so the radial eigenvalue is 1 - 1 = 0, while beta = (-32+8)/2 = -12
 * gives 1/4 tangentially. Every number is a small dyadic rational, so the computed matrix is
 * diag(0, 1/4, 1/4) exactly, in float and double, whatever the operation order.
 * For a pair A-B of unit masses the x-block is [[1+k, -k], [-k, 1+k]] with
 * k = dt^2 V''/4 (m = 1), singular when 1 + 2k = 0: V = -4 r^2 + 8 r (V'' = -8), bodies at
 * (+-1, 0, 0), dt = 1/2; again exact. */
static void ti_singular(void)
{
    static ti_upot one = {EDMI_R(-8.0), EDMI_R(8.0), EDMI_R(1e30)};
    static ti_upot two = {EDMI_R(-4.0), EDMI_R(8.0), EDMI_R(1e30)};
    edmi_real q[3] = {EDMI_R(2.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real qa[3] = {EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real qb[3] = {EDMI_R(-1.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot1 = edmi_pot_user(ti_upot_fn, 0, &one);
    edmi_potential pot2 = edmi_pot_user(ti_upot_fn, 0, &two);
    TH_NEEDS(ti_upot_in(0));
    if (CHECK(ti_build_one(EDMI_R(1.0), q, ti_zero3, &pot1, 0))) {
        ti_dirty_res();
        TI_EXPECT(edmi_step(&ti_sys, &ti_work, EDMI_R(0.5), &ti_res), EDMI_ERR_SINGULAR);
        CHECK(ti_res.iterations == 0);           /* the first correction failed */
        CHECK(ti_res.residual0 > EDMI_R(0.0));   /* but the predictor was evaluated */
        /* A neighbouring dt makes the matrix regular again: the step goes through. */
        CHECK_STATUS(edmi_step(&ti_sys, &ti_work, EDMI_R(0.25), &ti_res), EDMI_OK);
    }
    if (CHECK(edmi_init(&ti_sys, 0) == EDMI_OK &&
              edmi_add_body(&ti_sys, EDMI_R(1.0), qa, ti_zero3, 0) == EDMI_OK &&
              edmi_add_body(&ti_sys, EDMI_R(1.0), qb, ti_zero3, 0) == EDMI_OK &&
              edmi_add_pair(&ti_sys, 0, 1, &pot2, 0) == EDMI_OK)) {
        ti_dirty_res();
        TI_EXPECT(edmi_step(&ti_sys, &ti_work, EDMI_R(0.5), &ti_res), EDMI_ERR_SINGULAR);
        CHECK(ti_res.iterations == 0);
        CHECK(ti_res.residual0 > EDMI_R(0.0));
    }
}

/* l_max = 1 with tolerances no iterate can meet, on the paper's stiff neo-Hookean spring
 * with dt = 0.05 (50x the dt of the paper's energy study): one Newton correction reduces
 * the residual (0.7 -> 1e-2, quadratically) but not to tol_r * r0 = eps^2 r0, nor to its
 * round-off floor (~10 eps). */
static void ti_no_convergence(void)
{
    static const edmi_scheme schemes[5] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    edmi_real q[3] = {EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0)};
    edmi_real p[3] = {EDMI_R(-30.0), EDMI_R(15.0), EDMI_R(45.0)};
    edmi_potential nh = edmi_pot_neo_hooke(EDMI_R(1000.0), EDMI_R(4.0));
    int s;
    for (s = 0; s < 5; s++) {
        edmi_params prm = edmi_default_params();
        prm.scheme = schemes[s];
        prm.l_max = 1;
        prm.tol_r = EDMI_EPS * EDMI_EPS;
        prm.tol_a = EDMI_EPS * EDMI_EPS;
        if (th_skip(th_has_params(&prm) && th_has_pot(EDMI_POT_NEO_HOOKE),
                    "no convergence: scheme, neo-Hooke") ||
            !CHECK(ti_build_one(EDMI_R(10.0), q, p, &nh, &prm)))
            continue;
        ti_dirty_res();
        TI_EXPECT(edmi_step(&ti_sys, &ti_work, EDMI_R(0.05), &ti_res), EDMI_ERR_NO_CONVERGENCE);
        CHECK(ti_res.iterations == 1);
        if (!CHECK(ti_res.residual > EDMI_R(0.0) && ti_res.residual < ti_res.residual0))
            th_note_int("no convergence: scheme", (long)schemes[s]);
    }
}

/* A user callback that refuses: at the start (every r), or only once Newton leaves the
 * domain (V = r^2/2 refused beyond r = 2.05; the body starts at d = 2 moving out at speed 10,
 * so the first iterate has d_m ~ 2.5 and d_n+1 ~ 3 for dt = 0.1). And an iterate that makes
 * a distance exactly 0: V = 0 (no force), body at (1,0,0) with p = (-16,0,0), m = 1,
 * dt = 1/8: the first correction lands exactly on q1 = (-1,0,0), so MP's mid-point
 * r_m = (q0 + q1)/2 is the anchor. */
static void ti_diverged(void)
{
    static const edmi_scheme schemes[5] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    static ti_upot never = {EDMI_R(0.5), EDMI_R(0.0), EDMI_R(0.0)};
    static ti_upot outside = {EDMI_R(0.5), EDMI_R(0.0), EDMI_R(2.05)};
    static ti_upot zero = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(1e30)};
    edmi_real q[3] = {EDMI_R(2.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real p[3] = {EDMI_R(10.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real q0[3] = {EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_real p0[3] = {EDMI_R(-16.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pn = edmi_pot_user(ti_upot_fn, 0, &never);
    edmi_potential pr = edmi_pot_user(ti_upot_fn, 0, &outside);
    edmi_potential pz = edmi_pot_user(ti_upot_fn, 0, &zero);
    edmi_params prm_mp;
    int s;
    for (s = 0; s < 5; s++) {
        edmi_params prm = edmi_default_params();
        prm.scheme = schemes[s];
        int f0 = th_failed();
        if (th_skip(ti_upot_in(&prm), "diverged: scheme, user potential"))
            continue;
        if (CHECK(ti_build_one(EDMI_R(1.0), q, p, &pn, &prm))) /* refused at the start */
            TI_EXPECT(edmi_step(&ti_sys, &ti_work, EDMI_R(0.1), &ti_res), EDMI_ERR_DOMAIN);
        if (CHECK(ti_build_one(EDMI_R(1.0), q, p, &pr, &prm))) {
            TI_EXPECT(edmi_step(&ti_sys, &ti_work, EDMI_R(0.1), &ti_res), EDMI_ERR_DIVERGED);
            /* a small enough step stays in the domain (d_n+1 ~ 2 + 10 dt = 2.01) */
            CHECK_STATUS(edmi_step(&ti_sys, &ti_work, EDMI_R(1e-3), &ti_res), EDMI_OK);
        }
        if (th_failed() > f0)
            th_note_int("diverged: scheme", (long)schemes[s]);
    }
    /* MP (the default until the default became PM): its corrections land on the singular
     * point, which the domain guard halves */
    prm_mp = edmi_default_params();
    prm_mp.scheme = EDMI_SCHEME_MP;
    TH_NEEDS(ti_upot_in(&prm_mp));
    if (CHECK(ti_build_one(EDMI_R(1.0), q0, p0, &pz, &prm_mp))) {
        ti_dirty_res();
        if (edmi_is_double_precision()) {
            TI_EXPECT(edmi_step(&ti_sys, &ti_work, EDMI_R(0.125), &ti_res), EDMI_ERR_DIVERGED);
            /* the domain guard halved the corrections that landed on the singular point */
            CHECK(ti_res.halvings >= 1);
        } else {
            /* Float reaches its round-off floor near the exact (singular) solution q1 = -1
             * before l_max: accepting it there is also correct. */
            edmi_status st = edmi_step(&ti_sys, &ti_work, EDMI_R(0.125), &ti_res);
            edmi_real dq = ti_sys.body[0].q[0] + EDMI_R(1.0);
            CHECK(st == EDMI_ERR_DIVERGED ||
                  (st == EDMI_OK && dq <= EDMI_R(256.0) * EDMI_EPS && -dq <= EDMI_R(256.0) * EDMI_EPS));
        }
    }
}

/* Success paths do change the state: positions, momenta, time. */
static void ti_success(void)
{
    static const edmi_scheme schemes[5] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    edmi_real dt = EDMI_R(1e-3);
    int s;
    for (s = 0; s < 5; s++) {
        int f0 = th_failed();
        if (th_skip(ti_build_in(schemes[s]), "ti_build(scheme)") ||
            !CHECK(ti_build(schemes[s])))
            continue;
        ti_snapshot();
        ti_dirty_res();
        CHECK_STATUS(edmi_step(&ti_sys, &ti_work, dt, &ti_res), EDMI_OK);
        CHECK(!ti_unchanged());
        CHECK(ti_sys.t == dt);
        CHECK(ti_sys.body[0].q[0] != ti_snap.body[0].q[0]);
        CHECK(ti_sys.body[1].p[1] != ti_snap.body[1].p[1]);
        CHECK(ti_res.iterations >= 1 && ti_res.iterations <= ti_sys.params.l_max);
        CHECK(ti_res.residual <= ti_res.residual0);
        ti_snapshot();
        CHECK_STATUS(edmi_step(&ti_sys, &ti_work, dt, 0), EDMI_OK); /* NULL result is fine */
        CHECK(!ti_unchanged());
        CHECK(ti_sys.t > dt);
        if (th_failed() > f0)
            th_note_int("success path: scheme", (long)schemes[s]);
    }
}

/* ------------------------------------------------------------------------------------------
 * What this build compiled out (EDMI_WITH_*): EDMI_ERR_DISABLED, the system bit-identical
 * ---------------------------------------------------------------------------------------- */

/* V = r^2 / 2 as a user potential (V_c = V_+ = V, V_e = V_- = 0), with its divided
 * difference (d0 + d1) / 2, so that it needs no LG quotient form. */
static int ti_half_sq_fn(void *ctx, edmi_real r, edmi_pot_parts *out)
{
    int j;
    (void)ctx;
    for (j = 0; j < 5; j++)
        out->c[j] = out->e[j] = out->sp[j] = out->sm[j] = EDMI_R(0.0);
    out->c[0] = out->sp[0] = EDMI_R(0.5) * r * r;
    out->c[1] = out->sp[1] = r;
    out->c[2] = out->sp[2] = EDMI_R(1.0);
    return 0;
}

static int ti_half_sq_dd(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd, edmi_real *dd_d1)
{
    (void)ctx;
    *dd = EDMI_R(0.5) * (d0 + d1);
    *dd_d1 = EDMI_R(0.5);
    return 0;
}

/* The call gives EDMI_OK where the build has what it uses, else EDMI_ERR_DISABLED and the
 * system unchanged. */
#define TI_HAVE(call, have)                        \
    do {                                           \
        if (have)                                  \
            CHECK_STATUS(call, EDMI_OK);           \
        else                                       \
            TI_EXPECT(call, EDMI_ERR_DISABLED);    \
    } while (0)

/* One body at (1.5, 0, 0) moving along y, the defaults, and an anchor link at the origin of
 * potential *pot (none if NULL). */
static int ti_base(const edmi_potential *pot)
{
    const edmi_real q[3] = {EDMI_R(1.5), EDMI_R(0.0), EDMI_R(0.0)};
    const edmi_real p[3] = {EDMI_R(0.0), EDMI_R(1.0), EDMI_R(0.0)};
    return edmi_init(&ti_sys, 0) == EDMI_OK &&
           edmi_add_body(&ti_sys, EDMI_R(1.0), q, p, 0) == EDMI_OK &&
           (!pot || edmi_add_anchor(&ti_sys, 0, ti_zero3, pot, 0) == EDMI_OK);
}

static void ti_disabled(void)
{
    static const edmi_scheme schemes[5] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    const edmi_real g[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-9.81)};
    const edmi_real f[3] = {EDMI_R(1.0), EDMI_R(-2.0), EDMI_R(0.5)};
    edmi_potential pots[6];
    const edmi_potential *in = 0; /* the first potential this build carries */
    edmi_params prm = edmi_default_params();
    edmi_pot_parts pp;
    edmi_real dd, dd1;
    edmi_body body;
    edmi_link link;
    edmi_scene sc;
    int k;

    pots[0] = edmi_pot_harmonic(EDMI_R(1.0), EDMI_R(1.0));
    pots[1] = edmi_pot_quartic(EDMI_R(1.0), EDMI_R(1.0));
    pots[2] = edmi_pot_neo_hooke(EDMI_R(1.0), EDMI_R(1.0));
    pots[3] = edmi_pot_lj(EDMI_R(1.0), EDMI_R(1.0));
    pots[4] = edmi_pot_inverse(EDMI_R(1.0));
    pots[5] = edmi_pot_user(ti_half_sq_fn, ti_half_sq_dd, 0);
    for (k = 5; k >= 0; k--)
        if (th_has_pot(pots[k].kind))
            in = &pots[k];

    /* Schemes, and LG's quotient form where LG is in. */
    for (k = 0; k < 5; k++) {
        prm = edmi_default_params();
        prm.scheme = schemes[k];
        if (!CHECK(ti_base(in)))
            continue;
        TI_HAVE(edmi_set_params(&ti_sys, &prm), th_has_scheme(schemes[k]));
        CHECK(ti_base(in));
        TI_HAVE(edmi_init(&ti_sys, &prm), th_has_scheme(schemes[k]));
    }
    if (th_has_scheme(EDMI_SCHEME_LG)) {
        prm = edmi_default_params();
        prm.scheme = EDMI_SCHEME_LG;
        prm.lg_form = EDMI_LG_QUOTIENT;
        CHECK(ti_base(in));
        TI_HAVE(edmi_init(&ti_sys, &prm), EDMI_WITH_LG_QUOTIENT);
    }

    /* Potentials: a link of each kind, its evaluation and its divided difference. */
    for (k = 0; k < 6; k++) {
        int have = th_has_pot(pots[k].kind);
        if (!CHECK(ti_base(0)))
            continue;
        TI_HAVE(edmi_add_anchor(&ti_sys, 0, ti_zero3, &pots[k], 0), have);
        CHECK_STATUS(edmi_pot_eval(&pots[k], EDMI_R(1.5), &pp),
                     have ? EDMI_OK : EDMI_ERR_DISABLED);
        CHECK_STATUS(edmi_pot_divdiff(&pots[k], EDMI_R(1.5), EDMI_R(2.0), &dd, &dd1),
                     have ? EDMI_OK : EDMI_ERR_DISABLED);
    }

    /* The field, a port force, a scene. */
    CHECK(ti_base(in));
    TI_HAVE(edmi_set_field(&ti_sys, g), EDMI_WITH_FIELD);
    CHECK(ti_base(in));
    TI_HAVE(edmi_set_force(&ti_sys, 0, f), EDMI_WITH_PORTS);
    memcpy(&body, &ti_sys.body[0], sizeof body);
    memset(&link, 0, sizeof link);
    link.a = 0;
    link.b = EDMI_ANCHOR;
    link.pot = *in;
    memset(&sc, 0, sizeof sc);
    sc.n_bodies = 1;
    sc.bodies = &body;
    sc.n_links = 1;
    sc.links = &link;
    CHECK(ti_base(0));
    TI_HAVE(edmi_load_scene(&ti_sys, &sc), EDMI_WITH_SCENE);

    /* The field or a port written into the struct by hand: the step refuses them. */
    if (!EDMI_WITH_FIELD && CHECK(ti_base(in))) {
        ti_sys.has_field = 1;
        memcpy(ti_sys.g, g, sizeof g);
        TI_EXPECT(edmi_step(&ti_sys, &ti_work, EDMI_R(1e-3), &ti_res), EDMI_ERR_DISABLED);
    }
    if (!EDMI_WITH_PORTS && CHECK(ti_base(in))) {
        ti_sys.internal.n_forced = 1;
        ti_sys.internal.forced[0] = 0;
        memcpy(ti_sys.force[0], f, sizeof f);
        TI_EXPECT(edmi_step(&ti_sys, &ti_work, EDMI_R(1e-3), &ti_res), EDMI_ERR_DISABLED);
    }
}

void suite_invalid(void)
{
    th_suite("invalid: exact status, system bit-identical");
    ti_status_names();
    ti_params();
    ti_add_body();
    ti_add_links();
    ti_step_input();
    ti_coincident();
    ti_singular();
    ti_no_convergence();
    ti_diverged();
    ti_success();
    ti_disabled();
}
