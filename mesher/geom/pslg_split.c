/* pslg_split: crossing and overlapping segments split at their intersections (Triangle's
 * behaviour; pslg_check_ex with PSLG_SPLIT).
 *
 * pslg_check_ex finds the conflicting pairs with the exact geom_orient2d; this file turns each
 * pair into split points on its two segments, then replaces every split segment by its pieces.
 * The cases, each decided by the signs of exact orientation tests:
 *  - collinear overlap (both endpoints of one on the other's line): each segment is split at
 *    the other's endpoints that lie strictly inside it, so both become pieces of the union
 *    between consecutive endpoints; pieces covered twice are equal and the next normalisation
 *    drops the later copy (the earlier segment's marker stays);
 *  - proper crossing (the endpoints of each strictly on both sides of the other): a new vertex
 *    at the intersection point A + t (B - A), t = o(C,D,A) / (o(C,D,A) - o(C,D,B)), rounded to
 *    doubles, kept inside both segments' bounding boxes and on the working grid
 *    (geom_working_point).  Where to put the point is rounded arithmetic; whether the result
 *    is a valid PSLG is not: the caller checks the pieces again exactly and splits the new
 *    conflicts a rounded point made, or gives up with a clear error.  Several segments through
 *    one point would each get their own rounding of it, a few ulps apart (and tiny new
 *    crossings between them); so a crossing point within a few ulps of a crossing vertex
 *    already on either segment reuses that vertex -- again a choice of position, checked
 *    exactly afterwards.
 * A vertex of the input lying inside a segment is not a conflict: pslg_check_ex splits the
 * segment there once the crossings are resolved (no new vertex).  Invariant on return: every
 * segment of g is a piece of an input segment (endpoints in order along it), with the input
 * segment's marker and line.
 */
#include "geom/pslg_impl.h"

#include "base/base.h"
#include "geom/geom.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A split point of segment seg at vertex v; key orders the points along the segment. */
typedef struct split_pt {
    int32_t seg, v;
    double key;
    int64_t next; /* the previous point added on the same segment (-1: none) */
} split_pt;

typedef struct splitter {
    pslg *g;
    split_pt *pt;
    int64_t npt, cap;
    int32_t nv0;   /* vertices before this round: later ones are crossing vertices */
    int32_t vcap;  /* capacity of g's vertex arrays */
    int64_t *head; /* per segment: the last point added on it (-1: none) */
} splitter;

static int sgn(double v) {
    return (v > 0) - (v < 0);
}

static const double *V(const splitter *S, int32_t v) {
    return S->g->xy + 2 * (size_t)v;
}

/* Position of p along segment s (rounded; only orders points known to lie on or near it). */
static double along(const splitter *S, int32_t s, const double *p) {
    const double *a = V(S, S->g->seg[2 * s]), *b = V(S, S->g->seg[2 * s + 1]);
    return (p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]);
}

static void add_point(splitter *S, int32_t s, int32_t v) {
    if (S->npt == S->cap) {
        S->cap = S->cap ? 2 * S->cap : 64;
        S->pt = mesh_xrealloc(S->pt, (size_t)S->cap, sizeof *S->pt);
    }
    S->pt[S->npt] = (split_pt){s, v, along(S, s, V(S, v)), S->head[s]};
    S->head[s] = S->npt++;
}

/* 1 if p (collinear with ab) lies strictly between a and b. */
static int between(const double *a, const double *b, const double *p) {
    int k = a[0] != b[0] ? 0 : 1;
    double lo = fmin(a[k], b[k]), hi = fmax(a[k], b[k]);
    return p[k] > lo && p[k] < hi;
}

/* A new vertex at p (marker 0, line of segment s, attributes interpolated along s). */
static int32_t new_vertex(splitter *S, int32_t s, const double *p) {
    pslg *g = S->g;
    if (g->nverts == S->vcap) {
        S->vcap = 2 * S->vcap + 16;
        g->xy = mesh_xrealloc(g->xy, (size_t)S->vcap, 2 * sizeof(double));
        g->vmarker = mesh_xrealloc(g->vmarker, (size_t)S->vcap, sizeof(int32_t));
        g->vline = mesh_xrealloc(g->vline, (size_t)S->vcap, sizeof(int32_t));
        if (g->nattr > 0)
            g->vattr = mesh_xrealloc(g->vattr, (size_t)S->vcap * (size_t)g->nattr, sizeof(double));
    }
    int32_t v = g->nverts++, a = g->seg[2 * s], b = g->seg[2 * s + 1];
    g->xy[2 * (size_t)v] = p[0];
    g->xy[2 * (size_t)v + 1] = p[1];
    g->vmarker[v] = 0;
    g->vline[v] = g->sline ? g->sline[s] : 0;
    if (g->nattr > 0 && g->vattr) {
        double l2 = geom_dist2(V(S, a), V(S, b)),
               w = l2 > 0 ? sqrt(geom_dist2(V(S, a), p) / l2) : 0;
        w = w < 0 ? 0 : w > 1 ? 1 : w;
        for (int k = 0; k < g->nattr; k++) {
            double x = g->vattr[(size_t)a * g->nattr + k], y = g->vattr[(size_t)b * g->nattr + k];
            g->vattr[(size_t)v * g->nattr + k] = x + w * (y - x);
        }
    }
    return v;
}

/* A crossing vertex already on segment s within tol of p (per axis), or -1. */
static int32_t near_vertex(const splitter *S, int32_t s, const double *p, double tol) {
    for (int64_t i = S->head[s]; i >= 0; i = S->pt[i].next) {
        const split_pt *q = &S->pt[i];
        if (q->v < S->nv0) continue;
        const double *x = V(S, q->v);
        if (fabs(x[0] - p[0]) <= tol && fabs(x[1] - p[1]) <= tol) return q->v;
    }
    return -1;
}

static void split_crossing(splitter *S, int32_t s, int32_t t) {
    const pslg *g = S->g;
    const double *A = V(S, g->seg[2 * s]), *B = V(S, g->seg[2 * s + 1]);
    const double *C = V(S, g->seg[2 * t]), *D = V(S, g->seg[2 * t + 1]);
    double oa = geom_orient2d(C, D, A), ob = geom_orient2d(C, D, B);
    double u = oa / (oa - ob); /* opposite signs (exact): in (0, 1) up to rounding */
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    double p[2] = {A[0] + u * (B[0] - A[0]), A[1] + u * (B[1] - A[1])};
    for (int k = 0; k < 2; k++) { /* inside both bounding boxes */
        double lo = fmax(fmin(A[k], B[k]), fmin(C[k], D[k]));
        double hi = fmin(fmax(A[k], B[k]), fmax(C[k], D[k]));
        p[k] = p[k] < lo ? lo : p[k] > hi ? hi : p[k];
    }
    geom_working_point(p);
    const double *E[4] = {A, B, C, D};
    int32_t ev[4] = {g->seg[2 * s], g->seg[2 * s + 1], g->seg[2 * t], g->seg[2 * t + 1]};
    double mag = 0;
    for (int k = 0; k < 4; k++) {
        mag = fmax(mag, fmax(fabs(E[k][0]), fabs(E[k][1])));
        if (E[k][0] == p[0] && E[k][1] == p[1]) { /* rounded onto an endpoint: split there */
            if (k >= 2)
                add_point(S, s, ev[k]);
            else
                add_point(S, t, ev[k]);
            return;
        }
    }
    double tol = ldexp(mag, -46); /* a few ulps of the largest coordinate */
    int32_t v = near_vertex(S, s, p, tol);
    if (v < 0) v = near_vertex(S, t, p, tol);
    if (v < 0) v = new_vertex(S, s, p);
    add_point(S, s, v);
    add_point(S, t, v);
}

static void split_pair(splitter *S, int32_t s, int32_t t) {
    const pslg *g = S->g;
    int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1], c = g->seg[2 * t], d = g->seg[2 * t + 1];
    const double *A = V(S, a), *B = V(S, b), *C = V(S, c), *D = V(S, d);
    if (sgn(geom_orient2d(A, B, C)) == 0 && sgn(geom_orient2d(A, B, D)) == 0) {
        /* collinear overlap: each at the other's endpoints strictly inside it */
        if (c != a && c != b && between(A, B, C)) add_point(S, s, c);
        if (d != a && d != b && between(A, B, D)) add_point(S, s, d);
        if (a != c && a != d && between(C, D, A)) add_point(S, t, a);
        if (b != c && b != d && between(C, D, B)) add_point(S, t, b);
        return;
    }
    split_crossing(S, s, t);
}

static int cmp_pt(const void *x, const void *y) {
    const split_pt *p = x, *q = y;
    if (p->seg != q->seg) return p->seg < q->seg ? -1 : 1;
    if (p->key != q->key) return p->key < q->key ? -1 : 1;
    return (p->v > q->v) - (p->v < q->v);
}

void pslg_split_pairs(pslg *g, const int32_t *pairs, int64_t npairs) {
    splitter S = {g, NULL, 0, 0, g->nverts, g->nverts, NULL};
    S.head = mesh_xmalloc((size_t)g->nsegs + 1, sizeof *S.head);
    for (int32_t s = 0; s < g->nsegs; s++)
        S.head[s] = -1;
    if (!g->vmarker) g->vmarker = mesh_xcalloc((size_t)g->nverts + 1, sizeof(int32_t));
    if (!g->vline) g->vline = mesh_xcalloc((size_t)g->nverts + 1, sizeof(int32_t));
    for (int64_t k = 0; k < npairs; k++)
        split_pair(&S, pairs[2 * k], pairs[2 * k + 1]);
    free(S.head);
    qsort(S.pt, (size_t)S.npt, sizeof *S.pt, cmp_pt);
    /* the pieces, segment by segment in the file's order */
    int32_t ns = g->nsegs;
    int64_t cap = (int64_t)ns + S.npt;
    int32_t *seg = mesh_xmalloc((size_t)cap + 1, 2 * sizeof(int32_t));
    int32_t *smk = mesh_xmalloc((size_t)cap + 1, sizeof(int32_t));
    int32_t *sln = mesh_xmalloc((size_t)cap + 1, sizeof(int32_t));
    int64_t n = 0, i = 0;
    for (int32_t s = 0; s < ns; s++) {
        int32_t prev = g->seg[2 * s], last = g->seg[2 * s + 1];
        for (;;) {
            int from_pt = i < S.npt && S.pt[i].seg == s;
            int32_t v = from_pt ? S.pt[i++].v : last;
            const double *p = V(&S, prev), *q = V(&S, v);
            if (v != prev && (p[0] != q[0] || p[1] != q[1])) {
                seg[2 * n] = prev;
                seg[2 * n + 1] = v;
                smk[n] = g->smarker ? g->smarker[s] : 0;
                sln[n] = g->sline ? g->sline[s] : 0;
                n++;
                prev = v;
            }
            if (!from_pt) break;
        }
    }
    free(S.pt);
    pslg_set_segments(g, seg, smk, sln, (int32_t)n);
}

void pslg_set_segments(pslg *g, int32_t *seg, int32_t *smk, int32_t *sln, int32_t n) {
    free(g->seg);
    free(g->smarker);
    free(g->sline);
    g->seg = seg;
    g->smarker = smk;
    g->sline = sln;
    g->nsegs = n;
}
