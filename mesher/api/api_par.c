/* api_par.c: pcdm_triangulate_par (include/pcdm.h) -- PCDM (TR-97-17 section 3) in one call,
 * Collective over a communicator the caller gives.
 *
 * It is apps/pcdm.c without files or printing: the runtime is started on duplicates of the
 * caller's communicator (rt_init_comm: MPI stays the caller's, any communicator works, e.g. a
 * split), the pcdm handler registered, every rank builds the same decomposition of the same
 * input (pcdm_decomp_auto; a hash of it is compared across the ranks), keeps and refines its
 * subdomains (pcdm_part_refine), and the parts are checked along their interfaces and numbered
 * by prefix sums (par_check_interfaces_open, par_number_open).  The runtime is finalised before
 * the call returns, on every path.
 *
 * Output.  A rank's part lists its triangles' vertices; rank 0's part starts with every input
 * point (global numbers 0..nin-1, as the file writers do), so "pointowned" (the input points on
 * rank 0, every other vertex on its numbering owner) names each global number on exactly one
 * rank and the owned rows of ranks 0, 1, ... in order are the whole point list.  With
 * opt->root >= 0 exactly those rows, the triangles and the segments (in global numbers) are
 * gathered on the root (MPI_Gatherv on the library's communicator); that is the only gather.
 *
 * Errors.  Every failure is agreed collectively (agree(): the lowest failing rank's message is
 * broadcast) so every rank returns the same code and message and none waits in a collective
 * another rank skipped.  Nothing is printed.
 */
#include "api/api_impl.h"

#include "base/base.h"
#include "decomp/decomp.h"
#include "geom/geom.h"
#include "par/par.h"
#include "par/pout.h"
#include "pbw/pbw.h"
#include "pcdm/pcdm.h"
#include "rt.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Collective.  Nonzero on every rank when code != PCDM_OK on any rank; then every rank's st
 * holds the lowest failing rank's code and message. */
static int agree(int code, pcdm_status *st) {
    MPI_Comm c = rt_app_comm();
    int rank = rt_rank(), size = rt_size();
    int mine = code != PCDM_OK ? rank : size, first = size;
    MESH_MPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, c));
    if (first == size) return 0;
    struct {
        int code;
        char msg[sizeof st->message];
    } b;
    memset(&b, 0, sizeof b);
    if (rank == first) {
        b.code = code;
        memcpy(b.msg, st->message, sizeof b.msg);
    }
    MESH_MPI(MPI_Bcast(&b, (int)sizeof b, MPI_BYTE, first, c));
    st->code = b.code;
    memcpy(st->message, b.msg, sizeof st->message);
    st->message[sizeof st->message - 1] = '\0';
    return 1;
}

/* Local.  This rank's part (local numbering f, global numbering num) into out, as the header
 * describes; rank 0 lists the input points first.  nattr: point attributes per point (0: none;
 * taken from in for input points, from f for the others). */
static void part_to_mesh(const mesh_flat *f, const pslg *in, const par_numbering *num, int nattr,
                         int tattr, pcdm_mesh *out) {
    int rank = rt_rank();
    int32_t nin = rank == 0 ? (int32_t)num->nin : 0;
    int32_t *loc = mesh_xmalloc((size_t)f->nverts + 1, sizeof(int32_t)); /* local -> out row */
    uint8_t *owned = mesh_xcalloc((size_t)f->nverts + 1, 1);
    for (int32_t k = 0; k < num->nowned; k++)
        owned[num->owned[k]] = 1;
    int32_t n = nin;
    for (int32_t v = 0; v < f->nverts; v++) {
        int64_t g = num->gid[v];
        if (g < 0)
            loc[v] = -1;
        else if (g < nin) /* rank 0: an input point, already listed */
            loc[v] = (int32_t)g;
        else
            loc[v] = n++;
    }
    memset(out, 0, sizeof *out);
    out->npoints = n;
    out->points = mesh_xmalloc(2 * (size_t)n, sizeof(double));
    out->pointmarkers = mesh_xcalloc((size_t)n, sizeof(int32_t));
    out->pointglobal = mesh_xmalloc((size_t)n, sizeof(int64_t));
    out->pointowned = mesh_xcalloc((size_t)n, 1);
    out->npointattr = nattr;
    if (nattr) out->pointattr = mesh_xcalloc((size_t)n * nattr, sizeof(double));
    for (int32_t i = 0; i < nin; i++) {
        api_copy_points(out, i, in->xy + 2 * (size_t)i, in->scale_exp);
        out->pointmarkers[i] = in->vmarker ? in->vmarker[i] : 0;
        out->pointglobal[i] = i;
        out->pointowned[i] = 1;
        if (nattr && in->vattr)
            memcpy(out->pointattr + (size_t)i * nattr, in->vattr + (size_t)i * nattr,
                   (size_t)nattr * sizeof(double));
    }
    for (int32_t v = 0; v < f->nverts; v++) {
        int32_t i = loc[v];
        if (i < nin) continue; /* unused, or an input point rank 0 listed */
        api_copy_points(out, i, f->xy + 2 * (size_t)v, in->scale_exp);
        out->pointmarkers[i] = f->vmarker ? f->vmarker[v] : 0;
        out->pointglobal[i] = num->gid[v];
        out->pointowned[i] = owned[v] && num->gid[v] >= num->nin;
        if (nattr && f->vattr)
            memcpy(out->pointattr + (size_t)i * nattr, f->vattr + (size_t)v * nattr,
                   (size_t)nattr * sizeof(double));
    }
    out->ntriangles = f->ntris;
    out->triangles = mesh_xmalloc(3 * (size_t)f->ntris, sizeof(int32_t));
    for (size_t k = 0; k < 3 * (size_t)f->ntris; k++)
        out->triangles[k] = loc[f->tri[k]];
    if (tattr) out->triangleattr = mesh_xmalloc((size_t)f->ntris, sizeof(double));
    if (tattr && f->ntris) memcpy(out->triangleattr, f->tattr, (size_t)f->ntris * sizeof(double));
    out->nsegments = num->nwseg;
    out->segments = mesh_xmalloc(2 * (size_t)num->nwseg, sizeof(int32_t));
    out->segmentmarkers = mesh_xcalloc((size_t)num->nwseg, sizeof(int32_t));
    for (int32_t k = 0; k < num->nwseg; k++) {
        int32_t s = num->wseg[k];
        out->segments[2 * (size_t)k] = loc[f->seg[2 * (size_t)s]];
        out->segments[2 * (size_t)k + 1] = loc[f->seg[2 * (size_t)s + 1]];
        out->segmentmarkers[k] = f->smarker ? f->smarker[s] : 0;
    }
    out->trianglefirst = num->tfirst;
    out->nglobalpoints = num->nverts;
    out->nglobaltriangles = num->ntris;
    out->nglobalsegments = num->nsegs;
    free(loc);
    free(owned);
}

/* Collective.  Concatenates every rank's n bytes at root (returned there, NULL elsewhere);
 * -1 in *fail (every rank) when the total passes what one MPI call can move. */
static void *gather_bytes(const void *mine, size_t n, int root, int *fail) {
    MPI_Comm c = rt_app_comm();
    int P = rt_size(), rank = rt_rank();
    long long my = (long long)n, *all = mesh_xmalloc((size_t)P, sizeof(long long));
    MESH_MPI(MPI_Allgather(&my, 1, MPI_LONG_LONG, all, 1, MPI_LONG_LONG, c));
    long long tot = 0;
    for (int r = 0; r < P; r++)
        tot += all[r];
    if (tot > INT_MAX) {
        free(all);
        *fail = 1;
        return NULL;
    }
    int *cnt = mesh_xmalloc((size_t)P, sizeof(int)), *dsp = mesh_xmalloc((size_t)P, sizeof(int));
    for (int r = 0, d = 0; r < P; r++) {
        cnt[r] = (int)all[r];
        dsp[r] = d;
        d += cnt[r];
    }
    void *buf = rank == root ? mesh_xmalloc((size_t)tot + 1, 1) : NULL;
    MESH_MPI(MPI_Gatherv(mine, (int)n, MPI_BYTE, buf, cnt, dsp, MPI_BYTE, root, c));
    free(all);
    free(cnt);
    free(dsp);
    return buf;
}

/* Collective.  The whole mesh on root from every rank's part p (freed), in global numbering:
 * the owned point rows of ranks 0, 1, ... in order, then the triangles and segments. */
static int gather_whole(pcdm_mesh *p, int root, pcdm_mesh *out, pcdm_status *st) {
    int rank = rt_rank(), fail = 0;
    if (p->nglobalpoints > INT32_MAX || p->nglobaltriangles > INT32_MAX) {
        pcdm_mesh_free(p);
        return api_fail(st, PCDM_EINVAL, "the mesh is too large to collect on one rank");
    }
    int nattr = p->npointattr, tattr = p->triangleattr != NULL;
    /* owned rows: ascending global number already (inputs, then num->owned's order) */
    int32_t no = 0;
    for (int32_t i = 0; i < p->npoints; i++)
        no += p->pointowned[i];
    size_t prow = (2 + (size_t)nattr) * sizeof(double) + sizeof(int32_t);
    unsigned char *pr = mesh_xmalloc((size_t)no * prow + 1, 1), *w = pr;
    for (int32_t i = 0; i < p->npoints; i++) {
        if (!p->pointowned[i]) continue;
        memcpy(w, p->points + 2 * (size_t)i, 2 * sizeof(double));
        w += 2 * sizeof(double);
        if (nattr) memcpy(w, p->pointattr + (size_t)i * nattr, (size_t)nattr * sizeof(double));
        w += (size_t)nattr * sizeof(double);
        memcpy(w, p->pointmarkers + i, sizeof(int32_t));
        w += sizeof(int32_t);
    }
    size_t trow = 3 * sizeof(int32_t) + (tattr ? sizeof(double) : 0);
    unsigned char *tr = mesh_xmalloc((size_t)p->ntriangles * trow + 1, 1);
    w = tr;
    for (int32_t t = 0; t < p->ntriangles; t++) {
        for (int k = 0; k < 3; k++) {
            int32_t g = (int32_t)p->pointglobal[p->triangles[3 * (size_t)t + k]];
            memcpy(w, &g, sizeof g);
            w += sizeof g;
        }
        if (tattr) memcpy(w, p->triangleattr + t, sizeof(double));
        w += tattr ? sizeof(double) : 0;
    }
    size_t srow = 3 * sizeof(int32_t);
    int32_t *sr = mesh_xmalloc(3 * (size_t)p->nsegments + 1, sizeof(int32_t));
    for (int32_t s = 0; s < p->nsegments; s++) {
        sr[3 * (size_t)s] = (int32_t)p->pointglobal[p->segments[2 * (size_t)s]];
        sr[3 * (size_t)s + 1] = (int32_t)p->pointglobal[p->segments[2 * (size_t)s + 1]];
        sr[3 * (size_t)s + 2] = p->segmentmarkers[s];
    }
    int64_t nv = p->nglobalpoints, nt = p->nglobaltriangles, ns = p->nglobalsegments;
    size_t nmine_t = (size_t)p->ntriangles, nmine_s = (size_t)p->nsegments;
    pcdm_mesh_free(p);
    unsigned char *P = gather_bytes(pr, (size_t)no * prow, root, &fail);
    unsigned char *T = fail ? NULL : gather_bytes(tr, nmine_t * trow, root, &fail);
    unsigned char *S = fail ? NULL : gather_bytes(sr, nmine_s * srow, root, &fail);
    free(pr);
    free(tr);
    free(sr);
    memset(out, 0, sizeof *out);
    if (fail) {
        free(P);
        free(T);
        free(S);
        return api_fail(st, PCDM_EINVAL, "the mesh is too large to collect on one rank");
    }
    out->nglobalpoints = nv;
    out->nglobaltriangles = nt;
    out->nglobalsegments = ns;
    out->npointattr = nattr;
    if (rank == root) {
        out->npoints = (int32_t)nv;
        out->points = mesh_xmalloc(2 * (size_t)nv, sizeof(double));
        out->pointmarkers = mesh_xmalloc((size_t)nv, sizeof(int32_t));
        if (nattr) out->pointattr = mesh_xmalloc((size_t)nv * nattr, sizeof(double));
        const unsigned char *r = P;
        for (int64_t i = 0; i < nv; i++) {
            memcpy(out->points + 2 * i, r, 2 * sizeof(double));
            r += 2 * sizeof(double);
            if (nattr) memcpy(out->pointattr + i * nattr, r, (size_t)nattr * sizeof(double));
            r += (size_t)nattr * sizeof(double);
            memcpy(out->pointmarkers + i, r, sizeof(int32_t));
            r += sizeof(int32_t);
        }
        out->ntriangles = (int32_t)nt;
        out->triangles = mesh_xmalloc(3 * (size_t)nt, sizeof(int32_t));
        if (tattr) out->triangleattr = mesh_xmalloc((size_t)nt, sizeof(double));
        r = T;
        for (int64_t t = 0; t < nt; t++) {
            memcpy(out->triangles + 3 * t, r, 3 * sizeof(int32_t));
            r += 3 * sizeof(int32_t);
            if (tattr) memcpy(out->triangleattr + t, r, sizeof(double));
            r += tattr ? sizeof(double) : 0;
        }
        out->nsegments = (int32_t)ns;
        out->segments = mesh_xmalloc(2 * (size_t)ns, sizeof(int32_t));
        out->segmentmarkers = mesh_xmalloc((size_t)ns, sizeof(int32_t));
        const int32_t *q = (const int32_t *)(void *)S;
        for (int64_t k = 0; k < ns; k++) {
            int32_t rec[3];
            memcpy(rec, q + 3 * k, sizeof rec);
            out->segments[2 * k] = rec[0];
            out->segments[2 * k + 1] = rec[1];
            out->segmentmarkers[k] = rec[2];
        }
    }
    free(P);
    free(T);
    free(S);
    return PCDM_OK;
}

/* Collective.  Refines this rank's part of d to o's bounds and leaves it, checked along the
 * interfaces and numbered, in out (see part_to_mesh).  The runtime is up. */
/* Collective.  The common end of both meshers: the refined parts (local, this rank's;
 * artificial, topen: as par_output_sub takes them, may be NULL), checked along the interfaces,
 * numbered and copied into out.  limited/unmet_all: the Steiner limit stopped refinement with
 * unmet_all triangles outside the bounds (PCDM_ESTEINER).  Frees local, artificial and topen. */
static int finish_part(mesh_flat *local, const pslg *in, uint8_t *artificial, uint8_t *topen,
                       int limited, long long unmet_all, const pcdm_options *o, pcdm_mesh *out,
                       pcdm_status *st) {
    int rank = rt_rank();
    MPI_Comm c = rt_app_comm();
    char err[1024], msg[600];
    local->scale_exp = in->scale_exp;
    int rc = par_check_interfaces_open(local, topen, msg, sizeof msg) == 0
                 ? PCDM_OK
                 : api_fail(st, PCDM_EMESH, "rank %d: %s", rank, msg);
    par_numbering num;
    memset(&num, 0, sizeof num);
    if (!agree(rc, st)) {
        if (par_number_open(local, in, artificial, topen, &num, err, sizeof err) != 0)
            api_fail(st, PCDM_EMESH, "%s", err); /* the same on every rank */
    }
    if (st->code == PCDM_OK) {
        /* attributes only when every part has them (an empty part has none to offer) */
        int mine[2] = {local->vattr && local->nattr == in->nattr ? in->nattr : 0,
                       local->tattr != NULL || local->ntris == 0},
            all[2];
        if (local->ntris == 0 && in->nattr && !local->vattr) mine[0] = in->nattr;
        MESH_MPI(MPI_Allreduce(mine, all, 2, MPI_INT, MPI_MIN, c));
        int any_t = local->tattr != NULL, any_all = 0;
        MESH_MPI(MPI_Allreduce(&any_t, &any_all, 1, MPI_INT, MPI_MAX, c));
        part_to_mesh(local, in, &num, all[0], all[1] && any_all, out);
        par_numbering_free(&num);
        if (limited)
            api_fail(st, PCDM_ESTEINER,
                     "Steiner point limit (%lld) reached with %lld triangles outside the bounds; "
                     "the mesh is conforming but does not meet them",
                     (long long)o->max_steiner, unmet_all);
    }
    free(artificial);
    free(topen);
    mesh_flat_free(local);
    return st->code;
}

static int unmet_fail(long long unmet_all, long long refused, const pcdm_options *o,
                      pcdm_status *st) {
    return api_fail(st, PCDM_EUNMET,
                    "cannot meet the bounds: %lld triangles still violate them after %lld refused "
                    "splits (features below the precision of the coordinates, a region too thin "
                    "for its length, or min_angle %g beyond what refinement reaches)",
                    unmet_all, refused, o->min_angle);
}

/* Collective.  PCDM: refines this rank's subdomains of d to o's bounds (the runtime is up,
 * pcdm_register called) and leaves the part in out (finish_part). */
static int mesh_part_pcdm(const pcdm_decomp *d, const pslg *in, const pcdm_options *o,
                          pcdm_mesh *out, pcdm_status *st) {
    int rank = rt_rank();
    MPI_Comm c = rt_app_comm();
    char err[1024];
    pcdm_part part;
    int rc = pcdm_part_build(&part, d, rank, err, sizeof err) == 0
                 ? PCDM_OK
                 : api_fail(st, PCDM_EINPUT, "%s", err);
    if (agree(rc, st)) {
        if (rc == PCDM_OK) pcdm_part_free(&part);
        return st->code;
    }
    api_rule rule;
    mesh_quality q;
    api_quality(o, &q);
    api_size_rule(&part.m, o, &rule, in->scale_exp);
    if (o->max_steiner >= 0) { /* the global budget shared by target weight, as ./pcdm */
        double share = 0;
        for (int32_t s = 0; s < d->nsub; s++)
            if (d->sub_owner[s] == rank) share += d->sub_target[s];
        q.max_steiner = (int64_t)((double)o->max_steiner * share);
    }
    pcdm_part_refine(&part, &q, 300);
    int limit_any = 0;
    MESH_MPI(MPI_Allreduce(&part.limit_hit, &limit_any, 1, MPI_INT, MPI_MAX, c));
    long long un[2] = {(long long)mesh_count_unmet(&part.m, NULL),
                       (long long)part.m.stats.unresolved},
              un_all[2] = {0, 0};
    MESH_MPI(MPI_Allreduce(un, un_all, 2, MPI_LONG_LONG, MPI_SUM, c));
    int limited = limit_any && un_all[0] > 0;
    if (un_all[0] > 0 && !limited) {
        pcdm_part_free(&part);
        return unmet_fail(un_all[0], un_all[1], o, st);
    }
    uint8_t *artificial = pcdm_part_artificial(&part), *topen = NULL;
    mesh_flat local;
    pcdm_part_take_flat(&part, &local, NULL, &topen);
    pcdm_part_free(&part);
    return finish_part(&local, in, artificial, topen, limited, un_all[0], o, out, st);
}

/* Collective.  PBW (TR-97-17 section 2): one distributed mesh refined by remote cavity
 * expansion (the runtime is up, pbw_register called); the part into out (finish_part). */
static int mesh_part_pbw(const pcdm_decomp *d, const pslg *in, const pcdm_options *o,
                         pcdm_mesh *out, pcdm_status *st) {
    par_opts po;
    memset(&po, 0, sizeof po);
    po.prog = "pbw";
    po.min_angle = o->min_angle;
    po.max_area = o->max_area;
    po.max_steiner = o->max_steiner;
    po.circumcenters = o->circumcenters;
    po.imbalance = 1;
    mesh_flat local;
    pbw_result res;
    /* fails on every rank alike only when the input does not triangulate, which the
     * decomposition has ruled out already */
    if (pbw_mesh(&po, in, d, &local, &res) != 0)
        return api_fail(st, PCDM_EMESH, "pbw: the distributed mesh cannot be built");
    free(res.topen); /* finish_part finds the open edges itself */
    MPI_Comm c = rt_app_comm();
    int limit_any = 0;
    MESH_MPI(MPI_Allreduce(&res.limit_hit, &limit_any, 1, MPI_INT, MPI_MAX, c));
    long long un[2] = {(long long)res.unmet, (long long)res.unresolved}, un_all[2] = {0, 0};
    MESH_MPI(MPI_Allreduce(un, un_all, 2, MPI_LONG_LONG, MPI_SUM, c));
    int limited = limit_any && un_all[0] > 0;
    if (un_all[0] > 0 && !limited) {
        mesh_flat_free(&local);
        return unmet_fail(un_all[0], un_all[1], o, st);
    }
    return finish_part(&local, in, NULL, NULL, limited, un_all[0], o, out, st);
}

/* Collective.  Every rank builds the same decomposition of in for the communicator's ranks. */
static int decompose(const pslg *in, const pcdm_options *o, pcdm_decomp *d, pcdm_status *st) {
    int P = rt_size();
    char err[1024];
    pcdm_decomp_opts dopt;
    pcdm_decomp_opts_default(&dopt);
    dopt.nsub = o->subdomains;
    dopt.nranks = P;
    dopt.min_angle = o->min_angle;
    dopt.max_area = o->max_area;
    dopt.max_steiner = o->max_steiner;
    int32_t k = o->subdomains > 0 ? o->subdomains : P;
    int rc = PCDM_OK;
    memset(d, 0, sizeof *d);
    if (k > PAR_MAX_SUBDOMAINS)
        rc = api_fail(st, PCDM_EINVAL, "%d subdomains: at most %d", (int)k, PAR_MAX_SUBDOMAINS);
    else if (o->subdomains > 0 && o->subdomains < P)
        rc = api_fail(st, PCDM_EINVAL, "%d subdomains: fewer than the %d ranks", (int)o->subdomains,
                      P);
    else if (pcdm_decomp_auto(in, &dopt, d, err, sizeof err) != 0)
        rc = api_fail(st, PCDM_EINPUT, "cannot decompose the input for %d ranks: %.900s", P, err);
    if (!agree(rc, st) && !par_decomp_agrees(d))
        rc = api_fail(st, PCDM_EINVAL,
                      "the ranks computed different decompositions (was the same input and "
                      "options passed on every rank?)");
    if (rc != PCDM_OK) pcdm_decomp_free(d);
    return st->code;
}

int pcdm_triangulate_par(MPI_Comm comm, const pcdm_input *in, const pcdm_options *opt,
                         pcdm_mesh *out, pcdm_status *st) {
    pcdm_status own;
    if (!st) st = &own;
    st->code = PCDM_OK;
    st->message[0] = '\0';
    if (!out) return api_fail(st, PCDM_EINVAL, "no output mesh");
    memset(out, 0, sizeof *out);
    int inited = 0, fin = 0;
    MPI_Initialized(&inited);
    MPI_Finalized(&fin);
    if (!inited || fin)
        return api_fail(st, PCDM_EMPI, "MPI is not initialised (call MPI_Init_thread first)");
    pcdm_options o;
    if (opt)
        o = *opt;
    else
        pcdm_options_default(&o);
    int rc = rt_init_comm(comm, NULL);
    if (rc == RT_ESTATE)
        return api_fail(st, PCDM_EBUSY, "the parallel runtime is already running in this process");
    if (rc != RT_OK)
        return api_fail(st, PCDM_EMPI,
                        "cannot start the parallel runtime: %s (MPI must provide "
                        "MPI_THREAD_FUNNELED and be called from its main thread)",
                        rt_strerror(rc));
    int P = rt_size();
    if (o.method != PCDM_METHOD_PCDM && o.method != PCDM_METHOD_PBW) o.method = -1;
    int hid = o.method == PCDM_METHOD_PBW ? pbw_register() : pcdm_register();
    rc = hid < 0 ? api_fail(st, PCDM_EMESH, "cannot register the handlers: %s", rt_strerror(hid))
                 : PCDM_OK;
    if (rc == 0) rc = api_check_args(in, &o, st);
    if (rc == 0 && o.method < 0)
        rc = api_fail(st, PCDM_EINVAL, "method: PCDM_METHOD_PCDM or PCDM_METHOD_PBW");
    if (rc == 0 && o.method == PCDM_METHOD_PBW && o.unsuitable)
        rc = api_fail(st, PCDM_EINVAL,
                      "the size callback (unsuitable) works with "
                      "PCDM_METHOD_PCDM and pcdm_triangulate only");
    if (rc == 0 && (o.region_attributes || o.region_areas))
        rc = api_fail(st, PCDM_EINVAL,
                      "region_attributes and region_areas work with pcdm_triangulate only (the "
                      "parallel call does not label regions yet)");
    if (rc == 0 && (o.root >= P))
        rc = api_fail(st, PCDM_EINVAL, "root %d: the communicator has %d ranks", o.root, P);
    geom_init();
    pslg g;
    memset(&g, 0, sizeof g);
    if (rc == 0) rc = api_make_pslg(in, &o, &g, st);
    if (agree(rc, st)) {
        pslg_free(&g);
        rt_finalize();
        return st->code;
    }
    pcdm_decomp d;
    if (decompose(&g, &o, &d, st) == PCDM_OK) {
        rc = o.method == PCDM_METHOD_PBW ? mesh_part_pbw(&d, &g, &o, out, st)
                                         : mesh_part_pcdm(&d, &g, &o, out, st);
        pcdm_decomp_free(&d);
        if ((rc == PCDM_OK || rc == PCDM_ESTEINER) && o.root >= 0) {
            pcdm_mesh part = *out;
            int keep = st->code;
            memset(out, 0, sizeof *out);
            if (gather_whole(&part, o.root, out, st) == PCDM_OK) st->code = keep;
            agree(st->code == PCDM_ESTEINER ? PCDM_OK : st->code, st);
        }
    }
    pslg_free(&g);
    rt_finalize();
    return st->code;
}
