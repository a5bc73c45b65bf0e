/* par.c: the layer ./pcdm and ./pbw share around their algorithms (TR-97-17 sections 3-4 leave
 * it implicit): start-up (around the caller's argument parser), collective input loading and
 * decomposition, the interface check and collective error agreement.  The mesh is never
 * gathered: numbering, output and --check work on each rank's part (pout.c).
 *
 * Interface check: an interface vertex is computed by both neighbours with the same expression
 * from the same operands, so it has the same bits on both sides; every open edge of a part
 * travels to the rank its exact coordinates hash to (-0.0 folded onto +0.0), where the two
 * sides of an interface meet.
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

#include <fcntl.h>
#include <limits.h>
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

/* pslg_check's warnings (merged duplicates) would be printed once per rank; only rank 0 keeps
 * stderr while it runs. */
static int check_quietly(pslg *g, char *err, size_t errlen) {
    if (rt_rank() == 0) return pslg_check(g, err, errlen);
    fflush(stderr);
    int saved = dup(2), devnull = open("/dev/null", O_WRONLY);
    if (saved >= 0 && devnull >= 0) dup2(devnull, 2);
    int rc = pslg_check(g, err, errlen);
    fflush(stderr);
    if (saved >= 0 && devnull >= 0) dup2(saved, 2);
    if (saved >= 0) close(saved);
    if (devnull >= 0) close(devnull);
    return rc;
}

int par_load(const par_opts *o, pslg *in, pcdm_decomp *d) {
    char err[1024], msg[1200];
    memset(in, 0, sizeof *in);
    memset(d, 0, sizeof *d);
    geom_init();
    int rc = pslg_read(o->input, in, err, sizeof err);
    if (rc == 0) rc = check_quietly(in, err, sizeof err);
    if (rc == 0) {
        pcdm_decomp_opts dopt;
        pcdm_decomp_opts_default(&dopt);
        dopt.nsub = o->nsub;
        dopt.nranks = rt_size();
        dopt.min_angle = o->min_angle;
        dopt.max_area = o->max_area;
        dopt.imbalance = o->imbalance;
        int32_t k = o->nsub > 0 ? o->nsub : rt_size();
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
        } else if (o->cuts) {
            rc = pcdm_decomp_read_cuts(o->cuts, in, &dopt, d, err, sizeof err);
        } else {
            rc = pcdm_decomp_auto(in, &dopt, d, err, sizeof err);
        }
        if (rc != 0) {
            char tmp[sizeof err];
            memcpy(tmp, err, sizeof tmp);
            tmp[sizeof tmp - 200] = 0; /* room for the prefix below */
            snprintf(err, sizeof err, "cannot decompose %.150s for %d ranks: %.800s", o->input,
                     rt_size(), tmp);
        }
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

/* ---- exact coordinate keys --------------------------------------------------------------- */

static uint64_t key_bits(double x) {
    if (x == 0) x = 0; /* -0.0 and +0.0 are one point */
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
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

/* ---- the interface check ------------------------------------------------------------------ */

/* One open edge of a rank's piece, endpoints in lexicographic order (exact bits). */
typedef struct open_edge {
    double x[4];
    int32_t rank;
    int32_t must; /* 1: must be matched by another rank's piece (not a domain-boundary segment) */
} open_edge;
_Static_assert(sizeof(open_edge) == 40, "open_edge must be 40 bytes, no padding");

typedef struct ekey {
    int32_t lo, hi, n;
} ekey;

static int cmp_ekey(const void *x, const void *y) {
    const ekey *a = x, *b = y;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    return (a->hi > b->hi) - (a->hi < b->hi);
}

static int cmp_open(const void *x, const void *y) {
    const open_edge *a = x, *b = y;
    for (int k = 0; k < 4; k++)
        if (a->x[k] != b->x[k]) return a->x[k] < b->x[k] ? -1 : 1;
    return (a->rank > b->rank) - (a->rank < b->rank);
}

static uint64_t edge_hash(const open_edge *e) {
    uint64_t h = 0;
    for (int k = 0; k < 4; k++)
        h = mesh_hash64(h ^ key_bits(e->x[k]));
    return h;
}

/* The open edges of local (edges of exactly one local triangle). */
static int32_t open_edges(const mesh_flat *f, int rank, open_edge **out) {
    ekey *k = mesh_xmalloc(3 * (size_t)f->ntris + (size_t)f->nsegs + 1, sizeof(ekey));
    int32_t n = 0;
    for (int32_t t = 0; t < f->ntris; t++)
        for (int j = 0; j < 3; j++) {
            int32_t a = f->tri[3 * t + j], b = f->tri[3 * t + (j + 1) % 3];
            k[n++] = (ekey){a < b ? a : b, a < b ? b : a, 0};
        }
    for (int32_t s = 0; s < f->nsegs; s++) { /* n = 1: a boundary subsegment; 2: an interface */
        int32_t a = f->seg[2 * s], b = f->seg[2 * s + 1];
        k[n++] =
            (ekey){a < b ? a : b, a < b ? b : a, 1 + (f->sinterface ? f->sinterface[s] != 0 : 0)};
    }
    qsort(k, (size_t)n, sizeof *k, cmp_ekey);
    open_edge *o = mesh_xmalloc((size_t)n + 1, sizeof(open_edge));
    int32_t no = 0;
    for (int32_t i = 0; i < n;) {
        int32_t j = i, tris = 0, segkind = 0;
        while (j < n && k[j].lo == k[i].lo && k[j].hi == k[i].hi) {
            if (k[j].n == 0)
                tris++;
            else
                segkind = k[j].n;
            j++;
        }
        if (tris == 1) {
            const double *p = f->xy + 2 * (size_t)k[i].lo, *q = f->xy + 2 * (size_t)k[i].hi;
            int sw = p[0] > q[0] || (p[0] == q[0] && p[1] > q[1]);
            open_edge *e = &o[no++];
            memset(e, 0, sizeof *e);
            e->x[0] = sw ? q[0] : p[0];
            e->x[1] = sw ? q[1] : p[1];
            e->x[2] = sw ? p[0] : q[0];
            e->x[3] = sw ? p[1] : q[1];
            e->rank = rank;
            e->must = segkind != 1;
        }
        i = j;
    }
    mesh_xfree(k);
    *out = o;
    return no;
}

int par_check_interfaces(const mesh_flat *local, char *msg, size_t msglen) {
    MPI_Comm c = rt_app_comm();
    int rank = rt_rank(), P = rt_size();
    open_edge *e = NULL;
    int32_t n = open_edges(local, rank, &e);
    int *scnt = mesh_xcalloc((size_t)P, sizeof(int)), *rcnt = mesh_xcalloc((size_t)P, sizeof(int));
    int *sdsp = mesh_xcalloc((size_t)P + 1, sizeof(int)),
        *rdsp = mesh_xcalloc((size_t)P + 1, sizeof(int));
    int *dest = mesh_xmalloc((size_t)n + 1, sizeof(int));
    for (int32_t i = 0; i < n; i++) {
        dest[i] = (int)(edge_hash(&e[i]) % (uint64_t)P);
        scnt[dest[i]] += (int)sizeof(open_edge);
    }
    MESH_MPI(MPI_Alltoall(scnt, 1, MPI_INT, rcnt, 1, MPI_INT, c));
    for (int r = 0; r < P; r++) {
        sdsp[r + 1] = sdsp[r] + scnt[r];
        rdsp[r + 1] = rdsp[r] + rcnt[r];
    }
    open_edge *sb = mesh_xmalloc((size_t)n + 1, sizeof(open_edge));
    int *fill = mesh_xcalloc((size_t)P, sizeof(int));
    for (int32_t i = 0; i < n; i++) {
        sb[(sdsp[dest[i]] + fill[dest[i]]) / (int)sizeof(open_edge)] = e[i];
        fill[dest[i]] += (int)sizeof(open_edge);
    }
    int32_t nr = rdsp[P] / (int)sizeof(open_edge);
    open_edge *rb = mesh_xmalloc((size_t)nr + 1, sizeof(open_edge));
    MESH_MPI(MPI_Alltoallv(sb, scnt, sdsp, MPI_BYTE, rb, rcnt, rdsp, MPI_BYTE, c));
    qsort(rb, (size_t)nr, sizeof *rb, cmp_open);
    int bad = 0;
    char m[400] = "";
    for (int32_t i = 0; i < nr;) {
        int32_t j = i, must = 0;
        while (j < nr && !memcmp(rb[j].x, rb[i].x, sizeof rb[i].x)) {
            must |= rb[j].must;
            j++;
        }
        int ok = (j - i == 1 && !must) || (j - i == 2 && rb[i].rank != rb[i + 1].rank);
        if (!ok && !bad++)
            snprintf(m, sizeof m,
                     "interface check failed: edge (%.17g, %.17g)-(%.17g, %.17g) of rank %d %s",
                     rb[i].x[0], rb[i].x[1], rb[i].x[2], rb[i].x[3], (int)rb[i].rank,
                     j - i == 1 ? "has no matching edge on the other side of the interface"
                                : "is claimed by more than two pieces");
        i = j;
    }
    if (bad && msglen) snprintf(msg, msglen, "%s (%d edges disagree here)", m, bad);
    mesh_xfree(e);
    mesh_xfree(sb);
    mesh_xfree(rb);
    mesh_xfree(scnt);
    mesh_xfree(rcnt);
    mesh_xfree(sdsp);
    mesh_xfree(rdsp);
    mesh_xfree(dest);
    mesh_xfree(fill);
    return bad ? -1 : 0;
}
