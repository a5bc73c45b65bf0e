/* pcdm_par.h: the parallel half of libpcdm's public interface -- pcdm_triangulate_par, PCDM
 * (TR-97-17 section 3) or PBW (section 2) Collective over an MPI communicator.  Everything else
 * (input, options, mesh, status, codes, the version) is pcdm.h's, which this header includes.
 *
 * Link with `pkg-config --cflags --libs pcdm` (MPI, METIS and pthreads).
 */
#ifndef PCDM_PAR_PUBLIC_H
#define PCDM_PAR_PUBLIC_H

#include <mpi.h>

#include "pcdm.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Collective over comm (any communicator: MPI_COMM_WORLD, a split, ...).  The caller has
 * initialised MPI with at least MPI_THREAD_FUNNELED and calls from MPI's main thread; the
 * library neither initialises nor finalises MPI, and leaves comm as it was (it works on
 * duplicates).  Every rank passes the same input and options.  PCDM (TR-97-17): the domain is
 * cut into subdomains (METIS on a coarse mesh), each rank refines its own, splitting interface
 * subsegments by remote requests (or PBW, opt->method); the mesh is numbered globally by prefix
 * sums, never gathered unless opt->root >= 0.  Every rank returns the same code and message.  The
 * parallel runtime runs inside the call only: one call at a time per process. */
int pcdm_triangulate_par(MPI_Comm comm, const pcdm_input *in, const pcdm_options *opt,
                         pcdm_mesh *out, pcdm_status *st);

#ifdef __cplusplus
}
#endif

#endif
