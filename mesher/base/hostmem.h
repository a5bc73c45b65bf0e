/* hostmem: one block of memory that the ranks of a host share, written by the host's first rank
 * and then read-only for all -- so that read-only data every rank needs (the input, the
 * decomposition) is held once per host instead of once per rank.
 *
 * A POSIX shared-memory object (shm_open), its space reserved when it is made (posix_fallocate:
 * a full /dev/shm is an error here, never a SIGBUS later), mapped by every rank of the host, and
 * unlinked once all have mapped it, so nothing is left behind by a killed run.  The host's
 * first rank (its leader, the lowest rank of comm on the host) maps it writable until
 * mesh_hostmem_seal, the others read-only from the start: a write by any rank after the seal is
 * a fault at the writing instruction, never a silent change to another rank's data.
 */
#ifndef MESH_HOSTMEM_H
#define MESH_HOSTMEM_H

#include <mpi.h>
#include <stddef.h>

typedef struct mesh_hostmem {
    unsigned char *base; /* the mapping (NULL: none) */
    size_t len;          /* its bytes */
    int leader;          /* 1 on the host's first rank */
    int has_node;        /* node is set */
    MPI_Comm node;       /* the host's ranks */
} mesh_hostmem;

/* Collective over comm.  Maps a block of len bytes (len > 0) shared by the ranks of each host
 * (h zeroed first).  Returns 0 on every rank, or -1 on every rank when some rank could not have
 * it (nothing mapped anywhere then: the caller keeps private copies). */
int mesh_hostmem_open(mesh_hostmem *h, MPI_Comm comm, size_t len);

/* Collective over h's host.  The leader's writes are done: from now on the block is read-only
 * on every rank; returns once every rank of the host may read it. */
void mesh_hostmem_seal(mesh_hostmem *h);

/* Local.  1 iff p points into the block. */
int mesh_hostmem_holds(const mesh_hostmem *h, const void *p);

/* Local.  A fresh name for a POSIX object of this host ("/pcdm-KIND-PID-RANK-NS": process id,
 * rank, clock) into buf (len bytes), for an O_EXCL create. */
void mesh_host_name(char *buf, size_t len, const char *kind, int rank);

/* Local.  Unmaps the block (h zeroed; accepts a zeroed h). */
void mesh_hostmem_close(mesh_hostmem *h);

#endif
