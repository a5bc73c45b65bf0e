#!/usr/bin/env bash
# t_layers: the layers of the source tree, read from its #include lines.  LAYERS below lists
# them bottom to top (the README's Layout says the same in words; include/pcdm.h, the public
# header, includes nothing of ours and sits below the layers that implement it); names on one
# line are one level.  A file may include the headers of its own folder and of the levels below its own:
#  - never a header of a level above (up), nor of another folder of its own level (sideways:
#    ./pcdm and ./pbw know nothing of each other);
#  - never a *_impl.h or *_internal.h header of another folder (such a header is its folder's
#    inside; what another layer needs is declared in a named header);
#  - every quoted include resolves as the compiler resolves it (the including file's folder,
#    then -Iinclude -Iruntime -Imesher), and every folder holding sources is in LAYERS;
#  - runtime/mpi1, the one-process MPI stand-in, is included by no file outside it: the MPI-free
#    build (libpcdm_threads, the Python package's threaded path) alone reaches it, as <mpi.h>
#    with -Iruntime/mpi1 (and the Makefile names that folder on an include path in THR_CFLAGS
#    only).
# Scanned: runtime/, mesher/, include/, apps/, bench/, examples/ (tests/ are white-box and may
# include any header).
# The sequential library (the sources mesher/seq_sources.txt lists: libpcdm_seq and the Python
# package) needs neither MPI nor METIS nor the runtime: no file it lists, nor any header such a
# file includes (followed through quoted includes), includes <mpi.h>, <metis.h> or a runtime/
# header, and every line of the list names at least one file.  The checker first runs on a small tree made here with one violation of
# each kind, and must report exactly those (so it cannot pass by seeing nothing); then on the
# repository, where it must report nothing but the known exceptions (KNOWN), each of which must
# still occur.
. "$(dirname "$0")/lib.sh"

LAYERS=(
    "runtime/mpi1"
    "runtime"
    "mesher/base"
    "mesher/geom"
    "mesher/io"
    "mesher/check"
    "mesher/seq"
    "mesher/bounds"
    "mesher/decomp"
    "mesher/par"
    "mesher/pcdm mesher/pbw"
    "include"
    "mesher/run"
    "mesher/api"
    "apps bench examples"
)
# Known violations, "FILE INCLUDE", each to go (none today).  Delete a line when its include
# is gone (the test fails on a line that no longer occurs).
KNOWN=()

declare -A LEVEL
for ((i = 0; i < ${#LAYERS[@]}; i++)); do
    for d in ${LAYERS[i]}; do LEVEL[$d]=$i; done
done

# layer_check ROOT: one line "FILE INCLUDE: problem" per violation in the tree at ROOT
layer_check() {
    local root=$1 f dir inc target tdir why
    (cd "$root" && find runtime mesher include apps bench examples -name '*.[ch]' 2>/dev/null) |
        sort | while read -r f; do
        dir=$(dirname "$f")
        if [ -z "${LEVEL[$dir]:-}" ]; then
            echo "$f -: folder $dir is in no layer (add it to LAYERS in tests/t_layers.sh)"
            continue
        fi
        sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$root/$f" |
            while read -r inc; do
                target=""
                for base in "$dir" include runtime mesher; do
                    if [ -e "$root/$base/$inc" ]; then
                        target=$(realpath -m --relative-to="$root" "$root/$base/$inc")
                        break
                    fi
                done
                if [ -z "$target" ]; then
                    echo "$f $inc: does not resolve (own folder, include/, runtime/, mesher/)"
                    continue
                fi
                tdir=$(dirname "$target") why=""
                if [ "$tdir" = "$dir" ]; then
                    continue
                elif [ -z "${LEVEL[$tdir]:-}" ]; then
                    why="$target is in no layer"
                elif [ "${LEVEL[$tdir]}" -gt "${LEVEL[$dir]}" ]; then
                    why="points up: $dir includes $tdir, a layer above it"
                elif [ "${LEVEL[$tdir]}" -eq "${LEVEL[$dir]}" ]; then
                    why="points sideways: $dir and $tdir are one level"
                fi
                if [ "$tdir" = runtime/mpi1 ]; then
                    why="${why:+$why; }runtime/mpi1 (the MPI stand-in) is reached only as <mpi.h> by the MPI-free build"
                fi
                case $(basename "$target") in
                *_impl.h | *_internal.h) why="${why:+$why; }$target is internal to $tdir" ;;
                esac
                [ -z "$why" ] || echo "$f $inc: $why"
            done
    done
}

# 1. the checker on a tree with one violation of each kind, and lines that are fine
S=$T/tree
mkdir -p "$S"/runtime/mpi1 "$S"/mesher/{base,geom,seq,pcdm,pbw,new} "$S"/apps
touch "$S"/runtime/rt.h "$S"/runtime/mpi1/mpi.h "$S"/mesher/base/base.h "$S"/mesher/seq/mesh.h "$S"/mesher/seq/mesh_impl.h \
    "$S"/mesher/pcdm/pcdm.h "$S"/mesher/new/x.c
printf '#include "rt.h"\n#include "base/base.h"\n' >"$S"/runtime/rt.c
printf '#include "base/base.h"\n#include <stdio.h>\n#include "seq/mesh.h"\n' >"$S"/mesher/geom/g.c
printf '#include "mesh_impl.h"\n#include "seq/mesh.h"\n' >"$S"/mesher/seq/mesh.c
printf '#include "seq/mesh.h"\n  #  include "seq/mesh_impl.h" // x\n#include "pcdm.h"\n' >"$S"/mesher/pcdm/p.c
printf '#include "pcdm/pcdm.h"\n#include "nosuch.h"\n' >"$S"/mesher/pbw/w.c
printf '#include "pcdm/pcdm.h"\n#include "rt.h"\n#include "mpi1/mpi.h"\n' >"$S"/apps/m.c
printf '#include "mpi.h"\n' >"$S"/runtime/mpi1/mpi1.c
layer_check "$S" >"$T/self.txt"
cat >"$T/self.want" <<'EOF'
apps/m.c mpi1/mpi.h: runtime/mpi1 (the MPI stand-in) is reached only as <mpi.h> by the MPI-free build
mesher/geom/g.c seq/mesh.h: points up: mesher/geom includes mesher/seq, a layer above it
mesher/new/x.c -: folder mesher/new is in no layer (add it to LAYERS in tests/t_layers.sh)
mesher/pbw/w.c pcdm/pcdm.h: points sideways: mesher/pbw and mesher/pcdm are one level
mesher/pbw/w.c nosuch.h: does not resolve (own folder, include/, runtime/, mesher/)
mesher/pcdm/p.c seq/mesh_impl.h: mesher/seq/mesh_impl.h is internal to mesher/seq
runtime/rt.c base/base.h: points up: runtime includes mesher/base, a layer above it
EOF
if diff "$T/self.want" "$T/self.txt" >"$T/self.diff"; then
    ok "the checker finds the planted violations, and only those ($(wc -l <"$T/self.txt"))"
else
    fail "the checker on the planted tree (< wanted, > found): $(cat "$T/self.diff")"
fi

# seq_check ROOT: one line "FILE INCLUDE: problem" per include of the sequential library's files
# (ROOT/mesher/seq_sources.txt, and the headers they reach) that needs MPI, METIS or the runtime
seq_check() {
    local root=$1 pat f inc base target
    local -A seen=()
    local todo=()
    while read -r pat; do
        [ -n "$pat" ] || continue
        local n=0
        for f in $(cd "$root" && compgen -G "$pat"); do
            todo+=("$f") n=$((n + 1))
        done
        [ "$n" -gt 0 ] || echo "mesher/seq_sources.txt $pat: names no file"
    done < <(sed 's/#.*//; s/[[:space:]]*$//' "$root/mesher/seq_sources.txt")
    while [ ${#todo[@]} -gt 0 ]; do
        f=${todo[0]} todo=("${todo[@]:1}")
        [ -z "${seen[$f]:-}" ] || continue
        seen[$f]=1
        sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*<\(mpi\.h\|metis\.h\)>.*/\1/p' \
            "$root/$f" | while read -r inc; do
            echo "$f <$inc>: the sequential library includes <$inc>"
        done
        while read -r inc; do
            for base in "$(dirname "$f")" include runtime mesher; do
                if [ -e "$root/$base/$inc" ]; then
                    target=$(realpath -m --relative-to="$root" "$root/$base/$inc")
                    case $target in
                    runtime/*) echo "$f $inc: the sequential library includes the runtime" ;;
                    *) todo+=("$target") ;;
                    esac
                    break
                fi
            done
        done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$root/$f")
    done
}

# 1b. the sequential library's checker on a planted tree: a listed file reaching <mpi.h> through
# a header, one including <metis.h>, one the runtime, a pattern that names nothing
S2=$T/seqtree
mkdir -p "$S2"/mesher/{base,geom,io} "$S2"/runtime
printf '# comment\nmesher/base/*.c\nmesher/geom/g.c  # trailing\nmesher/io/none*.c\n' >"$S2"/mesher/seq_sources.txt
printf '#include "base/base.h"\n#include <stdio.h>\n' >"$S2"/mesher/base/base.c
printf '#include "io/w.h"\n' >"$S2"/mesher/base/b2.c
printf '#include <stddef.h>\n' >"$S2"/mesher/base/base.h
printf '#include "base/base.h"\n#include <mpi.h>\n' >"$S2"/mesher/io/w.h
printf '#include <metis.h>\n#include "rt.h"\n' >"$S2"/mesher/geom/g.c
touch "$S2"/runtime/rt.h "$S2"/mesher/io/p.c
seq_check "$S2" | sort >"$T/seq_self.txt"
cat >"$T/seq_self.want" <<'EOF2'
mesher/geom/g.c <metis.h>: the sequential library includes <metis.h>
mesher/geom/g.c rt.h: the sequential library includes the runtime
mesher/io/w.h <mpi.h>: the sequential library includes <mpi.h>
mesher/seq_sources.txt mesher/io/none*.c: names no file
EOF2
if diff "$T/seq_self.want" "$T/seq_self.txt" >"$T/seq_self.diff"; then
    ok "the sequential library's checker finds the planted violations, and only those ($(wc -l <"$T/seq_self.txt"))"
else
    fail "the sequential library's checker on the planted tree (< wanted, > found): $(cat "$T/seq_self.diff")"
fi

# 2. the repository
n0=$(nfailed)
layer_check . >"$T/found.txt"
: >"$T/known.txt"
[ ${#KNOWN[@]} -eq 0 ] || printf '%s\n' "${KNOWN[@]}" | sort >"$T/known.txt"
nfound=0
while read -r f inc why; do
    nfound=$((nfound + 1))
    if grep -qxF "$f ${inc%:}" "$T/known.txt"; then
        echo "known exception, to go: $f $inc $why"
    else
        fail "$f: #include \"${inc%:}\": $why"
    fi
done <"$T/found.txt"
while read -r f inc; do
    grep -q "^$f $inc: " "$T/found.txt" ||
        fail "KNOWN lists '$f $inc', which no longer occurs: delete it from tests/t_layers.sh"
done <"$T/known.txt"
seq_check . >"$T/seq_found.txt"
while read -r line; do
    fail "$line"
done <"$T/seq_found.txt"
nseq=$(sed 's/#.*//' mesher/seq_sources.txt | while read -r pat; do [ -z "$pat" ] || compgen -G "$pat"; done | wc -l)
[ -s "$T/seq_found.txt" ] || ok "the sequential library's $nseq sources reach neither <mpi.h> nor <metis.h> nor the runtime"
# the Makefile puts runtime/mpi1 on an include path in THR_CFLAGS only
bad=$(grep -n -- '-Iruntime/mpi1' Makefile | grep -v '^[0-9]*:THR_CFLAGS = ')
nmk=$(grep -c -- '-Iruntime/mpi1' Makefile)
if [ -z "$bad" ] && [ "$nmk" -ge 1 ]; then
    ok "the Makefile names runtime/mpi1 as an include path in THR_CFLAGS only ($nmk line)"
else
    fail "the Makefile names -Iruntime/mpi1 outside THR_CFLAGS (or nowhere): ${bad:-none}"
fi
nfiles=$(find runtime mesher include apps bench examples -name '*.[ch]' | wc -l)
[ "$(nfailed)" != "$n0" ] ||
    ok "$nfiles files: no include points up or sideways or into another folder's inside (but ${#KNOWN[@]} known exceptions)"
finish
