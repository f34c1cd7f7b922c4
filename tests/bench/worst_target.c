/* worst_target: the costliest edmi_step() of a one-body virtual coupling on the emulated
 * Cortex-M4F, found by a search that tries to make it long, and the bound the step's
 * structure gives from the costliest pieces such searches find (`make worst-target`).
 *
 * The build is the coupling build of `make cross` (PM, harmonic links, anchors that move, the
 * guard; FEAT_coupling) at a capacity of one body and two links, float, -Os: what a haptic
 * firmware carries. The system: a body of mass m at q with momentum p on two harmonic links
 * (k_j, r0_j) to anchors x_j, each anchor moved to x_j' in the step or not, a tank T, dt;
 * edmi_default_params() with l_max 20, fallback on, tank_cap 256 or 0, and substep_levels k
 * = 0, 1, 2, 3 (a search per k). Every scale is drawn log-uniformly over many decades (the
 * product omega dt from 1e-3 to 1e4, momenta from rest to 1e3 times the links' reach per
 * step, anchors moved by 1e-7 to 10 times the body's distance, rest lengths 0 or up to 3 times
 * it, the tank empty, partly or over full).
 *
 * The search, per k: WT_RANDOM random states, one step each; then from each of the WT_TOP
 * costliest, WT_CLIMB mutations (one field scaled by a random power of two, flipped in sign,
 * set to 0 or to another state's, or a few low bits changed), each kept when its step costs
 * more. Only the edmi_step() call is timed (port/cortex-m/span.h: exact instructions under
 * QEMU -icount shift=0, cycles on silicon).
 *
 * The pieces of a step (tests/bench/bench_target.c times them the same way, as differences of steps
 * from one state) are searched for the same way, each its own objective: the first
 * correction (a step failing at l_max = 1), one more correction (F(l_max = l + 1) -
 * F(l_max = l), both failing), one residual evaluation, the last correction with everything
 * after Newton (the energy balance, the guard and its rounding searches: the step less
 * F(l_max = its corrections - 1)) and the fallback (F(l_max, fallback) - F(l_max)). The count
 * of each piece in a step is fixed by its structure (edmi.c: l_max corrections, at most 8
 * halvings each, the guard's rounding candidates at most 3 x 128 + 27, the substeps'
 * 2^(k+1) - 1 attempts and 2^k fallbacks), so the pieces' maxima give the bound
 *     T(L) <= first + (L - 2) iter + last + 8 L halving + fallback + restart,
 *     T_k(L) <= (2^(k+1) - 1) (T(L) - fallback) + 2^k fallback,
 * halving <= iter (a move and an evaluation), restart = iter (a singular Newton matrix at the
 * predictor: Newton starts once more from the explicit predictor).
 *
 * Printed: the pieces' maxima, then per k the costliest step found, what it did (Newton
 * corrections, halvings, substeps, fallbacks, the guard's moves, the cause), its state bit
 * for bit, and the bound, which every step must meet (the program fails otherwise). */
#include <stddef.h>

#include "edmi.h"
#include "cortex-m/semihost.h"
#include "cortex-m/span.h"

#if EDMI_MAX_BODIES != 1 || EDMI_MAX_LINKS != 2 || EDMI_PREC_(EDMI_REAL) != EDMI_FLOAT_
#error "worst_target: build with EDMI_REAL=float, EDMI_MAX_BODIES=1, EDMI_MAX_LINKS=2"
#endif

#ifndef WT_RANDOM
#define WT_RANDOM 20000L
#endif
#ifndef WT_CLIMB
#define WT_CLIMB 1500L
#endif
#define WT_TOP 8
#define WT_LEVELS 4
#define WT_SPAN_CAL 80UL
#define WT_SPAN_MAX_ERR 8L

typedef struct wt_state {
    float m, dt, tank;
    float q[3], p[3];
    float k[2], r0[2];
    float x[2][3], xn[2][3];
    int moving[2], cap0;
} wt_state;

#define WT_NFIELDS 25 /* the floats of a state a mutation may change (m .. xn[1][2]) */

static float *wt_field(wt_state *s, int f)
{
    float *fl[WT_NFIELDS];
    int i, j, n = 0;
    fl[n++] = &s->m;
    fl[n++] = &s->dt;
    fl[n++] = &s->tank;
    for (i = 0; i < 3; i++)
        fl[n++] = &s->q[i];
    for (i = 0; i < 3; i++)
        fl[n++] = &s->p[i];
    for (j = 0; j < 2; j++) {
        fl[n++] = &s->k[j];
        fl[n++] = &s->r0[j];
        for (i = 0; i < 3; i++)
            fl[n++] = &s->x[j][i];
        for (i = 0; i < 3; i++)
            fl[n++] = &s->xn[j][i];
    }
    return fl[f];
}

/* ---- random numbers: xorshift32 --------------------------------------------------------- */

static unsigned long wt_seed = 2463534242UL;

static unsigned long wt_rand(void)
{
    wt_seed ^= (wt_seed << 13) & 0xffffffffUL;
    wt_seed ^= wt_seed >> 17;
    wt_seed ^= (wt_seed << 5) & 0xffffffffUL;
    return wt_seed & 0xffffffffUL;
}

static float wt_unit(void) { return (float)(wt_rand() >> 8) * (1.0f / 16777216.0f); }

/* 2^e for an integer e in [-126, 127] (exact, no libm) */
static float wt_pow2(int e)
{
    float x = 1.0f;
    for (; e > 0; e--)
        x *= 2.0f;
    for (; e < 0; e++)
        x *= 0.5f;
    return x;
}

/* log-uniform over [2^lo, 2^hi) */
static float wt_logu(int lo, int hi)
{
    int e = lo + (int)(wt_rand() % (unsigned long)(hi - lo));
    return wt_pow2(e) * (1.0f + wt_unit());
}

static float wt_sym(void) { return 2.0f * wt_unit() - 1.0f; }

/* ---- a state and its step ---------------------------------------------------------------- */

static void wt_random(wt_state *s)
{
    float len = wt_logu(-10, 4), v;
    int i, j;
    s->m = wt_logu(-12, 12);
    s->dt = wt_logu(-16, 3);
    for (i = 0; i < 3; i++)
        s->q[i] = len * wt_sym();
    for (j = 0; j < 2; j++) {
        float w = wt_logu(-10, 14) / s->dt; /* omega dt from 1e-3 to 1e4 */
        s->k[j] = s->m * w * w;
        for (i = 0; i < 3; i++)
            s->x[j][i] = s->q[i] + len * wt_sym();
        s->r0[j] = (wt_rand() & 1UL) ? 0.0f : wt_logu(-8, 2) * len;
        s->moving[j] = (int)(wt_rand() % 3UL) != 0;
        v = wt_logu(-24, 4) * len;
        for (i = 0; i < 3; i++)
            s->xn[j][i] = s->x[j][i] + v * wt_sym();
    }
    v = (wt_rand() % 4UL == 0) ? 0.0f : wt_logu(-14, 10) * len / s->dt;
    for (i = 0; i < 3; i++)
        s->p[i] = s->m * v * wt_sym();
    s->cap0 = wt_rand() % 4UL == 0;
    s->tank = (wt_rand() & 1UL) ? 0.0f : wt_logu(-40, 10) * s->k[0] * len * len;
}

static edmi_system wt_sys;
static edmi_workspace wt_work;
static edmi_step_result wt_res;
static edmi_status wt_st;
static float wt_dt;

static void wt_call_step(void) { wt_st = edmi_step(&wt_sys, &wt_work, wt_dt, &wt_res); }

/* Build the state's system; 0 if edmi refuses it (an input no firmware steps). */
static int wt_build(const wt_state *s, int levels)
{
    edmi_params prm = edmi_default_params();
    edmi_potential pot;
    int j;
    prm.l_max = 20;
    prm.fallback = 1;
    prm.substep_levels = levels;
    prm.tank_cap = s->cap0 ? 0.0f : prm.tank_cap;
    if (edmi_init(&wt_sys, &prm) != EDMI_OK || edmi_add_body(&wt_sys, s->m, s->q, s->p, 0) != EDMI_OK)
        return 0;
    for (j = 0; j < 2; j++) {
        pot = edmi_pot_harmonic(s->k[j], s->r0[j]);
        if (edmi_add_anchor(&wt_sys, 0, s->x[j], &pot, 0) != EDMI_OK ||
            (s->moving[j] && edmi_move_anchor(&wt_sys, j, s->xn[j]) != EDMI_OK))
            return 0;
    }
    if (!s->cap0 && edmi_set_tank(&wt_sys, s->tank) != EDMI_OK)
        return 0;
    return 1;
}

static int wt_cycles;
static unsigned long wt_null;

static void wt_mutate(wt_state *s, const wt_state *other)
{
    unsigned long r = wt_rand();
    int f = (int)((r >> 8) % (unsigned long)(WT_NFIELDS + 3));
    float *x;
    if (f == WT_NFIELDS) {
        s->cap0 = !s->cap0;
        return;
    }
    if (f > WT_NFIELDS) {
        s->moving[f - WT_NFIELDS - 1] ^= 1;
        return;
    }
    x = wt_field(s, f);
    switch (r % 6UL) {
    case 0: /* by a power of two, up to 2^+-8 */
        *x *= wt_pow2((int)(wt_rand() % 17UL) - 8);
        break;
    case 1:
        *x = -*x;
        break;
    case 2:
        *x = (wt_rand() & 1UL) ? 0.0f : *wt_field((wt_state *)other, f);
        break;
    case 3: /* a few units in the last place */
        {
            union {
                float f;
                unsigned long u;
            } b;
            b.f = *x;
            b.u += (wt_rand() % 9UL) - 4UL;
            *x = b.f;
        }
        break;
    default: /* by a factor near 1 */
        *x *= 1.0f + 0.25f * wt_sym();
        break;
    }
}

/* ---- the objectives: a step and its pieces ------------------------------------------------ */

/* A variant of the state's step: l_max, fallback and substep levels set; -1 if the input is
 * refused. */
static long wt_variant(const wt_state *s, int levels, int l_max, int fallback)
{
    if (!wt_build(s, levels))
        return -1;
    wt_sys.params.l_max = l_max;
    wt_sys.params.fallback = fallback;
    wt_dt = s->dt;
    return (long)tgt_span_raw(wt_call_step, wt_cycles) - (long)wt_null;
}

/* The whole step at l_max 20 with the fallback: the objective of the worst-step search. */
static long wt_obj_step(const wt_state *s, int levels)
{
    long n = wt_variant(s, levels, 20, 1);
    return n >= 0 && (wt_st == EDMI_OK || wt_st == EDMI_ERR_END_STATE ||
                      wt_st == EDMI_ERR_OVERFLOW)
               ? n
               : -1;
}

/* first: a step failing after one correction (l_max 1, no fallback) */
static long wt_obj_first(const wt_state *s, int levels)
{
    long n = wt_variant(s, levels, 1, 0);
    return wt_st == EDMI_ERR_NO_CONVERGENCE ? n : -1;
}

/* iter: one more correction, F(l + 1) - F(l), both failing without halvings, l from the
 * state's own bits (so that a climb keeps it) */
static long wt_obj_iter(const wt_state *s, int levels)
{
    union {
        float f;
        unsigned long u;
    } b;
    long f1, f2;
    int l, h;
    b.f = s->dt;
    l = 1 + (int)(b.u % 19UL);
    f1 = wt_variant(s, levels, l, 0);
    if (wt_st != EDMI_ERR_NO_CONVERGENCE || wt_res.iterations != l)
        return -1;
    h = wt_res.halvings;
    f2 = wt_variant(s, levels, l + 1, 0);
    if (wt_st != EDMI_ERR_NO_CONVERGENCE || wt_res.halvings != h)
        return -1;
    return f2 - f1;
}

/* last: the step's last correction and everything after Newton (the energy balance, the guard),
 * T(l_max 20) - F(l_max = its corrections - 1), a step that Newton solved */
static long wt_obj_last(const wt_state *s, int levels)
{
    long t, f;
    int l, h;
    t = wt_variant(s, levels, 20, 0);
    if (wt_st != EDMI_OK && wt_st != EDMI_ERR_PASSIVITY && wt_st != EDMI_ERR_OVERFLOW &&
        wt_st != EDMI_ERR_DIVERGED && wt_st != EDMI_ERR_END_STATE)
        return -1;
    l = wt_res.iterations;
    h = wt_res.halvings;
    if (l < 2 || (wt_st != EDMI_OK && wt_res.cause == EDMI_OK && l == 20))
        return -1;
    f = wt_variant(s, levels, l - 1, 0);
    if (wt_st != EDMI_ERR_NO_CONVERGENCE || wt_res.halvings > h)
        return -1;
    return t - f;
}

/* fallback: F(l_max, fallback) - F(l_max), the step failing without it (any l_max from the
 * state's bits) */
static long wt_obj_fallback(const wt_state *s, int levels)
{
    union {
        float f;
        unsigned long u;
    } b;
    long f0, f1;
    int l;
    b.f = s->m;
    l = 1 + (int)(b.u % 20UL);
    f0 = wt_variant(s, levels, l, 0);
    if (wt_st == EDMI_OK || f0 < 0)
        return -1;
    f1 = wt_variant(s, levels, l, 1);
    return wt_st == EDMI_OK && wt_res.stop == EDMI_STOP_FALLBACK ? f1 - f0 : -1;
}

/* eval: one residual evaluation with its tangent blocks at the trial state q + dt p / m, p
 * (edmi_residual less its validation and link set-up) */
static edmi_real wt_q1[1][3], wt_p1[1][3], wt_rq[1][3], wt_rp[1][3];
static void wt_call_residual(void)
{
    wt_st = edmi_residual(&wt_sys, &wt_work, wt_dt, (const edmi_real (*)[3])wt_q1,
                          (const edmi_real (*)[3])wt_p1, wt_rq, wt_rp, NULL);
}
static void wt_call_setup(void)
{
    wt_st = edmi_residual(&wt_sys, &wt_work, wt_dt, (const edmi_real (*)[3])wt_q1,
                          (const edmi_real (*)[3])wt_p1, NULL, wt_rp, NULL);
}

static long wt_obj_eval(const wt_state *s, int levels)
{
    long full, setup;
    int i;
    if (!wt_build(s, levels))
        return -1;
    wt_dt = s->dt;
    for (i = 0; i < 3; i++) {
        wt_q1[0][i] = s->q[i] + s->dt / s->m * s->p[i];
        wt_p1[0][i] = s->p[i];
    }
    full = (long)tgt_span_raw(wt_call_residual, wt_cycles);
    if (wt_st != EDMI_OK)
        return -1;
    setup = (long)tgt_span_raw(wt_call_setup, wt_cycles);
    return full - setup;
}

/* ---- the search ---------------------------------------------------------------------------- */

typedef long (*wt_obj)(const wt_state *s, int levels);

static wt_state wt_top[WT_TOP];
static long wt_top_n[WT_TOP];
static long wt_tried;

/* WT_RANDOM random states, then WT_CLIMB mutations from each of the WT_TOP costliest; the
 * largest value of f into *best (its state); -1 if no state gave one. */
static long wt_search(wt_obj f, int levels, long n_random, long n_climb, wt_state *best)
{
    wt_state s, t;
    long n, i, c;
    int j, b = 0;
    for (j = 0; j < WT_TOP; j++)
        wt_top_n[j] = -1;
    wt_tried = 0;
    for (i = 0; i < n_random; i++) {
        wt_random(&s);
        n = f(&s, levels);
        wt_tried++;
        if (n <= wt_top_n[WT_TOP - 1])
            continue;
        for (j = WT_TOP - 1; j > 0 && wt_top_n[j - 1] < n; j--) {
            wt_top[j] = wt_top[j - 1];
            wt_top_n[j] = wt_top_n[j - 1];
        }
        wt_top[j] = s;
        wt_top_n[j] = n;
    }
    for (j = 0; j < WT_TOP; j++)
        for (c = 0; c < n_climb && wt_top_n[j] >= 0; c++) {
            t = wt_top[j];
            wt_mutate(&t, &wt_top[(j + 1 + (int)(wt_rand() % (WT_TOP - 1))) % WT_TOP]);
            if (wt_rand() & 1UL)
                wt_mutate(&t, &wt_top[j]);
            n = f(&t, levels);
            wt_tried++;
            if (n > wt_top_n[j]) {
                wt_top[j] = t;
                wt_top_n[j] = n;
            }
        }
    for (j = 1; j < WT_TOP; j++)
        if (wt_top_n[j] > wt_top_n[b])
            b = j;
    *best = wt_top[b];
    return wt_top_n[b];
}

/* ---- output ------------------------------------------------------------------------------ */

static void wt_put_float(const char *name, float v)
{
    union {
        float f;
        unsigned long u;
    } b;
    b.f = v;
    tgt_puts(name);
    tgt_puts("=");
    tgt_put_hex(b.u);
    tgt_puts(" ");
}

static void wt_put_state(const wt_state *s)
{
    static const char *const names[WT_NFIELDS] = {
        "m", "dt", "tank", "q0", "q1", "q2", "p0", "p1", "p2",
        "k0", "r0_0", "x0_0", "x0_1", "x0_2", "x0'_0", "x0'_1", "x0'_2",
        "k1", "r0_1", "x1_0", "x1_1", "x1_2", "x1'_0", "x1'_1", "x1'_2"};
    int f;
    tgt_puts("  state (float bits):");
    for (f = 0; f < WT_NFIELDS; f++) {
        if (f % 6 == 0)
            tgt_puts("\n   ");
        wt_put_float(names[f], *wt_field((wt_state *)s, f));
    }
    tgt_puts("\n   anchors moved: ");
    tgt_puts(s->moving[0] ? "0 " : "");
    tgt_puts(s->moving[1] ? "1 " : "");
    tgt_puts(!s->moving[0] && !s->moving[1] ? "none" : "");
    tgt_puts(s->cap0 ? ", tank_cap 0\n" : ", tank_cap 256\n");
}

static void wt_put_row(const char *piece, long v, const char *how)
{
    tgt_puts("| ");
    tgt_puts(piece);
    tgt_puts(" | ");
    if (v < 0)
        tgt_puts("not found");
    else
        tgt_put_uint((unsigned long)v);
    tgt_puts(" | ");
    tgt_put_uint((unsigned long)wt_tried);
    tgt_puts(" | ");
    tgt_puts(how);
    tgt_puts(" |\n");
}

/* The pieces of a step: name, objective, how it is timed. */
typedef struct wt_piece {
    const char *name;
    wt_obj f;
    const char *how;
} wt_piece;

static const wt_piece pieces[5] = {
    {"first", wt_obj_first,
     "validation, set-up, the predictor, 1 correction: a step failing at l_max 1"},
    {"iter", wt_obj_iter,
     "one more correction: F(l_max = l + 1) - F(l_max = l), both failing, l from 1 to 19"},
    {"eval", wt_obj_eval, "one residual evaluation: edmi_residual less its set-up"},
    {"last", wt_obj_last,
     "the last correction, the energy balance and the guard: a step less F(l_max = its "
     "corrections - 1)"},
    {"fallback", wt_obj_fallback,
     "F(l_max, fallback) - F(l_max), the step failing without the fallback"}};

int main(void)
{
    static const char *const guard_moves[5] = {"impulse", "drag", "round", "stop", "hold"};
    wt_state best, step_best[WT_LEVELS];
    long piece[5], first, iter, eval, last, fallback, t_l, bound, estimate, worst[WT_LEVELS];
    long err, n_climb = WT_CLIMB, n_random = WT_RANDOM;
    int level, j, failed = 0;
    wt_cycles = tgt_cyccnt_start();
    tgt_ticks_start();
    err = tgt_span_calibrate(WT_SPAN_CAL, wt_cycles, &wt_null);
    if (err > WT_SPAN_MAX_ERR) {
        tgt_puts("worst_target: the counter does not time single calls (not -icount shift=0?)\n");
        return 1;
    }
    tgt_puts("One-body virtual coupling on the Cortex-M4F (the coupling build at 1 body and 2 "
             "links, float, -Os), l_max 20, fallback on; ");
    tgt_puts(wt_cycles ? "cycles" : "instructions");
    tgt_puts(" (+-");
    tgt_put_uint((unsigned long)err);
    tgt_puts("), each the largest a search of ");
    tgt_put_uint((unsigned long)n_random);
    tgt_puts(" random states and ");
    tgt_put_uint((unsigned long)(WT_TOP * n_climb));
    tgt_puts(" mutations of the costliest found.\n\n| piece | largest found | states tried | "
             "how |\n|---|---:|---:|---|\n");
    for (j = 0; j < 5; j++) { /* the pieces, in this order (the search's random sequence) */
        piece[j] = wt_search(pieces[j].f, 0, n_random, n_climb, &best);
        wt_put_row(pieces[j].name, piece[j], pieces[j].how);
    }
    first = piece[0];
    iter = piece[1];
    eval = piece[2];
    last = piece[3];
    fallback = piece[4];
    for (level = 0; level < WT_LEVELS; level++)
        worst[level] = wt_search(wt_obj_step, level, n_random, n_climb, &step_best[level]);
    t_l = first + 18L * iter + last + 160L * iter + fallback + iter;
    tgt_puts("\nT(20) = first + 18 iter + last + 8 x 20 halving + fallback + restart, halving "
             "<= iter, restart = iter: ");
    tgt_put_uint((unsigned long)t_l);
    tgt_puts("; with halving ~ eval (the estimate): ");
    estimate = first + 18L * iter + last + 160L * eval + fallback + iter;
    tgt_put_uint((unsigned long)estimate);
    tgt_puts("\n\n| substep_levels k | costliest step found | bound T_k(20) | estimate | "
             "what it did |\n|---:|---:|---:|---:|---|\n");
    for (level = 0; level < WT_LEVELS; level++) {
        long m = (2L << level) - 1L, f = 1L << level;
        bound = m * (t_l - fallback) + f * fallback;
        (void)wt_obj_step(&step_best[level], level);
        tgt_puts("| ");
        tgt_put_uint((unsigned long)level);
        tgt_puts(" | ");
        tgt_put_uint((unsigned long)worst[level]);
        tgt_puts(" | ");
        tgt_put_uint((unsigned long)bound);
        tgt_puts(" | ");
        tgt_put_uint((unsigned long)(m * (estimate - fallback) + f * fallback));
        tgt_puts(" | ");
        tgt_puts(edmi_status_name(wt_st));
        tgt_puts(", ");
        tgt_put_uint((unsigned long)wt_res.iterations);
        tgt_puts(" corrections, ");
        tgt_put_uint((unsigned long)wt_res.halvings);
        tgt_puts(" halvings, ");
        tgt_put_uint((unsigned long)wt_res.substeps);
        tgt_puts(" substeps, ");
        tgt_put_uint((unsigned long)wt_res.fallbacks);
        tgt_puts(" fallbacks, guard:");
        for (j = 0; j < 5; j++)
            if (wt_res.guard_action & (1u << j)) {
                tgt_puts(" ");
                tgt_puts(guard_moves[j]);
            }
        tgt_puts(wt_res.guard_action == 0u ? " none" : "");
        tgt_puts(", cause ");
        tgt_puts(edmi_status_name(wt_res.cause));
        tgt_puts(" |\n");
        if (worst[level] > bound) {
            tgt_puts("FAIL: the costliest step is above the bound\n");
            failed++;
        }
    }
    for (level = 0; level < WT_LEVELS; level++) {
        tgt_puts("\nThe costliest step at substep_levels ");
        tgt_put_uint((unsigned long)level);
        tgt_puts(":\n");
        wt_put_state(&step_best[level]);
    }
    tgt_puts(failed ? "\n0 passed, 1 failed\n" : "\n1 passed, 0 failed\n");
    return failed;
}
