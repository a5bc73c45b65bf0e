/* meshcheck: validates a mesh written in Triangle's format against its input PSLG.
 *
 *   ./meshcheck [-q DEG] [-a AREA] [-c] [-A] [--region-areas] [--interfaces-delaunay] input.poly
 *               PREFIX
 *
 * Reads and checks the input (pslg_read, pslg_check_ex; with -c its convex hull enclosed by
 * segments, as the meshers' -c does, so a mesh made with -c is checked against the domain it
 * meant: the input's segments plus the hull), reads PREFIX.node/.ele (and .poly when
 * present) with meshio_read_triangle, runs mesh_validate and prints its one-line summary.
 * Options and exit statuses come from the front end (apps/cli.c; ./meshcheck --help): 0 the
 * mesh passes, 1 it fails or a file cannot be read or is invalid, 2 usage error.
 */
#include "check/validate.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "io/meshio.h"

#include "cli.h"

#include <stdio.h>

int main(int argc, char **argv) {
    cli_opts co;
    int code;
    if (cli_parse(&cli_meshcheck, argc, argv, stdout, stderr, &co, &code)) return code;
    validate_opts o = {.min_angle = co.par.min_angle,
                       .max_area = co.par.max_area,
                       .check_delaunay_interfaces = co.interfaces_delaunay,
                       .region_attr = co.par.region_attr,
                       .region_area = co.par.region_area};
    const char *input = co.par.input, *prefix = co.mesh_prefix;
    geom_init();
    char err[1024];
    pslg g;
    unsigned flags = PSLG_SPLIT | (co.par.convex_hull ? PSLG_HULL : 0u); /* -c: as the mesher */
    if (pslg_read(input, &g, err, sizeof err) || pslg_check_ex(&g, flags, err, sizeof err)) {
        fprintf(stderr, "meshcheck: %s\n", err);
        pslg_free(&g);
        return 1;
    }
    mesh_flat m;
    if (meshio_read_triangle(prefix, &m, err, sizeof err)) {
        fprintf(stderr, "meshcheck: %s\n", err);
        pslg_free(&g);
        return 1;
    }
    validate_report r;
    int ok = mesh_validate(&g, &m, &o, &r);
    validate_report_print(&r, stdout);
    mesh_flat_free(&m);
    pslg_free(&g);
    return ok ? 0 : 1;
}
