/* pcdm: the Parallel Constrained Delaunay Meshing algorithm (TR-97-17 section 3) on one rank.
 *
 * Every rank builds the same coarse CDT of the decomposition's augmented PSLG (input segments
 * plus the artificial interface segments), keeps the triangles of the subdomains it owns and
 * refines them with the sequential Ruppert/Chew kernel (mesh.h) -- no locks, no blocking tasks.
 * When the kernel splits an interface subsegment it names it (segment id, dyadic level, index)
 * and this module sends the rank on the other side the only remote service request there is,
 * "split constraint edge (seg, level, k)"; the receiver splits the same subsegment at the same
 * point (bit for bit: mesh_rules_iface_point from the name and the original endpoints).  A request
 * for a subsegment already split is counted and dropped.  Termination: the runtime's detector.
 *
 * That is the asynchronous mode (./pcdm --async): the mesh depends on message timing.  The
 * deterministic mode (pcdm_part_build_det, pcdm_det.c; ./pcdm's default) refines each
 * subdomain in its own mesh, in rounds, so the mesh depends only on the input, the bounds and
 * the decomposition.  With p->balance (./pcdm --balance dynamic, pcdm_move.c) idle ranks take
 * unstarted subdomains from busy ones during the deterministic refinement; the mesh stays the
 * same.
 *
 * Usage (SPMD):
 *     rt_init(...); pcdm_register();            // before rt_start / the first rt_run
 *     pcdm_part p; pcdm_part_build(&p, &d, rt_rank(), err, sizeof err);  // or _build_det
 *     pcdm_part_refine(&p, &q, 0);              // Collective (rt_run)
 *     pcdm_part_take(&p, &flat, &art, ...);     // then par_output(..., &flat, art, ...)
 *     pcdm_part_free(&p);
 */
#ifndef PCDM_H
#define PCDM_H

#include <stddef.h>
#include <stdint.h>

#include "bounds/bounds.h"
#include "decomp/decomp.h"
#include "io/meshio.h"
#include "par/par.h"
#include "seq/mesh.h"

/* The one RSR payload: split the subsegment [k/2^level, (k+1)/2^level] of segment seg (an
 * interface piece of the decomposition's PSLG, d.g numbering). */
typedef struct pcdm_split_msg {
    int32_t seg;
    int32_t level;
    int64_t k;
} pcdm_split_msg;
_Static_assert(sizeof(pcdm_split_msg) == 16, "pcdm_split_msg must be 16 bytes, no padding");

typedef struct pcdm_det pcdm_det; /* private to pcdm_det.c */

/* One rank's part of the PCDM computation. */
typedef struct pcdm_part {
    mesh m;                 /* the local mesh: every subdomain this rank owns (asynchronous mode;
                             * empty in deterministic mode, which keeps one mesh per subdomain) */
    pcdm_det *det;          /* deterministic mode's state (pcdm_part_build_det), else NULL */
    int32_t rounds;         /* deterministic mode: rounds until no split anywhere (the same on
                             * every rank); 0 in asynchronous mode */
    const pcdm_decomp *d;   /* borrowed; must outlive the part */
    int rank;               /* owner of this part */
    int32_t nsub_owned;     /* subdomains owned by this rank (after refinement with balancing:
                             * the subdomains it ended with) */
    int32_t poll_every;     /* insertions between two returns to the scheduler */
    int threads;            /* deterministic mode: subdomain rounds run on this many of the
                             * runtime's worker threads at once (threaded handlers; <= 1: on
                             * the main thread, between polls) */
    int dirty;              /* refinement work may be queued (set by the split handler) */
    int limit_hit;          /* the Steiner limit stopped refinement */
    int progress;           /* progress lines on stderr (rank 0) */
    double t_start, t_last; /* for progress lines */
    /* counters */
    uint64_t split_sent;     /* split RSRs sent to other ranks */
    uint64_t split_recv;     /* split RSRs received */
    uint64_t split_done;     /* of those, splits performed here */
    uint64_t split_ignored;  /* of those, subsegment already split here (dropped) */
    uint64_t split_notfound; /* of those, segment not present here (a protocol error) */
    uint64_t work_steps;     /* calls of the local work function that refined */
    uint64_t flips;          /* edges flipped after refinement to make each mesh Delaunay again
                              * (pcdm_mesh_restore_delaunay; 0 unless refinement stopped short) */
    /* dynamic load balancing (deterministic parts; set balance before pcdm_part_refine) */
    int balance;          /* 1: idle ranks take unstarted subdomains from busy ones */
    uint64_t migrations;  /* subdomains this rank received */
    uint64_t moved_bytes; /* bytes of the subdomains this rank sent */
    double move_s;        /* seconds packing and unpacking (rebuilding) subdomains */
    uint64_t forwarded;   /* round lists sent on to where their subdomain moved */
    int regions;          /* PCDM_REGIONS_* the deterministic build labels each mesh with */
    int32_t fault_drop;   /* test-only: split requests still to drop (env PCDM_TEST_DROP_SPLIT=N
                           * drops rank 1's first N split requests: breaks an interface so
                           * the interface check must fail) */
} pcdm_part;

/* Local, SPMD: every rank calls it once, in the same position of its handler registration
 * sequence, after rt_init and before rt_start (or the first rt_run).  Registers the
 * non-threaded handler "pcdm_split".  Returns 0, or a negative RT_E* code. */
int pcdm_register(void);

/* Local.  Builds the CDT of d->g with d->seg_iface as interface flags (the same coarse CDT on
 * every rank), maps each region (component between constraint edges) to its subdomain exactly
 * (by the side of a bounding constraint edge and d->seg_sub), and keeps only the subdomains
 * that d->sub_owner assigns to rank.  p is overwritten; d is borrowed and must outlive p.
 * Returns 0, or -1 with a message in err (p then holds nothing). */
int pcdm_part_build(pcdm_part *p, const pcdm_decomp *d, int rank, char *err, size_t errlen);

/* Region labels for pcdm_part_build_regions. */
enum { PCDM_REGIONS_NONE = 0, PCDM_REGIONS_LABEL = 1, PCDM_REGIONS_AREA = 2 };

/* Local.  pcdm_part_build, and with regions != PCDM_REGIONS_NONE the input's regions (d->g's,
 * copied from the input) labelled on the whole coarse CDT before the subdomains are kept
 * (mesh_set_regions crosses interface edges, so a region spanning subdomains gets one label
 * on every rank); new triangles inherit them.  PCDM_REGIONS_AREA: the regions' area bounds
 * are honoured too.  The flat forms then carry tattr. */
int pcdm_part_build_regions(pcdm_part *p, const pcdm_decomp *d, int rank, int regions, char *err,
                            size_t errlen);

/* Local.  Deterministic mode (pcdm_det.c): like pcdm_part_build, but one mesh per owned
 * subdomain, each built from the same coarse CDT and holding that subdomain alone.  Refined by
 * pcdm_part_refine in rounds: in round r a subdomain applies, in canonical order (sorted by
 * (seg, level, k)), the interface splits its neighbours made in round r-1, refines to completion
 * and sends each neighbour its round-r splits (possibly none); it waits only for its neighbours'
 * previous round.  The run ends after the first round in which no subdomain split an interface
 * subsegment.  Each subdomain's mesh is then a pure function of the input, the bounds and the
 * decomposition: bit-identical for any rank count and any message timing.  With -S each
 * subdomain gets the budget's share of its weight (sub_weight / total_weight).  regions: as
 * pcdm_part_build_regions.  Returns 0, or -1 with a message in err. */
int pcdm_part_build_det(pcdm_part *p, const pcdm_decomp *d, int rank, int regions, int threads,
                        char *err, size_t errlen);

/* Collective (calls rt_run).  Refines p's mesh to q (per-rank Steiner limit: q->max_steiner
 * as given) with the split protocol above; poll_every (0: 300) insertions per work step
 * between two services of incoming RSRs.  Returns when every rank is done and no request is in
 * flight.  Returns 0. */
int pcdm_part_refine(pcdm_part *p, const mesh_quality *q, int32_t poll_every);

/* Figures of a refined part (either mode; sums over its meshes). */
typedef struct pcdm_figures {
    int64_t ntris, nverts, inserted, unmet;
    int64_t refused;      /* refused splits (mesh_stats.unresolved summed) */
    int64_t iface_enc;    /* interface subsegments that do not conform (mesh_iface_defects:
                           * split on one side only, or not Delaunay): a split refinement
                           * refused (precision, the interface piece cap) */
    int64_t iface_remote; /* ... and those left encroached whose other side is on another rank
                           * (Delaunay or not: par_check_interface_delaunay decides) */
    size_t mesh_bytes;
} pcdm_figures;

/* Local.  Fills *f (unmet: mesh_count_unmet summed; iface_enc, iface_remote:
 * mesh_iface_defects summed). */
void pcdm_part_figures(pcdm_part *p, pcdm_figures *f);

/* Local.  Either mode: moves the part into f as pcdm_part_take_flat does (trank NULL);
 * *artificial gets pcdm_part_artificial's flags for f's subsegments (free with free()).  In
 * deterministic mode the subdomains' meshes are merged into one part: the vertices two of them
 * share (on their interface, bit-equal coordinates) and the subsegments of that interface appear
 * once; topen then marks the edges open in the merged part.  The merge runs on p->threads
 * threads and frees each subdomain's mesh as soon as it is copied, so the rank holds every
 * triangle about once. */
void pcdm_part_take(pcdm_part *p, mesh_flat *f, uint8_t **artificial, int32_t **tsub,
                    uint8_t **topen);

/* Local, pure.  The mesh hash: the sum (mod 2^64) over f's triangles of a strong 64-bit mix of
 * the triangle's three vertices' coordinate bits, taken counter-clockwise from the vertex with
 * the smallest (x, y) (-0.0 as +0.0).  It does not depend on vertex or triangle numbering, so
 * the sum over the ranks' parts (MPI_SUM of uint64) hashes the whole mesh for any rank count.
 * Runs on up to threads threads (the sum is the same for any count). */
uint64_t pcdm_flat_hash(const mesh_flat *f, int threads);

/* Local, asynchronous parts only.  The part as a mesh_flat (local numbering) with trank set to
 * p->rank.  Returns 0 or -1 (out of memory).  Free with mesh_flat_free. */
int pcdm_part_flat(const pcdm_part *p, mesh_flat *f);

/* Local, asynchronous parts only.  Moves the part's mesh into f (mesh_take_flat: the mesh is never
 * held twice) with trank NULL (every triangle is this rank's: the writers take the rank); when tsub
 * is not NULL, *tsub gets each triangle's subdomain (f->ntris entries, same order; free with
 * free()); when topen is not NULL, *topen the open-edge mask of mesh_take_flat.  p's mesh is empty
 * afterwards: take every figure from it (and pcdm_part_artificial) first.  Free f with
 * mesh_flat_free. */
void pcdm_part_take_flat(pcdm_part *p, mesh_flat *f, int32_t **tsub, uint8_t **topen);

/* Local, asynchronous parts only.  Per subsegment of pcdm_part_flat's output (same order): 1 if it
 * is an artificial interface edge of the decomposition (not an input constraint: not written to
 * .poly files), else 0.  The caller frees the array (free). */
uint8_t *pcdm_part_artificial(const pcdm_part *p);

/* Local.  Frees the part's mesh and zeroes it. */
void pcdm_part_free(pcdm_part *p);

/* PCDM's entry (pcdm_entry.c), what the driver (run/) calls: the bounds b and the settings c
 * instead of the command line.
 * Local.  Builds this rank's part of d (in rounds, pcdm_part_build_det, when c->deterministic
 * or c->balance; else pcdm_part_build_regions), labelled with regions when c->regions (and
 * bounded by them when b->region_area).  Returns 0, or -1 with a message in err (*p then holds
 * nothing); the caller agrees on failure across the ranks before pcdm_part_run. */
int pcdm_part_start(pcdm_part *p, const pcdm_decomp *d, const mesh_bounds *b, const par_config *c,
                    char *err, size_t errlen);

/* Collective.  Refines the part to b (pcdm_part_refine; lenses never: diametral circles make
 * the interface subsegments Delaunay edges of the merged mesh): the Steiner limit is shared by
 * the subdomains in rounds, else split by the subdomains' target weights; b's size rule; c's
 * poll (default 300), balance and progress.  Resets the runtime's statistics first. */
void pcdm_part_run(pcdm_part *p, const mesh_bounds *b, const par_config *c);

#endif
