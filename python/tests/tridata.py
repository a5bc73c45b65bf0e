"""The triangle package's own data files, shared by the tests that compare against it: where
they are (DATA), the input keys of a data set (IN_KEYS) and the data sets' names (names())."""

import os

import pytest

triangle = pytest.importorskip("triangle")

DATA = os.path.join(os.path.dirname(triangle.__file__), "data")
IN_KEYS = ("vertices", "vertex_markers", "vertex_attributes", "segments", "segment_markers",
           "holes", "regions")


def names():
    """Every data set: a .poly or .node of the data folder that is not a mesh (NAME.1.node)."""
    out = set()
    for f in os.listdir(DATA):
        base, ext = os.path.splitext(f)
        if ext in (".poly", ".node") and "." not in base:
            out.add(base)
    return sorted(out)
