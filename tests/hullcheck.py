#!/usr/bin/env python3
"""hullcheck.py INPUT PREFIX [--area A] [--minus-cycle I,J,K,...] [--triangle SWITCHES]: checks a
mesh made with -c (PREFIX.node, PREFIX.poly) against INPUT (.poly or .node) independently of the
mesher, in exact rational arithmetic (tests/t_hull.sh):
 - the written segments are distinct and no mesh vertex lies inside one;
 - the convex hull of INPUT's vertices (computed here) is covered exactly by written segments
   (whose new vertices lie within 1e-9 of the edge's length from its line: rounded);
 - a written segment on the hull carries the marker of the input segment it lies on (the first
   in the file, as overlaps are split) when that is nonzero, else 1 (Triangle's -c);
   the domain must reach the whole hull (no hole point between a hull edge and the segments);
 - --area A: A (the area ./meshcheck measured) is the hull's area minus the areas of the
   polygons given by --minus-cycle (INPUT's vertex numbers, e.g. a hole's boundary), to 1e-12;
 - --triangle SW: Triangle itself (the PyPI `triangle` package, if installed) meshes INPUT with
   SW and writes the same segments with the same markers (compare with a mesh made without
   Steiner points, --cdt-only).
Exit 1 with a message on the first problem."""
import os
import sys
from fractions import Fraction as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xcheck import fail, rows  # noqa: E402  (the .node/.ele readers tests/xcheck.py uses)


def read_node(r, at):
    n, _, nattr, nmark = (int(x) for x in r[at][:4])
    pts = {}
    for row in r[at + 1:at + 1 + n]:
        pts[int(row[0])] = (F(float(row[1])), F(float(row[2])))
    return pts, at + 1 + n


def read_input(path):
    r = rows(path)
    if path.endswith(".node"):
        return read_node(r, 0)[0], []
    pts, at = read_node(r, 0)
    if not pts:
        pts = read_node(rows(path[:-5] + ".node"), 0)[0]
    m, nmark = int(r[at][0]), int(r[at][1])
    segs = [(int(x[1]), int(x[2]), int(x[3]) if nmark else 0) for x in r[at + 1:at + 1 + m]]
    return pts, segs


def orient(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def on_closed(a, b, p, tol=0):
    """p on the closed segment ab; tol > 0: within tol |ab| of its line (a point the mesher put
    on a slanted segment is rounded to doubles, a few ulps off it)."""
    if tol == 0 and orient(a, b, p) != 0:
        return False
    if tol and orient(a, b, p) ** 2 > tol * tol * ((b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2) ** 2:
        return False
    return (min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and
            min(a[1], b[1]) <= p[1] <= max(a[1], b[1]))


TOL = F(1, 10 ** 9)


def hull(points):
    """Corners only (collinear points dropped), counter-clockwise."""
    p = sorted(set(points))
    chain = []
    for seq in (p, p[::-1]):
        part = []
        for q in seq:
            while len(part) >= 2 and orient(part[-2], part[-1], q) <= 0:
                part.pop()
            part.append(q)
        chain += part[:-1]
    return chain


def area(poly):
    return sum(poly[i][0] * poly[(i + 1) % len(poly)][1] - poly[(i + 1) % len(poly)][0] *
               poly[i][1] for i in range(len(poly))) / 2


def along(a, b, p):
    """p's position on segment ab, 0 at a and 1 at b (p on the line ab)."""
    k = 0 if a[0] != b[0] else 1
    return (p[k] - a[k]) / (b[k] - a[k])


def main():
    args = sys.argv[1:]
    opts = {}
    while len(args) > 2:
        opts[args[-2]] = args[-1]
        args = args[:-2]
    inp, prefix = args
    ipts, isegs = read_input(inp)
    mpts = read_node(rows(prefix + ".node"), 0)[0]
    r = rows(prefix + ".poly")
    nseg = int(r[1][0])
    msegs = [(mpts[int(x[1])], mpts[int(x[2])], int(x[3])) for x in r[2:2 + nseg]]
    keys = [frozenset((a, b)) for a, b, _ in msegs]
    if len(set(keys)) != len(keys):
        fail("%s.poly: a segment is written twice" % prefix)
    verts = set(mpts.values())
    for a, b, _ in msegs:
        for p in verts:
            if p != a and p != b and on_closed(a, b, p):
                fail("%s.poly: vertex (%s, %s) lies inside segment (%s, %s)-(%s, %s)" %
                     (prefix, float(p[0]), float(p[1]), float(a[0]), float(a[1]), float(b[0]),
                      float(b[1])))
    h = hull(list(ipts.values()))
    nb = 0
    for i in range(len(h)):
        a, b = h[i], h[(i + 1) % len(h)]
        cover = F(0)
        for p, q, mk in msegs:
            if not (on_closed(a, b, p, TOL) and on_closed(a, b, q, TOL)):
                continue
            nb += 1
            cover += abs(along(a, b, q) - along(a, b, p))
            want = 0  # the first input segment's marker (overlaps keep it), 0 on the hull: 1
            for u, v, imk in isegs:
                if on_closed(ipts[u], ipts[v], p, TOL) and on_closed(ipts[u], ipts[v], q, TOL):
                    want = imk
                    break
            want = want or 1
            if mk != want:
                fail("segment (%s, %s)-(%s, %s) on the hull has marker %d, expected %d" %
                     (float(p[0]), float(p[1]), float(q[0]), float(q[1]), mk, want))
        if cover != 1:
            fail("hull edge (%s, %s)-(%s, %s): written segments cover %s of it" %
                 (float(a[0]), float(a[1]), float(b[0]), float(b[1]), float(cover)))
    print("hullcheck: %d hull corners, %d written segments on the hull, markers as expected" %
          (len(h), nb))
    if "--area" in opts:
        want = area(h)
        if "--minus-cycle" in opts:
            want -= area([ipts[int(v)] for v in opts["--minus-cycle"].split(",")])
        got = float(opts["--area"])
        if abs(got - float(want)) > 1e-12 * float(want):
            fail("area %r, expected the hull's minus the holes': %r" % (got, float(want)))
        print("hullcheck: area %r = hull %r minus holes" % (got, float(area(h))))
    if "--triangle" in opts:
        try:
            import triangle
        except ImportError:
            print("hullcheck: no comparison with Triangle (no python package `triangle`)")
            return
        d, name = os.path.split(inp)
        name = name.rsplit(".", 1)[0]
        t = triangle.triangulate(triangle.load(d or ".", name), opts["--triangle"])
        xy = t["vertices"]
        theirs = {(frozenset(((F(float(xy[a][0])), F(float(xy[a][1]))),
                              (F(float(xy[b][0])), F(float(xy[b][1]))))), int(m))
                  for (a, b), m in zip(t["segments"], t["segment_markers"].ravel())}
        ours = {(k, mk) for k, (_, _, mk) in zip(keys, msegs)}
        if theirs != ours:
            fail("Triangle -%s writes other segments: only Triangle's: %s; only ours: %s" %
                 (opts["--triangle"], sorted(str(sorted(map(float, sum(map(list, k), []))))
                                             for k, _ in theirs - ours)[:4],
                  sorted(str(sorted(map(float, sum(map(list, k), []))))
                         for k, _ in ours - theirs)[:4]))
        print("hullcheck: Triangle -%s writes the same %d segments and markers" %
              (opts["--triangle"], len(ours)))


main()
