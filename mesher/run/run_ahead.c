/* run_ahead: the Delaunay triangulation of the input's vertices, made on a second thread of the
 * parallel programs' rank 0, from the moment the vertices are read, while its main thread parses
 * the segments and checks the input (crossings, duplicates, vertices on segments), so that the
 * decomposition's constrained Delaunay triangulation of the input only has its segments left to
 * insert.  The other ranks and the rank's own worker threads wait in that phase, so the thread
 * takes an idle core.
 *
 * Invariant: the triangulation is used only for exactly the vertices the check leaves (same
 * count, coordinates equal bit for bit: the check merged, dropped and added none); it is then the
 * one mesh_build_cdt makes, since mesh_build_points is its first half run on the same points.
 * Otherwise it is thrown away and the decomposition triangulates the checked input itself, so
 * the mesh never depends on whether the thread ran.  Launchers bind each rank to a core, so
 * the thread moves onto the cores of its host's ranks (run_ahead_host_cpus), whose ranks sleep
 * meanwhile.  Local but for run_ahead_host_cpus; no MPI on the thread.
 */
#define _GNU_SOURCE /* sched_getaffinity, CPU_ISSET */
#include "run/run.h"

#include "base/base.h"
#include "base/base_mpi.h"
#include "rt.h"

#include <math.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>

void run_ahead_host_cpus(run_job *j) {
    memset(j->host_cpus, 0, sizeof j->host_cpus);
    if (rt_size() < 2) return;
    uint8_t mine[MESH_HOST_CPUS] = {0};
#ifdef __linux__
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0)
        for (int c = 0; c < MESH_HOST_CPUS && c < CPU_SETSIZE; c++)
            mine[c] = CPU_ISSET(c, &set) ? 1 : 0;
#endif
    MPI_Comm node;
    MESH_MPI(
        MPI_Comm_split_type(rt_app_comm(), MPI_COMM_TYPE_SHARED, rt_rank(), MPI_INFO_NULL, &node));
    MESH_MPI(MPI_Reduce(mine, j->host_cpus, MESH_HOST_CPUS, MPI_UINT8_T, MPI_MAX, 0, node));
    MESH_MPI(MPI_Comm_free(&node));
}

static void *dt_run(void *arg) {
    run_dt_ahead *a = arg;
    char err[256];
    mesh_thread_spread(a->cpus);
    if (getenv("PCDM_TEST_AHEAD_STALE")) a->xy[0] = nextafter(a->xy[0], INFINITY);
    a->rc = mesh_build_points(&a->m, a->n, a->xy, &a->dup, err, sizeof err);
    return NULL;
}

void run_dt_ahead_start(run_job *j, const pslg *g) {
    run_dt_ahead *a = &j->dt_ahead;
    memset(a, 0, sizeof *a);
    mesh_init(&a->m);
    a->cpus = j->host_cpus;
    if (g->nverts < 3) return; /* mesh_build_cdt says why */
    a->n = g->nverts;
    a->xy = mesh_xmalloc(2 * (size_t)a->n, sizeof(double));
    if (pslg_vertices_scaled(g, a->xy) != 0) { /* the check will refuse it */
        run_dt_ahead_free(a);
        return;
    }
    a->started = pthread_create(&a->thr, NULL, dt_run, a) == 0;
    if (!a->started) run_dt_ahead_free(a);
}

static void join(run_dt_ahead *a) {
    if (a->started && !a->joined) {
        pthread_join(a->thr, NULL);
        a->joined = 1;
    }
}

run_dt_ahead *run_dt_ahead_take(run_dt_ahead *a, const pslg *g) {
    if (!a->started) return NULL;
    join(a);
    /* test-only faults (tests/t_ahead.sh): PCDM_TEST_AHEAD_STALE, a stale copy (dt_run moved
     * one of its points by an ulp); PCDM_TEST_AHEAD_TRUST, the copy taken without the
     * comparison */
    int trust = getenv("PCDM_TEST_AHEAD_TRUST") != NULL;
    int same = a->rc == 0 && a->xy && a->n == g->nverts &&
               (trust || memcmp(a->xy, g->xy, 2 * (size_t)a->n * sizeof(double)) == 0);
    mesh_xfree(a->xy);
    a->xy = NULL;
    if (same) return a;
    run_dt_ahead_free(a);
    return NULL;
}

void run_dt_ahead_free(run_dt_ahead *a) {
    join(a);
    mesh_xfree(a->xy);
    mesh_xfree(a->dup);
    mesh_free(&a->m);
    a->xy = NULL;
    a->dup = NULL;
    a->started = 0;
}
