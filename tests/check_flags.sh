#!/usr/bin/env bash
# edmi.c refuses the compiler modes that drop the IEEE semantics it relies on (its NaN/Inf
# validation, the guard's double-word arithmetic): each must stop the build with edmi.c's
# #error, in both precisions; the strict flags must build.   usage: check_flags.sh CC
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
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
