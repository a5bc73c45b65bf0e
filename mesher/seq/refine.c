/* refine.c: Delaunay refinement -- Ruppert's algorithm with Chew's circumcenter insertion, as
 * used by the paper's Parallel Constrained Meshing Algorithm (section 3).
 *
 * Ruppert, "A Delaunay refinement algorithm for quality 2-dimensional mesh generation"
 * (J. Algorithms 18, 1995); Chew, "Guaranteed-quality mesh generation for curved surfaces"
 * (SoCG 1993); Shewchuk, "Delaunay refinement algorithms for triangular mesh generation"
 * (CGTA 22, 2002); Ungor, "Off-centers" (LATIN 2004).
 *
 * The rules themselves (what is bad, the Steiner point, encroachment, shell split points, the
 * forced-angle test) live in rules.c, shared with the other meshers; this file owns the queues,
 * the mesh surgery and the corner bookkeeping.
 *
 * Work queues: encroached subsegments (a FIFO of vertex pairs, always drained first) and bad
 * triangles in 4096 buckets by the binary exponent of the squared shortest edge, shortest
 * first (as Triangle orders them), last-in first-out inside a bucket (the newest triangles are
 * hot in cache, and in practice this inserts fewer points than FIFO).  Queue entries are triangle
 * ids (a stack of int32 per bucket) and are re-validated when popped, so stale entries (a dead
 * or reused slot) cost one test; a large bucket drops its stale entries before it grows. For
 * a bad triangle the Steiner point is its circumcenter, or Ungor's off-center on the bisector of
 * the shortest edge when that is closer (the off-center makes the new triangle on the shortest edge
 * just meet the bound, with a 5% margin).  The point is located by a walk from the triangle that
 * refuses to cross constraint edges; a walk stopped by a constraint edge splits that subsegment
 * instead (the point lies beyond it).  Its cavity is collected; if the point encroaches a
 * subsegment on the cavity boundary (geom_encroaches, exact), it is discarded and those subsegments
 * are split. Subsegments are split at the dyadic midpoint of their original segment, except a
 * non-interface subsegment with one endpoint at a small-angle input corner or at an end of an
 * interface segment, which is split on a concentric shell around it (power-of-two distance,
 * Ruppert 1995 / Shewchuk 2002 sec. 5), and an interface subsegment, split where its name puts
 * it (mesh_rules_iface_point: the pieces at both ends of an interface segment on the same
 * power-of-two shells, so at every corner of the decomposition the pieces on both sides can
 * become equal).
 * A skinny triangle whose shortest edge joins vertices on two input (non-interface) segments of
 * such a corner at the same distance from it is left alone: its small angle is forced by the
 * input.  Corners involving an interface segment get no such exemption (they are not corners
 * of the input).  Interface splits that would exhaust precision are refused identically on
 * every rank (decided from the name and the input coordinates); an interface segment splits
 * itself into at most MESH_RULES_IFACE_MAX_PIECES pieces.  Past the Steiner limit only
 * encroached interface subsegments are still split (named splits and their cascades included):
 * the merged parallel mesh must stay Delaunay across interfaces; what could not be split is
 * counted for the caller (mesh_iface_defects).  Invariants:
 * the mesh stays a CDT; encroached subsegments never wait behind bad triangles; a split is never
 * undone; an interface subsegment's split point is a function of its name and its segment's
 * endpoints alone.
 */
#include "mesh_impl.h"

#include "geom/geom.h"
#include "seq/rules.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define NBUCKET 4096
#define UNRESOLVED_BUDGET 256
#define QUEUE_COMPACT 4096 /* a bucket this full drops its stale entries before growing */
#define UNMET_AHEAD 16     /* mesh_count_unmet's prefetch distance, in triangle slots */

#if defined(__GNUC__)
#define PREFETCH(p) __builtin_prefetch(p)
#else
#define PREFETCH(p) ((void)(p))
#endif

/* One bucket of bad triangles: a stack of triangle ids (last in, first out). */
typedef struct qstack {
    int32_t *t;
    int32_t n, cap;
} qstack;

struct mesh_refine_state {
    qstack q[NBUCKET]; /* per bucket: a stack of triangle ids */
    int32_t cursor;    /* no bucket below it holds an entry (NBUCKET: none does) */
    int32_t *enc;      /* triples u, v, forced */
    int32_t nenc, enccap, enchead;
    mesh_rules R; /* the bounds, as the shared refinement rules take them */
    int need_scan;
    double floor2;            /* squared length floor: no new edge shorter (0: not computed yet) */
    int32_t *pieces, npieces; /* per segment: its subsegments (0: one, never split) */
    int32_t since_poll;
    double area_budget;    /* boundary splits may move the domain's area by this much in all
                              (mesh_rules_area_drift; < 0: not computed yet) */
    double area_spent;     /* ... and have moved it by this much (signed: + grown) */
    int64_t named_refused; /* named splits this mesh could not make (mesh_iface_defects) */
};

static const double *X(const mesh *m, int32_t v) {
    return m->xy + 2 * (size_t)v;
}

static mesh_refine_state *rf_get(mesh *m) {
    if (m->rf) return m->rf;
    mesh_refine_state *r = mesh_xrealloc(NULL, 1, sizeof *r);
    memset(r, 0, sizeof *r);
    r->cursor = NBUCKET;
    mesh_rules_init(&r->R, 0, 0, 0, 0);
    r->need_scan = 1;
    r->area_budget = -1;
    m->rf = r;
    return r;
}

void mesh_refine_free(mesh *m) {
    if (!m->rf) return;
    for (int i = 0; i < NBUCKET; i++)
        free(m->rf->q[i].t);
    free(m->rf->enc);
    free(m->rf->pieces);
    free(m->rf);
    m->rf = NULL;
}

void mesh_set_quality(mesh *m, const mesh_quality *q) {
    mesh_refine_state *r = rf_get(m);
    m->q = *q;
    mesh_rules_init(&r->R, q->min_angle, pslg_scaled_area(m->scale_exp, q->max_area), q->offcenter,
                    q->lens);
    r->R.unsuitable = m->size_rule;
    r->R.unsuitable_ctx = m->size_rule_ctx;
    r->need_scan = 1;
}

void mesh_set_size_rule(mesh *m, int (*fn)(void *ctx, const double *const p[3], double area),
                        void *ctx) {
    mesh_refine_state *r = rf_get(m);
    m->size_rule = fn;
    m->size_rule_ctx = ctx;
    r->R.unsuitable = fn;
    r->R.unsuitable_ctx = ctx;
    r->need_scan = 1;
}

void mesh_set_hooks(mesh *m, const mesh_hooks *h) {
    m->hooks = *h;
    if (m->hooks.poll_every <= 0) m->hooks.poll_every = 200;
}

/* ---- quality ------------------------------------------------------------------------------ */

/* Queue priority of a bad triangle whose squared shortest edge is l2 (0 = worst): the binary
 * exponent of l2, shortest first (mesh_rules_bucket, inline on the path of every new
 * triangle). */
static inline int bucket_of(double l2) {
    uint64_t bits;
    memcpy(&bits, &l2, sizeof bits);
    int k = (int)((bits >> 52) & 0x7ff) - 1023 + NBUCKET / 2; /* binary exponent */
    return k < 0 ? 0 : k >= NBUCKET ? NBUCKET - 1 : k;
}

/* MESH_BAD_ANGLE / MESH_BAD_AREA bits (mesh_rules_bad), 0: good.  *l2 (may be NULL): the
 * squared shortest edge.  *sh: index j of the shortest edge (edge 3t+j). */
MESH_RULES_INLINE int quality(const mesh *m, const mesh_rules *R, int32_t t, double *l2, int *sh) {
    const int32_t *tv = m->tv + 3 * (size_t)t;
    const double *p[3] = {X(m, tv[0]), X(m, tv[1]), X(m, tv[2])};
    return mesh_rules_bad_bound(R, mesh_tri_area_bound(m, t, R->max_area), p, sh, l2);
}

int mesh_tri_bad(const mesh *m, int32_t t) {
    mesh_rules R;
    mesh_rules_init(&R, m->q.min_angle, pslg_scaled_area(m->scale_exp, m->q.max_area), 0, 0);
    R.unsuitable = m->size_rule;
    R.unsuitable_ctx = m->size_rule_ctx;
    return quality(m, &R, t, NULL, NULL);
}

/* Makes room in a full bucket: doubles its stack, or once it holds QUEUE_COMPACT entries, first
 * drops the entries whose slot is no longer queued (the triangle died, or its slot was
 * rewritten since and not queued again: either is skipped when popped), keeping the order of
 * the rest, and doubles only if that freed less than half.  Most entries go stale before they
 * are popped (a queued triangle falls into the cavity of a neighbour's Steiner point): on lake
 * at 10M triangles the queue held 8.3M entries (67 MB as a linked pool) for about 0.6M live
 * ones; dropped, the queue stays near the size of its live part.  A dropped entry cannot
 * bring back its slot if the slot is queued again later, so the order of a large refinement
 * differs a little from one that keeps every entry (meshes as good; small ones, below the
 * threshold, are unchanged). */
static void make_room(mesh *m, qstack *q) {
    if (q->cap >= QUEUE_COMPACT) {
        int32_t n = 0;
        for (int32_t i = 0; i < q->n; i++) {
            int32_t t = q->t[i];
            if (m->tf[t] & MESH_QUEUED) q->t[n++] = t;
        }
        q->n = n;
    }
    if (2 * q->n >= q->cap) {
        q->cap = q->cap ? 2 * q->cap : 256;
        q->t = mesh_xrealloc(q->t, (size_t)q->cap, sizeof(int32_t));
    }
}

MESH_RULES_INLINE void push_bad(mesh *m, int32_t t) {
    mesh_refine_state *r = m->rf;
    double l2;
    if (!quality(m, &r->R, t, &l2, NULL)) return;
    int k = bucket_of(l2);
    m->tf[t] |= MESH_QUEUED;
    qstack *q = &r->q[k];
    if (q->n == q->cap) make_room(m, q);
    q->t[q->n++] = t; /* LIFO inside a bucket: hot in cache, fewer points */
    if (k < r->cursor) r->cursor = k;
}

static int32_t pop_bad(mesh *m) {
    mesh_refine_state *r = m->rf;
    while (r->cursor < NBUCKET && r->q[r->cursor].n == 0)
        r->cursor++;
    if (r->cursor == NBUCKET) return -1;
    qstack *q = &r->q[r->cursor];
    return q->t[--q->n];
}

static void push_new(mesh *m) {
    for (int32_t i = 0; i < m->nnewt; i++)
        push_bad(m, m->newt[i]);
}

/* ---- encroachment ------------------------------------------------------------------------- */

static void push_enc(mesh *m, int32_t u, int32_t v, int forced) {
    mesh_refine_state *r = m->rf;
    if (r->nenc + 3 > r->enccap) {
        if (r->enchead > 0) {
            memmove(r->enc, r->enc + r->enchead, (size_t)(r->nenc - r->enchead) * 4);
            r->nenc -= r->enchead;
            r->enchead = 0;
        }
        if (r->nenc + 3 > r->enccap) {
            r->enccap = r->enccap ? r->enccap * 2 : 192;
            r->enc = mesh_xrealloc(r->enc, r->enccap, sizeof(int32_t));
        }
    }
    r->enc[r->nenc++] = u;
    r->enc[r->nenc++] = v;
    r->enc[r->nenc++] = forced;
}

/* Does p encroach subsegment ab?  Diametral circle, or with q.lens the diametral lens
 * (mesh_rules_encroaches). */
static int enc_test(const mesh *m, const double *a, const double *b, const double *p) {
    return mesh_rules_encroaches(&m->rf->R, a, b, p);
}

/* Constraint edge e encroached by the apex of a triangle on either side. */
static int encroached(const mesh *m, int32_t e) {
    const double *a = X(m, m->tv[e]), *b = X(m, mesh_dest(m, e));
    if (enc_test(m, a, b, X(m, mesh_apex(m, e)))) return 1;
    int32_t f = m->tn[e];
    return f >= 0 && enc_test(m, a, b, X(m, mesh_apex(m, f)));
}

/* The corner of a small angle that a subsegment with endpoint v (an input vertex) touches. */
static int is_corner(const mesh *m, int32_t v) {
    return v < m->ninput && m->corner && m->corner[v];
}

/* 1 iff v is an end of an interface segment: a corner of the decomposition, where the pieces
 * of a boundary segment are split on the power-of-two shells the interface's pieces use
 * (mesh_rules_iface_point), so the pieces on both sides can become equal. */
static int iface_end(const mesh *m, int32_t v) {
    if (v >= m->ninput || !m->inc_off) return 0;
    for (int32_t i = m->inc_off[v]; i < m->inc_off[v + 1]; i++)
        if (m->siface[m->inc_seg[i]]) return 1;
    return 0;
}

/* The length floor (squared) below which refinement refuses to go, computed once from the
 * initial triangulation: the larger of 2^-24 times its smallest altitude (a bound on the
 * input's local feature size; Ruppert's refinement never needs edges that much shorter, so
 * reaching it means the refinement diverges, e.g. an angle bound beyond what it can reach) and
 * 2^-44 times the coordinates' magnitude (features below that are below the precision of the
 * coordinates: circumcenters and midpoints there are mostly rounding).  Deciding whether to
 * refine, never topology, so a rounded measure is fine. */
static double length_floor2(const mesh *m) {
    double mag = 0, alt2 = INFINITY;
    for (int32_t v = 0; v < m->nv; v++)
        mag = fmax(mag, fmax(fabs(X(m, v)[0]), fabs(X(m, v)[1])));
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        const int32_t *tv = m->tv + 3 * (size_t)t;
        const double *a = X(m, tv[0]), *b = X(m, tv[1]), *c = X(m, tv[2]);
        double l = fmax(geom_dist2(a, b), fmax(geom_dist2(b, c), geom_dist2(c, a)));
        double ar = geom_area(a, b, c);
        if (l > 0) alt2 = fmin(alt2, 4 * ar * ar / l);
    }
    double f = fmax(isfinite(alt2) ? alt2 * 0x1p-48 : 0, mag * mag * 0x1p-88);
    return f > 0 ? f : DBL_MIN;
}

void mesh_fix_length_floor(mesh *m) {
    rf_get(m)->floor2 = length_floor2(m);
}

void mesh_set_length_floor(mesh *m, double floor2) {
    rf_get(m)->floor2 = floor2 > 0 ? floor2 : length_floor2(m);
}

/* 1 iff a new vertex at p would make an edge to a shorter than the floor. */
static int below_floor(const mesh *m, const double *p, const double *a) {
    return geom_dist2(p, a) < m->rf->floor2;
}

/* The split point p of subsegment (pu, pv), edge e, is too far off its line for the
 * triangles beside it (mesh_rules_off_line). */
static int off_line(const mesh *m, int32_t e, const double *pu, const double *pv, const double *p) {
    const double *w[2] = {NULL, NULL};
    for (int k = 0; k < 2; k++) {
        int32_t f = k ? m->tn[e] : e, a = f >= 0 ? mesh_apex(m, f) : -1;
        if (a >= 0) w[k] = X(m, a);
    }
    return mesh_rules_off_line(pu, pv, p, w[0], w[1]);
}

/* 1 iff split point p of the boundary subsegment (pu, pv), edge e (its other side outside the
 * domain), would move the domain's area, summed with sign over every boundary split so far,
 * by more than its budget (mesh_rules_area_drift); otherwise the move is recorded.  A rounded
 * split point off its line moves the boundary by |orient2d| / 2: nothing on ordinary inputs
 * (a few ulps per split, of either sign), but on a sliver domain one rounded midpoint can move
 * it by percents (a fuzzed point set 8.9e17 long and 70 high gained 6% of its area, and
 * --check refused the mesh). */
static int area_drift(mesh *m, int32_t e, const double *pu, const double *pv, const double *p) {
    mesh_refine_state *rs = m->rf;
    if (rs->area_budget < 0) {
        double mag, len = mesh_boundary_length(m, &mag);
        rs->area_budget = mesh_rules_area_drift(mesh_area(m), mag, len);
    }
    return mesh_rules_drift_spend(pu, pv, p, X(m, mesh_apex(m, e)), rs->area_budget,
                                  &rs->area_spent);
}

/* Splits subsegment record r.  notify: call on_split for an interface subsegment.  Returns 0,
 * or -1 if it cannot be split (precision exhausted; counted as failed). */
static int split_subseg(mesh *m, int32_t r, int notify) {
    mesh_subseg s = m->ss[r];
    const double *pu = X(m, s.u), *pv = X(m, s.v);
    double p[2];
    int32_t nl = -1;
    int64_t k0 = 0, k1 = 0;
    int iface = m->siface[s.seg];
    if (iface) {
        /* Interface pieces must stay dyadic and nameable by both ranks: refuse, on the name and
         * the input coordinates alone (so every rank refuses alike), a split whose halves would
         * be shorter than 2^-44 (the length floor) of the coordinates' magnitude.  Refinement
         * cannot need it (the shells at corners match, see mesh_rules_iface_point); a split one
         * rank made and the other could not would leave the merged mesh non-conforming. */
        const double *a = X(m, m->seg[2 * s.seg]), *b = X(m, m->seg[2 * s.seg + 1]);
        double mag = fmax(fmax(fabs(a[0]), fabs(a[1])), fmax(fabs(b[0]), fabs(b[1])));
        double L = sqrt(geom_dist2(a, b));
        if (s.level < 0 || s.level >= 48 || ldexp(L, -(s.level + 1)) < 0x1p-44 * fmax(mag, L)) {
            m->stats.failed++;
            return -1;
        }
    }
    int cu = !iface && (is_corner(m, s.u) || iface_end(m, s.u));
    int cv = !iface && (is_corner(m, s.v) || iface_end(m, s.v));
    if (cu != cv) {
        mesh_rules_shell_point(cu ? pu : pv, cu ? pv : pu, 1.0, p);
    } else if (s.level >= 0 && s.level < 52) {
        if (iface)
            mesh_rules_iface_point(X(m, m->seg[2 * s.seg]), X(m, m->seg[2 * s.seg + 1]), s.level,
                                   s.k, p);
        else
            mesh_dyadic_point(X(m, m->seg[2 * s.seg]), X(m, m->seg[2 * s.seg + 1]), s.level, s.k,
                              p);
        nl = s.level + 1;
        k0 = 2 * s.k;
        k1 = 2 * s.k + 1;
    } else {
        geom_midpoint(pu, pv, p);
    }
    if (geom_working_point(p) != 0 || (p[0] == pu[0] && p[1] == pu[1]) ||
        (p[0] == pv[0] && p[1] == pv[1])) {
        m->stats.failed++;
        return -1;
    }
    if (!iface && m->rf->floor2 > 0 && (below_floor(m, p, pu) || below_floor(m, p, pv))) {
        m->stats.unresolved++;
        return -1;
    }
    /* a region too thin for its length: at most MESH_RULES_MAX_PIECES pieces per segment; an
     * interface segment splits itself (notify: its own decision, not a neighbour's request) into
     * at most MESH_RULES_IFACE_MAX_PIECES: two interfaces meeting at a tiny angle (a decomposition
     * of an input refinement cannot resolve) split each other's pieces practically forever
     * otherwise. The pieces on the two sides then differ only by what the other side split, which
     * it sends: the merged mesh still conforms; an interface left encroached is reported afterwards
     * (mesh_iface_defects) */
    {
        mesh_refine_state *rs = m->rf;
        if (rs->npieces < m->nseg) {
            rs->pieces = mesh_xrealloc(rs->pieces, (size_t)m->nseg, sizeof *rs->pieces);
            memset(rs->pieces + rs->npieces, 0,
                   (size_t)(m->nseg - rs->npieces) * sizeof *rs->pieces);
            rs->npieces = m->nseg;
        }
        if (iface ? notify && rs->pieces[s.seg] >= MESH_RULES_IFACE_MAX_PIECES - 1
                  : rs->pieces[s.seg] >= MESH_RULES_MAX_PIECES - 1) {
            m->stats.unresolved++;
            return -1;
        }
    }
    int32_t e = mesh_find_edge(m, s.u, s.v);
    if (e < 0) MESH_BUG("subsegment %d-%d has no edge", s.u, s.v);
    if (off_line(m, e, pu, pv, p)) {
        m->stats.failed++;
        return -1;
    }
    if (!iface && m->tn[e] < 0 && area_drift(m, e, pu, pv, p)) {
        m->stats.unresolved++;
        return -1;
    }
    int32_t bad = -1;
    int st = mesh_cavity_collect(m, p, e / 3, e, &bad);
    if (st != CAV_OK) {
        mesh_cavity_abort(m);
        m->stats.failed++;
        return -1;
    }
    int32_t v = mesh_vert_add(m, p[0], p[1], s.seg);
    mesh_cavity_commit(m, v, s.u, s.v);
    mesh_ss_del(m, r);
    mesh_ss_add(m, s.u, v, s.seg, nl, k0);
    mesh_ss_add(m, v, s.v, s.seg, nl, k1);
    m->stats.seg_splits++;
    m->rf->pieces[s.seg]++;
    m->rf->since_poll++;
    push_enc(m, s.u, v, 0);
    push_enc(m, v, s.v, 0);
    for (int32_t i = 0; i < m->nnewt; i++) {
        int32_t t = m->newt[i];
        if ((m->tf[t] & 1) && enc_test(m, X(m, m->tv[3 * t]), X(m, m->tv[3 * t + 1]), p))
            push_enc(m, m->tv[3 * t], m->tv[3 * t + 1], 0);
    }
    push_new(m);
    if (iface && notify) {
        m->stats.iface_splits++;
        if (m->hooks.on_split)
            m->hooks.on_split(m->hooks.ctx, s.seg, s.level, s.k, MESH_SPLIT_INTERFACE);
    }
    return 0;
}

/* Past the budget of refusals (UNRESOLVED_BUDGET + ninput / 4): the refinement diverges. */
static int over_budget(const mesh *m) {
    return m->stats.unresolved > UNRESOLVED_BUDGET + m->ninput / 4;
}

static int steiner_limit(const mesh *m) {
    return m->q.max_steiner >= 0 && (int64_t)(m->nv - m->ninput) >= m->q.max_steiner;
}

/* At the Steiner limit: splits the queued interface subsegments that are still encroached (a
 * vertex inside the diametral circle) and keeps every other entry queued, in order.  An
 * interface edge is no constraint of the input: the merged parallel mesh must be Delaunay across
 * it, which an encroached one may not be (the validator would refuse the mesh), so the limit
 * stops the refinement's own decisions but not these splits; their cascade stays on the
 * interfaces (input subsegments are never split here) and each split still notifies the other
 * side.  A mesh with no interface segment (./mesh) keeps its queue as it was. */
static int64_t drain_iface_at_limit(mesh *m) {
    mesh_refine_state *r = m->rf;
    int64_t done = 0;
    int32_t *kept = NULL, nkept = 0, cap = 0;
    while (r->enchead < r->nenc && !over_budget(m)) {
        int32_t u = r->enc[r->enchead], v = r->enc[r->enchead + 1];
        int forced = r->enc[r->enchead + 2];
        r->enchead += 3;
        int32_t rec = mesh_ss_find_pair(m, u, v);
        if (rec >= 0 && m->siface[m->ss[rec].seg]) {
            int32_t e = mesh_find_edge(m, u, v);
            if (e < 0) MESH_BUG("subsegment %d-%d has a record but no edge", u, v);
            if (encroached(m, e) && split_subseg(m, rec, 1) == 0) done++;
            continue;
        }
        if (nkept + 3 > cap) {
            cap = cap ? 2 * cap : 48;
            kept = mesh_xrealloc(kept, (size_t)cap, sizeof *kept);
        }
        kept[nkept++] = u;
        kept[nkept++] = v;
        kept[nkept++] = forced;
    }
    r->nenc = r->enchead = 0;
    for (int32_t i = 0; i < nkept; i += 3)
        push_enc(m, kept[i], kept[i + 1], kept[i + 2]);
    free(kept);
    return done;
}

static int on_corner_segments(const mesh *m, int32_t u, int32_t v);

/* Constraint edge e encroached by the apex of a triangle on either side, where the split can
 * change something: an apex on the other segment of a small input corner at the same distance
 * from it as an endpoint of e (on_corner_segments: the triangle's small angle is forced, the
 * validator exempts it) does not count.  Splitting for it only moves the mismatch: two
 * segments at 1e-10 radians whose far ends differ by more than their distance apart there
 * split each other into 2^20 pieces (MESH_RULES_MAX_PIECES), all forced, in seconds. */
static int encroached_unforced(const mesh *m, int32_t e) {
    int32_t u = m->tv[e], v = mesh_dest(m, e);
    for (int k = 0; k < 2; k++) {
        int32_t f = k ? m->tn[e] : e;
        if (f < 0) continue;
        int32_t p = mesh_apex(m, f);
        if (!enc_test(m, X(m, u), X(m, v), X(m, p))) continue;
        if (!m->has_corners || !(on_corner_segments(m, p, u) || on_corner_segments(m, p, v)))
            return 1;
    }
    return 0;
}

/* Drains the encroached-subsegment queue.  Returns the number of subsegments split.  Once the
 * Steiner limit is reached only encroached interface subsegments are split
 * (drain_iface_at_limit); the other entries stay queued. */
static int64_t drain_enc(mesh *m) {
    mesh_refine_state *r = m->rf;
    int64_t done = 0;
    while (r->enchead < r->nenc) {
        if (over_budget(m)) return done; /* diverging (mesh_refine stops) */
        if (steiner_limit(m)) return done + drain_iface_at_limit(m);
        int32_t u = r->enc[r->enchead], v = r->enc[r->enchead + 1];
        int forced = r->enc[r->enchead + 2];
        r->enchead += 3;
        int32_t rec = mesh_ss_find_pair(m, u, v);
        if (rec < 0) continue;
        int32_t e = mesh_find_edge(m, u, v);
        if (e < 0) MESH_BUG("subsegment %d-%d has a record but no edge", u, v);
        if (!forced && !encroached_unforced(m, e)) continue;
        if (split_subseg(m, rec, 1) == 0) done++;
    }
    r->nenc = r->enchead = 0;
    return done;
}

/* Splits the subsegments queued because of bad triangle t; t goes back to the queue only if
 * something was split, so an unsplittable subsegment (precision exhausted) cannot loop. */
static void split_for(mesh *m, int32_t t) {
    if (drain_enc(m) > 0) push_bad(m, t);
}

/* ---- bad triangles --------------------------------------------------------------------------*/

/* 1 iff no other input segment at corner a points strictly inside the wedge o1-a-o2
 * (< 180 deg): s1 and s2 are neighbours around a, as the validator's corner rule requires.
 * Interface segments are not input segments (the validator checks against the input without
 * the PCDM cuts), so they do not separate s1 from s2. */
static int consecutive(const mesh *m, int32_t a, int32_t o1, int32_t o2) {
    for (int32_t i = m->inc_off[a]; i < m->inc_off[a + 1]; i++) {
        int32_t s3 = m->inc_seg[i];
        if (m->siface[s3]) continue;
        int32_t o3 = m->seg[2 * s3] == a ? m->seg[2 * s3 + 1] : m->seg[2 * s3];
        if (o3 == o1 || o3 == o2) continue;
        if (mesh_rules_in_wedge(X(m, a), X(m, o1), X(m, o2), X(m, o3))) return 0;
    }
    return 1;
}

/* 1 iff u and v lie on two angularly consecutive input segments meeting at a corner below 60
 * degrees, at the same distance from it (within 1%).  Only input segments count: a corner
 * between an interface segment and another segment is a corner of the augmented PSLG, not of
 * the input, so the validator does not exempt it and the angle bound must be met there
 * (possible: cuts meet other segments at >= the angle bound, and the shells on both sides
 * match, see mesh_rules_iface_point). */
static int on_corner_segments(const mesh *m, int32_t u, int32_t v) {
    if (!m->has_corners) return 0;
    int32_t su1 = 0, su2 = 0, sv1 = 0, sv2 = 0;
    int32_t one_u = -1, one_v = -1;
    if (u < m->ninput)
        su1 = m->inc_off[u], su2 = m->inc_off[u + 1];
    else if (m->vseg[u] >= 0)
        one_u = m->vseg[u];
    else
        return 0;
    if (v < m->ninput)
        sv1 = m->inc_off[v], sv2 = m->inc_off[v + 1];
    else if (m->vseg[v] >= 0)
        one_v = m->vseg[v];
    else
        return 0;
    int32_t nu = one_u >= 0 ? 1 : su2 - su1, nv = one_v >= 0 ? 1 : sv2 - sv1;
    for (int32_t i = 0; i < nu; i++) {
        int32_t s1 = one_u >= 0 ? one_u : m->inc_seg[su1 + i];
        for (int32_t j = 0; j < nv; j++) {
            int32_t s2 = one_v >= 0 ? one_v : m->inc_seg[sv1 + j];
            if (s1 == s2 || m->siface[s1] || m->siface[s2]) continue;
            for (int x = 0; x < 2; x++)
                for (int y = 0; y < 2; y++) {
                    int32_t a = m->seg[2 * s1 + x];
                    if (a != m->seg[2 * s2 + y] || a == u || a == v || !is_corner(m, a)) continue;
                    int32_t o1 = m->seg[2 * s1 + 1 - x], o2 = m->seg[2 * s2 + 1 - y];
                    if (!consecutive(m, a, o1, o2)) continue;
                    if (mesh_rules_corner_forced(X(m, a), X(m, o1), X(m, o2), X(m, u), X(m, v)))
                        return 1;
                }
        }
    }
    return 0;
}

/* Steiner point of bad triangle t (mesh_rules_steiner).  Returns 0, -1 if degenerate. */
static int steiner_point(const mesh *m, int32_t t, int sh, double out[2]) {
    const int32_t *tv = m->tv + 3 * (size_t)t;
    const double *p[3] = {X(m, tv[0]), X(m, tv[1]), X(m, tv[2])};
    return mesh_rules_steiner(&m->rf->R, p, sh, out);
}

static void process_bad(mesh *m, int32_t t) {
    int sh = 0;
    int why = quality(m, &m->rf->R, t, NULL, &sh);
    if (!why) return;
    if (why == MESH_BAD_ANGLE && m->has_corners) { /* skinny but not too large */
        int32_t u = m->tv[3 * t + sh], v = m->tv[3 * t + (sh + 1) % 3];
        if (on_corner_segments(m, u, v)) {
            m->stats.skipped_small++;
            return;
        }
    }
    double c[2];
    if (steiner_point(m, t, sh, c) != 0 || geom_working_point(c) != 0) {
        m->stats.failed++;
        return;
    }
    /* the new vertex is at least the circumradius away from every vertex (empty circle): its
     * distance to t's vertices is the length of the shortest edge it creates */
    const int32_t *tt = m->tv + 3 * (size_t)t;
    if (below_floor(m, c, X(m, tt[0])) || below_floor(m, c, X(m, tt[1])) ||
        below_floor(m, c, X(m, tt[2]))) {
        m->stats.unresolved++;
        return;
    }
    int32_t blocked = -1;
    int32_t tc = mesh_walk(m, c, t, 1, &blocked);
    if (tc < 0) {
        m->stats.blocked++;
        if (blocked >= 0) {
            push_enc(m, m->tv[blocked], mesh_dest(m, blocked), 1);
            split_for(m, t);
        } else {
            m->stats.failed++;
        }
        return;
    }
    const int32_t *tv = m->tv + 3 * (size_t)tc;
    for (int j = 0; j < 3; j++)
        if (X(m, tv[j])[0] == c[0] && X(m, tv[j])[1] == c[1]) {
            m->stats.failed++;
            return;
        }
    int32_t bad = -1;
    int st = mesh_cavity_collect(m, c, tc, -1, &bad);
    if (st != CAV_OK) {
        mesh_cavity_abort(m);
        if (st == CAV_NOT_STAR && bad >= 0 && mesh_edge_constrained(m, bad)) {
            m->stats.rejected++;
            push_enc(m, m->tv[bad], mesh_dest(m, bad), 1);
            split_for(m, t);
        } else {
            m->stats.failed++;
        }
        return;
    }
    int enc = 0;
    for (int32_t i = 0; i < m->nbnd; i++) {
        const mesh_bedge *b = &m->bnd[i];
        if (b->cons && enc_test(m, X(m, b->org), X(m, b->dest), c)) {
            push_enc(m, b->org, b->dest, 1);
            enc = 1;
        }
    }
    if (enc) {
        mesh_cavity_abort(m);
        m->stats.rejected++;
        split_for(m, t);
        return;
    }
    int32_t v = mesh_vert_add(m, c[0], c[1], -1);
    mesh_cavity_commit(m, v, -1, -1);
    m->stats.inserted++;
    m->rf->since_poll++;
    push_new(m);
}

static void scan(mesh *m) {
    mesh_refine_state *r = m->rf;
    if (r->floor2 == 0) r->floor2 = length_floor2(m);
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t)) push_bad(m, t);
    for (int32_t i = 0; i < m->nss; i++) {
        const mesh_subseg *s = &m->ss[i];
        if (s->level == -2) continue;
        int32_t e = mesh_find_edge(m, s->u, s->v);
        if (e >= 0 && encroached(m, e)) push_enc(m, s->u, s->v, 0);
    }
    r->need_scan = 0;
}

mesh_refine_result mesh_refine(mesh *m) {
    mesh_refine_state *r = rf_get(m);
    if (r->need_scan) scan(m);
    for (;;) {
        drain_enc(m);
        if (over_budget(m)) return MESH_REFINE_UNRESOLVED;
        if (r->enchead < r->nenc) return MESH_REFINE_STEINER_LIMIT;
        if (r->since_poll >= m->hooks.poll_every && m->hooks.poll) {
            r->since_poll = 0;
            m->stats.polls++;
            if (m->hooks.poll(m->hooks.ctx)) return MESH_REFINE_STOPPED;
            continue;
        }
        if (steiner_limit(m)) return MESH_REFINE_STEINER_LIMIT;
        /* every refusal leaves a triangle bad; past a budget the refinement is diverging (it
         * fills the region at the floor's resolution): stop instead of running forever */
        if (over_budget(m)) return MESH_REFINE_UNRESOLVED;
        int32_t t = pop_bad(m);
        if (t < 0) {
            if (r->enchead < r->nenc) continue;
            return MESH_REFINE_DONE;
        }
        /* a slot rewritten since it was queued lost its bit: skip it without touching it */
        if (!(m->tf[t] & MESH_QUEUED)) continue;
        m->tf[t] &= (uint8_t)~MESH_QUEUED;
        process_bad(m, t);
    }
}

/* 1 iff v is a small-angle corner of the input alone: two non-interface segments meet there
 * below 60 degrees (is_corner counts the decomposition's interface segments too, which the
 * validator does not: a skinny triangle at such a vertex is not forced by the input).  The same
 * as is_corner in a mesh with no interface segment. */
static int input_corner(const mesh *m, int32_t v) {
    if (!is_corner(m, v)) return 0;
    for (int32_t i = m->inc_off[v]; i < m->inc_off[v + 1]; i++)
        for (int32_t j = i + 1; j < m->inc_off[v + 1]; j++) {
            int32_t s1 = m->inc_seg[i], s2 = m->inc_seg[j];
            if (m->siface[s1] || m->siface[s2]) continue;
            int32_t o1 = m->seg[2 * s1] == v ? m->seg[2 * s1 + 1] : m->seg[2 * s1];
            int32_t o2 = m->seg[2 * s2] == v ? m->seg[2 * s2 + 1] : m->seg[2 * s2];
            if (geom_angle_deg(X(m, o1), X(m, v), X(m, o2)) < 60.0) return 1;
        }
    return 0;
}

int64_t mesh_count_unmet(mesh *m, int64_t *forced) {
    mesh_refine_state *r = rf_get(m);
    int64_t unmet = 0, nforced = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        /* the vertices of a triangle a few slots ahead: a slot's vertices lie anywhere in the
         * coordinate array, and on a large mesh this pass waits on memory, not arithmetic */
        if (t + UNMET_AHEAD < m->nt) {
            const int32_t *ta = m->tv + 3 * (size_t)(t + UNMET_AHEAD);
            for (int j = 0; j < 3; j++)
                if (ta[j] >= 0) PREFETCH(X(m, ta[j]));
        }
        if (!mesh_tri_alive(m, t)) continue;
        int sh = 0;
        int why = quality(m, &r->R, t, NULL, &sh);
        if (!why) continue;
        if (why == MESH_BAD_ANGLE) {
            const int32_t *tv = m->tv + 3 * (size_t)t;
            int32_t u = tv[sh], v = tv[(sh + 1) % 3];
            if (input_corner(m, tv[0]) || input_corner(m, tv[1]) || input_corner(m, tv[2]) ||
                on_corner_segments(m, u, v)) {
                nforced++;
                continue;
            }
        }
        unmet++;
    }
    if (forced) *forced = nforced;
    return unmet;
}

mesh_split_result mesh_split_subsegment_named(mesh *m, int32_t seg, int32_t level, int64_t k) {
    rf_get(m);
    if (seg < 0 || seg >= m->nseg || level < 0 || level > 60 || k < 0 ||
        k >= ((int64_t)1 << level)) {
        m->stats.named_not_found++;
        return MESH_SPLIT_NOT_FOUND;
    }
    int32_t r = mesh_ss_find_name(m, seg, level, k);
    if (r < 0) {
        /* a coarser ancestor still whole here: split down to the named subsegment */
        for (int32_t j = level - 1; j >= 0 && r < 0; j--) {
            r = mesh_ss_find_name(m, seg, j, k >> (level - j));
            if (r < 0) continue;
            while (m->ss[r].level < level) {
                int32_t jl = m->ss[r].level;
                if (split_subseg(m, r, 0) != 0) {
                    m->stats.named_already++;
                    m->rf->named_refused++;
                    drain_enc(m);
                    return MESH_SPLIT_ALREADY;
                }
                r = mesh_ss_find_name(m, seg, jl + 1, k >> (level - jl - 1));
                if (r < 0) { /* not dyadic below (a shell split): nothing named is left */
                    m->stats.named_already++;
                    drain_enc(m);
                    return MESH_SPLIT_ALREADY;
                }
            }
        }
    }
    if (r < 0) {
        if (m->seg_nsub[seg] > 0) {
            m->stats.named_already++;
            return MESH_SPLIT_ALREADY;
        }
        m->stats.named_not_found++;
        return MESH_SPLIT_NOT_FOUND;
    }
    if (split_subseg(m, r, 0) != 0) {
        m->stats.named_already++;
        m->rf->named_refused++;
        drain_enc(m);
        return MESH_SPLIT_ALREADY;
    }
    m->stats.named_done++;
    drain_enc(m);
    return MESH_SPLIT_DONE;
}

int64_t mesh_iface_defects(mesh *m, int64_t *remote) {
    int64_t n = rf_get(m)->named_refused, nr = 0;
    for (int32_t i = 0; i < m->nss; i++) {
        const mesh_subseg *s = &m->ss[i];
        if (s->level == -2 || !m->siface[s->seg]) continue;
        int32_t e = mesh_find_edge(m, s->u, s->v);
        if (e < 0 || !encroached(m, e)) continue;
        int32_t f = m->tn[e]; /* both sides here: what counts is the Delaunay test, exact */
        if (f < 0)
            nr++;
        else if (geom_incircle(X(m, m->tv[e]), X(m, mesh_dest(m, e)), X(m, mesh_apex(m, e)),
                               X(m, mesh_apex(m, f))) > 0)
            n++;
    }
    if (remote) *remote = nr;
    return n;
}
