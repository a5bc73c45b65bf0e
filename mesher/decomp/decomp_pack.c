/* decomp_pack: a decomposition as one byte buffer and back (pcdm_decomp_pack, pcdm_decomp_unpack),
 * so that one rank can compute it and the others receive it instead of computing it again; the
 * input PSLG alone the same way (pslg_pack, pslg_unpack), so that one rank reads and checks it.
 *
 * Layout: the scalar fields, then every array as (present, bytes, data): a 64-bit flag (0: the
 * pointer was NULL), a 64-bit byte count and the bytes, in a fixed order.  The buffer is read
 * back with every count checked against what is left, so a short or corrupt buffer is an error,
 * never a read past its end.  Machine-native byte order: sender and receivers run the same build
 * (the ranks compare their handler tables and inputs already).  The CDT kept for ./pbw (cdt) is
 * not carried: a decomposition with one cannot be packed.
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

static void put_arr(wbuf *w, const void *a, size_t len) {
    int64_t h[2] = {a != NULL, a ? (int64_t)len : 0};
    put(w, h, sizeof h);
    if (a) put(w, a, len);
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

/* An array of exactly len bytes (len 0 allowed), or NULL if it was sent as NULL. */
static void *get_arr(rbuf *r, size_t len) {
    int64_t h[2];
    get(r, h, sizeof h);
    if (r->bad || !h[0]) return NULL;
    if (h[1] != (int64_t)len || len > r->n - r->at) {
        r->bad = 1;
        return NULL;
    }
    void *a = mesh_xmalloc(len + 1, 1);
    memcpy(a, r->p + r->at, len);
    r->at += len;
    return a;
}

#define PUT(x) put(&w, &(x), sizeof(x))
#define GET(x) get(&r, &(x), sizeof(x))

/* A PSLG's counts and names, then (after the caller's scalars) its arrays. */
static void put_pslg_head(wbuf *wp, const pslg *g) {
    put(wp, &g->nverts, sizeof g->nverts), put(wp, &g->nattr, sizeof g->nattr);
    put(wp, &g->nsegs, sizeof g->nsegs), put(wp, &g->nholes, sizeof g->nholes);
    put(wp, &g->nregions, sizeof g->nregions), put(wp, &g->first_index, sizeof g->first_index);
    put(wp, &g->quiet, sizeof g->quiet), put(wp, &g->scale_exp, sizeof g->scale_exp);
    put(wp, g->path, sizeof g->path);
    put(wp, g->segpath, sizeof g->segpath);
}

static void put_pslg_arrays(wbuf *wp, const pslg *g) {
    size_t nv = (size_t)g->nverts, ns = (size_t)g->nsegs;
    put_arr(wp, g->xy, 2 * nv * sizeof(double));
    put_arr(wp, g->vmarker, nv * sizeof(int32_t));
    put_arr(wp, g->vattr, (size_t)g->nattr * nv * sizeof(double));
    put_arr(wp, g->vline, nv * sizeof(int32_t));
    put_arr(wp, g->seg, 2 * ns * sizeof(int32_t));
    put_arr(wp, g->smarker, ns * sizeof(int32_t));
    put_arr(wp, g->sline, ns * sizeof(int32_t));
    put_arr(wp, g->holes, 2 * (size_t)g->nholes * sizeof(double));
    put_arr(wp, g->regions, 4 * (size_t)g->nregions * sizeof(double));
}

/* The counts are checked here: a bad one marks the buffer bad, and the arrays then read as
 * empty (NULL). */
static void get_pslg_head(rbuf *rp, pslg *g) {
    get(rp, &g->nverts, sizeof g->nverts), get(rp, &g->nattr, sizeof g->nattr);
    get(rp, &g->nsegs, sizeof g->nsegs), get(rp, &g->nholes, sizeof g->nholes);
    get(rp, &g->nregions, sizeof g->nregions), get(rp, &g->first_index, sizeof g->first_index);
    get(rp, &g->quiet, sizeof g->quiet), get(rp, &g->scale_exp, sizeof g->scale_exp);
    get(rp, g->path, sizeof g->path);
    get(rp, g->segpath, sizeof g->segpath);
    g->path[sizeof g->path - 1] = g->segpath[sizeof g->segpath - 1] = '\0';
    if (g->nverts < 0 || g->nsegs < 0 || g->nholes < 0 || g->nregions < 0 || g->nattr < 0)
        rp->bad = 1;
}

static void get_pslg_arrays(rbuf *rp, pslg *g) {
    size_t nv = rp->bad ? 0 : (size_t)g->nverts, ns = rp->bad ? 0 : (size_t)g->nsegs;
    g->xy = get_arr(rp, 2 * nv * sizeof(double));
    g->vmarker = get_arr(rp, nv * sizeof(int32_t));
    g->vattr = get_arr(rp, (size_t)(rp->bad ? 0 : g->nattr) * nv * sizeof(double));
    g->vline = get_arr(rp, nv * sizeof(int32_t));
    g->seg = get_arr(rp, 2 * ns * sizeof(int32_t));
    g->smarker = get_arr(rp, ns * sizeof(int32_t));
    g->sline = get_arr(rp, ns * sizeof(int32_t));
    g->holes = get_arr(rp, 2 * (size_t)(rp->bad ? 0 : g->nholes) * sizeof(double));
    g->regions = get_arr(rp, 4 * (size_t)(rp->bad ? 0 : g->nregions) * sizeof(double));
}

void pslg_pack(const pslg *g, void **buf, size_t *len) {
    wbuf w = {NULL, 0, 0};
    put_pslg_head(&w, g);
    put_pslg_arrays(&w, g);
    *buf = w.p;
    *len = w.n;
}

int pslg_unpack(const void *buf, size_t len, pslg *g) {
    memset(g, 0, sizeof *g);
    rbuf r = {buf, len, 0, 0};
    get_pslg_head(&r, g);
    get_pslg_arrays(&r, g);
    if (!r.bad && r.at != r.n) r.bad = 1;
    if (!r.bad && !g->xy) r.bad = 1;
    if (r.bad) pslg_free(g);
    return r.bad ? -1 : 0;
}

int pcdm_decomp_pack(const pcdm_decomp *d, void **buf, size_t *len) {
    if (d->cdt) return -1;
    wbuf w = {NULL, 0, 0};
    const pslg *g = &d->g;
    put_pslg_head(&w, g);
    PUT(d->ninput_verts), PUT(d->ninput_segs), PUT(d->nboundary), PUT(d->ncuts), PUT(d->nsub);
    PUT(d->nranks), PUT(d->floor2), PUT(d->total_weight), PUT(d->ncoarse), PUT(d->exact);
    PUT(d->build_s);
    size_t nv = (size_t)g->nverts, ns = (size_t)g->nsegs, K = (size_t)d->nsub;
    put_pslg_arrays(&w, g);
    put_arr(&w, d->seg_parent, ns * sizeof(int32_t));
    put_arr(&w, d->seg_iface, ns);
    put_arr(&w, d->seg_sub, 2 * ns * sizeof(int32_t));
    put_arr(&w, d->vert_sub, nv * sizeof(int32_t));
    put_arr(&w, d->tri_off, d->tri_off ? (K + 2) * sizeof(int32_t) : 0);
    put_arr(&w, d->tri, d->tri_off ? 3 * (size_t)d->tri_off[K] * sizeof(int32_t) : 0);
    put_arr(&w, d->cut_xy, 4 * (size_t)d->ncuts * sizeof(double));
    put_arr(&w, d->sub_seed, 2 * K * sizeof(double));
    put_arr(&w, d->sub_area, K * sizeof(double));
    put_arr(&w, d->sub_weight, K * sizeof(double));
    put_arr(&w, d->sub_target, K * sizeof(double));
    put_arr(&w, d->sub_owner, K * sizeof(int32_t));
    *buf = w.p;
    *len = w.n;
    return 0;
}

int pcdm_decomp_unpack(const void *buf, size_t len, pcdm_decomp *d) {
    memset(d, 0, sizeof *d);
    rbuf r = {buf, len, 0, 0};
    pslg *g = &d->g;
    get_pslg_head(&r, g);
    GET(d->ninput_verts), GET(d->ninput_segs), GET(d->nboundary), GET(d->ncuts), GET(d->nsub);
    GET(d->nranks), GET(d->floor2), GET(d->total_weight), GET(d->ncoarse), GET(d->exact);
    GET(d->build_s);
    if (d->ncuts < 0 || d->nsub < 1) r.bad = 1;
    size_t nv = r.bad ? 0 : (size_t)g->nverts, ns = r.bad ? 0 : (size_t)g->nsegs,
           K = r.bad ? 0 : (size_t)d->nsub;
    get_pslg_arrays(&r, g);
    d->seg_parent = get_arr(&r, ns * sizeof(int32_t));
    d->seg_iface = get_arr(&r, ns);
    d->seg_sub = get_arr(&r, 2 * ns * sizeof(int32_t));
    d->vert_sub = get_arr(&r, nv * sizeof(int32_t));
    d->tri_off = get_arr(&r, (K + 2) * sizeof(int32_t));
    size_t ntri = 0; /* the offsets must run from 0 up to the count of triangles sent */
    for (size_t k = 0; d->tri_off && !r.bad && k <= K; k++)
        if (d->tri_off[k] < (k ? d->tri_off[k - 1] : 0)) r.bad = 1;
    if (d->tri_off && !r.bad) ntri = (size_t)d->tri_off[K];
    if (d->tri_off && d->tri_off[0] != 0) r.bad = 1;
    d->tri = get_arr(&r, 3 * ntri * sizeof(int32_t));
    if (!r.bad && (d->tri != NULL) != (d->tri_off != NULL)) r.bad = 1;
    d->cut_xy = get_arr(&r, 4 * (size_t)(r.bad ? 0 : d->ncuts) * sizeof(double));
    d->sub_seed = get_arr(&r, 2 * K * sizeof(double));
    d->sub_area = get_arr(&r, K * sizeof(double));
    d->sub_weight = get_arr(&r, K * sizeof(double));
    d->sub_target = get_arr(&r, K * sizeof(double));
    d->sub_owner = get_arr(&r, K * sizeof(int32_t));
    if (!r.bad && r.at != r.n) r.bad = 1;
    if (!r.bad && (!g->xy || !g->seg || !d->seg_sub || !d->sub_owner)) r.bad = 1;
    if (!r.bad) /* the per-subdomain lists are made again, not sent */
        for (size_t s = 0; s < 2 * ns && !r.bad; s++)
            if (d->seg_sub[s] < -1 || d->seg_sub[s] >= d->nsub) r.bad = 1;
    if (!r.bad) decomp_index(d);
    if (r.bad) pcdm_decomp_free(d);
    return r.bad ? -1 : 0;
}
