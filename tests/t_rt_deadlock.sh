#!/usr/bin/env bash
# A task left blocked for good is a reported error, not a hang (runtime/rt_term.c): at 1, 2 and
# 4 ranks, tests/mpi_rt_term.c --deadlock=one (the last rank's task requests a handler that
# never replies) and --deadlock=every (one such task on every rank) must end within the
# timeout (status 124 is a hang) with a non-zero status on every rank; stderr must hold, from
# every rank, its "deadlock" header line, one dump line per blocked task with its label,
# pending count and last request, and the runtime's fatal message (rank, file, line).  The
# program's normal run (no argument) is run by tests/run.sh from its "// ranks:" line.
. "$(dirname "$0")/lib.sh"

out=$T/out err=$T/err
bad() { # what, message: a failure, with what the run printed
    fail "$1: $2"
    echo "--- stdout"
    cat "$out"
    echo "--- stderr"
    cat "$err"
}
for mode in one every; do
    for np in 1 2 4; do
        what="--deadlock=$mode on $np ranks"
        echo "== $what"
        n0=$(nfailed)
        TIMEOUT=60 mpi_run "$np" "$B/tests/mpi_rt_term" --deadlock=$mode >"$out" 2>"$err"
        rc=$?
        if [ "$rc" -eq 124 ]; then
            bad "$what" "hung (killed by timeout)"
            continue
        fi
        case " $rcs " in *" 0 "*) bad "$what" "a rank exited 0: $rcs" && continue ;; esac
        [ "$rc" -ne 0 ] || bad "$what" "exit status 0"
        ! grep -q 'rt_run returned although' "$err" || bad "$what" "rt_run returned"
        grep -Eq '^rt: fatal on rank [0-9]+ \(runtime/rt\.c:[0-9]+\): deadlock: [0-9]+ task\(s\) wait for replies that can never come' "$err" ||
            bad "$what" "no fatal deadlock message"
        nblocked=$([ $mode = every ] && echo "$np" || echo 1)
        for ((r = 0; r < np; r++)); do
            mine=$([ $mode = every ] || [ $r -eq $((np - 1)) ] && echo 1 || echo 0)
            grep -q "^rt: rank $r: deadlock: $mine task(s) blocked on this rank, $nblocked on all ranks" "$err" ||
                bad "$what" "rank $r did not report the deadlock"
            if [ "$mine" = 1 ]; then
                to=$(((r + 1) % np))
                grep -Eq "^rt: rank $r: blocked task slot [0-9]+ \(gen [0-9]+\): 1 pending, last request to rank $to handler [0-9]+ 'dl_sink', label \"lonely request to rank $to\", blocked [0-9.]+ s$" "$err" ||
                    bad "$what" "rank $r did not list its blocked task"
            fi
        done
        [ "$(grep -c ': blocked task slot' "$err")" -eq "$nblocked" ] ||
            bad "$what" "wrong number of dump lines"
        [ "$(nfailed)" != "$n0" ] || ok "$what: exit status $rc (ranks: $rcs): $(grep -c '^rt: fatal' "$err") fatal message(s), $nblocked blocked task(s) listed"
    done
done
finish
