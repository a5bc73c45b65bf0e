/* rt_queue.c - intrusive singly linked FIFO queues.
 *
 * The runtime's ready queue, blocking bookkeeping, worker job/outgoing/completion queues and
 * perturbation pools are all FIFOs of nodes embedded in the queued objects (rt_qnode as a
 * member; RT_CONTAINER recovers the object), so queueing never allocates.  Invariants: head
 * is NULL iff tail is NULL iff n == 0; tail->next is NULL.  Not thread-safe: callers hold the
 * lock that protects the queue.
 */
#include "rt_internal.h"

void rt_queue_init(rt_queue *q) {
    q->head = q->tail = NULL;
    q->n = 0;
}

void rt_queue_push(rt_queue *q, rt_qnode *n) {
    n->next = NULL;
    if (q->tail)
        q->tail->next = n;
    else
        q->head = n;
    q->tail = n;
    q->n++;
}

rt_qnode *rt_queue_pop(rt_queue *q) {
    rt_qnode *n = q->head;
    if (!n) return NULL;
    q->head = n->next;
    if (!q->head) q->tail = NULL;
    q->n--;
    n->next = NULL;
    return n;
}

void rt_queue_append(rt_queue *dst, rt_queue *src) {
    if (!src->head) return;
    if (dst->tail)
        dst->tail->next = src->head;
    else
        dst->head = src->head;
    dst->tail = src->tail;
    dst->n += src->n;
    rt_queue_init(src);
}
