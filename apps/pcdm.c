/* pcdm: Parallel Constrained Delaunay Meshing (Chew, Chrisochoides, Sukup, TR-97-17).
 *
 *   mpirun -np P ./pcdm [options] input.poly        (options: ./pcdm --help)
 *
 * SPMD: every rank reads the input and computes the same decomposition, builds the coarse CDT
 * of the augmented PSLG, keeps its own subdomains and refines them; the only remote service
 * request is "split constraint edge".  By default each subdomain is refined in its own mesh, in
 * rounds (pcdm_det.c; on --threads T workers per rank), so the mesh is the same for any ranks,
 * threads and timing; --balance dynamic moves unstarted subdomains to idle ranks (pcdm_move.c);
 * --async is the paper's protocol, one mesh per rank, requests served as they arrive
 * (mesher/pcdm/pcdm.c).  Each rank then checks, numbers and writes
 * its own part; no rank gathers the mesh.  The stages, messages, --stats lines and exit
 * statuses are the driver's (mesher/run/run.h, run_par.c); the options, usage errors and --help
 * the front end's (apps/cli.c; ./pcdm --help).
 */
#include "run/run.h"

#include "cli.h"

int main(int argc, char **argv) {
    return run_par_main(argc, argv, RUN_PCDM, cli_par_parse, &cli_pcdm);
}
