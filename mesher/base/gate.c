/* gate.c: the host's CPU gate (gate.h) -- a POSIX named semaphore per group of ranks that share
 * a host and a CPU set.
 *
 * Opening: the ranks of a host (MPI_Comm_split_type, shared memory) exchange their CPU sets
 * (sched_getaffinity) with one MPI_Allgather; a group is the ranks with the same set, its slots
 * the set's CPU count.  A group no larger than its slots needs no gate.  Otherwise its lowest
 * rank creates the semaphore under a fresh name (mesh_host_name), the names go round
 * in a second MPI_Allgather, every member opens its group's, and after a barrier the creator
 * unlinks it: the semaphore lives on only in the open handles, and goes with the processes.
 * A failure anywhere leaves that rank (or group) without a gate, which only costs speed.
 */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include "base/gate.h"

#include "base/base.h"
#include "base/hostmem.h"

#include <errno.h>
#include <fcntl.h>
#include <sched.h>
#include <semaphore.h>
#include <string.h>
#include <time.h>

#define NAME_LEN 64

void mesh_gate_open(mesh_gate *g, MPI_Comm comm) {
    memset(g, 0, sizeof *g);
    MPI_Comm node;
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    if (MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node) != MPI_SUCCESS)
        return;
    int n = 0, me = 0;
    MPI_Comm_size(node, &n);
    MPI_Comm_rank(node, &me);
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) CPU_ZERO(&set);
    cpu_set_t *all = mesh_xmalloc((size_t)n, sizeof *all);
    char(*names)[NAME_LEN] = mesh_xcalloc((size_t)n, NAME_LEN);
    MPI_Allgather(&set, (int)sizeof set, MPI_BYTE, all, (int)sizeof set, MPI_BYTE, node);
    int lead = -1, members = 0;
    for (int r = 0; r < n; r++)
        if (CPU_EQUAL(&all[r], &set)) {
            if (lead < 0) lead = r;
            members++;
        }
    int slots = CPU_COUNT(&set);
    int want = slots > 0 && members > slots;
    sem_t *sem = SEM_FAILED;
    char name[NAME_LEN] = "";
    if (want && lead == me) {
        mesh_host_name(name, sizeof name, "gate", rank);
        sem = sem_open(name, O_CREAT | O_EXCL, 0600, (unsigned)slots);
        if (sem == SEM_FAILED) name[0] = '\0';
    }
    MPI_Allgather(name, NAME_LEN, MPI_CHAR, names, NAME_LEN, MPI_CHAR, node);
    if (want && lead != me && names[lead][0]) sem = sem_open(names[lead], 0);
    MPI_Barrier(node);
    if (want && lead == me && name[0]) sem_unlink(name);
    mesh_xfree(all);
    mesh_xfree(names);
    MPI_Comm_free(&node);
    if (sem == SEM_FAILED) return;
    g->sem = sem;
    g->slots = slots;
}

int mesh_gate_take(mesh_gate *g, long wait_ns) {
    if (!g->sem || g->held) return 1;
    if (sem_trywait(g->sem) == 0) return g->held = 1;
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts); /* sem_timedwait's clock */
    ts.tv_nsec += wait_ns;
    ts.tv_sec += ts.tv_nsec / 1000000000L;
    ts.tv_nsec %= 1000000000L;
    while (sem_timedwait(g->sem, &ts) != 0)
        if (errno != EINTR) return 0;
    return g->held = 1;
}

void mesh_gate_give(mesh_gate *g) {
    if (!g->sem || !g->held) return;
    g->held = 0;
    sem_post(g->sem);
}

void mesh_gate_close(mesh_gate *g) {
    mesh_gate_give(g);
    if (g->sem) sem_close(g->sem);
    g->sem = NULL;
    g->slots = 0;
}
