/* fuzz_mesh: libFuzzer harness over the reader and the sequential mesher (issue 10).
 *
 * One input = one option byte followed by the text of a .poly (or, when bit 7 of the option
 * byte is set, a .node).  The option byte picks the angle bound (0, 20.7, 25, 30 or 33 degrees),
 * off-centers, lenses, an area bound and (bit 6) -c, the convex hull enclosed by segments.  The
 * text goes through ./mesh's own driver (run/run.h, run_mesh_flat: the load stage -- pslg_read,
 * the checks with crossing segments split, with -c the hull enclosed, Triangle's boundary
 * markers --, the bounds, the CDT refined with a Steiner limit so an input that would need
 * millions of points stays quick, the verdict, and the check stage, mesh_validate).  The
 * oracle, besides the sanitizers and libFuzzer's timeout: whenever ./mesh would exit 0 (the
 * verdict: the bounds met) the validator must accept the mesh at the bounds asked for, or the
 * harness traps.  Bad input is fine (the reader or
 * the checks reject it); a mesh bug aborts through MESH_BUG, which libFuzzer reports as a crash.
 * The input file lives in a private temporary directory made and removed by each call (no state
 * survives a call).
 */
#include "check/validate.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "run/run.h"

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
    char err[1024];
    pslg g; /* for the area bound only: about 1/50 of the bounding box */
    if (pslg_read(path, &g, err, sizeof err) != 0) goto out;
    double area = 0;
    if (area_on && g.nverts > 0) {
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
    pslg_free(&g);
    par_opts o;
    memset(&o, 0, sizeof o);
    o.prog = "mesh";
    o.input = path;
    o.min_angle = q;
    o.max_area = area;
    o.max_steiner = 20000;
    o.circumcenters = !offc;
    o.convex_hull = (opt & 64) != 0;
    o.quiet = 1; /* no warnings on every input */
    o.check = 1;
    run_job j;
    run_job_init(&j, RUN_SEQ, &o);
    j.lens = lens;
    j.lib = 1;
    mesh_flat fl;
    int scale_exp = 0;
    /* ./mesh exits 0 exactly when the verdict is "met" and the check passes */
    if (run_mesh_flat(&j, &fl, &scale_exp) == 0) {
        if (j.verdict == RUN_MET && !j.check_ok) {
            validate_report_print(&j.report, stderr);
            __builtin_trap(); /* exit-0 mesh outside its bounds, or a wrong mesh */
        }
        mesh_flat_free(&fl);
    }
out:
    unlink(path);
    rmdir(dir);
    return 0;
}
