#!/usr/bin/env bash
# Print the `make cross` tables (GitHub markdown) from the built objects.
#   usage: size_table.sh targets  LABEL SIZE NM OBJ FW_ELF  [LABEL SIZE NM OBJ FW_ELF]...
#          size_table.sh capacity CAPS  LABEL SIZE NM DIR  [LABEL SIZE NM DIR]...
#          size_table.sh options SIZE  NAME DEFS OBJ  [NAME DEFS OBJ]...
# `targets`: one row per target: text/data/bss of edmi.o (Berkeley `size`), the symbols
# edmi.o needs from outside, and the text of the minimal firmware port/fw_min.c linked with
# everything it needs. `capacity`: for each capacity setting N-L-D in CAPS (space-separated)
# and each target, edmi.o's text from DIR/N-L-D/edmi.o and the RAM
# sizeof(edmi_system) + sizeof(edmi_workspace), read with `nm -S` from DIR/N-L-D/ramsize.o.
# `options`: edmi.o's text per build option (the first NAME is the default build) and its
# difference from the default.
set -eu
mode=$1
shift

sz() { # sz SIZE FILE -> "text data bss"
    "$1" "$2" | awk 'NR == 2 { print $1, $2, $3 }'
}

if [ "$mode" = targets ]; then
    echo "| target | edmi.o text | data | bss | edmi.o needs | minimal firmware text |"
    echo "|---|---:|---:|---:|---|---:|"
    while [ $# -ge 5 ]; do
        label=$1 size=$2 nm=$3 obj=$4 fw=$5
        shift 5
        read -r text data bss <<<"$(sz "$size" "$obj")"
        # Library symbols by name; compiler runtime helpers (__aeabi_*, __addsf3, ...) counted.
        needs=$("$nm" -u "$obj" | awk '{ print $NF }' | sort -u | awk '
            /^__/ { h++; if ($0 ~ /^__aeabi_d|df[0-9]$|2d$/) d++; next }
            { s = s (s ? ", " : "") $0 }
            END { if (h) s = s (s ? " + " : "") h " libgcc helpers" (d ? " (" d " double)" : "")
                  print s }')
        read -r fwtext _ _ <<<"$(sz "$size" "$fw")"
        echo "| $label | $text | $data | $bss | ${needs:-nothing} | $fwtext |"
    done
elif [ "$mode" = capacity ]; then
    caps=$1
    shift
    header="| N bodies / L links / D dampers (/ mG: EDMI_MAX_MASS_GAP = G) |"
    rule="|---|"
    args=("$@")
    i=0
    while [ $i -lt ${#args[@]} ]; do
        header+=" ${args[$i]}: edmi.o text | ${args[$i]}: RAM (system + workspace) |"
        rule+="---:|---:|"
        i=$((i + 4))
    done
    echo "$header"
    echo "$rule"
    for cap in $caps; do
        row="| ${cap//-/ \/ } |"
        i=0
        while [ $i -lt ${#args[@]} ]; do
            size=${args[$((i + 1))]} nm=${args[$((i + 2))]} dir=${args[$((i + 3))]}/$cap
            read -r text _ _ <<<"$(sz "$size" "$dir/edmi.o")"
            ram=$("$nm" -S -t d "$dir/ramsize.o" |
                  awk '$4 == "tgt_ram_system" || $4 == "tgt_ram_workspace" { s += $2 } END { print s }')
            row+=" $text | $ram |"
            i=$((i + 4))
        done
        echo "$row"
    done
elif [ "$mode" = options ]; then
    size=$1
    shift
    echo "| build | what is in or out | edmi.o text | against the default |"
    echo "|---|---|---:|---:|"
    base=
    while [ $# -ge 3 ]; do
        name=$1 defs=$2 obj=$3
        shift 3
        read -r text _ _ <<<"$(sz "$size" "$obj")"
        [ -n "$base" ] || base=$text
        d=$((text - base))
        [ $d -gt 0 ] && d=+$d
        echo "| $name | ${defs:-(none)} | $text | $d |"
    done
else
    echo "usage: size_table.sh targets|capacity|options ..." >&2
    exit 2
fi
