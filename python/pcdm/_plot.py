"""``plot`` and ``compare``, the triangle package's pictures of a triangulation's dict, drawn
with matplotlib (imported when they are called, never by ``import pcdm``)."""

from __future__ import annotations

from typing import Any, Tuple

import numpy as np


def _array(kw: dict, key: str, cols: int, dtype: Any) -> Any:
    a = kw.get(key)
    if a is None:
        return None
    a = np.asarray(a, dtype=dtype)
    if a.size == 0:
        return None
    return a.reshape(-1, cols) if cols else a.reshape(-1)


def _edges_of(triangles: np.ndarray) -> np.ndarray:
    """Every edge of the triangles once (corners only: a quadratic triangle's first three)."""
    t = triangles[:, :3]
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    return np.unique(np.sort(e, axis=1), axis=0)


def plot(ax: Any, **kw: Any) -> None:
    """Draw a triangulation's dict on the matplotlib axes ``ax`` (``plot(ax, **mesh)``):
    ``vertices`` as dots, ``triangles`` as their edges, ``segments`` as thick lines, ``holes``
    as crosses, and a Voronoi diagram's ``edges`` and rays (``ray_origins``, indices into
    ``vertices``, and ``ray_directions``; the rays reach past the axes' limits without widening
    them); other keys are ignored.  The axes get an equal aspect ratio."""
    from matplotlib.collections import LineCollection

    v = _array(kw, "vertices", 2, np.float64)
    if v is not None:
        tri = kw.get("triangles")
        if tri is not None and np.size(tri):
            tri = np.asarray(tri, dtype=np.int64)
            lines = v[_edges_of(tri.reshape(len(tri), -1))]
            ax.add_collection(LineCollection(lines, colors="tab:blue", linewidths=0.5, zorder=1))
        e = _array(kw, "edges", 2, np.int64)
        if e is not None:
            ax.add_collection(LineCollection(v[e], colors="tab:blue", linewidths=0.8, zorder=1))
        s = _array(kw, "segments", 2, np.int64)
        if s is not None:
            ax.add_collection(LineCollection(v[s], colors="tab:green", linewidths=2, zorder=2))
        o = _array(kw, "ray_origins", 0, np.int64)
        d = _array(kw, "ray_directions", 2, np.float64)
        if o is not None and d is not None:
            span = float(np.ptp(v, axis=0).max()) or 1.0
            n = np.hypot(d[:, 0], d[:, 1])
            n[n == 0] = 1.0
            end = v[o] + d * (1e3 * span / n)[:, None]
            rays = np.stack([v[o], end], axis=1)
            ax.add_collection(
                LineCollection(rays, colors="tab:blue", linewidths=0.8, zorder=1), autolim=False
            )
        ax.plot(v[:, 0], v[:, 1], "k.", markersize=4, zorder=3)
    h = _array(kw, "holes", 2, np.float64)
    if h is not None:
        ax.plot(h[:, 0], h[:, 1], "rx", markersize=6, zorder=4)
    ax.set_aspect("equal")
    ax.autoscale_view()


def compare(plt: Any, A: dict, B: dict, figsize: Tuple[float, float] = (6, 3)) -> None:
    """Two triangulations' dicts side by side on a new figure of size ``figsize`` (matplotlib's
    ``pyplot`` as ``plt``): ``plot`` of ``A`` on the left, of ``B`` on the right, the two axes
    sharing their limits."""
    plt.figure(figsize=figsize)
    ax1 = plt.subplot(121)
    plot(ax1, **A)
    ax2 = plt.subplot(122, sharex=ax1, sharey=ax1)
    plot(ax2, **B)
    plt.tight_layout()
