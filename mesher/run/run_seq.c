/* run_seq.c: the sequential driver (run.h) -- ./mesh and pcdm_triangulate: the stages of run.c
 * with the mesh made by one process: the constrained Delaunay triangulation of the checked
 * input (mesh_build_cdt) refined by Ruppert/Chew (mesh_refine, seq/mesh.h).
 *
 * ./mesh (run_mesh) prints a message per problem ("mesh: FILE:LINE: problem"), -V a summary on
 * stderr, --progress a line every 2 s, --stats on stdout the line
 *   stats: triangles=N vertices=N steiner=N min_angle=D max_area=A mesh_s=T peak_rss_mb=M
 *          bytes_per_tri=B output_s=O cpu_s=C read_s=R wall_s=W
 * after the kernel's counters on stderr.  Times are wall-clock seconds, one field per phase:
 *   read_s: reading and checking the input (and the bounds made from it);
 *   mesh_s: the meshing -- triangulation and refinement, no file I/O;
 *   output_s: the flat (numbered) mesh, the files (-o, --vtk, --svg, ...) and --check;
 *   wall_s: the whole run, from before reading the input to after the output is written and
 *   checked: the phases above and what lies between them (the verdict, the area check).
 * cpu_s is the process's CPU time over the meshing (mesh_s's span), bytes_per_tri the peak
 * resident memory per triangle.  Every path ends at one clean-up and one exit status.
 */
#include "run/run.h"

#include "base/base.h"
#include "check/validate.h"
#include "geom/geom.h"
#include "io/meshio.h"
#include "io/oset.h"
#include "io/xwrite.h"
#include "seq/vattr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* This process's CPU time so far (user + system), in seconds. */
static double cpu_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct progress {
    int on;
    double t0, last;
    double t_cdt;     /* seconds of the triangulation */
    double c0;        /* CPU seconds at t0 */
    double mesh, cpu; /* seconds of triangulation and refinement (mesh_s, cpu_s) */
    double t_start;   /* when reading the input began (wall_s counts from there) */
    mesh *m;
} progress;

static int poll_progress(void *ctx) {
    progress *p = ctx;
    if (!p->on) return 0;
    double t = now();
    if (t - p->last >= 2.0) {
        p->last = t;
        fprintf(stderr, "mesh: %.1f s  %ld triangles  %ld vertices\n", t - p->t0, (long)p->m->nlive,
                (long)p->m->nv);
    }
    return 0;
}

/* -V: what was read and what is asked for. */
static void verbose_input(const run_job *j, const pslg *g, double read_s) {
    const par_opts *o = &j->o;
    char area[64] = "none", steiner[64] = "none";
    if (o->max_area > 0) snprintf(area, sizeof area, "%g", o->max_area);
    if (o->max_steiner >= 0) snprintf(steiner, sizeof steiner, "%lld", (long long)o->max_steiner);
    fprintf(stderr,
            "mesh: %s: %ld vertices, %ld segments, %ld holes, %ld regions (read and checked in "
            "%.3f s)\n",
            o->input, (long)g->nverts, (long)g->nsegs, (long)g->nholes, (long)g->nregions, read_s);
    if (j->cdt_only)
        fprintf(stderr, "mesh: bounds: none (--cdt-only)\n");
    else
        fprintf(stderr, "mesh: bounds: -q %g, -a %s, -S %s; %s, diametral %s\n", o->min_angle, area,
                steiner, o->circumcenters ? "circumcenters" : "off-centers",
                j->lens ? "lenses" : "circles");
}

/* Stages 3 and 4: the CDT of g refined to b (none with --cdt-only), then the verdict and the
 * area net.  Returns 0, or -1 with the message in err (bad input: the CDT; the area net);
 * j->verdict, j->unmet and j->refused are set. */
static int mesh_and_judge(run_job *j, const pslg *g, const mesh_bounds *b, mesh *m, progress *pr,
                          char *err, size_t errlen) {
    const par_opts *o = &j->o;
    if (mesh_build_cdt(m, g, NULL, err, errlen) != 0) return -1;
    if (o->region_attr || o->region_area) mesh_set_regions(m, g, o->region_area, m->nseg);
    if (pr) {
        pr->t_cdt = now() - pr->t0;
        mesh_hooks h = {NULL, poll_progress, 4096, pr};
        mesh_set_hooks(m, &h);
    }
    mesh_refine_result rr = MESH_REFINE_DONE;
    if (!j->cdt_only) {
        bounds_apply(b, m);
        rr = mesh_refine(m);
    }
    if (pr) {
        pr->mesh = now() - pr->t0;
        pr->cpu = cpu_now() - pr->c0;
    }
    /* never a silent success outside the bounds: what is left is forced, an error, or the
     * Steiner limit the user set */
    j->unmet = j->cdt_only ? 0 : mesh_count_unmet(m, &j->forced);
    j->refused = m->stats.unresolved;
    j->verdict = run_verdict_of(rr == MESH_REFINE_STEINER_LIMIT, j->unmet);
    return 0;
}

/* The cheap net (the full check is --check): the triangles' areas sum to the domain's.
 * Returns 1, or 0 with the message in err. */
static int area_net(const pslg *g, const mesh *m, char *err, size_t errlen) {
    double dom_w = 0, area_w = mesh_area(m);
    if (validate_area_net(g, area_w, &dom_w)) return 1;
    snprintf(err, errlen,
             "the mesh's area %.17g differs from the domain's %.17g by more than rounding "
             "explains (features below the precision of the coordinates)",
             ldexp(area_w, -2 * g->scale_exp), ldexp(dom_w, -2 * g->scale_exp));
    return 0;
}

/* Stage 5: the validator on f, held to the bounds only when they were met (run_check_bounds);
 * the report in j->report.  Returns 1 iff the mesh passes. */
static int check_stage(run_job *j, const pslg *g, const mesh_flat *f) {
    validate_opts vo;
    memset(&vo, 0, sizeof vo);
    run_check_bounds(j, &vo.min_angle, &vo.max_area, &vo.region_area);
    vo.region_attr = j->o.region_attr;
    return mesh_validate(g, f, &vo, &j->report);
}

/* --stats: the kernel's counters on stderr, the stats line on stdout; output_s: the seconds of
 * the output stage (flat mesh, files, --check). */
static void print_stats(const run_job *j, const mesh *m, const progress *pr, double output_s) {
    double amin = 180, amax = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        const double *a = mesh_vertex_xy(m, m->tv[3 * t]), *b = mesh_vertex_xy(m, m->tv[3 * t + 1]),
                     *c = mesh_vertex_xy(m, m->tv[3 * t + 2]);
        double an = geom_min_angle_deg(a, b, c), ar = geom_area(a, b, c);
        if (an < amin) amin = an;
        ar = ldexp(ar, -2 * m->scale_exp); /* in input units */
        if (ar > amax) amax = ar;
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    double rss = (double)ru.ru_maxrss * 1024.0;
    const mesh_stats *s = &m->stats;
    fprintf(stderr,
            "mesh: inserted=%lld seg_splits=%lld rejected=%lld blocked=%lld "
            "skipped_small=%lld failed=%lld unresolved=%lld forced=%lld mesh_bytes_per_tri=%.1f\n",
            (long long)s->inserted, (long long)s->seg_splits, (long long)s->rejected,
            (long long)s->blocked, (long long)s->skipped_small, (long long)s->failed,
            (long long)s->unresolved, (long long)j->forced,
            m->nlive ? (double)mesh_memory_bytes(m) / m->nlive : 0.0);
    printf("stats: triangles=%ld vertices=%ld steiner=%ld min_angle=%.4f max_area=%.6g "
           "mesh_s=%.3f peak_rss_mb=%.1f bytes_per_tri=%.1f output_s=%.3f cpu_s=%.3f "
           "read_s=%.3f wall_s=%.3f\n",
           (long)m->nlive, (long)m->nv, (long)(m->nv - m->ninput), amin, amax, pr->mesh,
           rss / 1048576.0, m->nlive ? rss / m->nlive : 0.0, output_s, pr->cpu,
           pr->t0 - pr->t_start, now() - pr->t_start);
}

/* Stage 6 for ./mesh: the files asked for from f.  Returns 0, or 1 after a message. */
static int write_files(const run_job *j, const pslg *g, mesh_flat *f) {
    const par_opts *o = &j->o;
    const char *prefix = o->out_prefix;
    int write_tri = prefix && par_skip_linear(o) != MESHIO_SKIP_ALL, rc = 0;
    char err[1024];
    meshio_set set; /* the run's files as one set (io/oset.h): committed once all are written */
    meshio_set_init(&set);
    if (prefix && mesh_interpolate_attributes(g, f, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s: %s\n", o->input, err);
        rc = 1;
    } else if (write_tri && meshio_write_triangle_some(f, &set, prefix, par_skip_linear(o), err,
                                                       sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    /* -e, -n, -o2 (quadratic .node/.ele and VTK), --msh: io/xwrite.h */
    mesh_xreq xr = {prefix,
                    o->edges,
                    o->neighbors,
                    o->order2,
                    o->msh,
                    o->order2 ? o->vtk : NULL,
                    par_skip_files(o),
                    &set};
    if (rc == 0 && ((prefix && (xr.edges || xr.neighbors || xr.order2)) || xr.msh || xr.vtk)) {
        if (meshio_write_extras(f, &xr, err, sizeof err) != 0) {
            fprintf(stderr, "mesh: %s\n", err);
            rc = 1;
        }
    }
    if (rc == 0 && o->vtk && !xr.vtk &&
        meshio_write_vtk(f, &set, !o->vtk_ascii, o->vtk, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    if (rc == 0 && o->svg && meshio_write_svg(f, &set, o->svg, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    if (rc == 0 && meshio_set_commit(&set, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    meshio_set_free(&set);
    return rc;
}

int run_mesh(run_job *j) {
    const par_opts *o = &j->o;
    int quiet = o->quiet, verbose = o->verbose && !quiet, rc = 0;
    char err[1024], msg[1400];
    geom_init();
    pslg g;
    double t_start = now();                                /* wall_s and read_s start here */
    if (run_load(j, &g, quiet, 1, err, sizeof err) != 0) { /* 1. load */
        fprintf(stderr, "mesh: %s\n", err);
        return 1;
    }
    mesh_bounds b = run_bounds(j, &g); /* 2. bounds */
    progress pr = {0};
    pr.t0 = pr.last = now();
    pr.t_start = t_start;
    pr.c0 = cpu_now();
    if (verbose) verbose_input(j, &g, pr.t0 - t_start);
    mesh m;
    mesh_init(&m);
    pr.m = &m;
    pr.on = !quiet && (o->progress || isatty(2));
    mesh_flat f;
    int need_flat = 0;
    if (mesh_and_judge(j, &g, &b, &m, &pr, err, sizeof err) != 0) { /* 3. mesh */
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
        goto done;
    }
    run_verdict_message(j, "", err, sizeof err); /* 4. verdict */
    if (j->verdict != RUN_MET) {
        snprintf(msg, sizeof msg, "mesh: %s: %s", o->input, err);
        fprintf(stderr, "%s\n", msg);
    }
    if (j->verdict == RUN_UNMET && !o->write_partial) goto done;
    if (j->verdict != RUN_UNMET && !area_net(&g, &m, err, sizeof err)) {
        fprintf(stderr, "mesh: %s: %s; no mesh written\n", o->input, err);
        rc = 1;
        goto done;
    }
    if (verbose)
        fprintf(stderr,
                "mesh: triangulation %.4f s, refinement %.4f s: %ld triangles, %ld vertices (%ld "
                "Steiner points)\n",
                pr.t_cdt, pr.mesh - pr.t_cdt, (long)m.nlive, (long)m.nv, (long)(m.nv - m.ninput));
    const char *prefix = o->out_prefix;
    int write_tri = prefix && par_skip_linear(o) != MESHIO_SKIP_ALL;
    need_flat = write_tri || o->vtk || o->svg || o->check || o->msh ||
                (prefix && (o->edges || o->neighbors || o->order2));
    double t_out = now(); /* output_s starts here */
    if (need_flat) {
        if (mesh_to_flat(&m, &f) != 0 || meshio_flat_domain(&f, &g) != 0)
            MESH_BUG("the flat mesh could not be made");
        if (!o->region_attr) { /* labels only for the region bounds: not written */
            free(f.tattr);
            f.tattr = NULL;
        }
        rc = write_files(j, &g, &f); /* 6. write */
    }
    double t_write = now() - t_out; /* the flat form and the files (-o, --vtk, --svg) */
    if (verbose && write_tri && rc == 0)
        fprintf(stderr, "mesh: wrote %s%s%s%s (%.3f s with the other outputs)\n", prefix,
                o->no_node ? "" : ".node ", o->no_ele ? "" : ".ele ", o->no_poly ? "" : ".poly",
                t_write);
    if (o->check) { /* 5. check (after the files, as always: a failed check names them) */
        int good = check_stage(j, &g, &f);
        if (!good) rc = 1;
        if (!quiet || !good) validate_report_print(&j->report, stdout);
    }
    if (o->stats) print_stats(j, &m, &pr, now() - t_out); /* output_s: with --check */
done:
    if (need_flat) mesh_flat_free(&f);
    mesh_free(&m);
    pslg_free(&g);
    run_job_free(j);
    return run_exit_status(j->verdict, rc); /* 7. exit status */
}

int run_mesh_flat(run_job *j, mesh_flat *f, int *scale_exp) {
    char err[1024];
    memset(f, 0, sizeof *f);
    geom_init();
    pslg g;
    if (run_load(j, &g, 1, 0, err, sizeof err) != 0) {
        snprintf(j->msg, sizeof j->msg, "%s", err);
        return 1;
    }
    mesh_bounds b = run_bounds(j, &g);
    mesh m;
    mesh_init(&m);
    int rc = 0;
    if (mesh_and_judge(j, &g, &b, &m, NULL, err, sizeof err) != 0) {
        snprintf(j->msg, sizeof j->msg, "%s", err);
        rc = 1;
    } else if (j->verdict == RUN_UNMET) {
        run_verdict_message(j, "", j->msg, sizeof j->msg);
        rc = 2;
    } else if (!area_net(&g, &m, j->msg, sizeof j->msg)) {
        rc = 2;
    } else {
        run_verdict_message(j, "", j->msg, sizeof j->msg);
        if (mesh_to_flat(&m, f) != 0) MESH_BUG("the flat mesh could not be made");
        if (!j->o.region_attr) { /* labels only for the region bounds: not returned */
            free(f->tattr);
            f->tattr = NULL;
        }
        /* the input's vertex attributes, interpolated on the new vertices (as ./mesh writes) */
        if (mesh_interpolate_attributes(&g, f, err, sizeof err) != 0) {
            snprintf(j->msg, sizeof j->msg, "%s", err);
            mesh_flat_free(f);
            rc = 1;
        }
        *scale_exp = g.scale_exp;
        if (rc == 0 &&
            j->o.check) { /* the check stage, as ./mesh --check (the harnesses' oracle) */
            if (meshio_flat_domain(f, &g) != 0) MESH_BUG("the flat mesh's domain");
            j->check_ok = check_stage(j, &g, f);
        }
    }
    mesh_free(&m);
    pslg_free(&g);
    run_job_free(j);
    return rc;
}
