/* mesh.c: the triangle data structure and its local operations -- allocation, point location,
 * Bowyer-Watson cavities, edge flips, the subsegment side table, regions and output.
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
 * failed insertion leaves the mesh unchanged.  Input regions (mesh_set_regions) are the
 * components of the triangles under adjacency across every edge but an input segment's, each
 * taking the last region point located in it; a cavity records, per boundary edge, the region
 * of the triangle inside it, and the new triangle on that edge inherits it.
 */
#include "mesh_impl.h"

#include "geom/geom.h"
#include "seq/rules.h"

#include <math.h>
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

int32_t mesh_tri_new(mesh *m) {
    int32_t t;
    if (m->free_head >= 0) {
        t = m->free_head;
        m->free_head = m->tn[3 * t];
    } else {
        if (m->nt == m->tcap) {
            int32_t cap = m->tcap ? m->tcap * 2 : 256;
            m->tv = mesh_xrealloc(m->tv, 3 * (size_t)cap, sizeof(int32_t));
            m->tn = mesh_xrealloc(m->tn, 3 * (size_t)cap, sizeof(int32_t));
            m->tf = mesh_xrealloc(m->tf, cap, 1);
            if (m->treg) m->treg = mesh_xrealloc(m->treg, cap, sizeof(int32_t));
            m->tcap = cap;
        }
        t = m->nt++;
    }
    m->tf[t] = 0;
    if (m->treg) m->treg[t] = -1;
    m->nlive++;
    return t;
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

/* Index (0..2) of the ghost vertex of t, or -1. */
static int ghost_index(const mesh *m, int32_t t) {
    const int32_t *v = m->tv + 3 * (size_t)t;
    return v[0] == MESH_GHOST ? 0 : v[1] == MESH_GHOST ? 1 : v[2] == MESH_GHOST ? 2 : -1;
}

static int32_t any_live_triangle(const mesh *m) {
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t) && ghost_index(m, t) < 0) return t;
    return -1;
}

/* Exhaustive search (fallback): a live real triangle containing p, or -1. */
static int32_t locate_brute(const mesh *m, const double p[2]) {
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || ghost_index(m, t) >= 0) continue;
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
        int g = ghost_index(m, t);
        if (g >= 0) {
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
        int j0 = (int)((bits & 3) % 3);
        bits >>= 2;
        nbits--;
        int32_t next = -1, cons = -1;
        for (int i = 0; i < 3; i++) {
            int j = (j0 + i) % 3;
            int32_t e = 3 * t + j;
            if (e == from) continue;
            const double *a = m->xy + 2 * v[j], *b = m->xy + 2 * v[(j + 1) % 3];
            if (geom_orient2d(a, b, p) < 0) {
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
        t = from / 3;
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
    if (t >= 0 && ghost_index(m, t) >= 0) t = -1;
    if (t < 0) t = locate_brute(m, p);
    return t;
}

/* ---- Bowyer-Watson cavities ------------------------------------------------------------- */

static int in_conflict(const mesh *m, int32_t t, const double p[2]) {
    const int32_t *v = m->tv + 3 * (size_t)t;
    int g = ghost_index(m, t);
    if (g >= 0) {
        const double *a = m->xy + 2 * v[(g + 1) % 3], *b = m->xy + 2 * v[(g + 2) % 3];
        double o = geom_orient2d(a, b, p);
        return o > 0 || (o == 0 && collinear_strictly_between(a, b, p));
    }
    return geom_incircle(m->xy + 2 * v[0], m->xy + 2 * v[1], m->xy + 2 * v[2], p) > 0;
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
            int32_t tt = nb / 3;
            if (m->tf[tt] & MESH_FENCE) return CAV_FENCED; /* a caller's (PBW: locked) */
            if (e == split_e) {
                enter = 1;
            } else if (!mesh_edge_constrained(m, e)) {
                if (m->tf[tt] & MESH_MARK) return CAV_CYCLE;
                enter = in_conflict(m, tt, p);
            }
            if (enter) {
                if (m->tf[tt] & MESH_MARK) return CAV_CYCLE;
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
        b->reg = m->treg ? m->treg[e / 3] : -1;
        /* remember the inner edge code in the stack array's slot: reuse twin for star check */
        if (!b->split && b->org >= 0 && b->dest >= 0 &&
            geom_orient2d(m->xy + 2 * b->org, m->xy + 2 * b->dest, p) <= 0) {
            if (bad) *bad = e;
            return CAV_NOT_STAR;
        }
    }
    return CAV_OK;
}

void mesh_cavity_commit(mesh *m, int32_t v, int32_t su, int32_t sv) {
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
            t = mesh_tri_new(m);
        }
        push_i32(&m->newt, &m->nnewt, &m->newtcap, t);
    }
    for (int32_t i = n; i < m->ncav; i++)
        mesh_tri_kill(m, m->cav[i]);
    for (int32_t i = 0; i < n; i++) {
        const mesh_bedge *b = &m->bnd[(st + i) % nb];
        const mesh_bedge *b2 = &m->bnd[(st + i + 1) % nb];
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
        if (b->org >= 0) m->vtri[b->org] = t;
        if (b->dest >= 0) m->vtri[b->dest] = t; /* the chain's last vertex is no origin */
    }
    for (int32_t i = 0; i < n; i++) {
        int32_t t = m->newt[i];
        if (s >= 0 && i == n - 1) {
            m->tn[3 * t + 1] = -1;
        } else {
            int32_t t2 = m->newt[(i + 1) % n];
            m->tn[3 * t + 1] = 3 * t2 + 2;
            m->tn[3 * t2 + 2] = 3 * t + 1;
        }
    }
    if (s >= 0) m->tn[3 * m->newt[0] + 2] = -1;
    m->vtri[v] = m->newt[0];
    m->last = m->newt[0];
    m->ncav = 0;
    m->nbnd = 0;
}

mesh_insert_result mesh_insert_point(mesh *m, const double p[2], int32_t hint, int32_t *vout) {
    int32_t blocked = -1;
    int32_t t = mesh_walk(m, p, hint, 1, &blocked);
    if (t >= 0 && ghost_index(m, t) >= 0) return MESH_OUTSIDE;
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

/* ---- subsegment side table ---------------------------------------------------------------- */

static uint64_t hash_pair(int32_t u, int32_t v) {
    uint32_t a = (uint32_t)(u < v ? u : v), b = (uint32_t)(u < v ? v : u);
    return mesh_hash64(((uint64_t)a << 32) | b);
}

static uint64_t hash_name(int32_t seg, int32_t level, int64_t k) {
    return mesh_hash64((uint64_t)k * 0x9e3779b97f4a7c15ull ^
                       mesh_hash64(((uint64_t)(uint32_t)seg << 8) | (uint64_t)(uint8_t)level));
}

static uint64_t rec_hash(const mesh *m, int which, int32_t r) {
    const mesh_subseg *s = &m->ss[r];
    return which == 0 ? hash_pair(s->u, s->v) : hash_name(s->seg, s->level, s->k);
}

static void tab_put(mesh *m, int32_t *tab, int which, int32_t r) {
    uint32_t mask = m->hcap - 1, i = (uint32_t)rec_hash(m, which, r) & mask;
    while (tab[i] >= 0)
        i = (i + 1) & mask;
    tab[i] = r;
}

static void tab_del(mesh *m, int32_t *tab, int which, int32_t r) {
    uint32_t mask = m->hcap - 1, i = (uint32_t)rec_hash(m, which, r) & mask;
    while (tab[i] != r) {
        if (tab[i] < 0) MESH_BUG("subsegment record %d missing from its table", r);
        i = (i + 1) & mask;
    }
    /* backward-shift deletion (linear probing, no tombstones) */
    uint32_t j = i;
    for (;;) {
        j = (j + 1) & mask;
        if (tab[j] < 0) break;
        uint32_t h = (uint32_t)rec_hash(m, which, tab[j]) & mask;
        int stays = (i <= j) ? (i < h && h <= j) : (i < h || h <= j);
        if (stays) continue;
        tab[i] = tab[j];
        i = j;
    }
    tab[i] = -1;
}

static void tab_rebuild(mesh *m, uint32_t cap) {
    free(m->hpair);
    free(m->hname);
    m->hcap = cap;
    m->hpair = mesh_xrealloc(NULL, cap, sizeof(int32_t));
    m->hname = mesh_xrealloc(NULL, cap, sizeof(int32_t));
    for (uint32_t i = 0; i < cap; i++)
        m->hpair[i] = m->hname[i] = -1;
    for (int32_t r = 0; r < m->nss; r++) {
        if (m->ss[r].level == -2) continue;
        tab_put(m, m->hpair, 0, r);
        if (m->ss[r].level >= 0) tab_put(m, m->hname, 1, r);
    }
}

int32_t mesh_ss_add(mesh *m, int32_t u, int32_t v, int32_t seg, int32_t level, int64_t k) {
    int32_t r;
    if (m->ss_free >= 0) {
        r = m->ss_free;
        m->ss_free = m->ss[r].u;
    } else {
        if (m->nss == m->sscap) {
            m->sscap = m->sscap ? m->sscap * 2 : 64;
            m->ss = mesh_xrealloc(m->ss, m->sscap, sizeof(mesh_subseg));
        }
        r = m->nss++;
    }
    mesh_subseg *s = &m->ss[r];
    s->u = u, s->v = v, s->seg = seg, s->level = level, s->k = k;
    m->ss_live++;
    m->seg_nsub[seg]++;
    if ((uint32_t)m->ss_live * 2 >= m->hcap) {
        tab_rebuild(m, m->hcap ? m->hcap * 2 : 256);
    } else {
        tab_put(m, m->hpair, 0, r);
        if (level >= 0) tab_put(m, m->hname, 1, r);
    }
    return r;
}

void mesh_ss_del(mesh *m, int32_t r) {
    mesh_subseg *s = &m->ss[r];
    tab_del(m, m->hpair, 0, r);
    if (s->level >= 0) tab_del(m, m->hname, 1, r);
    m->seg_nsub[s->seg]--;
    s->level = -2;
    s->u = m->ss_free;
    m->ss_free = r;
    m->ss_live--;
}

int32_t mesh_ss_find_pair(const mesh *m, int32_t u, int32_t v) {
    if (m->hcap == 0) return -1;
    uint32_t mask = m->hcap - 1, i = (uint32_t)hash_pair(u, v) & mask;
    for (;; i = (i + 1) & mask) {
        int32_t r = m->hpair[i];
        if (r < 0) return -1;
        const mesh_subseg *s = &m->ss[r];
        if ((s->u == u && s->v == v) || (s->u == v && s->v == u)) return r;
    }
}

int32_t mesh_ss_find_name(const mesh *m, int32_t seg, int32_t level, int64_t k) {
    if (m->hcap == 0 || level < 0) return -1;
    uint32_t mask = m->hcap - 1, i = (uint32_t)hash_name(seg, level, k) & mask;
    for (;; i = (i + 1) & mask) {
        int32_t r = m->hname[i];
        if (r < 0) return -1;
        const mesh_subseg *s = &m->ss[r];
        if (s->seg == seg && s->level == level && s->k == k) return r;
    }
}

void mesh_ss_prune(mesh *m) {
    for (int32_t r = 0; r < m->nss; r++) {
        if (m->ss[r].level == -2) continue;
        if (mesh_find_edge(m, m->ss[r].u, m->ss[r].v) < 0) mesh_ss_del(m, r);
    }
}

const mesh_subseg *mesh_subseg_of_edge(const mesh *m, int32_t e) {
    if (!mesh_edge_constrained(m, e)) return NULL;
    int32_t r = mesh_ss_find_pair(m, mesh_org(m, e), mesh_dest(m, e));
    return r < 0 ? NULL : &m->ss[r];
}

void mesh_dyadic_point(const double a[2], const double b[2], int32_t level, int64_t k,
                       double out[2]) {
    double f = ldexp((double)(2 * k + 1), -(level + 1));
    out[0] = a[0] + (b[0] - a[0]) * f;
    out[1] = a[1] + (b[1] - a[1]) * f;
}

/* ---- regions ------------------------------------------------------------------------------ */

int32_t mesh_label_regions(const mesh *m, int32_t *label) {
    for (int32_t t = 0; t < m->nt; t++)
        label[t] = -1;
    int32_t *stk = mesh_xrealloc(NULL, (size_t)m->nt + 1, sizeof(int32_t));
    int32_t nreg = 0;
    for (int32_t t0 = 0; t0 < m->nt; t0++) {
        if (!mesh_tri_alive(m, t0) || label[t0] >= 0) continue;
        int32_t n = 0;
        stk[n++] = t0;
        label[t0] = nreg;
        while (n > 0) {
            int32_t t = stk[--n];
            for (int j = 0; j < 3; j++) {
                int32_t e = 3 * t + j, nb = m->tn[e];
                if (nb < 0 || mesh_edge_constrained(m, e)) continue;
                if (label[nb / 3] >= 0) continue;
                label[nb / 3] = nreg;
                stk[n++] = nb / 3;
            }
        }
        nreg++;
    }
    free(stk);
    return nreg;
}

void mesh_keep_regions(mesh *m, const int32_t *label, const uint8_t *keep) {
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || label[t] < 0 || keep[label[t]]) continue;
        for (int j = 0; j < 3; j++) {
            int32_t nb = m->tn[3 * t + j];
            if (nb >= 0 && label[nb / 3] >= 0 && keep[label[nb / 3]]) m->tn[nb] = -1;
        }
        mesh_tri_kill(m, t);
    }
    mesh_rebuild_vtri(m);
    mesh_ss_prune(m);
    m->last = -1;
}

/* ---- input regions ------------------------------------------------------------------------ */

/* 1 iff constraint edge e is a piece of a real segment (id below nreal), not an artificial one;
 * an edge with no record counts as real. */
static int input_constraint(const mesh *m, int32_t e, int32_t nreal) {
    if (!mesh_edge_constrained(m, e)) return 0;
    const mesh_subseg *s = mesh_subseg_of_edge(m, e);
    return !s || s->seg < nreal;
}

/* 1 iff vertex v is an endpoint of an input-segment edge (scans the live triangles: region
 * points exactly on a vertex are rare). */
static int on_input_constraint_vertex(const mesh *m, int32_t v, int32_t nreal) {
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        for (int j = 0; j < 3; j++)
            if ((m->tv[3 * t + j] == v || mesh_dest(m, 3 * t + j) == v) &&
                input_constraint(m, 3 * t + j, nreal))
                return 1;
    }
    return 0;
}

/* The triangle region point p marks, or -1 (outside the domain, or on an input segment). */
static int32_t region_seed(mesh *m, const double p[2], int32_t nreal) {
    int32_t t = mesh_locate(m, p, -1);
    if (t < 0) return -1;
    for (int j = 0; j < 3; j++) {
        int32_t e = 3 * t + j, a = m->tv[e], b = mesh_dest(m, e);
        const double *pa = mesh_vertex_xy(m, a), *pb = mesh_vertex_xy(m, b);
        if (pa[0] == p[0] && pa[1] == p[1]) return on_input_constraint_vertex(m, a, nreal) ? -1 : t;
        if (geom_orient2d(pa, pb, p) == 0 && input_constraint(m, e, nreal)) return -1;
    }
    return t;
}

void mesh_set_regions(mesh *m, const pslg *g, int use_area, int32_t nreal) {
    free(m->treg), free(m->reg_attr), free(m->reg_area);
    m->nregion = g->nregions;
    m->treg = mesh_xmalloc((size_t)m->tcap * sizeof(int32_t) + 1, 1);
    m->reg_attr = mesh_xmalloc((size_t)g->nregions * sizeof(double) + 1, 1);
    m->reg_area = mesh_xmalloc((size_t)g->nregions * sizeof(double) + 1, 1);
    for (int32_t i = 0; i < g->nregions; i++) {
        m->reg_attr[i] = g->regions[4 * i + 2];
        double a = g->regions[4 * i + 3];
        m->reg_area[i] = use_area && a > 0 ? a : 0;
    }
    /* components across every edge but the input segments' (interface edges are crossed) */
    int32_t *comp = m->treg, *stk = mesh_xmalloc((size_t)m->nt * sizeof(int32_t) + 1, 1);
    for (int32_t t = 0; t < m->nt; t++)
        comp[t] = -1;
    int32_t ncomp = 0;
    for (int32_t t0 = 0; t0 < m->nt; t0++) {
        if (!mesh_tri_alive(m, t0) || comp[t0] >= 0) continue;
        int32_t n = 0;
        stk[n++] = t0;
        comp[t0] = ncomp;
        while (n > 0) {
            int32_t t = stk[--n];
            for (int j = 0; j < 3; j++) {
                int32_t e = 3 * t + j, nb = m->tn[e];
                if (nb < 0 || comp[nb / 3] >= 0 || input_constraint(m, e, nreal)) continue;
                comp[nb / 3] = ncomp;
                stk[n++] = nb / 3;
            }
        }
        ncomp++;
    }
    free(stk);
    int32_t *creg = mesh_xmalloc((size_t)ncomp * sizeof(int32_t) + 1, 1);
    for (int32_t c = 0; c < ncomp; c++)
        creg[c] = -1;
    for (int32_t i = 0; i < g->nregions; i++) { /* in file order: the later one wins */
        int32_t t = region_seed(m, g->regions + 4 * i, nreal);
        if (t >= 0) creg[comp[t]] = i;
    }
    for (int32_t t = 0; t < m->nt; t++)
        m->treg[t] = comp[t] >= 0 ? creg[comp[t]] : -1;
    free(creg);
}

/* ---- output --------------------------------------------------------------------------------*/

int mesh_to_flat(const mesh *m, mesh_flat *f) {
    memset(f, 0, sizeof *f);
    f->nverts = m->nv;
    f->xy = mesh_xmalloc(2 * (size_t)m->nv * sizeof(double) + 1, 1);
    f->vmarker = mesh_xmalloc((size_t)m->nv * sizeof(int32_t) + 1, 1);
    int32_t nt = 0;
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t) && ghost_index(m, t) < 0) nt++;
    f->ntris = nt;
    f->tri = mesh_xmalloc(3 * (size_t)nt * sizeof(int32_t) + 1, 1);
    f->nsegs = m->ss_live;
    f->seg = mesh_xmalloc(2 * (size_t)m->ss_live * sizeof(int32_t) + 1, 1);
    f->smarker = mesh_xmalloc((size_t)m->ss_live * sizeof(int32_t) + 1, 1);
    f->sinterface = mesh_xmalloc((size_t)m->ss_live * sizeof(int32_t) + 1, 1);
    if (!f->xy || !f->vmarker || !f->tri || !f->seg || !f->smarker || !f->sinterface) {
        free(f->xy), free(f->vmarker), free(f->tri), free(f->seg), free(f->smarker);
        free(f->sinterface);
        memset(f, 0, sizeof *f);
        return -1;
    }
    memcpy(f->xy, m->xy, 2 * (size_t)m->nv * sizeof(double));
    f->scale_exp = m->scale_exp;
    if (m->treg) f->tattr = mesh_xmalloc((size_t)nt * sizeof(double) + 1, 1);
    for (int32_t v = 0; v < m->nv; v++)
        f->vmarker[v] = v < m->ninput     ? (m->in_vmarker ? m->in_vmarker[v] : 0)
                        : m->vseg[v] >= 0 ? m->smarker[m->vseg[v]]
                                          : 0;
    nt = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || ghost_index(m, t) >= 0) continue;
        memcpy(f->tri + 3 * (size_t)nt, m->tv + 3 * (size_t)t, 3 * sizeof(int32_t));
        if (f->tattr) f->tattr[nt] = m->treg[t] >= 0 ? m->reg_attr[m->treg[t]] : 0;
        nt++;
    }
    int32_t ns = 0;
    for (int32_t r = 0; r < m->nss; r++) {
        const mesh_subseg *s = &m->ss[r];
        if (s->level == -2) continue;
        f->seg[2 * ns] = s->u;
        f->seg[2 * ns + 1] = s->v;
        f->smarker[ns] = m->smarker[s->seg];
        f->sinterface[ns] = m->siface[s->seg];
        ns++;
    }
    return 0;
}

void mesh_take_flat(mesh *m, mesh_flat *f, uint8_t **topen) {
    memset(f, 0, sizeof *f);
    /* scratch first: what remains is coordinates, vertices, triangles, segments */
    mesh_refine_free(m);
    free(m->vtri), free(m->cav), free(m->bnd), free(m->stk), free(m->newt);
    free(m->hpair), free(m->hname), free(m->inc_off), free(m->inc_seg), free(m->corner);
    free(m->seg_nsub);
    m->vtri = m->cav = m->stk = m->newt = m->hpair = m->hname = NULL;
    m->inc_off = m->inc_seg = m->seg_nsub = NULL;
    m->bnd = NULL;
    m->corner = NULL;
    uint8_t *open = topen ? mesh_xmalloc((size_t)m->nlive + 1, 1) : NULL;
    int32_t nt = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || ghost_index(m, t) >= 0) continue;
        if (nt != t) memmove(m->tv + 3 * (size_t)nt, m->tv + 3 * (size_t)t, 3 * sizeof(int32_t));
        if (m->treg) m->treg[nt] = m->treg[t]; /* compacted too, then turned into tattr */
        if (open)
            open[nt] = (uint8_t)((m->tn[3 * (size_t)t] < 0) | (m->tn[3 * (size_t)t + 1] < 0) << 1 |
                                 (m->tn[3 * (size_t)t + 2] < 0) << 2);
        nt++;
    }
    if (topen) *topen = open;
    free(m->tn), free(m->tf);
    m->tn = NULL;
    m->tf = NULL;
    f->ntris = nt;
    f->tri = mesh_xrealloc(m->tv, 3 * (size_t)nt + 1, sizeof(int32_t));
    m->tv = NULL;
    if (m->treg) { /* attributes in place of the labels (a double each) */
        f->tattr = mesh_xmalloc((size_t)nt * sizeof(double) + 1, 1);
        for (int32_t t = 0; t < nt; t++)
            f->tattr[t] = m->treg[t] >= 0 ? m->reg_attr[m->treg[t]] : 0;
    }
    f->nsegs = m->ss_live;
    f->seg = mesh_xmalloc(2 * (size_t)m->ss_live + 1, sizeof(int32_t));
    f->smarker = mesh_xmalloc((size_t)m->ss_live + 1, sizeof(int32_t));
    f->sinterface = mesh_xmalloc((size_t)m->ss_live + 1, sizeof(int32_t));
    int32_t ns = 0;
    for (int32_t r = 0; r < m->nss; r++) {
        const mesh_subseg *s = &m->ss[r];
        if (s->level == -2) continue;
        f->seg[2 * ns] = s->u;
        f->seg[2 * ns + 1] = s->v;
        f->smarker[ns] = m->smarker[s->seg];
        f->sinterface[ns] = m->siface[s->seg];
        ns++;
    }
    int32_t *mk = m->vseg; /* markers over vseg, one int32 each, in place */
    for (int32_t v = 0; v < m->nv; v++)
        mk[v] = v < m->ninput ? (m->in_vmarker ? m->in_vmarker[v] : 0)
                : mk[v] >= 0  ? m->smarker[mk[v]]
                              : 0;
    f->nverts = m->nv;
    f->vmarker = mesh_xrealloc(mk, (size_t)m->nv + 1, sizeof(int32_t));
    f->xy = mesh_xrealloc(m->xy, 2 * (size_t)m->nv + 1, sizeof(double));
    f->scale_exp = m->scale_exp;
    m->vseg = NULL;
    m->xy = NULL;
    mesh_free(m);
}

double mesh_area(const mesh *m) {
    /* doubled areas summed plainly in blocks of 256 slots, the blocks with Neumaier's
     * compensation: accurate for millions of triangles at a fraction of compensating each */
    double a = 0, c = 0;
    const double *xy = m->xy;
    for (int32_t t0 = 0; t0 < m->nt; t0 += 256) {
        int32_t t1 = m->nt - t0 < 256 ? m->nt : t0 + 256;
        double x = 0;
        for (int32_t t = t0; t < t1; t++) {
            if (!mesh_tri_alive(m, t)) continue;
            const int32_t *v = m->tv + 3 * (size_t)t;
            const double *p = xy + 2 * (size_t)v[0], *q = xy + 2 * (size_t)v[1],
                         *r = xy + 2 * (size_t)v[2];
            x += (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
        }
        double s = a + x;
        c += fabs(a) >= fabs(x) ? (a - s) + x : (x - s) + a;
        a = s;
    }
    return 0.5 * (a + c);
}

double mesh_boundary_length(const mesh *m, double *mag) {
    double len = 0, mg = 0;
    for (int32_t v = 0; v < m->nv; v++)
        mg = fmax(mg, fmax(fabs(m->xy[2 * (size_t)v]), fabs(m->xy[2 * (size_t)v + 1])));
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j;
            if (m->tn[e] >= 0) continue;
            const mesh_subseg *s = mesh_subseg_of_edge(m, e);
            if (s && m->siface[s->seg]) continue;
            len +=
                sqrt(geom_dist2(mesh_vertex_xy(m, m->tv[e]), mesh_vertex_xy(m, mesh_dest(m, e))));
        }
    }
    if (mag) *mag = mg;
    return len;
}

size_t mesh_memory_bytes(const mesh *m) {
    size_t b = (size_t)m->vcap * (2 * sizeof(double) + 2 * sizeof(int32_t));
    b += (size_t)m->tcap * (6 * sizeof(int32_t) + 1);
    b += (size_t)m->segcap * (4 * sizeof(int32_t) + 1);
    b += (size_t)m->sscap * sizeof(mesh_subseg) + 2 * (size_t)m->hcap * sizeof(int32_t);
    b += (size_t)m->cavcap * 4 + (size_t)m->bndcap * sizeof(mesh_bedge);
    b += (size_t)(m->stkcap + m->newtcap) * 4;
    if (m->treg) b += (size_t)m->tcap * sizeof(int32_t);
    return b;
}
