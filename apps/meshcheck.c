/* meshcheck: validates a mesh written in Triangle's format against its input PSLG.
 *
 *   ./meshcheck input.poly PREFIX [-q DEG] [-a AREA] [--interfaces-delaunay]
 *
 * Reads and checks the input (pslg_read, pslg_check), reads PREFIX.node/.ele (and .poly when
 * present) with meshio_read_triangle, runs mesh_validate and prints its one-line summary.
 * Exit status: 0 the mesh passes, 1 it fails, 2 bad usage or unreadable files.
 */
#include "geom/geom.h"
#include "geom/pslg.h"
#include "io/meshio.h"
#include "io/validate.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(FILE *f) {
    fprintf(f, "usage: meshcheck input.poly PREFIX [-q DEG] [-a AREA] [--interfaces-delaunay]\n"
               "  Validates PREFIX.node/.ele (and PREFIX.poly) against input.poly: conformity,\n"
               "  orientation, input vertices and segments present, domain area, local Delaunay\n"
               "  property, and optionally the quality bounds.\n"
               "  -q DEG    smallest angle bound in degrees (triangles at input angles below 60\n"
               "            degrees are exempt)\n"
               "  -a AREA   largest triangle area\n"
               "  --interfaces-delaunay  interface constraint edges must be locally Delaunay\n"
               "  Exit status: 0 valid, 1 invalid, 2 usage or input error.\n");
}

static int parse_num(const char *s, double *out) {
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno == ERANGE || !isfinite(v) || v < 0) return -1;
    *out = v;
    return 0;
}

int main(int argc, char **argv) {
    const char *input = NULL, *prefix = NULL;
    validate_opts o = {0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "-q") || !strcmp(a, "-a")) {
            if (i + 1 >= argc || parse_num(argv[i + 1], a[1] == 'q' ? &o.min_angle : &o.max_area)) {
                fprintf(stderr, "meshcheck: %s needs a non-negative number\n", a);
                usage(stderr);
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--interfaces-delaunay")) {
            o.check_delaunay_interfaces = 1;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "meshcheck: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        } else if (!input) {
            input = a;
        } else if (!prefix) {
            prefix = a;
        } else {
            fprintf(stderr, "meshcheck: unexpected argument '%s'\n", a);
            usage(stderr);
            return 2;
        }
    }
    if (!input || !prefix) {
        usage(stderr);
        return 2;
    }
    geom_init();
    char err[1024];
    pslg g;
    if (pslg_read(input, &g, err, sizeof err) || pslg_check(&g, err, sizeof err)) {
        fprintf(stderr, "meshcheck: %s\n", err);
        pslg_free(&g);
        return 2;
    }
    mesh_flat m;
    if (meshio_read_triangle(prefix, &m, err, sizeof err)) {
        fprintf(stderr, "meshcheck: %s\n", err);
        pslg_free(&g);
        return 2;
    }
    validate_report r;
    int ok = mesh_validate(&g, &m, &o, &r);
    validate_report_print(&r, stdout);
    mesh_flat_free(&m);
    pslg_free(&g);
    return ok ? 0 : 1;
}
