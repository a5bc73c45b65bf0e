/* pslg_faces: the faces of a PSLG's segment arrangement, and what is measured on them.
 *
 * The arrangement is a half-edge structure: the segments (pslg_check has split them at every
 * vertex lying on them), the outgoing half-edges of every vertex sorted counter-clockwise by an
 * exact angular order (quadrant, then geom_orient2d), so the face to the left of each half-edge
 * is traced by one step per half-edge.  Closed walks are classified by the exact sign of their
 * area, negative walks (islands and holes' outlines) attached to the bounded face enclosing them
 * (exact point-in-walk tests), and the faces reachable from a hole point removed.  From the faces:
 * pslg_domain_area measures the domain from the PSLG alone, so the validator can compare a
 * mesh against an independent figure; pslg_regions_build maps the region points onto faces, so
 * the validator finds each triangle's region without the mesher's labels;
 * pslg_input_angles lists the small angles between segments at a vertex; pslg_segment_pieces
 * and pslg_boundary_markers tell which segments border the domain (Triangle's marker rules).
 * Requires pslg_check's invariant; topology is decided only by exact predicates, the areas are
 * rounded sums whose signs are forced to the exact ones.
 */
#include "geom/pslg.h"

#include "base/base.h"
#include "geom/geom.h"
#include "geom/pslg_impl.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- arrangement ----------- */

/* Half-edge structure of the segment arrangement: the segments as edges (pslg_check's
 * invariant: no vertex lies inside a segment), outgoing half-edges of each vertex sorted
 * counter-clockwise. */
typedef struct arr {
    const double *xy;
    int32_t nv, ne;  /* vertices, undirected edges */
    int32_t *org;    /* 2*ne: origin of half-edge h; h^1 is its twin */
    int32_t *vstart; /* nv+1: outgoing half-edges of v are out[vstart[v] .. vstart[v+1]) */
    int32_t *out;    /* 2*ne */
    int32_t *pos;    /* 2*ne: position of h in out */
} arr;

static int quadrant(double dx, double dy) {
    if (dx > 0 && dy >= 0) return 0;
    if (dx <= 0 && dy > 0) return 1;
    if (dx < 0 && dy <= 0) return 2;
    return 3;
}

/* Angular order of half-edges leaving the same vertex (exact). */
static int cmp_angle(const void *ctx, int32_t h1, int32_t h2) {
    const arr *A = ctx;
    const double *o = A->xy + 2 * A->org[h1];
    const double *p = A->xy + 2 * A->org[h1 ^ 1], *q = A->xy + 2 * A->org[h2 ^ 1];
    int q1 = quadrant(p[0] - o[0], p[1] - o[1]), q2 = quadrant(q[0] - o[0], q[1] - o[1]);
    if (q1 != q2) return q1 < q2 ? -1 : 1;
    double d = geom_orient2d(o, p, q);
    return d > 0 ? -1 : d < 0 ? 1 : 0;
}

static void arr_free(arr *A) {
    free(A->org);
    free(A->vstart);
    free(A->out);
    free(A->pos);
}

/* Builds the arrangement of g's segments (free with arr_free). */
static void arr_build(const pslg *g, arr *A) {
    memset(A, 0, sizeof *A);
    A->xy = g->xy;
    A->nv = g->nverts;
    int32_t n = g->nverts, ns = g->nsegs;
    /* the edges: the segments (no vertex lies inside one: pslg_check's invariant), each as its
     * sorted endpoints, in (lo, hi) order, once */
    uint64_t *ek = mesh_xmalloc((size_t)(ns > 0 ? ns : 0) + 1, sizeof *ek);
    size_t ne = 0;
    for (int32_t s = 0; s < ns; s++) {
        uint32_t a = (uint32_t)g->seg[2 * s], b = (uint32_t)g->seg[2 * s + 1];
        if (a != b) ek[ne++] = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
    }
    mesh_sort_u64(ek, ne);
    size_t m = 0;
    for (size_t i = 0; i < ne; i++)
        if (m == 0 || ek[i] != ek[m - 1]) ek[m++] = ek[i];
    ne = m;
    A->ne = (int32_t)ne;
    A->org = mesh_xmalloc(2 * ne + 1, sizeof(int32_t));
    A->out = mesh_xmalloc(2 * ne + 1, sizeof(int32_t));
    A->pos = mesh_xmalloc(2 * ne + 1, sizeof(int32_t));
    A->vstart = mesh_xcalloc((size_t)n + 2, sizeof(int32_t));
    int32_t *tmp = mesh_xmalloc(2 * ne + 1, sizeof(int32_t));
    for (size_t e = 0; e < ne; e++) {
        int32_t lo = (int32_t)(ek[e] >> 32), hi = (int32_t)(ek[e] & 0xffffffffu);
        A->org[2 * e] = lo;
        A->org[2 * e + 1] = hi;
        A->vstart[lo + 1]++;
        A->vstart[hi + 1]++;
    }
    for (int32_t v = 0; v < n; v++)
        A->vstart[v + 1] += A->vstart[v];
    for (int32_t hh = 0; hh < (int32_t)(2 * ne); hh++)
        A->out[A->vstart[A->org[hh]]++] = hh;
    for (int32_t v = n; v > 0; v--)
        A->vstart[v] = A->vstart[v - 1];
    A->vstart[0] = 0;
    for (int32_t v = 0; v < n; v++) {
        int32_t *o = A->out + A->vstart[v];
        int32_t d = A->vstart[v + 1] - A->vstart[v];
        pslg_msort(o, tmp, d, cmp_angle, A);
        for (int32_t i = 0; i < d; i++)
            A->pos[o[i]] = A->vstart[v] + i;
    }
    free(ek);
    free(tmp);
}

/* The half-edge after h on the face to the left of h. */
static int32_t arr_next(const arr *A, int32_t h) {
    int32_t t = h ^ 1, v = A->org[t];
    int32_t p = A->pos[t] - 1;
    if (p < A->vstart[v]) p = A->vstart[v + 1] - 1;
    return A->out[p];
}

double pslg_input_angles(const pslg *g, double bound_deg,
                         void (*fn)(void *ctx, int32_t v, int32_t s1, int32_t s2, double deg),
                         void *ctx) {
    geom_init();
    int32_t n = g->nverts, ns = g->nsegs;
    double best = 360;
    /* every corner is at segment ends: pslg_check has split each segment at the vertices lying
     * inside it (a T-junction is two segments' ends) */
    int32_t ne = ns;
    arr A = {0};
    A.xy = g->xy;
    A.org = mesh_xmalloc(2 * (size_t)ne + 1, sizeof(int32_t));
    A.out = mesh_xmalloc(2 * (size_t)ne + 1, sizeof(int32_t));
    A.vstart = mesh_xcalloc((size_t)n + 2, sizeof(int32_t));
    int32_t *tmp = mesh_xmalloc(2 * (size_t)ne + 1, sizeof(int32_t));
    for (int32_t e = 0; e < ns; e++) {
        A.org[2 * e] = g->seg[2 * e];
        A.org[2 * e + 1] = g->seg[2 * e + 1];
    }
    for (int32_t h = 0; h < 2 * ne; h++)
        A.vstart[A.org[h] + 1]++;
    for (int32_t v = 0; v < n; v++)
        A.vstart[v + 1] += A.vstart[v];
    for (int32_t h = 0; h < 2 * ne; h++)
        A.out[A.vstart[A.org[h]]++] = h;
    for (int32_t v = n; v > 0; v--)
        A.vstart[v] = A.vstart[v - 1];
    A.vstart[0] = 0;
    for (int32_t v = 0; v < n; v++) {
        int32_t *o = A.out + A.vstart[v];
        int32_t d = A.vstart[v + 1] - A.vstart[v];
        if (d < 2) continue;
        pslg_msort(o, tmp, d, cmp_angle, &A);
        const double *c = g->xy + 2 * v;
        for (int32_t i = 0; i < d; i++) {
            int32_t h1 = o[i], h2 = o[(i + 1) % d];
            const double *p = g->xy + 2 * A.org[h1 ^ 1], *q = g->xy + 2 * A.org[h2 ^ 1];
            /* the counter-clockwise angle from p to q around c, in (0, 360]: the difference of
             * two atan2 values loses a sliver's angle entirely, so the size comes from
             * geom_angle_deg (exact cross product) and the side from orient2d */
            double deg = geom_angle_deg(p, c, q), side = geom_orient2d(c, p, q);
            if (side < 0) deg = 360 - deg;
            if (deg <= 0) deg += 360; /* coincident directions (overlapping segments) */
            if (deg < best) best = deg;
            if (deg < bound_deg && fn) fn(ctx, v, h1 >> 1, h2 >> 1, deg);
        }
    }
    free(A.org);
    free(A.out);
    free(A.vstart);
    free(tmp);
    return best;
}

/* 1 if p lies strictly inside the closed walk starting at half-edge h0 (crossing count with
 * exact side tests; edges walked in both directions cancel). */
static int in_cycle(const arr *A, int32_t h0, const double *p) {
    int in = 0;
    int32_t h = h0;
    do {
        const double *a = A->xy + 2 * A->org[h], *b = A->xy + 2 * A->org[h ^ 1];
        if ((a[1] <= p[1]) != (b[1] <= p[1])) {
            double o = geom_orient2d(a, b, p);
            if (b[1] > a[1] ? o > 0 : o < 0) in ^= 1;
        }
        h = arr_next(A, h);
    } while (h != h0);
    return in;
}

typedef struct cycle {
    int32_t h0, comp;
    int sign;          /* the exact sign of the walk's area (walk_sign): what topology uses */
    double area, face; /* signed area of the walk (rounded, its sign forced to `sign`); face
                          area (outer minus inner) */
    double x0, y0, x1, y1;
    int removed;
    int32_t encl; /* negative walks: the enclosing bounded face, or -1 */
} cycle;

static int32_t uf_find(int32_t *p, int32_t x) {
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

/* The exact sign of the area of closed walk number id starting at h0 (cid[] already holds id
 * on the whole walk).  Half-edges whose twin lies on the same walk (dangling segments, trees,
 * bridges to islands) add nothing to the area; if every half-edge is such, the area is exactly
 * 0.  The others bound the walk's region; at their lexicographically smallest vertex v every
 * one of them points into the half-plane right of v, and the most clockwise of them borders
 * the outside of the region: the face (left of each half-edge) lies inside iff that one leaves
 * v (a counter-clockwise outer boundary, positive) and outside iff it enters v (the clockwise
 * outer boundary of a component, negative).  Directions are compared by orient2d, exactly. */
static int lex_less(const double *p, const double *q) {
    return p[0] < q[0] || (p[0] == q[0] && p[1] < q[1]);
}

static int walk_sign(const arr *A, const int32_t *cid, int32_t h0, int32_t id) {
    int32_t h = h0, v = -1;
    do {
        if (cid[h ^ 1] != id)
            for (int k = 0; k < 2; k++) {
                int32_t x = A->org[h ^ k];
                if (v < 0 || lex_less(A->xy + 2 * x, A->xy + 2 * v)) v = x;
            }
        h = arr_next(A, h);
    } while (h != h0);
    if (v < 0) return 0;
    const double *pv = A->xy + 2 * v, *best = NULL;
    int out = 0;
    h = h0;
    do {
        if (cid[h ^ 1] != id && (A->org[h] == v || A->org[h ^ 1] == v)) {
            int leaves = A->org[h] == v;
            const double *q = A->xy + 2 * A->org[leaves ? h ^ 1 : h];
            if (!best || geom_orient2d(pv, q, best) > 0) { /* q clockwise of best */
                best = q;
                out = leaves;
            }
        }
        h = arr_next(A, h);
    } while (h != h0);
    return out ? 1 : -1;
}

/* The innermost positive cycle (other than component skip) strictly containing p, or -1; p
 * lies on no candidate (a hole point on no edge, or a vertex of another component).  Decided
 * exactly, without areas: a positive walk of one connected component winds once around its
 * face and the holes inside it and nowhere else, so two walks that both contain p belong to
 * different components, which share no point, and are nested; the inner one is the one whose
 * first vertex the other contains (in_cycle, orient2d). */
static int32_t enclosing(const arr *A, const cycle *cy, int32_t nc, const double *p, int32_t skip) {
    int32_t best = -1;
    for (int32_t i = 0; i < nc; i++) {
        const cycle *c = cy + i;
        if (c->sign <= 0 || c->comp == skip) continue;
        if (p[0] < c->x0 || p[0] > c->x1 || p[1] < c->y0 || p[1] > c->y1) continue;
        if (best >= 0) { /* c can only be inner if its box lies in best's */
            const cycle *b = cy + best;
            if (c->x0 < b->x0 || c->x1 > b->x1 || c->y0 < b->y0 || c->y1 > b->y1) continue;
        }
        if (!in_cycle(A, c->h0, p)) continue;
        if (best < 0 || in_cycle(A, cy[best].h0, A->xy + 2 * A->org[c->h0])) best = i;
    }
    return best;
}

/* The faces of the arrangement and which of them the domain keeps: cy[i] for each closed walk
 * (positive: a bounded face's outer boundary; negative or zero: the outer boundary of a
 * component, or a tree of dangling segments, whose face is cy[i].encl, -1 for the unbounded
 * face), cid[h] the walk of half-edge h (the
 * face to its left).  Hole points remove the face strictly containing them; one exactly on an
 * arrangement vertex or edge removes every face whose closure contains it (as the mesher's
 * carving does, cdt.c). */
typedef struct faces {
    arr A;
    cycle *cy;
    int32_t *cid, nc;
} faces;

static void faces_free(faces *F) {
    arr_free(&F->A);
    free(F->cy);
    free(F->cid);
}

/* The bounded face to the left of half-edge h, or -1 (unbounded). */
static int32_t face_left(const faces *F, int32_t h) {
    const cycle *c = F->cy + F->cid[h];
    return c->sign > 0 ? F->cid[h] : c->encl;
}

static void remove_face(faces *F, int32_t f) {
    if (f >= 0) F->cy[f].removed = 1;
}

/* Applies hole point p (see faces). */
static void faces_hole(faces *F, const pslg *g, const double *p) {
    const arr *A = &F->A;
    int on = 0;
    for (int32_t h = 0; h < 2 * A->ne; h += 2) {
        const double *a = g->xy + 2 * A->org[h], *b = g->xy + 2 * A->org[h + 1];
        int at_a = a[0] == p[0] && a[1] == p[1], at_b = b[0] == p[0] && b[1] == p[1];
        if (at_a || at_b || (geom_orient2d(a, b, p) == 0 && pslg_strictly_between(a, b, p))) {
            remove_face(F, face_left(F, h));
            remove_face(F, face_left(F, h + 1));
            on = 1;
        }
    }
    if (!on) remove_face(F, enclosing(A, F->cy, F->nc, p, -1));
}

static int faces_build(const pslg *g, faces *F) {
    memset(F, 0, sizeof *F);
    if (g->nsegs == 0) return -1;
    arr_build(g, &F->A);
    arr *A = &F->A;
    int32_t nh = 2 * A->ne, n = g->nverts;
    F->cid = mesh_xmalloc((size_t)nh, sizeof(int32_t));
    int32_t *uf = mesh_xmalloc((size_t)n, sizeof(int32_t));
    F->cy = mesh_xmalloc((size_t)nh, sizeof(cycle));
    int32_t *cid = F->cid;
    cycle *cy = F->cy;
    for (int32_t v = 0; v < n; v++)
        uf[v] = v;
    for (int32_t e = 0; e < A->ne; e++) {
        int32_t a = uf_find(uf, A->org[2 * e]), b = uf_find(uf, A->org[2 * e + 1]);
        if (a != b) uf[a] = b;
    }
    for (int32_t h = 0; h < nh; h++)
        cid[h] = -1;
    int32_t nc = 0;
    for (int32_t h0 = 0; h0 < nh; h0++) {
        if (cid[h0] >= 0) continue;
        cycle *c = cy + nc;
        const double *o = g->xy + 2 * A->org[h0];
        double sum = 0, comp = 0; /* Neumaier summation of the shoelace terms */
        c->x0 = c->x1 = o[0];
        c->y0 = c->y1 = o[1];
        int32_t h = h0;
        do {
            cid[h] = nc;
            const double *a = g->xy + 2 * A->org[h], *b = g->xy + 2 * A->org[h ^ 1];
            double t = geom_area2_accurate(o, a, b);
            double s = sum + t;
            comp += fabs(sum) >= fabs(t) ? (sum - s) + t : (t - s) + sum;
            sum = s;
            c->x0 = fmin(c->x0, a[0]);
            c->x1 = fmax(c->x1, a[0]);
            c->y0 = fmin(c->y0, a[1]);
            c->y1 = fmax(c->y1, a[1]);
            h = arr_next(A, h);
        } while (h != h0);
        c->h0 = h0;
        c->sign = walk_sign(A, cid, h0, nc);
        c->area = 0.5 * (sum + comp);
        if (c->sign == 0 || (c->sign > 0) != (c->area > 0)) /* rounding: the sign is exact */
            c->area = c->sign * DBL_MIN;
        c->face = c->area;
        c->comp = uf_find(uf, A->org[h0]);
        c->removed = 0;
        c->encl = -1;
        nc++;
    }
    free(uf);
    F->nc = nc;
    /* outer boundaries of components (negative walks) go to their enclosing face */
    for (int32_t i = 0; i < nc; i++) {
        if (cy[i].sign > 0) continue; /* zero: a tree of dangling segments */
        int32_t f = enclosing(A, cy, nc, g->xy + 2 * A->org[cy[i].h0], cy[i].comp);
        cy[i].encl = f;
        if (f >= 0) cy[f].face += cy[i].area;
    }
    for (int32_t k = 0; k < g->nholes; k++)
        faces_hole(F, g, g->holes + 2 * k);
    return 0;
}

double pslg_domain_area(const pslg *g) {
    geom_init();
    faces F;
    if (faces_build(g, &F)) return 0;
    double total = 0, comp = 0;
    for (int32_t i = 0; i < F.nc; i++)
        if (F.cy[i].sign > 0 && !F.cy[i].removed) {
            double t = F.cy[i].face, s = total + t;
            comp += fabs(total) >= fabs(t) ? (total - s) + t : (t - s) + total;
            total = s;
        }
    total += comp;
    faces_free(&F);
    return total;
}

struct pslg_regions {
    faces F;
    int32_t *freg; /* per walk: the region of its face (positive walks), or -1 */
};

/* 1 iff p lies on a segment of the arrangement (endpoints included). */
static int on_arrangement(const faces *F, const pslg *g, const double *p) {
    const arr *A = &F->A;
    for (int32_t h = 0; h < 2 * A->ne; h += 2) {
        const double *a = g->xy + 2 * A->org[h], *b = g->xy + 2 * A->org[h + 1];
        if ((a[0] == p[0] && a[1] == p[1]) || (b[0] == p[0] && b[1] == p[1]) ||
            (geom_orient2d(a, b, p) == 0 && pslg_strictly_between(a, b, p)))
            return 1;
    }
    return 0;
}

pslg_regions *pslg_regions_build(const pslg *g) {
    geom_init();
    if (g->nsegs == 0) return NULL;
    pslg_regions *R = mesh_xcalloc(1, sizeof *R);
    faces_build(g, &R->F);
    R->freg = mesh_xmalloc((size_t)R->F.nc, sizeof(int32_t));
    for (int32_t i = 0; i < R->F.nc; i++)
        R->freg[i] = -1;
    for (int32_t i = 0; i < g->nregions; i++) { /* in file order: the later one wins */
        const double *p = g->regions + 4 * i;
        if (on_arrangement(&R->F, g, p)) continue;
        int32_t f = enclosing(&R->F.A, R->F.cy, R->F.nc, p, -1);
        if (f >= 0 && !R->F.cy[f].removed) R->freg[f] = i;
    }
    return R;
}

int32_t pslg_region_at(const pslg_regions *R, const double p[2]) {
    if (!R) return -1;
    int32_t f = enclosing(&R->F.A, R->F.cy, R->F.nc, p, -1);
    return f >= 0 ? R->freg[f] : -1;
}

void pslg_regions_free(pslg_regions *R) {
    if (!R) return;
    faces_free(&R->F);
    free(R->freg);
    free(R);
}

/* 1 iff the half-edge h borders a kept face on one side or the other. */
static int borders_domain(const faces *F, int32_t h) {
    int32_t f1 = face_left(F, h), f2 = face_left(F, h ^ 1);
    return (f1 >= 0 && !F->cy[f1].removed) || (f2 >= 0 && !F->cy[f2].removed);
}

void pslg_pieces_free(pslg_pieces *P) {
    free(P->start);
    free(P->vert);
    free(P->border);
    memset(P, 0, sizeof *P);
}

/* Appends vertex v (and, after the first, the border flag of the piece ending there). */
static void piece_push(pslg_pieces *P, int32_t *cap, int32_t v, uint8_t border, int first) {
    if (P->nvert == *cap) {
        *cap = *cap ? 2 * *cap : 64;
        P->vert = mesh_xrealloc(P->vert, (size_t)*cap, sizeof *P->vert);
        P->border = mesh_xrealloc(P->border, (size_t)*cap, 1);
    }
    if (!first) P->border[P->nvert - 1] = border;
    P->border[P->nvert] = 0;
    P->vert[P->nvert++] = v;
}

/* The half-edge leaving vertex cur along a segment toward its endpoint b: the next piece of
 * the segment, whose far end is b or lies strictly between cur and b on their line (exact
 * orient2d); -1 if there is none. */
static int32_t step_toward(const faces *F, const pslg *g, int32_t cur, int32_t b) {
    const double *pc = g->xy + 2 * cur, *pb = g->xy + 2 * b;
    for (int32_t i = F->A.vstart[cur]; i < F->A.vstart[cur + 1]; i++) {
        int32_t h = F->A.out[i], w = F->A.org[h ^ 1];
        const double *pw = g->xy + 2 * w;
        if (w == b || (geom_orient2d(pc, pb, pw) == 0 && pslg_strictly_between(pc, pb, pw)))
            return h;
    }
    return -1;
}

int pslg_segment_pieces(const pslg *g, pslg_pieces *P) {
    geom_init();
    memset(P, 0, sizeof *P);
    int32_t cap = 0;
    P->start = mesh_xmalloc((size_t)g->nsegs + 1, sizeof *P->start);
    P->start[0] = 0;
    faces F;
    int have = g->nsegs > 0 && faces_build(g, &F) == 0;
    for (int32_t s = 0; s < g->nsegs; s++) {
        int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1], cur = a;
        int32_t first = P->nvert;
        piece_push(P, &cap, a, 0, 1);
        /* walk the pieces of s from a to b: at each vertex the outgoing half-edge pointing at
         * b (collinear, same direction) */
        for (int32_t steps = 0; have && cur != b && steps <= F.A.ne; steps++) {
            int32_t h = step_toward(&F, g, cur, b);
            if (h < 0) break;
            cur = F.A.org[h ^ 1];
            piece_push(P, &cap, cur, (uint8_t)borders_domain(&F, h), 0);
        }
        if (cur != b) { /* no arrangement (should not happen): the whole segment, required */
            P->nvert = first;
            piece_push(P, &cap, a, 0, 1);
            piece_push(P, &cap, b, 1, 0);
        }
        P->start[s + 1] = P->nvert;
    }
    if (have) faces_free(&F);
    return 0;
}

/* ---------------------------------------------------------------- markers --------------- */

/* 1 iff exactly one side of half-edge h is a kept face: the piece is on the domain's boundary. */
static int on_boundary(const faces *F, int32_t h) {
    int32_t f1 = face_left(F, h), f2 = face_left(F, h ^ 1);
    return ((f1 >= 0 && !F->cy[f1].removed) != 0) + ((f2 >= 0 && !F->cy[f2].removed) != 0) == 1;
}

int pslg_boundary_markers(pslg *g) {
    geom_init();
    if (g->nsegs == 0 && g->vmarker && g->nverts >= 3) { /* a point set: its hull's vertices */
        int32_t *cyc = mesh_xmalloc(2 * (size_t)g->nverts + 2, sizeof *cyc);
        int32_t h = pslg_hull(g, cyc);
        for (int32_t i = 0; i < h; i++)
            if (g->vmarker[cyc[i]] == 0) g->vmarker[cyc[i]] = 1;
        free(cyc);
    }
    if (g->nsegs == 0 || !g->smarker) return 0;
    int32_t unmarked = 0;
    for (int32_t s = 0; s < g->nsegs; s++)
        unmarked += g->smarker[s] == 0;
    if (unmarked == 0) { /* every segment marked: no face is needed (pslg_check left no vertex
                          * inside a segment, so a segment's vertices are its two ends) */
        for (int32_t s = 0; s < g->nsegs && g->vmarker; s++)
            for (int k = 0; k < 2; k++)
                if (g->vmarker[g->seg[2 * s + k]] == 0)
                    g->vmarker[g->seg[2 * s + k]] = g->smarker[s];
        return 0;
    }
    faces F;
    faces_build(g, &F); /* g has segments: it has faces */
    uint8_t *onb = mesh_xcalloc((size_t)g->nsegs + 1, 1);
    /* the vertices along each segment, in order (as pslg_segment_pieces walks them) */
    int32_t *start = mesh_xmalloc((size_t)g->nsegs + 1, sizeof(int32_t)), nv = 0, cap = 64;
    int32_t *vert = mesh_xmalloc((size_t)cap, sizeof(int32_t));
    for (int32_t s = 0; s < g->nsegs; s++) {
        int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1], cur = a;
        start[s] = nv;
        for (int32_t steps = 0; cur != b && steps <= F.A.ne; steps++) {
            int32_t h = step_toward(&F, g, cur, b);
            if (h < 0) break;
            cur = F.A.org[h ^ 1];
            if (on_boundary(&F, h)) onb[s] = 1;
            if (cur != b) {
                if (nv == cap) vert = mesh_xrealloc(vert, (size_t)(cap *= 2), sizeof(int32_t));
                vert[nv++] = cur;
            }
        }
    }
    faces_free(&F);
    if (g->vmarker) /* pass 1: the input's nonzero segment markers; pass 2: boundary ones */
        for (int pass = 0; pass < 2; pass++) {
            for (int32_t s = 0; s < g->nsegs; s++) {
                int32_t mk = g->smarker[s] ? g->smarker[s] : pass && onb[s] ? 1 : 0;
                if (!mk) continue;
                int32_t end = s + 1 < g->nsegs ? start[s + 1] : nv;
                for (int32_t i = start[s] - 2; i < end; i++) {
                    int32_t v = i < start[s] ? g->seg[2 * s + (i - start[s] + 2)] : vert[i];
                    if (g->vmarker[v] == 0) g->vmarker[v] = mk;
                }
            }
        }
    for (int32_t s = 0; s < g->nsegs; s++)
        if (g->smarker[s] == 0 && onb[s]) g->smarker[s] = 1;
    free(onb);
    free(start);
    free(vert);
    return 0;
}
