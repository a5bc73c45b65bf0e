/* pcdm_det.c: PCDM in deterministic rounds -- the same mesh for any rank count and any message
 * timing (issue 16).
 *
 * The asynchronous protocol (pcdm.c) refines a rank's subdomains in one mesh and applies a
 * neighbour's split the moment it arrives, so the insertion order, and with it the mesh,
 * depends on timing and on which subdomains share a rank.  Here every subdomain is refined on
 * its own, in its own mesh (built from the same coarse CDT, holding that subdomain alone), in
 * rounds: round 0 refines the coarse subdomain to completion; round r >= 1 waits until every
 * neighbouring subdomain has sent its round r-1 splits (possibly none), applies them in
 * canonical order (sorted by the dyadic name (seg, level, k), duplicates dropped), refines to
 * completion (skipped when nothing arrived: the mesh is unchanged and already complete) and
 * sends each neighbour the interface splits it made in round r (in its named splits' cascades
 * and in its refinement), one message per neighbour per round.  A subdomain's mesh is then a
 * pure function of its coarse mesh and the lists it received: its queues, vertex numbering,
 * point-location random stream and Steiner budget are its own, and the lists depend on the
 * neighbours' rounds alone, which are pure by induction.  Rounds of different subdomains overlap
 * freely: a subdomain waits only for its neighbours' previous round (a deterministic dataflow);
 * between subdomains of one rank the lists are handed over directly, between ranks as one RSR
 * ("pcdm_round": header + splits).  Still only "split this constraint edge" crosses ranks.
 *
 * Termination: when all its subdomains have completed round r a rank reports to every rank
 * ("pcdm_rdone") how many of its subdomains completed round r and the splits they sent in it; a
 * subdomain that arrived later (--balance dynamic, pcdm_move.c) and completes r here is reported
 * in another such message.  Round r is known once its completions add up to the number of
 * subdomains.  The first known round R with no split anywhere ends the run: round R+1's lists
 * are all empty, so nothing can change any more.  A subdomain may start round r only when rounds up
 * to r - WINDOW are known (so subdomains with nothing to do do not race ahead through empty
 * rounds); since the slowest subdomain is never held back by the window (the window never blocks a
 * round <= known), some rank is always busy or a message is in flight until R is known: rt_run's
 * detector cannot end the run early, and it ends once every rank knows R.  p->rounds = R + 1 on
 * every rank.
 *
 * More ranks than CPUs on a host (one thread each): a subdomain's first round, the bulk of its
 * refinement, runs only while its rank holds a slot of the host's CPU gate (base/gate.h), so the
 * kernel does not time-slice more refining ranks than there are CPUs and each keeps its mesh in
 * its caches (measured on North America at 13.9M triangles, 8 ranks on 2 cores: the refinement's
 * CPU time 6.9-7.1 -> 6.2-6.6 s); later rounds, short and awaited by the neighbours, run ungated.
 *
 * Invariants: a neighbour's round-r list arrives while its receiver has completed r or r + 1
 * rounds (it needs the receiver's round r-1 list; the receiver needs it for round r+1), so two
 * input slots by round parity suffice; each local interface split is sent exactly once, to the
 * subdomain on the other side; splits are never undone.
 */
#include "pcdm/pcdm_det_impl.h"

#include "base/base.h"
#include "base/gate.h"
#include "base/pfor.h"
#include "seq/kernel.h"

#include "rt.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* "pcdm_rdone" payload: the sender's subdomains completed round `round` `count` times (each
 * subdomain once, reported by the rank that held it then) and sent `splits` splits in it. */
typedef struct det_report {
    int32_t round;
    int32_t count;
    int64_t splits;
} det_report;
_Static_assert(sizeof(det_report) == 16, "det_report must be 16 bytes, no padding");

typedef struct det_slot {
    int round_handler, report_handler, refine_handler, refined_handler;
    pcdm_det *active;
} det_slot;

/* the longest sleep on the host's CPU gate before this rank polls its messages again */
#define GATE_WAIT_NS 1000000L

static det_slot dslot = {-1, -1, -1, -1, NULL};

static void refine_handler(const rt_msg *msg, void *arg);
static void refined_handler(const rt_msg *msg, void *arg);

/* ---- round bookkeeping ---------------------------------------------------------------------- */

static void rounds_grow(pcdm_det *D, int32_t r) {
    if (r < D->rep_cap) return;
    int32_t cap = D->rep_cap ? D->rep_cap : 16;
    while (cap <= r)
        cap *= 2;
    D->rep_n = mesh_xrealloc(D->rep_n, (size_t)cap, sizeof *D->rep_n);
    D->cnt = mesh_xrealloc(D->cnt, (size_t)cap, sizeof *D->cnt);
    D->rep_splits = mesh_xrealloc(D->rep_splits, (size_t)cap, sizeof *D->rep_splits);
    D->mine = mesh_xrealloc(D->mine, (size_t)cap, sizeof *D->mine);
    for (int32_t i = D->rep_cap; i < cap; i++) {
        D->rep_n[i] = D->cnt[i] = 0;
        D->rep_splits[i] = D->mine[i] = 0;
    }
    D->rep_cap = cap;
}

/* count more completions of round `round`, with splits; a round is known once every subdomain
 * of the decomposition completed it */
static void tally(pcdm_det *D, int32_t round, int32_t count, int64_t splits) {
    rounds_grow(D, round);
    D->rep_n[round] += count;
    D->rep_splits[round] += splits;
    if (D->rep_n[round] > D->p->d->nsub)
        MESH_BUG("round %d completed %d times by %d subdomains", round, D->rep_n[round],
                 D->p->d->nsub);
    while (D->known < D->rep_cap && D->rep_n[D->known] == D->p->d->nsub) {
        if (D->rep_splits[D->known] == 0 && D->stop < 0) D->stop = D->known;
        D->known++;
    }
}

static void report_handler(const rt_msg *msg, void *arg) {
    det_slot *sl = arg;
    if (!sl->active) MESH_BUG("round report from rank %d outside refinement", msg->src);
    det_report r;
    memcpy(&r, msg->data, sizeof r);
    tally(sl->active, r.round, r.count, r.splits);
}

/* Reports the completions of every round all of this rank's subdomains have completed (one
 * report per round, and another for a subdomain that arrived later and completed it here). */
void det_report_rounds(pcdm_det *D) {
    int32_t low = INT32_MAX;
    for (int32_t i = 0; i < D->n; i++)
        if (D->s[i]->done < low) low = D->s[i]->done;
    for (int32_t r = 0; r < low && r < D->rep_cap; r++) {
        if (D->cnt[r] == 0) continue;
        det_report rep = {r, D->cnt[r], D->mine[r]};
        for (int q = 0; q < rt_size(); q++)
            if (q != D->p->rank) rt_rsr(q, dslot.report_handler, &rep, (uint32_t)sizeof rep);
        D->cnt[r] = 0;
        D->mine[r] = 0;
        tally(D, r, rep.count, rep.splits);
    }
}

/* ---- split lists ---------------------------------------------------------------------------- */

static void list_push(det_list *l, const pcdm_split_msg *v, int32_t n) {
    if (n <= 0) return;
    if (l->n + n > l->cap) {
        int32_t cap = l->cap ? l->cap : 16;
        while (cap < l->n + n)
            cap *= 2;
        l->v = mesh_xrealloc(l->v, (size_t)cap, sizeof *l->v);
        l->cap = cap;
    }
    memcpy(l->v + l->n, v, (size_t)n * sizeof *v);
    l->n += n;
}

static int split_cmp(const void *a, const void *b) {
    const pcdm_split_msg *x = a, *y = b;
    if (x->seg != y->seg) return x->seg < y->seg ? -1 : 1;
    if (x->level != y->level) return x->level < y->level ? -1 : 1;
    if (x->k != y->k) return x->k < y->k ? -1 : 1;
    return 0;
}

static int32_t nb_index(const det_sub *s, int32_t sub) {
    int32_t lo = 0, hi = s->nnb - 1;
    while (lo <= hi) {
        int32_t mid = (lo + hi) / 2;
        if (s->nb[mid] == sub) return mid;
        if (s->nb[mid] < sub)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return -1;
}

void det_deliver(pcdm_det *D, const det_round_hdr *h, const pcdm_split_msg *v) {
    int32_t li = h->dst >= 0 && h->dst < D->p->d->nsub ? D->local[h->dst] : -1;
    if (li < 0) MESH_BUG("round list for subdomain %d, not held by rank %d", h->dst, D->p->rank);
    det_sub *s = D->s[li];
    if (s->done != h->round && s->done != h->round + 1)
        MESH_BUG("subdomain %d: round %d list from %d after %d rounds", s->id, h->round, h->src,
                 s->done);
    int par = h->round & 1;
    list_push(&s->in[par], v, h->n);
    s->got[par]++;
    D->delivered += h->n;
}

static void round_handler(const rt_msg *msg, void *arg) {
    det_slot *sl = arg;
    pcdm_det *D = sl->active;
    if (!D) MESH_BUG("round list from rank %d outside refinement", msg->src);
    det_round_hdr h;
    if (msg->len < sizeof h) MESH_BUG("short round list from rank %d", msg->src);
    memcpy(&h, msg->data, sizeof h);
    if (h.n < 0 || msg->len != sizeof h + (size_t)h.n * sizeof(pcdm_split_msg) || h.dst < 0 ||
        h.dst >= D->p->d->nsub)
        MESH_BUG("round list from rank %d: %d splits in %u bytes", msg->src, h.n,
                 (unsigned)msg->len);
    if (D->local[h.dst] < 0) { /* it moved on (dynamic balancing): the list follows it */
        if (D->owner[h.dst] == D->p->rank)
            MESH_BUG("round list for subdomain %d: neither here nor gone", h.dst);
        rt_rsr(D->owner[h.dst], dslot.round_handler, msg->data, msg->len);
        D->p->forwarded++;
        return;
    }
    pcdm_split_msg *v = mesh_xmalloc((size_t)h.n + 1, sizeof *v);
    memcpy(v, (const unsigned char *)msg->data + sizeof h, (size_t)h.n * sizeof *v);
    det_deliver(D, &h, v);
    D->p->split_recv += (uint64_t)h.n; /* from another rank */
    free(v);
}

int pcdm_det_register(void) {
    int a = rt_handler_register("pcdm_round", round_handler, &dslot, RT_NONTHREADED | RT_VARSIZE,
                                (uint32_t)DET_MAX_PAYLOAD);
    if (a < 0) return a;
    int b = rt_handler_register("pcdm_rdone", report_handler, &dslot, RT_NONTHREADED,
                                (uint32_t)sizeof(det_report));
    if (b < 0) return b;
    int c = rt_handler_register("pcdm_refine", refine_handler, &dslot, RT_THREADED,
                                (uint32_t)sizeof(int32_t));
    if (c < 0) return c;
    int e = rt_handler_register("pcdm_refined", refined_handler, &dslot, RT_NONTHREADED,
                                (uint32_t)sizeof(int32_t));
    if (e < 0) return e;
    dslot.round_handler = a;
    dslot.report_handler = b;
    dslot.refine_handler = c;
    dslot.refined_handler = e;
    return det_move_register();
}

/* ---- the held set --------------------------------------------------------------------------- */

void det_hold(pcdm_det *D, det_sub *s) {
    if (D->local[s->id] >= 0) MESH_BUG("subdomain %d held twice", s->id);
    if (D->n == D->cap) {
        D->cap = D->cap ? 2 * D->cap : 8;
        D->s = mesh_xrealloc(D->s, (size_t)D->cap, sizeof *D->s);
    }
    int32_t i = D->n;
    while (i > 0 && D->s[i - 1]->id > s->id) {
        D->s[i] = D->s[i - 1];
        D->local[D->s[i]->id] = i;
        i--;
    }
    D->s[i] = s;
    D->local[s->id] = i;
    D->n++;
    if (D->cur >= i) D->cur++;
}

det_sub *det_release(pcdm_det *D, int32_t sub) {
    int32_t i = D->local[sub];
    if (i < 0 || i == D->cur) MESH_BUG("release of subdomain %d (index %d)", sub, i);
    det_sub *s = D->s[i];
    for (int32_t j = i; j + 1 < D->n; j++) {
        D->s[j] = D->s[j + 1];
        D->local[D->s[j]->id] = j;
    }
    D->n--;
    D->local[sub] = -1;
    if (D->cur > i) D->cur--;
    return s;
}

void det_sub_free(det_sub *s) {
    if (!s) return;
    mesh_free(&s->m);
    pcdm_sub_map_free(&s->map);
    for (int32_t j = 0; j < s->nnb; j++)
        free(s->out[j].v);
    free(s->out);
    free(s->nb);
    free(s->in[0].v);
    free(s->in[1].v);
    free(s);
}

/* ---- build ---------------------------------------------------------------------------------- */

typedef struct build_job {
    pcdm_det *D;
    int32_t *sub, n;
    det_sub **rec;
    char (*err)[256];
} build_job;

static void build_one(void *arg, int64_t i) {
    build_job *b = arg;
    b->rec[i] = det_sub_new(b->D, b->sub[i], b->err[i], sizeof b->err[i]);
}

int pcdm_det_build(pcdm_part *p, char *err, size_t errlen) {
    const pcdm_decomp *d = p->d;
    pcdm_det *D = mesh_xcalloc(1, sizeof *D);
    p->det = D;
    D->p = p;
    D->cur = -1;
    D->stop = -1;
    D->local = mesh_xmalloc((size_t)d->nsub + 1, sizeof(int32_t));
    D->owner = mesh_xmalloc((size_t)d->nsub + 1, sizeof(int32_t));
    for (int32_t s = 0; s < d->nsub; s++) {
        D->local[s] = -1;
        D->owner[s] = d->sub_owner[s];
    }
    /* the owned subdomains' meshes, built on the rank's threads (each alone: its own size) */
    build_job b = {D, mesh_xcalloc((size_t)d->nsub + 1, sizeof(int32_t)), 0, NULL, NULL};
    for (int32_t sub = 0; sub < d->nsub; sub++)
        if (d->sub_owner[sub] == p->rank) b.sub[b.n++] = sub;
    b.rec = mesh_xcalloc((size_t)b.n + 1, sizeof(det_sub *));
    b.err = mesh_xcalloc((size_t)b.n + 1, sizeof *b.err);
    mesh_pfor_items(b.n, p->threads > 1 ? p->threads : 1, build_one, &b);
    int rc = 0;
    for (int32_t i = 0; i < b.n; i++) {
        if (b.rec[i] && rc == 0) {
            det_hold(D, b.rec[i]);
            continue;
        }
        if (!b.rec[i] && rc == 0) snprintf(err, errlen, "%s", b.err[i]);
        det_sub_free(b.rec[i]);
        rc = -1;
    }
    free(b.sub);
    free(b.rec);
    free(b.err);
    if (rc != 0) pcdm_det_free(p);
    return rc;
}

/* ---- refinement ----------------------------------------------------------------------------- */

static void det_on_split(void *ctx, int32_t seg, int32_t level, int64_t k, unsigned flags) {
    det_sub *s = ctx;
    const pcdm_decomp *d = s->D->p->d;
    if (!(flags & MESH_SPLIT_INTERFACE) || seg < 0 || seg >= s->m.nseg) return;
    seg = pcdm_map_seg_global(&s->map, seg); /* lists name d->g's segments */
    if (seg < 0 || seg >= d->g.nsegs || !d->seg_iface[seg]) return;
    int32_t a = d->seg_sub[2 * (size_t)seg], b = d->seg_sub[2 * (size_t)seg + 1];
    int32_t o = a == s->id ? b : a;
    if (o < 0 || o == s->id) return;
    int32_t i = nb_index(s, o);
    if (i < 0) MESH_BUG("subdomain %d: split of segment %d, not next to %d", s->id, seg, o);
    pcdm_part *p = s->D->p;
    if (p->fault_drop > 0 && s->D->owner[o] != p->rank) { /* test-only fault: lose it */
        p->fault_drop--;
        return;
    }
    pcdm_split_msg r;
    memset(&r, 0, sizeof r);
    r.seg = seg;
    r.level = level;
    r.k = k;
    list_push(&s->out[i], &r, 1);
    s->splits++;
}

static int det_poll(void *ctx) {
    det_sub *s = ctx;
    if (s->running) return 0; /* on a worker: refine on, the main thread serves requests */
    pcdm_part *p = s->D->p;
    if (p->progress) {
        double t = rt_wtime();
        if (t - p->t_last >= 2.0) {
            p->t_last = t;
            fprintf(stderr, "pcdm: rank %d: %.1f s  subdomain %d round %d  %ld triangles\n",
                    p->rank, t - p->t_start, (int)s->id, (int)s->done, (long)s->m.nlive);
        }
    }
    return 1; /* back to the scheduler: service requests, flush ours */
}

/* The bounds and hooks of a subdomain (when it is built after pcdm_det_refine began: on
 * arrival). */
static void sub_setup(pcdm_det *D, det_sub *s) {
    const pcdm_decomp *d = D->p->d;
    mesh_quality qs = D->q;
    if (D->q.max_steiner >= 0) /* the budget's share of this subdomain's expected work */
        qs.max_steiner =
            d->total_weight > 0
                ? (int64_t)((double)D->q.max_steiner * d->sub_weight[s->id] / d->total_weight)
                : D->q.max_steiner;
    mesh_set_quality(&s->m, &qs);
    if (D->p->m.size_rule) /* the caller's size rule (--size, -r's .area), set on p->m */
        mesh_set_size_rule(&s->m, D->p->m.size_rule, D->p->m.size_rule_ctx);
    mesh_hooks h;
    memset(&h, 0, sizeof h);
    h.on_split = det_on_split;
    h.poll = det_poll;
    h.poll_every = D->p->poll_every;
    h.ctx = s;
    mesh_set_hooks(&s->m, &h);
}

det_sub *det_sub_new(pcdm_det *D, int32_t sub, char *err, size_t errlen) {
    const pcdm_decomp *d = D->p->d;
    det_sub *s = mesh_xcalloc(1, sizeof *s);
    s->id = sub;
    s->D = D;
    if (!d->sub_seg_off) MESH_BUG("decomposition without its per-subdomain lists");
    for (int32_t i = d->sub_seg_off[sub]; i < d->sub_seg_off[sub + 1]; i++) {
        int32_t g = d->sub_seg[i]; /* neighbours across interface pieces */
        if (!d->seg_iface[g]) continue;
        int32_t a = d->seg_sub[2 * (size_t)g], b = d->seg_sub[2 * (size_t)g + 1];
        int32_t o = a == sub ? b : b == sub ? a : -1;
        if (o < 0 || o == sub || nb_index(s, o) >= 0) continue;
        s->nb = mesh_xrealloc(s->nb, (size_t)s->nnb + 1, sizeof(int32_t));
        int32_t y = s->nnb++; /* insertion keeps them ascending (nb_index searches) */
        for (; y > 0 && s->nb[y - 1] > o; y--)
            s->nb[y] = s->nb[y - 1];
        s->nb[y] = o;
    }
    s->out = mesh_xcalloc((size_t)s->nnb + 1, sizeof(det_list));
    if (pcdm_build_sub(&s->m, &s->map, d, sub, D->p->regions, err, errlen) != 0) {
        mesh_init(&s->m); /* pcdm_build_sub freed it */
        det_sub_free(s);
        return NULL;
    }
    if (D->q_set) sub_setup(D, s);
    return s;
}

/* Ends subdomain i's current round: one list to each neighbour. */
static void finish_round(pcdm_det *D, int32_t i) {
    det_sub *s = D->s[i];
    int32_t r = s->done;
    for (int32_t j = 0; j < s->nnb; j++) {
        det_list *l = &s->out[j];
        det_round_hdr h = {s->nb[j], s->id, r, l->n};
        D->listed += l->n;
        if (D->local[h.dst] >= 0) {
            det_deliver(D, &h, l->v);
        } else {
            size_t len = sizeof h + (size_t)l->n * sizeof(pcdm_split_msg);
            if (len > DET_MAX_PAYLOAD) MESH_BUG("round list of %d splits", l->n);
            if ((size_t)D->nbuf < len) {
                D->buf = mesh_xrealloc(D->buf, len, 1);
                D->nbuf = (int32_t)len;
            }
            memcpy(D->buf, &h, sizeof h);
            if (l->n) memcpy(D->buf + sizeof h, l->v, (size_t)l->n * sizeof(pcdm_split_msg));
            int to = D->home_route ? D->p->d->sub_owner[h.dst] : D->owner[h.dst];
            rt_rsr(to, dslot.round_handler, D->buf, (uint32_t)len);
            D->p->split_sent += (uint64_t)l->n; /* to another rank: the rsr= figure */
        }
        l->n = 0;
    }
    rounds_grow(D, r);
    D->mine[r] += s->splits;
    D->cnt[r]++;
    s->splits = 0;
    s->done = r + 1;
    det_report_rounds(D);
}

double det_cpu(void) {
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return 0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void refine_step(pcdm_det *D) {
    det_sub *s = D->s[D->cur];
    double c = det_cpu();
    mesh_refine_result r = mesh_refine(&s->m);
    D->p->work_steps++;
    s->cpu += det_cpu() - c;
    if (r == MESH_REFINE_STOPPED) return;
    if (r == MESH_REFINE_STEINER_LIMIT) D->p->limit_hit = 1;
    if (s->done == 0) { /* this rank's speed: expected work per CPU second of round 0 */
        D->wdone += D->p->d->sub_weight[s->id];
        D->cdone += s->cpu;
    }
    int32_t i = D->cur;
    D->cur = -1;
    finish_round(D, i);
}

/* Applies subdomain s's inputs for its next round: its neighbours' previous lists, in
 * canonical order.  Returns 1 if the round must refine (round 0, or a list arrived).  Touches s
 * alone (its counts go to s->consumed, s->sdone, ...), so a worker thread may run it. */
static int apply_lists(det_sub *s) {
    int32_t r = s->done;
    if (r == 0) return 1;
    int refine = 0;
    det_list *l = &s->in[(r - 1) & 1];
    s->consumed += l->n;
    if (l->n > 1) qsort(l->v, (size_t)l->n, sizeof *l->v, split_cmp);
    for (int32_t k = 0; k < l->n; k++) {
        if (k > 0 && split_cmp(&l->v[k - 1], &l->v[k]) == 0) continue;
        int32_t seg = pcdm_map_seg_local(&s->map, l->v[k].seg);
        switch (seg < 0 ? MESH_SPLIT_NOT_FOUND
                        : mesh_split_subsegment_named(&s->m, seg, l->v[k].level, l->v[k].k)) {
        case MESH_SPLIT_DONE:
            s->sdone++;
            break;
        case MESH_SPLIT_ALREADY:
            s->signored++;
            break;
        case MESH_SPLIT_NOT_FOUND:
            s->snotfound++;
            fprintf(stderr,
                    "pcdm: rank %d: subdomain %d: split request for segment %d (%d, %lld): "
                    "not in its mesh\n",
                    s->D->p->rank, (int)s->id, (int)l->v[k].seg, (int)l->v[k].level,
                    (long long)l->v[k].k);
            break;
        }
        refine = 1; /* cheap when nothing changed: the queues are empty */
    }
    l->n = 0;
    s->got[(r - 1) & 1] = 0;
    return refine;
}

/* Adds subdomain s's counts from apply_lists to the rank's (main thread). */
static void fold_counts(pcdm_det *D, det_sub *s) {
    D->consumed += s->consumed;
    D->p->split_done += (uint64_t)s->sdone;
    D->p->split_ignored += (uint64_t)s->signored;
    D->p->split_notfound += (uint64_t)s->snotfound;
    s->consumed = s->sdone = s->signored = s->snotfound = 0;
}

/* Starts subdomain i's next round on the main thread. */
static void start_round(pcdm_det *D, int32_t i) {
    det_sub *s = D->s[i];
    int refine = apply_lists(s);
    fold_counts(D, s);
    if (refine) {
        D->cur = i;
        refine_step(D);
    } else {
        finish_round(D, i); /* nothing arrived: the mesh is unchanged and complete */
    }
}

/* ---- threads: a round on a worker ------------------------------------------------------------
 * With D->threads > 1 the main thread only schedules: a ready subdomain's round goes to the
 * runtime's threaded handler "pcdm_refine" (a worker applies the lists and refines to
 * completion, without polls), whose end comes back as "pcdm_refined" on the main thread, which
 * sends the round's lists.  A round is a pure function of the subdomain's mesh and lists, so
 * which thread runs it changes nothing in the mesh.  Payloads: the subdomain number.
 * A fault in a worker (a broken invariant, memory exhausted: MESH_BUG) stops every rank at once
 * (MPI_Abort), before anything is written; PCDM_TEST_WORKER_FAULT=SUB injects one into the
 * worker that takes subdomain SUB's first round (tests/t_threads_fault.sh). */

static void refine_handler(const rt_msg *msg, void *arg) {
    det_slot *sl = arg;
    pcdm_det *D = sl->active;
    int32_t sub;
    memcpy(&sub, msg->data, sizeof sub);
    det_sub *s = D->job[sub];
    if (s->id == D->fault_sub && s->done == 0)
        MESH_BUG("worker thread refining subdomain %d: fault injected by PCDM_TEST_WORKER_FAULT",
                 (int)s->id);
    double c = det_cpu();
    mesh_refine_result r = MESH_REFINE_DONE;
    if (apply_lists(s)) {
        do
            r = mesh_refine(&s->m);
        while (r == MESH_REFINE_STOPPED);
        s->result = 1 + (int32_t)r; /* 0: nothing refined */
    } else {
        s->result = 0;
    }
    s->cpu += det_cpu() - c;
    rt_rsr(D->p->rank, sl->refined_handler, &sub, (uint32_t)sizeof sub);
}

static void refined_handler(const rt_msg *msg, void *arg) {
    det_slot *sl = arg;
    pcdm_det *D = sl->active;
    int32_t sub;
    memcpy(&sub, msg->data, sizeof sub);
    int32_t i = sub >= 0 && sub < D->p->d->nsub ? D->local[sub] : -1;
    if (i < 0 || !D->s[i]->running) MESH_BUG("subdomain %d: a round ended that did not run", sub);
    det_sub *s = D->s[i];
    s->running = 0;
    D->nrunning--;
    fold_counts(D, s);
    if (s->result > 0) {
        D->p->work_steps++;
        if (s->result - 1 == MESH_REFINE_STEINER_LIMIT) D->p->limit_hit = 1;
        if (s->done == 0) {
            D->wdone += D->p->d->sub_weight[s->id];
            D->cdone += s->cpu;
        }
    }
    finish_round(D, i);
}

/* Hands ready subdomain i to a worker. */
static void dispatch(pcdm_det *D, int32_t i) {
    det_sub *s = D->s[i];
    s->running = 1;
    D->nrunning++;
    D->job[s->id] = s;
    int32_t sub = s->id;
    rt_rsr(D->p->rank, dslot.refine_handler, &sub, (uint32_t)sizeof sub);
}

static int ready(const pcdm_det *D, const det_sub *s) {
    int32_t r = s->done;
    if (s->running) return 0;
    if (r >= D->known + DET_WINDOW) return 0;
    return r == 0 || s->got[(r - 1) & 1] == s->nnb;
}

/* The least advanced ready subdomain (index into D->s), or -1. */
static int32_t next_ready(const pcdm_det *D) {
    int32_t best = -1;
    for (int32_t i = 0; i < D->n; i++)
        if (ready(D, D->s[i]) && (best < 0 || D->s[i]->done < D->s[best]->done)) best = i;
    return best;
}

static int det_work(void *ctx) {
    pcdm_det *D = ctx;
    if (D->threads > 1) {
        if (D->stop >= 0) return RT_WORK_IDLE;
        int started = 0;
        while (D->nrunning < D->threads && D->stop < 0) {
            int32_t best = next_ready(D);
            if (best < 0) break;
            det_sub *s = D->s[best];
            if (s->done > 0 && s->in[(s->done - 1) & 1].n == 0) {
                apply_lists(s); /* nothing arrived: the round is complete as it stands */
                fold_counts(D, s);
                finish_round(D, best);
            } else {
                dispatch(D, best);
            }
            started = 1;
        }
        if (started) return RT_WORK_BUSY;
        /* a running round ends in a handler; with none, take work from a busy rank */
        if (D->nrunning > 0) return RT_WORK_IDLE;
        return det_move_steal(D) ? RT_WORK_BUSY : RT_WORK_IDLE;
    }
    if (D->cur >= 0) {
        refine_step(D);
        return RT_WORK_BUSY;
    }
    if (D->stop >= 0) return RT_WORK_IDLE;
    int32_t best = next_ready(D);
    if (best < 0) { /* only a handler can make one ready; meanwhile take work from a busy rank */
        mesh_gate_give(&D->gate);
        return det_move_steal(D) ? RT_WORK_BUSY : RT_WORK_IDLE;
    }
    /* a first round (the bulk of the work) runs on a CPU of the host's gate, waited for asleep
     * (busy meanwhile, so never quiescent); the short later rounds, on which the neighbours
     * wait, without it */
    if (D->s[best]->done > 0)
        mesh_gate_give(&D->gate);
    else if (!mesh_gate_take(&D->gate, GATE_WAIT_NS))
        return RT_WORK_BUSY;
    start_round(D, best);
    return RT_WORK_BUSY;
}

void pcdm_det_refine(pcdm_part *p, const mesh_quality *q) {
    pcdm_det *D = p->det;
    if (dslot.round_handler < 0) MESH_BUG("pcdm_register was not called");
    D->q = *q;
    D->q_set = 1;
    for (int32_t i = 0; i < D->n; i++)
        sub_setup(D, D->s[i]);
    D->balance = p->balance;
    D->threads = p->threads > 1 ? p->threads : 1;
    if (D->threads > 1) D->job = mesh_xcalloc((size_t)p->d->nsub, sizeof *D->job);
    const char *fault = getenv("PCDM_TEST_WORKER_FAULT");
    D->fault_sub = fault && *fault ? (int32_t)atoi(fault) : -1;
    det_move_begin(D);
    D->cpu0 = det_cpu();
    if (D->threads == 1) mesh_gate_open(&D->gate, rt_app_comm());
    dslot.active = D;
    rt_run(det_work, D);
    dslot.active = NULL;
    mesh_gate_close(&D->gate);
    if (D->stop < 0 || D->cur >= 0 || D->nrunning != 0)
        MESH_BUG("rank %d: rounds ended without a final round", p->rank);
    p->rounds = D->stop + 1;
    p->nsub_owned = D->n; /* after balancing: the subdomains this rank ends with */
    /* each mesh a constrained Delaunay triangulation again (pcdm.c): a function of the mesh
     * alone, so the same for any rank count */
    for (int32_t i = 0; i < D->n; i++)
        p->flips += (uint64_t)pcdm_mesh_restore_delaunay(&D->s[i]->m);
    det_move_end(D);
}

/* ---- figures and output --------------------------------------------------------------------- */

/* The figures of subdomains i = k, k + T, k + 2T, ... of D (a thread's share). */
typedef struct det_fig {
    pcdm_det *D;
    int32_t k, T;
    pcdm_figures f;
} det_fig;

static void *det_fig_run(void *arg) {
    det_fig *g = arg;
    pcdm_figures *f = &g->f;
    for (int32_t i = g->k; i < g->D->n; i += g->T) {
        mesh *m = &g->D->s[i]->m;
        f->ntris += m->nlive;
        f->nverts += m->nv;
        f->inserted += m->stats.inserted;
        f->mesh_bytes += mesh_memory_bytes(m);
        f->unmet += mesh_count_unmet(m, NULL);
        f->refused += m->stats.unresolved;
        int64_t remote = 0;
        f->iface_enc += mesh_iface_defects(m, &remote);
        f->iface_remote += remote;
    }
    return NULL;
}

void pcdm_det_figures(pcdm_part *p, pcdm_figures *f) {
    pcdm_det *D = p->det;
    memset(f, 0, sizeof *f);
    /* each subdomain is its own mesh: the rank's worker count of threads scan them at once
     * (integer sums: the same figures for any count) */
    enum { FIG_MAXTHR = 64 };
    int32_t T = D->threads < D->n ? D->threads : D->n;
    if (T > FIG_MAXTHR) T = FIG_MAXTHR;
    if (T < 1) T = 1;
    det_fig g[FIG_MAXTHR];
    pthread_t th[FIG_MAXTHR];
    int started[FIG_MAXTHR] = {0};
    for (int32_t k = 0; k < T; k++) {
        memset(&g[k], 0, sizeof g[k]);
        g[k].D = D;
        g[k].k = k;
        g[k].T = T;
    }
    for (int32_t k = 1; k < T; k++)
        started[k] = pthread_create(&th[k], NULL, det_fig_run, &g[k]) == 0;
    det_fig_run(&g[0]);
    for (int32_t k = 0; k < T; k++) {
        if (k > 0 && started[k]) pthread_join(th[k], NULL);
        if (k > 0 && !started[k]) det_fig_run(&g[k]);
        f->ntris += g[k].f.ntris;
        f->nverts += g[k].f.nverts;
        f->inserted += g[k].f.inserted;
        f->mesh_bytes += g[k].f.mesh_bytes;
        f->unmet += g[k].f.unmet;
        f->refused += g[k].f.refused;
        f->iface_enc += g[k].f.iface_enc;
        f->iface_remote += g[k].f.iface_remote;
    }
    /* the merged part hides the interfaces between this rank's subdomains from the collective
     * test (they are no open edges): an encroached piece counts as a defect when one of them
     * might be such an interface (a split refused at the precision limit: rare) */
    if (D->n > 1) {
        f->iface_enc += f->iface_remote;
        f->iface_remote = 0;
    }
}

void pcdm_det_free(pcdm_part *p) {
    pcdm_det *D = p->det;
    if (!D) return;
    for (int32_t i = 0; i < D->n; i++)
        det_sub_free(D->s[i]);
    free(D->s);
    free(D->local);
    free(D->owner);
    free(D->dry);
    free(D->order);
    free(D->rep_n);
    free(D->cnt);
    free(D->rep_splits);
    free(D->mine);
    free(D->buf);
    free(D->job);
    free(D);
    p->det = NULL;
}

int32_t pcdm_det_nmesh(const pcdm_part *p) {
    return p->det ? p->det->n : 0;
}

mesh *pcdm_det_mesh(pcdm_part *p, int32_t i, int32_t *sub, const pcdm_sub_map **map) {
    *sub = p->det->s[i]->id;
    *map = &p->det->s[i]->map;
    return &p->det->s[i]->m;
}
