/* pcdm_flat.c: a deterministic part's subdomain meshes as one rank part, and the mesh hash.
 *
 * Merge (pcdm_det_take).  The deterministic mode keeps one mesh per subdomain; the output layer
 * (pout.h) takes one part per rank.  The meshes come from the same coarse CDT, so their first
 * ninput vertices (the augmented PSLG's) are the same and keep their numbers.  Any other vertex
 * two subdomains of this rank share lies on their interface, is an endpoint of an interface
 * subsegment in both meshes and has bit-equal coordinates there (dyadic splits): such
 * candidates are merged through a hash of their coordinate bits; every other vertex is
 * appended.  An interface subsegment both subdomains list is kept once, and the triangle edges
 * on it are no longer open.  Meshes are moved out one at a time (mesh_take_flat) and appended,
 * so the rank never holds its mesh twice over.
 *
 * Hash (pcdm_flat_hash).  Each triangle is hashed from its vertices' coordinate bits, rotated to
 * start at the smallest (x, y) while keeping counter-clockwise order; the triangle hashes are
 * summed mod 2^64.  The sum is independent of numbering and of how the triangles are split among
 * ranks, so ranks sum their parts' hashes with one reduction.
 */
#include "pcdm/pcdm_impl.h"

#include "base/base.h"

#include <stdlib.h>
#include <string.h>

/* ---- the mesh hash ------------------------------------------------------------------------- */

uint64_t pcdm_flat_hash(const mesh_flat *f) {
    uint64_t sum = 0;
    for (int32_t t = 0; t < f->ntris; t++) {
        const int32_t *v = f->tri + 3 * (size_t)t;
        int first = 0;
        for (int j = 1; j < 3; j++) {
            const double *a = f->xy + 2 * (size_t)v[j], *b = f->xy + 2 * (size_t)v[first];
            if (a[0] < b[0] || (a[0] == b[0] && a[1] < b[1])) first = j;
        }
        uint64_t h = 0x243f6a8885a308d3ULL;
        for (int j = 0; j < 3; j++) {
            const double *a = f->xy + 2 * (size_t)v[(first + j) % 3];
            h = mesh_hash64(h ^ mesh_dbits(a[0]));
            h = mesh_hash64(h ^ (mesh_dbits(a[1]) * 0x9e3779b97f4a7c15ULL));
        }
        sum += h;
    }
    return sum;
}

/* ---- merge --------------------------------------------------------------------------------- */

/* Open-addressing table of int32 ids (-1: empty); keys are compared by the caller's test. */
typedef struct id_table {
    int32_t *slot;
    uint64_t mask;
} id_table;

static void table_init(id_table *t, int64_t n) {
    uint64_t cap = 16;
    while (cap < 2 * (uint64_t)n + 16)
        cap *= 2;
    t->slot = mesh_xmalloc(cap, sizeof(int32_t));
    for (uint64_t i = 0; i < cap; i++)
        t->slot[i] = -1;
    t->mask = cap - 1;
}

static uint64_t pt_key(const double *p) {
    return mesh_hash64(mesh_dbits(p[0]) * 0x9e3779b97f4a7c15ULL ^ mesh_hash64(mesh_dbits(p[1])));
}

static uint64_t pair_key(int32_t a, int32_t b) {
    if (a > b) {
        int32_t t = a;
        a = b;
        b = t;
    }
    return mesh_hash64((uint64_t)(uint32_t)a << 32 | (uint32_t)b);
}

/* The merged vertex with p's coordinate bits, or -1; *at gets the slot to fill. */
static int32_t vfind(const id_table *t, const double *xy, const double *p, uint64_t *at) {
    uint64_t i = pt_key(p) & t->mask;
    for (; t->slot[i] >= 0; i = (i + 1) & t->mask) {
        const double *q = xy + 2 * (size_t)t->slot[i];
        if (mesh_dbits(q[0]) == mesh_dbits(p[0]) && mesh_dbits(q[1]) == mesh_dbits(p[1]))
            return t->slot[i];
    }
    *at = i;
    return -1;
}

/* The merged segment {a, b} (either direction), or -1; *at gets the slot to fill. */
static int32_t sfind(const id_table *t, const int32_t *seg, int32_t a, int32_t b, uint64_t *at) {
    uint64_t i = pair_key(a, b) & t->mask;
    for (; t->slot[i] >= 0; i = (i + 1) & t->mask) {
        const int32_t *s = seg + 2 * (size_t)t->slot[i];
        if ((s[0] == a && s[1] == b) || (s[0] == b && s[1] == a)) return t->slot[i];
    }
    *at = i;
    return -1;
}

void pcdm_det_take(pcdm_part *p, mesh_flat *f, uint8_t **artificial, int32_t **tsub,
                   uint8_t **topen) {
    int32_t nm = pcdm_det_nmesh(p), nboundary = p->d->nboundary;
    memset(f, 0, sizeof *f);
    if (nm == 1) { /* one subdomain: moved as it is (the memory peak of the asynchronous mode) */
        int32_t sub;
        mesh *m = pcdm_det_mesh(p, 0, &sub);
        uint8_t *a = mesh_xmalloc((size_t)m->ss_live + 1, 1);
        int32_t k = 0;
        for (int32_t r = 0; r < m->nss; r++)
            if (m->ss[r].level != -2) a[k++] = m->ss[r].seg >= nboundary;
        mesh_take_flat(m, f, topen);
        f->trank = mesh_xmalloc((size_t)f->ntris + 1, sizeof(int32_t));
        for (int32_t t = 0; t < f->ntris; t++)
            f->trank[t] = p->rank;
        if (tsub) {
            *tsub = mesh_xmalloc((size_t)f->ntris + 1, sizeof(int32_t));
            for (int32_t t = 0; t < f->ntris; t++)
                (*tsub)[t] = sub;
        }
        *artificial = a;
        return;
    }
    int64_t ncand = 0, nseg_if = 0;
    for (int32_t i = 0; i < nm; i++) {
        int32_t sub;
        const mesh *m = pcdm_det_mesh(p, i, &sub);
        for (int32_t r = 0; r < m->nss; r++)
            if (m->ss[r].level != -2 && m->siface[m->ss[r].seg]) nseg_if++;
    }
    ncand = 2 * nseg_if;
    id_table vt, st;
    table_init(&vt, ncand);
    table_init(&st, nseg_if);
    uint8_t *art = NULL, *open = NULL, *dup = NULL;
    int32_t *ts = NULL;
    int64_t nv = 0, nt = 0, ns = 0;
    for (int32_t i = 0; i < nm; i++) {
        int32_t sub;
        mesh *m = pcdm_det_mesh(p, i, &sub);
        int32_t ninput = m->ninput;
        uint8_t *cand = mesh_xcalloc((size_t)m->nv + 1, 1);
        uint8_t *a = mesh_xmalloc((size_t)m->ss_live + 1, 1);
        int32_t k = 0;
        for (int32_t r = 0; r < m->nss; r++) { /* mesh_take_flat's subsegment order */
            const mesh_subseg *s = &m->ss[r];
            if (s->level == -2) continue;
            a[k++] = s->seg >= nboundary;
            if (m->siface[s->seg]) cand[s->u] = cand[s->v] = 1;
        }
        mesh_flat g;
        uint8_t *gopen = NULL;
        mesh_take_flat(m, &g, topen ? &gopen : NULL);
        if (i == 0) {
            f->scale_exp = g.scale_exp;
            nv = ninput;
        }
        /* vertices */
        f->xy = mesh_xrealloc(f->xy, 2 * ((size_t)nv + (size_t)g.nverts) + 1, sizeof(double));
        f->vmarker = mesh_xrealloc(f->vmarker, (size_t)nv + (size_t)g.nverts + 1, sizeof(int32_t));
        if (i == 0) {
            memcpy(f->xy, g.xy, 2 * (size_t)ninput * sizeof(double));
            memcpy(f->vmarker, g.vmarker, (size_t)ninput * sizeof(int32_t));
        }
        int32_t *map = mesh_xmalloc((size_t)g.nverts + 1, sizeof(int32_t));
        for (int32_t v = 0; v < g.nverts; v++) {
            if (v < ninput) {
                map[v] = v;
                continue;
            }
            uint64_t at = 0;
            int32_t w = cand[v] ? vfind(&vt, f->xy, g.xy + 2 * (size_t)v, &at) : -1;
            if (w < 0) {
                w = (int32_t)nv++;
                f->xy[2 * (size_t)w] = g.xy[2 * (size_t)v];
                f->xy[2 * (size_t)w + 1] = g.xy[2 * (size_t)v + 1];
                f->vmarker[w] = g.vmarker[v];
                if (cand[v]) vt.slot[at] = w;
            }
            map[v] = w;
        }
        /* triangles */
        f->tri = mesh_xrealloc(f->tri, 3 * ((size_t)nt + (size_t)g.ntris) + 1, sizeof(int32_t));
        ts = mesh_xrealloc(ts, (size_t)nt + (size_t)g.ntris + 1, sizeof(int32_t));
        if (g.tattr || f->tattr) {
            f->tattr = mesh_xrealloc(f->tattr, (size_t)nt + (size_t)g.ntris + 1, sizeof(double));
            for (int32_t t = 0; t < g.ntris; t++)
                f->tattr[nt + t] = g.tattr ? g.tattr[t] : 0;
        }
        if (topen) {
            open = mesh_xrealloc(open, (size_t)nt + (size_t)g.ntris + 1, 1);
            memcpy(open + nt, gopen, (size_t)g.ntris);
        }
        for (int32_t t = 0; t < g.ntris; t++) {
            for (int j = 0; j < 3; j++)
                f->tri[3 * (size_t)(nt + t) + j] = map[g.tri[3 * (size_t)t + j]];
            ts[nt + t] = sub;
        }
        nt += g.ntris;
        /* subsegments: an interface one both sides list is kept once */
        size_t sc = (size_t)ns + (size_t)g.nsegs + 1;
        f->seg = mesh_xrealloc(f->seg, 2 * sc, sizeof(int32_t));
        f->smarker = mesh_xrealloc(f->smarker, sc, sizeof(int32_t));
        f->sinterface = mesh_xrealloc(f->sinterface, sc, sizeof(int32_t));
        art = mesh_xrealloc(art, sc, 1);
        dup = mesh_xrealloc(dup, sc, 1);
        for (int32_t s = 0; s < g.nsegs; s++) {
            int32_t u = map[g.seg[2 * (size_t)s]], v = map[g.seg[2 * (size_t)s + 1]];
            uint64_t at = 0;
            if (g.sinterface[s]) {
                int32_t w = sfind(&st, f->seg, u, v, &at);
                if (w >= 0) {
                    dup[w] = 1;
                    continue;
                }
                st.slot[at] = (int32_t)ns;
            }
            f->seg[2 * (size_t)ns] = u;
            f->seg[2 * (size_t)ns + 1] = v;
            f->smarker[ns] = g.smarker[s];
            f->sinterface[ns] = g.sinterface[s];
            art[ns] = a[s];
            dup[ns] = 0;
            ns++;
        }
        free(map);
        free(cand);
        free(a);
        free(gopen);
        mesh_flat_free(&g);
    }
    if (open) /* edges on an interface between two of this rank's subdomains are inner now */
        for (int64_t t = 0; t < nt; t++)
            for (int j = 0; j < 3; j++) {
                if (!(open[t] >> j & 1)) continue;
                uint64_t at = 0;
                int32_t w = sfind(&st, f->seg, f->tri[3 * t + j], f->tri[3 * t + (j + 1) % 3], &at);
                if (w >= 0 && dup[w]) open[t] &= (uint8_t) ~(1u << j);
            }
    f->nverts = (int32_t)nv;
    f->ntris = (int32_t)nt;
    f->nsegs = (int32_t)ns;
    f->xy = mesh_xrealloc(f->xy, 2 * (size_t)nv + 1, sizeof(double));
    f->vmarker = mesh_xrealloc(f->vmarker, (size_t)nv + 1, sizeof(int32_t));
    f->trank = mesh_xmalloc((size_t)nt + 1, sizeof(int32_t));
    for (int64_t t = 0; t < nt; t++)
        f->trank[t] = p->rank;
    free(vt.slot);
    free(st.slot);
    free(dup);
    if (tsub)
        *tsub = ts;
    else
        free(ts);
    if (topen) *topen = open;
    *artificial = art;
}
