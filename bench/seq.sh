#!/usr/bin/env bash
# Sequential benchmark (make bench-seq): ./mesh against Shewchuk's Triangle on the domains in
# data/, at about 1M triangles each and 10M triangles for one domain, same bounds, same run.
#
# Triangle comes from the PyPI package `triangle` (a wrapper of Triangle 1.6), installed on
# demand into build/bench-venv; only its triangulate() call is timed (bench/seq_triangle.py),
# and its memory is the wrapper process's peak RSS minus its RSS just before the call.  ./mesh
# reports its own meshing time (CDT + refinement, no file I/O) and its whole process's peak
# RSS.  When Triangle cannot be installed the bench says so and runs ./mesh alone.
#
# Each case runs REPEAT times (default 3; the 10M case REPEAT_BIG, default 1) and the fastest
# run is reported.  Area bounds: a = domain_area * 1.55 / N gives about N triangles at
# -q 20.7 (calibrated on these domains).  Environment: Q (angle bound, default 20.7),
# N1 (default 1000000), N2 (default 10000000), BIG (domain for N2, default lshape),
# DOMAINS (default: every data/*.poly), NO_TRIANGLE=1 to skip Triangle.
set -u
cd "$(dirname "$0")/.."
Q=${Q:-20.7}
N1=${N1:-1000000}
N2=${N2:-10000000}
BIG=${BIG:-lshape}
REPEAT=${REPEAT:-3}
REPEAT_BIG=${REPEAT_BIG:-1}
MESH=./mesh
VENV=build/bench-venv
PY=$VENV/bin/python
T=$(mktemp -d "${TMPDIR:-/tmp}/bench_seq.XXXXXX")
trap 'rm -rf "$T"' EXIT

[ -x "$MESH" ] || { echo "bench-seq: $MESH not built (run make)"; exit 1; }

have_triangle=0
if [ "${NO_TRIANGLE:-0}" != 1 ]; then
    if [ ! -x "$PY" ] || ! "$PY" -c 'import triangle, numpy' 2>/dev/null; then
        echo "bench-seq: installing Triangle (PyPI 'triangle') into $VENV ..."
        { python3 -m venv "$VENV" && "$PY" -m pip install -q triangle numpy; } >"$T/pip.log" 2>&1
    fi
    if "$PY" -c 'import triangle, numpy' 2>/dev/null; then
        have_triangle=1
    else
        echo "bench-seq: Triangle is not available (pip install failed, see below);"
        echo "           running ./mesh alone."
        tail -n 3 "$T/pip.log" 2>/dev/null | sed 's/^/    /'
    fi
fi

field() { # name line
    sed -n "s/.*[ :]$1=\([^ ]*\).*/\1/p" <<<"$2"
}

# best_of N command...: runs the command N times, prints the stats line of the fastest run
best_of() {
    local n=$1 best="" bw=""
    shift
    for ((i = 0; i < n; i++)); do
        local line
        line=$("$@" 2>/dev/null | grep '^stats:' | tail -n 1)
        [ -n "$line" ] || { echo "FAILED"; return; }
        local w
        w=$(field wall_s "$line")
        if [ -z "$bw" ] || awk -v a="$w" -v b="$bw" 'BEGIN { exit !(a < b) }'; then
            best=$line
            bw=$w
        fi
    done
    echo "$best"
}

printf '%s\n' "bench-seq: ./mesh vs Triangle, -q $Q, area bound = domain area * 1.55 / N"
printf '%s\n' "host: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); best of $REPEAT runs ($REPEAT_BIG for the 10M case)"
printf '%-16s %-8s %10s %10s %8s %10s %9s %7s\n' case mesher triangles steiner wall_s tri/s peak_MB B/tri
summary=()
run_case() { # domain n repeat
    local f=data/$1.poly n=$2 rep=$3
    local area a afix label
    area=$("$MESH" -NEP --cdt-only --check "$f" 2>/dev/null | sed -n 's/.* domain_area=\([^ ]*\).*/\1/p')
    [ -n "$area" ] || { echo "$1: cannot compute the domain area"; return; }
    a=$(awk -v A="$area" -v n="$n" 'BEGIN { printf "%.6g", A * 1.55 / n }')
    afix=$(awk -v a="$a" 'BEGIN { printf "%.15f", a }' | sed 's/0*$//') # Triangle: no exponent
    label="$1@$(awk -v n="$n" 'BEGIN { printf "%gM", n / 1e6 }')"
    local ml tl=""
    ml=$(best_of "$rep" "$MESH" -NEP --stats -q "$Q" -a "$a" "$f")
    if [ "$ml" = FAILED ]; then
        printf '%-16s %-8s FAILED\n' "$label" mesh
        return
    fi
    local mt ms mw mr mbpt mtps
    mt=$(field triangles "$ml"); ms=$(field steiner "$ml"); mw=$(field wall_s "$ml")
    mr=$(field peak_rss_mb "$ml"); mbpt=$(field bytes_per_tri "$ml")
    mtps=$(awk -v t="$mt" -v w="$mw" 'BEGIN { printf "%.0f", (w > 0 ? t / w : 0) }')
    printf '%-16s %-8s %10s %10s %8s %10s %9s %7s\n' "$label" mesh "$mt" "$ms" "$mw" "$mtps" "$mr" "$mbpt"
    if [ "$have_triangle" = 1 ]; then
        tl=$(best_of "$rep" "$PY" bench/seq_triangle.py "$f" "pq${Q}a${afix}Q")
        if [ "$tl" = FAILED ]; then
            printf '%-16s %-8s FAILED\n' "$label" triangle
            return
        fi
        local tt ts tw tr tb tmem tbpt ttps
        tt=$(field triangles "$tl"); ts=$(field steiner "$tl"); tw=$(field wall_s "$tl")
        tr=$(field peak_rss_mb "$tl"); tb=$(field base_rss_mb "$tl")
        tmem=$(awk -v p="$tr" -v b="$tb" 'BEGIN { printf "%.1f", p - b }')
        tbpt=$(awk -v m="$tmem" -v t="$tt" 'BEGIN { printf "%.1f", m * 1048576 / t }')
        ttps=$(awk -v t="$tt" -v w="$tw" 'BEGIN { printf "%.0f", (w > 0 ? t / w : 0) }')
        printf '%-16s %-8s %10s %10s %8s %10s %9s %7s\n' "$label" triangle "$tt" "$ts" "$tw" "$ttps" "$tmem" "$tbpt"
        local r
        r=$(awk -v ms="$ms" -v ts="$ts" -v mt="$mtps" -v tt="$ttps" -v mb="$mbpt" -v tb="$tbpt" \
            'BEGIN { printf "steiner %+.2f%%  throughput x%.2f  memory/tri x%.2f", \
                     (ms / ts - 1) * 100, mt / tt, mb / tb }')
        printf '%-16s %-8s %s\n' "$label" ratio "$r"
        summary+=("$label: $r")
    fi
}

domains=${DOMAINS:-$(for f in data/*.poly; do basename "$f" .poly; done)}
for d in $domains; do
    run_case "$d" "$N1" "$REPEAT"
done
[ -f "data/$BIG.poly" ] && run_case "$BIG" "$N2" "$REPEAT_BIG"

echo
echo "targets: throughput >= Triangle's (x >= 1), Steiner points within 5%, <= 100 bytes/triangle"
echo "(./mesh B/tri is the whole process's peak RSS per triangle; Triangle's is the wrapper's"
echo " RSS growth during triangulate(), which includes the numpy copies of its output)"
for s in "${summary[@]}"; do echo "  $s"; done
