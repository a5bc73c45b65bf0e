/* pbw_check.c: PBW's always-on end check of the Delaunay property where the protocol decided
 * it (TR-97-17 section 2 commits cavities across ranks; pbw.c).  A cavity of the local fast
 * path is the sequential kernel's (pbw_local.c: only this rank's unlocked triangles, no ghost,
 * no tombstone, no edge to another rank), so what can go wrong is in the general path: a wrong
 * ghost decision, a stale link, a commit applied out of order, a split point off its line.  So
 * at the end every rank tests, with the exact incircle:
 *   - every unconstrained edge of every triangle a general commit created (pbw_apply_commit
 *     records its slots; a slot freed and reused since is tested all the same, which only
 *     costs time) whose neighbour is on this rank: the neighbour's apex must not lie strictly
 *     inside the triangle's circumcircle;
 *   - every unconstrained edge on a rank boundary: each side sends the other the edge and its
 *     own apex's coordinates (the same doubles on every rank), and the other side tests them
 *     against its triangle there (following tombstones' forward links, GHOSTS in pbw.c); an
 *     edge whose far side is not a live triangle with that edge is a defect too.
 * The rank's defects are counted; the caller fails every rank (par_fail_any) and writes
 * nothing.  Collective (one MPI_Alltoall and one MPI_Alltoallv on rt_app_comm()); its CPU
 * seconds outside them are reported (--stats: endcheck_max_s, endcheck_sum_s). */
#include "par/par.h"
#include "pbw/pbw_impl.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct bedge { /* a rank boundary edge a->b of the sender's triangle, for its owner */
    int64_t ga, gb;
    double pa[2], pb[2], apex[2]; /* their coordinates, and the sender's apex's */
    int32_t slot, pad;
} bedge;

static void note(pbw_ctx *C, char *msg, size_t len, int64_t *nbad, const char *what,
                 const double *a, const double *b, const double *apex) {
    if ((*nbad)++ == 0)
        snprintf(msg, len,
                 "rank %d: the mesh is not Delaunay: edge (%.17g, %.17g)-(%.17g, %.17g) %s "
                 "(%.17g, %.17g) (an internal error: please report it with the command)",
                 C->rank, a[0], a[1], b[0], b[1], what, apex[0], apex[1]);
}

void pbw_gen_note(pbw_ctx *C, int32_t slot) {
    MESH_GROW(C->gen, C->ngen, C->gencap);
    C->gen[C->ngen++] = slot;
}

int64_t pbw_check_delaunay(pbw_ctx *C, char *msg, size_t len, double *secs) {
    int64_t nbad = 0;
    msg[0] = 0;
    double t0 = par_cpu_seconds();
    const mesh *M = &C->M;
    /* the general commits' triangles, against their neighbours here */
    for (int64_t i = 0; i < C->ngen; i++) {
        int32_t t = C->gen[i];
        if (!alive(C, t)) continue;
        const int32_t *tv = M->tv + 3 * (size_t)t;
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, f = M->tn[e];
            if (f < 0 || mesh_edge_constrained(M, e)) continue;
            if (!alive(C, f / 3)) {
                note(C, msg, len, &nbad, "links a dead triangle, its apex", VX(C, tv[j]),
                     VX(C, tv[(j + 1) % 3]), VX(C, tv[(j + 2) % 3]));
                continue;
            }
            const double *d = VX(C, mesh_apex(M, f));
            if (geom_incircle(VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2]), d) > 0)
                note(C, msg, len, &nbad, "is not locally Delaunay: inside its circumcircle,",
                     VX(C, tv[j]), VX(C, tv[(j + 1) % 3]), d);
        }
    }
    /* the rank boundary: every edge with a remote neighbour goes to that neighbour's owner */
    int P = C->size;
    int *scount = mesh_xcalloc((size_t)P, sizeof(int)),
        *rcount = mesh_xcalloc((size_t)P, sizeof(int));
    int *sdisp = mesh_xcalloc((size_t)P + 1, sizeof(int)),
        *rdisp = mesh_xcalloc((size_t)P + 1, sizeof(int));
    /* the rank boundary edges are the records' (pbw_store.c), not a pass over every slot */
    for (int32_t i = 0; i < C->ncon; i++) {
        int32_t e = C->con[i].e;
        if (e < 0) continue;
        if (M->tn[e] != -2 - i) MESH_BUG("record %d names edge %d, which does not link it", i, e);
        if (alive(C, e / 3) && !mesh_edge_constrained(M, e)) scount[ref_rank(C->con[i].nb)]++;
    }
    for (int r = 0; r < P; r++)
        sdisp[r + 1] = sdisp[r] + scount[r];
    bedge *sb = mesh_xrealloc(NULL, (size_t)sdisp[P] + 1, sizeof *sb);
    int *fill = mesh_xcalloc((size_t)P, sizeof(int));
    for (int32_t i = 0; i < C->ncon; i++) {
        int32_t e = C->con[i].e;
        if (e < 0 || !alive(C, e / 3) || mesh_edge_constrained(M, e)) continue;
        const int32_t *tv = M->tv + 3 * (size_t)(e / 3);
        int j = e % 3;
        int64_t n = C->con[i].nb;
        int r = ref_rank(n);
        bedge *b = &sb[sdisp[r] + fill[r]++];
        memset(b, 0, sizeof *b);
        b->ga = C->vgid[tv[j]];
        b->gb = C->vgid[tv[(j + 1) % 3]];
        memcpy(b->pa, VX(C, tv[j]), sizeof b->pa);
        memcpy(b->pb, VX(C, tv[(j + 1) % 3]), sizeof b->pb);
        memcpy(b->apex, VX(C, tv[(j + 2) % 3]), sizeof b->apex);
        b->slot = ref_idx(n);
    }
    double t1 = par_cpu_seconds(); /* the collectives wait for the other ranks: not counted */
    MPI_Comm comm = rt_app_comm();
    MESH_MPI(MPI_Alltoall(scount, 1, MPI_INT, rcount, 1, MPI_INT, comm));
    for (int r = 0; r < P; r++)
        rdisp[r + 1] = rdisp[r] + rcount[r];
    bedge *rb = mesh_xrealloc(NULL, (size_t)rdisp[P] + 1, sizeof *rb);
    MPI_Datatype bt;
    MESH_MPI(MPI_Type_contiguous((int)sizeof(bedge), MPI_BYTE, &bt));
    MESH_MPI(MPI_Type_commit(&bt));
    MESH_MPI(MPI_Alltoallv(sb, scount, sdisp, bt, rb, rcount, rdisp, bt, comm));
    MESH_MPI(MPI_Type_free(&bt));
    double t2 = par_cpu_seconds();
    for (int i = 0; i < rdisp[P]; i++) {
        const bedge *b = &rb[i];
        int32_t x = b->slot;
        if (x >= 0 && x < M->nt && ROLE(C, x) == ROLE_TOMB)
            x = pbw_resolve_tomb(C, x, b->ga, b->gb);
        int j = alive(C, x) ? pbw_find_edge(C, x, b->gb, b->ga) : -1;
        if (j < 0) {
            note(C, msg, len, &nbad,
                 "on a rank boundary has no live triangle on this side; the other side's apex",
                 b->pa, b->pb, b->apex);
            continue;
        }
        const int32_t *tv = M->tv + 3 * (size_t)x;
        if (geom_incircle(VX(C, tv[0]), VX(C, tv[1]), VX(C, tv[2]), b->apex) > 0)
            note(C, msg, len, &nbad,
                 "on a rank boundary is not locally Delaunay: inside its circumcircle, the other "
                 "side's apex",
                 b->pa, b->pb, b->apex);
    }
    *secs = (t1 - t0) + (par_cpu_seconds() - t2);
    free(sb), free(rb), free(fill);
    free(scount), free(rcount), free(sdisp), free(rdisp);
    return nbad;
}

void pbw_test_break_delaunay(pbw_ctx *C) {
    const char *env = getenv("PBW_TEST_BREAK_DELAUNAY");
    if (!env || !*env || atoi(env) != C->rank) return;
    mesh *M = &C->M;
    for (int64_t i = 0; i < C->ngen; i++) {
        int32_t t = C->gen[i];
        if (!alive(C, t) || ROLE(C, t) != ROLE_NONE) continue;
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j, f = M->tn[e];
            if (f < 0 || mesh_edge_constrained(M, e) || !alive(C, f / 3) ||
                ROLE(C, f / 3) != ROLE_NONE)
                continue;
            int local = 1;
            for (int k = 0; k < 3; k++)
                if (M->tn[3 * t + k] < -1 || M->tn[3 * (f / 3) + k] < -1) local = 0;
            const double *u = VX(C, M->tv[e]), *v = VX(C, mesh_dest(M, e)),
                         *w = VX(C, mesh_apex(M, e)), *z = VX(C, mesh_apex(M, f));
            if (!local || geom_orient2d(w, u, z) <= 0 || geom_orient2d(z, v, w) <= 0 ||
                geom_incircle(u, v, w, z) == 0)
                continue;
            mesh_flip(M, e);
            return;
        }
    }
}
