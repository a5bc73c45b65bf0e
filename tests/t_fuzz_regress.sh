#!/usr/bin/env bash
# Every crash, hang or wrong answer the fuzzer (tests/fuzz) or issue 10 found, kept: each row
# of tests/fuzz/regress/TABLE runs ./mesh with a 90 s timeout (a hang is a failure; the slowest
# row, thin_quad_8e29, takes 4 s of CPU, 8 s under ASan, and passed 30 s in a loaded CI run) and
# checks the exit status and a pattern in the output; exit-0 rows run with --check (the
# validator must accept the mesh).  Any other status (a crash, a sanitizer report) is a failure.
. "$(dirname "$0")/lib.sh"
M=$BIN/mesh
D=tests/fuzz/regress
n=0
while IFS='|' read -r file optstr want pat; do
    file=$(echo $file)
    case "$file" in '' | '#'*) continue ;; esac
    read -r -a opts <<<"$optstr"
    want=$(echo $want)
    pat=$(echo "$pat" | sed 's/^ *//; s/ *$//')
    extra=()
    [ "$want" = 0 ] && extra=(--check)
    n=$((n + 1))
    out=$(timeout 90 "$M" -NEP "${opts[@]}" "${extra[@]}" "$D/$file" 2>&1) # -NEP: no files
    rc=$?
    if [ "$rc" != "$want" ]; then
        fail "$M ${opts[*]} ${extra[*]} $D/$file: exit $rc, expected $want: ${out:0:300}"
    elif [ "$pat" != - ] && ! grep -Eq -- "$pat" <<<"$out"; then
        fail "$M ${opts[*]} $D/$file: output lacks /$pat/: ${out:0:300}"
    else
        ok "$file ${opts[*]} -> $rc"
    fi
done <"$D/TABLE"
echo "$TEST: $n rows"
finish
