/* ptopo.c: vertex-to-triangle rows of a part (ptopo.h).  A counting sort of the triangle
 * corners by vertex; an edge {a, b} is then counted by scanning a's few triangles (about six
 * in a quality mesh).  Invariant: start is the prefix sum of the vertex degrees, so
 * t[start[v] .. start[v + 1]) lists exactly the triangles with corner v, in triangle order.
 */
#include "par/ptopo.h"

#include "base/base.h"

#include <stdlib.h>

void par_vtris_build(const mesh_flat *f, par_vtris *x) {
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
    int n = 0;
    for (int32_t i = x->start[a]; i < x->start[a + 1]; i++) {
        const int32_t *tv = f->tri + 3 * (size_t)x->t[i];
        n += tv[0] == b || tv[1] == b || tv[2] == b;
    }
    return n;
}
