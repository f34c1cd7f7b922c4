#!/usr/bin/env bash
# Check one compiled edmi object: what it exports and what it needs from outside.
#   usage: check_lib.sh NM CC OBJ [--no-double]
# CC (with its target flags) is only asked where its libgcc is, so that compiler runtime
# helpers are recognised. --no-double also rejects double-precision soft-float helpers
# (__aeabi_d*, __aeabi_f2d, __adddf3, ...), for a float build on an FPU-less-for-double core.
# Prints one line per check and closes with "N passed, N failed", like the test binaries.
set -u
nm_cmd=$1 cc_cmd=$2 obj=$3 mode=${4:-}
pass=0 fail=0

check() { # check NAME BAD-LIST: passes when BAD-LIST is empty
    if [ -z "$2" ]; then
        pass=$((pass + 1)); echo "ok   $obj: $1"
    else
        fail=$((fail + 1)); echo "FAIL $obj: $1:" $2
    fi
}

defined=$($nm_cmd -g --defined-only "$obj" | awk 'NF == 3 { print $3 }')
undefined=$($nm_cmd -u "$obj" | awk '{ print $NF }')
libgcc=$($nm_cmd -g --defined-only "$($cc_cmd -print-libgcc-file-name)" 2>/dev/null |
         awk 'NF == 3 { print $3 }' | sort -u)
echo "$obj exports $(wc -w <<<"$defined") symbols; needs:" ${undefined:-nothing}

# STYLE.md: public names are edmi_ only (REBOUND checks its prefix the same way).
check "every exported symbol starts with edmi_" "$(grep -v '^edmi_' <<<"$defined")"
check "exports edmi_step" "$(grep -qx edmi_step <<<"$defined" || echo missing)"

# The caller owns every byte and the library never prints, aborts or exits.
forbidden='malloc|calloc|realloc|free|aligned_alloc|(v|f|s|sn)?printf|puts|fputs|putchar|fputc'
forbidden+='|fwrite|abort|exit|_exit|__assert_fail|__.*printf_chk'
check "no allocation, stdio or exit" "$(grep -E -x "$forbidden" <<<"$undefined")"

# Anything else must be sqrt, one of the four functions GCC may emit for freestanding code,
# or a helper the compiler's own runtime library (libgcc) defines.
others=$(grep -v -E -x 'sqrtf?|memcpy|memset|memmove|memcmp' <<<"$undefined" |
         grep -v -x -F -f <(echo "$libgcc") || true)
check "needs only sqrt, mem*, libgcc helpers" "$others"

if [ "$mode" = --no-double ]; then
    check "no double-precision helpers" \
        "$(grep -E '^__aeabi_(d|[a-z0-9]*2d$)|^__[a-z0-9]*df' <<<"$undefined")"
fi

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
