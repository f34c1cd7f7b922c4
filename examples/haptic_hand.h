/* The haptic example's coupling and its synthetic hand: one axis, six seconds, deterministic.
 * Shared by examples/haptic.c (host) and tests/bench/haptic_target.c (Cortex-M4F), so that both run
 * the same model and trajectory in edmi_real; no libm (the sine is a series, see hh_sin).
 *
 * The coupling: a virtual tool of HH_MASS on a zero-rest-length spring HH_STIFFNESS with a
 * damper HH_DAMPING to the hand, one tick of HH_DT, HH_TICKS ticks. The hand:
 *
 *   x(t) = 25 mm (1 - cos 2 pi 0.9 t) - 6 mm (1 - cos 2 pi 3.1 t) + sum_j A_j s_j(t)
 *
 * A slow reach and a faster wobble that both start at rest (x = 0, x' = 0 at t = 0), plus five
 * flicks: minimum-jerk moves s(u) = 10 u^3 - 15 u^4 + 6 u^5 of 6-12 mm over 12-25 ms (peak
 * speed 1.875 A/T, up to 1.25 m/s; peak acceleration 5.77 A/T^2, up to 260 m/s^2). The flicks'
 * spectra reach well past the coupling's resonance, so they ring it: that is where
 * integrators differ. */
#ifndef EDMI_HAPTIC_HAND_H
#define EDMI_HAPTIC_HAND_H

#include "edmi.h"

#define HH_MASS EDMI_R(0.1)         /* tool mass [kg] */
#define HH_STIFFNESS EDMI_R(3000.0) /* coupling spring [N/m]: 3 N/mm */
#define HH_DAMPING EDMI_R(0.5)      /* coupling damper [N s/m] */
#define HH_DT EDMI_R(1e-3)          /* tick [s]: 1 kHz */
#define HH_TICKS 6000L              /* ticks: 6 s */

/* The wall the hand presses the tool into (examples/tool_on_wall.c, tests/bench/haptic_target.c
 * with HT_WALL): the plane x = HH_WALL_X, the tool on its side x < HH_WALL_X, the contact
 * potential HH_WALL_K / 3 (-g)^3 of the gap g = HH_WALL_X - x. */
#define HH_WALL_X EDMI_R(0.04)  /* [m]: the hand reaches 57 mm */
#define HH_WALL_K EDMI_R(1e8)   /* [N/m^2]: 51 N at 0.7 mm */

#define HH_PI EDMI_R(3.141592653589793)
#define HH_TWO_PI EDMI_R(6.283185307179586)
#define HH_N_FLICKS 5

/* Start time [s], amplitude [m] and duration [s] of each flick. */
static const edmi_real hh_flick[HH_N_FLICKS][3] = {
    {EDMI_R(0.8), EDMI_R(0.008), EDMI_R(0.020)},  {EDMI_R(1.9), EDMI_R(-0.012), EDMI_R(0.025)},
    {EDMI_R(2.9), EDMI_R(0.010), EDMI_R(0.015)},  {EDMI_R(3.6), EDMI_R(-0.006), EDMI_R(0.012)},
    {EDMI_R(4.7), EDMI_R(0.012), EDMI_R(0.020)}};

/* sin x without libm: x reduced to [-pi, pi] by whole turns, then the Taylor series to the
 * x^23 term (error below 1e-16 on [-pi, pi]; the trajectory needs smoothness and
 * reproducibility, not the last bit). Functions are static inline: each program uses what
 * it needs without unused-function warnings. */
static inline edmi_real hh_sin(edmi_real x)
{
    edmi_real t, sum, term;
    int k;
    x -= HH_TWO_PI * (edmi_real)(long)(x / HH_TWO_PI);
    if (x > HH_PI)
        x -= HH_TWO_PI;
    if (x < -HH_PI)
        x += HH_TWO_PI;
    t = x * x;
    sum = term = x;
    for (k = 1; k < 12; k++) {
        term *= -t / (edmi_real)((2 * k) * (2 * k + 1));
        sum += term;
    }
    return sum;
}

/* 1 - cos x = 2 sin^2(x/2): no cancellation near x = 0, where the hand starts. */
static inline edmi_real hh_one_minus_cos(edmi_real x)
{
    edmi_real s = hh_sin(EDMI_R(0.5) * x);
    return EDMI_R(2.0) * s * s;
}

/* The hand's position x(t) [m]. */
static inline edmi_real hh_position(edmi_real t)
{
    edmi_real x = EDMI_R(0.025) * hh_one_minus_cos(HH_TWO_PI * EDMI_R(0.9) * t) -
                  EDMI_R(0.006) * hh_one_minus_cos(HH_TWO_PI * EDMI_R(3.1) * t);
    int j;
    for (j = 0; j < HH_N_FLICKS; j++) {
        edmi_real u = (t - hh_flick[j][0]) / hh_flick[j][2];
        if (u >= EDMI_R(1.0))
            x += hh_flick[j][1];
        else if (u > EDMI_R(0.0))
            x += hh_flick[j][1] * u * u * u *
                 (EDMI_R(10.0) + u * (EDMI_R(-15.0) + EDMI_R(6.0) * u));
    }
    return x;
}

/* The hand's velocity x'(t) [m/s], the exact derivative of hh_position. The explicit
 * integrators' dampers need it; edmi does not (its damper acts on the step's displacement). */
static inline edmi_real hh_velocity(edmi_real t)
{
    static const edmi_real w1 = HH_TWO_PI * EDMI_R(0.9), w2 = HH_TWO_PI * EDMI_R(3.1);
    edmi_real v = EDMI_R(0.025) * w1 * hh_sin(w1 * t) - EDMI_R(0.006) * w2 * hh_sin(w2 * t);
    int j;
    for (j = 0; j < HH_N_FLICKS; j++) {
        edmi_real u = (t - hh_flick[j][0]) / hh_flick[j][2];
        if (u > EDMI_R(0.0) && u < EDMI_R(1.0))
            v += hh_flick[j][1] / hh_flick[j][2] * EDMI_R(30.0) * u * u * (EDMI_R(1.0) - u) *
                 (EDMI_R(1.0) - u);
    }
    return v;
}

#endif
