#!/usr/bin/env bash
# t_par_bounds: ./pcdm and ./pbw never exit 0 outside the bounds and handle any finite
# coordinates, as ./mesh does (issue 10 carried to the parallel meshers):
#  - ./pcdm -q 35 and ./pbw -q 40 on data/lake.poly stop with "cannot meet the bounds" and
#    exit 1 on every rank (./pbw's timing-dependent order occasionally reaches -q 35: t_pbw);
#  - an input scaled by 1e-161 (outside the predicates' range, so pslg_check rescales it) is
#    meshed by both at 2 and 3 ranks, passes the distributed --check, and the files written
#    with -o are in input units and pass ./meshcheck.
# Env: BIN (programs, default .), MPIRUN.  Exit status 1 if any case failed.
set -u
cd "$(dirname "$0")/.."
BIN=${BIN:-.}
MPIRUN=${MPIRUN:-mpirun --oversubscribe}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/t_par_bounds.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail=0
ok() { printf 'ok   %s\n' "$*"; }
bad() { fail=$((fail + 1)); printf 'FAIL %s\n' "$*"; }

expect_fail() { # prog np pattern args...
    local prog=$1 np=$2 pat=$3
    shift 3
    timeout 120 $MPIRUN -np "$np" "$BIN/$prog" -NEP "$@" >"$tmp/out" 2>"$tmp/err"
    local rc=$?
    if [ $rc -eq 1 ] && grep -q -- "$pat" "$tmp/err"; then
        ok "$prog np=$np $*: exit 1, '$pat'"
    else
        bad "$prog np=$np $*: exit $rc, wanted 1 and '$pat': $(head -c 300 "$tmp/err")"
    fi
}
expect_fail pcdm 2 "cannot meet the bounds" -q 35 data/lake.poly
expect_fail pbw 2 "cannot meet the bounds" -q 40 data/lake.poly
# --write-partial: the same error and exit status on every rank, but the mesh made so far is
# written, conforming (./meshcheck without the bounds)
for prog in pcdm pbw; do
    rm -f "$tmp"/wp.*
    timeout 120 $MPIRUN -np 2 "$BIN/$prog" -q 45 --write-partial --check -o "$tmp/wp" data/lake.poly \
        >"$tmp/out" 2>"$tmp/err"
    rc=$?
    if [ $rc -eq 1 ] && grep -q "cannot meet the bounds.*--write-partial" "$tmp/err" &&
        grep -q '^meshcheck: OK' "$tmp/out" && "$BIN/meshcheck" data/lake.poly "$tmp/wp" >/dev/null 2>&1; then
        ok "$prog np=2 -q 45 --write-partial: exit 1, the mesh made written and conforming"
    else
        bad "$prog np=2 -q 45 --write-partial: exit $rc: $(head -c 300 "$tmp/err")"
    fi
done

in=tests/fuzz/regress/holes_1e-161.poly
for prog in pcdm pbw; do
    for np in 2 3; do
        rm -f "$tmp"/m.*
        timeout 120 $MPIRUN -np "$np" "$BIN/$prog" -q 25 --check -o "$tmp/m" "$in" >"$tmp/out" 2>"$tmp/err"
        rc=$?
        if [ $rc -ne 0 ] || ! grep -q '^meshcheck: OK' "$tmp/out"; then
            bad "$prog np=$np $in: exit $rc: $(grep meshcheck "$tmp/out" | head -c 300) $(head -c 200 "$tmp/err")"
        elif ! "$BIN/meshcheck" -q 25 "$in" "$tmp/m" >"$tmp/mc" 2>&1; then
            bad "$prog np=$np $in: written files fail ./meshcheck: $(head -c 300 "$tmp/mc")"
        else
            ok "$prog np=$np $in: --check OK, files OK"
        fi
    done
done
echo "t_par_bounds: $fail failure(s)"
[ "$fail" -eq 0 ]
