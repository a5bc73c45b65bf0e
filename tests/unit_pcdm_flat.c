/* unit_pcdm_flat: Check suite for the mesh hash (pcdm_flat_hash, mesher/pcdm/pcdm_flat.c).
 *
 * The hash must not depend on numbering or on how a mesh is cut into parts: the same triangles
 * with the vertices renumbered, the triangles shuffled and each rotated (still
 * counter-clockwise), and the mesh split into parts whose hashes are summed (as ./pcdm sums the
 * ranks' parts) all give one value; -0.0 counts as +0.0.  It must see the geometry: one
 * coordinate moved by one ulp, one triangle reversed (clockwise), or a triangle missing changes
 * it.  Hashed on several threads it is the same value.
 */
#include "check_run.h"
#include "pcdm/pcdm.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static uint64_t next(void) {
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

enum { GN = 12 }; /* a GN x GN grid of vertices, two triangles per cell */

/* The grid mesh: vertices in row order, triangles in cell order. */
static void grid(mesh_flat *f) {
    memset(f, 0, sizeof *f);
    f->nverts = GN * GN;
    f->xy = malloc(2 * (size_t)f->nverts * sizeof(double));
    for (int i = 0; i < GN; i++)
        for (int j = 0; j < GN; j++) {
            f->xy[2 * (i * GN + j)] = (j - 3) * 0.125;
            f->xy[2 * (i * GN + j) + 1] = i * 0.1 + 1e-3 * (j - 3);
        }
    f->ntris = 2 * (GN - 1) * (GN - 1);
    f->tri = malloc(3 * (size_t)f->ntris * sizeof(int32_t));
    int32_t n = 0;
    for (int i = 0; i + 1 < GN; i++)
        for (int j = 0; j + 1 < GN; j++) {
            int32_t a = i * GN + j, b = a + 1, c = a + GN, d = c + 1;
            int32_t t[6] = {a, b, d, a, d, c};
            memcpy(f->tri + 3 * (size_t)n, t, sizeof t);
            n += 2;
        }
}

static void flat_clear(mesh_flat *f) {
    free(f->xy);
    free(f->tri);
    memset(f, 0, sizeof *f);
}

/* A copy of f with vertices permuted, triangles shuffled and each rotated. */
static void scramble(const mesh_flat *f, mesh_flat *g) {
    memset(g, 0, sizeof *g);
    int32_t nv = f->nverts, nt = f->ntris;
    int32_t *perm = malloc((size_t)nv * sizeof(int32_t)),
            *tp = malloc((size_t)nt * sizeof(int32_t));
    for (int32_t v = 0; v < nv; v++)
        perm[v] = v;
    for (int32_t v = nv - 1; v > 0; v--) {
        int32_t k = (int32_t)(next() % (uint64_t)(v + 1)), x = perm[v];
        perm[v] = perm[k];
        perm[k] = x;
    }
    for (int32_t t = 0; t < nt; t++)
        tp[t] = t;
    for (int32_t t = nt - 1; t > 0; t--) {
        int32_t k = (int32_t)(next() % (uint64_t)(t + 1)), x = tp[t];
        tp[t] = tp[k];
        tp[k] = x;
    }
    g->nverts = nv;
    g->xy = malloc(2 * (size_t)nv * sizeof(double));
    for (int32_t v = 0; v < nv; v++)
        memcpy(g->xy + 2 * (size_t)perm[v], f->xy + 2 * (size_t)v, 2 * sizeof(double));
    g->ntris = nt;
    g->tri = malloc(3 * (size_t)nt * sizeof(int32_t));
    for (int32_t t = 0; t < nt; t++) {
        int r = (int)(next() % 3);
        for (int j = 0; j < 3; j++)
            g->tri[3 * (size_t)t + j] = perm[f->tri[3 * (size_t)tp[t] + (j + r) % 3]];
    }
    free(perm);
    free(tp);
}

START_TEST(test_numbering) {
    mesh_flat f, g;
    grid(&f);
    uint64_t h = pcdm_flat_hash(&f, 1);
    ck_assert_uint_ne(h, 0);
    for (int rep = 0; rep < 20; rep++) {
        scramble(&f, &g);
        ck_assert_msg(pcdm_flat_hash(&g, 1) == h, "scrambled copy %d: %016llx != %016llx", rep,
                      (unsigned long long)pcdm_flat_hash(&g, 1), (unsigned long long)h);
        flat_clear(&g);
    }
    flat_clear(&f);
}
END_TEST

/* Parts: triangles [0, cut) and [cut, n) as two meshes with the whole vertex array each. */
START_TEST(test_parts) {
    mesh_flat f;
    grid(&f);
    uint64_t h = pcdm_flat_hash(&f, 1);
    int32_t n = f.ntris;
    for (int32_t cut = 0; cut <= n; cut += 7) {
        mesh_flat a = f, b = f;
        a.ntris = cut;
        b.ntris = n - cut;
        b.tri = f.tri + 3 * (size_t)cut;
        uint64_t s = pcdm_flat_hash(&a, 1) + pcdm_flat_hash(&b, 1);
        ck_assert_msg(s == h, "cut %d: %016llx != %016llx", cut, (unsigned long long)s,
                      (unsigned long long)h);
    }
    flat_clear(&f);
}
END_TEST

START_TEST(test_geometry) {
    mesh_flat f;
    grid(&f);
    uint64_t h = pcdm_flat_hash(&f, 1);
    /* -0.0 is +0.0: vertex (0, 0) exists at j = 3, i = 0 */
    double x = f.xy[2 * 3];
    ck_assert(x == 0);
    f.xy[2 * 3] = -0.0;
    ck_assert_uint_eq(pcdm_flat_hash(&f, 1), h);
    f.xy[2 * 3] = x;
    /* one ulp */
    f.xy[2 * 40 + 1] = nextafter(f.xy[2 * 40 + 1], 1e9);
    ck_assert_uint_ne(pcdm_flat_hash(&f, 1), h);
    f.xy[2 * 40 + 1] = nextafter(f.xy[2 * 40 + 1], -1e9);
    ck_assert_uint_eq(pcdm_flat_hash(&f, 1), h);
    /* a reversed triangle */
    int32_t t = f.tri[1];
    f.tri[1] = f.tri[2];
    f.tri[2] = t;
    ck_assert_uint_ne(pcdm_flat_hash(&f, 1), h);
    f.tri[2] = f.tri[1];
    f.tri[1] = t;
    /* a triangle missing */
    f.ntris--;
    ck_assert_uint_ne(pcdm_flat_hash(&f, 1), h);
    f.ntris++;
    ck_assert_uint_eq(pcdm_flat_hash(&f, 1), h);
    flat_clear(&f);
}
END_TEST

/* The grid's triangles repeated R times, rotated: R times the hash, on any number of threads. */
START_TEST(test_threads) {
    enum { R = 300 };
    mesh_flat f, g;
    grid(&f);
    uint64_t h = pcdm_flat_hash(&f, 1);
    g = f;
    g.ntris = R * f.ntris;
    g.tri = malloc(3 * (size_t)g.ntris * sizeof(int32_t));
    for (int32_t t = 0; t < g.ntris; t++)
        for (int j = 0; j < 3; j++)
            g.tri[3 * (size_t)t + j] = f.tri[3 * (size_t)(t % f.ntris) + (j + t / f.ntris) % 3];
    for (int T = 1; T <= 65; T += T < 4 ? 1 : 61) {
        uint64_t s = pcdm_flat_hash(&g, T);
        ck_assert_msg(s == (uint64_t)R * h, "%d threads: %016llx != %d x %016llx", T,
                      (unsigned long long)s, R, (unsigned long long)h);
    }
    free(g.tri);
    flat_clear(&f);
}
END_TEST

int main(void) {
    return ck_run_nofork(ck_suite(
        "pcdm_flat", 0, CK_TESTS(test_numbering, test_parts, test_geometry, test_threads)));
}
