/* hostmem.c: the block shared by a host's ranks (hostmem.h).
 *
 * Opening: the host's ranks (MPI_Comm_split_type, shared memory); the leader makes the object
 * under a fresh name (process id, rank, clock) with O_EXCL, reserves its bytes and maps it; the
 * name goes to the others in one MPI_Bcast over the host, each maps it read-only; one
 * MPI_Allreduce over comm agrees on success (a failure anywhere unmaps everywhere); then the
 * leader unlinks the name.  Sealing: the leader's mprotect to read-only, then a barrier over
 * the host waited for asleep (mesh_mpi_settle).
 */
#define _GNU_SOURCE
#include "base/hostmem.h"

#include "base/base_mpi.h"

#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#define NAME_LEN 64

void mesh_host_name(char *buf, size_t len, const char *kind, int rank) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    snprintf(buf, len, "/pcdm-%s-%ld-%d-%ld", kind, (long)getpid(), rank, (long)ts.tv_nsec);
}

int mesh_hostmem_open(mesh_hostmem *h, MPI_Comm comm, size_t len) {
    memset(h, 0, sizeof *h);
    int rank = 0, me = 0, ok = 1;
    MPI_Comm_rank(comm, &rank);
    h->has_node = MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &h->node) ==
                  MPI_SUCCESS;
    if (!h->has_node) ok = 0;
    if (h->has_node) MPI_Comm_rank(h->node, &me);
    h->leader = me == 0;
    char name[NAME_LEN] = "";
    int fd = -1;
    if (ok && h->leader) {
        mesh_host_name(name, sizeof name, "host", rank);
        fd = shm_open(name, O_CREAT | O_EXCL | O_RDWR, 0600);
        if (fd < 0 || posix_fallocate(fd, 0, (off_t)len) != 0) {
            if (fd >= 0) close(fd), shm_unlink(name);
            fd = -1;
            name[0] = '\0';
        }
    }
    if (h->has_node) MPI_Bcast(name, NAME_LEN, MPI_CHAR, 0, h->node);
    if (ok && !name[0]) ok = 0;
    if (ok && !h->leader) fd = shm_open(name, O_RDONLY, 0);
    if (fd >= 0) {
        void *p =
            mmap(NULL, len, h->leader ? PROT_READ | PROT_WRITE : PROT_READ, MAP_SHARED, fd, 0);
        close(fd);
        if (p != MAP_FAILED) h->base = p, h->len = len;
    }
    if (!h->base) ok = 0;
    int all = 0;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, comm);
    if (h->leader && name[0]) shm_unlink(name); /* every rank has mapped it, or gave up */
    if (all) return 0;
    mesh_hostmem_close(h);
    return -1;
}

void mesh_hostmem_seal(mesh_hostmem *h) {
    if (h->leader && h->base) mprotect(h->base, h->len, PROT_READ);
    if (h->has_node) mesh_mpi_settle(h->node);
}

int mesh_hostmem_holds(const mesh_hostmem *h, const void *p) {
    if (!h->base || !p) return 0;
    uintptr_t a = (uintptr_t)p, b = (uintptr_t)h->base;
    return a >= b && a < b + h->len;
}

void mesh_hostmem_close(mesh_hostmem *h) {
    if (h->base) munmap(h->base, h->len);
    if (h->has_node) MPI_Comm_free(&h->node);
    memset(h, 0, sizeof *h);
}
