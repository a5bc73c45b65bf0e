/* _bgsize.h: size= as a background mesh, the size rule of pcdm._core (_core.c includes it after
 * <Python.h>, numpy and geom/geom.h).
 *
 * size={"vertices", "triangles", "vertex_sizes" | "triangle_max_area"} is the caller's
 * background mesh (arrays borrowed: the call's arguments keep them alive) with a target edge
 * length h per vertex (linear over each background triangle; a triangle is too big when its
 * area exceeds the equilateral triangle's of side h, sqrt(3)/4 h^2, the rule of ./mesh --size)
 * or a largest area per background triangle (constant over it, Triangle's .area).  The value
 * is taken at the new triangle's centroid.
 *
 * Point location: a quadtree over the background's bounding box whose leaves list the
 * triangles whose bounding boxes meet them (closed boxes, in increasing order), a node split
 * in four while it lists more than BG_LEAF triangles (to depth BG_DEPTH, within a budget of
 * listed items), so a graded background, tiny triangles in one corner, costs a query no more
 * than a uniform one.  A query descends to the leaf holding the point and takes the first
 * listed triangle whose closure holds it, decided by the exact orient2d (on a shared edge or
 * vertex the lowest index, as geom/tloc.h decides for ./mesh --size).  A centroid in no
 * triangle takes the value at its nearest point of the background: a branch-and-bound descent
 * of the tree, nearest boxes first, pruning a box farther than the best distance found (every
 * triangle's nearest point lies in a leaf that lists it).  Distances and weights are rounded:
 * they pick a size, never topology.
 *
 * Invariant: once built, a bg_size is read only, so the rule needs no GIL and no lock and may
 * be called from any thread (pcdm_unsuitable_fn's contract).
 */
#ifndef PCDM_PY_BGSIZE_H
#define PCDM_PY_BGSIZE_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { BG_LEAF = 8, BG_DEPTH = 24 };

typedef struct bg_node {
    int32_t child;        /* the first of its four children (x low/high + 2 * y low/high), or
                           * -1: a leaf */
    int32_t first, count; /* a leaf's triangles: item[first .. first + count) */
} bg_node;

typedef struct bg_size {
    const double *xy;    /* vertices, 2 per vertex (caller's coordinates) */
    const int32_t *tri;  /* 3 vertex indices per triangle, either orientation */
    const double *value; /* h per vertex, or the largest area per triangle */
    int per_triangle;
    int32_t nt;
    double *box;    /* 4 per triangle: x low, y low, x high, y high */
    double root[4]; /* the tree's box (the triangles' bounding box) */
    bg_node *node;  /* node[0] is the root */
    int32_t nnode, capnode;
    int32_t *item;
    int64_t nitem, capitem, budget;
} bg_size;

/* 1 iff the closed boxes a and b (x low, y low, x high, y high) meet. */
static inline int bg_meet(const double *a, const double *b) {
    return !(a[2] < b[0] || a[0] > b[2] || a[3] < b[1] || a[1] > b[3]);
}

/* Child k's box of the node box b (the same arithmetic in building and in queries). */
static inline void bg_child_box(const double *b, int k, double *c) {
    double xm = 0.5 * (b[0] + b[2]), ym = 0.5 * (b[1] + b[3]);
    c[0] = k & 1 ? xm : b[0];
    c[2] = k & 1 ? b[2] : xm;
    c[1] = k & 2 ? ym : b[1];
    c[3] = k & 2 ? b[3] : ym;
}

/* Node n (box b, at depth d) over the triangles items[0 .. count): a leaf, or four children
 * built in turn.  0, or -1 out of memory. */
static int bg_fill(bg_size *B, int32_t n, const double *b, int d, const int32_t *items,
                   int32_t count) {
    if (count <= BG_LEAF || d >= BG_DEPTH || B->nitem + 4 * (int64_t)count > B->budget) {
        if (B->nitem + count > B->capitem) {
            int64_t cap = 2 * (B->nitem + count);
            int32_t *p = realloc(B->item, (size_t)cap * sizeof *p);
            if (!p) return -1;
            B->item = p, B->capitem = cap;
        }
        memcpy(B->item + B->nitem, items, (size_t)count * sizeof *items);
        B->node[n] = (bg_node){-1, (int32_t)B->nitem, count};
        B->nitem += count;
        return 0;
    }
    if (B->nnode + 4 > B->capnode) {
        int32_t cap = 2 * (B->nnode + 4);
        bg_node *p = realloc(B->node, (size_t)cap * sizeof *p);
        if (!p) return -1;
        B->node = p, B->capnode = cap;
    }
    int32_t c0 = B->nnode;
    B->nnode += 4;
    B->node[n] = (bg_node){c0, 0, 0};
    int32_t *sub = malloc((size_t)count * sizeof *sub + 1);
    if (!sub) return -1;
    int rc = 0;
    for (int k = 0; k < 4 && rc == 0; k++) {
        double c[4];
        bg_child_box(b, k, c);
        int32_t m = 0;
        for (int32_t i = 0; i < count; i++)
            if (bg_meet(B->box + 4 * (size_t)items[i], c)) sub[m++] = items[i];
        rc = bg_fill(B, c0 + k, c, d + 1, sub, m);
    }
    free(sub);
    return rc;
}

static void bg_free(bg_size *B) {
    free(B->box);
    free(B->node);
    free(B->item);
    memset(B, 0, sizeof *B);
}

/* B over the arrays (nt >= 1 triangles, indices in range, values positive: checked by the
 * caller); refuses a degenerate triangle (collinear corners, exact).  0, or -1 with a
 * ValueError or MemoryError set (B then holds nothing). */
static int bg_build(bg_size *B, const double *xy, const int32_t *tri, int32_t nt,
                    const double *value, int per_triangle) {
    memset(B, 0, sizeof *B);
    for (int32_t t = 0; t < nt; t++) {
        const int32_t *v = tri + 3 * (size_t)t;
        if (geom_orient2d(xy + 2 * (size_t)v[0], xy + 2 * (size_t)v[1], xy + 2 * (size_t)v[2]) ==
            0) {
            PyErr_Format(PyExc_ValueError,
                         "size[\"triangles\"][%d]: degenerate (its corners %d %d %d are "
                         "collinear)",
                         (int)t, v[0], v[1], v[2]);
            return -1;
        }
    }
    B->xy = xy, B->tri = tri, B->value = value, B->per_triangle = per_triangle, B->nt = nt;
    B->budget = 32 * (int64_t)nt + 4096;
    B->box = malloc(4 * (size_t)nt * sizeof(double));
    int32_t *all = malloc((size_t)nt * sizeof(int32_t));
    B->capnode = 64;
    B->node = malloc((size_t)B->capnode * sizeof(bg_node));
    int rc = B->box && all && B->node ? 0 : -1;
    B->root[0] = B->root[1] = INFINITY;
    B->root[2] = B->root[3] = -INFINITY;
    for (int32_t t = 0; t < nt && rc == 0; t++) {
        double *b = B->box + 4 * (size_t)t;
        b[0] = b[1] = INFINITY;
        b[2] = b[3] = -INFINITY;
        for (int k = 0; k < 3; k++) {
            const double *p = xy + 2 * (size_t)tri[3 * (size_t)t + k];
            b[0] = fmin(b[0], p[0]), b[1] = fmin(b[1], p[1]);
            b[2] = fmax(b[2], p[0]), b[3] = fmax(b[3], p[1]);
        }
        B->root[0] = fmin(B->root[0], b[0]), B->root[1] = fmin(B->root[1], b[1]);
        B->root[2] = fmax(B->root[2], b[2]), B->root[3] = fmax(B->root[3], b[3]);
        all[t] = t;
    }
    if (rc == 0) {
        B->nnode = 1;
        rc = bg_fill(B, 0, B->root, 0, all, nt);
    }
    free(all);
    if (rc != 0) {
        bg_free(B);
        PyErr_NoMemory();
    }
    return rc;
}

/* 1 iff p lies in the closure of triangle t (exact; t is not degenerate). */
static inline int bg_inside(const bg_size *B, int32_t t, const double p[2]) {
    const int32_t *v = B->tri + 3 * (size_t)t;
    const double *a = B->xy + 2 * (size_t)v[0], *b = B->xy + 2 * (size_t)v[1],
                 *c = B->xy + 2 * (size_t)v[2];
    double s = geom_orient2d(a, b, c) > 0 ? 1 : -1;
    return s * geom_orient2d(a, b, p) >= 0 && s * geom_orient2d(b, c, p) >= 0 &&
           s * geom_orient2d(c, a, p) >= 0;
}

/* The lowest-numbered triangle whose closure holds p, or -1. */
static int32_t bg_find(const bg_size *B, const double p[2]) {
    double pb[4] = {p[0], p[1], p[0], p[1]}, b[4];
    if (!bg_meet(pb, B->root)) return -1;
    memcpy(b, B->root, sizeof b);
    int32_t n = 0;
    while (B->node[n].child >= 0) {
        double xm = 0.5 * (b[0] + b[2]), ym = 0.5 * (b[1] + b[3]);
        int k = (p[0] >= xm) + 2 * (p[1] >= ym);
        bg_child_box(b, k, b);
        n = B->node[n].child + k;
    }
    const bg_node *L = &B->node[n];
    for (int32_t i = L->first; i < L->first + L->count; i++)
        if (bg_inside(B, B->item[i], p)) return B->item[i];
    return -1;
}

/* The point of segment ab nearest to p into q; returns the squared distance. */
static inline double bg_seg_nearest(const double *a, const double *b, const double p[2],
                                    double q[2]) {
    double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
    double s = l2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0;
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    q[0] = a[0] + s * dx;
    q[1] = a[1] + s * dy;
    return (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]);
}

/* The squared distance from p to the box b (0 inside). */
static inline double bg_box_dist(const double *b, const double p[2]) {
    double dx = p[0] < b[0] ? b[0] - p[0] : p[0] > b[2] ? p[0] - b[2] : 0;
    double dy = p[1] < b[1] ? b[1] - p[1] : p[1] > b[3] ? p[1] - b[3] : 0;
    return dx * dx + dy * dy;
}

/* The search below node n (box b) for the triangle nearest to p (which lies in none): *best,
 * its squared distance *bd and nearest point q, improved in place. */
static void bg_near(const bg_size *B, int32_t n, const double *b, const double p[2], int32_t *best,
                    double *bd, double q[2]) {
    const bg_node *N = &B->node[n];
    if (N->child < 0) {
        for (int32_t i = N->first; i < N->first + N->count; i++) {
            int32_t t = B->item[i];
            const int32_t *v = B->tri + 3 * (size_t)t;
            for (int e = 0; e < 3; e++) {
                double x[2];
                double d = bg_seg_nearest(B->xy + 2 * (size_t)v[e],
                                          B->xy + 2 * (size_t)v[(e + 1) % 3], p, x);
                if (d < *bd || (d == *bd && t < *best)) {
                    *bd = d, *best = t;
                    q[0] = x[0], q[1] = x[1];
                }
            }
        }
        return;
    }
    double c[4][4], d[4];
    int order[4] = {0, 1, 2, 3};
    for (int k = 0; k < 4; k++) {
        bg_child_box(b, k, c[k]);
        d[k] = bg_box_dist(c[k], p);
    }
    for (int i = 1; i < 4; i++) /* nearest boxes first */
        for (int j = i; j > 0 && d[order[j]] < d[order[j - 1]]; j--) {
            int x = order[j];
            order[j] = order[j - 1], order[j - 1] = x;
        }
    for (int i = 0; i < 4; i++)
        if (d[order[i]] <= *bd) bg_near(B, N->child + order[i], c[order[i]], p, best, bd, q);
}

/* The rule (mesh_rules' unsuitable, in the caller's units): 1 iff the triangle (corners,
 * area) is too big for the size at its centroid. */
static int bg_unsuitable(const bg_size *B, const double *const corner[3], double area) {
    double c[2] = {(corner[0][0] + corner[1][0] + corner[2][0]) / 3,
                   (corner[0][1] + corner[1][1] + corner[2][1]) / 3};
    double q[2] = {c[0], c[1]};
    int32_t t = bg_find(B, c);
    if (t < 0) {
        double bd = INFINITY;
        bg_near(B, 0, B->root, c, &t, &bd, q);
        if (t < 0) return 0;
    }
    if (B->per_triangle) return area > B->value[t];
    /* barycentric weights of q (rounded, clamped to [0, 1], summing to 1) */
    const int32_t *v = B->tri + 3 * (size_t)t;
    const double *x[3] = {B->xy + 2 * (size_t)v[0], B->xy + 2 * (size_t)v[1],
                          B->xy + 2 * (size_t)v[2]};
    double a = geom_area(x[0], x[1], x[2]), w[3], sum = 0, h = 0;
    for (int k = 0; k < 3; k++) {
        double f = geom_area(q, x[(k + 1) % 3], x[(k + 2) % 3]) / a;
        w[k] = f < 0 ? 0 : f > 1 ? 1 : f;
        sum += w[k];
    }
    for (int k = 0; k < 3; k++)
        h += (sum > 0 ? w[k] / sum : 1.0 / 3) * B->value[v[k]];
    return area > 0.4330127018922193 * h * h; /* sqrt(3)/4 h^2 */
}

#endif
