/* pslg_impl: what the PSLG files share (not part of the public interface): the reader
 * (pslg_read.c), the check and normalisation (pslg_check.c), the face arrangement
 * (pslg_faces.c), the crossing split (pslg_split.c) and the hull (pslg_hull.c). */
#ifndef PSLG_IMPL_H
#define PSLG_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "geom/pslg.h"

#include <math.h>

/* Splits the conflicting segment pairs pairs[2k], pairs[2k+1] (k < npairs; crossing in their
 * interiors or overlapping collinearly, found by pslg_check_ex's exact tests) at their
 * intersection: an overlap at the endpoints of each that lie strictly inside the other, a
 * crossing at a new vertex (the intersection point rounded, or an existing new vertex on either
 * segment within a few ulps of it, so that segments through one point share it).  The pieces
 * replace the segments, keeping their markers and lines; new vertices get marker 0, the line
 * of the first segment and attributes interpolated linearly along it.  The caller normalises
 * again (new pieces may repeat each other; rounded points may make new crossings). */
void pslg_split_pairs(pslg *g, const int32_t *pairs, int64_t npairs);

/* Replaces g's segments by n pieces: seg (2 per piece), their markers smk and lines sln (each
 * may be NULL); g takes ownership of the three arrays and frees its old ones. */
void pslg_set_segments(pslg *g, int32_t *seg, int32_t *smk, int32_t *sln, int32_t n);

/* ---- sorting, grid and the vertices inside segments (pslg_check.c) ---- */

typedef int (*pslg_cmp_fn)(const void *ctx, int32_t a, int32_t b);

/* Stable merge sort of a[0..n) with a context comparator; tmp has room for n items. */
void pslg_msort(int32_t *a, int32_t *tmp, int32_t n, pslg_cmp_fn cmp, const void *ctx);

/* A uniform grid of cells over a bounding box, each listing items (vertices or segments). */
typedef struct pslg_grid {
    double x0, y0, cw, ch;
    int nx, ny;
    int32_t *start; /* nx*ny + 1 */
    int32_t *item;
} pslg_grid;

void pslg_grid_free(pslg_grid *gr);

/* A segment as its sorted endpoints lo < hi, and its index i; ordered by (lo, hi, i). */
typedef struct pslg_skey {
    int32_t lo, hi, i;
} pslg_skey;

int pslg_cmp_skey(const void *pa, const void *pb);

/* 1 if p (collinear with ab) lies strictly between a and b. */
static inline int pslg_strictly_between(const double *a, const double *b, const double *p) {
    int k = a[0] != b[0] ? 0 : 1;
    double lo = fmin(a[k], b[k]), hi = fmax(a[k], b[k]);
    return p[k] > lo && p[k] < hi;
}

/* The vertices found strictly inside segments (pslg_vertex_hits). */
typedef struct pslg_split_ctx {
    const pslg *g;
    const pslg_grid *vg;
    int32_t s;
    int32_t *hits; /* growable list of (segment, vertex) pairs */
    size_t nhits, cap;
} pslg_split_ctx;

/* The vertices of g lying strictly inside its segments (exact orient2d and bounds): sc->hits
 * gets (segment, vertex) pairs grouped by segment in segment order.  vg is filled with a grid
 * of the vertices (caller frees). */
void pslg_vertex_hits(const pslg *g, pslg_grid *vg, pslg_split_ctx *sc);

/* The hits of segment s, the next ones in sc->hits from index *h on (pslg_vertex_hits groups
 * them by segment, in segment order): their indices into sc->hits go to order[0..m), sorted from
 * s's first endpoint to its second (tmp has room for m items), and *h moves past them.  Returns
 * m. */
int32_t pslg_hits_of(const pslg *g, const pslg_split_ctx *sc, int32_t s, size_t *h, int32_t *order,
                     int32_t *tmp);

/* Splits every segment at the vertices lying strictly inside it (pslg_check_ex, once the
 * crossings are resolved); the pieces keep the segment's marker and line.  Exact; adds no
 * vertex. */
void pslg_split_at_vertices(pslg *g);

#endif
