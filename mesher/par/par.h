/* par: what ./pcdm and ./pbw share around their algorithms -- the command line's struct and
 * the settings a parallel mesher takes, the decomposition's agreement, collective error exits.
 * The end of both programs (numbering, output, --check, without a gather) is in par/pout.h;
 * start-up, loading and the stages are the driver's (run/run.h).
 *
 * Both programs are SPMD: every rank parses the same arguments and reads the same input file
 * (a shared file system is assumed, as with mpirun on one machine), so input errors are
 * detected identically on every rank; only rank 0 prints them, and every rank exits non-zero.
 * Errors found on one rank only go through par_fail_any(), a collective agreement.
 *
 * Collective = every rank of rt_app_comm() calls it; Local otherwise.
 */
#ifndef PAR_H
#define PAR_H

#include <stdint.h>
#include <stdio.h>

#include "bounds/bounds.h"
#include "check/validate.h"
#include "decomp/decomp.h"
#include "geom/pslg.h"
#include "io/meshio.h"

/* Longest output prefix a mesher accepts (bytes, the terminating zero included). */
#define PAR_NAME_MAX 1000

/* What the parallel meshers are told; filled by the programs' front end (apps/cli.h), which
 * owns the options' names, defaults and checks. */
typedef struct par_opts {
    const char *prog;             /* "pcdm" or "pbw" (for messages) */
    const char *input;            /* input .poly */
    double min_angle;             /* -q DEG (default 20.7) */
    double max_area;              /* -a AREA (0 = none) */
    int64_t max_steiner;          /* -S N (< 0: none) */
    const char *out_prefix;       /* -o PREFIX: PREFIX.node/.ele/.poly; without -o the front end
                                     points it at out_name (apps/cli.h) */
    char out_name[PAR_NAME_MAX];  /* Triangle's name when -o is not given: the input's name
                                     without its extension, then ".1" (-r: its number plus 1) */
    int no_node, no_ele, no_poly; /* -N, -E, -P: write no PREFIX.node, .ele, .poly */
    int write_partial;      /* --write-partial: write the mesh although it misses the bounds */
    const char *vtk;        /* --vtk FILE */
    int vtk_ascii;          /* --vtk-ascii: ASCII VTK instead of binary */
    const char *svg;        /* --svg FILE */
    int stats;              /* --stats */
    int check;              /* --check: validate every part where it lives (pout.h) */
    int progress;           /* --progress: progress lines on stderr */
    int32_t nsub;           /* --subdomains K (0 = ranks) */
    int32_t threads;        /* --threads T (pcdm only; 0/1: one): subdomain rounds on T workers */
    double imbalance;       /* --imbalance R (default 1) */
    const char *cuts;       /* --cuts FILE */
    const char *write_cuts; /* --write-cuts FILE */
    int phases;             /* --phases (pbw only) */
    int32_t inflight;       /* --inflight N (pbw only): distributed cavities in flight per rank
                               at most (0: the default, MAX_INFLIGHT) */
    int circumcenters;      /* --circumcenters: circumcenters only, no off-centers */
    int32_t poll_every;     /* --poll N: local work units between two services of incoming
                               RSRs (0: the program's default; 1: after every insertion, as
                               the paper) */
    uint64_t perturb;       /* --perturb SEED (0 = off; also env RT_PERTURB) */
    const char *net;        /* --net SPEC: the runtime's network model (rt_net_parse; NULL:
                               the environment's PCDM_NET, else off) */
    int deterministic;      /* --deterministic (pcdm only): the default, refinement in rounds
                               (accepted, changes nothing; refused with --async) */
    int async;              /* --async (pcdm only): the paper's asynchronous protocol, one mesh
                               per rank, the mesh depending on message timing; 0: refinement in
                               rounds, the same mesh for any ranks x threads and timing
                               (mesher/pcdm/pcdm_det.c) */
    const char *balance;    /* --balance static|dynamic (pcdm only; NULL: static) */
    /* Triangle's switches (issue 15); the same for all three meshers. */
    int region_attr;        /* -A: regional attributes carried into .ele (and VTK/Gmsh) */
    int region_area;        /* -a without a number: the .poly's per-region area bounds (with -r:
                               the .area file's per-triangle bounds) */
    int edges;              /* -e: write PREFIX.edge */
    int neighbors;          /* -n: write PREFIX.neigh */
    int order2;             /* -o2: quadratic triangles (six nodes each) */
    int refine;             /* -r: the input is a mesh (.node/.ele) to refine */
    int quiet;              /* -Q: nothing on stdout or stderr but errors */
    int verbose;            /* -V: more detail on stderr */
    int strict;             /* --strict: refuse crossing or overlapping segments */
    int convex_hull;        /* -c: enclose the convex hull with segments (pslg_enclose_hull) */
    const char *msh;        /* --msh FILE: Gmsh 4.1 output */
    const char *size_field; /* --size FILE: background mesh with a target edge length per
                               vertex */
} par_opts;

/* How a parallel mesher runs, apart from the bounds (bounds/bounds.h): what pbw_mesh and
 * pcdm_mesh take instead of the command line (par_config_of). */
typedef struct par_config {
    const char *prog;   /* "pcdm" or "pbw": the prefix of messages */
    const char *input;  /* the input's name, for messages (may be NULL) */
    int32_t poll_every; /* local work units between two services of incoming RSRs (0: the
                           mesher's default) */
    int32_t inflight;   /* pbw: distributed cavities in flight per rank at most (0: default) */
    int phases;         /* pbw: the data-parallel variant (two phases) */
    int deterministic;  /* pcdm: refinement in rounds, each subdomain its own mesh */
    int balance;        /* pcdm: 1: idle ranks take unstarted subdomains (implies rounds) */
    int threads;        /* pcdm: subdomain rounds on this many worker threads (> 1 implies
                         * rounds) */
    int regions;        /* label triangles with their regions (-A or --region-areas) */
    int progress;       /* progress lines on stderr (rank 0) */
} par_config;

/* Local.  The parallel settings of o. */
par_config par_config_of(const par_opts *o);

/* Collective.  -V: rank 0 prints what was read and decomposed and the bounds asked for. */
void par_verbose_input(const par_opts *o, const pslg *in, const pcdm_decomp *d, double read_s);

/* Collective.  -V: rank 0 prints the slowest rank's refinement seconds (mesh_s: this rank's),
 * the mesh made (ntris, nverts, min_angle over all ranks) and the output seconds. */
void par_verbose_result(const par_opts *o, double mesh_s, int64_t ntris, int64_t nverts,
                        double min_angle, double out_s);

/* Local.  The Triangle files o asks to leave out (-N, -E, -P), as MESHIO_SKIP_* bits. */
static inline unsigned par_skip_files(const par_opts *o) {
    return (o->no_node ? MESHIO_SKIP_NODE : 0u) | (o->no_ele ? MESHIO_SKIP_ELE : 0u) |
           (o->no_poly ? MESHIO_SKIP_POLY : 0u);
}

/* Local.  What the linear Triangle writer leaves out: par_skip_files, and with -o2 the .node and
 * .ele too (the quadratic writer, io/xwrite.h, writes those; once, not over the linear ones). */
static inline unsigned par_skip_linear(const par_opts *o) {
    return par_skip_files(o) | (o->order2 ? MESHIO_SKIP_NODE | MESHIO_SKIP_ELE : 0u);
}

/* Local.  How the parallel driver reads the command line (the front end lives above this
 * layer): called on every rank once the runtime is up, with the arguments MPI left, this rank's
 * number (only rank 0 may print) and ctx.  Fills *o; returns 0 to go on, or 1 when the program
 * must exit now with *status (0: --help printed; 2: usage error). */
typedef int (*par_parse_fn)(int argc, char **argv, int rank, const void *ctx, par_opts *o,
                            int *status);

/* Local.  1 iff o asks for --balance dynamic. */
static inline int par_balance_dynamic(const par_opts *o) {
    return o->balance && o->balance[0] == 'd';
}

/* Largest number of subdomains the driver lets the automatic decomposition attempt (every rank
 * computes it, on a coarse mesh of about 200 K triangles); more is refused with a clear
 * message. */
#define PAR_MAX_SUBDOMAINS 256
/* ./pcdm's default number of subdomains in rounds (see run_par.c's decompose): fixed, so the
 * default mesh is the same for any ranks x threads up to this many */
#define PAR_ROUNDS_SUBDOMAINS 16

/* Collective over rt_app_comm().  1 iff every rank read the same input: a hash of its
 * coordinates, segments, holes, regions and scaling is compared across the ranks. */
int par_input_agrees(const pslg *in);

/* Collective over rt_app_comm().  1 iff every rank holds the same decomposition (./pbw's ranks
 * build it alone, ./pcdm's receive rank 0's): a hash of what the meshers consume (the cut
 * geometry, the cuts' subdomains, the owners) is compared across the ranks.  Both checks are 1
 * at once on one rank. */
int par_decomp_agrees(const pcdm_decomp *d);

/* Collective.  Agreement on failure with a code: code (0: none) and msg (may be NULL) on this
 * rank; returns 0 when no rank failed, else the lowest failing rank's code on every rank, with
 * its message in out (outlen bytes; may be NULL).  Prints nothing. */
int par_agree(int code, const char *msg, char *out, size_t outlen);

/* Collective.  Agreement on failure: returns nonzero on every rank if local_fail is nonzero on
 * any rank; the first failing rank's message (msg, may be NULL) is printed by rank 0. */
int par_fail_any(int local_fail, const char *msg);

/* Local.  CPU seconds (user + system, all threads) this process has used so far.  The
 * "modelled" times of the benchmarks are built on it: unlike wall-clock busy time it does not
 * grow while a rank waits for a core, so with more ranks than cores the busiest rank's CPU
 * time still estimates what that rank would take on a core of its own. */
double par_cpu_seconds(void);

/* Local.  Peak resident set size of this process in bytes (getrusage). */
long par_peak_rss_bytes(void);

#endif
