/* pbw_cavity.c: the cavity of one Steiner point -- its travelling state (packed into the
 * EXPAND and REPLY payloads), its expansion on each rank it reaches (Bowyer-Watson: members by
 * exact incircle, halos locked or decided on their ghost, boundary edges reported with reserved
 * slots, stale links forwarded by tombstones, see GHOSTS in pbw.c), and its
 * outcome: the commit (one message per participant with its new triangles) or the release
 * everywhere (undo), the rejection of a point that encroaches subsegments (which are split
 * instead), and the failures (not star-shaped, a member reached twice, a split point off its
 * line).  The protocol and its progress argument are in pbw.c.
 * Invariant: nothing is written until every triangle the commit touches is locked or is a
 * ghost whose apex is exact, so an undo is only a release of locks. */
#include "pbw/pbw_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Cavity states are recycled through C's pool (at most PBW_CAV_POOL kept, with their arrays):
 * a state per distributed cavity and per expansion request, each with four arrays, was a tenth
 * of a rank's instructions after its local work ran out (malloc, realloc and free). */
pbw_cav *pbw_cav_new(pbw_ctx *C) {
    pbw_cav *c;
    if (C->ncavpool > 0) {
        c = C->cavpool[--C->ncavpool];
        pbw_cav keep = *c; /* the arrays and their capacities; everything else starts empty */
        memset(c, 0, sizeof *c);
        c->parts = keep.parts, c->pcap = keep.pcap;
        c->b = keep.b, c->bcap = keep.bcap;
        c->todo = keep.todo, c->tcap = keep.tcap;
        c->stk = keep.stk, c->scap = keep.scap;
    } else {
        c = mesh_xrealloc(NULL, sizeof *c, 1);
        memset(c, 0, sizeof *c);
    }
    c->C = C;
    c->h.su = c->h.sv = c->h.holder = -1;
    return c;
}

void pbw_cav_free(pbw_cav *c) {
    if (!c) return;
    free(c->reply);
    c->reply = NULL;
    pbw_ctx *C = c->C;
    if (C && !C->cavpool_closed && C->ncavpool < PBW_CAV_POOL) {
        C->cavpool[C->ncavpool++] = c;
        return;
    }
    free(c->parts);
    free(c->b);
    free(c->todo);
    free(c->stk);
    free(c);
}

void pbw_cav_pool_free(pbw_ctx *C) {
    C->cavpool_closed = 1;
    while (C->ncavpool > 0)
        pbw_cav_free(C->cavpool[--C->ncavpool]);
}

void pbw_part_add(pbw_cav *c, int32_t r) {
    for (int32_t i = 0; i < c->np; i++)
        if (c->parts[i] == r) return;
    MESH_GROW(c->parts, c->np, c->pcap);
    c->parts[c->np++] = r;
}

void pbw_part_remove(pbw_cav *c, int32_t r) {
    for (int32_t i = 0; i < c->np; i++)
        if (c->parts[i] == r) {
            c->parts[i] = c->parts[--c->np];
            return;
        }
}

void pbw_push_seed(pbw_ctx *C, pbw_cav *c, int64_t target, int64_t from, int64_t back, int64_t ga,
                   int64_t gb, int mode) {
    int32_t reg =
        C->M.treg && from != NOREF && ref_rank(from) == C->rank ? C->M.treg[ref_idx(from)] : -1;
    pbw_seed s = {target, from, ga, gb, back, mode, reg};
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
void *pbw_cav_pack(pbw_cav *c, int full, uint32_t *len) {
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
void pbw_cav_unpack_into(pbw_cav *c, const void *data, uint32_t len) {
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
        pbw_part_add(c, ((const int32_t *)q)[i]);
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

/* Reports boundary edge ga->gb (vertex slots la, lb here) and reserves the new triangle's
 * slot on this rank.  ss: its subsegment record (NULL: not a constraint edge).  oapex: vertex
 * id of out's apex if out is a ghost (not locked), else -1. */
static void report(pbw_ctx *C, pbw_cav *c, int32_t hi, int32_t la, int32_t lb, int64_t out,
                   int64_t inref, const mesh_subseg *ss, int64_t oapex, int32_t reg) {
    int32_t s = pbw_slot_alloc(C);
    pbw_lock_slot(C, s, hi, ROLE_RES);
    pbw_bnd r;
    memset(&r, 0, sizeof r);
    r.ga = C->vgid[la];
    r.gb = C->vgid[lb];
    r.out = out;
    r.newref = mkref(C->rank, s);
    r.inref = inref;
    r.cseg = ss ? ss->seg : -1;
    r.clev = ss ? ss->level : -1;
    r.ck = ss ? ss->k : 0;
    r.oapex = oapex;
    r.reg = reg;
    if (geom_orient2d(VX(C, la), VX(C, lb), c->h.p) <= 0) r.flags |= BF_BEYOND;
    if (ss && mesh_rules_encroaches(&C->R, VX(C, la), VX(C, lb), c->h.p)) r.flags |= BF_ENC;
    MESH_GROW(c->b, c->nb, c->bcap);
    c->b[c->nb++] = r;
}

static int is_open_edge(const pbw_cav *c, int64_t ga, int64_t gb) {
    return c->h.kind == K_SPLIT &&
           ((ga == c->h.su && gb == c->h.sv) || (ga == c->h.sv && gb == c->h.su));
}

/* Member x (reached from member `from`) joins the cavity: visit its neighbours.  A remote
 * neighbour on this edge's ghost side with a known ghost is not visited unless it is in
 * conflict (exact incircle on the ghost): its edge is reported here, unlocked (GHOSTS, pbw.c). */
static void expand_member(pbw_ctx *C, pbw_cav *c, int32_t hi, int32_t x, int64_t from) {
    int64_t self = mkref(C->rank, x);
    int32_t reg = C->M.treg ? C->M.treg[x] : -1;
    for (int j = 0; j < 3; j++) {
        size_t e = 3 * (size_t)x + (size_t)j;
        int32_t la = C->M.tv[e], lb = C->M.tv[3 * (size_t)x + (size_t)((j + 1) % 3)];
        int64_t ga = C->vgid[la], gb = C->vgid[lb], n = TN(C, e);
        if (n != NOREF && n == from) continue;
        int32_t g = ghost_side(C, n) ? GX(C, e) : -1; /* n = (lb, la, g), counter-clockwise */
        if (is_open_edge(c, ga, gb)) {
            if (n != NOREF) pbw_push_seed(C, c, n, self, from, ga, gb, SEED_OPEN);
        } else if (mesh_edge_constrained(&C->M, (int32_t)e)) {
            if (n == NOREF)
                report(C, c, hi, la, lb, NOREF, self, SSEG(C, e), -1, reg);
            else if (g >= 0)
                report(C, c, hi, la, lb, n, self, SSEG(C, e), C->vgid[g], reg);
            else
                pbw_push_seed(C, c, n, self, from, ga, gb, SEED_HALO);
        } else if (n == NOREF) {
            report(C, c, hi, la, lb, NOREF, self, NULL, -1, reg); /* cannot happen in a CDT */
        } else if (g >= 0 && geom_incircle(VX(C, lb), VX(C, la), VX(C, g), c->h.p) <= 0) {
            report(C, c, hi, la, lb, n, self, NULL, C->vgid[g], reg);
        } else {
            pbw_push_seed(C, c, n, self, from, ga, gb, SEED_NORMAL);
        }
    }
}

static int in_conflict(pbw_ctx *C, int32_t x, const double p[2]) {
    const int32_t *tv = C->M.tv + 3 * (size_t)x;
    return geom_incircle(VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2]), p) > 0;
}

/* Processes the local seeds of c.  initial: the starter's first step (nothing sent yet). */
int pbw_process(pbw_ctx *C, pbw_cav *c, int32_t hi, int initial) {
    while (c->nstk > 0) {
        pbw_seed s = c->stk[c->nstk - 1];
        int32_t x = ref_idx(s.target);
        if (ref_rank(s.target) != C->rank || x < 0 || x >= C->M.nt)
            MESH_BUG("seed names triangle (%d, %d)", ref_rank(s.target), x);
        if (s.mode != SEED_START && ROLE(C, x) == ROLE_TOMB) {
            /* a stale link (a ghost commit replaced x): the triangle on that edge now */
            int32_t y = pbw_resolve_tomb(C, x, s.ga, s.gb);
            int jy = pbw_find_edge(C, y, s.gb, s.ga);
            if (TN(C, 3 * (size_t)y + (size_t)jy) != s.from)
                MESH_BUG("triangle %d on a forwarded edge does not border its member", y);
            if (mkref(C->rank, y) == s.back) { /* the edge the expansion came in through */
                c->nstk--;
                C->res.forwarded++;
                continue;
            }
            c->stk[c->nstk - 1].target = s.target = mkref(C->rank, y);
            x = y;
            C->res.forwarded++;
        }
        int32_t h = LK(C, x);
        if (h >= 0 && h != hi) {
            c->h.holder = C->hd[h].key;
            if (initial) return PR_DIE;
            return older(c->h.stamp, c->h.key, C->hd[h].stamp, C->hd[h].key) ? PR_PARK : PR_DIE;
        }
        c->nstk--;
        if (!alive(C, x)) MESH_BUG("seed names dead triangle %d (mode %d)", x, s.mode);
        int j = -1;
        if (s.mode != SEED_START) {
            j = pbw_find_edge(C, x, s.gb, s.ga);
            if (j < 0)
                MESH_BUG("triangle %d has no edge %lld->%lld (mode %d)", x, (long long)s.gb,
                         (long long)s.ga, s.mode);
        }
        int role = h == hi ? ROLE(C, x) : ROLE_NONE;
        switch (s.mode) {
        case SEED_START:
            pbw_lock_slot(C, x, hi, ROLE_MEMBER);
            expand_member(C, c, hi, x, NOREF);
            break;
        case SEED_OPEN: {
            if (role == ROLE_MEMBER) {
                c->h.cycle |= CYC_TWICE;
                break;
            }
            const int32_t *tx = C->M.tv + 3 * (size_t)x;
            if (mesh_rules_off_line_fan(VX(C, tx[j]), VX(C, tx[(j + 1) % 3]), c->h.p,
                                        VX(C, tx[(j + 2) % 3]), NULL))
                c->h.cycle |= CYC_OFF_LINE;
            pbw_lock_slot(C, x, hi, ROLE_MEMBER);
            expand_member(C, c, hi, x, s.from);
            break;
        }
        case SEED_HALO: {
            if (role == ROLE_NONE) pbw_lock_slot(C, x, hi, ROLE_HALO);
            size_t e = 3 * (size_t)x + (size_t)j;
            /* x's edge is gb->ga: the cavity's edge ga->gb runs from x's vertex j+1 to j */
            report(C, c, hi, C->M.tv[3 * (size_t)x + (size_t)((j + 1) % 3)], C->M.tv[e],
                   mkref(C->rank, x), s.from, SSEG(C, e), -1, s.reg);
            break;
        }
        case SEED_NORMAL:
            if (role == ROLE_MEMBER) { /* a second way in: see CAVITY above */
                c->h.cycle |= CYC_TWICE;
                break;
            }
            if (in_conflict(C, x, c->h.p)) {
                pbw_lock_slot(C, x, hi, ROLE_MEMBER);
                expand_member(C, c, hi, x, s.from);
            } else {
                if (role == ROLE_NONE) pbw_lock_slot(C, x, hi, ROLE_HALO);
                size_t e = 3 * (size_t)x + (size_t)j;
                report(C, c, hi, C->M.tv[3 * (size_t)x + (size_t)((j + 1) % 3)], C->M.tv[e],
                       mkref(C->rank, x), s.from, NULL, -1, s.reg);
            }
            break;
        default:
            MESH_BUG("bad seed mode %d", s.mode);
        }
    }
    return PR_DONE;
}

void pbw_check_new_triangle(pbw_ctx *C, int32_t t) {
    pbw_push_bad(C, t);
    unsigned cons = C->M.tf[t] & 7u; /* the constraint bits of its edges (most have none) */
    for (int j = 0; cons != 0 && j < 3; j++) {
        size_t e = 3 * (size_t)t + (size_t)j;
        if (!((cons >> j) & 1u)) continue;
        int32_t a = C->M.tv[e], b = C->M.tv[3 * (size_t)t + (size_t)((j + 1) % 3)],
                o = C->M.tv[3 * (size_t)t + (size_t)((j + 2) % 3)];
        /* an apex on the other segment of a small input corner, as far from it as a or b,
         * does not count (the forced-angle rule; refine.c's encroached_unforced) */
        if (mesh_rules_encroaches(&C->R, VX(C, a), VX(C, b), VX(C, o)) &&
            !pbw_edge_forced(C, o, a) && !pbw_edge_forced(C, o, b)) {
            pbw_item it;
            memset(&it, 0, sizeof it);
            it.kind = IT_SPLIT;
            it.t = t;
            it.gu = C->vgid[a];
            it.gv = C->vgid[b];
            it.notify = -1;
            it.ticket = -1;
            it.forced = 0;
            pbw_iv_push(&C->splitq, &it);
        }
    }
}

/* Applies this rank's part of a commit: members die, reserved slots become the new triangles,
 * halos get their link to the new triangle, everything is unlocked. */
/* How many earlier records of a commit pbw_apply_commit searches for a vertex's slot. */
#define FAN_LOOKBACK 8

void pbw_apply_commit(pbw_ctx *C, const pbw_commit_hdr *ch, const pbw_newtri *nt) {
    int32_t hi = pbw_hold_find(C, ch->key);
    if (hi < 0) MESH_BUG("commit for unknown cavity %llx", (unsigned long long)ch->key);
    pbw_hold *h = &C->hd[hi];
    int32_t pv = pbw_vt_add(C, ch->pgid, ch->p[0], ch->p[1], ch->pvseg);
    /* the new triangles' vertices first: a local link names the same edge in its neighbour,
     * so both ends must hold their vertices before any link is written */
    for (int32_t i = 0; i < ch->n; i++) {
        const pbw_newtri *r = &nt[i];
        int32_t s = r->slot;
        if (s < 0 || s >= C->M.nt || LK(C, s) != hi || ROLE(C, s) != ROLE_RES)
            MESH_BUG("commit writes slot %d not reserved by the cavity", s);
        for (int j = 0; j < 3; j++) {
            /* the fan's vertices: p itself, each boundary vertex in two new triangles (the
             * previous records hold it, in cache; the vertex table costs a cache miss) */
            int32_t v = j == 2 && r->g[2] == ch->pgid ? pv : -1;
            for (int32_t k = i - 1; v < 0 && k >= 0 && i - k <= FAN_LOOKBACK; k--)
                for (int jj = 0; jj < 2 && v < 0; jj++)
                    if (nt[k].g[jj] == r->g[j]) v = C->M.tv[3 * (size_t)nt[k].slot + (size_t)jj];
            if (v < 0) v = pbw_vt_find(C, r->g[j]);
            if (v < 0) MESH_BUG("commit names unknown vertex %lld", (long long)r->g[j]);
            C->M.tv[3 * (size_t)s + (size_t)j] = v;
        }
    }
    /* ghost edges: the member there becomes a tombstone forwarding to the new triangle */
    for (int32_t i = 0; i < ch->n; i++) {
        const pbw_newtri *r = &nt[i];
        if (r->nb[0] == NOREF || ref_rank(r->nb[0]) == C->rank) continue;
        int32_t m = ref_idx(r->in);
        int jm = ref_rank(r->in) == C->rank && m >= 0 && m < C->M.nt && LK(C, m) == hi
                     ? pbw_find_edge(C, m, r->g[0], r->g[1])
                     : -1;
        if (jm < 0 || (ROLE(C, m) != ROLE_MEMBER && ROLE(C, m) != ROLE_TOMB))
            MESH_BUG("ghost edge of the new triangle in slot %d has no member here", r->slot);
        pbw_forward_set(C, 3 * (size_t)m + (size_t)jm, r->slot);
        pbw_role_set(C, m, ROLE_TOMB);
    }
    for (int32_t i = 0; i < h->n; i++) {
        int32_t s = h->slots[i];
        if (LK(C, s) != hi) continue;
        if (ROLE(C, s) == ROLE_MEMBER) {
            pbw_slot_free(C, s);
            C->nlive--;
        } else if (ROLE(C, s) == ROLE_TOMB) {
            pbw_lk_set(C, s, -1); /* dead, kept: never reused */
            C->nlive--;
        }
    }
    for (int32_t i = 0; i < ch->n; i++) {
        const pbw_newtri *r = &nt[i];
        int32_t s = r->slot;
        for (int j = 0; j < 3; j++) {
            size_t e = 3 * (size_t)s + (size_t)j;
            pbw_tn_set(C, e, r->nb[j]);
            pbw_gx_set(C, e,
                       r->nb[j] != NOREF && ref_rank(r->nb[j]) != C->rank && r->ap[j] >= 0
                           ? pbw_vt_find(C, r->ap[j])
                           : -1);
            pbw_con_set(C, e, r->cseg[j], r->clev[j], r->ck[j]);
        }
        pbw_lk_set(C, s, -1);
        pbw_role_set(C, s, ROLE_NONE);
        if (C->M.treg) C->M.treg[s] = r->reg; /* the member's on its edge: same side of segments */
        C->nlive++;
        if (r->nb[0] != NOREF && ref_rank(r->nb[0]) != C->rank) {
            /* a ghost: its owner keeps its link to the tombstone, which forwards (GHOSTS, pbw.c) */
            if (GX(C, 3 * (size_t)s) < 0) MESH_BUG("ghost edge of slot %d without its apex", s);
        } else if (r->nb[0] != NOREF) {
            int32_t x = ref_idx(r->nb[0]);
            int j = alive(C, x) ? pbw_find_edge(C, x, r->g[1], r->g[0]) : -1;
            if (j < 0 || LK(C, x) != hi || ROLE(C, x) != ROLE_HALO)
                MESH_BUG("halo %d of the new triangle is not the cavity's", x);
            pbw_tn_set(C, 3 * (size_t)x + (size_t)j, mkref(C->rank, s));
            pbw_gx_set(C, 3 * (size_t)x + (size_t)j, -1);
        }
    }
    for (int32_t i = 0; i < h->n; i++) {
        int32_t s = h->slots[i];
        if (LK(C, s) != hi) continue;
        if (ROLE(C, s) == ROLE_RES) MESH_BUG("reserved slot %d left unused by the commit", s);
        pbw_lk_set(C, s, -1);
        pbw_role_set(C, s, ROLE_NONE);
    }
    pbw_hold_end(C, hi);
    for (int32_t i = 0; i < ch->n; i++) {
        pbw_check_new_triangle(C, nt[i].slot);
        pbw_gen_note(C, nt[i].slot);
    }
}

/* Sends RELEASE to every participant (and releases here). */
static void release_all(pbw_ctx *C, pbw_cav *c, int undo) {
    for (int32_t i = 0; i < c->np; i++) {
        int32_t r = c->parts[i];
        if (r == C->rank) {
            int32_t hi = pbw_hold_find(C, c->h.key);
            if (hi >= 0) pbw_release_local(C, hi, undo);
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
    m->key = mesh_xrealloc(NULL, cap, sizeof(int64_t));
    m->val = mesh_xrealloc(NULL, cap, sizeof(int32_t));
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
    *cseg = c->h.sseg;
    *clev = c->h.schild_lev;
    *ck = c->h.schild_lev < 0 ? 0 : (w == c->h.su ? c->h.sk_u : c->h.sk_v);
}

/* Builds the new triangles (one per boundary edge) and commits them on every participant.
 * Returns 0, or -1 if the boundary is not a proper fan (then nothing was sent). */
int pbw_commit_all(pbw_ctx *C, pbw_cav *c, const rt_msg *to_origin) {
    int32_t n = c->nb;
    int split = c->h.kind == K_SPLIT;
    gmap A, B;
    gmap_init(&A, n);
    gmap_init(&B, n);
    int bad = n < 1;
    for (int32_t i = 0; i < n && !bad; i++)
        if (gmap_put(&A, c->b[i].ga, i) != 0 || gmap_put(&B, c->b[i].gb, i) != 0) bad = 1;
    pbw_newtri *nt = mesh_xrealloc(NULL, (size_t)(n > 0 ? n : 1), sizeof *nt);
    int64_t pgid = ((int64_t)(C->rank + 1) << 32) | C->nvown;
    for (int32_t i = 0; i < n && !bad; i++) {
        const pbw_bnd *b = &c->b[i];
        pbw_newtri *r = &nt[i];
        memset(r, 0, sizeof *r);
        r->g[0] = b->ga;
        r->g[1] = b->gb;
        r->g[2] = pgid;
        r->slot = ref_idx(b->newref);
        r->reg = b->reg;
        r->nb[0] = b->out;
        r->in = b->inref;
        r->ap[0] = b->oapex;
        r->ap[1] = r->ap[2] = -1;
        r->cseg[0] = b->cseg;
        r->clev[0] = b->clev;
        r->ck[0] = b->ck;
        int ub = split && (b->gb == c->h.su || b->gb == c->h.sv);
        int ua = split && (b->ga == c->h.su || b->ga == c->h.sv);
        int32_t j = gmap_get(&A, b->gb), k = gmap_get(&B, b->ga);
        if (j >= 0) {
            r->nb[1] = c->b[j].newref;
            r->ap[1] = c->b[j].gb;
        } else if (ub)
            r->nb[1] = NOREF;
        else
            bad = 1;
        if (k >= 0) {
            r->nb[2] = c->b[k].newref;
            r->ap[2] = c->b[k].ga;
        } else if (ua)
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
    pbw_newtri *mine = mesh_xrealloc(NULL, (size_t)(n > 0 ? n : 1), sizeof *mine);
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
        ch.pvseg = split ? c->h.sseg : -1;
        ch.n = m;
        if (r == C->rank) {
            pbw_apply_commit(C, &ch, mine);
        } else {
            size_t len = sizeof ch + (size_t)m * sizeof(pbw_newtri);
            char *buf = mesh_xrealloc(NULL, len, 1);
            memcpy(buf, &ch, sizeof ch);
            if (m > 0) memcpy(buf + sizeof ch, mine, (size_t)m * sizeof(pbw_newtri));
            if (to_origin && r == c->h.origin) /* it wakes the starter's task (DECIDE, pbw.c) */
                rt_reply(to_origin, C->hid[PBW_RSR_COMMIT], buf, (uint32_t)len);
            else
                rt_rsr(r, C->hid[PBW_RSR_COMMIT], buf, (uint32_t)len);
            free(buf);
        }
    }
    free(mine);
    free(nt);
    return 0;
}

/* What the complete state of cavity c decides (pbw_outcome). */
int pbw_outcome(const pbw_cav *c) {
    if (c->h.status == ST_DIE) return OUT_DIE;
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
    if (!split && cbad && !c->h.cycle) return OUT_REJECT;
    if (nonstar || cbad || c->h.cycle) return OUT_FAIL;
    return OUT_COMMIT;
}

/* The starter's account of a committed cavity (committed here or by the chain's last rank). */
void pbw_committed(pbw_ctx *C, pbw_cav *c, int remote) {
    if (remote) {
        C->res.cavities_remote++;
    } else {
        C->res.cavities_local++;
        for (int32_t i = 0; i < c->nb; i++)
            if (c->b[i].oapex >= 0) {
                C->res.ghosted++;
                break;
            }
    }
    if (c->h.kind == K_SPLIT) {
        C->res.splits++;
        pbw_notify(C, c->it.notify, c->it.ticket, 0);
    } else {
        C->res.inserted++;
    }
}

/* The starter's decision once the whole cavity is known (or the expansion died). */
void pbw_finish(pbw_ctx *C, pbw_cav *c) {
    int out = pbw_outcome(c);
    if (out == OUT_DIE) {
        release_all(C, c, 1);
        C->res.undone_remote++;
        if (c->h.died_at == C->rank)
            pbw_defer_item(C, &c->it, W_HOLD, c->h.holder, 1);
        else if (c->woken)
            pbw_iv_push(&C->retryq, &c->it);
        else
            pbw_defer_item(C, &c->it, W_WAKE, c->h.holder, 1);
        return;
    }
    if (out == OUT_REJECT) {
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
                it.ticket = split_ticket(c->h.key);
                it.stamp = sst;
                it.forced = 1;
                pbw_iv_push(&C->splitq, &it);
            } else {
                pbw_split_msg m = {b->ga,  b->gb, split_ticket(c->h.key), sst, ref_idx(b->inref),
                                   C->rank};
                rt_rsr(r, C->hid[PBW_RSR_SPLIT], &m, sizeof m);
            }
        }
        /* retry once every split asked for is done (each one wakes us with our ticket) */
        pbw_defer_item(C, &c->it, W_WAKE, split_ticket(c->h.key), nreq);
        return;
    }
    if (out == OUT_FAIL || pbw_commit_all(C, c, NULL) != 0) {
        release_all(C, c, 0);
        C->res.failed++;
        if (c->h.kind == K_SPLIT) pbw_notify(C, c->it.notify, c->it.ticket, 1);
        return;
    }
    pbw_committed(C, c, c->np > 1);
}

/* A stale link (a seed across ga->gb naming tombstone slot x): the live triangle now on that
 * edge, following the tombstones' forward links, or -1 if x is not a tombstone. */
int32_t pbw_resolve_tomb(pbw_ctx *C, int32_t x, int64_t ga, int64_t gb) {
    if (x < 0 || x >= C->M.nt || ROLE(C, x) != ROLE_TOMB) return -1;
    for (int32_t hops = 0; ROLE(C, x) == ROLE_TOMB; hops++) {
        int j = pbw_find_edge(C, x, gb, ga);
        int64_t f = j >= 0 ? TN(C, 3 * (size_t)x + (size_t)j) : NOREF;
        if (f == NOREF || ref_rank(f) != C->rank || hops > C->M.nt)
            MESH_BUG("tombstone %d has no forward link across %lld->%lld", x, (long long)gb,
                     (long long)ga);
        x = ref_idx(f);
    }
    if (!alive(C, x) || pbw_find_edge(C, x, gb, ga) < 0)
        MESH_BUG("forward link ends at slot %d, which has no edge %lld->%lld", x, (long long)gb,
                 (long long)ga);
    return x;
}
