/* pslg_hull: the convex hull of a PSLG's vertices enclosed by segments (Triangle's -c:
 * pslg_check_ex with PSLG_HULL, or pslg_enclose_hull after pslg_check).
 *
 * The hull is Andrew's monotone chain (A. M. Andrew, "Another efficient algorithm for convex
 * hulls in two dimensions", Inf. Proc. Letters 9, 1979): the vertices sorted by (x, y), the
 * lower chain built left to right and the upper chain right to left, each popping its last
 * vertex while it makes a strictly clockwise turn with the next one.  Every turn is the sign of
 * the exact geom_orient2d, and only a strict clockwise turn pops, so a vertex lying on a hull
 * edge stays on the chain: the hull's edges are cut at every collinear vertex and no new
 * segment passes through a vertex.  (Keeping collinear vertices breaks the method only when
 * every vertex lies on one line; that hull has no area and nothing is added.)
 *
 * An input segment that lies on the hull's boundary covers the run of hull edges between its
 * endpoints (both are hull vertices, and the run is straight); those edges are not added again,
 * so no segment repeats or overlaps another.  Every other hull edge becomes a new segment with
 * boundary marker 1 (line 0: it is in no file), appended after the input's segments.
 *
 * Invariant kept (pslg_check.c's): distinct non-degenerate segments meeting only at
 * shared endpoints or at a vertex inside a segment -- a hull edge holds no vertex inside it and
 * no segment crosses it, since every segment lies in the closed hull.  The hull is taken of the
 * normalised vertices (duplicates merged, crossing vertices added), so it is exact for the PSLG
 * the meshers triangulate.
 */
#include "geom/pslg.h"

#include "base/base.h"
#include "geom/geom.h"

#include <stdlib.h>

typedef struct hkey {
    double x, y;
    int32_t i;
} hkey;

static int cmp_hkey(const void *pa, const void *pb) {
    const hkey *a = pa, *b = pb;
    if (a->x != b->x) return a->x < b->x ? -1 : 1;
    if (a->y != b->y) return a->y < b->y ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

static const double *P(const pslg *g, int32_t v) {
    return g->xy + 2 * (size_t)v;
}

/* 1 iff p lies on the closed segment ab (exact: collinear, then inside the bounding box). */
static int on_closed(const double *a, const double *b, const double *p) {
    if (geom_orient2d(a, b, p) != 0) return 0;
    return (a[0] <= b[0] ? a[0] <= p[0] && p[0] <= b[0] : b[0] <= p[0] && p[0] <= a[0]) &&
           (a[1] <= b[1] ? a[1] <= p[1] && p[1] <= b[1] : b[1] <= p[1] && p[1] <= a[1]);
}

int32_t pslg_hull(const pslg *g, int32_t *cyc) {
    int32_t n = g->nverts;
    if (n < 3) return 0;
    hkey *v = mesh_xmalloc((size_t)n, sizeof *v);
    for (int32_t i = 0; i < n; i++)
        v[i] = (hkey){g->xy[2 * i], g->xy[2 * i + 1], i};
    qsort(v, (size_t)n, sizeof *v, cmp_hkey);
    int32_t a = v[0].i, b = -1, k = 0;
    for (int32_t j = 1; j < n && b < 0; j++)
        if (v[j].x != v[0].x || v[j].y != v[0].y) b = v[j].i;
    int flat = 1;
    for (int32_t j = 0; j < n && flat && b >= 0; j++)
        flat = geom_orient2d(P(g, a), P(g, b), P(g, v[j].i)) == 0;
    if (flat) { /* one line (or one point): no area to enclose */
        free(v);
        return 0;
    }
    /* cyc holds the lower chain, then the upper chain; each chain's last vertex is the next
     * one's first, so it is dropped; a duplicate point (pslg_hull does not require
     * normalised input) is skipped. */
    for (int pass = 0; pass < 2; pass++) {
        int32_t base = k;
        for (int32_t j = 0; j < n; j++) {
            int32_t i = v[pass ? n - 1 - j : j].i;
            if (k > base && P(g, cyc[k - 1])[0] == P(g, i)[0] && P(g, cyc[k - 1])[1] == P(g, i)[1])
                continue;
            while (k >= base + 2 && geom_orient2d(P(g, cyc[k - 2]), P(g, cyc[k - 1]), P(g, i)) < 0)
                k--;
            cyc[k++] = i;
        }
        k--;
    }
    free(v);
    /* the chain's own check: every turn counter-clockwise or straight, never back */
    for (int32_t i = 0; i < k; i++) {
        const double *p = P(g, cyc[i]), *q = P(g, cyc[(i + 1) % k]), *r = P(g, cyc[(i + 2) % k]);
        if (geom_orient2d(p, q, r) < 0 || (p[0] == q[0] && p[1] == q[1]))
            MESH_BUG("convex hull: vertices %d, %d, %d turn clockwise or repeat", cyc[i],
                     cyc[(i + 1) % k], cyc[(i + 2) % k]);
    }
    return k;
}

void pslg_enclose_hull(pslg *g) {
    geom_init();
    int32_t n = g->nverts;
    if (n < 3) return;
    int32_t *cyc = mesh_xmalloc(2 * (size_t)n + 2, sizeof *cyc);
    int32_t h = pslg_hull(g, cyc);
    if (h < 3) {
        free(cyc);
        return;
    }
    int32_t *pos = mesh_xmalloc((size_t)n, sizeof *pos);
    uint8_t *covered = mesh_xcalloc((size_t)h, 1);
    for (int32_t i = 0; i < n; i++)
        pos[i] = -1;
    for (int32_t i = 0; i < h; i++)
        pos[cyc[i]] = i;
    /* a segment on the boundary: from one endpoint the hull runs straight to the other, one
     * way round; its edges are covered (each by one segment: segments do not overlap) */
    for (int32_t s = 0; s < g->nsegs; s++) {
        int32_t c = g->seg[2 * s], d = g->seg[2 * s + 1];
        if (pos[c] < 0 || pos[d] < 0) continue;
        for (int32_t dir = 1; dir >= -1; dir -= 2) {
            int32_t j = pos[c], nx = cyc[(j + dir + h) % h];
            if (!on_closed(P(g, c), P(g, d), P(g, nx))) continue;
            for (int32_t steps = 0; cyc[j] != d; steps++) {
                if (steps == h) MESH_BUG("segment %d on the hull does not reach its end", s);
                covered[dir > 0 ? j : (j - 1 + h) % h] = 1;
                j = (j + dir + h) % h;
            }
            break;
        }
    }
    int32_t add = 0;
    for (int32_t i = 0; i < h; i++)
        add += !covered[i];
    if (add > 0) {
        size_t ns = (size_t)g->nsegs + (size_t)add;
        g->seg = mesh_xrealloc(g->seg, 2 * ns, sizeof *g->seg);
        g->smarker = mesh_xrealloc(g->smarker, ns, sizeof *g->smarker);
        if (g->sline) g->sline = mesh_xrealloc(g->sline, ns, sizeof *g->sline);
        for (int32_t i = 0; i < h; i++) {
            if (covered[i]) continue;
            int32_t s = g->nsegs++;
            g->seg[2 * s] = cyc[i];
            g->seg[2 * s + 1] = cyc[(i + 1) % h];
            g->smarker[s] = 1;
            if (g->sline) g->sline[s] = 0;
        }
    }
    free(covered);
    free(pos);
    free(cyc);
}
