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
 * stale token (generation changed) is a bug.  The ready queue is a FIFO through rt_task.q.
 * The blocking queue is an intrusive doubly linked list (bprev/bnext, head and tail in
 * rt_tasks) in order of blocking: a reply finds its task through the token, not by a walk,
 * and unlinks it in O(1) when its last reply arrives.  Invariants: a task is on the
 * blocking queue iff its state is BLOCKED, and then pending > 0; nblocked is the list's
 * length.  The list exists for diagnosis: each task records since when it is blocked
 * (rt_now), its pending count, the destination and handler of its last request and an
 * application label, which rt_tasks_dump prints (the deadlock report, rt_term.c), and the
 * queue keeps statistics (times blocked, most blocked at once, time spent blocked).  All of
 * it runs on the main thread; worker threads reach tasks only through messages.
 */
#include "rt_internal.h"

#include <stdarg.h>
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
    t->bprev = t->bnext = NULL;
    t->blocked_at = 0;
    t->last_dest = t->last_handler = -1;
    t->label[0] = '\0';
    t->st = RT_TS_NEW;
    ts->nlive++;
    ts->spawned++;
    t->st = RT_TS_READY;
    rt_queue_push(&ts->ready, &t->q);
    return t;
}

/* Appends t to the blocking queue (it just returned WAIT with replies outstanding). */
static void block(rt_tasks *ts, rt_task *t) {
    t->st = RT_TS_BLOCKED;
    t->blocked_at = rt_now();
    t->bnext = NULL;
    t->bprev = ts->btail;
    if (ts->btail)
        ts->btail->bnext = t;
    else
        ts->bhead = t;
    ts->btail = t;
    ts->nblocked++;
    ts->blocked_count++;
    if (ts->nblocked > ts->blocked_max) ts->blocked_max = ts->nblocked;
}

/* Unlinks t from the blocking queue (its last reply arrived) and moves it to the ready
 * queue's tail. */
static void unblock(rt_tasks *ts, rt_task *t) {
    RT_CHECK(t->st == RT_TS_BLOCKED && ts->nblocked > 0);
    if (t->bprev)
        t->bprev->bnext = t->bnext;
    else
        ts->bhead = t->bnext;
    if (t->bnext)
        t->bnext->bprev = t->bprev;
    else
        ts->btail = t->bprev;
    t->bprev = t->bnext = NULL;
    ts->nblocked--;
    double dt = rt_now() - t->blocked_at;
    if (dt < 0) dt = 0;
    ts->blocked_time_sum += dt;
    if (dt > ts->blocked_time_max) ts->blocked_time_max = dt;
    t->st = RT_TS_READY;
    rt_queue_push(&ts->ready, &t->q);
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
            t->label[0] = '\0';
            ts->nlive--;
            ts->done++;
            rt_queue_push(&ts->free_q, &t->q);
            break;
        case RT_TASK_WAIT:
        case RT_TASK_YIELD:
            if (r == RT_TASK_WAIT && t->pending > 0) {
                block(ts, t);
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

rt_token rt_task_take_token(rt_task *t, int rank, int dest, int handler) {
    RT_CHECK(t->st == RT_TS_RUNNING || t->st == RT_TS_READY);
    t->pending++;
    t->last_dest = dest;
    t->last_handler = handler;
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
    if (--t->pending == 0 && t->st == RT_TS_BLOCKED) unblock(ts, t);
}

void rt_tasks_reset_stats(rt_tasks *ts) {
    ts->spawned = ts->done = 0;
    ts->blocked_count = 0;
    ts->blocked_max = ts->nblocked;
    ts->blocked_time_sum = ts->blocked_time_max = 0;
}

void rt_tasks_dump(const rt_tasks *ts, int rank, const rt_htable *ht, double now, FILE *f) {
    for (const rt_task *t = ts->bhead; t; t = t->bnext) {
        const char *hname = "-";
        if (ht && t->last_handler >= 0 && t->last_handler < ht->n &&
            ht->e[t->last_handler].registered)
            hname = ht->e[t->last_handler].name;
        fprintf(f,
                "rt: rank %d: blocked task slot %u (gen %u): %d pending, last request to rank %d "
                "handler %d '%s', label \"%s\", blocked %.6f s\n",
                rank, (unsigned)t->slot, (unsigned)t->gen, (int)t->pending, (int)t->last_dest,
                (int)t->last_handler, hname, t->label, now - t->blocked_at);
    }
}

void rt_task_label(rt_task *t, const char *fmt, ...) {
    if (!t || t->st == RT_TS_FREE || !fmt) RT_FATAL("rt_task_label: no live task or no format");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(t->label, sizeof t->label, fmt, ap); /* truncates, always terminated */
    va_end(ap);
}
