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

/* A sparse grid (pslg_sgrid.c): square cells of side h, twice the median length of the
 * segments it is sized by, grouped in blocks of 8 x 8 cells, of which only the occupied ones
 * are kept (an open-addressing table keyed by the block's column and row).  For the candidate
 * searches of pslg_check on inputs whose bounding box is far wider than their segments (a
 * coastline: a uniform grid of n cells there holds hundreds of items a cell).  A block's cells
 * lie together in memory, so a walk along a coastline (segments in file order) stays in cache
 * and mostly in the block it looked up last.  Candidates only: every decision stays exact. */
typedef struct pslg_sgrid {
    double x0, y0, h;
    uint64_t mask;
    int64_t *key; /* mask + 1 slots: block key, or -1 empty */
    int32_t *blk; /* mask + 1 slots: the block's number */
    int32_t nblk, bcap;
    int32_t *start; /* 64 nblk + 1: cell c of block b holds item[start[64 b + c] .. next) */
    int32_t *item;
    int64_t last_key; /* the block looked up last, and its number */
    int32_t last_blk;
} pslg_sgrid;

/* Sizes G over the box x0, y0, x1, y1 by the segments ids[0..ns) of g (ids NULL: 0..ns-1).
 * Returns 0, or -1 (nothing allocated: use a uniform grid) when it would not pay: fewer than
 * 1024 items, no segment length to size it by, or segments so long against the median that
 * walking their cells would cost more than nitems * 64 visits. */
int pslg_sgrid_init(pslg_sgrid *G, const pslg *g, const int32_t *ids, int32_t ns, int64_t nitems,
                    double x0, double y0, double x1, double y1);
/* Fills G with the points xy[0..n): item i in the cell holding point i.  Once per grid. */
void pslg_sgrid_add_points(pslg_sgrid *G, const double *xy, int32_t n);
/* Fills G with segments ids[0..n) (NULL: 0..n-1) of seg over xy: each segment in every cell it
 * passes near (pslg_sgrid_walk's cells).  Once per grid. */
void pslg_sgrid_add_segments(pslg_sgrid *G, const double *xy, const int32_t *seg,
                             const int32_t *ids, int32_t n);
/* fn(ctx, items, count) for every occupied cell the segment ab passes near: row by row, padded
 * by one cell in x so rounding cannot lose a cell (each cell once). */
void pslg_sgrid_walk(pslg_sgrid *G, const double *a, const double *b,
                     void (*fn)(void *ctx, const int32_t *item, int32_t n), void *ctx);
/* fn(ctx, items, count) for every occupied cell. */
void pslg_sgrid_cells(const pslg_sgrid *G, void (*fn)(void *ctx, const int32_t *item, int32_t n),
                      void *ctx);
void pslg_sgrid_free(pslg_sgrid *G);

/* Items 0 .. n-1 grouped by key[i] < nb (a stable counting sort): group b's items are
 * (*item)[(*start)[b] .. (*start)[b + 1]), ascending.  The caller frees *start (nb + 1) and
 * *item (n). */
void pslg_buckets(const uint32_t *key, int32_t n, uint32_t nb, int32_t **start, int32_t **item);

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
