/* unit_mesh: Check suite for the mesher core (mesher/seq/mesh.h): Delaunay triangulation of point
 * sets (square, collinear, cocircular lattice, random), constrained Delaunay triangulation of
 * PSLGs (polygons with holes, random non-crossing segments, vertices lying exactly on
 * segments), a mesh from given triangles (mesh_build_from_triangles, with refused faults),
 * refinement, the PCDM hooks (named splits, on_split, poll, resumable refinement,
 * regions), the flat output, and the quality rule (mesh_rules_bad_bound against its plain
 * statement, bit for bit).  Every mesh goes through a structural check of the mesh
 * itself (orientation, neighbour involution, constraint bits, boundary, local Delaunay with
 * exact incircle) and, when it comes from a PSLG, through mesh_validate (validate.h).
 */
#include "check/validate.h"
#include "check_run.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "io/meshio.h"
#include "seq/kernel.h"
#include "seq/mesh.h"
#include "seq/rules.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- helpers ---------------------------------------------------------------------------- */

static uint64_t rng_state = 88172645463325252ull;
static double urand(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * 0x1p-53;
}

static const double *P(const mesh *m, int32_t v) {
    return mesh_vertex_xy(m, v);
}

/* Structural check of the mesh; returns the number of non-Delaunay unconstrained edges
 * (which must be 0) and fails the test on any structural problem. */
static void check_structure(const mesh *m) {
    int32_t live = 0;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t)) continue;
        live++;
        const int32_t *v = m->tv + 3 * t;
        for (int j = 0; j < 3; j++)
            ck_assert_msg(v[j] >= 0 && v[j] < m->nv, "triangle %d vertex %d out of range", t, v[j]);
        double o = geom_orient2d(P(m, v[0]), P(m, v[1]), P(m, v[2]));
        ck_assert_msg(o > 0, "triangle %d (%d %d %d) not counter-clockwise (%g)", t, v[0], v[1],
                      v[2], o);
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, f = mesh_sym(m, e);
            if (f < 0) {
                ck_assert_msg(mesh_edge_constrained(m, e), "boundary edge %d-%d not constrained",
                              mesh_org(m, e), mesh_dest(m, e));
                continue;
            }
            ck_assert_msg(mesh_tri_alive(m, mesh_edge_tri(f)), "edge %d neighbour dead", e);
            ck_assert_int_eq(mesh_sym(m, f), e);
            ck_assert_int_eq(mesh_org(m, f), mesh_dest(m, e));
            ck_assert_int_eq(mesh_dest(m, f), mesh_org(m, e));
            ck_assert_int_eq(mesh_edge_constrained(m, f), mesh_edge_constrained(m, e));
            if (!mesh_edge_constrained(m, e)) {
                double ic =
                    geom_incircle(P(m, v[0]), P(m, v[1]), P(m, v[2]), P(m, mesh_apex(m, f)));
                ck_assert_msg(ic <= 0, "edge %d-%d not locally Delaunay", mesh_org(m, e),
                              mesh_dest(m, e));
            } else {
                ck_assert_msg(mesh_subseg_of_edge(m, e) != NULL,
                              "constraint edge %d-%d has no subsegment record", mesh_org(m, e),
                              mesh_dest(m, e));
            }
        }
    }
    ck_assert_int_eq(live, m->nlive);
    for (int32_t v = 0; v < m->nv; v++) {
        int32_t t = m->vtri[v];
        if (t < 0) continue;
        ck_assert(mesh_tri_alive(m, t));
        ck_assert(m->tv[3 * t] == v || m->tv[3 * t + 1] == v || m->tv[3 * t + 2] == v);
    }
    for (int32_t r = 0; r < m->nss; r++) {
        const mesh_subseg *s = &m->ss[r];
        if (s->level == -2) continue;
        int32_t e = mesh_find_edge(m, s->u, s->v);
        ck_assert_msg(e >= 0 && mesh_edge_constrained(m, e), "subsegment %d-%d not an edge", s->u,
                      s->v);
    }
}

static pslg make_pslg(int32_t nv, const double *xy, int32_t ns, const int32_t *seg, int32_t nh,
                      const double *holes) {
    pslg g;
    memset(&g, 0, sizeof g);
    g.nverts = nv;
    g.xy = calloc(2 * (size_t)nv + 1, sizeof(double));
    memcpy(g.xy, xy, 2 * (size_t)nv * sizeof(double));
    g.vmarker = calloc((size_t)nv + 1, sizeof(int32_t));
    g.vline = calloc((size_t)nv + 1, sizeof(int32_t));
    g.nsegs = ns;
    g.seg = calloc(2 * (size_t)ns + 1, sizeof(int32_t));
    if (ns) memcpy(g.seg, seg, 2 * (size_t)ns * sizeof(int32_t));
    g.smarker = calloc((size_t)ns + 1, sizeof(int32_t));
    for (int32_t s = 0; s < ns; s++)
        g.smarker[s] = 1;
    g.sline = calloc((size_t)ns + 1, sizeof(int32_t));
    g.nholes = nh;
    g.holes = calloc(2 * (size_t)nh + 1, sizeof(double));
    if (nh) memcpy(g.holes, holes, 2 * (size_t)nh * sizeof(double));
    snprintf(g.path, sizeof g.path, "(test)");
    return g;
}

/* Validates m against g with the given bounds; fails the test with the report if not ok. */
static void validate(const mesh *m, const pslg *g, double qmin, double amax) {
    check_structure(m);
    mesh_flat f;
    ck_assert_int_eq(mesh_to_flat(m, &f), 0);
    validate_opts o = {qmin, amax, 0, 0, 0, 0};
    validate_report r;
    int ok = mesh_validate(g, &f, &o, &r);
    ck_assert_msg(ok, "mesh_validate failed: %s (ntris %ld)", r.first_problem, r.ntris);
    mesh_flat_free(&f);
}

static int use_lens; /* refine with diametral lenses instead of circles */

/* CDT of g, validated; then refined at (q, a), validated. */
static void mesh_and_refine(pslg *g, double q, double a) {
    char err[512];
    ck_assert_msg(pslg_check(g, err, sizeof err) == 0, "pslg_check: %s", err);
    mesh m;
    mesh_init(&m);
    ck_assert_msg(mesh_build_cdt(&m, g, NULL, err, sizeof err) == 0, "cdt: %s", err);
    validate(&m, g, 0, 0);
    mesh_quality mq = {q, a, 2000000, 1, use_lens};
    mesh_set_quality(&m, &mq);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
    validate(&m, g, q, a);
    mesh_free(&m);
}

static const double square_xy[] = {0, 0, 1, 0, 1, 1, 0, 1};
static const int32_t square_seg[] = {0, 1, 1, 2, 2, 3, 3, 0};

/* ---- Delaunay of point sets ---------------------------------------------------------------- */

START_TEST(test_square_points) {
    mesh m;
    mesh_init(&m);
    char err[256];
    ck_assert_int_eq(mesh_build_delaunay(&m, 4, square_xy, err, sizeof err), 0);
    ck_assert_int_eq(m.nlive, 2);
    check_structure(&m);
    mesh_free(&m);
}
END_TEST

START_TEST(test_triangle_pslg) {
    const double xy[] = {0, 0, 3, 0, 1, 2};
    const int32_t seg[] = {0, 1, 1, 2, 2, 0};
    pslg g = make_pslg(3, xy, 3, seg, 0, NULL);
    mesh_and_refine(&g, 25, 0.01);
    pslg_free(&g);
}
END_TEST

START_TEST(test_collinear) {
    double xy[20];
    for (int i = 0; i < 10; i++)
        xy[2 * i] = 0.1 * i, xy[2 * i + 1] = 0.2 * i;
    mesh m;
    mesh_init(&m);
    char err[256] = "";
    ck_assert_int_eq(mesh_build_delaunay(&m, 10, xy, err, sizeof err), -1);
    ck_assert_msg(strstr(err, "collinear") != NULL, "message: %s", err);
    mesh_free(&m);
    /* collinear points plus one off the line: all but the apex on the hull */
    xy[18] = 5, xy[19] = -3;
    mesh_init(&m);
    ck_assert_int_eq(mesh_build_delaunay(&m, 10, xy, err, sizeof err), 0);
    ck_assert_int_eq(m.nlive, 8);
    check_structure(&m);
    mesh_free(&m);
}
END_TEST

START_TEST(test_lattice_cocircular) {
    double xy[200];
    for (int i = 0; i < 10; i++)
        for (int j = 0; j < 10; j++)
            xy[2 * (10 * i + j)] = i, xy[2 * (10 * i + j) + 1] = j;
    mesh m;
    mesh_init(&m);
    char err[256];
    ck_assert_int_eq(mesh_build_delaunay(&m, 100, xy, err, sizeof err), 0);
    ck_assert_int_eq(m.nlive, 2 * 81); /* 2n - h - 2 = 200 - 36 - 2 */
    check_structure(&m);
    /* the same lattice as a PSLG (square boundary through lattice points), refined */
    const int32_t seg[] = {0, 9, 9, 99, 99, 90, 90, 0};
    pslg g = make_pslg(100, xy, 4, seg, 0, NULL);
    mesh_and_refine(&g, 30, 0.2);
    pslg_free(&g);
    mesh_free(&m);
}
END_TEST

START_TEST(test_random_points) {
    int n = _i == 0 ? 1000 : 20000;
    double *xy = malloc(2 * (size_t)n * sizeof(double));
    for (int i = 0; i < 2 * n; i++)
        xy[i] = urand();
    /* a few exact duplicates and points on a coarse grid (degenerate incircle cases) */
    for (int i = 0; i < n / 10; i++) {
        xy[2 * i] = floor(xy[2 * i] * 8) / 8;
        xy[2 * i + 1] = floor(xy[2 * i + 1] * 8) / 8;
    }
    xy[2 * (n - 1)] = xy[2 * (n - 2)], xy[2 * (n - 1) + 1] = xy[2 * (n - 2) + 1];
    mesh m;
    mesh_init(&m);
    char err[256];
    ck_assert_int_eq(mesh_build_delaunay(&m, n, xy, err, sizeof err), 0);
    check_structure(&m);
    int isolated = 0;
    for (int32_t v = 0; v < m.nv; v++)
        isolated += m.vtri[v] < 0;
    ck_assert_int_ge(isolated, 1); /* the duplicates */
    /* insert free points and re-check */
    for (int i = 0; i < 200; i++) {
        double p[2] = {0.1 + 0.8 * urand(), 0.1 + 0.8 * urand()};
        int32_t v;
        mesh_insert_result r = mesh_insert_point(&m, p, -1, &v);
        ck_assert(r == MESH_INSERTED || r == MESH_DUPLICATE);
    }
    double out[2] = {5, 5};
    ck_assert_int_eq(mesh_insert_point(&m, out, -1, NULL), MESH_OUTSIDE);
    check_structure(&m);
    mesh_free(&m);
    free(xy);
}
END_TEST

/* ---- CDT of PSLGs ---------------------------------------------------------------------------- */

START_TEST(test_square_pslg) {
    pslg g = make_pslg(4, square_xy, 4, square_seg, 0, NULL);
    mesh_and_refine(&g, 20.7, 0);
    mesh_and_refine(&g, 30, 0.001);
    pslg_free(&g);
}
END_TEST

/* Star-shaped polygon with a star-shaped hole. */
START_TEST(test_polygon_with_hole) {
    int n = 40, h = 12;
    double xy[2 * 52];
    int32_t seg[2 * 52];
    for (int i = 0; i < n; i++) {
        double a = 2 * M_PI * i / n, r = 0.5 + 0.5 * urand();
        xy[2 * i] = r * cos(a), xy[2 * i + 1] = r * sin(a);
        seg[2 * i] = i, seg[2 * i + 1] = (i + 1) % n;
    }
    for (int i = 0; i < h; i++) {
        double a = 2 * M_PI * i / h, r = 0.1 + 0.1 * urand();
        xy[2 * (n + i)] = r * cos(a), xy[2 * (n + i) + 1] = r * sin(a);
        seg[2 * (n + i)] = n + i, seg[2 * (n + i) + 1] = n + (i + 1) % h;
    }
    double hole[2] = {0, 0};
    pslg g = make_pslg(n + h, xy, n + h, seg, 1, hole);
    mesh_and_refine(&g, 28, 0.002);
    use_lens = 1;
    mesh_and_refine(&g, 33, 0);
    use_lens = 0;
    pslg_free(&g);
}
END_TEST

static int segs_conflict(const double *xy, int32_t a, int32_t b, int32_t c, int32_t d) {
    const double *A = xy + 2 * a, *B = xy + 2 * b, *C = xy + 2 * c, *D = xy + 2 * d;
    if (a == c || a == d || b == c || b == d) {
        /* shared endpoint: conflict only if collinear and overlapping */
        int32_t s = (a == c || a == d) ? a : b, o1 = s == a ? b : a, o2 = (s == c) ? d : c;
        const double *S = xy + 2 * s, *O1 = xy + 2 * o1, *O2 = xy + 2 * o2;
        if (geom_orient2d(S, O1, O2) != 0) return 0;
        return (O1[0] - S[0]) * (O2[0] - S[0]) + (O1[1] - S[1]) * (O2[1] - S[1]) > 0;
    }
    double o1 = geom_orient2d(A, B, C), o2 = geom_orient2d(A, B, D);
    double o3 = geom_orient2d(C, D, A), o4 = geom_orient2d(C, D, B);
    if (((o1 > 0 && o2 > 0) || (o1 < 0 && o2 < 0)) || ((o3 > 0 && o4 > 0) || (o3 < 0 && o4 < 0)))
        return 0;
    return 1; /* crossing, touching or collinear overlap: reject to be safe */
}

/* Random points in the unit square with random non-crossing segments, some of them passing
 * exactly through other vertices (points placed on a coarse grid). */
START_TEST(test_random_pslg) {
    int n = 40 + 12 * _i;
    double *xy = malloc(2 * (size_t)(n + 4) * sizeof(double));
    int32_t *seg = malloc(2 * (size_t)(n * 3 + 4) * sizeof(int32_t));
    memcpy(xy, square_xy, sizeof square_xy);
    for (int i = 4; i < n + 4; i++) {
        xy[2 * i] = 0.05 + 0.9 * urand(), xy[2 * i + 1] = 0.05 + 0.9 * urand();
        if (i % 3 == 0) { /* dyadic grid points: exact collinearities */
            xy[2 * i] = 0.125 * (1 + (int)(urand() * 7));
            xy[2 * i + 1] = 0.125 * (1 + (int)(urand() * 7));
        }
    }
    /* drop exact duplicates among grid points by nudging them */
    for (int i = 4; i < n + 4; i++)
        for (int j = 4; j < i; j++)
            if (xy[2 * i] == xy[2 * j] && xy[2 * i + 1] == xy[2 * j + 1])
                xy[2 * i] += 0.0625 * urand();
    int ns = 4;
    memcpy(seg, square_seg, sizeof square_seg);
    for (int tries = 0; tries < 40 * n && ns < n; tries++) {
        int32_t a = 4 + (int32_t)(urand() * n), b = 4 + (int32_t)(urand() * n);
        if (a == b) continue;
        int ok = 1;
        for (int s = 0; s < ns && ok; s++)
            if (segs_conflict(xy, a, b, seg[2 * s], seg[2 * s + 1])) ok = 0;
        if (!ok) continue;
        seg[2 * ns] = a, seg[2 * ns + 1] = b;
        ns++;
    }
    pslg g = make_pslg(n + 4, xy, ns, seg, 0, NULL);
    if (getenv("UNIT_MESH_DUMP")) {
        char name[64];
        snprintf(name, sizeof name, "/tmp/random_pslg_%d.poly", _i);
        FILE *f = fopen(name, "w");
        fprintf(f, "%d 2 0 0\n", n + 4);
        for (int i = 0; i < n + 4; i++)
            fprintf(f, "%d %.17g %.17g\n", i + 1, xy[2 * i], xy[2 * i + 1]);
        fprintf(f, "%d 0\n", ns);
        for (int s = 0; s < ns; s++)
            fprintf(f, "%d %d %d\n", s + 1, seg[2 * s] + 1, seg[2 * s + 1] + 1);
        fprintf(f, "0\n");
        fclose(f);
    }
    mesh_and_refine(&g, 25, 0.0005);
    pslg_free(&g);
    free(xy);
    free(seg);
}
END_TEST

/* Vertices lying exactly on segments: the segments are split there. */
START_TEST(test_vertex_on_segment) {
    const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0, 0, 0.5, 1, 0.5, 0.25, 0.5, 0.75, 0.5};
    const int32_t seg[] = {0, 1, 1, 2, 2, 3, 3, 0, 5, 6};
    pslg g = make_pslg(9, xy, 5, seg, 0, NULL);
    char err[256];
    ck_assert_int_eq(pslg_check(&g, err, sizeof err), 0);
    mesh m;
    mesh_init(&m);
    ck_assert_int_eq(mesh_build_cdt(&m, &g, NULL, err, sizeof err), 0);
    validate(&m, &g, 0, 0);
    /* the bottom segment is two subsegments, the middle one three */
    ck_assert_int_ge(mesh_find_edge(&m, 0, 4), 0);
    ck_assert_int_ge(mesh_find_edge(&m, 4, 1), 0);
    ck_assert_int_ge(mesh_find_edge(&m, 5, 7), 0);
    ck_assert_int_ge(mesh_find_edge(&m, 7, 8), 0);
    ck_assert_int_ge(mesh_find_edge(&m, 8, 6), 0);
    ck_assert(mesh_edge_constrained(&m, mesh_find_edge(&m, 7, 8)));
    mesh_free(&m);
    mesh_and_refine(&g, 30, 0.01);
    pslg_free(&g);
}
END_TEST

/* A segment crossing many triangles of a dense point set (long flip sequences). */
START_TEST(test_long_segment) {
    int n = 2000;
    double *xy = malloc(2 * (size_t)(n + 6) * sizeof(double));
    memcpy(xy, square_xy, sizeof square_xy);
    xy[8] = 0.01, xy[9] = 0.013, xy[10] = 0.99, xy[11] = 0.987;
    for (int i = 6; i < n + 6; i++)
        xy[2 * i] = 0.02 + 0.96 * urand(), xy[2 * i + 1] = 0.02 + 0.96 * urand();
    const int32_t seg[] = {0, 1, 1, 2, 2, 3, 3, 0, 4, 5};
    pslg g = make_pslg(n + 6, xy, 5, seg, 0, NULL);
    char err[256];
    ck_assert_int_eq(pslg_check(&g, err, sizeof err), 0);
    mesh m;
    mesh_init(&m);
    ck_assert_int_eq(mesh_build_cdt(&m, &g, NULL, err, sizeof err), 0);
    validate(&m, &g, 0, 0);
    mesh_free(&m);
    pslg_free(&g);
    free(xy);
}
END_TEST

START_TEST(test_bad_input) {
    mesh m;
    mesh_init(&m);
    char err[256] = "";
    const double xy[] = {0, 0, 1, 1};
    ck_assert_int_eq(mesh_build_delaunay(&m, 2, xy, err, sizeof err), -1);
    ck_assert(err[0] != 0);
    mesh_free(&m);
    /* every triangle in a hole: empty domain */
    double hole[2] = {0.5, 0.5};
    pslg g = make_pslg(4, square_xy, 4, square_seg, 1, hole);
    mesh_init(&m);
    ck_assert_int_eq(mesh_build_cdt(&m, &g, NULL, err, sizeof err), -1);
    ck_assert_msg(strstr(err, "empty") != NULL, "message: %s", err);
    mesh_free(&m);
    pslg_free(&g);
}
END_TEST

/* ---- small input angles ---------------------------------------------------------------------- */

START_TEST(test_small_angles) {
    /* two wedges of 5 and 15 degrees sharing the apex, and a needle polygon */
    double xy[10];
    xy[0] = 0, xy[1] = 0;
    double ang[4] = {0, 5, 20, 80};
    for (int i = 0; i < 4; i++)
        xy[2 + 2 * i] = cos(ang[i] * M_PI / 180), xy[3 + 2 * i] = sin(ang[i] * M_PI / 180);
    const int32_t seg[] = {0, 1, 1, 2, 0, 2, 2, 3, 3, 4, 4, 0};
    pslg g = make_pslg(5, xy, 6, seg, 0, NULL);
    mesh_and_refine(&g, 30, 0.001);
    mesh_and_refine(&g, 25, 0);
    pslg_free(&g);
}
END_TEST

/* The split tree of an interface segment (mesh_rules_iface_point) on a cut of length 0.708
 * (about sqrt(2) times a power of two): the root is split on the power-of-two shell around the
 * start, its right piece on the shell around the end, every other piece at its midpoint; so
 * the pieces touching either end are powers of two long at every level, and every point lies
 * strictly inside its piece. */
START_TEST(test_iface_point) {
    const double a[2] = {0.42, 0}, b[2] = {0.42 + 0.708, 0};
    double p[2];
    mesh_rules_iface_point(a, b, 0, 0, p);
    ck_assert_double_eq_tol(p[0] - a[0], 0.25, 1e-15); /* largest 2^j <= 2/3 * 0.708 */
    mesh_rules_iface_point(a, b, 1, 1, p);
    ck_assert_double_eq_tol(b[0] - p[0], 0.25, 1e-15); /* the rest, 0.458: 2^-2 from the end */
    mesh_rules_iface_point(a, b, 1, 0, p);
    ck_assert_double_eq_tol(p[0] - a[0], 0.125, 1e-15); /* a power-of-two piece: its midpoint */
    for (int32_t lev = 1; lev <= 12; lev++) {
        double lo = a[0], hi = b[0];
        mesh_rules_iface_point(a, b, lev, 0, p); /* the first piece at the start */
        double first = p[0] - a[0];
        mesh_rules_iface_point(a, b, lev, ((int64_t)1 << lev) - 1, p); /* the last one */
        double last = b[0] - p[0];
        ck_assert_msg(fabs(log2(first) - round(log2(first))) < 1e-12, "level %d: first piece %.17g",
                      lev, first);
        ck_assert_msg(fabs(log2(last) - round(log2(last))) < 1e-12, "level %d: last piece %.17g",
                      lev, last);
        for (int64_t k = 0; k < ((int64_t)1 << lev) && k < 64; k++) {
            mesh_rules_iface_point(a, b, lev, k, p);
            ck_assert(p[0] > lo && p[0] < hi && p[1] == 0);
        }
    }
}
END_TEST

/* An interface segment (PCDM cut) meeting boundary segments at 35 and 55 degrees: the unit
 * square with a cut from (0.42, 0) to the right side (length 0.708: about sqrt(2) times a
 * power of two, the worst case for mismatched shells).  The interface's end pieces and the
 * boundary pieces at the two corners are cut on the same power-of-two shells; they must
 * match (else the two sides encroach each other at every scale
 * down to the corner until precision runs out: failed splits, degenerate chains), and the
 * angle bound must be met at the corners (they are not corners of the input, so the validator,
 * run against the square without the cut, exempts nothing there). */
START_TEST(test_iface_corner) {
    double t35 = tan(35 * M_PI / 180);
    const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.42, 0, 1, 0.58 * t35};
    const int32_t seg[] = {0, 4, 4, 1, 1, 5, 5, 2, 2, 3, 3, 0, 4, 5};
    const uint8_t flag[] = {0, 0, 0, 0, 0, 0, 1};
    pslg g = make_pslg(6, xy, 7, seg, 0, NULL);
    pslg in = make_pslg(4, square_xy, 4, square_seg, 0, NULL);
    char err[256];
    ck_assert_int_eq(pslg_check(&g, err, sizeof err), 0);
    ck_assert_int_eq(pslg_check(&in, err, sizeof err), 0);
    const double qa[][2] = {{30, 0.0002}, {30, 0.00002}, {20.7, 0.0001}, {30, 0}};
    for (int c = 0; c < 4; c++) {
        mesh m;
        mesh_init(&m);
        ck_assert_int_eq(mesh_build_cdt(&m, &g, flag, err, sizeof err), 0);
        mesh_quality q = {qa[c][0], qa[c][1], 2000000, 1, use_lens};
        mesh_set_quality(&m, &q);
        ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
        ck_assert_msg(m.stats.failed == 0, "-q %g -a %g: %lld failed splits", qa[c][0], qa[c][1],
                      (long long)m.stats.failed);
        ck_assert_int_eq(m.stats.skipped_small, 0);
        for (int32_t r = 0; r < m.nss; r++)
            if (m.ss[r].level != -2 && m.ss[r].seg == 6) ck_assert_int_ge(m.ss[r].level, 0);
        /* no cascade toward a corner: the local feature size is about 0.01 everywhere */
        double emin = INFINITY;
        for (int32_t t = 0; t < m.nt; t++)
            for (int j = 0; mesh_tri_alive(&m, t) && j < 3; j++)
                emin =
                    fmin(emin, geom_dist2(P(&m, m.tv[3 * t + j]), P(&m, mesh_dest(&m, 3 * t + j))));
        ck_assert_msg(sqrt(emin) > 1e-3, "-q %g -a %g: an edge of length %g", qa[c][0], qa[c][1],
                      sqrt(emin));
        validate(&m, &in, qa[c][0], qa[c][1]);
        mesh_free(&m);
    }
    pslg_free(&g);
    pslg_free(&in);
}
END_TEST

/* ---- PCDM hooks --------------------------------------------------------------------------------
 */

typedef struct hookctx {
    int splits, polls, stop_first;
    int32_t last_seg, last_level;
    int64_t last_k;
} hookctx;

static void on_split(void *ctx, int32_t seg, int32_t level, int64_t k, unsigned flags) {
    hookctx *h = ctx;
    ck_assert(flags & MESH_SPLIT_INTERFACE);
    h->splits++;
    h->last_seg = seg, h->last_level = level, h->last_k = k;
}

static int poll_cb(void *ctx) {
    hookctx *h = ctx;
    h->polls++;
    if (h->stop_first) {
        h->stop_first = 0;
        return 1;
    }
    return 0;
}

static const double iface_xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 0, 0.5, 1, 0.5};
/* The unit square cut in two by an interface, segment 4 from (0, 0.5) to (1, 0.5); the sides
 * are given in pieces at the interface's ends (the input check would split them there). */
static const int32_t iface_seg[] = {0, 1, 1, 5, 5, 2, 2, 3, 4, 5, 3, 4, 4, 0};
static const uint8_t iface_flag[] = {0, 0, 0, 0, 1, 0, 0};

START_TEST(test_named_split) {
    pslg g = make_pslg(6, iface_xy, 7, iface_seg, 0, NULL);
    char err[256];
    ck_assert_int_eq(pslg_check(&g, err, sizeof err), 0);
    mesh m;
    mesh_init(&m);
    ck_assert_int_eq(mesh_build_cdt(&m, &g, iface_flag, err, sizeof err), 0);
    int32_t *label = malloc((size_t)m.nt * sizeof(int32_t));
    ck_assert_int_eq(mesh_label_regions(&m, label), 2);
    free(label);
    hookctx h = {0};
    mesh_hooks hk = {on_split, poll_cb, 10, &h};
    mesh_set_hooks(&m, &hk);
    ck_assert_int_eq(mesh_split_subsegment_named(&m, 4, 0, 0), MESH_SPLIT_DONE);
    ck_assert_int_eq(mesh_split_subsegment_named(&m, 4, 0, 0), MESH_SPLIT_ALREADY);
    ck_assert_int_eq(mesh_split_subsegment_named(&m, 4, 1, 1), MESH_SPLIT_DONE);
    /* an ancestor still whole here is split down to the request */
    ck_assert_int_eq(mesh_split_subsegment_named(&m, 4, 4, 5), MESH_SPLIT_DONE);
    ck_assert_int_eq(mesh_split_subsegment_named(&m, 4, 4, 5), MESH_SPLIT_ALREADY);
    ck_assert_int_eq(mesh_split_subsegment_named(&m, 9, 0, 0), MESH_SPLIT_NOT_FOUND);
    ck_assert_int_eq(mesh_split_subsegment_named(&m, 4, 2, 7), MESH_SPLIT_NOT_FOUND);
    ck_assert_int_eq(h.splits, 0); /* requested splits are not echoed */
    ck_assert_int_eq(m.stats.named_done, 3);
    ck_assert_int_eq(m.stats.named_already, 2);
    /* the split point of (4, 5) is a vertex, bit for bit (a cut of length 1: its end pieces'
     * shells are its midpoints) */
    double p[2];
    mesh_rules_iface_point(iface_xy + 8, iface_xy + 10, 4, 5, p);
    int found = 0;
    for (int32_t v = 0; v < m.nv; v++)
        if (P(&m, v)[0] == p[0] && P(&m, v)[1] == p[1]) found = 1;
    ck_assert(found);
    ck_assert_double_eq(p[0], 11.0 / 32.0);
    validate(&m, &g, 0, 0);
    /* refinement stops at the first poll, then resumes to the end */
    h.stop_first = 1;
    mesh_quality q = {30, 0.0005, -1, 1, 0};
    mesh_set_quality(&m, &q);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_STOPPED);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
    ck_assert_int_gt(h.polls, 1);
    ck_assert_int_gt(h.splits, 0);
    ck_assert_int_eq(h.splits, m.stats.iface_splits);
    ck_assert_int_eq(h.last_seg, 4);
    validate(&m, &g, 30, 0.0005);
    /* a split arriving after refinement queues work; refinement picks it up */
    int32_t r = -1;
    for (int32_t i = 0; i < m.nss; i++)
        if (m.ss[i].level >= 0 && m.ss[i].seg == 4) r = i;
    ck_assert_int_ge(r, 0);
    ck_assert_int_eq(mesh_split_subsegment_named(&m, 4, m.ss[r].level, m.ss[r].k), MESH_SPLIT_DONE);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
    validate(&m, &g, 30, 0.0005);
    mesh_free(&m);
    pslg_free(&g);
}
END_TEST

/* Past the Steiner limit the interface pieces a vertex encroaches are still split (the merged
 * mesh must stay Delaunay across the interface: it is no constraint of the input), each sent to
 * the other side, and so is a named split (a neighbour's) with the pieces it leaves
 * encroached, but no input subsegment is split any more; nothing on the interface is left
 * encroached (mesh_iface_defects).  The square of test_named_split with two vertices near its
 * interface. */
START_TEST(test_named_split_at_limit) {
    static const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 0, 0.5, 1, 0.5, 0.3, 0.52, 0.7, 0.47};
    pslg g = make_pslg(8, xy, 7, iface_seg, 0, NULL);
    char err[256];
    ck_assert_int_eq(pslg_check(&g, err, sizeof err), 0);
    mesh m;
    mesh_init(&m);
    ck_assert_int_eq(mesh_build_cdt(&m, &g, iface_flag, err, sizeof err), 0);
    int32_t nbound = 0, nb = 0; /* the square's sides' pieces */
    for (int32_t i = 0; i < m.nss; i++)
        if (m.ss[i].level != -2 && m.ss[i].seg != 4) nbound++;
    /* (0.7, 0.47) lies inside the circumcircle of the interface's triangle with (0.3, 0.52) */
    ck_assert_int_gt(mesh_iface_defects(&m, NULL), 0);
    hookctx h = {0};
    mesh_hooks hk = {on_split, poll_cb, 1000, &h};
    mesh_set_hooks(&m, &hk);
    mesh_quality q = {30, 0.0005, 0, 1, 0}; /* limit 0: reached at once */
    mesh_set_quality(&m, &q);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_STEINER_LIMIT);
    ck_assert_int_gt(h.splits, 0); /* the interface's own splits, sent to the other side */
    ck_assert_int_eq(h.splits, m.stats.seg_splits);
    ck_assert_int_eq(m.stats.inserted, 0);
    ck_assert_int_eq(mesh_iface_defects(&m, NULL), 0);
    ck_assert_int_eq(mesh_split_subsegment_named(&m, 4, 12, 1365), MESH_SPLIT_DONE);
    ck_assert_int_eq(h.splits, m.stats.iface_splits);
    ck_assert_int_eq(mesh_iface_defects(&m, NULL), 0);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_STEINER_LIMIT);
    for (int32_t i = 0; i < m.nss; i++)
        if (m.ss[i].level != -2 && m.ss[i].seg != 4) nb++;
    ck_assert_int_eq(nb, nbound); /* input subsegments: never split past the limit */
    validate(&m, &g, 0, 0);
    mesh_free(&m);
    pslg_free(&g);
}
END_TEST

/* Two ranks' worth of subdomains in one process: mesh each half separately, exchanging the
 * on_split requests by hand, and check the interface subsegments agree bit for bit. */
typedef struct side {
    mesh m;
    int32_t q[4096][3];
    int64_t qk[4096];
    int nq;
} side;

static void side_split(void *ctx, int32_t seg, int32_t level, int64_t k, unsigned flags) {
    side *s = ctx;
    ck_assert_int_lt(s->nq, 4096);
    s->q[s->nq][0] = seg, s->q[s->nq][1] = level, s->qk[s->nq] = k;
    s->nq++;
}

START_TEST(test_two_halves) {
    pslg g = make_pslg(6, iface_xy, 7, iface_seg, 0, NULL);
    char err[256];
    ck_assert_int_eq(pslg_check(&g, err, sizeof err), 0);
    side *sd = calloc(2, sizeof(side));
    const double seeds[2][2] = {{0.5, 0.25}, {0.5, 0.75}};
    for (int i = 0; i < 2; i++) {
        mesh *m = &sd[i].m;
        mesh_init(m);
        ck_assert_int_eq(mesh_build_cdt(m, &g, iface_flag, err, sizeof err), 0);
        int32_t *label = malloc((size_t)m->nt * sizeof(int32_t));
        int32_t nr = mesh_label_regions(m, label);
        uint8_t keep[8] = {0};
        int32_t t = mesh_locate(m, seeds[i], -1);
        ck_assert_int_ge(t, 0);
        keep[label[t]] = 1;
        ck_assert_int_eq(nr, 2);
        mesh_keep_regions(m, label, keep);
        free(label);
        check_structure(m);
        mesh_hooks hk = {side_split, NULL, 50, &sd[i]};
        mesh_set_hooks(m, &hk);
        mesh_quality q = {25, i == 0 ? 0.0004 : 0.004, -1, 1, 1};
        mesh_set_quality(m, &q);
    }
    for (int round = 0; round < 100; round++) {
        int work = 0;
        for (int i = 0; i < 2; i++) {
            ck_assert_int_eq(mesh_refine(&sd[i].m), MESH_REFINE_DONE);
            side *o = &sd[1 - i];
            for (int j = 0; j < sd[i].nq; j++) {
                mesh_split_subsegment_named(&o->m, sd[i].q[j][0], sd[i].q[j][1], sd[i].qk[j]);
                work = 1;
            }
            sd[i].nq = 0;
        }
        if (!work) break;
    }
    /* the interface vertices of the two halves coincide */
    for (int i = 0; i < 2; i++) {
        const mesh *a = &sd[i].m, *b = &sd[1 - i].m;
        int na = 0;
        for (int32_t r = 0; r < a->nss; r++) {
            const mesh_subseg *s = &a->ss[r];
            if (s->level == -2 || s->seg != 4) continue;
            na++;
            ck_assert_int_ge(s->level, 0);
            int32_t rb = -1;
            for (int32_t x = 0; x < b->nss; x++)
                if (b->ss[x].seg == 4 && b->ss[x].level == s->level && b->ss[x].k == s->k) rb = x;
            ck_assert_msg(rb >= 0, "interface subsegment (%d,%lld) missing on the other side",
                          s->level, (long long)s->k);
            ck_assert(P(a, s->u)[0] == P(b, b->ss[rb].u)[0] &&
                      P(a, s->u)[1] == P(b, b->ss[rb].u)[1]);
            ck_assert(P(a, s->v)[0] == P(b, b->ss[rb].v)[0] &&
                      P(a, s->v)[1] == P(b, b->ss[rb].v)[1]);
        }
        ck_assert_int_gt(na, 4);
        check_structure(a);
    }
    for (int i = 0; i < 2; i++)
        mesh_free(&sd[i].m);
    free(sd);
    pslg_free(&g);
}
END_TEST

START_TEST(test_regions_keep) {
    pslg g = make_pslg(6, iface_xy, 7, iface_seg, 0, NULL);
    char err[256];
    ck_assert_int_eq(pslg_check(&g, err, sizeof err), 0);
    mesh m;
    mesh_init(&m);
    ck_assert_int_eq(mesh_build_cdt(&m, &g, iface_flag, err, sizeof err), 0);
    mesh_quality q = {25, 0.01, -1, 1, 0};
    mesh_set_quality(&m, &q);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
    int32_t *label = malloc((size_t)m.nt * sizeof(int32_t));
    ck_assert_int_eq(mesh_label_regions(&m, label), 2);
    double lower[2] = {0.3, 0.1};
    int32_t t = mesh_locate(&m, lower, -1);
    uint8_t keep[2] = {0, 0};
    keep[label[t]] = 1;
    mesh_keep_regions(&m, label, keep);
    free(label);
    check_structure(&m);
    double area = 0;
    for (int32_t i = 0; i < m.nt; i++)
        if (mesh_tri_alive(&m, i))
            area += geom_area(P(&m, m.tv[3 * i]), P(&m, m.tv[3 * i + 1]), P(&m, m.tv[3 * i + 2]));
    ck_assert_double_eq_tol(area, 0.5, 1e-12);
    mesh_flat f;
    ck_assert_int_eq(mesh_to_flat(&m, &f), 0);
    int iface = 0;
    for (int32_t s = 0; s < f.nsegs; s++)
        iface += f.sinterface[s];
    ck_assert_int_gt(iface, 0);
    mesh_flat_free(&f);
    mesh_free(&m);
    pslg_free(&g);
}
END_TEST

START_TEST(test_data_files) {
    static const char *files[] = {"data/square.poly",  "data/lshape.poly", "data/wedge.poly",
                                  "data/channel.poly", "data/holes.poly",  "data/lake.poly"};
    for (int i = 0; i < 6; i++) {
        pslg g;
        char err[512];
        if (pslg_read(files[i], &g, err, sizeof err) != 0) {
            /* run from another directory: skip quietly */
            continue;
        }
        ck_assert_msg(pslg_check(&g, err, sizeof err) == 0, "%s", err);
        mesh_and_refine(&g, 30, 0.002);
        pslg_free(&g);
    }
}
END_TEST

static TCase *tcase(Suite *s, const char *name) {
    TCase *tc = tcase_create(name);
    tcase_set_timeout(tc, 120);
    suite_add_tcase(s, tc);
    return tc;
}

/* The area drift of boundary splits (rules.h): a move towards the inside apex shrinks the
 * domain, away from it grows it; the signed sum may not pass the budget, moves of opposite
 * sign cancel, a point on the line costs nothing. */
START_TEST(test_area_drift) {
    geom_init();
    const double u[2] = {0, 0}, v[2] = {8, 0}, w[2] = {4, 4}; /* inside is above */
    const double in[2] = {4, 0.25}, out[2] = {4, -0.25}, on[2] = {2, 0};
    ck_assert_double_eq(mesh_rules_area_drift(-16, 0, 0), ldexp(16, -30));
    /* rounding's share: 2^-49 of the magnitude per unit of boundary, while at most 2^-8 area */
    ck_assert_double_eq(mesh_rules_area_drift(16, 0x1p40, 2), ldexp(16, -30) + 0x1p-8);
    ck_assert_double_eq(mesh_rules_area_drift(16, 0x1p44, 2), ldexp(16, -30) + 0x1p-4);
    ck_assert_double_eq(mesh_rules_area_drift(16, 0x1p45, 2), ldexp(16, -30));
    double drift = 0, budget = 1.5; /* each off-line point moves the area by 8 * 0.25 / 2 = 1 */
    ck_assert_int_eq(mesh_rules_drift_spend(u, v, on, w, budget, &drift), 0);
    ck_assert_double_eq(drift, 0);
    ck_assert_int_eq(mesh_rules_drift_spend(u, v, out, w, budget, &drift), 0);
    ck_assert_double_eq(drift, 1);
    ck_assert_int_eq(mesh_rules_drift_spend(u, v, out, w, budget, &drift), 1); /* 2 > 1.5 */
    ck_assert_double_eq(drift, 1);                                             /* not spent */
    ck_assert_int_eq(mesh_rules_drift_spend(u, v, in, w, budget, &drift), 0);  /* cancels */
    ck_assert_double_eq(drift, 0);
    ck_assert_int_eq(mesh_rules_drift_spend(v, u, in, w, budget, &drift), 0); /* either direction */
    ck_assert_double_eq(drift, -1);
    ck_assert_int_eq(mesh_rules_drift_spend(u, v, in, w, budget, &drift), 1); /* -2 */
}
END_TEST

/* The split of a subsegment (u, v) of a nearly vertical segment at a rounded dyadic point q off
 * its line by 2.8e-17 (away from the apex w, whose triangle is obtuse at u: w lies 0.125 beyond
 * u along the line and 1.6e-4 beside it).  The heights test passes (q is 1e-13 of w's height
 * off the line), yet the new edge w-q is not locally Delaunay: v lies inside the circle through
 * u, q and w, so the split must be refused.  Coordinates of ./pbw -np 3 -q 0 -S 20000 on
 * tests/fuzz/regress/pbw_split_off_line.poly, where such a split left a non-Delaunay edge in
 * the mesh in about 1 run in 5; the same point on the line, or the triangle on the other side
 * of it, is fine. */
START_TEST(test_off_line_fan) {
    geom_init();
    const double u[2] = {0.40340741764246874, 2.9801129667020491e-08},
                 v[2] = {0.40340741737109354, 4.2854608750531042e-14},
                 q[2] = {0.40340741750678116, 1.4900586260814627e-08},
                 w[2] = {0.40438381260153444, 0.12499618655128918};
    ck_assert(geom_orient2d(u, v, q) * geom_orient2d(u, v, w) < 0);    /* q away from w */
    ck_assert(geom_incircle(u, q, w, v) * geom_orient2d(u, q, w) > 0); /* v in circle(u, q, w) */
    ck_assert_int_eq(mesh_rules_off_line(u, v, q, w, NULL), 0); /* the heights alone pass it */
    ck_assert_int_eq(mesh_rules_off_line_fan(u, v, q, w, NULL), 1);
    ck_assert_int_eq(mesh_rules_off_line_fan(v, u, q, NULL, w),
                     1); /* either direction, either slot */
    /* the same shape in round numbers: w 100 beyond u along the line, 1 beside it */
    const double U[2] = {0, 0}, V[2] = {8, 0}, W[2] = {-100, 1};
    const double away2[2] = {4, -0.002}, away1[2] = {4, -0.001}, toward[2] = {4, 0.002},
                 on[2] = {4, 0};
    ck_assert_int_eq(mesh_rules_off_line_fan(U, V, away2, W, NULL), 1);  /* V inside: refused */
    ck_assert_int_eq(mesh_rules_off_line_fan(U, V, away1, W, NULL), 0);  /* V outside */
    ck_assert_int_eq(mesh_rules_off_line_fan(U, V, toward, W, NULL), 0); /* reflex at q: Delaunay */
    ck_assert_int_eq(mesh_rules_off_line_fan(U, V, on, W, NULL), 0);
    ck_assert_int_eq(mesh_rules_off_line_fan(U, V, away2, NULL, NULL), 0); /* no apex, no test */
}
END_TEST

/* The fuzz finding behind the rule: a point set 8.9e17 long and 70 high.  Refinement must not
 * put a vertex outside the hull: the mesh's area is the hull's, and the validator accepts it. */
START_TEST(test_sliver_hull) {
    geom_init();
    char path[] = "/tmp/unit_mesh_sliverXXXXXX.node";
    int fd = mkstemps(path, 5);
    ck_assert_int_ge(fd, 0);
    FILE *f = fdopen(fd, "w");
    fputs("3 2 0 0\n1 1 0\n2 9 0\n3 888888888888884970.1 70\n", f);
    fclose(f);
    for (int q = 0; q <= 30; q += 30) {
        mesh m;
        mesh_init(&m);
        pslg g;
        char err[256];
        ck_assert_int_eq(pslg_read(path, &g, err, sizeof err), 0);
        ck_assert_int_eq(pslg_check(&g, err, sizeof err), 0);
        ck_assert_int_eq(mesh_build_cdt(&m, &g, NULL, err, sizeof err), 0);
        mesh_quality mq = {q * (1 + 1e-9), 0, -1, 1, 0};
        mesh_set_quality(&m, &mq);
        mesh_refine(&m);
        double area = ldexp(mesh_area(&m), -2 * g.scale_exp); /* in the input's units */
        ck_assert_msg(fabs(area - 280) <= 280 * 1e-9, "-q %d: area %.17g, hull 280", q, area);
        mesh_free(&m);
        pslg_free(&g);
    }
    unlink(path);
}
END_TEST

/* MESH_FENCE (PBW's roles in tf bits 5..7) and links below -1 (PBW's edges to another rank):
 * a cavity that reaches either stops with CAV_FENCED and leaves nothing marked; without them
 * the same cavity is collected. */
START_TEST(test_cavity_fence) {
    const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5, 0.2, 0.8, 0.8, 0.2};
    mesh m;
    mesh_init(&m);
    char err[256];
    ck_assert_int_eq(mesh_build_delaunay(&m, 7, xy, err, sizeof err), 0);
    const double p[2] = {0.52, 0.49}; /* near the centre vertex: its star is the cavity */
    int32_t t0 = mesh_locate(&m, p, -1);
    ck_assert_int_ge(t0, 0);
    ck_assert_int_eq(mesh_cavity_collect(&m, p, t0, -1, NULL), CAV_OK);
    int32_t ncav = m.ncav;
    ck_assert_int_ge(ncav, 2);
    int32_t other = m.cav[ncav - 1];
    mesh_cavity_abort(&m);
    for (int k = 0; k < 2; k++) {
        int32_t e = -1;
        if (k == 0) {
            m.tf[other] |= 0x40; /* a role on a member */
        } else {
            for (int j = 0; j < 3 && e < 0; j++) /* the start's edge links to another rank */
                if (m.tn[3 * t0 + j] >= 0) e = 3 * t0 + j;
            ck_assert_int_ge(e, 0);
        }
        int32_t save = e >= 0 ? m.tn[e] : 0;
        if (e >= 0) m.tn[e] = -7;
        ck_assert_int_eq(mesh_cavity_collect(&m, p, t0, -1, NULL), CAV_FENCED);
        mesh_cavity_abort(&m);
        for (int32_t t = 0; t < m.nt; t++)
            ck_assert_int_eq(m.tf[t] & MESH_MARK, 0);
        if (e >= 0) m.tn[e] = save;
        m.tf[other] &= (uint8_t)~MESH_FENCE;
    }
    ck_assert_int_eq(mesh_cavity_collect(&m, p, t0, -1, NULL), CAV_OK);
    ck_assert_int_eq(m.ncav, ncav);
    mesh_cavity_abort(&m);
    mesh_free(&m);
}
END_TEST

/* The plain statement of the quality test (edge j: p[j] -> p[j+1]; the shortest edge's apex
 * angle against the bound on squared lengths; the area), branches and all. */
static int plain_bad(const mesh_rules *R, double max_area, const double *const p[3], int *sh,
                     double *short2) {
    double ex[3], ey[3], l[3];
    for (int j = 0; j < 3; j++) {
        ex[j] = p[(j + 1) % 3][0] - p[j][0];
        ey[j] = p[(j + 1) % 3][1] - p[j][1];
        l[j] = ex[j] * ex[j] + ey[j] * ey[j];
    }
    int j = (l[0] <= l[1] && l[0] <= l[2]) ? 0 : (l[1] <= l[2]) ? 1 : 2;
    *sh = j;
    *short2 = l[j];
    int res = 0;
    if (R->cosb < 1.0) {
        int a = (j + 1) % 3, b = (j + 2) % 3;
        double dot = -(ex[a] * ex[b] + ey[a] * ey[b]);
        if (dot > 0 && dot * dot > R->cosb * R->cosb * l[a] * l[b]) res = MESH_BAD_ANGLE;
    }
    if (max_area > 0) {
        double area = 0.5 * (ex[0] * -ey[2] - ey[0] * -ex[2]);
        if (area > max_area) res |= MESH_BAD_AREA;
    }
    return res;
}

/* mesh_rules_bad_bound (branch-free, evaluated at all three apexes) decides as the plain
 * statement, bit for bit, with the same shortest edge: random triangles, triangles whose
 * smallest angle is the bound up to an ulp or two, isosceles and equilateral ones (ties
 * between edges), and degenerate ones, at several bounds, with and without an area bound. */
START_TEST(test_quality_rule) {
    srand(12345);
    const double bounds[] = {0, 20.7, 30, 33.8, 60};
    int nbad = 0, ngood = 0;
    for (int bi = 0; bi < 5; bi++) {
        mesh_rules R;
        mesh_rules_init(&R, bounds[bi], 0, 1, 0);
        double b = bounds[bi] * M_PI / 180;
        for (int i = 0; i < 20000; i++) {
            double a[2], c[2], d[2];
            int kind = i % 4;
            a[0] = rand() / (double)RAND_MAX, a[1] = rand() / (double)RAND_MAX;
            if (kind == 0) { /* anywhere */
                c[0] = rand() / (double)RAND_MAX, c[1] = rand() / (double)RAND_MAX;
                d[0] = rand() / (double)RAND_MAX, d[1] = rand() / (double)RAND_MAX;
            } else { /* apex angle at a near the bound (or 60), two long sides of equal or
                        near-equal length: the shortest edge and the verdict are near ties */
                double th = 2 * M_PI * rand() / (double)RAND_MAX, L = 0.5;
                double ang = (bi == 0 ? M_PI / 3 : b) * (1 + (rand() % 5 - 2) * 0x1p-52);
                double L2 = kind == 1 ? L : L * (1 + (rand() % 3 - 1) * 0x1p-50);
                c[0] = a[0] + L * cos(th), c[1] = a[1] + L * sin(th);
                d[0] = a[0] + L2 * cos(th + ang), d[1] = a[1] + L2 * sin(th + ang);
                if (kind == 3)
                    d[0] = a[0], d[1] = a[1] + (i % 8 == 3 ? 0 : 1e-300); /* degenerate */
            }
            const double *p[3] = {a, c, d};
            if (geom_orient2d(a, c, d) < 0) p[1] = d, p[2] = c;
            for (int ar = 0; ar < 2; ar++) {
                double max_area = ar ? 0.01 : 0;
                int sh1 = -1, sh2 = -2;
                double l1 = -1, l2 = -2;
                int r1 = mesh_rules_bad_bound(&R, max_area, p, &sh1, &l1);
                int r2 = plain_bad(&R, max_area, p, &sh2, &l2);
                ck_assert_int_eq(r1, r2);
                ck_assert_int_eq(sh1, sh2);
                ck_assert(l1 == l2);
                if (r1 & MESH_BAD_ANGLE)
                    nbad++;
                else
                    ngood++;
            }
        }
    }
    ck_assert_int_gt(nbad, 1000); /* both verdicts were exercised */
    ck_assert_int_gt(ngood, 1000);
}
END_TEST

/* mesh_build_from_triangles: a CDT's own triangles give back a valid mesh that refines as the CDT
 * does; triangles that are not a triangulation of the PSLG are refused: one turned clockwise,
 * one missing (a boundary edge that is no segment), one repeated (an edge in three triangles),
 * a segment that is no edge. */
START_TEST(test_from_triangles) {
    const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.4, 0.3, 0.7};
    pslg g = make_pslg(6, xy, 4, square_seg, 0, NULL);
    char err[512];
    ck_assert_msg(pslg_check(&g, err, sizeof err) == 0, "pslg_check: %s", err);
    mesh c;
    mesh_init(&c);
    ck_assert_msg(mesh_build_cdt(&c, &g, NULL, err, sizeof err) == 0, "cdt: %s", err);
    int32_t n = 0, *tri = malloc(3 * (size_t)c.nt * sizeof(int32_t) + 12);
    for (int32_t t = 0; t < c.nt; t++)
        if (mesh_tri_alive(&c, t)) memcpy(tri + 3 * n++, c.tv + 3 * t, 3 * sizeof(int32_t));
    mesh_free(&c);
    mesh m;
    mesh_init(&m);
    ck_assert_msg(mesh_build_from_triangles(&m, &g, NULL, n, tri, err, sizeof err) == 0,
                  "from triangles: %s", err);
    validate(&m, &g, 0, 0);
    mesh_quality mq = {30, 0.001, 2000000, 1, 0};
    mesh_set_quality(&m, &mq);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
    validate(&m, &g, 30, 0.001);
    mesh_free(&m);
    for (int fault = 0; fault < 4; fault++) {
        int32_t k = n, *t2 = malloc(3 * ((size_t)n + 1) * sizeof(int32_t));
        memcpy(t2, tri, 3 * (size_t)n * sizeof(int32_t));
        /* fault 3: the square and one more segment between two vertices that no triangle
         * joins (none lies on it: the interior points are not collinear with a corner) */
        int32_t seg5[10];
        memcpy(seg5, square_seg, 8 * sizeof(int32_t));
        for (int32_t a = 0, found = 0; fault == 3 && a < 6 && !found; a++)
            for (int32_t b = a + 1; b < 6 && !found; b++) {
                int edge = (b == a + 1 && b < 4) || (a == 0 && b == 3);
                for (int32_t i = 0; i < n && !edge; i++)
                    for (int j = 0; j < 3; j++)
                        edge |= (tri[3 * i + j] == a && tri[3 * i + (j + 1) % 3] == b) ||
                                (tri[3 * i + j] == b && tri[3 * i + (j + 1) % 3] == a);
                if (!edge) seg5[8] = a, seg5[9] = b, found = 1;
            }
        pslg h = make_pslg(6, xy, fault == 3 ? 5 : 4, seg5, 0, NULL);
        ck_assert_int_eq(pslg_check(&h, err, sizeof err), 0);
        if (fault == 0) { /* clockwise */
            int32_t x = t2[0];
            t2[0] = t2[1];
            t2[1] = x;
        } else if (fault == 1) { /* one missing */
            k = n - 1;
        } else if (fault == 2) { /* one repeated */
            memcpy(t2 + 3 * n, t2, 3 * sizeof(int32_t));
            k = n + 1;
        }
        mesh_init(&m);
        err[0] = '\0';
        int rc = mesh_build_from_triangles(&m, &h, NULL, k, t2, err, sizeof err);
        ck_assert_msg(rc != 0, "fault %d: triangles accepted", fault);
        /* a missing triangle leaves a boundary edge that is no segment, or a segment no edge */
        const char *want[] = {"counter-clockwise", "edge", "more than two", "no edge"};
        ck_assert_msg(strstr(err, want[fault]) != NULL, "fault %d: refused with '%s'", fault, err);
        mesh_free(&m);
        pslg_free(&h);
        free(t2);
    }
    free(tri);
    pslg_free(&g);
}
END_TEST

static Suite *suite(void) {
    Suite *s = suite_create("mesh");
    TCase *tc = tcase(s, "delaunay");
    tcase_add_test(tc, test_square_points);
    tcase_add_test(tc, test_collinear);
    tcase_add_test(tc, test_lattice_cocircular);
    tcase_add_loop_test(tc, test_random_points, 0, 2);
    tcase_add_test(tc, test_cavity_fence);
    tcase_add_test(tc, test_quality_rule);
    tc = tcase(s, "cdt");
    tcase_add_test(tc, test_triangle_pslg);
    tcase_add_test(tc, test_square_pslg);
    tcase_add_test(tc, test_polygon_with_hole);
    tcase_add_test(tc, test_vertex_on_segment);
    tcase_add_test(tc, test_long_segment);
    tcase_add_test(tc, test_bad_input);
    tcase_add_test(tc, test_small_angles);
    tcase_add_test(tc, test_iface_corner);
    tcase_add_test(tc, test_iface_point);
    tcase_add_test(tc, test_area_drift);
    tcase_add_test(tc, test_sliver_hull);
    tcase_add_test(tc, test_off_line_fan);
    tcase_add_test(tc, test_from_triangles);
    tc = tcase(s, "random");
    tcase_add_loop_test(tc, test_random_pslg, 0, 6);
    tc = tcase(s, "hooks");
    tcase_add_test(tc, test_named_split);
    tcase_add_test(tc, test_named_split_at_limit);
    tcase_add_test(tc, test_two_halves);
    tcase_add_test(tc, test_regions_keep);
    tc = tcase(s, "data");
    tcase_add_test(tc, test_data_files);
    return s;
}

int main(void) {
    return ck_run(suite());
}
