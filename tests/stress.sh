#!/usr/bin/env bash
# stress.sh: the schedule explorer (make stress).  Runs ./pbw and ./pcdm over the fuzz
# regression table (tests/fuzz/regress/TABLE, with its options), a sample of the fuzz corpus
# (tests/fuzz/corpus: one option byte, then a .poly, or a .node when bit 7 is set, as
# tests/fuzz/fuzz_mesh.c reads them) and the domains in data/ (small meshes, -q 20.7 and -q 30),
# at 2, 3, 4 and 8 ranks, under many message schedules: --perturb SEED (the runtime delays and
# reorders deliveries), ./pbw's --inflight 1-4, ./pcdm in rounds (its default) and --async.  Every
# run has -S 20000 (unless its row sets -S) and --check, and is judged against ./mesh's answer
# for the same input and options (as tests/fuzz/replay_par.sh):
#   - ./mesh meshes it: every rank exits 0 with --check OK, or 1 with "cannot decompose" /
#     "cannot meet the bounds", or 3 (the Steiner limit);
#   - ./mesh cannot meet the bounds (exit 1) or stops at -S (exit 3): 0 with --check OK, 1 with
#     "cannot meet the bounds", or 3;
#   - ./mesh refuses the input: every rank exits 1.
# Always a failure: a timeout (a hang), a crash or any other status, ranks that disagree, exit 0
# without --check OK.  A run whose launcher failed before any rank started (Open MPI's
# orte_init, racing another mpirun on the machine) is run again, up to three times.  ./pcdm --subdomains 8 (in rounds) must moreover give one mesh hash
# (--stats: hash=) per input and options, whatever the rank count and the schedule (these runs
# share 12 of the cases, so that each is compared across many schedules).
# Each failure is kept in OUT/fail-JOB/: the input, `cmd` (the command that reproduces it, from
# the repository's root; a schedule-dependent failure may need a few runs of it) and `out` (what
# the run printed); OUT/failures.txt lists them, OUT/results.txt has one line per run.
# Bounded by time and count: the jobs (program, input, ranks, seed, --inflight) are drawn from
# STRESS_SEED, so a given STRESS_SEED and STRESS_RUNS is a fixed sample (what CI runs); runs not
# started by the deadline are skipped (counted).  Exit 0 iff no run failed.
# Env: STRESS_TIME (seconds, default 300), STRESS_RUNS (default 400), STRESS_SEED (default 1),
# STRESS_JOBS (runs at once, default 2), STRESS_CORPUS (corpus units sampled, default 40),
# STRESS_NPS (default "2 3 4 8"), STRESS_OUT (default build/stress), RUN_TIMEOUT (seconds per
# run, default 120), BIN (programs, default .), MPIRUN (default "mpirun --oversubscribe").
. "$(dirname "$0")/lib.sh"
export T
export -f mpi_run # for the runs xargs starts
STRESS_TIME=${STRESS_TIME:-300}
STRESS_RUNS=${STRESS_RUNS:-400}
STRESS_SEED=${STRESS_SEED:-1}
STRESS_JOBS=${STRESS_JOBS:-2}
STRESS_CORPUS=${STRESS_CORPUS:-40}
STRESS_NPS=${STRESS_NPS:-2 3 4 8}
export OUT=${STRESS_OUT:-build/stress}
export RUN_TIMEOUT=${RUN_TIMEOUT:-120}
LIMIT=20000
for p in pbw pcdm mesh; do
    [ -x "$BIN/$p" ] || {
        echo "stress: $BIN/$p is missing (make first)"
        exit 2
    }
done
rm -rf "$OUT"
mkdir -p "$OUT/in"
: >"$OUT/results.txt"
: >"$OUT/failures.txt"
: >"$OUT/hashes.txt"
: >"$OUT/retries.txt"
t_start=$(date +%s)
export DEADLINE=$((t_start + STRESS_TIME))

# ---- the cases: input, options, ./mesh's answer -------------------------------------------
QS=(0 20.7 25 30 33 20.7 25 28.6) # the fuzz harness's angle per option byte
ncase=0
add_case() { # path opts
    local path=$1 opts=$2 out rc kind
    case " $opts " in *" -S "*) ;; *) opts="$opts -S $LIMIT" ;; esac
    out=$(timeout 30 "$BIN/mesh" -NEP $opts "$path" 2>&1 </dev/null)
    rc=$?
    case "$rc" in
    0) kind=meshed ;;
    3) kind=unmet ;;
    1) if grep -q 'cannot meet the bounds' <<<"$out"; then kind=unmet; else kind=refused; fi ;;
    *) return ;; # over 30 s in ./mesh (or its own failure: the fuzzer's job)
    esac
    echo "$ncase|$path|$opts|$kind" >>"$OUT/cases.txt"
    ncase=$((ncase + 1))
}
: >"$OUT/cases.txt"
while IFS='|' read -r f opts want pat; do
    f=$(echo $f) opts=$(echo $opts)
    case "$f" in '#'* | '') continue ;; esac
    case "$opts" in *--cdt-only* | *--lens* | *--strict*) continue ;; esac # ./mesh's alone
    add_case "tests/fuzz/regress/$f" "$opts"
done <tests/fuzz/regress/TABLE
declare -A AREA=([square]=0.0004 [lshape]=0.0012 [wedge]=0.00004 [lake]=0.001 [holes]=0.0004
    [channel]=0.0008)
for d in square lshape wedge lake holes channel; do
    for q in 20.7 30; do add_case "data/$d.poly" "-q $q -a ${AREA[$d]}"; done
done
k=0
for f in $(ls tests/fuzz/corpus | awk -v s="$STRESS_SEED" 'BEGIN{srand(s)} {print rand() "\t" $0}' |
    sort -n | cut -f2 | head -n "$STRESS_CORPUS"); do
    u=tests/fuzz/corpus/$f
    opt=$(od -An -tu1 -N1 "$u" | tr -d ' ')
    [ -n "$opt" ] || continue
    if [ $((opt & 128)) -ne 0 ]; then in="$OUT/in/$f.node"; else in="$OUT/in/$f.poly"; fi
    tail -c +2 "$u" >"$in"
    add_case "$in" "-q ${QS[$((opt & 7))]}"
    k=$((k + 1))
done
echo "stress: $ncase cases ($k from the corpus), up to $STRESS_RUNS runs in ${STRESS_TIME} s, $STRESS_JOBS at once, seed $STRESS_SEED"

# ---- the jobs: drawn from the seed ---------------------------------------------------------
awk -v n="$STRESS_RUNS" -v s="$STRESS_SEED" -v nc="$ncase" -v nps="$STRESS_NPS" 'BEGIN {
    srand(s); k = split(nps, NP, " ")
    # runs in rounds share a few cases, so that each is compared across many schedules
    nd = nc < 12 ? nc : 12
    for (i = 0; i < nd; i++) D[i] = int(rand() * nc)
    for (j = 0; j < n; j++) {
        prog = rand() < 0.5 ? "pbw" : "pcdm"
        c = int(rand() * nc); np = NP[1 + int(rand() * k)]
        seed = rand() < 0.1 ? 0 : 1 + int(rand() * 1000000)
        extra = ""
        if (prog == "pbw") extra = "--inflight " (1 + int(rand() * 4))
        else if (rand() < 0.5) { extra = "--subdomains 8"; c = D[int(rand() * nd)] }
        else extra = "--async"
        printf "%d|%s|%d|%d|%d|%s\n", j, prog, c, np, seed, extra
    }
}' >"$OUT/jobs.txt"

# ---- one run, judged -----------------------------------------------------------------------
one() { # a line of jobs.txt
    local job prog c np seed extra line path opts kind
    IFS='|' read -r job prog c np seed extra <<<"$1"
    if [ "$(date +%s)" -ge "$DEADLINE" ]; then
        echo "$job skip" >>"$OUT/results.txt"
        return 0
    fi
    line=$(grep -m1 "^$c|" "$OUT/cases.txt")
    IFS='|' read -r _ path opts kind <<<"$line"
    local sched="--perturb $seed $extra" rcf out rc st why="" t0 t1
    rcf=$(mktemp "$T/stress_rc.XXXXXX")
    t0=$(date +%s.%N)
    local try
    for try in 1 2 3; do
        out=$(TIMEOUT=$RUN_TIMEOUT RCS_FILE=$rcf mpi_run "$np" "$BIN/$prog" -NEP $opts $sched \
            --check --stats "$path" 2>&1 </dev/null)
        rc=$?
        # the launcher failed before any rank ran (Open MPI's session directory, shared by
        # every mpirun on the machine, removed under it by another one): run it again
        [ -z "$(tr -d 'noe \n' <"$rcf")" ] && grep -q 'orte_init failed' <<<"$out" || break
        echo "$job launch-retry" >>"$OUT/retries.txt"
        sleep 1
    done
    t1=$(date +%s.%N)
    st=$(tr ' ' '\n' <"$rcf" | sort -u | tr '\n' ' ')
    if [ "$rc" = 124 ]; then
        why="timeout (${RUN_TIMEOUT} s)"
    elif grep -qw none "$rcf"; then
        why="not every rank ended"
    else
        case "$kind/$st" in
        */"0 ")
            grep -q '^meshcheck: OK' <<<"$out" || why="exit 0 without --check OK"
            [ "$kind" != refused ] || why="./mesh refuses the input, exit 0"
            ;;
        refused/"1 ") ;;
        meshed/"1 " | unmet/"1 ")
            grep -Eq 'cannot (meet the bounds|decompose)' <<<"$out" || why="exit 1 ($kind by ./mesh)"
            ;;
        meshed/"3 " | unmet/"3 ") ;;
        *) why="exit [$st] ($kind by ./mesh)" ;;
        esac
    fi
    rm -f "$rcf"
    if [ -z "$why" ] && [ "$prog" = pcdm ] && [ -n "$extra" ] && [ "$extra" != --async ] &&
        [ "$st" = "0 " ]; then
        local h
        h=$(sed -n 's/^stats: .* hash=\([0-9a-f]*\).*/\1/p' <<<"$out")
        if [ -z "$h" ]; then
            why="in rounds: no hash= in --stats"
        else
            echo "$c $h $prog -np $np $opts $sched $path" >>"$OUT/hashes.txt"
        fi
    fi
    if [ -n "$why" ]; then
        local d="$OUT/fail-$job" base
        mkdir -p "$d"
        base=$(basename "$path")
        cp "$path" "$d/$base"
        echo "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 $MPIRUN -np $np $BIN/$prog -NEP $opts $sched --check --stats $d/$base" >"$d/cmd"
        printf '%s\n' "$out" >"$d/out"
        echo "$job $prog np=$np $opts $sched $path: $why ($d)" >>"$OUT/failures.txt"
        echo "FAIL: $prog -np $np $opts $sched $path: $why ($d/cmd)"
    fi
    echo "$job $([ -n "$why" ] && echo fail || echo ok) $(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.2f", b - a}') $prog $np" >>"$OUT/results.txt"
}
export -f one

tr '\n' '\0' <"$OUT/jobs.txt" | xargs -0 -P "$STRESS_JOBS" -I{} bash -c 'one "$1"' _ {}

# ---- in rounds: one hash per case -----------------------------------------------------------
nhash=0
for c in $(awk '{print $1}' "$OUT/hashes.txt" | sort -un); do
    if [ "$(awk -v c="$c" '$1 == c {print $2}' "$OUT/hashes.txt" | sort -u | wc -l)" -gt 1 ]; then
        nhash=$((nhash + 1))
        d="$OUT/fail-hash-$c"
        mkdir -p "$d"
        awk -v c="$c" '$1 == c {$1 = ""; print}' "$OUT/hashes.txt" >"$d/runs"
        echo "hash case $c: ./pcdm --subdomains 8 gave $(awk '{print $1}' "$d/runs" | sort -u | wc -l) meshes ($d/runs)" |
            tee -a "$OUT/failures.txt"
    fi
done
ran=$(grep -vc ' skip$' "$OUT/results.txt")
skipped=$(grep -c ' skip$' "$OUT/results.txt")
nfail=$(wc -l <"$OUT/failures.txt")
echo "stress: $ran runs ($(grep -c ' pbw ' "$OUT/results.txt") ./pbw, $(grep -c ' pcdm ' "$OUT/results.txt") ./pcdm; $(wc -l <"$OUT/hashes.txt") deterministic hashes compared), $skipped not started by the deadline, $(wc -l <"$OUT/retries.txt") launcher retries, $nfail failure(s), $(($(date +%s) - t_start)) s; details in $OUT"
[ "$nfail" -eq 0 ]
