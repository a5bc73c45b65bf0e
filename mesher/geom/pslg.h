/* pslg: planar straight-line graphs read from Triangle's .poly (and .node) files.
 *
 * The reader accepts what Triangle accepts: '#' comments and blank lines anywhere, 0- or
 * 1-based ids (taken from the first vertex), attributes and boundary markers, a .poly whose
 * vertex count is 0 (vertices then come from the .node file of the same base name), holes and
 * the optional regional-attributes section; and LF, CRLF or CR line ends and a UTF-8
 * byte-order mark (base/textin.h).  As in Triangle, every other section must be there whole: a
 * file that ends before its hole count, or inside any list, is an error naming where it ends;
 * so is a NUL byte (binary input).  Every problem is reported as one message
 * "FILE:LINE: problem" and the function returns an error; nothing is left allocated.
 *
 * After reading, pslg_check() validates geometry: finite coordinates, segments with distinct
 * in-range endpoints, no zero-length segments, no two segments crossing in their interiors
 * (reported as self-intersecting, naming both segments and their lines).  Duplicate vertices
 * are merged (a warning names both lines) and segments are remapped; repeated segments are
 * dropped.  A vertex lying in the interior of a segment is allowed: the segment is split there
 * by the triangulator.  pslg_check_ex(PSLG_SPLIT) instead splits crossing and overlapping
 * segments as Triangle does (the meshers' default; --strict keeps the refusal).
 */
#ifndef PSLG_H
#define PSLG_H

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>

typedef struct pslg {
    int32_t nverts;
    double *xy;       /* 2 * nverts coordinates */
    int32_t *vmarker; /* nverts boundary markers (0 if the file has none) */
    int nattr;        /* attributes per vertex */
    double *vattr;    /* nattr * nverts, or NULL */
    int32_t *vline;   /* nverts: source line of each vertex (for messages) */
    int32_t nsegs;
    int32_t *seg;     /* 2 * nsegs vertex indices, 0-based */
    int32_t *smarker; /* nsegs boundary markers */
    int32_t *sline;   /* nsegs: source line of each segment */
    int32_t nholes;
    double *holes; /* 2 * nholes */
    int32_t nregions;
    double *regions;   /* 4 * nregions: x, y, attribute, max area (a line with one value after
                        * x y uses it for both, as Triangle; none: attribute 0, max area -1) */
    int first_index;   /* 0 or 1: the numbering the file used */
    int quiet;         /* 1: pslg_check prints no warnings (the library never prints) */
    int scale_exp;     /* pslg_check multiplied every coordinate by 2^scale_exp (0: untouched) */
    char path[512];    /* file the vertices came from (for messages) */
    char segpath[512]; /* file the segments, holes and regions came from (= path unless a .poly
                        * with no vertices took them from its .node file) */
} pslg;

/* Reads path (a .poly, or a .node for a point set).  Returns 0 on success; on failure returns
 * -1 and writes "FILE:LINE: problem" into err (errlen bytes).  *out is zeroed first and owns
 * its arrays on success; on failure it holds nothing. */
int pslg_read(const char *path, pslg *out, char *err, size_t errlen);

/* pslg_read, calling on_vertices(ctx, out) once the vertices are read, before the rest of the
 * file (out's vertex arrays and count set, coordinates as in the file; NULL: no call), so that
 * work on the vertices can start while the segments are parsed. */
int pslg_read_ex(const char *path, pslg *out, void (*on_vertices)(void *ctx, const pslg *g),
                 void *ctx, char *err, size_t errlen);

/* Coordinates (pslg_check): any finite doubles whose largest magnitude is at least 2^-723
 * (about 1.8e-218) and whose nonzero magnitudes are at least 2^-247 (about 4.4e-75) times the
 * largest (smaller ones only when they are multiples of 2^-300 of its power-of-two scale).
 * Inputs already within the predicates' working range (every coordinate a multiple of
 * 2^PSLG_GRID_EXP and at most 2^PSLG_TOP_EXP) are left untouched; any other input is scaled by
 * an exact power of two 2^scale_exp so that its largest magnitude lies in [2^99, 2^100), and
 * writers of the mesh undo the scaling exactly (mesh_flat.scale_exp).  In that range every
 * predicate is exact (geom.h, "working range"). */
#define PSLG_TOP_EXP 100
#define PSLG_GRID_EXP (-200)
#define PSLG_MAX_SCALE 822 /* 2^(GRID - MAX_SCALE) = 2^-1022: unscaled points stay normal */

/* An area in the input's units (a bound: 0 or less is none, and stays so) in the working units
 * of coordinates scaled by 2^scale_exp, where meshes measure areas; one that underflows stays
 * a bound (the smallest normal double).  pslg_input_area is the inverse. */
static inline double pslg_scaled_area(int scale_exp, double area) {
    if (!(area > 0) || scale_exp == 0) return area;
    double s = ldexp(area, 2 * scale_exp);
    return s > 0 ? s : DBL_MIN;
}
static inline double pslg_input_area(int scale_exp, double area) {
    return area > 0 && scale_exp != 0 ? ldexp(area, -2 * scale_exp) : area;
}

/* Validates and normalises geometry (see above).  Returns 0, or -1 with a message in err.
 * Warnings (merged duplicates) go to stderr prefixed with the file and line, unless g->quiet. */
int pslg_check(pslg *g, char *err, size_t errlen);

/* pslg_check_ex flags. */
enum {
    /* Split crossing and overlapping segments instead of refusing them (Triangle's behaviour):
     * collinear overlapping segments become the pieces of their union between each other's
     * endpoints (a piece covered twice keeps the marker of the segment first in the file); two
     * segments crossing in their interiors get a new vertex at the intersection point rounded
     * to doubles (marker 0, attributes interpolated linearly along the first segment), shared
     * by every segment through the same point, and their pieces become segments with the
     * segments' markers.  Every case is decided with the exact orient2d, and the result is
     * checked again the same way; pieces that the rounded points make cross are split again,
     * up to PSLG_SPLIT_ROUNDS rounds, then the one clear error "FILE:LINE: ... too close to
     * resolve".  Crossing vertices are numbered after the file's vertices. */
    PSLG_SPLIT = 1,
    /* Then enclose the convex hull of the vertices with segments (Triangle's -c; see
     * pslg_enclose_hull): the domain becomes everything inside the hull but the holes. */
    PSLG_HULL = 2
};
#define PSLG_SPLIT_ROUNDS 8

/* pslg_check, with flags (PSLG_SPLIT, PSLG_HULL, both or 0; pslg_check is pslg_check_ex(g, 0,
 * ...)).  Returns 0, or -1 with a message in err. */
int pslg_check_ex(pslg *g, unsigned flags, char *err, size_t errlen);

/* pslg_check_ex in two steps, for a caller that starts work on the vertices between them (the
 * parallel programs' rank 0 triangulates them while the rest is checked): pslg_check_start
 * refuses non-finite coordinates and segment ends out of range and scales the vertices into the
 * working range; pslg_check_finish then does the rest, which may still merge, drop or add
 * vertices.  Each returns 0, or -1 with a message in err; finish only after start returned 0. */
int pslg_check_start(pslg *g, char *err, size_t errlen);
int pslg_check_finish(pslg *g, unsigned flags, char *err, size_t errlen);

/* Local.  g's vertex coordinates into xy (2 g->nverts doubles) as pslg_check_start leaves them
 * when g's holes and regions do not change the scale it picks (a g of which only the vertices
 * are read yet, or one already checked, whose coordinates come back as they are).  Returns 0,
 * or -1 when a coordinate is not finite or not representable at that scale (pslg_check_start
 * says which). */
int pslg_vertices_scaled(const pslg *g, double *xy);

/* Triangle's -c: encloses the convex hull of g's vertices with segments.  The hull's edges are
 * cut at every vertex lying on them (exact orient2d), so no new segment passes through a
 * vertex; an edge an input segment already covers (the segment lying on the hull's boundary)
 * is not added again; every other edge becomes a segment with boundary marker 1 and line 0,
 * appended after g's segments.  Vertices all on one line have a hull without area: nothing is
 * added.  Call after pslg_check (pslg_check_ex's PSLG_HULL does); keeps its invariant. */
void pslg_enclose_hull(pslg *g);

/* The convex hull of g's vertices (Andrew's monotone chain, exact orient2d): writes its
 * vertices counter-clockwise into cyc (room for 2 * g->nverts + 2), every vertex lying on the
 * hull's boundary included (collinear ones too), each point once, starting from the lowest of
 * the leftmost.  Returns their number, or 0 when the vertices are fewer than 3 or all on one
 * line. */
int32_t pslg_hull(const pslg *g, int32_t *cyc);

/* Boundary markers as Triangle assigns them (its documentation of .node and .poly), on the
 * PSLG before meshing so that every mesher's output inherits them: a segment with marker 0
 * that borders the domain on exactly one side somewhere (the outer boundary, a hole's) gets 1;
 * a vertex with marker 0 lying on a segment (an endpoint, or inside it) takes the segment's
 * nonzero marker -- the file's markers first, then the boundary's 1.  Vertices on no such
 * segment keep 0.  A point set (no segments) is meshed over its convex hull, whose edges
 * become segments with marker 1: its vertices on the hull get 1 (as with -c).  The meshers give
 * a new vertex on a segment that segment's marker, and other new vertices 0.  Call after
 * pslg_check.  Returns 0 (it cannot fail: the int is kept for callers that test it). */
int pslg_boundary_markers(pslg *g);

/* Area of the domain the PSLG describes, computed from the PSLG alone (independently of any
 * mesh): the union of the bounded faces of the segment arrangement, minus the faces that
 * contain a hole point.  A hole point exactly on a segment or a vertex removes every face
 * whose closure contains it (as the mesher's carving does).  Used by the validator. */
double pslg_domain_area(const pslg *g);

/* The input's regions found from the PSLG alone (independently of any mesh), for the
 * validator: region point i marks the face of the segment arrangement strictly containing it
 * (a point exactly on a segment or a vertex of one, outside every bounded face, or in a face a
 * hole removed marks nothing); where two points mark the same face the later one in the file
 * wins (as the meshers do, mesh_set_regions).  Build once, then ask per point; g must outlive
 * the lookup. */
typedef struct pslg_regions pslg_regions;

/* Returns the lookup (free with pslg_regions_free), or NULL when g has no segments (then no
 * point is in a region). */
pslg_regions *pslg_regions_build(const pslg *g);

/* The region (index into g->regions) of the face strictly containing p, or -1 (no region, or p
 * on no face: outside, on a segment).  p must not lie on a segment for a meaningful answer. */
int32_t pslg_region_at(const pslg_regions *R, const double p[2]);

void pslg_regions_free(pslg_regions *R);

/* The pieces of every segment (cut at the vertices lying on it: none once pslg_check has run,
 * which splits segments there) and whether each borders the domain: segment s runs through
 * vertices vert[start[s] .. start[s+1]) in order from its first endpoint; the piece from
 * vert[i] to vert[i+1] has the domain on at least one side iff border[i] (0: inside the removed
 * region, e.g. around a hole point on it).  The validator asks the mesh for the bordering
 * pieces only. */
typedef struct pslg_pieces {
    int32_t *start; /* nsegs + 1 */
    int32_t *vert;
    uint8_t *border;
    int32_t nvert;
} pslg_pieces;

/* Fills P (caller frees with pslg_pieces_free).  Returns 0 (it cannot fail: the int is kept for
 * callers that test it). */
int pslg_segment_pieces(const pslg *g, pslg_pieces *P);
void pslg_pieces_free(pslg_pieces *P);

/* Like pslg_read for a .poly, except that when the .poly declares 0 vertices its .node file is
 * not read: segment endpoints are checked against nverts vertices numbered from first_index
 * and out->nverts stays 0.  (meshio_read_triangle uses it after reading PREFIX.node.)  A .poly
 * that lists its own vertices is read completely, as by pslg_read. */
int pslg_read_segments(const char *path, int32_t nverts, int first_index, pslg *out, char *err,
                       size_t errlen);

/* The angles between angularly consecutive segments at each vertex (in degrees, exact angular
 * order; g is pslg_check()ed, so no vertex lies inside a segment and every corner is at segment
 * ends).  For every such pair (s1, then s2 counter-clockwise around v) whose angle is below
 * bound_deg, calls fn(ctx, v, s1, s2, angle) when fn is not NULL.  Returns the smallest angle
 * found, or 360 when no vertex has two segments.  A vertex with two segments has two angles (theta
 * and 360 - theta). */
double pslg_input_angles(const pslg *g, double bound_deg,
                         void (*fn)(void *ctx, int32_t v, int32_t s1, int32_t s2, double deg),
                         void *ctx);

void pslg_free(pslg *g);

#endif
