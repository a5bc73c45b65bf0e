/* validate: the mesh validator (design.md, "Invariants every test can check"): mesh_validate
 * and the checks of the mesh's own structure; the checks against the input (vertices, segment
 * chains, small corners, quality, regions) are validate_input.c's.
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
 * to a relative 1e-9 plus what the chains' rounding can move (validate_area_slack).  Quality
 * checks exempt triangles at small input angles (rule in validate.h).  Regions (-A, --region-areas)
 * are found from the input alone: the face of the segment arrangement (pslg_regions) holding a
 * point exactly inside each triangle.
 */
#include "check/validate.h"

#include "base/base.h"
#include "check/validate_impl.h"
#include "geom/geom.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- helpers --------------- */

__attribute__((format(printf, 2, 3))) void validate_problem(validate_report *r, const char *fmt,
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

static void etab_grow(etab *T) {
    size_t ns = T->nslot ? T->nslot * 2 : 1024;
    int32_t *sl = mesh_xmalloc(ns, sizeof *sl);
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
}

/* Finds or adds the record of edge uv; returns its index. */
static int32_t etab_get(etab *T, int32_t u, int32_t v) {
    if (u > v) {
        int32_t x = u;
        u = v;
        v = x;
    }
    if ((size_t)(T->n + 1) * 2 > T->nslot) etab_grow(T);
    size_t mask = T->nslot - 1, i = mesh_hash64(ekey(u, v)) & mask;
    for (;; i = (i + 1) & mask) {
        int32_t k = T->slot[i];
        if (k < 0) break;
        if (T->rec[k].u == u && T->rec[k].v == v) return k;
    }
    if (T->n == T->cap) {
        T->cap = T->cap ? 2 * T->cap : 1024;
        T->rec = mesh_xrealloc(T->rec, (size_t)T->cap, sizeof *T->rec);
    }
    T->rec[T->n] = (erec){u, v, 0, -1, -1};
    T->slot[i] = T->n;
    return T->n++;
}

static void etab_free(etab *T) {
    free(T->rec);
    free(T->slot);
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

/* 1. indices and coordinates; 0 when every one is usable, else -1 (the other checks skipped) */
static int check_indices(vctx *c) {
    validate_report *r = c->r;
    const mesh_flat *m = c->m;
    for (int32_t i = 0; i < c->nv; i++)
        if (!isfinite(c->xy[2 * i]) || !isfinite(c->xy[2 * i + 1])) {
            r->bad_conform++;
            validate_problem(r, "vertex %d has a non-finite coordinate", i);
        }
    for (int64_t i = 0; i < 3 * (int64_t)c->nt; i++)
        if (c->tri[i] < 0 || c->tri[i] >= c->nv) {
            r->bad_conform++;
            validate_problem(r, "triangle %lld uses vertex %d, out of range [0, %d)",
                             (long long)(i / 3), c->tri[i], c->nv);
        }
    for (int64_t i = 0; i < 2 * (int64_t)m->nsegs; i++)
        if (m->seg[i] < 0 || m->seg[i] >= c->nv) {
            r->bad_conform++;
            validate_problem(r, "segment %lld uses vertex %d, out of range [0, %d)",
                             (long long)(i / 2), m->seg[i], c->nv);
        }
    if (c->nt > INT32_MAX / 3) {
        r->bad_conform++;
        validate_problem(r, "too many triangles (%d) for the validator", c->nt);
    }
    return r->bad_conform ? -1 : 0;
}

/* 2. orientation and areas */
static void check_orientation(vctx *c) {
    validate_report *r = c->r;
    const int32_t *tri = c->tri;
    c->tbad = mesh_xcalloc((size_t)c->nt + 1, 1);
    ksum area = {0, 0};
    for (int32_t t = 0; t < c->nt; t++) {
        const double *a = c->xy + 2 * tri[3 * t], *b = c->xy + 2 * tri[3 * t + 1],
                     *p = c->xy + 2 * tri[3 * t + 2];
        if (geom_orient2d(a, b, p) <= 0) {
            c->tbad[t] = 1;
            r->bad_orient++;
            validate_problem(r, "triangle %d (%d %d %d) is %s", t, tri[3 * t], tri[3 * t + 1],
                             tri[3 * t + 2],
                             geom_orient2d(a, b, p) < 0 ? "clockwise" : "degenerate (zero area)");
        }
        ksum_add(&area, 0.5 * geom_area2_accurate(a, b, p));
    }
    r->mesh_area = ksum_get(&area);
}

/* 3. directed edges bucketed by their smaller vertex, each bucket sorted by the larger */
static void build_edge_buckets(vctx *c) {
    const int32_t *tri = c->tri;
    int32_t nv = c->nv;
    c->bstart = mesh_xcalloc((size_t)nv + 2, sizeof *c->bstart);
    c->bhe = mesh_xmalloc(3 * (size_t)c->nt + 1, sizeof *c->bhe);
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
    pair64 *scratch = mesh_xmalloc((size_t)maxdeg + 1, sizeof *scratch);
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
}

/* 4. segment edges into the table */
static void add_segment_edges(vctx *c) {
    const mesh_flat *m = c->m;
    for (int32_t s = 0; s < m->nsegs; s++) {
        int32_t a = m->seg[2 * s], b = m->seg[2 * s + 1];
        if (a == b) {
            c->r->bad_conform++;
            validate_problem(c->r, "segment %d has equal endpoints (%d)", s, a);
            continue;
        }
        int32_t k = etab_get(&c->T, a, b);
        c->T.rec[k].flags |= E_MSEG;
        if (c->T.rec[k].mseg < 0) c->T.rec[k].mseg = s;
    }
}

/* 5. conformity; boundary edges */
static void check_conformity(vctx *c) {
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
                T->rec[k].flags |= E_BND | E_INMESH;
                T->rec[k].from = he_org(tri, he);
            } else {
                if (cnt > 2) {
                    r->bad_conform++;
                    validate_problem(r, "edge (%d, %d) is shared by %d triangles", v, w, cnt);
                } else if (he_org(tri, c->bhe[i]) == he_org(tri, c->bhe[i + 1])) {
                    r->bad_conform++;
                    validate_problem(
                        r,
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
            validate_problem(r, "segment %d (%d, %d) is not an edge of the mesh", T->rec[k].mseg,
                             T->rec[k].u, T->rec[k].v);
        }
}

/* 9. local Delaunay property of unconstrained interior edges */
static void check_delaunay(vctx *c) {
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
                        validate_problem(
                            c->r,
                            "edge (%d, %d) is not locally Delaunay: vertex %d lies inside "
                            "the circumcircle of triangle %u",
                            v, w, opp, t1);
                    }
                }
            }
            i = j;
        }
    }
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
    return validate_area_net_at(g, mesh_area, *dom);
}

int validate_area_net_at(const pslg *g, double mesh_area, double dom) {
    if (!g || g->nsegs == 0) return 1;
    return validate_area_ok(mesh_area, dom, input_area_slack(g, dom));
}

/* 11. area of the domain */
static void check_domain_area(vctx *c) {
    validate_report *r = c->r;
    r->domain_area = c->g ? pslg_domain_area(c->g) : 0;
    if (c->g) r->area_slack_w = input_area_slack(c->g, r->domain_area);
    if (c->o->part) return; /* the caller compares the sum over the parts */
    if (c->g && !validate_area_ok(r->mesh_area, r->domain_area, r->area_slack_w)) {
        r->area_mismatch = 1;
        validate_problem(r, "mesh area %.17g differs from the domain area %.17g", r->mesh_area,
                         r->domain_area);
    }
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
 */
static void hull_pslg(const pslg *g, pslg *h) {
    *h = *g;
    h->seg = NULL;
    h->smarker = NULL;
    h->sline = NULL;
    h->nsegs = 0;
    int32_t n = g->nverts;
    hsort *v = mesh_xmalloc((size_t)n + 1, sizeof *v);
    int32_t *st = mesh_xmalloc(2 * (size_t)n + 2, sizeof *st);
    h->seg = mesh_xmalloc(4 * (size_t)n + 4, sizeof *h->seg);
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
        sxy = mesh_xmalloc(2 * (size_t)m->nverts, sizeof *sxy);
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
        hull_pslg(g, &hull);
        c.g = &hull;
    }
    if (check_indices(&c) == 0) { /* the rest only with every index in range */
        check_orientation(&c);
        build_edge_buckets(&c);
        add_segment_edges(&c);
        check_conformity(&c);
        validate_input_vertices(&c);
        validate_small_corners(&c);
        validate_input_segments(&c);
        check_delaunay(&c);
        validate_quality(&c);
        validate_regions(&c);
        check_domain_area(&c);
    }
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
