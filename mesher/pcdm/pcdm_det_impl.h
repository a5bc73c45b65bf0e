/* pcdm_det_impl.h: the state of the deterministic rounds, shared by pcdm_det.c (the rounds) and
 * pcdm_move.c (dynamic load balancing: whole subdomains moving between ranks); private to
 * mesher/pcdm.
 *
 * A rank holds a set of subdomains (det_sub, each its own mesh), kept in ascending subdomain
 * order; with --balance dynamic the set changes while rt_run runs: a subdomain leaves (the
 * victim's "pcdm_steal" handler) and arrives (the thief's "pcdm_move" handler).  det_sub records
 * are heap objects that never move in memory while held (the mesh hooks point at them).
 * Ownership: D->s[i] belongs to D; a subdomain that left is freed at once.
 */
#ifndef PCDM_DET_IMPL_H
#define PCDM_DET_IMPL_H

#include "base/gate.h"
#include "pcdm/pcdm_impl.h"

enum { DET_WINDOW = 3, DET_MAX_PAYLOAD = 1 << 28 };

/* "pcdm_round" payload: this header, then n pcdm_split_msg. */
typedef struct det_round_hdr {
    int32_t dst;   /* receiving subdomain */
    int32_t src;   /* sending subdomain */
    int32_t round; /* the sender's round */
    int32_t n;     /* splits that follow */
} det_round_hdr;
_Static_assert(sizeof(det_round_hdr) == 16, "det_round_hdr must be 16 bytes, no padding");

typedef struct det_list {
    pcdm_split_msg *v;
    int32_t n, cap;
} det_list;

typedef struct det_sub {
    int32_t id; /* subdomain number in the decomposition */
    mesh m;
    pcdm_sub_map map; /* m's vertices and segments in d->g (pcdm_build_sub) */
    int32_t nnb;
    int32_t *nb;    /* neighbouring subdomains, ascending */
    det_list *out;  /* per neighbour: this round's splits for it */
    det_list in[2]; /* by round parity: splits received for the next round */
    int32_t got[2]; /* by round parity: neighbours heard from */
    int32_t done;   /* rounds completed */
    int64_t splits; /* splits sent in the current round */
    int moved;      /* 1: arrived by migration (never moves again) */
    double cpu;     /* CPU seconds refining it on this rank */
    pcdm_det *D;    /* back pointer (hook context) */
    /* with threads: 1 while a worker runs its round (the worker alone touches the mesh, the
     * output lists and the input slot of the round; the main thread leaves it alone) */
    int running;
    int32_t result;                               /* the worker's mesh_refine result */
    int64_t consumed, sdone, signored, snotfound; /* the worker's counts, added up on return */
} det_sub;

struct pcdm_det {
    pcdm_part *p;
    int32_t n, cap; /* held subdomains */
    det_sub **s;    /* ascending subdomain number */
    int32_t *local; /* per subdomain of the decomposition: index into s, or -1 */
    int32_t *owner; /* per subdomain: where this rank sends its lists (d->sub_owner, then
                     * where it moved: the thief's "pcdm_where", or the victim's own record) */
    int32_t cur;    /* index of the subdomain being refined, or -1 */
    mesh_quality q; /* the bounds of pcdm_det_refine (for subdomains that arrive later) */
    int q_set;      /* q is set: pcdm_det_refine began */
    /* per round: subdomain completions reported by all ranks and their splits; this rank's
     * completions and splits not reported yet */
    int32_t *rep_n, *cnt;
    int64_t *rep_splits, *mine;
    int32_t rep_cap;
    int32_t known; /* rounds 0..known-1 completed by every subdomain */
    int32_t stop;  /* the first round with no split anywhere, or -1 */
    int32_t nbuf;  /* scratch for outgoing RSRs */
    unsigned char *buf;
    /* dynamic load balancing (pcdm_move.c) */
    int balance;    /* 1: --balance dynamic */
    int steal_out;  /* a steal request is in flight */
    int home_route; /* test-only (PCDM_TEST_HOME_ROUTE=1): lists always go to a subdomain's
                     * home rank (d->sub_owner), which forwards them; no owner notices */
    int32_t *order; /* the other ranks, in the order a thief asks them */
    int32_t norder;
    int32_t victim;    /* index into order of the next rank to ask */
    uint8_t *dry;      /* per rank: answered that it has nothing to give (final, see pcdm_move.c) */
    double cpu0;       /* det_cpu() when the refinement began */
    double wdone;      /* sub_weight of the subdomains whose round 0 ran here ... */
    double cdone;      /* ... and its CPU seconds: this rank's speed (pcdm_move.c) */
    int64_t listed;    /* split entries put into lists for other subdomains (sent) */
    int64_t delivered; /* split entries that reached their subdomain's input lists */
    int64_t consumed;  /* split entries taken from input lists by start_round */
    /* threads (p->threads > 1): rounds run as the runtime's threaded handler "pcdm_refine";
     * job[sub] is the record a worker takes (written before the request, never moved) */
    int threads;
    int32_t nrunning;
    det_sub **job;
    mesh_gate gate;    /* the host's CPU gate (gate.h): held while refining, one thread only */
    int32_t fault_sub; /* test-only (PCDM_TEST_WORKER_FAULT=SUB): the worker that takes
                        * subdomain SUB's first round stops the job as a broken invariant in
                        * the kernel would (MESH_BUG); -1: off */
};

/* pcdm_det.c, for pcdm_move.c. */
/* Local.  A new record for subdomain sub with its coarse mesh (pcdm_build_mesh), neighbours and
 * hooks; with D->q set (after pcdm_det_refine began) its bounds too.  NULL with err on failure. */
det_sub *det_sub_new(pcdm_det *D, int32_t sub, char *err, size_t errlen);
void det_sub_free(det_sub *s);
/* Local.  Adds s to the held set (ascending order; D->local and D->cur follow), or removes and
 * returns the held subdomain sub (never the current one). */
void det_hold(pcdm_det *D, det_sub *s);
det_sub *det_release(pcdm_det *D, int32_t sub);
/* Local.  CPU seconds of the calling thread. */
double det_cpu(void);
/* Local.  Reports the rounds every held subdomain has completed (round bookkeeping). */
void det_report_rounds(pcdm_det *D);
/* Local.  A round list for a subdomain held here arrives; a copy is kept. */
void det_deliver(pcdm_det *D, const det_round_hdr *h, const pcdm_split_msg *v);

/* pcdm_move.c. */
/* Local, SPMD: registers "pcdm_steal", "pcdm_move", "pcdm_where" (pcdm_det_register). */
int det_move_register(void);
void det_move_begin(pcdm_det *D); /* before rt_run: balancing state */
void det_move_end(pcdm_det *D);   /* after rt_run */
/* Local, from det_work when this rank has nothing ready: asks a victim for a subdomain.
 * Returns 1 if it sent a request (the work step did something), else 0. */
int det_move_steal(pcdm_det *D);

#endif
