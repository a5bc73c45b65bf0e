"""Runs Shewchuk's Triangle (through the PyPI `triangle` wrapper) on one .poly file and prints
one line in the format of ./mesh --stats:

  stats: triangles=N vertices=N steiner=N mesh_s=T peak_rss_mb=M base_rss_mb=B cpu_s=C

Usage: python seq_triangle.py input.poly SWITCHES      (e.g. pq20.7a0.000002Q)

Only the triangulate() call is timed (mesh_s, beside ./mesh's meshing time of that name; cpu_s:
this process's CPU time during it).  peak_rss_mb is this process's peak resident size;
base_rss_mb is its resident size just before the call (Python, numpy, the input), so the
mesher's own memory is peak - base.  The .poly is read by bench/poly.py (vertices, segments,
holes; 0- or 1-based like Triangle).
"""
import os
import resource
import sys
import time

import triangle

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from poly import poly_dict  # noqa: E402  (the bench's one .poly reader)


def rss_now_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return 0.0


def main():
    path, switches = sys.argv[1], sys.argv[2]
    d = poly_dict(path)
    base = rss_now_mb()
    t0, c0 = time.perf_counter(), time.process_time()
    out = triangle.triangulate(d, switches)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    nt = len(out["triangles"])
    nv = len(out["vertices"])
    print(f"stats: triangles={nt} vertices={nv} steiner={nv - len(d['vertices'])} "
          f"mesh_s={wall:.3f} peak_rss_mb={peak:.1f} base_rss_mb={base:.1f} cpu_s={cpu:.3f}")


if __name__ == "__main__":
    main()
