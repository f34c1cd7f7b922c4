#!/usr/bin/env bash
# The paper's three examples with every scheme, as one Markdown table (`make run-examples`).
#   usage: run_examples.sh EDMI_SIM [JOBS]      (from the repository root)
# Runs edmi-sim on examples/scenes/{neo_hookean,lj_two_body,solar_system}.scene, JOBS at a
# time (longest first), and prints the rows in a fixed order. SIM_FULL=1 adds the ten-body
# tol_Q study (LG quotient, alternates Janz/GE/PM, tol_Q 1e-4 and 1e-6: 6 more long runs).
# Under the table, one line adds up the independent H check of every stored state of every
# run (edmi-sim --h-check, tests/lib/passive.c): the steps checked, those decided in __float128,
# and the steps where H rose by more than the work and the energy tank supplied, which must
# be 0 where the guard runs (GE, PM, PT; MP and LG have no such bound).
# Exit status non-zero if any run failed (its message is printed under the table), a run's H
# was not checked on every step, or a guarded run's H rose beyond the work and the tank.
set -u
sim=${1:?usage: run_examples.sh EDMI_SIM [JOBS]}
jobs=${2:-2}
S=examples/scenes
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# "ID SCENE OPTIONS...": IDs sort into table order; the list is in launch order.
runs=()
add() { runs+=("$*"); }
for s in mp lg ge pm pt; do add "3-$s $S/solar_system.scene --scheme $s"; done
for a in janz ge pm; do add "3-q-$a-8 $S/solar_system.scene --scheme lg --lg-switch $a --tol-q 1e-8"; done
if [ "${SIM_FULL:-0}" = 1 ]; then
    for q in 4 6; do for a in janz ge pm; do
        add "3-q-$a-$q $S/solar_system.scene --scheme lg --lg-switch $a --tol-q 1e-$q"
    done; done
fi
for s in mp lg ge pm pt; do add "1-$s $S/neo_hookean.scene --scheme $s"; done
for s in mp lg ge pm pt; do add "2-$s $S/lj_two_body.scene --scheme $s"; done
for q in 4 6 8; do for a in janz ge pm; do
    add "2-q-$q-$a $S/lj_two_body.scene --scheme lg --lg-switch $a --tol-q 1e-$q"
done; done

order() { # table order of the IDs
    for s in mp lg ge pm pt; do echo "1-$s"; done
    for s in mp lg ge pm pt; do echo "2-$s"; done
    for q in 4 6 8; do for a in janz ge pm; do echo "2-q-$q-$a"; done; done
    for s in mp lg ge pm pt; do echo "3-$s"; done
    if [ "${SIM_FULL:-0}" = 1 ]; then
        for q in 4 6 8; do for a in janz ge pm; do echo "3-q-$a-$q"; done; done
    else
        for a in janz ge pm; do echo "3-q-$a-8"; done
    fi
}

echo "edmi-sim: the paper's three examples, ${#runs[@]} runs, $jobs at a time (a line as each ends):"
t0=$(date +%s.%N)
total=${#runs[@]}
export sim out total
# shellcheck disable=SC2016 # the script is expanded by the inner bash
printf '%s\n' "${runs[@]}" | xargs -r -P "$jobs" -L 1 bash -c '
    id=$1; shift
    a=$(date +%s.%N)
    "$sim" "$@" --row --quiet --h-check "$out/$id.h" >"$out/$id.row" 2>"$out/$id.err"
    rc=$?
    b=$(date +%s.%N)
    scene=${1##*/}
    shift
    { flock 9
      echo $rc >"$out/$id.rc"
      n=$(find "$out" -name "*.rc" | wc -l)
      awk -v n="$n" -v t="$total" -v s="${scene%.scene} $*" -v a="$a" -v b="$b" -v rc="$rc" \
          "BEGIN { printf \"  [%2d/%d] %-60s %6.1f s%s\n\", n, t, s, b - a, rc ? \" FAILED\" : \"\" }"
    } 9>"$out/.lock"' run
t1=$(date +%s.%N)

echo
echo "| scene         | scheme          |   steps | us/step | it/st |    max dH |   final dH |    max dJ |    max dL |    max dC |"
echo "|---------------|-----------------|---------|---------|-------|-----------|------------|-----------|-----------|-----------|"
failed=0
for id in $(order); do
    if [ "$(cat "$out/$id.rc" 2>/dev/null)" != 0 ]; then
        failed=1
        echo "| run $id FAILED (see below) |"
    else
        cat "$out/$id.row"
    fi
done
echo
echo "dH = |H - H0|/|H0| (max over all steps, and the signed final value); dJ, dL, dC = the"
echo "max of |J - J0|, |L - L0|, |C(t) - C0| (absolute; n/a where anchors break the invariant)."
echo "LG-Q/ALT TOL: LG as the paper's quotient, with the alternate force ALT below tol_Q = TOL."
echo "Spring and LJ: LG is LG-Q/Janz 1e-08 (the paper's default); ten-body: LG is the closed form."
# The H check over all runs: "steps N checked C rose R beyond E quad Q guard on|off" per run.
hline=$(for id in $(order); do cat "$out/$id.h" 2>/dev/null || echo "missing $id"; done | awk '
    $1 != "steps" { bad++; next }
    { n += $2; c += $4; q += $10; if ($2 != $4) bad++
      if ($12 == "on") { gn += $2; ge += $8 } else { un += $2; ue += $8 } }
    END { printf "H check (tests/lib/passive.c, on %d of %d steps, %d of them in __float128): H rose beyond the work and the tank on %d of %d guarded steps (GE, PM, PT), %d of %d unguarded (MP, LG)%s\n", c, n, q, ge, gn, ue, un, bad || ge ? ": FAILED" : ""
          exit (bad > 0 || ge > 0) }')
hok=$?
echo "$hline"
[ "$hok" = 0 ] || failed=1
# Every effect at once (field, dampers, a force port): the per-step discrete energy balance.
bal=$("$sim" "$S/hanging_chain.scene" --energy-balance --quiet | sed -n 's/^balance *//p')
echo "energy balance, hanging_chain.scene (PM, 5000 steps, field + 6 dampers + force port):"
echo "  ${bal:-FAILED}"
[ -n "$bal" ] || failed=1
# Contact (one-sided potentials and walls, docs/contact.md): the cradle (ropes that only pull,
# balls that only push) and the bouncing ball with each scheme, a chain falling onto a table
# and the 16 balls in a box with PM; contacts begin and end inside steps. Exit status non-zero if a run fails, its energy
# balance misses, or a guarded scheme's H rose beyond the work and the tank.
echo "contact (docs/contact.md): (H - H0)/H0 at the end; steps where H rose beyond the work and the tank (__float128; MP and LG have no guard); guard moves; energy balance"
for run in "newtons_cradle mp lg ge pm pt" "bouncing_ball mp lg ge pm pt" "chain_on_table pm" \
           "balls_in_box pm"; do
    set -- $run
    scene=$1
    shift
    for s in "$@"; do
        c=$("$sim" "$S/$scene.scene" --scheme "$s" --energy-balance --quiet) || failed=1
        fin=$(sed -n 's/^|H-H0|\/|H0| *final \([^,]*\),.*/\1/p' <<<"$c")
        beyond=$(sed -n 's/^H steps.* supplied in \([0-9]*\).*/\1/p' <<<"$c")
        moved=$(sed -n 's/^guard .*changed \([0-9]*\) steps.*/\1/p' <<<"$c")
        okb=$(sed -n 's/^balance .*: \(ok\|EXCEEDED\)$/\1/p' <<<"$c")
        printf '  %-15s %s: %10s; %5s steps; moves %3s; balance %s\n' "$scene" "${s^^}" \
            "${fin:-?}" "${beyond:-?}" "${moved:--}" "${okb:-?}"
        if [ "$okb" != ok ] || { [ "$s" != mp ] && [ "$s" != lg ] && [ "${beyond:-1}" != 0 ]; }; then
            failed=1
        fi
    done
done
awk -v a="$t0" -v b="$t1" -v n="${#runs[@]}" -v j="$jobs" \
    'BEGIN { printf "total: %d runs in %.1f s wall, %d at a time\n", n, b - a, j }'
if [ "$failed" != 0 ]; then
    for id in $(order); do
        if [ "$(cat "$out/$id.rc" 2>/dev/null)" != 0 ]; then
            echo "run $id:"
            cat "$out/$id.err"
        fi
    done
    exit 1
fi
