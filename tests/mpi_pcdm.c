// ranks: 1 2 4 8
/* mpi_pcdm: Check suite for the PCDM layer under MPI (mesher/par/par.c, mesher/pcdm/pcdm.c).
 *
 *  - par_fail_any: agreement on failure from any one rank;
 *  - par_gather_mesh: pieces sharing vertices (bit-equal coordinates) and listing the same
 *    interface subsegment on both sides merge into one conforming mesh, input vertices first;
 *  - the whole pipeline on data/lake.poly: decomposition, per-rank refinement with split RSRs,
 *    gather, and the validator with interface edges required to be locally Delaunay; every
 *    split request names a subsegment that exists on the receiver (none "not found").
 * Results are reduced over ranks before asserting, so no rank waits in a collective that
 * another rank skipped.  Runs with CK_NOFORK (MPI does not survive fork); run from the
 * repository root (tests/run.sh does).
 */
#include "geom/geom.h"
#include "par/par.h"
#include "pcdm/pcdm.h"
#include "rt.h"

#include <check.h>
#include <stdlib.h>
#include <string.h>

static int all_true(int local) {
    int g = 0;
    MPI_Allreduce(&local, &g, 1, MPI_INT, MPI_LAND, rt_comm());
    return g;
}

START_TEST(test_fail_any) {
    int rank = rt_rank(), size = rt_size();
    ck_assert_int_eq(par_fail_any(0, "unused"), 0);
    int r = par_fail_any(rank == size - 1, "pcdm-test: expected failure message (ignore)");
    ck_assert_int_eq(all_true(r == 1), 1);
}
END_TEST

/* Rank r contributes the unit square [r, r+1] x [0, 1] as two triangles, its left and right
 * sides as interface subsegments (the outer ones as boundary), its bottom and top as boundary.
 * Local numbering is deliberately rotated so the merge must go by coordinates. */
START_TEST(test_gather) {
    int rank = rt_rank(), size = rt_size();
    double x0 = rank, x1 = rank + 1;
    double pts[4][2] = {{x1, 1}, {x0, 0}, {x1, 0}, {x0, 1}}; /* local ids 0..3 */
    mesh_flat f;
    memset(&f, 0, sizeof f);
    f.nverts = 4;
    f.xy = malloc(8 * sizeof(double));
    f.vmarker = calloc(4, sizeof(int32_t));
    memcpy(f.xy, pts, sizeof pts);
    f.ntris = 2;
    int32_t tri[6] = {1, 2, 0, 1, 0, 3};
    f.tri = malloc(sizeof tri);
    memcpy(f.tri, tri, sizeof tri);
    f.trank = malloc(2 * sizeof(int32_t));
    f.trank[0] = f.trank[1] = rank;
    f.nsegs = 4;
    int32_t seg[8] = {1, 2, 0, 3, 2, 0, 3, 1}; /* bottom, top, right, left */
    f.seg = malloc(sizeof seg);
    memcpy(f.seg, seg, sizeof seg);
    f.smarker = calloc(4, sizeof(int32_t));
    f.sinterface = calloc(4, sizeof(int32_t));
    f.sinterface[2] = rank < size - 1;
    f.sinterface[3] = rank > 0;
    /* the input: the four corners of [0, P] x [0, 1] */
    pslg in;
    memset(&in, 0, sizeof in);
    double corners[8] = {0, 0, size, 0, size, 1, 0, 1};
    in.nverts = 4;
    in.xy = corners;
    mesh_flat g;
    ck_assert_int_eq(par_gather_mesh(&f, &in, &g), 0);
    int ok = 1;
    if (rank == 0) {
        ck_assert_int_eq(g.nverts, 2 * (size + 1));
        ck_assert_int_eq(g.ntris, 2 * size);
        ck_assert_int_eq(g.nsegs, 2 * size + size + 1); /* bottoms, tops, verticals */
        for (int v = 0; v < 4; v++) {
            ck_assert_double_eq(g.xy[2 * v], corners[2 * v]);
            ck_assert_double_eq(g.xy[2 * v + 1], corners[2 * v + 1]);
        }
        int niface = 0;
        for (int s = 0; s < g.nsegs; s++)
            niface += g.sinterface[s];
        ck_assert_int_eq(niface, size - 1);
        for (int t = 0; t < g.ntris; t++) {
            const double *a = g.xy + 2 * g.tri[3 * t], *b = g.xy + 2 * g.tri[3 * t + 1],
                         *c = g.xy + 2 * g.tri[3 * t + 2];
            ck_assert_msg(geom_orient2d(a, b, c) > 0, "triangle %d not ccw", t);
            ck_assert_int_eq(g.trank[t], t / 2);
        }
        mesh_flat_free(&g);
    }
    mesh_flat_free(&f);
    ck_assert_int_eq(all_true(ok), 1);
}
END_TEST

START_TEST(test_pipeline_lake) {
    int rank = rt_rank();
    par_opts o;
    memset(&o, 0, sizeof o);
    o.prog = "pcdm";
    o.input = "data/lake.poly";
    o.min_angle = 30;
    o.max_area = 0.001;
    o.max_steiner = -1;
    o.imbalance = 1;
    pslg in;
    pcdm_decomp d;
    ck_assert_int_eq(par_load(&o, &in, &d), 0);
    pcdm_part p;
    char err[512];
    int rc = pcdm_part_build(&p, &d, rank, err, sizeof err);
    ck_assert_msg(all_true(rc == 0), "build failed: %s", rc ? err : "(other rank)");
    mesh_quality q;
    memset(&q, 0, sizeof q); /* diametral circles (lens = 0): interfaces end up Delaunay */
    q.min_angle = 30 * (1 + 1e-9) + 1e-12;
    q.max_area = 0.001;
    q.max_steiner = -1;
    q.offcenter = 1;
    pcdm_part_refine(&p, &q, 100);
    unsigned long long nf = p.split_notfound, nf_all = 0;
    MPI_Allreduce(&nf, &nf_all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, rt_comm());
    ck_assert_uint_eq(nf_all, 0);
    mesh_flat f, g;
    ck_assert_int_eq(pcdm_part_flat(&p, &f), 0);
    pcdm_part_free(&p);
    ck_assert_int_eq(par_gather_mesh(&f, &in, &g), 0);
    mesh_flat_free(&f);
    int ok = 1;
    if (rank == 0) {
        validate_report r;
        ok = par_validate(&o, &in, &g, &r);
        if (!ok) fprintf(stderr, "mpi_pcdm: %s\n", r.first_problem);
        mesh_flat_free(&g);
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, rt_comm());
    ck_assert_int_eq(ok, 1);
    pcdm_decomp_free(&d);
    pslg_free(&in);
}
END_TEST

int main(int argc, char **argv) {
    if (rt_init(&argc, &argv, NULL) != RT_OK) return 1;
    if (pcdm_register() != 0) return 1;
    geom_init();
    Suite *s = suite_create("mpi_pcdm");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_fail_any);
    tcase_add_test(tc, test_gather);
    tcase_add_test(tc, test_pipeline_lake);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_set_fork_status(sr, CK_NOFORK);
    srunner_run_all(sr, rt_rank() == 0 ? CK_NORMAL : CK_SILENT);
    int nf = srunner_ntests_failed(sr);
    srunner_free(sr);
    int any = 0;
    MPI_Allreduce(&nf, &any, 1, MPI_INT, MPI_MAX, rt_comm());
    rt_finalize();
    return any ? 1 : 0;
}
