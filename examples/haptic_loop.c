/* A 1 kHz virtual coupling: a tool of 0.1 kg on a 3 N/mm spring and a damper to the hand.
 * Each tick: read the hand (where it is at the tick's start), move the anchor there (it gets
 * there at the tick's end: one tick late), step, render the link's force over the next tick. */
#include <math.h>
#include <stdio.h>
#include "edmi.h"

static edmi_system sys;
static edmi_workspace work;

/* The device: here a hand that reaches 5 cm and wobbles at 3 Hz, measured at the start of
 * tick `tick` (t = (tick - 1) ms), and a console. */
static void read_hand(long tick, edmi_real x[3])
{
    double t = 1e-3 * (double)(tick - 1);
    x[0] = (edmi_real)(0.05 * (1.0 - cos(3.14159 * t)) + 0.002 * sin(18.85 * t));
    x[1] = x[2] = 0;
}
static void render_force(long tick, const edmi_real f[3])
{
    if (tick % 250 == 0)
        printf("t = %.2f s  force on the hand %+.4f N\n", 1e-3 * (double)tick, (double)f[0]);
}

/* 1 (and says which call and why) if a set-up call failed. */
static int failed(const char *call, edmi_status s)
{
    if (s != EDMI_OK)
        printf("%s: %s\n", call, edmi_status_name(s));
    return s != EDMI_OK;
}

int main(void)
{
    const edmi_real zero[3] = {0, 0, 0};
    edmi_potential spring = edmi_pot_harmonic(EDMI_R(3000.0), EDMI_R(0.0)); /* K, rest 0 */
    edmi_params prm = edmi_default_params(); /* PM, passivity guard on */
    edmi_real hand[3];
    int tool, link, fallbacks = 0;
    long tick;

    prm.fallback = 1; /* every tick ends with a passive state, in bounded time */
    if (!EDMI_CONFIG_MATCHES()) {
        printf("edmi.h here and edmi.c were built with different EDMI_ options\n");
        return 1;
    }
    if (failed("edmi_init", edmi_init(&sys, &prm)) ||
        failed("edmi_add_body", edmi_add_body(&sys, EDMI_R(0.1), zero, zero, &tool)) ||
        failed("edmi_add_anchor", edmi_add_anchor(&sys, tool, zero, &spring, &link)) ||
        failed("edmi_add_damper", edmi_add_damper(&sys, link, EDMI_R(0.5), NULL)))
        return 1;
    for (tick = 1; tick <= 2000; tick++) {
        edmi_step_result res;
        edmi_status s;
        read_hand(tick, hand);
        edmi_move_anchor(&sys, link, hand); /* where the anchor is at the tick's end */
        s = edmi_step(&sys, &work, EDMI_R(1e-3), &res);
        if (s != EDMI_OK) { /* refused input (NaN, bad dt): the state is unchanged */
            printf("tick %ld: %s\n", tick, edmi_status_name(s));
            return 1;
        }
        fallbacks += res.stop == EDMI_STOP_FALLBACK;
        render_force(tick, sys.link_force[link]); /* the mean force on the anchor */
    }
    printf("2000 ticks, %d fallback steps, tool at %.4f m\n", fallbacks,
           (double)sys.body[tool].q[0]);
    return 0;
}
