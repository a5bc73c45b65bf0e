/* api.c: the sequential half of libpcdm's public interface (include/pcdm.h) -- Triangle's
 * triangulate() in one call, and what both halves share (input, options, output, status).
 *
 * pcdm_triangulate is ./mesh without files: the caller's arrays are copied into a pslg and
 * handed to the driver (run/run.h) as a job, which goes through ./mesh's stages -- the input
 * checked and normalised (duplicates merged, coordinates scaled by an exact power of two,
 * crossing segments split, Triangle's boundary markers, the hull with convex_hull; quietly: the
 * library never prints), the bounds as one value, the CDT refined, the verdict -- and the mesh
 * is copied out with the scaling undone.  The caller's size rule sees the caller's coordinates
 * (the driver's wrapper).  A mesh outside the bounds is never a silent success: the Steiner
 * limit returns PCDM_ESTEINER with the (valid, coarser) mesh, anything else left unmet
 * PCDM_EUNMET and no mesh.  With threads >= 1 (and something to refine) the call is the
 * subdomain mesher of ./pcdm instead (api_thr.c), in the builds that have it (PCDM_THREADS:
 * libpcdm, libpcdm_threads); libpcdm_seq refuses it.  The parallel call is api_par.c.
 */
#include "api/api_impl.h"

#include "base/base.h"
#include "bounds/bounds.h"
#include "geom/geom.h"
#include "run/run.h"
#include "seq/mesh.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *pcdm_version(void) {
    return PCDM_VERSION_STRING;
}

void pcdm_options_default(pcdm_options *o) {
    memset(o, 0, sizeof *o);
    o->min_angle = BOUNDS_DEFAULT_ANGLE;
    o->max_steiner = -1;
    o->root = -1;
}

void pcdm_mesh_free(pcdm_mesh *m) {
    if (!m) return;
    free(m->points);
    free(m->pointmarkers);
    free(m->pointattr);
    free(m->triangles);
    free(m->triangleattr);
    free(m->segments);
    free(m->segmentmarkers);
    free(m->pointglobal);
    free(m->pointowned);
    memset(m, 0, sizeof *m);
}

int api_fail(pcdm_status *st, int code, const char *fmt, ...) {
    st->code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(st->message, sizeof st->message, fmt, ap);
    va_end(ap);
    return code;
}

const char *api_unpath(const char *msg) {
    /* the arrays have no file or lines: "input:LINE: " or "input: " says nothing */
    static const char name[] = "input:";
    if (strncmp(msg, name, sizeof name - 1) != 0) return msg;
    const char *p = msg + sizeof name - 1;
    while (*p >= '0' && *p <= '9')
        p++;
    if (*p == ':') p++;
    while (*p == ' ')
        p++;
    return *p ? p : msg;
}

int api_check_args(const pcdm_input *in, const pcdm_options *o, pcdm_status *st) {
    if (!in) return api_fail(st, PCDM_EINVAL, "no input");
    char why[sizeof st->message];
    if (bounds_check(o->min_angle, o->max_area, "min_angle", "max_area", why, sizeof why) != 0)
        return api_fail(st, PCDM_EINVAL, "%s", why);
    if (in->npoints < 0 || in->nsegments < 0 || in->nholes < 0 || in->nregions < 0 ||
        in->npointattr < 0)
        return api_fail(st, PCDM_EINVAL, "a negative count in the input");
    if ((in->npoints && !in->points) || (in->nsegments && !in->segments) ||
        (in->nholes && !in->holes) || (in->nregions && !in->regions) ||
        (in->npointattr && in->npoints && !in->pointattr))
        return api_fail(st, PCDM_EINVAL, "an input array is NULL but its count is not 0");
    if (in->npoints < 3)
        return api_fail(st, PCDM_EINPUT, "%d points: need at least 3", in->npoints);
    for (int32_t s = 0; s < in->nsegments; s++)
        for (int k = 0; k < 2; k++) {
            int32_t v = in->segments[2 * (size_t)s + k];
            if (v < 0 || v >= in->npoints)
                return api_fail(st, PCDM_EINPUT, "segment %d: point %d out of range (0..%d)", s, v,
                                in->npoints - 1);
        }
    return PCDM_OK;
}

static void *dup_array(const void *p, size_t n, size_t size) {
    void *q = mesh_xmalloc(n, size);
    if (p && n) memcpy(q, p, n * size);
    return q;
}

void api_copy_input(const pcdm_input *in, pslg *g) {
    memset(g, 0, sizeof *g);
    size_t nv = (size_t)in->npoints, ns = (size_t)in->nsegments;
    g->nverts = in->npoints;
    g->xy = dup_array(in->points, 2 * nv, sizeof(double));
    g->vmarker = in->pointmarkers ? dup_array(in->pointmarkers, nv, sizeof(int32_t))
                                  : mesh_xcalloc(nv, sizeof(int32_t));
    g->vline = mesh_xcalloc(nv, sizeof(int32_t)); /* no source lines: 0 */
    g->nattr = in->npointattr;
    if (in->npointattr > 0)
        g->vattr = dup_array(in->pointattr, (size_t)in->npointattr * nv, sizeof(double));
    g->nsegs = in->nsegments;
    g->seg = dup_array(in->segments, 2 * ns, sizeof(int32_t));
    g->smarker = in->segmentmarkers ? dup_array(in->segmentmarkers, ns, sizeof(int32_t))
                                    : mesh_xcalloc(ns, sizeof(int32_t));
    g->sline = mesh_xcalloc(ns, sizeof(int32_t));
    g->nholes = in->nholes;
    g->holes = dup_array(in->holes, 2 * (size_t)in->nholes, sizeof(double));
    g->nregions = in->nregions;
    g->regions = dup_array(in->regions, 4 * (size_t)in->nregions, sizeof(double));
    g->first_index = 0;
    g->quiet = 1;
    snprintf(g->path, sizeof g->path, "input");
}

void api_copy_points(pcdm_mesh *out, int32_t i, const double *xy, int scale_exp) {
    out->points[2 * (size_t)i] = ldexp(xy[0], -scale_exp);
    out->points[2 * (size_t)i + 1] = ldexp(xy[1], -scale_exp);
}

/* The whole mesh f (sequential numbering) into out, coordinates unscaled. */
static void flat_to_mesh(const mesh_flat *f, int scale_exp, pcdm_mesh *out) {
    memset(out, 0, sizeof *out);
    size_t nv = (size_t)f->nverts, nt = (size_t)f->ntris, ns = (size_t)f->nsegs;
    out->npoints = f->nverts;
    out->points = mesh_xmalloc(2 * nv, sizeof(double));
    for (int32_t i = 0; i < f->nverts; i++)
        api_copy_points(out, i, f->xy + 2 * (size_t)i, scale_exp);
    out->pointmarkers =
        f->vmarker ? dup_array(f->vmarker, nv, sizeof(int32_t)) : mesh_xcalloc(nv, sizeof(int32_t));
    if (f->vattr && f->nattr > 0) {
        out->npointattr = f->nattr;
        out->pointattr = dup_array(f->vattr, nv * (size_t)f->nattr, sizeof(double));
    }
    out->ntriangles = f->ntris;
    out->triangles = dup_array(f->tri, 3 * nt, sizeof(int32_t));
    if (f->tattr) out->triangleattr = dup_array(f->tattr, nt, sizeof(double));
    out->nsegments = f->nsegs;
    out->segments = dup_array(f->seg, 2 * ns, sizeof(int32_t));
    out->segmentmarkers =
        f->smarker ? dup_array(f->smarker, ns, sizeof(int32_t)) : mesh_xcalloc(ns, sizeof(int32_t));
    out->nglobalpoints = out->npoints;
    out->nglobaltriangles = out->ntriangles;
    out->nglobalsegments = out->nsegments;
}

void api_job(const pcdm_options *o, int method, pslg *g, run_job *j) {
    par_opts po;
    memset(&po, 0, sizeof po);
    po.prog = "pcdm";
    po.input = "input";
    po.min_angle = o->min_angle;
    po.max_area = o->max_area;
    po.max_steiner = o->max_steiner < 0 ? -1 : o->max_steiner;
    po.circumcenters = o->circumcenters;
    po.convex_hull = o->convex_hull;
    po.region_attr = o->region_attributes;
    po.region_area = o->region_areas;
    po.imbalance = 1;
    po.nsub = o->subdomains;
    po.threads = o->threads > 1 ? o->threads : 1;
    po.quiet = 1;
    run_job_init(j, (run_method)method, &po);
    j->given = g;
    j->lib = 1;
    j->cdt_only = o->no_refine;
    j->lens = o->lenses;
    j->user_size = o->unsuitable;
    j->user_size_ctx = o->unsuitable_ctx;
}

int api_make_pslg(const pcdm_input *in, const pcdm_options *o, pslg *g, pcdm_status *st) {
    pslg given;
    api_copy_input(in, &given);
    run_job j;
    api_job(o, RUN_SEQ, &given, &j);
    char err[1024];
    int rc = run_load(&j, g, 1, 0, err, sizeof err);
    run_job_free(&j);
    return rc == 0 ? PCDM_OK : api_fail(st, PCDM_EINPUT, "%s", err);
}

static int triangulate_here(const pcdm_input *in, const pcdm_options *o, pcdm_mesh *out,
                            pcdm_status *st);

int pcdm_triangulate(const pcdm_input *in, const pcdm_options *opt, pcdm_mesh *out,
                     pcdm_status *st) {
    pcdm_status own;
    if (!st) st = &own;
    st->code = PCDM_OK;
    st->message[0] = '\0';
    if (!out) return api_fail(st, PCDM_EINVAL, "no output mesh");
    memset(out, 0, sizeof *out);
    pcdm_options o;
    if (opt)
        o = *opt;
    else
        pcdm_options_default(&o);
    if (api_check_args(in, &o, st)) return st->code;
    if (o.threads < 0)
        return api_fail(st, PCDM_EINVAL, "threads %d: must be 0 (this thread) or more", o.threads);
    if (o.threads > 0 && !o.no_refine) {
#ifdef PCDM_THREADS
        return api_triangulate_threads(in, &o, out, st);
#else
        return api_fail(st, PCDM_EINVAL,
                        "threads %d: this build has no threaded mesher (it was built without "
                        "METIS): in C link libpcdm_threads (pkg-config pcdm-threads); the Python "
                        "package has threads when METIS (libmetis-dev) is there as it is built",
                        o.threads);
#endif
    }
    return triangulate_here(in, &o, out, st);
}

/* The driver's stages (run/run.h), as ./mesh: the input checked with crossing segments split
 * and Triangle's boundary-marker rules, the bounds, the mesh, the verdict; out of memory
 * anywhere in them gives back every block and returns here (base.h: mesh_guard). */
static int triangulate_here(const pcdm_input *in, const pcdm_options *o, pcdm_mesh *out,
                            pcdm_status *st) {
    mesh_guard guard;
    if (MESH_GUARD_ENTER(&guard)) {
        memset(out, 0, sizeof *out);
        return api_fail(st, PCDM_ENOMEM, "%s", guard.msg);
    }
    pslg g;
    api_copy_input(in, &g);
    run_job j;
    api_job(o, RUN_SEQ, &g, &j);
    mesh_flat f;
    int scale_exp = 0;
    int rc = run_mesh_flat(&j, &f, &scale_exp);
    if (rc == 0) {
        flat_to_mesh(&f, scale_exp, out);
        mesh_flat_free(&f);
    }
    mesh_guard_leave(&guard);
    if (rc == 1) return api_fail(st, PCDM_EINPUT, "%s", api_unpath(j.msg));
    if (rc == 2) return api_fail(st, PCDM_EUNMET, "%s", j.msg);
    if (j.verdict == RUN_STEINER) api_fail(st, PCDM_ESTEINER, "%s", j.msg);
    return st->code;
}
