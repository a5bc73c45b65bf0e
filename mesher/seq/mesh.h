/* mesh: the sequential mesher core -- triangle data structure, Bowyer-Watson insertion,
 * constrained Delaunay triangulation of a PSLG, and Ruppert/Chew Delaunay refinement, with the
 * hooks the parallel meshers (PCDM, PBW) need.
 *
 * DATA STRUCTURE (index based, pointer free; every index is an int32_t local index)
 *  - Vertex v: xy[2v], xy[2v+1]; vseg[v] = id of the original input segment a Steiner vertex
 *    was created on (-1 for input vertices and free Steiner vertices); vtri[v] = some live
 *    triangle incident to v (-1 if none).  Input vertices keep their input numbering
 *    (0 .. ninput-1); Steiner vertices follow.
 *  - Triangle t: vertices tv[3t+0..2], counter-clockwise.  Its three directed edges are named
 *    by the integer code e = 3t+j: edge j goes from tv[3t+j] (origin) to tv[3t+(j+1)%3]
 *    (destination); tv[3t+(j+2)%3] is its apex.  tn[e] is the code of the same edge seen from
 *    the neighbouring triangle (opposite direction), or -1 on the domain boundary, so stepping
 *    to the neighbour is one load and the neighbour's triangle is tn[e]/3.
 *  - tf[t]: bit j (j = 0, 1, 2) set iff edge 3t+j is a constraint edge (a subsegment); bit 3 is
 *    scratch (cavity / flood marks; always clear between calls); bit 4 means "in the refinement
 *    queue" (cleared whenever the slot is rewritten, so stale queue entries cost one byte);
 *    bits 5..7 (MESH_FENCE) belong to a caller that keeps more per triangle (PBW: the slot's
 *    role, non-zero while it is locked by a distributed cavity or is a tombstone): a cavity
 *    never enters or touches such a triangle, nor crosses an edge whose tn is below -1 (PBW:
 *    a link to another rank, in its side table); ./mesh sets neither.
 *  - A dead triangle has tv[3t] == MESH_DEAD and sits on a free list threaded through tn[3t];
 *    slots are reused first, so triangle ids stay dense and a triangle can be named across
 *    ranks by (rank, int32 index).  Ghost triangles (one vertex == MESH_GHOST, the vertex at
 *    infinity) exist only while the CDT is being built; a finished mesh has none.
 *  - Subsegments (constraint edges) carry metadata in a side table (a record per subsegment,
 *    found by hashing its vertex pair or its dyadic name): the original segment id, and the
 *    dyadic name (level j, index k): the subsegment is [k/2^j, (k+1)/2^j] of the original
 *    segment (a, b) in the parameter t of a + (b - a) t.  level == -1 marks a piece that is not
 *    dyadic (a segment cut at an input vertex lying on it, or a concentric-shell split).  The
 *    original segment's marker and "interface" flag (artificial boundary between PCDM
 *    subdomains) are kept per original segment.
 *  - Memory: 25 bytes per triangle slot plus 24 per vertex (about 0.5 vertex per triangle),
 *    plus the refinement queue (8 bytes per queued triangle) and the small subsegment table:
 *    measured peak resident size of ./mesh is about 42-46 bytes per triangle at 1M-10M
 *    triangles (arrays grow by doubling; untouched capacity is not resident).
 *  - Vertices not in any triangle (merged duplicates, vertices inside holes, or in regions
 *    dropped by mesh_keep_regions) stay in the vertex array with vtri == -1.
 *  - The struct is public for reading (PBW builds its distributed mesh from nv, xy, nt, tv,
 *    tn, tf); only the functions below may modify it.
 *
 * ALGORITHMS (details in the .c file headers)
 *  - Point location: remembering stochastic visibility walk from a hint, exact orient2d only.
 *  - Insertion: Bowyer-Watson; the cavity is the set of triangles whose circumcircle strictly
 *    contains the point (exact incircle) reachable from the containing triangle without
 *    crossing a constraint edge; the cavity is checked star-shaped (exact orient2d) before any
 *    write, then the point is joined to the cavity boundary reusing the dead slots.
 *  - CDT (cdt.c): BRIO + Hilbert ordered incremental Delaunay of the vertices, segments
 *    inserted by edge flips (Sloan 1993) and split at vertices lying exactly on them, then the
 *    exterior is eaten from the convex hull and from every hole point, stopping at segments.
 *  - Refinement (refine.c): Ruppert 1995 / Chew 1993 / Shewchuk 2002, see mesh_refine().
 *
 * All functions are Local (no communication).  A mesh is not thread-safe; one mesh per thread.
 * Errors: bugs abort with file and line; bad input returns -1 with a message; algorithm
 * outcomes are enums.
 */
#ifndef MESH_H
#define MESH_H

#include <stddef.h>
#include <stdint.h>

#include "geom/pslg.h"
#include "io/meshio.h"
#include "seq/rules.h"

#define MESH_GHOST (-1)  /* the vertex at infinity (only while building) */
#define MESH_DEAD (-2)   /* tv[3t] of a dead triangle */
#define MESH_FENCE 0xe0u /* tf bits a caller owns (see the data structure above) */

/* One subsegment record.  u -> v follows the direction of the original segment (u is nearer
 * its first endpoint). */
typedef struct mesh_subseg {
    int32_t u, v;
    int32_t seg;   /* original segment id */
    int32_t level; /* dyadic level j, or -1 if not a dyadic piece; -2 marks a free record */
    int64_t k;     /* dyadic index, 0 <= k < 2^j */
} mesh_subseg;

/* Refinement parameters (mesh_set_quality). */
typedef struct mesh_quality {
    double min_angle;    /* degrees; triangles with a smaller angle are split (0: none) */
    double max_area;     /* triangles with a larger area are split (0: no bound) */
    int64_t max_steiner; /* stop after this many Steiner vertices (< 0: no limit) */
    int offcenter;       /* 1: Ungor's off-centers instead of circumcenters when closer */
    int lens;            /* 1: diametral lenses instead of circles decide encroachment */
} mesh_quality;

/* Hooks for the parallel meshers (mesh_set_hooks).  on_split is called whenever an interface
 * subsegment is split by a local decision (not for splits requested through
 * mesh_split_subsegment_named): (seg, level, k) names the subsegment before the split; flags
 * has MESH_SPLIT_INTERFACE.  Interface segments must not pass through input vertices (their
 * pieces would not be dyadic: level -1, which no other rank can name).  poll is called every
 * poll_every insertions between two insertions, never inside one: it may call
 * mesh_split_subsegment_named on this mesh; if it returns non-zero, mesh_refine returns
 * MESH_REFINE_STOPPED (resumable). */
enum { MESH_SPLIT_INTERFACE = 1 };
typedef struct mesh_hooks {
    void (*on_split)(void *ctx, int32_t seg, int32_t level, int64_t k, unsigned flags);
    int (*poll)(void *ctx);
    int32_t poll_every; /* default 200 */
    void *ctx;
} mesh_hooks;

/* Counters, cumulative over the life of the mesh. */
typedef struct mesh_stats {
    int64_t inserted;      /* circumcenters / off-centers inserted */
    int64_t seg_splits;    /* subsegments split (all causes) */
    int64_t iface_splits;  /* of which interface subsegments split locally (on_split calls) */
    int64_t rejected;      /* Steiner points rejected because they encroach */
    int64_t blocked;       /* walks toward a Steiner point stopped by a constraint edge */
    int64_t skipped_small; /* bad triangles left alone: small angle forced by the input */
    int64_t failed;        /* insertions abandoned (not star-shaped / precision exhausted) */
    int64_t unresolved;    /* insertions and splits refused below the length floor (refine.c) */
    int64_t named_done, named_already, named_not_found; /* mesh_split_subsegment_named */
    int64_t polls;
} mesh_stats;

typedef struct mesh_refine_state mesh_refine_state; /* private to refine.c */

typedef struct mesh {
    /* vertices */
    int32_t nv, vcap, ninput;
    double *xy;
    int32_t *vseg, *vtri;
    int32_t *in_vmarker; /* ninput markers of the input vertices */
    /* triangles */
    int32_t nt, tcap;  /* slots in use (live + dead), capacity */
    int32_t nlive;     /* live triangles (ghosts included while building) */
    int32_t free_head; /* first dead slot, -1 if none */
    int32_t *tv, *tn;
    uint8_t *tf;
    /* original segments */
    int32_t nseg, segcap;
    int32_t *seg;               /* 2 * nseg vertex ids */
    int32_t *smarker;           /* nseg */
    uint8_t *siface;            /* nseg: 1 if an interface segment */
    int32_t *seg_nsub;          /* nseg: live subsegments of each original segment */
    int32_t *inc_off, *inc_seg; /* CSR: original segments incident to each input vertex */
    uint8_t *corner;            /* ninput: 1 if two segments meet there at < 60 degrees */
    int has_corners;
    int scale_exp; /* xy = input coordinates * 2^scale_exp (pslg.scale_exp; areas by 2^2e) */
    /* input regions (mesh_set_regions; all NULL and 0 until then) */
    int32_t nregion;
    int32_t *treg;    /* per triangle slot: the input region it lies in (-1: none) */
    double *reg_attr; /* nregion regional attributes */
    double *reg_area; /* nregion area bounds in working units (0: none, or not asked) */
    /* subsegment side table */
    mesh_subseg *ss;
    int32_t nss, sscap, ss_free, ss_live;
    int32_t *hpair, *hname; /* open-addressing tables of record ids (-1 empty) */
    uint32_t hcap;
    /* scratch for cavities and walks */
    int32_t *cav, ncav, cavcap;
    struct mesh_bedge *bnd;
    int32_t nbnd, bndcap;
    int32_t *stk, nstk, stkcap;
    int32_t *newt, nnewt, newtcap;
    uint64_t rng;
    int32_t last; /* remembered triangle for walks */
    /* refinement */
    mesh_quality q;
    /* a caller's size rule (mesh_set_size_rule; NULL: none) */
    int (*size_rule)(void *ctx, const double *const p[3], double area);
    void *size_rule_ctx;
    mesh_hooks hooks;
    mesh_stats stats;
    mesh_refine_state *rf;
} mesh;

/* ---- life cycle ---------------------------------------------------------------------- */

/* Empty mesh (calls geom_init()).  Pair with mesh_free. */
void mesh_init(mesh *m);
void mesh_free(mesh *m);

/* Builds the constrained Delaunay triangulation of g (which pslg_check has normalised):
 * Delaunay triangulation of all vertices, every segment inserted (split where it passes
 * exactly through a vertex), then triangles outside the domain removed: those reachable from
 * the convex hull and from each hole point without crossing a segment.  If g has no segments,
 * its convex hull is the domain and the hull edges become segments (marker 1).  iface (nsegs
 * flags, may be NULL) marks the interface segments (PCDM).  Regions: mesh_set_regions.
 * m must be empty (fresh from mesh_init).  Returns 0, or -1 with "FILE: problem" in err (e.g.
 * all vertices collinear, empty domain). */
int mesh_build_cdt(mesh *m, const pslg *g, const uint8_t *iface, char *err, size_t errlen);

/* mesh_build_cdt in two halves, so that the first can run while the input is still being
 * checked (the parallel programs' rank 0 does).  mesh_build_points: the Delaunay triangulation
 * of the n points xy (copied) in the empty m, a point equal to an earlier one left out (*dup:
 * n entries, the point each one repeats, or itself; the caller's).  Touches nothing but m and
 * *dup, so it may run on any thread once geom_init has run.  Returns 0, or -1 with the message
 * (fewer than 3 points, all collinear) and m to be freed.  mesh_build_cdt_from_points: the rest
 * for g, whose vertices must be those n points exactly (same number and coordinates, bit for
 * bit): then m ends as mesh_build_cdt(m, g, iface) makes it, and the same messages.  Takes dup
 * (freed). */
int mesh_build_points(mesh *m, int32_t n, const double *xy, int32_t **dup, char *err,
                      size_t errlen);
int mesh_build_cdt_from_points(mesh *m, int32_t *dup, const pslg *g, const uint8_t *iface,
                               char *err, size_t errlen);

/* The mesh of g's vertices made of the ntri triangles tri (3 vertex numbers each, counter-
 * clockwise), which must be a constrained Delaunay triangulation of g's segments over its domain
 * (as a subdomain cut from a larger CDT is): the same invariants as mesh_build_cdt's, without
 * the search.  Checked, not trusted: a triangle that is not counter-clockwise (exact), an edge
 * in more than two triangles, a segment that is no edge, a boundary edge that is no segment is
 * an error.  Every segment must be one edge (one subsegment record, dyadic level 0); iface as in
 * mesh_build_cdt.  m must be empty.  Returns 0, or -1 with a message in err (m then holds
 * partial state: mesh_free it). */
int mesh_build_from_triangles(mesh *m, const pslg *g, const uint8_t *iface, int32_t ntri,
                              const int32_t *tri, char *err, size_t errlen);

/* Delaunay triangulation of n points (xy: 2n doubles); the convex hull edges become segments
 * (marker 1).  Duplicated points are left isolated (vtri == -1).  Returns 0 or -1 + message. */
int mesh_build_delaunay(mesh *m, int32_t n, const double *xy, char *err, size_t errlen);

/* ---- regions (PCDM: keep one rank's subdomains) -------------------------------------- */

/* Labels the live triangles by region: the connected components under adjacency across
 * non-constraint edges.  label must hold m->nt entries; dead slots get -1.  Returns the number
 * of regions (labels 0 .. n-1). */
int32_t mesh_label_regions(const mesh *m, int32_t *label);

/* Deletes every live triangle t with keep[label[t]] == 0 (label from mesh_label_regions),
 * then drops subsegment records no longer on any triangle. */
void mesh_keep_regions(mesh *m, const int32_t *label, const uint8_t *keep);

/* ---- input regions (Triangle's regional attributes and area constraints) -------------- */

/* Labels every live triangle with the input region it lies in (g->regions, already scaled by
 * pslg_check; region i is the set of triangles reachable from the triangle containing region
 * point i without crossing an input segment).  Segments nreal .. nseg-1 are artificial (a
 * decomposition's interface edges, pcdm_decomp's segments from nboundary on) and are crossed,
 * so the parallel meshers label their coarse CDT whole, before keeping their subdomains;
 * ./mesh passes m->nseg.  Where two region
 * points fall in the same such component the later one in the file wins; triangles in no
 * region get -1 (attribute 0, no own bound).  A region point outside the domain (or in a
 * hole) or exactly on a segment (endpoints included) marks nothing; location is exact
 * (mesh_locate, orient2d).  use_area: keep the regions' positive maximum areas as per-triangle
 * bounds (mesh_refine then splits a triangle above min(q.max_area, its region's bound)).
 * Afterwards every new triangle inherits the region of the cavity triangle it replaces on the
 * same side (a cavity never crosses a segment, and a split segment's two sides keep theirs),
 * so labels stay exact through refinement.  Local.  Call once, after mesh_build_cdt. */
void mesh_set_regions(mesh *m, const pslg *g, int use_area, int32_t nreal);

/* The area bound of live triangle t in working units: mesh_rules_area_bound of the global
 * bound (working units) and t's region's, 0 if none. */
static inline double mesh_tri_area_bound(const mesh *m, int32_t t, double global) {
    if (!m->treg || m->treg[t] < 0) return global; /* on every quality test: inline */
    return mesh_rules_area_bound(global, m->reg_area[m->treg[t]]);
}

/* ---- point location and insertion ---------------------------------------------------- */

/* A live triangle containing p (possibly on its boundary), walking from hint (any triangle id,
 * or -1); -1 if p is outside the triangulated domain.  Walks never cross constraint edges
 * when they can avoid it; the answer is exact. */
int32_t mesh_locate(mesh *m, const double p[2], int32_t hint);

typedef enum {
    MESH_INSERTED,      /* *vout is the new vertex */
    MESH_DUPLICATE,     /* p coincides with vertex *vout; nothing changed */
    MESH_OUTSIDE,       /* p is outside the domain; nothing changed */
    MESH_ON_CONSTRAINT, /* p lies exactly on (or beyond, not visible across) a constraint edge */
    MESH_FAILED         /* cavity not star-shaped (cannot happen with exact predicates) */
} mesh_insert_result;

/* Inserts a free vertex at p (Bowyer-Watson with constrained cavity).  Local. */
mesh_insert_result mesh_insert_point(mesh *m, const double p[2], int32_t hint, int32_t *vout);

/* ---- refinement ------------------------------------------------------------------------ */

/* Sets the quality bounds; the next mesh_refine scans the whole mesh. */
void mesh_set_quality(mesh *m, const mesh_quality *q);

/* A caller's size rule (mesh_rules.unsuitable, Triangle's triunsuitable; e.g.
 * bounds/sizefield.h's size_field_unsuitable), kept across mesh_set_quality; fn NULL: none.  The
 * rule sees the mesh's internal coordinates (m->scale_exp). */
void mesh_set_size_rule(mesh *m, int (*fn)(void *ctx, const double *const p[3], double area),
                        void *ctx);
/* Local.  Computes the length floor (no refinement makes an edge shorter; see refine.c) from the
 * mesh as it is now and keeps it for every later mesh_refine, instead of computing it from the
 * mesh mesh_refine first sees.  The parallel meshers call it on the whole coarse CDT, which every
 * rank builds alike, before keeping their own subdomains: the floor then depends on the input
 * (its extent and smallest features), not on which part a rank holds, as ./mesh's does. */
void mesh_fix_length_floor(mesh *m);
/* The same with a floor computed elsewhere (mesh_rules_length_floor2 of the mesh the floor is to
 * follow; > 0): a subdomain built alone takes the one of the input's CDT. */
void mesh_set_length_floor(mesh *m, double floor2);
void mesh_set_hooks(mesh *m, const mesh_hooks *h);
/* Local.  A caller's size rule (mesh_rules.unsuitable, rules.h: Triangle's triunsuitable; NULL:
 * none) for every later refinement, kept across mesh_set_quality: fn sees the mesh's working
 * coordinates (the input's times 2^scale_exp; the library, mesher/api, unscales them for its
 * user).  Must be pure and thread-safe; ctx must outlive the refinement. */
void mesh_set_size_rule(mesh *m, int (*fn)(void *ctx, const double *const p[3], double area),
                        void *ctx);

typedef enum {
    MESH_REFINE_DONE,          /* no bad triangle and no encroached subsegment left */
    MESH_REFINE_STEINER_LIMIT, /* max_steiner reached */
    MESH_REFINE_STOPPED,       /* the poll hook asked to stop */
    MESH_REFINE_UNRESOLVED     /* gave up: too many splits refused below the length floor
                                * (features below the coordinates' precision, or a bound the
                                * refinement cannot reach); the bounds are not met */
} mesh_refine_result;

/* Ruppert/Chew refinement.  First every encroached subsegment (a vertex strictly inside its
 * diametral circle; in a CDT testing the apexes on both sides suffices) is split, then bad
 * triangles (smallest angle below min_angle, or area above max_area) are taken
 * shortest edge first (4096 buckets by its binary exponent, LIFO within a bucket): the
 * circumcenter (or off-center) is located by walking from the triangle; if the walk must cross
 * a constraint edge, that subsegment is split instead; if the point would encroach a
 * subsegment on its cavity's boundary it is discarded and those subsegments are split.
 * Split points: the exact dyadic midpoint a + (b - a) * ((2k+1) / 2^(j+1)) computed from the
 * original segment's endpoints (always for interface segments); a non-interface subsegment
 * with exactly one endpoint at a small-angle input corner (< 60 degrees) is split on a
 * concentric shell (at a power-of-two distance from the corner, Ruppert 1995; when an
 * interface segment s ends at the corner, at |s| times a power of two, so the shells match
 * the dyadic pieces of s there).  A skinny triangle whose shortest edge joins two vertices on
 * two neighbouring non-interface segments that meet at such a corner, at the same distance
 * from it (within 1%), is left alone unless it is also too large (its small angle is forced by
 * the input; the validator exempts it); corners with an interface segment are not exempt.  An
 * interface subsegment whose halves would be below 2^-44 of the coordinates' magnitude is not
 * split (counted in stats.failed; the same decision on every rank).  With q.lens,
 * diametral lenses (Shewchuk 2002) replace the circles in every encroachment test.
 * Resumable: returns when the queues are empty; new work (named splits) is queued and picked up
 * by the next call. */
mesh_refine_result mesh_refine(mesh *m);

typedef enum { MESH_SPLIT_DONE, MESH_SPLIT_ALREADY, MESH_SPLIT_NOT_FOUND } mesh_split_result;

/* Splits the subsegment named (seg, level, k) at its dyadic midpoint (PCDM: a split request
 * from the neighbouring rank).  If an ancestor (coarser subsegment) is still whole here it is
 * split down to the named one.  A subsegment already split here gives MESH_SPLIT_ALREADY
 * (counted, not an error); a segment with no subsegment here gives MESH_SPLIT_NOT_FOUND.
 * Subsegments the new vertex encroaches are split too (locally, calling on_split for
 * interface ones; past the Steiner limit, interface ones only); new bad triangles are queued for
 * the next mesh_refine.  Local. */
mesh_split_result mesh_split_subsegment_named(mesh *m, int32_t seg, int32_t level, int64_t k);

/* Dyadic split point of the subsegment (level, k) of segment a-b: a + (b-a)*((2k+1)/2^(j+1)),
 * componentwise; the one expression every rank uses. */
void mesh_dyadic_point(const double a[2], const double b[2], int32_t level, int64_t k,
                       double out[2]);

/* ---- output and accessors ---------------------------------------------------------------- */

/* Fills f (which it allocates; free with mesh_flat_free): every vertex (input numbering
 * first), live triangles compacted in slot order, the subsegments with their segment's marker
 * and interface flag; f->tattr (each triangle's regional attribute, 0 outside every region)
 * when mesh_set_regions was called, else NULL.  Returns 0 (it cannot fail: the int is kept for
 * callers that test it). */
int mesh_to_flat(const mesh *m, mesh_flat *f);

/* Moves m into f: the same f as mesh_to_flat (tattr included), built from m's own arrays (live
 * triangles compacted in place, vertex markers written over vseg, arrays shrunk) while everything
 * else of m is freed first, so the mesh is never held twice (the parallel meshers' memory peak).
 * When topen is not NULL, *topen gets one byte per triangle of f (free with free()): bit j set
 * iff edge j (tri[3t + j] -> tri[3t + (j + 1) % 3]) has no neighbour in m.  m is empty
 * afterwards (as after mesh_free).  Free f with mesh_flat_free. */
void mesh_take_flat(mesh *m, mesh_flat *f, uint8_t **topen);

/* Bytes held by the mesh's arrays (capacities). */
size_t mesh_memory_bytes(const mesh *m);

/* The sum of the live triangles' areas, in the mesh's (working) units; each rounded, summed
 * with compensation (a magnitude, never a topological decision). */
double mesh_area(const mesh *m);

/* The length of the mesh's boundary (edges with no triangle on one side) that lies on input
 * segments, interface segments left out, in working units; *mag (may be NULL) gets the largest
 * coordinate magnitude of the vertices.  Rounded: for mesh_rules_area_drift. */
double mesh_boundary_length(const mesh *m, double *mag);

/* Edge code of the edge {u, v} in some live triangle (either direction), or -1. */
int32_t mesh_find_edge(const mesh *m, int32_t u, int32_t v);

/* The subsegment record of constraint edge e, or NULL. */
const mesh_subseg *mesh_subseg_of_edge(const mesh *m, int32_t e);

/* Smallest-angle and area test used by the refiner: 0 good, 1 bad angle, 2 bad area only. */
int mesh_tri_bad(const mesh *m, int32_t t);

/* After mesh_refine: the number of live triangles that still break the bounds of
 * mesh_set_quality (area above the bound, or smallest angle below it where the input does not
 * force it).  *forced (may be NULL): triangles whose small angle the input forces (a vertex at
 * a small input corner, or the refiner's concentric-shell exemption); they are not counted as
 * unmet.  A mesher must not report success while this is non-zero: refinement stopped short
 * (Steiner limit, a refused split below the precision floor, a failed insertion). */
int64_t mesh_count_unmet(mesh *m, int64_t *forced);

static inline int32_t mesh_edge_tri(int32_t e) {
    return e / 3;
}
static inline int32_t mesh_edge_next(int32_t e) {
    return (e % 3 == 2) ? e - 2 : e + 1;
}
static inline int32_t mesh_edge_prev(int32_t e) {
    return (e % 3 == 0) ? e + 2 : e - 1;
}
static inline int32_t mesh_org(const mesh *m, int32_t e) {
    return m->tv[e];
}
static inline int32_t mesh_dest(const mesh *m, int32_t e) {
    return m->tv[mesh_edge_next(e)];
}
static inline int32_t mesh_apex(const mesh *m, int32_t e) {
    return m->tv[mesh_edge_prev(e)];
}
/* The same edge in the neighbouring triangle (reversed), or -1 on the boundary. */
static inline int32_t mesh_sym(const mesh *m, int32_t e) {
    return m->tn[e];
}
static inline int mesh_edge_constrained(const mesh *m, int32_t e) {
    return (m->tf[e / 3] >> (e % 3)) & 1;
}
static inline int mesh_tri_alive(const mesh *m, int32_t t) {
    return m->tv[3 * t] != MESH_DEAD;
}
static inline const double *mesh_vertex_xy(const mesh *m, int32_t v) {
    return m->xy + 2 * (size_t)v;
}

#endif
