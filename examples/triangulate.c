/* triangulate: the smallest use of libpcdm's sequential call (include/pcdm.h).
 *
 *   cc triangulate.c $(pkg-config --cflags --libs pcdm) -o triangulate
 *   ./triangulate NAME          writes NAME.poly (the input) and NAME.1.node/.ele/.poly
 *   ./meshcheck -q 25 NAME.poly NAME.1
 *
 * Meshes a plate with a hole: no angle below 25 degrees, no triangle above 0.5, and through the
 * size callback small triangles near the origin.  Prints one line of counts. */
#include "example_util.h"

#include <pcdm.h>

#include <stdio.h>

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s NAME\n", argv[0]);
        return 2;
    }
    pcdm_input in;
    ex_input(&in);
    pcdm_options o;
    pcdm_options_default(&o);
    o.min_angle = 25;
    o.max_area = 0.5;
    o.unsuitable = ex_small_near_origin;
    pcdm_mesh m;
    pcdm_status st;
    if (pcdm_triangulate(&in, &o, &m, &st) != PCDM_OK) {
        fprintf(stderr, "triangulate: %s\n", st.message);
        return 1;
    }
    printf("libpcdm %s: %d points, %d triangles, %d segments\n", pcdm_version(), m.npoints,
           m.ntriangles, m.nsegments);
    int rc = ex_write(argv[1], &m);
    if (rc) fprintf(stderr, "triangulate: cannot write %s.*\n", argv[1]);
    pcdm_mesh_free(&m);
    return rc ? 1 : 0;
}
