#!/usr/bin/env bash
# `make help` lists every target: each name on a .PHONY line of Makefile, examples/sim.mk,
# tests/bench/bench.mk and port/target.mk (tgt-cross is make cross's internal half; `all` is
# plain `make`) must start a line of its output, with a time quoted as a bound on the scale
# (tests/scripts/help_time.sh reads the quotes: "≤ N s" or "≤ N min"). README's two times,
# `make run` and `make test`, must be make help's. `make test` runs it.
# Last line: "N passed, N failed".
set -u
pass=0 fail=0
here=$(dirname "$0")
quotes=$(bash "$here/help_time.sh" quotes) || { echo "FAIL make help failed"; echo "0 passed, 1 failed"; exit 1; }
scale=$(bash "$here/help_time.sh" scale | cut -d' ' -f2-)
targets=$(awk '/^\.PHONY:/ { p = 1; sub(/^\.PHONY:/, "") } p { c = /\\$/; sub(/\\$/, ""); print; p = c }' \
    Makefile examples/sim.mk tests/bench/bench.mk port/target.mk | tr ' ' '\n' | grep . | sort -u)
for t in $targets; do
    case $t in tgt-cross) continue ;; all) cmd= ;; *) cmd=$t ;; esac
    q=$(awk -F'\t' -v c="$cmd" '$1 == c { print $3; exit }' <<<"$quotes")
    if [ -z "$q" ]; then
        echo "FAIL make help does not list '$t' with a time '≤ N s' or '≤ N min'"
        fail=$((fail + 1))
    elif ! grep -qx -- "$q" <<<"$scale"; then
        echo "FAIL make help quotes ≤ $q for '$t', not a value of the scale: $(tr '\n' ',' <<<"$scale")"
        fail=$((fail + 1))
    else
        pass=$((pass + 1))
    fi
done
echo "ok   make help lists $pass targets with their times"

# README's times are make help's.
for t in run test; do
    readme=$(grep -oE "\`make $t\`[^≤\`]*≤ [0-9]+ (s|min)" README.md | head -n 1 | sed 's/.*≤ //')
    help=$(awk -F'\t' -v c="$t" '$1 == c { print $3; exit }' <<<"$quotes")
    if [ -n "$readme" ] && [ "$readme" = "$help" ]; then
        echo "ok   README quotes make $t as make help does: ≤ $help"
        pass=$((pass + 1))
    else
        echo "FAIL README quotes make $t as '≤ ${readme:-nothing}', make help as '≤ ${help:-nothing}'"
        fail=$((fail + 1))
    fi
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
