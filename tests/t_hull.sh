#!/usr/bin/env bash
# t_hull: Triangle's -c (the convex hull enclosed by segments) end to end.
#  1. tests/inputs/hull/regions.poly: segments that enclose nothing but a hole (one from the
#     hull's left edge to its right edge, one dangling inside), vertices on the hull's edges,
#     one input segment covering two hull edges (marker 7), one equal to a hull edge (marker
#     3), two regions.  Without -c the domain is empty (exit 1); with -c (--cdt-only, and the
#     switch string -pcq30a0.05 with -A --region-areas) --check passes, and tests/hullcheck.py
#     checks the written mesh independently: the hull (computed there) covered exactly by
#     segments, no vertex inside a segment, no segment twice, marker 1 on the new ones and the
#     input's markers kept, the area the hull's minus the hole's; the triangulation's segments
#     are Triangle's own for -pc (when the PyPI `triangle` package is installed).  --convex-hull
#     is -c; --strict does not refuse the hull's edges that input segments cover.
#  2. ./meshcheck: -c against the input passes, without -c it fails (the domain it meant is
#     not the input's), the mesh's own written .poly (which holds the hull's segments) passes;
#     meshing that .poly again, without -c, gives a valid mesh of the same area.
#  3. ./pcdm and ./pbw at 1, 2 and 4 ranks with -pcq30a0.05: exit 0, --check passes, then
#     ./meshcheck -c and hullcheck.py on the written files.
#  4. A point set (tests/inputs/hull/points.node, points on the hull's edges) is meshed over its
#     convex hull with or without -c: the same .node and .ele, hull vertices marked 1.
#  5. 60 random inputs (fixed seeds): points on coarse grids (many collinear, some duplicates),
#     random segments (crossing, overlapping, dangling, some along the hull), random markers;
#     ./mesh -c -q25 --check either meshes (then hullcheck.py passes) or refuses with "cannot
#     meet the bounds" (small input angles) -- never exits 0 with a mesh that fails.
# Env: BIN, MPIRUN as the other tests.
. "$(dirname "$0")/lib.sh"
IN=tests/inputs/hull/regions.poly
HOLE=9,10,11,12 # the square around the hole, by vertex number
area_of() { sed -n 's/.* area=\([^ ]*\) .*/\1/p' "$1" | head -1; }

# run NAME OUT CMD...: CMD must exit 0 and print "meshcheck: OK"
run() {
    local name=$1 out=$2
    shift 2
    "$@" >"$out" 2>&1
    local rc=$?
    if [ "$rc" = 0 ] && grep -q '^meshcheck: OK' "$out"; then
        ok "$name"
        return 0
    fi
    fail "$name: exit $rc: $(grep -v '^$' "$out" | head -3 | tr '\n' ' ')"
    return 1
}
# hull NAME PREFIX [hullcheck options]: the independent check of a -c mesh of IN
hull() {
    local name=$1 prefix=$2 out
    shift 2
    if out=$(python3 tests/hullcheck.py "$IN" "$prefix" "$@" 2>&1); then
        ok "$name: $(tr '\n' ' ' <<<"$out")"
    else
        fail "$name: $out"
    fi
}

# 1. ./mesh
timeout 60 "$BIN/mesh" -NEP --check "$IN" >"$T/none.txt" 2>&1
rc=$?
[ "$rc" = 1 ] && grep -q 'domain is empty' "$T/none.txt" && ok "without -c: the domain is empty" ||
    fail "without -c: exit $rc: $(head -2 "$T/none.txt")"
if run "mesh -c --cdt-only" "$T/cdt.txt" timeout 60 "$BIN/mesh" -c --cdt-only --check -o "$T/cdt" "$IN"; then
    hull "mesh -c --cdt-only" "$T/cdt" --area "$(area_of "$T/cdt.txt")" --minus-cycle $HOLE --triangle pc
fi
if run "mesh -pcq30a0.05 -A --region-areas" "$T/q.txt" timeout 60 "$BIN/mesh" -pcq30a0.05 -A --region-areas --check -o "$T/q" "$IN"; then
    hull "mesh -pcq30a0.05" "$T/q" --area "$(area_of "$T/q.txt")" --minus-cycle $HOLE
    timeout 60 "$BIN/mesh" -pq30a0.05 -A --region-areas --convex-hull -o "$T/long" "$IN" >/dev/null 2>&1
    cmp -s "$T/q.ele" "$T/long.ele" && cmp -s "$T/q.poly" "$T/long.poly" && ok "--convex-hull is -c" ||
        fail "--convex-hull and -c write different meshes"
fi
run "mesh -c --strict" "$T/strict.txt" timeout 60 "$BIN/mesh" -c --strict -q30 -NEP --check "$IN"

# 2. ./meshcheck
if [ -s "$T/q.ele" ]; then
    out=$(timeout 60 "$BIN/meshcheck" -c -q 30 -a 0.05 -A --region-areas "$IN" "$T/q" 2>&1)
    [ $? = 0 ] && grep -q '^meshcheck: OK' <<<"$out" && ok "meshcheck -c" || fail "meshcheck -c: $out"
    out=$(timeout 60 "$BIN/meshcheck" "$IN" "$T/q" 2>&1)
    [ $? = 1 ] && grep -q '^meshcheck: FAIL' <<<"$out" && ok "meshcheck without -c fails" ||
        fail "meshcheck without -c: $out"
    out=$(timeout 60 "$BIN/meshcheck" -q 30 "$T/q.poly" "$T/q" 2>&1)
    [ $? = 0 ] && grep -q '^meshcheck: OK' <<<"$out" && ok "meshcheck against the written .poly" ||
        fail "meshcheck against the written .poly: $out"
    if run "the written .poly meshed again, without -c" "$T/again.txt" timeout 60 "$BIN/mesh" -q30 --check -o "$T/again" "$T/q.poly"; then
        [ "$(area_of "$T/again.txt")" = "$(area_of "$T/q.txt")" ] && ok "same area again" ||
            fail "meshed again: area $(area_of "$T/again.txt"), first $(area_of "$T/q.txt")"
    fi
fi

# 3. ./pcdm and ./pbw
TIMEOUT=300
for prog in pcdm pbw; do
    for np in 1 2 4; do
        name="$prog -pcq30a0.05 at $np ranks"
        if run "$name" "$T/$prog$np.txt" mpi_run "$np" "$BIN/$prog" -pcq30a0.05 --check -o "$T/$prog$np" "$IN"; then
            out=$(timeout 60 "$BIN/meshcheck" -c -q 30 -a 0.05 "$IN" "$T/$prog$np" 2>&1)
            [ $? = 0 ] && grep -q '^meshcheck: OK' <<<"$out" && ok "$name: meshcheck -c" ||
                fail "$name: meshcheck -c: $out"
            hull "$name" "$T/$prog$np" --area "$(area_of "$T/$prog$np.txt")" --minus-cycle $HOLE
        fi
    done
done
unset TIMEOUT

# 4. a point set: the hull with or without -c
P=tests/inputs/hull/points.node
for c in "" -c; do
    # shellcheck disable=SC2086
    run "point set $c" "$T/pts$c.txt" timeout 60 "$BIN/mesh" $c -q30 --check -o "$T/pts$c" "$P"
done
cmp -s "$T/pts.node" "$T/pts-c.node" && cmp -s "$T/pts.ele" "$T/pts-c.ele" &&
    ok "point set: the same mesh with and without -c" || fail "point set: -c changes the mesh"
IN=$P hull "point set -c" "$T/pts-c"
IN=$P hull "point set" "$T/pts"
marks=$(awk 'NR > 1 && !/^#/ && NF { x = $2; y = $3; on = (x == 0 || x == 4 || y == 0 || y == 2);
             if ($NF != on) bad++ } END { print bad + 0 }' "$T/pts.node")
[ "$marks" = 0 ] && ok "point set: hull vertices marked 1, others 0" ||
    fail "point set: $marks vertex markers wrong"

# 5. random inputs
nmeshed=0 nrefused=0
for seed in $(seq 1 60); do
    python3 - "$seed" >"$T/r.poly" <<'EOF'
import random, sys
random.seed(int(sys.argv[1]))
n, side = random.randint(3, 25), random.choice([3, 5, 8, 20])
pts = [(random.randint(0, side) * random.choice([1, 0.5, 0.1]), random.randint(0, side))
       for _ in range(n)]
segs = []
for _ in range(random.randint(0, 12)):
    a, b = random.sample(range(n), 2)
    if pts[a] != pts[b]:
        segs.append((a, b, random.choice([0, 0, 2, 5])))
print(n, 2, 0, 0)
for i, p in enumerate(pts):
    print(i + 1, p[0], p[1])
print(len(segs), 1)
for i, (a, b, m) in enumerate(segs):
    print(i + 1, a + 1, b + 1, m)
print(0)
EOF
    timeout 60 "$BIN/mesh" -Q -c -q25 --check -o "$T/r" "$T/r.poly" >"$T/r.txt" 2>&1
    rc=$?
    if [ "$rc" = 1 ] && grep -q 'cannot meet the bounds\|collinear' "$T/r.txt"; then
        nrefused=$((nrefused + 1))
    elif [ "$rc" != 0 ]; then
        fail "random input $seed: exit $rc: $(head -c 300 "$T/r.txt")"
    elif ! out=$(python3 tests/hullcheck.py "$T/r.poly" "$T/r" 2>&1); then
        fail "random input $seed: $out"
    else
        nmeshed=$((nmeshed + 1))
    fi
done
[ "$nmeshed" -ge 40 ] && ok "random inputs: $nmeshed meshed and checked, $nrefused refused" ||
    fail "random inputs: only $nmeshed of 60 meshed ($nrefused refused)"

finish
