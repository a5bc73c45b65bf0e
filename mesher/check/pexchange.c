/* pexchange: the all-to-all of fixed-size records that the distributed checks (par_check.c)
 * and, above, the numbering and the derived outputs of the parallel meshers (mesher/par/) are
 * built on: every rank sends each record to the rank its caller names (usually a rendezvous
 * rank chosen by hashing exact coordinate bits), with one MPI_Alltoall of the byte counts and
 * one MPI_Alltoallv of the records over rt_app_comm().  Records arrive grouped by source rank in
 * rank order, each source's in the order it listed them, so what a rank receives depends on the
 * inputs alone.  Counts past INT_MAX / 2 bytes (MPI's int displacements) are reported as a bug.
 */
#include "check/pexchange.h"

#include "base/base.h"
#include "rt.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

void *par_exchange(const void *recs, size_t sz, const int *dest, int64_t n, int64_t *nout) {
    MPI_Comm c = rt_app_comm();
    int P = rt_size();
    int *scnt = mesh_xcalloc((size_t)P, sizeof(int)), *rcnt = mesh_xcalloc((size_t)P, sizeof(int));
    int *sdsp = mesh_xcalloc((size_t)P + 1, sizeof(int));
    int *rdsp = mesh_xcalloc((size_t)P + 1, sizeof(int));
    int64_t *fill = mesh_xcalloc((size_t)P, sizeof(int64_t));
    for (int64_t i = 0; i < n; i++)
        fill[dest[i]]++;
    for (int r = 0; r < P; r++) {
        if ((uint64_t)fill[r] * sz > INT_MAX / 2) MESH_BUG("exchange: %lld records", (long long)n);
        scnt[r] = (int)((size_t)fill[r] * sz);
    }
    MESH_MPI(MPI_Alltoall(scnt, 1, MPI_INT, rcnt, 1, MPI_INT, c));
    int64_t rtot = 0;
    for (int r = 0; r < P; r++) {
        sdsp[r + 1] = sdsp[r] + scnt[r];
        rtot += rcnt[r];
        if (rtot > INT_MAX / 2) MESH_BUG("exchange: %lld bytes to receive", (long long)rtot);
        rdsp[r + 1] = (int)rtot;
        fill[r] = sdsp[r];
    }
    char *sb = mesh_xmalloc((size_t)sdsp[P] + 1, 1), *rb = mesh_xmalloc((size_t)rtot + 1, 1);
    for (int64_t i = 0; i < n; i++) {
        memcpy(sb + fill[dest[i]], (const char *)recs + (size_t)i * sz, sz);
        fill[dest[i]] += (int64_t)sz;
    }
    MESH_MPI(MPI_Alltoallv(sb, scnt, sdsp, MPI_BYTE, rb, rcnt, rdsp, MPI_BYTE, c));
    free(sb);
    free(scnt);
    free(rcnt);
    free(sdsp);
    free(rdsp);
    free(fill);
    *nout = rtot / (int64_t)sz;
    return rb;
}
