/* decomp_seeds: the predicted cost of a partition of the coarse mesh, by which ./pbw chooses
 * among METIS seeds (pcdm_decomp_opts.boundary_cost).
 *
 * METIS balances the work of the parts to within its tolerance (3%) and keeps the cut short,
 * but a ./pbw rank pays for its rank boundary as well as for its triangles: every cavity that
 * crosses the boundary costs a round of messages on both sides, and in the end game those
 * cavities are most of what is left.  Measured on the lake at 10M triangles, 8 ranks on 2
 * cores (40 rank records over 5 runs, each run's means removed): a rank's CPU time is 3.2e-7 s
 * per triangle plus 0.0144 s per unit length of its final rank boundary (r^2 0.86; triangles
 * alone 0.28).  The ranks' final boundaries differed 2.3 times in length, and the busiest rank
 * was 4-5% above the mean.
 *
 * So a part's predicted cost is its work (the coarse triangles' tw, about area / area bound)
 * plus boundary_cost times its boundary with other parts, each edge measured in units of the
 * final triangle size on its side: sqrt(area / tw) of the coarse triangle, the square root of
 * the area bound where the bound rules, the coarse triangle's own size where it does not.  In
 * those units the measurement above gives about 26: the final rank boundary is 1.6 times the
 * interfaces (the initial mesh's edges zig-zag across them, cavities roughen them further), a
 * unit of work is 1.56 triangles, and the bound was 3.356e-7 (0.0144 * 1.6 / (3.2e-7 * 1.56) *
 * sqrt(3.356e-7) = 26).  A partition's cost is its costliest part's.  Seeds give partitions of
 * different shapes whose costliest parts differ by a few percent (lake, 64 seeds: standard
 * deviation 1.2% of the mean).
 *
 * Local; part[t] in [0, K) for live triangles (others ignored).
 */
#include "decomp/decomp_impl.h"

#include "base/base.h"
#include "geom/geom.h"

#include <math.h>

double decomp_part_cost(const mesh *m, const double *tw, const int32_t *part, int32_t K,
                        double boundary_cost) {
    double *c = mesh_xcalloc((size_t)K + 1, sizeof(double));
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || part[t] < 0 || part[t] >= K) continue;
        c[part[t]] += tw[t];
        const double *a = mesh_vertex_xy(m, m->tv[3 * (size_t)t]),
                     *b = mesh_vertex_xy(m, m->tv[3 * (size_t)t + 1]),
                     *d = mesh_vertex_xy(m, m->tv[3 * (size_t)t + 2]);
        double h = sqrt(fabs(geom_area(a, b, d)) / tw[t]);
        if (!(h > 0)) continue;
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, f = m->tn[e];
            if (f < 0 || !mesh_tri_alive(m, f / 3)) continue;
            int32_t q = part[f / 3];
            if (q < 0 || q == part[t]) continue;
            double l = sqrt(
                geom_dist2(mesh_vertex_xy(m, mesh_org(m, e)), mesh_vertex_xy(m, mesh_dest(m, e))));
            c[part[t]] += boundary_cost * l / h;
        }
    }
    double worst = 0;
    for (int32_t k = 0; k < K; k++)
        if (c[k] > worst) worst = c[k];
    mesh_xfree(c);
    return worst;
}
