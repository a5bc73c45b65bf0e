#!/usr/bin/env bash
# make bench-hosts: the cost of crossing hosts, on hosts made of network namespaces on this
# machine (tests/hosts/lib.sh: veth pairs to a bridge, TCP only; needs root, else skips).
#  1. round trips between h1 and h2, in ROUNDS alternating rounds: a 1-byte message over a plain
#     TCP connection (build/bench/tcp_rtt), the runtime's null RSR and a raw MPI ping-pong (0
#     bytes, blocking MPI_Send/MPI_Recv) in one run of build/bench/rsr_rtt (Open MPI: pml ob1,
#     btl tcp,self), and the null RSR again with the runtime's socket wait off
#     (RT_SOCKET_WAIT=0: the timed idle sleep it uses on one host) and with the growing backoff
#     as the socket wait's timeout (RT_WAIT_LAZY=0, see runtime/rt_wait.c), and the raw MPI
#     ping-pong again with --mca mpi_yield_when_idle 1 (its blocking calls yield the CPU when
#     they find nothing: Open MPI's own floor on a shared machine).  Each figure is the median
#     over the rounds of each run's median trial (and of its best trial);
#  2. the RSR counts of Tables 2 and 3 (./pcdm and ./pbw on DOMAIN at about 43K triangles,
#     -q 20.7, imbalance 1 and 2) at 3 hosts x 1 and 3 hosts x 2 ranks beside the same rank
#     counts on one host (shared memory), REPS runs each, medians.
# Prints the tables and last the summary line
#   bench-hosts: tcp_rtt_us=T rsr_rtt_us=R mpi_rtt_us=M mpi_yield_rtt_us=Y rsr_sleep_rtt_us=S
#                rsr_backoff_rtt_us=K ratio_rsr_tcp=X
# (medians; the goal is ratio_rsr_tcp <= 2).  Env: ROUNDS (default 5), REPS (default 3),
# DOMAIN (data/lake.poly), AREA (default 0.000077, about 43K triangles on the lake), B (build),
# TABLES=0 (round trips only).
set -u
cd "$(dirname "$0")/.."
B=${B:-build}
ROUNDS=${ROUNDS:-5}
REPS=${REPS:-3}
DOMAIN=${DOMAIN:-data/lake.poly}
AREA=${AREA:-0.000077}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
. tests/hosts/lib.sh
if ! why=$(hosts_can); then
    echo "bench-hosts: skipped: $why"
    exit 0
fi
for f in ./pcdm ./pbw "$B/bench/rsr_rtt" "$B/bench/tcp_rtt"; do
    [ -x "$f" ] || { echo "bench-hosts: $f is missing (run make first)"; exit 1; }
done
W=$(mktemp -d "${TMPDIR:-/tmp}/pcdm-bench-hosts.XXXXXX")
trap 'hosts_down; rm -rf "$W"' EXIT
trap 'exit 130' INT TERM
hosts_up 3 "$W/hosts" || { echo "bench-hosts: could not set up the hosts"; exit 1; }
printf 'h1 slots=1\nh2 slots=1\n' >"$W/hostfile2"
printf 'h1 slots=2\nh2 slots=2\nh3 slots=2\n' >"$W/hostfile3"
OMPI_HOSTS="--mca plm_rsh_agent $W/hosts/agent --mca plm_rsh_no_tree_spawn 1 --mca pml ob1
 --mca btl tcp,self --mca btl_tcp_if_include hnet0 --mca oob_tcp_if_include hnet0
 --mca orte_tmpdir_base $W/ompi"
mpirun_hosts() { # HOSTFILE SECONDS ARGS...
    local hf=$1 t=$2; shift 2
    # shellcheck disable=SC2086
    on_host h1 timeout -k 5 "$t" mpirun --hostfile "$hf" $OMPI_HOSTS "$@"
}
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" | tail -1; }
median() { sort -g | awk '{v[NR]=$1} END{if (NR) print v[int((NR+1)/2)]; else print "NA"}'; }
failed=0

# ---- 1. round trips
echo "bench-hosts: round trips h1 <-> h2 (veth + bridge), $ROUNDS alternating rounds"
: >"$W/rtt"
for r in $(seq 1 "$ROUNDS"); do
    on_host h2 "$B/bench/tcp_rtt" serve 7000 >/dev/null 2>&1 &
    sp=$!
    out=$(on_host h1 timeout 60 "$B/bench/tcp_rtt" ping 10.231.0.2 7000 2>&1)
    wait $sp
    echo "tcp $(printf '%s\n' "$out" | field best_us) $(printf '%s\n' "$out" | field median_us)" >>"$W/rtt"
    for sw in 1 0 backoff yield; do
        if [ $sw = yield ]; then # Open MPI's blocking calls yield the CPU when they find nothing
            out=$(mpirun_hosts "$W/hostfile2" 120 --mca mpi_yield_when_idle 1 -np 2 --map-by node \
                "$B/bench/rsr_rtt" 2>&1)
        elif [ $sw = backoff ]; then # the socket wait with the backoff as its timeout
            out=$(mpirun_hosts "$W/hostfile2" 120 -x RT_SOCKET_WAIT=1 -x RT_WAIT_LAZY=0 -np 2 \
                --map-by node "$B/bench/rsr_rtt" 2>&1)
        else
            out=$(mpirun_hosts "$W/hostfile2" 120 -x RT_SOCKET_WAIT=$sw -np 2 --map-by node \
                "$B/bench/rsr_rtt" 2>&1)
        fi
        line=$(printf '%s\n' "$out" | grep '^rsr_rtt:')
        if [ -z "$line" ]; then
            echo "bench-hosts: rsr_rtt failed (RT_SOCKET_WAIT=$sw):"; printf '%s\n' "$out" | tail -5
            failed=1; continue
        fi
        if [ $sw = 1 ]; then
            echo "rsr $(printf '%s\n' "$line" | field rsr_best_us) $(printf '%s\n' "$line" | field rsr_median_us)" >>"$W/rtt"
            echo "mpi $(printf '%s\n' "$line" | field mpi_best_us) $(printf '%s\n' "$line" | field mpi_median_us)" >>"$W/rtt"
        elif [ $sw = 0 ]; then
            echo "sleep $(printf '%s\n' "$line" | field rsr_best_us) $(printf '%s\n' "$line" | field rsr_median_us)" >>"$W/rtt"
        elif [ $sw = backoff ]; then
            echo "backoff $(printf '%s\n' "$line" | field rsr_best_us) $(printf '%s\n' "$line" | field rsr_median_us)" >>"$W/rtt"
        else
            echo "mpiy $(printf '%s\n' "$line" | field mpi_best_us) $(printf '%s\n' "$line" | field mpi_median_us)" >>"$W/rtt"
        fi
    done
done
col() { awk -v k="$1" -v c="$2" '$1 == k {print $c}' "$W/rtt" | median; }
printf '%-58s %12s %12s\n' "round trip, microseconds (median over rounds)" "best trial" "median trial"
printf '%-58s %12s %12s\n' "raw TCP, 1 byte, TCP_NODELAY, blocking read" "$(col tcp 2)" "$(col tcp 3)"
printf '%-58s %12s %12s\n' "runtime null RSR (idle wait on the sockets)" "$(col rsr 2)" "$(col rsr 3)"
printf '%-58s %12s %12s\n' "runtime null RSR, RT_WAIT_LAZY=0 (backoff as the timeout)" "$(col backoff 2)" "$(col backoff 3)"
printf '%-58s %12s %12s\n' "runtime null RSR, RT_SOCKET_WAIT=0 (timed idle sleep)" "$(col sleep 2)" "$(col sleep 3)"
printf '%-58s %12s %12s\n' "raw MPI, 0 bytes, blocking MPI_Send/MPI_Recv (busy poll)" "$(col mpi 2)" "$(col mpi 3)"
printf '%-58s %12s %12s\n' "raw MPI, the same, --mca mpi_yield_when_idle 1" "$(col mpiy 2)" "$(col mpiy 3)"
ratio=$(awk -v a="$(col rsr 3)" -v b="$(col tcp 3)" 'BEGIN{if (a+0 > 0 && b+0 > 0) printf "%.2f", a/b; else print "NA"}')
ratio_best=$(awk -v a="$(col rsr 2)" -v b="$(col tcp 2)" 'BEGIN{if (a+0 > 0 && b+0 > 0) printf "%.2f", a/b; else print "NA"}')
echo "null RSR / raw TCP: $ratio (median trials), $ratio_best (best trials); goal <= 2"
echo "machine load (1-minute average) at the end of the round trips: $(cut -d' ' -f1 /proc/loadavg)"

# ---- 2. Tables 2 and 3: RSR counts, 3 hosts against one host
echo
echo "bench-hosts: Tables 2/3 RSR counts, $DOMAIN -q 20.7 -a $AREA, median of $REPS runs"
printf '%-5s %-4s %-9s %-10s %10s %10s %10s %10s\n' prog imb ranks where triangles rsr mpi_msgs mesh_s
imbs="1 2"
[ "${TABLES:-1}" = 0 ] && imbs="" && echo "(skipped: TABLES=0)"
for imb in $imbs; do
    imbargs=""
    [ $imb != 1 ] && imbargs="--imbalance $imb"
    for prog in pcdm pbw; do
        modeargs="" # ./pcdm: the paper's asynchronous protocol, as in Tables 2 and 3
        [ $prog = pcdm ] && modeargs=--async
        for np in 3 6; do
            for where in one-host 3-hosts; do
                : >"$W/t23"
                for rep in $(seq 1 "$REPS"); do
                    # shellcheck disable=SC2086
                    if [ $where = one-host ]; then
                        out=$(timeout 120 mpirun --oversubscribe -np $np "./$prog" -NEP -q 20.7 \
                            -a "$AREA" $imbargs $modeargs --stats "$DOMAIN" 2>&1)
                    else
                        out=$(mpirun_hosts "$W/hostfile3" 120 -np $np --map-by node "./$prog" -NEP \
                            -q 20.7 -a "$AREA" $imbargs $modeargs --stats "$DOMAIN" 2>&1)
                    fi
                    s=$(printf '%s\n' "$out" | grep '^stats:' | tail -1)
                    if [ -z "$s" ]; then
                        echo "bench-hosts: $prog np=$np $where failed:"; printf '%s\n' "$out" | tail -3
                        failed=1; continue
                    fi
                    msgs=$(printf '%s\n' "$out" | grep '^rsr:' | tail -1 | field mpi_msgs)
                    for k in triangles rsr; do printf '%s ' "$(printf '%s\n' "$s" | field $k)"; done >>"$W/t23"
                    printf '%s %s' "${msgs:-NA}" "$(printf '%s\n' "$s" | field mesh_s)" >>"$W/t23"
                    echo >>"$W/t23"
                done
                m() { awk -v c="$1" '{print $c}' "$W/t23" | median; }
                printf '%-5s %-4s %-9s %-10s %10s %10s %10s %10s\n' "$prog" "$imb" \
                    "$((np / 3))x3=$np" "$where" "$(m 1)" "$(m 2)" "$(m 3)" "$(m 4)"
            done
        done
    done
done
echo "bench-hosts: tcp_rtt_us=$(col tcp 3) rsr_rtt_us=$(col rsr 3) mpi_rtt_us=$(col mpi 3) mpi_yield_rtt_us=$(col mpiy 3) rsr_sleep_rtt_us=$(col sleep 3) rsr_backoff_rtt_us=$(col backoff 3) ratio_rsr_tcp=$ratio"
exit $failed
