#!/usr/bin/env bash
# The RSR storm under the runtime's other configurations, set through the environment:
# aggregation off; tiny aggregation buffers (every chain tail takes the large-message path) and
# a single worker; no idle sleeping; perturbation from the environment on top of the program's
# own seeds; and the network model (PCDM_NET: every message held at its receiver).  Shrinking
# buffers and pools gives bugs a chance to show.
. "$(dirname "$0")/lib.sh"

run() { # description, env...
    local what=$1
    shift
    echo "== $what"
    if (
        export "$@"
        mpi_run 4 "$B/tests/mpi_rt"
    ) >"$T/out" 2>&1; then
        grep -E "^storm seed|Checks" "$T/out"
        ok "$what"
    else
        cat "$T/out"
        fail "$what"
    fi
}
run "aggregation off" RT_AGGREGATE=0
run "256-byte buffers, 1 worker" RT_AGG_BYTES=256 RT_WORKERS=1
run "spin when idle" RT_IDLE_SPIN=1
run "perturbation from env" RT_PERTURB=99
run "network model from env (50 us, 10 MB/s)" PCDM_NET=50,10
finish
