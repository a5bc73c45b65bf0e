/* fmt.c: the shortest decimal form of a double that reads back to the same bits (fmt.h).
 *
 * A finite double v > 0 is m * 2^e (m < 2^53).  Every real in its rounding interval, between
 * the midpoints to its neighbours (m - 1/2) * 2^e and (m + 1/2) * 2^e (the lower one at
 * (m - 1/4) * 2^e when m = 2^52 and the gap below is half as wide), reads back as v under
 * round-to-nearest-even; the endpoints belong to it when m is even.  Scaled by 10^p so that v
 * has 17 digits before the decimal point, the interval's ends and v itself are fractions
 * N / 2^s with N < 2^127 exactly representable in unsigned __int128 when 10^p < 2^73, i.e.
 * for 1e-6 <= v < 1e17 -- the range of nearly every mesh coordinate.  In it, the digits are
 * found exactly: the largest k such that a multiple of 10^k lies in the interval gives the
 * fewest digits, and of the (at most two) such multiples next to v the nearer is taken (ties
 * to even), which is what shortest-round-trip algorithms (Steele & White 1990, "How to print
 * floating-point numbers accurately"; Adams 2018, "Ryu") produce.  Outside the range, and
 * where unsigned __int128 is missing, the shortest of "%.15g", "%.16g", "%.17g" that strtod
 * reads back is used (correct, not always shortest).  The text follows %g's layout: fixed
 * notation for decimal exponents -5 < E < 17, scientific otherwise, no trailing zeros.
 * Invariant (tested against strtod on millions of values): strtod(fmt_dbl(v)) == v, bit for
 * bit, for every finite v; -0 is written as 0.
 */
#include "io/fmt.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char fmt_pairs[201] = "00010203040506070809101112131415161718192021222324252627282930"
                            "31323334353637383940414243444546474849505152535455565758596061"
                            "62636465666768697071727374757677787980818283848586878889909192"
                            "93949596979899";

/* Fallback: the shortest %.{p}g that round-trips (p = 1..17; rare, so tried in order). */
static char *dbl_slow(char *p, double v) {
    for (int prec = 1; prec < 17; prec++) {
        int n = snprintf(p, 32, "%.*g", prec, v);
        if (strtod(p, NULL) == v) return p + n;
    }
    return p + snprintf(p, 32, "%.17g", v);
}

/* Writes the digits d (nd of them, no trailing zeros wanted) with decimal exponent E (the
 * first digit's place) in %g's layout. */
static char *layout(char *p, const char *d, int nd, int E) {
    while (nd > 1 && d[nd - 1] == '0')
        nd--;
    if (E < -4 || E >= 17) {
        *p++ = d[0];
        if (nd > 1) {
            *p++ = '.';
            memcpy(p, d + 1, (size_t)nd - 1);
            p += nd - 1;
        }
        return p + sprintf(p, "e%c%02d", E < 0 ? '-' : '+', E < 0 ? -E : E);
    }
    if (E < 0) {
        *p++ = '0';
        *p++ = '.';
        for (int i = 0; i < -E - 1; i++)
            *p++ = '0';
        memcpy(p, d, (size_t)nd);
        return p + nd;
    }
    for (int i = 0; i <= E; i++)
        *p++ = i < nd ? d[i] : '0';
    if (nd > E + 1) {
        *p++ = '.';
        memcpy(p, d + E + 1, (size_t)(nd - E - 1));
        p += nd - E - 1;
    }
    return p;
}

#if defined(__SIZEOF_INT128__)
typedef unsigned __int128 u128;

static const uint64_t P10[20] = {1ull,
                                 10ull,
                                 100ull,
                                 1000ull,
                                 10000ull,
                                 100000ull,
                                 1000000ull,
                                 10000000ull,
                                 100000000ull,
                                 1000000000ull,
                                 10000000000ull,
                                 100000000000ull,
                                 1000000000000ull,
                                 10000000000000ull,
                                 100000000000000ull,
                                 1000000000000000ull,
                                 10000000000000000ull,
                                 100000000000000000ull,
                                 1000000000000000000ull,
                                 10000000000000000000ull};

/* The 17 decimal digits of x < 10^17 into d, two at a time from a table, in two independent
 * halves of 32-bit arithmetic (the serial chain of 17 divisions was the formatter's cost). */
static void digits17(char d[17], uint64_t x) {
    uint32_t hi = (uint32_t)(x / 100000000u), lo = (uint32_t)(x % 100000000u); /* 9 + 8 digits */
    for (int i = 7; i > 0; i -= 2) {                                           /* lo: d[9..16] */
        uint32_t r = lo % 100;
        lo /= 100;
        memcpy(d + 9 + i - 1, fmt_pairs + 2 * r, 2);
    }
    d[8] = (char)('0' + hi % 10);
    hi /= 10;
    for (int i = 7; i > 0; i -= 2) { /* hi / 10: d[0..7] */
        uint32_t r = hi % 100;
        hi /= 100;
        memcpy(d + i - 1, fmt_pairs + 2 * r, 2);
    }
}

/* The exact shortest digits of v > 0 (significand m < 2^53, v = m 2^e) when v 10^(16 - E)
 * fits the 128-bit arithmetic (about 1e-5 <= v < 1e17), E being floor(log10 v) or one less:
 * returns 1 with the 17-digit integer *best (its trailing zeros dropped: *nd significant
 * digits) and the first digit's decimal exponent *E_out; 0 otherwise (*retry = 1 when E was
 * one too low). */
static int shortest_at(uint64_t m, int e, int narrow, int E, uint64_t *best_out, int *nd,
                       int *E_out, int *retry) {
    *retry = 0;
    /* scale so that v 10^pw has 17 integer digits: pw = 16 - E; (4m + 2) 10^pw < 2^128 */
    int pw = 16 - E;
    if (pw < 0 || pw > 21 || e >= 0 || -e + 2 > 127) return 0;
    /* quarter units (everything times 4) keep the narrow lower gap (m - 1/4) integral; one
     * 64 x 64 -> 128 bit product when 10^pw < 2^64, the interval's ends by addition */
    int s = -e + 2; /* denominator 2^s */
    u128 ten = pw <= 19 ? (u128)P10[pw] : (u128)P10[19] * P10[pw - 19];
    u128 nv = pw <= 19 ? (u128)(4 * m) * P10[pw] : (u128)(4 * m) * ten;
    u128 nh = nv + 2 * ten, nl = nv - (narrow ? ten : 2 * ten);
    u128 mask = ((u128)1 << s) - 1;
    u128 qv128 = nv >> s;
    if (qv128 >= P10[17]) { /* E was one too low */
        *retry = 1;
        return 0;
    }
    uint64_t qv = (uint64_t)qv128, hi = (uint64_t)(nh >> s), lo = (uint64_t)(nl >> s);
    u128 rv = nv & mask, rh = nh & mask, rl = nl & mask;
    int incl = (m & 1) == 0;    /* the ends read back to v (ties to even) */
    if (rh == 0 && !incl) hi--; /* largest integer inside */
    if (rl != 0 || !incl) lo++; /* smallest integer inside */
    /* fewest digits: the largest k with a multiple of 10^k in [lo, hi] (monotone in k);
     * hk = floor(hi / 10^k) by repeated division by the constant 10 (no variable divisor) */
    int k = 0;
    uint64_t hk = hi, t = 1;
    while (k < 17 && hk / 10 * (t * 10) >= lo) {
        hk /= 10;
        t *= 10;
        k++;
    }
    /* k is 0 or 1 for most coordinates (16-17 digits): no variable division then */
    uint64_t a = k == 0 ? qv : k == 1 ? qv - qv % 10 : qv - qv % t, b = a + t, best;
    int a_in = a >= lo, b_in = b <= hi;
    if (a_in && b_in) {
        /* the nearer to v = qv + rv / 2^s: v - a = da + rv/2^s, b - v = t - da - rv/2^s */
        uint64_t da = qv - a;
        int a_nearer;
        if (t > 2 * da + 1) {
            a_nearer = 1; /* t - 2 da >= 2 > 2 rv / 2^s */
        } else if (t == 2 * da + 1) {
            u128 two_rv = 2 * rv, S = (u128)1 << s;
            a_nearer = two_rv < S || (two_rv == S && (a / t) % 2 == 0);
        } else if (t == 2 * da) {
            a_nearer = rv == 0 && (a / t) % 2 == 0;
        } else {
            a_nearer = 0;
        }
        best = a_nearer ? a : b;
    } else {
        best = a_in ? a : b;
    }
    /* best is a multiple of 10^k and, k being the largest such power with a multiple in the
     * interval, not of 10^(k+1) -- unless it rounded up to 10^17: one more digit in front */
    if (best >= P10[17]) {
        best /= 10;
        E++;
        *nd = 1;
    } else {
        *nd = 17 - k;
    }
    *best_out = best;
    *E_out = E;
    return 1;
}

/* Characters of layout(d, nd, E) for nd significant digits (no trailing zeros). */
static int layout_len(int nd, int E) {
    if (E < -4 || E >= 17) return 1 + (nd > 1 ? nd : 0) + 2 + (E <= -100 || E >= 100 ? 3 : 2);
    if (E < 0) return 2 + (-E - 1) + nd;
    return (nd > E + 1 ? nd + 1 : E + 1);
}

/* v > 0 as m 2^e with the decimal exponent estimate (shortest_at's arguments); 0 when
 * subnormal (far outside the range). */
static int split(double v, uint64_t *m, int *e, int *narrow, int *E) {
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    int be = (int)((u >> 52) & 0x7ff);
    if (be == 0) return 0;
    *m = (u & ((1ull << 52) - 1)) | (1ull << 52);
    *e = be - 1075; /* v = m 2^e, 2^52 <= m < 2^53 */
    /* floor(log10 2^(e+52)) (78913 / 2^18 ~ log10 2; >> floors: GCC/Clang shift arithmetically):
     * floor(log10 v) or one less */
    *E = ((*e + 52) * 78913) >> 18;
    *narrow = (u & ((1ull << 52) - 1)) == 0 && be > 1;
    return 1;
}

/* shortest_at with the estimate, and the estimate plus one when it was one too low. */
static int shortest(double v, uint64_t *best, int *nd, int *E) {
    uint64_t m;
    int e, narrow, E0, retry;
    if (!split(v, &m, &e, &narrow, &E0)) return 0;
    if (shortest_at(m, e, narrow, E0, best, nd, E, &retry)) return 1;
    return retry && shortest_at(m, e, narrow, E0 + 1, best, nd, E, &retry);
}

static char *dbl_fast(char *p, double v) {
    uint64_t best;
    int nd, E;
    if (!shortest(v, &best, &nd, &E)) return NULL;
    char d[17];
    digits17(d, best);
    return layout(p, d, 17, E);
}
#endif

char *fmt_dbl(char *p, double v) {
    if (v == 0) { /* also turns -0 into 0 */
        *p++ = '0';
        return p;
    }
    if (!isfinite(v)) return p + snprintf(p, 32, "%.17g", v);
    char *q = p;
    double a = v;
    if (v < 0) {
        *q++ = '-';
        a = -v;
    }
#if defined(__SIZEOF_INT128__)
    char *end = dbl_fast(q, a);
    if (end) return end;
#endif
    return dbl_slow(p, v);
}

int fmt_dbl_len(double v) {
    if (v == 0) return 1;
#if defined(__SIZEOF_INT128__)
    if (isfinite(v)) {
        uint64_t best;
        int nd, E;
        if (shortest(fabs(v), &best, &nd, &E)) return (v < 0) + layout_len(nd, E);
    }
#endif
    char b[40];
    return (int)(fmt_dbl(b, v) - b);
}
