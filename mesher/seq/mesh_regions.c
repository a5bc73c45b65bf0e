/* mesh_regions.c: the components of a mesh cut by its constraints (mesh.h).
 *
 * mesh_label_regions labels the components of the live triangles under adjacency across every
 * non-constraint edge (a depth-first flood with an explicit stack), mesh_keep_regions deletes
 * the components not kept (holes, the outside) and repairs adjacency, vertex rows and the
 * subsegment table.  Input regions (mesh_set_regions, Triangle's regional attributes and area
 * bounds) are the components across every edge but an input segment's (artificial interface
 * constraints are crossed), each taking the last region point located in it (exact walk and
 * orient2d; a point on an input segment marks nothing).  Invariant on return: treg holds, for
 * every triangle slot, its region or -1.
 */
#include "mesh_impl.h"

#include "geom/geom.h"

/* ---- regions ------------------------------------------------------------------------------ */

int32_t mesh_label_regions(const mesh *m, int32_t *label) {
    for (int32_t t = 0; t < m->nt; t++)
        label[t] = -1;
    int32_t *stk = mesh_xrealloc(NULL, (size_t)m->nt + 1, sizeof(int32_t));
    int32_t nreg = 0;
    for (int32_t t0 = 0; t0 < m->nt; t0++) {
        if (!mesh_tri_alive(m, t0) || label[t0] >= 0) continue;
        int32_t n = 0;
        stk[n++] = t0;
        label[t0] = nreg;
        while (n > 0) {
            int32_t t = stk[--n];
            for (int j = 0; j < 3; j++) {
                int32_t e = 3 * t + j, nb = m->tn[e];
                if (nb < 0 || mesh_edge_constrained(m, e)) continue;
                if (label[nb / 3] >= 0) continue;
                label[nb / 3] = nreg;
                stk[n++] = nb / 3;
            }
        }
        nreg++;
    }
    free(stk);
    return nreg;
}

void mesh_keep_regions(mesh *m, const int32_t *label, const uint8_t *keep) {
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || label[t] < 0 || keep[label[t]]) continue;
        for (int j = 0; j < 3; j++) {
            int32_t nb = m->tn[3 * t + j];
            if (nb >= 0 && label[nb / 3] >= 0 && keep[label[nb / 3]]) m->tn[nb] = -1;
        }
        mesh_tri_kill(m, t);
    }
    mesh_rebuild_vtri(m);
    mesh_ss_prune(m);
    m->last = -1;
}

/* ---- input regions ------------------------------------------------------------------------ */

/* 1 iff constraint edge e is a piece of a real segment (id below nreal), not an artificial one;
 * an edge with no record counts as real. */
static int input_constraint(const mesh *m, int32_t e, int32_t nreal) {
    if (!mesh_edge_constrained(m, e)) return 0;
    const mesh_subseg *s = mesh_subseg_of_edge(m, e);
    return !s || s->seg < nreal;
}

/* 1 iff vertex v is an endpoint of an input-segment edge (scans the live triangles: region
 * points exactly on a vertex are rare). */
static int on_input_constraint_vertex(const mesh *m, int32_t v, int32_t nreal) {
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        for (int j = 0; j < 3; j++)
            if ((m->tv[3 * t + j] == v || mesh_dest(m, 3 * t + j) == v) &&
                input_constraint(m, 3 * t + j, nreal))
                return 1;
    }
    return 0;
}

/* The triangle region point p marks, or -1 (outside the domain, or on an input segment). */
static int32_t region_seed(mesh *m, const double p[2], int32_t nreal) {
    int32_t t = mesh_locate(m, p, -1);
    if (t < 0) return -1;
    for (int j = 0; j < 3; j++) {
        int32_t e = 3 * t + j, a = m->tv[e], b = mesh_dest(m, e);
        const double *pa = mesh_vertex_xy(m, a), *pb = mesh_vertex_xy(m, b);
        if (pa[0] == p[0] && pa[1] == p[1]) return on_input_constraint_vertex(m, a, nreal) ? -1 : t;
        if (geom_orient2d(pa, pb, p) == 0 && input_constraint(m, e, nreal)) return -1;
    }
    return t;
}

void mesh_set_regions(mesh *m, const pslg *g, int use_area, int32_t nreal) {
    free(m->treg), free(m->reg_attr), free(m->reg_area);
    m->nregion = g->nregions;
    m->treg = mesh_xmalloc((size_t)m->tcap, sizeof(int32_t));
    m->reg_attr = mesh_xmalloc((size_t)g->nregions, sizeof(double));
    m->reg_area = mesh_xmalloc((size_t)g->nregions, sizeof(double));
    for (int32_t i = 0; i < g->nregions; i++) {
        m->reg_attr[i] = g->regions[4 * i + 2];
        double a = g->regions[4 * i + 3];
        m->reg_area[i] = use_area && a > 0 ? a : 0;
    }
    /* components across every edge but the input segments' (interface edges are crossed) */
    int32_t *comp = m->treg, *stk = mesh_xmalloc((size_t)m->nt, sizeof(int32_t));
    for (int32_t t = 0; t < m->nt; t++)
        comp[t] = -1;
    int32_t ncomp = 0;
    for (int32_t t0 = 0; t0 < m->nt; t0++) {
        if (!mesh_tri_alive(m, t0) || comp[t0] >= 0) continue;
        int32_t n = 0;
        stk[n++] = t0;
        comp[t0] = ncomp;
        while (n > 0) {
            int32_t t = stk[--n];
            for (int j = 0; j < 3; j++) {
                int32_t e = 3 * t + j, nb = m->tn[e];
                if (nb < 0 || comp[nb / 3] >= 0 || input_constraint(m, e, nreal)) continue;
                comp[nb / 3] = ncomp;
                stk[n++] = nb / 3;
            }
        }
        ncomp++;
    }
    free(stk);
    int32_t *creg = mesh_xmalloc((size_t)ncomp, sizeof(int32_t));
    for (int32_t c = 0; c < ncomp; c++)
        creg[c] = -1;
    for (int32_t i = 0; i < g->nregions; i++) { /* in file order: the later one wins */
        int32_t t = region_seed(m, g->regions + 4 * i, nreal);
        if (t >= 0) creg[comp[t]] = i;
    }
    for (int32_t t = 0; t < m->nt; t++)
        m->treg[t] = comp[t] >= 0 ? creg[comp[t]] : -1;
    free(creg);
}
