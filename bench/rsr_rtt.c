/* rsr_rtt.c - the round trip of a null RSR through the runtime as the meshers run it (its
 * default idle policy: sleep with a growing backoff when there is nothing to do; RT_IDLE_SPIN=1
 * makes it spin), beside a raw MPI round trip (blocking MPI_Send / MPI_Recv of 0 bytes) in the
 * same run, on exactly 2 ranks, meant for two hosts (make bench-hosts).  Trials alternate
 * (raw, runtime, raw, ...) so both see the same machine load; each trial is ITERS round trips
 * after WARM unmeasured ones; the best and the median trial are printed, last the
 * machine-readable line
 *   rsr_rtt: rsr_best_us=X rsr_median_us=Y mpi_best_us=Z mpi_median_us=W msgs_per_rsr=M
 *            waves_per_rsr=V
 * (rank 0's MPI messages sent per round trip, and termination waves per round trip: rounds
 * started while a reply is on its way).
 * Rank 0 drives: its local work sends a ping when no reply is outstanding; rank 1's handler
 * answers with a pong.
 */
#include "rt.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

enum { TRIALS = 7, ITERS = 500, WARM = 50 };

typedef struct bench {
    int rank, h_ping, h_pong;
    long done, iters;
    atomic_int outstanding;
    double t0, t1;
} bench;

static bench B;

static void on_ping(const rt_msg *m, void *arg) {
    (void)arg;
    rt_rsr(m->src, B.h_pong, NULL, 0);
}

static void on_pong(const rt_msg *m, void *arg) {
    (void)m;
    (void)arg;
    atomic_store(&B.outstanding, 0);
    B.done++;
}

static int ping_work(void *ctx) {
    (void)ctx;
    if (B.rank != 0 || atomic_load(&B.outstanding)) return RT_WORK_IDLE;
    if (B.done == WARM) B.t0 = rt_wtime();
    if (B.done == B.iters + WARM) {
        if (B.t1 == 0) B.t1 = rt_wtime();
        return RT_WORK_IDLE;
    }
    atomic_store(&B.outstanding, 1);
    rt_rsr(1, B.h_ping, NULL, 0);
    return RT_WORK_BUSY;
}

static double rsr_trial(void) {
    B.iters = ITERS;
    B.done = 0;
    B.t0 = B.t1 = 0;
    atomic_store(&B.outstanding, 0);
    rt_run(ping_work, NULL);
    return 1e6 * (B.t1 - B.t0) / ITERS;
}

static double mpi_trial(void) {
    MPI_Comm c = MPI_COMM_WORLD;
    double t0 = 0;
    for (int i = 0; i < ITERS + WARM; i++) {
        if (i == WARM) t0 = MPI_Wtime();
        if (B.rank == 0) {
            MPI_Send(NULL, 0, MPI_BYTE, 1, 7, c);
            MPI_Recv(NULL, 0, MPI_BYTE, 1, 7, c, MPI_STATUS_IGNORE);
        } else {
            MPI_Recv(NULL, 0, MPI_BYTE, 0, 7, c, MPI_STATUS_IGNORE);
            MPI_Send(NULL, 0, MPI_BYTE, 0, 7, c);
        }
    }
    return 1e6 * (MPI_Wtime() - t0) / ITERS;
}

static int cmp_dbl(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv) {
    if (rt_init(&argc, &argv, NULL) != RT_OK) return 2;
    B.rank = rt_rank();
    if (rt_size() != 2) {
        if (B.rank == 0) fprintf(stderr, "rsr_rtt: run on exactly 2 ranks (got %d)\n", rt_size());
        rt_finalize();
        return 2;
    }
    B.h_ping = rt_handler_register("rtt_ping", on_ping, NULL, RT_NONTHREADED, 0);
    B.h_pong = rt_handler_register("rtt_pong", on_pong, NULL, RT_NONTHREADED, 0);
    rt_start();
    double rsr[TRIALS], mpi[TRIALS];
    rt_stats st0, st1;
    double msgs = 0, waves = 0;
    for (int k = 0; k < TRIALS; k++) {
        mpi[k] = mpi_trial();
        rt_stats_local(&st0);
        rsr[k] = rsr_trial();
        rt_stats_local(&st1);
        msgs += (double)(st1.mpi_sent - st0.mpi_sent);
        waves += (double)(st1.waves - st0.waves);
    }
    if (B.rank == 0) {
        qsort(rsr, TRIALS, sizeof rsr[0], cmp_dbl);
        qsort(mpi, TRIALS, sizeof mpi[0], cmp_dbl);
        printf("rsr_rtt: rsr_best_us=%.2f rsr_median_us=%.2f mpi_best_us=%.2f mpi_median_us=%.2f "
               "msgs_per_rsr=%.2f waves_per_rsr=%.2f\n",
               rsr[0], rsr[TRIALS / 2], mpi[0], mpi[TRIALS / 2],
               msgs / ((double)TRIALS * (ITERS + WARM)), waves / ((double)TRIALS * (ITERS + WARM)));
    }
    rt_finalize();
    return 0;
}
