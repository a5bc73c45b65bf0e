#!/usr/bin/env bash
# replay_par.sh [CORPUS_DIR...]: replays a fuzz corpus (files of tests/fuzz/fuzz_mesh.c's form:
# one option byte, then a .poly, or a .node when bit 7 is set) through ./mesh and then through
# the parallel programs, ./pcdm at PCDM_NP ranks (default 3) and ./pbw at PBW_NP ranks (default
# 2), each rank's exit status recorded.  ./mesh's answer is the reference:
#   - refused (exit 1, not "cannot meet the bounds"): every rank must exit 1;
#   - meshed (exit 0): exit 0 with --check OK on every rank, or exit 1 on every rank with
#     "cannot decompose" or "cannot meet the bounds" (a cut through a region ./mesh resolves
#     only through the shells of one far corner), or 3 (the Steiner limit);
#   - "cannot meet the bounds" or the Steiner limit (exit 3): any of 0 (with --check OK), 1
#     with "cannot meet the bounds", 3.
# Always a failure: a timeout, a crash or any other exit status, ranks that disagree, exit 0
# without --check OK.  Inputs ./mesh does not finish in TIMEOUT seconds are skipped.  Failing
# inputs are copied (with a line naming the command) into OUT (default build/fuzz/replay_fail).
# The angle bound comes from the option byte as in fuzz_mesh.c; the Steiner limit is LIMIT
# (default 20000, the harness's).  Not part of make test: run it by hand after a campaign
# (make fuzz-replay).  Env: BIN, MPIRUN, TIMEOUT (default 30), PAR_TIMEOUT (default 120).
. "$(dirname "$0")/../lib.sh"
TIMEOUT=${TIMEOUT:-30} PAR_TIMEOUT=${PAR_TIMEOUT:-120} LIMIT=${LIMIT:-20000}
PCDM_NP=${PCDM_NP:-3} PBW_NP=${PBW_NP:-2}
OUT=${OUT:-build/fuzz/replay_fail}
mkdir -p "$OUT"
QS=(0 20.7 25 30 33 20.7 25 28.6)
[ $# -gt 0 ] || set -- build/fuzz/corpus
n=0 skipped=0 nfail=0
declare -A seen=()

fail() { # file program np message
    nfail=$((nfail + 1))
    echo "FAIL: $1: $2 -np $3: $4"
    cp "$1" "$OUT/" && echo "$2 -np $3 -q $q: $4" >"$OUT/$(basename "$1").why"
}

par() { # program np kind file...: runs it, each rank appending "RANK STATUS"; judges the result
    local prog=$1 np=$2 kind=$3 src=$4 out rc st
    out=$(TIMEOUT=$PAR_TIMEOUT mpi_run "$np" "$BIN/$prog" -NEP -q "$q" -S "$LIMIT" --check "$in" \
        2>&1 </dev/null)
    rc=$?
    if [ "$rc" = 124 ]; then
        fail "$src" "$prog" "$np" "timeout (${PAR_TIMEOUT} s)"
        return
    fi
    if grep -qw none "$T/rcs"; then
        fail "$src" "$prog" "$np" "not every rank ended: $(grep -m2 -v '^ ' <<<"$out")"
        return
    fi
    st=$(tr ' ' '\n' <"$T/rcs" | sort -u | tr '\n' ' ')
    case "$kind/$st" in
    */"0 ")
        grep -q '^meshcheck: OK' <<<"$out" || fail "$src" "$prog" "$np" "exit 0 without --check OK"
        [ "$kind" != refused ] || fail "$src" "$prog" "$np" "./mesh refuses the input, exit 0"
        ;;
    refused/"1 ") ;;
    meshed/"1 " | unmet/"1 ")
        grep -Eq 'cannot (meet the bounds|decompose)' <<<"$out" ||
            fail "$src" "$prog" "$np" "exit 1 ($kind by ./mesh): $(grep -m2 -v '^ ' <<<"$out")"
        ;;
    meshed/"3 " | unmet/"3 ") ;;
    *) fail "$src" "$prog" "$np" "exit [$st] ($kind by ./mesh): $(grep -m3 -v '^ ' <<<"$out" | cut -c1-200)" ;;
    esac
}

for dir in "$@"; do
    for f in "$dir"/*; do
        [ -f "$f" ] || continue
        sum=$(sha1sum <"$f" | cut -c1-40)
        [ -z "${seen[$sum]:-}" ] || continue
        seen[$sum]=1
        opt=$(od -An -tu1 -N1 "$f" | tr -d ' ')
        [ -n "$opt" ] || continue
        q=${QS[$((opt & 7))]}
        if [ $((opt & 128)) -ne 0 ]; then in="$T/in.node"; else in="$T/in.poly"; fi
        rm -f "$T"/in.*
        tail -c +2 "$f" >"$in"
        out=$(timeout "$TIMEOUT" "$BIN/mesh" -NEP -q "$q" -S "$LIMIT" "$in" 2>&1 </dev/null)
        rc=$?
        case "$rc" in
        0) kind=meshed ;;
        3) kind=unmet ;;
        1) if grep -q 'cannot meet the bounds' <<<"$out"; then kind=unmet; else kind=refused; fi ;;
        *)
            skipped=$((skipped + 1))
            continue
            ;; # a timeout (or a ./mesh failure: the fuzzer's job)
        esac
        n=$((n + 1))
        par pcdm "$PCDM_NP" "$kind" "$f"
        par pbw "$PBW_NP" "$kind" "$f"
        [ $((n % 100)) -ne 0 ] || echo "replay_par: $n inputs, $nfail failure(s)"
    done
done
echo "replay_par: $n inputs through ./pcdm -np $PCDM_NP and ./pbw -np $PBW_NP, $skipped skipped (./mesh over ${TIMEOUT} s), $nfail failure(s) (inputs in $OUT)"
[ "$nfail" -eq 0 ]
