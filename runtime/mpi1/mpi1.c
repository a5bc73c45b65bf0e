/* mpi1.c: the one-process MPI stand-in (mpi.h in this folder says what it is and who uses it).
 *
 * With one rank every collective is a copy of the caller's own contribution: the send buffer
 * lands in the receive buffer at rank 0's place (its displacement), reductions reduce one
 * operand, so the operation is irrelevant.  Point-to-point has no peer: the runtime delivers
 * to itself without MPI (runtime/rt_comm.c), so a send or a blocking receive here is an error
 * the caller's check reports.  A request's whole state is its handle's value (REQ_* below);
 * a persistent receive, preposted by the runtime, never matches anything and stays active until
 * cancelled.  Invariants: no global state but the communicator counter (atomic; handles are
 * never reused, so a freed one is never mistaken for a live one); every function returns
 * MPI_SUCCESS or an MPI_ERR_* code and never prints; nothing blocks.
 */
#include "mpi.h"

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* request states (MPI_Request values) */
enum {
    REQ_NULL = MPI_REQUEST_NULL,
    REQ_DONE = 1,      /* a completed operation (Ibarrier), not yet tested */
    REQ_INACTIVE = 2,  /* a persistent receive, not started */
    REQ_ACTIVE = 3,    /* a persistent receive, started: never matched */
    REQ_CANCELLED = 4, /* a started persistent receive, cancelled: completes on test or wait */
};

static atomic_int next_comm = 3; /* after MPI_COMM_WORLD and MPI_COMM_SELF */

/* Bytes of one element of t; 0 for an invalid type. */
static size_t type_size(MPI_Datatype t) {
    if (t < 0) return (size_t) - (long)t;
    switch (t) {
    case MPI_BYTE:
    case MPI_CHAR:
    case MPI_UINT8_T:
        return 1;
    case MPI_INT:
        return sizeof(int);
    case MPI_LONG:
        return sizeof(long);
    case MPI_LONG_LONG:
        return sizeof(long long);
    case MPI_UNSIGNED_LONG:
        return sizeof(unsigned long);
    case MPI_DOUBLE:
        return sizeof(double);
    case MPI_INT32_T:
        return sizeof(int32_t);
    case MPI_INT64_T:
        return sizeof(int64_t);
    case MPI_UINT64_T:
        return sizeof(uint64_t);
    default:
        return 0;
    }
}

static int comm_ok(MPI_Comm c) {
    return c > 0;
}

/* Copies count elements of t from sb to rb (nothing when sb is MPI_IN_PLACE or the same). */
static int copy(const void *sb, void *rb, int count, MPI_Datatype t) {
    size_t s = type_size(t);
    if (!s || count < 0) return MPI_ERR_TYPE;
    if (sb != MPI_IN_PLACE && sb != rb && count > 0) memmove(rb, sb, (size_t)count * s);
    return MPI_SUCCESS;
}

static void status_set(MPI_Status *st, size_t bytes) {
    if (!st) return;
    st->MPI_SOURCE = MPI_ANY_SOURCE;
    st->MPI_TAG = MPI_ANY_TAG;
    st->MPI_ERROR = MPI_SUCCESS;
    st->mpi1_bytes = (int)bytes;
}

/* ---- life cycle ------------------------------------------------------------------------- */

int MPI_Init(int *argc, char ***argv) {
    return MPI_SUCCESS;
}

int MPI_Init_thread(int *argc, char ***argv, int required, int *provided) {
    *provided = MPI_THREAD_FUNNELED;
    return MPI_SUCCESS;
}

int MPI_Initialized(int *flag) {
    *flag = 1;
    return MPI_SUCCESS;
}

int MPI_Finalized(int *flag) {
    *flag = 0;
    return MPI_SUCCESS;
}

int MPI_Finalize(void) {
    return MPI_SUCCESS;
}

int MPI_Query_thread(int *provided) {
    *provided = MPI_THREAD_FUNNELED;
    return MPI_SUCCESS;
}

int MPI_Is_thread_main(int *flag) {
    *flag = 1;
    return MPI_SUCCESS;
}

_Noreturn int MPI_Abort(MPI_Comm comm, int code) {
    (void)comm;
    (void)code;
    abort();
}

int MPI_Error_string(int code, char *s, int *len) {
    const char *m;
    switch (code) {
    case MPI_SUCCESS:
        m = "no error";
        break;
    case MPI_ERR_RANK:
        m = "invalid rank (a one-process build has no other rank)";
        break;
    case MPI_ERR_REQUEST:
        m = "invalid request, or a wait that could never end (nothing to match in one process)";
        break;
    case MPI_ERR_IO:
        m = "I/O error";
        break;
    case MPI_ERR_TYPE:
        m = "invalid datatype or count";
        break;
    case MPI_ERR_COMM:
        m = "invalid communicator";
        break;
    default:
        m = "invalid argument";
    }
    *len = snprintf(s, MPI_MAX_ERROR_STRING, "%s", m);
    return MPI_SUCCESS;
}

double MPI_Wtime(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- communicators and datatypes ------------------------------------------------------------ */

int MPI_Comm_dup(MPI_Comm comm, MPI_Comm *out) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    *out = atomic_fetch_add(&next_comm, 1);
    return MPI_SUCCESS;
}

int MPI_Comm_split_type(MPI_Comm comm, int type, int key, MPI_Info info, MPI_Comm *out) {
    (void)type, (void)key, (void)info; /* one process: its own node */
    return MPI_Comm_dup(comm, out);
}

int MPI_Comm_free(MPI_Comm *comm) {
    if (!comm_ok(*comm) || *comm <= MPI_COMM_SELF) return MPI_ERR_COMM;
    *comm = MPI_COMM_NULL;
    return MPI_SUCCESS;
}

int MPI_Comm_rank(MPI_Comm comm, int *rank) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    *rank = 0;
    return MPI_SUCCESS;
}

int MPI_Comm_size(MPI_Comm comm, int *size) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    *size = 1;
    return MPI_SUCCESS;
}

int MPI_Comm_set_errhandler(MPI_Comm comm, MPI_Errhandler eh) {
    return comm_ok(comm) ? MPI_SUCCESS : MPI_ERR_COMM;
}

int MPI_Type_contiguous(int count, MPI_Datatype old, MPI_Datatype *out) {
    size_t s = type_size(old);
    if (!s || count <= 0 || (size_t)count * s > 0x7fffffff) return MPI_ERR_TYPE;
    *out = -(int)((size_t)count * s);
    return MPI_SUCCESS;
}

int MPI_Type_commit(MPI_Datatype *t) {
    return type_size(*t) ? MPI_SUCCESS : MPI_ERR_TYPE;
}

int MPI_Type_free(MPI_Datatype *t) {
    if (*t >= 0) return MPI_ERR_TYPE; /* predefined types are not freed */
    *t = MPI_DATATYPE_NULL;
    return MPI_SUCCESS;
}

/* ---- collectives: rank 0's own contribution ------------------------------------------------ */

int MPI_Barrier(MPI_Comm comm) {
    return comm_ok(comm) ? MPI_SUCCESS : MPI_ERR_COMM;
}

int MPI_Ibarrier(MPI_Comm comm, MPI_Request *req) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    *req = REQ_DONE;
    return MPI_SUCCESS;
}

int MPI_Bcast(void *buf, int count, MPI_Datatype t, int root, MPI_Comm comm) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    if (root != 0) return MPI_ERR_RANK;
    return type_size(t) ? MPI_SUCCESS : MPI_ERR_TYPE;
}

int MPI_Ibcast(void *buf, int count, MPI_Datatype t, int root, MPI_Comm comm, MPI_Request *req) {
    int rc = MPI_Bcast(buf, count, t, root, comm);
    if (rc == MPI_SUCCESS) *req = REQ_DONE; /* one rank: complete at once, as Ibarrier */
    return rc;
}

int MPI_Allreduce(const void *sb, void *rb, int count, MPI_Datatype t, MPI_Op op, MPI_Comm comm) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    return copy(sb, rb, count, t);
}

int MPI_Reduce(const void *sb, void *rb, int count, MPI_Datatype t, MPI_Op op, int root,
               MPI_Comm comm) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    if (root != 0) return MPI_ERR_RANK;
    return copy(sb, rb, count, t);
}

int MPI_Exscan(const void *sb, void *rb, int count, MPI_Datatype t, MPI_Op op, MPI_Comm comm) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    return type_size(t) && count >= 0 ? MPI_SUCCESS : MPI_ERR_TYPE; /* rank 0: undefined */
}

int MPI_Gather(const void *sb, int scount, MPI_Datatype st, void *rb, int rcount, MPI_Datatype rt,
               int root, MPI_Comm comm) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    if (root != 0) return MPI_ERR_RANK;
    if (type_size(st) * (size_t)scount != type_size(rt) * (size_t)rcount) return MPI_ERR_TYPE;
    return copy(sb, rb, scount, st);
}

int MPI_Gatherv(const void *sb, int scount, MPI_Datatype st, void *rb, const int *rcounts,
                const int *displs, MPI_Datatype rt, int root, MPI_Comm comm) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    if (root != 0) return MPI_ERR_RANK;
    if (type_size(st) * (size_t)scount != type_size(rt) * (size_t)rcounts[0]) return MPI_ERR_TYPE;
    if (sb == MPI_IN_PLACE) return MPI_SUCCESS;
    return copy(sb, (char *)rb + (size_t)displs[0] * type_size(rt), scount, st);
}

int MPI_Allgather(const void *sb, int scount, MPI_Datatype st, void *rb, int rcount,
                  MPI_Datatype rt, MPI_Comm comm) {
    return MPI_Gather(sb, scount, st, rb, rcount, rt, 0, comm);
}

int MPI_Allgatherv(const void *sb, int scount, MPI_Datatype st, void *rb, const int *rcounts,
                   const int *displs, MPI_Datatype rt, MPI_Comm comm) {
    return MPI_Gatherv(sb, scount, st, rb, rcounts, displs, rt, 0, comm);
}

int MPI_Alltoall(const void *sb, int scount, MPI_Datatype st, void *rb, int rcount, MPI_Datatype rt,
                 MPI_Comm comm) {
    return MPI_Gather(sb, scount, st, rb, rcount, rt, 0, comm);
}

int MPI_Alltoallv(const void *sb, const int *scounts, const int *sdispls, MPI_Datatype st, void *rb,
                  const int *rcounts, const int *rdispls, MPI_Datatype rt, MPI_Comm comm) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    if (type_size(st) * (size_t)scounts[0] != type_size(rt) * (size_t)rcounts[0])
        return MPI_ERR_TYPE;
    if (sb == MPI_IN_PLACE) return MPI_SUCCESS;
    return copy((const char *)sb + (size_t)sdispls[0] * type_size(st),
                (char *)rb + (size_t)rdispls[0] * type_size(rt), scounts[0], st);
}

/* ---- point-to-point and requests ------------------------------------------------------------ */

int MPI_Isend(const void *buf, int count, MPI_Datatype t, int dest, int tag, MPI_Comm comm,
              MPI_Request *req) {
    return MPI_ERR_RANK; /* no peer: the runtime never sends to itself through MPI */
}

int MPI_Recv(void *buf, int count, MPI_Datatype t, int src, int tag, MPI_Comm comm,
             MPI_Status *st) {
    return MPI_ERR_RANK; /* nothing could ever arrive */
}

int MPI_Recv_init(void *buf, int count, MPI_Datatype t, int src, int tag, MPI_Comm comm,
                  MPI_Request *req) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    if (!type_size(t) || count < 0) return MPI_ERR_TYPE;
    *req = REQ_INACTIVE;
    return MPI_SUCCESS;
}

int MPI_Start(MPI_Request *req) {
    if (*req != REQ_INACTIVE) return MPI_ERR_REQUEST;
    *req = REQ_ACTIVE;
    return MPI_SUCCESS;
}

/* Completes *req if it can: 1 (and *req moves on) or 0 (an active receive). */
static int complete(MPI_Request *req, MPI_Status *st) {
    switch (*req) {
    case REQ_ACTIVE:
        return 0;
    case REQ_DONE:
        *req = REQ_NULL;
        break;
    case REQ_CANCELLED:
        *req = REQ_INACTIVE;
        break;
    default: /* null or inactive: completes at once, empty */
        break;
    }
    status_set(st, 0);
    return 1;
}

int MPI_Test(MPI_Request *req, int *flag, MPI_Status *st) {
    *flag = complete(req, st);
    return MPI_SUCCESS;
}

int MPI_Testsome(int n, MPI_Request reqs[], int *outcount, int idx[], MPI_Status sts[]) {
    int live = 0, k = 0;
    for (int i = 0; i < n; i++) {
        if (reqs[i] == REQ_NULL || reqs[i] == REQ_INACTIVE) continue;
        live = 1;
        if (complete(&reqs[i], sts ? &sts[k] : NULL)) idx[k++] = i;
    }
    *outcount = live ? k : MPI_UNDEFINED;
    return MPI_SUCCESS;
}

int MPI_Wait(MPI_Request *req, MPI_Status *st) {
    return complete(req, st) ? MPI_SUCCESS : MPI_ERR_REQUEST;
}

int MPI_Waitall(int n, MPI_Request reqs[], MPI_Status sts[]) {
    for (int i = 0; i < n; i++)
        if (reqs[i] == REQ_ACTIVE) return MPI_ERR_REQUEST;
    for (int i = 0; i < n; i++)
        complete(&reqs[i], sts ? &sts[i] : NULL);
    return MPI_SUCCESS;
}

int MPI_Cancel(MPI_Request *req) {
    if (*req == REQ_ACTIVE) *req = REQ_CANCELLED;
    return MPI_SUCCESS;
}

int MPI_Request_free(MPI_Request *req) {
    *req = REQ_NULL;
    return MPI_SUCCESS;
}

int MPI_Get_count(const MPI_Status *st, MPI_Datatype t, int *count) {
    size_t s = type_size(t);
    if (!s) return MPI_ERR_TYPE;
    *count = st->mpi1_bytes % (int)s == 0 ? st->mpi1_bytes / (int)s : MPI_UNDEFINED;
    return MPI_SUCCESS;
}

/* ---- files ---------------------------------------------------------------------------------- */

int MPI_File_open(MPI_Comm comm, const char *path, int amode, MPI_Info info, MPI_File *fh) {
    if (!comm_ok(comm)) return MPI_ERR_COMM;
    if (amode & ~(MPI_MODE_WRONLY | MPI_MODE_CREATE)) return MPI_ERR_ARG;
    int fd = open(path, O_WRONLY | O_CLOEXEC | (amode & MPI_MODE_CREATE ? O_CREAT : 0), 0666);
    if (fd < 0) return MPI_ERR_IO;
    *fh = fd;
    return MPI_SUCCESS;
}

int MPI_File_write_at(MPI_File fh, MPI_Offset off, const void *buf, int count, MPI_Datatype t,
                      MPI_Status *st) {
    size_t s = type_size(t);
    if (!s || count < 0) return MPI_ERR_TYPE;
    size_t n = (size_t)count * s, done = 0;
    while (done < n) {
        ssize_t w = pwrite(fh, (const char *)buf + done, n - done, (off_t)off + (off_t)done);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return MPI_ERR_IO;
        done += (size_t)w;
    }
    status_set(st, done);
    return MPI_SUCCESS;
}

int MPI_File_sync(MPI_File fh) {
    return fsync(fh) == 0 || errno == EINVAL ? MPI_SUCCESS : MPI_ERR_IO;
}

int MPI_File_close(MPI_File *fh) {
    int rc = close(*fh);
    *fh = MPI_FILE_NULL;
    return rc == 0 ? MPI_SUCCESS : MPI_ERR_IO;
}

int MPI_File_set_errhandler(MPI_File fh, MPI_Errhandler eh) {
    return MPI_SUCCESS;
}
