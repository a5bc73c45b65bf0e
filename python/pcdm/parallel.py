"""pcdm.parallel: the parallel meshers from Python (mpi4py), libpcdm's pcdm_triangulate_par.

>>> from mpi4py import MPI
>>> import pcdm.parallel
>>> part = pcdm.parallel.triangulate(tri, "pq30a0.001", comm=MPI.COMM_WORLD)

Collective: every rank of ``comm`` calls with the same input and switches.  PCDM (Chew,
Chrisochoides, Sukup, TR-97-17 section 3) cuts the domain into subdomains, each rank refines its
own; ``method="pbw"`` runs parallel Bowyer-Watson (section 2) instead.  Each rank gets its part
(``root=None``): ``vertices`` (the ones its triangles use), ``vertex_markers``, ``triangles``
(local indices into ``vertices``), ``segments``, ``segment_markers``, ``vertex_global`` (int64:
each vertex's number in the whole mesh), ``vertex_owned`` (bool: exactly one rank owns each
number), ``triangle_first`` (the part's first triangle number in the whole mesh) and
``global_vertices``/``global_triangles``/``global_segments``; with ``root=R`` rank R gets the
whole mesh, the others an empty one.  Switches: those ``pcdm.triangulate`` takes but ``A``,
``e``, ``n`` and ``r`` (sequential only), and without ``q`` the default angle bound 20.7 (the
parallel meshers always refine).  Unlike ``pcdm.triangulate`` (a drop-in for ``triangle``),
the input is read as a PSLG with or without ``p``, and a vertex given twice is meshed and
numbered once: the whole mesh's numbering is the input's distinct vertices in their order, then
the Steiner points.  Built where MPI and METIS are (``pip install .[mpi]``).
"""

from __future__ import annotations

from typing import Any, Dict, Mapping, Optional

import numpy as np

from . import MeshError, _core, _input

try:
    from . import _par
except ImportError as e:  # built without MPI
    raise ImportError(
        "pcdm.parallel needs the package built with MPI and METIS (mpicc on PATH, "
        "libmetis-dev; pip install .[mpi]): " + str(e)) from None

__all__ = ["triangulate"]


def triangulate(
    tri: Mapping[str, Any],
    opts: str = "",
    comm: Any = None,
    *,
    method: str = "pcdm",
    subdomains: int = 0,
    threads: int = 1,
    root: Optional[int] = None,
    min_angle: Optional[float] = None,
    max_area: Optional[float] = None,
) -> Dict[str, Any]:
    """Collective over ``comm`` (an mpi4py communicator; None: ``MPI.COMM_WORLD``): this rank's
    part of the mesh of ``tri`` under ``opts`` (see the module's help).  Raises ValueError (the
    same on every rank) on bad input or switches, MeshError when the bounds cannot be met.
    ``threads``: worker threads per rank refining its subdomains at once (PCDM only); the mesh is
    the same for any count, and one process of several threads is ``comm=MPI.COMM_SELF``."""
    if comm is None:
        from mpi4py import MPI
        comm = MPI.COMM_WORLD
    s = _core.parse(opts.replace("z", ""))
    for k, what in (("region_attributes", "A"), ("edges", "e"), ("neighbors", "n"),
                    ("refine", "r"), ("order2", "o2")):
        if s[k]:
            raise ValueError(f"option -{what} works with pcdm.triangulate only")
    if method not in ("pcdm", "pbw"):
        raise ValueError(f"method {method!r}: 'pcdm' or 'pbw'")
    d = _input(tri)
    default = s["min_angle"] if s["q_given"] else _core.DEFAULT_MIN_ANGLE
    ma = float(min_angle) if min_angle is not None else default
    area = float(max_area) if max_area is not None else s["max_area"]
    code, message, mesh = _par.triangulate(
        int(comm.py2f()), d["vertices"], d["vertex_markers"], d["vertex_attributes"],
        d["segments"], d["segment_markers"], d["holes"], d["regions"], ma, area,
        s["max_steiner"], bool(s["circumcenters"]), bool(s["convex_hull"]),
        0 if method == "pcdm" else 1, int(subdomains), -1 if root is None else int(root),
        int(threads))
    if mesh is None:
        raise (MeshError if code == 4 else MemoryError if code == 8 else ValueError)(message)
    return mesh
