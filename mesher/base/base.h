/* base: the plumbing every layer of mesher/ shares -- one allocation funnel, one bug report,
 * one MPI error check, and the debug-only assertion tier.
 *
 * Three tiers of errors (house style):
 *  - bugs (a broken invariant, an impossible state) go through MESH_BUG /
 *    MESH_CHECK: one line "pcdm: bug on rank R (FILE:LINE): message" on stderr naming the
 *    caller's file and line, then MPI_Abort when MPI is running (so no rank hangs), abort()
 *    otherwise;
 *  - recoverable failures (bad input, I/O) are return codes with a "FILE:LINE: problem"
 *    message (worded through mesh_fail / mesh_fail_at), decided by each layer;
 *  - algorithm outcomes are enums.
 * Out of memory is none of these: the funnel ends the program with a message that says what was
 * asked and what to change (mesh_oom_at), never a bug report.
 * The bug report needs no MPI; the parallel layers' half of it (the rank, MPI_Abort, the MPI
 * error check) is base_mpi.c, so the sequential library links without MPI.
 * MESH_ASSERT is the debug tier: checked in `make SANITIZE=1` and `make DEBUG=1` builds (which
 * define MESH_DEBUG), compiled out of the normal build; use it for checks too costly to run
 * always.  MESH_MPI checks an MPI call; every communicator the project uses has
 * MPI_ERRORS_RETURN set (rt_init does it), so a failing call reaches the check.
 *
 * All functions here are Local and thread-safe.
 */
#ifndef MESH_BASE_H
#define MESH_BASE_H

#include <setjmp.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(__GNUC__)
#define MESH_NORETURN __attribute__((noreturn))
#define MESH_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define MESH_NORETURN
#define MESH_PRINTF(a, b)
#endif

/* Reports a bug at file:line of the caller and stops the program (every rank, via the
 * environment below, while a parallel run is up).  Never returns. */
MESH_NORETURN MESH_PRINTF(3, 4) void mesh_bug_at(const char *file, int line, const char *fmt, ...);
#define MESH_BUG(...) mesh_bug_at(__FILE__, __LINE__, __VA_ARGS__)
#define MESH_CHECK(c)                                                                              \
    do {                                                                                           \
        if (!(c)) mesh_bug_at(__FILE__, __LINE__, "check failed: %s", #c);                         \
    } while (0)
#ifdef MESH_DEBUG
#define MESH_ASSERT(c) MESH_CHECK(c)
#else
#define MESH_ASSERT(c) ((void)0)
#endif

/* Where the bug report learns its rank and how it stops every rank.  rank: this process's
 * rank while a parallel run is up (MPI initialised, not finalised), else -1; stop: stops every
 * rank with exit code code (MPI_Abort) and does not return.  base_mpi.c installs MPI's before
 * main in every program that links it (the parallel layers do: they use MESH_MPI); without it
 * (the sequential library, ./mesh) a report says rank "-" and calls abort().  Set before any
 * thread starts; e NULL: none. */
typedef struct mesh_bug_env {
    int (*rank)(void);
    void (*stop)(int code);
} mesh_bug_env;
void mesh_bug_set_env(const mesh_bug_env *e);

/* What the bug report and the out-of-memory end run before the program stops (io/oset.c:
 * removing the output's temporary files); set once; fn NULL: nothing. */
void mesh_on_fatal(void (*fn)(void));

/* Out of memory: n elements of size bytes could not be allocated at file:line.  Not a bug: the
 * message says what was asked and what to change (larger -a, more ranks, the memory limit);
 * the program ends with exit code 1 (every rank, via the environment above).  Never returns. */
MESH_NORETURN void mesh_oom_at(const char *file, int line, size_t n, size_t size);

/* The one way every layer words a recoverable failure: formats the message into err (errlen
 * bytes; err NULL or errlen 0: nothing) and returns -1. */
MESH_PRINTF(3, 4) int mesh_fail(char *err, size_t errlen, const char *fmt, ...);
/* The same with "path:line: " in front (the readers' "FILE:LINE: problem"). */
MESH_PRINTF(5, 6)
int mesh_fail_at(char *err, size_t errlen, const char *path, long line, const char *fmt, ...);

/* Checks an MPI call's return code; a failure is reported as a bug with MPI's error string
 * (base_mpi.c: only code that links MPI uses it). */
void mesh_mpi_fail_at(const char *file, int line, const char *call, int rc);
#define MESH_MPI(call)                                                                             \
    do {                                                                                           \
        int mesh_mpi_rc_ = (call);                                                                 \
        if (mesh_mpi_rc_ != 0) mesh_mpi_fail_at(__FILE__, __LINE__, #call, mesh_mpi_rc_);          \
    } while (0)

/* The allocation funnel.  n elements of size bytes (overflow-checked); a zero-size request
 * still returns a unique pointer.  Out of memory ends the program (mesh_oom_at) naming the
 * caller's file and line.
 * Free with free() (or mesh_xfree). */
void *mesh_xrealloc_at(const char *file, int line, void *p, size_t n, size_t size);
void *mesh_xcalloc_at(const char *file, int line, size_t n, size_t size);
#define mesh_xrealloc(p, n, size) mesh_xrealloc_at(__FILE__, __LINE__, (p), (n), (size))
#define mesh_xmalloc(n, size) mesh_xrealloc_at(__FILE__, __LINE__, NULL, (n), (size))
#define mesh_xcalloc(n, size) mesh_xcalloc_at(__FILE__, __LINE__, (n), (size))
void mesh_xfree(void *p);

/* Every free() in a file that includes this header is mesh_xfree (so an out-of-memory guard,
 * below, knows each block that is given back); base.c alone calls the C library's. */
#ifndef MESH_BASE_REAL_FREE
#define free(p) mesh_xfree(p)
#endif

/* A recovery point for out of memory, for the sequential library (pcdm_triangulate on the
 * caller's thread, and so the Python package): while a guard is entered on a thread, the funnel
 * records every block it hands out on that thread and forgets each one given back; out of
 * memory then frees every block still recorded and returns to the guard's setjmp with 1 (the
 * message in g->msg) instead of ending the program.  Leaving the guard keeps the blocks (the
 * result) and forgets the record.  Guards nest (the innermost is used).  Only for code whose
 * blocks are all allocated and freed on the guarded thread: the threaded and parallel paths end
 * the program instead (mesh_oom_at).  Usage:
 *     mesh_guard g;
 *     if (MESH_GUARD_ENTER(&g)) return out_of_memory(g.msg);   (g already left)
 *     ... work ...
 *     mesh_guard_leave(&g);                                    */
typedef struct mesh_guard {
    jmp_buf jb;
    void **slot; /* open addressing, linear probing; NULL: empty */
    size_t cap, n;
    struct mesh_guard *prev;
    char msg[256];
} mesh_guard;
void mesh_guard_push(mesh_guard *g);
#define MESH_GUARD_ENTER(g) (mesh_guard_push(g), setjmp((g)->jb))
void mesh_guard_leave(mesh_guard *g);

/* Programs only (never the library: it is the host's process).  Blocks above 128 KiB always
 * come from mmap and go back to the system when freed.  glibc otherwise raises that threshold to
 * the largest block freed so far, and the parallel meshers' per-subdomain meshes, freed as they
 * are merged, then stay in the heap beside the merged part (North America at 14M triangles,
 * --threads 2: peak 1249 MB, 752 MB with the fixed threshold, same time).  No-op off glibc. */
void mesh_alloc_for_program(void);

/* Grows array p (of element type *p) so that index n is valid; cap doubles (16 at first). */
#define MESH_GROW(p, n, cap)                                                                       \
    do {                                                                                           \
        if ((size_t)(n) >= (size_t)(cap)) {                                                        \
            (cap) = (cap) ? 2 * (cap) : 16;                                                        \
            if ((size_t)(n) >= (size_t)(cap)) (cap) = (n) + 1;                                     \
            (p) = mesh_xrealloc((p), (size_t)(cap), sizeof *(p));                                  \
        }                                                                                          \
    } while (0)

/* A 64-bit mixing function (the finaliser of MurmurHash3) for hash tables keyed by ids or
 * coordinate bits.  Local, pure. */
static inline uint64_t mesh_hash64(uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return x;
}

/* The bits of a coordinate as a key: two points are one when their keys are equal (-0.0 is
 * +0.0).  Local, pure. */
static inline uint64_t mesh_dbits(double x) {
    if (x == 0) x = 0;
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* Sorts a[0..n) ascending (LSD radix sort, 11-bit digits; a digit every key shares costs no
 * pass); O(n) time, n words of scratch from the funnel.  Local. */
void mesh_sort_u64(uint64_t *a, size_t n);
/* The same by the bits from lo (0..63) up only, stably: keys equal there keep their order (one
 * pass for every 11 of those bits).  Local. */
void mesh_sort_u64_from(uint64_t *a, size_t n, int lo);

/* qsort comparators of int32_t and of double (no NaN). */
static inline int mesh_cmp_i32(const void *pa, const void *pb) {
    int32_t a = *(const int32_t *)pa, b = *(const int32_t *)pb;
    return (a > b) - (a < b);
}

static inline int mesh_cmp_dbl(const void *pa, const void *pb) {
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* Entries of the ascending a[0 .. n) below v (binary search; where v would go). */
static inline int32_t mesh_lower_i32(const int32_t *a, int32_t n, int32_t v) {
    int32_t lo = 0, hi = n;
    while (lo < hi) {
        int32_t mid = lo + (hi - lo) / 2;
        if (a[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The same for n ascending 64-bit keys. */
static inline int32_t mesh_lower_u64(const uint64_t *a, int32_t n, uint64_t v) {
    int32_t lo = 0, hi = n;
    while (lo < hi) {
        int32_t mid = lo + (hi - lo) / 2;
        if (a[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

#endif
