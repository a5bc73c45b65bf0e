/* validate_impl: what the validator's two files share (internal to mesher/check/):
 * validate.c (the mesh's own structure: indices, orientation, conformity, local Delaunay,
 * areas; the driver mesh_validate) and validate_input.c (the mesh against its input: input
 * vertices and segments, small input corners, quality bounds and their exemptions, regions).
 */
#ifndef CHECK_VALIDATE_IMPL_H
#define CHECK_VALIDATE_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "check/validate.h"
#include "geom/pslg.h"

/* Edge records, reachable by an open-addressing hash on the undirected key. */
enum { E_MSEG = 1, E_BND = 2, E_INMESH = 4, E_INPUT = 8 };

typedef struct erec {
    int32_t u, v; /* u < v */
    int32_t flags;
    int32_t mseg; /* first m->seg index, or -1 */
    int32_t from; /* boundary edges: the direction with the mesh on its left */
} erec;

typedef struct etab {
    erec *rec;
    int32_t n, cap;
    int32_t *slot; /* hash slots: record index or -1 */
    size_t nslot;  /* power of two */
} etab;

/* Small input corners (pslg_input_angles below 60 degrees): vertex v between segments s1, s2. */
typedef struct gap {
    int32_t v, s1, s2;
} gap;

typedef struct gaplist {
    gap *g;
    int32_t n, cap;
} gaplist;

typedef struct vtag { /* mesh vertex on side `side` of small corner k */
    int32_t v, k, side;
} vtag;

/* Everything one validation run builds, handed from check to check.  The first check (indices
 * in range) decides whether the others can run at all. */
typedef struct vctx {
    const pslg *g;
    const mesh_flat *m;
    const validate_opts *o;
    validate_report *r;
    const double *xy;
    const int32_t *tri;
    int32_t nv, nt;
    uint8_t *tbad;   /* per triangle: not counter-clockwise (skipped by later checks) */
    uint8_t *vflag;  /* per vertex: 1 small corner, 2 on a small corner's segment chain */
    int32_t *bstart; /* directed edges bucketed by their smaller vertex: bhe[bstart[v]..] */
    uint32_t *bhe;
    int32_t maxdeg;
    etab T;          /* segment and boundary edges */
    int32_t *gmap;   /* input vertex -> mesh vertex, or -1 */
    gaplist gl;      /* small input corners */
    int32_t *tstart; /* per input segment: its corner tags tags[tstart[s]..] */
    int32_t (*tags)[2];
    pslg_pieces pc; /* input segments cut at the input vertices on them; which border the domain */
    vtag *vt;       /* mesh vertices on small corners' segments, sorted */
    size_t nvt, capvt;
} vctx;

/* Records the first problem found (later ones only counted by the caller). */
__attribute__((format(printf, 2, 3))) void validate_problem(validate_report *r, const char *fmt,
                                                            ...);

/* The checks of validate_input.c, in the order mesh_validate runs them (numbered as there). */
void validate_input_vertices(vctx *c); /* 6. input vertices: exact coordinates, by hash */
void validate_small_corners(vctx *c);  /* 7. small input corners and the segments forming them */
void validate_input_segments(vctx *c); /* 8. input segments as chains of segment/boundary edges */
void validate_quality(vctx *c);        /* 10. angle and area bounds, with the exemptions */
void validate_regions(vctx *c);        /* 10b. regional attributes and area bounds */

#endif
