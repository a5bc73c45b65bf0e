"""pcdm: quality constrained Delaunay triangulation (Ruppert/Chew refinement with exact
predicates), a drop-in for the ``triangle`` package.

>>> import pcdm
>>> t = pcdm.triangulate({"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]]}, "qa0.1")
>>> sorted(t)
['triangles', 'vertex_markers', 'vertices']
>>> pcdm.check(t, {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]]}, q=20, a=0.1)["ok"]
True

``pcdm.triangulate(tri, opts)`` takes what ``triangle.triangulate`` takes -- a dict of arrays
with the keys ``vertices``, ``vertex_markers``, ``vertex_attributes``, ``segments``,
``segment_markers``, ``holes``, ``regions`` (and ``triangles`` with ``triangle_max_area`` for
``r``) -- and Triangle's switch string, read by the command line's own parser (``./mesh``):
``p`` (read the segments, holes and regions: without it, as in Triangle, the vertices' convex
hull is meshed), ``q[DEG]``, ``a[AREA]``, ``A``, ``c``, ``e``, ``n``, ``S[N]``, ``Q``, ``V``,
``r``, ``z`` (indices are always zero-based here).  It returns the same keys, dtypes and shapes,
input vertex i at index i (a repeated vertex too, in no triangle), then the Steiner points.
Switches the command line refuses raise ``ValueError`` with its message, as do output files
(``-o``, ``--vtk``, ...: the mesh is returned, not written) and characters that are no switch.
Meshing releases the GIL, so Python threads mesh at once.  ``pcdm.check`` runs the project's
validator.

The rest of the ``triangle`` package's API, in Python on ``triangulate``: ``delaunay``,
``convex_hull`` and ``voronoi`` of a point set; ``loads``, ``load`` and ``get_data`` reading
Triangle's files (``get_data`` from the folders ``path=`` and ``PCDM_DATA`` name, then the
package's own examples); ``plot``, ``compare`` and ``show_data`` drawing with matplotlib
(imported only when they are called).
"""

from __future__ import annotations

import re
import unicodedata
import warnings
from typing import Any, Callable, Dict, Mapping, NamedTuple, Optional, Tuple, Union

import numpy as np

from . import _core

__all__ = [
    "triangulate",
    "check",
    "__version__",
    "MeshError",
    "delaunay",
    "convex_hull",
    "voronoi",
    "loads",
    "load",
    "get_data",
    "data_path",
    "show_data",
    "plot",
    "compare",
]

__version__: str = _core.version()

Mesh = Dict[str, np.ndarray]
SizeRule = Union[Callable[[np.ndarray, float], bool], Mapping[str, Any]]


class MeshError(ValueError):
    """The bounds cannot be met on this input (no mesh), or the size rule failed."""


# ---- input conversion -------------------------------------------------------------------------


def _floats(tri: Mapping[str, Any], key: str, cols: Optional[int]) -> Optional[np.ndarray]:
    if key not in tri or tri[key] is None:
        return None
    try:
        a = np.asarray(tri[key])
        if a.dtype.kind == "c":
            raise ValueError(f"{key}: complex numbers (dtype {a.dtype}); coordinates are real")
        a = a.astype(np.float64, copy=False)
    except (TypeError, ValueError) as e:
        if str(e).startswith(key):
            raise
        raise ValueError(f"{key}: not an array of numbers ({e})") from None
    if cols is None:  # vertex attributes: (n, k) or (n,)
        if a.ndim == 1:
            a = a.reshape(-1, 1)
        if a.ndim != 2:
            raise ValueError(f"{key}: expected shape (N, K), got {a.shape}")
    else:
        if a.size == 0:
            a = a.reshape(0, cols)
        if a.ndim != 2 or a.shape[1] != cols:
            raise ValueError(f"{key}: expected shape (N, {cols}), got {a.shape}")
    bad = np.argwhere(~np.isfinite(a))
    if len(bad):
        i = tuple(int(x) for x in bad[0])
        raise ValueError(f"{key}[{i[0]}]: {float(a[i])} is not a finite number")
    return np.ascontiguousarray(a)


def _ints(tri: Mapping[str, Any], key: str, cols: int) -> Optional[np.ndarray]:
    """Indices or markers as int32; cols 0: one per row (shape (N,) or (N, 1))."""
    if key not in tri or tri[key] is None:
        return None
    a = np.asarray(tri[key])
    if a.size == 0:
        a = a.reshape((0, cols) if cols else (0,))
    if a.dtype.kind == "b" or (a.dtype.kind not in "iuf"):
        raise ValueError(f"{key}: not an array of integers (dtype {a.dtype})")
    if cols == 0 and a.ndim == 2 and a.shape[1] == 1:
        a = a[:, 0]
    if (cols and (a.ndim != 2 or a.shape[1] != cols)) or (not cols and a.ndim != 1):
        want = f"(N, {cols})" if cols else "(N,) or (N, 1)"
        raise ValueError(f"{key}: expected shape {want}, got {a.shape}")
    if a.dtype.kind == "f":
        bad = np.argwhere(~np.isfinite(a) | (a != np.round(a)))
        if len(bad):
            i = tuple(int(x) for x in bad[0])
            raise ValueError(f"{key}[{i[0]}]: {float(a[i])} is not an integer")
    if a.size:
        lo, hi = a.min(), a.max()
        if lo < -(2**31) or hi >= 2**31:
            v = lo if lo < -(2**31) else hi
            i = tuple(int(x) for x in np.argwhere(a == v)[0])
            raise ValueError(f"{key}[{i[0]}]: {int(v)} does not fit 32 bits")
    return np.ascontiguousarray(a, dtype=np.int32)


def _input(tri: Mapping[str, Any]) -> Dict[str, Optional[np.ndarray]]:
    if not isinstance(tri, Mapping):
        raise TypeError("tri: a dict of arrays (vertices, segments, holes, regions, ...)")
    if tri.get("vertices") is None:
        what = "missing" if "vertices" not in tri else "None"
        raise ValueError(f"vertices: {what} (the input needs an (N, 2) array of N >= 3 vertices)")
    v = _floats(tri, "vertices", 2)
    d = {
        "vertices": v,
        "vertex_markers": _ints(tri, "vertex_markers", 0),
        "vertex_attributes": _floats(tri, "vertex_attributes", None),
        "segments": _ints(tri, "segments", 2),
        "segment_markers": _ints(tri, "segment_markers", 0),
        "holes": _floats(tri, "holes", 2),
        "regions": _floats(tri, "regions", 4) if _nregcols(tri) != 3 else _regions3(tri),
    }
    n = len(v)
    for k in ("vertex_markers", "vertex_attributes"):
        if d[k] is not None and len(d[k]) != n:
            raise ValueError(f"{k}: {len(d[k])} rows for {n} vertices")
    if d["segment_markers"] is not None:
        ns = 0 if d["segments"] is None else len(d["segments"])
        if len(d["segment_markers"]) != ns:
            raise ValueError(f"segment_markers: {len(d['segment_markers'])} rows for {ns} segments")
    if d["vertex_attributes"] is not None and d["vertex_attributes"].shape[1] == 0:
        d["vertex_attributes"] = None
    return d


def _nregcols(tri: Mapping[str, Any]) -> int:
    r = tri.get("regions")
    if r is None:
        return 4
    a = np.asarray(r)
    return a.shape[1] if a.ndim == 2 else 4


def _regions3(tri: Mapping[str, Any]) -> Optional[np.ndarray]:
    # x, y, attribute: Triangle reads a region line with one value after x y as both the
    # attribute and the area bound; a (N, 3) array here means no area bound (-1)
    r = _floats(tri, "regions", 3)
    return None if r is None else np.ascontiguousarray(np.hstack([r, -np.ones((len(r), 1))]))


# ---- the switch string --------------------------------------------------------------------------


class _Switches(NamedTuple):
    text: str  # what _core.parse reads: the string without Triangle's z
    letters: str  # the switch letters given, numbers left out
    long: str  # a long option's name ("--lens": "lens"), or ""


# ./mesh's long options that pcdm.triangulate does not take, and what to use instead
_WRITES = (
    "writes files: pcdm.triangulate writes none, it returns the mesh (python -m pcdm, the "
    "command line, writes them)"
)
_LONG_REFUSED = {
    "vtk": _WRITES,
    "vtk-ascii": _WRITES,
    "svg": _WRITES,
    "msh": _WRITES,
    "size": "reads a size file: give pcdm.triangulate size= (a callable or a background mesh)",
    "check": "is ./mesh's check: call pcdm.check(mesh, tri) on the result",
    "stats": "prints ./mesh's report: pcdm.check(mesh, tri) returns the measures",
    "progress": "prints ./mesh's progress lines: pcdm.triangulate prints nothing",
    "write-partial": "writes a partial mesh: pcdm.triangulate raises MeshError instead",
    "strict": "is not supported by pcdm.triangulate (crossing segments are split)",
    "help": "is not a switch: help(pcdm.triangulate) lists them",
    "version": "is not a switch: pcdm.__version__ is the version",
}
# a number as the command line reads one glued on to q, a or S: what strtod takes (decimal or
# hexadecimal), then everything up to the next letter
_GLUED = re.compile(
    r"[+-]?(?:0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?"
    r"|(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)[^A-Za-z]*"
)


def _switches(opts: Any) -> _Switches:
    """Triangle's switch string checked and read as far as the command line's parser needs:
    every character printable ASCII, Triangle's z (zero-based numbering, always so here) dropped
    where it stands as a switch letter, -o (an output prefix) and ./mesh's long options that
    write files or have no meaning here refused -- each a ValueError naming the switch."""
    if not isinstance(opts, str):
        raise TypeError(f"opts: a switch string such as 'pq30a0.01', not {type(opts).__name__}")
    for i, ch in enumerate(opts):
        if not (32 <= ord(ch) <= 126 or ch.isspace()):
            name = unicodedata.name(ch, f"U+{ord(ch):04X}")
            raise ValueError(
                f"{ch!r} ({name}) at {i} in {opts!r}: not a switch (switches are ASCII letters "
                "and numbers, as 'pq30a0.01')"
            )
    spaces = [i for i, ch in enumerate(opts) if ch.isspace()]
    if spaces:  # a command line's words: an option that writes files named first
        for w in opts.split():
            name = w[2:].split("=", 1)[0]
            if w.startswith("-o") and not w.startswith("-o2"):
                raise ValueError(f"option -o (output prefix) in {opts!r} {_WRITES}")
            if w.startswith("--") and name in _LONG_REFUSED:
                raise ValueError(f"option --{name} in {opts!r} {_LONG_REFUSED[name]}")
        raise ValueError(
            f"{opts[spaces[0]]!r} at {spaces[0]} in {opts!r}: switches go together without "
            "spaces, as 'pq30a0.01'"
        )
    if opts.startswith("--"):  # one long option, as ./mesh spells it
        name = opts[2:].split("=", 1)[0]
        if name in _LONG_REFUSED:
            raise ValueError(f"option --{name} in {opts!r} {_LONG_REFUSED[name]}")
        return _Switches(opts, "", name)
    body = opts[1:] if opts.startswith("-") else opts
    text, letters, i = [], [], 0
    while i < len(body):
        c = body[i]
        if body.startswith("o2", i):  # -o2: quadratic triangles (refused after parsing)
            text.append("o2")
            letters.append("o")
            i += 2
            continue
        if c == "o":
            raise ValueError(f"option -o (output prefix) in {opts!r} {_WRITES}")
        i += 1
        number = _GLUED.match(body, i)
        if c == "z":
            if number:
                raise ValueError(
                    f"'{number.group()}' after z in {opts!r}: z takes no number (a number goes "
                    "right after q, a or S)"
                )
            continue
        text.append(c)
        letters.append(c)
        if c in "qaS" and number:
            text.append(number.group())
            i = number.end()
    return _Switches("".join(text), "".join(letters), "")


# ---- triangulate --------------------------------------------------------------------------------


def triangulate(
    tri: Mapping[str, Any],
    opts: str = "",
    *,
    min_angle: Optional[float] = None,
    max_area: Optional[float] = None,
    max_steiner: Optional[int] = None,
    convex_hull: Optional[bool] = None,
    size: Optional[SizeRule] = None,
    circumcenters: Optional[bool] = None,
    lenses: Optional[bool] = None,
    threads: int = 0,
    pslg: Optional[bool] = None,
) -> Mesh:
    """Mesh ``tri`` (a dict of arrays, as ``triangle.triangulate`` takes) with Triangle's
    switches ``opts``; returns a dict of numpy arrays with ``triangle``'s keys, dtypes and shapes
    (``vertices`` float64 (N, 2), ``vertex_markers`` int32 (N, 1), ``triangles`` int32 (T, 3),
    ``segments`` int32 (S, 2), ``segment_markers`` int32 (S, 1), and when asked
    ``vertex_attributes``, ``triangle_attributes`` (``A``), ``edges``/``edge_markers`` (``e``),
    ``neighbors`` (``n``, -1 on the boundary); ``holes`` and ``regions`` are passed through with
    ``p``).  Indices are zero-based.

    As in Triangle, input vertex i is output vertex i, for every i: the Steiner points follow
    the input's vertices.  A vertex given twice (the same x and y exactly) is meshed once, as
    its first copy; a later copy stays in ``vertices`` at its own index, with its own marker and
    attributes, in no triangle, segment or edge (a segment naming it goes through the first
    copy).

    As in Triangle, the input is a PSLG only with ``p``: without it (and without ``r``, which
    keeps the given mesh's domain) ``segments``, ``holes`` and ``regions`` are not read and the
    mesh covers the vertices' convex hull, so ``A`` and ``a`` without a number, which read the
    regions, do nothing either (a long option alone, ``--lens``, has no ``p``: add
    ``pslg=True``).  Without ``q``,
    ``a`` (or the keywords below) the mesh is the constrained Delaunay triangulation alone.
    Keyword alternatives to switches: ``pslg`` (``p``: True reads the segments, holes and
    regions, False ignores them whatever ``opts`` says), ``min_angle`` (degrees,
    ``q``), ``max_area`` (``a``), ``max_steiner`` (``S``), ``convex_hull`` (``c``),
    ``circumcenters`` (circumcenters only, as Triangle; the default also uses off-centers),
    ``lenses`` (default True with ``threads=0``, as Triangle: a segment is split when a point
    lies in its diametral lens; False: in its diametral circle, as ``./mesh`` without
    ``--lens``; the subdomain mesher of ``threads`` >= 1 tests circles only);
    ``threads`` (default 0: the sequential mesher, ``./mesh``'s mesh; T >= 1: ``./pcdm``'s
    subdomain mesher on T threads of this process, the same mesh for every T, as
    ``./pcdm --threads T`` makes it; not with ``A`` or region areas; in builds with METIS,
    else ``ValueError``);
    ``size`` bounds the triangles' size where you say (Triangle's ``u``), in one of two forms:

    - a callable ``size(corners, area)``, called with a triangle's corners ((3, 2) array) and
      area, returning True when the triangle is too big;
    - a background mesh, a dict with ``vertices`` ((N, 2)), ``triangles`` ((M, 3), zero-based,
      either orientation, none degenerate) and one of ``vertex_sizes`` ((N,): the target edge
      length at each vertex, interpolated linearly over each background triangle; a triangle
      is too big when its area exceeds the equilateral triangle's of that side, sqrt(3)/4 h**2,
      as ``./mesh --size`` does) or ``triangle_max_area`` ((M,): the largest area over each
      background triangle, as Triangle's ``.area``).  Values must be positive.  The value is
      taken at the new triangle's centroid; a centroid outside the background mesh takes the
      value at the nearest point of the background mesh, so it need not cover the domain
      exactly.  Other keys are ignored, so a result of ``triangulate`` with one of the two
      arrays added is a background (``dict(mesh, vertex_sizes=h)``).  This rule runs in C
      (no Python call per triangle, the GIL stays released).

    The size rule adds to ``q``, ``a`` and the regions' bounds (a triangle is split when any of
    them says so).  The GIL is released while meshing (a size callable takes it back for each
    call).

    Raises ``ValueError`` (bad input or switches, with the command line's message),
    ``MeshError`` (a ``ValueError``: the bounds cannot be met) or ``MemoryError`` (out of memory:
    the message says how much more was asked; the memory the call took is given back); the
    Steiner limit (``S``) returns the mesh it reached with a ``RuntimeWarning``.
    """
    sw = _switches(opts)
    s = _core.parse(sw.text)
    for w in s["warnings"].splitlines():
        warnings.warn(w, RuntimeWarning, stacklevel=2)
    if s["order2"]:
        raise ValueError("option -o2 (quadratic triangles) is not supported by pcdm.triangulate")
    if sw.long == "lens" and lenses is None:
        lenses = True
    if sw.long == "cdt-only" and (min_angle, max_area, size) != (None, None, None):
        raise ValueError("option --cdt-only: no refinement, but min_angle, max_area or size asks")
    d = _input(tri)
    p_given = bool(pslg) if pslg is not None else "p" in sw.letters
    refine_input = s["refine"]
    # Triangle reads a PSLG with p (r reads the mesh, _refine_input); without either the
    # vertices alone, their convex hull meshed, and A and a alone have no regions to read
    reads_pslg = p_given or refine_input
    if not reads_pslg:
        for k in ("segments", "segment_markers", "holes", "regions"):
            d[k] = None
    given = {k: d[k] for k in ("vertices", "vertex_markers", "vertex_attributes")}
    dup = _Duplicates.of(d["vertices"])
    if dup is not None and d["vertex_markers"] is not None:
        # the mesher gives a merged point the first nonzero marker of its copies; Triangle
        # keeps the meshed copy's own (the later copies keep theirs, put back afterwards)
        d["vertex_markers"] = dup.zero_later(d["vertex_markers"])
    d["refine_areas"] = None
    if refine_input:
        d = _refine_input(tri, d, p_given, bool(s["region_areas"]), dup)
    q = s["q_given"] or min_angle is not None
    a = s["a_given"] or max_area is not None or (s["region_areas"] and reads_pslg)
    ma = float(min_angle) if min_angle is not None else s["min_angle"]
    area = float(max_area) if max_area is not None else s["max_area"]
    steiner = int(max_steiner) if max_steiner is not None else s["max_steiner"]
    if max_area is not None and not (area > 0 and np.isfinite(area)):
        raise ValueError(f"max_area {area:g}: must be a positive number")
    fn, background = (size, None) if size is None or callable(size) else (None, _background(size))
    hull = bool(convex_hull) if convex_hull is not None else bool(s["convex_hull"])
    cc = bool(circumcenters) if circumcenters is not None else bool(s["circumcenters"])
    threads = int(threads)
    if threads < 0:
        raise ValueError(f"threads {threads}: must be 0 (sequential) or a number of threads")
    if lenses is None:  # Triangle's lenses; the subdomain mesher tests diametral circles
        lenses = threads == 0
    code, message, mesh = _core.triangulate(
        d["vertices"],
        d["vertex_markers"],
        d["vertex_attributes"],
        d["segments"],
        d["segment_markers"],
        d["holes"],
        d["regions"],
        ma if q else 0.0,
        area,
        steiner,
        cc,
        hull and not refine_input,  # r: the mesh's domain (c: its boundary as segments)
        bool(s["region_attributes"]) and reads_pslg,
        bool(s["region_areas"]) and reads_pslg,
        not (q or a or size is not None),
        bool(lenses),
        fn,
        d["refine_areas"],
        bool(s["edges"]),
        bool(s["neighbors"]),
        background,
        threads,
    )
    if mesh is None:
        if code == 4:  # PCDM_EUNMET
            raise MeshError(message)
        if code == 8:  # PCDM_ENOMEM: every block given back
            raise MemoryError(message)
        raise ValueError(message)
    if code == 3:  # PCDM_ESTEINER: the mesh, outside the bounds
        warnings.warn(message, RuntimeWarning, stacklevel=2)
    if dup is not None:
        mesh = dup.expand(mesh, given)
    return _shape_output(mesh, tri, d, s, p_given, hull)


class _Duplicates:
    """The input's repeated vertices, found by the mesher's own rule (mesher/geom/pslg_check.c:
    the same x and the same y as doubles, so -0.0 is 0.0; the exact power-of-two scaling done
    before changes no equality): the first copy of each point is meshed, and the mesher's
    vertices are the input's first copies in their order, then the Steiner points.  ``expand``
    puts every later copy back at its own index, as Triangle keeps it: in no triangle, with its
    own marker and attributes."""

    def __init__(self, first: np.ndarray) -> None:
        n = len(first)
        self.first = first  # (n,) int32: each input vertex's first copy
        self.kept = np.flatnonzero(first == np.arange(n))  # the mesher's vertices 0..m-1
        self.later = np.flatnonzero(first != np.arange(n))

    @staticmethod
    def of(v: np.ndarray) -> Optional["_Duplicates"]:
        """None when no point repeats (the common case, found by one sort of the x's)."""
        n = len(v)
        x, y = v[:, 0], v[:, 1]
        xs = np.sort(x)
        if n < 2 or not (xs[1:] == xs[:-1]).any():
            return None
        rx = xs[1:][xs[1:] == xs[:-1]]  # the x's that repeat (sorted): only these can be copies
        rx = rx[np.concatenate([[True], rx[1:] != rx[:-1]])]
        c = np.flatnonzero(rx[np.minimum(np.searchsorted(rx, x), len(rx) - 1)] == x)
        c = c[np.lexsort((y[c], x[c]))]  # by x, y, then input order (lexsort is stable)
        same = (x[c[1:]] == x[c[:-1]]) & (y[c[1:]] == y[c[:-1]])
        if not same.any():
            return None
        start = np.concatenate([[True], ~same])  # a run of one point starts at its first copy
        first = np.arange(n, dtype=np.int32)
        first[c] = c[start][np.cumsum(start) - 1]
        return _Duplicates(first)

    def zero_later(self, markers: np.ndarray) -> np.ndarray:
        z = markers.copy()
        z[self.later] = 0
        return z

    def expand(self, mesh: Mesh, inp: Dict[str, Optional[np.ndarray]]) -> Mesh:
        """The mesher's result renumbered: input vertex i at i, the Steiner points after them.
        inp: the input's vertices, vertex_markers and vertex_attributes as given."""
        v = inp["vertices"]
        assert v is not None
        n, m = len(v), len(self.kept)
        mv = mesh["vertices"]
        if len(mv) < m or not np.array_equal(mv[:m], v[self.kept]):
            raise RuntimeError(  # the mesher merged other points than these: never expected
                "pcdm: the mesher's vertices are not the input's distinct vertices in order")
        to = np.concatenate([self.kept, np.arange(n, n + len(mv) - m)]).astype(np.int32)
        for k in ("triangles", "segments", "edges"):
            if k in mesh:
                mesh[k] = np.ascontiguousarray(to[mesh[k]], dtype=np.int32)
        for k, own in (("vertices", v), ("vertex_markers", inp.get("vertex_markers")),
                       ("vertex_attributes", inp.get("vertex_attributes"))):
            if k not in mesh:
                continue
            a = mesh[k]
            out = np.zeros((n + len(a) - m,) + a.shape[1:], dtype=a.dtype)
            out[to] = a
            if own is not None:  # a later copy: its own values (no markers given: 0)
                out[self.later] = own[self.later].reshape((-1,) + a.shape[1:])
            mesh[k] = out
        return mesh


def _background(size: Any) -> Tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """size= as a background mesh: (vertices, triangles, values, per_triangle) as _core takes
    them (shapes, dtypes and finite numbers checked here; indices, positive values and
    degenerate triangles by _core, which names the array and the index too)."""
    if not isinstance(size, Mapping):
        raise TypeError(
            "size: a callable size(corners, area) or a background mesh (a dict with vertices, "
            "triangles and vertex_sizes or triangle_max_area)"
        )
    for k in ("vertices", "triangles"):
        if size.get(k) is None:
            raise ValueError(
                f'size["{k}"]: missing (a background mesh needs vertices and triangles)'
            )
    given = [k for k in ("vertex_sizes", "triangle_max_area") if size.get(k) is not None]
    if len(given) != 1:
        raise ValueError(
            'size: a background mesh needs "vertex_sizes" (one per vertex) or "triangle_max_area" '
            "(one per triangle)" + (", not both" if given else "")
        )
    name = {k: f'size["{k}"]' for k in ("vertices", "triangles", given[0])}
    if np.ndim(size[given[0]]) not in (1, 2):
        raise ValueError(
            f"{name[given[0]]}: expected shape (N,) or (N, 1), got {np.shape(size[given[0]])}"
        )
    b = {name[k]: size[k] for k in name}
    v = _floats(b, name["vertices"], 2)
    t = _ints(b, name["triangles"], 3)
    val = _floats(b, name[given[0]], None)
    assert v is not None and t is not None and val is not None
    if val.shape[1] != 1:
        raise ValueError(f"{name[given[0]]}: expected shape (N,) or (N, 1), got {val.shape}")
    per_triangle = given[0] == "triangle_max_area"
    n, what = (len(t), "triangles") if per_triangle else (len(v), "vertices")
    if len(val) != n:
        raise ValueError(f"{name[given[0]]}: {len(val)} values for {n} {what}")
    return v, t, np.ascontiguousarray(val[:, 0]), per_triangle


def _shape_output(
    mesh: Mesh, tri: Mapping[str, Any], d: Dict[str, Any], s: Dict[str, Any], p: bool, c: bool
) -> Mesh:
    """triangle's output conventions: segments only with p or c, holes and regions passed
    through with p, the files N, E, P leave out."""
    if not (p or c):
        mesh.pop("segments", None)
        mesh.pop("segment_markers", None)
    if p:
        for k in ("holes", "regions"):
            if tri.get(k) is not None and len(np.asarray(tri[k])):
                mesh[k] = np.array(tri[k], dtype=np.float64)
    if s["no_node"]:
        for k in ("vertices", "vertex_markers", "vertex_attributes"):
            mesh.pop(k, None)
    if s["no_ele"]:
        for k in ("triangles", "triangle_attributes", "neighbors"):
            mesh.pop(k, None)
    if s["no_poly"]:
        mesh.pop("segments", None)
        mesh.pop("segment_markers", None)
    return mesh


def _refine_input(
    tri: Mapping[str, Any],
    d: Dict[str, Any],
    p: bool,
    area_bare: bool,
    dup: Optional[_Duplicates] = None,
) -> Dict[str, Any]:
    """r: the mesh tri["triangles"] refined, as ./mesh -r does: every vertex kept; the segments
    (and holes) the input gives with p, else the mesh's boundary edges with a hole point beside
    every chain of them; with a alone, tri["triangle_max_area"] bounds each old triangle's
    area (a new triangle is too big when it exceeds the bound of the old one holding its
    centroid).  As in Triangle, the domain is the mesh's: with p too, the boundary edges the
    segments leave out are added to them and every chain gets its hole point (a dict returned
    by triangulate lists no holes of its own: without them refining it again would fill the
    places its triangles left empty)."""
    t = _ints(tri, "triangles", 3)
    if t is None or len(t) == 0:
        raise ValueError("option -r: the input has no triangles to refine")
    n = len(d["vertices"])
    bad = np.argwhere((t < 0) | (t >= n))
    if len(bad):
        i, j = (int(x) for x in bad[0])
        raise ValueError(f"triangles[{i}]: vertex {int(t[i, j])} out of range (0..{n - 1})")
    if dup is not None:  # a repeated vertex is its first copy, as the mesher meshes it
        t = np.ascontiguousarray(dup.first[t])
    seg, holes = _core.boundary(d["vertices"], t)
    if p and d["segments"] is not None and len(d["segments"]):
        named = d["segments"]
        if dup is not None and named.size and named.min() >= 0 and named.max() < n:
            named = dup.first[named]
        have = set(map(tuple, np.sort(named, axis=1).tolist()))
        extra = seg[[tuple(e) not in have for e in np.sort(seg, axis=1).tolist()]]
        if len(extra):  # marker 0: a boundary segment gets 1
            d["segments"] = np.ascontiguousarray(np.vstack([d["segments"], extra]))
            if d["segment_markers"] is not None:
                zero = np.zeros(len(extra), dtype=np.int32)
                d["segment_markers"] = np.ascontiguousarray(
                    np.concatenate([d["segment_markers"], zero])
                )
    else:
        d["segments"], d["segment_markers"] = seg, None
    if p and d["holes"] is not None:
        holes = np.ascontiguousarray(np.vstack([d["holes"], holes]))
    d["holes"] = holes
    d["refine_areas"] = None
    if area_bare and tri.get("triangle_max_area") is not None:
        ar = np.asarray(tri["triangle_max_area"], dtype=np.float64).reshape(-1)
        if len(ar) != len(t):
            raise ValueError(f"triangle_max_area: {len(ar)} values for {len(t)} triangles")
        d["refine_areas"] = (d["vertices"], t, np.ascontiguousarray(ar))
    return d


# ---- check ------------------------------------------------------------------------------------


def check(
    mesh: Mapping[str, Any],
    tri: Mapping[str, Any],
    q: float = 0.0,
    a: float = 0.0,
    *,
    convex_hull: bool = False,
    region_attributes: bool = False,
    region_areas: bool = False,
) -> Dict[str, Any]:
    """The project's validator (``./meshcheck``) on ``mesh`` (a result of ``triangulate``, or
    any dict with ``vertices`` and ``triangles``, optionally ``segments``, ``segment_markers``,
    ``triangle_attributes``) against its input ``tri``: conforming, counter-clockwise, every
    input vertex and segment present, the domain's area, locally Delaunay, and the bounds
    ``q`` (smallest angle, degrees; 0: none) and ``a`` (largest area; 0: none).  With
    ``convex_hull`` the domain is the input and its hull (a mesh made with ``c``).

    Returns the report: ``ok``, ``summary`` (the one line ``./meshcheck`` prints),
    ``first_problem`` and the counts and measures (``min_angle``, ``max_area``, ``area``,
    ``domain_area``, ``missing_segments``, ``non_delaunay``, ...).  Bad input raises
    ``ValueError``.
    """
    d = _input(tri)
    mv = _floats(mesh, "vertices", 2)
    mt = _ints(mesh, "triangles", 3)
    if mv is None or mt is None:
        raise ValueError("mesh: needs vertices and triangles")
    ms = _ints(mesh, "segments", 2)
    msm = _ints(mesh, "segment_markers", 0)
    ta = None
    if region_attributes:
        if mesh.get("triangle_attributes") is None:
            raise ValueError("region_attributes: the mesh has no triangle_attributes")
        ta = np.ascontiguousarray(np.asarray(mesh["triangle_attributes"], np.float64)[:, 0])
    return _core.check(
        d["vertices"],
        d["vertex_markers"],
        d["segments"],
        d["segment_markers"],
        d["holes"],
        d["regions"],
        mv,
        mt,
        ms,
        msm,
        ta,
        float(q),
        float(a),
        bool(convex_hull),
        bool(region_attributes),
        bool(region_areas),
    )


# ---- the rest of the triangle package's API -------------------------------------------------

from ._files import data_path, get_data, load, loads, show_data  # noqa: E402
from ._plot import compare, plot  # noqa: E402
from ._points import convex_hull, delaunay, voronoi  # noqa: E402
