#!/usr/bin/env bash
# edmi through CMake, as a firmware project uses it (`make cmake-check`; CI runs it): the
# consumer in examples/cmake/ configured and built for the host and, with
# port/cortex-m/arm-none-eabi-m4f.cmake, for a Cortex-M4F; the host program run, the M4F image
# run under QEMU (mps2-an386). Checks that edmi.c got its floating-point flags whatever the
# consumer's, and that the M4F library contains no double-precision helper.
#   usage: cmake_check.sh BUILD_DIR      Last line: "N passed, N failed".
set -u
build=${1:?usage: cmake_check.sh BUILD_DIR}
pass=0 fail=0
ok() { echo "ok   $1"; pass=$((pass + 1)); }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }
run() { # DESCRIPTION COMMAND... (output shown on failure)
    local what=$1 out
    shift
    if out=$("$@" 2>&1); then ok "$what"; else bad "$what"; echo "$out" | tail -20; fi
}
host=$build/cmake-host m4f=$build/cmake-m4f
rm -rf "$host" "$m4f"
run "host: configure" cmake -S examples/cmake -B "$host" -DCMAKE_BUILD_TYPE=Release
run "host: build" cmake --build "$host"
out=$("$host/spring" 2>&1) && grep -q 'double, 1000 PM steps, H never rose' <<<"$out" &&
    ok "host: runs ($out)" || bad "host: runs: $out"
run "Cortex-M4F: configure" cmake -S examples/cmake -B "$m4f" -DCMAKE_BUILD_TYPE=MinSizeRel \
    -DCMAKE_TOOLCHAIN_FILE="$PWD/port/cortex-m/arm-none-eabi-m4f.cmake"
run "Cortex-M4F: build" cmake --build "$m4f"
flags=$(cat "$m4f/edmi/CMakeFiles/edmi.dir/flags.make" 2>/dev/null)
grep -q -- '-ffp-contract=off' <<<"$flags" && grep -q -- '-fno-math-errno' <<<"$flags" &&
    grep -q -- '-DEDMI_REAL=float' <<<"$flags" &&
    ok "Cortex-M4F: edmi.c compiled with EDMI_REAL=float -ffp-contract=off -fno-math-errno" ||
    bad "Cortex-M4F: edmi.c's flags: $(grep C_FLAGS <<<"$flags")"
undef=$(arm-none-eabi-nm -u "$m4f/edmi/libedmi.a" 2>&1 | awk '$1 == "U" { print $2 }' | sort -u)
if [ -n "$undef" ] && grep -Evq '^(memset|memcpy)$' <<<"$undef"; then
    bad "Cortex-M4F: libedmi.a needs more than memset/memcpy: $(tr '\n' ' ' <<<"$undef")"
else
    ok "Cortex-M4F: libedmi.a needs only $(tr '\n' ' ' <<<"$undef")(no double helper, no libm)"
fi
out=$(TGT_TIMEOUT=60 bash port/run_qemu.sh mps2-an386 "$m4f/spring.elf" 2>&1) &&
    grep -q 'float, 1000 PM steps, H never rose' <<<"$out" &&
    ok "Cortex-M4F: runs on QEMU mps2-an386 ($(head -1 <<<"$out"))" || bad "Cortex-M4F: $out"
# EDMI_WITHOUT: a host build with the schemes but PM, the field, the ports and the scene
# loader compiled out runs the same program to the same line.
lean=$build/cmake-lean
rm -rf "$lean"
run "host, EDMI_WITHOUT=MP;LG;GE;PT;FIELD;PORTS;SCENE: configure" cmake -S examples/cmake \
    -B "$lean" -DCMAKE_BUILD_TYPE=Release "-DEDMI_WITHOUT=MP;LG;GE;PT;FIELD;PORTS;SCENE"
run "host, EDMI_WITHOUT: build" cmake --build "$lean"
grep -q -- '-DEDMI_WITH_PORTS=0' "$lean/edmi/CMakeFiles/edmi.dir/flags.make" 2>/dev/null &&
    ok "host, EDMI_WITHOUT: edmi.c compiled with EDMI_WITH_MP=0 ... EDMI_WITH_SCENE=0" ||
    bad "host, EDMI_WITHOUT: the definitions are missing from edmi.c's flags"
lout=$("$lean/spring" 2>&1) && [ "$lout" = "$("$host/spring" 2>&1)" ] &&
    ok "host, EDMI_WITHOUT: the same output as the full build ($lout)" ||
    bad "host, EDMI_WITHOUT: $lout"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
