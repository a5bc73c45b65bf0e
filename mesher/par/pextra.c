/* pextra.c: .edge, .neigh, -o2 and Gmsh output of a distributed mesh (pextra.h).
 *
 * Algorithm.  Each rank builds its part's edge topology (mesh_xview_topo: local neighbours,
 * edges, open edges, segment markers).  (1) Every open edge goes to a rendezvous rank (the hash
 * of its two endpoints' coordinate bits, -0.0 folded onto +0.0; endpoints ordered by bits) with
 * this rank's half-edge and the global number of its triangle.  Where two ranks sent the same
 * edge, each learns the other's rank, half-edge and triangle number: the edge is an interface
 * edge (neighbour across = that triangle; written by the lower rank only); an open edge nobody
 * else sent is on the mesh boundary.  (2) Edges each rank writes are numbered by an MPI_Exscan
 * of the counts (so are the Gmsh line elements); the writer of an interface edge sends its
 * number to the other side (point to point through par_exchange), so a midpoint on an interface
 * has one number on both sides.  (3) The Gmsh physical groups (distinct line markers and
 * regional attributes) are gathered from every rank (a few values each), the block counts and
 * the bounding box reduced.  Then io/xwrite.c writes each file collectively.
 * Invariants: every edge is written by exactly one rank; data moved is O(part boundary) plus the
 * group values; every rank returns the same status.
 */
#include "par/pextra.h"

#include "base/base.h"
#include "check/pexchange.h"
#include "check/ptopo.h"
#include "io/oset.h"
#include "io/ptext.h"
#include "io/xwrite.h"
#include "rt.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct eq { /* an open edge, to its rendezvous */
    double x[4];
    int64_t tri;
    int32_t rank, h;
} eq;
_Static_assert(sizeof(eq) == 48, "eq: no padding");

typedef struct er { /* rendezvous -> holder: the other side */
    int64_t otri;
    int32_t h, orank, oh, pad;
} er;
_Static_assert(sizeof(er) == 24, "er: no padding");

typedef struct en { /* writer -> other side: the edge's number */
    int64_t egid;
    int32_t h, pad;
} en;
_Static_assert(sizeof(en) == 16, "en: no padding");

static int cmp_eq(const void *pa, const void *pb) {
    const eq *a = pa, *b = pb;
    for (int k = 0; k < 4; k++) {
        uint64_t u = mesh_dbits(a->x[k]), v = mesh_dbits(b->x[k]);
        if (u != v) return u < v ? -1 : 1;
    }
    return (a->rank > b->rank) - (a->rank < b->rank);
}

static int same_eq(const eq *a, const eq *b) {
    for (int k = 0; k < 4; k++)
        if (mesh_dbits(a->x[k]) != mesh_dbits(b->x[k])) return 0;
    return 1;
}

/* Step (1): the other side of every interface edge.  Fills oside (per local edge: the other
 * rank and its half-edge, or -1). */
static void match_open_edges(mesh_xview *x, int32_t *orank, int32_t *ohe) {
    const mesh_flat *f = x->f;
    int rank = rt_rank(), P = rt_size();
    int64_t n = 0;
    for (int32_t e = 0; e < x->ne; e++)
        n += (x->eflag[e] & XE_OPEN) != 0;
    eq *q = mesh_xmalloc((size_t)n + 1, sizeof(eq));
    int *dest = mesh_xmalloc((size_t)n + 1, sizeof(int));
    n = 0;
    for (int32_t e = 0; e < x->ne; e++) {
        if (!(x->eflag[e] & XE_OPEN)) continue;
        int32_t h = x->ehe[e];
        const int32_t *t = f->tri + 3 * (size_t)(h / 3);
        const double *p = f->xy + 2 * (size_t)t[(h % 3 + 1) % 3],
                     *r = f->xy + 2 * (size_t)t[(h % 3 + 2) % 3];
        if (mesh_dbits(p[0]) > mesh_dbits(r[0]) ||
            (mesh_dbits(p[0]) == mesh_dbits(r[0]) && mesh_dbits(p[1]) > mesh_dbits(r[1]))) {
            const double *s = p;
            p = r;
            r = s;
        }
        q[n] = (eq){{p[0], p[1], r[0], r[1]}, x->tfirst + h / 3, rank, h};
        uint64_t k =
            mesh_hash64(mesh_dbits(p[0]) ^
                        mesh_hash64(mesh_dbits(p[1]) ^
                                    mesh_hash64(mesh_dbits(r[0]) ^ mesh_hash64(mesh_dbits(r[1])))));
        dest[n++] = (int)(k % (uint64_t)P);
    }
    int64_t nr;
    eq *R = par_exchange(q, sizeof(eq), dest, n, &nr);
    qsort(R, (size_t)nr, sizeof *R, cmp_eq);
    er *rep = mesh_xmalloc((size_t)nr + 1, sizeof(er));
    int *rdest = mesh_xmalloc((size_t)nr + 1, sizeof(int));
    int64_t nrep = 0;
    for (int64_t i = 0; i < nr;) {
        int64_t j = i + 1;
        while (j < nr && same_eq(&R[j], &R[i]))
            j++;
        if (j - i == 2 && R[i].rank != R[i + 1].rank) /* two sides: an interface edge */
            for (int s = 0; s < 2; s++) {
                const eq *me = &R[i + s], *ot = &R[i + 1 - s];
                rep[nrep] = (er){ot->tri, me->h, ot->rank, ot->h, 0};
                rdest[nrep++] = me->rank;
            }
        i = j;
    }
    int64_t nb;
    er *back = par_exchange(rep, sizeof(er), rdest, nrep, &nb);
    for (int64_t i = 0; i < nb; i++) {
        mesh_xview_set_remote(x, back[i].h, rank, back[i].orank, back[i].otri);
        orank[x->eid[back[i].h]] = back[i].orank;
        ohe[x->eid[back[i].h]] = back[i].oh;
    }
    free(q);
    free(dest);
    free(R);
    free(rep);
    free(rdest);
    free(back);
}

/* Step (2): global edge and line numbers; the interface edges' numbers to the other side. */
static void number_edges(mesh_xview *x, const int32_t *orank, const int32_t *ohe) {
    MPI_Comm c = rt_app_comm();
    int rank = rt_rank();
    int64_t cnt[2] = {x->nwe, x->nwl}, first[2] = {0, 0}, tot[2];
    MESH_MPI(MPI_Exscan(cnt, first, 2, MPI_INT64_T, MPI_SUM, c));
    if (rank == 0) first[0] = first[1] = 0;
    MESH_MPI(MPI_Allreduce(cnt, tot, 2, MPI_INT64_T, MPI_SUM, c));
    x->efirst = first[0];
    x->lfirst = first[1];
    x->etot = tot[0];
    x->ltot = tot[1];
    for (int32_t k = 0; k < x->nwe; k++)
        x->egid[x->we[k]] = x->efirst + k;
    int64_t n = 0;
    for (int32_t k = 0; k < x->nwe; k++)
        n += orank[x->we[k]] >= 0;
    en *q = mesh_xmalloc((size_t)n + 1, sizeof(en));
    int *dest = mesh_xmalloc((size_t)n + 1, sizeof(int));
    n = 0;
    for (int32_t k = 0; k < x->nwe; k++) {
        int32_t e = x->we[k];
        if (orank[e] < 0) continue;
        q[n] = (en){x->egid[e], ohe[e], 0};
        dest[n++] = orank[e];
    }
    int64_t nb;
    en *back = par_exchange(q, sizeof(en), dest, n, &nb);
    for (int64_t i = 0; i < nb; i++)
        x->egid[x->eid[back[i].h]] = back[i].egid;
    free(q);
    free(dest);
    free(back);
}

/* Collective.  Gathers every rank's n values of sz bytes (sorted distinct) into one sorted
 * distinct array (*ntot values; free with free()). */
static void *gather_distinct(const void *mine, int32_t n, size_t sz, MPI_Datatype t,
                             int (*cmp)(const void *, const void *), int32_t *ntot) {
    MPI_Comm c = rt_app_comm();
    int P = rt_size(), cnt = n;
    int *cnts = mesh_xmalloc((size_t)P, sizeof(int)),
        *dsp = mesh_xmalloc((size_t)P + 1, sizeof(int));
    MESH_MPI(MPI_Allgather(&cnt, 1, MPI_INT, cnts, 1, MPI_INT, c));
    dsp[0] = 0;
    for (int r = 0; r < P; r++)
        dsp[r + 1] = dsp[r] + cnts[r];
    char *all = mesh_xmalloc((size_t)dsp[P] + 1, sz);
    MESH_MPI(MPI_Allgatherv(mine, cnt, t, all, cnts, dsp, t, c));
    qsort(all, (size_t)dsp[P], sz, cmp);
    int32_t k = 0;
    for (int32_t i = 0; i < dsp[P]; i++)
        if (k == 0 || cmp(all + (size_t)i * sz, all + (size_t)(k - 1) * sz) != 0)
            memmove(all + (size_t)k++ * sz, all + (size_t)i * sz, sz);
    free(cnts);
    free(dsp);
    *ntot = k;
    return all;
}

int par_write_extras(const par_opts *o, meshio_set *set, const pslg *in, const mesh_flat *local,
                     const uint8_t *artificial, const par_numbering *num) {
    const char *prefix = o->out_prefix;
    if (!((prefix && (o->edges || o->neighbors || o->order2)) || o->msh || (o->vtk && o->order2)))
        return 0;
    MPI_Comm c = rt_app_comm();
    int rank = rt_rank();
    mesh_xview x;
    mesh_xview_topo(&x, local, artificial);
    x.gid = num->gid;
    x.nvtot = num->nverts;
    x.ttot = num->ntris;
    x.tfirst = num->tfirst;
    x.nhead = rank == 0 ? num->nin : 0;
    x.hxy = in->xy;
    x.hvmarker = in->vmarker;
    x.vfirst = rank == 0 ? 0 : num->vfirst;
    x.vsel = num->owned;
    x.nsel = num->nowned;
    x.nattr = 0; /* the parallel .node carries no vertex attributes (pout.c) */
    /* the .ele's attribute: the region's with -A, else none, as the linear .ele (pout.c); agreed,
     * a rank may hold nothing */
    int ea = local->tattr ? 1 : 0;
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, &ea, 1, MPI_INT, MPI_MAX, c));
    x.ele_attr = ea;
    int32_t *orank = mesh_xmalloc((size_t)x.ne + 1, sizeof(int32_t));
    int32_t *ohe = mesh_xmalloc((size_t)x.ne + 1, sizeof(int32_t));
    for (int32_t e = 0; e < x.ne; e++)
        orank[e] = ohe[e] = -1;
    match_open_edges(&x, orank, ohe);
    mesh_xview_finish(&x);
    number_edges(&x, orank, ohe);
    free(orank);
    free(ohe);
    /* Gmsh groups, block counts, bounding box */
    if (o->msh) {
        int32_t *marks, nm, na, gm, ga;
        double *attrs;
        mesh_xview_local_groups(&x, &marks, &nm, &attrs, &na);
        int hasattr = local->tattr != NULL;
        MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, &hasattr, 1, MPI_INT, MPI_MAX, c));
        int32_t *gmarks =
            gather_distinct(marks, nm, sizeof(int32_t), MPI_INT32_T, mesh_cmp_i32, &gm);
        double *gattrs = gather_distinct(attrs, na, sizeof(double), MPI_DOUBLE, mesh_cmp_dbl, &ga);
        mesh_xview_groups(&x, gmarks, gm, hasattr && ga ? gattrs : NULL, ga);
        free(marks);
        free(attrs);
        free(gmarks);
        free(gattrs);
        int64_t b[2] = {x.nlblk + x.ntblk, (x.nhead + x.nsel > 0) + (o->order2 && x.nwe > 0)};
        MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, b, 2, MPI_INT64_T, MPI_SUM, c));
        x.blocks_tot = b[0];
        x.nodeblocks_tot = b[1];
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (size_t i = 0; i < 3 * (size_t)local->ntris; i++)
            for (int k = 0; k < 2; k++) {
                double v =
                    ldexp(local->xy[2 * (size_t)local->tri[i] + (size_t)k], -local->scale_exp);
                lo[k] = fmin(lo[k], v);
                hi[k] = fmax(hi[k], v);
            }
        MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, lo, 2, MPI_DOUBLE, MPI_MIN, c));
        MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, hi, 2, MPI_DOUBLE, MPI_MAX, c));
        if (!(lo[0] <= hi[0])) lo[0] = lo[1] = hi[0] = hi[1] = 0; /* no triangles */
        x.bbox[0] = lo[0];
        x.bbox[1] = lo[1];
        x.bbox[2] = hi[0];
        x.bbox[3] = hi[1];
    }
    /* -o2 --vtk F.pvtu (or F.vtu, F.vtk): one quadratic legacy file F.vtk, global numbering */
    char vtk[1100] = "";
    if (o->vtk && o->order2) {
        snprintf(vtk, sizeof vtk - 4, "%s", o->vtk);
        size_t n = strlen(vtk);
        static const char *const ext[3] = {".pvtu", ".vtu", ".vtk"};
        for (int k = 0; k < 3; k++) {
            size_t e = strlen(ext[k]);
            if (n > e && !strcmp(vtk + n - e, ext[k])) {
                vtk[n - e] = '\0';
                break;
            }
        }
        strcat(vtk, ".vtk");
    }
    mesh_xreq r = {
        prefix, o->edges, o->neighbors, o->order2, o->msh, vtk[0] ? vtk : NULL, par_skip_files(o),
        set};
    char err[600];
    mesh_text_out out = meshio_ptext_out(&c);
    int rc = mesh_xview_write(&x, &out, &r, err, sizeof err);
    if (rc != 0 && rank == 0) fprintf(stderr, "%s: %s\n", o->prog, err);
    mesh_xview_free(&x);
    return rc;
}
