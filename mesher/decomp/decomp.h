/* pcdm_decomp: automatic domain decomposition for PCDM (the artificial constraint edges).
 *
 * TR-97-17 section 3 asks of the boundaries between processors: equal work per processor,
 * well-spaced boundaries, and no small angles with each other or with the region boundary.
 * The paper drew them by hand and named automation as future work; this module draws them.
 *
 * pcdm_decomp_auto() cuts the domain of a checked PSLG into K subdomains by recursive
 * bisection with axis-parallel straight cuts (see pcdm_decomp.c for the algorithm).
 * Determinism: the same binary computes the same bits on every rank (plain IEEE arithmetic,
 * fixed scan orders, strict comparisons; no reductions, no randomness).
 * pcdm_decomp_read_cuts() takes the cuts from a file instead.  Both fill the same plain,
 * pointer-free description (a pcdm_decomp); every rank that calls either function with the same
 * input computes bit-identical output, so the decomposition needs no communication.
 *
 * Weight (expected work) of a subdomain: area / a, where a is the area bound in force for the
 * domain face it lies in (the smaller of opts.max_area and the face's regional max-area
 * attribute, whichever are > 0; faces with neither take the largest bound present anywhere).
 * With no area bound at all the weight is the plain area (a = 1).  This is the expected
 * number of triangles up to a constant factor.  No local-feature-size correction is applied:
 * refinement near small input features is local, and area weighting keeps every subdomain's
 * measured area balanced, which is what the tests verify.
 *
 * Cuts file format (pcdm_decomp_read_cuts, and what pcdm_decomp_write_cuts writes):
 *     # comment (from '#' to the end of the line; blank lines are ignored)
 *     x1 y1 x2 y2        one straight cut segment per line
 * Each endpoint must lie on the domain boundary, on another cut, or coincide with an endpoint
 * of another cut, to within 1e-6 times the diagonal of the input's bounding box (it is then
 * moved onto that segment or vertex).  Cuts must not cross each other or the input segments
 * except at their endpoints, must lie inside the domain, and must separate two different
 * subdomains; each subdomain is one face of the resulting arrangement.  Any violation is
 * reported as "FILE:LINE: problem".
 *
 * All functions are Local (no communication).  Out of memory aborts.
 */
#ifndef PCDM_DECOMP_H
#define PCDM_DECOMP_H

#include "geom/pslg.h"

#include <stddef.h>
#include <stdint.h>

typedef struct pcdm_decomp_opts {
    int32_t nsub;       /* K, number of subdomains; 0 = nranks (auto) / whatever the cuts make */
    int32_t nranks;     /* P >= 1 */
    double min_angle;   /* quality bound in degrees (cuts never meet a segment below it) */
    double max_area;    /* area bound, 0 = none */
    double imbalance;   /* R > 0: rank 0 gets R times the weight of each other rank (1 = even) */
    double balance_tol; /* allowed relative deviation of a subdomain's weight from its target;
                         * 0 = default 0.08 (auto mode only) */
} pcdm_decomp_opts;

typedef struct pcdm_decomp {
    /* The augmented PSLG.  Owns its arrays.  Vertices [0, ninput_verts) are the input's, same
     * order and coordinates; the rest are new: where a cut meets an input segment (vmarker =
     * that segment's marker, attributes interpolated) or another cut (vmarker 0).
     * Segments [0, nboundary) are the input segments split at the new vertices, in input
     * order, each piece directed like its input segment and keeping its marker; segments
     * [nboundary, g.nsegs) are the interface (cut) pieces, smarker 0.  holes and regions are
     * copied.  vline/sline: the input's lines; for cuts, the cuts file's line (0 in auto). */
    pslg g;
    int32_t ninput_verts, ninput_segs;
    int32_t nboundary;   /* number of pieces of input segments */
    int32_t *seg_parent; /* g.nsegs: input segment id (0-based) of a boundary piece, or the
                          * cut id of an interface piece */
    uint8_t *seg_iface;  /* g.nsegs: 1 for interface pieces, else 0 */
    int32_t *seg_sub;    /* 2 * g.nsegs: subdomain on the left and on the right of the piece
                          * (from its first to its second vertex); -1 = outside the domain */
    /* The cuts as straight segments before T-junction splitting (x1 y1 x2 y2 each). */
    int32_t ncuts;
    double *cut_xy; /* 4 * ncuts */
    /* Subdomains, in recursive-bisection (spatially coherent) order. */
    int32_t nsub;       /* K */
    int32_t nranks;     /* P */
    double *sub_seed;   /* 2 * K: a point strictly inside each subdomain, far from its edges */
    double *sub_area;   /* K: exact polygon area (shoelace over the subdomain's boundary) */
    double *sub_weight; /* K: expected weight (see above) */
    double *sub_target; /* K: target fraction of the total weight (sums to 1) */
    int32_t *sub_owner; /* K: owning rank; non-decreasing (contiguous), every rank owns one */
    double total_weight;
    double min_angle; /* smallest angle between an interface piece and any other segment
                       * at a shared vertex (degrees; 180 when there are no cuts) */
} pcdm_decomp;

/* Fills o with defaults: nsub 0, nranks 1, min_angle 30, max_area 0, imbalance 1,
 * balance_tol 0 (0.08). */
void pcdm_decomp_opts_default(pcdm_decomp_opts *o);

/* Cuts the domain of in (read and pslg_check()ed; not modified) into K = o->nsub subdomains
 * (o->nranks if 0; K >= P required) and fills *out (zeroed first; owns its arrays on success,
 * holds nothing on failure).  K = 1 adds nothing.  Guarantees on success:
 *  - balance: every subdomain's weight is within balance_tol of its target (sub_target:
 *    rank 0 owns R/(R+P-1) of the total, every other rank 1/(R+P-1), each rank's share split
 *    evenly over its subdomains; rank 0 gets about K R/(R+P-1) subdomains);
 *  - angles: every cut meets every other segment at a shared vertex at >= max(30,
 *    min(o->min_angle, 60)) degrees; 60 or more is preferred and found unless the boundary
 *    near every balanced position is too ragged (see d->min_angle);
 *  - spacing: no cut passes closer to a vertex or segment it does not end on than 20% of
 *    min(expected subdomain size, local feature size) (10% for a point another cut put on
 *    a segment the cut ends on), and no cut piece is shorter than 1% of sqrt(domain area);
 *  - cuts are axis-parallel; cuts meet at 90 degrees (T- or +-junctions, exact coordinates);
 *    a cut may end at an input vertex (e.g. continuing an edge out of a re-entrant corner).
 * Returns 0, or -1 with a message in err: empty domain (zero area), K < P, K < the number of
 * separate domain faces, K too large for the domain (no cut satisfies the rules; the message
 * names the region and the best values found), unsupported PSLG (dangling segments or
 * boundary cycles touching at a vertex: give a cuts file instead). */
int pcdm_decomp_auto(const pslg *in, const pcdm_decomp_opts *o, pcdm_decomp *out, char *err,
                     size_t errlen);

/* Reads cuts from path (format above) and builds the decomposition of in they define.
 * Subdomains are the faces of the arrangement, ordered by seed (x, then y); sub_target is the
 * measured weight fraction; owners are assigned contiguously so that rank 0 gets about
 * R/(R+P-1) of the weight.  o->nsub must be 0 or equal to the number of subdomains the cuts
 * make; K >= o->nranks.  A cut meeting a segment below o->min_angle is an error.  Returns 0,
 * or -1 with "FILE:LINE: problem" (or "FILE: problem") in err; *out as for
 * pcdm_decomp_auto. */
int pcdm_decomp_read_cuts(const char *path, const pslg *in, const pcdm_decomp_opts *o,
                          pcdm_decomp *out, char *err, size_t errlen);

/* Writes d's cuts in the cuts-file format (to a temporary name, then renamed).  Returns 0, or
 * -1 with "FILE: problem" in err. */
int pcdm_decomp_write_cuts(const pcdm_decomp *d, const char *path, char *err, size_t errlen);

/* Frees everything d owns and zeroes it.  Safe on a zeroed struct. */
void pcdm_decomp_free(pcdm_decomp *d);

#endif
