"""The triangle package's point-set calls -- ``delaunay``, ``convex_hull``, ``voronoi`` -- made
from ``pcdm.triangulate`` of the points alone (their Delaunay triangulation, exact predicates)
with numpy."""

from __future__ import annotations

from typing import Any, Tuple

import numpy as np


def _points(pts: Any) -> np.ndarray:
    """pts as an (N, 2) float64 array, or ValueError naming what is wrong."""
    from . import _floats  # the checks of triangulate's input (shape, finite, real)

    a = _floats({"pts": pts}, "pts", 2)
    if a is None:
        raise ValueError("pts: None (an (N, 2) array of N >= 3 points)")
    return a


def _mesh(pts: Any, opts: str) -> Tuple[np.ndarray, dict]:
    """The Delaunay triangulation of pts by triangulate, its indices mapped back to pts: a
    point given twice is meshed once, as its first occurrence."""
    from . import triangulate

    p = _points(pts)
    m = triangulate({"vertices": p}, opts)
    v = m["vertices"]
    if len(v) != len(p) or not np.array_equal(v, p):
        first: dict = {}
        for i, xy in enumerate(map(tuple, p.tolist())):
            first.setdefault(xy, i)
        back = np.array([first[xy] for xy in map(tuple, v.tolist())], dtype=np.int32)
        for k in ("triangles", "segments"):
            if k in m:
                m[k] = back[m[k]]
    return p, m


def delaunay(pts: Any) -> np.ndarray:
    """The triangles of the Delaunay triangulation of the points ``pts`` ((N, 2)): an int32
    (T, 3) array of indices into ``pts``, each triangle counter-clockwise.  A point given more
    than once is used once (its first occurrence); fewer than 3 distinct points, or all of them
    on a line, raise ``ValueError``.

    >>> delaunay([[0, 0], [1, 0], [0, 1]]).tolist()
    [[1, 2, 0]]
    """
    return np.ascontiguousarray(_mesh(pts, "")[1]["triangles"], dtype=np.int32)


def convex_hull(pts: Any) -> np.ndarray:
    """The edges of the convex hull of the points ``pts`` ((N, 2)): an int32 (H, 2) array of
    indices into ``pts``, in order around the hull, each edge with the hull's inside on its
    right (as the triangle package gives them); a point lying on the hull's boundary is a
    corner of two edges.

    >>> convex_hull([[0, 0], [1, 0], [0, 1]]).tolist()
    [[1, 0], [2, 1], [0, 2]]
    """
    seg = _mesh(pts, "c")[1]["segments"]
    return np.ascontiguousarray(seg[:, ::-1], dtype=np.int32)


def _circumcenters(p: np.ndarray, t: np.ndarray) -> np.ndarray:
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    ba, ca = b - a, c - a
    lb, lc = (ba * ba).sum(1), (ca * ca).sum(1)
    d = 2.0 * (ba[:, 0] * ca[:, 1] - ba[:, 1] * ca[:, 0])
    x = (ca[:, 1] * lb - ba[:, 1] * lc) / d
    y = (ba[:, 0] * lc - ca[:, 0] * lb) / d
    return a + np.stack([x, y], axis=1)


def voronoi(pts: Any) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The Voronoi diagram of the points ``pts`` ((N, 2)), as the triangle package returns it:
    ``(points, edges, ray_origin, ray_direction)`` --

    - ``points``, float64 (T, 2): the Voronoi vertices, the circumcenter of each triangle of
      ``delaunay(pts)`` in that order;
    - ``edges``, int32 (E, 2): the finite Voronoi edges, one for each Delaunay edge inside the
      hull, joining the circumcenters of its two triangles (sorted pairs, in order);
    - ``ray_origin``, int32 (R,): for each edge of the convex hull, the Voronoi vertex its
      infinite ray starts from (its triangle's circumcenter);
    - ``ray_direction``, float64 (R, 2): the ray's direction, outward, perpendicular to that hull
      edge and as long as it.

    Points on a common circle give coincident Voronoi vertices (and edges of length zero
    between them), one per Delaunay triangle.

    >>> points, edges, origin, direction = voronoi([[0, 0], [1, 0], [0, 1], [1, 1.5]])
    >>> points.tolist(), edges.tolist()
    ([[0.5, 0.5], [0.75, 0.75]], [[0, 1]])
    """
    p, m = _mesh(pts, "")
    t = np.ascontiguousarray(m["triangles"], dtype=np.int64)
    nt = len(t)
    points = _circumcenters(p, t)
    # every directed edge (t[i, j], t[i, j+1]) of every (counter-clockwise) triangle
    a = t.reshape(-1)
    b = np.roll(t, -1, axis=1).reshape(-1)
    owner = np.repeat(np.arange(nt), 3)
    n = np.int64(len(p))
    key = np.minimum(a, b) * n + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    k = key[order]
    pair = np.flatnonzero(k[1:] == k[:-1])  # an edge two triangles share
    shared = np.zeros(len(k), dtype=bool)
    shared[pair] = shared[pair + 1] = True
    e = np.sort(np.stack([owner[order[pair]], owner[order[pair + 1]]], axis=1), axis=1)
    e = e[np.lexsort((e[:, 1], e[:, 0]))]
    hull = np.sort(order[~shared])  # edges of one triangle: the hull's, by triangle
    d = p[b[hull]] - p[a[hull]]
    direction = np.stack([d[:, 1], -d[:, 0]], axis=1) + 0.0  # the edge turned outward (no -0)
    return (
        points,
        np.ascontiguousarray(e, dtype=np.int32),
        np.ascontiguousarray(owner[hull], dtype=np.int32),
        np.ascontiguousarray(direction, dtype=np.float64),
    )
