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

/* Appends the decimal form of v to p; returns the new end. */
static inline char *fmt_int(char *p, long long v) {
    char tmp[24];
    int n = 0;
    unsigned long long u = v < 0 ? 0ULL - (unsigned long long)v : (unsigned long long)v;
    do {
        tmp[n++] = (char)('0' + u % 10);
        u /= 10;
    } while (u);
    if (v < 0) *p++ = '-';
    while (n)
        *p++ = tmp[--n];
    return p;
}

/* Appends the shortest decimal form of v that strtod reads back to the same bits (fmt.c);
 * -0 is written as 0.  Needs 32 bytes of room. */
char *fmt_dbl(char *p, double v);

#endif
