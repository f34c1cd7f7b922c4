#!/usr/bin/env bash
# The documentation against the code (`make test`):
#  1. README.md is at most 400 lines;
#  2. each ```c block of README.md whose first line is the first line of an examples/*.c file
#     is that file, byte for byte (the recipes compile because `make` builds the files);
#  3. each function declaration of README's "Every call it makes" block is edmi.h's, up to
#     whitespace, and each EDMI_ macro it names is defined there;
#  4. every relative link in README.md and docs/*.md names an existing file;
#  5. README's compile lines work as a new user runs them: in a directory holding only edmi.h,
#     edmi.c and the recipe's program under the name the README gives it, each `cc` line
#     builds a program that runs and exits 0; the arm-none-eabi-gcc line (where that compiler
#     is installed) builds an object that needs nothing from outside and whose text is the
#     Cortex-M4F figure of README's sizing table (16 / 64 / 16);
#  6. docs/simulator.md's float figures for the spring are what build/float/edmi-sim prints,
#     and edmi-sim names an unknown option in one line;
#  7. no page or example says that H never grows (it may, within the tank);
#  8. every file path README.md and docs/*.md name under tests/, examples/, port/ or docs/
#     exists (globs such as tests/test_*.c and build/ paths are not checked);
#  9. no source in tests/, examples/ or port/ includes a file by a ../ path (issue 33: a folder
#     does not reach into another's files; shared helpers are in tests/lib/, found with
#     -Itests/lib, and edmi.h with -I.).
# Last line: "N passed, N failed".
set -u
pass=0 fail=0
ok() { echo "ok   $1"; pass=$((pass + 1)); }
bad() { echo "FAIL $1"; fail=$((fail + 1)); }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

n=$(wc -l <README.md)
if [ "$n" -le 400 ]; then ok "README.md: $n lines (at most 400)"; else bad "README.md: $n lines, more than 400"; fi

# 2. Split README's ```c blocks into files.
awk -v d="$tmp" '/^```c$/ { k++; f = d "/block" k ".c"; inb = 1; next }
                 /^```$/ && inb { inb = 0; close(f); next }
                 inb { print > f }' README.md
matched=0
for b in "$tmp"/block*.c; do
    [ -e "$b" ] || continue
    first=$(head -n 1 "$b")
    for ex in examples/*.c; do
        if [ "$(head -n 1 "$ex")" = "$first" ]; then
            matched=$((matched + 1))
            if cmp -s "$b" "$ex"; then ok "README's program is $ex byte for byte"
            else bad "README's program starting '$first' differs from $ex: $(diff "$ex" "$b" | head -3)"; fi
        fi
    done
done
[ "$matched" -ge 2 ] || bad "README: $matched example programs found, expected at least 2 (quickstart, haptic_loop)"

# 3. The declarations block: the ```c block holding "edmi_status    edmi_init(".
norm() { tr -s ' \n\t' ' ' | sed 's/ *( */(/g; s/ *) */)/g; s/ *, */, /g; s/ *; */;/g; s/\* /*/g'; }
hdr=$(norm <edmi.h)
decl=$(grep -l 'edmi_init(edmi_system' "$tmp"/block*.c | head -n 1)
if [ -z "$decl" ]; then
    bad "README: no declarations block"
else
    # join declarations that span lines, one per line
    awk '/^#define/ { print; next } { buf = buf " " $0 } /;$/ { print buf; buf = "" }' "$decl" >"$tmp/decls"
    while IFS= read -r d; do
        case $d in
        '#define'*)
            m=$(awk '{ print $2 }' <<<"$d"); m=${m%%(*}
            if grep -q "^#define $m\b" edmi.h; then ok "README names $m, defined in edmi.h"; else bad "README names $m, not in edmi.h"; fi ;;
        *)
            nd=$(norm <<<"$d" | sed 's/^ //')
            if grep -qF -- "$nd" <<<"$hdr"; then ok "README declares '$(sed 's/(.*//' <<<"$nd")(...)' as edmi.h does"
            else bad "README's declaration not in edmi.h: $nd"; fi ;;
        esac
    done <"$tmp/decls"
fi

# 4. Relative links.
for f in README.md docs/*.md; do
    dir=$(dirname "$f")
    grep -o '](\([^)#:]*\)\(#[^)]*\)\?)' "$f" | sed 's/^](//; s/)$//; s/#.*//' | grep . | sort -u |
    while IFS= read -r l; do
        if [ -e "$dir/$l" ]; then echo "ok"; else echo "FAIL $f links to $l, which does not exist"; fi
    done
done >"$tmp/links"
nl=$(grep -c '^ok$' "$tmp/links"); nb=$(grep -c '^FAIL' "$tmp/links")
grep '^FAIL' "$tmp/links"
pass=$((pass + nl)); fail=$((fail + nb))
echo "ok   $nl relative links in README.md and docs/ name existing files"

# 5. The compile lines, in a directory like a new user's.
awk '/^```sh$/ { inb = 1; next } /^```$/ && inb { inb = 0; next }
     inb { if (sub(/\\$/, "")) { buf = buf $0; next } print buf $0; buf = "" }' README.md |
    grep -E '^(cc|arm-none-eabi-gcc) ' >"$tmp/lines"
nc=0
while IFS= read -r line; do
    u="$tmp/user$nc"
    nc=$((nc + 1))
    mkdir -p "$u" && cp edmi.h edmi.c "$u"/
    for src in $(grep -oE '[a-z_]+\.c' <<<"$line" | grep -v '^edmi\.c$'); do
        [ -e "examples/$src" ] && cp "examples/$src" "$u/$src"
    done
    case $line in
    cc*)
        out=$(grep -oE -- '-o [a-z_]+' <<<"$line" | awk '{ print $2 }')
        if (cd "$u" && eval "$line" >"$tmp/cc.log" 2>&1 && "./$out" >/dev/null); then
            ok "README's line '${line:0:60}...' builds and runs $out in a directory of the two files and it"
        else
            bad "README's line '$line' fails in a directory of the two files and its program: $(head -3 "$tmp/cc.log")"
        fi ;;
    arm-none-eabi-gcc*)
        if ! command -v arm-none-eabi-gcc >/dev/null 2>&1; then
            echo "skip README's arm-none-eabi-gcc line: the compiler is not installed"
            continue
        fi
        want=$(awk -F'|' '/^\| 16 \/ 64 \/ 16 \|/ { gsub(/ /, "", $3); print $3; exit }' README.md)
        if (cd "$u" && eval "$line" >"$tmp/cc.log" 2>&1); then
            text=$(arm-none-eabi-size "$u/edmi.o" | awk 'NR == 2 { print $1 }')
            undef=$(arm-none-eabi-nm -u "$u/edmi.o" | awk '{ print $2 }' | tr '\n' ' ')
            if [ "$text" = "$want" ] && [ -z "$undef" ]; then
                ok "README's Cortex-M4F line: text $text B as its sizing table says, nothing undefined"
            else
                bad "README's Cortex-M4F line: text $text B (the table says $want), undefined: ${undef:-none}"
            fi
        else
            bad "README's line '$line' fails: $(head -3 "$tmp/cc.log")"
        fi ;;
    esac
done <"$tmp/lines"
[ "$nc" -ge 3 ] || bad "README: $nc compile lines found, expected 3 (quickstart, haptic_loop, Cortex-M4F)"

# 7. What the guard promises, said as it is: H may rise within the tank, so no program or page
#    says H never grows.
if grep -rn "never grows" README.md docs/*.md examples/*.c >"$tmp/grows"; then
    bad "'never grows' (H may rise within the tank): $(head -2 "$tmp/grows")"
else
    ok "no page or example says H never grows"
fi

# 8. File paths named in the text (links are 4.): tests/..., examples/..., port/..., docs/...
for f in README.md docs/*.md; do
    grep -oE '(^|[^A-Za-z0-9_.-])(tests|examples|port|docs)/[A-Za-z0-9_./*{},+-]*' "$f" |
        sed -E 's/^[^a-z]//; s/[.,]+$//' | grep -v '[*{}]' | sort -u |
        while IFS= read -r path; do
            if [ -e "$path" ]; then echo ok; else echo "FAIL $f names $path, which does not exist"; fi
        done
done >"$tmp/paths"
np=$(grep -c '^ok$' "$tmp/paths"); npb=$(grep -c '^FAIL' "$tmp/paths")
grep '^FAIL' "$tmp/paths"
if [ "$npb" -eq 0 ]; then ok "the $np file paths named in README.md and docs/ exist"; else fail=$((fail + npb)); fi

# 9. No #include "../...": each folder includes only its own files, the shared tests/lib/ and
#    edmi.h, by bare name.
if grep -rn --include='*.c' --include='*.h' --include='*.cpp' --include='*.S' '#include "\.\./' \
        tests examples port >"$tmp/up"; then
    bad "an #include by a ../ path (use bare names and -I): $(head -3 "$tmp/up" | tr '\n' ' ')"
else
    ok "no source in tests/, examples/ or port/ includes a file by a ../ path"
fi

# 6. docs/simulator.md's float figures: the spring with PM, with the guard and without.
if make -s sim EDMI_REAL=float >"$tmp/sim.log" 2>&1; then
    sim="build/float/edmi-sim examples/scenes/neo_hookean.scene"
    on=$($sim 2>&1); off=$($sim --guard off 2>&1)
    f_on=$(awk '/^\|H-H0\|/ { sub(/,$/, "", $3); print $3 }' <<<"$on")
    f_off=$(awk '/^\|H-H0\|/ { sub(/,$/, "", $3); print $3 }' <<<"$off")
    moved=$(awk '/^guard/ { print $5 }' <<<"$on")
    rose=$(awk '/^H steps/ { print $6 }' <<<"$on")
    want="10,000 steps (H−H0)/|H0| = $f_on with the guard (2.000 iterations per step; it changed
  $moved steps, and H rose within the tank on $rose others) and $f_off with \`--guard off\`"
    if grep -qF -- "$want" docs/simulator.md; then
        ok "docs/simulator.md's float spring: $f_on with the guard ($moved steps changed), $f_off without, as build/float/edmi-sim gives"
    else
        bad "docs/simulator.md's float spring figures differ from build/float/edmi-sim's: $f_on, $moved steps changed, $rose rises in the tank; $f_off with --guard off"
    fi
    # an unknown option: one line saying so, and where the options are (not the whole usage)
    build/float/edmi-sim examples/scenes/neo_hookean.scene --bogus >/dev/null 2>"$tmp/bogus"
    rc=$?
    if [ "$rc" = 2 ] && [ "$(wc -l <"$tmp/bogus")" -le 2 ] && grep -q "unknown option '--bogus'" "$tmp/bogus"; then
        ok "edmi-sim names an unknown option in one line and exits 2"
    else
        bad "edmi-sim --bogus: exit $rc, $(wc -l <"$tmp/bogus") lines: $(head -2 "$tmp/bogus")"
    fi
else
    bad "make sim EDMI_REAL=float failed: $(tail -3 "$tmp/sim.log")"
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
