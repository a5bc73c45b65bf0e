#!/usr/bin/env bash
# ./pbw end to end (the Parallel Meshing Algorithm, parallel Bowyer-Watson with remote cavity
# expansion, locks and undo): every domain in data/ at 1, 2, 4 and 8 ranks and -q 20.7, every
# domain at 8 ranks and -q 30, perturbed delivery (seeds 1 2 3) at 8 ranks on two domains,
# --phases, bad input and usage.  Each run must exit 0, pass ./pbw --check and ./meshcheck with
# the same bounds and with every non-input edge locally Delaunay (--interfaces-delaunay: the
# merged mesh of one distributed Delaunay mesh has no artificial constraints), end with the
# stats line, and have within 3% of ./mesh's triangle count.  Env: BIN (programs; "." or
# build/san/bin), MPIRUN ("mpirun --oversubscribe"), SANITIZE=1 (fewer runs).
set -u
cd "$(dirname "$0")/.."
BIN=${BIN:-.}
MPIRUN=${MPIRUN:-mpirun --oversubscribe}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
T=$(mktemp -d "${TMPDIR:-/tmp}/t_pbw.XXXXXX")
trap 'rm -rf "$T"' EXIT
fail() {
    echo "FAIL: $*"
    exit 1
}

# -a per domain: about 6-8K triangles (sanitizer build: about half)
declare -A AREA=([square]=0.0002 [lshape]=0.0006 [wedge]=0.00002 [lake]=0.0005 [holes]=0.0002
    [channel]=0.0004)
DOMAINS="square lshape wedge lake holes channel"
NPS="1 2 4 8"
SEEDS="1 2 3"
PERT_DOMAINS="square holes"
if [ "${SANITIZE:-}" = 1 ]; then
    # Same sizes as the normal run: below ~5K triangles the 3% count comparison is noise.
    DOMAINS="square wedge holes"
    NPS="1 4 8"
    SEEDS="1"
    PERT_DOMAINS="lake"
fi

declare -A SEQ
seq_count() { # domain q -> ./mesh's triangle count (cached)
    local k="$1/$2"
    if [ -z "${SEQ[$k]:-}" ]; then
        SEQ[$k]=$("$BIN/mesh" -q "$2" -a "${AREA[$1]}" --stats "data/$1.poly" |
            sed -n 's/^stats: triangles=\([0-9]*\).*/\1/p')
        [ -n "${SEQ[$k]}" ] || fail "./mesh gave no triangle count for $1"
    fi
    echo "${SEQ[$k]}"
}

n=0
run() { # np domain q extra-args...
    local np=$1 d=$2 q=$3
    shift 3
    local a=${AREA[$d]} pre="$T/m$n" out rc
    n=$((n + 1))
    out=$(timeout 120 $MPIRUN -np "$np" "$BIN/pbw" -q "$q" -a "$a" -o "$pre" --check --stats \
        "$@" "data/$d.poly" 2>&1)
    rc=$?
    local last
    last=$(tail -n 1 <<<"$out")
    echo "np=$np $d -q $q $* -> $rc: $last"
    [ "$rc" -eq 0 ] || {
        echo "$out" | tail -n 20
        fail "./pbw exit $rc (np=$np $d -q $q $*)"
    }
    grep -q '^meshcheck: OK' <<<"$out" || fail "--check did not pass (np=$np $d $*)"
    grep -Eq '^stats: ranks=[0-9]+ triangles=[0-9]+ vertices=[0-9]+ rsr=[0-9]+ undone=[0-9]+ min_angle=[0-9.]+ wall_s=[0-9.]+ busy_max_s=[0-9.]+ busy_sum_s=[0-9.]+ comm_pct=[0-9.]+ undo_pct=[0-9.]+' <<<"$last" ||
        fail "last line is not the stats line: $last"
    grep -q "^stats: ranks=$np " <<<"$last" || fail "stats line names the wrong rank count"
    grep -Eq '^rsr: expansion=[0-9]+ reply=[0-9]+ release=[0-9]+ commit=[0-9]+ split=[0-9]+' \
        <<<"$out" || fail "no RSR breakdown line"
    if [ "$np" = 1 ]; then grep -q ' rsr=0 ' <<<"$last" || fail "RSRs on one rank: $last"; fi
    local mc
    mc=$("$BIN/meshcheck" "data/$d.poly" "$pre" -q "$q" -a "$a" --interfaces-delaunay 2>&1) ||
        fail "meshcheck: $mc (np=$np $d -q $q $*)"
    local got want
    got=$(sed -n 's/^stats: ranks=[0-9]* triangles=\([0-9]*\).*/\1/p' <<<"$last")
    want=$(seq_count "$d" "$q")
    awk -v g="$got" -v w="$want" 'BEGIN { d = g - w; if (d < 0) d = -d; exit !(d <= 0.03 * w) }' ||
        fail "triangle count $got vs ./mesh $want (more than 3% apart; np=$np $d -q $q $*)"
}

# every domain, 1 2 4 8 ranks, -q 20.7
for d in $DOMAINS; do
    for np in $NPS; do run "$np" "$d" 20.7; done
done
# -q 30 at 8 ranks
for d in $DOMAINS; do run 8 "$d" 30; done
# perturbed delivery (delays and reorders RSRs between sources), several seeds, 8 ranks
for d in $PERT_DOMAINS; do
    for s in $SEEDS; do run 8 "$d" 20.7 --perturb "$s"; done
done
run 8 lshape 30 --perturb 7
# the data-parallel variant: local cavities first, then the rest
run 4 lake 20.7 --phases
run 8 channel 20.7 --phases --perturb 2
# imbalanced decomposition
run 4 holes 20.7 --imbalance 2

# bad input and impossible requests: one clear message, non-zero exit from every rank
out=$(timeout 60 $MPIRUN -np 4 "$BIN/pbw" tests/bad/self_intersecting.poly 2>&1)
rc=$?
echo "bad input -> $rc: $(head -n 1 <<<"$out")"
[ "$rc" -ne 0 ] || fail "bad input accepted"
grep -q 'self_intersecting.poly:11: segment 4 crosses segment 2' <<<"$out" ||
    fail "bad input message missing: $out"
out=$(timeout 60 $MPIRUN -np 2 "$BIN/pbw" "$T/nosuch.poly" 2>&1)
rc=$?
[ "$rc" -ne 0 ] || fail "missing input accepted"
grep -q 'nosuch.poly' <<<"$out" || fail "missing-file message does not name the file: $out"
out=$(timeout 60 $MPIRUN -np 2 "$BIN/pbw" -q abc data/square.poly 2>&1)
rc=$?
[ "$rc" -ne 0 ] || fail "bad -q accepted"
out=$(timeout 60 $MPIRUN -np 1 "$BIN/pbw" --help 2>&1)
rc=$?
[ "$rc" -eq 0 ] || fail "--help exit $rc"
grep -q 'pbw' <<<"$out" || fail "--help does not name the program"
echo "t_pbw: all $n runs passed"
