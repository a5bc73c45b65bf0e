# tests/lib.sh: what every shell test shares; sourced first thing by tests/t_*.sh:
#     . "$(dirname "$0")/lib.sh"
#
# Set-up: the working directory is the repository's root; BIN (the programs, default .), B (the
# build folder, default build), MPIRUN (default "mpirun --oversubscribe"), Open MPI allowed to
# run as root and to oversubscribe, ASAN_OPTIONS without leak checks (unless set); TEST (the
# test's name, from its file); T, a temporary folder removed on exit.
#
# One pass/fail idiom: `ok MESSAGE` and `fail MESSAGE` count a case each (the counts are kept in
# $T, so a case counted in a subshell, a pipeline or $(...) still counts; fail prints to stderr,
# which $(...) does not swallow); `finish` prints "TEST: N passed, M failed" last and exits 0
# only when nothing failed (and something was checked); `fatal MESSAGE` fails and finishes at
# once (for a set-up step nothing else can run without); `skip REASON` exits 0 saying why the
# test cannot run here.
#
# MPI runs: `mpi_run NP PROG ARGS...` runs PROG at NP ranks under timeout and $MPIRUN, each
# rank recording its own exit status (see mpi_run); field KEY reads a value of a stats line.
#
# Shell under tests/ is formatted with `shfmt -i 4 -w tests/*.sh tests/fuzz/*.sh`.
set -u
cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1
BIN=${BIN:-.}
B=${B:-build}
MPIRUN=${MPIRUN:-mpirun --oversubscribe}
export BIN B MPIRUN
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 PRTE_MCA_rmaps_default_mapping_policy=:oversubscribe
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
TEST=$(basename "$0" .sh)
T=$(mktemp -d "${TMPDIR:-/tmp}/$TEST.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
: >"$T/.passed"
: >"$T/.failed"

ok() { # MESSAGE: one case passed
    echo >>"$T/.passed"
    printf 'ok   %s\n' "$*"
}
fail() { # MESSAGE: one case failed
    echo >>"$T/.failed"
    printf 'FAIL %s\n' "$*" >&2
}
npassed() { wc -l <"$T/.passed" | tr -d ' '; }
nfailed() { wc -l <"$T/.failed" | tr -d ' '; }
finish() { # the summary line, and the exit status: 0 iff no case failed and some case ran
    local p f
    p=$(npassed) f=$(nfailed)
    echo "$TEST: $p passed, $f failed"
    [ "$f" -eq 0 ] && [ "$((p + f))" -gt 0 ]
    exit
}
fatal() { # MESSAGE: fail, and finish now
    fail "$*"
    finish
}
skip() { # REASON: the test cannot run here; exit 0 saying so
    echo "$TEST: SKIP: $*"
    exit 0
}

# field KEY: the value of KEY=VALUE in a stats line read from stdin (the last one)
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" | tail -1; }

# mpi_run NP PROG ARGS...: runs PROG ARGS at NP ranks, under `timeout ${TIMEOUT:-120}` and
# $MPIRUN (with ${MPI_X:-}, more mpirun options, e.g. -x VAR), each rank writing its own exit
# status and leaving 0 to mpirun (so mpirun lets every rank finish instead of killing the others
# when one fails).  Output goes where the caller sends it.  Returns the status every rank
# exited with; 124 when the run was killed by the timeout (a hang); 255 when the ranks
# disagree, a rank left no status (killed, or aborted with the others) or mpirun itself failed.
# Sets rcs (and writes it to ${RCS_FILE:-$T/rcs}, for callers in a subshell; runs at once
# each need their own RCS_FILE): every rank's status in rank order, "none" for a rank that left
# none, e.g. "1 1 1".
mpi_run() {
    local np=$1 d r s first="" agree=1 launcher
    shift
    d=$(mktemp -d "$T/ranks.XXXXXX")
    # shellcheck disable=SC2086
    timeout "${TIMEOUT:-120}" $MPIRUN ${MPI_X:-} -np "$np" sh -c \
        '"$0" "$@"; echo $? >"'"$d"'/${OMPI_COMM_WORLD_RANK:-${PMIX_RANK:-x}}"' "$@"
    launcher=$?
    rcs=""
    for ((r = 0; r < np; r++)); do
        s=$(cat "$d/$r" 2>/dev/null || echo none)
        rcs="$rcs $s"
        [ -n "$first" ] || first=$s
        [ "$s" = "$first" ] && [ "$s" != none ] || agree=0
    done
    rcs=${rcs# }
    echo "$rcs" >"${RCS_FILE:-$T/rcs}"
    rm -rf "$d"
    [ "$launcher" -ne 124 ] || return 124
    [ "$agree" = 1 ] && [ "$launcher" -eq 0 ] || return 255
    return "$first"
}

# all_ranks NP STATUS: true iff the last mpi_run's NP ranks all exited with STATUS
all_ranks() {
    local want="" r
    for ((r = 0; r < $1; r++)); do want="$want $2"; done
    [ "$(cat "${RCS_FILE:-$T/rcs}" 2>/dev/null)" = "${want# }" ]
}
