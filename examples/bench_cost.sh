#!/bin/sh
# The host cost table of `make bench`: instructions per step under callgrind (deterministic,
# unlike wall time), per Newton correction and per link, with a velocity-Verlet step of the
# same system counted in the same run. Usage: bench_cost.sh BUILD_DIR (holding bench_cost-float
# and bench_cost-double, built by examples/sim.mk). Each case is one run of
# examples/bench_cost.c under valgrind --tool=callgrind --toggle-collect=bc_run.
set -e
dir=$1
out=$dir/cg
mkdir -p "$out"
count() { # precision scene method n steps -> "instructions corrections links"
    f=$out/$1-$2-$3-$4.out
    r=$(valgrind --tool=callgrind --toggle-collect=bc_run --callgrind-out-file="$f" \
        "$dir/bench_cost-$1" "$2" "$3" "$4" "$5" 2>/dev/null) || { echo "FAIL $*" >&2; exit 1; }
    ir=$(awk '/^summary:/ {print $2}' "$f")
    echo "$ir $(echo "$r" | awk '{print $2, $4}')"
}
fmt() { awk -v a="$1" -v b="$2" -v d="$3" 'BEGIN { if (b == 0) print "-"; else printf "%.*f\n", d, a / b }'; }
for prec in float double; do
    echo "edmi host cost, EDMI_REAL=$prec, callgrind instructions (-O2), edmi_default_params()"
    echo
    echo "| scene | N | links | method | instructions/step | corrections/step | instructions/correction | instructions/link-step | x Verlet |"
    echo "|---|---:|---:|---|---:|---:|---:|---:|---:|"
    for case in "spring 1 200" "lj2 2 200" "solar 10 50" "pairs 4 100" "pairs 8 50" "pairs 16 20" \
                "pairs 32 10" "pairs 64 4"; do
        set -- $case
        scene=$1; n=$2; steps=$3
        set -- $(count $prec $scene verlet $n $steps)
        vv=$(fmt "$1" "$steps" 1)
        case $scene in pairs) methods="pm verlet" ;; *) methods="mp lg ge pm pt verlet" ;; esac
        for m in $methods; do
            set -- $(count $prec $scene $m $n $steps)
            per=$(fmt "$1" "$steps" 0)
            name=$m; [ "$m" = verlet ] && name=Verlet || name=$(echo "$m" | tr a-z A-Z)
            echo "| $scene | $n | $3 | $name | $per | $(fmt "$2" "$steps" 2) | $(fmt "$1" "$2" 0) |" \
                 "$(fmt "$1" $((steps * $3)) 0) | $(fmt "$(fmt "$1" "$steps" 3)" "$vv" 1) |"
        done
    done
    echo
done
