# coastline.awk: writes a coastline-like PSLG (Triangle's .poly) for the tests, deterministically:
#     awk -f tests/coastline.awk [-v n=9000] > coast.poly
# A land mass whose shore is a star-shaped closed polyline of n vertices (radius 1 with ripples
# at three scales, so segment lengths vary 4x along it) cut by three narrow inlets (wedges a few
# segments wide reaching half-way in), two islands off the shore (their own closed polylines:
# separate faces of the domain) and two lakes inside (holes, each with a hole point).  Every
# polyline is star-shaped about its centre, so none crosses itself, and the pieces lie apart.
function ring(cx, cy, r0, m, amp, ph, first,    k, t, r) {
    for (k = 0; k < m; k++) {
        t = 2 * PI * k / m
        r = r0 * (1 + amp * (0.5 * sin(3 * t + ph) + 0.3 * sin(17 * t + 2 * ph) + 0.2 * sin(61 * t)))
        printf "%d %.9f %.9f 1\n", first + k, cx + r * cos(t), cy + r * sin(t)
    }
}
function shore(k,    t, r, j, d) {
    t = 2 * PI * k / n
    r = 1 + 0.08 * sin(5 * t) + 0.03 * sin(29 * t + 1) + 0.012 * sin(211 * t)
    for (j = 0; j < 3; j++) { # inlets at 1, 3 and 5 radians, 0.004 radians wide
        d = t - (1 + 2 * j)
        if (d > -0.002 && d < 0.002) r *= 0.5 + 250 * (d < 0 ? -d : d)
    }
    printf "%d %.9f %.9f 1\n", k + 1, r * cos(t), r * sin(t)
}
function segs(first, m, s0,    k) {
    for (k = 0; k < m; k++) printf "%d %d %d 1\n", s0 + k, first + k, first + (k + 1) % m
}
BEGIN {
    PI = atan2(0, -1)
    if (!n) n = 9000
    mi = int(n / 20) # vertices of an island or a lake
    nv = n + 4 * mi
    printf "# coastline-like test input (tests/coastline.awk, n=%d)\n%d 2 0 1\n", n, nv
    for (k = 0; k < n; k++) shore(k)
    ring(1.45, 0.0, 0.12, mi, 0.3, 0.5, n + 1)           # island east
    ring(-0.2, 1.4, 0.1, mi, 0.3, 1.5, n + mi + 1)       # island north
    ring(0.3, -0.2, 0.15, mi, 0.2, 2.5, n + 2 * mi + 1)  # lake
    ring(-0.45, 0.3, 0.1, mi, 0.2, 3.5, n + 3 * mi + 1)  # lake
    printf "%d 1\n", nv
    segs(1, n, 1)
    for (i = 0; i < 4; i++) segs(n + i * mi + 1, mi, n + i * mi + 1)
    printf "2\n1 0.3 -0.2\n2 -0.45 0.3\n"
}
