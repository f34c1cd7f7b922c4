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
# refused LABEL WANT FLAGS...: edmi.c must fail to compile with FLAGS, with an #error whose
# text contains WANT.
refused() {
    local label=$1 want=$2 out
    shift 2
    if out=$($cc -std=c99 "$@" -c edmi.c -o "$tmp/x.o" 2>&1); then
        echo "FAIL $label: edmi.c compiled"; fail=$((fail + 1))
    elif grep -q -- "$want" <<<"$out"; then
        echo "ok   $label: refused with the #error"; pass=$((pass + 1))
    else
        echo "FAIL $label: failed, but not with the #error: $(head -1 <<<"$out")"
        fail=$((fail + 1))
    fi
}
for real in float double; do
    for mode in -ffast-math -Ofast -ffinite-math-only; do
        refused "$mode ($real)" 'edmi.c needs IEEE semantics' $mode -DEDMI_REAL=$real
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
if $cc -std=c99 -Wall -Wextra -Werror -DEDMI_USER_CONFIG='"edmi_config_template.h"' \
        -c edmi.c -o "$tmp/lib.o" 2>/dev/null; then
    echo "ok   edmi_config_template.h builds as EDMI_USER_CONFIG"; pass=$((pass + 1))
else
    echo "FAIL edmi_config_template.h does not build"; fail=$((fail + 1))
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
    refused "-D$cap" "#error \"edmi: ${cap%=*} must be" -D$cap
done
# Feature options the library cannot work with stop the build with edmi.h's #error: no scheme,
# no potential, the quotient form without LG, GE/PM/PT without the guard.
for opts in "-DEDMI_WITH_MP=0 -DEDMI_WITH_LG=0 -DEDMI_WITH_GE=0 -DEDMI_WITH_PM=0 -DEDMI_WITH_PT=0|at least one scheme" \
        "-DEDMI_WITH_HARMONIC=0 -DEDMI_WITH_QUARTIC=0 -DEDMI_WITH_NEO_HOOKE=0 -DEDMI_WITH_LJ=0 -DEDMI_WITH_INVERSE=0 -DEDMI_WITH_USER=0 -DEDMI_WITH_CONTACT=0|at least one potential" \
        "-DEDMI_WITH_LG=0 -DEDMI_WITH_LG_QUOTIENT=1|EDMI_WITH_LG_QUOTIENT needs" \
        "-DEDMI_WITH_GUARD=0|GE, PM and PT carry the guard"; do
    defs=${opts%|*} want=${opts#*|}
    # shellcheck disable=SC2086
    refused "$defs" "#error \"edmi: $want" $defs
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
            ! grep -q '^add_damper EDMI_ERR_DISABLED unchanged 1$' "$tmp/out0"; then
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

# A build with features compiled out steps what it carries bit for bit as the default build:
# a body on two harmonic anchor links (rest lengths 0 and 0.5), one anchor moving as a hand
# would move it, 2000 steps; the coupling build with PM, the decaying one with GE, the
# conservative one (no guard) with LG. Positions, momenta, tank and link forces compared.
cat > "$tmp/feat.c" <<'EOC'
#include <stdio.h>
#include "edmi.h"
static edmi_system sys;
static edmi_workspace work;
int main(void)
{
    const edmi_real q[3] = {1, 0.5, 0}, p[3] = {0.3, -0.2, 0.1}, o[3] = {0, 0, 0};
    edmi_real x[3] = {2, 0, 0};
    edmi_potential a = edmi_pot_harmonic(400, 0), b = edmi_pot_harmonic(150, EDMI_R(0.5));
    edmi_params prm = edmi_default_params();
    int n, i;
    prm.scheme = SCHEME;
    prm.fallback = 1;
    if (edmi_init(&sys, &prm) != EDMI_OK || edmi_add_body(&sys, 1, q, p, NULL) != EDMI_OK ||
        edmi_add_anchor(&sys, 0, o, &a, NULL) != EDMI_OK ||
        edmi_add_anchor(&sys, 0, x, &b, NULL) != EDMI_OK)
        return 1;
    for (n = 0; n < 2000; n++) {
        x[1] = EDMI_R(0.3) * (edmi_real)(n % 200) / EDMI_R(200.0);
        if (edmi_move_anchor(&sys, 1, x) != EDMI_OK ||
            edmi_step(&sys, &work, EDMI_R(1e-3), NULL) != EDMI_OK)
            return 2;
    }
    for (i = 0; i < 3; i++)
        printf("%a %a %a %a\n", (double)sys.body[0].q[i], (double)sys.body[0].p[i],
               (double)sys.link_force[0][i], (double)sys.link_force[1][i]);
    printf("%a\n", (double)sys.tank);
    return 0;
}
EOC
feat_coupling="-DEDMI_WITH_MP=0 -DEDMI_WITH_LG=0 -DEDMI_WITH_GE=0 -DEDMI_WITH_PT=0
    -DEDMI_WITH_QUARTIC=0 -DEDMI_WITH_NEO_HOOKE=0 -DEDMI_WITH_LJ=0 -DEDMI_WITH_INVERSE=0
    -DEDMI_WITH_USER=0 -DEDMI_WITH_CONTACT=0 -DEDMI_WITH_FIELD=0 -DEDMI_WITH_PORTS=0
    -DEDMI_WITH_SCENE=0 -DEDMI_MAX_DAMPERS=0"
for real in float double; do
    for cfg in "coupling|EDMI_SCHEME_PM|$feat_coupling" "decaying|EDMI_SCHEME_GE|-DEDMI_WITH_MP=0 -DEDMI_WITH_LG=0" \
            "conservative|EDMI_SCHEME_LG|-DEDMI_WITH_GE=0 -DEDMI_WITH_PM=0 -DEDMI_WITH_PT=0 -DEDMI_WITH_GUARD=0"; do
        name=${cfg%%|*} rest=${cfg#*|}
        scheme=${rest%%|*} defs=${rest#*|}
        ok=1
        for v in def feat; do
            d=; [ $v = feat ] && d=$defs
            # shellcheck disable=SC2086
            $cc -std=c99 -O2 -ffp-contract=off -fno-math-errno -DEDMI_REAL=$real $d \
                -c edmi.c -o "$tmp/f$v.o" &&
                $cc -std=c99 -I. -DEDMI_REAL=$real $d -DSCHEME=$scheme "$tmp/feat.c" "$tmp/f$v.o" \
                    -o "$tmp/feat$v" && "$tmp/feat$v" > "$tmp/fout$v" || ok=0
        done
        if [ $ok = 0 ]; then
            echo "FAIL $name build ($real): a build or run failed"; fail=$((fail + 1))
        elif ! cmp -s "$tmp/foutdef" "$tmp/foutfeat"; then
            echo "FAIL $name build ($real): 2000 steps differ from the default build"
            fail=$((fail + 1))
        else
            echo "ok   $name build ($real): 2000 $scheme steps bit for bit as the default build"
            pass=$((pass + 1))
        fi
    done
done

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
