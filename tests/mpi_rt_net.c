// ranks: 2 4
/* mpi_rt_net.c - the runtime's network model (rt_net_set, rt_net_parse; runtime/rt_net.c).
 *
 * The model holds each message at the receiver until latency + size/bandwidth after it was
 * sent, the link of one source carrying one message at a time.  Every rank sends to the next
 * one (a ring) one message, then a burst of BURST messages of PAYLOAD bytes, each stamped
 * with rt_wtime() (CLOCK_MONOTONIC: the same clock in every process of this node).  The
 * handlers check that no message is delivered before its due time: the single one not before
 * the latency, the last of the burst not before latency + the burst's bytes / bandwidth (a
 * lower bound that holds however slow the machine is; a 1 ms allowance covers the clock of
 * the hold, rdtsc scaled against CLOCK_MONOTONIC).  Also: every message arrives exactly once
 * and rt_run ends (termination waits for held messages), the same run without the model, and
 * the parser's accepted and rejected forms.  And rt_stats.comm_s, the communication time: a
 * run that sends no RSR adds exactly nothing to it (its empty polls and the termination
 * detector's records are not communication), while one that does adds to it on every rank
 * that received one.  Errors are reduced before asserting.
 */
#include "check_run.h"
#include "rt.h"

#include <math.h>
#include <string.h>

enum { BURST = 10, PAYLOAD = 4000 };

#define LAT 0.020  /* seconds */
#define BW 1.0e6   /* bytes per second */
#define SLACK 1e-3 /* clock allowance */

typedef struct ping {
    double sent;  /* rt_wtime() at the sender */
    double first; /* sent of the burst's first message */
    int32_t idx;  /* 0: the single message; 1..BURST: the burst */
    int32_t pad;
    unsigned char body[PAYLOAD];
} ping;

static int me, np, h_ping, phase, model_on;
static int got, early;
static double worst; /* the smallest (delivery - due) seen */

static void on_ping(const rt_msg *m, void *arg) {
    (void)arg;
    const ping *p = m->data;
    double now = rt_wtime(), due;
    if (p->idx == 0)
        due = p->sent + LAT;
    else
        due = p->first + LAT + (double)p->idx * PAYLOAD / BW;
    if (!model_on) due = p->sent;
    if (now - due < worst) worst = now - due;
    if (now < due - SLACK) early++;
    got++;
}

static int work(void *ctx) {
    (void)ctx;
    if (phase != 0) return RT_WORK_IDLE;
    phase = 1;
    static ping p;
    memset(&p, 0, sizeof p);
    int to = (me + 1) % np;
    p.sent = rt_wtime();
    rt_rsr(to, h_ping, &p, sizeof p);
    p.first = rt_wtime();
    for (int i = 1; i <= BURST; i++) {
        p.idx = i;
        p.sent = rt_wtime();
        rt_rsr(to, h_ping, &p, sizeof p);
    }
    return RT_WORK_BUSY;
}

static void run_ring(int on) {
    model_on = on && np > 1; /* self-sends are never delayed */
    phase = 0;
    got = early = 0;
    worst = INFINITY;
    ck_assert_int_eq(rt_net_set(on ? LAT : 0, on ? BW : 0), RT_OK);
    double t0 = rt_wtime();
    rt_run(work, NULL);
    double dt = rt_wtime() - t0;
    int mine[2] = {got, early}, all[2];
    MPI_Allreduce(mine, all, 2, MPI_INT, MPI_SUM, rt_comm());
    ck_assert_int_eq(all[0], np * (BURST + 1)); /* every message, exactly once */
    ck_assert_msg(all[1] == 0, "%d message(s) delivered before their due time (worst %.6f s)",
                  all[1], worst);
    if (model_on) /* the whole run cannot be shorter than the burst's transfer */
        ck_assert(dt >= LAT + BURST * PAYLOAD / BW - SLACK);
    ck_assert_int_eq(rt_net_set(0, 0), RT_OK);
}

START_TEST(test_not_early) {
    run_ring(1);
}
END_TEST

START_TEST(test_off) {
    run_ring(0);
}
END_TEST

static int idle_work(void *ctx) {
    (void)ctx;
    return RT_WORK_IDLE;
}

START_TEST(test_comm_s) {
    rt_stats_reset();
    for (int i = 0; i < 20; i++) /* many termination rounds, no RSR */
        rt_run(idle_work, NULL);
    rt_stats st;
    rt_stats_local(&st);
    double mine[2] = {st.comm_s, st.comm_s}, all[2];
    MPI_Allreduce(mine, all, 2, MPI_DOUBLE, MPI_MAX, rt_comm());
    ck_assert_msg(all[0] == 0.0, "comm_s = %g after runs without an RSR", all[0]);
    rt_stats_reset();
    run_ring(0);
    rt_stats_local(&st);
    int pos = np == 1 || st.comm_s > 0, allpos = 0;
    MPI_Allreduce(&pos, &allpos, 1, MPI_INT, MPI_MIN, rt_comm());
    ck_assert_msg(allpos, "comm_s = 0 on a rank that received RSRs");
}
END_TEST

START_TEST(test_parse) {
    double l = -1, b = -1;
    ck_assert_int_eq(rt_net_parse("sp2", &l, &b), RT_OK);
    ck_assert(fabs(l - 29e-6) < 1e-12 && fabs(b - 33.6e6) < 1e-3);
    ck_assert_int_eq(rt_net_parse("100,2", &l, &b), RT_OK);
    ck_assert(fabs(l - 1e-4) < 1e-12 && fabs(b - 2e6) < 1e-6);
    ck_assert_int_eq(rt_net_parse("5", &l, &b), RT_OK);
    ck_assert(fabs(l - 5e-6) < 1e-12 && b == 0);
    ck_assert_int_eq(rt_net_parse("off", &l, &b), RT_OK);
    ck_assert(l == 0 && b == 0);
    const char *bad[] = {"", "x", "-1", "5,", "5,abc", "5,2x", "nan", "5,-3", "inf"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        l = b = 7;
        ck_assert_msg(rt_net_parse(bad[i], &l, &b) == RT_EINVAL, "'%s' accepted", bad[i]);
        ck_assert(l == 7 && b == 7);
    }
    ck_assert_int_eq(rt_net_set(-1, 0), RT_EINVAL);
    ck_assert_int_eq(rt_net_set(0, INFINITY), RT_EINVAL);
}
END_TEST

int main(int argc, char **argv) {
    if (rt_init(&argc, &argv, NULL) != RT_OK) return 2;
    me = rt_rank();
    np = rt_size();
    h_ping = rt_handler_register("net_ping", on_ping, NULL, RT_NONTHREADED, sizeof(ping));
    if (h_ping < 0) return 2;
    rt_start();
    int rc = ck_run_mpi(
        ck_suite("rt_net", 60, CK_TESTS(test_parse, test_not_early, test_off, test_comm_s)),
        rt_app_comm());
    rt_finalize();
    return rc;
}
