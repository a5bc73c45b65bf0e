/* rt_internal.h - internals shared by the runtime's modules and its unit tests.
 *
 * Never included by applications.  Sections: allocation and fatal errors, intrusive FIFO
 * queues (rt_queue.c), wire format and packing (rt_msg.c), handler table (rt_handler.c),
 * tasks (rt_task.c), termination waves (rt_term.c), perturbation (rt_perturb.c), worker pool
 * (rt_worker.c), transport (rt_comm.c), the global runtime state (rt.c).
 *
 * Lock order: there is one lock, rt_g.wlock (worker pool + cross-thread queues).  Everything
 * else in rt_g is touched by the main thread only.
 */
#ifndef RT_INTERNAL_H
#define RT_INTERNAL_H

#include "rt.h"

#include <pthread.h>
#include <stdbool.h>

/* ---- allocation funnel and fatal errors (rt.c) ----------------------------------------- */

void *rt_xmalloc(size_t n);
void *rt_xrealloc(void *p, size_t n);
void rt_xfree(void *p);
#if defined(__GNUC__)
__attribute__((noreturn, format(printf, 3, 4)))
#endif
void rt_fatal_at(const char *file, int line, const char *fmt, ...);
#define RT_FATAL(...) rt_fatal_at(__FILE__, __LINE__, __VA_ARGS__)
/* Seconds, for intervals measured on the main thread (cheaper than rt_wtime where it can). */
double rt_now(void);
/* Before MPI_Init (rt.c): asks Open MPI for the ob1 point-to-point layer (OMPI_MCA_pml=ob1)
 * when every rank runs on one node and the user has not chosen one; 1 if it did. */
int rt_prefer_local_pml(void);
/* Before MPI_Init (rt.c): asks hwloc to leave I/O devices out of the topology Open MPI discovers
 * (HWLOC_COMPONENTS=-linuxio,-pci) when every rank runs on one node and the user has not chosen;
 * 1 if it did. */
int rt_prefer_cpu_topology(void);
/* Before MPI_Init (rt.c): asks Open MPI to run a singleton (no launcher) without its daemon
 * (OMPI_MCA_ess_singleton_isolated=1) unless the user has chosen; 1 if it did. */
int rt_prefer_isolated_singleton(void);
#define RT_CHECK(c)                                                                                \
    do {                                                                                           \
        if (!(c)) RT_FATAL("check failed: %s", #c);                                                \
    } while (0)
#define RT_MPI(call)                                                                               \
    do {                                                                                           \
        int rt_mpi_rc_ = (call);                                                                   \
        if (rt_mpi_rc_ != MPI_SUCCESS) RT_FATAL("%s failed (MPI error %d)", #call, rt_mpi_rc_);    \
    } while (0)

/* ---- intrusive FIFO queue (rt_queue.c) -------------------------------------------------- */

typedef struct rt_qnode {
    struct rt_qnode *next;
} rt_qnode;

typedef struct rt_queue {
    rt_qnode *head, *tail;
    size_t n;
} rt_queue;

void rt_queue_init(rt_queue *q);
static inline bool rt_queue_empty(const rt_queue *q) { /* inline: on every poll */
    return q->head == NULL;
}
void rt_queue_push(rt_queue *q, rt_qnode *n);       /* append at the tail */
rt_qnode *rt_queue_pop(rt_queue *q);                /* remove the head, NULL if empty */
void rt_queue_append(rt_queue *dst, rt_queue *src); /* move all of src to dst's tail */

#define RT_CONTAINER(ptr, type, member) ((type *)(void *)((char *)(ptr)-offsetof(type, member)))

/* ---- wire format (rt_msg.c) --------------------------------------------------------------- */

enum {
    RT_HF_TOKEN = 1u, /* header carries a reply token (a request or forwarded request) */
    RT_HF_REPLY = 2u  /* completes the token's task after the handler */
};

/* One RSR on the wire: this header, then len payload bytes, padded to a multiple of 8. */
typedef struct rt_hdr {
    uint16_t handler;
    uint16_t flags; /* RT_HF_* */
    int32_t src;
    uint32_t len;
    int32_t tok_rank;
    uint32_t tok_slot;
    uint32_t tok_gen;
} rt_hdr;
_Static_assert(sizeof(rt_hdr) == 24, "rt_hdr must be 24 bytes with no padding");
_Static_assert(sizeof(rt_hdr) % 8 == 0, "payloads must stay 8-byte aligned");

#define RT_MAX_PAYLOAD (1u << 30)

size_t rt_wire_size(uint32_t len); /* header + padded payload */
/* Appends one record at buf+*used; RT_ENOSPC (nothing written) if it does not fit in cap. */
int rt_pack(unsigned char *buf, size_t cap, size_t *used, const rt_hdr *h, const void *payload);
/* Reads the record at buf+*off: 1 and advances *off, 0 at the end, RT_EPROTO if malformed.
 * *payload points into buf. */
int rt_unpack(const unsigned char *buf, size_t n, size_t *off, rt_hdr *h,
              const unsigned char **payload);

/* An owned RSR: header and a payload copy (self-sends, threaded jobs, held messages). */
typedef struct rt_item {
    rt_qnode q;
    rt_hdr h;
    uint64_t release_at; /* perturbation: poll iteration at which it may be delivered */
    double elapsed;      /* threaded handler: seconds spent in the handler */
    int dest;            /* RSR sent by a worker: its destination */
    _Alignas(8) unsigned char data[];
} rt_item;

rt_item *rt_item_new(const rt_hdr *h, const void *payload);

/* ---- handler table (rt_handler.c) -------------------------------------------------------- */

typedef struct rt_hentry {
    char name[RT_NAME_MAX];
    rt_handler_fn fn;
    void *arg;
    uint32_t flags, size;
    bool registered;
    uint64_t sent, recv, bytes_sent, bytes_recv; /* statistics (main thread) */
    uint64_t sent_self;                          /* ... of sent, to this rank itself */
    double time;
} rt_hentry;

typedef struct rt_htable {
    rt_hentry e[RT_MAX_HANDLERS];
    int n;
    bool frozen; /* set by rt_start: no more registrations */
} rt_htable;

/* What ranks compare at rt_start. */
typedef struct rt_hsig {
    char name[RT_NAME_MAX];
    uint32_t flags, size;
} rt_hsig;

void rt_htable_init(rt_htable *t); /* every slot gets the fatal "unregistered" stub */
int rt_htable_add(rt_htable *t, const char *name, rt_handler_fn fn, void *arg, unsigned flags,
                  uint32_t size);
/* RT_OK, RT_EHANDLER (id out of range or unregistered) or RT_ELEN. */
int rt_htable_check(const rt_htable *t, uint32_t id, uint32_t len);
void rt_htable_sig(const rt_htable *t, rt_hsig out[RT_MAX_HANDLERS]);
/* First slot where a and b differ (registered-ness, name, flags or size), -1 if equal. */
int rt_hsig_compare(const rt_hsig a[RT_MAX_HANDLERS], const rt_hsig b[RT_MAX_HANDLERS]);
void rt_handler_unregistered(const rt_msg *m, void *arg); /* the stub: aborts */

/* ---- tasks (rt_task.c) ------------------------------------------------------------------- */

typedef enum rt_task_state {
    RT_TS_FREE = 0, /* slot unused (or the task finished: done) */
    RT_TS_NEW,
    RT_TS_READY,
    RT_TS_RUNNING,
    RT_TS_BLOCKED
} rt_task_state;

struct rt_task {
    rt_qnode q; /* ready queue or free list (a blocked task is on neither) */
    rt_task_fn fn;
    void *state;
    uint32_t slot, gen;
    int32_t pending;
    rt_task_state st;
    struct rt_task *bprev, *bnext; /* blocking queue links, while BLOCKED */
    double blocked_at;             /* rt_now() when it last became BLOCKED */
    int32_t last_dest;             /* rank and handler of its last request, -1 if none */
    int32_t last_handler;
    char label[RT_LABEL_MAX]; /* rt_task_label, "" if none */
};

typedef struct rt_tasks {
    rt_task **slot; /* every task ever allocated, by slot; reused after DONE with gen+1 */
    uint32_t nslot, cap;
    rt_queue free_q, ready;
    rt_task *bhead, *btail; /* the blocking queue, in order of blocking (oldest first) */
    size_t nblocked, nlive; /* nblocked: length of the blocking queue */
    uint64_t spawned, done;
    /* statistics of the blocking queue (rt_stats) */
    uint64_t blocked_count, blocked_max;
    double blocked_time_sum, blocked_time_max;
} rt_tasks;

void rt_tasks_init(rt_tasks *ts);
void rt_tasks_destroy(rt_tasks *ts);
rt_task *rt_tasks_spawn(rt_tasks *ts, rt_task_fn fn, void *state); /* NEW -> READY */
size_t rt_tasks_run(rt_tasks *ts, size_t max); /* runs up to max ready tasks; returns count */
/* pending++; records the request (dest, handler) as t's last one. */
rt_token rt_task_take_token(rt_task *t, int rank, int dest, int handler);
rt_task *rt_tasks_lookup(rt_tasks *ts, rt_token tok); /* NULL if stale or invalid */
void rt_tasks_reply(rt_tasks *ts, rt_task *t);        /* pending--; BLOCKED -> READY at 0 */
/* Zeroes the task statistics: spawned, done and the blocking queue's (blocked_max restarts
 * at the current length). */
void rt_tasks_reset_stats(rt_tasks *ts);
/* One line per blocked task to f, oldest first (rt_blocked_dump); handler names from ht if
 * not NULL; now: the current rt_now(). */
void rt_tasks_dump(const rt_tasks *ts, int rank, const rt_htable *ht, double now, FILE *f);

/* ---- termination detection (rt_term.c) -------------------------------------------------- */

/* Control records: handler ids above the table, sent with rt_send_ctl (not counted as RSRs). */
#define RT_CTL_TOKEN 0xFFFEu /* payload int64_t[RT_TOK_N]: the termination token */
#define RT_CTL_TERM 0xFFFDu  /* empty: rank 0 declared termination */
/* payload int64_t: rank 0 found that many tasks blocked for good; every rank reports them
 * and aborts (rt_term.c, rt.c) */
#define RT_CTL_DEADLOCK 0xFFFCu

enum { RT_TOK_SENT = 0, RT_TOK_RECV, RT_TOK_BLACK, RT_TOK_BLOCKED, RT_TOK_N };

typedef struct rt_term {
    bool active;           /* black: activity since this rank last passed (or started) the token */
    bool have_token;       /* the token is here */
    bool round_open;       /* rank 0: a round is under way */
    bool done;             /* rank != 0: TERM received */
    bool deadlock;         /* DEADLOCK declared (rank 0) or received (other ranks) */
    int64_t tok[RT_TOK_N]; /* the token while here: sent, received, black, blocked tasks */
    int64_t deadlock_blocked; /* with deadlock: tasks blocked on all ranks */
    uint64_t waves;           /* rounds started (rank 0) or tokens passed on (other ranks) */
} rt_term;

typedef enum rt_term_verdict {
    RT_TERM_GOING = 0, /* no decision (not rank 0, no token here, or the round failed) */
    RT_TERM_DONE,      /* rank 0: termination declared, TERM sent to every other rank */
    RT_TERM_DEADLOCK   /* rank 0: deadlock declared, DEADLOCK sent to every other rank */
} rt_term_verdict;

void rt_term_init(rt_term *t, int rank);
/* The decision on a returned round's {sent, received, black}: nothing in flight, nobody
 * active (blocked tasks are judged by the caller). */
bool rt_term_decide(const int64_t result[3]);
/* A token record arrived (main thread, from the transport). */
void rt_term_token(rt_term *t, const int64_t tok[RT_TOK_N]);
/* Call only while locally quiescent (passive except for blocked tasks; nblocked of them).
 * Passes on a held token adding this rank's counts; on rank 0 decides a returned round and,
 * if may_start, starts a new one. */
rt_term_verdict rt_term_pass(rt_term *t, int rank, int size, uint64_t sent, uint64_t recvd,
                             uint64_t nblocked, bool may_start);

/* ---- perturbation (rt_perturb.c) --------------------------------------------------------- */

typedef struct rt_perturb {
    uint64_t rng;
    uint64_t iter;
    rt_queue *held; /* per source FIFO */
    int *perm;
    int nsrc;
    size_t nheld;
} rt_perturb;

void rt_perturb_init(rt_perturb *p, uint64_t seed, int nsrc);
void rt_perturb_destroy(rt_perturb *p);
uint64_t rt_perturb_rand(rt_perturb *p);
void rt_perturb_hold(rt_perturb *p, rt_item *it, int src);
/* Advances one poll iteration and hands every due message to deliver(); returns how many. */
size_t rt_perturb_release(rt_perturb *p, void (*deliver)(rt_item *it));

/* ---- network model (rt_net.c) ------------------------------------------------------------ */

/* One MPI message held until its delivery time (a copy of the receive buffer). */
typedef struct rt_netmsg {
    rt_qnode q;
    double due; /* rt_now() at which it may be delivered */
    size_t n;
    int src;
    _Alignas(8) unsigned char data[];
} rt_netmsg;

typedef struct rt_net {
    double latency_s, bytes_per_s; /* both 0: off */
    bool on;
    rt_queue *held;   /* per source, FIFO; due times increase along each queue */
    double *link_end; /* per source: when its link finishes the last message held */
    int nsrc;
    size_t nheld;
    uint64_t delayed; /* messages held so far */
} rt_net;

void rt_net_init(rt_net *n, int nsrc, double latency_s, double bytes_per_s);
void rt_net_destroy(rt_net *n);
/* Main thread: copies the message (n bytes of buf from src, arrived now) into its source's
 * queue with its delivery time. */
void rt_net_hold(rt_net *n, const unsigned char *buf, size_t len, int src, double now);
/* Main thread: hands every held message due by now to rt_comm_process, in order per source;
 * true if one of them carried an RSR. */
bool rt_net_release(rt_net *n, double now);
/* Seconds from now to the earliest delivery time (0 if one is due; only with nheld > 0). */
double rt_net_wait(const rt_net *n, double now);

/* ---- worker pool (rt_worker.c) ----------------------------------------------------------- */

int rt_workers_start(int n);
/* Starts workers until there are n (none stopped); main thread, outside rt_run. */
int rt_workers_grow(int n);
void rt_workers_stop(void);
void rt_workers_submit(rt_item *it); /* main thread: run a threaded handler */
/* Main thread: moves RSRs sent by workers and finished jobs out; true if any. */
bool rt_workers_drain(void);
/* Main thread: waits up to ns for worker activity (or returns at once if there is some), or,
 * when rt_wait_sockets applies, for a message on the transport's sockets (up to long_ns when
 * every message arrives through them; long_ns <= ns means no such wait). */
void rt_workers_idle_wait(uint64_t ns, uint64_t long_ns);

/* ---- idle wait on the transport's sockets (rt_wait.c) ------------------------------------ */

#define RT_WAIT_MAXSOCK 256
typedef struct rt_waitst {
    bool on;              /* the job spans hosts (or RT_SOCKET_WAIT=1) */
    bool only;            /* every peer is reached through TCP sockets (pml ob1, btl tcp,self) */
    unsigned long slack0; /* the main thread's timer slack outside the long wait */
    int wake_fd;          /* eventfd written by workers while the main thread polls; -1 none */
    int nsock;            /* TCP sockets found by the last scan (connected, listening) */
    int sock[RT_WAIT_MAXSOCK];
    bool listening[RT_WAIT_MAXSOCK]; /* sock[i] listens: readable when a peer connects */
    unsigned char *talked;           /* [rank] this rank has sent to it; NULL when not on */
    double scanned;                  /* rt_wtime of the last scan, -1 never */
    int idle_wakes;                  /* wake-ups in a row with no RSR received */
    int spin;                        /* polls of MPI left before the next wait (after a wake-up) */
    uint64_t recvd_seen;             /* rt_g.recvd at the last wait */
    _Atomic int polling;             /* the main thread is in (or about to enter) ppoll */
} rt_waitst;
void rt_wait_init(void); /* after the workers started */
void rt_wait_fini(void);
/* Main thread, sending to dest: the first time, the socket set is looked up again at the next
 * wait (the transport connects on a first send). */
void rt_wait_sent_to(int dest);
/* Worker, after handing an item to the main thread: wakes it if it polls the sockets. */
void rt_wait_wake(void);
/* Main thread: waits on the sockets and the workers' eventfd, up to ns, or up to long_ns when
 * every message wakes the wait (rt_waitst.only, no send outstanding); false when this wait
 * does not apply (then the caller waits its own way, up to ns). */
bool rt_wait_sockets(uint64_t ns, uint64_t long_ns);
extern _Thread_local int rt_in_worker;

/* ---- transport (rt_comm.c) --------------------------------------------------------------- */

int rt_comm_init(void);
void rt_comm_destroy(void);
/* Main thread: sends one RSR to rank to (h->src is set here) and counts it. */
void rt_send_hdr(int to, rt_hdr *h, const void *payload);
/* Main thread: sends a control record (RT_CTL_*) to rank to at once; not counted. */
void rt_send_ctl(int to, uint16_t id, const void *payload, uint32_t len);
bool rt_comm_progress(void); /* receive, deliver, complete sends; true if an RSR came */
void rt_comm_flush_all(void);
/* rt_comm_flush_all with the clock read at now (rt_run: just read, not read again) */
void rt_comm_flush_all_at(double now);
bool rt_comm_flushed(void);
void rt_comm_wait_sends(void);
void rt_dispatch_item(rt_item *it); /* deliver an owned message now (inline or to a worker) */
/* Completion of a message's processing (main thread): counters, stats, reply token. */
void rt_complete(const rt_hdr *h, double elapsed);
bool rt_local_deliver(void); /* self-sends */
/* Main thread: unpacks and delivers the records of one MPI message of n bytes from src (the
 * buffer must stay valid until it returns); true if it carried an RSR. */
bool rt_comm_process(const unsigned char *buf, size_t n, int src);

/* ---- global state (rt.c) ------------------------------------------------------------------ */

typedef struct rt_sendbuf rt_sendbuf;

typedef struct rt_global {
    bool initialised, started, mpi_by_us, in_run, in_handler;
    int rank, size;
    MPI_Comm comm;     /* the runtime's own messages */
    MPI_Comm app_comm; /* handed to the layers above (rt_app_comm) */
    rt_config cfg;
    rt_htable ht;
    rt_tasks tasks;
    rt_term term;
    rt_perturb pert;
    bool perturbing;
    rt_stats st;
    uint64_t sent, recvd; /* RSR counts for termination (main thread) */
    double inline_time;   /* seconds in non-threaded handlers (not communication time) */
    int comm_depth;       /* rt_comm.c's comm_begin/comm_end nesting (rt_stats.comm_s) */
    double comm_t0;       /* when the outermost open communication stretch began */
    bool comm_lazy;       /* the open stretch's start is the next clock reading (rt_comm.c) */
    double comm_t1;       /* when the last counted stretch ended (a clock reading rt_run reuses) */
    rt_net net;           /* the network model (rt_net.c) */

    /* transport (rt_comm.c) */
    rt_sendbuf **agg; /* open aggregation buffer per destination */
    int *dirty;       /* destinations with an open buffer */
    int ndirty;
    rt_sendbuf *pool; /* free standard-size buffers */
    MPI_Request *reqs;
    rt_sendbuf **reqbuf;
    int *reqidx; /* scratch for MPI_Testsome */
    int nreq, capreq;
    unsigned char *rbuf; /* large messages */
    size_t rcap;
    unsigned char **pbuf; /* preposted receive buffers, RT_NPOST of pcap bytes */
    MPI_Request *preq;
    size_t pcap;
    int phead;   /* oldest preposted receive: completes (is matched) first */
    int nrepost; /* consumed receives before phead not yet reposted (rt_comm.c) */
    rt_queue selfq;

    /* worker pool (rt_worker.c) */
    pthread_mutex_t wlock;
    pthread_cond_t wcond; /* workers wait here for jobs */
    pthread_cond_t mcond; /* main thread waits here when idle */
    pthread_t *threads;
    int nthreads;
    bool wstop;
    rt_queue jobs, outq, doneq;
    size_t wk_outstanding; /* submitted jobs whose completion the main thread has not seen */
    _Atomic int njobs;     /* jobs queued, readable without the lock (spinning workers) */
    _Atomic int wstop_hint;
    _Atomic int wposted; /* items in outq + doneq: the main thread locks only if nonzero */
    rt_waitst wt;        /* idle wait on sockets (rt_wait.c) */
} rt_global;

extern rt_global rt_g;

#endif
