#!/usr/bin/env python3
"""xtriangle.py DIR NAME PREFIX: compares ./mesh --cdt-only -e -n --order2 -o PREFIX (run on
DIR/NAME.poly) with the PyPI `triangle` package (Triangle itself) on the same input, switches
-pen and -po2: the constrained Delaunay triangulation is unique for these inputs, so the
triangles, the edges with their boundary markers, the neighbour pairs and, for every triangle,
the midpoint node opposite each corner must be the same (keyed by exact coordinates).  Exit 1
with a message on the first difference (tests/t_xwrite.sh)."""
import sys

import triangle


def rows(p):
    out = []
    for line in open(p):
        f = line.split("#")[0].split()
        if f:
            out.append(f)
    return out


def fail(msg):
    print("FAIL " + msg)
    sys.exit(1)


def main():
    d, name, prefix = sys.argv[1:4]
    A = triangle.load(d, name)
    B = triangle.triangulate(A, "pen")
    xy = [tuple(map(float, p)) for p in B["vertices"]]
    tkey = lambda pts, t: tuple(sorted(pts[v] for v in t[:3]))
    T = [tkey(xy, t) for t in B["triangles"]]
    E = {tuple(sorted((xy[a], xy[b]))): int(m)
         for (a, b), m in zip(B["edges"], B["edge_markers"].ravel())}
    N = {tuple(sorted((T[t], T[n]))) for t, nb in enumerate(B["neighbors"]) for n in nb if n >= 0}
    C = triangle.triangulate(A, "po2")
    cxy = [tuple(map(float, p)) for p in C["vertices"]]
    M = {}
    for t in C["triangles"]:
        for j in range(3):
            M[(tkey(cxy, t), cxy[t[j]])] = cxy[t[3 + j]]

    nd = rows(prefix + ".node")
    pxy = {int(r[0]): (float(r[1]), float(r[2])) for r in nd[1:]}
    tr = [[int(v) for v in r[1:7]] for r in rows(prefix + ".ele")[1:]]
    T2 = [tkey(pxy, t) for t in tr]
    if set(T2) != set(T):
        fail("%s: %d triangles, Triangle made %d (sets differ)" % (name, len(T2), len(T)))
    E2 = {tuple(sorted((pxy[int(r[1])], pxy[int(r[2])]))): int(r[3])
          for r in rows(prefix + ".edge")[1:]}
    if E2 != E:
        bad = [k for k in E if E2.get(k) != E[k]][:3]
        fail("%s: edges differ from Triangle's: %s" % (name, [(k, E[k], E2.get(k)) for k in bad]))
    N2 = set()
    for r in rows(prefix + ".neigh")[1:]:
        t = int(r[0]) - 1
        for n in r[1:4]:
            if int(n) > 0:
                N2.add(tuple(sorted((T2[t], T2[int(n) - 1]))))
    if N2 != N:
        fail("%s: %d neighbour pairs, Triangle's %d (sets differ)" % (name, len(N2), len(N)))
    for t in tr:
        for j in range(3):
            if M.get((tkey(pxy, t), pxy[t[j]])) != pxy[t[3 + j]]:
                fail("%s: triangle %s: node %d is not Triangle's -o2 node" % (name, t, 4 + j))
    print("ok   %s: as Triangle: %d triangles, %d edges and markers, %d neighbour pairs, -o2 "
          "nodes" % (name, len(T), len(E), len(N)))


main()
