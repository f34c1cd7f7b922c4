#!/bin/sh
# Issue 21's hard cases measured on the current edmi.c (public API only), double and float:
# (1) two bodies deep in a Lennard-Jones wall, one step of every scheme and dt; (2) coupled
# mass matrices with the fallback; (3) a user spring the guard once failed on; (4) a port
# flipping sign every tick, radial chatter through an anchor, and l_max = 1. Each program
# prints, per configuration, steps, EDMI_OK steps, fallbacks, failures by status, steps split
# into substeps, and the residual at every stored, solved state against the terms'
# magnitudes (hard_common.h). Three runs each: as built (out/*.k0.txt), with 3 levels of
# substeps (HC_SUBSTEPS=3: *.k3.txt) and with the fallback too (HC_FB=1: *.k3fb.txt).
# Usage: sh tests/bench/hard/run.sh [outdir]   (from the repository root; `make hard` runs it with
# outdir $(BUILD)/hard)
set -e
out=${1:-/tmp/hard}
mkdir -p "$out"
for p in double float; do
    for c in case1_lj_wall case2_fallback_mass case3_user_spring case4_flip_port; do
        cc -std=c99 -O2 -Wall -Wextra -DEDMI_REAL=$p -DEDMI_MAX_MASS_GAP=1 -I. -Itests/bench/hard \
            -Itests/lib tests/bench/hard/$c.c tests/lib/passive.c edmi.c -lm -o "$out/${c}_$p"
        "$out/${c}_$p" > "$out/${c}_$p.k0.txt"
        HC_SUBSTEPS=3 "$out/${c}_$p" > "$out/${c}_$p.k3.txt"
        HC_SUBSTEPS=3 HC_FB=1 "$out/${c}_$p" > "$out/${c}_$p.k3fb.txt"
    done
done
echo "outputs in $out"
