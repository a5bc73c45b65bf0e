/* rt_worker.c - the pool of worker threads that run threaded handlers.
 *
 * DMCS (TR-97-17 section 4) runs an RSR either inside the poll loop or on a thread of its
 * own.  We create the threads once, at rt_init, and hand each threaded RSR to an idle worker
 * through a job FIFO.  Workers never call MPI (MPI_THREAD_FUNNELED): an RSR sent by a threaded
 * handler is copied into the outgoing FIFO, and a finished job goes to the completion FIFO;
 * the main thread drains both (rt_workers_drain) and does the MPI sends and the counting.
 * Invariant used by termination: a worker pushes the RSRs of a handler before that handler's
 * completion, and the main thread drains the outgoing FIFO before the completion FIFO, so
 * wk_outstanding == 0 after a drain means every threaded handler finished and all its RSRs
 * have been handed to the transport.  One lock (rt_g.wlock) guards jobs, outq and doneq;
 * workers sleep on wcond, the idle main thread on mcond (timed, as it must also poll MPI), or,
 * between hosts, in ppoll on the transport's sockets and an eventfd the workers write
 * (rt_wait.c).
 */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include "rt_internal.h"

#include <sched.h>
#include <stdatomic.h>
#include <time.h>
#include <unistd.h>

_Thread_local int rt_in_worker;

static void *worker_main(void *arg) {
    (void)arg;
    rt_in_worker = 1;
    double spin = 1e-6 * rt_g.cfg.worker_spin_us;
    pthread_mutex_lock(&rt_g.wlock);
    for (;;) {
        while (!rt_g.wstop && rt_queue_empty(&rt_g.jobs))
            pthread_cond_wait(&rt_g.wcond, &rt_g.wlock);
        if (rt_queue_empty(&rt_g.jobs)) break; /* stopping and nothing left */
        rt_item *it = RT_CONTAINER(rt_queue_pop(&rt_g.jobs), rt_item, q);
        atomic_fetch_sub(&rt_g.njobs, 1);
        pthread_mutex_unlock(&rt_g.wlock);

        const rt_hentry *e = &rt_g.ht.e[it->h.handler];
        rt_msg m = {.src = it->h.src,
                    .handler = it->h.handler,
                    .data = it->data,
                    .len = it->h.len,
                    .token = {it->h.tok_rank, it->h.tok_slot, it->h.tok_gen},
                    .task = NULL};
        if (!(it->h.flags & (RT_HF_TOKEN | RT_HF_REPLY))) m.token.rank = -1;
        double t0 = rt_wtime();
        e->fn(&m, e->arg);
        it->elapsed = rt_wtime() - t0;

        pthread_mutex_lock(&rt_g.wlock);
        rt_queue_push(&rt_g.doneq, &it->q);
        atomic_fetch_add(&rt_g.wposted, 1);
        pthread_cond_signal(&rt_g.mcond);
        rt_wait_wake();
        if (spin > 0 && rt_queue_empty(&rt_g.jobs)) {
            /* Latency mode: poll a while for the next job instead of sleeping at once. */
            pthread_mutex_unlock(&rt_g.wlock);
            double until = rt_wtime() + spin;
            while (atomic_load(&rt_g.njobs) == 0 && !atomic_load(&rt_g.wstop_hint) &&
                   rt_wtime() < until)
                sched_yield();
            pthread_mutex_lock(&rt_g.wlock);
        }
    }
    pthread_mutex_unlock(&rt_g.wlock);
    return NULL;
}

int rt_cpus(void) {
#ifdef __linux__
    cpu_set_t s;
    CPU_ZERO(&s);
    if (sched_getaffinity(0, sizeof s, &s) == 0 && CPU_COUNT(&s) > 0) return CPU_COUNT(&s);
#endif
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

int rt_workers_start(int n) {
    pthread_condattr_t ca;
    if (pthread_mutex_init(&rt_g.wlock, NULL) || pthread_condattr_init(&ca) ||
        pthread_condattr_setclock(&ca, CLOCK_MONOTONIC) || pthread_cond_init(&rt_g.wcond, NULL) ||
        pthread_cond_init(&rt_g.mcond, &ca))
        return RT_ETHREAD;
    pthread_condattr_destroy(&ca);
    rt_queue_init(&rt_g.jobs);
    rt_queue_init(&rt_g.outq);
    rt_queue_init(&rt_g.doneq);
    rt_g.wstop = false;
    atomic_store(&rt_g.wstop_hint, 0);
    atomic_store(&rt_g.njobs, 0);
    atomic_store(&rt_g.wposted, 0);
    rt_g.wk_outstanding = 0;
    rt_g.threads = rt_xmalloc(sizeof *rt_g.threads * (size_t)(n > 0 ? n : 1));
    rt_g.nthreads = 0;
    for (int i = 0; i < n; i++) {
        if (pthread_create(&rt_g.threads[i], NULL, worker_main, NULL) != 0) return RT_ETHREAD;
        rt_g.nthreads++;
    }
    rt_wait_init();
    return RT_OK;
}

int rt_workers_grow(int n) {
    if (n <= rt_g.nthreads) return RT_OK;
    rt_g.threads = rt_xrealloc(rt_g.threads, sizeof *rt_g.threads * (size_t)n);
    while (rt_g.nthreads < n) {
        if (pthread_create(&rt_g.threads[rt_g.nthreads], NULL, worker_main, NULL) != 0)
            return RT_ETHREAD;
        rt_g.nthreads++;
    }
    return RT_OK;
}

void rt_workers_stop(void) {
    rt_wait_fini();
    pthread_mutex_lock(&rt_g.wlock);
    rt_g.wstop = true;
    atomic_store(&rt_g.wstop_hint, 1);
    pthread_cond_broadcast(&rt_g.wcond);
    pthread_mutex_unlock(&rt_g.wlock);
    for (int i = 0; i < rt_g.nthreads; i++)
        pthread_join(rt_g.threads[i], NULL);
    rt_xfree(rt_g.threads);
    rt_g.threads = NULL;
    rt_g.nthreads = 0;
    rt_queue *qs[3] = {&rt_g.jobs, &rt_g.outq, &rt_g.doneq};
    for (int i = 0; i < 3; i++) {
        rt_qnode *n;
        while ((n = rt_queue_pop(qs[i])))
            rt_xfree(RT_CONTAINER(n, rt_item, q));
    }
    pthread_cond_destroy(&rt_g.wcond);
    pthread_cond_destroy(&rt_g.mcond);
    pthread_mutex_destroy(&rt_g.wlock);
}

void rt_workers_submit(rt_item *it) {
    if (rt_g.nthreads == 0)
        RT_FATAL("threaded handler '%s' called but the runtime has no worker threads",
                 rt_g.ht.e[it->h.handler].name);
    rt_g.wk_outstanding++;
    pthread_mutex_lock(&rt_g.wlock);
    rt_queue_push(&rt_g.jobs, &it->q);
    atomic_fetch_add(&rt_g.njobs, 1);
    pthread_cond_signal(&rt_g.wcond);
    pthread_mutex_unlock(&rt_g.wlock);
}

bool rt_workers_drain(void) {
    if (rt_g.nthreads == 0 || atomic_load(&rt_g.wposted) == 0) return false;
    rt_queue out, done;
    rt_queue_init(&out);
    rt_queue_init(&done);
    pthread_mutex_lock(&rt_g.wlock);
    rt_queue_append(&out, &rt_g.outq);
    rt_queue_append(&done, &rt_g.doneq);
    atomic_store(&rt_g.wposted, 0);
    pthread_mutex_unlock(&rt_g.wlock);
    bool any = out.n || done.n;
    rt_qnode *n;
    while ((n = rt_queue_pop(&out))) {
        rt_item *it = RT_CONTAINER(n, rt_item, q);
        rt_send_hdr(it->dest, &it->h, it->data);
        rt_xfree(it);
    }
    while ((n = rt_queue_pop(&done))) {
        rt_item *it = RT_CONTAINER(n, rt_item, q);
        RT_CHECK(rt_g.wk_outstanding > 0);
        rt_g.wk_outstanding--;
        rt_complete(&it->h, it->elapsed);
        rt_xfree(it);
    }
    return any;
}

void rt_workers_idle_wait(uint64_t ns, uint64_t long_ns) {
    if (rt_wait_sockets(ns, long_ns)) return;
    if (rt_g.nthreads == 0) {
        struct timespec ts = {(time_t)(ns / 1000000000u), (long)(ns % 1000000000u)};
        nanosleep(&ts, NULL);
        return;
    }
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    ts.tv_nsec += (long)ns;
    while (ts.tv_nsec >= 1000000000L) {
        ts.tv_nsec -= 1000000000L;
        ts.tv_sec++;
    }
    pthread_mutex_lock(&rt_g.wlock);
    if (rt_queue_empty(&rt_g.outq) && rt_queue_empty(&rt_g.doneq)) {
        int rc = pthread_cond_timedwait(&rt_g.mcond, &rt_g.wlock, &ts);
        (void)rc; /* ETIMEDOUT or a wake-up: either way poll again */
    }
    pthread_mutex_unlock(&rt_g.wlock);
}
