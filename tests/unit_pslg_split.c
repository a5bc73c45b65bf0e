/* unit_pslg_split: crossing and overlapping segments split at their intersections
 * (pslg_check_ex with PSLG_SPLIT, mesher/geom/pslg_split.c).
 *
 * Each case builds a small PSLG in memory, checks that pslg_check (strict) refuses it and that
 * PSLG_SPLIT turns it into a valid PSLG -- checked again strictly: no two segments conflict --
 * with the expected vertices, pieces and markers: an X (one new vertex, four pieces), a T (an
 * endpoint inside a segment is not a conflict: nothing changes), collinear overlaps and chains
 * (the union's pieces, the earlier segment's marker kept), three segments through one point
 * whose crossing is not representable (one shared vertex), a star of eight segments through the
 * origin, and attributes interpolated on a crossing vertex.  Also Triangle's boundary markers
 * (pslg_boundary_markers): outer and hole boundaries 1, a marked edge and the file's vertex
 * markers kept, interior segments 0.
 */
#include "check_run.h"
#include "geom/geom.h"
#include "geom/pslg.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* g from nv points and ns segments (0-based), marker of segment s = mk[s] (NULL: s + 1). */
static void build(pslg *g, int32_t nv, const double *xy, int32_t ns, const int32_t *seg,
                  const int32_t *mk) {
    memset(g, 0, sizeof *g);
    g->nverts = nv;
    g->xy = malloc(2 * (size_t)nv * sizeof(double));
    memcpy(g->xy, xy, 2 * (size_t)nv * sizeof(double));
    g->vmarker = calloc((size_t)nv, sizeof(int32_t));
    g->vline = calloc((size_t)nv, sizeof(int32_t));
    g->nsegs = ns;
    g->seg = malloc(2 * (size_t)ns * sizeof(int32_t));
    memcpy(g->seg, seg, 2 * (size_t)ns * sizeof(int32_t));
    g->smarker = malloc((size_t)ns * sizeof(int32_t));
    g->sline = malloc((size_t)ns * sizeof(int32_t));
    for (int32_t s = 0; s < ns; s++) {
        g->smarker[s] = mk ? mk[s] : s + 1;
        g->sline[s] = 10 + s;
    }
    snprintf(g->path, sizeof g->path, "case.poly");
}

static pslg copy_of(const pslg *g) {
    pslg c;
    build(&c, g->nverts, g->xy, g->nsegs, g->seg, g->smarker);
    return c;
}

/* Splits g (after checking that strict mode refuses it, unless refused == 0) and checks the
 * result strictly. */
static void split_ok(pslg *g, int refused) {
    char err[1024];
    pslg c = copy_of(g);
    int rc = pslg_check(&c, err, sizeof err);
    if (refused) ck_assert_msg(rc == -1 && strstr(err, "crosses"), "strict: rc %d '%s'", rc, err);
    pslg_free(&c);
    ck_assert_msg(pslg_check_ex(g, PSLG_SPLIT, err, sizeof err) == 0, "split: %s", err);
    c = copy_of(g);
    ck_assert_msg(pslg_check(&c, err, sizeof err) == 0, "result not valid: %s", err);
    ck_assert_int_eq(c.nsegs, g->nsegs);
    ck_assert_int_eq(c.nverts, g->nverts);
    pslg_free(&c);
}

/* Index of the vertex at (x, y), or -1. */
static int32_t find_vertex(const pslg *g, double x, double y) {
    for (int32_t v = 0; v < g->nverts; v++)
        if (g->xy[2 * v] == x && g->xy[2 * v + 1] == y) return v;
    return -1;
}

/* Marker of the segment joining the vertices at p and q (either way), or -99 if none. */
static int32_t seg_marker(const pslg *g, double px, double py, double qx, double qy) {
    int32_t a = find_vertex(g, px, py), b = find_vertex(g, qx, qy);
    for (int32_t s = 0; s < g->nsegs; s++)
        if ((g->seg[2 * s] == a && g->seg[2 * s + 1] == b) ||
            (g->seg[2 * s] == b && g->seg[2 * s + 1] == a))
            return g->smarker[s];
    return -99;
}

START_TEST(test_cross) {
    const double xy[] = {0, 0, 2, 2, 0, 2, 2, 0};
    const int32_t seg[] = {0, 1, 2, 3};
    pslg g;
    build(&g, 4, xy, 2, seg, NULL);
    split_ok(&g, 1);
    ck_assert_int_eq(g.nverts, 5);
    ck_assert_int_eq(g.nsegs, 4);
    ck_assert_int_eq(find_vertex(&g, 1, 1), 4);
    ck_assert_int_eq(seg_marker(&g, 0, 0, 1, 1), 1);
    ck_assert_int_eq(seg_marker(&g, 1, 1, 2, 2), 1);
    ck_assert_int_eq(seg_marker(&g, 0, 2, 1, 1), 2);
    ck_assert_int_eq(seg_marker(&g, 1, 1, 2, 0), 2);
    pslg_free(&g);
}
END_TEST

START_TEST(test_t_junction_split) {
    /* a vertex inside a segment splits it into two pieces with its marker (no new vertex),
     * also without PSLG_SPLIT: it is no crossing */
    const double xy[] = {0, 0, 4, 0, 2, 0, 2, 3};
    const int32_t seg[] = {0, 1, 2, 3};
    const int32_t mk[] = {5, 7};
    pslg g;
    build(&g, 4, xy, 2, seg, mk);
    char err[256];
    ck_assert_msg(pslg_check(&g, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(g.nverts, 4);
    ck_assert_int_eq(g.nsegs, 3);
    ck_assert_int_eq(seg_marker(&g, 0, 0, 2, 0), 5);
    ck_assert_int_eq(seg_marker(&g, 2, 0, 4, 0), 5);
    ck_assert_int_eq(seg_marker(&g, 2, 0, 2, 3), 7);
    pslg_free(&g);
}
END_TEST

START_TEST(test_overlap) {
    /* (0,0)-(3,0) marker 1 and (1,0)-(5,0) marker 2: pieces 0-1 (1), 1-3 (1, first), 3-5 (2) */
    const double xy[] = {0, 0, 3, 0, 1, 0, 5, 0};
    const int32_t seg[] = {0, 1, 2, 3};
    pslg g;
    build(&g, 4, xy, 2, seg, NULL);
    split_ok(&g, 1);
    ck_assert_int_eq(g.nverts, 4);
    ck_assert_int_eq(g.nsegs, 3);
    ck_assert_int_eq(seg_marker(&g, 0, 0, 1, 0), 1);
    ck_assert_int_eq(seg_marker(&g, 1, 0, 3, 0), 1);
    ck_assert_int_eq(seg_marker(&g, 3, 0, 5, 0), 2);
    pslg_free(&g);
}
END_TEST

START_TEST(test_contained_and_shared_end) {
    /* (0,0)-(4,0) contains (1,0)-(2,0) and shares (0,0) with the collinear (0,0)-(3,0) */
    const double xy[] = {0, 0, 4, 0, 1, 0, 2, 0, 3, 0};
    const int32_t seg[] = {0, 1, 2, 3, 0, 4};
    const int32_t mk[] = {5, 6, 7};
    pslg g;
    build(&g, 5, xy, 3, seg, mk);
    split_ok(&g, 1);
    ck_assert_int_eq(g.nverts, 5);
    ck_assert_int_eq(g.nsegs, 4);
    ck_assert_int_eq(seg_marker(&g, 0, 0, 1, 0), 5);
    ck_assert_int_eq(seg_marker(&g, 1, 0, 2, 0), 5);
    ck_assert_int_eq(seg_marker(&g, 2, 0, 3, 0), 5);
    ck_assert_int_eq(seg_marker(&g, 3, 0, 4, 0), 5);
    pslg_free(&g);
}
END_TEST

START_TEST(test_collinear_chain) {
    /* a chain 0-1-2-3 along y = x overlapped by one long segment and a shifted copy */
    const double xy[] = {0, 0, 1, 1, 2, 2, 3, 3, 0.5, 0.5, 2.5, 2.5};
    const int32_t seg[] = {0, 1, 1, 2, 2, 3, 0, 3, 4, 5};
    pslg g;
    build(&g, 6, xy, 5, seg, NULL);
    split_ok(&g, 1);
    ck_assert_int_eq(g.nverts, 6);
    ck_assert_int_eq(g.nsegs, 5); /* 0-.5-1-2-2.5-3 */
    ck_assert_int_eq(seg_marker(&g, 0, 0, 0.5, 0.5), 1);
    ck_assert_int_eq(seg_marker(&g, 0.5, 0.5, 1, 1), 1);
    ck_assert_int_eq(seg_marker(&g, 1, 1, 2, 2), 2);
    ck_assert_int_eq(seg_marker(&g, 2, 2, 2.5, 2.5), 3);
    ck_assert_int_eq(seg_marker(&g, 2.5, 2.5, 3, 3), 3);
    pslg_free(&g);
}
END_TEST

START_TEST(test_three_through_one_point) {
    /* lines y = x, y = 1 - 2x and y = (1 - x) / 2 meet at (1/3, 1/3), not a double */
    const double xy[] = {0, 0, 1, 1, 0, 1, 1, -1, 1, 0, -1, 1};
    const int32_t seg[] = {0, 1, 2, 3, 4, 5};
    pslg g;
    build(&g, 6, xy, 3, seg, NULL);
    split_ok(&g, 1);
    ck_assert_int_eq(g.nverts, 7); /* one shared crossing vertex */
    ck_assert_int_eq(g.nsegs, 6);
    ck_assert(fabs(g.xy[12] - 1.0 / 3) < 1e-15 && fabs(g.xy[13] - 1.0 / 3) < 1e-15);
    pslg_free(&g);
}
END_TEST

START_TEST(test_star_through_origin) {
    double xy[32];
    int32_t seg[16];
    for (int k = 0; k < 8; k++) { /* 8 diameters of a circle, all through the origin */
        double a = M_PI * k / 8;
        xy[4 * k] = 10 * cos(a);
        xy[4 * k + 1] = 10 * sin(a);
        xy[4 * k + 2] = -10 * cos(a);
        xy[4 * k + 3] = -10 * sin(a);
        seg[2 * k] = 2 * k;
        seg[2 * k + 1] = 2 * k + 1;
    }
    pslg g;
    build(&g, 16, xy, 8, seg, NULL);
    split_ok(&g, 1);
    ck_assert_int_eq(g.nverts, 17);
    ck_assert_int_eq(g.nsegs, 16);
    ck_assert_int_eq(find_vertex(&g, 0, 0), 16);
    pslg_free(&g);
}
END_TEST

START_TEST(test_grid_of_crossings) {
    /* 5 horizontal and 5 vertical segments: 25 crossings, 50 pieces... plus the ends */
    double xy[40];
    int32_t seg[20];
    for (int k = 0; k < 5; k++) {
        double c = 1 + k * 0.7;
        double h[4] = {0, c, 5, c}, v[4] = {c, 0, c, 5};
        memcpy(xy + 8 * k, h, sizeof h);
        memcpy(xy + 8 * k + 4, v, sizeof v);
        seg[4 * k] = 4 * k;
        seg[4 * k + 1] = 4 * k + 1;
        seg[4 * k + 2] = 4 * k + 2;
        seg[4 * k + 3] = 4 * k + 3;
    }
    pslg g;
    build(&g, 20, xy, 10, seg, NULL);
    split_ok(&g, 1);
    ck_assert_int_eq(g.nverts, 45);
    ck_assert_int_eq(g.nsegs, 60);
    pslg_free(&g);
}
END_TEST

START_TEST(test_attributes_interpolated) {
    const double xy[] = {0, 0, 4, 0, 1, -1, 1, 3};
    const int32_t seg[] = {0, 1, 2, 3};
    pslg g;
    build(&g, 4, xy, 2, seg, NULL);
    g.nattr = 1;
    g.vattr = malloc(4 * sizeof(double));
    double at[] = {0, 8, 100, 100};
    memcpy(g.vattr, at, sizeof at);
    split_ok(&g, 1);
    ck_assert_int_eq(g.nverts, 5);
    ck_assert(g.xy[8] == 1 && g.xy[9] == 0);
    ck_assert_msg(fabs(g.vattr[4] - 2) < 1e-12, "attribute %g, expected 2", g.vattr[4]);
    pslg_free(&g);
}
END_TEST

START_TEST(test_scaled_input) {
    /* coordinates beyond 2^100 are scaled first; the crossing vertex is in the scaled units */
    const double xy[] = {1e40, 1e40, 3e40, 3e40, 1e40, 3e40, 3e40, 1e40};
    const int32_t seg[] = {0, 1, 2, 3};
    pslg g;
    build(&g, 4, xy, 2, seg, NULL);
    split_ok(&g, 1);
    ck_assert_int_ne(g.scale_exp, 0);
    ck_assert_int_eq(g.nverts, 5);
    double x = ldexp(g.xy[8], -g.scale_exp), y = ldexp(g.xy[9], -g.scale_exp);
    ck_assert_msg(fabs(x / 2e40 - 1) < 1e-15 && fabs(y / 2e40 - 1) < 1e-15, "(%g, %g)", x, y);
    pslg_free(&g);
}
END_TEST

/* The marker tests' PSLG: nv vertices, the ten segments seg (a square, a square hole around
 * (1.5, 1.5), a dangling pair) marked mk; vertex 3 marked 3 in the file; checked, then given
 * Triangle's markers (pslg_boundary_markers). */
static void marked_square(pslg *g, int32_t nv, const double *xy, const int32_t *seg,
                          const int32_t *mk) {
    build(g, nv, xy, 10, seg, mk);
    g->vmarker[3] = 3;
    g->nholes = 1;
    g->holes = malloc(2 * sizeof(double));
    g->holes[0] = g->holes[1] = 1.5;
    char err[256];
    ck_assert_msg(pslg_check(g, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(pslg_boundary_markers(g), 0);
}

START_TEST(test_boundary_markers) {
    /* a square (bottom marker 7) with a square hole and a dangling interior segment, all other
     * markers 0; vertex 3 (0, 4) has marker 3 in the file */
    const double xy[] = {0, 0, 4, 0, 4, 4, 0, 4, 1, 1, 2, 1, 2, 2, 1, 2, 3, 3, 3.5, 2};
    const int32_t seg[] = {0, 1, 1, 2, 2, 3, 3, 0, 4, 5, 5, 6, 6, 7, 7, 4, 8, 2, 8, 9};
    const int32_t mk[] = {7, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    pslg g;
    marked_square(&g, 10, xy, seg, mk);
    const int32_t want_s[] = {7, 1, 1, 1, 1, 1, 1, 1, 0, 0};
    const int32_t want_v[] = {7, 7, 1, 3, 1, 1, 1, 1, 0, 0};
    for (int s = 0; s < 10; s++)
        ck_assert_msg(g.smarker[s] == want_s[s], "segment %d: %d", s, g.smarker[s]);
    for (int v = 0; v < 10; v++)
        ck_assert_msg(g.vmarker[v] == want_v[v], "vertex %d: %d", v, g.vmarker[v]);
    pslg_free(&g);
}
END_TEST

START_TEST(test_boundary_markers_all_marked) {
    /* every segment marked (no face needed): the outer square 7, the hole 5, the dangling
     * segments 9; vertex 10 (2, 0) lies inside the bottom segment (split there by pslg_check,
     * both pieces 7); vertex 3 keeps the file's 3 */
    const double xy[] = {0, 0, 4, 0, 4, 4, 0, 4, 1, 1, 2, 1, 2, 2, 1, 2, 3, 3, 3.5, 2, 2, 0};
    const int32_t seg[] = {0, 1, 1, 2, 2, 3, 3, 0, 4, 5, 5, 6, 6, 7, 7, 4, 8, 2, 8, 9};
    const int32_t mk[] = {7, 7, 7, 7, 5, 5, 5, 5, 9, 9};
    pslg g;
    marked_square(&g, 11, xy, seg, mk);
    ck_assert_int_eq(g.nsegs, 11);
    const int32_t want_v[] = {7, 7, 7, 3, 5, 5, 5, 5, 9, 9, 7};
    for (int v = 0; v < 11; v++)
        ck_assert_msg(g.vmarker[v] == want_v[v], "vertex %d: %d", v, g.vmarker[v]);
    for (int s = 0; s < g.nsegs; s++)
        ck_assert_msg(g.smarker[s] == 7 || g.smarker[s] == 5 || g.smarker[s] == 9, "segment %d: %d",
                      s, g.smarker[s]);
    pslg_free(&g);
}
END_TEST

int main(void) {
    geom_init();
    return ck_run(ck_suite(
        "pslg_split", 0,
        CK_TESTS(test_cross, test_t_junction_split, test_overlap, test_contained_and_shared_end,
                 test_collinear_chain, test_three_through_one_point, test_star_through_origin,
                 test_grid_of_crossings, test_attributes_interpolated, test_scaled_input,
                 test_boundary_markers, test_boundary_markers_all_marked)));
}
