/* pcdm: Parallel Constrained Delaunay Meshing (Chew, Chrisochoides, Sukup, TR-97-17).
 *
 *   mpirun -np P ./pcdm [options] input.poly        (options: ./pcdm --help)
 *
 * SPMD main: every rank reads the input and computes the same decomposition (par_load), builds
 * the coarse CDT of the augmented PSLG, keeps its own subdomains and refines them; the only
 * remote service request is "split constraint edge" (mesher/pcdm/pcdm.c); --deterministic and
 * --balance dynamic refine each subdomain in its own mesh, in rounds (pcdm_det.c), and dynamic
 * moves unstarted subdomains to idle ranks (pcdm_move.c).  After the runtime's
 * termination detector ends rt_run on every rank, each rank keeps its own part: the interfaces
 * are compared across ranks, the parts numbered by prefix sums, checked where they live
 * (--check) and written in parallel (par_output, mesher/par/pout.h); no rank gathers the mesh.
 *
 * --stats prints one line per rank ("rank R: ...") and last, on rank 0:
 *   stats: ranks=P triangles=N vertices=N rsr=S min_angle=D wall_s=T busy_max_s=B busy_sum_s=U
 *          subdomains=K idle_max_s=I max_area=A ignored=G mpi_msgs=M speedup_model=X
 *          peak_rss_mb=R bytes_per_tri=Y mesh_bytes_per_tri=Z output_s=W cpu_max_s=C
 *          cpu_sum_s=E decomp_s=D tri_max=N tri_mean=M decomp_exact=0|1 rounds=R hash=H
 *          comm_s=C comm_max_s=M handler_s=H net_latency_us=L net_MBps=B
 * (one line), after the line "rsr: split=S mpi_msgs=M" (the RSRs by kind, as ./pbw prints
 * them: ./pcdm's only kind is the split request, each sent to the owner of each side of a
 * constraint edge; ignored counts those that found the edge already split, duplicates).  rounds:
 * --deterministic's rounds (0 without); hash: the mesh hash (pcdm_flat_hash summed over the ranks'
 * parts), the same for the same mesh whatever its numbering and rank count. wall_s runs from a
 * barrier after input loading and decomposition to the moment the last rank left rt_run (CDT build
 * + region selection + refinement + termination; no numbering, no file output) -- the same span as
 * ./mesh's wall_s.  busy = time in local work and handlers (rt_stats RT_TIME_BUSY +
 * RT_TIME_HANDLER); speedup_model = busy_sum / busy_max. comm_s = the runtime's communication
 * seconds (rt_stats.comm_s: packing, sending, and the polls that received something, handler bodies
 * and empty polls excluded) summed over the ranks, comm_max_s its largest rank, handler_s the
 * handlers' seconds summed; net_* the network model in force (--net, PCDM_NET; 0 0: none). cpu =
 * CPU seconds (getrusage) over the wall_s span: unlike busy, it does not grow when the machine is
 * oversubscribed, so it measures work, not contention. peak_rss_mb is the largest rank's peak RSS
 * at the end (after the output), bytes_per_tri the sum over ranks of that peak RSS divided by the
 * number of triangles (per rank lines: its own peak over its own triangles), mesh_bytes_per_tri the
 * mesh arrays alone (mesh_memory_bytes summed over ranks / triangles); output_s the slowest rank's
 * seconds in par_output (numbering, --check, writing); per rank also output_cpu_s, its CPU seconds
 * in par_output. Options, usage errors and exit statuses (the same on every rank): the front end,
 * apps/cli.c
 * (./pcdm --help).
 */
#include "pcdm/pcdm.h"

#include "base/base.h"
#include "cli.h"
#include "par/par.h"
#include "par/pout.h"
#include "rt.h"
#include "seq/mesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

enum {
    RS_NTRIS,
    RS_NVERTS,
    RS_NSUB,
    RS_SENT,
    RS_RECV,
    RS_IGNORED,
    RS_NOTFOUND,
    RS_BUSY,
    RS_IDLE,
    RS_HANDLER,
    RS_COMM,
    RS_RSS,
    RS_MESHBYTES,
    RS_INSERTED,
    RS_MPI,
    RS_WALL,
    RS_CPU,
    RS_OUT,
    RS_NUMBER,
    RS_WRITE,
    RS_OUTCPU,
    RS_MIGR,
    RS_MOVED,
    RS_MOVES,
    RS_FWD,
    RS_N
};

int main(int argc, char **argv) {
    par_opts o;
    pslg in;
    pcdm_decomp d;
    int code, rc;
    if (par_startup(&argc, &argv, cli_pcdm.name, cli_par_parse, &cli_pcdm, pcdm_register, &o, &in,
                    &d, &code))
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

    /* wall_s starts here: input read, checked and decomposed on every rank */
    MESH_MPI(MPI_Barrier(comm));
    double t0 = rt_wtime(), c0 = par_cpu_seconds();
    char err[1024], msg[1200];
    pcdm_part part;
    int regions = o.region_area   ? PCDM_REGIONS_AREA
                  : o.region_attr ? PCDM_REGIONS_LABEL
                                  : PCDM_REGIONS_NONE;
    int dyn = par_balance_dynamic(&o);
    int det = o.deterministic || dyn; /* subdomains move between ranks only as whole meshes */
    rc = det ? pcdm_part_build_det(&part, &d, rank, regions, err, sizeof err)
             : pcdm_part_build_regions(&part, &d, rank, regions, err, sizeof err);
    snprintf(msg, sizeof msg, "pcdm: %s", err);
    if (par_fail_any(rc != 0, msg)) {
        if (rc == 0) pcdm_part_free(&part);
        pcdm_decomp_free(&d);
        pslg_free(&in);
        rt_finalize();
        return 1;
    }
    part.progress = o.progress && !o.quiet && rank == 0;
    mesh_quality q;
    memset(&q, 0, sizeof q);
    /* a hair above the requested bound, as ./mesh does, so rounding in the quality test can
     * never leave a triangle a few ulps below it */
    q.min_angle = o.min_angle > 0 ? o.min_angle * (1 + 1e-9) + 1e-12 : 0;
    q.max_area = o.max_area;
    q.offcenter = !o.circumcenters; /* as ./mesh; lens stays 0: diametral circles make the interface
                        subsegments Delaunay edges of the merged mesh */
    q.max_steiner = -1;
    if (o.max_steiner >= 0 && det) { /* shared by the subdomains (pcdm_det.c) */
        q.max_steiner = o.max_steiner;
    } else if (o.max_steiner >= 0) { /* the global budget shared by target weight */
        double share = 0;
        for (int32_t s = 0; s < d.nsub; s++)
            if (d.sub_owner[s] == rank) share += d.sub_target[s];
        q.max_steiner = (int64_t)((double)o.max_steiner * share);
    }
    rt_stats_reset();
    if (o.unsuitable) mesh_set_size_rule(&part.m, o.unsuitable, o.unsuitable_ctx);
    part.balance = dyn;
    pcdm_part_refine(&part, &q, o.poll_every > 0 ? o.poll_every : 300);
    double t1 = rt_wtime();

    /* figures from the mesh first: the part is then moved into its flat form (never held
     * twice, the memory peak), then the common end: interface check, numbering, --check,
     * output */
    pcdm_figures fig;
    pcdm_part_figures(&part, &fig);
    double rs[RS_N], *all = NULL;
    rt_stats st;
    rt_stats_local(&st);
    memset(rs, 0, sizeof rs);
    rs[RS_NTRIS] = (double)fig.ntris;
    rs[RS_NVERTS] = (double)fig.nverts;
    rs[RS_NSUB] = part.nsub_owned;
    rs[RS_SENT] = (double)part.split_sent;
    rs[RS_RECV] = (double)part.split_recv;
    rs[RS_IGNORED] = (double)part.split_ignored;
    rs[RS_NOTFOUND] = (double)part.split_notfound;
    rs[RS_BUSY] = st.time[RT_TIME_BUSY] + st.time[RT_TIME_HANDLER];
    rs[RS_IDLE] = st.time[RT_TIME_IDLE];
    rs[RS_HANDLER] = st.time[RT_TIME_HANDLER];
    rs[RS_COMM] = st.comm_s; /* the runtime's measure: sends and polls that found something */
    rs[RS_MESHBYTES] = (double)fig.mesh_bytes;
    rs[RS_INSERTED] = (double)fig.inserted;
    rs[RS_MPI] = (double)st.mpi_sent;
    rs[RS_WALL] = t1 - t0;
    rs[RS_CPU] = par_cpu_seconds() - c0;
    rs[RS_MIGR] = (double)part.migrations;
    rs[RS_MOVED] = (double)part.moved_bytes;
    rs[RS_MOVES] = part.move_s;
    rs[RS_FWD] = (double)part.forwarded;
    int limit_any = 0;
    MESH_MPI(MPI_Allreduce(&part.limit_hit, &limit_any, 1, MPI_INT, MPI_MAX, comm));
    /* never a silent success outside the bounds (as ./mesh): what is left must be forced by an
     * input corner (corners of the decomposition get no exemption), or the Steiner limit the
     * user set stopped refinement (exit 3: the mesh written, checked without the bounds) */
    long long unmet = (long long)fig.unmet, unmet_all = 0;
    MESH_MPI(MPI_Allreduce(&unmet, &unmet_all, 1, MPI_LONG_LONG, MPI_SUM, comm));
    /* an interface piece split on one side only, or still encroached (a split refinement
     * refused: interfaces at a tiny angle, precision): the parts would not form a Delaunay mesh
     * of the input; an error on every rank, nothing written (not even with --write-partial) */
    long long enc[2] = {(long long)fig.iface_enc, (long long)fig.iface_remote}, enc_all[2];
    MESH_MPI(MPI_Allreduce(enc, enc_all, 2, MPI_LONG_LONG, MPI_SUM, comm));
    if (enc_all[0] > 0) {
        if (rank == 0)
            fprintf(stderr,
                    "pcdm: %s: cannot meet the bounds: %lld subdomain interface pieces could "
                    "not be split on both sides (splits refused: interfaces meeting at a tiny "
                    "angle, or features below the precision of the coordinates); the parts "
                    "would not form a Delaunay mesh of the input, none written\n",
                    o.input, enc_all[0]);
        pcdm_part_free(&part);
        pcdm_decomp_free(&d);
        size_field_free(&sizes);
        pslg_free(&in);
        rt_finalize();
        return 1;
    }
    int limited = limit_any && unmet_all > 0;
    if (limited && rank == 0)
        fprintf(stderr,
                "pcdm: %s: Steiner point limit (-S %lld) reached with %lld triangles outside the "
                "bounds; the mesh is conforming but does not meet them (exit status 3)\n",
                o.input, (long long)o.max_steiner, unmet_all);
    /* bounds refinement cannot reach: an error on every rank; the mesh made so far is written
     * (checked without the bounds) only with --write-partial */
    int partial = unmet_all > 0 && !limited;
    if (partial && rank == 0)
        fprintf(stderr,
                "pcdm: %s: cannot meet the bounds: %lld triangles still violate them "
                "(features below the precision of the coordinates, a region too thin for its "
                "length, or -q %g beyond what refinement reaches on this input)%s\n",
                o.input, unmet_all, o.min_angle,
                o.write_partial ? "; writing the mesh made so far (--write-partial)" : "");
    if (partial && !o.write_partial) {
        pcdm_part_free(&part);
        pcdm_decomp_free(&d);
        pslg_free(&in);
        rt_finalize();
        return 1;
    }
    mesh_flat local;
    int32_t *tsub = NULL;
    uint8_t *topen = NULL;
    uint8_t *artificial = NULL;
    int32_t rounds = part.rounds;
    pcdm_part_take(&part, &local, &artificial, o.vtk ? &tsub : NULL, &topen);
    pcdm_part_free(&part);
    if (enc_all[1] > 0) { /* interface pieces left encroached: Delaunay across the ranks? */
        char imsg[512];
        long bad = par_check_interface_delaunay(&local, topen, imsg, sizeof imsg), bad_all = 0;
        MESH_MPI(MPI_Allreduce(&bad, &bad_all, 1, MPI_LONG, MPI_SUM, comm));
        snprintf(msg, sizeof msg,
                 "pcdm: %s: cannot meet the bounds: %ld subdomain interface edges are not "
                 "Delaunay across the ranks (their splits were refused: features below the "
                 "precision of the coordinates); none written",
                 o.input, bad_all);
        if (par_fail_any(bad_all > 0, msg)) {
            free(artificial);
            free(tsub);
            free(topen);
            mesh_flat_free(&local);
            pcdm_decomp_free(&d);
            size_field_free(&sizes);
            pslg_free(&in);
            rt_finalize();
            return 1;
        }
    }
    /* the mesh hash: a sum over triangles, so one reduction of the parts' sums */
    uint64_t hash = 0, hash_part = o.stats ? pcdm_flat_hash(&local) : 0;
    if (o.stats) MESH_MPI(MPI_Reduce(&hash_part, &hash, 1, MPI_UINT64_T, MPI_SUM, 0, comm));
    par_summary sum;
    double c2 = par_cpu_seconds();
    par_opts oc = o; /* what --check holds the mesh to */
    if (limited || partial) oc.min_angle = oc.max_area = 0, oc.region_area = 0;
    int status = par_output_sub(&oc, &in, &local, artificial, tsub, topen, &sum);
    free(artificial);
    free(tsub);
    free(topen);
    mesh_flat_free(&local);
    /* statistics: reductions of per-rank figures; memory taken now, after the output */
    rs[RS_RSS] = (double)par_peak_rss_bytes();
    rs[RS_OUT] = sum.number_s + sum.check_s + sum.write_s;
    rs[RS_NUMBER] = sum.number_s;
    rs[RS_WRITE] = sum.write_s;
    rs[RS_OUTCPU] = par_cpu_seconds() - c2;
    if (verbose && status == 0)
        par_verbose_result(&o, rs[RS_WALL], sum.ntris, sum.nverts, sum.min_angle, rs[RS_OUT]);
    double tot[RS_N], mx[RS_N];
    all = par_stats_collect(rs, RS_N, o.stats, tot, mx);
    if (all) {
        for (int r = 0; r < size; r++) {
            const double *x = all + (size_t)r * RS_N;
            printf(
                "rank %d: subdomains=%.0f triangles=%.0f vertices=%.0f inserted=%.0f "
                "split_sent=%.0f split_recv=%.0f split_ignored=%.0f busy_s=%.3f "
                "idle_s=%.3f handler_s=%.3f comm_s=%.3f cpu_s=%.3f mpi_msgs=%.0f "
                "output_s=%.3f number_s=%.3f write_s=%.3f output_cpu_s=%.3f peak_rss_mb=%.1f "
                "bytes_per_tri=%.1f migrations=%.0f moved_bytes=%.0f move_s=%.4f forwarded=%.0f\n",
                r, x[RS_NSUB], x[RS_NTRIS], x[RS_NVERTS], x[RS_INSERTED], x[RS_SENT], x[RS_RECV],
                x[RS_IGNORED], x[RS_BUSY], x[RS_IDLE], x[RS_HANDLER], x[RS_COMM], x[RS_CPU],
                x[RS_MPI], x[RS_OUT], x[RS_NUMBER], x[RS_WRITE], x[RS_OUTCPU],
                x[RS_RSS] / 1048576.0, x[RS_RSS] / (x[RS_NTRIS] > 0 ? x[RS_NTRIS] : 1), x[RS_MIGR],
                x[RS_MOVED], x[RS_MOVES], x[RS_FWD]);
        }
        if (tot[RS_NOTFOUND] > 0)
            fprintf(stderr, "pcdm: warning: %.0f split requests named no subsegment\n",
                    tot[RS_NOTFOUND]);
        double nt = sum.ntris > 0 ? (double)sum.ntris : 1, lat, bw;
        rt_net_get(&lat, &bw);
        printf("rsr: split=%.0f mpi_msgs=%.0f\n", tot[RS_SENT], tot[RS_MPI]);
        printf("stats: ranks=%d triangles=%lld vertices=%lld rsr=%.0f min_angle=%.4f "
               "wall_s=%.3f busy_max_s=%.3f busy_sum_s=%.3f subdomains=%d idle_max_s=%.3f "
               "max_area=%.6g ignored=%.0f mpi_msgs=%.0f speedup_model=%.2f "
               "peak_rss_mb=%.1f bytes_per_tri=%.1f mesh_bytes_per_tri=%.1f output_s=%.3f "
               "cpu_max_s=%.3f cpu_sum_s=%.3f decomp_s=%.3f tri_max=%.0f tri_mean=%.1f "
               "decomp_exact=%d rounds=%d hash=%016llx balance=%s migrations=%.0f "
               "moved_bytes=%.0f move_max_s=%.4f forwarded=%.0f comm_s=%.4f comm_max_s=%.4f "
               "handler_s=%.4f net_latency_us=%.1f net_MBps=%.1f\n",
               size, (long long)sum.ntris, (long long)sum.nverts, tot[RS_SENT], sum.min_angle,
               mx[RS_WALL], mx[RS_BUSY], tot[RS_BUSY], (int)d.nsub, mx[RS_IDLE], sum.max_area,
               tot[RS_IGNORED], tot[RS_MPI], mx[RS_BUSY] > 0 ? tot[RS_BUSY] / mx[RS_BUSY] : 0.0,
               mx[RS_RSS] / 1048576.0, tot[RS_RSS] / nt, tot[RS_MESHBYTES] / nt, mx[RS_OUT],
               mx[RS_CPU], tot[RS_CPU], d.build_s, mx[RS_NTRIS], tot[RS_NTRIS] / size, d.exact,
               (int)rounds, (unsigned long long)hash, dyn ? "dynamic" : "static", tot[RS_MIGR],
               tot[RS_MOVED], mx[RS_MOVES], tot[RS_FWD], tot[RS_COMM], mx[RS_COMM], tot[RS_HANDLER],
               lat * 1e6, bw / 1e6);
    }
    fflush(stdout);
    free(all);
    pcdm_decomp_free(&d);
    size_field_free(&sizes);
    pslg_free(&in);
    rt_finalize();
    return partial ? 1 : status == 0 && limited ? 3 : status;
}
