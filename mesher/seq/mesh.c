/* mesh.c: the triangle data structure and its local operations -- allocation, point location,
 * Bowyer-Watson cavities, edge flips and edge search (mesh.h; the subsegment side table,
 * regions and the flat output are mesh_subseg.c, mesh_regions.c and mesh_out.c).
 *
 * Point location is a remembering stochastic visibility walk (Devillers, Pion, Teillaud,
 * "Walking in a triangulation", 2002): from the current triangle, step across an edge that
 * has the target strictly on its far side (exact orient2d), trying the edges in random order
 * and never re-testing the edge just crossed; the walk terminates with probability 1 on any
 * triangulation.  Insertion is Bowyer-Watson (Bowyer 1981, Watson 1981) in its constrained
 * form (Chew 1989 "Constrained Delaunay triangulations"; the paper's section 3): the cavity is
 * grown depth-first from the containing triangle across non-constraint edges into triangles
 * whose circumcircle strictly contains the point (exact incircle; for a ghost triangle, its
 * outer open half-plane plus the open hull edge).  The depth-first order emits the cavity
 * boundary counter-clockwise, so joining the point to it is a single pass that reuses the
 * cavity's slots.  Invariants: every live non-ghost triangle is counter-clockwise; tn is an
 * involution on live edges (tn[tn[e]] == e) or -1; both sides of a constraint edge carry its
 * bit; before any write the cavity is checked star-shaped from the point (exact orient2d), so a
 * failed insertion leaves the mesh unchanged.  A cavity records, per boundary edge, the region
 * of the triangle inside it, and the new triangle on that edge inherits it.
 */
#include "mesh_impl.h"

#include "geom/geom.h"

#include <string.h>

/* ---- allocation ------------------------------------------------------------------------ */

uint64_t mesh_rand(mesh *m) {
    /* xorshift64* */
    uint64_t x = m->rng;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    m->rng = x;
    return x * 2685821657736338717ull;
}

void mesh_init(mesh *m) {
    geom_init();
    memset(m, 0, sizeof *m);
    m->free_head = -1;
    m->ss_free = -1;
    m->rng = 0x9e3779b97f4a7c15ull;
    m->last = -1;
    m->hooks.poll_every = 200;
    m->q.max_steiner = -1;
}

void mesh_free(mesh *m) {
    mesh_refine_free(m);
    free(m->xy);
    free(m->vseg);
    free(m->vtri);
    free(m->in_vmarker);
    free(m->tv);
    free(m->tn);
    free(m->tf);
    free(m->seg);
    free(m->smarker);
    free(m->siface);
    free(m->seg_nsub);
    free(m->inc_off);
    free(m->inc_seg);
    free(m->corner);
    free(m->ss);
    free(m->hpair);
    free(m->hname);
    free(m->cav);
    free(m->bnd);
    free(m->stk);
    free(m->newt);
    free(m->treg);
    free(m->reg_attr);
    free(m->reg_area);
    memset(m, 0, sizeof *m);
    m->free_head = -1;
    m->ss_free = -1;
}

/* n elements of size bytes from p into a new array of cap (>= n) elements; NULL stays NULL. */
static void *dup_array(const void *p, size_t n, size_t cap, size_t size) {
    if (!p) return NULL;
    void *q = mesh_xrealloc(NULL, cap + 1, size);
    if (n) memcpy(q, p, n * size);
    return q;
}

void mesh_copy(mesh *dst, const mesh *src) {
    if (src->rf) MESH_BUG("mesh_copy of a mesh with refinement state");
    *dst = *src; /* every scalar: counts, free lists, walk memory, rng, rules */
    /* the arrays at their length, not their capacity (a smaller copy; growth doubles from
     * there); the hash tables keep theirs (hcap is their modulus) */
    size_t nv = (size_t)src->nv, ni = (size_t)src->ninput, nt = (size_t)src->nt;
    size_t ns = (size_t)src->nseg, nss = (size_t)src->nss, nr = (size_t)src->nregion;
    dst->vcap = src->nv, dst->tcap = src->nt, dst->segcap = src->nseg, dst->sscap = src->nss;
    dst->xy = dup_array(src->xy, 2 * nv, 2 * nv, sizeof(double));
    dst->vseg = dup_array(src->vseg, nv, nv, sizeof(int32_t));
    dst->vtri = dup_array(src->vtri, nv, nv, sizeof(int32_t));
    dst->in_vmarker = dup_array(src->in_vmarker, ni, ni, sizeof(int32_t));
    dst->tv = dup_array(src->tv, 3 * nt, 3 * nt, sizeof(int32_t));
    dst->tn = dup_array(src->tn, 3 * nt, 3 * nt, sizeof(int32_t));
    dst->tf = dup_array(src->tf, nt, nt, 1);
    dst->treg = dup_array(src->treg, nt, nt, sizeof(int32_t));
    dst->seg = dup_array(src->seg, 2 * ns, 2 * ns, sizeof(int32_t));
    dst->smarker = dup_array(src->smarker, ns, ns, sizeof(int32_t));
    dst->siface = dup_array(src->siface, ns, ns, 1);
    dst->seg_nsub = dup_array(src->seg_nsub, ns, ns, sizeof(int32_t));
    dst->inc_off = dup_array(src->inc_off, ni + 1, ni + 1, sizeof(int32_t));
    size_t ninc = src->inc_off ? (size_t)src->inc_off[ni] : 0;
    dst->inc_seg = dup_array(src->inc_seg, ninc, ninc, sizeof(int32_t));
    dst->corner = dup_array(src->corner, ni, ni, 1);
    dst->reg_attr = dup_array(src->reg_attr, nr, nr, sizeof(double));
    dst->reg_area = dup_array(src->reg_area, nr, nr, sizeof(double));
    dst->ss = dup_array(src->ss, nss, nss, sizeof(mesh_subseg));
    dst->hpair = dup_array(src->hpair, src->hcap, src->hcap, sizeof(int32_t));
    dst->hname = dup_array(src->hname, src->hcap, src->hcap, sizeof(int32_t));
    /* the cavity and walk scratch, as it is */
    dst->cav = dup_array(src->cav, (size_t)src->ncav, (size_t)src->cavcap, sizeof(int32_t));
    dst->bnd = dup_array(src->bnd, (size_t)src->nbnd, (size_t)src->bndcap, sizeof(mesh_bedge));
    dst->stk = dup_array(src->stk, (size_t)src->nstk, (size_t)src->stkcap, sizeof(int32_t));
    dst->newt = dup_array(src->newt, (size_t)src->nnewt, (size_t)src->newtcap, sizeof(int32_t));
}

int32_t mesh_vert_add(mesh *m, double x, double y, int32_t vseg) {
    if (m->nv == m->vcap) {
        int32_t cap = m->vcap ? m->vcap * 2 : 64;
        m->xy = mesh_xrealloc(m->xy, 2 * (size_t)cap, sizeof(double));
        m->vseg = mesh_xrealloc(m->vseg, cap, sizeof(int32_t));
        m->vtri = mesh_xrealloc(m->vtri, cap, sizeof(int32_t));
        m->vcap = cap;
    }
    int32_t v = m->nv++;
    m->xy[2 * v] = x;
    m->xy[2 * v + 1] = y;
    m->vseg[v] = vseg;
    m->vtri[v] = -1;
    return v;
}

/* The triangle arrays' growth (doubling), out of line: rare, and it kept tri_new from being
 * inlined into the cavity's commit. */
static void tri_grow(mesh *m) {
    int32_t cap = m->tcap ? m->tcap * 2 : 256;
    m->tv = mesh_xrealloc(m->tv, 3 * (size_t)cap, sizeof(int32_t));
    m->tn = mesh_xrealloc(m->tn, 3 * (size_t)cap, sizeof(int32_t));
    m->tf = mesh_xrealloc(m->tf, cap, 1);
    if (m->treg) m->treg = mesh_xrealloc(m->treg, cap, sizeof(int32_t));
    m->tcap = cap;
}

static inline int32_t tri_new(mesh *m) {
    int32_t t;
    if (m->free_head >= 0) {
        t = m->free_head;
        m->free_head = m->tn[3 * t];
    } else {
        if (m->nt == m->tcap) tri_grow(m);
        t = m->nt++;
    }
    m->tf[t] = 0;
    if (m->treg) m->treg[t] = -1;
    m->nlive++;
    return t;
}

int32_t mesh_tri_new(mesh *m) {
    return tri_new(m);
}

void mesh_tri_kill(mesh *m, int32_t t) {
    m->tv[3 * t] = MESH_DEAD;
    m->tv[3 * t + 1] = MESH_DEAD;
    m->tv[3 * t + 2] = MESH_DEAD;
    m->tn[3 * t] = m->free_head;
    m->tn[3 * t + 1] = -1;
    m->tn[3 * t + 2] = -1;
    m->tf[t] = 0;
    m->free_head = t;
    m->nlive--;
}

int mesh_tri_is_ghost(const mesh *m, int32_t t) {
    const int32_t *v = m->tv + 3 * (size_t)t;
    return v[0] == MESH_GHOST || v[1] == MESH_GHOST || v[2] == MESH_GHOST;
}

void mesh_set_constrained(mesh *m, int32_t e) {
    m->tf[e / 3] |= (uint8_t)(1u << (e % 3));
    int32_t s = m->tn[e];
    if (s >= 0) m->tf[s / 3] |= (uint8_t)(1u << (s % 3));
}

int32_t mesh_seg_add(mesh *m, int32_t a, int32_t b, int32_t marker, uint8_t iface) {
    if (m->nseg == m->segcap) {
        int32_t cap = m->segcap ? m->segcap * 2 : 16;
        m->seg = mesh_xrealloc(m->seg, 2 * (size_t)cap, sizeof(int32_t));
        m->smarker = mesh_xrealloc(m->smarker, cap, sizeof(int32_t));
        m->siface = mesh_xrealloc(m->siface, cap, 1);
        m->seg_nsub = mesh_xrealloc(m->seg_nsub, cap, sizeof(int32_t));
        m->segcap = cap;
    }
    int32_t s = m->nseg++;
    m->seg[2 * s] = a;
    m->seg[2 * s + 1] = b;
    m->smarker[s] = marker;
    m->siface[s] = iface;
    m->seg_nsub[s] = 0;
    return s;
}

void mesh_rebuild_vtri(mesh *m) {
    for (int32_t v = 0; v < m->nv; v++)
        m->vtri[v] = -1;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        for (int j = 0; j < 3; j++) {
            int32_t v = m->tv[3 * t + j];
            if (v >= 0) m->vtri[v] = t;
        }
    }
}

/* ---- small exact helpers ---------------------------------------------------------------- */

/* p collinear with a and b (caller knows): 1 iff p lies strictly between them.  Exact: on a
 * line, betweenness is decided by one coordinate comparison. */
static int collinear_strictly_between(const double *a, const double *b, const double *p) {
    int c = (a[0] != b[0]) ? 0 : 1;
    return (a[c] < p[c] && p[c] < b[c]) || (b[c] < p[c] && p[c] < a[c]);
}

static int32_t any_live_triangle(const mesh *m) {
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t) && mesh_ghost_index(m, t) < 0) return t;
    return -1;
}

/* Exhaustive search (fallback): a live real triangle containing p, or -1. */
static int32_t locate_brute(const mesh *m, const double p[2]) {
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || mesh_ghost_index(m, t) >= 0) continue;
        const int32_t *v = m->tv + 3 * (size_t)t;
        const double *a = m->xy + 2 * v[0], *b = m->xy + 2 * v[1], *c = m->xy + 2 * v[2];
        if (geom_orient2d(a, b, p) >= 0 && geom_orient2d(b, c, p) >= 0 &&
            geom_orient2d(c, a, p) >= 0)
            return t;
    }
    return -1;
}

/* ---- point location --------------------------------------------------------------------- */

int32_t mesh_walk(mesh *m, const double p[2], int32_t t, int avoid, int32_t *blocked) {
    if (t < 0 || t >= m->nt || !mesh_tri_alive(m, t)) t = m->last;
    if (t < 0 || t >= m->nt || !mesh_tri_alive(m, t)) t = any_live_triangle(m);
    if (t < 0) return -1;
    int64_t limit = 8 * (int64_t)m->nlive + 64, steps = 0;
    int32_t from = -1; /* edge of t we came through */
    uint64_t bits = 0;
    int nbits = 0;
    for (;;) {
        if (++steps > limit) { /* cannot happen with exact predicates; be safe anyway */
            int32_t r = locate_brute(m, p);
            if (r < 0 && blocked) *blocked = -1;
            return r;
        }
        const int32_t *v = m->tv + 3 * (size_t)t;
        if ((v[0] | v[1] | v[2]) < 0) { /* a ghost (live: the only negative vertex id) */
            int g = mesh_ghost_index(m, t);
            int32_t fe = 3 * t + (g + 1) % 3;
            const double *a = m->xy + 2 * m->tv[fe], *b = m->xy + 2 * mesh_dest(m, fe);
            double o = geom_orient2d(a, b, p);
            if (o > 0 || (o == 0 && collinear_strictly_between(a, b, p))) return t;
            from = m->tn[fe];
            t = from / 3;
            continue;
        }
        if (nbits == 0) {
            bits = mesh_rand(m);
            nbits = 32;
        }
        static const uint8_t mod3[5] = {0, 1, 2, 0, 1}; /* x % 3 for x < 5: no division */
        int j0 = mod3[bits & 3];
        bits >>= 2;
        nbits--;
        int32_t next = -1, cons = -1;
        for (int i = 0; i < 3; i++) {
            int j = mod3[j0 + i];
            int32_t e = 3 * t + j;
            if (e == from) continue;
            const double *a = m->xy + 2 * v[j], *b = m->xy + 2 * v[mod3[j + 1]];
            if (geom_orient2d_inline(a, b, p) < 0) {
                if (m->tn[e] < 0 || (avoid && mesh_edge_constrained(m, e))) {
                    if (cons < 0) cons = e;
                    continue;
                }
                next = e;
                break;
            }
        }
        if (next < 0) {
            if (cons >= 0) {
                if (blocked) *blocked = cons;
                m->last = t;
                return -1;
            }
            m->last = t;
            return t;
        }
        from = m->tn[next];
        t = (int32_t)((uint32_t)from / 3u); /* from >= 0 */
    }
}

int32_t mesh_locate(mesh *m, const double p[2], int32_t hint) {
    int32_t blocked = -1;
    int32_t t = mesh_walk(m, p, hint, 1, &blocked);
    /* every way forward is a constraint edge or the domain's boundary: walk on from there
     * across constraints (a coastline's segments would otherwise send most walks to the
     * exhaustive search); only a walk the boundary itself stops (p behind a hole or a
     * concavity, or outside) is left to the search */
    if (t < 0 && blocked >= 0) t = mesh_walk(m, p, blocked / 3, 0, NULL);
    if (t >= 0 && mesh_ghost_index(m, t) >= 0) t = -1;
    if (t < 0) t = locate_brute(m, p);
    return t;
}

/* ---- Bowyer-Watson cavities ------------------------------------------------------------- */

static int in_conflict(const mesh *m, int32_t t, const double p[2]) {
    const int32_t *v = m->tv + 3 * (size_t)t;
    /* a live triangle's vertices are >= 0 but the ghost (-1): one sign test for the three */
    if ((v[0] | v[1] | v[2]) < 0) {
        int g = mesh_ghost_index(m, t);
        const double *a = m->xy + 2 * v[(g + 1) % 3], *b = m->xy + 2 * v[(g + 2) % 3];
        double o = geom_orient2d(a, b, p);
        return o > 0 || (o == 0 && collinear_strictly_between(a, b, p));
    }
    return geom_incircle_inline(m->xy + 2 * v[0], m->xy + 2 * v[1], m->xy + 2 * v[2], p) > 0;
}

/* The growth of push_i32's array, out of line: the cavity pushes several ids per inserted
 * vertex, and the call into this (rare) path kept push_i32 itself from being inlined. */
static void grow_i32(int32_t **a, int32_t *cap) {
    *cap = *cap ? *cap * 2 : 64;
    *a = mesh_xrealloc(*a, *cap, sizeof(int32_t));
}

static inline void push_i32(int32_t **a, int32_t *n, int32_t *cap, int32_t x) {
    if (*n == *cap) grow_i32(a, cap);
    (*a)[(*n)++] = x;
}

static void cav_add(mesh *m, int32_t t) {
    m->tf[t] |= MESH_MARK;
    push_i32(&m->cav, &m->ncav, &m->cavcap, t);
}

void mesh_cavity_abort(mesh *m) {
    for (int32_t i = 0; i < m->ncav; i++)
        m->tf[m->cav[i]] &= (uint8_t)~MESH_MARK;
    m->ncav = 0;
    m->nbnd = 0;
    m->nstk = 0;
}

int mesh_cavity_collect(mesh *m, const double p[2], int32_t t0, int32_t split_e, int32_t *bad) {
    m->ncav = 0;
    m->nbnd = 0;
    m->nstk = 0;
    cav_add(m, t0);
    push_i32(&m->stk, &m->nstk, &m->stkcap, 3 * t0 + 2);
    push_i32(&m->stk, &m->nstk, &m->stkcap, 3 * t0 + 1);
    push_i32(&m->stk, &m->nstk, &m->stkcap, 3 * t0);
    while (m->nstk > 0) {
        int32_t e = m->stk[--m->nstk];
        int32_t nb = m->tn[e];
        int enter = 0;
        if (nb >= 0) {
            int32_t tt = (int32_t)((uint32_t)nb / 3u); /* nb >= 0: no sign fix-up */
            unsigned ftt = m->tf[tt];
            if (ftt & MESH_FENCE) return CAV_FENCED; /* a caller's (PBW: locked) */
            if (e == split_e) {
                enter = 1;
            } else if (!mesh_edge_constrained(m, e)) {
                if (ftt & MESH_MARK) return CAV_CYCLE;
                enter = in_conflict(m, tt, p);
            }
            if (enter) {
                if (ftt & MESH_MARK) return CAV_CYCLE;
                cav_add(m, tt);
                push_i32(&m->stk, &m->nstk, &m->stkcap, mesh_edge_prev(nb));
                push_i32(&m->stk, &m->nstk, &m->stkcap, mesh_edge_next(nb));
                continue;
            }
        } else if (nb < -1) {
            return CAV_FENCED; /* a caller's link (PBW: a neighbour on another rank) */
        }
        if (m->nbnd == m->bndcap) {
            m->bndcap = m->bndcap ? m->bndcap * 2 : 64;
            m->bnd = mesh_xrealloc(m->bnd, m->bndcap, sizeof(mesh_bedge));
        }
        mesh_bedge *b = &m->bnd[m->nbnd++];
        b->org = m->tv[e];
        b->dest = mesh_dest(m, e);
        b->twin = nb;
        b->cons = (uint8_t)mesh_edge_constrained(m, e);
        b->split = (uint8_t)(e == split_e);
        b->reg = m->treg ? m->treg[(uint32_t)e / 3u] : -1;
        /* remember the inner edge code in the stack array's slot: reuse twin for star check */
        if (!b->split && b->org >= 0 && b->dest >= 0 &&
            geom_orient2d_inline(m->xy + 2 * b->org, m->xy + 2 * b->dest, p) <= 0) {
            if (bad) *bad = e;
            return CAV_NOT_STAR;
        }
    }
    return CAV_OK;
}

/* 1 iff the collected cavity is star-shaped from p: p strictly left of every boundary edge
 * with two real endpoints but the split one (the debug tier's repeat of the collect's test, for
 * every caller that commits). */
static inline int cavity_star(const mesh *m, const double *p) {
    for (int32_t i = 0; i < m->nbnd; i++) {
        const mesh_bedge *b = &m->bnd[i];
        if (!b->split && b->org >= 0 && b->dest >= 0 &&
            geom_orient2d(m->xy + 2 * b->org, m->xy + 2 * b->dest, p) <= 0)
            return 0;
    }
    return 1;
}

void mesh_cavity_commit(mesh *m, int32_t v, int32_t su, int32_t sv) {
    MESH_ASSERT(cavity_star(m, m->xy + 2 * v));
    int32_t nb = m->nbnd, s = -1;
    for (int32_t i = 0; i < nb; i++)
        if (m->bnd[i].split) s = i;
    int32_t n = nb - (s >= 0), st = (s >= 0) ? s + 1 : 0;
    m->nnewt = 0;
    for (int32_t i = 0; i < n; i++) {
        int32_t t;
        if (i < m->ncav) {
            t = m->cav[i];
            m->tf[t] = 0;
        } else {
            t = tri_new(m);
        }
        push_i32(&m->newt, &m->nnewt, &m->newtcap, t);
    }
    for (int32_t i = n; i < m->ncav; i++)
        mesh_tri_kill(m, m->cav[i]);
    /* boundary edge ib = (st + i) mod nb and its successor, without a division per edge */
    for (int32_t i = 0, ib = st < nb ? st : 0; i < n; i++, ib = (ib + 1 == nb) ? 0 : ib + 1) {
        const mesh_bedge *b = &m->bnd[ib];
        const mesh_bedge *b2 = &m->bnd[(ib + 1 == nb) ? 0 : ib + 1];
        if (b->dest != b2->org && !(s >= 0 && i == n - 1))
            MESH_BUG("cavity boundary not a cycle (%d -> %d, %d)", b->org, b->dest, b2->org);
        int32_t t = m->newt[i];
        int32_t *tv = m->tv + 3 * (size_t)t, *tn = m->tn + 3 * (size_t)t;
        tv[0] = b->org;
        tv[1] = b->dest;
        tv[2] = v;
        tn[0] = b->twin;
        if (b->twin >= 0) m->tn[b->twin] = 3 * t;
        uint8_t f = b->cons;
        if (su >= 0) {
            if (b->org == su || b->org == sv) f |= 4;
            if (b->dest == su || b->dest == sv) f |= 2;
        }
        m->tf[t] = f;
        if (m->treg) m->treg[t] = b->reg;
        if (b->org >= 0) m->vtri[b->org] = t; /* each dest is the next edge's origin ... */
    }
    if (n > 0) { /* ... but the last one's in a split cavity's open chain */
        const mesh_bedge *bl = &m->bnd[(st + n - 1) % nb];
        if (bl->dest >= 0) m->vtri[bl->dest] = m->newt[n - 1];
    }
    for (int32_t i = 0; i < n; i++) {
        int32_t t = m->newt[i];
        if (s >= 0 && i == n - 1) {
            m->tn[3 * t + 1] = -1;
        } else {
            int32_t t2 = m->newt[i + 1 < n ? i + 1 : 0];
            m->tn[3 * t + 1] = 3 * t2 + 2;
            m->tn[3 * t2 + 2] = 3 * t + 1;
        }
    }
    if (s >= 0) m->tn[3 * m->newt[0] + 2] = -1;
    for (int32_t i = 0; i < n; i++)
        MESH_ASSERT(mesh_tri_consistent(m, m->newt[i]));
    m->vtri[v] = m->newt[0];
    m->last = m->newt[0];
    m->ncav = 0;
    m->nbnd = 0;
}

mesh_insert_result mesh_insert_point(mesh *m, const double p[2], int32_t hint, int32_t *vout) {
    int32_t blocked = -1;
    int32_t t = mesh_walk(m, p, hint, 1, &blocked);
    if (t >= 0 && mesh_ghost_index(m, t) >= 0) return MESH_OUTSIDE;
    if (t < 0) t = locate_brute(m, p);
    if (t < 0) return MESH_OUTSIDE;
    const int32_t *tv = m->tv + 3 * (size_t)t;
    for (int j = 0; j < 3; j++) {
        const double *a = m->xy + 2 * tv[j];
        if (a[0] == p[0] && a[1] == p[1]) {
            if (vout) *vout = tv[j];
            return MESH_DUPLICATE;
        }
    }
    for (int j = 0; j < 3; j++) {
        int32_t e = 3 * t + j;
        if (mesh_edge_constrained(m, e) &&
            geom_orient2d(m->xy + 2 * tv[j], m->xy + 2 * mesh_dest(m, e), p) == 0)
            return MESH_ON_CONSTRAINT;
    }
    int32_t bad = -1;
    int st = mesh_cavity_collect(m, p, t, -1, &bad);
    if (st != CAV_OK) {
        mesh_cavity_abort(m);
        if (st == CAV_NOT_STAR && bad >= 0 && mesh_edge_constrained(m, bad))
            return MESH_ON_CONSTRAINT;
        return MESH_FAILED;
    }
    int32_t v = mesh_vert_add(m, p[0], p[1], -1);
    mesh_cavity_commit(m, v, -1, -1);
    if (vout) *vout = v;
    return MESH_INSERTED;
}

/* ---- flips ---------------------------------------------------------------------------------*/

void mesh_flip(mesh *m, int32_t e) {
    int32_t f = m->tn[e];
    int32_t t1 = e / 3, t2 = f / 3;
    int32_t u = m->tv[e], v = mesh_dest(m, e), w = mesh_apex(m, e), z = mesh_apex(m, f);
    int32_t e_vw = mesh_edge_next(e), e_wu = mesh_edge_prev(e);
    int32_t e_uz = mesh_edge_next(f), e_zv = mesh_edge_prev(f);
    int32_t n_vw = m->tn[e_vw], n_wu = m->tn[e_wu], n_uz = m->tn[e_uz], n_zv = m->tn[e_zv];
    uint8_t c_vw = (uint8_t)mesh_edge_constrained(m, e_vw);
    uint8_t c_wu = (uint8_t)mesh_edge_constrained(m, e_wu);
    uint8_t c_uz = (uint8_t)mesh_edge_constrained(m, e_uz);
    uint8_t c_zv = (uint8_t)mesh_edge_constrained(m, e_zv);
    /* t1 = (w, u, z), t2 = (z, v, w) */
    int32_t *a = m->tv + 3 * (size_t)t1, *b = m->tv + 3 * (size_t)t2;
    a[0] = w, a[1] = u, a[2] = z;
    b[0] = z, b[1] = v, b[2] = w;
    int32_t *an = m->tn + 3 * (size_t)t1, *bn = m->tn + 3 * (size_t)t2;
    an[0] = n_wu;
    if (n_wu >= 0) m->tn[n_wu] = 3 * t1;
    an[1] = n_uz;
    if (n_uz >= 0) m->tn[n_uz] = 3 * t1 + 1;
    an[2] = 3 * t2 + 2;
    bn[0] = n_zv;
    if (n_zv >= 0) m->tn[n_zv] = 3 * t2;
    bn[1] = n_vw;
    if (n_vw >= 0) m->tn[n_vw] = 3 * t2 + 1;
    bn[2] = 3 * t1 + 2;
    if (m->treg) m->treg[t2] = m->treg[t1]; /* an unconstrained edge: one region */
    m->tf[t1] = (uint8_t)(c_wu | (c_uz << 1));
    m->tf[t2] = (uint8_t)(c_zv | (c_vw << 1));
    if (w >= 0) m->vtri[w] = t1;
    if (u >= 0) m->vtri[u] = t1;
    if (z >= 0) m->vtri[z] = t2;
    if (v >= 0) m->vtri[v] = t2;
    MESH_ASSERT(mesh_tri_consistent(m, t1) && mesh_tri_consistent(m, t2));
}

int mesh_consistent(const mesh *m) {
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t) && !mesh_tri_consistent(m, t)) return 0;
    return 1;
}

/* ---- edges ------------------------------------------------------------------------------ */

/* Edge uv by rotating around u from vtri[u] (both ways).  Returns the edge, -1 if absent from
 * that fan, or -2 if it is absent and the fan is open on both sides (u on the boundary: the
 * domain may touch u in another fan too, a pinch vertex). */
static int32_t find_edge_fan(const mesh *m, int32_t u, int32_t v) {
    int32_t t = m->vtri[u];
    if (t < 0 || !mesh_tri_alive(m, t)) return -1;
    int j = m->tv[3 * t] == u ? 0 : m->tv[3 * t + 1] == u ? 1 : m->tv[3 * t + 2] == u ? 2 : -1;
    if (j < 0) return -1;
    int32_t e0 = 3 * t + j, e = e0;
    int64_t guard = (int64_t)m->nt + 4;
    /* counter-clockwise around u */
    for (;;) {
        if (mesh_dest(m, e) == v) return e;
        int32_t pe = mesh_edge_prev(e);
        if (m->tv[pe] == v) return pe;
        int32_t n = m->tn[pe];
        if (n < 0) break;
        e = n;
        if (e == e0 || --guard < 0) return -1;
    }
    /* clockwise around u */
    e = e0;
    for (;;) {
        int32_t n = m->tn[e];
        if (n < 0) return -2;
        e = mesh_edge_next(n);
        if (e == e0 || --guard < 0) return -1;
        if (mesh_dest(m, e) == v) return e;
        int32_t pe = mesh_edge_prev(e);
        if (m->tv[pe] == v) return pe;
    }
}

int32_t mesh_find_edge(const mesh *m, int32_t u, int32_t v) {
    if (u < 0 || u >= m->nv || v < 0 || v >= m->nv) return -1;
    int32_t e = find_edge_fan(m, u, v);
    if (e >= 0 || e == -1) return e;
    e = find_edge_fan(m, v, u);
    if (e >= 0 || e == -1) return e;
    /* both on the boundary and not in the fans vtri names: where the domain pinches a vertex
     * (touches it in two fans, e.g. a hole touching the boundary there) the edge may lie in
     * another fan.  Rare; a scan decides. */
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        for (int j = 0; j < 3; j++)
            if (m->tv[3 * t + j] == u && m->tv[3 * t + (j + 1) % 3] == v)
                return 3 * t + j;
            else if (m->tv[3 * t + j] == v && m->tv[3 * t + (j + 1) % 3] == u)
                return 3 * t + j;
    }
    return -1;
}
