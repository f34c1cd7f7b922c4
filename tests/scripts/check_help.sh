#!/usr/bin/env bash
# `make help` lists every target: each name on a .PHONY line of Makefile, examples/sim.mk,
# tests/bench/bench.mk and port/target.mk (tgt-cross is make cross's internal half; `all` is
# plain `make`) must start a line of its output, with a time. `make test` runs it.
# Last line: "N passed, N failed".
set -u
pass=0 fail=0
out=$(make --no-print-directory help 2>&1) || { echo "FAIL make help: $out"; echo "0 passed, 1 failed"; exit 1; }
targets=$(awk '/^\.PHONY:/ { p = 1; sub(/^\.PHONY:/, "") } p { c = /\\$/; sub(/\\$/, ""); print; p = c }' \
    Makefile examples/sim.mk tests/bench/bench.mk port/target.mk | tr ' ' '\n' | grep . | sort -u)
for t in $targets; do
    case $t in tgt-cross) continue ;; all) re='^make  +[0-9.]+ (s|min)' ;; *) re="^make $t +[0-9.]+ (s|min)" ;; esac
    if grep -Eq "$re" <<<"$out"; then
        pass=$((pass + 1))
    else
        echo "FAIL make help does not list '$t' with a time"
        fail=$((fail + 1))
    fi
done
echo "ok   make help lists $pass targets with their times"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
