#!/usr/bin/env bash
# t_readers: files written by ./pcdm without a gather, read by other people's readers (issue 12).
# ./pcdm meshes data/lake.poly with 4 subdomains at 1, 2 and 4 ranks, writing -o PREFIX
# (.node/.ele/.poly through MPI-IO) and --vtk PREFIX.pvtu (one .vtu piece per rank).  Then tests/readers.py reads them with
#  - the PyPI `triangle` package's reader (triangle.load: Triangle's file conventions), and
#  - meshio (every .vtu piece named by the .pvtu; cell data rank and subdomain, point data
#    marker),
# and requires: the same triangles (as sets of exact coordinates) from both readers, the counts
# in the headers, no .ele attribute column (Triangle's: only with -A), segments in the .poly, cell data that
# names the writing rank, and subdomains 0..3.  (Files written by 1-8 ranks for one mesh being
# equal is tests/mpi_pout.c's; ./pcdm's mesh itself changes with the rank count.)  When python3, triangle or meshio is missing the test says so and passes
# (SKIP); `make deps` tries to install them.  Env: BIN, MPIRUN as the other tests.
. "$(dirname "$0")/lib.sh"
python3 -c 'import numpy, triangle, meshio' 2>/dev/null ||
    skip "python3 with numpy, triangle and meshio is needed (pip install triangle meshio)"
for np in 1 2 4; do
    if TIMEOUT=300 mpi_run $np "$BIN/pcdm" -q 30 -a 2e-4 --subdomains 4 -o "$T/m$np" \
        --vtk "$T/m$np.pvtu" data/lake.poly >"$T/out$np" 2>&1; then
        ok "pcdm np=$np -o, --vtk"
    else
        cat "$T/out$np"
        fatal "pcdm np=$np: ranks exit $rcs"
    fi
done
if python3 tests/readers.py "$T" 1 2 4; then
    ok "the triangle package and meshio read the files of 1, 2 and 4 ranks alike"
else
    fatal "tests/readers.py (see above)"
fi
# ./mesh's legacy VTK, binary (the default) and --vtk-ascii, and ./pcdm's pieces with
# --vtk-ascii: meshio reads each; ./mesh: the same points (bit for bit, and as the .node has them),
# triangles and markers in both encodings; ./pcdm: every piece whole, its cells its rank's
"$BIN/mesh" -q 30 -a 2e-4 -o "$T/s" --vtk "$T/sb.vtk" data/lake.poly >/dev/null 2>&1 &&
    "$BIN/mesh" -NEP -q 30 -a 2e-4 --vtk "$T/sa.vtk" --vtk-ascii data/lake.poly >/dev/null 2>&1 &&
    TIMEOUT=300 mpi_run 2 "$BIN/pcdm" -NEP -q 30 -a 2e-4 --subdomains 4 --vtk "$T/pa.pvtu" \
        --vtk-ascii data/lake.poly >/dev/null 2>&1 || fatal "writing the VTK files"
grep -q '^BINARY$' "$T/sb.vtk" && grep -q '^ASCII$' "$T/sa.vtk" || fatal "VTK encodings"
grep -q 'format="ascii"' "$T/pa_0.vtu" && grep -q 'format="appended"' "$T/m2_0.vtu" ||
    fatal ".vtu encodings"
ok "VTK and .vtu encodings"
if python3 - "$T" <<'PY'; then
import sys, meshio, numpy as np
T = sys.argv[1]
b, a = meshio.read(T + "/sb.vtk"), meshio.read(T + "/sa.vtk")
node = np.loadtxt(T + "/s.node", skiprows=1, comments="#")
ok = (np.array_equal(a.points, b.points) and np.array_equal(b.points[:, :2], node[:, 1:3])
      and np.array_equal(a.cells_dict["triangle"], b.cells_dict["triangle"])
      and np.array_equal(a.point_data["marker"], b.point_data["marker"])
      and np.array_equal(b.point_data["marker"].ravel(), node[:, 3]))
for r in (0, 1):  # two runs of ./pcdm need not give the same mesh: each piece on its own
    pa = meshio.read("%s/pa_%d.vtu" % (T, r))
    tri = pa.cells_dict["triangle"]
    ok = ok and len(tri) > 0 and tri.max() < len(pa.points) and np.all(
        pa.cell_data["rank"][0] == r) and len(pa.point_data["marker"]) == len(pa.points)
print("t_readers: ./mesh VTK binary and ASCII, ./pcdm ASCII .vtu pieces read by meshio:",
      "OK" if ok else "FAILED")
sys.exit(0 if ok else 1)
PY
    ok "meshio reads ./mesh's VTK files and ./pcdm's ASCII pieces"
else
    fail "meshio on the VTK files (see above)"
fi
finish
