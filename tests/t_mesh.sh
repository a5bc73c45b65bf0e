#!/usr/bin/env bash
# ./mesh end to end: every domain in data/ at -q 20.7 and -q 30, each with two area bounds
# (domain area / 200 and / 2000), written as Triangle files and validated by ./meshcheck with
# the same bounds; then bad input (missing file, every file in tests/bad/, bad options) must
# give one message naming the file and a non-zero exit.
. "$(dirname "$0")/lib.sh"
M=$BIN/mesh
MC=$BIN/meshcheck

for f in data/*.poly; do
    name=$(basename "$f" .poly)
    # the domain's area, as the validator computes it from the PSLG alone
    area=$("$M" -NEP --cdt-only --check "$f" | sed -n 's/.* domain_area=\([^ ]*\).*/\1/p')
    [ -n "$area" ] || {
        fail "$f: no domain area from ./mesh --cdt-only --check"
        continue
    }
    for q in 20.7 30; do
        for div in 200 2000; do
            a=$(awk -v A="$area" -v d="$div" 'BEGIN { printf "%.6g", A / d }')
            out="$T/$name.q$q.a$div"
            if ! "$M" -q "$q" -a "$a" -o "$out" --stats "$f" >"$out.log" 2>&1; then
                fail "$M -q $q -a $a $f"
                cat "$out.log"
                continue
            fi
            res=$("$MC" "$f" "$out" -q "$q" -a "$a" 2>&1)
            rc=$?
            if [ "$rc" -eq 0 ]; then
                ok "$name -q $q -a $a: $(tail -n 1 "$out.log" | cut -c1-80) | ${res:0:60}"
            else
                fail "meshcheck $f $out -q $q -a $a: $res"
            fi
        done
    done
done

# ./mesh --check runs the validator in-process too
res=$("$M" -NEP --check -q 33 -a 0.001 data/lake.poly 2>&1) || fail "./mesh --check -q 33 lake: $res"

# other outputs, and the Steiner point limit
"$M" -NEP -q 30 -a 0.01 --vtk "$T/l.vtk" --svg "$T/l.svg" data/lake.poly || fail "--vtk/--svg"
[ -s "$T/l.vtk" ] && [ -s "$T/l.svg" ] || fail "--vtk/--svg wrote nothing"
rc=0
res=$("$M" --stats --check -S 100 -a 0.0001 -o "$T/s100" data/square.poly 2>&1) || rc=$?
[ "$rc" = 3 ] || fail "-S 100: exit $rc, not 3 (mesh outside the bounds): $res"
[ "$(sed -n 's/.* steiner=\([0-9]*\).*/\1/p' <<<"$res")" = 100 ] || fail "-S 100: $res"
grep -q "Steiner point limit (-S 100) reached" <<<"$res" || fail "-S 100: no message: $res"
grep -q "^meshcheck: OK" <<<"$res" || fail "-S 100: the mesh is not conforming: $res"
[ -s "$T/s100.ele" ] || fail "-S 100: no mesh written"
res=$("$M" -NEP -S 100000 -q 20 data/square.poly 2>&1) || fail "-S not reached must exit 0: $res"

# a bound refinement cannot reach (issue 15): a message and exit 1, nothing written; with
# --write-partial the mesh made so far is written (conforming: ./meshcheck without the bounds
# passes), still exit 1
rc=0
res=$("$M" -q 45 -o "$T/q45" data/lake.poly 2>&1) || rc=$?
[ "$rc" = 1 ] && grep -q "cannot meet the bounds" <<<"$res" && [ ! -e "$T/q45.ele" ] ||
    fail "-q 45: exit $rc, or files written: $res"
rc=0
res=$("$M" -q 45 --write-partial --check -o "$T/q45" data/lake.poly 2>&1) || rc=$?
[ "$rc" = 1 ] && grep -q "cannot meet the bounds.*--write-partial" <<<"$res" &&
    grep -q "^meshcheck: OK" <<<"$res" && "$MC" data/lake.poly "$T/q45" >/dev/null ||
    fail "-q 45 --write-partial: exit $rc, or no checked mesh: $res"

# a .node file (point set): the convex hull is the domain
awk 'BEGIN { srand(7); print 200, 2, 0, 0; for (i = 1; i <= 200; i++) print i, rand(), rand() }' \
    >"$T/points.node"
res=$("$M" --stats -q 25 -o "$T/points" "$T/points.node" 2>&1) || fail "./mesh points.node: $res"
grep -q '^stats: triangles=[1-9]' <<<"$res" || fail "./mesh points.node: no triangles: $res"

# bad input: one clear message naming the file, non-zero exit
expect_fail() { # pattern command...
    local pat=$1 out rc
    shift
    out=$("$@" 2>&1)
    rc=$?
    if [ "$rc" -eq 0 ]; then
        fail "exit 0, expected failure: $*"
    elif ! grep -q -- "$pat" <<<"$out"; then
        fail "message lacks '$pat': $* -> $out"
    else
        ok "exit $rc, '$pat': ${*#"$M "}"
    fi
}
expect_fail "$T/nosuch.poly" "$M" "$T/nosuch.poly"
expect_fail "nosuch.poly: cannot open" "$M" -q 30 "$T/nosuch.poly"
for f in tests/bad/*; do
    case $(basename "$f") in duplicate_points.poly) continue ;; esac # merged with a warning
    # --strict: crossings refused, not split
    expect_fail "$f:[0-9]*:" "$M" -NEP --strict "$f"
done
expect_fail "unknown option" "$M" --bogus data/square.poly
expect_fail "below 60" "$M" -q 70 data/square.poly
expect_fail "bad value" "$M" -a -1 data/square.poly
expect_fail "usage" "$M"
"$M" -NEP tests/bad/duplicate_points.poly >/dev/null 2>&1 || fail "duplicate points should be merged"
"$M" --help | grep -q "usage: ./mesh" || fail "--help"

finish
