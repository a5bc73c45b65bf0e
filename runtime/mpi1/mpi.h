/* mpi.h (runtime/mpi1): a one-process stand-in for MPI -- exactly the subset the runtime and
 * the parallel meshers call, for a communicator of one rank.  With this folder on the include
 * path in place of an MPI implementation's, the parallel stack (runtime/, the decomposition,
 * PCDM, the parallel end of the driver, pcdm_triangulate_par) compiles into a build with no MPI
 * at all, in which one process runs the very code ./pcdm runs, its subdomains refined by the
 * runtime's worker threads (libpcdm_threads, the Python package's threaded path).  Only that
 * build may put this folder on its include path (tests/t_layers.sh: no source names it).
 *
 * Semantics, for one rank (every communicator has size 1, rank 0):
 *  - collectives are copies (Allreduce, Allgather(v), Alltoall(v), Gather(v), Reduce: the
 *    send buffer into the receive buffer unless MPI_IN_PLACE; Bcast, Barrier: nothing;
 *    Exscan leaves the receive buffer as it is, as MPI leaves rank 0's undefined);
 *  - point-to-point: a one-rank communicator has no rank but itself and the runtime sends to
 *    itself without MPI, so a send (Isend) or a blocking receive (Recv) is an error (MPI_ERR_RANK:
 *    the caller's MPI check reports it as a bug); persistent receives (Recv_init, Start) stay
 *    pending for ever and can be cancelled (Cancel, then Wait) and freed;
 *  - a request lives in its handle's value (MPI_Request is an int): no table, no allocation;
 *  - MPI_File_* are POSIX open/pwrite/close; MPI_Abort is abort() (the project's bug tier);
 *  - MPI is always initialised and never finalised; the thread level is MPI_THREAD_FUNNELED
 *    and every thread counts as the main one (the runtime calls from one thread: the caller's).
 * Every function is renamed (pcdm_mpi1_*) so that a process holding a real MPI as well (a
 * Python session with mpi4py) never mixes the two.
 */
#ifndef PCDM_MPI1_H
#define PCDM_MPI1_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PCDM_MPI1 1

typedef int MPI_Comm;
typedef int MPI_Datatype; /* > 0: a predefined type; < 0: a contiguous type of -h bytes */
typedef int MPI_Op;
typedef int MPI_Request; /* the request's state (mpi1.c) */
typedef int MPI_Errhandler;
typedef int MPI_Info;
typedef int MPI_File; /* a POSIX file descriptor, -1: MPI_FILE_NULL */
typedef long long MPI_Offset;

typedef struct MPI_Status {
    int MPI_SOURCE;
    int MPI_TAG;
    int MPI_ERROR;
    int mpi1_bytes; /* the bytes the operation moved (MPI_Get_count) */
} MPI_Status;

enum {
    MPI_SUCCESS = 0,
    MPI_ERR_ARG = 12,
    MPI_ERR_RANK = 6,
    MPI_ERR_REQUEST = 19,
    MPI_ERR_IO = 32,
    MPI_ERR_TYPE = 3,
    MPI_ERR_COMM = 5
};

#define MPI_COMM_NULL 0
#define MPI_COMM_WORLD 1
#define MPI_COMM_SELF 2

#define MPI_BYTE 1
#define MPI_CHAR 2
#define MPI_INT 3
#define MPI_LONG 4
#define MPI_LONG_LONG 5
#define MPI_UNSIGNED_LONG 6
#define MPI_DOUBLE 7
#define MPI_INT32_T 8
#define MPI_INT64_T 9
#define MPI_UINT8_T 10
#define MPI_UINT64_T 11
#define MPI_DATATYPE_NULL 0

#define MPI_SUM 1
#define MPI_MAX 2
#define MPI_MIN 3

#define MPI_REQUEST_NULL 0
#define MPI_ERRORS_RETURN 1
#define MPI_ERRORS_ARE_FATAL 2
#define MPI_INFO_NULL 0
#define MPI_COMM_TYPE_SHARED 1
#define MPI_FILE_NULL (-1)

#define MPI_THREAD_SINGLE 0
#define MPI_THREAD_FUNNELED 1
#define MPI_THREAD_SERIALIZED 2
#define MPI_THREAD_MULTIPLE 3

#define MPI_ANY_SOURCE (-1)
#define MPI_ANY_TAG (-1)
#define MPI_UNDEFINED (-32766)
#define MPI_MAX_ERROR_STRING 256
#define MPI_MODE_WRONLY 4
#define MPI_MODE_CREATE 1

#define MPI_IN_PLACE ((void *)1)
#define MPI_STATUS_IGNORE ((MPI_Status *)0)
#define MPI_STATUSES_IGNORE ((MPI_Status *)0)

/* the renaming (see the top) */
#define MPI_Abort pcdm_mpi1_Abort
#define MPI_Allgather pcdm_mpi1_Allgather
#define MPI_Allgatherv pcdm_mpi1_Allgatherv
#define MPI_Allreduce pcdm_mpi1_Allreduce
#define MPI_Alltoall pcdm_mpi1_Alltoall
#define MPI_Alltoallv pcdm_mpi1_Alltoallv
#define MPI_Barrier pcdm_mpi1_Barrier
#define MPI_Bcast pcdm_mpi1_Bcast
#define MPI_Ibcast pcdm_mpi1_Ibcast
#define MPI_Cancel pcdm_mpi1_Cancel
#define MPI_Comm_dup pcdm_mpi1_Comm_dup
#define MPI_Comm_free pcdm_mpi1_Comm_free
#define MPI_Comm_rank pcdm_mpi1_Comm_rank
#define MPI_Comm_set_errhandler pcdm_mpi1_Comm_set_errhandler
#define MPI_Comm_size pcdm_mpi1_Comm_size
#define MPI_Comm_split_type pcdm_mpi1_Comm_split_type
#define MPI_Error_string pcdm_mpi1_Error_string
#define MPI_Exscan pcdm_mpi1_Exscan
#define MPI_File_close pcdm_mpi1_File_close
#define MPI_File_open pcdm_mpi1_File_open
#define MPI_File_set_errhandler pcdm_mpi1_File_set_errhandler
#define MPI_File_sync pcdm_mpi1_File_sync
#define MPI_File_write_at pcdm_mpi1_File_write_at
#define MPI_Finalize pcdm_mpi1_Finalize
#define MPI_Finalized pcdm_mpi1_Finalized
#define MPI_Gather pcdm_mpi1_Gather
#define MPI_Gatherv pcdm_mpi1_Gatherv
#define MPI_Get_count pcdm_mpi1_Get_count
#define MPI_Ibarrier pcdm_mpi1_Ibarrier
#define MPI_Init pcdm_mpi1_Init
#define MPI_Init_thread pcdm_mpi1_Init_thread
#define MPI_Initialized pcdm_mpi1_Initialized
#define MPI_Is_thread_main pcdm_mpi1_Is_thread_main
#define MPI_Isend pcdm_mpi1_Isend
#define MPI_Query_thread pcdm_mpi1_Query_thread
#define MPI_Recv pcdm_mpi1_Recv
#define MPI_Recv_init pcdm_mpi1_Recv_init
#define MPI_Reduce pcdm_mpi1_Reduce
#define MPI_Request_free pcdm_mpi1_Request_free
#define MPI_Start pcdm_mpi1_Start
#define MPI_Test pcdm_mpi1_Test
#define MPI_Testsome pcdm_mpi1_Testsome
#define MPI_Type_commit pcdm_mpi1_Type_commit
#define MPI_Type_contiguous pcdm_mpi1_Type_contiguous
#define MPI_Type_free pcdm_mpi1_Type_free
#define MPI_Wait pcdm_mpi1_Wait
#define MPI_Waitall pcdm_mpi1_Waitall
#define MPI_Wtime pcdm_mpi1_Wtime

/* life cycle and environment */
int MPI_Init(int *argc, char ***argv);
int MPI_Init_thread(int *argc, char ***argv, int required, int *provided);
int MPI_Initialized(int *flag);
int MPI_Finalized(int *flag);
int MPI_Finalize(void);
int MPI_Query_thread(int *provided);
int MPI_Is_thread_main(int *flag);
_Noreturn int MPI_Abort(MPI_Comm comm, int code);
int MPI_Error_string(int code, char *s, int *len);
double MPI_Wtime(void);

/* communicators */
int MPI_Comm_dup(MPI_Comm comm, MPI_Comm *out);
int MPI_Comm_free(MPI_Comm *comm);
int MPI_Comm_rank(MPI_Comm comm, int *rank);
int MPI_Comm_size(MPI_Comm comm, int *size);
int MPI_Comm_split_type(MPI_Comm comm, int type, int key, MPI_Info info, MPI_Comm *out);
int MPI_Comm_set_errhandler(MPI_Comm comm, MPI_Errhandler eh);

/* datatypes */
int MPI_Type_contiguous(int count, MPI_Datatype old, MPI_Datatype *out);
int MPI_Type_commit(MPI_Datatype *t);
int MPI_Type_free(MPI_Datatype *t);

/* collectives */
int MPI_Barrier(MPI_Comm comm);
int MPI_Ibarrier(MPI_Comm comm, MPI_Request *req);
int MPI_Bcast(void *buf, int count, MPI_Datatype t, int root, MPI_Comm comm);
int MPI_Ibcast(void *buf, int count, MPI_Datatype t, int root, MPI_Comm comm, MPI_Request *req);
int MPI_Allreduce(const void *sb, void *rb, int count, MPI_Datatype t, MPI_Op op, MPI_Comm comm);
int MPI_Reduce(const void *sb, void *rb, int count, MPI_Datatype t, MPI_Op op, int root,
               MPI_Comm comm);
int MPI_Exscan(const void *sb, void *rb, int count, MPI_Datatype t, MPI_Op op, MPI_Comm comm);
int MPI_Gather(const void *sb, int scount, MPI_Datatype st, void *rb, int rcount, MPI_Datatype rt,
               int root, MPI_Comm comm);
int MPI_Gatherv(const void *sb, int scount, MPI_Datatype st, void *rb, const int *rcounts,
                const int *displs, MPI_Datatype rt, int root, MPI_Comm comm);
int MPI_Allgather(const void *sb, int scount, MPI_Datatype st, void *rb, int rcount,
                  MPI_Datatype rt, MPI_Comm comm);
int MPI_Allgatherv(const void *sb, int scount, MPI_Datatype st, void *rb, const int *rcounts,
                   const int *displs, MPI_Datatype rt, MPI_Comm comm);
int MPI_Alltoall(const void *sb, int scount, MPI_Datatype st, void *rb, int rcount, MPI_Datatype rt,
                 MPI_Comm comm);
int MPI_Alltoallv(const void *sb, const int *scounts, const int *sdispls, MPI_Datatype st, void *rb,
                  const int *rcounts, const int *rdispls, MPI_Datatype rt, MPI_Comm comm);

/* point-to-point and requests */
int MPI_Isend(const void *buf, int count, MPI_Datatype t, int dest, int tag, MPI_Comm comm,
              MPI_Request *req);
int MPI_Recv(void *buf, int count, MPI_Datatype t, int src, int tag, MPI_Comm comm, MPI_Status *st);
int MPI_Recv_init(void *buf, int count, MPI_Datatype t, int src, int tag, MPI_Comm comm,
                  MPI_Request *req);
int MPI_Start(MPI_Request *req);
int MPI_Test(MPI_Request *req, int *flag, MPI_Status *st);
int MPI_Testsome(int n, MPI_Request reqs[], int *outcount, int idx[], MPI_Status sts[]);
int MPI_Wait(MPI_Request *req, MPI_Status *st);
int MPI_Waitall(int n, MPI_Request reqs[], MPI_Status sts[]);
int MPI_Cancel(MPI_Request *req);
int MPI_Request_free(MPI_Request *req);
int MPI_Get_count(const MPI_Status *st, MPI_Datatype t, int *count);

/* files: POSIX underneath (the file exists: the parallel writers create it first) */
int MPI_File_open(MPI_Comm comm, const char *path, int amode, MPI_Info info, MPI_File *fh);
int MPI_File_write_at(MPI_File fh, MPI_Offset off, const void *buf, int count, MPI_Datatype t,
                      MPI_Status *st);
int MPI_File_close(MPI_File *fh);
int MPI_File_sync(MPI_File fh);
int MPI_File_set_errhandler(MPI_File fh, MPI_Errhandler eh);

#ifdef __cplusplus
}
#endif

#endif
