/* rt_perturb.c - seeded perturbation of message delivery, for tests.
 *
 * When enabled (rt_config.perturb_seed / RT_PERTURB=SEED), every incoming RSR, including
 * self-sends, is put in a holding pool instead of being delivered.  It gets a random delay of
 * 0..7 poll iterations (sometimes 0..63); each poll iteration visits the sources in a random
 * order and delivers the due messages at the head of each source's FIFO.  So messages from
 * different sources are delayed and reordered relative to each other, while the order from
 * one source is kept (MPI's non-overtaking guarantee, which applications may rely on).  Held
 * messages count as received-but-not-processed: a rank holding any is not passive, so the
 * termination detector stays correct.  A xorshift64* generator makes a run reproducible by
 * seed (up to the timing of MPI arrivals).
 */
#include "rt_internal.h"

#include <string.h>

void rt_perturb_init(rt_perturb *p, uint64_t seed, int nsrc) {
    memset(p, 0, sizeof *p);
    p->rng = seed * 0x9E3779B97F4A7C15ull + 0x2545F4914F6CDD1Dull;
    if (!p->rng) p->rng = 1;
    p->nsrc = nsrc;
    p->held = rt_xmalloc(sizeof *p->held * (size_t)nsrc);
    p->perm = rt_xmalloc(sizeof *p->perm * (size_t)nsrc);
    for (int i = 0; i < nsrc; i++) {
        rt_queue_init(&p->held[i]);
        p->perm[i] = i;
    }
}

void rt_perturb_destroy(rt_perturb *p) {
    if (p->held) {
        for (int i = 0; i < p->nsrc; i++) {
            rt_qnode *n;
            while ((n = rt_queue_pop(&p->held[i])))
                rt_xfree(RT_CONTAINER(n, rt_item, q));
        }
    }
    rt_xfree(p->held);
    rt_xfree(p->perm);
    memset(p, 0, sizeof *p);
}

uint64_t rt_perturb_rand(rt_perturb *p) {
    uint64_t x = p->rng;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    p->rng = x;
    return x * 0x2545F4914F6CDD1Dull;
}

void rt_perturb_hold(rt_perturb *p, rt_item *it, int src) {
    RT_CHECK(src >= 0 && src < p->nsrc);
    uint64_t r = rt_perturb_rand(p);
    uint64_t delay = (r >> 8) % 16 == 0 ? (r >> 16) % 64 : (r >> 16) % 8;
    it->release_at = p->iter + delay;
    rt_queue_push(&p->held[src], &it->q);
    p->nheld++;
}

size_t rt_perturb_release(rt_perturb *p, void (*deliver)(rt_item *it)) {
    p->iter++;
    if (p->nheld == 0) return 0;
    for (int i = p->nsrc - 1; i > 0; i--) {
        int j = (int)(rt_perturb_rand(p) % (uint64_t)(i + 1));
        int tmp = p->perm[i];
        p->perm[i] = p->perm[j];
        p->perm[j] = tmp;
    }
    size_t n = 0;
    for (int k = 0; k < p->nsrc; k++) {
        rt_queue *q = &p->held[p->perm[k]];
        while (q->head && RT_CONTAINER(q->head, rt_item, q)->release_at <= p->iter) {
            rt_item *it = RT_CONTAINER(rt_queue_pop(q), rt_item, q);
            p->nheld--;
            n++;
            deliver(it);
        }
    }
    return n;
}
