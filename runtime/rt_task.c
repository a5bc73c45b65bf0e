/* rt_task.c - tasks: continuations that wait for remote replies without holding the CPU.
 *
 * TR-97-17 section 2: "blocking tasks are waiting for the completion of pending requests to
 * other processors ... stored in the blocking-queue ... moved to the ready-queue when all of
 * its remote requests have been serviced.  The ready queue is organized in FIFO order."
 * A task is a function plus a state pointer.  State machine:
 *     NEW -spawn-> READY -run-> RUNNING -DONE-> FREE (slot reused, generation + 1)
 *                                      -WAIT, pending > 0-> BLOCKED -last reply-> READY
 *                                      -WAIT, pending == 0 or YIELD-> READY (queue tail)
 * A request carries a token (rank, slot, generation) naming the waiting task; a reply with a
 * stale token (generation changed) is a bug.  Blocked tasks are only counted (nblocked): they
 * are found again through their token, so the "blocking queue" needs no list walk.  All of it
 * runs on the main thread; worker threads reach tasks only through messages.
 */
#include "rt_internal.h"

#include <stdlib.h>
#include <string.h>

void rt_tasks_init(rt_tasks *ts) {
    memset(ts, 0, sizeof *ts);
    rt_queue_init(&ts->free_q);
    rt_queue_init(&ts->ready);
}

void rt_tasks_destroy(rt_tasks *ts) {
    for (uint32_t i = 0; i < ts->nslot; i++)
        rt_xfree(ts->slot[i]);
    rt_xfree(ts->slot);
    rt_tasks_init(ts);
}

rt_task *rt_tasks_spawn(rt_tasks *ts, rt_task_fn fn, void *state) {
    RT_CHECK(fn != NULL);
    rt_task *t;
    rt_qnode *n = rt_queue_pop(&ts->free_q);
    if (n) {
        t = RT_CONTAINER(n, rt_task, q);
    } else {
        if (ts->nslot == ts->cap) {
            ts->cap = ts->cap ? 2 * ts->cap : 64;
            ts->slot = rt_xrealloc(ts->slot, ts->cap * sizeof *ts->slot);
        }
        t = rt_xmalloc(sizeof *t);
        memset(t, 0, sizeof *t);
        t->slot = ts->nslot;
        ts->slot[ts->nslot++] = t;
    }
    RT_CHECK(t->st == RT_TS_FREE);
    t->fn = fn;
    t->state = state;
    t->pending = 0;
    t->st = RT_TS_NEW;
    ts->nlive++;
    ts->spawned++;
    t->st = RT_TS_READY;
    rt_queue_push(&ts->ready, &t->q);
    return t;
}

size_t rt_tasks_run(rt_tasks *ts, size_t max) {
    size_t ran = 0;
    while (ran < max) {
        rt_qnode *n = rt_queue_pop(&ts->ready);
        if (!n) break;
        rt_task *t = RT_CONTAINER(n, rt_task, q);
        RT_CHECK(t->st == RT_TS_READY);
        t->st = RT_TS_RUNNING;
        rt_task_status r = t->fn(t, t->state);
        ran++;
        RT_CHECK(t->st == RT_TS_RUNNING);
        switch (r) {
        case RT_TASK_DONE:
            if (t->pending != 0)
                RT_FATAL("task finished with %d replies outstanding", (int)t->pending);
            t->st = RT_TS_FREE;
            t->gen++;
            t->fn = NULL;
            t->state = NULL;
            ts->nlive--;
            ts->done++;
            rt_queue_push(&ts->free_q, &t->q);
            break;
        case RT_TASK_WAIT:
        case RT_TASK_YIELD:
            if (r == RT_TASK_WAIT && t->pending > 0) {
                t->st = RT_TS_BLOCKED;
                ts->nblocked++;
            } else { /* yield, or nothing left to wait for */
                t->st = RT_TS_READY;
                rt_queue_push(&ts->ready, &t->q);
            }
            break;
        default:
            RT_FATAL("task returned invalid status %d", (int)r);
        }
    }
    return ran;
}

rt_token rt_task_take_token(rt_task *t, int rank) {
    RT_CHECK(t->st == RT_TS_RUNNING || t->st == RT_TS_READY);
    t->pending++;
    rt_token tok = {rank, t->slot, t->gen};
    return tok;
}

rt_task *rt_tasks_lookup(rt_tasks *ts, rt_token tok) {
    if (tok.slot >= ts->nslot) return NULL;
    rt_task *t = ts->slot[tok.slot];
    if (t->gen != tok.gen || t->st == RT_TS_FREE || t->pending <= 0) return NULL;
    return t;
}

void rt_tasks_reply(rt_tasks *ts, rt_task *t) {
    RT_CHECK(t->pending > 0);
    if (--t->pending == 0 && t->st == RT_TS_BLOCKED) {
        ts->nblocked--;
        t->st = RT_TS_READY;
        rt_queue_push(&ts->ready, &t->q);
    }
}
