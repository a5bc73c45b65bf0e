/* xtopo.c: the edge topology of a mesh part for the derived outputs (xwrite.h).
 *
 * Algorithm.  The half-edges (h = 3t + j) are bucketed by their lower vertex (a counting sort:
 * one int32 per half-edge, one per vertex); each bucket, a few entries, is sorted by (upper
 * vertex, h), so the half-edges of one edge are adjacent: two are neighbours, one alone is open.
 * Edges are numbered in (lower, upper) vertex order, each listed under its first half-edge (the
 * lowest triangle).  O(n) time but for the buckets' small sorts, and about 12 bytes per triangle
 * besides the results (no table of all edge keys).  The part's input segments (not
 * the artificial ones) are keyed the same way and sorted; an edge is on a segment when its key
 * is found there (bsearch), taking that segment's marker.  Gmsh groups: sorted distinct values,
 * found again by bsearch.  Everything here is Local and works in the part's numbering.
 */
#include "io/xwrite.h"

#include "base/base.h"

#include <stdlib.h>
#include <string.h>

static int cmp_pair(const void *pa, const void *pb) {
    const int64_t *a = pa, *b = pb;
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

static int cmp_key(const void *pa, const void *pb) { /* first int64 of a pair */
    int64_t a = *(const int64_t *)pa, b = *(const int64_t *)pb;
    return (a > b) - (a < b);
}

/* The local ends of half-edge h (the edge opposite corner h % 3 of triangle h / 3). */
static void he_ends_f(const mesh_flat *f, int32_t h, int32_t *a, int32_t *b) {
    const int32_t *t = f->tri + 3 * (size_t)(h / 3);
    *a = t[(h % 3 + 1) % 3];
    *b = t[(h % 3 + 2) % 3];
}

static int64_t ekey(int32_t a, int32_t b) {
    return (int64_t)(a < b ? a : b) << 32 | (int64_t)(a < b ? b : a);
}

static int cmp_u64(const void *pa, const void *pb) {
    uint64_t a = *(const uint64_t *)pa, b = *(const uint64_t *)pb;
    return (a > b) - (a < b);
}

void mesh_xview_topo(mesh_xview *x, const mesh_flat *f, const uint8_t *artificial) {
    memset(x, 0, sizeof *x);
    x->f = f;
    x->artificial = artificial;
    size_t nh = 3 * (size_t)f->ntris;
    /* half-edges bucketed by their lower vertex (counting sort) */
    int32_t *start = mesh_xcalloc((size_t)f->nverts + 2, sizeof(int32_t));
    int32_t *he = mesh_xmalloc(nh + 1, sizeof(int32_t));
    for (size_t h = 0; h < nh; h++) {
        int32_t a, b;
        he_ends_f(f, (int32_t)h, &a, &b);
        start[(a < b ? a : b) + 2]++;
    }
    for (int32_t v = 0; v < f->nverts; v++)
        start[v + 2] += start[v + 1];
    for (size_t h = 0; h < nh; h++) {
        int32_t a, b;
        he_ends_f(f, (int32_t)h, &a, &b);
        he[start[(a < b ? a : b) + 1]++] = (int32_t)h;
    }
    /* the input segments of the part, keyed */
    int64_t *sk = mesh_xmalloc(2 * (size_t)f->nsegs + 1, sizeof(int64_t));
    size_t ns = 0;
    for (int32_t s = 0; s < f->nsegs; s++) {
        if (artificial && artificial[s]) continue;
        if (f->sinterface && f->sinterface[s]) continue;
        sk[2 * ns] = ekey(f->seg[2 * (size_t)s], f->seg[2 * (size_t)s + 1]);
        sk[2 * ns + 1] = f->smarker ? f->smarker[s] : 0;
        ns++;
    }
    qsort(sk, ns, 2 * sizeof(int64_t), cmp_pair);
    /* each bucket sorted by (upper vertex, half-edge): a run of one upper vertex is an edge */
    int32_t big = 0;
    for (int32_t v = 0; v < f->nverts; v++)
        if (start[v + 1] - start[v] > big) big = start[v + 1] - start[v];
    uint64_t *run = mesh_xmalloc((size_t)big + 1, sizeof(uint64_t));
    x->nb = mesh_xmalloc(nh + 1, sizeof(int32_t));
    x->eid = mesh_xmalloc(nh + 1, sizeof(int32_t));
    size_t cap = nh / 2 + 16;
    x->ehe = mesh_xmalloc(cap, sizeof(int32_t));
    x->emark = mesh_xmalloc(cap, sizeof(int32_t));
    x->eflag = mesh_xmalloc(cap, 1);
    int32_t ne = 0;
    for (int32_t v = 0; v < f->nverts; v++) {
        int32_t n = start[v + 1] - start[v];
        for (int32_t i = 0; i < n; i++) {
            int32_t h = he[start[v] + i], a, b;
            he_ends_f(f, h, &a, &b);
            run[i] = (uint64_t)(a < b ? b : a) << 32 | (uint64_t)h;
        }
        qsort(run, (size_t)n, sizeof *run, cmp_u64);
        for (int32_t i = 0; i < n;) {
            int32_t j = i + 1;
            while (j < n && run[j] >> 32 == run[i] >> 32)
                j++;
            if ((size_t)ne + 1 >= cap) {
                cap *= 2;
                x->ehe = mesh_xrealloc(x->ehe, cap, sizeof(int32_t));
                x->emark = mesh_xrealloc(x->emark, cap, sizeof(int32_t));
                x->eflag = mesh_xrealloc(x->eflag, cap, 1);
            }
            int32_t h0 = (int32_t)(run[i] & 0xffffffffu);
            x->ehe[ne] = h0;
            x->emark[ne] = 0;
            x->eflag[ne] = 0;
            for (int32_t k = i; k < j; k++) {
                int32_t h = (int32_t)(run[k] & 0xffffffffu);
                x->eid[h] = ne;
                x->nb[h] = -1;
            }
            if (j - i == 1) {
                x->eflag[ne] |= XE_OPEN | XE_BOUND;
            } else { /* two half-edges: neighbours (a third would be no manifold; left open) */
                int32_t h1 = (int32_t)(run[i + 1] & 0xffffffffu);
                x->nb[h0] = h1 / 3;
                x->nb[h1] = h0 / 3;
            }
            int64_t key = (int64_t)v << 32 | (int64_t)(run[i] >> 32);
            const int64_t *hit = ns ? bsearch(&key, sk, ns, 2 * sizeof(int64_t), cmp_key) : 0;
            if (hit) {
                x->eflag[ne] |= XE_SEG;
                x->emark[ne] = (int32_t)hit[1];
            }
            ne++;
            i = j;
        }
    }
    x->ne = ne;
    x->egid = mesh_xmalloc((size_t)ne + 1, sizeof(int64_t));
    for (int32_t e = 0; e < ne; e++)
        x->egid[e] = -1;
    free(run);
    free(sk);
    free(he);
    free(start);
}

void mesh_xview_set_remote(mesh_xview *x, int32_t h, int rank, int orank, int64_t gtri) {
    int32_t e = x->eid[h];
    MESH_GROW(x->otri, x->notri, x->cap_otri);
    x->otri[x->notri] = gtri;
    x->nb[h] = -2 - x->notri++;
    x->eflag[e] &= (uint8_t)~XE_BOUND;
    if (orank < rank) x->eflag[e] |= XE_OTHER;
}

void mesh_xview_finish(mesh_xview *x) {
    x->we = mesh_xmalloc((size_t)x->ne + 1, sizeof(int32_t));
    x->wl = mesh_xmalloc((size_t)x->ne + 1, sizeof(int32_t));
    x->nwe = x->nwl = 0;
    for (int32_t e = 0; e < x->ne; e++) {
        uint8_t fl = x->eflag[e];
        int bound = (fl & XE_BOUND) != 0;
        if (!((fl & XE_SEG) && x->emark[e] != 0)) x->emark[e] = bound;
        fl = (uint8_t)(fl & ~(XE_WRITE | XE_LINE));
        if (!(fl & XE_OTHER)) fl |= XE_WRITE;
        if ((fl & XE_WRITE) && (bound || (fl & XE_SEG))) fl |= XE_LINE;
        x->eflag[e] = (uint8_t)(fl & ~XE_OTHER);
        if (fl & XE_WRITE) {
            x->egid[e] = x->efirst + x->nwe;
            x->we[x->nwe++] = e;
        }
        if (fl & XE_LINE) x->wl[x->nwl++] = e;
    }
}

void mesh_xview_local_groups(const mesh_xview *x, int32_t **marks, int32_t *nm, double **attrs,
                             int32_t *na) {
    int32_t *m = mesh_xmalloc((size_t)x->nwl + 1, sizeof(int32_t));
    for (int32_t k = 0; k < x->nwl; k++)
        m[k] = x->emark[x->wl[k]];
    qsort(m, (size_t)x->nwl, sizeof *m, mesh_cmp_i32);
    int32_t n = 0;
    for (int32_t k = 0; k < x->nwl; k++)
        if (n == 0 || m[k] != m[n - 1]) m[n++] = m[k];
    *marks = m;
    *nm = n;
    const mesh_flat *f = x->f;
    int32_t nt = f->tattr ? f->ntris : 0;
    double *a = mesh_xmalloc((size_t)nt + 1, sizeof(double));
    if (nt) memcpy(a, f->tattr, (size_t)nt * sizeof(double));
    qsort(a, (size_t)nt, sizeof *a, mesh_cmp_dbl);
    n = 0;
    for (int32_t k = 0; k < nt; k++)
        if (n == 0 || a[k] != a[n - 1]) a[n++] = a[k];
    *attrs = a;
    *na = n;
}

/* Sorts idx[0 .. n) by grp[idx] (counting sort, stable); returns the number of groups used. */
static int32_t sort_by_group(int32_t *idx, int32_t n, const int32_t *grp, int32_t ngrp) {
    int32_t *cnt = mesh_xcalloc((size_t)ngrp + 1, sizeof(int32_t));
    int32_t *tmp = mesh_xmalloc((size_t)n + 1, sizeof(int32_t));
    for (int32_t k = 0; k < n; k++)
        cnt[grp[k] + 1]++;
    int32_t used = 0;
    for (int32_t g = 0; g < ngrp; g++) {
        used += cnt[g + 1] > 0;
        cnt[g + 1] += cnt[g];
    }
    for (int32_t k = 0; k < n; k++)
        tmp[cnt[grp[k]]++] = idx[k];
    memcpy(idx, tmp, (size_t)n * sizeof(int32_t));
    free(tmp);
    free(cnt);
    return used;
}

void mesh_xview_groups(mesh_xview *x, const int32_t *marks, int32_t nmarks, const double *attrs,
                       int32_t nattrs) {
    const mesh_flat *f = x->f;
    x->ncurve = nmarks;
    x->curve_mark = mesh_xmalloc((size_t)nmarks + 1, sizeof(int32_t));
    if (nmarks) memcpy(x->curve_mark, marks, (size_t)nmarks * sizeof(int32_t));
    x->nsurf = attrs && nattrs ? nattrs : 1;
    x->surf_attr = NULL;
    if (attrs && nattrs) {
        x->surf_attr = mesh_xmalloc((size_t)nattrs, sizeof(double));
        memcpy(x->surf_attr, attrs, (size_t)nattrs * sizeof(double));
    }
    /* lines: group = index of the marker */
    int32_t *grp =
        mesh_xmalloc((size_t)(x->nwl > f->ntris ? x->nwl : f->ntris) + 1, sizeof(int32_t));
    x->lperm = mesh_xmalloc((size_t)x->nwl + 1, sizeof(int32_t));
    for (int32_t k = 0; k < x->nwl; k++) {
        int32_t m = x->emark[x->wl[k]];
        const int32_t *hit = bsearch(&m, x->curve_mark, (size_t)nmarks, sizeof m, mesh_cmp_i32);
        if (!hit) MESH_BUG("xview: marker %d of no group", (int)m);
        x->lperm[k] = k;
        grp[k] = (int32_t)(hit - x->curve_mark);
    }
    x->nlblk = sort_by_group(x->lperm, x->nwl, grp, nmarks);
    x->tperm = mesh_xmalloc((size_t)f->ntris + 1, sizeof(int32_t));
    for (int32_t t = 0; t < f->ntris; t++) {
        x->tperm[t] = t;
        grp[t] = 0;
        if (x->surf_attr && f->tattr) {
            const double *hit =
                bsearch(&f->tattr[t], x->surf_attr, (size_t)x->nsurf, sizeof(double), mesh_cmp_dbl);
            if (!hit) MESH_BUG("xview: attribute %g of no group", f->tattr[t]);
            grp[t] = (int32_t)(hit - x->surf_attr);
        }
    }
    x->ntblk = sort_by_group(x->tperm, f->ntris, grp, x->nsurf);
    free(grp);
}

void mesh_xview_free(mesh_xview *x) {
    free(x->nb);
    free(x->otri);
    free(x->eid);
    free(x->ehe);
    free(x->emark);
    free(x->eflag);
    free(x->egid);
    free(x->we);
    free(x->wl);
    free(x->curve_mark);
    free(x->surf_attr);
    free(x->lperm);
    free(x->tperm);
    memset(x, 0, sizeof *x);
}
