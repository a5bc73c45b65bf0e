/* base.c: the allocation funnel and the bug report of mesher/ (base.h); no MPI (the sequential
 * library is built from this file; the MPI half of the report is base_mpi.c).
 *
 * The bug report names the rank and the caller's file and line, flushes stderr, and stops every
 * rank (exit code 70, EX_SOFTWARE) when a parallel run is up -- the rank and the stop come from
 * the environment base_mpi.c installs in programs that link the parallel layers -- and calls
 * abort() otherwise (rank "-"), so a core dump or a debugger stops at the caller.  Out of memory is
 * not a bug: it says how much was asked and what to change, and ends the program (exit code 1,
 * every rank); both ends first run the fatal hook (the output's temporary files removed).
 */
#define MESH_BASE_REAL_FREE
#include "base/base.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

/* The parallel half of the report, when a program links it (base_mpi.c installs it before
 * main); NULL: a sequential program or library.  The one process-wide setting of mesher/: the
 * bug report has no caller's context to take it from. */
static const mesh_bug_env *bug_env;

void mesh_bug_set_env(const mesh_bug_env *e) {
    bug_env = e;
}

/* What a fatal end runs first (oset.c: removing the output's temporary files); NULL: nothing.
 * Process-wide for the same reason as bug_env. */
static void (*fatal_hook)(void);

void mesh_on_fatal(void (*fn)(void)) {
    fatal_hook = fn;
}

static void fatal_end(int r, int code) {
    if (fatal_hook) fatal_hook();
    fflush(stderr);
    if (r >= 0) bug_env->stop(code);
}

void mesh_bug_at(const char *file, int line, const char *fmt, ...) {
    char rank[16] = "-";
    int r = bug_env ? bug_env->rank() : -1;
    if (r >= 0) snprintf(rank, sizeof rank, "%d", r);
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "pcdm: bug on rank %s (%s:%d): %s\n", rank, file, line, msg);
    fatal_end(r, 70);
    abort();
}

void mesh_oom_at(const char *file, int line, size_t n, size_t size) {
    int r = bug_env ? bug_env->rank() : -1;
    char where[32] = "";
    if (r >= 0) snprintf(where, sizeof where, " on rank %d", r);
    char asked[96];
    if (size && n > SIZE_MAX / size)
        snprintf(asked, sizeof asked, "%zu elements of %zu bytes (more than the address space)", n,
                 size);
    else
        snprintf(asked, sizeof asked, "%zu bytes more", n * size);
    fprintf(stderr,
            "pcdm: out of memory%s: %s could not be had (%s:%d); ask for fewer triangles (a "
            "larger -a or -S, a smaller -q), run on more ranks or hosts, or raise the memory "
            "limit (ulimit -v)\n",
            where, asked, file, line);
    fatal_end(r, 1);
    _exit(1);
}

/* ---- the out-of-memory guard: this thread's innermost one, and its record of blocks ---- */

static _Thread_local mesh_guard *guard;

static size_t slot_of(const mesh_guard *g, uintptr_t p) {
    uint64_t h = (uint64_t)p * 0x9e3779b97f4a7c15ull;
    return (size_t)(h >> 20) & (g->cap - 1);
}

/* 0, or -1 when the record itself cannot grow */
static int record(mesh_guard *g, void *p) {
    if (2 * (g->n + 1) > g->cap) {
        size_t cap = g->cap ? 2 * g->cap : 1024, oldcap = g->cap;
        void **old = g->slot, **s = calloc(cap, sizeof *s);
        if (!s) return -1;
        g->slot = s;
        g->cap = cap;
        for (size_t i = 0; i < oldcap; i++)
            if (old[i]) {
                size_t k = slot_of(g, (uintptr_t)old[i]);
                while (s[k])
                    k = (k + 1) & (cap - 1);
                s[k] = old[i];
            }
        free(old);
    }
    size_t k = slot_of(g, (uintptr_t)p);
    while (g->slot[k])
        k = (k + 1) & (g->cap - 1);
    g->slot[k] = p;
    g->n++;
    return 0;
}

/* p: the block's address as a number (it may be freed already: never read through) */
static void forget(mesh_guard *g, uintptr_t p) {
    if (!g->cap) return;
    size_t k = slot_of(g, p), m = g->cap - 1;
    while (g->slot[k] && (uintptr_t)g->slot[k] != p)
        k = (k + 1) & m;
    if (!g->slot[k]) return; /* not the funnel's (a C library block) */
    g->slot[k] = NULL;
    g->n--;
    /* linear probing's deletion: move back what the hole would make unreachable */
    for (size_t j = (k + 1) & m; g->slot[j]; j = (j + 1) & m) {
        size_t h = slot_of(g, (uintptr_t)g->slot[j]);
        if (((j - h) & m) >= ((j - k) & m)) {
            g->slot[k] = g->slot[j];
            g->slot[j] = NULL;
            k = j;
        }
    }
}

void mesh_guard_push(mesh_guard *g) {
    g->slot = NULL;
    g->cap = g->n = 0;
    g->msg[0] = '\0';
    g->prev = guard;
    guard = g;
}

void mesh_guard_leave(mesh_guard *g) {
    guard = g->prev;
    free(g->slot);
    g->slot = NULL;
    g->cap = g->n = 0;
}

/* Out of memory under a guard: every recorded block freed, back to the guard's setjmp. */
MESH_NORETURN static void unwind(const char *file, int line, size_t n, size_t size) {
    mesh_guard *g = guard;
    for (size_t i = 0; i < g->cap; i++)
        free(g->slot[i]);
    if (size && n > SIZE_MAX / size)
        snprintf(g->msg, sizeof g->msg,
                 "out of memory: %zu elements of %zu bytes asked (%s:%d); ask for fewer "
                 "triangles (a larger max_area or a smaller min_angle)",
                 n, size, file, line);
    else
        snprintf(g->msg, sizeof g->msg,
                 "out of memory: %zu bytes more could not be had (%s:%d); ask for fewer "
                 "triangles (a larger max_area or a smaller min_angle) or free memory",
                 n * size, file, line);
    mesh_guard_leave(g);
    longjmp(g->jb, 1);
}

int mesh_fail(char *err, size_t errlen, const char *fmt, ...) {
    if (!err || !errlen) return -1;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
    return -1;
}

int mesh_fail_at(char *err, size_t errlen, const char *path, long line, const char *fmt, ...) {
    if (!err || !errlen) return -1;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    snprintf(err, errlen, "%s:%ld: %s", path, line, msg);
    return -1;
}

void *mesh_xrealloc_at(const char *file, int line, void *p, size_t n, size_t size) {
    mesh_guard *g = guard;
    if (size && n > SIZE_MAX / size) {
        if (g) unwind(file, line, n, size);
        mesh_oom_at(file, line, n, size);
    }
    size_t bytes = n * size;
    uintptr_t was = (uintptr_t)p;
    void *q = realloc(p, bytes ? bytes : 1);
    if (g && q) {
        if (was) forget(g, was);
        if (record(g, q) != 0) {
            free(q);
            q = NULL;
        }
    }
    if (!q) {
        if (g) unwind(file, line, n, size);
        mesh_oom_at(file, line, n, size);
    }
    return q;
}

void *mesh_xcalloc_at(const char *file, int line, size_t n, size_t size) {
    mesh_guard *g = guard;
    void *q = calloc(n ? n : 1, size ? size : 1);
    if (g && q && record(g, q) != 0) {
        free(q);
        q = NULL;
    }
    if (!q) {
        if (g) unwind(file, line, n, size);
        mesh_oom_at(file, line, n, size);
    }
    return q;
}

void mesh_xfree(void *p) {
    if (guard && p) forget(guard, (uintptr_t)p);
    free(p);
}

void mesh_alloc_for_program(void) {
#ifdef __GLIBC__
    mallopt(M_MMAP_THRESHOLD, 128 * 1024); /* a fixed threshold: glibc's dynamic one is off */
#endif
}

void mesh_sort_u64(uint64_t *a, size_t n) {
    mesh_sort_u64_from(a, n, 0);
}

void mesh_sort_u64_from(uint64_t *a, size_t n, int lo) {
    if (n < 2) return;
    if (n < 256) { /* insertion sort: no scratch */
        for (size_t i = 1; i < n; i++) {
            uint64_t x = a[i];
            size_t j = i;
            for (; j > 0 && a[j - 1] >> lo > x >> lo; j--)
                a[j] = a[j - 1];
            a[j] = x;
        }
        return;
    }
    /* 11-bit digits: the counts stay in the first-level cache and the scatter's 2048 streams
     * in the TLB (measured on 0.9M and 1.75M keys: 16-bit digits took 1.4-1.6 times as long) */
    enum { DIGIT = 11, NDIG = 1 << DIGIT };
    uint64_t *tmp = mesh_xmalloc(n, sizeof *tmp), *src = a, *dst = tmp;
    size_t *cnt = mesh_xmalloc(NDIG, sizeof *cnt);
    for (int shift = lo; shift < 64; shift += DIGIT) {
        memset(cnt, 0, NDIG * sizeof *cnt);
        for (size_t i = 0; i < n; i++)
            cnt[src[i] >> shift & (NDIG - 1)]++;
        if (cnt[src[0] >> shift & (NDIG - 1)] == n) continue; /* one digit: already in order */
        size_t sum = 0;
        for (size_t d = 0; d < NDIG; d++) {
            size_t c = cnt[d];
            cnt[d] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++)
            dst[cnt[src[i] >> shift & (NDIG - 1)]++] = src[i];
        uint64_t *t = src;
        src = dst;
        dst = t;
    }
    if (src != a) memcpy(a, src, n * sizeof *a);
    mesh_xfree(cnt); /* the funnel's blocks: a guard must forget them */
    mesh_xfree(tmp);
}
