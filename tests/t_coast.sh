#!/usr/bin/env bash
# t_coast: the parallel meshers on a coastline-like input (tests/coastline.awk: a shore of 9,000
# short segments with narrow inlets, two islands, two lakes; 10,800 vertices, enough for the
# decomposition's fast route on the input's CDT and for subdomain meshes built alone).  At
# -q 30 and two area bounds: ./mesh's mesh, then ./pcdm at (ranks, threads) (1,1) (1,2) (2,1)
# (3,1) (2,2) (8,1): every mesh passes --check, all give one hash (the mesh depends on the
# subdomains alone), and the triangle count is within 3% of ./mesh's (the interfaces add no
# refinement of their own); a 40,000-segment shore (the decomposition's passes in several
# chunks, on 1 or 2 threads) gives one mesh at (1,1) (1,2) (2,1) (3,1); ./pbw at 3 ranks passes
# --check.  Planted faults show the checks
# can fail: a part with one triangle reversed (PCDM_TEST_BREAK_PIECE) must fail --check, and
# rank 1's split requests dropped (PCDM_TEST_DROP_SPLIT) must end the run with an error on every rank.
# SANITIZE=1: one area bound, (1,1) (2,1) (1,2).
. "$(dirname "$0")/lib.sh"

awk -f tests/coastline.awk >"$T/coast.poly" || fatal "tests/coastline.awk failed"
f=$T/coast.poly
areas="0.002 0.0002"
cfgs=("1 1" "1 2" "2 1" "3 1" "2 2" "8 1")
if [ "${SANITIZE:-}" = 1 ]; then
    areas=0.002
    cfgs=("1 1" "2 1" "1 2")
fi
for a in $areas; do
    "$BIN/mesh" -q 30 -a "$a" -NEP --stats --check "$f" >"$T/mesh.txt" 2>&1
    if [ $? != 0 ] || ! grep -q '^meshcheck: OK' "$T/mesh.txt"; then
        fail "./mesh -a $a: $(head -c 300 "$T/mesh.txt")"
        continue
    fi
    n0=$(grep '^stats:' "$T/mesh.txt" | grep -o ' triangles=[0-9]*' | cut -d= -f2)
    want=""
    for cfg in "${cfgs[@]}"; do
        set -- $cfg
        name="./pcdm -a $a ranks $1 threads $2"
        mpi_run "$1" "$BIN/pcdm" --threads "$2" -q 30 -a "$a" -NEP --stats --check "$f" \
            >"$T/out.txt" 2>&1
        rc=$?
        if [ "$rc" != 0 ] || ! grep -q '^meshcheck: OK' "$T/out.txt"; then
            fail "$name: exit $rc: $(grep -m1 -v '^rank' "$T/out.txt" | head -c 300)"
            continue
        fi
        h=$(grep -o 'hash=[0-9a-f]*' "$T/out.txt" | tail -1)
        n=$(grep '^stats:' "$T/out.txt" | grep -o ' triangles=[0-9]*' | cut -d= -f2)
        [ -n "$want" ] || want=$h
        if [ "$h" != "$want" ]; then
            fail "$name: $h, (1,1) gave $want"
        elif ! awk -v n="$n" -v m="$n0" 'BEGIN { exit !(n <= 1.03 * m && n >= 0.97 * m) }'; then
            fail "$name: $n triangles, ./mesh $n0 (more than 3% apart)"
        else
            ok "$name: $h, $n triangles (./mesh $n0)"
        fi
    done
done

# a shore of 40,000 segments: the decomposition's passes over its 84,000 coarse triangles run
# in more than one chunk (decomp_pass.c), on 1 or 2 threads by configuration; one mesh for all
if [ "${SANITIZE:-}" != 1 ]; then
    awk -v n=40000 -f tests/coastline.awk >"$T/coast40k.poly" || fatal "coastline.awk -v n=40000"
    want=""
    for cfg in "1 1" "1 2" "2 1" "3 1"; do
        set -- $cfg
        name="./pcdm 40,000-segment shore, ranks $1 threads $2"
        mpi_run "$1" "$BIN/pcdm" --threads "$2" -q 30 -a 0.002 -NEP --stats --check \
            "$T/coast40k.poly" >"$T/out.txt" 2>&1
        rc=$?
        h=$(grep -o 'hash=[0-9a-f]*' "$T/out.txt" | tail -1)
        if [ "$rc" != 0 ] || ! grep -q '^meshcheck: OK' "$T/out.txt" || [ -z "$h" ]; then
            fail "$name: exit $rc: $(grep -m1 -v '^rank' "$T/out.txt" | head -c 300)"
            continue
        fi
        [ -n "$want" ] || want=$h
        if [ "$h" != "$want" ]; then fail "$name: $h, (1,1) gave $want"; else ok "$name: $h"; fi
    done
fi

mpi_run 3 "$BIN/pbw" -q 30 -a 0.002 -NEP --check "$f" >"$T/out.txt" 2>&1
rc=$?
if [ "$rc" = 0 ] && grep -q '^meshcheck: OK' "$T/out.txt"; then
    ok "./pbw -a 0.002 ranks 3: --check OK"
else
    fail "./pbw -a 0.002 ranks 3: exit $rc: $(head -c 300 "$T/out.txt")"
fi

# planted faults
PCDM_TEST_BREAK_PIECE=1 MPI_X="-x PCDM_TEST_BREAK_PIECE" mpi_run 2 "$BIN/pcdm" -q 30 -a 0.002 -NEP --check "$f" >"$T/out.txt" 2>&1
rc=$?
if [ "$rc" != 0 ] && grep -q '^meshcheck: FAIL' "$T/out.txt"; then
    ok "a reversed triangle in rank 1's part: --check FAIL, exit $rc"
else
    fail "a reversed triangle in rank 1's part: exit $rc: $(head -c 300 "$T/out.txt")"
fi
PCDM_TEST_DROP_SPLIT=1000000 MPI_X="-x PCDM_TEST_DROP_SPLIT" mpi_run 2 "$BIN/pcdm" -q 30 -a 0.002 -NEP "$f" >"$T/out.txt" 2>&1
rc=$?
if [ "$rc" != 0 ] && ! grep -qw 0 "$T/rcs"; then
    ok "rank 1's split requests dropped: every rank exits non-zero [$(cat "$T/rcs")]"
else
    fail "rank 1's split requests dropped: exit $rc, ranks [$(cat "$T/rcs")]: $(head -c 300 "$T/out.txt")"
fi
finish
