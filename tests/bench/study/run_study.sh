#!/usr/bin/env bash
# The work-precision study (`make study`; STUDY_QUICK=1 for the CI subset).
#   usage: run_study.sh STUDY_DOUBLE STUDY_FLOAT OUT_DIR FIGURE_DIR [JOBS]   (from the repo root)
# 1. A converged reference per scene (study ref: rk8pd, checked two ways).
# 2. Every (scene, method, dt) and PM's tol_R sweep: errors and median wall time per step from
#    a native run, instructions per step from a second run under callgrind that counts only
#    inside study_step_one() (one step of any method).
# 3. The tables (OUT_DIR/tables.md; without STUDY_QUICK also tests/bench/study/RESULTS.md) and
#    the plot data, then the long-time energy runs on the spring, then the figures (gnuplot)
#    into FIGURE_DIR, then the checks (study check: "N passed, N failed").
# The Cortex-M4F column comes from `make study-target` (tests/bench/study_target.c under QEMU).
set -eu -o pipefail
dbl=${1:?usage: run_study.sh STUDY_DOUBLE STUDY_FLOAT OUT_DIR FIGURE_DIR [JOBS]}
flt=${2:?float binary}
out=${3:?output dir}
fig=${4:?figure dir}
jobs=${5:-2}
quick=${STUDY_QUICK:-0}
S=examples/scenes
mkdir -p "$out/cg" "$out/dat" "$fig"
command -v valgrind >/dev/null || { echo "study: valgrind not found (it counts the instructions; make help lists the packages)" >&2; exit 1; }
have_gnuplot=1
command -v gnuplot >/dev/null || have_gnuplot=0
start=$(date +%s)

# per scene: T, checkpoints and the rk4imp step of the reference's second check; the dt sweep;
# the middle dt (PM's tol_R sweep)
scene_args() {
    case $1 in
    neo_hookean)   echo "10 50 1e-4"    ;;
    lj_two_body)   echo "2 25 2e-5"     ;;
    lj_cluster8)   echo "5 50 1e-4"     ;;
    solar_system)  echo "365 50 0.1140625" ;;
    hanging_chain) echo "5 50 1e-4"     ;;
    esac
}
scene_dts() {
    case $1 in
    neo_hookean)   [ "$quick" = 1 ] && echo "2e-3 1e-3 5e-4" || echo "4e-3 2e-3 1e-3 5e-4 2.5e-4" ;;
    lj_two_body)   [ "$quick" = 1 ] && echo "2e-3 1e-3 5e-4" || echo "4e-3 2e-3 1e-3 5e-4 2.5e-4" ;;
    lj_cluster8)   echo "1e-2 5e-3 2.5e-3 1.25e-3 6.25e-4" ;;
    solar_system)  echo "3.65 1.825 0.9125 0.45625" ;;
    hanging_chain) echo "4e-3 2e-3 1e-3 5e-4 2.5e-4" ;;
    esac
}
# larger dt's for the fourth-order methods, so that their curves meet the others' errors
scene_big() {
    case $1 in
    neo_hookean)   echo "2e-2 1e-2 8e-3" ;;
    lj_two_body)   echo "1.6e-2 8e-3" ;;
    lj_cluster8)   echo "5e-2 2e-2" ;;
    solar_system)  echo "7.3" ;;
    hanging_chain) echo "2e-2 1e-2 5e-3" ;;
    esac
}
scene_mid() {
    case $1 in
    neo_hookean | lj_two_body | hanging_chain) echo 1e-3 ;;
    lj_cluster8) echo 2.5e-3 ;;
    solar_system) echo 0.9125 ;;
    esac
}
if [ "$quick" = 1 ]; then
    scenes="neo_hookean lj_two_body"
    methods="mp lg pm verlet gsl-rk2imp gsl-rk4imp gsl-rk4"
    tols="1e-4 1e-8"
    long_n=100000
else
    scenes="neo_hookean lj_two_body lj_cluster8 solar_system hanging_chain"
    methods="mp lg lgq ge pm pt verlet euler gsl-rk2imp gsl-rk4imp gsl-rk4"
    tols="1e-2 1e-4 1e-6 1e-8"
    long_n=1000000
fi

echo "study: references ($scenes)"
for s in $scenes; do
    set -- $(scene_args $s)
    echo "$dbl ref $S/$s.scene $1 $2 $3 $out/$s.ref > $out/$s.ref.log"
done | xargs -P "$jobs" -I{} sh -c '{}'
for s in $scenes; do cat "$out/$s.ref.log"; done

# jobs: "BINARY SCENE METHOD DT T [TOL]"
joblist=$out/jobs.txt
: > "$joblist"
for s in $scenes; do
    set -- $(scene_args $s)
    t=$1
    for dt in $(scene_big $s); do
        for m in $methods; do
            case $m in gsl-rk4imp | gsl-rk4) echo "$dbl $s $m $dt $t" >> "$joblist" ;; esac
        done
    done
    for dt in $(scene_dts $s); do
        for m in $methods; do echo "$dbl $s $m $dt $t" >> "$joblist"; done
        echo "$flt $s pm $dt $t" >> "$joblist"
    done
    for tol in $tols; do echo "$dbl $s pm $(scene_mid $s) $t $tol" >> "$joblist"; done
done
echo "study: $(wc -l < "$joblist") runs, $jobs at a time (native, then callgrind)"

one() { # INDEX BINARY SCENE METHOD DT T [TOL] -> res/INDEX.csv: CSV row, instructions/step
    local idx=$1 bin=$2 s=$3 m=$4 dt=$5 t=$6 tol=${7:-}
    local cg=$out/cg/$idx.out row ir steps
    row=$("$bin" run "$S/$s.scene" "$m" "$dt" "$t" "$out/$s.ref" $tol)
    STUDY_NO_TIMING=1 valgrind --tool=callgrind --callgrind-out-file="$cg" \
        --toggle-collect=study_step_one "$bin" run "$S/$s.scene" "$m" "$dt" "$t" \
        "$out/$s.ref" $tol > /dev/null 2> "$cg.log"
    ir=$(sed -n 's/^totals: \([0-9]*\).*/\1/p' "$cg")
    steps=$(echo "$row" | cut -d, -f6)
    echo "$row,$(awk -v i="$ir" -v n="$steps" 'BEGIN { printf "%.1f", i / n }')" > "$out/res/$idx.csv"
}
export -f one
export out S
rm -rf "$out/res" && mkdir -p "$out/res"
awk '{ printf "%05d %s\n", NR, $0 }' "$joblist" | xargs -P "$jobs" -L 1 bash -c 'one "$@"' _
cat "$out"/res/*.csv > "$out/results.csv"
if [ "$(wc -l < "$out/results.csv")" -ne "$(wc -l < "$joblist")" ]; then
    echo "study: $(wc -l < "$out/results.csv") results for $(wc -l < "$joblist") runs" >&2
    exit 1
fi
"$dbl" table "$out" > "$out/tables.md"
# the Cortex-M4F column: `make study-target`'s lines (make study runs it into OUT/m4f.log)
if [ -s "$out/m4f.log" ]; then
    {
        printf '\nCortex-M4F (QEMU mps2-an386, -icount shift=0), float, edmi.c at -Os: instructions per step, mean over the first steps (tests/bench/study_target.c):\n\n'
        printf '| scene | method | dt | steps | M4F instructions/step | corrections/step |\n|---|---|---:|---:|---:|---:|\n'
        awk -F, '/^m4f,/ { if (NF == 5) printf "| %s | %s | %s | %s | | |\n", $2, $3, $4, $5;
                          else printf "| %s | %s | %s | %s | %s | %s |\n", $2, $3, $4, $5, $6, $7 }' "$out/m4f.log"
    } >> "$out/tables.md"
fi

echo "study: long-time energy on the spring, $long_n steps of 1e-3"
for m in verlet rk4 gsl-rk2imp mp lg pm; do
    echo "$dbl long $S/neo_hookean.scene $m 1e-3 $long_n 1000 > $out/long_${m}_double.dat"
done > "$out/long_jobs.txt"
for m in verlet rk4 mp lg pm; do
    echo "$flt long $S/neo_hookean.scene $m 1e-3 $long_n 1000 > $out/long_${m}_float.dat"
done >> "$out/long_jobs.txt"
xargs -P "$jobs" -I{} sh -c '{}' < "$out/long_jobs.txt"
for f in "$out"/long_*.dat; do
    printf '%s: max |H - H0|/|H0| over the run %s, final (H - H0)/|H0| %s;%s\n' "$(basename "$f" .dat)" \
        "$(awk '!/^#/ { if ($2 > m) m = $2 } END { printf "%.2e", m }' "$f")" \
        "$(awk '!/^#/ { e = $3 } END { printf "%+.2e", e }' "$f")" \
        "$(sed -n 's/^# steps H + T rose/ steps H + T rose/p' "$f")"
done | tee "$out/long_summary.txt"

if [ "$quick" != 1 ]; then
    # the full tables, committed next to the study (docs/study.md quotes their summary)
    {
        echo "# Work-precision study: the full tables"
        echo
        echo "Written by \`make study\` ($(date -u +%Y-%m-%d), $(uname -m), $(gcc --version | sed -n 1p));"
        echo "see docs/study.md for what each column means and how it is measured."
        echo
        cat "$out/tables.md"
        echo
        echo "Long-time energy on the paper's spring, $long_n steps of dt = 1e-3 (\`study long\`):"
        echo
        sed 's/^/    /' "$out/long_summary.txt"
    } > tests/bench/study/RESULTS.md
fi
if [ $have_gnuplot = 1 ]; then
    echo "study: figures into $fig"
    for g in cost energy long; do
        gnuplot -e "data='$out'; out='$fig/study_$g.png'; quick=$quick" tests/bench/study/study_$g.gp
    done
else
    echo "study: gnuplot not found: skipped the figures study_cost, study_energy and study_long"
    echo "  (the tables and checks below are complete; install gnuplot-nox to draw them)"
fi
cat "$out/tables.md"
echo "study: checks (study check)"
rc=0
"$dbl" check "$out" | tee "$out/checks.txt" || rc=1
if [ "$quick" != 1 ]; then
    { echo; echo "Checks (\`study check\`):"; echo; sed 's/^/    /' "$out/checks.txt"; } \
        >> tests/bench/study/RESULTS.md
fi
echo "study: done in $(( $(date +%s) - start )) s; tables in $out/tables.md"
exit $rc
