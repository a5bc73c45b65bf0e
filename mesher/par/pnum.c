/* pnum.c: global numbering of a distributed mesh without a gather (pout.h, par_number).
 *
 * Algorithm.  (1) Input vertices keep their input numbers: the part names them (mesh_flat.vin),
 * or holds them first in input order, or they are found by their exact coordinate bits (a hash
 * of the input, which every rank holds).  (2) The part's open
 * edges (edges of one local triangle) are found in O(n) with a vertex-to-triangle index; a
 * vertex another rank also holds lies on an open edge of every holder (the parts are disjoint
 * and only touch along their boundaries; a pinch point of the domain boundary is an input
 * vertex), so the non-input vertices of open edges are the candidates for sharing.  (3) Each
 * candidate travels to a rendezvous rank (hash of its coordinates, -0.0 folded onto +0.0);
 * there the holders of one point are grouped and the lowest rank is named owner.  (4) Owned
 * vertices are numbered by an MPI_Exscan of the owned counts; owners send the numbers of their
 * shared vertices to the rendezvous, which forwards them to the other holders.  (5) Listed
 * subsegments that are open edges go to a rendezvous the same way: of two ranks listing the
 * same one, only the lower writes it.  Triangles: an MPI_Exscan of the counts.
 *
 * Invariants: every written vertex has exactly one owner and one number; rank r's written
 * vertices (input ones on rank 0 first) carry consecutive numbers after rank r-1's; data moved
 * is O(part boundary), never the mesh.  All messages on rt_app_comm().
 */
#include "check/pexchange.h"
#include "check/ptopo.h"
#include "par/pout.h"

#include "base/base.h"
#include "base/pfor.h"
#include "rt.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- exact coordinate keys ----------------------------------------------------------------- */

static uint64_t pt_hash(double x, double y) {
    return mesh_hash64(mesh_dbits(x) * 0x9e3779b97f4a7c15ULL ^ mesh_hash64(mesh_dbits(y)));
}

/* ---- records ------------------------------------------------------------------------------- */

typedef struct vq { /* a candidate shared vertex, to its rendezvous */
    double x, y;
    int32_t rank, lid;
} vq;
_Static_assert(sizeof(vq) == 24, "vq: no padding");

typedef struct vr { /* rendezvous -> holder: who owns it */
    int32_t lid, owner, gpos, nhold;
} vr;
_Static_assert(sizeof(vr) == 16, "vr: no padding");

typedef struct vn { /* owner -> rendezvous, then rendezvous -> holder: the number */
    int64_t gid;
    int32_t idx, pad; /* owner -> rendezvous: group position; rendezvous -> holder: lid */
} vn;
_Static_assert(sizeof(vn) == 16, "vn: no padding");

typedef struct sq { /* an open listed subsegment, to its rendezvous */
    double x[4];
    int32_t rank, lsid;
} sq;
_Static_assert(sizeof(sq) == 40, "sq: no padding");

static int cmp_vq(const void *pa, const void *pb) {
    const vq *a = pa, *b = pb;
    uint64_t ax = mesh_dbits(a->x), bx = mesh_dbits(b->x), ay = mesh_dbits(a->y),
             by = mesh_dbits(b->y);
    if (ax != bx) return ax < bx ? -1 : 1;
    if (ay != by) return ay < by ? -1 : 1;
    return (a->rank > b->rank) - (a->rank < b->rank);
}

static int same_vq(const vq *a, const vq *b) {
    return mesh_dbits(a->x) == mesh_dbits(b->x) && mesh_dbits(a->y) == mesh_dbits(b->y);
}

static int cmp_sq(const void *pa, const void *pb) {
    const sq *a = pa, *b = pb;
    for (int k = 0; k < 4; k++) {
        uint64_t u = mesh_dbits(a->x[k]), v = mesh_dbits(b->x[k]);
        if (u != v) return u < v ? -1 : 1;
    }
    return (a->rank > b->rank) - (a->rank < b->rank);
}

/* ---- input vertices ------------------------------------------------------------------------ */

/* The input's points in an open-addressing table keyed by their coordinates. */
typedef struct in_table {
    const pslg *in;
    const mesh_flat *f;
    int32_t *slot; /* input point numbers, -1: empty */
    size_t mask;
    int64_t *id;
} in_table;

/* Local vertices [a, b) looked up in the table (read only: any number of threads at once). */
static void input_ids_range(void *arg, int part, int64_t a, int64_t b) {
    (void)part;
    const in_table *t = arg;
    const double *ixy = t->in->xy;
    for (int64_t v = a; v < b; v++) {
        double x = t->f->xy[2 * (size_t)v], y = t->f->xy[2 * (size_t)v + 1];
        size_t h = pt_hash(x, y) & t->mask;
        t->id[v] = -1;
        for (; t->slot[h] >= 0; h = (h + 1) & t->mask)
            if (ixy[2 * (size_t)t->slot[h]] == x && ixy[2 * (size_t)t->slot[h] + 1] == y) {
                t->id[v] = t->slot[h];
                break;
            }
    }
}

/* in_id[v] = input number of local vertex v (exact coordinates), or -1; the lookups on up to
 * threads threads.  A part whose first vertices are the input's, in order and bit for bit (as
 * ./pcdm's parts are: every subdomain mesh starts from the augmented PSLG's vertices), needs no
 * lookup: its other vertices are distinct from those. */
static int64_t *input_ids(const mesh_flat *f, const pslg *in, int threads) {
    if (f->vin) { /* the part says which */
        int64_t *id = mesh_xmalloc((size_t)f->nverts + 1, sizeof(int64_t));
        for (int32_t v = 0; v < f->nverts; v++)
            id[v] = v < f->nvin && f->vin[v] >= 0 && f->vin[v] < in->nverts ? f->vin[v] : -1;
        return id;
    }
    if (in->nverts > 0 && f->nverts >= in->nverts &&
        memcmp(f->xy, in->xy, 2 * (size_t)in->nverts * sizeof(double)) == 0) {
        int64_t *id = mesh_xmalloc((size_t)f->nverts + 1, sizeof(int64_t));
        for (int32_t v = 0; v < f->nverts; v++)
            id[v] = v < in->nverts ? v : -1;
        return id;
    }
    size_t ns = 16;
    while (ns < 2 * (size_t)in->nverts + 2)
        ns *= 2;
    int32_t *slot = mesh_xmalloc(ns, sizeof(int32_t));
    memset(slot, 0xff, ns * sizeof(int32_t));
    for (int32_t i = 0; i < in->nverts; i++) {
        double x = in->xy[2 * (size_t)i], y = in->xy[2 * (size_t)i + 1];
        size_t h = pt_hash(x, y) & (ns - 1);
        while (slot[h] >= 0 &&
               !(in->xy[2 * (size_t)slot[h]] == x && in->xy[2 * (size_t)slot[h] + 1] == y))
            h = (h + 1) & (ns - 1);
        if (slot[h] < 0) slot[h] = i; /* a repeated input point keeps its first number */
    }
    in_table t = {in, f, slot, ns - 1, mesh_xmalloc((size_t)f->nverts + 1, sizeof(int64_t))};
    mesh_pfor_ranges(f->nverts, threads, 1 << 14, input_ids_range, &t);
    free(slot);
    return t.id;
}

/* ---- vertices ------------------------------------------------------------------------------ */

typedef struct mark_ctx {
    uint8_t *st;
    const int64_t *gid;
} mark_ctx;

/* par_open_edges visitor: the non-input ends of an open edge are candidates (st bit 2). */
static void mark_open(void *ctx, int32_t a, int32_t b, int32_t apex) {
    mark_ctx *m = ctx;
    if (m->gid[a] < 0) m->st[a] |= 2;
    if (m->gid[b] < 0) m->st[b] |= 2;
}

/* The used vertices: st[v] = 1 for every triangle corner v, on several threads each over a
 * range of corners.  Two threads may mark one vertex: the marks are relaxed atomic stores of the
 * same value (plain stores on common hardware; no read-modify-write), and the join orders them
 * before every later read. */
typedef struct used_job {
    const mesh_flat *f;
    uint8_t *st;
} used_job;

static void used_mark(void *arg, int k, int64_t a, int64_t b) {
    (void)k;
    const used_job *j = arg;
    for (int64_t i = a; i < b; i++)
        __atomic_store_n(&j->st[j->f->tri[i]], (uint8_t)1, __ATOMIC_RELAXED);
}

static void mark_used(const mesh_flat *f, uint8_t *st, int threads) {
    used_job j = {f, st};
    mesh_pfor_ranges(3 * (int64_t)f->ntris, threads, 1 << 16, used_mark, &j);
}

/* Steps (2)-(4) of the header: fills num->gid, owned, nowned, vfirst, nverts, nshared; the
 * used vertices found on up to threads threads. */
static void number_vertices(const mesh_flat *f, const par_vtris *x, int threads,
                            par_numbering *num) {
    int rank = rt_rank(), P = rt_size();
    MPI_Comm c = rt_app_comm();
    int32_t nv = f->nverts;
    int64_t *gid = num->gid;
    /* used vertices and candidates (non-input vertices of open edges) */
    uint8_t *st = mesh_xcalloc((size_t)nv + 1, 1); /* 1 used, 2 candidate, 4 owned elsewhere */
    mark_used(f, st, threads);
    mark_ctx mc = {st, gid};
    par_open_edges(f, x, mark_open, &mc);
    int64_t nq = 0;
    for (int32_t v = 0; v < nv; v++)
        nq += (st[v] & 2) != 0;
    vq *q = mesh_xmalloc((size_t)nq + 1, sizeof(vq));
    int *dest = mesh_xmalloc((size_t)nq + 1, sizeof(int));
    nq = 0;
    for (int32_t v = 0; v < nv; v++)
        if (st[v] & 2) {
            q[nq] = (vq){f->xy[2 * (size_t)v], f->xy[2 * (size_t)v + 1], rank, v};
            dest[nq] = (int)(pt_hash(q[nq].x, q[nq].y) % (uint64_t)P);
            nq++;
        }
    /* round 1: candidates to their rendezvous; owner = lowest holder */
    int64_t nr;
    vq *R = par_exchange(q, sizeof(vq), dest, nq, &nr);
    qsort(R, (size_t)nr, sizeof *R, cmp_vq);
    vr *rep = mesh_xmalloc((size_t)nr + 1, sizeof(vr));
    int *rdest = mesh_xmalloc((size_t)nr + 1, sizeof(int));
    for (int64_t i = 0; i < nr;) {
        int64_t j = i + 1;
        while (j < nr && same_vq(&R[j], &R[i]))
            j++;
        for (int64_t k = i; k < j; k++) {
            rep[k] = (vr){R[k].lid, R[i].rank, (int32_t)i, (int32_t)(j - i)};
            rdest[k] = R[k].rank;
        }
        i = j;
    }
    int64_t nb;
    vr *back = par_exchange(rep, sizeof(vr), rdest, nr, &nb);
    free(rep);
    /* owned vertices, numbered by a prefix sum */
    int32_t nshared = 0;
    for (int64_t i = 0; i < nb; i++) {
        if (back[i].owner != rank) st[back[i].lid] |= 4;
        if (back[i].nhold > 1) nshared++;
    }
    int64_t mine = 0;
    for (int32_t v = 0; v < nv; v++)
        if ((st[v] & 1) && gid[v] < 0 && !(st[v] & 4)) mine++;
    int64_t first = 0, total = 0;
    MESH_MPI(MPI_Exscan(&mine, &first, 1, MPI_INT64_T, MPI_SUM, c));
    if (rank == 0) first = 0;
    MESH_MPI(MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, c));
    num->vfirst = num->nin + first;
    num->nverts = num->nin + total;
    num->nowned = (int32_t)mine;
    num->owned = mesh_xmalloc((size_t)mine + 1, sizeof(int32_t));
    int64_t k = 0;
    for (int32_t v = 0; v < nv; v++)
        if ((st[v] & 1) && gid[v] < 0 && !(st[v] & 4)) {
            num->owned[k] = v;
            gid[v] = num->vfirst + k++;
        }
    /* round 2: owners' numbers to the rendezvous, forwarded to the other holders */
    vn *nq2 = mesh_xmalloc((size_t)nb + 1, sizeof(vn));
    int64_t n2 = 0;
    for (int64_t i = 0; i < nb; i++)
        if (back[i].owner == rank && back[i].nhold > 1) {
            int32_t v = back[i].lid;
            nq2[n2] = (vn){gid[v], back[i].gpos, 0};
            dest[n2] = (int)(pt_hash(f->xy[2 * (size_t)v], f->xy[2 * (size_t)v + 1]) % (uint64_t)P);
            n2++;
        }
    int64_t ng;
    vn *got = par_exchange(nq2, sizeof(vn), dest, n2, &ng);
    vn *fwd = mesh_xmalloc((size_t)nr + 1, sizeof(vn));
    int64_t nf = 0;
    for (int64_t i = 0; i < ng; i++) {
        int64_t g0 = got[i].idx;
        for (int64_t j = g0 + 1; j < nr && same_vq(&R[j], &R[g0]); j++) {
            fwd[nf] = (vn){got[i].gid, R[j].lid, 0};
            rdest[nf++] = R[j].rank;
        }
    }
    int64_t nl;
    vn *learn = par_exchange(fwd, sizeof(vn), rdest, nf, &nl);
    for (int64_t i = 0; i < nl; i++)
        gid[learn[i].idx] = learn[i].gid;
    for (int32_t v = 0; v < nv && !num->unnumbered; v++)
        if ((st[v] & 1) && gid[v] < 0) num->unnumbered = v + 1;
    num->nshared = nshared;
    free(st);
    free(q);
    free(dest);
    free(R);
    free(rdest);
    free(back);
    free(nq2);
    free(got);
    free(fwd);
    free(learn);
}

/* ---- segments ------------------------------------------------------------------------------ */

typedef struct open_list {
    int64_t *k; /* undirected open edges as (min << 32 | max) */
    int64_t n, cap;
} open_list;

static void list_open(void *ctx, int32_t a, int32_t b, int32_t apex) {
    open_list *l = ctx;
    MESH_GROW(l->k, l->n, l->cap);
    l->k[l->n++] = (int64_t)(a < b ? a : b) << 32 | (a < b ? b : a);
}

static int cmp_i64(const void *pa, const void *pb) {
    int64_t a = *(const int64_t *)pa, b = *(const int64_t *)pb;
    return (a > b) - (a < b);
}

/* idx[0 .. n) reordered stably by key[idx[i]] in [0, nb) (a counting sort; tmp: n items, cnt:
 * nb + 1). */
static void count_sort(int32_t *idx, int32_t *tmp, int32_t n, const int32_t *key, int32_t nb,
                       int32_t *cnt) {
    memset(cnt, 0, ((size_t)nb + 1) * sizeof *cnt);
    for (int32_t i = 0; i < n; i++)
        cnt[key[idx[i]] + 1]++;
    for (int32_t b = 0; b < nb; b++)
        cnt[b + 1] += cnt[b];
    for (int32_t i = 0; i < n; i++)
        tmp[cnt[key[idx[i]]]++] = idx[i];
    memcpy(idx, tmp, (size_t)n * sizeof *idx);
}

/* Step (5): fills num->wseg, nwseg, nsegs. */
static void number_segments(const mesh_flat *f, const uint8_t *artificial, const par_vtris *x,
                            par_numbering *num) {
    int rank = rt_rank(), P = rt_size();
    open_list ol = {NULL, 0, 0}; /* the part's open edges, sorted: O(boundary) */
    if (P > 1) {                 /* one rank: no other part can list one of its subsegments */
        par_open_edges(f, x, list_open, &ol);
        mesh_sort_u64((uint64_t *)ol.k, (size_t)ol.n); /* non-negative: the same order */
    }
    /* listed input subsegments, each pair once (a part may list one from both its sides):
     * in (pair, id) order -- two stable counting sorts, by the higher end, then the lower --
     * the first of each pair kept */
    int32_t nk = 0, ns = f->nsegs;
    int32_t *lo = mesh_xmalloc((size_t)ns + 1, sizeof(int32_t)),
            *hi = mesh_xmalloc((size_t)ns + 1, sizeof(int32_t));
    int32_t *ord = mesh_xmalloc((size_t)ns + 1, sizeof(int32_t)),
            *tmp = mesh_xmalloc((size_t)ns + 1, sizeof(int32_t));
    for (int32_t s = 0; s < ns; s++) {
        int32_t a = f->seg[2 * (size_t)s], b = f->seg[2 * (size_t)s + 1];
        lo[s] = a < b ? a : b;
        hi[s] = a < b ? b : a;
        if (!(artificial && artificial[s])) ord[nk++] = s;
    }
    int32_t *cnt = mesh_xmalloc((size_t)f->nverts + 1, sizeof(int32_t));
    count_sort(ord, tmp, nk, hi, f->nverts, cnt);
    count_sort(ord, tmp, nk, lo, f->nverts, cnt);
    free(cnt);
    free(tmp);
    int32_t *cand = mesh_xmalloc((size_t)nk + 1, sizeof(int32_t));
    int32_t nc = 0;
    uint8_t *skip = mesh_xcalloc((size_t)f->nsegs + 1, 1);
    for (int32_t i = 0; i < nk; i++) {
        int32_t s = ord[i];
        if (i > 0 && lo[s] == lo[ord[i - 1]] && hi[s] == hi[ord[i - 1]]) {
            skip[s] = 1;
            continue;
        }
        int64_t key = (int64_t)lo[s] << 32 | hi[s];
        /* a PCDM part's subsegment with the same subdomain on both sides, or the domain on one
         * (sinterface 0), has one lister: no other part lists it, open or not */
        if (artificial && f->sinterface && !f->sinterface[s]) continue;
        if (ol.n && bsearch(&key, ol.k, (size_t)ol.n, sizeof *ol.k, cmp_i64))
            cand[nc++] = s; /* an open edge: another part may list it too */
    }
    free(ord);
    free(lo);
    free(hi);
    free(ol.k);
    /* open listed subsegments to their rendezvous: all but the lowest holder skip them */
    sq *q = mesh_xmalloc((size_t)nc + 1, sizeof(sq));
    int *dest = mesh_xmalloc((size_t)nc + 1, sizeof(int));
    for (int32_t i = 0; i < nc; i++) {
        int32_t s = cand[i];
        const double *p = f->xy + 2 * (size_t)f->seg[2 * (size_t)s],
                     *r = f->xy + 2 * (size_t)f->seg[2 * (size_t)s + 1];
        int sw = mesh_dbits(p[0]) > mesh_dbits(r[0]) ||
                 (mesh_dbits(p[0]) == mesh_dbits(r[0]) && mesh_dbits(p[1]) > mesh_dbits(r[1]));
        if (sw) {
            const double *t = p;
            p = r;
            r = t;
        }
        q[i] = (sq){{p[0], p[1], r[0], r[1]}, rank, s};
        dest[i] = (int)(mesh_hash64(pt_hash(p[0], p[1]) ^ pt_hash(r[0], r[1])) % (uint64_t)P);
    }
    int64_t nr;
    sq *R = par_exchange(q, sizeof(sq), dest, nc, &nr);
    qsort(R, (size_t)nr, sizeof *R, cmp_sq);
    int32_t *rep = mesh_xmalloc((size_t)nr + 1, sizeof(int32_t));
    int *rdest = mesh_xmalloc((size_t)nr + 1, sizeof(int));
    int64_t nrep = 0;
    for (int64_t i = 1; i < nr; i++)
        if (!memcmp(R[i].x, R[i - 1].x, sizeof R[i].x) && R[i].rank != R[i - 1].rank) {
            rep[nrep] = R[i].lsid;
            rdest[nrep++] = R[i].rank;
        }
    int64_t nb;
    int32_t *back = par_exchange(rep, sizeof(int32_t), rdest, nrep, &nb);
    for (int64_t i = 0; i < nb; i++)
        skip[back[i]] = 1;
    num->wseg = mesh_xmalloc((size_t)f->nsegs + 1, sizeof(int32_t));
    num->nwseg = 0;
    for (int32_t s = 0; s < f->nsegs; s++)
        if (!(artificial && artificial[s]) && !skip[s]) num->wseg[num->nwseg++] = s;
    int64_t mine = num->nwseg;
    MESH_MPI(MPI_Allreduce(&mine, &num->nsegs, 1, MPI_INT64_T, MPI_SUM, rt_app_comm()));
    free(cand);
    free(skip);
    free(q);
    free(dest);
    free(R);
    free(rep);
    free(rdest);
    free(back);
}

/* ---- the numbering ------------------------------------------------------------------------- */

int par_number(const mesh_flat *local, const pslg *in, const uint8_t *artificial,
               par_numbering *num, char *err, size_t errlen) {
    return par_number_open(local, in, artificial, NULL, 1, num, err, errlen);
}

int par_number_open(const mesh_flat *local, const pslg *in, const uint8_t *artificial,
                    const uint8_t *topen, int threads, par_numbering *num, char *err,
                    size_t errlen) {
    MPI_Comm c = rt_app_comm();
    int rank = rt_rank();
    memset(num, 0, sizeof *num);
    if (errlen) err[0] = '\0';
    num->nin = in->nverts;
    num->gid = input_ids(local, in, threads);
    par_vtris x;
    par_vtris_open(local, topen, &x);
    num->topen = topen;
    number_vertices(local, &x, threads, num);
    number_segments(local, artificial, &x, num);
    par_vtris_free(&x);
    /* a holder that did not see a shared vertex on its part's boundary owns it too, and the
     * other holders then wait for a number in vain: the parts disagree */
    int32_t u = num->unnumbered - 1;
    char m[300] = "";
    if (u >= 0)
        snprintf(m, sizeof m,
                 "rank %d: vertex (%.17g, %.17g) has no number: the parts disagree about it", rank,
                 local->xy[2 * (size_t)u], local->xy[2 * (size_t)u + 1]);
    if (par_fail_any(u >= 0, NULL) != 0) {
        int first_bad = u >= 0 ? rank : rt_size(), who = 0;
        MESH_MPI(MPI_Allreduce(&first_bad, &who, 1, MPI_INT, MPI_MIN, c));
        MESH_MPI(MPI_Bcast(m, (int)sizeof m, MPI_CHAR, who, c));
        snprintf(err, errlen, "%s", m);
        par_numbering_free(num);
        return -1;
    }
    int64_t nt = local->ntris, first = 0;
    MESH_MPI(MPI_Exscan(&nt, &first, 1, MPI_INT64_T, MPI_SUM, c));
    if (rank == 0) first = 0;
    num->tfirst = first;
    MESH_MPI(MPI_Allreduce(&nt, &num->ntris, 1, MPI_INT64_T, MPI_SUM, c));
    return 0;
}

void par_numbering_free(par_numbering *num) {
    free(num->owned);
    free(num->gid);
    free(num->wseg);
    memset(num, 0, sizeof *num);
}
