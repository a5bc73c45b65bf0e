/* thr_api: Check suite for pcdm_triangulate with worker threads in libpcdm_threads (no MPI: the
 * parallel stack built against the one-process stand-in runtime/mpi1).
 *
 *  - threads 1, 2 and 3 make one mesh, bit for bit (points, markers, triangles, segments), and it
 *    passes the validator with the bounds; threads 0 is the sequential mesher (another mesh,
 *    also valid);
 *  - bad input (NaN, a segment out of range or from a point to itself, too few points, all
 *    points on a line), bad options (lenses, regions, negative threads) and bounds that cannot
 *    be met come back as a code and a message -- the process lives on (each test runs in a
 *    fork: an abort or an exit would fail it) -- and the next call meshes;
 *  - the Steiner limit returns PCDM_ESTEINER with a valid mesh;
 *  - two host threads calling at once both get the mesh (the runtime is taken in turn).
 *
 * `thr_api --compare POLY PREFIX Q A T` is no test of its own: it meshes POLY at -q Q -a A on T
 * threads and compares the mesh with ./pcdm's files PREFIX.node/.ele/.poly (tests/
 * t_threads_lib.sh runs it), exit 0 iff they are the same mesh.
 */
#pragma GCC diagnostic ignored "-Wunused-function" /* api_check.h's helpers we do not use */
#include "api_check.h"
#include "check_run.h"
#include "geom/geom.h"
#include "io/meshio.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int same_mesh(const pcdm_mesh *a, const pcdm_mesh *b) {
    return a->npoints == b->npoints && a->ntriangles == b->ntriangles &&
           a->nsegments == b->nsegments &&
           !memcmp(a->points, b->points, 2 * (size_t)a->npoints * sizeof(double)) &&
           !memcmp(a->pointmarkers, b->pointmarkers, (size_t)a->npoints * sizeof(int32_t)) &&
           !memcmp(a->triangles, b->triangles, 3 * (size_t)a->ntriangles * sizeof(int32_t)) &&
           !memcmp(a->segments, b->segments, 2 * (size_t)a->nsegments * sizeof(int32_t)) &&
           !memcmp(a->segmentmarkers, b->segmentmarkers, (size_t)a->nsegments * sizeof(int32_t));
}

static int mesh_threads(const pcdm_input *in, int threads, double q, double a, pcdm_mesh *m,
                        pcdm_status *st) {
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = q;
    o.max_area = a;
    o.threads = threads;
    return pcdm_triangulate(in, &o, m, st);
}

START_TEST(test_same_any_threads) {
    pcdm_input in = plate();
    pcdm_mesh m[4];
    pcdm_status st;
    for (int t = 0; t < 4; t++) {
        ck_assert_msg(mesh_threads(&in, t, 30, 0.002, &m[t], &st) == PCDM_OK, "threads %d: %s", t,
                      st.message);
        ck_assert_ptr_null(m[t].pointglobal);
        ck_assert_int_eq((int)m[t].nglobaltriangles, m[t].ntriangles);
        ck_assert_msg(valid(&in, &m[t], 30, 0.002), "threads %d: the mesh fails the validator", t);
    }
    printf("thr_api: plate -q 30 -a 0.002: threads 0: %d triangles; threads 1-3: %d\n",
           m[0].ntriangles, m[1].ntriangles);
    ck_assert_msg(same_mesh(&m[1], &m[2]), "threads 2 differs from threads 1");
    ck_assert_msg(same_mesh(&m[1], &m[3]), "threads 3 differs from threads 1");
    ck_assert_msg(!same_mesh(&m[0], &m[1]), "threads 1 is the sequential mesh (no subdomains?)");
    for (int t = 0; t < 4; t++)
        pcdm_mesh_free(&m[t]);
}
END_TEST

/* Every failure is a return; the library still meshes afterwards (the runtime was finalised). */
START_TEST(test_errors_return) {
    pcdm_mesh m;
    pcdm_status st;
    pcdm_options o;
    pcdm_options_default(&o);
    o.threads = 2;
    double pts[16];
    memcpy(pts, plate_pts, sizeof pts);
    pts[5] = NAN;
    pcdm_input in = plate();
    in.points = pts;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EINPUT);
    ck_assert_ptr_nonnull(strstr(st.message, "non-finite"));
    ck_assert_ptr_null(m.triangles);
    int32_t segs[16];
    memcpy(segs, plate_segs, sizeof segs);
    segs[3] = 99;
    in = plate();
    in.segments = segs;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EINPUT);
    ck_assert_ptr_nonnull(strstr(st.message, "out of range"));
    segs[3] = segs[2]; /* a segment from a point to itself */
    ck_assert_int_ne(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    printf("thr_api: degenerate segment: %d: %s\n", st.code, st.message);
    ck_assert_str_ne(st.message, "");
    const double line[] = {0, 0, 1, 1, 2, 2, 3, 3};
    pcdm_input col = {.npoints = 4, .points = line};
    ck_assert_int_eq(pcdm_triangulate(&col, &o, &m, &st), PCDM_EINPUT);
    printf("thr_api: collinear points: %s\n", st.message);
    pcdm_input few = {.npoints = 2, .points = line};
    ck_assert_int_eq(pcdm_triangulate(&few, &o, &m, &st), PCDM_EINPUT);
    pcdm_input none = {0};
    ck_assert_int_eq(pcdm_triangulate(&none, &o, &m, &st), PCDM_EINPUT);
    in = plate();
    o.lenses = 1;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EINVAL);
    ck_assert_ptr_nonnull(strstr(st.message, "lenses"));
    o.lenses = 0;
    o.region_attributes = 1;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EINVAL);
    o.region_attributes = 0;
    o.threads = -1;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EINVAL);
    /* a hole the size of a pin: features below what the area bound can resolve in double */
    o.threads = 2;
    o.min_angle = 30;
    o.max_area = 1e-300;
    int rc = pcdm_triangulate(&in, &o, &m, &st);
    printf("thr_api: max_area 1e-300: %d: %s\n", rc, st.message);
    ck_assert_int_ne(rc, PCDM_OK);
    ck_assert_ptr_null(m.triangles);
    /* and the next call meshes */
    ck_assert_int_eq(mesh_threads(&in, 2, 25, 0.05, &m, &st), PCDM_OK);
    ck_assert(valid(&in, &m, 25, 0.05));
    pcdm_mesh_free(&m);
}
END_TEST

START_TEST(test_steiner_limit) {
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 30;
    o.max_area = 0.001;
    o.max_steiner = 200;
    o.threads = 2;
    pcdm_mesh m;
    pcdm_status st;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_ESTEINER);
    ck_assert_str_ne(st.message, "");
    ck_assert(valid(&in, &m, 0, 0)); /* conforming, without the bounds */
    pcdm_mesh full;
    ck_assert_int_eq(mesh_threads(&in, 2, 30, 0.001, &full, &st), PCDM_OK);
    printf("thr_api: max_steiner 200: %d points (%s); no limit: %d\n", m.npoints, st.message,
           full.npoints);
    ck_assert_int_lt(m.npoints, full.npoints / 4);
    pcdm_mesh_free(&m);
    pcdm_mesh_free(&full);
}
END_TEST

static void *mesh_plate2(void *arg) {
    pcdm_input in = plate();
    pcdm_status st;
    return mesh_threads(&in, 2, 30, 0.002, arg, &st) == PCDM_OK ? arg : NULL;
}

START_TEST(test_host_threads) {
    pcdm_mesh one, two[2];
    ck_assert_ptr_nonnull(mesh_plate2(&one));
    pthread_t th[2];
    for (int i = 0; i < 2; i++)
        ck_assert_int_eq(pthread_create(&th[i], NULL, mesh_plate2, &two[i]), 0);
    for (int i = 0; i < 2; i++) {
        void *r;
        ck_assert_int_eq(pthread_join(th[i], &r), 0);
        ck_assert_ptr_nonnull(r);
        ck_assert(same_mesh(&two[i], &one));
        pcdm_mesh_free(&two[i]);
    }
    pcdm_mesh_free(&one);
}
END_TEST

/* --compare POLY PREFIX Q A T (see the top). */
static int compare(char **argv) {
    char err[1024];
    pslg g;
    if (pslg_read(argv[0], &g, err, sizeof err) != 0) {
        fprintf(stderr, "thr_api: %s\n", err);
        return 2;
    }
    pcdm_input in = {.npoints = g.nverts,
                     .points = g.xy,
                     .pointmarkers = g.vmarker,
                     .npointattr = g.nattr,
                     .pointattr = g.vattr,
                     .nsegments = g.nsegs,
                     .segments = g.seg,
                     .segmentmarkers = g.smarker,
                     .nholes = g.nholes,
                     .holes = g.holes,
                     .nregions = g.nregions,
                     .regions = g.regions};
    pcdm_mesh m;
    pcdm_status st;
    int threads = atoi(argv[4]);
    if (mesh_threads(&in, threads, atof(argv[2]), atof(argv[3]), &m, &st) != PCDM_OK) {
        fprintf(stderr, "thr_api: pcdm_triangulate: %s\n", st.message);
        return 1;
    }
    mesh_flat w; /* what ./pcdm wrote */
    if (meshio_read_triangle(argv[1], &w, err, sizeof err) != 0) {
        fprintf(stderr, "thr_api: %s\n", err);
        return 2;
    }
    int same = w.nverts == m.npoints && w.ntris == m.ntriangles;
    for (int32_t i = 0; same && i < w.nverts; i++)
        same = w.xy[2 * i] == m.points[2 * i] && w.xy[2 * i + 1] == m.points[2 * i + 1] &&
               (!w.vmarker || w.vmarker[i] == m.pointmarkers[i]);
    for (size_t k = 0; same && k < 3 * (size_t)w.ntris; k++)
        same = w.tri[k] == m.triangles[k];
    printf("thr_api: %s -q %s -a %s threads %d: %d points, %d triangles; %s: %d points, %d "
           "triangles: %s\n",
           argv[0], argv[2], argv[3], threads, m.npoints, m.ntriangles, argv[1], w.nverts, w.ntris,
           same ? "the same mesh" : "DIFFERENT");
    mesh_flat_free(&w);
    pcdm_mesh_free(&m);
    pslg_free(&g);
    return same ? 0 : 1;
}

int main(int argc, char **argv) {
    geom_init();
    if (argc == 7 && strcmp(argv[1], "--compare") == 0) return compare(argv + 2);
    return ck_run(ck_suite("thr_api", 120,
                           CK_TESTS(test_same_any_threads, test_errors_return, test_steiner_limit,
                                    test_host_threads)));
}
