/* base.c: the allocation funnel and the bug report of mesher/ (base.h); no MPI (the sequential
 * library is built from this file; the MPI half of the report is base_mpi.c).
 *
 * The bug report names the rank and the caller's file and line, flushes stderr, and stops every
 * rank (exit code 70, EX_SOFTWARE) when a parallel run is up -- the rank and the stop come from
 * the environment base_mpi.c installs in programs that link the parallel layers -- and calls
 * abort() otherwise (rank "-"), so a core dump or a debugger stops at the caller.
 */
#include "base/base.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
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
    fflush(stderr);
    if (r >= 0) bug_env->stop(70);
    abort();
}

void *mesh_xrealloc_at(const char *file, int line, void *p, size_t n, size_t size) {
    if (size && n > SIZE_MAX / size)
        mesh_bug_at(file, line, "out of memory (%zu elements of %zu bytes)", n, size);
    size_t bytes = n * size;
    void *q = realloc(p, bytes ? bytes : 1);
    if (!q) mesh_bug_at(file, line, "out of memory (%zu bytes)", bytes);
    return q;
}

void *mesh_xcalloc_at(const char *file, int line, size_t n, size_t size) {
    void *q = calloc(n ? n : 1, size ? size : 1);
    if (!q) mesh_bug_at(file, line, "out of memory (%zu elements of %zu bytes)", n, size);
    return q;
}

void mesh_xfree(void *p) {
    free(p);
}

void mesh_alloc_for_program(void) {
#ifdef __GLIBC__
    mallopt(M_MMAP_THRESHOLD, 128 * 1024); /* a fixed threshold: glibc's dynamic one is off */
#endif
}

void mesh_sort_u64(uint64_t *a, size_t n) {
    if (n < 2) return;
    if (n < 256) { /* insertion sort: no scratch */
        for (size_t i = 1; i < n; i++) {
            uint64_t x = a[i];
            size_t j = i;
            for (; j > 0 && a[j - 1] > x; j--)
                a[j] = a[j - 1];
            a[j] = x;
        }
        return;
    }
    uint64_t *tmp = mesh_xmalloc(n, sizeof *tmp), *src = a, *dst = tmp;
    size_t *cnt = mesh_xmalloc(65536, sizeof *cnt);
    for (int shift = 0; shift < 64; shift += 16) {
        memset(cnt, 0, 65536 * sizeof *cnt);
        for (size_t i = 0; i < n; i++)
            cnt[src[i] >> shift & 0xffff]++;
        if (cnt[src[0] >> shift & 0xffff] == n) continue; /* one digit: already in order */
        size_t sum = 0;
        for (size_t d = 0; d < 65536; d++) {
            size_t c = cnt[d];
            cnt[d] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++)
            dst[cnt[src[i] >> shift & 0xffff]++] = src[i];
        uint64_t *t = src;
        src = dst;
        dst = t;
    }
    if (src != a) memcpy(a, src, n * sizeof *a);
    free(cnt);
    free(tmp);
}
