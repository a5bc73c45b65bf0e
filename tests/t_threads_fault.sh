#!/usr/bin/env bash
# A worker thread that faults ends the whole job with a clear error and writes nothing.  The
# test switch PCDM_TEST_WORKER_FAULT=SUB makes the worker that takes subdomain SUB's first round
# stop as a broken invariant in the kernel would (MESH_BUG: the message names the rank, the
# source line and the subdomain, then MPI_Abort stops every rank).  ./pcdm --threads 2 with -o:
#   - as a plain program (no mpirun): exit 70, the message, no file under the output prefix;
#   - at 1 and 3 ranks under mpirun: no rank exits 0, no hang (timeout), the message, no file;
#   - the same run without the switch writes the .node/.ele/.poly (so "no file" means something).
. "$(dirname "$0")/lib.sh"

ARGS=(--threads 2 --subdomains 8 -q 30 -a 1e-4)
msg='bug on rank [0-9]* (.*): worker thread refining subdomain 3: fault injected'

files() { ls "$T/out"/ 2>/dev/null | tr '\n' ' '; }

mkdir -p "$T/out"
PCDM_TEST_WORKER_FAULT=3 timeout 120 "$BIN/pcdm" "${ARGS[@]}" -o "$T/out/m" data/lake.poly \
    >"$T/o.txt" 2>&1
rc=$?
if [ "$rc" = 70 ] && grep -q "$msg" "$T/o.txt" && [ -z "$(files)" ]; then
    ok "one process: exit 70, $(grep -o "$msg" "$T/o.txt" | head -1), nothing written"
else
    fail "one process: exit $rc, files: $(files): $(head -3 "$T/o.txt")"
fi

for np in 1 3; do
    rm -rf "$T/out" && mkdir -p "$T/out"
    PCDM_TEST_WORKER_FAULT=3 MPI_X="-x PCDM_TEST_WORKER_FAULT" mpi_run "$np" "$BIN/pcdm" \
        "${ARGS[@]}" -o "$T/out/m" data/lake.poly >"$T/o.txt" 2>&1
    rc=$?
    if [ "$rc" = 124 ]; then
        fail "$np ranks: hang (killed by timeout), ranks: $rcs"
    elif [[ " $rcs " =~ \ 0\  ]] || [ "$rc" = 0 ]; then
        fail "$np ranks: a rank exited 0 (ranks: $rcs)"
    elif ! grep -q "$msg" "$T/o.txt"; then
        fail "$np ranks: no message naming the fault: $(head -3 "$T/o.txt")"
    elif [ -n "$(files)" ]; then
        fail "$np ranks: files written: $(files)"
    else
        ok "$np ranks: every rank stopped (ranks: $rcs), the fault named, nothing written"
    fi
done

rm -rf "$T/out" && mkdir -p "$T/out"
mpi_run 3 "$BIN/pcdm" "${ARGS[@]}" -o "$T/out/m" data/lake.poly >"$T/o.txt" 2>&1
rc=$?
if [ "$rc" = 0 ] && [ "$(files)" = "m.ele m.node m.poly " ]; then
    ok "without the switch: exit 0, $(files)written"
else
    fail "without the switch: exit $rc (ranks: $rcs), files: $(files): $(head -3 "$T/o.txt")"
fi
finish
