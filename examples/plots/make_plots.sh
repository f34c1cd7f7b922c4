#!/usr/bin/env bash
# CSV traces of the paper's examples and the PNG figures drawn from them (`make plots`).
#   usage: make_plots.sh EDMI_SIM DATA_DIR FIGURE_DIR [JOBS]     (from the repository root)
# With HAPTIC set to the examples/haptic.c binary (and HAPTIC_REAL to its EDMI_REAL), it also
# runs it (well under a second) and draws haptic_energy.png.
# A trace is recomputed only when it is missing or older than edmi-sim or its scene, so
# re-running after editing a .gp script only redraws. The figures need gnuplot (Debian:
# gnuplot-nox); without it the traces and the cable's table are made and the figures skipped.
set -u
sim=${1:?usage: make_plots.sh EDMI_SIM DATA_DIR FIGURE_DIR [JOBS]}
data=${2:?data dir}
fig=${3:?figure dir}
jobs=${4:-2}
P=examples/plots
S=examples/scenes
# Without gnuplot the traces and the tables are still made; the figures are skipped.
have_gnuplot=1
command -v gnuplot >/dev/null 2>&1 || have_gnuplot=0
mkdir -p "$data" "$fig"

# "ID SCENE OPTIONS...": the trace is DATA/ID.csv. Longest runs first.
runs=()
add() { runs+=("$*"); }
for s in mp lg ge pm pt; do
    add "solar_$s $S/solar_system.scene --scheme $s --every 10 --digits 9"
done
for s in mp lg ge pm pt; do
    add "spring_dt1e-2_$s $S/neo_hookean.scene --scheme $s --dt 1e-2"
    add "spring_dt1e-3_$s $S/neo_hookean.scene --scheme $s --dt 1e-3 --every 10"
    add "lj_$s $S/lj_two_body.scene --scheme $s"
done
if [ "${SIM_FULL:-0}" = 1 ]; then # the ten-body tol_Q study: 9 more long runs
    for q in 4 6 8; do for a in janz ge pm; do
        add "solar_q${q}_$a $S/solar_system.scene --scheme lg --lg-switch $a --tol-q 1e-$q --every 100 --digits 6"
    done; done
fi
add "chain_pm $S/hanging_chain.scene --scheme pm --energy-balance --every 5"
add "cable_consistent $S/cable_consistent.scene --every 5"
add "cable_lumped $S/cable_lumped.scene --every 5"
for q in 4 6 8; do for a in janz ge pm; do
    add "lj_q${q}_$a $S/lj_two_body.scene --scheme lg --lg-switch $a --tol-q 1e-$q"
done; done

todo=()
for r in "${runs[@]}"; do
    # shellcheck disable=SC2086 # split the run line into its words
    set -- $r
    csv="$data/$1.csv"
    if [ ! -s "$csv" ] || [ "$csv" -ot "$sim" ] || [ "$csv" -ot "$2" ]; then todo+=("$r"); fi
done
echo "make plots: ${#todo[@]} of ${#runs[@]} traces to compute, $jobs at a time, into $data"
export sim data
# shellcheck disable=SC2016 # the script is expanded by the inner bash
printf '%s\n' "${todo[@]}" | grep . | xargs -r -P "$jobs" -L 1 bash -c '
    id=$1; shift
    if ! "$sim" "$@" --quiet --csv "$data/$id.csv.tmp" >"$data/$id.txt" 2>"$data/$id.err"; then
        echo "edmi-sim $* failed:" >&2; cat "$data/$id.err" >&2; exit 255
    fi
    mv "$data/$id.csv.tmp" "$data/$id.csv"' run || exit 1

if [ -n "${HAPTIC:-}" ]; then
    if ! "$HAPTIC" --csv "$data/haptic.csv" >"$data/haptic.txt" 2>&1; then
        cat "$data/haptic.txt" >&2
        echo "make plots: $HAPTIC failed" >&2
        exit 1
    fi
fi

# The hanging cable, consistent against lumped masses: the two traces side by side (same
# rows), and the highest axial mode's frequency run by PM at steps dt against the exact FE
# value and the mid-point's (2/dt) atan(omega dt/2) (examples/plots/cable_mode.awk; 4000
# steps each; the tip is body 8: x in column 20 + 6 * 7).
paste -d, "$data/cable_consistent.csv" "$data/cable_lumped.csv" >"$data/cable_tips.csv" || exit 1
modes=$data/cable_modes.dat
echo "# dt omega_FE omega_midpoint omega_run (consistent) then the same (lumped); rad/s" >"$modes"
echo "make plots: the cable's highest axial mode, PM, relative error of the run against (2/dt) atan(omega_FE dt/2):"
for dt in 1e-4 2e-4 5e-4 1e-3 2e-3 5e-3 1e-2 2e-2 3e-2; do
    row=$dt
    for c in 1 0; do
        scene=$data/cable_mode_$c.scene
        awk -v consistent=$c -v dt=$dt -v steps=4000 -f $P/cable_mode.awk >"$scene" || exit 1
        if ! "$sim" "$scene" --quiet --csv "$data/cable_mode_$c.csv" >"$data/cable_mode_$c.txt" 2>&1; then
            cat "$data/cable_mode_$c.txt" >&2
            exit 1
        fi
        fe=$(sed -n 's/.*FE omega //p' "$scene")
        run=$(awk -v col=62 -v x0=0.8 -f $P/crossings.awk "$data/cable_mode_$c.csv")
        row="$row $(awk -v fe="$fe" -v dt=$dt -v run="$run" \
            'BEGIN { printf "%.12g %.12g %.12g", fe, 2 / dt * atan2(fe * dt / 2, 1), run }')"
    done
    echo "$row" >>"$modes"
    echo "$row" | awk '{ printf "  dt %-6s consistent %.3e, lumped %.3e\n", $1, ($4 - $3) / $3, ($7 - $6) / $6 }'
done

draw() { # SCRIPT OUTPUT.png [gnuplot assignments]
    local script=$1 png=$2
    shift 2
    if ! gnuplot -e "data='$data'; out='$fig/$png'; $*" "$P/$script" 2>"$data/$png.log"; then
        cat "$data/$png.log" >&2
        echo "make plots: $script failed for $png" >&2
        exit 1
    fi
    echo "  $fig/$png"
}
if [ $have_gnuplot = 0 ]; then
    echo "make plots: gnuplot not found: the traces are in $data, the figures in $fig were not"
    echo "  drawn (install it with: apt-get install -y --no-install-recommends gnuplot-nox)"
    exit 0
fi
echo "make plots: figures"
draw spring_orbits.gp spring_orbits.png
draw energy_panels.gp spring_energy.png "prefix='spring_dt1e-3_'; tscale=1; tunit='s'; xt=2;" \
    "name='Stiff neo-Hookean spring, dt = 1e-3: energy error per scheme, and |J - J_0|'"
draw energy_panels.gp lj_energy.png "prefix='lj_'; tscale=1; tunit='s'; xt=0.5;" \
    "name='Two Lennard-Jones bodies, dt = 1e-3: energy error per scheme (LG: quotient, Janz, tol_Q = 1e-8), and |J - J_0|'"
draw momenta.gp lj_momenta.png "prefix='lj_'; tscale=1; tunit='s'; xt=0.5;" \
    "name='Two Lennard-Jones bodies, dt = 1e-3: momentum and centre-of-mass errors (absolute, model units)'"
draw tolq.gp lj_tolq.png "prefix='lj_'; tscale=1; tunit='s'; xt=0.5;" \
    "name='Two Lennard-Jones bodies, dt = 1e-3: LG quotient form with its alternates'"
draw energy_panels.gp solar_energy.png "prefix='solar_'; tscale=365.25; tunit='years'; xt=1000;" \
    "name='Sun and nine planets, dt = 5 days: energy error per scheme (LG: closed form), and |J - J_0|'"
draw momenta.gp solar_momenta.png "prefix='solar_'; tscale=365.25; tunit='years'; xt=1000;" \
    "name='Sun and nine planets, dt = 5 days: momentum and centre-of-mass errors (absolute; M_{sun}, AU, day)'"
draw orbits.gp solar_inner.png "bodies='1 2 3 4'; names='Mercury Venus Earth Mars'; range=1.7;" \
    "name='Inner planets, 5000 years sampled every 50 days'"
draw orbits.gp solar_outer.png "bodies='5 6 7 8 9'; names='Jupiter Saturn Uranus Neptune Pluto'; range=50;" \
    "name='Outer planets, 5000 years sampled every 50 days'"
draw chain.gp chain.png
draw cable.gp cable.png
if [ -n "${HAPTIC:-}" ]; then
    draw haptic.gp haptic_energy.png "prec='${HAPTIC_REAL:-double}';"
fi
if [ "${SIM_FULL:-0}" = 1 ]; then
    draw tolq.gp solar_tolq.png "prefix='solar_'; tscale=365.25; tunit='years'; xt=1000;" \
        "name='Sun and nine planets, dt = 5 days: LG quotient form with its alternates'"
fi
du -ch "$fig"/*.png | tail -n 1 | sed 's/^/make plots: PNG total /'
