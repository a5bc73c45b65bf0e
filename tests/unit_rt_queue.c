/* unit_rt_queue.c - the runtime's intrusive FIFO queues (rt_queue.c). */
#include "check_run.h"
#include "rt_internal.h"

#include <stdlib.h>

typedef struct item {
    int v;
    rt_qnode q;
} item;

static int val(rt_qnode *n) {
    return RT_CONTAINER(n, item, q)->v;
}

START_TEST(test_fifo_order) {
    rt_queue q;
    rt_queue_init(&q);
    ck_assert(rt_queue_empty(&q));
    ck_assert_ptr_null(rt_queue_pop(&q));
    item it[5];
    for (int i = 0; i < 5; i++) {
        it[i].v = i;
        rt_queue_push(&q, &it[i].q);
    }
    ck_assert_uint_eq(q.n, 5);
    for (int i = 0; i < 5; i++) {
        rt_qnode *n = rt_queue_pop(&q);
        ck_assert_ptr_nonnull(n);
        ck_assert_int_eq(val(n), i);
    }
    ck_assert(rt_queue_empty(&q));
    ck_assert_ptr_null(q.tail);
    ck_assert_uint_eq(q.n, 0);
}
END_TEST

START_TEST(test_interleaved_and_reuse) {
    rt_queue q;
    rt_queue_init(&q);
    item a = {1, {0}}, b = {2, {0}}, c = {3, {0}};
    rt_queue_push(&q, &a.q);
    ck_assert_int_eq(val(rt_queue_pop(&q)), 1);
    ck_assert(rt_queue_empty(&q));
    rt_queue_push(&q, &b.q);
    rt_queue_push(&q, &a.q); /* a node may be queued again after it was popped */
    ck_assert_int_eq(val(rt_queue_pop(&q)), 2);
    rt_queue_push(&q, &c.q);
    ck_assert_int_eq(val(rt_queue_pop(&q)), 1);
    ck_assert_int_eq(val(rt_queue_pop(&q)), 3);
    ck_assert_ptr_null(rt_queue_pop(&q));
}
END_TEST

START_TEST(test_append) {
    rt_queue a, b;
    rt_queue_init(&a);
    rt_queue_init(&b);
    item it[6];
    for (int i = 0; i < 6; i++)
        it[i].v = i;
    rt_queue_append(&a, &b); /* empty into empty */
    ck_assert(rt_queue_empty(&a));
    for (int i = 3; i < 6; i++)
        rt_queue_push(&b, &it[i].q);
    rt_queue_append(&a, &b); /* into empty */
    ck_assert(rt_queue_empty(&b));
    ck_assert_uint_eq(a.n, 3);
    rt_queue_init(&a);
    for (int i = 0; i < 3; i++)
        rt_queue_push(&a, &it[i].q);
    for (int i = 3; i < 6; i++)
        rt_queue_push(&b, &it[i].q);
    rt_queue_append(&a, &b);
    ck_assert_uint_eq(a.n, 6);
    ck_assert_uint_eq(b.n, 0);
    for (int i = 0; i < 6; i++)
        ck_assert_int_eq(val(rt_queue_pop(&a)), i);
    ck_assert(rt_queue_empty(&a));
}
END_TEST

START_TEST(test_many) {
    enum { N = 100000 };
    item *it = malloc(sizeof *it * N);
    rt_queue q;
    rt_queue_init(&q);
    for (int i = 0; i < N; i++) {
        it[i].v = i;
        rt_queue_push(&q, &it[i].q);
        if (i % 3 == 2) rt_queue_pop(&q);
    }
    int expect = N / 3;
    rt_qnode *n;
    while ((n = rt_queue_pop(&q)))
        ck_assert_int_eq(val(n), expect++);
    ck_assert_int_eq(expect, N);
    free(it);
}
END_TEST

int main(void) {
    return ck_run(
        ck_suite("rt_queue", 0,
                 CK_TESTS(test_fifo_order, test_interleaved_and_reuse, test_append, test_many)));
}
