/* rt.h - public API of the pcdm runtime (a DMCS-like layer, TR-97-17 section 4).
 *
 * The runtime gives an SPMD MPI program three things:
 *   - remote service requests (RSRs): rt_rsr(dest, handler, payload, len) runs a registered
 *     handler on rank dest with a copy of the payload.  Handlers are non-threaded (run inside
 *     the scheduler's poll loop, must not block) or threaded (run on a pooled pthread worker).
 *   - tasks: continuations that run until done or until they wait for N replies to requests
 *     they issued (rt_request / rt_reply); a waiting task sits in the blocking queue and costs
 *     no CPU, its last reply moves it to the FIFO ready queue.  The blocking queue records
 *     what each task waits for (rt_task_label, rt_blocked_dump).
 *   - rt_run: the paper's REPEAT ... UNTIL DONE loop (service RSRs, run ready tasks, run the
 *     application's local work, check termination) with a distributed termination detector,
 *     which also reports a deadlock (tasks blocked for good) instead of hanging.
 *
 * Threads: MPI is called only by the thread that called rt_init (the "main thread").  Every
 * function below is main-thread only unless its contract says "any thread".
 * Errors: recoverable failures return a negative RT_E* code (see rt_strerror); misuse and
 * protocol violations (unknown handler id, bad payload length, ...) are bugs and abort every
 * rank with the rank, file and line.
 * Collective = every rank of rt_comm() must call it, in the same order.  Local = no MPI
 * communication with other ranks.
 */
#ifndef RT_H
#define RT_H

#include <mpi.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* ---- errors ---------------------------------------------------------------------------- */

enum {
    RT_OK = 0,
    RT_EINVAL = -1,    /* bad argument */
    RT_ENOMEM = -2,    /* allocation failed */
    RT_EMPI = -3,      /* an MPI call failed or MPI lacks thread support */
    RT_ETHREAD = -4,   /* a pthread call failed */
    RT_EMISMATCH = -5, /* handler tables differ between ranks */
    RT_ESTATE = -6,    /* call not allowed in the runtime's current state */
    RT_ENOSPC = -7,    /* buffer or table full */
    RT_EHANDLER = -8,  /* unknown / unregistered handler id */
    RT_ELEN = -9,      /* payload length does not match the handler's declaration */
    RT_EPROTO = -10    /* malformed message */
};

/* Local, any thread.  Static string describing err (one of RT_*); never NULL. */
const char *rt_strerror(int err);

/* ---- configuration and life cycle ----------------------------------------------------- */

typedef struct rt_config {
    int aggregate;           /* 1: pack small RSRs per destination into one MPI message (default 1;
                                env RT_AGGREGATE=0|1) */
    uint32_t agg_bytes;      /* capacity of one aggregation buffer in bytes (default 16384; env
                                RT_AGG_BYTES) */
    int nworkers;            /* worker threads for threaded handlers, created once (default 2;
                                env RT_WORKERS) */
    uint64_t perturb_seed;   /* nonzero: delay and reorder delivery between sources, seeded
                                (default 0 = off; env RT_PERTURB=SEED) */
    int idle_spin;           /* 1: when idle only sched_yield, never sleep (latency benchmarks;
                                default 0; env RT_IDLE_SPIN) */
    uint32_t idle_min_ns;    /* first idle sleep (default 2000) */
    uint32_t idle_max_ns;    /* cap of the exponential idle backoff (default 1000000) */
    uint32_t worker_spin_us; /* a worker that finished a job polls (with sched_yield) this long
                                for the next before sleeping (default 0; env
                                RT_WORKER_SPIN_US; latency benchmarks) */
    double net_latency_s;    /* network model (rt_net_set): one-way latency added to every MPI
                                message, seconds (default 0 = off; env PCDM_NET, rt_net_parse) */
    double net_bytes_per_s;  /* network model: bandwidth, bytes per second (0 = unlimited) */
} rt_config;

/* Local.  Fills *cfg with the defaults above (environment not applied). */
void rt_config_default(rt_config *cfg);

/* Collective over MPI_COMM_WORLD.  Initialises MPI with MPI_THREAD_FUNNELED unless it is
 * already initialised (then the provided level must be >= FUNNELED), duplicates
 * MPI_COMM_WORLD into the runtime's communicator and starts the worker pool.  cfg may be NULL
 * (defaults); environment variables override cfg.  argc/argv are passed to MPI_Init_thread
 * (may be NULL).  Returns RT_OK or RT_EMPI / RT_ETHREAD / RT_ESTATE (already initialised). */
int rt_init(int *argc, char ***argv, const rt_config *cfg);

/* Collective over comm.  rt_init for a library inside a program that owns MPI: MPI must
 * already be initialised (MPI_THREAD_FUNNELED or more, called on MPI's main thread; else
 * RT_ESTATE / RT_EMPI); the runtime's communicators are dups of comm (any communicator, e.g.
 * a split of MPI_COMM_WORLD: ranks are numbered in comm), comm's own error handler is left
 * alone, and rt_finalize never finalises MPI.  rt_init and rt_init_comm may be called again
 * after rt_finalize.  Returns as rt_init. */
int rt_init_comm(MPI_Comm comm, const rt_config *cfg);

/* Collective.  Stops the workers, frees the runtime, and calls MPI_Finalize if rt_init
 * initialised MPI.  No RSR may be in flight (call after rt_run returned). */
void rt_finalize(void);

/* Local.  This rank, the number of ranks, and the runtime's private communicator (a dup of
 * MPI_COMM_WORLD; the application may use it for collectives between rt_run calls, but never
 * for point-to-point messages, which the runtime's preposted receives would take). */
int rt_rank(void);
int rt_size(void);
MPI_Comm rt_comm(void);

/* Local.  The communicator the layers above own (another dup of MPI_COMM_WORLD, same ranks):
 * any collective and point-to-point message with any tag, outside rt_run (inside rt_run only
 * from the main thread, and never blocking on a rank that is inside rt_run).  Like rt_comm()
 * and MPI_COMM_WORLD it has MPI_ERRORS_RETURN set, so every call's return code must be
 * checked.  Freed by rt_finalize. */
MPI_Comm rt_app_comm(void);

/* Local, any thread.  Wall-clock seconds (monotonic). */
double rt_wtime(void);

/* ---- handlers ----------------------------------------------------------------------------- */

#define RT_MAX_HANDLERS 64
#define RT_NAME_MAX 32

enum {
    RT_NONTHREADED = 0u, /* runs in the poll loop on the main thread; must not block */
    RT_THREADED = 1u,    /* runs on a worker thread; may block on its own locks, never calls MPI */
    RT_VARSIZE = 2u      /* payload length may be 0..size (else it must equal size exactly) */
};

/* Identifies the task waiting for the reply to a request; travels inside messages. */
typedef struct rt_token {
    int32_t rank; /* rank of the waiting task, -1 if none */
    uint32_t slot;
    uint32_t gen;
} rt_token;

typedef struct rt_task rt_task;

/* What a handler sees.  data points to len bytes aligned to 8, owned by the runtime and valid
 * only during the call (copy what must outlive it).  token is the reply token of a request
 * (rank -1 if the message carries none).  task is non-NULL only in a reply handler: the task
 * whose pending count this reply will decrement after the handler returns. */
typedef struct rt_msg {
    int src;     /* rank that sent this message */
    int handler; /* id of the handler being run */
    const void *data;
    uint32_t len;
    rt_token token;
    rt_task *task;
} rt_msg;

typedef void (*rt_handler_fn)(const rt_msg *m, void *arg);

/* Local (but SPMD: every rank must register the same handlers in the same order, before
 * rt_start).  name: at most RT_NAME_MAX-1 chars, copied.  arg is passed to every call.
 * flags: RT_NONTHREADED or RT_THREADED, optionally | RT_VARSIZE.  size: exact payload size,
 * or the maximum with RT_VARSIZE.  Returns the handler id (0, 1, 2, ... in registration
 * order, so ids agree across ranks) or RT_EINVAL / RT_ENOSPC / RT_ESTATE (after rt_start). */
int rt_handler_register(const char *name, rt_handler_fn fn, void *arg, unsigned flags,
                        uint32_t size);

/* Collective.  Compares the handler tables of all ranks (names, flags, sizes, in order); on a
 * mismatch every rank prints a message naming the first mismatching slot and handler, and
 * the job aborts.  Called by rt_run if the program did not call it.  Idempotent. */
void rt_start(void);

/* ---- remote service requests -------------------------------------------------------------- */

/* Local, any thread (main thread or a threaded handler).  Sends an RSR: handler runs on rank
 * dest (0 <= dest < rt_size(), may be this rank) with a copy of payload[0..len).  The payload
 * is copied before return.  Delivery order between one pair of ranks is FIFO (without
 * perturbation).  The message is sent at the latest at the end of the current scheduler
 * iteration (aggregation) or when the calling threaded handler's RSR reaches the main thread. */
void rt_rsr(int dest, int handler, const void *payload, uint32_t len);

/* ---- tasks ------------------------------------------------------------------------------- */

typedef enum rt_task_status {
    RT_TASK_DONE = 0, /* finished; the runtime forgets the task (state is the caller's) */
    RT_TASK_WAIT = 1, /* wait until every request issued with rt_request has been replied */
    RT_TASK_YIELD = 2 /* run again later (goes to the back of the ready queue) */
} rt_task_status;

typedef rt_task_status (*rt_task_fn)(rt_task *t, void *state);

/* Local, main thread.  Creates a task and appends it to the ready queue; fn(t, state) will be
 * called by the scheduler, again after each WAIT once all replies arrived.  state is owned by
 * the caller (the task typically frees it before returning RT_TASK_DONE).  The returned
 * pointer is valid until fn returns RT_TASK_DONE.  Never NULL (aborts on OOM). */
rt_task *rt_task_spawn(rt_task_fn fn, void *state);

/* Local, main thread, from inside t's function.  Sends a request RSR carrying t's reply
 * token and increments t's pending count.  The request's handler (on dest) or any rank it
 * forwards to must eventually call rt_reply exactly once for it. */
void rt_request(rt_task *t, int dest, int handler, const void *payload, uint32_t len);

/* Local, any thread, from a handler.  Sends a reply RSR to the task named by req->token
 * (handler runs on that task's rank with m->task set, then the task's pending count drops
 * by one).  If req carries no token it is a plain RSR back to req->src. */
void rt_reply(const rt_msg *req, int handler, const void *payload, uint32_t len);

/* Local, any thread, from a handler.  Sends an RSR to dest carrying req's reply token, so the
 * handler on dest (or a later hop) answers the original requester with rt_reply. */
void rt_forward(const rt_msg *req, int dest, int handler, const void *payload, uint32_t len);

/* Local, main thread.  Replies still outstanding for t. */
int rt_task_pending(const rt_task *t);

/* Local, main thread.  The state pointer t was spawned with (for reply handlers, which get
 * the task as m->task). */
void *rt_task_data(const rt_task *t);

#define RT_LABEL_MAX 48

/* Local, main thread, while t is live (from its function, or from a reply handler through
 * m->task).  Sets t's label, printf-style, shown by rt_blocked_dump (say what the task waits
 * for: "cavity 17 at rank 3").  Copied into t (at most RT_LABEL_MAX-1 chars, the rest is cut
 * off); kept until changed or the task finishes.  A new task has an empty label. */
#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
void rt_task_label(rt_task *t, const char *fmt, ...);

/* Local, main thread.  Prints one line per task of this rank's blocking queue to f, longest
 * blocked first: rank, task slot, pending replies, destination rank and handler of its most
 * recent rt_request, label, seconds blocked.  Prints nothing when no task is blocked. */
void rt_blocked_dump(FILE *f);

/* ---- scheduler ------------------------------------------------------------------------- */

enum { RT_WORK_IDLE = 0, RT_WORK_BUSY = 1 };

/* The application's local work step: do a bounded amount of work (e.g. a few hundred point
 * insertions) and return RT_WORK_BUSY if it did work or has more, RT_WORK_IDLE if it has
 * none.  Contract: after returning IDLE it may return BUSY again only after a handler or task
 * ran on this rank (new work arrives only through RSRs), otherwise termination is wrong. */
typedef int (*rt_work_fn)(void *ctx);

/* Collective.  Runs the scheduler loop until distributed termination: every rank passive (no
 * ready or blocked task, local work IDLE, no threaded handler queued or running, no RSR
 * buffered or held) and no RSR in flight.  work may be NULL.  May be called again later
 * (e.g. per phase): no rank returns before every rank has seen termination, so RSRs sent
 * after rt_run returned are handled in the next rt_run (RSRs sent outside rt_run wait for
 * it).  Returns RT_OK.
 * Deadlock: if every rank is passive except for blocked tasks and no RSR is in flight, no
 * reply can ever arrive (a request whose handler never replies, ...).  Then every rank
 * prints "rt: rank R: deadlock: ..." and its rt_blocked_dump to stderr, and the job fails
 * through the fatal path (rank, file, line; exit status 70) instead of hanging. */
int rt_run(rt_work_fn work, void *ctx);

/* Local, main thread, outside rt_run, after rt_init.  At least n worker threads for threaded
 * handlers from now on: the missing ones are started (none is ever stopped before
 * rt_finalize).  Returns RT_OK, RT_EINVAL (n < 0 or n > 256), RT_ESTATE (inside rt_run or a
 * handler, or before rt_init) or RT_ETHREAD. */
int rt_workers_ensure(int n);

/* Local, any thread.  The CPUs this process may run on (its affinity mask on Linux: a launcher
 * that binds a rank to one core leaves 1; elsewhere the CPUs online), at least 1. */
int rt_cpus(void);

/* Local, main thread, outside rt_run.  Turns perturbation on with seed (0: off), replacing
 * the configured seed; lets one program run the same computation under several seeds.
 * Returns RT_OK or RT_ESTATE (inside rt_run). */
int rt_perturb_set(uint64_t seed);

/* ---- network model ------------------------------------------------------------------------ */

/* A slower network than this machine's, for asking how a program degrades as messages get
 * costly.  With latency L and bandwidth B on, every MPI message the runtime receives from
 * another rank (an aggregate of RSRs, or a control record) is copied into a holding queue of
 * its source when it arrives and delivered only when it is due: the link from that source is
 * busy for size/B after the later of the arrival and the end of the previous message from it,
 * and the message is due L after that.  So the order from each source is kept, bandwidth is
 * shared by the messages of one link, and the sender never waits.  The delay adds to this
 * machine's own transport time (about 1 us between ranks of one node).  Self-sends and large
 * messages' bodies (RT_TAG_BIG, announced by a delayed record) are not delayed.  A rank
 * holding a message is not passive, so termination stays correct.  "sp2" = 29 us, 33.6 MB/s:
 * TR-97-17's DMCS figures for the IBM SP2. */

/* Local, any thread.  Parses a model: "off" or "0" (no model), "sp2", or "LAT_US[,MBPS]"
 * (microseconds, megabytes (1e6 bytes) per second; MBPS omitted or 0: unlimited).  Sets
 * *latency_s and *bytes_per_s; returns RT_OK or RT_EINVAL (then they are left alone). */
int rt_net_parse(const char *spec, double *latency_s, double *bytes_per_s);

/* Local, main thread, outside rt_run (every rank should set the same model).  latency_s 0 and
 * bytes_per_s 0 turn the model off.  Overrides rt_config and PCDM_NET.  Returns RT_OK,
 * RT_EINVAL (negative or not finite) or RT_ESTATE (inside rt_run). */
int rt_net_set(double latency_s, double bytes_per_s);

/* Local.  The model in force (both 0: off). */
void rt_net_get(double *latency_s, double *bytes_per_s);

/* ---- statistics -------------------------------------------------------------------------- */

typedef enum rt_time_bucket {
    RT_TIME_HANDLER = 0, /* in handlers (non-threaded and threaded) */
    RT_TIME_COMM,        /* in MPI calls, packing, polling that found nothing */
    RT_TIME_IDLE,        /* sleeping or yielding with nothing to do */
    RT_TIME_BUSY,        /* in tasks and the application's local work */
    RT_TIME_UNDO,        /* application-defined (PBW: work undone after a lock conflict) */
    RT_TIME_NBUCKETS
} rt_time_bucket;

typedef struct rt_stats {
    uint64_t rsr_sent, rsr_recv;             /* RSRs (including self-sends) */
    uint64_t rsr_bytes_sent, rsr_bytes_recv; /* RSR payload bytes */
    uint64_t mpi_sent, mpi_recv;             /* MPI messages (an aggregate counts once) */
    uint64_t mpi_bytes_sent, mpi_bytes_recv; /* MPI message bytes (headers included) */
    uint64_t tasks_spawned, tasks_done;
    uint64_t waves;         /* termination detection waves */
    uint64_t blocked_count; /* times a task entered the blocking queue */
    uint64_t blocked_max;   /* most tasks blocked at once (a maximum) */
    double time[RT_TIME_NBUCKETS];
    double blocked_time_sum; /* seconds spent blocked, summed over the tasks that woke up */
    double blocked_time_max; /* longest single stretch a task spent blocked (a maximum) */
    /* Communication seconds, measured the same way whatever the program: sending (each
     * flush of an aggregation buffer to MPI, large messages, delivering self-sends; the copy
     * of a record into a buffer stays in its caller's time, tens of nanoseconds) and the polls that
     * received an RSR (receiving, unpacking, dispatching, completing sends), with the handlers' own
     * run time taken out (it is RT_TIME_HANDLER); polls that found nothing and the termination
     * detector's control records are left out.  Unlike RT_TIME_COMM it does not grow with idle
     * polling. */
    double comm_s;
} rt_stats;

typedef struct rt_handler_stats {
    char name[RT_NAME_MAX];
    uint64_t sent, recv, bytes_sent, bytes_recv;
    uint64_t sent_self; /* of sent: to this rank itself (no communication) */
    double time;
} rt_handler_stats;

/* Local, main thread.  This rank's counters. */
void rt_stats_local(rt_stats *out);

/* Local, main thread.  This rank's counters of handler id (RT_EINVAL if not registered). */
int rt_stats_handler(int id, rt_handler_stats *out);

/* Collective.  sum (may be NULL) gets the sum over ranks of every field except the maxima
 * (blocked_max, blocked_time_max), which are the maximum over ranks there too; max (may be
 * NULL) the maximum of every field.  Every rank gets the result. */
void rt_stats_reduce(rt_stats *sum, rt_stats *max);

/* Local, main thread.  Adds seconds to bucket b (the application uses RT_TIME_UNDO). */
void rt_stats_add_time(rt_time_bucket b, double seconds);

/* Local, main thread.  Zeroes this rank's counters and timers. */
void rt_stats_reset(void);

/* Collective.  Gathers every rank's counters to rank 0, which prints a per-rank table and a
 * per-handler table of totals to f (f is only used on rank 0; may be NULL elsewhere). */
void rt_stats_print(FILE *f);

#endif
