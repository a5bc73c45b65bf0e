/* primitives.c - cost of the runtime's primitive operations, as TR-97-17 section 4 lists
 * them for DMCS on the SP2: thread creation, context switch, peak bandwidth, one-way latency
 * of a 0-byte message, and a non-threaded null RSR (plus a threaded one, and a worker's task as
 * ./pcdm --threads starts one: a threaded RSR to self whose handler ends by sending a
 * non-threaded RSR back to the main thread).  Each is measured through the runtime and, in the
 * same run, with raw MPI or raw pthreads, next to the paper's figure.  Run on 2 ranks; rank 0
 * drives, rank 1 serves.  The runtime busy-polls here (idle_spin) because latency is being
 * measured.  Runtime and raw trials alternate; each figure is shown as the best (min time / max
 * rate) and the median of TRIALS trials, and the last line, machine-readable, uses the best:
 *   primitives: null_rsr_us=X raw_mpi_roundtrip_us=Y ratio=R threaded_rsr_us=Z bandwidth_MBps=B
 *               thread_start_us=S worker_task_us=W context_switch_us=C
 */
#include "rt.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { TRIALS = 9, RTT_ITERS = 2000, WARM = 200, BW_MSGS = 64, BW_SIZE = 1 << 20 };

typedef struct bench {
    int rank;
    int h_ping_nt, h_ping_t, h_pong, h_self_t, h_req, h_bulk, h_ack, h_task, h_task_done;
    int ping; /* handler used for pings in this measurement */
    long iters, done;
    atomic_int outstanding;
    double t0, t1;
    int finished;
    long bulk_recv;
    unsigned char *bulk;
} bench;

static bench B;

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(const double *v, int n) {
    double w[64];
    memcpy(w, v, sizeof *v * (size_t)n);
    qsort(w, (size_t)n, sizeof *w, cmp_double);
    return w[n / 2];
}

/* The best trial: the minimum of times (lower_is_better) or the maximum of rates. */
static double best(const double *v, int lower_is_better) {
    double b = v[0];
    for (int k = 1; k < TRIALS; k++)
        b = lower_is_better ? (v[k] < b ? v[k] : b) : (v[k] > b ? v[k] : b);
    return b;
}

static void print_row(const char *name, const double *rt, const double *raw, double paper,
                      int lower_is_better) {
    char p[16] = "-";
    if (paper > 0) snprintf(p, sizeof p, "%.1f", paper);
    printf("%-40s %10.2f / %8.2f %10.2f / %8.2f %10s\n", name, best(rt, lower_is_better),
           median(rt, TRIALS), best(raw, lower_is_better), median(raw, TRIALS), p);
}

/* A barrier that sleeps instead of spinning, so the other rank keeps its core. */
static void quiet_barrier(void) {
    MPI_Request r;
    int done = 0;
    MPI_Ibarrier(MPI_COMM_WORLD, &r);
    while (!done) {
        MPI_Test(&r, &done, MPI_STATUS_IGNORE);
        if (!done) {
            struct timespec ts = {0, 20000};
            nanosleep(&ts, NULL);
        }
    }
}

/* ---- handlers --------------------------------------------------------------------------- */

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

static void on_self_t(const rt_msg *m, void *arg) {
    (void)m;
    (void)arg;
    atomic_store(&B.outstanding, 0);
}

/* A worker's task (threaded): its end goes back to the main thread as a non-threaded RSR, as
 * ./pcdm --threads' "pcdm_refine" ends with "pcdm_refined". */
static void on_task(const rt_msg *m, void *arg) {
    (void)m;
    (void)arg;
    rt_rsr(B.rank, B.h_task_done, NULL, 0);
}

static void on_task_done(const rt_msg *m, void *arg) {
    (void)m;
    (void)arg;
    atomic_store(&B.outstanding, 0);
}

static void on_req(const rt_msg *m, void *arg) {
    (void)arg;
    rt_reply(m, B.h_pong, NULL, 0);
}

static void on_bulk(const rt_msg *m, void *arg) {
    (void)arg;
    if (++B.bulk_recv == BW_MSGS) {
        B.bulk_recv = 0;
        rt_rsr(m->src, B.h_ack, NULL, 0);
    }
}

static void on_ack(const rt_msg *m, void *arg) {
    (void)m;
    (void)arg;
    B.done++;
}

/* ---- runtime measurements (local work of rank 0) ----------------------------------------- */

static int pingpong_work(void *ctx) {
    (void)ctx;
    if (B.rank != 0) return RT_WORK_IDLE;
    if (atomic_load(&B.outstanding))
        return RT_WORK_IDLE; /* waiting for a reply: idle (the reply handler wakes us) */
    if (B.done == WARM) B.t0 = rt_wtime();
    if (B.done == B.iters + WARM) {
        if (!B.finished) B.t1 = rt_wtime();
        B.finished = 1;
        return RT_WORK_IDLE;
    }
    atomic_store(&B.outstanding, 1);
    rt_rsr(1, B.ping, NULL, 0);
    return RT_WORK_BUSY;
}

static double rt_roundtrip_us(int handler) {
    B.ping = handler;
    B.iters = RTT_ITERS;
    B.done = 0;
    B.finished = 0;
    atomic_store(&B.outstanding, 0);
    rt_run(pingpong_work, NULL);
    return 1e6 * (B.t1 - B.t0) / (double)B.iters;
}

static int selfthread_work(void *ctx) {
    (void)ctx;
    if (B.rank != 0) return RT_WORK_IDLE;
    if (atomic_load(&B.outstanding))
        return RT_WORK_IDLE; /* waiting for a reply: idle (the reply handler wakes us) */
    if (B.done == WARM) B.t0 = rt_wtime();
    if (B.done == B.iters + WARM) {
        if (!B.finished) B.t1 = rt_wtime();
        B.finished = 1;
        return RT_WORK_IDLE;
    }
    B.done++;
    atomic_store(&B.outstanding, 1);
    rt_rsr(0, B.ping, NULL, 0);
    return RT_WORK_BUSY;
}

/* Rank 0 sends itself RTT_ITERS threaded RSRs (handler h), one at a time: us per RSR. */
static double self_threaded_us(int h) {
    B.ping = h;
    B.iters = RTT_ITERS;
    B.done = 0;
    B.finished = 0;
    atomic_store(&B.outstanding, 0);
    rt_run(selfthread_work, NULL);
    return 1e6 * (B.t1 - B.t0) / (double)B.iters;
}

static rt_task_status switch_task(rt_task *t, void *state) {
    (void)state;
    if (B.done == WARM) B.t0 = rt_wtime();
    if (B.done == B.iters + WARM) {
        B.t1 = rt_wtime();
        return RT_TASK_DONE;
    }
    rt_request(t, 0, B.h_req, NULL, 0);
    return RT_TASK_WAIT;
}

static int bulk_work(void *ctx) {
    (void)ctx;
    if (B.rank != 0 || B.iters == 0) return RT_WORK_IDLE;
    if (B.done == 1) {
        B.t1 = rt_wtime();
        B.iters = 0;
        return RT_WORK_BUSY;
    }
    if (B.t0 == 0) {
        B.t0 = rt_wtime();
        for (int i = 0; i < BW_MSGS; i++)
            rt_rsr(1, B.h_bulk, B.bulk, BW_SIZE);
    }
    return RT_WORK_IDLE; /* the ack handler wakes us */
}

/* ---- raw measurements -------------------------------------------------------------------- */

static double raw_roundtrip_us(void) {
    MPI_Comm c = MPI_COMM_WORLD;
    double t0 = 0;
    for (int i = 0; i < RTT_ITERS + WARM; i++) {
        if (i == WARM) t0 = MPI_Wtime();
        if (B.rank == 0) {
            MPI_Send(NULL, 0, MPI_BYTE, 1, 5, c);
            MPI_Recv(NULL, 0, MPI_BYTE, 1, 5, c, MPI_STATUS_IGNORE);
        } else {
            MPI_Recv(NULL, 0, MPI_BYTE, 0, 5, c, MPI_STATUS_IGNORE);
            MPI_Send(NULL, 0, MPI_BYTE, 0, 5, c);
        }
    }
    return 1e6 * (MPI_Wtime() - t0) / RTT_ITERS;
}

static double raw_bandwidth(void) {
    MPI_Comm c = MPI_COMM_WORLD;
    unsigned char *buf = B.bulk;
    double t0 = MPI_Wtime();
    if (B.rank == 0) {
        for (int i = 0; i < BW_MSGS; i++)
            MPI_Send(buf, BW_SIZE, MPI_BYTE, 1, 6, c);
        MPI_Recv(NULL, 0, MPI_BYTE, 1, 6, c, MPI_STATUS_IGNORE);
    } else {
        for (int i = 0; i < BW_MSGS; i++)
            MPI_Recv(buf, BW_SIZE, MPI_BYTE, 0, 6, c, MPI_STATUS_IGNORE);
        MPI_Send(NULL, 0, MPI_BYTE, 0, 6, c);
    }
    return (double)BW_MSGS * BW_SIZE / 1e6 / (MPI_Wtime() - t0);
}

static void *null_thread(void *arg) {
    return arg;
}

static double raw_thread_create_us(void) {
    enum { N = 2000 };
    double t0 = rt_wtime();
    for (int i = 0; i < N; i++) {
        pthread_t th;
        if (pthread_create(&th, NULL, null_thread, NULL) != 0) return -1;
        pthread_join(th, NULL);
    }
    return 1e6 * (rt_wtime() - t0) / N;
}

typedef struct pp {
    pthread_mutex_t m;
    pthread_cond_t c;
    int turn;
    int n;
} pp;

static void *pp_thread(void *arg) {
    pp *p = arg;
    pthread_mutex_lock(&p->m);
    for (int i = 0; i < p->n; i++) {
        while (p->turn != 1)
            pthread_cond_wait(&p->c, &p->m);
        p->turn = 0;
        pthread_cond_signal(&p->c);
    }
    pthread_mutex_unlock(&p->m);
    return NULL;
}

/* Two threads passing the turn back and forth on a condvar: time per switch. */
static double raw_context_switch_us(void) {
    pp p = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, 0, 20000};
    pthread_t th;
    pthread_create(&th, NULL, pp_thread, &p);
    double t0 = rt_wtime();
    pthread_mutex_lock(&p.m);
    for (int i = 0; i < p.n; i++) {
        p.turn = 1;
        pthread_cond_signal(&p.c);
        while (p.turn != 0)
            pthread_cond_wait(&p.c, &p.m);
    }
    pthread_mutex_unlock(&p.m);
    double dt = rt_wtime() - t0;
    pthread_join(th, NULL);
    return 1e6 * dt / (2.0 * p.n);
}

int main(int argc, char **argv) {
    rt_config cfg;
    rt_config_default(&cfg);
    cfg.idle_spin = 1;
    cfg.nworkers = 1;
    cfg.worker_spin_us = 200;
    if (rt_init(&argc, &argv, &cfg) != RT_OK) return 2;
    B.rank = rt_rank();
    if (rt_size() != 2) {
        if (B.rank == 0)
            fprintf(stderr, "primitives: run on exactly 2 ranks (got %d)\n", rt_size());
        rt_finalize();
        return 2;
    }
    B.h_ping_nt = rt_handler_register("ping_nt", on_ping, NULL, RT_NONTHREADED, 0);
    B.h_ping_t = rt_handler_register("ping_t", on_ping, NULL, RT_THREADED, 0);
    B.h_pong = rt_handler_register("pong", on_pong, NULL, RT_NONTHREADED, 0);
    B.h_self_t = rt_handler_register("self_t", on_self_t, NULL, RT_THREADED, 0);
    B.h_req = rt_handler_register("req", on_req, NULL, RT_NONTHREADED, 0);
    B.h_bulk = rt_handler_register("bulk", on_bulk, NULL, RT_VARSIZE, BW_SIZE);
    B.h_ack = rt_handler_register("ack", on_ack, NULL, RT_NONTHREADED, 0);
    B.h_task = rt_handler_register("task", on_task, NULL, RT_THREADED, 0);
    B.h_task_done = rt_handler_register("task_done", on_task_done, NULL, RT_NONTHREADED, 0);
    rt_start();
    B.bulk = calloc(BW_SIZE, 1);

    /* Runtime and raw trials alternate so both see the same machine load. */
    double raw_rt[TRIALS], nt_rt[TRIALS], t_rt[TRIALS], disp[TRIALS], task_sw[TRIALS];
    double wtask[TRIALS];
    double bw[TRIALS], raw_bw[TRIALS], raw_thr[TRIALS] = {0}, raw_sw[TRIALS] = {0};
    for (int k = 0; k < TRIALS; k++) {
        raw_rt[k] = raw_roundtrip_us();
        nt_rt[k] = rt_roundtrip_us(B.h_ping_nt);
        t_rt[k] = rt_roundtrip_us(B.h_ping_t);

        disp[k] = self_threaded_us(B.h_self_t);
        wtask[k] = self_threaded_us(B.h_task);

        B.iters = RTT_ITERS;
        B.done = 0;
        B.t0 = B.t1 = 0;
        if (B.rank == 0) rt_task_spawn(switch_task, NULL);
        rt_run(NULL, NULL);
        task_sw[k] = 1e6 * (B.t1 - B.t0) / (double)B.iters;

        B.iters = 1;
        B.done = 0;
        B.t0 = B.t1 = 0;
        rt_run(bulk_work, NULL);
        bw[k] = B.rank == 0 ? (double)BW_MSGS * BW_SIZE / 1e6 / (B.t1 - B.t0) : 0;
        raw_bw[k] = raw_bandwidth();

        if (B.rank == 0) {
            raw_thr[k] = raw_thread_create_us();
            raw_sw[k] = raw_context_switch_us();
        }
        quiet_barrier();
    }

    if (B.rank == 0) {
        printf("%-40s %21s %21s %10s\n", "primitive (2 ranks)", "runtime best / median",
               "raw best / median", "paper SP2");
        print_row("thread creation [us]", disp, raw_thr, 12.0, 1);
        printf("  runtime: threaded null RSR to self, run by a pooled worker;\n"
               "  raw: pthread_create + pthread_join of a null thread\n");
        print_row("worker task, start to end [us]", wtask, raw_thr, 12.0, 1);
        printf("  runtime: threaded RSR to self whose handler sends a non-threaded RSR back to\n"
               "  the main thread (./pcdm --threads' round on a worker, without the work)\n");
        print_row("context switch [us]", task_sw, raw_sw, 5.5, 1);
        printf("  runtime: task waits for a self request's reply and resumes;\n"
               "  raw: two pthreads passing a turn on a condvar, per switch\n");
        print_row("peak bandwidth, 1 MB payloads [MB/s]", bw, raw_bw, 33.6, 0);
        double half_nt[TRIALS], half_raw[TRIALS];
        for (int k = 0; k < TRIALS; k++) {
            half_nt[k] = nt_rt[k] / 2;
            half_raw[k] = raw_rt[k] / 2;
        }
        print_row("one-way latency, 0 bytes [us] (RTT/2)", half_nt, half_raw, 29.0, 1);
        print_row("non-threaded null RSR round trip [us]", nt_rt, raw_rt, 31.0, 1);
        print_row("threaded null RSR round trip [us]", t_rt, raw_rt, 0, 1);
        printf(
            "  raw: MPI_Send/MPI_Recv ping-pong on MPI_COMM_WORLD; bandwidth: MPI_Send of 1 MB\n");
        printf("  best = minimum (bandwidth: maximum) of %d trials of %d round trips\n", TRIALS,
               RTT_ITERS);
        double nt = best(nt_rt, 1), raw = best(raw_rt, 1);
        printf("primitives: null_rsr_us=%.2f raw_mpi_roundtrip_us=%.2f ratio=%.2f "
               "threaded_rsr_us=%.2f bandwidth_MBps=%.1f thread_start_us=%.2f worker_task_us=%.2f "
               "context_switch_us=%.2f\n",
               nt, raw, nt / raw, best(t_rt, 1), best(bw, 0), best(disp, 1), best(wtask, 1),
               best(task_sw, 1));
        fflush(stdout);
    }
    free(B.bulk);
    rt_finalize();
    return 0;
}
