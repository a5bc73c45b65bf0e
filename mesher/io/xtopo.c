/* xtopo.c: the edge topology of a mesh part for the derived outputs (xwrite.h).
 *
 * Algorithm.  Every half-edge h = 3t + j gets the key (min << 32 | max) of its two local
 * vertices; sorting (key, h) pairs groups the half-edges of one edge (O(n log n), no hash
 * table): a pair of them are neighbours, a single one is open.  An edge is listed once, under
 * its first half-edge in the sorted run (the lowest triangle).  The part's input segments (not
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

static int64_t ekey(int32_t a, int32_t b) {
    return (int64_t)(a < b ? a : b) << 32 | (int64_t)(a < b ? b : a);
}

void mesh_xview_topo(mesh_xview *x, const mesh_flat *f, const uint8_t *artificial) {
    memset(x, 0, sizeof *x);
    x->f = f;
    x->artificial = artificial;
    size_t nh = 3 * (size_t)f->ntris;
    int64_t *kp = mesh_xmalloc(2 * nh + 1, sizeof(int64_t));
    for (size_t h = 0; h < nh; h++) {
        size_t t = h / 3, j = h % 3;
        kp[2 * h] = ekey(f->tri[3 * t + (j + 1) % 3], f->tri[3 * t + (j + 2) % 3]);
        kp[2 * h + 1] = (int64_t)h;
    }
    qsort(kp, nh, 2 * sizeof(int64_t), cmp_pair);
    x->nb = mesh_xmalloc(nh + 1, sizeof(int32_t));
    x->gnb = mesh_xmalloc(nh + 1, sizeof(int64_t));
    x->eid = mesh_xmalloc(nh + 1, sizeof(int32_t));
    int32_t ne = 0;
    for (size_t i = 0; i < nh; i++)
        ne += i == 0 || kp[2 * i] != kp[2 * (i - 1)];
    x->ne = ne;
    x->ehe = mesh_xmalloc((size_t)ne + 1, sizeof(int32_t));
    x->emark = mesh_xcalloc((size_t)ne + 1, sizeof(int32_t));
    x->eflag = mesh_xcalloc((size_t)ne + 1, 1);
    x->egid = mesh_xmalloc((size_t)ne + 1, sizeof(int64_t));
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
    int32_t e = -1;
    for (size_t i = 0; i < nh; i++) {
        int32_t h = (int32_t)kp[2 * i + 1];
        x->nb[h] = -1;
        x->gnb[h] = -1;
        if (i == 0 || kp[2 * i] != kp[2 * (i - 1)]) {
            e++;
            x->ehe[e] = h;
            x->egid[e] = -1;
            int open = i + 1 == nh || kp[2 * (i + 1)] != kp[2 * i];
            if (open) x->eflag[e] |= XE_OPEN | XE_BOUND;
            const int64_t *hit = ns ? bsearch(&kp[2 * i], sk, ns, 2 * sizeof(int64_t), cmp_key) : 0;
            if (hit) {
                x->eflag[e] |= XE_SEG;
                x->emark[e] = (int32_t)hit[1];
            }
        } else { /* the second half-edge of the edge: neighbours */
            int32_t g = (int32_t)kp[2 * (i - 1) + 1];
            x->nb[h] = g / 3;
            x->nb[g] = h / 3;
        }
        x->eid[h] = e;
    }
    free(sk);
    free(kp);
}

void mesh_xview_set_remote(mesh_xview *x, int32_t h, int rank, int orank, int64_t gtri) {
    int32_t e = x->eid[h];
    x->gnb[h] = gtri;
    x->eflag[e] &= (uint8_t)~XE_BOUND;
    if (orank < rank) x->eflag[e] |= XE_OTHER;
}

void mesh_xview_finish(mesh_xview *x) {
    const mesh_flat *f = x->f;
    for (size_t h = 0; h < 3 * (size_t)f->ntris; h++)
        if (x->nb[h] >= 0) x->gnb[h] = x->tfirst + x->nb[h];
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

static int cmp_i32(const void *pa, const void *pb) {
    int32_t a = *(const int32_t *)pa, b = *(const int32_t *)pb;
    return (a > b) - (a < b);
}

static int cmp_dbl(const void *pa, const void *pb) {
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

void mesh_xview_local_groups(const mesh_xview *x, int32_t **marks, int32_t *nm, double **attrs,
                             int32_t *na) {
    int32_t *m = mesh_xmalloc((size_t)x->nwl + 1, sizeof(int32_t));
    for (int32_t k = 0; k < x->nwl; k++)
        m[k] = x->emark[x->wl[k]];
    qsort(m, (size_t)x->nwl, sizeof *m, cmp_i32);
    int32_t n = 0;
    for (int32_t k = 0; k < x->nwl; k++)
        if (n == 0 || m[k] != m[n - 1]) m[n++] = m[k];
    *marks = m;
    *nm = n;
    const mesh_flat *f = x->f;
    int32_t nt = f->tattr ? f->ntris : 0;
    double *a = mesh_xmalloc((size_t)nt + 1, sizeof(double));
    if (nt) memcpy(a, f->tattr, (size_t)nt * sizeof(double));
    qsort(a, (size_t)nt, sizeof *a, cmp_dbl);
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
        const int32_t *hit = bsearch(&m, x->curve_mark, (size_t)nmarks, sizeof m, cmp_i32);
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
                bsearch(&f->tattr[t], x->surf_attr, (size_t)x->nsurf, sizeof(double), cmp_dbl);
            if (!hit) MESH_BUG("xview: attribute %g of no group", f->tattr[t]);
            grp[t] = (int32_t)(hit - x->surf_attr);
        }
    }
    x->ntblk = sort_by_group(x->tperm, f->ntris, grp, x->nsurf);
    free(grp);
}

void mesh_xview_free(mesh_xview *x) {
    free(x->nb);
    free(x->gnb);
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
