/* libFuzzer harness over edmi's whole public API (one source, built once per precision).
 *
 * The input bytes are a program: parameters, a scene (bodies, every potential kind with
 * random, extreme and non-finite parameters, user potentials with limited domains or
 * non-finite values, pairs, anchors, dampers, a field, ports), then a sequence of calls to
 * every public function, including direct writes to the system's fields as firmware makes
 * them (a state, a count overwritten). After every call it checks the library's promise:
 *   - the status is a member of edmi_status;
 *   - on an error, the system and every output are byte-identical to before the call;
 *   - on success of edmi_step: a finite state and clock, iterations within l_max, a result
 *     whose fields are finite, and with the guard on the passivity inequality
 *     H(q_n+1, p_n+1) - H(q_n, p_n) <= work_ext + work_anchor + T_n - T_n+1 on the stored
 *     values and the window form H_n - H_m <= the works in between + T_m over every run of
 *     guarded steps (tp_window_step), both evaluated in __float128 by tests/lib/passive.c (no
 *     library code) within its own bound, user potentials included (as the built-in one
 *     each callback computes); the tank within its capacity, and 0 with tank_cap 0;
 *   - on success of edmi_step that is not a fallback: the stored state solves the scheme
 *     to the bound edmi.h states (EDMI_SOLVED), judged with this harness's own magnitudes
 *     (fz_check_solved);
 *   - on success of edmi_invariants_of, edmi_pot_eval, edmi_pot_divdiff, edmi_residual,
 *     edmi_tangent: finite outputs.
 * A broken promise prints what broke and aborts, so libFuzzer stores the input.
 * tests/fuzz/replay.c runs the same function over stored inputs without libFuzzer. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>

#include "edmi.h"
#include "passive.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* ---- the input as a stream of bytes (zeros once it runs out) ---------------------------- */

typedef struct fz_in {
    const uint8_t *d;
    size_t n, i;
} fz_in;

static unsigned fz_u8(fz_in *in) { return in->i < in->n ? in->d[in->i++] : 0u; }

static unsigned long fz_bits(fz_in *in, int bytes)
{
    unsigned long v = 0;
    int k;
    for (k = 0; k < bytes; k++)
        v = (v << 8) | fz_u8(in);
    return v;
}

static int fz_done(const fz_in *in) { return in->i >= in->n; }

/* A real: mostly moderate values a scene would use, sometimes any exponent, raw bit
 * patterns (NaN, infinities, subnormals) and the format's edge values. */
static edmi_real fz_real(fz_in *in)
{
    static const double table[16] = {0.0, 1.0, -1.0, 0.5, 2.0, 1e-3, 10.0, 0.1,
                                     -0.0, 100.0, 1e-6, 3.0, 0.25, -2.0, 1e3, 1e6};
    unsigned sel = fz_u8(in);
    switch (sel >> 5) {
    case 0:
        return (edmi_real)table[sel & 15u];
    case 1:
    case 2:
    case 3:
    case 4: {
        int m = (int)(signed char)fz_u8(in);
        int e = (int)(fz_u8(in) % 17u) - 8;
        return (edmi_real)ldexp((double)m / 16.0, e);
    }
    case 5: { /* any exponent of the format */
        int lo = edmi_is_double_precision() ? -1080 : -155;
        int span = edmi_is_double_precision() ? 2110 : 290;
        double m = 1.0 + (double)fz_u8(in) / 256.0;
        int e = lo + (int)(fz_bits(in, 2) % (unsigned long)span);
        return (edmi_real)((sel & 1u) ? -ldexp(m, e) : ldexp(m, e));
    }
    case 6: { /* raw bits */
        edmi_real x;
        if (sizeof x == 4) {
            uint32_t b = (uint32_t)fz_bits(in, 4);
            memcpy(&x, &b, sizeof x);
        } else {
            uint64_t b = ((uint64_t)fz_bits(in, 4) << 32) | (uint64_t)fz_bits(in, 4);
            memcpy(&x, &b, sizeof x);
        }
        return x;
    }
    default: {
        switch (sel & 15u) {
        case 0: return (edmi_real)INFINITY;
        case 1: return (edmi_real)-INFINITY;
        case 2: return (edmi_real)NAN;
        case 3: return EDMI_REAL_MAX;
        case 4: return -EDMI_REAL_MAX;
        case 5: return edmi_is_double_precision() ? (edmi_real)DBL_MIN : (edmi_real)FLT_MIN;
        case 6: return edmi_is_double_precision() ? (edmi_real)4.9e-324 : (edmi_real)1.4e-45f;
        case 7: return EDMI_EPS;
        case 8: return (edmi_real)1.9e19;
        case 9: return (edmi_real)1e-20;
        case 10: return (edmi_real)(edmi_is_double_precision() ? 1.4e154 : 1e30);
        case 11: return (edmi_real)(edmi_is_double_precision() ? 1e-155 : 1e-30);
        case 12: return (edmi_real)735.29;
        case 13: return (edmi_real)1e12;
        case 14: return (edmi_real)1e-12;
        default: return (edmi_real)-1e-300;
        }
    }
    }
}

/* A real meant to be positive (masses, stiffnesses, steps): |x| most of the time. */
static edmi_real fz_pos(fz_in *in)
{
    unsigned s = fz_u8(in);
    edmi_real x = fz_real(in);
    return (s & 7u) ? (edmi_real)fabs((double)x) : x;
}

static void fz_vec(fz_in *in, edmi_real v[3])
{
    int i;
    for (i = 0; i < 3; i++)
        v[i] = fz_real(in);
}

/* An int near the valid range of a count or index n, sometimes far outside it. */
static int fz_index(fz_in *in, int n)
{
    unsigned s = fz_u8(in);
    if (s < 224u)
        return n > 0 ? (int)(s % (unsigned)n) : 0;
    switch (s & 7u) {
    case 0: return -1;
    case 1: return n;
    case 2: return n + 1;
    case 3: return -2;
    case 4: return 1 << 30;
    case 5: return -(1 << 30);
    case 6: return EDMI_ANCHOR;
    default: return (int)fz_bits(in, 1) - 128;
    }
}

/* ---- user potentials -------------------------------------------------------------------- */

typedef struct fz_user {
    int kind;        /* 0: harmonic; 1: harmonic refusing r outside [lo, hi]; 2: NaN beyond hi */
    double k, r0, lo, hi;
} fz_user;

#define FZ_MAX_USER 8 /* per input; never reused, so a live link's ctx never changes */
static fz_user fz_users[FZ_MAX_USER];
/* built-ins behind a user callback (tests/lib/passive.c, tp_user_builtin_fn): the harmonic and
 * inverse ones, whose V' edmi_pot_eval gives to a few units in the last place everywhere (a
 * user potential's promise) */
static edmi_potential fz_wrapped[FZ_MAX_USER];


static int fz_user_fn(void *ctx, edmi_real r, edmi_pot_parts *o)
{
    const fz_user *u = (const fz_user *)ctx;
    double x = (double)r, k = u->k, s = x - u->r0;
    int i;
    if (u->kind == 1 && (x < u->lo || x > u->hi))
        return 1;
    for (i = 0; i < 5; i++)
        o->c[i] = o->e[i] = o->sp[i] = o->sm[i] = (edmi_real)0;
    o->c[0] = (edmi_real)(0.5 * k * s * s);
    o->c[1] = (edmi_real)(k * s);
    o->c[2] = (edmi_real)k;
    for (i = 0; i < 5; i++)
        o->sp[i] = o->c[i];
    if (u->kind == 2 && x > u->hi)
        o->c[1] = (edmi_real)NAN;
    return 0;
}

static int fz_user_dd(void *ctx, edmi_real d0, edmi_real d1, edmi_real *dd, edmi_real *dd_d1)
{
    const fz_user *u = (const fz_user *)ctx;
    double a = (double)d0, b = (double)d1;
    if (u->kind == 1 && (a < u->lo || a > u->hi || b < u->lo || b > u->hi))
        return 1;
    *dd = (edmi_real)(u->k * (0.5 * (a + b) - u->r0));
    *dd_d1 = (edmi_real)(0.5 * u->k);
    return 0;
}

/* The built-in potential whose V fz_user_fn computes, for the check (tp_user_register). */
static int fz_user_map(const edmi_potential *p, edmi_potential *b)
{
    const fz_user *u = (const fz_user *)p->ctx;
    if (p->fn != fz_user_fn)
        return 0;
    *b = edmi_pot_harmonic((edmi_real)u->k, (edmi_real)u->r0);
    return 1;
}

static edmi_potential fz_potential(fz_in *in, int *n_user)
{
    unsigned kind = fz_u8(in) % 8u;
    edmi_real a = fz_pos(in), b = fz_pos(in);
    edmi_potential p;
    switch (kind) {
    case 0: return edmi_pot_harmonic(a, b);
    case 1: return edmi_pot_quartic(a, b);
    case 2: return edmi_pot_neo_hooke(a, b);
    case 3: return edmi_pot_lj(a, b);
    case 4: return edmi_pot_inverse(fz_real(in));
    case 5:
    case 6: {
        fz_user *u;
        if (*n_user >= FZ_MAX_USER)
            return edmi_pot_harmonic(a, b);
        u = &fz_users[(*n_user)++];
        u->kind = (int)(fz_u8(in) % 3u);
        u->k = (double)a;
        u->r0 = (double)b;
        u->lo = (double)fz_pos(in);
        u->hi = u->lo + (double)fz_pos(in);
        p = edmi_pot_user((fz_u8(in) & 1u) ? fz_user_fn : 0, (fz_u8(in) & 1u) ? fz_user_dd : 0,
                          u);
        if (kind == 6 && !p.fn)
            p.fn = fz_user_fn;
        if (kind == 6 && (fz_u8(in) & 3u) == 0u) { /* a built-in behind a user callback */
            edmi_potential *w = &fz_wrapped[*n_user - 1];
            *w = (fz_u8(in) & 1u) ? edmi_pot_inverse(fz_real(in)) : edmi_pot_harmonic(a, b);
            p = edmi_pot_user(tp_user_builtin_fn, (fz_u8(in) & 1u) ? tp_user_builtin_dd : 0, w);
        }
        return p;
    }
    default: /* the one-sided forms, or an invalid kind */
        switch (fz_u8(in) % 4u) {
        case 0: return edmi_pot_contact(a, b);
        case 1: return edmi_pot_tether(a, b);
        default:
            p = edmi_pot_harmonic(a, b);
            p.kind = (edmi_pot_kind)(int)(fz_u8(in) % 2u ? 42 : -1);
            return p;
        }
    }
}

static edmi_params fz_params(fz_in *in)
{
    edmi_params p = edmi_default_params();
    unsigned s = fz_u8(in), f = fz_u8(in);
    p.scheme = (edmi_scheme)(int)(s % 5u);
    if ((s & 0xf0u) == 0xf0u)
        p.scheme = (edmi_scheme)(int)(s % 8u); /* sometimes out of range */
    p.lg_form = (edmi_lg_form)(int)(f & 1u);
    p.lg_alt = (edmi_lg_alt)(int)((f >> 1) % 5u);
    p.guard = (edmi_guard_mode)(int)((f >> 4) % 3u);
    p.fallback = (int)((f >> 6) & 1u);
    p.energy_balance = (int)((f >> 7) & 1u);
    s = fz_u8(in);
    if (s & 1u)
        p.tol_q = fz_real(in);
    if (s & 2u)
        p.tol_r = fz_real(in);
    if (s & 4u)
        p.tol_a = fz_real(in);
    if (s & 8u)
        p.l_max = (int)(fz_u8(in) % 40u) - 2;
    if (s & 16u) { /* 0 to 4 levels of substeps, sometimes out of range (-1, 11) */
        unsigned k = fz_u8(in);
        p.substep_levels = (k & 0xf0u) == 0xf0u ? ((k & 1u) ? -1 : EDMI_MAX_SUBSTEP_LEVELS + 1)
                                                : (int)(k % 5u);
    }
    if ((s & 0xf0u) == 0xf0u) /* an out-of-range enum */
        p.guard = (edmi_guard_mode)7;
    else if ((s & 0x30u) == 0x10u) /* no tank: the per-step inequality */
        p.tank_cap = (edmi_real)0;
    else if ((s & 0x30u) == 0x20u) /* any capacity, invalid ones too */
        p.tank_cap = fz_real(in);
    return p;
}

/* ---- the checks ------------------------------------------------------------------------- */

static void fz_fail(const char *what, const char *call, edmi_status st)
{
    fprintf(stderr, "edmi fuzz (%s): %s after %s (status %d %s)\n",
            edmi_is_double_precision() ? "double" : "float", what, call, (int)st,
            edmi_status_name(st));
    abort();
}

static int fz_finite(edmi_real x) { return x - x == x - x; }

static int fz_finite_n(const edmi_real *x, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!fz_finite(x[i]))
            return 0;
    return 1;
}

static void fz_status(edmi_status st, const char *call)
{
    if ((int)st < (int)EDMI_OK || (int)st > (int)EDMI_ERR_DOMAIN)
        fz_fail("status out of range", call, st);
}

/* On error: nothing the caller owns changed (sys and the output buffer). */
static void fz_unchanged(edmi_status st, const char *call, const edmi_system *sys,
                         const edmi_system *before, const void *out, const void *out_before,
                         size_t out_size)
{
    fz_status(st, call);
    if (st == EDMI_OK)
        return;
    if (sys && memcmp(sys, before, sizeof *sys) != 0)
        fz_fail("system changed on error", call, st);
    if (out && memcmp(out, out_before, out_size) != 0)
        fz_fail("output written on error", call, st);
}

static int fz_guard_on(const edmi_params *p)
{
    return p->guard == EDMI_GUARD_ON ||
           (p->guard == EDMI_GUARD_AUTO &&
            (p->scheme == EDMI_SCHEME_GE || p->scheme == EDMI_SCHEME_PM || p->scheme == EDMI_SCHEME_PT));
}

/* The state the library hands back after a successful step. */
static void fz_check_step(const edmi_system *s0, const edmi_system *s1, edmi_real dt,
                          const edmi_step_result *res)
{
    int a;
    tp_delta d;
    for (a = 0; a < s1->n_bodies; a++)
        if (!fz_finite_n(s1->body[a].q, 3) || !fz_finite_n(s1->body[a].p, 3))
            fz_fail("non-finite state", "edmi_step", EDMI_OK);
    if (!fz_finite(s1->t) || !fz_finite(s1->internal.t_carry))
        fz_fail("clock not finite", "edmi_step", EDMI_OK);
    { /* compensated: t - t_carry advances by dt, up to the roundings of Kahan's sum, a few
       * eps of |t| and |t_carry| (t itself may step back by one unit when dt is below its
       * spacing and the carry above dt; a caller may have written t_carry) */
        long double t0 = (long double)s0->t - (long double)s0->internal.t_carry;
        long double t1 = (long double)s1->t - (long double)s1->internal.t_carry;
        long double e = t1 - t0 - (long double)dt;
        long double mag = fabsl((long double)s0->t) + fabsl((long double)s0->internal.t_carry) +
                          fabsl((long double)s1->t) + fabsl((long double)s1->internal.t_carry) +
                          (long double)dt;
        if (e < 0)
            e = -e;
        if (!(e <= 4.0L * (long double)EDMI_EPS * mag)) {
            fprintf(stderr, "t %.21Lg carry %.21Lg -> t %.21Lg carry %.21Lg, dt %.21Lg\n",
                    (long double)s0->t, (long double)s0->internal.t_carry, (long double)s1->t,
                    (long double)s1->internal.t_carry, (long double)dt);
            fz_fail("clock not advanced by dt", "edmi_step", EDMI_OK);
        }
    }
    for (a = 0; a < s1->n_links; a++)
        if (!fz_finite_n(s1->link_force[a], 3))
            fz_fail("non-finite link force", "edmi_step", EDMI_OK);
    if (res->iterations < 0 ||
        res->iterations > s0->params.l_max * ((2 << s0->params.substep_levels) - 1))
        fz_fail("iterations outside [0, l_max (2^(k+1) - 1)]", "edmi_step", EDMI_OK);
    if (res->substeps < 1 || res->substeps > (1 << s0->params.substep_levels) ||
        res->fallbacks < 0 || res->fallbacks > res->substeps ||
        (res->fallbacks > 0) != (res->stop == EDMI_STOP_FALLBACK) ||
        (res->cause == EDMI_OK) != (res->substeps == 1 && res->fallbacks == 0))
        fz_fail("substeps, fallbacks or cause not as the step went", "edmi_step", EDMI_OK);
    if ((int)res->stop < (int)EDMI_STOP_CONVERGED || (int)res->stop > (int)EDMI_STOP_FALLBACK)
        fz_fail("stop out of range", "edmi_step", EDMI_OK);
    if (!fz_finite(res->work_ext) || !fz_finite(res->work_anchor) ||
        !fz_finite(res->diss_damping) || !fz_finite(res->diss_scheme) || !fz_finite(res->dh) ||
        !fz_finite(res->diss_guard)) {
        fprintf(stderr, "work_ext %g work_anchor %g diss_damping %g diss_scheme %g dh %g "
                        "diss_guard %g\n", (double)res->work_ext, (double)res->work_anchor,
                (double)res->diss_damping, (double)res->diss_scheme, (double)res->dh,
                (double)res->diss_guard);
        fz_fail("non-finite energy balance", "edmi_step", EDMI_OK);
    }
    if (!(res->diss_damping >= 0))
        fz_fail("negative damper dissipation", "edmi_step", EDMI_OK);
    if (res->tank != s1->tank || (int)res->certificate < (int)EDMI_CERT_NONE ||
        (int)res->certificate > (int)EDMI_CERT_SCALED)
        fz_fail("tank or certificate not as reported", "edmi_step", EDMI_OK);
    if (!fz_guard_on(&s0->params) && s1->tank != s0->tank)
        fz_fail("tank changed with the guard off", "edmi_step", EDMI_OK);
    if (fz_guard_on(&s0->params) &&
        !(s1->tank >= 0 && s1->tank <= res->tank_cap && fz_finite(res->tank_cap)))
        fz_fail("tank negative or above its capacity", "edmi_step", EDMI_OK);
    if (fz_guard_on(&s0->params) && !(s0->params.tank_cap > 0) &&
        !(s1->tank == 0 && res->tank_cap == 0))
        fz_fail("a tank with tank_cap 0", "edmi_step", EDMI_OK);
    if (!fz_guard_on(&s0->params))
        return;
    if (!tp_delta_h(s0, s1, res, &d))
        fz_fail("stored state cannot be evaluated by tests/lib/passive.c", "edmi_step", EDMI_OK);
    if (d.broken) {
        fprintf(stderr, "dH = %.21Lg, work + T_n - T_n+1 = %.21Lg, dH - that %.3Lg, bound %.3Lg "
                "(%s)\n", d.dh, d.w, d.diff, d.err, tp_q_name());
        fz_fail("passivity: H rose by more than the work and the tank", "edmi_step", EDMI_OK);
    }
    if (tp_window_step(s0, s1, res) != 1)
        fz_fail("passivity: a window of steps rose by more than its work and T_m", "edmi_step",
                EDMI_OK);
}

/* FZ_TRACE=1 in the environment prints the system before every step (triage). */
static int fz_trace = -1;

static void fz_print_sys(const edmi_system *s, edmi_real dt)
{
    int a, j;
    fprintf(stderr, "step dt=%.9g t=%.9g scheme=%d guard=%d lg_form=%d alt=%d tol_q=%g "
                    "tol_r=%g tol_a=%g l_max=%d fallback=%d eb=%d tank_cap=%g tank=%.9g\n",
            (double)dt, (double)s->t, (int)s->params.scheme, (int)s->params.guard,
            (int)s->params.lg_form, (int)s->params.lg_alt, (double)s->params.tol_q,
            (double)s->params.tol_r, (double)s->params.tol_a, s->params.l_max,
            s->params.fallback, s->params.energy_balance, (double)s->params.tank_cap,
            (double)s->tank);
    for (a = 0; a < s->n_bodies; a++)
        fprintf(stderr, "  body %d m=%.9g q=(%.9g %.9g %.9g) p=(%.9g %.9g %.9g)\n", a,
                (double)s->body[a].m, (double)s->body[a].q[0], (double)s->body[a].q[1],
                (double)s->body[a].q[2], (double)s->body[a].p[0], (double)s->body[a].p[1],
                (double)s->body[a].p[2]);
    for (j = 0; j < s->n_links; j++)
        fprintf(stderr, "  link %d %d-%d kind=%d a=%.9g b=%.9g anchor=(%.9g %.9g %.9g)\n", j,
                s->link[j].a, s->link[j].b, (int)s->link[j].pot.kind, (double)s->link[j].pot.a,
                (double)s->link[j].pot.b, (double)s->link[j].anchor[0],
                (double)s->link[j].anchor[1], (double)s->link[j].anchor[2]);
    for (j = 0; j < s->n_dampers; j++)
        fprintf(stderr, "  damper link %d c=%.9g\n", s->damper[j].link, (double)s->damper[j].c);
    for (j = 0; j < s->internal.n_forced; j++)
        fprintf(stderr, "  force on %d (%.9g %.9g %.9g)\n", s->internal.forced[j],
                (double)s->force[s->internal.forced[j]][0], (double)s->force[s->internal.forced[j]][1],
                (double)s->force[s->internal.forced[j]][2]);
    for (j = 0; j < s->internal.n_moving; j++)
        fprintf(stderr, "  anchor %d moves to (%.9g %.9g %.9g)\n", s->internal.moving[j],
                (double)s->internal.anchor_next[s->internal.moving[j]][0], (double)s->internal.anchor_next[s->internal.moving[j]][1],
                (double)s->internal.anchor_next[s->internal.moving[j]][2]);
    if (s->has_field)
        fprintf(stderr, "  field (%.9g %.9g %.9g)\n", (double)s->g[0], (double)s->g[1],
                (double)s->g[2]);
#if EDMI_MAX_MASS_GAP > 0
    for (j = 1; j < s->n_bodies; j++) {
        int k;
        for (k = 0; k < EDMI_MAX_MASS_GAP && k < j; k++)
            if (s->mass_off[j][k] != 0)
                fprintf(stderr, "  mass %d %d %.9g\n", j, j - 1 - k, (double)s->mass_off[j][k]);
    }
#endif
}

/* ---- the program ------------------------------------------------------------------------ */

#define FZ_N3 (3 * EDMI_MAX_BODIES)

static edmi_system fz_sys, fz_before;
static edmi_workspace fz_work;

/* ---- OK means solved: the scheme's residual at the stored state ------------------------- */

/* The bound edmi.h states for an EDMI_OK step (EDMI_SOLVED), checked with magnitudes of the
 * test suite's own (tp_solved, tests/lib/passive.c: the residual at the stored state against the
 * terms' magnitudes as edmi.h defines them, in long double from public data). A solved step
 * is within EDMI_SOLVED there up to the rounding of the magnitudes, which the library sums in
 * its own precision: the factor 2 is for that (a step deep in a repulsive wall that Newton
 * never solved is off by 1e10 to 1e30). The guard's moves change the stored state by energy,
 * not by residual (its last-resort rounding can be far): where it acted and the stored state
 * is off, the step is taken again with the guard off, from the same system and workspace as
 * they were (the factors the last step kept), which stores Newton's iterate itself.
 * Fallback steps store no solution, and a step split into substeps solves each substep (not
 * the whole dt): neither is checked here. */
#ifndef FZ_SOLVED /* -DFZ_SOLVED=... hunts closer to the bound */
#define FZ_SOLVED (2.0L * (long double)EDMI_SOLVED)
#endif

static edmi_system fz_off, fz_after;
static edmi_workspace fz_work2, fz_work_before, fz_work_after;

static long double fz_n3l(const edmi_real *v)
{
    long double x = v[0], y = v[1], z = v[2];
    return sqrtl(x * x + y * y + z * z);
}


/* The step from s0 (fz_before) again with the guard off: Newton's iterate as it is (NULL if
 * that fails or splits into substeps). It is taken by the step's own system and workspace,
 * set back as they were before it (fz_work_before), so that Newton starts from the same
 * factors kept by the last step (edmi_workspace) and takes the same path; both are then put
 * back as the step left them. */
static const edmi_system *fz_guard_off(const edmi_system *s0, edmi_real dt)
{
    edmi_params prm = s0->params;
    edmi_step_result r;
    edmi_status st;
    memcpy(&fz_after, &fz_sys, sizeof fz_sys);
    memcpy(&fz_work_after, &fz_work, sizeof fz_work);
    memcpy(&fz_sys, s0, sizeof fz_sys);
    memcpy(&fz_work, &fz_work_before, sizeof fz_work);
    prm.guard = EDMI_GUARD_OFF;
    prm.fallback = 0;
    st = edmi_set_params(&fz_sys, &prm);
    if (st == EDMI_OK)
        st = edmi_step(&fz_sys, &fz_work, dt, &r);
    memcpy(&fz_off, &fz_sys, sizeof fz_sys);
    memcpy(&fz_sys, &fz_after, sizeof fz_sys);
    memcpy(&fz_work, &fz_work_after, sizeof fz_work);
    return st == EDMI_OK && r.substeps == 1 && r.stop != EDMI_STOP_FALLBACK ? &fz_off : 0;
}

/* How far state s is from solving the step from s0 (tp_solved), against the bound: 1 if
 * within it; 0 (with *worst, *body, *which, *st) if not. */
static int fz_solved_within(const edmi_system *s0, const edmi_system *s, edmi_real dt,
                            const edmi_step_result *res, long double *worst, int *body,
                            int *which, edmi_status *st)
{
    long double bound = FZ_SOLVED;
    *worst = tp_solved(s0, s, dt, &fz_work2, st, body, which);
    if (res->stop == EDMI_STOP_TOL_R || res->stop == EDMI_STOP_TOL_A) {
        /* the early stops hold the bound with EDMI_SOLVED eps raised to the tolerance */
        long double tol = res->stop == EDMI_STOP_TOL_R ? s0->params.tol_r : s0->params.tol_a;
        if (16.0L * tol / (long double)EDMI_EPS > bound)
            bound = 16.0L * tol / (long double)EDMI_EPS;
    }
    return *st == EDMI_OK && *worst <= bound;
}

/* The stored state s1 solves the step; where the guard acted on it and it does not (a move
 * by energy, or a rounding that crossed a domain's edge), Newton's iterate, stored by the
 * same step with the guard off, does. */
static void fz_check_solved(const edmi_system *s0, const edmi_system *s1, edmi_real dt,
                            const edmi_step_result *res)
{
    long double worst;
    int body, which;
    edmi_status st;
    if (res->stop == EDMI_STOP_FALLBACK || res->substeps != 1)
        return; /* a fallback solves nothing; substeps each solve their own part of dt */
    if (fz_solved_within(s0, s1, dt, res, &worst, &body, &which, &st))
        return;
    if (res->guard_action != 0) {
        const edmi_system *s = fz_guard_off(s0, dt);
        if (!s) /* without the guard the step ends elsewhere (a range the guard avoided) */
            return;
        if (fz_solved_within(s0, s, dt, res, &worst, &body, &which, &st))
            return;
    }
    if (st != EDMI_OK)
        fz_fail("the stored state's residual cannot be evaluated", "edmi_step", st);
    fprintf(stderr, "body %d: |R_%c| = %.3Lg eps x its magnitudes, stop %d, %d iterations, "
                    "residual %.3g, residual0 %.3g, guard_action %u\n",
            body, which ? 'p' : 'q', worst, (int)res->stop, res->iterations,
            (double)res->residual, (double)res->residual0, res->guard_action);
    fz_fail("EDMI_OK but the stored state does not solve the scheme", "edmi_step", EDMI_OK);
}

static void fz_build(fz_in *in, edmi_system *sys, int *n_user)
{
    int nb = (int)(fz_u8(in) % (unsigned)(EDMI_MAX_BODIES + 2)), nl, k;
    for (k = 0; k < nb; k++) {
        edmi_real q[3], p[3], m = fz_pos(in);
        fz_vec(in, q);
        fz_vec(in, p);
        (void)edmi_add_body(sys, m, q, p, 0);
    }
    nl = (int)(fz_u8(in) % (unsigned)(EDMI_MAX_LINKS + 2));
    for (k = 0; k < nl; k++) {
        edmi_potential pot = fz_potential(in, n_user);
        int a = fz_index(in, sys->n_bodies);
        if (fz_u8(in) & 1u) {
            edmi_real x[3];
            fz_vec(in, x);
            (void)edmi_add_anchor(sys, a, x, &pot, 0);
        } else {
            (void)edmi_add_pair(sys, a, fz_index(in, sys->n_bodies), &pot, 0);
        }
    }
}

/* Whether a wall of s moves in its next step (edmi_move_wall). */
static int fz_walls_moved(const edmi_system *s)
{
#if EDMI_MAX_WALLS > 0
    int j;
    for (j = 0; j < s->n_walls && j < EDMI_MAX_WALLS; j++)
        if (s->internal.wall_next[j] != s->wall[j].c)
            return 1;
#else
    (void)s;
#endif
    return 0;
}

/* Every link's potential evaluates at its start distance (edmi_pot_eval: every derivative
 * finite, a user potential accepting it), and every wall's at its start gap: else the start
 * state is input edmi_step refuses. */
/* The next representable edmi_real after d towards the sign of dir. */
static edmi_real fz_next(edmi_real d, int dir)
{
    if (sizeof(edmi_real) == sizeof(float))
        return (edmi_real)nextafterf((float)d, dir > 0 ? HUGE_VALF : -HUGE_VALF);
    return (edmi_real)nextafter((double)d, dir > 0 ? HUGE_VAL : -HUGE_VAL);
}

static int fz_start_evaluable(const edmi_system *s)
{
    int j, i, k;
    for (j = 0; j < s->n_links; j++) {
        const edmi_link *lk = &s->link[j];
        const edmi_real *xb = lk->b == EDMI_ANCHOR ? lk->anchor : s->body[lk->b].q;
        edmi_real r[3], d;
        edmi_pot_parts pp;
        for (i = 0; i < 3; i++)
            r[i] = s->body[lk->a].q[i] - xb[i];
        d = (edmi_real)fz_n3l(r);
        /* the library forms |r| in working precision, within two units of the correctly
         * rounded d: a start it refuses at its own d (a user potential's domain ending
         * there) is refused input too (float: d = 214 here, 214 + 1 ulp there) */
        for (d = fz_next(fz_next(d, -1), -1), k = 0; k < 5; k++, d = fz_next(d, 1))
            if (d > 0 && edmi_pot_eval(&lk->pot, d, &pp) != EDMI_OK)
                return 0;
    }
#if EDMI_MAX_WALLS > 0
    /* every wall's V and V' at its start gap (in long double) well inside the range: else the
     * library, which forms them in working precision, may refuse the start (float: a field of
     * 1.7e25 pressed a body 1e13 into a harmonic wall) */
    for (j = 0; j < s->n_walls && j < EDMI_MAX_WALLS; j++) {
        const edmi_wall *wl = &s->wall[j];
        long double g = -(long double)wl->c, x, v, dv;
        for (i = 0; i < 3; i++)
            g += (long double)wl->n[i] * (long double)s->body[wl->a].q[i];
        x = g - (long double)wl->pot.b;
        if (wl->pot.kind == EDMI_POT_CONTACT)
            x = -x;
        if (wl->pot.kind == EDMI_POT_HARMONIC) {
            v = 0.5L * (long double)wl->pot.a * x * x;
            dv = (long double)wl->pot.a * x;
        } else {
            x = x > 0.0L ? x : 0.0L;
            v = (long double)wl->pot.a * x * x * x / 3.0L;
            dv = (long double)wl->pot.a * x * x;
        }
        if (!(fabsl(v) < 0.5L * (long double)EDMI_REAL_MAX && fabsl(dv) < 0.5L * (long double)EDMI_REAL_MAX))
            return 0;
    }
#endif
    return 1;
}

/* A run of guarded steps under the window check (tp_window_step) is live until a call other
 * than a step (a build call, a write into the system) or a step with the guard off. */
static int fz_window_live;

static void fz_op_step(fz_in *in, int *steps)
{
    edmi_step_result res;
    edmi_real dt = fz_pos(in);
    edmi_status st;
    if (fz_u8(in) < 192u) /* mostly a step a scene would take */
        dt = (edmi_real)ldexp(1.0 + (double)fz_u8(in) / 256.0, (int)(fz_u8(in) % 16u) - 12);
    if (fz_trace < 0)
        fz_trace = getenv("FZ_TRACE") != 0;
    if (fz_trace)
        fz_print_sys(&fz_sys, dt);
    memcpy(&fz_before, &fz_sys, sizeof fz_sys);
    memcpy(&fz_work_before, &fz_work, sizeof fz_work); /* its kept factors (fz_guard_off) */
    if (!fz_window_live)
        tp_window_start(&fz_sys);
    fz_window_live = 1;
    st = edmi_step(&fz_sys, &fz_work, dt, &res);
    if (fz_trace)
        fprintf(stderr, "  -> %s, %d iterations, stop %d, dh %.17g diss_guard %.17g "
                        "diss_scheme %.17g guard_action %u certificate %d tank %.9g cap %.9g\n",
                edmi_status_name(st), res.iterations, (int)res.stop, (double)res.dh,
                (double)res.diss_guard, (double)res.diss_scheme, res.guard_action,
                (int)res.certificate, (double)res.tank, (double)res.tank_cap);
    fz_unchanged(st, "edmi_step", &fz_sys, &fz_before, 0, 0, 0);
    if (fz_before.params.fallback && fz_before.params.l_max >= 1 &&
        (st == EDMI_ERR_SINGULAR || st == EDMI_ERR_NO_CONVERGENCE || st == EDMI_ERR_PASSIVITY ||
         st == EDMI_ERR_DIVERGED || st == EDMI_ERR_OVERFLOW || st == EDMI_ERR_END_STATE ||
         st == EDMI_ERR_RANGE || st == EDMI_ERR_DOMAIN)) {
        /* the fallback's contract: only a start state its potentials refuse (the input) or a
         * moved anchor or wall with no passive state may fail */
        edmi_invariants inv;
        if (!((st == EDMI_ERR_END_STATE || st == EDMI_ERR_OVERFLOW || st == EDMI_ERR_RANGE ||
               st == EDMI_ERR_DOMAIN) &&
              (fz_before.internal.n_moving > 0 || fz_walls_moved(&fz_before) ||
               edmi_invariants_of(&fz_before, &inv) != EDMI_OK ||
               !fz_start_evaluable(&fz_before))))
            fz_fail("fallback set but the step failed", "edmi_step", st);
    }
    if (st == EDMI_OK) {
        fz_check_step(&fz_before, &fz_sys, dt, &res);
        fz_check_solved(&fz_before, &fz_sys, dt, &res);
        fz_window_live = fz_guard_on(&fz_before.params);
    }
    ++*steps;
}

static void fz_op_measure(fz_in *in)
{
    edmi_invariants inv, inv0;
    edmi_status st;
    memset(&inv, 0xa5, sizeof inv);
    memcpy(&inv0, &inv, sizeof inv);
    memcpy(&fz_before, &fz_sys, sizeof fz_sys);
    st = edmi_invariants_of(&fz_sys, (fz_u8(in) & 15u) ? &inv : 0);
    fz_unchanged(st, "edmi_invariants_of", &fz_sys, &fz_before, &inv, &inv0, sizeof inv);
    if (st == EDMI_OK && (!fz_finite(inv.h) || !fz_finite(inv.k) || !fz_finite(inv.v) ||
                          !fz_finite_n(inv.j, 3) || !fz_finite_n(inv.l, 3) ||
                          !fz_finite_n(inv.c, 3)))
        fz_fail("non-finite invariants", "edmi_invariants_of", st);
}

/* A trial end state: the current state moved a little (or a lot). */
static void fz_trial(fz_in *in, edmi_real (*q1)[3], edmi_real (*p1)[3])
{
    int a, i;
    unsigned how = fz_u8(in);
    for (a = 0; a < EDMI_MAX_BODIES; a++)
        for (i = 0; i < 3; i++) {
            q1[a][i] = fz_sys.body[a].q[i];
            p1[a][i] = fz_sys.body[a].p[i];
            if (how & 1u)
                q1[a][i] += fz_real(in) * (edmi_real)1e-3;
            if (how & 2u)
                p1[a][i] += fz_real(in);
        }
    if (how & 4u) { /* a trial where one link ends at length 0 */
        int j = fz_index(in, fz_sys.n_links);
        if (j >= 0 && j < fz_sys.n_links) {
            const edmi_link *lk = &fz_sys.link[j];
            if (lk->a >= 0 && lk->a < EDMI_MAX_BODIES) {
                if (lk->b == EDMI_ANCHOR)
                    memcpy(q1[lk->a], lk->anchor, sizeof q1[lk->a]);
                else if (lk->b >= 0 && lk->b < EDMI_MAX_BODIES)
                    memcpy(q1[lk->a], q1[lk->b], sizeof q1[lk->a]);
            }
        }
    }
}

static void fz_op_verify(fz_in *in)
{
    static edmi_real q1[EDMI_MAX_BODIES][3], p1[EDMI_MAX_BODIES][3];
    static edmi_real rq[EDMI_MAX_BODIES + 1][3], rp[EDMI_MAX_BODIES + 1][3];
    static edmi_real rq0[EDMI_MAX_BODIES + 1][3], rp0[EDMI_MAX_BODIES + 1][3];
    static edmi_real kmat[FZ_N3 * FZ_N3 + 1], kmat0[FZ_N3 * FZ_N3 + 1];
    edmi_real dt = fz_pos(in);
    unsigned which = fz_u8(in);
    int sw = -7, sw0 = -7, n;
    edmi_status st;
    fz_trial(in, q1, p1);
    memcpy(&fz_before, &fz_sys, sizeof fz_sys);
    if (which & 1u) {
        memset(rq, 0xa5, sizeof rq);
        memset(rp, 0x5a, sizeof rp);
        memcpy(rq0, rq, sizeof rq);
        memcpy(rp0, rp, sizeof rp);
        st = edmi_residual(&fz_sys, &fz_work, dt, (const edmi_real (*)[3])q1,
                           (const edmi_real (*)[3])p1, rq, rp, (which & 2u) ? &sw : 0);
        fz_unchanged(st, "edmi_residual", &fz_sys, &fz_before, rq, rq0, sizeof rq);
        fz_unchanged(st, "edmi_residual", &fz_sys, &fz_before, rp, rp0, sizeof rp);
        if (st != EDMI_OK && sw != sw0)
            fz_fail("lg_switches written on error", "edmi_residual", st);
        if (st == EDMI_OK) {
            n = fz_sys.n_bodies;
            if (!fz_finite_n(rq[0], 3 * n) || !fz_finite_n(rp[0], 3 * n))
                fz_fail("non-finite residual", "edmi_residual", st);
            if (memcmp(rq[n], rq0[n], sizeof rq[n]) != 0 || memcmp(rp[n], rp0[n], sizeof rp[n]))
                fz_fail("wrote past n_bodies rows", "edmi_residual", st);
        }
    } else {
        memset(kmat, 0xa5, sizeof kmat);
        memcpy(kmat0, kmat, sizeof kmat);
        st = edmi_tangent(&fz_sys, &fz_work, dt, (const edmi_real (*)[3])q1,
                          (const edmi_real (*)[3])p1, kmat);
        fz_unchanged(st, "edmi_tangent", &fz_sys, &fz_before, kmat, kmat0, sizeof kmat);
        if (st == EDMI_OK) {
            n = 3 * fz_sys.n_bodies;
            if (!fz_finite_n(kmat, n * n))
                fz_fail("non-finite tangent", "edmi_tangent", st);
            if (memcmp(&kmat[n * n], &kmat0[n * n], sizeof kmat[0]) != 0)
                fz_fail("wrote past (3n)^2 entries", "edmi_tangent", st);
        }
    }
}

static void fz_op_potential(fz_in *in, int *n_user)
{
    edmi_potential pot = fz_potential(in, n_user);
    edmi_pot_parts pp, pp0;
    edmi_real d0 = fz_pos(in), d1 = fz_pos(in), dd = (edmi_real)-7, ddd = (edmi_real)-7;
    edmi_status st;
    if (fz_u8(in) & 1u)
        d1 = d0 * ((edmi_real)1 + fz_real(in) * (edmi_real)1e-6);
    memset(&pp, 0xa5, sizeof pp);
    memcpy(&pp0, &pp, sizeof pp);
    st = edmi_pot_eval(&pot, d0, &pp);
    fz_unchanged(st, "edmi_pot_eval", 0, 0, &pp, &pp0, sizeof pp);
    if (st == EDMI_OK && !fz_finite_n(pp.v, 25))
        fz_fail("non-finite derivatives", "edmi_pot_eval", st);
    st = edmi_pot_divdiff(&pot, d0, d1, &dd, &ddd);
    fz_status(st, "edmi_pot_divdiff");
    if (st != EDMI_OK && (dd != (edmi_real)-7 || ddd != (edmi_real)-7))
        fz_fail("output written on error", "edmi_pot_divdiff", st);
    if (st == EDMI_OK && (!fz_finite(dd) || !fz_finite(ddd)))
        fz_fail("non-finite divided difference", "edmi_pot_divdiff", st);
}

/* Build calls on the existing system: every one either succeeds or changes nothing. */
static void fz_op_build(fz_in *in, int *n_user)
{
    edmi_real v[3], w[3];
    edmi_potential pot;
    edmi_params prm;
    int idx = -9, idx0 = -9;
    edmi_status st;
    unsigned which = fz_u8(in) % 10u;
    fz_vec(in, v);
    memcpy(&fz_before, &fz_sys, sizeof fz_sys);
    switch (which) {
    case 0:
        fz_vec(in, w);
        st = edmi_add_body(&fz_sys, fz_pos(in), v, w, &idx);
        break;
    case 1:
        pot = fz_potential(in, n_user);
        st = edmi_add_pair(&fz_sys, fz_index(in, fz_sys.n_bodies), fz_index(in, fz_sys.n_bodies),
                           &pot, &idx);
        break;
    case 2:
        pot = fz_potential(in, n_user);
        st = edmi_add_anchor(&fz_sys, fz_index(in, fz_sys.n_bodies), v, &pot, &idx);
        break;
    case 3:
        st = edmi_add_damper(&fz_sys, fz_index(in, fz_sys.n_links), fz_pos(in), &idx);
        break;
    case 4:
        st = edmi_set_field(&fz_sys, v);
        break;
    case 5:
        st = edmi_set_force(&fz_sys, fz_index(in, fz_sys.n_bodies), v);
        break;
    case 6:
        st = edmi_move_anchor(&fz_sys, fz_index(in, fz_sys.n_links), v);
        break;
    case 7:
        prm = fz_params(in);
        st = edmi_set_params(&fz_sys, &prm);
        break;
    case 8:
        which = fz_u8(in);
        if (which & 1u) { /* a wall: normal v, offset, any potential (most refused) */
            edmi_real c = fz_real(in);
            pot = fz_potential(in, n_user);
            st = edmi_add_wall(&fz_sys, fz_index(in, fz_sys.n_bodies), v, c, &pot, &idx);
            break;
        }
        if (which & 2u) { /* a wall moved (any index, any offset) */
            st = edmi_move_wall(&fz_sys, fz_index(in, EDMI_MAX_WALLS), v[0]);
            break;
        }
        st = edmi_set_mass_coupling(&fz_sys, fz_index(in, fz_sys.n_bodies),
                                    fz_index(in, fz_sys.n_bodies), fz_real(in));
        break;
    default:
        if (v[0] < (edmi_real)0) { /* the tank: any value, invalid ones too */
            st = edmi_set_tank(&fz_sys, v[1]);
            if (st == EDMI_OK && v[1] > 0 && !(fz_sys.params.tank_cap > 0))
                fz_fail("a tank accepted with tank_cap 0", "edmi_set_tank", st);
            break;
        }
        prm = fz_params(in);
        st = edmi_init(&fz_sys, (fz_u8(in) & 1u) ? &prm : 0);
        break;
    }
    fz_unchanged(st, "a build call", &fz_sys, &fz_before, &idx, &idx0, sizeof idx);
}

/* A scene as constant data, validated by edmi_load_scene before it replaces anything. */
static void fz_op_scene(fz_in *in, int *n_user)
{
    static edmi_body bodies[EDMI_MAX_BODIES];
    static edmi_link links[EDMI_MAX_LINKS];
    static edmi_damper dampers[EDMI_MAX_DAMPERS];
    static edmi_mass_coupling couplings[2 * EDMI_MAX_BODIES];
    edmi_params prm = fz_params(in);
    edmi_scene sc;
    edmi_status st;
    int k;
    memset(bodies, 0, sizeof bodies);
    memset(links, 0, sizeof links);
    memset(dampers, 0, sizeof dampers);
    sc.n_bodies = fz_index(in, EDMI_MAX_BODIES + 1);
    sc.n_links = fz_index(in, EDMI_MAX_LINKS + 1);
    sc.n_dampers = fz_index(in, EDMI_MAX_DAMPERS + 1);
    for (k = 0; k < EDMI_MAX_BODIES && k < sc.n_bodies; k++) {
        bodies[k].m = fz_pos(in);
        fz_vec(in, bodies[k].q);
        fz_vec(in, bodies[k].p);
    }
    for (k = 0; k < EDMI_MAX_LINKS && k < sc.n_links; k++) {
        links[k].a = fz_index(in, sc.n_bodies);
        links[k].b = (fz_u8(in) & 1u) ? EDMI_ANCHOR : fz_index(in, sc.n_bodies);
        fz_vec(in, links[k].anchor);
        links[k].pot = fz_potential(in, n_user);
    }
    for (k = 0; k < EDMI_MAX_DAMPERS && k < sc.n_dampers; k++) {
        dampers[k].link = fz_index(in, sc.n_links);
        dampers[k].c = fz_pos(in);
    }
    sc.bodies = (fz_u8(in) == 255u) ? 0 : bodies;
    sc.links = (fz_u8(in) == 255u) ? 0 : links;
    sc.dampers = (fz_u8(in) == 255u) ? 0 : dampers;
    sc.has_field = (int)(fz_u8(in) & 1u);
    fz_vec(in, sc.g);
    sc.params = (fz_u8(in) & 1u) ? &prm : 0;
    sc.n_mass_couplings = fz_index(in, 2 * EDMI_MAX_BODIES + 1);
    for (k = 0; k < 2 * EDMI_MAX_BODIES && k < sc.n_mass_couplings; k++) {
        couplings[k].a = fz_index(in, sc.n_bodies);
        couplings[k].b = fz_index(in, sc.n_bodies);
        couplings[k].m = fz_real(in);
    }
    sc.mass_couplings = (fz_u8(in) == 255u) ? 0 : couplings;
    memcpy(&fz_before, &fz_sys, sizeof fz_sys);
    st = edmi_load_scene(&fz_sys, &sc);
    fz_unchanged(st, "edmi_load_scene", &fz_sys, &fz_before, 0, 0, 0);
}

/* Firmware writes the state directly (docs/api.md: state access); sometimes it corrupts a count. */
static void fz_op_poke(fz_in *in)
{
    unsigned which = fz_u8(in) % 16u;
    int a = fz_index(in, fz_sys.n_bodies);
    int v = fz_index(in, EDMI_MAX_BODIES + 1);
    if (which < 4u && a >= 0 && a < EDMI_MAX_BODIES) {
        if (which == 0)
            fz_vec(in, fz_sys.body[a].q);
        else if (which == 1)
            fz_vec(in, fz_sys.body[a].p);
        else if (which == 2)
            fz_sys.body[a].m = fz_pos(in);
        else
            fz_sys.t = fz_real(in);
        return;
    }
    switch (which) {
    case 4: fz_sys.internal.n_forced = v; break;
    case 5: fz_sys.n_bodies = v; break;
    case 6: fz_sys.internal.n_moving = v; break;
    case 7: fz_sys.n_dampers = v; break;
    default: { /* a field written directly: a value, not a count */
        int j = fz_index(in, EDMI_MAX_LINKS), k = (int)(fz_u8(in) % 3u);
        edmi_real x = fz_real(in);
        if (j < 0 || j >= EDMI_MAX_DAMPERS)
            j = 0;
        switch (which) {
        case 8: fz_sys.damper[j].c = x; break;
        case 9: fz_sys.force[j % EDMI_MAX_BODIES][k] = x; break;
        case 10: fz_sys.internal.anchor_next[j][k] = x; break;
        case 11: fz_sys.g[k] = x; break;
        case 12: fz_sys.link[j].pot.a = x; break;
        case 13: fz_sys.link[j].anchor[k] = x; break;
        case 14: /* the clock's carry, or the tank (any value: the next step checks it) */
            if (k == 2)
                fz_sys.tank = x;
            else
                fz_sys.internal.t_carry = x;
            break;
        default: fz_sys.damper[j].link = fz_index(in, EDMI_MAX_LINKS + 1); break;
        }
    }
    }
}

/* NULL pointers everywhere a pointer is taken. */
static void fz_op_null(void)
{
    static const edmi_real v[3] = {0, 0, 0};
    edmi_potential pot = edmi_pot_harmonic(1, 1);
    edmi_pot_parts pp;
    edmi_invariants inv;
    edmi_real x, y;
    int k;
    memcpy(&fz_before, &fz_sys, sizeof fz_sys);
#define FZ_NULL(call)                                                                  \
    do {                                                                               \
        edmi_status st_ = (call);                                                      \
        if (st_ != EDMI_ERR_NULL)                                                      \
            fz_fail("NULL not reported", #call, st_);                                  \
    } while (0)
    FZ_NULL(edmi_init(0, 0));
    FZ_NULL(edmi_set_params(&fz_sys, 0));
    FZ_NULL(edmi_add_body(&fz_sys, 1, 0, v, 0));
    FZ_NULL(edmi_add_body(&fz_sys, 1, v, 0, 0));
    FZ_NULL(edmi_add_pair(0, 0, 1, &pot, 0));
    FZ_NULL(edmi_add_anchor(&fz_sys, 0, 0, &pot, 0));
    FZ_NULL(edmi_set_field(&fz_sys, 0));
    FZ_NULL(edmi_add_damper(0, 0, 1, 0));
    FZ_NULL(edmi_add_wall(0, 0, v, 0, &pot, 0));
    FZ_NULL(edmi_add_wall(&fz_sys, 0, 0, 0, &pot, 0));
    FZ_NULL(edmi_add_wall(&fz_sys, 0, v, 0, 0, 0));
    FZ_NULL(edmi_move_wall(0, 0, 0));
    FZ_NULL(edmi_set_mass_coupling(0, 0, 1, 1));
    FZ_NULL(edmi_move_anchor(&fz_sys, 0, 0));
    FZ_NULL(edmi_set_force(&fz_sys, 0, 0));
    FZ_NULL(edmi_load_scene(&fz_sys, 0));
    FZ_NULL(edmi_step(&fz_sys, 0, 1, 0));
    FZ_NULL(edmi_invariants_of(0, &inv));
    FZ_NULL(edmi_pot_eval(0, 1, &pp));
    FZ_NULL(edmi_pot_eval(&pot, 1, 0));
    FZ_NULL(edmi_pot_divdiff(0, 1, 1, &x, &y));
    FZ_NULL(edmi_pot_divdiff(&pot, 1, 1, 0, &y));
    FZ_NULL(edmi_pot_divdiff(&pot, 1, 1, &x, 0));
    FZ_NULL(edmi_residual(&fz_sys, &fz_work, 1, 0, 0, 0, 0, 0));
    FZ_NULL(edmi_tangent(&fz_sys, 0, 1, 0, 0, 0));
#undef FZ_NULL
    (void)y;
    if (memcmp(&fz_sys, &fz_before, sizeof fz_sys) != 0)
        fz_fail("system changed", "a call with a NULL pointer", EDMI_ERR_NULL);
    for (k = -2; k <= (int)EDMI_ERR_DISABLED + 2; k++)
        if (edmi_status_name((edmi_status)k) == 0)
            fz_fail("no status name", "edmi_status_name", (edmi_status)k);
    if (!EDMI_CONFIG_MATCHES() || edmi_config_matches(0, (unsigned long)sizeof fz_work) ||
        edmi_config_matches((unsigned long)sizeof fz_sys, (unsigned long)sizeof fz_work + 1u))
        fz_fail("wrong answer", "edmi_config_matches", EDMI_OK);
}

#define FZ_MAX_OPS 64
#define FZ_MAX_STEPS 48

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in in;
    edmi_params prm;
    int n_user = 0, ops, steps = 0;
    in.d = data;
    in.n = size;
    in.i = 0;
    tp_user_register(fz_user_map);
    prm = fz_params(&in);
    if (edmi_init(&fz_sys, &prm) != EDMI_OK)
        (void)edmi_init(&fz_sys, 0);
    fz_build(&in, &fz_sys, &n_user);
    fz_window_live = 0;
    for (ops = 0; ops < FZ_MAX_OPS && !fz_done(&in); ops++) {
        unsigned op = fz_u8(&in) % 16u;
        if (op >= 7u && op != 15u)
            fz_window_live = 0; /* anything but a step may change the system */
        if (op < 7u) {
            int k, n = 1 + (int)(fz_u8(&in) % 8u);
            for (k = 0; k < n && steps < FZ_MAX_STEPS; k++)
                fz_op_step(&in, &steps);
        } else if (op < 9u) {
            fz_op_build(&in, &n_user);
        } else if (op == 9u) {
            fz_op_measure(&in);
        } else if (op == 10u) {
            fz_op_verify(&in);
        } else if (op == 11u) {
            fz_op_potential(&in, &n_user);
        } else if (op == 12u) {
            fz_op_scene(&in, &n_user);
        } else if (op == 13u) {
            fz_op_poke(&in);
        } else if (op == 14u) {
            fz_op_null();
        } else {
            fz_op_measure(&in);
            fz_op_step(&in, &steps);
        }
    }
    return 0;
}
