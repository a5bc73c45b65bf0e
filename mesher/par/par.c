/* par.c: the layer ./pcdm and ./pbw share around their algorithms (TR-97-17 sections 3-4 leave
 * it implicit): start-up (around the caller's argument parser), collective input loading and
 * decomposition and collective error agreement.  The mesh is never gathered: the interface
 * check is par_check.c; numbering, output and --check work on each rank's part (pout.c).
 *
 * Decomposition: the automatic one (a coarse quality mesh partitioned by METIS, decomp.h) or
 * a cuts file; more than PAR_MAX_SUBDOMAINS subdomains are refused.  Whether the domain is
 * empty is the triangulator's exact decision, not a floating-point area.
 *
 * Errors: every rank reads the same input, so input errors are found on every rank; the
 * decision to fail is still taken collectively (par_fail_any: an MPI_Allreduce of the lowest
 * failing rank, then that rank's message broadcast), so no rank can wait in a collective that
 * another rank skipped.
 */
#include "par/par.h"

#include "base/base.h"

#include "geom/geom.h"
#include "rt.h"

#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

/* ---- collective failure ----------------------------------------------------------------- */

int par_fail_any(int local_fail, const char *msg) {
    MPI_Comm c = rt_app_comm();
    int rank = rt_rank(), size = rt_size();
    int mine = local_fail ? rank : size, first = size;
    MESH_MPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, c));
    if (first == size) return 0;
    char buf[1024];
    memset(buf, 0, sizeof buf);
    if (rank == first && msg) snprintf(buf, sizeof buf, "%s", msg);
    MESH_MPI(MPI_Bcast(buf, (int)sizeof buf, MPI_CHAR, first, c));
    if (rank == 0 && buf[0]) fprintf(stderr, "%s\n", buf);
    return 1;
}

/* ---- loading ---------------------------------------------------------------------------- */

/* pslg_check_ex, its warnings (merged duplicates) printed by rank 0 only, and not even there
 * with -Q (pslg.quiet); its errors come back in err. */
static int check_quietly(pslg *g, int quiet, unsigned flags, char *err, size_t errlen) {
    g->quiet = quiet || rt_rank() != 0;
    return pslg_check_ex(g, flags, err, errlen);
}

static uint64_t hash_bytes(uint64_t h, const void *p, size_t n) {
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = mesh_hash64(h ^ b[i]);
    return h;
}

int par_decomp_agrees(const pcdm_decomp *d) {
    uint64_t h = 0;
    h = hash_bytes(h, d->g.xy, 2 * (size_t)d->g.nverts * sizeof(double));
    h = hash_bytes(h, d->g.seg, 2 * (size_t)d->g.nsegs * sizeof(int32_t));
    h = hash_bytes(h, d->seg_sub, 2 * (size_t)d->g.nsegs * sizeof(int32_t));
    h = hash_bytes(h, d->sub_owner, (size_t)d->nsub * sizeof(int32_t));
    uint64_t lo = 0, hi = 0;
    MESH_MPI(MPI_Allreduce(&h, &lo, 1, MPI_UINT64_T, MPI_MIN, rt_app_comm()));
    MESH_MPI(MPI_Allreduce(&h, &hi, 1, MPI_UINT64_T, MPI_MAX, rt_app_comm()));
    return lo == hi;
}

int par_load(const par_opts *o, pslg *in, pcdm_decomp *d) {
    char err[1024], msg[1200];
    memset(in, 0, sizeof *in);
    memset(d, 0, sizeof *d);
    geom_init();
    int rc = o->refine ? size_field_read_mesh_pslg(o->input, in, err, sizeof err)
                       : pslg_read(o->input, in, err, sizeof err);
    unsigned flags = (o->strict ? 0u : PSLG_SPLIT) | (o->convex_hull ? PSLG_HULL : 0u);
    if (rc == 0) rc = check_quietly(in, o->quiet, flags, err, sizeof err);
    if (rc == 0 && pslg_boundary_markers(in) != 0) { /* Triangle's rules, as ./mesh */
        snprintf(err, sizeof err, "%s: out of memory", o->input);
        rc = -1;
    }
    if (rc == 0) {
        pcdm_decomp_opts dopt;
        pcdm_decomp_opts_default(&dopt);
        /* --balance dynamic moves whole subdomains: several per rank by default */
        int32_t k = o->nsub > 0 ? o->nsub : rt_size() * (par_balance_dynamic(o) ? 4 : 1);
        if (!o->nsub && k > PAR_MAX_SUBDOMAINS && rt_size() <= PAR_MAX_SUBDOMAINS)
            k = PAR_MAX_SUBDOMAINS;
        dopt.nsub = o->cuts ? o->nsub : k; /* cuts: 0 = as many as they make */
        dopt.nranks = rt_size();
        dopt.min_angle = o->min_angle;
        dopt.max_area = o->max_area;
        dopt.imbalance = o->imbalance;
        dopt.max_steiner = o->max_steiner;
        dopt.region_area = o->region_area;
        if (!o->cuts && k > PAR_MAX_SUBDOMAINS) {
            snprintf(err, sizeof err,
                     "%d subdomains: the automatic decomposition supports at most %d (fewer "
                     "ranks or --subdomains, or give --cuts)",
                     (int)k, PAR_MAX_SUBDOMAINS);
            rc = -1;
        } else if (o->nsub > 0 && o->nsub < rt_size()) {
            snprintf(err, sizeof err, "--subdomains %d: fewer subdomains than ranks (%d)",
                     (int)o->nsub, rt_size());
            rc = -1;
        } else {
            double t0 = rt_wtime();
            if (o->cuts)
                rc = pcdm_decomp_read_cuts(o->cuts, in, &dopt, d, err, sizeof err);
            else
                rc = pcdm_decomp_auto(in, &dopt, d, err, sizeof err);
            if (rc == 0) d->build_s = rt_wtime() - t0;
        }
        if (rc != 0) {
            char tmp[sizeof err];
            memcpy(tmp, err, sizeof tmp);
            tmp[sizeof tmp - 200] = 0; /* room for the prefix below */
            snprintf(err, sizeof err, "cannot decompose %.150s for %d ranks: %.800s", o->input,
                     rt_size(), tmp);
        }
    }
    int failed = rc != 0, failed_any = 0;
    MESH_MPI(MPI_Allreduce(&failed, &failed_any, 1, MPI_INT, MPI_MAX, rt_app_comm()));
    if (!failed_any && !par_decomp_agrees(d)) {
        snprintf(err, sizeof err, "the ranks computed different decompositions of %.200s",
                 o->input);
        rc = -1;
    }
    if (rc == 0 && o->write_cuts && rt_rank() == 0) {
        if (pcdm_decomp_write_cuts(d, o->write_cuts, err, sizeof err) != 0) rc = -1;
    }
    snprintf(msg, sizeof msg, "%s: %s", o->prog, err);
    if (par_fail_any(rc != 0, msg)) {
        pslg_free(in); /* both zero what they free and accept a zeroed struct */
        pcdm_decomp_free(d);
        return -1;
    }
    return 0;
}

int par_startup(int *argc, char ***argv, const char *prog, par_parse_fn parse, const void *ctx,
                int (*reg)(void), par_opts *o, pslg *in, pcdm_decomp *d, int *code) {
    int rc = rt_init(argc, argv, NULL);
    if (rc != RT_OK) {
        fprintf(stderr, "%s: runtime initialisation failed: %s\n", prog, rt_strerror(rc));
        *code = 1;
        return 1;
    }
    /* every rank parses the same arguments; the agreement below only guards against a rank
     * that saw others (every rank must stop, or none, with one status) */
    int status = 0, stop = parse(*argc, *argv, rt_rank(), ctx, o, &status) ? status : -1;
    int agreed = stop;
    MESH_MPI(MPI_Allreduce(&stop, &agreed, 1, MPI_INT, MPI_MAX, rt_app_comm()));
    if (agreed >= 0) {
        rt_finalize();
        *code = agreed;
        return 1;
    }
    if ((rc = reg()) != 0) {
        fprintf(stderr, "%s: cannot register the handlers: %s\n", prog, rt_strerror(rc));
        rt_finalize();
        *code = 1;
        return 1;
    }
    if (o->perturb) rt_perturb_set(o->perturb);
    if (o->net) { /* every rank parses the same text: all stop or none */
        double lat = 0, bw = 0;
        if (rt_net_parse(o->net, &lat, &bw) != RT_OK) {
            if (rt_rank() == 0)
                fprintf(stderr,
                        "%s: --net '%s': want off, sp2 or LAT_US[,MBPS] (microseconds, "
                        "megabytes per second)\n",
                        prog, o->net);
            rt_finalize();
            *code = 2;
            return 1;
        }
        rt_net_set(lat, bw);
    }
    /* Triangle's output name (no -o): rank 0 decides, every rank writes to the same files */
    int named = o->out_prefix == o->out_name;
    MESH_MPI(MPI_Bcast(&named, 1, MPI_INT, 0, rt_app_comm()));
    MESH_MPI(MPI_Bcast(o->out_name, (int)sizeof o->out_name, MPI_CHAR, 0, rt_app_comm()));
    if (named) o->out_prefix = o->out_name;
    geom_init();
    if (par_load(o, in, d) != 0) {
        rt_finalize();
        *code = 1;
        return 1;
    }
    *code = 0;
    return 0;
}

double par_mesh_quality(const mesh_flat *g, double *max_area) {
    double amin = 180, amax = 0;
    for (int32_t t = 0; t < g->ntris; t++) {
        const double *a = g->xy + 2 * (size_t)g->tri[3 * (size_t)t],
                     *b = g->xy + 2 * (size_t)g->tri[3 * (size_t)t + 1],
                     *c = g->xy + 2 * (size_t)g->tri[3 * (size_t)t + 2];
        double an = geom_min_angle_deg(a, b, c), ar = geom_area(a, b, c);
        if (an < amin) amin = an;
        if (ar > amax) amax = ar;
    }
    if (max_area) *max_area = amax;
    return amin;
}

double par_cpu_seconds(void) {
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0;
    return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
           (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
}

long par_peak_rss_bytes(void) {
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0;
    return (long)ru.ru_maxrss * 1024L;
}

/* ---- -V --------------------------------------------------------------------------------- */

void par_verbose_input(const par_opts *o, const pslg *in, const pcdm_decomp *d) {
    double build = d->build_s;
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, &build, 1, MPI_DOUBLE, MPI_MAX, rt_app_comm()));
    if (rt_rank() != 0) return;
    char area[64] = "none", steiner[64] = "none";
    if (o->max_area > 0) snprintf(area, sizeof area, "%g", o->max_area);
    if (o->max_steiner >= 0) snprintf(steiner, sizeof steiner, "%lld", (long long)o->max_steiner);
    fprintf(stderr, "%s: %s: %ld vertices, %ld segments, %ld holes, %ld regions\n", o->prog,
            o->input, (long)in->nverts, (long)in->nsegs, (long)in->nholes, (long)in->nregions);
    fprintf(stderr, "%s: %d ranks, %d subdomains (%s, %.4f s)\n", o->prog, rt_size(), (int)d->nsub,
            o->cuts ? "--cuts" : "automatic", build);
    fprintf(stderr, "%s: bounds: -q %g, -a %s, -S %s; %s\n", o->prog, o->min_angle, area, steiner,
            o->circumcenters ? "circumcenters" : "off-centers");
}

void par_verbose_result(const par_opts *o, double wall, int64_t ntris, int64_t nverts,
                        double min_angle, double out_s) {
    double t[2] = {wall, out_s};
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, t, 2, MPI_DOUBLE, MPI_MAX, rt_app_comm()));
    if (rt_rank() != 0) return;
    fprintf(stderr,
            "%s: refinement %.4f s (slowest rank): %lld triangles, %lld vertices, "
            "smallest angle %.4f degrees\n",
            o->prog, t[0], (long long)ntris, (long long)nverts, min_angle);
    if (o->out_prefix && par_skip_files(o) != MESHIO_SKIP_ALL) /* -o2: the quadratic ones */
        fprintf(stderr, "%s: wrote %s%s%s%s\n", o->prog, o->out_prefix, o->no_node ? "" : ".node ",
                o->no_ele ? "" : ".ele ", o->no_poly ? "" : ".poly");
    fprintf(stderr, "%s: output %.4f s (numbering, --check, files; slowest rank)\n", o->prog, t[1]);
}
