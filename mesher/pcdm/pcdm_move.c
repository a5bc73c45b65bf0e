/* pcdm_move.c: dynamic load balancing for the deterministic rounds (./pcdm --balance dynamic):
 * whole subdomains move from busy ranks to idle ones, in the spirit of the Mobile Object Layer
 * the paper cites [CH97] and its successor PREMA (the paper's future work: "dynamic load
 * balancing").
 *
 * Work stealing.  A rank with nothing ready (det_work) asks one victim at a time ("pcdm_steal"),
 * the ranks the decomposition gave the most expected work first (ties in turn from rank + 1:
 * with --imbalance the thieves go to rank 0 at once instead of through a chain of refusals).  The
 * victim gives the lightest (sub_weight: expected work) subdomain it holds that has not begun
 * (round 0 not started, not being refined, never moved before), provided it keeps work for itself
 * (it is refining one, or holds another unstarted one) and the move shortens the pair's finish
 * forecast in CPU seconds: the thief's CPU so far plus the subdomain's weight at the thief's speed
 * must be below the victim's CPU so far plus its remaining round-0 weight at its own speed (speed:
 * weight per CPU second of the round-0 work each rank has done).  CPU, not wall time: on an
 * oversubscribed machine a rank the OS does not run looks slow by the clock, and thieves that
 * judged by the clock took two or three subdomains from it (60% above the mean at 8 ranks on 2
 * shared cores).  Otherwise the victim says no and the thief never asks it again ("dry").  That is
 * final, near enough: a rank's set of movable subdomains only shrinks (a subdomain that began or
 * moved once never moves) and the forecasts only move against the thief (its CPU grows, the
 * victim's remaining work shrinks), so each thief sends at most P - 1 refusals and the balancing
 * traffic is bounded (idle ranks do not spin).
 *
 * What moves.  An unstarted subdomain is its coarse mesh plus the round-0 lists its neighbours
 * already sent it.  The coarse mesh is a pure function of the decomposition every rank holds
 * (pcdm_build_mesh, the same bits everywhere), so it travels by name: "pcdm_move" carries the
 * subdomain number, how many neighbours were heard from and their splits, and the thief rebuilds
 * the mesh bit for bit (move_s counts that time).  Shipping the mesh's arrays instead would not
 * give back the same vertex and triangle numbering, hence not the same refinement: rebuilding
 * keeps --deterministic's promise (the mesh does not depend on where a subdomain is refined).
 *
 * Lists follow their subdomain.  The victim records the new owner at once, so its own lists go
 * to the thief; the thief tells every other rank ("pcdm_where") once it holds the subdomain, so
 * a list sent directly to the thief always finds it there; a list that reached the victim
 * first (sent before its sender heard) is forwarded (pcdm_det.c round_handler; MPI keeps the
 * victim's "pcdm_move" ahead of its forwarded lists).  After rt_run every split listed for a
 * subdomain must have been delivered and consumed exactly once: summed over the ranks and
 * checked (a loss aborts with a message).  Test knob: PCDM_TEST_HOME_ROUTE=1 sends every list to
 * its subdomain's home rank (the decomposition's owner: a subdomain moves once at most, so the
 * home knows where it is), which forwards it, and no owner notices go out; t_balance.sh uses it
 * to make lists arrive while and after their subdomain moves.
 *
 * Termination.  A request, a subdomain and an owner notice in flight are RSRs, counted by the
 * runtime's detector like any other, so rt_run cannot end while a subdomain moves.  The rounds
 * count subdomain completions (pcdm_det.c), so a subdomain that changes rank between its own
 * round and its rank's report is counted once.
 */
#include "pcdm/pcdm_det_impl.h"

#include "base/base.h"

#include "rt.h"

#include <stdlib.h>
#include <string.h>

/* "pcdm_steal" payload: the thief asks for one unstarted subdomain. */
typedef struct move_ask {
    int32_t thief;
    int32_t pad;
    double cpu;  /* the thief's CPU seconds of refinement so far (it is idle: all its work) */
    double rate; /* its expected work (sub_weight) per CPU second, 0: not known */
} move_ask;
_Static_assert(sizeof(move_ask) == 24, "move_ask must be 24 bytes, no padding");

/* "pcdm_move" payload: this header, then nin pcdm_split_msg (the round-0 splits received for
 * it); sub < 0: a refusal. */
typedef struct move_hdr {
    int32_t sub; /* the subdomain, or -1: nothing to give */
    int32_t nin; /* splits that follow */
    int32_t got; /* neighbours whose round-0 list arrived */
    int32_t pad;
} move_hdr;
_Static_assert(sizeof(move_hdr) == 16, "move_hdr must be 16 bytes, no padding");

/* "pcdm_where" payload: subdomain sub is now held by rank owner. */
typedef struct move_where {
    int32_t sub;
    int32_t owner;
} move_where;
_Static_assert(sizeof(move_where) == 8, "move_where must be 8 bytes, no padding");

typedef struct move_slot {
    int steal, move, where;
    pcdm_det *active;
} move_slot;

static move_slot mslot = {-1, -1, -1, NULL};

static pcdm_det *active(const rt_msg *msg) {
    if (!mslot.active) MESH_BUG("balancing message from rank %d outside refinement", msg->src);
    return mslot.active;
}

/* The victim's CPU-time forecast: would giving subdomain index give to the thief shorten the
 * pair's finish?  Without a known speed: yes. */
static int worth_moving(const pcdm_det *D, int32_t give, const move_ask *a) {
    const double *w = D->p->d->sub_weight;
    double rate = D->cdone > 0 ? D->wdone / D->cdone : a->rate;
    double rate_t = a->rate > 0 ? a->rate : rate;
    if (!(rate > 0) || !(rate_t > 0)) return 1;
    double left = 0; /* expected work of this rank's round-0 subdomains, the current one's
                      * progress deducted */
    for (int32_t i = 0; i < D->n; i++) {
        const det_sub *s = D->s[i];
        if (s->done > 0) continue;
        double x = w[s->id] - (i == D->cur ? s->cpu * rate : 0);
        left += x > 0 ? x : 0;
    }
    double mine = det_cpu() - D->cpu0 + left / rate; /* this rank's forecast finish */
    double theirs = a->cpu + w[D->s[give]->id] / rate_t;
    return theirs < mine;
}

/* The victim: gives an unstarted subdomain, or refuses. */
static void steal_handler(const rt_msg *msg, void *arg) {
    pcdm_det *D = active(msg);
    const double *w = D->p->d->sub_weight;
    move_ask a;
    memcpy(&a, msg->data, sizeof a);
    int32_t give = -1, unstarted = 0;
    if (D->balance && D->stop < 0)
        for (int32_t i = D->n - 1; i >= 0; i--) {
            const det_sub *s = D->s[i];
            if (i == D->cur || s->running || s->done > 0) continue;
            unstarted++;
            if (!s->moved && (give < 0 || w[s->id] < w[D->s[give]->id])) give = i;
        }
    if (give >= 0 && D->cur < 0 && D->nrunning == 0 && unstarted < 2)
        give = -1; /* keep work for this rank */
    if (give >= 0 && !worth_moving(D, give, &a)) give = -1;
    if (give < 0) {
        move_hdr h = {-1, 0, 0, 0};
        rt_rsr(msg->src, mslot.move, &h, (uint32_t)sizeof h);
        return;
    }
    double t0 = rt_wtime();
    det_sub *s = det_release(D, D->s[give]->id);
    if (s->in[1].n || s->got[1] || s->splits)
        MESH_BUG("unstarted subdomain %d holds round-1 state", s->id);
    move_hdr h = {s->id, s->in[0].n, s->got[0], 0};
    size_t len = sizeof h + (size_t)h.nin * sizeof(pcdm_split_msg);
    if (len > DET_MAX_PAYLOAD) MESH_BUG("subdomain %d: %d splits to move", s->id, h.nin);
    if ((size_t)D->nbuf < len) {
        D->buf = mesh_xrealloc(D->buf, len, 1);
        D->nbuf = (int32_t)len;
    }
    memcpy(D->buf, &h, sizeof h);
    if (h.nin) memcpy(D->buf + sizeof h, s->in[0].v, (size_t)h.nin * sizeof(pcdm_split_msg));
    rt_rsr(msg->src, mslot.move, D->buf, (uint32_t)len);
    D->owner[s->id] = msg->src; /* this rank's lists for it go there from now on */
    D->p->moved_bytes += len;
    det_sub_free(s);
    det_report_rounds(D); /* the rounds it held back may be complete now */
    D->p->move_s += rt_wtime() - t0;
}

/* The thief: rebuilds the subdomain and tells every other rank where it is. */
static void move_handler(const rt_msg *msg, void *arg) {
    pcdm_det *D = active(msg);
    move_hdr h;
    if (msg->len < sizeof h) MESH_BUG("short subdomain message from rank %d", msg->src);
    memcpy(&h, msg->data, sizeof h);
    D->steal_out = 0;
    if (h.sub < 0) {
        D->dry[msg->src] = 1;
        return;
    }
    if (h.sub >= D->p->d->nsub || h.nin < 0 ||
        msg->len != sizeof h + (size_t)h.nin * sizeof(pcdm_split_msg))
        MESH_BUG("subdomain message from rank %d: subdomain %d, %d splits in %u bytes", msg->src,
                 h.sub, h.nin, (unsigned)msg->len);
    double t0 = rt_wtime();
    char err[512];
    det_sub *s = det_sub_new(D, h.sub, err, sizeof err);
    if (!s) MESH_BUG("subdomain %d does not rebuild on rank %d: %s", h.sub, D->p->rank, err);
    s->moved = 1;
    if (h.nin) {
        s->in[0].v = mesh_xmalloc((size_t)h.nin, sizeof(pcdm_split_msg));
        memcpy(s->in[0].v, (const unsigned char *)msg->data + sizeof h,
               (size_t)h.nin * sizeof(pcdm_split_msg));
        s->in[0].n = s->in[0].cap = h.nin;
    }
    s->got[0] = h.got;
    det_hold(D, s);
    D->owner[h.sub] = D->p->rank;
    D->p->migrations++;
    if (!D->home_route) {
        move_where w = {h.sub, D->p->rank};
        for (int q = 0; q < rt_size(); q++)
            if (q != D->p->rank && q != msg->src) rt_rsr(q, mslot.where, &w, (uint32_t)sizeof w);
    }
    D->p->move_s += rt_wtime() - t0;
}

static void where_handler(const rt_msg *msg, void *arg) {
    pcdm_det *D = active(msg);
    move_where w;
    memcpy(&w, msg->data, sizeof w);
    if (w.sub < 0 || w.sub >= D->p->d->nsub || w.owner < 0 || w.owner >= rt_size() ||
        D->local[w.sub] >= 0)
        MESH_BUG("owner notice from rank %d: subdomain %d at rank %d", msg->src, w.sub, w.owner);
    D->owner[w.sub] = w.owner;
}

int det_move_register(void) {
    int a = rt_handler_register("pcdm_steal", steal_handler, &mslot, RT_NONTHREADED,
                                (uint32_t)sizeof(move_ask));
    if (a < 0) return a;
    int b = rt_handler_register("pcdm_move", move_handler, &mslot, RT_NONTHREADED | RT_VARSIZE,
                                (uint32_t)DET_MAX_PAYLOAD);
    if (b < 0) return b;
    int c = rt_handler_register("pcdm_where", where_handler, &mslot, RT_NONTHREADED,
                                (uint32_t)sizeof(move_where));
    if (c < 0) return c;
    mslot.steal = a;
    mslot.move = b;
    mslot.where = c;
    return 0;
}

void det_move_begin(pcdm_det *D) {
    const pcdm_decomp *d = D->p->d;
    int size = rt_size(), me = D->p->rank;
    free(D->dry);
    free(D->order);
    D->dry = mesh_xcalloc((size_t)size + 1, 1);
    /* whom to ask, most expected work first (the decomposition's owners: every rank computes the
     * same loads), ties in ring order from rank + 1 */
    double *load = mesh_xcalloc((size_t)size + 1, sizeof(double));
    for (int32_t s = 0; s < d->nsub; s++)
        load[d->sub_owner[s]] += d->sub_weight[s];
    D->order = mesh_xmalloc((size_t)size + 1, sizeof(int32_t));
    D->norder = 0;
    for (int k = 1; k < size; k++) {
        int32_t v = (me + k) % size, j = D->norder++;
        for (; j > 0 && load[D->order[j - 1]] < load[v]; j--)
            D->order[j] = D->order[j - 1];
        D->order[j] = v;
    }
    free(load);
    D->victim = 0;
    D->steal_out = 0;
    const char *hr = getenv("PCDM_TEST_HOME_ROUTE");
    D->home_route = hr && atoi(hr) != 0;
    mslot.active = D;
}

int det_move_steal(pcdm_det *D) {
    if (!D->balance || D->steal_out) return 0;
    for (; D->victim < D->norder; D->victim++) { /* the same one again until it refuses */
        int v = D->order[D->victim];
        if (D->dry[v]) continue;
        move_ask a = {D->p->rank, 0, det_cpu() - D->cpu0, D->cdone > 0 ? D->wdone / D->cdone : 0};
        rt_rsr(v, mslot.steal, &a, (uint32_t)sizeof a);
        D->steal_out = 1;
        return 1;
    }
    return 0;
}

void det_move_end(pcdm_det *D) {
    mslot.active = NULL;
    if (D->steal_out) MESH_BUG("rank %d: a steal request outlived the run", D->p->rank);
    /* every split listed for a subdomain reached it (wherever it went) and was applied or
     * found a duplicate: no list lost in a move */
    int64_t mine[3] = {D->listed, D->delivered, D->consumed}, all[3];
    MESH_MPI(MPI_Allreduce(mine, all, 3, MPI_INT64_T, MPI_SUM, rt_app_comm()));
    if (all[0] != all[1] || all[1] != all[2])
        MESH_BUG("split lists: %lld splits listed, %lld delivered, %lld applied", (long long)all[0],
                 (long long)all[1], (long long)all[2]);
}
