/* pbw_items.c: PBW's local work items and locks.  A work item (a bad triangle, or a
 * subsegment to split) that cannot go on now is deferred until what it waits for happens: the
 * release of a local lock holder, or a WAKE naming a key; a deferred item waiting for a refused
 * split is dropped, not retried. A hold is one cavity's locks on this rank; ending a hold wakes
 * whoever died on it (the waiters, possibly on other ranks).  Invariant: a deferred item comes back
 * only after an event, as the runtime's termination contract requires.  Part of TR-97-17 section 2.
 */
#include "pbw/pbw_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void pbw_iv_push(ivec *q, const pbw_item *it) {
    if (q->n >= q->cap && q->head > 0) {
        memmove(q->a, q->a + q->head, (size_t)(q->n - q->head) * sizeof(pbw_item));
        q->n -= q->head;
        q->head = 0;
    }
    MESH_GROW(q->a, q->n, q->cap);
    q->a[q->n++] = *it;
}

int pbw_iv_pop(ivec *q, pbw_item *it) {
    if (q->head >= q->n) {
        q->head = q->n = 0;
        return 0;
    }
    *it = q->a[q->head++];
    return 1;
}

void pbw_iv_shuffle(ivec *q, uint64_t seed) {
    for (int32_t i = q->n - 1; i > q->head; i--) {
        seed += 0x9e3779b97f4a7c15u; /* splitmix64 */
        uint64_t z = seed;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
        z ^= z >> 31;
        int32_t j = q->head + (int32_t)(z % (uint64_t)(i - q->head + 1));
        pbw_item t = q->a[i];
        q->a[i] = q->a[j];
        q->a[j] = t;
    }
}

int pbw_iv_empty(const ivec *q) {
    return q->head >= q->n;
}

void pbw_iv_free(ivec *q) {
    free(q->a);
    memset(q, 0, sizeof *q);
}

/* Parks a failed item until what it waits for happens (see W_*). */
void pbw_defer_item(pbw_ctx *C, const pbw_item *it, int kind, int64_t key, int32_t count) {
    pbw_item d = *it;
    d.wait_kind = kind;
    d.wait_key = key;
    d.wait_count = count;
    d.refused = 0;
    if ((kind == W_HOLD && pbw_hold_find(C, key) < 0) || (kind == W_WAKE && count <= 0))
        pbw_iv_push(&C->retryq, &d); /* already happened */
    else
        pbw_iv_push(&C->deferred, &d);
}

/* Moves the deferred items waiting for (kind, key) to the retry queue.  refused (W_WAKE): the split
 * that wakes them was refused; an item that waited for a refused split is dropped, not retried (its
 * Steiner point would ask for the same split again), as refine.c drops a bad triangle whose splits
 * all failed. */
static void deferred_release(pbw_ctx *C, int kind, int64_t key, int refused) {
    int32_t k = C->deferred.head;
    for (int32_t i = C->deferred.head; i < C->deferred.n; i++) {
        pbw_item *d = &C->deferred.a[i];
        int hit = d->wait_kind == kind && d->wait_key == key;
        if (hit && kind == W_WAKE) {
            d->refused |= refused;
            if (--d->wait_count > 0) hit = 0;
        }
        if (hit) {
            if (!d->refused) pbw_iv_push(&C->retryq, d);
        } else
            C->deferred.a[k++] = *d;
    }
    C->deferred.n = k;
}

void pbw_wake_key(pbw_ctx *C, int64_t key, int refused) {
    deferred_release(C, W_WAKE, key, refused);
    for (int32_t i = 0; i < C->ndy; i++)
        if (C->dy[i]->die_holder == key) C->dy[i]->woken = 1;
}

/* Wakes whoever waits for key on rank r (r < 0: nobody); refused: see deferred_release. */
void pbw_notify(pbw_ctx *C, int32_t r, int64_t key, int refused) {
    if (r < 0) return;
    if (r == C->rank) {
        pbw_wake_key(C, key, refused);
    } else {
        pbw_wake_msg w = {key, refused, 0};
        rt_rsr(r, C->hid[PBW_RSR_WAKE], &w, sizeof w);
    }
}

int32_t pbw_hold_find(pbw_ctx *C, int64_t key) {
    for (int32_t i = 0; i < C->nhd; i++)
        if (C->hd[i].active && C->hd[i].key == key) return i;
    return -1;
}

int32_t pbw_hold_new(pbw_ctx *C, int64_t key, uint64_t stamp, int32_t origin) {
    int32_t i;
    for (i = 0; i < C->nhd; i++)
        if (!C->hd[i].active) break;
    if (i == C->nhd) {
        MESH_GROW(C->hd, C->nhd, C->hdcap);
        memset(&C->hd[C->nhd], 0, sizeof(pbw_hold));
        C->nhd++;
    }
    pbw_hold *h = &C->hd[i];
    h->key = key;
    h->stamp = stamp;
    h->origin = origin;
    h->active = 1;
    h->distributed = 0;
    h->n = 0;
    h->t_spent = 0;
    return i;
}

/* The locks: an open-addressing table slot -> hold index, linear probing, deletion by
 * backward shift (no tombstones); at most half full. */
static uint32_t lk_home(const pbw_ctx *C, int32_t s) {
    return (uint32_t)mesh_hash64((uint64_t)(uint32_t)s) & (C->lkcap - 1);
}

int32_t pbw_lk_find(const pbw_ctx *C, int32_t s) {
    if (C->lkn == 0) return -1;
    for (uint32_t h = lk_home(C, s);; h = (h + 1) & (C->lkcap - 1)) {
        if (C->lkk[h] < 0) return -1;
        if (C->lkk[h] == s) return C->lkv[h];
    }
}

static void lk_grow(pbw_ctx *C) {
    int32_t *ok = C->lkk, *ov = C->lkv;
    uint32_t ocap = C->lkcap;
    C->lkcap = ocap ? 2 * ocap : 256;
    C->lkk = mesh_xrealloc(NULL, C->lkcap, sizeof(int32_t));
    C->lkv = mesh_xrealloc(NULL, C->lkcap, sizeof(int32_t));
    for (uint32_t i = 0; i < C->lkcap; i++)
        C->lkk[i] = -1;
    for (uint32_t i = 0; i < ocap; i++)
        if (ok[i] >= 0) {
            uint32_t h = lk_home(C, ok[i]);
            while (C->lkk[h] >= 0)
                h = (h + 1) & (C->lkcap - 1);
            C->lkk[h] = ok[i];
            C->lkv[h] = ov[i];
        }
    free(ok);
    free(ov);
}

void pbw_lk_set(pbw_ctx *C, int32_t s, int32_t hi) {
    if (hi >= 0) {
        if (2 * (C->lkn + 1) > C->lkcap) lk_grow(C);
        uint32_t h = lk_home(C, s);
        while (C->lkk[h] >= 0 && C->lkk[h] != s)
            h = (h + 1) & (C->lkcap - 1);
        if (C->lkk[h] < 0) C->lkn++;
        C->lkk[h] = s;
        C->lkv[h] = hi;
        return;
    }
    if (C->lkn == 0) return;
    uint32_t m = C->lkcap - 1, h = lk_home(C, s);
    while (C->lkk[h] >= 0 && C->lkk[h] != s)
        h = (h + 1) & m;
    if (C->lkk[h] < 0) return; /* not locked */
    C->lkn--;
    /* backward shift: move later entries of the run into the hole if their home allows */
    for (uint32_t j = (h + 1) & m; C->lkk[j] >= 0; j = (j + 1) & m) {
        uint32_t k = lk_home(C, C->lkk[j]);
        if (((j - k) & m) >= ((j - h) & m)) {
            C->lkk[h] = C->lkk[j];
            C->lkv[h] = C->lkv[j];
            h = j;
        }
    }
    C->lkk[h] = -1;
}

void pbw_lock_slot(pbw_ctx *C, int32_t s, int32_t hi, int role) {
    if (LK(C, s) != hi) {
        pbw_hold *h = &C->hd[hi];
        MESH_GROW(h->slots, h->n, h->cap);
        h->slots[h->n++] = s;
        pbw_lk_set(C, s, hi);
    }
    pbw_role_set(C, s, role);
}

void pbw_waiter_add(pbw_ctx *C, int64_t key, int32_t rank) {
    for (int32_t i = 0; i < C->nwt; i++)
        if (C->wt[i].key == key && C->wt[i].rank == rank) return;
    MESH_GROW(C->wt, C->nwt, C->wtcap);
    C->wt[C->nwt].key = key;
    C->wt[C->nwt].rank = rank;
    C->nwt++;
}

/* Frees hold hi (its locks must be gone) and wakes whoever died on it. */
void pbw_hold_end(pbw_ctx *C, int32_t hi) {
    int64_t key = C->hd[hi].key;
    C->hd[hi].active = 0;
    C->hd[hi].n = 0;
    for (int32_t i = 0; i < C->nwt;) {
        if (C->wt[i].key == key) {
            pbw_notify(C, C->wt[i].rank, key, 0);
            C->wt[i] = C->wt[--C->nwt];
        } else {
            i++;
        }
    }
    /* only a distributed cavity's locks outlive one step of local work, so only those can
     * have deferred items waiting for them */
    if (C->hd[hi].distributed) deferred_release(C, W_HOLD, key, 0);
}

/* Releases every lock of hold hi on this rank (undo: a lock conflict: the expansion time
 * goes to RT_TIME_UNDO). */
void pbw_release_local(pbw_ctx *C, int32_t hi, int undo) {
    pbw_hold *h = &C->hd[hi];
    for (int32_t i = 0; i < h->n; i++) {
        int32_t s = h->slots[i];
        if (LK(C, s) != hi) continue;
        if (ROLE(C, s) == ROLE_RES) {
            pbw_slot_free(C, s);
        } else {
            pbw_lk_set(C, s, -1);
            pbw_role_set(C, s, ROLE_NONE);
        }
    }
    if (undo) rt_stats_add_time(RT_TIME_UNDO, h->t_spent);
    pbw_hold_end(C, hi);
}
