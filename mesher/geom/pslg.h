/* pslg: planar straight-line graphs read from Triangle's .poly (and .node) files.
 *
 * The reader accepts what Triangle accepts: '#' comments and blank lines anywhere, 0- or
 * 1-based ids (taken from the first vertex), attributes and boundary markers, a .poly whose
 * vertex count is 0 (vertices then come from the .node file of the same base name), holes and
 * the optional regional-attributes section.  Every problem is reported as one message
 * "FILE:LINE: problem" and the function returns an error; nothing is left allocated.
 *
 * After reading, pslg_check() validates geometry: finite coordinates, segments with distinct
 * in-range endpoints, no zero-length segments, no two segments crossing in their interiors
 * (reported as self-intersecting, naming both segments and their lines).  Duplicate vertices
 * are merged (a warning names both lines) and segments are remapped; repeated segments are
 * dropped.  A vertex lying in the interior of a segment is allowed: the segment is split there
 * by the triangulator.
 */
#ifndef PSLG_H
#define PSLG_H

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
    double *regions;   /* 4 * nregions: x, y, attribute, max area */
    int first_index;   /* 0 or 1: the numbering the file used */
    char path[512];    /* file the vertices came from (for messages) */
    char segpath[512]; /* file the segments, holes and regions came from (= path unless a .poly
                        * with no vertices took them from its .node file) */
} pslg;

/* Reads path (a .poly, or a .node for a point set).  Returns 0 on success; on failure returns
 * -1 and writes "FILE:LINE: problem" into err (errlen bytes).  *out is zeroed first and owns
 * its arrays on success; on failure it holds nothing. */
int pslg_read(const char *path, pslg *out, char *err, size_t errlen);

/* Validates and normalises geometry (see above).  Returns 0, or -1 with a message in err.
 * Warnings (merged duplicates) go to stderr prefixed with the file and line. */
int pslg_check(pslg *g, char *err, size_t errlen);

/* Area of the domain the PSLG describes, computed from the PSLG alone (independently of any
 * mesh): the union of the bounded faces of the segment arrangement, minus the faces that
 * contain a hole point.  A hole point exactly on a segment or a vertex removes every face
 * whose closure contains it (as the mesher's carving does).  Used by the validator. */
double pslg_domain_area(const pslg *g);

/* out[s] (g->nsegs bytes) = 1 iff some piece of segment s has the domain on at least one side;
 * 0 for a segment inside the removed region (both sides outside, e.g. all around a hole point
 * placed on it or on its vertex).  Returns 0, or -1 (out of memory; out is all 1). */
int pslg_segments_bordering(const pslg *g, uint8_t *out);

/* Like pslg_read for a .poly, except that when the .poly declares 0 vertices its .node file is
 * not read: segment endpoints are checked against nverts vertices numbered from first_index
 * and out->nverts stays 0.  (meshio_read_triangle uses it after reading PREFIX.node.)  A .poly
 * that lists its own vertices is read completely, as by pslg_read. */
int pslg_read_segments(const char *path, int32_t nverts, int first_index, pslg *out, char *err,
                       size_t errlen);

/* The angles between angularly consecutive segments at each vertex (in degrees, exact angular
 * order).  For every such pair (s1, then s2 counter-clockwise around v) whose angle is below
 * bound_deg, calls fn(ctx, v, s1, s2, angle) when fn is not NULL.  Returns the smallest angle
 * found, or 360 when no vertex has two segments.  A vertex with two segments has two angles
 * (theta and 360 - theta). */
double pslg_input_angles(const pslg *g, double bound_deg,
                         void (*fn)(void *ctx, int32_t v, int32_t s1, int32_t s2, double deg),
                         void *ctx);

void pslg_free(pslg *g);

#endif
