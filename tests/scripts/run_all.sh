#!/usr/bin/env bash
# Run test programs, show their output, and add up their closing "N passed, N failed" lines.
#   usage: run_all.sh [-p] CMD...   (each CMD is one shell command line, e.g. a binary's path;
#                                   -p runs them side by side and shows each output when all end)
# A command that crashes, times out, prints no closing line, or exits non-zero while claiming
# no failures counts as 1 failed. The last line printed is the total, "N passed, N failed";
# the exit status is 0 only when that total has 0 failed.
set -u
limit=${EDMI_TEST_TIMEOUT:-1800} # seconds per command
parallel=0
if [ "${1:-}" = "-p" ]; then
    parallel=1
    shift
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
total_pass=0 total_fail=0 summary=""

# Add up one command's closing line: account CMD EXIT_STATUS LOG
account() {
    local cmd=$1 rc=$2 log=$3 last p f note=""
    last=$(grep -E -x '[0-9]+ passed, [0-9]+ failed' "$log" | tail -n 1)
    if [ -z "$last" ]; then
        p=0 f=1 note="no closing line"
    else
        read -r p _ f _ <<<"${last//,/}"
        if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then f=1 note="reported 0 failed"; fi
    fi
    if [ "$rc" -eq 124 ]; then note="$note, timed out after ${limit}s"
    elif [ "$rc" -gt 128 ]; then note="$note, killed by signal $((rc - 128))"
    elif [ "$rc" -ne 0 ]; then note="$note, exit status $rc"; fi
    total_pass=$((total_pass + p)) total_fail=$((total_fail + f))
    note=${note#, }
    summary+=$(printf '%6d passed, %3d failed  %s%s' "$p" "$f" "$cmd" "${note:+  ($note)}")$'\n'
}

if [ "$parallel" = 1 ]; then
    i=0
    for cmd in "$@"; do
        (timeout "$limit" bash -c "$cmd" > "$dir/$i.log" 2>&1; echo $? > "$dir/$i.rc") &
        i=$((i + 1))
    done
    wait
    i=0
    for cmd in "$@"; do
        echo "### $cmd"
        cat "$dir/$i.log"
        account "$cmd" "$(cat "$dir/$i.rc")" "$dir/$i.log"
        i=$((i + 1))
    done
else
    for cmd in "$@"; do
        echo "### $cmd"
        timeout "$limit" bash -c "$cmd" 2>&1 | tee "$dir/log"
        account "$cmd" "${PIPESTATUS[0]}" "$dir/log"
    done
fi

echo "### summary"
printf '%s' "$summary"
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
