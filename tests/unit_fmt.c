/* unit_fmt: Check suite for the writers' number formatting (mesher/io/fmt.c).
 *
 * fmt_dbl must give, for every finite double, text that strtod reads back to the same bits, in
 * no more significant digits than the shortest "%.{p}g" that reads back (p = 1..17), which is
 * the reference computed here the slow way.  Values: random bit patterns over every exponent,
 * random values in the fast path's range, decimal fractions k / 10^j (short forms), powers of
 * two (the narrow rounding intervals), neighbours of powers of ten, and the extremes.
 */
#include "check_run.h"
#include "io/fmt.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng = 88172645463325252ull;
static uint64_t next(void) {
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

/* Significant digits of the shortest %.{p}g that reads back. */
static int ref_digits(double v) {
    char b[64];
    for (int p = 1; p <= 17; p++) {
        snprintf(b, sizeof b, "%.*g", p, v);
        if (strtod(b, NULL) == v) return p;
    }
    return 17;
}

/* Significant digits of a %g-style text. */
static int digits_of(const char *s) {
    int n = 0, lead = 1, trail = 0;
    for (; *s && *s != 'e'; s++) {
        if (*s < '0' || *s > '9') continue;
        if (lead && *s == '0') continue;
        lead = 0;
        n++;
        trail = *s == '0' ? trail + 1 : 0;
    }
    return n - trail;
}

static long nchecked, nshorter;

/* 0 when v formats correctly; prints the case otherwise. */
static int check_one(double v) {
    char b[64];
    char *end = fmt_dbl(b, v);
    *end = '\0';
    double back = strtod(b, NULL);
    nchecked++;
    if (memcmp(&back, &v, sizeof v) != 0 && !(v == 0 && back == 0)) {
        fprintf(stderr, "fmt_dbl(%.17g) = \"%s\" reads back as %.17g\n", v, b, back);
        return 1;
    }
    if (fmt_dbl_len(v) != (int)(end - b)) {
        fprintf(stderr, "fmt_dbl_len(%.17g) = %d, fmt_dbl wrote \"%s\"\n", v, fmt_dbl_len(v), b);
        return 1;
    }
    int d = digits_of(b), r = v == 0 ? 1 : ref_digits(v);
    if (d > r) {
        fprintf(stderr, "fmt_dbl(%.17g) = \"%s\": %d digits, %%.%dg reads back\n", v, b, d, r);
        return 1;
    }
    if (d < r) nshorter++;
    return 0;
}

START_TEST(test_random_bits) {
    int bad = 0;
    for (int i = 0; i < 100000 && bad < 10; i++) {
        uint64_t u = next();
        double v;
        memcpy(&v, &u, sizeof v);
        if (!isfinite(v)) continue;
        bad += check_one(v);
    }
    ck_assert_int_eq(bad, 0);
}
END_TEST

START_TEST(test_mesh_range) {
    int bad = 0;
    for (int i = 0; i < 100000 && bad < 10; i++) {
        double f = (double)(next() >> 11) / 9007199254740992.0; /* [0, 1) */
        int ex = (int)(next() % 24) - 6;                        /* 1e-6 .. 1e17 */
        double v = (f + 0.05) * pow(10, ex);
        bad += check_one(next() & 1 ? v : -v);
    }
    ck_assert_int_eq(bad, 0);
}
END_TEST

START_TEST(test_special) {
    int bad = 0;
    for (int j = 0; j <= 8; j++)
        for (long k = 1; k < 3000; k += 7)
            bad += check_one((double)k / pow(10, j));
    for (int e = -1074; e <= 1023; e++) {
        double p = ldexp(1.0, e);
        bad += check_one(p);
        bad += check_one(nextafter(p, 0));
        bad += check_one(nextafter(p, INFINITY));
    }
    for (int e = -20; e <= 22; e++) {
        double p = pow(10, e);
        bad += check_one(p);
        bad += check_one(nextafter(p, 0));
        bad += check_one(nextafter(p, INFINITY));
    }
    double ext[] = {DBL_MAX, -DBL_MAX, DBL_MIN,   DBL_TRUE_MIN, 1e17,       99999999999999999.0,
                    0.1,     0.3,      2.0 / 3.0, 1e-5,         123456.789, 5e-324};
    for (size_t i = 0; i < sizeof ext / sizeof *ext; i++)
        bad += check_one(ext[i]);
    char b[64];
    *fmt_dbl(b, -0.0) = '\0';
    ck_assert_str_eq(b, "0");
    *fmt_dbl(b, 0.5) = '\0';
    ck_assert_str_eq(b, "0.5");
    *fmt_dbl(b, 1234.0) = '\0';
    ck_assert_str_eq(b, "1234");
    *fmt_dbl(b, 1e-7) = '\0';
    ck_assert_str_eq(b, "1e-07");
    *fmt_dbl(b, 0.1 + 0.2) = '\0';
    ck_assert_str_eq(b, "0.30000000000000004");
    ck_assert_int_eq(bad, 0);
}
END_TEST

START_TEST(test_int) {
    char b[32];
    *fmt_int(b, 0) = '\0';
    ck_assert_str_eq(b, "0");
    *fmt_int(b, -9223372036854775807LL - 1) = '\0';
    ck_assert_str_eq(b, "-9223372036854775808");
    *fmt_int(b, 4711) = '\0';
    ck_assert_str_eq(b, "4711");
}
END_TEST

int main(void) {
    int rc = ck_run_nofork(
        ck_suite("fmt", 120, CK_TESTS(test_random_bits, test_mesh_range, test_special, test_int)));
    printf("unit_fmt: %ld values checked, %ld shorter than the shortest %%.{p}g\n", nchecked,
           nshorter);
    return rc;
}
