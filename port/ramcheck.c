/* ramcheck: the RAM formula of docs/sizing.md against sizeof (`make check-ram`).
 *
 * Built once per (EDMI_REAL, EDMI_MAX_BODIES, EDMI_MAX_LINKS, EDMI_MAX_DAMPERS) setting. The
 * formula is checked twice: at compile time (a negative array size stops the build, so a
 * cross compile of this file checks a target's ABI without running anything) and at run
 * time on the host (printing both sides and closing with "N passed, N failed").
 * -DTGT_RAMCHECK_NO_MAIN: the compile-time checks only. -DTGT_RAMCHECK_SIZES_ONLY: no checks,
 * only the two arrays below, whose symbol sizes `make cross` reads with nm -S.
 *
 * Derivation from the struct definitions in edmi.h, with R = sizeof(edmi_real),
 * P = sizeof(void *), E = sizeof(an enum), N = EDMI_MAX_BODIES, L = EDMI_MAX_LINKS,
 * D = max(EDMI_MAX_DAMPERS, 1) (0 compiles dampers out but keeps one slot), RP = max(R, P),
 * and up(x, a) = x rounded up to a multiple of a.
 * Assumptions: int is 4 bytes; edmi_real and pointers are aligned to their size (AAPCS Arm,
 * RISC-V ilp32/lp64, x86-64, AArch64; not i386, where double is 4-aligned in structs); an
 * enum is 4 bytes except on arm-none-eabi, whose GCC defaults to -fshort-enums (E = 1).
 *   edmi_params    = up(up(up(3E, R) + 3R + 2*4 + E, R) + R + 2*4, R) 3 enums, 3 reals,
 *                                                                2 ints, guard (enum),
 *                                                                tank_cap, substep_levels and
 *                                                                fallback (ints)
 *   edmi_potential = up(up(up(E, R) + 2R, P) + 3P, RP)           kind, a, b, fn, dd, ctx
 *   edmi_link      = up(2*4 + 3R, RP) + edmi_potential           a, b, anchor[3], pot
 *   edmi_body      = 7R                                          m, q[3], p[3]
 *   edmi_damper    = up(4, R) + R                                link, c
 *   edmi_wall      = up(up(4, R) + 4R, RP) + edmi_potential       a, n[3], c, pot
 *   edmi_system, field by field:
 *     s = up(2*4, R) + R + edmi_params + N*7R                    n_bodies, n_links, t, params,
 *                                                                body[N]
 *     s = up(s, RP) + L*edmi_link + 4                            link[L], has_field
 *     s = up(s, R) + 3R + 4                                      g[3], n_dampers
 *     s = up(s, R) + D*edmi_damper [+ 4, up(, RP) + W*edmi_wall] damper[D], n_walls, wall[W]
 *                                                                (W = EDMI_MAX_WALLS > 0 only)
 *     s = up(s, R) + 3R*N + N*G*R + R + 3R*L + 3R*W              force[N][3], mass_off[N][G]
 *                                                                (G = EDMI_MAX_MASS_GAP, 0 by
 *                                                                default), tank, link_force[L][3],
 *                                                                wall_force[W][3]
 *     internal = up(up(P, R) + (2 + W + 3L)R + 4(4 + N + L), RP) kept_work, kept_dt, t_carry,
 *                                                                wall_next[W], anchor_next[L][3],
 *                                                                kept_bodies, kept_links,
 *                                                                n_forced, forced[N], n_moving,
 *                                                                moving[L]
 *     sizeof(edmi_system) = up(s, RP) + internal
 *   edmi_link_ws   = up(56R + 12, R)    r0[3], 12 scalars, x1[3], f[3], gamma, rm[3], u[3],
 *                                       the balance's 6 reals and the 13 of its cached end,
 *                                       the substeps' fsum[3], xs[3], xt[3], bal_on, have1,
 *                                       end_kind
 *   edmi_workspace = up((M + 32N + 9D) R + (L + W)*edmi_link_ws + 4(6N + L + 3), R)
 *                    reals, lw[L], ww[W], then the ints row[3N], order[L], n_pair, piv[3N],
 *                    kb, upper
 * The 32N reals are q1, p1, rq, rp, dp, rhs, q0, p0 (3 each), sq, sp, h (1 each) and kend (5); M =
 * EDMI_MAX_MATRIX (default 9N^2) is the Newton matrix; 9 reals per damper its tangent block. */
#include "edmi.h"

#define TGT_UP(x, a) ((((x) + (a) - 1u) / (a)) * (a))
#define TGT_MAX(a, b) ((a) > (b) ? (a) : (b))
#define TGT_R ((unsigned long)sizeof(edmi_real))
#define TGT_P ((unsigned long)sizeof(void *))
#define TGT_E ((unsigned long)sizeof(edmi_scheme))
#define TGT_N ((unsigned long)EDMI_MAX_BODIES)
#define TGT_L ((unsigned long)EDMI_MAX_LINKS)
#define TGT_D ((unsigned long)EDMI_DAMPER_SLOTS_) /* EDMI_MAX_DAMPERS = 0 keeps one slot */
#define TGT_W ((unsigned long)EDMI_MAX_WALLS) /* 0: no wall members at all */
#define TGT_RP TGT_MAX(TGT_R, TGT_P)

#define TGT_PARAMS \
    TGT_UP(TGT_UP(TGT_UP(3u * TGT_E, TGT_R) + 3u * TGT_R + 8u + TGT_E, TGT_R) + TGT_R + 8u, TGT_R)
#define TGT_POT TGT_UP(TGT_UP(TGT_UP(TGT_E, TGT_R) + 2u * TGT_R, TGT_P) + 3u * TGT_P, TGT_RP)
#define TGT_LINK (TGT_UP(8u + 3u * TGT_R, TGT_RP) + TGT_POT)
#define TGT_DAMPER (TGT_UP(4u, TGT_R) + TGT_R)
#define TGT_WALL (TGT_UP(TGT_UP(4u, TGT_R) + 4u * TGT_R, TGT_RP) + TGT_POT)
#define TGT_S1 (TGT_UP(8u, TGT_R) + TGT_R + TGT_PARAMS + TGT_N * 7u * TGT_R)
#define TGT_S2 (TGT_UP(TGT_S1, TGT_RP) + TGT_L * TGT_LINK + 4u)
#define TGT_S3 (TGT_UP(TGT_S2, TGT_R) + 3u * TGT_R + 4u)
#define TGT_S4                                                                              \
    (TGT_W > 0u ? TGT_UP(TGT_UP(TGT_S3, TGT_R) + TGT_D * TGT_DAMPER + 4u, TGT_RP) +             \
                      TGT_W * TGT_WALL                                                        \
                : TGT_UP(TGT_S3, TGT_R) + TGT_D * TGT_DAMPER)
#define TGT_G ((unsigned long)EDMI_MAX_MASS_GAP)
#define TGT_S5                                                                              \
    (TGT_UP(TGT_S4, TGT_R) + 3u * TGT_R * TGT_N + TGT_R * TGT_N * TGT_G + TGT_R +             \
     3u * TGT_R * TGT_L + 3u * TGT_R * TGT_W)
/* the internal sub-struct: the kept factors' pointer, kept_dt, t_carry, wall_next[W],
 * anchor_next[L][3], then the ints kept_bodies, kept_links, n_forced, forced[N], n_moving,
 * moving[L] */
#define TGT_INTERNAL                                                                        \
    TGT_UP(TGT_UP(TGT_P, TGT_R) + (2u + TGT_W + 3u * TGT_L) * TGT_R + 4u * (4u + TGT_N + TGT_L), \
           TGT_RP)
#define TGT_SYSTEM (TGT_UP(TGT_S5, TGT_RP) + TGT_INTERNAL)
#define TGT_M ((unsigned long)EDMI_MAX_MATRIX)
#define TGT_LINK_WS TGT_UP(56u * TGT_R + 12u, TGT_R)
#define TGT_WS0                                                                               \
    ((TGT_M + 32u * TGT_N + 9u * TGT_D) * TGT_R + (TGT_L + TGT_W) * TGT_LINK_WS +               \
     4u * (6u * TGT_N + TGT_L + 3u))
/* then whose kept factors they are (a pointer) and two ints */
#define TGT_WORKSPACE TGT_UP(TGT_UP(TGT_WS0, TGT_P) + TGT_P + 8u, TGT_RP)

/* The closed forms of docs/sizing.md: RAM = sizeof(edmi_system) + sizeof(edmi_workspace) =
 * K + R M + b N + l L + d D + w W + R N G + pad (M = EDMI_MAX_MATRIX, by default 9 N^2):
 *   float:  K = 128 with 4-byte pointers and 1-byte enums (arm-none-eabi), 136 with 4-byte
 *           enums, 148 with 8-byte pointers; with walls 4 more with 4-byte pointers (n_walls);
 *           b = 196, d = 44; l = 312 and w = 296 with 4-byte pointers, 332 and 316 with 8-byte
 *           ones; pad = 0 with 4-byte pointers; with 8-byte ones, without walls, 4 when
 *           N + N G + L is odd (the public part's tail before the internal sub-struct's
 *           pointer) + 4 when M + D is even (the workspace's pointer after its int tail);
 *           with walls 4 when N is even (link[] after body[N]) + 4 when N + N G + L + W is
 *           even + 4 when N + W is odd (the sub-struct's int tail) + 4 when M + D + W is even
 *   double: K = 192 with 4-byte pointers and 1-byte enums, 200 with 4-byte enums, 204 with
 *           8-byte pointers; with walls 8 more (n_walls and its alignment); b = 364, d = 88;
 *           l = 592 and w = 576 with 4-byte pointers, 600 and 584 with 8-byte ones; pad = 4
 *           when N + L is odd (the sub-struct's int tail) + 4 when L is odd with 4-byte
 *           pointers, even with 8-byte ones (the workspace's int tail before its pointer) */
#define TGT_CLOSED_K                                                                        \
    ((TGT_R == 4u ? (TGT_P == 4u ? 128u : 140u) : (TGT_P == 4u ? 192u : 196u)) +              \
     (TGT_E == 4u ? 8u : 0u) +                                                                \
     (TGT_W > 0u ? (TGT_R == 8u ? 8u : TGT_P == 4u ? 4u : 0u) : 0u))
#define TGT_CLOSED_B (TGT_R == 4u ? 196u : 364u)
#define TGT_CLOSED_L (TGT_P == 4u ? (TGT_R == 4u ? 312u : 592u) : (TGT_R == 4u ? 332u : 600u))
#define TGT_CLOSED_D (TGT_R == 4u ? 44u : 88u)
#define TGT_CLOSED_W (TGT_R == 4u ? (TGT_P == 4u ? 296u : 316u) : (TGT_P == 4u ? 576u : 584u))
#define TGT_ODD(x) ((x) % 2u == 1u ? 4u : 0u)
#define TGT_EVEN(x) ((x) % 2u == 0u ? 4u : 0u)
#define TGT_CLOSED_PAD                                                                      \
    (TGT_R == 8u ? TGT_ODD(TGT_N + TGT_L) + (TGT_P == 4u ? TGT_ODD(TGT_L) : TGT_EVEN(TGT_L))    \
     : TGT_P == 4u ? 0u                                                                        \
     : TGT_W == 0u ? TGT_ODD(TGT_N + TGT_N * TGT_G + TGT_L) + TGT_EVEN(TGT_M + TGT_D)         \
                   : TGT_EVEN(TGT_N) + TGT_EVEN(TGT_N + TGT_N * TGT_G + TGT_L + TGT_W) +      \
                         TGT_ODD(TGT_N + TGT_W) + TGT_EVEN(TGT_M + TGT_D + TGT_W))
#define TGT_CLOSED                                                                          \
    (TGT_CLOSED_K + TGT_R * TGT_M + TGT_CLOSED_B * TGT_N + TGT_CLOSED_L * TGT_L +             \
     TGT_CLOSED_D * TGT_D + TGT_CLOSED_W * TGT_W + TGT_R * TGT_N * TGT_G + TGT_CLOSED_PAD)
#define TGT_TOTAL ((unsigned long)(sizeof(edmi_system) + sizeof(edmi_workspace)))

#ifndef TGT_RAMCHECK_SIZES_ONLY
/* The assumptions, then the formulas, checked by the compiler. */
typedef char tgt_assume_int[sizeof(int) == 4 ? 1 : -1];
typedef char tgt_assume_enum[TGT_E == 1u || TGT_E == 4u ? 1 : -1];
typedef char tgt_assume_ptr[TGT_P == 4u || TGT_P == 8u ? 1 : -1];
typedef char tgt_check_system[sizeof(edmi_system) == TGT_SYSTEM ? 1 : -1];
typedef char tgt_check_workspace[sizeof(edmi_workspace) == TGT_WORKSPACE ? 1 : -1];
typedef char tgt_check_closed[TGT_TOTAL == TGT_CLOSED ? 1 : -1];
#endif

/* The sizes as symbol sizes, for `nm -S` on a cross-compiled object (make cross). */
char tgt_ram_system[sizeof(edmi_system)];
char tgt_ram_workspace[sizeof(edmi_workspace)];

#if !defined(TGT_RAMCHECK_NO_MAIN) && !defined(TGT_RAMCHECK_SIZES_ONLY)
#include <stdio.h>

static int n_pass, n_fail;

static void check(const char *what, unsigned long got, unsigned long want)
{
    int ok = got == want;
    if (ok)
        n_pass++;
    else
        n_fail++;
    printf("%s %-44s sizeof %7lu  formula %7lu\n", ok ? "ok  " : "FAIL", what, got, want);
}

int main(void)
{
    unsigned long n = TGT_N, l = TGT_L;
    printf("EDMI_REAL=%s EDMI_MAX_BODIES=%lu EDMI_MAX_LINKS=%lu EDMI_MAX_DAMPERS=%lu "
           "(R=%lu, P=%lu, E=%lu)\n",
           TGT_R == 8u ? "double" : "float", n, l, (unsigned long)EDMI_MAX_DAMPERS, TGT_R, TGT_P,
           TGT_E);
    check("sizeof(edmi_params)", (unsigned long)sizeof(edmi_params), TGT_PARAMS);
    check("sizeof(edmi_potential)", (unsigned long)sizeof(edmi_potential), TGT_POT);
    check("sizeof(edmi_link)", (unsigned long)sizeof(edmi_link), TGT_LINK);
    check("sizeof(edmi_body)", (unsigned long)sizeof(edmi_body), 7u * TGT_R);
    check("sizeof(edmi_damper)", (unsigned long)sizeof(edmi_damper), TGT_DAMPER);
    check("sizeof(edmi_wall)", (unsigned long)sizeof(edmi_wall), TGT_WALL);
    check("sizeof(edmi_link_ws)", (unsigned long)sizeof(edmi_link_ws), TGT_LINK_WS);
    check("sizeof(edmi_system)", (unsigned long)sizeof(edmi_system), TGT_SYSTEM);
    check("sizeof(edmi_workspace)", (unsigned long)sizeof(edmi_workspace), TGT_WORKSPACE);
    check("system + workspace (docs/sizing.md closed form)", TGT_TOTAL, TGT_CLOSED);
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
#endif
