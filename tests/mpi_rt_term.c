// ranks: 1 2 4
/* mpi_rt_term.c - the blocking queue and the deadlock report of the runtime.
 *
 * Without arguments (what tests/run.sh runs) it is a normal run that must terminate: every
 * rank's local work spawns NTASK tasks, each of which labels itself and, ROUNDS times, issues
 * 1..3 requests and waits: a plain echo on a random rank, an echo by a threaded handler that
 * takes a millisecond (a worker busy while its requester is blocked), or a chain forwarded
 * over 1..3 ranks before the reply.  So ranks are often quiescent with tasks blocked while
 * replies are in flight or being made: the detector must pass the token there and must
 * neither declare a deadlock nor terminate early.  After rt_run every task must have
 * finished with the right sums, nothing may be blocked (rt_blocked_dump prints nothing), and
 * the blocking queue's statistics must add up: each round blocked its task exactly once,
 * blocked_max is at least 1, the sum over ranks reduces the maxima with max.  Errors are
 * reduced before asserting so no rank hangs.  Runs without perturbation and with two seeds.
 * With --deadlock=one (or --deadlock) the last rank's task also sends a request to a handler
 * that never replies; with --deadlock=every every rank has such a task.  The run must then
 * end, on every rank, with the deadlock report (a header line per rank, a dump line per
 * blocked task with its label "lonely request to rank N") and a fatal error, never hang and
 * never return from rt_run (exit status 3 if it does): tests/t_rt_deadlock.sh checks that.
 */
#include "check_run.h"
#include "rt.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { NTASK = 40, ROUNDS = 3, MAXREQ = 3 };

typedef struct dl_req {
    int64_t value;
    int32_t hops; /* forwards left before the reply (chain requests) */
    int32_t pad;
} dl_req;

typedef struct dl_task {
    int id, round;
    int64_t expect, sum;
    int lonely; /* deadlock mode: send the request that is never answered */
} dl_task;

static int me, np;
static int kinds = 3; /* request kinds in use: 3 = all (echo, slow, chain), 1 = chains only */
static int h_echo, h_slow, h_hop, h_ans, h_sink;
static int spawned, finished, errors, sunk;
static uint64_t rng;

static uint64_t next_rand(void) {
    uint64_t x = (rng += 0x9E3779B97F4A7C15ull);
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

static void echo_handler(const rt_msg *m, void *arg) {
    (void)arg;
    dl_req r;
    memcpy(&r, m->data, sizeof r);
    int64_t v = 3 * r.value + 1;
    rt_reply(m, h_ans, &v, sizeof v);
}

/* Threaded: keeps a worker busy for a millisecond before answering. */
static void slow_handler(const rt_msg *m, void *arg) {
    struct timespec ts = {0, 1000000};
    nanosleep(&ts, NULL);
    echo_handler(m, arg);
}

static void hop_handler(const rt_msg *m, void *arg) {
    dl_req r;
    memcpy(&r, m->data, sizeof r);
    if (r.hops == 0) {
        echo_handler(m, arg);
        return;
    }
    r.hops--;
    rt_forward(m, (rt_rank() + 1) % rt_size(), h_hop, &r, sizeof r);
}

static void ans_handler(const rt_msg *m, void *arg) {
    (void)arg;
    if (!m->task) {
        errors++;
        return;
    }
    int64_t v;
    memcpy(&v, m->data, sizeof v);
    dl_task *s = rt_task_data(m->task);
    s->sum += v;
}

/* Never replies: the requester stays blocked for good. */
static void sink_handler(const rt_msg *m, void *arg) {
    (void)m;
    (void)arg;
    sunk++;
}

static rt_task_status dl_task_fn(rt_task *t, void *state) {
    dl_task *s = state;
    if (s->round > 0 && s->sum != s->expect) errors++;
    if (s->round == ROUNDS || (s->lonely && s->round == 1)) {
        finished++;
        free(s);
        return RT_TASK_DONE;
    }
    s->round++;
    s->expect = s->sum = 0;
    int n = 1 + (int)(next_rand() % MAXREQ);
    rt_task_label(t, "task %d of rank %d, round %d, %d requests", s->id, me, s->round, n);
    for (int i = 0; i < n; i++) {
        int32_t hops = (int32_t)(1 + next_rand() % (kinds == 1 ? 16 : 3));
        dl_req r = {(int64_t)(next_rand() % 100000), hops, 0};
        int kind = kinds == 1 ? 2 : (int)(next_rand() % 3);
        int dest = (int)(next_rand() % (uint64_t)np);
        s->expect += 3 * r.value + 1;
        rt_request(t, dest, kind == 0 ? h_echo : kind == 1 ? h_slow : h_hop, &r, sizeof r);
    }
    if (s->lonely) {
        int dest = (me + 1) % np;
        dl_req r = {0, 0, 0};
        rt_task_label(t, "lonely request to rank %d", dest);
        rt_request(t, dest, h_sink, &r, sizeof r);
    }
    if (rt_task_pending(t) != n + (s->lonely ? 1 : 0)) errors++;
    return RT_TASK_WAIT;
}

static int ntask_here; /* tasks the local work spawns on this rank */
static int lonely_here;

static int local_work(void *ctx) {
    (void)ctx;
    /* chains: one task at a time, so ranks sit quiescent with a blocked task between hops */
    if (spawned < ntask_here && (kinds != 1 || finished == spawned)) {
        dl_task *s = calloc(1, sizeof *s);
        s->id = spawned;
        s->lonely = spawned == 0 && lonely_here;
        rt_task_spawn(dl_task_fn, s);
        spawned++;
    }
    return spawned < ntask_here && (kinds != 1 || finished == spawned) ? RT_WORK_BUSY
                                                                       : RT_WORK_IDLE;
}

static void run_waits(uint64_t seed, int kinds_) {
    kinds = kinds_;
    ck_assert_int_eq(rt_perturb_set(seed), RT_OK);
    spawned = finished = errors = sunk = 0;
    ntask_here = NTASK;
    lonely_here = 0;
    rng = seed * 7919u + (uint64_t)me + 1;
    rt_stats_reset();
    ck_assert_int_eq(rt_run(local_work, NULL), RT_OK);

    /* Checked at once: termination must not have come early. */
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    rt_blocked_dump(f);
    fclose(f);
    rt_stats st;
    rt_stats_local(&st);
    int bad = errors + (finished != NTASK) + (spawned != NTASK) + (len != 0) + (sunk != 0) +
              (st.blocked_count != (uint64_t)NTASK * ROUNDS) + (st.blocked_max < 1) +
              (st.blocked_max > NTASK) + !(st.blocked_time_sum > 0) +
              !(st.blocked_time_max <= st.blocked_time_sum) + (st.tasks_done != NTASK);
    if (len) fprintf(stderr, "rank %d: tasks still blocked:\n%s", me, text);
    free(text);

    rt_stats sum, max;
    rt_stats_reduce(&sum, &max);
    bad += (sum.blocked_count != (uint64_t)np * NTASK * ROUNDS) +
           (sum.blocked_max != max.blocked_max) + (max.blocked_max < st.blocked_max) +
           (sum.blocked_time_max != max.blocked_time_max) +
           !(sum.blocked_time_sum >= max.blocked_time_sum) +
           (sum.tasks_done != (uint64_t)np * NTASK);
    int glob = 0;
    MPI_Allreduce(&bad, &glob, 1, MPI_INT, MPI_SUM, rt_comm());
    if (me == 0)
        printf(
            "waits (%s) seed %llu on %d ranks: %llu blocks, at most %llu at once, longest %.6f s, "
            "total %.6f s, %llu waves, errors %d\n",
            kinds == 1 ? "chains" : "mixed", (unsigned long long)seed, np,
            (unsigned long long)sum.blocked_count, (unsigned long long)sum.blocked_max,
            sum.blocked_time_max, sum.blocked_time_sum, (unsigned long long)sum.waves, glob);
    ck_assert_int_eq(glob, 0);
}

START_TEST(test_waits_plain) {
    run_waits(0, 3);
}
END_TEST

START_TEST(test_waits_perturbed) {
    run_waits((uint64_t)_i + 5, 3);
}
END_TEST

/* Only chains of 1..16 non-threaded hops, one task at a time per rank: ranks are quiescent
 * with a blocked task while requests and replies travel, so the token goes round often. */
START_TEST(test_waits_chains) {
    run_waits((uint64_t)_i, 1);
}
END_TEST

/* Deadlock mode: a few ordinary tasks, and lonely tasks that can never finish. */
static int run_deadlock(int every) {
    spawned = finished = errors = sunk = 0;
    ntask_here = 4;
    lonely_here = every || me == np - 1;
    rng = (uint64_t)me + 1;
    rt_run(local_work, NULL);
    fprintf(stderr, "mpi_rt_term: rank %d: rt_run returned although a task is still blocked\n", me);
    return 3;
}

static void register_handlers(void) {
    h_echo = rt_handler_register("dl_echo", echo_handler, NULL, RT_NONTHREADED, sizeof(dl_req));
    h_slow = rt_handler_register("dl_slow", slow_handler, NULL, RT_THREADED, sizeof(dl_req));
    h_hop = rt_handler_register("dl_hop", hop_handler, NULL, RT_NONTHREADED, sizeof(dl_req));
    h_ans = rt_handler_register("dl_ans", ans_handler, NULL, RT_NONTHREADED, sizeof(int64_t));
    h_sink = rt_handler_register("dl_sink", sink_handler, NULL, RT_NONTHREADED, sizeof(dl_req));
}

int main(int argc, char **argv) {
    if (rt_init(&argc, &argv, NULL) != RT_OK) return 2;
    me = rt_rank();
    np = rt_size();
    register_handlers();
    if (h_sink < 0) return 2;
    rt_start();
    if (argc > 1) {
        if (!strcmp(argv[1], "--deadlock") || !strcmp(argv[1], "--deadlock=one"))
            return run_deadlock(0);
        if (!strcmp(argv[1], "--deadlock=every")) return run_deadlock(1);
        fprintf(stderr, "usage: mpi_rt_term [--deadlock[=one|every]]\n");
        return 2;
    }
    Suite *s = suite_create("rt_term");
    TCase *tc = ck_case(s, "waits", 120, CK_TESTS(test_waits_plain));
    tcase_add_loop_test(tc, test_waits_perturbed, 0, 2);
    tcase_add_loop_test(tc, test_waits_chains, 0, 2);
    int rc = ck_run_mpi(s, rt_app_comm());
    rt_finalize();
    return rc;
}
