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

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
