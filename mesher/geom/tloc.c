/* tloc: point location in a fixed triangle set (exact tests over a uniform grid).
 *
 * The grid has about one cell per triangle over the triangles' bounding box, at most 2048
 * cells a side.  A triangle is listed in every cell its bounding box meets: the cell of a
 * coordinate is a monotone function of it, so a point inside a triangle's box falls in a cell
 * between the cells of the box's corners, and the query needs only its own cell.  Whether the
 * point lies in a listed triangle's closure is decided by three exact orient2d signs (taken
 * with the triangle's own orientation).  Invariant: item[start[c] .. start[c+1]) lists the
 * triangles of cell c in increasing order, so ties go to the lowest index.
 */
#include "geom/tloc.h"

#include "base/base.h"
#include "geom/geom.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int32_t cell_of(double v, double v0, double w, int32_t n) {
    double c = (v - v0) / w;
    if (!(c > 0)) return 0;
    return c >= n - 1 ? n - 1 : (int32_t)c;
}

static void tri_box(const tloc *L, int32_t t, int32_t *i0, int32_t *i1, int32_t *j0, int32_t *j1) {
    const int32_t *v = L->tri + 3 * (size_t)t;
    double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
    for (int k = 0; k < 3; k++) {
        const double *p = L->xy + 2 * (size_t)v[k];
        xlo = fmin(xlo, p[0]);
        xhi = fmax(xhi, p[0]);
        ylo = fmin(ylo, p[1]);
        yhi = fmax(yhi, p[1]);
    }
    *i0 = cell_of(xlo, L->x0, L->cw, L->nx);
    *i1 = cell_of(xhi, L->x0, L->cw, L->nx);
    *j0 = cell_of(ylo, L->y0, L->ch, L->ny);
    *j1 = cell_of(yhi, L->y0, L->ch, L->ny);
}

int tloc_build(tloc *L, const double *xy, const int32_t *tri, int32_t ntris) {
    memset(L, 0, sizeof *L);
    L->xy = xy;
    L->tri = tri;
    L->ntris = ntris;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int64_t k = 0; k < 3 * (int64_t)ntris; k++) {
        const double *p = xy + 2 * (size_t)tri[k];
        x0 = fmin(x0, p[0]);
        x1 = fmax(x1, p[0]);
        y0 = fmin(y0, p[1]);
        y1 = fmax(y1, p[1]);
    }
    if (ntris == 0) x0 = y0 = x1 = y1 = 0;
    double w = x1 - x0, h = y1 - y0, n = ntris > 0 ? ntris : 1;
    double fx = w > 0 && h > 0 ? ceil(sqrt(n * w / h)) : w > 0 ? n : 1;
    double fy = w > 0 && h > 0 ? ceil(sqrt(n * h / w)) : h > 0 ? n : 1;
    L->nx = fx < 1 ? 1 : fx > 2048 ? 2048 : (int32_t)fx;
    L->ny = fy < 1 ? 1 : fy > 2048 ? 2048 : (int32_t)fy;
    L->x0 = x0;
    L->y0 = y0;
    L->cw = w > 0 ? w / L->nx : 1;
    L->ch = h > 0 ? h / L->ny : 1;
    size_t ncell = (size_t)L->nx * (size_t)L->ny;
    L->start = mesh_xcalloc(ncell + 1, sizeof(int32_t));
    int64_t total = 0;
    for (int32_t t = 0; t < ntris; t++) {
        int32_t i0, i1, j0, j1;
        tri_box(L, t, &i0, &i1, &j0, &j1);
        total += (int64_t)(i1 - i0 + 1) * (j1 - j0 + 1);
        if (total > INT32_MAX / 2) {
            tloc_free(L);
            return -1;
        }
        for (int32_t j = j0; j <= j1; j++)
            for (int32_t i = i0; i <= i1; i++)
                L->start[(size_t)j * L->nx + i + 1]++;
    }
    for (size_t c = 0; c < ncell; c++)
        L->start[c + 1] += L->start[c];
    L->item = mesh_xmalloc((size_t)total + 1, sizeof(int32_t));
    int32_t *fill = mesh_xmalloc(ncell + 1, sizeof(int32_t));
    memcpy(fill, L->start, ncell * sizeof(int32_t));
    for (int32_t t = 0; t < ntris; t++) {
        int32_t i0, i1, j0, j1;
        tri_box(L, t, &i0, &i1, &j0, &j1);
        for (int32_t j = j0; j <= j1; j++)
            for (int32_t i = i0; i <= i1; i++)
                L->item[fill[(size_t)j * L->nx + i]++] = t;
    }
    free(fill);
    return 0;
}

/* 1 iff p lies in the closure of the non-degenerate triangle t (exact). */
static int inside(const tloc *L, int32_t t, const double p[2]) {
    const int32_t *v = L->tri + 3 * (size_t)t;
    const double *a = L->xy + 2 * (size_t)v[0], *b = L->xy + 2 * (size_t)v[1],
                 *c = L->xy + 2 * (size_t)v[2];
    double o = geom_orient2d(a, b, c);
    if (o == 0) return 0;
    double s = o > 0 ? 1 : -1;
    return s * geom_orient2d(a, b, p) >= 0 && s * geom_orient2d(b, c, p) >= 0 &&
           s * geom_orient2d(c, a, p) >= 0;
}

int32_t tloc_find(const tloc *L, const double p[2]) {
    if (!L->start || !(p[0] >= L->x0 && p[1] >= L->y0)) return -1;
    int32_t i = cell_of(p[0], L->x0, L->cw, L->nx), j = cell_of(p[1], L->y0, L->ch, L->ny);
    size_t c = (size_t)j * L->nx + i;
    for (int32_t k = L->start[c]; k < L->start[c + 1]; k++)
        if (inside(L, L->item[k], p)) return L->item[k];
    return -1;
}

/* The smallest barycentric weight of p in triangle t (rounded; negative outside). */
static double min_weight(const tloc *L, int32_t t, const double p[2]) {
    const int32_t *v = L->tri + 3 * (size_t)t;
    const double *q[3] = {L->xy + 2 * (size_t)v[0], L->xy + 2 * (size_t)v[1],
                          L->xy + 2 * (size_t)v[2]};
    double a = geom_area(q[0], q[1], q[2]), w = INFINITY;
    if (a == 0) return -INFINITY;
    for (int k = 0; k < 3; k++)
        w = fmin(w, geom_area(p, q[(k + 1) % 3], q[(k + 2) % 3]) / a);
    return w;
}

int32_t tloc_find_near(const tloc *L, const double p[2]) {
    int32_t t = tloc_find(L, p);
    if (t >= 0 || !L->start) return t;
    double best = -INFINITY;
    int32_t i0 = cell_of(p[0], L->x0, L->cw, L->nx), j0 = cell_of(p[1], L->y0, L->ch, L->ny);
    for (int32_t j = j0 - 1; j <= j0 + 1; j++)
        for (int32_t i = i0 - 1; i <= i0 + 1; i++) {
            if (i < 0 || j < 0 || i >= L->nx || j >= L->ny) continue;
            size_t c = (size_t)j * L->nx + i;
            for (int32_t k = L->start[c]; k < L->start[c + 1]; k++) {
                double w = min_weight(L, L->item[k], p);
                if (w > best) {
                    best = w;
                    t = L->item[k];
                }
            }
        }
    return t;
}

void tloc_weights(const tloc *L, int32_t t, const double p[2], double w[3]) {
    const int32_t *v = L->tri + 3 * (size_t)t;
    const double *q[3] = {L->xy + 2 * (size_t)v[0], L->xy + 2 * (size_t)v[1],
                          L->xy + 2 * (size_t)v[2]};
    double a = geom_area(q[0], q[1], q[2]), sum = 0;
    for (int k = 0; k < 3; k++) {
        double x = a != 0 ? geom_area(p, q[(k + 1) % 3], q[(k + 2) % 3]) / a : 1.0 / 3;
        w[k] = x < 0 ? 0 : x > 1 ? 1 : x;
        sum += w[k];
    }
    for (int k = 0; k < 3; k++)
        w[k] = sum > 0 ? w[k] / sum : 1.0 / 3;
}

void tloc_free(tloc *L) {
    free(L->start);
    free(L->item);
    L->start = L->item = NULL;
}
