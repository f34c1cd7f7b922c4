#!/bin/sh
# The host cost table of `make bench`: instructions per step under callgrind (deterministic,
# unlike wall time), per Newton correction and per link, with a velocity-Verlet step of the
# same system counted in the same run. Usage: bench_cost.sh BUILD_DIR (holding bench_cost-float
# and bench_cost-double, built by tests/bench/bench.mk). Each case is one run of
# tests/bench/bench_cost.c under valgrind --tool=callgrind --toggle-collect=bc_run.
set -e
if [ "$1" = --one ]; then # one run: --one DIR precision scene method n steps
    dir=$2; out=$dir/cg; shift 2
    f=$out/$1-$2-$3-$4.out
    r=$(valgrind --tool=callgrind --toggle-collect=bc_run --callgrind-out-file="$f" \
        "$dir/bench_cost-$1" "$2" "$3" "$4" "$5" 2>/dev/null) || { echo "FAIL $*" >&2; exit 1; }
    ir=$(awk '/^summary:/ {print $2}' "$f")
    # "instructions corrections links"
    echo "$ir $(echo "$r" | awk '{print $2, $4}')" > "$out/$1-$2-$3-$4.res"
    exit 0
fi
dir=$1
out=$dir/cg
mkdir -p "$out"
rm -f "$out"/*.res
fmt() { awk -v a="$1" -v b="$2" -v d="$3" 'BEGIN { if (b == 0) print "-"; else printf "%.*f\n", d, a / b }'; }
# "scene N steps": the scenes 2,000 steps each (costs change as a run goes on: the first 200
# steps of the spring understated the guard's cost by 18-23 %); the all-pairs scaling rows
# above 16 bodies fewer (their steps cost alike: no guard action, 2 corrections each).
cases="spring:1:2000 lj2:2:2000 solar:10:2000 pairs:4:2000 pairs:8:2000 pairs:10:2000
pairs:16:2000 pairs:32:200 pairs:64:20"
methods_of() { case $1 in pairs) echo "pm verlet" ;; *) echo "mp lg ge pm pt verlet" ;; esac; }
# every run, JOBS (default 2) at a time, each into its own file
jobs=${JOBS:-2}
for prec in float double; do
    for c in $cases; do
        set -- $(echo "$c" | tr : ' ')
        for m in $(methods_of "$1"); do echo "$prec $1 $m $2 $3"; done
    done
done | xargs -P "$jobs" -L 1 sh "$0" --one "$dir"
for prec in float double; do
    echo "edmi host cost, EDMI_REAL=$prec, callgrind instructions (-O2), edmi_default_params()"
    echo
    echo "| scene | N | links | steps | method | instructions/step | corrections/step | instructions/correction | instructions/link-step | x Verlet |"
    echo "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|"
    for c in $cases; do
        set -- $(echo "$c" | tr : ' ')
        scene=$1; n=$2; steps=$3
        set -- $(cat "$out/$prec-$scene-verlet-$n.res" 2>/dev/null) 0
        vv=$(fmt "$1" "$steps" 1)
        for m in $(methods_of "$scene"); do
            set -- $(cat "$out/$prec-$scene-$m-$n.res" 2>/dev/null)
            [ -n "${3:-}" ] || { echo "FAIL $prec $scene $m $n" >&2; exit 1; }
            per=$(fmt "$1" "$steps" 0)
            name=$m; [ "$m" = verlet ] && name=Verlet || name=$(echo "$m" | tr a-z A-Z)
            echo "| $scene | $n | $3 | $steps | $name | $per | $(fmt "$2" "$steps" 2) | $(fmt "$1" "$2" 0) |" \
                 "$(fmt "$1" $((steps * $3)) 0) | $(fmt "$(fmt "$1" "$steps" 3)" "$vv" 1) |"
        done
    done
    echo
done
