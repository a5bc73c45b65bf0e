#!/usr/bin/env bash
# t_install: the library as a user gets it.  `make install PREFIX=$T` (programs, libpcdm.a,
# libpcdm.so with its soname links, libpcdm_seq and libpcdm_threads (.a, .so), include/pcdm.h and pcdm_par.h,
# lib/pkgconfig/pcdm.pc and pcdm-seq.pc), then the examples
# (examples/triangulate.c, examples/triangulate_par.c) compiled with the plain C compiler and
# nothing but `pkg-config --cflags --libs pcdm` from the temporary prefix -- against the shared
# library, and once against the static one -- run, and their meshes validated by the installed
# ./meshcheck; the parallel example runs on 3 ranks (its halves: 2 ranks keeping parts, 1 rank
# collecting the mesh).  The sequential example is built a third time against libpcdm_seq with
# `pkg-config pcdm-seq` alone (no MPI, no METIS: neither may be NEEDED) and must make the same
# mesh.  Then a staged install (DESTDIR, PREFIX=/opt/pcdm: the .pc file names
# the PREFIX, the files land under DESTDIR) and `make uninstall`, which must leave nothing.
# Env: MPIRUN (default "mpirun --oversubscribe"), CC_USER (default cc), SANITIZE=1 (skipped: the
# sanitizer build's library needs the sanitizer runtime, which a user's plain link lacks).
. "$(dirname "$0")/lib.sh"
CC_USER=${CC_USER:-cc}
if [ "${SANITIZE:-}" = 1 ] || [ "${DEBUG:-}" = 1 ] || [ "$B" != build ]; then
    skip "sanitizer/debug build (the installed library is the normal build's)"
fi
# the version is include/pcdm.h's (the one place it is stated)
ver() { sed -n "s/^#define PCDM_VERSION_$1 *\([0-9]*\).*/\1/p" include/pcdm.h; }
M=$(ver MAJOR) V=$(ver MAJOR).$(ver MINOR).$(ver PATCH)

p=$T/usr
make -s --no-print-directory install PREFIX="$p" >"$T/install.log" 2>&1 ||
    {
        cat "$T/install.log"
        fatal "make install"
    }
for f in bin/mesh bin/pcdm bin/pbw bin/meshcheck include/pcdm.h include/pcdm_par.h lib/libpcdm.a \
    lib/libpcdm.so.$V lib/libpcdm.so.$M lib/libpcdm.so lib/pkgconfig/pcdm.pc lib/libpcdm_seq.a \
    lib/libpcdm_seq.so.$V lib/libpcdm_seq.so.$M lib/libpcdm_seq.so lib/pkgconfig/pcdm-seq.pc \
    lib/libpcdm_threads.a lib/libpcdm_threads.so.$V lib/libpcdm_threads.so.$M lib/libpcdm_threads.so \
    lib/pkgconfig/pcdm-threads.pc; do
    [ -e "$p/$f" ] || fail "make install did not install $f"
done
[ "$(readlink "$p/lib/libpcdm.so")" = libpcdm.so.$M ] || fail "libpcdm.so does not link to libpcdm.so.$M"
readelf -d "$p/lib/libpcdm.so.$V" | grep -q "SONAME.*libpcdm.so.$M\\]" || fail "soname is not libpcdm.so.$M"
# only the public API is exported
exported=$(nm -D --defined-only "$p/lib/libpcdm.so" | awk '$2 == "T" {print $3}' | sed 's/@.*//' | sort | tr '\n' ' ')
[ "$exported" = "pcdm_mesh_free pcdm_options_default pcdm_triangulate pcdm_triangulate_par pcdm_version " ] ||
    fail "libpcdm.so exports more (or less) than the API: $exported"
exported=$(nm -D --defined-only "$p/lib/libpcdm_seq.so" | awk '$2 == "T" {print $3}' | sed 's/@.*//' | sort | tr '\n' ' ')
[ "$exported" = "pcdm_mesh_free pcdm_options_default pcdm_triangulate pcdm_version " ] ||
    fail "libpcdm_seq.so exports more (or less) than the sequential API: $exported"
readelf -d "$p/lib/libpcdm_seq.so" | grep NEEDED | grep -q -i -e mpi -e metis &&
    fail "libpcdm_seq.so needs MPI or METIS: $(readelf -d "$p/lib/libpcdm_seq.so" | grep NEEDED | tr -s ' ')"
# no internal header leaks: pcdm.h includes only <stdint.h> (no MPI: the sequential half),
# pcdm_par.h only <mpi.h> and pcdm.h
grep '#include' "$p/include/pcdm.h" | grep -qv -e '<stdint.h>' && fail "pcdm.h includes more than <stdint.h>"
grep '#include' "$p/include/pcdm_par.h" | grep -qv -e '<mpi.h>' -e '"pcdm.h"' && fail "pcdm_par.h includes more than <mpi.h> and pcdm.h"

export PKG_CONFIG_PATH=$p/lib/pkgconfig
[ "$(pkg-config --modversion pcdm)" = "$V" ] || fail "pkg-config --modversion pcdm: $(pkg-config --modversion pcdm)"
cflags=$(pkg-config --cflags pcdm) libs=$(pkg-config --libs pcdm)
echo "cflags: $cflags"
echo "libs: $libs"

# the sequential example against the shared library
$CC_USER -std=c11 -Wall -Wextra -Werror examples/triangulate.c $cflags $libs -o "$T/tri" ||
    fail "examples/triangulate.c does not build with pkg-config's flags"
if [ -x "$T/tri" ]; then
    readelf -d "$T/tri" | grep -q "NEEDED.*libpcdm.so.$M\\]" || fail "triangulate is not linked to libpcdm.so.$M"
    (cd "$T" && LD_LIBRARY_PATH=$p/lib ./tri seq) || fail "triangulate failed"
    "$p/bin/meshcheck" -q 25 -a 0.5 "$T/seq.poly" "$T/seq.1" || fail "triangulate's mesh fails meshcheck"
fi
# against the static library (the same flags, libpcdm.a in place of -lpcdm)
$CC_USER -std=c11 examples/triangulate.c $cflags ${libs/-lpcdm/$p/lib/libpcdm.a} -o "$T/tri_static" ||
    fail "examples/triangulate.c does not link with libpcdm.a"
if [ -x "$T/tri_static" ]; then
    readelf -d "$T/tri_static" | grep -q libpcdm && fail "tri_static needs libpcdm.so"
    (cd "$T" && ./tri_static st) || fail "triangulate (static) failed"
    cmp -s "$T/st.1.ele" "$T/seq.1.ele" || fail "the static and shared builds made different meshes"
fi
# against libpcdm_seq: pkg-config pcdm-seq alone, neither MPI nor METIS
scflags=$(pkg-config --cflags pcdm-seq) slibs=$(pkg-config --libs pcdm-seq)
echo "pcdm-seq: $scflags $slibs"
case "$scflags $slibs" in *mpi* | *metis*) fail "pkg-config pcdm-seq names MPI or METIS: $scflags $slibs" ;; esac
$CC_USER -std=c11 -Wall -Wextra -Werror examples/triangulate.c $scflags $slibs -o "$T/tri_seq" ||
    fail "examples/triangulate.c does not build with pkg-config pcdm-seq's flags"
if [ -x "$T/tri_seq" ]; then
    needed=$(readelf -d "$T/tri_seq" | sed -n 's/.*NEEDED.*\[\(.*\)\]/\1/p' | tr '\n' ' ')
    case "$needed" in *libpcdm_seq.so.$M*) ;; *) fail "tri_seq is not linked to libpcdm_seq.so.$M: $needed" ;; esac
    case "$needed" in *mpi* | *metis*) fail "tri_seq needs MPI or METIS: $needed" ;; esac
    (cd "$T" && LD_LIBRARY_PATH=$p/lib ./tri_seq sq) || fail "triangulate (libpcdm_seq) failed"
    cmp -s "$T/sq.1.ele" "$T/seq.1.ele" || fail "libpcdm_seq and libpcdm made different meshes"
    cmp -s "$T/sq.1.node" "$T/seq.1.node" || fail "libpcdm_seq and libpcdm made different vertices"
fi
# against libpcdm_threads: pkg-config pcdm-threads alone (METIS, no MPI); threads 0 (the
# example's default) is the sequential mesh
tcflags=$(pkg-config --cflags pcdm-threads) tlibs=$(pkg-config --libs pcdm-threads)
echo "pcdm-threads: $tcflags $tlibs"
case "$tcflags $tlibs" in *mpi*) fail "pkg-config pcdm-threads names MPI: $tcflags $tlibs" ;; esac
$CC_USER -std=c11 -Wall -Wextra -Werror examples/triangulate.c $tcflags $tlibs -o "$T/tri_thr" ||
    fail "examples/triangulate.c does not build with pkg-config pcdm-threads' flags"
if [ -x "$T/tri_thr" ]; then
    needed=$(readelf -d "$T/tri_thr" "$p/lib/libpcdm_threads.so.$V" | sed -n 's/.*NEEDED.*\[\(.*\)\]/\1/p' | tr '\n' ' ')
    case "$needed" in *libpcdm_threads.so.$M*) ;; *) fail "tri_thr is not linked to libpcdm_threads.so.$M: $needed" ;; esac
    case "$needed" in *mpi*) fail "tri_thr or libpcdm_threads needs MPI: $needed" ;; esac
    (cd "$T" && LD_LIBRARY_PATH=$p/lib ./tri_thr th) || fail "triangulate (libpcdm_threads) failed"
    cmp -s "$T/th.1.ele" "$T/seq.1.ele" || fail "libpcdm_threads and libpcdm made different meshes"
fi
# the parallel example: 3 ranks = a half of 2 (parts) and a half of 1 (the whole mesh)
$CC_USER -std=c11 -Wall -Wextra -Werror examples/triangulate_par.c $cflags $libs -o "$T/trp" ||
    fail "examples/triangulate_par.c does not build with pkg-config's flags"
if [ -x "$T/trp" ]; then
    (cd "$T" && LD_LIBRARY_PATH=$p/lib MPI_X="-x LD_LIBRARY_PATH" mpi_run 3 ./trp par) ||
        fail "triangulate_par on 3 ranks failed"
    "$p/bin/meshcheck" -q 25 -a 0.5 "$T/par.poly" "$T/par.1" || fail "triangulate_par's mesh fails meshcheck"
fi

# staged install: DESTDIR + PREFIX, then uninstall leaves nothing
s=$T/stage
make -s --no-print-directory install DESTDIR="$s" PREFIX=/opt/pcdm >"$T/stage.log" 2>&1 || fail "make install DESTDIR"
[ -e "$s/opt/pcdm/lib/libpcdm.so.$V" ] || fail "DESTDIR install: no $s/opt/pcdm/lib/libpcdm.so.$V"
grep -qx 'prefix=/opt/pcdm' "$s/opt/pcdm/lib/pkgconfig/pcdm.pc" || fail "DESTDIR install: pcdm.pc does not name PREFIX"
make -s --no-print-directory uninstall DESTDIR="$s" PREFIX=/opt/pcdm >>"$T/stage.log" 2>&1 || fail "make uninstall"
left=$(find "$s" -type f -o -type l)
[ -z "$left" ] || fail "make uninstall left: $left"
make -s --no-print-directory uninstall PREFIX="$p" >>"$T/stage.log" 2>&1 || fail "make uninstall"
[ -z "$(find "$p" -type f -o -type l)" ] || fail "make uninstall left files in $p"
[ "$(nfailed)" -gt 0 ] || ok "installed, built against with pkg-config (shared and static), run, staged, uninstalled"
finish
