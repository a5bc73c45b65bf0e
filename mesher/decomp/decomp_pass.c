/* decomp_pass: the passes of decomp_build over the labelled triangulation's triangles, run on the
 * host's idle CPUs while the decomposition is the only work there is (rank 0 decomposes for
 * ./pcdm while the other ranks and its own workers wait).
 *
 * The triangle slots are cut into chunks whose size depends on the slot count alone
 * (decomp_chunk), each chunk's results are made apart, and they are combined in chunk order, so
 * the decomposition is the same bits for any number of threads: sums per part are sums of the
 * chunks' sums in chunk order; the seed of a part is its first largest triangle in slot order
 * (a chunk's first largest, the first chunk's of equal area); interface edges and the
 * triangles by part come out in slot order, as one pass would list them.  Marks that several
 * chunks may set (kept vertices, a vertex's part) are relaxed atomic stores of values that do
 * not depend on which chunk stores last (decomp_build resets the vertex parts that could).
 * Local; the helper threads move onto the caller's CPUs beside its own (mesh_cpus_beside: a
 * rank a launcher bound to one core gets the cores of the ranks that wait) and call no MPI.
 */
#include "decomp/decomp_impl.h"

#include "base/base.h"
#include "base/pfor.h"
#include "geom/geom.h"

#include <pthread.h>
#include <string.h>

/* Slots a chunk: at least 2^16, and at most 1024 chunks. */
int64_t decomp_chunk(int64_t n) {
    int64_t c = (n + 1023) / 1024;
    return c < (1 << 16) ? (1 << 16) : c;
}

typedef struct chunked {
    const uint8_t *cpus; /* where the helpers go (mesh_cpus_beside), or NULL */
    pthread_t caller;
    int64_t n, size;
    void (*fn)(void *ctx, int32_t c, int32_t a, int32_t b);
    void *ctx;
} chunked;

static void chunk_run(void *arg, int64_t c) {
    chunked *k = arg;
    if (!pthread_equal(pthread_self(), k->caller)) mesh_thread_spread(k->cpus);
    int64_t a = c * k->size, b = a + k->size < k->n ? a + k->size : k->n;
    k->fn(k->ctx, (int32_t)c, (int32_t)a, (int32_t)b);
}

int32_t decomp_for_chunks(const decomp_threads *th, int64_t n,
                          void (*fn)(void *ctx, int32_t c, int32_t a, int32_t b), void *ctx) {
    int64_t size = decomp_chunk(n), nc = n > 0 ? (n + size - 1) / size : 0;
    int T = th && th->n > 1 && nc > 1 ? th->n : 1;
    uint8_t beside[MESH_HOST_CPUS];
    if (T > 1 && th->cpus) mesh_cpus_beside(th->cpus, beside);
    chunked k = {T > 1 && th->cpus ? beside : NULL, pthread_self(), n, size, fn, ctx};
    mesh_pfor_items(nc, T, chunk_run, &k);
    return (int32_t)nc;
}

int32_t decomp_nchunks(int64_t n) {
    int64_t s = decomp_chunk(n);
    return n > 0 ? (int32_t)((n + s - 1) / s) : 0;
}

/* ---- pass 1: per-part sums and seeds, interface endpoints kept ----------------------------- */

typedef struct p1 {
    const mesh *m;
    const int32_t *part;
    const double *tw;
    int32_t K;
    uint8_t *keep;
    double *area, *weight, *barea, *seed; /* [c * K + p] (seed: 2 each) */
    int32_t *best;
} p1;

static void pass1_chunk(void *arg, int32_t c, int32_t t0, int32_t t1) {
    p1 *q = arg;
    const mesh *m = q->m;
    int32_t K = q->K;
    double *area = q->area + (size_t)c * K, *weight = q->weight + (size_t)c * K;
    double *barea = q->barea + (size_t)c * K, *seed = q->seed + 2 * (size_t)c * K;
    int32_t *best = q->best + (size_t)c * K;
    for (int32_t k = 0; k < K; k++)
        best[k] = -1;
    for (int32_t t = t0; t < t1; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        int32_t p = q->part[t];
        if (p < 0 || p >= K) MESH_BUG("triangle %d has label %d of %d", t, p, K);
        const double *a = mesh_vertex_xy(m, m->tv[3 * t]),
                     *bb = mesh_vertex_xy(m, m->tv[3 * t + 1]),
                     *cc = mesh_vertex_xy(m, m->tv[3 * t + 2]);
        double ar = geom_area(a, bb, cc);
        area[p] += ar;
        weight[p] += q->tw[t];
        if (best[p] < 0 || ar > barea[p]) {
            best[p] = t;
            barea[p] = ar;
            seed[2 * p] = (a[0] + bb[0] + cc[0]) / 3;
            seed[2 * p + 1] = (a[1] + bb[1] + cc[1]) / 3;
        }
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, n = m->tn[e];
            if (n < 0 || q->part[n / 3] == p) continue;
            __atomic_store_n(&q->keep[mesh_org(m, e)], 1, __ATOMIC_RELAXED);
            __atomic_store_n(&q->keep[mesh_dest(m, e)], 1, __ATOMIC_RELAXED);
        }
    }
}

int decomp_pass1(const decomp_threads *th, const mesh *m, const int32_t *part, const double *tw,
                 int32_t K, uint8_t *keep, pcdm_decomp *d) {
    int32_t nc = decomp_nchunks(m->nt);
    size_t cells = (size_t)(nc > 0 ? nc : 1) * K;
    p1 q = {.m = m, .part = part, .tw = tw, .K = K, .keep = keep};
    q.area = mesh_xcalloc(cells, sizeof(double));
    q.weight = mesh_xcalloc(cells, sizeof(double));
    q.barea = mesh_xcalloc(cells, sizeof(double));
    q.seed = mesh_xcalloc(2 * cells, sizeof(double));
    q.best = mesh_xmalloc(cells, sizeof(int32_t));
    for (size_t i = 0; i < cells; i++)
        q.best[i] = -1;
    decomp_for_chunks(th, m->nt, pass1_chunk, &q);
    int empty = -1;
    for (int32_t p = 0; p < K; p++) {
        int32_t best = -1;
        double barea = 0;
        for (int32_t c = 0; c < nc; c++) {
            size_t i = (size_t)c * K + p;
            d->sub_area[p] += q.area[i];
            d->sub_weight[p] += q.weight[i];
            if (q.best[i] >= 0 && (best < 0 || q.barea[i] > barea)) {
                best = q.best[i];
                barea = q.barea[i];
                d->sub_seed[2 * p] = q.seed[2 * i];
                d->sub_seed[2 * p + 1] = q.seed[2 * i + 1];
            }
        }
        d->total_weight += d->sub_weight[p];
        if (best < 0 && empty < 0) empty = p;
    }
    mesh_xfree(q.area);
    mesh_xfree(q.weight);
    mesh_xfree(q.barea);
    mesh_xfree(q.seed);
    mesh_xfree(q.best);
    return empty;
}

/* ---- the sharp corners' parts (decomp_auto.c, step (4)) ---------------------------------- */

/* Every live triangle around an input corner sharper than 60 degrees takes the part of the
 * first such triangle (in slot order), a triangle at two such corners that of its last one:
 * chunk by chunk (decomp_for_chunks), first[v] the lowest slot at corner v (an atomic minimum,
 * whatever the order the chunks run in), then every chunk's triangles relabelled. */
typedef struct corner_merge {
    const mesh *m;
    int32_t *part, *first, *cp;
    int relabel;
} corner_merge;

static void corners_chunk(void *arg, int32_t c, int32_t t0, int32_t t1) {
    (void)c;
    corner_merge *C = arg;
    const mesh *m = C->m;
    for (int32_t t = t0; t < t1; t++)
        for (int j = 0; mesh_tri_alive(m, t) && j < 3; j++) {
            int32_t v = m->tv[3 * t + j];
            if (v >= m->ninput || !m->corner[v]) continue;
            if (C->relabel) {
                C->part[t] = C->cp[v];
                continue;
            }
            int32_t cur = __atomic_load_n(&C->first[v], __ATOMIC_RELAXED);
            while (t < cur && !__atomic_compare_exchange_n(&C->first[v], &cur, t, 0,
                                                           __ATOMIC_RELAXED, __ATOMIC_RELAXED))
                ;
        }
}

void decomp_merge_corners(const decomp_threads *th, const mesh *m, int32_t *part) {
    if (!m->has_corners || !m->corner) return;
    corner_merge C = {.m = m, .part = part};
    C.first = mesh_xmalloc((size_t)m->ninput + 1, sizeof(int32_t));
    C.cp = mesh_xmalloc((size_t)m->ninput + 1, sizeof(int32_t));
    for (int32_t v = 0; v < m->ninput; v++)
        C.first[v] = INT32_MAX;
    decomp_for_chunks(th, m->nt, corners_chunk, &C);
    for (int32_t v = 0; v < m->ninput; v++)
        C.cp[v] = C.first[v] < INT32_MAX ? part[C.first[v]] : -1;
    C.relabel = 1;
    decomp_for_chunks(th, m->nt, corners_chunk, &C);
    mesh_xfree(C.first);
    mesh_xfree(C.cp);
}

/* ---- the kept vertices' parts ----------------------------------------------------------- */

typedef struct pv {
    const mesh *m;
    const int32_t *part, *gid;
    const uint8_t *keep;
    int32_t *vert_sub;
} pv;

static void vsub_chunk(void *arg, int32_t c, int32_t t0, int32_t t1) {
    (void)c;
    pv *q = arg;
    const mesh *m = q->m;
    for (int32_t t = t0; t < t1; t++)
        for (int j = 0; mesh_tri_alive(m, t) && j < 3; j++) {
            int32_t v = m->tv[3 * t + j];
            if (q->keep[v] && q->gid[v] >= 0)
                __atomic_store_n(&q->vert_sub[q->gid[v]], q->part[t], __ATOMIC_RELAXED);
        }
}

void decomp_vert_parts(const decomp_threads *th, const mesh *m, const int32_t *part,
                       const uint8_t *keep, const int32_t *gid, int32_t *vert_sub) {
    pv q = {m, part, gid, keep, vert_sub};
    decomp_for_chunks(th, m->nt, vsub_chunk, &q);
}

/* ---- the edges between parts ------------------------------------------------------------ */

typedef struct pe {
    const mesh *m;
    const int32_t *part;
    int32_t **e, *n, *cap; /* each chunk's half-edges */
} pe;

static void edges_chunk(void *arg, int32_t c, int32_t t0, int32_t t1) {
    pe *q = arg;
    const mesh *m = q->m;
    for (int32_t t = t0; t < t1; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, n = m->tn[e];
            if (n < 0 || n / 3 < t || q->part[n / 3] == q->part[t]) continue;
            MESH_GROW(q->e[c], (size_t)q->n[c] + 1, q->cap[c]);
            q->e[c][q->n[c]++] = e;
        }
    }
}

int32_t *decomp_part_edges(const decomp_threads *th, const mesh *m, const int32_t *part,
                           int32_t *count) {
    int32_t nc = decomp_nchunks(m->nt);
    pe q = {.m = m, .part = part};
    q.e = mesh_xcalloc((size_t)nc + 1, sizeof(int32_t *));
    q.n = mesh_xcalloc((size_t)nc + 1, sizeof(int32_t));
    q.cap = mesh_xcalloc((size_t)nc + 1, sizeof(int32_t));
    decomp_for_chunks(th, m->nt, edges_chunk, &q);
    int32_t tot = 0;
    for (int32_t c = 0; c < nc; c++)
        tot += q.n[c];
    int32_t *out = mesh_xmalloc((size_t)tot + 1, sizeof(int32_t));
    for (int32_t c = 0, at = 0; c < nc; c++) {
        if (q.n[c]) memcpy(out + at, q.e[c], (size_t)q.n[c] * sizeof(int32_t));
        at += q.n[c];
        mesh_xfree(q.e[c]);
    }
    mesh_xfree(q.e);
    mesh_xfree(q.n);
    mesh_xfree(q.cap);
    *count = tot;
    return out;
}

/* ---- the triangles by part -------------------------------------------------------------- */

typedef struct pt {
    const mesh *m;
    const int32_t *part, *gid;
    int32_t K;
    int32_t *at;  /* [c * K + k]: counts, then where chunk c's next triangle of part k goes */
    int32_t *tri; /* 3 per triangle, in g's numbers */
    int fill;
} pt;

static void tri_chunk(void *arg, int32_t c, int32_t t0, int32_t t1) {
    pt *q = arg;
    const mesh *m = q->m;
    int32_t *at = q->at + (size_t)c * q->K;
    for (int32_t t = t0; t < t1; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        if (!q->fill) {
            at[q->part[t]]++;
            continue;
        }
        int32_t i = at[q->part[t]]++;
        for (int j = 0; j < 3; j++) {
            int32_t v = q->gid[m->tv[3 * t + j]];
            if (v < 0) MESH_BUG("vertex %d of triangle %d is not kept", m->tv[3 * t + j], t);
            q->tri[3 * (size_t)i + j] = v;
        }
    }
}

void decomp_tris_by_part(const decomp_threads *th, const mesh *m, const int32_t *part,
                         const int32_t *gid, int32_t K, pcdm_decomp *d) {
    int32_t nc = decomp_nchunks(m->nt);
    pt q = {.m = m, .part = part, .gid = gid, .K = K};
    q.at = mesh_xcalloc((size_t)(nc > 0 ? nc : 1) * K, sizeof(int32_t));
    decomp_for_chunks(th, m->nt, tri_chunk, &q);
    d->tri_off = mesh_xcalloc((size_t)K + 2, sizeof(int32_t));
    int32_t sum = 0;
    for (int32_t k = 0; k < K; k++) { /* part by part, chunk by chunk: slot order in a part */
        d->tri_off[k] = sum;
        for (int32_t c = 0; c < nc; c++) {
            int32_t n = q.at[(size_t)c * K + k];
            q.at[(size_t)c * K + k] = sum;
            sum += n;
        }
    }
    d->tri_off[K] = d->tri_off[K + 1] = sum;
    d->tri = mesh_xmalloc(3 * (size_t)sum + 1, sizeof(int32_t));
    q.tri = d->tri;
    q.fill = 1;
    decomp_for_chunks(th, m->nt, tri_chunk, &q);
    mesh_xfree(q.at);
}
