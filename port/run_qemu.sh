#!/usr/bin/env bash
# Run one Cortex-M ELF on a QEMU MPS2 board with semihosting, under a timeout.
#   usage: run_qemu.sh MACHINE ELF [QEMU-ARGS...]     e.g. run_qemu.sh mps2-an386 tests.elf
# The program's console (semihosting SYS_WRITE0) goes to stdout. The exit status is the
# program's: 0 passed, 1 a test failed, 3 a fault (the handler printed the faulting PC),
# 4 stack overflow; 124 when it did not finish within TGT_TIMEOUT seconds (default 600),
# i.e. a hang. The wall time goes to the last line.
set -u
machine=$1 elf=$2
shift 2
limit=${TGT_TIMEOUT:-600}
qemu=${TGT_QEMU:-qemu-system-arm}
start=$(date +%s.%N)
timeout "$limit" "$qemu" -M "$machine" -display none -monitor none -serial none \
    -chardev stdio,id=semihost -semihosting-config enable=on,target=native,chardev=semihost \
    -kernel "$elf" "$@" </dev/null
rc=$?
end=$(date +%s.%N)
case $rc in
    0) what="exit 0" ;;
    1) what="exit 1: a test failed" ;;
    3) what="exit 3: fault" ;;
    4) what="exit 4: stack overflow" ;;
    124) what="TIMEOUT after ${limit} s: hang or too slow" ;;
    *) what="exit $rc" ;;
esac
awk -v m="$machine" -v w="$what" -v a="$start" -v b="$end" \
    'BEGIN { printf "[qemu %s] %s, %.1f s wall\n", m, w, b - a }'
exit $rc
