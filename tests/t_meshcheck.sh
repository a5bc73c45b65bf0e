#!/usr/bin/env bash
# meshcheck end to end: usage and exit codes (0 valid; 1 invalid, or an unreadable or bad input;
# 2 usage error) and the one-line summary, on small meshes written here in Triangle's format.
. "$(dirname "$0")/lib.sh"
MC=$BIN/meshcheck
expect() { # rc pattern command...: exit status rc and a line matching pattern
    local want=$1 pat=$2
    shift 2
    local out rc
    out=$("$@" 2>&1)
    rc=$?
    echo "\$ ${*#"$MC "} -> $rc: $out"
    if [ "$rc" -ne "$want" ]; then
        fail "exit $rc, expected $want: $*"
    elif ! grep -q -- "$pat" <<<"$out"; then
        fail "output lacks '$pat': $*"
    else
        ok "exit $rc, '$pat'"
    fi
}

printf '4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n' >"$T/sq.node"
printf '2 3 0\n1 1 2 3\n2 1 3 4\n' >"$T/sq.ele"
printf '0 2 0 1\n4 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n0\n' >"$T/sq.poly"
mkdir "$T/flip" && cp "$T/sq.node" "$T/sq.poly" "$T/flip/"
printf '2 3 0\n1 1 3 2\n2 1 3 4\n' >"$T/flip/sq.ele"

expect 0 'usage: meshcheck' "$MC" --help
expect 2 'usage: meshcheck' "$MC"
expect 2 'usage: meshcheck' "$MC" data/square.poly
expect 2 'unknown option' "$MC" data/square.poly "$T/sq" --bogus
expect 2 '\-q needs a non-negative number' "$MC" data/square.poly "$T/sq" -q abc
expect 0 'meshcheck: OK triangles=2 vertices=4 min_angle=45.0000 max_area=0.5 area=1 domain_area=1' \
    "$MC" data/square.poly "$T/sq"
expect 0 'meshcheck: OK' "$MC" data/square.poly "$T/sq" -q 45 -a 0.5 --interfaces-delaunay
expect 1 'meshcheck: FAIL triangle 0 has smallest angle 45 < 50 degrees bad_angle=2' \
    "$MC" data/square.poly "$T/sq" -q 50
expect 1 'bad_area=2' "$MC" data/square.poly "$T/sq" -a 0.25
expect 1 'meshcheck: FAIL triangle 0 (0 2 1) is clockwise bad_orient=1' "$MC" data/square.poly "$T/flip/sq"
expect 1 'area_mismatch=1' "$MC" data/lshape.poly "$T/sq"
expect 1 'nosuch.node: cannot open: No such file or directory' "$MC" data/square.poly "$T/nosuch"
# crossing segments are split as the meshers split them: the bow tie's crossing vertex is missing
expect 1 'input vertex 5 (line 9) at (0.5, 0.5) is not a mesh vertex' \
    "$MC" tests/bad/self_intersecting.poly "$T/sq"
rm "$T/sq.poly" # without the .poly the boundary edges still carry the input segments
expect 0 'meshcheck: OK' "$MC" data/square.poly "$T/sq"
# second order (-o2): six nodes per triangle, each midside node the midpoint of the edge
# opposite its corner (nodes 5..9: midpoints of 2-3, 3-1, 1-2 of triangle 1, then 3-4, 4-1)
printf '9 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n5 1 0.5 1\n6 0.5 0.5 0\n7 0.5 0 1\n8 0.5 1 1\n9 0 0.5 1\n' >"$T/o2.node"
printf '2 6 0\n1 1 2 3 5 6 7\n2 1 3 4 8 9 6\n' >"$T/o2.ele"
expect 0 'meshcheck: OK triangles=2' "$MC" data/square.poly "$T/o2"
printf '2 6 0\n1 1 2 3 6 5 7\n2 1 3 4 8 9 6\n' >"$T/o2.ele"
expect 1 'o2.ele:2: triangle 1: node 6 is not the midpoint of the edge opposite corner 1' \
    "$MC" data/square.poly "$T/o2"
printf '2 5 0\n1 1 2 3 5 6\n2 1 3 4 8 9\n' >"$T/o2.ele"
expect 1 'expected 3 nodes per triangle (6: second order' "$MC" data/square.poly "$T/o2"
finish
