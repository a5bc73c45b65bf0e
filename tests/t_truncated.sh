#!/usr/bin/env bash
# t_truncated: input files that end too soon or are not what they look like.
#  1. a truncated file is an error naming the file and the line where it ends: a .poly cut after
#     its segments (Triangle says "Unexpected end of file"; once it was read as a domain without
#     holes; ./mesh, ./meshcheck and ./pcdm at 2 ranks), in the vertex, segment, hole and region
#     lists, inside a line; a .node, .ele and .area cut short (./mesh -r, ./meshcheck).  A .poly
#     without its regions section is complete (the section is optional in Triangle's format);
#  2. a UTF-8 byte-order mark, CRLF and CR-only (old Mac) line ends: the same mesh, byte for
#     byte, as from the plain LF file (.poly, and -r's .node/.ele/.area); a CR file's errors name
#     the right line; UTF-16 text is refused saying so;
#  3. /dev/zero, /dev/urandom and endless non-text streams (a .poly, -r's .node/.ele/.area,
#     ./meshcheck's mesh, ./pcdm's input at 2 ranks and its --cuts file) stop at once with
#     "FILE:LINE: ..." and exit 1, under `timeout 10` and a 2 GB address-space limit (so a
#     reader that reads until memory runs out fails the test instead of taking the machine; no
#     limit on ASan and TSan builds, whose shadow memory needs more).
# Env: BIN, MPIRUN as the other tests.
. "$(dirname "$0")/lib.sh"
M=$BIN/mesh
MC=$BIN/meshcheck
LIMIT=2000000 # KiB of address space (none on sanitizer builds: their shadow memory needs more)
grep -qaE "__asan_init|__tsan_init" "$M" && LIMIT=unlimited

# refused NAME PATTERN CMD...: CMD exits 1 (within 10 s, in LIMIT) and its stderr has a line
# "PROG: PATTERN" (PATTERN a grep -E pattern starting with FILE:LINE:)
refused() {
    local name=$1 pat=$2 rc
    shift 2
    (
        ulimit -v "$LIMIT"
        exec timeout 10 "$@" </dev/null >"$T/out" 2>"$T/err"
    )
    rc=$?
    if [ "$rc" != 1 ]; then
        fail "$name: exit $rc, expected 1: $(head -c 300 "$T/err")"
    elif ! grep -Eq -- "^[a-z]+: $pat" "$T/err"; then
        fail "$name: message lacks /$pat/: $(head -c 300 "$T/err")"
    else
        ok "$name: $(head -n 1 "$T/err" | cut -c 1-150)"
    fi
}
# same NAME A B: the files PREFIX.node/.ele/.poly of A and B are byte for byte the same
same() {
    local e
    for e in node ele poly; do
        if ! cmp -s "$2.$e" "$3.$e"; then
            fail "$1: $2.$e and $3.$e differ"
            return
        fi
    done
    ok "$1: the same .node, .ele and .poly"
}
crlf() { sed 's/$/\r/' "$1"; }
cr() { tr '\n' '\r' <"$1"; }
bom() { printf '\357\273\277' && cat "$1"; }

L=data/lake.poly # 196 vertices (lines 4-199), segments (201-397), holes (399-401)
[ "$(wc -l <"$L")" = 401 ] && [ "$(sed -n 399p "$L")" = 2 ] || fatal "$L: not the lake this test knows"

# ---- 1. truncated files -------------------------------------------------------------------
head -n 397 "$L" >"$T/cut_segs.poly"
refused "a .poly cut after its segments" \
    "$T/cut_segs.poly:397: the file ends before the hole count \(a .poly lists its holes after its segments; write 0 for none\)" \
    "$M" -NEP "$T/cut_segs.poly"
head -n 398 "$L" >"$T/cut_comment.poly" # the holes' comment line kept
refused "a .poly cut after the holes' comment" "$T/cut_comment.poly:398: the file ends before the hole count" \
    "$M" -NEP "$T/cut_comment.poly"
head -n 100 "$L" >"$T/cut_verts.poly"
refused "a .poly cut in its vertices" "$T/cut_verts.poly:100: unexpected end of file: expected 196 vertices, found 97" \
    "$M" -NEP "$T/cut_verts.poly"
head -c "$(($(head -n 149 "$L" | wc -c) + 12))" "$L" >"$T/cut_line.poly" # inside line 150
refused "a .poly cut inside a vertex's line" "$T/cut_line.poly:150: missing (y coordinate|boundary marker) of vertex 147" \
    "$M" -NEP "$T/cut_line.poly"
head -n 300 "$L" >"$T/cut_segs2.poly"
refused "a .poly cut in its segments" "$T/cut_segs2.poly:300: unexpected end of file: expected 196 segments, found 99" \
    "$M" -NEP "$T/cut_segs2.poly"
head -n 400 "$L" >"$T/cut_holes.poly"
refused "a .poly cut in its holes" "$T/cut_holes.poly:400: unexpected end of file: expected 2 holes, found 1" \
    "$M" -NEP "$T/cut_holes.poly"
head -n 44 tests/inputs/regions.poly >"$T/cut_regions.poly"
refused "a .poly cut in its regions" "$T/cut_regions.poly:44: unexpected end of file: expected 6 regions, found 3" \
    "$M" -NEP "$T/cut_regions.poly"
head -n 40 tests/inputs/regions.poly >"$T/no_regions.poly" # complete: regions are optional
if out=$("$M" -NEP -q 25 --check "$T/no_regions.poly" 2>&1) && grep -q 'meshcheck: OK' <<<"$out"; then
    ok "a .poly without its regions section meshes"
else
    fail "a .poly without its regions section: $out"
fi
refused "./meshcheck, a .poly cut after its segments" "$T/cut_segs.poly:397: the file ends before the hole count" \
    "$MC" "$T/cut_segs.poly" "$T/none"
# par_refused NAME PATTERN INPUT: ./pcdm at 2 ranks (in LIMIT, 30 s) exits 1 on every rank, saying
# PATTERN
par_refused() {
    (
        ulimit -v "$LIMIT"
        TIMEOUT=30 mpi_run 2 "$BIN/pcdm" -NEP "$3" </dev/null >"$T/pout" 2>&1
    )
    if all_ranks 2 1 && grep -Eq -- "^pcdm: $2" "$T/pout"; then
        ok "./pcdm -np 2, $1: every rank exits 1"
    else
        fail "./pcdm -np 2, $1: ranks exit [$(cat "$T/rcs")]: $(head -c 300 "$T/pout")"
    fi
}
par_refused "a .poly cut after its segments" "$T/cut_segs.poly:397: the file ends before the hole count" \
    "$T/cut_segs.poly"

# a mesh to cut: PREFIX m (.node, .ele, .poly) and m.area
"$M" -Q -q 30 -a 0.01 -o "$T/m" "$L" || fatal "meshing $L"
nv=$(awk 'NR == 1 { print $1 }' "$T/m.node")
nt=$(awk 'NR == 1 { print $1 }' "$T/m.ele")
awk -v n="$nt" 'BEGIN { print n; for (i = 1; i <= n; i++) print i, 0.002 }' >"$T/m.area"
# cut PREFIX EXT LINES: PREFIX.EXT keeps its first LINES lines, the others are m's
cut_mesh() {
    local e
    for e in node ele area; do cp "$T/m.$e" "$T/$1.$e"; done
    head -n "$3" "$T/m.$2" >"$T/$1.$2"
}
cut_mesh cn node 300
refused "-r, a .node cut in its vertices" "$T/cn.node:300: unexpected end of file: expected $nv vertices, found 299" \
    "$M" -NEP -r "$T/cn"
refused "./meshcheck, a .node cut in its vertices" "$T/cn.node:300: unexpected end of file" \
    "$MC" "$L" "$T/cn"
cut_mesh ce ele $((nt - 20))
refused "-r, a .ele cut in its triangles" "$T/ce.ele:$((nt - 20)): unexpected end of file: expected $nt triangles, found $((nt - 21))" \
    "$M" -NEP -r "$T/ce"
refused "./meshcheck, a .ele cut in its triangles" "$T/ce.ele:$((nt - 20)): unexpected end of file" \
    "$MC" "$L" "$T/ce"
cut_mesh ca area 100
refused "-r -a, a .area cut in its triangles" "$T/ca.area:100: unexpected end of file: expected $nt triangles, found 99" \
    "$M" -NEP -r -a "$T/ca"
head -n 30 tests/inputs/points.node >"$T/pts.node"
refused "a point set's .node cut" "$T/pts.node:30: unexpected end of file: expected 40 vertices, found 28" \
    "$M" -NEP "$T/pts.node"

# ---- 2. byte-order mark, CRLF, CR ---------------------------------------------------------
"$M" -Q -q 30 -a 0.002 -o "$T/lf" "$L" || fatal "meshing $L"
for v in bom crlf cr; do
    $v "$L" >"$T/l_$v.poly"
    if "$M" -Q -q 30 -a 0.002 -o "$T/o_$v" "$T/l_$v.poly" 2>"$T/err"; then
        same "a .poly with $v" "$T/lf" "$T/o_$v"
    else
        fail "a .poly with $v: $(head -c 300 "$T/err")"
    fi
done
bom "$T/l_cr.poly" >"$T/l_bomcr.poly"
"$M" -Q -q 30 -a 0.002 -o "$T/o_bomcr" "$T/l_bomcr.poly" 2>/dev/null && same "a CR .poly with a byte-order mark" "$T/lf" "$T/o_bomcr" ||
    fail "a CR .poly with a byte-order mark refused"
"$M" -Q -r -a -o "$T/r_lf" "$T/m" || fatal "-r -a $T/m"
for v in bom crlf cr; do
    for e in node ele area; do $v "$T/m.$e" >"$T/r$v.$e"; done
    cp "$T/m.poly" "$T/r$v.poly"
    if "$M" -Q -r -a -o "$T/r_$v" "$T/r$v" 2>"$T/err"; then
        same "-r -a with the .node, .ele and .area in $v" "$T/r_lf" "$T/r_$v"
    else
        fail "-r -a, $v: $(head -c 300 "$T/err")"
    fi
done
cr "$T/cut_segs.poly" >"$T/cr_cut.poly"
refused "a CR .poly cut after its segments" "$T/cr_cut.poly:397: the file ends before the hole count" \
    "$M" -NEP "$T/cr_cut.poly"
sed '150s/.* \(.*\) \(.*\) \(.*\)$/147 \1 x\2 \3/' "$L" >"$T/bad150.poly"
cr "$T/bad150.poly" >"$T/cr_bad.poly"
refused "a CR .poly's bad number" "$T/cr_bad.poly:150: malformed y coordinate of vertex 147 'x" \
    "$M" -NEP "$T/cr_bad.poly"
bom "$T/bad150.poly" | crlf /dev/stdin >"$T/bomcrlf_bad.poly"
refused "a CRLF .poly with a byte-order mark, its bad number" "$T/bomcrlf_bad.poly:150: malformed y coordinate of vertex 147 'x" \
    "$M" -NEP "$T/bomcrlf_bad.poly"
printf '\377\376\064\000\040\000\062\000\n\000' >"$T/u16.poly"
refused "UTF-16 text" "$T/u16.poly:1: UTF-16 text" "$M" -NEP "$T/u16.poly"

# ---- 3. not text --------------------------------------------------------------------------
for dev in /dev/zero /dev/urandom; do
    refused "$dev as a .poly" "$dev:[0-9]+: a NUL byte: not a text file" "$M" -NEP "$dev"
    refused "./meshcheck, $dev as the .poly" "$dev:[0-9]+: a NUL byte: not a text file" "$MC" "$dev" "$T/m"
    n=$(basename "$dev")
    for e in node ele area; do
        cut_mesh "d$n$e" "$e" 1000000
        ln -sf "$dev" "$T/d$n$e.$e"
        refused "-r -a, $dev as the .$e" "$T/d$n$e.$e:[0-9]+: a NUL byte: not a text file" \
            "$M" -NEP -r -a "$T/d$n$e"
    done
    refused "./meshcheck, $dev as the .ele" "$T/d${n}ele.ele:[0-9]+: a NUL byte" "$MC" "$L" "$T/d${n}ele"
    # (random bytes may hold a newline before any NUL: that first line is then refused as no cut)
    refused "./pcdm --cuts $dev" ".*$dev:[0-9]+: (not a text file of cuts|expected four finite numbers)" \
        "$BIN/pcdm" -NEP --cuts "$dev" "$L"
done
par_refused /dev/zero "/dev/zero:1: a NUL byte: not a text file" /dev/zero
# endless streams without a NUL byte: text that is no count, comments, one endless line
endless() { # NAME PATTERN CMD...: the program reads CMD's output as its .poly
    local name=$1 pat=$2
    shift 2
    mkfifo "$T/fifo"
    "$@" >"$T/fifo" 2>/dev/null &
    local pid=$!
    refused "$name" "$pat" "$M" -NEP "$T/fifo"
    kill "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    rm -f "$T/fifo"
}
endless "endless 'abc' lines" "$T/fifo:1: malformed vertex count 'abc' \(not an integer\)" yes abc
endless "endless comments" "$T/fifo:[0-9]+: no count in the first MiB" yes '# a comment'
endless "one endless line of digits" "$T/fifo:1: a line of more than 64 KiB" sh -c "tr '\\000' 1 </dev/zero"
yes abcdefgh | head -c 100000000 >"$T/big.txt" # 100 MB that is no .poly: only its start is read
refused "100 MB of text that is no count" "$T/big.txt:1: malformed vertex count 'abcdefgh'" "$M" -NEP "$T/big.txt"
rm -f "$T/big.txt"

finish
