/* unit_api: Check suite for libpcdm's sequential call (include/pcdm.h, mesher/api/api.c).
 *
 *  - a plate with a hole meshed to an angle and an area bound passes the validator, and the
 *    input points keep their indices and markers;
 *  - the size callback (Triangle's triunsuitable) is honoured in one corner only, is shown the
 *    caller's coordinates (the mesher works on scaled ones), and without it that corner is
 *    coarse;
 *  - bad arguments and bad input return a code and a message, never a mesh; the Steiner limit
 *    returns PCDM_ESTEINER with a valid mesh; pcdm_mesh_free is idempotent;
 *  - convex_hull (Triangle's -c) meshes segments that enclose nothing over their hull;
 *  - nothing is printed (duplicates merged quietly); two threads meshing at once agree with one;
 *  - a PSLG with crossing and overlapping segments (tests/inputs/cross.poly) is split and
 *    marked as ./mesh does: the same points, markers and triangles as ./mesh's files;
 *  - out of memory returns PCDM_ENOMEM and gives back every block the call took.
 */
#include "api_check.h"
#include "check_run.h"
#include "io/meshio.h"

#include <malloc.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <unistd.h>

START_TEST(test_plate) {
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 28;
    o.max_area = 0.2;
    pcdm_mesh m;
    pcdm_status st;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    ck_assert_str_eq(st.message, "");
    ck_assert_int_gt(m.ntriangles, 100);
    ck_assert_int_eq((int)m.nglobaltriangles, m.ntriangles);
    ck_assert(valid(&in, &m, 28, 0.2));
    for (int i = 0; i < 8; i++) { /* the input's points first, in its order */
        ck_assert_double_eq(m.points[2 * i], plate_pts[2 * i]);
        ck_assert_double_eq(m.points[2 * i + 1], plate_pts[2 * i + 1]);
        ck_assert_int_eq(m.pointmarkers[i], plate_vmk[i]);
    }
    for (int32_t s = 0; s < m.nsegments; s++)
        ck_assert(m.segmentmarkers[s] == 1 || m.segmentmarkers[s] == 2);
    ck_assert_ptr_null(m.pointglobal);
    pcdm_mesh_free(&m);
    pcdm_mesh_free(&m); /* idempotent */
    char v[32];
    snprintf(v, sizeof v, "%d.%d.%d", PCDM_VERSION_MAJOR, PCDM_VERSION_MINOR, PCDM_VERSION_PATCH);
    ck_assert_str_eq(pcdm_version(), v);
}
END_TEST

/* Regions (Triangle's -A and -a without a number): the plate is one region (attribute 7, area
 * bound 0.05); with region_areas every triangle meets the bound, without it some does not; with
 * region_attributes every triangle carries 7, without it there is no triangleattr. */
START_TEST(test_regions) {
    static const double reg[] = {1, 1, 7, 0.05};
    pcdm_input in = plate();
    in.nregions = 1;
    in.regions = reg;
    pcdm_options o;
    pcdm_options_default(&o);
    o.region_attributes = o.region_areas = 1;
    pcdm_mesh m;
    pcdm_status st;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    ck_assert_ptr_nonnull(m.triangleattr);
    double amax = 0;
    for (int32_t t = 0; t < m.ntriangles; t++) {
        ck_assert_double_eq(m.triangleattr[t], 7);
        const int32_t *v = m.triangles + 3 * t;
        const double *a = m.points + 2 * v[0], *b = m.points + 2 * v[1], *c = m.points + 2 * v[2];
        amax = fmax(amax, 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])));
    }
    ck_assert(amax <= 0.05);
    ck_assert(valid(&in, &m, 20.7, 0.05));
    pcdm_mesh_free(&m);
    o.region_attributes = o.region_areas = 0;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    ck_assert_ptr_null(m.triangleattr);
    ck_assert(!valid(&in, &m, 20.7, 0.05)); /* the bound was not asked for: not met */
    pcdm_mesh_free(&m);
}
END_TEST

/* convex_hull (Triangle's -c): segments that enclose nothing but a hole are no domain without
 * it; with it the mesh covers the hull minus the hole, passes the validator against the input
 * enclosed by its hull (and fails against the input alone), new hull segments carry 1. */
START_TEST(test_convex_hull) {
    pcdm_input in = dangle();
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 30;
    o.max_area = 0.05;
    pcdm_mesh m;
    pcdm_status st;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EINPUT);
    ck_assert_msg(strstr(st.message, "domain is empty") != NULL, "%s", st.message);
    o.convex_hull = 1;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    int32_t ones, kept;
    double a = dangle_area(&m, &ones, &kept);
    ck_assert_msg(fabs(a - DANGLE_AREA) <= 1e-12 * DANGLE_AREA, "area %.17g", a);
    ck_assert_int_gt(ones, 4);
    ck_assert_int_gt(kept, 3);
    ck_assert(valid_hull(&in, &m, 30, 0.05, 1));
    ck_assert(!valid(&in, &m, 30, 0.05));
    pcdm_mesh_free(&m);
}
END_TEST

START_TEST(test_callback) {
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    pcdm_mesh m;
    pcdm_status st;
    double near, far;
    /* without the rule the corner is coarse: the test below would fail */
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    areas(&m, &near, &far);
    ck_assert_double_gt(near, 10 * NEAR_AREA);
    pcdm_mesh_free(&m);
    seen s = {0, 0};
    o.unsuitable = small_near_origin;
    o.unsuitable_ctx = &s;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    areas(&m, &near, &far);
    ck_assert_double_le(near, NEAR_AREA);
    ck_assert_double_gt(far, 100 * NEAR_AREA); /* honoured in the corner only */
    ck_assert_int_gt(s.calls, 0);
    ck_assert_double_eq(s.maxabs, 10); /* the caller's coordinates, not the scaled ones */
    ck_assert(valid(&in, &m, 20.7, 0));
    pcdm_mesh_free(&m);
}
END_TEST

START_TEST(test_errors) {
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    pcdm_mesh m;
    pcdm_status st;
    int32_t bad[16];
    memcpy(bad, plate_segs, sizeof bad);
    bad[5] = 8;
    in.segments = bad;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EINPUT);
    ck_assert_int_eq(st.code, PCDM_EINPUT);
    ck_assert_ptr_nonnull(strstr(st.message, "segment 2: point 8 out of range"));
    ck_assert_ptr_null(m.triangles);
    in = plate();
    o.min_angle = 65;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EINVAL);
    ck_assert_ptr_nonnull(strstr(st.message, "min_angle 65"));
    o.min_angle = 60; /* the command line's rule: below 60 */
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EINVAL);
    ck_assert_ptr_nonnull(strstr(st.message, "min_angle 60: must be at least 0 and below 60"));
    o.min_angle = 20;
    o.threads = 2; /* libpcdm (MPI) runs threads on MPI_COMM_SELF: MPI is not initialised */
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_EMPI);
    ck_assert_ptr_nonnull(strstr(st.message, "libpcdm_threads needs no MPI"));
    o.threads = 0;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, NULL, &st), PCDM_EINVAL);
    ck_assert_int_eq(pcdm_triangulate(NULL, &o, &m, NULL), PCDM_EINVAL);
    const double line[] = {0, 0, 1, 1, 2, 2, 3, 3};
    pcdm_input col = {.npoints = 4, .points = line};
    ck_assert_int_eq(pcdm_triangulate(&col, &o, &m, &st), PCDM_EINPUT);
    ck_assert_str_ne(st.message, "");
    const double inf[] = {0, 0, 1, 0, INFINITY, 1};
    pcdm_input nf = {.npoints = 3, .points = inf};
    ck_assert_int_eq(pcdm_triangulate(&nf, NULL, &m, &st), PCDM_EINPUT);
    ck_assert_ptr_nonnull(strstr(st.message, "non-finite"));
}
END_TEST

START_TEST(test_steiner_limit) {
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 30;
    o.max_area = 0.01;
    o.max_steiner = 20;
    pcdm_mesh m;
    pcdm_status st;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_ESTEINER);
    ck_assert_ptr_nonnull(strstr(st.message, "Steiner point limit (20)"));
    ck_assert_int_le(m.npoints, 8 + 20);
    ck_assert(valid(&in, &m, 0, 0)); /* conforming, without the bounds */
    pcdm_mesh_free(&m);
}
END_TEST

/* Duplicate points are merged and repeated segments dropped without a word on stderr (the
 * library never prints; the programs warn). */
START_TEST(test_quiet) {
    const double pts[] = {0, 0, 1, 0, 1, 1, 0, 1, 1, 0};
    const int32_t segs[] = {0, 1, 1, 2, 2, 3, 3, 0, 4, 2, 0, 1};
    pcdm_input in = {.npoints = 5, .points = pts, .nsegments = 6, .segments = segs};
    FILE *tmp = tmpfile();
    ck_assert_ptr_nonnull(tmp);
    fflush(stderr);
    int saved = dup(2);
    dup2(fileno(tmp), 2);
    pcdm_mesh m;
    pcdm_status st;
    int rc = pcdm_triangulate(&in, NULL, &m, &st);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    ck_assert_int_eq(rc, PCDM_OK);
    ck_assert_int_eq((int)lseek(fileno(tmp), 0, SEEK_END), 0);
    fclose(tmp);
    ck_assert(valid(&in, &m, 20.7, 0));
    pcdm_mesh_free(&m);
}
END_TEST

static void *mesh_plate(void *arg) {
    pcdm_mesh *m = arg;
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    o.max_area = 0.05;
    o.unsuitable = small_near_origin;
    return pcdm_triangulate(&in, &o, m, NULL) == PCDM_OK ? m : NULL;
}

/* Two threads at once (no state outside the call) make the mesh one thread makes. */
START_TEST(test_threads) {
    pcdm_mesh one, two[2];
    ck_assert_ptr_nonnull(mesh_plate(&one));
    pthread_t th[2];
    for (int i = 0; i < 2; i++)
        ck_assert_int_eq(pthread_create(&th[i], NULL, mesh_plate, &two[i]), 0);
    for (int i = 0; i < 2; i++) {
        void *r;
        ck_assert_int_eq(pthread_join(th[i], &r), 0);
        ck_assert_ptr_nonnull(r);
        ck_assert_int_eq(two[i].ntriangles, one.ntriangles);
        ck_assert_int_eq(two[i].npoints, one.npoints);
        ck_assert(!memcmp(two[i].points, one.points, 2 * (size_t)one.npoints * sizeof(double)));
        ck_assert(!memcmp(two[i].triangles, one.triangles, 3 * (size_t)one.ntriangles * 4));
        pcdm_mesh_free(&two[i]);
    }
    pcdm_mesh_free(&one);
}
END_TEST

/* tests/inputs/cross.poly: an X of crossing segments, a T, an overlap on the bottom edge. */
START_TEST(test_crossing_as_mesh) {
    const char *bin = getenv("BIN") ? getenv("BIN") : ".";
    char dir[] = "/tmp/unit_api_XXXXXX", cmd[1024], prefix[600], err[512];
    ck_assert_ptr_nonnull(mkdtemp(dir));
    snprintf(prefix, sizeof prefix, "%s/cross", dir);
    snprintf(cmd, sizeof cmd, "%s/mesh -Q -q 30 -a 0.5 -o %s tests/inputs/cross.poly", bin, prefix);
    ck_assert_msg(system(cmd) == 0, "%s failed", cmd);
    mesh_flat w; /* what ./mesh wrote */
    ck_assert_msg(meshio_read_triangle(prefix, &w, err, sizeof err) == 0, "%s", err);
    pslg g; /* the file as given, unchecked: the library's input arrays */
    ck_assert_msg(pslg_read("tests/inputs/cross.poly", &g, err, sizeof err) == 0, "%s", err);
    pcdm_input in = {0};
    in.npoints = g.nverts;
    in.points = g.xy;
    in.pointmarkers = g.vmarker;
    in.npointattr = g.nattr;
    in.pointattr = g.vattr;
    in.nsegments = g.nsegs;
    in.segments = g.seg;
    in.segmentmarkers = g.smarker;
    in.nholes = g.nholes;
    in.holes = g.holes;
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 30;
    o.max_area = 0.5;
    pcdm_mesh m;
    pcdm_status st;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    ck_assert_int_gt(g.nsegs, 0);
    ck_assert_int_eq(m.npoints, w.nverts);
    ck_assert_int_eq(m.ntriangles, w.ntris);
    ck_assert_int_eq(m.nsegments, w.nsegs);
    for (int32_t i = 0; i < m.npoints; i++) {
        ck_assert_msg(m.points[2 * i] == w.xy[2 * i] && m.points[2 * i + 1] == w.xy[2 * i + 1],
                      "point %d: (%.17g, %.17g) against ./mesh's (%.17g, %.17g)", i,
                      m.points[2 * i], m.points[2 * i + 1], w.xy[2 * i], w.xy[2 * i + 1]);
        ck_assert_int_eq(m.pointmarkers[i], w.vmarker[i]);
    }
    for (int64_t k = 0; k < 3 * (int64_t)m.ntriangles; k++)
        ck_assert_int_eq(m.triangles[k], w.tri[k]);
    for (int64_t k = 0; k < m.nsegments; k++) {
        ck_assert_int_eq(m.segments[2 * k], w.seg[2 * k]);
        ck_assert_int_eq(m.segments[2 * k + 1], w.seg[2 * k + 1]);
        ck_assert_int_eq(m.segmentmarkers[k], w.smarker[k]);
    }
    pcdm_mesh_free(&m);
    mesh_flat_free(&w);
    pslg_free(&g);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    ck_assert_int_eq(system(cmd), 0);
}
END_TEST

/* Out of memory (an address-space limit a little above what the process holds, Check's forked
 * child only): PCDM_ENOMEM with a message that says what to change, no mesh; the blocks the
 * call took are given back (the heap in use after it as before it, within 1 MiB); the next call
 * under the same limit, with a bound that fits, succeeds.  (Sanitizer builds reserve their
 * shadow memory up front and cannot run under such a limit: SKIP there.) */
static size_t heap_in_use(void) {
    struct mallinfo2 mi = mallinfo2();
    return mi.uordblks + mi.hblkhd;
}

static void limit_address_space(size_t more) {
    FILE *f = fopen("/proc/self/statm", "r");
    ck_assert_ptr_nonnull(f);
    unsigned long pages = 0;
    ck_assert_int_eq(fscanf(f, "%lu", &pages), 1);
    fclose(f);
    struct rlimit rl = {pages * (size_t)sysconf(_SC_PAGESIZE) + more, RLIM_INFINITY};
    ck_assert_int_eq(setrlimit(RLIMIT_AS, &rl), 0);
}

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define NO_AS_LIMIT 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define NO_AS_LIMIT 1
#endif
#endif

START_TEST(test_out_of_memory) {
#ifdef NO_AS_LIMIT
    printf("unit_api: test_out_of_memory: SKIP (a sanitizer build: no address-space limit)\n");
    return;
#endif
    pcdm_input in = plate();
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 30;
    o.max_area = 0.1; /* a first call, so what the library keeps for good is already there */
    pcdm_mesh m;
    pcdm_status st;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    pcdm_mesh_free(&m);
    malloc_trim(0);
    size_t before = heap_in_use();
    limit_address_space((size_t)300 << 20);
    o.max_area = 1e-7; /* some 10^9 triangles */
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_ENOMEM);
    ck_assert_int_eq(st.code, PCDM_ENOMEM);
    ck_assert_msg(strstr(st.message, "out of memory") && strstr(st.message, "max_area"), "%s",
                  st.message);
    ck_assert_ptr_null(m.points);
    ck_assert_ptr_null(m.triangles);
    size_t after = heap_in_use();
    ck_assert_msg(after < before + ((size_t)1 << 20),
                  "heap in use %zu bytes before the call, %zu after: not given back", before,
                  after);
    o.max_area = 0.01;
    ck_assert_int_eq(pcdm_triangulate(&in, &o, &m, &st), PCDM_OK);
    ck_assert(valid(&in, &m, 30, 0.01));
    pcdm_mesh_free(&m);
}
END_TEST

int main(void) {
    return ck_run(ck_suite("api", 120,
                           CK_TESTS(test_plate, test_regions, test_convex_hull, test_callback,
                                    test_errors, test_steiner_limit, test_quiet, test_threads,
                                    test_crossing_as_mesh, test_out_of_memory)));
}
