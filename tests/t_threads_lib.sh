#!/usr/bin/env bash
# t_threads_lib: pcdm_triangulate with worker threads in libpcdm_threads -- the parallel stack
# built with no MPI (runtime/mpi1, a one-process stand-in, in place of MPI's header).
#   - the library needs no MPI: libpcdm_threads.so's NEEDED names no MPI library, and neither
#     the .so nor the .a leaves an MPI symbol undefined; it exports the sequential API only;
#   - its Check suite (tests/thr_api.c: threads 1-3 one valid mesh, bad input and unmeetable
#     bounds returned as codes, the Steiner limit, host threads at once);
#   - the mesh is ./pcdm --threads T's, point for point and triangle for triangle (the files
#     ./pcdm -o writes read back): lake at -q 30 -a 2e-5 (172,888 triangles) on 2 threads, holes
#     at -q 33 on 1 and 3, square at -q 20.7 -a 1e-4 on 2 (THREADS_QUICK=1, the ThreadSanitizer
#     build of make TSAN=1 test: lake alone).
. "$(dirname "$0")/lib.sh"
so=$(ls "$B"/lib/libpcdm_threads.so.* 2>/dev/null | head -1)
a=$B/lib/libpcdm_threads.a
[ -n "$so" ] && [ -f "$a" ] && [ -x "$B/tests/thr_api" ] || fatal "libpcdm_threads or thr_api not built (make)"

needed=$(readelf -d "$so" | sed -n 's/.*NEEDED.*\[\(.*\)\]/\1/p' | tr '\n' ' ')
case $needed in
*mpi* | *MPI*) fail "$so needs MPI: $needed" ;;
*) ok "$so needs $needed(no MPI)" ;;
esac
und=$(nm -u "$a" "$so" 2>/dev/null | grep -E ' (MPI_|PMPI_|ompi_)' | sort -u | tr '\n' ' ')
[ -z "$und" ] && ok "no MPI symbol left undefined" || fail "MPI symbols undefined: $und"
exported=$(nm -D --defined-only "$so" | awk '$2 == "T" {print $3}' | sed 's/@.*//' | sort | tr '\n' ' ')
[ "$exported" = "pcdm_mesh_free pcdm_options_default pcdm_triangulate pcdm_version " ] &&
    ok "exports the sequential API: $exported" || fail "exports more (or less) than the API: $exported"

if timeout 300 "$B/tests/thr_api" >"$T/suite.txt" 2>&1; then
    ok "thr_api: $(grep -o 'Checks: [0-9]*, Failures: [0-9]*, Errors: [0-9]*' "$T/suite.txt")"
else
    fail "thr_api: $(cat "$T/suite.txt")"
fi
grep '^thr_api:' "$T/suite.txt"

same_as_pcdm() { # POLY Q A THREADS
    local f=$1 q=$2 area=$3 th=$4 args=(-q "$2")
    [ "$area" = 0 ] || args+=(-a "$area")
    if ! timeout 300 "$BIN/pcdm" --threads "$th" "${args[@]}" -o "$T/p" "$f" >"$T/p.txt" 2>&1; then
        fail "./pcdm --threads $th ${args[*]} $f: $(tail -1 "$T/p.txt")"
        return
    fi
    if timeout 300 "$B/tests/thr_api" --compare "$f" "$T/p" "$q" "$area" "$th" >"$T/c.txt" 2>&1; then
        ok "$(cat "$T/c.txt")"
    else
        fail "$(cat "$T/c.txt")"
    fi
}
same_as_pcdm data/lake.poly 30 2e-5 2
if [ "${THREADS_QUICK:-}" != 1 ]; then # the ThreadSanitizer build: lake alone
    same_as_pcdm data/holes.poly 33 0 1
    same_as_pcdm data/holes.poly 33 0 3
    same_as_pcdm data/square.poly 20.7 1e-4 2
fi
finish
