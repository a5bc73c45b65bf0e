/* pslg_check: a PSLG validated and normalised before any meshing (pslg_check,
 * pslg_check_ex).
 *
 * In order: finite coordinates and in-range segment endpoints; an exact power-of-two scaling
 * into the predicates' working range (pslg.h); duplicate vertices merged (sort by (x, y)) and
 * segments remapped; zero-length and repeated segments dropped; crossing and overlapping
 * segments refused or, with PSLG_SPLIT, handed to pslg_split.c and the pieces checked again
 * (up to PSLG_SPLIT_ROUNDS rounds); finally every segment split at the vertices lying strictly
 * inside it.  Candidate pairs come from a uniform grid whose cells each segment visits along
 * its length (and vertices from a grid of points), so the work is near-linear for spread-out
 * inputs; every candidate is decided by the exact geom_orient2d, never by a tolerance.
 * Invariant after pslg_check: distinct vertex coordinates, distinct non-degenerate segments,
 * no two segments meeting except at shared endpoints, and no vertex inside a segment (so every
 * corner a segment makes with another is at an endpoint of both).
 */
#include "geom/pslg.h"

#include "base/base.h"
#include "geom/geom.h"
#include "geom/pslg_impl.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- sorting helper -------- */

/* Stable merge sort of a[0..n) with a context comparator; tmp has room for n items. */
void pslg_msort(int32_t *a, int32_t *tmp, int32_t n, pslg_cmp_fn cmp, const void *ctx) {
    if (n <= 16) {
        for (int32_t i = 1; i < n; i++) {
            int32_t v = a[i], j = i;
            while (j > 0 && cmp(ctx, a[j - 1], v) > 0) {
                a[j] = a[j - 1];
                j--;
            }
            a[j] = v;
        }
        return;
    }
    int32_t h = n / 2;
    pslg_msort(a, tmp, h, cmp, ctx);
    pslg_msort(a + h, tmp, n - h, cmp, ctx);
    int32_t i = 0, j = h, k = 0;
    while (i < h && j < n)
        tmp[k++] = cmp(ctx, a[j], a[i]) < 0 ? a[j++] : a[i++];
    while (i < h)
        tmp[k++] = a[i++];
    while (j < n)
        tmp[k++] = a[j++];
    memcpy(a, tmp, (size_t)n * sizeof *a);
}

/* ---------------------------------------------------------------- uniform grid ---------- */

static void grid_setup(pslg_grid *gr, double x0, double y0, double x1, double y1, long n) {
    memset(gr, 0, sizeof *gr);
    double w = x1 - x0, h = y1 - y0;
    long nx = 1, ny = 1;
    if (n < 1) n = 1;
    if (w > 0 && h > 0) { /* clamped as doubles: a thin box's ratio may exceed a long */
        double fx = ceil(sqrt((double)n * w / h)), fy = ceil(sqrt((double)n * h / w));
        nx = fx >= 1 && fx <= 2048 ? (long)fx : fx > 2048 ? 2048 : 1;
        ny = fy >= 1 && fy <= 2048 ? (long)fy : fy > 2048 ? 2048 : 1;
    } else if (w > 0) {
        nx = n;
    } else if (h > 0) {
        ny = n;
    }
    nx = nx < 1 ? 1 : nx > 2048 ? 2048 : nx;
    ny = ny < 1 ? 1 : ny > 2048 ? 2048 : ny;
    gr->x0 = x0;
    gr->y0 = y0;
    gr->nx = (int)nx;
    gr->ny = (int)ny;
    gr->cw = w > 0 ? w / nx : 1;
    gr->ch = h > 0 ? h / ny : 1;
}

static int grid_cx(const pslg_grid *gr, double x) {
    double c = (x - gr->x0) / gr->cw;
    if (!(c > 0)) return 0;
    return c >= gr->nx - 1 ? gr->nx - 1 : (int)c;
}

static int grid_cy(const pslg_grid *gr, double y) {
    double c = (y - gr->y0) / gr->ch;
    if (!(c > 0)) return 0;
    return c >= gr->ny - 1 ? gr->ny - 1 : (int)c;
}

/* Calls visit(ctx, cell) for every cell the segment ab passes near (row by row, padded by one
 * cell in x so rounding cannot lose a cell). */
static void grid_segment(const pslg_grid *gr, const double *a, const double *b,
                         void (*visit)(void *, int32_t), void *ctx) {
    double ylo = fmin(a[1], b[1]), yhi = fmax(a[1], b[1]);
    int j0 = grid_cy(gr, ylo), j1 = grid_cy(gr, yhi);
    int bx0 = grid_cx(gr, fmin(a[0], b[0])), bx1 = grid_cx(gr, fmax(a[0], b[0]));
    for (int j = j0; j <= j1; j++) {
        int i0 = bx0, i1 = bx1;
        if (j0 != j1) {
            double s0 = fmax(ylo, gr->y0 + j * gr->ch), s1 = fmin(yhi, gr->y0 + (j + 1) * gr->ch);
            double k = (b[0] - a[0]) / (b[1] - a[1]);
            double xa = a[0] + (s0 - a[1]) * k, xb = a[0] + (s1 - a[1]) * k;
            int c0 = grid_cx(gr, fmin(xa, xb)) - 1, c1 = grid_cx(gr, fmax(xa, xb)) + 1;
            if (c0 > i0) i0 = c0;
            if (c1 < i1) i1 = c1;
        }
        for (int i = i0; i <= i1; i++)
            visit(ctx, (int32_t)j * gr->nx + i);
    }
}

typedef struct fill_ctx {
    pslg_grid *gr;
    int32_t id;
    int counting;
} fill_ctx;

static void grid_visit(void *vctx, int32_t cell) {
    fill_ctx *c = vctx;
    if (c->counting)
        c->gr->start[cell + 1]++;
    else
        c->gr->item[c->gr->start[cell]++] = c->id;
}

/* Buckets the segments listed in ids[0..n) (endpoint pairs in seg, coordinates in xy) into a
 * grid over the bounding box of their endpoints.  Returns 0, or -1 when the cells visited
 * would overflow the grid's int32 counts (absurd inputs). */
static int grid_build_segments(pslg_grid *gr, const double *xy, const int32_t *seg,
                               const int32_t *ids, int32_t n) {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int32_t i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) {
            const double *p = xy + 2 * seg[2 * ids[i] + k];
            x0 = fmin(x0, p[0]);
            x1 = fmax(x1, p[0]);
            y0 = fmin(y0, p[1]);
            y1 = fmax(y1, p[1]);
        }
    if (n == 0) x0 = y0 = x1 = y1 = 0;
    grid_setup(gr, x0, y0, x1, y1, n);
    size_t ncell = (size_t)gr->nx * gr->ny;
    gr->start = mesh_xcalloc(ncell + 1, sizeof(int32_t));
    fill_ctx c = {gr, 0, 1};
    for (int32_t i = 0; i < n; i++) {
        const int32_t *s = seg + 2 * ids[i];
        grid_segment(gr, xy + 2 * s[0], xy + 2 * s[1], grid_visit, &c);
        if (gr->start[ncell] > INT32_MAX / 2) /* cell count overflow guard (absurd inputs) */
            return -1;
    }
    for (size_t i = 0; i < ncell; i++)
        gr->start[i + 1] += gr->start[i];
    gr->item = mesh_xmalloc((size_t)gr->start[ncell] + 1, sizeof(int32_t));
    c.counting = 0;
    for (int32_t i = 0; i < n; i++) {
        const int32_t *s = seg + 2 * ids[i];
        c.id = ids[i];
        grid_segment(gr, xy + 2 * s[0], xy + 2 * s[1], grid_visit, &c);
    }
    for (size_t i = ncell; i > 0; i--)
        gr->start[i] = gr->start[i - 1];
    gr->start[0] = 0;
    return 0;
}

void pslg_grid_free(pslg_grid *gr) {
    free(gr->start);
    free(gr->item);
    gr->start = gr->item = NULL;
}

/* ---------------------------------------------------------------- exact tests ----------- */

static int sgn(double v) {
    return (v > 0) - (v < 0);
}

/* For collinear s, p, q with p, q != s: 1 if p and q lie on the same side of s. */
static int same_direction(const double *s, const double *p, const double *q) {
    if (p[0] != s[0]) return (p[0] > s[0]) == (q[0] > s[0]);
    return (p[1] > s[1]) == (q[1] > s[1]);
}

/* 1 if segments ab and cd (vertex indices) cross in their interiors or overlap collinearly.
 * Touching at a shared endpoint or at a vertex inside the other segment is allowed. */
static int segs_conflict(const double *xy, int32_t a, int32_t b, int32_t c, int32_t d) {
    const double *A = xy + 2 * a, *B = xy + 2 * b, *C = xy + 2 * c, *D = xy + 2 * d;
    if (a == c || a == d || b == c || b == d) {
        const double *S, *P, *Q;
        if (a == c || a == d) {
            S = A;
            P = B;
            Q = a == c ? D : C;
        } else {
            S = B;
            P = A;
            Q = b == c ? D : C;
        }
        if (P == Q || (P[0] == Q[0] && P[1] == Q[1])) return 1;
        if (geom_orient2d(S, P, Q) != 0) return 0;
        return same_direction(S, P, Q);
    }
    int o1 = sgn(geom_orient2d(A, B, C)), o2 = sgn(geom_orient2d(A, B, D));
    if (o1 == 0 && o2 == 0) {
        int k = A[0] != B[0] ? 0 : 1;
        double lo1 = fmin(A[k], B[k]), hi1 = fmax(A[k], B[k]);
        double lo2 = fmin(C[k], D[k]), hi2 = fmax(C[k], D[k]);
        return fmax(lo1, lo2) < fmin(hi1, hi2);
    }
    if (o1 * o2 >= 0) return 0;
    int o3 = sgn(geom_orient2d(C, D, A)), o4 = sgn(geom_orient2d(C, D, B));
    return o3 * o4 < 0;
}

/* ---------------------------------------------------------------- vertices inside segments */

/* Position of vertex v along segment s (for sorting split points). */
typedef struct along_ctx {
    const double *xy;
    const int32_t *hits;
    const double *a, *b;
} along_ctx;

static int cmp_along(const void *vctx, int32_t i, int32_t j) {
    const along_ctx *c = vctx;
    int k = c->a[0] != c->b[0] ? 0 : 1;
    double pi = c->xy[2 * c->hits[2 * i + 1] + k], pj = c->xy[2 * c->hits[2 * j + 1] + k];
    double dir = c->b[k] > c->a[k] ? 1 : -1;
    return pi == pj ? 0 : (pi - pj) * dir < 0 ? -1 : 1;
}
/* The vertices item[0..n) of one grid cell near segment c->s: those strictly inside it (exact
 * orient2d, bounding box first) are hits.  Each vertex lives in one cell and a segment visits a
 * cell once: no repeats. */
static void hits_cell(void *vctx, const int32_t *item, int32_t n) {
    pslg_split_ctx *c = vctx;
    const double *xy = c->g->xy;
    int32_t sa = c->g->seg[2 * c->s], sb = c->g->seg[2 * c->s + 1];
    const double *A = xy + 2 * sa, *B = xy + 2 * sb;
    for (int32_t q = 0; q < n; q++) {
        int32_t v = item[q];
        if (v == sa || v == sb) continue;
        const double *P = xy + 2 * v;
        if (P[0] < fmin(A[0], B[0]) || P[0] > fmax(A[0], B[0]) || P[1] < fmin(A[1], B[1]) ||
            P[1] > fmax(A[1], B[1]))
            continue;
        if (geom_orient2d(A, B, P) != 0 || !pslg_strictly_between(A, B, P)) continue;
        if (c->nhits == c->cap) {
            size_t nc = c->cap ? 2 * c->cap : 64;
            c->hits = mesh_xrealloc(c->hits, nc * 2, sizeof(int32_t));
            c->cap = nc;
        }
        c->hits[2 * c->nhits] = c->s;
        c->hits[2 * c->nhits + 1] = v;
        c->nhits++;
    }
}

/* One cell of the uniform vertex grid (grid_segment's visitor): as hits_cell. */
static void split_visit(void *vctx, int32_t cell) {
    pslg_split_ctx *c = vctx;
    hits_cell(c, c->vg->item + c->vg->start[cell], c->vg->start[cell + 1] - c->vg->start[cell]);
}

/* The vertices of g lying strictly inside its segments (exact orient2d and bounds): sc->hits
 * gets (segment, vertex) pairs grouped by segment in segment order, each segment's in the order
 * its cells and their vertices are visited (pslg_hits_of sorts them along it).  vg is filled
 * with a grid of the vertices when the sparse one does not pay (caller frees). */
void pslg_vertex_hits(const pslg *g, pslg_grid *vg, pslg_split_ctx *sc) {
    int32_t n = g->nverts, ns = g->nsegs;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int32_t i = 0; i < n; i++) {
        x0 = fmin(x0, g->xy[2 * i]);
        x1 = fmax(x1, g->xy[2 * i]);
        y0 = fmin(y0, g->xy[2 * i + 1]);
        y1 = fmax(y1, g->xy[2 * i + 1]);
    }
    if (n == 0) x0 = x1 = y0 = y1 = 0;
    sc->g = g;
    pslg_sgrid G;
    if (pslg_sgrid_init(&G, g, NULL, ns, n, x0, y0, x1, y1) == 0) {
        pslg_sgrid_add_points(&G, g->xy, n);
        for (int32_t s = 0; s < ns; s++) {
            sc->s = s;
            pslg_sgrid_walk(&G, g->xy + 2 * g->seg[2 * s], g->xy + 2 * g->seg[2 * s + 1], hits_cell,
                            sc);
        }
        pslg_sgrid_free(&G);
        return;
    }
    grid_setup(vg, x0, y0, x1, y1, n);
    size_t ncell = (size_t)vg->nx * vg->ny;
    vg->start = mesh_xcalloc(ncell + 1, sizeof(int32_t));
    vg->item = mesh_xmalloc((size_t)n, sizeof(int32_t));
    for (int32_t i = 0; i < n; i++)
        vg->start[grid_cy(vg, g->xy[2 * i + 1]) * vg->nx + grid_cx(vg, g->xy[2 * i]) + 1]++;
    for (size_t c = 0; c < ncell; c++)
        vg->start[c + 1] += vg->start[c];
    for (int32_t i = 0; i < n; i++)
        vg->item[vg->start[grid_cy(vg, g->xy[2 * i + 1]) * vg->nx + grid_cx(vg, g->xy[2 * i])]++] =
            i;
    for (size_t c = ncell; c > 0; c--)
        vg->start[c] = vg->start[c - 1];
    vg->start[0] = 0;
    sc->g = g;
    sc->vg = vg;
    for (int32_t s = 0; s < ns; s++) {
        sc->s = s;
        grid_segment(vg, g->xy + 2 * g->seg[2 * s], g->xy + 2 * g->seg[2 * s + 1], split_visit, sc);
    }
}

int32_t pslg_hits_of(const pslg *g, const pslg_split_ctx *sc, int32_t s, size_t *h, int32_t *order,
                     int32_t *tmp) {
    size_t h0 = *h;
    while (*h < sc->nhits && sc->hits[2 * *h] == s)
        (*h)++;
    int32_t m = (int32_t)(*h - h0);
    for (int32_t i = 0; i < m; i++)
        order[i] = (int32_t)(h0 + (size_t)i);
    along_ctx ac = {g->xy, sc->hits, g->xy + 2 * g->seg[2 * s], g->xy + 2 * g->seg[2 * s + 1]};
    pslg_msort(order, tmp, m, cmp_along, &ac);
    return m;
}

/* Splits every segment at the vertices lying strictly inside it, so that afterwards a segment
 * meets other vertices only at its endpoints: the refinement rules then see every corner a
 * segment makes with the others at a vertex (incidences, small input angles), and the pieces
 * keep the segment's marker and line.  Exact; adds no vertex, so no crossing.  Repeated pieces
 * (a piece that is also an input segment) are left to the next normalisation. */
void pslg_split_at_vertices(pslg *g) {
    pslg_grid vg = {0};
    pslg_split_ctx sc = {0};
    pslg_vertex_hits(g, &vg, &sc);
    pslg_grid_free(&vg);
    if (sc.nhits == 0) {
        free(sc.hits);
        return;
    }
    int32_t ns = g->nsegs;
    size_t cap = (size_t)ns + sc.nhits;
    int32_t *seg = mesh_xmalloc(cap, 2 * sizeof(int32_t));
    int32_t *smk = g->smarker ? mesh_xmalloc(cap, sizeof(int32_t)) : NULL;
    int32_t *sln = g->sline ? mesh_xmalloc(cap, sizeof(int32_t)) : NULL;
    int32_t *order = mesh_xmalloc(sc.nhits, sizeof *order);
    int32_t *tmp = mesh_xmalloc(sc.nhits, sizeof *tmp);
    size_t n = 0, h = 0;
    for (int32_t s = 0; s < ns; s++) {
        int32_t m = pslg_hits_of(g, &sc, s, &h, order, tmp);
        int32_t prev = g->seg[2 * s];
        for (int32_t i = 0; i <= m; i++) {
            int32_t v = i < m ? sc.hits[2 * order[i] + 1] : g->seg[2 * s + 1];
            seg[2 * n] = prev;
            seg[2 * n + 1] = v;
            if (smk) smk[n] = g->smarker[s];
            if (sln) sln[n] = g->sline[s];
            n++;
            prev = v;
        }
    }
    free(order);
    free(tmp);
    free(sc.hits);
    pslg_set_segments(g, seg, smk, sln, (int32_t)n);
}

/* ---------------------------------------------------------------- pslg_check ------------ */

/* Vertices i, j of xy in (x, y, index) order. */
static int cmp_vxy(const void *ctx, int32_t i, int32_t j) {
    const double *xy = ctx;
    if (xy[2 * i] != xy[2 * j]) return xy[2 * i] < xy[2 * j] ? -1 : 1;
    if (xy[2 * i + 1] != xy[2 * j + 1]) return xy[2 * i + 1] < xy[2 * j + 1] ? -1 : 1;
    return (i > j) - (i < j);
}

/* The higher endpoint of segment s. */
static int32_t seg_hi(const int32_t *seg, int32_t s) {
    return seg[2 * s] > seg[2 * s + 1] ? seg[2 * s] : seg[2 * s + 1];
}

/* Segments s, t of seg in (higher endpoint, index) order. */
static int cmp_shi(const void *ctx, int32_t s, int32_t t) {
    const int32_t *seg = ctx;
    int32_t a = seg_hi(seg, s), b = seg_hi(seg, t);
    if (a != b) return a < b ? -1 : 1;
    return (s > t) - (s < t);
}

void pslg_buckets(const uint32_t *key, int32_t n, uint32_t nb, int32_t **start, int32_t **item) {
    int32_t *st = mesh_xcalloc((size_t)nb + 1, sizeof *st);
    int32_t *it = mesh_xmalloc((size_t)n + 1, sizeof *it);
    for (int32_t i = 0; i < n; i++)
        st[key[i] + 1]++;
    for (uint32_t b = 0; b < nb; b++)
        st[b + 1] += st[b];
    for (int32_t i = 0; i < n; i++) /* ascending within each bucket: stable */
        it[st[key[i]]++] = i;
    for (uint32_t b = nb; b > 0; b--)
        st[b] = st[b - 1];
    st[0] = 0;
    *start = st;
    *item = it;
}

/* ---------------------------------------------------------------- scaling --------------- */

/* 1 iff x * 2^e is a multiple of 2^PSLG_GRID_EXP (0 included); x * 2^e is at most 2^100. */
static int on_grid(double x, int e) {
    if (x == 0) return 1;
    double y = ldexp(x, e - PSLG_GRID_EXP);
    return y != 0 && y == floor(y);
}

static double scale_area(double a, int e) {
    if (!(a > 0)) return a;
    double s = ldexp(a, 2 * e);
    return s > 0 ? s : DBL_MIN; /* a bound that underflowed stays a bound */
}

/* The exponent pslg_scale applies to g (*e; 0: none) and g's largest magnitude (*bigp).
 * Returns 0, or -1 when that magnitude is below the supported range. */
static int scale_choice(const pslg *g, double *bigp, int *ep) {
    double big = 0;
    for (int32_t i = 0; i < 2 * g->nverts; i++)
        big = fmax(big, fabs(g->xy[i]));
    for (int32_t i = 0; i < 2 * g->nholes; i++)
        if (isfinite(g->holes[i])) big = fmax(big, fabs(g->holes[i]));
    for (int32_t i = 0; i < g->nregions; i++)
        for (int k = 0; k < 2; k++)
            if (isfinite(g->regions[4 * i + k])) big = fmax(big, fabs(g->regions[4 * i + k]));
    *bigp = big;
    *ep = 0;
    if (big == 0) return 0;
    int e = 0, k;
    if (big > 0x1p100) {
        e = 1; /* below */
    } else {
        for (int32_t i = 0; i < 2 * g->nverts && !e; i++)
            if (!on_grid(g->xy[i], 0)) e = 1;
        for (int32_t i = 0; i < 2 * g->nholes && !e; i++)
            if (isfinite(g->holes[i]) && !on_grid(g->holes[i], 0)) e = 1;
        for (int32_t i = 0; i < g->nregions && !e; i++)
            for (int j = 0; j < 2; j++)
                if (isfinite(g->regions[4 * i + j]) && !on_grid(g->regions[4 * i + j], 0)) e = 1;
    }
    if (!e) return 0; /* already in range: nothing moves, not even by a bit */
    frexp(big, &k);   /* big < 2^k */
    e = PSLG_TOP_EXP - k;
    *ep = e;
    return e > PSLG_MAX_SCALE ? -1 : 0;
}

int pslg_vertices_scaled(const pslg *g, double *xy) {
    for (int32_t i = 0; i < 2 * g->nverts; i++)
        if (!isfinite(g->xy[i])) return -1;
    double big;
    int e;
    if (scale_choice(g, &big, &e) != 0) return -1;
    for (int32_t i = 0; i < 2 * g->nverts; i++) {
        if (!on_grid(g->xy[i], e)) return -1;
        xy[i] = ldexp(g->xy[i], e);
    }
    return 0;
}

/* Scales g by an exact power of two into the predicates' working range (pslg.h). */
static int pslg_scale(pslg *g, char *err, size_t errlen) {
    const char *vf = g->path[0] ? g->path : "(input)";
    const char *sf = g->segpath[0] ? g->segpath : vf;
    double big;
    int e;
    if (scale_choice(g, &big, &e) != 0)
        return mesh_fail(err, errlen,
                         "%s: the largest coordinate magnitude %.17g is below the supported range "
                         "(at least 2^%d, about 1.8e-218)",
                         vf, big, PSLG_TOP_EXP - 1 - PSLG_MAX_SCALE);
    if (!e) return 0; /* already in range: nothing moves, not even by a bit */
    for (int32_t i = 0; i < 2 * g->nverts; i++)
        if (!on_grid(g->xy[i], e))
            return mesh_fail(err, errlen,
                             "%s:%d: vertex %d: coordinate %.17g is too small next to the largest "
                             "coordinate magnitude %.17g (supported: nonzero magnitudes down to "
                             "2^-247, about 4.4e-75, times the largest)",
                             vf, g->vline ? g->vline[i / 2] : 0, i / 2 + g->first_index, g->xy[i],
                             big);
    for (int32_t i = 0; i < 2 * g->nholes; i++)
        if (isfinite(g->holes[i]) && !on_grid(g->holes[i], e))
            return mesh_fail(err, errlen,
                             "%s: hole %d: coordinate %.17g is too small next to the largest "
                             "coordinate magnitude %.17g",
                             sf, i / 2 + g->first_index, g->holes[i], big);
    for (int32_t i = 0; i < g->nregions; i++)
        for (int j = 0; j < 2; j++)
            if (isfinite(g->regions[4 * i + j]) && !on_grid(g->regions[4 * i + j], e))
                return mesh_fail(err, errlen,
                                 "%s: region %d: coordinate %.17g is too small next to the largest "
                                 "coordinate magnitude %.17g",
                                 sf, i + g->first_index, g->regions[4 * i + j], big);
    for (int32_t i = 0; i < 2 * g->nverts; i++)
        g->xy[i] = ldexp(g->xy[i], e);
    for (int32_t i = 0; i < 2 * g->nholes; i++)
        g->holes[i] = ldexp(g->holes[i], e);
    for (int32_t i = 0; i < g->nregions; i++) {
        g->regions[4 * i] = ldexp(g->regions[4 * i], e);
        g->regions[4 * i + 1] = ldexp(g->regions[4 * i + 1], e);
        g->regions[4 * i + 3] = scale_area(g->regions[4 * i + 3], e);
    }
    g->scale_exp += e;
    return 0;
}

/* The crossing search's state: without split the conflicting pair whose later segment comes
 * first in the file (bs, bt); with split every conflicting pair (pr, np of them). */
typedef struct cross_ctx {
    const pslg *g;
    int split;
    int32_t bs, bt;
    int32_t *pr;
    int64_t np, pcap;
} cross_ctx;

static int cmp_pair(const void *pa, const void *pb) {
    const int32_t *a = pa, *b = pb;
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

/* Every pair of the segments in one grid cell, decided exactly. */
static void cross_cell(void *vctx, const int32_t *item, int32_t n) {
    cross_ctx *c = vctx;
    const pslg *g = c->g;
    for (int32_t i = 0; i < n; i++)
        for (int32_t j = i + 1; j < n; j++) {
            int32_t s = item[i], t = item[j];
            if (s > t) {
                int32_t x = s;
                s = t;
                t = x;
            }
            /* report the pair whose later segment comes first in the file */
            if (!c->split && c->bt >= 0 && (t > c->bt || (t == c->bt && s >= c->bs))) continue;
            if (!segs_conflict(g->xy, g->seg[2 * s], g->seg[2 * s + 1], g->seg[2 * t],
                               g->seg[2 * t + 1]))
                continue;
            c->bs = s;
            c->bt = t;
            if (!c->split) continue;
            if (c->np == c->pcap) {
                c->pcap = c->pcap ? 2 * c->pcap : 64;
                c->pr = mesh_xrealloc(c->pr, (size_t)c->pcap, 2 * sizeof *c->pr);
            }
            c->pr[2 * c->np] = s;
            c->pr[2 * c->np + 1] = t;
            c->np++;
        }
}

/* One normalisation pass of pslg_check_ex: merges duplicate vertices, rejects zero-length
 * segments, drops repeated ones and looks for conflicting pairs (crossing or overlapping).
 * quiet: no warnings (after a split the pieces are not the file's segments).  Without split the
 * conflict whose later segment comes first in the file is the error; with split every
 * conflicting pair goes into *pairs (s < t, two entries each, *npairs of them). */
static int normalise(pslg *g, int split, int quiet, int32_t **pairs, int64_t *npairs, char *err,
                     size_t errlen) {
    const char *vf = g->path[0] ? g->path : "(input)";
    const char *sf = g->segpath[0] ? g->segpath : vf;
    int32_t n = g->nverts;
    *pairs = NULL;
    *npairs = 0;
    /* 1. merge duplicate vertices: grouped by a hash of their coordinates (pslg_buckets), each
     * group of equal points kept in index order so the first is the representative; the
     * warnings go out in (x, y, index) order */
    int32_t *map = mesh_xmalloc((size_t)n, sizeof *map);
    uint32_t nb = 1;
    while (nb < (uint32_t)n && nb < (1u << 30))
        nb *= 2;
    uint32_t *key = mesh_xmalloc((size_t)n + 1, sizeof *key);
    for (int32_t i = 0; i < n; i++)
        key[i] = (uint32_t)mesh_hash64(mesh_dbits(g->xy[2 * i]) ^
                                       mesh_hash64(mesh_dbits(g->xy[2 * i + 1]))) &
                 (nb - 1);
    int32_t *bstart, *bitem;
    pslg_buckets(key, n, nb, &bstart, &bitem);
    free(key);
    int32_t ndup = 0, *dup = NULL, *tmp = mesh_xmalloc((size_t)n + 1, sizeof *tmp);
    for (uint32_t b = 0; b < nb; b++) {
        int32_t *it = bitem + bstart[b], d = bstart[b + 1] - bstart[b];
        if (d > 1) pslg_msort(it, tmp, d, cmp_vxy, g->xy);
        for (int32_t k = 0, rep = 0; k < d; k++) {
            int32_t a = it[k], r = it[rep];
            if (k > 0 && g->xy[2 * a] == g->xy[2 * r] && g->xy[2 * a + 1] == g->xy[2 * r + 1]) {
                map[a] = r;
                if (!dup) dup = mesh_xmalloc((size_t)n, sizeof *dup);
                dup[ndup++] = a;
                if (g->vmarker && g->vmarker[r] == 0) g->vmarker[r] = g->vmarker[a];
            } else {
                rep = k;
                map[a] = a;
            }
        }
    }
    free(bstart);
    free(bitem);
    if (ndup && !quiet && !g->quiet) {
        pslg_msort(dup, tmp, ndup, cmp_vxy, g->xy);
        for (int32_t k = 0; k < ndup; k++) {
            int32_t a = dup[k], b = map[a];
            fprintf(stderr, "%s:%d: warning: vertex %d duplicates vertex %d (line %d); merged\n",
                    vf, g->vline ? g->vline[a] : 0, a + g->first_index, b + g->first_index,
                    g->vline ? g->vline[b] : 0);
        }
    }
    free(dup);
    free(tmp);
    if (ndup) {
        int32_t m = 0;
        int32_t *newidx = mesh_xmalloc((size_t)n, sizeof *newidx);
        for (int32_t i = 0; i < n; i++) {
            if (map[i] != i) continue;
            newidx[i] = m;
            g->xy[2 * m] = g->xy[2 * i];
            g->xy[2 * m + 1] = g->xy[2 * i + 1];
            if (g->vmarker) g->vmarker[m] = g->vmarker[i];
            if (g->vline) g->vline[m] = g->vline[i];
            if (g->vattr)
                memmove(g->vattr + (size_t)m * g->nattr, g->vattr + (size_t)i * g->nattr,
                        (size_t)g->nattr * sizeof(double));
            m++;
        }
        for (int32_t i = 0; i < n; i++)
            map[i] = newidx[map[i]];
        free(newidx);
        for (int32_t s = 0; s < 2 * g->nsegs; s++)
            g->seg[s] = map[g->seg[s]];
        g->nverts = n = m;
    }
    free(map);
    /* 2. zero-length and repeated segments */
    int32_t ns = g->nsegs;
    for (int32_t s = 0; s < ns && !quiet; s++) /* pieces of a split: dropped below */
        if (g->seg[2 * s] == g->seg[2 * s + 1])
            return mesh_fail(err, errlen,
                             "%s:%d: segment %d has zero length (both endpoints are %s)", sf,
                             g->sline ? g->sline[s] : 0, s + g->first_index,
                             ndup ? "the same point" : "the same vertex");
    /* grouped by their lower endpoint, each group in (higher endpoint, index) order: one walk
     * visits them in (lo, hi, index) order, and the first of a run of equal ones is kept */
    int32_t *ids = mesh_xmalloc((size_t)ns, sizeof *ids);
    char *keep = mesh_xmalloc((size_t)ns, 1);
    uint32_t *lo = mesh_xmalloc((size_t)ns + 1, sizeof *lo);
    for (int32_t s = 0; s < ns; s++) {
        int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1];
        lo[s] = (uint32_t)(a < b ? a : b);
        keep[s] = 1;
    }
    int32_t *sstart, *sitem, *stmp = mesh_xmalloc((size_t)ns + 1, sizeof *stmp);
    pslg_buckets(lo, ns, (uint32_t)n, &sstart, &sitem);
    free(lo);
    for (int32_t v = 0; v < n; v++) {
        int32_t *it = sitem + sstart[v], d = sstart[v + 1] - sstart[v];
        if (d > 1) pslg_msort(it, stmp, d, cmp_shi, g->seg);
        for (int32_t k = 0, run = 0; k < d; k++) {
            int32_t s = it[k], t = it[run];
            if (g->seg[2 * s] == g->seg[2 * s + 1]) keep[s] = 0; /* ends merged (quiet passes) */
            if (k == 0 || seg_hi(g->seg, s) != seg_hi(g->seg, t)) {
                run = k;
                continue;
            }
            keep[s] = 0;
            if (!quiet && !g->quiet)
                fprintf(stderr,
                        "%s:%d: warning: segment %d repeats segment %d (line %d); dropped\n", sf,
                        g->sline ? g->sline[s] : 0, s + g->first_index, t + g->first_index,
                        g->sline ? g->sline[t] : 0);
        }
    }
    free(sstart);
    free(sitem);
    free(stmp);
    int32_t nk = 0;
    for (int32_t s = 0; s < ns; s++)
        if (keep[s]) ids[nk++] = s;
    free(keep);
    /* 3. crossings and overlaps: grid candidates, exact decision */
    pslg_grid gr = {0};
    pslg_sgrid sg;
    int rc = 0;
    cross_ctx cc = {g, split, -1, -1, NULL, 0, 0};
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int32_t i = 0; i < nk; i++)
        for (int k = 0; k < 2; k++) {
            const double *p = g->xy + 2 * g->seg[2 * ids[i] + k];
            x0 = fmin(x0, p[0]), x1 = fmax(x1, p[0]), y0 = fmin(y0, p[1]), y1 = fmax(y1, p[1]);
        }
    if (nk > 0 && pslg_sgrid_init(&sg, g, ids, nk, nk, x0, y0, x1, y1) == 0) {
        pslg_sgrid_add_segments(&sg, g->xy, g->seg, ids, nk);
        pslg_sgrid_cells(&sg, cross_cell, &cc);
        pslg_sgrid_free(&sg);
        /* a pair shares several of these small cells: each once, in (s, t) order */
        if (cc.np > 1) qsort(cc.pr, (size_t)cc.np, 2 * sizeof *cc.pr, cmp_pair);
        int64_t k = 0;
        for (int64_t i = 0; i < cc.np; i++)
            if (k == 0 || cc.pr[2 * i] != cc.pr[2 * k - 2] ||
                cc.pr[2 * i + 1] != cc.pr[2 * k - 1]) {
                cc.pr[2 * k] = cc.pr[2 * i];
                cc.pr[2 * k + 1] = cc.pr[2 * i + 1];
                k++;
            }
        cc.np = k;
    } else if (grid_build_segments(&gr, g->xy, g->seg, ids, nk)) {
        rc = mesh_fail(err, errlen, "%s: too many segments to check for crossings (%d)", sf, nk);
    } else {
        size_t ncell = (size_t)gr.nx * gr.ny;
        for (size_t c = 0; c < ncell; c++)
            cross_cell(&cc, gr.item + gr.start[c], gr.start[c + 1] - gr.start[c]);
    }
    pslg_grid_free(&gr);
    int32_t *pr = cc.pr;
    int64_t np = cc.np;
    if (rc == 0 && !split && cc.bt >= 0)
        rc = mesh_fail(err, errlen, "%s:%d: segment %d crosses segment %d (line %d)", sf,
                       g->sline ? g->sline[cc.bt] : 0, cc.bt + g->first_index,
                       cc.bs + g->first_index, g->sline ? g->sline[cc.bs] : 0);
    if (rc == 0 && nk < ns) { /* compact; pairs follow the segments' new numbers */
        int32_t *pos = mesh_xmalloc((size_t)ns, sizeof *pos);
        for (int32_t i = 0; i < nk; i++) {
            int32_t s = ids[i];
            pos[s] = i;
            g->seg[2 * i] = g->seg[2 * s];
            g->seg[2 * i + 1] = g->seg[2 * s + 1];
            if (g->smarker) g->smarker[i] = g->smarker[s];
            if (g->sline) g->sline[i] = g->sline[s];
        }
        for (int64_t k = 0; k < 2 * np; k++)
            pr[k] = pos[pr[k]];
        free(pos);
        g->nsegs = nk;
    }
    free(ids);
    if (rc == 0) {
        *pairs = pr;
        *npairs = np;
    } else {
        free(pr);
    }
    return rc;
}

int pslg_check_start(pslg *g, char *err, size_t errlen) {
    geom_init();
    if (errlen) err[0] = '\0';
    const char *vf = g->path[0] ? g->path : "(input)";
    const char *sf = g->segpath[0] ? g->segpath : vf;
    int32_t n = g->nverts;
    for (int32_t i = 0; i < n; i++)
        if (!isfinite(g->xy[2 * i]) || !isfinite(g->xy[2 * i + 1]))
            return mesh_fail(err, errlen, "%s:%d: vertex %d has a non-finite coordinate", vf,
                             g->vline ? g->vline[i] : 0, i + g->first_index);
    for (int32_t s = 0; s < g->nsegs; s++)
        for (int k = 0; k < 2; k++)
            if (g->seg[2 * s + k] < 0 || g->seg[2 * s + k] >= n)
                return mesh_fail(err, errlen, "%s:%d: segment %d: vertex %d out of range", sf,
                                 g->sline ? g->sline[s] : 0, s + g->first_index,
                                 g->seg[2 * s + k] + g->first_index);
    return pslg_scale(g, err, errlen) != 0 ? -1 : 0;
}

int pslg_check_finish(pslg *g, unsigned flags, char *err, size_t errlen) {
    const char *sf = g->segpath[0] ? g->segpath : g->path[0] ? g->path : "(input)";
    int split = (flags & PSLG_SPLIT) != 0;
    for (int round = 0;; round++) {
        int32_t *pairs;
        int64_t np;
        if (normalise(g, split, round > 0, &pairs, &np, err, errlen) != 0) return -1;
        if (np == 0) {
            int32_t ns = g->nsegs;
            pslg_split_at_vertices(g);
            if (g->nsegs != ns) { /* drop pieces that repeat a segment; no new conflicts */
                if (normalise(g, split, 1, &pairs, &np, err, errlen) != 0) return -1;
                free(pairs);
            }
            if (flags & PSLG_HULL) pslg_enclose_hull(g); /* pslg_hull.c */
            return 0;
        }
        int rc = 0;
        if (round == PSLG_SPLIT_ROUNDS) {
            int32_t s = pairs[0], t = pairs[1];
            rc = mesh_fail(err, errlen,
                           "%s:%d: the segment on this line crosses the segment on line %d, and "
                           "splitting them at their intersection keeps making new crossings "
                           "(intersection points rounded to doubles; the segments are too close to "
                           "resolve): move them apart, or use --strict to see the first crossing",
                           sf, g->sline ? g->sline[t] : 0, g->sline ? g->sline[s] : 0);
        } else {
            pslg_split_pairs(g, pairs, np);
        }
        free(pairs);
        if (rc != 0) return -1;
    }
}

int pslg_check_ex(pslg *g, unsigned flags, char *err, size_t errlen) {
    if (pslg_check_start(g, err, errlen) != 0) return -1;
    return pslg_check_finish(g, flags, err, errlen);
}

int pslg_check(pslg *g, char *err, size_t errlen) {
    return pslg_check_ex(g, 0, err, errlen);
}
