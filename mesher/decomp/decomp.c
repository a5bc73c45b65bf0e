/* pcdm_decomp: automatic, balanced, well-spaced domain decomposition for PCDM.
 *
 * What: the preprocessing step of TR-97-17 section 3 ("the boundaries between processors must
 * be created during a preprocessing step"), which the paper did by hand and lists as future
 * work.  It augments the input PSLG with artificial constraint segments (cuts) that split the
 * domain into K subdomains, and assigns the subdomains to P ranks.
 *
 * Algorithm: recursive coordinate bisection on faces.  A region is one face of the domain
 * (outer ring + hole rings, stored as directed edges with the face on their left).  To split a
 * region holding subdomains [i0, i1) into [i0, mid) and [mid, i1), mid = i0 + floor(k/2), we
 * try vertical (x = c) and horizontal (y = c) lines.  For each axis the exact area of the
 * region on the low side of the line, A(c) = sum of the clipped edges' integral of (s - c) da
 * (Green's theorem; the cut itself contributes nothing), is inverted by bisection for the
 * target fraction, and candidate positions are scanned in the window of c where the balance
 * is within tolerance: evenly spaced ones, the region's vertices (a cut may end at a vertex,
 * e.g. out of a re-entrant corner or through opposite vertices of a polygonal hole), and the
 * points neighbours' cuts put on the region's boundary (continuing them gives "+" junctions).
 * The line meets the region in chords (maximal open intervals inside it); cutting along all
 * chords gives cells, and every two-colouring of the cells with both colours connected
 * through the unused chords is a candidate split (a cut through a hole uses two chords; a
 * chord that would orphan a sliver of a jagged boundary is left out).  A candidate is
 * admissible when both parts are within the balance tolerance of their targets, every used
 * chord meets the boundary at >= the hard angle, is at least 1% of sqrt(domain area) long,
 * and keeps 20% of min(subdomain size, local feature size) from other vertices and segments;
 * the best score wins (angle up to 60 degrees weighs most, then balance, spacing, compact
 * parts, short cuts).  The tolerance starts at an even share of the remaining budget per
 * level and grows while no candidate reaches 60 degrees; a split whose subtree then fails is
 * undone and redone with the smaller tolerance (bounded retries).  Each child inherits the
 * budget its parent's error leaves, so the final deviation is within balance_tol.  Ties go to
 * the first found, in a fixed order, so every rank computes the same bits.  Crossing points are
 * computed once from the crossed segment's original endpoints (rounded; the cut coordinate is
 * exact), so a cut ending on an earlier, perpendicular cut (a T-junction) lies exactly on it and
 * meets it at 90 degrees.  Finally the input segments and cuts are split at the new vertices, the
 * faces of the resulting arrangement are traced (half-edges sorted by angle), and each face is
 * matched to its subdomain through the subdomain's seed point; areas and left/right
 * subdomains of every segment come from that independent tracing.  pcdm_decomp_read_cuts
 * builds the same arrangement from user-given cuts instead.
 *
 * Invariants: regions are faces (one outer ring, vertex-disjoint rings, face on the left of
 * every edge); a new vertex lies strictly inside the segment it splits (to rounding, on an
 * input segment; exactly, on an earlier cut); no two vertices coincide; cuts are straight and
 * axis-parallel (auto mode); all choices are made by deterministic scans.
 */
#include "decomp/decomp.h"

#include "base/base.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CELLS 16     /* a line cutting a region into more cells is not considered */
#define SPACE_HARD 0.2   /* minimum clearance of a cut, relative to the local size (eval_cut) */
#define SPACE_GOOD 0.5   /* clearance beyond which spacing no longer improves the score */
#define SCAN_FINE 48     /* candidate positions per window, first pass */
#define SCAN_WIDE 160    /* candidate positions per window, second (wider) pass */
#define DEFAULT_TOL 0.08 /* default balance tolerance */
#define MIN_CUT_REL 0.01 /* shortest cut piece, times the square root of the domain area */
#define SNAP_REL 1e-6    /* cuts file: snapping distance relative to the bounding-box diagonal */
#define PI 3.14159265358979323846

/* ------------------------------------------------------------------------------------------ */
/* Messages                                                                                    */

#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static int
fail(char *err, size_t errlen, const char *fmt, ...) {
    if (err && errlen) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, errlen, fmt, ap);
        va_end(ap);
    }
    return -1;
}

/* ------------------------------------------------------------------------------------------ */
/* Directed edge sets (a face: the face lies to the left of every edge)                       */

typedef struct eset {
    int32_t n, cap;
    int32_t *u, *v, *par;
} eset;

static void eset_push(eset *e, int32_t u, int32_t v, int32_t par) {
    if (e->n == e->cap) {
        int32_t nc = e->cap ? 2 * e->cap : 16;
        e->u = mesh_xrealloc(e->u, (size_t)nc * sizeof *e->u, 1);
        e->v = mesh_xrealloc(e->v, (size_t)nc * sizeof *e->v, 1);
        e->par = mesh_xrealloc(e->par, (size_t)nc * sizeof *e->par, 1);
        e->cap = nc;
    }
    e->u[e->n] = u;
    e->v[e->n] = v;
    e->par[e->n] = par;
    e->n++;
}

static void eset_free(eset *e) {
    free(e->u);
    free(e->v);
    free(e->par);
    memset(e, 0, sizeof *e);
}

/* ------------------------------------------------------------------------------------------ */
/* Decomposition context                                                                      */

typedef struct ctx {
    const pslg *in;
    /* vertices: input first, then new ones */
    int32_t nv, capv;
    double *xy;
    int32_t *vpar;  /* parent (segment or cut) a new vertex lies on; -1 for input vertices */
    double *vscale; /* local feature size at a vertex: shortest incident input segment, or the
                     * length of the parent a new vertex lies on */
    int32_t *vnext; /* next new vertex on the same parent (list heads in phead), or -1 */
    /* parents: input segments [0, in->nsegs), then cuts */
    int32_t npar, capp;
    int32_t *pa, *pb; /* endpoint vertex ids */
    int32_t *paxis;   /* -1: input segment or free cut; 0: cut on x = const; 1: on y = const */
    int32_t *pline;   /* cuts file line (0 in auto mode) */
    double *plen;     /* length */
    int32_t *phead;   /* last new vertex put on the parent, or -1 */
    /* subdomains */
    int32_t nsub;
    double *target;
    int32_t *owner;
    eset *sub;       /* auto mode: the face of each subdomain */
    double *density; /* weight per unit area of each subdomain */
    /* isolated input vertices (degree 0): cuts keep away from them */
    int32_t nfree;
    int32_t *freev;
    double hard_angle, scale;
    double min_cut;            /* shortest admissible chord */
    double tol_level, tol_ref; /* balance tolerance of the current attempt; of the first */
    int attempt;               /* index of the current attempt */
    int retries;               /* undo-and-retry budget left (split_region) */
    char *err;
    size_t errlen;
} ctx;

static int32_t ctx_add_vertex(ctx *c, double x, double y, int32_t par) {
    if (c->nv == c->capv) {
        c->capv = c->capv ? 2 * c->capv : 64;
        c->xy = mesh_xrealloc(c->xy, 2 * (size_t)c->capv * sizeof *c->xy, 1);
        c->vpar = mesh_xrealloc(c->vpar, (size_t)c->capv * sizeof *c->vpar, 1);
        c->vscale = mesh_xrealloc(c->vscale, (size_t)c->capv * sizeof *c->vscale, 1);
        c->vnext = mesh_xrealloc(c->vnext, (size_t)c->capv * sizeof *c->vnext, 1);
    }
    c->vnext[c->nv] = -1;
    if (par >= 0) {
        c->vnext[c->nv] = c->phead[par];
        c->phead[par] = c->nv;
    }
    c->vscale[c->nv] = par >= 0 ? c->plen[par] : HUGE_VAL;
    c->xy[2 * c->nv] = x;
    c->xy[2 * c->nv + 1] = y;
    c->vpar[c->nv] = par;
    return c->nv++;
}

static int32_t ctx_add_parent(ctx *c, int32_t a, int32_t b, int32_t axis, int32_t line) {
    if (c->npar == c->capp) {
        c->capp = c->capp ? 2 * c->capp : 64;
        c->pa = mesh_xrealloc(c->pa, (size_t)c->capp * sizeof *c->pa, 1);
        c->pb = mesh_xrealloc(c->pb, (size_t)c->capp * sizeof *c->pb, 1);
        c->paxis = mesh_xrealloc(c->paxis, (size_t)c->capp * sizeof *c->paxis, 1);
        c->pline = mesh_xrealloc(c->pline, (size_t)c->capp * sizeof *c->pline, 1);
        c->plen = mesh_xrealloc(c->plen, (size_t)c->capp * sizeof *c->plen, 1);
        c->phead = mesh_xrealloc(c->phead, (size_t)c->capp * sizeof *c->phead, 1);
    }
    c->phead[c->npar] = -1;
    c->plen[c->npar] = a >= 0 && b >= 0
                           ? hypot(c->xy[2 * b] - c->xy[2 * a], c->xy[2 * b + 1] - c->xy[2 * a + 1])
                           : 0;
    c->pa[c->npar] = a;
    c->pb[c->npar] = b;
    c->paxis[c->npar] = axis;
    c->pline[c->npar] = line;
    return c->npar++;
}

static void ctx_init(ctx *c, const pslg *in, char *err, size_t errlen) {
    memset(c, 0, sizeof *c);
    c->in = in;
    c->err = err;
    c->errlen = errlen;
    for (int32_t i = 0; i < in->nverts; i++)
        ctx_add_vertex(c, in->xy[2 * i], in->xy[2 * i + 1], -1);
    for (int32_t s = 0; s < in->nsegs; s++) {
        int32_t p = ctx_add_parent(c, in->seg[2 * s], in->seg[2 * s + 1], -1, 0);
        for (int e = 0; e < 2; e++)
            c->vscale[in->seg[2 * s + e]] = fmin(c->vscale[in->seg[2 * s + e]], c->plen[p]);
    }
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int32_t i = 0; i < in->nverts; i++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], in->xy[2 * i + k]);
            hi[k] = fmax(hi[k], in->xy[2 * i + k]);
        }
    c->scale = in->nverts ? hypot(hi[0] - lo[0], hi[1] - lo[1]) : 0;
    int32_t *deg = mesh_xcalloc((size_t)in->nverts, sizeof *deg);
    for (int32_t s = 0; s < 2 * in->nsegs; s++)
        deg[in->seg[s]]++;
    c->freev = mesh_xmalloc((size_t)in->nverts * sizeof *c->freev, 1);
    for (int32_t i = 0; i < in->nverts; i++)
        if (!deg[i]) c->freev[c->nfree++] = i;
    free(deg);
}

static void ctx_free(ctx *c) {
    free(c->xy);
    free(c->vpar);
    free(c->vscale);
    free(c->vnext);
    free(c->phead);
    free(c->plen);
    free(c->pa);
    free(c->pb);
    free(c->paxis);
    free(c->pline);
    free(c->target);
    free(c->owner);
    if (c->sub)
        for (int32_t i = 0; i < c->nsub; i++)
            eset_free(&c->sub[i]);
    free(c->sub);
    free(c->density);
    free(c->freev);
    memset(c, 0, sizeof *c);
}

/* Coordinates of vertex id: global below nv0, else the tentative point tmp[id - nv0]. */
static const double *vxy(const ctx *c, int32_t nv0, const double *tmp, int32_t id) {
    return id < nv0 ? c->xy + 2 * (size_t)id : tmp + 2 * (size_t)(id - nv0);
}

/* ------------------------------------------------------------------------------------------ */
/* Small geometry helpers (rounded arithmetic; decisions are made with margins)               */

static double cross3(const double *a, const double *b, const double *p) {
    return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}

static double dist_point_seg(const double *p, const double *a, const double *b) {
    double dx = b[0] - a[0], dy = b[1] - a[1];
    double l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return hypot(p[0] - (a[0] + t * dx), p[1] - (a[1] + t * dy));
}

/* Distance between segments ab and cd (0 if they intersect). */
static double dist_seg_seg(const double *a, const double *b, const double *c, const double *d) {
    double o1 = cross3(a, b, c), o2 = cross3(a, b, d), o3 = cross3(c, d, a), o4 = cross3(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
        return 0;
    return fmin(fmin(dist_point_seg(a, c, d), dist_point_seg(b, c, d)),
                fmin(dist_point_seg(c, a, b), dist_point_seg(d, a, b)));
}

/* Angle in [0, 90] degrees between two undirected lines with directions d1, d2. */
static double line_angle(const double *d1, const double *d2) {
    double cr = fabs(d1[0] * d2[1] - d1[1] * d2[0]), dt = fabs(d1[0] * d2[0] + d1[1] * d2[1]);
    return atan2(cr, dt) * (180.0 / PI);
}

/* Crossing number test of p against the edges of e with ring[i] == r (all edges if ring is
 * NULL).  Half-open in y, so a scanline through a vertex counts it once. */
static int point_in_edges(const ctx *c, int32_t nv0, const double *tmp, const eset *e,
                          const int32_t *ring, int32_t r, const double *p) {
    int in = 0;
    for (int32_t i = 0; i < e->n; i++) {
        if (ring && ring[i] != r) continue;
        const double *a = vxy(c, nv0, tmp, e->u[i]), *b = vxy(c, nv0, tmp, e->v[i]);
        if ((a[1] > p[1]) != (b[1] > p[1])) {
            double x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if (p[0] < x) in = !in;
        }
    }
    return in;
}

static double eset_area(const ctx *c, int32_t nv0, const double *tmp, const eset *e) {
    double s = 0;
    for (int32_t i = 0; i < e->n; i++) {
        const double *a = vxy(c, nv0, tmp, e->u[i]), *b = vxy(c, nv0, tmp, e->v[i]);
        s += a[0] * b[1] - a[1] * b[0];
    }
    return 0.5 * s;
}

/* ------------------------------------------------------------------------------------------ */
/* Rings and faces of an edge set                                                             */

typedef struct pairi {
    int32_t key, idx;
} pairi;

static int cmp_pairi(const void *x, const void *y) {
    const pairi *a = x, *b = y;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->idx > b->idx) - (a->idx < b->idx);
}

/* Splits e into rings (each vertex must start exactly one edge and end exactly one) and groups
 * them into faces: rings of positive area are outer rings, each ring of negative area belongs
 * to the smallest outer ring containing it.  face[i] receives the face of edge i; returns the
 * number of faces, or -1 if e is not a proper set of vertex-disjoint rings. */
static int32_t faces_of(const ctx *c, int32_t nv0, const double *tmp, const eset *e,
                        int32_t *face) {
    int32_t n = e->n, result = -1;
    if (n < 3) return -1;
    pairi *byu = mesh_xmalloc((size_t)n * sizeof *byu, 1);
    int32_t *next = mesh_xmalloc((size_t)n * sizeof *next, 1),
            *ring = mesh_xmalloc((size_t)n * sizeof *ring, 1);
    for (int32_t i = 0; i < n; i++) {
        byu[i].key = e->u[i];
        byu[i].idx = i;
        ring[i] = -1;
    }
    qsort(byu, (size_t)n, sizeof *byu, cmp_pairi);
    int32_t nring = 0, *rfirst = NULL, *rface = NULL;
    double *rarea = NULL;
    for (int32_t i = 1; i < n; i++)
        if (byu[i].key == byu[i - 1].key) goto out;
    for (int32_t i = 0; i < n; i++) {
        int32_t lo = 0, hi = n - 1, want = e->v[i], at = -1;
        while (lo <= hi) {
            int32_t mid = lo + (hi - lo) / 2;
            if (byu[mid].key == want) {
                at = byu[mid].idx;
                break;
            }
            if (byu[mid].key < want)
                lo = mid + 1;
            else
                hi = mid - 1;
        }
        if (at < 0) goto out;
        next[i] = at;
    }
    rfirst = mesh_xmalloc((size_t)n * sizeof *rfirst, 1);
    for (int32_t i = 0; i < n; i++) {
        if (ring[i] >= 0) continue;
        int32_t j = i;
        do {
            if (ring[j] >= 0) goto out; /* next is not a permutation */
            ring[j] = nring;
            j = next[j];
        } while (j != i);
        rfirst[nring++] = i;
    }
    rarea = mesh_xcalloc((size_t)nring, sizeof *rarea);
    rface = mesh_xmalloc((size_t)nring * sizeof *rface, 1);
    for (int32_t i = 0; i < n; i++) {
        const double *a = vxy(c, nv0, tmp, e->u[i]), *b = vxy(c, nv0, tmp, e->v[i]);
        rarea[ring[i]] += 0.5 * (a[0] * b[1] - a[1] * b[0]);
    }
    int32_t nface = 0;
    for (int32_t r = 0; r < nring; r++) {
        if (!(rarea[r] != 0)) goto out;
        rface[r] = rarea[r] > 0 ? nface++ : -1;
    }
    for (int32_t r = 0; r < nring; r++) {
        if (rarea[r] > 0) continue;
        const double *p = vxy(c, nv0, tmp, e->u[rfirst[r]]);
        int32_t best = -1;
        for (int32_t o = 0; o < nring; o++)
            if (rarea[o] > 0 && (best < 0 || rarea[o] < rarea[best]) &&
                point_in_edges(c, nv0, tmp, e, ring, o, p))
                best = o;
        if (best < 0) goto out;
        rface[r] = rface[best];
    }
    for (int32_t i = 0; i < n; i++)
        face[i] = rface[ring[i]];
    result = nface;
out:
    free(byu);
    free(next);
    free(ring);
    free(rfirst);
    free(rarea);
    free(rface);
    return result;
}

/* A point strictly inside the face e (global ids), as far from its edges as a few scanlines
 * find: midpoints of the inside intervals of 31 horizontal and 31 vertical lines. */
static void face_seed(const ctx *c, const eset *e, double out[2]) {
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int32_t i = 0; i < e->n; i++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], c->xy[2 * e->u[i] + k]);
            hi[k] = fmax(hi[k], c->xy[2 * e->u[i] + k]);
        }
    double best = -1, *xs = mesh_xmalloc((size_t)e->n * sizeof *xs, 1);
    out[0] = 0.5 * (lo[0] + hi[0]);
    out[1] = 0.5 * (lo[1] + hi[1]);
    for (int k = 0; k < 2; k++) /* k: coordinate held fixed by the scanline */
        for (int j = 1; j < 32; j++) {
            double t = lo[k] + (hi[k] - lo[k]) * j / 32.0;
            int32_t nx = 0;
            for (int32_t i = 0; i < e->n; i++) {
                const double *a = c->xy + 2 * e->u[i], *b = c->xy + 2 * e->v[i];
                if ((a[k] > t) != (b[k] > t))
                    xs[nx++] = a[1 - k] + (t - a[k]) * (b[1 - k] - a[1 - k]) / (b[k] - a[k]);
            }
            for (int32_t p = 1; p < nx; p++) /* insertion sort: nx is small */
                for (int32_t q = p; q > 0 && xs[q - 1] > xs[q]; q--) {
                    double tt = xs[q];
                    xs[q] = xs[q - 1];
                    xs[q - 1] = tt;
                }
            for (int32_t p = 0; p + 1 < nx; p += 2) {
                double pt[2];
                pt[k] = t;
                pt[1 - k] = 0.5 * (xs[p] + xs[p + 1]);
                double d = HUGE_VAL;
                for (int32_t i = 0; i < e->n; i++)
                    d = fmin(d, dist_point_seg(pt, c->xy + 2 * e->u[i], c->xy + 2 * e->v[i]));
                if (d > best && point_in_edges(c, c->nv, NULL, e, NULL, 0, pt)) {
                    best = d;
                    out[0] = pt[0];
                    out[1] = pt[1];
                }
            }
        }
    free(xs);
}

/* ------------------------------------------------------------------------------------------ */
/* Evaluating one cut line                                                                    */

typedef struct xing {
    int32_t edge;  /* edge of the region it crosses */
    double p[2];   /* crossing point */
    double a;      /* coordinate along the line */
    int enter;     /* 1: the edge goes from the low side to the high side */
    int32_t reuse; /* an existing vertex at exactly p on the same parent (made from the other
                    * side of an earlier cut), or -1 */
    int32_t vtx;   /* the line passes through this vertex of the region (edge ends there and
                    * edge2 starts there), or -1 */
    int32_t edge2;
} xing;

typedef struct cutev {
    int axis; /* 0: line x = cv; 1: line y = cv */
    double cv;
    int32_t nv0; /* tentative id of crossing k is nv0 + k */
    int32_t nx;
    xing *x;
    double *xp;  /* 2 * nx crossing coordinates, sorted along the line */
    int32_t nch; /* chord j runs from crossing 2j to crossing 2j + 1 */
    double *ang, *spc, *len;
    int32_t ncell;
    int32_t *chcell; /* 2 * nch: low-side cell, high-side cell */
    double area[MAX_CELLS];
    double box[MAX_CELLS][4]; /* bounding box of each cell: xmin, xmax, ymin, ymax */
    eset cell[MAX_CELLS];
} cutev;

static void cutev_free(cutev *ev) {
    free(ev->x);
    free(ev->xp);
    free(ev->ang);
    free(ev->spc);
    free(ev->len);
    free(ev->chcell);
    for (int i = 0; i < MAX_CELLS; i++)
        eset_free(&ev->cell[i]);
    memset(ev, 0, sizeof *ev);
}

/* Coordinate across (s) and along (a) the cut line; (s, a) is a rotation of (x, y). */
static double s_of(int axis, const double *p) {
    return axis == 0 ? p[0] : p[1];
}
static double a_of(int axis, const double *p) {
    return axis == 0 ? p[1] : -p[0];
}

/* Where the line s = cv crosses parent par, from the parent's original endpoints (taken in
 * lexicographic order, so the result does not depend on the segment's direction). */
static void cross_point(const ctx *c, int32_t par, int axis, double cv, double out[2]) {
    const double *A = c->xy + 2 * c->pa[par], *B = c->xy + 2 * c->pb[par];
    int s = axis, t = 1 - axis;
    if (c->paxis[par] >= 0) { /* an earlier axis-parallel cut: exact T-junction */
        out[s] = cv;
        out[t] = A[t];
        return;
    }
    if (B[0] < A[0] || (B[0] == A[0] && B[1] < A[1])) {
        const double *T = A;
        A = B;
        B = T;
    }
    out[s] = cv;
    out[t] = A[t] + (cv - A[s]) * ((B[t] - A[t]) / (B[s] - A[s]));
}

static int cmp_xing(const void *x, const void *y) {
    const xing *a = x, *b = y;
    return (a->a > b->a) - (a->a < b->a);
}

/* Tentative id of crossing k: the vertex itself for a crossing at a vertex, else nv0 + k. */
static int32_t xid(const cutev *ev, int32_t k) {
    return ev->x[k].vtx >= 0 ? ev->x[k].vtx : ev->nv0 + k;
}

static int side_of(int axis, const double *p, double cv) {
    double s = s_of(axis, p);
    return s < cv ? -1 : s > cv ? 1 : 0;
}

/* Angle in [0, 180] degrees between directions d1 and d2. */
static double ray_angle(const double *d1, const double *d2) {
    return atan2(fabs(d1[0] * d2[1] - d1[1] * d2[0]), d1[0] * d2[0] + d1[1] * d2[1]) * (180.0 / PI);
}

/* 1 if the ray from vertex v in direction r points strictly into the region, whose boundary
 * arrives at v along din (from v back to the previous vertex) and leaves along dout. */
static int ray_inside(const double *din, const double *dout, const double *r) {
    double turn = dout[0] * din[1] - dout[1] * din[0];
    double c1 = dout[0] * r[1] - dout[1] * r[0], c2 = r[0] * din[1] - r[1] * din[0];
    if (turn > 0) return c1 > 0 && c2 > 0;                    /* convex corner */
    if (turn < 0) return !(c1 <= 0 && c2 <= 0);               /* reflex corner */
    return dout[0] * din[0] + dout[1] * din[1] < 0 && c1 > 0; /* straight */
}

/* Cuts region f along s = cv into cells and measures every chord.  A chord is a maximal open
 * interval of the line inside f; it ends where an edge crosses the line (a new vertex) or at
 * a vertex of f on the line (nothing is split there; edges of f may lie along the line, e.g.
 * a cut continuing an edge out of a re-entrant corner).  h is the expected subdomain size.
 * Returns 0, or -1 if the line is unusable (misses f, or f touches it from inside at a
 * vertex, degenerate crossings, too many cells). */
static int eval_cut(const ctx *c, const eset *f, int axis, double cv, double h, const int32_t *nb,
                    int32_t nnb, cutev *ev) {
    memset(ev, 0, sizeof *ev);
    ev->axis = axis;
    ev->cv = cv;
    ev->nv0 = c->nv;
    int32_t n = f->n;
    ev->x = mesh_xmalloc((size_t)n * sizeof *ev->x, 1);
    double up[2] = {axis == 0 ? 0 : -1, axis == 0 ? 1 : 0}; /* direction of increasing a */
    double down[2] = {-up[0], -up[1]};
    for (int32_t i = 0; i < n; i++) {
        const double *u = c->xy + 2 * f->u[i], *v = c->xy + 2 * f->v[i];
        int cu = side_of(axis, u, cv), cw = side_of(axis, v, cv);
        xing *x = &ev->x[ev->nx];
        x->edge = i;
        x->edge2 = -1;
        x->vtx = -1;
        x->reuse = -1;
        x->enter = cu < 0;
        if (cw == 0) { /* vertex v on the line: does a chord start or end there? */
            int32_t j = -1;
            for (int32_t k = 0; k < n && j < 0; k++)
                if (f->u[k] == f->v[i]) j = k;
            if (j < 0) return -1;
            const double *w = c->xy + 2 * f->v[j];
            double din[2] = {u[0] - v[0], u[1] - v[1]}, dout[2] = {w[0] - v[0], w[1] - v[1]};
            int in_up = ray_inside(din, dout, up), in_down = ray_inside(din, dout, down);
            if (in_up && in_down) return -1; /* f touches the line from inside */
            if (!in_up && !in_down) continue;
            x->enter = in_up;
            x->edge2 = j;
            x->vtx = f->v[i];
            x->p[0] = v[0];
            x->p[1] = v[1];
        } else if (cu == 0 || cu == cw) {
            continue;
        } else {
            if (c->paxis[f->par[i]] == axis) return -1;
            cross_point(c, f->par[i], axis, cv, x->p);
            int t = 1 - axis; /* the crossing must lie within the piece it splits */
            if (!(x->p[t] >= fmin(u[t], v[t]) && x->p[t] <= fmax(u[t], v[t]))) return -1;
            for (int32_t k = 0; k < nnb; k++)
                if (c->vpar[nb[k]] == f->par[i] && c->xy[2 * nb[k]] == x->p[0] &&
                    c->xy[2 * nb[k] + 1] == x->p[1])
                    x->reuse = nb[k];
        }
        x->a = a_of(axis, x->p);
        ev->nx++;
    }
    if (ev->nx == 0 || ev->nx % 2) return -1;
    qsort(ev->x, (size_t)ev->nx, sizeof *ev->x, cmp_xing);
    for (int32_t k = 0; k < ev->nx; k++) {
        if (k > 0 && !(ev->x[k].a > ev->x[k - 1].a)) return -1;
        if (ev->x[k].enter != !(k % 2)) return -1;
    }
    ev->nch = ev->nx / 2;
    ev->xp = mesh_xmalloc(2 * (size_t)ev->nx * sizeof *ev->xp, 1);
    int32_t *xe = mesh_xmalloc((size_t)n * sizeof *xe, 1);
    for (int32_t i = 0; i < n; i++)
        xe[i] = -1;
    for (int32_t k = 0; k < ev->nx; k++) {
        ev->xp[2 * k] = ev->x[k].p[0];
        ev->xp[2 * k + 1] = ev->x[k].p[1];
        if (ev->x[k].vtx < 0) xe[ev->x[k].edge] = k;
    }
    /* split into the low side and the high side */
    eset side[2] = {{0}};
    for (int32_t i = 0; i < n; i++) {
        const double *u = c->xy + 2 * f->u[i], *v = c->xy + 2 * f->v[i];
        int cu = side_of(axis, u, cv);
        if (cu == 0) cu = side_of(axis, v, cv);
        if (cu == 0) /* along the line: f lies on its left, i.e. low side if going up */
            cu = a_of(axis, v) > a_of(axis, u) ? -1 : 1;
        int su = cu > 0;
        if (xe[i] < 0) {
            eset_push(&side[su], f->u[i], f->v[i], f->par[i]);
        } else {
            int32_t w = ev->nv0 + xe[i];
            eset_push(&side[su], f->u[i], w, f->par[i]);
            eset_push(&side[!su], w, f->v[i], f->par[i]);
        }
    }
    for (int32_t j = 0; j < ev->nch; j++) {
        int32_t p = xid(ev, 2 * j), q = xid(ev, 2 * j + 1);
        eset_push(&side[0], p, q, -2 - j);
        eset_push(&side[1], q, p, -2 - j);
    }
    free(xe);
    int rc = -1;
    int32_t *fc[2] = {NULL, NULL}, nf[2];
    for (int k = 0; k < 2; k++) {
        fc[k] = mesh_xmalloc((size_t)side[k].n * sizeof *fc[k], 1);
        nf[k] = faces_of(c, ev->nv0, ev->xp, &side[k], fc[k]);
        if (nf[k] < 1) goto out;
    }
    if (nf[0] + nf[1] > MAX_CELLS) goto out;
    ev->ncell = nf[0] + nf[1];
    ev->chcell = mesh_xmalloc(2 * (size_t)ev->nch * sizeof *ev->chcell, 1);
    for (int k = 0; k < 2; k++)
        for (int32_t i = 0; i < side[k].n; i++) {
            int32_t cell = fc[k][i] + (k ? nf[0] : 0);
            eset_push(&ev->cell[cell], side[k].u[i], side[k].v[i], side[k].par[i]);
            if (side[k].par[i] <= -2) ev->chcell[2 * (-2 - side[k].par[i]) + k] = cell;
        }
    for (int32_t k = 0; k < ev->ncell; k++) {
        ev->area[k] = eset_area(c, ev->nv0, ev->xp, &ev->cell[k]);
        double *b = ev->box[k];
        b[0] = b[2] = HUGE_VAL;
        b[1] = b[3] = -HUGE_VAL;
        for (int32_t i = 0; i < ev->cell[k].n; i++) {
            const double *p = vxy(c, ev->nv0, ev->xp, ev->cell[k].u[i]);
            b[0] = fmin(b[0], p[0]);
            b[1] = fmax(b[1], p[0]);
            b[2] = fmin(b[2], p[1]);
            b[3] = fmax(b[3], p[1]);
        }
    }
    /* chord measures: length, angles with the segments met, clearance */
    ev->ang = mesh_xmalloc((size_t)ev->nch * sizeof *ev->ang, 1);
    ev->spc = mesh_xmalloc((size_t)ev->nch * sizeof *ev->spc, 1);
    ev->len = mesh_xmalloc((size_t)ev->nch * sizeof *ev->len, 1);
    for (int32_t j = 0; j < ev->nch; j++) {
        const xing *xp = &ev->x[2 * j], *xq = &ev->x[2 * j + 1];
        ev->len[j] = fabs(xq->a - xp->a);
        double ang = 180;
        for (int e = 0; e < 2; e++) {
            const xing *x = e ? xq : xp;
            const double *ray = e ? down : up; /* into the region */
            if (x->vtx >= 0) {
                const double *o = c->xy + 2 * x->vtx, *a = c->xy + 2 * f->u[x->edge],
                             *b = c->xy + 2 * f->v[x->edge2];
                double da[2] = {a[0] - o[0], a[1] - o[1]}, db[2] = {b[0] - o[0], b[1] - o[1]};
                ang = fmin(ang, fmin(ray_angle(ray, da), ray_angle(ray, db)));
            } else {
                int32_t par = f->par[x->edge];
                const double *A = c->xy + 2 * c->pa[par], *B = c->xy + 2 * c->pb[par];
                double d[2] = {B[0] - A[0], B[1] - A[1]};
                ang = fmin(ang, line_angle(ray, d));
            }
        }
        ev->ang[j] = ang;
        /* clearance, each distance relative to min(h, the obstacle's local size) */
        double spc = HUGE_VAL;
        for (int32_t i = 0; i < n; i++) {
            const double *u = c->xy + 2 * f->u[i], *v = c->xy + 2 * f->v[i];
            double le = fmin(h, c->plen[f->par[i]]);
            if (f->u[i] != xp->vtx && f->u[i] != xq->vtx)
                spc = fmin(spc, dist_point_seg(u, xp->p, xq->p) / fmin(h, c->vscale[f->u[i]]));
            if (i != xp->edge && i != xp->edge2) spc = fmin(spc, dist_point_seg(xp->p, u, v) / le);
            if (i != xq->edge && i != xq->edge2) spc = fmin(spc, dist_point_seg(xq->p, u, v) / le);
        }
        for (int32_t i = 0; i < c->nfree; i++)
            spc = fmin(spc, dist_point_seg(c->xy + 2 * c->freev[i], xp->p, xq->p) / h);
        /* vertices put on the crossed parents by neighbours' cuts: half as strict, since a
         * neighbour's T-junction only shortens one piece of a cut, which continuing that cut
         * (an exact "+" junction) avoids altogether */
        for (int e = 0; e < 2; e++) {
            const xing *x = e ? xq : xp;
            if (x->vtx >= 0) continue;
            int32_t par = f->par[x->edge];
            for (int32_t k = 0; k < nnb; k++)
                if (c->vpar[nb[k]] == par && nb[k] != x->reuse)
                    spc = fmin(spc, dist_point_seg(c->xy + 2 * nb[k], xp->p, xq->p) /
                                        (0.5 * fmin(h, c->plen[par])));
        }
        ev->spc[j] = spc;
    }
    rc = 0;
out:
    for (int k = 0; k < 2; k++) {
        free(fc[k]);
        eset_free(&side[k]);
    }
    return rc;
}

/* Area of region f on the low side of s = cv: sum over the clipped edges of the integral of
 * (s - cv) da, exact up to rounding (the closing pieces on the line contribute zero). */
static double low_area(const ctx *c, const eset *f, int axis, double cv) {
    double sum = 0;
    for (int32_t i = 0; i < f->n; i++) {
        const double *u = c->xy + 2 * f->u[i], *v = c->xy + 2 * f->v[i];
        double s1 = s_of(axis, u), a1 = a_of(axis, u), s2 = s_of(axis, v), a2 = a_of(axis, v);
        int in1 = s1 < cv, in2 = s2 < cv;
        if (in1 && in2) {
            sum += (0.5 * (s1 + s2) - cv) * (a2 - a1);
        } else if (in1 != in2) {
            double ac = a1 + (cv - s1) * (a2 - a1) / (s2 - s1);
            if (in1)
                sum += (0.5 * (s1 + cv) - cv) * (ac - a1);
            else
                sum += (0.5 * (cv + s2) - cv) * (a2 - ac);
        }
    }
    return sum;
}

/* The c in [lo, hi] with low_area(c) = frac * total (bisection; deterministic). */
static double invert_area(const ctx *c, const eset *f, int axis, double lo, double hi, double frac,
                          double total) {
    double want = frac * total;
    for (int it = 0; it < 200; it++) {
        double mid = lo + 0.5 * (hi - lo);
        if (!(mid > lo && mid < hi)) break;
        if (low_area(c, f, axis, mid) < want)
            lo = mid;
        else
            hi = mid;
    }
    return lo + 0.5 * (hi - lo);
}

/* ------------------------------------------------------------------------------------------ */
/* Choosing and applying a split                                                              */

/* What the scan saw, for the error message when nothing is admissible. */
typedef struct scanstat {
    long lines, unusable, splits;
    double best_err, best_ang, best_spc; /* each over splits admissible in the other two */
} scanstat;

typedef struct cand {
    int valid, axis, a_first, attempt;
    double cv, score, err, ang, spc, fa;
    uint32_t mask; /* cells in group A (the group holding cell 0) */
} cand;

static int connected(uint32_t set, const uint32_t *adj) {
    if (!set) return 0;
    uint32_t reach = set & (~set + 1), prev = 0;
    while (reach != prev) {
        prev = reach;
        for (int i = 0; i < MAX_CELLS; i++)
            if (reach & (1u << i)) reach |= adj[i] & set;
    }
    return reach == set;
}

/* Scores every admissible split of ev; keeps the best in *best. */
static void score_splits(const ctx *c, const cutev *ev, double f1, double rarea, cand *best,
                         scanstat *st) {
    uint32_t full = (ev->ncell >= 32) ? 0xffffffffu : ((1u << ev->ncell) - 1);
    uint32_t adj[MAX_CELLS] = {0};
    double total = 0;
    for (int32_t k = 0; k < ev->ncell; k++)
        total += ev->area[k];
    for (int32_t j = 0; j < ev->nch; j++) {
        adj[ev->chcell[2 * j]] |= 1u << ev->chcell[2 * j + 1];
        adj[ev->chcell[2 * j + 1]] |= 1u << ev->chcell[2 * j];
    }
    for (uint32_t mask = 1; mask < full; mask += 2) { /* cell 0 always in A */
        uint32_t bmask = full & ~mask;
        if (!connected(mask, adj) || !connected(bmask, adj)) continue;
        double wa = 0, ang = 180, spc = HUGE_VAL, len = 0, minlen = HUGE_VAL;
        double gb[2][4] = {{HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL},
                           {HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL}};
        for (int32_t k = 0; k < ev->ncell; k++) {
            int g = !(mask & (1u << k));
            if (!g) wa += ev->area[k];
            for (int e = 0; e < 4; e += 2) {
                gb[g][e] = fmin(gb[g][e], ev->box[k][e]);
                gb[g][e + 1] = fmax(gb[g][e + 1], ev->box[k][e + 1]);
            }
        }
        double aspect = 1; /* worst bounding-box aspect ratio of the two parts */
        for (int g = 0; g < 2; g++) {
            double wx = gb[g][1] - gb[g][0], wy = gb[g][3] - gb[g][2];
            aspect = fmax(aspect, fmax(wx, wy) / fmin(wx, wy));
        }
        for (int32_t j = 0; j < ev->nch; j++) {
            int ina = !!(mask & (1u << ev->chcell[2 * j]));
            int inb = !!(mask & (1u << ev->chcell[2 * j + 1]));
            if (ina == inb) continue;
            ang = fmin(ang, ev->ang[j]);
            spc = fmin(spc, ev->spc[j]);
            len += ev->len[j];
            minlen = fmin(minlen, ev->len[j]);
        }
        double fa = wa / total;
        st->splits++;
        double err = HUGE_VAL;
        for (int a_first = 1; a_first >= 0; a_first--) {
            double ta = a_first ? f1 : 1 - f1;
            err = fmin(err, fmax(fabs(fa / ta - 1), fabs((1 - fa) / (1 - ta) - 1)));
        }
        int ok_a = ang >= c->hard_angle, ok_b = err <= c->tol_level;
        int ok_s = spc >= SPACE_HARD && minlen >= c->min_cut;
        if (ok_a && ok_s) st->best_err = fmin(st->best_err, err);
        if (ok_s && ok_b) st->best_ang = fmax(st->best_ang, ang);
        if (ok_a && ok_b) st->best_spc = fmax(st->best_spc, spc);
        if (!ok_a || !ok_s) continue;
        for (int a_first = 1; a_first >= 0; a_first--) {
            double ta = a_first ? f1 : 1 - f1;
            err = fmax(fabs(fa / ta - 1), fabs((1 - fa) / (1 - ta) - 1));
            if (!(err <= c->tol_level)) continue;
            double score = 6.0 * fmin(ang, 60) / 60 + 0.5 * fmax(0, fmin(ang, 90) - 60) / 30 +
                           2.0 * fmin(spc, SPACE_GOOD) / SPACE_GOOD + 3.0 * (1 - err / c->tol_ref) -
                           0.5 * len / sqrt(rarea) - 0.5 * log2(aspect);
            if (!best->valid || score > best->score) {
                best->valid = 1;
                best->axis = ev->axis;
                best->cv = ev->cv;
                best->mask = mask;
                best->a_first = a_first;
                best->score = score;
                best->err = err;
                best->ang = ang;
                best->spc = spc;
                best->fa = fa;
                best->attempt = c->attempt;
            }
        }
    }
}

/* Applies split (ev, mask): creates the vertices and cuts of the used chords, and returns the
 * two groups as faces with global ids.  Returns 0, or -1 if a group is not a single face. */
static int apply_split(ctx *c, const eset *f, const cutev *ev, uint32_t mask, eset out[2]) {
    int32_t *gid = mesh_xmalloc((size_t)ev->nx * sizeof *gid, 1);
    int32_t *cutid = mesh_xmalloc((size_t)ev->nch * sizeof *cutid, 1);
    for (int32_t j = 0; j < ev->nch; j++) {
        int ina = !!(mask & (1u << ev->chcell[2 * j]));
        int inb = !!(mask & (1u << ev->chcell[2 * j + 1]));
        gid[2 * j] = gid[2 * j + 1] = -1;
        cutid[j] = -1;
        if (ina == inb) continue;
        for (int e = 0; e < 2; e++) {
            const xing *x = &ev->x[2 * j + e];
            gid[2 * j + e] = x->vtx >= 0     ? x->vtx
                             : x->reuse >= 0 ? x->reuse
                                             : ctx_add_vertex(c, x->p[0], x->p[1], f->par[x->edge]);
        }
        cutid[j] = ctx_add_parent(c, gid[2 * j], gid[2 * j + 1], ev->axis, 0);
    }
    int rc = 0;
    for (int g = 0; g < 2; g++) {
        eset tmp = {0};
        for (int32_t k = 0; k < ev->ncell; k++) {
            if (!!(mask & (1u << k)) != (g == 0)) continue;
            for (int32_t i = 0; i < ev->cell[k].n; i++) {
                int32_t par = ev->cell[k].par[i];
                if (par <= -2 && cutid[-2 - par] < 0)
                    continue; /* unused chord: both directions are in this group */
                eset_push(&tmp, ev->cell[k].u[i], ev->cell[k].v[i], par);
            }
        }
        /* contract unused crossings: x -> w -> y becomes x -> y */
        int32_t *outedge = mesh_xmalloc((size_t)ev->nx * sizeof *outedge, 1);
        for (int32_t k = 0; k < ev->nx; k++)
            outedge[k] = -1;
        for (int32_t i = 0; i < tmp.n; i++)
            if (tmp.u[i] >= ev->nv0) outedge[tmp.u[i] - ev->nv0] = i;
        memset(&out[g], 0, sizeof out[g]);
        for (int32_t i = 0; i < tmp.n; i++) {
            int32_t u = tmp.u[i], v = tmp.v[i], par = tmp.par[i];
            if (u >= ev->nv0 && gid[u - ev->nv0] < 0) continue;
            int guard = 0;
            while (v >= ev->nv0 && gid[v - ev->nv0] < 0 && guard++ <= ev->nx) {
                int32_t o = outedge[v - ev->nv0];
                if (o < 0) break;
                v = tmp.v[o];
            }
            if (v >= ev->nv0 && gid[v - ev->nv0] < 0) {
                rc = -1;
                continue;
            }
            eset_push(&out[g], u >= ev->nv0 ? gid[u - ev->nv0] : u,
                      v >= ev->nv0 ? gid[v - ev->nv0] : v, par <= -2 ? cutid[-2 - par] : par);
        }
        free(outedge);
        eset_free(&tmp);
        int32_t *fc = mesh_xmalloc(((size_t)out[g].n + 1) * sizeof *fc, 1);
        if (faces_of(c, c->nv, NULL, &out[g], fc) != 1) rc = -1;
        free(fc);
    }
    free(gid);
    free(cutid);
    return rc;
}

static double region_extent(const ctx *c, const eset *f, int axis, double *lo, double *hi) {
    *lo = HUGE_VAL;
    *hi = -HUGE_VAL;
    for (int32_t i = 0; i < f->n; i++) {
        double s = s_of(axis, c->xy + 2 * f->u[i]);
        *lo = fmin(*lo, s);
        *hi = fmax(*hi, s);
    }
    return *hi - *lo;
}

/* Scans the lines of one axis whose low side holds fraction fr of region f (within +-delta):
 * evenly spaced positions, the balanced one, every vertex of f in the window, and every
 * vertex a neighbour's cut put on f's boundary (nb, nnb; continuing that cut). */
static void scan_axis(ctx *c, const eset *f, int axis, double fr, double delta, int npos,
                      const int32_t *nb, int32_t nnb, double f1, double h, double rarea, cand *best,
                      scanstat *st) {
    double lo, hi;
    region_extent(c, f, axis, &lo, &hi);
    double clo = invert_area(c, f, axis, lo, hi, fmax(fr - delta, 0), rarea);
    double chi = invert_area(c, f, axis, lo, hi, fmin(fr + delta, 1), rarea);
    double cstar = invert_area(c, f, axis, lo, hi, fr, rarea);
    for (int32_t p = -1; p <= npos + f->n + nnb; p++) {
        double cv;
        if (p < 0)
            cv = cstar;
        else if (p <= npos)
            cv = clo + (chi - clo) * p / npos;
        else if (p <= npos + f->n)
            cv = s_of(axis, c->xy + 2 * f->u[p - npos - 1]);
        else
            cv = s_of(axis, c->xy + 2 * nb[p - npos - f->n - 1]);
        if (!(cv > lo && cv < hi) || !(cv >= clo && cv <= chi)) continue;
        cutev ev;
        st->lines++;
        if (eval_cut(c, f, axis, cv, h, nb, nnb, &ev) == 0)
            score_splits(c, &ev, f1, rarea, best, st);
        else
            st->unusable++;
        cutev_free(&ev);
    }
}

/* Budget left for a part whose weight deviates by d (relative) from its target, when the
 * region's subdomains may deviate by b in total. */
static double child_budget(double b, double d) {
    return fmax(0, fmin((1 + b) / (1 + d) - 1, 1 - (1 - b) / (1 + d)));
}

static void eset_copy(eset *dst, const eset *src) {
    memset(dst, 0, sizeof *dst);
    for (int32_t i = 0; i < src->n; i++)
        eset_push(dst, src->u[i], src->v[i], src->par[i]);
}

/* Splits region f (not modified) holding subdomains [i0, i1) recursively; every subdomain of
 * it may deviate from its target by the relative budget.  The balance tolerance of a split
 * starts at an even share of the budget per level and grows while no cut meets the boundary
 * at 60 degrees or more; if the rest of the recursion then fails, the split is undone and
 * chosen again with the smaller tolerances (a bounded number of times in all). */
static int split_region(ctx *c, const eset *f, int32_t i0, int32_t i1, double density,
                        double budget) {
    int32_t k = i1 - i0;
    if (k == 1) {
        eset_copy(&c->sub[i0], f);
        c->density[i0] = density;
        return 0;
    }
    int32_t mid = i0 + k / 2;
    double t1 = 0, t = 0;
    for (int32_t i = i0; i < i1; i++) {
        t += c->target[i];
        if (i < mid) t1 += c->target[i];
    }
    double f1 = t1 / t, rarea = eset_area(c, c->nv, NULL, f);
    double h = sqrt(rarea / k);
    int levels = 0;
    while ((1L << levels) < (long)k)
        levels++;
    double tols[3] = {budget / levels, fmin(budget, 2 * budget / levels), 0.75 * budget};
    int ntol = levels == 1 ? 1 : levels == 2 ? 2 : 3;
    /* new vertices on the parents of f's edges that are not vertices of f: put there by
     * neighbours' cuts */
    int32_t nnb = 0, capnb = 16, *nb = mesh_xmalloc((size_t)capnb * sizeof *nb, 1);
    for (int32_t i = 0; i < f->n; i++)
        for (int32_t w = c->phead[f->par[i]]; w >= 0; w = c->vnext[w]) {
            int dup = 0;
            for (int32_t j = 0; j < f->n && !dup; j++)
                dup = f->u[j] == w;
            for (int32_t j = 0; j < nnb && !dup; j++)
                dup = nb[j] == w;
            if (dup) continue;
            if (nnb == capnb) {
                capnb *= 2;
                nb = mesh_xrealloc(nb, (size_t)capnb * sizeof *nb, 1);
            }
            nb[nnb++] = w;
        }
    int rc = -1;
    for (;;) {
        cand best = {0};
        scanstat st = {0, 0, 0, HUGE_VAL, 0, 0};
        for (int a = 0; a < ntol && !(best.valid && best.ang >= 60); a++) {
            c->tol_level = tols[a];
            c->tol_ref = tols[0];
            c->attempt = a;
            for (int pass = 0; pass < 2 && !(best.valid && best.ang >= 60); pass++) {
                if (pass == 1 && a + 1 < ntol) break; /* the wide scan only with the last */
                for (int axis = 0; axis < 2; axis++)
                    for (int side = 0; side < 2; side++) {
                        double fr = side ? 1 - f1 : f1;
                        if (side && fr == f1) break;
                        double m = fmin(fr, 1 - fr);
                        double delta = pass == 0 ? 1.5 * c->tol_level * m : fmin(0.3, 0.9 * m);
                        scan_axis(c, f, axis, fr, delta, pass == 0 ? SCAN_FINE : SCAN_WIDE, nb, nnb,
                                  f1, h, rarea, &best, &st);
                    }
            }
        }
        if (!best.valid) {
            double bx0, bx1, by0, by1;
            region_extent(c, f, 0, &bx0, &bx1);
            region_extent(c, f, 1, &by0, &by1);
            rc = fail(c->err, c->errlen,
                      "%s: cannot split the region [%g, %g] x [%g, %g] of area %g into %d "
                      "subdomains: no straight cut keeps the balance within %.1f%% while "
                      "meeting the boundary at >= %.0f degrees and staying %.0f%% of the "
                      "subdomain size (%g) or of the local feature size away from other "
                      "vertices and segments, with every piece at least %g long (%g%% of the "
                      "domain size); too many subdomains for this domain? (%ld lines tried, %ld "
                      "unusable, %ld splits; best balance error %.1f%%, best angle %.1f, best "
                      "clearance %.2f)",
                      c->in->path[0] ? c->in->path : "(input)", bx0, bx1, by0, by1, rarea, (int)k,
                      100 * c->tol_level, c->hard_angle, 100 * SPACE_HARD, h, c->min_cut,
                      100 * MIN_CUT_REL, st.lines, st.unusable, st.splits, 100 * st.best_err,
                      st.best_ang, st.best_spc);
            break;
        }
        int32_t nv_save = c->nv, npar_save = c->npar;
        cutev ev;
        eset parts[2] = {{0}};
        rc = eval_cut(c, f, best.axis, best.cv, h, nb, nnb, &ev);
        if (rc == 0) rc = apply_split(c, f, &ev, best.mask, parts);
        cutev_free(&ev);
        if (rc) {
            eset_free(&parts[0]);
            eset_free(&parts[1]);
            rc = fail(c->err, c->errlen, "%s: internal error: a chosen cut did not split cleanly",
                      c->in->path[0] ? c->in->path : "(input)");
            break;
        }
        double ffirst = best.a_first ? best.fa : 1 - best.fa;
        const eset *first = best.a_first ? &parts[0] : &parts[1];
        const eset *second = best.a_first ? &parts[1] : &parts[0];
        rc = split_region(c, first, i0, mid, density, child_budget(budget, ffirst / f1 - 1));
        if (rc == 0)
            rc = split_region(c, second, mid, i1, density,
                              child_budget(budget, (1 - ffirst) / (1 - f1) - 1));
        eset_free(&parts[0]);
        eset_free(&parts[1]);
        if (rc == 0 || best.attempt == 0 || c->retries <= 0 || k > 8) break;
        /* undo and choose again with a smaller balance tolerance */
        c->retries--;
        while (c->nv > nv_save) {
            c->nv--;
            if (c->vpar[c->nv] >= 0) c->phead[c->vpar[c->nv]] = c->vnext[c->nv];
        }
        c->npar = npar_save;
        for (int32_t i = i0; i < i1; i++)
            eset_free(&c->sub[i]);
        ntol = best.attempt;
    }
    free(nb);
    return rc;
}

/* ------------------------------------------------------------------------------------------ */
/* Face tracing of a straight-line graph (half-edges sorted by angle)                         */

typedef struct trace {
    int32_t nh;    /* 2 * nsegs; half-edge 2s runs a -> b, 2s + 1 runs b -> a */
    int32_t *next; /* next half-edge around the face on its left */
    int32_t *cyc;  /* cycle of each half-edge */
    int32_t ncyc;
    double *carea;  /* signed area of each cycle */
    int32_t *cface; /* face of each cycle (-1: unbounded) */
    int32_t nface;  /* bounded faces; face f's outer cycle is fouter[f] */
    int32_t *fouter;
    int32_t *cstart, *clist; /* half-edges of cycle c: clist[cstart[c] .. cstart[c + 1]) */
    double *cbox;            /* 4 per cycle: xmin, xmax, ymin, ymax */
} trace;

typedef struct angi {
    double ang;
    int32_t h;
} angi;

static int cmp_angi(const void *x, const void *y) {
    const angi *a = x, *b = y;
    if (a->ang != b->ang) return a->ang < b->ang ? -1 : 1;
    return (a->h > b->h) - (a->h < b->h);
}

static void trace_free(trace *t) {
    free(t->cstart);
    free(t->clist);
    free(t->cbox);
    free(t->next);
    free(t->cyc);
    free(t->carea);
    free(t->cface);
    free(t->fouter);
    memset(t, 0, sizeof *t);
}

static int32_t h_org(const int32_t *seg, int32_t h) {
    return seg[2 * (h / 2) + (h & 1)];
}
static int32_t h_dst(const int32_t *seg, int32_t h) {
    return seg[2 * (h / 2) + 1 - (h & 1)];
}

/* Crossing-number test of p against the half-edges of cycle cy. */
static int point_in_cycle(const double *xy, const int32_t *seg, const trace *t, int32_t cy,
                          const double *p) {
    const double *bx = t->cbox + 4 * cy;
    if (p[0] < bx[0] || p[0] > bx[1] || p[1] < bx[2] || p[1] > bx[3]) return 0;
    int in = 0;
    for (int32_t k = t->cstart[cy]; k < t->cstart[cy + 1]; k++) {
        int32_t h = t->clist[k];
        const double *a = xy + 2 * h_org(seg, h), *b = xy + 2 * h_dst(seg, h);
        if ((a[1] > p[1]) != (b[1] > p[1])) {
            double x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if (p[0] < x) in = !in;
        }
    }
    return in;
}

/* 1 if p lies in bounded face f (inside its outer cycle, outside its hole cycles). */
static int point_in_face(const double *xy, const int32_t *seg, const trace *t, int32_t f,
                         const double *p) {
    if (!point_in_cycle(xy, seg, t, t->fouter[f], p)) return 0;
    for (int32_t cy = 0; cy < t->ncyc; cy++)
        if (t->cface[cy] == f && cy != t->fouter[f] && point_in_cycle(xy, seg, t, cy, p)) return 0;
    return 1;
}

static void trace_build(const double *xy, int32_t nv, const int32_t *seg, int32_t ns, trace *t) {
    memset(t, 0, sizeof *t);
    t->nh = 2 * ns;
    int32_t nh = t->nh;
    int32_t *start = mesh_xcalloc((size_t)nv + 1, sizeof *start),
            *pos = mesh_xmalloc((size_t)nh * sizeof *pos, 1);
    angi *list = mesh_xmalloc((size_t)nh * sizeof *list, 1);
    for (int32_t h = 0; h < nh; h++)
        start[h_org(seg, h) + 1]++;
    for (int32_t v = 0; v < nv; v++)
        start[v + 1] += start[v];
    int32_t *fill = mesh_xmalloc(((size_t)nv + 1) * sizeof *fill, 1);
    memcpy(fill, start, (size_t)nv * sizeof *fill);
    for (int32_t h = 0; h < nh; h++) {
        const double *a = xy + 2 * h_org(seg, h), *b = xy + 2 * h_dst(seg, h);
        angi *e = &list[fill[h_org(seg, h)]++];
        e->ang = atan2(b[1] - a[1], b[0] - a[0]);
        e->h = h;
    }
    for (int32_t v = 0; v < nv; v++)
        qsort(list + start[v], (size_t)(start[v + 1] - start[v]), sizeof *list, cmp_angi);
    for (int32_t i = 0; i < nh; i++)
        pos[list[i].h] = i;
    t->next = mesh_xmalloc((size_t)nh * sizeof *t->next, 1);
    for (int32_t h = 0; h < nh; h++) {
        int32_t tw = h ^ 1, v = h_org(seg, tw), i = pos[tw];
        int32_t j = i == start[v] ? start[v + 1] - 1 : i - 1; /* clockwise from the twin */
        t->next[h] = list[j].h;
    }
    t->cyc = mesh_xmalloc((size_t)nh * sizeof *t->cyc, 1);
    for (int32_t h = 0; h < nh; h++)
        t->cyc[h] = -1;
    for (int32_t h = 0; h < nh; h++) {
        if (t->cyc[h] >= 0) continue;
        int32_t g = h;
        do {
            t->cyc[g] = t->ncyc;
            g = t->next[g];
        } while (g != h && t->cyc[g] < 0);
        t->ncyc++;
    }
    t->carea = mesh_xcalloc((size_t)t->ncyc, sizeof *t->carea);
    t->cstart = mesh_xcalloc((size_t)t->ncyc + 1, sizeof *t->cstart);
    t->clist = mesh_xmalloc(((size_t)nh + 1) * sizeof *t->clist, 1);
    t->cbox = mesh_xmalloc(4 * ((size_t)t->ncyc + 1) * sizeof *t->cbox, 1);
    for (int32_t cy = 0; cy < t->ncyc; cy++) {
        t->cbox[4 * cy] = t->cbox[4 * cy + 2] = HUGE_VAL;
        t->cbox[4 * cy + 1] = t->cbox[4 * cy + 3] = -HUGE_VAL;
    }
    for (int32_t h = 0; h < nh; h++) {
        const double *a = xy + 2 * h_org(seg, h), *b = xy + 2 * h_dst(seg, h);
        double *bx = t->cbox + 4 * t->cyc[h];
        t->carea[t->cyc[h]] += 0.5 * (a[0] * b[1] - a[1] * b[0]);
        t->cstart[t->cyc[h] + 1]++;
        bx[0] = fmin(bx[0], a[0]);
        bx[1] = fmax(bx[1], a[0]);
        bx[2] = fmin(bx[2], a[1]);
        bx[3] = fmax(bx[3], a[1]);
    }
    for (int32_t cy = 0; cy < t->ncyc; cy++)
        t->cstart[cy + 1] += t->cstart[cy];
    {
        int32_t *cf = mesh_xmalloc(((size_t)t->ncyc + 1) * sizeof *cf, 1);
        memcpy(cf, t->cstart, (size_t)t->ncyc * sizeof *cf);
        for (int32_t h = 0; h < nh; h++)
            t->clist[cf[t->cyc[h]]++] = h;
        free(cf);
    }
    t->cface = mesh_xmalloc((size_t)t->ncyc * sizeof *t->cface, 1);
    t->fouter = mesh_xmalloc((size_t)t->ncyc * sizeof *t->fouter, 1);
    for (int32_t cy = 0; cy < t->ncyc; cy++) {
        t->cface[cy] = -1;
        if (t->carea[cy] > 0) {
            t->fouter[t->nface] = cy;
            t->cface[cy] = t->nface++;
        }
    }
    /* a cycle of non-positive area bounds a hole of the smallest positive cycle around it */
    int32_t *first = mesh_xmalloc((size_t)t->ncyc * sizeof *first, 1);
    for (int32_t cy = 0; cy < t->ncyc; cy++)
        first[cy] = -1;
    for (int32_t h = nh - 1; h >= 0; h--)
        first[t->cyc[h]] = h;
    for (int32_t cy = 0; cy < t->ncyc; cy++) {
        if (t->carea[cy] > 0) continue;
        int32_t h = first[cy];
        const double *a = xy + 2 * h_org(seg, h), *b = xy + 2 * h_dst(seg, h);
        double p[2] = {0.5 * (a[0] + b[0]) - 1e-6 * (b[1] - a[1]),
                       0.5 * (a[1] + b[1]) + 1e-6 * (b[0] - a[0])};
        int32_t best = -1;
        for (int32_t o = 0; o < t->ncyc; o++)
            if (t->carea[o] > 0 && (best < 0 || t->carea[o] < t->carea[best]) &&
                point_in_cycle(xy, seg, t, o, p))
                best = o;
        t->cface[cy] = best < 0 ? -1 : t->cface[best];
    }
    free(first);
    free(start);
    free(pos);
    free(list);
    free(fill);
}

/* Domain faces of a trace: bounded faces containing no hole point.  Returns their number and
 * fills isdom[face]. */
static int32_t domain_faces(const double *xy, const int32_t *seg, const trace *t, const pslg *in,
                            uint8_t *isdom) {
    int32_t n = 0;
    for (int32_t f = 0; f < t->nface; f++) {
        isdom[f] = 1;
        for (int32_t k = 0; k < in->nholes; k++)
            if (point_in_face(xy, seg, t, f, in->holes + 2 * k)) isdom[f] = 0;
        n += isdom[f];
    }
    return n;
}

/* Area density (1 / area bound) of face f: see the header. */
static double face_density(const double *xy, const int32_t *seg, const trace *t, int32_t f,
                           const pslg *in, double max_area) {
    double a = max_area > 0 ? max_area : 0, largest = a;
    for (int32_t r = 0; r < in->nregions; r++)
        largest = fmax(largest, in->regions[4 * r + 3]);
    for (int32_t r = 0; r < in->nregions; r++) {
        double ra = in->regions[4 * r + 3];
        if (ra > 0 && point_in_face(xy, seg, t, f, in->regions + 4 * r))
            a = a > 0 ? fmin(a, ra) : ra;
    }
    if (!(a > 0)) a = largest > 0 ? largest : 1;
    return 1.0 / a;
}

/* ------------------------------------------------------------------------------------------ */
/* Building the output                                                                        */

typedef struct tpos {
    double t;
    int32_t v;
} tpos;

static int cmp_tpos(const void *x, const void *y) {
    const tpos *a = x, *b = y;
    if (a->t != b->t) return a->t < b->t ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

/* Builds d->g and the segment tables from c's vertices and parents (input segments and cuts
 * split at the vertices lying on them). */
static void build_segments(const ctx *c, pcdm_decomp *d) {
    const pslg *in = c->in;
    pslg *g = &d->g;
    g->nverts = c->nv;
    g->xy = mesh_xmalloc(2 * (size_t)c->nv * sizeof *g->xy, 1);
    memcpy(g->xy, c->xy, 2 * (size_t)c->nv * sizeof *g->xy);
    g->vmarker = mesh_xcalloc((size_t)c->nv, sizeof *g->vmarker);
    g->vline = mesh_xcalloc((size_t)c->nv, sizeof *g->vline);
    g->nattr = in->nattr;
    if (in->nattr > 0 && in->vattr)
        g->vattr = mesh_xcalloc((size_t)c->nv * in->nattr, sizeof *g->vattr);
    for (int32_t i = 0; i < c->nv; i++) {
        if (i < in->nverts) {
            g->vmarker[i] = in->vmarker ? in->vmarker[i] : 0;
            g->vline[i] = in->vline ? in->vline[i] : 0;
            if (g->vattr)
                memcpy(g->vattr + (size_t)i * in->nattr, in->vattr + (size_t)i * in->nattr,
                       (size_t)in->nattr * sizeof *g->vattr);
            continue;
        }
        int32_t par = c->vpar[i];
        if (par < 0) continue; /* a free cut endpoint (cuts files) */
        g->vline[i] = c->pline[par];
        if (par < in->nsegs) {
            g->vmarker[i] = in->smarker ? in->smarker[par] : 0;
            g->vline[i] = in->sline ? in->sline[par] : 0;
            if (g->vattr) {
                const double *A = c->xy + 2 * c->pa[par], *B = c->xy + 2 * c->pb[par];
                double l2 = (B[0] - A[0]) * (B[0] - A[0]) + (B[1] - A[1]) * (B[1] - A[1]);
                double s = ((c->xy[2 * i] - A[0]) * (B[0] - A[0]) +
                            (c->xy[2 * i + 1] - A[1]) * (B[1] - A[1])) /
                           l2;
                for (int k = 0; k < in->nattr; k++)
                    g->vattr[(size_t)i * in->nattr + k] =
                        (1 - s) * in->vattr[(size_t)c->pa[par] * in->nattr + k] +
                        s * in->vattr[(size_t)c->pb[par] * in->nattr + k];
            }
        }
    }
    /* vertices on each parent, by counting sort */
    int32_t *cnt = mesh_xcalloc((size_t)c->npar + 1, sizeof *cnt);
    for (int32_t i = in->nverts; i < c->nv; i++)
        if (c->vpar[i] >= 0) cnt[c->vpar[i] + 1]++;
    for (int32_t p = 0; p < c->npar; p++)
        cnt[p + 1] += cnt[p];
    int32_t nnew = c->nv - in->nverts;
    int32_t *onpar = mesh_xmalloc(((size_t)nnew + 1) * sizeof *onpar, 1);
    int32_t *fill = mesh_xmalloc(((size_t)c->npar + 1) * sizeof *fill, 1);
    memcpy(fill, cnt, (size_t)c->npar * sizeof *fill);
    for (int32_t i = in->nverts; i < c->nv; i++)
        if (c->vpar[i] >= 0) onpar[fill[c->vpar[i]]++] = i;
    int32_t cap = c->npar + nnew;
    g->seg = mesh_xmalloc(2 * (size_t)cap * sizeof *g->seg, 1);
    g->smarker = mesh_xmalloc((size_t)cap * sizeof *g->smarker, 1);
    g->sline = mesh_xmalloc((size_t)cap * sizeof *g->sline, 1);
    d->seg_parent = mesh_xmalloc((size_t)cap * sizeof *d->seg_parent, 1);
    d->seg_iface = mesh_xmalloc((size_t)cap * sizeof *d->seg_iface, 1);
    tpos *tp = mesh_xmalloc(((size_t)nnew + 2) * sizeof *tp, 1);
    int32_t ns = 0;
    for (int32_t p = 0; p < c->npar; p++) {
        const double *A = c->xy + 2 * c->pa[p], *B = c->xy + 2 * c->pb[p];
        int32_t m = 0;
        tp[m].t = 0;
        tp[m++].v = c->pa[p];
        for (int32_t k = cnt[p]; k < cnt[p + 1]; k++) {
            const double *P = c->xy + 2 * onpar[k];
            tp[m].t = (P[0] - A[0]) * (B[0] - A[0]) + (P[1] - A[1]) * (B[1] - A[1]);
            tp[m++].v = onpar[k];
        }
        qsort(tp + 1, (size_t)(m - 1), sizeof *tp, cmp_tpos);
        tp[m++].v = c->pb[p];
        int iface = p >= in->nsegs;
        for (int32_t k = 0; k + 1 < m; k++) {
            g->seg[2 * ns] = tp[k].v;
            g->seg[2 * ns + 1] = tp[k + 1].v;
            g->smarker[ns] = iface ? 0 : (in->smarker ? in->smarker[p] : 0);
            g->sline[ns] = iface ? c->pline[p] : (in->sline ? in->sline[p] : 0);
            d->seg_parent[ns] = iface ? p - in->nsegs : p;
            d->seg_iface[ns] = (uint8_t)iface;
            ns++;
        }
        if (p + 1 == in->nsegs) d->nboundary = ns;
    }
    g->nsegs = ns;
    g->nholes = in->nholes;
    g->holes = mesh_xmalloc(2 * ((size_t)in->nholes + 1) * sizeof *g->holes, 1);
    if (in->nholes) memcpy(g->holes, in->holes, 2 * (size_t)in->nholes * sizeof *g->holes);
    g->nregions = in->nregions;
    g->regions = mesh_xmalloc(4 * ((size_t)in->nregions + 1) * sizeof *g->regions, 1);
    if (in->nregions)
        memcpy(g->regions, in->regions, 4 * (size_t)in->nregions * sizeof *g->regions);
    g->first_index = in->first_index;
    memcpy(g->path, in->path, sizeof g->path);
    memcpy(g->segpath, in->segpath, sizeof g->segpath);
    d->ninput_verts = in->nverts;
    d->ninput_segs = in->nsegs;
    d->ncuts = c->npar - in->nsegs;
    d->cut_xy = mesh_xmalloc(4 * ((size_t)d->ncuts + 1) * sizeof *d->cut_xy, 1);
    for (int32_t k = 0; k < d->ncuts; k++) {
        int32_t p = in->nsegs + k;
        memcpy(d->cut_xy + 4 * k, c->xy + 2 * c->pa[p], 2 * sizeof(double));
        memcpy(d->cut_xy + 4 * k + 2, c->xy + 2 * c->pb[p], 2 * sizeof(double));
    }
    free(cnt);
    free(onpar);
    free(fill);
    free(tp);
}

/* Smallest angle between an interface piece and any other segment at a shared vertex. */
static double iface_min_angle(const pcdm_decomp *d, int32_t *worst_seg) {
    const pslg *g = &d->g;
    double best = 180;
    *worst_seg = -1;
    int32_t *start = mesh_xcalloc((size_t)g->nverts + 1, sizeof *start);
    for (int32_t s = 0; s < 2 * g->nsegs; s++)
        start[g->seg[s] + 1]++;
    for (int32_t v = 0; v < g->nverts; v++)
        start[v + 1] += start[v];
    int32_t *fill = mesh_xmalloc(((size_t)g->nverts + 1) * sizeof *fill, 1),
            *inc = mesh_xmalloc(((size_t)2 * g->nsegs + 1) * sizeof *inc, 1);
    memcpy(fill, start, (size_t)g->nverts * sizeof *fill);
    for (int32_t s = 0; s < 2 * g->nsegs; s++)
        inc[fill[g->seg[s]]++] = s; /* s = 2 * segment + end */
    for (int32_t v = 0; v < g->nverts; v++)
        for (int32_t i = start[v]; i < start[v + 1]; i++)
            for (int32_t j = i + 1; j < start[v + 1]; j++) {
                int32_t s1 = inc[i] / 2, s2 = inc[j] / 2;
                if (!d->seg_iface[s1] && !d->seg_iface[s2]) continue;
                const double *o = g->xy + 2 * v;
                const double *a = g->xy + 2 * g->seg[2 * s1 + 1 - inc[i] % 2];
                const double *b = g->xy + 2 * g->seg[2 * s2 + 1 - inc[j] % 2];
                double u1[2] = {a[0] - o[0], a[1] - o[1]}, u2[2] = {b[0] - o[0], b[1] - o[1]};
                double ang =
                    atan2(fabs(u1[0] * u2[1] - u1[1] * u2[0]), u1[0] * u2[0] + u1[1] * u2[1]) *
                    (180.0 / PI);
                if (ang < best) {
                    best = ang;
                    *worst_seg = d->seg_iface[s1] ? s1 : s2;
                }
            }
    free(start);
    free(fill);
    free(inc);
    return best;
}

/* Owners for subdomain weights w (in order), contiguous, rank 0 getting R shares. */
static void assign_owners(const double *w, int32_t K, int32_t P, double R, int32_t *owner) {
    double total = 0;
    for (int32_t i = 0; i < K; i++)
        total += w[i];
    double unit = total / (R + P - 1), bound = R * unit, acc = 0;
    int32_t r = 0;
    for (int32_t i = 0; i < K; i++) {
        owner[i] = r;
        acc += w[i];
        if (r == P - 1) continue;
        int must = K - i - 1 == P - 1 - r;
        int enough = i + 1 < K && acc + 0.5 * w[i + 1] >= bound;
        if (must || enough) {
            r++;
            bound += unit;
        }
    }
}

/* Traces the faces of d->g, matches them with the subdomains (auto: seeds given in
 * d->sub_seed; cuts mode, seeds == NULL: every domain face becomes a subdomain, ordered by
 * seed), fills seg_sub, areas, weights. */
static int finish(ctx *c, pcdm_decomp *d, int auto_mode, const double *in_density_face,
                  const trace *tin) {
    pslg *g = &d->g;
    trace t;
    trace_build(g->xy, g->nverts, g->seg, g->nsegs, &t);
    uint8_t *isdom = mesh_xcalloc((size_t)t.nface + 1, 1);
    int32_t ndom = domain_faces(g->xy, g->seg, &t, c->in, isdom);
    int32_t *f2s = mesh_xmalloc(((size_t)t.nface + 1) * sizeof *f2s, 1);
    int rc = 0;
    const char *path = c->in->path[0] ? c->in->path : "(input)";
    for (int32_t f = 0; f < t.nface; f++)
        f2s[f] = -1;
    if (auto_mode) {
        if (ndom != d->nsub) {
            rc = fail(c->err, c->errlen,
                      "%s: internal error: the cuts make %d faces for %d subdomains", path,
                      (int)ndom, (int)d->nsub);
            goto out;
        }
        for (int32_t s = 0; s < d->nsub; s++) {
            int32_t hit = -1;
            for (int32_t f = 0; f < t.nface && hit < 0; f++)
                if (isdom[f] && point_in_face(g->xy, g->seg, &t, f, d->sub_seed + 2 * s)) hit = f;
            if (hit < 0 || f2s[hit] >= 0) {
                rc = fail(c->err, c->errlen,
                          "%s: internal error: seed of subdomain %d not in its own face", path,
                          (int)s);
                goto out;
            }
            f2s[hit] = s;
        }
    } else {
        d->nsub = ndom;
        d->sub_seed = mesh_xmalloc(2 * ((size_t)ndom + 1) * sizeof *d->sub_seed, 1);
        double *seeds = mesh_xmalloc(2 * ((size_t)ndom + 1) * sizeof *seeds, 1);
        int32_t *fid = mesh_xmalloc(((size_t)ndom + 1) * sizeof *fid, 1), n = 0;
        for (int32_t f = 0; f < t.nface; f++) {
            if (!isdom[f]) continue;
            eset e = {0};
            for (int32_t h = 0; h < t.nh; h++)
                if (t.cface[t.cyc[h]] == f)
                    eset_push(&e, h_org(g->seg, h), h_dst(g->seg, h), h / 2);
            face_seed(c, &e, seeds + 2 * n);
            fid[n++] = f;
            eset_free(&e);
        }
        /* order by seed (x, then y), a deterministic spatial order */
        for (int32_t i = 1; i < n; i++)
            for (int32_t j = i; j > 0; j--) {
                double *a = seeds + 2 * (j - 1), *b = seeds + 2 * j;
                if (a[0] < b[0] || (a[0] == b[0] && a[1] <= b[1])) break;
                double tx = a[0], ty = a[1];
                a[0] = b[0];
                a[1] = b[1];
                b[0] = tx;
                b[1] = ty;
                int32_t tf = fid[j - 1];
                fid[j - 1] = fid[j];
                fid[j] = tf;
            }
        for (int32_t i = 0; i < n; i++) {
            f2s[fid[i]] = i;
            d->sub_seed[2 * i] = seeds[2 * i];
            d->sub_seed[2 * i + 1] = seeds[2 * i + 1];
        }
        free(seeds);
        free(fid);
    }
    d->seg_sub = mesh_xmalloc(2 * ((size_t)g->nsegs + 1) * sizeof *d->seg_sub, 1);
    for (int32_t h = 0; h < t.nh; h++) {
        int32_t f = t.cface[t.cyc[h]];
        d->seg_sub[h] = f >= 0 ? f2s[f] : -1; /* h = 2s: left of s; 2s + 1: right of s */
    }
    int32_t K = d->nsub;
    d->sub_area = mesh_xcalloc((size_t)K + 1, sizeof *d->sub_area);
    d->sub_weight = mesh_xcalloc((size_t)K + 1, sizeof *d->sub_weight);
    for (int32_t h = 0; h < t.nh; h++) {
        int32_t s = d->seg_sub[h];
        if (s < 0) continue;
        const double *a = g->xy + 2 * h_org(g->seg, h), *b = g->xy + 2 * h_dst(g->seg, h);
        d->sub_area[s] += 0.5 * (a[0] * b[1] - a[1] * b[0]);
    }
    d->total_weight = 0;
    for (int32_t s = 0; s < K; s++) {
        double dens = 1;
        for (int32_t f = 0; f < tin->nface; f++)
            if (in_density_face[f] > 0 &&
                point_in_face(c->in->xy, c->in->seg, tin, f, d->sub_seed + 2 * s))
                dens = in_density_face[f];
        d->sub_weight[s] = d->sub_area[s] * dens;
        d->total_weight += d->sub_weight[s];
    }
    int32_t worst;
    d->min_angle = iface_min_angle(d, &worst);
out:
    trace_free(&t);
    free(isdom);
    free(f2s);
    return rc;
}

/* ------------------------------------------------------------------------------------------ */
/* Public API                                                                                 */

void pcdm_decomp_opts_default(pcdm_decomp_opts *o) {
    memset(o, 0, sizeof *o);
    o->nranks = 1;
    o->min_angle = 30;
    o->imbalance = 1;
}

void pcdm_decomp_free(pcdm_decomp *d) {
    if (!d) return;
    pslg_free(&d->g);
    free(d->seg_parent);
    free(d->seg_iface);
    free(d->seg_sub);
    free(d->cut_xy);
    free(d->sub_seed);
    free(d->sub_area);
    free(d->sub_weight);
    free(d->sub_target);
    free(d->sub_owner);
    memset(d, 0, sizeof *d);
}

/* Targets and owners: rank 0 gets k0 ~ K R / (R + P - 1) subdomains (at least 1, leaving one
 * for every other rank), the others share the rest evenly; every rank's share is divided
 * evenly over its subdomains. */
static void plan_targets(int32_t K, int32_t P, double R, double *target, int32_t *owner) {
    int32_t k0 = P == 1 ? K : (int32_t)floor(K * R / (R + P - 1) + 0.5);
    if (k0 < 1) k0 = 1;
    if (k0 > K - (P - 1)) k0 = K - (P - 1);
    int32_t i = 0;
    for (int32_t r = 0; r < P; r++) {
        int32_t kr = r == 0 ? k0 : (K - k0) / (P - 1) + (r - 1 < (K - k0) % (P - 1));
        double share = (r == 0 ? R : 1) / (R + P - 1);
        for (int32_t j = 0; j < kr; j++, i++) {
            target[i] = share / kr;
            owner[i] = r;
        }
    }
}

static int check_opts(const pslg *in, const pcdm_decomp_opts *o, char *err, size_t errlen) {
    const char *path = in->path[0] ? in->path : "(input)";
    if (o->nranks < 1)
        return fail(err, errlen, "%s: rank count %d must be >= 1", path, (int)o->nranks);
    if (!(o->imbalance > 0) || !isfinite(o->imbalance))
        return fail(err, errlen, "%s: imbalance factor %g must be > 0", path, o->imbalance);
    if (!(o->max_area >= 0) || !(o->min_angle >= 0) || !(o->balance_tol >= 0) ||
        !(o->balance_tol < 1))
        return fail(err, errlen, "%s: bad quality, area or balance bound", path);
    if (in->nsegs < 3) return fail(err, errlen, "%s: empty domain (fewer than 3 segments)", path);
    return 0;
}

/* Domain faces of the input: the trace, a density per face (0 = not a domain face), count. */
static int32_t input_faces(const pslg *in, const pcdm_decomp_opts *o, trace *t, double **density,
                           double *area_total) {
    trace_build(in->xy, in->nverts, in->seg, in->nsegs, t);
    uint8_t *isdom = mesh_xcalloc((size_t)t->nface + 1, 1);
    int32_t n = domain_faces(in->xy, in->seg, t, in, isdom);
    *density = mesh_xcalloc((size_t)t->nface + 1, sizeof **density);
    *area_total = 0;
    for (int32_t f = 0; f < t->nface; f++) {
        if (!isdom[f]) continue;
        (*density)[f] = face_density(in->xy, in->seg, t, f, in, o->max_area);
        double a = 0;
        for (int32_t h = 0; h < t->nh; h++)
            if (t->cface[t->cyc[h]] == f) {
                const double *p = in->xy + 2 * h_org(in->seg, h);
                const double *q = in->xy + 2 * h_dst(in->seg, h);
                a += 0.5 * (p[0] * q[1] - p[1] * q[0]);
            }
        *area_total += a;
    }
    free(isdom);
    return n;
}

int pcdm_decomp_auto(const pslg *in, const pcdm_decomp_opts *o, pcdm_decomp *out, char *err,
                     size_t errlen) {
    memset(out, 0, sizeof *out);
    if (errlen) err[0] = '\0';
    if (check_opts(in, o, err, errlen)) return -1;
    const char *path = in->path[0] ? in->path : "(input)";
    int32_t P = o->nranks, K = o->nsub > 0 ? o->nsub : P;
    if (K < P)
        return fail(err, errlen, "%s: %d subdomains for %d ranks: need at least one per rank", path,
                    (int)K, (int)P);
    if (K > (1 << 24)) return fail(err, errlen, "%s: %d subdomains is too many", path, (int)K);
    trace tin;
    double *dens = NULL, atot;
    int32_t nf = input_faces(in, o, &tin, &dens, &atot);
    ctx c;
    ctx_init(&c, in, err, errlen);
    int rc = 0;
    if (nf == 0 || !(atot > 0)) {
        rc = fail(err, errlen, "%s: empty domain (zero area)", path);
        goto out;
    }
    if (K < nf) {
        rc = fail(err, errlen, "%s: the domain has %d separate faces, more than %d subdomains",
                  path, (int)nf, (int)K);
        goto out;
    }
    c.hard_angle = fmax(30, fmin(o->min_angle, 60));
    double tol = o->balance_tol > 0 ? o->balance_tol : DEFAULT_TOL;
    c.tol_level = tol;
    c.min_cut = MIN_CUT_REL * sqrt(atot);
    c.retries = 64;
    c.nsub = K;
    c.target = mesh_xmalloc((size_t)K * sizeof *c.target, 1);
    c.owner = mesh_xmalloc((size_t)K * sizeof *c.owner, 1);
    c.sub = mesh_xcalloc((size_t)K, sizeof *c.sub);
    c.density = mesh_xcalloc((size_t)K, sizeof *c.density);
    plan_targets(K, P, o->imbalance, c.target, c.owner);
    /* domain faces become regions; each takes a contiguous range of subdomains */
    double wtot = 0, wacc = 0, tacc = 0;
    eset *reg = mesh_xcalloc((size_t)nf, sizeof *reg);
    double *rw = mesh_xcalloc((size_t)nf, sizeof *rw), *rd = mesh_xcalloc((size_t)nf, sizeof *rd);
    int32_t r = 0;
    for (int32_t f = 0; f < tin.nface; f++) {
        if (!(dens[f] > 0)) continue;
        for (int32_t h = 0; h < tin.nh; h++)
            if (tin.cface[tin.cyc[h]] == f)
                eset_push(&reg[r], h_org(in->seg, h), h_dst(in->seg, h), h / 2);
        int32_t *fc = mesh_xmalloc((size_t)reg[r].n * sizeof *fc, 1);
        int32_t got = faces_of(&c, c.nv, NULL, &reg[r], fc);
        free(fc);
        if (got != 1) {
            rc = fail(err, errlen,
                      "%s: automatic decomposition needs boundary cycles that do not touch "
                      "and no dangling segments; give the cuts with a cuts file",
                      path);
            break;
        }
        rd[r] = dens[f];
        rw[r] = eset_area(&c, c.nv, NULL, &reg[r]) * dens[f];
        wtot += rw[r];
        r++;
    }
    int32_t i0 = 0;
    for (r = 0; r < nf && rc == 0; r++) {
        wacc += rw[r];
        int32_t i1 = i0 + 1;
        tacc += c.target[i0];
        if (r == nf - 1) {
            i1 = K;
        } else {
            while (i1 < K - (nf - 1 - r) && tacc + 0.5 * c.target[i1] < wacc / wtot)
                tacc += c.target[i1++];
        }
        rc = split_region(&c, &reg[r], i0, i1, rd[r], tol);
        i0 = i1;
    }
    for (r = 0; r < nf; r++)
        eset_free(&reg[r]);
    free(reg);
    free(rw);
    free(rd);
    if (rc) goto out;
    out->nsub = K;
    out->nranks = P;
    out->sub_seed = mesh_xmalloc(2 * (size_t)K * sizeof *out->sub_seed, 1);
    for (int32_t s = 0; s < K; s++)
        face_seed(&c, &c.sub[s], out->sub_seed + 2 * s);
    build_segments(&c, out);
    rc = finish(&c, out, 1, dens, &tin);
    if (rc) goto out;
    out->sub_target = mesh_xmalloc((size_t)K * sizeof *out->sub_target, 1);
    out->sub_owner = mesh_xmalloc((size_t)K * sizeof *out->sub_owner, 1);
    memcpy(out->sub_target, c.target, (size_t)K * sizeof *c.target);
    memcpy(out->sub_owner, c.owner, (size_t)K * sizeof *c.owner);
out:
    if (rc) pcdm_decomp_free(out);
    ctx_free(&c);
    trace_free(&tin);
    free(dens);
    return rc;
}

/* ------------------------------------------------------------------------------------------ */
/* Cuts files                                                                                 */

typedef struct rawcut {
    double p[2][2];
    int32_t line;
    int32_t v[2]; /* resolved endpoint vertices */
    int32_t par;  /* parent id of this cut */
} rawcut;

/* Resolves endpoint e of cut i: an existing vertex, a point on an input segment, a point on
 * another cut, or (provisionally) a free vertex shared with other cuts' endpoints. */
static int32_t resolve_endpoint(ctx *c, rawcut *cuts, int32_t ncut, int32_t i, int e, double tol,
                                uint8_t *onbound) {
    const double *p = cuts[i].p[e];
    for (int32_t v = 0; v < c->nv; v++)
        if (hypot(c->xy[2 * v] - p[0], c->xy[2 * v + 1] - p[1]) <= tol) {
            return v;
        }
    const pslg *in = c->in;
    for (int32_t s = 0; s < in->nsegs; s++) {
        const double *A = in->xy + 2 * in->seg[2 * s], *B = in->xy + 2 * in->seg[2 * s + 1];
        if (dist_point_seg(p, A, B) > tol) continue;
        double dx = B[0] - A[0], dy = B[1] - A[1];
        double t = ((p[0] - A[0]) * dx + (p[1] - A[1]) * dy) / (dx * dx + dy * dy);
        *onbound = 1;
        return ctx_add_vertex(c, A[0] + t * dx, A[1] + t * dy, s);
    }
    for (int32_t j = 0; j < ncut; j++) {
        if (j == i) continue;
        const double *A = cuts[j].p[0], *B = cuts[j].p[1];
        if (dist_point_seg(p, A, B) > tol || hypot(p[0] - A[0], p[1] - A[1]) <= tol ||
            hypot(p[0] - B[0], p[1] - B[1]) <= tol)
            continue;
        double dx = B[0] - A[0], dy = B[1] - A[1];
        double t = ((p[0] - A[0]) * dx + (p[1] - A[1]) * dy) / (dx * dx + dy * dy);
        *onbound = 1;
        return ctx_add_vertex(c, A[0] + t * dx, A[1] + t * dy, cuts[j].par);
    }
    return ctx_add_vertex(c, p[0], p[1], -2); /* free: must be shared with another cut */
}

int pcdm_decomp_read_cuts(const char *path, const pslg *in, const pcdm_decomp_opts *o,
                          pcdm_decomp *out, char *err, size_t errlen) {
    memset(out, 0, sizeof *out);
    if (errlen) err[0] = '\0';
    if (check_opts(in, o, err, errlen)) return -1;
    FILE *fp = fopen(path, "r");
    if (!fp) return fail(err, errlen, "%s: cannot open: %s", path, strerror(errno));
    rawcut *cuts = NULL;
    int32_t ncut = 0, capc = 0, lineno = 0;
    char buf[4096];
    int rc = 0;
    while (fgets(buf, sizeof buf, fp)) {
        lineno++;
        size_t len = strlen(buf);
        if (len == sizeof buf - 1 && buf[len - 1] != '\n' && !feof(fp)) {
            rc = fail(err, errlen, "%s:%d: line too long", path, (int)lineno);
            break;
        }
        char *hash = strchr(buf, '#');
        if (hash) *hash = '\0';
        char *s = buf, *end;
        double v[4];
        while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')
            s++;
        if (!*s) continue;
        int k;
        for (k = 0; k < 4; k++) {
            errno = 0;
            v[k] = strtod(s, &end);
            if (end == s) break;
            s = end;
        }
        while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')
            s++;
        if (k < 4 || *s) {
            rc = fail(err, errlen, "%s:%d: expected four numbers \"x1 y1 x2 y2\"", path,
                      (int)lineno);
            break;
        }
        if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]) || !isfinite(v[3])) {
            rc = fail(err, errlen, "%s:%d: non-finite coordinate", path, (int)lineno);
            break;
        }
        if (ncut == capc) {
            capc = capc ? 2 * capc : 16;
            cuts = mesh_xrealloc(cuts, (size_t)capc * sizeof *cuts, 1);
        }
        rawcut *rc_ = &cuts[ncut++];
        rc_->p[0][0] = v[0];
        rc_->p[0][1] = v[1];
        rc_->p[1][0] = v[2];
        rc_->p[1][1] = v[3];
        rc_->line = lineno;
    }
    if (rc == 0 && ferror(fp)) rc = fail(err, errlen, "%s: read error", path);
    fclose(fp);
    if (rc) {
        free(cuts);
        return rc;
    }
    trace tin;
    double *dens = NULL, atot;
    int32_t nf = input_faces(in, o, &tin, &dens, &atot);
    ctx c;
    ctx_init(&c, in, err, errlen);
    const char *ipath = in->path[0] ? in->path : "(input)";
    uint8_t *onb = NULL;
    if (nf == 0 || !(atot > 0)) {
        rc = fail(err, errlen, "%s: empty domain (zero area)", ipath);
        goto out;
    }
    double tol = SNAP_REL * c.scale;
    for (int32_t i = 0; i < ncut && rc == 0; i++)
        if (hypot(cuts[i].p[0][0] - cuts[i].p[1][0], cuts[i].p[0][1] - cuts[i].p[1][1]) <= tol)
            rc = fail(err, errlen, "%s:%d: cut has zero length", path, (int)cuts[i].line);
    if (rc) goto out;
    /* parents first (endpoints filled below), so that T-junctions can name them */
    for (int32_t i = 0; i < ncut; i++)
        cuts[i].par = ctx_add_parent(&c, -1, -1, -1, cuts[i].line);
    onb = mesh_xcalloc(2 * (size_t)ncut + 1, 1);
    for (int32_t i = 0; i < ncut; i++)
        for (int e = 0; e < 2; e++) {
            cuts[i].v[e] = resolve_endpoint(&c, cuts, ncut, i, e, tol, &onb[2 * i + e]);
            c.pa[cuts[i].par] = e == 0 ? cuts[i].v[0] : c.pa[cuts[i].par];
            c.pb[cuts[i].par] = cuts[i].v[1];
        }
    for (int32_t i = 0; i < ncut && rc == 0; i++) {
        if (cuts[i].v[0] == cuts[i].v[1]) {
            rc = fail(err, errlen, "%s:%d: cut has zero length", path, (int)cuts[i].line);
            break;
        }
        for (int e = 0; e < 2 && rc == 0; e++) {
            int32_t v = cuts[i].v[e];
            if (v < in->nverts || onb[2 * i + e]) continue;
            int shared = 0;
            for (int32_t j = 0; j < ncut; j++)
                if (j != i && (cuts[j].v[0] == v || cuts[j].v[1] == v)) shared = 1;
            if (!shared)
                rc = fail(err, errlen,
                          "%s:%d: endpoint (%.17g, %.17g) is not on the domain boundary or on "
                          "another cut",
                          path, (int)cuts[i].line, cuts[i].p[e][0], cuts[i].p[e][1]);
        }
    }
    if (rc) goto out;
    /* crossings: a cut may meet another segment only where one ends on the other */
    for (int32_t i = 0; i < ncut && rc == 0; i++) {
        int32_t pi = cuts[i].par;
        const double *a = c.xy + 2 * c.pa[pi], *b = c.xy + 2 * c.pb[pi];
        for (int32_t q = 0; q < c.npar && rc == 0; q++) {
            if (q == pi) continue;
            int32_t qa = c.pa[q], qb = c.pb[q];
            int32_t sv = -1, o1 = -1, o2 = -1; /* a shared endpoint and the other ends */
            for (int e1 = 0; e1 < 2; e1++)
                for (int e2 = 0; e2 < 2; e2++)
                    if ((e1 ? c.pb[pi] : c.pa[pi]) == (e2 ? qb : qa)) {
                        sv = e1 ? c.pb[pi] : c.pa[pi];
                        o1 = e1 ? c.pa[pi] : c.pb[pi];
                        o2 = e2 ? qa : qb;
                    }
            int tee = c.vpar[c.pa[pi]] == q || c.vpar[c.pb[pi]] == q || c.vpar[qa] == pi ||
                      c.vpar[qb] == pi;
            const double *A = c.xy + 2 * qa, *B = c.xy + 2 * qb;
            double d1[2] = {b[0] - a[0], b[1] - a[1]}, d2[2] = {B[0] - A[0], B[1] - A[1]};
            int collinear = line_angle(d1, d2) <= 1e-9;
            if (sv >= 0) {
                const double *S = c.xy + 2 * sv, *P1 = c.xy + 2 * o1, *P2 = c.xy + 2 * o2;
                if (!collinear ||
                    (P1[0] - S[0]) * (P2[0] - S[0]) + (P1[1] - S[1]) * (P2[1] - S[1]) < 0)
                    continue;
            } else if (tee) {
                if (!collinear) continue;
            } else if (dist_seg_seg(a, b, A, B) > tol) {
                continue;
            }
            if (q < in->nsegs)
                rc = fail(err, errlen, "%s:%d: cut crosses or overlaps input segment %d (%s:%d)",
                          path, (int)cuts[i].line, (int)(q + in->first_index),
                          in->segpath[0] ? in->segpath : ipath, in->sline ? (int)in->sline[q] : 0);
            else
                rc = fail(err, errlen, "%s:%d: cut crosses or overlaps the cut on line %d", path,
                          (int)cuts[i].line, (int)c.pline[q]);
        }
    }
    if (rc) goto out;
    build_segments(&c, out); /* free endpoints (vpar -2) lie on no parent */
    rc = finish(&c, out, 0, dens, &tin);
    if (rc) goto out;
    /* every cut piece must separate two different subdomains */
    for (int32_t s = out->nboundary; s < out->g.nsegs && rc == 0; s++) {
        int32_t l = out->seg_sub[2 * s], r = out->seg_sub[2 * s + 1];
        int line = out->g.sline[s];
        if (l < 0 || r < 0)
            rc = fail(err, errlen, "%s:%d: cut lies (partly) outside the domain", path, line);
        else if (l == r)
            rc = fail(err, errlen, "%s:%d: cut does not separate two subdomains", path, line);
    }
    if (rc) goto out;
    int32_t worst;
    double amin = iface_min_angle(out, &worst);
    if (worst >= 0 && amin < o->min_angle) {
        rc = fail(err, errlen,
                  "%s:%d: cut meets a segment at %.2f degrees, below the quality bound %.2f", path,
                  (int)out->g.sline[worst], amin, o->min_angle);
        goto out;
    }
    int32_t K = out->nsub, P = o->nranks;
    if (o->nsub > 0 && o->nsub != K) {
        rc = fail(err, errlen, "%s: the cuts make %d subdomains, but %d were requested", path,
                  (int)K, (int)o->nsub);
        goto out;
    }
    if (K < P) {
        rc = fail(err, errlen, "%s: the cuts make %d subdomains, fewer than the %d ranks", path,
                  (int)K, (int)P);
        goto out;
    }
    out->nranks = P;
    out->sub_owner = mesh_xmalloc((size_t)K * sizeof *out->sub_owner, 1);
    out->sub_target = mesh_xmalloc((size_t)K * sizeof *out->sub_target, 1);
    assign_owners(out->sub_weight, K, P, o->imbalance, out->sub_owner);
    for (int32_t s = 0; s < K; s++)
        out->sub_target[s] = out->sub_weight[s] / out->total_weight;
out:
    if (rc) pcdm_decomp_free(out);
    free(onb);
    free(cuts);
    ctx_free(&c);
    trace_free(&tin);
    free(dens);
    return rc;
}

int pcdm_decomp_write_cuts(const pcdm_decomp *d, const char *path, char *err, size_t errlen) {
    char tmp[1100];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
        return fail(err, errlen, "%s: path too long", path);
    FILE *fp = fopen(tmp, "w");
    if (!fp) return fail(err, errlen, "%s: cannot create: %s", tmp, strerror(errno));
    fprintf(fp, "# pcdm cuts: %d subdomains; one cut per line: x1 y1 x2 y2\n", (int)d->nsub);
    for (int32_t k = 0; k < d->ncuts; k++)
        fprintf(fp, "%.17g %.17g %.17g %.17g\n", d->cut_xy[4 * k], d->cut_xy[4 * k + 1],
                d->cut_xy[4 * k + 2], d->cut_xy[4 * k + 3]);
    int bad = ferror(fp);
    if (fclose(fp) || bad) {
        remove(tmp);
        return fail(err, errlen, "%s: write error", tmp);
    }
    if (rename(tmp, path)) {
        remove(tmp);
        return fail(err, errlen, "%s: cannot rename from %s: %s", path, tmp, strerror(errno));
    }
    return 0;
}
