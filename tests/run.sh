#!/usr/bin/env bash
# Runs every test: Check unit programs (tests/unit_*.c), MPI programs (tests/mpi_*.c) at the
# rank counts named on their "// ranks:" line, and shell tests (tests/t_*.sh).
# The shell tests share their set-up, pass/fail counting and MPI runs (every rank's exit status)
# through tests/lib.sh.  Each MPI run is wrapped in timeout and oversubscribed.  Prints
# "N passed, N failed" last and exits non-zero on any failure.
set -u
cd "$(dirname "$0")/.."
B=${BUILD:-build}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 PRTE_MCA_rmaps_default_mapping_policy=:oversubscribe
export TMPDIR=${TMPDIR:-/tmp}
if [ "${SANITIZE:-}" = 1 ]; then
    export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
fi
# The normal build puts the programs at the root; sanitizer and debug builds keep them in $B/bin.
if [ "$B" = build ]; then export BIN=.; else export BIN=$B/bin; fi
export B
MPIRUN="mpirun --oversubscribe"
export MPIRUN
pass=0 fail=0 failed=()
# TSAN=1 (make TSAN=1 test): the ThreadSanitizer build runs the tests that start threads only --
# the runtime's tasks and threaded handlers, ./pcdm --threads, the writer's formatting threads,
# pcdm_triangulate's threads in libpcdm_threads --
# at the rank counts given here
# (TSan slows a program 5-15x); tests/tsan.supp holds the suppressions for Open MPI's insides.
declare -A only=()
if [ "${TSAN:-}" = 1 ]; then
    only=([unit_rt_task]=1 [mpi_rt]="1 2" [mpi_rt_term]="1 2" [mpi_pwrite]="1 2" [t_threads]=1
        [t_threads_fault]=1 [t_threads_lib]=1)
    export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1 suppressions=$PWD/tests/tsan.supp} THREADS_QUICK=1
fi
# Nothing a test runs may write into the repository's inputs (a mesher without -o writes
# NAME.1.* next to its input, as Triangle does: tests pass -o into a temporary folder or -NEP).
inputs_before=$(ls data tests/inputs 2>/dev/null)
log=$B/test-logs
mkdir -p "$log"
run() { # name, command...
    local name=$1
    shift
    local t0=$SECONDS
    if "$@" >"$log/$name.log" 2>&1; then
        pass=$((pass + 1))
        printf 'PASS %-40s %3ds\n' "$name" $((SECONDS - t0))
    else
        fail=$((fail + 1))
        failed+=("$name")
        printf 'FAIL %-40s %3ds (log: %s)\n' "$name" $((SECONDS - t0)) "$log/$name.log"
        tail -n 30 "$log/$name.log" | sed 's/^/    /'
    fi
}
for src in tests/unit_*.c; do
    [ -e "$src" ] || continue
    t=$(basename "$src" .c)
    [ ${#only[@]} = 0 ] || [ -n "${only[$t]:-}" ] || continue
    run "$t" timeout 600 "$B/tests/$t"
done
for src in tests/mpi_*.c; do
    [ -e "$src" ] || continue
    t=$(basename "$src" .c)
    [ ${#only[@]} = 0 ] || [ -n "${only[$t]:-}" ] || continue
    ranks=$(sed -n 's|^// ranks: *||p' "$src" | head -1)
    [ ${#only[@]} = 0 ] || ranks=${only[$t]}
    for np in ${ranks:-1 2 4 8}; do
        run "$t.np$np" timeout 300 $MPIRUN -np "$np" "$B/tests/$t"
    done
done
for sh in tests/t_*.sh; do
    [ -e "$sh" ] || continue
    [ ${#only[@]} = 0 ] || [ -n "${only[$(basename "$sh" .sh)]:-}" ] || continue
    run "$(basename "$sh" .sh)" timeout 900 bash "$sh"
done
inputs_after=$(ls data tests/inputs 2>/dev/null)
if [ "$inputs_before" != "$inputs_after" ]; then
    fail=$((fail + 1))
    failed+=("inputs-untouched")
    echo "FAIL inputs-untouched: tests wrote into data/ or tests/inputs/:"
    diff <(echo "$inputs_before") <(echo "$inputs_after") | sed -n 's/^> /    /p'
fi
echo
[ "$fail" -gt 0 ] && printf 'failed: %s\n' "${failed[*]}"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
