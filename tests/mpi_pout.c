// ranks: 1 2 4 8
/* mpi_pout: Check suite for the output of a distributed mesh without a gather (mesher/par/pout.h).
 *
 * Every rank meshes data/lake.poly with the sequential mesher (deterministic: the same mesh F on
 * every rank), keeps a share of F's triangles as its part (local numbering reversed, so only
 * coordinates can match vertices; every subsegment listed once per triangle side, so a part may
 * list one twice and two parts may list the same one), and then:
 *  - round trip: par_number + par_write_parts (-o, MPI-IO) write PREFIX.node/.ele/.poly; rank 0
 *    reads them back (meshio_read_triangle) and finds exactly F's triangles and subsegments as
 *    sets of exact coordinates (so files written by 1, 2, 4 and 8 ranks are equal to each
 *    other), the input vertices first under their input numbers, and the validator accepts them;
 *  - the distributed check (par_check_parts) passes, and fails on every rank when one part is
 *    broken (PCDM_TEST_BREAK_PIECE);
 *  - --vtk writes the .pvtu index and one piece per rank;
 *  - the interface local-Delaunay test finds a non-Delaunay edge between two ranks' triangles
 *    and exempts a constraint;
 *  - the always-on interface check finds a T-junction and an unlisted boundary edge, at one rank
 *    and across ranks, and passes a whole mesh.
 * Two shares: slabs by centroid (parts meet along chains of edges) and triangles dealt out by
 * a hash (parts meet everywhere, also at single vertices).  Results are reduced over ranks
 * before asserting.  CK_NOFORK (MPI does not survive fork); run from the repository root.
 */
#include "base/base.h"
#include "bounds/bounds.h"
#include "check/par_check.h"
#include "check_run.h"
#include "geom/geom.h"
#include "par/par.h"
#include "par/pout.h"
#include "rt.h"
#include "seq/mesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define QDEG 30.0
#define AREA 0.002

static int all_true(int local) {
    int g = 0;
    MPI_Allreduce(&local, &g, 1, MPI_INT, MPI_LAND, rt_app_comm());
    return g;
}

static uint64_t bits(double x) {
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static int cmp_u64x(const void *a, const void *b, size_t n) {
    const uint64_t *x = a, *y = b;
    for (size_t i = 0; i < n; i++)
        if (x[i] != y[i]) return x[i] < y[i] ? -1 : 1;
    return 0;
}
static int cmp6(const void *a, const void *b) {
    return cmp_u64x(a, b, 6);
}
static int cmp4(const void *a, const void *b) {
    return cmp_u64x(a, b, 4);
}

/* Sorts the k points (2 words each) of rec in place, then returns it. */
static void sort_points(uint64_t *rec, int k) {
    for (int i = 1; i < k; i++)
        for (int j = i; j > 0 && cmp_u64x(rec + 2 * j - 2, rec + 2 * j, 2) > 0; j--) {
            uint64_t t0 = rec[2 * j - 2], t1 = rec[2 * j - 1];
            rec[2 * j - 2] = rec[2 * j];
            rec[2 * j - 1] = rec[2 * j + 1];
            rec[2 * j] = t0;
            rec[2 * j + 1] = t1;
        }
}

/* The triangles (6 words) or segments (4 words) of m as a sorted array of exact coordinates. */
static uint64_t *coord_set(const mesh_flat *m, int tris) {
    int k = tris ? 3 : 2;
    int32_t n = tris ? m->ntris : m->nsegs;
    const int32_t *ix = tris ? m->tri : m->seg;
    uint64_t *s = malloc((size_t)(n + 1) * 2 * (size_t)k * sizeof(uint64_t));
    for (int32_t i = 0; i < n; i++) {
        uint64_t *r = s + (size_t)i * 2 * (size_t)k;
        for (int j = 0; j < k; j++) {
            r[2 * j] = bits(m->xy[2 * ix[k * i + j]]);
            r[2 * j + 1] = bits(m->xy[2 * ix[k * i + j] + 1]);
        }
        sort_points(r, k);
    }
    qsort(s, (size_t)n, 2 * (size_t)k * sizeof(uint64_t), tris ? cmp6 : cmp4);
    return s;
}

/* Rank of triangle t of F under share `how` (0: slabs by centroid x; 1: hashed). */
static int owner_of(const mesh_flat *F, int32_t t, int how, double x0, double x1, int P) {
    if (how == 1) return (int)(mesh_hash64((uint64_t)t * 0x9e3779b97f4a7c15ULL) % (uint64_t)P);
    double cx = 0;
    for (int j = 0; j < 3; j++)
        cx += F->xy[2 * F->tri[3 * t + j]] / 3;
    int r = (int)((cx - x0) / (x1 - x0) * P);
    return r < 0 ? 0 : r >= P ? P - 1 : r;
}

static int cmp_i64(const void *a, const void *b) {
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* This rank's part of F (see the file header). */
static void make_part(const mesh_flat *F, int how, mesh_flat *p) {
    int rank = rt_rank(), P = rt_size();
    double x0 = F->xy[0], x1 = F->xy[0];
    for (int32_t v = 0; v < F->nverts; v++) {
        if (F->xy[2 * v] < x0) x0 = F->xy[2 * v];
        if (F->xy[2 * v] > x1) x1 = F->xy[2 * v];
    }
    int64_t *skey = malloc(((size_t)F->nsegs + 1) * sizeof(int64_t));
    for (int32_t s = 0; s < F->nsegs; s++) {
        int64_t a = F->seg[2 * s], b = F->seg[2 * s + 1];
        skey[s] = (a < b ? a : b) << 32 | (a < b ? b : a);
    }
    qsort(skey, (size_t)F->nsegs, sizeof *skey, cmp_i64);
    int32_t *map = malloc(((size_t)F->nverts + 1) * sizeof(int32_t));
    for (int32_t v = 0; v < F->nverts; v++)
        map[v] = -1;
    memset(p, 0, sizeof *p);
    p->tri = malloc((3 * (size_t)F->ntris + 1) * sizeof(int32_t));
    p->trank = malloc(((size_t)F->ntris + 1) * sizeof(int32_t));
    p->seg = malloc((6 * (size_t)F->ntris + 1) * sizeof(int32_t));
    p->smarker = malloc((3 * (size_t)F->ntris + 1) * sizeof(int32_t));
    p->sinterface = calloc(3 * (size_t)F->ntris + 1, sizeof(int32_t));
    int32_t nv = 0;
    for (int32_t t = 0; t < F->ntris; t++) {
        if (owner_of(F, t, how, x0, x1, P) != rank) continue;
        for (int j = 0; j < 3; j++) {
            int32_t v = F->tri[3 * t + j];
            if (map[v] < 0) map[v] = nv++;
        }
        for (int j = 0; j < 3; j++) {
            int64_t a = F->tri[3 * t + j], b = F->tri[3 * t + (j + 1) % 3];
            int64_t key = (a < b ? a : b) << 32 | (a < b ? b : a);
            if (bsearch(&key, skey, (size_t)F->nsegs, sizeof *skey, cmp_i64)) {
                p->seg[2 * p->nsegs] = (int32_t)a;
                p->seg[2 * p->nsegs + 1] = (int32_t)b;
                p->smarker[p->nsegs++] = 1;
            }
        }
        memcpy(p->tri + 3 * p->ntris, F->tri + 3 * t, 3 * sizeof(int32_t));
        p->trank[p->ntris++] = rank;
    }
    p->nverts = nv;
    p->xy = malloc((2 * (size_t)nv + 1) * sizeof(double));
    p->vmarker = calloc((size_t)nv + 1, sizeof(int32_t));
    for (int32_t v = 0; v < F->nverts; v++)
        if (map[v] >= 0) { /* reversed local numbering */
            int32_t l = nv - 1 - map[v];
            map[v] = l;
            p->xy[2 * l] = F->xy[2 * v];
            p->xy[2 * l + 1] = F->xy[2 * v + 1];
        }
    for (int32_t i = 0; i < 3 * p->ntris; i++)
        p->tri[i] = map[p->tri[i]];
    for (int32_t i = 0; i < 2 * p->nsegs; i++)
        p->seg[i] = map[p->seg[i]];
    free(map);
    free(skey);
}

static void mesh_input(pslg *in, mesh_flat *F) {
    char err[512];
    geom_init();
    ck_assert_msg(pslg_read("data/lake.poly", in, err, sizeof err) == 0, "%s", err);
    ck_assert_msg(pslg_check(in, err, sizeof err) == 0, "%s", err);
    mesh m;
    mesh_init(&m);
    ck_assert_msg(mesh_build_cdt(&m, in, NULL, err, sizeof err) == 0, "%s", err);
    mesh_quality q = {bounds_refine_angle(QDEG), AREA, -1, 1, 0};
    mesh_set_quality(&m, &q);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
    ck_assert_int_eq(mesh_to_flat(&m, F), 0);
    mesh_free(&m);
}

static void roundtrip(int how) {
    int rank = rt_rank(), P = rt_size();
    pslg in;
    mesh_flat F, part;
    mesh_input(&in, &F);
    make_part(&F, how, &part);
    char dir[256] = "";
    if (rank == 0) {
        snprintf(dir, sizeof dir, "%s/mpi_pout.XXXXXX",
                 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
        ck_assert_ptr_nonnull(mkdtemp(dir));
    }
    MPI_Bcast(dir, sizeof dir, MPI_CHAR, 0, rt_app_comm());
    char prefix[300], vtk[300];
    snprintf(prefix, sizeof prefix, "%s/m", dir);
    snprintf(vtk, sizeof vtk, "%s/m.pvtu", dir);
    par_opts o;
    memset(&o, 0, sizeof o);
    o.prog = "mpi_pout";
    o.min_angle = QDEG;
    o.max_area = AREA;
    o.out_prefix = prefix;
    o.vtk = vtk;
    par_numbering num;
    char err[512];
    ck_assert_int_eq(par_number(&part, &in, NULL, &num, err, sizeof err), 0);
    ck_assert_int_eq(num.ntris, F.ntris);
    validate_report r;
    int ok = par_check_parts(&o, &in, &part, &num, 0, &r);
    if (!ok && rank == 0) fprintf(stderr, "mpi_pout: check: %s\n", r.first_problem);
    ck_assert_int_eq(all_true(ok), 1);
    ck_assert_int_eq(par_write_parts(&o, NULL, &in, &part, NULL, &num), 0);

    int good = 1;
    if (rank == 0) {
        mesh_flat R;
        ck_assert_msg(meshio_read_triangle(prefix, &R, err, sizeof err) == 0, "%s", err);
        ck_assert_int_eq(R.ntris, F.ntris);
        ck_assert_int_eq(R.nsegs, F.nsegs);
        ck_assert_int_eq(R.nverts, num.nverts);
        for (int32_t v = 0; v < in.nverts; v++) /* input vertices under their input numbers */
            ck_assert(bits(R.xy[2 * v]) == bits(in.xy[2 * v]) &&
                      bits(R.xy[2 * v + 1]) == bits(in.xy[2 * v + 1]));
        uint64_t *a = coord_set(&F, 1), *b = coord_set(&R, 1);
        ck_assert_msg(memcmp(a, b, 6 * sizeof(uint64_t) * (size_t)F.ntris) == 0,
                      "triangles differ from the sequential mesh's");
        free(a);
        free(b);
        a = coord_set(&F, 0);
        b = coord_set(&R, 0);
        ck_assert_msg(memcmp(a, b, 4 * sizeof(uint64_t) * (size_t)F.nsegs) == 0,
                      "segments differ from the sequential mesh's");
        free(a);
        free(b);
        validate_opts vo = {QDEG, AREA, 0, 0, 0, 0};
        validate_report vr;
        good = mesh_validate(&in, &R, &vo, &vr);
        if (!good) fprintf(stderr, "mpi_pout: read back: %s\n", vr.first_problem);
        mesh_flat_free(&R);
        char path[400];
        snprintf(path, sizeof path, "%s/m_%d.vtu", dir, P - 1);
        ck_assert_int_eq(access(vtk, R_OK), 0);
        ck_assert_int_eq(access(path, R_OK), 0);
    }
    ck_assert_int_eq(all_true(good), 1);

    /* a broken part fails the check on every rank */
    char who[16];
    snprintf(who, sizeof who, "%d", P - 1);
    setenv("PCDM_TEST_BREAK_PIECE", who, 1);
    int bad = !par_check_parts(&o, &in, &part, &num, 0, &r);
    unsetenv("PCDM_TEST_BREAK_PIECE");
    ck_assert_int_eq(all_true(bad), 1);
    ck_assert(r.bad_orient > 0 || r.bad_conform > 0);

    MPI_Barrier(rt_app_comm());
    if (rank == 0) {
        char cmd[400];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
        ck_assert_int_eq(system(cmd), 0);
    }
    par_numbering_free(&num);
    mesh_flat_free(&part);
    mesh_flat_free(&F);
    pslg_free(&in);
}

START_TEST(test_roundtrip_slabs) {
    roundtrip(0);
}
END_TEST

START_TEST(test_roundtrip_scattered) {
    roundtrip(1);
}
END_TEST

/* The interface local-Delaunay test: a quadrilateral P0 P1 P2 P3 whose diagonal P0-P2 is not
 * locally Delaunay (P3 lies inside the circle through P0, P1, P2) and whose diagonal P1-P3 is;
 * rank 0 holds one triangle, rank 1 the other (other ranks nothing).  Bad edges summed over the
 * ranks: 1 for P0-P2, 0 for P1-P3, 0 for P0-P2 listed as an input subsegment on both sides (a
 * constraint is exempt).  On one rank no edge lies between ranks: always 0. */
static long quad_bad(int diag, int constrained) {
    double xy[8] = {0, 0, 1, -1, 2, 0, 1, 0.3};
    int32_t tris[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{1, 2, 3}, {1, 3, 0}}};
    int32_t seg[2] = {0, 2}, sm[1] = {1}, si[1] = {0};
    int rank = rt_rank(), P = rt_size();
    mesh_flat f;
    memset(&f, 0, sizeof f);
    f.nverts = 4;
    f.xy = xy;
    int32_t both[6];
    if (P == 1) {
        memcpy(both, tris[diag][0], sizeof tris[diag][0]);
        memcpy(both + 3, tris[diag][1], sizeof tris[diag][1]);
        f.ntris = 2;
        f.tri = both;
    } else if (rank < 2) {
        f.ntris = 1;
        f.tri = tris[diag][rank];
    }
    if (constrained && f.ntris) {
        f.nsegs = 1;
        f.seg = seg;
        f.smarker = sm;
        f.sinterface = si;
    }
    char msg[256];
    long bad = par_check_interface_delaunay(&f, NULL, msg, sizeof msg), tot = 0;
    if (bad) fprintf(stderr, "rank %d: %s\n", rank, msg);
    MPI_Allreduce(&bad, &tot, 1, MPI_LONG, MPI_SUM, rt_app_comm());
    return tot;
}

/* The always-on interface check: a square (0,0) (2,0) (2,2) (0,2) cut along its diagonal, an
 * interface; at one rank both triangles are rank 0's, at more rank 0 holds one and rank 1 the
 * other.  Returns the ranks that found a disagreement: none for the whole square; with the
 * diagonal split on one side only (a T-junction at (1,1)), or a boundary edge that is listed as
 * no subsegment, some. */
static int square_bad(int fault) {
    double xy[10] = {0, 0, 2, 0, 2, 2, 0, 2, 1, 1};
    int32_t a[3] = {0, 1, 2}, b[3] = {0, 2, 3}, bsplit[6] = {0, 4, 3, 4, 2, 3};
    int32_t seg[14] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2, 0, 4, 4, 2};
    int32_t sm[7] = {1, 1, 1, 1, 0, 0, 0}, si[7] = {0, 0, 0, 0, 1, 1, 1};
    int rank = rt_rank(), P = rt_size();
    int32_t tri[9];
    mesh_flat f;
    memset(&f, 0, sizeof f);
    f.nverts = 5;
    f.xy = xy;
    f.tri = tri;
    f.seg = seg;
    f.smarker = sm;
    f.sinterface = si;
    f.nsegs = fault == 2 ? 6 : 7; /* fault 2: edge 0-1 unlisted (the list starts at 1-2) */
    if (fault == 2) f.seg = seg + 2, f.smarker = sm + 1, f.sinterface = si + 1;
    if (rank == 0) memcpy(tri, a, sizeof a), f.ntris = 1;
    if (rank == (P > 1)) { /* B: rank 1, or rank 0 beside A */
        memcpy(tri + 3 * f.ntris, fault == 1 ? bsplit : b, fault == 1 ? sizeof bsplit : sizeof b);
        f.ntris += fault == 1 ? 2 : 1;
    }
    if (rank > 1) f.ntris = 0;
    char msg[600] = "";
    int bad = par_check_interfaces_open(&f, NULL, msg, sizeof msg) != 0, tot = 0;
    if (bad) fprintf(stderr, "rank %d, fault %d: %s\n", rank, fault, msg);
    MPI_Allreduce(&bad, &tot, 1, MPI_INT, MPI_SUM, rt_app_comm());
    return tot;
}

START_TEST(test_interfaces_open) {
    int whole = square_bad(0), tee = square_bad(1), unlisted = square_bad(2);
    if (rt_rank() == 0)
        fprintf(stderr, "interfaces: ranks in disagreement %d (want 0), %d, %d (want > 0)\n", whole,
                tee, unlisted);
    ck_assert_int_eq(whole, 0);
    ck_assert_int_gt(tee, 0);
    ck_assert_int_gt(unlisted, 0);
}
END_TEST

START_TEST(test_interface_delaunay) {
    long want = rt_size() > 1 ? 1 : 0;
    long a = quad_bad(0, 0), b = quad_bad(1, 0), c = quad_bad(0, 1);
    if (rt_rank() == 0)
        fprintf(stderr, "interface delaunay: bad %ld (want %ld), %ld, %ld (want 0, 0)\n", a, want,
                b, c);
    ck_assert_int_eq(a, want);
    ck_assert_int_eq(b, 0);
    ck_assert_int_eq(c, 0);
}
END_TEST

int main(int argc, char **argv) {
    if (rt_init(&argc, &argv, NULL) != RT_OK) return 1;
    int rc = ck_run_mpi(ck_suite("mpi_pout", 0,
                                 CK_TESTS(test_roundtrip_slabs, test_roundtrip_scattered,
                                          test_interface_delaunay, test_interfaces_open)),
                        rt_app_comm());
    rt_finalize();
    return rc;
}
