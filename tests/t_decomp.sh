#!/usr/bin/env bash
# t_decomp: the decomposition on inputs of every class (tests/inputs/: a letter with a hole, an
# inclusion with two materials, separate faces, internal and dangling segments, many small
# regions, far-from-origin coordinates, a thin sliver, small input angles, a point set,
# crossing and overlapping segments split at their intersections), each
# meshed by ./pcdm and ./pbw at 1, 2, 3, 4 and 8 ranks with --check, runs with --perturb seeds, --subdomains
# and --imbalance, --write-cuts read back with --cuts, the coarse route on larger meshes, counts
# and balance against ./mesh on small angle-only domains and at 128 subdomains, and the
# test-only fault switch (PCDM_TEST_DROP_SPLIT) that must make the always-on interface check
# fail on every rank.
# Env: BIN (programs, default .), MPIRUN (default "mpirun --oversubscribe"), SANITIZE=1 (fewer
# rank counts).  One line per case; exit status 1 if any case failed.
. "$(dirname "$0")/lib.sh"

# area bounds: about 1-3K triangles each
declare -A AREA=([letter_a.poly]=0.005 [inclusion.poly]=0.001 [map.poly]=0.003
    [segments.poly]=0.002 [grid.poly]=0.001 [far.poly]=0.00000006 [sliver.poly]=0.00002
    [angles.poly]=0.0003 [points.node]=0.001 [cross.poly]=0.01 [star.poly]=0.02
    [overlap.poly]=0.008 [markers.poly]=0.01 [attributes.poly]=0.01 [regions.poly]=0.01)
NPS="1 2 3 4 8"
[ "${SANITIZE:-}" = 1 ] && NPS="1 3 8"

run() { # prog np input extra-args...
    local prog=$1 np=$2 f=$3
    shift 3
    local a=${AREA[$(basename "$f")]}
    local name="$prog np=$np $(basename "$f") -q 30 -a $a $*"
    mpi_run "$np" "$BIN/$prog" -NEP -q 30 -a "$a" --check --stats "$@" "$f" >"$T/out" 2>"$T/err"
    local rc=$?
    if [ $rc -ne 0 ]; then
        fail "$name: exit $rc (ranks: $rcs): $(grep -v '^-\|^ \|^$\|mpirun\|Process\|Exit code\|Primary' "$T/err" "$T/out" | head -2 | tr '\n' ' ')"
    elif ! grep -q '^meshcheck: OK' "$T/out"; then
        fail "$name: validator did not report OK: $(grep meshcheck "$T/out" | head -c 300)"
    else
        ok "$name: $(grep '^stats:' "$T/out" | tail -1 | cut -d' ' -f2-6)"
    fi
}

for f in tests/inputs/*.poly tests/inputs/*.node; do
    for np in $NPS; do
        run pcdm "$np" "$f"
        run pbw "$np" "$f"
    done
done
for seed in 1 2 3; do
    run pcdm 4 tests/inputs/inclusion.poly --perturb "$seed"
    run pbw 4 tests/inputs/letter_a.poly --perturb "$seed"
done
run pcdm 3 tests/inputs/map.poly --subdomains 12
run pbw 2 tests/inputs/grid.poly --subdomains 5
run pcdm 3 tests/inputs/letter_a.poly --imbalance 2

# the coarse route (final meshes of 8-30K triangles, above the exact preview's 1000 per
# subdomain) on inputs of several classes
for f in letter_a inclusion map segments; do
    a=$(awk -v a="${AREA[$f.poly]}" 'BEGIN { printf "%.6g", a / 10 }')
    name="pcdm np=3 $f.poly -q 30 -a $a (coarse route)"
    mpi_run 3 "$BIN/pcdm" -NEP -q 30 -a "$a" --check --stats "tests/inputs/$f.poly" \
        >"$T/out" 2>"$T/err"
    rc=$?
    if [ $rc -ne 0 ] || ! grep -q '^meshcheck: OK' "$T/out"; then
        fail "$name: exit $rc: $(grep -v '^-\|^ \|^$' "$T/err" "$T/out" | head -2 | tr '\n' ' ')"
    else
        ok "$name: $(grep '^stats:' "$T/out" | tail -1 | cut -d' ' -f2-3)"
    fi
done

# counts and balance (issue 11): ./pcdm at 8 ranks with the angle bound alone on small domains
# (the exact preview) must give ./mesh's triangle count within 3% and the busiest rank at most
# 10% above the mean; many subdomains on a small mesh must still meet the bounds, and within
# 10% of ./mesh's count where the mesh has 25+ triangles per subdomain.  Counts, not times.
count_case() { # name np maxdev maxbal input q a [pcdm-only args...]
    local name=$1 np=$2 maxdev=$3 maxbal=$4 f=$5 q=$6 a=$7
    shift 7
    local ref
    ref=$("$BIN/mesh" -NEP --stats -q "$q" -a "$a" "$f" 2>/dev/null | grep '^stats:' | field triangles)
    mpi_run "$np" "$BIN/pcdm" -NEP --check --stats -q "$q" -a "$a" "$@" "$f" >"$T/out" 2>"$T/err"
    local rc=$?
    if [ $rc -ne 0 ] || ! grep -q '^meshcheck: OK' "$T/out" || [ -z "$ref" ]; then
        fail "$name: exit $rc: $(grep -v '^-\|^ \|^$' "$T/err" "$T/out" | head -2 | tr '\n' ' ')"
        return
    fi
    local sl nt tmax tmean
    sl=$(grep '^stats:' "$T/out" | tail -1)
    nt=$(echo "$sl" | field triangles)
    tmax=$(echo "$sl" | field tri_max)
    tmean=$(echo "$sl" | field tri_mean)
    if awk -v n="$nt" -v r="$ref" -v d="$maxdev" -v a="$tmax" -v b="$tmean" -v mb="$maxbal" \
        'BEGIN { exit !((n - r) <= d / 100 * r && (r - n) <= d / 100 * r && a <= mb * b) }'; then
        ok "$name: triangles=$nt (./mesh $ref) balance $tmax/$tmean"
    else
        fail "$name: triangles=$nt vs ./mesh $ref (tolerance $maxdev%), balance $tmax/$tmean (at most $maxbal)"
    fi
}
for d in lake holes channel; do
    count_case "pcdm np=8 $d -q 20.7 (angle bound alone)" 8 3 1.10 "data/$d.poly" 20.7 0
done
count_case "pcdm np=2 lake -q 20.7 -a 0.001 --subdomains 128" 2 10 1.10 data/lake.poly 20.7 0.001 \
    --subdomains 128
count_case "pcdm np=2 lake -q 20.7 --subdomains 128 (390 triangles at one rank)" 2 1000 1.10 \
    data/lake.poly 20.7 0 --subdomains 128
count_case "pcdm np=2 channel -q 30 --subdomains 128" 2 1000 1.10 data/channel.poly 30 0 \
    --subdomains 128

# --write-cuts, then the same decomposition read back with --cuts
f=tests/inputs/inclusion.poly
if TIMEOUT=60 mpi_run 3 "$BIN/pcdm" -NEP -q 30 -a 0.001 --write-cuts "$T/cuts" "$f" \
    >/dev/null 2>&1 && [ -s "$T/cuts" ]; then
    run pcdm 3 "$f" --cuts "$T/cuts"
    run pbw 2 "$f" --cuts "$T/cuts"
else
    fail "--write-cuts wrote nothing"
fi
printf '# one cut\n0.15 0 0.15 1\n' >"$T/square.cuts"
run pcdm 2 tests/inputs/segments.poly --cuts "$T/square.cuts"
printf '0.1 0.1 0.2 0.8\n' >"$T/dangling.cuts"
if TIMEOUT=60 mpi_run 2 "$BIN/pcdm" -NEP --cuts "$T/dangling.cuts" tests/inputs/segments.poly \
    >"$T/out" 2>&1; then
    fail "a dangling cut was accepted"
elif grep -q "dangling.cuts:1: the cut does not separate" "$T/out"; then
    ok "a dangling cut is refused: $(grep -m1 'dangling.cuts:1' "$T/out")"
else
    fail "dangling cut: no FILE:LINE message: $(head -c 300 "$T/out")"
fi

# the fault switch: rank 1 drops its split requests (a mesh of ~16K triangles: on the exact
# preview of a small one no interface is split at all).  Whether that leaves the interfaces in
# disagreement depends on timing (the neighbours may split every shared subsegment first, and
# the mesh is then whole), so: a run that exits 0 must have written a mesh ./meshcheck
# accepts (never exit 0 with a broken mesh), a run that fails must name the interface check and
# write nothing, and at least one of the runs must have tripped the check.
tripped=0
for prog_np in 2 4 3; do
    rm -f "$T"/broken.*
    PCDM_TEST_DROP_SPLIT=1000000 MPI_X="-x PCDM_TEST_DROP_SPLIT" TIMEOUT=60 mpi_run "$prog_np" \
        "$BIN/pcdm" -q 30 -a 0.0001 -o "$T/broken" tests/inputs/inclusion.poly >"$T/out" 2>&1
    rc=$?
    if [ $rc -eq 124 ]; then
        fail "fault switch np=$prog_np: timeout"
    elif [ $rc -eq 0 ]; then
        if "$BIN/meshcheck" tests/inputs/inclusion.poly "$T/broken" >"$T/mc" 2>&1; then
            ok "fault switch np=$prog_np: exit 0, nothing was broken (the written mesh passes ./meshcheck)"
        else
            fail "fault switch np=$prog_np: exit 0 with a broken mesh: $(head -c 200 "$T/mc")"
        fi
    elif ! grep -q 'interface check failed' "$T/out"; then
        fail "fault switch np=$prog_np: exit $rc without the interface-check message"
    elif [ -e "$T/broken.ele" ]; then
        fail "fault switch np=$prog_np: the broken mesh was written"
    elif ! all_ranks "$prog_np" 1; then
        fail "fault switch np=$prog_np: the interface check failed, but not every rank exited 1: $rcs"
    else
        tripped=$((tripped + 1))
        ok "fault switch np=$prog_np: exit $rc: $(grep -m1 -o 'interface check failed.*' "$T/out" | cut -c1-120)"
    fi
done
if [ "$tripped" -eq 0 ]; then
    fail "fault switch: no run tripped the interface check"
fi

finish
