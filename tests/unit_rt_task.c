/* unit_rt_task.c - task state machine of rt_task.c without MPI: new -> ready -> running ->
 * blocked -> ready -> running -> done, FIFO order of the ready queue, reply tokens; the
 * blocking queue (a list in order of blocking, O(1) removal from anywhere in it, what each
 * task waits for: pending count, last request, label, time), its dump (rt_tasks_dump and
 * rt_blocked_dump) and statistics (rt_stats_local, rt_stats_reset), and the one-rank
 * termination ring telling termination from deadlock (rt_term_pass); rt_cpus against the
 * process's affinity mask. */
#define _GNU_SOURCE /* sched_setaffinity */
#include "check_run.h"
#include "rt_internal.h"

#include <sched.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct ts_state {
    int runs;
    int want; /* replies to wait for on the first run */
    rt_task_state seen[4];
    rt_task *self;
    int *order, *norder, id;
    rt_token tok[4];
} ts_state;

static rt_task_status waiter(rt_task *t, void *p) {
    ts_state *s = p;
    s->seen[s->runs] = t->st;
    s->runs++;
    if (s->order) s->order[(*s->norder)++] = s->id;
    if (s->runs == 1 && s->want > 0) {
        for (int i = 0; i < s->want; i++)
            s->tok[i] = rt_task_take_token(t, 0, 1, 2);
        return RT_TASK_WAIT;
    }
    return RT_TASK_DONE;
}

START_TEST(test_state_transitions) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    ts_state s = {.want = 3};
    rt_task *t = rt_tasks_spawn(&ts, waiter, &s);
    ck_assert_int_eq(t->st, RT_TS_READY);
    ck_assert_uint_eq(ts.nlive, 1);
    ck_assert_uint_eq(rt_tasks_run(&ts, 10), 1);
    ck_assert_int_eq(s.seen[0], RT_TS_RUNNING);
    ck_assert_int_eq(t->st, RT_TS_BLOCKED);
    ck_assert_int_eq(t->pending, 3);
    ck_assert_uint_eq(ts.nblocked, 1);
    ck_assert(rt_queue_empty(&ts.ready));
    ck_assert_uint_eq(rt_tasks_run(&ts, 10), 0); /* a blocked task is not run */
    for (int i = 0; i < 3; i++) {
        rt_task *u = rt_tasks_lookup(&ts, s.tok[i]);
        ck_assert_ptr_eq(u, t);
        rt_tasks_reply(&ts, u);
        ck_assert_int_eq(t->st, i < 2 ? RT_TS_BLOCKED : RT_TS_READY);
    }
    ck_assert_uint_eq(ts.nblocked, 0);
    ck_assert_uint_eq(rt_tasks_run(&ts, 10), 1);
    ck_assert_int_eq(s.runs, 2);
    ck_assert_int_eq(t->st, RT_TS_FREE);
    ck_assert_uint_eq(ts.nlive, 0);
    ck_assert_uint_eq(ts.done, 1);
    /* the finished task's tokens are stale now */
    ck_assert_ptr_null(rt_tasks_lookup(&ts, s.tok[0]));
    rt_tasks_destroy(&ts);
}
END_TEST

START_TEST(test_fifo_and_reuse) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    int order[16], n = 0;
    ts_state s[4] = {{0}};
    for (int i = 0; i < 4; i++) {
        s[i].order = order;
        s[i].norder = &n;
        s[i].id = i;
        s[i].want = i == 1 ? 1 : 0;
        rt_tasks_spawn(&ts, waiter, &s[i]);
    }
    ck_assert_uint_eq(rt_tasks_run(&ts, 2), 2); /* max is respected */
    ck_assert_uint_eq(rt_tasks_run(&ts, 100), 2);
    ck_assert_int_eq(n, 4);
    for (int i = 0; i < 4; i++)
        ck_assert_int_eq(order[i], i);
    rt_task *t1 = rt_tasks_lookup(&ts, s[1].tok[0]);
    ck_assert_ptr_nonnull(t1);
    uint32_t gen = t1->gen;
    rt_tasks_reply(&ts, t1);
    ck_assert_uint_eq(rt_tasks_run(&ts, 100), 1);
    ck_assert_int_eq(order[4], 1);
    /* slots are reused with a new generation */
    ts_state s5 = {0};
    rt_task *t5 = rt_tasks_spawn(&ts, waiter, &s5);
    ck_assert_uint_lt(t5->slot, 4);
    ck_assert_uint_eq(ts.nslot, 4);
    if (t5 == t1) ck_assert_uint_ne(t5->gen, gen);
    ck_assert_uint_eq(rt_tasks_run(&ts, 100), 1);
    ck_assert_uint_eq(ts.done, 5);
    rt_tasks_destroy(&ts);
}
END_TEST

static rt_task_status yielder(rt_task *t, void *p) {
    int *n = p;
    (void)t;
    return ++*n < 3 ? RT_TASK_YIELD : RT_TASK_DONE;
}

static rt_task_status wait_nothing(rt_task *t, void *p) {
    int *n = p;
    (void)t;
    return ++*n < 2 ? RT_TASK_WAIT : RT_TASK_DONE;
}

START_TEST(test_yield_and_empty_wait) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    int a = 0, b = 0;
    rt_tasks_spawn(&ts, yielder, &a);
    rt_tasks_spawn(&ts, wait_nothing, &b);
    size_t total = 0, r;
    while ((r = rt_tasks_run(&ts, 1)) > 0)
        total += r;
    ck_assert_uint_eq(total, 5);
    ck_assert_int_eq(a, 3);
    ck_assert_int_eq(b, 2);
    ck_assert_uint_eq(ts.nblocked, 0);
    ck_assert_uint_eq(ts.nlive, 0);
    rt_tasks_destroy(&ts);
}
END_TEST

START_TEST(test_bad_tokens) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    rt_token bad = {0, 99, 0};
    ck_assert_ptr_null(rt_tasks_lookup(&ts, bad));
    ts_state s = {.want = 1};
    rt_tasks_spawn(&ts, waiter, &s);
    rt_tasks_run(&ts, 1);
    rt_token wrong_gen = s.tok[0];
    wrong_gen.gen++;
    ck_assert_ptr_null(rt_tasks_lookup(&ts, wrong_gen));
    ck_assert_ptr_nonnull(rt_tasks_lookup(&ts, s.tok[0]));
    rt_tasks_destroy(&ts);
}
END_TEST

static rt_task_status done_with_pending(rt_task *t, void *p) {
    (void)p;
    rt_task_take_token(t, 0, 0, 0);
    return RT_TASK_DONE;
}

START_TEST(test_done_with_pending_aborts) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    rt_tasks_spawn(&ts, done_with_pending, NULL);
    rt_tasks_run(&ts, 1);
}
END_TEST

/* ---- the blocking queue ---------------------------------------------------------------- */

/* A task that labels itself and issues nreq requests (to rank 10 + i, handler i) on its
 * first run, then finishes. */
typedef struct bq_state {
    int nreq, runs;
    const char *label;
    rt_token tok[4];
} bq_state;

static rt_task_status bq_task(rt_task *t, void *p) {
    bq_state *s = p;
    if (s->runs++ > 0) return RT_TASK_DONE;
    if (s->label) rt_task_label(t, "%s #%d", s->label, s->nreq);
    for (int i = 0; i < s->nreq; i++)
        s->tok[i] = rt_task_take_token(t, 0, 10 + i, i);
    return RT_TASK_WAIT;
}

/* The blocking queue from head to tail, checked against the back links; returns its length. */
static size_t bq_walk(const rt_tasks *ts, const rt_task **out, size_t cap) {
    size_t n = 0;
    const rt_task *prev = NULL;
    for (const rt_task *t = ts->bhead; t; prev = t, t = t->bnext) {
        ck_assert_ptr_eq(t->bprev, prev);
        ck_assert_int_eq(t->st, RT_TS_BLOCKED);
        ck_assert_int_gt(t->pending, 0);
        if (n < cap) out[n] = t;
        n++;
    }
    ck_assert_ptr_eq(ts->btail, prev);
    ck_assert_uint_eq(n, ts->nblocked);
    return n;
}

static void spin_for(double seconds) {
    double until = rt_now() + seconds;
    while (rt_now() < until) {
    }
}

START_TEST(test_blocked_list) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    bq_state a = {.nreq = 2, .label = "alpha"}, b = {.nreq = 1, .label = "beta"},
             c = {.nreq = 3, .label = NULL};
    rt_task *ta = rt_tasks_spawn(&ts, bq_task, &a);
    rt_task *tb = rt_tasks_spawn(&ts, bq_task, &b);
    rt_task *tc = rt_tasks_spawn(&ts, bq_task, &c);
    ck_assert_str_eq(ta->label, ""); /* a new task has no label */
    ck_assert_int_eq(ta->last_dest, -1);
    ck_assert_int_eq(ta->last_handler, -1);
    ck_assert_ptr_null(ts.bhead);
    ck_assert_uint_eq(rt_tasks_run(&ts, 10), 3);
    const rt_task *l[4];
    ck_assert_uint_eq(bq_walk(&ts, l, 4), 3);
    ck_assert_ptr_eq(l[0], ta); /* in order of blocking */
    ck_assert_ptr_eq(l[1], tb);
    ck_assert_ptr_eq(l[2], tc);
    ck_assert_int_eq(ta->pending, 2);
    ck_assert_int_eq(tb->pending, 1);
    ck_assert_int_eq(tc->pending, 3);
    ck_assert_str_eq(ta->label, "alpha #2");
    ck_assert_str_eq(tb->label, "beta #1");
    ck_assert_str_eq(tc->label, "");
    ck_assert_int_eq(ta->last_dest, 11); /* the most recent request */
    ck_assert_int_eq(ta->last_handler, 1);
    ck_assert_int_eq(tc->last_dest, 12);
    ck_assert_int_eq(tc->last_handler, 2);
    ck_assert_uint_eq(ts.blocked_count, 3);
    ck_assert_uint_eq(ts.blocked_max, 3);
    ck_assert(rt_queue_empty(&ts.ready));

    /* the middle one leaves first: its single reply brings pending to 0 */
    rt_tasks_reply(&ts, rt_tasks_lookup(&ts, b.tok[0]));
    ck_assert_int_eq(tb->st, RT_TS_READY);
    ck_assert_ptr_null(tb->bnext);
    ck_assert_ptr_null(tb->bprev);
    ck_assert_uint_eq(bq_walk(&ts, l, 4), 2);
    ck_assert_ptr_eq(l[0], ta);
    ck_assert_ptr_eq(l[1], tc);
    /* a reply that leaves replies pending keeps the task where it is */
    rt_tasks_reply(&ts, rt_tasks_lookup(&ts, c.tok[1]));
    ck_assert_int_eq(tc->pending, 2);
    ck_assert_uint_eq(bq_walk(&ts, l, 4), 2);
    /* the tail, then the head */
    rt_tasks_reply(&ts, rt_tasks_lookup(&ts, c.tok[0]));
    rt_tasks_reply(&ts, rt_tasks_lookup(&ts, c.tok[2]));
    ck_assert_uint_eq(bq_walk(&ts, l, 4), 1);
    ck_assert_ptr_eq(ts.bhead, ta);
    ck_assert_ptr_eq(ts.btail, ta);
    rt_tasks_reply(&ts, rt_tasks_lookup(&ts, a.tok[0]));
    rt_tasks_reply(&ts, rt_tasks_lookup(&ts, a.tok[1]));
    ck_assert_uint_eq(bq_walk(&ts, l, 4), 0);
    ck_assert_ptr_null(ts.bhead);
    ck_assert_ptr_null(ts.btail);
    /* woken in the order their last replies came */
    ck_assert_uint_eq(ts.ready.n, 3);
    ck_assert_ptr_eq(RT_CONTAINER(ts.ready.head, rt_task, q), tb);
    ck_assert_uint_eq(rt_tasks_run(&ts, 10), 3);
    ck_assert_uint_eq(ts.nlive, 0);
    ck_assert_uint_eq(ts.blocked_count, 3);
    ck_assert_uint_eq(ts.blocked_max, 3);
    ck_assert(ts.blocked_time_sum >= ts.blocked_time_max && ts.blocked_time_max >= 0);

    /* a reused slot starts without the old label and request */
    bq_state d = {.nreq = 0};
    rt_task *td = rt_tasks_spawn(&ts, bq_task, &d);
    ck_assert_str_eq(td->label, "");
    ck_assert_int_eq(td->last_dest, -1);
    rt_tasks_destroy(&ts);
}
END_TEST

START_TEST(test_label_truncated) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    bq_state s = {.nreq = 1};
    rt_task *t = rt_tasks_spawn(&ts, bq_task, &s);
    char longer[200];
    memset(longer, 'x', sizeof longer - 1);
    longer[sizeof longer - 1] = '\0';
    rt_task_label(t, "cavity %d at rank %d: %s", 17, 3, longer);
    ck_assert_uint_eq(strlen(t->label), RT_LABEL_MAX - 1);
    ck_assert(strncmp(t->label, "cavity 17 at rank 3: xxx", 24) == 0);
    rt_task_label(t, "short");
    ck_assert_str_eq(t->label, "short");
    rt_tasks_destroy(&ts);
}
END_TEST

static rt_task_status quick(rt_task *t, void *p) {
    (void)t;
    (void)p;
    return RT_TASK_DONE;
}

START_TEST(test_label_finished_task_aborts) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    rt_task *t = rt_tasks_spawn(&ts, quick, NULL);
    rt_tasks_run(&ts, 1);
    rt_task_label(t, "too late");
}
END_TEST

/* Reads back what a dump wrote. */
typedef struct membuf {
    char *text;
    size_t len;
    FILE *f;
} membuf;

static void membuf_open(membuf *m) {
    m->text = NULL;
    m->len = 0;
    m->f = open_memstream(&m->text, &m->len);
    ck_assert_ptr_nonnull(m->f);
}

static void membuf_close(membuf *m) {
    fclose(m->f);
}

static int count_lines(const char *s) {
    int n = 0;
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

static void noop_handler(const rt_msg *m, void *arg) {
    (void)m;
    (void)arg;
}

START_TEST(test_dump) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    rt_htable ht;
    rt_htable_init(&ht);
    ck_assert_int_eq(rt_htable_add(&ht, "h_zero", noop_handler, NULL, RT_NONTHREADED, 8), 0);
    ck_assert_int_eq(rt_htable_add(&ht, "h_one", noop_handler, NULL, RT_NONTHREADED, 8), 1);
    bq_state a = {.nreq = 2, .label = "waits for the sink"}, b = {.nreq = 1};
    rt_tasks_spawn(&ts, bq_task, &a);
    rt_tasks_spawn(&ts, bq_task, &b);
    rt_tasks_run(&ts, 10);
    spin_for(0.002);
    membuf m;
    membuf_open(&m);
    rt_tasks_dump(&ts, 5, &ht, rt_now(), m.f);
    membuf_close(&m);
    ck_assert_int_eq(count_lines(m.text), 2);
    ck_assert_ptr_nonnull(strstr(m.text, "rt: rank 5: blocked task slot 0 (gen 0): 2 pending, last "
                                         "request to rank 11 handler 1 'h_one', label \"waits for "
                                         "the sink #2\", blocked "));
    ck_assert_ptr_nonnull(strstr(m.text, "rt: rank 5: blocked task slot 1 (gen 0): 1 pending, last "
                                         "request to rank 10 handler 0 'h_zero', label \"\""));
    ck_assert(strstr(m.text, "slot 0") < strstr(m.text, "slot 1")); /* oldest first */
    double secs = atof(strstr(m.text, "blocked 0") + strlen("blocked "));
    ck_assert(secs >= 0.002 && secs < 60);
    free(m.text);

    /* without a handler table, or a handler id it does not know: '-' */
    membuf_open(&m);
    rt_tasks_dump(&ts, 5, NULL, rt_now(), m.f);
    membuf_close(&m);
    ck_assert_ptr_nonnull(strstr(m.text, "handler 1 '-'"));
    free(m.text);

    /* a task whose pending count reaches 0 is no longer listed */
    rt_tasks_reply(&ts, rt_tasks_lookup(&ts, a.tok[0]));
    rt_tasks_reply(&ts, rt_tasks_lookup(&ts, a.tok[1]));
    membuf_open(&m);
    rt_tasks_dump(&ts, 5, &ht, rt_now(), m.f);
    membuf_close(&m);
    ck_assert_int_eq(count_lines(m.text), 1);
    ck_assert_ptr_null(strstr(m.text, "slot 0"));
    free(m.text);
    rt_tasks_reply(&ts, rt_tasks_lookup(&ts, b.tok[0]));
    membuf_open(&m);
    rt_tasks_dump(&ts, 5, &ht, rt_now(), m.f);
    membuf_close(&m);
    ck_assert_uint_eq(m.len, 0); /* nothing blocked: nothing printed */
    free(m.text);
    rt_tasks_destroy(&ts);
}
END_TEST

/* The public face on this rank's state (rt_g, never initialised here: rank 0, no MPI). */
START_TEST(test_public_dump_and_stats) {
    rt_tasks_init(&rt_g.tasks);
    rt_stats_reset();
    bq_state a = {.nreq = 1, .label = "first"}, b = {.nreq = 2, .label = "second"};
    rt_tasks_spawn(&rt_g.tasks, bq_task, &a);
    rt_tasks_spawn(&rt_g.tasks, bq_task, &b);
    rt_tasks_run(&rt_g.tasks, 10);
    membuf m;
    membuf_open(&m);
    rt_blocked_dump(m.f);
    membuf_close(&m);
    ck_assert_int_eq(count_lines(m.text), 2);
    ck_assert_ptr_nonnull(strstr(m.text, "rt: rank 0: blocked task slot 0 (gen 0): 1 pending"));
    ck_assert_ptr_nonnull(strstr(m.text, "label \"second #2\""));
    free(m.text);

    rt_stats st;
    rt_stats_local(&st);
    ck_assert_uint_eq(st.blocked_count, 2);
    ck_assert_uint_eq(st.blocked_max, 2);
    ck_assert(st.blocked_time_sum == 0 && st.blocked_time_max == 0); /* nobody woke yet */

    spin_for(0.003);
    rt_tasks_reply(&rt_g.tasks, rt_tasks_lookup(&rt_g.tasks, a.tok[0])); /* a: >= 3 ms */
    rt_tasks_run(&rt_g.tasks, 10);                                       /* a finishes */
    rt_tasks_reply(&rt_g.tasks, rt_tasks_lookup(&rt_g.tasks, b.tok[0]));
    rt_stats_local(&st);
    ck_assert(st.blocked_time_max >= 0.003 && st.blocked_time_max < 60);
    ck_assert(st.blocked_time_sum >= st.blocked_time_max);
    ck_assert_uint_eq(st.blocked_max, 2);
    ck_assert_uint_eq(st.tasks_done, 1);

    /* a reset keeps the current length as the new maximum */
    rt_stats_reset();
    rt_stats_local(&st);
    ck_assert_uint_eq(st.blocked_count, 0);
    ck_assert_uint_eq(st.blocked_max, 1);
    ck_assert(st.blocked_time_sum == 0 && st.blocked_time_max == 0);
    rt_tasks_reply(&rt_g.tasks, rt_tasks_lookup(&rt_g.tasks, b.tok[1]));
    rt_tasks_run(&rt_g.tasks, 10);
    rt_stats_local(&st);
    ck_assert_uint_eq(st.blocked_max, 1);
    ck_assert(st.blocked_time_max >= 0.003); /* b was blocked since before the reset */
    ck_assert_uint_eq(rt_g.tasks.nlive, 0);
    rt_tasks_destroy(&rt_g.tasks);
}
END_TEST

/* One rank: a quiet, balanced round ends in termination when no task is blocked and in a
 * deadlock verdict when some are (the count travels with it); an RSR still in flight or
 * activity during the round decides nothing, blocked tasks or not. */
START_TEST(test_term_deadlock_one_rank) {
    rt_term t;
    rt_term_init(&t, 0);
    ck_assert_int_eq(rt_term_pass(&t, 0, 1, 4, 4, 2, true), RT_TERM_GOING); /* opens a round */
    ck_assert_int_eq(rt_term_pass(&t, 0, 1, 5, 4, 2, true), RT_TERM_GOING); /* in flight */
    t.active = true;
    ck_assert_int_eq(rt_term_pass(&t, 0, 1, 5, 5, 2, true), RT_TERM_GOING); /* activity */
    ck_assert(!t.deadlock);
    ck_assert_int_eq(rt_term_pass(&t, 0, 1, 5, 5, 2, false), RT_TERM_DEADLOCK);
    ck_assert(t.deadlock);
    ck_assert_int_eq(t.deadlock_blocked, 2);

    rt_term_init(&t, 0);
    ck_assert_int_eq(rt_term_pass(&t, 0, 1, 4, 4, 0, true), RT_TERM_GOING);
    ck_assert_int_eq(rt_term_pass(&t, 0, 1, 4, 4, 0, false), RT_TERM_DONE);
    ck_assert(!t.deadlock);
}
END_TEST

/* rt_cpus: the CPUs this process may run on, 1 to the CPUs online; pinned to one CPU, 1. */
START_TEST(test_cpus) {
    long online = sysconf(_SC_NPROCESSORS_ONLN);
    int n = rt_cpus();
    ck_assert_int_ge(n, 1);
    ck_assert_int_le(n, online > 0 ? online : 1);
#ifdef __linux__
    cpu_set_t all, one;
    ck_assert_int_eq(sched_getaffinity(0, sizeof all, &all), 0);
    int first = 0;
    while (!CPU_ISSET(first, &all))
        first++;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    ck_assert_int_eq(sched_setaffinity(0, sizeof one, &one), 0);
    int pinned = rt_cpus();
    ck_assert_int_eq(sched_setaffinity(0, sizeof all, &all), 0);
    ck_assert_int_eq(pinned, 1);
    ck_assert_int_eq(rt_cpus(), n);
#endif
}
END_TEST

int main(void) {
    Suite *s = suite_create("rt_task");
    TCase *tc =
        ck_case(s, "rt_task", 0,
                CK_TESTS(test_state_transitions, test_fifo_and_reuse, test_yield_and_empty_wait,
                         test_bad_tokens, test_blocked_list, test_label_truncated, test_dump,
                         test_public_dump_and_stats, test_term_deadlock_one_rank, test_cpus));
    tcase_add_test_raise_signal(tc, test_done_with_pending_aborts, SIGABRT);
    tcase_add_test_raise_signal(tc, test_label_finished_task_aborts, SIGABRT);
    return ck_run(s);
}
