/* pcdm.h: the public interface of libpcdm -- quality triangulation in one call, sequential or
 * parallel (Chew, Chrisochoides, Sukup, "Parallel Constrained Delaunay Meshing", TR-97-17).
 * This header is the sequential half and needs no MPI; the parallel call is in pcdm_par.h,
 * which includes this one and <mpi.h>.
 *
 * In the spirit of Triangle's triangulate(): give a planar straight-line graph (points,
 * segments with boundary markers, holes, regions, point attributes) and the bounds, get back a
 * conforming constrained Delaunay mesh whose triangles meet them.  pcdm_triangulate meshes on
 * the calling thread (Ruppert/Chew refinement); pcdm_triangulate_par is Collective over a
 * communicator the caller gives (PCDM: a decomposition, every rank refines its subdomains) and
 * leaves every rank with its own part in global numbering, or the whole mesh on one rank.
 *
 * Contracts.  Every array in pcdm_input is borrowed (read only, for the duration of the call).
 * Every array in pcdm_mesh is allocated by the library and owned by the caller, who frees them
 * all with pcdm_mesh_free.  The library never prints and never exits: every failure returns a
 * nonzero PCDM_E* code with a message in the pcdm_status.  Indices are 0-based.  Coordinates
 * are the caller's: the meshers scale them internally by a power of two (exactly), and every
 * coordinate the library returns or shows the size callback is in the caller's units.
 * Out of memory is the one exception: the allocation funnel aborts the process.
 *
 * Link with `pkg-config --cflags --libs pcdm` (the whole library: MPI, METIS and pthreads), or,
 * for pcdm_triangulate alone, `pkg-config --cflags --libs pcdm-threads` (libpcdm_threads: METIS
 * and pthreads, no MPI; pcdm_options.threads on every core of one machine) or `pkg-config
 * --cflags --libs pcdm-seq` (libpcdm_seq: neither MPI nor METIS; no threads).
 */
#ifndef PCDM_PUBLIC_H
#define PCDM_PUBLIC_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PCDM_VERSION_MAJOR 0
#define PCDM_VERSION_MINOR 15
#define PCDM_VERSION_PATCH 0

/* Local.  The version string ("MAJOR.MINOR.PATCH" of the macros above: the one place the
 * project states its version; the programs print it for --version, the Makefile names the
 * shared library and pcdm.pc after it). */
const char *pcdm_version(void);

/* Return codes (pcdm_status.code). */
enum {
    PCDM_OK = 0,
    PCDM_EINVAL = 1,   /* bad argument (NULL pointer, an option out of range) */
    PCDM_EINPUT = 2,   /* bad input geometry (message names the point or segment) */
    PCDM_ESTEINER = 3, /* the Steiner limit stopped refinement before the bounds were met: the
                        * mesh is returned (conforming, valid, coarser than asked) */
    PCDM_EUNMET = 4,   /* the bounds cannot be met (features below the precision of the
                        * coordinates, a region too thin, an angle bound refinement cannot
                        * reach): no mesh is returned */
    PCDM_EMPI = 5,     /* MPI is not initialised (or lacks MPI_THREAD_FUNNELED), or an MPI call
                        * failed */
    PCDM_EBUSY = 6,    /* the parallel runtime is already in use in this process */
    PCDM_EMESH = 7,    /* the mesher failed (a bug: please report the message) */
    PCDM_ENOMEM = 8    /* out of memory: the message says how much more was asked; every block
                        * the call took is given back.  Returned by the calls on the caller's
                        * thread (pcdm_triangulate with threads 0); the threaded and parallel
                        * calls end the program with that message instead */
};

typedef struct pcdm_status {
    int code;          /* PCDM_OK or a PCDM_E* code (also the functions' return value) */
    char message[512]; /* "" or one line saying what went wrong */
} pcdm_status;

/* The PSLG to mesh.  Points: npoints, points[2i], points[2i+1].  pointmarkers (npoints, may be
 * NULL: 0), pointattr (npointattr per point, may be NULL when npointattr is 0).  Segments:
 * segments[2s], segments[2s+1] are point indices; segmentmarkers (may be NULL: 0).  With no
 * segments, or with pcdm_options.convex_hull, the domain is the convex hull of the points (but
 * the holes).  Holes: nholes points, each inside a region to remove (holes[2h], holes[2h+1]).
 * Regions: nregions records of four doubles (x, y, attribute, maximum area), as in Triangle's
 * .poly.  The input is prepared as ./mesh, ./pcdm and ./pbw prepare a .poly (they share one
 * driver): duplicate points are merged and repeated segments dropped (silently); a point inside
 * a segment splits it; crossing segments are split at a new point at their (rounded)
 * intersection, shared by every segment through it, and collinear overlaps become the pieces of
 * their union (a piece covered twice keeps the earlier segment's marker).  Boundary markers
 * follow Triangle's rules: a segment with marker 0 on the domain's boundary gets 1, a point
 * with marker 0 takes the nonzero marker of a segment it lies on, a new point on a segment that
 * segment's marker, other new points 0.  The mesh returned is the one ./mesh writes for the
 * same input and bounds (the same points, markers and triangles, in the same order). */
typedef struct pcdm_input {
    int32_t npoints;
    const double *points;
    const int32_t *pointmarkers;
    int npointattr;
    const double *pointattr;
    int32_t nsegments;
    const int32_t *segments;
    const int32_t *segmentmarkers;
    int32_t nholes;
    const double *holes;
    int32_t nregions;
    const double *regions;
} pcdm_input;

/* A caller's size rule, Triangle's triunsuitable without recompiling: called with the
 * counter-clockwise triangle's corners (caller's coordinates) and its area; return nonzero if
 * the triangle is too big (it is then split).  Must be a pure function of its arguments and
 * thread-safe, and in the parallel call the same function on every rank. */
typedef int (*pcdm_unsuitable_fn)(void *ctx, const double *const corner[3], double area);

/* The parallel meshers (pcdm_options.method).  PCDM (TR-97-17 section 3): subdomains with
 * artificial interface segments, each refined by its rank, interface splits by remote request.
 * PBW (section 2): one distributed mesh refined by parallel Bowyer-Watson with remote cavity
 * expansion and locks (no size callback). */
enum { PCDM_METHOD_PCDM = 0, PCDM_METHOD_PBW = 1 };

/* pcdm_options: the bounds and switches of both calls; the fields marked
 * "pcdm_triangulate_par only" are read by the parallel call (pcdm_par.h) alone. */
typedef struct pcdm_options {
    double min_angle;    /* degrees: no triangle angle below it (0: none; default 20.7; at
                          * most about 34 is reached on every input) */
    double max_area;     /* no triangle larger (0: no bound; default 0) */
    int64_t max_steiner; /* at most this many points added (< 0: no limit; default -1); in
                          * the parallel call the budget of all ranks together */
    int circumcenters;   /* 1: circumcenters only (Triangle's default); 0: off-centers where
                          * closer (fewer points; default 0) */
    pcdm_unsuitable_fn unsuitable; /* NULL: none (default) */
    void *unsuitable_ctx;
    int region_attributes; /* 1: triangleattr = each triangle's region's attribute (0 in none;
                            * Triangle's -A); default 0.  pcdm_triangulate only for now: the
                            * parallel call refuses it (PCDM_EINVAL) */
    int region_areas;      /* 1: honour the regions' area bounds (Triangle's -a without a
                            * number; the smaller of it and max_area wins); default 0; as
                            * region_attributes, pcdm_triangulate only */
    /* pcdm_triangulate_par only */
    int method;         /* PCDM_METHOD_PCDM (default) or PCDM_METHOD_PBW */
    int32_t subdomains; /* subdomains of the decomposition (0: ./pcdm's default: 16, or ranks
                         * x threads where that is more, fewer on a small mesh; with
                         * PCDM_METHOD_PBW one per rank; default 0); also pcdm_triangulate's
                         * with threads >= 1 */
    int root;           /* < 0: every rank keeps its part (default -1); >= 0: the whole mesh
                         * is collected on this rank (others get an empty mesh) */
    /* both calls */
    int convex_hull; /* 1: enclose the convex hull of the points with segments (Triangle's -c):
                      * new segments on the hull's edges not covered by input segments, cut at
                      * every point on them, marker 1; the domain is everything inside the
                      * hull but the holes (default 0: the domain the segments enclose) */
    /* pcdm_triangulate only */
    int no_refine; /* 1: the constrained Delaunay triangulation of the input alone, no Steiner
                    * points, the bounds ignored (Triangle without -q, -a and -u); default 0 */
    int lenses;    /* 1: a subsegment is encroached by a point in its diametral lens (as
                    * Triangle: fewer points on segments); 0: its diametral circle (default) */
    /* both calls */
    int threads; /* pcdm_triangulate_par (PCDM): worker threads per rank refining its subdomains
                  * at once (0 or 1: the calling thread alone; default 0); the mesh is the same
                  * for any count.  pcdm_triangulate: 0 (default) is the sequential mesher
                  * (./mesh's mesh); T >= 1 is ./pcdm's subdomain mesher on T worker threads of
                  * this process (./pcdm --threads T's mesh, the same for every T, given
                  * subdomains; not with lenses, region_attributes, region_areas: PCDM_EINVAL;
                  * with no_refine the sequential CDT).  It needs libpcdm_threads (no MPI) or
                  * libpcdm with MPI initialised (else PCDM_EMPI); libpcdm_seq refuses it
                  * (PCDM_EINVAL).  Threaded calls in one process take turns (one runtime). */
} pcdm_options;

/* Local.  Fills *o with the defaults above. */
void pcdm_options_default(pcdm_options *o);

/* A mesh (or one rank's part of it).  Points: npoints, points[2i], points[2i+1];
 * pointmarkers (npoints); pointattr (npointattr per point, the input's point attributes
 * linearly interpolated on the new points as Triangle does; NULL with npointattr 0 when the
 * input has none, and for now in the parallel call).  The input's points come
 * first, in their order (after merging duplicates), then the Steiner points.  Triangles:
 * triangles[3t..3t+2], counter-clockwise; triangleattr (one per triangle: its region's
 * attribute, or NULL when the mesher does not provide them).  Segments: the subsegments of the
 * input's segments (both endpoints), with segmentmarkers.
 * A whole mesh may list input points no triangle uses (inside a hole, or merged duplicates).
 * A rank's part (pcdm_triangulate_par, root < 0): points are the vertices its triangles use
 * (a vertex on the boundary between two parts appears in both; rank 0 lists every input point
 * first, numbers 0 .. ninput-1, whether its triangles use it or not), pointglobal[i] is point i's
 * number in the whole mesh, pointowned[i] is 1 on exactly one rank for each number (the input
 * points: rank 0); triangle t is number trianglefirst + t of the whole mesh; a segment shared
 * by two parts is listed by one; nglobal* count the whole mesh.  pointglobal and pointowned are
 * NULL for a whole mesh. */
typedef struct pcdm_mesh {
    int32_t npoints;
    double *points;
    int32_t *pointmarkers;
    int npointattr;
    double *pointattr;
    int32_t ntriangles;
    int32_t *triangles;
    double *triangleattr;
    int32_t nsegments;
    int32_t *segments;
    int32_t *segmentmarkers;
    /* parallel parts only */
    int64_t *pointglobal;
    uint8_t *pointowned;
    int64_t trianglefirst;
    int64_t nglobalpoints, nglobaltriangles, nglobalsegments;
} pcdm_mesh;

/* Local.  Frees every array of m and zeroes it (a zeroed or already freed m is fine). */
void pcdm_mesh_free(pcdm_mesh *m);

/* Local (no MPI needed but in libpcdm with threads >= 1).  Meshes in (the constrained Delaunay
 * triangulation, then Delaunay refinement to opt's bounds; opt NULL: the defaults; with
 * opt->threads >= 1 ./pcdm's subdomain mesher on worker threads, see pcdm_options).  out is
 * overwritten: on PCDM_OK and PCDM_ESTEINER it holds the mesh (free with pcdm_mesh_free), otherwise
 * nothing.  st may be NULL.  Returns st->code.  Thread-safe for distinct arguments (the callback's
 * own state aside). */
int pcdm_triangulate(const pcdm_input *in, const pcdm_options *opt, pcdm_mesh *out,
                     pcdm_status *st);

#ifdef __cplusplus
}
#endif

#endif
