#!/usr/bin/env bash
# make test-hosts: ./pcdm, ./pbw and the runtime across three hosts that talk over TCP only.
#
# The hosts are network namespaces on this machine (tests/hosts/lib.sh: each with its own
# hostname and interface, joined by a bridge; nothing outside the namespaces changes).  Open MPI
# starts its daemons on them through a launch agent that enters the namespace (no ssh), from a
# hostfile, with the TCP transport alone (btl tcp,self; pml ob1) pinned to the hosts' interface.
# Checks:
#  1. the ranks land on three hosts (hostnames h1, h2, h3);
#  2. ./pcdm --deterministic at 3 hosts x 1 and 3 hosts x 2 ranks: --check OK and the same mesh
#     hash as 1 rank; ./pbw at 3 hosts x 1 and x 2: --check OK;
#  3. files written through MPI-IO (-o: .node .ele .poly, -e .edge, -n .neigh) and the per-rank
#     --vtk pieces with their index are byte-identical to a run of as many ranks on one host;
#  4. the runtime's tests (tests/mpi_rt, mpi_rt_term, mpi_rt_net) pass across hosts,
#     and a handler table that differs on one host stops every rank with the mismatch named;
#  5. faults in the middle of a run (./pbw -o, stretched by the --net model so it runs for
#     seconds): a rank killed on h2, and h2's link taken down.  Every host's part of the job
#     must end, mpirun and every remote daemon with a non-zero status, within 30 s, and no
#     output may exist under its final name; a run without a fault first shows that the same
#     command does finish and write them;
#  6. bad set-ups end quickly with a clear error: h2 listed twice in the hostfile with different
#     programs on it, a rank count the input cannot use (more ranks than subdomains), a host in
#     the hostfile that does not exist.
# Needs root, iproute2 and network namespaces; otherwise it says why and skips (exit 0).
# Env: BIN (programs, default .), B (build dir, default build), MPIRUN (the single-host
# launcher, default "mpirun --oversubscribe"), HOSTS_KEEP=1 keeps the work directory.
# One line per check; exit status 1 if any failed.
set -u
cd "$(dirname "$0")/../.."
BIN=${BIN:-.}
B=${B:-build}
MPIRUN=${MPIRUN:-mpirun --oversubscribe}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
. tests/hosts/lib.sh

if ! why=$(hosts_can); then
    echo "test-hosts: skipped: $why"
    exit 0
fi
for f in "$BIN/pcdm" "$BIN/pbw" "$B/tests/mpi_rt" "$B/tests/mpi_rt_term" \
    "$B/tests/mpi_rt_net"; do
    [ -x "$f" ] || { echo "test-hosts: $f is missing (run make first)"; exit 1; }
done
BIN=$(cd "$BIN" && pwd) B=$(cd "$B" && pwd)

W=$(mktemp -d "${TMPDIR:-/tmp}/pcdm-hosts.XXXXXX")
cleanup() {
    hosts_down
    if [ "${HOSTS_KEEP:-0}" = 1 ]; then echo "work directory kept: $W"; else rm -rf "$W"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM
if ! hosts_up 3 "$W/hosts"; then echo "FAIL could not set up the hosts"; exit 1; fi
printf 'h1 slots=2\nh2 slots=2\nh3 slots=2\n' >"$W/hostfile"

# Every launch: the hostfile, the agent, TCP only on the hosts' interface; a lost daemon is
# noticed within seconds (keepalive on the daemons' connections).
OMPI_HOSTS="--mca plm_rsh_agent $W/hosts/agent --mca plm_rsh_no_tree_spawn 1
 --mca pml ob1 --mca btl tcp,self --mca btl_tcp_if_include hnet0 --mca oob_tcp_if_include hnet0
 --mca orte_tmpdir_base $W/ompi --mca oob_tcp_keepalive_time 1 --mca oob_tcp_keepalive_intvl 1
 --mca oob_tcp_keepalive_probes 3"
# mpirun_hosts SECONDS MPIRUN-ARGS...: mpirun on h1 (the head node) across the hosts of the
# hostfile $HF
HF=$W/hostfile
mpirun_hosts() {
    local t=$1; shift
    # shellcheck disable=SC2086
    on_host h1 timeout -k 5 "$t" mpirun --hostfile "$HF" $OMPI_HOSTS "$@"
}

pass=0 fail=0
ok() { pass=$((pass + 1)); printf 'ok   %s\n' "$*"; }
bad() { fail=$((fail + 1)); printf 'FAIL %s\n' "$*"; }
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" | tail -1; }
show() { printf '%s\n' "$1" | tail -n "${2:-8}" | sed 's/^/    /'; }

# ---- 1. placement
out=$(mpirun_hosts 60 -np 6 --map-by node sh -c 'echo "$OMPI_COMM_WORLD_RANK $(hostname)"' 2>&1)
# (only the ranks' lines: Open MPI's launcher may add a warning such as "setpgid ... failed")
got=$(printf '%s\n' "$out" | grep -E '^[0-9]+ h[0-9]+$' | sort -n |
    awk '{printf "%s%s", sep, $2; sep=","}')
if [ "$got" = "h1,h2,h3,h1,h2,h3" ]; then
    ok "placement: ranks 0-5 on $got"
else
    bad "placement: ranks 0-5 on '$got', expected h1,h2,h3,h1,h2,h3"
    show "$out"
fi

# ---- 2. the meshers across hosts
declare -A BOUNDS=([data/lake.poly]="-q 30 -a 1e-4" [tests/inputs/map.poly]="-q 28 -a 2e-4")
for dom in data/lake.poly tests/inputs/map.poly; do
    b=${BOUNDS[$dom]}
    # shellcheck disable=SC2086
    out=$(timeout 120 $MPIRUN -np 1 "$BIN/pcdm" -NEP --deterministic --subdomains 8 --check \
        --stats $b "$dom" 2>&1)
    ref=$(printf '%s\n' "$out" | grep '^stats:' | field hash)
    if [ -z "$ref" ] || ! printf '%s\n' "$out" | grep -q 'check: OK'; then
        bad "pcdm $dom $b at 1 rank: no passing check or hash"; show "$out"; continue
    fi
    for np in 3 6; do
        # shellcheck disable=SC2086
        out=$(mpirun_hosts 120 -np $np --map-by node "$BIN/pcdm" -NEP --deterministic \
            --subdomains 8 --check --stats $b "$dom" 2>&1)
        st=$?
        h=$(printf '%s\n' "$out" | grep '^stats:' | field hash)
        if [ $st -ne 0 ] || ! printf '%s\n' "$out" | grep -q 'check: OK'; then
            bad "pcdm --deterministic $dom $b at 3 hosts x $((np / 3)): exit $st, no passing check"
            show "$out"
        elif [ "$h" != "$ref" ]; then
            bad "pcdm --deterministic $dom $b at 3 hosts x $((np / 3)): hash $h, 1 rank $ref"
        else
            ok "pcdm --deterministic $dom $b at 3 hosts x $((np / 3)): check OK, hash $h = 1 rank's"
        fi
    done
    for np in 3 6; do
        # shellcheck disable=SC2086
        out=$(mpirun_hosts 120 -np $np --map-by node "$BIN/pbw" -NEP --check --stats $b "$dom" 2>&1)
        st=$?
        tri=$(printf '%s\n' "$out" | grep '^stats:' | field triangles)
        if [ $st -eq 0 ] && printf '%s\n' "$out" | grep -q 'check: OK'; then
            ok "pbw $dom $b at 3 hosts x $((np / 3)): check OK, $tri triangles"
        else
            bad "pbw $dom $b at 3 hosts x $((np / 3)): exit $st, no passing check"; show "$out"
        fi
    done
done

# ---- 3. MPI-IO and per-rank files: byte-identical to one host's
mkdir -p "$W/one" "$W/three"
OUTARGS="--deterministic --subdomains 8 -q 30 -a 1e-4 -e -n"
# shellcheck disable=SC2086
out1=$(timeout 120 $MPIRUN -np 3 "$BIN/pcdm" $OUTARGS -o "$W/one/m" --vtk "$W/one/m.vtk" \
    data/lake.poly 2>&1)
st1=$?
# shellcheck disable=SC2086
out3=$(mpirun_hosts 120 -np 3 --map-by node "$BIN/pcdm" $OUTARGS -o "$W/three/m" \
    --vtk "$W/three/m.vtk" data/lake.poly 2>&1)
st3=$?
files=$(cd "$W/one" && ls)
nf=$(printf '%s\n' $files | grep -c .)
if [ $st1 -ne 0 ] || [ $st3 -ne 0 ]; then
    bad "outputs: exit $st1 on one host, $st3 on three"; show "$out1"; show "$out3"
elif [ "$nf" -lt 9 ]; then
    bad "outputs: expected .node .ele .poly .edge .neigh, .pvtu and 3 pieces, found: $files"
else
    diff=""
    for f in $files; do cmp -s "$W/one/$f" "$W/three/$f" || diff="$diff $f"; done
    if [ -z "$diff" ] && [ "$files" = "$(cd "$W/three" && ls)" ]; then
        ok "outputs: $nf files ($(printf '%s ' $files)) byte-identical on 3 hosts and 1 host"
    else
        bad "outputs differ between 3 hosts and 1 host:$diff"
    fi
fi

# ---- 4. the runtime across hosts
for t in mpi_rt mpi_rt_term mpi_rt_net; do
    for np in 3 6; do
        out=$(mpirun_hosts 180 -np $np --map-by node "$B/tests/$t" 2>&1)
        st=$?
        if [ $st -eq 0 ]; then
            ok "runtime $t at 3 hosts x $((np / 3)): $(printf '%s\n' "$out" | grep -o '[0-9]*%: Checks: [0-9]*, Failures: [0-9]*, Errors: [0-9]*' | tail -1)"
        else
            bad "runtime $t at 3 hosts x $((np / 3)): exit $st"; show "$out"
        fi
    done
done
# the last rank (on h3) registers a different handler
out=$(mpirun_hosts 60 -np 3 --map-by node -x RT_TEST_MISMATCH=1 "$B/tests/mpi_rt" 2>&1)
st=$?
n=$(printf '%s\n' "$out" | grep -c "rank [012]: handler table mismatch at slot 1: rank 0 registered 'storm_chain_t'.*rank 2 registered 'storm_chain_X'")
if [ $st -ne 0 ] && [ $st -ne 124 ] && [ $st -ne 137 ] && [ "$n" -eq 3 ]; then
    ok "runtime: a handler table differing on h3 stops all 3 ranks (exit $st), each naming it"
else
    bad "runtime: handler table differing on h3: exit $st, $n of 3 ranks named the mismatch"
    show "$out"
fi

# ---- 5. faults
# 20 ms a message: the run lasts several seconds (locally 2.3-6.5 s of meshing); at 5 ms a ./pbw
# whose end game keeps more cavities in flight finished in 1.8 s, before the fault came
FAULT_RUN="-q 30 -a 1e-5 --net 20000"
# fault_run NAME FAULT: ./pbw on 3 hosts, FAULT (kill or link) at 1.5 s; sets fault_msg
since() { awk -v a="$1" -v b="${2:-$(date +%s.%N)}" 'BEGIN{printf "%.1f", b - a}'; } # T0 [NOW]
gt() { awk -v a="$1" -v b="$2" 'BEGIN{exit !(a > b)}'; }
procs() { ip netns pids "${NS_PREFIX}-$1" 2>/dev/null | wc -l; }
fault_run() {
    local name=$1 fault=$2 dir=$W/fault-$1
    mkdir -p "$dir"
    rm -f "$W/hosts/status/"*
    local t0 mp
    t0=$(date +%s.%N)
    # shellcheck disable=SC2086
    mpirun_hosts 90 -np 3 --map-by node "$BIN/pbw" $FAULT_RUN -o "$dir/m" --vtk "$dir/m.vtk" \
        data/lake.poly >"$dir/log" 2>&1 &
    mp=$!
    if [ "$fault" = none ]; then
        wait $mp
        local st=$?
        fault_msg="exit $st after $(since "$t0") s"
        return $st
    fi
    sleep 1.5
    local pid victim=""
    for pid in $(ip netns pids "${NS_PREFIX}-h2"); do
        [ "$(cat /proc/"$pid"/comm 2>/dev/null)" = pbw ] && victim=$pid
    done
    if [ -z "$victim" ] || ! kill -0 $mp 2>/dev/null; then
        wait $mp
        fault_msg="the run was not in progress at 1.5 s (no pbw on h2), exit $?"
        return 1
    fi
    local tf
    tf=$(date +%s.%N)
    if [ "$fault" = kill ]; then kill -9 "$victim"; else ip -n "${NS_PREFIX}-h2" link set hnet0 down; fi
    # every host's processes gone, mpirun's status
    local h end=() left=3 now
    while [ $left -gt 0 ]; do
        now=$(date +%s.%N)
        left=0
        for h in 1 2 3; do
            if [ -z "${end[$h]:-}" ]; then
                if [ "$(procs h$h)" -eq 0 ]; then end[$h]=$(since "$tf" "$now"); else left=$((left + 1)); fi
            fi
        done
        gt "$(since "$tf" "$now")" 40 && break
        sleep 0.1
    done
    wait $mp
    local st=$? worst=0 msg="" problems=""
    for h in 1 2 3; do
        msg="$msg h$h ${end[$h]:-never}s"
        if [ -z "${end[$h]:-}" ] || gt "${end[$h]}" 30; then
            problems="$problems h$h still running after 30 s;"
        fi
    done
    [ $st -eq 0 ] && problems="$problems mpirun exit 0;"
    [ $st -eq 124 ] && problems="$problems mpirun timed out;"
    # Open MPI's daemons on h2 and h3 exit 0 once they have killed their ranks: the job's
    # status is mpirun's; theirs is shown
    for h in 2 3; do
        msg="$msg, daemon h$h exit $(cat "$W/hosts/status/h$h" 2>/dev/null || echo none)"
    done
    local f claims=""
    for f in m.node m.ele m.poly m.pvtu; do [ -e "$dir/$f" ] && claims="$claims $f"; done
    [ -n "$claims" ] && problems="$problems complete-looking output:$claims;"
    local tmps
    tmps=$(find "$dir" -name '*.tmp??????' | wc -l)
    ip -n "${NS_PREFIX}-h2" link set hnet0 up 2>/dev/null
    fault_msg="mpirun exit $st; every process gone after:$msg; no final output ($tmps temporary files left)"
    [ -z "$problems" ] || { fault_msg="$problems $fault_msg"; return 1; }
}
if fault_run control none && [ -e "$W/fault-control/m.ele" ] && [ -e "$W/fault-control/m.pvtu" ]; then
    ok "faults: the fault run's command without a fault writes its outputs ($fault_msg)"
else
    bad "faults: the fault run's command without a fault: $fault_msg"; show "$(cat "$W/fault-control/log")"
fi
if fault_run kill kill; then
    ok "fault: rank 1 killed on h2 mid-run: $fault_msg"
else
    bad "fault: rank 1 killed on h2 mid-run: $fault_msg"; show "$(cat "$W/fault-kill/log")"
fi
if fault_run link link; then
    ok "fault: h2's link down mid-run: $fault_msg"
else
    bad "fault: h2's link down mid-run: $fault_msg"; show "$(cat "$W/fault-link/log")"
fi
# nothing left behind on any host
left=""
for h in 1 2 3; do [ "$(procs h$h)" -eq 0 ] || left="$left h$h"; done
if [ -z "$left" ]; then ok "faults: no process left on any host"; else bad "faults: processes left on$left"; fi

# ---- 6. bad set-ups
# bad_setup NAME EXPECTED-MESSAGE-REGEX HOSTFILE SECONDS MPIRUN-ARGS...
bad_setup() {
    local name=$1 re=$2 hf=$3 t=$4; shift 4
    local t0=$SECONDS out st
    out=$(HF=$hf mpirun_hosts "$t" "$@" 2>&1)
    st=$?
    local line
    line=$(printf '%s\n' "$out" | grep -E -m1 "$re")
    if [ $st -ne 0 ] && [ $st -ne 124 ] && [ $((SECONDS - t0)) -lt "$t" ] && [ -n "$line" ]; then
        ok "bad set-up: $name: exit $st after $((SECONDS - t0)) s: $line"
    else
        bad "bad set-up: $name: exit $st, no message matching '$re'"; show "$out"
    fi
}
# h2 listed twice (two slots), one of them running a different program: rank 0 on h1, ranks 1
# and 2 on h2 (./pcdm and ./pbw), rank 3 on h3
printf 'h1 slots=1\nh2\nh3 slots=1\nh2\n' >"$W/hostfile2"
out=$(HF=$W/hostfile2 mpirun_hosts 60 --map-by slot -np 2 sh -c 'echo "$(hostname) a"' : \
    -np 1 sh -c 'echo "$(hostname) b"' : -np 1 sh -c 'echo "$(hostname) a"' 2>&1)
# (only the ranks' lines: Open MPI's launcher may add a warning such as "setpgid ... failed")
got=$(printf '%s\n' "$out" | grep -E '^h[0-9]+ [ab]$' | sort | tr '\n' ' ')
if [ "$got" = "h1 a h2 a h2 b h3 a " ]; then
    bad_setup "h2 listed twice, running ./pcdm and ./pbw" \
        "rank [0-3]: handler table mismatch at slot 0: rank 0 registered 'pcdm_split'.*'pbw_expand'" \
        "$W/hostfile2" 60 --map-by slot -np 2 "$BIN/pcdm" -NEP data/lake.poly : \
        -np 1 "$BIN/pbw" -NEP data/lake.poly : -np 1 "$BIN/pcdm" -NEP data/lake.poly
else
    bad "bad set-up: h2 listed twice: placement '$got', expected h1 a h2 a h2 b h3 a"; show "$out"
fi
printf 'h1 slots=1\nh2 slots=1\nh3 slots=1\nh2 slots=1\n' >"$W/hostfile4"
bad_setup "h2 listed twice with a slot count each" "contains multiple definitions" \
    "$W/hostfile4" 60 -np 3 "$BIN/pcdm" -NEP data/lake.poly
bad_setup "6 ranks, 4 subdomains" "subdomains 4: fewer subdomains than ranks \(6\)" "$W/hostfile" 60 \
    -np 6 --map-by node "$BIN/pcdm" -NEP --subdomains 4 data/lake.poly
printf 'h1 slots=2\nh4 slots=2\n' >"$W/hostfile3"
bad_setup "a host that does not exist (h4)" "agent: no host 'h4'" "$W/hostfile3" 60 \
    -np 4 --map-by node "$BIN/pcdm" -NEP data/lake.poly

echo "test-hosts: $pass passed, $fail failed"
[ $fail -eq 0 ]
