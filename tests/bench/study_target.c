/* study_target: the Cortex-M4F column of the work-precision study (`make study-target`, run
 * by `make study`; tests/bench/study/).
 *
 * The study's five scenes, built here as edmi calls from the same data as their scene files
 * (examples/scenes/: neo_hookean, lj_two_body, lj_cluster8, solar_system, hanging_chain), with
 * edmi_default_params() and one scheme, in float. For each, PM at every dt of the study's sweep
 * and MP, LG, GE, PT and a velocity-Verlet step (tests/lib/bench_scenes.h: links only, so not on
 * the chain) at the sweep's middle dt. Each run takes STUDY_STEPS steps from the initial state
 * (fewer when the scene reaches the study's end time T first) and prints one CSV line:
 *     m4f,SCENE,METHOD,DT,STEPS,INSTRUCTIONS_PER_STEP,CORRECTIONS_PER_STEP
 * Counting as in tests/bench/bench_target.c: SysTick under QEMU's -icount shift=0 ticks once per 40
 * instructions; a loop of known length checks that ratio first, and the program refuses to
 * print numbers without it. Instructions, not cycles (a VDIV.F32 or VSQRT.F32 takes 14). */
#include <stddef.h>

#include "edmi.h"
#include "bench_scenes.h"
#include "cortex-m/counter.h"
#include "cortex-m/semihost.h"

#define STUDY_STEPS 500
#define STUDY_CHUNK 50 /* steps per SysTick interval: far below its 2^24-tick wrap */
#define STUDY_INSNS_PER_TICK 40UL
#define STUDY_CAL_ITERS 100000UL

static edmi_system sys;
static edmi_workspace work;

static void cal_loop(unsigned long n)
{
    __asm__ volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n) : : "cc");
}

/* 1 if SysTick counts one tick per 40 instructions (a 2n-instruction loop, n = 100000). */
static int counter_ok(void)
{
    unsigned long t0, t1, want = 2UL * STUDY_CAL_ITERS / STUDY_INSNS_PER_TICK;
    tgt_ticks_start();
    t0 = tgt_ticks();
    cal_loop(STUDY_CAL_ITERS);
    t1 = tgt_ticks();
    return t1 - t0 >= want && t1 - t0 <= want + 2UL;
}

/* ---- scenes (the scene files' data) ------------------------------------------------------- */

static edmi_status cluster8(edmi_scheme scheme)
{
    static const edmi_real qp[8][6] = {
        {EDMI_R(-0.5803), EDMI_R(-0.5115), EDMI_R(-0.5891), EDMI_R(-0.3712), EDMI_R(0.1292), EDMI_R(-0.0795)},
        {EDMI_R(-0.5325), EDMI_R(-0.5992), EDMI_R(0.5455), EDMI_R(-0.0126), EDMI_R(-0.0398), EDMI_R(0.1089)},
        {EDMI_R(-0.5030), EDMI_R(0.5357), EDMI_R(-0.5375), EDMI_R(-0.1105), EDMI_R(0.1469), EDMI_R(0.2350)},
        {EDMI_R(-0.5570), EDMI_R(0.5600), EDMI_R(0.5703), EDMI_R(-0.0601), EDMI_R(-0.1576), EDMI_R(-0.2672)},
        {EDMI_R(0.5387), EDMI_R(-0.5247), EDMI_R(-0.5927), EDMI_R(0.1586), EDMI_R(0.0503), EDMI_R(-0.1895)},
        {EDMI_R(0.5429), EDMI_R(-0.6057), EDMI_R(0.5474), EDMI_R(0.1586), EDMI_R(0.1045), EDMI_R(0.1315)},
        {EDMI_R(0.5603), EDMI_R(0.6049), EDMI_R(-0.5638), EDMI_R(0.1195), EDMI_R(-0.0715), EDMI_R(-0.0918)},
        {EDMI_R(0.5309), EDMI_R(0.5406), EDMI_R(0.6199), EDMI_R(0.1177), EDMI_R(-0.1620), EDMI_R(0.1526)}};
    edmi_potential lj = edmi_pot_lj(EDMI_R(1.0), EDMI_R(1.0));
    edmi_params prm = edmi_default_params();
    edmi_status s;
    int a, b;
    prm.scheme = scheme;
    s = edmi_init(&sys, &prm);
    for (a = 0; a < 8 && s == EDMI_OK; a++)
        s = edmi_add_body(&sys, EDMI_R(1.0), qp[a], qp[a] + 3, NULL);
    for (a = 0; a < 8; a++)
        for (b = a + 1; b < 8 && s == EDMI_OK; b++)
            s = edmi_add_pair(&sys, a, b, &lj, NULL);
    return s;
}

static edmi_status chain(edmi_scheme scheme)
{
    static const edmi_real origin[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
    static const edmi_real g[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(-9.81)};
    static const edmi_real push[3] = {EDMI_R(0.3), EDMI_R(0.0), EDMI_R(0.0)};
    edmi_potential spring = edmi_pot_neo_hooke(EDMI_R(200.0), EDMI_R(0.1));
    edmi_params prm = edmi_default_params();
    edmi_status s;
    int k;
    prm.scheme = scheme;
    s = edmi_init(&sys, &prm);
    for (k = 1; k <= 6 && s == EDMI_OK; k++) {
        edmi_real q[3], p[3] = {EDMI_R(0.0), EDMI_R(0.0), EDMI_R(0.0)};
        q[0] = EDMI_R(0.05) * (edmi_real)k;
        q[1] = EDMI_R(0.0);
        q[2] = EDMI_R(-0.1) * (edmi_real)k;
        if (k == 6)
            p[1] = EDMI_R(0.02);
        s = edmi_add_body(&sys, EDMI_R(0.1), q, p, NULL);
    }
    if (s == EDMI_OK)
        s = edmi_add_anchor(&sys, 0, origin, &spring, NULL);
    for (k = 0; k < 5 && s == EDMI_OK; k++)
        s = edmi_add_pair(&sys, k, k + 1, &spring, NULL);
    if (s == EDMI_OK)
        s = edmi_set_field(&sys, g);
    for (k = 0; k < 6 && s == EDMI_OK; k++)
        s = edmi_add_damper(&sys, k, EDMI_R(0.05), NULL);
    if (s == EDMI_OK)
        s = edmi_set_force(&sys, 5, push);
    return s;
}

static edmi_status spring(edmi_scheme scheme) { return bs_spring(&sys, scheme); }
static edmi_status lj2(edmi_scheme scheme) { return bs_lj2(&sys, scheme); }
static edmi_status solar(edmi_scheme scheme) { return bs_solar(&sys, scheme); }

typedef edmi_status (*scene_fn)(edmi_scheme scheme);

typedef struct study_scene {
    const char *name;
    scene_fn build;
    edmi_real t_end;
    int n_dt, mid;       /* the sweep and the index of its middle dt */
    edmi_real dt[5];
    const char *dt_text[5];
    int verlet;          /* bs_verlet_step handles its effects */
} study_scene;

static const study_scene scenes[] = {
    {"neo_hookean", spring, EDMI_R(10.0), 5, 2,
     {EDMI_R(4e-3), EDMI_R(2e-3), EDMI_R(1e-3), EDMI_R(5e-4), EDMI_R(2.5e-4)},
     {"0.004", "0.002", "0.001", "0.0005", "0.00025"}, 1},
    {"lj_two_body", lj2, EDMI_R(2.0), 5, 2,
     {EDMI_R(4e-3), EDMI_R(2e-3), EDMI_R(1e-3), EDMI_R(5e-4), EDMI_R(2.5e-4)},
     {"0.004", "0.002", "0.001", "0.0005", "0.00025"}, 1},
    {"lj_cluster8", cluster8, EDMI_R(5.0), 5, 2,
     {EDMI_R(1e-2), EDMI_R(5e-3), EDMI_R(2.5e-3), EDMI_R(1.25e-3), EDMI_R(6.25e-4)},
     {"0.01", "0.005", "0.0025", "0.00125", "0.000625"}, 1},
    {"solar_system", solar, EDMI_R(365.0), 4, 2,
     {EDMI_R(3.65), EDMI_R(1.825), EDMI_R(0.9125), EDMI_R(0.45625), EDMI_R(0.0)},
     {"3.65", "1.825", "0.9125", "0.45625", ""}, 1},
    {"hanging_chain", chain, EDMI_R(5.0), 5, 2,
     {EDMI_R(4e-3), EDMI_R(2e-3), EDMI_R(1e-3), EDMI_R(5e-4), EDMI_R(2.5e-4)},
     {"0.004", "0.002", "0.001", "0.0005", "0.00025"}, 0}};

static const char *const scheme_word[] = {"mp", "lg", "ge", "pm", "pt"};

/* v / d to two decimals, rounded half up. */
static void put_ratio(unsigned long long v, unsigned long long d)
{
    unsigned long long x = (v * 100ULL + d / 2ULL) / d;
    tgt_put_uint((unsigned long)(x / 100ULL));
    tgt_putchar('.');
    tgt_putchar('0' + (int)(x / 10ULL % 10ULL));
    tgt_putchar('0' + (int)(x % 10ULL));
}

static void put_head(const study_scene *sc, int k, int scheme)
{
    tgt_puts("m4f,");
    tgt_puts(sc->name);
    tgt_putchar(',');
    tgt_puts(scheme < 0 ? "verlet" : scheme_word[scheme]);
    tgt_putchar(',');
    tgt_puts(sc->dt_text[k]);
    tgt_putchar(',');
}

/* Run one scene, scheme (or Verlet) and dt; print its line. A step that fails is a measured
 * outcome (printed with its status); 1 only if the scene cannot be built or SysTick wrapped. */
static int measure(const study_scene *sc, int k, int scheme)
{
    edmi_real dt = sc->dt[k];
    long n = (long)(sc->t_end / dt + EDMI_R(0.5)), done = 0;
    unsigned long long insns = 0, corrections = 0;
    edmi_step_result res;
    edmi_status s;
    if (n > STUDY_STEPS)
        n = STUDY_STEPS;
    s = sc->build(scheme < 0 ? EDMI_SCHEME_PM : (edmi_scheme)scheme);
    if (s != EDMI_OK)
        return 1;
    if (scheme < 0)
        bs_verlet_start(&sys);
    while (done < n) {
        unsigned long t0, t1;
        long j, m = n - done < STUDY_CHUNK ? n - done : STUDY_CHUNK;
        tgt_ticks_start();
        t0 = tgt_ticks();
        for (j = 0; j < m; j++) {
            if (scheme < 0) {
                bs_verlet_step(&sys, dt);
                continue;
            }
            s = edmi_step(&sys, &work, dt, &res);
            if (s != EDMI_OK)
                break;
            corrections += (unsigned long long)res.iterations;
        }
        t1 = tgt_ticks();
        if (tgt_ticks_wrapped())
            return 1;
        if (s != EDMI_OK) {
            put_head(sc, k, scheme);
            tgt_puts("failed at step ");
            tgt_put_uint((unsigned long)(done + j + 1));
            tgt_puts(": ");
            tgt_puts(edmi_status_name(s));
            tgt_putchar('\n');
            return 0;
        }
        insns += (unsigned long long)(t1 - t0) * STUDY_INSNS_PER_TICK;
        done += m;
    }
    put_head(sc, k, scheme);
    tgt_put_uint((unsigned long)n);
    tgt_putchar(',');
    put_ratio(insns, (unsigned long long)n);
    tgt_putchar(',');
    put_ratio(corrections, (unsigned long long)n);
    tgt_putchar('\n');
    return 0;
}

int main(void)
{
    static const int others[] = {EDMI_SCHEME_MP, EDMI_SCHEME_LG, EDMI_SCHEME_GE, EDMI_SCHEME_PT, -1};
    size_t i;
    int k, o, failed = 0;
    (void)bs_pairs; /* tests/lib/bench_scenes.h's all-pairs scene: not one of the study's */
    if (!counter_ok()) {
        tgt_puts("study_target: SysTick does not tick once per 40 instructions: run under "
                 "QEMU with -icount shift=0\n");
        tgt_exit(1);
    }
    tgt_puts("# scene,method,dt,steps,instructions/step,corrections/step (Cortex-M4F, float, "
             "edmi.c -Os; the mean over the first steps from the initial state)\n");
    for (i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        const study_scene *sc = &scenes[i];
        for (k = 0; k < sc->n_dt; k++)
            failed |= measure(sc, k, EDMI_SCHEME_PM);
        for (o = 0; o < 5; o++)
            if (others[o] >= 0 || sc->verlet)
                failed |= measure(sc, sc->mid, others[o]);
    }
    tgt_puts(failed ? "study_target: a run failed\n" : "study_target: done\n");
    tgt_exit(failed);
}
