/* pbw_proto.c: PBW's remote service requests (TR-97-17 section 2, Table 1): the handlers
 * (EXPAND, REPLY, RELEASE, COMMIT, SPLIT, WAKE), the chains of remote expansion (a cavity
 * grows on a rank, then is forwarded to the next rank with pending seeds, the last one replies
 * to the waiting task), the parking of an older cavity behind a younger lock (wait-die), and
 * the task that waits for a distributed cavity's reply in the runtime's blocking queue.  The
 * handlers are registered once per process; they reach the running mesher's context through
 * pbw_attach, the only state kept outside a context. */
#include "pbw/pbw_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The handler table and the handlers' way to the context.  Handlers are registered once per
 * process, before any pbw_mesh (SPMD, rt_handler_register), with &pbw_active as their
 * argument; pbw_mesh points it at its context for the duration of the call (one at a time).
 * Everything else is passed the context explicitly. */
static int pbw_hid[PBW_RSR_NKINDS];

static pbw_ctx *pbw_active;

void pbw_attach(pbw_ctx *C) {
    if (pbw_active) MESH_BUG("pbw_mesh called while another pbw_mesh runs");
    pbw_active = C;
    memcpy(C->hid, pbw_hid, sizeof C->hid);
}

void pbw_detach(void) {
    pbw_active = NULL;
}

static pbw_ctx *handler_ctx(void *arg) {
    pbw_ctx *C = *(pbw_ctx *const *)arg;
    if (!C) MESH_BUG("pbw handler called outside pbw_mesh");
    return C;
}

static void drain_parked(pbw_ctx *C);

/* Continues c's expansion on this rank (it arrived by EXPAND, or a parked one resumes). */
static void chain_continue(pbw_ctx *C, pbw_cav *c, int32_t hi) {
    double t0 = rt_wtime();
    int r = pbw_process(C, c, hi, 0);
    C->hd[hi].t_spent += rt_wtime() - t0;
    if (r == PR_PARK) {
        MESH_GROW(C->pk, C->npk, C->pkcap);
        C->pk[C->npk++] = c;
        C->res.parked++;
        return;
    }
    rt_msg fm;
    memset(&fm, 0, sizeof fm);
    fm.src = c->src;
    fm.token = c->tok;
    uint32_t len;
    void *buf;
    if (r == PR_DIE) {
        int64_t holder = c->h.holder;
        pbw_release_local(C, hi, 1);
        pbw_part_remove(c, C->rank);
        if (c->h.origin != C->rank) pbw_waiter_add(C, holder, c->h.origin);
        c->h.status = ST_DIE;
        c->h.died_at = C->rank;
        buf = pbw_cav_pack(c, 0, &len);
        rt_reply(&fm, C->hid[PBW_RSR_REPLY], buf, len);
    } else if (c->ntodo > 0) {
        buf = pbw_cav_pack(c, 1, &len);
        rt_forward(&fm, ref_rank(c->todo[0].target), C->hid[PBW_RSR_EXPAND], buf, len);
    } else if (c->h.origin != C->rank && pbw_outcome(c) == OUT_COMMIT &&
               pbw_commit_all(C, c, &fm) == 0) {
        /* the last rank of the chain knows the whole cavity: it commits (DECIDE, pbw.c) */
        pbw_cav_free(c);
        return;
    } else {
        buf = pbw_cav_pack(c, 1, &len);
        rt_reply(&fm, C->hid[PBW_RSR_REPLY], buf, len);
    }
    free(buf);
    pbw_cav_free(c);
}

/* Resumes parked expansions whose blocker has released its locks here, oldest first. */
static void drain_parked(pbw_ctx *C) {
    if (C->draining) return;
    C->draining = 1;
    for (;;) {
        int32_t best = -1;
        for (int32_t i = 0; i < C->npk; i++)
            if (pbw_hold_find(C, C->pk[i]->h.holder) < 0 &&
                (best < 0 || older(C->pk[i]->h.stamp, C->pk[i]->h.key, C->pk[best]->h.stamp,
                                   C->pk[best]->h.key)))
                best = i;
        if (best < 0) break;
        pbw_cav *c = C->pk[best];
        C->pk[best] = C->pk[--C->npk];
        int32_t hi = pbw_hold_find(C, c->h.key);
        if (hi < 0) MESH_BUG("parked cavity lost its locks");
        chain_continue(C, c, hi);
    }
    C->draining = 0;
}

static void h_expand(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    pbw_cav *c = pbw_cav_new(C);
    pbw_cav_unpack_into(c, m->data, m->len);
    uint64_t ts = c->h.stamp >> 24;
    if (ts > C->lclock) C->lclock = ts;
    int32_t hi = pbw_hold_find(C, c->h.key);
    if (hi < 0) {
        hi = pbw_hold_new(C, c->h.key, c->h.stamp, c->h.origin);
        pbw_part_add(c, C->rank);
    }
    C->hd[hi].distributed = 1;
    /* seeds for this rank go to the local stack, the rest stay pending */
    int32_t k = 0;
    for (int32_t i = 0; i < c->ntodo; i++) {
        pbw_seed s = c->todo[i];
        if (ref_rank(s.target) == C->rank) {
            MESH_GROW(c->stk, c->nstk, c->scap);
            c->stk[c->nstk++] = s;
        } else {
            c->todo[k++] = s;
        }
    }
    c->ntodo = k;
    c->src = m->src;
    c->tok = m->token;
    chain_continue(C, c, hi);
    drain_parked(C);
}

/* The chain's answer m (a cavity state, or the starter's commit) kept for the waiting task. */
static pbw_cav *keep_answer(const rt_msg *m, int decided) {
    pbw_cav *c = rt_task_data(m->task);
    free(c->reply);
    c->reply = mesh_xrealloc(NULL, m->len, 1);
    memcpy(c->reply, m->data, m->len);
    c->replylen = m->len;
    c->decided = decided;
    return c;
}

static void h_reply(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    if (!m->task) MESH_BUG("cavity reply without a waiting task");
    pbw_cav *c = keep_answer(m, 0);
    pbw_whdr h;
    if (m->len < sizeof h) MESH_BUG("short cavity reply");
    memcpy(&h, m->data, sizeof h);
    if (h.status == ST_DIE && h.died_at != C->rank) {
        /* the WAKE for the holder may overtake the task's run: note it (wake_key) */
        c->die_holder = h.holder;
        c->woken = 0;
        MESH_GROW(C->dy, C->ndy, C->dycap);
        C->dy[C->ndy++] = c;
    }
}

static void h_release(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    const pbw_release_msg *r = m->data;
    int32_t hi = pbw_hold_find(C, r->key);
    if (hi >= 0) pbw_release_local(C, hi, r->undo);
    drain_parked(C);
}

static void h_commit(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    const pbw_commit_hdr *ch = m->data;
    if (m->len < sizeof *ch || m->len != sizeof *ch + (size_t)ch->n * sizeof(pbw_newtri))
        MESH_BUG("malformed commit (%u bytes)", (unsigned)m->len);
    if (m->task) { /* the starter's part, decided by the chain's last rank: its task applies it */
        keep_answer(m, 1);
        return;
    }
    pbw_apply_commit(C, ch, (const pbw_newtri *)(ch + 1));
    drain_parked(C);
}

static void h_split(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    const pbw_split_msg *s = m->data;
    pbw_item it;
    memset(&it, 0, sizeof it);
    it.kind = IT_SPLIT;
    it.t = s->t;
    it.gu = s->gu;
    it.gv = s->gv;
    it.notify = s->notify;
    it.ticket = s->ticket;
    it.stamp = s->stamp;
    it.forced = 1;
    pbw_iv_push(&C->splitq, &it);
}

static void h_wake(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    const pbw_wake_msg *w = m->data;
    pbw_wake_key(C, w->key, w->refused);
}

/* The task of a distributed cavity: send the expansion, wait in the blocking queue for the
 * chain's reply, decide. */
rt_task_status pbw_cav_task(rt_task *t, void *state) {
    pbw_cav *c = state;
    pbw_ctx *C = c->C;
    if (c->phase == 0) {
        c->phase = 1;
        uint32_t len;
        void *buf = pbw_cav_pack(c, 1, &len);
        rt_task_label(t, "cavity %llx expansion", (unsigned long long)c->h.key);
        rt_request(t, ref_rank(c->todo[0].target), C->hid[PBW_RSR_EXPAND], buf, len);
        free(buf);
        return RT_TASK_WAIT;
    }
    if (!c->reply) MESH_BUG("cavity task resumed without a reply");
    for (int32_t i = 0; i < C->ndy; i++)
        if (C->dy[i] == c) {
            C->dy[i] = C->dy[--C->ndy];
            break;
        }
    if (c->decided) {
        const pbw_commit_hdr *ch = c->reply;
        pbw_apply_commit(C, ch, (const pbw_newtri *)(ch + 1));
        pbw_committed(C, c, 1);
    } else {
        pbw_cav_unpack_into(c, c->reply, c->replylen);
        pbw_finish(C, c);
    }
    C->inflight--;
    pbw_cav_free(c);
    drain_parked(C);
    return RT_TASK_DONE;
}

int pbw_register(void) {
    static const struct {
        const char *name;
        rt_handler_fn fn;
        unsigned flags;
        uint32_t size;
    } tab[PBW_RSR_NKINDS] = {
        {"pbw_expand", h_expand, RT_NONTHREADED | RT_VARSIZE, MAXMSG},
        {"pbw_reply", h_reply, RT_NONTHREADED | RT_VARSIZE, MAXMSG},
        {"pbw_release", h_release, RT_NONTHREADED, sizeof(pbw_release_msg)},
        {"pbw_commit", h_commit, RT_NONTHREADED | RT_VARSIZE, MAXMSG},
        {"pbw_split", h_split, RT_NONTHREADED, sizeof(pbw_split_msg)},
        {"pbw_wake", h_wake, RT_NONTHREADED, sizeof(pbw_wake_msg)},
    };
    for (int k = 0; k < PBW_RSR_NKINDS; k++) {
        int id =
            rt_handler_register(tab[k].name, tab[k].fn, &pbw_active, tab[k].flags, tab[k].size);
        if (id < 0) return id;
        pbw_hid[k] = id;
    }
    return 0;
}
