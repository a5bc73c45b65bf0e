/* cdt.c: constrained Delaunay triangulation of a PSLG.
 *
 * 1. Delaunay triangulation of the vertices by randomized incremental Bowyer-Watson insertion
 *    with ghost triangles (a vertex at infinity closes the convex hull, so points outside the
 *    hull need no special case).  Insertion order is BRIO (Amenta, Choi, Rote, "Incremental
 *    constructions con BRIO", 2003): rounds of geometrically growing random subsets, each round
 *    sorted along a Hilbert curve, and every walk starts from the previous insertion, so point
 *    location is a few steps and memory access stays local.  Then the triangles are renumbered
 *    along the same curve (the slots the insertions freed and reused scatter neighbours over
 *    the arrays; every later pass reads them in adjacency order).
 * 2. Segments are inserted one by one (Sloan, "A fast algorithm for generating constrained
 *    Delaunay triangulations", 1993): walk along the segment from one endpoint collecting the
 *    edges it crosses (stopping early at a vertex lying exactly on it -- exact orient2d == 0 --
 *    where the segment is split), flip crossing edges whose quadrilateral is strictly convex
 *    until none crosses, then flip the new edges that are not locally Delaunay.  The result is
 *    the CDT (Chew 1989, Lee and Lin 1986).  The pieces' subsegment records are added after the
 *    last segment, in segment order, the hash tables read a few records ahead.
 * 3. Triangles outside the domain are removed as Triangle does: everything reachable from the
 *    convex hull (ghost triangles) or from a hole point without crossing a segment.  A PSLG with
 *    no segment keeps its convex hull, whose edges become segments.
 * 4. mesh_build_from_triangles takes a triangulation already made instead (a subdomain's
 *    triangles cut from the CDT of its decomposition): the triangles' adjacency found through
 *    each vertex's outgoing edges, each segment marked on its edge, checked (counter-clockwise
 *    by exact orient2d, every edge in at most two triangles, every segment an edge, every
 *    boundary edge a segment) rather than trusted.
 * Invariants on return: no ghost triangles; every boundary edge (tn == -1) is a constraint
 * edge with a subsegment record; every subsegment record is an edge of the mesh.
 */
#include "mesh_impl.h"

#include "geom/geom.h"

#include <math.h>
#include <stdarg.h>
#include <string.h>

static const double *X(const mesh *m, int32_t v) {
    return m->xy + 2 * (size_t)v;
}

/* ---- insertion order: BRIO rounds, Hilbert order inside a round --------------------------- */

/* The Hilbert curve's index of cell (x, y) of a 65536 x 65536 grid, read 4 bits of x and y at
 * a time.  The curve's rule, a bit of each at a time from the top: the quadrant (rx, ry) of the
 * coordinates as the curve's orientation there sees them gives the index's next 2 bits
 * (3 rx) ^ ry, and when ry is 0 the orientation turns: the axes swap, and both flip when rx is
 * 1.  Swap and flip commute, so an orientation is two bits (swap, flip), and tab[orientation,
 * 4 bits of x, 4 bits of y] holds the 8 index bits those 4 levels give and the orientation
 * after them (hilbert_table fills it from the rule). */
static void hilbert_table(uint16_t tab[1024]) {
    for (int st = 0; st < 4; st++)
        for (int bx4 = 0; bx4 < 16; bx4++)
            for (int by4 = 0; by4 < 16; by4++) {
                int sw = st & 1, fl = st >> 1, d = 0;
                for (int k = 3; k >= 0; k--) {
                    int bx = bx4 >> k & 1, by = by4 >> k & 1;
                    int rx = (sw ? by : bx) ^ fl, ry = (sw ? bx : by) ^ fl;
                    d = d << 2 | ((3 * rx) ^ ry);
                    if (!ry) {
                        fl ^= rx;
                        sw ^= 1;
                    }
                }
                tab[st << 8 | bx4 << 4 | by4] = (uint16_t)(d | (sw | fl << 1) << 8);
            }
}

static uint32_t hilbert_index(const uint16_t *tab, uint32_t x, uint32_t y) {
    uint32_t d = 0, st = 0;
    for (int k = 12; k >= 0; k -= 4) {
        uint32_t e = tab[st << 8 | (x >> k & 15) << 4 | (y >> k & 15)];
        d = d << 8 | (e & 255);
        st = e >> 8;
    }
    return d;
}

typedef struct {
    uint64_t key;
    int32_t v;
} okey;

static int okey_cmp(const void *a, const void *b) { /* by key, then vertex */
    const okey *p = a, *q = b;
    if (p->key != q->key) return p->key < q->key ? -1 : 1;
    return (p->v > q->v) - (p->v < q->v);
}

static int32_t *brio_order(mesh *m, int32_t n, uint32_t *hv) {
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int32_t v = 0; v < n; v++)
        for (int c = 0; c < 2; c++) {
            if (X(m, v)[c] < lo[c]) lo[c] = X(m, v)[c];
            if (X(m, v)[c] > hi[c]) hi[c] = X(m, v)[c];
        }
    double span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(span > 0)) span = 1;
    /* sorted by (key, v): one radix sort of (round, Hilbert index, v) packed into 64 bits
     * (5 + 32 + 27) while v fits, else a comparison sort of the pairs */
    int packed = n <= (1 << 27);
    uint16_t tab[1024];
    hilbert_table(tab);
    okey *k = packed ? NULL : mesh_xrealloc(NULL, n, sizeof(okey));
    uint64_t *pk = packed ? mesh_xrealloc(NULL, n, sizeof(uint64_t)) : NULL;
    for (int32_t v = 0; v < n; v++) {
        uint32_t hx = (uint32_t)fmin(65535.0, (X(m, v)[0] - lo[0]) / span * 65535.0);
        uint32_t hy = (uint32_t)fmin(65535.0, (X(m, v)[1] - lo[1]) / span * 65535.0);
        uint64_t r = mesh_rand(m);
        uint32_t round = 0;
        while ((r & 1) && round < 20)
            round++, r >>= 1;
        hv[v] = hilbert_index(tab, hx, hy);
        uint64_t key = ((uint64_t)(20 - round) << 32) | hv[v];
        if (packed)
            pk[v] = key << 27 | (uint64_t)v;
        else
            k[v] = (okey){key, v};
    }
    int32_t *order = mesh_xrealloc(NULL, n, sizeof(int32_t));
    if (packed) {
        mesh_sort_u64_from(pk, (size_t)n, 27); /* v ascending already: ties keep it */
        for (int32_t i = 0; i < n; i++)
            order[i] = (int32_t)(pk[i] & ((1u << 27) - 1));
        free(pk);
    } else {
        qsort(k, n, sizeof(okey), okey_cmp);
        for (int32_t i = 0; i < n; i++)
            order[i] = k[i].v;
        free(k);
    }
    return order;
}

/* ---- Delaunay triangulation of the vertices ----------------------------------------------- */

static void initial_triangle(mesh *m, int32_t a, int32_t b, int32_t c) {
    int32_t t = mesh_tri_new(m), gab = mesh_tri_new(m), gbc = mesh_tri_new(m),
            gca = mesh_tri_new(m);
    int32_t *tv = m->tv, *tn = m->tn;
    tv[3 * t] = a, tv[3 * t + 1] = b, tv[3 * t + 2] = c;
    tv[3 * gab] = b, tv[3 * gab + 1] = a, tv[3 * gab + 2] = MESH_GHOST;
    tv[3 * gbc] = c, tv[3 * gbc + 1] = b, tv[3 * gbc + 2] = MESH_GHOST;
    tv[3 * gca] = a, tv[3 * gca + 1] = c, tv[3 * gca + 2] = MESH_GHOST;
    tn[3 * t] = 3 * gab, tn[3 * gab] = 3 * t;
    tn[3 * t + 1] = 3 * gbc, tn[3 * gbc] = 3 * t + 1;
    tn[3 * t + 2] = 3 * gca, tn[3 * gca] = 3 * t + 2;
    tn[3 * gab + 1] = 3 * gca + 2, tn[3 * gca + 2] = 3 * gab + 1;
    tn[3 * gca + 1] = 3 * gbc + 2, tn[3 * gbc + 2] = 3 * gca + 1;
    tn[3 * gbc + 1] = 3 * gab + 2, tn[3 * gab + 2] = 3 * gbc + 1;
    m->vtri[a] = m->vtri[b] = m->vtri[c] = t;
    m->last = t;
}

/* The triangles renumbered in the Hilbert order of a vertex of theirs (hv: each vertex's
 * index on the curve, from brio_order), the dead slots dropped: neighbours then lie near each
 * other in memory, which the passes over the triangulation (segment insertion, the
 * decomposition's graph, refinement) feel on large inputs, where the slots the insertions
 * reused are scattered.  Only tv, tn, tf, vtri and last refer to triangles at this point. */
static void sort_triangles(mesh *m, const uint32_t *hv) {
    uint64_t *key = mesh_xrealloc(NULL, (size_t)m->nlive + 1, sizeof(uint64_t));
    int32_t nk = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        const int32_t *v = m->tv + 3 * (size_t)t;
        if (v[0] == MESH_DEAD) continue;
        int32_t a = v[0] >= 0 ? v[0] : v[1];
        key[nk++] = (uint64_t)hv[a] << 32 | (uint32_t)t;
    }
    mesh_sort_u64_from(key, (size_t)nk, 32); /* by curve index; slots in order already */
    int32_t *nid = mesh_xrealloc(NULL, (size_t)m->nt + 1, sizeof(int32_t));
    for (int32_t i = 0; i < nk; i++)
        nid[(uint32_t)key[i]] = i;
    free(key);
    int32_t *tv = mesh_xrealloc(NULL, 3 * (size_t)m->tcap, sizeof(int32_t));
    int32_t *tn = mesh_xrealloc(NULL, 3 * (size_t)m->tcap, sizeof(int32_t));
    uint8_t *tf = mesh_xrealloc(NULL, (size_t)m->tcap, 1);
    for (int32_t t = 0; t < m->nt; t++) {
        if (m->tv[3 * (size_t)t] == MESH_DEAD) continue;
        int32_t i = nid[t];
        for (int j = 0; j < 3; j++) {
            int32_t e = m->tn[3 * t + j];
            tv[3 * i + j] = m->tv[3 * t + j];
            tn[3 * i + j] = e >= 0 ? 3 * nid[e / 3] + e % 3 : e;
        }
        tf[i] = m->tf[t];
    }
    for (int32_t v = 0; v < m->nv; v++) { /* a commit points its cavity's vertices at live ones */
        MESH_ASSERT(m->vtri[v] < 0 || mesh_tri_alive(m, m->vtri[v]));
        if (m->vtri[v] >= 0) m->vtri[v] = nid[m->vtri[v]];
    }
    if (m->last >= 0) m->last = mesh_tri_alive(m, m->last) ? nid[m->last] : -1;
    free(m->tv), free(m->tn), free(m->tf);
    m->tv = tv, m->tn = tn, m->tf = tf;
    m->nt = nk;
    m->free_head = -1;
    free(nid);
}

/* Triangulates vertices 0..n-1.  dup[v] = the vertex v duplicates (or v). */
static int delaunay(mesh *m, int32_t n, int32_t *dup, char *err, size_t errlen) {
    for (int32_t v = 0; v < n; v++)
        dup[v] = v;
    if (n < 3) {
        mesh_fail(err, errlen, "fewer than 3 vertices: nothing to triangulate");
        return -1;
    }
    uint32_t *hv = mesh_xrealloc(NULL, (size_t)n, sizeof(uint32_t));
    int32_t *order = brio_order(m, n, hv);
    int32_t i0 = order[0], i1 = -1, i2 = -1;
    for (int32_t i = 1; i < n && i1 < 0; i++)
        if (X(m, order[i])[0] != X(m, i0)[0] || X(m, order[i])[1] != X(m, i0)[1]) i1 = order[i];
    double o = 0;
    for (int32_t i = 1; i < n && i1 >= 0 && i2 < 0; i++) {
        o = geom_orient2d(X(m, i0), X(m, i1), X(m, order[i]));
        if (o != 0) i2 = order[i];
    }
    if (i2 < 0) {
        free(order);
        free(hv);
        mesh_fail(err, errlen, "all vertices are collinear: no triangle");
        return -1;
    }
    if (o > 0)
        initial_triangle(m, i0, i1, i2);
    else
        initial_triangle(m, i0, i2, i1);
    for (int32_t i = 0; i < n; i++) {
        int32_t v = order[i];
        if (v == i0 || v == i1 || v == i2) continue;
        const double *p = X(m, v);
        int32_t t = mesh_walk(m, p, m->last, 0, NULL);
        if (t < 0) MESH_BUG("point location failed for vertex %d", v);
        int d = -1;
        for (int j = 0; j < 3; j++) {
            int32_t w = m->tv[3 * t + j];
            if (w >= 0 && X(m, w)[0] == p[0] && X(m, w)[1] == p[1]) d = w;
        }
        if (d >= 0) {
            dup[v] = d;
            continue;
        }
        int32_t bad = -1;
        int st = mesh_cavity_collect(m, p, t, -1, &bad);
        if (st != CAV_OK) MESH_BUG("Delaunay cavity of vertex %d failed (%d)", v, st);
        mesh_cavity_commit(m, v, -1, -1);
    }
    free(order);
    sort_triangles(m, hv);
    free(hv);
    return 0;
}

/* ---- segment insertion ------------------------------------------------------------------- */

typedef struct {
    int32_t *a;
    int32_t n, cap, head;
} ivec;

static void ivec_push2(ivec *q, int32_t x, int32_t y) {
    if (q->n + 2 > q->cap) {
        q->cap = q->cap ? q->cap * 2 : 64;
        q->a = mesh_xrealloc(q->a, q->cap, sizeof(int32_t));
    }
    q->a[q->n++] = x;
    q->a[q->n++] = y;
}

/* x is collinear with a->b: 1 iff it lies on the ray from a through b (x != a). */
static int same_direction(const double *a, const double *b, const double *x) {
    for (int c = 0; c < 2; c++) {
        if ((x[c] > a[c]) != (b[c] > a[c])) return 0;
        if ((x[c] < a[c]) != (b[c] < a[c])) return 0;
    }
    return 1;
}

/* Traces segment a->b from a.  Returns the vertex where this piece ends (b, or a vertex lying
 * exactly on the segment) and appends the crossed edges as (right, left) vertex pairs. */
static int32_t trace(mesh *m, int32_t a, int32_t b, ivec *cross, int32_t *edge) {
    *edge = -1;
    int32_t t = m->vtri[a];
    int j = m->tv[3 * t] == a ? 0 : m->tv[3 * t + 1] == a ? 1 : 2;
    int32_t e0 = 3 * t + j, e = e0, start = -1;
    int64_t guard = (int64_t)m->nt + 4;
    do {
        int32_t x = mesh_dest(m, e), y = mesh_apex(m, e);
        if (x == b || y == b) { /* the edge a-b exists: the one mesh_find_edge would find */
            *edge = x == b ? e : mesh_edge_prev(e);
            return b;
        }
        /* a hull edge out of a belongs to a ghost triangle: test both fan vertices */
        if (y >= 0 && geom_orient2d(X(m, a), X(m, b), X(m, y)) == 0 &&
            same_direction(X(m, a), X(m, b), X(m, y)))
            return y;
        if (x >= 0 && y >= 0) {
            double ox = geom_orient2d(X(m, a), X(m, b), X(m, x));
            if (ox == 0 && same_direction(X(m, a), X(m, b), X(m, x))) return x;
            double oy = geom_orient2d(X(m, a), X(m, b), X(m, y));
            if (ox < 0 && oy > 0) {
                start = mesh_edge_next(e);
                break;
            }
        }
        e = m->tn[mesh_edge_prev(e)];
        if (--guard < 0) MESH_BUG("vertex fan of %d does not close", a);
    } while (e != e0);
    if (start < 0) MESH_BUG("segment %d-%d: no triangle around %d in its direction", a, b, a);
    e = start;
    int32_t x = m->tv[e], y = mesh_dest(m, e);
    for (;;) {
        ivec_push2(cross, x, y);
        int32_t f = m->tn[e], z = mesh_apex(m, f);
        if (z == b) return b;
        if (z < 0) MESH_BUG("segment %d-%d leaves the convex hull", a, b);
        double oz = geom_orient2d(X(m, a), X(m, b), X(m, z));
        if (oz == 0) return z;
        if (oz > 0) {
            e = mesh_edge_next(f);
            y = z;
        } else {
            e = mesh_edge_prev(f);
            x = z;
        }
    }
}

static int crosses(const mesh *m, int32_t a, int32_t b, int32_t w, int32_t z) {
    double ow = geom_orient2d(X(m, a), X(m, b), X(m, w));
    double oz = geom_orient2d(X(m, a), X(m, b), X(m, z));
    return (ow > 0 && oz < 0) || (ow < 0 && oz > 0);
}

/* The half-edge of x's fan whose origin is x, in vtri[x]'s triangle; -1 if vtri is stale. */
static int32_t fan_start(const mesh *m, int32_t x) {
    int32_t t = m->vtri[x];
    if (t < 0 || !mesh_tri_alive(m, t)) return -1;
    for (int j = 0; j < 3; j++)
        if (m->tv[3 * t + j] == x) return 3 * t + j;
    return -1;
}

/* One step of a rotation around the origin of *e (closed fan), looking for the edge to w:
 * returns the half-edge found, -1 to go on, -2 when the fan came back to start (no such
 * edge), -3 when the fan is open (a boundary: not while building). */
static int32_t fan_step(const mesh *m, int32_t *e, int32_t start, int32_t w) {
    if (mesh_dest(m, *e) == w) return *e;
    int32_t pe = mesh_edge_prev(*e);
    if (m->tv[pe] == w) return pe;
    int32_t n = m->tn[pe];
    if (n < 0) return -3;
    *e = n;
    return n == start ? -2 : -1;
}

/* Edge x-y while the CDT is built, exactly the half-edge mesh_find_edge(m, x, y) returns, in
 * O(min(deg x, deg y)) steps: the fans of x and y are rotated in lockstep (every fan is closed:
 * ghost triangles).  mesh_find_edge rotates around x alone, and Sloan's flips look up their
 * crossing edges by vertex pair: around a vertex of huge degree (thousands of interface
 * segments ending at one tiny feature of a fuzzed input) that made a CDT take 70 s.  Which half
 * mesh_find_edge returns: its rotation runs counter-clockwise from vtri[x]'s triangle, and the
 * triangle right of x->y comes just before the one left of it, so x->y only if vtri[x] is the
 * triangle left of x->y, else y->x. */
static int32_t find_edge_cdt(const mesh *m, int32_t x, int32_t y) {
    if (x < 0 || x >= m->nv || y < 0 || y >= m->nv) return -1;
    int32_t sx = fan_start(m, x), sy = fan_start(m, y), ex = sx, ey = sy, h = -1;
    if (sx < 0 || sy < 0) return mesh_find_edge(m, x, y);
    for (int64_t guard = 3 * (int64_t)m->nt + 8; guard > 0; guard--) {
        h = fan_step(m, &ex, sx, y);
        if (h == -1) h = fan_step(m, &ey, sy, x);
        if (h == -2) return -1;
        if (h == -3) return mesh_find_edge(m, x, y);
        if (h >= 0) break;
    }
    if (h < 0) return mesh_find_edge(m, x, y);
    int32_t h1 = m->tv[h] == x ? h : m->tn[h]; /* x -> y */
    if (h1 < 0) return mesh_find_edge(m, x, y);
    return h1 / 3 == m->vtri[x] ? h1 : m->tn[h1];
}

/* Flips away the crossing edges so that edge a-b exists, then restores the Delaunay property
 * of the new edges (Sloan 1993). */
static void sloan(mesh *m, int32_t a, int32_t b, ivec *q) {
    ivec newe = {0};
    int64_t guard = 0;
    while (q->head < q->n) {
        int32_t x = q->a[q->head], y = q->a[q->head + 1];
        q->head += 2;
        if (q->head > 4096 && q->head * 2 > q->n) {
            memmove(q->a, q->a + q->head, (size_t)(q->n - q->head) * sizeof(int32_t));
            q->n -= q->head;
            q->head = 0;
        }
        int32_t e = find_edge_cdt(m, x, y);
        if (e < 0 || m->tn[e] < 0) MESH_BUG("crossing edge %d-%d lost", x, y);
        int32_t u = m->tv[e], v = mesh_dest(m, e), w = mesh_apex(m, e), z = mesh_apex(m, m->tn[e]);
        if (geom_orient2d(X(m, z), X(m, v), X(m, w)) > 0 &&
            geom_orient2d(X(m, w), X(m, u), X(m, z)) > 0) {
            mesh_flip(m, e);
            if (crosses(m, a, b, w, z))
                ivec_push2(q, w, z);
            else
                ivec_push2(&newe, w, z);
        } else {
            ivec_push2(q, x, y);
        }
        if (++guard > 100000000) MESH_BUG("segment %d-%d: flipping does not converge", a, b);
    }
    int changed;
    do {
        changed = 0;
        for (int32_t i = 0; i < newe.n; i += 2) {
            int32_t w = newe.a[i], z = newe.a[i + 1];
            if ((w == a && z == b) || (w == b && z == a)) continue;
            int32_t e = find_edge_cdt(m, w, z);
            if (e < 0 || m->tn[e] < 0 || mesh_edge_constrained(m, e)) continue;
            int32_t f = m->tn[e], p = mesh_apex(m, e), s = mesh_apex(m, f);
            if (p < 0 || s < 0) continue;
            if (geom_incircle(X(m, m->tv[e]), X(m, mesh_dest(m, e)), X(m, p), X(m, s)) > 0) {
                mesh_flip(m, e);
                newe.a[i] = p;
                newe.a[i + 1] = s;
                changed = 1;
            }
        }
    } while (changed);
    free(newe.a);
}

/* Inserts segment s (flips, Sloan's method), its pieces made constraint edges; each piece's
 * subsegment record is left in pend (u, v, s, was: whether the edge was a constraint already),
 * for add_records. */
static void insert_segment(mesh *m, int32_t s, ivec *pieces, ivec *cross, ivec *pend) {
    int32_t a = m->seg[2 * s], b = m->seg[2 * s + 1], cur = a;
    /* pieces: each piece's end and whether its edge was a constraint already (only then can
     * an earlier segment have a record for it: records are made here, for constraint edges) */
    pieces->n = 0;
    ivec_push2(pieces, a, 0);
    while (cur != b) {
        cross->n = cross->head = 0;
        int32_t e, end = trace(m, cur, b, cross, &e);
        if (cross->n > 0) sloan(m, cur, end, cross);
        if (e < 0) e = mesh_find_edge(m, cur, end);
        if (e < 0) MESH_BUG("segment piece %d-%d missing after insertion", cur, end);
        int was = mesh_edge_constrained(m, e);
        mesh_set_constrained(m, e);
        ivec_push2(pieces, end, was);
        cur = end;
    }
    int32_t np = pieces->n / 2 - 1;
    for (int32_t i = 0; i < np; i++) {
        ivec_push2(pend, pieces->a[2 * i], pieces->a[2 * i + 2]);
        ivec_push2(pend, np == 1 ? s : -1 - s, pieces->a[2 * i + 3]);
    }
}

/* The subsegment records of the pieces in pend (insert_segment), in order: a piece whose edge
 * was a constraint before its segment came may be an earlier segment's piece, which keeps it.
 * The same records in the same table slots as adding each at its segment, but the tables are
 * read a few pieces ahead (mesh_ss_prefetch): on a large input each record's slots are a
 * cache miss otherwise. */
static void add_records(mesh *m, const ivec *pend) {
    enum { AHEAD = 12 };
    int32_t n = pend->n / 4;
    const int32_t *q = pend->a;
    for (int32_t i = 0; i < n; i++) {
        if (i + AHEAD < n) {
            const int32_t *r = q + 4 * (i + AHEAD);
            mesh_ss_prefetch(m, r[0], r[1], r[2] >= 0 ? r[2] : -1 - r[2], r[2] >= 0 ? 0 : -1, 0);
        }
        const int32_t *r = q + 4 * i;
        int32_t u = r[0], v = r[1], s = r[2] >= 0 ? r[2] : -1 - r[2];
        if (r[3] && mesh_ss_find_pair(m, u, v) >= 0) continue; /* shared with an earlier one */
        mesh_ss_add(m, u, v, s, r[2] >= 0 ? 0 : -1, 0);
    }
}

/* ---- removing the exterior ----------------------------------------------------------------- */

static void seed(mesh *m, int32_t t, int32_t *stk, int32_t *n) {
    if (t < 0 || mesh_tri_is_ghost(m, t) || (m->tf[t] & MESH_MARK)) return;
    m->tf[t] |= MESH_MARK;
    stk[(*n)++] = t;
}

/* 1 iff p lies in the closed triangle t (exact). */
static int in_closure(const mesh *m, int32_t t, const double *p) {
    for (int j = 0; j < 3; j++)
        if (geom_orient2d(X(m, m->tv[3 * t + j]), X(m, m->tv[3 * t + (j + 1) % 3]), p) < 0)
            return 0;
    return 1;
}

/* Seeds the carving flood from hole point p, found in (or next to) triangle t: every
 * triangle whose closure contains p, so a hole point exactly on a segment removes the regions
 * on both sides and one on a vertex every region around it (the rule pslg_domain_area and
 * the validator apply).  Ghost triangles are never seeded.  The fan around a vertex is closed
 * while the CDT is built (ghosts included), so rotating through tn comes back to t. */
static void seed_hole(mesh *m, const double *p, int32_t t, int32_t *stk, int32_t *n) {
    int32_t cand[4] = {t, -1, -1, -1};
    for (int j = 0; j < 3; j++)
        cand[j + 1] = m->tn[3 * t + j] >= 0 ? m->tn[3 * t + j] / 3 : -1;
    for (int c = 0; c < 4; c++) {
        int32_t r = cand[c];
        if (r < 0 || mesh_tri_is_ghost(m, r) || !in_closure(m, r, p)) continue;
        seed(m, r, stk, n);
        for (int j = 0; j < 3; j++) {
            int32_t v = m->tv[3 * r + j];
            if (X(m, v)[0] != p[0] || X(m, v)[1] != p[1]) continue;
            int32_t cur = r, k = j;
            for (int32_t guard = 0; guard < m->nt; guard++) { /* rotate around v */
                int32_t e = m->tn[3 * cur + k];
                if (e < 0) break;
                cur = e / 3;
                if (cur == r) break;
                seed(m, cur, stk, n);
                k = (e % 3 + 1) % 3; /* v is the destination of e, so the origin of the next */
            }
        }
    }
}

static void carve(mesh *m, const double *holes, int32_t nholes, int keep_hull) {
    int32_t *stk = mesh_xrealloc(NULL, (size_t)m->nt + 1, sizeof(int32_t));
    int32_t n = 0;
    for (int32_t h = 0; h < nholes; h++) {
        const double *p = holes + 2 * h;
        if (!isfinite(p[0]) || !isfinite(p[1])) continue;
        int32_t t = mesh_walk(m, p, m->last, 0, NULL);
        if (t >= 0) seed_hole(m, p, t, stk, &n);
    }
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || !mesh_tri_is_ghost(m, t)) continue;
        m->tf[t] |= MESH_MARK;
        if (keep_hull) continue;
        int g = m->tv[3 * t] == MESH_GHOST ? 0 : m->tv[3 * t + 1] == MESH_GHOST ? 1 : 2;
        int32_t fe = 3 * t + (g + 1) % 3;
        if (mesh_edge_constrained(m, fe)) continue;
        int32_t r = m->tn[fe] / 3;
        if (m->tf[r] & MESH_MARK) continue;
        m->tf[r] |= MESH_MARK;
        stk[n++] = r;
    }
    while (n > 0) {
        int32_t t = stk[--n];
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, nb = m->tn[e];
            if (nb < 0 || mesh_edge_constrained(m, e)) continue;
            int32_t r = nb / 3;
            if ((m->tf[r] & MESH_MARK) || mesh_tri_is_ghost(m, r)) continue;
            m->tf[r] |= MESH_MARK;
            stk[n++] = r;
        }
    }
    free(stk);
    /* a constraint edge whose triangles all go leaves the mesh: its subsegment record goes
     * too, the records in index order (as a look-up of every record's edge would find them) */
    int32_t *lost = NULL, nl = 0, lcap = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || !(m->tf[t] & MESH_MARK)) continue;
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, nb = m->tn[e];
            if (nb >= 0 && mesh_tri_alive(m, nb / 3) && !(m->tf[nb / 3] & MESH_MARK)) {
                m->tn[nb] = -1;
            } else if (mesh_edge_constrained(m, e)) {
                int32_t r = mesh_ss_find_pair(m, m->tv[e], mesh_dest(m, e));
                if (r >= 0) {
                    MESH_GROW(lost, (size_t)nl + 1, lcap);
                    lost[nl++] = r;
                }
            }
        }
        mesh_tri_kill(m, t);
    }
    if (nl > 1) qsort(lost, (size_t)nl, sizeof(int32_t), mesh_cmp_i32);
    for (int32_t i = 0; i < nl; i++)
        if (i == 0 || lost[i] != lost[i - 1]) mesh_ss_del(m, lost[i]);
    free(lost);
}

/* Convex hull edges become segments (marker 1): used when the input has no segment. */
static void hull_to_segments(mesh *m) {
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || !mesh_tri_is_ghost(m, t)) continue;
        int g = m->tv[3 * t] == MESH_GHOST ? 0 : m->tv[3 * t + 1] == MESH_GHOST ? 1 : 2;
        int32_t fe = 3 * t + (g + 1) % 3, re = m->tn[fe];
        int32_t u = m->tv[re], v = mesh_dest(m, re);
        int32_t s = mesh_seg_add(m, u, v, 1, 0);
        mesh_set_constrained(m, re);
        mesh_ss_add(m, u, v, s, 0, 0);
    }
}

/* geom_angle_deg(a, b, c) < 60, its arc tangent taken only within a few degrees of 60 (the
 * angle is atan2(|cross|, dot), so below 56 degrees |cross| < 1.5 dot, above 63 |cross| > 2 dot,
 * and dot <= 0 with cross != 0 is 90 degrees or more). */
static int sharp(const double *a, const double *b, const double *c) {
    double cross = fabs(geom_orient2d(a, c, b));
    double dot = (a[0] - b[0]) * (c[0] - b[0]) + (a[1] - b[1]) * (c[1] - b[1]);
    if (dot <= 0 && cross != 0) return 0;
    if (dot > 0 && cross < 1.5 * dot) return 1;
    if (dot > 0 && cross > 2 * dot) return 0;
    return geom_angle_deg(a, b, c) < 60.0;
}

/* Incidence lists of the segments at input vertices, and the small-angle corners. */
static void corners(mesh *m) {
    int32_t n = m->ninput;
    free(m->inc_off);
    free(m->inc_seg);
    free(m->corner);
    m->inc_off = mesh_xrealloc(NULL, (size_t)n + 1, sizeof(int32_t));
    m->inc_seg = mesh_xrealloc(NULL, 2 * (size_t)m->nseg + 1, sizeof(int32_t));
    m->corner = mesh_xrealloc(NULL, (size_t)n + 1, 1);
    memset(m->inc_off, 0, ((size_t)n + 1) * sizeof(int32_t));
    for (int32_t s = 0; s < m->nseg; s++) {
        m->inc_off[m->seg[2 * s] + 1]++;
        m->inc_off[m->seg[2 * s + 1] + 1]++;
    }
    for (int32_t v = 0; v < n; v++)
        m->inc_off[v + 1] += m->inc_off[v];
    int32_t *fill = mesh_xrealloc(NULL, (size_t)n + 1, sizeof(int32_t));
    memcpy(fill, m->inc_off, (size_t)n * sizeof(int32_t));
    for (int32_t s = 0; s < m->nseg; s++) {
        m->inc_seg[fill[m->seg[2 * s]]++] = s;
        m->inc_seg[fill[m->seg[2 * s + 1]]++] = s;
    }
    free(fill);
    m->has_corners = 0;
    for (int32_t v = 0; v < n; v++) {
        m->corner[v] = 0;
        for (int32_t i = m->inc_off[v]; i < m->inc_off[v + 1]; i++)
            for (int32_t j = i + 1; j < m->inc_off[v + 1]; j++) {
                int32_t s1 = m->inc_seg[i], s2 = m->inc_seg[j];
                int32_t o1 = m->seg[2 * s1] == v ? m->seg[2 * s1 + 1] : m->seg[2 * s1];
                int32_t o2 = m->seg[2 * s2] == v ? m->seg[2 * s2 + 1] : m->seg[2 * s2];
                if (sharp(X(m, o1), X(m, v), X(m, o2))) m->corner[v] = 1;
            }
        m->has_corners |= m->corner[v];
    }
}

/* The first half of build: the vertices and their Delaunay triangulation (dup: n entries). */
static int build_points(mesh *m, int32_t n, const double *xy, int32_t *dup, char *err,
                        size_t errlen) {
    if (m->nv != 0 || m->nt != 0) {
        mesh_fail(err, errlen, "mesh_build: mesh is not empty");
        return -1;
    }
    for (int32_t v = 0; v < n; v++)
        mesh_vert_add(m, xy[2 * v], xy[2 * v + 1], -1);
    m->ninput = n;
    return delaunay(m, n, dup, err, errlen);
}

/* The second half: the input markers, the segments, the exterior removed.  Frees dup. */
static int build_rest(mesh *m, int32_t n, const int32_t *vmarker, int32_t nseg, const int32_t *seg,
                      const int32_t *smarker, const uint8_t *iface, const double *holes,
                      int32_t nholes, int32_t *dup, char *err, size_t errlen) {
    m->in_vmarker = mesh_xrealloc(NULL, (size_t)n + 1, sizeof(int32_t));
    for (int32_t v = 0; v < n; v++)
        m->in_vmarker[v] = vmarker ? vmarker[v] : 0;
    ivec pieces = {0}, cross = {0}, pend = {0};
    mesh_ss_reserve(m, nseg); /* a record a segment, unless segments are cut at vertices */
    for (int32_t s = 0; s < nseg; s++) {
        int32_t a = dup[seg[2 * s]], b = dup[seg[2 * s + 1]];
        int32_t id = mesh_seg_add(m, a, b, smarker ? smarker[s] : 0, iface ? iface[s] : 0);
        if (a == b) continue;
        insert_segment(m, id, &pieces, &cross, &pend);
    }
    add_records(m, &pend);
    free(pieces.a);
    free(cross.a);
    free(pend.a);
    free(dup);
    if (nseg == 0) hull_to_segments(m);
    carve(m, holes, nholes, nseg == 0); /* and the records of the edges it removes */
    mesh_rebuild_vtri(m);
    corners(m);
    m->last = -1;
    if (m->nlive == 0) {
        mesh_fail(err, errlen, "the domain is empty (holes or missing boundary segments?)");
        return -1;
    }
    return 0;
}

static int build(mesh *m, int32_t n, const double *xy, const int32_t *vmarker, int32_t nseg,
                 const int32_t *seg, const int32_t *smarker, const uint8_t *iface,
                 const double *holes, int32_t nholes, char *err, size_t errlen) {
    int32_t *dup = mesh_xrealloc(NULL, (size_t)n + 1, sizeof(int32_t));
    if (build_points(m, n, xy, dup, err, errlen) != 0) {
        free(dup);
        return -1;
    }
    return build_rest(m, n, vmarker, nseg, seg, smarker, iface, holes, nholes, dup, err, errlen);
}

/* mesh_build_cdt's message: "FILE: problem". */
static void name_failure(const pslg *g, char *err, size_t errlen) {
    if (!err || errlen == 0) return;
    char tmp[1200];
    snprintf(tmp, sizeof tmp, "%.512s: %.600s", g->path[0] ? g->path : "(pslg)", err);
    snprintf(err, errlen, "%s", tmp);
}

int mesh_build_points(mesh *m, int32_t n, const double *xy, int32_t **dup, char *err,
                      size_t errlen) {
    *dup = mesh_xrealloc(NULL, (size_t)n + 1, sizeof(int32_t));
    if (build_points(m, n, xy, *dup, err, errlen) == 0) return 0;
    free(*dup);
    *dup = NULL;
    return -1;
}

int mesh_build_cdt_from_points(mesh *m, int32_t *dup, const pslg *g, const uint8_t *iface,
                               char *err, size_t errlen) {
    m->scale_exp = g->scale_exp;
    MESH_ASSERT(m->ninput == g->nverts && m->nv == g->nverts);
    int r = build_rest(m, g->nverts, g->vmarker, g->nsegs, g->seg, g->smarker, iface, g->holes,
                       g->nholes, dup, err, errlen);
    if (r != 0) name_failure(g, err, errlen);
    MESH_ASSERT(r != 0 || mesh_consistent(m));
    return r;
}

int mesh_build_cdt(mesh *m, const pslg *g, const uint8_t *iface, char *err, size_t errlen) {
    m->scale_exp = g->scale_exp;
    int r = build(m, g->nverts, g->xy, g->vmarker, g->nsegs, g->seg, g->smarker, iface, g->holes,
                  g->nholes, err, errlen);
    if (r != 0) name_failure(g, err, errlen);
    MESH_ASSERT(r != 0 || mesh_consistent(m));
    return r;
}

/* The edge a -> b among the directed edges out of a (rows of the CSR off/code), or -1. */
static int32_t out_edge(const mesh *m, const int32_t *off, const int32_t *code, int32_t a,
                        int32_t b) {
    for (int32_t i = off[a]; i < off[a + 1]; i++)
        if (mesh_dest(m, code[i]) == b) return code[i];
    return -1;
}

int mesh_build_from_triangles(mesh *m, const pslg *g, const uint8_t *iface, int32_t ntri,
                              const int32_t *tri, char *err, size_t errlen) {
    if (m->nv != 0 || m->nt != 0) {
        mesh_fail(err, errlen, "mesh_build: mesh is not empty");
        return -1;
    }
    m->scale_exp = g->scale_exp;
    int32_t n = g->nverts;
    for (int32_t v = 0; v < n; v++)
        mesh_vert_add(m, g->xy[2 * (size_t)v], g->xy[2 * (size_t)v + 1], -1);
    m->ninput = n;
    m->in_vmarker = mesh_xrealloc(NULL, (size_t)n + 1, sizeof(int32_t));
    for (int32_t v = 0; v < n; v++)
        m->in_vmarker[v] = g->vmarker ? g->vmarker[v] : 0;
    int bad = ntri < 1;
    if (bad) mesh_fail(err, errlen, "no triangle");
    for (int32_t i = 0; i < ntri && !bad; i++) {
        const int32_t *v = tri + 3 * (size_t)i;
        for (int j = 0; j < 3; j++)
            bad |= v[j] < 0 || v[j] >= n;
        if (bad || geom_orient2d(X(m, v[0]), X(m, v[1]), X(m, v[2])) <= 0) {
            mesh_fail(err, errlen,
                      "triangle %d is not a counter-clockwise triangle of the vertices", (int)i);
            bad = 1;
            break;
        }
        int32_t t = mesh_tri_new(m);
        for (int j = 0; j < 3; j++) {
            m->tv[3 * t + j] = v[j];
            m->tn[3 * t + j] = -1;
        }
    }
    /* adjacency: each vertex's outgoing edges, then each edge's reverse among its end's */
    int32_t *off = mesh_xcalloc((size_t)n + 2, sizeof(int32_t));
    int32_t *code = mesh_xmalloc(3 * (size_t)(bad ? 0 : ntri) + 1, sizeof(int32_t));
    if (!bad) {
        for (int32_t e = 0; e < 3 * ntri; e++)
            off[m->tv[e] + 2]++;
        for (int32_t v = 0; v < n; v++)
            off[v + 2] += off[v + 1];
        for (int32_t e = 0; e < 3 * ntri; e++)
            code[off[m->tv[e] + 1]++] = e;
    }
    for (int32_t e = 0; e < 3 * ntri && !bad; e++) {
        int32_t a = mesh_org(m, e), b = mesh_dest(m, e), twin = out_edge(m, off, code, b, a);
        if (twin >= 0) m->tn[e] = twin;
        for (int32_t i = off[a]; i < off[a + 1] && !bad; i++) /* a -> b once only */
            if (code[i] != e && mesh_dest(m, code[i]) == b) {
                mesh_fail(err, errlen, "edge %d-%d is in more than two triangles", (int)a, (int)b);
                bad = 1;
            }
    }
    /* the segments, each on its edge (one subsegment record, dyadic level 0) */
    for (int32_t s = 0; s < g->nsegs && !bad; s++) {
        int32_t a = g->seg[2 * (size_t)s], b = g->seg[2 * (size_t)s + 1];
        int32_t id = mesh_seg_add(m, a, b, g->smarker ? g->smarker[s] : 0, iface ? iface[s] : 0);
        int ok = a >= 0 && a < n && b >= 0 && b < n && a != b;
        int32_t e = ok ? out_edge(m, off, code, a, b) : -1;
        if (e < 0 && ok) e = out_edge(m, off, code, b, a);
        if (e < 0) {
            mesh_fail(err, errlen, "segment %d (%d-%d) is no edge of the triangles", (int)s, (int)a,
                      (int)b);
            bad = 1;
            break;
        }
        mesh_set_constrained(m, e);
        if (mesh_ss_find_pair(m, a, b) < 0) mesh_ss_add(m, a, b, id, 0, 0);
    }
    for (int32_t e = 0; e < 3 * ntri && !bad; e++)
        if (m->tn[e] < 0 && !mesh_edge_constrained(m, e)) {
            mesh_fail(err, errlen, "boundary edge %d-%d is no segment", (int)mesh_org(m, e),
                      (int)mesh_dest(m, e));
            bad = 1;
        }
    free(off);
    free(code);
    if (bad) return -1;
    mesh_rebuild_vtri(m);
    corners(m);
    m->last = -1;
    MESH_ASSERT(mesh_consistent(m));
    return 0;
}

int mesh_build_delaunay(mesh *m, int32_t n, const double *xy, char *err, size_t errlen) {
    return build(m, n, xy, NULL, 0, NULL, NULL, NULL, NULL, 0, err, errlen);
}
