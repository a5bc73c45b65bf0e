#!/usr/bin/env bash
# t_outset: a run's output files appear as one set or not at all, whatever stops the run
# (mesher/io/oset.h), and the faults a real machine has end in one clear message.
#  1. every point of the commit: a run over a previous run's files is killed (SIGKILL, the
#     test-only fault PCDM_TEST_COMMIT_KILL=K) before each removal or rename of its commit, for
#     ./mesh and ./pcdm at 2 ranks; afterwards either no .node is there, or every file of the set
#     is byte for byte from the same run as the .node (the old run's or the new one's) and passes
#     ./meshcheck; both outcomes and "no set" must occur;
#  2. kills from outside at many moments of a run (SIGKILL after 0.05 .. 1.6 s), same checks;
#  3. SIGTERM and SIGINT (at a commit point and from outside during the run): no temporary
#     file is left, the previous set stays whole;
#  4. a file size limit (ulimit -f: EFBIG) and, as root where tmpfs mounts, a full disk
#     (ENOSPC): the message names the cause, exit status 1, nothing under the final names;
#  5. an output folder that is missing or read-only is refused before any meshing;
#  6. out of memory (ulimit -v) ends with "out of memory" and what to change, never a bug
#     report, exit status 1, nothing written.
. "$(dirname "$0")/lib.sh"

IN=data/lake.poly
EXTS="node ele poly edge"

# same_set DIR PREFIX REFDIR...: 0 when DIR/PREFIX.node is absent, or every file of the set
# equals the one of a single reference run REFDIR/PREFIX.*; prints "none", or the reference's
# name; 1 (with the reason) otherwise
same_set() {
    local d=$1 p=$2 r e
    shift 2
    [ -e "$d/$p.node" ] || {
        echo none
        return 0
    }
    for r in "$@"; do
        cmp -s "$d/$p.node" "$r/$p.node" || continue
        for e in $EXTS; do
            [ -e "$r/$p.$e" ] || continue
            cmp -s "$d/$p.$e" "$r/$p.$e" || {
                echo "$p.$e is not from the run of $p.node ($(basename "$r"))"
                return 1
            }
        done
        basename "$r"
        return 0
    done
    echo "$p.node is from neither run"
    return 1
}

no_temps() { # DIR: no temporary file left
    local left
    left=$(find "$1" -name '*.tmp??????' | head -3)
    [ -z "$left" ] || {
        echo "temporary files left: $left"
        return 1
    }
}

# the two reference runs: "old" (the files found in place) and "new" (what the killed run makes)
run_mesh() { "$BIN/mesh" -Q -q 30 -e "$@" "$IN"; }
run_pcdm() { timeout 120 $MPIRUN -np 2 "$BIN/pcdm" -Q -q 30 -e "$@" "$IN"; }
for prog in mesh pcdm; do
    mkdir -p "$T/$prog.old" "$T/$prog.new"
    "run_$prog" -a 0.01 -o "$T/$prog.old/P" >/dev/null 2>&1 &&
        "run_$prog" -a 0.0002 -o "$T/$prog.new/P" >/dev/null 2>&1 ||
        fatal "$prog: the reference runs failed"
done

# 1. every point of the commit: 4 files, .node removed first and renamed last: 5 points
for prog in mesh pcdm; do
    seen=""
    for k in 0 1 2 3 4 5; do
        d="$T/$prog.k$k"
        rm -rf "$d" && cp -r "$T/$prog.old" "$d"
        PCDM_TEST_COMMIT_KILL=$k MPI_X="-x PCDM_TEST_COMMIT_KILL" \
            "run_$prog" -a 0.0002 -o "$d/P" >/dev/null 2>&1
        if r=$(same_set "$d" P "$T/$prog.old" "$T/$prog.new"); then
            if [ "$r" = none ] || timeout 60 "$BIN/meshcheck" "$IN" "$d/P" >/dev/null 2>&1; then
                seen="$seen $r"
            else
                fail "$prog: killed at commit point $k: the set ($r) fails ./meshcheck"
                continue
            fi
        else
            fail "$prog: killed at commit point $k: $r"
        fi
    done
    case "$seen" in
    *old*none*new* | *old*new*) ok "$prog: killed at each commit point: the sets found:$seen" ;;
    *) fail "$prog: killed at each commit point: want the old set, then none, then the new: got$seen" ;;
    esac
done

# 2. kills from outside at many moments
for prog in mesh pcdm; do
    bad=0 n=0
    for delay in 0.05 0.1 0.15 0.2 0.3 0.4 0.5 0.6 0.8 1.0 1.2 1.6; do
        d="$T/$prog.t$delay"
        rm -rf "$d" && cp -r "$T/$prog.old" "$d"
        if [ $prog = mesh ]; then
            timeout -s KILL "$delay" "$BIN/mesh" -Q -q 30 -e -a 0.0002 -o "$d/P" "$IN" >/dev/null 2>&1
        else
            timeout -s KILL "$delay" $MPIRUN -np 2 "$BIN/pcdm" -Q -q 30 -e -a 0.0002 -o "$d/P" "$IN" \
                >/dev/null 2>&1
            sleep 0.3 # the ranks end after mpirun
        fi
        n=$((n + 1))
        if ! r=$(same_set "$d" P "$T/$prog.old" "$T/$prog.new"); then
            fail "$prog: killed after ${delay}s: $r"
            bad=1
        elif [ "$r" != none ] && ! timeout 60 "$BIN/meshcheck" "$IN" "$d/P" >/dev/null 2>&1; then
            fail "$prog: killed after ${delay}s: the set ($r) fails ./meshcheck"
            bad=1
        fi
    done
    [ $bad = 0 ] && ok "$prog: killed at $n moments: every set found whole"
done

# 3. SIGTERM and SIGINT: at a commit point (the temporary files all exist then) and from outside
for prog in mesh pcdm; do
    for sig in 15 2; do
        d="$T/$prog.sig$sig"
        rm -rf "$d" && cp -r "$T/$prog.old" "$d"
        PCDM_TEST_COMMIT_KILL=0 PCDM_TEST_COMMIT_SIG=$sig \
            MPI_X="-x PCDM_TEST_COMMIT_KILL -x PCDM_TEST_COMMIT_SIG" \
            "run_$prog" -a 0.0002 -o "$d/P" >/dev/null 2>&1
        rc=$?
        sleep 0.3
        if ! why=$(no_temps "$d"); then
            fail "$prog: signal $sig during the commit: $why"
        elif [ "$(same_set "$d" P "$T/$prog.old" "$T/$prog.new")" != "$prog.old" ]; then
            fail "$prog: signal $sig before the commit changed anything: the previous set is not whole"
        elif [ $rc = 0 ]; then
            fail "$prog: signal $sig: exit status 0"
        else
            ok "$prog: signal $sig during the commit: temporary files removed, previous set kept (exit $rc)"
        fi
    done
done
# from outside, while the files are written (a larger mesh: the write takes a while)
big=2e-6
for prog in mesh pcdm; do
    for sig in TERM INT; do
        d="$T/$prog.out$sig"
        mkdir -p "$d"
        # (a background job starts with SIGINT ignored: env gives it back its default)
        if [ $prog = mesh ]; then
            env --default-signal=INT "$BIN/mesh" -Q -q 30 -a $big -o "$d/P" "$IN" >/dev/null 2>&1 &
        else
            env --default-signal=INT $MPIRUN -np 2 "$BIN/pcdm" -Q -q 30 -a $big -o "$d/P" "$IN" \
                >/dev/null 2>&1 &
        fi
        pid=$!
        # wait until a temporary file exists (the write has begun), at most 60 s
        for _ in $(seq 600); do
            [ -n "$(find "$d" -name '*.tmp??????' | head -1)" ] && break
            kill -0 $pid 2>/dev/null || break
            sleep 0.1
        done
        kill -s $sig $pid 2>/dev/null
        wait $pid
        rc=$?
        sleep 0.5
        if [ $rc = 0 ]; then
            fail "$prog: SIG$sig while writing: the run was not stopped (exit 0)"
        elif why=$(no_temps "$d"); then
            ok "$prog: SIG$sig while writing: no temporary file left (exit $rc)"
        else
            fail "$prog: SIG$sig while writing: $why"
        fi
    done
done

# under_limit PROG SETUP ARGS...: ./mesh, or ./pcdm at 2 ranks, with the shell commands SETUP
# (a limit) run in the program's own process -- each rank's for ./pcdm: mpirun's own files and
# memory need more; stdout dropped, stderr in $T/err
under_limit() {
    local prog=$1 setup=$2
    shift 2
    if [ "$prog" = mesh ]; then
        sh -c "$setup && exec \"\$0\" \"\$@\"" "$BIN/mesh" "$@"
    else
        timeout 120 $MPIRUN -np 2 sh -c "$setup && exec \"\$0\" \"\$@\"" "$BIN/pcdm" "$@"
    fi >/dev/null 2>"$T/err"
}

# 4. the cause of a failed write: a file size limit (SIGXFSZ ignored: the write gets EFBIG)
for prog in mesh pcdm; do
    d="$T/$prog.fsize"
    mkdir -p "$d"
    under_limit $prog "trap '' XFSZ && ulimit -f 64" -Q -q 30 -a 1e-5 -o "$d/P" "$IN"
    rc=$?
    msg=$(grep -m1 "P\.\(node\|ele\|poly\)" "$T/err")
    if [ $rc = 0 ]; then
        fail "$prog: past the file size limit: exit status 0"
    elif ! echo "$msg" | grep -qi "too large"; then
        fail "$prog: past the file size limit: the message does not name the cause: $(head -2 "$T/err")"
    elif ls "$d"/P.* >/dev/null 2>&1 || ! no_temps "$d" >/dev/null; then
        fail "$prog: past the file size limit: files left: $(ls "$d")"
    else
        ok "$prog: past the file size limit: $msg"
    fi
done
# a full disk: a small tmpfs (root only, where mounting is allowed)
full="$T/full"
mkdir -p "$full"
if [ "$(id -u)" = 0 ] && mount -t tmpfs -o size=256k tmpfs "$full" 2>/dev/null; then
    for prog in mesh pcdm; do
        if [ $prog = mesh ]; then
            "$BIN/mesh" -Q -q 30 -a 1e-5 -o "$full/P" "$IN" >/dev/null 2>"$T/err"
        else
            timeout 120 $MPIRUN -np 2 "$BIN/pcdm" -Q -q 30 -a 1e-5 -o "$full/P" "$IN" >/dev/null 2>"$T/err"
        fi
        rc=$?
        msg=$(grep -m1 "P\." "$T/err")
        if [ $rc != 0 ] && echo "$msg" | grep -qi "no space left" && ! ls "$full"/P.* >/dev/null 2>&1 &&
            no_temps "$full" >/dev/null; then
            ok "$prog: full disk: $msg"
        else
            fail "$prog: full disk: exit $rc, files: $(ls "$full" | head -3), message: $(head -2 "$T/err")"
        fi
    done
    umount "$full"
else
    echo "$TEST: full disk: SKIP (needs root and tmpfs mounts)"
fi

# 5. an output folder that takes no files: refused before the meshing (the probe's message)
for prog in mesh pcdm; do
    for target in "$T/missing/P" "/proc/P"; do
        if [ $prog = mesh ]; then
            "$BIN/mesh" -Q -q 30 -a 1e-4 -o "$target" "$IN" >/dev/null 2>"$T/err"
        else
            timeout 120 $MPIRUN -np 2 "$BIN/pcdm" -Q -q 30 -a 1e-4 -o "$target" "$IN" >/dev/null 2>"$T/err"
        fi
        rc=$?
        if [ $rc != 0 ] && grep -q "cannot create files in its folder" "$T/err"; then
            ok "$prog: $target: $(grep -m1 'cannot create' "$T/err")"
        else
            fail "$prog: $target: exit $rc, want the folder refused before meshing: $(head -2 "$T/err")"
        fi
    done
done

# 6. out of memory: a clear end, nothing written (sanitizer builds reserve their shadow memory up
# front and cannot start under an address-space limit)
[ "${SANITIZE:-}" = 1 ] && echo "$TEST: out of memory: SKIP (a sanitizer build)"
for prog in mesh pcdm; do
    [ "${SANITIZE:-}" = 1 ] && break
    d="$T/$prog.oom"
    mkdir -p "$d"
    under_limit $prog "ulimit -v 600000" -Q -q 30 -a 1e-9 -o "$d/P" "$IN"
    rc=$?
    msg=$(grep -m1 "out of memory" "$T/err")
    if [ $rc = 0 ]; then
        fail "$prog: out of memory: exit status 0"
    elif grep -q "bug on rank" "$T/err"; then
        fail "$prog: out of memory reported as a bug: $(grep -m1 'bug on' "$T/err")"
    elif [ -z "$msg" ] || ! echo "$msg" | grep -q -- "-a"; then
        fail "$prog: out of memory: no clear message: $(head -3 "$T/err")"
    elif ls "$d"/P.* >/dev/null 2>&1; then
        fail "$prog: out of memory: files written: $(ls "$d")"
    else
        ok "$prog: out of memory (exit $rc): ${msg:0:110}"
    fi
done

finish
