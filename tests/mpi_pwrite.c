// ranks: 1 2 3 4 8
/* mpi_pwrite: Check suite for the parallel writers (mesher/io/pwrite.c) under MPI.
 *
 *  - a structured mesh split by rows over the ranks, written with meshio_pwrite_triangle, gives
 *    PREFIX.node/.ele/.poly byte-identical to what meshio_write_triangle writes for the whole
 *    mesh on one rank, and reads back (meshio_read_triangle) to the same doubles, bit for bit;
 *  - a write into a folder that does not exist fails on every rank with the same message and
 *    leaves no file behind;
 *  - meshio_pwrite_pvtu writes one .vtu piece per rank and a .pvtu naming them all.
 * Results are reduced over ranks before asserting, so no rank waits in a collective another
 * rank skipped.  Plain MPI (no runtime); CK_NOFORK, since MPI does not survive fork.
 */
#include "check_run.h"
#include "io/meshio.h"
#include "io/pwrite.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define NX 23
#define NY 37 /* rows of vertices; cells are split by the row of their lower side */

static char dir[256];

static int all_true(int local) {
    int g = 0;
    MPI_Allreduce(&local, &g, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    return g;
}

static double vx(int i, int j) {
    return i * 0.1 + j * (1.0 / 3.0) * 1e-3;
}
static double vy(int i, int j) {
    return j * 0.07 - i * 1e-17;
}

/* The rows of vertices [*j0, *j1) rank r owns. */
static void rows(int r, int size, int *j0, int *j1) {
    *j0 = (int)((long)NY * r / size);
    *j1 = (int)((long)NY * (r + 1) / size);
}

/* Fills the part of rank r (global numbering: vertex j * NX + i; cell (i, j) gives triangles
 * 2 * (j * (NX - 1) + i) and +1; one segment per horizontal edge of each row).  Arrays are
 * allocated here and freed by free_part. */
static void make_part(int r, int size, mesh_part *p, double **xy, int32_t **vm, int64_t **tri,
                      int32_t **tr, int64_t **seg, int32_t **sm) {
    int j0, j1;
    rows(r, size, &j0, &j1);
    int jc1 = j1 < NY - 1 ? j1 : NY - 1; /* cell rows [j0, jc1) */
    int64_t nv = (int64_t)(j1 - j0) * NX, nt = jc1 > j0 ? 2 * (int64_t)(jc1 - j0) * (NX - 1) : 0;
    int64_t ns = (int64_t)(j1 - j0) * (NX - 1);
    *xy = malloc(sizeof(double) * (size_t)(2 * nv + 1));
    *vm = malloc(sizeof(int32_t) * (size_t)(nv + 1));
    *tri = malloc(sizeof(int64_t) * (size_t)(3 * nt + 1));
    *tr = malloc(sizeof(int32_t) * (size_t)(nt + 1));
    *seg = malloc(sizeof(int64_t) * (size_t)(2 * ns + 1));
    *sm = malloc(sizeof(int32_t) * (size_t)(ns + 1));
    int64_t k = 0, t = 0, s = 0;
    for (int j = j0; j < j1; j++)
        for (int i = 0; i < NX; i++, k++) {
            (*xy)[2 * k] = vx(i, j);
            (*xy)[2 * k + 1] = vy(i, j);
            (*vm)[k] = (i == 0 || j == 0) ? 1 : 0;
        }
    for (int j = j0; j < jc1; j++)
        for (int i = 0; i < NX - 1; i++) {
            int64_t a = (int64_t)j * NX + i, b = a + 1, c = a + NX, d = c + 1;
            int64_t tv[6] = {a, b, d, a, d, c};
            for (int h = 0; h < 2; h++, t++) {
                for (int q = 0; q < 3; q++)
                    (*tri)[3 * t + q] = tv[3 * h + q];
                (*tr)[t] = r;
            }
        }
    for (int j = j0; j < j1; j++)
        for (int i = 0; i < NX - 1; i++, s++) {
            (*seg)[2 * s] = (int64_t)j * NX + i;
            (*seg)[2 * s + 1] = (int64_t)j * NX + i + 1;
            (*sm)[s] = j;
        }
    memset(p, 0, sizeof *p);
    p->nverts = nv;
    p->xy = *xy;
    p->vmarker = *vm;
    p->ntris = nt;
    p->tri = *tri;
    p->trank = *tr;
    p->nsegs = ns;
    p->seg = *seg;
    p->smarker = *sm;
}

/* The whole mesh as rank-ordered parts concatenated into one mesh_flat (same numbering). */
static void make_whole(int size, mesh_flat *f) {
    memset(f, 0, sizeof *f);
    f->xy = malloc(sizeof(double) * 2 * NX * NY);
    f->vmarker = malloc(sizeof(int32_t) * NX * NY);
    f->tri = malloc(sizeof(int32_t) * 6 * (NX - 1) * (NY - 1));
    f->trank = malloc(sizeof(int32_t) * 2 * (NX - 1) * (NY - 1));
    f->seg = malloc(sizeof(int32_t) * 2 * (NX - 1) * NY);
    f->smarker = malloc(sizeof(int32_t) * (NX - 1) * NY);
    for (int r = 0; r < size; r++) {
        mesh_part p;
        double *xy;
        int32_t *vm, *tr, *sm;
        int64_t *tri, *seg;
        make_part(r, size, &p, &xy, &vm, &tri, &tr, &seg, &sm);
        for (int64_t k = 0; k < p.nverts; k++, f->nverts++) {
            f->xy[2 * f->nverts] = xy[2 * k];
            f->xy[2 * f->nverts + 1] = xy[2 * k + 1];
            f->vmarker[f->nverts] = vm[k];
        }
        for (int64_t t = 0; t < p.ntris; t++, f->ntris++) {
            for (int q = 0; q < 3; q++)
                f->tri[3 * f->ntris + q] = (int32_t)tri[3 * t + q];
            f->trank[f->ntris] = tr[t];
        }
        for (int64_t s = 0; s < p.nsegs; s++, f->nsegs++) {
            f->seg[2 * f->nsegs] = (int32_t)seg[2 * s];
            f->seg[2 * f->nsegs + 1] = (int32_t)seg[2 * s + 1];
            f->smarker[f->nsegs] = sm[s];
        }
        free(xy), free(vm), free(tri), free(tr), free(seg), free(sm);
    }
}

/* 1 when the two files have the same bytes. */
static int same_file(const char *a, const char *b) {
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    int same = fa && fb;
    while (same) {
        int ca = fgetc(fa), cb = fgetc(fb);
        if (ca != cb) same = 0;
        if (ca == EOF || cb == EOF) break;
    }
    if (fa) fclose(fa);
    if (fb) fclose(fb);
    return same;
}

START_TEST(test_triangle_files) {
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mesh_part p;
    double *xy;
    int32_t *vm, *tr, *sm;
    int64_t *tri, *seg;
    make_part(rank, size, &p, &xy, &vm, &tri, &tr, &seg, &sm);
    char par[300], seq[300], err[512] = "";
    snprintf(par, sizeof par, "%s/par", dir);
    snprintf(seq, sizeof seq, "%s/seq", dir);
    int rc = meshio_pwrite_triangle(MPI_COMM_WORLD, NULL, &p, par, err, sizeof err);
    if (rc) fprintf(stderr, "rank %d: %s\n", rank, err);
    ck_assert_int_eq(all_true(rc == 0), 1);
    int ok = 1;
    if (rank == 0) {
        mesh_flat whole, back;
        make_whole(size, &whole);
        ok = meshio_write_triangle(&whole, seq, err, sizeof err) == 0;
        static const char *const ext[3] = {"node", "ele", "poly"};
        for (int e = 0; e < 3 && ok; e++) {
            char a[320], b[320];
            snprintf(a, sizeof a, "%s.%s", par, ext[e]);
            snprintf(b, sizeof b, "%s.%s", seq, ext[e]);
            if (!same_file(a, b)) {
                fprintf(stderr, "%s and %s differ\n", a, b);
                ok = 0;
            }
        }
        memset(&back, 0, sizeof back);
        if (ok && meshio_read_triangle(par, &back, err, sizeof err) != 0) {
            fprintf(stderr, "read back: %s\n", err);
            ok = 0;
        }
        if (ok)
            ok = back.nverts == whole.nverts && back.ntris == whole.ntris &&
                 memcmp(back.xy, whole.xy, sizeof(double) * 2 * (size_t)whole.nverts) == 0 &&
                 memcmp(back.tri, whole.tri, sizeof(int32_t) * 3 * (size_t)whole.ntris) == 0;
        mesh_flat_free(&whole);
        mesh_flat_free(&back);
    }
    free(xy), free(vm), free(tri), free(tr), free(seg), free(sm);
    ck_assert_int_eq(all_true(ok), 1);
}
END_TEST

/* The part in its other form (what pout.c passes): triangles as local ids through gid, the
 * vertices stored in reverse and picked through vsel, and on rank 0 the first HEAD vertices
 * from separate head arrays; written with tiny chunks (every record its own chunk, a few per
 * chunk, the header and trailer alone) and a few amounts of text kept from the counting pass,
 * the files must still equal the sequential writer's. */
#define HEAD 5
START_TEST(test_triangle_chunks) {
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    mesh_part p;
    double *xy;
    int32_t *vm, *tr, *sm;
    int64_t *tri, *seg;
    make_part(rank, size, &p, &xy, &vm, &tri, &tr, &seg, &sm);
    long long base = 0, mine = p.nverts;
    MPI_Exscan(&mine, &base, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0) base = 0;
    int64_t nh = rank == 0 && p.nverts >= HEAD ? HEAD : 0, nl = p.nverts - nh;
    double *rxy = malloc(sizeof(double) * (size_t)(2 * nl + 1));
    int32_t *rvm = malloc(sizeof(int32_t) * (size_t)(nl + 1));
    int32_t *sel = malloc(sizeof(int32_t) * (size_t)(nl + 1));
    int32_t *ltri = malloc(sizeof(int32_t) * (size_t)(3 * p.ntris + 1));
    int64_t *gid = malloc(sizeof(int64_t) * (size_t)(p.nverts + NX + 1));
    for (int64_t k = 0; k < nl; k++) { /* written vertex nh + k is stored at nl - 1 - k */
        int64_t at = nl - 1 - k;
        rxy[2 * at] = xy[2 * (nh + k)];
        rxy[2 * at + 1] = xy[2 * (nh + k) + 1];
        rvm[at] = vm[nh + k];
        sel[k] = (int32_t)at;
    }
    /* local ids: the stored ones, then nh more for the head vertices (a part lists them too) */
    for (int64_t k = 0; k < nl; k++)
        gid[nl - 1 - k] = base + nh + k;
    for (int64_t k = 0; k < nh; k++)
        gid[nl + k] = base + k;
    for (int64_t k = 0; k < NX; k++) /* the next row (the next rank's): local ids after */
        gid[p.nverts + k] = base + p.nverts + k;
    for (int64_t i = 0; i < 3 * p.ntris; i++) {
        int64_t k = tri[i] - base;
        ltri[i] = k >= p.nverts ? (int32_t)k
                  : k < nh      ? (int32_t)(nl + k)
                                : (int32_t)(nl - 1 - (k - nh));
    }
    mesh_part q = p;
    q.nhead = nh;
    q.hxy = xy;
    q.hvmarker = vm;
    q.xy = rxy;
    q.vmarker = rvm;
    q.vsel = sel;
    q.tri = NULL;
    q.ltri = ltri;
    q.gid = gid;
    q.nlocal = p.nverts + NX; /* the writer caches each local vertex's digits */
    static const size_t chunks[4] = {1, 40, 333, 0}, keep[4] = {0, 100, 7, 1 << 20};
    int ok = 1;
    char seq[300], par[300], err[512] = "";
    snprintf(seq, sizeof seq, "%s/seqc", dir);
    if (rank == 0) {
        mesh_flat whole;
        make_whole(size, &whole);
        ok = meshio_write_triangle(&whole, seq, err, sizeof err) == 0;
        mesh_flat_free(&whole);
    }
    for (int ct = 0; ct < 12; ct++) { /* every chunk size with 1, 2 and 3 formatting threads */
        int c = ct % 4;
        meshio_pwrite_set_chunk(chunks[c]);
        q.keep = keep[c];
        q.threads = 1 + ct / 4;
        snprintf(par, sizeof par, "%s/chunk%d", dir, ct);
        int rc = meshio_pwrite_triangle(MPI_COMM_WORLD, NULL, &q, par, err, sizeof err);
        if (rc) fprintf(stderr, "rank %d: chunk %zu: %s\n", rank, chunks[c], err);
        ok = ok && rc == 0;
        static const char *const ext[3] = {"node", "ele", "poly"};
        for (int e = 0; e < 3 && ok && rank == 0; e++) {
            char a[320], b[320];
            snprintf(a, sizeof a, "%s.%s", par, ext[e]);
            snprintf(b, sizeof b, "%s.%s", seq, ext[e]);
            if (!same_file(a, b)) {
                fprintf(stderr, "chunk %zu, %d threads: %s and %s differ\n", chunks[c], q.threads,
                        a, b);
                ok = 0;
            }
        }
    }
    meshio_pwrite_set_chunk(0);
    free(rxy), free(rvm), free(sel), free(ltri), free(gid);
    free(xy), free(vm), free(tri), free(tr), free(seg), free(sm);
    ck_assert_int_eq(all_true(ok), 1);
}
END_TEST

START_TEST(test_missing_folder) {
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    mesh_part p;
    double *xy;
    int32_t *vm, *tr, *sm;
    int64_t *tri, *seg;
    int size;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    make_part(rank, size, &p, &xy, &vm, &tri, &tr, &seg, &sm);
    char pre[300], err[512] = "", all0[512] = "";
    snprintf(pre, sizeof pre, "%s/no-such-folder/out", dir);
    int rc = meshio_pwrite_triangle(MPI_COMM_WORLD, NULL, &p, pre, err, sizeof err);
    /* every rank failed, with rank 0's message */
    memcpy(all0, err, sizeof all0);
    MPI_Bcast(all0, (int)sizeof all0, MPI_CHAR, 0, MPI_COMM_WORLD);
    int ok = rc == -1 && strcmp(err, all0) == 0 && strstr(err, "no-such-folder") != NULL;
    if (!ok) fprintf(stderr, "rank %d: rc %d, message '%s'\n", rank, rc, err);
    free(xy), free(vm), free(tri), free(tr), free(seg), free(sm);
    ck_assert_int_eq(all_true(ok), 1);
}
END_TEST

START_TEST(test_pvtu) {
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    /* each rank: one triangle of its own */
    double xy[6] = {rank, 0, rank + 1.0, 0, rank + 0.5, 1};
    int32_t tri[3] = {0, 1, 2}, vm[3] = {1, 1, 0};
    mesh_flat m;
    memset(&m, 0, sizeof m);
    m.nverts = 3;
    m.xy = xy;
    m.vmarker = vm;
    m.ntris = 1;
    m.tri = tri;
    char pre[300], err[512] = "";
    snprintf(pre, sizeof pre, "%s/pv", dir);
    int ok = meshio_pwrite_pvtu(MPI_COMM_WORLD, NULL, &m, NULL, 1, pre, err, sizeof err) == 0;
    if (!ok) fprintf(stderr, "rank %d: %s\n", rank, err);
    if (ok && rank == 0) {
        char path[320], buf[4096] = "";
        snprintf(path, sizeof path, "%s.pvtu", pre);
        FILE *f = fopen(path, "r");
        size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
        buf[n] = '\0';
        if (f) fclose(f);
        for (int r = 0; r < size && ok; r++) {
            char piece[64];
            snprintf(piece, sizeof piece, "Source=\"pv_%d.vtu\"", r);
            snprintf(path, sizeof path, "%s_%d.vtu", pre, r);
            ok = strstr(buf, piece) != NULL && access(path, R_OK) == 0;
        }
        if (!ok) fprintf(stderr, "pvtu: pieces missing:\n%s\n", buf);
    }
    ck_assert_int_eq(all_true(ok), 1);
}
END_TEST

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0) {
        snprintf(dir, sizeof dir, "%s/mpi_pwrite.XXXXXX",
                 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
        if (!mkdtemp(dir)) dir[0] = '\0';
    }
    MPI_Bcast(dir, (int)sizeof dir, MPI_CHAR, 0, MPI_COMM_WORLD);
    if (!dir[0]) {
        MPI_Finalize();
        return 1;
    }
    int rc = ck_run_mpi(ck_suite("mpi_pwrite", 0,
                                 CK_TESTS(test_triangle_files, test_triangle_chunks,
                                          test_missing_folder, test_pvtu)),
                        MPI_COMM_WORLD);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0 && rc == EXIT_SUCCESS) {
        char cmd[300];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
        if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    }
    MPI_Finalize();
    return rc;
}
