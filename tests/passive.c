/* The passivity inequality on stored states, checked in long double, and the adversarial
 * scenes of the guard's suite and soak (see passive.h).
 *
 * Independence. The library certifies H(q_n+1, p_n+1) - H(q_n, p_n) <= work_ext +
 * work_anchor with its own double-word evaluation. The check here shares none of that code:
 * it evaluates each link's V(|q_a - x_b|) of both stored states in long double from the
 * potentials' textbook formulas and each body's kinetic change as (p1 - p0).(p1 + p0)/2m,
 * subtracts term by term, and bounds its own rounding by TP_ERR_ULPS units of long double's
 * epsilon times the terms' magnitudes M (tp_pot: M u bounds a term's error, u = eps/2; the
 * factor 16 eps = 32 u covers the dozen roundings along each formula and the sums over
 * terms). On x86-64 long double has 64 bits of significand: for float states the check
 * resolves ~1e-17 of the terms, far below float's grid (~6e-8 of them per unit of a
 * coordinate), for double states ~1e-17 too, a tenth of double's grid. On the Arm targets
 * long double is double: float states are still resolved (~4e-15), double states only to
 * about their own grid, which is what the count `uncertain` reports. */
#include "passive.h"

#include <float.h>
#include <string.h>

#include "../examples/haptic_hand.h" /* hh_sin: a sine without libm */

#define TP_ERR_ULPS 16.0L

static long double tp_absl(long double x) { return x < 0.0L ? -x : x; }

static long double tp_sqrtl(long double x) { return x > 0.0L ? __builtin_sqrtl(x) : 0.0L; }

/* V(d) of a built-in potential in long double, with s = d^2, and a magnitude M with
 * |computed V - V| <= M u (u = LDBL_EPSILON/2) for the formula as written: each of its
 * roundings is at most u times an intermediate that M bounds, and the rounding of d itself
 * (at most 4u d after the link vector's difference, the sum of squares and the square root)
 * moves V by |V'| 4u d, which M also bounds. Near a rest length V is small but the rounding
 * of d - rb is not, hence terms like |d - rb| (d + rb), with |d - rb| taken as |x| + 4 eps
 * (d + rb), x as computed: where the rounding of d hides all of x (x computed 0, the true one
 * 1e-20 at d = 1: V = 5e-41 seen as 0), V's error is second order in it, a (4 eps d)^2, and
 * M still bounds it. 0 for a user potential (not checkable here). */
static int tp_pot(const edmi_potential *p, long double s, long double d, long double *v,
                  long double *mag)
{
    long double a = (long double)p->a, b = (long double)p->b, x, t, xe;
    switch (p->kind) {
    case EDMI_POT_HARMONIC: /* V' d = a |x| d */
        x = d - b;
        xe = tp_absl(x) + 4.0L * LDBL_EPSILON * (d + b);
        *v = 0.5L * a * x * x;
        *mag = 4.0L * a * xe * (d + b) + 4.0L * *v;
        return 1;
    case EDMI_POT_QUARTIC: /* V' d = a |x| s */
        x = s - b * b;
        xe = tp_absl(x) + 8.0L * LDBL_EPSILON * (s + b * b);
        *v = 0.25L * a * x * x;
        *mag = 4.0L * a * xe * (s + b * b) + 4.0L * *v;
        return 1;
    case EDMI_POT_NEO_HOOKE: /* V' d = a/3 |x| (d^2 + d b + b^2) / d */
        if (!(d > 0.0L))
            return 0;
        x = d - b;
        xe = tp_absl(x) + 4.0L * LDBL_EPSILON * (d + b);
        *v = a * x * x * (d + 2.0L * b) / (6.0L * d);
        *mag = 2.0L * a * xe * (d + b) * (d + 2.0L * b) / d + 8.0L * *v;
        return 1;
    case EDMI_POT_LJ: /* V' d = 4 a (12 t^12 + 6 t^6) */
        if (!(d > 0.0L))
            return 0;
        t = b / d;
        t = t * t * t * t * t * t;
        *v = 4.0L * a * t * (t - 1.0L);
        *mag = 4.0L * a * t * (t + 1.0L) * 64.0L;
        return 1;
    case EDMI_POT_INVERSE: /* V' d = |V| */
        if (!(d > 0.0L))
            return 0;
        *v = -a / d;
        *mag = 8.0L * tp_absl(a) / d;
        return 1;
    case EDMI_POT_USER:
    default:
        return 0;
    }
}

/* The link vector of link j in state s, and its squared length, in long double. */
static long double tp_link_sq(const edmi_system *s, int j, long double *d)
{
    const edmi_link *lk = &s->link[j];
    const edmi_real *xb = lk->b == EDMI_ANCHOR ? lk->anchor : s->body[lk->b].q;
    long double r0 = (long double)s->body[lk->a].q[0] - (long double)xb[0];
    long double r1 = (long double)s->body[lk->a].q[1] - (long double)xb[1];
    long double r2 = (long double)s->body[lk->a].q[2] - (long double)xb[2];
    long double sq = r0 * r0 + r1 * r1 + r2 * r2;
    *d = tp_sqrtl(sq);
    return sq;
}

#if EDMI_MAX_MASS_GAP > 0
/* m_ab of a coupled mass matrix (issue 12), a != b; 0 beyond the gap. */
static long double tp_mass_ab(const edmi_system *s, int a, int b)
{
    int hi = a > b ? a : b, k = (a > b ? a - b : b - a) - 1;
    return k < EDMI_MAX_MASS_GAP ? (long double)s->mass_off[hi][k] : 0.0L;
}

static int tp_coupled(const edmi_system *s)
{
    int a, k;
    for (a = 1; a < s->n_bodies; a++)
        for (k = 0; k < EDMI_MAX_MASS_GAP && k < a; k++)
            if (s->mass_off[a][k] != 0)
                return 1;
    return 0;
}

/* The extreme eigenvalues of the symmetric n x n matrix m, by cyclic Jacobi rotations on a
 * copy (no library code), each within 8 n eps ||m||_F of its computed value (Jacobi is
 * backward stable): *lmin is the lower end of that interval, *lmax the upper. */
static void tp_eig_range(long double m[EDMI_MAX_BODIES][EDMI_MAX_BODIES], int n,
                         long double *lmin, long double *lmax)
{
    static long double a[EDMI_MAX_BODIES][EDMI_MAX_BODIES];
    long double fro = 0.0L, off;
    int i, j, k, p, q, sweep;
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) {
            a[i][j] = m[i][j];
            fro += m[i][j] * m[i][j];
        }
    for (sweep = 0; sweep < 64; sweep++) {
        for (off = 0.0L, i = 0; i < n; i++)
            for (j = 0; j < n; j++)
                off += i != j ? a[i][j] * a[i][j] : 0.0L;
        if (!(off > LDBL_EPSILON * LDBL_EPSILON * fro))
            break;
        for (p = 0; p < n; p++)
            for (q = p + 1; q < n; q++) {
                long double th, t, c, s;
                if (a[p][q] == 0.0L)
                    continue;
                th = (a[q][q] - a[p][p]) / (2.0L * a[p][q]);
                t = (th >= 0.0L ? 1.0L : -1.0L) / (tp_absl(th) + tp_sqrtl(th * th + 1.0L));
                c = 1.0L / tp_sqrtl(t * t + 1.0L);
                s = t * c;
                for (k = 0; k < n; k++) { /* columns p, q */
                    long double kp = a[k][p], kq = a[k][q];
                    a[k][p] = c * kp - s * kq;
                    a[k][q] = s * kp + c * kq;
                }
                for (k = 0; k < n; k++) { /* rows p, q */
                    long double pk = a[p][k], qk = a[q][k];
                    a[p][k] = c * pk - s * qk;
                    a[q][k] = s * pk + c * qk;
                }
            }
    }
    *lmin = LDBL_MAX;
    *lmax = -LDBL_MAX;
    for (i = 0; i < n; i++) {
        if (a[i][i] < *lmin)
            *lmin = a[i][i];
        if (a[i][i] > *lmax)
            *lmax = a[i][i];
    }
    fro = tp_sqrtl(fro) * 8.0L * (long double)n * LDBL_EPSILON;
    *lmin -= fro;
    *lmax += fro;
}

/* K(p1) - K(p0) = 1/2 (p1 - p0) . M^-1 (p1 + p0) of a coupled M, by Gaussian elimination on
 * the dense M in long double (no library code), and a bound on its error: a few units of
 * long double times kappa(M) times the terms, kappa from M's extreme eigenvalues (Jacobi,
 * tp_eig_range). 0 if M is not positive definite to long double's resolution. */
static int tp_delta_k_coupled(const edmi_system *s0, const edmi_system *s1, long double *dk,
                              long double *mag) /* s0 NULL: K(p1) itself */
{
    static long double m[EDMI_MAX_BODIES][EDMI_MAX_BODIES], x[EDMI_MAX_BODIES][3];
    long double lmin, lmax, kappa, t;
    int n = s1->n_bodies, a, b, c, k;
#define TP_P0(a, c) (s0 ? (long double)s0->body[a].p[c] : 0.0L)
    for (a = 0; a < n; a++) {
        for (b = 0; b < n; b++)
            m[a][b] = a == b ? (long double)s1->body[a].m : tp_mass_ab(s1, a, b);
        for (c = 0; c < 3; c++)
            x[a][c] = (long double)s1->body[a].p[c] + TP_P0(a, c);
    }
    tp_eig_range(m, n, &lmin, &lmax);
    if (!(lmin > 0.0L))
        return 0;
    kappa = lmax / lmin;
    for (k = 0; k < n; k++) /* positive definite: no pivoting needed */
        for (a = k + 1; a < n; a++) {
            long double f = m[a][k] / m[k][k];
            if (f == 0.0L)
                continue;
            for (b = k; b < n; b++)
                m[a][b] -= f * m[k][b];
            for (c = 0; c < 3; c++)
                x[a][c] -= f * x[k][c];
        }
    for (a = n - 1; a >= 0; a--)
        for (c = 0; c < 3; c++) {
            t = x[a][c];
            for (b = a + 1; b < n; b++)
                t -= m[a][b] * x[b][c];
            x[a][c] = t / m[a][a];
        }
    *dk = 0.0L;
    *mag = 0.0L;
    for (a = 0; a < n; a++)
        for (c = 0; c < 3; c++) {
            long double d = (long double)s1->body[a].p[c] - TP_P0(a, c);
            *dk += 0.5L * d * x[a][c];
            *mag += 8.0L * (long double)(n + 2) * kappa * tp_absl(d * x[a][c]);
        }
#undef TP_P0
    return 1;
}
#endif

int tp_delta_h(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res,
               tp_delta *out)
{
    long double dh = 0.0L, mag = 0.0L;
    int a, i, j, coupled = 0;
#if EDMI_MAX_MASS_GAP > 0
    if (tp_coupled(s0)) {
        coupled = 1;
        if (!tp_delta_k_coupled(s0, s1, &dh, &mag))
            return 0;
        if (s0->has_field) /* V = -sum_ab m_ab g . q_a: the off-diagonal masses' part */
            for (a = 0; a < s0->n_bodies; a++) {
                int b;
                for (b = 0; b < s0->n_bodies; b++)
                    for (i = 0; i < 3 && b != a; i++) {
                        long double g = (long double)s0->g[i], m = tp_mass_ab(s0, a, b);
                        long double dq = (long double)s1->body[a].q[i] -
                                         (long double)s0->body[a].q[i];
                        dh -= m * g * dq;
                        mag += 8.0L * tp_absl(m * g * dq);
                    }
            }
    }
#endif
    for (a = 0; a < s0->n_bodies; a++) {
        long double m2 = 2.0L * (long double)s0->body[a].m, k = 0.0L, km = 0.0L;
        /* K1 - K0 = sum (p1 - p0)(p1 + p0) / 2m: p1 - p0 exact or within u of itself (two
         * stored values, at most 53 significant bits, in 64), so the error is a few u
         * times the terms of the change, not of K */
        for (i = 0; i < 3 && !coupled; i++) {
            long double p0 = (long double)s0->body[a].p[i], p1 = (long double)s1->body[a].p[i];
            k += (p1 - p0) * (p1 + p0);
            km += tp_absl(p1 - p0) * (tp_absl(p1) + tp_absl(p0));
        }
        dh += k / m2;
        mag += 8.0L * km / m2;
        if (s0->has_field) /* V = -m g . q, changed by -m g . (q1 - q0) */
            for (i = 0; i < 3; i++) {
                long double g = (long double)s0->g[i], m = (long double)s0->body[a].m;
                long double dq = (long double)s1->body[a].q[i] - (long double)s0->body[a].q[i];
                dh -= m * g * dq;
                mag += 8.0L * tp_absl(m * g * dq);
            }
    }
    for (j = 0; j < s0->n_links; j++) {
        long double d0, d1, sq0 = tp_link_sq(s0, j, &d0), sq1 = tp_link_sq(s1, j, &d1);
        long double v0, v1, m0, m1;
        if (!tp_pot(&s0->link[j].pot, sq0, d0, &v0, &m0) ||
            !tp_pot(&s1->link[j].pot, sq1, d1, &v1, &m1))
            return 0;
        dh += v1 - v0;
        mag += m0 + m1;
    }
    out->dh = dh;
    out->w = (long double)res->work_ext + (long double)res->work_anchor +
             ((long double)s0->tank - (long double)s1->tank);
    out->err = TP_ERR_ULPS * LDBL_EPSILON *
               (mag + tp_absl((long double)res->work_ext) + tp_absl((long double)res->work_anchor) +
                (long double)s0->tank + (long double)s1->tank);
    out->mag = mag;
    return dh - dh == 0.0L && out->err - out->err == 0.0L;
}

long double tp_h(const edmi_system *s)
{
    long double h = 0.0L;
    int a, i, j, coupled = 0;
#if EDMI_MAX_MASS_GAP > 0
    if (tp_coupled(s)) {
        long double mag;
        coupled = 1;
        if (!tp_delta_k_coupled(0, s, &h, &mag))
            return LDBL_MAX; /* not evaluated (M not provably definite): no H */
        if (s->has_field)
            for (a = 0; a < s->n_bodies; a++) {
                int b;
                for (b = 0; b < s->n_bodies; b++)
                    for (i = 0; i < 3 && b != a; i++)
                        h -= tp_mass_ab(s, a, b) * (long double)s->g[i] *
                             (long double)s->body[a].q[i];
            }
    }
#endif
    for (a = 0; a < s->n_bodies; a++) {
        long double k = 0.0L;
        for (i = 0; i < 3 && !coupled; i++)
            k += (long double)s->body[a].p[i] * (long double)s->body[a].p[i];
        h += k / (2.0L * (long double)s->body[a].m);
        if (s->has_field)
            for (i = 0; i < 3; i++)
                h -= (long double)s->body[a].m * (long double)s->g[i] *
                     (long double)s->body[a].q[i];
    }
    for (j = 0; j < s->n_links; j++) {
        long double d, sq = tp_link_sq(s, j, &d), v, m;
        if (tp_pot(&s->link[j].pot, sq, d, &v, &m))
            h += v;
    }
    return h;
}

/* ---- scenes ------------------------------------------------------------------------------ */

const char *tp_scene_name(tp_scene s)
{
    static const char *const names[TP_NSCENES] = {
        "paper spring",          "virtual spring, pumping port F = +c v",
        "virtual spring, random port", "virtual spring, port flipping sign every tick",
        "stiff harmonic, omega dt = 100", "LJ near-collisions on tethers",
        "virtual coupling through d = 0", "hanging chain, field, dampers, random port"};
    return (unsigned)s < (unsigned)TP_NSCENES ? names[s] : "?";
}

/* A deterministic uniform random number in [-1, 1) (a 32-bit LCG; the state is per run). */
static unsigned long tp_seed;

static edmi_real tp_rand(void)
{
    tp_seed = (tp_seed * 1664525UL + 1013904223UL) & 0xffffffffUL;
    return (edmi_real)((long)(tp_seed >> 8) - 0x800000L) / (edmi_real)0x800000L;
}

/* The hand of TP_COUPLING at time t: through the origin (where the body starts) at t = 0,
 * 20-60 mm excursions at 1, 3 and 7 Hz. */
static void tp_hand(edmi_real t, edmi_real x[3])
{
    static const edmi_real w = EDMI_R(6.283185307179586);
    x[0] = EDMI_R(0.05) * hh_sin(w * t) + EDMI_R(0.02) * hh_sin(EDMI_R(7.0) * w * t);
    x[1] = EDMI_R(0.03) * hh_sin(EDMI_R(3.0) * w * t);
    x[2] = EDMI_R(0.01) * hh_sin(EDMI_R(2.0) * w * t);
}

static edmi_status tp_body(edmi_system *sys, edmi_real m, edmi_real x, edmi_real y, edmi_real z,
                           edmi_real px, edmi_real py, edmi_real pz)
{
    edmi_real q[3], p[3];
    q[0] = x, q[1] = y, q[2] = z;
    p[0] = px, p[1] = py, p[2] = pz;
    return edmi_add_body(sys, m, q, p, 0);
}

static edmi_status tp_anchor(edmi_system *sys, int a, edmi_real x, edmi_real y, edmi_real z,
                             edmi_potential pot)
{
    edmi_real p[3];
    p[0] = x, p[1] = y, p[2] = z;
    return edmi_add_anchor(sys, a, p, &pot, 0);
}

edmi_status tp_build(tp_scene s, const edmi_params *prm, edmi_system *sys, edmi_real *dt)
{
    edmi_params p = *prm;
    edmi_status st;
    p.fallback = 1; /* as a control loop runs it: a failed solve stores the fallback state */
    st = edmi_init(sys, &p);
    static const edmi_real gz[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-9.81)};
    int i;
    tp_seed = 12345UL + (unsigned long)s;
    if (st != EDMI_OK)
        return st;
    switch (s) {
    case TP_SPRING:
        *dt = EDMI_R(1e-3);
        st = tp_body(sys, EDMI_R(10.0), EDMI_R(2.0), EDMI_R(1.0), EDMI_R(1.0), EDMI_R(-30.0),
                     EDMI_R(15.0), EDMI_R(45.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0)));
        return st;
    case TP_PUMP:
    case TP_RANDOM:
    case TP_FLIP:
        *dt = EDMI_R(1e-3);
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.06), EDMI_R(0.01), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.02), EDMI_R(0.01));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_harmonic(EDMI_R(1e4), EDMI_R(0.05)));
        if (st == EDMI_OK && s == TP_PUMP)
            st = edmi_add_damper(sys, 0, EDMI_R(0.05), 0);
        return st;
    case TP_STIFF: /* float Newton fails here once in a few thousand steps */
        *dt = EDMI_R(0.1);
        st = tp_body(sys, EDMI_R(1.0), EDMI_R(1.0), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(300.0), EDMI_R(100.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_harmonic(EDMI_R(1e6), EDMI_R(0.5)));
        return st;
    case TP_COLLIDE: {
        edmi_potential lj = edmi_pot_lj(EDMI_R(100.0), EDMI_R(1.0));
        edmi_potential tether = edmi_pot_harmonic(EDMI_R(50.0), EDMI_R(0.0));
        *dt = EDMI_R(5e-4);
        st = tp_body(sys, EDMI_R(1.0), EDMI_R(-1.5), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(30.0),
                     EDMI_R(0.3), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_body(sys, EDMI_R(1.0), EDMI_R(1.5), EDMI_R(0.05), EDMI_R(0.0),
                         EDMI_R(-30.0), EDMI_R(-0.2), EDMI_R(0.1));
        if (st == EDMI_OK)
            st = edmi_add_pair(sys, 0, 1, &lj, 0);
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(-1.5), EDMI_R(0.0), EDMI_R(0.0), tether);
        if (st == EDMI_OK)
            st = tp_anchor(sys, 1, EDMI_R(1.5), EDMI_R(0.0), EDMI_R(0.0), tether);
        return st;
    }
    case TP_COUPLING:
        *dt = EDMI_R(1e-3);
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_harmonic(EDMI_R(1e3), EDMI_R(0.0)));
        if (st == EDMI_OK)
            st = edmi_add_damper(sys, 0, EDMI_R(0.5), 0);
        return st;
    case TP_CHAIN:
    default: {
        static const edmi_real mass[4] = {EDMI_R(1.0), EDMI_R(2.0), EDMI_R(1.5), EDMI_R(0.5)};
        edmi_potential spring = edmi_pot_neo_hooke(EDMI_R(500.0), EDMI_R(1.0));
        *dt = EDMI_R(1e-3);
        for (i = 0; i < 4 && st == EDMI_OK; i++)
            st = tp_body(sys, mass[i], EDMI_R(0.3) * (edmi_real)(i + 1), EDMI_R(0.0),
                         -EDMI_R(0.9) * (edmi_real)(i + 1), EDMI_R(0.0),
                         EDMI_R(0.5) * (edmi_real)i, EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0), spring);
        for (i = 1; i < 4 && st == EDMI_OK; i++)
            st = edmi_add_pair(sys, i - 1, i, &spring, 0);
        for (i = 0; i < 4 && st == EDMI_OK; i++)
            st = edmi_add_damper(sys, i, EDMI_R(0.2), 0);
        if (st == EDMI_OK)
            st = edmi_set_field(sys, gz);
        return st;
    }
    }
}

void tp_control(tp_scene s, edmi_system *sys, long n)
{
    edmi_real f[3], x[3];
    int i;
    switch (s) {
    case TP_PUMP: { /* F = +c v, |F| <= 2 N: a controller that pumps energy in */
        edmi_real c = EDMI_R(0.3) / sys->body[0].m, mag;
        for (i = 0; i < 3; i++)
            f[i] = c * sys->body[0].p[i];
        mag = EDMI_SQRT(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        if (mag > EDMI_R(2.0))
            for (i = 0; i < 3; i++)
                f[i] *= EDMI_R(2.0) / mag;
        (void)edmi_set_force(sys, 0, f);
        break;
    }
    case TP_RANDOM:
        for (i = 0; i < 3; i++)
            f[i] = EDMI_R(5.0) * tp_rand();
        (void)edmi_set_force(sys, 0, f);
        break;
    case TP_FLIP:
        f[0] = EDMI_R(3.0), f[1] = EDMI_R(2.0), f[2] = EDMI_R(1.0);
        if (n & 1)
            for (i = 0; i < 3; i++)
                f[i] = -f[i];
        (void)edmi_set_force(sys, 0, f);
        break;
    case TP_COUPLING:
        tp_hand((edmi_real)(n + 1) * EDMI_R(1e-3), x);
        (void)edmi_move_anchor(sys, 0, x);
        break;
    case TP_CHAIN:
        for (i = 0; i < 3; i++)
            f[i] = EDMI_R(2.0) * tp_rand();
        (void)edmi_set_force(sys, 3, f);
        break;
    default:
        break;
    }
}

/* Snapshots: systems are tens of kB, too large for a target's stack. */
static edmi_system tp_sys, tp_old;
static edmi_workspace tp_work;

static void tp_j(const edmi_system *s, long double j[3])
{
    int a;
    j[0] = j[1] = j[2] = 0.0L;
    for (a = 0; a < s->n_bodies; a++) {
        long double q0 = s->body[a].q[0], q1 = s->body[a].q[1], q2 = s->body[a].q[2];
        long double p0 = s->body[a].p[0], p1 = s->body[a].p[1], p2 = s->body[a].p[2];
        j[0] += q1 * p2 - q2 * p1;
        j[1] += q2 * p0 - q0 * p2;
        j[2] += q0 * p1 - q1 * p0;
    }
}

void tp_run(tp_scene s, const edmi_params *prm, long n, tp_stats *st)
{
    edmi_real dt;
    long double j0[3], jn, scale;
    long k;
    int track_j = s == TP_SPRING || s == TP_STIFF;
    /* over the steps m so far: min of A_m + T_m and of A_m, A_m = H_m - sum_{k<m} W_k, and the
     * accumulated error of A */
    long double a_min = 0.0L, a_low = 0.0L, a_err = 0.0L;
    st->steps = st->violations = st->rises = st->uncertain = 0;
    st->fallbacks = st->guarded = st->iterations = 0;
    st->window_violations = st->tank_violations = 0;
    st->worst = -1.0L;
    st->sum_w = st->max_dj = st->max_window = st->max_cap = st->window_err = 0.0L;
    st->status = tp_build(s, prm, &tp_sys, &dt);
    if (st->status != EDMI_OK)
        return;
    st->h0 = st->h_last = tp_h(&tp_sys);
    scale = tp_absl(st->h0) > 0.0L ? tp_absl(st->h0) : 1.0L;
    a_min = st->h0 + (long double)tp_sys.tank;
    a_low = st->h0;
    tp_j(&tp_sys, j0);
    jn = tp_sqrtl(j0[0] * j0[0] + j0[1] * j0[1] + j0[2] * j0[2]);
    for (k = 0; k < n; k++) {
        edmi_step_result res;
        tp_delta d;
        tp_control(s, &tp_sys, k);
        tp_old = tp_sys;
        st->status = edmi_step(&tp_sys, &tp_work, dt, &res);
        if (st->status != EDMI_OK)
            return;
        st->steps++;
        st->iterations += res.iterations;
        st->fallbacks += res.stop == EDMI_STOP_FALLBACK;
        st->guarded += res.guard_action != 0;
        if (!tp_delta_h(&tp_old, &tp_sys, &res, &d)) {
            st->violations++; /* a state the check cannot evaluate is not accepted */
            continue;
        }
        st->violations += d.dh - d.w > d.err;
        st->uncertain += tp_absl(d.dh - d.w) <= d.err;
        st->rises += d.dh > d.err;
        if ((d.dh - d.w) / scale > st->worst)
            st->worst = (d.dh - d.w) / scale;
        /* the works alone (d.w holds the tank's part too) */
        st->sum_w += (long double)res.work_ext + (long double)res.work_anchor;
        st->tank_violations += !(tp_sys.tank >= 0 && tp_sys.tank <= res.tank_cap &&
                                 tp_sys.tank == res.tank);
        if ((long double)res.tank_cap / scale > st->max_cap)
            st->max_cap = (long double)res.tank_cap / scale;
        {
            /* windows: A_n = H_n - sum_{k<n} W_k must stay <= A_m + T_m for every m < n. A_n
             * from this step's change (H_n = H_n-1 + dh, not a fresh H: its rounding is in
             * d.err, accumulated into a_err) */
            long double a_n = st->h_last + d.dh - st->sum_w;
            a_err += d.err + LDBL_EPSILON * (tp_absl(st->sum_w) + tp_absl(a_n));
            if ((a_n - a_low) / scale > st->max_window)
                st->max_window = (a_n - a_low) / scale;
            st->window_violations += a_n - a_min > a_err;
            st->h_last += d.dh;
            if (a_n + (long double)tp_sys.tank < a_min)
                a_min = a_n + (long double)tp_sys.tank;
            if (a_n < a_low)
                a_low = a_n;
        }
        if (track_j && (k & 63) == 0) {
            long double j[3], dj;
            tp_j(&tp_sys, j);
            dj = tp_sqrtl((j[0] - j0[0]) * (j[0] - j0[0]) + (j[1] - j0[1]) * (j[1] - j0[1]) +
                          (j[2] - j0[2]) * (j[2] - j0[2])) / jn;
            if (dj > st->max_dj)
                st->max_dj = dj;
        }
    }
    st->h_last = tp_h(&tp_sys);
    st->window_err = a_err / scale;
}

/* ---- rest is a fixed point; user potentials guarded as the built-ins are ------------------- */

const char *tp_rest_name(tp_rest s)
{
    static const char *const names[TP_NREST] = {
        "zero-rest-length spring settling onto its anchor", "body exactly on its anchor, p = 0",
        "neo-Hookean spring settling at its rest length", "pair spring, two bodies settling together",
        "zero-rest-length spring settling onto an anchor at (0.25, -1, 3)",
        "pair spring, masses 0.1 and 0.3, meeting off the origin",
        "user potential = harmonic(50, 1)"};
    return (unsigned)s < (unsigned)TP_NREST ? names[s] : "?";
}

int tp_user_harmonic_fn(void *ctx, edmi_real r, edmi_pot_parts *out)
{
    const tp_user_harmonic *u = (const tp_user_harmonic *)ctx;
    edmi_real x = r - u->r0;
    int j;
    out->c[0] = EDMI_R(0.5) * u->k * x * x;
    out->c[1] = u->k * x;
    out->c[2] = u->k;
    out->c[3] = EDMI_R(0.0);
    out->c[4] = EDMI_R(0.0);
    for (j = 0; j < 5; j++) {
        out->sp[j] = out->c[j];
        out->e[j] = out->sm[j] = EDMI_R(0.0);
    }
    return 0;
}

int tp_user_harmonic_dd(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd, edmi_real *dd_d1)
{
    const tp_user_harmonic *u = (const tp_user_harmonic *)ctx;
    *dd = EDMI_R(0.5) * u->k * ((d1 - u->r0) + (d0 - u->r0));
    *dd_d1 = EDMI_R(0.5) * u->k;
    return 0;
}

/* TP_REST_USER's potential: the built-in edmi_pot_harmonic(50, 1) written as a user one */
static tp_user_harmonic tp_user_ctx = {EDMI_R(50.0), EDMI_R(1.0)};

edmi_status tp_rest_build(tp_rest s, const edmi_params *prm, int damper, int user_dd,
                          edmi_system *sys, edmi_real *dt)
{
    edmi_potential zero = edmi_pot_harmonic(EDMI_R(1e4), EDMI_R(0.0));
    edmi_status st = edmi_init(sys, prm);
    int j;
    *dt = EDMI_R(1e-3);
    if (st != EDMI_OK)
        return st;
    switch (s) {
    case TP_REST_ANCHOR:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.01), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0), zero);
        break;
    case TP_REST_ON_ANCHOR:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.25), EDMI_R(-1.0), EDMI_R(3.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.25), EDMI_R(-1.0), EDMI_R(3.0), zero);
        break;
    case TP_REST_NEO_HOOKE:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(1.2), EDMI_R(0.3), EDMI_R(-0.1), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(1.0)));
        break;
    case TP_REST_PAIR:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.005), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_body(sys, EDMI_R(0.1), -EDMI_R(0.005), EDMI_R(0.0), EDMI_R(0.0),
                         EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = edmi_add_pair(sys, 0, 1, &zero, 0);
        break;
    case TP_REST_OFF_ANCHOR:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.26), EDMI_R(-1.0), EDMI_R(3.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.25), EDMI_R(-1.0), EDMI_R(3.0), zero);
        break;
    case TP_REST_PAIR_OFF:
        st = tp_body(sys, EDMI_R(0.1), EDMI_R(0.0075), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_body(sys, EDMI_R(0.3), -EDMI_R(0.0025), EDMI_R(0.0), EDMI_R(0.0),
                         EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = edmi_add_pair(sys, 0, 1, &zero, 0);
        break;
    case TP_REST_USER:
    default:
        st = tp_body(sys, EDMI_R(1.0), EDMI_R(1.3), EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                     EDMI_R(2.0), EDMI_R(0.0));
        if (st == EDMI_OK)
            st = tp_anchor(sys, 0, EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0),
                           edmi_pot_user(tp_user_harmonic_fn, user_dd ? tp_user_harmonic_dd : 0,
                                         &tp_user_ctx));
        break;
    }
    for (j = 0; damper && j < sys->n_links && st == EDMI_OK; j++)
        st = edmi_add_damper(sys, j, EDMI_R(5.0), 0);
    return st;
}

/* x 2^e, in steps of 2^60, 2^8 and 2: exact wherever the result and the steps are normal
 * (a few operations even where long double is soft-float, as on the Cortex-M4F) */
static long double tp_ldexp(long double x, int e)
{
    static const long double big = 1152921504606846976.0L; /* 2^60 */
    while (e >= 60 && x != 0.0L) {
        x *= big;
        e -= 60;
    }
    while (e <= -60 && x != 0.0L) {
        x /= big;
        e += 60;
    }
    for (; e >= 8; e -= 8)
        x *= 256.0L;
    for (; e <= -8; e += 8)
        x *= 1.0L / 256.0L;
    for (; e > 0; e--)
        x *= 2.0L;
    for (; e < 0; e++)
        x *= 0.5L;
    return x;
}

/* e with 2^(e-1) <= x < 2^e, for x > 0 (exact: only powers of two multiply it) */
static int tp_exponent(long double x)
{
    static const long double big = 1152921504606846976.0L, small = 1.0L / 1152921504606846976.0L;
    int e = 0;
    while (x >= big) {
        x *= small;
        e += 60;
    }
    while (x < small) {
        x *= big;
        e -= 60;
    }
    for (; x >= 256.0L; e += 8)
        x *= 1.0L / 256.0L;
    for (; x < 1.0L / 256.0L; e -= 8)
        x *= 256.0L;
    for (; x >= 1.0L; e++)
        x *= 0.5L;
    for (; x < 0.5L; e--)
        x *= 2.0L;
    return e;
}

/* A zero-rest-length harmonic spring: H's part in it is homogeneous of degree 2 in (r, p). */
static int tp_homogeneous(const edmi_potential *p)
{
    return p->kind == EDMI_POT_HARMONIC && p->b == 0;
}

static void tp_link_vec(const edmi_system *s, int j, long double r[3])
{
    const edmi_link *lk = &s->link[j];
    const edmi_real *xb = lk->b == EDMI_ANCHOR ? lk->anchor : s->body[lk->b].q;
    int i;
    for (i = 0; i < 3; i++)
        r[i] = (long double)s->body[lk->a].q[i] - (long double)xb[i];
}

/* V of a link that is not homogeneous, unscaled: as tp_pot, and tp_user_harmonic_fn's V */
static int tp_rest_pot(const edmi_potential *p, const long double r[3], long double *v,
                       long double *mag)
{
    long double s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2], d = tp_sqrtl(s);
    if (p->kind == EDMI_POT_USER) {
        const tp_user_harmonic *u = (const tp_user_harmonic *)p->ctx;
        edmi_potential h;
        if (p->fn != tp_user_harmonic_fn)
            return 0;
        h = edmi_pot_harmonic(u->k, u->r0);
        return tp_pot(&h, s, d, v, mag);
    }
    return tp_pot(p, s, d, v, mag);
}

int tp_rest_delta(const edmi_system *s0, const edmi_system *s1, const edmi_step_result *res,
                  long double *excess, int *exponent)
{
    const edmi_system *st[2];
    long double big = 0.0L, hs = 0.0L, ms = 0.0L, hu = 0.0L, mu = 0.0L, f1, f2, t[3], wt;
    long double r[3];
    int a, i, j, k, s, e;
    st[0] = s0;
    st[1] = s1;
    if (s0->has_field || s0->n_bodies != s1->n_bodies || s0->n_links != s1->n_links)
        return 0;
    /* s: the largest |p| and |r| of the homogeneous links, and sqrt of T and |W|, to ~1 */
    for (k = 0; k < 2; k++) {
        for (a = 0; a < st[k]->n_bodies; a++)
            for (i = 0; i < 3; i++)
                if (tp_absl((long double)st[k]->body[a].p[i]) > big)
                    big = tp_absl((long double)st[k]->body[a].p[i]);
        for (j = 0; j < st[k]->n_links; j++)
            if (tp_homogeneous(&st[k]->link[j].pot)) {
                tp_link_vec(st[k], j, r);
                for (i = 0; i < 3; i++)
                    if (tp_absl(r[i]) > big)
                        big = tp_absl(r[i]);
            }
    }
    e = big > 0.0L ? tp_exponent(big) : INT_MIN / 4;
    t[0] = (long double)s0->tank;
    t[1] = (long double)s1->tank;
    t[2] = tp_absl((long double)res->work_ext + (long double)res->work_anchor);
    wt = t[0] > t[1] ? t[0] : t[1];
    wt = wt > t[2] ? wt : t[2];
    if (wt > 0.0L) {
        int et = tp_exponent(wt);
        et = et > 0 ? (et + 1) / 2 : et / 2; /* ceil(et / 2) */
        e = et > e ? et : e;
    }
    s = e == INT_MIN / 4 ? 0 : -e;
    /* 2^s as two factors within double's exponent range (|s| <= 1075 + 60) */
    f1 = tp_ldexp(1.0L, s / 2);
    f2 = tp_ldexp(1.0L, s - s / 2);
    /* the scaled part: K, the homogeneous links, T and W, in units of 2^-2s */
    for (a = 0; a < s0->n_bodies; a++) {
        long double k2 = 0.0L, km = 0.0L, m2 = 2.0L * (long double)s0->body[a].m;
        for (i = 0; i < 3; i++) {
            long double p0 = (long double)s0->body[a].p[i] * f1 * f2;
            long double p1 = (long double)s1->body[a].p[i] * f1 * f2;
            k2 += (p1 - p0) * (p1 + p0);
            km += tp_absl(p1 - p0) * (tp_absl(p1) + tp_absl(p0));
        }
        hs += k2 / m2;
        ms += 8.0L * km / m2;
    }
    for (j = 0; j < s0->n_links; j++) {
        const edmi_potential *p = &s0->link[j].pot;
        if (tp_homogeneous(p)) {
            long double v[2];
            for (k = 0; k < 2; k++) {
                tp_link_vec(st[k], j, r);
                for (i = 0; i < 3; i++)
                    r[i] = r[i] * f1 * f2;
                v[k] = 0.5L * (long double)p->a * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            }
            hs += v[1] - v[0];
            ms += 16.0L * (v[0] + v[1]);
        } else {
            long double v0, v1, m0, m1;
            tp_link_vec(s0, j, r);
            if (!tp_rest_pot(p, r, &v0, &m0))
                return 0;
            tp_link_vec(s1, j, r);
            if (!tp_rest_pot(&s1->link[j].pot, r, &v1, &m1))
                return 0;
            hu += v1 - v0;
            mu += m0 + m1;
        }
    }
    for (i = 0; i < 3; i++)
        t[i] = t[i] * f1 * f1 * f2 * f2;
    hs -= ((long double)res->work_ext + (long double)res->work_anchor) * f1 * f1 * f2 * f2 +
          (t[0] - t[1]);
    ms += t[0] + t[1] + t[2];
    /* the check's own rounding (as tp_delta_h: 16 eps of the terms), and what underflowed */
    ms = TP_ERR_ULPS * LDBL_EPSILON * ms + LDBL_MIN;
    mu = TP_ERR_ULPS * LDBL_EPSILON * mu;
    if (hu == 0.0L && mu == 0.0L) {
        *excess = hs - ms;
        *exponent = -2 * s;
    } else { /* an unscaled part: combine in unscaled units */
        *excess = hu - mu + tp_ldexp(hs - ms, -2 * s) - LDBL_MIN;
        *exponent = 0;
    }
    return *excess - *excess == 0.0L && *excess <= 0.0L;
}

/* |r| without underflow: the largest component times the norm of r over it */
static long double tp_norm_scaled(const long double r[3])
{
    long double m = tp_absl(r[0]), x, y, z;
    m = tp_absl(r[1]) > m ? tp_absl(r[1]) : m;
    m = tp_absl(r[2]) > m ? tp_absl(r[2]) : m;
    if (m == 0.0L)
        return 0.0L;
    x = r[0] / m, y = r[1] / m, z = r[2] / m;
    return m * tp_sqrtl(x * x + y * y + z * z);
}

/* How far scene s is from rest: its link's length, or that length's distance from the rest
 * length (neo-Hookean spring, user potential). */
static long double tp_rest_dist(tp_rest s, const edmi_system *sys)
{
    long double r[3], d;
    tp_link_vec(sys, 0, r);
    d = tp_norm_scaled(r);
    if (s == TP_REST_NEO_HOOKE || s == TP_REST_USER)
        d = tp_absl(d - 1.0L); /* both rest lengths are 1 */
    return d;
}

/* H of a state of a tp_rest scene (no field), in long double: for the user potential's
 * energies, O(1) (no scaling) */
static long double tp_rest_h(const edmi_system *s)
{
    long double h = 0.0L, r[3], v, m;
    int a, i, j;
    for (a = 0; a < s->n_bodies; a++)
        for (i = 0; i < 3; i++)
            h += (long double)s->body[a].p[i] * (long double)s->body[a].p[i] /
                 (2.0L * (long double)s->body[a].m);
    for (j = 0; j < s->n_links; j++) {
        tp_link_vec(s, j, r);
        if (tp_homogeneous(&s->link[j].pot))
            h += 0.5L * (long double)s->link[j].pot.a * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        else if (tp_rest_pot(&s->link[j].pot, r, &v, &m))
            h += v;
    }
    return h;
}

long double tp_rest_bound(tp_rest s, long double qmax)
{
#if EDMI_PREC_(EDMI_REAL) == EDMI_DOUBLE_
    const long double sigma = 4.9406564584124654e-324L; /* 2^-1074 */
#else
    const long double sigma = 1.4012984643248171e-45L; /* 2^-149 */
#endif
    if (s == TP_REST_NEO_HOOKE)
        return 4.0L * (long double)EDMI_EPS;
    return s == TP_REST_USER ? LDBL_MAX : 64.0L * sigma + 16.0L * (long double)EDMI_EPS * qmax;
}

static int tp_guard_on(const edmi_params *p)
{
    return p->guard == EDMI_GUARD_ON ||
           (p->guard == EDMI_GUARD_AUTO && p->scheme != EDMI_MP && p->scheme != EDMI_LG);
}

static edmi_system tp_ref;

void tp_rest_run(tp_rest s, const edmi_params *prm, int damper, int user_dd, long n,
                 tp_rest_stats *st)
{
    edmi_real dt;
    long k;
    int i, guard = tp_guard_on(prm);
    st->steps = st->fallbacks = st->scaled = st->stops = st->guarded = 0;
    st->uncertified = st->violations = st->tank_violations = 0;
    st->fail_step = st->last_change = -1;
    st->dist = st->tail_dist = st->qmax = st->ref_diff = st->ref_amp = 0.0L;
    st->ref_status = EDMI_OK;
    st->ref_guarded = 0;
    st->status = tp_rest_build(s, prm, damper, user_dd, &tp_sys, &dt);
    if (st->status != EDMI_OK)
        return;
    if (s == TP_REST_USER) { /* the reference: the built-in potential, the same parameters */
        edmi_potential h = edmi_pot_harmonic(tp_user_ctx.k, tp_user_ctx.r0);
        tp_ref = tp_sys;
        tp_ref.link[0].pot = h;
    }
    st->h0 = tp_rest_h(&tp_sys);
    tp_old = tp_sys; /* then only what a step changes and tp_rest_delta reads: bodies, tank */
    for (k = 0; k < n; k++) {
        edmi_step_result res;
        long double excess, d;
        int exponent;
        memcpy(tp_old.body, tp_sys.body, (size_t)tp_sys.n_bodies * sizeof tp_sys.body[0]);
        tp_old.tank = tp_sys.tank;
        st->status = edmi_step(&tp_sys, &tp_work, dt, &res);
        if (st->status != EDMI_OK) {
            st->fail_step = k;
            for (i = 0; i < 3; i++) {
                st->fail_q[i] = tp_sys.body[0].q[i];
                st->fail_p[i] = tp_sys.body[0].p[i];
            }
            st->fail_tank = tp_sys.tank;
            break;
        }
        st->steps++;
        st->fallbacks += res.stop == EDMI_STOP_FALLBACK;
        st->scaled += res.certificate == EDMI_CERT_SCALED;
        st->stops += (res.guard_action & EDMI_GUARD_STOP) != 0;
        st->guarded += res.guard_action != 0;
        if (memcmp(tp_old.body, tp_sys.body, (size_t)tp_sys.n_bodies * sizeof tp_sys.body[0]))
            st->last_change = k;
        if (guard) {
            st->uncertified += res.certificate == EDMI_CERT_NONE;
            st->tank_violations += !(tp_sys.tank >= 0 && tp_sys.tank <= res.tank_cap &&
                                     tp_sys.tank == res.tank);
        }
        st->violations += !tp_rest_delta(&tp_old, &tp_sys, &res, &excess, &exponent);
        d = tp_rest_dist(s, &tp_sys);
        if (k >= n - n / 4) {
            int a, j;
            st->tail_dist = d > st->tail_dist ? d : st->tail_dist;
            for (a = 0; a < tp_sys.n_bodies; a++)
                for (i = 0; i < 3; i++)
                    if (tp_absl((long double)tp_sys.body[a].q[i]) > st->qmax)
                        st->qmax = tp_absl((long double)tp_sys.body[a].q[i]);
            for (j = 0; j < tp_sys.n_links; j++)
                for (i = 0; tp_sys.link[j].b == EDMI_ANCHOR && i < 3; i++)
                    if (tp_absl((long double)tp_sys.link[j].anchor[i]) > st->qmax)
                        st->qmax = tp_absl((long double)tp_sys.link[j].anchor[i]);
        }
        if (s == TP_REST_USER) {
            long double r[3], x;
            edmi_step_result rr;
            st->ref_status = edmi_step(&tp_ref, &tp_work, dt, &rr);
            st->ref_guarded += rr.guard_action != 0;
            if (st->ref_status != EDMI_OK)
                break;
            for (i = 0; i < 3; i++)
                r[i] = (long double)tp_sys.body[0].q[i] - (long double)tp_ref.body[0].q[i];
            x = tp_norm_scaled(r);
            st->ref_diff = x > st->ref_diff ? x : st->ref_diff;
            for (i = 0; i < 3; i++)
                r[i] = (long double)tp_ref.body[0].q[i];
            x = tp_norm_scaled(r);
            st->ref_amp = x > st->ref_amp ? x : st->ref_amp;
        }
    }
    st->dist = tp_rest_dist(s, &tp_sys);
    st->h_end = tp_rest_h(&tp_sys);
    st->h_ref_end = s == TP_REST_USER ? tp_rest_h(&tp_ref) : st->h_end;
}
