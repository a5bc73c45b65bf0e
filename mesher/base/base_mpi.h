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
 * every rank, with its message in out (outlen bytes; out may be NULL).  Prints nothing. */
int mesh_agree(MPI_Comm comm, int code, const char *msg, char *out, size_t outlen);

#endif
