/* fuzz_mesh: libFuzzer harness over the reader and the sequential mesher (issue 10).
 *
 * One input = one option byte followed by the text of a .poly (or, when bit 7 of the option
 * byte is set, a .node).  The option byte picks the angle bound (0, 20.7, 25, 30 or 33 degrees),
 * off-centers, lenses, an area bound and (bit 6) -c, the convex hull enclosed by segments.  The
 * text goes through exactly what ./mesh does: pslg_read, pslg_check_ex (crossing segments split, as
 * without --strict; with -c the hull enclosed), Triangle's boundary markers, mesh_build_cdt,
 * mesh_refine (with a Steiner limit, so an input that would need millions of points stays quick),
 * mesh_to_flat, mesh_validate.  The oracle, besides the sanitizers and libFuzzer's timeout:
 * whenever ./mesh would exit 0 (MESH_REFINE_DONE and mesh_count_unmet() == 0) the validator must
 * accept the mesh at the bounds asked for, or the harness traps.  Bad input is fine (the reader or
 * the checks reject it); a mesh bug aborts through MESH_BUG, which libFuzzer reports as a crash.
 * The input file lives in a private temporary directory made and removed by each call (no state
 * survives a call).
 */
#include "check/validate.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "io/meshio.h"
#include "seq/mesh.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1 || size > 20000) return 0;
    geom_init();
    char dir[256];
    snprintf(dir, sizeof dir, "%s/fuzz_mesh.XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    if (!mkdtemp(dir)) abort();
    static const double qs[8] = {0, 20.7, 25, 30, 33, 20.7, 25, 28.6};
    unsigned opt = data[0];
    char path[300];
    snprintf(path, sizeof path, "%s/in.%s", dir, (opt & 0x80) ? "node" : "poly");
    FILE *f = fopen(path, "wb");
    if (!f) abort();
    fwrite(data + 1, 1, size - 1, f);
    fclose(f);

    double q = qs[opt & 7];
    int offc = !(opt & 8), lens = !!(opt & 16), area_on = !!(opt & 32);
    unsigned flags = PSLG_SPLIT | ((opt & 64) ? PSLG_HULL : 0u);
    char err[1024];
    pslg g;
    if (pslg_read(path, &g, err, sizeof err) != 0) goto out;
    g.quiet = 1; /* no warnings on every input */
    if (pslg_check_ex(&g, flags, err, sizeof err) != 0 || pslg_boundary_markers(&g) != 0) {
        pslg_free(&g);
        goto out;
    }
    mesh m;
    mesh_init(&m);
    if (mesh_build_cdt(&m, &g, NULL, err, sizeof err) == 0) {
        double area = 0;
        if (area_on && g.nverts > 0) { /* about 1/50 of the bounding box */
            double x0 = g.xy[0], x1 = x0, y0 = g.xy[1], y1 = y0;
            for (int32_t i = 1; i < g.nverts; i++) {
                double x = g.xy[2 * i], y = g.xy[2 * i + 1];
                x0 = x < x0 ? x : x0;
                x1 = x > x1 ? x : x1;
                y0 = y < y0 ? y : y0;
                y1 = y > y1 ? y : y1;
            }
            area = (x1 - x0) * (y1 - y0) / 50;
            if (!(area > 0) || area > 1e300) area = 0;
        }
        mesh_quality mq = {q > 0 ? q * (1 + 1e-9) + 1e-12 : 0, area, 20000, offc, lens};
        mesh_set_quality(&m, &mq);
        mesh_refine_result rr = mesh_refine(&m);
        mesh_flat fl;
        /* ./mesh reports success exactly when this holds (apps/mesh.c) */
        if (rr == MESH_REFINE_DONE && mesh_count_unmet(&m, NULL) == 0 &&
            mesh_to_flat(&m, &fl) == 0) {
            validate_opts vo = {q, area, 0, 0, 0, 0};
            validate_report vr;
            if (!mesh_validate(&g, &fl, &vo, &vr)) {
                validate_report_print(&vr, stderr);
                __builtin_trap(); /* exit-0 mesh outside its bounds, or a wrong mesh */
            }
            mesh_flat_free(&fl);
        }
    }
    mesh_free(&m);
    pslg_free(&g);
out:
    unlink(path);
    rmdir(dir);
    return 0;
}
