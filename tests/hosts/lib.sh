# Network hosts on one machine, for tests/hosts/run.sh and bench/hosts.sh (sourced).
#
# hosts_up N makes N "hosts": each a network namespace NS_PREFIX-hI with its own loopback and
# one interface, hnet0, address 10.231.0.I/24, joined by veth pairs to a bridge that lives in a
# switch namespace of its own (NS_PREFIX-sw), so no address or route appears outside the
# namespaces.  Processes on host hI run in its network namespace and in a UTS namespace whose
# hostname is hI (on_host hI CMD...).  Open MPI launches its daemons there through the launch
# agent $HOSTS_DIR/agent (plm_rsh_agent; no ssh): agent hI CMD... runs CMD with sh on hI.
# hosts_down removes it all (called from an EXIT trap; safe to call twice).
# hosts_can says, with a reason on stdout, whether this machine can do it (root, iproute2,
# unshare, network namespaces allowed).

HOSTS_TAG=${HOSTS_TAG:-$$}
NS_PREFIX=pcdm$HOSTS_TAG
HOSTS_N=0
HOSTS_DIR=

hosts_can() {
    if [ "$(id -u)" -ne 0 ]; then echo "not root (network namespaces need root)"; return 1; fi
    local t
    for t in ip unshare timeout; do
        command -v $t >/dev/null 2>&1 || { echo "$t is missing (iproute2 / util-linux / coreutils)"; return 1; }
    done
    local probe=${NS_PREFIX}-probe err
    if ! err=$(ip netns add "$probe" 2>&1); then
        echo "cannot create a network namespace: $err"; return 1
    fi
    if ! err=$(ip netns exec "$probe" unshare --uts sh -c 'hostname probe && ip link set lo up' 2>&1); then
        ip netns del "$probe" 2>/dev/null
        echo "cannot enter a network and UTS namespace: $err"; return 1
    fi
    if ! err=$(ip link add "${NS_PREFIX}pa" type veth peer name "${NS_PREFIX}pb" 2>&1); then
        ip netns del "$probe" 2>/dev/null
        echo "cannot create veth pairs: $err"; return 1
    fi
    ip link del "${NS_PREFIX}pa" 2>/dev/null
    ip netns del "$probe"
    return 0
}

# hosts_up N DIR: N hosts h1..hN; DIR (created) holds the agent and the hostfiles.
hosts_up() {
    local n=$1 i sw=${NS_PREFIX}-sw
    HOSTS_DIR=$2
    mkdir -p "$HOSTS_DIR"
    HOSTS_N=$n
    ip netns add "$sw" || return 1
    ip -n "$sw" link add br0 type bridge || return 1
    ip -n "$sw" link set br0 up
    ip -n "$sw" link set lo up
    for i in $(seq 1 "$n"); do
        local ns=${NS_PREFIX}-h$i
        ip netns add "$ns" || return 1
        ip link add "${NS_PREFIX}h$i" type veth peer name "${NS_PREFIX}s$i" || return 1
        ip link set "${NS_PREFIX}h$i" netns "$ns" || return 1
        ip link set "${NS_PREFIX}s$i" netns "$sw" || return 1
        ip -n "$ns" link set "${NS_PREFIX}h$i" name hnet0
        ip -n "$ns" addr add "10.231.0.$i/24" dev hnet0
        ip -n "$ns" link set hnet0 up
        ip -n "$ns" link set lo up
        ip -n "$sw" link set "${NS_PREFIX}s$i" master br0
        ip -n "$sw" link set "${NS_PREFIX}s$i" up
    done
    # the launch agent: "agent HOST COMMAND..." runs COMMAND (a shell command line, as ssh
    # would) on HOST and leaves its exit status in status/HOST
    mkdir -p "$HOSTS_DIR/status"
    cat >"$HOSTS_DIR/agent" <<AGENT
#!/bin/sh
# launch agent for Open MPI (plm_rsh_agent): runs a command line on a namespace host
host=\$1; shift
case "\$host" in h[0-9]*) ;; *) echo "agent: unknown host '\$host'" >&2; exit 255;; esac
[ -e /run/netns/${NS_PREFIX}-\$host ] || { echo "agent: no host '\$host'" >&2; exit 255; }
exec ip netns exec "${NS_PREFIX}-\$host" unshare --uts sh -c \\
    'hostname "\$0" || exit 255; eval "\$1"; st=\$?; echo \$st >"\$2/\$0"; exit \$st' \\
    "\$host" "\$*" "$HOSTS_DIR/status"
AGENT
    chmod +x "$HOSTS_DIR/agent"
}

# on_host hI CMD...: CMD in host hI's namespaces (hostname hI)
on_host() {
    local host=$1; shift
    ip netns exec "${NS_PREFIX}-$host" unshare --uts sh -c 'hostname "$0" && exec "$@"' "$host" "$@"
}

# hosts_down: kill what still runs on the hosts, delete the namespaces (and with them the veths)
hosts_down() {
    local ns p
    for ns in $(ip netns list 2>/dev/null | awk '{print $1}' | grep "^${NS_PREFIX}-"); do
        for p in $(ip netns pids "$ns" 2>/dev/null); do kill -9 "$p" 2>/dev/null; done
        ip netns del "$ns" 2>/dev/null
    done
    HOSTS_N=0
}
