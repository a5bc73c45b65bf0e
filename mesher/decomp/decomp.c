/* decomp: from a labelled triangulation to the decomposition PCDM and PBW consume.
 *
 * What: the last step of both decomposition routes (TR-97-17 section 3's "boundaries between
 * processors", drawn automatically).  Input: a triangulation of the domain (the coarse quality
 * mesh, or the CDT of the input plus a cuts file) whose triangles carry subdomain labels.
 * Output: the augmented PSLG -- the input segments split where interfaces end on them, plus the
 * interface edges (the triangulation's edges between triangles of different labels) -- with the
 * subdomain on each side of every piece, and the owners.
 *
 * Algorithm: one pass over the triangles finds the interface edges (each counted from its
 * lower-numbered triangle) and marks their endpoints as kept vertices (with keep_all, every
 * vertex of the triangulation is kept: the exact preview of decomp_auto.c); then each input
 * segment's subsegments are sorted along it (lexicographic order of their first vertex: exact for
 * collinear points) and cut into pieces at kept vertices and input vertices.  The two sides of
 * a piece are the labels of the triangles on the left and right of its first subsegment (the
 * directed edge's triangle is on its left; no float decides a side).  Owners: METIS on the
 * subdomain graph (METIS 5 manual, METIS_PartGraphKway) when K > P.
 *
 * Invariants: vertices keep the input's numbering first; no piece passes through a vertex of the
 * augmented PSLG (kept vertices and input vertices end pieces); every interface edge has two
 * different subdomains on its sides; the same input gives the same bits on every rank.
 */
#include "decomp/decomp_impl.h"

#include "base/base.h"
#include "geom/geom.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void pcdm_decomp_opts_default(pcdm_decomp_opts *o) {
    memset(o, 0, sizeof *o);
    o->nranks = 1;
    o->min_angle = 30;
    o->imbalance = 1;
    o->max_steiner = -1;
}

void pcdm_decomp_drop_triangles(pcdm_decomp *d) {
    mesh_xfree(d->tri_off);
    mesh_xfree(d->tri);
    d->tri_off = NULL;
    d->tri = NULL;
}

void pcdm_decomp_free(pcdm_decomp *d) {
    if (!d) return;
    pslg_free(&d->g);
    mesh_xfree(d->seg_parent);
    mesh_xfree(d->seg_iface);
    mesh_xfree(d->seg_sub);
    mesh_xfree(d->vert_sub);
    mesh_xfree(d->tri_off);
    mesh_xfree(d->tri);
    mesh_xfree(d->sub_seg_off);
    mesh_xfree(d->sub_seg);
    mesh_xfree(d->sub_vert_off);
    mesh_xfree(d->sub_vert);
    mesh_xfree(d->cut_xy);
    mesh_xfree(d->sub_seed);
    mesh_xfree(d->sub_area);
    mesh_xfree(d->sub_weight);
    mesh_xfree(d->sub_target);
    mesh_xfree(d->sub_owner);
    if (d->cdt) mesh_free(d->cdt);
    mesh_xfree(d->cdt);
    memset(d, 0, sizeof *d);
}

void decomp_int_weights(const double *w, int32_t n, idx_t *out) {
    double sum = 0, mn = INFINITY;
    for (int32_t i = 0; i < n; i++) {
        sum += w[i];
        if (w[i] > 0 && w[i] < mn) mn = w[i];
    }
    /* the smallest positive weight becomes about 8, unless the sum would pass 2^30 */
    double s = isfinite(mn) ? 8.0 / mn : 1.0;
    if (sum * s > 1073741824.0) s = 1073741824.0 / sum;
    for (int32_t i = 0; i < n; i++) {
        double x = floor(w[i] * s + 0.5);
        out[i] = x < 1 ? 1 : (idx_t)x;
    }
}

/* ---- building the augmented PSLG ---------------------------------------------------------- */

/* Lexicographic (x, then y) comparison of vertices: exact. */
static int lex_cmp(const double *a, const double *b) {
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    if (a[1] != b[1]) return a[1] < b[1] ? -1 : 1;
    return 0;
}

typedef struct rec {
    int32_t seg, u, v;
    int asc;
    const double *xy;
} rec;

static int cmp_rec(const void *x, const void *y) {
    const rec *a = x, *b = y;
    if (a->seg != b->seg) return a->seg < b->seg ? -1 : 1;
    int c = lex_cmp(a->xy + 2 * (size_t)a->u, a->xy + 2 * (size_t)b->u);
    return a->asc ? c : -c;
}

/* Subdomains on the left and right of the directed edge u -> v of m. */
static void sides(const mesh *m, const int32_t *part, int32_t u, int32_t v, int32_t *l,
                  int32_t *r) {
    int32_t e = mesh_find_edge(m, u, v);
    *l = *r = -1;
    if (e < 0) return;
    int32_t n = m->tn[e];
    int32_t a = part[e / 3], b = n >= 0 ? part[n / 3] : -1;
    if (mesh_org(m, e) == u) {
        *l = a;
        *r = b;
    } else {
        *l = b;
        *r = a;
    }
}

typedef struct gbuild {
    pcdm_decomp *d;
    int32_t cap;
} gbuild;

static void add_seg(gbuild *b, int32_t u, int32_t v, int32_t mark, int32_t line, int32_t parent,
                    int32_t l, int32_t r, int iface) {
    pcdm_decomp *d = b->d;
    int32_t s = d->g.nsegs;
    if (s >= b->cap) {
        b->cap = b->cap ? 2 * b->cap : 64;
        d->g.seg = mesh_xrealloc(d->g.seg, 2 * (size_t)b->cap, sizeof(int32_t));
        d->g.smarker = mesh_xrealloc(d->g.smarker, (size_t)b->cap, sizeof(int32_t));
        d->g.sline = mesh_xrealloc(d->g.sline, (size_t)b->cap, sizeof(int32_t));
        d->seg_parent = mesh_xrealloc(d->seg_parent, (size_t)b->cap, sizeof(int32_t));
        d->seg_iface = mesh_xrealloc(d->seg_iface, (size_t)b->cap, sizeof(uint8_t));
        d->seg_sub = mesh_xrealloc(d->seg_sub, 2 * (size_t)b->cap, sizeof(int32_t));
    }
    d->g.seg[2 * s] = u;
    d->g.seg[2 * s + 1] = v;
    d->g.smarker[s] = mark;
    d->g.sline[s] = line;
    d->seg_parent[s] = parent;
    d->seg_iface[s] = (uint8_t)iface;
    d->seg_sub[2 * s] = l;
    d->seg_sub[2 * s + 1] = r;
    d->g.nsegs = s + 1;
}

static void copy_pslg_extras(const pslg *in, pslg *g) {
    g->nholes = in->nholes;
    g->holes = mesh_xmalloc(2 * (size_t)in->nholes + 1, sizeof(double));
    if (in->nholes) memcpy(g->holes, in->holes, 2 * (size_t)in->nholes * sizeof(double));
    g->nregions = in->nregions;
    g->regions = mesh_xmalloc(4 * (size_t)in->nregions + 1, sizeof(double));
    if (in->nregions) memcpy(g->regions, in->regions, 4 * (size_t)in->nregions * sizeof(double));
    g->first_index = in->first_index;
    memcpy(g->path, in->path, sizeof g->path);
    memcpy(g->segpath, in->segpath, sizeof g->segpath);
}

/* Vertices of g: the input's, then every kept vertex of m beyond them (gid[v], -1 if dropped). */
static void build_vertices(const pslg *in, const mesh *m, const int32_t *mseg_marker,
                           const uint8_t *keep, int32_t *gid, pcdm_decomp *d) {
    int32_t n = in->nverts;
    for (int32_t v = 0; v < m->nv; v++)
        gid[v] = v < in->nverts ? v : (keep[v] ? n++ : -1);
    pslg *g = &d->g;
    g->nverts = n;
    g->xy = mesh_xmalloc(2 * (size_t)n + 1, sizeof(double));
    g->vmarker = mesh_xcalloc((size_t)n + 1, sizeof(int32_t));
    g->vline = mesh_xcalloc((size_t)n + 1, sizeof(int32_t));
    g->nattr = in->nattr;
    g->vattr = in->nattr ? mesh_xcalloc((size_t)in->nattr * n + 1, sizeof(double)) : NULL;
    if (in->nverts) {
        memcpy(g->xy, in->xy, 2 * (size_t)in->nverts * sizeof(double));
        memcpy(g->vmarker, in->vmarker, (size_t)in->nverts * sizeof(int32_t));
        memcpy(g->vline, in->vline, (size_t)in->nverts * sizeof(int32_t));
        if (in->nattr) memcpy(g->vattr, in->vattr, (size_t)in->nattr * in->nverts * sizeof(double));
    }
    for (int32_t v = in->nverts; v < m->nv; v++) {
        if (gid[v] < 0) continue;
        g->xy[2 * (size_t)gid[v]] = m->xy[2 * (size_t)v];
        g->xy[2 * (size_t)gid[v] + 1] = m->xy[2 * (size_t)v + 1];
        int32_t s = m->vseg[v];
        if (s >= 0 && s < m->nseg)
            g->vmarker[gid[v]] = mseg_marker ? mseg_marker[s] : m->smarker[s];
    }
}

static int cmp_rec_u(const void *x, const void *y) {
    const rec *a = x, *b = y;
    return (a->u > b->u) - (a->u < b->u);
}

/* 1 iff x is among the n sorted values a. */
static int has_i32(const int32_t *a, int32_t n, int32_t x) {
    int32_t lo = mesh_lower_i32(a, n, x);
    return lo < n && a[lo] == x;
}

/* Puts the n subsegment records of segment s (each directed along the segment) into chain
 * order by following vertex ids (u -> v), never coordinates: rounded split points need not be
 * monotone in x along a steep segment (a fuzzed segment from (0, 82) to (-1e4, 5.7e88) had them
 * out of order, and the chain looked broken).  Where removed regions cut the segment, what is
 * left in the domain is several chains (a segment through two holes that meet it at vertices of
 * its interior keeps its two ends): each chain starts at a record whose u is no record's v, and
 * the chains follow one another in order of their first vertex. */
static void chain_order(rec *r, int32_t n, int32_t s) {
    if (n < 2) return;
    qsort(r, (size_t)n, sizeof *r, cmp_rec_u);
    int32_t *vs = mesh_xmalloc((size_t)n, sizeof *vs);
    for (int32_t k = 0; k < n; k++)
        vs[k] = r[k].v;
    qsort(vs, (size_t)n, sizeof *vs, mesh_cmp_i32);
    rec *out = mesh_xmalloc((size_t)n, sizeof *out);
    int32_t no = 0;
    for (int32_t st = 0; st < n; st++) {
        if (has_i32(vs, n, r[st].u)) continue; /* not the start of a chain */
        int32_t at = r[st].u;
        for (;;) {
            int32_t lo = 0, hi = n; /* the record whose u is at */
            while (lo < hi) {
                int32_t mid = lo + (hi - lo) / 2;
                if (r[mid].u < at)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            if (lo == n || r[lo].u != at) break; /* the chain ends at at */
            if (no == n) MESH_BUG("subsegments of segment %d branch", s);
            out[no++] = r[lo];
            at = r[lo].v;
        }
    }
    mesh_xfree(vs);
    if (no != n) MESH_BUG("subsegments of segment %d form a cycle", s);
    memcpy(r, out, (size_t)n * sizeof *r);
    mesh_xfree(out);
}

/* The pieces of the non-cut segments of m (in segment order), split at kept vertices. */
static void build_pieces(const pslg *in, const mesh *m, const uint8_t *mseg_cut,
                         const int32_t *mseg_parent, const int32_t *mseg_marker,
                         const int32_t *part, const uint8_t *keep, const int32_t *gid, gbuild *b) {
    rec *r = mesh_xmalloc((size_t)m->nss + 1, sizeof(rec));
    int32_t nr = 0;
    int in_order = 1; /* by segment already (records are made segment by segment) */
    for (int32_t i = 0; i < m->nss; i++) {
        const mesh_subseg *s = &m->ss[i];
        if (s->level == -2 || s->seg < 0 || s->seg >= m->nseg) continue;
        if (mseg_cut && mseg_cut[s->seg]) continue;
        if (nr > 0 && s->seg < r[nr - 1].seg) in_order = 0;
        r[nr++] = (rec){s->seg, s->u, s->v, 0, m->xy};
    }
    /* by segment (a stable counting sort, unless they are in order), then along it: cmp_rec's
     * order (it has no ties), and on the fast route most segments have one piece */
    if (!in_order) {
        int32_t *cnt = mesh_xcalloc((size_t)m->nseg + 1, sizeof(int32_t));
        rec *sorted = mesh_xmalloc((size_t)nr + 1, sizeof(rec));
        for (int32_t k = 0; k < nr; k++)
            cnt[r[k].seg + 1]++;
        for (int32_t s = 0; s < m->nseg; s++)
            cnt[s + 1] += cnt[s];
        for (int32_t k = 0; k < nr; k++)
            sorted[cnt[r[k].seg]++] = r[k];
        mesh_xfree(cnt);
        mesh_xfree(r);
        r = sorted;
    }
    for (int32_t k = 0, k2; k < nr; k = k2) {
        for (k2 = k + 1; k2 < nr && r[k2].seg == r[k].seg; k2++)
            ;
        if (k2 - k == 1) continue;
        int32_t sg = r[k].seg; /* the segment's direction, for cmp_rec */
        int asc =
            lex_cmp(m->xy + 2 * (size_t)m->seg[2 * sg], m->xy + 2 * (size_t)m->seg[2 * sg + 1]) < 0;
        for (int32_t q = k; q < k2; q++)
            r[q].asc = asc;
        qsort(r + k, (size_t)(k2 - k), sizeof *r, cmp_rec);
    }
    int32_t i = 0;
    for (int32_t s = 0; s < m->nseg; s++) {
        if (mseg_cut && mseg_cut[s]) continue;
        int32_t parent = mseg_parent ? mseg_parent[s] : (s < in->nsegs ? s : -1);
        int32_t line = parent >= 0 && parent < in->nsegs ? in->sline[parent] : 0;
        int32_t mark = mseg_marker ? mseg_marker[s] : m->smarker[s];
        int32_t j = i;
        while (j < nr && r[j].seg == s)
            j++;
        if (j == i) { /* not in the triangulation (e.g. inside a hole): keep it whole */
            add_seg(b, gid[m->seg[2 * s]], gid[m->seg[2 * s + 1]], mark, line, parent, -1, -1, 0);
            continue;
        }
        chain_order(r + i, j - i, s);
        int32_t start = r[i].u, l = -1, rr = -1;
        sides(m, part, r[i].u, r[i].v, &l, &rr);
        for (int32_t k = i; k < j; k++) {
            int32_t v = r[k].v;
            int chain_ends = k + 1 == j || r[k + 1].u != v; /* a removed region follows */
            if (chain_ends || v < m->ninput || keep[v]) {
                add_seg(b, gid[start], gid[v], mark, line, parent, l, rr,
                        l >= 0 && rr >= 0 && l != rr);
                if (k + 1 < j) {
                    start = r[k + 1].u;
                    sides(m, part, r[k + 1].u, r[k + 1].v, &l, &rr);
                }
            }
        }
        i = j;
    }
    mesh_xfree(r);
}

void decomp_index(pcdm_decomp *d) {
    int32_t K = d->nsub, ns = d->g.nsegs, nv = d->vert_sub ? d->g.nverts : 0;
    int32_t *so = mesh_xcalloc((size_t)K + 2, sizeof(int32_t));
    int32_t *vo = mesh_xcalloc((size_t)K + 2, sizeof(int32_t));
    for (int pass = 0; pass < 2; pass++) { /* counts, then the lists (a counting sort) */
        for (int32_t s = 0; s < ns; s++)
            for (int side = 0; side < 2; side++) {
                int32_t k = d->seg_sub[2 * (size_t)s + side];
                if (k < 0 || k >= K || (side == 1 && k == d->seg_sub[2 * (size_t)s])) continue;
                if (pass == 0)
                    so[k + 2]++;
                else
                    d->sub_seg[so[k + 1]++] = s;
            }
        for (int32_t v = 0; v < nv; v++) {
            int32_t k = d->vert_sub[v];
            if (k < 0 || k >= K) continue;
            if (pass == 0)
                vo[k + 2]++;
            else
                d->sub_vert[vo[k + 1]++] = v;
        }
        if (pass == 1) break;
        for (int32_t k = 0; k < K; k++) {
            so[k + 2] += so[k + 1];
            vo[k + 2] += vo[k + 1];
        }
        d->sub_seg = mesh_xmalloc((size_t)so[K + 1] + 1, sizeof(int32_t));
        d->sub_vert = mesh_xmalloc((size_t)vo[K + 1] + 1, sizeof(int32_t));
    }
    d->sub_seg_off = so;
    d->sub_vert_off = vo;
}

int decomp_build(const decomp_threads *th, const pslg *in, const mesh *m, const uint8_t *mseg_cut,
                 const int32_t *mseg_parent, const int32_t *mseg_marker, const int32_t *part,
                 const double *tw, int32_t K, int keep_all, pcdm_decomp *d, char *err,
                 size_t errlen) {
    memset(d, 0, sizeof *d);
    d->g.scale_exp = in->scale_exp; /* its coordinates are in's, scaled alike */
    d->nsub = K;
    d->ninput_verts = in->nverts;
    d->ninput_segs = in->nsegs;
    uint8_t *keep = mesh_xcalloc((size_t)m->nv + 1, 1);
    d->sub_seed = mesh_xcalloc(2 * (size_t)K, sizeof(double));
    d->sub_area = mesh_xcalloc((size_t)K, sizeof(double));
    d->sub_weight = mesh_xcalloc((size_t)K, sizeof(double));
    d->sub_target = mesh_xcalloc((size_t)K, sizeof(double));
    d->sub_owner = mesh_xcalloc((size_t)K, sizeof(int32_t));
    /* pass 1: interface edges mark their endpoints; per-part sums and seeds */
    int32_t empty = decomp_pass1(th, m, part, tw, K, keep, d);
    if (empty >= 0) {
        mesh_xfree(keep);
        pcdm_decomp_free(d);
        return mesh_fail(err, errlen, "subdomain %d of %d is empty", (int)empty, (int)K);
    }
    int32_t *gid = mesh_xmalloc((size_t)m->nv + 1, sizeof(int32_t));
    for (int32_t v = 0; v < (keep_all ? m->nv : m->ninput); v++) /* input (cuts-file) vertices */
        keep[v] = keep_all ? m->vtri[v] >= 0 || v < m->ninput : 1;
    build_vertices(in, m, mseg_marker, keep, gid, d);
    d->vert_sub = mesh_xmalloc((size_t)d->g.nverts + 1, sizeof(int32_t));
    for (int32_t v = 0; v < d->g.nverts; v++)
        d->vert_sub[v] = -1;
    decomp_vert_parts(th, m, part, keep, gid, d->vert_sub);
    gbuild b = {d, 0};
    build_pieces(in, m, mseg_cut, mseg_parent, mseg_marker, part, keep, gid, &b);
    d->nboundary = d->g.nsegs;
    /* pass 2: the interface edges (non-input edges between different parts) */
    int32_t ncut = 0, ccap = 0, ne = 0, *edges = decomp_part_edges(th, m, part, &ne);
    for (int32_t i = 0; i < ne; i++) {
        int32_t e = edges[i], t = e / 3, n = m->tn[e], cid = -1;
        if (mesh_edge_constrained(m, e)) {
            const mesh_subseg *s = mesh_subseg_of_edge(m, e);
            if (!s) MESH_BUG("constraint edge %d has no subsegment", e);
            if (!mseg_cut || !mseg_cut[s->seg]) continue; /* an input piece: done above */
            cid = mseg_parent ? mseg_parent[s->seg] : s->seg;
        }
        int32_t u = mesh_org(m, e), v = mesh_dest(m, e);
        add_seg(&b, gid[u], gid[v], 0, 0, cid >= 0 ? cid : ncut, part[t], part[n / 3], 1);
        MESH_GROW(d->cut_xy, 4 * (size_t)ncut + 3, ccap);
        memcpy(d->cut_xy + 4 * (size_t)ncut, mesh_vertex_xy(m, u), 2 * sizeof(double));
        memcpy(d->cut_xy + 4 * (size_t)ncut + 2, mesh_vertex_xy(m, v), 2 * sizeof(double));
        ncut++;
    }
    mesh_xfree(edges);
    d->ncuts = ncut;
    if (!d->cut_xy) d->cut_xy = mesh_xmalloc(1, sizeof(double));
    if (!d->g.seg) { /* no segments at all: keep the arrays non-NULL */
        gbuild e = {d, 0};
        add_seg(&e, 0, 0, 0, 0, 0, 0, 0, 0);
        d->g.nsegs = 0;
    }
    copy_pslg_extras(in, &d->g);
    for (int32_t s = 0; s < d->g.nsegs; s++) /* a vertex that ends a segment is on no side */
        d->vert_sub[d->g.seg[2 * s]] = d->vert_sub[d->g.seg[2 * s + 1]] = -1;
    if (keep_all == 2) decomp_tris_by_part(th, m, part, gid, K, d); /* in g's numbers */
    decomp_index(d);
    d->iface_min_deg = pcdm_decomp_iface_min_angle(d);
    mesh_xfree(keep);
    mesh_xfree(gid);
    return 0;
}

/* ---- owners -------------------------------------------------------------------------------- */

/* Interface length between subdomains, as a CSR graph over the K subdomains. */
static void sub_graph(const pcdm_decomp *d, idx_t *xadj, idx_t **adjncy, double **len) {
    int32_t K = d->nsub;
    double *w = mesh_xcalloc((size_t)K * K, sizeof(double));
    for (int32_t s = 0; s < d->g.nsegs; s++) {
        int32_t a = d->seg_sub[2 * s], b = d->seg_sub[2 * s + 1];
        if (a < 0 || b < 0 || a == b) continue;
        const double *p = d->g.xy + 2 * (size_t)d->g.seg[2 * s],
                     *q = d->g.xy + 2 * (size_t)d->g.seg[2 * s + 1];
        double l = sqrt(geom_dist2(p, q));
        w[(size_t)a * K + b] += l;
        w[(size_t)b * K + a] += l;
    }
    int32_t n = 0;
    for (size_t i = 0; i < (size_t)K * K; i++)
        n += w[i] > 0;
    *adjncy = mesh_xmalloc((size_t)n + 1, sizeof(idx_t));
    *len = mesh_xmalloc((size_t)n + 1, sizeof(double));
    n = 0;
    xadj[0] = 0;
    for (int32_t a = 0; a < K; a++) {
        for (int32_t b = 0; b < K; b++)
            if (w[(size_t)a * K + b] > 0) {
                (*adjncy)[n] = b;
                (*len)[n++] = w[(size_t)a * K + b];
            }
        xadj[a + 1] = n;
    }
    mesh_xfree(w);
}

/* METIS may miss its balance on a graph of a few dozen subdomains (64 subdomains on 8 ranks:
 * the busiest rank 12% above its share).  Greedy repair: while moving one subdomain off the rank
 * with the highest load / target lowers the higher of the two loads involved below the busiest
 * one, move the subdomain that does it best (at most K * P moves; a rank keeps one subdomain).
 * Deterministic. */
static void rebalance(const pcdm_decomp *d, idx_t *own, int32_t *cnt, const real_t *tp, int32_t P) {
    int32_t K = d->nsub;
    double *load = mesh_xcalloc((size_t)P, sizeof(double));
    for (int32_t s = 0; s < K; s++)
        load[own[s]] += d->sub_weight[s];
    double tot = d->total_weight > 0 ? d->total_weight : 1;
    for (int64_t it = 0; it < (int64_t)K * P; it++) {
        int32_t h = 0;
        for (int32_t r = 1; r < P; r++)
            if (load[r] / tp[r] > load[h] / tp[h]) h = r;
        double worst = load[h] / (tp[h] * tot), best = worst;
        int32_t bs = -1, br = -1;
        for (int32_t s = 0; s < K && cnt[h] > 1; s++) {
            if (own[s] != h) continue;
            for (int32_t r = 0; r < P; r++) {
                if (r == h) continue;
                double a = (load[h] - d->sub_weight[s]) / (tp[h] * tot),
                       b = (load[r] + d->sub_weight[s]) / (tp[r] * tot), m = a > b ? a : b;
                if (m < best - 1e-12) {
                    best = m;
                    bs = s;
                    br = r;
                }
            }
        }
        if (bs < 0) break;
        load[h] -= d->sub_weight[bs];
        load[br] += d->sub_weight[bs];
        cnt[h]--;
        cnt[br]++;
        own[bs] = br;
    }
    mesh_xfree(load);
}

int decomp_map_owners(pcdm_decomp *d, int32_t P, double R, const int32_t *planned, char *err,
                      size_t errlen) {
    int32_t K = d->nsub;
    d->nranks = P;
    if (K < P) return mesh_fail(err, errlen, "%d subdomains for %d ranks", (int)K, (int)P);
    if (planned || K == P || P == 1) { /* (METIS cannot make one part) */
        for (int32_t s = 0; s < K; s++)
            d->sub_owner[s] = planned ? planned[s] : P == 1 ? 0 : s;
        return 0;
    }
    idx_t *xadj = mesh_xmalloc((size_t)K + 1, sizeof(idx_t)), *adj = NULL;
    double *len = NULL;
    sub_graph(d, xadj, &adj, &len);
    idx_t *vw = mesh_xmalloc((size_t)K, sizeof(idx_t)),
          *ew = mesh_xmalloc((size_t)xadj[K] + 1, sizeof(idx_t));
    decomp_int_weights(d->sub_weight, K, vw);
    decomp_int_weights(len, (int32_t)xadj[K], ew);
    real_t *tp = mesh_xmalloc((size_t)P, sizeof(real_t));
    for (int32_t r = 0; r < P; r++)
        tp[r] = (real_t)((r == 0 ? R : 1.0) / (R + P - 1));
    idx_t opt[METIS_NOPTIONS], n = K, ncon = 1, np = P, cut = 0;
    idx_t *own = mesh_xmalloc((size_t)K, sizeof(idx_t));
    METIS_SetDefaultOptions(opt);
    opt[METIS_OPTION_SEED] = 1;
    opt[METIS_OPTION_NUMBERING] = 0;
    int rc = METIS_PartGraphKway(&n, &ncon, xadj, adj, vw, NULL, ew, &np, tp, NULL, opt, &cut, own);
    if (rc != METIS_OK) {
        for (int32_t s = 0; s < K; s++) /* round robin still gives every rank a subdomain */
            own[s] = s % P;
    }
    int32_t *cnt = mesh_xcalloc((size_t)P, sizeof(int32_t));
    for (int32_t s = 0; s < K; s++)
        cnt[own[s]]++;
    for (int32_t r = 0; r < P; r++) {
        while (cnt[r] == 0) { /* take the lightest subdomain of the rank with the most */
            int32_t rich = 0, pick = -1;
            for (int32_t q = 1; q < P; q++)
                if (cnt[q] > cnt[rich]) rich = q;
            for (int32_t s = 0; s < K; s++)
                if (own[s] == rich && (pick < 0 || d->sub_weight[s] < d->sub_weight[pick]))
                    pick = s;
            own[pick] = r;
            cnt[rich]--;
            cnt[r]++;
        }
    }
    rebalance(d, own, cnt, tp, P);
    for (int32_t s = 0; s < K; s++)
        d->sub_owner[s] = (int32_t)own[s];
    mesh_xfree(cnt);
    mesh_xfree(own);
    mesh_xfree(tp);
    mesh_xfree(vw);
    mesh_xfree(ew);
    mesh_xfree(len);
    mesh_xfree(adj);
    mesh_xfree(xadj);
    return 0;
}

/* ---- cuts file output ------------------------------------------------------------------------ */

int pcdm_decomp_write_cuts(const pcdm_decomp *d, const char *path, char *err, size_t errlen) {
    char tmp[1100];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
        return mesh_fail(err, errlen, "%s: path too long", path);
    FILE *fp = fopen(tmp, "w");
    if (!fp) return mesh_fail(err, errlen, "%s: cannot create: %s", tmp, strerror(errno));
    fprintf(fp, "# pcdm cuts: %d subdomains; one cut per line: x1 y1 x2 y2\n", (int)d->nsub);
    for (int32_t k = 0; k < d->ncuts; k++)
        fprintf(fp, "%.17g %.17g %.17g %.17g\n", /* in the input's units */
                ldexp(d->cut_xy[4 * k], -d->g.scale_exp),
                ldexp(d->cut_xy[4 * k + 1], -d->g.scale_exp),
                ldexp(d->cut_xy[4 * k + 2], -d->g.scale_exp),
                ldexp(d->cut_xy[4 * k + 3], -d->g.scale_exp));
    int bad = ferror(fp);
    if (fclose(fp) || bad) {
        remove(tmp);
        return mesh_fail(err, errlen, "%s: write error", tmp);
    }
    if (rename(tmp, path)) {
        remove(tmp);
        return mesh_fail(err, errlen, "%s: cannot rename from %s: %s", path, tmp, strerror(errno));
    }
    return 0;
}

double pcdm_decomp_iface_min_angle(const pcdm_decomp *d) {
    const pslg *g = &d->g;
    int32_t *off = mesh_xcalloc((size_t)g->nverts + 2, sizeof(int32_t));
    int32_t *inc = mesh_xmalloc(2 * (size_t)g->nsegs + 1, sizeof(int32_t));
    for (int32_t s = 0; s < 2 * g->nsegs; s++)
        off[g->seg[s] + 1]++;
    for (int32_t v = 0; v < g->nverts; v++)
        off[v + 1] += off[v];
    for (int32_t s = 0; s < 2 * g->nsegs; s++)
        inc[off[g->seg[s]]++] = s / 2; /* off[v] ends as the start of v + 1 */
    double best = 180;
    for (int32_t v = 0, lo = 0; v < g->nverts; lo = off[v], v++)
        for (int32_t i = lo; i < off[v]; i++)
            for (int32_t j = i + 1; j < off[v]; j++) {
                int32_t a = inc[i], b = inc[j];
                if (!d->seg_iface[a] && !d->seg_iface[b]) continue;
                int32_t oa = g->seg[2 * a] == v ? g->seg[2 * a + 1] : g->seg[2 * a];
                int32_t ob = g->seg[2 * b] == v ? g->seg[2 * b + 1] : g->seg[2 * b];
                best = fmin(best, geom_angle_deg(g->xy + 2 * (size_t)oa, g->xy + 2 * (size_t)v,
                                                 g->xy + 2 * (size_t)ob));
            }
    free(off);
    free(inc);
    return best;
}
