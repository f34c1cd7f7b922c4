#!/usr/bin/env bash
# edmi-sim's summary: the "H steps" line (H of every stored state in tp_q, __float128 on the
# host, by tests/lib/passive.c, not the library), --energy-balance's tolerance and exit status, and the
# --row cost column. `make test` runs it with the double and the float edmi-sim.
#   usage: test_summary.sh EDMI_SIM SCENE_DIR [float|double]   Last line: "N passed, N failed".
set -u
sim=${1:?usage: test_summary.sh EDMI_SIM SCENE_DIR [float|double]}
scenes=${2:?scene dir}
real=${3:-double}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
spring=$scenes/neo_hookean.scene
pass=0 fail=0
ok() { echo "ok   $1"; pass=$((pass + 1)); }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }
# "H rose in R of N steps, by more than the work and the tank supplied in E": R, N and E
rises() { sed -n 's/^H steps *H rose in \([0-9]*\) of \([0-9]*\) steps, by more than the work and the tank supplied in \([0-9]*\) .*/\1 \2 \3/p' <<<"$1"; }

# 1. PM on the paper's spring: the energy-safe guarantee, on the stored states: H never rose
#    by more than the energy tank gave (E = 0); without a tank (--tank-cap 0) it never rose.
read -r r n e <<<"$(rises "$("$sim" "$spring" --scheme pm --quiet)")"
if [ "${n:-0}" = 10000 ] && [ "${e:-x}" = 0 ]; then
    ok "PM, spring: H rose in $r of 10000 steps, never beyond what the tank held"
else
    bad "PM, spring: rises '$r' of '$n', beyond the work and the tank '$e'"
fi
out=$("$sim" "$spring" --scheme pm --tank-cap 0 --quiet)
if [ "$(rises "$out")" = "0 10000 0" ]; then
    ok "PM, spring, --tank-cap 0: H rose in 0 of 10000 steps (tests/lib/passive.c on the stored states)"
else
    bad "PM, spring, --tank-cap 0: $(grep '^H steps' <<<"$out")"
fi
# 2. MP has no energy bound: its H rises on about half the steps (no port: every rise is
#    beyond the work supplied). The check sees rises when there are some.
read -r r n e <<<"$(rises "$("$sim" "$spring" --scheme mp --quiet)")"
if [ "${n:-0}" = 10000 ] && [ "${r:-0}" -ge 3000 ] && [ "${r:-0}" = "${e:-x}" ]; then
    ok "MP, spring: H rose in $r of 10000 steps, all beyond the work supplied (0)"
else
    bad "MP, spring: rises '$r' of '$n', beyond the work '$e'"
fi
# 3. The hanging chain's force port supplies work: H rises on many steps, never by more than
#    the work (PM), and the energy balance holds within its default tolerance (exit 0).
out=$("$sim" "$scenes/hanging_chain.scene" --energy-balance --quiet); rc=$?
read -r r n e <<<"$(rises "$out")"
if [ $rc = 0 ] && [ "${r:-0}" -gt 0 ] && [ "${e:-x}" = 0 ] && grep -q '^balance .*: ok$' <<<"$out"; then
    ok "PM, hanging chain: H rose in $r steps, never beyond the work; balance ok, exit 0"
else
    bad "PM, hanging chain: exit $rc, rises '$r', beyond the work '$e': $(grep '^balance' <<<"$out")"
fi
# 4. A tolerance below the arithmetic's resolution: EXCEEDED, a message, exit status 3.
out=$("$sim" "$spring" --balance-tol 1e-30 --quiet 2>&1); rc=$?
if [ $rc = 3 ] && grep -q 'EXCEEDED$' <<<"$out" &&
        grep -q '^edmi-sim: energy balance: largest mismatch .* exceeds the tolerance 1e-30$' <<<"$out"; then
    ok "--balance-tol 1e-30: EXCEEDED, exit 3"
else
    bad "--balance-tol 1e-30: exit $rc: $(tail -n 1 <<<"$out")"
fi
# 5. --row: the cost column is microseconds per step with 3 significant digits, never the
#    0.000 a 1 ms resolution gave the spring's 10^4 steps.
row=$("$sim" "$spring" --row --quiet)
cost=$(awk -F'|' '{ gsub(/ /, "", $5); print $5 }' <<<"$row")
if [[ $cost =~ ^[0-9.]+(e[-+][0-9]+)?$ ]] && awk -v c="$cost" 'BEGIN { exit !(c > 0) }'; then
    ok "--row: us/step column '$cost' (> 0)"
else
    bad "--row: us/step column '$cost' in: $row"
fi
# 5b. --h-check FILE, with --row too (make run-examples adds the files up): one line of the H
#     check's counts, the summary's own (H rose, beyond the work and the tank), every step
#     checked; the spring's PM steps all settled in double-word arithmetic (0 in __float128).
read -r r n e <<<"$(rises "$("$sim" "$spring" --scheme pm --quiet)")"
"$sim" "$spring" --scheme pm --row --quiet --h-check "$tmp/h" >/dev/null
line=$(cat "$tmp/h" 2>/dev/null)
if [ "$line" = "steps 10000 checked 10000 rose $r beyond $e quad 0 guard on" ]; then
    ok "--row --h-check: '$line' (the summary's counts)"
else
    bad "--row --h-check: '$line', the summary: rose '$r' of '$n', beyond '$e'"
fi
"$sim" "$spring" --scheme mp --row --quiet --h-check "$tmp/h" >/dev/null
line=$(cat "$tmp/h" 2>/dev/null)
if [[ $line =~ ^steps\ 10000\ checked\ 10000\ rose\ ([0-9]+)\ beyond\ ([0-9]+)\ quad\ [0-9]+\ guard\ off$ ]] &&
        [ "${BASH_REMATCH[1]}" = "${BASH_REMATCH[2]}" ] && [ "${BASH_REMATCH[1]}" -ge 3000 ]; then
    ok "--row --h-check, MP: '$line'"
else
    bad "--row --h-check, MP: '$line'"
fi

# 6. The general mass matrix: the cable with consistent masses (`mass` lines), PM with the
#    guard and the energy balance on: H never rises beyond what the tank held, the balance
#    holds, exit 0.
out=$("$sim" "$scenes/cable_consistent.scene" --energy-balance --quiet); rc=$?
read -r r n e <<<"$(rises "$out")"
if [ $rc = 0 ] && [ "${n:-0}" = 2000 ] && [ "${e:-x}" = 0 ] && grep -q '^balance .*: ok$' <<<"$out"; then
    ok "PM, cable with a consistent (coupled) mass matrix: H rose in $r of 2000 steps, never beyond the tank; balance ok"
else
    bad "PM, consistent cable: exit $rc: $(grep -E '^(H steps|balance)' <<<"$out")"
fi

# 7. A step far longer than the stiffest link's period: four bodies of 0.2 on springs of
#    k = 2000 (omega = sqrt(k / mu) = sqrt(2000 / 0.1) = 141.4 for a pair, 100 on the anchor)
#    at dt = 1, 23 periods per step. The run succeeds and H behaves, so the only sign is the
#    warning (stderr) and the summary's "stiffest" line, both naming link 1 on line 7; the
#    paper's spring (omega dt = 0.018) has neither.
cat >"$tmp/chain.scene" <<'SCENE'
title stiff chain
body a 0.2 0 0 0 0 0 0
body b 0.2 1.1 0 0 0 0 0
body c 0.2 2 0 0 0 0.1 0
body d 0.2 3.05 0 0 0 0 0
anchor a -1 0 0 harmonic 2000 0
chain a d harmonic 2000 1
set dt 1e-3
set t_end 5
SCENE
out=$("$sim" "$tmp/chain.scene" --dt 1 --quiet 2>"$tmp/err"); rc=$?
if [ $rc = 0 ] && grep -q 'warning: .*link 1 (line 7: .*omega dt = 141 (23 of its periods per step).*Take --dt 0.0141 or less' "$tmp/err" &&
        grep -q '^stiffest  link 1 (line 7: body 0 (a) - body 1 (b)): omega dt 141 at the start: FAR ABOVE 1' <<<"$out"; then
    ok "stiff chain at dt = 1: warned, omega dt = 141 = sqrt(2000/0.1) on link 1 (line 7), exit 0"
else
    bad "stiff chain at dt = 1: exit $rc: $(cat "$tmp/err") / $(grep '^stiffest' <<<"$out")"
fi
out=$("$sim" "$spring" --quiet 2>"$tmp/err"); rc=$?
if [ $rc = 0 ] && [ ! -s "$tmp/err" ] && grep -q '^stiffest  link 0 .*: omega dt 0.018 at the start$' <<<"$out"; then
    ok "paper's spring: omega dt 0.018, no warning"
else
    bad "paper's spring: exit $rc: $(cat "$tmp/err") / $(grep '^stiffest' <<<"$out")"
fi
# 8. --ref converged on that chain: the halved runs fail (Newton, l_max 20), and with substeps
#    they never agree; either way the message says so and the exit status is 1.
out=$("$sim" "$tmp/chain.scene" --dt 1 --ref converged --quiet 2>/dev/null); rc=$?
if [ $rc = 1 ] && grep -q '^vs ref    converged: no reference: the run at dt/[0-9]* = .* failed at step [0-9]* of [0-9]* (from t = .*): EDMI_ERR_' <<<"$out"; then
    ok "--ref converged, stiff chain: $(grep -o 'the run at dt/[0-9]*[^:]*' <<<"$out"), exit 1"
else
    bad "--ref converged, stiff chain: exit $rc: $(grep '^vs ref' <<<"$out")"
fi
out=$("$sim" "$tmp/chain.scene" --dt 1 --ref converged --substeps 3 --quiet 2>/dev/null); rc=$?
if [ $rc = 1 ] && grep -q '^vs ref    converged (dt/64 .*: NOT CONVERGED, the error is unknown' <<<"$out"; then
    ok "--ref converged --substeps 3, stiff chain: not converged in 6 halvings, exit 1"
else
    bad "--ref converged --substeps 3, stiff chain: exit $rc: $(grep '^vs ref' <<<"$out")"
fi
# 9. An initial state beyond the range: the body (line 2) or the link (line 4) is named.
#    |p|^2 / 2: 1e400 / 2 in double, 1e60 / 2 in float.
big=1e200; [ "$real" = float ] && big=1e30
printf 'title t\nbody a 1 0 0 0 %s 0 0\nbody b 1 1 0 0 0 0 0\npair a b harmonic 1 1\nset dt 0.1\nset t_end 1\n' \
    "$big" >"$tmp/big_p.scene"
err=$("$sim" "$tmp/big_p.scene" --quiet 2>&1 >/dev/null); rc=$?
if [ $rc = 2 ] && grep -q 'big_p.scene:2: body 0 (a): its kinetic energy |p|^2/(2m) is beyond the range of EDMI_REAL' <<<"$err"; then
    ok "initial momentum $big: line 2, body 0, kinetic energy beyond the range, exit 2"
else
    bad "initial momentum $big: exit $rc: $err"
fi
printf 'title t\nbody a 1 0 0 0 0 0 0\nbody b 1 1e-30 0 0 0 0 0\npair a b lj 1 1\nset dt 0.1\nset t_end 1\n' \
    >"$tmp/close.scene"
err=$("$sim" "$tmp/close.scene" --quiet 2>&1 >/dev/null); rc=$?
if [ $rc = 2 ] && grep -q 'close.scene:4: link 0 (body 0 (a) - body 1 (b)): its energy or force at the start length 1e-30 is beyond the range' <<<"$err"; then
    ok "Lennard-Jones pair 1e-30 apart: line 4, link 0, beyond the range, exit 2"
else
    bad "Lennard-Jones pair 1e-30 apart: exit $rc: $err"
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
