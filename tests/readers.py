#!/usr/bin/env python3
"""readers.py DIR NP...: checks DIR/mNP.{node,ele,poly} and DIR/mNP.pvtu (written by ./pcdm at
NP ranks, tests/t_readers.sh) with the PyPI `triangle` reader and meshio.  Exit status 1 and a
message on the first problem."""
import os
import re
import sys

import meshio
import numpy as np
import triangle


def fail(msg):
    print("FAIL " + msg)
    sys.exit(1)


def tri_set(xy, tris):
    """Triangles as a set of sorted coordinate triples (exact doubles)."""
    return {tuple(sorted(tuple(xy[v]) for v in t)) for t in tris}


def header_count(path):
    with open(path) as f:
        return int(f.readline().split()[0])


def main():
    d, nps = sys.argv[1], [int(a) for a in sys.argv[2:]]
    for np_ in nps:
        name = "m%d" % np_
        # the triangle package's reader (.node/.ele/.poly, Triangle's conventions)
        t = triangle.load(d, name)
        xy, tris = np.asarray(t["vertices"]), np.asarray(t["triangles"])
        nv, nt = header_count(os.path.join(d, name + ".node")), header_count(
            os.path.join(d, name + ".ele"))
        if len(xy) != nv or len(tris) != nt:
            fail("%s: triangle.load read %d vertices, %d triangles; headers say %d, %d" %
                 (name, len(xy), len(tris), nv, nt))
        if tris.min() < 0 or tris.max() >= nv:
            fail("%s: triangle indices out of range" % name)
        if "triangle_attributes" in t:  # Triangle's: only with -A (the rank is VTK cell data)
            fail("%s: the .ele has an attribute column without -A" % name)
        if "segments" not in t or len(t["segments"]) == 0:
            fail("%s: no segments read from the .poly" % name)
        s_tri = tri_set(xy, tris)
        if len(s_tri) != nt:
            fail("%s: %d triangles but %d distinct ones" % (name, nt, len(s_tri)))
        # meshio: every piece the .pvtu names
        with open(os.path.join(d, name + ".pvtu")) as f:
            pieces = re.findall(r'Source="([^"]+)"', f.read())
        if len(pieces) != np_:
            fail("%s.pvtu names %d pieces, expected %d" % (name, len(pieces), np_))
        s_vtu, subs = set(), set()
        for r, piece in enumerate(pieces):
            m = meshio.read(os.path.join(d, piece))
            cells = m.cells_dict.get("triangle")
            if cells is None:
                fail("%s: no triangles" % piece)
            for key in ("rank", "subdomain"):
                if key not in m.cell_data:
                    fail("%s: no cell data %s" % (piece, key))
            if "marker" not in m.point_data:
                fail("%s: no point data marker" % piece)
            rk = np.concatenate(m.cell_data["rank"])
            if not (rk == r).all():
                fail("%s: cell data rank is not %d everywhere" % (piece, r))
            subs |= set(np.concatenate(m.cell_data["subdomain"]).astype(int).tolist())
            pts = m.points[:, :2]
            s_vtu |= tri_set(pts, cells)
        if subs != set(range(4)):
            fail("%s: subdomains %s, expected 0..3" % (name, sorted(subs)))
        if s_vtu != s_tri:
            fail("%s: the .vtu pieces (%d triangles) and the Triangle files (%d) differ" %
                 (name, len(s_vtu), len(s_tri)))
        print("ok   np=%d: triangle.load and meshio read %d triangles, %d vertices" % (np_, nt, nv))


main()
