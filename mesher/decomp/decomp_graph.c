/* decomp_graph: the graph METIS partitions on the automatic decomposition's coarse mesh, and
 * the partition (decomp_auto.c's steps (3) and the graph behind them).
 *
 * The dual graph of the coarse triangles, the triangles around each input corner sharper than
 * 60 degrees one graph vertex (corner_nodes: union-find, numbered in order of first appearance);
 * an edge's weight is the shared edge's length, ENC_PENALTY times when an apex encroaches it
 * (PCDM would have to split it).  On the fast route, with CLUSTER_MIN graph vertices or more,
 * METIS partitions connected clusters of at most CLUSTER of them instead (graph_clusters, made
 * from the mesh directly, its rows on the decomposition's threads: decomp_for_chunks' chunks of
 * clusters, concatenated in order, so the same graph for any thread count).  METIS_PartGraphKway
 * (METIS 5 manual) with fixed seeds is deterministic, so every rank that partitions the same
 * graph gets the same labels.  Local.
 */
#include "decomp/decomp_impl.h"

#include "base/base.h"
#include "geom/geom.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define ENC_PENALTY 64.0 /* METIS edge weight factor of an encroached edge */
#define CLUSTER 8        /* the fast route: METIS partitions clusters of this many triangles */
#define CLUSTER_MIN 8192 /* ... when the graph has this many vertices */

/* Is edge e (a live triangle's) encroached by the apex on either side (diametral circle)? */
int decomp_edge_encroached(const mesh *m, int32_t e) {
    const double *a = mesh_vertex_xy(m, mesh_org(m, e)), *b = mesh_vertex_xy(m, mesh_dest(m, e));
    if (geom_encroaches(a, b, mesh_vertex_xy(m, mesh_apex(m, e)))) return 1;
    int32_t f = m->tn[e];
    return f >= 0 && geom_encroaches(a, b, mesh_vertex_xy(m, mesh_apex(m, f)));
}

typedef struct gedge {
    int32_t a, b;
    double len;
} gedge;

static int32_t uf_find(int32_t *up, int32_t x) {
    while (up[x] != x)
        x = up[x] = up[up[x]];
    return x;
}

void decomp_graph_free(pgraph *g) {
    mesh_xfree(g->node);
    mesh_xfree(g->xadj);
    mesh_xfree(g->adj);
    mesh_xfree(g->len);
    mesh_xfree(g->w);
    memset(g, 0, sizeof *g);
}

/* The length METIS sees on edge e (a live triangle's): its length, ENC_PENALTY times when an
 * apex encroaches it and penalize is set.  The same from either side. */
static double edge_len(const mesh *m, int32_t e, int penalize) {
    double l =
        sqrt(geom_dist2(mesh_vertex_xy(m, mesh_org(m, e)), mesh_vertex_xy(m, mesh_dest(m, e))));
    return penalize && decomp_edge_encroached(m, e) ? l * ENC_PENALTY : l;
}

/* Triangles' graph vertices (node[i] of compact triangle i): the triangles around each input
 * corner sharper than 60 degrees united, numbered in order of first appearance.  Returns their
 * number. */
static int32_t corner_nodes(const mesh *m, const int32_t *id, int32_t n, int32_t *node) {
    int32_t *up = mesh_xmalloc((size_t)n + 1, sizeof(int32_t));
    for (int32_t i = 0; i < n; i++)
        up[i] = i;
    if (m->has_corners && m->corner) {
        int32_t *first = mesh_xmalloc((size_t)m->ninput + 1, sizeof(int32_t));
        for (int32_t v = 0; v < m->ninput; v++)
            first[v] = -1;
        for (int32_t t = 0; t < m->nt; t++)
            for (int j = 0; id[t] >= 0 && j < 3; j++) {
                int32_t v = m->tv[3 * t + j];
                if (v >= m->ninput || !m->corner[v]) continue;
                if (first[v] < 0)
                    first[v] = id[t];
                else
                    up[uf_find(up, id[t])] = uf_find(up, first[v]);
            }
        mesh_xfree(first);
    }
    int32_t nn = 0;
    for (int32_t i = 0; i < n; i++)
        node[i] = -1;
    for (int32_t i = 0; i < n; i++) { /* numbered in order of first appearance */
        int32_t r = uf_find(up, i);
        if (node[r] < 0) node[r] = nn++;
        node[i] = node[r];
    }
    mesh_xfree(up);
    return nn;
}

/* The dual graph itself: a vertex per corner node.  The edges in rows by a, in triangle order
 * within a row (two passes over the triangles: the rows' lengths, then the edges in place),
 * each row then sorted by b with duplicates (united vertices) merged. */
static void graph_triangles(const mesh *m, const int32_t *id, const double *tw, int penalize,
                            pgraph *g) {
    int32_t nn = g->nn, *node = g->node;
    double *w = mesh_xcalloc((size_t)nn + 1, sizeof(double));
    idx_t *xadj = mesh_xcalloc((size_t)nn + 2, sizeof(idx_t));
    for (int32_t t = 0; t < m->nt; t++) {
        if (id[t] < 0) continue;
        int32_t a = node[id[t]];
        w[a] += tw[t];
        for (int j = 0; j < 3; j++) {
            int32_t nb = m->tn[3 * t + j];
            if (nb >= 0 && node[id[nb / 3]] != a) xadj[a + 2]++;
        }
    }
    for (int32_t x = 0; x < nn; x++)
        xadj[x + 2] += xadj[x + 1];
    int32_t ng = (int32_t)xadj[nn + 1];
    gedge *row = mesh_xmalloc((size_t)ng + 1, sizeof(gedge));
    for (int32_t t = 0; t < m->nt; t++) { /* each edge once, from its lower code: both rows */
        if (id[t] < 0) continue;
        int32_t a = node[id[t]];
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, nb = m->tn[e];
            if (nb < e) continue;
            int32_t b = node[id[nb / 3]];
            if (b == a) continue;
            double l = edge_len(m, e, penalize);
            row[xadj[a + 1]++] = (gedge){a, b, l};
            row[xadj[b + 1]++] = (gedge){b, a, l};
        }
    }
    idx_t *adj = mesh_xmalloc((size_t)ng + 1, sizeof(idx_t));
    double *len = mesh_xmalloc((size_t)ng + 1, sizeof(double));
    int32_t ne = 0;
    for (int32_t x = 0, at = 0; x < nn; x++) {
        int32_t end = (int32_t)xadj[x + 1];
        xadj[x] = ne;
        for (int32_t u = at + 1; u < end; u++) { /* insertion sort by b: rows are short */
            gedge ge = row[u];
            int32_t k = u;
            for (; k > at && row[k - 1].b > ge.b; k--)
                row[k] = row[k - 1];
            row[k] = ge;
        }
        for (int32_t i = at; i < end; i++) {
            if (i > at && row[i].b == row[i - 1].b) {
                len[ne - 1] += row[i].len;
                continue;
            }
            adj[ne] = row[i].b;
            len[ne++] = row[i].len;
        }
        at = end;
    }
    xadj[nn] = ne;
    mesh_xfree(row);
    g->xadj = xadj, g->adj = adj, g->len = len, g->w = w;
}

/* graph_clusters' rows, made chunk by chunk of clusters (decomp_for_chunks): chunk k's rows in
 * ca[k], cln[k] (n[k] entries), cx[c] the start of cluster c's row in its chunk's. */
typedef struct graph_rows {
    const mesh *m;
    const int32_t *id, *node, *cl, *q, *start;
    const double *tw;
    int penalize;
    idx_t **ca, *cx;
    double **cln, *cw;
    int64_t *n;
} graph_rows;

static void rows_chunk(void *arg, int32_t k, int32_t c0, int32_t c1) {
    graph_rows *R = arg;
    const mesh *m = R->m;
    int64_t n = 0, cap = 0;
    idx_t *ca = NULL;
    double *cln = NULL;
    for (int32_t c = c0; c < c1; c++) {
        int64_t row = n;
        R->cx[c] = (idx_t)n;
        for (int32_t at = R->start[c]; at < R->start[c + 1]; at++) {
            int32_t t = R->q[at];
            R->cw[c] += R->tw[t];
            for (int j = 0; j < 3; j++) {
                int32_t e = 3 * t + j, nb = m->tn[e];
                if (nb < 0) continue;
                int32_t d = R->cl[R->node[R->id[nb / 3]]];
                if (d == c) continue;
                double l = edge_len(m, e, R->penalize);
                int64_t i = row;
                while (i < n && ca[i] != d)
                    i++;
                if (i < n) { /* this row has d already */
                    cln[i] += l;
                    continue;
                }
                if (n == cap) {
                    cap = cap ? 2 * cap : 4096;
                    ca = mesh_xrealloc(ca, (size_t)cap, sizeof(idx_t));
                    cln = mesh_xrealloc(cln, (size_t)cap, sizeof(double));
                }
                ca[n] = d;
                cln[n++] = l;
            }
        }
    }
    R->ca[k] = ca, R->cln[k] = cln, R->n[k] = n;
}

/* The graph of clusters (g->node: the triangles' graph vertices, g->nn of them), made from m
 * directly, never the graph of the triangles: the graph vertices are grown into connected
 * clusters of at most CLUSTER (breadth first across the triangles' edges from the lowest
 * unclustered triangle, in slot order: a cluster of the triangles' graph, since a corner node's
 * triangles are one graph vertex), and a cluster is a vertex of the graph METIS partitions (its
 * weight the sum of its triangles' tw, an edge's length the sum of edge_len over the triangle
 * edges it stands for), so METIS starts CLUSTER times smaller.  g->node is mapped to the
 * clusters; g->nn becomes their number. */
static void graph_clusters(const decomp_threads *th, const mesh *m, const int32_t *id,
                           const double *tw, int penalize, pgraph *g) {
    int32_t nn = g->nn, nc = 0, *node = g->node;
    int32_t *cl = mesh_xmalloc((size_t)nn + 1, sizeof(int32_t));
    int32_t *q = mesh_xmalloc((size_t)m->nt + 1, sizeof(int32_t));
    for (int32_t x = 0; x < nn; x++)
        cl[x] = -1;
    for (int32_t t = 0; t < m->nt; t++) {
        if (id[t] < 0 || cl[node[id[t]]] >= 0) continue;
        int32_t qh = 0, qt = 0, got = 1;
        q[qt++] = t;
        cl[node[id[t]]] = nc;
        while (qh < qt && got < CLUSTER) {
            int32_t y = q[qh++];
            for (int j = 0; j < 3 && got < CLUSTER; j++) {
                int32_t nb = m->tn[3 * y + j];
                if (nb < 0) continue;
                int32_t b = node[id[nb / 3]];
                if (cl[b] >= 0) continue;
                cl[b] = nc;
                got++;
                q[qt++] = nb / 3;
            }
        }
        nc++;
    }
    /* the live triangles by cluster (a counting sort, slot order within one) */
    int32_t *start = mesh_xcalloc((size_t)nc + 2, sizeof(int32_t));
    for (int32_t t = 0; t < m->nt; t++)
        if (id[t] >= 0) start[cl[node[id[t]]] + 2]++;
    for (int32_t c = 0; c < nc; c++)
        start[c + 2] += start[c + 1];
    for (int32_t t = 0; t < m->nt; t++)
        if (id[t] >= 0) q[start[cl[node[id[t]]] + 1]++] = t;
    /* each cluster's row: its triangles' edges to other clusters (a row names a cluster once:
     * found in the row so far, rows being short), chunks of clusters on th's threads */
    graph_rows R = {.m = m,
                    .id = id,
                    .node = node,
                    .cl = cl,
                    .q = q,
                    .start = start,
                    .tw = tw,
                    .penalize = penalize};
    int32_t nk = decomp_nchunks(nc);
    R.ca = mesh_xcalloc((size_t)nk + 1, sizeof(idx_t *));
    R.cln = mesh_xcalloc((size_t)nk + 1, sizeof(double *));
    R.n = mesh_xcalloc((size_t)nk + 1, sizeof(int64_t));
    R.cx = mesh_xmalloc((size_t)nc + 1, sizeof(idx_t));
    R.cw = mesh_xcalloc((size_t)nc + 1, sizeof(double));
    decomp_for_chunks(th, nc, rows_chunk, &R);
    idx_t ne = 0, *cx = R.cx;
    for (int32_t k = 0; k < nk; k++)
        ne += (idx_t)R.n[k];
    idx_t *ca = mesh_xmalloc((size_t)ne + 1, sizeof(idx_t));
    double *cln = mesh_xmalloc((size_t)ne + 1, sizeof(double)), *cw = R.cw;
    int64_t csz = decomp_chunk(nc);
    for (int32_t k = 0, at = 0; k < nk; k++) {
        for (int64_t c = k * csz; c < (k + 1) * csz && c < nc; c++)
            cx[c] += at;
        if (R.n[k]) {
            memcpy(ca + at, R.ca[k], (size_t)R.n[k] * sizeof(idx_t));
            memcpy(cln + at, R.cln[k], (size_t)R.n[k] * sizeof(double));
        }
        at += (idx_t)R.n[k];
        mesh_xfree(R.ca[k]);
        mesh_xfree(R.cln[k]);
    }
    mesh_xfree(R.ca);
    mesh_xfree(R.cln);
    mesh_xfree(R.n);
    cx[nc] = ne;
    for (int32_t i = 0; i < g->ntri; i++)
        node[i] = cl[node[i]];
    mesh_xfree(q);
    mesh_xfree(start);
    mesh_xfree(cl);
    g->nn = nc;
    g->xadj = cx, g->adj = ca, g->len = cln, g->w = cw;
}

/* 1 iff every vertex of g is reached from vertex 0. */
static int graph_connected(const pgraph *g) {
    int32_t nn = g->nn, ns = 0, reached = 1;
    int32_t *stk = mesh_xmalloc((size_t)nn + 1, sizeof(int32_t));
    uint8_t *seen = mesh_xcalloc((size_t)nn + 1, 1);
    stk[ns++] = 0;
    seen[0] = 1;
    while (ns > 0) {
        int32_t x = stk[--ns];
        for (idx_t k = g->xadj[x]; k < g->xadj[x + 1]; k++)
            if (!seen[g->adj[k]]) {
                seen[g->adj[k]] = 1;
                reached++;
                stk[ns++] = (int32_t)g->adj[k];
            }
    }
    mesh_xfree(stk);
    mesh_xfree(seen);
    return reached == nn;
}

/* The graph of m's live triangles (id[t]: compact index, -1 for dead slots) that partition
 * splits: the dual graph, the triangles around each input corner sharper than 60 degrees one
 * graph vertex (they must share a part, decomp_merge_corners, so METIS sees their weight together
 * and balances around it); with coarsen and at least CLUSTER_MIN of those, its clusters
 * (graph_clusters, which never makes the graph of the triangles).  Made once for all the seeds
 * partition tries on it. */
void decomp_graph_build(const decomp_threads *th, const mesh *m, const int32_t *id, int32_t n,
                        const double *tw, int penalize, int coarsen, pgraph *g) {
    memset(g, 0, sizeof *g);
    g->node = mesh_xmalloc((size_t)n + 1, sizeof(int32_t));
    g->ntri = n;
    g->nn = corner_nodes(m, id, n, g->node);
    if (coarsen && g->nn >= CLUSTER_MIN) {
        /* METIS on clusters, and no contiguous parts asked for (g->connected 0): measured on
         * North America at 16 subdomains, they made 64% more interface splits and a largest
         * part 3% larger */
        graph_clusters(th, m, id, tw, penalize, g);
    } else {
        graph_triangles(m, id, tw, penalize, g);
        g->connected = graph_connected(g);
    }
}

/* METIS on g (graph_build of m's triangles), n of them live, into K parts of the target
 * fractions; labels of m's triangle slots into part (-1 for dead ones).  sel (NULL: METIS seed
 * `seed`): the seeds to try, keeping the partition of least decomp_part_cost in part and its
 * cost in *cost (INFINITY, labels -1, if METIS failed on every seed: not an error here, since
 * another rank may have one). */
int decomp_partition(const mesh *m, const int32_t *id, int32_t n, const pgraph *g, const double *tw,
                     const double *target, int32_t K, const pcdm_decomp_opts *sel, int32_t seed,
                     double *cost, int32_t *part, char *err, size_t errlen) {
    int32_t nn = g->nn, ne = (int32_t)g->xadj[nn];
    const int32_t *node = g->node;
    idx_t *vw = mesh_xmalloc((size_t)nn + 1, sizeof(idx_t)),
          *ew = mesh_xmalloc((size_t)ne + 1, sizeof(idx_t)),
          *pp = mesh_xmalloc((size_t)nn + 1, sizeof(idx_t));
    decomp_int_weights(g->w, nn, vw);
    decomp_int_weights(g->len, ne, ew);
    real_t *tp = mesh_xmalloc((size_t)K, sizeof(real_t));
    for (int32_t k = 0; k < K; k++)
        tp[k] = (real_t)target[k];
    idx_t opt[METIS_NOPTIONS], nv = nn, ncon = 1, np = K, cut = 0;
    METIS_SetDefaultOptions(opt);
    opt[METIS_OPTION_NUMBERING] = 0;
    int32_t nseeds = sel && sel->seed_count > 0 ? sel->seed_count : 1;
    int32_t *cand = sel ? mesh_xmalloc((size_t)m->nt + 1, sizeof(int32_t)) : part;
    int rc = METIS_ERROR_INPUT;
    if (sel) *cost = INFINITY;
    for (int32_t i = 0; i < nseeds; i++) {
        opt[METIS_OPTION_SEED] =
            sel && sel->seed_count > 0 ? sel->seed_first + i * sel->seed_step : seed;
        opt[METIS_OPTION_CONTIG] = g->connected;
        int r = nn < K ? METIS_ERROR_INPUT
                       : METIS_PartGraphKway(&nv, &ncon, g->xadj, g->adj, vw, NULL, ew, &np, tp,
                                             NULL, opt, &cut, pp);
        if (r != METIS_OK && nn >= K && opt[METIS_OPTION_CONTIG]) {
            opt[METIS_OPTION_CONTIG] = 0;
            r = METIS_PartGraphKway(&nv, &ncon, g->xadj, g->adj, vw, NULL, ew, &np, tp, NULL, opt,
                                    &cut, pp);
        }
        if (!sel || r == METIS_OK) rc = r;
        for (int32_t t = 0; t < m->nt; t++)
            cand[t] = id[t] >= 0 && r == METIS_OK ? (int32_t)pp[node[id[t]]] : -1;
        if (!sel) break;
        double c = r == METIS_OK ? decomp_part_cost(m, tw, cand, K, sel->boundary_cost) : INFINITY;
        if (c < *cost || i == 0) {
            if (c < *cost) *cost = c;
            memcpy(part, cand, (size_t)m->nt * sizeof(int32_t));
        }
    }
    if (sel) {
        mesh_xfree(cand);
        rc = METIS_OK; /* failures: *cost stays INFINITY (the caller decides) */
    }
    mesh_xfree(vw);
    mesh_xfree(ew);
    mesh_xfree(pp);
    mesh_xfree(tp);
    if (rc != METIS_OK)
        return mesh_fail(err, errlen,
                         "METIS could not partition %d coarse triangles into %d "
                         "parts (error %d)",
                         (int)n, (int)K, rc);
    return 0;
}
