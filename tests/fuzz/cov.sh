#!/usr/bin/env bash
# Line and branch coverage of edmi.c by the fuzz corpora (seed corpus plus what `make fuzz`
# added under BUILD/fuzz-*/corpus), both precisions together.
#   usage: cov.sh BUILD_DIR LLVM_PROFDATA LLVM_COV
set -eu
build=$1 profdata=$2 cov=$3
profs=() objs=()
for r in double float; do
    bin="$build/fuzzcov-$r/replay"
    LLVM_PROFILE_FILE="$build/fuzzcov-$r/replay.profraw" \
        "$bin" tests/fuzz/corpus $(ls -d "$build/fuzz-$r/corpus" 2>/dev/null) | head -n 1
    profs+=("$build/fuzzcov-$r/replay.profraw")
    objs+=(-object "$bin")
done
"$profdata" merge -sparse "${profs[@]}" -o "$build/fuzzcov.profdata"
"$cov" report "${objs[@]:1}" -instr-profile="$build/fuzzcov.profdata" edmi.c
