/* run_par.c: the parallel driver (run.h) -- ./pcdm, ./pbw and pcdm_triangulate_par: the stages
 * of run.c with the mesh made by PCDM (TR-97-17 section 3) or PBW (section 2) over the ranks.
 *
 * The programs' rank 0 reads and checks the input and ./pcdm's rank 0 decomposes it (./pbw's
 * ranks each decompose, trying different METIS seeds, and all keep the partition of least
 * predicted cost, pick_partition); the input and ./pcdm's decomposition go to the other ranks
 * into one block per host that the host's ranks share read-only (base/hostmem.h: held once per
 * host, not once per rank; private copies where no block can be had).  The library's ranks each
 * hold their own input (a hash of it is compared across the ranks, and of a decomposition each
 * made).  Every failure is agreed collectively (run_agree: the lowest failing rank's message
 * goes to every rank, rank 0 prints it unless the library asked), so no rank waits in a
 * collective another one skipped.
 * After refinement each rank keeps its own part: the verdict is reduced over the ranks, then
 * the programs check the interfaces, number, check (--check) and write in parallel (par/pout.h)
 * and the library copies the part out (api_par.c); no rank ever gathers the mesh.
 *
 * --stats (rank 0, stdout): one line per rank ("rank R: key=value ..."), then ./pcdm's
 *   rsr: split=S mpi_msgs=M
 *   stats: ranks=P triangles=N vertices=N rsr=S min_angle=D mesh_s=T busy_max_s=B busy_sum_s=U
 *          subdomains=K idle_max_s=I max_area=A ignored=G mpi_msgs=M speedup_model=X
 *          peak_rss_mb=R bytes_per_tri=Y mesh_bytes_per_tri=Z output_s=W cpu_max_s=C
 *          cpu_sum_s=E decomp_s=D tri_max=N tri_mean=M decomp_exact=0|1 rounds=R hash=H
 *          balance=static|dynamic migrations=N moved_bytes=B move_max_s=S forwarded=F
 *          comm_s=C comm_max_s=M handler_s=H net_latency_us=L net_MBps=B start_s=S read_s=R
 *          wall_s=W
 * or ./pbw's rsr line by kind, its cavities: and blocking: lines, and
 *   stats: ranks=P triangles=N vertices=N rsr=TOTAL_RSRS undone=CAVITIES_UNDONE min_angle=D
 *          mesh_s=T busy_max_s=B busy_sum_s=S comm_pct=C undo_pct=U speedup_model=X
 *          peak_rss_mb=R bytes_per_tri=Y mesh_bytes_per_tri=Z phase1_s=F cpu_max_s=C
 *          cpu_sum_s=E output_s=W comm_s=C comm_max_s=M handler_s=H net_latency_us=L net_MBps=B
 *          start_s=S read_s=R decomp_s=D wall_s=W endcheck_max_s=K endcheck_sum_s=L
 * (one line each).  Definitions (rt_stats time buckets, inside rt_run):
 *   busy (per rank) = RT_TIME_BUSY + RT_TIME_HANDLER (local work, tasks and handlers);
 *                     speedup_model = busy_sum / busy_max.
 *   comm (per rank) = rt_stats.comm_s: packing and sending RSRs and the polls that received
 *                     something (handler bodies and empty polls excluded); comm_s its sum over
 *                     the ranks, comm_max_s the largest rank's, handler_s the handlers' seconds.
 *   comm_pct = 100 sum(handler + comm) / sum(busy + comm), the paper's communication overhead;
 *   undo_pct = 100 sum(RT_TIME_UNDO) / sum(busy + comm), its undo computation overhead (the
 *   expansion work of cavities released after a lock conflict); undone = cavity attempts
 *   abandoned after a conflict; rsr = every RSR sent to another rank.
 *   Times: wall-clock seconds, each phase under its own name, the slowest rank's (rank lines:
 *   each rank's own):
 *     start_s: the start-up (MPI, the command line, the handlers, --threads' threads);
 *     read_s: reading and checking the input (rank 0) and sending it to the other ranks;
 *     decomp_s: the decomposition (automatic or --cuts), sent to the ranks where rank 0 makes it;
 *     mesh_s: from a barrier after reading and decomposition to the last rank leaving the
 *     mesher (CDT, refinement, termination; no numbering, no output) -- ./mesh's mesh_s span;
 *     output_s: the output stage (par_output_sub): the interface and area checks, numbering,
 *     --check and writing (./pcdm's rank lines: number_s and write_s apart);
 *     wall_s: the whole run, from the program's start (before MPI's) to the statistics: the
 *     phases above and what lies between them (agreement, verdict, the mesh hash).
 *   cpu: CPU seconds (getrusage) over mesh_s's span: unlike busy it does not grow when the
 *   machine is oversubscribed.  peak_rss_mb: the largest rank's peak RSS after the output;
 *   bytes_per_tri: the ranks' peak RSS summed over the triangles (rank lines: its own over its
 *   own); mesh_bytes_per_tri: the mesh arrays alone.  rounds: the refinement's rounds (0 with
 *   --async); hash: the mesh hash (pcdm_flat_hash summed over the parts), the same for the same
 *   mesh whatever its numbering and rank count.  endcheck_*: pbw's always-on end check of the
 *   Delaunay property.  net_latency_us, net_MBps: the network model in force (--net, PCDM_NET;
 *   0 0: none).
 */
#include "run/run.h"
#include "run/run_stats.h"

#include "base/base.h"
#include "base/base_mpi.h"
#include "base/hostmem.h"
#include "geom/geom.h"
#include "par/pout.h"
#include "pbw/pbw.h"
#include "pcdm/pcdm.h"
#include "rt.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- agreement -------------------------------------------------------------------------- */

int run_agree(run_job *j, int code, const char *msg) {
    int rc = par_agree(code, msg, j->msg, sizeof j->msg);
    if (rc && !j->lib && rt_rank() == 0 && j->msg[0]) fprintf(stderr, "%s\n", j->msg);
    return rc;
}

/* Local.  The prefix of a message: "PROG: " (with_input: "PROG: INPUT: ") for the programs,
 * "" for the library, which prints nothing and names no program. */
static const char *msg_prefix(const run_job *j, int with_input, char *buf, size_t len) {
    buf[0] = '\0';
    if (j->lib) return buf;
    if (with_input)
        snprintf(buf, len, "%s: %s: ", j->o.prog, j->o.input);
    else
        snprintf(buf, len, "%s: ", j->o.prog);
    return buf;
}

/* ---- load and decomposition ------------------------------------------------------------- */

/* Collective (pcdm_decomp_opts.pick).  Every rank offers its best partition of the coarse mesh
 * (the same mesh on every rank) and its predicted cost; the cheapest (the lowest rank on a tie)
 * is broadcast to all.  -1 if no rank has one. */
static int pick_partition(void *ctx, double cost, int32_t n, int32_t *part) {
    (void)ctx;
    double mine = isfinite(cost) ? cost : DBL_MAX, best = 0;
    MESH_MPI(MPI_Allreduce(&mine, &best, 1, MPI_DOUBLE, MPI_MIN, rt_app_comm()));
    if (best == DBL_MAX) return -1;
    int me = mine == best ? rt_rank() : INT_MAX, root = 0;
    MESH_MPI(MPI_Allreduce(&me, &root, 1, MPI_INT, MPI_MIN, rt_app_comm()));
    MESH_MPI(MPI_Bcast(part, n, MPI_INT32_T, root, rt_app_comm()));
    return 0;
}

/* Collective.  Ranks per core on the most crowded node: this node's ranks (MPI's shared-memory
 * split) over its online CPUs, the largest over the ranks. */
static double ranks_per_core(void) {
    MPI_Comm node;
    int local = 1;
    MESH_MPI(
        MPI_Comm_split_type(rt_app_comm(), MPI_COMM_TYPE_SHARED, rt_rank(), MPI_INFO_NULL, &node));
    MESH_MPI(MPI_Comm_size(node, &local));
    MESH_MPI(MPI_Comm_free(&node));
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    double mine = (double)local / (double)(cpus > 0 ? cpus : 1), most = mine;
    MESH_MPI(MPI_Allreduce(&mine, &most, 1, MPI_DOUBLE, MPI_MAX, rt_app_comm()));
    return most;
}

/* Collective.  MPI_Bcast of n (a few) items of type t from rank 0, waited for asleep
 * (mesh_mpi_wait_asleep), so that ranks sharing cores leave them to rank 0 while it works. */
static void bcast_asleep(void *p, int n, MPI_Datatype t) {
    MPI_Request rq;
    MESH_MPI(MPI_Ibcast(p, n, t, 0, rt_app_comm(), &rq));
    mesh_mpi_wait_asleep(&rq);
}

/* Collective.  Rank 0's status and bytes to every rank: with rc == 0 its *buf (*len bytes),
 * else its message in err.  Returns rank 0's rc; the other ranks get *buf and *len (theirs to
 * free) when it is 0, the message in err when it is not.  Rank 0's *buf stays its own. */
static int share_bytes(int rc, void **buf, size_t *len, char *err, size_t errlen) {
    int64_t hdr[2] = {rc, 0};
    void *b = NULL;
    if (rt_rank() == 0) {
        b = rc == 0 ? *buf : err;
        hdr[1] = (int64_t)(rc == 0 ? *len : strlen(err) + 1);
    }
    bcast_asleep(hdr, 2, MPI_INT64_T);
    if (rt_rank() != 0) b = mesh_xmalloc((size_t)hdr[1] + 1, 1);
    /* the bytes with a plain broadcast: every rank is here now, and a large broadcast moves on
     * only while the ranks forwarding it call MPI (asleep, each piece would wait for a wake) */
    for (int64_t at = 0; at < hdr[1];) {
        int k = (int)(hdr[1] - at < ((int64_t)1 << 28) ? hdr[1] - at : ((int64_t)1 << 28));
        MESH_MPI(MPI_Bcast((char *)b + at, k, MPI_BYTE, 0, rt_app_comm()));
        at += k;
    }
    if (rt_rank() == 0) return rc;
    rc = (int)hdr[0];
    if (rc != 0) {
        snprintf(err, errlen, "%.*s", (int)(hdr[1] > 0 ? hdr[1] - 1 : 0), (char *)b);
        free(b);
        return rc;
    }
    *buf = b;
    *len = (size_t)hdr[1];
    return 0;
}

/* Collective.  The arrays a[0 .. na) a head lists, from rank 0's memory straight into the
 * receivers' (one plain broadcast each, in pieces of at most 2^28 bytes: every rank is here). */
static void share_arrays(const pcdm_pack_arr *a, int na) {
    for (int i = 0; i < na; i++)
        for (size_t at = 0; at < a[i].len;) {
            size_t left = a[i].len - at, k = left < ((size_t)1 << 28) ? left : (size_t)1 << 28;
            MESH_MPI(MPI_Bcast((char *)a[i].p + at, (int)k, MPI_BYTE, 0, rt_app_comm()));
            at += k;
        }
}

/* The blocks the ranks of a host share (hostmem.h): the input's arrays and the
 * decomposition's, each held once per host. */
struct run_shared {
    mesh_hostmem in, d;
};

static int shared_holds(const void *ctx, const void *p) {
    const struct run_shared *sh = ctx;
    return mesh_hostmem_holds(&sh->in, p) || mesh_hostmem_holds(&sh->d, p);
}

/* Local.  Forgets in's and d's arrays that live in the host's blocks (either may be NULL), so
 * that they can be freed, and unmaps the blocks. */
static void unshare(run_job *j, pslg *in, pcdm_decomp *d) {
    struct run_shared *sh = j->shared;
    if (!sh) return;
    if (in) pslg_pack_forget(in, shared_holds, sh);
    if (d) pcdm_decomp_pack_forget(d, shared_holds, sh);
    mesh_hostmem_close(&sh->in);
    mesh_hostmem_close(&sh->d);
    mesh_xfree(sh);
    j->shared = NULL;
}

/* Collective.  The arrays a[0 .. na) a head lists -- rank 0's, the others' as their unpack
 * allocated them, empty -- into one block shared by each host's ranks (hm): rank 0 copies its
 * arrays into its host's and sends them to the first rank of every other host, which receives
 * them into its own, and each host's block is sealed read-only; at[i] is where a[i] now lies.
 * Returns 0, or -1 on every rank when a block cannot be had (nothing sent). */
static int share_arrays_host(const pcdm_pack_arr *a, int na, mesh_hostmem *hm, unsigned char **at) {
    size_t off[PCDM_PACK_MAX_ARRS], tot = 0;
    for (int i = 0; i < na; i++) {
        off[i] = tot;
        /* each array on cache lines of its own, an empty one too (so every at[i] lies inside
         * the block, which is how unshare knows it) */
        tot += (a[i].len + 64) / 64 * 64;
    }
    if (mesh_hostmem_open(hm, rt_app_comm(), tot > 0 ? tot : 64) != 0) return 1;
    for (int i = 0; i < na; i++)
        at[i] = hm->base + off[i];
    int P = rt_size(), me = rt_rank();
    int *lead = mesh_xmalloc((size_t)P, sizeof(int));
    MESH_MPI(MPI_Allgather(&hm->leader, 1, MPI_INT, lead, 1, MPI_INT, rt_app_comm()));
    if (me == 0)
        for (int i = 0; i < na; i++)
            if (a[i].len) memcpy(at[i], a[i].p, a[i].len);
    for (int r = 1; r < P; r++) { /* the other hosts' first ranks, from rank 0 */
        if (!lead[r] || (me != 0 && me != r)) continue;
        for (int i = 0; i < na; i++)
            for (size_t o = 0; o < a[i].len;) {
                size_t left = a[i].len - o, k = left < ((size_t)1 << 28) ? left : (size_t)1 << 28;
                if (me == 0) {
                    MPI_Request rq;
                    MESH_MPI(MPI_Isend(at[i] + o, (int)k, MPI_BYTE, r, 0, rt_app_comm(), &rq));
                    MESH_MPI(MPI_Wait(&rq, MPI_STATUS_IGNORE));
                } else
                    MESH_MPI(MPI_Recv(at[i] + o, (int)k, MPI_BYTE, 0, 0, rt_app_comm(),
                                      MPI_STATUS_IGNORE));
                o += k;
            }
    }
    mesh_xfree(lead);
    mesh_hostmem_seal(hm);
    return 0;
}

/* Collective.  After a head every rank has (a receiver's read of it failed: bad), the arrays it
 * lists (a, as for share_arrays_host): with j->host_share into the host's block for the input
 * (decomp 0) or the decomposition (decomp 1) (share_arrays_host; returns 0, at[i] where a[i] now
 * lies), else or when no block can be had into the private arrays a (share_arrays; returns 1).
 * -1 on every rank when some rank could not read the head (nothing sent). */
static int share_any(run_job *j, int decomp, int bad, const pcdm_pack_arr *a, int na,
                     unsigned char **at) {
    int any = 0;
    MESH_MPI(MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, rt_app_comm()));
    if (any) return -1;
    if (j->host_share) {
        if (!j->shared) j->shared = mesh_xcalloc(1, sizeof *j->shared);
        if (share_arrays_host(a, na, decomp ? &j->shared->d : &j->shared->in, at) == 0) return 0;
    }
    share_arrays(a, na);
    return 1;
}

/* Collective.  Rank 0's decomposition, or its failure (rc != 0 and the message in err), to every
 * rank: its head (pcdm_decomp_pack_head), then its arrays, received where they will stay (no
 * packed copy on either side).  Returns rank 0's rc; d and err as on rank 0. */
static int share_decomp(run_job *j, pcdm_decomp *d, int rc, char *err, size_t errlen) {
    void *head = NULL;
    size_t hlen = 0;
    pcdm_pack_arr a[PCDM_PACK_MAX_ARRS];
    int na = 0, mine = rt_rank() == 0;
    if (mine && rc == 0 && pcdm_decomp_pack_head(d, &head, &hlen, a, &na) != 0) {
        snprintf(err, errlen, "the decomposition cannot be sent to the other ranks");
        rc = -1;
    }
    rc = share_bytes(rc, &head, &hlen, err, errlen);
    if (rc != 0) {
        if (mine) free(head);
        return rc;
    }
    int bad = !mine && pcdm_decomp_unpack_head(head, hlen, d, a, &na) != 0;
    free(head);
    unsigned char *at[PCDM_PACK_MAX_ARRS];
    int host = share_any(j, 1, bad, a, na, at);
    if (host == 0) { /* the host's copy replaces this rank's arrays */
        pcdm_decomp_pack_place(d, at);
        for (int i = 0; i < na; i++)
            a[i].p = at[i];
    }
    /* in the host's block, a malformed d is freed by the caller (unshare first) */
    if (host < 0 || (!mine && (host == 0 ? pcdm_decomp_unpack_index(d, a, na)
                                         : pcdm_decomp_unpack_done(d, a, na)) != 0)) {
        snprintf(err, errlen, "the decomposition received from rank 0 is malformed");
        return -1;
    }
    return 0;
}

/* Collective.  Rank 0's input, read and checked (or its failure: rc != 0, the message in err),
 * to every rank as share_decomp sends a decomposition (pslg_pack_head), which then loads the
 * size rules itself.  Returns rank 0's rc, or -1 where the size rules cannot be loaded; in and
 * err as on rank 0. */
static int share_input(run_job *j, pslg *in, int rc, char *err, size_t errlen) {
    void *head = NULL;
    size_t hlen = 0;
    pcdm_pack_arr a[PCDM_PACK_MAX_ARRS];
    int na = 0, mine = rt_rank() == 0;
    if (mine && rc == 0) pslg_pack_head(in, &head, &hlen, a, &na);
    rc = share_bytes(rc, &head, &hlen, err, errlen);
    if (rc != 0) {
        if (mine) free(head);
        return rc;
    }
    int bad = !mine && pslg_unpack_head(head, hlen, in, a, &na) != 0;
    free(head);
    unsigned char *at[PCDM_PACK_MAX_ARRS];
    int host = share_any(j, 0, bad, a, na, at);
    if (host == 0) pslg_pack_place(in, at); /* the host's copy replaces this rank's arrays */
    if (host < 0 || (!mine && pslg_unpack_done(in) != 0)) {
        snprintf(err, errlen, "the input received from rank 0 is malformed");
        return -1;
    }
    if (!mine) in->quiet = 1; /* warnings: rank 0's */
    if (run_load_sizes(j, in, err, errlen) != 0) rc = -1;
    return rc;
}

/* ./pcdm: rank 0 decomposes and the other ranks receive its decomposition (./pbw's ranks each
 * try their METIS seeds and keep the input's CDT, so they all decompose) */
static int decomp_received(const run_job *j) {
    return rt_size() > 1 && j->method == RUN_PCDM;
}

/* Local, but Collective for ./pbw's automatic decomposition (pick_partition).  The decomposition
 * of in for the ranks (auto, or --cuts).  Returns 0, or a RUN_F* code with the message in err. */
static int decompose(run_job *j, const pslg *in, pcdm_decomp *d, char *err, size_t errlen) {
    const par_opts *o = &j->o;
    int P = rt_size(), rc = 0;
    pcdm_decomp_opts dopt;
    pcdm_decomp_opts_default(&dopt);
    /* The default count.  In rounds (./pcdm without --async) the mesh is a function of the
     * input, the bounds and the number of subdomains, so the default is one fixed count,
     * PAR_ROUNDS_SUBDOMAINS, whatever the ranks, threads and balancing (one per rank and thread
     * where there are more): the same mesh for any of those.  Otherwise one per rank, several
     * with --balance dynamic, which moves whole subdomains. */
    int rounds = j->method == RUN_PCDM && (!o->async || o->threads > 1);
    int32_t per = par_balance_dynamic(o) ? 4 : 1;
    int32_t T = o->threads > 1 ? o->threads : 1;
    int32_t dflt =
        rounds ? (P * T > PAR_ROUNDS_SUBDOMAINS ? P * T : PAR_ROUNDS_SUBDOMAINS) : P * per;
    int32_t k = o->nsub > 0 ? o->nsub : dflt;
    if (!o->nsub && k > PAR_MAX_SUBDOMAINS && P <= PAR_MAX_SUBDOMAINS) k = PAR_MAX_SUBDOMAINS;
    dopt.nsub = o->cuts ? o->nsub : k; /* cuts: 0 = as many as they make */
    dopt.nranks = P;
    dopt.nsub_fit = rounds && !o->nsub && !o->cuts;
    dopt.min_angle = o->min_angle;
    dopt.max_area = o->max_area;
    dopt.imbalance = o->imbalance;
    dopt.max_steiner = o->max_steiner;
    dopt.region_area = o->region_area;
    dopt.keep_cdt = j->method == RUN_PBW; /* PBW starts from the same CDT of the input */
    /* ./pbw's ranks weigh boundary against triangles when they share cores (PBW_BOUNDARY_COST);
     * the seeds are shared out: rank r tries r + 1, r + 1 + P, ... */
    double rho = j->method == RUN_PBW && P > 1 && !o->cuts ? ranks_per_core() : 0;
    if (rho > 1) {
        int32_t per_rank = (PBW_DECOMP_SEEDS + P - 1) / P;
        dopt.boundary_cost = PBW_BOUNDARY_COST * (1 - 1 / rho) / (1 - 1 / PBW_BOUNDARY_RHO);
        dopt.seed_first = 1 + rt_rank();
        dopt.seed_step = P;
        dopt.seed_count = per_rank < PBW_SEEDS_PER_RANK ? per_rank : PBW_SEEDS_PER_RANK;
        dopt.pick = pick_partition;
    }
    if (!o->cuts && k > PAR_MAX_SUBDOMAINS) {
        snprintf(err, errlen,
                 "%d subdomains: the automatic decomposition supports at most %d (fewer ranks or "
                 "--subdomains, or give --cuts)",
                 (int)k, PAR_MAX_SUBDOMAINS);
        return RUN_FINVAL;
    }
    if (o->nsub > 0 && o->nsub < P) {
        snprintf(err, errlen, "--subdomains %d: fewer subdomains than ranks (%d)", (int)o->nsub, P);
        return RUN_FINVAL;
    }
    int share = decomp_received(j);
    /* the passes of a decomposition made alone (./pcdm's rank 0, or one rank) take the CPUs the
     * waiting ranks and workers leave (the same decomposition for any number) */
    if (share || P == 1) {
        int ncpu = 0;
        for (int c = 0; c < MESH_HOST_CPUS; c++)
            ncpu += j->host_cpus[c] != 0;
        dopt.threads = ncpu > 0 ? ncpu : o->threads;
        dopt.cpus = ncpu > 0 ? j->host_cpus : NULL;
    }
    double t0 = rt_wtime();
    /* the input's vertices, triangulated while it was checked (rank 0; run_ahead.c) */
    run_dt_ahead *dt = run_dt_ahead_take(&j->dt_ahead, in);
    if (dt) {
        dopt.dt = &dt->m;
        dopt.dt_dup = &dt->dup;
    }
    if (!share || rt_rank() == 0)
        rc = o->cuts ? pcdm_decomp_read_cuts(o->cuts, in, &dopt, d, err, errlen)
                     : pcdm_decomp_auto(in, &dopt, d, err, errlen);
    run_dt_ahead_free(&j->dt_ahead);
    if (share) rc = share_decomp(j, d, rc, err, errlen);
    if (rc == 0) {
        d->build_s = rt_wtime() - t0;
        return 0;
    }
    char tmp[1024];
    snprintf(tmp, sizeof tmp, "%.800s", err);
    snprintf(err, errlen, "cannot decompose %.150s for %d ranks: %.800s", o->input, P, tmp);
    return RUN_FINPUT;
}

int run_par_load(run_job *j, pslg *in, pcdm_decomp *d) {
    const par_opts *o = &j->o;
    char err[1024] = "", msg[sizeof j->msg];
    memset(d, 0, sizeof *d);
    geom_init();
    int quiet = j->lib || o->quiet || rt_rank() != 0; /* warnings: rank 0 only */
    /* the programs: rank 0 reads and checks the input and sends it (ranks sharing cores would
     * each read it again; the file need not be on the other ranks' machines); the library's
     * ranks each hold their own arrays */
    int share = rt_size() > 1 && !j->lib && !j->given;
    if (share) run_ahead_host_cpus(j);
    double t0 = rt_wtime();
    int rc = 0;
    /* ./pcdm's rank 0, which alone decomposes while the other ranks and its own workers wait:
     * the input's vertices are triangulated on a second thread while the rest of the input is
     * checked */
    if (j->method == RUN_PCDM && !j->lib && !j->given && !o->cuts && rt_rank() == 0 &&
        (rt_size() > 1 || o->threads > 1))
        j->vertices_ready = run_dt_ahead_start;
    if (!share || rt_rank() == 0)
        rc = run_load(j, in, quiet, !j->lib && !share, err, sizeof err) == 0 ? 0 : RUN_FINPUT;
    if (share && share_input(j, in, rc, err, sizeof err) != 0 && rc == 0) rc = RUN_FINPUT;
    j->read_s = rt_wtime() - t0;
    /* the area check's domain area, on a thread of rank 0 while it decomposes and the other
     * ranks and threads wait for it */
    if (rc == 0 && !j->lib && rt_rank() == 0 && (rt_size() > 1 || o->threads > 1))
        par_dom_ahead_start(&j->dom_ahead, in, j->host_cpus);
    char pre[600];
    /* every rank holds the same input before the decomposition (which may be collective), and
     * the same decomposition after it */
    for (int stage = 0; stage < 2; stage++) {
        if (stage == 1) rc = decompose(j, in, d, err, sizeof err);
        snprintf(msg, sizeof msg, "%s%s", msg_prefix(j, 0, pre, sizeof pre), err);
        if ((rc = run_agree(j, rc, msg)) != 0) goto fail;
        if (stage == 0 ? share : decomp_received(j)) continue; /* received: rank 0's */
        if (stage == 0 ? par_input_agrees(in) : par_decomp_agrees(d)) continue;
        snprintf(msg, sizeof msg,
                 stage == 0 ? "%sthe ranks read different inputs from %.200s (is it the same file "
                              "on every host?)"
                            : "%sthe ranks computed different decompositions of %.200s (was the "
                              "same input and options passed on every rank?)",
                 pre, o->input);
        rc = run_agree(j, RUN_FINVAL, msg);
        goto fail;
    }
    /* the area's thread is done by now (it costs a fraction of the decomposition): joined
     * here, so that no thread of ours outlives a fatal error in the meshing */
    par_dom_ahead_get(&j->dom_ahead);
    if (o->write_cuts && rt_rank() == 0 &&
        pcdm_decomp_write_cuts(d, o->write_cuts, err, sizeof err) != 0)
        rc = RUN_FINPUT;
    snprintf(msg, sizeof msg, "%s: %s", o->prog, err);
    if ((rc = run_agree(j, rc, msg)) != 0) goto fail;
    return 0;
fail:
    par_dom_ahead_get(&j->dom_ahead); /* joined before in goes */
    run_dt_ahead_free(&j->dt_ahead);
    unshare(j, in, d);
    pslg_free(in); /* both zero what they free and accept a zeroed struct */
    pcdm_decomp_free(d);
    run_job_free(j);
    return rc;
}

/* ---- mesh and verdict ------------------------------------------------------------------- */

/* Local.  The runtime's time buckets (rt_stats) both meshers report, in their rank lines'
 * order: busy (local work, tasks and handlers), idle, handlers, communication. */
static void set_runtime_times(run_stats *st, const rt_stats *rs) {
    run_stats_set(st, "busy_s", 3, 1, rs->time[RT_TIME_BUSY] + rs->time[RT_TIME_HANDLER]);
    run_stats_set(st, "idle_s", 3, 1, rs->time[RT_TIME_IDLE]);
    run_stats_set(st, "handler_s", 3, 1, rs->time[RT_TIME_HANDLER]);
    run_stats_set(st, "comm_s", 3, 1, rs->comm_s);
}

/* Collective.  PCDM: this rank's subdomains refined to b; figures into st.  Returns 0, or a
 * RUN_F* code on every rank (message agreed). */
static int mesh_pcdm(run_job *j, pcdm_decomp *d, const mesh_bounds *b, const par_config *c,
                     run_part *p, run_stats *st, long long *unmet) {
    char err[1024], msg[sizeof j->msg];
    pcdm_part part;
    int rc = pcdm_part_start(&part, d, b, c, err, sizeof err) == 0 ? 0 : RUN_FINPUT;
    char pre[600];
    snprintf(msg, sizeof msg, "%s%s", msg_prefix(j, 0, pre, sizeof pre), err);
    if (run_agree(j, rc, msg)) {
        if (rc == 0) pcdm_part_free(&part);
        return RUN_FINPUT;
    }
    /* the subdomains are built: the triangles are no longer needed (a host's shared copy stays
     * until the end) */
    if (j->shared && shared_holds(j->shared, d->tri))
        d->tri = NULL, d->tri_off = NULL;
    else
        pcdm_decomp_drop_triangles(d);
    pcdm_part_run(&part, b, c);
    p->mesh_s = rt_wtime() - p->t0;
    pcdm_figures fig;
    pcdm_part_figures(&part, &fig);
    rt_stats rs;
    rt_stats_local(&rs);
    run_stats_set(st, "subdomains", 0, 1, part.nsub_owned);
    run_stats_set(st, "triangles", 0, 1, (double)fig.ntris);
    run_stats_set(st, "vertices", 0, 1, (double)fig.nverts);
    run_stats_set(st, "inserted", 0, 1, (double)fig.inserted);
    run_stats_set(st, "split_sent", 0, 1, (double)part.split_sent);
    run_stats_set(st, "split_recv", 0, 1, (double)part.split_recv);
    run_stats_set(st, "split_ignored", 0, 1, (double)part.split_ignored);
    set_runtime_times(st, &rs);
    run_stats_set(st, "cpu_s", 3, 1, par_cpu_seconds() - p->c0);
    run_stats_set(st, "mpi_msgs", 0, 1, (double)rs.mpi_sent);
    run_stats_set(st, "output_s", 3, 1, 0);
    run_stats_set(st, "number_s", 3, 1, 0);
    run_stats_set(st, "write_s", 3, 1, 0);
    run_stats_set(st, "output_cpu_s", 3, 1, 0);
    run_stats_set(st, "peak_rss_mb", 1, 1, 0);
    run_stats_set(st, "bytes_per_tri", 1, 1, 0);
    run_stats_set(st, "migrations", 0, 1, (double)part.migrations);
    run_stats_set(st, "moved_bytes", 0, 1, (double)part.moved_bytes);
    run_stats_set(st, "move_s", 4, 1, part.move_s);
    run_stats_set(st, "forwarded", 0, 1, (double)part.forwarded);
    run_stats_set(st, "flips", 0, 1, (double)part.flips);
    run_stats_set(st, "split_notfound", 0, 0, (double)part.split_notfound);
    run_stats_set(st, "mesh_bytes", 0, 0, (double)fig.mesh_bytes);
    run_stats_set(st, "mesh_s", 3, 0, p->mesh_s);
    MPI_Comm comm = rt_app_comm();
    int limit_any = 0;
    MESH_MPI(MPI_Allreduce(&part.limit_hit, &limit_any, 1, MPI_INT, MPI_MAX, comm));
    unmet[0] = fig.unmet;
    unmet[1] = fig.refused;
    unmet[2] = limit_any;
    /* an interface piece split on one side only, or still encroached (a split refinement
     * refused: interfaces at a tiny angle, precision): the parts would not form a Delaunay mesh
     * of the input; an error on every rank, nothing written (not even with --write-partial) */
    long long enc[2] = {(long long)fig.iface_enc, (long long)fig.iface_remote}, enc_all[2];
    MESH_MPI(MPI_Allreduce(enc, enc_all, 2, MPI_LONG_LONG, MPI_SUM, comm));
    if (enc_all[0] > 0) {
        snprintf(msg, sizeof msg,
                 "%scannot meet the bounds: %lld subdomain interface pieces could not be "
                 "split on both sides (splits refused: interfaces meeting at a tiny angle, or "
                 "features below the precision of the coordinates); the parts would not form a "
                 "Delaunay mesh of the input, none written",
                 msg_prefix(j, 1, pre, sizeof pre), enc_all[0]);
        run_agree(j, rt_rank() == 0 ? RUN_FUNMET : 0, msg);
        pcdm_part_free(&part);
        return RUN_FUNMET;
    }
    p->rounds = part.rounds;
    p->iface_remote = enc_all[1];
    pcdm_part_take(&part, &p->local, &p->artificial, j->o.vtk ? &p->tsub : NULL, &p->topen);
    pcdm_part_free(&part);
    return 0;
}

/* Collective.  PBW: the one distributed mesh refined to b; figures into st. */
static int mesh_pbw(run_job *j, const pslg *in, const pcdm_decomp *d, const mesh_bounds *b,
                    const par_config *c, run_part *p, run_stats *st, long long *unmet) {
    pbw_result res;
    if (pbw_mesh(b, c, in, d, &p->local, &res) != 0) { /* message printed by rank 0 */
        snprintf(j->msg, sizeof j->msg, "pbw: the distributed mesh cannot be built");
        return RUN_FMESH;
    }
    p->mesh_s = rt_wtime() - p->t0;
    p->topen = res.topen;
    rt_stats rs;
    rt_stats_local(&rs);
    run_stats_set(st, "triangles", 0, 1, (double)res.ntris);
    run_stats_set(st, "inserted", 0, 1, (double)res.inserted);
    run_stats_set(st, "splits", 0, 1, (double)res.splits);
    run_stats_set(st, "cav_local", 0, 1, (double)res.cavities_local);
    run_stats_set(st, "cav_remote", 0, 1, (double)res.cavities_remote);
    run_stats_set(st, "undone_local", 0, 1, (double)res.undone_local);
    run_stats_set(st, "undone_remote", 0, 1, (double)res.undone_remote);
    run_stats_set(st, "parked", 0, 1, (double)res.parked);
    run_stats_set(st, "rsr_sent", 0, 1, (double)(rs.rsr_sent - res.rsr_self));
    set_runtime_times(st, &rs);
    run_stats_set(st, "undo_s", 4, 1, rs.time[RT_TIME_UNDO]);
    run_stats_set(st, "output_s", 3, 1, 0);
    run_stats_set(st, "peak_rss_mb", 1, 1, 0);
    run_stats_set(st, "bytes_per_tri", 1, 1, 0);
    run_stats_set(st, "rejected", 0, 0, (double)res.rejected);
    run_stats_set(st, "skipped_small", 0, 0, (double)res.skipped_small);
    run_stats_set(st, "failed", 0, 0, (double)res.failed);
    run_stats_set(st, "postponed", 0, 0, (double)res.postponed);
    run_stats_set(st, "ghosted", 0, 0, (double)res.ghosted);
    run_stats_set(st, "forwarded", 0, 0, (double)res.forwarded);
    run_stats_set(st, "iface_edges", 0, 0, (double)res.iface_edges);
    run_stats_set(st, "iface_len", 4, 0, res.iface_len);
    run_stats_set(st, "unresolved", 0, 0, (double)res.unresolved);
    run_stats_set(st, "forced", 0, 0, (double)res.forced);
    run_stats_set(st, "mesh_bytes", 0, 0, (double)res.mesh_bytes);
    run_stats_set(st, "mesh_s", 3, 0, p->mesh_s);
    run_stats_set(st, "phase1_s", 3, 0, res.phase1_s);
    run_stats_set(st, "cpu_s", 3, 1, par_cpu_seconds() - p->c0);
    run_stats_set(st, "mpi_msgs", 0, 0, (double)rs.mpi_sent);
    run_stats_set(st, "self", 0, 0, (double)res.rsr_self);
    run_stats_set(st, "endcheck_s", 4, 0, res.endcheck_s);
    run_stats_set(st, "tasks_blocked", 0, 0, (double)rs.blocked_count);
    run_stats_set(st, "most_at_once", 0, 0, (double)rs.blocked_max);
    run_stats_set(st, "wait_sum_s", 4, 0, rs.blocked_time_sum);
    run_stats_set(st, "wait_max_s", 4, 0, rs.blocked_time_max);
    for (int k = 0; k < PBW_RSR_NKINDS; k++)
        run_stats_set(st, pbw_rsr_kind_name[k], 0, 0, (double)res.rsr_sent[k]);
    int limit_any = 0;
    MESH_MPI(MPI_Allreduce(&res.limit_hit, &limit_any, 1, MPI_INT, MPI_MAX, rt_app_comm()));
    unmet[0] = res.unmet;
    unmet[1] = res.unresolved;
    unmet[2] = limit_any;
    return 0;
}

int run_par_mesh(run_job *j, const pslg *in, pcdm_decomp *d, run_part *p, run_stats *st) {
    memset(p, 0, sizeof *p);
    mesh_bounds b = run_bounds(j, in); /* 2. bounds */
    par_config c = par_config_of(&j->o);
    if (j->lib) c.progress = 0;
    MPI_Comm comm = rt_app_comm();
    /* mesh_s starts here: input read, checked and decomposed on every rank */
    MESH_MPI(MPI_Barrier(comm));
    p->t0 = rt_wtime();
    p->c0 = par_cpu_seconds();
    rt_stats_reset();
    long long un[3] = {0, 0, 0}; /* unmet, refused, Steiner limit hit (any rank) */
    int rc = j->method == RUN_PBW ? mesh_pbw(j, in, d, &b, &c, p, st, un) /* 3. mesh */
                                  : mesh_pcdm(j, d, &b, &c, p, st, un);
    if (rc != 0) return rc;
    /* 4. verdict: never a silent success outside the bounds: what is left must be forced by the
     * input (corners of the decomposition get no exemption), or the Steiner limit the user set
     * stopped refinement (exit 3: the mesh kept, checked without the bounds) */
    long long all[2] = {0, 0};
    MESH_MPI(MPI_Allreduce(un, all, 2, MPI_LONG_LONG, MPI_SUM, comm));
    j->unmet = all[0];
    j->refused = all[1];
    j->verdict = run_verdict_of((int)un[2], j->unmet);
    char prefix[600], msg[sizeof j->msg];
    msg_prefix(j, 1, prefix, sizeof prefix);
    run_verdict_message(j, prefix, msg, sizeof msg);
    if (j->verdict != RUN_MET) {
        snprintf(j->msg, sizeof j->msg, "%s", msg);
        if (!j->lib && rt_rank() == 0) fprintf(stderr, "%s\n", msg);
    }
    if (j->verdict == RUN_UNMET && (j->lib || !j->o.write_partial)) return RUN_FUNMET;
    if (p->iface_remote > 0) { /* interface pieces left encroached: Delaunay across the ranks? */
        char imsg[512];
        long bad = par_check_interface_delaunay(&p->local, p->topen, imsg, sizeof imsg), bad_all;
        MESH_MPI(MPI_Allreduce(&bad, &bad_all, 1, MPI_LONG, MPI_SUM, comm));
        snprintf(msg, sizeof msg,
                 "%scannot meet the bounds: %ld subdomain interface edges are not Delaunay "
                 "across the ranks (their splits were refused: features below the precision of "
                 "the coordinates); none written",
                 prefix, bad_all);
        if (run_agree(j, bad_all > 0 ? RUN_FUNMET : 0, msg)) return RUN_FUNMET;
    }
    return 0;
}

void run_part_free(run_part *p) {
    free(p->artificial);
    free(p->tsub);
    free(p->topen);
    mesh_flat_free(&p->local);
    memset(p, 0, sizeof *p);
}

/* ---- the programs: start-up, output, statistics ----------------------------------------- */

/* Collective over MPI_COMM_WORLD.  The runtime, the command line (every rank parses the same
 * arguments; all stop or none, with one status), the method's handlers, --perturb, --net and
 * Triangle's output name (rank 0's).  Returns 0 to go on, or 1 with *code (the runtime
 * finalised; messages printed on rank 0). */
static int startup(int *argc, char ***argv, run_method method, par_parse_fn parse, const void *ctx,
                   par_opts *o, int *code) {
    const char *prog = method == RUN_PBW ? "pbw" : "pcdm";
    mesh_alloc_for_program();
    int rc = rt_init(argc, argv, NULL);
    *code = 1;
    if (rc != RT_OK) {
        fprintf(stderr, "%s: runtime initialisation failed: %s\n", prog, rt_strerror(rc));
        return 1;
    }
    int status = 0, stop = parse(*argc, *argv, rt_rank(), ctx, o, &status) ? status : -1;
    int agreed = stop;
    MESH_MPI(MPI_Allreduce(&stop, &agreed, 1, MPI_INT, MPI_MAX, rt_app_comm()));
    if (agreed >= 0) {
        *code = agreed;
        goto fin;
    }
    if ((rc = method == RUN_PBW ? pbw_register() : pcdm_register()) != 0) {
        fprintf(stderr, "%s: cannot register the handlers: %s\n", prog, rt_strerror(rc));
        goto fin;
    }
    /* the ranks compare their handler tables now, before any other collective (./pbw's
     * decomposition has some): ranks running different programs stop here, each naming it */
    rt_start();
    if (o->async && (o->threads > 1 || par_balance_dynamic(o) || o->deterministic)) {
        /* every rank parsed the same arguments: all stop */
        if (rt_rank() == 0)
            fprintf(stderr,
                    "%s: --async: the asynchronous protocol refines one mesh per rank on one "
                    "thread: not with %s\n",
                    prog,
                    o->threads > 1           ? "--threads above 1"
                    : par_balance_dynamic(o) ? "--balance dynamic"
                                             : "--deterministic");
        *code = 2;
        goto fin;
    }
    if (o->perturb) rt_perturb_set(o->perturb);
    if (o->threads > 1 && (rc = rt_workers_ensure(o->threads)) != RT_OK) {
        fprintf(stderr, "%s: --threads %d: cannot start the threads: %s\n", prog, (int)o->threads,
                rt_strerror(rc));
        goto fin;
    }
    if (o->threads > 1) { /* the threads share the CPUs a launcher left the rank */
        int cpus = rt_cpus(), fewest = cpus;
        MESH_MPI(MPI_Allreduce(&cpus, &fewest, 1, MPI_INT, MPI_MIN, rt_app_comm()));
        if (fewest < o->threads && rt_rank() == 0 && !o->quiet)
            fprintf(stderr,
                    "%s: warning: --threads %d, but a rank may run on %d CPU%s only: the threads "
                    "share %s (under mpirun, which binds each rank to one core by default, add "
                    "--bind-to none or --map-by slot:PE=%d)\n",
                    prog, (int)o->threads, fewest, fewest == 1 ? "" : "s",
                    fewest == 1 ? "it" : "them", (int)o->threads);
    }
    if (o->net) { /* every rank parses the same text: all stop or none */
        double lat = 0, bw = 0;
        if (rt_net_parse(o->net, &lat, &bw) != RT_OK) {
            if (rt_rank() == 0)
                fprintf(stderr,
                        "%s: --net '%s': want off, sp2 or LAT_US[,MBPS] (microseconds, "
                        "megabytes per second)\n",
                        prog, o->net);
            *code = 2;
            goto fin;
        }
        rt_net_set(lat, bw);
    }
    /* Triangle's output name (no -o): rank 0 decides, every rank writes to the same files */
    int named = o->out_prefix == o->out_name;
    MESH_MPI(MPI_Bcast(&named, 1, MPI_INT, 0, rt_app_comm()));
    MESH_MPI(MPI_Bcast(o->out_name, (int)sizeof o->out_name, MPI_CHAR, 0, rt_app_comm()));
    if (named) o->out_prefix = o->out_name;
    *code = 0;
    return 0;
fin:
    rt_finalize();
    return 1;
}

/* Rank 0: ./pcdm's --stats lines (after the rank lines). */
static void print_pcdm_stats(const run_job *j, const run_stats *st, const par_summary *sum,
                             const pcdm_decomp *d, int32_t rounds, uint64_t hash) {
#define S(k) run_stats_sum(st, k)
#define M(k) run_stats_max(st, k)
    int size = rt_size();
    if (S("split_notfound") > 0)
        fprintf(stderr, "pcdm: warning: %.0f split requests named no subsegment\n",
                S("split_notfound"));
    double nt = sum->ntris > 0 ? (double)sum->ntris : 1, lat, bw;
    rt_net_get(&lat, &bw);
    printf("rsr: split=%.0f mpi_msgs=%.0f\n", S("split_sent"), S("mpi_msgs"));
    printf("stats: ranks=%d triangles=%lld vertices=%lld rsr=%.0f min_angle=%.4f "
           "mesh_s=%.3f busy_max_s=%.3f busy_sum_s=%.3f subdomains=%d idle_max_s=%.3f "
           "max_area=%.6g ignored=%.0f mpi_msgs=%.0f speedup_model=%.2f "
           "peak_rss_mb=%.1f bytes_per_tri=%.1f mesh_bytes_per_tri=%.1f output_s=%.3f "
           "cpu_max_s=%.3f cpu_sum_s=%.3f decomp_s=%.3f tri_max=%.0f tri_mean=%.1f "
           "decomp_exact=%d rounds=%d hash=%016llx balance=%s migrations=%.0f "
           "moved_bytes=%.0f move_max_s=%.4f forwarded=%.0f comm_s=%.4f comm_max_s=%.4f "
           "handler_s=%.4f net_latency_us=%.1f net_MBps=%.1f start_s=%.3f read_s=%.3f "
           "wall_s=%.3f\n",
           size, (long long)sum->ntris, (long long)sum->nverts, S("split_sent"), sum->min_angle,
           M("mesh_s"), M("busy_s"), S("busy_s"), (int)d->nsub, M("idle_s"), sum->max_area,
           S("split_ignored"), S("mpi_msgs"), M("busy_s") > 0 ? S("busy_s") / M("busy_s") : 0.0,
           M("rss") / 1048576.0, S("rss") / nt, S("mesh_bytes") / nt, M("output_s"), M("cpu_s"),
           S("cpu_s"), M("decomp_s"), M("triangles"), S("triangles") / size, d->exact, (int)rounds,
           (unsigned long long)hash, par_balance_dynamic(&j->o) ? "dynamic" : "static",
           S("migrations"), S("moved_bytes"), M("move_s"), S("forwarded"), S("comm_s"), M("comm_s"),
           S("handler_s"), lat * 1e6, bw / 1e6, M("start_s"), M("read_s"), M("wall_s"));
}

/* Rank 0: ./pbw's --stats lines (after the rank lines). */
static void print_pbw_stats(const run_stats *st, const par_summary *sum) {
    int size = rt_size();
    printf("rsr:");
    for (int k = 0; k < PBW_RSR_NKINDS; k++)
        printf(" %s=%.0f", pbw_rsr_kind_name[k], S(pbw_rsr_kind_name[k]));
    printf(" mpi_msgs=%.0f self=%.0f\n", S("mpi_msgs"), S("self"));
    printf("cavities: local=%.0f remote=%.0f undone_local=%.0f undone_remote=%.0f "
           "parked=%.0f rejected=%.0f failed=%.0f skipped_small=%.0f postponed=%.0f "
           "unresolved=%.0f forced=%.0f ghosted=%.0f forwarded=%.0f "
           "iface_edges=%.0f iface_len=%.4f\n",
           S("cav_local"), S("cav_remote"), S("undone_local"), S("undone_remote"), S("parked"),
           S("rejected"), S("failed"), S("skipped_small"), S("postponed"), S("unresolved"),
           S("forced"), S("ghosted"), S("forwarded"), S("iface_edges") / 2, S("iface_len") / 2);
    double ncav = S("cav_local") + S("cav_remote");
    printf("blocking: tasks_blocked=%.0f most_at_once=%.0f wait_sum_s=%.4f wait_max_s=%.4f "
           "remote_cavity_pct=%.2f\n",
           S("tasks_blocked"), M("most_at_once"), S("wait_sum_s"), M("wait_max_s"),
           ncav > 0 ? 100 * S("cav_remote") / ncav : 0.0);
    double nonidle = S("busy_s") + S("comm_s");
    double nt = sum->ntris > 0 ? (double)sum->ntris : 1, lat, bw;
    rt_net_get(&lat, &bw);
    printf("stats: ranks=%d triangles=%ld vertices=%ld rsr=%.0f undone=%.0f "
           "min_angle=%.4f mesh_s=%.3f busy_max_s=%.3f busy_sum_s=%.3f comm_pct=%.2f "
           "undo_pct=%.2f speedup_model=%.2f peak_rss_mb=%.1f bytes_per_tri=%.1f "
           "mesh_bytes_per_tri=%.1f phase1_s=%.3f cpu_max_s=%.3f cpu_sum_s=%.3f output_s=%.3f "
           "comm_s=%.4f comm_max_s=%.4f handler_s=%.4f net_latency_us=%.1f net_MBps=%.1f "
           "start_s=%.3f read_s=%.3f decomp_s=%.3f wall_s=%.3f endcheck_max_s=%.4f "
           "endcheck_sum_s=%.4f\n",
           size, (long)sum->ntris, (long)sum->nverts, S("rsr_sent"),
           S("undone_local") + S("undone_remote"), sum->min_angle, M("mesh_s"), M("busy_s"),
           S("busy_s"), nonidle > 0 ? 100.0 * (S("handler_s") + S("comm_s")) / nonidle : 0.0,
           nonidle > 0 ? 100.0 * S("undo_s") / nonidle : 0.0,
           M("busy_s") > 0 ? S("busy_s") / M("busy_s") : 0.0, M("rss") / 1048576.0, S("rss") / nt,
           S("mesh_bytes") / nt, M("phase1_s"), M("cpu_s"), S("cpu_s"), M("output_s"), S("comm_s"),
           M("comm_s"), S("handler_s"), lat * 1e6, bw / 1e6, M("start_s"), M("read_s"),
           M("decomp_s"), M("wall_s"), M("endcheck_s"), S("endcheck_s"));
#undef S
#undef M
}

int run_par_main(int argc, char **argv, run_method method, par_parse_fn parse, const void *ctx) {
    par_opts o;
    int code;
    double t_start = rt_wtime(); /* wall_s: from here (before MPI's start) to the statistics */
    if (startup(&argc, &argv, method, parse, ctx, &o, &code)) return code;
    double start_s = rt_wtime() - t_start;
    run_job j;
    run_job_init(&j, method, &o);
    j.host_share = 1; /* released below (unshare) */
    pslg in;
    pcdm_decomp d;
    run_part p;
    run_stats st;
    memset(&p, 0, sizeof p);
    memset(&st, 0, sizeof st);
    int status = 1;
    if (run_par_load(&j, &in, &d) != 0) { /* 1. load (the job freed) */
        rt_finalize();
        return 1;
    }
    int verbose = j.o.verbose && !j.o.quiet; /* -Q wins */
    if (verbose) par_verbose_input(&j.o, &in, &d, j.read_s);
    if (run_par_mesh(&j, &in, &d, &p, &st) != 0) goto done; /* 2-4. bounds, mesh, verdict */
    /* 5, 6. the interface check, numbering, --check (held to the bounds only when they were
     * met) and the files, every rank its own part */
    par_summary sum;
    double c2 = par_cpu_seconds(), t_out = rt_wtime();
    par_opts oc = j.o;
    run_check_bounds(&j, &oc.min_angle, &oc.max_area, &oc.region_area);
    int out = par_output_sub(&oc, &in, par_dom_ahead_get(&j.dom_ahead), &p.local, p.artificial,
                             p.tsub, p.topen, &sum);
    double output_s = rt_wtime() - t_out;
    /* the mesh hash: a sum over triangles (par_output_sub's pass), so one reduction of the
     * parts' sums */
    uint64_t hash = 0;
    if (j.o.stats && method == RUN_PCDM && out == 0)
        MESH_MPI(MPI_Reduce(&sum.hash, &hash, 1, MPI_UINT64_T, MPI_SUM, 0, rt_app_comm()));
    int32_t rounds = p.rounds;
    double mesh_s = p.mesh_s;
    run_part_free(&p);
    /* statistics: memory taken now, after the output */
    double rss = (double)par_peak_rss_bytes(), ntri = run_stats_get(&st, "triangles");
    run_stats_set(&st, "output_s", 3, 1, output_s);
    if (method == RUN_PCDM) {
        run_stats_set(&st, "number_s", 3, 1, sum.number_s);
        run_stats_set(&st, "write_s", 3, 1, sum.write_s);
        run_stats_set(&st, "output_cpu_s", 3, 1, par_cpu_seconds() - c2);
    }
    run_stats_set(&st, "peak_rss_mb", 1, 1, rss / 1048576.0);
    run_stats_set(&st, "bytes_per_tri", 1, 1, rss / (ntri > 0 ? ntri : 1));
    run_stats_set(&st, "rss", 0, 0, rss);
    if (verbose && out == 0)
        par_verbose_result(&j.o, mesh_s, sum.ntris, sum.nverts, sum.min_angle,
                           run_stats_get(&st, "output_s"));
    run_stats_set(&st, "start_s", 3, 0, start_s);
    run_stats_set(&st, "read_s", 3, 1, j.read_s);
    run_stats_set(&st, "decomp_s", 3, 0, d.build_s);
    run_stats_set(&st, "wall_s", 3, 1, rt_wtime() - t_start);
    if (run_stats_collect(&st, j.o.stats)) {
        run_stats_rank_lines(&st, rt_size(), stdout);
        if (method == RUN_PCDM)
            print_pcdm_stats(&j, &st, &sum, &d, rounds, hash);
        else
            print_pbw_stats(&st, &sum);
    }
    fflush(stdout);
    status = run_exit_status(j.verdict, out); /* 7. exit status */
done:
    par_dom_ahead_get(&j.dom_ahead); /* joined before in goes */
    run_part_free(&p);
    run_stats_free(&st);
    unshare(&j, &in, &d);
    pcdm_decomp_free(&d);
    pslg_free(&in);
    run_job_free(&j);
    rt_finalize();
    return status;
}
