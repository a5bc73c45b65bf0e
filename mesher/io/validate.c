/* validate: the mesh validator (design.md, "Invariants every test can check").
 *
 * Everything topological uses the exact predicates: orientation (geom_orient2d) and local
 * Delaunay (geom_incircle of the opposite vertex across each shared edge, strict).  Edges are
 * grouped by counting sort on their smaller vertex followed by a small sort of each vertex's
 * bucket, which is O(n) work and memory (one int32 per directed edge) even at 10M triangles;
 * each undirected edge must have one or two uses, two in opposite directions.  Segment edges
 * (m->seg) and boundary edges go into a hash table; each input segment must be a monotone
 * chain of such edges that stays within rounding distance of the segment (refinement splits
 * segments at rounded midpoints), and every boundary edge must lie on such a chain.  Input
 * vertices are found by hashing their exact coordinates.  Areas use compensated summation;
 * total triangle area, area enclosed by the boundary edges and pslg_domain_area() must agree
 * to a relative 1e-9.  Quality checks exempt triangles at small input angles (rule in
 * validate.h).
 */
#include "io/validate.h"

#include "base/base.h"

#include "geom/geom.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- helpers --------------- */

__attribute__((format(printf, 2, 3))) static void problem(validate_report *r, const char *fmt,
                                                          ...) {
    if (r->first_problem[0]) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->first_problem, sizeof r->first_problem, fmt, ap);
    va_end(ap);
}

typedef struct ksum { /* Neumaier compensated sum */
    double s, c;
} ksum;

static void ksum_add(ksum *k, double t) {
    double s = k->s + t;
    k->c += fabs(k->s) >= fabs(t) ? (k->s - s) + t : (t - s) + k->s;
    k->s = s;
}

static double ksum_get(const ksum *k) {
    return k->s + k->c;
}

/* Edge records, reachable by an open-addressing hash on the undirected key. */
enum { E_MSEG = 1, E_BND = 2, E_INMESH = 4, E_INPUT = 8 };

typedef struct erec {
    int32_t u, v; /* u < v */
    int32_t flags;
    int32_t mseg; /* first m->seg index, or -1 */
    int32_t from; /* boundary edges: the direction with the mesh on its left */
} erec;

typedef struct etab {
    erec *rec;
    int32_t n, cap;
    int32_t *slot; /* hash slots: record index or -1 */
    size_t nslot;  /* power of two */
} etab;

static uint64_t ekey(int32_t u, int32_t v) {
    return ((uint64_t)(uint32_t)u << 32) | (uint32_t)v;
}

static int32_t etab_find(const etab *T, int32_t u, int32_t v) {
    if (u > v) {
        int32_t x = u;
        u = v;
        v = x;
    }
    size_t mask = T->nslot - 1, i = mesh_hash64(ekey(u, v)) & mask;
    for (;; i = (i + 1) & mask) {
        int32_t k = T->slot[i];
        if (k < 0) return -1;
        if (T->rec[k].u == u && T->rec[k].v == v) return k;
    }
}

static int etab_grow(etab *T) {
    size_t ns = T->nslot ? T->nslot * 2 : 1024;
    int32_t *sl = mesh_xmalloc(ns * sizeof *sl, 1);
    if (!sl) return -1;
    memset(sl, 0xff, ns * sizeof *sl);
    for (int32_t k = 0; k < T->n; k++) {
        size_t i = mesh_hash64(ekey(T->rec[k].u, T->rec[k].v)) & (ns - 1);
        while (sl[i] >= 0)
            i = (i + 1) & (ns - 1);
        sl[i] = k;
    }
    free(T->slot);
    T->slot = sl;
    T->nslot = ns;
    return 0;
}

/* Finds or adds the record of edge uv; returns its index or -1 (out of memory). */
static int32_t etab_get(etab *T, int32_t u, int32_t v) {
    if (u > v) {
        int32_t x = u;
        u = v;
        v = x;
    }
    if ((size_t)(T->n + 1) * 2 > T->nslot && etab_grow(T)) return -1;
    size_t mask = T->nslot - 1, i = mesh_hash64(ekey(u, v)) & mask;
    for (;; i = (i + 1) & mask) {
        int32_t k = T->slot[i];
        if (k < 0) break;
        if (T->rec[k].u == u && T->rec[k].v == v) return k;
    }
    if (T->n == T->cap) {
        int32_t nc = T->cap ? 2 * T->cap : 1024;
        erec *nr = mesh_xrealloc(T->rec, (size_t)nc * sizeof *nr, 1);
        if (!nr) return -1;
        T->rec = nr;
        T->cap = nc;
    }
    T->rec[T->n] = (erec){u, v, 0, -1, -1};
    T->slot[i] = T->n;
    return T->n++;
}

static void etab_free(etab *T) {
    free(T->rec);
    free(T->slot);
}

/* Smallest angle of abc in degrees: the angle opposite the shortest edge, by atan2. */
static double tri_min_angle(const double *a, const double *b, const double *c) {
    const double *p[3] = {a, b, c};
    double l[3]; /* l[i]: squared length of the edge opposite p[i] */
    for (int i = 0; i < 3; i++) {
        const double *q = p[(i + 1) % 3], *s = p[(i + 2) % 3];
        l[i] = (q[0] - s[0]) * (q[0] - s[0]) + (q[1] - s[1]) * (q[1] - s[1]);
    }
    int k = l[0] <= l[1] ? (l[0] <= l[2] ? 0 : 2) : (l[1] <= l[2] ? 1 : 2);
    const double *o = p[k], *q = p[(k + 1) % 3], *s = p[(k + 2) % 3];
    double ux = q[0] - o[0], uy = q[1] - o[1], vx = s[0] - o[0], vy = s[1] - o[1];
    return atan2(fabs(ux * vy - uy * vx), ux * vx + uy * vy) * (180 / 3.14159265358979323846);
}

/* ---------------------------------------------------------------- small corners --------- */

typedef struct gap {
    int32_t v, s1, s2;
} gap;

typedef struct gaplist {
    gap *g;
    int32_t n, cap;
    int oom;
} gaplist;

static void gap_cb(void *ctx, int32_t v, int32_t s1, int32_t s2, double deg) {
    gaplist *L = ctx;
    if (L->n == L->cap) {
        int32_t nc = L->cap ? 2 * L->cap : 16;
        gap *ng = mesh_xrealloc(L->g, (size_t)nc * sizeof *ng, 1);
        if (!ng) {
            L->oom = 1;
            return;
        }
        L->g = ng;
        L->cap = nc;
    }
    L->g[L->n++] = (gap){v, s1, s2};
}

typedef struct vtag { /* mesh vertex on side `side` of small corner k */
    int32_t v, k, side;
} vtag;

static int cmp_vtag(const void *pa, const void *pb) {
    const vtag *a = pa, *b = pb;
    if (a->v != b->v) return a->v < b->v ? -1 : 1;
    if (a->k != b->k) return a->k < b->k ? -1 : 1;
    return a->side - b->side;
}

/* ---------------------------------------------------------------- validator ------------- */

/* Other endpoint helpers for directed edge he = 3t + k. */
static int32_t he_org(const int32_t *tri, uint32_t he) {
    return tri[he];
}

static int32_t he_dst(const int32_t *tri, uint32_t he) {
    uint32_t k = he % 3;
    return tri[he - k + (k + 1) % 3];
}

static int32_t he_hi(const int32_t *tri, uint32_t he) {
    int32_t a = he_org(tri, he), b = he_dst(tri, he);
    return a > b ? a : b;
}

typedef struct pair64 {
    int32_t key;
    uint32_t he;
} pair64;

static int cmp_pair(const void *pa, const void *pb) {
    const pair64 *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->he > b->he) - (a->he < b->he);
}

static void oom(validate_report *r) {
    r->bad_conform++;
    problem(r, "validator out of memory");
}

int mesh_validate(const pslg *g, const mesh_flat *m, const validate_opts *o, validate_report *r) {
    geom_init();
    memset(r, 0, sizeof *r);
    validate_opts none = {0};
    if (!o) o = &none;
    r->ntris = m->ntris;
    r->nverts = m->nverts;
    r->min_angle = 180;
    r->min_angle_unforced = 180;
    const double *xy = m->xy;
    const int32_t *tri = m->tri;
    int32_t nv = m->nverts, nt = m->ntris;

    uint8_t *tbad = NULL, *vflag = NULL;
    int32_t *bstart = NULL, *gmap = NULL, *astart = NULL, *gslot = NULL, *chain = NULL,
            *chainv = NULL;
    uint32_t *bhe = NULL;
    pair64 *scratch = NULL;
    int32_t(*adj)[2] = NULL;
    etab T = {0};
    gaplist gl = {0};
    int32_t *tstart = NULL;
    int32_t(*tags)[2] = NULL;
    vtag *vt = NULL;
    size_t nvt = 0, capvt = 0;

    /* 1. indices and coordinates */
    for (int32_t i = 0; i < nv; i++)
        if (!isfinite(xy[2 * i]) || !isfinite(xy[2 * i + 1])) {
            r->bad_conform++;
            problem(r, "vertex %d has a non-finite coordinate", i);
        }
    for (int64_t i = 0; i < 3 * (int64_t)nt; i++)
        if (tri[i] < 0 || tri[i] >= nv) {
            r->bad_conform++;
            problem(r, "triangle %lld uses vertex %d, out of range [0, %d)", (long long)(i / 3),
                    tri[i], nv);
        }
    for (int64_t i = 0; i < 2 * (int64_t)m->nsegs; i++)
        if (m->seg[i] < 0 || m->seg[i] >= nv) {
            r->bad_conform++;
            problem(r, "segment %lld uses vertex %d, out of range [0, %d)", (long long)(i / 2),
                    m->seg[i], nv);
        }
    if (nt > INT32_MAX / 3) {
        r->bad_conform++;
        problem(r, "too many triangles (%d) for the validator", nt);
    }
    if (r->bad_conform) goto done;

    /* 2. orientation and areas */
    tbad = mesh_xcalloc((size_t)nt + 1, 1);
    if (!tbad) {
        oom(r);
        goto done;
    }
    ksum area = {0, 0};
    for (int32_t t = 0; t < nt; t++) {
        const double *a = xy + 2 * tri[3 * t], *b = xy + 2 * tri[3 * t + 1],
                     *c = xy + 2 * tri[3 * t + 2];
        if (geom_orient2d(a, b, c) <= 0) {
            tbad[t] = 1;
            r->bad_orient++;
            problem(r, "triangle %d (%d %d %d) is %s", t, tri[3 * t], tri[3 * t + 1],
                    tri[3 * t + 2],
                    geom_orient2d(a, b, c) < 0 ? "clockwise" : "degenerate (zero area)");
        }
        ksum_add(&area, 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])));
    }
    r->mesh_area = ksum_get(&area);

    /* 3. directed edges bucketed by their smaller vertex, each bucket sorted by the larger */
    bstart = mesh_xcalloc((size_t)nv + 2, sizeof *bstart);
    bhe = mesh_xmalloc((3 * (size_t)nt + 1) * sizeof *bhe, 1);
    if (!bstart || !bhe) {
        oom(r);
        goto done;
    }
    for (uint32_t he = 0; he < 3 * (uint32_t)nt; he++) {
        int32_t a = he_org(tri, he), b = he_dst(tri, he);
        if (a != b) bstart[(a < b ? a : b) + 1]++;
    }
    int32_t maxdeg = 0;
    for (int32_t v = 0; v < nv; v++) {
        if (bstart[v + 1] > maxdeg) maxdeg = bstart[v + 1];
        bstart[v + 1] += bstart[v];
    }
    for (uint32_t he = 0; he < 3 * (uint32_t)nt; he++) {
        int32_t a = he_org(tri, he), b = he_dst(tri, he);
        if (a != b) bhe[bstart[a < b ? a : b]++] = he;
    }
    for (int32_t v = nv; v > 0; v--)
        bstart[v] = bstart[v - 1];
    bstart[0] = 0;
    scratch = mesh_xmalloc(((size_t)maxdeg + 1) * sizeof *scratch, 1);
    if (!scratch) {
        oom(r);
        goto done;
    }
    for (int32_t v = 0; v < nv; v++) {
        uint32_t *e = bhe + bstart[v];
        int32_t d = bstart[v + 1] - bstart[v];
        if (d <= 24) {
            for (int32_t i = 1; i < d; i++) {
                uint32_t x = e[i];
                int32_t kx = he_hi(tri, x), j = i;
                while (j > 0 && he_hi(tri, e[j - 1]) > kx) {
                    e[j] = e[j - 1];
                    j--;
                }
                e[j] = x;
            }
        } else {
            for (int32_t i = 0; i < d; i++)
                scratch[i] = (pair64){he_hi(tri, e[i]), e[i]};
            qsort(scratch, (size_t)d, sizeof *scratch, cmp_pair);
            for (int32_t i = 0; i < d; i++)
                e[i] = scratch[i].he;
        }
    }

    /* 4. segment edges into the table */
    for (int32_t s = 0; s < m->nsegs; s++) {
        int32_t a = m->seg[2 * s], b = m->seg[2 * s + 1];
        if (a == b) {
            r->bad_conform++;
            problem(r, "segment %d has equal endpoints (%d)", s, a);
            continue;
        }
        int32_t k = etab_get(&T, a, b);
        if (k < 0) {
            oom(r);
            goto done;
        }
        T.rec[k].flags |= E_MSEG;
        if (T.rec[k].mseg < 0) T.rec[k].mseg = s;
    }

    /* 5. conformity; boundary edges */
    double cx = 0, cy = 0;
    if (nv > 0) {
        double x0 = xy[0], x1 = xy[0], y0 = xy[1], y1 = xy[1];
        for (int32_t i = 1; i < nv; i++) {
            x0 = fmin(x0, xy[2 * i]);
            x1 = fmax(x1, xy[2 * i]);
            y0 = fmin(y0, xy[2 * i + 1]);
            y1 = fmax(y1, xy[2 * i + 1]);
        }
        cx = 0.5 * (x0 + x1);
        cy = 0.5 * (y0 + y1);
    }
    ksum barea = {0, 0};
    for (int32_t v = 0; v < nv; v++) {
        for (int32_t i = bstart[v]; i < bstart[v + 1];) {
            int32_t w = he_hi(tri, bhe[i]), j = i + 1;
            while (j < bstart[v + 1] && he_hi(tri, bhe[j]) == w)
                j++;
            int32_t cnt = j - i;
            if (cnt == 1) {
                uint32_t he = bhe[i];
                int32_t k = etab_get(&T, v, w);
                if (k < 0) {
                    oom(r);
                    goto done;
                }
                T.rec[k].flags |= E_BND | E_INMESH;
                T.rec[k].from = he_org(tri, he);
                const double *p = xy + 2 * he_org(tri, he), *q = xy + 2 * he_dst(tri, he);
                ksum_add(&barea, 0.5 * ((p[0] - cx) * (q[1] - cy) - (p[1] - cy) * (q[0] - cx)));
            } else {
                if (cnt > 2) {
                    r->bad_conform++;
                    problem(r, "edge (%d, %d) is shared by %d triangles", v, w, cnt);
                } else if (he_org(tri, bhe[i]) == he_org(tri, bhe[i + 1])) {
                    r->bad_conform++;
                    problem(r,
                            "edge (%d, %d) is used twice in the same direction (triangles %u "
                            "and %u overlap)",
                            v, w, bhe[i] / 3, bhe[i + 1] / 3);
                }
                int32_t k = T.n ? etab_find(&T, v, w) : -1;
                if (k >= 0) T.rec[k].flags |= E_INMESH;
            }
            i = j;
        }
    }
    double benc = ksum_get(&barea);
    if (fabs(r->mesh_area - benc) > 1e-9 * fmax(fabs(r->mesh_area), fabs(benc))) {
        r->bad_conform++;
        problem(r, "triangles overlap: their areas sum to %.17g but the boundary encloses %.17g",
                r->mesh_area, benc);
    }
    for (int32_t k = 0; k < T.n; k++)
        if (!(T.rec[k].flags & E_INMESH)) {
            r->bad_conform++;
            problem(r, "segment %d (%d, %d) is not an edge of the mesh", T.rec[k].mseg, T.rec[k].u,
                    T.rec[k].v);
        }

    /* 6. input vertices: exact coordinates, by hash */
    int32_t gn = g ? g->nverts : 0;
    gmap = mesh_xmalloc(((size_t)gn + 1) * sizeof *gmap, 1);
    size_t gns = 16;
    while (gns < 2 * (size_t)gn + 2)
        gns *= 2;
    gslot = mesh_xmalloc(gns * sizeof *gslot, 1);
    if (!gmap || !gslot) {
        oom(r);
        goto done;
    }
    memset(gslot, 0xff, gns * sizeof *gslot);
    for (int32_t i = 0; i < gn; i++) {
        double x = g->xy[2 * i] + 0.0, y = g->xy[2 * i + 1] + 0.0;
        uint64_t bx, by;
        memcpy(&bx, &x, 8);
        memcpy(&by, &y, 8);
        size_t h = mesh_hash64(bx ^ mesh_hash64(by)) & (gns - 1);
        gmap[i] = -1;
        while (gslot[h] >= 0 && !(g->xy[2 * gslot[h]] == x && g->xy[2 * gslot[h] + 1] == y))
            h = (h + 1) & (gns - 1);
        if (gslot[h] < 0)
            gslot[h] = i;
        else
            gmap[i] = -2 - gslot[h]; /* duplicate input vertex: resolved below */
    }
    for (int32_t i = 0; i < nv; i++) {
        double x = xy[2 * i] + 0.0, y = xy[2 * i + 1] + 0.0;
        uint64_t bx, by;
        memcpy(&bx, &x, 8);
        memcpy(&by, &y, 8);
        size_t h = mesh_hash64(bx ^ mesh_hash64(by)) & (gns - 1);
        while (gslot[h] >= 0) {
            int32_t gi = gslot[h];
            if (g->xy[2 * gi] == x && g->xy[2 * gi + 1] == y) {
                if (gmap[gi] == -1) gmap[gi] = i;
                break;
            }
            h = (h + 1) & (gns - 1);
        }
    }
    for (int32_t i = 0; i < gn; i++) {
        if (gmap[i] <= -2) gmap[i] = gmap[-2 - gmap[i]];
        if (gmap[i] < 0) {
            r->missing_verts++;
            problem(r, "input vertex %d (line %d) at (%.17g, %.17g) is not a mesh vertex",
                    i + g->first_index, g->vline ? g->vline[i] : 0, g->xy[2 * i], g->xy[2 * i + 1]);
        }
    }

    /* 7. small input corners and the segments that form them */
    vflag = mesh_xcalloc((size_t)nv + 1, 1);
    if (!vflag) {
        oom(r);
        goto done;
    }
    if (g && g->nsegs > 0) pslg_input_angles(g, 60.0, gap_cb, &gl);
    if (gl.oom) {
        oom(r);
        goto done;
    }
    int32_t gsn = g ? g->nsegs : 0;
    tstart = mesh_xcalloc((size_t)gsn + 2, sizeof *tstart);
    tags = mesh_xmalloc(((size_t)gl.n * 2 + 1) * sizeof *tags, 1);
    if (!tstart || !tags) {
        oom(r);
        goto done;
    }
    for (int32_t k = 0; k < gl.n; k++) {
        tstart[gl.g[k].s1 + 1]++;
        tstart[gl.g[k].s2 + 1]++;
        if (gmap[gl.g[k].v] >= 0) vflag[gmap[gl.g[k].v]] |= 1;
    }
    for (int32_t s = 0; s < gsn; s++)
        tstart[s + 1] += tstart[s];
    for (int32_t k = 0; k < gl.n; k++) {
        int32_t *p1 = tags[tstart[gl.g[k].s1]++], *p2 = tags[tstart[gl.g[k].s2]++];
        p1[0] = k;
        p1[1] = 0;
        p2[0] = k;
        p2[1] = 1;
    }
    for (int32_t s = gsn; s > 0; s--)
        tstart[s] = tstart[s - 1];
    tstart[0] = 0;

    /* 8. input segments as chains over segment and boundary edges */
    astart = mesh_xcalloc((size_t)nv + 2, sizeof *astart);
    adj = mesh_xmalloc(((size_t)T.n * 2 + 1) * sizeof *adj, 1);
    chain = mesh_xmalloc(((size_t)T.n + 1) * sizeof *chain, 1);
    chainv = mesh_xmalloc(((size_t)T.n + 2) * sizeof *chainv, 1);
    if (!astart || !adj || !chain || !chainv) {
        oom(r);
        goto done;
    }
    for (int32_t k = 0; k < T.n; k++) { /* chains use real mesh edges only */
        if (!(T.rec[k].flags & E_INMESH)) continue;
        astart[T.rec[k].u + 1]++;
        astart[T.rec[k].v + 1]++;
    }
    for (int32_t v = 0; v < nv; v++)
        astart[v + 1] += astart[v];
    for (int32_t k = 0; k < T.n; k++) {
        if (!(T.rec[k].flags & E_INMESH)) continue;
        int32_t *p = adj[astart[T.rec[k].u]++];
        p[0] = T.rec[k].v;
        p[1] = k;
        p = adj[astart[T.rec[k].v]++];
        p[0] = T.rec[k].u;
        p[1] = k;
    }
    for (int32_t v = nv; v > 0; v--)
        astart[v] = astart[v - 1];
    astart[0] = 0;
    for (int32_t s = 0; s < gsn; s++) {
        int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1];
        int32_t A = gmap[a], B = gmap[b];
        if (A < 0 || B < 0 || A == B) {
            r->missing_segs++;
            problem(r, "input segment %d (line %d) is missing: an endpoint is not in the mesh",
                    s + g->first_index, g->sline ? g->sline[s] : 0);
            continue;
        }
        const double *pa = xy + 2 * A, *pb = xy + 2 * B;
        double dx = pb[0] - pa[0], dy = pb[1] - pa[1], L2 = dx * dx + dy * dy, L = sqrt(L2);
        double mag = fmax(fmax(fabs(pa[0]), fabs(pa[1])), fmax(fabs(pb[0]), fabs(pb[1])));
        double tol = (1e-9 * L + 8 * DBL_EPSILON * mag) * L; /* bound on |cross| */
        int32_t cur = A, nch = 0;
        double tcur = 0;
        chainv[0] = A;
        while (cur != B && nch < T.n) {
            int32_t best = -1, brec = -1;
            double bt = INFINITY;
            for (int32_t i = astart[cur]; i < astart[cur + 1]; i++) {
                int32_t w = adj[i][0];
                double t;
                if (w == B) {
                    t = 1;
                } else {
                    const double *q = xy + 2 * w;
                    double qx = q[0] - pa[0], qy = q[1] - pa[1];
                    if (fabs(dx * qy - dy * qx) > tol) continue;
                    t = (qx * dx + qy * dy) / L2;
                    if (!(t > tcur && t < 1)) continue;
                }
                if (t < bt) {
                    bt = t;
                    best = w;
                    brec = adj[i][1];
                }
            }
            if (best < 0) break;
            chain[nch++] = brec;
            chainv[nch] = best;
            cur = best;
            tcur = bt;
        }
        if (cur != B) {
            r->missing_segs++;
            problem(r,
                    "input segment %d (line %d) from (%.17g, %.17g) to (%.17g, %.17g) is not "
                    "a chain of mesh segment/boundary edges",
                    s + g->first_index, g->sline ? g->sline[s] : 0, pa[0], pa[1], pb[0], pb[1]);
            continue;
        }
        for (int32_t i = 0; i < nch; i++)
            T.rec[chain[i]].flags |= E_INPUT;
        for (int32_t q = tstart[s]; q < tstart[s + 1]; q++) /* tag the chain's vertices */
            for (int32_t i = 0; i <= nch; i++) {
                if (nvt == capvt) {
                    size_t nc = capvt ? 2 * capvt : 256;
                    vtag *nvtag = mesh_xrealloc(vt, nc * sizeof *vt, 1);
                    if (!nvtag) {
                        oom(r);
                        goto done;
                    }
                    vt = nvtag;
                    capvt = nc;
                }
                vt[nvt++] = (vtag){chainv[i], tags[q][0], tags[q][1]};
                vflag[chainv[i]] |= 2;
            }
    }
    for (int32_t k = 0; k < T.n; k++)
        if ((T.rec[k].flags & E_BND) && !(T.rec[k].flags & E_INPUT)) {
            r->stray_boundary++;
            const double *p = xy + 2 * T.rec[k].u, *q = xy + 2 * T.rec[k].v;
            problem(r,
                    "boundary edge (%d, %d) from (%.17g, %.17g) to (%.17g, %.17g) lies on no "
                    "input segment",
                    T.rec[k].u, T.rec[k].v, p[0], p[1], q[0], q[1]);
        }
    if (nvt > 1) { /* sort and drop repeats */
        qsort(vt, nvt, sizeof *vt, cmp_vtag);
        size_t w = 1;
        for (size_t i = 1; i < nvt; i++)
            if (cmp_vtag(&vt[i], &vt[w - 1]) != 0) vt[w++] = vt[i];
        nvt = w;
    }

    /* 9. local Delaunay property of unconstrained interior edges */
    for (int32_t v = 0; v < nv; v++) {
        for (int32_t i = bstart[v]; i < bstart[v + 1];) {
            int32_t w = he_hi(tri, bhe[i]), j = i + 1;
            while (j < bstart[v + 1] && he_hi(tri, bhe[j]) == w)
                j++;
            if (j - i == 2) {
                uint32_t h1 = bhe[i], h2 = bhe[i + 1];
                uint32_t t1 = h1 / 3, t2 = h2 / 3;
                int32_t k = T.n ? etab_find(&T, v, w) : -1;
                int exempt = 0;
                if (k >= 0) {
                    const erec *e = T.rec + k;
                    int iface = !m->sinterface || e->mseg < 0 || m->sinterface[e->mseg];
                    exempt = (e->flags & E_INPUT) ||
                             ((e->flags & E_MSEG) && !(o->check_delaunay_interfaces && iface));
                }
                if (!exempt && !tbad[t1] && !tbad[t2] && he_org(tri, h1) != he_org(tri, h2)) {
                    uint32_t k2 = h2 % 3;
                    int32_t opp = tri[3 * t2 + (k2 + 2) % 3];
                    if (geom_incircle(xy + 2 * tri[3 * t1], xy + 2 * tri[3 * t1 + 1],
                                      xy + 2 * tri[3 * t1 + 2], xy + 2 * opp) > 0) {
                        r->non_delaunay++;
                        problem(r,
                                "edge (%d, %d) is not locally Delaunay: vertex %d lies inside "
                                "the circumcircle of triangle %u",
                                v, w, opp, t1);
                    }
                }
            }
            i = j;
        }
    }

    /* 10. quality */
    double abound = o->max_area > 0 ? o->max_area * (1 + 1e-12) : INFINITY;
    double qbound = o->min_angle > 0 ? o->min_angle - 1e-6 : -INFINITY;
    r->max_area = 0;
    for (int32_t t = 0; t < nt; t++) {
        if (tbad[t]) continue;
        const int32_t *tv = tri + 3 * t;
        const double *a = xy + 2 * tv[0], *b = xy + 2 * tv[1], *c = xy + 2 * tv[2];
        double ar = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
        double ang = tri_min_angle(a, b, c);
        if (ar > r->max_area) r->max_area = ar;
        if (ang < r->min_angle) r->min_angle = ang;
        if (ar > abound) {
            r->bad_area++;
            problem(r, "triangle %d has area %.6g > %.6g", t, ar, o->max_area);
        }
        int exempt = (vflag[tv[0]] | vflag[tv[1]] | vflag[tv[2]]) & 1;
        for (int x = 0; x < 3 && !exempt; x++) {
            int32_t p = tv[x], q = tv[(x + 1) % 3];
            if (!(vflag[p] & 2) || !(vflag[q] & 2)) continue;
            vtag key = {p, -1, 0};
            size_t lo = 0, hi = nvt; /* first tag of p */
            while (lo < hi) {
                size_t mid = (lo + hi) / 2;
                if (cmp_vtag(&vt[mid], &key) < 0)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            for (size_t i1 = lo; i1 < nvt && vt[i1].v == p && !exempt; i1++) {
                vtag k2 = {q, vt[i1].k, 1 - vt[i1].side};
                size_t l2 = 0, h2 = nvt;
                while (l2 < h2) {
                    size_t mid = (l2 + h2) / 2;
                    if (cmp_vtag(&vt[mid], &k2) < 0)
                        l2 = mid + 1;
                    else
                        h2 = mid;
                }
                exempt = l2 < nvt && cmp_vtag(&vt[l2], &k2) == 0;
            }
        }
        if (exempt) {
            r->nexempt++;
            continue;
        }
        if (ang < r->min_angle_unforced) r->min_angle_unforced = ang;
        if (ang < qbound) {
            r->bad_angle++;
            problem(r, "triangle %d has smallest angle %.6g < %.6g degrees", t, ang, o->min_angle);
        }
    }

    /* 11. area of the domain */
    r->domain_area = g ? pslg_domain_area(g) : 0;
    if (g && !(fabs(r->mesh_area - r->domain_area) <=
               1e-9 * fmax(fabs(r->mesh_area), fabs(r->domain_area)))) {
        r->area_mismatch = 1;
        problem(r, "mesh area %.17g differs from the domain area %.17g", r->mesh_area,
                r->domain_area);
    }

done:
    r->ok = !(r->bad_orient || r->bad_conform || r->missing_verts || r->missing_segs ||
              r->stray_boundary || r->non_delaunay || r->bad_angle || r->bad_area ||
              r->area_mismatch || r->first_problem[0]);
    free(tbad);
    free(vflag);
    free(bstart);
    free(bhe);
    free(gmap);
    free(gslot);
    free(astart);
    free(adj);
    free(chain);
    free(chainv);
    free(scratch);
    etab_free(&T);
    free(gl.g);
    free(tstart);
    free(tags);
    free(vt);
    return r->ok;
}

void validate_report_print(const validate_report *r, FILE *f) {
    if (r->ok) {
        fprintf(f,
                "meshcheck: OK triangles=%ld vertices=%ld min_angle=%.4f max_area=%.6g area=%.17g "
                "domain_area=%.17g min_angle_unforced=%.4f exempt=%ld\n",
                r->ntris, r->nverts, r->min_angle, r->max_area, r->mesh_area, r->domain_area,
                r->min_angle_unforced, r->nexempt);
        return;
    }
    fprintf(f, "meshcheck: FAIL %s", r->first_problem[0] ? r->first_problem : "(unknown)");
    const struct {
        const char *name;
        long v;
    } c[] = {{"bad_orient", r->bad_orient},         {"bad_conform", r->bad_conform},
             {"missing_verts", r->missing_verts},   {"missing_segs", r->missing_segs},
             {"stray_boundary", r->stray_boundary}, {"non_delaunay", r->non_delaunay},
             {"bad_angle", r->bad_angle},           {"bad_area", r->bad_area},
             {"area_mismatch", r->area_mismatch}};
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++)
        if (c[i].v) fprintf(f, " %s=%ld", c[i].name, c[i].v);
    fprintf(f,
            " triangles=%ld vertices=%ld min_angle=%.4f max_area=%.6g area=%.17g "
            "domain_area=%.17g\n",
            r->ntris, r->nverts, r->min_angle, r->max_area, r->mesh_area, r->domain_area);
}
