#!/usr/bin/env bash
# t_regions: regions end to end (Triangle's regional attributes -A and per-region area bounds,
# --region-areas), and round trips of the output .poly.
#  1. ./mesh, ./pcdm and ./pbw (1, 2 and 4 ranks) mesh tests/inputs/regions.poly (four strips,
#     a hole, two region points that mark nothing, one strip marked twice, one not at all) with
#     -A --region-areas: --check and ./meshcheck -A --region-areas pass (the validator finds the
#     regions itself from the .poly), the .ele has one attribute column, and the attributes per
#     strip (by triangle centroid) are exactly 1, 2, 5, 0 for every mesher and rank count;
#     with a global -a 0.03 as well, the smaller bound wins (checked by ./meshcheck -a 0.03);
#     the legacy VTK and the .vtu pieces carry region_attr cell data.
#  2. The validator is not fooled: a mesh made without -A fails ./meshcheck -A, one made without
#     --region-areas fails ./meshcheck --region-areas.
#  3. Round trips: the .poly that ./mesh, ./pcdm (4 ranks) and ./pbw (2 ranks) write for
#     data/lake.poly (holes) meshes again into a valid mesh of the same domain (./meshcheck
#     against the original input: same area), and holds no interface edge of ./pcdm (lake's
#     segments all have marker 1; interface edges would have 0); the .poly written for
#     regions.poly keeps its regions, so meshing it again with -A --region-areas passes the
#     checks against the original.
# Env: BIN, MPIRUN as the other tests.
. "$(dirname "$0")/lib.sh"
IN=tests/inputs/regions.poly

# strips PREFIX: "strip:attribute" for every distinct pair (strip = floor of the centroid's x)
strips() {
    awk 'FNR == 1 { f++; next } /^#/ || NF == 0 { next }
         f == 1 { x[$1] = $2; next }
         f == 2 { s = int((x[$2] + x[$3] + x[$4]) / 3); print s ":" $5 }' \
        "$1.node" "$1.ele" | sort -u | tr '\n' ' '
}
WANT="0:1 1:2 2:5 3:0 "

# check NAME PREFIX [MESHCHECK OPTIONS]: ./meshcheck -A --region-areas, header, strips
check() {
    local name=$1 p=$2
    shift 2
    if ! "$BIN/meshcheck" -q 20 -A --region-areas "$@" "$IN" "$p" >"$T/mc" 2>&1; then
        fail "$name: meshcheck: $(cat "$T/mc")"
        return
    fi
    if ! head -1 "$p.ele" | grep -q ' 3 1$'; then
        fail "$name: .ele header $(head -1 "$p.ele") (expected one attribute)"
        return
    fi
    local got
    got=$(strips "$p")
    if [ "$got" != "$WANT" ]; then
        fail "$name: attributes per strip '$got', expected '$WANT'"
        return
    fi
    ok "$name"
}

# 1. every mesher
if "$BIN/mesh" -q 20 -A --region-areas --check -o "$T/m" --vtk "$T/m.vtk" --vtk-ascii "$IN" \
    >"$T/out" 2>&1 && grep -q "meshcheck: OK" "$T/out"; then
    check "mesh -A --region-areas" "$T/m"
else
    fail "mesh -A --region-areas: $(cat "$T/out")"
fi
if grep -q "SCALARS region_attr double" "$T/m.vtk"; then ok "mesh: VTK region_attr"; else
    fail "mesh: no region_attr in the VTK file"
fi
if "$BIN/mesh" -q 20 -a 0.03 -A --region-areas -o "$T/ma" "$IN" >"$T/out" 2>&1; then
    check "mesh -a 0.03 -A --region-areas" "$T/ma" -a 0.03
else
    fail "mesh -a 0.03: $(cat "$T/out")"
fi
for prog in pcdm pbw; do
    for np in 1 2 4; do
        p="$T/$prog$np"
        if mpi_run "$np" "$BIN/$prog" -q 20 -A --region-areas --check -o "$p" \
            --vtk "$p.pvtu" "$IN" >"$T/out" 2>&1 && grep -q "meshcheck: OK" "$T/out"; then
            check "$prog np=$np -A --region-areas" "$p"
        else
            fail "$prog np=$np: $(tail -3 "$T/out")"
            continue
        fi
        if grep -q 'Name="region_attr"' "$p.pvtu" && grep -q 'Name="region_attr"' "${p}_0.vtu"; then ok "$prog np=$np: .pvtu/.vtu region_attr"; else
            fail "$prog np=$np: no region_attr in the .vtu pieces"
        fi
    done
    if mpi_run 2 "$BIN/$prog" -q 20 -a 0.03 -A --region-areas -o "$T/${prog}a" \
        "$IN" >"$T/out" 2>&1; then
        check "$prog np=2 -a 0.03 -A --region-areas" "$T/${prog}a" -a 0.03
    else
        fail "$prog -a 0.03: $(tail -3 "$T/out")"
    fi
done

# 2. the validator's own regions
"$BIN/mesh" -q 20 -o "$T/plain" "$IN" >/dev/null 2>&1
if "$BIN/meshcheck" -A "$IN" "$T/plain" >"$T/mc" 2>&1; then
    fail "meshcheck -A passed a mesh without attributes"
else ok "meshcheck -A: no attributes fail"; fi
if "$BIN/meshcheck" --region-areas "$IN" "$T/plain" >"$T/mc" 2>&1; then
    fail "meshcheck --region-areas passed a mesh made without the region bounds"
else ok "meshcheck --region-areas: bounds not met fail"; fi

# 3. round trips of the .poly
rt() { # NAME PREFIX: mesh PREFIX.poly again, check against data/lake.poly
    local name=$1 p=$2
    if [ "$(awk 'FNR > 2 && NF == 4 && $4 == 0' "$p.poly" | wc -l)" -ne 0 ]; then
        fail "$name: the .poly lists segments with marker 0 (interface edges)"
        return
    fi
    if "$BIN/mesh" -q 25 -o "$p.again" "$p.poly" >"$T/out" 2>&1 &&
        "$BIN/meshcheck" -q 25 data/lake.poly "$p.again" >"$T/mc" 2>&1; then
        ok "$name: the written .poly meshes the same domain"
    else
        fail "$name: $(cat "$T/out" "$T/mc")"
    fi
}
"$BIN/mesh" -q 25 -o "$T/lake" data/lake.poly >/dev/null 2>&1 && rt "mesh lake" "$T/lake" ||
    fail "mesh lake: exit $?"
mpi_run 4 "$BIN/pcdm" -q 25 -o "$T/lakep" data/lake.poly >/dev/null 2>&1 &&
    rt "pcdm np=4 lake" "$T/lakep" || fail "pcdm np=4 lake: ranks exit $rcs"
mpi_run 2 "$BIN/pbw" -q 25 -o "$T/lakeb" data/lake.poly >/dev/null 2>&1 &&
    rt "pbw np=2 lake" "$T/lakeb" || fail "pbw np=2 lake: ranks exit $rcs"
for p in "$T/m" "$T/pcdm4"; do
    if "$BIN/mesh" -q 20 -A --region-areas -o "$p.again" "$p.poly" >"$T/out" 2>&1; then
        check "round trip of $(basename "$p").poly with its regions" "$p.again"
    else
        fail "round trip of $p.poly: $(cat "$T/out")"
    fi
done

finish
