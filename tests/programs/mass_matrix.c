/* mass_matrix: the paper's general mass matrix (section 2), K = 1/2 p . M^-1 p, stepped by
 * every scheme as M (q_n+1 - q_n) = dt p_n+1/2 (edmi_set_mass_coupling(), EDMI_MAX_MASS_GAP).
 *
 * Built by the Makefile with EDMI_MAX_MASS_GAP = 1, EDMI_MAX_BODIES = 8 and EDMI_MAX_MATRIX
 * = 384 = 48 N: the band of a chain, below the dense 9 N^2 = 576, so a tridiagonal M is
 * solved in the band store or not at all. The scene is a free cable of 8 bodies joined by 7
 * bar elements (quartic springs) with the consistent mass matrix of each element, me/6 [2 1;
 * 1 2]: diagonal me/3 per element end, couplings me/6. Every check compares with an
 * independent truth computed here in long double from the stored states, never with the
 * library's own estimates:
 *   - M^-1 p by Gaussian elimination on the dense M (K, and the library's invariants_of K);
 *   - the time finite element M (q_n+1 - q_n) = dt (p_n + p_n+1)/2 after every step;
 *   - for MP, the momentum equation p_n+1 - p_n = -dt V'(d_m)/d_m r_m per link end;
 *   - L, J and the centre-of-mass invariant C = (1^T M q - t L) / 1^T M 1 (what replaces
 *     sum m q: d/dt 1^T M q = 1^T p = L), to round-off;
 *   - H (tests/lib/passive.c: term by term, with a bound on its own rounding): LG conserves it,
 *     GE, PM and PT never raise it beyond the rounding of the state
 *     with the guard off, and not at all with it on (the energy-safe guarantee, with the
 *     energy balance checked too); the fallback keeps q and L and lowers H;
 *   - the observed order against a run at dt/64, and the coupled M changing the motion;
 *   - refusals, each leaving the system bit-identical.
 * No stdio: output goes through the harness (tests/lib/harness.c), and H's changes are evaluated
 * by tests/lib/passive.c, so the same source runs on the emulated targets (`make test-target`,
 * port/target.mk), where long double is double and every bound adds the truth's rounding.
 * Closing line "N passed, N failed". */
#include <float.h>
#include <math.h>
#include <string.h>

#include "harness.h"
#include "passive.h"

#define MM_N 8
#define MM_ME EDMI_R(0.06)   /* element mass */
#define MM_K EDMI_R(900.0)   /* quartic spring constant */
#define MM_L EDMI_R(0.12)    /* rest length */

static edmi_system mm_sys, mm_copy;
static edmi_workspace mm_work;
/* The truths' own unit of rounding: 1.1e-19 where long double has a 64-bit significand
 * (x86-64), but DBL_EPSILON where long double is double (Arm EABI): there a double build's
 * truths are no finer than its states, and each bound below adds what they may err by. */
#define MM_LD_EPS ((long double)LDBL_EPSILON)

/* One check with the values it measured: counted by the harness (a FAIL line with file:line
 * when !ok) and printed as "ok|FAIL WHO TEXT: v0, v1, v2" either way (sig digits). */
static void mm_report(int ok, int line, const char *who, const char *text, int sig, int nv,
                      long double v0, long double v1, long double v2)
{
    char buf[200];
    const char *part[2];
    long double v[3];
    size_t n = 0;
    int i;
    part[0] = who;
    part[1] = text;
    v[0] = v0;
    v[1] = v1;
    v[2] = v2;
    for (i = 0; i < 2; i++) {
        const char *c = part[i];
        while (*c != '\0' && n + 1 < sizeof buf)
            buf[n++] = *c++;
    }
    buf[n] = '\0';
    ok = th_check(ok, __FILE__, line, buf);
    th_puts(ok ? "ok   " : "FAIL ");
    th_puts(buf);
    for (i = 0; i < nv && i < 3; i++) {
        th_puts(i > 0 ? ", " : ": ");
        th_put_ld(v[i], sig);
    }
    th_newline();
}
#define MM_REPORT(ok, who, text, nv, v0, v1, v2) \
    mm_report((ok) ? 1 : 0, __LINE__, (who), (text), 3, (nv), (v0), (v1), (v2))
#define MM_CHECK(ok, text) th_check((ok) ? 1 : 0, __FILE__, __LINE__, (text))

static long double mm_abs(long double x) { return x < 0.0L ? -x : x; }

/* The dense M of the system in long double. */
static void mm_dense(const edmi_system *s, long double m[MM_N][MM_N])
{
    int a, b;
    for (a = 0; a < MM_N; a++)
        for (b = 0; b < MM_N; b++)
            m[a][b] = 0.0L;
    for (a = 0; a < s->n_bodies; a++)
        m[a][a] = (long double)s->body[a].m;
    for (a = 1; a < s->n_bodies; a++) {
        m[a][a - 1] = (long double)s->mass_off[a][0];
        m[a - 1][a] = (long double)s->mass_off[a][0];
    }
}

/* x = M^-1 p (3 components) by Gaussian elimination with partial pivoting, long double. */
static void mm_solve(const edmi_system *s, long double x[MM_N][3])
{
    long double m[MM_N][MM_N], r[MM_N][3];
    int n = s->n_bodies, i, j, k, c;
    mm_dense(s, m);
    for (i = 0; i < n; i++)
        for (c = 0; c < 3; c++)
            r[i][c] = (long double)s->body[i].p[c];
    for (k = 0; k < n; k++) {
        int piv = k;
        for (i = k + 1; i < n; i++)
            if (mm_abs(m[i][k]) > mm_abs(m[piv][k]))
                piv = i;
        for (j = 0; j < n; j++) {
            long double t = m[k][j];
            m[k][j] = m[piv][j];
            m[piv][j] = t;
        }
        for (c = 0; c < 3; c++) {
            long double t = r[k][c];
            r[k][c] = r[piv][c];
            r[piv][c] = t;
        }
        for (i = k + 1; i < n; i++) {
            long double f = m[i][k] / m[k][k];
            for (j = k; j < n; j++)
                m[i][j] -= f * m[k][j];
            for (c = 0; c < 3; c++)
                r[i][c] -= f * r[k][c];
        }
    }
    for (i = n - 1; i >= 0; i--)
        for (c = 0; c < 3; c++) {
            long double t = r[i][c];
            for (j = i + 1; j < n; j++)
                t -= m[i][j] * x[j][c];
            x[i][c] = t / m[i][i];
        }
}

static long double mm_dist(const edmi_real *a, const edmi_real *b, long double r[3])
{
    long double d2 = 0.0L;
    int c;
    for (c = 0; c < 3; c++) {
        r[c] = (long double)a[c] - (long double)b[c];
        d2 += r[c] * r[c];
    }
    return sqrtl(d2);
}

/* H = 1/2 p . M^-1 p + sum k/4 (d^2 - L^2)^2 in long double; *kin the kinetic part. */
static long double mm_h(const edmi_system *s, long double *kin)
{
    long double x[MM_N][3], k = 0.0L, v = 0.0L, r[3];
    int a, c;
    mm_solve(s, x);
    for (a = 0; a < s->n_bodies; a++)
        for (c = 0; c < 3; c++)
            k += 0.5L * (long double)s->body[a].p[c] * x[a][c];
    for (a = 0; a + 1 < s->n_bodies; a++) {
        long double d = mm_dist(s->body[a].q, s->body[a + 1].q, r);
        long double e = d * d - (long double)MM_L * (long double)MM_L;
        v += 0.25L * (long double)MM_K * e * e;
    }
    if (kin)
        *kin = k;
    return k + v;
}

/* L, J and C in long double. */
static void mm_momenta(const edmi_system *s, long double l[3], long double j[3],
                       long double cm[3])
{
    long double m[MM_N][MM_N], mass = 0.0L, mq[3] = {0.0L, 0.0L, 0.0L};
    int a, b, c;
    mm_dense(s, m);
    for (c = 0; c < 3; c++)
        l[c] = j[c] = 0.0L;
    for (a = 0; a < s->n_bodies; a++) {
        const edmi_real *q = s->body[a].q, *p = s->body[a].p;
        long double row = 0.0L;
        for (b = 0; b < s->n_bodies; b++)
            row += m[a][b];
        mass += row;
        for (c = 0; c < 3; c++) {
            l[c] += (long double)p[c];
            mq[c] += row * (long double)q[c];
        }
        j[0] += (long double)q[1] * p[2] - (long double)q[2] * p[1];
        j[1] += (long double)q[2] * p[0] - (long double)q[0] * p[2];
        j[2] += (long double)q[0] * p[1] - (long double)q[1] * p[0];
    }
    for (c = 0; c < 3; c++)
        cm[c] = (mq[c] - (long double)s->t * l[c]) / mass;
}

/* The cable: bodies along a bent line, momenta with net L and J; consistent masses when
 * `coupled`, else the lumped ones (row sums: me/2 per element end). */
static edmi_status mm_cable(edmi_scheme scheme, int coupled)
{
    edmi_potential bar = edmi_pot_quartic(MM_K, MM_L);
    edmi_params prm = edmi_default_params();
    edmi_status s;
    int a;
    prm.scheme = scheme;
    prm.guard = EDMI_GUARD_OFF;
    prm.tol_r = EDMI_R(0.0);
    prm.tol_a = EDMI_R(0.0);
    s = edmi_init(&mm_sys, &prm);
    for (a = 0; a < MM_N && s == EDMI_OK; a++) {
        edmi_real q[3], p[3], ends = (a == 0 || a == MM_N - 1) ? EDMI_R(1.0) : EDMI_R(2.0);
        edmi_real m = coupled ? ends * MM_ME / EDMI_R(3.0) : ends * MM_ME / EDMI_R(2.0);
        q[0] = EDMI_R(0.11) * (edmi_real)a;
        q[1] = EDMI_R(0.015) * (edmi_real)((a * a) % 5);
        q[2] = EDMI_R(0.01) * (edmi_real)(a % 3);
        p[0] = EDMI_R(0.004) * (edmi_real)((a % 4) - 1);
        p[1] = EDMI_R(0.006) * (edmi_real)(3 - a);
        p[2] = EDMI_R(0.003) * (edmi_real)(a % 2);
        s = edmi_add_body(&mm_sys, m, q, p, NULL);
    }
    for (a = 0; a + 1 < MM_N && s == EDMI_OK; a++)
        s = edmi_add_pair(&mm_sys, a, a + 1, &bar, NULL);
    for (a = 0; a + 1 < MM_N && s == EDMI_OK && coupled; a++)
        s = edmi_set_mass_coupling(&mm_sys, a, a + 1, MM_ME / EDMI_R(6.0));
    return s;
}

static const char *const mm_names[] = {"MP", "LG", "GE", "PM", "PT"};

/* The cable as constant data (edmi_scene with its mass couplings): loaded, it is the system
 * mm_cable() builds call by call, byte for byte; each bad scene is refused with the system
 * unchanged. */
static void mm_scene(void)
{
    static edmi_system built;
    static edmi_body bodies[MM_N];
    static edmi_link links[MM_N - 1];
    static edmi_mass_coupling mc[MM_N];
    edmi_scene sc;
    edmi_status st;
    int a;
    MM_CHECK(mm_cable(EDMI_SCHEME_PM, 1) == EDMI_OK, "coupled cable builds");
    built = mm_sys;
    memset(&sc, 0, sizeof sc);
    for (a = 0; a < MM_N; a++)
        bodies[a] = built.body[a];
    for (a = 0; a + 1 < MM_N; a++) {
        links[a] = built.link[a];
        mc[a].a = a + 1; /* either order */
        mc[a].b = a;
        mc[a].m = MM_ME / EDMI_R(6.0);
    }
    sc.n_bodies = MM_N;
    sc.bodies = bodies;
    sc.n_links = MM_N - 1;
    sc.links = links;
    sc.params = &built.params;
    sc.n_mass_couplings = MM_N - 1;
    sc.mass_couplings = mc;
    memset(&mm_sys, 0, sizeof mm_sys);
    st = edmi_load_scene(&mm_sys, &sc);
    MM_CHECK(st == EDMI_OK && memcmp(&mm_sys, &built, sizeof built) == 0,
             "a scene with mass couplings loads into the system edmi_set_mass_coupling builds");
    mm_copy = mm_sys;
#define MM_BAD_SCENE(want, what)                                                               \
    MM_CHECK(edmi_load_scene(&mm_sys, &sc) == (want) &&                                       \
                 memcmp(&mm_sys, &mm_copy, sizeof mm_sys) == 0,                               \
             what)
    mc[MM_N - 1] = mc[2];
    sc.n_mass_couplings = MM_N;
    MM_BAD_SCENE(EDMI_ERR_PARAM, "a scene listing a pair twice: EDMI_ERR_PARAM, unchanged");
    mc[MM_N - 1].a = 0;
    mc[MM_N - 1].b = 2;
    MM_BAD_SCENE(EDMI_ERR_CAPACITY, "a scene coupling beyond the gap: EDMI_ERR_CAPACITY");
    mc[MM_N - 1].b = 0;
    MM_BAD_SCENE(EDMI_ERR_INDEX, "a scene coupling a body to itself: EDMI_ERR_INDEX");
    mc[MM_N - 1].b = MM_N;
    MM_BAD_SCENE(EDMI_ERR_INDEX, "a scene coupling a body that does not exist: EDMI_ERR_INDEX");
    sc.n_mass_couplings = MM_N - 1;
    mc[3].m = MM_ME * EDMI_R(0.7);
    MM_BAD_SCENE(EDMI_ERR_MASS, "a scene whose M is indefinite: EDMI_ERR_MASS, unchanged");
    mc[3].m = MM_ME / EDMI_R(6.0);
    sc.mass_couplings = NULL;
    MM_BAD_SCENE(EDMI_ERR_NULL, "couplings counted but no list: EDMI_ERR_NULL, unchanged");
    sc.mass_couplings = mc;
    sc.n_mass_couplings = -1;
    MM_BAD_SCENE(EDMI_ERR_PARAM, "a negative count: EDMI_ERR_PARAM, unchanged");
#undef MM_BAD_SCENE
}

/* The refusals: each returns its status and leaves the system bit-identical. */
static void mm_refusals(void)
{
    edmi_real dt = EDMI_R(1e-3), big;
    MM_CHECK(mm_cable(EDMI_SCHEME_PM, 1) == EDMI_OK, "coupled cable builds");
    mm_copy = mm_sys;
#define MM_REFUSE(call, want, what)                                                            \
    MM_CHECK((call) == (want) && memcmp(&mm_sys, &mm_copy, sizeof mm_sys) == 0, what)
    MM_REFUSE(edmi_set_mass_coupling(&mm_sys, 0, 2, EDMI_R(0.001)), EDMI_ERR_CAPACITY,
              "a coupling beyond EDMI_MAX_MASS_GAP: EDMI_ERR_CAPACITY, unchanged");
    MM_REFUSE(edmi_set_mass_coupling(&mm_sys, 3, 3, EDMI_R(0.001)), EDMI_ERR_INDEX,
              "a body coupled to itself: EDMI_ERR_INDEX, unchanged");
    MM_REFUSE(edmi_set_mass_coupling(&mm_sys, 7, 8, EDMI_R(0.001)), EDMI_ERR_INDEX,
              "no body 8: EDMI_ERR_INDEX, unchanged");
    MM_REFUSE(edmi_set_mass_coupling(NULL, 0, 1, EDMI_R(0.001)), EDMI_ERR_NULL,
              "NULL system: EDMI_ERR_NULL");
    big = EDMI_REAL_MAX;
    MM_REFUSE(edmi_set_mass_coupling(&mm_sys, 0, 1, big * EDMI_R(2.0)), EDMI_ERR_NONFINITE,
              "an infinite coupling: EDMI_ERR_NONFINITE, unchanged");
    /* m_01^2 > m_00 m_11 = (me/3)(2 me/3): [[me/3, x], [x, 2me/3]] not positive definite */
    MM_REFUSE(edmi_set_mass_coupling(&mm_sys, 0, 1, MM_ME * EDMI_R(0.48)), EDMI_ERR_MASS,
              "a coupling that makes M indefinite: EDMI_ERR_MASS, unchanged");
    MM_REFUSE(edmi_set_mass_coupling(&mm_sys, 0, 1, -MM_ME * EDMI_R(0.48)), EDMI_ERR_MASS,
              "a negative coupling that makes M indefinite: EDMI_ERR_MASS, unchanged");
    /* A mass written between steps that leaves M indefinite: the step refuses it. */
    mm_sys.body[0].m = MM_ME * EDMI_R(0.02);
    mm_copy = mm_sys;
    MM_REFUSE(edmi_step(&mm_sys, &mm_work, dt, NULL), EDMI_ERR_MASS,
              "a body mass written so that M is indefinite: edmi_step EDMI_ERR_MASS, unchanged");
    {
        edmi_invariants inv;
        MM_CHECK(edmi_invariants_of(&mm_sys, &inv) == EDMI_ERR_MASS,
                 "... and edmi_invariants_of EDMI_ERR_MASS");
    }
#undef MM_REFUSE
    MM_CHECK(mm_cable(EDMI_SCHEME_PM, 1) == EDMI_OK &&
                 edmi_set_mass_coupling(&mm_sys, 2, 3, EDMI_R(0.0)) == EDMI_OK &&
                 mm_sys.mass_off[3][0] == EDMI_R(0.0),
             "a coupling set to 0 uncouples the bodies");
}

/* One scheme on the coupled cable: every step checked against the long double truth. */
static void mm_scheme(edmi_scheme scheme, int steps, edmi_real dt)
{
    static edmi_system first;
    long double l0[3], j0[3], c0[3], h0, kin, worst_fe = 0.0L, worst_mp = 0.0L;
    long double worst_rise = 0.0L, worst_lg = 0.0L, worst_k = 0.0L, dl = 0.0L, dj = 0.0L,
                dc = 0.0L, scale_p = 0.0L, scale_j = 0.0L, scale_q = 0.0L;
    long double eps = (long double)EDMI_EPS;
    const char *who = mm_names[scheme];
    int n, a, c, ok = 1;
    MM_CHECK(mm_cable(scheme, 1) == EDMI_OK, "coupled cable builds");
    first = mm_sys;
    mm_momenta(&mm_sys, l0, j0, c0);
    h0 = mm_h(&mm_sys, &kin);
    for (a = 0; a < MM_N; a++)
        for (c = 0; c < 3; c++) {
            long double q = mm_abs((long double)mm_sys.body[a].q[c]);
            scale_p += mm_abs((long double)mm_sys.body[a].p[c]);
            scale_q = q > scale_q ? q : scale_q;
        }
    scale_j = scale_p * scale_q;
    for (n = 0; n < steps && ok; n++) {
        long double l[3], j[3], cm[3], fe = 0.0L, mp = 0.0L, m[MM_N][MM_N];
        edmi_invariants inv;
        edmi_step_result res;
        tp_delta d;
        mm_copy = mm_sys;
        if (edmi_step(&mm_sys, &mm_work, dt, &res) != EDMI_OK) {
            ok = 0;
            break;
        }
        /* M (q1 - q0) - dt (p0 + p1)/2, relative to its terms: |m_ab| (|q1_b| + |q0_b|) (the
         * stored positions carry eps |q| each, far above eps |q1 - q0|) and dt |p|. */
        mm_dense(&mm_sys, m);
        for (a = 0; a < MM_N; a++)
            for (c = 0; c < 3; c++) {
                long double mdq = 0.0L, mag = 0.0L, r;
                int b;
                for (b = 0; b < MM_N; b++) {
                    long double t = m[a][b] * ((long double)mm_sys.body[b].q[c] -
                                               (long double)mm_copy.body[b].q[c]);
                    mdq += t;
                    mag += mm_abs(m[a][b]) * (mm_abs((long double)mm_sys.body[b].q[c]) +
                                              mm_abs((long double)mm_copy.body[b].q[c]));
                }
                r = mdq - 0.5L * (long double)dt *
                              ((long double)mm_copy.body[a].p[c] + (long double)mm_sys.body[a].p[c]);
                mag += (long double)dt * (mm_abs((long double)mm_copy.body[a].p[c]) +
                                          mm_abs((long double)mm_sys.body[a].p[c]));
                if (mag > 0.0L && mm_abs(r) / mag > fe)
                    fe = mm_abs(r) / mag;
            }
        if (fe > worst_fe)
            worst_fe = fe;
        if (scheme == EDMI_SCHEME_MP) { /* p1 - p0 = -dt beta r_m, beta = V'(d_m)/d_m at the mid-point,
                                    relative to |p1 - p0| + |p1| + dt k (d_m^2 + L^2) |r_m| */
            long double rp[MM_N][3], mag[MM_N];
            for (a = 0; a < MM_N; a++) {
                mag[a] = 0.0L;
                for (c = 0; c < 3; c++) {
                    rp[a][c] = (long double)mm_sys.body[a].p[c] - (long double)mm_copy.body[a].p[c];
                    mag[a] += mm_abs(rp[a][c]) + mm_abs((long double)mm_sys.body[a].p[c]);
                }
            }
            for (a = 0; a + 1 < MM_N; a++) {
                long double rm[3], d2 = 0.0L, beta, big;
                for (c = 0; c < 3; c++) {
                    rm[c] = 0.5L * (((long double)mm_sys.body[a].q[c] - mm_sys.body[a + 1].q[c]) +
                                    ((long double)mm_copy.body[a].q[c] - mm_copy.body[a + 1].q[c]));
                    d2 += rm[c] * rm[c];
                }
                beta = (long double)MM_K * (d2 - (long double)MM_L * MM_L); /* V'(d)/d */
                big = (long double)dt * (long double)MM_K * (d2 + (long double)MM_L * MM_L);
                for (c = 0; c < 3; c++) {
                    rp[a][c] += (long double)dt * beta * rm[c];
                    rp[a + 1][c] -= (long double)dt * beta * rm[c];
                    mag[a] += big * mm_abs(rm[c]);
                    mag[a + 1] += big * mm_abs(rm[c]);
                }
            }
            for (a = 0; a < MM_N; a++)
                for (c = 0; c < 3; c++)
                    if (mag[a] > 0.0L && mm_abs(rp[a][c]) / mag[a] > mp)
                        mp = mm_abs(rp[a][c]) / mag[a];
            if (mp > worst_mp)
                worst_mp = mp;
        }
        mm_momenta(&mm_sys, l, j, cm);
        for (c = 0; c < 3; c++) {
            if (mm_abs(l[c] - l0[c]) > dl)
                dl = mm_abs(l[c] - l0[c]);
            if (mm_abs(j[c] - j0[c]) > dj)
                dj = mm_abs(j[c] - j0[c]);
            if (mm_abs(cm[c] - c0[c]) > dc)
                dc = mm_abs(cm[c] - c0[c]);
        }
        /* H's change over the step and since the start, by tests/lib/passive.c (term by term,
         * with a bound on its own rounding, subtracted: what the truth cannot resolve is
         * not counted as a rise) */
        if (!tp_delta_h(&mm_copy, &mm_sys, &res, &d)) {
            ok = 0;
            break;
        }
        if (d.dh - d.err > worst_rise)
            worst_rise = d.dh - d.err;
        if (!tp_delta_h(&first, &mm_sys, &res, &d)) {
            ok = 0;
            break;
        }
        if (mm_abs(d.dh) - d.err > worst_lg)
            worst_lg = mm_abs(d.dh) - d.err;
        mm_h(&mm_sys, &kin);
        if (edmi_invariants_of(&mm_sys, &inv) != EDMI_OK) {
            ok = 0;
            break;
        }
        if (mm_abs((long double)inv.k - kin) / kin > worst_k)
            worst_k = mm_abs((long double)inv.k - kin) / kin;
    }
    MM_REPORT(ok && n == steps, who, ": the coupled cable's steps succeed", 1, (long double)n,
              0.0L, 0.0L);
    /* Newton to its floor: each equation holds to a few units of rounding of its terms (and
     * of the truth's, 8 of them: a sum of 8 products, each rounded) */
    MM_REPORT(worst_fe <= 64.0L * eps + 8.0L * MM_LD_EPS, who,
              ": M (q1 - q0) = dt p_n+1/2 within 64 eps of its terms", 1, worst_fe, 0.0L, 0.0L);
    if (scheme == EDMI_SCHEME_MP)
        MM_REPORT(worst_mp <= 64.0L * eps + 8.0L * MM_LD_EPS, who,
                  ": p1 - p0 = -dt V'(d_m)/d_m r_m within 64 eps of its terms", 1, worst_mp,
                  0.0L, 0.0L);
    /* L, J, C: conserved up to the rounding of the stored state, a random walk of ~eps of
     * their scale per step; bounded by 4 eps scale per step. */
    MM_REPORT(dl <= 4.0L * eps * scale_p * steps && dj <= 4.0L * eps * scale_j * steps &&
                  dc <= 4.0L * eps * scale_q * steps,
              who, ": |dL|, |dJ|, |dC| to round-off, 4 eps of their scale per step", 3, dl, dj,
              dc);
    /* the truth: Gaussian elimination on a matrix of condition ~3, 8 rows */
    MM_REPORT(worst_k <= 64.0L * (eps + MM_LD_EPS), who,
              ": the library's K (a banded Cholesky solve) within 64 eps of Gaussian "
              "elimination",
              1, worst_k, 0.0L, 0.0L);
    if (scheme == EDMI_SCHEME_LG)
        MM_REPORT(worst_lg <= 8.0L * eps * h0 * steps, who,
                  ": conserves H, |H - H0| <= 8 eps H0 per step (/ H0)", 1, worst_lg / h0,
                  0.0L, 0.0L);
    else if (scheme != EDMI_SCHEME_MP)
        MM_REPORT(worst_rise <= 8.0L * eps * h0, who,
                  ": H never rises beyond the state's rounding, 8 eps H0 (largest rise / H0)",
                  1, worst_rise / h0, 0.0L, 0.0L);
}

/* The passivity guard with a coupled M (GE, PM, PT, guard on as by default), with the energy
 * balance on: every step's H change, evaluated by tests/lib/passive.c from the stored states,
 * is <= 0 beyond the evaluation's own resolution, and equals the reported balance
 * -D_scheme - D_guard (no work, no dampers) within 256 eps of the energies involved. Then the
 * fallback: a solve cut off after one correction stores q_n and the frame's momentum
 * (M 1)_a v, v = L / 1^T M 1, which keeps L and does not raise H. */
static void mm_guarded(edmi_scheme scheme, int steps, edmi_real dt)
{
    long double h, hprev, kin, l0[3], j0[3], c0[3], worst_rise = 0.0L, worst_bal = 0.0L;
    long double dl = 0.0L, scale_p = 0.0L, eps = (long double)EDMI_EPS;
    long guarded = 0, rises = 0;
    const char *who = mm_names[scheme];
    int n, a, c, ok = 1;
    MM_CHECK(mm_cable(scheme, 1) == EDMI_OK, "coupled cable builds");
    mm_sys.params.guard = EDMI_GUARD_AUTO;
    mm_sys.params.energy_balance = 1;
    mm_sys.params.tol_r = scheme == EDMI_SCHEME_PM ? EDMI_R(1e-6) : EDMI_R(0.0); /* the guard's work */
    mm_momenta(&mm_sys, l0, j0, c0);
    hprev = mm_h(&mm_sys, &kin);
    for (a = 0; a < MM_N; a++)
        for (c = 0; c < 3; c++)
            scale_p += mm_abs((long double)mm_sys.body[a].p[c]);
    for (n = 0; n < steps; n++) {
        edmi_step_result res;
        long double l[3], j[3], cm[3], bal, mag;
        tp_delta d;
        mm_copy = mm_sys;
        if (edmi_step(&mm_sys, &mm_work, dt, &res) != EDMI_OK ||
            !tp_delta_h(&mm_copy, &mm_sys, &res, &d)) {
            ok = 0;
            break;
        }
        guarded += res.guard_action != 0;
        rises += d.broken; /* dh > w + err; w: no work here, what the tank gave */
        if (d.dh > worst_rise)
            worst_rise = d.dh;
        h = mm_h(&mm_sys, &kin);
        bal = (h - hprev) + (long double)res.diss_scheme + (long double)res.diss_guard;
        mag = mm_abs(hprev) + mm_abs((long double)res.diss_scheme) +
              mm_abs((long double)res.diss_guard);
        if (mm_abs(bal) / mag > worst_bal)
            worst_bal = mm_abs(bal) / mag;
        hprev = h;
        mm_momenta(&mm_sys, l, j, cm);
        for (c = 0; c < 3; c++)
            if (mm_abs(l[c] - l0[c]) > dl)
                dl = mm_abs(l[c] - l0[c]);
    }
    MM_REPORT(ok, who, ", guard on, coupled M: steps succeed; steps the guard changed", 2,
              (long double)n, (long double)guarded, 0.0L);
    /* H(s1) - H(s0) <= T_n - T_n+1 + its evaluation's own error bound (tests/lib/passive.c) on
     * every step */
    MM_REPORT(ok && rises == 0, who,
              ", guard on, coupled M: H never rose beyond the tank (steps it did; largest change "
              "/ H)", 2,
              (long double)rises, worst_rise / hprev, 0.0L);
    MM_REPORT(worst_bal <= 256.0L * (eps + MM_LD_EPS), who,
              ", guard on: H_n+1 - H_n = -D_scheme - D_guard within 256 eps of the energies", 1,
              worst_bal, 0.0L, 0.0L);
    MM_REPORT(dl <= 4.0L * eps * scale_p * steps, who,
              ", guard on: L conserved to 4 eps |p| per step", 1, dl, 0.0L, 0.0L);
}

static void mm_fallback(void)
{
    long double l0[3], j0[3], c0[3], l1[3], j1[3], c1[3], eps = (long double)EDMI_EPS, dl;
    edmi_step_result res;
    edmi_status st;
    tp_delta d;
    int rose = 1;
    mm_cable(EDMI_SCHEME_PM, 1);
    mm_sys.params.guard = EDMI_GUARD_AUTO;
    mm_sys.params.fallback = 1;
    mm_sys.params.l_max = 1;
    mm_sys.params.tol_r = EDMI_R(0.0);
    mm_sys.params.tol_a = EDMI_R(0.0);
    mm_momenta(&mm_sys, l0, j0, c0);
    mm_copy = mm_sys;
    st = edmi_step(&mm_sys, &mm_work, EDMI_R(1e-3), &res);
    mm_momenta(&mm_sys, l1, j1, c1);
    if (st == EDMI_OK && tp_delta_h(&mm_copy, &mm_sys, &res, &d))
        rose = d.broken; /* dh > w + err; no work: at most what the tank gave */
    dl = mm_abs(l1[0] - l0[0]) + mm_abs(l1[1] - l0[1]) + mm_abs(l1[2] - l0[2]);
    MM_REPORT(st == EDMI_OK && res.stop == EDMI_STOP_FALLBACK &&
                  res.cause == EDMI_ERR_NO_CONVERGENCE && !rose &&
                  dl <= 64.0L * eps * (mm_abs(l0[0]) + mm_abs(l0[1]) + mm_abs(l0[2])) + 1e-30L,
              "fallback, coupled M", ": EDMI_OK with stop FALLBACK (Newton's last iterate under "
              "the guard), H not raised beyond the tank (H1 - H0), L changed by",
              2, st == EDMI_OK ? d.dh : 0.0L, dl, 0.0L);
}

/* The highest axial mode of a fixed-free bar of MM_N linear elements (harmonic springs along
 * x, so the motion stays linear): its exact FE frequency, omega^2 the largest root of
 * det(K - w M) by bisection on the Sturm count of the tridiagonal pencil (the negative pivots
 * of K - w M, long double), against the frequency a PM run in that mode's shape shows. On a
 * linear system every scheme here is the mid-point rule, whose frequency is
 * (2/dt) atan(omega dt / 2): the run must show exactly that, and consistent masses must give
 * the higher FE frequency, lumped the lower (the classical bracketing of the exact one). */
static long double mm_sturm(const long double *kd, const long double *ko, const long double *md,
                            const long double *mo, int n, long double w)
{
    long double d = 0.0L;
    int i, neg = 0;
    for (i = 0; i < n; i++) {
        long double a = kd[i] - w * md[i], b = i > 0 ? ko[i - 1] - w * mo[i - 1] : 0.0L;
        d = i > 0 ? a - b * b / d : a;
        if (d == 0.0L)
            d = -1e-300L;
        neg += d < 0.0L;
    }
    return (long double)neg;
}

static void mm_modes(int consistent, long double *w_fe, long double *w_run, long double *w_mid)
{
    long double kd[MM_N], ko[MM_N], md[MM_N], mo[MM_N], lo = 0.0L, hi, x[MM_N], y[MM_N];
    const long double k = (long double)MM_K, me = (long double)MM_ME;
    const edmi_real dt = EDMI_R(2e-4);
    edmi_potential bar = edmi_pot_harmonic(MM_K, MM_L);
    edmi_params prm = edmi_default_params();
    long double prev = 0.0L, t_first = -1.0L, t_last = -1.0L;
    int i, it, n, crossings = 0;
    for (i = 0; i < MM_N; i++) { /* body i = node i + 1; node 0 fixed */
        kd[i] = i == MM_N - 1 ? k : 2.0L * k;
        ko[i] = -k;
        md[i] = consistent ? (i == MM_N - 1 ? me / 3.0L : 2.0L * me / 3.0L)
                           : (i == MM_N - 1 ? me / 2.0L : me);
        mo[i] = consistent ? me / 6.0L : 0.0L;
    }
    hi = 8.0L * k / (consistent ? me / 6.0L : me / 2.0L); /* above every eigenvalue */
    for (it = 0; it < 200; it++) {
        long double mid = 0.5L * (lo + hi);
        if (mm_sturm(kd, ko, md, mo, MM_N, mid) >= (long double)MM_N)
            hi = mid;
        else
            lo = mid;
    }
    *w_fe = sqrtl(0.5L * (lo + hi));
    /* its shape by inverse iteration on K - (w^2 (1 - 1e-9)) M */
    for (i = 0; i < MM_N; i++)
        x[i] = (i % 2) ? 1.0L : -1.0L;
    for (it = 0; it < 30; it++) {
        long double c[MM_N], r[MM_N], sh = *w_fe * *w_fe * (1.0L - 1e-9L), nrm = 0.0L;
        for (i = 0; i < MM_N; i++) { /* tridiagonal solve (Thomas) of (K - sh M) y = M x */
            long double a = kd[i] - sh * md[i], b = i > 0 ? ko[i - 1] - sh * mo[i - 1] : 0.0L;
            long double rhs = md[i] * x[i] + (i > 0 ? mo[i - 1] * x[i - 1] : 0.0L) +
                              (i + 1 < MM_N ? mo[i] * x[i + 1] : 0.0L);
            long double den = a - (i > 0 ? b * c[i - 1] : 0.0L);
            c[i] = (i + 1 < MM_N ? ko[i] - sh * mo[i] : 0.0L) / den;
            r[i] = (rhs - (i > 0 ? b * r[i - 1] : 0.0L)) / den;
        }
        for (i = MM_N - 1; i >= 0; i--)
            y[i] = r[i] - (i + 1 < MM_N ? c[i] * y[i + 1] : 0.0L);
        for (i = 0; i < MM_N; i++)
            nrm = mm_abs(y[i]) > nrm ? mm_abs(y[i]) : nrm;
        for (i = 0; i < MM_N; i++)
            x[i] = y[i] / nrm;
    }
    /* the run: the bar along x at rest lengths, displaced by 1e-2 L times the mode (a
     * linear system: any amplitude; a much smaller one, 1e-4 L, is below what float's
     * guard can certify, its positions' rounding outweighing the mode's kinetic energy) */
    prm.scheme = EDMI_SCHEME_PM;
    edmi_init(&mm_sys, &prm);
    for (i = 0; i < MM_N; i++) {
        edmi_real q[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)}, p[3] = {EDMI_R(0.0), EDMI_R(0.0),
                                                                        EDMI_R(0.0)};
        q[0] = (edmi_real)((long double)MM_L * ((long double)(i + 1) + 1e-2L * x[i]));
        edmi_add_body(&mm_sys, (edmi_real)md[i], q, p, NULL);
    }
    {
        const edmi_real o[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
        edmi_add_anchor(&mm_sys, 0, o, &bar, NULL);
    }
    for (i = 0; i + 1 < MM_N; i++) {
        edmi_add_pair(&mm_sys, i, i + 1, &bar, NULL);
        if (consistent)
            edmi_set_mass_coupling(&mm_sys, i, i + 1, MM_ME / EDMI_R(6.0));
    }
    for (n = 1; n <= 4000; n++) { /* upward zero crossings of the tip's displacement */
        long double u;
        if (edmi_step(&mm_sys, &mm_work, dt, NULL) != EDMI_OK)
            break;
        u = (long double)mm_sys.body[MM_N - 1].q[0] - (long double)MM_L * MM_N;
        if (n > 1 && prev < 0.0L && u >= 0.0L) {
            long double tc = (long double)dt * ((long double)(n - 1) + prev / (prev - u));
            if (t_first < 0.0L)
                t_first = tc;
            t_last = tc;
            crossings++;
        }
        prev = u;
    }
    *w_run = crossings > 1 ? 2.0L * 3.14159265358979323846L * (long double)(crossings - 1) /
                                 (t_last - t_first)
                           : 0.0L;
    *w_mid = 2.0L / (long double)dt * atanl(*w_fe * (long double)dt / 2.0L);
}

static void mm_highest_mode(void)
{
    long double fe_c, run_c, mid_c, fe_l, run_l, mid_l;
    mm_modes(1, &fe_c, &run_c, &mid_c);
    mm_modes(0, &fe_l, &run_l, &mid_l);
    mm_report(fe_c > fe_l * 1.05L, __LINE__, "highest axial mode, 8 elements",
              ": FE omega consistent above lumped", 9, 2, fe_c, fe_l, 0.0L);
    mm_report(mm_abs(run_c - mid_c) <= 1e-3L * mid_c, __LINE__, "consistent",
              ": PM run [rad/s] against the mid-point's (2/dt) atan(omega dt/2), relative "
              "difference",
              9, 3, run_c, mid_c, mm_abs(run_c - mid_c) / mid_c);
    mm_report(mm_abs(run_l - mid_l) <= 1e-3L * mid_l, __LINE__, "lumped",
              ": PM run [rad/s] against (2/dt) atan(omega dt/2), relative difference", 9, 3,
              run_l, mid_l, mm_abs(run_l - mid_l) / mid_l);
}

/* Position error at T against the same scheme at dt/64: the observed order at dt and dt/2. */
static long double mm_error(edmi_scheme scheme, edmi_real dt, int steps, int coupled,
                            edmi_real ref[MM_N][3])
{
    long double e = 0.0L;
    int n, a, c;
    if (mm_cable(scheme, coupled) != EDMI_OK)
        return -1.0L;
    for (n = 0; n < steps; n++)
        if (edmi_step(&mm_sys, &mm_work, dt, NULL) != EDMI_OK)
            return -1.0L;
    for (a = 0; a < MM_N; a++)
        for (c = 0; c < 3; c++) {
            long double d = (long double)mm_sys.body[a].q[c] - (long double)ref[a][c];
            e = mm_abs(d) > e ? mm_abs(d) : e;
        }
    return e;
}

/* GE is first order (tests/test_orders.c), the others second; GE reaches its asymptotic
 * rate at smaller steps (measured: 0.87 at dt = 4e-3), so it runs at dt / 8. */
static void mm_orders(void)
{
    static edmi_real ref[MM_N][3];
    edmi_scheme s;
    for (s = EDMI_SCHEME_MP; s <= EDMI_SCHEME_PT; s = (edmi_scheme)(s + 1)) {
        const edmi_real dt = s == EDMI_SCHEME_GE ? EDMI_R(5e-4) : EDMI_R(4e-3);
        const int steps = s == EDMI_SCHEME_GE ? 200 : 25; /* T = 0.1 */
        const long double want = s == EDMI_SCHEME_GE ? 1.0L : 2.0L;
        long double e1, e2, order;
        int a, c, n;
        mm_cable(s, 1);
        for (n = 0; n < steps * 64; n++)
            edmi_step(&mm_sys, &mm_work, dt / EDMI_R(64.0), NULL);
        for (a = 0; a < MM_N; a++)
            for (c = 0; c < 3; c++)
                ref[a][c] = mm_sys.body[a].q[c];
        e1 = mm_error(s, dt, steps, 1, ref);
        e2 = mm_error(s, dt / EDMI_R(2.0), 2 * steps, 1, ref);
        order = log2l(e1 / e2);
        MM_REPORT(e1 > 0.0L && e2 > 0.0L && mm_abs(order - want) <= 0.15L, mm_names[s],
                  ", coupled M: observed order (want 2, GE 1, +- 0.15); errors at dt, dt/2", 3,
                  order, e1, e2);
    }
}

/* The hanging cable of examples/scenes/cable_*.scene (8 elements of 0.05 kg, harmonic
 * 500 N/m, 0.1 m, released from the horizontal under gravity, PM, guard on, dt = 1e-3, 2 s):
 * the guard's drags (a last resort, taken when its rounding search misses) and its rises of
 * H, consistent against lumped masses. The search models a coupled M exactly to first order
 * (K's slope m_aa (M^-1 p)_a, the field's pull (M 1)_a g), so it must miss no more often
 * than with the diagonal masses, whose model is exact: at most 2 more drags in 2000 steps. */
static long mm_hanging(int consistent, long *rises)
{
    edmi_potential bar = edmi_pot_harmonic(EDMI_R(500.0), EDMI_R(0.1));
    edmi_params prm = edmi_default_params();
    const edmi_real o[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    const edmi_real g[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-9.81)};
    const edmi_real me = EDMI_R(0.05);
    edmi_status st;
    long drags = 0;
    int a, n;
    prm.scheme = EDMI_SCHEME_PM;
    *rises = -1;
    st = edmi_init(&mm_sys, &prm);
    for (a = 0; a < MM_N && st == EDMI_OK; a++) {
        edmi_real q[3], p[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
        edmi_real ends = a == MM_N - 1 ? EDMI_R(1.0) : EDMI_R(2.0);
        q[0] = EDMI_R(0.1) * (edmi_real)(a + 1);
        q[1] = q[2] = EDMI_R(0.0);
        st = edmi_add_body(&mm_sys, consistent ? ends * me / EDMI_R(3.0) : ends * me / EDMI_R(2.0),
                           q, p, NULL);
    }
    if (st == EDMI_OK)
        st = edmi_add_anchor(&mm_sys, 0, o, &bar, NULL);
    for (a = 0; a + 1 < MM_N && st == EDMI_OK; a++) {
        st = edmi_add_pair(&mm_sys, a, a + 1, &bar, NULL);
        if (st == EDMI_OK && consistent)
            st = edmi_set_mass_coupling(&mm_sys, a, a + 1, me / EDMI_R(6.0));
    }
    if (st == EDMI_OK)
        st = edmi_set_field(&mm_sys, g);
    if (st != EDMI_OK)
        return -1;
    *rises = 0;
    for (n = 0; n < 2000; n++) {
        edmi_step_result res;
        tp_delta d;
        mm_copy = mm_sys;
        if (edmi_step(&mm_sys, &mm_work, EDMI_R(1e-3), &res) != EDMI_OK ||
            !tp_delta_h(&mm_copy, &mm_sys, &res, &d)) {
            *rises = -1;
            return -1;
        }
        drags += (res.guard_action & EDMI_MOVE_DRAG) != 0;
        *rises += d.broken; /* dh > w + err, decided in tp_q */
    }
    return drags;
}

static void mm_hanging_guard(void)
{
    long rises_c, rises_l, drags_c = mm_hanging(1, &rises_c), drags_l = mm_hanging(0, &rises_l);
    MM_REPORT(drags_c >= 0 && drags_l >= 0 && rises_c == 0 && rises_l == 0, "hanging cable",
              ", PM, guard on, 2000 steps: H never rose, consistent and lumped (steps it did)",
              2, (long double)rises_c, (long double)rises_l, 0.0L);
    MM_REPORT(drags_c >= 0 && drags_l >= 0 && drags_c <= drags_l + 2, "hanging cable",
              ": the guard drags on as few steps with the consistent mass as with the lumped "
              "(+2)",
              2, (long double)drags_c, (long double)drags_l, 0.0L);
}

/* The consistent mass changes the motion: lumped and consistent cables part by more than
 * the schemes' own error. */
static void mm_lumped_differs(void)
{
    static edmi_real q_lumped[MM_N][3];
    long double diff, err;
    int a, c, n;
    mm_cable(EDMI_SCHEME_PM, 0);
    for (n = 0; n < 100; n++)
        edmi_step(&mm_sys, &mm_work, EDMI_R(1e-3), NULL);
    for (a = 0; a < MM_N; a++)
        for (c = 0; c < 3; c++)
            q_lumped[a][c] = mm_sys.body[a].q[c];
    diff = mm_error(EDMI_SCHEME_PM, EDMI_R(1e-3), 100, 1, q_lumped);
    err = mm_error(EDMI_SCHEME_PM, EDMI_R(5e-4), 200, 1, q_lumped);
    MM_REPORT(diff > 1e-4L && mm_abs(diff - err) < 0.05L * diff, "consistent against lumped",
              " mass after 0.1: the tips part by (dt 1e-3; dt 5e-4), not a time-step effect",
              2, diff, err, 0.0L);
}

/* Issue 21's coupled-mass cases. (1) Three bodies in a chain of springs (k 10, rest length 1),
 * M = [1 .6 0; .6 1 .6; 0 .6 1] (definite, not diagonally dominant), PM with the fallback, dt
 * 1e-2: the guard failed every step (EDMI_ERR_PASSIVITY returned although the fallback was
 * set) before it learnt any SPD M; 2000 steps now all solve, each passive. (2) Two bodies of
 * mass 0.5 coupled by 0.49999 (M's condition 1e5): in float Newton stopped converging at step
 * 25 for good (1975 of 2000 steps NO_CONVERGENCE); with 3 levels of substeps every step is
 * stored, each passive, none falls back. */
static void mm_hard_run(int nb, edmi_real m, edmi_real mc, int levels, const char *who)
{
    const edmi_real q[3][3] = {{0, 0, 0}, {EDMI_R(1.1), EDMI_R(0.1), 0},
                               {EDMI_R(2.0), EDMI_R(-0.1), EDMI_R(0.2)}};
    const edmi_real p[3][3] = {{0, 1, 0}, {EDMI_R(0.5), 0, EDMI_R(-0.3)}, {0, -1, EDMI_R(0.4)}};
    edmi_potential sp = edmi_pot_harmonic(10, 1);
    edmi_params prm = edmi_default_params();
    edmi_step_result res;
    long n, ok = 0, fb = 0, split = 0, broken = 0;
    int i;
    prm.scheme = EDMI_SCHEME_PM;
    prm.fallback = 1;
    prm.substep_levels = levels;
    MM_CHECK(edmi_init(&mm_sys, &prm) == EDMI_OK, "init");
    for (i = 0; i < nb; i++)
        MM_CHECK(edmi_add_body(&mm_sys, m, q[i], p[i], 0) == EDMI_OK, "body");
    for (i = 0; i + 1 < nb; i++) {
        MM_CHECK(edmi_add_pair(&mm_sys, i, i + 1, &sp, 0) == EDMI_OK, "spring");
        MM_CHECK(edmi_set_mass_coupling(&mm_sys, i, i + 1, mc) == EDMI_OK, "coupling");
    }
    for (n = 0; n < 2000; n++) {
        tp_delta d;
        mm_copy = mm_sys;
        ok += edmi_step(&mm_sys, &mm_work, EDMI_R(1e-2), &res) == EDMI_OK;
        fb += res.fallbacks > 0;
        split += res.substeps > 1;
        broken += !tp_delta_h(&mm_copy, &mm_sys, &res, &d) || d.broken;
    }
    MM_REPORT(ok == 2000 && fb == 0 && broken == 0, who,
              ", PM, fallback set, 2000 steps of 1e-2: all solved, none falls back, each passive;"
              " OK, split into substeps", 2, (long double)ok, (long double)split, 0.0L);
}

static void mm_hard(void)
{
    mm_hard_run(3, 1, EDMI_R(0.6), 0, "M [1 .6 0; .6 1 .6; 0 .6 1]");
    mm_hard_run(2, EDMI_R(0.5), EDMI_R(0.49999), 3, "M [.5 .49999; .49999 .5], 3 levels");
}

int main(void)
{
    edmi_scheme s;
    th_puts(edmi_is_double_precision() ? "mass_matrix: EDMI_REAL double" : "mass_matrix: EDMI_REAL float");
    th_puts(", EDMI_MAX_MASS_GAP ");
    th_put_int(EDMI_MAX_MASS_GAP);
    th_puts(", EDMI_MAX_MATRIX ");
    th_put_int(EDMI_MAX_MATRIX);
    th_puts(" (dense: ");
    th_put_int(9L * EDMI_MAX_BODIES * EDMI_MAX_BODIES);
    th_puts("), truths with LDBL_EPSILON ");
    th_put_ld(MM_LD_EPS, 3);
    th_newline();
    mm_refusals();
    mm_scene();
    for (s = EDMI_SCHEME_MP; s <= EDMI_SCHEME_PT; s = (edmi_scheme)(s + 1))
        mm_scheme(s, 400, EDMI_R(1e-3));
    for (s = EDMI_SCHEME_GE; s <= EDMI_SCHEME_PT; s = (edmi_scheme)(s + 1))
        mm_guarded(s, 400, EDMI_R(1e-3));
    mm_fallback();
    mm_hard();
    mm_hanging_guard();
    mm_orders();
    mm_lumped_differs();
    mm_highest_mode();
    return th_finish() == 0 ? 0 : 1;
}
