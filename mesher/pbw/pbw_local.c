/* pbw_local.c: the local fast path of a Steiner point -- a Bowyer-Watson insertion that
 * stays on this rank, done in place on the store, without the travelling cavity state.
 *
 * Most cavities (over 90% at 8 ranks, all on one rank) touch only this rank's unlocked
 * triangles.  For those the general protocol (pbw_cavity.c: seeds, reserved slots, boundary
 * records, the fan built through hash maps, then applied as a commit) is bookkeeping that
 * decides nothing.  Here the cavity is collected by a depth-first search from the bad
 * triangle (a neighbour is a member iff p lies strictly in its circumcircle, exact incircle;
 * never across a constraint edge), its boundary edges are checked as the general path checks
 * them (p strictly left of each: star-shaped; p encroaching no subsegment), and the fan is
 * written over the members' slots (two more are allocated), each new triangle linked to its
 * fan neighbours through a scratch array indexed by vertex slot.
 *
 * Anything else goes to the general path, which decides it exactly as before: a remote or
 * ghost neighbour, a tombstone, a locked triangle (member or halo), a member reached twice (the
 * cavity encloses a vertex), a boundary that is not star-shaped, or p encroaching a
 * subsegment (then the subsegments are split).  Nothing is written before that decision, and
 * the search's member marks are cleared, so falling back costs only the search.
 * Invariant kept: a boundary edge's link (with its record, pbw_con, if it is constrained) moves
 * with the edge to the new triangle on it; a member's other edges are interior and hold none.
 */
#include "pbw/pbw_impl.h"

#include <stdlib.h>
#include <string.h>

/* A boundary edge a->b (vertex slots) of member x's edge j (the cavity on its left); out: the
 * triangle across it (NOREF: none); link: x's raw tn there (the outside slot, -1, or its record),
 * reg: x's region -- both carried over to the new triangle on the edge. */
typedef struct lbnd {
    int64_t out;
    int32_t a, b, link, reg;
} lbnd;

/* The fast path's scratch arrays, kept in the context between calls. */
struct pbw_lscratch {
    int32_t *stk, nstk, scap; /* members to expand */
    int32_t *mem, nmem, mcap; /* members, in the order found */
    lbnd *bd;
    int32_t nbd, bcap;
    int32_t *vfan, vcap; /* per vertex slot: the new triangle whose edge 0 starts there, -1 */
};

void pbw_lscratch_free(pbw_lscratch *S) {
    if (!S) return;
    free(S->stk);
    free(S->mem);
    free(S->bd);
    free(S->vfan);
    free(S);
}

static void unmark(pbw_ctx *C, pbw_lscratch *S) {
    for (int32_t i = 0; i < S->nmem; i++)
        C->role[S->mem[i]] = ROLE_NONE;
}

/* Collects the cavity of p from t.  1 if it is purely local and may be committed here. */
static int collect(pbw_ctx *C, pbw_lscratch *S, const double p[2], int32_t t) {
    S->nstk = S->nmem = S->nbd = 0;
    if (C->role[t] != ROLE_NONE) return 0; /* locked (a locked slot has a role), or marked */
    C->role[t] = ROLE_MEMBER;
    MESH_GROW(S->mem, S->nmem, S->mcap);
    S->mem[S->nmem++] = t;
    MESH_GROW(S->stk, S->nstk, S->scap);
    S->stk[S->nstk++] = t;
    while (S->nstk > 0) {
        int32_t x = S->stk[--S->nstk];
        for (int j = 0; j < 3; j++) {
            size_t e = 3 * (size_t)x + (size_t)j;
            int64_t n = TN(C, e);
            int constrained = CS(C, e) >= 0;
            int32_t y = -1;
            if (n != NOREF) {
                if (ref_rank(n) != C->rank) return 0; /* a remote (or ghost) neighbour */
                y = ref_idx(n);
                if (C->role[y] == ROLE_MEMBER) {
                    /* the member it came from, or a second way in (a cycle): the edge is
                     * interior either way; a cycle shows as an edge seen from one side only */
                    continue;
                }
                if (C->role[y] != ROLE_NONE) return 0; /* locked: a lock gives a role */
            } else if (!constrained) {
                return 0; /* the domain boundary is always constrained in a CDT */
            }
            if (!constrained && y >= 0) {
                const int32_t *tv = C->tv + 3 * (size_t)y;
                if (geom_incircle(VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2]), p) > 0) {
                    C->role[y] = ROLE_MEMBER;
                    MESH_GROW(S->mem, S->nmem, S->mcap);
                    S->mem[S->nmem++] = y;
                    MESH_GROW(S->stk, S->nstk, S->scap);
                    S->stk[S->nstk++] = y;
                    continue;
                }
            }
            int32_t a = C->tv[e], b = C->tv[3 * (size_t)x + (size_t)((j + 1) % 3)];
            if (geom_orient2d(VX(C, a), VX(C, b), p) <= 0) return 0; /* not star-shaped */
            if (constrained && mesh_rules_encroaches(&C->R, VX(C, a), VX(C, b), p)) return 0;
            MESH_GROW(S->bd, S->nbd, S->bcap);
            S->bd[S->nbd++] = (lbnd){n, a, b, C->tn[e], C->treg ? C->treg[x] : -1};
        }
    }
    /* a disk whose vertices all lie on its boundary: as many boundary edges as members + 2
     * (a member reached twice, i.e. a vertex inside, breaks it), every vertex starting one */
    if (S->nbd != S->nmem + 2) return 0;
    if (S->vcap < C->nv) {
        int32_t cap = S->vcap ? S->vcap : 1024;
        while (cap < C->nv)
            cap *= 2;
        S->vfan = mesh_xrealloc(S->vfan, (size_t)cap * sizeof(int32_t), 1);
        for (int32_t v = S->vcap; v < cap; v++)
            S->vfan[v] = -1;
        S->vcap = cap;
    }
    int ok = 1;
    for (int32_t i = 0; i < S->nbd; i++) {
        if (S->vfan[S->bd[i].a] >= 0) ok = 0;
        S->vfan[S->bd[i].a] = i;
    }
    for (int32_t i = 0; i < S->nbd && ok; i++)
        if (S->vfan[S->bd[i].b] < 0) ok = 0;
    if (!ok)
        for (int32_t i = 0; i < S->nbd; i++)
            S->vfan[S->bd[i].a] = -1;
    return ok;
}

int pbw_local_insert(pbw_ctx *C, const double p[2], int32_t t) {
    if (!C->ls) {
        C->ls = mesh_xrealloc(NULL, sizeof *C->ls, 1);
        memset(C->ls, 0, sizeof *C->ls);
    }
    pbw_lscratch *S = C->ls;
    if (!collect(C, S, p, t)) {
        unmark(C, S);
        return 0;
    }
    int64_t pgid = ((int64_t)(C->rank + 1) << 32) | C->nvown;
    int32_t pv = pbw_vt_add(C, pgid, p[0], p[1], -1);
    C->nvown++;
    C->res.steiner++;
    int32_t nb = S->nbd, nm = S->nmem;
    /* slots: the members', then two more (the stack array holds the list); every edge of a
     * reused slot is rewritten: a member edge is a boundary edge (its link moves) or interior
     * (local, unconstrained: no record, see the invariant above) */
    MESH_GROW(S->stk, nb, S->scap);
    int32_t *slot = S->stk;
    for (int32_t i = 0; i < nb; i++)
        slot[i] = i < nm ? S->mem[i] : pbw_slot_alloc(C);
    for (int32_t i = 0; i < nb; i++) {
        const lbnd *bd = &S->bd[i];
        size_t e = 3 * (size_t)slot[i];
        C->tv[e] = bd->a;
        C->tv[e + 1] = bd->b;
        C->tv[e + 2] = pv;
        C->tn[e] = bd->link; /* the edge keeps its link and record (con[].nb is still out) */
        C->role[slot[i]] = ROLE_NONE;
        if (C->treg) C->treg[slot[i]] = bd->reg;
    }
    for (int32_t i = 0; i < nb; i++) {
        const lbnd *bd = &S->bd[i];
        int32_t k = S->vfan[bd->b];               /* the new triangle (b, c, p): across b->p */
        C->tn[3 * (size_t)slot[i] + 1] = slot[k]; /* interior edges: plain local links */
        C->tn[3 * (size_t)slot[k] + 2] = slot[i];
        if (bd->out != NOREF) {
            int32_t y = ref_idx(bd->out);
            int32_t *ty = C->tv + 3 * (size_t)y;
            int jy = ty[0] == bd->b ? 0 : ty[1] == bd->b ? 1 : 2;
            if (ty[jy] != bd->b || ty[(jy + 1) % 3] != bd->a)
                MESH_BUG("triangle %d across a cavity edge lacks the edge", y);
            pbw_tn_set(C, 3 * (size_t)y + (size_t)jy, mkref(C->rank, slot[i]));
        }
    }
    for (int32_t i = 0; i < nb; i++)
        S->vfan[S->bd[i].a] = -1;
    C->nlive += nb - nm;
    C->res.cavities_local++;
    C->res.inserted++;
    for (int32_t i = 0; i < nb; i++)
        pbw_check_new_triangle(C, slot[i]);
    return 1;
}
