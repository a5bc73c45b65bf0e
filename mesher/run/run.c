/* run.c: the driver's stages shared by every mesher (run.h), in the order a job goes through
 * them, as Triangle's triangulate() lists its own:
 *
 *   1. load: the input is read (pslg_read; -r: the mesh to refine as a PSLG,
 *      meshio_read_mesh_pslg) or taken from the library's arrays, then checked and
 *      normalised (pslg_check_ex: duplicates merged, coordinates scaled by an exact power of
 *      two, crossing and overlapping segments split -- refused under --strict --, -c's convex
 *      hull enclosed), and Triangle's boundary-marker rules applied (pslg_boundary_markers);
 *      the size rules (-r's .area, --size) are loaded in the input's scale.
 *   2. bounds: one value (bounds_make): the angle with its margin, the area, the Steiner limit,
 *      off-centres or circumcentres, lenses, region bounds, the size rule.
 *   3. mesh: the constrained Delaunay triangulation and Ruppert/Chew refinement, sequentially
 *      (run_seq.c) or in parallel by PCDM or PBW after a decomposition (run_par.c).
 *   4. verdict: triangles outside the bounds that the input does not force are counted; none:
 *      met; some, with the Steiner limit hit: the limit (exit 3, the mesh kept); otherwise
 *      cannot meet the bounds (exit 1; the mesh written only with --write-partial).  Then the
 *      cheap net: the triangles' areas sum to the domain's.
 *   5. check: with --check the validator, holding the mesh to the bounds only when they were
 *      met.
 *   6. write: the Triangle files, -e, -n, -o2, --msh, VTK, SVG (the parallel meshers: every rank
 *      its own part); the library copies the mesh into the caller's arrays instead.
 *   7. exit status: 0, 1 or 3 for the programs (the same on every rank), the verdict's code for
 *      the library.
 * --stats and -V report along the way.
 */
#include "run/run.h"

#include "base/base.h"
#include "geom/geom.h"
#include "io/oset.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void run_job_init(run_job *j, run_method method, const par_opts *o) {
    memset(j, 0, sizeof *j);
    j->method = method;
    j->o = *o;
    if (o->out_prefix == o->out_name) j->o.out_prefix = j->o.out_name; /* Triangle's name */
}

void run_job_free(run_job *j) {
    size_field_free(&j->sizes);
}

/* The programs' outputs, checked before any work: each file's folder must take new files (an
 * unwritable or missing folder is found now, not after minutes of meshing). */
static int probe_outputs(const par_opts *o, char *err, size_t errlen) {
    char path[1100];
    if (o->out_prefix && (par_skip_linear(o) != MESHIO_SKIP_ALL || o->edges || o->neighbors)) {
        snprintf(path, sizeof path, "%.1000s.node", o->out_prefix);
        if (meshio_probe(path, err, errlen) != 0) return -1;
    }
    const char *single[3] = {o->vtk, o->svg, o->msh};
    for (int k = 0; k < 3; k++)
        if (single[k] && meshio_probe(single[k], err, errlen) != 0) return -1;
    return 0;
}

/* j->vertices_ready, once: as soon as the input's vertices are read, else after pslg_check_start */
static void vertices_read(void *ctx, const pslg *g) {
    run_job *j = ctx;
    void (*ready)(run_job *, const pslg *) = j->vertices_ready;
    j->vertices_ready = NULL;
    ready(j, g);
}

int run_load(run_job *j, pslg *g, int quiet, int sizes, char *err, size_t errlen) {
    const par_opts *o = &j->o;
    memset(g, 0, sizeof *g);
    memset(&j->sizes, 0, sizeof j->sizes);
    if (bounds_check(o->min_angle, o->max_area, j->lib ? "min_angle" : "-q",
                     j->lib ? "max_area" : "-a", err, errlen) != 0)
        return -1;
    if (!j->lib && probe_outputs(o, err, errlen) != 0) return -1;
    int rc;
    if (j->given) {
        *g = *j->given; /* taken over */
        memset(j->given, 0, sizeof *j->given);
        rc = 0;
    } else {
        rc = o->refine ? meshio_read_mesh_pslg(o->input, g, err, errlen)
                       : pslg_read_ex(o->input, g, j->vertices_ready ? vertices_read : NULL, j, err,
                                      errlen);
    }
    if (rc != 0) return -1;
    g->quiet = quiet; /* no warnings (merged duplicates) */
    unsigned flags = (o->strict ? 0u : PSLG_SPLIT) | (o->convex_hull ? PSLG_HULL : 0u);
    if (pslg_check_start(g, err, errlen) != 0) {
        pslg_free(g);
        return -1;
    }
    if (j->vertices_ready) vertices_read(j, g); /* not read from a .poly or .node */
    if (pslg_check_finish(g, flags, err, errlen) != 0) {
        pslg_free(g);
        return -1;
    }
    if (pslg_boundary_markers(g) != 0) /* Triangle's marker rules, inherited by the mesh */
        MESH_BUG("%s: the boundary markers could not be set", g->path);
    if (sizes && run_load_sizes(j, g, err, errlen) != 0) {
        pslg_free(g);
        return -1;
    }
    return 0;
}

int run_load_sizes(run_job *j, const pslg *g, char *err, size_t errlen) {
    const par_opts *o = &j->o;
    memset(&j->sizes, 0, sizeof j->sizes);
    /* -r with -a alone: the old mesh's .area; --size: a background mesh (sizefield.h) */
    return size_field_load(&j->sizes, o->refine && o->region_area ? o->input : NULL, o->size_field,
                           g->scale_exp, err, errlen) != 0
               ? -1
               : 0;
}

/* The library's size rule in the caller's units: coordinates and area scaled back exactly. */
static int unscaled_rule(void *ctx, const double *const p[3], double area) {
    const run_job *j = ctx;
    double q[3][2];
    const double *qp[3] = {q[0], q[1], q[2]};
    for (int i = 0; i < 3; i++) {
        q[i][0] = ldexp(p[i][0], -j->user_scale_exp);
        q[i][1] = ldexp(p[i][1], -j->user_scale_exp);
    }
    return j->user_size(j->user_size_ctx, qp, ldexp(area, -2 * j->user_scale_exp));
}

mesh_bounds run_bounds(run_job *j, const pslg *g) {
    const par_opts *o = &j->o;
    mesh_bounds b = bounds_make(o->min_angle, o->max_area, o->max_steiner, o->circumcenters,
                                j->method == RUN_SEQ ? j->lens : 0);
    b.region_area = o->region_area;
    if (j->sizes.active) bounds_set_size(&b, size_field_unsuitable, &j->sizes);
    if (j->user_size) {
        j->user_scale_exp = g->scale_exp;
        bounds_set_size(&b, unscaled_rule, j);
    }
    j->bounds = b;
    return b;
}

run_verdict run_verdict_of(int limit_hit, int64_t unmet) {
    return unmet <= 0 ? RUN_MET : limit_hit ? RUN_STEINER : RUN_UNMET;
}

void run_verdict_message(const run_job *j, const char *prefix, char *buf, size_t len) {
    const par_opts *o = &j->o;
    buf[0] = '\0';
    if (j->verdict == RUN_STEINER)
        snprintf(buf, len,
                 "%sSteiner point limit (%s%lld) reached with %lld triangles outside the bounds; "
                 "the mesh is conforming but does not meet them%s",
                 prefix, j->lib ? "" : "-S ", (long long)o->max_steiner, (long long)j->unmet,
                 j->lib ? "" : " (exit status 3)");
    else if (j->verdict == RUN_UNMET)
        snprintf(buf, len,
                 "%scannot meet the bounds: %lld triangles still violate them after %lld refused "
                 "splits (features below the precision of the coordinates, a region too thin "
                 "for its length, or %s %g beyond what refinement reaches on this input)%s",
                 prefix, (long long)j->unmet, (long long)j->refused, j->lib ? "min_angle" : "-q",
                 o->min_angle,
                 !j->lib && o->write_partial ? "; writing the mesh made so far (--write-partial)"
                                             : "");
}

int run_exit_status(run_verdict v, int rc) {
    return v == RUN_UNMET ? 1 : rc != 0 ? rc : v == RUN_STEINER ? 3 : 0;
}

void run_check_bounds(const run_job *j, double *min_angle, double *max_area, int *region_area) {
    int none = j->cdt_only || j->verdict != RUN_MET; /* the bounds were given up */
    *min_angle = none ? 0 : j->bounds.min_angle;
    *max_area = none ? 0 : j->bounds.max_area;
    *region_area = !none && j->bounds.region_area;
}
