/* rt_stats.c - the runtime's statistics: counters, time buckets, reductions and a table.
 *
 * TR-97-17 section 4 splits the overhead of the meshers into communication (creating RSRs,
 * releasing them to the network, retrieving and queueing them) and undo computation; Tables
 * 2 and 3 count RSRs.  We keep per handler: RSRs sent and received and their payload bytes
 * and the time spent in it; per rank: RSRs, MPI messages (an aggregate of many RSRs is one
 * message) and bytes, tasks, termination waves, the blocking queue (times a task blocked,
 * most tasks blocked at once, total and longest time blocked; kept by rt_task.c), and time
 * in handlers, communication, idle, busy (tasks + local work) and an application bucket
 * (RT_TIME_UNDO).  Counters are updated by the main thread only (threaded handlers report
 * their time through their completion), so no atomics are needed.  Reductions and the table
 * are collectives over rt_comm().  Fields travel as two arrays (integers, doubles); the
 * maxima (blocked_max, blocked_time_max) are reduced with MPI_MAX even into the "sum".
 */
#include "rt_internal.h"

#include <string.h>

/* Integer and double fields, in array order; U_BMAX and D_BMAX are the maxima. */
enum {
    NU64 = 13,
    U_BMAX = 12,
    ND = RT_TIME_NBUCKETS + 3,
    D_BSUM = RT_TIME_NBUCKETS,
    D_BMAX,
    D_COMM
};

static void to_arrays(const rt_stats *s, uint64_t u[NU64], double d[ND]) {
    uint64_t v[NU64] = {s->rsr_sent,      s->rsr_recv,   s->rsr_bytes_sent, s->rsr_bytes_recv,
                        s->mpi_sent,      s->mpi_recv,   s->mpi_bytes_sent, s->mpi_bytes_recv,
                        s->tasks_spawned, s->tasks_done, s->waves,          s->blocked_count,
                        s->blocked_max};
    memcpy(u, v, sizeof v);
    memcpy(d, s->time, sizeof s->time);
    d[D_BSUM] = s->blocked_time_sum;
    d[D_BMAX] = s->blocked_time_max;
    d[D_COMM] = s->comm_s;
}

static void from_arrays(rt_stats *s, const uint64_t u[NU64], const double d[ND]) {
    s->rsr_sent = u[0];
    s->rsr_recv = u[1];
    s->rsr_bytes_sent = u[2];
    s->rsr_bytes_recv = u[3];
    s->mpi_sent = u[4];
    s->mpi_recv = u[5];
    s->mpi_bytes_sent = u[6];
    s->mpi_bytes_recv = u[7];
    s->tasks_spawned = u[8];
    s->tasks_done = u[9];
    s->waves = u[10];
    s->blocked_count = u[11];
    s->blocked_max = u[U_BMAX];
    memcpy(s->time, d, sizeof s->time);
    s->blocked_time_sum = d[D_BSUM];
    s->blocked_time_max = d[D_BMAX];
    s->comm_s = d[D_COMM];
}

void rt_stats_local(rt_stats *out) {
    *out = rt_g.st;
    out->tasks_spawned = rt_g.tasks.spawned;
    out->tasks_done = rt_g.tasks.done;
    out->waves = rt_g.term.waves;
    out->blocked_count = rt_g.tasks.blocked_count;
    out->blocked_max = rt_g.tasks.blocked_max;
    out->blocked_time_sum = rt_g.tasks.blocked_time_sum;
    out->blocked_time_max = rt_g.tasks.blocked_time_max;
}

int rt_stats_handler(int id, rt_handler_stats *out) {
    if (id < 0 || id >= rt_g.ht.n) return RT_EINVAL;
    const rt_hentry *e = &rt_g.ht.e[id];
    memcpy(out->name, e->name, RT_NAME_MAX);
    out->sent = e->sent;
    out->sent_self = e->sent_self;
    out->recv = e->recv;
    out->bytes_sent = e->bytes_sent;
    out->bytes_recv = e->bytes_recv;
    out->time = e->time;
    return RT_OK;
}

void rt_stats_reduce(rt_stats *sum, rt_stats *max) {
    rt_stats me;
    rt_stats_local(&me);
    uint64_t u[NU64], su[NU64], mu[NU64];
    double d[ND], sd[ND], md[ND];
    to_arrays(&me, u, d);
    if (!sum && !max) return;
    /* The maxima are needed by both results. */
    RT_MPI(MPI_Allreduce(u, mu, NU64, MPI_UINT64_T, MPI_MAX, rt_g.comm));
    RT_MPI(MPI_Allreduce(d, md, ND, MPI_DOUBLE, MPI_MAX, rt_g.comm));
    if (sum) {
        RT_MPI(MPI_Allreduce(u, su, NU64, MPI_UINT64_T, MPI_SUM, rt_g.comm));
        RT_MPI(MPI_Allreduce(d, sd, ND, MPI_DOUBLE, MPI_SUM, rt_g.comm));
        su[U_BMAX] = mu[U_BMAX];
        sd[D_BMAX] = md[D_BMAX];
        from_arrays(sum, su, sd);
    }
    if (max) from_arrays(max, mu, md);
}

void rt_stats_add_time(rt_time_bucket b, double seconds) {
    if ((int)b < 0 || b >= RT_TIME_NBUCKETS) RT_FATAL("rt_stats_add_time: bad bucket %d", (int)b);
    rt_g.st.time[b] += seconds;
}

void rt_stats_reset(void) {
    memset(&rt_g.st, 0, sizeof rt_g.st);
    for (int i = 0; i < rt_g.ht.n; i++) {
        rt_hentry *e = &rt_g.ht.e[i];
        e->sent = e->sent_self = e->recv = e->bytes_sent = e->bytes_recv = 0;
        e->time = 0;
    }
    rt_tasks_reset_stats(&rt_g.tasks);
    rt_g.term.waves = 0;
}

void rt_stats_print(FILE *f) {
    int p = rt_g.size, nh = rt_g.ht.n;
    rt_stats me;
    rt_stats_local(&me);
    /* per rank: NU64 counters, ND times; per handler: 4 counters and a time */
    uint64_t u[NU64];
    double d[ND];
    to_arrays(&me, u, d);
    uint64_t *hu = rt_xmalloc(sizeof *hu * 4 * (size_t)(nh ? nh : 1));
    double *hd = rt_xmalloc(sizeof *hd * (size_t)(nh ? nh : 1));
    for (int i = 0; i < nh; i++) {
        const rt_hentry *e = &rt_g.ht.e[i];
        hu[4 * i] = e->sent;
        hu[4 * i + 1] = e->recv;
        hu[4 * i + 2] = e->bytes_sent;
        hu[4 * i + 3] = e->bytes_recv;
        hd[i] = e->time;
    }
    bool root = rt_g.rank == 0;
    uint64_t *au = root ? rt_xmalloc(sizeof *au * NU64 * (size_t)p) : NULL;
    double *ad = root ? rt_xmalloc(sizeof *ad * ND * (size_t)p) : NULL;
    uint64_t *shu = root ? rt_xmalloc(sizeof *shu * 4 * (size_t)(nh ? nh : 1)) : NULL;
    double *shd = root ? rt_xmalloc(sizeof *shd * (size_t)(nh ? nh : 1)) : NULL;
    RT_MPI(MPI_Gather(u, NU64, MPI_UINT64_T, au, NU64, MPI_UINT64_T, 0, rt_g.comm));
    RT_MPI(MPI_Gather(d, ND, MPI_DOUBLE, ad, ND, MPI_DOUBLE, 0, rt_g.comm));
    if (nh) {
        RT_MPI(MPI_Reduce(hu, shu, 4 * nh, MPI_UINT64_T, MPI_SUM, 0, rt_g.comm));
        RT_MPI(MPI_Reduce(hd, shd, nh, MPI_DOUBLE, MPI_SUM, 0, rt_g.comm));
    }
    if (root && f) {
        /* blocks: times a task blocked; blk_max: most blocked at once; blk_s, blk_max_s:
         * total and longest time blocked */
        fprintf(f, "%4s %10s %10s %9s %9s %12s %8s %8s %8s %8s %8s %8s %8s %7s %8s %9s\n", "rank",
                "rsr_sent", "rsr_recv", "mpi_sent", "mpi_recv", "mpi_bytes", "tasks", "handl_s",
                "comm_s", "idle_s", "busy_s", "undo_s", "blocks", "blk_max", "blk_s", "blk_max_s");
        for (int r = 0; r < p; r++) {
            const uint64_t *x = au + (size_t)r * NU64;
            const double *t = ad + (size_t)r * ND;
            fprintf(f,
                    "%4d %10llu %10llu %9llu %9llu %12llu %8llu %8.3f %8.3f %8.3f %8.3f %8.3f "
                    "%8llu %7llu %8.3f %9.6f\n",
                    r, (unsigned long long)x[0], (unsigned long long)x[1], (unsigned long long)x[4],
                    (unsigned long long)x[5], (unsigned long long)x[6], (unsigned long long)x[9],
                    t[RT_TIME_HANDLER], t[RT_TIME_COMM], t[RT_TIME_IDLE], t[RT_TIME_BUSY],
                    t[RT_TIME_UNDO], (unsigned long long)x[11], (unsigned long long)x[U_BMAX],
                    t[D_BSUM], t[D_BMAX]);
        }
        fprintf(f, "%-24s %10s %10s %12s %12s %9s\n", "handler", "sent", "recv", "bytes_sent",
                "bytes_recv", "time_s");
        for (int i = 0; i < nh; i++)
            fprintf(f, "%-24s %10llu %10llu %12llu %12llu %9.3f\n", rt_g.ht.e[i].name,
                    (unsigned long long)shu[4 * i], (unsigned long long)shu[4 * i + 1],
                    (unsigned long long)shu[4 * i + 2], (unsigned long long)shu[4 * i + 3], shd[i]);
        fflush(f);
    }
    rt_xfree(hu);
    rt_xfree(hd);
    rt_xfree(au);
    rt_xfree(ad);
    rt_xfree(shu);
    rt_xfree(shd);
}
