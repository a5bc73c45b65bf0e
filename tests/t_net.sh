#!/usr/bin/env bash
# The network model (--net / PCDM_NET, runtime/rt_net.c) in both parallel meshers: with the
# SP2's figures (--net sp2) and with a slow network from the environment, ./pcdm and ./pbw on
# 2 and 3 ranks make meshes the validator accepts (--check), and their stats line reports the
# model in force (net_latency_us, net_MBps) and the runtime's communication time (comm_s);
# a malformed --net is a usage error (exit 2) on every rank.  Delivery times themselves are
# checked by tests/mpi_rt_net.c.
set -u
cd "$(dirname "$0")/.."
BIN=${BIN:-.}
MPIRUN=${MPIRUN:-mpirun --oversubscribe}
fail() { echo "t_net: FAILED: $*"; exit 1; }
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
for prog in pcdm pbw; do
    for np in 2 3; do
        for how in "--net sp2" "env 200,5"; do
            if [ "$how" = "--net sp2" ]; then
                timeout 120 $MPIRUN -np $np "$BIN/$prog" -NEP -q 25 -a 0.0004 --check --stats --net sp2 data/lake.poly >"$tmp" 2>&1
                rc=$?; lat=29.0; bw=33.6
            else
                PCDM_NET=200,5 timeout 120 $MPIRUN -np $np -x PCDM_NET "$BIN/$prog" -NEP -q 25 -a 0.0004 --check --stats data/lake.poly >"$tmp" 2>&1
                rc=$?; lat=200.0; bw=5.0
            fi
            [ "$rc" = 0 ] || { cat "$tmp"; fail "$prog np=$np $how: exit $rc"; }
            grep -q "^meshcheck: OK" "$tmp" ||
                { cat "$tmp"; fail "$prog np=$np $how: no meshcheck line"; }
            sl=$(grep '^stats:' "$tmp" | tail -1)
            grep -q " net_latency_us=$lat net_MBps=$bw" <<<"$sl" || fail "$prog np=$np $how: model not reported: $sl"
            grep -Eq ' comm_s=[0-9.]+ comm_max_s=[0-9.]+ handler_s=[0-9.]+' <<<"$sl" || fail "$prog np=$np $how: no comm_s: $sl"
            echo "ok $prog np=$np $how: $(grep -o 'rsr=[0-9]*' <<<"$sl") $(grep -o 'comm_s=[0-9.]*' <<<"$sl")"
        done
    done
    timeout 60 $MPIRUN -np 2 "$BIN/$prog" --net 5,x data/lake.poly >"$tmp" 2>&1
    rc=$?
    [ "$rc" = 2 ] || { cat "$tmp"; fail "$prog --net 5,x: exit $rc, want 2"; }
    grep -q -- "--net '5,x'" "$tmp" || fail "$prog --net 5,x: no message"
done
echo "t_net: ok"
