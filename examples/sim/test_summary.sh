#!/usr/bin/env bash
# edmi-sim's summary: the "H steps" line (H of every stored state in tp_q, __float128 on the
# host, by tests/passive.c, not the library), --energy-balance's tolerance and exit status, and the
# --row cost column. `make test` runs it with the double and the float edmi-sim.
#   usage: test_summary.sh EDMI_SIM SCENE_DIR      Last line: "N passed, N failed".
set -u
sim=${1:?usage: test_summary.sh EDMI_SIM SCENE_DIR}
scenes=${2:?scene dir}
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
    ok "PM, spring, --tank-cap 0: H rose in 0 of 10000 steps (tests/passive.c on the stored states)"
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

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
