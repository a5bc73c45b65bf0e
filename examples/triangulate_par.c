/* triangulate_par: libpcdm's parallel call (include/pcdm_par.h) on a communicator of the caller's.
 *
 *   cc triangulate_par.c $(pkg-config --cflags --libs pcdm) -o triangulate_par
 *   mpirun -np 4 ./triangulate_par NAME     writes NAME.poly and NAME.1.node/.ele/.poly
 *
 * The program owns MPI (MPI_Init_thread, MPI_THREAD_FUNNELED) and splits MPI_COMM_WORLD into
 * its even and odd ranks; each half meshes the same plate as ./triangulate on its own
 * communicator, at the same time.  The even half keeps the mesh in parts (global numbering, no
 * gather) and prints the totals; the odd half (or the only rank) collects the whole mesh on
 * its rank 0, which writes the files. */
#include "example_util.h"

#include <mpi.h>
#include <pcdm_par.h>

#include <stdio.h>

int main(int argc, char **argv) {
    int provided, rank, size;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (argc != 2) {
        if (rank == 0) fprintf(stderr, "usage: %s NAME\n", argv[0]);
        MPI_Finalize();
        return 2;
    }
    int color = size > 1 ? rank % 2 : 1, sub;
    MPI_Comm half;
    MPI_Comm_split(MPI_COMM_WORLD, color, rank, &half);
    MPI_Comm_rank(half, &sub);
    pcdm_input in;
    ex_input(&in);
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 25;
    o.max_area = 0.5;
    o.unsuitable = ex_small_near_origin;
    o.root = color == 1 ? 0 : -1; /* the odd half collects the whole mesh on its rank 0 */
    pcdm_mesh m;
    pcdm_status st;
    int rc = pcdm_triangulate_par(half, &in, &o, &m, &st) != PCDM_OK;
    if (rc && sub == 0) fprintf(stderr, "triangulate_par: %s\n", st.message);
    if (!rc && color == 0) { /* parts: every global number is owned once */
        long long mine[2] = {0, m.ntriangles}, tot[2];
        for (int32_t i = 0; i < m.npoints; i++)
            mine[0] += m.pointowned[i];
        MPI_Allreduce(mine, tot, 2, MPI_LONG_LONG, MPI_SUM, half);
        if (sub == 0)
            printf("parts: %lld of %lld points owned, %lld of %lld triangles\n", tot[0],
                   (long long)m.nglobalpoints, tot[1], (long long)m.nglobaltriangles);
        rc = tot[0] != m.nglobalpoints || tot[1] != m.nglobaltriangles;
    }
    if (!rc && color == 1 && sub == 0) {
        printf("whole: %d points, %d triangles, %d segments\n", m.npoints, m.ntriangles,
               m.nsegments);
        rc = ex_write(argv[1], &m) != 0;
    }
    pcdm_mesh_free(&m);
    int any = 0;
    MPI_Allreduce(&rc, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Comm_free(&half);
    MPI_Finalize();
    return any ? 1 : 0;
}
