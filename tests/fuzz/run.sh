#!/usr/bin/env bash
# Run the API fuzzer (tests/fuzz/fuzz_api.c) for SECONDS per precision, both precisions at
# once (one core each), and report like a test program.
#   usage: run.sh SECONDS BUILD_DIR PRECISION...
# Each precision's binary is BUILD_DIR/fuzz-PRECISION/fuzz. Inputs that add coverage go to
# BUILD_DIR/fuzz-PRECISION/corpus (the seed corpus tests/fuzz/corpus is read, never written);
# an input that breaks a promise is written to BUILD_DIR/fuzz-PRECISION/crash-* and counts
# as failed: copy it into tests/fuzz/corpus so that `make test` replays it from then on.
# Prints per precision the inputs run, executions per second and coverage, then the
# closing "N passed, N failed" (1 passed per precision that ran its time without a finding).
set -u
secs=$1 build=$2
shift 2
pids=()
for r in "$@"; do
    dir="$build/fuzz-$r"
    mkdir -p "$dir/corpus"
    rm -f "$dir"/crash-* "$dir"/leak-* "$dir"/timeout-* "$dir"/oom-*
    start=$(date +%s)
    (
        "$dir/fuzz" -max_len=1024 -timeout=10 -rss_limit_mb=1024 -max_total_time="$secs" \
            -print_final_stats=1 -artifact_prefix="$dir/" "$dir/corpus" tests/fuzz/corpus \
            >"$dir/log" 2>&1
        rc=$?
        echo $(($(date +%s) - start)) >"$dir/elapsed"
        exit $rc
    ) &
    pids+=($!)
done
passed=0 failed=0 i=0
for r in "$@"; do
    dir="$build/fuzz-$r"
    wait "${pids[$i]}"
    rc=$?
    i=$((i + 1))
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log" | tail -n 1)
    speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$dir/log" | tail -n 1)
    cov=$(grep -E '^#[0-9]+' "$dir/log" | tail -n 1 | sed -n 's/.*cov: \([0-9]*\) ft: \([0-9]*\) corp: \([0-9]*\).*/\1 edges, \2 features, corpus \3/p')
    if [ -z "$runs" ]; then # stopped by a finding: the last status line has the count
        runs=$(grep -E '^#[0-9]+' "$dir/log" | tail -n 1 | sed 's/^#\([0-9]*\).*/\1/')
    fi
    echo "fuzz $r: ${runs:-?} inputs in $(cat "$dir/elapsed") s (${speed:-?} per second), ${cov:-?}"
    found=$(ls "$dir"/crash-* "$dir"/timeout-* "$dir"/oom-* 2>/dev/null)
    if [ "$rc" -ne 0 ] || [ -n "$found" ]; then
        grep -E 'edmi fuzz|runtime error|ERROR: AddressSanitizer|ERROR: libFuzzer|dH =' "$dir/log" | head -n 5
        echo "fuzz $r: FAILED (exit $rc) ${found:-}"
        failed=$((failed + 1))
    else
        passed=$((passed + 1))
    fi
done
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
