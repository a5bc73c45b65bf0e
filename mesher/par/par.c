/* par.c: the layer ./pcdm and ./pbw share around their algorithms (TR-97-17 sections 3-4 leave
 * it implicit): the settings of a run, the check that every rank built the same
 * decomposition, collective error agreement, -V lines and process figures.  Start-up, loading
 * and the decomposition are the driver's (run/run_par.c).  The mesh is never gathered: the
 * interface check is par_check.c; numbering, output and --check work on each rank's part
 * (pout.c).
 *
 * Errors: every rank reads the same input, so input errors are found on every rank; the
 * decision to fail is still taken collectively (par_fail_any: an MPI_Allreduce of the lowest
 * failing rank, then that rank's message broadcast), so no rank can wait in a collective that
 * another rank skipped.
 */
#include "par/par.h"

#include "base/base.h"
#include "base/base_mpi.h"

#include "geom/geom.h"
#include "rt.h"

#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

par_config par_config_of(const par_opts *o) {
    par_config c = {.prog = o->prog,
                    .input = o->input,
                    .poll_every = o->poll_every,
                    .inflight = o->inflight,
                    .phases = o->phases,
                    .deterministic = !o->async || o->threads > 1,
                    .balance = par_balance_dynamic(o),
                    .threads = o->threads > 1 ? o->threads : 1,
                    .regions = o->region_attr || o->region_area,
                    .progress = o->progress && !o->quiet};
    return c;
}

/* ---- collective failure ----------------------------------------------------------------- */

int par_agree(int code, const char *msg, char *out, size_t outlen) {
    return mesh_agree(rt_app_comm(), code, msg, out, outlen);
}

int par_fail_any(int local_fail, const char *msg) {
    char buf[1200];
    if (!par_agree(local_fail ? 1 : 0, msg, buf, sizeof buf)) return 0;
    if (rt_rank() == 0 && buf[0]) fprintf(stderr, "%s\n", buf);
    return 1;
}

/* ---- the decomposition's agreement ------------------------------------------------------ */

static uint64_t hash_bytes(uint64_t h, const void *p, size_t n) {
    const unsigned char *b = p;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) { /* a word at a time */
        uint64_t w;
        memcpy(&w, b + i, sizeof w);
        h = mesh_hash64(h ^ w);
    }
    for (; i < n; i++)
        h = mesh_hash64(h ^ b[i]);
    return h;
}

/* Collective.  1 iff every rank has hash h. */
static int hash_agrees(uint64_t h) {
    uint64_t lo = 0, hi = 0;
    MESH_MPI(MPI_Allreduce(&h, &lo, 1, MPI_UINT64_T, MPI_MIN, rt_app_comm()));
    MESH_MPI(MPI_Allreduce(&h, &hi, 1, MPI_UINT64_T, MPI_MAX, rt_app_comm()));
    return lo == hi;
}

int par_input_agrees(const pslg *in) {
    if (rt_size() == 1) return 1;
    uint64_t h = mesh_hash64((uint64_t)in->scale_exp);
    h = hash_bytes(h, in->xy, 2 * (size_t)in->nverts * sizeof(double));
    h = hash_bytes(h, in->seg, 2 * (size_t)in->nsegs * sizeof(int32_t));
    h = hash_bytes(h, in->holes, 2 * (size_t)in->nholes * sizeof(double));
    h = hash_bytes(h, in->regions, 4 * (size_t)in->nregions * sizeof(double));
    return hash_agrees(h);
}

int par_decomp_agrees(const pcdm_decomp *d) {
    if (rt_size() == 1) return 1;
    uint64_t h = 0;
    h = hash_bytes(h, d->g.xy, 2 * (size_t)d->g.nverts * sizeof(double));
    h = hash_bytes(h, d->g.seg, 2 * (size_t)d->g.nsegs * sizeof(int32_t));
    h = hash_bytes(h, d->seg_sub, 2 * (size_t)d->g.nsegs * sizeof(int32_t));
    h = hash_bytes(h, d->sub_owner, (size_t)d->nsub * sizeof(int32_t));
    return hash_agrees(h);
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

void par_verbose_input(const par_opts *o, const pslg *in, const pcdm_decomp *d, double read_s) {
    double t[2] = {d->build_s, read_s};
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, t, 2, MPI_DOUBLE, MPI_MAX, rt_app_comm()));
    double build = t[0];
    if (rt_rank() != 0) return;
    char area[64] = "none", steiner[64] = "none";
    if (o->max_area > 0) snprintf(area, sizeof area, "%g", o->max_area);
    if (o->max_steiner >= 0) snprintf(steiner, sizeof steiner, "%lld", (long long)o->max_steiner);
    fprintf(stderr,
            "%s: %s: %ld vertices, %ld segments, %ld holes, %ld regions (read and checked in "
            "%.3f s, slowest rank)\n",
            o->prog, o->input, (long)in->nverts, (long)in->nsegs, (long)in->nholes,
            (long)in->nregions, t[1]);
    fprintf(stderr, "%s: %d ranks, %d subdomains (%s, %.4f s)\n", o->prog, rt_size(), (int)d->nsub,
            o->cuts ? "--cuts" : "automatic", build);
    fprintf(stderr, "%s: bounds: -q %g, -a %s, -S %s; %s\n", o->prog, o->min_angle, area, steiner,
            o->circumcenters ? "circumcenters" : "off-centers");
}

void par_verbose_result(const par_opts *o, double mesh_s, int64_t ntris, int64_t nverts,
                        double min_angle, double out_s) {
    double t[2] = {mesh_s, out_s};
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, t, 2, MPI_DOUBLE, MPI_MAX, rt_app_comm()));
    if (rt_rank() != 0) return;
    fprintf(stderr,
            "%s: refinement %.4f s (slowest rank): %lld triangles, %lld vertices, "
            "smallest angle %.4f degrees\n",
            o->prog, t[0], (long long)ntris, (long long)nverts, min_angle);
    if (o->out_prefix && par_skip_files(o) != MESHIO_SKIP_ALL) /* -o2: the quadratic ones */
        fprintf(stderr, "%s: wrote %s%s%s%s\n", o->prog, o->out_prefix, o->no_node ? "" : ".node ",
                o->no_ele ? "" : ".ele ", o->no_poly ? "" : ".poly");
    fprintf(stderr,
            "%s: output %.4f s (interface check, numbering, --check, files; slowest rank)\n",
            o->prog, t[1]);
}
