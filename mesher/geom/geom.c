/* geom: exact-in-sign geometric predicates (orient2d, incircle, diametral test) and rounded
 * geometry helpers.
 *
 * Algorithm: Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
 * Predicates" (Discrete Comput. Geom. 18, 1997).  A real number is held as an expansion: a
 * sum of doubles ordered by increasing magnitude, pairwise nonoverlapping, zeros eliminated
 * (section 2).  The error-free building blocks are Two-Sum / Fast-Two-Sum (Theorems 6, 7),
 * Two-Product with Dekker's splitting (Theorem 18, no fused multiply-add), Fast-Expansion-Sum
 * (Theorem 13) and Scale-Expansion (Theorem 19).  Each predicate first evaluates its
 * determinant in plain floating point and accepts the sign when it exceeds a proven error
 * bound (stage A, section 4; written branch-free: one well-predicted test).  Otherwise the adaptive
 * path recomputes the determinant exactly from the rounded coordinate differences (stage B: exact
 * whenever the differences were exact, which covers grids and cocircular lattices), adds a
 * first-order correction for the differences' roundoff (stage C), and finally evaluates the exact
 * expansion (stage D) and returns the sign of its most significant component.  geom_diametral has
 * the same structure as orient2d (two products of two differences, one sum), so it uses orient2d's
 * bounds.
 *
 * Invariants and assumptions: IEEE-754 binary64, round-to-nearest-even, every operation
 * rounded once (FLT_EVAL_METHOD == 0, compiled with -ffp-contract=off and no fast-math);
 * geom_init() verifies the arithmetic at run time.  The predicates are exact barring
 * underflow and overflow; see geom.h for the sufficient coordinate ranges.  All state is
 * compile-time constant, so every function is thread-safe and Local.
 */
#include "geom/geom.h"

#include "base/base.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "geom.c needs FLT_EVAL_METHOD == 0 (doubles evaluated in double precision, e.g. SSE2)"
#endif

#if defined(__GNUC__)
#define GEOM_NOINLINE __attribute__((noinline))
#else
#define GEOM_NOINLINE
#endif

/* Machine constants (section 2 of the paper): EPS is half an ulp of 1, the largest power of
 * two with 1 + EPS == 1 under round-to-nearest-even; SPLITTER = 2^ceil(53/2) + 1. */
#define EPS 0x1p-53
#define SPLITTER 134217729.0

/* Error-bound coefficients of section 4 (the stage-A ones of orient2d and incircle are
 * geom.h's, for the inline filters there).  The stage-A bound of orient2d is also the bound of
 * geom_diametral (same expression tree up to the sign of one product). */
static const double result_bound = (3.0 + 8.0 * EPS) * EPS;
static const double ccw_bound_a = GEOM_CCW_BOUND_A;
static const double ccw_bound_b = (2.0 + 12.0 * EPS) * EPS;
static const double ccw_bound_c = (9.0 + 64.0 * EPS) * EPS * EPS;
static const double icc_bound_b = (4.0 + 48.0 * EPS) * EPS;
static const double icc_bound_c = (44.0 + 576.0 * EPS) * EPS * EPS;

void geom_init(void) {
    /* Recompute EPS and SPLITTER the way the paper defines them and check that the build's
     * constants describe this machine; volatile keeps the compiler from folding the loop. */
    volatile double eps = 1.0, check = 1.0, sum;
    double splitter = 1.0;
    int every_other = 1;
    do {
        eps *= 0.5;
        if (every_other) splitter *= 2.0;
        every_other = !every_other;
        check = sum = 1.0 + eps;
    } while (check != 1.0 && sum != 1.0);
    splitter += 1.0;
    /* 1 + 3*EPS must round up to 1 + 4*EPS (nearest), 1 + EPS down to 1 (ties to even). */
    volatile double three_eps = 3.0 * EPS, one = 1.0;
    if (eps != EPS || splitter != SPLITTER || one + three_eps != 1.0 + 4.0 * EPS ||
        one + EPS != 1.0) {
        MESH_BUG("geom_init: floating point is not IEEE binary64 round-to-even");
    }
}

/* ---- error-free transformations --------------------------------------------------------- */

/* x + y == a + b exactly, x = fl(a + b).  Requires |a| >= |b| (or a == 0). */
static inline void fast_two_sum(double a, double b, double *x, double *y) {
    double s = a + b;
    double b_virtual = s - a;
    *x = s;
    *y = b - b_virtual;
}

/* x + y == a + b exactly, x = fl(a + b); no precondition. */
static inline void two_sum(double a, double b, double *x, double *y) {
    double s = a + b;
    double b_virtual = s - a;
    double a_virtual = s - b_virtual;
    double b_round = b - b_virtual;
    double a_round = a - a_virtual;
    *x = s;
    *y = a_round + b_round;
}

/* x + y == a - b exactly, x = fl(a - b).  Two-Sum of a and -b with the negation folded in. */
static inline void two_diff(double a, double b, double *x, double *y) {
    double s = a - b;
    double b_virtual = a - s; /* the negation of Two-Sum's virtual -b */
    double a_virtual = s + b_virtual;
    double b_round = b_virtual - b;
    double a_round = a - a_virtual;
    *x = s;
    *y = a_round + b_round;
}

/* Only the roundoff of x = fl(a - b), given x. */
static inline double diff_tail(double a, double b, double x) {
    double b_virtual = a - x;
    double a_virtual = x + b_virtual;
    double b_round = b_virtual - b;
    double a_round = a - a_virtual;
    return a_round + b_round;
}

/* Dekker: a == hi + lo, each half with at most 26 significant bits. */
static inline void split(double a, double *hi, double *lo) {
    double c = SPLITTER * a;
    double a_big = c - a;
    *hi = c - a_big;
    *lo = a - *hi;
}

/* x + y == a * b exactly, x = fl(a * b); b already split into bhi + blo. */
static inline void two_product_presplit(double a, double b, double bhi, double blo, double *x,
                                        double *y) {
    double p = a * b;
    double ahi, alo;
    split(a, &ahi, &alo);
    double err1 = p - ahi * bhi;
    double err2 = err1 - alo * bhi;
    double err3 = err2 - ahi * blo;
    *x = p;
    *y = alo * blo - err3;
}

/* x + y == a * b exactly, x = fl(a * b). */
static inline void two_product(double a, double b, double *x, double *y) {
    double bhi, blo;
    split(b, &bhi, &blo);
    two_product_presplit(a, b, bhi, blo, x, y);
}

/* ---- expansion arithmetic --------------------------------------------------------------- */
/* An expansion is an array of length >= 1, increasing magnitude, nonoverlapping (in fact
 * strongly nonoverlapping, as the paper's algorithms guarantee under round-to-even); its
 * value is the exact sum.  Zero components are removed except that zero is stored as {0}. */

/* The next component of the merge of e and f by increasing magnitude (advances *ei or *fi). */
static inline double merge_next(int elen, const double *e, int *ei, int flen, const double *f,
                                int *fi) {
    if (*fi >= flen || (*ei < elen && fabs(e[*ei]) <= fabs(f[*fi]))) return e[(*ei)++];
    return f[(*fi)++];
}

/* h = e + f (Fast-Expansion-Sum with zero elimination).  h needs elen + flen slots and may
 * not alias e or f.  Returns the length of h. */
static int exp_sum(int elen, const double *e, int flen, const double *f, double *h) {
    int ei = 0, fi = 0, hn = 0;
    int n = elen + flen;
    double q, g, hh;
    q = merge_next(elen, e, &ei, flen, f, &fi);
    for (int k = 1; k < n; k++) {
        g = merge_next(elen, e, &ei, flen, f, &fi);
        if (k == 1)
            fast_two_sum(g, q, &q, &hh); /* |g| >= |q| by the merge order */
        else
            two_sum(q, g, &q, &hh);
        if (hh != 0.0) h[hn++] = hh;
    }
    if (q != 0.0 || hn == 0) h[hn++] = q;
    return hn;
}

/* h = b * e (Scale-Expansion with zero elimination).  h needs 2 * elen slots, no aliasing. */
static int exp_scale(int elen, const double *e, double b, double *h) {
    double bhi, blo, q, sum, hh, p_hi, p_lo;
    int hn = 0;
    split(b, &bhi, &blo);
    two_product_presplit(e[0], b, bhi, blo, &q, &hh);
    if (hh != 0.0) h[hn++] = hh;
    for (int i = 1; i < elen; i++) {
        two_product_presplit(e[i], b, bhi, blo, &p_hi, &p_lo);
        two_sum(q, p_lo, &sum, &hh);
        if (hh != 0.0) h[hn++] = hh;
        fast_two_sum(p_hi, sum, &q, &hh);
        if (hh != 0.0) h[hn++] = hh;
    }
    if (q != 0.0 || hn == 0) h[hn++] = q;
    return hn;
}

/* h = e * f by summing the scalings of e by each component of f.  h needs 2 * elen * flen
 * slots; elen * flen <= EXP_MUL_MAX. */
#define EXP_MUL_MAX 256
static int exp_mul(int elen, const double *e, int flen, const double *f, double *h) {
    double scaled[2 * 16 + 2];
    double acc[2][2 * EXP_MUL_MAX];
    int accn = 0, cur = 0;
    if (elen > 16) { /* scale the longer one; keep the scratch small */
        const double *t = e;
        int tn = elen;
        e = f, elen = flen, f = t, flen = tn;
    }
    if (elen > 16 || elen * flen > EXP_MUL_MAX) {
        MESH_BUG("exp_mul: operands too long (%d x %d)", elen, flen);
    }
    for (int j = 0; j < flen; j++) {
        int sn = exp_scale(elen, e, f[j], scaled);
        if (j == 0) {
            for (int i = 0; i < sn; i++)
                acc[cur][i] = scaled[i];
            accn = sn;
        } else {
            accn = exp_sum(accn, acc[cur], sn, scaled, acc[!cur]);
            cur = !cur;
        }
    }
    for (int i = 0; i < accn; i++)
        h[i] = acc[cur][i];
    return accn;
}

static void exp_negate(int n, double *e) {
    for (int i = 0; i < n; i++)
        e[i] = -e[i];
}

/* Rounded value of an expansion, with the sign of the exact value guaranteed: the sum of the
 * components from small to large, or the top component itself in the (pathological) case
 * where that sum's sign disagrees with the top component, which carries the exact sign. */
static double exp_value(int n, const double *e) {
    double s = 0.0;
    for (int i = 0; i < n; i++)
        s += e[i];
    double top = e[n - 1];
    if ((s > 0.0 && top > 0.0) || (s < 0.0 && top < 0.0) || top == 0.0) return s;
    return top;
}

static double exp_estimate(int n, const double *e) {
    double s = 0.0;
    for (int i = 0; i < n; i++)
        s += e[i];
    return s;
}

/* h = x * y exactly for 2-component expansions x = {x0, x1}, y = {y0, y1}; h needs 8 slots. */
static int mul2x2(const double *x, const double *y, double *h) {
    return exp_mul(2, x, 2, y, h);
}

/* ---- orient2d ---------------------------------------------------------------------------- */

GEOM_NOINLINE double geom_orient2d_adapt(const double a[2], const double b[2], const double c[2],
                                         double detsum) {
    double acx = a[0] - c[0], bcx = b[0] - c[0];
    double acy = a[1] - c[1], bcy = b[1] - c[1];
    double l[2], r[2], bb[4], det, errbound;
    /* Stage B: exact determinant of the rounded differences. */
    two_product(acx, bcy, &l[1], &l[0]);
    two_product(acy, bcx, &r[1], &r[0]);
    exp_negate(2, r);
    int bn = exp_sum(2, l, 2, r, bb);
    det = exp_estimate(bn, bb);
    errbound = ccw_bound_b * detsum;
    if (det > errbound || -det > errbound) return det;

    double acxt = diff_tail(a[0], c[0], acx), bcxt = diff_tail(b[0], c[0], bcx);
    double acyt = diff_tail(a[1], c[1], acy), bcyt = diff_tail(b[1], c[1], bcy);
    if (acxt == 0.0 && acyt == 0.0 && bcxt == 0.0 && bcyt == 0.0) return exp_value(bn, bb);

    /* Stage C: first-order correction for the differences' roundoff. */
    errbound = ccw_bound_c * detsum + result_bound * fabs(det);
    det += (acx * bcyt + bcy * acxt) - (acy * bcxt + bcx * acyt);
    if (det > errbound || -det > errbound) return det;

    /* Stage D: (acx + acxt)(bcy + bcyt) - (acy + acyt)(bcx + bcxt), exactly, as
     * B + [acxt bcy - acyt bcx] + [acx bcyt - acy bcxt] + [acxt bcyt - acyt bcxt]. */
    double u[4], s1[8], s2[12], s3[16];
    two_product(acxt, bcy, &l[1], &l[0]);
    two_product(acyt, bcx, &r[1], &r[0]);
    exp_negate(2, r);
    int un = exp_sum(2, l, 2, r, u);
    int n1 = exp_sum(bn, bb, un, u, s1);
    two_product(acx, bcyt, &l[1], &l[0]);
    two_product(acy, bcxt, &r[1], &r[0]);
    exp_negate(2, r);
    un = exp_sum(2, l, 2, r, u);
    int n2 = exp_sum(n1, s1, un, u, s2);
    two_product(acxt, bcyt, &l[1], &l[0]);
    two_product(acyt, bcxt, &r[1], &r[0]);
    exp_negate(2, r);
    un = exp_sum(2, l, 2, r, u);
    int n3 = exp_sum(n2, s2, un, u, s3);
    return exp_value(n3, s3);
}

double geom_orient2d(const double a[2], const double b[2], const double c[2]) {
    return geom_orient2d_inline(a, b, c);
}

/* Twice the signed area of abc with a relative error of at most about 2^-40: the plain
 * formula when its cancellation is mild, else the exact determinant (stage D of orient2d taken
 * unconditionally) rounded once.  For sums of areas (the validator, the domain's area), where
 * the plain formula loses every digit on a sliver far from the origin. */
double geom_area2_accurate(const double a[2], const double b[2], const double c[2]) {
    double acx = a[0] - c[0], bcx = b[0] - c[0];
    double acy = a[1] - c[1], bcy = b[1] - c[1];
    double detleft = acx * bcy, detright = acy * bcx;
    double det = detleft - detright;
    if (fabs(detleft) + fabs(detright) <= 0x1p8 * fabs(det)) return det;
    double acxt = diff_tail(a[0], c[0], acx), bcxt = diff_tail(b[0], c[0], bcx);
    double acyt = diff_tail(a[1], c[1], acy), bcyt = diff_tail(b[1], c[1], bcy);
    double x[2] = {acxt, acx}, y[2] = {bcyt, bcy}, z[2] = {acyt, acy}, w[2] = {bcxt, bcx};
    double p[8], q[8], h[16];
    int pn = mul2x2(x, y, p), qn = mul2x2(z, w, q);
    exp_negate(qn, q);
    return exp_value(exp_sum(pn, p, qn, q, h), h);
}

/* ---- incircle ---------------------------------------------------------------------------- */

/* Stage B term: lift * (x1 y2 - x2 y1) with lift = dx^2 + dy^2, all arguments doubles taken as
 * exact; h needs 32 slots. */
static int incircle_term_b(double dx, double dy, double x1, double y2, double x2, double y1,
                           double *h) {
    double l[2], r[2], m[4], t1[8], t2[16], t3[8], t4[16];
    two_product(x1, y2, &l[1], &l[0]);
    two_product(x2, y1, &r[1], &r[0]);
    exp_negate(2, r);
    int mn = exp_sum(2, l, 2, r, m);
    int n1 = exp_scale(mn, m, dx, t1);
    int n2 = exp_scale(n1, t1, dx, t2);
    int n3 = exp_scale(mn, m, dy, t3);
    int n4 = exp_scale(n3, t3, dy, t4);
    return exp_sum(n2, t2, n4, t4, h);
}

/* Stage D term: lift * (x1 y2 - x2 y1) for 2-component expansions; h needs 512 slots. */
static int incircle_term_exact(const double *dx, const double *dy, const double *x1,
                               const double *y2, const double *x2, const double *y1, double *h) {
    double p[8], q[8], lift[16], m[16];
    int pn = mul2x2(dx, dx, p);
    int qn = mul2x2(dy, dy, q);
    int liftn = exp_sum(pn, p, qn, q, lift);
    pn = mul2x2(x1, y2, p);
    qn = mul2x2(x2, y1, q);
    exp_negate(qn, q);
    int mn = exp_sum(pn, p, qn, q, m);
    return exp_mul(liftn, lift, mn, m, h);
}

GEOM_NOINLINE double geom_incircle_adapt(const double a[2], const double b[2], const double c[2],
                                         const double d[2], double permanent) {
    double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
    double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
    double ta[32], tb[32], tc[32], ab[64], fin[96], det, errbound;

    /* Stage B. */
    int an = incircle_term_b(adx, ady, bdx, cdy, cdx, bdy, ta);
    int bn = incircle_term_b(bdx, bdy, cdx, ady, adx, cdy, tb);
    int cn = incircle_term_b(cdx, cdy, adx, bdy, bdx, ady, tc);
    int abn = exp_sum(an, ta, bn, tb, ab);
    int finn = exp_sum(abn, ab, cn, tc, fin);
    det = exp_estimate(finn, fin);
    errbound = icc_bound_b * permanent;
    if (det > errbound || -det > errbound) return det;

    double adxt = diff_tail(a[0], d[0], adx), bdxt = diff_tail(b[0], d[0], bdx);
    double cdxt = diff_tail(c[0], d[0], cdx), adyt = diff_tail(a[1], d[1], ady);
    double bdyt = diff_tail(b[1], d[1], bdy), cdyt = diff_tail(c[1], d[1], cdy);
    if (adxt == 0.0 && bdxt == 0.0 && cdxt == 0.0 && adyt == 0.0 && bdyt == 0.0 && cdyt == 0.0)
        return exp_value(finn, fin);

    /* Stage C: first-order terms in the tails of lift_a * (bdx cdy - cdx bdy) + ... */
    errbound = icc_bound_c * permanent + result_bound * fabs(det);
    det += ((adx * adx + ady * ady) * ((bdx * cdyt + cdy * bdxt) - (bdy * cdxt + cdx * bdyt)) +
            2.0 * (adx * adxt + ady * adyt) * (bdx * cdy - bdy * cdx)) +
           ((bdx * bdx + bdy * bdy) * ((cdx * adyt + ady * cdxt) - (cdy * adxt + adx * cdyt)) +
            2.0 * (bdx * bdxt + bdy * bdyt) * (cdx * ady - cdy * adx)) +
           ((cdx * cdx + cdy * cdy) * ((adx * bdyt + bdy * adxt) - (ady * bdxt + bdx * adyt)) +
            2.0 * (cdx * cdxt + cdy * cdyt) * (adx * bdy - ady * bdx));
    if (det > errbound || -det > errbound) return det;

    /* Stage D: the whole determinant over the exact differences. */
    double ax[2] = {adxt, adx}, ay[2] = {adyt, ady}, bx[2] = {bdxt, bdx};
    double by[2] = {bdyt, bdy}, cx[2] = {cdxt, cdx}, cy[2] = {cdyt, cdy};
    double ea[2 * EXP_MUL_MAX], eb[2 * EXP_MUL_MAX], ec[2 * EXP_MUL_MAX];
    double eab[4 * EXP_MUL_MAX], all[6 * EXP_MUL_MAX];
    an = incircle_term_exact(ax, ay, bx, cy, cx, by, ea);
    bn = incircle_term_exact(bx, by, cx, ay, ax, cy, eb);
    cn = incircle_term_exact(cx, cy, ax, by, bx, ay, ec);
    abn = exp_sum(an, ea, bn, eb, eab);
    int alln = exp_sum(abn, eab, cn, ec, all);
    return exp_value(alln, all);
}

double geom_incircle(const double a[2], const double b[2], const double c[2], const double d[2]) {
    return geom_incircle_inline(a, b, c, d);
}

/* ---- diametral circle --------------------------------------------------------------------- */

static GEOM_NOINLINE double diametral_adapt(const double a[2], const double b[2], const double p[2],
                                            double detsum) {
    double apx = a[0] - p[0], bpx = b[0] - p[0];
    double apy = a[1] - p[1], bpy = b[1] - p[1];
    double l[2], r[2], bb[4], det, errbound;
    two_product(apx, bpx, &l[1], &l[0]);
    two_product(apy, bpy, &r[1], &r[0]);
    int bn = exp_sum(2, l, 2, r, bb);
    det = exp_estimate(bn, bb);
    errbound = ccw_bound_b * detsum;
    if (det > errbound || -det > errbound) return det;

    double apxt = diff_tail(a[0], p[0], apx), bpxt = diff_tail(b[0], p[0], bpx);
    double apyt = diff_tail(a[1], p[1], apy), bpyt = diff_tail(b[1], p[1], bpy);
    if (apxt == 0.0 && apyt == 0.0 && bpxt == 0.0 && bpyt == 0.0) return exp_value(bn, bb);

    /* Stage D (no stage C: this predicate is rarely near-degenerate with inexact
     * differences): (apx + apxt)(bpx + bpxt) + (apy + apyt)(bpy + bpyt), exactly. */
    double ax[2] = {apxt, apx}, bx[2] = {bpxt, bpx}, ay[2] = {apyt, apy}, by[2] = {bpyt, bpy};
    double px[8], py[8], s[16];
    int pxn = mul2x2(ax, bx, px);
    int pyn = mul2x2(ay, by, py);
    int sn = exp_sum(pxn, px, pyn, py, s);
    return exp_value(sn, s);
}

double geom_diametral(const double a[2], const double b[2], const double p[2]) {
    double t1 = (a[0] - p[0]) * (b[0] - p[0]);
    double t2 = (a[1] - p[1]) * (b[1] - p[1]);
    double det = t1 + t2;
    /* As in geom_orient2d: products of equal sign give |det| == detsum and pass the test. */
    double detsum = fabs(t1) + fabs(t2);
    if (fabs(det) > ccw_bound_a * detsum) return det;
    if (detsum == 0.0) return 0.0;
    return diametral_adapt(a, b, p, detsum);
}

int geom_encroaches(const double a[2], const double b[2], const double p[2]) {
    return geom_diametral(a, b, p) < 0.0;
}

/* ---- rounded geometry --------------------------------------------------------------------- */

int geom_circumcenter(const double a[2], const double b[2], const double c[2], double out[2]) {
    double o = geom_orient2d(a, b, c); /* == (b - a) x (c - a), sign exact */
    if (o == 0.0) return -1;
    double bx = b[0] - a[0], by = b[1] - a[1];
    double cx = c[0] - a[0], cy = c[1] - a[1];
    double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    double denom = 2.0 * o;
    out[0] = a[0] + (cy * b2 - by * c2) / denom;
    out[1] = a[1] + (bx * c2 - cx * b2) / denom;
    return 0;
}

void geom_midpoint(const double a[2], const double b[2], double out[2]) {
    /* Lexicographically smaller endpoint first, so that the result does not depend on the
     * orientation in which a rank stores the segment. */
    if (b[0] < a[0] || (b[0] == a[0] && b[1] < a[1])) {
        const double *t = a;
        a = b;
        b = t;
    }
    out[0] = a[0] + 0.5 * (b[0] - a[0]);
    out[1] = a[1] + 0.5 * (b[1] - a[1]);
}

double geom_area(const double a[2], const double b[2], const double c[2]) {
    return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

static const double rad_to_deg = 57.295779513082320876798154814105170332405472466564;

double geom_angle_deg(const double a[2], const double b[2], const double c[2]) {
    double ux = a[0] - b[0], uy = a[1] - b[1];
    double vx = c[0] - b[0], vy = c[1] - b[1];
    /* the cross product from orient2d: its sign is exact and a nearly straight or nearly
     * closed angle keeps its digits (the plain formula can cancel to 0 or the wrong sign) */
    double cross = geom_orient2d(a, c, b);
    double dot = ux * vx + uy * vy;
    return atan2(fabs(cross), dot) * rad_to_deg;
}

double geom_min_angle_deg(const double a[2], const double b[2], const double c[2]) {
    /* The smallest angle is opposite the shortest edge (law of sines): one atan2. */
    double la = geom_dist2(b, c), lb = geom_dist2(c, a), lc = geom_dist2(a, b);
    if (la <= lb && la <= lc) return geom_angle_deg(b, a, c);
    if (lb <= lc) return geom_angle_deg(a, b, c);
    return geom_angle_deg(a, c, b);
}

int geom_working_point_slow(double p[2]) {
    for (int k = 0; k < 2; k++) {
        if (!(fabs(p[k]) <= GEOM_WORK_MAX)) return -1; /* also NaN */
        if (fabs(p[k]) < 0x1p-147) p[k] = ldexp(nearbyint(ldexp(p[k], 200)), -200);
    }
    return 0;
}
