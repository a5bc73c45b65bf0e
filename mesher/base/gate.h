/* gate: the ranks of one host that share CPUs compute at most as many at once as they have CPUs.
 *
 * With more ranks than cores on a host (mpirun -np 8 on 2 cores), the kernel time-slices the
 * busy ranks: each switch hands a core to another process whose mesh is not in its caches, and
 * memory-bound refinement then costs more CPU per triangle.  A gate is a counting semaphore
 * shared by the ranks of a host whose CPU sets are equal, with one slot per CPU of that set: a
 * rank holds a slot while it has local work and gives it back when it runs out, so as many ranks
 * as there are CPUs run to completion of their work while the others sleep in the kernel.
 * Where a host's ranks do not outnumber their CPUs (or the semaphore cannot be made) there is no
 * gate and every call below does nothing.
 *
 * Invariants: a rank holds at most one slot, and only while it has work that needs no message
 * (so no rank can wait on the gate for a rank that waits on it); the semaphore is unlinked once
 * every rank of its group has opened it, so nothing is left behind by a killed run.
 */
#ifndef MESH_GATE_H
#define MESH_GATE_H

#include <mpi.h>

typedef struct mesh_gate {
    void *sem; /* sem_t *, NULL: no gate */
    int held;  /* this rank holds a slot */
    int slots; /* the CPUs of the group (0: no gate) */
} mesh_gate;

/* Collective over comm.  Opens the gate of this rank's host and CPU set (g zeroed first).  Never
 * fails: without a gate, g->sem is NULL. */
void mesh_gate_open(mesh_gate *g, MPI_Comm comm);

/* Local.  Takes a slot, waiting at most wait_ns in the kernel; 1 when held (at once when no
 * gate or already held), 0 when the wait ran out (the caller polls its messages and asks again). */
int mesh_gate_take(mesh_gate *g, long wait_ns);

/* Local.  Gives the slot back if held. */
void mesh_gate_give(mesh_gate *g);

/* Local.  Gives the slot back and closes the gate. */
void mesh_gate_close(mesh_gate *g);

#endif
