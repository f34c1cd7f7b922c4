/*
 * edmi.c: energy-decaying, momentum-conserving integrators (see edmi.h).
 *
 * Follows the paper's order: potentials and their splits (section 3.1, 3.3) -> the five
 * algorithmic forces (section 4.1) -> the Newton predictor multi-corrector (section 3.4)
 * -> invariants (section 2, 4.1). Freestanding: includes only edmi.h (and <float.h>).
 */
#include "edmi.h"

/* ==========================================================================================
 * Small helpers
 * ======================================================================================== */

#define EDMI__ZERO EDMI_R(0.0)
#define EDMI__ONE EDMI_R(1.0)
#define EDMI__HALF EDMI_R(0.5)

/* At most this many halvings of a Newton correction that left the domain (down to 1/256). */
#define EDMI__MAX_HALVINGS 8

/* Newton accepts a residual within this factor of its estimated round-off floor. */
#define EDMI__FLOOR_FACTOR EDMI_R(8.0)

/* sqrt(eps): a residual reduced this far below the predictor's is in Newton's quadratic
 * regime, where (the tangent being exact) only round-off stops it from shrinking. */
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
#define EDMI__SQRT_EPS EDMI_R(1.4901161193847656e-8)
#else
#define EDMI__SQRT_EPS EDMI_R(3.4526698e-4)
#endif

static int edmi__finite(edmi_real x)
{
    /* x - x is 0 for finite x and NaN for inf/NaN (no fast-math: this is not folded). */
    return (x - x) == EDMI__ZERO;
}

static int edmi__finite3(const edmi_real v[3])
{
    return edmi__finite(v[0]) && edmi__finite(v[1]) && edmi__finite(v[2]);
}

static edmi_real edmi__abs(edmi_real x) { return x < EDMI__ZERO ? -x : x; }

static edmi_real edmi__max(edmi_real a, edmi_real b) { return a > b ? a : b; }

static edmi_real edmi__dot(const edmi_real a[3], const edmi_real b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static edmi_real edmi__norm(const edmi_real a[3]) { return EDMI_SQRT(edmi__dot(a, a)); }

static void edmi__sub(const edmi_real a[3], const edmi_real b[3], edmi_real out[3])
{
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

static void edmi__cross(const edmi_real a[3], const edmi_real b[3], edmi_real out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void edmi__copy3(const edmi_real a[3], edmi_real out[3])
{
    out[0] = a[0];
    out[1] = a[1];
    out[2] = a[2];
}

/* ==========================================================================================
 * Potentials, their convex/concave and super-convex/super-concave splits (eqs. convex-split,
 * super-convex-split), and closed-form divided differences [V(d1)-V(d0)]/(d1-d0).
 * Each fills derivatives 0..4; no pow(), no numeric differentiation.
 * ======================================================================================== */

static void edmi__zero5(edmi_real a[5])
{
    a[0] = a[1] = a[2] = a[3] = a[4] = EDMI__ZERO;
}

static void edmi__copy5(const edmi_real a[5], edmi_real out[5])
{
    int i;
    for (i = 0; i < 5; i++)
        out[i] = a[i];
}

/* V = k/2 (r - r0)^2: convex and super-convex (V'''' = 0), so V_c = V_+ = V. */
static void edmi__pot_harmonic(edmi_real k, edmi_real r0, edmi_real r, edmi_pot_parts *o)
{
    edmi_real x = r - r0;
    o->v[0] = EDMI__HALF * k * x * x;
    o->v[1] = k * x;
    o->v[2] = k;
    o->v[3] = EDMI__ZERO;
    o->v[4] = EDMI__ZERO;
    edmi__copy5(o->v, o->c);
    edmi__copy5(o->v, o->sp);
    edmi__zero5(o->e);
    edmi__zero5(o->sm);
}

/* V = k/4 (r^2 - L^2)^2 (Gonzalez's quartic spring). Not convex for r < L/sqrt(3):
 * V_c = k/4 (r^4 + L^4), V_e = -k L^2 r^2 / 2. V'''' = 6k >= 0, so V_+ = V. */
static void edmi__pot_quartic(edmi_real k, edmi_real len, edmi_real r, edmi_pot_parts *o)
{
    edmi_real l2 = len * len, r2 = r * r, u = r2 - l2;
    o->v[0] = EDMI_R(0.25) * k * u * u;
    o->v[1] = k * r * u;
    o->v[2] = k * (EDMI_R(3.0) * r2 - l2);
    o->v[3] = EDMI_R(6.0) * k * r;
    o->v[4] = EDMI_R(6.0) * k;
    o->c[0] = EDMI_R(0.25) * k * (r2 * r2 + l2 * l2);
    o->c[1] = k * r2 * r;
    o->c[2] = EDMI_R(3.0) * k * r2;
    o->c[3] = o->v[3];
    o->c[4] = o->v[4];
    o->e[0] = -EDMI__HALF * k * l2 * r2;
    o->e[1] = -k * l2 * r;
    o->e[2] = -k * l2;
    o->e[3] = EDMI__ZERO;
    o->e[4] = EDMI__ZERO;
    edmi__copy5(o->v, o->sp);
    edmi__zero5(o->sm);
}

/* The paper's neo-Hookean spring (section 3.4): V = c rb^2/6 ((r/rb)^2 + 2 rb/r - 3)
 * = c (r - rb)^2 (r + 2 rb) / (6 r), the factored form being exact near the rest length.
 * V'' = c/3 (1 + 2 rb^3/r^3) > 0 and V'''' = 8 c rb^3 / r^5 > 0: V_c = V_+ = V. */
static void edmi__pot_neo_hooke(edmi_real c, edmi_real rb, edmi_real r, edmi_pot_parts *o)
{
    edmi_real ir = EDMI__ONE / r, x = r - rb;
    edmi_real b3 = rb * rb * rb * ir * ir * ir; /* (rb/r)^3 */
    edmi_real third = c / EDMI_R(3.0);
    o->v[0] = third * EDMI__HALF * x * x * (r + EDMI_R(2.0) * rb) * ir;
    o->v[1] = third * x * (r * r + r * rb + rb * rb) * ir * ir;
    o->v[2] = third * (EDMI__ONE + EDMI_R(2.0) * b3);
    o->v[3] = -EDMI_R(2.0) * c * b3 * ir;
    o->v[4] = EDMI_R(8.0) * c * b3 * ir * ir;
    edmi__copy5(o->v, o->c);
    edmi__copy5(o->v, o->sp);
    edmi__zero5(o->e);
    edmi__zero5(o->sm);
}

/* Derivatives 0..4 of a * r^-n given t = a r^-n, ir = 1/r and the rising factorials of n. */
static void edmi__inv_pow_derivs(edmi_real t, edmi_real ir, edmi_real n1, edmi_real n2,
                                 edmi_real n3, edmi_real n4, edmi_real o[5])
{
    o[0] = t;
    o[1] = -n1 * t * ir;
    o[2] = n2 * t * ir * ir;
    o[3] = -n3 * t * ir * ir * ir;
    o[4] = n4 * t * ir * ir * ir * ir;
}

/* Lennard-Jones 12-6 (eq. lennard_jones_12_6), split as in section 4.3.1:
 * V_c = V_+ = 4 eps (s/r)^12, V_e = V_- = -4 eps (s/r)^6. */
static void edmi__pot_lj(edmi_real eps, edmi_real sigma, edmi_real r, edmi_pot_parts *o)
{
    edmi_real ir = EDMI__ONE / r, s = sigma * ir;
    edmi_real s6 = s * s * s * s * s * s;
    int i;
    edmi__inv_pow_derivs(EDMI_R(4.0) * eps * s6 * s6, ir, EDMI_R(12.0), EDMI_R(156.0),
                         EDMI_R(2184.0), EDMI_R(32760.0), o->c);
    edmi__inv_pow_derivs(-EDMI_R(4.0) * eps * s6, ir, EDMI_R(6.0), EDMI_R(42.0),
                         EDMI_R(336.0), EDMI_R(3024.0), o->e);
    for (i = 0; i < 5; i++)
        o->v[i] = o->c[i] + o->e[i];
    o->v[0] = EDMI_R(4.0) * eps * s6 * (s6 - EDMI__ONE); /* exact zero at r = sigma */
    edmi__copy5(o->c, o->sp);
    edmi__copy5(o->e, o->sm);
}

/* V = -k/r. Gravity (k > 0) is concave and super-concave: V_e = V_- = V (section 4.3.2);
 * a repulsive Coulomb pair (k < 0) is convex and super-convex: V_c = V_+ = V. */
static void edmi__pot_inverse(edmi_real k, edmi_real r, edmi_pot_parts *o)
{
    edmi_real ir = EDMI__ONE / r;
    edmi__inv_pow_derivs(-k * ir, ir, EDMI_R(1.0), EDMI_R(2.0), EDMI_R(6.0), EDMI_R(24.0),
                         o->v);
    if (k > EDMI__ZERO) {
        edmi__copy5(o->v, o->e);
        edmi__copy5(o->v, o->sm);
        edmi__zero5(o->c);
        edmi__zero5(o->sp);
    } else {
        edmi__copy5(o->v, o->c);
        edmi__copy5(o->v, o->sp);
        edmi__zero5(o->e);
        edmi__zero5(o->sm);
    }
}

static int edmi__pot_valid(const edmi_potential *pot)
{
    edmi_real a = pot->a, b = pot->b;
    if (pot->kind == EDMI_POT_USER)
        return pot->fn != 0;
    if (!edmi__finite(a) || !edmi__finite(b))
        return 0;
    switch (pot->kind) {
    case EDMI_POT_HARMONIC:
    case EDMI_POT_QUARTIC:
        return a > EDMI__ZERO && b >= EDMI__ZERO;
    case EDMI_POT_NEO_HOOKE:
    case EDMI_POT_LJ:
        return a > EDMI__ZERO && b > EDMI__ZERO;
    case EDMI_POT_INVERSE:
        return a != EDMI__ZERO;
    case EDMI_POT_USER:
    default:
        return 0;
    }
}

/* Evaluate a validated potential at r > 0. EDMI_ERR_DIVERGED if a user callback refuses r. */
static edmi_status edmi__pot_parts(const edmi_potential *pot, edmi_real r, edmi_pot_parts *o)
{
    int i;
    switch (pot->kind) {
    case EDMI_POT_HARMONIC:
        edmi__pot_harmonic(pot->a, pot->b, r, o);
        break;
    case EDMI_POT_QUARTIC:
        edmi__pot_quartic(pot->a, pot->b, r, o);
        break;
    case EDMI_POT_NEO_HOOKE:
        edmi__pot_neo_hooke(pot->a, pot->b, r, o);
        break;
    case EDMI_POT_LJ:
        edmi__pot_lj(pot->a, pot->b, r, o);
        break;
    case EDMI_POT_INVERSE:
        edmi__pot_inverse(pot->a, r, o);
        break;
    case EDMI_POT_USER:
    default:
        if (pot->fn(pot->ctx, r, o) != 0)
            return EDMI_ERR_DIVERGED;
        for (i = 0; i < 5; i++)
            o->v[i] = o->c[i] + o->e[i];
        break;
    }
    return EDMI_OK;
}

/* Round-off scale of V': |computed V'(r) - V'(r)| <~ eps * this. Not eps |V'|: near a rest
 * length the terms that cancel (r - r0, r^2 - L^2, the attractive and repulsive LJ parts) are
 * much larger than V' itself. Newton's stopping test uses it to know its round-off floor. */
static edmi_real edmi__dv_roundoff(const edmi_potential *pot, edmi_real r, const edmi_pot_parts *pp)
{
    edmi_real a = pot->a, b = pot->b;
    switch (pot->kind) {
    case EDMI_POT_HARMONIC:
        return a * (r + b);
    case EDMI_POT_QUARTIC:
        return a * r * (r * r + b * b);
    case EDMI_POT_NEO_HOOKE:
        return a / EDMI_R(3.0) * (r + b) * (r * r + r * b + b * b) / (r * r);
    case EDMI_POT_INVERSE:
        return edmi__abs(pp->v[1]);
    case EDMI_POT_LJ:
    case EDMI_POT_USER:
    default:
        return edmi__abs(pp->c[1]) + edmi__abs(pp->e[1]);
    }
}

/* Complete homogeneous polynomial h = sum_{j=0..m} a^j b^(m-j) and dh/da, by Horner in a
 * (all terms positive for a, b > 0: no cancellation). */
static void edmi__homog(int m, edmi_real a, edmi_real b, edmi_real *h, edmi_real *ha)
{
    edmi_real hh = EDMI__ONE, hd = EDMI__ZERO, bp = EDMI__ONE;
    int j;
    for (j = 0; j < m; j++) {
        bp *= b;
        hd = hd * a + hh;
        hh = hh * a + bp;
    }
    *h = hh;
    *ha = hd;
}

/* Divided difference of (sigma/r)^n between d0 and d1, and its d1-derivative:
 * with a = sigma/d1, b = sigma/d0, dd = -(a b / sigma) h_{n-1}(a, b). */
static void edmi__dd_inv_pow(int n, edmi_real sigma, edmi_real d0, edmi_real d1, edmi_real *dd,
                             edmi_real *dd_d1)
{
    edmi_real a = sigma / d1, b = sigma / d0, h, ha;
    edmi__homog(n - 1, a, b, &h, &ha);
    *dd = -(a * b / sigma) * h;
    *dd_d1 = (a * a * b / (sigma * sigma)) * (h + a * ha);
}

/* Closed-form [V(d1)-V(d0)]/(d1-d0) for the built-ins (the paper's eq. solar_flg_2 for
 * gravity, generalised). */
static edmi_status edmi__divdiff(const edmi_potential *pot, edmi_real d0, edmi_real d1,
                                 edmi_real *dd, edmi_real *dd_d1)
{
    edmi_real a = pot->a, b = pot->b;
    switch (pot->kind) {
    case EDMI_POT_HARMONIC:
        *dd = EDMI__HALF * a * ((d1 - b) + (d0 - b));
        *dd_d1 = EDMI__HALF * a;
        return EDMI_OK;
    case EDMI_POT_QUARTIC: {
        edmi_real w = d1 * d1 + d0 * d0 - EDMI_R(2.0) * b * b;
        *dd = EDMI_R(0.25) * a * (d1 + d0) * w;
        *dd_d1 = EDMI_R(0.25) * a * (w + EDMI_R(2.0) * d1 * (d1 + d0));
        return EDMI_OK;
    }
    case EDMI_POT_NEO_HOOKE: {
        edmi_real b3 = EDMI_R(2.0) * b * b * b / (d0 * d1);
        *dd = a / EDMI_R(6.0) * ((d1 + d0) - b3);
        *dd_d1 = a / EDMI_R(6.0) * (EDMI__ONE + b3 / d1);
        return EDMI_OK;
    }
    case EDMI_POT_LJ: {
        edmi_real q12, q12d, q6, q6d;
        edmi__dd_inv_pow(12, b, d0, d1, &q12, &q12d);
        edmi__dd_inv_pow(6, b, d0, d1, &q6, &q6d);
        *dd = EDMI_R(4.0) * a * (q12 - q6);
        *dd_d1 = EDMI_R(4.0) * a * (q12d - q6d);
        return EDMI_OK;
    }
    case EDMI_POT_INVERSE:
        *dd = a / (d0 * d1);
        *dd_d1 = -a / (d0 * d1 * d1);
        return EDMI_OK;
    case EDMI_POT_USER:
    default:
        if (pot->dd == 0)
            return EDMI_ERR_PARAM;
        return pot->dd(pot->ctx, d0, d1, dd, dd_d1) == 0 ? EDMI_OK : EDMI_ERR_DIVERGED;
    }
}

/* ==========================================================================================
 * The five algorithmic forces (section 4.1). Every pair force has the form
 *     f = dt * beta * r_m,   r_m = q_A,n+1/2 - q_B,n+1/2,
 * which conserves L, J and C (lemma many-body-momentum). MP has beta = V'(d_m)/d_m; the
 * others have beta = 2 Lambda / (d_n + d_n+1) with a scalar Lambda(d_n+1) per scheme. Each
 * Lambda function returns Lambda and dLambda/dd_n+1 for the consistent tangent.
 * ======================================================================================== */

/* Everything a Lambda needs at the end of the step. */
typedef struct edmi__at_end {
    edmi_real d1;       /* d_n+1 */
    edmi_pot_parts p1;  /* potential parts at d_n+1 (when the scheme needs them) */
    edmi_pot_parts pa;  /* potential parts at d_avg = (d_n + d_n+1)/2 (when needed) */
} edmi__at_end;

/* LG (eq. LaBudde-Greenspan-approximation): the quotient as written. Its cancellation error
 * eps (|V(d_n+1)| + |V(d_n)|) / |d_n+1 - d_n| is returned in *err for the stopping test. The
 * exact tangent (V'(d_n+1) - Lambda)/(d_n+1 - d_n) has error eps |V| / (d_n+1 - d_n)^2; its
 * limit V''(d_n+1)/2 has error |d_n+1 - d_n| |V'''| / 6: use whichever is smaller (the tangent
 * only steers Newton, the solution is set by the residual). */
static void edmi__lambda_lg_quotient(const edmi_link_ws *w, const edmi__at_end *e,
                                     edmi_real *lam, edmi_real *dlam, edmi_real *err)
{
    edmi_real dd = e->d1 - w->d0, ad = edmi__abs(dd);
    edmi_real verr = EDMI_EPS * (edmi__abs(e->p1.v[0]) + edmi__abs(w->v0));
    *lam = (e->p1.v[0] - w->v0) / dd;
    *err = verr / ad;
    if (verr > ad * ad * ad * edmi__abs(e->p1.v[3]) / EDMI_R(6.0))
        *dlam = EDMI__HALF * e->p1.v[2];
    else
        *dlam = (e->p1.v[1] - *lam) / dd;
}

/* Janz's alternate (eq. janz-mid-point-rescue): V'(||q||_n+1/2). */
static void edmi__lambda_janz(const edmi__at_end *e, edmi_real *lam, edmi_real *dlam)
{
    *lam = e->pa.v[1];
    *dlam = EDMI__HALF * e->pa.v[2];
}

/* Gonzalez's alternate (eq. gonzalez-mid-point-rescue). */
static void edmi__lambda_gonzalez(const edmi_link_ws *w, const edmi__at_end *e, edmi_real *lam,
                                  edmi_real *dlam)
{
    edmi_real dd = e->d1 - w->d0;
    *lam = e->pa.v[1] + dd * dd / EDMI_R(24.0) * e->pa.v[3];
    *dlam = EDMI__HALF * e->pa.v[2] + dd / EDMI_R(12.0) * e->pa.v[3] +
            dd * dd / EDMI_R(48.0) * e->pa.v[4];
}

/* f_ge (eq. convex-concave-scheme-p): V_c'(d_n+1) + V_e'(d_n). */
static void edmi__lambda_ge(const edmi_link_ws *w, const edmi__at_end *e, edmi_real *lam,
                            edmi_real *dlam)
{
    *lam = e->p1.c[1] + w->dve0;
    *dlam = e->p1.c[2];
}

/* f_pm (eq. super-convex-concave-scheme-p):
 * V'(d_avg) + (d_n+1 - d_n)^2/24 (V_+'''(d_n+1) + V_-'''(d_n)). */
static void edmi__lambda_pm(const edmi_link_ws *w, const edmi__at_end *e, edmi_real *lam,
                            edmi_real *dlam)
{
    edmi_real dd = e->d1 - w->d0, s3 = e->p1.sp[3] + w->d3m0;
    *lam = e->pa.v[1] + dd * dd / EDMI_R(24.0) * s3;
    *dlam = EDMI__HALF * e->pa.v[2] + dd / EDMI_R(12.0) * s3 + dd * dd / EDMI_R(24.0) * e->p1.sp[4];
}

/* f_pt (eq. super-convex-concave-trapezoidal-scheme-p):
 * (V'(d_n) + V'(d_n+1))/2 - (d_n+1 - d_n)^2/12 (V_+'''(d_n) + V_-'''(d_n+1)). */
static void edmi__lambda_pt(const edmi_link_ws *w, const edmi__at_end *e, edmi_real *lam,
                            edmi_real *dlam)
{
    edmi_real dd = e->d1 - w->d0, s3 = w->d3p0 + e->p1.sm[3];
    *lam = EDMI__HALF * (e->p1.v[1] + w->dv0) - dd * dd / EDMI_R(12.0) * s3;
    *dlam = EDMI__HALF * e->p1.v[2] - dd / EDMI_R(6.0) * s3 - dd * dd / EDMI_R(12.0) * e->p1.sm[4];
}

/* Which evaluations a Lambda needs: at d_n+1 and/or at d_avg (GE, PT: end; PM: both). */
enum { EDMI__NEED_END = 1, EDMI__NEED_AVG = 2 };

static int edmi__needs_decaying(edmi_scheme s)
{
    return s == EDMI_PM ? EDMI__NEED_END | EDMI__NEED_AVG : EDMI__NEED_END;
}

/* The energy-decaying scheme an LG alternate borrows its force from. */
static edmi_scheme edmi__alt_scheme(edmi_lg_alt alt)
{
    return alt == EDMI_ALT_GE ? EDMI_GE : alt == EDMI_ALT_PM ? EDMI_PM : EDMI_PT;
}

/* Lambda of an energy-decaying scheme, used by GE/PM/PT and by LG's decaying alternates. */
static void edmi__lambda_decaying(edmi_scheme s, const edmi_link_ws *w, const edmi__at_end *e,
                                  edmi_real *lam, edmi_real *dlam)
{
    if (s == EDMI_GE)
        edmi__lambda_ge(w, e, lam, dlam);
    else if (s == EDMI_PM)
        edmi__lambda_pm(w, e, lam, dlam);
    else
        edmi__lambda_pt(w, e, lam, dlam);
}

/* LG's alternate force in the singular limit |d_n+1 - d_n| <= tol_Q (section 3.4). */
static void edmi__lambda_lg_alt(edmi_lg_alt alt, const edmi_link_ws *w, const edmi__at_end *e,
                                edmi_real *lam, edmi_real *dlam)
{
    switch (alt) {
    case EDMI_ALT_GONZALEZ:
        edmi__lambda_gonzalez(w, e, lam, dlam);
        break;
    case EDMI_ALT_GE:
    case EDMI_ALT_PM:
    case EDMI_ALT_PT:
        edmi__lambda_decaying(edmi__alt_scheme(alt), w, e, lam, dlam);
        break;
    case EDMI_ALT_JANZ:
    default:
        edmi__lambda_janz(e, lam, dlam);
        break;
    }
}

/* beta and the tangent d f / d r_n+1 = dt (beta/2 I + gamma r_m (x) u) of one link. */
typedef struct edmi__link_eval {
    edmi_real beta;
    edmi_real gamma;
    edmi_real u[3];
    edmi_real beta_err; /* round-off in beta beyond a few eps |beta| (the LG quotient's) */
    int switched;       /* LG used its alternate */
} edmi__link_eval;

/* f_mp: beta = V'(d_m)/d_m with d_m = |r_m| (one-point Gauss, section 3.2). */
static edmi_status edmi__beta_mp(const edmi_potential *pot, const edmi_real rm[3],
                                 edmi__link_eval *le)
{
    edmi_pot_parts pm;
    edmi_real dm = edmi__norm(rm);
    edmi_status st;
    if (!(dm > EDMI__ZERO) || !edmi__finite(dm))
        return EDMI_ERR_DIVERGED;
    st = edmi__pot_parts(pot, dm, &pm);
    if (st != EDMI_OK)
        return st;
    le->beta = pm.v[1] / dm;
    /* d beta / d r_n+1 = (V'' - beta)/d_m * r_m/(2 d_m) */
    le->gamma = (pm.v[2] - le->beta) / (EDMI_R(2.0) * dm * dm);
    edmi__copy3(rm, le->u);
    return EDMI_OK;
}

/* f_lg, f_ge, f_pm, f_pt: beta = 2 Lambda / (d_n + d_n+1). */
static edmi_status edmi__beta_split(const edmi_params *prm, const edmi_potential *pot,
                                    const edmi_link_ws *w, const edmi_real r1[3],
                                    edmi__link_eval *le)
{
    edmi__at_end e;
    edmi_real lam = EDMI__ZERO, dlam = EDMI__ZERO, lam_err = EDMI__ZERO, s;
    edmi_status st;
    int need, lg_closed = 0, lg_switch = 0;
    e.d1 = edmi__norm(r1);
    if (!(e.d1 > EDMI__ZERO) || !edmi__finite(e.d1))
        return EDMI_ERR_DIVERGED;
    if (prm->scheme == EDMI_LG) {
        lg_closed = prm->lg_form == EDMI_LG_CLOSED &&
                    (pot->kind != EDMI_POT_USER || pot->dd != 0);
        lg_switch = !lg_closed && edmi__abs(e.d1 - w->d0) <= prm->tol_q;
    }
    if (lg_closed) {
        st = edmi__divdiff(pot, w->d0, e.d1, &lam, &dlam);
        if (st != EDMI_OK)
            return st;
    } else {
        if (prm->scheme != EDMI_LG)
            need = edmi__needs_decaying(prm->scheme);
        else if (!lg_switch)
            need = EDMI__NEED_END; /* the quotient needs V(d_n+1), V'(d_n+1) */
        else if (prm->lg_alt == EDMI_ALT_JANZ || prm->lg_alt == EDMI_ALT_GONZALEZ)
            need = EDMI__NEED_AVG;
        else
            need = edmi__needs_decaying(edmi__alt_scheme(prm->lg_alt));
        if (need & EDMI__NEED_END) {
            st = edmi__pot_parts(pot, e.d1, &e.p1);
            if (st != EDMI_OK)
                return st;
        }
        if (need & EDMI__NEED_AVG) {
            st = edmi__pot_parts(pot, EDMI__HALF * (w->d0 + e.d1), &e.pa);
            if (st != EDMI_OK)
                return st;
        }
        if (prm->scheme != EDMI_LG)
            edmi__lambda_decaying(prm->scheme, w, &e, &lam, &dlam);
        else if (lg_switch)
            edmi__lambda_lg_alt(prm->lg_alt, w, &e, &lam, &dlam);
        else
            edmi__lambda_lg_quotient(w, &e, &lam, &dlam, &lam_err);
    }
    s = w->d0 + e.d1;
    le->beta = EDMI_R(2.0) * lam / s;
    le->beta_err = EDMI_R(2.0) * lam_err / s;
    /* d beta / d r_n+1 = (2 Lambda' - beta)/s * r_n+1/d_n+1 */
    le->gamma = (EDMI_R(2.0) * dlam - le->beta) / (s * e.d1);
    edmi__copy3(r1, le->u);
    le->switched = lg_switch;
    return EDMI_OK;
}

/* ==========================================================================================
 * Residuals and consistent tangent (section 3.4, many-body form of section 4.1)
 * ======================================================================================== */

/* Second end of a link in the configuration q (rows per body). */
static const edmi_real *edmi__end_b(const edmi_link *lk, const edmi_real (*q)[3])
{
    return lk->b == EDMI_ANCHOR ? lk->anchor : q[lk->b];
}

/* Link vector q_A - q_B (or q_A - anchor) of the system's current state. */
static void edmi__link_vector(const edmi_system *sys, const edmi_link *lk, edmi_real r[3])
{
    edmi__sub(sys->body[lk->a].q, lk->b == EDMI_ANCHOR ? lk->anchor : sys->body[lk->b].q, r);
}

/* Start-of-step quantities of every link: r_n, d_n and the values at d_n the forces use. */
static edmi_status edmi__prepare_links(const edmi_system *sys, edmi_workspace *work)
{
    int i, back = sys->n_links;
    work->n_pair = 0;
    for (i = 0; i < sys->n_links; i++) /* pair links first, anchor links after them */
        if (sys->link[i].b == EDMI_ANCHOR)
            work->order[--back] = i;
        else
            work->order[work->n_pair++] = i;
    for (i = 0; i < sys->n_links; i++) {
        const edmi_link *lk = &sys->link[i];
        edmi_link_ws *w = &work->lw[i];
        edmi_pot_parts p0;
        edmi_status st;
        edmi__link_vector(sys, lk, w->r0);
        w->d0 = edmi__norm(w->r0);
        if (!(w->d0 > EDMI__ZERO))
            return EDMI_ERR_COINCIDENT;
        st = edmi__pot_parts(&lk->pot, w->d0, &p0);
        if (st != EDMI_OK)
            return st;
        w->v0 = p0.v[0];
        w->dv0 = p0.v[1];
        w->dve0 = p0.e[1];
        w->d3p0 = p0.sp[3];
        w->d3m0 = p0.sm[3];
        w->dv0_err = EDMI_EPS * edmi__dv_roundoff(&lk->pot, w->d0, &p0);
    }
    return EDMI_OK;
}

/* Linear viscous damper along a link (section "effects" of README): impulse
 *     I = c (dr . r_m) r_m / |r_m|^2,   dr = r_n+1 - r_n,
 * is parallel to r_m, so L, J and C are conserved (lemma many-body-momentum), and it removes
 * exactly dr . I / dt = c (dr . r_m)^2 / (|r_m|^2 dt) >= 0 per step. k = dI / dr_n+1. */
static edmi_status edmi__damper(const edmi_link_ws *w, edmi_real c, const edmi_real r1[3],
                                edmi_real imp[3], edmi_real k[9])
{
    edmi_real dr[3], rm[3], m2, s, cs;
    int i, j;
    edmi__sub(r1, w->r0, dr);
    for (i = 0; i < 3; i++)
        rm[i] = EDMI__HALF * (w->r0[i] + r1[i]);
    m2 = edmi__dot(rm, rm);
    if (!(m2 > EDMI__ZERO))
        return EDMI_ERR_DIVERGED;
    s = edmi__dot(dr, rm);
    cs = c * s / m2;
    for (i = 0; i < 3; i++) {
        imp[i] = cs * rm[i];
        for (j = 0; j < 3; j++)
            k[3 * i + j] = c / m2 * rm[i] * (rm[j] + EDMI__HALF * dr[j] - EDMI_R(2.0) * s / m2 * rm[j]) +
                           (i == j ? EDMI__HALF * cs : EDMI__ZERO);
    }
    return EDMI_OK;
}

/* Add the effects beyond links to R_p: force ports (-dt F), the uniform field (-dt m g),
 * dampers (+I on a, -I on b). Each is a loop over its own list: absent effects cost nothing. */
static edmi_status edmi__effects_residual(const edmi_system *sys, edmi_workspace *work,
                                          edmi_real dt, const edmi_real (*q1)[3],
                                          edmi_real (*rp)[3])
{
    int a, i, d;
    for (a = 0; a < sys->n_forced; a++) {
        int b = sys->forced[a];
        for (i = 0; i < 3; i++)
            rp[b][i] -= dt * sys->force[b][i];
        work->np[b] += EDMI_EPS * dt * edmi__norm(sys->force[b]);
    }
    if (sys->has_field)
        for (a = 0; a < sys->n_bodies; a++) {
            edmi_real mdt = dt * sys->body[a].m;
            for (i = 0; i < 3; i++)
                rp[a][i] -= mdt * sys->g[i];
            work->np[a] += EDMI_EPS * mdt * edmi__norm(sys->g);
        }
    for (d = 0; d < sys->n_dampers; d++) {
        const edmi_link *lk = &sys->link[sys->damper[d].link];
        edmi_real r1[3], imp[3], ni;
        edmi_status st;
        edmi__sub(q1[lk->a], edmi__end_b(lk, q1), r1);
        st = edmi__damper(&work->lw[sys->damper[d].link], sys->damper[d].c, r1, imp,
                          work->kd[d]);
        if (st != EDMI_OK)
            return st;
        ni = EDMI_R(4.0) * EDMI_EPS * edmi__norm(imp);
        work->np[lk->a] += ni;
        for (i = 0; i < 3; i++)
            rp[lk->a][i] += imp[i];
        if (lk->b != EDMI_ANCHOR) {
            work->np[lk->b] += ni;
            for (i = 0; i < 3; i++)
                rp[lk->b][i] -= imp[i];
        }
    }
    return EDMI_OK;
}

/* R_q, R_p at the trial end state (q1, p1), each link's tangent block (in work->lw), and
 * the round-off floors |R_q| and |R_p| cannot go below (work->nq, work->np): eps times the
 * magnitudes summed into them, plus the LG quotient's cancellation error. */
/* One link's algorithmic force f = dt beta r_m for the end-of-step link vector r1, its tangent
 * block (into work->lw[j]) and the round-off floor of f (*nf). */
static edmi_status edmi__link_force(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                    int j, const edmi_real r1[3], edmi_real f[3], edmi_real *nf,
                                    int *switched)
{
    const edmi_link *lk = &sys->link[j];
    edmi_link_ws *w = &work->lw[j];
    edmi__link_eval le;
    edmi_real rm[3];
    edmi_status st;
    int i, c;
    for (i = 0; i < 3; i++)
        rm[i] = EDMI__HALF * (w->r0[i] + r1[i]);
    le.switched = 0;
    le.beta_err = EDMI__ZERO;
    st = sys->params.scheme == EDMI_MP ? edmi__beta_mp(&lk->pot, rm, &le)
                                       : edmi__beta_split(&sys->params, &lk->pot, w, r1, &le);
    if (st != EDMI_OK)
        return st;
    *switched = le.switched;
    w->beta = le.beta;
    for (i = 0; i < 3; i++) {
        f[i] = dt * le.beta * rm[i];
        for (c = 0; c < 3; c++)
            w->k[3 * i + c] = dt * (le.gamma * rm[i] * le.u[c] +
                                    (i == c ? EDMI__HALF * le.beta : EDMI__ZERO));
    }
    /* beta ~ V'/d: its round-off is a few eps |beta|, V''s own (2 evaluations near d_n),
     * and the LG quotient's cancellation */
    *nf = dt * edmi__norm(rm) *
          (EDMI_R(4.0) * EDMI_EPS * edmi__abs(le.beta) + EDMI_R(2.0) * w->dv0_err / w->d0 +
           le.beta_err);
    return EDMI_OK;
}

static edmi_status edmi__residual(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                  const edmi_real (*q1)[3], const edmi_real (*p1)[3],
                                  edmi_real (*rq)[3], edmi_real (*rp)[3], int *switches)
{
    int a, i, k, nsw = 0, sw;
    edmi_real r1[3], f[3], nf;
    edmi_status st;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi_real h = dt / bd->m * EDMI__HALF;
        edmi_real np1 = edmi__norm(p1[a]), np0 = edmi__norm(bd->p);
        for (i = 0; i < 3; i++) {
            rq[a][i] = q1[a][i] - bd->q[i] - h * (bd->p[i] + p1[a][i]);
            rp[a][i] = p1[a][i] - bd->p[i];
        }
        work->nq[a] = EDMI_EPS * (edmi__norm(q1[a]) + edmi__norm(bd->q) + h * (np0 + np1));
        work->np[a] = EDMI_EPS * (np0 + np1);
    }
    /* Pair links, then anchor links (work->order, set once per step): no per-link branch. */
    for (k = 0; k < work->n_pair; k++) {
        const edmi_link *lk = &sys->link[work->order[k]];
        edmi__sub(q1[lk->a], q1[lk->b], r1);
        st = edmi__link_force(sys, work, dt, work->order[k], r1, f, &nf, &sw);
        if (st != EDMI_OK)
            return st;
        nsw += sw;
        work->np[lk->a] += nf;
        work->np[lk->b] += nf;
        for (i = 0; i < 3; i++) {
            rp[lk->a][i] += f[i];
            rp[lk->b][i] -= f[i];
        }
    }
    for (k = work->n_pair; k < sys->n_links; k++) {
        const edmi_link *lk = &sys->link[work->order[k]];
        edmi__sub(q1[lk->a], lk->anchor, r1);
        st = edmi__link_force(sys, work, dt, work->order[k], r1, f, &nf, &sw);
        if (st != EDMI_OK)
            return st;
        nsw += sw;
        work->np[lk->a] += nf;
        for (i = 0; i < 3; i++)
            rp[lk->a][i] += f[i];
    }
    st = edmi__effects_residual(sys, work, dt, q1, rp);
    if (st != EDMI_OK)
        return st;
    for (a = 0; a < sys->n_bodies; a++)
        if (!edmi__finite3(rq[a]) || !edmi__finite3(rp[a]))
            return EDMI_ERR_DIVERGED;
    if (switches)
        *switches = nsw;
    return EDMI_OK;
}

/* ==========================================================================================
 * Linear solves: the segregated Newton system (I + dt/(2m) C) dq = -R_q - dt/(2m) R_p.
 * One body: a hand-written 3x3 solve. Several: Gaussian elimination with partial pivoting,
 * restricted to the band the links occupy (bodies linked to bodies far away in index widen
 * it; all-pairs scenes are dense). Exact solves keep Newton quadratic.
 * ======================================================================================== */

/* Solve A x = b (3x3, row-major) by the adjugate; singular when |det| is below 8 eps of
 * Hadamard's bound |det| <= prod of row norms (scale-free, catches NaN). */
static edmi_status edmi__solve3(const edmi_real m[9], const edmi_real b[3], edmi_real x[3])
{
    edmi_real c0 = m[4] * m[8] - m[5] * m[7];
    edmi_real c1 = m[5] * m[6] - m[3] * m[8];
    edmi_real c2 = m[3] * m[7] - m[4] * m[6];
    edmi_real det = m[0] * c0 + m[1] * c1 + m[2] * c2;
    edmi_real had = edmi__norm(m) * edmi__norm(m + 3) * edmi__norm(m + 6);
    edmi_real id;
    if (!(edmi__abs(det) > EDMI_R(8.0) * EDMI_EPS * had))
        return EDMI_ERR_SINGULAR;
    id = EDMI__ONE / det;
    x[0] = (c0 * b[0] + (m[2] * m[7] - m[1] * m[8]) * b[1] + (m[1] * m[5] - m[2] * m[4]) * b[2]) * id;
    x[1] = (c1 * b[0] + (m[0] * m[8] - m[2] * m[6]) * b[1] + (m[2] * m[3] - m[0] * m[5]) * b[2]) * id;
    x[2] = (c2 * b[0] + (m[1] * m[6] - m[0] * m[7]) * b[1] + (m[0] * m[4] - m[1] * m[3]) * b[2]) * id;
    return EDMI_OK;
}

/* Scalar half-bandwidth of the Newton matrix: 3 * (largest body-index gap of a pair link) + 2. */
static int edmi__bandwidth(const edmi_system *sys)
{
    int j, w = 0;
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        if (lk->b != EDMI_ANCHOR) {
            int g = lk->a > lk->b ? lk->a - lk->b : lk->b - lk->a;
            if (g > w)
                w = g;
        }
    }
    return 3 * w + 2;
}

/* Add the tangent block k = d(force on a)/d(q_a - q_b) of a force acting + on body a and -
 * on body b into the dense row-major n x n matrix g, rows of a scaled by ha, of b by hb. */
static void edmi__scatter_pair(edmi_real *g, int n, int a, int b, const edmi_real k[9],
                               edmi_real ha, edmi_real hb)
{
    int r, c, ra = 3 * a, rb = 3 * b;
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++) {
            edmi_real v = k[3 * r + c];
            g[(ra + r) * n + ra + c] += ha * v;
            g[(ra + r) * n + rb + c] -= ha * v;
            g[(rb + r) * n + ra + c] -= hb * v;
            g[(rb + r) * n + rb + c] += hb * v;
        }
}

/* The same for a force on body a from a fixed anchor: only the (a, a) block. */
static void edmi__scatter_anchor(edmi_real *g, int n, int a, const edmi_real k[9], edmi_real ha)
{
    int r, c, ra = 3 * a;
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++)
            g[(ra + r) * n + ra + c] += ha * k[3 * r + c];
}

/* A damper acts along a link that may be a pair or an anchor link. */
static void edmi__scatter(edmi_real *g, int n, const edmi_link *lk, const edmi_real k[9],
                          edmi_real ha, edmi_real hb)
{
    if (lk->b == EDMI_ANCHOR)
        edmi__scatter_anchor(g, n, lk->a, k, ha);
    else
        edmi__scatter_pair(g, n, lk->a, lk->b, k, ha, hb);
}

/* Row scale dt / (2 m) of a link's ends (hb unused for an anchor). */
static void edmi__end_scales(const edmi_system *sys, const edmi_link *lk, edmi_real dt,
                             edmi_real *ha, edmi_real *hb)
{
    *ha = dt / (EDMI_R(2.0) * sys->body[lk->a].m);
    *hb = lk->b == EDMI_ANCHOR ? EDMI__ZERO : dt / (EDMI_R(2.0) * sys->body[lk->b].m);
}

/* Assemble G = I + dt/(2 m_A) dR_p/dq1 (rows of body A) into the band of work->mat. */
static void edmi__assemble(const edmi_system *sys, edmi_workspace *work, edmi_real dt, int n,
                           int kb)
{
    edmi_real *g = work->mat, ha, hb;
    int i, j;
    for (i = 0; i < n; i++) {
        int lo = i - kb < 0 ? 0 : i - kb, hi = i + 2 * kb >= n ? n - 1 : i + 2 * kb;
        for (j = lo; j <= hi; j++)
            g[i * n + j] = EDMI__ZERO;
        g[i * n + i] = EDMI__ONE;
    }
    for (j = 0; j < work->n_pair; j++) {
        const edmi_link *lk = &sys->link[work->order[j]];
        edmi__scatter_pair(g, n, lk->a, lk->b, work->lw[work->order[j]].k,
                           dt / (EDMI_R(2.0) * sys->body[lk->a].m),
                           dt / (EDMI_R(2.0) * sys->body[lk->b].m));
    }
    for (j = work->n_pair; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[work->order[j]];
        edmi__scatter_anchor(g, n, lk->a, work->lw[work->order[j]].k,
                             dt / (EDMI_R(2.0) * sys->body[lk->a].m));
    }
    for (j = 0; j < sys->n_dampers; j++) {
        const edmi_link *lk = &sys->link[sys->damper[j].link];
        edmi__end_scales(sys, lk, dt, &ha, &hb);
        edmi__scatter(g, n, lk, work->kd[j], ha, hb);
    }
}

/* Solve G x = rhs in place (x returned in rhs) by banded Gaussian elimination with partial
 * pivoting: lower bandwidth kb, upper bandwidth 2 kb after fill-in from row exchanges. */
static edmi_status edmi__solve_band(edmi_real *g, edmi_real *rhs, int n, int kb)
{
    edmi_real amax = EDMI__ZERO;
    int i, j, k;
    for (i = 0; i < n; i++) {
        int lo = i - kb < 0 ? 0 : i - kb, hi = i + kb >= n ? n - 1 : i + kb;
        for (j = lo; j <= hi; j++)
            amax = edmi__max(amax, edmi__abs(g[i * n + j]));
    }
    if (!(amax > EDMI__ZERO) || !edmi__finite(amax))
        return EDMI_ERR_SINGULAR;
    for (k = 0; k < n; k++) {
        int last = k + kb >= n ? n - 1 : k + kb, cmax = k + 2 * kb >= n ? n - 1 : k + 2 * kb;
        int p = k;
        edmi_real best = edmi__abs(g[k * n + k]), piv;
        for (i = k + 1; i <= last; i++)
            if (edmi__abs(g[i * n + k]) > best) {
                best = edmi__abs(g[i * n + k]);
                p = i;
            }
        if (!(best > EDMI_R(4.0) * EDMI_EPS * amax))
            return EDMI_ERR_SINGULAR;
        if (p != k) {
            edmi_real t;
            for (j = k; j <= cmax; j++) {
                t = g[k * n + j];
                g[k * n + j] = g[p * n + j];
                g[p * n + j] = t;
            }
            t = rhs[k];
            rhs[k] = rhs[p];
            rhs[p] = t;
        }
        piv = g[k * n + k];
        for (i = k + 1; i <= last; i++) {
            edmi_real f = g[i * n + k] / piv;
            if (f == EDMI__ZERO)
                continue;
            for (j = k + 1; j <= cmax; j++)
                g[i * n + j] -= f * g[k * n + j];
            rhs[i] -= f * rhs[k];
        }
    }
    for (i = n - 1; i >= 0; i--) {
        int cmax = i + 2 * kb >= n ? n - 1 : i + 2 * kb;
        edmi_real s = rhs[i];
        for (j = i + 1; j <= cmax; j++)
            s -= g[i * n + j] * rhs[j];
        rhs[i] = s / g[i * n + i];
    }
    return EDMI_OK;
}

/* One Newton correction: solve for dq (into work->rhs), recover dp = 2m/dt (R_q + dq). */
static edmi_status edmi__newton_update(const edmi_system *sys, edmi_workspace *work,
                                       edmi_real dt)
{
    int nb = sys->n_bodies, n = 3 * nb, a, i;
    edmi_status st;
    for (a = 0; a < nb; a++) {
        edmi_real h = dt / (EDMI_R(2.0) * sys->body[a].m);
        for (i = 0; i < 3; i++)
            work->rhs[3 * a + i] = -work->rq[a][i] - h * work->rp[a][i];
    }
    if (nb == 1) {
        edmi_real g[9], x[3];
        edmi_real h = dt / (EDMI_R(2.0) * sys->body[0].m);
        int j;
        for (i = 0; i < 9; i++)
            g[i] = EDMI__ZERO;
        for (j = 0; j < sys->n_links; j++) /* one body: every link is an anchor link */
            for (i = 0; i < 9; i++)
                g[i] += h * work->lw[j].k[i];
        for (j = 0; j < sys->n_dampers; j++)
            for (i = 0; i < 9; i++)
                g[i] += h * work->kd[j][i];
        g[0] += EDMI__ONE;
        g[4] += EDMI__ONE;
        g[8] += EDMI__ONE;
        st = edmi__solve3(g, work->rhs, x);
        if (st != EDMI_OK)
            return st;
        edmi__copy3(x, work->rhs);
    } else {
        int kb = edmi__bandwidth(sys);
        edmi__assemble(sys, work, dt, n, kb);
        st = edmi__solve_band(work->mat, work->rhs, n, kb);
        if (st != EDMI_OK)
            return st;
    }
    for (a = 0; a < nb; a++) {
        edmi_real c = EDMI_R(2.0) * sys->body[a].m / dt;
        for (i = 0; i < 3; i++)
            work->dp[a][i] = c * (work->rq[a][i] + work->rhs[3 * a + i]);
    }
    return EDMI_OK;
}

/* Move the iterate by lambda times the Newton correction (dq in work->rhs, dp in work->dp). */
static void edmi__move(const edmi_system *sys, edmi_workspace *work, edmi_real lambda)
{
    int a, i;
    for (a = 0; a < sys->n_bodies; a++)
        for (i = 0; i < 3; i++) {
            work->q1[a][i] += lambda * work->rhs[3 * a + i];
            work->p1[a][i] += lambda * work->dp[a][i];
        }
}

/* ==========================================================================================
 * The Newton predictor multi-corrector with a scale-aware stopping test.
 * R_q and R_p carry different units and bodies differ by orders of magnitude (the Sun and
 * Mercury), so each body's residual blocks are measured against that body's own scales:
 *   S_p = |p_n| + |R_p at the predictor| (momentum plus the impulse of one step),
 *   S_q = |q_n| + dt/m S_p               (position plus the motion of one step),
 * and the scaled residual is the largest |R_q|/S_q, |R_p|/S_p over bodies.
 * ======================================================================================== */

static void edmi__set_scales(const edmi_system *sys, edmi_workspace *work, edmi_real dt)
{
    int a;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi_real sp = edmi__norm(bd->p) + edmi__norm(work->rp[a]);
        edmi_real sq = edmi__norm(bd->q) + dt / bd->m * sp;
        work->sp[a] = sp > EDMI__ZERO ? sp : EDMI__ONE;
        work->sq[a] = sq > EDMI__ZERO ? sq : EDMI__ONE;
    }
}

/* The scaled residual and, in *floor, the same measure of its round-off floor. */
static edmi_real edmi__scaled_residual(const edmi_system *sys, const edmi_workspace *work,
                                       edmi_real *floor)
{
    edmi_real r = EDMI__ZERO, f = EDMI__ZERO;
    int a;
    for (a = 0; a < sys->n_bodies; a++) {
        r = edmi__max(r, edmi__norm(work->rq[a]) / work->sq[a]);
        r = edmi__max(r, edmi__norm(work->rp[a]) / work->sp[a]);
        f = edmi__max(f, work->nq[a] / work->sq[a]);
        f = edmi__max(f, work->np[a] / work->sp[a]);
    }
    *floor = f;
    return r;
}

/* Residual, tangent, scaled residual and floor at the current iterate. */
static edmi_status edmi__evaluate(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                  edmi_real *r, edmi_step_result *res)
{
    edmi_status st = edmi__residual(sys, work, dt, (const edmi_real (*)[3])work->q1,
                                    (const edmi_real (*)[3])work->p1, work->rq, work->rp,
                                    &res->lg_switches);
    if (st == EDMI_OK)
        *r = edmi__scaled_residual(sys, work, &res->floor);
    return st;
}

/* Take the Newton correction; halve it while the trial leaves the potentials' domain (a link
 * distance of 0 or a non-finite residual, e.g. a near-collision overshoot). No descent test:
 * at omega dt >> 1 plain Newton reaches the solution along a non-monotone path that a
 * monotone line search blocks (measured on the paper's spring at dt = 0.5). */
static edmi_status edmi__line_search(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                     edmi_real *r, edmi_step_result *res)
{
    edmi_real lambda = EDMI__ONE;
    edmi_status st;
    int h;
    edmi__move(sys, work, lambda);
    st = edmi__evaluate(sys, work, dt, r, res);
    for (h = 0; h < EDMI__MAX_HALVINGS && st == EDMI_ERR_DIVERGED; h++) {
        lambda *= EDMI__HALF;
        edmi__move(sys, work, -lambda);
        st = edmi__evaluate(sys, work, dt, r, res);
        res->halvings++;
    }
    return st;
}

static int edmi__params_valid(const edmi_params *p)
{
    return (p->scheme == EDMI_MP || p->scheme == EDMI_LG || p->scheme == EDMI_GE ||
            p->scheme == EDMI_PM || p->scheme == EDMI_PT) &&
           (p->lg_form == EDMI_LG_CLOSED || p->lg_form == EDMI_LG_QUOTIENT) &&
           (p->lg_alt == EDMI_ALT_JANZ || p->lg_alt == EDMI_ALT_GONZALEZ ||
            p->lg_alt == EDMI_ALT_GE || p->lg_alt == EDMI_ALT_PM || p->lg_alt == EDMI_ALT_PT) &&
           edmi__finite(p->tol_q) && p->tol_q > EDMI__ZERO && edmi__finite(p->tol_r) &&
           p->tol_r > EDMI__ZERO && edmi__finite(p->tol_a) && p->tol_a > EDMI__ZERO &&
           p->l_max >= 1;
}

/* Body a exists; b is an anchor or another existing body. */
static int edmi__link_ends_valid(int n_bodies, int a, int b)
{
    return a >= 0 && a < n_bodies && (b == EDMI_ANCHOR || (b >= 0 && b < n_bodies && b != a));
}

/* The effects beyond links: dampers on existing links, ports on existing bodies, finite. */
static edmi_status edmi__validate_effects(const edmi_system *sys)
{
    int i;
    if (sys->n_dampers < 0 || sys->n_dampers > EDMI_MAX_DAMPERS || sys->n_forced < 0 ||
        sys->n_forced > sys->n_bodies)
        return EDMI_ERR_CAPACITY;
    for (i = 0; i < sys->n_dampers; i++) {
        const edmi_damper *d = &sys->damper[i];
        if (d->link < 0 || d->link >= sys->n_links)
            return EDMI_ERR_INDEX;
        if (!edmi__finite(d->c) || d->c < EDMI__ZERO)
            return EDMI_ERR_PARAM;
    }
    for (i = 0; i < sys->n_forced; i++) {
        int b = sys->forced[i];
        if (b < 0 || b >= sys->n_bodies)
            return EDMI_ERR_INDEX;
        if (!edmi__finite3(sys->force[b]))
            return EDMI_ERR_NONFINITE;
    }
    if (sys->has_field && !edmi__finite3(sys->g))
        return EDMI_ERR_NONFINITE;
    if (!edmi__finite(sys->t) || !edmi__finite(sys->t_carry))
        return EDMI_ERR_NONFINITE;
    return EDMI_OK;
}

/* Everything edmi_step checks before it touches anything. */
static edmi_status edmi__validate(const edmi_system *sys, edmi_real dt)
{
    int i;
    if (!edmi__finite(dt) || !(dt > EDMI__ZERO))
        return EDMI_ERR_DT;
    if (!edmi__params_valid(&sys->params))
        return EDMI_ERR_PARAM;
    if (sys->n_bodies < 0 || sys->n_bodies > EDMI_MAX_BODIES || sys->n_links < 0 ||
        sys->n_links > EDMI_MAX_LINKS)
        return EDMI_ERR_CAPACITY;
    for (i = 0; i < sys->n_bodies; i++) {
        const edmi_body *bd = &sys->body[i];
        if (!edmi__finite(bd->m) || !(bd->m > EDMI__ZERO))
            return EDMI_ERR_MASS;
        if (!edmi__finite3(bd->q) || !edmi__finite3(bd->p))
            return EDMI_ERR_NONFINITE;
    }
    for (i = 0; i < sys->n_links; i++) {
        const edmi_link *lk = &sys->link[i];
        if (!edmi__link_ends_valid(sys->n_bodies, lk->a, lk->b))
            return EDMI_ERR_INDEX;
        if (!edmi__pot_valid(&lk->pot))
            return EDMI_ERR_PARAM;
        if (!edmi__finite3(lk->anchor))
            return EDMI_ERR_NONFINITE;
    }
    return edmi__validate_effects(sys);
}

/* The discrete energy balance of the converged step (before it is committed):
 * H_n+1 - H_n = work_ext - diss_scheme - diss_damping up to the Newton residual. */
static edmi_status edmi__energy_report(const edmi_system *sys, edmi_workspace *work,
                                       edmi_real dt, edmi_step_result *res)
{
    const edmi_real (*q1)[3] = (const edmi_real (*)[3])work->q1;
    int a, j;
    for (a = 0; a < sys->n_forced; a++) {
        int b = sys->forced[a];
        edmi_real dq[3];
        edmi__sub(q1[b], sys->body[b].q, dq);
        res->work_ext += edmi__dot(sys->force[b], dq);
    }
    for (j = 0; j < sys->n_dampers; j++) {
        const edmi_link *lk = &sys->link[sys->damper[j].link];
        edmi_link_ws *w = &work->lw[sys->damper[j].link];
        edmi_real r1[3], dr[3], imp[3], k[9];
        edmi_status st;
        edmi__sub(q1[lk->a], edmi__end_b(lk, q1), r1);
        st = edmi__damper(w, sys->damper[j].c, r1, imp, k);
        if (st != EDMI_OK)
            return st;
        edmi__sub(r1, w->r0, dr);
        res->diss_damping += edmi__dot(dr, imp) / dt;
    }
    if (!sys->params.energy_balance)
        return EDMI_OK;
    for (j = 0; j < sys->n_links; j++) {
        const edmi_link *lk = &sys->link[j];
        edmi_link_ws *w = &work->lw[j];
        edmi_real r1[3];
        edmi_pot_parts p1;
        edmi_status st;
        edmi__sub(q1[lk->a], edmi__end_b(lk, q1), r1);
        st = edmi__pot_parts(&lk->pot, edmi__norm(r1), &p1);
        if (st != EDMI_OK)
            return st;
        /* work of f = dt beta r_m over dr, per dt: beta (dr . r_m) = beta (|r1|^2 - |r0|^2)/2 */
        res->diss_scheme += w->beta * EDMI__HALF * (edmi__dot(r1, r1) - w->d0 * w->d0) -
                            (p1.v[0] - w->v0);
    }
    return EDMI_OK;
}

/* t += dt with Kahan's compensation: after n steps t is off by ~eps t, not ~n eps t, which
 * keeps the centre-of-mass invariant C(t) = (sum m q - t L)/M free of clock drift. */
static void edmi__advance_clock(edmi_system *sys, edmi_real dt)
{
    edmi_real y = dt - sys->t_carry, t = sys->t + y;
    sys->t_carry = (t - sys->t) - y;
    sys->t = t;
}

static void edmi__clear_result(edmi_step_result *res)
{
    res->iterations = 0;
    res->stop = EDMI_STOP_TOL_R;
    res->residual = EDMI__ZERO;
    res->residual0 = EDMI__ZERO;
    res->floor = EDMI__ZERO;
    res->lg_switches = 0;
    res->halvings = 0;
    res->work_ext = EDMI__ZERO;
    res->diss_damping = EDMI__ZERO;
    res->diss_scheme = EDMI__ZERO;
}

edmi_status edmi_step(edmi_system *sys, edmi_workspace *work, edmi_real dt,
                      edmi_step_result *res)
{
    edmi_step_result local;
    const edmi_params *prm;
    edmi_real r, rprev;
    edmi_status st;
    int a, l, halvings_before;
    if (!res)
        res = &local;
    edmi__clear_result(res);
    if (!sys || !work)
        return EDMI_ERR_NULL;
    st = edmi__validate(sys, dt);
    if (st != EDMI_OK)
        return st;
    prm = &sys->params;
    st = edmi__prepare_links(sys, work);
    if (st != EDMI_OK)
        return st;

    /* Predictor: q_n+1,(0) = q_n, p_n+1,(0) = p_n. */
    for (a = 0; a < sys->n_bodies; a++) {
        edmi__copy3(sys->body[a].q, work->q1[a]);
        edmi__copy3(sys->body[a].p, work->p1[a]);
    }
    st = edmi__evaluate(sys, work, dt, &r, res);
    if (st != EDMI_OK)
        return st;
    edmi__set_scales(sys, work, dt); /* the predictor's residual sets the scales, */
    r = edmi__scaled_residual(sys, work, &res->floor); /* so measure again with them */
    res->residual0 = r;
    res->residual = r;

    /* Multi-corrector. */
    if (r > EDMI__ZERO) {
        for (l = 1;; l++) {
            st = edmi__newton_update(sys, work, dt);
            if (st != EDMI_OK)
                return st;
            rprev = r;
            halvings_before = res->halvings;
            st = edmi__line_search(sys, work, dt, &r, res);
            if (st != EDMI_OK)
                return st;
            res->iterations = l;
            res->residual = r;
            if (r <= prm->tol_r * res->residual0) {
                res->stop = EDMI_STOP_TOL_R;
                break;
            }
            if (r <= prm->tol_a) {
                res->stop = EDMI_STOP_TOL_A;
                break;
            }
            /* Round-off floor: estimated, or shown by a quadratic regime that stopped
             * contracting (cancellation inside a potential, e.g. r^2 - L^2 near the rest
             * length, is not in the estimate). */
            if (r <= EDMI__FLOOR_FACTOR * res->floor ||
                (l >= 2 && rprev <= EDMI__SQRT_EPS * res->residual0 &&
                 r <= EDMI__SQRT_EPS * res->residual0 && r > EDMI__HALF * rprev)) {
                res->stop = EDMI_STOP_STALLED;
                break;
            }
            if (l >= prm->l_max) /* still pushed out of the domain, or just slow */
                return res->halvings > halvings_before ? EDMI_ERR_DIVERGED
                                                       : EDMI_ERR_NO_CONVERGENCE;
        }
    } else {
        res->stop = EDMI_STOP_TOL_A;
    }

    st = edmi__energy_report(sys, work, dt, res);
    if (st != EDMI_OK)
        return st;

    /* Commit. */
    for (a = 0; a < sys->n_bodies; a++) {
        edmi__copy3(work->q1[a], sys->body[a].q);
        edmi__copy3(work->p1[a], sys->body[a].p);
    }
    edmi__advance_clock(sys, dt);
    return EDMI_OK;
}

/* ==========================================================================================
 * Verification entry points: the residual and tangent Newton uses.
 * ======================================================================================== */

static edmi_status edmi__check_trial(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                                     const void *q1, const void *p1)
{
    edmi_status st;
    if (!sys || !work || !q1 || !p1)
        return EDMI_ERR_NULL;
    st = edmi__validate(sys, dt);
    if (st != EDMI_OK)
        return st;
    return edmi__prepare_links(sys, work);
}

edmi_status edmi_residual(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                          const edmi_real (*q1)[3], const edmi_real (*p1)[3],
                          edmi_real (*rq)[3], edmi_real (*rp)[3], int *lg_switches)
{
    edmi_status st = edmi__check_trial(sys, work, dt, q1, p1);
    if (st != EDMI_OK)
        return st;
    if (!rq || !rp)
        return EDMI_ERR_NULL;
    return edmi__residual(sys, work, dt, q1, p1, rq, rp, lg_switches);
}

edmi_status edmi_tangent(const edmi_system *sys, edmi_workspace *work, edmi_real dt,
                         const edmi_real (*q1)[3], const edmi_real (*p1)[3], edmi_real *kmat)
{
    int n, i, j;
    edmi_status st = edmi__check_trial(sys, work, dt, q1, p1);
    if (st != EDMI_OK)
        return st;
    if (!kmat)
        return EDMI_ERR_NULL;
    st = edmi__residual(sys, work, dt, q1, p1, work->rq, work->rp, 0);
    if (st != EDMI_OK)
        return st;
    n = 3 * sys->n_bodies;
    for (i = 0; i < n * n; i++)
        kmat[i] = EDMI__ZERO;
    for (j = 0; j < sys->n_links; j++)
        edmi__scatter(kmat, n, &sys->link[j], work->lw[j].k, EDMI__ONE, EDMI__ONE);
    for (j = 0; j < sys->n_dampers; j++)
        edmi__scatter(kmat, n, &sys->link[sys->damper[j].link], work->kd[j], EDMI__ONE,
                      EDMI__ONE);
    return EDMI_OK;
}

/* ==========================================================================================
 * Invariants: H = K + V, J, L, C(t) (sections 2 and 4.1).
 * ======================================================================================== */

edmi_status edmi_invariants_of(const edmi_system *sys, edmi_invariants *out)
{
    edmi_real mass = EDMI__ZERO, mq[3] = {EDMI__ZERO, EDMI__ZERO, EDMI__ZERO};
    int a, i;
    if (!sys || !out)
        return EDMI_ERR_NULL;
    out->k = EDMI__ZERO;
    out->v = EDMI__ZERO;
    for (i = 0; i < 3; i++)
        out->j[i] = out->l[i] = EDMI__ZERO;
    for (a = 0; a < sys->n_bodies; a++) {
        const edmi_body *bd = &sys->body[a];
        edmi_real jq[3];
        out->k += EDMI__HALF * edmi__dot(bd->p, bd->p) / bd->m;
        edmi__cross(bd->q, bd->p, jq);
        for (i = 0; i < 3; i++) {
            out->j[i] += jq[i];
            out->l[i] += bd->p[i];
            mq[i] += bd->m * bd->q[i];
        }
        mass += bd->m;
    }
    for (a = 0; a < sys->n_links; a++) {
        const edmi_link *lk = &sys->link[a];
        edmi_real r[3], d;
        edmi_pot_parts pp;
        edmi_status st;
        edmi__link_vector(sys, lk, r);
        d = edmi__norm(r);
        if (!(d > EDMI__ZERO))
            return EDMI_ERR_COINCIDENT;
        st = edmi__pot_parts(&lk->pot, d, &pp);
        if (st != EDMI_OK)
            return st;
        out->v += pp.v[0];
    }
    if (sys->has_field)
        for (a = 0; a < sys->n_bodies; a++)
            out->v -= sys->body[a].m * edmi__dot(sys->g, sys->body[a].q);
    out->h = out->k + out->v;
    for (i = 0; i < 3; i++)
        out->c[i] = mass > EDMI__ZERO ? (mq[i] - sys->t * out->l[i]) / mass : EDMI__ZERO;
    return EDMI_OK;
}

edmi_status edmi_pot_eval(const edmi_potential *pot, edmi_real r, edmi_pot_parts *out)
{
    if (!pot || !out)
        return EDMI_ERR_NULL;
    if (!edmi__pot_valid(pot) || !edmi__finite(r) || !(r > EDMI__ZERO))
        return EDMI_ERR_PARAM;
    return edmi__pot_parts(pot, r, out);
}

edmi_status edmi_pot_divdiff(const edmi_potential *pot, edmi_real d0, edmi_real d1,
                             edmi_real *dd, edmi_real *dd_d1)
{
    if (!pot || !dd || !dd_d1)
        return EDMI_ERR_NULL;
    if (!edmi__pot_valid(pot) || !edmi__finite(d0) || !edmi__finite(d1) ||
        !(d0 > EDMI__ZERO) || !(d1 > EDMI__ZERO))
        return EDMI_ERR_PARAM;
    return edmi__divdiff(pot, d0, d1, dd, dd_d1);
}

/* ==========================================================================================
 * Building a system
 * ======================================================================================== */

edmi_params edmi_default_params(void)
{
    edmi_params p;
    p.scheme = EDMI_MP;
    p.lg_form = EDMI_LG_CLOSED;
    p.lg_alt = EDMI_ALT_JANZ;
    p.l_max = 20;
    p.energy_balance = 0;
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
    /* The paper's section 3.4 values. */
    p.tol_q = EDMI_R(1e-8);
    p.tol_r = EDMI_R(1e-10);
    p.tol_a = EDMI_R(1e-15);
#else
    /* Float (eps = 1.19e-7): the scaled residual cannot fall much below ~10 eps, so
     * tol_a = 1e-6 (~8 eps) is the absolute floor and tol_r = 1e-5 (~100 eps) the relative
     * reduction float can resolve. The LG quotient [V(d1)-V(d0)]/(d1-d0) loses about
     * eps |V| / |d1 - d0| to cancellation; tol_q = 1e-3 keeps that below ~1e-4 relative for
     * distances and potentials of order one (the double default 1e-8 would let the
     * quotient be pure round-off). */
    p.tol_q = EDMI_R(1e-3);
    p.tol_r = EDMI_R(1e-5);
    p.tol_a = EDMI_R(1e-6);
#endif
    return p;
}

edmi_status edmi_set_params(edmi_system *sys, const edmi_params *params)
{
    if (!sys || !params)
        return EDMI_ERR_NULL;
    if (!edmi__params_valid(params))
        return EDMI_ERR_PARAM;
    sys->params = *params;
    return EDMI_OK;
}

edmi_status edmi_init(edmi_system *sys, const edmi_params *params)
{
    edmi_params p = params ? *params : edmi_default_params();
    unsigned char *bytes;
    unsigned long i;
    if (!sys)
        return EDMI_ERR_NULL;
    if (!edmi__params_valid(&p))
        return EDMI_ERR_PARAM;
    /* Zero every byte (padding included) so that snapshots compare with memcmp. */
    bytes = (unsigned char *)sys;
    for (i = 0; i < (unsigned long)sizeof *sys; i++)
        bytes[i] = 0;
    sys->n_bodies = 0;
    sys->n_links = 0;
    sys->t = EDMI__ZERO;
    sys->params = p;
    return EDMI_OK;
}

edmi_status edmi_add_body(edmi_system *sys, edmi_real m, const edmi_real q[3],
                          const edmi_real p[3], int *index)
{
    edmi_body *bd;
    if (!sys || !q || !p)
        return EDMI_ERR_NULL;
    if (!edmi__finite(m) || !(m > EDMI__ZERO))
        return EDMI_ERR_MASS;
    if (!edmi__finite3(q) || !edmi__finite3(p))
        return EDMI_ERR_NONFINITE;
    if (sys->n_bodies >= EDMI_MAX_BODIES)
        return EDMI_ERR_CAPACITY;
    bd = &sys->body[sys->n_bodies];
    bd->m = m;
    edmi__copy3(q, bd->q);
    edmi__copy3(p, bd->p);
    if (index)
        *index = sys->n_bodies;
    sys->n_bodies++;
    return EDMI_OK;
}

/* Write a link field by field into zeroed storage: never copy a caller's padding bytes, so
 * that equal systems compare equal with memcmp (edmi_init zeroes every byte). */
static void edmi__write_link(edmi_link *dst, int a, int b, const edmi_real x[3],
                             const edmi_potential *pot)
{
    dst->a = a;
    dst->b = b;
    edmi__copy3(x, dst->anchor);
    dst->pot.kind = pot->kind;
    dst->pot.a = pot->a;
    dst->pot.b = pot->b;
    dst->pot.fn = pot->fn;
    dst->pot.dd = pot->dd;
    dst->pot.ctx = pot->ctx;
}

static edmi_status edmi__add_link(edmi_system *sys, int a, int b, const edmi_real x[3],
                                  const edmi_potential *pot, int *index)
{
    static const edmi_real origin[3] = {EDMI__ZERO, EDMI__ZERO, EDMI__ZERO};
    if (!sys || !pot || (b == EDMI_ANCHOR && !x))
        return EDMI_ERR_NULL;
    if (!edmi__link_ends_valid(sys->n_bodies, a, b))
        return EDMI_ERR_INDEX;
    if (!edmi__pot_valid(pot))
        return EDMI_ERR_PARAM;
    if (x && !edmi__finite3(x))
        return EDMI_ERR_NONFINITE;
    if (sys->n_links >= EDMI_MAX_LINKS)
        return EDMI_ERR_CAPACITY;
    edmi__write_link(&sys->link[sys->n_links], a, b, x ? x : origin, pot);
    if (index)
        *index = sys->n_links;
    sys->n_links++;
    return EDMI_OK;
}

edmi_status edmi_add_pair(edmi_system *sys, int a, int b, const edmi_potential *pot,
                          int *index)
{
    if (b == EDMI_ANCHOR)
        return sys ? EDMI_ERR_INDEX : EDMI_ERR_NULL;
    return edmi__add_link(sys, a, b, 0, pot, index);
}

edmi_status edmi_add_anchor(edmi_system *sys, int a, const edmi_real x[3],
                            const edmi_potential *pot, int *index)
{
    if (!x)
        return EDMI_ERR_NULL;
    return edmi__add_link(sys, a, EDMI_ANCHOR, x, pot, index);
}

edmi_status edmi_set_field(edmi_system *sys, const edmi_real g[3])
{
    if (!sys || !g)
        return EDMI_ERR_NULL;
    if (!edmi__finite3(g))
        return EDMI_ERR_NONFINITE;
    edmi__copy3(g, sys->g);
    sys->has_field = 1;
    return EDMI_OK;
}

edmi_status edmi_add_damper(edmi_system *sys, int link, edmi_real c, int *index)
{
    if (!sys)
        return EDMI_ERR_NULL;
    if (link < 0 || link >= sys->n_links)
        return EDMI_ERR_INDEX;
    if (!edmi__finite(c) || c < EDMI__ZERO)
        return EDMI_ERR_PARAM;
    if (sys->n_dampers >= EDMI_MAX_DAMPERS)
        return EDMI_ERR_CAPACITY;
    sys->damper[sys->n_dampers].link = link;
    sys->damper[sys->n_dampers].c = c;
    if (index)
        *index = sys->n_dampers;
    sys->n_dampers++;
    return EDMI_OK;
}

edmi_status edmi_set_force(edmi_system *sys, int a, const edmi_real f[3])
{
    int i;
    if (!sys || !f)
        return EDMI_ERR_NULL;
    if (a < 0 || a >= sys->n_bodies)
        return EDMI_ERR_INDEX;
    if (!edmi__finite3(f))
        return EDMI_ERR_NONFINITE;
    for (i = 0; i < sys->n_forced && sys->forced[i] != a; i++)
        ;
    if (i == sys->n_forced)
        sys->forced[sys->n_forced++] = a;
    edmi__copy3(f, sys->force[a]);
    return EDMI_OK;
}

edmi_status edmi_load_scene(edmi_system *sys, const edmi_scene *scene)
{
    edmi_params p;
    int i;
    if (!sys || !scene || (scene->n_bodies > 0 && !scene->bodies) ||
        (scene->n_links > 0 && !scene->links) || (scene->n_dampers > 0 && !scene->dampers))
        return EDMI_ERR_NULL;
    p = scene->params ? *scene->params : edmi_default_params();
    if (scene->n_bodies < 0 || scene->n_bodies > EDMI_MAX_BODIES || scene->n_links < 0 ||
        scene->n_links > EDMI_MAX_LINKS || scene->n_dampers < 0 ||
        scene->n_dampers > EDMI_MAX_DAMPERS)
        return EDMI_ERR_CAPACITY;
    if (!edmi__params_valid(&p))
        return EDMI_ERR_PARAM;
    if (scene->has_field && !edmi__finite3(scene->g))
        return EDMI_ERR_NONFINITE;
    for (i = 0; i < scene->n_bodies; i++) {
        const edmi_body *bd = &scene->bodies[i];
        if (!edmi__finite(bd->m) || !(bd->m > EDMI__ZERO))
            return EDMI_ERR_MASS;
        if (!edmi__finite3(bd->q) || !edmi__finite3(bd->p))
            return EDMI_ERR_NONFINITE;
    }
    for (i = 0; i < scene->n_links; i++) {
        const edmi_link *lk = &scene->links[i];
        if (!edmi__link_ends_valid(scene->n_bodies, lk->a, lk->b))
            return EDMI_ERR_INDEX;
        if (!edmi__pot_valid(&lk->pot))
            return EDMI_ERR_PARAM;
        if (!edmi__finite3(lk->anchor))
            return EDMI_ERR_NONFINITE;
    }
    for (i = 0; i < scene->n_dampers; i++) {
        const edmi_damper *d = &scene->dampers[i];
        if (d->link < 0 || d->link >= scene->n_links)
            return EDMI_ERR_INDEX;
        if (!edmi__finite(d->c) || d->c < EDMI__ZERO)
            return EDMI_ERR_PARAM;
    }
    /* validated: now replace */
    (void)edmi_init(sys, &p);
    for (i = 0; i < scene->n_bodies; i++) {
        const edmi_body *bd = &scene->bodies[i];
        sys->body[i].m = bd->m;
        edmi__copy3(bd->q, sys->body[i].q);
        edmi__copy3(bd->p, sys->body[i].p);
    }
    for (i = 0; i < scene->n_links; i++) {
        const edmi_link *lk = &scene->links[i];
        edmi__write_link(&sys->link[i], lk->a, lk->b, lk->anchor, &lk->pot);
    }
    for (i = 0; i < scene->n_dampers; i++) {
        sys->damper[i].link = scene->dampers[i].link;
        sys->damper[i].c = scene->dampers[i].c;
    }
    sys->n_bodies = scene->n_bodies;
    sys->n_links = scene->n_links;
    sys->n_dampers = scene->n_dampers;
    if (scene->has_field) {
        sys->has_field = 1;
        edmi__copy3(scene->g, sys->g);
    }
    return EDMI_OK;
}

static edmi_potential edmi__pot(edmi_pot_kind kind, edmi_real a, edmi_real b)
{
    edmi_potential p;
    p.kind = kind;
    p.a = a;
    p.b = b;
    p.fn = 0;
    p.dd = 0;
    p.ctx = 0;
    return p;
}

edmi_potential edmi_pot_harmonic(edmi_real k, edmi_real r0)
{
    return edmi__pot(EDMI_POT_HARMONIC, k, r0);
}

edmi_potential edmi_pot_quartic(edmi_real k, edmi_real len)
{
    return edmi__pot(EDMI_POT_QUARTIC, k, len);
}

edmi_potential edmi_pot_neo_hooke(edmi_real c, edmi_real rbar)
{
    return edmi__pot(EDMI_POT_NEO_HOOKE, c, rbar);
}

edmi_potential edmi_pot_lj(edmi_real eps, edmi_real sigma)
{
    return edmi__pot(EDMI_POT_LJ, eps, sigma);
}

edmi_potential edmi_pot_inverse(edmi_real k) { return edmi__pot(EDMI_POT_INVERSE, k, EDMI__ZERO); }

edmi_potential edmi_pot_user(edmi_user_pot_fn fn, edmi_user_dd_fn dd, void *ctx)
{
    edmi_potential p = edmi__pot(EDMI_POT_USER, EDMI__ZERO, EDMI__ZERO);
    p.fn = fn;
    p.dd = dd;
    p.ctx = ctx;
    return p;
}

/* ==========================================================================================
 * Misc
 * ======================================================================================== */

const char *edmi_status_name(edmi_status s)
{
    switch (s) {
    case EDMI_OK: return "EDMI_OK";
    case EDMI_ERR_NULL: return "EDMI_ERR_NULL";
    case EDMI_ERR_DT: return "EDMI_ERR_DT";
    case EDMI_ERR_MASS: return "EDMI_ERR_MASS";
    case EDMI_ERR_NONFINITE: return "EDMI_ERR_NONFINITE";
    case EDMI_ERR_CAPACITY: return "EDMI_ERR_CAPACITY";
    case EDMI_ERR_INDEX: return "EDMI_ERR_INDEX";
    case EDMI_ERR_PARAM: return "EDMI_ERR_PARAM";
    case EDMI_ERR_COINCIDENT: return "EDMI_ERR_COINCIDENT";
    case EDMI_ERR_SINGULAR: return "EDMI_ERR_SINGULAR";
    case EDMI_ERR_NO_CONVERGENCE: return "EDMI_ERR_NO_CONVERGENCE";
    case EDMI_ERR_DIVERGED: return "EDMI_ERR_DIVERGED";
    default: return "EDMI_ERR_UNKNOWN";
    }
}

int edmi_is_double_precision(void) { return EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_; }
