#!/usr/bin/env bash
# Cost of the runtime's primitive operations next to raw MPI / pthreads and the paper's SP2
# figures (TR-97-17 section 4).  Runs build/bench/primitives on 2 ranks; prints its table and,
# last, the machine-readable "primitives: ..." line.  B selects the build directory.
set -eu
cd "$(dirname "$0")/.."
B=${B:-build}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
exec timeout 300 mpirun --oversubscribe -np 2 "$B/bench/primitives"
