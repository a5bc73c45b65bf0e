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
 * Where: steps (3) in decomp_graph.c, (4) and (5) in decomp_widen.c, (6) in decomp.c, the
 * passes over every coarse triangle (weights, corners, decomp_build's) on the threads the
 * caller gives (decomp_pass.c: the same bits for any number).
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
#define FAST_MIN_DEG 30.0 /* the fast route's interfaces narrower than this: try the coarse one */
#define FAST_SEEDS 3      /* ... after this many METIS seeds on the fast route */
#define FAST_MIN_VERTS                                                                             \
    8192 /* inputs with fewer vertices take the coarse route (it costs little)                     \
          */

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
        if (nn > 1) qsort(next, (size_t)nn, sizeof(int32_t), mesh_cmp_i32);
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
/* The coarse triangles' work weights (tw) and compact numbers (id), chunk by chunk (decomp_for_
 * chunks): a first pass weighs the live triangles and counts them a chunk (live[c]), a second
 * numbers them from where their chunk's count starts (live[c], made a running sum between). */
typedef struct tri_weights {
    const mesh *m;
    const pslg *in;
    const pcdm_decomp_opts *o;
    int fast, number;
    int32_t *id, *part, *live;
    double *tw;
} tri_weights;

static void weigh_chunk(void *arg, int32_t c, int32_t t0, int32_t t1) {
    tri_weights *W = arg;
    const mesh *m = W->m;
    const pcdm_decomp_opts *o = W->o;
    if (W->number) {
        for (int32_t t = t0, n = W->live[c]; t < t1; t++)
            W->id[t] = mesh_tri_alive(m, t) ? n++ : -1;
        return;
    }
    for (int32_t t = t0; t < t1; t++) {
        W->part[t] = 0;
        if (!mesh_tri_alive(m, t)) continue;
        W->live[c]++;
        double ar = geom_area(mesh_vertex_xy(m, m->tv[3 * t]), mesh_vertex_xy(m, m->tv[3 * t + 1]),
                              mesh_vertex_xy(m, m->tv[3 * t + 2]));
        double b = o->max_area;
        if (o->region_area && m->treg && m->treg[t] >= 0)
            b = mesh_rules_area_bound(b, W->in->regions[4 * m->treg[t] + 3]);
        if (W->fast) /* lfs-graded triangles about each coarse one, and the area bound's */
            W->tw[t] = (b > 0 ? 1.45 * ar / b : 0) + 2.5;
        else
            W->tw[t] = b > 0 && ar > b ? ar / b : 1;
    }
}

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
    decomp_threads th = {o->threads, o->cpus};
    tri_weights W = {.m = &m, .in = in, .o = o, .fast = fast};
    W.id = mesh_xmalloc((size_t)m.nt + 1, sizeof(int32_t));
    W.part = mesh_xmalloc((size_t)m.nt + 1, sizeof(int32_t));
    W.tw = mesh_xcalloc((size_t)m.nt + 1, sizeof(double));
    W.live = mesh_xcalloc((size_t)decomp_nchunks(m.nt) + 1, sizeof(int32_t));
    decomp_for_chunks(&th, m.nt, weigh_chunk, &W); /* the weights, and the live count a chunk */
    int32_t n = 0, *id = W.id, *part = W.part;
    double *tw = W.tw;
    for (int32_t c = 0, nc = decomp_nchunks(m.nt); c < nc; c++) { /* where its numbers start */
        int32_t k = W.live[c];
        W.live[c] = n;
        n += k;
    }
    W.number = 1;
    decomp_for_chunks(&th, m.nt, weigh_chunk, &W); /* the compact numbers, in slot order */
    mesh_xfree(W.live);
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
    if (K > 1 && rc == 0) decomp_graph_build(&th, &m, id, n, tw, exact || fast, fast && !exact, &g);
    for (int32_t seed = 1, got = 0; seed <= seeds && rc == 0; seed++) {
        pcdm_decomp cand;
        if (K > 1)
            rc = decomp_partition(&m, id, n, &g, tw, target, K, choose ? o : NULL, seed, &cost,
                                  part, err, errlen);
        if (rc == 0 && choose &&
            (o->pick ? o->pick(o->pick_ctx, cost, m.nt, part) != 0 : !isfinite(cost)))
            rc = mesh_fail(err, errlen,
                           "METIS could not partition %d coarse triangles into %d parts", (int)n,
                           (int)K);
        if (rc == 0) {
            decomp_merge_corners(&th, &m, part);
            if (K > 1) decomp_fill_empty(&m, part, K);
            if (K > 1) decomp_widen(&m, part, tw, K, exact);
            /* the fast route keeps its triangles: the subdomains' first meshes (pcdm_build_sub) */
            int keep_all = exact ? 1 : fast && K > 1 ? 2 : 0;
            rc = decomp_build(&th, in, &m, NULL, NULL, NULL, part, tw, K, keep_all, &cand, err,
                              errlen);
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
    decomp_graph_free(&g);
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
