/* pbw: the Parallel Meshing Algorithm of TR-97-17 section 2 -- a parallel Bowyer-Watson
 * (Chew-Ruppert) Delaunay refinement of ONE distributed mesh, without artificial constraints.
 *
 * The initial boundary-conforming CDT of the input is partitioned among the ranks (every
 * triangle has one owner; neighbours across ranks are (owner rank, slot) names).  Every rank
 * refines its own bad triangles; a cavity that reaches triangles owned by other ranks is
 * expanded by remote service requests, locked on every rank it touches, and either committed
 * everywhere or released everywhere (undo).  See pbw.c for the protocol and its progress
 * argument.
 *
 * Collective = every rank of rt_app_comm() calls it; Local otherwise.
 */
#ifndef PBW_H
#define PBW_H

#include <stdint.h>

#include "decomp/decomp.h"
#include "geom/pslg.h"
#include "io/meshio.h"
#include "par/par.h"

/* RSR kinds, in handler registration order (the per-kind counts in pbw_result). */
enum {
    PBW_RSR_EXPAND,  /* remote cavity expansion (first hop: rt_request; later hops: rt_forward) */
    PBW_RSR_REPLY,   /* the chain's answer to the waiting task (rt_reply) */
    PBW_RSR_RELEASE, /* undo: release a cavity's locks on a participant */
    PBW_RSR_COMMIT,  /* create the new triangles, fix links, unlock */
    PBW_RSR_SPLIT,   /* split an encroached boundary subsegment (sent to its owner) */
    PBW_RSR_WAKE,    /* a lock a died cavity ran into was released: retry */
    PBW_RSR_NKINDS
};

/* Names of the kinds above ("expansion", "reply", ...). */
extern const char *const pbw_rsr_kind_name[PBW_RSR_NKINDS];

/* Per-rank outcome and counters of one pbw_mesh call. */
typedef struct pbw_result {
    int64_t ntris;           /* live triangles owned by this rank at the end */
    int64_t steiner;         /* vertices this rank created */
    int64_t inserted;        /* circumcenters / off-centers inserted by this rank */
    int64_t splits;          /* subsegment splits initiated by this rank */
    int64_t cavities_local;  /* committed cavities that touched no other rank */
    int64_t cavities_remote; /* committed cavities that crossed ranks */
    int64_t undone_local;    /* attempts abandoned on a lock before any RSR was sent */
    int64_t undone_remote;   /* distributed cavities released everywhere after a conflict */
    int64_t parked;          /* remote expansions that waited for an older-holds-younger lock */
    int64_t rejected;        /* Steiner points discarded because they encroach (split instead) */
    int64_t skipped_small;   /* bad triangles left alone: small angle forced by the input */
    int64_t failed;          /* insertions abandoned (degenerate / not star-shaped) */
    int64_t postponed;       /* --phases: nonlocal cavities put off to phase 2 */
    int64_t ghosted;         /* committed local cavities with a ghost edge (a tombstone, no lock) */
    int64_t forwarded;       /* seeds that followed a stale link through a tombstone */
    int64_t iface_edges;     /* edges of this rank's triangles whose neighbour is on another rank */
    double iface_len;   /* their summed length (each rank boundary edge counted by both sides) */
    int64_t unresolved; /* refusals: a new edge would be below the length floor */
    int64_t unmet;      /* this rank's triangles outside the bounds at the end, not forced */
    int64_t forced;     /* this rank's triangles below the angle bound forced by the input */
    int gave_up;        /* refusals passed the budget: this rank stopped refining */
    int limit_hit;      /* the Steiner limit stopped this rank */
    int32_t pre_tris;   /* triangles of the initial mesh (all ranks, before distribution) */
    uint64_t rsr_sent[PBW_RSR_NKINDS]; /* RSRs this rank sent to other ranks, by kind */
    uint64_t rsr_self;                 /* RSRs it sent to itself (a reply to its own task) */
    double phase1_s;                   /* --phases: seconds of phase 1 (0 otherwise) */
    double endcheck_s; /* seconds of the end check of the Delaunay property: CPU seconds
                          (pbw_check.c) */
    size_t mesh_bytes; /* bytes of this rank's mesh arrays (capacities) */
    uint8_t *topen;    /* *local's open edges, one byte per triangle: bit j set when edge j (tri[j]
                        * -> tri[j+1]) has no neighbour in *local (domain boundary, another rank):
                        * what par_output_sub takes instead of finding them by vertex rows; the
                        * caller's (free()) */
} pbw_result;

/* Registers PBW's RSR handlers.  Local but SPMD: every rank, same order, before any rt_run.
 * Returns 0 or a negative RT_E* code. */
int pbw_register(void);

/* Where ranks share cores, the decomposition for ./pbw weighs a part's boundary with other parts
 * against its triangles: pcdm_decomp_opts.boundary_cost (decomp_seeds.c), PBW_BOUNDARY_COST as
 * measured with PBW_BOUNDARY_RHO ranks per core (the lake at 10M triangles, 8 ranks on 2 cores),
 * scaled by the share of ranks waiting for a core, 1 - 1/rho at rho ranks per core (a rank whose
 * neighbour is not running waits for it; with a core per rank the partition is METIS's own:
 * at 2 ranks on 2 cores the weighted choice measured 3% slower), the best of PBW_DECOMP_SEEDS
 * METIS seeds (shared out over the ranks, at most PBW_SEEDS_PER_RANK on each). */
#define PBW_BOUNDARY_COST 26.0
#define PBW_BOUNDARY_RHO 4.0
#define PBW_DECOMP_SEEDS 16
#define PBW_SEEDS_PER_RANK 4

/* Collective.  Builds the initial CDT of in on every rank (or takes d->cdt's contents when the
 * decomposition kept it: decomp.h), distributes its triangles by the
 * subdomains of d (triangle centroid -> subdomain -> d->sub_owner), refines the distributed
 * mesh to the bounds b (c: --phases, --poll, --inflight, regions) and fills *local with this rank's
 * triangles (local vertex numbering, trank = rank, the subsegments of its triangles); *local is the
 * caller's (mesh_flat_free).  res may be NULL.  Refinement always ends: a rank whose
 * refusals (edges below the length floor, seq/rules.h) pass the budget stops (res->gave_up),
 * and res->unmet counts this rank's triangles left outside the bounds that the input does not
 * force; the caller must fail if their sum over the ranks is not 0 (unless the Steiner limit
 * was hit).  Test-only fault: env PBW_TEST_BREAK_IFACE=R makes rank R drop one triangle at a
 * rank boundary from *local (the caller's interface check must catch it).  Returns 0, or -1
 * on every rank (after rank 0 printed the message) if the CDT cannot be built. */
int pbw_mesh(const mesh_bounds *b, const par_config *c, const pslg *in, const pcdm_decomp *d,
             mesh_flat *local, pbw_result *res);

#endif
