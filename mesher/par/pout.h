/* pout: the end of ./pcdm and ./pbw without a gather (design.md "output") -- global numbering
 * by prefix sums, output written by every rank from its own part, the distributed --check,
 * and statistics as reductions.  No rank ever holds more than its own part of the mesh (the
 * SVG picture excepted: it is collected on rank 0, up to PAR_SVG_MAX_TRIS triangles).
 *
 * A rank's part is a mesh_flat in local numbering (what pcdm_part_flat and pbw_mesh give):
 * its triangles, every vertex they use (and possibly unused ones, which are not written), the
 * constraint subsegments of its triangles.  Vertices on an interface between ranks are held
 * by every rank whose triangles touch them, with bit-equal coordinates (the interface check,
 * par_check_interfaces_open, has verified this before any of the functions below runs).
 *
 * Collective = every rank of rt_app_comm() calls it, in the same order; Local otherwise.
 */
#ifndef PAR_POUT_H
#define PAR_POUT_H

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>

#include "check/par_check.h"
#include "check/validate.h"
#include "geom/pslg.h"
#include "io/meshio.h"
#include "par/par.h"

/* Largest mesh --svg collects on rank 0 (triangles, all ranks); above it --svg is an error. */
#define PAR_SVG_MAX_TRIS 2000000

/* Global numbering of a distributed mesh (0-based numbers; the files are 1-based).
 *  - Vertices: the input's vertices keep their input numbers 0..nin-1 and are written by rank
 *    0 (every rank has the input).  Every other vertex used by a triangle has exactly one
 *    owner: the lowest rank holding a vertex with the same coordinate bits.  Owned vertices
 *    are numbered in local order from nin + (owned vertices of lower ranks) (MPI_Exscan), so
 *    the ranks' written vertices are consecutive in rank order.  Non-owners learn the numbers
 *    of shared vertices from the owners through a rendezvous rank (the hash of the
 *    coordinates): O(part boundary) data on rt_app_comm(), four all-to-all rounds.
 *  - Triangles: this rank's, numbered from tfirst (MPI_Exscan of the counts).
 *  - Segments: the subsegments that are input constraints (not artificial interface edges);
 *    one listed by two ranks (an input segment between their parts) is written by the lower
 *    rank only (decided at a rendezvous like the vertices'). */
typedef struct par_numbering {
    int64_t nin;        /* input vertices */
    int64_t nverts;     /* vertices in the output (all ranks) */
    int64_t ntris;      /* triangles (all ranks) */
    int64_t nsegs;      /* segments written (all ranks) */
    int64_t vfirst;     /* number of this rank's first owned non-input vertex */
    int64_t tfirst;     /* number of this rank's first triangle */
    int32_t nowned;     /* owned non-input vertices */
    int32_t *owned;     /* nowned local ids, in the order of their numbers (owned by this struct) */
    int64_t *gid;       /* per local vertex: its number, or -1 (unused, not written) */
    int32_t nwseg;      /* segments this rank writes */
    int32_t *wseg;      /* nwseg local segment ids */
    int32_t nshared;    /* local vertices another rank also holds (for --stats) */
    int32_t unnumbered; /* 1 + a used local vertex left without a number (0: none) */
    const uint8_t *topen; /* the part's open-edge mask (par_number_open; borrowed) or NULL */
} par_numbering;

/* Collective.  Numbers local (this rank's part) as above.  artificial (local->nsegs flags, may
 * be NULL: none) marks the subsegments that are not input constraints (PCDM's interface
 * edges); given, local is a PCDM part, whose subsegments with sinterface 0 (no interface: the
 * same subdomain on both sides, or the domain on one) no other part lists.  Returns 0 and fills
 * *num (free with par_numbering_free), or -1 on every rank with the same message in err (*num then
 * holds nothing) when the parts disagree about a shared vertex (one holder does not have it on its
 * part's boundary). */
int par_number(const mesh_flat *local, const pslg *in, const uint8_t *artificial,
               par_numbering *num, char *err, size_t errlen);

/* Collective.  par_number with the part's open edges from the mesher's mask (topen,
 * mesh_take_flat's; NULL: found through vertex rows), kept in num->topen for the check; the
 * part's vertices are matched with the input's on up to threads threads (the same numbers for
 * any count). */
int par_number_open(const mesh_flat *local, const pslg *in, const uint8_t *artificial,
                    const uint8_t *topen, int threads, par_numbering *num, char *err,
                    size_t errlen);

/* Local.  Frees what num owns and zeroes it. */
void par_numbering_free(par_numbering *num);

/* Collective.  The distributed --check.  Every rank runs the exact validator
 * (mesh_validate, part mode: the part's boundary may be interface edges, which
 * the interface check compared across the neighbours; input vertices and the domain area are
 * checked over all parts) on its part with o's bounds, the edges between parts are tested
 * locally Delaunay across the ranks (par_check_interface_delaunay, counted as non_delaunay, as
 * the sequential validator counts every non-constraint edge), then the reports are reduced: counts
 * summed, extremes reduced, the first failing rank's first problem kept; the parts' areas are
 * summed and compared with the input's domain area (relative 1e-9), and every input vertex
 * must be a vertex of some part.  *r (every rank) gets the combined report; rank 0 prints its
 * summary line when print is set.  Returns 1 on every rank if the mesh passes, else 0.
 * Test-only fault: env PCDM_TEST_BREAK_PIECE=R makes rank R reverse one triangle of its part
 * before the check (so --check must fail on every rank). */
int par_check_parts(const par_opts *o, const pslg *in, mesh_flat *local, const par_numbering *num,
                    int print, validate_report *r);

/* Collective.  Writes what o asks for from every rank's part: -o PREFIX (MPI-IO single
 * Triangle files through meshio_pwrite_triangle, numbering num), --vtk FILE (FILE is the .pvtu
 * index; one piece FILE-without-.pvtu_R.vtu per rank, binary appended data, cell data rank
 * and, when tsub (local->ntris entries; NULL or not on every rank alike) is given,
 * subdomain), --svg FILE
 * (collected on rank 0, at most PAR_SVG_MAX_TRIS triangles).  Returns 0, or -1 on every rank
 * (the message printed by rank 0). */
/* Collective.  The cheap check every end runs: the parts' areas (part_area, this rank's, in the
 * working scale: par_part_area) summed over the ranks against the domain's (validate_area_net),
 * decided on rank 0 and sent to the others; dom: the domain's area when rank 0 already has it
 * (par_dom_ahead), else NULL (rank 0 computes it).  1 when they agree (on every rank alike);
 * else 0 with "the parts' areas sum to A, the domain's area is D: ..." in why. */
int par_area_agrees(const pslg *in, double part_area, const double *dom, char *why, size_t len);

/* The domain's area (pslg_domain_area) computed on a thread of its own while the caller goes on
 * (rank 0 during the decomposition, when the other ranks and threads wait), so that the area
 * check after meshing finds it made.  start: in must stay alive and unchanged until
 * par_dom_ahead_get, which joins the thread and returns the area (safe to call more than once:
 * the later calls return it at once; NULL on a struct that never started).  Join it before
 * anything that may end the process, so no thread is left behind.  Local. */
typedef struct par_dom_ahead {
    const pslg *in;
    const uint8_t *cpus; /* where the thread may run (mesh_thread_spread; NULL: the rank's) */
    double area;
    int started, joined;
    pthread_t thr;
} par_dom_ahead;
void par_dom_ahead_start(par_dom_ahead *a, const pslg *in, const uint8_t *cpus);
const double *par_dom_ahead_get(par_dom_ahead *a);

/* Local.  The area of f's triangles in its working scale, on threads threads (the same value
 * for any thread count: blocks of 256 triangles summed in order with compensation). */
double par_part_area(const mesh_flat *f, int threads);

struct meshio_set;
int par_write_parts(const par_opts *o, struct meshio_set *set, const pslg *in,
                    const mesh_flat *local, const int32_t *tsub, const par_numbering *num);

/* Collective.  The --stats figures: when on, rank 0 receives every rank's n figures (returned,
 * rank-major, free with free()) and tot/mx (n entries each) get their sums and maxima over the
 * ranks; other ranks, or on == 0: returns NULL and leaves tot/mx alone.  The mesh never moves:
 * only these few numbers per rank. */
double *par_stats_collect(const double *mine, int n, int on, double *tot, double *mx);

/* What par_output found (the same on every rank). */
typedef struct par_summary {
    int64_t ntris, nverts, nsegs;      /* the whole mesh as written */
    double min_angle, max_area;        /* over all triangles (with --stats or -V only; else 0) */
    uint64_t hash;                     /* this rank's share of the mesh hash (--stats; else 0) */
    int32_t nshared;                   /* this rank's vertices another rank also holds */
    double number_s, check_s, write_s; /* seconds (this rank) in each step */
} par_summary;

/* Collective.  The common end of ./pcdm and ./pbw once every rank holds its part (local):
 * the interface check (par_check_interfaces_open) and the parts' area sum against the domain's
 * (validate_area_net; both always, a failure fails every rank), par_number, the distributed
 * check when o->check (its summary line printed by rank 0), then par_write_parts (nothing is
 * written when the check failed).  tsub: each triangle's subdomain (local->ntris entries, NULL
 * or not on every rank alike), written as VTU cell data; topen: the part's open edges from the
 * mesher's mask (mesh_take_flat's, or NULL), which saves the vertex rows; dom: as
 * par_area_agrees.  Returns 0, or 1 on every rank (messages printed by rank 0).  local may be
 * changed by the test-only fault of par_check_parts. */
int par_output_sub(const par_opts *o, const pslg *in, const double *dom, mesh_flat *local,
                   const uint8_t *artificial, const int32_t *tsub, const uint8_t *topen,
                   par_summary *sum);

#endif
