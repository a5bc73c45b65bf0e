/* decomp_pack: a decomposition sent from the rank that computed it to the others, so that they
 * receive it instead of computing it again (pcdm_decomp_pack_head, pcdm_decomp_unpack_head,
 * pcdm_decomp_unpack_done); the input PSLG alone the same way (pslg_pack_head, ...), so that one
 * rank reads and checks it.  The one-buffer forms (pcdm_decomp_pack, pslg_pack and their
 * unpacks) are the head followed by the arrays.
 *
 * Layout of a head: the scalar fields, then for every array, in a fixed order, a 64-bit flag (0:
 * the pointer was NULL) and a 64-bit byte count.  The arrays themselves are not copied into it:
 * a sender hands each to MPI where it lies, a receiver allocates each from the head's count and
 * receives straight into it, so neither holds a second copy of the decomposition (on North
 * America at 8 ranks, 60 MB less on every rank that receives it).  Every count the scalars
 * determine is checked against them when the head is read, and what depends on an array's
 * contents (the triangles' count from the offsets, labels in range) once the arrays are in
 * (..._unpack_done), so a short or corrupt head or buffer is an error, never a read past an end.
 * Machine-native byte order: sender and receivers run the same build (the ranks compare their
 * handler tables and inputs already).  The CDT kept for ./pbw (cdt) is not carried: a
 * decomposition with one cannot be packed.
 */
#include "decomp/decomp_impl.h"

#include "base/base.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct wbuf {
    unsigned char *p;
    size_t n, cap;
} wbuf;

static void put(wbuf *w, const void *src, size_t len) {
    if (w->n + len > w->cap) {
        size_t c = w->cap ? w->cap : 4096;
        while (c < w->n + len)
            c *= 2;
        w->p = mesh_xrealloc(w->p, c, 1);
        w->cap = c;
    }
    if (len) memcpy(w->p + w->n, src, len);
    w->n += len;
}

typedef struct rbuf {
    const unsigned char *p;
    size_t n, at;
    int bad;
} rbuf;

static void get(rbuf *r, void *dst, size_t len) {
    if (r->bad || len > r->n - r->at) {
        r->bad = 1;
        memset(dst, 0, len);
        return;
    }
    memcpy(dst, r->p + r->at, len);
    r->at += len;
}

#define PUT(x) put(w, &(x), sizeof(x))
#define GET(x) get(r, &(x), sizeof(x))

/* The arrays of a PSLG and of a decomposition in their fixed order: where each pointer lives
 * and the bytes the scalars give it (SIZE_MAX: known from another array's contents only). */
enum { MAX_ARRS = PCDM_PACK_MAX_ARRS };
typedef struct arrs {
    int n;
    void **slot[MAX_ARRS];
    size_t want[MAX_ARRS];
} arrs;

static void arr(arrs *a, void *slot, size_t want) {
    if (a->n >= MAX_ARRS) MESH_BUG("decomp_pack: more than %d arrays", MAX_ARRS);
    a->slot[a->n] = (void **)slot;
    a->want[a->n++] = want;
}

static void pslg_arrs(pslg *g, arrs *a) {
    size_t nv = (size_t)g->nverts, ns = (size_t)g->nsegs;
    arr(a, &g->xy, 2 * nv * sizeof(double));
    arr(a, &g->vmarker, nv * sizeof(int32_t));
    arr(a, &g->vattr, (size_t)g->nattr * nv * sizeof(double));
    arr(a, &g->vline, nv * sizeof(int32_t));
    arr(a, &g->seg, 2 * ns * sizeof(int32_t));
    arr(a, &g->smarker, ns * sizeof(int32_t));
    arr(a, &g->sline, ns * sizeof(int32_t));
    arr(a, &g->holes, 2 * (size_t)g->nholes * sizeof(double));
    arr(a, &g->regions, 4 * (size_t)g->nregions * sizeof(double));
}

static void decomp_arrs(pcdm_decomp *d, arrs *a) {
    pslg_arrs(&d->g, a);
    size_t nv = (size_t)d->g.nverts, ns = (size_t)d->g.nsegs, K = (size_t)d->nsub;
    arr(a, &d->seg_parent, ns * sizeof(int32_t));
    arr(a, &d->seg_iface, ns);
    arr(a, &d->seg_sub, 2 * ns * sizeof(int32_t));
    arr(a, &d->vert_sub, nv * sizeof(int32_t));
    arr(a, &d->tri_off, (K + 2) * sizeof(int32_t));
    arr(a, &d->tri, SIZE_MAX); /* 3 tri_off[K] of them */
    arr(a, &d->cut_xy, 4 * (size_t)d->ncuts * sizeof(double));
    arr(a, &d->sub_seed, 2 * K * sizeof(double));
    arr(a, &d->sub_area, K * sizeof(double));
    arr(a, &d->sub_weight, K * sizeof(double));
    arr(a, &d->sub_target, K * sizeof(double));
    arr(a, &d->sub_owner, K * sizeof(int32_t));
}

/* A PSLG's counts and names (the caller's scalars follow). */
static void put_pslg_head(wbuf *w, const pslg *g) {
    PUT(g->nverts), PUT(g->nattr), PUT(g->nsegs), PUT(g->nholes), PUT(g->nregions);
    PUT(g->first_index), PUT(g->quiet), PUT(g->scale_exp);
    put(w, g->path, sizeof g->path);
    put(w, g->segpath, sizeof g->segpath);
}

/* The counts are checked here: a bad one marks the head bad. */
static void get_pslg_head(rbuf *r, pslg *g) {
    GET(g->nverts), GET(g->nattr), GET(g->nsegs), GET(g->nholes), GET(g->nregions);
    GET(g->first_index), GET(g->quiet), GET(g->scale_exp);
    get(r, g->path, sizeof g->path);
    get(r, g->segpath, sizeof g->segpath);
    g->path[sizeof g->path - 1] = g->segpath[sizeof g->segpath - 1] = '\0';
    if (g->nverts < 0 || g->nsegs < 0 || g->nholes < 0 || g->nregions < 0 || g->nattr < 0)
        r->bad = 1;
}

/* Every array's (present, bytes), and the list of those present for the caller; an array whose
 * length the scalars do not give (SIZE_MAX) has other bytes. */
static void put_arrs(wbuf *w, const arrs *a, size_t other, pcdm_pack_arr *out, int *nout) {
    *nout = 0;
    for (int i = 0; i < a->n; i++) {
        void *p = *a->slot[i];
        size_t len = a->want[i] == SIZE_MAX ? other : a->want[i];
        int64_t h[2] = {p != NULL, p ? (int64_t)len : 0};
        put(w, h, sizeof h);
        if (p) out[(*nout)++] = (pcdm_pack_arr){p, len};
    }
}

/* Reads every array's (present, bytes), checks the bytes against the scalars' (and, for a whole
 * buffer, whole = 1, their sum against the bytes left after the head) and only then allocates
 * the arrays present (contents to come); the list of those for the caller.  Marks r bad on any
 * mismatch, before anything is allocated. */
static void get_arrs(rbuf *r, const arrs *a, int whole, pcdm_pack_arr *out, int *nout) {
    int64_t h[MAX_ARRS][2];
    size_t sum = 0;
    *nout = 0;
    for (int i = 0; i < a->n && !r->bad; i++) {
        get(r, h[i], sizeof h[i]);
        if (r->bad || !h[i][0]) continue;
        if (h[i][1] < 0 || (a->want[i] != SIZE_MAX && (size_t)h[i][1] != a->want[i]) ||
            (a->want[i] == SIZE_MAX && h[i][1] % (3 * (int64_t)sizeof(int32_t)) != 0))
            r->bad = 1;
        sum += (size_t)h[i][1];
    }
    if (!r->bad && whole && sum != r->n - r->at) r->bad = 1;
    for (int i = 0; i < a->n && !r->bad; i++) {
        if (!h[i][0]) continue;
        void *p = mesh_xmalloc((size_t)h[i][1] + 1, 1);
        *a->slot[i] = p;
        out[(*nout)++] = (pcdm_pack_arr){p, (size_t)h[i][1]};
    }
}

/* The one-buffer forms: the head, then the arrays' bytes in order. */
static void *join(const wbuf *head, const pcdm_pack_arr *a, int n, size_t *len) {
    size_t tot = head->n;
    for (int i = 0; i < n; i++)
        tot += a[i].len;
    unsigned char *b = mesh_xmalloc(tot + 1, 1), *q = b;
    memcpy(q, head->p, head->n);
    q += head->n;
    for (int i = 0; i < n; i++) {
        if (a[i].len) memcpy(q, a[i].p, a[i].len);
        q += a[i].len;
    }
    *len = tot;
    return b;
}

/* Copies the arrays' bytes from the rest of the buffer after the head (get_arrs checked that
 * they are exactly its length). */
static void fill(const unsigned char *p, size_t at, const pcdm_pack_arr *a, int na) {
    for (int i = 0; i < na; i++) {
        if (a[i].len) memcpy(a[i].p, p + at, a[i].len);
        at += a[i].len;
    }
}

/* The present arrays of a (those a pack lists, in its order) moved to at[0], at[1], ...: each
 * old array freed.  Returns how many. */
static int place(const arrs *a, unsigned char *const *at) {
    int k = 0;
    for (int i = 0; i < a->n; i++) {
        if (!*a->slot[i]) continue;
        mesh_xfree(*a->slot[i]);
        *a->slot[i] = at[k++];
    }
    return k;
}

/* Every array of a that held says lives elsewhere forgotten (NULL, not freed). */
static void forget(const arrs *a, int (*held)(const void *ctx, const void *p), const void *ctx) {
    for (int i = 0; i < a->n; i++)
        if (*a->slot[i] && held(ctx, *a->slot[i])) *a->slot[i] = NULL;
}

void pslg_pack_place(pslg *g, unsigned char *const *at) {
    arrs l = {0};
    pslg_arrs(g, &l);
    place(&l, at);
}

void pcdm_decomp_pack_place(pcdm_decomp *d, unsigned char *const *at) {
    arrs l = {0};
    decomp_arrs(d, &l);
    place(&l, at);
}

void pslg_pack_forget(pslg *g, int (*held)(const void *ctx, const void *p), const void *ctx) {
    arrs l = {0};
    pslg_arrs(g, &l);
    forget(&l, held, ctx);
}

void pcdm_decomp_pack_forget(pcdm_decomp *d, int (*held)(const void *ctx, const void *p),
                             const void *ctx) {
    arrs l = {0};
    decomp_arrs(d, &l);
    forget(&l, held, ctx);
}

/* ---- the input ------------------------------------------------------------------------------ */

void pslg_pack_head(const pslg *g, void **head, size_t *hlen, pcdm_pack_arr *a, int *na) {
    wbuf wb = {NULL, 0, 0}, *w = &wb;
    arrs l = {0};
    pslg_arrs((pslg *)g, &l);
    put_pslg_head(w, g);
    put_arrs(w, &l, 0, a, na);
    *head = wb.p;
    *hlen = wb.n;
}

/* The head's fields into g and its arrays allocated (whole: as get_arrs); r's position after the
 * head. */
static void read_pslg_head(rbuf *r, pslg *g, int whole, pcdm_pack_arr *a, int *na) {
    memset(g, 0, sizeof *g);
    *na = 0;
    get_pslg_head(r, g);
    arrs l = {0};
    if (!r->bad) pslg_arrs(g, &l);
    get_arrs(r, &l, whole, a, na);
}

int pslg_unpack_head(const void *head, size_t hlen, pslg *g, pcdm_pack_arr *a, int *na) {
    rbuf rb = {head, hlen, 0, 0};
    read_pslg_head(&rb, g, 0, a, na);
    if (!rb.bad && rb.at != rb.n) rb.bad = 1;
    if (rb.bad) pslg_free(g);
    return rb.bad ? -1 : 0;
}

int pslg_unpack_done(pslg *g) {
    if (g->xy) return 0;
    pslg_free(g);
    return -1;
}

void pslg_pack(const pslg *g, void **buf, size_t *len) {
    void *h;
    size_t hl;
    pcdm_pack_arr a[MAX_ARRS];
    int na;
    pslg_pack_head(g, &h, &hl, a, &na);
    *buf = join(&(wbuf){h, hl, hl}, a, na, len);
    free(h);
}

int pslg_unpack(const void *buf, size_t len, pslg *g) {
    pcdm_pack_arr a[MAX_ARRS];
    int na;
    rbuf rb = {buf, len, 0, 0};
    read_pslg_head(&rb, g, 1, a, &na);
    if (rb.bad) {
        pslg_free(g);
        return -1;
    }
    fill(buf, rb.at, a, na);
    return pslg_unpack_done(g);
}

/* ---- the decomposition ---------------------------------------------------------------------- */

static void put_decomp_scalars(wbuf *w, const pcdm_decomp *d) {
    PUT(d->ninput_verts), PUT(d->ninput_segs), PUT(d->nboundary), PUT(d->ncuts), PUT(d->nsub);
    PUT(d->nranks), PUT(d->floor2), PUT(d->total_weight), PUT(d->ncoarse), PUT(d->exact);
    PUT(d->build_s), PUT(d->iface_min_deg);
}

static void get_decomp_scalars(rbuf *r, pcdm_decomp *d) {
    GET(d->ninput_verts), GET(d->ninput_segs), GET(d->nboundary), GET(d->ncuts), GET(d->nsub);
    GET(d->nranks), GET(d->floor2), GET(d->total_weight), GET(d->ncoarse), GET(d->exact);
    GET(d->build_s), GET(d->iface_min_deg);
    if (d->ncuts < 0 || d->nsub < 1) r->bad = 1;
}

int pcdm_decomp_pack_head(const pcdm_decomp *d, void **head, size_t *hlen, pcdm_pack_arr *a,
                          int *na) {
    if (d->cdt) return -1;
    wbuf wb = {NULL, 0, 0}, *w = &wb;
    put_pslg_head(w, &d->g);
    put_decomp_scalars(w, d);
    arrs l = {0};
    decomp_arrs((pcdm_decomp *)d, &l);
    size_t tri = d->tri && d->tri_off ? 3 * (size_t)d->tri_off[d->nsub] * sizeof(int32_t) : 0;
    put_arrs(w, &l, tri, a, na);
    *head = wb.p;
    *hlen = wb.n;
    return 0;
}

/* The head's fields into d and its arrays allocated (whole: as get_arrs); r's position after the
 * head. */
static void read_decomp_head(rbuf *r, pcdm_decomp *d, int whole, pcdm_pack_arr *a, int *na) {
    memset(d, 0, sizeof *d);
    *na = 0;
    get_pslg_head(r, &d->g);
    get_decomp_scalars(r, d);
    arrs l = {0};
    if (!r->bad) decomp_arrs(d, &l);
    get_arrs(r, &l, whole, a, na);
}

int pcdm_decomp_unpack_head(const void *head, size_t hlen, pcdm_decomp *d, pcdm_pack_arr *a,
                            int *na) {
    rbuf rb = {head, hlen, 0, 0};
    read_decomp_head(&rb, d, 0, a, na);
    if (!rb.bad && rb.at != rb.n) rb.bad = 1;
    if (rb.bad) pcdm_decomp_free(d);
    return rb.bad ? -1 : 0;
}

int pcdm_decomp_unpack_done(pcdm_decomp *d, const pcdm_pack_arr *a, int na) {
    if (pcdm_decomp_unpack_index(d, a, na) == 0) return 0;
    pcdm_decomp_free(d);
    return -1;
}

int pcdm_decomp_unpack_index(pcdm_decomp *d, const pcdm_pack_arr *a, int na) {
    size_t ns = (size_t)d->g.nsegs, K = (size_t)d->nsub;
    int bad = !d->g.xy || !d->g.seg || !d->seg_sub || !d->sub_owner;
    bad = bad || (d->tri != NULL) != (d->tri_off != NULL);
    if (!bad && d->tri_off) { /* the offsets run from 0 up to the count of triangles sent */
        bad = d->tri_off[0] != 0;
        for (size_t k = 1; k <= K && !bad; k++)
            if (d->tri_off[k] < d->tri_off[k - 1]) bad = 1;
        size_t bytes = SIZE_MAX;
        for (int i = 0; i < na; i++)
            if (a[i].p == (void *)d->tri) bytes = a[i].len;
        if (!bad && bytes != 3 * (size_t)d->tri_off[K] * sizeof(int32_t)) bad = 1;
    }
    for (size_t s = 0; s < 2 * ns && !bad; s++) /* the per-subdomain lists are made again */
        if (d->seg_sub[s] < -1 || d->seg_sub[s] >= d->nsub) bad = 1;
    if (bad) return -1;
    decomp_index(d);
    return 0;
}

int pcdm_decomp_pack(const pcdm_decomp *d, void **buf, size_t *len) {
    void *h;
    size_t hl;
    pcdm_pack_arr a[MAX_ARRS];
    int na;
    if (pcdm_decomp_pack_head(d, &h, &hl, a, &na) != 0) return -1;
    *buf = join(&(wbuf){h, hl, hl}, a, na, len);
    free(h);
    return 0;
}

int pcdm_decomp_unpack(const void *buf, size_t len, pcdm_decomp *d) {
    pcdm_pack_arr a[MAX_ARRS];
    int na;
    rbuf rb = {buf, len, 0, 0};
    read_decomp_head(&rb, d, 1, a, &na);
    if (rb.bad) {
        pcdm_decomp_free(d);
        return -1;
    }
    fill(buf, rb.at, a, na);
    return pcdm_decomp_unpack_done(d, a, na);
}
