/* decomp_widen: the automatic decomposition's wide sectors and filled parts (decomp_auto.c's
 * steps (4) and (5)).
 *
 * Around every vertex of the coarse mesh, a sector of triangles of one part narrower than
 * WIDE_DEG that an interface bounds makes two interfaces (or an interface and the boundary)
 * meet at a narrow angle, where their splits can cascade; the sector's triangles join the
 * lighter part across that interface if that lowers the number of narrow sectors around them
 * (so it cannot oscillate), pass after pass (at most WIDEN_PASSES).  On the exact preview a
 * triangle whose apex encroaches an interface edge joins the part across it instead.  A part
 * METIS left empty takes a triangle of the largest part that can give one.  Sector angles are
 * a float quality figure that only moves interfaces; topology stays the exact predicates'.
 * Local.
 */
#include "decomp/decomp_impl.h"

#include "base/base.h"
#include "geom/geom.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WIDE_DEG 60.0 /* sectors an interface bounds are at least this wide */
#define WIDEN_PASSES 32
#define DEG_PER_RAD 57.295779513082320876798

/* ---- wide sectors (step 5) ------------------------------------------------------------ */

typedef struct corner_rec {
    int32_t t;  /* triangle */
    int j;      /* position of the vertex in t */
    double deg; /* t's angle there */
} corner_rec;

typedef struct smooth {
    const mesh *m;
    int32_t *part;
    double *pw;    /* K: work per part */
    double pw_max; /* the heaviest part's work before step 5 */
    int32_t *cnt;  /* K: triangles per part */
    const double *tw;
    corner_rec *c, *c2; /* corners of a star; of another star (bad_at) */
    int32_t ncap, ncap2;
    int32_t *vs, vcap; /* bad_around's vertices */
    /* nv: 1 where a vertex may end an interface edge (set, at the first pass over vertices, for
     * those that do, and for every vertex of a moved triangle, so a superset of those that do
     * at every pass's start: a vertex becomes an end only when a triangle around it moves): a
     * vertex with 0 bounds no sector a pass looks at, so its star (an arctangent a corner) is
     * not walked; one with 1 that ends no interface edge moves nothing */
    uint8_t *near;
    int near_set;
} smooth;

static int touches_corner(const mesh *m, int32_t t) {
    if (!m->has_corners || !m->corner) return 0;
    for (int j = 0; j < 3; j++) {
        int32_t v = m->tv[3 * t + j];
        if (v < m->ninput && m->corner[v]) return 1;
    }
    return 0;
}

static double corner_deg(const mesh *m, int32_t t, int j) {
    const double *p = mesh_vertex_xy(m, m->tv[3 * t + j]),
                 *a = mesh_vertex_xy(m, m->tv[3 * t + (j + 1) % 3]),
                 *b = mesh_vertex_xy(m, m->tv[3 * t + (j + 2) % 3]);
    double ux = a[0] - p[0], uy = a[1] - p[1], vx = b[0] - p[0], vy = b[1] - p[1];
    return atan2(fabs(ux * vy - uy * vx), ux * vx + uy * vy) * DEG_PER_RAD;
}

/* Edge e separates two sectors: a constraint, the domain boundary, or two parts. */
static int edge_cut(const mesh *m, const int32_t *part, int32_t e) {
    int32_t n = m->tn[e];
    return n < 0 || mesh_edge_constrained(m, e) || part[n / 3] != part[e / 3];
}

/* An interface edge: unconstrained, between two parts. */
static int edge_iface(const mesh *m, const int32_t *part, int32_t e) {
    int32_t n = m->tn[e];
    return n >= 0 && !mesh_edge_constrained(m, e) && part[n / 3] != part[e / 3];
}

/* Moves triangles ts[0..n) (all of part p) to part q unless that empties p or moves a triangle
 * at a sharp input corner.  Returns 1 if moved. */
static int move_tris(smooth *S, const int32_t *ts, int32_t n, int32_t p, int32_t q) {
    if (S->cnt[p] <= n) return 0;
    for (int32_t i = 0; i < n; i++)
        if (touches_corner(S->m, ts[i])) return 0;
    for (int32_t i = 0; i < n; i++) {
        S->part[ts[i]] = q;
        S->pw[p] -= S->tw[ts[i]];
        S->pw[q] += S->tw[ts[i]];
        for (int j = 0; S->near && j < 3; j++)
            S->near[S->m->tv[3 * ts[i] + j]] = 1;
    }
    S->cnt[p] -= n;
    S->cnt[q] += n;
    return 1;
}

/* Would triangle t, moved to part q, leave no encroached interface edge among its own?  (So
 * every move of the exact preview's pass removes one and adds none: no oscillation.) */
static int clean_move(const smooth *S, int32_t t, int32_t q) {
    const mesh *m = S->m;
    for (int j = 0; j < 3; j++) {
        int32_t e = 3 * t + j, n = m->tn[e];
        if (n < 0 || mesh_edge_constrained(m, e) || S->part[n / 3] == q) continue;
        if (decomp_edge_encroached(m, e)) return 0;
    }
    return 1;
}

/* The corners around v in counter-clockwise order into *buf (capacity *cap, grown), starting
 * just after a cut edge.  Returns the number of corners, 0 if v has no sector to consider. */
static int32_t star(const smooth *S, int32_t v, corner_rec **buf, int32_t *cap) {
    const mesh *m = S->m;
    int32_t t0 = m->vtri[v];
    if (t0 < 0 || !mesh_tri_alive(m, t0)) return 0;
    int j0 = 0;
    while (j0 < 3 && m->tv[3 * t0 + j0] != v)
        j0++;
    if (j0 == 3) return 0;
    /* clockwise (across the outgoing edge) until that edge is a cut */
    int32_t t = t0;
    int j = j0;
    for (;;) {
        int32_t e = 3 * t + j;
        if (edge_cut(m, S->part, e)) break;
        int32_t n = m->tn[e];
        t = n / 3;
        j = (n % 3 + 1) % 3;
        if (t == t0) return 0; /* a full turn inside one part */
    }
    /* counter-clockwise (across the incoming edge) from there */
    int32_t nc = 0, ts = t;
    for (;;) {
        if (nc >= *cap) {
            *cap = *cap ? 2 * *cap : 64;
            *buf = mesh_xrealloc(*buf, (size_t)*cap, sizeof **buf);
        }
        (*buf)[nc++] = (corner_rec){t, j, corner_deg(m, t, j)};
        int32_t n = m->tn[3 * t + (j + 2) % 3];
        if (n < 0) break;
        t = n / 3;
        j = n % 3;
        if (t == ts) break;
        if (nc > m->nt) MESH_BUG("star of vertex %d does not close", v);
    }
    return nc;
}

/* The sector of star c[0..nc) that starts at corner a ends before corner *b; its angle. */
static double sector(const smooth *S, const corner_rec *c, int32_t nc, int32_t a, int32_t *b) {
    double deg = 0;
    int32_t k = a;
    do {
        deg += c[k].deg;
        k++;
    } while (k < nc && !edge_cut(S->m, S->part, 3 * c[k - 1].t + (c[k - 1].j + 2) % 3));
    *b = k;
    return deg;
}

/* Narrow sectors at v that an interface bounds. */
static int32_t bad_at(smooth *S, int32_t v) {
    int32_t nc = star(S, v, &S->c2, &S->ncap2), bad = 0;
    for (int32_t a = 0, b = 0; a < nc; a = b) {
        double deg = sector(S, S->c2, nc, a, &b);
        int32_t left = 3 * S->c2[a].t + S->c2[a].j,
                right = 3 * S->c2[b - 1].t + (S->c2[b - 1].j + 2) % 3;
        bad +=
            deg < WIDE_DEG && (edge_iface(S->m, S->part, left) || edge_iface(S->m, S->part, right));
    }
    return bad;
}

static int cmp_i32(const void *a, const void *b) {
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

/* Narrow sectors at the vertices of triangles ts[0..n) (a vertex counted once per triangle).
 * Each distinct vertex's star is walked once and weighted by its count: a sector's apex is in
 * all n triangles, and at a fan of thousands of triangles (a tiny input feature) walking its
 * star n times made the decomposition quadratic in the fan (minutes at 8 subdomains). */
static int32_t bad_around(smooth *S, const int32_t *ts, int32_t n) {
    if (3 * n > S->vcap) {
        S->vcap = 3 * n;
        S->vs = mesh_xrealloc(S->vs, (size_t)S->vcap, sizeof *S->vs);
    }
    for (int32_t i = 0; i < n; i++)
        for (int j = 0; j < 3; j++)
            S->vs[3 * i + j] = S->m->tv[3 * ts[i] + j];
    qsort(S->vs, (size_t)(3 * n), sizeof *S->vs, cmp_i32);
    int32_t bad = 0;
    for (int32_t i = 0, k; i < 3 * n; i = k) {
        for (k = i + 1; k < 3 * n && S->vs[k] == S->vs[i]; k++)
            ;
        bad += (k - i) * bad_at(S, S->vs[i]);
    }
    return bad;
}

/* One pass of step 5: over every vertex (the coarse mesh), or over every interface edge (the
 * exact preview: its interfaces are never split unless encroached, so no split can start a
 * cascade at a narrow sector, and moving whole sectors would cost balance); returns the number
 * of moves. */
static int32_t widen_pass(smooth *S, int exact) {
    const mesh *m = S->m;
    int32_t moves = 0, *ts = NULL, tcap = 0;
    if (!exact && !S->near_set) { /* once: moves mark their vertices (move_tris) */
        for (int32_t t = 0; t < m->nt; t++)
            for (int j = 0; mesh_tri_alive(m, t) && j < 3; j++)
                if (edge_iface(m, S->part, 3 * t + j))
                    S->near[mesh_org(m, 3 * t + j)] = S->near[mesh_dest(m, 3 * t + j)] = 1;
        S->near_set = 1;
    }
    for (int32_t v = 0; v < m->nv && !exact; v++) {
        if (!S->near[v]) continue; /* no interface edge ends here */
        int32_t nc = star(S, v, &S->c, &S->ncap);
        for (int32_t a = 0, b = 0; a < nc; a = b) {
            /* the sector starting at corner a: corners a..b-1 (same part, no cut inside) */
            double deg = sector(S, S->c, nc, a, &b);
            int32_t left = 3 * S->c[a].t + S->c[a].j;                    /* outgoing edge */
            int32_t right = 3 * S->c[b - 1].t + (S->c[b - 1].j + 2) % 3; /* incoming edge */
            int li = edge_iface(m, S->part, left), ri = edge_iface(m, S->part, right);
            if (deg >= WIDE_DEG || !(li || ri)) continue;
            int32_t p = S->part[S->c[a].t], n = b - a;
            int32_t ql = li ? S->part[m->tn[left] / 3] : -1,
                    qr = ri ? S->part[m->tn[right] / 3] : -1;
            if (ql >= 0 && qr >= 0 && S->pw[qr] < S->pw[ql]) { /* the lighter part first */
                int32_t x = ql;
                ql = qr;
                qr = x;
            }
            if (n > tcap) {
                tcap = n;
                ts = mesh_xrealloc(ts, (size_t)tcap, sizeof *ts);
            }
            for (int32_t k = a; k < b; k++)
                ts[k - a] = S->c[k].t;
            /* a move must lower the number of narrow sectors around it: no oscillation */
            int32_t before = bad_around(S, ts, n), moved = 0;
            for (int side = 0; side < 2 && !moved; side++) {
                int32_t q = side == 0 ? ql : qr;
                if (q < 0 || (side == 1 && q == ql) || !move_tris(S, ts, n, p, q)) continue;
                if (bad_around(S, ts, n) < before)
                    moved = 1;
                else
                    move_tris(S, ts, n, q, p);
            }
            if (moved) {
                moves++;
                break; /* v's star changed: look again next pass */
            }
        }
    }
    if (exact) /* a triangle whose apex encroaches an interface edge joins the other side */
        for (int32_t t = 0; t < m->nt; t++) {
            if (!mesh_tri_alive(m, t)) continue;
            for (int j = 0; j < 3; j++) {
                int32_t e = 3 * t + j;
                if (!edge_iface(m, S->part, e)) continue;
                const double *pa = mesh_vertex_xy(m, mesh_org(m, e)),
                             *pb = mesh_vertex_xy(m, mesh_dest(m, e));
                if (!geom_encroaches(pa, pb, mesh_vertex_xy(m, mesh_apex(m, e)))) continue;
                int32_t nb = m->tn[e] / 3, pt = S->part[t], pn = S->part[nb];
                /* t joins the other side, or the triangle across joins t's part: the lighter
                 * destination first, and none past the heaviest part */
                int first = S->pw[pn] <= S->pw[pt] ? 0 : 1, done = 0;
                for (int k = 0; k < 2 && !done; k++) {
                    int32_t x = (k == first) ? t : nb, from = x == t ? pt : pn,
                            to = x == t ? pn : pt;
                    if (S->pw[to] + S->tw[x] > S->pw_max) continue;
                    done = clean_move(S, x, to) && move_tris(S, &x, 1, from, to);
                }
                if (done) {
                    moves++;
                    break;
                }
            }
        }
    mesh_xfree(ts);
    return moves;
}

void decomp_widen(const mesh *m, int32_t *part, const double *tw, int32_t K, int exact) {
    smooth S;
    memset(&S, 0, sizeof S);
    S.m = m;
    S.part = part;
    S.tw = tw;
    S.pw = mesh_xcalloc((size_t)K, sizeof(double));
    S.cnt = mesh_xcalloc((size_t)K, sizeof(int32_t));
    S.near = mesh_xcalloc((size_t)m->nv + 1, 1);
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t)) {
            S.pw[part[t]] += tw[t];
            S.cnt[part[t]]++;
        }
    for (int32_t k = 0; k < K; k++)
        S.pw_max = fmax(S.pw_max, S.pw[k]);
    for (int pass = 0; pass < WIDEN_PASSES && widen_pass(&S, exact) > 0; pass++)
        ;
    /* an interface still encroached will be split: then, as on the coarse route, no narrow
     * sector may let that split start a cascade */
    int left = 0;
    for (int32_t t = 0; exact && !left && t < m->nt; t++)
        for (int j = 0; mesh_tri_alive(m, t) && j < 3 && !left; j++)
            left = edge_iface(m, part, 3 * t + j) && decomp_edge_encroached(m, 3 * t + j);
    for (int pass = 0; left && pass < WIDEN_PASSES && widen_pass(&S, 0) > 0; pass++)
        ;
    mesh_xfree(S.c);
    mesh_xfree(S.c2);
    mesh_xfree(S.vs);
    mesh_xfree(S.pw);
    mesh_xfree(S.cnt);
    mesh_xfree(S.near);
}

/* Every part left empty by METIS (it may, at a few triangles per part) or by decomp_merge_corners
 * takes one triangle of the part with the most: preferably one whose edges no apex encroaches
 * (on the exact preview they all become interfaces) and that touches no sharp input corner. */
void decomp_fill_empty(const mesh *m, int32_t *part, int32_t K) {
    int32_t *cnt = mesh_xcalloc((size_t)K, sizeof(int32_t));
    for (int32_t t = 0; t < m->nt; t++)
        if (mesh_tri_alive(m, t)) cnt[part[t]]++;
    uint8_t *tried = mesh_xmalloc((size_t)K, 1);
    for (int32_t q = 0; q < K; q++) {
        if (cnt[q] > 0) continue;
        memset(tried, 0, (size_t)K);
        int32_t p = -1, pick = -1;
        for (;;) { /* the parts by decreasing size, until one gives a triangle */
            p = -1;
            for (int32_t k = 0; k < K; k++)
                if (!tried[k] && cnt[k] >= 2 && (p < 0 || cnt[k] > cnt[p])) p = k;
            if (p < 0) break; /* fewer triangles than parts: decomp_build reports it */
            tried[p] = 1;
            for (int pass = 0; pass < 2 && pick < 0; pass++)
                for (int32_t t = 0; t < m->nt && pick < 0; t++) {
                    if (!mesh_tri_alive(m, t) || part[t] != p || touches_corner(m, t)) continue;
                    int ok = 1;
                    for (int j = 0; j < 3 && ok && pass == 0; j++)
                        ok = !decomp_edge_encroached(m, 3 * t + j);
                    if (ok) pick = t;
                }
            if (pick >= 0) break;
        }
        if (pick < 0) continue;
        part[pick] = q;
        cnt[p]--;
        cnt[q]++;
    }
    mesh_xfree(tried);
    mesh_xfree(cnt);
}
