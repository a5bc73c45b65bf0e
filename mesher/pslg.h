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
    double *xy;        /* 2 * nverts coordinates */
    int32_t *vmarker;  /* nverts boundary markers (0 if the file has none) */
    int nattr;         /* attributes per vertex */
    double *vattr;     /* nattr * nverts, or NULL */
    int32_t *vline;    /* nverts: source line of each vertex (for messages) */
    int32_t nsegs;
    int32_t *seg;      /* 2 * nsegs vertex indices, 0-based */
    int32_t *smarker;  /* nsegs boundary markers */
    int32_t *sline;    /* nsegs: source line of each segment */
    int32_t nholes;
    double *holes;     /* 2 * nholes */
    int32_t nregions;
    double *regions;   /* 4 * nregions: x, y, attribute, max area */
    int first_index;   /* 0 or 1: the numbering the file used */
    char path[512];    /* file the vertices came from (for messages) */
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
 * contain a hole point.  Used by the validator. */
double pslg_domain_area(const pslg *g);

void pslg_free(pslg *g);

#endif
