#!/usr/bin/env bash
# Compare the band-stored Newton matrix with the dense one (tests/programs/band_store.c):
#   band_check.sh DENSE_BIN NARROW_BIN
# runs both, passes if their printed final states are identical bit for bit, and adds that
# check to the narrow binary's own (its refusals). Closing line "N passed, N failed".
set -u
dense=$("$1") || { echo "FAIL $1 exited with $?"; echo "0 passed, 1 failed"; exit 1; }
narrow=$("$2"); rc=$?
echo "$narrow" | grep '^FAIL'
read -r p _ f _ <<<"$(echo "$narrow" | tail -n 1 | tr -d ,)"
[ "$rc" -eq 0 ] || f=$((f + 1))
if [ "$(echo "$dense" | grep -v passed)" = "$(echo "$narrow" | grep -v passed)" ]; then
    p=$((p + 1))
    echo "final states identical: 5 schemes x $(( $(echo "$narrow" | grep -c "^q") / 5 )) bodies"
else
    f=$((f + 1))
    echo "FAIL final states differ between the dense and the band store"
fi
echo "$p passed, $f failed"
[ "$f" -eq 0 ]
