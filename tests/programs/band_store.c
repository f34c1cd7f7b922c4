/* band_store: the Newton matrix kept as a band (EDMI_MAX_MATRIX below the dense size) gives
 * the dense store's results bit for bit, and a system that would not fit is refused.
 *
 * Built twice per precision by the Makefile, EDMI_MAX_BODIES = 64: with the default (dense)
 * store, and with EDMI_MAX_MATRIX = 3024 = 3 * 63 * 16, the band of a chain of 63 bodies
 * (largest pair gap 1: half-bandwidth kb = 5, rows of 3 kb + 1 = 16). Each binary steps the
 * same scene, a hanging chain of 63 bodies (quartic springs between neighbours, the first
 * anchored, a damper on every fourth link, gravity), 60 steps of each scheme, and prints the
 * final states as hexadecimal bit patterns; tests/scripts/band_check.sh compares the two outputs (the
 * dense build is the independent reference: the same arithmetic in the plain row-major
 * layout). The banded build (BAND_NARROW) also checks its refusals, each leaving the system
 * bit-identical: a 64th body, a pair of gap 2, a scene with a gap-2 link, a link rewritten
 * in place to gap 2 (edmi_step), all EDMI_ERR_CAPACITY. Closing line "N passed, N failed". */
#include <stdio.h>
#include <string.h>

#include "edmi.h"

#define BS_N 63
#define BS_STEPS 60

static edmi_system bs_sys;
static edmi_workspace bs_work;
static int bs_pass, bs_fail;

static void bs_check(int ok, const char *what)
{
    if (ok) {
        bs_pass++;
    } else {
        bs_fail++;
        printf("FAIL %s\n", what);
    }
}

static edmi_status bs_chain(edmi_scheme scheme)
{
    static const edmi_real g[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-9.81)};
    static const edmi_real top[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential spring = edmi_pot_quartic(EDMI_R(400.0), EDMI_R(0.1));
    edmi_params prm = edmi_default_params();
    edmi_status s;
    int a;
    prm.scheme = scheme;
    s = edmi_init(&bs_sys, &prm);
    for (a = 0; a < BS_N && s == EDMI_OK; a++) {
        edmi_real q[3], p[3];
        q[0] = EDMI_R(0.1) * (edmi_real)(a + 1);
        q[1] = EDMI_R(0.01) * (edmi_real)(a % 3);
        q[2] = EDMI_R(0.0);
        p[0] = EDMI_R(0.0);
        p[1] = EDMI_R(0.02) * (edmi_real)((a % 5) - 2);
        p[2] = EDMI_R(0.01) * (edmi_real)(a % 2);
        s = edmi_add_body(&bs_sys, EDMI_R(0.05), q, p, NULL);
    }
    if (s == EDMI_OK)
        s = edmi_add_anchor(&bs_sys, 0, top, &spring, NULL);
    for (a = 0; a + 1 < BS_N && s == EDMI_OK; a++)
        s = edmi_add_pair(&bs_sys, a, a + 1, &spring, NULL);
    for (a = 1; a < BS_N && s == EDMI_OK; a += 4)
        s = edmi_add_damper(&bs_sys, a, EDMI_R(0.01), NULL);
    if (s == EDMI_OK)
        s = edmi_set_field(&bs_sys, g);
    return s;
}

static void bs_print_bits(const edmi_real *x, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        unsigned char b[sizeof(edmi_real)];
        size_t k;
        memcpy(b, &x[i], sizeof b);
        for (k = sizeof b; k > 0; k--)
            printf("%02x", b[k - 1]);
        putchar(i + 1 < n ? ' ' : '\n');
    }
}

#ifdef BAND_NARROW
static edmi_system bs_copy;

static int bs_same(void) { return memcmp(&bs_sys, &bs_copy, sizeof bs_sys) == 0; }

static void bs_refusals(void)
{
    static const edmi_real q[3] = {EDMI_R(9.0), EDMI_R(0.0), EDMI_R(0.0)};
    static const edmi_real p[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential spring = edmi_pot_quartic(EDMI_R(400.0), EDMI_R(0.1));
    edmi_scene scene;
    edmi_link links[1];
    edmi_body bodies[3];
    int a;
    bs_check(bs_chain(EDMI_SCHEME_PM) == EDMI_OK, "the chain of 63 bodies fits the band store");
    memcpy(&bs_copy, &bs_sys, sizeof bs_sys);
    bs_check(edmi_add_body(&bs_sys, EDMI_R(1.0), q, p, NULL) == EDMI_ERR_CAPACITY && bs_same(),
             "a 64th body is refused, nothing changed");
    bs_check(edmi_add_pair(&bs_sys, 0, 2, &spring, NULL) == EDMI_ERR_CAPACITY && bs_same(),
             "a pair of gap 2 is refused, nothing changed");
    bs_sys.link[1].b = 3; /* was the pair (0, 1): now (0, 3), gap 3 */
    memcpy(&bs_copy, &bs_sys, sizeof bs_sys);
    bs_check(edmi_step(&bs_sys, &bs_work, EDMI_R(1e-3), NULL) == EDMI_ERR_CAPACITY && bs_same(),
             "edmi_step refuses a link rewritten to gap 3, nothing changed");
    memset(&scene, 0, sizeof scene);
    memset(links, 0, sizeof links);
    memset(bodies, 0, sizeof bodies);
    for (a = 0; a < 3; a++) {
        bodies[a].m = EDMI_R(1.0);
        bodies[a].q[0] = (edmi_real)a;
    }
    links[0].a = 0;
    links[0].b = 2;
    links[0].pot = spring;
    scene.n_bodies = 3;
    scene.bodies = bodies;
    scene.n_links = 1;
    scene.links = links;
    bs_check(edmi_load_scene(&bs_sys, &scene) == EDMI_OK, "3 bodies with a gap-2 link fit");
    bs_check(bs_chain(EDMI_SCHEME_PM) == EDMI_OK, "the chain again");
    memcpy(&bs_copy, &bs_sys, sizeof bs_sys);
    {
        static edmi_body many[BS_N];
        memset(many, 0, sizeof many);
        for (a = 0; a < BS_N; a++) {
            many[a].m = EDMI_R(1.0);
            many[a].q[0] = (edmi_real)a;
        }
        scene.n_bodies = BS_N;
        scene.bodies = many;
        bs_check(edmi_load_scene(&bs_sys, &scene) == EDMI_ERR_CAPACITY && bs_same(),
                 "a scene of 63 bodies with a gap-2 link is refused, nothing changed");
    }
}
#endif

int main(void)
{
    int scheme, k;
#ifdef BAND_NARROW
    bs_refusals();
#endif
    for (scheme = EDMI_SCHEME_MP; scheme <= EDMI_SCHEME_PT; scheme++) {
        edmi_status s = bs_chain((edmi_scheme)scheme);
        for (k = 0; k < BS_STEPS && s == EDMI_OK; k++)
            s = edmi_step(&bs_sys, &bs_work, EDMI_R(1e-3), NULL);
        bs_check(s == EDMI_OK, "60 steps of the chain");
        printf("state %d ", scheme);
        bs_print_bits(&bs_sys.body[0].q[0], 3);
        for (k = 0; k < BS_N; k++) {
            printf("q%d ", k);
            bs_print_bits(bs_sys.body[k].q, 3);
            printf("p%d ", k);
            bs_print_bits(bs_sys.body[k].p, 3);
        }
    }
    printf("%d passed, %d failed\n", bs_pass, bs_fail);
    return bs_fail != 0;
}
