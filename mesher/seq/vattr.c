/* vattr: linear interpolation of the input's vertex attributes on new vertices (vattr.h).
 *
 * Builds the CDT of the input afresh (mesh_build_cdt: its vertices are the input's, in the
 * input's numbering, so its triangles index pslg.vattr directly), indexes its triangles with a
 * tloc, recognises input vertices by their exact coordinates (a sorted copy of the input's,
 * binary search), and interpolates every other vertex barycentrically.  Cost: one CDT of the
 * input and one point location per vertex; only when the input has attributes.
 */
#include "seq/vattr.h"

#include "base/base.h"
#include "geom/geom.h"
#include "geom/tloc.h"
#include "seq/mesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct vkey {
    double x, y;
    int32_t v;
} vkey;

static int cmp_vkey(const void *pa, const void *pb) {
    const vkey *a = pa, *b = pb;
    if (a->x != b->x) return a->x < b->x ? -1 : 1;
    if (a->y != b->y) return a->y < b->y ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

int mesh_interpolate_attributes(const pslg *g, mesh_flat *f, char *err, size_t errlen) {
    if (g->nattr <= 0 || !g->vattr) return 0;
    mesh m;
    mesh_init(&m);
    if (mesh_build_cdt(&m, g, NULL, err, errlen) != 0) {
        mesh_free(&m);
        return -1;
    }
    mesh_flat c;
    mesh_to_flat(&m, &c);
    mesh_free(&m);
    tloc L;
    if (tloc_build(&L, c.xy, c.tri, c.ntris) != 0) {
        mesh_flat_free(&c);
        snprintf(err, errlen, "too many triangles to interpolate vertex attributes");
        return -1;
    }
    int na = g->nattr;
    vkey *k = mesh_xmalloc((size_t)g->nverts + 1, sizeof *k);
    for (int32_t v = 0; v < g->nverts; v++)
        k[v] = (vkey){g->xy[2 * (size_t)v], g->xy[2 * (size_t)v + 1], v};
    qsort(k, (size_t)g->nverts, sizeof *k, cmp_vkey);
    double *at = mesh_xmalloc((size_t)f->nverts * (size_t)na + 1, sizeof(double));
    for (int32_t v = 0; v < f->nverts; v++) {
        const double *p = f->xy + 2 * (size_t)v;
        double *out = at + (size_t)v * na;
        vkey key = {p[0], p[1], -1};
        int32_t lo = 0, hi = g->nverts; /* first key >= (x, y, -1) */
        while (lo < hi) {
            int32_t mid = lo + (hi - lo) / 2;
            if (cmp_vkey(&k[mid], &key) < 0)
                lo = mid + 1;
            else
                hi = mid;
        }
        if (lo < g->nverts && k[lo].x == p[0] && k[lo].y == p[1]) {
            memcpy(out, g->vattr + (size_t)k[lo].v * na, (size_t)na * sizeof(double));
            continue;
        }
        int32_t t = tloc_find_near(&L, p);
        if (t < 0) {
            memset(out, 0, (size_t)na * sizeof(double));
            continue;
        }
        double w[3];
        tloc_weights(&L, t, p, w);
        const int32_t *tv = c.tri + 3 * (size_t)t;
        for (int a = 0; a < na; a++)
            out[a] = w[0] * g->vattr[(size_t)tv[0] * na + a] +
                     w[1] * g->vattr[(size_t)tv[1] * na + a] +
                     w[2] * g->vattr[(size_t)tv[2] * na + a];
    }
    free(k);
    tloc_free(&L);
    mesh_flat_free(&c);
    free(f->vattr);
    f->vattr = at;
    f->nattr = na;
    return 0;
}
