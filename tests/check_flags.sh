#!/usr/bin/env bash
# edmi.c refuses the compiler modes that drop the IEEE semantics it relies on (its NaN/Inf
# validation, the guard's double-word arithmetic): each must stop the build with edmi.c's
# #error, in both precisions; the strict flags must build. Then the configuration template and
# EDMI_CONFIG_MATCHES().   usage: check_flags.sh CC   (from the repository root)
# Last line: "N passed, N failed".
set -u
cc=${1:?usage: check_flags.sh CC}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
for real in float double; do
    for mode in -ffast-math -Ofast -ffinite-math-only; do
        if out=$($cc -std=c99 $mode -DEDMI_REAL=$real -c edmi.c -o "$tmp/x.o" 2>&1); then
            echo "FAIL $mode ($real): edmi.c compiled"; fail=$((fail + 1))
        elif grep -q 'edmi.c needs IEEE semantics' <<<"$out"; then
            echo "ok   $mode ($real): refused with edmi.c's #error"; pass=$((pass + 1))
        else
            echo "FAIL $mode ($real): failed, but not with edmi.c's #error: $(head -1 <<<"$out")"
            fail=$((fail + 1))
        fi
    done
    if $cc -std=c99 -O2 -ffp-contract=off -fno-math-errno -DEDMI_REAL=$real -c edmi.c \
            -o "$tmp/x.o" 2>/dev/null; then
        echo "ok   -O2 ($real): builds"; pass=$((pass + 1))
    else
        echo "FAIL -O2 ($real): does not build"; fail=$((fail + 1))
    fi
done
# The configuration template builds as it ships, and EDMI_CONFIG_MATCHES() tells a
# translation unit compiled with other capacities from one compiled with the library's.
if $cc -std=c99 -Wall -Wextra -Werror -DEDMI_USER_CONFIG='"port/edmi_config_template.h"' \
        -c edmi.c -o "$tmp/lib.o" 2>/dev/null; then
    echo "ok   port/edmi_config_template.h builds as EDMI_USER_CONFIG"; pass=$((pass + 1))
else
    echo "FAIL port/edmi_config_template.h does not build"; fail=$((fail + 1))
fi
printf '#include "edmi.h"\nint main(void) { return EDMI_CONFIG_MATCHES() ? 0 : 3; }\n' > "$tmp/app.c"
$cc -std=c99 -I. -c edmi.c -o "$tmp/lib16.o"
for bodies in 16 8; do
    if $cc -std=c99 -I. -DEDMI_MAX_BODIES=$bodies "$tmp/app.c" "$tmp/lib16.o" -o "$tmp/app" -lm; then
        "$tmp/app"; rc=$?
        want=$([ $bodies = 16 ] && echo 0 || echo 3)
        if [ "$rc" = "$want" ]; then
            echo "ok   EDMI_CONFIG_MATCHES(): caller with EDMI_MAX_BODIES=$bodies, library 16: exit $rc"
            pass=$((pass + 1))
        else
            echo "FAIL EDMI_CONFIG_MATCHES(): caller with EDMI_MAX_BODIES=$bodies: exit $rc, want $want"
            fail=$((fail + 1))
        fi
    else
        echo "FAIL the EDMI_CONFIG_MATCHES() program does not build"; fail=$((fail + 1))
    fi
done

# edmi.c turns floating-point contraction off for itself: built in GNU mode with FMA available
# and no -ffp-contract=off it holds exactly as many fused multiply-adds as the -ffp-contract=off
# build (the guard's intentional ones). Object code only, so it needs no FMA on this machine.
fmas() { objdump -d "$1" | grep -cE 'vfn?m(add|sub)'; }
for std in gnu99 c99; do
    if $cc -std=$std -O2 -mfma -fno-math-errno -c edmi.c -o "$tmp/fused.o" 2>/dev/null &&
            $cc -std=$std -O2 -mfma -fno-math-errno -ffp-contract=off -c edmi.c \
                -o "$tmp/plain.o" 2>/dev/null; then
        nf=$(fmas "$tmp/fused.o") np=$(fmas "$tmp/plain.o")
        if [ "$nf" = "$np" ]; then
            echo "ok   -std=$std -mfma without -ffp-contract=off: $nf FMAs, as with it"
            pass=$((pass + 1))
        else
            echo "FAIL -std=$std -mfma without -ffp-contract=off: $nf FMAs, $np with it"
            fail=$((fail + 1))
        fi
    else
        echo "FAIL -std=$std -mfma: edmi.c does not build"; fail=$((fail + 1))
    fi
done
# Capacities the library cannot work with stop the build with edmi.h's #error.
for cap in EDMI_MAX_BODIES=0 EDMI_MAX_LINKS=0 EDMI_MAX_DAMPERS=-1 EDMI_MAX_MATRIX=8 \
        EDMI_MAX_MATRIX=2305; do
    if out=$($cc -std=c99 -D$cap -c edmi.c -o "$tmp/x.o" 2>&1); then
        echo "FAIL -D$cap: edmi.c compiled"; fail=$((fail + 1))
    elif grep -q "#error \"edmi: ${cap%=*} must be" <<<"$out"; then
        echo "ok   -D$cap: refused with edmi.h's #error"; pass=$((pass + 1))
    else
        echo "FAIL -D$cap: failed, but not with edmi.h's #error: $(head -1 <<<"$out")"
        fail=$((fail + 1))
    fi
done
# EDMI_MAX_DAMPERS=0 compiles dampers out: the library has less code, refuses a damper (state
# unchanged) and steps a system without dampers bit for bit as the default build does.
cat > "$tmp/nodamp.c" <<'EOC'
#include <stdio.h>
#include <string.h>
#include "edmi.h"
static edmi_system sys, copy;
static edmi_workspace work;
int main(void)
{
    const edmi_real q[3] = {2, 1, 1}, p[3] = {-30, 15, 45}, o[3] = {0, 0, 0};
    edmi_potential spring = edmi_pot_neo_hooke(EDMI_R(1e3), EDMI_R(4.0));
    edmi_params prm = edmi_default_params();
    int n, i;
    edmi_status st;
    if (edmi_init(&sys, &prm) != EDMI_OK || edmi_add_body(&sys, 10, q, p, NULL) != EDMI_OK ||
        edmi_add_anchor(&sys, 0, o, &spring, NULL) != EDMI_OK)
        return 1;
    copy = sys;
    st = edmi_add_damper(&sys, 0, 1, NULL);
    printf("add_damper %s unchanged %d\n", edmi_status_name(st), !memcmp(&sys, &copy, sizeof sys));
    sys = copy; /* the default build took the damper: both step the same system */
    for (n = 0; n < 2000; n++)
        if (edmi_step(&sys, &work, EDMI_R(1e-3), NULL) != EDMI_OK)
            return 2;
    for (i = 0; i < 3; i++)
        printf("%a %a\n", (double)sys.body[0].q[i], (double)sys.body[0].p[i]);
    return 0;
}
EOC
for real in float double; do
    ok=1
    for d in 16 0; do
        $cc -std=c99 -O2 -ffp-contract=off -fno-math-errno -DEDMI_REAL=$real -DEDMI_MAX_DAMPERS=$d \
            -c edmi.c -o "$tmp/lib$d.o" &&
            $cc -std=c99 -I. -DEDMI_REAL=$real -DEDMI_MAX_DAMPERS=$d "$tmp/nodamp.c" \
                "$tmp/lib$d.o" -o "$tmp/nodamp$d" &&
            "$tmp/nodamp$d" > "$tmp/out$d" || ok=0
    done
    text16=$(size "$tmp/lib16.o" | awk 'NR == 2 { print $1 }')
    text0=$(size "$tmp/lib0.o" | awk 'NR == 2 { print $1 }')
    if [ $ok = 0 ]; then
        echo "FAIL EDMI_MAX_DAMPERS=0 ($real): a build or run failed"; fail=$((fail + 1))
    elif ! grep -q '^add_damper EDMI_OK unchanged 0$' "$tmp/out16" ||
            ! grep -q '^add_damper EDMI_ERR_CAPACITY unchanged 1$' "$tmp/out0"; then
        echo "FAIL EDMI_MAX_DAMPERS=0 ($real): edmi_add_damper: $(head -1 "$tmp/out0")"
        fail=$((fail + 1))
    elif ! diff <(tail -n +2 "$tmp/out16") <(tail -n +2 "$tmp/out0") > /dev/null; then
        echo "FAIL EDMI_MAX_DAMPERS=0 ($real): 2000 steps differ from the default build"
        fail=$((fail + 1))
    elif [ "$text0" -ge "$text16" ]; then
        echo "FAIL EDMI_MAX_DAMPERS=0 ($real): text $text0 B, not below the default's $text16 B"
        fail=$((fail + 1))
    else
        echo "ok   EDMI_MAX_DAMPERS=0 ($real): damper refused, state unchanged; 2000 steps" \
            "bit for bit as the default build; text $text0 B against $text16 B"
        pass=$((pass + 1))
    fi
done

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
