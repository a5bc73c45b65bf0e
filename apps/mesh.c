/* mesh: the sequential quality mesher.  ./mesh [options] input.poly
 *
 * Reads a PSLG (Triangle's .poly or .node), builds its constrained Delaunay triangulation and
 * refines it with Ruppert/Chew Delaunay refinement, then writes the requested outputs: the
 * Triangle files where Triangle puts them unless -o names a prefix (or -NEP none).  The stages,
 * messages, --stats line and exit statuses are the driver's (mesher/run/run.h, run_seq.c); the
 * options, usage errors and --help the front end's (apps/cli.c; ./mesh --help).
 */
#include "run/run.h"

#include "cli.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

int main(int argc, char **argv) {
    cli_opts o;
    int code;
#if defined(__GLIBC__)
    /* The mesh's arrays grow by doubling.  glibc serves blocks below its mmap threshold, which
     * it raises up to 32 MB as blocks are freed, from the heap, where a realloc copies and
     * leaves the old block resident: on a 49K-vertex coastline that was 20-30 MB of peak RSS
     * (at 1M and at 10M triangles).  Above a fixed 256 KB threshold a growing array is mapped
     * and realloc moves its pages without copying. */
    mallopt(M_MMAP_THRESHOLD, 256 * 1024);
#endif
    if (cli_parse(&cli_mesh, argc, argv, stdout, stderr, &o, &code)) return code;
    run_job j;
    run_job_init(&j, RUN_SEQ, &o.par);
    j.lens = o.lens;
    j.cdt_only = o.cdt_only;
    return run_mesh(&j);
}
