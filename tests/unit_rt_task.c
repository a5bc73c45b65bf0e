/* unit_rt_task.c - task state machine of rt_task.c without MPI: new -> ready -> running ->
 * blocked -> ready -> running -> done, FIFO order of the ready queue, reply tokens. */
#include "rt_internal.h"

#include <check.h>
#include <signal.h>

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
            s->tok[i] = rt_task_take_token(t, 0);
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
    rt_task_take_token(t, 0);
    return RT_TASK_DONE;
}

START_TEST(test_done_with_pending_aborts) {
    rt_tasks ts;
    rt_tasks_init(&ts);
    rt_tasks_spawn(&ts, done_with_pending, NULL);
    rt_tasks_run(&ts, 1);
}
END_TEST

int main(void) {
    Suite *s = suite_create("rt_task");
    TCase *tc = tcase_create("task");
    tcase_add_test(tc, test_state_transitions);
    tcase_add_test(tc, test_fifo_and_reuse);
    tcase_add_test(tc, test_yield_and_empty_wait);
    tcase_add_test(tc, test_bad_tokens);
    tcase_add_test_raise_signal(tc, test_done_with_pending_aborts, SIGABRT);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed ? 1 : 0;
}
