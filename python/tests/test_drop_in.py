"""Two of triangle's semantics pcdm.triangulate keeps, against the triangle package.

1. Input vertex i is output vertex i.  A vertex given twice (the same x and y exactly) is meshed
   once, as its first copy; a later copy stays in ``vertices`` at its own index, with its own
   marker and attributes, used by no triangle, segment or edge, and a segment naming it goes
   through the first copy.  Checked on copies at the start, in the middle, at the end, three
   copies of one point, -0.0 against 0.0, coordinates the mesher scales, with markers,
   attributes, segments naming either copy, regions, ``e``, ``n``, ``c``, ``r`` and threads:
   every result is the mesh of the input without its later copies, renumbered (the same
   triangles), and passes the validator (which finds an input point at the first mesh vertex
   with its coordinates, so the unused copies need no compacting); against the triangle package
   (run in a child process: it crashes on some inputs with repeated vertices) where it keeps
   the first copy too.
2. Without ``p`` (and ``r``) the input is no PSLG: segments, holes and regions are not read, the
   mesh covers the vertices' convex hull, ``A`` and a bare ``a`` do nothing.  Over every data
   set the triangle package ships, with '', 'q', 'q30', 'a0.1' and 'c': the same domain (area
   within 1e-9, relative), the same keys, dtypes, markers and (``c``) hull segments, input
   vertices at their indices; ``pslg=`` is ``p`` as a keyword.
"""

import os
import pickle
import re
import subprocess
import sys
import warnings

import numpy as np
import pytest

import pcdm

triangle = pytest.importorskip("triangle")

from tridata import DATA, IN_KEYS, names  # noqa: E402  (after the importorskip)


def area(m):
    v, t = np.asarray(m["vertices"]), np.asarray(m["triangles"])
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    return float(np.sum((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]) / 2)


def edges(s):
    return set(map(tuple, np.sort(np.asarray(s), axis=1).tolist()))


def quiet(f, *a, **k):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return f(*a, **k)


# ---- 2. without p: the vertices' convex hull, as triangle -------------------------------------

NO_P = ["", "q", "q30", "a0.1", "c"]


@pytest.mark.parametrize("opts", NO_P)
@pytest.mark.parametrize("name", names())
def test_without_p_same_domain(name, opts):
    d = {k: v for k, v in triangle.get_data(name).items() if k in IN_KEYS}
    x = np.asarray(d["vertices"], np.float64)
    if name == "greenland" and "q" in opts:  # Triangle refines it for minutes (test_pcdm)
        with pytest.raises(pcdm.MeshError):
            quiet(pcdm.triangulate, d, opts)
        return
    r = quiet(pcdm.triangulate, d, opts)
    t = triangle.triangulate(d, opts)
    assert sorted(r) == sorted(t)
    for k in t:
        assert r[k].dtype == t[k].dtype and r[k].shape[1:] == t[k].shape[1:], k
    assert area(r) == pytest.approx(area(t), rel=1e-9, abs=0)
    assert np.array_equal(r["vertices"][: len(x)], x)
    assert np.array_equal(t["vertices"][: len(x)], x)
    if opts in ("", "c"):  # the points' Delaunay triangulation: no Steiner point, same markers
        assert len(r["vertices"]) == len(x) and len(r["triangles"]) == len(t["triangles"])
        assert np.array_equal(r["vertex_markers"], t["vertex_markers"])
    if opts == "c":  # the hull's edges as segments, marker 1
        assert edges(r["segments"]) == edges(t["segments"])
        assert (r["segment_markers"] == 1).all()
    q = 30 if "q30" in opts else 20 if "q" in opts else 0
    m = re.search(r"a([0-9.]+)", opts)
    rep = pcdm.check(r, {"vertices": x}, q=q, a=float(m.group(1)) if m else 0)
    assert rep["ok"], rep["summary"]


BOX = {"vertices": [[0, 0], [3, 0], [3, 3], [0, 3], [1, 1], [2, 1], [2, 2], [1, 2]],
       "segments": [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]],
       "holes": [[1.5, 1.5]], "regions": [[0.5, 0.5, 7, 0.05]]}


def same(a, b):
    assert sorted(a) == sorted(b)
    for k in a:
        assert np.array_equal(a[k], b[k]), k


@pytest.mark.parametrize("opts", ["", "q", "A", "a", "aA", "c", "e", "n", "q30a0.1"])
def test_without_p_no_pslg(opts):
    """Segments, holes and regions unread: the hull meshed (area 9, the hole filled), the
    same keys as triangle; A adds no attributes and a bare a no bound (nothing to read)."""
    r = pcdm.triangulate(BOX, opts)
    t = triangle.triangulate(BOX, opts)
    assert sorted(r) == sorted(t)
    assert area(r) == pytest.approx(9) and area(t) == pytest.approx(9)
    bare = {"vertices": BOX["vertices"]}
    same(r, pcdm.triangulate(bare, opts))
    if "q" not in opts and "a0" not in opts:
        assert len(r["vertices"]) == 8 and len(r["triangles"]) == len(t["triangles"])


@pytest.mark.parametrize("opts", ["", "q30", "A", "aA", "c", "e"])
def test_pslg_keyword(opts):
    """pslg= is p: True reads the PSLG, False leaves it unread whatever opts says."""
    same(pcdm.triangulate(BOX, opts, pslg=True), pcdm.triangulate(BOX, "p" + opts))
    same(pcdm.triangulate(BOX, "p" + opts, pslg=False), pcdm.triangulate(BOX, opts))
    p = pcdm.triangulate(BOX, "p" + opts)
    assert area(p) == pytest.approx(8)
    assert sorted(p) == sorted(triangle.triangulate(BOX, "p" + opts))


# ---- 1. input vertices keep their indices --------------------------------------------------


def first_copies(v):
    """Each vertex's first copy, by exact coordinates (-0.0 is 0.0): a plain dict."""
    seen, out = {}, []
    for i, (x, y) in enumerate(np.asarray(v, np.float64).tolist()):
        out.append(seen.setdefault((x + 0.0, y + 0.0), i))
    return np.array(out)


def deduplicated(d):
    """d without its later copies, segments and triangles naming the first copies, and the
    map from its vertex numbers to d's."""
    first = first_copies(d["vertices"])
    kept = np.flatnonzero(first == np.arange(len(first)))
    new = np.full(len(first), -1)
    new[kept] = np.arange(len(kept))
    e = dict(d)
    for k in ("vertices", "vertex_markers", "vertex_attributes"):
        if k in d:
            e[k] = np.asarray(d[k])[kept]
    for k in ("segments", "triangles"):
        if k in d:
            e[k] = new[first[np.asarray(d[k])]]
    return e, kept


def check_kept(d, r, opts, renumbered=True):
    """r, pcdm's mesh of d, has d's vertices at their indices, the later copies in no triangle
    with their own markers and attributes, and (renumbered) is pcdm's mesh of d without the
    later copies, renumbered."""
    v = np.asarray(d["vertices"], np.float64)
    n = len(v)
    first = first_copies(v)
    later = np.flatnonzero(first != np.arange(n))
    assert len(later), "the case has no repeated vertex"
    # vertex i is input vertex i, to the bit (the sign of a zero too)
    assert np.array_equal(r["vertices"][:n], v)
    assert np.array_equal(np.signbit(r["vertices"][:n]), np.signbit(v))
    # the later copies are in no triangle, segment or edge
    for k in ("triangles", "segments", "edges"):
        if k in r:
            assert not np.isin(r[k], later).any(), k
    # their markers and attributes are their own (no markers given: 0)
    if "vertex_markers" in r:
        own = np.zeros(n, np.int32)
        if "vertex_markers" in d:
            own = np.asarray(d["vertex_markers"]).reshape(-1)
        assert np.array_equal(r["vertex_markers"][later, 0], own[later])
    if "vertex_attributes" in d:
        a = np.asarray(d["vertex_attributes"], np.float64).reshape(n, -1)
        assert np.array_equal(r["vertex_attributes"][later], a[later])
    if not renumbered:
        return
    # the mesh of the input without its later copies, renumbered
    e, kept = deduplicated(d)
    u = quiet(pcdm.triangulate, e, opts)
    m = len(kept)
    to = np.concatenate([kept, np.arange(n, n + len(u["vertices"]) - m)])
    assert len(r["vertices"]) == n + len(u["vertices"]) - m
    for k in u:
        if k in ("triangles", "segments", "edges"):
            assert np.array_equal(r[k], to[u[k]]), k
        elif k in ("vertices", "vertex_markers", "vertex_attributes"):
            assert np.array_equal(r[k][to], u[k]), k
        else:
            assert np.array_equal(r[k], u[k]), k


SQ = [[0, 0], [1, 0], [1, 1], [0, 1]]
INNER = [[0.5, 0.5], [0.2, 0.7], [0.8, 0.3]]
# name: vertices, segments (None: none); each has repeated vertices
DUPS = {
    "start": ([[0, 0], [0, 0]] + SQ[1:] + INNER, [[1, 2], [2, 3], [3, 4], [4, 0]]),
    "middle": (SQ + [[0.5, 0.5], [1, 0], [0.2, 0.7], [0.5, 0.5]] + INNER[2:],
               [[0, 5], [5, 2], [2, 3], [3, 0], [7, 6]]),
    "end": (SQ + INNER + [[0.8, 0.3], [0, 1]], [[0, 1], [1, 2], [2, 8], [8, 0]]),
    "thrice": (SQ + [[0.5, 0.5]] + INNER[1:] + [[0.5, 0.5], [0.5, 0.5]],
               [[0, 1], [1, 2], [2, 3], [3, 0], [4, 2], [7, 0]]),
    "signed zero": ([[0.0, 0.0], [1, -0.0], [1, 1], [-0.0, 1], [-0.0, -0.0], [1, 0.0]] + INNER,
                    [[4, 5], [1, 2], [2, 3], [3, 0]]),
    "scaled": ((np.array(SQ + INNER + [[1, 1], [0.5, 0.5]]) * 1e150).tolist(),
               [[0, 1], [1, 7], [2, 3], [3, 0], [8, 6]]),
    "tiny": ((np.array(SQ + INNER + [[1, 1], [0.5, 0.5]]) * 1e-150).tolist(),
             [[0, 1], [1, 7], [2, 3], [3, 0], [8, 6]]),
}
OPTS = ["", "q30", "c", "e", "n", "q30a0.01en", "p", "pq30a0.01", "pc", "pe", "pn", "pA", "pq30A"]


def case_input(name, markers, attributes):
    v, s = DUPS[name]
    n = len(v)
    d = {"vertices": np.array(v, np.float64)}
    if s is not None:
        d["segments"] = np.array(s)
        d["segment_markers"] = np.arange(2, 2 + len(s))
    if markers:  # the later copies' markers differ from their first copies'
        d["vertex_markers"] = np.arange(10, 10 + n).reshape(-1, 1)
        d["vertex_markers"][0] = 0  # the mesher's own marker where none is given
    if attributes:
        d["vertex_attributes"] = np.stack([np.arange(n) * 1.5, -np.arange(n)], axis=1)
    scale = float(np.abs(d["vertices"]).max())
    d["regions"] = np.array([[0.6 * scale, 0.5 * scale, 3, -1]])
    return d


@pytest.mark.parametrize("attributes", [False, True])
@pytest.mark.parametrize("markers", [False, True])
@pytest.mark.parametrize("opts", OPTS)
@pytest.mark.parametrize("name", sorted(DUPS))
def test_repeated_vertices_keep_indices(name, opts, markers, attributes):
    d = case_input(name, markers, attributes)
    scale = float(np.abs(d["vertices"]).max())
    if "a0.01" in opts:
        opts = opts.replace("a0.01", "a%g" % (0.01 * scale**2))
    r = quiet(pcdm.triangulate, d, opts)
    check_kept(d, r, opts)
    if "p" in opts:
        tri = dict(d)
    else:
        tri = {k: d[k] for k in ("vertices", "vertex_markers") if k in d}
    q = 30 if "q30" in opts else 0
    m = re.search(r"a([0-9.]+(?:e[+-]?[0-9]+)?)", opts)
    rep = pcdm.check(r, tri, q=q, a=float(m.group(1)) if m else 0, convex_hull="c" in opts,
                     region_attributes="A" in opts)
    assert rep["ok"], rep["summary"]
    assert rep["area"] == pytest.approx(scale**2, rel=1e-12)


def test_segment_naming_later_copy_maps_to_first():
    v = SQ + [[0.5, 0.5], [1, 0], [0.5, 0.5]]
    r = pcdm.triangulate({"vertices": v, "segments": [[0, 5], [5, 2], [2, 3], [3, 0], [6, 2]]},
                         "p")
    assert edges(r["segments"]) == {(0, 1), (1, 2), (2, 3), (0, 3), (2, 4)}
    assert not np.isin(r["triangles"], [5, 6]).any()


def test_segment_between_copies_is_zero_length():
    """A segment from a vertex to its own copy: the mesher's message, with the input's
    numbers."""
    with pytest.raises(ValueError, match="segment 4 has zero length.*same point"):
        pcdm.triangulate({"vertices": SQ + [[1, 0]], "segments": [[0, 1], [1, 2], [2, 3],
                                                                  [3, 0], [1, 4]]}, "p")
    with pytest.raises(ValueError, match="point 9 out of range"):
        pcdm.triangulate({"vertices": SQ + [[1, 0]], "segments": [[0, 9]]}, "p")


def triangle_in_child(d, opts):
    """triangle.triangulate(d, opts) in a child process (the package crashes on some inputs
    with repeated vertices); None when it did not return."""
    code = ("import pickle, sys, triangle\n"
            "d, o = pickle.load(sys.stdin.buffer)\n"
            "sys.stdout.buffer.write(pickle.dumps(triangle.triangulate(d, o)))\n")
    p = subprocess.run([sys.executable, "-c", code], input=pickle.dumps((d, opts)),
                       capture_output=True, timeout=120)
    return pickle.loads(p.stdout) if p.returncode == 0 else None


TRIANGLE_RUNS = []  # (case, opts, what happened)


# Triangle's predicates overflow and underflow at pcdm's scaled inputs' magnitudes
@pytest.mark.parametrize("opts", ["", "q30", "c", "e", "p", "pq30"])
@pytest.mark.parametrize("name", sorted(set(DUPS) - {"scaled", "tiny"}))
def test_repeated_vertices_against_triangle(name, opts):
    """Where triangle keeps the first copy of each point (which copy it meshes depends on its
    sort), its vertices, markers, attributes and domain are pcdm's."""
    d = case_input(name, True, True)
    d.pop("regions")
    if "p" in opts:  # triangle crashes on segments naming a later copy: the first copies
        first = first_copies(d["vertices"])
        d["segments"] = first[d["segments"]]
    else:
        del d["segments"], d["segment_markers"]
    r = quiet(pcdm.triangulate, d, opts)
    t = triangle_in_child(d, opts)
    if t is None:
        TRIANGLE_RUNS.append((name, opts, "triangle crashed"))
        pytest.skip("the triangle package crashed on this input")
    n = len(d["vertices"])
    first = first_copies(d["vertices"])
    later = np.flatnonzero(first != np.arange(n))
    single = np.bincount(first, minlength=n)[first] == 1  # points given once
    assert sorted(r) == sorted(t)
    for k in t:
        assert r[k].dtype == t[k].dtype and r[k].shape[1:] == t[k].shape[1:], k
    assert np.array_equal(t["vertices"][:n], d["vertices"])
    assert area(r) == pytest.approx(area(t), rel=1e-9)
    assert np.array_equal(r["vertex_attributes"][:n], t["vertex_attributes"][:n])
    assert np.array_equal(r["vertex_markers"][:n][single], t["vertex_markers"][:n][single])
    if np.isin(t["triangles"], later).any():
        TRIANGLE_RUNS.append((name, opts, "triangle meshes a later copy"))
        return
    TRIANGLE_RUNS.append((name, opts, "same copies"))
    assert np.array_equal(r["vertex_markers"][:n], t["vertex_markers"][:n])
    if "q" not in opts:
        assert len(r["triangles"]) == len(t["triangles"])
        assert np.array_equal(r["vertices"], t["vertices"])
    if "segments" in t and "q" not in opts:
        assert edges(r["segments"]) == edges(t["segments"])


def test_repeated_vertices_triangle_summary():
    """Run after the test above: how often triangle kept the first copies (printed)."""
    if not TRIANGLE_RUNS:
        pytest.skip("test_repeated_vertices_against_triangle did not run")
    kinds = {}
    for _, _, what in TRIANGLE_RUNS:
        kinds[what] = kinds.get(what, 0) + 1
    print("\nrepeated vertices against triangle: " +
          ", ".join(f"{v} {k}" for k, v in sorted(kinds.items())))
    assert kinds.get("same copies", 0) > 0


def test_repeated_vertices_refine():
    """r: a mesh whose triangles name both copies of a point is refined with every vertex at
    its index; the later copy in no triangle."""
    m = pcdm.triangulate({"vertices": SQ + INNER}, "q30")
    n0 = len(m["vertices"])
    k = 4  # INNER[0]: a copy appended, and two of its triangles made to name it
    v = np.vstack([m["vertices"], m["vertices"][k]])
    t = m["triangles"].copy()
    uses = np.flatnonzero((t == k).any(axis=1))[:2]
    t[uses] = np.where(t[uses] == k, n0, t[uses])
    mesh = {"vertices": v, "triangles": t, "vertex_markers": np.arange(len(v)).reshape(-1, 1)}
    for opts in ("r", "rq30a0.01", "rp", "rc"):
        r = pcdm.triangulate(mesh, opts)
        assert np.array_equal(r["vertices"][: len(v)], v), opts
        assert not np.isin(r["triangles"], [n0]).any(), opts
        assert r["vertex_markers"][n0, 0] == n0
        assert area(r) == pytest.approx(1.0)
        rep = pcdm.check(r, {"vertices": v}, q=30 if "q30" in opts else 0)
        assert rep["ok"], rep["summary"]
        if opts == "r":
            assert len(r["vertices"]) == len(v)


def test_repeated_vertices_threads():
    """threads=T meshes the same input: every vertex at its index there too."""
    rng = np.random.default_rng(3)
    v = rng.uniform(size=(200, 2))
    v = np.vstack([v, v[[5, 17, 5, 199]], SQ])
    d = {"vertices": v, "segments": [[204, 205], [205, 206], [206, 207], [207, 204]]}
    for opts in ("q30a0.001", "pq30a0.001"):
        try:
            r = pcdm.triangulate(d, opts, threads=2)
        except ValueError as e:
            if "METIS" in str(e):
                pytest.skip(str(e))
            raise
        check_kept(d, r, opts, renumbered=False)  # (its subdomains depend on the count)
        assert pcdm.check(r, d if "p" in opts else {"vertices": v}, q=30, a=0.001)["ok"]


def test_delaunay_with_repeated_points():
    """delaunay() meshes a point given twice once, as its first occurrence."""
    pts = np.array(SQ + INNER + [[0.5, 0.5], [1, 1]], np.float64)
    t = pcdm.delaunay(pts)
    assert not np.isin(t, [7, 8]).any()
    assert len(t) == len(pcdm.delaunay(pts[:7]))
