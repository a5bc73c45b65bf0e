"""The rest of the triangle package's API in pcdm: delaunay, convex_hull, voronoi, loads, load,
get_data, plot, compare -- and the switch string's refusals.

Each point-set call is checked on its own (numpy: every circumcircle empty, the triangle count
2n - 2 - h, the hull's edges with every point on their inner side, the Voronoi vertices the
circumcenters) on random points (fixed seed), a grid (cocircular points: a degenerate
Delaunay triangulation), and three letters built here (an H with points on its collinear
sides and inside, a T of random points, an O of two rings), and, where the triangle package
is importable, against it: the same triangle count (the same triangles in general position),
the same hull edges, the same Voronoi vertex set (within 1e-9) and edge and ray counts (the
same edges and rays in general position).  The readers: every file of the triangle package's
data folder read by both packages (same keys, dtypes, shapes and values), and the files
``python -m pcdm`` (./mesh) writes read back into exactly the dict pcdm.triangulate returns
for the same input.  plot and compare draw on matplotlib's Agg backend when matplotlib is
importable.  Then the switch string's refusals (each a ValueError naming the switch) and bad
arrays naming their key.
"""

import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import pcdm

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def real_triangle():
    return pytest.importorskip("triangle")


# ---- point sets ---------------------------------------------------------------------------------


def letter_h(rng):
    """An H: its 12 corners, points along its sides (collinear on the hull), points inside."""
    outline = np.array([[0, 0], [1, 0], [1, 2], [2, 2], [2, 0], [3, 0], [3, 5], [2, 5], [2, 3],
                        [1, 3], [1, 5], [0, 5]], dtype=float)
    pts = [outline]
    for a, b in zip(outline, np.roll(outline, -1, axis=0)):
        t = np.linspace(0, 1, 6)[1:-1, None]
        pts.append(a + t * (b - a))
    inside = rng.uniform([0, 0], [3, 5], size=(400, 2))
    x, y = inside[:, 0], inside[:, 1]
    keep = (x < 1) | (x > 2) | ((y > 2) & (y < 3))
    pts.append(inside[keep][:120])
    return np.vstack(pts)


def letter_t(rng):
    """A T of random points alone (general position): a bar on a stem."""
    p = rng.uniform([0, 0], [5, 6], size=(600, 2))
    keep = (p[:, 1] > 5) | ((p[:, 0] > 2) & (p[:, 0] < 3))
    return p[keep][:150]


def letter_o():
    """An O: two concentric rings of points (cocircular four by four)."""
    t1 = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    t2 = np.linspace(0, 2 * np.pi, 12, endpoint=False) + 0.1
    return np.vstack([np.stack([np.cos(t1), np.sin(t1)], 1) * 2,
                      np.stack([np.cos(t2), np.sin(t2)], 1)])


def point_sets():
    rng = np.random.default_rng(20250106)
    gx, gy = np.meshgrid(np.arange(12.0), np.arange(9.0))
    return {
        "random": rng.uniform(-1, 1, size=(250, 2)),
        "grid": np.stack([gx.ravel(), gy.ravel()], 1),
        "H": letter_h(rng),
        "T": letter_t(rng),
        "O": letter_o(),
    }


SETS = point_sets()
GENERAL = ("random", "T")  # general position: the Delaunay triangulation is unique


def orient(a, b, c):
    return (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (
        c[..., 0] - a[..., 0])


def hull_count(p):
    """Points on the convex hull's boundary (corners and points on its edges), and its area."""
    e = pcdm.convex_hull(p)
    return len(e), 0.5 * abs(orient(np.zeros(2), p[e[:, 0]], p[e[:, 1]]).sum())


def incircle_violations(p, t):
    """How many (triangle, point) pairs have the point strictly inside the triangle's
    circumcircle (numpy's determinant, with a tolerance for rounding)."""
    a, b, c = (p[t[:, k]][:, None, :] - p[None, :, :] for k in range(3))
    det = ((a * a).sum(2) * orient(np.zeros(2), b, c) + (b * b).sum(2) * orient(np.zeros(2), c, a)
           + (c * c).sum(2) * orient(np.zeros(2), a, b))
    scale = np.abs(p).max() ** 4
    return int((det > 1e-9 * scale).sum())


# ---- delaunay -----------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(SETS))
def test_delaunay_is_delaunay(name):
    p = SETS[name]
    t = pcdm.delaunay(p)
    assert t.dtype == np.int32 and t.ndim == 2 and t.shape[1] == 3
    assert (orient(p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]) > 0).all()  # counter-clockwise
    assert incircle_violations(p, t) == 0
    h, hull_area = hull_count(p)
    assert len(t) == 2 * len(p) - 2 - h
    area = 0.5 * orient(p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]).sum()
    assert area == pytest.approx(hull_area, rel=1e-12)
    assert len(np.unique(t)) == len(p)  # every point a corner


@pytest.mark.parametrize("name", sorted(SETS))
def test_delaunay_against_triangle(name):
    tr = real_triangle()
    p = SETS[name]
    r, t = pcdm.delaunay(p), tr.delaunay(p)
    assert r.dtype == t.dtype and r.shape == t.shape
    if name in GENERAL:  # the same triangles (in another order)
        assert sorted(map(tuple, np.sort(r, 1))) == sorted(map(tuple, np.sort(t, 1)))


def test_delaunay_repeated_points_and_errors():
    p = np.array([[0, 0], [1, 0], [0, 1], [1, 0], [1, 1]])
    t = pcdm.delaunay(p)
    assert len(t) == 2 and 3 not in t  # the repeated point as its first occurrence
    with pytest.raises(ValueError, match="collinear"):
        pcdm.delaunay([[0, 0], [1, 1], [2, 2]])
    with pytest.raises(ValueError, match="at least 3|fewer than 3"):
        pcdm.delaunay([[0, 0], [1, 1]])
    with pytest.raises(ValueError, match="pts: None"):
        pcdm.delaunay(None)
    with pytest.raises(ValueError, match="pts: complex"):
        pcdm.delaunay(np.array([[0, 0], [1, 0], [0, 1j]]))
    with pytest.raises(ValueError, match=r"pts: expected shape \(N, 2\)"):
        pcdm.delaunay([[0, 0, 0], [1, 0, 0], [0, 1, 0]])


# ---- convex_hull --------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(SETS))
def test_convex_hull(name):
    p = SETS[name]
    e = pcdm.convex_hull(p)
    assert e.dtype == np.int32 and e.shape[1] == 2
    assert (e[1:, 1] == e[:-1, 0]).all() and e[0, 1] == e[-1, 0]  # one closed chain, in order
    # the inside on each edge's right: no point on its left
    side = orient(p[e[:, 0]][:, None], p[e[:, 1]][:, None], p[None])
    assert (side <= 1e-12 * np.abs(p).max() ** 2).all()
    # every point on the hull's boundary a corner (test_delaunay_is_delaunay's count 2n - 2 - h
    # holds only so): the grid's 2 (11 + 8) edges; the H's 11 along its foot and its top (4
    # corners, 8 side points each) and 5 along each side
    if name in ("grid", "H"):
        assert len(e) == {"grid": 2 * (11 + 8), "H": 2 * 11 + 2 * 5}[name]


@pytest.mark.parametrize("name", sorted(SETS))
def test_convex_hull_against_triangle(name):
    tr = real_triangle()
    p = SETS[name]
    r, t = pcdm.convex_hull(p), tr.convex_hull(p)
    assert r.dtype == t.dtype and r.shape == t.shape
    assert set(map(tuple, r)) == set(map(tuple, t))  # the same directed edges


def test_convex_hull_small():
    e = pcdm.convex_hull([[0, 0], [0, 1], [1, 1], [1, 0]])
    assert e.tolist() == [[3, 0], [2, 3], [1, 2], [0, 1]]  # as the triangle package's docs
    e = pcdm.convex_hull([[0, 0], [2, 0], [1, 0], [1, 1]])  # (1, 0) on the hull: two edges
    assert set(map(tuple, e.tolist())) == {(2, 0), (1, 2), (3, 1), (0, 3)}


# ---- voronoi ------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(SETS))
def test_voronoi(name):
    p = SETS[name]
    points, edges, origin, direction = pcdm.voronoi(p)
    t = pcdm.delaunay(p)
    assert points.dtype == np.float64 and points.shape == (len(t), 2)
    assert edges.dtype == np.int32 and edges.shape[1] == 2
    assert origin.dtype == np.int32 and origin.ndim == 1
    assert direction.dtype == np.float64 and direction.shape == (len(origin), 2)
    # each point its triangle's circumcenter: as far from the three corners
    d = np.linalg.norm(points[:, None, :] - p[t], axis=2)
    assert np.allclose(d, d[:, :1], rtol=1e-9)
    # an edge for every pair of triangles sharing a side, a ray for every hull edge
    h, _ = hull_count(p)
    assert len(origin) == h
    assert len(edges) == (3 * len(t) - h) // 2
    shared = [len(set(t[i]) & set(t[j])) for i, j in edges]
    assert shared == [2] * len(edges) and (edges[:, 0] < edges[:, 1]).all()
    # a ray: perpendicular to its triangle's hull edge, as long as it, pointing out
    hull = pcdm.convex_hull(p)
    c = p.mean(axis=0)
    for o, dv in zip(origin, direction):
        corners = set(t[o])
        hit = [(a, b) for a, b in hull if a in corners and b in corners]
        assert any(np.isclose(np.dot(dv, p[b] - p[a]), 0, atol=1e-12)
                   and np.isclose(np.hypot(*dv), np.hypot(*(p[b] - p[a])))
                   and np.dot(dv, (p[a] + p[b]) / 2 - c) > 0 for a, b in hit)


def near(a, b, tol):
    """Every row of a within tol (max norm) of some row of b."""
    if not len(a):
        return not len(b)
    return bool((np.abs(a[:, None, :] - b[None, :, :]).max(2).min(1) <= tol).all())


@pytest.mark.parametrize("name", sorted(SETS))
def test_voronoi_against_triangle(name):
    tr = real_triangle()
    p = SETS[name]
    r, t = pcdm.voronoi(p), tr.voronoi(p)
    for a, b in zip(r, t):
        assert a.dtype == b.dtype and a.shape == b.shape
    tol = 1e-9 * max(1.0, np.abs(np.vstack([r[0], t[0]])).max())
    assert near(r[0], t[0], tol) and near(t[0], r[0], tol)  # the same vertex set
    if name in GENERAL:  # the same edges and rays, as segments and (origin, direction)
        seg = [np.hstack([v[0][v[1][:, 0]], v[0][v[1][:, 1]]]) for v in (r, t)]
        flip = [s[:, [2, 3, 0, 1]] for s in seg]
        for s, u, fu in ((seg[0], seg[1], flip[1]), (seg[1], seg[0], flip[0])):
            assert near(s, np.vstack([u, fu]), tol)
        rays = [np.hstack([v[0][v[2]], v[3]]) for v in (r, t)]
        assert near(rays[0], rays[1], tol) and near(rays[1], rays[0], tol)


def test_voronoi_small():
    points, edges, origin, direction = pcdm.voronoi([[0, 0], [1, 0], [0, 1], [1, 1.5]])
    assert sorted(points.tolist()) == [[0.5, 0.5], [0.75, 0.75]]
    assert edges.tolist() == [[0, 1]] and sorted(origin.tolist()) == [0, 0, 1, 1]


# ---- loads, load, get_data ----------------------------------------------------------------------


def triangle_data():
    tr = real_triangle()
    d = os.path.join(os.path.dirname(tr.__file__), "data")
    if not os.path.isdir(d):
        pytest.skip("the triangle package has no data folder")
    return tr, d


def stems(d):
    out = set()
    for f in os.listdir(d):
        for e in pcdm._files.EXTS:
            if f.endswith("." + e):
                out.add(f[: -len(e) - 1])
    return sorted(out)


def same(a, b, skip=()):
    assert sorted(a) == sorted(b)
    for k in a:
        assert a[k].dtype == b[k].dtype, k
        assert a[k].shape == b[k].shape, k
        if k not in skip:
            assert np.array_equal(a[k], b[k]), k


def test_load_triangle_data():
    """Every example file the triangle package ships, read by both: the same dicts.  But for
    the regions of la and la.1: la.poly's region lines hold one value after x y, which
    Triangle's format makes both the attribute and the area bound (the triangle package: the
    bound alone, attribute 0); la.1.poly's (Triangle's output) hold x y attribute area, which
    the triangle package reads shifted."""
    tr, d = triangle_data()
    names = stems(d)
    assert len(names) > 20
    for n in names:
        a, b = pcdm.load(d, n), tr.get_data(n)
        same(a, b, skip=("regions",) if n in ("la", "la.1") else ())
        same(pcdm.get_data(n, path=d), a)
        if n == "la":
            assert np.array_equal(a["regions"][:, [0, 1, 3]], b["regions"][:, [0, 1, 3]])
        if n in ("la", "la.1"):  # as in the files: 1 6 -0.2 0.05 [0.05] ... 6 5 -10 3 [3]
            assert a["regions"][[0, 5]].tolist() == [[6, -0.2, 0.05, 0.05], [5, -10, 3, 3]]


def mesh_files(tmp_path, poly, args):
    out = str(tmp_path / "x")
    r = subprocess.run([sys.executable, "-m", "pcdm"] + args + ["-o", out, poly],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return str(tmp_path), "x"


REGIONS = """# two squares side by side, attributes 1 and 2, one vertex attribute
6 2 1 1
1 0 0 0.5 1
2 1 0 1.5 1
3 2 0 2.5 1
4 2 1 3.5 1
5 1 1 4.5 1
6 0 1 5.5 1
7 1
1 1 2 1
2 2 3 1
3 3 4 1
4 4 5 1
5 5 6 1
6 6 1 1
7 2 5 7
0
2
1 0.5 0.5 1 0.05
2 1.5 0.5 2 0.1
"""


@pytest.mark.parametrize("name,args,opts", [
    ("lake", ["-q", "30"], "pq30"),
    ("lake", ["-q", "30", "-e", "-n"], "pq30en"),
    ("holes", ["-q", "25", "-a", "0.001"], "pq25a0.001"),
    ("channel", ["-c", "--cdt-only"], "pc"),
    ("regions", ["-q", "30", "-A", "-a"], "pq30Aa"),
])
def test_round_trip_mesh_files(tmp_path, name, args, opts):
    """./mesh's files (python -m pcdm -o) read by load: the very dict pcdm.triangulate returns
    for the same input and switches (./mesh tests diametral circles: lenses=False)."""
    if name == "regions":
        poly = str(tmp_path / "regions.poly")
        with open(poly, "w") as f:
            f.write(REGIONS)
        tri = pcdm.loads(poly=REGIONS)
        assert tri["regions"].tolist() == [[0.5, 0.5, 1, 0.05], [1.5, 0.5, 2, 0.1]]
    else:
        poly = os.path.join(ROOT, "data", name + ".poly")
        tri = pcdm.get_data(name)
        same(tri, pcdm.load(os.path.join(ROOT, "data"), name))
    d, x = mesh_files(tmp_path, poly, args)
    got = pcdm.load(d, x)
    want = pcdm.triangulate(tri, opts, lenses=False)
    same(got, want)


def test_round_trip_against_triangle(tmp_path):
    """The same files read by triangle.loads and pcdm.loads: the same dict."""
    tr = real_triangle()
    d, x = mesh_files(tmp_path, os.path.join(ROOT, "data", "lake.poly"), ["-q", "30"])
    text = {e: open(os.path.join(d, x + "." + e)).read() for e in ("node", "ele", "poly")}
    same(pcdm.loads(**text), tr.loads(**text))


def test_loads_numbering_and_comments():
    one = pcdm.loads(node="# a comment\n3 2 0 1\n1 0 0 2\n2 1 0 3  # more\n\n3 0 1 4\n",
                     ele="1 3 1\n1 1 2 3 7.5\n", neigh="1 3\n1 -1 -1 -1\n",
                     area="1\n1 0.25\n", edge="3 1\n1 1 2 5\n2 2 3 6\n3 3 1 7\n")
    zero = pcdm.loads(node="3 2 0 1\n0 0 0 2\n1 1 0 3\n2 0 1 4\n", ele="1 3 1\n0 0 1 2 7.5\n",
                      neigh="1 3\n0 -1 -1 -1\n", area="1\n0 0.25\n",
                      edge="3 1\n0 0 1 5\n1 1 2 6\n2 2 0 7\n")
    same(one, zero)
    assert one["triangles"].tolist() == [[0, 1, 2]]
    assert one["vertex_markers"].tolist() == [[2], [3], [4]]
    assert one["triangle_attributes"].tolist() == [[7.5]]
    assert one["neighbors"].tolist() == [[-1, -1, -1]]
    assert one["triangle_max_area"].tolist() == [[0.25]]
    assert one["edge_markers"].tolist() == [[5], [6], [7]]
    assert pcdm.loads() == {}


@pytest.mark.parametrize("kw,words", [
    ({"node": "3 2 0 0\n1 0 0\n2 1 0\n"}, "node:3: the file ends where vertex 3 of 3"),
    ({"node": "99999999999 2 0 0\n1 0 0\n"}, "node:2: the file ends where vertex 2 of 99999999999"),
    ({"node": "3 2 0 1\n1 0 0 1.5\n2 1 0 1\n3 0 1 1\n"}, "node:2: vertex marker 1.5 is not an"),
    ({"poly": "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 2\n1 1 2 3 4\n"},
     "poly:5: the segment marker count must be 0 or 1, not 2"),
    ({"node": "3 2 0 0\n1 0 0\n2 1 x\n3 0 1\n"}, "node:3: vertex 'x' is not a number"),
    ({"node": "3 2 0 0\n2 0 0\n3 1 0\n4 0 1\n"}, "node:2: the first vertex number must be 0 or 1"),
    ({"node": "3 2 0 0\n1 0 0\n3 1 0\n2 0 1\n"}, "node:3: vertex number 3 out of sequence"),
    ({"node": "3 3 0 0\n1 0 0 0\n"}, "node:1: dimension must be 2"),
    ({"node": "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", "ele": "1 3 0\n1 1 2 4\n"},
     "ele:2: triangle: 4 is out of range (1..3)"),
    ({"poly": "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 0\n1 1 2 3\n"}, "poly:6: segment: expected 3"),
    ({"node": "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n4\n"}, "node:5: unexpected data"),
    ({"node": 3}, "node: the file's text"),
])
def test_loads_errors(kw, words):
    with pytest.raises((ValueError, TypeError)) as e:
        pcdm.loads(**kw)
    assert words in str(e.value)


def test_load_and_get_data_not_found(tmp_path, monkeypatch):
    with pytest.raises(FileNotFoundError, match="no such file"):
        pcdm.load(tmp_path, "nothing")
    bad = tmp_path / "bad.node"
    bad.write_text("3 2 0 0\n1 0 0\n2 1\n3 0 1\n")
    with pytest.raises(ValueError, match=r"bad\.node:3: vertex: expected 3 numbers, found 2"):
        pcdm.load(tmp_path, "bad")
    monkeypatch.setenv("PCDM_DATA", str(tmp_path / "a") + os.pathsep + str(tmp_path / "b"))
    with pytest.raises(FileNotFoundError) as e:
        pcdm.get_data("A", path=str(tmp_path / "c"))
    msg = str(e.value)
    for where in ("a", "b", "c"):
        assert str(tmp_path / where) in msg
    assert "PCDM_DATA" in msg and "path=" in msg
    assert pcdm.data_path()[-1] in msg  # the package's own examples, looked in last


def test_get_data_folders(tmp_path, monkeypatch):
    monkeypatch.delenv("PCDM_DATA", raising=False)
    lake = pcdm.get_data("lake")  # the package's own examples
    assert lake["vertices"].shape == (196, 2) and lake["holes"].shape == (2, 2)
    same(pcdm.get_data("lake.poly"), lake)
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "lake.node").write_text("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n")
    (mine / "tri.node").write_text("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n")
    assert len(pcdm.get_data("lake", path=mine)["vertices"]) == 3  # path= first
    monkeypatch.setenv("PCDM_DATA", str(mine))
    assert len(pcdm.get_data("lake")["vertices"]) == 3  # then PCDM_DATA
    assert len(pcdm.get_data("tri")["vertices"]) == 3
    assert pcdm.data_path()[0] == str(mine)
    with pytest.raises(TypeError):
        pcdm.get_data(None)


# ---- plot, compare ------------------------------------------------------------------------------


def pyplot():
    mpl = pytest.importorskip("matplotlib")
    mpl.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def test_import_pcdm_loads_no_matplotlib():
    code = "import sys, pcdm; print('matplotlib' in sys.modules)"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.stdout.strip() == "False", r.stderr


def test_plot_draws_every_part(tmp_path):
    plt = pyplot()
    box = {"vertices": [[0, 0], [3, 0], [3, 3], [0, 3], [1, 1], [2, 1], [2, 2], [1, 2]],
           "segments": [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]],
           "holes": [[1.5, 1.5]]}
    m = pcdm.triangulate(box, "pq30a0.5")
    ax = plt.axes()
    assert pcdm.plot(ax, **m) is None
    lines = [len(c.get_segments()) for c in ax.collections]
    t = m["triangles"]
    edges = {tuple(sorted(e)) for e in np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])}
    assert sorted(lines) == sorted([len(edges), len(m["segments"])])
    dots, crosses = ax.lines
    assert len(dots.get_xdata()) == len(m["vertices"]) and len(crosses.get_xdata()) == 1
    plt.savefig(str(tmp_path / "mesh.png"))
    plt.close("all")


def test_plot_voronoi_rays_keep_the_limits():
    plt = pyplot()
    pts = np.array([[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]])
    v, e, o, d = pcdm.voronoi(pts)
    ax = plt.axes()
    pcdm.plot(ax, vertices=v, edges=e, ray_origins=o, ray_directions=d)
    assert [len(c.get_segments()) for c in ax.collections] == [len(e), len(o)]
    x0, x1, y0, y1 = ax.axis()
    assert -0.5 < x0 < 0 and 1 < x1 < 1.5 and -0.5 < y0 < 0 and 1 < y1 < 1.5
    plt.close("all")


def test_compare(tmp_path):
    plt = pyplot()
    A = pcdm.get_data("lake")
    B = pcdm.triangulate(A, "pq30")
    assert pcdm.compare(plt, A, B, figsize=(8, 4)) is None
    fig = plt.gcf()
    assert tuple(fig.get_size_inches()) == (8, 4)
    ax1, ax2 = fig.axes
    assert ax1.get_shared_x_axes().joined(ax1, ax2) and ax1.get_shared_y_axes().joined(ax1, ax2)
    assert len(ax2.collections) == 2 and len(ax1.collections) == 1  # triangles: B alone
    fig.savefig(str(tmp_path / "compare.png"))
    plt.close("all")
    pcdm.compare(plt, dict(vertices=SETS["random"]), dict(zip(
        ("vertices", "edges", "ray_origins", "ray_directions"), pcdm.voronoi(SETS["random"]))))
    plt.close("all")
    pcdm.show_data("lake")
    plt.close("all")


# ---- r: the mesh's domain kept ------------------------------------------------------------------


def area(m):
    p = m["vertices"][m["triangles"]]
    return 0.5 * orient(p[:, 0], p[:, 1], p[:, 2]).sum()


def bare_mesh(tri):
    """A mesh as a mesh alone (vertices and triangles, as Triangle's NAME.1.node/.ele)."""
    m = pcdm.triangulate(tri, "p")
    return {k: m[k] for k in ("vertices", "vertex_markers", "triangles")}


HOLE = {"vertices": [[0, 0], [3, 0], [3, 3], [0, 3], [1, 1], [2, 1], [2, 2], [1, 2]],
        "segments": [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]],
        "holes": [[1.5, 1.5]]}


def test_refine_again_keeps_the_hole():
    """The documentation's refine.py: rpa0.2, then rpa0.05 and rpa0.0125 of each result (whose
    dict lists no hole): the hole stays empty, as in Triangle."""
    m = bare_mesh(HOLE)
    for a in (0.2, 0.05, 0.0125):
        m = pcdm.triangulate(m, "rpa%g" % a)
        assert area(m) == pytest.approx(8)
        assert pcdm.check(m, HOLE, a=a)["ok"]
    tr = real_triangle()
    t = bare_mesh(HOLE)
    for a in (0.2, 0.05, 0.0125):
        t = tr.triangulate(t, "rpa%g" % a)
    assert area(t) == pytest.approx(8)
    assert abs(len(m["triangles"]) - len(t["triangles"])) < 0.1 * len(t["triangles"])


@pytest.mark.parametrize("opts", ["rc", "rpc"])
def test_refine_c_gives_the_boundary(opts):
    """The documentation's bndries.py: r with c keeps the mesh's domain (the L's concavity and
    the hole stay out) and returns its boundary edges as segments, as Triangle does."""
    for tri in (pcdm.get_data("lshape"), HOLE):
        m = bare_mesh(tri)
        r = pcdm.triangulate(m, opts)
        assert area(r) == pytest.approx(area(m))
        seg, _ = pcdm._core.boundary(np.ascontiguousarray(m["vertices"]), m["triangles"])
        assert set(map(tuple, np.sort(r["segments"], 1).tolist())) == set(
            map(tuple, np.sort(seg, 1).tolist()))
        tr = real_triangle()
        t = tr.triangulate(m, opts)
        assert sorted(r) == sorted(t)
        assert set(map(tuple, np.sort(r["segments"], 1).tolist())) == set(
            map(tuple, np.sort(t["segments"], 1).tolist()))


def test_holes_passed_through_with_p_only():
    tr = real_triangle()
    for opts in ("c", "pc", "p"):
        assert sorted(pcdm.triangulate(HOLE, opts)) == sorted(tr.triangulate(HOLE, opts)), opts


# ---- the switch string --------------------------------------------------------------------------

SQ = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]], "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}


@pytest.mark.parametrize("opts,words", [
    ("--size=/x/zz", "option --size in '--size=/x/zz' reads a size file"),
    ("--vtk=/tmp/m.vtk", "option --vtk in '--vtk=/tmp/m.vtk' writes files"),
    ("--vtk-ascii", "option --vtk-ascii"),
    ("--svg=m.svg", "option --svg in '--svg=m.svg' writes files"),
    ("--msh=m.msh", "option --msh"),
    ("-o P", "option -o (output prefix) in '-o P' writes files"),
    ("-oP", "option -o (output prefix)"),
    ("po/tmp/zz", "option -o (output prefix) in 'po/tmp/zz'"),
    ("pq30 --vtk m.vtk", "option --vtk in 'pq30 --vtk m.vtk'"),
    ("pq30 a0.1", "' ' at 4 in 'pq30 a0.1': switches go together without spaces"),
    ("pq３０", "'３' (FULLWIDTH DIGIT THREE) at 2 in 'pq３０': not a switch"),
    ("pé", "'é' (LATIN SMALL LETTER E WITH ACUTE) at 1"),
    ("p\x00", "'\\x00' (U+0000) at 1"),
    ("pqz30", "'30' after z in 'pqz30': z takes no number"),
    ("--check", "pcdm.check"),
    ("--stats", "option --stats"),
    ("--strict", "option --strict"),
    ("--help", "help(pcdm.triangulate)"),
    ("pq30o2", "-o2"),
])
def test_switch_string_refusals(opts, words):
    with pytest.raises(ValueError) as e:
        pcdm.triangulate(SQ, opts)
    assert words in str(e.value)
    assert "--sie" not in str(e.value)


def test_z_is_dropped_as_a_letter_only():
    want = pcdm.triangulate(SQ, "pq30a0.1")
    for opts in ("pzq30a0.1", "zpq30a0.1", "pq30a0.1z", "-pq30za0.1", "pq30a0.1zzz"):
        same(pcdm.triangulate(SQ, opts), want)
    same(pcdm.triangulate(SQ, "pa1e-1q30z"), want)  # a number's exponent is no letter


def test_long_options_that_mean_something():
    same(pcdm.triangulate(SQ, "--lens"), pcdm.triangulate(SQ, "", lenses=True))
    same(pcdm.triangulate(SQ, "--cdt-only"), pcdm.triangulate(SQ, ""))
    assert "segments" in pcdm.triangulate(SQ, "--convex-hull")
    with pytest.raises(ValueError, match="--cdt-only"):
        pcdm.triangulate(SQ, "--cdt-only", min_angle=30)


def test_bad_arrays_name_the_key():
    with pytest.raises(TypeError, match="opts"):
        pcdm.triangulate(SQ, 30)
    with pytest.raises(ValueError, match=r"vertices: None"):
        pcdm.triangulate({"vertices": None}, "")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning: refused before any cast
        with pytest.raises(ValueError, match="vertices: complex numbers"):
            pcdm.triangulate({"vertices": np.array([[0, 0], [1, 0], [0, 1 + 1j]])}, "")
        with pytest.raises(ValueError, match="holes: complex numbers"):
            pcdm.triangulate(dict(SQ, holes=[[0.5 + 0j, 0.5]]), "p")
        with pytest.raises(ValueError, match="regions: complex numbers"):
            pcdm.triangulate(dict(SQ, regions=[[0.5, 0.5, 1j, 0.1]]), "p")
        with pytest.raises(ValueError, match="segments: not an array of integers"):
            pcdm.triangulate(dict(SQ, segments=np.array(SQ["segments"]) + 0j), "p")
    same(pcdm.triangulate(dict(SQ, holes=None, regions=None), "p"), pcdm.triangulate(SQ, "p"))


def test_docstring_examples():
    import doctest

    for m in (pcdm, pcdm._points, pcdm._files):
        r = doctest.testmod(m)
        assert r.failed == 0 and r.attempted > 0, m.__name__
