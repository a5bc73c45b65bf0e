// ranks: 1 2 4 8
/* mpi_rt.c - a storm of RSRs through the runtime, checked for exactly-once delivery.
 *
 * Every rank's local work issues NSEQ chains: a chain starts at its origin, visits 0..3
 * random ranks (A -> B -> C -> A), each hop handled by a threaded or non-threaded handler
 * chosen at random, carries a variable-length tail (sometimes larger than an aggregation
 * buffer) whose bytes are checked at every hop, and ends back at the origin.  Every rank
 * also spawns NTASK tasks that twice issue 1..4 requests (some forwarded before the reply)
 * and wait for all replies, checking their sum.  After rt_run returns, each origin checks
 * at once that every chain came home exactly once and every task finished (so termination
 * was not declared early); the per-(origin, seq) hop counts are then summed over all ranks
 * and compared with the plan.  Errors are reduced before asserting so no rank hangs.  The
 * storm runs without perturbation and with three seeds, with aggregation on.
 * With RT_TEST_MISMATCH=1 the last rank registers a differently named handler: rt_start must
 * then fail on every rank (tests/t_rt_mismatch.sh).
 */
#include "check_run.h"
#include "rt.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

enum { NSEQ = 1500, NTASK = 150, MAXHOPS = 3, MAXTAIL = 24000, PER_CALL = 8 };

typedef struct chain_msg {
    int32_t origin;
    uint32_t seq;
    int32_t hops_left;
    uint32_t tail_len; /* pattern bytes following the struct */
} chain_msg;

typedef struct req_msg {
    int64_t value;
    int32_t fwd; /* forwards left before replying */
    int32_t threaded;
} req_msg;

typedef struct rep_msg {
    int64_t value;
} rep_msg;

typedef struct task_state {
    int phase;
    int64_t expect, sum;
} task_state;

static int me, np;
static int h_chain_nt, h_chain_t, h_req_nt, h_req_t, h_rep;
static atomic_int *handled;  /* [np * NSEQ]: hops of (origin, seq) handled on this rank */
static atomic_int *returned; /* [NSEQ]: this rank's chains that came home */
static int *planned;         /* [NSEQ]: hops planned for this rank's chains */
static atomic_int errors;
static int issued, spawned, tasks_done;
static uint64_t rng;

static uint64_t mix(uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdull;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ull;
    x ^= x >> 33;
    return x;
}

static uint64_t next_rand(void) {
    rng = mix(rng + 0x9E3779B97F4A7C15ull);
    return rng;
}

static unsigned char pattern(int origin, uint32_t seq, uint32_t i) {
    return (unsigned char)((uint32_t)origin * 31u + seq * 7u + i);
}

/* Sends one hop of a chain, building the tail afresh (also from worker threads). */
static void send_chain(int dest, const chain_msg *c, int threaded) {
    size_t n = sizeof *c + c->tail_len;
    unsigned char *buf = malloc(n);
    memcpy(buf, c, sizeof *c);
    for (uint32_t i = 0; i < c->tail_len; i++)
        buf[sizeof *c + i] = pattern(c->origin, c->seq, i);
    rt_rsr(dest, threaded ? h_chain_t : h_chain_nt, buf, (uint32_t)n);
    free(buf);
}

static void chain_handler(const rt_msg *m, void *arg) {
    (void)arg;
    chain_msg c;
    if (m->len < sizeof c) {
        atomic_fetch_add(&errors, 1);
        return;
    }
    memcpy(&c, m->data, sizeof c);
    const unsigned char *tail = (const unsigned char *)m->data + sizeof c;
    if (c.origin < 0 || c.origin >= np || c.seq >= NSEQ || m->len != sizeof c + c.tail_len) {
        atomic_fetch_add(&errors, 1);
        return;
    }
    for (uint32_t i = 0; i < c.tail_len; i++)
        if (tail[i] != pattern(c.origin, c.seq, i)) {
            atomic_fetch_add(&errors, 1);
            break;
        }
    atomic_fetch_add(&handled[(size_t)c.origin * NSEQ + c.seq], 1);
    if (c.hops_left == 0) {
        if (c.origin != me)
            atomic_fetch_add(&errors, 1);
        else
            atomic_fetch_add(&returned[c.seq], 1);
        return;
    }
    uint64_t h = mix(((uint64_t)c.origin << 40) ^ ((uint64_t)c.seq << 8) ^ (uint64_t)c.hops_left);
    c.hops_left--;
    int dest = c.hops_left == 0 ? c.origin : (int)(h % (uint64_t)np);
    send_chain(dest, &c, (int)((h >> 20) & 1));
}

static void req_handler(const rt_msg *m, void *arg) {
    (void)arg;
    req_msg r;
    memcpy(&r, m->data, sizeof r);
    if (m->token.rank < 0) atomic_fetch_add(&errors, 1);
    if (r.fwd > 0) {
        r.fwd--;
        uint64_t h = mix((uint64_t)r.value * 977u + (uint64_t)r.fwd);
        r.threaded = (int)(h & 1);
        rt_forward(m, (int)((h >> 8) % (uint64_t)np), r.threaded ? h_req_t : h_req_nt, &r,
                   sizeof r);
        return;
    }
    rep_msg p = {2 * r.value + 1};
    rt_reply(m, h_rep, &p, sizeof p);
}

static void rep_handler(const rt_msg *m, void *arg) {
    (void)arg;
    if (!m->task) {
        atomic_fetch_add(&errors, 1);
        return;
    }
    rep_msg p;
    memcpy(&p, m->data, sizeof p);
    task_state *s = rt_task_data(m->task);
    s->sum += p.value;
}

static void issue_requests(rt_task *t, task_state *s) {
    int n = 1 + (int)(next_rand() % 4);
    s->expect = s->sum = 0;
    for (int i = 0; i < n; i++) {
        req_msg r = {(int64_t)(next_rand() % 1000000), (int32_t)(next_rand() % 3),
                     (int32_t)(next_rand() & 1)};
        s->expect += 2 * r.value + 1;
        rt_request(t, (int)(next_rand() % (uint64_t)np), r.threaded ? h_req_t : h_req_nt, &r,
                   sizeof r);
    }
    if (rt_task_pending(t) != n) atomic_fetch_add(&errors, 1);
}

static rt_task_status task_fn(rt_task *t, void *state) {
    task_state *s = state;
    if (s->phase > 0 && s->sum != s->expect) atomic_fetch_add(&errors, 1);
    if (s->phase == 2) {
        tasks_done++;
        free(s);
        return RT_TASK_DONE;
    }
    s->phase++;
    issue_requests(t, s);
    return RT_TASK_WAIT;
}

static int local_work(void *ctx) {
    (void)ctx;
    for (int k = 0; k < PER_CALL && issued < NSEQ; k++, issued++) {
        uint64_t r = next_rand();
        int hops = (int)(r % (MAXHOPS + 1));
        chain_msg c = {me, (uint32_t)issued, hops, 0};
        c.tail_len =
            (r >> 8) % 50 == 0 ? 20000u + (uint32_t)((r >> 16) % 4000) : (uint32_t)((r >> 16) % 64);
        planned[issued] = hops + 1;
        int dest = hops == 0 ? me : (int)((r >> 32) % (uint64_t)np);
        send_chain(dest, &c, (int)((r >> 40) & 1));
    }
    if (spawned < NTASK && (next_rand() & 1)) {
        task_state *s = calloc(1, sizeof *s);
        rt_task_spawn(task_fn, s);
        spawned++;
    }
    return issued < NSEQ || spawned < NTASK ? RT_WORK_BUSY : RT_WORK_IDLE;
}

static void run_storm(uint64_t seed) {
    const char *env = getenv("RT_PERTURB"); /* t_rt_env.sh: perturb the plain run too */
    if (seed == 0 && env && *env) seed = strtoull(env, NULL, 0);
    ck_assert_int_eq(rt_perturb_set(seed), RT_OK);
    for (size_t i = 0; i < (size_t)np * NSEQ; i++)
        atomic_store(&handled[i], 0);
    for (int i = 0; i < NSEQ; i++) {
        atomic_store(&returned[i], 0);
        planned[i] = 0;
    }
    atomic_store(&errors, 0);
    issued = spawned = tasks_done = 0;
    rng = mix(seed * 1315423911u + (uint64_t)me + 1);
    rt_stats_reset();

    double t0 = rt_wtime();
    ck_assert_int_eq(rt_run(local_work, NULL), RT_OK);
    double dt = rt_wtime() - t0;

    /* Checked the moment termination is declared, before any further communication. */
    int bad_return = 0;
    for (int i = 0; i < NSEQ; i++)
        bad_return += atomic_load(&returned[i]) != 1;
    int bad_tasks = (tasks_done != NTASK) + (spawned != NTASK) + (issued != NSEQ);

    int *mine = malloc(sizeof *mine * (size_t)np * NSEQ);
    int *total = malloc(sizeof *total * (size_t)np * NSEQ);
    for (size_t i = 0; i < (size_t)np * NSEQ; i++)
        mine[i] = atomic_load(&handled[i]);
    MPI_Allreduce(mine, total, np * NSEQ, MPI_INT, MPI_SUM, rt_comm());
    int bad_hops = 0;
    for (int i = 0; i < NSEQ; i++)
        bad_hops += total[(size_t)me * NSEQ + i] != planned[i];
    free(mine);
    free(total);

    int local[4] = {atomic_load(&errors), bad_return, bad_tasks, bad_hops}, glob[4];
    MPI_Allreduce(local, glob, 4, MPI_INT, MPI_SUM, rt_comm());
    rt_stats s1, sum;
    rt_stats_local(&s1);
    rt_stats_reduce(&sum, NULL);
    if (me == 0)
        printf("storm seed %llu on %d ranks: %.3f s, %llu RSRs in %llu MPI messages, "
               "%llu waves, errors %d returns %d tasks %d hops %d\n",
               (unsigned long long)seed, np, dt, (unsigned long long)sum.rsr_sent,
               (unsigned long long)sum.mpi_sent, (unsigned long long)sum.waves, glob[0], glob[1],
               glob[2], glob[3]);
    ck_assert_int_eq(glob[0], 0);
    ck_assert_int_eq(glob[1], 0);
    ck_assert_int_eq(glob[2], 0);
    ck_assert_int_eq(glob[3], 0);
    ck_assert_uint_eq(sum.rsr_sent, sum.rsr_recv);
    ck_assert_uint_eq(s1.tasks_done, NTASK);
}

START_TEST(test_storm_plain) {
    run_storm(0);
}
END_TEST

START_TEST(test_storm_perturbed) {
    run_storm((uint64_t)_i + 1);
}
END_TEST

START_TEST(test_storm_stats_table) {
    rt_stats_print(stdout);
    rt_handler_stats hs;
    ck_assert_int_eq(rt_stats_handler(h_rep, &hs), RT_OK);
    ck_assert_str_eq(hs.name, "storm_rep");
    ck_assert_int_eq(rt_stats_handler(RT_MAX_HANDLERS, &hs), RT_EINVAL);
}
END_TEST

int main(int argc, char **argv) {
    if (rt_init(&argc, &argv, NULL) != RT_OK) return 2;
    me = rt_rank();
    np = rt_size();
    const char *mm = getenv("RT_TEST_MISMATCH");
    int mismatch = mm && *mm == '1' && me == np - 1;
    h_chain_nt = rt_handler_register("storm_chain_nt", chain_handler, NULL, RT_VARSIZE,
                                     sizeof(chain_msg) + MAXTAIL);
    h_chain_t = rt_handler_register(mismatch ? "storm_chain_X" : "storm_chain_t", chain_handler,
                                    NULL, RT_THREADED | RT_VARSIZE, sizeof(chain_msg) + MAXTAIL);
    h_req_nt =
        rt_handler_register("storm_req_nt", req_handler, NULL, RT_NONTHREADED, sizeof(req_msg));
    h_req_t = rt_handler_register("storm_req_t", req_handler, NULL, RT_THREADED, sizeof(req_msg));
    h_rep = rt_handler_register("storm_rep", rep_handler, NULL, RT_NONTHREADED, sizeof(rep_msg));
    if (h_rep < 0) return 2;
    rt_start();

    handled = calloc((size_t)np * NSEQ, sizeof *handled);
    returned = calloc(NSEQ, sizeof *returned);
    planned = calloc(NSEQ, sizeof *planned);

    Suite *s = suite_create("rt");
    TCase *tc = ck_case(s, "storm", 0, CK_TESTS(test_storm_plain));
    tcase_add_loop_test(tc, test_storm_perturbed, 0, 3);
    tcase_add_test(tc, test_storm_stats_table);
    int rc = ck_run_mpi(s, rt_app_comm());
    free(handled);
    free(returned);
    free(planned);
    rt_finalize();
    return rc;
}
