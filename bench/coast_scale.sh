#!/usr/bin/env bash
# bench/coast_scale.sh -- the parallel meshers on real coastlines at scale, end to end and by phase.
#
# Great Britain (49,152 vertices) and North America (876,535 vertices), GSHHG at full resolution
# in projected metres (bench/coast.py through bench/coast.sh: cached in build/bench-data, never
# committed), -q 30, an area bound for about SCALE_N triangles (domain area * 1.6 / SCALE_N, the
# rule of bench/seq.sh; the counts made are printed).  Each run is one whole process, read to
# exit, measured here by the wall clock: ./mesh, ./pcdm --threads 2 (one process), mpirun -np 2
# and -np 8 ./pcdm (rounds, the default mode), mpirun -np 2 ./pbw (the same start-up), then Triangle (the PyPI `triangle` wrapper,
# bench/seq_triangle.py: its whole process, and the triangulate() call alone).  Phases come from
# each program's -V lines: read and check, decomposition, refinement (./mesh: CDT + refinement),
# output (numbering, the interface check and Triangle's .node/.ele/.poly written with -o into
# OUTDIR/files, removed after each run; Triangle's wrapper returns arrays and writes no file).
# Peak memory: --stats'
# peak_rss_mb (the largest rank's).  SCALE_REPS repetitions (default 1), the programs
# alternating; wall times are medians.  Last line:
#   coast_scale: KEY=VALUE ...  (per coastline: x_threads2, x_np2, x_np8 = wall / ./mesh's wall,
#   decomp_pct_np2, decomp_pct_np8 = the decomposition's share of the end-to-end time,
#   tri_pct = ./pcdm's triangles against ./mesh's, in percent; x_pbw2_pcdm2 = ./pbw's wall at 2
#   ranks over ./pcdm's)
# Goals (the issue on real coastlines): x_threads2 and x_np2 <= 0.6, np8 no slower than np2,
# decomposition <= 5%, triangles within 3%, reading and checking <= the CDT, ./pbw at 2 ranks
# within 1.5x ./pcdm.
# Usage: bash bench/coast_scale.sh [OUTDIR]   (default build/bench-coast)
# Env: SCALE_N (10000000), SCALE_REPS (1), SCALE_COASTS ("gb na"), SCALE_TIMEOUT (600 s a run),
# NO_TRIANGLE=1, MESH, PCDM, PBW (programs; default ./mesh, ./pcdm, ./pbw), COAST_INSTALL (1: install the
# coastlines' package when missing; 0: cached coastlines only).
set -uo pipefail
cd "$(dirname "$0")/.."
. bench/coast.sh
OUT=${1:-build/bench-coast}
N=${SCALE_N:-10000000}
REPS=${SCALE_REPS:-1}
COASTS=${SCALE_COASTS:-gb na}
TMO=${SCALE_TIMEOUT:-600}
MESH=${MESH:-./mesh}
PCDM=${PCDM:-./pcdm}
PBW=${PBW:-./pbw}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p "$OUT/logs" "$OUT/files"
files=$OUT/files
VENV=build/bench-venv
PY=$VENV/bin/python
have_triangle=0
if [ -z "${NO_TRIANGLE:-}" ] && [ -x "$PY" ]; then
    "$PY" -c 'import triangle, numpy' 2>/dev/null ||
        { [ "${COAST_INSTALL:-1}" = 1 ] && "$PY" -m pip install -q triangle numpy >"$OUT/logs/pip.log" 2>&1; }
    "$PY" -c 'import triangle, numpy' 2>/dev/null && have_triangle=1
fi
now() { date +%s.%N; }
num() { grep -o "$1[0-9.e+-]*" | head -1 | sed "s/^$1//"; }
median() { sort -g | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]; else print "NA"}'; }
summary=()
for c in $COASTS; do
    f=$(coast_poly "$VENV" build/bench-data "$OUT/logs/coast_$c.log" "${COAST_INSTALL:-1}" "$c") || {
        echo "coast_scale: $c: no coastline (see $OUT/logs/coast_$c.log) -- skipped"
        continue
    }
    dom=$(timeout "$TMO" "$MESH" -NEP --cdt-only --check "$f" 2>/dev/null | num 'domain_area=')
    [ -n "$dom" ] || { echo "coast_scale: $c: ./mesh cannot triangulate $f -- skipped"; continue; }
    a=$(awk -v A="$dom" -v n="$N" 'BEGIN { printf "%.6g", A * 1.6 / n }')
    # Triangle's switches take no exponent ("a3.2e+06" is -a 3.2, then -e): the same bound in
    # plain decimals
    ta=$(awk -v a="$a" 'BEGIN { s = sprintf("%.15f", a); sub(/0+$/, "", s); sub(/\.$/, "", s); print s }')
    echo "coast_scale: $c: $f, -q 30 -a $a (about $N triangles)"
    confs="mesh threads2 np2 np8 pbw2"
    [ "$have_triangle" = 1 ] && confs="$confs triangle"
    for rep in $(seq 1 "$REPS"); do
        for k in $confs; do
            case $k in
            mesh) cmd=("$MESH" -q 30 -a "$a" -o "$files/$c" -V --stats "$f") ;;
            threads2) cmd=("$PCDM" --threads 2 -q 30 -a "$a" -o "$files/$c" -V --stats "$f") ;;
            np2 | np8) cmd=(mpirun --oversubscribe -np "${k#np}" "$PCDM" -q 30 -a "$a" -o "$files/$c" -V --stats "$f") ;;
            pbw2) cmd=(mpirun --oversubscribe -np 2 "$PBW" -q 30 -a "$a" -o "$files/$c" -V --stats "$f") ;;
            triangle) cmd=("$PY" bench/seq_triangle.py "$f" "pq30a${ta}Q") ;;
            esac
            log=$OUT/logs/${c}_${k}_r$rep
            echo "${cmd[*]}" >"$log.cmd"
            t0=$(now)
            timeout "$TMO" "${cmd[@]}" >"$log.out" 2>"$log.err"
            echo $? >"$log.rc"
            t1=$(now)
            awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f\n", b - a }' >"$log.wall"
            rm -f "$files/$c".*
        done
    done
    printf '%-10s %8s %7s %7s %8s %7s %8s %8s %8s %10s %7s\n' run wall_s x_mesh read_s decomp_s \
        decomp% refine_s output_s peak_MB triangles tri%
    mwall=$(cat "$OUT"/logs/"${c}"_mesh_r*.wall | median)
    mtri=$(grep -h '^stats:' "$OUT/logs/${c}_mesh_r1.out" | num ' triangles=')
    for k in $confs; do
        log=$OUT/logs/${c}_${k}_r1
        if [ "$(cat "$log.rc")" != 0 ]; then
            printf '%-10s FAILED (exit %s; %s)\n' "$k" "$(cat "$log.rc")" "$log.err"
            summary+=("${c}_${k}=FAILED")
            continue
        fi
        w=$(cat "$OUT"/logs/"${c}_${k}"_r*.wall | median)
        x=$(awk -v w="$w" -v m="$mwall" 'BEGIN { printf "%.2f", w / m }')
        rd=$(num 'read and checked in ' <"$log.err")
        dc=$(num 'automatic, ' <"$log.err")
        if [ "$k" = mesh ]; then
            rf=$(awk '/triangulation/ { for (i = 1; i <= NF; i++) { if ($i == "triangulation") t = $(i + 1); if ($i == "refinement") r = $(i + 1) } } END { if (t != "") printf "%.3f", t + r }' "$log.err")
        else
            rf=$(num 'refinement ' <"$log.err")
        fi
        st=$(grep -h '^stats:' "$log.out" | tail -1)
        op=$(num ' output_s=' <<<"$st")
        pk=$(num ' peak_rss_mb=' <<<"$st")
        tri=$(num ' triangles=' <<<"$st")
        if [ "$k" = triangle ]; then
            rf=$(num ' mesh_s=' <<<"$st")
            pk=$(num ' peak_rss_mb=' <<<"$st")
        fi
        dp=NA
        [ -n "$dc" ] && dp=$(awk -v d="$dc" -v w="$w" 'BEGIN { printf "%.1f", 100 * d / w }')
        tp=$(awk -v t="$tri" -v m="$mtri" 'BEGIN { if (t > 0 && m > 0) printf "%+.2f", 100 * (t - m) / m; else print "NA" }')
        printf '%-10s %8s %7s %7s %8s %7s %8s %8s %8s %10s %7s\n' "$k" "$w" "$x" "${rd:-NA}" \
            "${dc:-NA}" "$dp" "${rf:-NA}" "${op:-NA}" "${pk:-NA}" "${tri:-NA}" "$tp"
        case $k in
        threads2 | np2 | np8) summary+=("${c}_x_$k=$x") ;;
        esac
        case $k in np2 | np8) summary+=("${c}_decomp_pct_$k=$dp") ;; esac
        [ "$k" = np2 ] && summary+=("${c}_tri_pct=$tp") && np2wall=$w
        [ "$k" = pbw2 ] && summary+=("${c}_x_pbw2_pcdm2=$(awk -v w="$w" -v p="${np2wall:-0}" 'BEGIN { if (p > 0) printf "%.2f", w / p; else print "NA" }')")
        [ "$k" = triangle ] && summary+=("${c}_x_triangle=$x")
    done
    echo
done
echo "coast_scale: ${summary[*]}"
