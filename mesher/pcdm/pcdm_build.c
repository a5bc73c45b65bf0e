/* pcdm_build.c: the initial mesh of a subdomain, or of a rank's subdomains, from the
 * decomposition (TR-97-17 section 3: each processor starts from a CDT of its subdomain, whose
 * boundary is made of input segments and the artificial interface segments).
 *
 * Whole (pcdm_build_mesh, the asynchronous mode and inputs with regions): every rank
 * triangulates the same augmented PSLG (input + interface cuts), so the coarse CDT, its vertex
 * numbering and its segment numbering are identical everywhere.  Each region (component under
 * adjacency across non-constraint edges) is mapped to a subdomain exactly: a triangle edge on
 * constraint piece s, directed like s (u -> v of its subsegment record), has the triangle on the
 * left of s, so the region lies in d->seg_sub[2s], otherwise in d->seg_sub[2s + 1].  Every
 * constraint edge of a region must agree (checked), so a wrong decomposition is reported instead
 * of producing a wrong mesh.  Regions of other ranks are deleted (mesh_keep_regions).  The
 * input's regions (-A, --region-areas) are labelled on the whole coarse CDT first
 * (mesh_set_regions crosses the interface edges), identically on every rank, so a region
 * spanning subdomains has one label everywhere; refinement inherits it.
 *
 * Alone (pcdm_build_sub, the rounds): a subdomain's CDT is the CDT of its own boundary pieces
 * and the free vertices inside it (d->vert_sub), numbered in d->g's order (pcdm_sub_map), so
 * building it costs its own size, not the whole input's, and the subdomain mesh holds only its
 * own vertices.  The CDT of that smaller PSLG restricted to the subdomain is the CDT of the
 * subdomain (a CDT restricted to a region its constraint edges bound is the region's CDT), so
 * the mesh is the whole build's up to cocircular ties, the same on every rank and thread.  Its
 * regions are mapped as above; those of no side of the subdomain (other subdomains it
 * surrounds, holes) are deleted, one that has both is an inconsistent decomposition.  The
 * length floor is the input's CDT's (d->floor2), as ./mesh's.  On the decomposition's fast route
 * the subdomain's triangles come with it (d->tri: the triangles of the CDT it was partitioned
 * on, every vertex kept), and the first mesh is made of those (mesh_build_from_triangles, which
 * checks them) instead of being triangulated again; should they be refused, the CDT of the
 * subdomain's PSLG is built as above.
 */
#include "pcdm/pcdm_impl.h"

#include "base/base.h"
#include "seq/kernel.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int pcdm_build_mesh(mesh *m, const pcdm_decomp *d, int rank, int32_t only_sub, int regions,
                    char *err, size_t errlen) {
    mesh_init(m);
    if (mesh_build_cdt(m, &d->g, d->seg_iface, err, errlen) != 0) {
        mesh_free(m);
        return -1;
    }
    if (m->nseg != d->g.nsegs) {
        snprintf(err, errlen, "pcdm: the CDT has %d segments, the decomposition %d", (int)m->nseg,
                 (int)d->g.nsegs);
        mesh_free(m);
        return -1;
    }
    int32_t *label = mesh_xmalloc((size_t)m->nt + 1, sizeof(int32_t));
    int32_t nreg = mesh_label_regions(m, label);
    int32_t *regsub = mesh_xmalloc((size_t)nreg + 1, sizeof(int32_t));
    uint8_t *keep = mesh_xmalloc((size_t)nreg + 1, 1);
    for (int32_t r = 0; r < nreg; r++)
        regsub[r] = -2;
    int bad = 0;
    for (int32_t t = 0; t < m->nt && !bad; t++) {
        if (!mesh_tri_alive(m, t) || !(m->tf[t] & 7)) continue;
        for (int j = 0; j < 3 && !bad; j++) {
            int32_t e = 3 * t + j;
            if (!mesh_edge_constrained(m, e)) continue;
            const mesh_subseg *s = mesh_subseg_of_edge(m, e);
            if (!s || s->seg < 0 || s->seg >= d->g.nsegs) {
                snprintf(err, errlen, "pcdm: constraint edge without a segment record");
                bad = 1;
                break;
            }
            int32_t o = mesh_org(m, e), de = mesh_dest(m, e), side;
            if (o == s->u && de == s->v)
                side = 0; /* triangle (ccw) on the left of the directed segment */
            else if (o == s->v && de == s->u)
                side = 1;
            else {
                snprintf(err, errlen, "pcdm: subsegment record does not match its edge");
                bad = 1;
                break;
            }
            int32_t sub = d->seg_sub[2 * (size_t)s->seg + side];
            if (sub < 0 || sub >= d->nsub) {
                snprintf(err, errlen,
                         "pcdm: a triangle lies outside every subdomain (segment %d, side %d)",
                         (int)s->seg, side);
                bad = 1;
            } else if (regsub[label[t]] == -2) {
                regsub[label[t]] = sub;
            } else if (regsub[label[t]] != sub) {
                snprintf(err, errlen,
                         "pcdm: inconsistent decomposition: one region touches subdomains %d "
                         "and %d",
                         (int)regsub[label[t]], (int)sub);
                bad = 1;
            }
        }
    }
    for (int32_t r = 0; r < nreg && !bad; r++) {
        if (regsub[r] == -2) {
            snprintf(err, errlen, "pcdm: a region of the CDT has no constraint edge");
            bad = 1;
        } else {
            keep[r] = only_sub >= 0 ? regsub[r] == only_sub : d->sub_owner[regsub[r]] == rank;
        }
    }
    /* the length floor from the whole coarse CDT (the same on every rank, and like ./mesh's
     * from the input's extent): computed from one rank's part alone, a part far from the
     * input's largest coordinates got a floor far below ./mesh's and refined a thin region
     * practically forever (a fuzzed point set 8e29 long and 2 wide, at 3 ranks) */
    if (!bad) {
        mesh_fix_length_floor(m);
        if (regions != PCDM_REGIONS_NONE) /* the whole coarse CDT, the same on every rank */
            mesh_set_regions(m, &d->g, regions == PCDM_REGIONS_AREA, d->nboundary);
        mesh_keep_regions(m, label, keep);
    }
    free(label);
    free(regsub);
    free(keep);
    if (bad) {
        mesh_free(m);
        return -1;
    }
    return 0;
}

int32_t pcdm_map_seg_local(const pcdm_sub_map *mp, int32_t g) {
    if (!mp->gs) return g;
    int32_t k = mesh_lower_i32(mp->gs, mp->ns, g);
    return k < mp->ns && mp->gs[k] == g ? k : -1;
}

void pcdm_sub_map_free(pcdm_sub_map *mp) {
    free(mp->gv);
    free(mp->gs);
    memset(mp, 0, sizeof *mp);
}

/* The side of subdomain sub's own segment piece e (a constraint edge of m) that e's triangle
 * lies on, as a subdomain of d (-1: outside the domain); -3 if the records disagree. */
static int32_t edge_side(const mesh *m, const pcdm_decomp *d, const pcdm_sub_map *mp, int32_t e) {
    const mesh_subseg *s = mesh_subseg_of_edge(m, e);
    if (!s || s->seg < 0 || s->seg >= mp->ns) return -3;
    int32_t o = mesh_org(m, e), de = mesh_dest(m, e), side;
    if (o == s->u && de == s->v)
        side = 0; /* triangle (ccw) on the left of the directed segment */
    else if (o == s->v && de == s->u)
        side = 1;
    else
        return -3;
    return d->seg_sub[2 * (size_t)mp->gs[s->seg] + side];
}

/* Subdomain sub's first mesh cut from the decomposition's triangles (d->tri, in d->g's numbers)
 * onto its PSLG lg (local numbers: vs[i] is local vertex i's number in d->g, sorted).  Returns
 * 0, or -1 (m emptied again, fresh from mesh_init) when a triangle has a vertex outside the
 * subdomain or mesh_build_from_triangles refuses them: the caller triangulates lg instead. */
static int from_triangles(mesh *m, const pslg *lg, const uint8_t *iface, const pcdm_decomp *d,
                          int32_t sub, const int32_t *vs, int32_t nv) {
    int32_t a = d->tri_off[sub], n = d->tri_off[sub + 1] - a;
    int32_t *lt = mesh_xmalloc(3 * (size_t)n + 1, sizeof(int32_t));
    int rc = 0;
    for (int64_t i = 0; i < 3 * (int64_t)n && rc == 0; i++) {
        int32_t gv = d->tri[3 * (size_t)a + (size_t)i], l = mesh_lower_i32(vs, nv, gv);
        if (l >= nv || vs[l] != gv) rc = -1;
        lt[i] = l;
    }
    char e[256];
    if (rc == 0) rc = mesh_build_from_triangles(m, lg, iface, n, lt, e, sizeof e);
    free(lt);
    if (rc != 0) {
        mesh_free(m);
        mesh_init(m);
    }
    return rc;
}

int pcdm_build_sub(mesh *m, pcdm_sub_map *mp, const pcdm_decomp *d, int32_t sub, int regions,
                   char *err, size_t errlen) {
    memset(mp, 0, sizeof *mp);
    if (regions != PCDM_REGIONS_NONE || d->floor2 <= 0 || !d->vert_sub)
        return pcdm_build_mesh(m, d, -1, sub, regions, err, errlen);
    const pslg *g = &d->g;
    /* its segments and vertices, in d->g's order (the decomposition's lists) */
    if (!d->sub_seg_off) MESH_BUG("decomposition without its per-subdomain lists");
    const int32_t *sl = d->sub_seg + d->sub_seg_off[sub], *fl = d->sub_vert + d->sub_vert_off[sub];
    int32_t ns = d->sub_seg_off[sub + 1] - d->sub_seg_off[sub], nv = 0;
    int32_t nfree = d->sub_vert_off[sub + 1] - d->sub_vert_off[sub];
    mp->gs = mesh_xmalloc((size_t)ns + 1, sizeof(int32_t));
    memcpy(mp->gs, sl, (size_t)ns * sizeof(int32_t));
    int32_t *vs = mesh_xmalloc(2 * (size_t)ns + (size_t)nfree + 1, sizeof(int32_t));
    for (int32_t i = 0; i < ns; i++) {
        vs[nv++] = g->seg[2 * (size_t)sl[i]];
        vs[nv++] = g->seg[2 * (size_t)sl[i] + 1];
    }
    memcpy(vs + nv, fl, (size_t)nfree * sizeof(int32_t));
    nv += nfree;
    uint64_t *vk = mesh_xmalloc((size_t)nv + 1, sizeof *vk); /* sorted by a radix sort */
    for (int32_t i = 0; i < nv; i++)
        vk[i] = (uint64_t)(uint32_t)vs[i];
    mesh_sort_u64(vk, (size_t)nv);
    for (int32_t i = 0; i < nv; i++)
        vs[i] = (int32_t)vk[i];
    free(vk);
    int32_t k = 0;
    for (int32_t i = 0; i < nv; i++)
        if (k == 0 || vs[i] != vs[k - 1]) vs[k++] = vs[i];
    mp->gv = vs;
    mp->nv = nv = k;
    mp->ns = ns;
    /* the subdomain's PSLG in local numbers */
    pslg lg;
    memset(&lg, 0, sizeof lg);
    lg.nverts = nv;
    lg.xy = mesh_xmalloc(2 * (size_t)nv + 1, sizeof(double));
    lg.vmarker = mesh_xmalloc((size_t)nv + 1, sizeof(int32_t));
    for (int32_t i = 0; i < nv; i++) {
        lg.xy[2 * (size_t)i] = g->xy[2 * (size_t)vs[i]];
        lg.xy[2 * (size_t)i + 1] = g->xy[2 * (size_t)vs[i] + 1];
        lg.vmarker[i] = g->vmarker ? g->vmarker[vs[i]] : 0;
    }
    lg.nsegs = ns;
    lg.seg = mesh_xmalloc(2 * (size_t)ns + 1, sizeof(int32_t));
    lg.smarker = mesh_xmalloc((size_t)ns + 1, sizeof(int32_t));
    uint8_t *iface = mesh_xmalloc((size_t)ns + 1, 1);
    for (int32_t i = 0; i < ns; i++) {
        int32_t s = mp->gs[i];
        for (int j = 0; j < 2; j++)
            lg.seg[2 * (size_t)i + j] = mesh_lower_i32(vs, nv, g->seg[2 * (size_t)s + j]);
        lg.smarker[i] = g->smarker ? g->smarker[s] : 0;
        iface[i] = d->seg_iface[s];
    }
    lg.scale_exp = g->scale_exp;
    snprintf(lg.path, sizeof lg.path, "%s", g->path);
    mesh_init(m);
    if (d->tri && from_triangles(m, &lg, iface, d, sub, vs, nv) == 0) {
        free(lg.xy), free(lg.vmarker), free(lg.seg), free(lg.smarker), free(iface);
        mesh_set_length_floor(m, d->floor2);
        return 0;
    }
    int rc = mesh_build_cdt(m, &lg, iface, err, errlen);
    free(lg.xy), free(lg.vmarker), free(lg.seg), free(lg.smarker), free(iface);
    if (rc == 0 && m->nseg != ns) {
        snprintf(err, errlen, "pcdm: subdomain %d's CDT has %d segments, its PSLG %d", (int)sub,
                 (int)m->nseg, (int)ns);
        rc = -1;
    }
    int32_t *label = NULL, nreg = 0;
    uint8_t *keep = NULL, *out = NULL;
    if (rc == 0) {
        label = mesh_xmalloc((size_t)m->nt + 1, sizeof(int32_t));
        nreg = mesh_label_regions(m, label);
        keep = mesh_xcalloc((size_t)nreg + 1, 1);
        out = mesh_xcalloc((size_t)nreg + 1, 1);
    }
    for (int32_t t = 0; rc == 0 && t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || !(m->tf[t] & 7)) continue;
        for (int j = 0; j < 3 && rc == 0; j++) {
            if (!mesh_edge_constrained(m, 3 * t + j)) continue;
            int32_t side = edge_side(m, d, mp, 3 * t + j);
            if (side == -3) {
                snprintf(err, errlen, "pcdm: subdomain %d: a constraint edge without its record",
                         (int)sub);
                rc = -1;
            } else if (side == sub) {
                keep[label[t]] = 1;
            } else {
                out[label[t]] = 1;
            }
        }
    }
    for (int32_t r = 0; rc == 0 && r < nreg; r++) {
        if (keep[r] && out[r]) {
            snprintf(err, errlen,
                     "pcdm: inconsistent decomposition: a region of subdomain %d touches another",
                     (int)sub);
            rc = -1;
        } else if (!keep[r] && !out[r]) {
            snprintf(err, errlen, "pcdm: a region of the CDT has no constraint edge");
            rc = -1;
        }
    }
    if (rc == 0) {
        mesh_set_length_floor(m, d->floor2);
        mesh_keep_regions(m, label, keep);
    }
    free(label);
    free(keep);
    free(out);
    if (rc != 0) {
        mesh_free(m);
        pcdm_sub_map_free(mp);
    }
    return rc;
}
