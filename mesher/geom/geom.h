/* geom: exact geometric predicates and floating-point geometry helpers.
 *
 * orient2d, incircle and the diametral-circle (encroachment) test are exact in sign for every
 * pair of finite doubles: a floating-point filter answers when the rounded value is certain,
 * otherwise adaptive expansion arithmetic (Shewchuk, "Adaptive Precision Floating-Point
 * Arithmetic and Fast Robust Geometric Predicates", 1997) decides.  Topology in this project
 * is decided by these predicates only.  Everything else here (circumcenter, angles, areas) is
 * ordinary rounded arithmetic used for point creation and quality measures.
 *
 * All functions are Local (no communication) and thread-safe after geom_init().
 *
 * Valid range (sufficient; "exact barring underflow and overflow" made concrete): the signs
 * are exact when every nonzero coordinate has magnitude in [2^-380, 2^400] (about 4e-115 to
 * 2.6e120) for geom_orient2d, geom_diametral and geom_encroaches, and in [2^-160, 2^200]
 * (about 6.8e-49 to 1.6e60) for geom_incircle, whose determinant has degree 4.  (Then every
 * intermediate is a multiple of 2^-1074 and no error bound underflows.)  Outside that range
 * intermediate products may underflow or overflow and the sign may be wrong.
 */
#ifndef GEOM_H
#define GEOM_H

#include <math.h>

/* Working range of the mesher (sufficient for every predicate here, incircle included): every
 * coordinate a multiple of 2^-200 with magnitude at most 2^250.  Then every product of up to
 * four coordinate differences is a multiple of 2^-800 below 2^1010: no intermediate of the
 * expansions or of the error bounds underflows or overflows.  pslg_check scales inputs into
 * [-2^100, 2^100] on that grid; geom_working_point keeps every new point on it. */
#define GEOM_WORK_MAX 0x1p200

/* Puts a new point p (a circumcenter or a split point) into the working range: a coordinate
 * of magnitude below 2^-147 is rounded to the nearest multiple of 2^-200 (a no-op for every
 * other double).  Returns 0, or -1 if p is not finite or farther than GEOM_WORK_MAX from the
 * origin on either axis (the point is then unusable). */
int geom_working_point_slow(double p[2]); /* the whole test, out of line */
static inline int geom_working_point(double p[2]) {
    /* both coordinates' magnitudes in [2^-147, GEOM_WORK_MAX] (the common case): nothing to do
     * (zero, NaN and the rest take the whole test) */
    if (fabs(p[0]) >= 0x1p-147 && fabs(p[0]) <= GEOM_WORK_MAX && fabs(p[1]) >= 0x1p-147 &&
        fabs(p[1]) <= GEOM_WORK_MAX)
        return 0;
    return geom_working_point_slow(p);
}

/* Computes the machine constants of the filters.  Idempotent; call once before anything
 * else (the mesher and the programs do). */
void geom_init(void);

/* > 0 if a, b, c are in counter-clockwise order, < 0 if clockwise, 0 if collinear.
 * The sign is exact; the magnitude is twice the signed area, approximately. */
double geom_orient2d(const double a[2], const double b[2], const double c[2]);

/* > 0 if d lies inside the circle through a, b, c (given counter-clockwise), < 0 outside,
 * 0 on it.  Sign exact.  For clockwise a, b, c the sign is reversed. */
double geom_incircle(const double a[2], const double b[2], const double c[2], const double d[2]);

/* The stage-A error bounds of orient2d and incircle (Shewchuk 1997, section 4; EPS = 2^-53,
 * which geom_init checks): ccwerrboundA = (3 + 16 EPS) EPS, iccerrboundA = (10 + 96 EPS) EPS. */
#define GEOM_CCW_BOUND_A ((3.0 + 16.0 * 0x1p-53) * 0x1p-53)
#define GEOM_ICC_BOUND_A ((10.0 + 96.0 * 0x1p-53) * 0x1p-53)

/* The adaptive stages of geom_orient2d and geom_incircle, for the inline filters below only:
 * detsum / permanent is the filter's magnitude bound (nonzero). */
double geom_orient2d_adapt(const double a[2], const double b[2], const double c[2], double detsum);
double geom_incircle_adapt(const double a[2], const double b[2], const double c[2],
                           const double d[2], double permanent);

/* geom_orient2d and geom_incircle with their floating-point filter (stage A) inline, for the
 * kernel's hot loops (cavities, walks: several calls per inserted vertex); the same operations
 * in the same order, so the same value bit for bit, and the same adaptive stages out of line
 * when the filter cannot decide.  The filter is branch-free but for one well-predicted test:
 * with products of opposite signs |det| == detsum, which passes it. */
static inline double geom_orient2d_inline(const double a[2], const double b[2], const double c[2]) {
    double detleft = (a[0] - c[0]) * (b[1] - c[1]);
    double detright = (a[1] - c[1]) * (b[0] - c[0]);
    double det = detleft - detright;
    double detsum = fabs(detleft) + fabs(detright);
    if (fabs(det) > GEOM_CCW_BOUND_A * detsum) return det;
    if (detsum == 0.0) return 0.0; /* both products exactly zero */
    return geom_orient2d_adapt(a, b, c, detsum);
}

static inline double geom_incircle_inline(const double a[2], const double b[2], const double c[2],
                                          const double d[2]) {
    double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
    double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
    double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    double alift = adx * adx + ady * ady;
    double cdxady = cdx * ady, adxcdy = adx * cdy;
    double blift = bdx * bdx + bdy * bdy;
    double adxbdy = adx * bdy, bdxady = bdx * ady;
    double clift = cdx * cdx + cdy * cdy;
    double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
    double permanent = (fabs(bdxcdy) + fabs(cdxbdy)) * alift +
                       (fabs(cdxady) + fabs(adxcdy)) * blift +
                       (fabs(adxbdy) + fabs(bdxady)) * clift;
    if (fabs(det) > GEOM_ICC_BOUND_A * permanent) return det;
    if (permanent == 0.0) return 0.0; /* every product exactly zero */
    return geom_incircle_adapt(a, b, c, d, permanent);
}

/* Sign of (a - p) . (b - p), exact: < 0 iff p lies strictly inside the circle whose diameter
 * is the segment ab (p "encroaches" ab), 0 on it, > 0 outside. */
double geom_diametral(const double a[2], const double b[2], const double p[2]);

/* 1 if p lies strictly inside the diametral circle of ab (exact), else 0. */
int geom_encroaches(const double a[2], const double b[2], const double p[2]);

/* Circumcenter of triangle abc (rounded).  Returns 0, or -1 if abc is degenerate. */
int geom_circumcenter(const double a[2], const double b[2], const double c[2], double out[2]);

/* Midpoint of ab computed as a + (b - a) / 2 componentwise, the same bits on every rank.
 * Precisely: with (a, b) first put in lexicographic order (x, then y), out[i] is
 * a[i] + 0.5 * (b[i] - a[i]), so geom_midpoint(a, b) and geom_midpoint(b, a) agree bit for
 * bit. */
void geom_midpoint(const double a[2], const double b[2], double out[2]);

/* Signed area of abc (rounded; positive when counter-clockwise). */
double geom_area(const double a[2], const double b[2], const double c[2]);

/* Twice the signed area of abc, to a relative error of about 2^-40 even when the plain formula
 * cancels (slivers far from the origin); costs an exact determinant only then.  For sums of
 * areas, not for topology (geom_orient2d decides signs). */
double geom_area2_accurate(const double a[2], const double b[2], const double c[2]);

/* Smallest interior angle of triangle abc, in degrees (rounded). */
double geom_min_angle_deg(const double a[2], const double b[2], const double c[2]);

/* Angle at vertex b between rays b->a and b->c, in degrees in [0, 180] (rounded). */
double geom_angle_deg(const double a[2], const double b[2], const double c[2]);

/* Squared length of ab (inline: on every Steiner point's path). */
static inline double geom_dist2(const double a[2], const double b[2]) {
    double dx = b[0] - a[0], dy = b[1] - a[1];
    return dx * dx + dy * dy;
}

#endif
