/* run: the one driver -- how a mesh is made, written once for ./mesh, ./pcdm, ./pbw and the
 * library (pcdm_triangulate, pcdm_triangulate_par).
 *
 * A job says what is asked: the input (a path, or arrays the library was given), the bounds as
 * the user states them, the size rules, the outputs, and the method (sequential, PCDM or PBW)
 * with its parallel settings.  Its stages, in order (run.c lists them in detail):
 *   load     read the input (or -r's mesh), check it (crossing segments split, or refused with
 *            --strict; -c's hull), apply Triangle's boundary-marker rules, load the size rules;
 *   bounds   the bounds as one value (bounds/bounds.h; the one place the angle margin is added);
 *   mesh     sequentially (seq/), by PCDM (pcdm/) or by PBW (pbw/);
 *   verdict  met, the Steiner limit, or cannot meet the bounds: one status, one message each;
 *   check    the validator (--check), the bounds left out when they were not met;
 *   write    the files asked for (programs) or the arrays (library);
 *   exit     the exit status (0, 1, 3) or the library's code.
 * The programs' mains are their option tables and one call (run_mesh, run_par_main); the
 * library fills a job from its arrays and calls the same stages, printing nothing.
 *
 * Layer: above pcdm/ and pbw/ (it calls both), below api/ and apps/.  Collective = every rank
 * of rt_app_comm() calls it; Local otherwise.
 */
#ifndef RUN_H
#define RUN_H

#include <stddef.h>
#include <stdint.h>

#include "base/pfor.h"
#include "bounds/bounds.h"
#include "bounds/sizefield.h"
#include "decomp/decomp.h"
#include "geom/pslg.h"
#include "par/par.h"
#include "par/pout.h"
#include "seq/mesh.h"

/* How the mesh is made. */
typedef enum run_method { RUN_SEQ, RUN_PCDM, RUN_PBW } run_method;

/* The verdict on a refined mesh (one status; one message each, run_verdict_message). */
typedef enum run_verdict {
    RUN_MET = 0, /* every triangle meets the bounds, or its small angle is forced by the input */
    RUN_STEINER, /* the Steiner limit stopped refinement: conforming, outside the bounds (exit 3) */
    RUN_UNMET    /* refinement cannot reach the bounds: exit 1, the mesh written only with
                    --write-partial (the library: no mesh) */
} run_verdict;

/* The Delaunay triangulation of the input's vertices, made on a thread of its own while the rest
 * of the input is checked (the parallel programs' rank 0, whose decomposition starts from it:
 * run_ahead.c).  Owned by the job; run_par_load joins and frees it once the decomposition is
 * made or has failed. */
typedef struct run_dt_ahead {
    int32_t n;
    double *xy;          /* the n points it triangulates, a copy taken before the check goes on */
    mesh m;              /* mesh_build_points' triangulation, once joined */
    int32_t *dup;        /* its duplicate map */
    int rc;              /* mesh_build_points' status */
    const uint8_t *cpus; /* where the thread may run (mesh_thread_spread) */
    int started, joined;
    pthread_t thr;
} run_dt_ahead;

/* A job.  o is the request as the front end (apps/cli.h) or the library fills it; the rest is
 * the driver's. */
typedef struct run_job {
    run_method method;
    par_opts o;   /* input, bounds as stated, outputs asked for, parallel settings */
    int lens;     /* ./mesh --lens: diametral lenses */
    int cdt_only; /* ./mesh --cdt-only: no refinement, no bounds */
    /* the library's: the input as arrays already copied into a pslg, not yet checked (the job
     * takes it over: run_load moves it out); NULL: read o.input */
    pslg *given;
    int lib; /* 1: the library: print nothing, write no file; the message in msg */
    /* the size rules of -r's .area and --size (run_load; freed by run_job_free) */
    size_field sizes;
    /* the size rule the library was given (NULL: none), shown the caller's coordinates */
    bounds_size_fn user_size;
    void *user_size_ctx;
    int user_scale_exp; /* set by the driver: the scale its wrapper undoes */
    mesh_bounds bounds; /* the bounds stage's value (run_bounds) */
    double read_s;      /* parallel: wall seconds this rank spent reading and checking the input */
    /* the parallel programs: the domain's area, computed on rank 0 while it decomposes
     * (run_par_load starts it; the area check after meshing takes it) */
    par_dom_ahead dom_ahead;
    /* set by the driver before run_load: called once, as soon as the input's vertices are read
     * (before its segments are parsed; their coordinates as in the file), or between
     * pslg_check_start and pslg_check_finish for an input not read from a file or with -r
     * (in their working scale); run_load clears it (run_dt_ahead_start) */
    void (*vertices_ready)(struct run_job *j, const pslg *g);
    run_dt_ahead dt_ahead;
    /* rank 0: the CPUs the ranks of its host are bound to, which its threads ahead (the area,
     * the triangulation) may use while those ranks wait (run_ahead_host_cpus) */
    uint8_t host_cpus[MESH_HOST_CPUS];
    /* set by run_par_main before run_par_load: the input and the decomposition received into
     * blocks the host's ranks share (shared: run_par.c's, released by run_par_main; without
     * host_share, private copies the caller frees as always) */
    int host_share;
    struct run_shared *shared;
    /* out */
    run_verdict verdict;
    int64_t unmet;          /* triangles outside the bounds, not forced (all ranks) */
    int64_t refused;        /* refused splits (all ranks) */
    int64_t forced;         /* ./mesh: triangles below the angle bound forced by the input */
    char msg[1200];         /* the library: the failure's or the Steiner limit's message */
    int check_ok;           /* o.check: 1 iff the validator passed the mesh (run_mesh_flat) */
    validate_report report; /* o.check: the validator's report */
} run_job;

/* Local (run_ahead.c, the parallel library only).  start: a thread begins the Delaunay
 * triangulation of g's vertices (copied first, in their working scale: pslg_vertices_scaled; g
 * may change afterwards).  take: joins it and,
 * when it succeeded on exactly g's vertices (count and coordinates bit for bit), returns it for
 * mesh_build_cdt_from_points (the caller may take m and dup, leaving them empty and NULL); else
 * frees it and returns NULL.  free: joins and frees whatever is left (safe on a struct that
 * never started, and more than once). */
void run_dt_ahead_start(run_job *j, const pslg *g);
/* Collective (run_ahead.c).  Fills j->host_cpus on the first rank of each host (the union of
 * the affinity masks of the ranks there); all 0 at one rank (the thread stays in the rank's). */
void run_ahead_host_cpus(run_job *j);
run_dt_ahead *run_dt_ahead_take(run_dt_ahead *a, const pslg *g);
void run_dt_ahead_free(run_dt_ahead *a);

/* Local.  A job for method with the options o (copied); nothing else set. */
void run_job_init(run_job *j, run_method method, const par_opts *o);

/* Local.  Frees what the stages left in j (the size rules). */
void run_job_free(run_job *j);

/* ---- stages (run.c) ------------------------------------------------------------------- */

/* Local.  The load stage: for the programs first checks that every output's folder takes new
 * files (io/oset.h: meshio_probe), then reads o.input (-r: as a mesh to refine) or takes
 * j->given, checks it
 * (pslg_check_ex: crossing segments split unless --strict, -c's hull; warnings only when
 * quiet is 0), applies Triangle's boundary-marker rules (pslg_boundary_markers) and, with
 * sizes set, loads -r's .area and --size into j->sizes.  Returns 0 (*g the caller's), or -1
 * with "FILE:LINE: problem" in err (*g holds nothing). */
int run_load(run_job *j, pslg *g, int quiet, int sizes, char *err, size_t errlen);
/* Local.  run_load's last step alone, for ranks that received g instead of reading it: loads
 * -r's .area and --size into j->sizes (in g's working scale).  Returns 0, or -1 with the
 * message in err. */
int run_load_sizes(run_job *j, const pslg *g, char *err, size_t errlen);

/* Local.  The bounds stage: the job's bounds as one value (bounds_make), with the region
 * bounds and the size rule (j->sizes, or the library's callback through a wrapper that shows
 * it the caller's coordinates; g's scale); kept in j->bounds too. */
mesh_bounds run_bounds(run_job *j, const pslg *g);

/* Local.  The verdict: limit_hit: the Steiner limit stopped refinement (on some rank); unmet:
 * triangles outside the bounds not forced by the input (over all ranks). */
run_verdict run_verdict_of(int limit_hit, int64_t unmet);

/* Local.  The verdict's message (none for RUN_MET: empty), in one text for every mesher:
 * prefix is "PROG: INPUT: " for the programs, "" for the library, which names the angle bound
 * min_angle instead of -q. */
void run_verdict_message(const run_job *j, const char *prefix, char *buf, size_t len);

/* Local.  The exit status of a program: 1 when the bounds cannot be met (even when the mesh
 * was written with --write-partial), else rc when not 0, else 3 for the Steiner limit, else 0. */
int run_exit_status(run_verdict v, int rc);

/* Local.  What --check holds the mesh to, derived from the bounds (j->bounds, run_bounds): the
 * angle as asked (no margin), the area and the region bounds, or none when they were not met
 * (the Steiner limit, --write-partial, --cdt-only). */
void run_check_bounds(const run_job *j, double *min_angle, double *max_area, int *region_area);

/* ---- the sequential driver (run_seq.c) -------------------------------------------------- */

/* Local.  ./mesh: every stage for j (RUN_SEQ), printing as ./mesh does; returns the exit
 * status. */
int run_mesh(run_job *j);

/* Local.  The library's sequential call: the stages up to the verdict, then the mesh in flat
 * form into *f (the caller's: mesh_flat_free; region labels kept only with -A) and g's scale
 * in *scale_exp; with o.check, the check stage too (j->check_ok, j->report).  Returns 0 (met or
 * the Steiner limit: j->verdict), 1 for bad input, 2 when the bounds cannot be met (no mesh);
 * j->msg says why. */
int run_mesh_flat(run_job *j, mesh_flat *f, int *scale_exp);

/* ---- the parallel driver (run_par.c) ---------------------------------------------------- */

/* Codes of a failed parallel stage (the same on every rank); the library maps them to its own. */
enum { RUN_FINPUT = 1, RUN_FUNMET, RUN_FINVAL, RUN_FMESH };

/* This rank's part of a parallel mesh (run_par_mesh), local numbering. */
typedef struct run_part {
    mesh_flat local;        /* its triangles, their vertices and subsegments */
    uint8_t *artificial;    /* pcdm: per subsegment, 1 for an interface edge (NULL: none) */
    uint8_t *topen;         /* the mesher's open-edge mask (par_output_sub; may be NULL) */
    int32_t *tsub;          /* pcdm with --vtk: each triangle's subdomain (else NULL) */
    int32_t rounds;         /* pcdm: the refinement's rounds (0: --async) */
    long long iface_remote; /* pcdm: interface pieces left encroached (all ranks) */
    double t0, c0, mesh_s;  /* the mesh stage's start (wall-clock s), CPU s then, its span */
} run_part;

struct run_stats;

/* Collective.  Agreement on failure: code (0: none) and msg on this rank; returns 0 when no
 * rank failed, else the lowest failing rank's code on every rank, its message in j->msg
 * (printed by rank 0 unless j->lib). */
int run_agree(run_job *j, int code, const char *msg);

/* Collective.  Stage 1 for a parallel job (the runtime up): every rank loads the input
 * (run_load; the size rules unless j->lib) and builds the same decomposition for the ranks
 * (automatic, or --cuts; --write-cuts), compared across the ranks.  Returns 0 (*in and *d the
 * caller's), or a RUN_F* code on every rank with the message agreed (in, d and the job freed). */
int run_par_load(run_job *j, pslg *in, pcdm_decomp *d);

/* Collective.  Stages 2 to 4 for a parallel job: the bounds, the mesh by j->method (pcdm_part_*
 * or pbw_mesh; the handlers registered), the verdict reduced over the ranks (its message printed
 * by rank 0 unless j->lib) and, for PCDM, the interfaces' Delaunay property.  Fills *p (free
 * with run_part_free) and the per-rank statistics st.  Returns 0 (a mesh to write: met, the
 * Steiner limit, or --write-partial), or a RUN_F* code on every rank (j->msg).  PCDM frees d's
 * triangles once the subdomains are built from them (pcdm_decomp_drop_triangles). */
int run_par_mesh(run_job *j, const pslg *in, pcdm_decomp *d, run_part *p, struct run_stats *st);

/* Local. */
void run_part_free(run_part *p);

/* Collective over MPI_COMM_WORLD.  ./pcdm and ./pbw: start-up (runtime, the command line read
 * by parse with ctx, the method's handlers), every stage for the method, the statistics;
 * returns the exit status (the same on every rank; the runtime finalised). */
int run_par_main(int argc, char **argv, run_method method, par_parse_fn parse, const void *ctx);

#endif
