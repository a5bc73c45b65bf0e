#!/usr/bin/env bash
# Handler tables that differ between ranks must fail at rt_start on every rank, with a message
# naming the first mismatching slot and handler.  mpi_rt_storm registers a differently named
# handler on its last rank when RT_TEST_MISMATCH=1.
set -u
cd "$(dirname "$0")/.."
B=${B:-build}
out=$(RT_TEST_MISMATCH=1 timeout 120 ${MPIRUN:-mpirun --oversubscribe} -np 2 "$B/tests/mpi_rt_storm" 2>&1)
rc=$?
echo "$out" | tail -n 20
if [ $rc -eq 0 ] || [ $rc -eq 124 ]; then
    echo "t_rt_mismatch: expected a failure exit, got $rc"; exit 1
fi
for r in 0 1; do
    if ! echo "$out" | grep -q "rank $r: handler table mismatch at slot 1: rank 0 registered 'storm_chain_t'.*rank 1 registered 'storm_chain_X'"; then
        echo "t_rt_mismatch: rank $r did not report the mismatching handler"; exit 1
    fi
done
echo "t_rt_mismatch: ok (exit $rc)"
