/* unit_mesh_regions: the input's regions (Triangle's regional attributes and area constraints).
 *
 * tests/inputs/regions.poly is the square [0,4]^2 cut into four vertical strips by segments at
 * x = 1, 2, 3, with a square hole in strip 2; strip 3 is marked twice (the later point wins),
 * strip 4 not at all, and two more region points lie on a segment and in the hole (they mark
 * nothing).  The mesher's labels (mesh_set_regions) must give every triangle its strip's region,
 * on the CDT and after refinement (new triangles inherit), and agree with the validator's own
 * labelling from the PSLG alone (pslg_regions); refinement must honour each region's area bound
 * (the smaller of it and the global one); interface (artificial) segments are crossed; the flat
 * forms carry the attributes; the writers put them into .ele and the holes and regions into the
 * .poly; the validator rejects a wrong attribute.  Run from the repository root.
 */
#include "check/validate.h"
#include "check_run.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "io/meshio.h"
#include "seq/mesh.h"
#include "seq/rules.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void load(const char *path, pslg *g) {
    char err[1024];
    ck_assert_msg(pslg_read(path, g, err, sizeof err) == 0, "%s", err);
    ck_assert_msg(pslg_check(g, err, sizeof err) == 0, "%s", err);
}

static void build(mesh *m, const pslg *g) {
    char err[1024];
    mesh_init(m);
    ck_assert_msg(mesh_build_cdt(m, g, NULL, err, sizeof err) == 0, "%s", err);
}

static void centroid(const mesh *m, int32_t t, double c[2]) {
    const double *a = mesh_vertex_xy(m, m->tv[3 * t]), *b = mesh_vertex_xy(m, m->tv[3 * t + 1]),
                 *d = mesh_vertex_xy(m, m->tv[3 * t + 2]);
    c[0] = (a[0] + b[0] + d[0]) / 3;
    c[1] = (a[1] + b[1] + d[1]) / 3;
}

/* The region regions.poly gives the strip containing x: 0, 1, 3 (the later of two), none. */
static int32_t strip_region(double x) {
    return x < 1 ? 0 : x < 2 ? 1 : x < 3 ? 3 : -1;
}

/* Every live triangle has its strip's region, and the validator's lookup agrees. */
static void check_strips(const mesh *m, const pslg *g) {
    pslg_regions *R = pslg_regions_build(g);
    ck_assert_ptr_nonnull(R);
    int32_t n = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        double c[2];
        centroid(m, t, c);
        ck_assert_int_eq(m->treg[t], strip_region(c[0]));
        ck_assert_int_eq(pslg_region_at(R, c), strip_region(c[0]));
        n++;
    }
    ck_assert_int_gt(n, 10);
    pslg_regions_free(R);
}

START_TEST(test_labels_cdt_and_refined) {
    pslg g;
    load("tests/inputs/regions.poly", &g);
    mesh m;
    build(&m, &g);
    mesh_set_regions(&m, &g, 1, m.nseg);
    ck_assert_int_eq(m.nregion, 6);
    check_strips(&m, &g);
    mesh_quality q = {20, 0, -1, 1, 0};
    mesh_set_quality(&m, &q);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
    ck_assert_int_eq(mesh_count_unmet(&m, NULL), 0);
    check_strips(&m, &g);
    /* each region's bound holds; strip 4 has none (and no global bound): it stays coarse */
    const double bound[4] = {0.02, 0.1, 0.05, INFINITY};
    double big4 = 0;
    for (int32_t t = 0; t < m.nt; t++) {
        if (!mesh_tri_alive(&m, t)) continue;
        double c[2];
        centroid(&m, t, c);
        int s = c[0] < 1 ? 0 : c[0] < 2 ? 1 : c[0] < 3 ? 2 : 3;
        double ar = geom_area(mesh_vertex_xy(&m, m.tv[3 * t]), mesh_vertex_xy(&m, m.tv[3 * t + 1]),
                              mesh_vertex_xy(&m, m.tv[3 * t + 2]));
        ck_assert_msg(ar <= bound[s] * (1 + 1e-9), "strip %d triangle area %g", s + 1, ar);
        if (s == 3 && ar > big4) big4 = ar;
    }
    ck_assert_double_gt(big4, 0.1);
    mesh_free(&m);
    pslg_free(&g);
}
END_TEST

START_TEST(test_global_bound_wins_when_smaller) {
    ck_assert_double_eq(mesh_rules_area_bound(0, 0), 0);
    ck_assert_double_eq(mesh_rules_area_bound(0.5, 0), 0.5);
    ck_assert_double_eq(mesh_rules_area_bound(0, 0.25), 0.25);
    ck_assert_double_eq(mesh_rules_area_bound(0.5, 0.25), 0.25);
    ck_assert_double_eq(mesh_rules_area_bound(0.1, 0.25), 0.1);
    ck_assert_double_eq(mesh_rules_area_bound(0.1, -1), 0.1);
    pslg g;
    load("tests/inputs/regions.poly", &g);
    mesh m;
    build(&m, &g);
    mesh_set_regions(&m, &g, 1, m.nseg);
    mesh_quality q = {0, 0.03, -1, 1, 0};
    mesh_set_quality(&m, &q);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
    for (int32_t t = 0; t < m.nt; t++) {
        if (!mesh_tri_alive(&m, t)) continue;
        double c[2];
        centroid(&m, t, c);
        double ar = geom_area(mesh_vertex_xy(&m, m.tv[3 * t]), mesh_vertex_xy(&m, m.tv[3 * t + 1]),
                              mesh_vertex_xy(&m, m.tv[3 * t + 2]));
        ck_assert_double_le(ar, (c[0] < 1 ? 0.02 : 0.03) * (1 + 1e-9));
    }
    mesh_free(&m);
    pslg_free(&g);
}
END_TEST

/* Segments from nreal on are artificial (a decomposition's interfaces): a region crosses them;
 * the same segment counted as real separates two regions. */
START_TEST(test_interface_segments_crossed) {
    static const double xy[] = {0, 0, 2, 0, 4, 0, 4, 4, 2, 4, 0, 4};
    static const int32_t seg[] = {0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 0, 1, 4};
    pslg g;
    memset(&g, 0, sizeof g);
    g.nverts = 6;
    g.xy = malloc(sizeof xy);
    memcpy(g.xy, xy, sizeof xy);
    g.nsegs = 7;
    g.seg = malloc(sizeof seg);
    memcpy(g.seg, seg, sizeof seg);
    g.nregions = 1;
    g.regions = malloc(4 * sizeof(double));
    g.regions[0] = 1, g.regions[1] = 1, g.regions[2] = 7, g.regions[3] = -1;
    char err[256];
    ck_assert_msg(pslg_check(&g, err, sizeof err) == 0, "%s", err);
    for (int artificial = 0; artificial < 2; artificial++) {
        mesh m;
        build(&m, &g);
        mesh_set_regions(&m, &g, 0, artificial ? 6 : 7);
        for (int32_t t = 0; t < m.nt; t++) {
            if (!mesh_tri_alive(&m, t)) continue;
            double c[2];
            centroid(&m, t, c);
            ck_assert_int_eq(m.treg[t], artificial || c[0] < 2 ? 0 : -1);
        }
        mesh_flat f;
        ck_assert_int_eq(mesh_to_flat(&m, &f), 0);
        ck_assert_ptr_nonnull(f.tattr);
        for (int32_t t = 0; t < f.ntris; t++) {
            const double *a = f.xy + 2 * f.tri[3 * t];
            double want =
                artificial || a[0] + f.xy[2 * f.tri[3 * t + 1]] + f.xy[2 * f.tri[3 * t + 2]] < 6
                    ? 7
                    : 0;
            ck_assert_double_eq(f.tattr[t], want);
        }
        mesh_flat_free(&f);
        mesh_free(&m);
    }
    pslg_free(&g);
}
END_TEST

/* mesh_to_flat and mesh_take_flat give the same attributes; the writers put them in .ele (and
 * the holes and regions in .poly); reading back gives them again; the validator checks them. */
START_TEST(test_flat_write_validate) {
    pslg g;
    load("tests/inputs/regions.poly", &g);
    mesh m;
    build(&m, &g);
    mesh_set_regions(&m, &g, 1, m.nseg);
    mesh_quality q = {20, 0, -1, 1, 0};
    mesh_set_quality(&m, &q);
    mesh_refine(&m);
    mesh_flat a, b;
    ck_assert_int_eq(mesh_to_flat(&m, &a), 0);
    mesh_take_flat(&m, &b, NULL);
    ck_assert_int_eq(a.ntris, b.ntris);
    ck_assert_ptr_nonnull(b.tattr);
    for (int32_t t = 0; t < a.ntris; t++)
        ck_assert_double_eq(a.tattr[t], b.tattr[t]);
    validate_opts vo = {20, 0, 0, 0, 1, 1};
    validate_report r;
    ck_assert_msg(mesh_validate(&g, &a, &vo, &r), "%s", r.first_problem);
    /* files */
    char dir[] = "/tmp/unit_regions_XXXXXX", prefix[64], err[512];
    ck_assert_ptr_nonnull(mkdtemp(dir));
    snprintf(prefix, sizeof prefix, "%s/m", dir);
    ck_assert_int_eq(meshio_flat_domain(&a, &g), 0);
    ck_assert_msg(meshio_write_triangle(&a, prefix, err, sizeof err) == 0, "%s", err);
    mesh_flat c;
    ck_assert_msg(meshio_read_triangle(prefix, &c, err, sizeof err) == 0, "%s", err);
    ck_assert_ptr_nonnull(c.tattr);
    for (int32_t t = 0; t < a.ntris; t++)
        ck_assert_double_eq(a.tattr[t], c.tattr[t]);
    ck_assert_int_eq(c.nholes, g.nholes); /* read back from the .poly too */
    ck_assert_int_eq(c.nregions, g.nregions);
    ck_assert_msg(mesh_validate(&g, &c, &vo, &r), "%s", r.first_problem);
    char poly[96];
    snprintf(poly, sizeof poly, "%s.poly", prefix);
    pslg h;
    load(poly, &h);
    ck_assert_int_eq(h.nholes, g.nholes);
    ck_assert_int_eq(h.nregions, g.nregions);
    for (int32_t i = 0; i < 4 * g.nregions; i++)
        ck_assert_double_eq(h.regions[i], g.regions[i]);
    ck_assert_double_eq(pslg_domain_area(&h), pslg_domain_area(&g));
    pslg_free(&h);
    /* a wrong attribute, and no attributes at all, are caught */
    c.tattr[c.ntris / 2] += 1;
    ck_assert(!mesh_validate(&g, &c, &vo, &r));
    ck_assert_int_eq(r.bad_region, 1);
    free(c.tattr);
    c.tattr = NULL;
    ck_assert(!mesh_validate(&g, &c, &vo, &r));
    ck_assert_int_gt(r.bad_region, 0);
    mesh_flat_free(&c);
    const char *ext[] = {"node", "ele", "poly"};
    for (int i = 0; i < 3; i++) {
        char p[96];
        snprintf(p, sizeof p, "%s.%s", prefix, ext[i]);
        unlink(p);
    }
    rmdir(dir);
    mesh_flat_free(&a);
    mesh_flat_free(&b);
    pslg_free(&g);
}
END_TEST

/* The validator's per-region area check: a coarse mesh made without the region bounds fails it,
 * with only the global bound it passes. */
START_TEST(test_validator_region_area) {
    pslg g;
    load("tests/inputs/regions.poly", &g);
    mesh m;
    build(&m, &g);
    mesh_quality q = {20, 0, -1, 1, 0};
    mesh_set_quality(&m, &q);
    mesh_refine(&m);
    mesh_flat f;
    ck_assert_int_eq(mesh_to_flat(&m, &f), 0);
    ck_assert_ptr_null(f.tattr);
    validate_opts plain = {20, 0, 0, 0, 0, 0}, areas = {20, 0, 0, 0, 0, 1};
    validate_report r;
    ck_assert_msg(mesh_validate(&g, &f, &plain, &r), "%s", r.first_problem);
    ck_assert(!mesh_validate(&g, &f, &areas, &r));
    ck_assert_int_gt(r.bad_area, 0);
    mesh_flat_free(&f);
    mesh_free(&m);
    pslg_free(&g);
}
END_TEST

int main(void) {
    geom_init();
    return ck_run(
        ck_suite("mesh_regions", 60,
                 CK_TESTS(test_labels_cdt_and_refined, test_global_bound_wins_when_smaller,
                          test_interface_segments_crossed, test_flat_write_validate,
                          test_validator_region_area)));
}
