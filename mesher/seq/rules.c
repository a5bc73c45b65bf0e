/* rules: the refinement rules (what is bad, where Steiner points go, encroachment, shells,
 * forced small angles), shared by every mesher; contracts in rules.h.
 *
 * Bad triangles (Ruppert 1995; Chew 1993): the smallest angle sits at the apex of the shortest
 * edge, so one comparison of cos^2 against the bound decides it without trigonometry.  Steiner
 * point: the circumcenter, or Ungor's off-center (LATIN 2004) -- the point on the bisector of
 * the shortest edge pq at height |pq| / (2 tan(b/2)), where the new triangle on pq has apex
 * angle exactly b; we keep 5% inside.  Encroachment: the diametral circle by the exact
 * predicate, or Shewchuk's diametral lens (CGTA 22, 2002, sec. 4), a rounded test that only
 * ever narrows the exact circle.  Small input angles: concentric shells at powers of two
 * (Ruppert 1995; Shewchuk 2002 sec. 5), and the forced-angle rule the validator mirrors (two
 * vertices on the two neighbouring segments of a corner below 60 degrees, equally far from
 * it), with the input's segments given as plain arrays (mesh_rules_input) so a mesher with
 * its own store (PBW) asks the same question.  Termination (issue 10): the length floor below
 * which no edge is made and the budget of such refusals, and the queue priority (shortest edge
 * first).  Invariant: every function depends on its arguments only, so all meshers that call
 * it make the same decision on the same bits.
 */
#include "seq/rules.h"

#include "geom/geom.h"

#include <float.h>
#include <math.h>
#include <string.h>

void mesh_rules_init(mesh_rules *R, double min_angle, double max_area, int offcenter, int lens) {
    double b = min_angle > 0 ? min_angle : 0;
    if (b > 60) b = 60;
    R->min_angle = b;
    R->max_area = max_area > 0 ? max_area : 0;
    R->offcenter = offcenter;
    R->lens = lens;
    R->cosb = cos(b * M_PI / 180.0);
    R->offfac = b > 0 ? 0.95 / (2.0 * tan(b * M_PI / 360.0)) : 0;
    R->cos2b = (lens && b > 0 && b < 45) ? cos(2 * b * M_PI / 180.0) : 1.0;
    R->unsuitable = NULL;
    R->unsuitable_ctx = NULL;
}

int mesh_rules_bad(const mesh_rules *R, const double *const p[3], int *sh, double *short2) {
    return mesh_rules_bad_bound(R, R->max_area, p, sh, short2);
}

int mesh_rules_steiner(const mesh_rules *R, const double *const p[3], int sh, double out[2]) {
    if (geom_circumcenter(p[0], p[1], p[2], out) != 0) return -1;
    if (!R->offcenter || R->offfac <= 0) return 0;
    const double *a = p[sh], *b = p[(sh + 1) % 3];
    double mid[2];
    geom_midpoint(a, b, mid);
    double dc = sqrt(geom_dist2(mid, out)), h = R->offfac * sqrt(geom_dist2(a, b));
    if (dc > h) {
        out[0] = mid[0] + (out[0] - mid[0]) * (h / dc);
        out[1] = mid[1] + (out[1] - mid[1]) * (h / dc);
    }
    return 0;
}

int mesh_rules_encroaches(const mesh_rules *R, const double a[2], const double b[2],
                          const double p[2]) {
    if (!geom_encroaches(a, b, p)) return 0;
    if (!R->lens || R->cos2b >= 1.0) return 1;
    double ax = a[0] - p[0], ay = a[1] - p[1], bx = b[0] - p[0], by = b[1] - p[1];
    double dot = ax * bx + ay * by; /* < 0: obtuse at p */
    return dot * dot >= R->cos2b * R->cos2b * (ax * ax + ay * ay) * (bx * bx + by * by);
}

void mesh_rules_shell_point(const double a[2], const double w[2], double unit, double out[2]) {
    double L = sqrt(geom_dist2(a, w));
    double d = unit * exp2(floor(log2(L * (2.0 / 3.0) / unit)));
    double f = d / L;
    if (!(f > 0.3 && f < 0.7)) f = 0.5;
    out[0] = a[0] + (w[0] - a[0]) * f;
    out[1] = a[1] + (w[1] - a[1]) * f;
}

/* Fraction of ab (length L) at which a piece [t0, t1] touching the end at t0 = 0 (from_a) or
 * t1 = 1 (from b) is split on the power-of-two shells around that end. */
static double shell_fraction(double L, double t0, double t1, int from_a) {
    double len = (t1 - t0) * L;
    double d = exp2(floor(log2(len * (2.0 / 3.0))));
    double f = d / len;
    if (!(f > 0.3 && f < 0.7)) f = 0.5;
    return from_a ? t0 + f * (t1 - t0) : t1 - f * (t1 - t0);
}

void mesh_rules_iface_point(const double a[2], const double b[2], int32_t level, int64_t k,
                            double out[2]) {
    double L = sqrt(geom_dist2(a, b));
    double t0 = 0, t1 = 1;
    for (int32_t d = 0; d <= level; d++) {
        /* the split point of the current piece (depth d, [t0, t1]) */
        double s;
        if (d == 0)
            s = shell_fraction(L, t0, t1, 1);
        else if (t1 == 1 && t0 > 0 && d == 1)
            s = shell_fraction(L, t0, t1, 0);
        else
            s = 0.5 * (t0 + t1);
        if (d == level) {
            out[0] = a[0] + (b[0] - a[0]) * s;
            out[1] = a[1] + (b[1] - a[1]) * s;
            return;
        }
        if ((k >> (level - 1 - d)) & 1)
            t0 = s;
        else
            t1 = s;
    }
}

int mesh_rules_in_wedge(const double a[2], const double o1[2], const double o2[2],
                        const double o3[2]) {
    double s = geom_orient2d(a, o1, o2);
    double x1 = geom_orient2d(a, o1, o3);
    double x2 = geom_orient2d(a, o3, o2);
    return (s > 0 && x1 > 0 && x2 > 0) || (s < 0 && x1 < 0 && x2 < 0);
}

int mesh_rules_corner_forced(const double a[2], const double o1[2], const double o2[2],
                             const double u[2], const double v[2]) {
    if (geom_angle_deg(o1, a, o2) >= 60.0) return 0;
    double du = sqrt(geom_dist2(a, u)), dv = sqrt(geom_dist2(a, v));
    return fabs(du - dv) <= 0.01 * fmax(du, dv);
}

/* 1 iff the new edge w-p of a split of (pu, pv) at p is not locally Delaunay: pv lies strictly
 * inside the circle through pu, p and w (exact; the pair of new triangles beside w-p is
 * (pu, p, w), (p, pv, w)).  Degenerate (pu, p, w collinear): 1. */
static int fan_not_delaunay(const double pu[2], const double pv[2], const double p[2],
                            const double w[2]) {
    double o = geom_orient2d(pu, p, w);
    if (o == 0) return 1;
    double ic = geom_incircle(pu, p, w, pv);
    return o > 0 ? ic > 0 : ic < 0;
}

int mesh_rules_off_line(const double pu[2], const double pv[2], const double p[2], const double *w1,
                        const double *w2) {
    double off = fabs(geom_orient2d(pu, pv, p));
    if (off == 0) return 0;
    return (w1 && 16 * off > fabs(geom_orient2d(pu, pv, w1))) ||
           (w2 && 16 * off > fabs(geom_orient2d(pu, pv, w2)));
}

int mesh_rules_off_line_fan(const double pu[2], const double pv[2], const double p[2],
                            const double *w1, const double *w2) {
    if (mesh_rules_off_line(pu, pv, p, w1, w2)) return 1;
    if (geom_orient2d(pu, pv, p) == 0) return 0;
    return (w1 && fan_not_delaunay(pu, pv, p, w1)) || (w2 && fan_not_delaunay(pu, pv, p, w2));
}

double mesh_rules_area_drift(double area, double mag, double bperim) {
    double a = fabs(area), r = ldexp(mag, -MESH_RULES_ULP_EXP) * bperim;
    return ldexp(a, -30) + (r <= ldexp(a, -8) ? r : 0);
}

int mesh_rules_drift_spend(const double pu[2], const double pv[2], const double p[2],
                           const double w[2], double budget, double *drift) {
    double o = geom_orient2d(pu, pv, p);
    if (o == 0) return 0;
    /* towards the inside apex w the domain shrinks, away from it it grows */
    double d = 0.5 * ((o > 0) == (geom_orient2d(pu, pv, w) > 0) ? -fabs(o) : fabs(o));
    if (!(fabs(*drift + d) <= budget)) return 1;
    *drift += d;
    return 0;
}

int mesh_rules_bucket(double short2) {
    uint64_t bits;
    memcpy(&bits, &short2, sizeof bits);
    int k = (int)((bits >> 52) & 0x7ff) - 1023 + MESH_RULES_NBUCKET / 2; /* binary exponent */
    return k < 0 ? 0 : k >= MESH_RULES_NBUCKET ? MESH_RULES_NBUCKET - 1 : k;
}

double mesh_rules_length_floor2(const double *xy, int32_t nv, const int32_t *tv, int32_t nt) {
    double mag = 0, alt2 = INFINITY;
    for (int32_t v = 0; v < nv; v++)
        mag = fmax(mag, fmax(fabs(xy[2 * (size_t)v]), fabs(xy[2 * (size_t)v + 1])));
    for (int32_t t = 0; t < nt; t++) {
        const int32_t *w = tv + 3 * (size_t)t;
        if (w[0] < 0) continue;
        const double *a = xy + 2 * (size_t)w[0], *b = xy + 2 * (size_t)w[1],
                     *c = xy + 2 * (size_t)w[2];
        double l = fmax(geom_dist2(a, b), fmax(geom_dist2(b, c), geom_dist2(c, a)));
        double ar = geom_area(a, b, c);
        if (l > 0) alt2 = fmin(alt2, 4 * ar * ar / l);
    }
    double f = fmax(isfinite(alt2) ? alt2 * 0x1p-48 : 0, mag * mag * 0x1p-88);
    return f > 0 ? f : DBL_MIN;
}

int64_t mesh_rules_unresolved_budget(int32_t ninput) {
    return 256 + (int64_t)ninput / 4;
}

/* No other input segment at corner a points strictly inside the wedge o1-a-o2. */
static int consecutive(const mesh_rules_input *I, int32_t a, int32_t o1, int32_t o2) {
    const double *X = I->xy;
    for (int32_t i = I->inc_off[a]; i < I->inc_off[a + 1]; i++) {
        int32_t s3 = I->inc_seg[i];
        if (I->siface && I->siface[s3]) continue;
        int32_t o3 = I->seg[2 * s3] == a ? I->seg[2 * s3 + 1] : I->seg[2 * s3];
        if (o3 == o1 || o3 == o2) continue;
        if (mesh_rules_in_wedge(X + 2 * (size_t)a, X + 2 * (size_t)o1, X + 2 * (size_t)o2,
                                X + 2 * (size_t)o3))
            return 0;
    }
    return 1;
}

int mesh_rules_edge_forced(const mesh_rules_input *I, int32_t u, int32_t useg, const double pu[2],
                           int32_t v, int32_t vseg, const double pv[2]) {
    if (!I->corner) return 0;
    /* the segments each vertex lies on: all segments at an input vertex, or its own one */
    int32_t su1, nu, sv1, nv;
    if (u >= 0 && u < I->ninput)
        su1 = I->inc_off[u], nu = I->inc_off[u + 1] - su1;
    else if (useg >= 0)
        su1 = -1, nu = 1;
    else
        return 0;
    if (v >= 0 && v < I->ninput)
        sv1 = I->inc_off[v], nv = I->inc_off[v + 1] - sv1;
    else if (vseg >= 0)
        sv1 = -1, nv = 1;
    else
        return 0;
    const double *X = I->xy;
    for (int32_t i = 0; i < nu; i++) {
        int32_t s1 = su1 < 0 ? useg : I->inc_seg[su1 + i];
        for (int32_t j = 0; j < nv; j++) {
            int32_t s2 = sv1 < 0 ? vseg : I->inc_seg[sv1 + j];
            if (s1 == s2 || (I->siface && (I->siface[s1] || I->siface[s2]))) continue;
            for (int x = 0; x < 2; x++)
                for (int y = 0; y < 2; y++) {
                    int32_t a = I->seg[2 * s1 + x];
                    if (a != I->seg[2 * s2 + y] || a == u || a == v || !I->corner[a]) continue;
                    int32_t o1 = I->seg[2 * s1 + 1 - x], o2 = I->seg[2 * s2 + 1 - y];
                    if (!consecutive(I, a, o1, o2)) continue;
                    if (mesh_rules_corner_forced(X + 2 * (size_t)a, X + 2 * (size_t)o1,
                                                 X + 2 * (size_t)o2, pu, pv))
                        return 1;
                }
        }
    }
    return 0;
}
