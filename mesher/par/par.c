/* par.c: the layer ./pcdm and ./pbw share around their algorithms (TR-97-17 sections 3-4 leave
 * it implicit): start-up (around the caller's argument parser), collective input loading and
 * decomposition, the gather of the
 * per-rank pieces into one conforming mesh on rank 0, output files, validation and collective
 * error agreement.
 *
 * Gather algorithm: every rank sends its local mesh_flat (all its vertices, its triangles, its
 * subsegments) to rank 0, one rank at a time (rank 0 merges piece by piece, so it never holds
 * more than one foreign piece).  Vertices are merged by their exact coordinate bits in an
 * open-addressing hash table (-0.0 is folded onto +0.0): an interface vertex is computed by
 * both neighbours with the same expression from the same operands, so it has the same bits on
 * both sides.  The input's vertices are entered first, in input order, so they keep their input
 * numbers; other vertices get numbers in order of first reference (unreferenced Steiner
 * vertices are dropped).  Subsegments are de-duplicated by their unordered pair of global
 * vertex ids; a pair listed by both sides keeps the first marker and is an interface if either
 * side says so.  Invariant: the merged vertex count equals the number of distinct points.
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

#define PAR_TAG_GATHER 1 /* on rt_app_comm(), which this layer owns */

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

/* ---- gather ----------------------------------------------------------------------------- */

typedef struct vhash {
    int32_t *slot; /* global vertex id or -1 */
    uint64_t mask;
} vhash;

static uint64_t key_bits(double x) {
    if (x == 0) x = 0; /* -0.0 and +0.0 are one point */
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static uint64_t point_hash(const double p[2]) {
    return mesh_hash64(key_bits(p[0]) * 0x9e3779b97f4a7c15ULL ^ mesh_hash64(key_bits(p[1])));
}

static int same_point(const double *a, const double *b) {
    return key_bits(a[0]) == key_bits(b[0]) && key_bits(a[1]) == key_bits(b[1]);
}

typedef struct gbuild {
    mesh_flat *g;
    int32_t vcap, tcap, scap;
    vhash vh;
    int64_t *shash; /* segment pair keys, -1 empty */
    int32_t *sidx;
    uint64_t smask;
} gbuild;

/* Global id of point p (vertex marker mk), added if new. */
static int32_t gb_vertex(gbuild *b, const double p[2], int32_t mk) {
    mesh_flat *g = b->g;
    uint64_t h = point_hash(p) & b->vh.mask;
    for (;;) {
        int32_t id = b->vh.slot[h];
        if (id < 0) break;
        if (same_point(g->xy + 2 * (size_t)id, p)) return id;
        h = (h + 1) & b->vh.mask;
    }
    if (g->nverts == b->vcap) {
        b->vcap = b->vcap ? 2 * b->vcap : 1024;
        g->xy = mesh_xrealloc(g->xy, 2 * (size_t)b->vcap * sizeof(double), 1);
        g->vmarker = mesh_xrealloc(g->vmarker, (size_t)b->vcap * sizeof(int32_t), 1);
    }
    int32_t id = g->nverts++;
    g->xy[2 * (size_t)id] = p[0];
    g->xy[2 * (size_t)id + 1] = p[1];
    g->vmarker[id] = mk;
    b->vh.slot[h] = id;
    return id;
}

static void gb_segment(gbuild *b, int32_t u, int32_t v, int32_t mk, int32_t iface) {
    mesh_flat *g = b->g;
    int64_t lo = u < v ? u : v, hi = u < v ? v : u;
    int64_t key = (lo << 32) | hi;
    uint64_t h = mesh_hash64((uint64_t)key) & b->smask;
    for (;;) {
        if (b->shash[h] < 0) break;
        if (b->shash[h] == key) {
            int32_t s = b->sidx[h];
            if (iface) g->sinterface[s] = 1;
            return;
        }
        h = (h + 1) & b->smask;
    }
    if (g->nsegs == b->scap) {
        b->scap = b->scap ? 2 * b->scap : 1024;
        g->seg = mesh_xrealloc(g->seg, 2 * (size_t)b->scap * sizeof(int32_t), 1);
        g->smarker = mesh_xrealloc(g->smarker, (size_t)b->scap * sizeof(int32_t), 1);
        g->sinterface = mesh_xrealloc(g->sinterface, (size_t)b->scap * sizeof(int32_t), 1);
    }
    int32_t s = g->nsegs++;
    g->seg[2 * (size_t)s] = u;
    g->seg[2 * (size_t)s + 1] = v;
    g->smarker[s] = mk;
    g->sinterface[s] = iface ? 1 : 0;
    b->shash[h] = key;
    b->sidx[h] = s;
}

/* Merges one piece (rank r) into the global mesh. */
static void gb_piece(gbuild *b, const mesh_flat *p, int r) {
    mesh_flat *g = b->g;
    int32_t *map = mesh_xmalloc(((size_t)p->nverts + 1) * sizeof(int32_t), 1);
    for (int32_t v = 0; v < p->nverts; v++)
        map[v] = -1;
    if (g->ntris + (int64_t)p->ntris > INT32_MAX) {
        MESH_BUG("merged mesh exceeds 2^31 triangles (the gather's limit)");
    }
    int32_t need = g->ntris + p->ntris;
    if (need > b->tcap) {
        while (b->tcap < need)
            b->tcap = b->tcap ? 2 * b->tcap : 1024;
        g->tri = mesh_xrealloc(g->tri, 3 * (size_t)b->tcap * sizeof(int32_t), 1);
        g->trank = mesh_xrealloc(g->trank, (size_t)b->tcap * sizeof(int32_t), 1);
    }
    for (int32_t t = 0; t < p->ntris; t++) {
        for (int j = 0; j < 3; j++) {
            int32_t v = p->tri[3 * (size_t)t + j];
            if (v < 0 || v >= p->nverts) {
                MESH_BUG("rank %d sent a triangle with vertex %d of %d", r, v, p->nverts);
            }
            if (map[v] < 0) map[v] = gb_vertex(b, p->xy + 2 * (size_t)v, p->vmarker[v]);
            g->tri[3 * (size_t)g->ntris + j] = map[v];
        }
        g->trank[g->ntris] = p->trank ? p->trank[t] : r;
        g->ntris++;
    }
    for (int32_t s = 0; s < p->nsegs; s++) {
        int32_t u = p->seg[2 * (size_t)s], v = p->seg[2 * (size_t)s + 1];
        if (u < 0 || u >= p->nverts || v < 0 || v >= p->nverts) continue;
        if (map[u] < 0) map[u] = gb_vertex(b, p->xy + 2 * (size_t)u, p->vmarker[u]);
        if (map[v] < 0) map[v] = gb_vertex(b, p->xy + 2 * (size_t)v, p->vmarker[v]);
        gb_segment(b, map[u], map[v], p->smarker ? p->smarker[s] : 0,
                   p->sinterface ? p->sinterface[s] : 0);
    }
    free(map);
}

static uint64_t pow2_at_least(uint64_t n) {
    uint64_t c = 1024;
    while (c < n)
        c <<= 1;
    return c;
}

/* Piece transfer: counts [nverts, ntris, nsegs, has_trank], then xy, vmarker, tri, trank, seg,
 * smarker, sinterface (each only if non-empty). */
static void send_piece(const mesh_flat *f) {
    MPI_Comm c = rt_app_comm();
    int32_t cnt[4] = {f->nverts, f->ntris, f->nsegs, f->trank ? 1 : 0};
    MESH_MPI(MPI_Send(cnt, 4, MPI_INT32_T, 0, PAR_TAG_GATHER, c));
    if (f->nverts) {
        MESH_MPI(MPI_Send(f->xy, 2 * f->nverts, MPI_DOUBLE, 0, PAR_TAG_GATHER, c));
        int32_t *mk = mesh_xmalloc((size_t)f->nverts * sizeof(int32_t), 1);
        for (int32_t v = 0; v < f->nverts; v++)
            mk[v] = f->vmarker ? f->vmarker[v] : 0;
        MESH_MPI(MPI_Send(mk, f->nverts, MPI_INT32_T, 0, PAR_TAG_GATHER, c));
        free(mk);
    }
    if (f->ntris) {
        MESH_MPI(MPI_Send(f->tri, 3 * f->ntris, MPI_INT32_T, 0, PAR_TAG_GATHER, c));
        if (f->trank) MESH_MPI(MPI_Send(f->trank, f->ntris, MPI_INT32_T, 0, PAR_TAG_GATHER, c));
    }
    if (f->nsegs) {
        int32_t *a = mesh_xmalloc(4 * (size_t)f->nsegs * sizeof(int32_t), 1);
        for (int32_t s = 0; s < f->nsegs; s++) {
            a[4 * (size_t)s] = f->seg[2 * (size_t)s];
            a[4 * (size_t)s + 1] = f->seg[2 * (size_t)s + 1];
            a[4 * (size_t)s + 2] = f->smarker ? f->smarker[s] : 0;
            a[4 * (size_t)s + 3] = f->sinterface ? f->sinterface[s] : 0;
        }
        MESH_MPI(MPI_Send(a, 4 * f->nsegs, MPI_INT32_T, 0, PAR_TAG_GATHER, c));
        free(a);
    }
}

static void recv_piece(int src, mesh_flat *f) {
    MPI_Comm c = rt_app_comm();
    int32_t cnt[4];
    memset(f, 0, sizeof *f);
    MESH_MPI(MPI_Recv(cnt, 4, MPI_INT32_T, src, PAR_TAG_GATHER, c, MPI_STATUS_IGNORE));
    f->nverts = cnt[0];
    f->ntris = cnt[1];
    f->nsegs = cnt[2];
    f->xy = mesh_xmalloc(2 * (size_t)f->nverts * sizeof(double), 1);
    f->vmarker = mesh_xmalloc((size_t)f->nverts * sizeof(int32_t), 1);
    f->tri = mesh_xmalloc(3 * (size_t)f->ntris * sizeof(int32_t), 1);
    f->trank = cnt[3] ? mesh_xmalloc((size_t)f->ntris * sizeof(int32_t), 1) : NULL;
    if (f->nverts) {
        MESH_MPI(
            MPI_Recv(f->xy, 2 * f->nverts, MPI_DOUBLE, src, PAR_TAG_GATHER, c, MPI_STATUS_IGNORE));
        MESH_MPI(MPI_Recv(f->vmarker, f->nverts, MPI_INT32_T, src, PAR_TAG_GATHER, c,
                          MPI_STATUS_IGNORE));
    }
    if (f->ntris) {
        MESH_MPI(
            MPI_Recv(f->tri, 3 * f->ntris, MPI_INT32_T, src, PAR_TAG_GATHER, c, MPI_STATUS_IGNORE));
        if (f->trank)
            MESH_MPI(MPI_Recv(f->trank, f->ntris, MPI_INT32_T, src, PAR_TAG_GATHER, c,
                              MPI_STATUS_IGNORE));
    }
    f->seg = mesh_xmalloc(2 * (size_t)f->nsegs * sizeof(int32_t), 1);
    f->smarker = mesh_xmalloc((size_t)f->nsegs * sizeof(int32_t), 1);
    f->sinterface = mesh_xmalloc((size_t)f->nsegs * sizeof(int32_t), 1);
    if (f->nsegs) {
        int32_t *a = mesh_xmalloc(4 * (size_t)f->nsegs * sizeof(int32_t), 1);
        MESH_MPI(MPI_Recv(a, 4 * f->nsegs, MPI_INT32_T, src, PAR_TAG_GATHER, c, MPI_STATUS_IGNORE));
        for (int32_t s = 0; s < f->nsegs; s++) {
            f->seg[2 * (size_t)s] = a[4 * (size_t)s];
            f->seg[2 * (size_t)s + 1] = a[4 * (size_t)s + 1];
            f->smarker[s] = a[4 * (size_t)s + 2];
            f->sinterface[s] = a[4 * (size_t)s + 3];
        }
        free(a);
    }
}

int par_gather_mesh(const mesh_flat *local, const pslg *in, mesh_flat *global) {
    MPI_Comm c = rt_app_comm();
    int rank = rt_rank(), size = rt_size();
    memset(global, 0, sizeof *global);
    int too_big = (int64_t)2 * local->nverts > INT_MAX || (int64_t)4 * local->nsegs > INT_MAX ||
                  (int64_t)3 * local->ntris > INT_MAX;
    if (par_fail_any(too_big, "par: a rank's piece of the mesh is too large to gather")) return -1;
    /* never a silent broken mesh: both sides of every interface must agree first */
    char imsg[600];
    int ibad = par_check_interfaces(local, imsg, sizeof imsg) != 0;
    char fmsg[1300];
    snprintf(fmsg, sizeof fmsg, "%s: rank %d: %s", in->path[0] ? in->path : "mesh", rank, imsg);
    if (par_fail_any(ibad, fmsg)) return -1;
    int64_t mine[3] = {local->nverts, local->ntris, local->nsegs}, tot[3];
    MESH_MPI(MPI_Reduce(mine, tot, 3, MPI_INT64_T, MPI_SUM, 0, c));
    if (rank != 0) {
        /* wait for rank 0's go-ahead so pieces arrive one at a time */
        int go;
        MESH_MPI(MPI_Recv(&go, 1, MPI_INT, 0, PAR_TAG_GATHER, c, MPI_STATUS_IGNORE));
        send_piece(local);
        return 0;
    }
    gbuild b;
    memset(&b, 0, sizeof b);
    b.g = global;
    uint64_t vslots = pow2_at_least(2 * (uint64_t)(tot[0] + in->nverts) + 16);
    b.vh.slot = mesh_xmalloc(vslots * sizeof(int32_t), 1);
    for (uint64_t i = 0; i < vslots; i++)
        b.vh.slot[i] = -1;
    b.vh.mask = vslots - 1;
    uint64_t sslots = pow2_at_least(2 * (uint64_t)tot[2] + 16);
    b.shash = mesh_xmalloc(sslots * sizeof(int64_t), 1);
    b.sidx = mesh_xmalloc(sslots * sizeof(int32_t), 1);
    for (uint64_t i = 0; i < sslots; i++)
        b.shash[i] = -1;
    b.smask = sslots - 1;
    /* input vertices first, in input order */
    for (int32_t v = 0; v < in->nverts; v++) {
        int32_t id = gb_vertex(&b, in->xy + 2 * (size_t)v, in->vmarker ? in->vmarker[v] : 0);
        if (id != v) {
            MESH_BUG("input vertex %d repeats vertex %d (unchecked input?)", v, id);
        }
    }
    gb_piece(&b, local, 0);
    for (int r = 1; r < size; r++) {
        int go = 1;
        MESH_MPI(MPI_Send(&go, 1, MPI_INT, r, PAR_TAG_GATHER, c));
        mesh_flat p;
        recv_piece(r, &p);
        gb_piece(&b, &p, r);
        mesh_flat_free(&p);
    }
    free(b.vh.slot);
    free(b.shash);
    free(b.sidx);
    return 0;
}

/* ---- outputs and validation -------------------------------------------------------------- */

int par_write_outputs(const par_opts *o, const mesh_flat *global) {
    char err[1024];
    int rc = 0;
    if (o->out_prefix && meshio_write_triangle(global, o->out_prefix, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", o->prog, err);
        rc = -1;
    }
    if (o->vtk && meshio_write_vtk(global, o->vtk, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", o->prog, err);
        rc = -1;
    }
    if (o->svg && meshio_write_svg(global, o->svg, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", o->prog, err);
        rc = -1;
    }
    return rc;
}

int par_validate(const par_opts *o, const pslg *in, const mesh_flat *global, validate_report *r) {
    validate_opts vo;
    memset(&vo, 0, sizeof vo);
    vo.min_angle = o->min_angle;
    vo.max_area = o->max_area;
    vo.check_delaunay_interfaces = 1;
    int ok = mesh_validate(in, global, &vo, r);
    if (o->check || o->stats) validate_report_print(r, stdout);
    return ok;
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

int par_finish(int status, mesh_flat *global, pcdm_decomp *d, pslg *in) {
    MESH_MPI(MPI_Bcast(&status, 1, MPI_INT, 0, rt_app_comm()));
    mesh_flat_free(global);
    pcdm_decomp_free(d);
    pslg_free(in);
    rt_finalize();
    return status;
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
