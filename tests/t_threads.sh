#!/usr/bin/env bash
# ./pcdm --threads T: subdomain rounds on T worker threads per rank (the runtime's threaded
# handlers).  The mesh is the one of refinement in rounds (the default), so for a given input,
# bounds and --subdomains every (ranks, threads) gives the same hash as one rank on one thread,
# and every mesh passes --check:
#   - the six domains of data/ at -q 20.7, 30 and 33, 8 subdomains, (ranks, threads) in (1,1)
#     (1,2) (2,1) (2,2) (4,2) (8,1), plus, at -q 30 on three of them, (2,2) with --balance
#     dynamic, (3,2) under --perturb and (2,1) with --deterministic (accepted, the default);
#   - without --subdomains (its default is fixed), lake and square (4 subdomains at
#     -a 0.005) at 5 settings: one hash;
#   - one process without mpirun (./pcdm --threads 2 as a plain program) gives the same hash;
#   - --threads 0 and a non-number are refused with a message, exit 2 (a usage error), and so
#     is --async (the asynchronous protocol, one thread) with --threads 2.
# SANITIZE=1: lake, holes and square at -q 30 and 33.  THREADS_QUICK=1 (the ThreadSanitizer
# build): lake at -q 30 only, (1,1) (1,2) (2,2), (1,2) under --perturb, (2,2) with --balance
# dynamic.
. "$(dirname "$0")/lib.sh"

hash_of() { grep -o 'hash=[0-9a-f]*' "$1" | tail -1; }

doms="lake holes square channel lshape wedge" bounds="20.7 30 33"
[ "${SANITIZE:-}" = 1 ] && doms="lake holes square" bounds="30 33" # the ASan build: slower
[ "${THREADS_QUICK:-}" = 1 ] && doms=lake bounds=30
for d in $doms; do
    f=data/$d.poly
    for q in $bounds; do
        want=""
        cfgs=("1 1" "1 2" "2 1" "2 2" "4 2" "8 1")
        case $d/$q in lake/30 | holes/30 | square/30)
            cfgs+=("2 2 --balance dynamic" "3 2 --perturb 5" "2 1 --deterministic") ;;
        esac
        [ "${THREADS_QUICK:-}" = 1 ] && cfgs=("1 1" "1 2" "2 2" "1 2 --perturb 5" "2 2 --balance dynamic")
        for cfg in "${cfgs[@]}"; do
            set -- $cfg
            np=$1 th=$2
            shift 2
            mpi_run "$np" "$BIN/pcdm" --threads "$th" --subdomains 8 -q "$q" -a 2e-5 -NEP --stats \
                --check "$@" "$f" >"$T/out.txt" 2>&1
            rc=$?
            if [ "$rc" != 0 ] || ! grep -q '^meshcheck: OK' "$T/out.txt"; then
                fail "$f -q $q ranks $np threads $th $*: exit $rc: $(grep -m1 'pcdm:' "$T/out.txt")"
                continue
            fi
            h=$(hash_of "$T/out.txt")
            [ -n "$want" ] || want=$h
            if [ "$h" = "$want" ]; then
                ok "$f -q $q ranks $np threads $th $*: $h"
            else
                fail "$f -q $q ranks $np threads $th $*: $h, (1,1) gave $want"
            fi
        done
    done
done

# the default --subdomains is fixed (16, halved where the coarse mesh is small): the same hash
# for any ranks x threads and balancing without giving it (square at -q 30 -a 0.005: a final
# mesh of about 320 triangles, halved to 4 subdomains, so at most 4 ranks)
for spec in "data/lake.poly 30 2e-5" "data/square.poly 30 0.005"; do
    read -r f q a <<<"$spec"
    cfgs=("1 1" "2 2" "4 2" "8 1" "2 1 --balance dynamic")
    [ "$a" = 0.005 ] && cfgs=("1 1" "1 2" "2 2" "4 1" "2 1 --balance dynamic")
    want=""
    for cfg in "${cfgs[@]}"; do
        set -- $cfg
        np=$1 th=$2
        shift 2
        mpi_run "$np" "$BIN/pcdm" --threads "$th" -q "$q" -a "$a" -NEP --stats --check "$@" "$f" \
            >"$T/out.txt" 2>&1
        rc=$?
        h=$(hash_of "$T/out.txt")
        [ -n "$want" ] || want=$h
        if [ "$rc" = 0 ] && grep -q '^meshcheck: OK' "$T/out.txt" && [ "$h" = "$want" ]; then
            ok "$f -q $q -a $a default subdomains, ranks $np threads $th $*: $h"
        else
            fail "$f -q $q -a $a default subdomains, ranks $np threads $th $*: exit $rc, $h against $want"
        fi
    done
done

# one process, no mpirun
f=data/lake.poly
mpi_run 1 "$BIN/pcdm" --subdomains 8 -q 30 -a 2e-5 -NEP --stats "$f" >"$T/a.txt" 2>&1
timeout 120 "$BIN/pcdm" --threads 2 --subdomains 8 -q 30 -a 2e-5 -NEP --stats --check "$f" \
    >"$T/b.txt" 2>&1
rc=$?
if [ "$rc" = 0 ] && grep -q '^meshcheck: OK' "$T/b.txt" &&
    [ "$(hash_of "$T/a.txt")" = "$(hash_of "$T/b.txt")" ] && [ -n "$(hash_of "$T/b.txt")" ]; then
    ok "./pcdm --threads 2 without mpirun: $(hash_of "$T/b.txt"), as mpirun -np 1"
else
    fail "./pcdm --threads 2 without mpirun: exit $rc, $(hash_of "$T/b.txt") against $(hash_of "$T/a.txt")"
fi

for bad in 0 x -1; do
    timeout 60 "$BIN/pcdm" --threads "$bad" -NEP data/square.poly >"$T/e.txt" 2>&1
    rc=$?
    if [ "$rc" = 2 ] && grep -q -- '--threads' "$T/e.txt"; then
        ok "--threads $bad refused: $(head -1 "$T/e.txt")"
    else
        fail "--threads $bad: exit $rc: $(head -1 "$T/e.txt")"
    fi
done
timeout 60 "$BIN/pcdm" --async --threads 2 -NEP data/square.poly >"$T/e.txt" 2>&1
rc=$?
if [ "$rc" = 2 ] && grep -q -- '--async.*not with --threads above 1' "$T/e.txt"; then
    ok "--async --threads 2 refused: $(head -1 "$T/e.txt")"
else
    fail "--async --threads 2: exit $rc: $(head -1 "$T/e.txt")"
fi
finish
