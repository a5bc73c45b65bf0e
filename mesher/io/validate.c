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
 * to a relative 1e-9 plus what the chains' rounding can move (validate_area_slack).  Quality checks
 * exempt triangles at small input angles (rule in validate.h).  Regions (-A, --region-areas) are
 * found from the input alone: the face of the segment arrangement (pslg_regions) holding a point
 * exactly inside each triangle.
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

/* Everything one validation run builds, handed from check to check.  Each check below returns
 * 0 to go on, or -1 when a later check could not run (out of memory, or indices out of range). */
typedef struct vctx {
    const pslg *g;
    const mesh_flat *m;
    const validate_opts *o;
    validate_report *r;
    const double *xy;
    const int32_t *tri;
    int32_t nv, nt;
    uint8_t *tbad;   /* per triangle: not counter-clockwise (skipped by later checks) */
    uint8_t *vflag;  /* per vertex: 1 small corner, 2 on a small corner's segment chain */
    int32_t *bstart; /* directed edges bucketed by their smaller vertex: bhe[bstart[v]..] */
    uint32_t *bhe;
    int32_t maxdeg;
    etab T;          /* segment and boundary edges */
    int32_t *gmap;   /* input vertex -> mesh vertex, or -1 */
    gaplist gl;      /* small input corners */
    int32_t *tstart; /* per input segment: its corner tags tags[tstart[s]..] */
    int32_t (*tags)[2];
    pslg_pieces pc; /* input segments cut at the input vertices on them; which border the domain */
    vtag *vt;       /* mesh vertices on small corners' segments, sorted */
    size_t nvt, capvt;
} vctx;

/* 1. indices and coordinates */
static int check_indices(vctx *c) {
    validate_report *r = c->r;
    const mesh_flat *m = c->m;
    for (int32_t i = 0; i < c->nv; i++)
        if (!isfinite(c->xy[2 * i]) || !isfinite(c->xy[2 * i + 1])) {
            r->bad_conform++;
            problem(r, "vertex %d has a non-finite coordinate", i);
        }
    for (int64_t i = 0; i < 3 * (int64_t)c->nt; i++)
        if (c->tri[i] < 0 || c->tri[i] >= c->nv) {
            r->bad_conform++;
            problem(r, "triangle %lld uses vertex %d, out of range [0, %d)", (long long)(i / 3),
                    c->tri[i], c->nv);
        }
    for (int64_t i = 0; i < 2 * (int64_t)m->nsegs; i++)
        if (m->seg[i] < 0 || m->seg[i] >= c->nv) {
            r->bad_conform++;
            problem(r, "segment %lld uses vertex %d, out of range [0, %d)", (long long)(i / 2),
                    m->seg[i], c->nv);
        }
    if (c->nt > INT32_MAX / 3) {
        r->bad_conform++;
        problem(r, "too many triangles (%d) for the validator", c->nt);
    }
    return r->bad_conform ? -1 : 0;
}

/* 2. orientation and areas */
static int check_orientation(vctx *c) {
    validate_report *r = c->r;
    const int32_t *tri = c->tri;
    c->tbad = mesh_xcalloc((size_t)c->nt + 1, 1);
    if (!c->tbad) {
        oom(r);
        return -1;
    }
    ksum area = {0, 0};
    for (int32_t t = 0; t < c->nt; t++) {
        const double *a = c->xy + 2 * tri[3 * t], *b = c->xy + 2 * tri[3 * t + 1],
                     *p = c->xy + 2 * tri[3 * t + 2];
        if (geom_orient2d(a, b, p) <= 0) {
            c->tbad[t] = 1;
            r->bad_orient++;
            problem(r, "triangle %d (%d %d %d) is %s", t, tri[3 * t], tri[3 * t + 1],
                    tri[3 * t + 2],
                    geom_orient2d(a, b, p) < 0 ? "clockwise" : "degenerate (zero area)");
        }
        ksum_add(&area, 0.5 * geom_area2_accurate(a, b, p));
    }
    r->mesh_area = ksum_get(&area);
    return 0;
}

/* 3. directed edges bucketed by their smaller vertex, each bucket sorted by the larger */
static int build_edge_buckets(vctx *c) {
    const int32_t *tri = c->tri;
    int32_t nv = c->nv;
    c->bstart = mesh_xcalloc((size_t)nv + 2, sizeof *c->bstart);
    c->bhe = mesh_xmalloc((3 * (size_t)c->nt + 1) * sizeof *c->bhe, 1);
    if (!c->bstart || !c->bhe) {
        oom(c->r);
        return -1;
    }
    int32_t *bstart = c->bstart;
    uint32_t *bhe = c->bhe;
    for (uint32_t he = 0; he < 3 * (uint32_t)c->nt; he++) {
        int32_t a = he_org(tri, he), b = he_dst(tri, he);
        if (a != b) bstart[(a < b ? a : b) + 1]++;
    }
    int32_t maxdeg = 0;
    for (int32_t v = 0; v < nv; v++) {
        if (bstart[v + 1] > maxdeg) maxdeg = bstart[v + 1];
        bstart[v + 1] += bstart[v];
    }
    for (uint32_t he = 0; he < 3 * (uint32_t)c->nt; he++) {
        int32_t a = he_org(tri, he), b = he_dst(tri, he);
        if (a != b) bhe[bstart[a < b ? a : b]++] = he;
    }
    for (int32_t v = nv; v > 0; v--)
        bstart[v] = bstart[v - 1];
    bstart[0] = 0;
    pair64 *scratch = mesh_xmalloc(((size_t)maxdeg + 1) * sizeof *scratch, 1);
    if (!scratch) {
        oom(c->r);
        return -1;
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
    free(scratch);
    c->maxdeg = maxdeg;
    return 0;
}

/* 4. segment edges into the table */
static int add_segment_edges(vctx *c) {
    const mesh_flat *m = c->m;
    for (int32_t s = 0; s < m->nsegs; s++) {
        int32_t a = m->seg[2 * s], b = m->seg[2 * s + 1];
        if (a == b) {
            c->r->bad_conform++;
            problem(c->r, "segment %d has equal endpoints (%d)", s, a);
            continue;
        }
        int32_t k = etab_get(&c->T, a, b);
        if (k < 0) {
            oom(c->r);
            return -1;
        }
        c->T.rec[k].flags |= E_MSEG;
        if (c->T.rec[k].mseg < 0) c->T.rec[k].mseg = s;
    }
    return 0;
}

/* 5. conformity; boundary edges */
static int check_conformity(vctx *c) {
    validate_report *r = c->r;
    const int32_t *tri = c->tri;
    int32_t nv = c->nv;
    etab *T = &c->T;
    /* No "the boundary encloses the triangles' area" test: with every interior edge used
     * once in each direction (checked below), the sum of the triangles' signed areas equals
     * the boundary's shoelace sum identically (the interior terms cancel), so such a test could
     * only report rounding -- as it did for a vertex at 1.7e20 beside a unit triangle (fuzzer,
     * tests/fuzz/regress/far_dangling_segment.poly).  Overlaps show as edge misuse here, as a
     * domain area mismatch, or as boundary edges on no input segment. */
    for (int32_t v = 0; v < nv; v++) {
        for (int32_t i = c->bstart[v]; i < c->bstart[v + 1];) {
            int32_t w = he_hi(tri, c->bhe[i]), j = i + 1;
            while (j < c->bstart[v + 1] && he_hi(tri, c->bhe[j]) == w)
                j++;
            int32_t cnt = j - i;
            if (cnt == 1) {
                uint32_t he = c->bhe[i];
                int32_t k = etab_get(T, v, w);
                if (k < 0) {
                    oom(r);
                    return -1;
                }
                T->rec[k].flags |= E_BND | E_INMESH;
                T->rec[k].from = he_org(tri, he);
            } else {
                if (cnt > 2) {
                    r->bad_conform++;
                    problem(r, "edge (%d, %d) is shared by %d triangles", v, w, cnt);
                } else if (he_org(tri, c->bhe[i]) == he_org(tri, c->bhe[i + 1])) {
                    r->bad_conform++;
                    problem(r,
                            "edge (%d, %d) is used twice in the same direction (triangles %u "
                            "and %u overlap)",
                            v, w, c->bhe[i] / 3, c->bhe[i + 1] / 3);
                }
                int32_t k = T->n ? etab_find(T, v, w) : -1;
                if (k >= 0) T->rec[k].flags |= E_INMESH;
            }
            i = j;
        }
    }
    for (int32_t k = 0; k < T->n; k++)
        if (!(T->rec[k].flags & E_INMESH)) {
            r->bad_conform++;
            problem(r, "segment %d (%d, %d) is not an edge of the mesh", T->rec[k].mseg,
                    T->rec[k].u, T->rec[k].v);
        }
    return 0;
}

/* 6. input vertices: exact coordinates, by hash */
static int check_input_vertices(vctx *c) {
    const pslg *g = c->g;
    const double *xy = c->xy;
    int32_t gn = g ? g->nverts : 0;
    c->gmap = mesh_xmalloc(((size_t)gn + 1) * sizeof *c->gmap, 1);
    size_t gns = 16;
    while (gns < 2 * (size_t)gn + 2)
        gns *= 2;
    int32_t *gslot = mesh_xmalloc(gns * sizeof *gslot, 1), *gmap = c->gmap;
    if (!gmap || !gslot) {
        free(gslot);
        oom(c->r);
        return -1;
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
    for (int32_t i = 0; i < c->nv; i++) {
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
    free(gslot);
    for (int32_t i = 0; i < gn; i++) {
        if (gmap[i] <= -2) gmap[i] = gmap[-2 - gmap[i]];
        if (gmap[i] < 0 && !c->o->part) {
            c->r->missing_verts++;
            problem(c->r, "input vertex %d (line %d) at (%.17g, %.17g) is not a mesh vertex",
                    i + g->first_index, g->vline ? g->vline[i] : 0, g->xy[2 * i], g->xy[2 * i + 1]);
        }
    }
    return 0;
}

/* 7. small input corners and the segments that form them */
static int find_small_corners(vctx *c) {
    const pslg *g = c->g;
    c->vflag = mesh_xcalloc((size_t)c->nv + 1, 1);
    if (!c->vflag) {
        oom(c->r);
        return -1;
    }
    gaplist *gl = &c->gl;
    if (g && g->nsegs > 0) pslg_input_angles(g, 60.0, gap_cb, gl);
    if (gl->oom) {
        oom(c->r);
        return -1;
    }
    int32_t gsn = g ? g->nsegs : 0;
    c->tstart = mesh_xcalloc((size_t)gsn + 2, sizeof *c->tstart);
    c->tags = mesh_xmalloc(((size_t)gl->n * 2 + 1) * sizeof *c->tags, 1);
    if (!c->tstart || !c->tags) {
        oom(c->r);
        return -1;
    }
    int32_t *tstart = c->tstart;
    for (int32_t k = 0; k < gl->n; k++) {
        tstart[gl->g[k].s1 + 1]++;
        tstart[gl->g[k].s2 + 1]++;
        if (c->gmap[gl->g[k].v] >= 0) c->vflag[c->gmap[gl->g[k].v]] |= 1;
    }
    for (int32_t s = 0; s < gsn; s++)
        tstart[s + 1] += tstart[s];
    for (int32_t k = 0; k < gl->n; k++) {
        int32_t *p1 = c->tags[tstart[gl->g[k].s1]++], *p2 = c->tags[tstart[gl->g[k].s2]++];
        p1[0] = k;
        p1[1] = 0;
        p2[0] = k;
        p2[1] = 1;
    }
    for (int32_t s = gsn; s > 0; s--)
        tstart[s] = tstart[s - 1];
    tstart[0] = 0;
    return 0;
}

/* Records that mesh vertex v lies on side `side` of small corner k. */
static int tag_vertex(vctx *c, int32_t v, int32_t k, int32_t side) {
    if (c->nvt == c->capvt) {
        size_t nc = c->capvt ? 2 * c->capvt : 256;
        vtag *nvtag = mesh_xrealloc(c->vt, nc * sizeof *c->vt, 1);
        if (!nvtag) {
            oom(c->r);
            return -1;
        }
        c->vt = nvtag;
        c->capvt = nc;
    }
    c->vt[c->nvt++] = (vtag){v, k, side};
    c->vflag[v] |= 2;
    return 0;
}

/* The chain of mesh edges (indices into T) along input segment s: from the mesh vertex of its
 * first endpoint, each step to a neighbour farther along the segment that lies within rounding
 * distance of it; among those, the step whose direction deviates least from the segment's (so
 * a neighbouring segment at a tiny angle, whose vertices are also within rounding distance,
 * does not lure the walk away), then the nearest.  Returns the number of edges, or -1 if the
 * chain does not reach the other endpoint.  chainv gets the chain's vertices. */
static int32_t trace_chain(const vctx *c, int32_t S0, int32_t S1, int32_t A, int32_t B,
                           const int32_t *astart, const int32_t (*adj)[2], int32_t *chain,
                           int32_t *chainv) {
    const double *xy = c->xy;
    const double *pa = xy + 2 * S0, *pb = xy + 2 * S1;
    double dx = pb[0] - pa[0], dy = pb[1] - pa[1], L2 = dx * dx + dy * dy, L = sqrt(L2);
    double mag = fmax(fmax(fabs(pa[0]), fabs(pa[1])), fmax(fabs(pb[0]), fabs(pb[1])));
    double tol = (1e-9 * L + 8 * DBL_EPSILON * mag) * L; /* bound on |cross| */
    int32_t cur = A, nch = 0;
    double tcur = ((xy[2 * A] - pa[0]) * dx + (xy[2 * A + 1] - pa[1]) * dy) / L2;
    chainv[0] = A;
    while (cur != B && nch < c->T.n) {
        int32_t best = -1, brec = -1;
        double bt = INFINITY, bdev = INFINITY;
        const double *pc = xy + 2 * cur;
        for (int32_t i = astart[cur]; i < astart[cur + 1]; i++) {
            int32_t w = adj[i][0];
            const double *q = xy + 2 * w;
            double t;
            double qx = q[0] - pa[0], qy = q[1] - pa[1];
            if (w == B) { /* the piece's end, through a segment or boundary edge: the chain
                           * ends here (a sliver's far vertex may also pass the distance test,
                           * e.g. two hull edges 1e-50 radians apart: never detour through it) */
                best = w;
                brec = adj[i][1];
                bt = (qx * dx + qy * dy) / L2;
                break;
            }
            if (fabs(dx * qy - dy * qx) > tol) continue;
            t = (qx * dx + qy * dy) / L2;
            if (!(t > tcur && t < 1)) continue;
            double sx = q[0] - pc[0], sy = q[1] - pc[1];
            double dev = fabs(dx * sy - dy * sx) / (L * sqrt(sx * sx + sy * sy));
            if (dev < bdev || (dev == bdev && t < bt)) {
                bdev = dev;
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
    return cur == B ? nch : -1;
}

/* Part mode (validate.h): the chain of input segment s is not whole in this part, so its
 * corner tags go to every vertex of a segment or boundary edge that lies on s, by the chain's
 * own distance test.  Returns 0, or -1 (out of memory). */
static int tag_partial_chain(vctx *c, int32_t s, const int32_t *astart) {
    if (c->tstart[s] == c->tstart[s + 1]) return 0; /* s forms no small corner */
    const double *pa = c->g->xy + 2 * c->g->seg[2 * s], *pb = c->g->xy + 2 * c->g->seg[2 * s + 1];
    double dx = pb[0] - pa[0], dy = pb[1] - pa[1], L2 = dx * dx + dy * dy, L = sqrt(L2);
    double mag = fmax(fmax(fabs(pa[0]), fabs(pa[1])), fmax(fabs(pb[0]), fabs(pb[1])));
    double tol = (1e-9 * L + 8 * DBL_EPSILON * mag) * L;
    for (int32_t v = 0; v < c->nv; v++) {
        if (astart[v] == astart[v + 1]) continue; /* on no segment or boundary edge */
        double qx = c->xy[2 * v] - pa[0], qy = c->xy[2 * v + 1] - pa[1];
        double t = (qx * dx + qy * dy) / L2;
        if (fabs(dx * qy - dy * qx) > tol || t < 0 || t > 1) continue;
        for (int32_t q = c->tstart[s]; q < c->tstart[s + 1]; q++)
            if (tag_vertex(c, v, c->tags[q][0], c->tags[q][1])) return -1;
    }
    return 0;
}

/* 8. input segments as chains over segment and boundary edges */
static int check_input_segments(vctx *c) {
    const pslg *g = c->g;
    validate_report *r = c->r;
    const double *xy = c->xy;
    etab *T = &c->T;
    int32_t nv = c->nv, gsn = g ? g->nsegs : 0;
    int32_t *astart = mesh_xcalloc((size_t)nv + 2, sizeof *astart);
    int32_t(*adj)[2] = mesh_xmalloc(((size_t)T->n * 2 + 1) * sizeof *adj, 1);
    int32_t *chain = mesh_xmalloc(((size_t)T->n + 1) * sizeof *chain, 1);
    int32_t *chainv = mesh_xmalloc(((size_t)T->n + 2) * sizeof *chainv, 1);
    int res = 0;
    if (!astart || !adj || !chain || !chainv) {
        oom(r);
        res = -1;
        goto out;
    }
    for (int32_t k = 0; k < T->n; k++) { /* chains use real mesh edges only */
        if (!(T->rec[k].flags & E_INMESH)) continue;
        astart[T->rec[k].u + 1]++;
        astart[T->rec[k].v + 1]++;
    }
    for (int32_t v = 0; v < nv; v++)
        astart[v + 1] += astart[v];
    for (int32_t k = 0; k < T->n; k++) {
        if (!(T->rec[k].flags & E_INMESH)) continue;
        int32_t *p = adj[astart[T->rec[k].u]++];
        p[0] = T->rec[k].v;
        p[1] = k;
        p = adj[astart[T->rec[k].v]++];
        p[0] = T->rec[k].u;
        p[1] = k;
    }
    for (int32_t v = nv; v > 0; v--)
        astart[v] = astart[v - 1];
    astart[0] = 0;
    if (g && pslg_segment_pieces(g, &c->pc) != 0) {
        oom(r);
        res = -1;
        goto out;
    }
    for (int32_t s = 0; s < gsn; s++) {
        int32_t A = c->gmap[g->seg[2 * s]], B = c->gmap[g->seg[2 * s + 1]];
        if (c->o->part && (A < 0 || B < 0)) { /* an endpoint in another part */
            if (tag_partial_chain(c, s, astart)) {
                res = -1;
                goto out;
            }
            continue;
        }
        if (A < 0 || B < 0 || A == B) {
            r->missing_segs++;
            problem(r, "input segment %d (line %d) is missing: an endpoint is not in the mesh",
                    s + g->first_index, g->sline ? g->sline[s] : 0);
            continue;
        }
        /* each piece that borders the domain (pieces inside the removed region have no edges):
         * its chain's edges are input edges, its vertices lie on s (tags of s's corners) */
        int ok = 1;
        for (int32_t i = c->pc.start[s]; i + 1 < c->pc.start[s + 1] && ok; i++) {
            if (!c->pc.border[i]) continue;
            int32_t P = c->gmap[c->pc.vert[i]], Q = c->gmap[c->pc.vert[i + 1]];
            int32_t nch = P < 0 || Q < 0 ? -1
                                         : trace_chain(c, A, B, P, Q, astart,
                                                       (const int32_t(*)[2])adj, chain, chainv);
            if (nch < 0) {
                ok = 0;
                break;
            }
            for (int32_t j = 0; j < nch; j++)
                T->rec[chain[j]].flags |= E_INPUT;
            for (int32_t q = c->tstart[s]; q < c->tstart[s + 1]; q++)
                for (int32_t j = 0; j <= nch; j++)
                    if (tag_vertex(c, chainv[j], c->tags[q][0], c->tags[q][1])) {
                        res = -1;
                        goto out;
                    }
        }
        if (!ok && c->o->part) { /* the chain leaves this part */
            if (tag_partial_chain(c, s, astart)) {
                res = -1;
                goto out;
            }
            continue;
        }
        if (!ok) {
            const double *pa = xy + 2 * A, *pb = xy + 2 * B;
            r->missing_segs++;
            problem(r,
                    "input segment %d (line %d) from (%.17g, %.17g) to (%.17g, %.17g) is not "
                    "a chain of mesh segment/boundary edges",
                    s + g->first_index, g->sline ? g->sline[s] : 0, pa[0], pa[1], pb[0], pb[1]);
        }
    }
    for (int32_t k = 0; k < T->n; k++)
        if ((T->rec[k].flags & E_BND) && !(T->rec[k].flags & E_INPUT) && !c->o->part) {
            r->stray_boundary++;
            const double *p = xy + 2 * T->rec[k].u, *q = xy + 2 * T->rec[k].v;
            problem(r,
                    "boundary edge (%d, %d) from (%.17g, %.17g) to (%.17g, %.17g) lies on no "
                    "input segment",
                    T->rec[k].u, T->rec[k].v, p[0], p[1], q[0], q[1]);
        }
    if (c->nvt > 1) { /* sort and drop repeats */
        qsort(c->vt, c->nvt, sizeof *c->vt, cmp_vtag);
        size_t w = 1;
        for (size_t i = 1; i < c->nvt; i++)
            if (cmp_vtag(&c->vt[i], &c->vt[w - 1]) != 0) c->vt[w++] = c->vt[i];
        c->nvt = w;
    }
out:
    free(astart);
    free(adj);
    free(chain);
    free(chainv);
    return res;
}

/* 9. local Delaunay property of unconstrained interior edges */
static int check_delaunay(vctx *c) {
    const mesh_flat *m = c->m;
    const double *xy = c->xy;
    const int32_t *tri = c->tri;
    const etab *T = &c->T;
    for (int32_t v = 0; v < c->nv; v++) {
        for (int32_t i = c->bstart[v]; i < c->bstart[v + 1];) {
            int32_t w = he_hi(tri, c->bhe[i]), j = i + 1;
            while (j < c->bstart[v + 1] && he_hi(tri, c->bhe[j]) == w)
                j++;
            if (j - i == 2) {
                uint32_t h1 = c->bhe[i], h2 = c->bhe[i + 1];
                uint32_t t1 = h1 / 3, t2 = h2 / 3;
                int32_t k = T->n ? etab_find(T, v, w) : -1;
                int exempt = 0;
                if (k >= 0) {
                    const erec *e = T->rec + k;
                    int iface = !m->sinterface || e->mseg < 0 || m->sinterface[e->mseg];
                    exempt = (e->flags & E_INPUT) ||
                             ((e->flags & E_MSEG) && !(c->o->check_delaunay_interfaces && iface));
                }
                if (!exempt && !c->tbad[t1] && !c->tbad[t2] && he_org(tri, h1) != he_org(tri, h2)) {
                    uint32_t k2 = h2 % 3;
                    int32_t opp = tri[3 * t2 + (k2 + 2) % 3];
                    if (geom_incircle(xy + 2 * tri[3 * t1], xy + 2 * tri[3 * t1 + 1],
                                      xy + 2 * tri[3 * t1 + 2], xy + 2 * opp) > 0) {
                        c->r->non_delaunay++;
                        problem(c->r,
                                "edge (%d, %d) is not locally Delaunay: vertex %d lies inside "
                                "the circumcircle of triangle %u",
                                v, w, opp, t1);
                    }
                }
            }
            i = j;
        }
    }
    return 0;
}

/* The first entry of the sorted tags not below key. */
static size_t vtag_lower_bound(const vctx *c, const vtag *key) {
    size_t lo = 0, hi = c->nvt;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (cmp_vtag(&c->vt[mid], key) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* 1 iff triangle tv's small angle is forced by the input (rule in validate.h). */
static int angle_exempt(const vctx *c, const int32_t *tv) {
    const uint8_t *vflag = c->vflag;
    int exempt = (vflag[tv[0]] | vflag[tv[1]] | vflag[tv[2]]) & 1;
    for (int x = 0; x < 3 && !exempt; x++) {
        int32_t p = tv[x], q = tv[(x + 1) % 3];
        if (!(vflag[p] & 2) || !(vflag[q] & 2)) continue;
        vtag key = {p, -1, 0};
        for (size_t i1 = vtag_lower_bound(c, &key); i1 < c->nvt && c->vt[i1].v == p && !exempt;
             i1++) {
            vtag k2 = {q, c->vt[i1].k, 1 - c->vt[i1].side};
            size_t l2 = vtag_lower_bound(c, &k2);
            exempt = l2 < c->nvt && cmp_vtag(&c->vt[l2], &k2) == 0;
        }
    }
    return exempt;
}

/* 10. quality */
static int check_quality(vctx *c) {
    validate_report *r = c->r;
    const validate_opts *o = c->o;
    double abound = o->max_area > 0 ? o->max_area * (1 + 1e-12) : INFINITY;
    double qbound = o->min_angle > 0 ? o->min_angle - 1e-6 : -INFINITY;
    r->max_area = 0;
    for (int32_t t = 0; t < c->nt; t++) {
        if (c->tbad[t]) continue;
        const int32_t *tv = c->tri + 3 * t;
        const double *a = c->xy + 2 * tv[0], *b = c->xy + 2 * tv[1], *p = c->xy + 2 * tv[2];
        double ar = 0.5 * ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]));
        double ang = tri_min_angle(a, b, p);
        if (ar > r->max_area) r->max_area = ar;
        if (ang < r->min_angle) r->min_angle = ang;
        if (ar > abound) {
            r->bad_area++;
            problem(r, "triangle %d has area %.6g > %.6g", t, ar, o->max_area);
        }
        if (angle_exempt(c, tv)) {
            r->nexempt++;
            continue;
        }
        if (ang < r->min_angle_unforced) r->min_angle_unforced = ang;
        if (ang < qbound) {
            r->bad_angle++;
            problem(r, "triangle %d has smallest angle %.6g < %.6g degrees", t, ang, o->min_angle);
        }
    }
    return 0;
}

/* A point strictly inside triangle (a, b, p), decided by exact orient2d: the centroid, or when
 * rounding puts it on an edge (a sliver) another barycentric point.  0, or -1 if none is. */
static int interior_point(const double *a, const double *b, const double *p, double out[2]) {
    static const double w[4][3] = {
        {1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.5, 0.25, 0.25}, {0.25, 0.5, 0.25}, {0.25, 0.25, 0.5}};
    for (int k = 0; k < 4; k++) {
        out[0] = w[k][0] * a[0] + w[k][1] * b[0] + w[k][2] * p[0];
        out[1] = w[k][0] * a[1] + w[k][1] * b[1] + w[k][2] * p[1];
        if (geom_orient2d(a, b, out) > 0 && geom_orient2d(b, p, out) > 0 &&
            geom_orient2d(p, a, out) > 0)
            return 0;
    }
    return -1;
}

/* 10b. regions: attributes and per-region area bounds (rule in validate.h) */
static int check_regions(vctx *c) {
    const validate_opts *o = c->o;
    validate_report *r = c->r;
    if (!(o->region_attr || o->region_area) || !c->g) return 0;
    if (o->region_attr && !c->m->tattr) {
        r->bad_region++;
        problem(r, "the mesh has no regional attributes (expected one per triangle)");
        return 0;
    }
    pslg_regions *R = pslg_regions_build(c->g);
    if (!R && c->g->nsegs > 0 && c->g->nregions > 0) {
        oom(r);
        return -1;
    }
    const double *reg = c->g->regions;
    for (int32_t t = 0; t < c->nt; t++) {
        if (c->tbad[t]) continue;
        const int32_t *tv = c->tri + 3 * t;
        const double *a = c->xy + 2 * tv[0], *b = c->xy + 2 * tv[1], *p = c->xy + 2 * tv[2];
        double q[2];
        if (interior_point(a, b, p, q)) continue;
        int32_t k = c->g->nregions ? pslg_region_at(R, q) : -1;
        if (o->region_attr) {
            double want = k >= 0 ? reg[4 * k + 2] : 0;
            if (c->m->tattr[t] != want) {
                r->bad_region++;
                problem(r, "triangle %d has attribute %.17g, its region's is %.17g", t,
                        c->m->tattr[t], want);
            }
        }
        if (o->region_area && k >= 0 && reg[4 * k + 3] > 0 &&
            !(o->max_area > 0 && o->max_area < reg[4 * k + 3])) {
            double ar = 0.5 * ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]));
            if (ar > reg[4 * k + 3] * (1 + 1e-12)) {
                r->bad_area++;
                problem(r, "triangle %d has area %.6g > %.6g, its region's bound", t, ar,
                        reg[4 * k + 3]);
            }
        }
    }
    pslg_regions_free(R);
    return 0;
}

/* validate_area_slack of input g (working scale) whose domain area is dom. */
static double input_area_slack(const pslg *g, double dom) {
    double mag = 0, len = 0;
    for (int32_t i = 0; i < 2 * g->nverts; i++)
        mag = fmax(mag, fabs(g->xy[i]));
    for (int32_t s = 0; s < g->nsegs; s++)
        len += sqrt(
            geom_dist2(g->xy + 2 * (size_t)g->seg[2 * s], g->xy + 2 * (size_t)g->seg[2 * s + 1]));
    return validate_area_slack(dom, mag, len);
}

int validate_area_net(const pslg *g, double mesh_area, double *dom) {
    *dom = 0;
    if (!g || g->nsegs == 0) return 1; /* a point set: its hull is what the mesher made */
    *dom = pslg_domain_area(g);
    return validate_area_ok(mesh_area, *dom, input_area_slack(g, *dom));
}

/* 11. area of the domain */
static int check_domain_area(vctx *c) {
    validate_report *r = c->r;
    r->domain_area = c->g ? pslg_domain_area(c->g) : 0;
    if (c->g) r->area_slack_w = input_area_slack(c->g, r->domain_area);
    if (c->o->part) return 0; /* the caller compares the sum over the parts */
    if (c->g && !validate_area_ok(r->mesh_area, r->domain_area, r->area_slack_w)) {
        r->area_mismatch = 1;
        problem(r, "mesh area %.17g differs from the domain area %.17g", r->mesh_area,
                r->domain_area);
    }
    return 0;
}

typedef struct hsort {
    double x, y;
    int32_t i;
} hsort;

static int cmp_hsort(const void *pa, const void *pb) {
    const hsort *a = pa, *b = pb;
    if (a->x != b->x) return a->x < b->x ? -1 : 1;
    if (a->y != b->y) return a->y < b->y ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

/* A point set (no segments) is meshed over its convex hull, whose edges the mesher makes
 * segments (and may split, and splits at input points on them).  So the validator checks the
 * mesh against the same PSLG with the hull edges as segments: *h shares g's arrays except seg,
 * which the caller frees.  Andrew's monotone chain with exact orientation; collinear points
 * are not hull vertices (a hull segment passing through them is split there, as in the mesh).
 * Returns 0, or -1 (out of memory). */
static int hull_pslg(const pslg *g, pslg *h) {
    *h = *g;
    h->seg = NULL;
    h->smarker = NULL;
    h->sline = NULL;
    h->nsegs = 0;
    int32_t n = g->nverts;
    hsort *v = mesh_xmalloc(((size_t)n + 1) * sizeof *v, 1);
    int32_t *st = mesh_xmalloc((2 * (size_t)n + 2) * sizeof *st, 1);
    h->seg = mesh_xmalloc((4 * (size_t)n + 4) * sizeof *h->seg, 1);
    if (!v || !st || !h->seg) {
        free(v);
        free(st);
        free(h->seg);
        h->seg = NULL;
        return -1;
    }
    for (int32_t i = 0; i < n; i++)
        v[i] = (hsort){g->xy[2 * i], g->xy[2 * i + 1], i};
    qsort(v, (size_t)n, sizeof *v, cmp_hsort);
    int32_t k = 0;
    for (int pass = 0; pass < 2; pass++) { /* lower hull left to right, upper right to left */
        int32_t base = k;
        for (int32_t j = 0; j < n; j++) {
            int32_t i = v[pass ? n - 1 - j : j].i;
            while (k >= base + 2 &&
                   geom_orient2d(g->xy + 2 * st[k - 2], g->xy + 2 * st[k - 1], g->xy + 2 * i) <= 0)
                k--;
            if (k > base && g->xy[2 * st[k - 1]] == g->xy[2 * i] &&
                g->xy[2 * st[k - 1] + 1] == g->xy[2 * i + 1])
                continue; /* a duplicate point */
            st[k++] = i;
        }
        if (k - base >= 1 && pass == 0)
            k--; /* the last lower point starts the upper hull */
        else if (pass == 1)
            k--; /* ... and the first ends it */
    }
    for (int32_t i = 0; i < k; i++) {
        int32_t a = st[i], b = st[(i + 1) % k];
        if (a == b || (g->xy[2 * a] == g->xy[2 * b] && g->xy[2 * a + 1] == g->xy[2 * b + 1]))
            continue;
        h->seg[2 * h->nsegs] = a;
        h->seg[2 * h->nsegs + 1] = b;
        h->nsegs++;
    }
    free(v);
    free(st);
    return 0;
}

int mesh_validate(const pslg *g, const mesh_flat *m, const validate_opts *o, validate_report *r) {
    geom_init();
    memset(r, 0, sizeof *r);
    validate_opts none = {0};
    if (!o) o = &none;
    /* Work where the mesher worked: in g's coordinates, scaled by pslg_check (exact powers of
     * two, so the mesh's vertices land on the input's bits); areas go back at the end. */
    int e = g ? g->scale_exp : 0;
    double *sxy = NULL;
    validate_opts so = *o;
    if (e && so.max_area > 0) {
        so.max_area = ldexp(o->max_area, 2 * e);
        if (so.max_area == 0) so.max_area = DBL_MIN;
    }
    if (e != m->scale_exp) {
        sxy = mesh_xmalloc(2 * (size_t)m->nverts * sizeof *sxy + 1, 1);
        if (!sxy) {
            oom(r);
            return 0;
        }
        for (int64_t i = 0; i < 2 * (int64_t)m->nverts; i++)
            sxy[i] = ldexp(m->xy[i], e - m->scale_exp);
    }
    vctx c = {.g = g,
              .m = m,
              .o = &so,
              .r = r,
              .xy = sxy ? sxy : m->xy,
              .tri = m->tri,
              .nv = m->nverts,
              .nt = m->ntris};
    r->ntris = m->ntris;
    r->nverts = m->nverts;
    r->min_angle = 180;
    r->min_angle_unforced = 180;
    pslg hull;
    int use_hull = g && g->nsegs == 0 && g->nverts >= 3;
    if (use_hull) {
        if (hull_pslg(g, &hull) != 0) {
            oom(r);
            r->ok = 0;
            return 0;
        }
        c.g = &hull;
    }
    if (!check_indices(&c) && !check_orientation(&c) && !build_edge_buckets(&c) &&
        !add_segment_edges(&c) && !check_conformity(&c) && !check_input_vertices(&c) &&
        !find_small_corners(&c) && !check_input_segments(&c) && !check_delaunay(&c) &&
        !check_quality(&c) && !check_regions(&c))
        check_domain_area(&c);
    r->ok = !(r->bad_orient || r->bad_conform || r->missing_verts || r->missing_segs ||
              r->stray_boundary || r->non_delaunay || r->bad_angle || r->bad_area ||
              r->area_mismatch || r->bad_region || r->first_problem[0]);
    free(c.tbad);
    free(c.vflag);
    free(c.bstart);
    free(c.bhe);
    free(c.gmap);
    etab_free(&c.T);
    free(c.gl.g);
    free(c.tstart);
    free(c.tags);
    free(c.vt);
    pslg_pieces_free(&c.pc);
    free(sxy);
    if (use_hull) free(hull.seg);
    r->mesh_area_w = r->mesh_area;
    r->domain_area_w = r->domain_area;
    r->mesh_area = ldexp(r->mesh_area, -2 * e);
    r->domain_area = ldexp(r->domain_area, -2 * e);
    r->max_area = ldexp(r->max_area, -2 * e);
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
