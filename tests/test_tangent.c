/* suite_tangent: the residual and consistent tangent Newton uses, and Newton itself.
 *
 * (1) edmi_residual against the step equations written out here from the paper (section 3.4
 *     and the many-body forces of section 4.1): R_q = q1 - q0 - dt/m (p0+p1)/2 and
 *     R_p = p1 - p0 + sum of link impulses f = dt beta r_m, beta per scheme;
 * (2) pair impulses cancel: sum over bodies of R_p - (p1 - p0) = 0 (linear momentum);
 * (3) edmi_tangent = dR_p/dq1 against a finite-difference Jacobian of edmi_residual;
 * (4) a converged edmi_step satisfies the step equations to its documented stopping test,
 *     with the documented residual scaling recomputed here;
 * (5) Newton's iteration counts on the paper's problems, and its quadratic convergence;
 * (6) dampers: their tangent blocks against finite differences (an anchor link and a pair
 *     link in general position, and a body on one axis whose step crosses its anchor), and
 *     Newton on the 1-D virtual coupling of examples/haptic.c through its anchor.
 * Scenes: a neo-Hookean anchor, LJ, gravity and quartic pairs, and a 3-body chain with pair
 * links, a non-neighbour Coulomb pair and an anchor. Schemes: MP, LG (closed form; quotient;
 * quotient forced onto each of the five alternates), GE, PM, PT. */
#include <string.h>

#include "harness.h"
#include "scenes.h"
#include "suites.h"

/* ------------------------------------------------------------------------------------------
 * Tolerances
 * ---------------------------------------------------------------------------------------- */

/* R_q = q1 - q0 - h (p0 + p1), h = dt/(2m): four roundings of magnitudes bounded by
 * |q1| + |q0| + h (|p0| + |p1|); 8 eps allows for another operation order. */
#define TG_U_RQ (EDMI_R(8.0) * EDMI_EPS)

/* Round-off of one link impulse f = dt beta r_m relative to |f|: a potential derivative
 * (<= ~20 roundings, see test_potentials.c), two norms, a quotient and a product each add a
 * few; the LG quotient [V(d1)-V(d0)]/(d1-d0) amplifies the error of its V values by
 * (|V0| + |V1|)/(|Lambda| |d1 - d0|), which is <= ~20 at the trial states below (every link
 * length changes by >= 10% between q0 and q1). 256 eps covers it. */
#define TG_U_RP (EDMI_R(256.0) * EDMI_EPS)

/* Round-off of assembling R_p = (p1 - p0) + sum of f: one rounding per addition, at most
 * four terms per body here, each bounded by |p1 - p0| + sum |f|. */
#define TG_U_SUM (EDMI_R(4.0) * EDMI_EPS)

/* Round-off of a tangent entry relative to max |K|: a handful of products of already
 * rounded values (beta, gamma, r_m, u). */
#define TG_U_K (EDMI_R(64.0) * EDMI_EPS)

/* Finite-difference step relative to the shortest link, for the 4th-order central stencil
 * D(h) = [R(-2h) - 8 R(-h) + 8 R(h) - R(2h)] / (12h) of R_p along one coordinate of q1.
 * Its error is c h^4 (truncation) + 1.5 e_R / h (round-off, e_R the error of one R_p entry:
 * TG_U_SUM and TG_U_RP above). The truncation is measured by Richardson:
 * D(2h) - D(h) = 15 c h^4, so |D(h) - D| ~ |D(2h) - D(h)| / 15, of which we allow twice;
 * the round-off is bounded a priori. The step balances both for LJ (5th derivative
 * ~ 13*14*15*16*17 / d^5 ~ 7e5 relative): 2^-11 ~ 5e-4 in double (tolerance <~ 1e-9 of
 * max |K|), 2^-7 ~ 8e-3 in float, where 1.5 * 256 eps / 2^-7 ~ 6e-3 is what float can
 * resolve: there the check confirms the tangent's structure and every term to ~2%, not its
 * last digits.
 * TG_FD_CAP: the FD check must mean something, so its tolerance relative to max |K| may not
 * exceed this (observed: 8e-10 double, 2e-2 float). */
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define TG_FD_REL EDMI_R(0.00048828125) /* 2^-11 */
#define TG_FD_CAP EDMI_R(1e-7)
#else
#define TG_FD_REL EDMI_R(0.0078125) /* 2^-7 */
#define TG_FD_CAP EDMI_R(5e-2)
#endif

/* Newton iteration bound on the paper's problems (dt = 1e-2, 1e-3 neo-Hooke; 1e-3 LJ).
 * The first scaled correction is c_1 <~ r_0 <= 1 (S_p contains |R_p(pred)|, and
 * |R_q(pred)| = dt/m |p_n| <= S_q). In Newton's quadratic regime c_{l+1} <= C c_l^2 with
 * C <~ 0.2 here (measured below at 10-50x these steps: 0.11-0.16), so c_2 <= 0.2,
 * c_3 <= 8e-3, c_4 <= 1.3e-5, c_5 <= 3.3e-11, and the stop (predicted c_l^3 / c_l-1^2 <= eps)
 * holds at l = 5 in double (3.6e-32 / 1.7e-10 = 2e-22) and at l = 4 in float (2.2e-15 /
 * 6.4e-5 = 3.4e-11) at the latest. Measured: 2-3 corrections. */
#define TG_ITER_MAX 5

/* The accepted state is at Newton's round-off floor: one more Newton correction, computed
 * here (edmi_residual, edmi_tangent and the test's own elimination), moves the state by at
 * most this much in the scaled norm. Its size is the residual's noise mapped through the
 * Newton matrix: a few eps times the ratio of the magnitudes summed into the residual to
 * the scales (observed <= 3.2 eps over these scenes in double, <= 2.3 eps in float; 64 leaves
 * room for scenes whose residual sums larger magnitudes than it keeps). The LG quotient's
 * cancellation noise eps |V| / |d1 - d0| is exempt: its STALLED stop is checked instead. */
#define TG_NEXT_MAX (EDMI_R(64.0) * EDMI_EPS)

/* Quadratic convergence: with r_{l+1} = C r_l^2, log r_{l+1} / log r_l = 2 + log C / log r_l,
 * which tends to 2 as r_l -> 0. We assert >= 1.5 (|log C| <= |log r_l| / 2) on every pair
 * in the asymptotic regime (r_l <= 0.1; before it a long step may even raise the residual)
 * whose smaller residual is resolved: above 32x the residual at which the sequence ended
 * (the measured noise floor of that step), so noise moves log r_{l+1} by < 0.3, the order
 * by < 0.15. And the sequence must reach the floor. On the floor nothing is asserted.
 * Double resolves 2-3 such pairs per step, float one. */
#define TG_QUAD_ORDER EDMI_R(1.5)
#define TG_QUAD_REGIME EDMI_R(0.1)
#define TG_QUAD_ABOVE_FLOOR EDMI_R(32.0)
/* Resolved pairs required over the six sequences of suite_tangent (observed: 12 in double,
 * 4 in float); fewer would mean the assertion above had (almost) nothing to judge. */
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define TG_QUAD_MIN_PAIRS 10
#else
#define TG_QUAD_MIN_PAIRS 3
#endif

/* ------------------------------------------------------------------------------------------
 * Helpers (no libm)
 * ---------------------------------------------------------------------------------------- */

#define TG_C3(x) ((const edmi_real (*)[3])(x))
#define TG_NB 3 /* bodies in the largest scene */
#define TG_N (3 * TG_NB)

static edmi_real tg_abs(edmi_real x) { return x < EDMI_R(0.0) ? -x : x; }

static edmi_real tg_max(edmi_real a, edmi_real b) { return a > b ? a : b; }

static edmi_real tg_norm(const edmi_real v[3])
{
    return EDMI_SQRT(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* Natural logarithm for x > 0: x = m 2^e with m in [1/sqrt2, sqrt2), then
 * ln m = 2 atanh(s), s = (m-1)/(m+1), |s| < 0.172: 9 terms, truncation < 1e-15. */
static edmi_real tg_log(edmi_real x)
{
    static const edmi_real ln2 = EDMI_R(0.69314718055994530942);
    static const edmi_real sqrt2 = EDMI_R(1.41421356237309504880);
    edmi_real s, s2, term, sum;
    int e = 0, k;
    if (!(x > EDMI_R(0.0)))
        return EDMI_R(0.0);
    while (x >= sqrt2) {
        x /= EDMI_R(2.0);
        e++;
    }
    while (x < sqrt2 / EDMI_R(2.0)) {
        x *= EDMI_R(2.0);
        e--;
    }
    s = (x - EDMI_R(1.0)) / (x + EDMI_R(1.0));
    s2 = s * s;
    term = s;
    sum = EDMI_R(0.0);
    for (k = 1; k <= 17; k += 2) {
        sum += term / (edmi_real)k;
        term *= s2;
    }
    return EDMI_R(2.0) * sum + (edmi_real)e * ln2;
}

/* Static: systems and workspaces are tens of kB. */
static edmi_system tg_sys;
static edmi_system tg_old;
static edmi_workspace tg_work;

/* ------------------------------------------------------------------------------------------
 * Scenes: a system, its dt, and a trial end state away from the predictor
 * ---------------------------------------------------------------------------------------- */

enum { TG_NEO_ANCHOR = 0, TG_LJ_PAIR, TG_GRAVITY_PAIR, TG_QUARTIC_PAIR, TG_CHAIN, TG_NSCENES };

static const char *const tg_scene_name[TG_NSCENES] = {
    "neo-Hookean anchor", "LJ pair", "gravity pair", "quartic pair", "3-body chain"};

typedef struct tg_scene {
    edmi_real dt;
    int pairs_only;                /* no anchor links: linear momentum is conserved */
    edmi_real q1[TG_NB][3];        /* trial end state */
    edmi_real p1[TG_NB][3];
} tg_scene;

static int tg_body(edmi_real m, edmi_real x, edmi_real y, edmi_real z, edmi_real px,
                   edmi_real py, edmi_real pz)
{
    edmi_real q[3], p[3];
    q[0] = x, q[1] = y, q[2] = z;
    p[0] = px, p[1] = py, p[2] = pz;
    return edmi_add_body(&tg_sys, m, q, p, 0) == EDMI_OK;
}

/* What scene `which` needs of the build besides prm (EDMI_WITH_*): its links' potentials. */
static int tg_scene_in(int which, const edmi_params *prm)
{
    if (!th_has_params(prm))
        return 0;
    switch (which) {
    case TG_NEO_ANCHOR:
        return th_has_pot(EDMI_POT_NEO_HOOKE);
    case TG_LJ_PAIR:
        return th_has_pot(EDMI_POT_LJ);
    case TG_GRAVITY_PAIR:
        return th_has_pot(EDMI_POT_INVERSE);
    case TG_QUARTIC_PAIR:
        return th_has_pot(EDMI_POT_QUARTIC);
    case TG_CHAIN:
    default:
        return th_has_pot(EDMI_POT_LJ) && th_has_pot(EDMI_POT_NEO_HOOKE) &&
               th_has_pot(EDMI_POT_INVERSE) && th_has_pot(EDMI_POT_HARMONIC);
    }
}

/* Build scene `which` into tg_sys with parameters *prm, and its trial state: free flight
 * q0 + dt p0/m plus a displacement that changes every link length by 10-20% (so that LG's
 * quotient is well conditioned and no finite-difference stencil comes near d1 = d0), and
 * p1 = p0 + an arbitrary impulse. */
static int tg_build(int which, const edmi_params *prm, tg_scene *sc)
{
    static const edmi_real disp[TG_NSCENES][TG_NB][3] = {
        {{EDMI_R(0.25), EDMI_R(-0.15), EDMI_R(0.3)}},
        {{EDMI_R(0.02), EDMI_R(-0.08), EDMI_R(0.05)}, {EDMI_R(-0.03), EDMI_R(0.06), EDMI_R(0.01)}},
        {{EDMI_R(0.2), EDMI_R(-0.1), EDMI_R(0.05)}, {EDMI_R(-0.15), EDMI_R(0.1), EDMI_R(0.0)}},
        {{EDMI_R(-0.1), EDMI_R(0.05), EDMI_R(-0.1)}, {EDMI_R(0.1), EDMI_R(0.0), EDMI_R(0.1)}},
        {{EDMI_R(0.1), EDMI_R(0.05), EDMI_R(-0.05)},
         {EDMI_R(-0.1), EDMI_R(0.1), EDMI_R(0.05)},
         {EDMI_R(0.35), EDMI_R(-0.1), EDMI_R(0.1)}}};
    static const edmi_real kick[TG_NB][3] = {{EDMI_R(1.5), EDMI_R(-2.0), EDMI_R(0.7)},
                                             {EDMI_R(-0.4), EDMI_R(0.9), EDMI_R(0.3)},
                                             {EDMI_R(0.2), EDMI_R(0.1), EDMI_R(-0.6)}};
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential pot;
    int ok = edmi_init(&tg_sys, prm) == EDMI_OK, a, i;
    sc->pairs_only = 1;
    switch (which) {
    case TG_NEO_ANCHOR: /* the paper's section 3.5 problem */
        sc->dt = EDMI_R(1e-2);
        sc->pairs_only = 0;
        pot = edmi_pot_neo_hooke(EDMI_R(1000.0), EDMI_R(4.0));
        ok = ok && tg_body(EDMI_R(10.0), EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0), EDMI_R(-30.0),
                           EDMI_R(15.0), EDMI_R(45.0));
        ok = ok && edmi_add_anchor(&tg_sys, 0, origin, &pot, 0) == EDMI_OK;
        break;
    case TG_LJ_PAIR: /* the paper's section 4.3.1 problem */
        sc->dt = EDMI_R(1e-3);
        pot = edmi_pot_lj(EDMI_R(100.0), EDMI_R(1.0));
        ok = ok && tg_body(EDMI_R(1.0), EDMI_R(0.0), EDMI_R(-0.5612), EDMI_R(0.0), EDMI_R(5.0),
                           EDMI_R(0.0), EDMI_R(0.0));
        ok = ok && tg_body(EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.5612), EDMI_R(0.0), EDMI_R(10.0),
                           EDMI_R(0.0), EDMI_R(0.0));
        ok = ok && edmi_add_pair(&tg_sys, 0, 1, &pot, 0) == EDMI_OK;
        break;
    case TG_GRAVITY_PAIR:
        sc->dt = EDMI_R(0.05);
        pot = edmi_pot_inverse(EDMI_R(2.5));
        ok = ok && tg_body(EDMI_R(1.0), EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.2), EDMI_R(0.1),
                           EDMI_R(1.2), EDMI_R(0.0));
        ok = ok && tg_body(EDMI_R(0.5), EDMI_R(-0.5), EDMI_R(0.3), EDMI_R(0.0), EDMI_R(-0.1),
                           EDMI_R(-1.5), EDMI_R(0.2));
        ok = ok && edmi_add_pair(&tg_sys, 0, 1, &pot, 0) == EDMI_OK;
        break;
    case TG_QUARTIC_PAIR:
        sc->dt = EDMI_R(0.1);
        pot = edmi_pot_quartic(EDMI_R(2.0), EDMI_R(1.0));
        ok = ok && tg_body(EDMI_R(1.5), EDMI_R(0.3), EDMI_R(0.2), EDMI_R(-0.1), EDMI_R(0.3),
                           EDMI_R(-0.2), EDMI_R(0.1));
        ok = ok && tg_body(EDMI_R(2.0), EDMI_R(1.4), EDMI_R(-0.3), EDMI_R(0.5), EDMI_R(-0.2),
                           EDMI_R(0.4), EDMI_R(0.0));
        ok = ok && edmi_add_pair(&tg_sys, 0, 1, &pot, 0) == EDMI_OK;
        break;
    case TG_CHAIN:
    default:
        sc->dt = EDMI_R(1e-2);
        sc->pairs_only = 0;
        ok = ok && tg_body(EDMI_R(1.0), EDMI_R(0.9), EDMI_R(0.1), EDMI_R(0.0), EDMI_R(0.5),
                           EDMI_R(-0.3), EDMI_R(0.2));
        ok = ok && tg_body(EDMI_R(2.0), EDMI_R(2.0), EDMI_R(0.2), EDMI_R(0.1), EDMI_R(-0.4),
                           EDMI_R(0.6), EDMI_R(0.0));
        ok = ok && tg_body(EDMI_R(0.5), EDMI_R(3.4), EDMI_R(-0.1), EDMI_R(0.3), EDMI_R(0.1),
                           EDMI_R(0.2), EDMI_R(-0.3));
        pot = edmi_pot_lj(EDMI_R(1.0), EDMI_R(1.0));
        ok = ok && edmi_add_pair(&tg_sys, 0, 1, &pot, 0) == EDMI_OK;
        pot = edmi_pot_neo_hooke(EDMI_R(50.0), EDMI_R(1.5));
        ok = ok && edmi_add_pair(&tg_sys, 1, 2, &pot, 0) == EDMI_OK;
        pot = edmi_pot_inverse(EDMI_R(-0.5)); /* Coulomb repulsion between the ends */
        ok = ok && edmi_add_pair(&tg_sys, 2, 0, &pot, 0) == EDMI_OK;
        pot = edmi_pot_harmonic(EDMI_R(20.0), EDMI_R(0.8));
        ok = ok && edmi_add_anchor(&tg_sys, 0, origin, &pot, 0) == EDMI_OK;
        break;
    }
    for (a = 0; a < tg_sys.n_bodies; a++)
        for (i = 0; i < 3; i++) {
            const edmi_body *b = &tg_sys.body[a];
            sc->q1[a][i] = b->q[i] + sc->dt * b->p[i] / b->m + disp[which][a][i];
            sc->p1[a][i] = b->p[i] + kick[a][i];
        }
    return ok;
}

/* ------------------------------------------------------------------------------------------
 * Scheme configurations
 * ---------------------------------------------------------------------------------------- */

#define TG_NCONF 11

static const char *const tg_conf_name[TG_NCONF] = {
    "MP", "LG closed", "LG quotient", "LG alt Janz", "LG alt Gonzalez", "LG alt GE",
    "LG alt PM", "LG alt PT", "GE", "PM", "PT"};

/* Configuration c; *forced = 1 when every link must be on LG's alternate. */
static edmi_params tg_conf(int c, int *forced)
{
    static const edmi_lg_alt alts[5] = {EDMI_LG_ALT_JANZ, EDMI_LG_ALT_GONZALEZ, EDMI_LG_ALT_GE,
                                        EDMI_LG_ALT_PM, EDMI_LG_ALT_PT};
    edmi_params p = edmi_default_params();
    *forced = 0;
    p.guard = EDMI_GUARD_OFF; /* Newton's own iterate: the guard has its suite (test_guard.c) */
    if (c == 0) {
        p.scheme = EDMI_SCHEME_MP;
    } else if (c == 1) {
        p.scheme = EDMI_SCHEME_LG;
        p.lg_form = EDMI_LG_CLOSED;
    } else if (c == 2) {
        p.scheme = EDMI_SCHEME_LG;
        p.lg_form = EDMI_LG_QUOTIENT; /* default tol_q << every |d1 - d0| here */
    } else if (c <= 7) {
        p.scheme = EDMI_SCHEME_LG;
        p.lg_form = EDMI_LG_QUOTIENT;
        p.lg_alt = alts[c - 3];
        p.tol_q = EDMI_R(1e3); /* larger than any |d1 - d0|: the alternate everywhere */
        *forced = 1;
    } else {
        p.scheme = c == 8 ? EDMI_SCHEME_GE : c == 9 ? EDMI_SCHEME_PM : EDMI_SCHEME_PT;
    }
    return p;
}

/* ------------------------------------------------------------------------------------------
 * The step equations, written out from the paper
 * ---------------------------------------------------------------------------------------- */

/* Lambda (or, for MP, beta) of one link from potential values; 0 on failure. */
static int tg_link_beta(const edmi_params *prm, const edmi_potential *pot, edmi_real d0,
                        edmi_real d1, edmi_real dm, edmi_real *beta)
{
    edmi_pot_parts a, b, avg;
    edmi_real lam, dd, junk, dl = d1 - d0, da = (d0 + d1) / EDMI_R(2.0);
    if (prm->scheme == EDMI_SCHEME_MP) {
        if (edmi_pot_eval(pot, dm, &a) != EDMI_OK)
            return 0;
        *beta = a.v[1] / dm; /* V' at the distance between the mid-points */
        return 1;
    }
    if (edmi_pot_eval(pot, d0, &a) != EDMI_OK || edmi_pot_eval(pot, d1, &b) != EDMI_OK ||
        edmi_pot_eval(pot, da, &avg) != EDMI_OK)
        return 0;
    switch (prm->scheme) {
    case EDMI_SCHEME_LG:
        if (prm->lg_form == EDMI_LG_CLOSED) {
            if (edmi_pot_divdiff(pot, d0, d1, &dd, &junk) != EDMI_OK)
                return 0;
            lam = dd;
        } else if (tg_abs(dl) > prm->tol_q) {
            lam = (b.v[0] - a.v[0]) / dl;
        } else {
            switch (prm->lg_alt) {
            case EDMI_LG_ALT_GONZALEZ:
                lam = avg.v[1] + dl * dl / EDMI_R(24.0) * avg.v[3];
                break;
            case EDMI_LG_ALT_GE:
                lam = b.c[1] + a.e[1];
                break;
            case EDMI_LG_ALT_PM:
                lam = avg.v[1] + dl * dl / EDMI_R(24.0) * (b.sp[3] + a.sm[3]);
                break;
            case EDMI_LG_ALT_PT:
                lam = (b.v[1] + a.v[1]) / EDMI_R(2.0) -
                      dl * dl / EDMI_R(12.0) * (a.sp[3] + b.sm[3]);
                break;
            case EDMI_LG_ALT_JANZ:
            default:
                lam = avg.v[1];
                break;
            }
        }
        break;
    case EDMI_SCHEME_GE:
        lam = b.c[1] + a.e[1];
        break;
    case EDMI_SCHEME_PM:
        lam = avg.v[1] + dl * dl / EDMI_R(24.0) * (b.sp[3] + a.sm[3]);
        break;
    case EDMI_SCHEME_PT:
    default:
        lam = (b.v[1] + a.v[1]) / EDMI_R(2.0) - dl * dl / EDMI_R(12.0) * (a.sp[3] + b.sm[3]);
        break;
    }
    *beta = EDMI_R(2.0) * lam / (d0 + d1);
    return 1;
}

/* R_q, R_p of sys's scheme at (q1, p1); the magnitude scale of R_q; and the round-off bound
 * of one R_p entry, max over bodies of TG_U_SUM (|p1 - p0| + F) + TG_U_RP F with F the sum
 * of |f| over the body's links. Returns 0 if a potential evaluation failed. */
static int tg_expected(const edmi_system *sys, edmi_real dt, const edmi_real (*q1)[3],
                       const edmi_real (*p1)[3], edmi_real (*rq)[3], edmi_real (*rp)[3],
                       edmi_real *rp_err, edmi_real *rq_scale)
{
    edmi_real mag[TG_NB], dpm[TG_NB];
    int a, i, j;
    *rq_scale = EDMI_R(0.0);
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *b = &sys->body[a];
        for (i = 0; i < 3; i++) {
            rq[a][i] = q1[a][i] - b->q[i] - dt / b->m * (b->p[i] + p1[a][i]) / EDMI_R(2.0);
            rp[a][i] = p1[a][i] - b->p[i];
            *rq_scale = tg_max(*rq_scale, tg_abs(q1[a][i]) + tg_abs(b->q[i]) +
                                              dt / b->m * (tg_abs(b->p[i]) + tg_abs(p1[a][i])));
        }
        dpm[a] = tg_norm(rp[a]);
        mag[a] = EDMI_R(0.0);
    }
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        const edmi_real *b0 = lk->b == EDMI_ANCHOR ? lk->anchor : sys->body[lk->b].q;
        const edmi_real *b1 = lk->b == EDMI_ANCHOR ? lk->anchor : q1[lk->b];
        edmi_real rn[3], r1[3], rm[3], beta, f;
        for (i = 0; i < 3; i++) {
            rn[i] = sys->body[lk->a].q[i] - b0[i];
            r1[i] = q1[lk->a][i] - b1[i];
            rm[i] = (rn[i] + r1[i]) / EDMI_R(2.0);
        }
        if (!tg_link_beta(&sys->params, &lk->pot, tg_norm(rn), tg_norm(r1), tg_norm(rm), &beta))
            return 0;
        for (i = 0; i < 3; i++) {
            f = dt * beta * rm[i];
            rp[lk->a][i] += f;
            if (lk->b != EDMI_ANCHOR)
                rp[lk->b][i] -= f;
        }
        f = tg_abs(dt * beta) * tg_norm(rm);
        mag[lk->a] += f;
        if (lk->b != EDMI_ANCHOR)
            mag[lk->b] += f;
    }
    *rp_err = EDMI_R(0.0);
    for (a = 0; a < sys->n_bodies; a++)
        *rp_err = tg_max(*rp_err, TG_U_SUM * (dpm[a] + mag[a]) + TG_U_RP * mag[a]);
    return 1;
}

/* ------------------------------------------------------------------------------------------
 * (1)-(3): residual and tangent at the trial state
 * ---------------------------------------------------------------------------------------- */

/* R_p of tg_sys at q1 with coordinate k moved by s; 0 on failure. */
static int tg_rp_at(const tg_scene *sc, edmi_real (*q1)[3], int k, edmi_real s,
                    edmi_real (*rp)[3])
{
    edmi_real rq[TG_NB][3], save = q1[k / 3][k % 3];
    edmi_status st;
    q1[k / 3][k % 3] = save + s;
    st = edmi_residual(&tg_sys, &tg_work, sc->dt, TG_C3(q1), TG_C3(sc->p1), rq, rp, 0);
    q1[k / 3][k % 3] = save;
    return st == EDMI_OK;
}

static edmi_real tg_fd4(edmi_real fm2, edmi_real fm1, edmi_real fp1, edmi_real fp2, edmi_real h)
{
    return ((fm2 - fp2) + EDMI_R(8.0) * (fp1 - fm1)) / (EDMI_R(12.0) * h);
}

static edmi_real tg_worst_fd; /* largest FD tolerance / max|K| seen, for the log */

/* Each column k of kmat (n x n, max |entry| kscale) against the 4th-order stencil of R_p in
 * q1's coordinate k with step h, its truncation estimated by Richardson (2h against h) and
 * its round-off bounded by eround. *worst: the largest tolerance / kscale. 0 on a failure. */
static int tg_fd_columns(const tg_scene *sc, int n, const edmi_real *kmat, edmi_real kscale,
                         edmi_real h, edmi_real eround, edmi_real *worst)
{
    static const edmi_real s[6] = {EDMI_R(-4.0), EDMI_R(-2.0), EDMI_R(-1.0),
                                   EDMI_R(1.0),  EDMI_R(2.0),  EDMI_R(4.0)};
    edmi_real q1[TG_NB][3], f[6][TG_NB][3]; /* R_p at -4h, -2h, -h, +h, +2h, +4h */
    int i, k, ok = 1;
    memcpy(q1, sc->q1, sizeof q1);
    for (k = 0; k < n && ok; k++) {
        for (i = 0; i < 6 && ok; i++)
            ok = tg_rp_at(sc, q1, k, s[i] * h, f[i]);
        if (!CHECK(ok))
            break;
        for (i = 0; i < n; i++) {
            int ba = i / 3, c = i % 3;
            edmi_real d1h = tg_fd4(f[1][ba][c], f[2][ba][c], f[3][ba][c], f[4][ba][c], h);
            edmi_real d2h = tg_fd4(f[0][ba][c], f[1][ba][c], f[4][ba][c], f[5][ba][c],
                                   EDMI_R(2.0) * h);
            edmi_real tol = EDMI_R(2.0) * tg_abs(d2h - d1h) / EDMI_R(15.0) + eround +
                            TG_U_K * kscale;
            CHECK_NEAR(kmat[i * n + k], d1h, tol, EDMI_R(0.0));
            /* a tolerance that large would make the comparison meaningless */
            if (!CHECK(tol <= TG_FD_CAP * kscale)) {
                th_note_real("FD tolerance / max|K|", tol / kscale);
                ok = 0;
                break;
            }
            *worst = tg_max(*worst, tol / kscale);
        }
    }
    return ok;
}

/* After failures, say which scene and scheme they came from. */
static void tg_where(int failed_before, int which, int conf)
{
    if (th_failed() > failed_before) {
        th_puts("    (in scene ");
        th_puts(tg_scene_name[which]);
        th_puts(", scheme ");
        th_puts(tg_conf_name[conf]);
        th_puts(")");
        th_newline();
    }
}

static void tg_check_trial(int which, int conf)
{
    tg_scene sc;
    int forced, nsw = -1, a, i, j, n, f0;
    edmi_params prm = tg_conf(conf, &forced);
    edmi_real rq[TG_NB][3], rp[TG_NB][3], xq[TG_NB][3], xp[TG_NB][3];
    edmi_real kmat[TG_N * TG_N];
    edmi_real rp_err = EDMI_R(0.0), rq_scale = EDMI_R(0.0), dmin, h, kscale, eround;

    if (th_skip(tg_scene_in(which, &prm), ts_label(tg_scene_name[which], tg_conf_name[conf])) ||
        !CHECK(tg_build(which, &prm, &sc)))
        return;
    f0 = th_failed();
    n = 3 * tg_sys.n_bodies;
    if (!CHECK_STATUS(edmi_residual(&tg_sys, &tg_work, sc.dt, TG_C3(sc.q1), TG_C3(sc.p1), rq, rp,
                                    &nsw),
                      EDMI_OK) ||
        !CHECK(tg_expected(&tg_sys, sc.dt, TG_C3(sc.q1), TG_C3(sc.p1), xq, xp, &rp_err,
                           &rq_scale)))
        return;

    /* (1) the step equations */
    for (a = 0; a < tg_sys.n_bodies; a++)
        for (i = 0; i < 3; i++) {
            CHECK_NEAR(rq[a][i], xq[a][i], TG_U_RQ * rq_scale, EDMI_R(0.0));
            CHECK_NEAR(rp[a][i], xp[a][i], EDMI_R(2.0) * rp_err, EDMI_R(0.0)); /* two sides */
        }
    /* LG quotient: on the alternate exactly when forced (trial |d1 - d0| >> default tol_q). */
    if (prm.scheme == EDMI_SCHEME_LG && prm.lg_form == EDMI_LG_QUOTIENT)
        CHECK(nsw == (forced ? tg_sys.n_links : 0));
    else
        CHECK(nsw == 0);

    /* (2) pair impulses cancel: sum_A R_p^A - (p1^A - p0^A) = 0 up to the rounding of each
     * R_p^A (and of p1 - p0 here), 4 eps of their magnitudes. */
    if (sc.pairs_only)
        for (i = 0; i < 3; i++) {
            edmi_real s = EDMI_R(0.0), mag = EDMI_R(0.0);
            for (a = 0; a < tg_sys.n_bodies; a++) {
                edmi_real dp = sc.p1[a][i] - tg_sys.body[a].p[i];
                s += rp[a][i] - dp;
                mag += tg_abs(rp[a][i]) + tg_abs(dp);
            }
            CHECK_NEAR(s, EDMI_R(0.0), EDMI_R(4.0) * EDMI_EPS * mag, EDMI_R(0.0));
        }

    /* (3) tangent against finite differences */
    if (!CHECK_STATUS(edmi_tangent(&tg_sys, &tg_work, sc.dt, TG_C3(sc.q1), TG_C3(sc.p1), kmat),
                      EDMI_OK))
        return;
    dmin = EDMI_REAL_MAX;
    for (j = 0; j < tg_sys.n_links; j++) {
        const edmi_link *lk = &tg_sys.link[j];
        edmi_real r[3];
        for (i = 0; i < 3; i++)
            r[i] = sc.q1[lk->a][i] - (lk->b == EDMI_ANCHOR ? lk->anchor[i] : sc.q1[lk->b][i]);
        dmin = tg_norm(r) < dmin ? tg_norm(r) : dmin;
    }
    h = dmin * TG_FD_REL;
    kscale = EDMI_R(0.0);
    for (i = 0; i < n * n; i++)
        kscale = tg_max(kscale, tg_abs(kmat[i]));
    /* Round-off of D(h): (1 + 8 + 8 + 1)/12 times the error of one R_p entry, over h. */
    eround = EDMI_R(1.5) * rp_err / h;
    tg_fd_columns(&sc, n, kmat, kscale, h, eround, &tg_worst_fd);
    tg_where(f0, which, conf);
}

/* ------------------------------------------------------------------------------------------
 * (4): a converged step satisfies the step equations to its stopping test
 * ---------------------------------------------------------------------------------------- */

/* The documented scaled residual of (rq, rp) with the scales of the old state and the
 * predictor residual rp0: S_p = |p_n| + |R_p(pred)|, S_q = |q_n| + dt/m S_p (1 if 0). */
static edmi_real tg_scaled(const edmi_system *old, edmi_real dt, edmi_real (*rq)[3],
                           edmi_real (*rp)[3], edmi_real (*rp0)[3])
{
    edmi_real r = EDMI_R(0.0);
    int a;
    for (a = 0; a < old->n_bodies; a++) {
        const edmi_body *b = &old->body[a];
        edmi_real sp = tg_norm(b->p) + tg_norm(rp0[a]);
        edmi_real sq = tg_norm(b->q) + dt / b->m * sp;
        if (sp == EDMI_R(0.0))
            sp = EDMI_R(1.0);
        if (sq == EDMI_R(0.0))
            sq = EDMI_R(1.0);
        r = tg_max(r, tg_norm(rq[a]) / sq);
        r = tg_max(r, tg_norm(rp[a]) / sp);
    }
    return r;
}

static edmi_real tg_worst_next; /* largest next correction / eps seen (not LG quotient) */

static int tg_stops[5]; /* stop reasons of the checked steps, for the log */

/* A stalled residual may exceed the previous one by round-off noise: at most this factor
 * times the sqrt(eps) r0 threshold of the header's stagnation clause. */
#define TG_STALL_GROWTH EDMI_R(4.0)

/* Two evaluations of the same norms in another order: a few eps relative. */
#define TG_U_SCALED (EDMI_R(8.0) * EDMI_EPS)

/* Solve A x = b (n x n, row-major, overwritten) by Gaussian elimination with partial
 * pivoting: the test's own solver, independent of the library's banded one. */
static int tg_solve(edmi_real *a, edmi_real *b, int n)
{
    int i, j, k;
    for (k = 0; k < n; k++) {
        int p = k;
        for (i = k + 1; i < n; i++)
            if (tg_abs(a[i * n + k]) > tg_abs(a[p * n + k]))
                p = i;
        if (a[p * n + k] == EDMI_R(0.0))
            return 0;
        for (j = 0; j < n; j++) {
            edmi_real x = a[k * n + j];
            a[k * n + j] = a[p * n + j];
            a[p * n + j] = x;
        }
        {
            edmi_real x = b[k];
            b[k] = b[p];
            b[p] = x;
        }
        for (i = k + 1; i < n; i++) {
            edmi_real f = a[i * n + k] / a[k * n + k];
            for (j = k; j < n; j++)
                a[i * n + j] -= f * a[k * n + j];
            b[i] -= f * b[k];
        }
    }
    for (i = n - 1; i >= 0; i--) {
        for (j = i + 1; j < n; j++)
            b[i] -= a[i * n + j] * b[j];
        b[i] /= a[i * n + i];
    }
    return 1;
}

/* The scaled size of one more Newton correction from the end state (q1, p1) of a step from
 * tg_old: with R_q = q1 - q0 - h (p0 + p1), R_p = p1 - p0 + F(q1), h = dt/(2m) and K =
 * dR_p/dq1, Newton's (dq, dp) satisfies dq = -R_q + h dp and (I + K h) dp = -R_p + K R_q. */
static edmi_real tg_next_correction(edmi_real dt, edmi_real (*q1)[3], edmi_real (*p1)[3],
                                    edmi_real (*rq)[3], edmi_real (*rp)[3], edmi_real (*rp0)[3])
{
    static edmi_real k[TG_N * TG_N], a[TG_N * TG_N];
    edmi_real b[TG_N], dq[TG_N], c = EDMI_R(0.0);
    int nb = tg_old.n_bodies, n = 3 * nb, i, j;
    if (!CHECK_STATUS(edmi_tangent(&tg_old, &tg_work, dt, TG_C3(q1), TG_C3(p1), k), EDMI_OK))
        return EDMI_REAL_MAX;
    for (i = 0; i < n; i++) {
        b[i] = -rp[i / 3][i % 3];
        for (j = 0; j < n; j++) {
            edmi_real h = dt / (EDMI_R(2.0) * tg_old.body[j / 3].m);
            a[i * n + j] = (i == j ? EDMI_R(1.0) : EDMI_R(0.0)) + k[i * n + j] * h;
            b[i] += k[i * n + j] * rq[j / 3][j % 3];
        }
    }
    if (!CHECK(tg_solve(a, b, n)))
        return EDMI_REAL_MAX;
    for (i = 0; i < n; i++)
        dq[i] = -rq[i / 3][i % 3] + dt / (EDMI_R(2.0) * tg_old.body[i / 3].m) * b[i];
    for (i = 0; i < nb; i++) {
        const edmi_body *bd = &tg_old.body[i];
        edmi_real sp = tg_norm(bd->p) + tg_norm(rp0[i]);
        edmi_real sq = tg_norm(bd->q) + dt / bd->m * sp;
        if (sp == EDMI_R(0.0))
            sp = EDMI_R(1.0);
        if (sq == EDMI_R(0.0))
            sq = EDMI_R(1.0);
        c = tg_max(c, tg_norm(dq + 3 * i) / sq);
        c = tg_max(c, tg_norm(b + 3 * i) / sp);
    }
    return c;
}

/* Checks one successful step of tg_old -> tg_sys against the stopping test. */
static void tg_check_converged(edmi_real dt, const edmi_step_result *res)
{
    edmi_real q0[TG_NB][3], p0[TG_NB][3], q1[TG_NB][3], p1[TG_NB][3];
    edmi_real rq[TG_NB][3], rp[TG_NB][3], rq0[TG_NB][3], rp0[TG_NB][3];
    edmi_real r, r0, bound = EDMI_R(0.0), next;
    const edmi_params *prm = &tg_old.params;
    int a, i, quotient = prm->scheme == EDMI_SCHEME_LG && prm->lg_form == EDMI_LG_QUOTIENT;
    for (a = 0; a < tg_old.n_bodies; a++)
        for (i = 0; i < 3; i++) {
            q0[a][i] = tg_old.body[a].q[i];
            p0[a][i] = tg_old.body[a].p[i];
            q1[a][i] = tg_sys.body[a].q[i];
            p1[a][i] = tg_sys.body[a].p[i];
        }
    if (!CHECK_STATUS(edmi_residual(&tg_old, &tg_work, dt, TG_C3(q0), TG_C3(p0), rq0, rp0, 0),
                      EDMI_OK) ||
        !CHECK_STATUS(edmi_residual(&tg_old, &tg_work, dt, TG_C3(q1), TG_C3(p1), rq, rp, 0),
                      EDMI_OK))
        return;
    r0 = tg_scaled(&tg_old, dt, rq0, rp0, rp0);
    r = tg_scaled(&tg_old, dt, rq, rp, rp0);
    /* The library reports what we recompute (same residual function, same state). */
    CHECK_NEAR(res->residual0, r0, EDMI_R(0.0), TG_U_SCALED);
    CHECK_NEAR(res->residual, r, EDMI_R(0.0), TG_U_SCALED);
    /* ... and it meets the stopping test it claims (the header's edmi_stop). */
    CHECK(res->iterations >= 1 && res->iterations <= prm->l_max);
    next = tg_next_correction(dt, q1, p1, rq, rp, rp0);
    switch (res->stop) {
    case EDMI_STOP_CONVERGED:
        /* the independent check: one more Newton correction changes nothing that matters */
        CHECK(quotient || next <= TG_NEXT_MAX);
        break;
    case EDMI_STOP_TOL_R:
        bound = prm->tol_r * res->residual0;
        CHECK(prm->tol_r > EDMI_R(0.0) && res->residual <= bound);
        break;
    case EDMI_STOP_TOL_A:
        bound = prm->tol_a;
        CHECK(prm->tol_a > EDMI_R(0.0) && res->residual <= bound);
        break;
    case EDMI_STOP_STALLED:
        /* "previous residual <= sqrt(eps) x residual0, and it stopped halving": a residual
         * that has stalled at round-off stays within a small factor of the threshold */
        bound = TG_STALL_GROWTH * EDMI_SQRT(EDMI_EPS) * res->residual0;
        CHECK(res->residual <= bound);
        CHECK(r <= bound * (EDMI_R(1.0) + TG_U_SCALED));
        CHECK(quotient || next <= TG_NEXT_MAX);
        break;
    default:
        CHECK(0 && "unexpected stop reason");
    }
    tg_stops[(int)res->stop % 5]++; /* the enum may be 1 byte (arm -fshort-enums) */
    if (!quotient)
        tg_worst_next = tg_max(tg_worst_next, next / EDMI_EPS);
}

static void tg_check_step(int which, int conf)
{
    tg_scene sc;
    int forced, f0;
    edmi_params prm = tg_conf(conf, &forced);
    edmi_step_result res;
    if (forced)
        return; /* tol_q = 1e3 is a test device, not a way to step */
    if (th_skip(tg_scene_in(which, &prm), ts_label(tg_scene_name[which], tg_conf_name[conf])) ||
        !CHECK(tg_build(which, &prm, &sc)))
        return;
    f0 = th_failed();
    memcpy(&tg_old, &tg_sys, sizeof tg_sys);
    if (CHECK_STATUS(edmi_step(&tg_sys, &tg_work, sc.dt, &res), EDMI_OK))
        tg_check_converged(sc.dt, &res);
    tg_where(f0, which, conf);
}

/* ------------------------------------------------------------------------------------------
 * (5): Newton on the paper's problems: iteration counts and quadratic convergence
 * ---------------------------------------------------------------------------------------- */

static void tg_newton_counts(void)
{
    static const edmi_scheme schemes[5] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PM, EDMI_SCHEME_PT};
    static const char *const runs[3] = {"neo-Hooke dt=1e-2", "neo-Hooke dt=1e-3",
                                        "LJ pair dt=1e-3"};
    int hist[TG_ITER_MAX + 2];
    int run, s, n, i, failures = 0, worst = 0;
    for (run = 0; run < 3; run++) {
        for (i = 0; i < TG_ITER_MAX + 2; i++)
            hist[i] = 0;
        for (s = 0; s < 5; s++) {
            tg_scene sc;
            edmi_params prm = edmi_default_params();
            prm.scheme = schemes[s];
            prm.guard = EDMI_GUARD_OFF; /* Newton's iterate is what is checked */
            if (th_skip(tg_scene_in(run < 2 ? TG_NEO_ANCHOR : TG_LJ_PAIR, &prm),
                        ts_label(runs[run], ts_scheme_name(schemes[s]))) ||
                !CHECK(tg_build(run < 2 ? TG_NEO_ANCHOR : TG_LJ_PAIR, &prm, &sc)))
                continue;
            if (run == 1)
                sc.dt = EDMI_R(1e-3);
            for (n = 0; n < 100; n++) {
                edmi_step_result res;
                memcpy(&tg_old, &tg_sys, sizeof tg_sys);
                if (edmi_step(&tg_sys, &tg_work, sc.dt, &res) != EDMI_OK) {
                    failures++;
                    break;
                }
                hist[res.iterations <= TG_ITER_MAX ? res.iterations : TG_ITER_MAX + 1]++;
                worst = res.iterations > worst ? res.iterations : worst;
                if (n % 25 == 0)
                    tg_check_converged(sc.dt, &res);
            }
        }
        th_puts("  Newton iterations, ");
        th_puts(runs[run]);
        th_puts(" (5 schemes x 100 steps), count:steps");
        for (i = 0; i <= TG_ITER_MAX + 1; i++)
            if (hist[i] != 0) {
                th_putchar(' ');
                th_put_int(i);
                th_putchar(':');
                th_put_int(hist[i]);
            }
        th_newline();
    }
    CHECK(failures == 0);
    CHECK(worst <= TG_ITER_MAX);
}

/* Residuals r_l after l = 1, 2, ... corrections of one step, from fresh copies with
 * l_max = l: EDMI_ERR_NO_CONVERGENCE with res.residual filled, until Newton stops at its
 * floor (CONVERGED or STALLED). */
static const char *const tg_scheme_name[5] = {"MP", "LG", "GE", "PM", "PT"};

static int tg_quad_skipped; /* sequences this build cannot run (compiled out) */

static int tg_quadratic(int which, edmi_scheme scheme, edmi_real dt)
{
    edmi_real r[16];
    int l, nl = 0, pairs = 0;
    edmi_step_result res;
    tg_scene sc;
    edmi_params prm = edmi_default_params();
    prm.scheme = scheme;
    prm.guard = EDMI_GUARD_OFF;
    if (th_skip(tg_scene_in(which, &prm),
                ts_label(tg_scene_name[which], tg_scheme_name[scheme]))) {
        tg_quad_skipped++;
        return 0;
    }
    if (!CHECK(tg_build(which, &prm, &sc)))
        return 0;
    memcpy(&tg_old, &tg_sys, sizeof tg_sys);
    r[0] = EDMI_R(0.0);
    for (l = 1; l < 16; l++) {
        edmi_status st;
        memcpy(&tg_sys, &tg_old, sizeof tg_sys);
        tg_sys.params.l_max = l;
        st = edmi_step(&tg_sys, &tg_work, dt, &res);
        if (l == 1)
            r[0] = res.residual0;
        r[l] = res.residual;
        nl = l;
        if (st == EDMI_OK) {
            CHECK((res.stop == EDMI_STOP_CONVERGED || res.stop == EDMI_STOP_STALLED) &&
                  res.iterations == l);
            tg_check_converged(dt, &res);
            break;
        }
        if (!CHECK_STATUS(st, EDMI_ERR_NO_CONVERGENCE))
            return 0;
        CHECK(res.iterations == l);
    }
    th_puts("  quadratic convergence, ");
    th_puts(tg_scene_name[which]);
    th_puts(", ");
    th_puts(tg_scheme_name[scheme]);
    th_puts(", dt ");
    th_put_real(dt, 2);
    th_puts(": r_l =");
    for (l = 0; l <= nl; l++) {
        th_putchar(' ');
        th_put_real(r[l], 3);
    }
    th_newline();
    CHECK(nl < 16 - 1); /* reached the floor */
    for (l = 1; l < nl; l++) {
        /* both residuals resolved: above the final one by TG_QUAD_ABOVE_FLOOR, below 1 */
        if (r[l + 1] > TG_QUAD_ABOVE_FLOOR * r[nl] && r[l] <= TG_QUAD_REGIME) {
            edmi_real order = tg_log(r[l + 1]) / tg_log(r[l]);
            pairs++;
            if (!CHECK(order >= TG_QUAD_ORDER))
                th_note_real("observed order", order);
        }
    }
    return pairs;
}

/* ------------------------------------------------------------------------------------------
 * (6): dampers
 * ---------------------------------------------------------------------------------------- */

/* An anchor link and a pair link with a damper, in general 3-D position, and a body on one
 * axis whose trial state has crossed its anchor with |dr| = 78 |r_m|: there an error in the
 * damper's tangent proportional to c |dr| / |r_m| (the one this case was written for) is 78
 * times the damper's own stiffness c. */
enum { TG_DAMP_ANCHOR = 0, TG_DAMP_PAIR, TG_DAMP_AXIS, TG_NDAMP };

static const char *const tg_damp_name[TG_NDAMP] = {"anchor link + damper",
                                                   "pair link + damper",
                                                   "one axis, crossing the anchor"};

/* What damper scene `which` needs of the build: PM, dampers, its link's potential. */
static int tg_damp_in(int which)
{
    return th_has_scheme(EDMI_SCHEME_PM) && EDMI_MAX_DAMPERS > 0 &&
           th_has_pot(which == TG_DAMP_PAIR ? EDMI_POT_NEO_HOOKE : EDMI_POT_HARMONIC);
}

static int tg_damp_build(int which, tg_scene *sc, edmi_real *c)
{
    static const edmi_real disp[TG_NDAMP][2][3] = {
        {{EDMI_R(-0.004), EDMI_R(0.003), EDMI_R(0.001)}},
        {{EDMI_R(0.05), EDMI_R(-0.02), EDMI_R(0.03)}, {EDMI_R(-0.04), EDMI_R(0.03), EDMI_R(0.01)}},
        {{EDMI_R(0.0001), EDMI_R(0.0), EDMI_R(0.0)}}};
    static const edmi_real kick[TG_NDAMP][2][3] = {
        {{EDMI_R(0.01), EDMI_R(-0.005), EDMI_R(0.002)}},
        {{EDMI_R(0.2), EDMI_R(-0.1), EDMI_R(0.05)}, {EDMI_R(-0.1), EDMI_R(0.15), EDMI_R(0.0)}},
        {{EDMI_R(0.01), EDMI_R(0.0), EDMI_R(0.0)}}};
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_params prm = edmi_default_params();
    edmi_potential pot = edmi_pot_harmonic(EDMI_R(3000.0), EDMI_R(0.0));
    int ok, a, i;
    prm.scheme = EDMI_SCHEME_PM;
    prm.guard = EDMI_GUARD_OFF;
    ok = edmi_init(&tg_sys, &prm) == EDMI_OK;
    sc->dt = EDMI_R(1e-3);
    sc->pairs_only = which == TG_DAMP_PAIR;
    switch (which) {
    case TG_DAMP_ANCHOR:
        *c = EDMI_R(2.0);
        ok = ok && tg_body(EDMI_R(0.1), EDMI_R(0.01), EDMI_R(0.004), EDMI_R(-0.002),
                           EDMI_R(0.05), EDMI_R(-0.02), EDMI_R(0.01));
        ok = ok && edmi_add_anchor(&tg_sys, 0, origin, &pot, 0) == EDMI_OK;
        break;
    case TG_DAMP_PAIR:
        *c = EDMI_R(3.0);
        sc->dt = EDMI_R(1e-2);
        pot = edmi_pot_neo_hooke(EDMI_R(50.0), EDMI_R(1.0));
        ok = ok && tg_body(EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.1),
                           EDMI_R(0.2), EDMI_R(0.0));
        ok = ok && tg_body(EDMI_R(2.0), EDMI_R(1.2), EDMI_R(0.1), EDMI_R(-0.1), EDMI_R(-0.1),
                           EDMI_R(0.0), EDMI_R(0.3));
        ok = ok && edmi_add_pair(&tg_sys, 0, 1, &pot, 0) == EDMI_OK;
        break;
    case TG_DAMP_AXIS:
    default: /* q1 = 0.002 - 0.004 + 0.0001: r_m = 0.00005, dr = -0.0039 */
        *c = EDMI_R(2.0);
        ok = ok && tg_body(EDMI_R(0.1), EDMI_R(0.002), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-0.4),
                           EDMI_R(0.0), EDMI_R(0.0));
        ok = ok && edmi_add_anchor(&tg_sys, 0, origin, &pot, 0) == EDMI_OK;
        break;
    }
    ok = ok && edmi_add_damper(&tg_sys, 0, *c, 0) == EDMI_OK;
    for (a = 0; a < tg_sys.n_bodies; a++)
        for (i = 0; i < 3; i++) {
            const edmi_body *b = &tg_sys.body[a];
            sc->q1[a][i] = b->q[i] + sc->dt * b->p[i] / b->m + disp[which][a][i];
            sc->p1[a][i] = b->p[i] + kick[which][a][i];
        }
    return ok;
}

/* edmi_tangent against the 4th-order stencil of (3), with its Richardson estimate of the
 * truncation. The damper's impulse is smooth on the scale |r_m| (its direction r_m/|r_m|),
 * so the step is TG_FD_REL times the smaller of |r_m| and |r_n+1|. The round-off of one R_p
 * entry is bounded by (TG_U_SUM + TG_U_RP) times the magnitudes summed into it: |p1 - p0|,
 * the link impulse dt |V'(|r_m|)| (a bound within a factor 2 for the trial states here) and
 * the damper impulse c |dr|. */
static void tg_damp_check(int which)
{
    tg_scene sc;
    edmi_real kmat[TG_N * TG_N];
    edmi_real c = EDMI_R(0.0), len = EDMI_REAL_MAX, mag = EDMI_R(0.0), h, kscale = EDMI_R(0.0);
    edmi_real eround, worst = EDMI_R(0.0);
    const edmi_link *lk = &tg_sys.link[0];
    edmi_real r0[3], r1[3], rm[3], dr[3];
    edmi_pot_parts pp;
    int n, i, a, f0 = th_failed();
    if (th_skip(tg_damp_in(which), tg_damp_name[which]) || !CHECK(tg_damp_build(which, &sc, &c)))
        return;
    n = 3 * tg_sys.n_bodies;
    for (i = 0; i < 3; i++) {
        const edmi_real *b0 = lk->b == EDMI_ANCHOR ? lk->anchor : tg_sys.body[lk->b].q;
        const edmi_real *b1 = lk->b == EDMI_ANCHOR ? lk->anchor : sc.q1[lk->b];
        r0[i] = tg_sys.body[lk->a].q[i] - b0[i];
        r1[i] = sc.q1[lk->a][i] - b1[i];
        rm[i] = (r0[i] + r1[i]) / EDMI_R(2.0);
        dr[i] = r1[i] - r0[i];
    }
    len = tg_norm(rm) < tg_norm(r1) ? tg_norm(rm) : tg_norm(r1);
    if (!CHECK_STATUS(edmi_pot_eval(&lk->pot, tg_norm(rm), &pp), EDMI_OK))
        return;
    for (a = 0; a < tg_sys.n_bodies; a++) {
        edmi_real dp[3];
        for (i = 0; i < 3; i++)
            dp[i] = sc.p1[a][i] - tg_sys.body[a].p[i];
        mag = tg_max(mag, tg_norm(dp));
    }
    mag += EDMI_R(2.0) * sc.dt * tg_abs(pp.v[1]) + c * tg_norm(dr);
    if (!CHECK_STATUS(edmi_tangent(&tg_sys, &tg_work, sc.dt, TG_C3(sc.q1), TG_C3(sc.p1), kmat),
                      EDMI_OK))
        return;
    for (i = 0; i < n * n; i++)
        kscale = tg_max(kscale, tg_abs(kmat[i]));
    h = len * TG_FD_REL;
    eround = EDMI_R(1.5) * (TG_U_SUM + TG_U_RP) * mag / h;
    tg_fd_columns(&sc, n, kmat, kscale, h, eround, &worst);
    th_puts("  damper tangent vs FD, ");
    th_puts(tg_damp_name[which]);
    th_puts(": FD tolerance / max|K| = ");
    th_put_real(worst, 2);
    th_newline();
    if (th_failed() > f0) {
        th_puts("    (in damper scene ");
        th_puts(tg_damp_name[which]);
        th_puts(")");
        th_newline();
    }
}

/* Newton on the coupling of examples/haptic.c (m 0.1, k 3000, c 0.5, dt 1e-3, PM, guard
 * and fallback at their defaults) while the tool crosses its anchor: at 0.5-8 m/s, from
 * d0 = 0.5 v dt (1 + e) with e = 0.3, 0.03, -0.045, the anchor moving 0.05 v dt the same
 * way, so that every step ends on the far side with |dr| / |r_m| from ~5 to ~200. Each step
 * must converge like the paper's problems (at most TG_ITER_MAX corrections) and stay on the
 * axis. The damper's old tangent (a factor 2 in d|r_m|^2) took up to l_max here, and 4 of
 * the example's 6000 ticks fell back. */
static void tg_damp_crossing(void)
{
    static const edmi_real speed[6] = {EDMI_R(0.5), EDMI_R(1.0), EDMI_R(2.0),
                                       EDMI_R(3.0), EDMI_R(5.0), EDMI_R(8.0)};
    static const edmi_real offset[3] = {EDMI_R(0.3), EDMI_R(0.03), EDMI_R(-0.045)};
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    const edmi_real dt = EDMI_R(1e-3);
    edmi_potential pot = edmi_pot_harmonic(EDMI_R(3000.0), EDMI_R(0.0));
    edmi_params prm = edmi_default_params();
    edmi_real ratio = EDMI_R(0.0);
    int v, e, worst = 0;
    prm.scheme = EDMI_SCHEME_PM;
    TH_NEEDS(tg_damp_in(TG_DAMP_AXIS));
    for (v = 0; v < 6; v++)
        for (e = 0; e < 3; e++) {
            edmi_step_result res;
            edmi_real q[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
            edmi_real p[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
            edmi_real hand[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
            edmi_real r0, r1;
            q[0] = EDMI_R(0.5) * speed[v] * dt * (EDMI_R(1.0) + offset[e]);
            p[0] = -EDMI_R(0.1) * speed[v];
            hand[0] = -EDMI_R(0.05) * speed[v] * dt;
            if (!CHECK_STATUS(edmi_init(&tg_sys, &prm), EDMI_OK) ||
                !CHECK_STATUS(edmi_add_body(&tg_sys, EDMI_R(0.1), q, p, 0), EDMI_OK) ||
                !CHECK_STATUS(edmi_add_anchor(&tg_sys, 0, origin, &pot, 0), EDMI_OK) ||
                !CHECK_STATUS(edmi_add_damper(&tg_sys, 0, EDMI_R(0.5), 0), EDMI_OK) ||
                !CHECK_STATUS(edmi_move_anchor(&tg_sys, 0, hand), EDMI_OK))
                return;
            if (!CHECK_STATUS(edmi_step(&tg_sys, &tg_work, dt, &res), EDMI_OK))
                continue;
            CHECK(res.stop == EDMI_STOP_CONVERGED || res.stop == EDMI_STOP_STALLED);
            CHECK(res.iterations <= TG_ITER_MAX);
            r0 = q[0];
            r1 = tg_sys.body[0].q[0] - hand[0];
            CHECK(r1 < EDMI_R(0.0)); /* it did cross */
            CHECK(tg_sys.body[0].q[1] == EDMI_R(0.0) && tg_sys.body[0].q[2] == EDMI_R(0.0));
            ratio = tg_max(ratio, tg_abs(r1 - r0) / tg_abs(EDMI_R(0.5) * (r0 + r1)));
            worst = res.iterations > worst ? res.iterations : worst;
        }
    th_note_real("coupling through its anchor at 0.5-8 m/s: largest |dr| / |r_m|", ratio);
    th_note_int("coupling through its anchor: most Newton corrections", worst);
}

void suite_tangent(void)
{
    int s, c, pairs;
    th_suite("tangent: residual, consistent tangent vs FD, Newton convergence");
    tg_worst_fd = EDMI_R(0.0);
    tg_worst_next = EDMI_R(0.0);
    tg_stops[0] = tg_stops[1] = tg_stops[2] = tg_stops[3] = tg_stops[4] = 0;
    tg_quad_skipped = 0;
    for (s = 0; s < TG_NSCENES; s++)
        for (c = 0; c < TG_NCONF; c++) {
            tg_check_trial(s, c);
            tg_check_step(s, c);
        }
    th_note_real("largest FD tolerance / max|K|", tg_worst_fd);
    tg_newton_counts();
    /* Steps 10x (neo-Hooke) and 50x (LJ) the paper's, so that Newton needs several
     * corrections and float still resolves one of them (see TG_QUAD_ABOVE_FLOOR). */
    pairs = tg_quadratic(TG_NEO_ANCHOR, EDMI_SCHEME_MP, EDMI_R(0.1));
    pairs += tg_quadratic(TG_NEO_ANCHOR, EDMI_SCHEME_LG, EDMI_R(0.1));
    pairs += tg_quadratic(TG_NEO_ANCHOR, EDMI_SCHEME_PM, EDMI_R(0.1));
    pairs += tg_quadratic(TG_LJ_PAIR, EDMI_SCHEME_GE, EDMI_R(0.05));
    pairs += tg_quadratic(TG_LJ_PAIR, EDMI_SCHEME_PT, EDMI_R(0.05));
    pairs += tg_quadratic(TG_CHAIN, EDMI_SCHEME_MP, EDMI_R(0.2));
    th_note_int("resolved pairs in the asymptotic regime", pairs);
    if (!th_skip(tg_quad_skipped == 0, "all six sequences (the pair count)"))
        CHECK(pairs >= TG_QUAD_MIN_PAIRS);
    th_note_real("largest next Newton correction / eps at accepted states (not LG quotient)",
                 tg_worst_next);
    th_note_int("checked steps stopped converged", tg_stops[EDMI_STOP_CONVERGED]);
    th_note_int("checked steps stopped stalled", tg_stops[EDMI_STOP_STALLED]);
    CHECK(tg_stops[EDMI_STOP_TOL_R] == 0 && tg_stops[EDMI_STOP_TOL_A] == 0); /* off by default */
    for (s = 0; s < TG_NDAMP; s++)
        tg_damp_check(s);
    tg_damp_crossing();
}
