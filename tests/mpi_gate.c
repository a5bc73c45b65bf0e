// ranks: 1 2 4 8
/* mpi_gate: Check suite for the host's CPU gate (mesher/base/gate.c).
 *
 *  - there is a gate exactly where the ranks of a host with one CPU set outnumber its CPUs
 *    (found here again from the ranks' affinity masks), with one slot per CPU;
 *  - never more ranks inside than slots: every rank takes the gate many times, counting itself in
 *    and out of a counter in memory shared by the host's ranks (MPI_Win_allocate_shared), and
 *    the largest count any rank saw inside is at most the slots;
 *  - without a gate, taking and giving return at once.
 * Results are reduced over ranks before asserting.  Runs with CK_NOFORK (MPI does not survive
 * fork).
 */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include "base/gate.h"
#include "check_run.h"

#include <sched.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

static int all_true(int local) {
    int g = 0;
    MPI_Allreduce(&local, &g, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    return g;
}

/* The ranks of this host with this rank's CPU set, and the set's CPU count. */
static void my_group(MPI_Comm node, int *members, int *cpus) {
    int n = 0;
    MPI_Comm_size(node, &n);
    cpu_set_t set, *all = malloc((size_t)n * sizeof *all);
    CPU_ZERO(&set);
    ck_assert_int_eq(sched_getaffinity(0, sizeof set, &set), 0);
    MPI_Allgather(&set, (int)sizeof set, MPI_BYTE, all, (int)sizeof set, MPI_BYTE, node);
    *members = 0;
    for (int r = 0; r < n; r++)
        *members += CPU_EQUAL(&all[r], &set) != 0;
    *cpus = CPU_COUNT(&set);
    free(all);
}

START_TEST(test_where) {
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
    int members = 0, cpus = 0;
    my_group(node, &members, &cpus);
    mesh_gate g;
    mesh_gate_open(&g, MPI_COMM_WORLD);
    int want = members > cpus;
    int ok = (g.sem != NULL) == want && (!want || g.slots == cpus) && !g.held;
    ck_assert_int_eq(all_true(ok), 1);
    if (!want) { /* no gate: nothing waits */
        ok = mesh_gate_take(&g, 1) == 1;
        mesh_gate_give(&g);
        ck_assert_int_eq(all_true(ok), 1);
    }
    mesh_gate_close(&g);
    ck_assert_int_eq(all_true(g.sem == NULL && !g.held), 1);
    MPI_Comm_free(&node);
}
END_TEST

START_TEST(test_exclusion) {
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
    int me = 0;
    MPI_Comm_rank(node, &me);
    /* one counter per host, in rank 0's part of a shared window */
    MPI_Win win;
    int64_t *cnt = NULL;
    MPI_Win_allocate_shared(me == 0 ? (MPI_Aint)sizeof(int64_t) : 0, (int)sizeof(int64_t),
                            MPI_INFO_NULL, node, &cnt, &win);
    MPI_Aint sz;
    int du;
    MPI_Win_shared_query(win, 0, &sz, &du, &cnt);
    if (me == 0) __atomic_store_n(cnt, 0, __ATOMIC_SEQ_CST);
    MPI_Barrier(node);
    mesh_gate g;
    mesh_gate_open(&g, MPI_COMM_WORLD);
    int64_t most = 0;
    int held_ok = 1;
    for (int i = 0; i < 40; i++) {
        while (!mesh_gate_take(&g, 200000L)) {
        }
        held_ok &= !g.sem || g.held;
        int64_t in = __atomic_add_fetch(cnt, 1, __ATOMIC_SEQ_CST);
        if (in > most) most = in;
        struct timespec ts = {0, 300000L}; /* inside a while, as a rank refining */
        nanosleep(&ts, NULL);
        __atomic_sub_fetch(cnt, 1, __ATOMIC_SEQ_CST);
        mesh_gate_give(&g);
    }
    int slots = g.slots;
    mesh_gate_close(&g);
    MPI_Barrier(node);
    if (slots > 0 && most > slots)
        fprintf(stderr, "mpi_gate: %lld ranks inside a gate of %d slots\n", (long long)most, slots);
    ck_assert_int_eq(all_true(held_ok && (slots == 0 || most <= slots)), 1);
    MPI_Win_free(&win);
    MPI_Comm_free(&node);
}
END_TEST

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rc =
        ck_run_mpi(ck_suite("mpi_gate", 0, CK_TESTS(test_where, test_exclusion)), MPI_COMM_WORLD);
    MPI_Finalize();
    return rc;
}
