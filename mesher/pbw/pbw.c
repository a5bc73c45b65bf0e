/* pbw.c: the Parallel Meshing Algorithm (TR-97-17 section 2; Chrisochoides and Sukup 1996):
 * parallel Bowyer-Watson Delaunay refinement of one distributed mesh, data-centric and
 * task-parallel, with remote cavity expansion, locking and undo.
 *
 * MESH.  Every rank builds the same CDT of the input (with an area bound, refined identically
 * on every rank by the sequential refiner to about 32 triangles per rank, and at least 16 times
 * coarser than the bound, so that every rank owns a piece) and keeps the triangles whose
 * centroid lies in one of its subdomains (the decomposition only distributes the initial mesh;
 * no artificial constraint exists).  A triangle lives in a slot of its owner; a neighbour is named
 * by a packed (rank, slot) reference.  A vertex has a global id: input vertex i is i, the n-th
 * vertex created by rank r is ((r + 1) << 32) | n.  Each rank keeps the coordinates of every
 * vertex its triangles use, so every predicate sees identical doubles on every rank.
 * Constraint edges (subsegments of input segments) carry (segment, dyadic level, index) on
 * both sides.
 *
 * CAVITY (one per Steiner point p).  The owner of a bad triangle t (or of a triangle on an
 * encroached subsegment) starts it: t is a member; every neighbour x of a member across a
 * non-constraint edge is a member iff p lies strictly in its circumcircle (exact incircle);
 * every other neighbour of a member (across a constraint, or not in conflict) is a halo
 * triangle.  Members and halos are locked by the cavity, whichever rank owns them, because a
 * commit deletes the members and rewrites one link of each halo.  A boundary edge of the
 * cavity (member | non-member, or a constraint edge, or the domain boundary) is reported by
 * the rank owning the outside triangle (or the member when there is none); that rank reserves
 * a slot for the new triangle (a, b, p) on it, so the OWNERSHIP RULE is: the new triangle on a
 * cavity boundary edge belongs to the owner of the triangle on the other side of that edge
 * (the member's owner on the domain boundary).  The reporter also evaluates, exactly, whether p
 * is strictly left of the edge (star-shapedness) and whether p encroaches a constraint edge.
 * The members must form a disk with every vertex on its boundary (their dual graph a tree):
 * a member reached a second time across a non-constraint edge means the cavity encloses a
 * vertex (p nearly on it, where the mesh is not Delaunay), and the cavity fails, as
 * mesh_cavity_collect's CAV_CYCLE (the vertex would otherwise vanish from the mesh).
 *
 * MESSAGES.  A cavity that stays on its rank is done at once, with no message.  Otherwise the
 * starter spawns a task which sends the cavity state (header, participants, boundary edges,
 * pending seeds = remote triangles to visit) as an EXPAND request to the owner of the first
 * seed; each rank locks and grows what it owns and FORWARDS the state to the next rank with
 * pending seeds (the chains A->B->C of the paper's Table 1), and the last one REPLIES to the
 * task, which sits in the blocking queue meanwhile while its rank goes on with other work.
 * The task then decides: COMMIT (one message per participant with its new triangles: links
 * are fully resolved because every reserved slot is known), or RELEASE everywhere (undo, after
 * a conflict; or reject: p encroaches a subsegment, which is then split by a SPLIT request to
 * the owner of the triangle on it; the bad triangle is retried after the split's WAKE).
 * Nothing is written until every triangle is locked, so undo is only a release of locks
 * (and the wasted expansion time, which goes to RT_TIME_UNDO).  Locks are held until the
 * owner applies the commit, so nobody follows a link that is being rewritten; a link to a slot
 * reserved by a cavity whose commit has not arrived yet finds that slot locked.
 *
 * CONFLICTS AND PROGRESS (wait-die).  Each cavity has a priority stamp (Lamport clock, rank),
 * kept across retries of the same work item; smaller = older.  When an expansion meets a
 * triangle locked by another cavity D: a cavity that has sent nothing yet (its starter's
 * first, local step) just lets go and is retried later; a distributed cavity C older than D
 * PARKS at that rank (its state waits there, holding its locks) and is resumed, oldest first,
 * the moment D's locks on that rank are released; a C younger than D DIES: it is released on
 * every rank and its work item (keeping its stamp) is deferred until the rank where it died
 * sends a WAKE naming D (D released there; a WAKE that overtakes the task is remembered), or D
 * releases on the starter's own rank.  A cavity rejected for encroachment waits for WAKEs from
 * the splits it asked for, and those splits carry a stamp just older than its own, so the
 * retried cavity can never starve the splits it depends on.
 * Progress: waits only go from older to younger cavities, so no cycle of waits (deadlock)
 * exists; the youngest cavity in any chain of waits is not waiting, so it commits or dies in
 * finite time and releases; hence the oldest cavity holding locks never dies and eventually
 * acquires every triangle it needs (a parked request is served before any newer work on that
 * rank) and finishes.  So while work remains, some cavity commits: no livelock.  Cavities
 * that stay on one rank run to completion in one step and hold nothing across steps.  No
 * rank spins: a deferred item waits for a wake (an RSR) or a local release, and the runtime's
 * termination detector sees a blocked task wherever a cavity is still in flight.
 *
 * RULES.  What is bad, the Steiner point (off-center), encroachment, the shell split point and
 * the forced small angle are seq/rules.h's, the same code ./mesh and ./pcdm run, and so is the
 * queue order (shortest edge first, last in first out inside a bucket).  As in refine.c: a
 * circumcenter (or off-center) that lies beyond or on a constraint edge of its cavity, or
 * encroaches one, is discarded and those subsegments are split; splits use the dyadic midpoint
 * of the original segment, or a concentric shell at a small input corner; skinny triangles
 * whose small angle is forced by such a corner are left alone (unless they exceed the area
 * bound).  TERMINATION (issue 10), as refine.c: no new edge shorter than the length floor of
 * the initial CDT; such a refusal drops the work item (a bad triangle whose split was refused
 * is not retried), and a rank whose refusals pass the budget stops refining; what is left
 * outside the bounds and not forced is counted at the end (pbw_result.unmet) and ./pbw fails.
 * --phases: phase 1 commits only cavities that stay on their rank, phase 2 the rest (the paper's
 * data-parallel variant, Figure 1 bottom). Env PBW_DEBUG=DIR: each rank writes its queue/lock state
 * to DIR/pbw.RANK.log every 2 s.
 */
#include "pbw/pbw.h"

#include "base/base.h"

#include "geom/geom.h"
#include "rt.h"
#include "seq/mesh.h"
#include "seq/rules.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const pbw_rsr_kind_name[PBW_RSR_NKINDS] = {"expansion", "reply", "release",
                                                       "commit",    "split", "wake"};

/* ---- references and ids ---------------------------------------------------------------- */

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

enum { ROLE_NONE = 0, ROLE_MEMBER = 1, ROLE_HALO = 2, ROLE_RES = 3 };
enum { SEED_START = 0, SEED_NORMAL = 1, SEED_HALO = 2, SEED_OPEN = 3 };
enum { K_INSERT = 0, K_SPLIT = 1 };
enum { ST_OK = 0, ST_DIE = 1 };
enum { BF_BEYOND = 1, BF_ENC = 2 };
enum { PR_DONE = 0, PR_DIE = 1, PR_PARK = 2 };
enum { IT_BAD = 0, IT_SPLIT = 1 };

#define NBUCKET MESH_RULES_NBUCKET
#define MAX_INFLIGHT 16
#define WORK_BATCH 64
#define MAXMSG (1u << 28)

/* ---- wire formats (every handler payload is a plain struct or a header + arrays) -------- */

typedef struct pbw_seed { /* visit triangle target, reached from member `from` across ga->gb */
    int64_t target, from, ga, gb;
    int32_t mode, pad;
} pbw_seed;
_Static_assert(sizeof(pbw_seed) == 40, "pbw_seed layout");

typedef struct pbw_bnd { /* cavity boundary edge ga->gb (cavity on its left) */
    int64_t ga, gb;
    int64_t out;    /* triangle on the other side, or NOREF */
    int64_t newref; /* slot reserved for the new triangle (ga, gb, p) */
    int64_t inref;  /* the member triangle on this edge */
    int64_t ck;     /* constraint: dyadic index */
    int32_t cseg;   /* constraint: original segment, -1 if not a constraint edge */
    int32_t clev;   /* constraint: dyadic level, -1 if not dyadic */
    int32_t flags;  /* BF_* */
    int32_t pad;
} pbw_bnd;
_Static_assert(sizeof(pbw_bnd) == 64, "pbw_bnd layout");

typedef struct pbw_whdr { /* head of EXPAND and REPLY payloads */
    int64_t key;          /* (starter rank << 40) | attempt sequence: unique per attempt */
    uint64_t stamp;       /* priority (Lamport << 16 | rank); smaller = older */
    int64_t su, sv;       /* split: the subsegment's vertex ids (else -1) */
    int64_t holder;       /* DIE: key of the cavity holding the contested triangle */
    double p[2];          /* the new point */
    int32_t kind, status, origin, nparts, nbnd, nseed;
    int32_t died_at; /* DIE: the rank where the conflict was found */
    int32_t cycle;   /* 1: a member was reached twice, the cavity encloses a vertex */
} pbw_whdr;
_Static_assert(sizeof(pbw_whdr) == 88, "pbw_whdr layout");

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
    int32_t slot, pad;
} pbw_newtri;
_Static_assert(sizeof(pbw_newtri) == 104, "pbw_newtri layout");

/* ---- local state ----------------------------------------------------------------------- */

typedef struct pbw_ctx pbw_ctx;

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

/* What a deferred item waits for: the release of a local lock holder (W_HOLD), a WAKE with
 * its key (W_WAKE: the holder released on the rank where the cavity died, or a split it asked
 * for is done), or any event (W_EVENT: a slot for another distributed cavity). */
enum { W_EVENT = 0, W_HOLD = 1, W_WAKE = 2 };

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
    void *reply;
    uint32_t replylen;
    int32_t sseg, schild_lev; /* split: segment, level of the halves (-1: not dyadic) */
    int64_t sk_u, sk_v;       /* split: dyadic index of the half at su / at sv */
    /* parked only */
    int src;
    rt_token tok;
    pbw_ctx *C; /* the mesher it belongs to (for its task) */
} pbw_cav;

typedef struct pbw_waiter {
    int64_t key;
    int32_t rank, pad;
} pbw_waiter;

typedef struct qent {
    int32_t t, next;
} qent;

struct pbw_ctx {
    int rank, size;
    int hid[PBW_RSR_NKINDS];
    /* vertices */
    int32_t nv, vcap;
    double *xy;
    int64_t *vgid;
    int32_t *vseg;
    int32_t *vh;
    uint32_t vhcap;
    int64_t nvown;
    /* triangles */
    int32_t nt, tcap, nlive;
    int32_t *tv; /* 3 per slot; tv[3s] < 0: dead */
    int64_t *tn; /* 3 per slot */
    int32_t *cs, *cl;
    int64_t *ck;
    int32_t *lk; /* hold index or -1 */
    uint8_t *role;
    int32_t *fre, nfree, frecap;
    /* input */
    int32_t ninput, nseg;
    int32_t *seg, *smarker, *in_vmarker, *inc_off, *inc_seg;
    uint8_t *corner;
    int has_corners;
    /* quality: the shared rules (seq/rules.h) and the input facts they need */
    mesh_rules R;
    mesh_rules_input I;
    double floor2;             /* squared length floor (mesh_rules_length_floor2) */
    int64_t unresolved_budget; /* refusals this rank accepts before it gives up */
    int64_t steiner_limit;
    int stopped;
    /* queues */
    int32_t head[NBUCKET + 1]; /* per bucket: a stack of pool entries */
    qent *pool;
    int32_t npool, poolcap, pool_free, cursor;
    ivec splitq, retryq, deferred, phase2;
    uint32_t ev_epoch, seen_epoch;
    int32_t nevent; /* deferred W_EVENT items */
    int phase1;
    /* cavities */
    pbw_hold *hd;
    int32_t nhd, hdcap;
    pbw_waiter *wt;
    int32_t nwt, wtcap;
    pbw_cav **pk;
    int32_t npk, pkcap;
    pbw_cav **dy; /* tasks whose DIE reply arrived, not yet run */
    int32_t ndy, dycap;
    int draining;
    int inflight;
    uint64_t lclock;
    int64_t seq;
    pbw_result res;
    /* PBW_DEBUG */
    int dbg_on; /* 0: not looked yet, 1: on, 2: off */
    double dbg_last;
    FILE *dbg_f;
};

/* The handler table and the handlers' way to the context.  Handlers are registered once per
 * process, before any pbw_mesh (SPMD, rt_handler_register), with &pbw_active as their
 * argument; pbw_mesh points it at its context for the duration of the call (one at a time).
 * Everything else is passed the context explicitly. */
static int pbw_hid[PBW_RSR_NKINDS];
static pbw_ctx *pbw_active;

static pbw_ctx *handler_ctx(void *arg) {
    pbw_ctx *C = *(pbw_ctx *const *)arg;
    if (!C) MESH_BUG("pbw handler called outside pbw_mesh");
    return C;
}

/* ---- vertices ---------------------------------------------------------------------------- */

static int32_t vt_find(pbw_ctx *C, int64_t gid) {
    uint32_t mask = C->vhcap - 1, h = (uint32_t)mesh_hash64((uint64_t)gid) & mask;
    while (C->vh[h] >= 0) {
        if (C->vgid[C->vh[h]] == gid) return C->vh[h];
        h = (h + 1) & mask;
    }
    return -1;
}

static void vt_rehash(pbw_ctx *C, uint32_t cap) {
    free(C->vh);
    C->vhcap = cap;
    C->vh = mesh_xrealloc(NULL, (size_t)cap * sizeof(int32_t), 1);
    for (uint32_t i = 0; i < cap; i++)
        C->vh[i] = -1;
    for (int32_t v = 0; v < C->nv; v++) {
        uint32_t h = (uint32_t)mesh_hash64((uint64_t)C->vgid[v]) & (cap - 1);
        while (C->vh[h] >= 0)
            h = (h + 1) & (cap - 1);
        C->vh[h] = v;
    }
}

static int32_t vt_add(pbw_ctx *C, int64_t gid, double x, double y, int32_t vseg) {
    int32_t v = vt_find(C, gid);
    if (v >= 0) return v;
    if (C->nv >= C->vcap) {
        C->vcap = C->vcap ? 2 * C->vcap : 1024;
        C->xy = mesh_xrealloc(C->xy, 2 * (size_t)C->vcap * sizeof(double), 1);
        C->vgid = mesh_xrealloc(C->vgid, (size_t)C->vcap * sizeof(int64_t), 1);
        C->vseg = mesh_xrealloc(C->vseg, (size_t)C->vcap * sizeof(int32_t), 1);
    }
    v = C->nv++;
    C->xy[2 * v] = x;
    C->xy[2 * v + 1] = y;
    C->vgid[v] = gid;
    C->vseg[v] = vseg;
    if (2 * (uint32_t)C->nv >= C->vhcap) {
        vt_rehash(C, C->vhcap ? 2 * C->vhcap : 2048);
    } else {
        uint32_t h = (uint32_t)mesh_hash64((uint64_t)gid) & (C->vhcap - 1);
        while (C->vh[h] >= 0)
            h = (h + 1) & (C->vhcap - 1);
        C->vh[h] = v;
    }
    return v;
}

static inline const double *VX(pbw_ctx *C, int32_t v) {
    return C->xy + 2 * (size_t)v;
}
static inline int64_t TG(pbw_ctx *C, int32_t t, int j) { /* global id of vertex j of slot t */
    return C->vgid[C->tv[3 * (size_t)t + j]];
}

/* ---- triangle slots ---------------------------------------------------------------------- */

static int32_t slot_alloc(pbw_ctx *C) {
    int32_t s;
    if (C->nfree > 0) {
        s = C->fre[--C->nfree];
    } else {
        if (C->nt >= C->tcap) {
            C->tcap = C->tcap ? 2 * C->tcap : 1024;
            size_t c = (size_t)C->tcap;
            C->tv = mesh_xrealloc(C->tv, 3 * c * sizeof(int32_t), 1);
            C->tn = mesh_xrealloc(C->tn, 3 * c * sizeof(int64_t), 1);
            C->cs = mesh_xrealloc(C->cs, 3 * c * sizeof(int32_t), 1);
            C->cl = mesh_xrealloc(C->cl, 3 * c * sizeof(int32_t), 1);
            C->ck = mesh_xrealloc(C->ck, 3 * c * sizeof(int64_t), 1);
            C->lk = mesh_xrealloc(C->lk, c * sizeof(int32_t), 1);
            C->role = mesh_xrealloc(C->role, c, 1);
        }
        s = C->nt++;
    }
    C->tv[3 * (size_t)s] = -1;
    C->lk[s] = -1;
    C->role[s] = ROLE_NONE;
    return s;
}

static void slot_free(pbw_ctx *C, int32_t s) {
    C->tv[3 * (size_t)s] = -1;
    C->lk[s] = -1;
    C->role[s] = ROLE_NONE;
    MESH_GROW(C->fre, C->nfree, C->frecap);
    C->fre[C->nfree++] = s;
}

static inline int alive(pbw_ctx *C, int32_t t) {
    return t >= 0 && t < C->nt && C->tv[3 * (size_t)t] >= 0;
}

/* Edge j of t going from vertex id ga to gb, or -1. */
static int find_edge(pbw_ctx *C, int32_t t, int64_t ga, int64_t gb) {
    for (int j = 0; j < 3; j++)
        if (TG(C, t, j) == ga && TG(C, t, (j + 1) % 3) == gb) return j;
    return -1;
}

/* ---- quality: the shared rules ---------------------------------------------------------- */

/* MESH_BAD_ANGLE / MESH_BAD_AREA bits (mesh_rules_bad), 0: good.  *bucket (may be NULL): queue
 * priority (mesh_rules_bucket: shortest edge first, as refine.c).  *sh: shortest edge j. */
static int quality(pbw_ctx *C, int32_t t, int *bucket, int *sh) {
    const int32_t *tv = C->tv + 3 * (size_t)t;
    const double *p[3] = {VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2])};
    double l2;
    int res = mesh_rules_bad(&C->R, p, sh, &l2);
    if (res && bucket) *bucket = mesh_rules_bucket(l2);
    return res;
}

static void push_bad(pbw_ctx *C, int32_t t) {
    int k;
    if (!quality(C, t, &k, NULL)) return;
    int32_t i;
    if (C->pool_free >= 0) {
        i = C->pool_free;
        C->pool_free = C->pool[i].next;
    } else {
        MESH_GROW(C->pool, C->npool, C->poolcap);
        i = C->npool++;
    }
    C->pool[i].t = t;
    C->pool[i].next = C->head[k]; /* LIFO inside a bucket, as refine.c */
    C->head[k] = i;
    if (k < C->cursor) C->cursor = k;
}

static int32_t pop_bad(pbw_ctx *C) {
    while (C->cursor <= NBUCKET && C->head[C->cursor] < 0)
        C->cursor++;
    if (C->cursor > NBUCKET) return -1;
    int k = C->cursor;
    int32_t i = C->head[k];
    C->head[k] = C->pool[i].next;
    C->pool[i].next = C->pool_free;
    C->pool_free = i;
    return C->pool[i].t;
}

static int is_corner_gid(pbw_ctx *C, int64_t g) {
    return g >= 0 && g < C->ninput && C->corner[g];
}

/* The shared forced-angle rule (mesh_rules_edge_forced) for the shortest edge lu-lv (vertex
 * slots): an input vertex is named by its id, a Steiner vertex by the segment it lies on. */
static int edge_forced(pbw_ctx *C, int32_t lu, int32_t lv) {
    if (!C->has_corners) return 0;
    C->I.xy = C->xy; /* input vertex i is slot i (setup); the array moves as it grows */
    int64_t u = C->vgid[lu], v = C->vgid[lv];
    int32_t iu = u >= 0 && u < C->ninput ? (int32_t)u : -1;
    int32_t iv = v >= 0 && v < C->ninput ? (int32_t)v : -1;
    return mesh_rules_edge_forced(&C->I, iu, iu < 0 ? C->vseg[lu] : -1, VX(C, lu), iv,
                                  iv < 0 ? C->vseg[lv] : -1, VX(C, lv));
}

/* 1 iff a new vertex at p would make an edge to vertex slot a shorter than the floor. */
static int below_floor(pbw_ctx *C, const double p[2], int32_t a) {
    return geom_dist2(p, VX(C, a)) < C->floor2;
}

/* Counts a refusal (a split or Steiner point below the length floor); past the budget this
 * rank's refinement is diverging (an angle bound beyond reach, or features below the precision
 * of the coordinates) and it stops, as refine.c does (MESH_REFINE_UNRESOLVED). */
static void refuse(pbw_ctx *C) {
    C->res.unresolved++;
    if (C->res.unresolved > C->unresolved_budget) {
        C->stopped = 1;
        C->res.gave_up = 1;
    }
}

/* Steiner point of bad triangle t (mesh_rules_steiner, on the working grid).  0, or -1. */
static int steiner_point(pbw_ctx *C, int32_t t, int sh, double out[2]) {
    const int32_t *tv = C->tv + 3 * (size_t)t;
    const double *p[3] = {VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2])};
    if (mesh_rules_steiner(&C->R, p, sh, out) != 0) return -1;
    return geom_working_point(out);
}

/* ---- work item queues ---------------------------------------------------------------------- */

static void iv_push(ivec *q, const pbw_item *it) {
    if (q->n >= q->cap && q->head > 0) {
        memmove(q->a, q->a + q->head, (size_t)(q->n - q->head) * sizeof(pbw_item));
        q->n -= q->head;
        q->head = 0;
    }
    MESH_GROW(q->a, q->n, q->cap);
    q->a[q->n++] = *it;
}

static int iv_pop(ivec *q, pbw_item *it) {
    if (q->head >= q->n) {
        q->head = q->n = 0;
        return 0;
    }
    *it = q->a[q->head++];
    return 1;
}

static int iv_empty(const ivec *q) {
    return q->head >= q->n;
}

static void iv_free(ivec *q) {
    free(q->a);
    memset(q, 0, sizeof *q);
}

static int32_t hold_find(pbw_ctx *C, int64_t key);

/* Parks a failed item until what it waits for happens (see W_*). */
static void defer_item(pbw_ctx *C, const pbw_item *it, int kind, int64_t key, int32_t count) {
    pbw_item d = *it;
    d.wait_kind = kind;
    d.wait_key = key;
    d.wait_count = count;
    d.refused = 0;
    if ((kind == W_HOLD && hold_find(C, key) < 0) || (kind == W_WAKE && count <= 0))
        iv_push(&C->retryq, &d); /* already happened */
    else {
        if (kind == W_EVENT) C->nevent++;
        iv_push(&C->deferred, &d);
    }
}

/* Moves the deferred items waiting for (kind, key) to the retry queue (W_EVENT: all
 * W_EVENT items).  refused (W_WAKE): the split that wakes them was refused; an item that
 * waited for a refused split is dropped, not retried (its Steiner point would ask for the same
 * split again), as refine.c drops a bad triangle whose splits all failed. */
static void deferred_release(pbw_ctx *C, int kind, int64_t key, int refused) {
    int32_t k = C->deferred.head;
    for (int32_t i = C->deferred.head; i < C->deferred.n; i++) {
        pbw_item *d = &C->deferred.a[i];
        int hit = d->wait_kind == kind && (kind == W_EVENT || d->wait_key == key);
        if (hit && kind == W_WAKE) {
            d->refused |= refused;
            if (--d->wait_count > 0) hit = 0;
        }
        if (hit) {
            if (d->wait_kind == W_EVENT) C->nevent--;
            if (!d->refused) iv_push(&C->retryq, d);
        } else
            C->deferred.a[k++] = *d;
    }
    C->deferred.n = k;
}

static void refresh_deferred(pbw_ctx *C) {
    if (C->seen_epoch == C->ev_epoch) return;
    C->seen_epoch = C->ev_epoch;
    if (C->nevent > 0) deferred_release(C, W_EVENT, 0, 0);
}

static void wake_key(pbw_ctx *C, int64_t key, int refused) {
    deferred_release(C, W_WAKE, key, refused);
    for (int32_t i = 0; i < C->ndy; i++)
        if (C->dy[i]->die_holder == key) C->dy[i]->woken = 1;
}

/* Wakes whoever waits for key on rank r (r < 0: nobody); refused: see deferred_release. */
static void notify(pbw_ctx *C, int32_t r, int64_t key, int refused) {
    if (r < 0) return;
    if (r == C->rank) {
        wake_key(C, key, refused);
    } else {
        pbw_wake_msg w = {key, refused, 0};
        rt_rsr(r, C->hid[PBW_RSR_WAKE], &w, sizeof w);
    }
}

/* Priority order: stamp, then key (unique), smaller = older. */
static int older(uint64_t sa, int64_t ka, uint64_t sb, int64_t kb) {
    return sa < sb || (sa == sb && ka < kb);
}

#define STAMP_FRESH 128u
static uint64_t stamp_derived(uint64_t s) { /* just older than s, same clock and rank */
    uint64_t pri = s & 0xff;
    return (s & ~(uint64_t)0xff) | (pri > 0 ? pri - 1 : 0);
}

/* ---- holds (locks), waiters, parked expansions ------------------------------------------ */

static int32_t hold_find(pbw_ctx *C, int64_t key) {
    for (int32_t i = 0; i < C->nhd; i++)
        if (C->hd[i].active && C->hd[i].key == key) return i;
    return -1;
}

static int32_t hold_new(pbw_ctx *C, int64_t key, uint64_t stamp, int32_t origin) {
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

static void lock_slot(pbw_ctx *C, int32_t s, int32_t hi, int role) {
    if (C->lk[s] != hi) {
        pbw_hold *h = &C->hd[hi];
        MESH_GROW(h->slots, h->n, h->cap);
        h->slots[h->n++] = s;
        C->lk[s] = hi;
    }
    C->role[s] = (uint8_t)role;
}

static void waiter_add(pbw_ctx *C, int64_t key, int32_t rank) {
    for (int32_t i = 0; i < C->nwt; i++)
        if (C->wt[i].key == key && C->wt[i].rank == rank) return;
    MESH_GROW(C->wt, C->nwt, C->wtcap);
    C->wt[C->nwt].key = key;
    C->wt[C->nwt].rank = rank;
    C->nwt++;
}

/* Frees hold hi (its locks must be gone) and wakes whoever died on it. */
static void hold_end(pbw_ctx *C, int32_t hi, int bump) {
    int64_t key = C->hd[hi].key;
    C->hd[hi].active = 0;
    C->hd[hi].n = 0;
    for (int32_t i = 0; i < C->nwt;) {
        if (C->wt[i].key == key) {
            notify(C, C->wt[i].rank, key, 0);
            C->wt[i] = C->wt[--C->nwt];
        } else {
            i++;
        }
    }
    /* only a distributed cavity's locks outlive one step of local work, so only those can
     * have deferred items waiting for them */
    if (C->hd[hi].distributed) deferred_release(C, W_HOLD, key, 0);
    if (bump) C->ev_epoch++;
}

/* Releases every lock of hold hi on this rank (undo: a lock conflict; bump: wake deferred
 * local work -- only needed if other work could have been waiting on these locks). */
static void release_local(pbw_ctx *C, int32_t hi, int undo, int bump) {
    pbw_hold *h = &C->hd[hi];
    for (int32_t i = 0; i < h->n; i++) {
        int32_t s = h->slots[i];
        if (C->lk[s] != hi) continue;
        if (C->role[s] == ROLE_RES) {
            slot_free(C, s);
        } else {
            C->lk[s] = -1;
            C->role[s] = ROLE_NONE;
        }
    }
    if (undo) rt_stats_add_time(RT_TIME_UNDO, h->t_spent);
    hold_end(C, hi, bump);
}

/* ---- cavity state -------------------------------------------------------------------------- */

static pbw_cav *cav_new(pbw_ctx *C) {
    pbw_cav *c = mesh_xrealloc(NULL, sizeof *c, 1);
    memset(c, 0, sizeof *c);
    c->C = C;
    c->h.su = c->h.sv = c->h.holder = -1;
    return c;
}

static void cav_free(pbw_cav *c) {
    if (!c) return;
    free(c->parts);
    free(c->b);
    free(c->todo);
    free(c->stk);
    free(c->reply);
    free(c);
}

static void part_add(pbw_cav *c, int32_t r) {
    for (int32_t i = 0; i < c->np; i++)
        if (c->parts[i] == r) return;
    MESH_GROW(c->parts, c->np, c->pcap);
    c->parts[c->np++] = r;
}

static void part_remove(pbw_cav *c, int32_t r) {
    for (int32_t i = 0; i < c->np; i++)
        if (c->parts[i] == r) {
            c->parts[i] = c->parts[--c->np];
            return;
        }
}

static void push_seed(pbw_ctx *C, pbw_cav *c, int64_t target, int64_t from, int64_t ga, int64_t gb,
                      int mode) {
    pbw_seed s = {target, from, ga, gb, mode, 0};
    if (ref_rank(target) == C->rank) {
        MESH_GROW(c->stk, c->nstk, c->scap);
        c->stk[c->nstk++] = s;
    } else {
        MESH_GROW(c->todo, c->ntodo, c->tcap);
        c->todo[c->ntodo++] = s;
    }
}

static size_t pad8(size_t n) {
    return (n + 7) & ~(size_t)7;
}

/* Serialises c (full: with boundary edges and seeds). */
static void *cav_pack(pbw_cav *c, int full, uint32_t *len) {
    c->h.nparts = c->np;
    c->h.nbnd = full ? c->nb : 0;
    c->h.nseed = full ? c->ntodo : 0;
    size_t pl = pad8((size_t)c->np * sizeof(int32_t));
    size_t n = sizeof(pbw_whdr) + pl + (size_t)c->h.nbnd * sizeof(pbw_bnd) +
               (size_t)c->h.nseed * sizeof(pbw_seed);
    if (n > MAXMSG) MESH_BUG("cavity message of %zu bytes", n);
    char *buf = mesh_xrealloc(NULL, n, 1), *q = buf;
    memset(buf, 0, n);
    memcpy(q, &c->h, sizeof c->h);
    q += sizeof c->h;
    memcpy(q, c->parts, (size_t)c->np * sizeof(int32_t));
    q += pl;
    if (c->h.nbnd > 0) memcpy(q, c->b, (size_t)c->h.nbnd * sizeof(pbw_bnd));
    q += (size_t)c->h.nbnd * sizeof(pbw_bnd);
    if (c->h.nseed > 0) memcpy(q, c->todo, (size_t)c->h.nseed * sizeof(pbw_seed));
    *len = (uint32_t)n;
    return buf;
}

/* Replaces c's header and arrays by the serialised state data. */
static void cav_unpack_into(pbw_cav *c, const void *data, uint32_t len) {
    const char *q = data;
    if (len < sizeof(pbw_whdr)) MESH_BUG("short cavity message (%u bytes)", (unsigned)len);
    memcpy(&c->h, q, sizeof c->h);
    q += sizeof c->h;
    size_t pl = pad8((size_t)c->h.nparts * sizeof(int32_t));
    size_t need = sizeof(pbw_whdr) + pl + (size_t)c->h.nbnd * sizeof(pbw_bnd) +
                  (size_t)c->h.nseed * sizeof(pbw_seed);
    if (c->h.nparts < 0 || c->h.nbnd < 0 || c->h.nseed < 0 || need != len)
        MESH_BUG("malformed cavity message (%u bytes, expected %zu)", (unsigned)len, need);
    c->np = c->nb = c->ntodo = 0;
    for (int32_t i = 0; i < c->h.nparts; i++)
        part_add(c, ((const int32_t *)q)[i]);
    q += pl;
    for (int32_t i = 0; i < c->h.nbnd; i++) {
        MESH_GROW(c->b, c->nb, c->bcap);
        memcpy(&c->b[c->nb++], q, sizeof(pbw_bnd));
        q += sizeof(pbw_bnd);
    }
    for (int32_t i = 0; i < c->h.nseed; i++) {
        MESH_GROW(c->todo, c->ntodo, c->tcap);
        memcpy(&c->todo[c->ntodo++], q, sizeof(pbw_seed));
        q += sizeof(pbw_seed);
    }
}

/* ---- expansion (the same on the starter and on every remote rank) ------------------------ */

/* Reports boundary edge ga->gb (vertex slots la, lb here) and reserves the new triangle's
 * slot on this rank. */
static void report(pbw_ctx *C, pbw_cav *c, int32_t hi, int32_t la, int32_t lb, int64_t out,
                   int64_t inref, int32_t cseg, int32_t clev, int64_t ck) {
    int32_t s = slot_alloc(C);
    lock_slot(C, s, hi, ROLE_RES);
    pbw_bnd r;
    memset(&r, 0, sizeof r);
    r.ga = C->vgid[la];
    r.gb = C->vgid[lb];
    r.out = out;
    r.newref = mkref(C->rank, s);
    r.inref = inref;
    r.cseg = cseg;
    r.clev = clev;
    r.ck = ck;
    if (geom_orient2d(VX(C, la), VX(C, lb), c->h.p) <= 0) r.flags |= BF_BEYOND;
    if (cseg >= 0 && mesh_rules_encroaches(&C->R, VX(C, la), VX(C, lb), c->h.p)) r.flags |= BF_ENC;
    MESH_GROW(c->b, c->nb, c->bcap);
    c->b[c->nb++] = r;
}

static int is_open_edge(const pbw_cav *c, int64_t ga, int64_t gb) {
    return c->h.kind == K_SPLIT &&
           ((ga == c->h.su && gb == c->h.sv) || (ga == c->h.sv && gb == c->h.su));
}

/* Member x (reached from member `from`) joins the cavity: visit its neighbours. */
static void expand_member(pbw_ctx *C, pbw_cav *c, int32_t hi, int32_t x, int64_t from) {
    int64_t self = mkref(C->rank, x);
    for (int j = 0; j < 3; j++) {
        size_t e = 3 * (size_t)x + (size_t)j;
        int32_t la = C->tv[e], lb = C->tv[3 * (size_t)x + (size_t)((j + 1) % 3)];
        int64_t ga = C->vgid[la], gb = C->vgid[lb], n = C->tn[e];
        if (n != NOREF && n == from) continue;
        if (is_open_edge(c, ga, gb)) {
            if (n != NOREF) push_seed(C, c, n, self, ga, gb, SEED_OPEN);
        } else if (C->cs[e] >= 0) {
            if (n == NOREF)
                report(C, c, hi, la, lb, NOREF, self, C->cs[e], C->cl[e], C->ck[e]);
            else
                push_seed(C, c, n, self, ga, gb, SEED_HALO);
        } else if (n == NOREF) {
            report(C, c, hi, la, lb, NOREF, self, -1, -1, 0); /* cannot happen in a CDT */
        } else {
            push_seed(C, c, n, self, ga, gb, SEED_NORMAL);
        }
    }
}

static int in_conflict(pbw_ctx *C, int32_t x, const double p[2]) {
    const int32_t *tv = C->tv + 3 * (size_t)x;
    return geom_incircle(VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2]), p) > 0;
}

/* Processes the local seeds of c.  initial: the starter's first step (nothing sent yet). */
static int process(pbw_ctx *C, pbw_cav *c, int32_t hi, int initial) {
    while (c->nstk > 0) {
        pbw_seed s = c->stk[c->nstk - 1];
        int32_t x = ref_idx(s.target);
        if (ref_rank(s.target) != C->rank || x < 0 || x >= C->nt)
            MESH_BUG("seed names triangle (%d, %d)", ref_rank(s.target), x);
        int32_t h = C->lk[x];
        if (h >= 0 && h != hi) {
            c->h.holder = C->hd[h].key;
            if (initial) return PR_DIE;
            return older(c->h.stamp, c->h.key, C->hd[h].stamp, C->hd[h].key) ? PR_PARK : PR_DIE;
        }
        c->nstk--;
        if (!alive(C, x)) MESH_BUG("seed names dead triangle %d (mode %d)", x, s.mode);
        int j = -1;
        if (s.mode != SEED_START) {
            j = find_edge(C, x, s.gb, s.ga);
            if (j < 0)
                MESH_BUG("triangle %d has no edge %lld->%lld (mode %d)", x, (long long)s.gb,
                         (long long)s.ga, s.mode);
        }
        int role = h == hi ? C->role[x] : ROLE_NONE;
        switch (s.mode) {
        case SEED_START:
            lock_slot(C, x, hi, ROLE_MEMBER);
            expand_member(C, c, hi, x, NOREF);
            break;
        case SEED_OPEN:
            if (role == ROLE_MEMBER) {
                c->h.cycle = 1;
                break;
            }
            lock_slot(C, x, hi, ROLE_MEMBER);
            expand_member(C, c, hi, x, s.from);
            break;
        case SEED_HALO: {
            if (role == ROLE_NONE) lock_slot(C, x, hi, ROLE_HALO);
            size_t e = 3 * (size_t)x + (size_t)j;
            /* x's edge is gb->ga: the cavity's edge ga->gb runs from x's vertex j+1 to j */
            report(C, c, hi, C->tv[3 * (size_t)x + (size_t)((j + 1) % 3)], C->tv[e],
                   mkref(C->rank, x), s.from, C->cs[e], C->cl[e], C->ck[e]);
            break;
        }
        case SEED_NORMAL:
            if (role == ROLE_MEMBER) { /* a second way in: see CAVITY above */
                c->h.cycle = 1;
                break;
            }
            if (in_conflict(C, x, c->h.p)) {
                lock_slot(C, x, hi, ROLE_MEMBER);
                expand_member(C, c, hi, x, s.from);
            } else {
                if (role == ROLE_NONE) lock_slot(C, x, hi, ROLE_HALO);
                size_t e = 3 * (size_t)x + (size_t)j;
                report(C, c, hi, C->tv[3 * (size_t)x + (size_t)((j + 1) % 3)], C->tv[e],
                       mkref(C->rank, x), s.from, -1, -1, 0);
            }
            break;
        default:
            MESH_BUG("bad seed mode %d", s.mode);
        }
    }
    return PR_DONE;
}

/* ---- commit ---------------------------------------------------------------------------------- */

static void check_new_triangle(pbw_ctx *C, int32_t t) {
    push_bad(C, t);
    for (int j = 0; j < 3; j++) {
        size_t e = 3 * (size_t)t + (size_t)j;
        if (C->cs[e] < 0) continue;
        int32_t a = C->tv[e], b = C->tv[3 * (size_t)t + (size_t)((j + 1) % 3)],
                o = C->tv[3 * (size_t)t + (size_t)((j + 2) % 3)];
        if (mesh_rules_encroaches(&C->R, VX(C, a), VX(C, b), VX(C, o))) {
            pbw_item it;
            memset(&it, 0, sizeof it);
            it.kind = IT_SPLIT;
            it.t = t;
            it.gu = C->vgid[a];
            it.gv = C->vgid[b];
            it.notify = -1;
            it.ticket = -1;
            it.forced = 0;
            iv_push(&C->splitq, &it);
        }
    }
}

/* Applies this rank's part of a commit: members die, reserved slots become the new triangles,
 * halos get their link to the new triangle, everything is unlocked. */
static void apply_commit(pbw_ctx *C, const pbw_commit_hdr *ch, const pbw_newtri *nt, int bump) {
    int32_t hi = hold_find(C, ch->key);
    if (hi < 0) MESH_BUG("commit for unknown cavity %llx", (unsigned long long)ch->key);
    pbw_hold *h = &C->hd[hi];
    vt_add(C, ch->pgid, ch->p[0], ch->p[1], ch->pvseg);
    for (int32_t i = 0; i < h->n; i++) {
        int32_t s = h->slots[i];
        if (C->lk[s] == hi && C->role[s] == ROLE_MEMBER) {
            slot_free(C, s);
            C->nlive--;
        }
    }
    for (int32_t i = 0; i < ch->n; i++) {
        const pbw_newtri *r = &nt[i];
        int32_t s = r->slot;
        if (s < 0 || s >= C->nt || C->lk[s] != hi || C->role[s] != ROLE_RES)
            MESH_BUG("commit writes slot %d not reserved by the cavity", s);
        for (int j = 0; j < 3; j++) {
            int32_t v = vt_find(C, r->g[j]);
            if (v < 0) MESH_BUG("commit names unknown vertex %lld", (long long)r->g[j]);
            size_t e = 3 * (size_t)s + (size_t)j;
            C->tv[e] = v;
            C->tn[e] = r->nb[j];
            C->cs[e] = r->cseg[j];
            C->cl[e] = r->clev[j];
            C->ck[e] = r->ck[j];
        }
        C->lk[s] = -1;
        C->role[s] = ROLE_NONE;
        C->nlive++;
        if (r->nb[0] != NOREF) {
            if (ref_rank(r->nb[0]) != C->rank) MESH_BUG("halo of a new triangle on another rank");
            int32_t x = ref_idx(r->nb[0]);
            int j = alive(C, x) ? find_edge(C, x, r->g[1], r->g[0]) : -1;
            if (j < 0 || C->lk[x] != hi || C->role[x] != ROLE_HALO)
                MESH_BUG("halo %d of the new triangle is not the cavity's", x);
            C->tn[3 * (size_t)x + (size_t)j] = mkref(C->rank, s);
        }
    }
    for (int32_t i = 0; i < h->n; i++) {
        int32_t s = h->slots[i];
        if (C->lk[s] != hi) continue;
        if (C->role[s] == ROLE_RES) MESH_BUG("reserved slot %d left unused by the commit", s);
        C->lk[s] = -1;
        C->role[s] = ROLE_NONE;
    }
    hold_end(C, hi, bump);
    for (int32_t i = 0; i < ch->n; i++)
        check_new_triangle(C, nt[i].slot);
}

/* Sends RELEASE to every participant (and releases here). */
static void release_all(pbw_ctx *C, pbw_cav *c, int undo) {
    for (int32_t i = 0; i < c->np; i++) {
        int32_t r = c->parts[i];
        if (r == C->rank) {
            int32_t hi = hold_find(C, c->h.key);
            if (hi >= 0) release_local(C, hi, undo, C->hd[hi].distributed);
        } else {
            pbw_release_msg m = {c->h.key, undo, 0};
            rt_rsr(r, C->hid[PBW_RSR_RELEASE], &m, sizeof m);
        }
    }
}

typedef struct gmap {
    int64_t *key;
    int32_t *val;
    uint32_t mask;
} gmap;

static void gmap_init(gmap *m, int32_t n) {
    uint32_t cap = 16;
    while (cap < 2 * (uint32_t)n + 2)
        cap *= 2;
    m->key = mesh_xrealloc(NULL, cap * sizeof(int64_t), 1);
    m->val = mesh_xrealloc(NULL, cap * sizeof(int32_t), 1);
    m->mask = cap - 1;
    for (uint32_t i = 0; i < cap; i++)
        m->val[i] = -1;
}

static int gmap_put(gmap *m, int64_t k, int32_t v) { /* 0, or -1 if k is present */
    uint32_t h = (uint32_t)mesh_hash64((uint64_t)k) & m->mask;
    while (m->val[h] >= 0) {
        if (m->key[h] == k) return -1;
        h = (h + 1) & m->mask;
    }
    m->key[h] = k;
    m->val[h] = v;
    return 0;
}

static int32_t gmap_get(const gmap *m, int64_t k) {
    uint32_t h = (uint32_t)mesh_hash64((uint64_t)k) & m->mask;
    while (m->val[h] >= 0) {
        if (m->key[h] == k) return m->val[h];
        h = (h + 1) & m->mask;
    }
    return -1;
}

static void gmap_free(gmap *m) {
    free(m->key);
    free(m->val);
}

/* Constraint info of the split half with endpoint w (w is su or sv). */
static void half_info(const pbw_cav *c, int64_t w, int32_t *cseg, int32_t *clev, int64_t *ck) {
    *cseg = c->sseg;
    *clev = c->schild_lev;
    *ck = c->schild_lev < 0 ? 0 : (w == c->h.su ? c->sk_u : c->sk_v);
}

/* Builds the new triangles (one per boundary edge) and commits them on every participant.
 * Returns 0, or -1 if the boundary is not a proper fan (then nothing was sent). */
static int commit_all(pbw_ctx *C, pbw_cav *c) {
    int32_t n = c->nb;
    int split = c->h.kind == K_SPLIT;
    gmap A, B;
    gmap_init(&A, n);
    gmap_init(&B, n);
    int bad = n < 1;
    for (int32_t i = 0; i < n && !bad; i++)
        if (gmap_put(&A, c->b[i].ga, i) != 0 || gmap_put(&B, c->b[i].gb, i) != 0) bad = 1;
    pbw_newtri *nt = mesh_xrealloc(NULL, (size_t)(n > 0 ? n : 1) * sizeof *nt, 1);
    int64_t pgid = ((int64_t)(C->rank + 1) << 32) | C->nvown;
    for (int32_t i = 0; i < n && !bad; i++) {
        const pbw_bnd *b = &c->b[i];
        pbw_newtri *r = &nt[i];
        memset(r, 0, sizeof *r);
        r->g[0] = b->ga;
        r->g[1] = b->gb;
        r->g[2] = pgid;
        r->slot = ref_idx(b->newref);
        r->nb[0] = b->out;
        r->cseg[0] = b->cseg;
        r->clev[0] = b->clev;
        r->ck[0] = b->ck;
        int ub = split && (b->gb == c->h.su || b->gb == c->h.sv);
        int ua = split && (b->ga == c->h.su || b->ga == c->h.sv);
        int32_t j = gmap_get(&A, b->gb), k = gmap_get(&B, b->ga);
        if (j >= 0)
            r->nb[1] = c->b[j].newref;
        else if (ub)
            r->nb[1] = NOREF;
        else
            bad = 1;
        if (k >= 0)
            r->nb[2] = c->b[k].newref;
        else if (ua)
            r->nb[2] = NOREF;
        else
            bad = 1;
        r->cseg[1] = r->cseg[2] = -1;
        r->clev[1] = r->clev[2] = -1;
        if (ub) half_info(c, b->gb, &r->cseg[1], &r->clev[1], &r->ck[1]);
        if (ua) half_info(c, b->ga, &r->cseg[2], &r->clev[2], &r->ck[2]);
    }
    gmap_free(&A);
    gmap_free(&B);
    if (bad) {
        free(nt);
        return -1;
    }
    C->nvown++;
    C->res.steiner++;
    /* one message per participant, with the new triangles it owns */
    pbw_newtri *mine = mesh_xrealloc(NULL, (size_t)(n > 0 ? n : 1) * sizeof *mine, 1);
    for (int32_t pi = 0; pi < c->np; pi++) {
        int32_t r = c->parts[pi];
        int32_t m = 0;
        for (int32_t i = 0; i < n; i++)
            if (ref_rank(c->b[i].newref) == r) mine[m++] = nt[i];
        pbw_commit_hdr ch;
        memset(&ch, 0, sizeof ch);
        ch.key = c->h.key;
        ch.pgid = pgid;
        ch.p[0] = c->h.p[0];
        ch.p[1] = c->h.p[1];
        ch.pvseg = split ? c->sseg : -1;
        ch.n = m;
        if (r == C->rank) {
            int32_t hi = hold_find(C, c->h.key);
            apply_commit(C, &ch, mine, hi >= 0 && C->hd[hi].distributed);
        } else {
            size_t len = sizeof ch + (size_t)m * sizeof(pbw_newtri);
            char *buf = mesh_xrealloc(NULL, len, 1);
            memcpy(buf, &ch, sizeof ch);
            if (m > 0) memcpy(buf + sizeof ch, mine, (size_t)m * sizeof(pbw_newtri));
            rt_rsr(r, C->hid[PBW_RSR_COMMIT], buf, (uint32_t)len);
            free(buf);
        }
    }
    free(mine);
    free(nt);
    return 0;
}

/* The starter's decision once the whole cavity is known (or the expansion died). */
static void finish(pbw_ctx *C, pbw_cav *c) {
    if (c->h.status == ST_DIE) {
        release_all(C, c, 1);
        C->res.undone_remote++;
        if (c->h.died_at == C->rank)
            defer_item(C, &c->it, W_HOLD, c->h.holder, 1);
        else if (c->woken)
            iv_push(&C->retryq, &c->it);
        else
            defer_item(C, &c->it, W_WAKE, c->h.holder, 1);
        return;
    }
    int split = c->h.kind == K_SPLIT;
    int cbad = 0, nonstar = 0;
    for (int32_t i = 0; i < c->nb; i++) {
        const pbw_bnd *b = &c->b[i];
        if (b->cseg >= 0) {
            if ((b->flags & BF_BEYOND) || (!split && (b->flags & BF_ENC))) cbad = 1;
        } else if (b->flags & BF_BEYOND) {
            nonstar = 1;
        }
    }
    if (!split && cbad && !c->h.cycle) {
        /* p encroaches (or lies beyond) subsegments: discard it, split them, retry later */
        release_all(C, c, 0);
        C->res.rejected++;
        int32_t nreq = 0;
        uint64_t sst = stamp_derived(c->h.stamp);
        for (int32_t i = 0; i < c->nb; i++) {
            const pbw_bnd *b = &c->b[i];
            if (b->cseg < 0 || !(b->flags & (BF_BEYOND | BF_ENC))) continue;
            int dup = 0;
            for (int32_t k = 0; k < i && !dup; k++) {
                const pbw_bnd *o = &c->b[k];
                if (o->cseg >= 0 && (o->flags & (BF_BEYOND | BF_ENC)) &&
                    ((o->ga == b->ga && o->gb == b->gb) || (o->ga == b->gb && o->gb == b->ga)))
                    dup = 1;
            }
            if (dup) continue;
            int r = ref_rank(b->inref);
            nreq++;
            if (r == C->rank) {
                pbw_item it;
                memset(&it, 0, sizeof it);
                it.kind = IT_SPLIT;
                it.t = ref_idx(b->inref);
                it.gu = b->ga;
                it.gv = b->gb;
                it.notify = C->rank;
                it.ticket = c->h.key;
                it.stamp = sst;
                it.forced = 1;
                iv_push(&C->splitq, &it);
            } else {
                pbw_split_msg m = {b->ga, b->gb, c->h.key, sst, ref_idx(b->inref), C->rank};
                rt_rsr(r, C->hid[PBW_RSR_SPLIT], &m, sizeof m);
            }
        }
        /* retry once every split asked for is done (each one wakes us with our key) */
        defer_item(C, &c->it, W_WAKE, c->h.key, nreq);
        return;
    }
    if (nonstar || cbad || c->h.cycle || commit_all(C, c) != 0) {
        release_all(C, c, 0);
        C->res.failed++;
        if (split) notify(C, c->it.notify, c->it.ticket, 1);
        return;
    }
    if (c->np > 1)
        C->res.cavities_remote++;
    else
        C->res.cavities_local++;
    if (split) {
        C->res.splits++;
        notify(C, c->it.notify, c->it.ticket, 0);
    } else {
        C->res.inserted++;
    }
}

/* ---- chains, parking, handlers ------------------------------------------------------------- */

static void drain_parked(pbw_ctx *C);

/* Continues c's expansion on this rank (it arrived by EXPAND, or a parked one resumes). */
static void chain_continue(pbw_ctx *C, pbw_cav *c, int32_t hi) {
    double t0 = rt_wtime();
    int r = process(C, c, hi, 0);
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
        release_local(C, hi, 1, 1);
        part_remove(c, C->rank);
        if (c->h.origin != C->rank) waiter_add(C, holder, c->h.origin);
        c->h.status = ST_DIE;
        c->h.died_at = C->rank;
        buf = cav_pack(c, 0, &len);
        rt_reply(&fm, C->hid[PBW_RSR_REPLY], buf, len);
    } else if (c->ntodo > 0) {
        buf = cav_pack(c, 1, &len);
        rt_forward(&fm, ref_rank(c->todo[0].target), C->hid[PBW_RSR_EXPAND], buf, len);
    } else {
        buf = cav_pack(c, 1, &len);
        rt_reply(&fm, C->hid[PBW_RSR_REPLY], buf, len);
    }
    free(buf);
    cav_free(c);
}

/* Resumes parked expansions whose blocker has released its locks here, oldest first. */
static void drain_parked(pbw_ctx *C) {
    if (C->draining) return;
    C->draining = 1;
    for (;;) {
        int32_t best = -1;
        for (int32_t i = 0; i < C->npk; i++)
            if (hold_find(C, C->pk[i]->h.holder) < 0 &&
                (best < 0 || older(C->pk[i]->h.stamp, C->pk[i]->h.key, C->pk[best]->h.stamp,
                                   C->pk[best]->h.key)))
                best = i;
        if (best < 0) break;
        pbw_cav *c = C->pk[best];
        C->pk[best] = C->pk[--C->npk];
        int32_t hi = hold_find(C, c->h.key);
        if (hi < 0) MESH_BUG("parked cavity lost its locks");
        chain_continue(C, c, hi);
    }
    C->draining = 0;
}

static void h_expand(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    pbw_cav *c = cav_new(C);
    cav_unpack_into(c, m->data, m->len);
    uint64_t ts = c->h.stamp >> 24;
    if (ts > C->lclock) C->lclock = ts;
    int32_t hi = hold_find(C, c->h.key);
    if (hi < 0) {
        hi = hold_new(C, c->h.key, c->h.stamp, c->h.origin);
        part_add(c, C->rank);
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

static void h_reply(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    if (!m->task) MESH_BUG("cavity reply without a waiting task");
    pbw_cav *c = rt_task_data(m->task);
    free(c->reply);
    c->reply = mesh_xrealloc(NULL, m->len, 1);
    memcpy(c->reply, m->data, m->len);
    c->replylen = m->len;
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
    int32_t hi = hold_find(C, r->key);
    if (hi >= 0) release_local(C, hi, r->undo, 1);
    drain_parked(C);
}

static void h_commit(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    const pbw_commit_hdr *ch = m->data;
    if (m->len < sizeof *ch || m->len != sizeof *ch + (size_t)ch->n * sizeof(pbw_newtri))
        MESH_BUG("malformed commit (%u bytes)", (unsigned)m->len);
    apply_commit(C, ch, (const pbw_newtri *)(ch + 1), 1);
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
    iv_push(&C->splitq, &it);
}

static void h_wake(const rt_msg *m, void *arg) {
    pbw_ctx *C = handler_ctx(arg);
    const pbw_wake_msg *w = m->data;
    wake_key(C, w->key, w->refused);
}

/* The task of a distributed cavity: send the expansion, wait in the blocking queue for the
 * chain's reply, decide. */
static rt_task_status cav_task(rt_task *t, void *state) {
    pbw_cav *c = state;
    pbw_ctx *C = c->C;
    if (c->phase == 0) {
        c->phase = 1;
        uint32_t len;
        void *buf = cav_pack(c, 1, &len);
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
    cav_unpack_into(c, c->reply, c->replylen);
    finish(C, c);
    C->inflight--;
    C->ev_epoch++; /* a slot for another distributed cavity */
    cav_free(c);
    drain_parked(C);
    return RT_TASK_DONE;
}

/* ---- local work ---------------------------------------------------------------------------- */

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
    pbw_cav *c = cav_new(C);
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
        c->sseg = sd->sseg;
        c->schild_lev = sd->child_lev;
        c->sk_u = sd->ku;
        c->sk_v = sd->kv;
    }
    c->it = *it;
    int32_t hi = hold_new(C, c->h.key, c->h.stamp, C->rank);
    part_add(c, C->rank);
    push_seed(C, c, mkref(C->rank, t), NOREF, -1, -1, SEED_START);
    double t0 = rt_wtime();
    int r = process(C, c, hi, 1);
    C->hd[hi].t_spent += rt_wtime() - t0;
    if (r == PR_DIE) {
        int64_t holder = c->h.holder;
        release_local(C, hi, 1, 0);
        C->res.undone_local++;
        defer_item(C, &c->it, W_HOLD, holder, 1);
        cav_free(c);
        return;
    }
    if (c->ntodo == 0) {
        finish(C, c);
        cav_free(c);
        return;
    }
    if (C->phase1) {
        release_local(C, hi, 0, 0);
        C->res.postponed++;
        iv_push(&C->phase2, &c->it);
        cav_free(c);
        return;
    }
    if (C->inflight >= MAX_INFLIGHT) {
        release_local(C, hi, 0, 0);
        defer_item(C, &c->it, W_EVENT, 0, 1);
        cav_free(c);
        return;
    }
    C->hd[hi].distributed = 1;
    C->inflight++;
    rt_task_spawn(cav_task, c);
}

/* Split point of the subsegment (la, lb) of segment s with dyadic name (lev, k), as refine.c
 * computes it (shells of unit 1 around a small corner: PBW has no interface segments); fills
 * the halves' names into c-independent outputs.  Returns 0, -1 if the point is unusable
 * (precision exhausted), -2 if it is below the length floor (a refusal). */
static int split_point(pbw_ctx *C, int32_t la, int32_t lb, int32_t s, int32_t lev, int64_t k,
                       double p[2], int32_t *child_lev, int64_t *ka, int64_t *kb) {
    const double *pu = VX(C, la), *pv = VX(C, lb);
    const double *A = VX(C, C->seg[2 * s]), *B = VX(C, C->seg[2 * s + 1]);
    int cu = is_corner_gid(C, C->vgid[la]), cv = is_corner_gid(C, C->vgid[lb]);
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
    if (below_floor(C, p, la) || below_floor(C, p, lb)) return -2;
    return 0;
}

static void process_item(pbw_ctx *C, pbw_item *it) {
    int32_t t = it->t;
    if (!alive(C, t)) {
        if (it->kind == IT_SPLIT) notify(C, it->notify, it->ticket, 0);
        return;
    }
    if (it->kind == IT_SPLIT) {
        int j = find_edge(C, t, it->gu, it->gv);
        if (j < 0) j = find_edge(C, t, it->gv, it->gu);
        size_t e = 3 * (size_t)t + (size_t)j;
        if (j < 0 || C->cs[e] < 0) { /* already split, or the triangle changed */
            notify(C, it->notify, it->ticket, 0);
            return;
        }
        if (C->lk[t] >= 0) {
            defer_item(C, it, W_HOLD, C->hd[C->lk[t]].key, 1);
            return;
        }
        int32_t la = C->tv[e], lb = C->tv[3 * (size_t)t + (size_t)((j + 1) % 3)];
        if (!it->forced &&
            !mesh_rules_encroaches(&C->R, VX(C, la), VX(C, lb),
                                   VX(C, C->tv[3 * (size_t)t + (size_t)((j + 2) % 3)]))) {
            notify(C, it->notify, it->ticket, 0);
            return;
        }
        if (limit_reached(C)) return;
        double p[2];
        int32_t clev;
        int64_t ka, kb;
        int sp = split_point(C, la, lb, C->cs[e], C->cl[e], C->ck[e], p, &clev, &ka, &kb);
        if (sp != 0) {
            if (sp == -2)
                refuse(C);
            else
                C->res.failed++;
            notify(C, it->notify, it->ticket, 1);
            return;
        }
        it->gu = C->vgid[la];
        it->gv = C->vgid[lb];
        split_desc sd = {C->cs[e], clev, ka, kb};
        start_cavity(C, it, p, t, &sd);
        return;
    }
    /* a bad triangle */
    if (C->lk[t] >= 0) {
        defer_item(C, it, W_HOLD, C->hd[C->lk[t]].key, 1);
        return;
    }
    int sh = 0;
    int why = quality(C, t, NULL, &sh);
    if (!why) return;
    const int32_t *tv = C->tv + 3 * (size_t)t;
    if (why == MESH_BAD_ANGLE && edge_forced(C, tv[sh], tv[(sh + 1) % 3])) {
        /* skinny but not too large, and the small angle is forced by the input */
        C->res.skipped_small++;
        return;
    }
    double p[2];
    if (steiner_point(C, t, sh, p) != 0) {
        C->res.failed++;
        return;
    }
    /* the new vertex is at least the circumradius away from every vertex (empty circle): its
     * distance to t's vertices is the length of the shortest edge it creates */
    if (below_floor(C, p, tv[0]) || below_floor(C, p, tv[1]) || below_floor(C, p, tv[2])) {
        refuse(C);
        return;
    }
    if (limit_reached(C)) return;
    start_cavity(C, it, p, t, NULL);
}

static int next_item(pbw_ctx *C, pbw_item *it) {
    if (iv_pop(&C->splitq, it)) return 1;
    if (iv_pop(&C->retryq, it)) return 1;
    int32_t t = pop_bad(C);
    if (t < 0) return 0;
    memset(it, 0, sizeof *it);
    it->kind = IT_BAD;
    it->t = t;
    it->notify = -1;
    it->ticket = -1;
    return 1;
}

static int has_items(pbw_ctx *C) {
    if (!iv_empty(&C->splitq) || !iv_empty(&C->retryq)) return 1;
    while (C->cursor <= NBUCKET && C->head[C->cursor] < 0)
        C->cursor++;
    return C->cursor <= NBUCKET;
}

static void drop_all_items(pbw_ctx *C) {
    pbw_item it;
    while (next_item(C, &it)) {
    }
    C->deferred.n = C->deferred.head = 0;
    C->nevent = 0;
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
            "waiters=%d epoch=%u undone=%lld/%lld ins=%lld\n",
            C->rank, C->nlive, C->inflight, C->npk, nh, C->deferred.n - C->deferred.head,
            C->retryq.n - C->retryq.head, C->splitq.n - C->splitq.head, C->nwt, C->ev_epoch,
            (long long)C->res.undone_local, (long long)C->res.undone_remote,
            (long long)C->res.inserted);
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

static int work(void *ctx) {
    pbw_ctx *C = ctx;
    int did = 0;
    debug_report(C);
    for (int n = 0; n < WORK_BATCH && !C->stopped; n++) {
        refresh_deferred(C);
        pbw_item it;
        if (!next_item(C, &it)) break;
        did = 1;
        process_item(C, &it);
    }
    if (C->stopped) {
        drop_all_items(C);
        return did ? RT_WORK_BUSY : RT_WORK_IDLE;
    }
    refresh_deferred(C);
    return (did || has_items(C)) ? RT_WORK_BUSY : RT_WORK_IDLE;
}

/* ---- the initial distributed mesh ------------------------------------------------------ */

typedef struct pbw_setup_opts {
    double min_angle, max_area;
    int64_t max_steiner;
} pbw_setup_opts;

static void centroid(const mesh *m, int32_t t, double c[2]) {
    const double *a = mesh_vertex_xy(m, m->tv[3 * t]), *b = mesh_vertex_xy(m, m->tv[3 * t + 1]),
                 *d = mesh_vertex_xy(m, m->tv[3 * t + 2]);
    c[0] = (a[0] + b[0] + d[0]) / 3.0;
    c[1] = (a[1] + b[1] + d[1]) / 3.0;
}

/* Owner rank of every triangle slot of m0: the owner of the subdomain of d containing its
 * centroid (exact point location in the CDT of d's augmented PSLG, whose regions are the
 * subdomains).  Every rank computes the same answer. */
static int owners(pbw_ctx *C, const mesh *m0, const pcdm_decomp *d, int32_t *own, char *err,
                  size_t errlen) {
    mesh md;
    mesh_init(&md);
    if (mesh_build_cdt(&md, &d->g, d->seg_iface, err, errlen) != 0) {
        mesh_free(&md);
        return -1;
    }
    int32_t *lab = mesh_xrealloc(NULL, ((size_t)md.nt + 1) * sizeof(int32_t), 1);
    int32_t nreg = mesh_label_regions(&md, lab);
    int32_t *rsub = mesh_xrealloc(NULL, ((size_t)nreg + 1) * sizeof(int32_t), 1);
    for (int32_t i = 0; i < nreg; i++)
        rsub[i] = -1;
    for (int32_t t = 0; t < md.nt; t++) {
        if (!mesh_tri_alive(&md, t) || rsub[lab[t]] >= 0) continue;
        for (int j = 0; j < 3; j++) {
            const mesh_subseg *ss = mesh_subseg_of_edge(&md, 3 * t + j);
            if (!ss || ss->seg < 0 || ss->seg >= d->g.nsegs) continue;
            int32_t s = ss->seg;
            double c[2];
            centroid(&md, t, c);
            const double *A = d->g.xy + 2 * (size_t)d->g.seg[2 * s],
                         *B = d->g.xy + 2 * (size_t)d->g.seg[2 * s + 1];
            int32_t sub = d->seg_sub[2 * s + (geom_orient2d(A, B, c) > 0 ? 0 : 1)];
            if (sub >= 0 && sub < d->nsub) {
                rsub[lab[t]] = sub;
                break;
            }
        }
    }
    int32_t hint = -1;
    for (int32_t t = 0; t < m0->nt; t++) {
        own[t] = -1;
        if (!mesh_tri_alive(m0, t)) continue;
        double c[2];
        centroid(m0, t, c);
        int32_t tt = mesh_locate(&md, c, hint);
        int32_t sub = -1;
        if (tt >= 0) {
            hint = tt;
            sub = rsub[lab[tt]];
        }
        own[t] = sub >= 0 ? d->sub_owner[sub] : 0;
        if (own[t] < 0 || own[t] >= C->size) own[t] = 0;
    }
    free(rsub);
    free(lab);
    mesh_free(&md);
    return 0;
}

static int32_t *dup_i32(const int32_t *a, size_t n) {
    int32_t *b = mesh_xrealloc(NULL, (n + 1) * sizeof(int32_t), 1);
    if (n) memcpy(b, a, n * sizeof(int32_t));
    return b;
}

/* The initial boundary-conforming mesh: the CDT of the input; with an area bound, refined
 * (identically on every rank, by the sequential refiner) to about PRE_TRIS_PER_RANK triangles
 * per rank but at least PRE_COARSEN times coarser than the bound, so that every rank owns a
 * piece of it (the CDT of a square has two triangles) while nearly all the work is left to the
 * parallel phase. */
#define PRE_TRIS_PER_RANK 32.0
#define PRE_COARSEN 16.0

static int setup(pbw_ctx *C, const pbw_setup_opts *so, const pslg *in, const pcdm_decomp *d,
                 char *err, size_t errlen) {
    mesh m0;
    mesh_init(&m0);
    if (mesh_build_cdt(&m0, in, NULL, err, errlen) != 0) {
        mesh_free(&m0);
        return -1;
    }
    /* the length floor of the initial CDT, as ./mesh computes it from the same CDT */
    C->floor2 = mesh_rules_length_floor2(m0.xy, m0.nv, m0.tv, m0.nt);
    C->unresolved_budget = mesh_rules_unresolved_budget(m0.ninput);
    if (so->max_area > 0 && C->size > 1) {
        double area = 0;
        for (int32_t t = 0; t < m0.nt; t++)
            if (mesh_tri_alive(&m0, t))
                area += geom_area(mesh_vertex_xy(&m0, m0.tv[3 * t]),
                                  mesh_vertex_xy(&m0, m0.tv[3 * t + 1]),
                                  mesh_vertex_xy(&m0, m0.tv[3 * t + 2]));
        double a0 = fmax(area / (PRE_TRIS_PER_RANK * C->size), PRE_COARSEN * so->max_area);
        mesh_quality q;
        memset(&q, 0, sizeof q);
        q.min_angle = so->min_angle;
        q.max_area = a0;
        q.max_steiner = so->max_steiner;
        q.offcenter = 1;
        mesh_set_quality(&m0, &q);
        mesh_refine(&m0);
        C->res.pre_tris = m0.nlive;
    }
    int32_t *own = mesh_xrealloc(NULL, ((size_t)m0.nt + 1) * sizeof(int32_t), 1);
    if (owners(C, &m0, d, own, err, errlen) != 0) {
        free(own);
        mesh_free(&m0);
        return -1;
    }
    int32_t *lidx = mesh_xrealloc(NULL, ((size_t)m0.nt + 1) * sizeof(int32_t), 1);
    int32_t *cnt = mesh_xrealloc(NULL, (size_t)C->size * sizeof(int32_t), 1);
    memset(cnt, 0, (size_t)C->size * sizeof(int32_t));
    for (int32_t t = 0; t < m0.nt; t++)
        lidx[t] = own[t] >= 0 ? cnt[own[t]]++ : -1;
    /* input data */
    C->ninput = m0.ninput;
    C->nseg = m0.nseg;
    C->seg = dup_i32(m0.seg, 2 * (size_t)m0.nseg);
    C->smarker = dup_i32(m0.smarker, (size_t)m0.nseg);
    C->in_vmarker = dup_i32(m0.in_vmarker, (size_t)m0.ninput);
    C->inc_off = dup_i32(m0.inc_off, (size_t)m0.ninput + 1);
    C->inc_seg = dup_i32(m0.inc_seg, (size_t)m0.inc_off[m0.ninput]);
    C->corner = mesh_xrealloc(NULL, (size_t)m0.ninput + 1, 1);
    memcpy(C->corner, m0.corner, (size_t)m0.ninput);
    C->has_corners = m0.has_corners;
    C->I.ninput = C->ninput;
    C->I.seg = C->seg;
    C->I.inc_off = C->inc_off;
    C->I.inc_seg = C->inc_seg;
    C->I.corner = C->has_corners ? C->corner : NULL;
    C->I.siface = NULL; /* PBW has no artificial segments */
    /* initial vertices keep their index as global id (input vertices first) */
    vt_rehash(C, 2048);
    for (int32_t v = 0; v < m0.nv; v++) {
        const double *p = mesh_vertex_xy(&m0, v);
        vt_add(C, v, p[0], p[1], v < m0.ninput ? -1 : m0.vseg[v]);
    }
    /* this rank's triangles, in CDT slot order */
    for (int32_t t = 0; t < m0.nt; t++) {
        if (own[t] != C->rank) continue;
        int32_t s = slot_alloc(C);
        if (s != lidx[t]) MESH_BUG("slot %d for triangle %d (expected %d)", s, t, lidx[t]);
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j;
            size_t f = 3 * (size_t)s + (size_t)j;
            C->tv[f] = m0.tv[e];
            int32_t nb = m0.tn[e];
            C->tn[f] = nb >= 0 ? mkref(own[nb / 3], lidx[nb / 3]) : NOREF;
            const mesh_subseg *ss = mesh_subseg_of_edge(&m0, e);
            if (mesh_edge_constrained(&m0, e) && !ss) MESH_BUG("constraint edge without record");
            C->cs[f] = ss ? ss->seg : -1;
            C->cl[f] = ss ? ss->level : -1;
            C->ck[f] = ss ? ss->k : 0;
        }
        C->nlive++;
    }
    free(cnt);
    free(lidx);
    free(own);
    mesh_free(&m0);
    /* initial work: every bad triangle, every encroached subsegment */
    for (int32_t t = 0; t < C->nt; t++)
        check_new_triangle(C, t);
    return 0;
}

/* The end check of the bounds (as mesh_count_unmet): every triangle this rank owns that is
 * outside them, except a small angle forced by the input (a corner vertex, or the shared
 * forced-angle rule on its shortest edge).  Fills C->res.unmet and C->res.forced. */
static void count_unmet(pbw_ctx *C) {
    for (int32_t t = 0; t < C->nt; t++) {
        if (!alive(C, t)) continue;
        int sh = 0, why = quality(C, t, NULL, &sh);
        if (!why) continue;
        const int32_t *tv = C->tv + 3 * (size_t)t;
        if (why == MESH_BAD_ANGLE &&
            (is_corner_gid(C, C->vgid[tv[0]]) || is_corner_gid(C, C->vgid[tv[1]]) ||
             is_corner_gid(C, C->vgid[tv[2]]) || edge_forced(C, tv[sh], tv[(sh + 1) % 3]))) {
            C->res.forced++;
            continue;
        }
        C->res.unmet++;
    }
}

/* Test-only fault (env PBW_TEST_BREAK_IFACE=R): rank R loses the first triangle it owns that
 * has a neighbour on another rank, as if a commit had been lost at a rank boundary, so the
 * result no longer matches across that boundary.  The always-on end check (par_output's
 * interface check) must then fail every rank; tests/t_pbw.sh shows it does. */
static void test_fault(pbw_ctx *C) {
    const char *e = getenv("PBW_TEST_BREAK_IFACE");
    if (!e || !*e || atoi(e) != C->rank) return;
    for (int32_t t = 0; t < C->nt; t++) {
        if (!alive(C, t) || C->lk[t] >= 0) continue;
        for (int j = 0; j < 3; j++) {
            int64_t n = C->tn[3 * (size_t)t + (size_t)j];
            if (n != NOREF && ref_rank(n) != C->rank) {
                slot_free(C, t);
                C->nlive--;
                return;
            }
        }
    }
}

/* This rank's triangles as a mesh_flat (local numbering of the vertices they use). */
static int to_flat(pbw_ctx *C, mesh_flat *f) {
    memset(f, 0, sizeof *f);
    int32_t *map = mesh_xrealloc(NULL, ((size_t)C->nv + 1) * sizeof(int32_t), 1);
    for (int32_t v = 0; v < C->nv; v++)
        map[v] = -1;
    int32_t nv = 0, ntri = 0, nseg = 0;
    for (int32_t t = 0; t < C->nt; t++) {
        if (!alive(C, t) || C->lk[t] >= 0) continue;
        ntri++;
        for (int j = 0; j < 3; j++) {
            int32_t v = C->tv[3 * (size_t)t + (size_t)j];
            if (map[v] < 0) map[v] = nv++;
            if (C->cs[3 * (size_t)t + (size_t)j] >= 0) nseg++;
        }
    }
    f->nverts = nv;
    f->xy = mesh_xrealloc(NULL, 2 * ((size_t)nv + 1) * sizeof(double), 1);
    f->vmarker = mesh_xrealloc(NULL, ((size_t)nv + 1) * sizeof(int32_t), 1);
    for (int32_t v = 0; v < C->nv; v++) {
        int32_t o = map[v];
        if (o < 0) continue;
        f->xy[2 * o] = C->xy[2 * v];
        f->xy[2 * o + 1] = C->xy[2 * v + 1];
        int64_t g = C->vgid[v];
        f->vmarker[o] = (g >= 0 && g < C->ninput) ? C->in_vmarker[g]
                        : C->vseg[v] >= 0         ? C->smarker[C->vseg[v]]
                                                  : 0;
    }
    f->ntris = ntri;
    f->tri = mesh_xrealloc(NULL, 3 * ((size_t)ntri + 1) * sizeof(int32_t), 1);
    f->trank = mesh_xrealloc(NULL, ((size_t)ntri + 1) * sizeof(int32_t), 1);
    f->nsegs = nseg;
    f->seg = mesh_xrealloc(NULL, 2 * ((size_t)nseg + 1) * sizeof(int32_t), 1);
    f->smarker = mesh_xrealloc(NULL, ((size_t)nseg + 1) * sizeof(int32_t), 1);
    f->sinterface = mesh_xrealloc(NULL, ((size_t)nseg + 1) * sizeof(int32_t), 1);
    ntri = nseg = 0;
    for (int32_t t = 0; t < C->nt; t++) {
        if (!alive(C, t) || C->lk[t] >= 0) continue;
        for (int j = 0; j < 3; j++) {
            size_t e = 3 * (size_t)t + (size_t)j;
            f->tri[3 * (size_t)ntri + (size_t)j] = map[C->tv[e]];
            if (C->cs[e] >= 0) {
                f->seg[2 * (size_t)nseg] = map[C->tv[e]];
                f->seg[2 * (size_t)nseg + 1] = map[C->tv[3 * (size_t)t + (size_t)((j + 1) % 3)]];
                f->smarker[nseg] = C->smarker[C->cs[e]];
                f->sinterface[nseg] = 0;
                nseg++;
            }
        }
        f->trank[ntri] = C->rank;
        ntri++;
    }
    free(map);
    return 0;
}

static void ctx_free(pbw_ctx *C) {
    free(C->xy), free(C->vgid), free(C->vseg), free(C->vh);
    free(C->tv), free(C->tn), free(C->cs), free(C->cl), free(C->ck), free(C->lk), free(C->role);
    free(C->fre);
    free(C->seg), free(C->smarker), free(C->in_vmarker), free(C->inc_off), free(C->inc_seg);
    free(C->corner);
    free(C->pool);
    iv_free(&C->splitq), iv_free(&C->retryq), iv_free(&C->deferred), iv_free(&C->phase2);
    for (int32_t i = 0; i < C->nhd; i++)
        free(C->hd[i].slots);
    free(C->hd);
    free(C->wt);
    for (int32_t i = 0; i < C->npk; i++)
        cav_free(C->pk[i]);
    free(C->pk);
    free(C->dy);
    if (C->dbg_f) fclose(C->dbg_f);
    free(C);
}

static size_t mesh_bytes(pbw_ctx *C) {
    size_t c = (size_t)C->tcap;
    size_t b = c * (3 * (4 + 8 + 4 + 4 + 8) + 4 + 1);
    b += (size_t)C->vcap * (16 + 8 + 4) + (size_t)C->vhcap * 4 + (size_t)C->frecap * 4;
    b += (size_t)C->poolcap * sizeof(qent);
    return b;
}

/* ---- public API ---------------------------------------------------------------------------- */

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

int pbw_mesh(const par_opts *o, const pslg *in, const pcdm_decomp *d, mesh_flat *local,
             pbw_result *res) {
    if (pbw_active) MESH_BUG("pbw_mesh called while another pbw_mesh runs");
    pbw_ctx *C = mesh_xcalloc(1, sizeof *C);
    memcpy(C->hid, pbw_hid, sizeof C->hid);
    C->rank = rt_rank();
    C->size = rt_size();
    C->pool_free = -1;
    C->cursor = NBUCKET + 1;
    for (int i = 0; i <= NBUCKET; i++)
        C->head[i] = -1;
    /* a hair above the requested bound, as ./mesh and ./pcdm do; the area bound in the
     * working scale of the coordinates (pslg_check), as refine.c takes it */
    double qa = o->min_angle > 0 ? o->min_angle * (1 + 1e-9) + 1e-12 : 0;
    if (qa > 60) qa = 60;
    double area = o->max_area;
    if (area > 0 && in->scale_exp != 0) {
        area = ldexp(area, 2 * in->scale_exp);
        if (!(area > 0)) area = DBL_MIN;
    }
    mesh_rules_init(&C->R, qa, area, 1, 0);
    C->steiner_limit = o->max_steiner >= 0 ? (o->max_steiner + C->size - 1) / C->size : -1;
    memset(local, 0, sizeof *local);
    char err[1024], msg[1200];
    err[0] = 0;
    pbw_setup_opts so = {qa, o->max_area, o->max_steiner};
    pbw_active = C; /* the handlers' way to the context (pbw_register) */
    int rc = setup(C, &so, in, d, err, sizeof err);
    snprintf(msg, sizeof msg, "%s: %s", o->prog ? o->prog : "pbw", err);
    if (par_fail_any(rc != 0, msg)) {
        pbw_active = NULL;
        ctx_free(C);
        return -1;
    }
    if (o->phases) {
        double t0 = rt_wtime();
        C->phase1 = 1;
        rt_run(work, C);
        C->phase1 = 0;
        pbw_item it;
        while (iv_pop(&C->phase2, &it))
            iv_push(&C->retryq, &it);
        C->res.phase1_s = rt_wtime() - t0;
    }
    rt_run(work, C);
    if (C->npk != 0 || C->inflight != 0)
        MESH_BUG("%d parked, %d in flight at the end", C->npk, C->inflight);
    for (int32_t i = 0; i < C->nhd; i++)
        if (C->hd[i].active)
            MESH_BUG("cavity %llx still holds locks", (unsigned long long)C->hd[i].key);
    count_unmet(C);
    test_fault(C);
    to_flat(C, local);
    C->res.ntris = C->nlive;
    C->res.mesh_bytes = mesh_bytes(C);
    for (int k = 0; k < PBW_RSR_NKINDS; k++) {
        rt_handler_stats hs;
        if (rt_stats_handler(C->hid[k], &hs) == RT_OK) C->res.rsr_sent[k] = hs.sent;
    }
    if (res) *res = C->res;
    pbw_active = NULL;
    ctx_free(C);
    return 0;
}
