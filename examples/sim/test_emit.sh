#!/usr/bin/env bash
# edmi-sim --emit-c (`make test` runs it): two emitted scenes in one program, in float and in
# double, load and step with their own dt; a build whose capacities are too small stops at
# the scene's #error; float gets float's tolerances.
#   usage: test_emit.sh EDMI_SIM CC     (from the repository root)   Last: "N passed, N failed".
set -u
sim=${1:?usage: test_emit.sh EDMI_SIM CC}
cc=${2:?cc}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { echo "ok   $1"; pass=$((pass + 1)); }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }
"$sim" examples/scenes/neo_hookean.scene --emit-c > "$tmp/spring.h" &&
    "$sim" examples/scenes/hanging_chain.scene --emit-c > "$tmp/chain.h" ||
    { bad "--emit-c failed"; echo "$pass passed, $fail failed"; exit 1; }
cat > "$tmp/app.c" <<'C'
#include <stdio.h>
#include "spring.h"
#include "chain.h"
static edmi_system sys;
static edmi_workspace work;
static int run(const edmi_scene *sc, const int *port_body, const edmi_real (*port)[3],
               int n_ports, edmi_real dt)
{
    int k;
    if (edmi_load_scene(&sys, sc) != EDMI_OK)
        return 1;
    for (k = 0; k < n_ports; k++)
        if (edmi_set_force(&sys, port_body[k], port[k]) != EDMI_OK)
            return 1;
    for (k = 0; k < 10; k++)
        if (edmi_step(&sys, &work, dt, NULL) != EDMI_OK)
            return 1;
    return 0;
}
int main(void)
{
    int bad = run(&neo_hookean_scene, 0, 0, 0, neo_hookean_DT) ||
              run(&hanging_chain_scene, hanging_chain_port_body, hanging_chain_port_force,
                  hanging_chain_N_PORTS, hanging_chain_DT);
    printf("%s tol_r %g tol_q %g\n", bad ? "failed" : "stepped",
           (double)neo_hookean_scene.params->tol_r, (double)neo_hookean_scene.params->tol_q);
    return bad;
}
C
for real in double float; do
    flags="-std=c99 -Wall -Wextra -Wpedantic -Werror -DEDMI_REAL=$real -I. -I$tmp"
    if out=$($cc $flags "$tmp/app.c" edmi.c -o "$tmp/app" -lm 2>&1) && out=$("$tmp/app"); then
        want=$([ $real = double ] && echo "stepped tol_r 1e-10 tol_q 1e-08" || echo "stepped tol_r 0 tol_q 0.001")
        [ "$out" = "$want" ] && ok "$real: two emitted scenes in one program step ($out)" ||
            bad "$real: '$out', want '$want'"
    else
        bad "$real: $out"
    fi
done
if out=$($cc -std=c99 -DEDMI_MAX_DAMPERS=4 -I. -I$tmp -c "$tmp/app.c" -o "$tmp/x.o" 2>&1); then
    bad "EDMI_MAX_DAMPERS=4 (the chain has 6): compiled"
elif grep -q 'scene hanging_chain needs EDMI_MAX_BODIES >= 6, EDMI_MAX_LINKS >= 6, EDMI_MAX_DAMPERS >= 6' <<<"$out"; then
    ok "EDMI_MAX_DAMPERS=4: the chain's #error names what it needs"
else
    bad "EDMI_MAX_DAMPERS=4: $(head -2 <<<"$out")"
fi
# A scene with coupled masses: emitted with its couplings, it loads where the build takes
# them (EDMI_MAX_MASS_GAP = 1) and stops the build with its #error where it does not.
"$sim" examples/scenes/cable_consistent.scene --emit-c > "$tmp/cable.h"
printf '#include "cable.h"\nstatic edmi_system s;\nint main(void) { return edmi_load_scene(&s, &cable_consistent_scene) == EDMI_OK && s.mass_off[1][0] > 0 ? 0 : 3; }\n' > "$tmp/cable.c"
if $cc -std=c99 -DEDMI_MAX_MASS_GAP=1 -I. -I$tmp "$tmp/cable.c" edmi.c -o "$tmp/cable" -lm &&
        "$tmp/cable"; then
    ok "cable_consistent: emitted couplings load with EDMI_MAX_MASS_GAP=1"
else
    bad "cable_consistent: the emitted scene does not load with EDMI_MAX_MASS_GAP=1"
fi
if out=$($cc -std=c99 -I. -I$tmp -c "$tmp/cable.c" -o "$tmp/x.o" 2>&1); then
    bad "cable_consistent with EDMI_MAX_MASS_GAP=0: compiled"
elif grep -q 'scene cable_consistent couples masses 1 bodies apart: it needs EDMI_MAX_MASS_GAP >= 1' <<<"$out"; then
    ok "EDMI_MAX_MASS_GAP=0: the cable's #error names what it needs"
else
    bad "EDMI_MAX_MASS_GAP=0: $(head -2 <<<"$out")"
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
