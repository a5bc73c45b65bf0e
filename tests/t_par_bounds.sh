#!/usr/bin/env bash
# t_par_bounds: ./pcdm and ./pbw never exit 0 outside the bounds and handle any finite
# coordinates, as ./mesh does (issue 10 carried to the parallel meshers):
#  - ./pcdm and ./pbw at -q 40 on data/lake.poly stop with "cannot meet the bounds" and
#    exit 1 on every rank (-q 35 is met at times: the order of the splits decides);
#  - an input scaled by 1e-161 (outside the predicates' range, so pslg_check rescales it) is
#    meshed by both at 2 and 3 ranks, passes the distributed --check, and the files written
#    with -o are in input units and pass ./meshcheck.
# Env: BIN (programs, default .), MPIRUN.  Exit status 1 if any case failed.
. "$(dirname "$0")/lib.sh"

expect_fail() { # prog np pattern args...
    local prog=$1 np=$2 pat=$3
    shift 3
    mpi_run "$np" "$BIN/$prog" -NEP "$@" >"$T/out" 2>"$T/err"
    local rc=$?
    if [ $rc -eq 1 ] && grep -q -- "$pat" "$T/err"; then
        ok "$prog np=$np $*: exit 1 on every rank, '$pat'"
    else
        fail "$prog np=$np $*: exit $rc (ranks: $rcs), wanted 1 and '$pat': $(head -c 300 "$T/err")"
    fi
}
expect_fail pcdm 2 "cannot meet the bounds" -q 40 data/lake.poly
expect_fail pbw 2 "cannot meet the bounds" -q 40 data/lake.poly
# --write-partial: the same error and exit status on every rank, but the mesh made so far is
# written, conforming (./meshcheck without the bounds)
for prog in pcdm pbw; do
    rm -f "$T"/wp.*
    mpi_run 2 "$BIN/$prog" -q 45 --write-partial --check -o "$T/wp" data/lake.poly \
        >"$T/out" 2>"$T/err"
    rc=$?
    if [ $rc -eq 1 ] && grep -q "cannot meet the bounds.*--write-partial" "$T/err" &&
        grep -q '^meshcheck: OK' "$T/out" && "$BIN/meshcheck" data/lake.poly "$T/wp" >/dev/null 2>&1; then
        ok "$prog np=2 -q 45 --write-partial: exit 1, the mesh made written and conforming"
    else
        fail "$prog np=2 -q 45 --write-partial: exit $rc: $(head -c 300 "$T/err")"
    fi
done

in=tests/fuzz/regress/holes_1e-161.poly
for prog in pcdm pbw; do
    for np in 2 3; do
        rm -f "$T"/m.*
        mpi_run "$np" "$BIN/$prog" -q 25 --check -o "$T/m" "$in" >"$T/out" 2>"$T/err"
        rc=$?
        if [ $rc -ne 0 ] || ! grep -q '^meshcheck: OK' "$T/out"; then
            fail "$prog np=$np $in: exit $rc: $(grep meshcheck "$T/out" | head -c 300) $(head -c 200 "$T/err")"
        elif ! "$BIN/meshcheck" -q 25 "$in" "$T/m" >"$T/mc" 2>&1; then
            fail "$prog np=$np $in: written files fail ./meshcheck: $(head -c 300 "$T/mc")"
        else
            ok "$prog np=$np $in: --check OK, files OK"
        fi
    done
done
finish
