// ranks: 1 2 4
/* mpi_api: Check suite for libpcdm's parallel call (include/pcdm.h, mesher/api/api_par.c).
 *
 * The program owns MPI, as a library user would: main calls MPI_Init_thread and MPI_Finalize,
 * the library only duplicates the communicators it is given.
 *  - the whole mesh collected on a root of MPI_COMM_WORLD passes the validator with the bounds,
 *    and the size callback is honoured in its corner on every rank;
 *  - on the halves of a split MPI_COMM_WORLD (both meshing at once), every rank keeps its part:
 *    each global point number is owned by exactly one rank, triangle numbers follow by prefix
 *    sums, and the counts agree with the same call collecting on a root;
 *  - PBW through the same call gives a valid mesh (and refuses the size callback);
 *  - convex_hull (Triangle's -c), PCDM and PBW: segments that enclose nothing meshed over
 *    their hull, valid against the input enclosed by it;
 *  - threads: 2 worker threads per rank give the mesh of one (PCDM), and so does
 *    pcdm_triangulate with threads 2 on every rank (MPI_COMM_SELF); PBW refuses them;
 *  - bad input fails on every rank with the same code and message, and the next call works;
 *  - the parts' areas are checked against the domain's (a planted fault fails both calls);
 *  - crossing and overlapping segments (tests/inputs/cross.poly), PCDM and PBW: split as
 *    ./pcdm and ./pbw split them, the whole mesh valid against the input so prepared.
 * Results are reduced over ranks before asserting, so no rank waits in a collective that
 * another rank skipped.  Runs with CK_NOFORK (MPI does not survive fork).
 */
#include "api_check.h"
#include "check_run.h"
#include "pcdm/pcdm.h"
#include "pcdm_par.h"

#include <mpi.h>
#include <stdlib.h>

/* The mesh hash of ./pcdm --stats (pcdm_flat_hash: independent of the numbering) of a whole
 * mesh, in the caller's coordinates. */
static uint64_t mesh_hash(const pcdm_mesh *m) {
    mesh_flat f;
    memset(&f, 0, sizeof f);
    f.nverts = m->npoints;
    f.xy = m->points;
    f.ntris = m->ntriangles;
    f.tri = m->triangles;
    return pcdm_flat_hash(&f, 1);
}

static int all_true(int local, MPI_Comm c) {
    int g = 0;
    MPI_Allreduce(&local, &g, 1, MPI_INT, MPI_LAND, c);
    return g;
}

START_TEST(test_world_root) {
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 25;
    o.max_area = 0.3;
    o.unsuitable = small_near_origin; /* no context: it is called on every rank */
    o.root = size - 1;
    pcdm_mesh m;
    pcdm_status st;
    int rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &m, &st);
    ck_assert_msg(all_true(rc == PCDM_OK, MPI_COMM_WORLD), "code %d: %s", rc, st.message);
    int ok = 1;
    if (rank == size - 1) {
        double near, far;
        areas(&m, &near, &far);
        ok = valid(&in, &m, 25, 0.3) && near <= NEAR_AREA && m.ntriangles == m.nglobaltriangles;
    } else {
        ok = m.ntriangles == 0 && m.triangles == NULL && m.nglobaltriangles > 0;
    }
    pcdm_mesh_free(&m);
    ck_assert(all_true(ok, MPI_COMM_WORLD));
}
END_TEST

START_TEST(test_split_parts) {
    int wrank, wsize, rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &wrank);
    MPI_Comm_size(MPI_COMM_WORLD, &wsize);
    MPI_Comm half;
    MPI_Comm_split(MPI_COMM_WORLD, wrank % 2, wsize - wrank, &half); /* reversed order */
    MPI_Comm_rank(half, &rank);
    MPI_Comm_size(half, &size);
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    o.max_area = 0.05;
    pcdm_mesh m, w;
    pcdm_status st;
    int rc = pcdm_triangulate_par(half, &in, &o, &m, &st);
    ck_assert_msg(all_true(rc == PCDM_OK, MPI_COMM_WORLD), "code %d: %s", rc, st.message);
    /* every global number owned once: gather the owned numbers on the half's rank 0 */
    int ok = m.pointglobal && m.pointowned;
    long long mine = 0, first = 0, nt = m.ntriangles;
    MPI_Exscan(&nt, &first, 1, MPI_LONG_LONG, MPI_SUM, half);
    if (rank == 0) first = 0;
    ok = ok && first == m.trianglefirst;
    int64_t *gid = malloc(((size_t)m.npoints + 1) * sizeof(int64_t));
    for (int32_t i = 0; i < m.npoints; i++) {
        ok = ok && m.pointglobal[i] >= 0 && m.pointglobal[i] < m.nglobalpoints;
        if (m.pointowned[i]) gid[mine++] = m.pointglobal[i];
    }
    for (int32_t k = 0; k < 3 * m.ntriangles; k++)
        ok = ok && m.triangles[k] >= 0 && m.triangles[k] < m.npoints;
    int cnt = (int)mine, *cnts = malloc((size_t)size * sizeof(int)), *dsp = NULL;
    MPI_Gather(&cnt, 1, MPI_INT, cnts, 1, MPI_INT, 0, half);
    int64_t *all = NULL;
    long long tot = 0;
    if (rank == 0) {
        dsp = malloc((size_t)size * sizeof(int));
        for (int r = 0; r < size; r++) {
            dsp[r] = (int)tot;
            tot += cnts[r];
        }
        all = malloc(((size_t)tot + 1) * sizeof(int64_t));
    }
    MPI_Gatherv(gid, cnt, MPI_INT64_T, all, cnts, dsp, MPI_INT64_T, 0, half);
    if (rank == 0) { /* rank order lists the numbers in order: 0, 1, 2, ... */
        ok = ok && tot == m.nglobalpoints;
        for (long long i = 0; i < tot; i++)
            ok = ok && all[i] == i;
    }
    long long sumt = 0;
    MPI_Allreduce(&nt, &sumt, 1, MPI_LONG_LONG, MPI_SUM, half);
    ok = ok && sumt == m.nglobaltriangles;
    /* the same call collecting the whole mesh: the same counts, a valid mesh */
    o.root = 0;
    rc = pcdm_triangulate_par(half, &in, &o, &w, &st);
    ok = ok && rc == PCDM_OK && w.nglobalpoints == m.nglobalpoints &&
         w.nglobaltriangles == m.nglobaltriangles && w.nglobalsegments == m.nglobalsegments;
    if (rank == 0) ok = ok && valid(&in, &w, 20.7, 0.05);
    pcdm_mesh_free(&w);
    pcdm_mesh_free(&m);
    free(gid);
    free(cnts);
    free(dsp);
    free(all);
    MPI_Comm_free(&half);
    ck_assert(all_true(ok, MPI_COMM_WORLD));
}
END_TEST

/* PBW through the same call: the whole mesh on rank 0 passes the validator; the size callback
 * is refused (PBW has its own rules instance). */
START_TEST(test_pbw) {
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    o.method = PCDM_METHOD_PBW;
    o.max_area = 0.1;
    o.root = 0;
    pcdm_mesh m;
    pcdm_status st;
    int rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &m, &st);
    ck_assert_msg(all_true(rc == PCDM_OK, MPI_COMM_WORLD), "code %d: %s", rc, st.message);
    int ok = rank != 0 || valid(&in, &m, 20.7, 0.1);
    pcdm_mesh_free(&m);
    o.unsuitable = small_near_origin;
    rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &m, &st);
    ok = ok && rc == PCDM_EINVAL && strstr(st.message, "size callback") != NULL;
    ck_assert(all_true(ok, MPI_COMM_WORLD));
}
END_TEST

/* convex_hull through the parallel call, PCDM and PBW: the whole mesh on rank 0 covers the hull
 * minus the hole and passes the validator against the input enclosed by its hull. */
START_TEST(test_convex_hull) {
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    pcdm_input in = dangle();
    pcdm_options o;
    pcdm_options_default(&o);
    o.convex_hull = 1;
    o.max_area = 0.05;
    o.root = 0;
    int ok = 1;
    for (int method = PCDM_METHOD_PCDM; method <= PCDM_METHOD_PBW; method++) {
        o.method = method;
        pcdm_mesh m;
        pcdm_status st;
        int rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &m, &st);
        ck_assert_msg(all_true(rc == PCDM_OK, MPI_COMM_WORLD), "code %d: %s", rc, st.message);
        if (rank == 0) {
            int32_t ones, kept;
            double a = dangle_area(&m, &ones, &kept);
            ok = ok && fabs(a - DANGLE_AREA) <= 1e-12 * DANGLE_AREA && ones > 4 && kept > 3 &&
                 valid_hull(&in, &m, 20.7, 0.05, 1);
        }
        pcdm_mesh_free(&m);
    }
    ck_assert(all_true(ok, MPI_COMM_WORLD));
}
END_TEST

/* The arrays of a .poly as written (unchecked: the library prepares them); g keeps them. */
static pcdm_input poly_arrays(const char *path, pslg *g) {
    char err[512];
    pcdm_input in = {0};
    if (pslg_read(path, g, err, sizeof err) != 0) return in;
    in.npoints = g->nverts;
    in.points = g->xy;
    in.pointmarkers = g->vmarker;
    in.nsegments = g->nsegs;
    in.segments = g->seg;
    in.segmentmarkers = g->smarker;
    in.nholes = g->nholes;
    in.holes = g->holes;
    return in;
}

START_TEST(test_crossing) {
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    pslg g;
    pcdm_input in = poly_arrays("tests/inputs/cross.poly", &g);
    ck_assert_int_gt(in.nsegments, 0);
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 30;
    o.max_area = 0.5;
    o.root = 0;
    int ok = 1;
    for (int method = PCDM_METHOD_PCDM; method <= PCDM_METHOD_PBW; method++) {
        o.method = method;
        pcdm_mesh m;
        pcdm_status st;
        int rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &m, &st);
        ck_assert_msg(all_true(rc == PCDM_OK, MPI_COMM_WORLD), "method %d: code %d: %s", method, rc,
                      st.message);
        /* more points than given: the crossings' new points */
        if (rank == 0) ok = ok && m.npoints > in.npoints && valid(&in, &m, 30, 0.5);
        pcdm_mesh_free(&m);
    }
    pslg_free(&g);
    ck_assert(all_true(ok, MPI_COMM_WORLD));
}
END_TEST

/* threads: each rank refines its subdomains on 2 worker threads; the mesh is the one of one
 * thread (the same counts and the same points in the same order on the root), valid; PBW
 * refuses threads on every rank */
START_TEST(test_threads) {
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 28;
    o.max_area = 0.01;
    o.root = 0;
    o.subdomains = 8; /* the default count fits a small mesh, not below the ranks */
    pcdm_mesh one, two;
    pcdm_status st;
    int rc1 = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &one, &st);
    o.threads = 2;
    int rc2 = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &two, &st);
    ck_assert_msg(all_true(rc1 == PCDM_OK && rc2 == PCDM_OK, MPI_COMM_WORLD), "codes %d %d: %s",
                  rc1, rc2, st.message);
    int ok = one.nglobaltriangles == two.nglobaltriangles && one.nglobaltriangles > 0;
    if (rank == 0)
        ok = ok && valid(&in, &two, 28, 0.01) && one.npoints == two.npoints &&
             memcmp(one.points, two.points, 2 * sizeof(double) * (size_t)one.npoints) == 0;
    /* pcdm_triangulate with threads 2 (MPI initialised: on MPI_COMM_SELF, every rank at once):
     * the parallel call's whole mesh, bit for bit */
    pcdm_mesh self;
    pcdm_status sst;
    int rc3 = pcdm_triangulate(&in, &o, &self, &sst);
    ck_assert_msg(all_true(rc3 == PCDM_OK, MPI_COMM_WORLD), "pcdm_triangulate threads 2: %s",
                  sst.message);
    int same = self.nglobaltriangles == one.nglobaltriangles;
    if (rank == 0) /* on more ranks the numbering follows the ranks: compare hashes */
        same = same && self.npoints == one.npoints && self.ntriangles == one.ntriangles &&
               mesh_hash(&self) == mesh_hash(&one) &&
               (size > 1 ||
                (!memcmp(self.points, one.points, 2 * sizeof(double) * (size_t)one.npoints) &&
                 !memcmp(self.triangles, one.triangles,
                         3 * sizeof(int32_t) * (size_t)one.ntriangles)));
    pcdm_mesh_free(&self);
    pcdm_mesh_free(&one);
    pcdm_mesh_free(&two);
    ck_assert_msg(all_true(ok, MPI_COMM_WORLD), "threads 2 differs from threads 1");
    ck_assert_msg(all_true(same, MPI_COMM_WORLD),
                  "pcdm_triangulate threads 2 differs from pcdm_triangulate_par");
    o.method = PCDM_METHOD_PBW;
    int rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &two, &st);
    ck_assert(all_true(rc == PCDM_EINVAL && strstr(st.message, "threads") != NULL, MPI_COMM_WORLD));
}
END_TEST

START_TEST(test_errors_agree) {
    pcdm_input in = plate();
    int32_t bad[16];
    memcpy(bad, plate_segs, sizeof bad);
    bad[0] = -1;
    in.segments = bad;
    pcdm_mesh m;
    pcdm_status st;
    int rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, NULL, &m, &st);
    int ok = rc == PCDM_EINPUT && strstr(st.message, "segment 0: point -1") != NULL &&
             m.triangles == NULL;
    pcdm_options o;
    pcdm_options_default(&o);
    o.root = 1000;
    in = plate();
    rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &m, &st);
    ok = ok && rc == PCDM_EINVAL && strstr(st.message, "root 1000") != NULL;
    o.root = -1; /* and the runtime starts again after the failures */
    int size;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    o.subdomains = 2 * size;
    rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &m, &st);
    ok = ok && rc == PCDM_OK && m.nglobaltriangles > 0;
    pcdm_mesh_free(&m);
    ck_assert(all_true(ok, MPI_COMM_WORLD));
}
END_TEST

/* The parallel call and the threaded one check that the parts' areas sum to the domain's, as
 * the programs do: with the test-only fault PCDM_TEST_AREA_SKEW (each rank's area taken 1e-6
 * too large) both fail with PCDM_EMESH saying so on every rank; without it they mesh. */
START_TEST(test_area_checked) {
    pcdm_input in = plate();
    pcdm_mesh m;
    pcdm_status st;
    pcdm_options o;
    pcdm_options_default(&o);
    setenv("PCDM_TEST_AREA_SKEW", "1", 1);
    int rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &m, &st);
    int ok = rc == PCDM_EMESH && strstr(st.message, "areas sum to") && m.triangles == NULL;
    o.threads = 2;
    rc = pcdm_triangulate(&in, &o, &m, &st);
    ok = ok && rc == PCDM_EMESH && strstr(st.message, "areas sum to") && m.triangles == NULL;
    unsetenv("PCDM_TEST_AREA_SKEW");
    rc = pcdm_triangulate(&in, &o, &m, &st);
    ok = ok && rc == PCDM_OK && m.ntriangles > 0;
    pcdm_mesh_free(&m);
    o.threads = 0;
    rc = pcdm_triangulate_par(MPI_COMM_WORLD, &in, &o, &m, &st);
    ok = ok && rc == PCDM_OK && m.nglobaltriangles > 0;
    pcdm_mesh_free(&m);
    ck_assert(all_true(ok, MPI_COMM_WORLD));
}
END_TEST

int main(int argc, char **argv) {
    int provided;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    int rc = ck_run_mpi(
        ck_suite("mpi_api", 0,
                 CK_TESTS(test_world_root, test_split_parts, test_pbw, test_convex_hull,
                          test_crossing, test_threads, test_errors_agree, test_area_checked)),
        MPI_COMM_WORLD);
    MPI_Finalize();
    return rc;
}
