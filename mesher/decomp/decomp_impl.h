/* decomp_impl: what the decomposition's files share (private to mesher/decomp).
 *
 * Both routes (coarse mesh + METIS, and a cuts file) end with a triangulation of the domain
 * whose live triangles carry a subdomain label; decomp_build turns it into a pcdm_decomp and
 * decomp_map_owners assigns the subdomains to ranks.  All functions are Local.
 */
#ifndef DECOMP_IMPL_H
#define DECOMP_IMPL_H

#include "decomp/decomp.h"
#include "seq/mesh.h"

#include <metis.h>

/* The threads a decomposition may use (n < 2: the caller's alone) and the CPUs their helpers
 * move onto (MESH_HOST_CPUS entries, pfor.h; NULL: the caller's). */
typedef struct decomp_threads {
    int n;
    const uint8_t *cpus;
} decomp_threads;

/* The graph METIS partitions: nn vertices in rows xadj/adj (no duplicates, none to itself),
 * edge lengths len, vertex weights w; node[i] is the graph vertex of compact triangle i;
 * connected: every vertex reached from vertex 0 (contiguous parts are asked for only then);
 * ntri: the number of compact triangles. */
typedef struct pgraph {
    int32_t nn, ntri, *node;
    idx_t *xadj, *adj;
    double *len, *w;
    int connected;
} pgraph;

/* decomp_graph.c.  The graph of m's live triangles (id[t]: compact index, -1 for dead slots; n
 * of them; tw their work) that decomp_partition splits, with edge lengths penalized where an
 * apex encroaches (penalize) and clusters (coarsen: the fast route); made once for every seed
 * tried.  Free with decomp_graph_free. */
void decomp_graph_build(const decomp_threads *th, const mesh *m, const int32_t *id, int32_t n,
                        const double *tw, int penalize, int coarsen, pgraph *g);
void decomp_graph_free(pgraph *g);
/* METIS on g into K parts of the target fractions; labels of m's triangle slots into part (-1
 * for dead ones).  sel (NULL: METIS seed `seed`): the seeds to try, keeping the partition of
 * least decomp_part_cost in part and its cost in *cost (INFINITY, labels -1, if METIS failed on
 * every seed).  Returns 0, or -1 with a message in err. */
int decomp_partition(const mesh *m, const int32_t *id, int32_t n, const pgraph *g, const double *tw,
                     const double *target, int32_t K, const pcdm_decomp_opts *sel, int32_t seed,
                     double *cost, int32_t *part, char *err, size_t errlen);
/* Is edge e (a live triangle's) encroached by the apex on either side (diametral circle)? */
int decomp_edge_encroached(const mesh *m, int32_t e);

/* decomp_widen.c.  decomp_widen: the wide-sector passes over part (exact: the exact preview's
 * rule for encroached interfaces first); decomp_fill_empty: every empty part takes a triangle
 * of the part with the most. */
void decomp_widen(const mesh *m, int32_t *part, const double *tw, int32_t K, int exact);
void decomp_fill_empty(const mesh *m, int32_t *part, int32_t K);

/* Fills d (zeroed first) from the labelled triangulation m: part[t] in [0, K) for every live
 * triangle slot t (dead slots ignored), tw[t] its work.  mseg_cut[s] (m->nseg, may be NULL) is
 * 1 for the segments of m that are cuts rather than input segments; mseg_parent[s] (may be
 * NULL: identity for s < in->nsegs, else -1) names a non-cut segment's input segment and a
 * cut's id; mseg_marker (may be NULL: m->smarker) the markers of m's segments.  Interface
 * edges are the edges between triangles of different parts that are not pieces of input
 * segments.  keep_all: every vertex of m in a triangle becomes a vertex of d->g (the CDT of
 * d->g is then m itself up to cocircular ties); keep_all 2: that, and m's triangles kept in
 * d->tri_off, d->tri; else only input vertices and interface endpoints.  Every part must hold a
 * triangle.  Fills everything but sub_target and sub_owner. Returns 0, or -1 with a message in err.
 */
int decomp_build(const decomp_threads *th, const pslg *in, const mesh *m, const uint8_t *mseg_cut,
                 const int32_t *mseg_parent, const int32_t *mseg_marker, const int32_t *part,
                 const double *tw, int32_t K, int keep_all, pcdm_decomp *d, char *err,
                 size_t errlen);

/* decomp_build's passes over m's triangle slots (decomp_pass.c), on th's threads, the same bits
 * for any thread count.  decomp_nchunks: the chunks they cut m->nt slots into.
 * decomp_pass1: adds each part's area, work (tw) and total to d's sums (zeroed), sets its seed
 * (the centroid of its first largest triangle) and keep[] of every vertex of an edge between
 * parts; returns the first part without a triangle, or -1.  decomp_vert_parts: vert_sub[gid[v]]
 * = the part of a triangle of v, for every kept v (gid[v] >= 0).  decomp_part_edges: the
 * half-edges e between live triangles of different parts (seen from the lower triangle), in
 * slot order (*count of them; free the array).  decomp_tris_by_part: d->tri_off, d->tri: the
 * live triangles part by part, in slot order within one, their vertices in gid's numbers. */
/* Every live triangle around an input corner sharper than 60 degrees takes the part of the first
 * such triangle in slot order (one at two such corners, its last one's). */
void decomp_merge_corners(const decomp_threads *th, const mesh *m, int32_t *part);
int32_t decomp_nchunks(int64_t n);
int64_t decomp_chunk(int64_t n); /* the items of each of them but the last */
/* fn(ctx, c, a, b) for every chunk c of [0, n) ([a, b): decomp_nchunks' chunks, whatever
 * th->n), on th's threads; returns the chunk count. */
int32_t decomp_for_chunks(const decomp_threads *th, int64_t n,
                          void (*fn)(void *ctx, int32_t c, int32_t a, int32_t b), void *ctx);
int decomp_pass1(const decomp_threads *th, const mesh *m, const int32_t *part, const double *tw,
                 int32_t K, uint8_t *keep, pcdm_decomp *d);
void decomp_vert_parts(const decomp_threads *th, const mesh *m, const int32_t *part,
                       const uint8_t *keep, const int32_t *gid, int32_t *vert_sub);
int32_t *decomp_part_edges(const decomp_threads *th, const mesh *m, const int32_t *part,
                           int32_t *count);
void decomp_tris_by_part(const decomp_threads *th, const mesh *m, const int32_t *part,
                         const int32_t *gid, int32_t K, pcdm_decomp *d);

/* Makes d's per-subdomain lists (sub_seg_off, sub_seg, sub_vert_off, sub_vert) from seg_sub and
 * vert_sub (vert_sub may be NULL: no free vertex listed). */
void decomp_index(pcdm_decomp *d);

/* Assigns d->sub_owner for P = nranks ranks and imbalance R (rank 0 gets R/(R+P-1) of the
 * work).  planned (K entries, may be NULL) are owners decided before partitioning (then kept);
 * otherwise K = P maps s to rank s and K > P runs METIS on the subdomain graph (vertex weight:
 * work; edge weight: interface length), then every rank left without a subdomain takes one from
 * the rank with the most.  Returns 0, or -1 with a message in err. */
int decomp_map_owners(pcdm_decomp *d, int32_t P, double R, const int32_t *planned, char *err,
                      size_t errlen);

/* The predicted cost of the partition part of m's live triangles into K parts: that of its
 * costliest part, work (tw) plus boundary_cost times its boundary with other parts in units
 * of the local final triangle size (decomp_seeds.c). */
double decomp_part_cost(const mesh *m, const double *tw, const int32_t *part, int32_t K,
                        double boundary_cost);

/* Scales positive doubles to METIS integer weights (at least 1 each, sum below 2^30). */
void decomp_int_weights(const double *w, int32_t n, idx_t *out);

#endif
