/* unit_pcdm_flip: Check suite for the flips that make a refined mesh Delaunay again
 * (pcdm_mesh_restore_delaunay, mesher/pcdm/pcdm.c).
 *
 * On a refined mesh, which is a constrained Delaunay triangulation, the pass flips nothing and
 * leaves every array as it was, bit for bit (./pcdm's meshes that were valid stay the same).
 * With one edge at a vertex on a segment flipped away from Delaunay (a convex quadrilateral, no
 * four points on a circle), the pass makes exactly one flip and gives back the triangles there
 * were (same slots, same corners): every unconstrained edge is then locally Delaunay (exact
 * incircle) and no constraint edge has moved.  No MPI.
 */
#include "check_run.h"
#include "geom/geom.h"
#include "pcdm/pcdm_impl.h"
#include "seq/kernel.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The square [0, 1]^2 with its four sides as segments, refined to (25 degrees, area 0.004):
 * Steiner vertices on the sides (vseg >= 0) and inside. */
static void square(mesh *m, pslg *g) {
    static const double xy[] = {0, 0, 1, 0, 1, 1, 0, 1.125};
    static const int32_t seg[] = {0, 1, 1, 2, 2, 3, 3, 0};
    memset(g, 0, sizeof *g);
    g->nverts = 4;
    g->xy = calloc(9, sizeof(double));
    memcpy(g->xy, xy, sizeof xy);
    g->vmarker = calloc(5, sizeof(int32_t));
    g->vline = calloc(5, sizeof(int32_t));
    g->nsegs = 4;
    g->seg = calloc(9, sizeof(int32_t));
    memcpy(g->seg, seg, sizeof seg);
    g->smarker = calloc(5, sizeof(int32_t));
    g->sline = calloc(5, sizeof(int32_t));
    g->holes = calloc(1, sizeof(double));
    char err[256];
    ck_assert_msg(pslg_check(g, err, sizeof err) == 0, "pslg_check: %s", err);
    mesh_init(m);
    ck_assert_msg(mesh_build_cdt(m, g, NULL, err, sizeof err) == 0, "cdt: %s", err);
    mesh_quality q = {25, 0.004, -1, 1, 0};
    mesh_set_quality(m, &q);
    ck_assert_int_eq(mesh_refine(m), MESH_REFINE_DONE);
}

/* The number of unconstrained edges between two live triangles that are not locally Delaunay. */
static int32_t non_delaunay(const mesh *m) {
    int32_t n = 0;
    for (int32_t e = 0; e < 3 * m->nt; e++) {
        int32_t f = m->tn[e];
        if (f < e || !mesh_tri_alive(m, e / 3) || mesh_edge_constrained(m, e)) continue;
        int32_t u = mesh_org(m, e), v = mesh_dest(m, e), w = mesh_apex(m, e), z = mesh_apex(m, f);
        if (u < 0 || v < 0 || w < 0 || z < 0) continue;
        if (geom_incircle(mesh_vertex_xy(m, u), mesh_vertex_xy(m, v), mesh_vertex_xy(m, w),
                          mesh_vertex_xy(m, z)) > 0)
            n++;
    }
    return n;
}

static void sort3(int32_t *a) {
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (a[j] > a[j + 1]) {
                int32_t x = a[j];
                a[j] = a[j + 1];
                a[j + 1] = x;
            }
}

START_TEST(test_delaunay_unchanged) {
    geom_init();
    mesh m;
    pslg g;
    square(&m, &g);
    ck_assert_int_eq(non_delaunay(&m), 0);
    size_t n3 = 3 * (size_t)m.nt;
    int32_t *tv = malloc(n3 * sizeof *tv), *tn = malloc(n3 * sizeof *tn);
    memcpy(tv, m.tv, n3 * sizeof *tv);
    memcpy(tn, m.tn, n3 * sizeof *tn);
    ck_assert_int_eq(pcdm_mesh_restore_delaunay(&m), 0);
    ck_assert(memcmp(tv, m.tv, n3 * sizeof *tv) == 0);
    ck_assert(memcmp(tn, m.tn, n3 * sizeof *tn) == 0);
    free(tv);
    free(tn);
    mesh_free(&m);
    pslg_free(&g);
}
END_TEST

START_TEST(test_one_flip_back) {
    geom_init();
    mesh m;
    pslg g;
    square(&m, &g);
    /* an unconstrained edge at a vertex on a segment whose quadrilateral is strictly convex and
     * not cocircular: flipping it makes it not locally Delaunay */
    int32_t pick = -1;
    for (int32_t e = 0; e < 3 * m.nt && pick < 0; e++) {
        int32_t f = m.tn[e], u = mesh_org(&m, e);
        if (f < 0 || !mesh_tri_alive(&m, e / 3) || mesh_edge_constrained(&m, e) || u < 0 ||
            m.vseg[u] < 0)
            continue;
        int32_t v = mesh_dest(&m, e), w = mesh_apex(&m, e), z = mesh_apex(&m, f);
        const double *U = mesh_vertex_xy(&m, u), *V = mesh_vertex_xy(&m, v),
                     *W = mesh_vertex_xy(&m, w), *Z = mesh_vertex_xy(&m, z);
        if (geom_incircle(U, V, W, Z) < 0 && geom_orient2d(W, U, Z) > 0 &&
            geom_orient2d(Z, V, W) > 0)
            pick = e;
    }
    ck_assert_msg(pick >= 0, "no flippable edge at a vertex on a segment");
    size_t n3 = 3 * (size_t)m.nt;
    int32_t t1 = pick / 3, t2 = m.tn[pick] / 3, nt = m.nt;
    /* the two triangles' corners, as sets, before */
    int32_t before[6];
    memcpy(before, m.tv + 3 * (size_t)t1, 3 * sizeof(int32_t));
    memcpy(before + 3, m.tv + 3 * (size_t)t2, 3 * sizeof(int32_t));
    int32_t *tv = malloc(n3 * sizeof *tv);
    memcpy(tv, m.tv, n3 * sizeof *tv);
    int32_t nseg_edges = 0;
    for (int32_t e = 0; e < 3 * m.nt; e++)
        nseg_edges += mesh_tri_alive(&m, e / 3) && mesh_edge_constrained(&m, e);
    mesh_flip(&m, pick);
    ck_assert_int_eq(non_delaunay(&m), 1);
    ck_assert_int_eq(pcdm_mesh_restore_delaunay(&m), 1);
    ck_assert_int_eq(non_delaunay(&m), 0);
    ck_assert_int_eq(m.nt, nt);
    /* every other slot as it was; t1 and t2 hold the two old triangles again (either way) */
    for (int32_t t = 0; t < m.nt; t++) {
        if (t == t1 || t == t2) continue;
        ck_assert(memcmp(tv + 3 * (size_t)t, m.tv + 3 * (size_t)t, 3 * sizeof(int32_t)) == 0);
    }
    int32_t after[6];
    memcpy(after, m.tv + 3 * (size_t)t1, 3 * sizeof(int32_t));
    memcpy(after + 3, m.tv + 3 * (size_t)t2, 3 * sizeof(int32_t));
    sort3(before), sort3(before + 3), sort3(after), sort3(after + 3);
    int same = memcmp(before, after, sizeof before) == 0 ||
               (memcmp(before, after + 3, 3 * sizeof(int32_t)) == 0 &&
                memcmp(before + 3, after, 3 * sizeof(int32_t)) == 0);
    ck_assert_msg(same, "the two triangles are not the ones there were");
    int32_t n = 0;
    for (int32_t e = 0; e < 3 * m.nt; e++)
        n += mesh_tri_alive(&m, e / 3) && mesh_edge_constrained(&m, e);
    ck_assert_int_eq(n, nseg_edges);
    free(tv);
    mesh_free(&m);
    pslg_free(&g);
}
END_TEST

int main(void) {
    return ck_run(ck_suite("pcdm_flip", 0, CK_TESTS(test_delaunay_unchanged, test_one_flip_back)));
}
