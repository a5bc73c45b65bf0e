/* unit_validate: the mesh validator on hand-made meshes.
 *
 * A correct two-triangle square passes; each kind of defect (clockwise triangle, non-Delaunay
 * diagonal, missing triangle, overlapping triangle, missing input segment, missing input
 * vertex, quality bounds) must be caught by its own counter; the wedge's 10-degree corner is
 * exempt from the angle bound while the square's corners are not; a structured grid mesh of
 * half a million triangles validates quickly.  Run from the repository root.
 */
#include "check/validate.h"
#include "check_run.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "io/meshio.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void load(const char *path, pslg *g) {
    char err[1024];
    ck_assert_msg(pslg_read(path, g, err, sizeof err) == 0, "%s", err);
    ck_assert_msg(pslg_check(g, err, sizeof err) == 0, "%s", err);
}

/* A PSLG from arrays (copied, so pslg_free can release it): a closed polygon plus extra
 * segments. */
static void make_pslg(pslg *g, int nv, const double *xy, int ns, const int32_t *seg) {
    memset(g, 0, sizeof *g);
    g->nverts = nv;
    g->xy = malloc(sizeof(double) * 2 * nv);
    memcpy(g->xy, xy, sizeof(double) * 2 * nv);
    g->nsegs = ns;
    g->seg = malloc(sizeof(int32_t) * 2 * ns);
    memcpy(g->seg, seg, sizeof(int32_t) * 2 * ns);
    snprintf(g->path, sizeof g->path, "(test)");
    char err[256];
    ck_assert_msg(pslg_check(g, err, sizeof err) == 0, "%s", err);
}

static mesh_flat flat(int nv, double *xy, int nt, int32_t *tri, int ns, int32_t *seg) {
    mesh_flat m;
    memset(&m, 0, sizeof m);
    m.nverts = nv;
    m.xy = xy;
    m.ntris = nt;
    m.tri = tri;
    m.nsegs = ns;
    m.seg = seg;
    return m;
}

static double sq_xy[] = {0, 0, 1, 0, 1, 1, 0, 1};
static int32_t sq_seg[] = {0, 1, 1, 2, 2, 3, 3, 0};

static int run(const pslg *g, const mesh_flat *m, double q, double a, validate_report *r) {
    validate_opts o = {q, a, 0, 0, 0, 0};
    int ok = mesh_validate(g, m, &o, r);
    validate_report_print(r, stdout);
    ck_assert_int_eq(ok, r->ok);
    return ok;
}

START_TEST(test_square_ok) {
    pslg g;
    load("data/square.poly", &g);
    int32_t tri[] = {0, 1, 2, 0, 2, 3};
    mesh_flat m = flat(4, sq_xy, 2, tri, 4, sq_seg);
    validate_report r;
    ck_assert_msg(run(&g, &m, 30, 0.5, &r), "%s", r.first_problem);
    ck_assert_double_eq_tol(r.min_angle, 45, 1e-9);
    ck_assert_double_eq_tol(r.max_area, 0.5, 1e-15);
    ck_assert_double_eq(r.mesh_area, 1);
    ck_assert_double_eq(r.domain_area, 1);
    ck_assert_int_eq(r.nexempt, 0);
    /* the other diagonal is just as Delaunay (cocircular) */
    int32_t tri2[] = {0, 1, 3, 1, 2, 3};
    m.tri = tri2;
    ck_assert_msg(run(&g, &m, 0, 0, &r), "%s", r.first_problem);
    /* no segment list at all: the boundary edges carry the input segments */
    m.nsegs = 0;
    ck_assert_msg(run(&g, &m, 0, 0, &r), "%s", r.first_problem);
    pslg_free(&g);
}
END_TEST

START_TEST(test_flipped) {
    pslg g;
    load("data/square.poly", &g);
    int32_t tri[] = {0, 2, 1, 0, 2, 3};
    mesh_flat m = flat(4, sq_xy, 2, tri, 4, sq_seg);
    validate_report r;
    ck_assert(!run(&g, &m, 0, 0, &r));
    ck_assert_int_eq(r.bad_orient, 1);
    ck_assert_msg(strstr(r.first_problem, "triangle 0 (0 2 1) is clockwise"), "%s",
                  r.first_problem);
    pslg_free(&g);
}
END_TEST

/* A kite whose long diagonal is not Delaunay. */
START_TEST(test_non_delaunay) {
    double xy[] = {0, 0, 2, -1, 4, 0, 2, 1};
    int32_t seg[] = {0, 1, 1, 2, 2, 3, 3, 0};
    pslg g;
    make_pslg(&g, 4, xy, 4, seg);
    int32_t bad[] = {0, 1, 2, 0, 2, 3}, good[] = {0, 1, 3, 1, 2, 3};
    mesh_flat m = flat(4, xy, 2, bad, 4, seg);
    validate_report r;
    ck_assert(!run(&g, &m, 0, 0, &r));
    ck_assert_int_eq(r.non_delaunay, 1);
    ck_assert_int_eq(r.bad_conform + r.bad_orient + r.missing_segs + r.area_mismatch, 0);
    m.tri = good;
    ck_assert_msg(run(&g, &m, 0, 0, &r), "%s", r.first_problem);
    /* the long diagonal as an input segment is a constraint: then it is allowed */
    double xy2[] = {0, 0, 2, -1, 4, 0, 2, 1};
    int32_t seg2[] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2};
    pslg g2;
    make_pslg(&g2, 4, xy2, 5, seg2);
    m.tri = bad;
    m.seg = seg2;
    m.nsegs = 5;
    ck_assert_msg(run(&g2, &m, 0, 0, &r), "%s", r.first_problem);
    /* ... but the other diagonal misses that input segment */
    m.tri = good;
    ck_assert(!run(&g2, &m, 0, 0, &r));
    ck_assert_int_eq(r.missing_segs, 1);
    pslg_free(&g);
    pslg_free(&g2);
}
END_TEST

/* An interface constraint (listed segment on no input segment) may be non-Delaunay unless
 * --interfaces-delaunay is asked for. */
START_TEST(test_interface_delaunay) {
    double xy[] = {0, 0, 2, -1, 4, 0, 2, 1};
    int32_t seg[] = {0, 1, 1, 2, 2, 3, 3, 0};
    pslg g;
    make_pslg(&g, 4, xy, 4, seg);
    int32_t tri[] = {0, 1, 2, 0, 2, 3};
    int32_t mseg[] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2};
    int32_t iface[] = {0, 0, 0, 0, 1};
    mesh_flat m = flat(4, xy, 2, tri, 5, mseg);
    m.sinterface = iface;
    validate_report r;
    validate_opts o = {0};
    ck_assert_msg(mesh_validate(&g, &m, &o, &r), "%s", r.first_problem);
    o.check_delaunay_interfaces = 1;
    ck_assert(!mesh_validate(&g, &m, &o, &r));
    ck_assert_int_eq(r.non_delaunay, 1);
    m.sinterface = NULL; /* read back from files: any listed non-input edge is an interface */
    ck_assert(!mesh_validate(&g, &m, &o, &r));
    o.check_delaunay_interfaces = 0;
    ck_assert(mesh_validate(&g, &m, &o, &r));
    pslg_free(&g);
}
END_TEST

START_TEST(test_missing_triangle) {
    pslg g;
    load("data/square.poly", &g);
    int32_t tri[] = {0, 1, 2};
    mesh_flat m = flat(4, sq_xy, 1, tri, 4, sq_seg);
    validate_report r;
    ck_assert(!run(&g, &m, 0, 0, &r));
    ck_assert_int_eq(r.area_mismatch, 1);
    ck_assert(r.stray_boundary >= 1); /* the diagonal is now a boundary edge */
    ck_assert(r.missing_segs >= 1);
    ck_assert_double_eq(r.mesh_area, 0.5);
    pslg_free(&g);
}
END_TEST

START_TEST(test_overlap) {
    pslg g;
    load("data/square.poly", &g);
    validate_report r;
    /* the same triangle twice */
    int32_t tri[] = {0, 1, 2, 0, 2, 3, 0, 1, 2};
    mesh_flat m = flat(4, sq_xy, 3, tri, 4, sq_seg);
    ck_assert(!run(&g, &m, 0, 0, &r));
    ck_assert(r.bad_conform >= 1);
    /* both diagonals' triangle pairs at once: every edge used consistently, area doubled */
    int32_t tri2[] = {0, 1, 2, 0, 2, 3, 0, 1, 3, 1, 2, 3};
    m.tri = tri2;
    m.ntris = 4;
    ck_assert(!run(&g, &m, 0, 0, &r));
    ck_assert(r.bad_conform >= 1);
    ck_assert_int_eq(r.area_mismatch, 1);
    /* a triangle floating over the square, sharing no edge */
    double xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.2, 0.2, 0.4, 0.2, 0.3, 0.4};
    int32_t tri3[] = {0, 1, 2, 0, 2, 3, 4, 5, 6};
    mesh_flat m3 = flat(7, xy, 3, tri3, 4, sq_seg);
    ck_assert(!run(&g, &m3, 0, 0, &r));
    ck_assert_int_eq(r.area_mismatch, 1);
    ck_assert_int_eq(r.stray_boundary, 3);
    pslg_free(&g);
}
END_TEST

START_TEST(test_missing_segment_and_vertex) {
    pslg g;
    load("data/square.poly", &g);
    validate_report r;
    /* a square whose corner (1, 1) moved: vertex missing and two segments with it */
    double xy[] = {0, 0, 1, 0, 1, 1.0000001, 0, 1};
    int32_t tri[] = {0, 1, 2, 0, 2, 3};
    mesh_flat m = flat(4, xy, 2, tri, 4, sq_seg);
    ck_assert(!run(&g, &m, 0, 0, &r));
    ck_assert_int_eq(r.missing_verts, 1);
    ck_assert_int_eq(r.missing_segs, 2);
    /* an interior input segment not listed among the mesh segments */
    double pxy[] = {0, 0, 1, 0, 1, 1, 0, 1};
    int32_t pseg[] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2};
    pslg g2;
    make_pslg(&g2, 4, pxy, 5, pseg);
    m = flat(4, sq_xy, 2, tri, 4, sq_seg);
    ck_assert(!run(&g2, &m, 0, 0, &r));
    ck_assert_int_eq(r.missing_segs, 1);
    m.seg = pseg;
    m.nsegs = 5;
    ck_assert_msg(run(&g2, &m, 0, 0, &r), "%s", r.first_problem);
    /* a listed segment that is not a mesh edge */
    int32_t tri2[] = {0, 1, 3, 1, 2, 3};
    m.tri = tri2;
    ck_assert(!run(&g2, &m, 0, 0, &r));
    ck_assert(r.bad_conform >= 1 && r.missing_segs == 1);
    pslg_free(&g);
    pslg_free(&g2);
}
END_TEST

/* Boundary segments split at rounded midpoints still count as the input segment. */
START_TEST(test_split_segment_chain) {
    double a[2] = {0.1, 0.7}, b[2] = {0.9, 0.3}, mid[2], q[2];
    geom_midpoint(a, b, mid);
    geom_midpoint(a, mid, q);
    double xy[] = {a[0], a[1], b[0], b[1], 0.3, 1.9, mid[0], mid[1], q[0], q[1]};
    int32_t pseg[] = {0, 1, 1, 2, 2, 0};
    pslg g;
    make_pslg(&g, 3, xy, 3, pseg);
    int32_t tri[] = {0, 4, 2, 4, 3, 2, 3, 1, 2};
    int32_t mseg[] = {0, 4, 4, 3, 3, 1, 1, 2, 2, 0};
    mesh_flat m = flat(5, xy, 3, tri, 5, mseg);
    validate_report r;
    ck_assert_msg(run(&g, &m, 0, 0, &r), "%s", r.first_problem);
    pslg_free(&g);
}
END_TEST

/* The precision model (README, Robustness): far from the origin a split point of a slanted
 * boundary segment rounds off its line by an ulp of the coordinates, which moves the domain's
 * area by far more than a relative 1e-9 of a small domain; the validator accepts what rounding
 * explains (validate_area_slack: 2^-48 of the magnitude per unit of segment length, at most
 * 2^-7 of the area), and the cheap net (validate_area_net) applies the same tolerance. */
START_TEST(test_area_rounding_far) {
    const double X = 0x1p30; /* ulp 2^-22 */
    double a[2] = {X + 0.1, X + 0.7}, b[2] = {X + 0.9, X + 0.3}, mid[2];
    geom_midpoint(a, b, mid);
    mid[1] += 0x1p-22; /* one ulp off the line, outwards or inwards */
    double xy[] = {a[0], a[1], b[0], b[1], X + 0.3, X + 1.9, mid[0], mid[1]};
    int32_t pseg[] = {0, 1, 1, 2, 2, 0};
    pslg g;
    make_pslg(&g, 3, xy, 3, pseg);
    int32_t tri[] = {0, 3, 2, 3, 1, 2};
    int32_t mseg[] = {0, 3, 3, 1, 1, 2, 2, 0};
    mesh_flat m = flat(4, xy, 2, tri, 4, mseg);
    validate_report r;
    ck_assert_msg(run(&g, &m, 0, 0, &r), "%s", r.first_problem);
    double moved = fabs(r.mesh_area - r.domain_area);
    printf("far triangle: area moved by %.3g (relative %.3g), slack %.3g\n", moved,
           moved / r.domain_area, r.area_slack_w);
    ck_assert(moved > 1e-9 * r.domain_area); /* the old relative test would refuse it */
    ck_assert(moved <= r.area_slack_w);
    double dom = 0;
    ck_assert_int_eq(validate_area_net(&g, r.mesh_area, &dom), 1);
    ck_assert_double_eq(dom, r.domain_area);
    ck_assert_int_eq(validate_area_net(&g, r.domain_area * (1 + 1e-4), &dom), 0);
    pslg_free(&g);
    /* the slack: 2^-48 mag seglen, capped at 2^-7 of the area */
    ck_assert_double_eq(validate_area_slack(1, 1, 4), 0x1p-46);
    ck_assert_double_eq(validate_area_slack(1, 0x1p50, 4), 0x1p-7);
    ck_assert_int_eq(validate_area_ok(1 + 2e-9, 1, 0), 0);
    ck_assert_int_eq(validate_area_ok(1 + 2e-9, 1, 1.5e-9), 1);
}
END_TEST

/* Two boundary segments 1e-50 radians apart at a far vertex (a fuzz finding): the midpoint of
 * one lies within the distance test of the other, and the chain of the other must not detour
 * through it when its own edge reaches its end. */
START_TEST(test_near_parallel_segments) {
    double xy[] = {0, 0, 0, 0.21, 0, 82, 9, 9.4e50, 4.5, 4.7e50};
    int32_t seg[] = {0, 3, 3, 2, 2, 1, 1, 0};
    pslg g;
    make_pslg(&g, 4, xy, 4, seg);
    int32_t tri[] = {3, 2, 4, 2, 1, 4, 1, 0, 4};
    int32_t mseg[] = {0, 4, 4, 3, 3, 2, 2, 1, 1, 0};
    mesh_flat m = flat(5, xy, 3, tri, 5, mseg);
    validate_report r;
    ck_assert_msg(run(&g, &m, 0, 0, &r), "%s", r.first_problem);
    pslg_free(&g);
}
END_TEST

START_TEST(test_quality_bounds) {
    pslg g;
    load("data/square.poly", &g);
    int32_t tri[] = {0, 1, 2, 0, 2, 3};
    mesh_flat m = flat(4, sq_xy, 2, tri, 4, sq_seg);
    validate_report r;
    ck_assert(!run(&g, &m, 50, 0, &r)); /* 45-degree angles, square corners: no exemption */
    ck_assert_int_eq(r.bad_angle, 2);
    ck_assert_int_eq(r.nexempt, 0);
    ck_assert(!run(&g, &m, 0, 0.4, &r));
    ck_assert_int_eq(r.bad_area, 2);
    ck_assert(run(&g, &m, 45, 0.5, &r)); /* bounds met exactly */
    pslg_free(&g);
}
END_TEST

/* The wedge's 10-degree corner forces small angles: exempt.  (a) the triangle at the corner;
 * (b) triangles spanning the two sides of the corner. */
START_TEST(test_wedge_exemption) {
    pslg g;
    load("data/wedge.poly", &g);
    double *w = g.xy;
    double xy[10] = {w[0], w[1], w[2], w[3], w[4], w[5]};
    int32_t tri[] = {0, 1, 2};
    int32_t seg[] = {0, 1, 1, 2, 2, 0};
    mesh_flat m = flat(3, xy, 1, tri, 3, seg);
    validate_report r;
    ck_assert_msg(run(&g, &m, 20, 0, &r), "%s", r.first_problem);
    ck_assert_int_eq(r.nexempt, 1);
    ck_assert_double_eq_tol(r.min_angle, 10, 1e-9);
    ck_assert_double_eq(r.min_angle_unforced, 180); /* nothing left to measure */
    /* split both long sides at their midpoints: (0,3,4) at the corner, (3,1,4) and (4,1,2)
     * span the corner's two sides */
    geom_midpoint(xy, xy + 2, xy + 6);
    geom_midpoint(xy, xy + 4, xy + 8);
    int32_t tri2[] = {0, 3, 4, 3, 1, 4, 4, 1, 2};
    int32_t seg2[] = {0, 3, 3, 1, 1, 2, 2, 4, 4, 0};
    m = flat(5, xy, 3, tri2, 5, seg2);
    int ok = run(&g, &m, 20, 0, &r);
    if (!ok) { /* the other diagonal of the quadrilateral 3-1-2-4 may be the Delaunay one */
        int32_t tri3[] = {0, 3, 4, 3, 1, 2, 3, 2, 4};
        memcpy(tri2, tri3, sizeof tri3);
        ok = run(&g, &m, 20, 0, &r);
    }
    ck_assert_msg(ok, "%s", r.first_problem);
    ck_assert_int_eq(r.nexempt, 3);
    ck_assert_int_eq(r.bad_angle, 0);
    pslg_free(&g);
}
END_TEST

/* n x n squares cut into 2 n^2 triangles: cocircular everywhere, valid, timed. */
START_TEST(test_grid_mesh) {
    const int n = 500;
    int nv = (n + 1) * (n + 1), nt = 2 * n * n, ns = 4 * n;
    double *xy = malloc(sizeof(double) * 2 * nv);
    int32_t *tri = malloc(sizeof(int32_t) * 3 * nt), *seg = malloc(sizeof(int32_t) * 2 * ns);
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            xy[2 * (j * (n + 1) + i)] = (double)i / n;
            xy[2 * (j * (n + 1) + i) + 1] = (double)j / n;
        }
    int t = 0, s = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            int32_t q[6] = {a, b, c, a, c, d};
            memcpy(tri + 3 * t, q, sizeof q);
            t += 2;
        }
    for (int i = 0; i < n; i++) {
        int32_t e[8] = {i,          i + 1,      n + i * (n + 1),   n + (i + 1) * (n + 1),
                        nv - 1 - i, nv - 2 - i, (n - i) * (n + 1), (n - i - 1) * (n + 1)};
        memcpy(seg + 2 * s, e, sizeof e);
        s += 4;
    }
    pslg g;
    load("data/square.poly", &g);
    mesh_flat m = flat(nv, xy, nt, tri, ns, seg);
    validate_report r;
    clock_t c0 = clock();
    int ok = run(&g, &m, 45, 1.0 / (n * n), &r);
    double sec = (double)(clock() - c0) / CLOCKS_PER_SEC;
    printf("grid %d triangles validated in %.3f s\n", nt, sec);
    ck_assert_msg(ok, "%s", r.first_problem);
    ck_assert_int_eq(r.ntris, nt);
    free(xy);
    free(tri);
    free(seg);
    pslg_free(&g);
}
END_TEST

int main(void) {
    geom_init();
    return ck_run(ck_suite("validate", 120,
                           CK_TESTS(test_square_ok, test_flipped, test_non_delaunay,
                                    test_interface_delaunay, test_missing_triangle, test_overlap,
                                    test_missing_segment_and_vertex, test_split_segment_chain,
                                    test_area_rounding_far, test_near_parallel_segments,
                                    test_quality_bounds, test_wedge_exemption, test_grid_mesh)));
}
