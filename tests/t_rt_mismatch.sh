#!/usr/bin/env bash
# Handler tables that differ between ranks must fail at rt_start on every rank, with a message
# naming the first mismatching slot and handler.  mpi_rt registers a differently named
# handler on its last rank when RT_TEST_MISMATCH=1.
. "$(dirname "$0")/lib.sh"

out=$(RT_TEST_MISMATCH=1 mpi_run 2 "$B/tests/mpi_rt" 2>&1)
rc=$?
echo "$out" | tail -n 20
if [ $rc -eq 0 ] || [ $rc -eq 124 ]; then
    fail "expected a failure exit, got $rc (ranks: $(cat "$T/rcs"))"
else
    ok "exit $rc (ranks: $(cat "$T/rcs"))"
fi
for r in 0 1; do
    if echo "$out" | grep -q "rank $r: handler table mismatch at slot 1: rank 0 registered 'storm_chain_t'.*rank 1 registered 'storm_chain_X'"; then
        ok "rank $r reports the mismatching handler"
    else
        fail "rank $r did not report the mismatching handler"
    fi
done
finish
