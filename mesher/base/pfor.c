/* pfor.c: loops on a few threads at once (pfor.h).
 *
 * Ranges: part k of [0, count) is [count k / n, count (k + 1) / n); threads 1 .. n-1 are
 * started, the caller runs part 0, then joins them in order (a part whose thread did not start
 * runs on the caller then).  Items: a shared counter under a mutex hands out the next item; the
 * caller takes items too, so the loop finishes even when no thread starts.  The mutex also
 * orders each item's writes before the join that ends the call.
 */
#define _GNU_SOURCE /* pthread_setaffinity_np, CPU_SET */
#include "base/pfor.h"

#include <pthread.h>
#include <sched.h>
#include <string.h>

typedef struct range_job {
    void (*fn)(void *ctx, int k, int64_t a, int64_t b);
    void *ctx;
    int k;
    int64_t a, b;
} range_job;

static void *range_run(void *arg) {
    range_job *j = arg;
    j->fn(j->ctx, j->k, j->a, j->b);
    return NULL;
}

int mesh_pfor_ranges(int64_t count, int threads, int64_t min_len,
                     void (*fn)(void *ctx, int k, int64_t a, int64_t b), void *ctx) {
    if (count <= 0) return 0;
    if (min_len < 1) min_len = 1;
    int64_t n = threads < 1 ? 1 : threads > MESH_PFOR_MAXTHR ? MESH_PFOR_MAXTHR : threads;
    if (n > count / min_len) n = count / min_len > 0 ? count / min_len : 1;
    range_job job[MESH_PFOR_MAXTHR];
    pthread_t th[MESH_PFOR_MAXTHR];
    int started[MESH_PFOR_MAXTHR] = {0};
    for (int k = 0; k < n; k++)
        job[k] = (range_job){fn, ctx, k, count * k / n, count * (k + 1) / n};
    for (int k = 1; k < n; k++)
        started[k] = pthread_create(&th[k], NULL, range_run, &job[k]) == 0;
    range_run(&job[0]);
    for (int k = 1; k < n; k++) {
        if (started[k])
            pthread_join(th[k], NULL);
        else
            range_run(&job[k]);
    }
    return (int)n;
}

typedef struct item_job {
    void (*fn)(void *ctx, int64_t i);
    void *ctx;
    pthread_mutex_t mu;
    int64_t next, count;
} item_job;

static void *item_run(void *arg) {
    item_job *j = arg;
    for (;;) {
        pthread_mutex_lock(&j->mu);
        int64_t i = j->next < j->count ? j->next++ : -1;
        pthread_mutex_unlock(&j->mu);
        if (i < 0) break;
        j->fn(j->ctx, i);
    }
    return NULL;
}

void mesh_pfor_items(int64_t count, int threads, void (*fn)(void *ctx, int64_t i), void *ctx) {
    if (count <= 0) return;
    int n = threads < 1 ? 1 : threads > MESH_PFOR_MAXTHR ? MESH_PFOR_MAXTHR : threads;
    if (n > count) n = (int)count;
    item_job j = {.fn = fn, .ctx = ctx, .next = 0, .count = count};
    pthread_mutex_init(&j.mu, NULL);
    pthread_t th[MESH_PFOR_MAXTHR];
    int started[MESH_PFOR_MAXTHR] = {0};
    for (int k = 1; k < n; k++)
        started[k] = pthread_create(&th[k], NULL, item_run, &j) == 0;
    item_run(&j);
    for (int k = 1; k < n; k++)
        if (started[k]) pthread_join(th[k], NULL);
    pthread_mutex_destroy(&j.mu);
}

void mesh_thread_spread(const uint8_t *cpus) {
#ifdef __linux__
    if (!cpus) return;
    cpu_set_t set;
    CPU_ZERO(&set);
    int n = 0;
    for (int c = 0; c < MESH_HOST_CPUS && c < CPU_SETSIZE; c++)
        if (cpus[c]) {
            CPU_SET(c, &set);
            n++;
        }
    if (n > 0) (void)pthread_setaffinity_np(pthread_self(), sizeof set, &set);
#else
    (void)cpus;
#endif
}

void mesh_cpus_beside(const uint8_t *cpus, uint8_t *out) {
    memset(out, 0, MESH_HOST_CPUS);
    if (!cpus) return;
    int n = 0;
#ifdef __linux__
    cpu_set_t own;
    CPU_ZERO(&own);
    if (pthread_getaffinity_np(pthread_self(), sizeof own, &own) != 0) CPU_ZERO(&own);
    for (int c = 0; c < MESH_HOST_CPUS && c < CPU_SETSIZE; c++)
        if (cpus[c] && !CPU_ISSET(c, &own)) out[c] = 1, n++;
#endif
    if (n == 0) memcpy(out, cpus, MESH_HOST_CPUS);
}
