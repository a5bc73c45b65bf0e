/* pcdm_decomp: domain decomposition for PCDM and PBW (the artificial constraint edges).
 *
 * TR-97-17 section 3 asks of the boundaries between processors: equal work per processor,
 * well-spaced boundaries, and no small angles with each other or with the region boundary.
 * The paper drew them by hand and named automation as future work; this module draws them.
 *
 * pcdm_decomp_auto() meshes the input coarsely with the project's own quality mesher, weights
 * every coarse triangle by the work it will become, partitions the coarse mesh's dual graph
 * into K parts with METIS and takes the part boundaries (chains of coarse edges) as the
 * interface segments; every angle an interface makes with another segment holds a corner of a
 * coarse quality triangle.  When the final mesh is small (at most exact_per_sub triangles per
 * subdomain, found by refining at the real bounds under a Steiner limit) the coarse mesh IS the
 * final mesh (the "exact preview"): METIS balances the actual triangles, every preview vertex
 * goes into the augmented PSLG, and the interfaces are final mesh edges that need no splitting,
 * so the count matches ./mesh.  pcdm_decomp_read_cuts() takes straight cuts from a file instead.
 * Both fill the same plain, pointer-free description (a pcdm_decomp) from a labelled
 * triangulation (decomp_impl.h); every rank that calls either function with the same input
 * computes bit-identical output (deterministic mesher, METIS with a fixed seed), so the
 * decomposition needs no communication.
 *
 * Work (weight) of a coarse triangle: with an area bound a, max(1, area / a) (the triangles it
 * will become, at least one where the local feature size already makes it small; a is the
 * smaller of the global bound and the bound of the triangle's input region, with
 * region_area); with no area bound, 1 (the coarse mesh is then graded by the local feature size
 * like the final one); on the exact preview, 1.
 *
 * Cuts file format (pcdm_decomp_read_cuts, and what pcdm_decomp_write_cuts writes):
 *     # comment (from '#' to the end of the line; blank lines are ignored)
 *     x1 y1 x2 y2        one straight cut segment per line
 * An endpoint within 1e-6 times the diagonal of the input's bounding box of an input vertex,
 * of another cut's endpoint or of a segment (input or cut) is moved onto it (the segment is
 * split there).  Cuts must not cross each other or the input segments except at their
 * endpoints, must lie inside the domain, must meet every other segment at an angle of at least
 * the -q bound (opts.min_angle), and every cut must separate two different
 * subdomains; the subdomains are the faces of the arrangement of the input segments and the
 * cuts.  Any violation is reported as "FILE:LINE: problem".
 *
 * All functions are Local (no communication).  Out of memory aborts.
 */
#ifndef PCDM_DECOMP_H
#define PCDM_DECOMP_H

#include "geom/pslg.h"

#include <stddef.h>
#include <stdint.h>

struct mesh; /* seq/mesh.h */

typedef struct pcdm_decomp_opts {
    int32_t nsub;          /* K, number of subdomains; 0 = nranks (auto) / whatever the cuts make */
    int32_t nranks;        /* P >= 1 */
    int nsub_fit;          /* 1: nsub is a default, not asked for: halved (not below nranks)
                            * while the coarse mesh has fewer than 2 triangles per subdomain */
    double min_angle;      /* quality bound in degrees of the final mesh (the coarse mesh's bound is
                            * at least 30 and a little above this one) */
    double max_area;       /* area bound in the input's units (as given: the decomposition scales
                            * it like the coordinates, pslg.scale_exp), 0 = none */
    double imbalance;      /* R > 0: rank 0 gets R times the weight of each other rank (1 = even) */
    int32_t per_sub;       /* auto: coarse triangles per subdomain (0 = default 200) */
    int32_t exact_per_sub; /* auto: exact preview when the final mesh has at most this many
                            * triangles per subdomain (0 = default 1000; < 0 = never) */
    int64_t max_steiner;   /* the final mesh's Steiner budget (< 0: none); with a budget the
                            * exact preview is not used (it would spend the budget) */
    int region_area;       /* 1: the input's per-region area bounds hold too (--region-areas):
                            * auto: they enter the work weights, the exact preview and its
                            * trial (a cuts file's weights ignore them) */
    int keep_cdt;          /* auto: 1 = keep a copy of the input's CDT in the result (cdt) */
    /* auto: the Delaunay triangulation of exactly in's vertices, already made by
     * mesh_build_points (its duplicate map in *dt_dup), or NULL: the first CDT of the input is
     * completed from it (mesh_build_cdt_from_points: the same mesh) instead of built; taken (*dt
     * left empty, *dt_dup NULL) when used */
    struct mesh *dt;
    int32_t **dt_dup;
    int coarse_route; /* auto: 1 = partition the lfs-graded coarse mesh, not the input's CDT
                       * with interior points, whatever the input's size (decomp_auto.c) */
    /* Auto, coarse route, K = P > 1, imbalance 1 (./pbw): the partition is the one of least
     * predicted cost among several METIS seeds (decomp_seeds.c).  The cost of a part is its
     * work plus boundary_cost times its boundary with other parts measured in local final
     * triangle sizes; a partition's cost is its costliest part's.  0: METIS seed 1 alone.  This
     * caller tries the seeds seed_first + i * seed_step, i < seed_count (seed_count 0: seed 1
     * alone).  pick (if set) then chooses among the callers' candidates: it is called once,
     * with this caller's best predicted cost and its labels of the coarse triangles (n of
     * them), and replaces them with the labels every caller keeps (returns 0; -1 if no caller
     * has one).  Collective where pick is: every rank calls pcdm_decomp_auto with the same input
     * and options but its own seeds. */
    double boundary_cost;
    int32_t seed_first, seed_step, seed_count;
    int (*pick)(void *ctx, double cost, int32_t n, int32_t *part);
    void *pick_ctx;
    /* threads the decomposition's passes may run on (< 2: the caller's alone; the result is the
     * same for any count) and the CPUs its helper threads move onto (MESH_HOST_CPUS entries, as
     * mesh_thread_spread takes them; NULL: the caller's) */
    int threads;
    const uint8_t *cpus;
} pcdm_decomp_opts;

typedef struct pcdm_decomp {
    /* The augmented PSLG.  Owns its arrays.  Vertices [0, ninput_verts) are the input's, same
     * order and coordinates; the rest are new: coarse-mesh vertices where interfaces meet or
     * end (vmarker = the marker of the input segment they lie on, else 0; attributes 0).
     * Segments [0, nboundary) are the input segments split at the new vertices (and at input
     * vertices lying on them), in input order, each piece directed like its input segment and
     * keeping its marker; for a point set they are the convex hull's edges (marker 1).
     * Segments [nboundary, g.nsegs) are the interface edges, smarker 0.  No segment passes
     * through a vertex.  holes and regions are copied. */
    pslg g;
    int32_t ninput_verts, ninput_segs;
    int32_t nboundary;   /* number of pieces of input (or hull) segments */
    int32_t *seg_parent; /* g.nsegs: input segment id (0-based; -1 for hull edges) of a boundary
                          * piece, or the cut id (cuts file: its index) of an interface edge */
    uint8_t *seg_iface;  /* g.nsegs: 1 if the piece has different subdomains on its two sides
                          * (every interface edge, and input pieces between two subdomains) */
    int32_t *seg_sub;    /* 2 * g.nsegs: subdomain on the left and on the right of the piece
                          * (from its first to its second vertex); -1 = outside the domain */
    /* The interface edges as straight cuts (x1 y1 x2 y2 each), what --write-cuts writes. */
    int32_t ncuts;
    double *cut_xy;    /* 4 * ncuts */
    int32_t *vert_sub; /* g.nverts: the subdomain whose interior holds a vertex that ends no
                        * segment (a free input or Steiner vertex), else -1 (on a segment, or
                        * in no triangle: a hole, a merged duplicate) */
    /* The fast route's triangles by subdomain, so that each subdomain's first mesh is cut
     * from the decomposition's triangulation instead of triangulated again: subdomain k's are
     * tri[3 tri_off[k] .. 3 tri_off[k + 1]), counter-clockwise, in g's vertex numbers (every
     * vertex of a triangle is in g); both NULL on the other routes. */
    int32_t *tri_off; /* K + 1 */
    int32_t *tri;
    /* Each subdomain's own segment pieces (a side of them in it) and free vertices, ascending:
     * subdomain k's are sub_seg[sub_seg_off[k] .. sub_seg_off[k + 1]) and likewise sub_vert
     * (from seg_sub and vert_sub, made wherever a decomposition is made or received, so that a
     * subdomain's set-up costs its own size) */
    int32_t *sub_seg_off, *sub_seg, *sub_vert_off, *sub_vert;
    double floor2;      /* the refinement's squared length floor (mesh_rules_length_floor2) of
                         * the input's CDT, so that every subdomain mesh and ./mesh use the
                         * same one; 0: unknown (a subdomain then takes its own) */
    int32_t nsub;       /* K */
    int32_t nranks;     /* P */
    double *sub_seed;   /* 2 * K: a point strictly inside each subdomain */
    double *sub_area;   /* K: area (sum of its coarse triangles' rounded areas) */
    double *sub_weight; /* K: expected work (see above) */
    double *sub_target; /* K: target fraction of the total work (sums to 1) */
    int32_t *sub_owner; /* K: owning rank; every rank owns at least one subdomain */
    double total_weight;
    int32_t ncoarse;      /* triangles of the coarse mesh the decomposition was drawn on */
    int exact;            /* 1: drawn on the exact preview (the coarse mesh is the final mesh at the
                           * real bounds, and every one of its vertices is a vertex of g) */
    double iface_min_deg; /* pcdm_decomp_iface_min_angle, found once where it is drawn */
    double build_s;       /* wall seconds this rank spent building it (the driver measures) */
    /* pcdm_decomp_auto with opts.keep_cdt: the constrained Delaunay triangulation of the input
     * (mesh_build_cdt of in, no iface marks), as built before any refinement; else NULL.  Owned
     * (pcdm_decomp_free frees it); a user may take its contents, leaving it an empty mesh
     * (mesh_init): PBW's setup does, instead of building the same CDT again. */
    struct mesh *cdt;
} pcdm_decomp;

/* Local.  Frees the fast route's triangles (tri_off, tri: both NULL after) once the
 * subdomains' first meshes are built from them; the rest of d stays whole. */
void pcdm_decomp_drop_triangles(pcdm_decomp *d);

/* Fills o with defaults: nsub 0, nranks 1, min_angle 30, max_area 0, imbalance 1,
 * per_sub 0 (200), exact_per_sub 0 (1000), max_steiner -1, keep_cdt 0. */
void pcdm_decomp_opts_default(pcdm_decomp_opts *o);

/* Decomposes the domain of in (read and pslg_check()ed; not modified) into K = o->nsub
 * subdomains (o->nranks if 0; K >= P required) and fills *out (zeroed first; owns its arrays
 * on success, holds nothing on failure).  K = 1 adds nothing.  Owners: with K = P subdomain s
 * goes to rank s; otherwise METIS maps the subdomain graph (weights: work; edge weights:
 * interface length) onto the ranks.  Targets: rank 0 gets R/(R+P-1) of the work, every other
 * rank 1/(R+P-1).  out->exact tells whether the exact preview was used (it is checked by one
 * sequential refinement of out->g at o's bounds, so it costs about two ./mesh runs of the final
 * mesh, which is at most exact_per_sub triangles per subdomain).  Returns 0, or -1 with a message
 * in err (the input does not triangulate, K < P, the coarse mesh has too few triangles for K parts,
 * METIS failed). */
int pcdm_decomp_auto(const pslg *in, const pcdm_decomp_opts *o, pcdm_decomp *out, char *err,
                     size_t errlen);

/* Reads cuts from path (format above) and builds the decomposition of in they define.
 * Subdomains are numbered in the order of their first triangle in the CDT of the input plus the
 * cuts; sub_target is the measured work fraction; owners as in pcdm_decomp_auto.  o->nsub must
 * be 0 or equal to the number of subdomains the cuts make; K >= o->nranks.  Returns 0, or -1
 * with "FILE:LINE: problem" (or "FILE: problem") in err; *out as for pcdm_decomp_auto. */
int pcdm_decomp_read_cuts(const char *path, const pslg *in, const pcdm_decomp_opts *o,
                          pcdm_decomp *out, char *err, size_t errlen);

/* Writes d's interface edges in the cuts-file format (to a temporary name, then renamed).
 * Returns 0, or -1 with "FILE: problem" in err. */
int pcdm_decomp_write_cuts(const pcdm_decomp *d, const char *path, char *err, size_t errlen);

/* Sending a decomposition (or the input) to the ranks that did not compute it, without copying
 * it: the sender's *_pack_head makes a head (*head, *hlen bytes, the caller frees it: the
 * scalars and every array's length) and lists the arrays to send after it (a[0 .. *na), each
 * where it lies and its bytes; at most PCDM_PACK_MAX_ARRS).  A receiver's *_unpack_head fills
 * the fields from the head and allocates the arrays (a: where to receive each), and *_unpack_done
 * checks them once filled (contents against counts, labels in range) and makes the
 * per-subdomain lists.  The unpacks return 0, or -1 with nothing held (zeroed) when the head or
 * the arrays are malformed.  The pack of a decomposition that holds a CDT (keep_cdt, which is
 * not carried) returns -1.  Local, machine-native byte order (decomp_pack.c). */
enum { PCDM_PACK_MAX_ARRS = 24 };
typedef struct pcdm_pack_arr {
    void *p;
    size_t len;
} pcdm_pack_arr;
int pcdm_decomp_pack_head(const pcdm_decomp *d, void **head, size_t *hlen, pcdm_pack_arr *a,
                          int *na);
int pcdm_decomp_unpack_head(const void *head, size_t hlen, pcdm_decomp *d, pcdm_pack_arr *a,
                            int *na);
int pcdm_decomp_unpack_done(pcdm_decomp *d, const pcdm_pack_arr *a, int na);
/* pcdm_decomp_unpack_done, but a malformed d is left as it is (-1: the caller frees it), for
 * arrays that live in the caller's memory (pcdm_decomp_pack_place). */
int pcdm_decomp_unpack_index(pcdm_decomp *d, const pcdm_pack_arr *a, int na);
void pslg_pack_head(const pslg *g, void **head, size_t *hlen, pcdm_pack_arr *a, int *na);
int pslg_unpack_head(const void *head, size_t hlen, pslg *g, pcdm_pack_arr *a, int *na);
int pslg_unpack_done(pslg *g);

/* Local.  The arrays a pack lists (the present ones, in the list's order: a sender's as its
 * *_pack_head lists them, a receiver's as its *_unpack_head allocated them) moved to at[0],
 * at[1], ... (memory the caller owns and fills, each as large as the listed bytes): the old
 * arrays are freed, their contents not copied.  *_pack_forget: every such array for which held(ctx,
 * p) is 1 is forgotten (its pointer NULL, not freed), so that d (g) can be freed while the caller's
 * memory lives on. */
void pslg_pack_place(pslg *g, unsigned char *const *at);
void pcdm_decomp_pack_place(pcdm_decomp *d, unsigned char *const *at);
void pslg_pack_forget(pslg *g, int (*held)(const void *ctx, const void *p), const void *ctx);
void pcdm_decomp_pack_forget(pcdm_decomp *d, int (*held)(const void *ctx, const void *p),
                             const void *ctx);

/* The same as one byte buffer (*buf, *len bytes: the head, then the arrays; the caller frees
 * *buf) and back, field for field. */
int pcdm_decomp_pack(const pcdm_decomp *d, void **buf, size_t *len);
int pcdm_decomp_unpack(const void *buf, size_t len, pcdm_decomp *d);
void pslg_pack(const pslg *g, void **buf, size_t *len);
int pslg_unpack(const void *buf, size_t len, pslg *g);

/* Frees everything d owns and zeroes it.  Safe on a zeroed struct. */
void pcdm_decomp_free(pcdm_decomp *d);

/* The smallest angle (degrees) between an interface piece (d->seg_iface) and another segment
 * of the augmented PSLG at a vertex they share; 180 if none.  A quality figure, not topology:
 * below 180 / pi / MESH_RULES_IFACE_MAX_PIECES the splits along the two never end (PCDM
 * refuses such a decomposition; the preview's trial refinement skips it).  Local. */
double pcdm_decomp_iface_min_angle(const pcdm_decomp *d);

#endif
