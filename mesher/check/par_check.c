/* par_check: the cheap interface check both parallel meshers always run before any output.
 *
 * What: "never a silent broken mesh".  PCDM (TR-97-17 section 3) is correct only if the two
 * ranks on either side of an interface split it identically (same subsegments, same vertex
 * bits); PBW only if the triangles of neighbouring ranks meet edge to edge.  A T-junction or a
 * missing split on one side is exactly what the full validator (--check) would find, but that
 * runs only on request (par_check_parts, mesher/par/pout.h).
 *
 * Algorithm: each rank lists the open edges of its piece (edges of exactly one local triangle;
 * found through vertex-to-triangle rows, ptopo.h), with endpoints in lexicographic order
 * so both sides name an edge identically.  A non-interface constraint edge (a domain-boundary
 * subsegment: the domain on one side, so one part claims it) stays at home -- on a coastline
 * most open edges are such; two parts claiming one would overlap, which the area check after
 * this one sees.  Every other open edge must be matched: it is sent to the rank its coordinate
 * bits hash to (a distributed hash table: MPI_Alltoall of the counts, MPI_Alltoallv of the edges,
 * O(interface) data).  There, equal edges are grouped: a group of two from two different ranks
 * is a matched interface edge; anything else is a disagreement.
 *
 * The interface local-Delaunay test (par_check_interface_delaunay, for the distributed --check)
 * goes the same way: each open edge that is not an input constraint travels with the apex of
 * its one local triangle; at the rendezvous the two records of an interface edge (two ranks)
 * meet, and the edge must be locally Delaunay exactly as the sequential validator asks
 * (geom_incircle of one apex against the other side's triangle, strictly inside = bad), so a
 * distributed check is as strong as ./meshcheck on the merged mesh.
 *
 * Invariants: exact comparison of coordinate bits (-0.0 folded onto +0.0), no tolerance; every
 * rank takes part in every collective whatever its piece holds.
 */
#include "check/par_check.h"

#include "base/base.h"
#include "check/pexchange.h"
#include "check/ptopo.h"
#include "geom/geom.h"
#include "rt.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t coord_bits(double x) {
    if (x == 0) x = 0; /* -0.0 and +0.0 are one point */
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* One open edge of a rank's piece, endpoints in lexicographic order (exact bits). */
typedef struct open_edge {
    double x[4];
    int32_t rank;
    int32_t pad;
} open_edge;
_Static_assert(sizeof(open_edge) == 40, "open_edge must be 40 bytes, no padding");

/* A listed subsegment as a sort key: lo << 33 | hi << 2 | kind (vertex numbers below 2^31;
 * kind 1 a boundary (input) subsegment, 2 an interface). */
static uint64_t seg_key(int32_t a, int32_t b, int kind) {
    uint64_t lo = (uint64_t)(a < b ? a : b), hi = (uint64_t)(a < b ? b : a);
    return lo << 33 | hi << 2 | (uint64_t)kind;
}

/* The kinds (bit 1 << kind) of every listing of edge a-b among the n sorted keys k. */
static int seg_kinds(const uint64_t *k, int32_t n, int32_t a, int32_t b) {
    uint64_t want = seg_key(a, b, 0);
    int32_t lo = mesh_lower_u64(k, n, want);
    int kinds = 0;
    for (; lo < n && k[lo] >> 2 == want >> 2; lo++)
        kinds |= 1 << (k[lo] & 3);
    return kinds;
}

/* The hash of an edge's endpoint bits: its rendezvous rank and its place in edge_order. */
static uint64_t edges_hash(const double x[4]) {
    uint64_t h = 0;
    for (int k = 0; k < 4; k++)
        h = mesh_hash64(h ^ coord_bits(x[k]));
    return h;
}

/* Endpoint bits, then rank: the order equal edges are grouped in (edge_order). */
static int cmp_edge_bits(const double *x, int32_t rx, const double *y, int32_t ry) {
    for (int k = 0; k < 4; k++) {
        uint64_t u = coord_bits(x[k]), v = coord_bits(y[k]);
        if (u != v) return u < v ? -1 : 1;
    }
    return (rx > ry) - (rx < ry);
}

static int same_edge(const double *x, const double *y) {
    return cmp_edge_bits(x, 0, y, 0) == 0;
}

/* The n edge records at e (size bytes each, the endpoints double x[4] first) at their
 * rendezvous ranks (the hash of the endpoints): the records this rank receives, *nr of them;
 * e is taken (freed, or returned as it is at one rank, its own rendezvous). */
static void *to_rendezvous(void *e, size_t size, int32_t n, int64_t *nr) {
    int P = rt_size();
    *nr = n;
    if (P == 1) return e;
    int *dest = mesh_xmalloc((size_t)n + 1, sizeof(int));
    for (int32_t i = 0; i < n; i++)
        dest[i] = (int)(edges_hash((const double *)(const void *)((char *)e + (size_t)i * size)) %
                        (uint64_t)P);
    void *rb = par_exchange(e, size, dest, n, nr);
    mesh_xfree(dest);
    mesh_xfree(e);
    return rb;
}

/* An order of the n records (size bytes each: the endpoints double x[4] first, the rank at
 * rank_off) in which bit-equal edges are adjacent, by rank: sorted by a 32-bit hash of the
 * endpoints (radix sort, O(n)), each run of equal hashes then by endpoint bits and rank
 * (insertion sort: a run is the one or two records of an edge but for hash collisions).
 * Returns n record numbers (free with free()). */
static int32_t *edge_order(const void *recs, size_t size, size_t rank_off, int64_t n) {
    const char *b = recs;
    uint64_t *key = mesh_xmalloc((size_t)n + 1, sizeof *key);
    for (int64_t i = 0; i < n; i++) {
        uint64_t h = edges_hash((const double *)(const void *)(b + (size_t)i * size));
        key[i] = (h >> 32) << 32 | (uint64_t)i;
    }
    mesh_sort_u64(key, (size_t)n);
    int32_t *ord = mesh_xmalloc((size_t)n + 1, sizeof *ord);
    for (int64_t i = 0; i < n; i++)
        ord[i] = (int32_t)(key[i] & 0xffffffffu);
    for (int64_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && key[j] >> 32 == key[i] >> 32;)
            j++;
        for (int64_t u = i + 1; u < j; u++) { /* insertion sort of the run */
            int32_t r = ord[u];
            const char *pr = b + (size_t)r * size;
            int64_t w = u;
            for (; w > i; w--) {
                const char *pq = b + (size_t)ord[w - 1] * size;
                int32_t rq, rr;
                memcpy(&rq, pq + rank_off, sizeof rq);
                memcpy(&rr, pr + rank_off, sizeof rr);
                if (cmp_edge_bits((const double *)(const void *)pq, rq,
                                  (const double *)(const void *)pr, rr) <= 0)
                    break;
                ord[w] = ord[w - 1];
            }
            ord[w] = r;
        }
    }
    free(key);
    return ord;
}

/* What add_open needs: the part, its listed subsegments sorted by vertex pair, the growing
 * list of open edges. */
typedef struct open_ctx {
    const mesh_flat *f;
    const uint64_t *k;
    int rank;
    open_edge *o;
    int32_t n, cap;
} open_ctx;

/* par_open_edges visitor: records open edge a -> b with its coordinates in lexicographic
 * order, unless it is listed as a boundary subsegment only (kind 1; kind 2, an interface, wins
 * if listed twice). */
static void add_open(void *ctx, int32_t a, int32_t b, int32_t apex) {
    open_ctx *c = ctx;
    const mesh_flat *f = c->f;
    int kinds = seg_kinds(c->k, f->nsegs, a, b); /* every listing of the pair */
    int segkind = kinds & 4 ? 2 : kinds & 2 ? 1 : 0;
    if (segkind == 1) return; /* a domain-boundary subsegment: needs no match */
    const double *p = f->xy + 2 * (size_t)a, *q = f->xy + 2 * (size_t)b;
    int sw = p[0] > q[0] || (p[0] == q[0] && p[1] > q[1]);
    MESH_GROW(c->o, c->n, c->cap);
    open_edge *e = &c->o[c->n++];
    memset(e, 0, sizeof *e);
    e->x[0] = sw ? q[0] : p[0];
    e->x[1] = sw ? q[1] : p[1];
    e->x[2] = sw ? p[0] : q[0];
    e->x[3] = sw ? p[1] : q[1];
    e->rank = c->rank;
}

/* f's listed subsegments as sorted keys: n = 1 a boundary (input) subsegment, 2 an interface. */
static uint64_t *seg_keys(const mesh_flat *f) {
    uint64_t *k = mesh_xmalloc((size_t)f->nsegs + 1, sizeof *k);
    for (int32_t s = 0; s < f->nsegs; s++)
        k[s] = seg_key(f->seg[2 * s], f->seg[2 * s + 1],
                       1 + (f->sinterface ? f->sinterface[s] != 0 : 0));
    mesh_sort_u64(k, (size_t)f->nsegs);
    return k;
}

/* The open edges of local (edges of exactly one local triangle), found through the
 * vertex-to-triangle rows (ptopo.h: one pass, no sort of all edges). */
static int32_t open_edges(const mesh_flat *f, const uint8_t *topen, int rank, open_edge **out) {
    uint64_t *k = seg_keys(f);
    par_vtris x;
    par_vtris_open(f, topen, &x);
    open_ctx oc = {f, k, rank, NULL, 0, 0};
    par_open_edges(f, &x, add_open, &oc);
    open_edge *o = oc.o;
    int32_t no = oc.n;
    par_vtris_free(&x);
    if (!o) o = mesh_xmalloc(1, sizeof(open_edge));
    mesh_xfree(k);
    *out = o;
    return no;
}

int par_check_interfaces_open(const mesh_flat *local, const uint8_t *topen, char *msg,
                              size_t msglen) {
    int rank = rt_rank();
    open_edge *e = NULL;
    int32_t n = open_edges(local, topen, rank, &e);
    int64_t nr;
    open_edge *rb = to_rendezvous(e, sizeof *e, n, &nr);
    int32_t *ord = edge_order(rb, sizeof *rb, offsetof(open_edge, rank), nr);
    int bad = 0;
    char m[400] = "";
    for (int64_t i = 0; i < nr;) {
        int64_t j = i;
        const open_edge *first = &rb[ord[i]];
        while (j < nr && same_edge(rb[ord[j]].x, first->x))
            j++;
        int ok = j - i == 2 && first->rank != rb[ord[i + 1]].rank;
        if (!ok && !bad++)
            snprintf(m, sizeof m,
                     "interface check failed: edge (%.17g, %.17g)-(%.17g, %.17g) of rank %d %s",
                     first->x[0], first->x[1], first->x[2], first->x[3], (int)first->rank,
                     j - i == 1 ? "has no matching edge on the other side of the interface"
                                : "is claimed by more than two pieces");
        i = j;
    }
    if (bad && msglen) snprintf(msg, msglen, "%s (%d edges disagree here)", m, bad);
    mesh_xfree(ord);
    mesh_xfree(rb);
    return bad ? -1 : 0;
}

/* ---- interface edges: locally Delaunay across ranks ------------------------------------ */

/* An open edge (endpoints in lexicographic order) with the apex of its local triangle. */
typedef struct apex_edge {
    double x[4];
    double c[2];
    int32_t rank;
    int32_t exempt; /* 1: an input constraint edge (need not be Delaunay) */
} apex_edge;
_Static_assert(sizeof(apex_edge) == 56, "apex_edge must be 56 bytes, no padding");

typedef struct apex_ctx {
    const mesh_flat *f;
    const par_vtris *x; /* unused by the visitor (the apex comes with the edge) */
    const uint64_t *k;
    int rank;
    apex_edge *o;
    int32_t n, cap;
} apex_ctx;

/* par_open_edges visitor: records open edge a -> b, its apex and whether it is exempt. */
static void add_apex(void *ctx, int32_t a, int32_t b, int32_t apex) {
    apex_ctx *c = ctx;
    const mesh_flat *f = c->f;
    /* an input subsegment in any listing: a constraint, exempt */
    int exempt = (seg_kinds(c->k, f->nsegs, a, b) & 2) != 0;
    const double *p = f->xy + 2 * (size_t)a, *q = f->xy + 2 * (size_t)b;
    int sw = p[0] > q[0] || (p[0] == q[0] && p[1] > q[1]);
    MESH_GROW(c->o, c->n, c->cap);
    apex_edge *e = &c->o[c->n++];
    memset(e, 0, sizeof *e);
    e->x[0] = sw ? q[0] : p[0];
    e->x[1] = sw ? q[1] : p[1];
    e->x[2] = sw ? p[0] : q[0];
    e->x[3] = sw ? p[1] : q[1];
    e->c[0] = f->xy[2 * (size_t)apex];
    e->c[1] = f->xy[2 * (size_t)apex + 1];
    e->rank = c->rank;
    e->exempt = exempt;
}

long par_check_interface_delaunay(const mesh_flat *local, const uint8_t *topen, char *msg,
                                  size_t msglen) {
    int rank = rt_rank();
    if (msglen) msg[0] = '\0';
    uint64_t *k = seg_keys(local);
    par_vtris x;
    par_vtris_open(local, topen, &x);
    apex_ctx ac = {local, &x, k, rank, NULL, 0, 0};
    par_open_edges(local, &x, add_apex, &ac);
    par_vtris_free(&x);
    mesh_xfree(k);
    int32_t n = ac.n;
    apex_edge *e = ac.o;
    /* to the rendezvous (the hash of the edge) */
    int64_t nr;
    apex_edge *rb = to_rendezvous(e, sizeof *e, n, &nr);
    int32_t *ord = edge_order(rb, sizeof *rb, offsetof(apex_edge, rank), nr);
    long bad = 0;
    for (int64_t i = 0; i + 1 < nr; i++) {
        const apex_edge *u = &rb[ord[i]], *v = &rb[ord[i + 1]];
        if (!same_edge(u->x, v->x) || u->rank == v->rank || u->exempt || v->exempt)
            continue; /* not the two sides of one interface edge (par_check_interfaces_open decides
                       * what else is wrong), or a constraint */
        const double *p = u->x, *q = u->x + 2;
        double o = geom_orient2d(p, q, u->c);
        if (o == 0) continue; /* a degenerate triangle: the validator reports it */
        int in = o > 0 ? geom_incircle(p, q, u->c, v->c) > 0 : geom_incircle(q, p, u->c, v->c) > 0;
        if (in && !bad++ && msglen)
            snprintf(msg, msglen,
                     "interface edge (%.17g, %.17g)-(%.17g, %.17g) of ranks %d, %d is not "
                     "locally Delaunay (apex (%.17g, %.17g) inside)",
                     p[0], p[1], q[0], q[1], (int)u->rank, (int)v->rank, v->c[0], v->c[1]);
    }
    mesh_xfree(ord);
    mesh_xfree(rb);
    return bad;
}
