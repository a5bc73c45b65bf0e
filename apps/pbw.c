/* pbw: the Parallel Meshing Algorithm (parallel Bowyer-Watson, TR-97-17 section 2).
 *
 *   mpirun -np P ./pbw [options] input.poly        (options: ./pbw --help: ./pcdm's and --phases)
 *
 * SPMD main: every rank reads the input and the decomposition (par_load; the decomposition
 * only says which rank owns which triangle of the initial CDT), then mesher/pbw/pbw.c refines the
 * one distributed mesh with remote cavity expansions, locks and undo.  After the runtime's
 * termination detector ends rt_run everywhere, each rank keeps its own triangles: the
 * interfaces are compared across ranks, the parts numbered by prefix sums, checked where they
 * live (--check) and written in parallel (par_output, mesher/par/pout.h); no gather.
 *
 * --stats prints one line per rank, then the RSRs by kind and the cavity counters, and last:
 *   stats: ranks=P triangles=N vertices=N rsr=TOTAL_RSRS undone=CAVITIES_UNDONE min_angle=D
 *          wall_s=T busy_max_s=B busy_sum_s=S comm_pct=C undo_pct=U speedup_model=X
 *          peak_rss_mb=R bytes_per_tri=Y mesh_bytes_per_tri=Z phase1_s=F cpu_max_s=C
 *          cpu_sum_s=E output_s=W comm_s=C comm_max_s=M handler_s=H net_latency_us=L net_MBps=B
 *          endcheck_max_s=K endcheck_sum_s=L
 * (one line).  Definitions (rt_stats time buckets, summed over ranks, inside rt_run):
 *   busy (per rank)  = RT_TIME_BUSY + RT_TIME_HANDLER (local work, tasks and handlers), as
 *                      ./pcdm; speedup_model = busy_sum / busy_max.
 *   comm (per rank)  = rt_stats.comm_s: packing and sending RSRs and the polls that received
 *                      something (handler bodies and polls that found nothing excluded), the
 *                      same measure as ./pcdm's; comm_s = its sum over ranks, comm_max_s the
 *                      largest rank's, handler_s the handlers' seconds summed.
 *   non-idle         = RT_TIME_BUSY + RT_TIME_HANDLER + comm.
 *   comm_pct         = 100 * sum(RT_TIME_HANDLER + comm) / sum(non-idle): the paper's
 *                      "communication overhead" -- creating, sending, receiving and servicing
 *                      RSRs (remote expansions, commits, releases included).
 *   net_latency_us, net_MBps: the network model in force (--net, PCDM_NET; 0 0: none).
 *   endcheck_max_s, endcheck_sum_s = the largest rank's and the summed seconds of the
 *                      always-on end check of the Delaunay property (the edges the general
 *                      path committed and the rank boundary's; in cpu_max_s and cpu_sum_s).
 *   undo_pct         = 100 * sum(RT_TIME_UNDO) / sum(non-idle): the paper's "undo computation
 *                      overhead" -- expansion work (local and remote) of cavities released
 *                      after a lock conflict.
 *   undone           = cavity attempts abandoned after a lock conflict (local + distributed).
 *   rsr              = every RSR sent by every rank (self-sends included).
 *   wall_s           = from a barrier after loading to the last rank leaving pbw_mesh (CDT,
 *                      distribution, refinement, termination; no gather, no output).
 * Options, usage errors and exit statuses (the same on every rank): the front end, apps/cli.c
 * (./pbw --help).
 */
#include "pbw/pbw.h"

#include "base/base.h"
#include "cli.h"
#include "geom/geom.h"
#include "par/par.h"
#include "par/pout.h"
#include "rt.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    RS_NTRIS,
    RS_INSERTED,
    RS_SPLITS,
    RS_CLOCAL,
    RS_CREMOTE,
    RS_ULOCAL,
    RS_UREMOTE,
    RS_PARKED,
    RS_REJECTED,
    RS_SKIPPED,
    RS_FAILED,
    RS_POSTPONED,
    RS_LIMIT,
    RS_BUSY,
    RS_IDLE,
    RS_HANDLER,
    RS_COMM,
    RS_UNDO,
    RS_RSS,
    RS_MESHBYTES,
    RS_WALL,
    RS_PHASE1,
    RS_CPU,
    RS_MPI,
    RS_RSR,
    RS_OUT,
    RS_UNRESOLVED,
    RS_FORCED,
    RS_BLOCKED,  /* times a cavity task blocked (the runtime's blocking queue) */
    RS_BLKMAX,   /* most tasks blocked at once */
    RS_BLKSUM,   /* seconds tasks spent blocked, summed */
    RS_BLKTMAX,  /* longest single wait, seconds */
    RS_GHOSTED,  /* committed cavities kept local by ghosts (a tombstone instead of locks) */
    RS_FORWARD,  /* stale links forwarded through a tombstone */
    RS_IFEDGES,  /* rank boundary edges (each counted by both sides) */
    RS_IFLEN,    /* their length */
    RS_SELF,     /* RSRs a rank sent to itself (not in rsr=, which counts communication) */
    RS_ENDCHECK, /* seconds of the end check of the Delaunay property */
    RS_KIND0,
    RS_N = RS_KIND0 + PBW_RSR_NKINDS
};

int main(int argc, char **argv) {
    par_opts o;
    pslg in;
    pcdm_decomp d;
    int code;
    if (par_startup(&argc, &argv, cli_pbw.name, cli_par_parse, &cli_pbw, pbw_register, &o, &in, &d,
                    &code))
        return code;
    size_field sizes;
    if (par_load_sizes(&o, &in, &sizes) != 0) {
        pcdm_decomp_free(&d);
        pslg_free(&in);
        rt_finalize();
        return 1;
    }
    int rank = rt_rank(), size = rt_size();
    MPI_Comm comm = rt_app_comm();
    int verbose = o.verbose && !o.quiet; /* -Q wins */
    if (verbose) par_verbose_input(&o, &in, &d);
    MESH_MPI(MPI_Barrier(comm));
    double t0 = rt_wtime(), c0 = par_cpu_seconds();
    rt_stats_reset();
    mesh_flat local;
    pbw_result res;
    if (pbw_mesh(&o, &in, &d, &local, &res) != 0) {
        pcdm_decomp_free(&d);
        pslg_free(&in);
        rt_finalize();
        return 1;
    }
    double t1 = rt_wtime();

    double rs[RS_N], *all = NULL;
    memset(rs, 0, sizeof rs);
    rt_stats st;
    rt_stats_local(&st);
    rs[RS_NTRIS] = (double)res.ntris;
    rs[RS_INSERTED] = (double)res.inserted;
    rs[RS_SPLITS] = (double)res.splits;
    rs[RS_CLOCAL] = (double)res.cavities_local;
    rs[RS_CREMOTE] = (double)res.cavities_remote;
    rs[RS_ULOCAL] = (double)res.undone_local;
    rs[RS_UREMOTE] = (double)res.undone_remote;
    rs[RS_PARKED] = (double)res.parked;
    rs[RS_REJECTED] = (double)res.rejected;
    rs[RS_SKIPPED] = (double)res.skipped_small;
    rs[RS_FAILED] = (double)res.failed;
    rs[RS_POSTPONED] = (double)res.postponed;
    rs[RS_GHOSTED] = (double)res.ghosted;
    rs[RS_FORWARD] = (double)res.forwarded;
    rs[RS_IFEDGES] = (double)res.iface_edges;
    rs[RS_IFLEN] = res.iface_len;
    rs[RS_LIMIT] = res.limit_hit;
    rs[RS_BUSY] = st.time[RT_TIME_BUSY] + st.time[RT_TIME_HANDLER];
    rs[RS_IDLE] = st.time[RT_TIME_IDLE];
    rs[RS_HANDLER] = st.time[RT_TIME_HANDLER];
    rs[RS_COMM] = st.comm_s; /* the runtime's measure: sends and polls that found something */
    rs[RS_UNDO] = st.time[RT_TIME_UNDO];
    rs[RS_MESHBYTES] = (double)res.mesh_bytes;
    rs[RS_WALL] = t1 - t0;
    rs[RS_PHASE1] = res.phase1_s;
    rs[RS_CPU] = par_cpu_seconds() - c0;
    rs[RS_MPI] = (double)st.mpi_sent;
    rs[RS_RSR] = (double)(st.rsr_sent - res.rsr_self);
    rs[RS_SELF] = (double)res.rsr_self;
    rs[RS_ENDCHECK] = res.endcheck_s;
    rs[RS_UNRESOLVED] = (double)res.unresolved;
    rs[RS_FORCED] = (double)res.forced;
    rs[RS_BLOCKED] = (double)st.blocked_count;
    rs[RS_BLKMAX] = (double)st.blocked_max;
    rs[RS_BLKSUM] = st.blocked_time_sum;
    rs[RS_BLKTMAX] = st.blocked_time_max;
    for (int k = 0; k < PBW_RSR_NKINDS; k++)
        rs[RS_KIND0 + k] = (double)res.rsr_sent[k];
    int limit_any = 0;
    MESH_MPI(MPI_Allreduce(&res.limit_hit, &limit_any, 1, MPI_INT, MPI_MAX, comm));
    /* never a silent success outside the bounds (as ./mesh and ./pcdm): what is left must be
     * forced by the input (a rank that gave up, refusals past the budget, always leaves some),
     * or the Steiner limit the user set stopped refinement (exit 3: the mesh written, checked
     * without the bounds) */
    long long unmet[2] = {(long long)res.unmet, (long long)res.unresolved}, unmet_all[2] = {0, 0};
    MESH_MPI(MPI_Allreduce(unmet, unmet_all, 2, MPI_LONG_LONG, MPI_SUM, comm));
    int limited = limit_any && unmet_all[0] > 0;
    if (limited && rank == 0)
        fprintf(stderr,
                "pbw: %s: Steiner point limit (-S %lld) reached with %lld triangles outside the "
                "bounds; the mesh is conforming but does not meet them (exit status 3)\n",
                o.input, (long long)o.max_steiner, unmet_all[0]);
    /* bounds refinement cannot reach: an error on every rank; the mesh made so far is written
     * (checked without the bounds) only with --write-partial */
    int partial = unmet_all[0] > 0 && !limited;
    if (partial && rank == 0)
        fprintf(stderr,
                "pbw: %s: cannot meet the bounds: %lld triangles still violate them after "
                "%lld refused splits (features below the precision of the coordinates, a "
                "region too thin for its length, or -q %g beyond what refinement reaches on this "
                "input)%s\n",
                o.input, unmet_all[0], unmet_all[1], o.min_angle,
                o.write_partial ? "; writing the mesh made so far (--write-partial)" : "");
    if (partial && !o.write_partial) {
        free(res.topen);
        mesh_flat_free(&local);
        pcdm_decomp_free(&d);
        pslg_free(&in);
        rt_finalize();
        return 1;
    }
    /* the common end: interface check, numbering, --check, output (no gather) */
    par_summary sum;
    par_opts oc = o; /* what --check holds the mesh to */
    if (limited || partial) oc.min_angle = oc.max_area = 0, oc.region_area = 0;
    int status = par_output_sub(&oc, &in, &local, NULL, NULL, res.topen, &sum);
    free(res.topen);
    mesh_flat_free(&local);
    /* statistics: reductions of per-rank figures; memory taken now, after the output */
    rs[RS_RSS] = (double)par_peak_rss_bytes();
    rs[RS_OUT] = sum.number_s + sum.check_s + sum.write_s;
    if (verbose && status == 0)
        par_verbose_result(&o, rs[RS_WALL], sum.ntris, sum.nverts, sum.min_angle, rs[RS_OUT]);
    double tot[RS_N], mx[RS_N];
    all = par_stats_collect(rs, RS_N, o.stats, tot, mx);
    if (all) {
        for (int r = 0; r < size; r++) {
            const double *x = all + (size_t)r * RS_N;
            printf("rank %d: triangles=%.0f inserted=%.0f splits=%.0f cav_local=%.0f "
                   "cav_remote=%.0f undone_local=%.0f undone_remote=%.0f parked=%.0f "
                   "rsr_sent=%.0f busy_s=%.3f idle_s=%.3f handler_s=%.3f comm_s=%.3f "
                   "undo_s=%.4f output_s=%.3f peak_rss_mb=%.1f bytes_per_tri=%.1f\n",
                   r, x[RS_NTRIS], x[RS_INSERTED], x[RS_SPLITS], x[RS_CLOCAL], x[RS_CREMOTE],
                   x[RS_ULOCAL], x[RS_UREMOTE], x[RS_PARKED], x[RS_RSR], x[RS_BUSY], x[RS_IDLE],
                   x[RS_HANDLER], x[RS_COMM], x[RS_UNDO], x[RS_OUT], x[RS_RSS] / 1048576.0,
                   x[RS_RSS] / (x[RS_NTRIS] > 0 ? x[RS_NTRIS] : 1));
        }
        printf("rsr:");
        for (int k = 0; k < PBW_RSR_NKINDS; k++)
            printf(" %s=%.0f", pbw_rsr_kind_name[k], tot[RS_KIND0 + k]);
        printf(" mpi_msgs=%.0f self=%.0f\n", tot[RS_MPI], tot[RS_SELF]);
        printf("cavities: local=%.0f remote=%.0f undone_local=%.0f undone_remote=%.0f "
               "parked=%.0f rejected=%.0f failed=%.0f skipped_small=%.0f postponed=%.0f "
               "unresolved=%.0f forced=%.0f ghosted=%.0f forwarded=%.0f "
               "iface_edges=%.0f iface_len=%.4f\n",
               tot[RS_CLOCAL], tot[RS_CREMOTE], tot[RS_ULOCAL], tot[RS_UREMOTE], tot[RS_PARKED],
               tot[RS_REJECTED], tot[RS_FAILED], tot[RS_SKIPPED], tot[RS_POSTPONED],
               tot[RS_UNRESOLVED], tot[RS_FORCED], tot[RS_GHOSTED], tot[RS_FORWARD],
               tot[RS_IFEDGES] / 2, tot[RS_IFLEN] / 2);
        double ncav = tot[RS_CLOCAL] + tot[RS_CREMOTE];
        printf("blocking: tasks_blocked=%.0f most_at_once=%.0f wait_sum_s=%.4f wait_max_s=%.4f "
               "remote_cavity_pct=%.2f\n",
               tot[RS_BLOCKED], mx[RS_BLKMAX], tot[RS_BLKSUM], mx[RS_BLKTMAX],
               ncav > 0 ? 100 * tot[RS_CREMOTE] / ncav : 0.0);
        double nonidle = tot[RS_BUSY] + tot[RS_COMM];
        double nt = sum.ntris > 0 ? (double)sum.ntris : 1, lat, bw;
        rt_net_get(&lat, &bw);
        printf("stats: ranks=%d triangles=%ld vertices=%ld rsr=%.0f undone=%.0f "
               "min_angle=%.4f wall_s=%.3f busy_max_s=%.3f busy_sum_s=%.3f comm_pct=%.2f "
               "undo_pct=%.2f speedup_model=%.2f peak_rss_mb=%.1f bytes_per_tri=%.1f "
               "mesh_bytes_per_tri=%.1f phase1_s=%.3f cpu_max_s=%.3f cpu_sum_s=%.3f output_s=%.3f "
               "comm_s=%.4f comm_max_s=%.4f handler_s=%.4f net_latency_us=%.1f net_MBps=%.1f "
               "endcheck_max_s=%.4f endcheck_sum_s=%.4f\n",
               size, (long)sum.ntris, (long)sum.nverts, tot[RS_RSR],
               tot[RS_ULOCAL] + tot[RS_UREMOTE], sum.min_angle, mx[RS_WALL], mx[RS_BUSY],
               tot[RS_BUSY], nonidle > 0 ? 100.0 * (tot[RS_HANDLER] + tot[RS_COMM]) / nonidle : 0.0,
               nonidle > 0 ? 100.0 * tot[RS_UNDO] / nonidle : 0.0,
               mx[RS_BUSY] > 0 ? tot[RS_BUSY] / mx[RS_BUSY] : 0.0, mx[RS_RSS] / 1048576.0,
               tot[RS_RSS] / nt, tot[RS_MESHBYTES] / nt, mx[RS_PHASE1], mx[RS_CPU], tot[RS_CPU],
               mx[RS_OUT], tot[RS_COMM], mx[RS_COMM], tot[RS_HANDLER], lat * 1e6, bw / 1e6,
               mx[RS_ENDCHECK], tot[RS_ENDCHECK]);
        fflush(stdout);
    }
    free(all);
    pcdm_decomp_free(&d);
    size_field_free(&sizes);
    pslg_free(&in);
    rt_finalize();
    return partial ? 1 : status == 0 && limited ? 3 : status;
}
