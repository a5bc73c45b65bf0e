/* pbw_ghosts.c: which side of each pair of neighbouring ranks keeps the ghosts (GHOSTS in
 * pbw.c).
 *
 * Of the two triangles on a rank boundary edge, only the one on the ghost side decides the other
 * on its ghost; the other side locks across.  The exactness argument needs only that, for each
 * pair of ranks, exactly one side is the ghost side and both sides agree; which one is free.
 * The choice moves work: a cavity on the ghost side whose neighbours across are unconflicted
 * stays local and keeps its new triangles, while the same cavity on the other side goes remote
 * and, by the ownership rule, gives the new triangle on each locked halo's edge to the halo's
 * owner.  So the rank boundary drifts towards the side without ghosts, and that side starts the
 * cross-rank cavities.  With the lower rank always the ghost side, the highest rank lost the
 * most (lake, 10M triangles, 8 ranks: rank 7 ended with 1.17M triangles, ranks 2 and 4 with
 * 1.29M, and rank 7 started 5,000 cross-rank cavities against rank 0's 2,700).
 *
 * Here every rank computes the same orientation of the rank adjacency graph, weighted by the
 * initial mesh's edges between the two ranks' triangles: pairs in decreasing weight (ties by
 * rank), each giving the ghost side to the rank whose running balance (weights where it is the
 * ghost side minus weights where it is not) is smaller, the lower rank on a tie.  A pair with no
 * initial edge between them (ranks that meet later, at a moving triple point) keeps the lower
 * rank as the ghost side.  Integer weights and a total order: the same answer on every rank.
 */
#include "pbw/pbw_impl.h"

#include <stdlib.h>
#include <string.h>

typedef struct rank_pair {
    int32_t a, b; /* a < b */
    int64_t w;    /* initial mesh edges between a's and b's triangles */
} rank_pair;

static int pair_by_ranks(const void *x, const void *y) {
    const rank_pair *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

static int pair_by_weight(const void *x, const void *y) {
    const rank_pair *p = x, *q = y;
    if (p->w != q->w) return p->w > q->w ? -1 : 1;
    return pair_by_ranks(x, y);
}

void pbw_ghost_sides(pbw_ctx *C, const mesh *m0, const int32_t *own) {
    int P = C->size;
    C->gside = mesh_xcalloc((size_t)P + 1, 1);
    for (int r = C->rank + 1; r < P; r++) /* the default: the lower rank */
        C->gside[r] = 1;
    if (P < 3) return; /* two ranks: either way one side drifts to the other, and back */
    rank_pair *pr = NULL;
    int32_t n = 0, cap = 0;
    for (int32_t t = 0; t < m0->nt; t++) {
        if (!mesh_tri_alive(m0, t)) continue;
        for (int j = 0; j < 3; j++) {
            int32_t f = m0->tn[3 * (size_t)t + (size_t)j];
            if (f < 0 || own[f / 3] <= own[t]) continue; /* each edge once, from the lower */
            MESH_GROW(pr, n, cap);
            pr[n++] = (rank_pair){own[t], own[f / 3], 1};
        }
    }
    if (n == 0) {
        free(pr);
        return;
    }
    qsort(pr, (size_t)n, sizeof *pr, pair_by_ranks);
    int32_t k = 0;
    for (int32_t i = 0; i < n; i++) {
        if (k > 0 && pr[k - 1].a == pr[i].a && pr[k - 1].b == pr[i].b)
            pr[k - 1].w++;
        else
            pr[k++] = pr[i];
    }
    qsort(pr, (size_t)k, sizeof *pr, pair_by_weight);
    int64_t *bal = mesh_xcalloc((size_t)P + 1, sizeof *bal);
    for (int32_t i = 0; i < k; i++) {
        int32_t a = pr[i].a, b = pr[i].b, g = bal[b] < bal[a] ? b : a;
        bal[g] += pr[i].w;
        bal[g == a ? b : a] -= pr[i].w;
        if (a == C->rank) C->gside[b] = g == a;
        if (b == C->rank) C->gside[a] = g == b;
    }
    free(bal);
    free(pr);
}
