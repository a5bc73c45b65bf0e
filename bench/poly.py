#!/usr/bin/env python3
"""Read a Triangle .poly file (the bench's one .poly reader; standard library only).

read_poly(path) -> (vertices [(x, y)], segments [(i, j)] as 0-based indices, holes [(x, y)]):
comments (#) and blank lines ignored, vertex numbering from 0 or 1 as the file says.
poly_dict(path) -> the same as the dict of numpy arrays triangle.triangulate and
pcdm.triangulate take (vertices float64, segments int32, holes float64; absent keys left out).
Command line:  python3 bench/poly.py bbox-area FILE   prints the area of the bounding box
of the vertices (the calibration's starting point, bench/bench.sh).
"""
import sys


def read_poly(path):
    lines = []
    with open(path) as fh:
        for ln in fh:
            ln = ln.split("#", 1)[0].split()
            if ln:
                lines.append(ln)
    i = 0
    nv = int(lines[i][0])
    i += 1
    idx, pts = {}, []
    for k in range(nv):
        idx[int(lines[i][0])] = k
        pts.append((float(lines[i][1]), float(lines[i][2])))
        i += 1
    segs, holes = [], []
    if i < len(lines):
        ns = int(lines[i][0])
        i += 1
        for _ in range(ns):
            segs.append((idx[int(lines[i][1])], idx[int(lines[i][2])]))
            i += 1
    if i < len(lines):
        nh = int(lines[i][0])
        i += 1
        for _ in range(nh):
            holes.append((float(lines[i][1]), float(lines[i][2])))
            i += 1
    return pts, segs, holes


def poly_dict(path):
    import numpy as np  # only the Python bench needs numpy; bbox-area runs without it

    pts, segs, holes = read_poly(path)
    d = {"vertices": np.array(pts, dtype=np.float64)}
    if segs:
        d["segments"] = np.array(segs, dtype=np.int32)
    if holes:
        d["holes"] = np.array(holes, dtype=np.float64)
    return d


def bbox_area(path):
    pts, _, _ = read_poly(path)
    xs = [p[0] for p in pts]
    ys = [p[1] for p in pts]
    return (max(xs) - min(xs)) * (max(ys) - min(ys))


def main():
    if len(sys.argv) != 3 or sys.argv[1] != "bbox-area":
        sys.stderr.write("usage: python3 bench/poly.py bbox-area FILE.poly\n")
        sys.exit(2)
    print("%.6g" % bbox_area(sys.argv[2]))


if __name__ == "__main__":
    main()
