/* unit_sizefield: exact point location (geom/tloc.h), the mesh to refine read as a PSLG and the
 * size rules of -r's .area and --size (bounds/sizefield.h).
 *
 * tloc: points inside, on a shared edge and vertex (the lowest triangle), outside (-1, and the
 * nearest triangle for tloc_find_near), clockwise input triangles, barycentric weights.  -r
 * without a .poly: a square ring meshed by 8 triangles becomes 8 boundary segments and hole
 * points that keep the ring's hole out (the PSLG's domain area is the ring's), with a .poly
 * its segments are taken instead; .area bounds the triangles whose centroid lies in a bounded
 * old triangle only; the background size bounds areas by sqrt(3)/4 h^2, h interpolated, and
 * the rules see coordinates scaled by 2^scale_exp.  Files are written to a temporary folder.
 */
#include "bounds/sizefield.h"
#include "check_run.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "geom/tloc.h"
#include "io/meshio.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[256];

static void put(const char *name, const char *text) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    ck_assert_msg(f != NULL, "cannot write %s", path);
    fputs(text, f);
    fclose(f);
}

static const char *at(const char *name) {
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return path;
}

START_TEST(test_tloc) {
    /* the unit square as two triangles, the second clockwise */
    const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1};
    const int32_t tri[] = {0, 1, 2, 0, 3, 2};
    tloc L;
    ck_assert_int_eq(tloc_build(&L, xy, tri, 2), 0);
    ck_assert_int_eq(tloc_find(&L, (double[]){0.75, 0.25}), 0);
    ck_assert_int_eq(tloc_find(&L, (double[]){0.25, 0.75}), 1);
    ck_assert_int_eq(tloc_find(&L, (double[]){0.5, 0.5}), 0); /* shared edge: the lowest */
    ck_assert_int_eq(tloc_find(&L, (double[]){0, 0}), 0);
    ck_assert_int_eq(tloc_find(&L, (double[]){0, 1}), 1);
    ck_assert_int_eq(tloc_find(&L, (double[]){1, 0.5}), 0);
    ck_assert_int_eq(tloc_find(&L, (double[]){1.0000001, 0.5}), -1);
    ck_assert_int_eq(tloc_find(&L, (double[]){-1, -1}), -1);
    ck_assert_int_eq(tloc_find_near(&L, (double[]){1.0000001, 0.5}), 0);
    ck_assert_int_eq(tloc_find_near(&L, (double[]){0.25, 1.0000001}), 1);
    double w[3];
    tloc_weights(&L, 0, (double[]){0.75, 0.25}, w);
    ck_assert(fabs(w[0] - 0.25) < 1e-15 && fabs(w[1] - 0.5) < 1e-15 && fabs(w[2] - 0.25) < 1e-15);
    tloc_free(&L);
}
END_TEST

/* A square ring [0,3]^2 minus [1,2]^2 as 8 triangles (counter-clockwise). */
static void write_ring(const char *name) {
    char b[64];
    snprintf(b, sizeof b, "%s.node", name);
    put(b, "8 2 0 0\n1 0 0\n2 3 0\n3 3 3\n4 0 3\n5 1 1\n6 2 1\n7 2 2\n8 1 2\n");
    snprintf(b, sizeof b, "%s.ele", name);
    put(b, "8 3 0\n1 1 2 6\n2 1 6 5\n3 2 3 7\n4 2 7 6\n5 3 4 8\n6 3 8 7\n7 4 1 5\n8 4 5 8\n");
}

START_TEST(test_refine_pslg_boundary) {
    write_ring("ring");
    pslg g;
    char err[1024];
    ck_assert_msg(meshio_read_mesh_pslg(at("ring.ele"), &g, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(g.nverts, 8);
    ck_assert_int_eq(g.nsegs, 8);
    ck_assert_int_ge(g.nholes, 1);
    for (int32_t s = 0; s < g.nsegs; s++)
        ck_assert_int_eq(g.smarker[s], 1);
    ck_assert_msg(pslg_check(&g, err, sizeof err) == 0, "%s", err);
    double a = pslg_domain_area(&g);
    ck_assert_msg(fabs(a - 8) < 1e-12, "domain area %g, expected 8 (the hole kept out)", a);
    pslg_free(&g);
    /* with a .poly: its segments (only the outer square) and no holes */
    write_ring("ringp");
    put("ringp.poly", "0 2 0 1\n4 1\n1 1 2 5\n2 2 3 5\n3 3 4 5\n4 4 1 5\n0\n");
    ck_assert_msg(meshio_read_mesh_pslg(at("ringp"), &g, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(g.nsegs, 4);
    ck_assert_int_eq(g.nholes, 0);
    ck_assert_int_eq(g.smarker[0], 5);
    ck_assert_msg(pslg_check(&g, err, sizeof err) == 0, "%s", err);
    ck_assert(fabs(pslg_domain_area(&g) - 9) < 1e-12);
    pslg_free(&g);
}
END_TEST

static int too_big(size_field *S, double ax, double ay, double bx, double by, double cx,
                   double cy) {
    const double a[2] = {ax, ay}, b[2] = {bx, by}, c[2] = {cx, cy};
    const double *const p[3] = {a, b, c};
    return size_field_unsuitable(S, p, geom_area(a, b, c));
}

START_TEST(test_area_rule) {
    write_ring("ra");
    /* triangles 1 and 2 (0-based 0 and 1, the bottom left) at most 0.01; the others free */
    put("ra.area", "# bounds\n8\n1 0.01\n2 0.01\n3 -1\n4 0\n5 0\n6 0\n7 0\n8 0\n");
    size_field S;
    char err[1024];
    ck_assert_msg(size_field_load(&S, at("ra"), NULL, 0, err, sizeof err) == 0, "%s", err);
    ck_assert(S.active);
    ck_assert_int_eq(too_big(&S, 0.1, 0.05, 0.5, 0.05, 0.3, 0.3), 1);   /* area 0.05 */
    ck_assert_int_eq(too_big(&S, 0.1, 0.05, 0.2, 0.05, 0.15, 0.15), 0); /* area 0.005 */
    ck_assert_int_eq(too_big(&S, 2.1, 2.5, 2.9, 2.5, 2.5, 2.9), 0);     /* unbounded */
    ck_assert_int_eq(too_big(&S, 1.2, 1.2, 1.8, 1.2, 1.5, 1.8), 0);     /* in the hole */
    size_field_free(&S);
    /* scaled by 2^3: coordinates times 8, areas times 64 */
    ck_assert(size_field_load(&S, at("ra"), NULL, 3, err, sizeof err) == 0);
    ck_assert_int_eq(too_big(&S, 0.8, 0.4, 4, 0.4, 2.4, 2.4), 1);   /* 0.05 * 64 > 0.01 * 64 */
    ck_assert_int_eq(too_big(&S, 0.8, 0.4, 1.0, 0.4, 0.9, 0.6), 0); /* area 0.02 < 0.64 */
    size_field_free(&S);
    put("bad.area", "8\n1 0.01\n3 0.01\n");
    write_ring("bad");
    ck_assert(size_field_load(&S, at("bad"), NULL, 0, err, sizeof err) == -1);
    ck_assert_msg(strstr(err, "bad.area:3: triangle number out of sequence (expected 2)"), "%s",
                  err);
}
END_TEST

START_TEST(test_background_rule) {
    /* h = 0.1 at (0,0), 1 elsewhere on the unit square */
    put("bg.node", "4 2 1 0\n1 0 0 0.1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n");
    put("bg.ele", "2 3 0\n1 1 2 3\n2 1 3 4\n");
    size_field S;
    char err[1024];
    ck_assert_msg(size_field_load(&S, NULL, at("bg.node"), 0, err, sizeof err) == 0, "%s", err);
    /* h = 0.1 + 0.9 max(x, y) at the centroid */
    ck_assert_int_eq(too_big(&S, 0, 0, 0.2, 0, 0, 0.2), 1);         /* 0.02 > 0.011 (h 0.16) */
    ck_assert_int_eq(too_big(&S, 0, 0, 0.05, 0, 0, 0.05), 0);       /* 0.00125 */
    ck_assert_int_eq(too_big(&S, 0.5, 0.5, 0.9, 0.5, 0.5, 0.9), 0); /* 0.08 < 0.43 h^2, h ~ .7 */
    ck_assert_int_eq(too_big(&S, 2, 2, 3, 2, 2, 3), 0);             /* outside: no bound */
    size_field_free(&S);
    put("nolen.node", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n");
    put("nolen.ele", "1 3 0\n1 1 2 3\n");
    ck_assert(size_field_load(&S, NULL, at("nolen"), 0, err, sizeof err) == -1);
    ck_assert_msg(strstr(err, "nolen.node: a background mesh needs one attribute"), "%s", err);
}
END_TEST

int main(void) {
    geom_init();
    snprintf(dir, sizeof dir, "%s/unit_sizefield.XXXXXX",
             getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    if (!mkdtemp(dir)) return 1;
    int rc = ck_run(ck_suite(
        "sizefield", 0,
        CK_TESTS(test_tloc, test_refine_pslg_boundary, test_area_rule, test_background_rule)));
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) rc = EXIT_FAILURE;
    return rc;
}
