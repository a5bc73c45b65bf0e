#!/usr/bin/env bash
# t_input: input geometry, refining a mesh and size fields (issue 15) in all three meshers.
#  1. crossing and overlapping segments (tests/inputs/cross, star, overlap) are split: ./mesh
#     --check passes, and ./pcdm and ./pbw at 2 ranks too; --strict refuses with FILE:LINE;
#  2. boundary markers as Triangle assigns them (tests/inputs/markers.poly: a marked edge, a hole
#     and an interior segment, all with marker 0 but the edge) and vertex attributes
#     interpolated (tests/inputs/attributes.poly: x + 2y and a constant, which linear
#     interpolation reproduces exactly on every new vertex), ./mesh and ./pcdm;
#  3. -r: a mesh of data/lake.poly refined again with a smaller -a (without its .poly: the
#     boundary edges and hole points beside them keep the islands out) passes --check and
#     ./meshcheck against the original .poly, and keeps every old vertex; -r with a .area file
#     (--region-areas: Triangle's -a alone) meets each old triangle's bound; ./pcdm, ./pbw -r;
#  4. --size: a background mesh with a small target length at one corner makes the triangles
#     there smaller than at the far corner, in all three meshers.
# Env: BIN, MPIRUN as the other tests.  Needs python3 for the file checks (plain, no modules).
. "$(dirname "$0")/lib.sh"
M=$BIN/mesh
MC=$BIN/meshcheck
ok_check() { # name, command... : must exit 0 and print "meshcheck: OK"
    local name=$1 out
    shift
    out=$("$@" 2>&1)
    local rc=$?
    if [ $rc -ne 0 ] || ! grep -q 'meshcheck: OK' <<<"$out"; then
        fail "$name: exit $rc: $(grep -E 'FAIL|error|:[0-9]+:' <<<"$out" | head -3)"
    else
        ok "$name"
    fi
}
par() { mpi_run 2 "$@"; } # at 2 ranks, every rank's status

# ---- 1. crossings -------------------------------------------------------------------------
for f in cross star overlap; do
    ok_check "mesh $f" "$M" -q 25 -a 0.1 --check -o "$T/$f" "tests/inputs/$f.poly"
    out=$("$M" --strict "tests/inputs/$f.poly" 2>&1) && fail "--strict accepted $f"
    grep -q "tests/inputs/$f.poly:[0-9]*: segment [0-9]* crosses segment" <<<"$out" ||
        fail "--strict $f: $out"
done
ok_check "pcdm cross" par "$BIN/pcdm" -NEP -q 25 -a 0.05 --check tests/inputs/cross.poly
ok_check "pbw cross" par "$BIN/pbw" -NEP -q 25 -a 0.05 --check tests/inputs/cross.poly
ok_check "pcdm star" par "$BIN/pcdm" -NEP -q 25 -a 0.05 --check tests/inputs/star.poly
ok_check "pbw overlap" par "$BIN/pbw" -NEP -q 25 -a 0.05 --check tests/inputs/overlap.poly
out=$(par "$BIN/pcdm" --strict tests/inputs/cross.poly 2>&1) && fail "pcdm --strict accepted"
grep -q 'cross.poly:17: segment 6 crosses segment 5' <<<"$out" || fail "pcdm --strict: $out"

# ---- 2. markers and attributes ------------------------------------------------------------
ok_check "mesh markers" "$M" -q 20 -a 1 --check -o "$T/mk" tests/inputs/markers.poly
ok_check "pcdm markers" par "$BIN/pcdm" -q 20 -a 0.5 --check -o "$T/pmk" tests/inputs/markers.poly
ok_check "mesh attributes" "$M" -q 25 -a 0.5 --check -o "$T/at" tests/inputs/attributes.poly
ok_check "pcdm attributes" par "$BIN/pcdm" -q 25 -a 0.3 --check -o "$T/pat" \
    tests/inputs/attributes.poly
ok_check "pbw attributes" par "$BIN/pbw" -q 25 -a 0.3 --check -o "$T/wat" \
    tests/inputs/attributes.poly
python3 - "$T" <<'EOF' || fail "markers or attributes (see above)"
import sys
T = sys.argv[1]
def rows(p):
    return [l.split('#')[0].split() for l in open(p) if l.split('#')[0].strip()]
bad = 0
def die(msg):
    global bad
    print("FAIL:", msg); bad += 1
for pre in ("mk", "pmk"):
    n = rows(f"{T}/{pre}.node")
    nv = int(n[0][0])
    for r in n[1:nv + 1]:
        x, y, mk = float(r[1]), float(r[2]), int(r[3])
        if (x, y) == (0, 4): want = 3                     # the file's marker
        elif y == 0: want = 7                             # on the marked edge
        elif x in (0, 4) or y == 4: want = 1              # outer boundary, marker 0 in the file
        elif 1 <= x <= 2 and 1 <= y <= 2 and (x in (1, 2) or y in (1, 2)): want = 1  # hole
        else: want = 0                                    # inside (the interior segment too)
        if mk != want: die(f"{pre}: vertex ({x}, {y}) marker {mk}, expected {want}")
    p = rows(f"{T}/{pre}.poly")
    ns = int(p[1][0])
    xy = {int(r[0]): (float(r[1]), float(r[2])) for r in n[1:nv + 1]}
    for r in p[2:2 + ns]:
        a, b, mk = xy[int(r[1])], xy[int(r[2])], int(r[3])
        inner = all(3 <= q[0] <= 4 and abs(q[0] - q[1]) < 1e-12 for q in (a, b))
        want = 7 if a[1] == 0 and b[1] == 0 else 0 if inner else 1
        if mk != want: die(f"{pre}: segment {a}-{b} marker {mk}, expected {want}")
for pre in ("at", "pat", "wat"):
    n = rows(f"{T}/{pre}.node")
    nv, na = int(n[0][0]), int(n[0][2])
    if na != 2: die(f"{pre}: {na} attributes, expected 2")
    for r in n[1:nv + 1]:
        x, y, a, c = map(float, r[1:5])
        if abs(a - (x + 2 * y)) > 1e-9 or abs(c - 10) > 1e-9:
            die(f"{pre}: vertex ({x}, {y}) attributes {a} {c}")
    if nv <= 4: die(f"{pre}: no new vertices")
sys.exit(1 if bad else 0)
EOF

# ---- 3. -r --------------------------------------------------------------------------------
"$M" -q 25 -a 0.1 -o "$T/l1" data/lake.poly >/dev/null 2>&1 || fail "mesh lake"
rm -f "$T/l1.poly"
ok_check "mesh -r" "$M" -r -q 25 -a 0.02 --check -o "$T/l2" "$T/l1"
ok_check "meshcheck -r against the .poly" "$MC" -q 25 -a 0.02 data/lake.poly "$T/l2"
ok_check "mesh -r NAME.node" "$M" -r -q 25 -a 0.02 --check -o "$T/l2n" "$T/l1.node"
ok_check "pcdm -r" par "$BIN/pcdm" -r -q 25 -a 0.01 --check -o "$T/l3" "$T/l1"
ok_check "pbw -r" par "$BIN/pbw" -r -q 25 -a 0.01 --check -o "$T/l4" "$T/l1"
ok_check "meshcheck pbw -r against the .poly" "$MC" -q 25 -a 0.01 data/lake.poly "$T/l4"
"$M" -q 20 -a 0.05 -o "$T/s1" data/square.poly >/dev/null 2>&1 || fail "mesh square"
python3 - "$T" <<'EOF' || fail "writing s1.area"
import sys
T = sys.argv[1]
def rows(p):
    return [l.split('#')[0].split() for l in open(p) if l.split('#')[0].strip()]
n, e = rows(f"{T}/s1.node"), rows(f"{T}/s1.ele")
xy = {int(r[0]): (float(r[1]), float(r[2])) for r in n[1:int(n[0][0]) + 1]}
with open(f"{T}/s1.area", "w") as f:
    f.write(f"# left half: at most 0.002\n{e[0][0]}\n")
    for r in e[1:int(e[0][0]) + 1]:
        cx = sum(xy[int(v)][0] for v in r[1:4]) / 3
        f.write(f"{r[0]} {0.002 if cx < 0.5 else -1}\n")
EOF
ok_check "mesh -r .area" "$M" -r --region-areas -q 20 --check -o "$T/s2" "$T/s1"
ok_check "pbw -r .area" par "$BIN/pbw" -r --region-areas -q 20 --check -o "$T/s3" "$T/s1"
# Triangle's own example of -r with a .area (and one with a hole and no .poly), when the PyPI
# triangle package that ships them is installed
pairs="s1:s2 s1:s3"
tri=$(python3 -c 'import triangle, os; print(os.path.dirname(triangle.__file__))' 2>/dev/null)
if [ -n "$tri" ] && [ -e "$tri/data/bbox.1.area" ]; then
    for e in node ele area; do cp "$tri/data/bbox.1.$e" "$T/b1.$e"; done
    for e in node ele; do cp "$tri/data/square_circle_hole.1.$e" "$T/h1.$e"; done
    ok_check "mesh -r Triangle's bbox.1.area" "$M" -r --region-areas -q 25 --check -o "$T/b2" "$T/b1"
    ok_check "pcdm -r Triangle's square_circle_hole.1" par "$BIN/pcdm" -r -q 25 --check \
        -o "$T/h2" "$T/h1"
    pairs="$pairs b1:b2"
else
    echo "skip Triangle's example files (python3 -c 'import triangle' failed)"
fi
python3 - "$T" $pairs <<'EOF' || fail "-r: old vertices or .area bounds (see above)"
import sys
T = sys.argv[1]
def rows(p):
    return [l.split('#')[0].split() for l in open(p) if l.split('#')[0].strip()]
def mesh(pre):
    n, e = rows(f"{T}/{pre}.node"), rows(f"{T}/{pre}.ele")
    xy = {int(r[0]): (float(r[1]), float(r[2])) for r in n[1:int(n[0][0]) + 1]}
    return xy, [[xy[int(v)] for v in r[1:4]] for r in e[1:int(e[0][0]) + 1]]
def area(t):
    (a, b), (c, d), (e, f) = t
    return ((c - a) * (f - b) - (e - a) * (d - b)) / 2
def inside(t, p):
    s = [area([t[i], t[(i + 1) % 3], p]) for i in range(3)]
    return all(x >= 0 for x in s) or all(x <= 0 for x in s)
bad = 0
for old, new in (("l1", "l2"), ("l1", "l3"), ("l1", "l4"), ("s1", "s2"), ("s1", "s3")):
    oxy, otris = mesh(old)
    nxy, ntris = mesh(new)
    have = set(nxy.values())
    missing = [p for p in oxy.values() if p not in have]
    if missing:
        print(f"FAIL: {new}: {len(missing)} old vertices missing, e.g. {missing[0]}"); bad += 1
    if new in ("l2", "l3", "l4") and len(ntris) <= len(otris):
        print(f"FAIL: {new}: {len(ntris)} triangles, not more than {len(otris)}"); bad += 1
for old, new in (a.split(":") for a in sys.argv[2:]):
    oxy, otris = mesh(old)
    bound = [float(r[1]) for r in rows(f"{T}/{old}.area")[1:]]
    _, ntris = mesh(new)
    have = set(_.values())
    if any(p not in have for p in oxy.values()):
        print(f"FAIL: {new}: old vertices missing"); bad += 1
    for t in ntris:
        c = (sum(p[0] for p in t) / 3, sum(p[1] for p in t) / 3)
        for i, o in enumerate(otris):
            if inside(o, c):
                if bound[i] > 0 and abs(area(t)) > bound[i] * (1 + 1e-9):
                    print(f"FAIL: {new}: triangle {t} area {abs(area(t))} > {bound[i]}"); bad += 1
                break
sys.exit(1 if bad else 0)
EOF
printf '1\n' >"$T/short.area"
cp "$T/s1.node" "$T/short.node"
cp "$T/s1.ele" "$T/short.ele"
out=$("$M" -r --region-areas "$T/short" 2>&1) && fail "a .area with the wrong count accepted"
grep -q "short.area:1: triangle count 1 does not match" <<<"$out" || fail ".area count: $out"

# ---- 4. --size ----------------------------------------------------------------------------
printf '4 2 1 0\n1 0 0 0.02\n2 1 0 0.5\n3 1 1 0.5\n4 0 1 0.5\n' >"$T/bg.node"
printf '2 3 0\n1 1 2 3\n2 1 3 4\n' >"$T/bg.ele"
ok_check "mesh --size" "$M" -q 20 --size "$T/bg" --check -o "$T/z1" data/square.poly
ok_check "pcdm --size" par "$BIN/pcdm" -q 20 --size "$T/bg.node" --check -o "$T/z2" data/square.poly
ok_check "pbw --size" par "$BIN/pbw" -q 20 --size "$T/bg" --check -o "$T/z3" data/square.poly
python3 - "$T" <<'EOF' || fail "--size (see above)"
import sys
T = sys.argv[1]
def rows(p):
    return [l.split('#')[0].split() for l in open(p) if l.split('#')[0].strip()]
bad = 0
for pre in ("z1", "z2", "z3"):
    n, e = rows(f"{T}/{pre}.node"), rows(f"{T}/{pre}.ele")
    xy = {int(r[0]): (float(r[1]), float(r[2])) for r in n[1:int(n[0][0]) + 1]}
    near, far = [], []
    for r in e[1:int(e[0][0]) + 1]:
        (a, b), (c, d), (g, h) = [xy[int(v)] for v in r[1:4]]
        ar, cx, cy = abs((c - a) * (h - b) - (g - a) * (d - b)) / 2, (a + c + g) / 3, (b + d + h) / 3
        # the target length at the centroid (linear over the background's two triangles)
        L = 0.02 + 0.48 * (cx if cx >= cy else cy)
        if ar > 0.4330127018922193 * L * L * (1 + 1e-9):
            print(f"FAIL: {pre}: triangle at ({cx:.3f}, {cy:.3f}) area {ar} above the size"); bad += 1
        (near if cx + cy < 0.2 else far if cx + cy > 1.5 else []).append(ar)
    if not near or not far or max(near) * 10 > max(far):
        print(f"FAIL: {pre}: near {len(near)} max {max(near or [0])}, far max {max(far or [0])}"); bad += 1
sys.exit(1 if bad else 0)
EOF
out=$("$M" --size "$T/s1" data/square.poly 2>&1) && fail "--size without lengths accepted"
grep -q "s1.node: a background mesh needs one attribute per vertex" <<<"$out" || fail "--size: $out"

finish
