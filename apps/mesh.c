/* mesh: the sequential quality mesher.  ./mesh [options] input.poly
 *
 * Reads a PSLG (Triangle's .poly or .node), builds its constrained Delaunay triangulation and
 * refines it with Ruppert/Chew Delaunay refinement (mesher/seq/mesh.h), then writes the requested
 * outputs.  Options, usage errors and exit statuses: the front end (apps/cli.c; ./mesh --help).
 * Bad input: one message "FILE:LINE: problem" and exit status 1.  With --stats the
 * last line printed is
 *   stats: triangles=N vertices=N steiner=N min_angle=D max_area=A wall_s=T peak_rss_mb=M
 *          bytes_per_tri=B
 * (one line) where wall_s is the meshing time (triangulation + refinement, no file I/O) and
 * bytes_per_tri is the process's peak resident memory divided by the number of triangles.
 */
#include "seq/mesh.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "io/meshio.h"
#include "io/validate.h"

#include "cli.h"

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

int main(int argc, char **argv) {
    cli_opts o;
    int code;
    if (cli_parse(&cli_mesh, argc, argv, stdout, stderr, &o, &code)) return code;
    const char *input = o.par.input, *prefix = o.par.out_prefix, *vtk = o.par.vtk, *svg = o.par.svg;
    double qdeg = o.par.min_angle, area = o.par.max_area;
    long long steiner = (long long)o.par.max_steiner;
    int stats = o.par.stats, check = o.par.check, cdt_only = o.cdt_only;

    geom_init();
    char err[1024];
    pslg g;
    if (pslg_read(input, &g, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        return 1;
    }
    if (pslg_check(&g, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        pslg_free(&g);
        return 1;
    }
    double t0 = now();
    mesh m;
    mesh_init(&m);
    if (mesh_build_cdt(&m, &g, NULL, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        mesh_free(&m);
        pslg_free(&g);
        return 1;
    }
    if (o.par.region_attr || o.par.region_area) mesh_set_regions(&m, &g, o.par.region_area, m.nseg);
    progress pr = {o.par.progress || isatty(2), t0, t0, &m};
    mesh_hooks h = {NULL, poll_progress, 4096, &pr};
    mesh_set_hooks(&m, &h);
    mesh_refine_result rr = MESH_REFINE_DONE;
    if (!cdt_only) {
        /* the refiner's bound sits a hair above the requested one so rounding in the quality
         * test can never leave a triangle a few ulps below it */
        mesh_quality q = {qdeg > 0 ? qdeg * (1 + 1e-9) + 1e-12 : 0, area, steiner,
                          !o.par.circumcenters, o.lens};
        mesh_set_quality(&m, &q);
        rr = mesh_refine(&m);
    }
    double wall = now() - t0;
    /* never a silent success outside the bounds (issue 10): what is left is forced, an error,
     * or the Steiner limit the user set (exit 3, the mesh written and checked without bounds) */
    int64_t forced = 0, unmet = cdt_only ? 0 : mesh_count_unmet(&m, &forced);
    int limited = rr == MESH_REFINE_STEINER_LIMIT && unmet > 0;
    if (limited)
        fprintf(stderr,
                "mesh: %s: Steiner point limit (-S %lld) reached with %lld triangles outside the "
                "bounds; the mesh is conforming but does not meet them (exit status 3)\n",
                input, steiner, (long long)unmet);
    if (unmet > 0 && !limited) {
        fprintf(stderr,
                "mesh: %s: cannot meet the bounds: %lld triangles still violate them after %lld "
                "refused splits (features below the precision of the coordinates, a region too "
                "thin for its length, or -q %g "
                "beyond what refinement reaches on this input)\n",
                input, (long long)unmet, (long long)m.stats.unresolved, qdeg);
        mesh_free(&m);
        pslg_free(&g);
        return 1;
    }

    int rc = 0;
    mesh_flat f;
    int need_flat = prefix || vtk || svg || check;
    double t_out = now();
    if (need_flat && (mesh_to_flat(&m, &f) != 0 || meshio_flat_domain(&f, &g) != 0)) {
        fprintf(stderr, "mesh: out of memory\n");
        return 1;
    }
    if (need_flat && !o.par.region_attr) { /* labels only for the region bounds: not written */
        free(f.tattr);
        f.tattr = NULL;
    }
    if (prefix && meshio_write_triangle(&f, prefix, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    if (vtk && meshio_write_vtk(&f, !o.par.vtk_ascii, vtk, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    if (svg && meshio_write_svg(&f, svg, err, sizeof err) != 0) {
        fprintf(stderr, "mesh: %s\n", err);
        rc = 1;
    }
    t_out = now() - t_out; /* the flat form and the files (-o, --vtk, --svg) */
    if (check) {
        int nob = cdt_only || limited; /* the bounds were given up: check the rest */
        validate_opts vo = {nob ? 0 : qdeg,    nob ? 0 : area,           0, 0,
                            o.par.region_attr, !nob && o.par.region_area};
        validate_report vr;
        if (!mesh_validate(&g, &f, &vo, &vr)) rc = 1;
        validate_report_print(&vr, stdout);
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
               "wall_s=%.3f peak_rss_mb=%.1f bytes_per_tri=%.1f output_s=%.3f\n",
               (long)m.nlive, (long)m.nv, (long)(m.nv - m.ninput), amin, amax, wall,
               rss / 1048576.0, m.nlive ? rss / m.nlive : 0.0, t_out);
    }
    if (need_flat) mesh_flat_free(&f);
    mesh_free(&m);
    pslg_free(&g);
    return rc == 0 && limited ? 3 : rc;
}
