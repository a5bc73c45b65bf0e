/* pbw_store.c: PBW's distributed mesh store on one rank -- the vertex table (global id ->
 * slot: direct for the initial vertices and this rank's own, open addressing for the vertices
 * of other ranks), the triangle slots (3 vertex slots and 3 int32 neighbour links each, a lock
 * and a role; a tombstone slot is never reused), the edge records (a side table for the few
 * edges that need more than a local link: a remote neighbour's (rank, slot) reference, the
 * constraint names, the ghost apex of a remote neighbour), and the bad-triangle queue with the
 * quality questions asked of the shared rules (seq/rules.h: what is bad, the Steiner point,
 * the forced small angle, the length floor).  Invariants: a slot is dead iff tv[3s] < 0; every
 * vertex a live slot uses is in the table, with the same coordinates on every rank; initial
 * vertex i (input vertices first) is slot i; an edge has a record iff its neighbour is remote,
 * it is constrained or it keeps a ghost.  Part of TR-97-17 section 2 (pbw.c). */
#include "pbw/pbw_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Vertex ids this rank finds without the hash table: an initial vertex (id < ninit) is the slot
 * of that index; one this rank made (id (rank + 1) << 32 | n) is own[n].  Only the vertices
 * other ranks made are hashed (none on one rank). */
static int direct(const pbw_ctx *C, int64_t gid) {
    return (gid >= 0 && gid < C->ninit) || (gid >> 32) == (int64_t)C->rank + 1;
}

int32_t pbw_vt_find(pbw_ctx *C, int64_t gid) {
    if (gid >= 0 && gid < C->ninit) return gid < C->nv ? (int32_t)gid : -1;
    if ((gid >> 32) == (int64_t)C->rank + 1) {
        int64_t n = gid & 0xffffffff;
        return n < C->nown ? C->own[n] : -1;
    }
    uint32_t mask = C->vhcap - 1, h = (uint32_t)mesh_hash64((uint64_t)gid) & mask;
    while (C->vh[h] >= 0) {
        if (C->vgid[C->vh[h]] == gid) return C->vh[h];
        h = (h + 1) & mask;
    }
    return -1;
}

void pbw_vt_rehash(pbw_ctx *C, uint32_t cap) {
    free(C->vh);
    C->vhcap = cap;
    C->vh = mesh_xrealloc(NULL, (size_t)cap * sizeof(int32_t), 1);
    for (uint32_t i = 0; i < cap; i++)
        C->vh[i] = -1;
    for (int32_t v = 0; v < C->nv; v++) {
        if (direct(C, C->vgid[v])) continue;
        uint32_t h = (uint32_t)mesh_hash64((uint64_t)C->vgid[v]) & (cap - 1);
        while (C->vh[h] >= 0)
            h = (h + 1) & (cap - 1);
        C->vh[h] = v;
    }
}

int32_t pbw_vt_add(pbw_ctx *C, int64_t gid, double x, double y, int32_t vseg) {
    int32_t v = pbw_vt_find(C, gid);
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
    if (gid >= 0 && gid < C->ninit) {
        if (v != gid) MESH_BUG("initial vertex %lld added as slot %d", (long long)gid, v);
        return v;
    }
    if ((gid >> 32) == (int64_t)C->rank + 1) {
        int64_t n = gid & 0xffffffff;
        while (C->nown <= n) {
            MESH_GROW(C->own, C->nown, C->owncap);
            C->own[C->nown++] = -1;
        }
        C->own[n] = v;
        return v;
    }
    if (2 * (uint32_t)(C->nvh + 1) >= C->vhcap) pbw_vt_rehash(C, C->vhcap ? 2 * C->vhcap : 2048);
    uint32_t h = (uint32_t)mesh_hash64((uint64_t)gid) & (C->vhcap - 1);
    while (C->vh[h] >= 0)
        h = (h + 1) & (C->vhcap - 1);
    C->vh[h] = v;
    C->nvh++;
    return v;
}

int32_t pbw_slot_alloc(pbw_ctx *C) {
    int32_t s;
    if (C->nfree > 0) {
        s = C->fre[--C->nfree];
    } else {
        if (C->nt >= C->tcap) {
            C->tcap = C->tcap ? 2 * C->tcap : 1024;
            size_t c = (size_t)C->tcap;
            C->tv = mesh_xrealloc(C->tv, 3 * c * sizeof(int32_t), 1);
            C->tn = mesh_xrealloc(C->tn, 3 * c * sizeof(int32_t), 1);
            C->role = mesh_xrealloc(C->role, c, 1);
            if (C->treg) C->treg = mesh_xrealloc(C->treg, c * sizeof(int32_t), 1);
        }
        s = C->nt++;
    }
    C->tv[3 * (size_t)s] = -1;
    for (int j = 0; j < 3; j++)
        C->tn[3 * (size_t)s + (size_t)j] = -1;
    C->role[s] = ROLE_NONE;
    if (C->treg) C->treg[s] = -1;
    return s;
}

/* Edge e's record, made (holding its neighbour; no constraint, no ghost) if it has none. */
static int32_t rec_make(pbw_ctx *C, size_t e) {
    int32_t i = REC(C, e);
    if (i >= 0) return i;
    int64_t nb = TN(C, e);
    if (C->confree >= 0) {
        i = C->confree;
        C->confree = (int32_t)C->con[i].nb;
    } else {
        MESH_GROW(C->con, C->ncon, C->concap);
        i = C->ncon++;
    }
    C->con[i] = (pbw_con){nb, 0, -1, -1, -1, 0};
    C->tn[e] = -2 - i;
    return i;
}

/* Frees edge e's record (its neighbour goes back into tn if it is local or none). */
static void rec_free(pbw_ctx *C, size_t e, int32_t i) {
    int64_t nb = C->con[i].nb;
    C->con[i].nb = C->confree;
    C->confree = i;
    C->tn[e] = nb == NOREF ? -1 : ref_idx(nb);
}

/* Releases edge e's record if it holds nothing a plain tn cannot. */
static void rec_trim(pbw_ctx *C, size_t e) {
    int32_t i = REC(C, e);
    if (i < 0 || C->con[i].seg >= 0 || C->con[i].gx >= 0) return;
    int64_t nb = C->con[i].nb;
    if (nb != NOREF && ref_rank(nb) != C->rank) return;
    rec_free(C, e, i);
}

void pbw_tn_set(pbw_ctx *C, size_t e, int64_t ref) {
    int32_t i = REC(C, e);
    if (i >= 0) {
        C->con[i].nb = ref;
        rec_trim(C, e);
    } else if (ref == NOREF) {
        C->tn[e] = -1;
    } else if (ref_rank(ref) == C->rank) {
        C->tn[e] = ref_idx(ref);
    } else {
        C->tn[e] = -1;
        int32_t k = rec_make(C, e); /* first: it may move C->con */
        C->con[k].nb = ref;
    }
}

void pbw_con_set(pbw_ctx *C, size_t e, int32_t seg, int32_t lev, int64_t k) {
    if (seg < 0) {
        if (REC(C, e) >= 0) C->con[REC(C, e)].seg = -1;
        rec_trim(C, e);
        return;
    }
    int32_t i = rec_make(C, e); /* first: it may move C->con */
    pbw_con *r = &C->con[i];
    r->seg = seg;
    r->lev = lev;
    r->k = k;
}

void pbw_gx_set(pbw_ctx *C, size_t e, int32_t gx) {
    if (gx < 0) {
        if (REC(C, e) >= 0) C->con[REC(C, e)].gx = -1;
        rec_trim(C, e);
        return;
    }
    int32_t i = rec_make(C, e); /* first: it may move C->con */
    C->con[i].gx = gx;
}

void pbw_slot_free(pbw_ctx *C, int32_t s) {
    for (int j = 0; j < 3; j++) {
        size_t e = 3 * (size_t)s + (size_t)j;
        if (REC(C, e) >= 0) rec_free(C, e, REC(C, e));
        C->tn[e] = -1;
    }
    C->tv[3 * (size_t)s] = -1;
    pbw_lk_set(C, s, -1);
    C->role[s] = ROLE_NONE;
    MESH_GROW(C->fre, C->nfree, C->frecap);
    C->fre[C->nfree++] = s;
}

/* Edge j of t going from vertex id ga to gb, or -1. */
int pbw_find_edge(pbw_ctx *C, int32_t t, int64_t ga, int64_t gb) {
    for (int j = 0; j < 3; j++)
        if (TG(C, t, j) == ga && TG(C, t, (j + 1) % 3) == gb) return j;
    return -1;
}

/* MESH_BAD_ANGLE / MESH_BAD_AREA bits (mesh_rules_bad), 0: good.  *bucket (may be NULL): queue
 * priority (mesh_rules_bucket: shortest edge first, as refine.c).  *sh: shortest edge j. */
int pbw_quality(pbw_ctx *C, int32_t t, int *bucket, int *sh) {
    const int32_t *tv = C->tv + 3 * (size_t)t;
    const double *p[3] = {VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2])};
    double l2;
    double rb = C->treg && C->treg[t] >= 0 ? C->reg_area[C->treg[t]] : 0;
    int res = mesh_rules_bad_bound(&C->R, mesh_rules_area_bound(C->R.max_area, rb), p, sh, &l2);
    if (res && bucket) *bucket = mesh_rules_bucket(l2);
    return res;
}

void pbw_push_bad(pbw_ctx *C, int32_t t) {
    int k;
    if (!pbw_quality(C, t, &k, NULL)) return;
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

int32_t pbw_pop_bad(pbw_ctx *C) {
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

int pbw_is_corner_gid(pbw_ctx *C, int64_t g) {
    return g >= 0 && g < C->ninput && C->corner[g];
}

/* The shared forced-angle rule (mesh_rules_edge_forced) for the shortest edge lu-lv (vertex
 * slots): an input vertex is named by its id, a Steiner vertex by the segment it lies on. */
int pbw_edge_forced(pbw_ctx *C, int32_t lu, int32_t lv) {
    if (!C->has_corners) return 0;
    C->I.xy = C->xy; /* input vertex i is slot i (setup); the array moves as it grows */
    int64_t u = C->vgid[lu], v = C->vgid[lv];
    int32_t iu = u >= 0 && u < C->ninput ? (int32_t)u : -1;
    int32_t iv = v >= 0 && v < C->ninput ? (int32_t)v : -1;
    return mesh_rules_edge_forced(&C->I, iu, iu < 0 ? C->vseg[lu] : -1, VX(C, lu), iv,
                                  iv < 0 ? C->vseg[lv] : -1, VX(C, lv));
}

/* 1 iff a new vertex at p would make an edge to vertex slot a shorter than the floor. */
int pbw_below_floor(pbw_ctx *C, const double p[2], int32_t a) {
    return geom_dist2(p, VX(C, a)) < C->floor2;
}

/* Counts a refusal (a split or Steiner point below the length floor); past the budget this
 * rank's refinement is diverging (an angle bound beyond reach, or features below the precision
 * of the coordinates) and it stops, as refine.c does (MESH_REFINE_UNRESOLVED). */
void pbw_refuse(pbw_ctx *C) {
    C->res.unresolved++;
    if (C->res.unresolved > C->unresolved_budget) {
        C->stopped = 1;
        C->res.gave_up = 1;
    }
}

/* Steiner point of bad triangle t (mesh_rules_steiner, on the working grid).  0, or -1. */
int pbw_steiner_point(pbw_ctx *C, int32_t t, int sh, double out[2]) {
    const int32_t *tv = C->tv + 3 * (size_t)t;
    const double *p[3] = {VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2])};
    if (mesh_rules_steiner(&C->R, p, sh, out) != 0) return -1;
    return geom_working_point(out);
}
