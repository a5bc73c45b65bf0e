"""size= as a background mesh: pcdm.triangulate(tri, opts, size={"vertices", "triangles",
"vertex_sizes" | "triangle_max_area"}).

Every mesh is checked by the validator (pcdm.check) and its triangles' areas are computed here
and held against the size the background gives at their centroids (the interpolation redone in
numpy: linear over the background triangle holding the centroid, or at the nearest point of the
background when the centroid is outside it).  A constant background gives the mesh of ``a``
with that area; ``./mesh --size`` (as ``python -m pcdm``) gives the same mesh from the same
background in files; a background that covers a part of the domain, or lies beside it, gives
its nearest value; bad backgrounds raise ValueError naming the array and the index; the rule
costs less per query than the cheapest Python callable, on a uniform background and where a
graded one is densest.
"""

import os
import subprocess
import sys
import time

import numpy as np
import pytest

import pcdm

SQ = [[0, 0], [1, 0], [1, 1], [0, 1]]
BOX = [[0, 1], [1, 2], [2, 3], [3, 0]]
SQUARE = {"vertices": SQ, "segments": BOX}
EQ = np.sqrt(3) / 4  # the equilateral triangle of side h has area EQ h^2


def grid_mesh(k, x0=0.0, x1=1.0, y0=0.0, y1=1.0):
    """A k x k grid of squares over [x0, x1] x [y0, y1], two triangles each."""
    gx, gy = np.linspace(x0, x1, k + 1), np.linspace(y0, y1, k + 1)
    v = np.array([[x, y] for y in gy for x in gx])
    t = []
    for j in range(k):
        for i in range(k):
            a, b = j * (k + 1) + i, j * (k + 1) + i + 1
            c, d = (j + 1) * (k + 1) + i + 1, (j + 1) * (k + 1) + i
            t += [[a, b, c], [a, c, d]]
    return v, np.array(t, dtype=np.int32)


def areas_centroids(m):
    x = m["vertices"][m["triangles"]]
    ar = 0.5 * np.abs((x[:, 1, 0] - x[:, 0, 0]) * (x[:, 2, 1] - x[:, 0, 1]) -
                      (x[:, 2, 0] - x[:, 0, 0]) * (x[:, 1, 1] - x[:, 0, 1]))
    return ar, x.mean(axis=1)


def interpolate(bv, bt, h, p):
    """h (per background vertex) at the points p: linear in the background triangle holding
    the point (rounded barycentric weights >= -1e-12), else at the point's nearest point of
    the background."""
    out = np.full(len(p), np.nan)
    for tri in bt:
        a, b, c = bv[tri]
        m = np.array([[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]])
        st = np.linalg.solve(m, (p - a).T).T
        w = np.c_[1 - st.sum(axis=1), st]
        inside = np.isnan(out) & (w.min(axis=1) >= -1e-12)
        out[inside] = w[inside] @ h[tri]
    for i in np.flatnonzero(np.isnan(out)):  # outside: the nearest point of the background
        best = (np.inf, 0.0)
        for tri in bt:
            for e in range(3):
                a, b = bv[tri[e]], bv[tri[(e + 1) % 3]]
                s = np.clip(np.dot(p[i] - a, b - a) / np.dot(b - a, b - a), 0, 1)
                q = a + s * (b - a)
                d = np.dot(p[i] - q, p[i] - q)
                if d < best[0]:
                    best = (d, h[tri[e]] + s * (h[tri[(e + 1) % 3]] - h[tri[e]]))
        out[i] = best[1]
    return out


def test_small_in_one_corner_coarse_elsewhere():
    bv, bt = grid_mesh(2)  # 9 vertices, 8 triangles
    h = np.full(len(bv), 0.25)
    h[0] = 0.01  # the corner (0, 0)
    m = pcdm.triangulate(SQUARE, "pq30", size={"vertices": bv, "triangles": bt, "vertex_sizes": h})
    rep = pcdm.check(m, SQUARE, q=30)
    assert rep["ok"], rep["summary"]
    ar, c = areas_centroids(m)
    want = EQ * interpolate(bv, bt, h, c) ** 2
    over = ar / want
    assert over.max() <= 1 + 1e-9, (over.max(), c[np.argmax(over)])
    near = np.hypot(c[:, 0], c[:, 1]) < 0.02  # h <= 0.01 + 0.24 * 0.02 * sqrt(2) / 0.5 there
    far = np.hypot(c[:, 0] - 1, c[:, 1] - 1) < 0.5
    assert near.sum() >= 3 and far.sum() >= 4
    assert ar[near].max() <= EQ * 0.0236**2, ar[near].max()  # small at the corner
    assert ar[far].min() > 20 * ar[near].max(), (ar[far].min(), ar[near].max())  # coarse there
    uniform = pcdm.triangulate(SQUARE, "pq30a%.17g" % ar[near].max())
    assert len(m["triangles"]) < len(uniform["triangles"]) / 10


def test_triangle_max_area_per_background_triangle():
    bv, bt = grid_mesh(2)
    amax = np.full(len(bt), 1e-2)
    amax[0] = 1e-4  # the lower triangle of the square at the corner (0, 0)
    bg = {"vertices": bv, "triangles": bt, "triangle_max_area": amax}
    m = pcdm.triangulate(SQUARE, "pq30", size=bg)
    assert pcdm.check(m, SQUARE, q=30)["ok"]
    ar, c = areas_centroids(m)
    in0 = (c[:, 0] < 0.5) & (c[:, 1] <= c[:, 0])  # centroid in background triangle 0
    assert ar[in0].max() <= 1e-4 and ar[~in0].max() <= 1e-2
    assert ar[~in0].max() > 10 * ar[in0].max()


@pytest.mark.parametrize("opts", ["pq30", "pq20", "p"])
def test_constant_background_is_a(opts):
    area = 1e-3
    bv, bt = grid_mesh(3)
    bg = {"vertices": bv, "triangles": bt, "triangle_max_area": np.full(len(bt), area)}
    m = pcdm.triangulate(SQUARE, opts, size=bg)
    a = pcdm.triangulate(SQUARE, opts + "a%g" % area)
    assert np.array_equal(m["vertices"], a["vertices"])
    assert np.array_equal(m["triangles"], a["triangles"])
    assert pcdm.check(m, SQUARE, q=float(opts[2:] or 0), a=area)["ok"]
    # a result of triangulate with the sizes added is a background too
    areas = np.full(len(a["triangles"]), area)
    m2 = pcdm.triangulate(SQUARE, opts, size=dict(a, triangle_max_area=areas))
    assert np.array_equal(m2["triangles"], a["triangles"])


def test_constant_vertex_sizes_meet_their_area():
    h = 0.05
    bv, bt = grid_mesh(4)
    m = pcdm.triangulate(SQUARE, "pq30", size={"vertices": bv, "triangles": bt,
                                                "vertex_sizes": np.full(len(bv), h)})
    a = pcdm.triangulate(SQUARE, "pq30a%.17g" % (EQ * h * h))
    assert pcdm.check(m, SQUARE, q=30, a=EQ * h * h * (1 + 1e-12))["ok"]
    assert abs(len(m["triangles"]) - len(a["triangles"])) <= 0.01 * len(a["triangles"])


def test_outside_takes_the_nearest_value():
    # the background covers the left half only; h grows with y, so on the right half the size is
    # the value at (0.5, y), the nearest point of the background
    bv, bt = grid_mesh(2, 0, 0.5, 0, 1)
    h = 0.02 + 0.1 * bv[:, 1]
    m = pcdm.triangulate(SQUARE, "pq30", size={"vertices": bv, "triangles": bt, "vertex_sizes": h})
    assert pcdm.check(m, SQUARE, q=30)["ok"]
    ar, c = areas_centroids(m)
    want = EQ * interpolate(bv, bt, h, c) ** 2
    assert (ar / want).max() <= 1 + 1e-9
    right = c[:, 0] > 0.6
    assert ar[right & (c[:, 1] < 0.2)].max() < ar[right & (c[:, 1] > 0.8)].max() / 4
    # a background beside the domain, not meeting it: its nearest values everywhere
    bv2, bt2 = grid_mesh(3, 2, 3, 0, 1)
    bg2 = {"vertices": bv2, "triangles": bt2, "triangle_max_area": np.full(len(bt2), 2e-3)}
    m2 = pcdm.triangulate(SQUARE, "pq30", size=bg2)
    assert np.array_equal(m2["triangles"], pcdm.triangulate(SQUARE, "pq30a2e-3")["triangles"])


def test_same_mesh_as_the_command_lines_size(tmp_path):
    bv, bt = grid_mesh(2)
    h = np.full(len(bv), 0.2)
    h[4] = 0.02  # the centre
    with open(tmp_path / "bg.node", "w") as f:
        f.write("%d 2 1 0\n" % len(bv))
        for i, (x, y) in enumerate(bv):
            f.write("%d %.17g %.17g %.17g\n" % (i, x, y, h[i]))
    with open(tmp_path / "bg.ele", "w") as f:
        f.write("%d 3 0\n" % len(bt))
        for i, t in enumerate(bt):
            f.write("%d %d %d %d\n" % (i, *t))
    with open(tmp_path / "sq.poly", "w") as f:
        f.write("4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n4 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n0\n")
    out = str(tmp_path / "out")
    p = subprocess.run([sys.executable, "-m", "pcdm", "-q", "30", "--size", str(tmp_path / "bg"),
                        "--check", "-o", out, str(tmp_path / "sq.poly")],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    node = np.loadtxt(out + ".node", skiprows=1, comments="#", ndmin=2)
    ele = np.loadtxt(out + ".ele", skiprows=1, comments="#", ndmin=2, dtype=np.int64)
    m = pcdm.triangulate(SQUARE, "pq30", lenses=False,
                         size={"vertices": bv, "triangles": bt, "vertex_sizes": h})
    assert len(m["vertices"]) == len(node) and len(m["triangles"]) == len(ele)
    assert np.array_equal(m["vertices"], node[:, 1:3])
    first = int(node[0, 0])
    assert np.array_equal(m["triangles"], ele[:, 1:4] - first)


BV, BT = grid_mesh(1)  # 4 vertices, 2 triangles
BG = {"vertices": BV, "triangles": BT, "vertex_sizes": [0.1, 0.1, 0.1, 0.1]}
BAD = {
    "NaN vertex": (dict(BG, vertices=[[0, 0], [1, 0], [np.nan, 1], [1, 1]]),
                   r'size\["vertices"\]\[2\]: nan is not a finite number'),
    "index out of range": (dict(BG, triangles=[[0, 1, 3], [0, 3, 4]]),
                           r'size\["triangles"\]\[1\]: vertex 4 out of range \(0..3\)'),
    "negative index": (dict(BG, triangles=[[0, 1, -1], [0, 3, 2]]),
                       r'size\["triangles"\]\[0\]: vertex -1 out of range'),
    "negative size": (dict(BG, vertex_sizes=[0.1, 0.1, -0.5, 0.1]),
                      r'size\["vertex_sizes"\]\[2\]: -0.5 is not a positive number'),
    "zero size": (dict(BG, vertex_sizes=[0.1, 0, 0.1, 0.1]),
                  r'size\["vertex_sizes"\]\[1\]: 0 is not a positive number'),
    "infinite size": (dict(BG, vertex_sizes=[0.1, 0.1, 0.1, np.inf]),
                      r'size\["vertex_sizes"\]\[3\]: inf is not a finite number'),
    "negative area": ({"vertices": BV, "triangles": BT, "triangle_max_area": [1, -1]},
                      r'size\["triangle_max_area"\]\[1\]: -1 is not a positive number'),
    "degenerate triangle": (dict(BG, vertices=[[0, 0], [1, 0], [0, 1], [2, 0]]),
                            r'size\["triangles"\]\[0\]: degenerate'),
    "repeated corner": (dict(BG, triangles=[[0, 1, 3], [0, 0, 3]]),
                        r'size\["triangles"\]\[1\]: degenerate'),
    "sizes per vertex, too few": (dict(BG, vertex_sizes=[0.1, 0.1]),
                                  r'size\["vertex_sizes"\]: 2 values for 4 vertices'),
    "areas per triangle, too many": ({"vertices": BV, "triangles": BT,
                                      "triangle_max_area": [1, 1, 1]},
                                     r'size\["triangle_max_area"\]: 3 values for 2 triangles'),
    "sizes as columns": (dict(BG, vertex_sizes=np.ones((4, 2))),
                         r'size\["vertex_sizes"\]: expected shape'),
    "one size for all": (dict(BG, vertex_sizes=0.1), r'size\["vertex_sizes"\]: expected shape'),
    "vertices of 3 columns": (dict(BG, vertices=np.zeros((4, 3))),
                              r'size\["vertices"\]: expected shape \(N, 2\)'),
    "triangles of 2 columns": (dict(BG, triangles=[[0, 1], [1, 2]]),
                               r'size\["triangles"\]: expected shape \(N, 3\)'),
    "fractional index": (dict(BG, triangles=[[0, 1, 2.5], [0, 2, 3]]),
                         r'size\["triangles"\]\[0\]: 2.5 is not an integer'),
    "no triangles": (dict(BG, triangles=np.zeros((0, 3))), r'size\["triangles"\]: no triangles'),
    "no triangles key": ({"vertices": BV, "vertex_sizes": [1, 1, 1, 1]},
                         r'size\["triangles"\]: missing'),
    "no sizes": ({"vertices": BV, "triangles": BT}, "needs \"vertex_sizes\""),
    "both sizes": (dict(BG, triangle_max_area=[1, 1]), "not both"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_background(case):
    bg, words = BAD[case]
    with pytest.raises(ValueError, match=words):
        pcdm.triangulate(SQUARE, "pq", size=bg)


def test_not_a_background():
    with pytest.raises(TypeError, match="size: a callable"):
        pcdm.triangulate(SQUARE, "pq", size=[1, 2, 3])


def graded_background(n):
    """A background graded 1000:1 in edge length towards the corner (0, 0) of the unit square."""
    def rule(corners, area):
        return area > (1e-5 + 0.2 * np.hypot(*corners.mean(axis=0))) ** 2
    m = pcdm.triangulate(SQUARE, "pq30", size=rule)
    assert len(m["triangles"]) > n
    return m


@pytest.mark.parametrize("case", ["uniform", "graded"])
def test_cost_against_a_callable(case):
    """The same mesh from a, a constant background and a callable; prints the cost per query of
    the background's rule (in C) against the cheapest Python callable (area > A) on the
    same mesh (a constant background): medians of 5 alternating runs, the cost per query over
    the mesh of ``a``.  uniform: a 20 x 20 grid background over the unit square; graded: a
    background graded 1000:1 towards a corner, the mesh in the dense 5% x 5% there (every
    query where the background's triangles are smallest and most numerous)."""
    if case == "uniform":
        area, side = 1e-5, 1.0
        bv, bt = grid_mesh(20)
    else:
        area, side = 2.5e-8, 0.05
        g = graded_background(300)
        bv, bt = g["vertices"], g["triangles"]
    dom = {"vertices": np.array(SQ, dtype=float) * side, "segments": BOX}
    bg = {"vertices": bv, "triangles": bt, "triangle_max_area": np.full(len(bt), area)}
    calls = [0]

    def fn(corners, a):
        calls[0] += 1
        return a > area

    runs = {"a": ("pq30a%g" % area, None), "background": ("pq30", bg), "callable": ("pq30", fn)}
    times = {k: [] for k in runs}
    ntri = {}
    for _ in range(5):
        for k, (opts, size) in runs.items():
            calls[0] = 0
            t = time.perf_counter()
            m = pcdm.triangulate(dom, opts, size=size)
            times[k].append(time.perf_counter() - t)
            ntri[k] = len(m["triangles"])
            if k == "callable":
                queries = calls[0]
    assert ntri["a"] == ntri["background"] == ntri["callable"]
    med = {k: sorted(v)[2] for k, v in times.items()}
    per = {k: (med[k] - med["a"]) / queries * 1e6 for k in ("background", "callable")}
    print("\nsize queries (%s background, %d triangles): %d on %d triangles; medians: a %.3f s, "
          "background %.3f s, callable %.3f s; per query over a: background %.3f us, callable "
          "%.3f us" % (case, len(bt), queries, ntri["a"], med["a"], med["background"],
                       med["callable"], per["background"], per["callable"]))


def rss_kb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") // 1024


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="no /proc/self/statm")
def test_repeated_calls_do_not_grow_memory():
    bv, bt = grid_mesh(4)
    good = {"vertices": bv, "triangles": bt, "vertex_sizes": 0.1 + bv[:, 0]}
    bad = dict(good, triangles=np.vstack([bt[:-1], [[0, 1, 1]]]))  # refused while checked
    empty = dict(SQUARE, holes=[[0.5, 0.5]])  # refused by the mesher, after the tree is built

    def calls(n):
        for _ in range(n):
            assert len(pcdm.triangulate(SQUARE, "pq30", size=good)["triangles"]) > 20
            with pytest.raises(ValueError, match="degenerate"):
                pcdm.triangulate(SQUARE, "pq30", size=bad)
            with pytest.raises(ValueError, match="domain is empty"):
                pcdm.triangulate(empty, "pq30", size=good)
    calls(500)
    before = rss_kb()
    calls(5000)
    grown = rss_kb() - before
    print(f"\nsize= background: RSS after 500 calls {before} KB, after 5,000 more "
          f"{before + grown} KB")
    assert grown < 1024, f"RSS grew {grown} KB over 5,000 calls"
