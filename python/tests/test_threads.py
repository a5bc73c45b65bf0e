"""pcdm.triangulate(..., threads=T): ./pcdm's subdomain mesher on T worker threads of this
process, no MPI (the package's _core built with METIS: the parallel stack over the one-process
MPI stand-in runtime/mpi1).

- threads 1, 2 and 3 give one mesh, array for array; threads 0 (the default) is the sequential
  mesher's, another mesh; both pass pcdm.check with the bounds;
- bad input through the threaded path raises ValueError (the process lives on), and the next
  call meshes;
- a build without METIS refuses threads with a ValueError that says so.
"""

import ctypes.util
import os

import numpy as np
import pytest

import pcdm

# a plate with a hole, in non-dyadic coordinates
PLATE = {
    "vertices": np.array([[0, 0], [10, 0], [10, 6], [0, 6],
                          [4.1, 2.3], [5.7, 2.3], [5.7, 3.9], [4.1, 3.9]], dtype=float),
    "segments": np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]),
    "holes": np.array([[4.9, 3.1]]),
}
OPTS = "pq30a0.002"


def has_threads():
    """Whether this build has the threaded mesher (ValueError naming METIS when not)."""
    try:
        pcdm.triangulate(PLATE, "pq20a1", threads=2)
        return True
    except ValueError as e:
        assert "METIS" in str(e), str(e)
        return False


def test_threads_or_metis_message():
    """Threads where libmetis is (and PCDM_THREADS=0 did not turn them off), else the message."""
    want = ctypes.util.find_library("metis") is not None and os.environ.get("PCDM_THREADS") != "0"
    assert has_threads() == want


@pytest.mark.skipif(not has_threads(), reason="built without METIS")
def test_same_mesh_any_threads():
    m = {t: pcdm.triangulate(PLATE, OPTS, threads=t) for t in (0, 1, 2, 3)}
    for t in (2, 3):
        for k in ("vertices", "vertex_markers", "triangles", "segments", "segment_markers"):
            assert np.array_equal(m[t][k], m[1][k]), (t, k)
    assert len(m[0]["triangles"]) != len(m[1]["triangles"]) or \
        not np.array_equal(m[0]["vertices"], m[1]["vertices"])
    print("threads 0: %d triangles, threads 1-3: %d" % (len(m[0]["triangles"]),
                                                         len(m[1]["triangles"])))
    for t in (0, 2):
        r = pcdm.check(m[t], PLATE, q=30, a=0.002)
        assert r["ok"], r


@pytest.mark.skipif(not has_threads(), reason="built without METIS")
def test_bad_input_raises():
    bad = dict(PLATE, vertices=PLATE["vertices"].copy())
    bad["vertices"][2, 1] = np.nan
    with pytest.raises(ValueError):
        pcdm.triangulate(bad, OPTS, threads=2)
    with pytest.raises(ValueError, match="out of range"):
        pcdm.triangulate(dict(PLATE, segments=np.array([[0, 1], [1, 99]])), OPTS, threads=2)
    with pytest.raises(ValueError, match="zero length"):
        pcdm.triangulate(dict(PLATE, segments=np.array([[0, 1], [1, 1], [1, 2], [2, 3], [3, 0]])),
                         OPTS, threads=2)
    with pytest.raises(ValueError):
        pcdm.triangulate({"vertices": np.zeros((0, 2))}, OPTS, threads=2)
    with pytest.raises(ValueError):
        pcdm.triangulate({"vertices": np.array([[0, 0], [1, 1], [2, 2], [3, 3.0]])}, "q30",
                         threads=2)
    m = pcdm.triangulate(PLATE, OPTS, threads=2)  # and the next call meshes
    assert len(m["triangles"]) > 1000


@pytest.mark.skipif(not has_threads(), reason="built without METIS")
def test_size_rules_with_threads():
    """size= (a callable, called back from the worker threads with the GIL, and a background
    mesh, read by them without it) gives one mesh for threads 1 and 2, and meets its bound."""
    corner = lambda c: np.hypot(c[:, 0], c[:, 1])  # noqa: E731
    def fn(corners, area):
        return area > 0.0005 + 0.01 * corner(corners.mean(axis=0, keepdims=True))[0]
    bg = {"vertices": np.array([[0, 0], [10, 0], [10, 6], [0, 6.0]]),
          "triangles": np.array([[0, 1, 2], [0, 2, 3]]),
          "vertex_sizes": np.array([0.05, 0.5, 0.5, 0.5])}
    for size in (fn, bg):
        m = {t: pcdm.triangulate(PLATE, "pq30", size=size, threads=t) for t in (1, 2)}
        for k in ("vertices", "triangles", "segments"):
            assert np.array_equal(m[1][k], m[2][k]), k
        r = pcdm.check(m[2], PLATE, q=30)
        assert r["ok"], r
        v, t = m[2]["vertices"], m[2]["triangles"]
        p = v[t]
        d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
        area = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
        if size is fn:
            bound = 0.0005 + 0.01 * corner(p.mean(axis=1))
            assert (area <= bound * (1 + 1e-9)).all()
        assert len(t) > 200
