/* sizefield: the size rules of refining an existing mesh (-r) and of size fields (--size),
 * which every mesher applies through mesh_rules.unsuitable (the bounds' size rule,
 * bounds/bounds.h).  The mesh to refine itself is read by io/meshio.h's meshio_read_mesh_pslg.
 *
 * -r NAME (NAME, NAME.node or NAME.ele): NAME.area (Triangle's .area
 * format: a count, then "triangle-number maximum-area" per line, a bound <= 0 meaning none)
 * gives a maximum area per old triangle, applied with -a alone as Triangle does: a new triangle
 * is too big when its area exceeds the bound of the old triangle containing its centroid.
 *
 * --size FILE (FILE, FILE.node or FILE.ele): a background mesh, FILE.node with at least one
 * attribute per vertex (the first is the target edge length h there) and FILE.ele.  h is
 * interpolated linearly at the new triangle's centroid (in the background triangle containing
 * it); the triangle is too big when its area exceeds that of the equilateral triangle of side
 * h, sqrt(3)/4 h^2.  Outside the background mesh, and where h <= 0, there is no bound.
 *
 * The rule sees the meshers' internal coordinates (the input's times 2^scale_exp, pslg.h): the
 * files' coordinates, areas and lengths are scaled by the same exact power of two when loaded.
 * All functions are Local; a loaded size_field is read-only, so size_field_unsuitable is
 * thread-safe and gives the same answer on every rank.
 */
#ifndef SIZEFIELD_H
#define SIZEFIELD_H

#include <stddef.h>
#include <stdint.h>

#include "geom/pslg.h"
#include "geom/tloc.h"

typedef struct size_field {
    int active; /* 1 iff some rule was loaded (size_field_unsuitable may say "too big") */
    /* -r's .area: the old triangles and their bounds (internal units; <= 0: none) */
    int32_t ont;
    double *oxy;   /* 6 per old triangle (its corners, counter-clockwise) */
    int32_t *otri; /* 0 1 2, 3 4 5, ... into oxy */
    double *oarea;
    tloc old;
    /* --size: the background mesh and its target lengths per vertex (internal units) */
    int32_t bnv, bnt;
    double *bxy;
    int32_t *btri;
    double *blen;
    tloc bg;
} size_field;

/* Loads the rules into S (zeroed first): refine_area (NULL: none) is -r's NAME whose NAME.area
 * is read (an error when it does not exist), background (NULL: none) the --size FILE;
 * scale_exp the input's (pslg.scale_exp, after pslg_check).  Returns 0, or -1 with a message
 * (S then holds nothing). */
int size_field_load(size_field *S, const char *refine_area, const char *background, int scale_exp,
                    char *err, size_t errlen);

/* mesh_rules.unsuitable for S (ctx): 1 iff the counter-clockwise triangle p (internal
 * coordinates) of the given area is too big for the old mesh's .area bound or the background
 * size at its centroid. */
int size_field_unsuitable(void *ctx, const double *const p[3], double area);

void size_field_free(size_field *S);

#endif
