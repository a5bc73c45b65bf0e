#!/usr/bin/env bash
# t_pout: the parallel meshers' end without a gather (mesher/par/pout.h), end to end.
#  1. ./pcdm and ./pbw at 1, 2, 4 and 8 ranks with -o, --vtk and --check: the distributed check
#     prints "meshcheck: OK", every rank exits 0, the files (written by MPI-IO from every rank's
#     part) pass ./meshcheck, and the .pvtu index names one .vtu piece per rank;
#  2. a broken part (test-only fault PCDM_TEST_BREAK_PIECE=R: rank R reverses a triangle) makes
#     --check fail with exit status 1 on every rank, and nothing is written.
# (The numbering itself, and files written by 1-8 ranks being equal as sets of exact
# coordinates, are tested by tests/mpi_pout.c.)  Env: BIN, MPIRUN as the other tests.
set -u
cd "$(dirname "$0")/.."
BIN=${BIN:-.}
MPIRUN=${MPIRUN:-mpirun --oversubscribe}
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
T=$(mktemp -d "${TMPDIR:-/tmp}/t_pout.XXXXXX")
trap 'rm -rf "$T"' EXIT
pass=0 nfail=0
ok() { pass=$((pass + 1)); printf 'ok   %s\n' "$*"; }
fail() { nfail=$((nfail + 1)); printf 'FAIL %s\n' "$*"; }

# runp PROG NP ARGS...: every rank writes its exit status to $T/rc.RANK; sets rcs (the statuses,
# rank order, space separated) and out/err files
runp() {
    local prog=$1 np=$2
    shift 2
    rm -f "$T"/rc.*
    timeout 120 $MPIRUN -np "$np" sh -c \
        '"$0" "$@"; echo $? >"'"$T"'/rc.${OMPI_COMM_WORLD_RANK:-${PMIX_RANK:-x}}"' \
        "$BIN/$prog" "$@" >"$T/out" 2>"$T/err"
    local r
    rcs=""
    for ((r = 0; r < np; r++)); do rcs="$rcs $(cat "$T/rc.$r" 2>/dev/null || echo none)"; done
    rcs=${rcs# }
}
all() { # NP STATUS: the string of NP copies of STATUS
    local s="" r
    for ((r = 0; r < $1; r++)); do s="$s $2"; done
    echo "${s# }"
}

A=0.001
for prog in pcdm pbw; do
    for np in 1 2 4 8; do
        p="$T/$prog$np"
        runp "$prog" "$np" -q 30 -a $A --check -o "$p" --vtk "$p.vtk" data/lake.poly
        name="$prog np=$np"
        if [ "$rcs" != "$(all "$np" 0)" ]; then
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
    PCDM_TEST_BREAK_PIECE=2 runp "$prog" $np -q 30 -a $A --check -o "$T/broken" data/lake.poly
    name="$prog np=$np broken part"
    [ "$rcs" = "$(all $np 1)" ] && ok "$name: every rank exits 1" ||
        fail "$name: exit statuses $rcs, want $(all $np 1)"
    grep -q '^meshcheck: FAIL rank 2: ' "$T/out" && ok "$name: $(grep '^meshcheck' "$T/out" | cut -c1-70)" ||
        fail "$name: no FAIL line naming rank 2: $(head -2 "$T/out")"
    [ ! -e "$T/broken.node" ] && ok "$name: nothing written" || fail "$name: files written"
done

echo "$pass passed, $nfail failed"
[ "$nfail" -eq 0 ]
