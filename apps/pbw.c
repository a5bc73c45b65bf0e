/* pbw: the Parallel Meshing Algorithm (parallel Bowyer-Watson, TR-97-17 section 2).
 *
 *   mpirun -np P ./pbw [options] input.poly        (options: ./pbw --help: ./pcdm's and --phases)
 *
 * SPMD: every rank reads the input and the decomposition (which only says which rank owns which
 * triangle of the initial CDT), then mesher/pbw/pbw.c refines the one distributed mesh with
 * remote cavity expansions, locks and undo.  Each rank then checks, numbers and writes its own
 * triangles; no gather.  The stages, messages, --stats lines (their definitions included) and
 * exit statuses are the driver's (mesher/run/run.h, run_par.c); the options, usage errors and
 * --help the front end's (apps/cli.c; ./pbw --help).
 */
#include "run/run.h"

#include "cli.h"

int main(int argc, char **argv) {
    return run_par_main(argc, argv, RUN_PBW, cli_par_parse, &cli_pbw);
}
