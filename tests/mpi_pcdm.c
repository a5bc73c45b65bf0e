// ranks: 1 2 4 8
/* mpi_pcdm: Check suite for the PCDM layer under MPI (mesher/par/par.c, mesher/pcdm/pcdm.c).
 *
 *  - par_fail_any: agreement on failure from any one rank;
 *  - par_number: pieces sharing vertices (bit-equal coordinates) get one number per point,
 *    input vertices keep theirs, each rank's owned vertices follow the lower ranks', and a
 *    subsegment listed by two ranks is written once; artificial ones not at all;
 *  - the whole pipeline on data/lake.poly: decomposition, per-rank refinement with split RSRs,
 *    numbering and the distributed check (par_check_parts, interface edges required to be
 *    locally Delaunay); every split request names a subsegment that exists on the receiver.
 * Results are reduced over ranks before asserting, so no rank waits in a collective that
 * another rank skipped.  Runs with CK_NOFORK (MPI does not survive fork); run from the
 * repository root (tests/run.sh does).
 */
#include "check_run.h"
#include "geom/geom.h"
#include "par/par.h"
#include "par/pout.h"
#include "pcdm/pcdm.h"
#include "rt.h"
#include "run/run.h"

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
START_TEST(test_number) {
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
    uint8_t art[4] = {0, 0, (uint8_t)(rank < size - 1), (uint8_t)(rank > 0)};
    par_numbering num;
    char err[256];
    ck_assert_int_eq(par_number(&f, &in, art, &num, err, sizeof err), 0);
    ck_assert_int_eq(num.nverts, 2 * (size + 1));
    ck_assert_int_eq(num.ntris, 2 * size);
    ck_assert_int_eq(num.tfirst, 2 * rank);
    ck_assert_int_eq(num.nsegs, 2 * size + 2); /* bottoms, tops, the two outer sides */
    /* owned vertices follow the lower ranks' */
    int64_t end = num.vfirst + num.nowned, prev_end = 4;
    MPI_Status stt;
    if (rank > 0) MPI_Recv(&prev_end, 1, MPI_INT64_T, rank - 1, 7, rt_app_comm(), &stt);
    if (rank < size - 1) MPI_Send(&end, 1, MPI_INT64_T, rank + 1, 7, rt_app_comm());
    ck_assert_int_eq(num.vfirst, prev_end);
    /* the same point has the same number everywhere: x = k, y = j gets a number; gather them */
    int64_t mine[4 * 3], *all = malloc((size_t)size * sizeof mine);
    for (int v = 0; v < 4; v++) {
        mine[3 * v] = (int64_t)pts[v][0];
        mine[3 * v + 1] = (int64_t)pts[v][1];
        mine[3 * v + 2] = num.gid[v];
        for (int k = 0; k < 4; k++)
            if (pts[v][0] == corners[2 * k] && pts[v][1] == corners[2 * k + 1])
                ck_assert_int_eq(num.gid[v], k); /* input vertices keep their numbers */
    }
    MPI_Allgather(mine, 12, MPI_INT64_T, all, 12, MPI_INT64_T, rt_app_comm());
    int64_t *byxy = malloc(2 * ((size_t)size + 1) * sizeof(int64_t));
    for (int i = 0; i < 2 * (size + 1); i++)
        byxy[i] = -1;
    for (int i = 0; i < 4 * size; i++) {
        int64_t x = all[3 * i], y = all[3 * i + 1], id = all[3 * i + 2];
        ck_assert(id >= 0 && id < num.nverts);
        if (byxy[2 * x + y] < 0) byxy[2 * x + y] = id;
        ck_assert_int_eq(byxy[2 * x + y], id);
    }
    for (int i = 0; i < 2 * (size + 1); i++) /* distinct points, distinct numbers */
        for (int j = 0; j < i; j++)
            ck_assert(byxy[i] != byxy[j]);
    free(all);
    free(byxy);
    par_numbering_free(&num);
    int ok = 1;
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
    run_job j;
    run_job_init(&j, RUN_PCDM, &o);
    ck_assert_int_eq(run_par_load(&j, &in, &d), 0);
    run_job_free(&j);
    pcdm_part p;
    char err[512];
    int rc = pcdm_part_build(&p, &d, rank, err, sizeof err);
    ck_assert_msg(all_true(rc == 0), "build failed: %s", rc ? err : "(other rank)");
    mesh_quality q;
    memset(&q, 0, sizeof q); /* diametral circles (lens = 0): interfaces end up Delaunay */
    q.min_angle = bounds_refine_angle(30);
    q.max_area = 0.001;
    q.max_steiner = -1;
    q.offcenter = 1;
    pcdm_part_refine(&p, &q, 100);
    unsigned long long nf = p.split_notfound, nf_all = 0;
    MPI_Allreduce(&nf, &nf_all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, rt_comm());
    ck_assert_uint_eq(nf_all, 0);
    mesh_flat f;
    ck_assert_int_eq(pcdm_part_flat(&p, &f), 0);
    uint8_t *art = pcdm_part_artificial(&p);
    pcdm_part_free(&p);
    par_numbering num;
    ck_assert_int_eq(par_number(&f, &in, art, &num, err, sizeof err), 0);
    validate_report r;
    int ok = par_check_parts(&o, &in, &f, &num, 0, &r);
    if (!ok && rank == 0) fprintf(stderr, "mpi_pcdm: %s\n", r.first_problem);
    ck_assert_int_eq(all_true(ok), 1);
    ck_assert_int_eq(r.ntris, num.ntris);
    par_numbering_free(&num);
    mesh_flat_free(&f);
    free(art);
    pcdm_decomp_free(&d);
    pslg_free(&in);
}
END_TEST

int main(int argc, char **argv) {
    if (rt_init(&argc, &argv, NULL) != RT_OK) return 1;
    if (pcdm_register() != 0) return 1;
    geom_init();
    int rc = ck_run_mpi(
        ck_suite("mpi_pcdm", 0, CK_TESTS(test_fail_any, test_number, test_pipeline_lake)),
        rt_app_comm());
    rt_finalize();
    return rc;
}
