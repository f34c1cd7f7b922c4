#!/bin/sh
# Where a step's instructions go (`make bench-profile`): tests/bench/bench_cost.c under
# valgrind --tool=callgrind (only the stepping loop counted), per step, for the paper's spring
# (PM, 2,000 steps) and 10 bodies with all 45 pairs (PM, 2,000 steps), both precisions.
# First the step's phases (inclusive counts: everything a phase calls), then the functions
# with the largest own counts. Usage: bench_profile.sh BUILD_DIR (holding bench_cost-float
# and bench_cost-double, built by tests/bench/bench.mk).
set -e
dir=$1
out=$dir/profile
mkdir -p "$out"
phases="edmi__validate_system:validation_(the_system) edmi__prepare_links:link_set-up edmi__residual:residual_evaluations_(all) edmi__predictor:of_which_the_predictor's edmi__newton_update:linear_solves_(assembly,_factors,_solves) edmi__solved:solved_test edmi__finish:energy_balance_and_guard"
for prec in float double; do
    for case in "spring 1" "pairs 10"; do
        set -- $case
        f=$out/$prec-$1.out
        valgrind --tool=callgrind --toggle-collect=bc_run --callgrind-out-file="$f" \
            "$dir/bench_cost-$prec" "$1" pm "$2" 2000 >/dev/null 2>&1 ||
            { echo "FAIL $prec $1" >&2; exit 1; }
        total=$(awk '/^summary:/ {print $2}' "$f")
        echo "$prec, $1 (N = $2), PM: $(awk -v t="$total" 'BEGIN { printf "%.0f", t / 2000 }') instructions per step"
        echo
        echo "| phase (inclusive) | instructions/step | share |"
        echo "|---|---:|---:|"
        callgrind_annotate --inclusive=yes "$f" 2>/dev/null > "$f.incl"
        for ph in $phases; do
            fn=${ph%%:*}; name=$(echo "${ph#*:}" | tr _ ' ')
            awk -v fn="$fn" -v name="$name" -v t="$total" '
                $0 ~ (":" fn " ") { gsub(",", "", $1); printf "| %s | %.0f | %.1f %% |\n", name, $1 / 2000, 100 * $1 / t; found = 1; exit }
                END { if (!found) printf "| %s | 0 | 0.0 %% |\n", name }' "$f.incl"
        done
        echo
        echo "| function (own instructions) | instructions/step | share |"
        echo "|---|---:|---:|"
        callgrind_annotate "$f" 2>/dev/null | awk -v t="$total" '
            /edmi\.c:edmi/ && n < 10 { c = $1; gsub(",", "", c); match($0, /edmi\.c:[A-Za-z_0-9.]+/);
                fn = substr($0, RSTART + 7, RLENGTH - 7); sub(/\.(isra|part|constprop)\..*/, "", fn);
                printf "| %s | %.0f | %.1f %% |\n", fn, c / 2000, 100 * c / t; n++ }'
        echo
    done
done
