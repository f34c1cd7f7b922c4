#!/usr/bin/env bash
# The wall times `make help` quotes, read in one place (tests/scripts/check_help.sh, .ci/run).
# A quote is a bound, "≤ N s" or "≤ N min", N on the scale below: a measured time rounded up to
# the next value of the scale, so a new measurement changes the quote (and needs a commit) only
# when it crosses a step.            (from the repository root)
#   help_time.sh quotes         every quote of `make help`: "COMMAND<TAB>SECONDS<TAB>TEXT" per
#                               line, COMMAND what follows "make" ("" for plain make, "study
#                               STUDY_QUICK=1"), TEXT e.g. "2 min"
#   help_time.sh quote COMMAND  that command's quote, "SECONDS TEXT"; exit 1 if make help has none
#   help_time.sh round SECONDS  the scale's value SECONDS rounds up to, "SECONDS TEXT"; exit 1
#                               beyond the scale
#   help_time.sh below SECONDS  the scale's value one step below SECONDS (a value on the
#                               scale), "SECONDS TEXT"; nothing for the scale's first
#   help_time.sh scale          the scale, "SECONDS TEXT" per line
set -u
scale='5 s|10 s|20 s|30 s|1 min|2 min|3 min|5 min|10 min|15 min|20 min|30 min'

seconds() { # N UNIT
    case $2 in min) echo $(($1 * 60)) ;; *) echo "$1" ;; esac
}

case ${1:-} in
scale)
    tr '|' '\n' <<<"$scale" | while read -r n u; do echo "$(seconds "$n" "$u") $n $u"; done ;;
quotes)
    make --no-print-directory help |
        sed -n -E 's/^make( (.*[^ ]))? +≤ ([0-9]+) (s|min)( .*)?$/\2\t\3\t\4/p' |
        awk -F'\t' '{ printf "%s\t%d\t%s %s\n", $1, $3 == "min" ? $2 * 60 : $2, $2, $3 }' ;;
quote)
    line=$(bash "$0" quotes | awk -F'\t' -v c="${2-}" '$1 == c { print $2 " " $3; exit }')
    [ -n "$line" ] || exit 1
    echo "$line" ;;
below)
    s=${2:?usage: help_time.sh below SECONDS}
    bash "$0" scale | awk -v s="$s" '$1 == s { if (prev != "") print prev; exit } { prev = $0 }' ;;
round)
    s=${2:?usage: help_time.sh round SECONDS}
    bash "$0" scale | awk -v s="$s" '$1 >= s { print $1 " " $2 " " $3; found = 1; exit } END { exit !found }' ;;
*)
    echo "usage: help_time.sh quotes | quote COMMAND | round SECONDS | below SECONDS | scale" >&2
    exit 2 ;;
esac
