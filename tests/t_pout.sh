#!/usr/bin/env bash
# t_pout: the parallel meshers' end without a gather (mesher/par/pout.h), end to end.
#  1. ./pcdm and ./pbw at 1, 2, 4 and 8 ranks with -o, --vtk and --check: the distributed check
#     prints "meshcheck: OK", every rank exits 0, the files (written by MPI-IO from every rank's
#     part) pass ./meshcheck, and the .pvtu index names one .vtu piece per rank;
#  2. a broken part (test-only fault PCDM_TEST_BREAK_PIECE=R: rank R reverses a triangle) makes
#     --check fail with exit status 1 on every rank, and nothing is written;
#  3. parts whose areas do not sum to the domain's (test-only fault PCDM_TEST_AREA_SKEW=R: rank
#     R's area taken 1e-6 too large) fail the always-on area check, whose domain area rank 0
#     computes on a thread while it decomposes: exit status 1 on every rank, nothing written
#     (./pcdm at 2 ranks, and at 1 rank with --threads 2).
# (The numbering itself, and files written by 1-8 ranks being equal as sets of exact
# coordinates, are tested by tests/mpi_pout.c.)  Env: BIN, MPIRUN as the other tests.
. "$(dirname "$0")/lib.sh"

A=0.001
for prog in pcdm pbw; do
    for np in 1 2 4 8; do
        p="$T/$prog$np"
        mpi_run "$np" "$BIN/$prog" -q 30 -a $A --check -o "$p" --vtk "$p.vtk" data/lake.poly \
            >"$T/out" 2>"$T/err"
        name="$prog np=$np"
        if ! all_ranks "$np" 0; then
            fail "$name: exit statuses $rcs: $(head -3 "$T/err")"
            continue
        fi
        grep -q '^meshcheck: OK' "$T/out" && ok "$name: --check: $(grep '^meshcheck' "$T/out" | cut -c1-60)" ||
            fail "$name: no 'meshcheck: OK' line: $(head -3 "$T/out")"
        if r=$(timeout 120 "$BIN/meshcheck" data/lake.poly "$p" -q 30 -a $A 2>&1); then
            ok "$name: files pass ./meshcheck"
        else
            fail "$name: files: $r"
        fi
        n=$(grep -c '<Piece Source=' "$p.pvtu" 2>/dev/null)
        [ "$n" = "$np" ] && [ -s "${p}_$((np - 1)).vtu" ] && ok "$name: $p.pvtu with $n pieces" ||
            fail "$name: .pvtu names ${n:-no} pieces, want $np"
    done
done

for prog in pcdm pbw; do
    np=4
    PCDM_TEST_BREAK_PIECE=2 mpi_run $np "$BIN/$prog" -q 30 -a $A --check -o "$T/broken" \
        data/lake.poly >"$T/out" 2>"$T/err"
    name="$prog np=$np broken part"
    all_ranks $np 1 && ok "$name: every rank exits 1" ||
        fail "$name: exit statuses $rcs, want 1 on each of $np ranks"
    grep -q '^meshcheck: FAIL rank 2: ' "$T/out" && ok "$name: $(grep '^meshcheck' "$T/out" | cut -c1-70)" ||
        fail "$name: no FAIL line naming rank 2: $(head -2 "$T/out")"
    [ ! -e "$T/broken.node" ] && ok "$name: nothing written" || fail "$name: files written"
done

for np in 2 1; do
    thr=()
    [ "$np" = 1 ] && thr=(--threads 2)
    PCDM_TEST_AREA_SKEW=$((np - 1)) mpi_run $np "$BIN/pcdm" "${thr[@]}" -q 30 -a $A -o "$T/skew" \
        data/lake.poly >"$T/out" 2>"$T/err"
    name="pcdm np=$np ${thr[*]} area skew"
    if all_ranks "$np" 1 && grep -q "areas sum to" "$T/err" && ! ls "$T"/skew.* >/dev/null 2>&1; then
        ok "$name: refused on every rank, nothing written"
    else
        fail "$name: exit statuses $rcs, files: $(ls "$T"/skew.* 2>/dev/null | head -2), $(head -2 "$T/err")"
    fi
done

finish
