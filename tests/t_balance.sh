#!/usr/bin/env bash
# t_balance: ./pcdm --balance dynamic (issue 16 item 2; mesher/pcdm/pcdm_move.c): idle ranks take
# unstarted subdomains from busy ones, and the mesh does not change.
#  1. usage: --balance takes static or dynamic (anything else: exit 2); without --subdomains,
#     dynamic makes 4 subdomains per rank;
#  2. --imbalance 6 (rank 0 gets six shares, so the others run dry and steal) at 2, 4 and 8
#     ranks under --perturb seeds: every run passes --check, its hash equals the static
#     --deterministic run's at the same rank count (same decomposition), and subdomains moved;
#  3. balanced, --subdomains 16: the dynamic runs at 1, 3 and 8 ranks (perturbed) give the
#     hash of the static deterministic run at 1 rank (one mesh for any rank count);
#  4. lists that arrive while and after their subdomain moves: with PCDM_TEST_HOME_ROUTE=1 every
#     round list for a subdomain goes to its home rank, which forwards it to where the subdomain
#     went; the runs must forward some (forwarded= of --stats), lose none (pcdm_move.c checks
#     after every run that every split listed was delivered and applied, else it aborts) and
#     give the same hash and a passing --check;
#  5. --size reaches every subdomain's mesh (the deterministic mode ignored it before).
# Env: BIN (directory of the programs, default .), MPIRUN (default "mpirun --oversubscribe").
# One line per case; exit status 1 if any case failed.
. "$(dirname "$0")/lib.sh"
DOM=data/lake.poly
BOUNDS="-q 30 -a 1e-4" # about 35K triangles, several rounds

# run NP FLAGS...: sets out, st, h (hash), mig (migrations), fwd (forwarded); 1 if the run
# failed or its check did not pass
run() {
    local np=$1
    shift
    out=$(mpi_run "$np" "$BIN/pcdm" -NEP --stats --check "$@" 2>&1)
    st=$?
    local s
    s=$(printf '%s\n' "$out" | grep '^stats:')
    h=$(printf '%s\n' "$s" | field hash)
    mig=$(printf '%s\n' "$s" | field migrations)
    fwd=$(printf '%s\n' "$s" | field forwarded)
    if [ $st -ne 0 ] || ! printf '%s\n' "$out" | grep -q 'check: OK' || [ -z "$h" ]; then
        printf '%s\n' "$out" | tail -5 | sed 's/^/    /'
        return 1
    fi
    return 0
}

# 1. usage
out=$(TIMEOUT=60 mpi_run 1 "$BIN/pcdm" --balance sometimes $DOM 2>&1)
st=$?
if [ $st -eq 2 ] && printf '%s\n' "$out" | grep -q "static|dynamic"; then
    ok "--balance sometimes: exit 2, names static|dynamic"
else
    fail "--balance sometimes: exit $st: $out"
fi
# shellcheck disable=SC2086
if run 2 --balance dynamic $BOUNDS $DOM; then
    k=$(printf '%s\n' "$out" | grep '^stats:' | field subdomains)
    # the default count in rounds is fixed (16), whatever the ranks and the balancing
    if [ "$k" = 16 ]; then ok "--balance dynamic at 2 ranks: 16 subdomains by default"; else
        fail "--balance dynamic at 2 ranks: $k subdomains (want 16)"
    fi
else
    fail "--balance dynamic at 2 ranks: exit $st"
fi

# 2. imbalanced: migrations happen and change nothing
moved=0
for r in 2:0 2:7 4:3 8:0 8:11; do
    np=${r%%:*} seed=${r##*:}
    # shellcheck disable=SC2086
    if ! run "$np" --deterministic --subdomains 16 --imbalance 6 $BOUNDS $DOM; then
        fail "static np=$np --imbalance 6: exit $st, no passing check or hash"
        continue
    fi
    ref=$h
    # shellcheck disable=SC2086
    if ! run "$np" --balance dynamic --subdomains 16 --imbalance 6 --perturb "$seed" $BOUNDS $DOM; then
        fail "dynamic np=$np --imbalance 6 --perturb $seed: exit $st, no passing check or hash"
        continue
    fi
    moved=$((moved + ${mig:-0}))
    if [ "$h" = "$ref" ]; then
        ok "np=$np --imbalance 6 --perturb $seed: $mig migrations, hash $h as static, check OK"
    else
        fail "np=$np --imbalance 6 --perturb $seed: hash $h, static $ref ($mig migrations)"
    fi
done
if [ "$moved" -gt 0 ]; then ok "$moved subdomains moved in the imbalanced runs"; else
    fail "no subdomain moved in the imbalanced runs: balancing not exercised"
fi

# 3. balanced: one mesh for any rank count, with or without balancing
# shellcheck disable=SC2086
if run 1 --deterministic --subdomains 16 $BOUNDS $DOM; then
    ref=$h
    hs=""
    for r in 1:0 3:5 8:9; do
        np=${r%%:*} seed=${r##*:}
        # shellcheck disable=SC2086
        if run "$np" --balance dynamic --subdomains 16 --perturb "$seed" $BOUNDS $DOM; then
            hs="$hs $np:$h"
            [ "$h" = "$ref" ] || fail "balanced dynamic np=$np perturb=$seed: hash $h, want $ref"
        else
            fail "balanced dynamic np=$np perturb=$seed: exit $st, no passing check or hash"
        fi
    done
    ok "balanced --subdomains 16: dynamic at ranks:hash$hs (reference $ref at 1 rank static)"
else
    fail "static deterministic at 1 rank: exit $st"
fi

# 4. lists follow their subdomain (forwarded by its home rank) and none is lost
fwdsum=0
for r in 2:0 4:13 8:0; do
    np=${r%%:*} seed=${r##*:}
    # shellcheck disable=SC2086
    run "$np" --deterministic --subdomains 16 --imbalance 6 $BOUNDS $DOM || {
        fail "static np=$np: exit $st"
        continue
    }
    ref=$h
    # shellcheck disable=SC2086
    if ! PCDM_TEST_HOME_ROUTE=1 run "$np" --balance dynamic --subdomains 16 --imbalance 6 \
        --perturb "$seed" $BOUNDS $DOM; then
        fail "home-routed np=$np perturb=$seed: exit $st, no passing check or hash"
        continue
    fi
    fwdsum=$((fwdsum + ${fwd:-0}))
    if [ "$h" = "$ref" ]; then
        ok "home-routed np=$np perturb=$seed: $mig migrations, $fwd lists forwarded, same hash"
    else
        fail "home-routed np=$np perturb=$seed: hash $h, static $ref"
    fi
done
if [ "$fwdsum" -gt 0 ]; then ok "$fwdsum round lists reached a moved subdomain by forwarding"; else
    fail "no list was forwarded: the forwarding path is not exercised"
fi
# 5. a size rule (--size) reaches every subdomain's mesh, also one that moved: more triangles than
#    without it, the same mesh with and without balancing
printf '4 2 1 0\n1 0 0 0.02\n2 1 0 0.5\n3 1 1 0.5\n4 0 1 0.5\n' >"$T/bg.node"
printf '2 3 0\n1 1 2 3\n2 1 3 4\n' >"$T/bg.ele"
if run 2 --deterministic --subdomains 8 -q 20 data/square.poly; then
    n0=$(printf '%s\n' "$out" | grep '^stats:' | field triangles)
    if run 2 --deterministic --subdomains 8 -q 20 --size "$T/bg" data/square.poly; then
        n1=$(printf '%s\n' "$out" | grep '^stats:' | field triangles) ref=$h
        if run 4 --balance dynamic --subdomains 8 -q 20 --size "$T/bg" data/square.poly &&
            [ "$h" = "$ref" ] && [ "$n1" -gt "$n0" ]; then
            ok "--size: $n1 triangles (without: $n0), the same mesh with --balance dynamic"
        else
            fail "--size: $n1 triangles (without: $n0), hash $h with balancing, $ref without"
        fi
    else
        fail "--deterministic --size: exit $st"
    fi
else
    fail "--deterministic square: exit $st"
fi
finish
