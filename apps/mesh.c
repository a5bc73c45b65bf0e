/* mesh: the sequential quality mesher.  ./mesh [options] input.poly
 *
 * Reads a PSLG (Triangle's .poly or .node), builds its constrained Delaunay triangulation and
 * refines it with Ruppert/Chew Delaunay refinement (mesher/seq/mesh.h), then writes the requested
 * outputs: the Triangle files where Triangle puts them unless -o names a prefix (or -NEP none).
 * -Q keeps stdout and stderr for errors (and --stats); -V adds a summary on stderr.  Bounds
 * refinement cannot reach end with a message and exit 1, the mesh written only with
 * --write-partial.  Options, usage errors and exit statuses: the front end (apps/cli.c; ./mesh
 * --help). Bad input: one message "FILE:LINE: problem" and exit status 1.  With --stats the last
 * line printed is stats: triangles=N vertices=N steiner=N min_angle=D max_area=A wall_s=T
 * peak_rss_mb=M bytes_per_tri=B output_s=O cpu_s=C (one line) where wall_s is the meshing time
 * (triangulation + refinement, no file I/O), cpu_s the process's CPU time over the same stretch,
 * and bytes_per_tri is the process's peak resident memory divided by the number of triangles.
 */
#include "seq/mesh.h"
#include "check/validate.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "io/meshio.h"
#include "io/sizefield.h"
#include "io/xwrite.h"
#include "seq/vattr.h"

#include "cli.h"

#include <math.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
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
static void verbose_input(const cli_opts *o, const pslg *g, double read_s) {
    char area[64] = "none", steiner[64] = "none";
    if (o->par.max_area > 0) snprintf(area, sizeof area, "%g", o->par.max_area);
    if (o->par.max_steiner >= 0)
        snprintf(steiner, sizeof steiner, "%lld", (long long)o->par.max_steiner);
    fprintf(stderr,
            "mesh: %s: %ld vertices, %ld segments, %ld holes, %ld regions (read and checked in "
            "%.3f s)\n",
            o->par.input, (long)g->nverts, (long)g->nsegs, (long)g->nholes, (long)g->nregions,
            read_s);
    if (o->cdt_only)
        fprintf(stderr, "mesh: bounds: none (--cdt-only)\n");
    else
        fprintf(stderr, "mesh: bounds: -q %g, -a %s, -S %s; %s, diametral %s\n", o->par.min_angle,
                area, steiner, o->par.circumcenters ? "circumcenters" : "off-centers",
                o->lens ? "lenses" : "circles");
}

int main(int argc, char **argv) {
    cli_opts o;
    int code;
#if defined(__GLIBC__)
    /* The mesh's arrays grow by doubling.  glibc serves blocks below its mmap threshold, which
     * it raises up to 32 MB as blocks are freed, from the heap, where a realloc copies and
     * leaves the old block resident: on a 49K-vertex coastline that was 20-30 MB of peak RSS
     * (at 1M and at 10M triangles).  Above a fixed 256 KB threshold a growing array is mapped
     * and realloc moves its pages without copying. */
    mallopt(M_MMAP_THRESHOLD, 256 * 1024);
#endif
    if (cli_parse(&cli_mesh, argc, argv, stdout, stderr, &o, &code)) return code;
    const char *input = o.par.input, *prefix = o.par.out_prefix, *vtk = o.par.vtk, *svg = o.par.svg;
    double qdeg = o.par.min_angle, area = o.par.max_area;
    long long steiner = (long long)o.par.max_steiner;
    int stats = o.par.stats, check = o.par.check, cdt_only = o.cdt_only;
    int quiet = o.par.quiet, verbose = o.par.verbose && !quiet;
    /* the Triangle files: prefix is -o's or Triangle's name (the front end's); -NEP: none */
    int write_tri = prefix && par_skip_linear(&o.par) != MESHIO_SKIP_ALL;

    geom_init();
    char err[1024];
    pslg g;
    double t_read = now();
    if ((o.par.refine ? size_field_read_mesh_pslg(input, &g, err, sizeof err)
                      : pslg_read(input, &g, err, sizeof err)) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        return 1;
    }
    g.quiet = quiet; /* -Q: no warnings (merged duplicates) */
    unsigned flags = (o.par.strict ? 0u : PSLG_SPLIT) | (o.par.convex_hull ? PSLG_HULL : 0u);
    if (pslg_check_ex(&g, flags, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        pslg_free(&g);
        return 1;
    }
    if (pslg_boundary_markers(&g) != 0) { /* Triangle's marker rules, inherited by the mesh */
        fprintf(stderr, "mesh: %s: out of memory\n", input);
        pslg_free(&g);
        return 1;
    }
    /* -r with -a alone: the old mesh's .area; --size: a background mesh (sizefield.h) */
    size_field sizes;
    if (size_field_load(&sizes, o.par.refine && o.par.region_area ? input : NULL, o.par.size_field,
                        g.scale_exp, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        pslg_free(&g);
        return 1;
    }
    double t0 = now(), c0 = cpu_now();
    if (verbose) verbose_input(&o, &g, t0 - t_read);
    mesh m;
    mesh_init(&m);
    if (mesh_build_cdt(&m, &g, NULL, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        mesh_free(&m);
        pslg_free(&g);
        return 1;
    }
    if (o.par.region_attr || o.par.region_area) mesh_set_regions(&m, &g, o.par.region_area, m.nseg);
    double t_cdt = now() - t0;
    progress pr = {!quiet && (o.par.progress || isatty(2)), t0, t0, &m};
    mesh_hooks h = {NULL, poll_progress, 4096, &pr};
    mesh_set_hooks(&m, &h);
    mesh_refine_result rr = MESH_REFINE_DONE;
    if (!cdt_only) {
        /* the refiner's bound sits a hair above the requested one so rounding in the quality
         * test can never leave a triangle a few ulps below it */
        mesh_quality q = {qdeg > 0 ? qdeg * (1 + 1e-9) + 1e-12 : 0, area, steiner,
                          !o.par.circumcenters, o.lens};
        mesh_set_quality(&m, &q);
        if (sizes.active) mesh_set_size_rule(&m, size_field_unsuitable, &sizes);
        rr = mesh_refine(&m);
    }
    double wall = now() - t0, cpu = cpu_now() - c0;
    /* never a silent success outside the bounds (issue 10): what is left is forced, an error,
     * or the Steiner limit the user set (exit 3, the mesh written and checked without bounds) */
    int64_t forced = 0, unmet = cdt_only ? 0 : mesh_count_unmet(&m, &forced);
    int limited = rr == MESH_REFINE_STEINER_LIMIT && unmet > 0;
    if (limited)
        fprintf(stderr,
                "mesh: %s: Steiner point limit (-S %lld) reached with %lld triangles outside the "
                "bounds; the mesh is conforming but does not meet them (exit status 3)\n",
                input, steiner, (long long)unmet);
    /* bounds refinement cannot reach: an error; the mesh made so far is written (and checked
     * without the bounds) only when --write-partial asks for it */
    int partial = unmet > 0 && !limited;
    if (partial) {
        fprintf(stderr,
                "mesh: %s: cannot meet the bounds: %lld triangles still violate them after %lld "
                "refused splits (features below the precision of the coordinates, a region too "
                "thin for its length, or -q %g "
                "beyond what refinement reaches on this input)%s\n",
                input, (long long)unmet, (long long)m.stats.unresolved, qdeg,
                o.par.write_partial ? "; writing the mesh made so far (--write-partial)" : "");
        if (!o.par.write_partial) {
            mesh_free(&m);
            pslg_free(&g);
            return 1;
        }
    }
    /* the cheap net (the full check is --check): the triangles' areas sum to the domain's */
    double dom_w = 0, area_w = mesh_area(&m);
    if (!partial && !validate_area_net(&g, area_w, &dom_w)) {
        fprintf(stderr,
                "mesh: %s: the mesh's area %.17g differs from the domain's %.17g by more than "
                "rounding explains (features below the precision of the coordinates); no mesh "
                "written\n",
                input, ldexp(area_w, -2 * g.scale_exp), ldexp(dom_w, -2 * g.scale_exp));
        mesh_free(&m);
        pslg_free(&g);
        return 1;
    }
    if (verbose)
        fprintf(stderr,
                "mesh: triangulation %.4f s, refinement %.4f s: %ld triangles, %ld vertices (%ld "
                "Steiner points)\n",
                t_cdt, wall - t_cdt, (long)m.nlive, (long)m.nv, (long)(m.nv - m.ninput));

    int rc = 0;
    mesh_flat f;
    int need_flat = write_tri || vtk || svg || check || o.par.msh ||
                    (prefix && (o.par.edges || o.par.neighbors || o.par.order2));
    double t_out = now();
    if (need_flat && (mesh_to_flat(&m, &f) != 0 || meshio_flat_domain(&f, &g) != 0)) {
        fprintf(stderr, "mesh: out of memory\n");
        return 1;
    }
    if (need_flat && !o.par.region_attr) { /* labels only for the region bounds: not written */
        free(f.tattr);
        f.tattr = NULL;
    }
    if (prefix && mesh_interpolate_attributes(&g, &f, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s: %s\n", input, err);
        rc = 1;
    } else if (write_tri && meshio_write_triangle_some(&f, prefix, par_skip_linear(&o.par), err,
                                                       sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    /* -e, -n, -o2 (quadratic .node/.ele and VTK), --msh: io/xwrite.h */
    mesh_xreq xr = {prefix,
                    o.par.edges,
                    o.par.neighbors,
                    o.par.order2,
                    o.par.msh,
                    o.par.order2 ? vtk : NULL,
                    par_skip_files(&o.par)};
    if ((prefix && (xr.edges || xr.neighbors || xr.order2)) || xr.msh || xr.vtk) {
        if (meshio_write_extras(&f, &xr, err, sizeof err) != 0) {
            fprintf(stderr, "mesh: %s\n", err);
            rc = 1;
        }
    }
    if (vtk && !xr.vtk && meshio_write_vtk(&f, !o.par.vtk_ascii, vtk, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    if (svg && meshio_write_svg(&f, svg, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    t_out = now() - t_out; /* the flat form and the files (-o, --vtk, --svg) */
    if (verbose && write_tri && rc == 0)
        fprintf(stderr, "mesh: wrote %s%s%s%s (%.3f s with the other outputs)\n", prefix,
                o.par.no_node ? "" : ".node ", o.par.no_ele ? "" : ".ele ",
                o.par.no_poly ? "" : ".poly", t_out);
    if (check) {
        int nob = cdt_only || limited || partial; /* the bounds were given up: check the rest */
        validate_opts vo = {nob ? 0 : qdeg,    nob ? 0 : area,           0, 0,
                            o.par.region_attr, !nob && o.par.region_area};
        validate_report vr;
        int good = mesh_validate(&g, &f, &vo, &vr);
        if (!good) rc = 1;
        if (!quiet || !good) validate_report_print(&vr, stdout);
    }
    if (stats) {
        double amin = 180, amax = 0;
        for (int32_t t = 0; t < m.nt; t++) {
            if (!mesh_tri_alive(&m, t)) continue;
            const double *a = mesh_vertex_xy(&m, m.tv[3 * t]),
                         *b = mesh_vertex_xy(&m, m.tv[3 * t + 1]),
                         *c = mesh_vertex_xy(&m, m.tv[3 * t + 2]);
            double an = geom_min_angle_deg(a, b, c), ar = geom_area(a, b, c);
            if (an < amin) amin = an;
            ar = ldexp(ar, -2 * m.scale_exp); /* in input units */
            if (ar > amax) amax = ar;
        }
        struct rusage ru;
        getrusage(RUSAGE_SELF, &ru);
        double rss = (double)ru.ru_maxrss * 1024.0;
        const mesh_stats *s = &m.stats;
        fprintf(
            stderr,
            "mesh: inserted=%lld seg_splits=%lld rejected=%lld blocked=%lld "
            "skipped_small=%lld failed=%lld unresolved=%lld forced=%lld mesh_bytes_per_tri=%.1f\n",
            (long long)s->inserted, (long long)s->seg_splits, (long long)s->rejected,
            (long long)s->blocked, (long long)s->skipped_small, (long long)s->failed,
            (long long)s->unresolved, (long long)forced,
            m.nlive ? (double)mesh_memory_bytes(&m) / m.nlive : 0.0);
        printf("stats: triangles=%ld vertices=%ld steiner=%ld min_angle=%.4f max_area=%.6g "
               "wall_s=%.3f peak_rss_mb=%.1f bytes_per_tri=%.1f output_s=%.3f cpu_s=%.3f\n",
               (long)m.nlive, (long)m.nv, (long)(m.nv - m.ninput), amin, amax, wall,
               rss / 1048576.0, m.nlive ? rss / m.nlive : 0.0, t_out, cpu);
    }
    if (need_flat) mesh_flat_free(&f);
    mesh_free(&m);
    pslg_free(&g);
    size_field_free(&sizes);
    return partial ? 1 : rc == 0 && limited ? 3 : rc;
}
