#!/usr/bin/env bash
# The network model (--net / PCDM_NET, runtime/rt_net.c) in both parallel meshers: with the
# SP2's figures (--net sp2) and with a slow network from the environment, ./pcdm and ./pbw on
# 2 and 3 ranks make meshes the validator accepts (--check), and their stats line reports the
# model in force (net_latency_us, net_MBps) and the runtime's communication time (comm_s);
# a malformed --net is a usage error (exit 2) on every rank.  Delivery times themselves are
# checked by tests/mpi_rt_net.c.
. "$(dirname "$0")/lib.sh"
out=$T/out
for prog in pcdm pbw; do
    for np in 2 3; do
        for how in "--net sp2" "env 200,5"; do
            what="$prog np=$np $how"
            if [ "$how" = "--net sp2" ]; then
                mpi_run $np "$BIN/$prog" -NEP -q 25 -a 0.0004 --check --stats --net sp2 \
                    data/lake.poly >"$out" 2>&1
                rc=$? lat=29.0 bw=33.6
            else
                PCDM_NET=200,5 MPI_X="-x PCDM_NET" mpi_run $np "$BIN/$prog" -NEP -q 25 -a 0.0004 \
                    --check --stats data/lake.poly >"$out" 2>&1
                rc=$? lat=200.0 bw=5.0
            fi
            if [ "$rc" != 0 ]; then
                cat "$out"
                fail "$what: exit $rc (ranks: $rcs)"
                continue
            fi
            if ! grep -q "^meshcheck: OK" "$out"; then
                cat "$out"
                fail "$what: no meshcheck line"
                continue
            fi
            sl=$(grep '^stats:' "$out" | tail -1)
            if ! grep -q " net_latency_us=$lat net_MBps=$bw" <<<"$sl"; then
                fail "$what: model not reported: $sl"
            elif ! grep -Eq ' comm_s=[0-9.]+ comm_max_s=[0-9.]+ handler_s=[0-9.]+' <<<"$sl"; then
                fail "$what: no comm_s: $sl"
            else
                ok "$what: $(grep -o 'rsr=[0-9]*' <<<"$sl") $(grep -o 'comm_s=[0-9.]*' <<<"$sl")"
            fi
        done
    done
    TIMEOUT=60 mpi_run 2 "$BIN/$prog" --net 5,x data/lake.poly >"$out" 2>&1
    rc=$?
    if [ "$rc" != 2 ]; then
        cat "$out"
        fail "$prog --net 5,x: exit $rc (ranks: $rcs), want 2 on every rank"
    elif ! grep -q -- "--net '5,x'" "$out"; then
        fail "$prog --net 5,x: no message"
    else
        ok "$prog --net 5,x: exit 2 on every rank, named"
    fi
done
finish
