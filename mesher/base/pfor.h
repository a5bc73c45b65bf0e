/* pfor: a loop run on a few threads at once -- the rank's --threads after meshing, when the
 * runtime's workers are idle (merging the subdomain meshes, numbering, checking, hashing).
 *
 * Plain pthreads started for the one loop and joined before the call returns: the caller's
 * thread runs a share too, a thread that cannot start has its share run by the caller (never
 * an error), and nothing outlives the call.  Every share is disjoint, so results the caller
 * combines in share order (sums, minima with the lowest index on ties) are the same for any
 * thread count when the combination is exact.
 *
 * All functions are Local; fn must not call MPI (only the thread that initialised MPI does).
 */
#ifndef MESH_PFOR_H
#define MESH_PFOR_H

#include <stdint.h>

enum { MESH_PFOR_MAXTHR = 64 }; /* more threads are capped to this many */

/* fn(ctx, k, a, b) on parts k = 0 .. n-1 of [0, count): contiguous ranges [a, b) in order, at
 * most threads of them and none shorter than min_len (one part when count < 2 min_len; zero
 * parts when count <= 0).  Part 0 runs on the calling thread.  Returns n, the number of parts,
 * so the caller can size per-part results with MESH_PFOR_MAXTHR entries and combine 0 .. n-1. */
int mesh_pfor_ranges(int64_t count, int threads, int64_t min_len,
                     void (*fn)(void *ctx, int k, int64_t a, int64_t b), void *ctx);

/* fn(ctx, i) for every item i in [0, count), each exactly once, on up to threads threads at
 * once; the threads take the next item as they finish one (items of uneven size balance). */
void mesh_pfor_items(int64_t count, int threads, void (*fn)(void *ctx, int64_t i), void *ctx);

/* The CPUs a helper thread may take beyond its rank's (MESH_HOST_CPUS entries, 1 = may run
 * there): a launcher binds each rank to a core, and while the other ranks of the host wait
 * asleep their cores are free.  mesh_thread_spread moves the calling thread onto the CPUs set in
 * cpus (all 0, or NULL: it stays where it is); Linux only, a no-op elsewhere or on failure. */
enum { MESH_HOST_CPUS = 1024 };
void mesh_thread_spread(const uint8_t *cpus);
/* out (MESH_HOST_CPUS entries) = the CPUs of cpus outside the calling thread's own, or all of
 * cpus when none is (cpus NULL: none): where the caller's helpers go (mesh_thread_spread) to
 * run beside it, not on the core a launcher bound it to. */
void mesh_cpus_beside(const uint8_t *cpus, uint8_t *out);

#endif
