"""Triangle's text formats read into the dict ``triangulate`` takes and returns: ``loads``
(the files' text), ``load`` (a folder and a name) and ``get_data`` (a name looked up in the
folders the user names, then in the package's own examples)."""

from __future__ import annotations

import os
from typing import Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

Data = Dict[str, np.ndarray]
EXTS = ("node", "ele", "poly", "area", "edge", "neigh")


class _Lines:
    """The records of one file: its lines without comments ('#' to the end) and blank lines,
    each split into words, with the line's number for messages."""

    def __init__(self, text: Union[str, bytes], what: str):
        if isinstance(text, bytes):
            text = text.decode("utf-8", errors="replace")
        if not isinstance(text, str):
            raise TypeError(f"{what}: the file's text (a str), not {type(text).__name__}")
        self.what = what
        self.rows: List[Tuple[int, List[str]]] = []
        for n, line in enumerate(text.splitlines(), 1):
            words = line.split("#", 1)[0].split()
            if words:
                self.rows.append((n, words))
        self.at = 0
        self.lines: List[int] = []

    def fail(self, line: Optional[int], problem: str) -> ValueError:
        where = f"{self.what}:{line}" if line else self.what
        return ValueError(f"{where}: {problem}")

    def more(self) -> bool:
        return self.at < len(self.rows)

    def next(self, what: str) -> Tuple[int, List[str]]:
        if not self.more():
            last = self.rows[-1][0] if self.rows else None
            raise self.fail(last, f"the file ends where {what} should be")
        self.at += 1
        return self.rows[self.at - 1]

    def header(self, what: str, names: Sequence[str], dflt: Sequence[int] = ()) -> List[int]:
        """A header line: len(names) integers, the first one required, the others dflt's
        values (0 where dflt gives none) when left out."""
        line, w = self.next(what)
        if len(w) > len(names):
            opt = " ".join("[" + x + "]" for x in names[1:])
            raise self.fail(line, f"expected {what}: {names[0]} {opt}".rstrip())
        out = [self.int(line, x, names[k]) for k, x in enumerate(w)]
        if out[0] < 0:
            raise self.fail(line, f"{names[0]} {out[0]} is negative")
        pad = list(dflt[1:]) + [0] * len(names)
        return out + pad[len(out) - 1 : len(names) - 1]

    def int(self, line: int, word: str, what: str) -> int:
        try:
            return int(word)
        except ValueError:
            raise self.fail(line, f"{what} '{word}' is not an integer") from None

    def float(self, line: int, word: str, what: str) -> float:
        try:
            return float(word)
        except ValueError:
            raise self.fail(line, f"{what} '{word}' is not a number") from None

    def table(self, count: int, what: str, ints: int, floats: int, extra: int = 0) -> Tuple:
        """count records "<number> ints... floats... [up to extra more floats]": their numbers
        (int64 (count,)), the integer columns (int64 (count, ints)) and the float columns
        (float64 (count, floats + extra), nan where an extra one is left out)."""
        self.lines = []  # each record's line, for messages (_base, _indices)
        left = len(self.rows) - self.at
        if count > left:  # found before anything is allocated for them
            last = self.rows[-1][0] if self.rows else None
            raise self.fail(last, f"the file ends where {what} {left + 1} of {count} should be")
        num = np.zeros(count, dtype=np.int64)
        iv = np.zeros((count, ints), dtype=np.int64)
        fv = np.full((count, floats + extra), np.nan)
        for r in range(count):
            line, w = self.next(f"{what} {r + 1} of {count}")
            self.lines.append(line)
            if not (1 + ints + floats <= len(w) <= 1 + ints + floats + extra):
                want = 1 + ints + floats
                n = f"{want} to {want + extra}" if extra else f"{want}"
                raise self.fail(line, f"{what}: expected {n} numbers, found {len(w)}")
            num[r] = self.int(line, w[0], f"{what} number")
            for k in range(ints):
                iv[r, k] = self.int(line, w[1 + k], what)
            for k, x in enumerate(w[1 + ints :]):
                fv[r, k] = self.float(line, x, what)
        return num, iv, fv

    def done(self) -> None:
        if self.more():
            line, _ = self.rows[self.at]
            raise self.fail(line, "unexpected data after the last section")


def _base(num: np.ndarray, lines: _Lines, what: str) -> int:
    """The numbering a file uses, 0 or 1: its first record's number (as Triangle decides)."""
    if not len(num):
        return 0
    if num[0] not in (0, 1):
        raise lines.fail(lines.lines[0], f"the first {what} number must be 0 or 1, not {num[0]}")
    return int(num[0])


def _sequence(num: np.ndarray, base: int, lines: _Lines, what: str) -> None:
    """Records numbered base, base + 1, ... in order (indices refer to them)."""
    bad = np.flatnonzero(num != base + np.arange(len(num)))
    if len(bad):
        r = int(bad[0])
        raise lines.fail(
            lines.lines[r], f"{what} number {num[r]} out of sequence (expected {base + r})"
        )


def _indices(
    iv: np.ndarray,
    base: int,
    nv: Optional[int],
    lines: _Lines,
    what: str,
    keep: Optional[int] = None,
) -> np.ndarray:
    """Vertex (or triangle) numbers made zero-based and checked against nv; keep: a value left
    as it is (-1: no neighbour)."""
    out = iv - base
    if keep is not None:
        out[iv == keep] = keep
    if nv is not None and out.size:
        bad = (out < 0) | (out >= nv)
        if keep is not None:
            bad &= iv != keep
        if bad.any():
            r = int(np.argwhere(bad)[0][0])
            raise lines.fail(
                lines.lines[r],
                f"{what}: {int(iv[bad][0])} is out of range ({base}..{nv - 1 + base})",
            )
    return out.astype(np.int32)


def _column(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a.reshape(-1, 1), dtype=np.int32)


def _markers(a: np.ndarray, lines: _Lines, what: str) -> np.ndarray:
    """A marker column read as numbers: integers, as an int32 (N, 1) column."""
    bad = np.flatnonzero((a != np.round(a)) | (np.abs(a) >= 2**31))
    if len(bad):
        r = int(bad[0])
        raise lines.fail(lines.lines[r], f"{what} marker {a[r]:g} is not an integer")
    return _column(a)


def _flag(lines: _Lines, value: int, what: str) -> None:
    if value not in (0, 1):
        raise lines.fail(lines.rows[lines.at - 1][0], f"{what} must be 0 or 1, not {value}")


def _read_vertices(lines: _Lines, d: Data) -> Tuple[int, int]:
    """A vertex section (.node, or a .poly's first): into d; returns (count, numbering base)."""
    n, dim, nattr, nmark = lines.header(
        "the vertex header", ("vertex count", "dimension", "attributes", "markers"), (0, 2)
    )
    if dim != 2:
        raise lines.fail(lines.rows[lines.at - 1][0], f"dimension must be 2, not {dim}")
    _flag(lines, nmark, "the marker count")
    num, _, fv = lines.table(n, "vertex", 0, 2 + nattr + nmark)
    base = _base(num, lines, "vertex")
    _sequence(num, base, lines, "vertex")
    if n:
        d["vertices"] = np.ascontiguousarray(fv[:, :2])
        if nattr:
            d["vertex_attributes"] = np.ascontiguousarray(fv[:, 2 : 2 + nattr])
        if nmark:
            d["vertex_markers"] = _markers(fv[:, 2 + nattr], lines, "vertex")
    return n, base


def loads(
    node: Optional[str] = None,
    ele: Optional[str] = None,
    poly: Optional[str] = None,
    area: Optional[str] = None,
    edge: Optional[str] = None,
    neigh: Optional[str] = None,
) -> Data:
    """The dict ``triangulate`` takes and returns, read from the text of Triangle's files (each
    optional): ``node`` (``vertices`` (N, 2), ``vertex_attributes`` (N, K) and
    ``vertex_markers`` (N, 1) when the header has them), ``ele`` (``triangles`` (T, 3), or
    (T, 6) for quadratic triangles, ``triangle_attributes`` (T, K)), ``poly`` (its vertices when
    it lists any, else the ``node``'s; ``segments`` (S, 2), ``segment_markers`` (S, 1),
    ``holes`` (H, 2), ``regions`` (R, 4): x, y, attribute, maximum area -- one value after x y
    is both, none gives attribute 0 and no bound, -1), ``area`` (``triangle_max_area`` (T, 1),
    -1 for none), ``edge`` (``edges`` (E, 2), ``edge_markers`` (E, 1); a Voronoi diagram's rays,
    "<n> <origin> -1 <dx> <dy>", as ``ray_origins`` (R, 1) and ``ray_directions`` (R, 2)) and
    ``neigh`` (``neighbors`` (T, 3), -1 where there is none).  Indices are made zero-based: a
    file's numbering starts at its first vertex's number, 0 or 1, as in Triangle (the ``node``'s,
    or the ``poly``'s when it lists its vertices, for every file).  Comments ('#' to the end of a
    line) and blank lines are skipped; a section left empty gives no key.  Malformed text raises
    ``ValueError`` naming the file and line.

    >>> loads(node="3 2 0 0\\n1 0 0\\n2 1 0\\n3 0 1\\n", ele="1 3 0\\n1 1 2 3\\n")["triangles"]
    array([[0, 1, 2]], dtype=int32)
    """
    d: Data = {}
    base: Optional[int] = None
    nv: Optional[int] = None
    if node is not None:
        lines = _Lines(node, "node")
        nv, base = _read_vertices(lines, d)
        lines.done()
    if poly is not None:
        lines = _Lines(poly, "poly")
        pv: Data = {}
        n, pbase = _read_vertices(lines, pv)
        if n:  # the .poly's own vertices (a vertex count of 0: the .node's)
            for k in ("vertices", "vertex_attributes", "vertex_markers"):
                d.pop(k, None)
            d.update(pv)
            nv, base = n, pbase
        ns, nsm = lines.header("the segment header", ("segment count", "markers"))
        _flag(lines, nsm, "the segment marker count")
        num, iv, fv = lines.table(ns, "segment", 2, nsm)
        sb = base if base is not None else _base(num, lines, "segment")
        if ns:
            d["segments"] = _indices(iv, sb, nv, lines, "segment")
            if nsm:
                d["segment_markers"] = _markers(fv[:, 0], lines, "segment")
        if lines.more():  # holes (a missing section means none)
            (nh,) = lines.header("the hole count", ("hole count",))
            _, _, fv = lines.table(nh, "hole", 0, 2)
            if nh:
                d["holes"] = np.ascontiguousarray(fv)
        if lines.more():  # regions (optional)
            (nr,) = lines.header("the region count", ("region count",))
            _, _, fv = lines.table(nr, "region", 0, 2, 2)
            if nr:
                r = np.ascontiguousarray(fv)
                one = np.isnan(r[:, 3]) & ~np.isnan(r[:, 2])
                r[one, 3] = r[one, 2]  # one value: the attribute and the area bound
                r[np.isnan(r[:, 2]), 2] = 0
                r[np.isnan(r[:, 3]), 3] = -1
                d["regions"] = r
        lines.done()
    nt: Optional[int] = None
    if ele is not None:
        lines = _Lines(ele, "ele")
        nt, corners, nattr = lines.header(
            "the triangle header", ("triangle count", "corners", "attributes"), (0, 3)
        )
        if corners not in (3, 6):
            raise lines.fail(
                lines.rows[0][0], f"corners per triangle must be 3 or 6, not {corners}"
            )
        num, iv, fv = lines.table(nt, "triangle", corners, nattr)
        tb = base if base is not None else _base(num, lines, "triangle")
        _sequence(num, tb, lines, "triangle")
        if nt:
            d["triangles"] = _indices(iv, tb, nv, lines, "triangle")
            if nattr:
                d["triangle_attributes"] = np.ascontiguousarray(fv)
        lines.done()
    if area is not None:
        lines = _Lines(area, "area")
        (na,) = lines.header("the triangle count", ("triangle count",))
        if nt is not None and na != nt:
            raise lines.fail(lines.rows[0][0], f"{na} areas for {nt} triangles")
        _, _, fv = lines.table(na, "area", 0, 1)
        if na:
            d["triangle_max_area"] = np.ascontiguousarray(fv)
        lines.done()
    if edge is not None:
        lines = _Lines(edge, "edge")
        ne, nem = lines.header("the edge header", ("edge count", "markers"))
        _flag(lines, nem, "the edge marker count")
        if ne > len(lines.rows) - lines.at:  # found before anything is allocated for them
            left = len(lines.rows) - lines.at
            raise lines.fail(
                lines.rows[-1][0], f"the file ends where edge {left + 1} of {ne} should be"
            )
        rows = [lines.next(f"edge {r + 1} of {ne}") for r in range(ne)]
        lines.lines = [line for line, _ in rows]
        eb = base
        if eb is None and rows:
            first = lines.int(rows[0][0], rows[0][1][0], "edge number")
            eb = _base(np.array([first]), lines, "edge")
        ends, marks, rays, dirs = [], [], [], []
        end_lines, ray_lines = [], []
        for line, w in rows:
            if len(w) >= 3 and w[2] == "-1":  # a ray: origin, -1, direction
                if len(w) not in (5, 5 + nem):
                    raise lines.fail(line, f"ray: expected 5 numbers, found {len(w)}")
                ray_lines.append(line)
                rays.append(lines.int(line, w[1], "edge"))
                dirs.append([lines.float(line, x, "ray direction") for x in w[3:5]])
                continue
            if len(w) != 3 + nem:
                raise lines.fail(line, f"edge: expected {3 + nem} numbers, found {len(w)}")
            end_lines.append(line)
            ends.append([lines.int(line, x, "edge") for x in w[1:3]])
            if nem:
                marks.append(lines.int(line, w[3], "edge marker"))
        if ends:
            lines.lines = end_lines
            d["edges"] = _indices(np.array(ends, dtype=np.int64), eb or 0, nv, lines, "edge")
            if nem:
                d["edge_markers"] = _column(np.array(marks))
        if rays:
            lines.lines = ray_lines
            o = _indices(np.array(rays, dtype=np.int64), eb or 0, nv, lines, "ray")
            d["ray_origins"] = _column(o)
            d["ray_directions"] = np.array(dirs, dtype=np.float64)
        lines.done()
    if neigh is not None:
        lines = _Lines(neigh, "neigh")
        nn, per = lines.header("the neighbour header", ("triangle count", "neighbours"), (0, 3))
        if per != 3:
            raise lines.fail(lines.rows[0][0], f"neighbours per triangle must be 3, not {per}")
        num, iv, _ = lines.table(nn, "neighbour", 3, 0)
        nb = base if base is not None else _base(num, lines, "triangle")
        if nn:
            d["neighbors"] = _indices(iv, nb, nt if nt is not None else nn, lines, "neighbour", -1)
        lines.done()
    return d


def _strip(name: str) -> str:
    for e in EXTS:
        if name.endswith("." + e):
            return name[: -len(e) - 1]
    return name


def load(directory: Union[str, os.PathLike], name: str) -> Data:
    """``loads`` of the files ``directory/name.node``, ``.ele``, ``.poly``, ``.area``,
    ``.edge`` and ``.neigh`` that exist (``name`` may end with one of these extensions; a
    Voronoi diagram's are ``name.v.node`` and ``name.v.edge``: ``load(d, "dots.1.v")``).  Raises
    ``FileNotFoundError`` naming the files looked for when there is none, ``ValueError`` naming
    the file and line when one is malformed.
    """
    base = os.path.join(os.fspath(directory), _strip(name))
    text: Dict[str, str] = {}
    for e in EXTS:
        path = f"{base}.{e}"
        if os.path.isfile(path):
            with open(path, encoding="utf-8", errors="replace") as f:
                text[e] = f.read()
    if not text:
        raise FileNotFoundError(f"{base}.{{{','.join(EXTS)}}}: no such file")
    try:
        return loads(**text)
    except ValueError as err:  # name the file, not only its kind
        msg = str(err)
        for e in text:
            if msg.startswith(e + ":"):
                raise ValueError(f"{base}.{msg}") from None
        raise


def _package_data() -> List[str]:
    """The package's own examples: pcdm/data, installed with it; in the source tree, data/."""
    here = os.path.dirname(os.path.abspath(__file__))
    out = [os.path.join(here, "data")]
    tree = os.path.join(os.path.dirname(os.path.dirname(here)), "data")
    if os.path.isfile(os.path.join(tree, "lake.poly")):
        out.append(tree)
    return [d for d in out if os.path.isdir(d)]


def data_path(
    path: Union[None, str, os.PathLike, Sequence[Union[str, os.PathLike]]] = None,
) -> List[str]:
    """The folders ``get_data`` looks in, in order: ``path`` (a folder or a list of them), the
    folders in the environment variable ``PCDM_DATA`` (separated by ``os.pathsep``), then the
    package's own examples."""
    out: List[str] = []
    if path is not None:
        out += (
            [os.fspath(path)]
            if isinstance(path, (str, os.PathLike))
            else [os.fspath(p) for p in path]
        )
    out += [p for p in os.environ.get("PCDM_DATA", "").split(os.pathsep) if p]
    return out + _package_data()


def get_data(name: str, path: Union[None, str, Sequence[str]] = None) -> Data:
    """The example ``name`` (``load``'s files ``name.node``, ``.ele``, ``.poly``, ...) from the
    first folder of ``data_path(path)`` that has it: ``path``, then ``PCDM_DATA``, then the
    package's own examples (``lake``, ``holes``, ``channel``, ``lshape``, ``square``,
    ``wedge``).  pcdm ships no copy of Triangle's example files (the letter ``A``, ``face``,
    ``dots``, ...): point ``PCDM_DATA`` (or ``path``) at a folder that holds them.  A name found
    nowhere raises ``FileNotFoundError`` naming every folder looked in.
    """
    if not isinstance(name, str) or not name:
        raise TypeError(f"name: an example's name such as 'lake', not {name!r}")
    dirs = data_path(path)
    stem = _strip(name)
    for d in dirs:
        if any(os.path.isfile(os.path.join(d, f"{stem}.{e}")) for e in EXTS):
            return load(d, stem)
    looked = ", ".join(dirs) if dirs else "nowhere"
    raise FileNotFoundError(
        f"get_data({name!r}): no {stem}.node, .ele, .poly, ... in {looked} (pcdm ships only its "
        "own examples; set PCDM_DATA, or pass path=, to a folder holding the others, e.g. "
        "Triangle's example files)"
    )


def show_data(name: str, path: Union[None, str, Sequence[str]] = None) -> None:
    """``plot`` of ``get_data(name, path)`` on new axes of matplotlib's current figure."""
    import matplotlib.pyplot as plt

    from ._plot import plot

    plot(plt.axes(), **get_data(name, path))
