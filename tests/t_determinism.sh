#!/usr/bin/env bash
# t_determinism: ./pcdm --deterministic gives the same mesh, bit for bit, for any rank count and
# any message timing (issue 16).
#  1. for several domains (bounds chosen so the decomposition is not the exact preview and the
#     subdomains exchange interface splits), --subdomains 8 at 1, 2, 3, 4 and 8 ranks and under
#     --perturb seeds: every run passes --check, and the mesh hash of --stats is one value;
#     at least one domain needs more than one round (the protocol is exercised);
#     and 16 subdomains at up to 16 ranks;
#  2. -S (the Steiner budget, split among the subdomains) and --poll 1 do not change the mesh;
#  3. a measurement, not a test: the asynchronous mode's hashes for the same runs (how many
#     distinct meshes it made), printed as "note" lines.
# Env: BIN (directory of the programs, default .), MPIRUN (default "mpirun --oversubscribe").
# One line per case; exit status 1 if any case failed.
. "$(dirname "$0")/lib.sh"

# domain -> "-q DEG -a AREA": 10-40K triangles, above the exact preview's 8 x 1000
declare -A BOUNDS=(["data/lake.poly"]="-q 30 -a 1e-4" ["tests/inputs/letter_a.poly"]="-q 30 -a 3e-4"
    ["tests/inputs/map.poly"]="-q 28 -a 2e-4" ["data/wedge.poly"]="-q 25 -a 1e-5")
# ranks:perturb seed (0: off); the asynchronous mode's measurement on fewer runs
RUNS="1:0 2:0 3:0 4:0 8:0 3:11 8:23"
ARUNS="2:0 2:5 4:0 4:7"
maxrounds=0
for dom in data/lake.poly tests/inputs/letter_a.poly tests/inputs/map.poly data/wedge.poly; do
    b=${BOUNDS[$dom]}
    for mode in det async; do
        [ $mode = async ] && [ $dom != data/lake.poly ] && [ $dom != data/wedge.poly ] && continue
        hashes="" allok=1 runs=$RUNS
        [ $mode = async ] && runs=$ARUNS
        for r in $runs; do
            np=${r%%:*} seed=${r##*:}
            flags="--subdomains 8 --perturb $seed --stats"
            if [ $mode = det ]; then flags="$flags --deterministic --check"; fi
            # shellcheck disable=SC2086
            out=$(mpi_run "$np" "$BIN/pcdm" -NEP $flags $b "$dom" 2>&1)
            st=$?
            h=$(printf '%s\n' "$out" | grep '^stats:' | field hash)
            if [ $mode = det ]; then
                if [ $st -ne 0 ] || ! printf '%s\n' "$out" | grep -q 'check: OK' || [ -z "$h" ]; then
                    fail "$dom $b np=$np perturb=$seed: exit $st, no passing check or hash"
                    printf '%s\n' "$out" | tail -5 | sed 's/^/    /'
                    allok=0
                    continue
                fi
                rounds=$(printf '%s\n' "$out" | grep '^stats:' | field rounds)
                [ "${rounds:-0}" -gt $maxrounds ] && maxrounds=$rounds
            fi
            hashes="$hashes $h"
        done
        n=$(printf '%s\n' $hashes | sort -u | wc -l)
        if [ $mode = async ]; then
            echo "note $dom $b asynchronous mode: $n distinct meshes in runs (ranks:seed) $ARUNS"
        elif [ $allok = 1 ] && [ "$n" -eq 1 ]; then
            ok "$dom $b: one hash $(printf "%s\n" $hashes | head -1) at ranks:seeds $RUNS, check OK"
        elif [ $allok = 1 ]; then
            fail "$dom $b: $n different hashes:$hashes"
        fi
    done
done
# 16 subdomains (3 rounds here) at 1, 5, 8 and 16 ranks, perturbed
hs="" allok=1
for r in 1:0 5:3 8:9 16:2; do
    np=${r%%:*} seed=${r##*:}
    out=$(mpi_run "$np" "$BIN/pcdm" -NEP --deterministic --perturb "$seed" \
        --subdomains 16 -q 31 -a 1e-4 --check --stats tests/inputs/map.poly 2>&1)
    st=$?
    h=$(printf '%s\n' "$out" | grep '^stats:' | field hash)
    if [ $st -ne 0 ] || ! printf '%s\n' "$out" | grep -q 'check: OK' || [ -z "$h" ]; then
        fail "map --subdomains 16 np=$np perturb=$seed: exit $st, no passing check or hash"
        allok=0
    fi
    rounds=$(printf '%s\n' "$out" | grep '^stats:' | field rounds)
    [ "${rounds:-0}" -gt $maxrounds ] && maxrounds=$rounds
    hs="$hs $h"
done
n=$(printf '%s\n' $hs | sort -u | wc -l)
if [ $allok = 1 ] && [ "$n" -eq 1 ]; then
    ok "map -q 31 -a 1e-4 --subdomains 16: one hash at 1, 5, 8, 16 ranks (perturbed)"
elif [ $allok = 1 ]; then
    fail "map --subdomains 16: $n different hashes:$hs"
fi
# the Steiner budget (-S: split among the subdomains by weight) and the poll interval (--poll 1:
# the kernel stops after every insertion) must not change the mesh either
hs=""
for r in "1 " "3 " "2 --poll 1"; do
    np=${r%% *} extra=${r#* }
    # shellcheck disable=SC2086
    out=$(mpi_run "$np" "$BIN/pcdm" -NEP --deterministic --subdomains 4 -q 30 -a 1e-4 \
        -S 5000 --stats --check $extra data/lake.poly 2>&1)
    st=$?
    h=$(printf '%s\n' "$out" | grep '^stats:' | field hash)
    if [ $st -ne 3 ] || ! printf '%s\n' "$out" | grep -q 'check: OK' || [ -z "$h" ]; then
        fail "-S 5000 np=$np $extra: exit $st (want 3, the limit), no passing check or hash"
    fi
    hs="$hs $h"
done
n=$(printf '%s\n' $hs | sort -u | wc -l)
if [ "$n" -eq 1 ]; then ok "-S 5000 (exit 3) at 1 and 3 ranks and with --poll 1: one hash"; else
    fail "-S 5000 / --poll 1: $n different hashes:$hs"
fi
if [ "$maxrounds" -ge 2 ]; then
    ok "the domains needed up to $maxrounds rounds"
else
    fail "no domain needed a second round (max $maxrounds): the rounds are not exercised"
fi
finish
