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
int decomp_build(const pslg *in, const mesh *m, const uint8_t *mseg_cut, const int32_t *mseg_parent,
                 const int32_t *mseg_marker, const int32_t *part, const double *tw, int32_t K,
                 int keep_all, pcdm_decomp *d, char *err, size_t errlen);

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
