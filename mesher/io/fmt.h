/* fmt: number formatting shared by the writers of mesher/io (internal to io/).
 *
 * Integers are formatted by hand (the big meshes have tens of millions of them and snprintf
 * dominates otherwise).  Doubles are written in the fewest digits that read back to the same
 * bits with any correctly rounding strtod (fmt.c); -0 is written as 0.  The functions append
 * to a caller's buffer and return the new end; the caller guarantees room (24 bytes for an
 * integer, 32 for a double).
 */
#ifndef MESH_IO_FMT_H
#define MESH_IO_FMT_H

#include <stdio.h>

/* "00" "01" ... "99": two digits at a time (fmt.c). */
extern const char fmt_pairs[201];

/* Appends the decimal form of v to p; returns the new end. */
static inline char *fmt_int(char *p, long long v) {
    char tmp[24];
    int n = 24;
    unsigned long long u = v < 0 ? 0ULL - (unsigned long long)v : (unsigned long long)v;
    while (u >= 100) {
        unsigned r = (unsigned)(u % 100);
        u /= 100;
        n -= 2;
        tmp[n] = fmt_pairs[2 * r];
        tmp[n + 1] = fmt_pairs[2 * r + 1];
    }
    if (u >= 10) {
        n -= 2;
        tmp[n] = fmt_pairs[2 * u];
        tmp[n + 1] = fmt_pairs[2 * u + 1];
    } else {
        tmp[--n] = (char)('0' + u);
    }
    if (v < 0) *p++ = '-';
    for (int i = n; i < 24; i++)
        *p++ = tmp[i];
    return p;
}

/* The number of characters fmt_int(p, v) appends (no formatting). */
static inline int fmt_int_len(long long v) {
    unsigned long long u = v < 0 ? 0ULL - (unsigned long long)v : (unsigned long long)v;
    int n = 1 + (v < 0);
    while (u >= 10000) {
        u /= 10000;
        n += 4;
    }
    return n + (u >= 10) + (u >= 100) + (u >= 1000);
}

/* Appends the shortest decimal form of v that strtod reads back to the same bits (fmt.c);
 * -0 is written as 0.  Needs 32 bytes of room. */
char *fmt_dbl(char *p, double v);

/* The number of characters fmt_dbl(p, v) appends, found without writing the digits (the
 * parallel writer's counting pass; about half the cost of fmt_dbl). */
int fmt_dbl_len(double v);

#endif
