/* api_par.c: pcdm_triangulate_par (include/pcdm_par.h) -- PCDM (TR-97-17 section 3) or PBW
 * (section 2) in one call, Collective over a communicator the caller gives.
 *
 * It is ./pcdm and ./pbw without files or printing: the runtime is started on duplicates of the
 * caller's communicator (rt_init_comm: MPI stays the caller's, any communicator works, e.g. a
 * split), the method's handlers registered, and the caller's arrays handed to the driver
 * (run/run_par.c) as a job: every rank loads the same input and builds the same decomposition
 * (a hash of it compared across the ranks), refines its part, and the verdict is reduced.  The
 * library's own end is here: the parts checked along their interfaces and numbered by prefix
 * sums (par_check_interfaces_open, par_number_open) and copied into the caller's arrays.  The
 * runtime is finalised before the call returns, on every path.
 *
 * Output.  A rank's part lists its triangles' vertices; rank 0's part starts with every input
 * point (global numbers 0..nin-1, as the file writers do), so "pointowned" (the input points on
 * rank 0, every other vertex on its numbering owner) names each global number on exactly one
 * rank and the owned rows of ranks 0, 1, ... in order are the whole point list.  With
 * opt->root >= 0 exactly those rows, the triangles and the segments (in global numbers) are
 * gathered on the root (MPI_Gatherv on the library's communicator); that is the only gather.
 *
 * Errors.  Every failure is agreed collectively (par_agree: the lowest failing rank's code and
 * message are broadcast) so every rank returns the same code and message and none waits in a
 * collective another rank skipped.  Nothing is printed.
 */
#include "api/api_impl.h"
#include "pcdm_par.h"

#include "base/base.h"
#include "decomp/decomp.h"
#include "geom/geom.h"
#include "par/par.h"
#include "par/pout.h"
#include "pbw/pbw.h"
#include "pcdm/pcdm.h"
#include "rt.h"
#include "run/run.h"
#include "run/run_stats.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Collective.  Nonzero on every rank when code != PCDM_OK on any rank; then every rank's st
 * holds the lowest failing rank's code and message. */
static int agree(int code, pcdm_status *st) {
    char buf[sizeof st->message];
    int rc = par_agree(code, st->message, buf, sizeof buf);
    if (!rc) return 0;
    st->code = rc;
    memcpy(st->message, buf, sizeof st->message);
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

/* Collective.  The library's end of both meshers (the driver's write stage for arrays): the
 * refined parts (local, this rank's; artificial, topen: as par_output_sub takes them, may be
 * NULL), checked along the interfaces, numbered and copied into out; the Steiner limit
 * (j->verdict) gives PCDM_ESTEINER with the driver's message.  Frees local, artificial and
 * topen. */
static int finish_part(mesh_flat *local, const pslg *in, uint8_t *artificial, uint8_t *topen,
                       const run_job *j, pcdm_mesh *out, pcdm_status *st) {
    int rank = rt_rank();
    MPI_Comm c = rt_app_comm();
    char err[1024], msg[600];
    local->scale_exp = in->scale_exp;
    int rc = par_check_interfaces_open(local, topen, msg, sizeof msg) == 0
                 ? PCDM_OK
                 : api_fail(st, PCDM_EMESH, "rank %d: %s", rank, msg);
    /* the parts' areas sum to the domain's, as the programs check before they write (test-only
     * fault PCDM_TEST_AREA_SKEW: this rank's area taken 1e-6 too large) */
    double area = rc == PCDM_OK ? par_part_area(local, j->o.threads) : 0;
    if (getenv("PCDM_TEST_AREA_SKEW")) area *= 1 + 1e-6;
    if (!agree(rc, st) && !par_area_agrees(in, area, NULL, msg, sizeof msg))
        api_fail(st, PCDM_EMESH, "%s", msg); /* the same on every rank */
    par_numbering num;
    memset(&num, 0, sizeof num);
    if (st->code == PCDM_OK) {
        if (par_number_open(local, in, artificial, topen, j->o.threads, &num, err, sizeof err) != 0)
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
        if (j->verdict == RUN_STEINER) api_fail(st, PCDM_ESTEINER, "%s", j->msg);
    }
    free(artificial);
    free(topen);
    mesh_flat_free(local);
    return st->code;
}

/* The library's code for a driver's RUN_F* code. */
static int api_code(int run_code) {
    switch (run_code) {
    case 0:
        return PCDM_OK;
    case RUN_FINPUT:
        return PCDM_EINPUT;
    case RUN_FUNMET:
        return PCDM_EUNMET;
    case RUN_FINVAL:
        return PCDM_EINVAL;
    default:
        return PCDM_EMESH;
    }
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
    if (rc == 0 && (o.no_refine || o.lenses))
        rc = api_fail(st, PCDM_EINVAL, "no_refine and lenses work with pcdm_triangulate only");
    if (rc == 0 && o.threads > 1 && o.method == PCDM_METHOD_PBW)
        rc = api_fail(st, PCDM_EINVAL, "threads work with PCDM_METHOD_PCDM only");
    if (rc == 0 && o.threads > 1) {
        int w = rt_workers_ensure(o.threads);
        if (w != RT_OK)
            rc = api_fail(st, PCDM_EMESH, "cannot start %d worker threads: %s", o.threads,
                          rt_strerror(w));
    }
    if (rc == 0 && (o.root >= P))
        rc = api_fail(st, PCDM_EINVAL, "root %d: the communicator has %d ranks", o.root, P);
    if (agree(rc, st)) {
        rt_finalize();
        return st->code;
    }
    /* the driver's stages (run/run.h), as ./pcdm and ./pbw: the input checked with crossing
     * segments split and Triangle's boundary-marker rules, the decomposition, the bounds, the
     * mesh, the verdict; then the library's own end (finish_part, the gather on root) */
    pslg g, pin;
    api_copy_input(in, &g);
    run_job j;
    api_job(&o, o.method == PCDM_METHOD_PBW ? RUN_PBW : RUN_PCDM, &g, &j);
    pcdm_decomp d;
    rc = run_par_load(&j, &pin, &d);
    if (rc != 0) {
        api_fail(st, api_code(rc), "%s", j.msg);
        rt_finalize();
        return st->code;
    }
    run_part part;
    run_stats rs;
    memset(&rs, 0, sizeof rs);
    rc = run_par_mesh(&j, &pin, &d, &part, &rs);
    run_stats_free(&rs);
    if (rc != 0) {
        api_fail(st, api_code(rc), "%s", j.msg);
        run_part_free(&part);
    } else {
        free(part.tsub);
        finish_part(&part.local, &pin, part.artificial, part.topen, &j, out, st);
        if ((st->code == PCDM_OK || st->code == PCDM_ESTEINER) && o.root >= 0) {
            pcdm_mesh whole = *out;
            int keep = st->code;
            memset(out, 0, sizeof *out);
            if (gather_whole(&whole, o.root, out, st) == PCDM_OK) st->code = keep;
            agree(st->code == PCDM_ESTEINER ? PCDM_OK : st->code, st);
        }
    }
    pcdm_decomp_free(&d);
    pslg_free(&pin);
    run_job_free(&j);
    rt_finalize();
    return st->code;
}
