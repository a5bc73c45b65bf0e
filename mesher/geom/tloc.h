/* tloc: exact point location in a fixed set of triangles, and linear interpolation over them.
 *
 * A uniform grid over the triangles' bounding box (about one cell per triangle) lists in every
 * cell the triangles whose bounding boxes meet it; a query tests the triangles of its cell
 * with the exact geom_orient2d.  Used for the size rules of -r (the old triangle containing a
 * new triangle's centroid) and --size (the background mesh), and for interpolating vertex
 * attributes on new vertices (the input's triangulation).  The triangles may be given in
 * either orientation; degenerate ones are never found.  All functions are Local; a built
 * tloc is read-only, so queries are thread-safe.
 */
#ifndef TLOC_H
#define TLOC_H

#include <stdint.h>

typedef struct tloc {
    const double *xy;   /* borrowed: vertex coordinates, 2 per vertex */
    const int32_t *tri; /* borrowed: 3 vertex indices per triangle */
    int32_t ntris;
    double x0, y0, cw, ch;
    int32_t nx, ny;
    int32_t *start; /* nx * ny + 1 */
    int32_t *item;
} tloc;

/* Builds L over triangles tri[0 .. 3 ntris) of the vertices xy (both borrowed: they must
 * outlive L and not change).  Returns 0, or -1 (too many grid entries: a pathological set). */
int tloc_build(tloc *L, const double *xy, const int32_t *tri, int32_t ntris);

/* The triangle whose closure contains p (exact; on a shared edge or vertex the lowest index),
 * or -1 when p is in none. */
int32_t tloc_find(const tloc *L, const double p[2]);

/* tloc_find, or when p is in no triangle (a point that rounding put just outside the set) the
 * triangle of p's cell or the cells around it whose smallest barycentric weight of p is the
 * largest (the nearest in that sense); -1 when there is none nearby. */
int32_t tloc_find_near(const tloc *L, const double p[2]);

/* Barycentric weights of p in triangle t (rounded; clamped to [0, 1] and summing to 1, so a
 * point just outside gets the nearest value on the triangle). */
void tloc_weights(const tloc *L, int32_t t, const double p[2], double w[3]);

void tloc_free(tloc *L);

#endif
