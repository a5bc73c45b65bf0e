#!/usr/bin/env bash
# t_xwrite: the derived outputs (issue 15; mesher/io/xwrite.h, mesher/par/pextra.h) end to end:
# -e PREFIX.edge, -n PREFIX.neigh, --order2 (quadratic .node/.ele, and VTK cell type 22: one
# legacy file, also from the parallel meshers) and --msh (Gmsh 4.1), from ./mesh, ./pcdm at 1, 2 and 4 ranks and ./pbw at 3 ranks.
# Every run passes its --check; tests/xcheck.py then checks each output against the run's own
# .node/.ele (every edge once with Triangle's markers, neighbours across the right edges, -1
# only on the boundary, one midpoint node per edge, meshio reading the .msh and the VTK).  Where
# ./pcdm's mesh equals ./mesh's (as sets of exact coordinates), the edges, markers and
# neighbour relations must be equal too; on inputs whose CDT is unique, ./mesh --cdt-only gives
# Triangle's own .edge, .neigh and -o2 nodes (tests/xtriangle.py, PyPI triangle).  A .msh that cannot be written fails every rank with
# exit status 1.  Without python3 and meshio the file checks are skipped (SKIP).  Env: BIN,
# MPIRUN as the other tests.
. "$(dirname "$0")/lib.sh"
python3 -c 'import meshio' 2>/dev/null || skip "python3 with meshio is needed (pip install meshio)"
X="-q 25 -a 0.01 --check -e -n"

# name, python checks..., then the run's exit status in $rc and output in $T/out
checked() {
    local name=$1
    shift
    if [ "$rc" -ne 0 ]; then
        fail "$name: exit status $rc: $(head -3 "$T/out")"
    elif ! grep -q '^meshcheck: OK' "$T/out"; then
        fail "$name: no 'meshcheck: OK': $(head -3 "$T/out")"
    elif r=$(python3 tests/xcheck.py "$@" 2>&1); then
        ok "$name: $(echo "$r" | grep -c '^ok') outputs check"
    else
        fail "$name: $(echo "$r" | grep -v '^ok' | head -3)"
    fi
}

"$BIN/mesh" $X --order2 --msh "$T/s2.msh" --vtk "$T/s2.vtk" -o "$T/s2" data/lake.poly >"$T/out" 2>&1
rc=$?
checked "mesh -e -n --order2 --msh --vtk" "$T/s2" --o2 --msh "$T/s2.msh" --vtk "$T/s2.vtk" --keys "$T/s2.keys"
"$BIN/mesh" $X --msh "$T/s1.msh" -o "$T/s1" data/lake.poly >"$T/out" 2>&1
rc=$?
checked "mesh -e -n --msh" "$T/s1" --msh "$T/s1.msh" --keys "$T/s1.keys"

for np in 1 2 4; do
    p=$T/p$np
    mpi_run $np "$BIN/pcdm" $X --order2 --msh "$p.msh" --vtk "$p.pvtu" -o "$p" data/lake.poly >"$T/out" 2>&1
    rc=$?
    checked "pcdm np=$np -e -n --order2 --msh --vtk" "$p" --o2 --msh "$p.msh" --vtk "$p.vtk" --keys "$p.keys"
    [ ! -e "$p.pvtu" ] || fail "pcdm np=$np --order2 --vtk: linear pieces written too"
    if [ "$(grep '^T' "$p.keys" 2>/dev/null)" = "$(grep '^T' "$T/s2.keys")" ]; then
        cmp -s "$p.keys" "$T/s2.keys" && ok "pcdm np=$np: the same edges, markers and neighbours as ./mesh" ||
            fail "pcdm np=$np: the same triangles as ./mesh, other edges or neighbours"
    else
        ok "pcdm np=$np: (its mesh differs from ./mesh's; compared with its own .ele only)"
    fi
done
# several chunks per rank (the files are a few MiB), another mesher
mpi_run 3 "$BIN/pbw" -q 25 -a 1e-4 --check -e -n --order2 --msh "$T/b.msh" -o "$T/b" data/lake.poly >"$T/out" 2>&1
rc=$?
checked "pbw np=3 -a 1e-4 -e -n --order2 --msh" "$T/b" --o2 --msh "$T/b.msh"

# two triangles on four ranks: ranks without a triangle write nothing but agree on the headers
mpi_run 4 "$BIN/pbw" -q 20 --check -e -n --order2 --msh "$T/e.msh" -o "$T/e" data/square.poly >"$T/out" 2>&1
rc=$?
checked "pbw np=4 square (empty ranks)" "$T/e" --o2 --msh "$T/e.msh"

# Triangle itself (the PyPI triangle package, when installed) on the same inputs: the CDT is
# unique there, so the edges with their markers, the neighbours and the -o2 nodes must be its own
if python3 -c 'import triangle' 2>/dev/null; then
    for n in lake holes; do
        if ! "$BIN/mesh" --cdt-only -e -n --order2 -o "$T/c$n" data/$n.poly >"$T/out" 2>&1; then
            fail "mesh --cdt-only $n: $(head -2 "$T/out")"
        elif r=$(python3 tests/xtriangle.py data $n "$T/c$n" 2>&1); then
            ok "${r#ok   }"
        else
            fail "$n: $(echo "$r" | tail -2)"
        fi
    done
else
    echo "skip the comparison with Triangle: python triangle is not installed"
fi

# -o2 with -N: the quadratic .ele alone (the .node left out, no linear file written first)
for prog in mesh pcdm; do
    rm -f "$T/n2".*
    if [ $prog = mesh ]; then
        "$BIN/mesh" -q 25 --order2 -N -o "$T/n2" data/lake.poly >"$T/out" 2>&1
    else
        mpi_run 2 "$BIN/pcdm" -q 25 --order2 -N -o "$T/n2" data/lake.poly >"$T/out" 2>&1
    fi
    [ ! -e "$T/n2.node" ] && [ -e "$T/n2.poly" ] && [ "$(awk 'NR == 1 {print $2}' "$T/n2.ele")" = 6 ] &&
        ok "$prog --order2 -N: six-node .ele, no .node" ||
        fail "$prog --order2 -N: $(ls "$T" | grep n2 | tr '\n' ' ') $(head -1 "$T/n2.ele" 2>/dev/null)"
done

# a file that cannot be written: exit 1 (every rank), a message naming it
"$BIN/mesh" -q 25 -NEP --msh "$T/no/such/dir/x.msh" data/lake.poly >"$T/out" 2>&1
rc=$?
[ $rc -eq 1 ] && grep -q "no/such/dir/x.msh" "$T/out" && ok "mesh: unwritable --msh: exit 1, named" ||
    fail "mesh: unwritable --msh: exit $rc: $(head -2 "$T/out")"
mpi_run 2 "$BIN/pcdm" -q 25 -NEP --msh "$T/no/such/dir/x.msh" data/lake.poly >"$T/out" 2>&1
all_ranks 2 1 && grep -q "no/such/dir/x.msh" "$T/out" && ok "pcdm np=2: unwritable --msh: every rank exits 1" ||
    fail "pcdm np=2: unwritable --msh: statuses '$rcs': $(head -2 "$T/out")"

finish
