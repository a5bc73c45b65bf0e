/* decomp_auto: automatic decomposition by partitioning a coarse quality mesh with METIS.
 *
 * What: the preprocessing step of TR-97-17 section 3 ("the boundaries between processors must
 * be created during a preprocessing step"), which the paper did by hand.  Works for every PSLG
 * the sequential mesher accepts (holes, separate faces, internal and dangling segments, point
 * sets, far-from-origin coordinates), because it only ever asks that mesher for a mesh.
 *
 * Algorithm: (0) the exact preview: when the final mesh is small -- at most exact_per_sub
 * triangles per subdomain, which the area bound rules out at once or a refinement of the input's
 * CDT at the real bounds under a Steiner limit finds out -- that refinement IS the coarse mesh
 * (refined further with an area bound only if it has fewer than 12 triangles per rank or 2 per
 * subdomain).  Its triangles are the final ones, so METIS balances the actual triangles and every
 * interface is a final mesh edge; edges a neighbouring apex encroaches (diametral circle) cost
 * METIS 64 times their length, since PCDM would have to split them.  Otherwise (1) on inputs of
 * FAST_MIN_VERTS vertices or more (below, the coarse route (1') costs little), the fast route:
 * the input's CDT itself, with the centroids of its triangles larger than about 1/per_sub of
 * a subdomain's area inserted (never below 4 times the final area bound), so the coarse mesh costs
 * about one CDT of the input and splits no segment, whatever the input's size: on a coastline the
 * lfs-graded mesh is most of the final one, and the subdomains make it in parallel.  Its work
 * weights are 2.5 per triangle (the triangles the local feature size grades about each input
 * vertex, 5 per vertex on coastlines, over about 2 CDT triangles a vertex) plus 1.45 area /
 * max_area (the area bound's triangles, whose mean area is about 0.7 of the bound); its edges an
 * apex encroaches cost METIS 64 times their length, as on the preview.  The interior points are
 * circumcenters that encroach no segment (Ruppert's rule: well spaced, away from the boundary),
 * else centroids.  When its interfaces meet a segment below FAST_MIN_DEG for FAST_SEEDS METIS
 * seeds (the partition made again for each), or it fails, (1') the coarse route: the CDT of the
 * input is refined with the angle bound alone (at least 30 degrees, a little above the final
 * bound), which grades it by the local feature size like the final mesh; then, with an area bound,
 * with an area bound that gives about per_sub triangles per subdomain (never below 4 times the
 * final bound, so the interfaces stay coarser than the final mesh); without one, only when that
 * leaves fewer than 8 triangles per subdomain; the one whose interfaces are wider is kept.  (2) On
 * the coarse route each coarse triangle's work is max(1, area / max_area) with an area bound,
 * else 1.  (3) METIS_PartGraphKway splits the dual graph (vertex weights: work; edge weights:
 * shared edge length; target fractions from the imbalance; contiguous parts when the graph is
 * connected, but not on the fast route's clusters; fixed seed; the graph made once for every
 * seed tried) into K parts; the triangles around an input corner sharper than 60 degrees
 * are one graph vertex.  (4) So they join one part, and no interface ends in a corner whose coarse
 * triangles are exempt from the angle bound; a part METIS left empty takes a triangle of the
 * largest part that can give one.  (5) Wide sectors (coarse route): around every vertex, a sector
 * of triangles of one part narrower than 60 degrees that an interface bounds joins the lighter part
 * across that interface if that lowers the number of narrow sectors around the moved triangles (so
 * it cannot oscillate; repeated until nothing changes, at most 32 passes).  On the exact preview,
 * instead, a triangle whose apex encroaches an interface edge joins the part across it (or the
 * triangle across joins its part), so PCDM splits no interface and no cascade can start; if some
 * interface stays encroached (parts of one or two triangles), the sectors are widened as well.  Two
 * interfaces (or an interface and the boundary) meeting at less than 45 degrees split each other's
 * dyadic pieces forever when their lengths fall in a bad ratio (each new midpoint lies in the other
 * piece's diametral circle), which refinement reaches at many subdomains; at 60 degrees or more no
 * midpoint can encroach the neighbouring piece.  (6) decomp_build turns the labels into interface
 * segments. Every angle an interface makes with another segment then contains a corner of a coarse
 * triangle, hence is at least the coarse bound.  (7) An exact preview is kept only if one
 * sequential refinement of the augmented PSLG meets the bounds (as small as the preview; the PCDM
 * mesh does not depend on the ranks); else it is redrawn with 12 triangles per subdomain, and
 * failing that the coarse route is used.
 *
 * Invariants: topology comes from the mesher's exact predicates (encroachment by
 * geom_encroaches); sector angles are a float quality figure that only moves interfaces; METIS
 * and the mesher are deterministic, so every rank computes the same decomposition without
 * communication.
 */
#include "decomp/decomp_impl.h"

#include "base/base.h"
#include "bounds/bounds.h"
#include "geom/geom.h"
#include "seq/kernel.h"
#include "seq/rules.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PER_SUB_DEFAULT 200
#define MIN_PER_SUB 8              /* with no area bound: coarse triangles per subdomain at least */
#define EXACT_PER_SUB_DEFAULT 1000 /* exact preview up to this many final triangles per part */
#define EXACT_MIN_PER_RANK 12      /* exact preview: triangles per rank at least */
#define EXACT_SAFE_PER_SUB 12      /* ... per subdomain, when 2 per subdomain fails the trial */
#define FIT_MIN_PER_SUB 64         /* a default count halves to this many final triangles each */
#define ENC_PENALTY 64.0           /* METIS edge weight factor of an encroached edge (exact) */
#define WIDE_DEG 60.0              /* sectors an interface bounds are at least this wide */
#define WIDEN_PASSES 32
#define FAST_MIN_DEG 30.0 /* the fast route's interfaces narrower than this: try the coarse one */
#define FAST_SEEDS 3      /* ... after this many METIS seeds on the fast route */
#define FAST_MIN_VERTS                                                                             \
    8192 /* inputs with fewer vertices take the coarse route (it costs little)                     \
          */
#define DEG_PER_RAD 57.295779513082320876798
#define CLUSTER 8        /* the fast route: METIS partitions clusters of this many triangles */
#define CLUSTER_MIN 8192 /* ... when the graph has this many vertices */

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

/* Refines m (off-centers and diametral circles, as ./mesh and ./pcdm) to area (working units,
 * 0: none); a Steiner limit (or an unresolved triangle) only leaves a coarser mesh, still a
 * partition. */
static mesh_refine_result refine(mesh *m, double angle, double area, int64_t limit) {
    mesh_quality q;
    memset(&q, 0, sizeof q);
    q.min_angle = angle;
    q.max_area = pslg_input_area(m->scale_exp, area);
    q.max_steiner = limit;
    q.offcenter = 1;
    mesh_set_quality(m, &q);
    return mesh_refine(m);
}

/* Inserts p as a free vertex of m, found from triangle t, unless it lies outside the domain, on
 * a constraint, or (check) in the diametral circle of a constraint edge of its cavity's
 * boundary (Ruppert's rule, which keeps inserted points away from the segments).  1 if
 * inserted. */
static int insert_free(mesh *m, const double p[2], int32_t t, int check) {
    t = mesh_locate(m, p, t);
    if (t < 0) return 0;
    for (int j = 0; j < 3; j++) {
        int32_t e = 3 * t + j;
        const double *a = mesh_vertex_xy(m, m->tv[e]), *b = mesh_vertex_xy(m, mesh_dest(m, e));
        if ((a[0] == p[0] && a[1] == p[1]) ||
            (mesh_edge_constrained(m, e) && geom_orient2d(a, b, p) == 0))
            return 0;
    }
    int32_t bad = -1;
    int ok = mesh_cavity_collect(m, p, t, -1, &bad) == CAV_OK;
    for (int32_t i = 0; ok && check && i < m->nbnd; i++) {
        const mesh_bedge *b = &m->bnd[i];
        if (b->cons && geom_encroaches(mesh_vertex_xy(m, b->org), mesh_vertex_xy(m, b->dest), p))
            ok = 0;
    }
    if (!ok) {
        mesh_cavity_abort(m);
        return 0;
    }
    mesh_cavity_commit(m, mesh_vert_add(m, p[0], p[1], -1), -1, -1);
    return 1;
}

/* A min-heap of slot indices (interior_points' slots made ahead of its position in a pass). */
typedef struct iheap {
    int32_t *a, n, cap;
} iheap;

static void iheap_push(iheap *h, int32_t x) {
    MESH_GROW(h->a, (size_t)h->n + 1, h->cap);
    int32_t i = h->n++;
    for (; i > 0 && h->a[(i - 1) / 2] > x; i = (i - 1) / 2)
        h->a[i] = h->a[(i - 1) / 2];
    h->a[i] = x;
}

static int32_t iheap_pop(iheap *h) {
    int32_t top = h->a[0], x = h->a[--h->n], i = 0;
    for (;;) {
        int32_t c = 2 * i + 1;
        if (c >= h->n) break;
        if (c + 1 < h->n && h->a[c + 1] < h->a[c]) c++;
        if (h->a[c] >= x) break;
        h->a[i] = h->a[c];
        i = c;
    }
    if (h->n > 0) h->a[i] = x;
    return top;
}

/* The fast route's coarse mesh: every triangle larger than area (working units) gets a free
 * vertex, pass after pass, until none is larger or limit vertices were added: its circumcenter
 * where that encroaches no segment (well spaced, as in Delaunay refinement), else its centroid,
 * which lies strictly inside it.  No segment is split: the input's segments stay whole.  A pass
 * visits, in index order, the slots below the pass's first slot count that are not known small
 * -- the order of a scan of all of them that skips the slots found small since they were last
 * made -- but only those: the first pass every slot, later ones the slots an insertion made
 * (behind the pass's position or beyond its count: the next pass; ahead of it: this one, from
 * the heap) and those whose insertion failed. */
static void interior_points(mesh *m, double area, int64_t limit) {
    int64_t added = 0;
    int32_t nb = m->nt, *base = mesh_xmalloc((size_t)nb + 1, sizeof(int32_t)), nn = 0, ncap = 0;
    int32_t *next = NULL;
    for (int32_t t = 0; t < nb; t++)
        base[t] = t;
    iheap h = {0};
    for (int more = 1; more && added < limit;) {
        more = 0;
        int32_t nt = m->nt, last = -1;
        nn = 0;
        for (int32_t bi = 0; added < limit;) {
            int32_t t;
            if (h.n > 0 && (bi == nb || h.a[0] < base[bi]))
                t = iheap_pop(&h);
            else if (bi < nb)
                t = base[bi++];
            else
                break;
            if (t <= last || t >= nt) continue; /* met twice, or made after the pass began */
            last = t;
            if (!mesh_tri_alive(m, t)) continue; /* made again later: an insertion's new slot */
            const double *a = mesh_vertex_xy(m, m->tv[3 * t]),
                         *b = mesh_vertex_xy(m, m->tv[3 * t + 1]),
                         *c = mesh_vertex_xy(m, m->tv[3 * t + 2]);
            if (geom_area(a, b, c) <= area) continue; /* small: until it is made again */
            double cc[2], p[2] = {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3};
            int ins = geom_circumcenter(a, b, c, cc) == 0 && insert_free(m, cc, t, 1);
            if (!ins) ins = insert_free(m, p, t, 0);
            if (!ins) { /* looked at again next pass */
                MESH_GROW(next, (size_t)nn + 1, ncap);
                next[nn++] = t;
                continue;
            }
            added++, more = 1;
            for (int32_t i = 0; i < m->nnewt; i++) {
                int32_t u = m->newt[i];
                if (u > t && u < nt) {
                    iheap_push(&h, u);
                } else {
                    MESH_GROW(next, (size_t)nn + 1, ncap);
                    next[nn++] = u;
                }
            }
        }
        h.n = 0;
        /* the next pass's slots, ascending, each once */
        qsort(next, (size_t)nn, sizeof(int32_t), mesh_cmp_i32);
        int32_t k = 0;
        for (int32_t i = 0; i < nn; i++)
            if (k == 0 || next[i] != next[k - 1]) next[k++] = next[i];
        mesh_xfree(base);
        base = next, nb = k;
        next = NULL, ncap = 0;
    }
    mesh_xfree(base);
    mesh_xfree(next);
    mesh_xfree(h.a);
}

/* Is edge e (a live triangle's) encroached by the apex on either side (diametral circle)? */
static int edge_encroached(const mesh *m, int32_t e) {
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

/* The graph METIS partitions: nn vertices in rows xadj/adj (no duplicates, none to itself),
 * edge lengths len, vertex weights w; node[i] is the graph vertex of compact triangle i;
 * connected: every vertex reached from vertex 0 (contiguous parts are asked for only then);
 * ntri: the number of compact triangles. */
typedef struct pgraph {
    int32_t nn, ntri, *node;
    idx_t *xadj, *adj;
    double *len, *w;
    int connected;
} pgraph;

static void graph_free(pgraph *g) {
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
    return penalize && edge_encroached(m, e) ? l * ENC_PENALTY : l;
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

/* The graph of clusters (g->node: the triangles' graph vertices, g->nn of them), made from m
 * directly, never the graph of the triangles: the graph vertices are grown into connected
 * clusters of at most CLUSTER (breadth first across the triangles' edges from the lowest
 * unclustered triangle, in slot order: a cluster of the triangles' graph, since a corner node's
 * triangles are one graph vertex), and a cluster is a vertex of the graph METIS partitions (its
 * weight the sum of its triangles' tw, an edge's length the sum of edge_len over the triangle
 * edges it stands for), so METIS starts CLUSTER times smaller.  g->node is mapped to the
 * clusters; g->nn becomes their number. */
static void graph_clusters(const mesh *m, const int32_t *id, const double *tw, int penalize,
                           pgraph *g) {
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
    /* each cluster's row: its triangles' edges to other clusters, merged through last[] */
    int64_t cap = 4 * (int64_t)nc + 64;
    idx_t *cx = mesh_xmalloc((size_t)nc + 1, sizeof(idx_t));
    idx_t *ca = mesh_xmalloc((size_t)cap, sizeof(idx_t));
    double *cln = mesh_xmalloc((size_t)cap, sizeof(double));
    double *cw = mesh_xcalloc((size_t)nc + 1, sizeof(double));
    int32_t *last = mesh_xmalloc((size_t)nc + 1, sizeof(int32_t));
    for (int32_t c = 0; c < nc; c++)
        last[c] = -1;
    idx_t ne = 0;
    for (int32_t c = 0, at = 0; c < nc; c++) {
        cx[c] = ne;
        for (; at < start[c + 1]; at++) {
            int32_t t = q[at];
            cw[c] += tw[t];
            for (int j = 0; j < 3; j++) {
                int32_t e = 3 * t + j, nb = m->tn[e];
                if (nb < 0) continue;
                int32_t d = cl[node[id[nb / 3]]];
                if (d == c) continue;
                double l = edge_len(m, e, penalize);
                if (last[d] >= cx[c]) { /* this row has d already */
                    cln[last[d]] += l;
                    continue;
                }
                if (ne == cap) {
                    cap *= 2;
                    ca = mesh_xrealloc(ca, (size_t)cap, sizeof(idx_t));
                    cln = mesh_xrealloc(cln, (size_t)cap, sizeof(double));
                }
                last[d] = (int32_t)ne;
                ca[ne] = d;
                cln[ne++] = l;
            }
        }
    }
    cx[nc] = ne;
    for (int32_t i = 0; i < g->ntri; i++)
        node[i] = cl[node[i]];
    mesh_xfree(q);
    mesh_xfree(start);
    mesh_xfree(last);
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
 * graph vertex (they must share a part, merge_corners, so METIS sees their weight together and
 * balances around it); with coarsen and at least CLUSTER_MIN of those, its clusters
 * (graph_clusters, which never makes the graph of the triangles).  Made once for all the seeds
 * partition tries on it. */
static void graph_build(const mesh *m, const int32_t *id, int32_t n, const double *tw, int penalize,
                        int coarsen, pgraph *g) {
    memset(g, 0, sizeof *g);
    g->node = mesh_xmalloc((size_t)n + 1, sizeof(int32_t));
    g->ntri = n;
    g->nn = corner_nodes(m, id, n, g->node);
    if (coarsen && g->nn >= CLUSTER_MIN) {
        /* METIS on clusters, and no contiguous parts asked for (g->connected 0): measured on
         * North America at 16 subdomains, they made 64% more interface splits and a largest
         * part 3% larger */
        graph_clusters(m, id, tw, penalize, g);
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
static int partition(const mesh *m, const int32_t *id, int32_t n, const pgraph *g, const double *tw,
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

/* ---- wide sectors (step 5) ------------------------------------------------------------ */

typedef struct corner_rec {
    int32_t t;  /* triangle */
    int j;      /* position of the vertex in t */
    double deg; /* t's angle there */
} corner_rec;

typedef struct smooth {
    const mesh *m;
    int32_t *part;
    double *pw;    /* K: work per part */
    double pw_max; /* the heaviest part's work before step 5 */
    int32_t *cnt;  /* K: triangles per part */
    const double *tw;
    corner_rec *c, *c2; /* corners of a star; of another star (bad_at) */
    int32_t ncap, ncap2;
    int32_t *vs, vcap; /* bad_around's vertices */
    /* nv: 1 where a vertex may end an interface edge (set, at the first pass over vertices, for
     * those that do, and for every vertex of a moved triangle, so a superset of those that do
     * at every pass's start: a vertex becomes an end only when a triangle around it moves): a
     * vertex with 0 bounds no sector a pass looks at, so its star (an arctangent a corner) is
     * not walked; one with 1 that ends no interface edge moves nothing */
    uint8_t *near;
    int near_set;
} smooth;

static int touches_corner(const mesh *m, int32_t t) {
    if (!m->has_corners || !m->corner) return 0;
    for (int j = 0; j < 3; j++) {
        int32_t v = m->tv[3 * t + j];
        if (v < m->ninput && m->corner[v]) return 1;
    }
    return 0;
}

static double corner_deg(const mesh *m, int32_t t, int j) {
    const double *p = mesh_vertex_xy(m, m->tv[3 * t + j]),
                 *a = mesh_vertex_xy(m, m->tv[3 * t + (j + 1) % 3]),
                 *b = mesh_vertex_xy(m, m->tv[3 * t + (j + 2) % 3]);
    double ux = a[0] - p[0], uy = a[1] - p[1], vx = b[0] - p[0], vy = b[1] - p[1];
    return atan2(fabs(ux * vy - uy * vx), ux * vx + uy * vy) * DEG_PER_RAD;
}

/* Edge e separates two sectors: a constraint, the domain boundary, or two parts. */
static int edge_cut(const mesh *m, const int32_t *part, int32_t e) {
    int32_t n = m->tn[e];
    return n < 0 || mesh_edge_constrained(m, e) || part[n / 3] != part[e / 3];
}

/* An interface edge: unconstrained, between two parts. */
static int edge_iface(const mesh *m, const int32_t *part, int32_t e) {
    int32_t n = m->tn[e];
    return n >= 0 && !mesh_edge_constrained(m, e) && part[n / 3] != part[e / 3];
}

/* Moves triangles ts[0..n) (all of part p) to part q unless that empties p or moves a triangle
 * at a sharp input corner.  Returns 1 if moved. */
static int move_tris(smooth *S, const int32_t *ts, int32_t n, int32_t p, int32_t q) {
    if (S->cnt[p] <= n) return 0;
    for (int32_t i = 0; i < n; i++)
        if (touches_corner(S->m, ts[i])) return 0;
    for (int32_t i = 0; i < n; i++) {
        S->part[ts[i]] = q;
        S->pw[p] -= S->tw[ts[i]];
        S->pw[q] += S->tw[ts[i]];
        for (int j = 0; S->near && j < 3; j++)
            S->near[S->m->tv[3 * ts[i] + j]] = 1;
    }
    S->cnt[p] -= n;
    S->cnt[q] += n;
    return 1;
}

/* Would triangle t, moved to part q, leave no encroached interface edge among its own?  (So
 * every move of the exact preview's pass removes one and adds none: no oscillation.) */
static int clean_move(const smooth *S, int32_t t, int32_t q) {
    const mesh *m = S->m;
    for (int j = 0; j < 3; j++) {
        int32_t e = 3 * t + j, n = m->tn[e];
        if (n < 0 || mesh_edge_constrained(m, e) || S->part[n / 3] == q) continue;
        if (edge_encroached(m, e)) return 0;
    }
    return 1;
}

/* The corners around v in counter-clockwise order into *buf (capacity *cap, grown), starting
 * just after a cut edge.  Returns the number of corners, 0 if v has no sector to consider. */
static int32_t star(const smooth *S, int32_t v, corner_rec **buf, int32_t *cap) {
    const mesh *m = S->m;
    int32_t t0 = m->vtri[v];
    if (t0 < 0 || !mesh_tri_alive(m, t0)) return 0;
    int j0 = 0;
    while (j0 < 3 && m->tv[3 * t0 + j0] != v)
        j0++;
    if (j0 == 3) return 0;
    /* clockwise (across the outgoing edge) until that edge is a cut */
    int32_t t = t0;
    int j = j0;
    for (;;) {
        int32_t e = 3 * t + j;
        if (edge_cut(m, S->part, e)) break;
        int32_t n = m->tn[e];
        t = n / 3;
        j = (n % 3 + 1) % 3;
        if (t == t0) return 0; /* a full turn inside one part */
    }
    /* counter-clockwise (across the incoming edge) from there */
    int32_t nc = 0, ts = t;
    for (;;) {
        if (nc >= *cap) {
            *cap = *cap ? 2 * *cap : 64;
            *buf = mesh_xrealloc(*buf, (size_t)*cap, sizeof **buf);
        }
        (*buf)[nc++] = (corner_rec){t, j, corner_deg(m, t, j)};
        int32_t n = m->tn[3 * t + (j + 2) % 3];
        if (n < 0) break;
        t = n / 3;
        j = n % 3;
        if (t == ts) break;
        if (nc > m->nt) MESH_BUG("star of vertex %d does not close", v);
    }
    return nc;
}

/* The sector of star c[0..nc) that starts at corner a ends before corner *b; its angle. */
static double sector(const smooth *S, const corner_rec *c, int32_t nc, int32_t a, int32_t *b) {
    double deg = 0;
    int32_t k = a;
    do {
        deg += c[k].deg;
        k++;
    } while (k < nc && !edge_cut(S->m, S->part, 3 * c[k - 1].t + (c[k - 1].j + 2) % 3));
    *b = k;
    return deg;
}

/* Narrow sectors at v that an interface bounds. */
static int32_t bad_at(smooth *S, int32_t v) {
    int32_t nc = star(S, v, &S->c2, &S->ncap2), bad = 0;
    for (int32_t a = 0, b = 0; a < nc; a = b) {
        double deg = sector(S, S->c2, nc, a, &b);
        int32_t left = 3 * S->c2[a].t + S->c2[a].j,
                right = 3 * S->c2[b - 1].t + (S->c2[b - 1].j + 2) % 3;
        bad +=
            deg < WIDE_DEG && (edge_iface(S->m, S->part, left) || edge_iface(S->m, S->part, right));
    }
    return bad;
}

static int cmp_i32(const void *a, const void *b) {
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

/* Narrow sectors at the vertices of triangles ts[0..n) (a vertex counted once per triangle).
 * Each distinct vertex's star is walked once and weighted by its count: a sector's apex is in
 * all n triangles, and at a fan of thousands of triangles (a tiny input feature) walking its
 * star n times made the decomposition quadratic in the fan (minutes at 8 subdomains). */
static int32_t bad_around(smooth *S, const int32_t *ts, int32_t n) {
    if (3 * n > S->vcap) {
        S->vcap = 3 * n;
        S->vs = mesh_xrealloc(S->vs, (size_t)S->vcap, sizeof *S->vs);
    }
    for (int32_t i = 0; i < n; i++)
        for (int j = 0; j < 3; j++)
            S->vs[3 * i + j] = S->m->tv[3 * ts[i] + j];
    qsort(S->vs, (size_t)(3 * n), sizeof *S->vs, cmp_i32);
    int32_t bad = 0;
    for (int32_t i = 0, k; i < 3 * n; i = k) {
        for (k = i + 1; k < 3 * n && S->vs[k] == S->vs[i]; k++)
            ;
        bad += (k - i) * bad_at(S, S->vs[i]);
    }
    return bad;
}

/* One pass of step 5: over every vertex (the coarse mesh), or over every interface edge (the
 * exact preview: its interfaces are never split unless encroached, so no split can start a
 * cascade at a narrow sector, and moving whole sectors would cost balance); returns the number
 * of moves. */
static int32_t widen_pass(smooth *S, int exact) {
    const mesh *m = S->m;
    int32_t moves = 0, *ts = NULL, tcap = 0;
    if (!exact && !S->near_set) { /* once: moves mark their vertices (move_tris) */
        for (int32_t t = 0; t < m->nt; t++)
            for (int j = 0; mesh_tri_alive(m, t) && j < 3; j++)
                if (edge_iface(m, S->part, 3 * t + j))
                    S->near[mesh_org(m, 3 * t + j)] = S->near[mesh_dest(m, 3 * t + j)] = 1;
        S->near_set = 1;
    }
    for (int32_t v = 0; v < m->nv && !exact; v++) {
        if (!S->near[v]) continue; /* no interface edge ends here */
        int32_t nc = star(S, v, &S->c, &S->ncap);
        for (int32_t a = 0, b = 0; a < nc; a = b) {
            /* the sector starting at corner a: corners a..b-1 (same part, no cut inside) */
            double deg = sector(S, S->c, nc, a, &b);
            int32_t left = 3 * S->c[a].t + S->c[a].j;                    /* outgoing edge */
            int32_t right = 3 * S->c[b - 1].t + (S->c[b - 1].j + 2) % 3; /* incoming edge */
            int li = edge_iface(m, S->part, left), ri = edge_iface(m, S->part, right);
            if (deg >= WIDE_DEG || !(li || ri)) continue;
            int32_t p = S->part[S->c[a].t], n = b - a;
            int32_t ql = li ? S->part[m->tn[left] / 3] : -1,
                    qr = ri ? S->part[m->tn[right] / 3] : -1;
            if (ql >= 0 && qr >= 0 && S->pw[qr] < S->pw[ql]) { /* the lighter part first */
                int32_t x = ql;
                ql = qr;
                qr = x;
            }
            if (n > tcap) {
                tcap = n;
                ts = mesh_xrealloc(ts, (size_t)tcap, sizeof *ts);
            }
            for (int32_t k = a; k < b; k++)
                ts[k - a] = S->c[k].t;
            /* a move must lower the number of narrow sectors around it: no oscillation */
            int32_t before = bad_around(S, ts, n), moved = 0;
            for (int side = 0; side < 2 && !moved; side++) {
                int32_t q = side == 0 ? ql : qr;
                if (q < 0 || (side == 1 && q == ql) || !move_tris(S, ts, n, p, q)) continue;
                if (bad_around(S, ts, n) < before)
                    moved = 1;
                else
                    move_tris(S, ts, n, q, p);
            }
            if (moved) {
                moves++;
                break; /* v's star changed: look again next pass */
            }
        }
    }
    if (exact) /* a triangle whose apex encroaches an interface edge joins the other side */
        for (int32_t t = 0; t < m->nt; t++) {
            if (!mesh_tri_alive(m, t)) continue;
            for (int j = 0; j < 3; j++) {
                int32_t e = 3 * t + j;
                if (!edge_iface(m, S->part, e)) continue;
                const double *pa = mesh_vertex_xy(m, mesh_org(m, e)),
                             *pb = mesh_vertex_xy(m, mesh_dest(m, e));
                if (!geom_encroaches(pa, pb, mesh_vertex_xy(m, mesh_apex(m, e)))) continue;
                int32_t nb = m->tn[e] / 3, pt = S->part[t], pn = S->part[nb];
                /* t joins the other side, or the triangle across joins t's part: the lighter
                 * destination first, and none past the heaviest part */
                int first = S->pw[pn] <= S->pw[pt] ? 0 : 1, done = 0;
                for (int k = 0; k < 2 && !done; k++) {
                    int32_t x = (k == first) ? t : nb, from = x == t ? pt : pn,
                            to = x == t ? pn : pt;
                    if (S->pw[to] + S->tw[x] > S->pw_max) continue;
                    done = clean_move(S, x, to) && move_tris(S, &x, 1, from, to);
                }
                if (done) {
                    moves++;
                    break;
                }
            }
        }
    mesh_xfree(ts);
    return moves;
}

static void widen(const mesh *m, int32_t *part, const double *tw, int32_t K, int exact) {
    smooth S;
    memset(&S, 0, sizeof S);
    S.m = m;
    S.part = part;
    S.tw = tw;
    S.pw = mesh_xcalloc((size_t)K, sizeof(double));
    S.cnt = mesh_xcalloc((size_t)K, sizeof(int32_t));
    S.near = mesh_xcalloc((size_t)m->nv + 1, 1);
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t)) {
            S.pw[part[t]] += tw[t];
            S.cnt[part[t]]++;
        }
    for (int32_t k = 0; k < K; k++)
        S.pw_max = fmax(S.pw_max, S.pw[k]);
    for (int pass = 0; pass < WIDEN_PASSES && widen_pass(&S, exact) > 0; pass++)
        ;
    /* an interface still encroached will be split: then, as on the coarse route, no narrow
     * sector may let that split start a cascade */
    int left = 0;
    for (int32_t t = 0; exact && !left && t < m->nt; t++)
        for (int j = 0; mesh_tri_alive(m, t) && j < 3 && !left; j++)
            left = edge_iface(m, part, 3 * t + j) && edge_encroached(m, 3 * t + j);
    for (int pass = 0; left && pass < WIDEN_PASSES && widen_pass(&S, 0) > 0; pass++)
        ;
    mesh_xfree(S.c);
    mesh_xfree(S.c2);
    mesh_xfree(S.vs);
    mesh_xfree(S.pw);
    mesh_xfree(S.cnt);
    mesh_xfree(S.near);
}

/* Every part left empty by METIS (it may, at a few triangles per part) or by merge_corners
 * takes one triangle of the part with the most: preferably one whose edges no apex encroaches
 * (on the exact preview they all become interfaces) and that touches no sharp input corner. */
static void fill_empty(const mesh *m, int32_t *part, int32_t K) {
    int32_t *cnt = mesh_xcalloc((size_t)K, sizeof(int32_t));
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t)) cnt[part[t]]++;
    uint8_t *tried = mesh_xmalloc((size_t)K, 1);
    for (int32_t q = 0; q < K; q++) {
        if (cnt[q] > 0) continue;
        memset(tried, 0, (size_t)K);
        int32_t p = -1, pick = -1;
        for (;;) { /* the parts by decreasing size, until one gives a triangle */
            p = -1;
            for (int32_t k = 0; k < K; k++)
                if (!tried[k] && cnt[k] >= 2 && (p < 0 || cnt[k] > cnt[p])) p = k;
            if (p < 0) break; /* fewer triangles than parts: decomp_build reports it */
            tried[p] = 1;
            for (int pass = 0; pass < 2 && pick < 0; pass++)
                for (int32_t t = 0; t < m->nt && pick < 0; t++) {
                    if (!mesh_tri_alive(m, t) || part[t] != p || touches_corner(m, t)) continue;
                    int ok = 1;
                    for (int j = 0; j < 3 && ok && pass == 0; j++)
                        ok = !edge_encroached(m, 3 * t + j);
                    if (ok) pick = t;
                }
            if (pick >= 0) break;
        }
        if (pick < 0) continue;
        part[pick] = q;
        cnt[p]--;
        cnt[q]++;
    }
    mesh_xfree(tried);
    mesh_xfree(cnt);
}

/* Step 0: refines m (the input's CDT, area A) at the real bounds under a Steiner limit (and
 * with an area bound up to min_per_sub triangles per subdomain).
 * Returns 1 if m is now the exact preview, 0 if it was not tried (m untouched), -1 if it was
 * tried and the final mesh is too large (m is spoilt: rebuild it). */
static int exact_preview(mesh *m, const pslg *in, const pcdm_decomp_opts *o, int32_t *Kp, double A,
                         int32_t min_per_sub) {
    int32_t K = *Kp;
    int32_t eps = o->exact_per_sub == 0 ? EXACT_PER_SUB_DEFAULT : o->exact_per_sub;
    if (K == 1 || eps < 0 || o->max_steiner >= 0) return 0;
    int64_t tmax = (int64_t)K * eps;
    if (o->max_area > 0 && A / o->max_area > (double)tmax) return 0;
    /* the bound exactly as ./mesh and ./pcdm refine with */
    double q = bounds_refine_angle(o->min_angle);
    int64_t limit = tmax / 2 + 1; /* Steiner vertices: about half the triangles */
    if (o->region_area) mesh_set_regions(m, in, 1, m->nseg); /* the final mesh's bounds */
    if (refine(m, q, o->max_area, limit) != MESH_REFINE_DONE || m->nlive > tmax) return -1;
    /* enough triangles to balance the ranks, and min_per_sub per subdomain; counted per
     * subdomain (K >= P), so the subdomains depend on K alone, not on the rank count (the
     * deterministic mode's promise: the same mesh for any rank count, given K) */
    /* a default count (nsub_fit) halves, not below the ranks, to what the final mesh can
     * share out without refining it further: a small mesh stays as ./mesh makes it */
    if (o->nsub_fit) {
        while (K > o->nranks && m->nlive < (int64_t)K * FIT_MIN_PER_SUB)
            K = K / 2 < o->nranks ? o->nranks : K / 2;
        *Kp = K;
        if (K == 1) return -1; /* one subdomain: the input's CDT, as when one is asked for */
    }
    int64_t want = (int64_t)K * EXACT_MIN_PER_RANK;
    if (want < min_per_sub * (int64_t)K) want = min_per_sub * (int64_t)K;
    if (m->nlive < want) { /* the final mesh has too few triangles to share out */
        if (refine(m, q, A / (double)want, limit) != MESH_REFINE_DONE) return -1;
    }
    return 1;
}

/* One decomposition: mode 0 the exact preview with 2 triangles per subdomain at least, mode 1
 * with EXACT_SAFE_PER_SUB (both else the fast route), mode 2 the fast route only, mode 3 the
 * lfs-graded coarse route only. */
static int attempt(const pslg *in, const pcdm_decomp_opts *o, int mode, pcdm_decomp *out,
                   double *angle, char *err, size_t errlen) {
    *angle = NAN;
    memset(out, 0, sizeof *out);
    int32_t P = o->nranks, K = o->nsub > 0 ? o->nsub : o->nranks;
    if (P < 1) return mesh_fail(err, errlen, "%d ranks", (int)P);
    if (K < P)
        return mesh_fail(err, errlen, "%d subdomains: fewer than the %d ranks", (int)K, (int)P);
    double R = o->imbalance > 0 ? o->imbalance : 1;
    int32_t per = o->per_sub > 0 ? o->per_sub : PER_SUB_DEFAULT;
    mesh m, *keep = NULL;
    mesh_init(&m);
    int built;
    if (o->dt && o->dt_dup && *o->dt_dup && o->dt->nv == in->nverts) { /* made ahead: taken */
        m = *o->dt;
        mesh_init(o->dt);
        int32_t *dup = *o->dt_dup;
        *o->dt_dup = NULL;
        built = mesh_build_cdt_from_points(&m, dup, in, NULL, err, errlen);
    } else {
        built = mesh_build_cdt(&m, in, NULL, err, errlen);
    }
    if (built != 0) {
        mesh_free(&m);
        return -1;
    }
    double floor2 = mesh_rules_length_floor2(m.xy, m.nv, m.tv, m.nt); /* as ./mesh's */
    if (o->keep_cdt) { /* the caller's copy, before anything below refines m */
        keep = mesh_xmalloc(1, sizeof *keep);
        mesh_copy(keep, &m);
    }
    int exact =
        mode >= 2 ? 0
                  : exact_preview(&m, in, o, &K, mesh_area(&m), mode == 0 ? 2 : EXACT_SAFE_PER_SUB);
    if (exact < 0) { /* the final mesh is larger: start again from the CDT */
        mesh_free(&m);
        mesh_init(&m);
        if (mesh_build_cdt(&m, in, NULL, err, errlen) != 0) {
            mesh_free(&m);
            return -1;
        }
        exact = 0;
    }
    /* the coarse route: region labels only (the coarse mesh stays coarser than their bounds),
     * for the work weights below */
    if (o->region_area && !exact) mesh_set_regions(&m, in, 0, m.nseg);
    double qc = o->min_angle + 2;
    qc = qc < 30 ? 30 : qc > 33 ? 33 : qc;
    int fast = mode != 3 && !o->coarse_route && in->nverts >= FAST_MIN_VERTS;
    if (K > 1 && !exact && fast) {
        /* the fast route: the input's CDT, with an area bound alone for about per_sub
         * triangles per subdomain (circumcenters of the large triangles: a few per subdomain) */
        int64_t limit = 4 * (int64_t)K * per + 1000;
        double A = mesh_area(&m), ac = A / ((double)K * per);
        if (o->max_area > 0 && ac < 4 * o->max_area) ac = 4 * o->max_area;
        if (ac < A) interior_points(&m, ac, limit);
    } else if (K > 1 && !exact) {
        int64_t limit = 40 * (int64_t)K * per + 20 * (int64_t)m.nv + 1000;
        refine(&m, qc, 0, limit);
        double A = mesh_area(&m);
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
        double b = o->max_area;
        if (o->region_area && m.treg && m.treg[t] >= 0)
            b = mesh_rules_area_bound(b, in->regions[4 * m.treg[t] + 3]);
        if (fast) /* lfs-graded triangles about each coarse one, and the area bound's */
            tw[t] = (b > 0 ? 1.45 * ar / b : 0) + 2.5;
        else
            tw[t] = b > 0 && ar > b ? ar / b : 1;
    }
    /* a default count shrinks to what the coarse mesh can share out; halving from the same
     * default gives the same K for every rank count up to it */
    if (o->nsub_fit)
        while (K > P && n < 2 * K)
            K = K / 2 < P ? P : K / 2;
    double *target = mesh_xmalloc((size_t)K, sizeof(double));
    int32_t *planned = mesh_xmalloc((size_t)K, sizeof(int32_t));
    plan(K, P, R, target, planned);
    int rc = 0;
    if (K > 1 && n < 2 * K)
        rc = mesh_fail(err, errlen, "%d subdomains: the domain's coarse mesh has only %d triangles",
                       (int)K, (int)n);
    /* ./pbw: the partition of least predicted cost among the seeds (decomp_seeds.c) */
    int choose = K > 1 && K == P && R == 1 && !exact && o->boundary_cost > 0;
    double cost = 0;
    /* the fast route: when its interfaces meet a segment below FAST_MIN_DEG, the partition alone
     * again with the next METIS seeds (measured on Great Britain at 0.97M triangles: seed 1 20.8
     * degrees, seeds 2-8 48-64), the widest kept, before the caller turns to the coarse route */
    int seeds = fast && !exact && K > 1 && !choose ? FAST_SEEDS : 1;
    pgraph g; /* made once for every seed */
    memset(&g, 0, sizeof g);
    if (K > 1 && rc == 0) graph_build(&m, id, n, tw, exact || fast, fast && !exact, &g);
    for (int32_t seed = 1, got = 0; seed <= seeds && rc == 0; seed++) {
        pcdm_decomp cand;
        if (K > 1)
            rc = partition(&m, id, n, &g, tw, target, K, choose ? o : NULL, seed, &cost, part, err,
                           errlen);
        if (rc == 0 && choose &&
            (o->pick ? o->pick(o->pick_ctx, cost, m.nt, part) != 0 : !isfinite(cost)))
            rc = mesh_fail(err, errlen,
                           "METIS could not partition %d coarse triangles into %d parts", (int)n,
                           (int)K);
        if (rc == 0) {
            merge_corners(&m, part);
            if (K > 1) fill_empty(&m, part, K);
            if (K > 1) widen(&m, part, tw, K, exact);
            /* the fast route keeps its triangles: the subdomains' first meshes (pcdm_build_sub) */
            int keep_all = exact ? 1 : fast && K > 1 ? 2 : 0;
            rc = decomp_build(in, &m, NULL, NULL, NULL, part, tw, K, keep_all, &cand, err, errlen);
        }
        if (rc != 0) { /* a later seed's failure: the best so far stands */
            if (got) rc = 0;
            break;
        }
        double a = cand.iface_min_deg;
        if (!got || a > *angle) {
            if (got) pcdm_decomp_free(out);
            *out = cand;
            *angle = a;
            got = 1;
        } else {
            pcdm_decomp_free(&cand);
        }
        if (!(*angle < FAST_MIN_DEG)) break;
    }
    graph_free(&g);
    if (rc == 0) {
        out->floor2 = floor2;
        out->ncoarse = n;
        out->exact = exact;
        memcpy(out->sub_target, target, (size_t)K * sizeof(double));
        rc = decomp_map_owners(out, P, R, R != 1 ? planned : NULL, err, errlen);
        if (rc != 0) pcdm_decomp_free(out);
    }
    if (rc == 0) {
        out->cdt = keep;
    } else if (keep) {
        mesh_free(keep);
        mesh_xfree(keep);
    }
    mesh_xfree(id);
    mesh_xfree(part);
    mesh_xfree(tw);
    mesh_xfree(target);
    mesh_xfree(planned);
    mesh_free(&m);
    return rc;
}

/* Does PCDM meet the bounds on d?  The mesh PCDM makes depends only on the input, the bounds
 * and the subdomains, not on the ranks, so one sequential refinement of d's augmented PSLG (as
 * ./pcdm at one rank) tells.  Used on the exact preview only, where it is as small as the
 * preview: its interfaces may make narrow sectors that a split could cascade through. */
static int trial_ok(const pcdm_decomp *d, const pcdm_decomp_opts *o) {
    /* interfaces at a tiny angle to a segment split each other practically forever (a sliver
     * of 1e-10 radians along its length): not ok, and PCDM would refuse it anyway */
    if (d->iface_min_deg < 57.29577951308232 / MESH_RULES_IFACE_MAX_PIECES) return 0;
    mesh m;
    mesh_init(&m);
    char e[256];
    int ok = mesh_build_cdt(&m, &d->g, d->seg_iface, e, sizeof e) == 0;
    if (ok) {
        mesh_quality q;
        memset(&q, 0, sizeof q);
        q.min_angle = bounds_refine_angle(o->min_angle);
        q.max_area = pslg_input_area(m.scale_exp, o->max_area);
        /* the preview's final mesh has at most K * exact_per_sub triangles (exact_preview):
         * a trial that needs 8 times as many cascades along an interface (a sliver of 1e-10
         * radians cut along its length split for minutes), so it is not ok */
        int32_t K = d->nsub;
        int32_t eps = o->exact_per_sub == 0 ? EXACT_PER_SUB_DEFAULT : o->exact_per_sub;
        q.max_steiner = 4 * (int64_t)K * (eps > 0 ? eps : EXACT_PER_SUB_DEFAULT);
        q.offcenter = 1;
        if (o->region_area) mesh_set_regions(&m, &d->g, 1, d->nboundary);
        mesh_set_quality(&m, &q);
        ok = mesh_refine(&m) == MESH_REFINE_DONE && mesh_count_unmet(&m, NULL) == 0;
    }
    mesh_free(&m);
    return ok;
}

int pcdm_decomp_auto(const pslg *in, const pcdm_decomp_opts *opts, pcdm_decomp *out, char *err,
                     size_t errlen) {
    pcdm_decomp_opts so = *opts; /* the area bound in the working units of in's coordinates */
    so.max_area = pslg_scaled_area(in->scale_exp, opts->max_area);
    const pcdm_decomp_opts *o = &so;
    double ang, slow_ang;
    for (int mode = 0; mode < 3; mode++) {
        int rc = attempt(in, o, mode, out, &ang, err, errlen);
        if (rc == 0 && !out->exact && isnan(ang)) ang = out->iface_min_deg;
        if (rc == 0 && !out->exact && ang < FAST_MIN_DEG) {
            /* the fast route's interfaces meet a segment at a narrow angle: the coarse route's
             * (lfs-graded) mesh may give wider ones; the wider of the two is kept */
            pcdm_decomp slow;
            char e2[256];
            if (attempt(in, o, 3, &slow, &slow_ang, e2, sizeof e2) == 0 &&
                slow.iface_min_deg > ang) {
                pcdm_decomp_free(out);
                *out = slow;
            } else {
                pcdm_decomp_free(&slow);
            }
        } else if (rc != 0) { /* the fast route (or the preview) failed: the coarse route */
            return attempt(in, o, 3, out, &ang, err, errlen);
        }
        if (rc != 0 || !out->exact || trial_ok(out, o)) return rc;
        /* would mode 1 differ? */
        int more = out->ncoarse < (int64_t)out->nsub * EXACT_SAFE_PER_SUB;
        pcdm_decomp_free(out);
        if (mode == 0 && !more) mode = 1;
    }
    return attempt(in, o, 2, out, &ang, err, errlen); /* not reached: mode 2 is never exact */
}
