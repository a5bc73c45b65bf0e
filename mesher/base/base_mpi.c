/* base_mpi.c: the MPI half of the bug report (base.h) -- the rank from MPI_COMM_WORLD and
 * MPI_Abort while MPI is initialised and not finalised -- the MPI error check (MESH_MPI), and
 * the agreement on failure (base_mpi.h).
 *
 * Linked into every program and library that uses the parallel layers (they call
 * mesh_mpi_fail_at through MESH_MPI, which pulls this object in); a constructor installs the
 * environment before main, so a bug anywhere, on any thread, names its rank and stops every
 * rank, with no set-up call for a program or a test to forget.  The sequential library leaves
 * this file out and needs no MPI.
 */
#include "base/base_mpi.h"
#include "base/base.h"

#include <mpi.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

/* the sleeping wait: tests without a pause first, then pauses doubling up to the longest */
#define WAIT_SPINS 64
#define WAIT_FIRST_NS 20000L
#define WAIT_MAX_NS 1000000L

static int mpi_rank(void) {
    int init = 0, fin = 0, r = 0;
    MPI_Initialized(&init);
    if (init) MPI_Finalized(&fin);
    if (!init || fin) return -1;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
}

static void mpi_stop(int code) {
    MPI_Abort(MPI_COMM_WORLD, code);
}

static const mesh_bug_env mpi_env = {mpi_rank, mpi_stop};

#if defined(__GNUC__)
__attribute__((constructor))
#endif
static void
mpi_env_install(void) {
    mesh_bug_set_env(&mpi_env);
}

void mesh_mpi_fail_at(const char *file, int line, const char *call, int rc) {
    char s[MPI_MAX_ERROR_STRING] = "";
    int len = 0;
    if (MPI_Error_string(rc, s, &len) != MPI_SUCCESS) snprintf(s, sizeof s, "error %d", rc);
    mesh_bug_at(file, line, "%s failed: %s", call, s);
}

void mesh_mpi_wait_asleep(MPI_Request *rq) {
    long ns = 0;
    for (int done = 0, spins = 0;;) {
        MESH_MPI(MPI_Test(rq, &done, MPI_STATUS_IGNORE));
        if (done) return;
        if (++spins <= WAIT_SPINS) continue;
        ns = ns ? 2 * ns : WAIT_FIRST_NS;
        if (ns > WAIT_MAX_NS) ns = WAIT_MAX_NS;
        struct timespec ts = {0, ns};
        nanosleep(&ts, NULL);
    }
}

void mesh_mpi_settle(MPI_Comm comm) {
    int size = 1;
    MESH_MPI(MPI_Comm_size(comm, &size));
    if (size < 2) return;
    MPI_Request rq;
    MESH_MPI(MPI_Ibarrier(comm, &rq));
    mesh_mpi_wait_asleep(&rq);
}

int mesh_agree(MPI_Comm comm, int code, const char *msg, char *out, size_t outlen) {
    int rank, size;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    MESH_MPI(MPI_Comm_size(comm, &size));
    int mine = code != 0 ? rank : size, first = size;
    mesh_mpi_settle(comm); /* the ranks that wait for a slower one, asleep */
    MESH_MPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
    if (first == size) return 0;
    struct {
        int code;
        char msg[1200];
    } b;
    memset(&b, 0, sizeof b);
    if (rank == first) {
        b.code = code;
        if (msg) snprintf(b.msg, sizeof b.msg, "%s", msg);
    }
    MESH_MPI(MPI_Bcast(&b, (int)sizeof b, MPI_BYTE, first, comm));
    if (out && outlen) snprintf(out, outlen, "%s", b.msg);
    return b.code;
}
