/* base.c: the allocation funnel, the bug report and the MPI error check of mesher/ (base.h).
 *
 * The bug report names the rank (from MPI_COMM_WORLD when MPI is running, "-" otherwise) and
 * the caller's file and line, flushes stderr, and stops every rank with MPI_Abort (exit code
 * 70, EX_SOFTWARE) when MPI is initialised and not yet finalised; abort() otherwise, so a core
 * dump or a debugger stops at the caller.
 */
#include "base/base.h"

#include <mpi.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int mpi_running(void) {
    int init = 0, fin = 0;
    MPI_Initialized(&init);
    if (init) MPI_Finalized(&fin);
    return init && !fin;
}

void mesh_bug_at(const char *file, int line, const char *fmt, ...) {
    char rank[16] = "-";
    int running = mpi_running();
    if (running) {
        int r = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &r);
        snprintf(rank, sizeof rank, "%d", r);
    }
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "pcdm: bug on rank %s (%s:%d): %s\n", rank, file, line, msg);
    fflush(stderr);
    if (running) MPI_Abort(MPI_COMM_WORLD, 70);
    abort();
}

void mesh_mpi_fail_at(const char *file, int line, const char *call, int rc) {
    char s[MPI_MAX_ERROR_STRING] = "";
    int len = 0;
    if (MPI_Error_string(rc, s, &len) != MPI_SUCCESS) snprintf(s, sizeof s, "error %d", rc);
    mesh_bug_at(file, line, "%s failed: %s", call, s);
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

char *mesh_read_stream(FILE *f, size_t *n) {
    size_t cap = 1 << 16, len = 0;
    char *buf = mesh_xmalloc(cap, 1);
    for (;;) {
        len += fread(buf + len, 1, cap - len - 1, f);
        if (len < cap - 1) break;
        buf = mesh_xrealloc(buf, cap, 2);
        cap *= 2;
    }
    buf[len] = '\0';
    *n = len;
    return buf;
}
