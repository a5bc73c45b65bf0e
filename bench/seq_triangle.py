"""Runs Shewchuk's Triangle (through the PyPI `triangle` wrapper) on one .poly file and prints
one line in the format of ./mesh --stats:

  stats: triangles=N vertices=N steiner=N wall_s=T peak_rss_mb=M base_rss_mb=B

Usage: python seq_triangle.py input.poly SWITCHES      (e.g. pq20.7a0.000002Q)

Only the triangulate() call is timed.  peak_rss_mb is this process's peak resident size;
base_rss_mb is its resident size just before the call (Python, numpy, the input), so the
mesher's own memory is peak - base.  The .poly is parsed here (vertices, segments, holes; 0-
or 1-based like Triangle).
"""
import resource
import sys
import time

import numpy as np
import triangle


def read_poly(path):
    rows = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].split()
            if line:
                rows.append(line)
    i = 0
    nv, _, nattr, nmark = (int(x) for x in rows[i][:4])
    i += 1
    first = int(rows[i][0]) if nv > 0 else 0
    xy = np.array([[float(r[1]), float(r[2])] for r in rows[i : i + nv]], dtype=np.float64)
    i += nv
    ns = int(rows[i][0])
    i += 1
    seg = np.array([[int(r[1]) - first, int(r[2]) - first] for r in rows[i : i + ns]],
                   dtype=np.int32)
    i += ns
    holes = []
    if i < len(rows):
        nh = int(rows[i][0])
        i += 1
        holes = [[float(r[1]), float(r[2])] for r in rows[i : i + nh]]
    d = {"vertices": xy}
    if ns:
        d["segments"] = seg
    if holes:
        d["holes"] = np.array(holes, dtype=np.float64)
    return d


def rss_now_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return 0.0


def main():
    path, switches = sys.argv[1], sys.argv[2]
    d = read_poly(path)
    base = rss_now_mb()
    t0 = time.perf_counter()
    out = triangle.triangulate(d, switches)
    wall = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    nt = len(out["triangles"])
    nv = len(out["vertices"])
    print(f"stats: triangles={nt} vertices={nv} steiner={nv - len(d['vertices'])} "
          f"wall_s={wall:.3f} peak_rss_mb={peak:.1f} base_rss_mb={base:.1f}")


if __name__ == "__main__":
    main()
