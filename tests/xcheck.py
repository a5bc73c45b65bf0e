#!/usr/bin/env python3
"""xcheck.py PREFIX [--o2] [--msh FILE] [--vtk FILE] [--keys OUT]: checks the derived outputs
of one run (tests/t_xwrite.sh) against its own PREFIX.node/.ele, read independently here:
 - PREFIX.edge (when present): every edge of the triangles exactly once, boundary edges (of
   one triangle) marked non-zero, the rest marked 0 unless on a .poly segment with a marker;
 - PREFIX.neigh (when present): neighbour j of triangle t shares t's edge opposite corner j,
   -1 exactly on the boundary;
 - --o2: .ele has six nodes, node 3+j is the midpoint of the edge opposite corner j, every
   midpoint node is one edge's;
 - --msh: meshio reads the Gmsh file; its triangles (or triangle6) are the .ele's (as sets of
   coordinates), its lines the boundary and segment edges, physical groups named; and when
   Gmsh's Python package is installed, gmsh reads the same triangles and groups;
 - --vtk (with --o2): meshio reads the quadratic VTK (triangle6 cells).
 --keys OUT writes the triangles, the edges (with markers) and the neighbour pairs as sorted
 coordinate keys, so that runs at different rank counts can be compared.  Exit 1 with a message on a problem."""
import os
import sys


def fail(msg):
    print("FAIL " + msg)
    sys.exit(1)


def rows(path):
    out = []
    with open(path) as f:
        for line in f:
            line = line.split("#")[0].split()
            if line:
                out.append(line)
    return out


def main():
    a = sys.argv[1:]
    prefix = a[0]
    o2 = "--o2" in a
    opt = lambda k: a[a.index(k) + 1] if k in a else None
    msh, vtk, keys = opt("--msh"), opt("--vtk"), opt("--keys")
    nd = rows(prefix + ".node")
    nv = int(nd[0][0])
    nattr = int(nd[0][2])
    xy = {}
    for r in nd[1:1 + nv]:
        xy[int(r[0])] = (float(r[1]), float(r[2]))
    if len(xy) != nv:
        fail("%s.node: %d nodes, header says %d" % (prefix, len(xy), nv))
    el = rows(prefix + ".ele")
    nt, per = int(el[0][0]), int(el[0][1])
    if per != (6 if o2 else 3):
        fail("%s.ele: %d nodes per triangle" % (prefix, per))
    tris = [[int(v) for v in r[1:1 + per]] for r in el[1:1 + nt]]
    tnum = [int(r[0]) for r in el[1:1 + nt]]
    if tnum != list(range(1, nt + 1)):
        fail("%s.ele: triangles not numbered 1..%d" % (prefix, nt))
    key = lambda u, v: tuple(sorted((xy[u], xy[v])))
    edges = {}
    for t, tr in enumerate(tris):
        for j in range(3):
            edges.setdefault(key(tr[(j + 1) % 3], tr[(j + 2) % 3]), []).append((t, j))
    bound = {k for k, v in edges.items() if len(v) == 1}
    segs = {}
    if os.path.exists(prefix + ".poly"):
        po = rows(prefix + ".poly")
        ns = int(po[1][0])
        for r in po[2:2 + ns]:
            segs[key(int(r[1]), int(r[2]))] = int(r[3]) if len(r) > 3 else 0
    out_keys = []
    if os.path.exists(prefix + ".edge"):
        ed = rows(prefix + ".edge")
        ne = int(ed[0][0])
        seen = {}
        for i, r in enumerate(ed[1:1 + ne]):
            if int(r[0]) != i + 1:
                fail("%s.edge: edge %d numbered %s" % (prefix, i + 1, r[0]))
            k = key(int(r[1]), int(r[2]))
            if k in seen:
                fail("%s.edge: edge %s twice" % (prefix, k))
            seen[k] = int(r[3])
        if set(seen) != set(edges):
            fail("%s.edge: %d edges, the triangles have %d (%d missing)" %
                 (prefix, len(seen), len(edges), len(set(edges) - set(seen))))
        for k, m in seen.items():
            want = segs.get(k, 0) or (1 if k in bound else 0)
            if m != want:
                fail("%s.edge: edge %s has marker %d, expected %d" % (prefix, k, m, want))
        out_keys += ["E %r %r %d" % (k[0], k[1], m) for k, m in seen.items()]
        print("ok   %s.edge: %d edges, %d on the boundary" % (prefix, ne, len(bound)))
    if os.path.exists(prefix + ".neigh"):
        ng = rows(prefix + ".neigh")
        if int(ng[0][0]) != nt or int(ng[0][1]) != 3:
            fail("%s.neigh: header %s" % (prefix, ng[0]))
        for t, r in enumerate(ng[1:1 + nt]):
            tr = tris[t]
            for j in range(3):
                n = int(r[1 + j])
                k = key(tr[(j + 1) % 3], tr[(j + 2) % 3])
                if n == -1:
                    if k not in bound:
                        fail("%s.neigh: triangle %d, neighbour %d is -1 on an inner edge" %
                             (prefix, t + 1, j))
                    continue
                if n < 1 or n > nt or n == t + 1:
                    fail("%s.neigh: triangle %d: neighbour %d" % (prefix, t + 1, n))
                other = tris[n - 1][:3]
                if not all(xy[v] in {xy[u] for u in other} for v in
                           (tr[(j + 1) % 3], tr[(j + 2) % 3])):
                    fail("%s.neigh: triangle %d, neighbour %d (%d) does not share the edge "
                         "opposite corner %d" % (prefix, t + 1, j, n, j))
                out_keys.append("N %r %r" % tuple(sorted((
                    tuple(sorted(xy[v] for v in tr[:3])), tuple(sorted(xy[v] for v in other))))))
        print("ok   %s.neigh: %d triangles" % (prefix, nt))
    if o2:
        mids = {}
        for t, tr in enumerate(tris):
            for j in range(3):
                p, q = xy[tr[(j + 1) % 3]], xy[tr[(j + 2) % 3]]
                m = xy[tr[3 + j]]
                if m != ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2):
                    d = max(abs(m[0] - (p[0] + q[0]) / 2), abs(m[1] - (p[1] + q[1]) / 2))
                    if d > 1e-12 * (1 + max(abs(c) for c in p + q)):
                        fail("%s: triangle %d: node %d at %s is not the midpoint of %s, %s" %
                             (prefix, t + 1, 4 + j, m, p, q))
                k = key(tr[(j + 1) % 3], tr[(j + 2) % 3])
                if mids.setdefault(k, tr[3 + j]) != tr[3 + j]:
                    fail("%s: edge %s has two midpoint nodes %d, %d" % (prefix, k, mids[k],
                                                                     tr[3 + j]))
        corners = {v for tr in tris for v in tr[:3]}
        if len(set(mids.values())) != len(mids) or corners & set(mids.values()):
            fail("%s: midpoint nodes shared between edges or with corners" % prefix)
        if len(corners) + len(mids) != nv:
            fail("%s.node: %d nodes, %d corners + %d midpoints" % (prefix, nv, len(corners),
                                                                    len(mids)))
        print("ok   %s: quadratic, %d midpoints" % (prefix, len(mids)))
    if msh or vtk:
        try:
            import meshio
        except ImportError:
            print("skip meshio checks: python meshio not installed")
            msh = vtk = None
    if msh:
        m = meshio.read(msh)
        tt = "triangle6" if o2 else "triangle"
        lt = "line3" if o2 else "line"
        got = [c.data for c in m.cells if c.type == tt]
        if sum(len(c) for c in got) != nt:
            fail("%s: %d %s cells, .ele has %d" % (msh, sum(len(c) for c in got), tt, nt))
        P = [tuple(p[:2]) for p in m.points]
        ts = {tuple(sorted(P[v] for v in c)) for blk in got for c in blk}
        want = {tuple(sorted(xy[v] for v in tr)) for tr in tris}
        if ts != want:
            fail("%s: triangles differ from %s.ele" % (msh, prefix))
        lines = {tuple(sorted((P[c[0]], P[c[1]]))) for cb in m.cells if cb.type == lt
                 for c in cb.data}
        wantl = bound | set(segs)
        if lines != wantl:
            fail("%s: %d line elements, expected %d (boundary and segments)" % (msh, len(lines),
                                                                               len(wantl)))
        if not m.field_data or "gmsh:physical" not in m.cell_data:
            fail("%s: no physical groups" % msh)
        print("ok   %s: meshio reads %d %s, %d %s, groups %s" %
              (msh, nt, tt, len(lines), lt, sorted(m.field_data)))
    if msh:
        try:
            import gmsh
        except ImportError:
            gmsh = None
        if gmsh:  # Gmsh itself, when its Python package is installed (pip install gmsh)
            gmsh.initialize()
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.open(msh)
            names = sorted(gmsh.model.getPhysicalName(d, t)
                           for d, t in gmsh.model.getPhysicalGroups())
            ntri = sum(len(tags) for tags in gmsh.model.mesh.getElements(2)[1])
            gmsh.finalize()
            if ntri != nt or names != sorted(m.field_data):
                fail("%s: gmsh reads %d triangles, groups %s" % (msh, ntri, names))
            print("ok   %s: gmsh reads %d triangles, groups %s" % (msh, ntri, names))
    if vtk and o2:
        m = meshio.read(vtk)
        n6 = sum(len(c.data) for c in m.cells if c.type == "triangle6")
        if n6 != nt or len(m.points) != nv:
            fail("%s: %d triangle6 cells, %d points; expected %d, %d" % (vtk, n6, len(m.points),
                                                                         nt, nv))
        print("ok   %s: meshio reads %d triangle6" % (vtk, n6))
    if keys:
        out_keys += ["T %r" % (tuple(sorted(xy[v] for v in tr[:3])),) for tr in tris]
        with open(keys, "w") as f:
            f.write("\n".join(sorted(out_keys)) + "\n")


if __name__ == "__main__":
    main()
