"""pcdm.parallel under mpirun (tests/t_python.sh runs it at 2 and 3 ranks): every rank's part
adds up to the whole (owned vertices, triangles, triangle_first as the prefix sums), the whole
mesh collected on a root passes the validator with the bounds, its size is within 3% of the
sequential mesh's (about 20K triangles: on smaller meshes the interface splits of the
asynchronous protocol alone move the count by up to 3%, as tests/t_pcdm.sh found) (pcdm.triangulate with the library's diametral circles), PBW as well, and bad
input raises the same ValueError on every rank; threads=2 gives the mesh of one thread.  Prints "par_check: OK ..." on rank 0 and exits
0 only when every rank passed."""
import os
import sys

import numpy as np
from mpi4py import MPI

import pcdm
import pcdm.parallel

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "bench"))
from poly import read_poly  # noqa: E402

comm = MPI.COMM_WORLD
problems = []
devs = []


def expect(c, what):
    if not c:
        problems.append(what)


pts, segs, holes = read_poly(os.path.join(HERE, "..", "..", "data", "lake.poly"))
d = {"vertices": np.array(pts), "segments": np.array(segs), "holes": np.array(holes)}
seq = pcdm.triangulate(d, "pq30a0.00015", lenses=False)
for method in ("pcdm", "pbw"):
    p = pcdm.parallel.triangulate(d, "pq30a0.00015", comm=comm, method=method)
    nt = len(p["triangles"])
    expect(comm.allreduce(int(p["vertex_owned"].sum())) == p["global_vertices"],
           f"{method}: owned vertices do not add up to global_vertices")
    expect(comm.allreduce(nt) == p["global_triangles"], f"{method}: triangles do not add up")
    below = comm.exscan(nt)  # collective: every rank calls it (rank 0 gets None)
    expect(p["triangle_first"] == (below if comm.rank else 0),
           f"{method}: triangle_first is not the prefix sum")
    expect(p["triangles"].max() < len(p["vertices"]), f"{method}: a local index out of range")
    w = pcdm.parallel.triangulate(d, "pq30a0.00015", comm=comm, method=method, root=0)
    if comm.rank == 0:
        rep = pcdm.check(w, d, q=30, a=0.00015)
        expect(rep["ok"], f"{method}: the whole mesh: {rep['summary']}")
        dev = len(w["triangles"]) / len(seq["triangles"]) - 1
        devs.append(f"{method} {len(w['triangles'])} ({dev:+.1%})")
        expect(abs(dev) <= 0.03, f"{method}: {len(w['triangles'])} triangles against "
               f"{len(seq['triangles'])} sequential ({dev:+.1%})")
    else:
        expect(len(w["triangles"]) == 0, f"{method}: a rank other than root got triangles")
# threads=2: each rank refines its subdomains on two worker threads; the mesh is the one of
# one thread (the same vertices on the root)
t1 = pcdm.parallel.triangulate(d, "pq30a0.001", comm=comm, root=0)
t2 = pcdm.parallel.triangulate(d, "pq30a0.001", comm=comm, root=0, threads=2)
if comm.rank == 0:
    expect(len(t1["triangles"]) > 0 and np.array_equal(t1["vertices"], t2["vertices"])
           and np.array_equal(t1["triangles"], t2["triangles"]),
           "threads=2: not the mesh of one thread")
try:
    pcdm.parallel.triangulate({"vertices": [[0, 0], [1, 1], [2, 2]]}, "pq", comm=comm)
    expect(False, "collinear input: no ValueError")
except ValueError as e:
    msgs = comm.allgather(str(e))
    expect(len(set(msgs)) == 1 and "collinear" in msgs[0], f"different errors: {msgs}")
try:
    pcdm.parallel.triangulate(d, "pqe", comm=comm)
    expect(False, "e: no ValueError")
except ValueError:
    pass
allp = comm.gather(problems)
if comm.rank == 0:
    bad = [f"rank {r}: {x}" for r, ps in enumerate(allp) for x in ps]
    print("\n".join(bad) if bad else
          f"par_check: OK {comm.size} ranks: {', '.join(devs)} triangles against "
          f"{len(seq['triangles'])} sequentially")
sys.exit(1 if comm.allreduce(len(problems)) else 0)
