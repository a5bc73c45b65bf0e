#!/usr/bin/env python3
"""The Python section of the bench: pcdm.triangulate against triangle.triangulate (the PyPI
`triangle` package, a wrapper of Shewchuk's Triangle 1.6) on the same input and switches.

  python3 bench/python.py [--sizes 1e6,1e7] [--reps 3] [--domain data/lake.poly] [--q 30]

For each size N the area bound is domain_area * 1.6 / N (about N triangles at -q 30, as
bench/seq.sh).  Every run is a child process (python3 bench/python.py --one PKG SWITCHES) that
reads the domain (bench/poly.py), calls the package once and reports the call's wall time,
the triangles made and its peak resident size over its size just before the call (the
mesher's own memory, with the returned arrays); the two packages alternate, repetition after
repetition, and the medians are reported.  Then the GIL: two Python threads meshing two copies
of the input at once, against the same two calls one after the other, in one process (pcdm
only; the ratio of the medians).

Lines printed (last): "python: N=... pcdm_tps=... triangle_tps=... ratio=... pcdm_mb=...
triangle_mb=... mem_ratio=..." per size, then "python: threads=2 seq_s=... par_s=...
ratio=... cpu_per_wall=..." (the threads' CPU seconds per wall second: 2 when both ran at
once; the machine's load average beside it).  Figures are measured, never typed in; on a loaded machine compare ratios only.
"""
import argparse
import os
import resource
import statistics
import subprocess
import sys
import threading
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from poly import poly_dict  # noqa: E402  (the bench's one .poly reader)


def rss_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def one(pkg, path, switches):
    mod = __import__(pkg)
    d = poly_dict(path)
    base = rss_mb()
    t0 = time.perf_counter()
    r = mod.triangulate(d, switches)
    wall = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"one: pkg={pkg} triangles={len(r['triangles'])} wall_s={wall:.4f} "
          f"peak_mb={peak:.1f} base_mb={base:.1f}")


def child(pkg, path, switches, timeout):
    p = subprocess.run([sys.executable, os.path.abspath(__file__), "--one", pkg, path, switches],
                       capture_output=True, text=True, timeout=timeout)
    line = [ln for ln in p.stdout.splitlines() if ln.startswith("one:")]
    if p.returncode != 0 or not line:
        raise RuntimeError(f"{pkg} {switches}: exit {p.returncode}: {p.stderr.strip()[-300:]}")
    return dict(kv.split("=") for kv in line[0].split()[1:])


def switches(q, area):
    """Triangle reads no exponent in a switch string: the area in plain decimals."""
    return "pq%sa%sQ" % (q, ("%.15f" % area).rstrip("0"))


def domain_area(d):
    import pcdm
    m = pcdm.triangulate(d, "p")
    x = m["vertices"][m["triangles"]]
    return float(np.sum(0.5 * np.abs((x[:, 1, 0] - x[:, 0, 0]) * (x[:, 2, 1] - x[:, 0, 1]) -
                                     (x[:, 2, 0] - x[:, 0, 0]) * (x[:, 1, 1] - x[:, 0, 1]))))


def threads(path, switches, reps):
    import pcdm
    d1, d2 = poly_dict(path), poly_dict(path)
    pcdm.triangulate(d1, switches)  # warm
    seq, par, cpu = [], [], []

    def cpu_s():
        r = resource.getrusage(resource.RUSAGE_SELF)
        return r.ru_utime + r.ru_stime
    for _ in range(reps):
        t0 = time.perf_counter()
        pcdm.triangulate(d1, switches)
        pcdm.triangulate(d2, switches)
        seq.append(time.perf_counter() - t0)
        ts = [threading.Thread(target=pcdm.triangulate, args=(d, switches)) for d in (d1, d2)]
        t0, c0 = time.perf_counter(), cpu_s()
        for t in ts:
            t.start()
        for t in ts:
            t.join()
        par.append(time.perf_counter() - t0)
        cpu.append(cpu_s() - c0)
    # the threads' CPU seconds over the wall seconds: near 2 when both ran at once on two free
    # cores, near 1 when they took turns (a lock, or one core free)
    return statistics.median(seq), statistics.median(par), statistics.median(
        c / w for c, w in zip(cpu, par))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="1e6,1e7")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--domain", default=os.path.join(HERE, "..", "data", "lake.poly"))
    ap.add_argument("--q", default="30")
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--thread-size", type=float, default=1e6)
    ap.add_argument("--one", nargs=3, metavar=("PKG", "POLY", "SWITCHES"))
    a = ap.parse_args()
    if a.one:
        one(*a.one)
        return 0
    path = os.path.abspath(a.domain)
    dom = domain_area(poly_dict(path))
    try:
        import triangle  # noqa: F401
        pkgs = ["pcdm", "triangle"]
    except ImportError:
        print("python: the triangle package is not installed: pcdm alone")
        pkgs = ["pcdm"]
    for n in (float(s) for s in a.sizes.split(",")):
        sw = switches(a.q, dom * 1.6 / n)
        res = {p: [] for p in pkgs}
        for rep in range(a.reps):
            for p in (pkgs if rep % 2 == 0 else pkgs[::-1]):
                r = child(p, path, sw, a.timeout)
                res[p].append(r)
                print(f"python:   {p} {sw} rep {rep + 1}: {r['triangles']} triangles "
                      f"{r['wall_s']} s, peak {r['peak_mb']} MB over {r['base_mb']} MB",
                      flush=True)
        med = {}
        for p in pkgs:
            tps = statistics.median(int(r["triangles"]) / float(r["wall_s"]) for r in res[p])
            mb = statistics.median(float(r["peak_mb"]) - float(r["base_mb"]) for r in res[p])
            med[p] = (tps, mb, int(res[p][0]["triangles"]))
        line = f"python: N={med['pcdm'][2]} pcdm_tps={med['pcdm'][0]:.0f} pcdm_mb={med['pcdm'][1]:.0f}"
        if "triangle" in med:
            line += (f" triangle_N={med['triangle'][2]} triangle_tps={med['triangle'][0]:.0f}"
                     f" triangle_mb={med['triangle'][1]:.0f}"
                     f" ratio={med['pcdm'][0] / med['triangle'][0]:.2f}"
                     f" mem_ratio={med['pcdm'][1] / med['triangle'][1]:.2f}")
        print(line, flush=True)
    sw = switches(a.q, dom * 1.6 / a.thread_size)
    s, p, busy = threads(path, sw, a.reps)
    print(f"python: threads=2 switches={sw} seq_s={s:.3f} par_s={p:.3f} ratio={p / s:.2f} "
          f"cpu_per_wall={busy:.2f} cpus={os.cpu_count()} "
          f"loadavg={os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
