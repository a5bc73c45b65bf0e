/* mesh_out.c: a finished mesh handed out (mesh.h): the flat, pointer-free mesh_flat
 * (io/meshio.h) every writer and checker reads -- copied (mesh_to_flat) or taken over in place
 * (mesh_take_flat, which compacts the live real triangles and vertices into the mesh's own
 * arrays and keeps an open-edge mask for the parallel checks) -- and the mesh's measures: area
 * (compensated sum), boundary length and memory.  Ghost and dead triangles are never handed
 * out; triangles stay counter-clockwise, vertices keep their numbers (input first).
 */
#include "mesh_impl.h"

#include "geom/geom.h"

#include <math.h>
#include <string.h>

/* ---- output --------------------------------------------------------------------------------*/

/* The live subsegments into f's seg, smarker and sinterface (room for m->ss_live each), in
 * record order, each with its segment's marker and interface flag. */
static void flat_segments(const mesh *m, mesh_flat *f) {
    int32_t ns = 0;
    for (int32_t r = 0; r < m->nss; r++) {
        const mesh_subseg *s = &m->ss[r];
        if (s->level == -2) continue;
        f->seg[2 * ns] = s->u;
        f->seg[2 * ns + 1] = s->v;
        f->smarker[ns] = m->smarker[s->seg];
        f->sinterface[ns] = m->siface[s->seg];
        ns++;
    }
}

int mesh_to_flat(const mesh *m, mesh_flat *f) {
    memset(f, 0, sizeof *f);
    f->nverts = m->nv;
    f->xy = mesh_xmalloc(2 * (size_t)m->nv, sizeof(double));
    f->vmarker = mesh_xmalloc((size_t)m->nv, sizeof(int32_t));
    int32_t nt = 0;
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t) && mesh_ghost_index(m, t) < 0) nt++;
    f->ntris = nt;
    f->tri = mesh_xmalloc(3 * (size_t)nt, sizeof(int32_t));
    f->nsegs = m->ss_live;
    f->seg = mesh_xmalloc(2 * (size_t)m->ss_live, sizeof(int32_t));
    f->smarker = mesh_xmalloc((size_t)m->ss_live, sizeof(int32_t));
    f->sinterface = mesh_xmalloc((size_t)m->ss_live, sizeof(int32_t));
    flat_segments(m, f);
    memcpy(f->xy, m->xy, 2 * (size_t)m->nv * sizeof(double));
    f->scale_exp = m->scale_exp;
    if (m->treg) f->tattr = mesh_xmalloc((size_t)nt, sizeof(double));
    for (int32_t v = 0; v < m->nv; v++)
        f->vmarker[v] = v < m->ninput     ? (m->in_vmarker ? m->in_vmarker[v] : 0)
                        : m->vseg[v] >= 0 ? m->smarker[m->vseg[v]]
                                          : 0;
    nt = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || mesh_ghost_index(m, t) >= 0) continue;
        memcpy(f->tri + 3 * (size_t)nt, m->tv + 3 * (size_t)t, 3 * sizeof(int32_t));
        if (f->tattr) f->tattr[nt] = m->treg[t] >= 0 ? m->reg_attr[m->treg[t]] : 0;
        nt++;
    }
    return 0;
}

void mesh_take_flat(mesh *m, mesh_flat *f, uint8_t **topen) {
    memset(f, 0, sizeof *f);
    /* scratch first: what remains is coordinates, vertices, triangles, segments */
    mesh_refine_free(m);
    free(m->vtri), free(m->cav), free(m->bnd), free(m->stk), free(m->newt);
    free(m->hpair), free(m->hname), free(m->inc_off), free(m->inc_seg), free(m->corner);
    free(m->seg_nsub);
    m->vtri = m->cav = m->stk = m->newt = m->hpair = m->hname = NULL;
    m->inc_off = m->inc_seg = m->seg_nsub = NULL;
    m->bnd = NULL;
    m->corner = NULL;
    uint8_t *open = topen ? mesh_xmalloc((size_t)m->nlive + 1, 1) : NULL;
    int32_t nt = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || mesh_ghost_index(m, t) >= 0) continue;
        if (nt != t) memmove(m->tv + 3 * (size_t)nt, m->tv + 3 * (size_t)t, 3 * sizeof(int32_t));
        if (m->treg) m->treg[nt] = m->treg[t]; /* compacted too, then turned into tattr */
        if (open)
            open[nt] = (uint8_t)((m->tn[3 * (size_t)t] < 0) | (m->tn[3 * (size_t)t + 1] < 0) << 1 |
                                 (m->tn[3 * (size_t)t + 2] < 0) << 2);
        nt++;
    }
    if (topen) *topen = open;
    free(m->tn), free(m->tf);
    m->tn = NULL;
    m->tf = NULL;
    f->ntris = nt;
    f->tri = mesh_xrealloc(m->tv, 3 * (size_t)nt + 1, sizeof(int32_t));
    m->tv = NULL;
    if (m->treg) { /* attributes in place of the labels (a double each) */
        f->tattr = mesh_xmalloc((size_t)nt, sizeof(double));
        for (int32_t t = 0; t < nt; t++)
            f->tattr[t] = m->treg[t] >= 0 ? m->reg_attr[m->treg[t]] : 0;
    }
    f->nsegs = m->ss_live;
    f->seg = mesh_xmalloc(2 * (size_t)m->ss_live + 1, sizeof(int32_t));
    f->smarker = mesh_xmalloc((size_t)m->ss_live + 1, sizeof(int32_t));
    f->sinterface = mesh_xmalloc((size_t)m->ss_live + 1, sizeof(int32_t));
    flat_segments(m, f);
    int32_t *mk = m->vseg; /* markers over vseg, one int32 each, in place */
    for (int32_t v = 0; v < m->nv; v++)
        mk[v] = v < m->ninput ? (m->in_vmarker ? m->in_vmarker[v] : 0)
                : mk[v] >= 0  ? m->smarker[mk[v]]
                              : 0;
    f->nverts = m->nv;
    f->vmarker = mesh_xrealloc(mk, (size_t)m->nv + 1, sizeof(int32_t));
    f->xy = mesh_xrealloc(m->xy, 2 * (size_t)m->nv + 1, sizeof(double));
    f->scale_exp = m->scale_exp;
    m->vseg = NULL;
    m->xy = NULL;
    mesh_free(m);
}

double mesh_area(const mesh *m) {
    /* doubled areas summed plainly in blocks of 256 slots, the blocks with Neumaier's
     * compensation: accurate for millions of triangles at a fraction of compensating each */
    double a = 0, c = 0;
    const double *xy = m->xy;
    for (int32_t t0 = 0; t0 < m->nt; t0 += 256) {
        int32_t t1 = m->nt - t0 < 256 ? m->nt : t0 + 256;
        double x = 0;
        for (int32_t t = t0; t < t1; t++) {
            if (!mesh_tri_alive(m, t)) continue;
            const int32_t *v = m->tv + 3 * (size_t)t;
            const double *p = xy + 2 * (size_t)v[0], *q = xy + 2 * (size_t)v[1],
                         *r = xy + 2 * (size_t)v[2];
            x += (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
        }
        double s = a + x;
        c += fabs(a) >= fabs(x) ? (a - s) + x : (x - s) + a;
        a = s;
    }
    return 0.5 * (a + c);
}

double mesh_boundary_length(const mesh *m, double *mag) {
    double len = 0, mg = 0;
    for (int32_t v = 0; v < m->nv; v++)
        mg = fmax(mg, fmax(fabs(m->xy[2 * (size_t)v]), fabs(m->xy[2 * (size_t)v + 1])));
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j;
            if (m->tn[e] >= 0) continue;
            const mesh_subseg *s = mesh_subseg_of_edge(m, e);
            if (s && m->siface[s->seg]) continue;
            len +=
                sqrt(geom_dist2(mesh_vertex_xy(m, m->tv[e]), mesh_vertex_xy(m, mesh_dest(m, e))));
        }
    }
    if (mag) *mag = mg;
    return len;
}

size_t mesh_memory_bytes(const mesh *m) {
    size_t b = (size_t)m->vcap * (2 * sizeof(double) + 2 * sizeof(int32_t));
    b += (size_t)m->tcap * (6 * sizeof(int32_t) + 1);
    b += (size_t)m->segcap * (4 * sizeof(int32_t) + 1);
    b += (size_t)m->sscap * sizeof(mesh_subseg) + 2 * (size_t)m->hcap * sizeof(int32_t);
    b += (size_t)m->cavcap * 4 + (size_t)m->bndcap * sizeof(mesh_bedge);
    b += (size_t)(m->stkcap + m->newtcap) * 4;
    if (m->treg) b += (size_t)m->tcap * sizeof(int32_t);
    return b;
}
