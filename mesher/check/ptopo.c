/* ptopo.c: vertex-to-triangle rows of a part (ptopo.h).  A counting sort of the triangle
 * corners by vertex; an edge {a, b} is then counted by scanning a's few triangles (about six
 * in a quality mesh); the open edges come from one pass over the rows, each vertex's
 * neighbours (next and previous corner of each of its triangles) compared in a small scratch
 * array.  Invariant: start is the prefix sum of the vertex degrees, so
 * t[start[v] .. start[v + 1]) lists exactly the triangles with corner v, in triangle order.
 * When the mesher handed over its adjacency as an open-edge mask (par_vtris_open), no rows are
 * built: the open edges are one sequential pass over the triangles (the rows' random accesses
 * were most of the par layer's time at 10M triangles).
 */
#include "check/ptopo.h"

#include "base/base.h"

#include <stdlib.h>

void par_vtris_open(const mesh_flat *f, const uint8_t *topen, par_vtris *x) {
    if (!topen) {
        par_vtris_build(f, x);
        return;
    }
    x->start = x->t = NULL;
    x->topen = topen;
}

void par_vtris_build(const mesh_flat *f, par_vtris *x) {
    x->topen = NULL;
    x->start = mesh_xcalloc((size_t)f->nverts + 2, sizeof(int32_t));
    x->t = mesh_xmalloc(3 * (size_t)f->ntris + 1, sizeof(int32_t));
    for (size_t i = 0; i < 3 * (size_t)f->ntris; i++)
        x->start[f->tri[i] + 2]++;
    for (int32_t v = 0; v < f->nverts; v++)
        x->start[v + 2] += x->start[v + 1];
    for (int32_t t = 0; t < f->ntris; t++) /* start[v + 1] runs from v's start to v's end */
        for (int j = 0; j < 3; j++)
            x->t[x->start[f->tri[3 * (size_t)t + (size_t)j] + 1]++] = t;
}

void par_vtris_free(par_vtris *x) {
    free(x->start);
    free(x->t);
    x->start = x->t = NULL;
}

int par_edge_uses(const mesh_flat *f, const par_vtris *x, int32_t a, int32_t b) {
    MESH_CHECK(x->start != NULL);
    int n = 0;
    for (int32_t i = x->start[a]; i < x->start[a + 1]; i++) {
        const int32_t *tv = f->tri + 3 * (size_t)x->t[i];
        n += tv[0] == b || tv[1] == b || tv[2] == b;
    }
    return n;
}

int64_t par_open_edges(const mesh_flat *f, const par_vtris *x,
                       void (*visit)(void *ctx, int32_t a, int32_t b, int32_t c), void *ctx) {
    if (!x->start) { /* the mesher's mask */
        int64_t n = 0;
        for (int32_t t = 0; t < f->ntris; t++) {
            if (!x->topen[t]) continue;
            const int32_t *tv = f->tri + 3 * (size_t)t;
            for (int j = 0; j < 3; j++)
                if (x->topen[t] >> j & 1) {
                    visit(ctx, tv[j], tv[(j + 1) % 3], tv[(j + 2) % 3]);
                    n++;
                }
        }
        return n;
    }
    int32_t maxdeg = 0;
    for (int32_t v = 0; v < f->nverts; v++)
        if (x->start[v + 1] - x->start[v] > maxdeg) maxdeg = x->start[v + 1] - x->start[v];
    int32_t *nb = mesh_xmalloc(2 * (size_t)maxdeg + 1, sizeof(int32_t)), *pv = nb + maxdeg;
    int64_t n = 0;
    for (int32_t a = 0; a < f->nverts; a++) {
        int32_t d = x->start[a + 1] - x->start[a];
        for (int32_t i = 0; i < d; i++) {
            const int32_t *tv = f->tri + 3 * (size_t)x->t[x->start[a] + i];
            int k = tv[0] == a ? 0 : tv[1] == a ? 1 : 2;
            nb[i] = tv[(k + 1) % 3]; /* the triangle's edge a -> nb[i] */
            pv[i] = tv[(k + 2) % 3];
        }
        for (int32_t i = 0; i < d; i++) { /* edge a -> nb[i]: its triangles among a's */
            int32_t b = nb[i], uses = 0;
            for (int32_t j = 0; j < d; j++)
                uses += (nb[j] == b) + (pv[j] == b);
            if (uses == 1) {
                visit(ctx, a, b, pv[i]);
                n++;
            }
        }
    }
    free(nb);
    return n;
}
