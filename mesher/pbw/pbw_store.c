/* pbw_store.c: PBW's distributed mesh on one rank.  The local triangles and vertices are the
 * shared kernel's mesh (seq/mesh.h: the same slots, edge-coded links, constraint bits,
 * subsegment table and free list as ./mesh, and its Bowyer-Watson cavity for the local fast
 * path, pbw_local.c); what PBW adds is small: the global vertex ids (direct for the initial
 * vertices and this rank's own, open addressing for the vertices of other ranks), a side table
 * of records for the edges whose neighbour is on another rank (its (rank, slot) reference and
 * the ghost apex, GHOSTS in pbw.c; tn = -2 - record there), the role of a slot in tf's caller
 * bits (a lock, a reservation, a tombstone: the kernel's cavities never touch it), and the
 * bad-triangle queue with the quality questions asked of the shared rules (seq/rules.h: what
 * is bad, the Steiner point, the forced small angle, the length floor).  Invariants: a slot is
 * dead or reserved iff tv[3s] < 0; local links are an involution (tn[tn[e]] == e) on live
 * slots (a tombstone's forward links point one way); every vertex a live slot uses is in the
 * table, with the same coordinates on every rank; initial vertex i (input vertices first) is
 * slot i; an edge has a record iff its neighbour is remote.  Part of TR-97-17 section 2
 * (pbw.c). */
#include "pbw/pbw_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Vertex ids this rank finds without the hash table: an initial vertex (id < ninit) is the slot
 * of that index; one this rank made (id (rank + 1) << 32 | n) is own[n].  Only the vertices
 * other ranks made are hashed (none on one rank). */
int32_t pbw_vt_find(pbw_ctx *C, int64_t gid) {
    if (gid >= 0 && gid < C->ninit) return gid < C->M.nv ? (int32_t)gid : -1;
    if ((gid >> 32) == (int64_t)C->rank + 1) {
        int64_t n = gid & 0xffffffff;
        return n < C->nown ? C->own[n] : -1;
    }
    if (C->vhcap == 0) return -1;
    uint32_t mask = C->vhcap - 1, h = (uint32_t)mesh_hash64((uint64_t)gid) & mask;
    while (C->vh[h] >= 0) {
        if (C->vgid[C->vh[h]] == gid) return C->vh[h];
        h = (h + 1) & mask;
    }
    return -1;
}

/* The table at cap entries (a power of two), holding what it held: its entries are moved, not
 * found again among all the vertices (most are direct: a scan of them cost 6M instructions per
 * doubling at 600K vertices a rank). */
void pbw_vt_rehash(pbw_ctx *C, uint32_t cap) {
    int32_t *old = C->vh;
    uint32_t oldcap = C->vhcap;
    C->vhcap = cap;
    C->vh = mesh_xrealloc(NULL, (size_t)cap, sizeof(int32_t));
    for (uint32_t i = 0; i < cap; i++)
        C->vh[i] = -1;
    for (uint32_t i = 0; i < oldcap; i++) {
        int32_t v = old[i];
        if (v < 0) continue;
        uint32_t h = (uint32_t)mesh_hash64((uint64_t)C->vgid[v]) & (cap - 1);
        while (C->vh[h] >= 0)
            h = (h + 1) & (cap - 1);
        C->vh[h] = v;
    }
    free(old);
}

int32_t pbw_vt_add(pbw_ctx *C, int64_t gid, double x, double y, int32_t vseg) {
    int32_t v = pbw_vt_find(C, gid);
    if (v >= 0) return v;
    v = mesh_vert_add(&C->M, x, y, vseg);
    if (v >= C->vgcap) {
        C->vgcap = C->M.vcap;
        C->vgid = mesh_xrealloc(C->vgid, (size_t)C->vgcap, sizeof(int64_t));
    }
    C->vgid[v] = gid;
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
    int32_t s = mesh_tri_new(&C->M); /* tf (constraints, role) cleared, treg -1 */
    for (int j = 0; j < 3; j++) {
        C->M.tv[3 * (size_t)s + (size_t)j] = MESH_DEAD;
        C->M.tn[3 * (size_t)s + (size_t)j] = -1;
    }
    return s;
}

/* A new record holding remote neighbour nb (no ghost) for edge e. */
static void rec_make(pbw_ctx *C, size_t e, int64_t nb) {
    int32_t i;
    if (C->confree >= 0) {
        i = C->confree;
        C->confree = (int32_t)C->con[i].nb;
    } else {
        MESH_GROW(C->con, C->ncon, C->concap);
        i = C->ncon++;
    }
    C->con[i] = (pbw_con){nb, -1, (int32_t)e};
    C->M.tn[e] = -2 - i;
}

/* Frees edge e's record, if it has one (tn becomes -1). */
static void rec_free(pbw_ctx *C, size_t e) {
    int32_t i = REC(C, e);
    if (i < 0) return;
    C->con[i].nb = C->confree;
    C->con[i].e = -1;
    C->confree = i;
    C->M.tn[e] = -1;
}

void pbw_tn_set(pbw_ctx *C, size_t e, int64_t ref) {
    if (ref != NOREF && ref_rank(ref) != C->rank) {
        if (REC(C, e) >= 0)
            C->con[REC(C, e)].nb = ref;
        else
            rec_make(C, e, ref);
        return;
    }
    rec_free(C, e);
    if (ref == NOREF) {
        C->M.tn[e] = -1;
        return;
    }
    /* the same edge in triangle y, reversed */
    int32_t y = ref_idx(ref), a = C->M.tv[e], b = C->M.tv[mesh_edge_next((int32_t)e)];
    const int32_t *ty = C->M.tv + 3 * (size_t)y;
    for (int j = 0; j < 3; j++)
        if (ty[j] == b && ty[(j + 1) % 3] == a) {
            C->M.tn[e] = 3 * y + j;
            return;
        }
    MESH_BUG("slot %d has no edge %d->%d to link to", y, b, a);
}

void pbw_forward_set(pbw_ctx *C, size_t e, int32_t y) {
    rec_free(C, e);
    int32_t a = C->M.tv[e], b = C->M.tv[mesh_edge_next((int32_t)e)];
    const int32_t *ty = C->M.tv + 3 * (size_t)y;
    for (int j = 0; j < 3; j++)
        if (ty[j] == a && ty[(j + 1) % 3] == b) {
            C->M.tn[e] = 3 * y + j;
            return;
        }
    MESH_BUG("slot %d does not replace edge %d->%d", y, a, b);
}

void pbw_con_set(pbw_ctx *C, size_t e, int32_t seg, int32_t lev, int64_t k) {
    uint8_t bit = (uint8_t)(1u << (e % 3));
    if (seg < 0) {
        C->M.tf[e / 3] &= (uint8_t)~bit;
        return;
    }
    C->M.tf[e / 3] |= bit;
    int32_t u = C->M.tv[e], v = C->M.tv[mesh_edge_next((int32_t)e)];
    int32_t r = mesh_ss_find_pair(&C->M, u, v);
    if (r >= 0) {
        const mesh_subseg *ss = &C->M.ss[r];
        if (ss->seg == seg && ss->level == lev && ss->k == k) return;
        mesh_ss_del(&C->M, r);
    }
    mesh_ss_add(&C->M, u, v, seg, lev, k);
}

void pbw_gx_set(pbw_ctx *C, size_t e, int32_t gx) {
    int32_t i = REC(C, e);
    if (i >= 0)
        C->con[i].gx = gx;
    else if (gx >= 0)
        MESH_BUG("ghost apex on edge %zu, whose neighbour is not remote", e);
}

void pbw_slot_free(pbw_ctx *C, int32_t s) {
    for (int j = 0; j < 3; j++)
        rec_free(C, 3 * (size_t)s + (size_t)j);
    pbw_lk_set(C, s, -1);
    mesh_tri_kill(&C->M, s); /* role and constraint bits cleared with tf */
}

/* Edge j of t going from vertex id ga to gb, or -1. */
int pbw_find_edge(pbw_ctx *C, int32_t t, int64_t ga, int64_t gb) {
    for (int j = 0; j < 3; j++)
        if (TG(C, t, j) == ga && TG(C, t, (j + 1) % 3) == gb) return j;
    return -1;
}

/* Makes room in a full bucket, as refine.c's queue: doubles its stack, or once it holds
 * QUEUE_COMPACT entries, first drops the entries whose slot is no longer queued (the triangle
 * died or its slot was rewritten: either is skipped when popped), keeping the order of the rest,
 * and doubles only if that freed less than half.  Most entries go stale before they are popped
 * (a queued triangle falls into a neighbour's cavity), so the queue stays near its live size. */
#define QUEUE_COMPACT 4096

static void make_room(pbw_ctx *C, pbw_qstack *q) {
    if (q->cap >= QUEUE_COMPACT) {
        int32_t n = 0;
        for (int32_t i = 0; i < q->n; i++) {
            int32_t t = q->t[i];
            if (C->M.tf[t] & MESH_QUEUED) q->t[n++] = t;
        }
        q->n = n;
    }
    if (2 * q->n >= q->cap) {
        q->cap = q->cap ? 2 * q->cap : 256;
        q->t = mesh_xrealloc(q->t, (size_t)q->cap, sizeof(int32_t));
    }
}

void pbw_push_bad(pbw_ctx *C, int32_t t) {
    int k;
    if (!pbw_quality(C, t, &k, NULL)) return;
    C->M.tf[t] |= MESH_QUEUED; /* cleared when the slot is rewritten: see pbw_pop_bad */
    pbw_qstack *q = &C->q[k];
    if (q->n == q->cap) make_room(C, q);
    q->t[q->n++] = t; /* LIFO inside a bucket, as refine.c */
    if (k < C->cursor) C->cursor = k;
    if (k > C->qhi) C->qhi = k;
}

int32_t pbw_pop_bad(pbw_ctx *C) {
    for (;;) {
        if (!pbw_bad_left(C)) return -1;
        pbw_qstack *q = &C->q[C->cursor];
        int32_t t = q->t[--q->n];
        /* a slot rewritten since it was queued lost its bit (the kernel clears tf when it
         * writes a slot): its new triangle was queued on its own, so skip it untouched, as
         * refine.c does */
        if (!(C->M.tf[t] & MESH_QUEUED)) continue;
        C->M.tf[t] &= (uint8_t)~MESH_QUEUED;
        return t;
    }
}

void pbw_queue_free(pbw_ctx *C) {
    for (int k = 0; k < NBUCKET; k++) {
        free(C->q[k].t);
        C->q[k].t = NULL;
        C->q[k].n = C->q[k].cap = 0;
    }
}

size_t pbw_queue_bytes(const pbw_ctx *C) {
    size_t b = 0;
    for (int k = 0; k < NBUCKET; k++)
        b += (size_t)C->q[k].cap * sizeof(int32_t);
    return b;
}

int pbw_is_corner_gid(pbw_ctx *C, int64_t g) {
    return g >= 0 && g < C->ninput && C->corner[g];
}

/* The shared forced-angle rule (mesh_rules_edge_forced) for the shortest edge lu-lv (vertex
 * slots): an input vertex is named by its id, a Steiner vertex by the segment it lies on. */
int pbw_edge_forced(pbw_ctx *C, int32_t lu, int32_t lv) {
    if (!C->has_corners) return 0;
    C->I.xy = C->M.xy; /* input vertex i is slot i (setup); the array moves as it grows */
    int64_t u = C->vgid[lu], v = C->vgid[lv];
    int32_t iu = u >= 0 && u < C->ninput ? (int32_t)u : -1;
    int32_t iv = v >= 0 && v < C->ninput ? (int32_t)v : -1;
    return mesh_rules_edge_forced(&C->I, iu, iu < 0 ? C->M.vseg[lu] : -1, VX(C, lu), iv,
                                  iv < 0 ? C->M.vseg[lv] : -1, VX(C, lv));
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
    const int32_t *tv = C->M.tv + 3 * (size_t)t;
    const double *p[3] = {VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2])};
    if (mesh_rules_steiner(&C->R, p, sh, out) != 0) return -1;
    return geom_working_point(out);
}
