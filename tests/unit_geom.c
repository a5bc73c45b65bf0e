/* unit_geom: Check suite for mesher/geom/geom.c.
 *
 * The predicates are compared in sign against an exact reference.  Every double is a dyadic
 * rational m * 2^e, so after shifting all inputs of one call to their smallest exponent E the
 * determinant is an integer polynomial in the shifted mantissas times a positive power of two;
 * the reference evaluates it with a small signed-magnitude big integer (base 2^32 limbs)
 * written here, so the test needs no GMP.  The inputs are chosen where floating point is
 * hardest: points on a line moved by single ulps (nextafter) in every direction, integer
 * lattice points on one circle (exactly cocircular, then scaled by powers of two, translated,
 * scaled by inexact factors such as 1e-3), coordinates near 1e6 with features near 1e-3,
 * scales across each predicate's documented range, and many random and random
 * near-degenerate cases.  Each case is also checked under argument permutations with known
 * sign changes, which runs the adaptive stages with different coordinate differences.  The
 * rounded helpers (circumcenter, angles, midpoint, area) are checked against known values and
 * invariants.
 */
#include "check_run.h"
#include "geom/geom.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- exact reference: big integers ----------------------------------------------------- */

#define BIG_LIMBS 160 /* 5120 bits: inputs of one call may span ~1000 binary orders */

typedef struct big {
    int neg; /* 1 if negative; 0 for zero */
    int n;   /* limbs in use, no leading zero limbs; 0 for zero */
    uint32_t d[BIG_LIMBS];
} big;

static void big_norm(big *x) {
    while (x->n > 0 && x->d[x->n - 1] == 0)
        x->n--;
    if (x->n == 0) x->neg = 0;
}

static void big_need(int n) {
    if (n > BIG_LIMBS) {
        fprintf(stderr, "unit_geom: big integer capacity exceeded (%d limbs)\n", n);
        abort();
    }
}

static int mag_cmp(const big *x, const big *y) {
    if (x->n != y->n) return x->n < y->n ? -1 : 1;
    for (int i = x->n - 1; i >= 0; i--)
        if (x->d[i] != y->d[i]) return x->d[i] < y->d[i] ? -1 : 1;
    return 0;
}

static big mag_add(const big *x, const big *y) {
    big r;
    int n = x->n > y->n ? x->n : y->n;
    big_need(n + 1);
    uint64_t carry = 0;
    for (int i = 0; i < n; i++) {
        uint64_t s = carry;
        if (i < x->n) s += x->d[i];
        if (i < y->n) s += y->d[i];
        r.d[i] = (uint32_t)s;
        carry = s >> 32;
    }
    r.d[n] = (uint32_t)carry;
    r.n = n + 1;
    r.neg = 0;
    big_norm(&r);
    return r;
}

/* |x| - |y| for |x| >= |y|. */
static big mag_sub(const big *x, const big *y) {
    big r;
    int64_t borrow = 0;
    for (int i = 0; i < x->n; i++) {
        int64_t s = (int64_t)x->d[i] - borrow - (i < y->n ? (int64_t)y->d[i] : 0);
        borrow = s < 0;
        r.d[i] = (uint32_t)(s + (borrow ? ((int64_t)1 << 32) : 0));
    }
    r.n = x->n;
    r.neg = 0;
    big_norm(&r);
    return r;
}

static big big_add(const big *x, const big *y) {
    big r;
    if (x->neg == y->neg) {
        r = mag_add(x, y);
        r.neg = x->neg;
    } else if (mag_cmp(x, y) >= 0) {
        r = mag_sub(x, y);
        r.neg = x->neg;
    } else {
        r = mag_sub(y, x);
        r.neg = y->neg;
    }
    big_norm(&r);
    return r;
}

static big big_sub(const big *x, const big *y) {
    big t = *y;
    if (t.n > 0) t.neg = !t.neg;
    return big_add(x, &t);
}

static big big_mul(const big *x, const big *y) {
    big r;
    if (x->n == 0 || y->n == 0) {
        r.n = 0;
        r.neg = 0;
        return r;
    }
    int n = x->n + y->n;
    big_need(n);
    memset(r.d, 0, sizeof(uint32_t) * (size_t)n);
    for (int i = 0; i < x->n; i++) {
        uint64_t carry = 0;
        for (int j = 0; j < y->n; j++) {
            uint64_t t = (uint64_t)x->d[i] * y->d[j] + r.d[i + j] + carry;
            r.d[i + j] = (uint32_t)t;
            carry = t >> 32;
        }
        r.d[i + y->n] = (uint32_t)carry;
    }
    r.n = n;
    r.neg = x->neg != y->neg;
    big_norm(&r);
    return r;
}

static int big_sign(const big *x) {
    return x->n == 0 ? 0 : (x->neg ? -1 : 1);
}

/* v = m * 2^e with integer m, |m| < 2^53; returns e (unused for v == 0). */
static int dyadic(double v, int64_t *m) {
    int k;
    double f = frexp(v, &k);
    *m = (int64_t)ldexp(f, 53);
    return k - 53;
}

/* out[i] = v[i] * 2^-E exactly, E the smallest exponent among the nonzero v[i]. */
static void to_bigs(const double *v, int n, big *out) {
    int emin = 1 << 20;
    for (int i = 0; i < n; i++) {
        int64_t m;
        if (v[i] != 0.0) {
            int e = dyadic(v[i], &m);
            if (e < emin) emin = e;
        }
    }
    for (int i = 0; i < n; i++) {
        big *r = &out[i];
        int64_t m = 0;
        r->neg = 0;
        r->n = 0;
        if (v[i] == 0.0) continue;
        int shift = dyadic(v[i], &m) - emin;
        uint64_t mag = (uint64_t)(m < 0 ? -m : m);
        int word = shift / 32, bit = shift % 32;
        big_need(word + 3);
        memset(r->d, 0, sizeof(uint32_t) * (size_t)(word + 3));
        uint64_t lo = (mag & 0xffffffffu) << bit, hi = (mag >> 32) << bit;
        r->d[word] |= (uint32_t)lo;
        r->d[word + 1] |= (uint32_t)(lo >> 32);
        r->d[word + 1] |= (uint32_t)hi;
        r->d[word + 2] |= (uint32_t)(hi >> 32);
        r->n = word + 3;
        r->neg = m < 0;
        big_norm(r);
    }
}

/* Exact sign of (a - c) x (b - c). */
static int ref_orient(const double a[2], const double b[2], const double c[2]) {
    double v[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
    big z[6];
    to_bigs(v, 6, z);
    big acx = big_sub(&z[0], &z[4]), acy = big_sub(&z[1], &z[5]);
    big bcx = big_sub(&z[2], &z[4]), bcy = big_sub(&z[3], &z[5]);
    big l = big_mul(&acx, &bcy), r = big_mul(&acy, &bcx);
    big det = big_sub(&l, &r);
    return big_sign(&det);
}

/* Exact sign of the incircle determinant (positive: d inside ccw abc). */
static int ref_incircle(const double a[2], const double b[2], const double c[2],
                        const double d[2]) {
    double v[8] = {a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]};
    big z[8];
    to_bigs(v, 8, z);
    big adx = big_sub(&z[0], &z[6]), ady = big_sub(&z[1], &z[7]);
    big bdx = big_sub(&z[2], &z[6]), bdy = big_sub(&z[3], &z[7]);
    big cdx = big_sub(&z[4], &z[6]), cdy = big_sub(&z[5], &z[7]);
    big t1, t2, lift, m, term, det;
    t1 = big_mul(&adx, &adx), t2 = big_mul(&ady, &ady), lift = big_add(&t1, &t2);
    t1 = big_mul(&bdx, &cdy), t2 = big_mul(&cdx, &bdy), m = big_sub(&t1, &t2);
    det = big_mul(&lift, &m);
    t1 = big_mul(&bdx, &bdx), t2 = big_mul(&bdy, &bdy), lift = big_add(&t1, &t2);
    t1 = big_mul(&cdx, &ady), t2 = big_mul(&adx, &cdy), m = big_sub(&t1, &t2);
    term = big_mul(&lift, &m);
    det = big_add(&det, &term);
    t1 = big_mul(&cdx, &cdx), t2 = big_mul(&cdy, &cdy), lift = big_add(&t1, &t2);
    t1 = big_mul(&adx, &bdy), t2 = big_mul(&bdx, &ady), m = big_sub(&t1, &t2);
    term = big_mul(&lift, &m);
    det = big_add(&det, &term);
    return big_sign(&det);
}

/* Exact sign of (a - p) . (b - p). */
static int ref_diametral(const double a[2], const double b[2], const double p[2]) {
    double v[6] = {a[0], a[1], b[0], b[1], p[0], p[1]};
    big z[6];
    to_bigs(v, 6, z);
    big apx = big_sub(&z[0], &z[4]), apy = big_sub(&z[1], &z[5]);
    big bpx = big_sub(&z[2], &z[4]), bpy = big_sub(&z[3], &z[5]);
    big x = big_mul(&apx, &bpx), y = big_mul(&apy, &bpy);
    big det = big_add(&x, &y);
    return big_sign(&det);
}

/* ---- helpers --------------------------------------------------------------------------- */

static int sgn(double x) {
    return (x > 0.0) - (x < 0.0);
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static void rng_seed(uint64_t s) {
    rng_state = s * 0x9e3779b97f4a7c15ull + 0x632be59bd9b4e019ull;
    if (rng_state == 0) rng_state = 1;
}

static uint64_t rng_next(void) { /* xorshift64* */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 0x2545f4914f6cdd1dull;
}

/* Uniform in [lo, hi). */
static double urand(double lo, double hi) {
    double u = (double)(rng_next() >> 11) * 0x1p-53;
    return lo + (hi - lo) * u;
}

static int irand(int lo, int hi) { /* inclusive */
    return lo + (int)(rng_next() % (uint64_t)(hi - lo + 1));
}

/* x moved by k ulps (k < 0: toward -inf). */
static double ulps(double x, int k) {
    for (; k > 0; k--)
        x = nextafter(x, INFINITY);
    for (; k < 0; k++)
        x = nextafter(x, -INFINITY);
    return x;
}

static long n_checked; /* predicate evaluations compared with the exact reference */

#define P2(p) (p)[0], (p)[1]

/* orient2d(a,b,c) and three permutations against one exact evaluation. */
static void check_orient(const double a[2], const double b[2], const double c[2]) {
    int want = ref_orient(a, b, c);
    const double *perm[4][3] = {{a, b, c}, {b, c, a}, {c, a, b}, {b, a, c}};
    const int flip[4] = {1, 1, 1, -1};
    for (int k = 0; k < 4; k++) {
        double got = geom_orient2d(perm[k][0], perm[k][1], perm[k][2]);
        ck_assert_msg(sgn(got) == flip[k] * want,
                      "orient2d perm %d of (%a,%a) (%a,%a) (%a,%a) = %g, exact sign %d", k, P2(a),
                      P2(b), P2(c), got, flip[k] * want);
        n_checked++;
    }
}

/* incircle(a,b,c,d) and five permutations (the determinant is alternating in its rows). */
static void check_incircle(const double a[2], const double b[2], const double c[2],
                           const double d[2]) {
    int want = ref_incircle(a, b, c, d);
    const double *perm[6][4] = {{a, b, c, d}, {b, c, a, d}, {b, a, c, d},
                                {b, c, d, a}, {d, a, b, c}, {c, d, a, b}};
    const int flip[6] = {1, 1, -1, -1, -1, 1};
    for (int k = 0; k < 6; k++) {
        double got = geom_incircle(perm[k][0], perm[k][1], perm[k][2], perm[k][3]);
        ck_assert_msg(sgn(got) == flip[k] * want,
                      "incircle perm %d of (%a,%a) (%a,%a) (%a,%a) (%a,%a) = %g, exact sign %d", k,
                      P2(a), P2(b), P2(c), P2(d), got, flip[k] * want);
        n_checked++;
    }
}

static void check_diametral(const double a[2], const double b[2], const double p[2]) {
    int want = ref_diametral(a, b, p);
    double got = geom_diametral(a, b, p), got2 = geom_diametral(b, a, p);
    ck_assert_msg(sgn(got) == want && sgn(got2) == want,
                  "diametral((%a,%a) (%a,%a) (%a,%a)) = %g / swapped %g, exact sign %d", P2(a),
                  P2(b), P2(p), got, got2, want);
    int enc = geom_encroaches(a, b, p);
    ck_assert_msg(enc == (want < 0), "encroaches((%a,%a) (%a,%a) (%a,%a)) = %d, exact sign %d",
                  P2(a), P2(b), P2(p), enc, want);
    n_checked += 3;
}

static void report(const char *what) {
    printf("%-44s %8ld exact comparisons\n", what, n_checked);
    fflush(stdout);
}

static void setup(void) {
    geom_init();
    n_checked = 0;
}

/* Integer points on x^2 + y^2 = 5525 = 5^2 * 13 * 17 (48 of them). */
static int lattice(double pts[][2], int max) {
    int n = 0;
    for (int x = -75; x <= 75; x++)
        for (int y = -75; y <= 75; y++)
            if (x * x + y * y == 5525 && n < max) {
                pts[n][0] = x;
                pts[n][1] = y;
                n++;
            }
    return n;
}

/* ---- the reference itself ---------------------------------------------------------------- */

START_TEST(test_reference_selfcheck) {
    /* Small integers: double arithmetic is exact, so int64 gives the truth. */
    rng_seed(1);
    for (int t = 0; t < 20000; t++) {
        int64_t v[8];
        double p[4][2];
        for (int i = 0; i < 8; i++) {
            v[i] = irand(-1000, 1000);
            p[i / 2][i % 2] = (double)v[i];
        }
        int64_t o = (v[0] - v[4]) * (v[3] - v[5]) - (v[1] - v[5]) * (v[2] - v[4]);
        ck_assert_int_eq(ref_orient(p[0], p[1], p[2]), (o > 0) - (o < 0));
        int64_t adx = v[0] - v[6], ady = v[1] - v[7], bdx = v[2] - v[6], bdy = v[3] - v[7];
        int64_t cdx = v[4] - v[6], cdy = v[5] - v[7];
        int64_t ic = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
                     (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                     (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
        ck_assert_int_eq(ref_incircle(p[0], p[1], p[2], p[3]), (ic > 0) - (ic < 0));
        int64_t dm = (v[0] - v[4]) * (v[2] - v[4]) + (v[1] - v[5]) * (v[3] - v[5]);
        ck_assert_int_eq(ref_diametral(p[0], p[1], p[2]), (dm > 0) - (dm < 0));
    }
    /* Dyadic scaling and mixed exponents do not change the sign. */
    double a[2] = {0x1p-300, 3.0}, b[2] = {1.0, 0x1p-300}, c[2] = {0.0, 0.0};
    ck_assert_int_eq(ref_orient(a, b, c), -1);
    double d[2] = {0x1p-300, 0x1p-300}, e[2] = {0x1p-299, 0x1p-299},
           f[2] = {0x1.8p-299, 0x1.8p-299};
    ck_assert_int_eq(ref_orient(d, e, f), 0);
    f[1] = nextafter(f[1], 1.0);
    ck_assert_int_eq(ref_orient(d, e, f), 1);
}
END_TEST

/* ---- orient2d --------------------------------------------------------------------------- */

START_TEST(test_orient_simple) {
    double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1}, m[2] = {0.5, 0};
    ck_assert(geom_orient2d(a, b, c) > 0);
    ck_assert(geom_orient2d(a, c, b) < 0);
    ck_assert(geom_orient2d(a, b, m) == 0);
    ck_assert(geom_orient2d(a, a, c) == 0);
    ck_assert_msg(fabs(geom_orient2d(a, b, c) - 1.0) < 1e-15, "%g", geom_orient2d(a, b, c));
}
END_TEST

START_TEST(test_orient_random) {
    rng_seed(2);
    for (int t = 0; t < 100000; t++) {
        double p[3][2];
        for (int i = 0; i < 3; i++)
            p[i][0] = urand(-1, 1), p[i][1] = urand(-1, 1);
        check_orient(p[0], p[1], p[2]);
    }
    for (int t = 0; t < 50000; t++) { /* small integers: many exact zeros */
        double p[3][2];
        for (int i = 0; i < 3; i++)
            p[i][0] = irand(-3, 3), p[i][1] = irand(-3, 3);
        check_orient(p[0], p[1], p[2]);
    }
    report("orient2d random + small integers");
}
END_TEST

/* Shewchuk's classic picture: p near (x0, y0) moved by i, j ulps, against a line through it. */
START_TEST(test_orient_ulp_grid) {
    const double lines[][4] = {{0.5, 0.5, 12, 12},   {0.5, 0.5, 24, 24},   {0.5, 0.5, -7, -7},
                               {0.1, 0.2, 0.3, 0.6}, {1e6, 1e6, 3e6, 3e6}, {-0.7, 0.3, 17, 0.3},
                               {0.3, 0.7, 0.3, 99}};
    for (int L = 0; L < (int)(sizeof lines / sizeof lines[0]); L++) {
        double q[2] = {lines[L][2], lines[L][3]};
        double r[2] = {2 * lines[L][2] - lines[L][0], 2 * lines[L][3] - lines[L][1]};
        for (int i = -48; i < 48; i++)
            for (int j = -48; j < 48; j++) {
                double p[2] = {ulps(lines[L][0], i), ulps(lines[L][1], j)};
                check_orient(p, q, r);
            }
    }
    report("orient2d ulp grids on 7 lines");
}
END_TEST

/* b on the line through a and c (rounded), then moved by up to 2 ulps in each direction. */
static void orient_near_line(double scale, double offset, int trials) {
    for (int t = 0; t < trials; t++) {
        double a[2] = {offset + scale * urand(-1, 1), offset + scale * urand(-1, 1)};
        double c[2] = {offset + scale * urand(-1, 1), offset + scale * urand(-1, 1)};
        double s = urand(-1, 2);
        double b0[2] = {a[0] + s * (c[0] - a[0]), a[1] + s * (c[1] - a[1])};
        for (int i = -2; i <= 2; i++)
            for (int j = -2; j <= 2; j++) {
                double b[2] = {ulps(b0[0], i), ulps(b0[1], j)};
                check_orient(a, b, c);
            }
    }
}

START_TEST(test_orient_near_collinear) {
    rng_seed(3);
    orient_near_line(1.0, 0.0, 10000);
    orient_near_line(1e-3, 1e6, 4000); /* coordinates near 1e6, features near 1e-3 */
    orient_near_line(1.0, 1e6, 2000);
    orient_near_line(1e-9, 0.25, 2000);
    report("orient2d near-collinear (+-2 ulps)");
}
END_TEST

/* Exactly the cases where the first-order (stage C) correction cancels: c = (C, C) near 1,
 * a and b tiny multiples of 2^-60, so every difference is inexact, with i - k == j - l.  Then
 * (a - c) x (b - c) = 2^-120 (i l - j k) + C 2^-60 ((j - l) - (i - k)) = 2^-120 (i l - j k):
 * the sign lives in the product of two roundoff tails. */
START_TEST(test_orient_second_order) {
    rng_seed(13);
    for (int t = 0; t < 40000; t++) {
        double C = urand(1, 2), e = 0x1p-60 * (t % 2 ? 1.0 : 0x1p-7);
        int i = irand(-1000, 1000), j = irand(-1000, 1000), k = irand(-1000, 1000);
        int l = j - i + k;
        double a[2] = {i * e, j * e}, b[2] = {k * e, l * e}, c[2] = {C, C};
        check_orient(a, b, c);
        double a2[2] = {C - i * e, C + j * e}; /* and a translated copy, inexact */
        check_orient(a2, b, c);
    }
    report("orient2d second-order (tail x tail) cases");
}
END_TEST

START_TEST(test_orient_scales) {
    rng_seed(4);
    for (int k = -100; k <= 100; k++) {
        double s = pow(10.0, k);
        for (int t = 0; t < 200; t++) {
            double p[3][2];
            for (int i = 0; i < 3; i++)
                p[i][0] = s * urand(-1, 1), p[i][1] = s * urand(-1, 1);
            check_orient(p[0], p[1], p[2]);
        }
        orient_near_line(s, 0.0, 20);
        orient_near_line(s * 1e-9, s, 10);
    }
    for (int k = -380; k <= 400; k += 13) { /* the documented range, by powers of two */
        double s = ldexp(1.0, k);
        orient_near_line(s, 0.0, 10);
    }
    report("orient2d scales 1e-100..1e100, 2^-380..2^400");
}
END_TEST

/* ---- incircle --------------------------------------------------------------------------- */

START_TEST(test_incircle_simple) {
    double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1};
    double in[2] = {0.5, 0.5}, out[2] = {2, 2}, on[2] = {1, 1};
    ck_assert(geom_incircle(a, b, c, in) > 0);
    ck_assert(geom_incircle(a, b, c, out) < 0);
    ck_assert(geom_incircle(a, b, c, on) == 0);
    ck_assert(geom_incircle(a, c, b, in) < 0);
}
END_TEST

START_TEST(test_incircle_random) {
    rng_seed(5);
    for (int t = 0; t < 60000; t++) {
        double p[4][2];
        for (int i = 0; i < 4; i++)
            p[i][0] = urand(-1, 1), p[i][1] = urand(-1, 1);
        check_incircle(p[0], p[1], p[2], p[3]);
    }
    for (int t = 0; t < 30000; t++) { /* small integers: many cocircular quadruples */
        double p[4][2];
        for (int i = 0; i < 4; i++)
            p[i][0] = irand(-2, 2), p[i][1] = irand(-2, 2);
        check_incircle(p[0], p[1], p[2], p[3]);
    }
    report("incircle random + small integers");
}
END_TEST

/* Exactly cocircular lattice points under exact maps (must give exactly 0) and inexact maps
 * (scaling by 1e-3, translation by 1e6 after that, one-ulp moves; compared with the
 * reference). */
START_TEST(test_incircle_lattice) {
    double pts[64][2];
    int n = lattice(pts, 64);
    ck_assert_int_eq(n, 48);
    rng_seed(6);
    long zeros = 0;
    for (int t = 0; t < 6000; t++) {
        int id[4];
        for (int i = 0; i < 4; i++)
            id[i] = irand(0, n - 1);
        /* exact maps: x * 2^k, plus an integer offset up to 1e9 when k in [0, 20] (exact) */
        int k = irand(-60, 60);
        double off[2] = {irand(-1000, 1000), irand(-1000, 1000)};
        double q[4][2];
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 2; j++)
                q[i][j] = ldexp(pts[id[i]][j], k) + (k >= 0 && k <= 20 ? off[j] * 1e6 : 0.0);
        for (int s = 0; s < 6; s++) {
            const int perm[6][4] = {{0, 1, 2, 3}, {1, 2, 0, 3}, {1, 0, 2, 3},
                                    {1, 2, 3, 0}, {3, 0, 1, 2}, {2, 3, 0, 1}};
            double got = geom_incircle(q[perm[s][0]], q[perm[s][1]], q[perm[s][2]], q[perm[s][3]]);
            ck_assert_msg(got == 0.0, "lattice quadruple %d %d %d %d (2^%d, offset %g %g) = %g",
                          id[0], id[1], id[2], id[3], k, off[0], off[1], got);
            zeros++;
        }
        /* inexact maps */
        double r[4][2];
        const double factors[] = {1e-3, 1e-6, 0.1, 3.0 / 7.0};
        double f = factors[irand(0, 3)];
        double tr = (t % 3 == 0) ? 1e6 : (t % 3 == 1) ? 0.0 : 0.1;
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 2; j++)
                r[i][j] = tr + pts[id[i]][j] * f;
        check_incircle(r[0], r[1], r[2], r[3]);
        for (int dx = -1; dx <= 1; dx++)
            for (int dy = -1; dy <= 1; dy++) {
                double d[2] = {ulps(q[3][0], dx), ulps(q[3][1], dy)};
                check_incircle(q[0], q[1], q[2], d);
                double e[2] = {ulps(r[3][0], dx), ulps(r[3][1], dy)};
                check_incircle(r[0], r[1], r[2], e);
            }
    }
    n_checked += zeros;
    report("incircle cocircular lattice (48 pts)");
}
END_TEST

/* Four points on one circle, computed with cos/sin and rounded: nearly cocircular. */
static void incircle_near_circle(double scale, double offset, int trials) {
    for (int t = 0; t < trials; t++) {
        double cx = offset + scale * urand(-1, 1), cy = offset + scale * urand(-1, 1);
        double rad = scale * urand(0.01, 1);
        double p[4][2];
        for (int i = 0; i < 4; i++) {
            double th = urand(0, 6.283185307179586);
            p[i][0] = cx + rad * cos(th);
            p[i][1] = cy + rad * sin(th);
        }
        check_incircle(p[0], p[1], p[2], p[3]);
        double d[2] = {ulps(p[3][0], irand(-2, 2)), ulps(p[3][1], irand(-2, 2))};
        check_incircle(p[0], p[1], p[2], d);
    }
}

START_TEST(test_incircle_near_cocircular) {
    rng_seed(7);
    incircle_near_circle(1.0, 0.0, 20000);
    incircle_near_circle(1e-3, 1e6, 8000); /* coordinates near 1e6, features near 1e-3 */
    incircle_near_circle(1e-12, 1.0, 4000);
    report("incircle near-cocircular");
}
END_TEST

START_TEST(test_incircle_scales) {
    rng_seed(8);
    for (int k = -45; k <= 55; k++) {
        double s = pow(10.0, k);
        for (int t = 0; t < 100; t++) {
            double p[4][2];
            for (int i = 0; i < 4; i++)
                p[i][0] = s * urand(-1, 1), p[i][1] = s * urand(-1, 1);
            check_incircle(p[0], p[1], p[2], p[3]);
        }
        incircle_near_circle(s, 0.0, 40);
        incircle_near_circle(s * 1e-9, s, 20);
    }
    for (int k = -150; k <= 190; k += 7) { /* the documented range, by powers of two */
        double s = ldexp(1.0, k);
        incircle_near_circle(s, 0.0, 10);
    }
    report("incircle scales 1e-45..1e55, 2^-150..2^190");
}
END_TEST

/* The mesher's working range (geom.h): every coordinate a multiple of 2^-200, magnitude at most
 * 2^250 (pslg_check scales inputs into it; geom_working_point keeps new points on it).  Points
 * mixing the extremes: tiny grid multiples next to huge coordinates, near-degenerate too. */
static double grid_coord(void) {
    switch ((int)urand(0, 4)) {
    case 0: /* a small multiple of the grid step */
        return ldexp(floor(urand(-1000, 1000)), -200);
    case 1: /* the largest magnitudes */
        return ldexp(urand(-1, 1), 250);
    case 2: /* everyday numbers */
        return urand(-1, 1);
    default: /* anywhere in between: 53 bits at exponents -147..197, all on the grid */
        return ldexp(nearbyint(ldexp(urand(-1, 1), 53)), (int)urand(-147, 197) - 53);
    }
}

START_TEST(test_working_range) {
    rng_seed(21);
    for (int t = 0; t < 4000; t++) {
        double p[4][2];
        for (int i = 0; i < 4; i++) {
            p[i][0] = grid_coord();
            p[i][1] = grid_coord();
        }
        if (t % 3 == 0) { /* d on or next to the line ab: the sign is in doubt */
            p[2][0] = p[0][0] + (p[1][0] - p[0][0]) * 0.5;
            p[2][1] = p[0][1] + (p[1][1] - p[0][1]) * 0.5;
            if (geom_working_point(p[2]) != 0) continue; /* beyond 2^200: not a new point */
        }
        double o = geom_orient2d(p[0], p[1], p[2]);
        ck_assert_int_eq((o > 0) - (o < 0), ref_orient(p[0], p[1], p[2]));
        if (o > 0) check_incircle(p[0], p[1], p[2], p[3]);
    }
    /* geom_working_point: rounds only magnitudes below 2^-147, refuses what is out of range */
    double q[2] = {0x1.8p-210, 0.3};
    ck_assert_int_eq(geom_working_point(q), 0);
    ck_assert(q[0] == 0x1p-200 * nearbyint(0x1.8p-10) && q[1] == 0.3);
    double r[2] = {0x1.123456789abcdp-140, -0x1p-1074};
    ck_assert_int_eq(geom_working_point(r), 0);
    ck_assert(r[0] == 0x1.123456789abcdp-140 && r[1] == 0);
    double far[2] = {0x1p201, 0}, nan_[2] = {NAN, 0};
    ck_assert_int_eq(geom_working_point(far), -1);
    ck_assert_int_eq(geom_working_point(nan_), -1);
    report("working range: grid 2^-200, magnitudes to 2^250");
}
END_TEST

/* ---- diametral circle -------------------------------------------------------------------- */

START_TEST(test_diametral_simple) {
    double a[2] = {-1, 0}, b[2] = {1, 0};
    double in[2] = {0, 0.5}, on[2] = {0, 1}, out[2] = {0, 1.5}, end[2] = {1, 0};
    ck_assert(geom_diametral(a, b, in) < 0 && geom_encroaches(a, b, in));
    ck_assert(geom_diametral(a, b, on) == 0 && !geom_encroaches(a, b, on));
    ck_assert(geom_diametral(a, b, out) > 0 && !geom_encroaches(a, b, out));
    ck_assert(geom_diametral(a, b, end) == 0 && !geom_encroaches(a, b, end));
}
END_TEST

/* p on the diametral circle of ab (rounded), moved by up to 2 ulps. */
static void diametral_near_circle(double scale, double offset, int trials) {
    for (int t = 0; t < trials; t++) {
        double a[2] = {offset + scale * urand(-1, 1), offset + scale * urand(-1, 1)};
        double b[2] = {offset + scale * urand(-1, 1), offset + scale * urand(-1, 1)};
        double mx = 0.5 * (a[0] + b[0]), my = 0.5 * (a[1] + b[1]);
        double rad = 0.5 * sqrt(geom_dist2(a, b));
        double th = urand(0, 6.283185307179586);
        double p0[2] = {mx + rad * cos(th), my + rad * sin(th)};
        for (int i = -2; i <= 2; i++)
            for (int j = -2; j <= 2; j++) {
                double p[2] = {ulps(p0[0], i), ulps(p0[1], j)};
                check_diametral(a, b, p);
            }
    }
}

START_TEST(test_diametral) {
    rng_seed(9);
    for (int t = 0; t < 100000; t++) {
        double p[3][2];
        for (int i = 0; i < 3; i++)
            p[i][0] = urand(-1, 1), p[i][1] = urand(-1, 1);
        check_diametral(p[0], p[1], p[2]);
    }
    diametral_near_circle(1.0, 0.0, 6000);
    diametral_near_circle(1e-3, 1e6, 3000);
    for (int k = -100; k <= 100; k++) {
        double s = pow(10.0, k);
        diametral_near_circle(s, 0.0, 15);
        diametral_near_circle(s * 1e-9, s, 10);
    }
    /* Thales on the lattice: antipodal pair plus a third lattice point is exactly on. */
    double pts[64][2];
    int n = lattice(pts, 64);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double a[2] = {pts[i][0], pts[i][1]}, b[2] = {-pts[i][0], -pts[i][1]};
            for (int k = -40; k <= 40; k += 20) {
                double sa[2] = {ldexp(a[0], k), ldexp(a[1], k)};
                double sb[2] = {ldexp(b[0], k), ldexp(b[1], k)};
                double sp[2] = {ldexp(pts[j][0], k), ldexp(pts[j][1], k)};
                ck_assert_msg(geom_diametral(sa, sb, sp) == 0.0, "Thales %d %d 2^%d", i, j, k);
                n_checked++;
                for (int dx = -1; dx <= 1; dx++)
                    for (int dy = -1; dy <= 1; dy++) {
                        double q[2] = {ulps(sp[0], dx), ulps(sp[1], dy)};
                        check_diametral(sa, sb, q);
                    }
            }
            double ta[2] = {1e6 + a[0] * 1e-3, 1e6 + a[1] * 1e-3};
            double tb[2] = {1e6 + b[0] * 1e-3, 1e6 + b[1] * 1e-3};
            double tp[2] = {1e6 + pts[j][0] * 1e-3, 1e6 + pts[j][1] * 1e-3};
            check_diametral(ta, tb, tp);
        }
    report("diametral/encroaches");
}
END_TEST

/* ---- rounded geometry -------------------------------------------------------------------- */

START_TEST(test_circumcenter) {
    double o[2];
    double a[2] = {0, 0}, b[2] = {2, 0}, c[2] = {0, 2};
    ck_assert_int_eq(geom_circumcenter(a, b, c, o), 0);
    ck_assert_msg(o[0] == 1.0 && o[1] == 1.0, "circumcenter %g %g", o[0], o[1]);
    ck_assert_int_eq(geom_circumcenter(a, c, b, o), 0); /* clockwise works too */
    ck_assert_msg(o[0] == 1.0 && o[1] == 1.0, "circumcenter %g %g", o[0], o[1]);
    double m[2] = {1, 0};
    ck_assert_int_eq(geom_circumcenter(a, b, m, o), -1);
    ck_assert_int_eq(geom_circumcenter(a, a, c, o), -1);

    rng_seed(10);
    double worst = 0.0;
    for (int t = 0; t < 100000; t++) {
        double p[3][2];
        double off = (t % 2) ? 0.0 : 100.0, s = (t % 3) ? 1.0 : 1e-3;
        for (int i = 0; i < 3; i++)
            p[i][0] = off + s * urand(-1, 1), p[i][1] = off + s * urand(-1, 1);
        if (geom_min_angle_deg(p[0], p[1], p[2]) < 5.0) continue;
        ck_assert_int_eq(geom_circumcenter(p[0], p[1], p[2], o), 0);
        double r0 = sqrt(geom_dist2(o, p[0])), r1 = sqrt(geom_dist2(o, p[1]));
        double r2 = sqrt(geom_dist2(o, p[2]));
        double spread = (fmax(r0, fmax(r1, r2)) - fmin(r0, fmin(r1, r2))) / r0;
        /* off-origin inputs lose ~|offset| / s digits to the relative-to-a differences */
        double tol = 1e-12 * (1.0 + off / s);
        ck_assert_msg(spread <= tol, "circumcenter radii %.17g %.17g %.17g (rel %g)", r0, r1, r2,
                      spread);
        if (off == 0.0 && spread > worst) worst = spread;
    }
    printf("%-44s worst relative radius spread %.3g (min angle >= 5 deg)\n", "circumcenter", worst);
}
END_TEST

START_TEST(test_angles) {
    double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0.5, sqrt(3.0) / 2};
    ck_assert_msg(fabs(geom_min_angle_deg(a, b, c) - 60.0) < 1e-12, "%.17g",
                  geom_min_angle_deg(a, b, c));
    for (int i = 0; i < 3; i++) {
        const double *p[3] = {a, b, c};
        double ang = geom_angle_deg(p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
        ck_assert_msg(fabs(ang - 60.0) < 1e-12, "angle %d = %.17g", i, ang);
    }
    double r[2] = {0, 1};
    ck_assert_msg(fabs(geom_angle_deg(b, a, r) - 90.0) < 1e-12, "%.17g", geom_angle_deg(b, a, r));
    ck_assert_msg(fabs(geom_min_angle_deg(a, b, r) - 45.0) < 1e-12, "%.17g",
                  geom_min_angle_deg(a, b, r));
    double m[2] = {0.5, 0}, far[2] = {2, 0};
    ck_assert(geom_angle_deg(a, m, b) == 180.0);
    ck_assert(geom_angle_deg(b, a, far) == 0.0);
    ck_assert(geom_min_angle_deg(a, m, b) == 0.0);
    double tiny[2] = {0.5, 1e-300};
    ck_assert_msg(geom_min_angle_deg(a, b, tiny) < 1e-290, "%g", geom_min_angle_deg(a, b, tiny));

    rng_seed(11);
    for (int t = 0; t < 100000; t++) {
        double p[3][2];
        for (int i = 0; i < 3; i++)
            p[i][0] = urand(-1, 1), p[i][1] = urand(-1, 1);
        double x = geom_angle_deg(p[2], p[0], p[1]), y = geom_angle_deg(p[0], p[1], p[2]);
        double z = geom_angle_deg(p[1], p[2], p[0]);
        ck_assert_msg(x >= 0 && x <= 180 && y >= 0 && y <= 180 && z >= 0 && z <= 180,
                      "angles %g %g %g", x, y, z);
        ck_assert_msg(fabs(x + y + z - 180.0) < 1e-9, "angle sum %.17g", x + y + z);
        double mn = geom_min_angle_deg(p[0], p[1], p[2]);
        ck_assert_msg(fabs(mn - fmin(x, fmin(y, z))) < 1e-9, "min angle %.17g vs %.17g %.17g %.17g",
                      mn, x, y, z);
    }
}
END_TEST

START_TEST(test_midpoint_area_dist) {
    double a[2] = {1, 2}, b[2] = {3, -6}, o[2], o2[2];
    geom_midpoint(a, b, o);
    ck_assert(o[0] == 2.0 && o[1] == -2.0);
    rng_seed(12);
    for (int t = 0; t < 100000; t++) {
        double s = ldexp(1.0, irand(-60, 60)), off = (t % 2) ? 1e6 : 0.0;
        double p[2] = {off + s * urand(-1, 1), off + s * urand(-1, 1)};
        double q[2] = {off + s * urand(-1, 1), off + s * urand(-1, 1)};
        geom_midpoint(p, q, o);
        geom_midpoint(q, p, o2);
        ck_assert_msg(memcmp(o, o2, sizeof o) == 0, "midpoint not symmetric: %a %a vs %a %a", o[0],
                      o[1], o2[0], o2[1]);
        for (int j = 0; j < 2; j++)
            ck_assert_msg(o[j] >= fmin(p[j], q[j]) && o[j] <= fmax(p[j], q[j]),
                          "midpoint %a outside [%a, %a]", o[j], p[j], q[j]);
        double r[2] = {urand(-1, 1), urand(-1, 1)};
        double area = geom_area(p, q, r), orient = geom_orient2d(p, q, r);
        if (fabs(orient) > 1e-6 * s * s)
            ck_assert_msg(sgn(area) == sgn(orient), "area %g vs orient %g", area, orient);
    }
    double u[2] = {0, 0}, v[2] = {3, 0}, w[2] = {0, 4};
    ck_assert(geom_area(u, v, w) == 6.0);
    ck_assert(geom_area(u, w, v) == -6.0);
    ck_assert(geom_dist2(v, w) == 25.0);
    ck_assert(geom_dist2(v, v) == 0.0);
}
END_TEST

/* geom_area2_accurate against a 128-bit integer determinant: integer coordinates below 2^53 far
 * from the origin, slivers whose plain formula cancels completely. */
START_TEST(test_area2_accurate) {
    rng_seed(13);
    for (int t = 0; t < 200000; t++) {
        int64_t base = (int64_t)1 << irand(20, 51), span = (int64_t)1 << irand(1, 20);
        int64_t v[6];
        for (int i = 0; i < 6; i++)
            v[i] = base + irand(0, (int)(span > 1000000 ? 1000000 : span));
        if (t % 2) { /* c on or next to the line ab */
            v[4] = v[0] + 2 * (v[2] - v[0]);
            v[5] = v[1] + 2 * (v[3] - v[1]) + irand(-1, 1);
        }
        double a[2] = {(double)v[0], (double)v[1]}, b[2] = {(double)v[2], (double)v[3]},
               c[2] = {(double)v[4], (double)v[5]};
        __int128 d =
            (__int128)(v[0] - v[4]) * (v[3] - v[5]) - (__int128)(v[1] - v[5]) * (v[2] - v[4]);
        double want = (double)d, got = geom_area2_accurate(a, b, c);
        ck_assert_msg(fabs(got - want) <= 0x1p-40 * fabs(want), "area2 %a vs exact %a", got, want);
        n_checked++;
    }
    double X = 7.7777777777777777e48, p[2] = {1, 0}, q[2] = {X, 1}, r[2] = {X / 2, 0.5};
    ck_assert(geom_area2_accurate(p, q, r) == 0.5 && geom_area2_accurate(p, r, q) == -0.5);
    report("area2_accurate");
}
END_TEST

START_TEST(test_init_idempotent) {
    geom_init();
    geom_init();
    double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1};
    ck_assert(geom_orient2d(a, b, c) > 0);
}
END_TEST

static Suite *geom_suite(void) {
    Suite *s = suite_create("geom");
    struct {
        const char *name;
        const TTest *test;
    } cases[] = {
        {"reference", test_reference_selfcheck},
        {"orient_simple", test_orient_simple},
        {"orient_random", test_orient_random},
        {"orient_ulp_grid", test_orient_ulp_grid},
        {"orient_near_collinear", test_orient_near_collinear},
        {"orient_second_order", test_orient_second_order},
        {"orient_scales", test_orient_scales},
        {"incircle_simple", test_incircle_simple},
        {"incircle_random", test_incircle_random},
        {"incircle_lattice", test_incircle_lattice},
        {"incircle_near_cocircular", test_incircle_near_cocircular},
        {"incircle_scales", test_incircle_scales},
        {"working_range", test_working_range},
        {"diametral_simple", test_diametral_simple},
        {"diametral", test_diametral},
        {"circumcenter", test_circumcenter},
        {"angles", test_angles},
        {"midpoint_area_dist", test_midpoint_area_dist},
        {"area2_accurate", test_area2_accurate},
        {"init", test_init_idempotent},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        TCase *tc = tcase_create(cases[i].name);
        tcase_add_checked_fixture(tc, setup, NULL);
        tcase_set_timeout(tc, 300);
        tcase_add_test(tc, cases[i].test);
        suite_add_tcase(s, tc);
    }
    return s;
}

int main(void) {
    geom_init();
    return ck_run(geom_suite());
}
