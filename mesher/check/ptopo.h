/* ptopo: the local topology of a rank's part of a distributed mesh: which triangles meet at a
 * vertex, hence how many triangles use an edge, in O(n) time and memory (one int32 per
 * triangle corner) -- no sort of all edges.  Used to find a part's open edges (edges of one
 * local triangle) for the interface checks (par_check.c) and, above, for the numbering and the
 * derived outputs (mesher/par/).
 * All functions are Local.
 */
#ifndef CHECK_PTOPO_H
#define CHECK_PTOPO_H

#include <stddef.h>
#include <stdint.h>

#include "io/meshio.h"

/* Vertex -> incident triangles of a mesh_flat, as compressed rows; or, when the mesher kept
 * its adjacency (mesh_take_flat), only the mask of open edges: then no rows are built and
 * the open edges come from one sequential pass over the triangles. */
typedef struct par_vtris {
    int32_t *start;       /* nverts + 2: triangles of vertex v are t[start[v] .. start[v + 1]) */
    int32_t *t;           /* 3 * ntris */
    const uint8_t *topen; /* or: per triangle, bit j = edge j is open (borrowed; start NULL) */
} par_vtris;

/* Builds x for f (counting sort by vertex); free with par_vtris_free. */
void par_vtris_build(const mesh_flat *f, par_vtris *x);

/* x from f's open-edge mask (mesh_take_flat's topen; borrowed), when topen is not NULL, else
 * par_vtris_build.  Free with par_vtris_free. */
void par_vtris_open(const mesh_flat *f, const uint8_t *topen, par_vtris *x);
void par_vtris_free(par_vtris *x);

/* Calls visit(ctx, a, b, c) once for every open edge of f (an edge of exactly one triangle),
 * directed as in that triangle (the part on its left), c the triangle's third vertex.  With a
 * mask (par_vtris_open): one pass over the triangles.  Otherwise:  Each vertex's row is read once
 * and its edges counted among the row's triangles, so the work is O(sum of squared degrees) with
 * one pass over the triangles -- no search per edge.  Returns the number of open edges. */
int64_t par_open_edges(const mesh_flat *f, const par_vtris *x,
                       void (*visit)(void *ctx, int32_t a, int32_t b, int32_t c), void *ctx);

/* Number of f's triangles that have the (undirected) edge {a, b}.  Needs the rows. */
int par_edge_uses(const mesh_flat *f, const par_vtris *x, int32_t a, int32_t b);

#endif
