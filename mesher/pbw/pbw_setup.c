/* pbw_setup.c: the start and the end of a PBW run on one rank.  Start: every rank has the
 * same CDT of the input (the decomposition's, which built it first and kept it; else built here),
 * refines it coarsely with an area bound, so every rank owns a piece, computes the length floor
 * from it as ./mesh does, and keeps the triangles whose centroid lies in one of its subdomains (by
 * the decomposition's segments a path to it crosses), with their input regions when asked
 * (mesh_set_regions on the CDT; new triangles inherit the region of the cavity member on their
 * edge, carried in the seeds and boundary records).  End: the count of triangles left outside
 * the bounds that the input does not force, the test-only fault (PBW_TEST_BREAK_IFACE), this
 * rank's triangles as a mesh_flat, and freeing the context. */
#include "pbw/pbw_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void centroid(const mesh *m, int32_t t, double c[2]) {
    const double *a = mesh_vertex_xy(m, m->tv[3 * t]), *b = mesh_vertex_xy(m, m->tv[3 * t + 1]),
                 *d = mesh_vertex_xy(m, m->tv[3 * t + 2]);
    c[0] = (a[0] + b[0] + d[0]) / 3.0;
    c[1] = (a[1] + b[1] + d[1]) / 3.0;
}

/* ---- ownership: the subdomain of each centroid, by the segments a path crosses -----------
 *
 * The faces of d's augmented PSLG (input pieces and interfaces) are the subdomains, and each
 * side of a piece lies in one face (d->seg_sub), since no segment passes through a vertex.  So
 * the face of a point b is known from any path a->b that crosses segments properly (no
 * endpoint of either on the other's line): the face on b's side of the crossing nearest to b,
 * or a's face if there is none.  The initial mesh's triangles are labelled breadth first, each
 * centroid from its neighbour's; each component of the mesh starts from a subdomain's seed
 * point (d->sub_seed, strictly inside it).  The segments sit in a uniform grid, so a short path
 * looks at the few segments near it; a path between two neighbours through their shared edge,
 * not a constraint, crosses no input segment (those are edges of the mesh), so it looks only
 * at the interfaces (a second grid).  That is O(1) per triangle, where the CDT of the
 * decomposition and a walk in it per centroid cost as much as the input's own CDT (measured,
 * CPU seconds of a rank on Great Britain's GSHHG coastline, -q 30 -a 1055000: 0.056-0.060
 * against 0.011-0.012 at 2 ranks, 0.066 against 0.029 at 8; the same owner for every one of its
 * 53,435 initial triangles).  The side and crossing tests are exact (orient2d); which of
 * several crossings is nearest is rounded, and a path that touches a segment (a centroid on a
 * segment, a vertex on the path) is not used: that triangle takes its label from another
 * neighbour, else from a seed point, else from the first labelled neighbour.  The labels only
 * distribute the mesh (a degenerate choice costs balance, never correctness); every rank
 * computes the same ones. */

typedef struct sgrid {
    double x0, y0, cw, ch; /* origin and cell size */
    int32_t nx, ny;
    int32_t *off, *ids; /* per cell: its segments ids[off[c] .. off[c + 1]) */
    int32_t *mark;      /* per segment: the query that last looked at it */
    int32_t stamp;
} sgrid;

static int32_t cell_x(const sgrid *G, double x) {
    double f = (x - G->x0) / G->cw;
    return f <= 0 ? 0 : f >= G->nx - 1 ? G->nx - 1 : (int32_t)f;
}

static int32_t cell_y(const sgrid *G, double y) {
    double f = (y - G->y0) / G->ch;
    return f <= 0 ? 0 : f >= G->ny - 1 ? G->ny - 1 : (int32_t)f;
}

/* Calls fn(G, cell, arg) for every cell segment a-b may pass through: column by column, the
 * rows its line spans there, one more on each side (rounding); a conservative cover. */
static void cover(const sgrid *G, const double a[2], const double b[2],
                  void (*fn)(sgrid *, int32_t, void *), void *arg) {
    const double *l = a[0] <= b[0] ? a : b, *r = a[0] <= b[0] ? b : a;
    int32_t c0 = cell_x(G, l[0]), c1 = cell_x(G, r[0]);
    double ylo = fmin(a[1], b[1]), yhi = fmax(a[1], b[1]);
    for (int32_t cx = c0; cx <= c1; cx++) {
        double lo = ylo, hi = yhi;
        if (c1 > c0 && r[0] > l[0]) { /* the line's rows within this column */
            double xa = fmax(l[0], G->x0 + cx * G->cw), xb = fmin(r[0], G->x0 + (cx + 1) * G->cw);
            double s = (r[1] - l[1]) / (r[0] - l[0]);
            double ya = l[1] + (xa - l[0]) * s, yb = l[1] + (xb - l[0]) * s;
            lo = fmax(ylo, fmin(ya, yb)), hi = fmin(yhi, fmax(ya, yb));
            if (!(lo <= hi)) lo = ylo, hi = yhi;
        }
        int32_t r0 = cell_y(G, lo) - 1, r1 = cell_y(G, hi) + 1;
        if (r0 < 0) r0 = 0;
        if (r1 > G->ny - 1) r1 = G->ny - 1;
        for (int32_t cy = r0; cy <= r1; cy++)
            fn((sgrid *)G, cy * G->nx + cx, arg);
    }
}

static void count_cell(sgrid *G, int32_t c, void *arg) {
    (void)arg;
    G->off[c + 1]++;
}

static void fill_cell(sgrid *G, int32_t c, void *arg) {
    G->ids[G->off[c]++] = *(const int32_t *)arg;
}

static void sgrid_build(sgrid *G, const pslg *g, int32_t s0, int32_t s1, double min_cells) {
    memset(G, 0, sizeof *G);
    double x0 = g->xy[0], x1 = x0, y0 = g->xy[1], y1 = y0;
    for (int32_t v = 1; v < g->nverts; v++) {
        x0 = fmin(x0, g->xy[2 * v]), x1 = fmax(x1, g->xy[2 * v]);
        y0 = fmin(y0, g->xy[2 * v + 1]), y1 = fmax(y1, g->xy[2 * v + 1]);
    }
    double w = fmax(x1 - x0, DBL_MIN), h = fmax(y1 - y0, DBL_MIN);
    double cells =
        fmax(2.0 * (s1 - s0) + 64, min_cells); /* about one segment per cell, or min_cells */
    double side = sqrt(w * h / cells);
    G->nx = (int32_t)fmin(fmax(w / side, 1), 4096), G->ny = (int32_t)fmin(fmax(h / side, 1), 4096);
    G->x0 = x0, G->y0 = y0, G->cw = w / G->nx, G->ch = h / G->ny;
    if (!(G->cw > 0)) G->cw = 1;
    if (!(G->ch > 0)) G->ch = 1;
    size_t nc = (size_t)G->nx * (size_t)G->ny;
    G->off = mesh_xcalloc(nc + 1, sizeof(int32_t));
    for (int32_t s = s0; s < s1; s++)
        cover(G, g->xy + 2 * (size_t)g->seg[2 * s], g->xy + 2 * (size_t)g->seg[2 * s + 1],
              count_cell, NULL);
    for (size_t c = 0; c < nc; c++)
        G->off[c + 1] += G->off[c];
    G->ids = mesh_xmalloc((size_t)G->off[nc] + 1, sizeof(int32_t));
    for (int32_t s = s0; s < s1; s++) /* off[c] moves to the end of cell c ... */
        cover(G, g->xy + 2 * (size_t)g->seg[2 * s], g->xy + 2 * (size_t)g->seg[2 * s + 1],
              fill_cell, &s);
    for (size_t c = nc; c > 0; c--) /* ... which is where cell c + 1 starts */
        G->off[c] = G->off[c - 1];
    G->off[0] = 0;
    G->mark = mesh_xcalloc((size_t)g->nsegs + 1, sizeof(int32_t));
}

static void sgrid_free(sgrid *G) {
    free(G->off), free(G->ids), free(G->mark);
}

typedef struct crossing { /* a path a->b against the segments of d */
    const pcdm_decomp *d;
    const double *a, *b;
    int32_t n, near; /* proper crossings; the one nearest to b */
    double tnear;    /* its parameter along the path (rounded) */
    int touch;       /* the path touches a segment: no answer */
} crossing;

static void cross_cell(sgrid *G, int32_t c, void *arg) {
    crossing *X = arg;
    const pslg *g = &X->d->g;
    for (int32_t i = G->off[c]; i < G->off[c + 1] && !X->touch; i++) {
        int32_t s = G->ids[i];
        if (G->mark[s] == G->stamp) continue;
        G->mark[s] = G->stamp;
        const double *P = g->xy + 2 * (size_t)g->seg[2 * s],
                     *Q = g->xy + 2 * (size_t)g->seg[2 * s + 1];
        double o1 = geom_orient2d(X->a, X->b, P), o2 = geom_orient2d(X->a, X->b, Q);
        if ((o1 > 0 && o2 > 0) || (o1 < 0 && o2 < 0)) continue;
        double oa = geom_orient2d(P, Q, X->a), ob = geom_orient2d(P, Q, X->b);
        if ((oa > 0 && ob > 0) || (oa < 0 && ob < 0)) continue;
        if (o1 == 0 || o2 == 0 || oa == 0 || ob == 0) {
            X->touch = 1;
            return;
        }
        double t = oa / (oa - ob);
        if (X->n == 0 || t > X->tnear) X->near = s, X->tnear = t;
        X->n++;
    }
}

/* The subdomain (-1: none) of point b, given that of a (sa), by the path a->b; -2 if the
 * path touches a segment.  check: the crossing nearest to a must have sa on a's side (seeds:
 * otherwise -2). */
static int32_t face_across(sgrid *G, const pcdm_decomp *d, const double a[2], int32_t sa,
                           const double b[2], int check) {
    /* both ends in one cell no segment was filed in (the filing is conservative, and the cell
     * is convex): nothing crosses the path -- most paths, without a look at any segment */
    int32_t ca = cell_x(G, a[0]);
    if (!check && ca == cell_x(G, b[0])) {
        int32_t ra = cell_y(G, a[1]);
        if (ra == cell_y(G, b[1])) {
            int32_t c = ra * G->nx + ca;
            if (G->off[c] == G->off[c + 1]) return sa;
        }
    }
    crossing X = {d, a, b, 0, -1, 0, 0};
    if (++G->stamp == INT32_MAX) { /* wrap: forget every mark */
        memset(G->mark, 0, (size_t)d->g.nsegs * sizeof(int32_t));
        G->stamp = 1;
    }
    cover(G, a, b, cross_cell, &X);
    if (X.touch) return -2;
    if (X.n == 0) return sa;
    const pslg *g = &d->g;
    if (check) { /* the crossing nearest to a: smallest parameter */
        crossing Y = {d, b, a, 0, -1, 0, 0};
        if (++G->stamp == INT32_MAX) {
            memset(G->mark, 0, (size_t)d->g.nsegs * sizeof(int32_t));
            G->stamp = 1;
        }
        cover(G, b, a, cross_cell, &Y);
        int32_t s = Y.near;
        const double *P = g->xy + 2 * (size_t)g->seg[2 * s],
                     *Q = g->xy + 2 * (size_t)g->seg[2 * s + 1];
        if (Y.touch || d->seg_sub[2 * (size_t)s + (geom_orient2d(P, Q, a) > 0 ? 0 : 1)] != sa)
            return -2;
    }
    int32_t s = X.near;
    const double *P = g->xy + 2 * (size_t)g->seg[2 * s], *Q = g->xy + 2 * (size_t)g->seg[2 * s + 1];
    int32_t sub = d->seg_sub[2 * (size_t)s + (geom_orient2d(P, Q, b) > 0 ? 0 : 1)];
    return sub >= 0 && sub < d->nsub ? sub : -1;
}

/* Owner rank of every triangle slot of m0: the owner of the subdomain of d containing its
 * centroid (above).  Every rank computes the same answer.  (The subdomains balance area; a rank's
 * cross-rank cavities follow the length of its rank boundary, which differed 2.3 times between
 * ranks on the lake at 8 ranks, and its CPU time with them.  Measured, 10M triangles, 4 runs
 * alternating: moving initial triangles across rank boundaries until area plus weighted boundary
 * length balanced to 0.5% lengthened the boundaries, RSRs +4% to +11%, and cpu_max did not
 * improve: 0.3555-0.3615 s against 0.359 s, medians.) */
static void owners(pbw_ctx *C, const mesh *m0, const pcdm_decomp *d, int32_t *own) {
    sgrid G, GI; /* every segment; the interfaces alone */
    sgrid_build(&G, &d->g, 0, d->g.nsegs, 0);
    /* GI finer: about four initial triangles per cell, so that most paths lie in a cell no
     * interface crosses (face_across looks at no segment then) */
    sgrid_build(&GI, &d->g, d->nboundary, d->g.nsegs, 0.25 * m0->nt);
    int32_t nt = m0->nt;
    double *cen = mesh_xmalloc(2 * ((size_t)nt + 1), sizeof(double));
    int32_t *lab = mesh_xmalloc((size_t)nt + 1, sizeof(int32_t)); /* -3: none yet */
    int32_t *q = mesh_xmalloc((size_t)nt + 1, sizeof(int32_t));
    for (int32_t t = 0; t < nt; t++) {
        lab[t] = -3;
        if (mesh_tri_alive(m0, t)) centroid(m0, t, cen + 2 * (size_t)t);
    }
    int32_t seed_tries = 0; /* paths from seed points (long ones: bounded) */
    for (int32_t t0 = 0; t0 < nt; t0++) {
        if (!mesh_tri_alive(m0, t0) || lab[t0] != -3) continue;
        /* a new component, or every path from a labelled neighbour touched a segment: a path
         * from a seed point; failing that, a labelled neighbour's label */
        for (int32_t k = 0; k < d->nsub && lab[t0] == -3 && seed_tries < 4096; k++, seed_tries++) {
            int32_t sub =
                face_across(&G, d, d->sub_seed + 2 * (size_t)k, k, cen + 2 * (size_t)t0, 1);
            if (sub >= -1) lab[t0] = sub;
        }
        for (int j = 0; j < 3 && lab[t0] == -3; j++) {
            int32_t f = m0->tn[3 * (size_t)t0 + (size_t)j];
            if (f >= 0 && lab[f / 3] != -3) lab[t0] = lab[f / 3];
        }
        if (lab[t0] == -3) continue; /* left to its neighbours (below) */
        int32_t head = 0, tail = 0;
        q[tail++] = t0;
        while (head < tail) {
            int32_t t = q[head++];
            for (int j = 0; j < 3; j++) {
                int32_t f = m0->tn[3 * (size_t)t + (size_t)j];
                if (f < 0 || lab[f / 3] != -3) continue;
                /* a path through the shared edge e, not a constraint, crosses no input
                 * segment (they are edges of m0): only the interfaces can change its face */
                int32_t e = 3 * t + j;
                const double *ct = cen + 2 * (size_t)t, *cf = cen + 2 * (size_t)(f / 3);
                const double *u = m0->xy + 2 * (size_t)mesh_org(m0, e),
                             *v = m0->xy + 2 * (size_t)mesh_dest(m0, e);
                int inner = !mesh_edge_constrained(m0, e) && geom_orient2d(u, v, ct) > 0 &&
                            geom_orient2d(u, v, cf) < 0 && geom_orient2d(ct, cf, u) < 0 &&
                            geom_orient2d(ct, cf, v) > 0;
                int32_t sub = face_across(inner ? &GI : &G, d, ct, lab[t], cf, 0);
                if (sub < -1) continue; /* touches: another neighbour may do */
                lab[f / 3] = sub;
                q[tail++] = f / 3;
            }
        }
    }
    /* what no path reached: a labelled neighbour's label, until nothing changes */
    for (int changed = 1; changed;) {
        changed = 0;
        for (int32_t t = 0; t < nt; t++) {
            if (!mesh_tri_alive(m0, t) || lab[t] != -3) continue;
            for (int j = 0; j < 3 && lab[t] == -3; j++) {
                int32_t f = m0->tn[3 * (size_t)t + (size_t)j];
                if (f >= 0 && lab[f / 3] != -3) lab[t] = lab[f / 3], changed = 1;
            }
        }
    }
    for (int32_t t = 0; t < nt; t++) {
        int32_t sub = mesh_tri_alive(m0, t) ? lab[t] : -1;
        own[t] = sub >= 0 ? d->sub_owner[sub] : 0;
        if (own[t] < 0 || own[t] >= C->size) own[t] = 0;
    }
    free(q), free(lab), free(cen);
    sgrid_free(&G);
    sgrid_free(&GI);
}

/* ---- the pre-refinement's band: fine only where the interfaces run ----------------------
 *
 * Where a subdomain interface runs, the initial triangles are the grain of the distribution; a
 * triangle no interface touches lies in one subdomain whatever its size.  So the pre-refinement
 * asks for the fine area a0 only of a triangle whose bounding box meets a cell (of a grid of
 * side about sqrt(a0)) that an interface crosses or borders, and PRE_FAR times a0 elsewhere.  A
 * size heuristic, not topology: the same floats on every rank give the same mesh. */
typedef struct band {
    double x0, y0, cw, ch, a0;
    int32_t nx, ny;
    int32_t *sum; /* (nx + 1) * (ny + 1) prefix sums: marked cells in [0, i) x [0, j) */
} band;

static int32_t band_cell(double v, double v0, double w, int32_t n) {
    double c = floor((v - v0) / w);
    return c < 0 ? 0 : c >= n ? n - 1 : (int32_t)c;
}

/* The size rule (mesh_set_size_rule): above a0 and its bounding box meets a marked cell. */
static int band_rule(void *ctx, const double *const p[3], double area) {
    const band *B = ctx;
    if (!(area > B->a0)) return 0;
    double xl = fmin(fmin(p[0][0], p[1][0]), p[2][0]), xh = fmax(fmax(p[0][0], p[1][0]), p[2][0]);
    double yl = fmin(fmin(p[0][1], p[1][1]), p[2][1]), yh = fmax(fmax(p[0][1], p[1][1]), p[2][1]);
    size_t i0 = (size_t)band_cell(xl, B->x0, B->cw, B->nx),
           i1 = (size_t)band_cell(xh, B->x0, B->cw, B->nx) + 1;
    size_t j0 = (size_t)band_cell(yl, B->y0, B->ch, B->ny),
           j1 = (size_t)band_cell(yh, B->y0, B->ch, B->ny) + 1;
    size_t w = (size_t)B->nx + 1;
    const int32_t *S = B->sum;
    return S[j1 * w + i1] - S[j0 * w + i1] - S[j1 * w + i0] + S[j0 * w + i0] > 0;
}

/* The cells of d's interfaces (segments nboundary..) and their eight neighbours: cells of side
 * about sqrt(a0), but at most four per fine triangle of the domain (area dom) -- a thin domain
 * across a wide bounding box gets wider cells (a wider band), not millions of them. */
static void band_build(band *B, const pcdm_decomp *d, double a0, double dom) {
    const pslg *g = &d->g;
    double x0 = g->xy[0], x1 = x0, y0 = g->xy[1], y1 = y0;
    for (int32_t v = 1; v < g->nverts; v++) {
        x0 = fmin(x0, g->xy[2 * v]), x1 = fmax(x1, g->xy[2 * v]);
        y0 = fmin(y0, g->xy[2 * v + 1]), y1 = fmax(y1, g->xy[2 * v + 1]);
    }
    sgrid G;
    sgrid_build(&G, g, d->nboundary, g->nsegs, fmin((x1 - x0) * (y1 - y0), 4 * dom) / a0);
    B->x0 = G.x0, B->y0 = G.y0, B->cw = G.cw, B->ch = G.ch, B->nx = G.nx, B->ny = G.ny;
    B->a0 = a0;
    size_t w = (size_t)G.nx + 1;
    B->sum = mesh_xcalloc(w * ((size_t)G.ny + 1), sizeof(int32_t));
    for (int32_t j = 0; j < G.ny; j++)
        for (int32_t i = 0; i < G.nx; i++) {
            int on = 0;
            for (int32_t jj = j - 1; jj <= j + 1 && !on; jj++)
                for (int32_t ii = i - 1; ii <= i + 1 && !on; ii++)
                    if (ii >= 0 && jj >= 0 && ii < G.nx && jj < G.ny) {
                        size_t c = (size_t)jj * (size_t)G.nx + (size_t)ii;
                        on = G.off[c + 1] > G.off[c];
                    }
            size_t at = (size_t)(j + 1) * w + (size_t)i + 1;
            B->sum[at] = on + B->sum[at - w] + B->sum[at - 1] - B->sum[at - w - 1];
        }
    sgrid_free(&G);
}

/* The initial boundary-conforming mesh: the CDT of the input; with an area bound, refined
 * (identically on every rank, by the sequential refiner, by the area alone) where the interfaces
 * run (the band above; PRE_FAR times coarser elsewhere) to the size of about PRE_TRIS_PER_RANK
 * triangles per rank but at least PRE_COARSEN times coarser than the bound,
 * so that every rank owns a piece of it (the CDT of a square has two triangles) while nearly
 * all the work is left to the parallel phase.  The initial triangles are the grain of the
 * distribution: a rank owns the ones whose centroid lies in its subdomains, so coarser ones
 * follow the subdomains' borders less closely.  No angle bound: near a detailed boundary the
 * quality refinement is most of the mesh, and every rank would repeat it (Great Britain's
 * GSHHG coastline at -q 30 -a 1055000: 243K of the 521K triangles at 8 ranks, the largest part
 * of each rank's time).  Measured (lake, -q 30 -a 3.5e-6, 8 ranks): at 256 per rank the ranks
 * ended within 1.11 of the mean triangle count, at 1024 1.05, at 4096 1.03 with a third fewer
 * RSRs; the cap at 64 keeps the repeated part at 1.5% of the mesh where it decides (below
 * about 2M triangles at 8 ranks). */
#define PRE_TRIS_PER_RANK 4096.0

#define PRE_COARSEN 64.0

/* The area bound of the pre-refinement away from the interfaces, in units of the fine one (see
 * the band above).  Measured (lake, -q 20.7 -a 3.356e-7, 10M triangles, 8 ranks on 2 cores, 3
 * runs alternating): the initial mesh 51K triangles -> 11K (9.6K at 64), the set-up 15 ms -> 5 ms
 * of CPU per rank, cpu_sum 2.90-2.95 s -> 2.80-2.85 s, cpu_max 0.376-0.385 s -> 0.367-0.373 s;
 * the triangles per rank (1.22M-1.28M) and the RSRs as before. */
#define PRE_FAR 16.0

int pbw_setup(pbw_ctx *C, const pbw_setup_opts *so, const pslg *in, const pcdm_decomp *d, char *err,
              size_t errlen) {
    const char *nf = getenv("PBW_NO_FAST_PATH");
    C->no_fast = nf && nf[0] == '1';
    mesh m0;
    if (d->cdt && d->cdt->nt > 0) { /* the decomposition's CDT of in: taken, not built again */
        m0 = *d->cdt;
        mesh_init(d->cdt);
    } else {
        mesh_init(&m0);
        if (mesh_build_cdt(&m0, in, NULL, err, errlen) != 0) {
            mesh_free(&m0);
            return -1;
        }
    }
    /* regions labelled on the CDT (the pre-refinement below inherits them; their bounds are
     * the parallel phase's) */
    if (so->regions) mesh_set_regions(&m0, in, 0, m0.nseg);
    /* the length floor of the initial CDT, as ./mesh computes it from the same CDT */
    C->floor2 = mesh_rules_length_floor2(m0.xy, m0.nv, m0.tv, m0.nt);
    double dom_area = mesh_area(&m0);
    double mag, blen = mesh_boundary_length(&m0, &mag);
    C->area_budget = mesh_rules_area_drift(dom_area, mag, blen) / C->size;
    C->unresolved_budget = mesh_rules_unresolved_budget(m0.ninput);
    if (so->max_area > 0 && C->size > 1) {
        /* the bound in the working units of the coordinates (pslg_check's scaling), as areas
         * are measured here */
        double bound = pslg_scaled_area(m0.scale_exp, so->max_area);
        double a0 = fmax(dom_area / (PRE_TRIS_PER_RANK * C->size), PRE_COARSEN * bound);
        mesh_quality q;
        memset(&q, 0, sizeof q);
        q.min_angle = 0;                                /* the area alone: see above */
        q.max_area = pslg_input_area(m0.scale_exp, a0); /* mesh_quality takes the input's units */
        q.max_steiner = so->max_steiner;
        q.offcenter = so->offcenter;
        band B = {0};
        if (!so->regions && d->g.nsegs > d->nboundary) { /* regions: treg is the input's */
            band_build(&B, d, a0, dom_area);
            q.max_area = pslg_input_area(m0.scale_exp, PRE_FAR * a0);
            mesh_set_size_rule(&m0, band_rule, &B);
        }
        mesh_set_quality(&m0, &q);
        mesh_refine(&m0);
        if (B.sum) {
            mesh_set_size_rule(&m0, NULL, NULL);
            free(B.sum);
        }
        C->res.pre_tris = m0.nlive;
    }
    int32_t *own = mesh_xrealloc(NULL, (size_t)m0.nt + 1, sizeof(int32_t));
    owners(C, &m0, d, own);
    pbw_ghost_sides(C, &m0, own);
    /* input data: the CDT's own arrays (it becomes C->M below, which owns and frees them) */
    C->ninput = m0.ninput;
    C->nseg = m0.nseg;
    C->seg = m0.seg;
    C->pieces = mesh_xcalloc((size_t)m0.nseg + 1, sizeof *C->pieces);
    C->smarker = m0.smarker;
    C->in_vmarker = m0.in_vmarker;
    C->inc_off = m0.inc_off;
    C->inc_seg = m0.inc_seg;
    C->corner = m0.corner;
    C->has_corners = m0.has_corners;
    C->I.ninput = C->ninput;
    C->I.seg = C->seg;
    C->I.inc_off = C->inc_off;
    C->I.inc_seg = C->inc_seg;
    C->I.corner = C->has_corners ? C->corner : NULL;
    C->I.siface = NULL; /* PBW has no artificial segments */
    if (so->regions) {
        C->nregion = in->nregions;
        C->reg_attr = mesh_xrealloc(NULL, (size_t)in->nregions + 1, sizeof(double));
        C->reg_area = mesh_xrealloc(NULL, (size_t)in->nregions + 1, sizeof(double));
        for (int32_t i = 0; i < in->nregions; i++) {
            C->reg_attr[i] = in->regions[4 * i + 2];
            double a = in->regions[4 * i + 3]; /* scaled by pslg_check, like the coordinates */
            C->reg_area[i] = so->region_area && a > 0 ? a : 0;
        }
    }
    /* the CDT becomes this rank's store: every rank numbers the triangles alike (the same CDT),
     * so slot t is triangle t's name on its owner, and an initial vertex's id is its slot.
     * Edges to another rank's triangles get their record (reference and ghost apex); then the
     * other ranks' triangles go to the free list and their subsegment records are dropped. */
    mesh_refine_free(&m0);
    C->M = m0;
    mesh *M = &C->M;
    C->ninit = M->nv;
    C->vgcap = M->vcap;
    C->vgid = mesh_xrealloc(NULL, (size_t)C->vgcap + 1, sizeof(int64_t));
    for (int32_t v = 0; v < M->nv; v++)
        C->vgid[v] = v;
    pbw_vt_rehash(C, 2048);
    for (int32_t t = 0; t < M->nt; t++) {
        /* a free slot of the CDT (own 0) is nobody's: its tn[3t] is the free list's link */
        if (own[t] != C->rank || !mesh_tri_alive(M, t)) continue;
        M->tf[t] &= (uint8_t) ~(MESH_MARK | MESH_QUEUED | MESH_FENCE); /* role none */
        for (int j = 0; j < 3; j++) {
            size_t e = 3 * (size_t)t + (size_t)j;
            int32_t nb = M->tn[e];
            if (nb < 0 || own[nb / 3] == C->rank) continue;
            /* ghost: the remote neighbour's apex (an initial vertex: id = slot) */
            int32_t apex = M->tv[mesh_edge_prev(nb)];
            M->tn[e] = -1;
            pbw_tn_set(C, e, mkref(own[nb / 3], nb / 3));
            pbw_gx_set(C, e, apex);
        }
        C->nlive++;
    }
    /* the subsegment records this rank's constraint edges use; the others go */
    uint8_t *used = mesh_xcalloc((size_t)M->nss + 1, 1);
    for (int32_t t = 0; t < M->nt; t++)
        for (int j = 0; j < 3 && own[t] == C->rank; j++)
            if (mesh_edge_constrained(M, 3 * t + j)) {
                int32_t r = mesh_ss_find_pair(M, M->tv[3 * t + j], M->tv[3 * t + (j + 1) % 3]);
                if (r < 0) MESH_BUG("constraint edge %d without its subsegment record", 3 * t + j);
                used[r] = 1;
            }
    for (int32_t r = 0; r < M->nss; r++)
        if (!used[r] && M->ss[r].level != -2) mesh_ss_del(M, r);
    free(used);
    for (int32_t t = 0; t < M->nt; t++)
        if (own[t] != C->rank && mesh_tri_alive(M, t)) mesh_tri_kill(M, t);
    mesh_rebuild_vtri(M);
    free(own);
    /* initial work: every bad triangle, every encroached subsegment */
    for (int32_t t = 0; t < C->M.nt; t++)
        if (alive(C, t)) pbw_check_new_triangle(C, t);
    return 0;
}

/* The end check of the bounds for live slot t (as mesh_count_unmet): outside them and not
 * forced by the input (a corner vertex, or the shared forced-angle rule on its shortest edge)
 * counts in C->res.unmet, forced in C->res.forced; its rank boundary edges in the statistics
 * C->res.iface_edges and iface_len.  Called by pbw_to_flat's pass over the triangles. */
static void tally(pbw_ctx *C, int32_t t) {
    const int32_t *tv = C->M.tv + 3 * (size_t)t;
    for (int j = 0; j < 3; j++) { /* the rank boundary (a statistic: its length) */
        if (C->M.tn[3 * (size_t)t + (size_t)j] > -2) continue; /* local or none: no record */
        C->res.iface_edges++;
        C->res.iface_len += sqrt(geom_dist2(VX(C, tv[j]), VX(C, tv[(j + 1) % 3])));
    }
    int sh = 0, why = pbw_quality(C, t, NULL, &sh);
    if (!why) return;
    if (why == MESH_BAD_ANGLE &&
        (pbw_is_corner_gid(C, C->vgid[tv[0]]) || pbw_is_corner_gid(C, C->vgid[tv[1]]) ||
         pbw_is_corner_gid(C, C->vgid[tv[2]]) || pbw_edge_forced(C, tv[sh], tv[(sh + 1) % 3]))) {
        C->res.forced++;
        return;
    }
    C->res.unmet++;
}

/* Test-only fault (env PBW_TEST_BREAK_IFACE=R): rank R loses the first triangle it owns that
 * has a neighbour on another rank, as if a commit had been lost at a rank boundary, so the
 * result no longer matches across that boundary.  The always-on end check (par_output's
 * interface check) must then fail every rank; tests/t_pbw.sh shows it does. */
void pbw_test_fault(pbw_ctx *C) {
    const char *e = getenv("PBW_TEST_BREAK_IFACE");
    if (!e || !*e || atoi(e) != C->rank) return;
    for (int32_t t = 0; t < C->M.nt; t++) {
        if (!alive(C, t) || LK(C, t) >= 0) continue;
        for (int j = 0; j < 3; j++) {
            int64_t n = TN(C, 3 * (size_t)t + (size_t)j);
            if (n != NOREF && ref_rank(n) != C->rank) {
                /* its local neighbours lose their link too (a live slot links only live
                 * slots: pbw_to_flat's open edges rely on it) */
                for (int i = 0; i < 3; i++) {
                    int32_t y = C->M.tn[3 * (size_t)t + (size_t)i];
                    if (y >= 0) C->M.tn[y] = -1;
                }
                pbw_slot_free(C, t);
                C->nlive--;
                return;
            }
        }
    }
}

/* This rank's triangles as a mesh_flat (local numbering of the vertices they use).  Nothing is
 * locked at the end, so every live slot is written, and a live slot's local links name live
 * slots (pbw_store.c: an involution on live slots; a tombstone's forward links point one way):
 * an edge is open iff it has no local link, and no neighbour is looked at. */

int pbw_to_flat(pbw_ctx *C, mesh_flat *f, uint8_t **topen) {
    memset(f, 0, sizeof *f);
    int32_t *map = mesh_xrealloc(NULL, (size_t)C->M.nv + 1, sizeof(int32_t));
    for (int32_t v = 0; v < C->M.nv; v++)
        map[v] = -1;
    /* pass 1, on the whole store: the vertices used, the open edges, the subsegments; a slot
     * not written is marked dead (tv[3t] = -1) for pass 2 */
    int32_t nv = 0, ntri = 0, nseg = 0, segcap = 0;
    int32_t *sv = NULL; /* 3 per subsegment: vertex slots a, b and the segment */
    uint8_t *open = topen ? mesh_xrealloc(NULL, (size_t)C->nlive + 1, 1) : NULL;
    for (int32_t t = 0; t < C->M.nt; t++) {
        if (!alive(C, t)) {
            C->M.tv[3 * (size_t)t] = -1;
            continue;
        }
        tally(C, t);
        if (open) {
            if (ntri > C->nlive) MESH_BUG("more triangles written than live");
            uint8_t o = 0;
            for (int j = 0; j < 3; j++) { /* open: no local neighbour (boundary, another rank) */
                int32_t y = C->M.tn[3 * (size_t)t + (size_t)j];
                MESH_ASSERT(y < 0 || alive(C, y / 3));
                o |= (uint8_t)((y < 0) << j);
            }
            open[ntri] = o;
        }
        unsigned cons = C->M.tf[t] & 7u; /* its constraint edges */
        for (int j = 0; j < 3; j++) {
            size_t e = 3 * (size_t)t + (size_t)j;
            int32_t v = C->M.tv[e];
            if (map[v] < 0) map[v] = nv++;
            const mesh_subseg *ss = (cons >> j) & 1u ? SSEG(C, e) : NULL;
            if (ss) {
                MESH_GROW(sv, 3 * (nseg + 1), segcap);
                sv[3 * nseg] = v;
                sv[3 * nseg + 1] = C->M.tv[3 * (size_t)t + (size_t)((j + 1) % 3)];
                sv[3 * nseg + 2] = ss->seg;
                nseg++;
            }
        }
        ntri++;
    }
    /* what only refinement needed goes before the flat copy is made (a lower peak) */
    free(C->M.tn), free(C->M.tf), free(C->con), free(C->lkk), free(C->lkv);
    C->M.tn = NULL, C->M.tf = NULL, C->con = NULL, C->lkk = NULL, C->lkv = NULL;
    pbw_queue_free(C);
    free(C->M.ss), free(C->M.hpair), free(C->M.hname), free(C->M.cav), free(C->M.bnd);
    free(C->M.stk), free(C->M.newt);
    C->M.ss = NULL, C->M.hpair = C->M.hname = NULL, C->M.cav = NULL, C->M.bnd = NULL;
    C->M.stk = NULL, C->M.newt = NULL;
    f->nverts = nv;
    f->xy = mesh_xrealloc(NULL, 2 * ((size_t)nv + 1), sizeof(double));
    f->vmarker = mesh_xrealloc(NULL, (size_t)nv + 1, sizeof(int32_t));
    for (int32_t v = 0; v < C->M.nv; v++) {
        int32_t o = map[v];
        if (o < 0) continue;
        f->xy[2 * o] = C->M.xy[2 * v];
        f->xy[2 * o + 1] = C->M.xy[2 * v + 1];
        int64_t g = C->vgid[v];
        f->vmarker[o] = (g >= 0 && g < C->ninput) ? C->in_vmarker[g]
                        : C->M.vseg[v] >= 0       ? C->smarker[C->M.vseg[v]]
                                                  : 0;
    }
    f->nsegs = nseg;
    f->seg = mesh_xrealloc(NULL, 2 * ((size_t)nseg + 1), sizeof(int32_t));
    f->smarker = mesh_xrealloc(NULL, (size_t)nseg + 1, sizeof(int32_t));
    f->sinterface = mesh_xrealloc(NULL, (size_t)nseg + 1, sizeof(int32_t));
    for (int32_t i = 0; i < nseg; i++) {
        f->seg[2 * (size_t)i] = map[sv[3 * i]];
        f->seg[2 * (size_t)i + 1] = map[sv[3 * i + 1]];
        f->smarker[i] = C->smarker[sv[3 * i + 2]];
        f->sinterface[i] = 0;
    }
    free(sv);
    /* the vertex table has been copied out */
    free(C->M.xy), free(C->vgid), free(C->M.vseg), free(C->M.vtri), free(C->own), free(C->vh);
    C->M.xy = NULL, C->vgid = NULL, C->M.vseg = NULL, C->M.vtri = NULL, C->own = NULL;
    C->vh = NULL;
    /* pass 2: the triangles, in the same (slot) order as the open mask, renumbered in place:
     * the store's vertex array becomes the flat's (live slots moved to the front) */
    f->ntris = ntri;
    int32_t w = 0;
    for (int32_t t = 0; t < C->M.nt; t++) {
        if (C->M.tv[3 * (size_t)t] < 0) continue;
        if (C->M.treg) C->M.treg[w] = C->M.treg[t];
        for (int j = 0; j < 3; j++)
            C->M.tv[3 * (size_t)w + (size_t)j] = map[C->M.tv[3 * (size_t)t + (size_t)j]];
        w++;
    }
    if (w != ntri) MESH_BUG("%d triangles renumbered, %d written", w, ntri);
    f->tri = mesh_xrealloc(C->M.tv, 3 * ((size_t)ntri + 1), sizeof(int32_t));
    C->M.tv = NULL;
    C->M.nt = 0;
    f->trank = mesh_xrealloc(NULL, (size_t)ntri + 1, sizeof(int32_t));
    if (C->M.treg) f->tattr = mesh_xrealloc(NULL, (size_t)ntri + 1, sizeof(double));
    for (int32_t i = 0; i < ntri; i++) {
        f->trank[i] = C->rank;
        if (f->tattr) f->tattr[i] = C->M.treg[i] >= 0 ? C->reg_attr[C->M.treg[i]] : 0;
    }
    if (topen) *topen = open;
    free(map);
    return 0;
}

void pbw_ctx_free(pbw_ctx *C) {
    mesh_free(&C->M);
    free(C->vgid), free(C->vh), free(C->own);
    free(C->con), free(C->lkk), free(C->lkv);
    free(C->reg_attr), free(C->reg_area);
    free(C->pieces);
    free(C->gside);
    free(C->gen);
    pbw_queue_free(C);
    pbw_iv_free(&C->splitq), pbw_iv_free(&C->retryq), pbw_iv_free(&C->deferred),
        pbw_iv_free(&C->slotq), pbw_iv_free(&C->phase2);
    for (int32_t i = 0; i < C->nhd; i++)
        free(C->hd[i].slots);
    free(C->hd);
    free(C->wt);
    pbw_cav_pool_free(C);
    for (int32_t i = 0; i < C->npk; i++)
        pbw_cav_free(C->pk[i]);
    free(C->pk);
    free(C->dy);
    if (C->dbg_f) fclose(C->dbg_f);
    free(C);
}

size_t pbw_mesh_bytes(pbw_ctx *C) {
    size_t b = mesh_memory_bytes(&C->M); /* the kernel's arrays (and its cavity scratch) */
    b += (size_t)C->lkcap * 8;           /* the locks */
    b += (size_t)C->concap * sizeof(pbw_con);
    b += (size_t)C->vgcap * 8 + (size_t)C->vhcap * 4;
    b += (size_t)C->owncap * sizeof(int32_t);
    b += pbw_queue_bytes(C);
    return b;
}
