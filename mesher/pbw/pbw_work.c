/* pbw_work.c: PBW's local work, rt_run's work step -- a bounded batch of items, encroached
 * subsegments first, then retries, then bad triangles in the queue's order: a bad triangle's
 * Steiner point (or a subsegment's split point: dyadic, or a concentric shell at a small
 * input corner) starts a cavity; a cavity that stays on this rank is decided at once, one that
 * reaches other ranks becomes a task (at most --inflight at a time; ENDGAME_FACTOR times as
 * many once the rank's own bad triangles and splits are done, if many such cavities wait: the
 * end game).  Refusals below the
 * length floor and the Steiner limit stop a rank's refinement (issue 10).  Env PBW_DEBUG=DIR:
 * each rank writes its queue and lock state to DIR/pbw.RANK.log every 2 s. */
#include "pbw/pbw_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int limit_reached(pbw_ctx *C) {
    if (C->steiner_limit >= 0 && C->res.steiner >= C->steiner_limit) {
        C->stopped = 1;
        C->res.limit_hit = 1;
        return 1;
    }
    return 0;
}

/* A split's description, kept by its starter for commit_all. */
typedef struct split_desc {
    int32_t sseg, child_lev;
    int64_t ku, kv; /* dyadic index of the half at it->gu / at it->gv */
} split_desc;

/* Starts the cavity of point p seeded at local triangle t (sd: a split of t's edge
 * it->gu - it->gv, which is opened; NULL: a Steiner point for bad triangle t). */
static void start_cavity(pbw_ctx *C, pbw_item *it, const double p[2], int32_t t,
                         const split_desc *sd) {
    pbw_cav *c = pbw_cav_new(C);
    c->h.key = ((int64_t)C->rank << 40) | (++C->seq);
    if (!it->stamp) it->stamp = ((++C->lclock) << 24) | ((uint64_t)C->rank << 8) | STAMP_FRESH;
    c->h.stamp = it->stamp;
    c->h.origin = C->rank;
    c->h.kind = sd ? K_SPLIT : K_INSERT;
    c->h.status = ST_OK;
    c->h.p[0] = p[0];
    c->h.p[1] = p[1];
    if (sd) {
        c->h.su = it->gu;
        c->h.sv = it->gv;
        c->h.sseg = sd->sseg;
        c->h.schild_lev = sd->child_lev;
        c->h.sk_u = sd->ku;
        c->h.sk_v = sd->kv;
    }
    c->it = *it;
    int32_t hi = pbw_hold_new(C, c->h.key, c->h.stamp, C->rank);
    pbw_part_add(c, C->rank);
    pbw_push_seed(C, c, mkref(C->rank, t), NOREF, NOREF, -1, -1, SEED_START);
    double t0 = rt_wtime();
    int r = pbw_process(C, c, hi, 1);
    C->hd[hi].t_spent += rt_wtime() - t0;
    if (r == PR_DIE) {
        int64_t holder = c->h.holder;
        pbw_release_local(C, hi, 1);
        C->res.undone_local++;
        pbw_defer_item(C, &c->it, W_HOLD, holder, 1);
        pbw_cav_free(c);
        return;
    }
    if (c->ntodo == 0) {
        pbw_finish(C, c);
        pbw_cav_free(c);
        return;
    }
    if (C->phase1) {
        pbw_release_local(C, hi, 0);
        C->res.postponed++;
        pbw_iv_push(&C->phase2, &c->it);
        pbw_cav_free(c);
        return;
    }
    if (C->inflight >= C->max_inflight) {
        /* it waits in the slot queue, taken again only when a slot is free (re-expanding
         * every waiting cavity after each event cost as much as the refinement) */
        pbw_release_local(C, hi, 0);
        pbw_iv_push(&C->slotq, &c->it);
        pbw_cav_free(c);
        return;
    }
    C->hd[hi].distributed = 1;
    C->inflight++;
    rt_task_spawn(pbw_cav_task, c);
}

/* Split point of the subsegment (la, lb) of segment s with dyadic name (lev, k), as refine.c
 * computes it (shells of unit 1 around a small corner: PBW has no interface segments); fills
 * the halves' names into c-independent outputs.  Returns 0, -1 if the point is unusable
 * (precision exhausted), -2 if it is below the length floor (a refusal). */
static int split_point(pbw_ctx *C, int32_t la, int32_t lb, int32_t s, int32_t lev, int64_t k,
                       double p[2], int32_t *child_lev, int64_t *ka, int64_t *kb) {
    const double *pu = VX(C, la), *pv = VX(C, lb);
    const double *A = VX(C, C->seg[2 * s]), *B = VX(C, C->seg[2 * s + 1]);
    int cu = pbw_is_corner_gid(C, C->vgid[la]), cv = pbw_is_corner_gid(C, C->vgid[lb]);
    *child_lev = -1;
    *ka = *kb = 0;
    if (cu != cv) {
        mesh_rules_shell_point(cu ? pu : pv, cu ? pv : pu, 1.0, p);
    } else if (lev >= 0 && lev < 52) {
        mesh_dyadic_point(A, B, lev, k, p);
        *child_lev = lev + 1;
        /* the half nearer the segment's first endpoint gets index 2k */
        double dx = B[0] - A[0], dy = B[1] - A[1];
        int a_first = (pu[0] - p[0]) * dx + (pu[1] - p[1]) * dy < 0;
        *ka = a_first ? 2 * k : 2 * k + 1;
        *kb = a_first ? 2 * k + 1 : 2 * k;
    } else {
        geom_midpoint(pu, pv, p);
    }
    if (geom_working_point(p) != 0 || (p[0] == pu[0] && p[1] == pu[1]) ||
        (p[0] == pv[0] && p[1] == pv[1]))
        return -1;
    if (pbw_below_floor(C, p, la) || pbw_below_floor(C, p, lb)) return -2;
    /* a region too thin for its length (rules.h): splits this rank made of segment s, counted
     * when the point is chosen (an undone cavity counts too: a bound, not a statistic) */
    if (C->pieces[s] >= MESH_RULES_MAX_PIECES - 1) return -2;
    C->pieces[s]++;
    return 0;
}

static void process_item(pbw_ctx *C, pbw_item *it) {
    int32_t t = it->t;
    if (!alive(C, t)) {
        if (it->kind == IT_SPLIT) pbw_notify(C, it->notify, it->ticket, 0);
        return;
    }
    if (it->kind == IT_SPLIT) {
        int j = pbw_find_edge(C, t, it->gu, it->gv);
        if (j < 0) j = pbw_find_edge(C, t, it->gv, it->gu);
        size_t e = 3 * (size_t)t + (size_t)(j < 0 ? 0 : j);
        const mesh_subseg *ss = j >= 0 ? SSEG(C, e) : NULL;
        if (!ss) { /* already split, or the triangle changed */
            pbw_notify(C, it->notify, it->ticket, 0);
            return;
        }
        if (LK(C, t) >= 0) {
            pbw_defer_item(C, it, W_HOLD, C->hd[LK(C, t)].key, 1);
            return;
        }
        int32_t la = C->M.tv[e], lb = C->M.tv[3 * (size_t)t + (size_t)((j + 1) % 3)],
                lo = C->M.tv[3 * (size_t)t + (size_t)((j + 2) % 3)];
        if (!it->forced && (!mesh_rules_encroaches(&C->R, VX(C, la), VX(C, lb), VX(C, lo)) ||
                            pbw_edge_forced(C, lo, la) || pbw_edge_forced(C, lo, lb))) {
            pbw_notify(C, it->notify, it->ticket, 0);
            return;
        }
        if (limit_reached(C)) { /* the requester drops what waited for this split */
            pbw_notify(C, it->notify, it->ticket, 1);
            return;
        }
        double p[2];
        int32_t clev;
        int64_t ka, kb;
        mesh_subseg sg = *ss; /* the record may move once the split is made */
        int sp = split_point(C, la, lb, sg.seg, sg.level, sg.k, p, &clev, &ka, &kb);
        /* too far off the line for the triangle beside it (this side's apex decides here;
         * the far side's owner decides with its apex when the expansion crosses: CYC_OFF_LINE) */
        if (sp == 0 &&
            mesh_rules_off_line_fan(VX(C, la), VX(C, lb), p,
                                    VX(C, C->M.tv[3 * (size_t)t + (size_t)((j + 2) % 3)]), NULL))
            sp = -1;
        /* on the domain's boundary: the area the rounded split points may move (rules.h;
         * spent when the split starts: a retried split spends again, which only refuses
         * sooner) */
        if (sp == 0 && TN(C, e) == NOREF &&
            mesh_rules_drift_spend(VX(C, la), VX(C, lb), p,
                                   VX(C, C->M.tv[3 * (size_t)t + (size_t)((j + 2) % 3)]),
                                   C->area_budget, &C->area_spent))
            sp = -2;
        if (sp != 0) {
            if (sp == -2)
                pbw_refuse(C);
            else
                C->res.failed++;
            pbw_notify(C, it->notify, it->ticket, 1);
            return;
        }
        if (!C->no_fast && pbw_local_split(C, p, t, j, sg.seg, clev, ka, kb)) {
            pbw_notify(C, it->notify, it->ticket, 0);
            return;
        }
        it->gu = C->vgid[la];
        it->gv = C->vgid[lb];
        split_desc sd = {sg.seg, clev, ka, kb};
        start_cavity(C, it, p, t, &sd);
        return;
    }
    /* a bad triangle */
    if (LK(C, t) >= 0) {
        pbw_defer_item(C, it, W_HOLD, C->hd[LK(C, t)].key, 1);
        return;
    }
    int sh = 0;
    int why = pbw_quality(C, t, NULL, &sh);
    if (!why) return;
    const int32_t *tv = C->M.tv + 3 * (size_t)t;
    if (why == MESH_BAD_ANGLE && pbw_edge_forced(C, tv[sh], tv[(sh + 1) % 3])) {
        /* skinny but not too large, and the small angle is forced by the input */
        C->res.skipped_small++;
        return;
    }
    double p[2];
    if (pbw_steiner_point(C, t, sh, p) != 0) {
        C->res.failed++;
        return;
    }
    /* the new vertex is at least the circumradius away from every vertex (empty circle): its
     * distance to t's vertices is the length of the shortest edge it creates */
    if (pbw_below_floor(C, p, tv[0]) || pbw_below_floor(C, p, tv[1]) ||
        pbw_below_floor(C, p, tv[2])) {
        pbw_refuse(C);
        return;
    }
    if (limit_reached(C)) return;
    if (!C->no_fast) {
        if (pbw_local_insert(C, p, t)) return;
        /* the cavity reaches another rank (or a lock) while every slot is taken: it waits for
         * a slot without the general path's expansion, which start_cavity would only undo
         * (measured: at 8 ranks on the lake at 1M, 5-11K such expansions per rank, a fifth of
         * a rank's instructions, and 5x more cavities that died on a lock) */
        if (C->fast_fenced && !C->phase1 && C->inflight >= C->max_inflight) {
            pbw_iv_push(&C->slotq, it);
            return;
        }
    }
    start_cavity(C, it, p, t, NULL);
}

static int next_item(pbw_ctx *C, pbw_item *it) {
    if (pbw_iv_pop(&C->splitq, it)) return 1;
    if (pbw_iv_pop(&C->retryq, it)) return 1;
    if (C->inflight < C->max_inflight && pbw_iv_pop(&C->slotq, it)) return 1;
    int32_t t = pbw_pop_bad(C);
    if (t < 0) return 0;
    memset(it, 0, sizeof *it);
    it->kind = IT_BAD;
    it->t = t;
    it->notify = -1;
    it->ticket = -1;
    return 1;
}

static int has_items(pbw_ctx *C) {
    if (!pbw_iv_empty(&C->splitq) || !pbw_iv_empty(&C->retryq)) return 1;
    if (C->inflight < C->max_inflight && !pbw_iv_empty(&C->slotq)) return 1;
    return pbw_bad_left(C);
}

/* A stopped rank drops its work; whoever waits for one of its splits is told the split was
 * refused (so it drops that work too, and nothing waits forever). */
static void drop_all_items(pbw_ctx *C) {
    ivec d = C->deferred;
    memset(&C->deferred, 0, sizeof C->deferred);
    pbw_item it;
    while (next_item(C, &it))
        if (it.kind == IT_SPLIT) pbw_notify(C, it.notify, it.ticket, 1);
    while (pbw_iv_pop(&C->slotq, &it))
        if (it.kind == IT_SPLIT) pbw_notify(C, it.notify, it.ticket, 1);
    while (pbw_iv_pop(&d, &it))
        if (it.kind == IT_SPLIT) pbw_notify(C, it.notify, it.ticket, 1);
    pbw_iv_free(&d);
}

/* rt_run's local work step: a bounded number of cavities, splits first, then retries, then
 * bad triangles worst first.  Deferred items come back only after an event (a handler or a
 * task ran), as the runtime's termination contract requires. */
static void debug_report(pbw_ctx *C) {
    if (C->dbg_on == 0) {
        const char *dir = getenv("PBW_DEBUG");
        C->dbg_on = 2;
        if (dir) {
            char path[512];
            snprintf(path, sizeof path, "%s/pbw.%d.log", dir, C->rank);
            C->dbg_f = fopen(path, "w");
            if (C->dbg_f) C->dbg_on = 1;
        }
    }
    if (C->dbg_on != 1) return;
    FILE *f = C->dbg_f;
    double t = rt_wtime();
    if (t - C->dbg_last < 2.0) return;
    C->dbg_last = t;
    int32_t nh = 0;
    for (int32_t i = 0; i < C->nhd; i++)
        nh += C->hd[i].active;
    fprintf(f,
            "pbw[%d]: live=%d inflight=%d parked=%d holds=%d deferred=%d retry=%d split=%d "
            "waiters=%d slotq=%d undone=%lld/%lld ins=%lld\n",
            C->rank, C->nlive, C->inflight, C->npk, nh, C->deferred.n - C->deferred.head,
            C->retryq.n - C->retryq.head, C->splitq.n - C->splitq.head, C->nwt,
            C->slotq.n - C->slotq.head, (long long)C->res.undone_local,
            (long long)C->res.undone_remote, (long long)C->res.inserted);
    for (int32_t i = 0; i < C->npk; i++)
        fprintf(f, "pbw[%d]:   parked %llx stamp %llx waits for %llx\n", C->rank,
                (unsigned long long)C->pk[i]->h.key, (unsigned long long)C->pk[i]->h.stamp,
                (unsigned long long)C->pk[i]->h.holder);
    for (int32_t i = 0; i < C->nhd; i++)
        if (C->hd[i].active)
            fprintf(f, "pbw[%d]:   hold %llx stamp %llx origin %d n=%d\n", C->rank,
                    (unsigned long long)C->hd[i].key, (unsigned long long)C->hd[i].stamp,
                    C->hd[i].origin, C->hd[i].n);
    fflush(f);
}

int pbw_work(void *ctx) {
    pbw_ctx *C = ctx;
    int did = 0;
    debug_report(C);
    if (C->endgame == 0 && !pbw_bad_left(C) && pbw_iv_empty(&C->splitq)) {
        /* the end game: with many cavities waiting for a slot, more slots (pbw.c, MESSAGES) */
        C->endgame = C->slotq.n - C->slotq.head >= ENDGAME_MIN_WAITING ? 1 : 2;
        if (C->endgame == 1) {
            C->max_inflight *= ENDGAME_FACTOR;
            pbw_iv_shuffle(&C->slotq, (uint64_t)C->rank + 1);
        }
    }
    for (int32_t n = 0; n < C->poll_every && !C->stopped; n++) {
        pbw_item it;
        if (!next_item(C, &it)) break;
        did = 1;
        process_item(C, &it);
    }
    if (C->stopped) {
        drop_all_items(C);
        return did ? RT_WORK_BUSY : RT_WORK_IDLE;
    }
    return did || has_items(C) ? RT_WORK_BUSY : RT_WORK_IDLE;
}
