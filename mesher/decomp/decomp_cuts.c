/* decomp_cuts: a decomposition given as straight cuts in a file (--cuts FILE).
 *
 * What: the paper's own route (TR-97-17 section 3 drew the processor boundaries by hand): the
 * user names the artificial constraint segments, this file turns them into the decomposition.
 *
 * Algorithm: the cuts are read ("FILE:LINE: problem" on any malformed line); an endpoint near
 * (1e-6 of the bounding box's diagonal) an input vertex or an earlier endpoint becomes that
 * point, one near a segment is projected onto it and splits it.  The input plus the cuts form
 * an augmented PSLG that pslg_check validates (crossings) and mesh_build_cdt triangulates.  The
 * subdomains are the faces of that arrangement (components of its triangles under adjacency
 * across non-constraint edges), so the cuts written by --write-cuts read back to a
 * decomposition at least as fine as the one written; a cut edge with the same subdomain (or the
 * outside) on both sides is an error naming its line.  decomp_build then extracts the pieces
 * exactly as for the automatic route.
 *
 * Invariants: segment identity survives pslg_check's normalisation through the marker field
 * (temporarily the index into a side table); sides and components come from the CDT's exact
 * topology.
 */
#include "decomp/decomp_impl.h"

#include "base/base.h"
#include "geom/geom.h"
#include "seq/rules.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SNAP_REL 1e-6

typedef struct cut {
    int32_t a, b; /* vertex ids in the augmented PSLG */
    int32_t line;
} cut;

typedef struct segrec { /* side table of the augmented PSLG's segments */
    int32_t parent;     /* input segment id, or cut id */
    int32_t marker;
    int32_t line;
    uint8_t is_cut;
} segrec;

typedef struct aug {
    pslg g;
    int32_t vcap, scap;
    segrec *sr;
    int32_t nsr, srcap;
} aug;

static int32_t add_vertex(aug *a, const double p[2]) {
    MESH_GROW(a->g.xy, 2 * (size_t)a->g.nverts + 1, a->vcap);
    a->g.xy[2 * (size_t)a->g.nverts] = p[0];
    a->g.xy[2 * (size_t)a->g.nverts + 1] = p[1];
    return a->g.nverts++;
}

static double dist_point_seg(const double *p, const double *a, const double *b, double q[2]) {
    double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    q[0] = a[0] + t * dx;
    q[1] = a[1] + t * dy;
    return sqrt(geom_dist2(p, q));
}

/* Endpoint p: an input vertex or earlier point within tol, else a new vertex (projected onto
 * the first segment within tol, input segments first, then earlier cuts). */
static int32_t place(aug *a, const pslg *in, const cut *c, int32_t nc, const double *p,
                     double tol) {
    for (int32_t v = 0; v < a->g.nverts; v++)
        if (sqrt(geom_dist2(p, a->g.xy + 2 * (size_t)v)) <= tol) return v;
    double q[2];
    for (int32_t s = 0; s < in->nsegs; s++)
        if (dist_point_seg(p, in->xy + 2 * (size_t)in->seg[2 * s],
                           in->xy + 2 * (size_t)in->seg[2 * s + 1], q) <= tol)
            return add_vertex(a, q);
    for (int32_t k = 0; k < nc; k++)
        if (dist_point_seg(p, a->g.xy + 2 * (size_t)c[k].a, a->g.xy + 2 * (size_t)c[k].b, q) <= tol)
            return add_vertex(a, q);
    return add_vertex(a, p);
}

typedef struct tpos {
    double t;
    int32_t v;
} tpos;

static int cmp_tpos(const void *x, const void *y) {
    const tpos *a = x, *b = y;
    return a->t < b->t ? -1 : a->t > b->t ? 1 : (a->v > b->v) - (a->v < b->v);
}

/* Adds segment u-v split at every new vertex (id >= first_new) within tol of its interior. */
static void add_split(aug *a, int32_t u, int32_t v, int32_t first_new, double tol, segrec r) {
    tpos *tp = mesh_xmalloc((size_t)(a->g.nverts - first_new) + 2, sizeof(tpos));
    int32_t n = 0;
    const double *pu = a->g.xy + 2 * (size_t)u, *pv = a->g.xy + 2 * (size_t)v;
    double l2 = geom_dist2(pu, pv), q[2];
    for (int32_t w = first_new; w < a->g.nverts; w++) {
        if (w == u || w == v) continue;
        const double *pw = a->g.xy + 2 * (size_t)w;
        if (dist_point_seg(pw, pu, pv, q) > tol) continue;
        double t = ((pw[0] - pu[0]) * (pv[0] - pu[0]) + (pw[1] - pu[1]) * (pv[1] - pu[1])) / l2;
        if (t > 0 && t < 1) tp[n++] = (tpos){t, w};
    }
    qsort(tp, (size_t)n, sizeof *tp, cmp_tpos);
    int32_t prev = u;
    for (int32_t i = 0; i <= n; i++) {
        int32_t w = i < n ? tp[i].v : v;
        if (w == prev) continue;
        int32_t s = a->g.nsegs;
        MESH_GROW(a->g.seg, 2 * (size_t)s + 1, a->scap);
        MESH_GROW(a->sr, a->nsr, a->srcap);
        a->g.seg[2 * s] = prev;
        a->g.seg[2 * s + 1] = w;
        a->sr[a->nsr] = r;
        a->g.nsegs++;
        a->nsr++;
        prev = w;
    }
    mesh_xfree(tp);
}

/* The next line of fp into buf (cap bytes, NUL-terminated, the newline kept): 1, 0 at the end,
 * -1 on a NUL byte (not a text file: /dev/zero stops here) or a line longer than buf. */
static int cut_line(FILE *fp, char *buf, size_t cap) {
    size_t k = 0;
    int c = EOF;
    while (k + 1 < cap && (c = getc(fp)) != EOF) {
        if (c == 0) return -1;
        buf[k++] = (char)c;
        if (c == '\n') break;
    }
    buf[k] = '\0';
    if (k + 1 == cap && c != '\n') return -1;
    return k > 0 ? 1 : 0;
}

static int read_cuts(const char *path, double **xy, int32_t **lines, int32_t *n, char *err,
                     size_t errlen) {
    FILE *fp = fopen(path, "r");
    if (!fp) return mesh_fail(err, errlen, "%s: cannot open: %s", path, strerror(errno));
    char buf[4096];
    int32_t line = 0, cap = 0, lcap = 0;
    *n = 0;
    *xy = NULL;
    *lines = NULL;
    for (int got; (got = cut_line(fp, buf, sizeof buf)) != 0;) {
        line++;
        if (got < 0) {
            fclose(fp);
            return mesh_fail(err, errlen,
                             "%s:%d: not a text file of cuts (a NUL byte, or a line of more "
                             "than %zu bytes)",
                             path, (int)line, sizeof buf - 2);
        }
        char *h = strchr(buf, '#');
        if (h) *h = 0;
        char *s = buf;
        while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')
            s++;
        if (!*s) continue;
        double v[4];
        char *end = s;
        for (int k = 0; k < 4; k++) {
            errno = 0;
            char *from = end;
            v[k] = strtod(from, &end);
            if (end == from || errno || !isfinite(v[k]) || (*end && !strchr(" \t\r\n", *end))) {
                fclose(fp);
                return mesh_fail(err, errlen, "%s:%d: expected four finite numbers x1 y1 x2 y2",
                                 path, (int)line);
            }
        }
        while (*end == ' ' || *end == '\t' || *end == '\r' || *end == '\n')
            end++;
        if (*end || (v[0] == v[2] && v[1] == v[3])) {
            fclose(fp);
            return mesh_fail(err, errlen, "%s:%d: %s", path, (int)line,
                             *end ? "trailing text after x1 y1 x2 y2" : "zero-length cut");
        }
        MESH_GROW(*xy, 4 * (size_t)*n + 3, cap);
        MESH_GROW(*lines, *n, lcap);
        memcpy(*xy + 4 * (size_t)*n, v, sizeof v);
        (*lines)[(*n)++] = line;
    }
    fclose(fp);
    if (*n == 0) return mesh_fail(err, errlen, "%s: no cuts", path);
    return 0;
}

typedef struct angle_ctx {
    const pslg *g;
    const segrec *sr;
    const char *path;
    char *err;
    size_t errlen;
    int bad;
} angle_ctx;

/* pslg_input_angles callback: a cut meeting another segment below the bound is an error. */
static void sharp(void *vctx, int32_t v, int32_t s1, int32_t s2, double deg) {
    angle_ctx *c = vctx;
    const segrec *a = &c->sr[c->g->smarker[s1]], *b = &c->sr[c->g->smarker[s2]];
    if (c->bad || (!a->is_cut && !b->is_cut)) return;
    const segrec *k = a->is_cut ? a : b, *o = a->is_cut ? b : a;
    c->bad = 1;
    mesh_fail(c->err, c->errlen,
              "%s:%d: the cut meets %s at %.2f degrees at (%.17g, %.17g), below the -q bound",
              c->path, (int)k->line, o->is_cut ? "another cut" : "an input segment", deg,
              c->g->xy[2 * (size_t)v], c->g->xy[2 * (size_t)v + 1]);
}

/* Components of m's triangles across non-constraint edges (the faces of the arrangement of
 * the input segments and the cuts); returns their number. */
static int32_t label(const mesh *m, int32_t *lab) {
    int32_t *stk = mesh_xmalloc((size_t)m->nt + 1, sizeof(int32_t)), K = 0;
    for (int32_t t = 0; t < m->nt; t++)
        lab[t] = -1;
    for (int32_t t0 = 0; t0 < m->nt; t0++) {
        if (!mesh_tri_alive(m, t0) || lab[t0] >= 0) continue;
        int32_t ns = 0;
        stk[ns++] = t0;
        lab[t0] = K;
        while (ns > 0) {
            int32_t t = stk[--ns];
            for (int j = 0; j < 3; j++) {
                int32_t e = 3 * t + j, n = m->tn[e];
                if (n < 0 || lab[n / 3] >= 0 || mesh_edge_constrained(m, e)) continue;
                lab[n / 3] = K;
                stk[ns++] = n / 3;
            }
        }
        K++;
    }
    mesh_xfree(stk);
    return K;
}

int pcdm_decomp_read_cuts(const char *path, const pslg *in, const pcdm_decomp_opts *o,
                          pcdm_decomp *out, char *err, size_t errlen) {
    memset(out, 0, sizeof *out);
    double *cxy = NULL;
    int32_t *cline = NULL, nc = 0;
    if (read_cuts(path, &cxy, &cline, &nc, err, errlen) != 0) {
        mesh_xfree(cxy);
        mesh_xfree(cline);
        return -1;
    }
    for (int32_t i = 0; i < 4 * nc; i++) /* the file's units are the input's: scaled alike */
        cxy[i] = ldexp(cxy[i], in->scale_exp);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int32_t v = 0; v < in->nverts; v++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], in->xy[2 * v + k]);
            hi[k] = fmax(hi[k], in->xy[2 * v + k]);
        }
    double tol = SNAP_REL * hypot(hi[0] - lo[0], hi[1] - lo[1]);
    aug a;
    memset(&a, 0, sizeof a);
    for (int32_t v = 0; v < in->nverts; v++)
        add_vertex(&a, in->xy + 2 * (size_t)v);
    cut *c = mesh_xmalloc((size_t)nc, sizeof(cut));
    for (int32_t k = 0; k < nc; k++) {
        c[k].a = place(&a, in, c, k, cxy + 4 * (size_t)k, tol);
        c[k].b = place(&a, in, c, k, cxy + 4 * (size_t)k + 2, tol);
        c[k].line = cline[k];
    }
    for (int32_t s = 0; s < in->nsegs; s++)
        add_split(&a, in->seg[2 * s], in->seg[2 * s + 1], in->nverts, tol,
                  (segrec){s, in->smarker[s], in->sline[s], 0});
    for (int32_t k = 0; k < nc; k++)
        add_split(&a, c[k].a, c[k].b, in->nverts, tol, (segrec){k, 0, c[k].line, 1});
    /* the augmented PSLG; smarker holds the side-table index through pslg_check */
    pslg *g = &a.g;
    g->vmarker = mesh_xcalloc((size_t)g->nverts + 1, sizeof(int32_t));
    g->vline = mesh_xcalloc((size_t)g->nverts + 1, sizeof(int32_t));
    if (in->nverts) memcpy(g->vmarker, in->vmarker, (size_t)in->nverts * sizeof(int32_t));
    g->smarker = mesh_xmalloc((size_t)g->nsegs + 1, sizeof(int32_t));
    g->sline = mesh_xmalloc((size_t)g->nsegs + 1, sizeof(int32_t));
    for (int32_t s = 0; s < g->nsegs; s++) {
        g->smarker[s] = s;
        g->sline[s] = a.sr[s].line;
    }
    g->nholes = in->nholes;
    g->holes = mesh_xmalloc(2 * (size_t)in->nholes + 1, sizeof(double));
    if (in->nholes) memcpy(g->holes, in->holes, 2 * (size_t)in->nholes * sizeof(double));
    g->first_index = in->first_index;
    snprintf(g->path, sizeof g->path, "%s", path);
    snprintf(g->segpath, sizeof g->segpath, "%s", path);
    mesh m;
    mesh_init(&m);
    int32_t *lab = NULL, *parent = NULL, *marker = NULL;
    uint8_t *iscut = NULL;
    double *tw = NULL;
    int rc = pslg_check(g, err, errlen);
    if (rc == 0 && o->min_angle > 0) {
        angle_ctx ac = {g, a.sr, path, err, errlen, 0};
        pslg_input_angles(g, o->min_angle, sharp, &ac);
        if (ac.bad) rc = -1;
    }
    if (rc == 0) rc = mesh_build_cdt(&m, g, NULL, err, errlen);
    for (int32_t s = 0; rc == 0 && s < m.nseg; s++) /* a cut in a hole or outside is eaten */
        if (a.sr[m.smarker[s]].is_cut && m.seg_nsub[s] == 0)
            rc = mesh_fail(err, errlen, "%s:%d: the cut lies outside the domain", path,
                           (int)a.sr[m.smarker[s]].line);
    for (int32_t i = 0; rc == 0 && i < m.nss; i++) {
        const mesh_subseg *r = &m.ss[i];
        if (r->level == -2 || !a.sr[m.smarker[r->seg]].is_cut) continue;
        if (mesh_find_edge(&m, r->u, r->v) < 0)
            rc = mesh_fail(err, errlen, "%s:%d: the cut lies (partly) outside the domain", path,
                           (int)a.sr[m.smarker[r->seg]].line);
    }
    int32_t K = 0;
    if (rc == 0) {
        lab = mesh_xmalloc((size_t)m.nt + 1, sizeof(int32_t));
        K = label(&m, lab);
        for (int32_t t = 0; rc == 0 && t < m.nt; t++)
            for (int j = 0; rc == 0 && mesh_tri_alive(&m, t) && j < 3; j++) {
                int32_t e = 3 * t + j, n = m.tn[e];
                if (!mesh_edge_constrained(&m, e)) continue;
                const mesh_subseg *s = mesh_subseg_of_edge(&m, e);
                if (!s || !a.sr[m.smarker[s->seg]].is_cut) continue;
                if (n < 0 || lab[n / 3] == lab[t])
                    rc = mesh_fail(err, errlen,
                                   "%s:%d: the cut does not separate two "
                                   "subdomains (%s)",
                                   path, (int)a.sr[m.smarker[s->seg]].line,
                                   n < 0 ? "it lies on the domain boundary"
                                         : "the same subdomain is on both sides");
            }
    }
    if (rc == 0 && o->nsub > 0 && o->nsub != K)
        rc = mesh_fail(err, errlen, "%s: the cuts make %d subdomains, not the %d asked for", path,
                       (int)K, (int)o->nsub);
    if (rc == 0 && K < o->nranks)
        rc = mesh_fail(err, errlen, "%s: the cuts make %d subdomains, fewer than the %d ranks",
                       path, (int)K, (int)o->nranks);
    if (rc == 0) {
        parent = mesh_xmalloc((size_t)m.nseg + 1, sizeof(int32_t));
        marker = mesh_xmalloc((size_t)m.nseg + 1, sizeof(int32_t));
        iscut = mesh_xmalloc((size_t)m.nseg + 1, 1);
        for (int32_t s = 0; s < m.nseg; s++) {
            const segrec *r = &a.sr[m.smarker[s]];
            parent[s] = r->parent;
            marker[s] = r->marker;
            iscut[s] = r->is_cut;
        }
        tw = mesh_xcalloc((size_t)m.nt + 1, sizeof(double));
        double b = pslg_scaled_area(in->scale_exp, o->max_area);
        for (int32_t t = 0; t < m.nt; t++)
            if (mesh_tri_alive(&m, t)) {
                double ar =
                    geom_area(mesh_vertex_xy(&m, m.tv[3 * t]), mesh_vertex_xy(&m, m.tv[3 * t + 1]),
                              mesh_vertex_xy(&m, m.tv[3 * t + 2]));
                tw[t] = b > 0 ? ar / b : ar;
            }
        decomp_threads th = {o->threads, o->cpus};
        rc = decomp_build(&th, in, &m, iscut, parent, marker, lab, tw, K, 0, out, err, errlen);
    }
    if (rc == 0) {
        out->floor2 = mesh_rules_length_floor2(m.xy, m.nv, m.tv, m.nt);
        for (int32_t k = 0; k < K; k++)
            out->sub_target[k] =
                out->total_weight > 0 ? out->sub_weight[k] / out->total_weight : 1.0 / K;
        out->ncoarse = m.nlive;
        rc = decomp_map_owners(out, o->nranks, o->imbalance > 0 ? o->imbalance : 1, NULL, err,
                               errlen);
        if (rc != 0) pcdm_decomp_free(out);
    }
    mesh_free(&m);
    mesh_xfree(lab);
    mesh_xfree(parent);
    mesh_xfree(marker);
    mesh_xfree(iscut);
    mesh_xfree(tw);
    mesh_xfree(c);
    mesh_xfree(cxy);
    mesh_xfree(cline);
    mesh_xfree(a.sr);
    pslg_free(g);
    return rc;
}
