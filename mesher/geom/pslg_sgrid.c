/* pslg_sgrid: the sparse blocked grid behind pslg_check's candidate searches (pslg_impl.h).
 *
 * Cells of side h (twice the median length of a sample of 1024 segments) are numbered by column
 * and row from the box's low corner; 8 x 8 of them make a block, and only blocks that hold an
 * item exist, found through an open-addressing table (linear probing, keys hashed with
 * mesh_hash64).  Items are counted per cell, the counts summed into start[], then filled, so a
 * cell's items are consecutive and a block's 64 cells are too.  A segment passes near the cells
 * of the rows its y-range meets, in each row those its x-range there meets, one more on each
 * side (the x-range is rounded; grid_segment in pslg_check.c does the same on the uniform grid),
 * so an item on the segment, or a segment crossing it, is never missed: the grid only proposes
 * candidates, the exact predicates decide.
 */
#include "geom/geom.h"
#include "geom/pslg_impl.h"

#include "base/base.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { SG_B = 8, SG_BB = SG_B * SG_B, SG_SAMPLE = 1024 };

static int64_t sg_col(const pslg_sgrid *G, double x) {
    double c = floor((x - G->x0) / G->h);
    return c > 0 ? (int64_t)c : 0;
}

static int64_t sg_row(const pslg_sgrid *G, double y) {
    double c = floor((y - G->y0) / G->h);
    return c > 0 ? (int64_t)c : 0;
}

static int64_t sg_key(int64_t i, int64_t j) {
    return (i / SG_B) << 31 | (j / SG_B);
}

static int32_t sg_cell(int64_t i, int64_t j) {
    return (int32_t)(j % SG_B) * SG_B + (int32_t)(i % SG_B);
}

/* The slot of block key: its own, or the empty one where it would go. */
static uint64_t sg_slot(const pslg_sgrid *G, int64_t key) {
    uint64_t k = mesh_hash64((uint64_t)key) & G->mask;
    while (G->key[k] >= 0 && G->key[k] != key)
        k = (k + 1) & G->mask;
    return k;
}

static void sg_grow(pslg_sgrid *G) {
    uint64_t cap = 2 * (G->mask + 1);
    int64_t *key = G->key;
    int32_t *blk = G->blk;
    uint64_t old = G->mask + 1;
    G->mask = cap - 1;
    G->key = mesh_xmalloc(cap, sizeof(int64_t));
    G->blk = mesh_xmalloc(cap, sizeof(int32_t));
    for (uint64_t k = 0; k < cap; k++)
        G->key[k] = -1;
    for (uint64_t k = 0; k < old; k++)
        if (key[k] >= 0) {
            uint64_t q = sg_slot(G, key[k]);
            G->key[q] = key[k];
            G->blk[q] = blk[k];
        }
    free(key);
    free(blk);
}

/* The number of the block holding cell (i, j); add: created (with zero counts) if missing,
 * else -1 when missing. */
static int32_t sg_block(pslg_sgrid *G, int64_t i, int64_t j, int add) {
    int64_t key = sg_key(i, j);
    if (key == G->last_key) return G->last_blk;
    uint64_t k = sg_slot(G, key);
    if (G->key[k] < 0 && add) {
        if (2 * (uint64_t)(G->nblk + 1) > G->mask) { /* half full: twice the slots */
            sg_grow(G);
            k = sg_slot(G, key);
        }
        if (G->nblk == G->bcap) {
            G->bcap = G->bcap ? 2 * G->bcap : 1024;
            G->start = mesh_xrealloc(G->start, (size_t)SG_BB * G->bcap + 1, sizeof(int32_t));
        }
        G->key[k] = key;
        G->blk[k] = G->nblk++;
        memset(G->start + (size_t)SG_BB * G->blk[k], 0, SG_BB * sizeof(int32_t));
    }
    G->last_key = key;
    G->last_blk = G->key[k] < 0 ? -1 : G->blk[k];
    return G->last_blk;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int pslg_sgrid_init(pslg_sgrid *G, const pslg *g, const int32_t *ids, int32_t ns, int64_t nitems,
                    double x0, double y0, double x1, double y1) {
    memset(G, 0, sizeof *G);
    if (nitems < 1024 || ns < 1) return -1;
    double len[SG_SAMPLE];
    int32_t m = 0;
    for (int32_t i = 0; i < SG_SAMPLE && i < ns; i++) {
        int32_t k = (int32_t)((int64_t)i * ns / (ns < SG_SAMPLE ? ns : SG_SAMPLE));
        int32_t s = ids ? ids[k] : k;
        len[m++] = sqrt(geom_dist2(g->xy + 2 * g->seg[2 * s], g->xy + 2 * g->seg[2 * s + 1]));
    }
    qsort(len, (size_t)m, sizeof *len, cmp_double);
    double h = 2 * len[m / 2];
    if (!(h > 0) || !isfinite(h) || (x1 - x0) / h > 0x1p30 || (y1 - y0) / h > 0x1p30) return -1;
    double visits = 0; /* cells the segments walk */
    for (int32_t k = 0; k < ns; k++) {
        int32_t s = ids ? ids[k] : k;
        const double *a = g->xy + 2 * g->seg[2 * s], *b = g->xy + 2 * g->seg[2 * s + 1];
        visits += 3 * ((fabs(a[0] - b[0]) + fabs(a[1] - b[1])) / h + 3);
    }
    if (visits > 64.0 * (double)nitems + 1e6) return -1;
    G->x0 = x0;
    G->y0 = y0;
    G->h = h;
    G->last_key = -1;
    uint64_t cap = 1024; /* grows as blocks are added (sg_block) */
    G->mask = cap - 1;
    G->key = mesh_xmalloc(cap, sizeof(int64_t));
    G->blk = mesh_xmalloc(cap, sizeof(int32_t));
    for (uint64_t k = 0; k < cap; k++)
        G->key[k] = -1;
    return 0;
}

/* Turns the counts in start[] into first positions; returns the item count. */
static int32_t sg_sum(pslg_sgrid *G) {
    size_t nc = (size_t)SG_BB * G->nblk;
    if (!G->start) G->start = mesh_xmalloc(1, sizeof(int32_t));
    int64_t sum = 0;
    for (size_t c = 0; c < nc; c++) {
        int32_t k = G->start[c];
        G->start[c] = (int32_t)sum;
        sum += k;
    }
    if (sum > INT32_MAX) MESH_BUG("sparse grid of %lld items", (long long)sum);
    G->start[nc] = (int32_t)sum;
    G->item = mesh_xmalloc((size_t)sum + 1, sizeof(int32_t));
    return (int32_t)sum;
}

void pslg_sgrid_add_points(pslg_sgrid *G, const double *xy, int32_t n) {
    int32_t *cell = mesh_xmalloc((size_t)n + 1, sizeof(int32_t));
    for (int32_t v = 0; v < n; v++) {
        int64_t i = sg_col(G, xy[2 * v]), j = sg_row(G, xy[2 * v + 1]);
        cell[v] = SG_BB * sg_block(G, i, j, 1) + sg_cell(i, j);
        G->start[cell[v]]++;
    }
    sg_sum(G);
    int32_t *fill = mesh_xmalloc((size_t)SG_BB * G->nblk + 1, sizeof(int32_t));
    memcpy(fill, G->start, ((size_t)SG_BB * G->nblk + 1) * sizeof(int32_t));
    for (int32_t v = 0; v < n; v++) /* in point order within a cell */
        G->item[fill[cell[v]]++] = v;
    free(fill);
    free(cell);
}

/* Calls visit(G, ctx, i, j) for the cells the segment ab passes near (see the top). */
static void sg_cells_of(pslg_sgrid *G, const double *a, const double *b,
                        void (*visit)(pslg_sgrid *, void *, int64_t, int64_t), void *ctx) {
    double ylo = fmin(a[1], b[1]), yhi = fmax(a[1], b[1]);
    int64_t j0 = sg_row(G, ylo), j1 = sg_row(G, yhi);
    int64_t bx0 = sg_col(G, fmin(a[0], b[0])), bx1 = sg_col(G, fmax(a[0], b[0]));
    for (int64_t j = j0; j <= j1; j++) {
        int64_t i0 = bx0, i1 = bx1;
        if (j0 != j1) {
            double s0 = fmax(ylo, G->y0 + (double)j * G->h),
                   s1 = fmin(yhi, G->y0 + (double)(j + 1) * G->h);
            double k = (b[0] - a[0]) / (b[1] - a[1]);
            double xa = a[0] + (s0 - a[1]) * k, xb = a[0] + (s1 - a[1]) * k;
            int64_t c0 = sg_col(G, fmin(xa, xb)) - 1, c1 = sg_col(G, fmax(xa, xb)) + 1;
            if (c0 > i0) i0 = c0;
            if (c1 < i1) i1 = c1;
        }
        for (int64_t i = i0; i <= i1; i++)
            visit(G, ctx, i, j);
    }
}

typedef struct sg_fill {
    int32_t *fill; /* NULL: counting */
    int32_t id;
} sg_fill;

static void sg_visit_add(pslg_sgrid *G, void *vctx, int64_t i, int64_t j) {
    sg_fill *f = vctx;
    int32_t c = SG_BB * sg_block(G, i, j, f->fill == NULL) + sg_cell(i, j);
    if (f->fill)
        G->item[f->fill[c]++] = f->id;
    else
        G->start[c]++;
}

void pslg_sgrid_add_segments(pslg_sgrid *G, const double *xy, const int32_t *seg,
                             const int32_t *ids, int32_t n) {
    sg_fill f = {NULL, 0};
    for (int32_t k = 0; k < n; k++) {
        int32_t s = ids ? ids[k] : k;
        sg_cells_of(G, xy + 2 * seg[2 * s], xy + 2 * seg[2 * s + 1], sg_visit_add, &f);
    }
    sg_sum(G);
    f.fill = mesh_xmalloc((size_t)SG_BB * G->nblk + 1, sizeof(int32_t));
    memcpy(f.fill, G->start, ((size_t)SG_BB * G->nblk + 1) * sizeof(int32_t));
    for (int32_t k = 0; k < n; k++) {
        f.id = ids ? ids[k] : k;
        sg_cells_of(G, xy + 2 * seg[2 * f.id], xy + 2 * seg[2 * f.id + 1], sg_visit_add, &f);
    }
    free(f.fill);
}

typedef struct sg_query {
    void (*fn)(void *ctx, const int32_t *item, int32_t n);
    void *ctx;
} sg_query;

static void sg_visit_query(pslg_sgrid *G, void *vctx, int64_t i, int64_t j) {
    sg_query *q = vctx;
    int32_t b = sg_block(G, i, j, 0);
    if (b < 0) return;
    int32_t c = SG_BB * b + sg_cell(i, j);
    if (G->start[c + 1] > G->start[c])
        q->fn(q->ctx, G->item + G->start[c], G->start[c + 1] - G->start[c]);
}

void pslg_sgrid_walk(pslg_sgrid *G, const double *a, const double *b,
                     void (*fn)(void *ctx, const int32_t *item, int32_t n), void *ctx) {
    sg_query q = {fn, ctx};
    sg_cells_of(G, a, b, sg_visit_query, &q);
}

void pslg_sgrid_cells(const pslg_sgrid *G, void (*fn)(void *ctx, const int32_t *item, int32_t n),
                      void *ctx) {
    size_t nc = (size_t)SG_BB * G->nblk;
    for (size_t c = 0; c < nc; c++)
        if (G->start[c + 1] > G->start[c])
            fn(ctx, G->item + G->start[c], G->start[c + 1] - G->start[c]);
}

void pslg_sgrid_free(pslg_sgrid *G) {
    free(G->key), free(G->blk), free(G->start), free(G->item);
    memset(G, 0, sizeof *G);
}
