/* pbw_impl.h: what the files of PBW share (internal to mesher/pbw/): the packed (rank, slot)
 * references, the wire formats of the RSRs (plain structs, no pointers), the local state (work
 * items, holds, cavities) and the context of one pbw_mesh call, pbw_ctx -- passed to every
 * function, never a file-level global -- and the functions one file offers the others, by file.
 * All functions are Local (they run on the rank's one MPI thread, inside rt_run's work step,
 * a handler or a task).
 */
#ifndef PBW_IMPL_H
#define PBW_IMPL_H

#include "pbw/pbw.h"

#include "base/base.h"
#include "geom/geom.h"
#include "rt.h"
#include "seq/kernel.h"
#include "seq/mesh.h"
#include "seq/rules.h"

#include <float.h>
#include <stdint.h>
#include <stdio.h>

/* ---- references, kinds, limits ---------------------------------------------------------- */

#define NOREF ((int64_t)-1)

static inline int64_t mkref(int r, int32_t i) {
    return ((int64_t)r << 32) | (int64_t)(uint32_t)i;
}

static inline int ref_rank(int64_t r) {
    return (int)(r >> 32);
}

static inline int32_t ref_idx(int64_t r) {
    return (int32_t)(uint32_t)(r & 0xffffffff);
}

/* ROLE_TOMB: a dead triangle that keeps its vertices and, across each ghost edge (an edge whose
 * remote neighbour was not locked, see GHOSTS in pbw.c), the link to the triangle that replaced
 * it there; it is never reused, so a stale link from another rank to it can be forwarded. */
/* The key a cavity rejected for encroachment waits for, one WAKE per split it asked for: its
 * own key with bit 62 set (keys use bits 0..61).  Not the key itself: a WAKE naming the key
 * means "that cavity released here", sent to the cavities that died on it, and when both
 * waited for the same key a release woke the rejected cavity before its splits were done; it
 * retried at once, locked the subsegment's triangle again and deferred the split it waited
 * for, again and again (10^4 - 10^6 RSRs, 1 run in 15 under CPU contention). */
static inline int64_t split_ticket(int64_t key) {
    return key | ((int64_t)1 << 62);
}

enum { ROLE_NONE = 0, ROLE_MEMBER = 1, ROLE_HALO = 2, ROLE_RES = 3, ROLE_TOMB = 4 };

enum { SEED_START = 0, SEED_NORMAL = 1, SEED_HALO = 2, SEED_OPEN = 3 };

enum { K_INSERT = 0, K_SPLIT = 1 };

enum { ST_OK = 0, ST_DIE = 1 };

enum { BF_BEYOND = 1, BF_ENC = 2 };

enum { PR_DONE = 0, PR_DIE = 1, PR_PARK = 2 };

/* pbw_whdr.cycle: CYC_TWICE, a member was reached twice (the cavity encloses a vertex);
 * CYC_OFF_LINE, the split point lies too far off its subsegment for the triangle on the far
 * side (mesh_rules_off_line_fan with that triangle's apex, decided by its owner when the expansion
 * crosses the subsegment; the starter decided its own side before starting): a rounded
 * midpoint off the line of a segment a few ulps from a sliver's apex, or beside a triangle
 * obtuse at an end of the subsegment, breaks the Delaunay property of the new fan. */
enum { CYC_TWICE = 1, CYC_OFF_LINE = 2 };

enum { IT_BAD = 0, IT_SPLIT = 1 };

#define NBUCKET MESH_RULES_NBUCKET

#define MAX_INFLIGHT 2 /* --inflight's default (see MESSAGES in pbw.c) */

/* The end game (see MESSAGES in pbw.c): once a rank has no bad triangle and no split of its own
 * left, only cavities that reach other ranks remain (the slot queue); if at least
 * ENDGAME_MIN_WAITING of them wait, they are shuffled and it keeps up to ENDGAME_FACTOR times
 * --inflight of them in flight from then on. */
#define ENDGAME_FACTOR 8
#define ENDGAME_MIN_WAITING 512

/* Work items per work step (between two services of RSRs): --poll's default.  Each service is
 * an MPI progress call, which on shared cores (Open MPI yields the core when it finds nothing)
 * lets another rank run and evicts this one's cache.  Measured (lake -q 20.7, 10M triangles, 8
 * ranks on 2 cores, alternating runs): cpu_max_s 0.73-0.81 at 64, 0.61-0.73 at 256, 0.57-0.64
 * at 1024, 0.61-0.62 at 4096, with 15% fewer RSRs than at 64 and undo unchanged (0.01-0.04%);
 * at the paper's size (43K triangles, 8 ranks) the RSRs and undo did not change. */
#define WORK_BATCH 1024

#define MAXMSG (1u << 28)

#define PBW_CAV_POOL 16 /* freed cavity states kept for reuse */

/* ---- wire formats (every handler payload is a plain struct or a header + arrays) -------- */

typedef struct pbw_seed { /* visit triangle target, reached from member `from` across ga->gb */
    int64_t target, from, ga, gb;
    int64_t back; /* the triangle `from` was reached from (NOREF: none): a stale link resolved
                   * to it is the edge the expansion came in through */
    int32_t mode;
    int32_t reg; /* input region of member `from` (-1: none, or no regions) */
} pbw_seed;
_Static_assert(sizeof(pbw_seed) == 48, "pbw_seed layout");

typedef struct pbw_bnd { /* cavity boundary edge ga->gb (cavity on its left) */
    int64_t ga, gb;
    int64_t out;    /* triangle on the other side, or NOREF */
    int64_t newref; /* slot reserved for the new triangle (ga, gb, p) */
    int64_t inref;  /* the member triangle on this edge */
    int64_t ck;     /* constraint: dyadic index */
    int32_t cseg;   /* constraint: original segment, -1 if not a constraint edge */
    int32_t clev;   /* constraint: dyadic level, -1 if not dyadic */
    int32_t flags;  /* BF_* */
    int32_t reg;    /* input region of the member on this edge (the new triangle's) */
    int64_t oapex;  /* vertex id of out's apex (the new triangle's ghost across ga-gb), or -1 */
} pbw_bnd;
_Static_assert(sizeof(pbw_bnd) == 72, "pbw_bnd layout");

typedef struct pbw_whdr { /* head of EXPAND and REPLY payloads */
    int64_t key;          /* (starter rank << 40) | attempt sequence: unique per attempt */
    uint64_t stamp;       /* priority (Lamport << 16 | rank); smaller = older */
    int64_t su, sv;       /* split: the subsegment's vertex ids (else -1) */
    int64_t holder;       /* DIE: key of the cavity holding the contested triangle */
    double p[2];          /* the new point */
    int32_t kind, status, origin, nparts, nbnd, nseed;
    int32_t died_at;    /* DIE: the rank where the conflict was found */
    int32_t cycle;      /* CYC_* bits: the cavity fails (a member reached twice; a split point off
                         * its line for the far side's triangle) */
    int64_t sk_u, sk_v; /* split: dyadic index of the half at su / at sv */
    int32_t sseg, schild_lev; /* split: segment, level of the halves (-1: not dyadic) */
} pbw_whdr;
_Static_assert(sizeof(pbw_whdr) == 112, "pbw_whdr layout");

typedef struct pbw_release_msg {
    int64_t key;
    int32_t undo, pad;
} pbw_release_msg;

typedef struct pbw_split_msg {
    int64_t gu, gv; /* the subsegment */
    int64_t ticket; /* wake key for the requester */
    uint64_t stamp; /* priority: just older than the requesting cavity */
    int32_t t, notify;
} pbw_split_msg;
_Static_assert(sizeof(pbw_split_msg) == 40, "pbw_split_msg layout");

typedef struct pbw_wake_msg {
    int64_t key;     /* the released cavity, or a split ticket */
    int32_t refused; /* split ticket: the split was refused (length floor, precision) */
    int32_t pad;
} pbw_wake_msg;
_Static_assert(sizeof(pbw_wake_msg) == 16, "pbw_wake_msg layout");

typedef struct pbw_commit_hdr {
    int64_t key, pgid;
    double p[2];
    int32_t pvseg, n;
} pbw_commit_hdr;
_Static_assert(sizeof(pbw_commit_hdr) == 40, "pbw_commit_hdr layout");

typedef struct pbw_newtri {
    int64_t g[3];  /* vertex ids a, b, p (counter-clockwise) */
    int64_t nb[3]; /* neighbours across a-b, b-p, p-a */
    int64_t ck[3];
    int32_t cseg[3], clev[3];
    int32_t slot, reg; /* reg: input region (-1: none) */
    int64_t ap[3];     /* vertex id of the apex of nb[j] (a ghost if nb[j] is remote), or -1 */
    int64_t in;        /* the member on edge a-b (its owner tombstones it if nb[0] is remote) */
} pbw_newtri;
_Static_assert(sizeof(pbw_newtri) == 136, "pbw_newtri layout");

/* ---- local state and the context -------------------------------------------------------- */

typedef struct pbw_ctx pbw_ctx;

typedef struct pbw_con { /* an edge whose neighbour is on another rank (tn = -2 - record) */
    int64_t nb;          /* the neighbour reference (free record: the next free one) */
    int32_t gx;          /* ghost: vertex slot of the remote neighbour's apex, or -1 */
    int32_t e;           /* the edge (tn[e] = -2 - record); -1: a free record */
} pbw_con;

typedef struct pbw_item { /* a unit of local work */
    int64_t gu, gv;       /* split: the subsegment */
    int64_t ticket;       /* split: key to wake the requester with */
    int64_t wait_key;     /* deferred: the key it waits for */
    uint64_t stamp;       /* priority kept across retries (0: not yet assigned) */
    int32_t kind, t;      /* IT_*, local triangle slot */
    int32_t notify;       /* split: rank to wake when done (-1 none) */
    int32_t forced;       /* split: 0 = only if the apex still encroaches */
    int32_t wait_kind;    /* deferred: W_* */
    int32_t wait_count;   /* deferred W_WAKE: wakes still expected */
    int32_t refused;      /* deferred W_WAKE: a split it waits for was refused: drop it */
} pbw_item;

/* What a deferred item waits for: the release of a local lock holder (W_HOLD), or a WAKE with
 * its key (W_WAKE: the holder released on the rank where the cavity died, or a split it asked
 * for is done).  (A cavity waiting for a slot to go remote waits in C->slotq.) */
enum { W_HOLD = 1, W_WAKE = 2 };

typedef struct ivec {
    pbw_item *a;
    int32_t n, cap, head;
} ivec;

typedef struct pbw_hold { /* one cavity's locks on this rank */
    int64_t key;
    uint64_t stamp;
    int32_t origin, active, distributed;
    int32_t *slots, n, cap;
    double t_spent; /* expansion time spent here (-> RT_TIME_UNDO if released after conflict) */
} pbw_hold;

typedef struct pbw_cav { /* a cavity's travelling state, at its starter or parked */
    pbw_whdr h;
    int32_t *parts, np, pcap;
    pbw_bnd *b;
    int32_t nb, bcap;
    pbw_seed *todo;
    int32_t ntodo, tcap;
    pbw_seed *stk;
    int32_t nstk, scap;
    /* starter only */
    pbw_item it;
    int phase;
    int woken; /* a WAKE for die_holder arrived before the task ran */
    int64_t die_holder;
    void *reply; /* the chain's answer: a cavity state (REPLY) or this rank's commit */
    uint32_t replylen;
    int decided; /* the answer is a COMMIT: the chain's last rank decided (DECIDE, pbw.c) */
    /* parked only */
    int src;
    rt_token tok;
    pbw_ctx *C; /* the mesher it belongs to (for its task) */
} pbw_cav;

typedef struct pbw_waiter {
    int64_t key;
    int32_t rank, pad;
} pbw_waiter;

typedef struct pbw_qstack { /* one bucket of bad triangles: a stack of slots (LIFO) */
    int32_t *t;
    int32_t n, cap;
} pbw_qstack;

struct pbw_ctx {
    int rank, size;
    int hid[PBW_RSR_NKINDS];
    /* the local mesh: the shared kernel's (seq/mesh.h) vertices xy, vseg, vtri (slot v), triangle
     * slots tv, tn (edge codes), tf (constraint bits; bits 5..7, MESH_FENCE: the slot's role,
     * ROLE and pbw_role_set), the free list, regions treg, the subsegment table (constraint
     * names, by vertex pair) and the cavity scratch of the local fast path; tn below -1 is an
     * edge whose neighbour is on another rank: record -2 - tn in con (use TN, GX, pbw_tn_set,
     * pbw_gx_set).  Only the store's functions below write it. */
    mesh M;
    int64_t *vgid; /* per vertex slot: its global id */
    int32_t vgcap;
    int32_t *vh; /* hash of the vertices other ranks made (pbw_vt_find) */
    uint32_t vhcap;
    int32_t nvh;   /* vertices in vh */
    int32_t ninit; /* initial vertices: id i is slot i on every rank */
    int32_t *own;  /* own[n]: slot of the n-th vertex this rank made (-1: none yet) */
    int64_t nown, owncap;
    int64_t nvown;
    int32_t nlive; /* live triangles (not reserved, not tombstones) */
    pbw_con *con;  /* records of the edges whose neighbour is on another rank (few) */
    int32_t ncon, concap, confree; /* records used; capacity; free list head (-1: none) */
    int32_t *lkk, *lkv; /* the locks: slot -> hold index, open addressing (LK, pbw_lk_set); a
                         * locked slot's role is never ROLE_NONE, so LK of an unlocked live slot
                         * costs no lookup (4 bytes per triangle saved: few are locked at once) */
    uint32_t lkcap, lkn;
    int32_t nregion;
    double *reg_attr, *reg_area; /* per region: attribute, area bound in working units (0) */
    /* input (seg .. corner: the CDT's arrays, which M owns) */
    int32_t ninput, nseg;
    int32_t *seg, *smarker, *in_vmarker, *inc_off, *inc_seg; /* M's arrays (M owns them) */
    uint8_t *corner;
    int has_corners;
    /* quality: the shared rules (seq/rules.h) and the input facts they need */
    mesh_rules R;
    mesh_rules_input I;
    double floor2;      /* squared length floor (mesh_rules_length_floor2) */
    double area_budget; /* this rank's share of mesh_rules_area_drift of the domain */
    double area_spent;  /* ... moved by its boundary splits, signed (mesh_rules_drift_spend) */
    int32_t *pieces;    /* per segment: splits this rank made (MESH_RULES_MAX_PIECES) */
    uint8_t *gside;     /* per rank r: 1 if this rank keeps the ghosts towards r (pbw_ghosts.c) */
    int64_t unresolved_budget; /* refusals this rank accepts before it gives up */
    int64_t steiner_limit;
    int stopped;
    int32_t poll_every; /* work items per work step (--poll; default WORK_BATCH) */
    /* queues */
    pbw_qstack q[NBUCKET]; /* per bucket: a stack of slots (pbw_push_bad) */
    int32_t cursor;        /* no bucket below it holds an entry */
    int32_t qhi; /* no bucket above it holds an entry (the scans for the next entry stop there) */
    ivec splitq, retryq, deferred, phase2;
    ivec slotq; /* cavities that reach other ranks, waiting for a slot (max_inflight) */
    int phase1;
    /* cavities */
    pbw_hold *hd;
    int32_t nhd, hdcap;
    pbw_waiter *wt;
    int32_t nwt, wtcap;
    pbw_cav **pk;
    int32_t npk, pkcap;
    pbw_cav *cavpool[PBW_CAV_POOL]; /* freed cavity states kept for reuse (pbw_cav_new) */
    int32_t ncavpool;
    int cavpool_closed; /* pbw_cav_pool_free ran: pbw_cav_free frees */
    pbw_cav **dy;       /* tasks whose DIE reply arrived, not yet run */
    int32_t ndy, dycap;
    int draining;
    int inflight;
    int max_inflight; /* distributed cavities in flight at most (--inflight; MAX_INFLIGHT) */
    int endgame;      /* 0; once the end game began 1 (max_inflight raised: pbw_work.c) or 2 (few
                       * cavities waited: not raised); -1 never (--phases) */
    int fast_fenced;  /* pbw_local_insert declined at another rank's triangle or a role */
    uint64_t lclock;
    int64_t seq;
    pbw_result res;
    int no_fast;  /* env PBW_NO_FAST_PATH=1: every cavity takes the general path (tests) */
    int32_t *gen; /* slots of the triangles general commits created (pbw_check.c) */
    int64_t ngen, gencap;
    /* PBW_DEBUG */
    int dbg_on; /* 0: not looked yet, 1: on, 2: off */
    double dbg_last;
    FILE *dbg_f;
};

static inline const double *VX(const pbw_ctx *C, int32_t v) {
    return C->M.xy + 2 * (size_t)v;
}

/* Slot s's role (ROLE_*: tf bits 5..7, the kernel's MESH_FENCE: a cavity of the local fast path
 * never touches a slot with a role). */
static inline int ROLE(const pbw_ctx *C, int32_t s) {
    return C->M.tf[s] >> 5;
}

static inline void pbw_role_set(pbw_ctx *C, int32_t s, int role) {
    C->M.tf[s] = (uint8_t)((C->M.tf[s] & ~MESH_FENCE) | ((unsigned)role << 5));
}

/* Edge e's record in con, or -1. */
static inline int32_t REC(const pbw_ctx *C, size_t e) {
    return C->M.tn[e] <= -2 ? -2 - C->M.tn[e] : -1;
}

/* Edge e's neighbour: a (rank, slot) reference, or NOREF. */
static inline int64_t TN(const pbw_ctx *C, size_t e) {
    int32_t v = C->M.tn[e];
    return v >= 0 ? mkref(C->rank, v / 3) : v == -1 ? NOREF : C->con[-2 - v].nb;
}

/* Edge e's subsegment record (mesh_subseg: segment, dyadic level and index), NULL if e is not
 * a constraint edge. */
static inline const mesh_subseg *SSEG(const pbw_ctx *C, size_t e) {
    if (!mesh_edge_constrained(&C->M, (int32_t)e)) return NULL;
    const mesh_subseg *ss = mesh_subseg_of_edge(&C->M, (int32_t)e);
    if (!ss) MESH_BUG("constraint edge %zu without its subsegment record", e);
    return ss;
}

/* Edge e's ghost: the vertex slot of its remote neighbour's apex, or -1. */
static inline int32_t GX(const pbw_ctx *C, size_t e) {
    return C->M.tn[e] <= -2 ? C->con[-2 - C->M.tn[e]].gx : -1;
}

/* The hold index that locks slot s, or -1. */
int32_t pbw_lk_find(const pbw_ctx *C, int32_t s);

static inline int32_t LK(const pbw_ctx *C, int32_t s) {
    return ROLE(C, s) == ROLE_NONE ? -1 : pbw_lk_find(C, s);
}

/* Locks slot s for hold hi (hi < 0: unlocks it).  Set the role after locking, clear it after
 * unlocking (a locked slot's role is never ROLE_NONE). */
void pbw_lk_set(pbw_ctx *C, int32_t s, int32_t hi);

static inline int64_t TG(pbw_ctx *C, int32_t t, int j) { /* global id of vertex j of slot t */
    return C->vgid[C->M.tv[3 * (size_t)t + j]];
}

static inline int alive(pbw_ctx *C, int32_t t) {
    return t >= 0 && t < C->M.nt && C->M.tv[3 * (size_t)t] >= 0 && ROLE(C, t) != ROLE_TOMB;
}

/* 1 iff this rank may decide the conflict of remote neighbour n on its ghost and never lock
 * it: the pair's ghost side does (see GHOSTS in pbw.c, pbw_ghosts.c). */
static inline int ghost_side(pbw_ctx *C, int64_t n) {
    return n != NOREF && C->gside[ref_rank(n)];
}

/* Priority order: stamp, then key (unique), smaller = older. */
static inline int older(uint64_t sa, int64_t ka, uint64_t sb, int64_t kb) {
    return sa < sb || (sa == sb && ka < kb);
}

#define STAMP_FRESH 128u

static inline uint64_t stamp_derived(uint64_t s) { /* just older than s, same clock and rank */
    uint64_t pri = s & 0xff;
    return (s & ~(uint64_t)0xff) | (pri > 0 ? pri - 1 : 0);
}

typedef struct pbw_setup_opts {
    double min_angle, max_area;
    int64_t max_steiner;
    int offcenter;   /* 0: --circumcenters */
    int regions;     /* 1: label the input's regions (-A or --region-areas) */
    int region_area; /* 1: and honour their area bounds */
} pbw_setup_opts;

/* ---- pbw_store.c: the store ------------------------------------------------------------- */

/* The slot of the vertex with global id gid, or -1 if this rank does not know it. */
int32_t pbw_vt_find(pbw_ctx *C, int64_t gid);

/* Rebuilds the vertex hash table with cap (a power of two > 2 * C->M.nv) buckets. */
void pbw_vt_rehash(pbw_ctx *C, uint32_t cap);

/* The slot of vertex gid, added at (x, y) on segment vseg (-1: none) if it is new. */
int32_t pbw_vt_add(pbw_ctx *C, int64_t gid, double x, double y, int32_t vseg);

/* A free triangle slot (mesh_tri_new; dead: tv MESH_DEAD, no links, unlocked, role none). */
int32_t pbw_slot_alloc(pbw_ctx *C);

/* Sets edge e's neighbour (a reference or NOREF): a local one is the edge code of the same edge
 * in that triangle, which must already hold its vertices; a remote one gets a record (con),
 * released when the neighbour is local or none again.  Its constraint (seg < 0: none): e's tf
 * bit and the subsegment record of its vertex pair (added if the pair has none; records of
 * split subsegments stay: their pair never forms an edge again).  Its ghost apex (gx < 0:
 * none; only on an edge with a remote neighbour, set after it). */
void pbw_tn_set(pbw_ctx *C, size_t e, int64_t ref);
void pbw_con_set(pbw_ctx *C, size_t e, int32_t seg, int32_t lev, int64_t k);
/* A tombstone's forward link: edge e (of a member that dies as a tombstone) now names local
 * slot y, the new triangle on the same side of the same edge (same direction, not reversed). */
void pbw_forward_set(pbw_ctx *C, size_t e, int32_t y);
void pbw_gx_set(pbw_ctx *C, size_t e, int32_t gx);

/* Kills slot s (its records and lock go) and puts it on the kernel's free list. */
void pbw_slot_free(pbw_ctx *C, int32_t s);

/* Edge j of t going from vertex id ga to gb, or -1. */
int pbw_find_edge(pbw_ctx *C, int32_t t, int64_t ga, int64_t gb);

/* MESH_BAD_ANGLE / MESH_BAD_AREA bits (mesh_rules_bad), 0: good.  *bucket (may be NULL): queue
 * priority (mesh_rules_bucket: shortest edge first, as refine.c).  *sh (may be NULL): shortest
 * edge j.  Inline, as refine.c's quality: it runs for every new triangle. */
MESH_RULES_INLINE int pbw_quality(const pbw_ctx *C, int32_t t, int *bucket, int *sh) {
    const int32_t *tv = C->M.tv + 3 * (size_t)t;
    const double *p[3] = {VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2])};
    double l2;
    double rb = C->M.treg && C->M.treg[t] >= 0 ? C->reg_area[C->M.treg[t]] : 0;
    int res = mesh_rules_bad_bound(&C->R, mesh_rules_area_bound(C->R.max_area, rb), p, sh, &l2);
    if (res && bucket) *bucket = mesh_rules_bucket(l2);
    return res;
}

/* Queues triangle t if it is bad (its bucket: pbw_quality). */
void pbw_push_bad(pbw_ctx *C, int32_t t);

/* 1 iff a bucket may hold an entry; moves the cursor to the first such bucket.  The scan
 * stops at qhi, and an empty queue resets both, so a rank whose queue empties again and again
 * (waiting for remote cavities, each commit queueing a few triangles) does not walk the 4096
 * empty buckets every time (measured: 8 ranks, lake 1M: 146M instructions in pbw_pop_bad
 * summed over the ranks, 12M on 1 rank). */
static inline int pbw_bad_left(pbw_ctx *C) {
    while (C->cursor <= C->qhi && C->q[C->cursor].n == 0)
        C->cursor++;
    if (C->cursor <= C->qhi) return 1;
    C->cursor = NBUCKET + 1;
    C->qhi = -1;
    return 0;
}

/* The next queued triangle (worst bucket first), or -1; entries whose slot was rewritten since
 * they were queued (MESH_QUEUED cleared) are skipped.  The triangle may still have changed
 * role or become good: re-check it. */
int32_t pbw_pop_bad(pbw_ctx *C);

/* Frees the bad-triangle queue (empty afterwards); its bytes (capacities). */
void pbw_queue_free(pbw_ctx *C);
size_t pbw_queue_bytes(const pbw_ctx *C);

/* 1 iff vertex id g is an input vertex at a corner below 60 degrees. */
int pbw_is_corner_gid(pbw_ctx *C, int64_t g);

/* The shared forced-angle rule (mesh_rules_edge_forced) for the shortest edge lu-lv (vertex
 * slots): an input vertex is named by its id, a Steiner vertex by the segment it lies on. */
int pbw_edge_forced(pbw_ctx *C, int32_t lu, int32_t lv);

/* 1 iff a new vertex at p would make an edge to vertex slot a shorter than the floor. */
int pbw_below_floor(pbw_ctx *C, const double p[2], int32_t a);

/* Counts a refusal (a split or Steiner point below the length floor); past the budget this
 * rank's refinement is diverging (an angle bound beyond reach, or features below the precision
 * of the coordinates) and it stops, as refine.c does (MESH_REFINE_UNRESOLVED). */
void pbw_refuse(pbw_ctx *C);

/* Steiner point of bad triangle t (mesh_rules_steiner, on the working grid).  0, or -1. */
int pbw_steiner_point(pbw_ctx *C, int32_t t, int sh, double out[2]);

/* ---- pbw_items.c: work items and locks -------------------------------------------------- */

/* A FIFO of work items: push a copy of *it; pop the oldest into *it (0 if empty); shuffle the
 * waiting items (a permutation fixed by seed); empty?; free (q is then empty and usable). */
void pbw_iv_push(ivec *q, const pbw_item *it);
int pbw_iv_pop(ivec *q, pbw_item *it);
void pbw_iv_shuffle(ivec *q, uint64_t seed);
int pbw_iv_empty(const ivec *q);
void pbw_iv_free(ivec *q);

/* Parks a failed item until what it waits for happens (see W_*). */
void pbw_defer_item(pbw_ctx *C, const pbw_item *it, int kind, int64_t key, int32_t count);

/* A WAKE for key arrived (refused: the split it announces was refused): deferred items
 * waiting for it go back to work (or are dropped), dying tasks waiting for it are marked. */
void pbw_wake_key(pbw_ctx *C, int64_t key, int refused);

/* Wakes whoever waits for key on rank r (r < 0: nobody); refused: see deferred_release. */
void pbw_notify(pbw_ctx *C, int32_t r, int64_t key, int refused);

/* The active hold of cavity key on this rank, or -1. */
int32_t pbw_hold_find(pbw_ctx *C, int64_t key);

/* A new active hold (no locks yet) for cavity key with priority stamp, started by origin. */
int32_t pbw_hold_new(pbw_ctx *C, int64_t key, uint64_t stamp, int32_t origin);

/* Locks slot s for hold hi (if not yet) with role (ROLE_*). */
void pbw_lock_slot(pbw_ctx *C, int32_t s, int32_t hi, int role);

/* Remembers that a cavity of rank `rank` died on cavity key here: it gets a WAKE when key's
 * hold ends. */
void pbw_waiter_add(pbw_ctx *C, int64_t key, int32_t rank);

/* Frees hold hi (its locks must be gone) and wakes whoever died on it. */
void pbw_hold_end(pbw_ctx *C, int32_t hi);

/* Releases every lock of hold hi on this rank (undo: a lock conflict: the expansion time
 * goes to RT_TIME_UNDO). */
void pbw_release_local(pbw_ctx *C, int32_t hi, int undo);

/* ---- pbw_cavity.c: cavities ------------------------------------------------------------- */

/* A new empty cavity state of C (free with pbw_cav_free; NULL is fine there): both recycle
 * states through C's pool; pbw_cav_pool_free empties it for good (pbw_ctx_free). */
pbw_cav *pbw_cav_new(pbw_ctx *C);
void pbw_cav_free(pbw_cav *c);
void pbw_cav_pool_free(pbw_ctx *C);

/* Adds rank r to c's participants (once) / removes it. */
void pbw_part_add(pbw_cav *c, int32_t r);
void pbw_part_remove(pbw_cav *c, int32_t r);

/* A triangle to visit: on this rank's stack, or pending for its owner (SEED_* mode). */
void pbw_push_seed(pbw_ctx *C, pbw_cav *c, int64_t target, int64_t from, int64_t back, int64_t ga,
                   int64_t gb, int mode);
/* Serialises c (full: with boundary edges and seeds). */
void *pbw_cav_pack(pbw_cav *c, int full, uint32_t *len);

/* Replaces c's header and arrays by the serialised state data. */
void pbw_cav_unpack_into(pbw_cav *c, const void *data, uint32_t len);

/* Processes the local seeds of c.  initial: the starter's first step (nothing sent yet). */
int pbw_process(pbw_ctx *C, pbw_cav *c, int32_t hi, int initial);

/* New work from triangle t: queued if bad; each of its subsegments its apex encroaches
 * goes to the split queue. */
void pbw_check_new_triangle(pbw_ctx *C, int32_t t);

/* Applies this rank's part of a commit: members die, reserved slots become the new triangles,
 * halos get their link to the new triangle, everything is unlocked. */
void pbw_apply_commit(pbw_ctx *C, const pbw_commit_hdr *ch, const pbw_newtri *nt);

/* Builds the new triangles (one per boundary edge) and commits them on every participant:
 * here at once, elsewhere by a COMMIT; the origin's by rt_reply(to_origin) when to_origin is
 * not NULL (the chain's last rank decides, DECIDE in pbw.c).  Returns 0, or -1 if the
 * boundary is not a proper fan (then nothing was sent or written). */
int pbw_commit_all(pbw_ctx *C, pbw_cav *c, const rt_msg *to_origin);

/* What the complete state of cavity c decides: OUT_DIE (the expansion met a younger lock),
 * OUT_REJECT (p encroaches or lies beyond subsegments: split them instead), OUT_FAIL (not
 * star-shaped, or a member reached twice), OUT_COMMIT. */
enum { OUT_COMMIT = 0, OUT_DIE = 1, OUT_REJECT = 2, OUT_FAIL = 3 };
int pbw_outcome(const pbw_cav *c);

/* The starter's decision once the whole cavity is known (or the expansion died). */
void pbw_finish(pbw_ctx *C, pbw_cav *c);

/* The starter's account of committed cavity c (remote: it had other participants): counts,
 * and the WAKE a split owes its requester. */
void pbw_committed(pbw_ctx *C, pbw_cav *c, int remote);

/* A stale link (a seed across ga->gb naming tombstone slot x): the live triangle now on that
 * edge, following the tombstones' forward links, or -1 if x is not a tombstone. */
int32_t pbw_resolve_tomb(pbw_ctx *C, int32_t x, int64_t ga, int64_t gb);

/* ---- pbw_local.c: the local fast path ------------------------------------------------- */

/* Inserts Steiner point p of bad triangle t at once if its cavity lies on this rank, touches
 * no lock, ghost or tombstone, is star-shaped, has no vertex inside and p encroaches no
 * subsegment (the new vertex, the fan, the counts, the new work).  Returns 1 if it did, 0 if
 * the general path must decide (nothing was written); then C->fast_fenced is 1 iff the cavity
 * reached another rank's triangle or a triangle with a role (lock, reservation, tombstone). */
int pbw_local_insert(pbw_ctx *C, const double p[2], int32_t t);

/* Splits the subsegment on edge j of t at p (its segment sseg; the halves' dyadic level clev,
 * -1: none; ka the index of the half at the edge's first vertex, kb at its second) at once if
 * the cavity opened across it lies on this rank, touches no lock, ghost or tombstone, is
 * star-shaped, has no vertex inside, and p passes the far side's off-line test.  Returns 1 if
 * it did (the new vertex, the fan, the halves' records, the counts, the new work; the caller
 * wakes whoever asked for the split), 0 if the general path must decide (nothing written). */
int pbw_local_split(pbw_ctx *C, const double p[2], int32_t t, int j, int32_t sseg, int32_t clev,
                    int64_t ka, int64_t kb);

/* ---- pbw_proto.c: the protocol ---------------------------------------------------------- */

/* The task of a distributed cavity: send the expansion, wait in the blocking queue for the
 * chain's reply, decide. */
rt_task_status pbw_cav_task(rt_task *t, void *state);

/* ---- pbw_work.c: local work ------------------------------------------------------------- */

/* rt_run's work step (ctx: the pbw_ctx): RT_WORK_BUSY or RT_WORK_IDLE. */
int pbw_work(void *ctx);

/* ---- pbw_setup.c: set-up and end -------------------------------------------------------- */

/* Builds the initial CDT of in (or takes d->cdt's contents, the same CDT, when the
 * decomposition kept it, leaving d->cdt empty), its length floor and this rank's share by the
 * subdomains of d; queues the initial work.  Returns 0, or -1 with a message in err. */
int pbw_setup(pbw_ctx *C, const pbw_setup_opts *so, const pslg *in, const pcdm_decomp *d, char *err,
              size_t errlen);
/* Test-only fault (env PBW_TEST_BREAK_IFACE=R): rank R loses the first triangle it owns that
 * has a neighbour on another rank, as if a commit had been lost at a rank boundary, so the
 * result no longer matches across that boundary.  The always-on end check (par_output's
 * interface check) must then fail every rank; tests/t_pbw.sh shows it does. */
void pbw_test_fault(pbw_ctx *C);

/* The end: this rank's triangles as a mesh_flat (local numbering of the vertices they use); *topen
 * (topen may be NULL): their open edges (pbw_result.topen).  The same pass is the end check of
 * the bounds (as mesh_count_unmet): every triangle this rank owns that is outside them, except a
 * small angle forced by the input (a corner vertex, or the shared forced-angle rule on its
 * shortest edge), into C->res.unmet and C->res.forced, and the rank boundary's statistics
 * C->res.iface_edges and iface_len.  Nothing may be locked.  It dismantles the store on the way
 * (the links, constraints, locks and queue are freed before the copy is made, the vertex table
 * once copied, and the triangles are renumbered in place into the flat's array): only
 * pbw_mesh_bytes, C->nlive and pbw_ctx_free may follow. */
int pbw_to_flat(pbw_ctx *C, mesh_flat *f, uint8_t **topen);

/* Frees C and everything it owns. */
void pbw_ctx_free(pbw_ctx *C);

/* Bytes of this rank's mesh arrays (capacities). */
size_t pbw_mesh_bytes(pbw_ctx *C);

/* ---- pbw_ghosts.c: the ghost side of each pair of ranks ---------------------------------- */

/* Allocates C->gside: per rank, whether this rank keeps the ghosts towards it; computed alike on
 * every rank from the initial mesh m0 and its triangles' owners own (slot -> rank). */
void pbw_ghost_sides(pbw_ctx *C, const mesh *m0, const int32_t *own);

/* ---- pbw_check.c: the end check ------------------------------------------------------- */

/* Records that a general commit made slot (pbw_apply_commit). */
void pbw_gen_note(pbw_ctx *C, int32_t slot);

/* Collective.  The end check of the Delaunay property where the protocol decided it: every
 * unconstrained edge of a triangle a general commit made, and every unconstrained rank
 * boundary edge (the apexes exchanged), exact incircle.  Returns this rank's defects (0: none);
 * msg (len bytes) describes the first; *secs: the seconds it worked (outside the collectives). */
int64_t pbw_check_delaunay(pbw_ctx *C, char *msg, size_t len, double *secs);

/* Test-only fault (env PBW_TEST_BREAK_DELAUNAY=R): rank R flips an edge between two triangles
 * general commits made (both unlocked, every other edge of theirs local, the quadrilateral
 * strictly convex and not cocircular), as if a cavity had been committed wrong; the end check
 * must fail every rank (tests/t_pbw.sh). */
void pbw_test_break_delaunay(pbw_ctx *C);

/* ---- pbw_proto.c: the bridge to the handlers ------------------------------------------ */

/* Points the handlers at C (and fills C->hid) for one pbw_mesh call; at most one at a time. */
void pbw_attach(pbw_ctx *C);

/* Ends pbw_attach. */
void pbw_detach(void);

#endif
