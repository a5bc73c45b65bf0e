#!/usr/bin/env bash
# t_install: the library as a user gets it.  `make install PREFIX=$tmp` (programs, libpcdm.a,
# libpcdm.so with its soname links, include/pcdm.h, lib/pkgconfig/pcdm.pc), then the examples
# (examples/triangulate.c, examples/triangulate_par.c) compiled with the plain C compiler and
# nothing but `pkg-config --cflags --libs pcdm` from the temporary prefix -- against the shared
# library, and once against the static one -- run, and their meshes validated by the installed
# ./meshcheck; the parallel example runs on 3 ranks (its halves: 2 ranks keeping parts, 1 rank
# collecting the mesh).  Then a staged install (DESTDIR, PREFIX=/opt/pcdm: the .pc file names
# the PREFIX, the files land under DESTDIR) and `make uninstall`, which must leave nothing.
# Env: MPIRUN (default "mpirun --oversubscribe"), CC_USER (default cc), SANITIZE=1 (skipped: the
# sanitizer build's library needs the sanitizer runtime, which a user's plain link lacks).
set -u
cd "$(dirname "$0")/.."
MPIRUN=${MPIRUN:-mpirun --oversubscribe}
CC_USER=${CC_USER:-cc}
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
if [ "${SANITIZE:-}" = 1 ] || [ "${DEBUG:-}" = 1 ] || [ "${B:-build}" != build ]; then
    echo "t_install: SKIP: sanitizer/debug build (the installed library is the normal build's)"
    exit 0
fi
tmp=$(mktemp -d "${TMPDIR:-/tmp}/t_install.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
# the version is include/pcdm.h's (the one place it is stated)
ver() { sed -n "s/^#define PCDM_VERSION_$1 *\([0-9]*\).*/\1/p" include/pcdm.h; }
M=$(ver MAJOR) V=$(ver MAJOR).$(ver MINOR).$(ver PATCH)
fail=0
bad() { echo "t_install: FAIL: $*"; fail=1; }

p=$tmp/usr
make -s --no-print-directory install PREFIX="$p" >"$tmp/install.log" 2>&1 ||
    { cat "$tmp/install.log"; echo "t_install: FAIL: make install"; exit 1; }
for f in bin/mesh bin/pcdm bin/pbw bin/meshcheck include/pcdm.h lib/libpcdm.a \
    lib/libpcdm.so.$V lib/libpcdm.so.$M lib/libpcdm.so lib/pkgconfig/pcdm.pc; do
    [ -e "$p/$f" ] || bad "make install did not install $f"
done
[ "$(readlink "$p/lib/libpcdm.so")" = libpcdm.so.$M ] || bad "libpcdm.so does not link to libpcdm.so.$M"
readelf -d "$p/lib/libpcdm.so.$V" | grep -q "SONAME.*libpcdm.so.$M\\]" || bad "soname is not libpcdm.so.$M"
# only the public API is exported
exported=$(nm -D --defined-only "$p/lib/libpcdm.so" | awk '$2 == "T" {print $3}' | sed 's/@.*//' | sort | tr '\n' ' ')
[ "$exported" = "pcdm_mesh_free pcdm_options_default pcdm_triangulate pcdm_triangulate_par pcdm_version " ] ||
    bad "libpcdm.so exports more (or less) than the API: $exported"
# no internal header leaks: pcdm.h includes only system and MPI headers
grep '#include' "$p/include/pcdm.h" | grep -qv -e '<mpi.h>' -e '<stdint.h>' && bad "pcdm.h includes an internal header"

export PKG_CONFIG_PATH=$p/lib/pkgconfig
[ "$(pkg-config --modversion pcdm)" = "$V" ] || bad "pkg-config --modversion pcdm: $(pkg-config --modversion pcdm)"
cflags=$(pkg-config --cflags pcdm) libs=$(pkg-config --libs pcdm)
echo "cflags: $cflags"
echo "libs: $libs"

# the sequential example against the shared library
$CC_USER -std=c11 -Wall -Wextra -Werror examples/triangulate.c $cflags $libs -o "$tmp/tri" ||
    bad "examples/triangulate.c does not build with pkg-config's flags"
if [ -x "$tmp/tri" ]; then
    readelf -d "$tmp/tri" | grep -q "NEEDED.*libpcdm.so.$M\\]" || bad "triangulate is not linked to libpcdm.so.$M"
    (cd "$tmp" && LD_LIBRARY_PATH=$p/lib ./tri seq) || bad "triangulate failed"
    "$p/bin/meshcheck" -q 25 -a 0.5 "$tmp/seq.poly" "$tmp/seq.1" || bad "triangulate's mesh fails meshcheck"
fi
# against the static library (the same flags, libpcdm.a in place of -lpcdm)
$CC_USER -std=c11 examples/triangulate.c $cflags ${libs/-lpcdm/$p/lib/libpcdm.a} -o "$tmp/tri_static" ||
    bad "examples/triangulate.c does not link with libpcdm.a"
if [ -x "$tmp/tri_static" ]; then
    readelf -d "$tmp/tri_static" | grep -q libpcdm && bad "tri_static needs libpcdm.so"
    (cd "$tmp" && ./tri_static st) || bad "triangulate (static) failed"
    cmp -s "$tmp/st.1.ele" "$tmp/seq.1.ele" || bad "the static and shared builds made different meshes"
fi
# the parallel example: 3 ranks = a half of 2 (parts) and a half of 1 (the whole mesh)
$CC_USER -std=c11 -Wall -Wextra -Werror examples/triangulate_par.c $cflags $libs -o "$tmp/trp" ||
    bad "examples/triangulate_par.c does not build with pkg-config's flags"
if [ -x "$tmp/trp" ]; then
    (cd "$tmp" && LD_LIBRARY_PATH=$p/lib timeout 120 $MPIRUN -np 3 -x LD_LIBRARY_PATH ./trp par) ||
        bad "triangulate_par on 3 ranks failed"
    "$p/bin/meshcheck" -q 25 -a 0.5 "$tmp/par.poly" "$tmp/par.1" || bad "triangulate_par's mesh fails meshcheck"
fi

# staged install: DESTDIR + PREFIX, then uninstall leaves nothing
s=$tmp/stage
make -s --no-print-directory install DESTDIR="$s" PREFIX=/opt/pcdm >"$tmp/stage.log" 2>&1 || bad "make install DESTDIR"
[ -e "$s/opt/pcdm/lib/libpcdm.so.$V" ] || bad "DESTDIR install: no $s/opt/pcdm/lib/libpcdm.so.$V"
grep -qx 'prefix=/opt/pcdm' "$s/opt/pcdm/lib/pkgconfig/pcdm.pc" || bad "DESTDIR install: pcdm.pc does not name PREFIX"
make -s --no-print-directory uninstall DESTDIR="$s" PREFIX=/opt/pcdm >>"$tmp/stage.log" 2>&1 || bad "make uninstall"
left=$(find "$s" -type f -o -type l)
[ -z "$left" ] || bad "make uninstall left: $left"
make -s --no-print-directory uninstall PREFIX="$p" >>"$tmp/stage.log" 2>&1 || bad "make uninstall"
[ -z "$(find "$p" -type f -o -type l)" ] || bad "make uninstall left files in $p"
[ "$fail" = 0 ] && echo "t_install: OK"
exit "$fail"
