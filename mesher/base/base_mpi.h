/* base_mpi: the collective half of base (base_mpi.c), for the layers that link MPI: one
 * agreement on failure that every collective step uses (the ends' "did any rank fail", the
 * parallel writers' after each step).
 */
#ifndef MESH_BASE_MPI_H
#define MESH_BASE_MPI_H

#include <mpi.h>
#include <stddef.h>

/* Collective over comm.  code: this rank's failure (0: none) and msg its message (may be NULL;
 * may be out itself).  Returns 0 when no rank failed, else the lowest failing rank's code on
 * every rank, with its message in out (outlen bytes; out may be NULL).  Prints nothing.  The
 * ranks that arrive first wait asleep (mesh_mpi_settle). */
int mesh_agree(MPI_Comm comm, int code, const char *msg, char *out, size_t outlen);

/* Local.  Waits for rq (an MPI request of this thread's), testing it and, while it is not
 * complete, sleeping between tests (20 us doubling to 1 ms after 64 quick tests): a rank that
 * waits for a slower one leaves the CPU to the ranks that share its core, where MPI's own wait
 * would spin or yield to them thousands of times a second.  Costs at most the last pause in
 * latency. */
void mesh_mpi_wait_asleep(MPI_Request *rq);

/* Collective over comm.  A barrier waited for asleep (mesh_mpi_wait_asleep): put before a
 * collective step that some ranks reach long before others. */
void mesh_mpi_settle(MPI_Comm comm);

#endif
