#!/usr/bin/env bash
# ./pbw end to end (the Parallel Meshing Algorithm, parallel Bowyer-Watson with remote cavity
# expansion, locks and undo): every domain in data/ at 1, 2, 3, 4 and 8 ranks and -q 20.7, every
# domain at 8 ranks and -q 30, perturbed delivery (seeds 1 2 3) at 8 ranks on two domains and
# at 2 and 4 ranks, --phases (which must postpone the cross-rank cavities), the general path
# alone (PBW_NO_FAST_PATH=1), bad input and usage.  Each run must exit 0, pass ./pbw --check and ./meshcheck with
# the same bounds and with every non-input edge locally Delaunay (--interfaces-delaunay: the
# merged mesh of one distributed Delaunay mesh has no artificial constraints), end with the
# stats line, and have within 3% of ./mesh's triangle count.  Then what issue 10 asks of every
# mesher: no input runs forever -- -q 35 and -q 40 on lake stop with "cannot meet the bounds"
# and exit 1 on every rank (each rank's exit status is recorded), and every row of the fuzz
# regression table that ./mesh meshes or answers "cannot meet the bounds" gets that answer or a
# mesh that passes --check from ./pbw (pbw_split_off_line.poly also at 2, 3, 4 and 8 ranks under
# perturbed delivery and several --inflight); the Steiner limit gives exit 3 on every rank; and the
# test-only fault PBW_TEST_BREAK_IFACE=R (rank R
# loses a triangle at a rank boundary) makes every rank exit 1 through the always-on interface
# check, writing nothing; PBW_TEST_BREAK_DELAUNAY=R (rank R flips an edge the general path
# committed) the same through the always-on end check of the Delaunay property.  Env: BIN (programs; "." or build/san/bin), MPIRUN ("mpirun
# --oversubscribe"), SANITIZE=1 (fewer runs).
. "$(dirname "$0")/lib.sh"

# -a per domain: about 6-8K triangles (sanitizer build: about half)
declare -A AREA=([square]=0.0002 [lshape]=0.0006 [wedge]=0.00002 [lake]=0.0005 [holes]=0.0002
    [channel]=0.0004)
DOMAINS="square lshape wedge lake holes channel"
NPS="1 2 3 4 8"
SEEDS="1 2 3"
PERT_DOMAINS="square holes"
if [ "${SANITIZE:-}" = 1 ]; then
    # Same sizes as the normal run: below ~5K triangles the 3% count comparison is noise.
    DOMAINS="square wedge holes"
    NPS="1 4 8"
    SEEDS="1"
    PERT_DOMAINS="lake"
fi

declare -A SEQ
seq_count() { # domain q -> ./mesh's triangle count (cached)
    local k="$1/$2"
    if [ -z "${SEQ[$k]:-}" ]; then
        SEQ[$k]=$("$BIN/mesh" -NEP -q "$2" -a "${AREA[$1]}" --stats "data/$1.poly" |
            sed -n 's/^stats: triangles=\([0-9]*\).*/\1/p')
        [ -n "${SEQ[$k]}" ] || fail "./mesh gave no triangle count for $1" # counted in $(...) too
    fi
    echo "${SEQ[$k]}"
}

n=0
run() { # np domain q extra-args...: one run, its checks
    local np=$1 d=$2 q=$3
    shift 3
    local a=${AREA[$d]} pre="$T/m$n" out rc n0
    n=$((n + 1)) n0=$(nfailed)
    out=$(mpi_run "$np" "$BIN/pbw" -q "$q" -a "$a" -o "$pre" --check --stats "$@" "data/$d.poly" 2>&1)
    rc=$?
    local last
    last=$(tail -n 1 <<<"$out")
    echo "np=$np $d -q $q $* -> $rc: $last"
    if [ "$rc" -ne 0 ]; then
        echo "$out" | tail -n 20
        fail "./pbw exit $rc, ranks $(cat "$T/rcs") (np=$np $d -q $q $*)"
        return
    fi
    grep -q '^meshcheck: OK' <<<"$out" || fail "--check did not pass (np=$np $d $*)"
    grep -Eq '^stats: ranks=[0-9]+ triangles=[0-9]+ vertices=[0-9]+ rsr=[0-9]+ undone=[0-9]+ min_angle=[0-9.]+ mesh_s=[0-9.]+ busy_max_s=[0-9.]+ busy_sum_s=[0-9.]+ comm_pct=[0-9.]+ undo_pct=[0-9.]+' <<<"$last" ||
        fail "last line is not the stats line: $last"
    grep -q "^stats: ranks=$np " <<<"$last" || fail "stats line names the wrong rank count"
    grep -Eq '^rsr: expansion=[0-9]+ reply=[0-9]+ release=[0-9]+ commit=[0-9]+ split=[0-9]+' \
        <<<"$out" || fail "no RSR breakdown line"
    grep -Eq '^blocking: tasks_blocked=[0-9]+ most_at_once=[0-9]+ wait_sum_s=[0-9.]+ wait_max_s=[0-9.]+ remote_cavity_pct=[0-9.]+$' \
        <<<"$out" || fail "no blocking-queue line"
    if [ "$np" = 1 ]; then
        grep -q ' rsr=0 ' <<<"$last" || fail "RSRs on one rank: $last"
        grep -q '^blocking: tasks_blocked=0 ' <<<"$out" || fail "blocked tasks on one rank"
    else
        grep -q ' rsr=0 ' <<<"$last" && fail "no RSR at $np ranks: $last"
    fi
    local mc
    mc=$("$BIN/meshcheck" "data/$d.poly" "$pre" -q "$q" -a "$a" --interfaces-delaunay 2>&1) ||
        fail "meshcheck: $mc (np=$np $d -q $q $*)"
    local got want
    got=$(sed -n 's/^stats: ranks=[0-9]* triangles=\([0-9]*\).*/\1/p' <<<"$last")
    want=$(seq_count "$d" "$q")
    awk -v g="$got" -v w="$want" 'BEGIN { d = g - w; if (d < 0) d = -d; exit !(d <= 0.03 * w) }' ||
        fail "triangle count $got vs ./mesh $want (more than 3% apart; np=$np $d -q $q $*)"
    [ "$(nfailed)" != "$n0" ] || ok "np=$np $d -q $q $*: checked, $got triangles (./mesh $want)"
}

# every domain, 1 2 4 8 ranks, -q 20.7
for d in $DOMAINS; do
    for np in $NPS; do run "$np" "$d" 20.7; done
done
# -q 30 at 8 ranks
for d in $DOMAINS; do run 8 "$d" 30; done
# perturbed delivery (delays and reorders RSRs between sources), several seeds, 8 ranks
for d in $PERT_DOMAINS; do
    for s in $SEEDS; do run 8 "$d" 20.7 --perturb "$s"; done
done
run 8 lshape 30 --perturb 7
# and at 2 and 4 ranks
for s in $SEEDS; do
    run 2 lake 20.7 --perturb "$s"
    run 4 wedge 20.7 --perturb "$s"
done
# ghosts (issue 13): a cavity whose remote neighbours are not in conflict is decided on their
# ghosts at the lower rank and stays local (a ghost commit sends nothing: the other side's stale
# link is forwarded by the tombstone when an expansion follows it)
out=$(mpi_run 8 "$BIN/pbw" -NEP -q 20.7 -a "${AREA[lake]}" --check --stats data/lake.poly 2>&1) ||
    fail "./pbw with ghosts: ranks $(cat "$T/rcs"): $(tail -n 5 <<<"$out")"
grep -q '^meshcheck: OK' <<<"$out" || fail "--check did not pass (ghosts)"
grep -Eq '^cavities: .* ghosted=[1-9][0-9]* ' <<<"$out" &&
    ok "ghosts: $(grep -o 'ghosted=[0-9]* forwarded=[0-9]*' <<<"$out")" ||
    fail "no cavity kept local by ghosts"
# the data-parallel variant: local cavities first, then the rest (phase 1 postpones the
# cavities that reach another rank)
run 4 lake 20.7 --phases
out=$(mpi_run 4 "$BIN/pbw" -NEP -q 20.7 -a "${AREA[lake]}" --phases --stats data/lake.poly 2>&1) ||
    fail "./pbw --phases: ranks $(cat "$T/rcs"): $(tail -n 5 <<<"$out")"
grep -Eq '^cavities: .* postponed=[1-9][0-9]* ' <<<"$out" && ok "--phases postponed cavities" ||
    fail "--phases postponed nothing"
run 8 channel 20.7 --phases --perturb 2
# imbalanced decomposition
run 4 holes 20.7 --imbalance 2
# the paper's choices: circumcenters only, requests serviced after every work item
run 4 lake 30 --circumcenters --poll 1
# one or many distributed cavities in flight per rank
run 4 lake 20.7 --inflight 1
run 8 holes 20.7 --inflight 16 --perturb 5
# every cavity through the general protocol (no local fast path, pbw_local.c), 1 and 4 ranks
PBW_NO_FAST_PATH=1 run 1 lake 30
PBW_NO_FAST_PATH=1 run 4 holes 20.7 --perturb 3

# bad input and impossible requests: one clear message, non-zero exit from every rank
out=$(TIMEOUT=60 mpi_run 4 "$BIN/pbw" -NEP --strict tests/bad/self_intersecting.poly 2>&1)
rc=$?
echo "bad input -> $rc: $(head -n 1 <<<"$out")"
[ "$rc" -ne 0 ] || fail "bad input accepted"
all_ranks 4 1 || fail "bad input: not exit 1 on every rank: $(cat "$T/rcs")"
grep -q 'self_intersecting.poly:11: segment 4 crosses segment 2' <<<"$out" &&
    ok "bad input: exit 1 on every rank, FILE:LINE message" || fail "bad input message missing: $out"
out=$(TIMEOUT=60 mpi_run 2 "$BIN/pbw" "$T/nosuch.poly" 2>&1)
rc=$?
[ "$rc" -ne 0 ] || fail "missing input accepted"
grep -q 'nosuch.poly' <<<"$out" && ok "missing input: exit $rc, file named" ||
    fail "missing-file message does not name the file: $out"
out=$(TIMEOUT=60 mpi_run 2 "$BIN/pbw" -NEP -q abc data/square.poly 2>&1)
rc=$?
[ "$rc" -ne 0 ] && ok "bad -q: exit $rc" || fail "bad -q accepted"
out=$(TIMEOUT=60 mpi_run 1 "$BIN/pbw" --help 2>&1)
rc=$?
[ "$rc" -eq 0 ] || fail "--help exit $rc"
grep -q 'pbw' <<<"$out" && ok "--help names the program" || fail "--help does not name the program"

# no input runs forever (issue 10): a bound beyond reach ends with a clear error on every rank.
# PBW's insertion order depends on message timing, so at -q 35 it occasionally does reach the
# bound (about 1 run in 20 at 2 ranks): that run must then pass --check, as any run that exits
# 0 must; -q 40 is never reached, and most -q 35 runs are not.
bounded() { # label np args...: "cannot meet" with exit 1 on every rank, or exit 0 with --check OK
    local label=$1 np=$2
    shift 2
    out=$(mpi_run "$np" "$BIN/pbw" -NEP --check "$@" 2>&1)
    local rc=$?
    echo "np=$np $label -> [$(cat "$T/rcs")]: $(grep -m1 -o 'cannot meet.*\|^meshcheck: OK' <<<"$out" | cut -c1-80)"
    n=$((n + 1))
    if [ "$rc" -eq 124 ]; then
        fail "$label at $np ranks: timeout"
    elif all_ranks "$np" 1; then
        if grep -q "^pbw: data/lake.poly: cannot meet the bounds: [0-9]* triangles" <<<"$out"; then
            ok "$label at $np ranks: cannot meet the bounds, exit 1 on every rank"
        else
            fail "$label at $np ranks: exit 1 without 'cannot meet the bounds': $out"
        fi
        unmet_runs=$((unmet_runs + 1))
    elif all_ranks "$np" 0 && grep -q '^meshcheck: OK' <<<"$out"; then
        ok "$label at $np ranks: met, --check OK"
        met_runs=$((met_runs + 1))
    else
        fail "$label at $np ranks: neither 'cannot meet' on every rank nor a checked mesh: $(cat "$T/rcs") $out"
    fi
}
unmet_runs=0 met_runs=0
for np in 1 2 4 8; do
    for q in 35 40; do
        [ "${SANITIZE:-}" = 1 ] && [ "$np" != 2 ] && continue
        bounded "lake -q $q" "$np" -q "$q" data/lake.poly
        [ "$q" != 40 ] || grep -q 'cannot meet the bounds' <<<"$out" || fail "lake -q 40 was met?"
    done
done
# with an area bound too, and the warning above 34 degrees is printed once
bounded "lake -q 35 -a 0.0005" 3 -q 35 -a 0.0005 data/lake.poly
[ "$(grep -c 'warning: -q 35 above about 34' <<<"$out")" -eq 1 ] || fail "not one warning: $out"
echo "bounds beyond reach: $unmet_runs runs stopped with 'cannot meet the bounds', $met_runs met them"

# the fuzz regression table (tests/fuzz/regress/TABLE) through ./pbw: rows ./mesh meshes must
# mesh and pass --check (or be refused by the decomposition, issue 11, not by PBW); rows ./mesh
# answers "cannot meet the bounds" must get that answer, on every rank (or the same refusal)
REG_NPS="1 2 3"
[ "${SANITIZE:-}" = 1 ] && REG_NPS="2"
while IFS='|' read -r f opts want pat; do
    f=$(echo $f) opts=$(echo $opts) want=$(echo $want)
    case "$f" in '#'* | '') continue ;; esac
    case "$opts" in *--cdt-only* | *--lens*) continue ;; esac # ./mesh only
    if [ "$want" = 0 ]; then
        kind=meshed
    elif grep -q 'cannot meet the bounds' <<<"$pat"; then
        kind=unmet
    else
        continue
    fi
    for np in $REG_NPS; do
        out=$(mpi_run "$np" "$BIN/pbw" -NEP $opts --check "tests/fuzz/regress/$f" 2>&1 </dev/null)
        rc=$?
        n=$((n + 1))
        if [ "$rc" -eq 124 ]; then
            fail "regress $f $opts np=$np: timeout"
            continue
        fi
        st=$(tr ' ' '\n' <"$T/rcs" | sort -u | tr '\n' ' ')
        if grep -qw none "$T/rcs"; then
            fail "regress $f $opts np=$np: not every rank ended: $(cat "$T/rcs")"
            continue
        fi
        if [ "$kind" = meshed ]; then
            if [ "$st" = "0 " ]; then
                grep -q '^meshcheck: OK' <<<"$out" || {
                    fail "regress $f $opts np=$np: no --check OK"
                    continue
                }
            elif [ "$st" = "1 " ] && grep -q "^pbw: cannot decompose" <<<"$out"; then
                :
            else
                fail "regress $f $opts np=$np: exit [$st]: $(grep -v '^ ' <<<"$out" | head -n 3)"
                continue
            fi
        elif [ "$st" = "0 " ]; then
            # PBW's timing-dependent order may reach a bound ./mesh does not (see above)
            grep -q '^meshcheck: OK' <<<"$out" || {
                fail "regress $f $opts np=$np: exit 0, no --check OK"
                continue
            }
        elif [ "$st" = "1 " ] && grep -q "^pbw: cannot decompose" <<<"$out"; then
            :
        elif ! { [ "$st" = "1 " ] && grep -q 'cannot meet the bounds' <<<"$out"; }; then
            fail "regress $f $opts np=$np: exit [$st], wanted 1 and 'cannot meet the bounds'"
            continue
        fi
        ok "np=$np regress $f $opts ($kind) -> [$st]"
    done
done <tests/fuzz/regress/TABLE

# split points a rounding put off their line beside slivers 1e-8 high: on several ranks the
# order of the splits varies with the schedule, and a split whose new edge from an apex was not
# locally Delaunay (refused now, rules.h mesh_rules_off_line) made --check fail in about 1 run in
# 5 at 3 ranks; here at 2, 3, 4 and 8 ranks under perturbed delivery and several --inflight
PSEEDS="1 2 3 4 5 6"
[ "${SANITIZE:-}" = 1 ] && PSEEDS="1 2"
for np in 2 3 4 8; do
    for s in $PSEEDS; do
        inf=$((s % 4 + 1))
        out=$(mpi_run "$np" "$BIN/pbw" -NEP -q 0 -S 20000 --check --perturb "$s" --inflight "$inf" \
            tests/fuzz/regress/pbw_split_off_line.poly 2>&1 </dev/null)
        rc=$?
        n=$((n + 1))
        if [ "$rc" -eq 124 ]; then
            fail "pbw_split_off_line np=$np --perturb $s: timeout"
        elif all_ranks "$np" 0 && grep -q '^meshcheck: OK' <<<"$out"; then
            ok "np=$np pbw_split_off_line.poly -q 0 -S 20000 --perturb $s --inflight $inf"
        else
            fail "pbw_split_off_line np=$np --perturb $s --inflight $inf: exit [$(cat "$T/rcs")]: $(grep -v '^ ' <<<"$out" | head -n 3)"
        fi
    done
done

# the Steiner limit: exit 3 on every rank, a conforming mesh written (checked without bounds);
# not reached: exit 0
rm -f "$T"/s100.*
out=$(mpi_run 3 "$BIN/pbw" -S 100 -a 0.0001 --check -o "$T/s100" data/square.poly 2>&1)
echo "np=3 -S 100 -> [$(cat "$T/rcs")]"
all_ranks 3 3 || fail "-S 100: not every rank exited 3: $(cat "$T/rcs") $out"
grep -q "Steiner point limit (-S 100) reached" <<<"$out" && grep -q '^meshcheck: OK' <<<"$out" &&
    [ -s "$T/s100.ele" ] && ok "-S 100: message, --check OK, mesh written" ||
    fail "-S 100: no message, no --check OK or no mesh: $out"
# a fuzz find (tests/fuzz/pending_par, 9a6bcc4c...): with the ghosts, once rank 0 reached its
# share of the limit the other rank's cavities into it died and retried for ever (it needed
# 20000 Steiner points then; since encroachment splits the forced-angle rule makes pointless are
# skipped it meshes with about 150, so -S 100 keeps it at the limit)
out=$(mpi_run 2 "$BIN/pbw" -NEP -q 30 -S 100 --check tests/fuzz/regress/pbw_ghost_steiner_limit.poly 2>&1)
echo "np=2 fuzz -S 100 -> [$(cat "$T/rcs")]"
all_ranks 2 3 && grep -q '^meshcheck: OK' <<<"$out" && ok "pbw_ghost_steiner_limit: exit 3 on both ranks" ||
    fail "pbw_ghost_steiner_limit: want exit 3 on both ranks and --check OK: $(cat "$T/rcs") $out"
out=$(mpi_run 3 "$BIN/pbw" -NEP -S 100000 -a 0.01 --check data/square.poly 2>&1)
all_ranks 3 0 && ok "-S not reached: exit 0 on every rank" || fail "-S not reached: $(cat "$T/rcs") $out"
n=$((n + 2))

# the test-only fault: rank 1 loses a triangle at a rank boundary; the always-on end check
# (the interface check before any output) must fail every rank and write nothing
for np in 2 3 4 8; do
    [ "${SANITIZE:-}" = 1 ] && [ "$np" != 3 ] && continue
    rm -f "$T"/broken.*
    n0=$(nfailed)
    out=$(PBW_TEST_BREAK_IFACE=1 MPI_X="-x PBW_TEST_BREAK_IFACE" mpi_run "$np" "$BIN/pbw" -q 30 \
        -a 0.001 -o "$T/broken" data/lake.poly 2>&1)
    echo "np=$np PBW_TEST_BREAK_IFACE=1 -> [$(cat "$T/rcs")]: $(grep -m1 -o 'interface check failed.*' <<<"$out" | cut -c1-90)"
    all_ranks "$np" 1 || fail "fault np=$np: not every rank exited 1: $(cat "$T/rcs") $out"
    grep -q "^pbw: data/lake.poly: rank [0-9]*: interface check failed: edge" <<<"$out" ||
        fail "fault np=$np: no interface-check message: $out"
    ! ls "$T"/broken.* >/dev/null 2>&1 || fail "fault np=$np: a broken mesh was written"
    [ "$(nfailed)" != "$n0" ] || ok "fault np=$np: every rank exits 1 through the interface check, nothing written"
    n=$((n + 1))
done
# the other test-only fault: rank R flips an edge between two triangles the general path
# committed (a wrong commit); the always-on end check of the Delaunay property must fail every
# rank with its message and write nothing (rank 0 at np=1: the check runs on one rank too; there
# every cavity is local and the fast paths, the kernel's cavities as in ./mesh, leave no general
# commit to break, so that run takes the general path: PBW_NO_FAST_PATH=1)
for np in 1 2 3 4 8; do
    [ "${SANITIZE:-}" = 1 ] && [ "$np" != 3 ] && continue
    r=$((np > 1 ? 1 : 0))
    nf=$((np > 1 ? 0 : 1))
    rm -f "$T"/broken.*
    n0=$(nfailed)
    out=$(PBW_NO_FAST_PATH=$nf PBW_TEST_BREAK_DELAUNAY=$r \
        MPI_X="-x PBW_TEST_BREAK_DELAUNAY -x PBW_NO_FAST_PATH" mpi_run "$np" "$BIN/pbw" \
        -q 30 -a 0.001 -o "$T/broken" data/lake.poly 2>&1)
    echo "np=$np PBW_TEST_BREAK_DELAUNAY=$r -> [$(cat "$T/rcs")]: $(grep -m1 -o 'the mesh is not Delaunay.*' <<<"$out" | cut -c1-90)"
    all_ranks "$np" 1 || fail "Delaunay fault np=$np: not every rank exited 1: $(cat "$T/rcs") $out"
    grep -q "^pbw: data/lake.poly: rank $r: the mesh is not Delaunay: edge (" <<<"$out" ||
        fail "Delaunay fault np=$np: no end-check message: $out"
    ! ls "$T"/broken.* >/dev/null 2>&1 || fail "Delaunay fault np=$np: a mesh was written"
    [ "$(nfailed)" != "$n0" ] || ok "Delaunay fault np=$np: every rank exits 1 through the end check, nothing written"
    n=$((n + 1))
done
# the same run without the faults is whole (so the fault, not the input, broke it), and the
# stats line ends with the end check's cost
run 3 lake 30
out=$(mpi_run 3 "$BIN/pbw" -NEP -q 30 -a 0.001 --stats data/lake.poly 2>&1)
grep -Eq '^stats: .* endcheck_max_s=[0-9.]+ endcheck_sum_s=[0-9.]+$' <<<"$out" &&
    ok "the stats line ends with the end check's seconds" ||
    fail "the stats line does not end with the end check's seconds: $(tail -n 1 <<<"$out")"
n=$((n + 1))
echo "$TEST: $n runs"
finish
