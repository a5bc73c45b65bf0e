/* decomp_auto: automatic decomposition by partitioning a coarse quality mesh with METIS.
 *
 * What: the preprocessing step of TR-97-17 section 3 ("the boundaries between processors must
 * be created during a preprocessing step"), which the paper did by hand.  Works for every PSLG
 * the sequential mesher accepts (holes, separate faces, internal and dangling segments, point
 * sets, far-from-origin coordinates), because it only ever asks that mesher for a mesh.
 *
 * Algorithm: (1) the CDT of the input is refined with the angle bound alone (at least 30
 * degrees, a little above the final bound), which grades it by the local feature size like the
 * final mesh; then, with an area bound, with an area bound that gives about per_sub triangles
 * per subdomain (never below 4 times the final bound, so the interfaces stay coarser than the
 * final mesh); without one, only when that leaves fewer than 8 triangles per subdomain (the
 * final mesh is then about as coarse as this one, and every interface vertex stays in it).  (2)
 * Each coarse triangle's work is max(1, area / max_area) with an area bound, else 1.  (3)
 * METIS_PartGraphKway splits the dual graph (vertex weights: work; edge weights: shared edge
 * length; target fractions from the imbalance; contiguous parts when the graph is connected; fixed
 * seed) into K parts. (4) Triangles around an input corner sharper than 60 degrees join one part,
 * so no interface ends in a corner whose coarse triangles are exempt from the angle bound.  (5)
 * decomp_build turns the labels into interface segments.  Every angle an interface makes with
 * another segment then contains a corner of a coarse triangle, hence is at least the coarse bound.
 *
 * Invariants: topology comes from the mesher's exact predicates; METIS and the mesher are
 * deterministic, so every rank computes the same decomposition without communication.
 */
#include "decomp/decomp_impl.h"

#include "base/base.h"
#include "geom/geom.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define PER_SUB_DEFAULT 200
#define MIN_PER_SUB 8 /* with no area bound: coarse triangles per subdomain at least */

/* Rank 0 gets k0 ~ K R / (R + P - 1) subdomains (at least one, leaving one per other rank);
 * the others share the rest; a rank's work share is split evenly over its subdomains. */
static void plan(int32_t K, int32_t P, double R, double *target, int32_t *owner) {
    if (P == 1 || R == 1) {
        for (int32_t s = 0; s < K; s++) {
            target[s] = 1.0 / K;
            owner[s] = (int32_t)((int64_t)s * P / K);
        }
        return;
    }
    int32_t k0 = (int32_t)floor(K * R / (R + P - 1) + 0.5);
    if (k0 < 1) k0 = 1;
    if (k0 > K - (P - 1)) k0 = K - (P - 1);
    int32_t rest = K - k0, base = rest / (P - 1), extra = rest % (P - 1), s = 0;
    for (int32_t r = 0; r < P; r++) {
        int32_t cnt = r == 0 ? k0 : base + (r - 1 < extra);
        double share = (r == 0 ? R : 1.0) / (R + P - 1);
        for (int32_t i = 0; i < cnt; i++, s++) {
            target[s] = share / cnt;
            owner[s] = r;
        }
    }
}

static double live_area(const mesh *m) {
    double a = 0;
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t))
            a += geom_area(mesh_vertex_xy(m, m->tv[3 * t]), mesh_vertex_xy(m, m->tv[3 * t + 1]),
                           mesh_vertex_xy(m, m->tv[3 * t + 2]));
    return a;
}

static void refine(mesh *m, double angle, double area, int64_t limit) {
    mesh_quality q;
    memset(&q, 0, sizeof q);
    q.min_angle = angle;
    q.max_area = area;
    q.max_steiner = limit;
    q.offcenter = 1;
    mesh_set_quality(m, &q);
    (void)mesh_refine(m); /* a Steiner limit only leaves a coarser mesh: still a partition */
}

/* METIS on the dual graph of m's live triangles (id[t]: compact index, -1 for dead slots). */
static int partition(const mesh *m, const int32_t *id, int32_t n, const double *tw,
                     const double *target, int32_t K, int32_t *part, char *err, size_t errlen) {
    idx_t *xadj = mesh_xmalloc((size_t)n + 1, sizeof(idx_t));
    idx_t *adj = mesh_xmalloc(3 * (size_t)n + 1, sizeof(idx_t));
    double *len = mesh_xmalloc(3 * (size_t)n + 1, sizeof(double)),
           *w = mesh_xmalloc((size_t)n + 1, sizeof(double));
    int32_t ne = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        if (id[t] < 0) continue;
        xadj[id[t]] = ne;
        w[id[t]] = tw[t];
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, nb = m->tn[e];
            if (nb < 0) continue;
            adj[ne] = id[nb / 3];
            len[ne++] = sqrt(
                geom_dist2(mesh_vertex_xy(m, mesh_org(m, e)), mesh_vertex_xy(m, mesh_dest(m, e))));
        }
    }
    xadj[n] = ne;
    /* connected? (contiguous parts are asked for only then) */
    int32_t *stk = mesh_xmalloc((size_t)n + 1, sizeof(int32_t));
    uint8_t *seen = mesh_xcalloc((size_t)n + 1, 1);
    int32_t ns = 0, reached = 1;
    stk[ns++] = 0;
    seen[0] = 1;
    while (ns > 0) {
        int32_t x = stk[--ns];
        for (idx_t k = xadj[x]; k < xadj[x + 1]; k++)
            if (!seen[adj[k]]) {
                seen[adj[k]] = 1;
                reached++;
                stk[ns++] = (int32_t)adj[k];
            }
    }
    mesh_xfree(stk);
    mesh_xfree(seen);
    idx_t *vw = mesh_xmalloc((size_t)n + 1, sizeof(idx_t)),
          *ew = mesh_xmalloc((size_t)ne + 1, sizeof(idx_t)),
          *pp = mesh_xmalloc((size_t)n + 1, sizeof(idx_t));
    decomp_int_weights(w, n, vw);
    decomp_int_weights(len, ne, ew);
    real_t *tp = mesh_xmalloc((size_t)K, sizeof(real_t));
    for (int32_t k = 0; k < K; k++)
        tp[k] = (real_t)target[k];
    idx_t opt[METIS_NOPTIONS], nn = n, ncon = 1, np = K, cut = 0;
    METIS_SetDefaultOptions(opt);
    opt[METIS_OPTION_SEED] = 1;
    opt[METIS_OPTION_NUMBERING] = 0;
    opt[METIS_OPTION_CONTIG] = reached == n;
    int rc = METIS_PartGraphKway(&nn, &ncon, xadj, adj, vw, NULL, ew, &np, tp, NULL, opt, &cut, pp);
    if (rc != METIS_OK && opt[METIS_OPTION_CONTIG]) {
        opt[METIS_OPTION_CONTIG] = 0;
        rc = METIS_PartGraphKway(&nn, &ncon, xadj, adj, vw, NULL, ew, &np, tp, NULL, opt, &cut, pp);
    }
    for (int32_t t = 0; t < m->nt; t++)
        part[t] = id[t] >= 0 ? (int32_t)pp[id[t]] : -1;
    mesh_xfree(xadj);
    mesh_xfree(adj);
    mesh_xfree(len);
    mesh_xfree(w);
    mesh_xfree(vw);
    mesh_xfree(ew);
    mesh_xfree(pp);
    mesh_xfree(tp);
    if (rc != METIS_OK)
        return decomp_fail(err, errlen,
                           "METIS could not partition %d coarse triangles into %d "
                           "parts (error %d)",
                           (int)n, (int)K, rc);
    return 0;
}

/* Every live triangle around an input corner sharper than 60 degrees takes the part of the
 * first such triangle met. */
static void merge_corners(const mesh *m, int32_t *part) {
    if (!m->has_corners || !m->corner) return;
    int32_t *cp = mesh_xmalloc((size_t)m->ninput + 1, sizeof(int32_t));
    for (int32_t v = 0; v < m->ninput; v++)
        cp[v] = -1;
    for (int32_t t = 0; t < m->nt; t++)
        for (int j = 0; mesh_tri_alive(m, t) && j < 3; j++) {
            int32_t v = m->tv[3 * t + j];
            if (v < m->ninput && m->corner[v] && cp[v] < 0) cp[v] = part[t];
        }
    for (int32_t t = 0; t < m->nt; t++)
        for (int j = 0; mesh_tri_alive(m, t) && j < 3; j++) {
            int32_t v = m->tv[3 * t + j];
            if (v < m->ninput && m->corner[v]) part[t] = cp[v];
        }
    mesh_xfree(cp);
}

int pcdm_decomp_auto(const pslg *in, const pcdm_decomp_opts *o, pcdm_decomp *out, char *err,
                     size_t errlen) {
    memset(out, 0, sizeof *out);
    int32_t P = o->nranks, K = o->nsub > 0 ? o->nsub : o->nranks;
    if (P < 1) return decomp_fail(err, errlen, "%d ranks", (int)P);
    if (K < P)
        return decomp_fail(err, errlen, "%d subdomains: fewer than the %d ranks", (int)K, (int)P);
    double R = o->imbalance > 0 ? o->imbalance : 1;
    int32_t per = o->per_sub > 0 ? o->per_sub : PER_SUB_DEFAULT;
    mesh m;
    mesh_init(&m);
    if (mesh_build_cdt(&m, in, NULL, err, errlen) != 0) {
        mesh_free(&m);
        return -1;
    }
    double qc = o->min_angle + 2;
    qc = qc < 30 ? 30 : qc > 33 ? 33 : qc;
    if (K > 1) {
        int64_t limit = 40 * (int64_t)K * per + 20 * (int64_t)m.nv + 1000;
        refine(&m, qc, 0, limit);
        double A = live_area(&m);
        if (o->max_area > 0) {
            double ac = A / ((double)K * per);
            if (ac < 4 * o->max_area) ac = 4 * o->max_area;
            if (ac < A) refine(&m, qc, ac, limit);
        } else if (m.nlive < (int64_t)K * MIN_PER_SUB) {
            /* the final mesh will be about as coarse as this one: refine only as far as the
             * partition needs, since every interface vertex stays in the final mesh */
            refine(&m, qc, A / ((double)K * MIN_PER_SUB), limit);
        }
    }
    int32_t *id = mesh_xmalloc((size_t)m.nt + 1, sizeof(int32_t));
    int32_t *part = mesh_xmalloc((size_t)m.nt + 1, sizeof(int32_t));
    double *tw = mesh_xcalloc((size_t)m.nt + 1, sizeof(double));
    int32_t n = 0;
    for (int32_t t = 0; t < m.nt; t++) {
        id[t] = mesh_tri_alive(&m, t) ? n++ : -1;
        part[t] = 0;
        if (id[t] < 0) continue;
        double ar = geom_area(mesh_vertex_xy(&m, m.tv[3 * t]), mesh_vertex_xy(&m, m.tv[3 * t + 1]),
                              mesh_vertex_xy(&m, m.tv[3 * t + 2]));
        tw[t] = o->max_area > 0 && ar > o->max_area ? ar / o->max_area : 1;
    }
    double *target = mesh_xmalloc((size_t)K, sizeof(double));
    int32_t *planned = mesh_xmalloc((size_t)K, sizeof(int32_t));
    plan(K, P, R, target, planned);
    int rc = 0;
    if (K > 1 && n < 2 * K)
        rc = decomp_fail(err, errlen,
                         "%d subdomains: the domain's coarse mesh has only %d triangles", (int)K,
                         (int)n);
    if (rc == 0 && K > 1) rc = partition(&m, id, n, tw, target, K, part, err, errlen);
    if (rc == 0) {
        merge_corners(&m, part);
        rc = decomp_build(in, &m, NULL, NULL, NULL, part, tw, K, out, err, errlen);
    }
    if (rc == 0) {
        out->ncoarse = n;
        memcpy(out->sub_target, target, (size_t)K * sizeof(double));
        rc = decomp_map_owners(out, P, R, R != 1 ? planned : NULL, err, errlen);
        if (rc != 0) pcdm_decomp_free(out);
    }
    mesh_xfree(id);
    mesh_xfree(part);
    mesh_xfree(tw);
    mesh_xfree(target);
    mesh_xfree(planned);
    mesh_free(&m);
    return rc;
}
