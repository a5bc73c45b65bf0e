/* pcdm_flat.c: a deterministic part's subdomain meshes as one rank part, and the mesh hash.
 *
 * Merge (pcdm_det_take).  The deterministic mode keeps one mesh per subdomain; the output layer
 * (pout.h) takes one part per rank.  The meshes come from the same coarse CDT, so their first
 * ninput vertices (the augmented PSLG's) are the same: those any of the rank's meshes holds come
 * first in the part, in the augmented PSLG's order, each named as the input vertex it is
 * (mesh_flat.vin), and the others are left out (the part and the output's passes over it follow
 * the rank's share, not the whole input).  Any other vertex two subdomains of this rank share
 * lies on their interface, is an endpoint of an interface subsegment in both meshes and has
 * bit-equal coordinates there (dyadic splits): such candidates are merged through a hash of
 * their coordinate bits; every other vertex is appended.  An interface subsegment both
 * subdomains list is kept once, and the triangle edges on it are no longer open.  The part is
 * the meshes' vertices and live triangles in mesh order (each mesh in mesh_take_flat's order),
 * so every place in it is known before anything is copied: (1) on the rank's threads, each
 * mesh sheds its scratch, counts its triangles and lists its candidates; (2) one thread numbers
 * the candidates in mesh order (a repeat takes the first one's number: vertex v of mesh i is
 * numbered vbase_i + v - ninput - (repeats of mesh i below v)) and merges the subsegments
 * (O(interface)); (3) on the rank's threads, each mesh writes its triangles, then its vertices,
 * straight into the part and frees each array once read.  The
 * part is the one the meshes merged one after another would give, for any thread count, and
 * the rank holds each triangle about once (the part grows as the meshes go).
 *
 * Hash (pcdm_flat_hash).  Each triangle is hashed from its vertices' coordinate bits, rotated to
 * start at the smallest (x, y) while keeping counter-clockwise order; the triangle hashes are
 * summed mod 2^64.  The sum is independent of numbering and of how the triangles are split among
 * ranks (or a rank's threads), so ranks sum their parts' hashes with one reduction.
 */
#include "pcdm/pcdm_impl.h"

#include "base/base.h"
#include "base/pfor.h"
#include "seq/kernel.h"

#include <stdlib.h>
#include <string.h>

/* ---- the mesh hash ------------------------------------------------------------------------- */

typedef struct hash_job {
    const mesh_flat *f;
    uint64_t sum[MESH_PFOR_MAXTHR];
} hash_job;

/* Part k of pcdm_flat_hash: triangles [a, b). */
static void hash_range(void *arg, int k, int64_t a, int64_t b) {
    hash_job *j = arg;
    const mesh_flat *f = j->f;
    uint64_t sum = 0;
    for (int64_t t = a; t < b; t++)
        sum += meshio_tri_hash(f, t);
    j->sum[k] = sum;
}

uint64_t pcdm_flat_hash(const mesh_flat *f, int threads) {
    hash_job j = {.f = f};
    int n = mesh_pfor_ranges(f->ntris, threads, 1 << 14, hash_range, &j);
    uint64_t sum = 0; /* mod 2^64: the same for any split */
    for (int k = 0; k < n; k++)
        sum += j.sum[k];
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

/* The entry whose point (xy[2 id], xy[2 id + 1]) has p's coordinate bits, or -1; *at gets the
 * slot to fill. */
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

/* One subdomain mesh in the merge. */
typedef struct take_mesh {
    mesh *m;
    const pcdm_sub_map *map; /* its input vertices in d->g (identity when gv is NULL) */
    const int32_t *gpos;     /* d->g's vertices: their numbers in the part (-1: in no mesh) */
    int32_t sub;
    int32_t ncand, *cand; /* its non-input interface vertices, ascending */
    int32_t ndup;         /* of those, the ones an earlier candidate already gave a number */
    int32_t *dv, *did;    /* ascending: those vertices, and the numbers they take */
    int64_t vbase;        /* merged number of its first own non-input vertex */
    int64_t tbase, nt;    /* its first merged triangle, its triangles */
} take_mesh;

typedef struct take_ctx {
    take_mesh *tm;
    int32_t ninput;
    mesh_flat *f;
    int32_t *ts;   /* or NULL */
    uint8_t *open; /* or NULL */
    id_table st;   /* the merged subsegments */
    const uint8_t *dup;
} take_ctx;

/* A triangle slot mesh_take_flat hands out: live, no ghost. */
static int slot_real(const mesh *m, int32_t t) {
    const int32_t *v = m->tv + 3 * (size_t)t;
    return v[0] != MESH_DEAD && v[0] != MESH_GHOST && v[1] != MESH_GHOST && v[2] != MESH_GHOST;
}

/* Item i of the first parallel pass: mesh i's scratch freed (what the merge does not read:
 * refinement queues, cavity buffers, vertex-to-triangle links, triangle flags, hash tables),
 * its triangles counted, its candidates listed. */
static void take_scan(void *arg, int64_t i) {
    take_ctx *c = arg;
    take_mesh *tm = &c->tm[i];
    mesh *m = tm->m;
    mesh_refine_free(m);
    free(m->vtri), free(m->cav), free(m->bnd), free(m->stk), free(m->newt), free(m->tf);
    free(m->hpair), free(m->hname), free(m->inc_off), free(m->inc_seg), free(m->corner);
    free(m->seg_nsub);
    m->vtri = m->cav = m->stk = m->newt = m->hpair = m->hname = NULL;
    m->inc_off = m->inc_seg = m->seg_nsub = NULL;
    m->bnd = NULL;
    m->tf = m->corner = NULL;
    int64_t nt = 0;
    for (int32_t t = 0; t < m->nt; t++)
        nt += slot_real(m, t);
    tm->nt = nt;
    int32_t n = 0;
    int32_t *cv = mesh_xmalloc(2 * (size_t)m->nss + 1, sizeof(int32_t));
    for (int32_t r = 0; r < m->nss; r++) {
        const mesh_subseg *s = &m->ss[r];
        if (s->level == -2 || !m->siface[s->seg]) continue;
        if (s->u >= m->ninput) cv[n++] = s->u;
        if (s->v >= m->ninput) cv[n++] = s->v;
    }
    qsort(cv, (size_t)n, sizeof *cv, mesh_cmp_i32);
    int32_t k = 0;
    for (int32_t j = 0; j < n; j++)
        if (k == 0 || cv[j] != cv[k - 1]) cv[k++] = cv[j];
    tm->ncand = k;
    tm->cand = cv;
}

/* The merged number of vertex v of tm (its dups decided up to v): an input vertex of the mesh
 * (a d->g vertex) takes its place among the part's d->g vertices, the others follow. */
static int32_t merged_id(const take_mesh *tm, int32_t v) {
    int32_t nin = tm->m->ninput;
    if (v < nin) return tm->gpos[pcdm_map_vert_global(tm->map, v)];
    int32_t k = mesh_lower_i32(tm->dv, tm->ndup, v);
    if (k < tm->ndup && tm->dv[k] == v) return tm->did[k];
    return (int32_t)(tm->vbase + (v - nin) - k);
}

/* Item i of the second parallel pass: mesh i's triangles (with their open-edge bits), then its
 * vertices written at its place in the merged part, each array of the mesh freed once read, so
 * the rank holds each triangle about once while the part grows. */
static void take_copy(void *arg, int64_t i) {
    take_ctx *c = arg;
    take_mesh *tm = &c->tm[i];
    mesh *m = tm->m;
    mesh_flat *f = c->f;
    int32_t ninput = m->ninput;
    int32_t *map = mesh_xmalloc((size_t)m->nv + 1, sizeof(int32_t));
    for (int32_t v = 0, k = 0; v < m->nv; v++) {
        if (v < ninput)
            map[v] = tm->gpos[pcdm_map_vert_global(tm->map, v)];
        else if (k < tm->ndup && tm->dv[k] == v)
            map[v] = tm->did[k++];
        else
            map[v] = (int32_t)(tm->vbase + (v - ninput) - k);
    }
    int64_t n = tm->tbase;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!slot_real(m, t)) continue;
        int32_t *out = f->tri + 3 * (size_t)n;
        for (int j = 0; j < 3; j++)
            out[j] = map[m->tv[3 * (size_t)t + j]];
        if (f->tattr) f->tattr[n] = m->treg && m->treg[t] >= 0 ? m->reg_attr[m->treg[t]] : 0;
        if (c->ts) c->ts[n] = tm->sub;
        if (c->open) {
            uint8_t o = 0;
            for (int j = 0; j < 3; j++) {
                if (m->tn[3 * (size_t)t + j] >= 0) continue;
                /* an edge on an interface between two of this rank's subdomains is inner now */
                uint64_t at = 0;
                int32_t s = sfind(&c->st, f->seg, out[j], out[(j + 1) % 3], &at);
                if (s < 0 || !c->dup[s]) o |= (uint8_t)(1u << j);
            }
            c->open[n] = o;
        }
        n++;
    }
    free(m->tv), free(m->tn), free(m->treg);
    m->tv = m->tn = m->treg = NULL;
    for (int32_t v = ninput, k = 0; v < m->nv; v++) { /* d->g's vertices: pcdm_det_take */
        int32_t w = map[v];
        if (k < tm->ndup && tm->dv[k] == v) { /* a vertex an earlier candidate gave */
            k++;
            continue;
        }
        f->xy[2 * (size_t)w] = m->xy[2 * (size_t)v];
        f->xy[2 * (size_t)w + 1] = m->xy[2 * (size_t)v + 1];
        f->vmarker[w] = m->vseg[v] >= 0 ? m->smarker[m->vseg[v]] : 0;
    }
    free(map);
    mesh_free(m);
}

void pcdm_det_take(pcdm_part *p, mesh_flat *f, uint8_t **artificial, int32_t **tsub,
                   uint8_t **topen) {
    int32_t nm = pcdm_det_nmesh(p), nboundary = p->d->nboundary;
    int T = p->threads > 1 ? p->threads : 1;
    memset(f, 0, sizeof *f);
    int32_t sub0 = -1;
    const pcdm_sub_map *map0 = NULL;
    mesh *m0 = nm == 1 ? pcdm_det_mesh(p, 0, &sub0, &map0) : NULL;
    if (m0 && !map0->gv) { /* one subdomain numbered as d->g: moved as it is (the memory peak of
                            * the asynchronous mode) */
        uint8_t *a = mesh_xmalloc((size_t)m0->ss_live + 1, 1);
        int32_t k = 0;
        for (int32_t r = 0; r < m0->nss; r++)
            if (m0->ss[r].level != -2) a[k++] = m0->ss[r].seg >= nboundary;
        mesh_take_flat(m0, f, topen);
        if (tsub) {
            *tsub = mesh_xmalloc((size_t)f->ntris + 1, sizeof(int32_t));
            for (int32_t t = 0; t < f->ntris; t++)
                (*tsub)[t] = sub0;
        }
        *artificial = a;
        return;
    }
    take_ctx c;
    memset(&c, 0, sizeof c);
    c.tm = mesh_xcalloc((size_t)nm + 1, sizeof(take_mesh));
    c.f = f;
    for (int32_t i = 0; i < nm; i++)
        c.tm[i].m = pcdm_det_mesh(p, i, &c.tm[i].sub, &c.tm[i].map);
    const pslg *g = &p->d->g;
    /* the part's first vertices are the d->g vertices its meshes hold, in d->g's order (the
     * others are in no triangle of this rank: left out), every mesh's Steiner vertices follow */
    int32_t *gpos = mesh_xmalloc((size_t)g->nverts + 1, sizeof(int32_t));
    for (int32_t v = 0; v < g->nverts; v++)
        gpos[v] = -1;
    for (int32_t i = 0; i < nm; i++) {
        const pcdm_sub_map *mp = c.tm[i].map;
        int32_t n = mp->gv ? mp->nv : g->nverts;
        for (int32_t v = 0; v < n; v++)
            gpos[pcdm_map_vert_global(mp, v)] = 0;
        c.tm[i].gpos = gpos;
    }
    int32_t ninput = 0;
    for (int32_t v = 0; v < g->nverts; v++)
        if (gpos[v] == 0) gpos[v] = ninput++;
    c.ninput = ninput;
    mesh_pfor_items(nm, T, take_scan, &c);

    /* vertices: numbers in mesh order, a candidate seen before (bit-equal coordinates) takes
     * the earlier one's; records (mesh, vertex) of first sightings in a coordinate table */
    int64_t ncand = 0, nv = ninput, nt = 0;
    for (int32_t i = 0; i < nm; i++)
        ncand += c.tm[i].ncand;
    id_table vt;
    table_init(&vt, ncand);
    int32_t *rec = mesh_xmalloc(2 * (size_t)ncand + 1, sizeof(int32_t)); /* (mesh, vertex) */
    double *rxy = mesh_xmalloc(2 * (size_t)ncand + 1, sizeof(double));
    int32_t nrec = 0;
    for (int32_t i = 0; i < nm; i++) {
        take_mesh *tm = &c.tm[i];
        const mesh *m = tm->m;
        if (tm->map->gv ? m->ninput != tm->map->nv : m->ninput != g->nverts)
            MESH_BUG("subdomain %d's mesh has %d input vertices, its map %d", (int)tm->sub,
                     (int)m->ninput, (int)(tm->map->gv ? tm->map->nv : g->nverts));
        tm->vbase = nv;
        tm->dv = mesh_xmalloc((size_t)tm->ncand + 1, sizeof(int32_t));
        tm->did = mesh_xmalloc((size_t)tm->ncand + 1, sizeof(int32_t));
        for (int32_t j = 0; j < tm->ncand; j++) {
            int32_t v = tm->cand[j];
            uint64_t at = 0;
            int32_t w = vfind(&vt, rxy, m->xy + 2 * (size_t)v, &at);
            if (w >= 0) {
                tm->dv[tm->ndup] = v;
                tm->did[tm->ndup++] = merged_id(&c.tm[rec[2 * (size_t)w]], rec[2 * (size_t)w + 1]);
                continue;
            }
            rec[2 * (size_t)nrec] = i;
            rec[2 * (size_t)nrec + 1] = v;
            rxy[2 * (size_t)nrec] = m->xy[2 * (size_t)v];
            rxy[2 * (size_t)nrec + 1] = m->xy[2 * (size_t)v + 1];
            vt.slot[at] = nrec++;
        }
        nv += (m->nv - m->ninput) - tm->ndup;
        tm->tbase = nt;
        nt += tm->nt;
    }
    free(vt.slot);
    free(rec);
    free(rxy);

    /* subsegments in mesh order (mesh_take_flat's order in each): an interface one both sides
     * list is kept once */
    int64_t nss = 0;
    for (int32_t i = 0; i < nm; i++)
        nss += c.tm[i].m->ss_live;
    table_init(&c.st, nss);
    f->seg = mesh_xmalloc(2 * (size_t)nss + 1, sizeof(int32_t));
    f->smarker = mesh_xmalloc((size_t)nss + 1, sizeof(int32_t));
    f->sinterface = mesh_xmalloc((size_t)nss + 1, sizeof(int32_t));
    uint8_t *art = mesh_xmalloc((size_t)nss + 1, 1), *dup = mesh_xmalloc((size_t)nss + 1, 1);
    int64_t ns = 0;
    int any_reg = 0;
    for (int32_t i = 0; i < nm; i++) {
        const take_mesh *tm = &c.tm[i];
        const mesh *m = tm->m;
        any_reg |= m->treg != NULL;
        for (int32_t r = 0; r < m->nss; r++) {
            const mesh_subseg *s = &m->ss[r];
            if (s->level == -2) continue;
            int32_t u = merged_id(tm, s->u), v = merged_id(tm, s->v);
            if (m->siface[s->seg]) {
                uint64_t at = 0;
                int32_t w = sfind(&c.st, f->seg, u, v, &at);
                if (w >= 0) {
                    dup[w] = 1;
                    continue;
                }
                c.st.slot[at] = (int32_t)ns;
            }
            f->seg[2 * (size_t)ns] = u;
            f->seg[2 * (size_t)ns + 1] = v;
            f->smarker[ns] = m->smarker[s->seg];
            f->sinterface[ns] = m->siface[s->seg];
            art[ns] = pcdm_map_seg_global(tm->map, s->seg) >= nboundary;
            dup[ns] = 0;
            ns++;
        }
    }
    c.dup = dup;

    /* vertices and triangles: each mesh at its place, on the rank's threads */
    f->scale_exp = nm ? c.tm[0].m->scale_exp : 0;
    f->nverts = (int32_t)nv;
    f->ntris = (int32_t)nt;
    f->nsegs = (int32_t)ns;
    f->xy = mesh_xmalloc(2 * (size_t)nv + 1, sizeof(double));
    f->vmarker = mesh_xmalloc((size_t)nv + 1, sizeof(int32_t));
    f->tri = mesh_xmalloc(3 * (size_t)nt + 1, sizeof(int32_t));
    if (any_reg) f->tattr = mesh_xmalloc((size_t)nt + 1, sizeof(double));
    c.ts = tsub ? mesh_xmalloc((size_t)nt + 1, sizeof(int32_t)) : NULL;
    c.open = topen ? mesh_xmalloc((size_t)nt + 1, 1) : NULL;
    f->nvin = ninput;
    f->vin = mesh_xmalloc((size_t)ninput + 1, sizeof(int32_t));
    int32_t nin = p->d->ninput_verts; /* d->g's first vertices are the input's */
    for (int32_t v = 0; v < g->nverts; v++) {
        int32_t w = gpos[v];
        if (w < 0) continue;
        f->xy[2 * (size_t)w] = g->xy[2 * (size_t)v];
        f->xy[2 * (size_t)w + 1] = g->xy[2 * (size_t)v + 1];
        f->vmarker[w] = g->vmarker ? g->vmarker[v] : 0;
        f->vin[w] = v < nin ? v : -1;
    }
    mesh_pfor_items(nm, T, take_copy, &c);
    free(gpos);

    for (int32_t i = 0; i < nm; i++) {
        free(c.tm[i].cand);
        free(c.tm[i].dv);
        free(c.tm[i].did);
    }
    free(c.tm);
    free(c.st.slot);
    free(dup);
    if (tsub) *tsub = c.ts;
    if (topen) *topen = c.open;
    *artificial = art;
}
