/* api.c: the sequential half of libpcdm's public interface (include/pcdm.h) -- Triangle's
 * triangulate() in one call, and what both halves share (input, options, output, status).
 *
 * pcdm_triangulate is apps/mesh.c without files: the caller's PSLG is copied into a pslg and
 * normalised by pslg_check (duplicates merged, coordinates scaled by an exact power of two into
 * the predicates' working range, quietly: the library never prints; with convex_hull the hull
 * enclosed by segments, as ./mesh -c), triangulated
 * (mesh_build_cdt) and refined (mesh_refine) to the bounds, then copied out with the scaling
 * undone.  The caller's size rule sees the caller's coordinates: a wrapper multiplies the
 * mesher's coordinates by 2^-scale_exp and the area by 2^-2scale_exp, both exact (powers of
 * two).  As ./mesh, the angle bound is raised by a hair so that rounding in the quality test can
 * never leave a triangle a few ulps below it, and a mesh outside the bounds is never a silent
 * success: the Steiner limit returns PCDM_ESTEINER with the (valid, coarser) mesh, anything
 * else left unmet returns PCDM_EUNMET and no mesh.  The parallel call is api_par.c.
 */
#include "api/api_impl.h"

#include "base/base.h"
#include "check/validate.h"
#include "geom/geom.h"
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
    o->min_angle = 20.7;
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

int api_check_args(const pcdm_input *in, const pcdm_options *o, pcdm_status *st) {
    if (!in) return api_fail(st, PCDM_EINVAL, "no input");
    if (!(o->min_angle >= 0 && o->min_angle < 60))
        return api_fail(st, PCDM_EINVAL, "min_angle %g: must be at least 0 and below 60",
                        o->min_angle);
    if (!(o->max_area >= 0) || isinf(o->max_area))
        return api_fail(st, PCDM_EINVAL, "max_area %g: must be 0 (none) or a positive number",
                        o->max_area);
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

int api_make_pslg(const pcdm_input *in, const pcdm_options *o, pslg *g, pcdm_status *st) {
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
    char err[1024];
    if (pslg_check_ex(g, o->convex_hull ? PSLG_HULL : 0u, err, sizeof err) != 0) {
        pslg_free(g);
        return api_fail(st, PCDM_EINPUT, "%s", err);
    }
    return PCDM_OK;
}

/* The caller's size rule in the caller's units. */
static int unscaled_rule(void *ctx, const double *const p[3], double area) {
    const api_rule *u = ctx;
    double q[3][2];
    const double *qp[3] = {q[0], q[1], q[2]};
    for (int i = 0; i < 3; i++) {
        q[i][0] = ldexp(p[i][0], -u->scale_exp);
        q[i][1] = ldexp(p[i][1], -u->scale_exp);
    }
    return u->fn(u->ctx, qp, ldexp(area, -2 * u->scale_exp));
}

void api_quality(const pcdm_options *o, mesh_quality *q) {
    memset(q, 0, sizeof *q);
    q->min_angle = o->min_angle > 0 ? o->min_angle * (1 + 1e-9) + 1e-12 : 0;
    q->max_area = o->max_area;
    q->max_steiner = o->max_steiner < 0 ? -1 : o->max_steiner;
    q->offcenter = !o->circumcenters;
    q->lens = 0;
}

void api_size_rule(mesh *m, const pcdm_options *o, api_rule *u, int scale_exp) {
    if (!o->unsuitable) return;
    u->fn = o->unsuitable;
    u->ctx = o->unsuitable_ctx;
    u->scale_exp = scale_exp;
    mesh_set_size_rule(m, unscaled_rule, u);
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
    geom_init();
    pslg g;
    if (api_make_pslg(in, &o, &g, st)) return st->code;
    mesh m;
    mesh_init(&m);
    char err[1024];
    if (mesh_build_cdt(&m, &g, NULL, err, sizeof err) != 0) {
        mesh_free(&m);
        pslg_free(&g);
        return api_fail(st, PCDM_EINPUT, "%s", err);
    }
    if (o.region_attributes || o.region_areas) mesh_set_regions(&m, &g, o.region_areas, m.nseg);
    api_rule rule;
    mesh_quality q;
    api_quality(&o, &q);
    mesh_set_quality(&m, &q);
    api_size_rule(&m, &o, &rule, g.scale_exp);
    mesh_refine_result rr = mesh_refine(&m);
    int64_t unmet = mesh_count_unmet(&m, NULL);
    int limited = rr == MESH_REFINE_STEINER_LIMIT && unmet > 0;
    if (unmet > 0 && !limited) {
        api_fail(st, PCDM_EUNMET,
                 "cannot meet the bounds: %lld triangles still violate them after %lld refused "
                 "splits (features below the precision of the coordinates, a region too thin "
                 "for its length, or min_angle %g beyond what refinement reaches)",
                 (long long)unmet, (long long)m.stats.unresolved, o.min_angle);
        mesh_free(&m);
        pslg_free(&g);
        return st->code;
    }
    double dom_w = 0, area_w = mesh_area(&m);
    if (!validate_area_net(&g, area_w, &dom_w)) { /* the cheap net, as ./mesh */
        api_fail(st, PCDM_EUNMET,
                 "the mesh's area %.17g differs from the domain's %.17g by more than rounding "
                 "explains (features below the precision of the coordinates)",
                 ldexp(area_w, -2 * g.scale_exp), ldexp(dom_w, -2 * g.scale_exp));
        mesh_free(&m);
        pslg_free(&g);
        return st->code;
    }
    mesh_flat f;
    if (mesh_to_flat(&m, &f) != 0) MESH_BUG("out of memory");
    if (!o.region_attributes) { /* labels only for the region bounds: not returned */
        free(f.tattr);
        f.tattr = NULL;
    }
    flat_to_mesh(&f, g.scale_exp, out);
    mesh_flat_free(&f);
    mesh_free(&m);
    pslg_free(&g);
    if (limited)
        api_fail(st, PCDM_ESTEINER,
                 "Steiner point limit (%lld) reached with %lld triangles outside the bounds; the "
                 "mesh is conforming but does not meet them",
                 (long long)o.max_steiner, (long long)unmet);
    return st->code;
}
