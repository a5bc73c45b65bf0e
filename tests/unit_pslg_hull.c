/* unit_pslg_hull: the convex hull enclosed by segments (Triangle's -c; mesher/geom/pslg_hull.c).
 *
 * pslg_hull against brute force on random point sets drawn from a small integer grid (many
 * collinear points and duplicates): every turn counter-clockwise or straight, every point on
 * the left of or on every hull edge, every point on the hull's boundary a hull vertex (so no
 * hull edge passes through a point), each point once, one turn around; the 5 x 3 grid's hull
 * has its 12 boundary points; points on one line have no hull.  pslg_enclose_hull: segments
 * that enclose nothing get the hull's edges as marker-1 segments, cut at the vertices on them,
 * without repeating an input segment that lies on the hull (its marker kept), and the result
 * passes the strict check unchanged; the domain's area is the hull's minus the hole's.
 * pslg_check_ex with PSLG_HULL after crossings were split and duplicates merged; a point set's
 * hull vertices get boundary marker 1 (pslg_boundary_markers).
 */
#include "check_run.h"
#include "geom/geom.h"
#include "geom/pslg.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void build(pslg *g, int32_t nv, const double *xy, int32_t ns, const int32_t *seg,
                  const int32_t *mk) {
    memset(g, 0, sizeof *g);
    g->nverts = nv;
    g->xy = malloc(2 * (size_t)nv * sizeof(double) + 8);
    memcpy(g->xy, xy, 2 * (size_t)nv * sizeof(double));
    g->vmarker = calloc((size_t)nv + 1, sizeof(int32_t));
    g->vline = calloc((size_t)nv + 1, sizeof(int32_t));
    g->nsegs = ns;
    g->seg = malloc(2 * (size_t)ns * sizeof(int32_t) + 8);
    if (ns) memcpy(g->seg, seg, 2 * (size_t)ns * sizeof(int32_t));
    g->smarker = malloc((size_t)ns * sizeof(int32_t) + 8);
    g->sline = malloc((size_t)ns * sizeof(int32_t) + 8);
    for (int32_t s = 0; s < ns; s++) {
        g->smarker[s] = mk ? mk[s] : 0;
        g->sline[s] = 10 + s;
    }
    snprintf(g->path, sizeof g->path, "case.poly");
}

static const double *P(const pslg *g, int32_t v) {
    return g->xy + 2 * (size_t)v;
}

static int same(const double *a, const double *b) {
    return a[0] == b[0] && a[1] == b[1];
}

static int on_closed(const double *a, const double *b, const double *p) {
    return geom_orient2d(a, b, p) == 0 && fmin(a[0], b[0]) <= p[0] && p[0] <= fmax(a[0], b[0]) &&
           fmin(a[1], b[1]) <= p[1] && p[1] <= fmax(a[1], b[1]);
}

/* Checks cyc[0..h) as the hull of g's points by brute force; returns h. */
static int32_t hull_ok(const pslg *g, const int32_t *cyc, int32_t h) {
    int32_t n = g->nverts;
    int flat = 1;
    for (int32_t i = 0; i < n && flat; i++)
        for (int32_t j = 0; j < n && flat; j++)
            for (int32_t k = 0; k < n && flat; k++)
                if (geom_orient2d(P(g, i), P(g, j), P(g, k)) != 0) flat = 0;
    if (flat) {
        ck_assert_int_eq(h, 0);
        return 0;
    }
    ck_assert_int_ge(h, 3);
    int changes = 0, last = 0, strict = 0;
    for (int32_t i = 0; i < h; i++) {
        const double *a = P(g, cyc[i]), *b = P(g, cyc[(i + 1) % h]), *c = P(g, cyc[(i + 2) % h]);
        double o = geom_orient2d(a, b, c);
        ck_assert_msg(o >= 0, "hull turns clockwise at %d", cyc[(i + 1) % h]);
        strict += o > 0;
        for (int32_t j = i + 1; j < h; j++)
            ck_assert_msg(!same(a, P(g, cyc[j])), "point %d twice on the hull", cyc[i]);
        int dir = (b[0] > a[0]) - (b[0] < a[0]);
        if (dir && last && dir != last) changes++;
        if (dir) last = dir;
        for (int32_t p = 0; p < n; p++) {
            ck_assert_msg(geom_orient2d(a, b, P(g, p)) >= 0, "point %d outside the hull", p);
            if (on_closed(a, b, P(g, p)))
                ck_assert_msg(same(P(g, p), a) || same(P(g, p), b),
                              "point %d (%g, %g) inside hull edge %d-%d", p, P(g, p)[0], P(g, p)[1],
                              cyc[i], cyc[(i + 1) % h]);
        }
    }
    ck_assert_int_ge(strict, 3);
    ck_assert_int_le(changes, 2); /* x-monotone up, then down: once around */
    return h;
}

START_TEST(test_grid_hull) {
    double xy[2 * 18];
    int32_t n = 0;
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 5; x++) {
            xy[2 * n] = x;
            xy[2 * n + 1] = y;
            n++;
        }
    double in[] = {1.5, 0.5, 2.5, 1.5, 3.25, 0.75};
    memcpy(xy + 2 * n, in, sizeof in);
    n += 3;
    pslg g;
    build(&g, n, xy, 0, NULL, NULL);
    int32_t cyc[2 * 18 + 2];
    int32_t h = pslg_hull(&g, cyc);
    ck_assert_int_eq(hull_ok(&g, cyc, h), 12);
    ck_assert_int_eq(cyc[0], 0); /* the lowest of the leftmost */
    /* a point set: the hull's points get marker 1, the others keep 0 */
    ck_assert_int_eq(pslg_boundary_markers(&g), 0);
    for (int32_t v = 0; v < n; v++) {
        int x = (int)g.xy[2 * v], y = (int)g.xy[2 * v + 1];
        int on = v < 15 && (x == 0 || x == 4 || y == 0 || y == 2);
        ck_assert_msg(g.vmarker[v] == on, "vertex %d marker %d", v, g.vmarker[v]);
    }
    pslg_free(&g);
}
END_TEST

START_TEST(test_random_hulls) {
    srand(12345);
    int32_t total = 0;
    for (int trial = 0; trial < 400; trial++) {
        int32_t n = 1 + rand() % 40, side = 2 + rand() % 7;
        double xy[2 * 40];
        int line = trial % 10 == 0; /* now and then every point on one slanted line */
        for (int32_t i = 0; i < n; i++) {
            int t = rand() % side;
            xy[2 * i] = line ? t : rand() % side;
            xy[2 * i + 1] = line ? 2 * t + 1 : (rand() % side) * 0.5;
        }
        pslg g;
        build(&g, n, xy, 0, NULL, NULL);
        int32_t cyc[2 * 40 + 2];
        total += hull_ok(&g, cyc, pslg_hull(&g, cyc));
        pslg_free(&g);
    }
    ck_assert_int_gt(total, 400); /* the trials had hulls */
}
END_TEST

/* tests/inputs/hull/regions.poly in memory: segments that enclose nothing but a hole. */
static const double box_xy[] = {0, 0, 4, 0, 8, 0, 8, 2, 8, 4, 0, 4, 0,   1,
                                8, 1, 2, 2, 3, 2, 3, 3, 2, 3, 5, 3, 6.5, 2.5};
static const int32_t box_seg[] = {6, 7, 0, 2, 4, 5, 8, 9, 9, 10, 10, 11, 11, 8, 12, 13};
static const int32_t box_mk[] = {0, 7, 3, 0, 0, 0, 0, 0};

START_TEST(test_enclose) {
    pslg g;
    build(&g, 14, box_xy, 8, box_seg, box_mk);
    g.nholes = 1;
    g.holes = malloc(2 * sizeof(double));
    g.holes[0] = g.holes[1] = 2.5;
    char err[1024];
    ck_assert_msg(pslg_check(&g, err, sizeof err) == 0, "%s", err);
    ck_assert(pslg_domain_area(&g) == 0); /* without the hull: nothing enclosed but the hole */
    pslg_enclose_hull(&g);
    /* hull: 0 1 2 7 3 4 5 6; 0-1-2 is segment 1 (split at 1 by the check: pieces 1 and 2),
     * 4-5 segment 3: five new segments */
    static const int32_t want[][2] = {{2, 7}, {7, 3}, {3, 4}, {5, 6}, {6, 0}};
    static const int32_t mk_after[] = {0, 7, 7, 3, 0, 0, 0, 0, 0};
    ck_assert_int_eq(g.nsegs, 14);
    for (int k = 0; k < 5; k++) {
        int32_t s = 9 + k;
        ck_assert_msg(g.seg[2 * s] == want[k][0] && g.seg[2 * s + 1] == want[k][1],
                      "new segment %d: %d-%d", k, g.seg[2 * s], g.seg[2 * s + 1]);
        ck_assert_int_eq(g.smarker[s], 1);
        ck_assert_int_eq(g.sline[s], 0);
    }
    for (int32_t s = 0; s < 9; s++)
        ck_assert_int_eq(g.smarker[s], mk_after[s]);
    pslg c;
    build(&c, g.nverts, g.xy, g.nsegs, g.seg, g.smarker);
    ck_assert_msg(pslg_check(&c, err, sizeof err) == 0, "strict check: %s", err);
    ck_assert_int_eq(c.nsegs, g.nsegs); /* nothing repeated */
    ck_assert(pslg_domain_area(&g) == 32 - 1);
    pslg_enclose_hull(&c); /* enclosing again adds nothing */
    ck_assert_int_eq(c.nsegs, g.nsegs);
    pslg_free(&c);
    pslg_free(&g);
}
END_TEST

START_TEST(test_enclose_flat) {
    static const double xy[] = {0, 0, 1, 1, 2, 2, 3, 3};
    static const int32_t seg[] = {0, 1, 2, 3};
    pslg g;
    build(&g, 4, xy, 2, seg, NULL);
    char err[1024];
    ck_assert_msg(pslg_check_ex(&g, PSLG_SPLIT | PSLG_HULL, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(g.nsegs, 2);
    pslg_free(&g);
}
END_TEST

/* PSLG_HULL after the split and the merge: an X of two segments, a duplicate point, and a
 * segment along the hull's edge through a point on it. */
START_TEST(test_check_ex_hull) {
    static const double xy[] = {0, 0, 4, 4, 0, 4, 4, 0, 2, 4, 4, 4, 6, 2};
    static const int32_t seg[] = {0, 1, 2, 3, 2, 5};
    pslg g;
    build(&g, 7, xy, 3, seg, NULL);
    char err[1024];
    g.quiet = 1;
    ck_assert_msg(pslg_check_ex(&g, PSLG_SPLIT | PSLG_HULL, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(g.nverts, 7); /* 6 distinct, plus the crossing (2, 2) */
    int32_t cyc[2 * 7 + 2];
    int32_t h = pslg_hull(&g, cyc); /* (0,0) (4,0) (6,2) (4,4) (2,4) (0,4) */
    ck_assert_int_eq(hull_ok(&g, cyc, h), 6);
    /* the X's four pieces, the top segment's two pieces (split at (2,4), each a hull edge),
     * four new ones */
    ck_assert_int_eq(g.nsegs, 10);
    for (int32_t s = 6; s < 10; s++)
        ck_assert_int_eq(g.smarker[s], 1);
    ck_assert(pslg_domain_area(&g) == 20);
    pslg_free(&g);
}
END_TEST

int main(void) {
    geom_init();
    return ck_run(ck_suite("pslg_hull", 0,
                           CK_TESTS(test_grid_hull, test_random_hulls, test_enclose,
                                    test_enclose_flat, test_check_ex_hull)));
}
