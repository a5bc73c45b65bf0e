/* meshin: the mesh to refine (-r) read as a PSLG (meshio.h: meshio_read_mesh_pslg).
 *
 * The vertices come from NAME.node (pslg_read, so messages name its lines), the triangles from
 * NAME.ele (meshio_read_triangle), segments and holes from NAME.poly or, without it, from the
 * boundary: every directed edge of a counter-clockwise triangle whose reverse is in no triangle
 * is a boundary edge with the mesh on its left.  Boundary edges are chained through vertices
 * with exactly one boundary edge in and one out (such a chain borders one outside face); each
 * chain gets one hole point, tried at the midpoint m of one of its edges moved by (m - apex)
 * 2^-k for a few k, and kept only when exact tests put it strictly on the outer side of the
 * edge and inside no triangle (tloc, closed).  A hole point in the unbounded face removes
 * nothing, so the outer boundary's is harmless.
 */
#include "io/meshio.h"

#include "base/base.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "geom/tloc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int meshio_mesh_prefix(const char *name, char *out, size_t n, char *err, size_t errlen) {
    if (strlen(name) + 8 > n) return mesh_fail(err, errlen, "%s: path too long", name);
    snprintf(out, n, "%s", name);
    static const char *const ext[] = {".node", ".ele", ".poly", ".area"};
    size_t l = strlen(out);
    for (int k = 0; k < 4; k++) {
        size_t e = strlen(ext[k]);
        if (l > e && strcmp(out + l - e, ext[k]) == 0) {
            out[l - e] = '\0';
            break;
        }
    }
    return 0;
}

void meshio_flat_orient_ccw(mesh_flat *m) {
    for (int32_t t = 0; t < m->ntris; t++) {
        int32_t *v = m->tri + 3 * (size_t)t;
        if (geom_orient2d(m->xy + 2 * (size_t)v[0], m->xy + 2 * (size_t)v[1],
                          m->xy + 2 * (size_t)v[2]) < 0) {
            int32_t x = v[1];
            v[1] = v[2];
            v[2] = x;
        }
    }
}

/* ---------------------------------------------------------------- -r: the PSLG ----------- */

typedef struct ekey {
    int32_t lo, hi, e; /* e = 3 t + j: edge j of triangle t, from v[j] to v[j+1] */
} ekey;

static int cmp_ekey(const void *x, const void *y) {
    const ekey *a = x, *b = y;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    return (a->e > b->e) - (a->e < b->e);
}

static int32_t uf_find(int32_t *p, int32_t x) {
    while (p[x] != x)
        x = p[x] = p[p[x]];
    return x;
}

/* A hole point just outside boundary edge a -> b (apex c inside), or 0 if none was found. */
static int hole_beside(const tloc *L, const double *a, const double *b, const double *c,
                       double out[2]) {
    double m[2] = {a[0] + 0.5 * (b[0] - a[0]), a[1] + 0.5 * (b[1] - a[1])};
    double d[2] = {m[0] - c[0], m[1] - c[1]};
    double side = geom_orient2d(a, b, c);
    static const int ks[] = {3, 8, 14, 20, 28};
    for (int i = 0; i < 5; i++) {
        double p[2] = {m[0] + ldexp(d[0], -ks[i]), m[1] + ldexp(d[1], -ks[i])};
        double o = geom_orient2d(a, b, p);
        if (!((side > 0 && o < 0) || (side < 0 && o > 0))) continue;
        if (tloc_find(L, p) >= 0) continue;
        out[0] = p[0];
        out[1] = p[1];
        return 1;
    }
    return 0;
}

int meshio_boundary_pslg(const mesh_flat *m, pslg *g) {
    int64_t ne = 3 * (int64_t)m->ntris;
    ekey *k = mesh_xmalloc((size_t)ne + 1, sizeof *k);
    for (int64_t e = 0; e < ne; e++) {
        int32_t a = m->tri[e], b = m->tri[e - e % 3 + (e % 3 + 1) % 3];
        k[e] = (ekey){a < b ? a : b, a < b ? b : a, (int32_t)e};
    }
    qsort(k, (size_t)ne, sizeof *k, cmp_ekey);
    int32_t nb = 0, *be = mesh_xmalloc((size_t)ne + 1, sizeof(int32_t));
    for (int64_t i = 0; i < ne;) {
        int64_t j = i + 1;
        while (j < ne && k[j].lo == k[i].lo && k[j].hi == k[i].hi)
            j++;
        if (j == i + 1) be[nb++] = k[i].e;
        i = j;
    }
    free(k);
    g->nsegs = nb;
    g->seg = mesh_xmalloc(2 * (size_t)nb + 1, sizeof(int32_t));
    g->smarker = mesh_xmalloc((size_t)nb + 1, sizeof(int32_t));
    g->sline = mesh_xcalloc((size_t)nb + 1, sizeof(int32_t));
    int32_t *indeg = mesh_xcalloc((size_t)m->nverts + 1, sizeof(int32_t));
    int32_t *outdeg = mesh_xcalloc((size_t)m->nverts + 1, sizeof(int32_t));
    int32_t *outseg = mesh_xmalloc((size_t)m->nverts + 1, sizeof(int32_t));
    for (int32_t s = 0; s < nb; s++) {
        int32_t e = be[s], a = m->tri[e], b = m->tri[e - e % 3 + (e % 3 + 1) % 3];
        g->seg[2 * s] = a;
        g->seg[2 * s + 1] = b;
        g->smarker[s] = 1;
        outdeg[a]++;
        indeg[b]++;
        outseg[a] = s;
    }
    /* chains: s joins the segment leaving its end when that vertex has one in and one out */
    int32_t *uf = mesh_xmalloc((size_t)nb + 1, sizeof(int32_t));
    for (int32_t s = 0; s < nb; s++)
        uf[s] = s;
    for (int32_t s = 0; s < nb; s++) {
        int32_t b = g->seg[2 * s + 1];
        if (indeg[b] == 1 && outdeg[b] == 1) {
            int32_t x = uf_find(uf, s), y = uf_find(uf, outseg[b]);
            if (x != y) uf[x] = y;
        }
    }
    tloc L;
    int rc = tloc_build(&L, m->xy, m->tri, m->ntris);
    uint8_t *done = mesh_xcalloc((size_t)nb + 1, 1);
    g->holes = mesh_xmalloc(2 * (size_t)nb + 1, sizeof(double));
    g->nholes = 0;
    for (int32_t s = 0; s < nb && rc == 0; s++) {
        int32_t r = uf_find(uf, s);
        if (done[r]) continue;
        int32_t e = be[s];
        const double *a = m->xy + 2 * (size_t)g->seg[2 * s],
                     *b = m->xy + 2 * (size_t)g->seg[2 * s + 1],
                     *c = m->xy + 2 * (size_t)m->tri[e - e % 3 + (e % 3 + 2) % 3];
        if (hole_beside(&L, a, b, c, g->holes + 2 * (size_t)g->nholes)) {
            g->nholes++;
            done[r] = 1;
        }
    }
    tloc_free(&L);
    free(done);
    free(uf);
    free(indeg);
    free(outdeg);
    free(outseg);
    free(be);
    return rc;
}

int meshio_read_mesh_pslg(const char *name, pslg *g, char *err, size_t errlen) {
    memset(g, 0, sizeof *g);
    char prefix[400], path[512];
    if (meshio_mesh_prefix(name, prefix, sizeof prefix, err, errlen)) return -1;
    snprintf(path, sizeof path, "%s.node", prefix);
    if (pslg_read(path, g, err, errlen)) return -1;
    /* pslg_read of a .node takes no segments; the mesh gives them */
    mesh_flat m;
    if (meshio_read_triangle(prefix, &m, err, errlen)) {
        pslg_free(g);
        return -1;
    }
    meshio_flat_orient_ccw(&m);
    snprintf(path, sizeof path, "%s.poly", prefix);
    int rc = 0;
    free(g->seg), free(g->smarker), free(g->sline), free(g->holes), free(g->regions);
    g->seg = g->smarker = g->sline = NULL;
    g->holes = g->regions = NULL;
    g->nsegs = g->nholes = g->nregions = 0;
    if (access(path, F_OK) == 0) {
        pslg p;
        rc = pslg_read_segments(path, g->nverts, g->first_index, &p, err, errlen);
        if (rc == 0) {
            g->nsegs = p.nsegs, g->seg = p.seg, g->smarker = p.smarker, g->sline = p.sline;
            g->nholes = p.nholes, g->holes = p.holes;
            g->nregions = p.nregions, g->regions = p.regions;
            p.seg = p.smarker = p.sline = NULL;
            p.holes = p.regions = NULL;
            snprintf(g->segpath, sizeof g->segpath, "%s", path);
            pslg_free(&p);
        }
    } else {
        snprintf(g->segpath, sizeof g->segpath, "%s.ele", prefix);
        if (meshio_boundary_pslg(&m, g) != 0)
            rc = mesh_fail(err, errlen, "%s.ele: too many triangles to index", prefix);
    }
    mesh_flat_free(&m);
    if (rc) pslg_free(g);
    return rc;
}
