// ranks: 1 2 3 4
/* mpi_pextra: Check suite for the derived outputs of a distributed mesh (mesher/par/pextra.h):
 * the same mesh written whole by one process (meshio_write_extras) and in parts by every rank
 * (par_write_extras) must give the same .edge, .neigh and -o2 files as sets keyed by exact
 * coordinates, whatever the parts.
 *
 * Every rank meshes data/lake.poly with the sequential mesher (deterministic: the same mesh F
 * everywhere) and keeps a share of F's triangles as its part, in a local numbering of its own
 * (reversed), listing the subsegments of its triangles' sides (so an input segment between two
 * parts is listed by both).  Two shares: slabs by centroid (parts meet along chains of edges)
 * and triangles dealt out by a hash (parts meet everywhere, edges between ranks are most
 * edges).  Rank 0 writes F with meshio_write_extras, all ranks write their parts with
 * par_number + par_write_extras; rank 0 reads both sets of files and compares: every edge with
 * its marker, every (triangle, corner) with the edge opposite it and the neighbour across it,
 * every (triangle, corner) with the -o2 node opposite it.  The Gmsh file must exist whole.
 * CK_NOFORK (MPI does not survive fork); run from the repository root.
 */
#include "base/base.h"
#include "bounds/bounds.h"
#include "check_run.h"
#include "geom/geom.h"
#include "io/xwrite.h"
#include "par/par.h"
#include "par/pextra.h"
#include "par/pout.h"
#include "rt.h"
#include "seq/mesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int all_true(int local) {
    int g = 0;
    MPI_Allreduce(&local, &g, 1, MPI_INT, MPI_LAND, rt_app_comm());
    return g;
}

static uint64_t bits(double x) {
    uint64_t u;
    if (x == 0) x = 0;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* ---- a part of F ------------------------------------------------------------------------- */

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

static void make_part(const mesh_flat *F, int how, mesh_flat *p) {
    int rank = rt_rank(), P = rt_size();
    double x0 = F->xy[0], x1 = F->xy[0];
    for (int32_t v = 0; v < F->nverts; v++) {
        if (F->xy[2 * v] < x0) x0 = F->xy[2 * v];
        if (F->xy[2 * v] > x1) x1 = F->xy[2 * v];
    }
    int64_t *skey = malloc(((size_t)F->nsegs + 1) * 2 * sizeof(int64_t));
    for (int32_t s = 0; s < F->nsegs; s++) {
        int64_t a = F->seg[2 * s], b = F->seg[2 * s + 1];
        skey[2 * s] = (a < b ? a : b) << 32 | (a < b ? b : a);
        skey[2 * s + 1] = F->smarker ? F->smarker[s] : 0;
    }
    qsort(skey, (size_t)F->nsegs, 2 * sizeof *skey, cmp_i64);
    int32_t *map = malloc(((size_t)F->nverts + 1) * sizeof(int32_t));
    for (int32_t v = 0; v < F->nverts; v++)
        map[v] = -1;
    memset(p, 0, sizeof *p);
    p->tri = malloc((3 * (size_t)F->ntris + 1) * sizeof(int32_t));
    p->seg = malloc((6 * (size_t)F->ntris + 1) * sizeof(int32_t));
    p->smarker = malloc((3 * (size_t)F->ntris + 1) * sizeof(int32_t));
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
            const int64_t *hit = bsearch(&key, skey, (size_t)F->nsegs, 2 * sizeof *skey, cmp_i64);
            if (hit) {
                p->seg[2 * p->nsegs] = (int32_t)a;
                p->seg[2 * p->nsegs + 1] = (int32_t)b;
                p->smarker[p->nsegs++] = (int32_t)hit[1];
            }
        }
        memcpy(p->tri + 3 * p->ntris, F->tri + 3 * t, 3 * sizeof(int32_t));
        p->ntris++;
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

/* ---- reading the files back -------------------------------------------------------------- */

#define MAXCOL 12

typedef struct rows {
    int64_t n;
    double *v; /* MAXCOL per row; row 0 the header */
} rows;

static rows read_rows(const char *path) {
    FILE *f = fopen(path, "r");
    ck_assert_msg(f != NULL, "cannot open %s", path);
    rows r = {0, NULL};
    size_t cap = 0;
    char line[1024];
    while (fgets(line, sizeof line, f)) {
        char *h = strchr(line, '#');
        if (h) *h = '\0';
        double row[MAXCOL] = {0};
        int k = 0;
        for (char *s = strtok(line, " \t\n"); s && k < MAXCOL; s = strtok(NULL, " \t\n"))
            row[k++] = strtod(s, NULL);
        if (!k) continue;
        MESH_GROW(r.v, (size_t)(r.n + 1) * MAXCOL, cap);
        memcpy(r.v + r.n * MAXCOL, row, sizeof row);
        r.n++;
    }
    fclose(f);
    return r;
}

static int cmp_words(const void *a, const void *b, size_t n) {
    const uint64_t *x = a, *y = b;
    for (size_t i = 0; i < n; i++)
        if (x[i] != y[i]) return x[i] < y[i] ? -1 : 1;
    return 0;
}

static size_t g_words; /* record width for qsort */
static int cmp_rec(const void *a, const void *b) {
    return cmp_words(a, b, g_words);
}

/* Sorts k points (2 words each) in place. */
static void sort_points(uint64_t *r, int k) {
    for (int i = 1; i < k; i++)
        for (int j = i; j > 0 && cmp_words(r + 2 * j - 2, r + 2 * j, 2) > 0; j--)
            for (int w = 0; w < 2; w++) {
                uint64_t t = r[2 * j - 2 + w];
                r[2 * j - 2 + w] = r[2 * j + w];
                r[2 * j + w] = t;
            }
}

/* The records of one set of files, sorted: kind 0 edges (5 words: ends, marker), 1 neighbour
 * relations (16 words: triangle, edge opposite corner j, neighbour or zeros), 2 -o2 nodes (10
 * words: triangle, corner j, node opposite). */
static uint64_t *records(const char *prefix, int kind, int64_t *n, size_t *w) {
    char p[400];
    snprintf(p, sizeof p, "%s.node", prefix);
    rows nd = read_rows(p);
    int64_t nn = (int64_t)nd.v[0];
    double *xy = calloc(2 * (size_t)nn + 2, sizeof(double));
    for (int64_t i = 1; i <= nn; i++) {
        int64_t k = (int64_t)nd.v[i * MAXCOL];
        ck_assert(k >= 1 && k <= nn);
        xy[2 * k] = nd.v[i * MAXCOL + 1];
        xy[2 * k + 1] = nd.v[i * MAXCOL + 2];
    }
    snprintf(p, sizeof p, "%s.ele", prefix);
    rows el = read_rows(p);
    int64_t nt = (int64_t)el.v[0];
    uint64_t *tk = malloc((size_t)(nt + 1) * 6 * sizeof(uint64_t));
    for (int64_t t = 0; t < nt; t++) {
        for (int j = 0; j < 3; j++) {
            int64_t v = (int64_t)el.v[(t + 1) * MAXCOL + 1 + j];
            tk[6 * t + 2 * j] = bits(xy[2 * v]);
            tk[6 * t + 2 * j + 1] = bits(xy[2 * v + 1]);
        }
        sort_points(tk + 6 * t, 3);
    }
    uint64_t *out = NULL;
    if (kind == 0) {
        snprintf(p, sizeof p, "%s.edge", prefix);
        rows ed = read_rows(p);
        *n = (int64_t)ed.v[0];
        *w = 5;
        out = calloc((size_t)(*n + 1) * 5, sizeof(uint64_t));
        for (int64_t i = 0; i < *n; i++) {
            const double *r = ed.v + (i + 1) * MAXCOL;
            uint64_t *o = out + 5 * i;
            for (int j = 0; j < 2; j++) {
                o[2 * j] = bits(xy[2 * (int64_t)r[1 + j]]);
                o[2 * j + 1] = bits(xy[2 * (int64_t)r[1 + j] + 1]);
            }
            sort_points(o, 2);
            o[4] = (uint64_t)(int64_t)r[3];
        }
        free(ed.v);
    } else {
        rows ng = {0, NULL};
        if (kind == 1) {
            snprintf(p, sizeof p, "%s.neigh", prefix);
            ng = read_rows(p);
        }
        *n = 3 * nt;
        *w = kind == 1 ? 16 : 10;
        out = calloc((size_t)(*n + 1) * *w, sizeof(uint64_t));
        for (int64_t t = 0; t < nt; t++)
            for (int j = 0; j < 3; j++) {
                uint64_t *o = out + (size_t)(3 * t + j) * *w;
                const double *er = el.v + (t + 1) * MAXCOL;
                memcpy(o, tk + 6 * t, 6 * sizeof(uint64_t));
                if (kind == 1) {
                    for (int k = 0; k < 2; k++) {
                        int64_t v = (int64_t)er[1 + (j + 1 + k) % 3];
                        o[6 + 2 * k] = bits(xy[2 * v]);
                        o[7 + 2 * k] = bits(xy[2 * v + 1]);
                    }
                    sort_points(o + 6, 2);
                    int64_t nb = (int64_t)ng.v[(t + 1) * MAXCOL + 1 + j];
                    if (nb > 0) memcpy(o + 10, tk + 6 * (nb - 1), 6 * sizeof(uint64_t));
                } else {
                    int64_t c = (int64_t)er[1 + j], m = (int64_t)er[4 + j];
                    o[6] = bits(xy[2 * c]);
                    o[7] = bits(xy[2 * c + 1]);
                    o[8] = bits(xy[2 * m]);
                    o[9] = bits(xy[2 * m + 1]);
                }
            }
        free(ng.v);
    }
    g_words = *w;
    qsort(out, (size_t)*n, *w * sizeof(uint64_t), cmp_rec);
    free(nd.v);
    free(el.v);
    free(xy);
    free(tk);
    return out;
}

/* ---- the test ---------------------------------------------------------------------------- */

static void mesh_input(pslg *in, mesh_flat *F) {
    char err[512];
    geom_init();
    ck_assert_msg(pslg_read("data/lake.poly", in, err, sizeof err) == 0, "%s", err);
    ck_assert_msg(pslg_check(in, err, sizeof err) == 0, "%s", err);
    mesh m;
    mesh_init(&m);
    ck_assert_msg(mesh_build_cdt(&m, in, NULL, err, sizeof err) == 0, "%s", err);
    mesh_quality q = {bounds_refine_angle(30), 0.005, -1, 1, 0};
    mesh_set_quality(&m, &q);
    ck_assert_int_eq(mesh_refine(&m), MESH_REFINE_DONE);
    ck_assert_int_eq(mesh_to_flat(&m, F), 0);
    mesh_free(&m);
}

static void compare(int how) {
    int rank = rt_rank();
    pslg in;
    mesh_flat F, part;
    mesh_input(&in, &F);
    for (int32_t s = 0; s < F.nsegs; s++) /* markers 0 and 2 alternate: both rules are used */
        F.smarker[s] = (s % 3 == 0) ? 0 : 2;
    make_part(&F, how, &part);
    part.scale_exp = F.scale_exp = in.scale_exp;
    char dir[256] = "";
    if (rank == 0) {
        snprintf(dir, sizeof dir, "%s/mpi_pextra.XXXXXX",
                 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
        ck_assert_ptr_nonnull(mkdtemp(dir));
    }
    MPI_Bcast(dir, sizeof dir, MPI_CHAR, 0, rt_app_comm());
    char pp[300], sp[300], msh[300], err[512];
    snprintf(pp, sizeof pp, "%s/p", dir);
    snprintf(sp, sizeof sp, "%s/s", dir);
    snprintf(msh, sizeof msh, "%s/p.msh", dir);
    int ok = 1;
    if (rank == 0) {
        mesh_xreq r = {sp, 1, 1, 1, NULL, NULL, 0, NULL};
        ok = meshio_write_extras(&F, &r, err, sizeof err) == 0;
        if (!ok) fprintf(stderr, "mpi_pextra: %s\n", err);
    }
    ck_assert_int_eq(all_true(ok), 1);
    par_opts o;
    memset(&o, 0, sizeof o);
    o.prog = "mpi_pextra";
    o.out_prefix = pp;
    o.edges = o.neighbors = o.order2 = 1;
    o.msh = msh;
    par_numbering num;
    ck_assert_int_eq(par_number(&part, &in, NULL, &num, err, sizeof err), 0);
    ck_assert_int_eq(par_write_extras(&o, NULL, &in, &part, NULL, &num), 0);
    int good = 1; /* decided on rank 0, asserted on every rank (no rank left in a collective) */
    if (rank == 0) {
        static const char *const what[3] = {"edges and markers", "neighbours", "-o2 nodes"};
        for (int kind = 0; kind < 3; kind++) {
            int64_t na, nb;
            size_t wa, wb;
            uint64_t *a = records(sp, kind, &na, &wa), *b = records(pp, kind, &nb, &wb);
            if (na != nb || memcmp(a, b, (size_t)na * wa * sizeof(uint64_t)) != 0) {
                fprintf(stderr, "mpi_pextra: %s differ: %lld sequential, %lld parallel\n",
                        what[kind], (long long)na, (long long)nb);
                good = 0;
            }
            free(a);
            free(b);
        }
        FILE *f = fopen(msh, "r");
        char tail[64] = "";
        if (!f || fseek(f, -13, SEEK_END) != 0 || !fgets(tail, sizeof tail, f) ||
            strcmp(tail, "$EndElements\n") != 0) {
            fprintf(stderr, "mpi_pextra: %s: not whole\n", msh);
            good = 0;
        }
        if (f) fclose(f);
    }
    ck_assert_int_eq(all_true(good), 1);
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

START_TEST(test_slabs) {
    compare(0);
}
END_TEST

START_TEST(test_scattered) {
    compare(1);
}
END_TEST

int main(int argc, char **argv) {
    if (rt_init(&argc, &argv, NULL) != RT_OK) return 1;
    int rc = ck_run_mpi(ck_suite("mpi_pextra", 120, CK_TESTS(test_slabs, test_scattered)),
                        rt_app_comm());
    rt_finalize();
    return rc;
}
