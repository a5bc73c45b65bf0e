/* rt.c - life cycle, the RSR and task verbs, and the scheduler loop of the runtime.
 *
 * rt_run is the main loop of the Parallel (Constrained) Meshing Algorithm, TR-97-17 section
 * 2: REPEAT { service incoming RSRs (rt_comm_progress, perturbation release, self-sends,
 * finished threaded handlers); complete suspended tasks whose replies have arrived (the FIFO
 * ready queue); run one bounded step of the application's local work; flush aggregated RSRs }
 * UNTIL the distributed termination detector (rt_term.c) declares that every rank is passive
 * and no RSR is in flight.  A rank with nothing to do backs off exponentially (about 2 us to
 * 1 ms) in a timed condition wait that a finishing worker cuts short, so idle ranks give
 * their core to busy ones (between hosts a wait on the sockets, rt_wait.c, that a message
 * also cuts short).  Invariants: only the thread that called rt_init calls MPI; every
 * RSR is counted once as sent (when the main thread hands it to the transport) and once as
 * received (when its handler has returned); a rank is quiescent only when no ready task,
 * local work, buffered or held RSR, or threaded handler remains, and passive when it is
 * quiescent with no blocked task; quiescent ranks pass the termination token; rt_run
 * returns on no rank before every rank has seen the termination decision (a closing
 * barrier), so the RSRs of the next phase are never handled inside this one.  When the
 * detector finds every rank quiescent, nothing in flight and tasks still blocked, no reply
 * can come any more: every rank prints its blocking queue (rt_blocked_dump) and, after a
 * barrier (so that every rank's report is out), fails through RT_FATAL.
 */
#include "rt_internal.h"

#include <math.h>
#include <sched.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#if defined(__x86_64__) && defined(__GNUC__)
#include <cpuid.h>
#include <x86intrin.h>
#endif

rt_global rt_g;

static atomic_long rt_live_allocs;

/* ---- allocation and errors ---------------------------------------------------------------- */

/* Out of memory is not a bug: the message says what was asked and what to change, and every
 * rank ends with exit code 1. */
static void oom_at(const char *file, int line, size_t n) {
    fprintf(stderr,
            "pcdm: out of memory on rank %d: %zu bytes more could not be had (%s:%d); ask for "
            "fewer triangles (a larger -a or -S), run on more ranks or hosts, or raise the memory "
            "limit (ulimit -v)\n",
            rt_g.initialised ? rt_g.rank : -1, n, file, line);
    fflush(stderr);
    int inited = 0, fin = 0;
    MPI_Initialized(&inited);
    MPI_Finalized(&fin);
    if (inited && !fin && !rt_in_worker) MPI_Abort(MPI_COMM_WORLD, 1);
    _exit(1);
}

void *rt_xmalloc(size_t n) {
    void *p = malloc(n ? n : 1);
    if (!p) oom_at(__FILE__, __LINE__, n);
    atomic_fetch_add(&rt_live_allocs, 1);
    return p;
}

void *rt_xrealloc(void *p, size_t n) {
    void *q = realloc(p, n ? n : 1);
    if (!q) oom_at(__FILE__, __LINE__, n);
    if (!p) atomic_fetch_add(&rt_live_allocs, 1);
    return q;
}

void rt_xfree(void *p) {
    if (!p) return;
    atomic_fetch_sub(&rt_live_allocs, 1);
    free(p);
}

void rt_fatal_at(const char *file, int line, const char *fmt, ...) {
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "rt: fatal on rank %d (%s:%d): %s\n", rt_g.initialised ? rt_g.rank : -1, file,
            line, msg);
    fflush(stderr);
    int inited = 0, fin = 0;
    MPI_Initialized(&inited);
    MPI_Finalized(&fin);
    if (inited && !fin && !rt_in_worker) MPI_Abort(MPI_COMM_WORLD, 70);
    abort();
}

const char *rt_strerror(int err) {
    switch (err) {
    case RT_OK:
        return "success";
    case RT_EINVAL:
        return "invalid argument";
    case RT_ENOMEM:
        return "out of memory";
    case RT_EMPI:
        return "MPI error or insufficient MPI thread support";
    case RT_ETHREAD:
        return "thread creation or synchronisation failed";
    case RT_EMISMATCH:
        return "handler tables differ between ranks";
    case RT_ESTATE:
        return "call not allowed in the runtime's current state";
    case RT_ENOSPC:
        return "buffer or table full";
    case RT_EHANDLER:
        return "unknown or unregistered handler";
    case RT_ELEN:
        return "payload length does not match the handler";
    case RT_EPROTO:
        return "malformed message";
    default:
        return "unknown error";
    }
}

double rt_wtime(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The main thread's interval clock (laps, inline handler times): on x86-64 with an invariant
 * TSC, rdtsc scaled by a rate measured against CLOCK_MONOTONIC at rt_init (a few ns instead
 * of a clock_gettime on the path of every message); elsewhere rt_wtime. */
#if defined(__x86_64__) && defined(__GNUC__)
static double tsc_scale; /* seconds per tick; 0: use rt_wtime */
static uint64_t tsc_base;
static double tsc_base_s;

static void clock_calibrate(void) {
    unsigned a, b, c, d;
    tsc_scale = 0;
    if (!__get_cpuid(0x80000000u, &a, &b, &c, &d) || a < 0x80000007u) return;
    __get_cpuid(0x80000007u, &a, &b, &c, &d);
    if (!(d & (1u << 8))) return; /* not invariant: may change rate or stop */
    double s0 = rt_wtime();
    uint64_t c0 = __rdtsc();
    struct timespec ts = {0, 2000000};
    nanosleep(&ts, NULL);
    double s1 = rt_wtime();
    uint64_t c1 = __rdtsc();
    if (c1 <= c0 || s1 - s0 < 1e-3) return;
    tsc_scale = (s1 - s0) / (double)(c1 - c0);
    tsc_base = c1;
    tsc_base_s = s1;
}

double rt_now(void) {
    if (tsc_scale == 0) return rt_wtime();
    return tsc_base_s + tsc_scale * (double)(int64_t)(__rdtsc() - tsc_base);
}
#else
static void clock_calibrate(void) {}
double rt_now(void) {
    return rt_wtime();
}
#endif

/* ---- configuration and life cycle ----------------------------------------------------- */

void rt_config_default(rt_config *cfg) {
    memset(cfg, 0, sizeof *cfg);
    cfg->aggregate = 1;
    cfg->agg_bytes = 16384;
    cfg->nworkers = 2;
    cfg->perturb_seed = 0;
    cfg->idle_spin = 0;
    cfg->idle_min_ns = 2000;
    cfg->idle_max_ns = 1000000;
}

static void env_u64(const char *name, uint64_t *v) {
    const char *s = getenv(name);
    if (s && *s) *v = strtoull(s, NULL, 0);
}

static void apply_env(rt_config *c) {
    uint64_t v;
    v = (uint64_t)c->aggregate;
    env_u64("RT_AGGREGATE", &v);
    c->aggregate = v != 0;
    v = c->agg_bytes;
    env_u64("RT_AGG_BYTES", &v);
    c->agg_bytes = (uint32_t)v;
    v = (uint64_t)c->nworkers;
    env_u64("RT_WORKERS", &v);
    c->nworkers = (int)v;
    env_u64("RT_PERTURB", &c->perturb_seed);
    v = (uint64_t)c->idle_spin;
    env_u64("RT_IDLE_SPIN", &v);
    c->idle_spin = v != 0;
    v = c->worker_spin_us;
    env_u64("RT_WORKER_SPIN_US", &v);
    c->worker_spin_us = (uint32_t)v;
    const char *net = getenv("PCDM_NET");
    if (net && *net && rt_net_parse(net, &c->net_latency_s, &c->net_bytes_per_s) != RT_OK)
        fprintf(stderr, "rt_init: ignoring PCDM_NET='%s' (want off, sp2 or LAT_US[,MBPS])\n", net);
}

/* Open MPI 4.1 chooses its point-to-point layer at MPI_Init by opening every candidate: the cm
 * layer and its MTLs (PSM, PSM2, OFI) load libraries that probe for network hardware, then ob1
 * (shared memory between the ranks of one node) wins on one node anyway.  The probing was
 * measured at 0.29 s of MPI_Init against 0.06 s with ob1 asked for directly (an empty program,
 * 2 ranks): a quarter of a second on every run of ./pcdm or ./pbw.  So when every rank runs on
 * one node (mpirun's OMPI_COMM_WORLD_LOCAL_SIZE equals OMPI_COMM_WORLD_SIZE, or a singleton
 * without mpirun) and the user has not chosen (OMPI_MCA_pml unset; mpirun --mca pml X sets it),
 * ob1 is asked for; across nodes Open MPI's own choice stands.  Before MPI_Init only, and never
 * when the caller initialised MPI. */
/* Every rank on one node: mpirun's OMPI_COMM_WORLD_LOCAL_SIZE equals OMPI_COMM_WORLD_SIZE, or
 * a singleton without mpirun (neither set). */
static int one_node(void) {
    const char *n = getenv("OMPI_COMM_WORLD_SIZE"), *l = getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    return (n && l && strcmp(n, l) == 0) || (!n && !l);
}

int rt_prefer_local_pml(void) {
    if (getenv("OMPI_MCA_pml") || !one_node()) return 0;
    return setenv("OMPI_MCA_pml", "ob1", 0) == 0;
}

/* At MPI_Init every process of Open MPI 4.1 that is not handed its node's topology discovers it
 * with hwloc, and hwloc's Linux I/O discovery reads the configuration space of every PCI device
 * through sysfs, which on a virtual machine traps to the hypervisor at every read: a third of
 * an empty program's MPI_Init at 8 ranks on 2 cores, where the processes queue for the cores
 * (measured: MPI_Init 0.13 s, 0.065 s without it; a singleton's start 0.021 s, 0.011 s).  The
 * topology's I/O devices only place network cards near processes, which shared memory on one
 * node never asks, so when every rank runs on one node (as rt_prefer_local_pml decides) and the
 * user has not chosen (HWLOC_COMPONENTS unset), hwloc is asked to leave them out
 * (HWLOC_COMPONENTS=-linuxio,-pci: processors, caches and memory are still discovered).  Before
 * MPI_Init only. */
int rt_prefer_cpu_topology(void) {
    if (getenv("HWLOC_COMPONENTS") || !one_node()) return 0;
    return setenv("HWLOC_COMPONENTS", "-linuxio,-pci", 0) == 0;
}

/* Open MPI 4.1 starts a singleton (a program run without mpirun) by forking a daemon (orted)
 * and waiting for it, at MPI_Init and again at MPI_Finalize -- measured 0.10-0.17 s and 0.05 s
 * on every run of ./pcdm as a plain program, against 0.03 s and 0.004 s without the daemon.
 * The daemon serves MPI_Comm_spawn and connecting to other jobs, which the runtime never uses,
 * so a singleton is asked to run isolated (OMPI_MCA_ess_singleton_isolated=1) unless the user
 * chose (the variable set).  Under a launcher (OMPI_COMM_WORLD_SIZE set, or a PMIx/PMI rank)
 * the setting is not made (Open MPI would ignore it there).  Before MPI_Init only. */
int rt_prefer_isolated_singleton(void) {
    if (getenv("OMPI_MCA_ess_singleton_isolated") || getenv("OMPI_COMM_WORLD_SIZE") ||
        getenv("PMIX_RANK") || getenv("PMI_RANK"))
        return 0;
    return setenv("OMPI_MCA_ess_singleton_isolated", "1", 0) == 0;
}

/* The common start of rt_init and rt_init_comm: MPI is initialised (by us or the caller). */
/* A network model's figures (rt_config.net_*): finite and not negative. */
static bool net_valid(double latency_s, double bytes_per_s) {
    return latency_s >= 0 && bytes_per_s >= 0 && isfinite(latency_s) && isfinite(bytes_per_s);
}

static int init_on(MPI_Comm world, const rt_config *cfg, int *argc, char ***argv, int may_init);

int rt_init(int *argc, char ***argv, const rt_config *cfg) {
    return init_on(MPI_COMM_WORLD, cfg, argc, argv, 1);
}

int rt_init_comm(MPI_Comm comm, const rt_config *cfg) {
    return init_on(comm, cfg, NULL, NULL, 0);
}

static int init_on(MPI_Comm world, const rt_config *cfg, int *argc, char ***argv, int may_init) {
    if (rt_g.initialised) return RT_ESTATE;
    memset(&rt_g, 0, sizeof rt_g);
    if (cfg)
        rt_g.cfg = *cfg;
    else
        rt_config_default(&rt_g.cfg);
    apply_env(&rt_g.cfg);
    rt_config *c = &rt_g.cfg;
    if (c->agg_bytes < 256) c->agg_bytes = 256;
    c->agg_bytes = (c->agg_bytes + 7u) & ~7u;
    if (c->nworkers < 0 || c->nworkers > 256) return RT_EINVAL;
    if (c->idle_min_ns == 0) c->idle_min_ns = 1000;
    if (c->idle_max_ns < c->idle_min_ns) c->idle_max_ns = c->idle_min_ns;

    int inited = 0, provided = 0;
    int fin = 0;
    MPI_Initialized(&inited);
    MPI_Finalized(&fin);
    if (fin || (!inited && !may_init)) return RT_ESTATE;
    if (!inited) {
        rt_prefer_local_pml();
        rt_prefer_cpu_topology();
        rt_prefer_isolated_singleton();
        if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
            fprintf(stderr, "rt_init: MPI_Init_thread failed\n");
            return RT_EMPI;
        }
        rt_g.mpi_by_us = true;
    } else {
        RT_MPI(MPI_Query_thread(&provided));
    }
    int is_main = 0;
    RT_MPI(MPI_Is_thread_main(&is_main));
    if (provided < MPI_THREAD_FUNNELED || !is_main) {
        if (may_init) /* rt_init_comm (a library) never prints */
            fprintf(stderr,
                    "rt_init: MPI provides thread level %d (need MPI_THREAD_FUNNELED = %d) and "
                    "rt_init must run on MPI's main thread (%s)\n",
                    provided, MPI_THREAD_FUNNELED, is_main ? "it does" : "it does not");
        return RT_EMPI;
    }
    /* Every communicator returns errors, so the checks on each MPI call can fire (a caller's
     * communicator is left as it is: the runtime's dups get the handler) */
    if ((may_init && MPI_Comm_set_errhandler(world, MPI_ERRORS_RETURN) != MPI_SUCCESS) ||
        MPI_Comm_dup(world, &rt_g.comm) != MPI_SUCCESS ||
        MPI_Comm_dup(world, &rt_g.app_comm) != MPI_SUCCESS ||
        MPI_Comm_set_errhandler(rt_g.comm, MPI_ERRORS_RETURN) != MPI_SUCCESS ||
        MPI_Comm_set_errhandler(rt_g.app_comm, MPI_ERRORS_RETURN) != MPI_SUCCESS ||
        MPI_Comm_rank(rt_g.comm, &rt_g.rank) != MPI_SUCCESS ||
        MPI_Comm_size(rt_g.comm, &rt_g.size) != MPI_SUCCESS)
        return RT_EMPI;
    clock_calibrate();
    rt_htable_init(&rt_g.ht);
    rt_tasks_init(&rt_g.tasks);
    rt_term_init(&rt_g.term, rt_g.rank);
    rt_g.perturbing = c->perturb_seed != 0;
    if (rt_g.perturbing)
        rt_perturb_init(&rt_g.pert, c->perturb_seed * 1000003u + (uint64_t)rt_g.rank, rt_g.size);
    if (!net_valid(c->net_latency_s, c->net_bytes_per_s)) return RT_EINVAL;
    rt_net_init(&rt_g.net, rt_g.size, c->net_latency_s, c->net_bytes_per_s);
    int rc = rt_comm_init();
    if (rc == RT_OK) rc = rt_workers_start(c->nworkers);
    if (rc != RT_OK) return rc;
    rt_g.initialised = true;
    return RT_OK;
}

void rt_finalize(void) {
    if (!rt_g.initialised) return;
    RT_CHECK(!rt_g.in_run);
    rt_comm_flush_all();
    rt_comm_wait_sends();
    rt_workers_stop();
    rt_comm_destroy();
    rt_net_destroy(&rt_g.net);
    if (rt_g.perturbing) rt_perturb_destroy(&rt_g.pert);
    rt_tasks_destroy(&rt_g.tasks);
    RT_MPI(MPI_Comm_free(&rt_g.comm));
    RT_MPI(MPI_Comm_free(&rt_g.app_comm));
    rt_g.initialised = false;
    long live = atomic_load(&rt_live_allocs);
    if (live != 0)
        fprintf(stderr, "rt_finalize: rank %d: %ld runtime allocations not freed\n", rt_g.rank,
                live);
    if (rt_g.mpi_by_us) RT_MPI(MPI_Finalize());
}

static void need_init(const char *fn) {
    if (!rt_g.initialised) RT_FATAL("%s called before rt_init", fn);
}

int rt_rank(void) {
    return rt_g.rank;
}

int rt_size(void) {
    return rt_g.size;
}

MPI_Comm rt_comm(void) {
    return rt_g.comm;
}

MPI_Comm rt_app_comm(void) {
    return rt_g.app_comm;
}

/* ---- handlers ----------------------------------------------------------------------------- */

int rt_handler_register(const char *name, rt_handler_fn fn, void *arg, unsigned flags,
                        uint32_t size) {
    need_init("rt_handler_register");
    return rt_htable_add(&rt_g.ht, name, fn, arg, flags, size);
}

void rt_start(void) {
    need_init("rt_start");
    if (rt_g.started) return;
    rt_g.ht.frozen = true;
    rt_g.started = true;
    rt_hsig mine[RT_MAX_HANDLERS];
    rt_htable_sig(&rt_g.ht, mine);
    size_t one = sizeof mine;
    rt_hsig *all = rt_xmalloc(one * (size_t)rt_g.size);
    RT_MPI(MPI_Allgather(mine, (int)one, MPI_BYTE, all, (int)one, MPI_BYTE, rt_g.comm));
    int slot = -1, who = -1;
    for (int r = 1; r < rt_g.size; r++) {
        int s = rt_hsig_compare(all, all + (size_t)r * RT_MAX_HANDLERS);
        if (s >= 0 && (slot < 0 || s < slot)) {
            slot = s;
            who = r;
        }
    }
    if (slot >= 0) {
        const rt_hsig *a = &all[slot], *b = &all[(size_t)who * RT_MAX_HANDLERS + slot];
        fprintf(stderr,
                "rt_start: rank %d: handler table mismatch at slot %d: rank 0 registered '%s' "
                "(flags %u, size %u) but rank %d registered '%s' (flags %u, size %u)\n",
                rt_g.rank, slot, a->name[0] ? a->name : "(nothing)", (unsigned)a->flags,
                (unsigned)a->size, who, b->name[0] ? b->name : "(nothing)", (unsigned)b->flags,
                (unsigned)b->size);
        fflush(stderr);
        (void)MPI_Barrier(rt_g.comm); /* let every rank print first; aborting anyway */
        MPI_Abort(MPI_COMM_WORLD, 71);
    }
    rt_xfree(all);
}

/* ---- RSRs and tasks -------------------------------------------------------------------- */

static void send_common(int dest, int handler, const void *payload, uint32_t len, uint16_t flags,
                        rt_token tok) {
    need_init("rt_rsr");
    if (dest < 0 || dest >= rt_g.size)
        RT_FATAL("RSR to invalid rank %d (handler %d)", dest, handler);
    int rc = rt_htable_check(&rt_g.ht, (uint32_t)handler, len);
    if (rc == RT_EHANDLER) RT_FATAL("RSR to rank %d names unregistered handler %d", dest, handler);
    if (rc == RT_ELEN)
        RT_FATAL("RSR to rank %d for handler %d '%s': payload length %u, declared %s%u", dest,
                 handler, rt_g.ht.e[handler].name, (unsigned)len,
                 (rt_g.ht.e[handler].flags & RT_VARSIZE) ? "at most " : "",
                 (unsigned)rt_g.ht.e[handler].size);
    if (len && !payload) RT_FATAL("RSR with NULL payload of length %u", (unsigned)len);
    rt_hdr h = {.handler = (uint16_t)handler,
                .flags = flags,
                .src = rt_g.rank,
                .len = len,
                .tok_rank = tok.rank,
                .tok_slot = tok.slot,
                .tok_gen = tok.gen};
    if (rt_in_worker) {
        rt_item *it = rt_item_new(&h, payload);
        it->dest = dest;
        pthread_mutex_lock(&rt_g.wlock);
        rt_queue_push(&rt_g.outq, &it->q);
        atomic_fetch_add(&rt_g.wposted, 1);
        pthread_cond_signal(&rt_g.mcond);
        pthread_mutex_unlock(&rt_g.wlock);
        rt_wait_wake();
        return;
    }
    rt_send_hdr(dest, &h, payload);
}

static const rt_token no_token = {-1, 0, 0};

void rt_rsr(int dest, int handler, const void *payload, uint32_t len) {
    send_common(dest, handler, payload, len, 0, no_token);
}

rt_task *rt_task_spawn(rt_task_fn fn, void *state) {
    need_init("rt_task_spawn");
    if (rt_in_worker) RT_FATAL("rt_task_spawn called from a threaded handler");
    return rt_tasks_spawn(&rt_g.tasks, fn, state);
}

void rt_request(rt_task *t, int dest, int handler, const void *payload, uint32_t len) {
    if (rt_in_worker) RT_FATAL("rt_request called from a threaded handler");
    if (!t || t->st != RT_TS_RUNNING) RT_FATAL("rt_request outside the running task");
    rt_token tok = rt_task_take_token(t, rt_g.rank, dest, handler);
    send_common(dest, handler, payload, len, RT_HF_TOKEN, tok);
}

void rt_reply(const rt_msg *req, int handler, const void *payload, uint32_t len) {
    if (req->token.rank >= 0)
        send_common(req->token.rank, handler, payload, len, RT_HF_REPLY, req->token);
    else
        send_common(req->src, handler, payload, len, 0, no_token);
}

void rt_forward(const rt_msg *req, int dest, int handler, const void *payload, uint32_t len) {
    if (req->token.rank >= 0)
        send_common(dest, handler, payload, len, RT_HF_TOKEN, req->token);
    else
        send_common(dest, handler, payload, len, 0, no_token);
}

int rt_task_pending(const rt_task *t) {
    return (int)t->pending;
}

void *rt_task_data(const rt_task *t) {
    return t->state;
}

void rt_blocked_dump(FILE *f) {
    if (rt_in_worker) RT_FATAL("rt_blocked_dump called from a threaded handler");
    rt_tasks_dump(&rt_g.tasks, rt_g.rank, &rt_g.ht, rt_now(), f);
}

int rt_perturb_set(uint64_t seed) {
    need_init("rt_perturb_set");
    if (rt_g.in_run || rt_in_worker) return RT_ESTATE;
    if (rt_g.perturbing) {
        RT_CHECK(rt_g.pert.nheld == 0);
        rt_perturb_destroy(&rt_g.pert);
    }
    rt_g.cfg.perturb_seed = seed;
    rt_g.perturbing = seed != 0;
    if (rt_g.perturbing)
        rt_perturb_init(&rt_g.pert, seed * 1000003u + (uint64_t)rt_g.rank, rt_g.size);
    return RT_OK;
}

int rt_workers_ensure(int n) {
    if (!rt_g.initialised) return RT_ESTATE;
    if (rt_g.in_run || rt_in_worker || rt_g.in_handler) return RT_ESTATE;
    if (n < 0 || n > 256) return RT_EINVAL;
    int rc = rt_workers_grow(n);
    if (rc == RT_OK && n > rt_g.cfg.nworkers) rt_g.cfg.nworkers = n;
    return rc;
}

int rt_net_set(double latency_s, double bytes_per_s) {
    need_init("rt_net_set");
    if (rt_g.in_run || rt_in_worker) return RT_ESTATE;
    if (!net_valid(latency_s, bytes_per_s)) return RT_EINVAL;
    RT_CHECK(rt_g.net.nheld == 0);
    rt_net_destroy(&rt_g.net);
    rt_g.cfg.net_latency_s = latency_s;
    rt_g.cfg.net_bytes_per_s = bytes_per_s;
    rt_net_init(&rt_g.net, rt_g.size, latency_s, bytes_per_s);
    return RT_OK;
}

void rt_net_get(double *latency_s, double *bytes_per_s) {
    need_init("rt_net_get");
    *latency_s = rt_g.net.latency_s;
    *bytes_per_s = rt_g.net.bytes_per_s;
}

/* ---- scheduler ------------------------------------------------------------------------- */

#define RT_WAVE_DELAY 20e-6 /* seconds of quiet before rank 0 starts a termination round */
/* the same between hosts, where one round trip takes tens of microseconds (rt_wait.c): a
 * round started while a reply is on its way would only add messages to that wait */
#define RT_WAVE_DELAY_HOSTS 500e-6

/* Nothing to do until a message arrives (blocked tasks allowed; rt_term.c). */
static bool quiescent(bool local_busy) {
    return !local_busy && rt_queue_empty(&rt_g.tasks.ready) && rt_g.wk_outstanding == 0 &&
           rt_g.ndirty == 0 && rt_queue_empty(&rt_g.selfq) && rt_g.net.nheld == 0 &&
           (!rt_g.perturbing || rt_g.pert.nheld == 0);
}

/* The termination detector found tasks blocked for good (rank 0), or rank 0 said so
 * (DEADLOCK).  Every rank gets here: its report goes out before the barrier, so no abort
 * cuts another rank's report short. */
_Noreturn static void deadlock_report(bool quiet) {
    fprintf(stderr,
            "rt: rank %d: deadlock: %zu task(s) blocked on this rank, %lld on all ranks, no "
            "message in flight%s\n",
            rt_g.rank, rt_g.tasks.nblocked, (long long)rt_g.term.deadlock_blocked,
            quiet ? "" : " (but this rank was not quiescent: a runtime bug)");
    rt_blocked_dump(stderr);
    fflush(stderr);
    (void)MPI_Barrier(rt_g.comm);
    RT_FATAL("deadlock: %lld task(s) wait for replies that can never come (every rank idle, no "
             "message in flight); blocked tasks are listed above",
             (long long)rt_g.term.deadlock_blocked);
}

int rt_run(rt_work_fn work, void *ctx) {
    need_init("rt_run");
    if (rt_in_worker || rt_g.in_run || rt_g.in_handler)
        RT_FATAL("rt_run called from a handler, a task or a worker");
    rt_start();
    rt_g.in_run = true;
    uint64_t backoff = rt_g.cfg.idle_min_ns;
    double idle_since = -1; /* when this rank last became quiescent, -1 while active */
    unsigned spins = 0;
    double wave_delay = rt_g.wt.on ? RT_WAVE_DELAY_HOSTS : RT_WAVE_DELAY;
    /* Time accounting by laps: each stretch between two clock readings goes to one bucket;
     * non-threaded handler time is taken out of the communication laps. */
    double lap = rt_now(), inl = rt_g.inline_time, now;
#define RT_LAP(bucket) (now = rt_now(), rt_g.st.time[bucket] += now - lap, lap = now)
#define RT_COMM_LAP()                                                                              \
    (RT_LAP(RT_TIME_COMM), rt_g.st.time[RT_TIME_COMM] -= rt_g.inline_time - inl,                   \
     inl = rt_g.inline_time)
    /* the same, at a clock reading just taken by the transport (one rdtsc less per message) */
#define RT_COMM_LAP_AT(t)                                                                          \
    (now = (t), rt_g.st.time[RT_TIME_COMM] += now - lap - (rt_g.inline_time - inl), lap = now,     \
     inl = rt_g.inline_time)
    for (;;) {
        bool did = rt_comm_progress();
        bool fresh = did; /* rt_g.comm_t1 was read at the end of that poll */
        if (rt_g.perturbing && rt_perturb_release(&rt_g.pert, rt_dispatch_item) > 0)
            did = true, fresh = false;
        if (rt_g.selfq.head && rt_local_deliver()) did = true, fresh = false;
        if (rt_g.nthreads > 0 && atomic_load_explicit(&rt_g.wposted, memory_order_acquire) != 0 &&
            rt_workers_drain())
            did = true, fresh = false;
        bool local_busy = false, lapped = false; /* lapped: lap is a reading of just now */
        if (!rt_queue_empty(&rt_g.tasks.ready) || work) {
            /* Clock reads are kept off the empty-poll path: a lap is closed only around
             * real work, and the time of an empty poll goes with the idle lap. */
            if (fresh)
                RT_COMM_LAP_AT(rt_g.comm_t1);
            else if (did)
                RT_COMM_LAP();
            bool ran = rt_g.tasks.ready.head && rt_tasks_run(&rt_g.tasks, rt_g.tasks.ready.n) > 0;
            if (work) local_busy = work(ctx) != RT_WORK_IDLE;
            if (ran || local_busy) {
                RT_LAP(RT_TIME_BUSY);
                did = lapped = true;
            }
        }
        if (rt_g.ndirty) {
            if (lapped)
                rt_comm_flush_all_at(lap); /* the clock was read right after the work */
            else
                rt_comm_flush_all();
        }
        if (did) {
            rt_g.term.active = true;
            backoff = rt_g.cfg.idle_min_ns;
            idle_since = -1;
            continue;
        }
        bool qui = quiescent(local_busy);
        if (rt_g.term.done) { /* rank 0 declared termination (TERM) */
            if (!qui || rt_g.tasks.nblocked != 0)
                RT_FATAL("termination announced while this rank was active (local work returned "
                         "BUSY without a message, or a runtime bug)");
            rt_g.term.done = false;
            rt_g.term.active = true;
            break;
        }
        if (rt_g.term.deadlock) deadlock_report(qui); /* rank 0 sent DEADLOCK */
        /* Rank 0 starts a round only after RT_WAVE_DELAY of quiet, so that ranks exchanging
         * messages quickly do not pass the token around between every two of them; others
         * pass a token on as soon as they are quiescent. */
        if (qui && rt_g.term.have_token) {
            if (idle_since < 0) idle_since = lap;
            rt_term_verdict v =
                rt_term_pass(&rt_g.term, rt_g.rank, rt_g.size, rt_g.sent, rt_g.recvd,
                             rt_g.tasks.nblocked, lap - idle_since >= wave_delay);
            if (v == RT_TERM_DONE) break;
            if (v == RT_TERM_DEADLOCK) deadlock_report(true);
        } else if (qui && idle_since < 0) {
            idle_since = lap;
        }
        if (rt_g.cfg.idle_spin) {
            /* busy-poll, but let this rank's workers run while they have jobs; read the
             * clock (idle time, wave delay) only every few empty polls */
            if (rt_g.wk_outstanding > 0) sched_yield();
            if (++spins % 32 != 0) continue;
        } else if (rt_g.perturbing && rt_g.pert.nheld > 0) {
            RT_COMM_LAP();
            sched_yield(); /* held messages are released by iterations, not by time */
        } else {
            RT_COMM_LAP();
            /* ns: the growing backoff; long_ns: the wait when every message wakes the rank
             * (rt_wait.c: a lazy timer), bounded by the end of rank 0's wave delay; none
             * while the network model holds a message (its deliveries are timed) */
            uint64_t ns = backoff, long_ns = rt_g.cfg.idle_max_ns;
            if (rt_g.net.nheld) { /* not past the network model's next delivery */
                double w = rt_net_wait(&rt_g.net, lap) * 1e9;
                if (w < (double)ns) ns = (uint64_t)w;
                long_ns = 0;
            }
            if (qui && rt_g.term.have_token) {
                double w = (wave_delay - (lap - idle_since)) * 1e9;
                if (w < (double)long_ns) long_ns = w > 0 ? (uint64_t)w : 0;
            }
            if (ns > 0) rt_workers_idle_wait(ns, long_ns);
            backoff = backoff * 2 > rt_g.cfg.idle_max_ns ? rt_g.cfg.idle_max_ns : backoff * 2;
        }
        RT_LAP(RT_TIME_IDLE);
    }
    RT_COMM_LAP();
    /* Leave together: until every rank has seen the decision nobody may start the next
     * phase, or its RSRs would be handled inside this one.  Nothing is in flight here. */
    MPI_Request bar;
    int left = 0;
    RT_MPI(MPI_Ibarrier(rt_g.comm, &bar));
    backoff = rt_g.cfg.idle_min_ns;
    for (;;) {
        RT_MPI(MPI_Test(&bar, &left, MPI_STATUS_IGNORE));
        if (left) break;
        if (rt_g.cfg.idle_spin) {
            sched_yield();
        } else {
            rt_workers_idle_wait(backoff, 0);
            backoff = backoff * 2 > rt_g.cfg.idle_max_ns ? rt_g.cfg.idle_max_ns : backoff * 2;
        }
    }
    RT_LAP(RT_TIME_IDLE);
#undef RT_LAP
#undef RT_COMM_LAP
    rt_g.st.waves = rt_g.term.waves;
    rt_comm_wait_sends();
    rt_g.in_run = false;
    return RT_OK;
}
