/* vattr: vertex attributes on the vertices a mesher made (Triangle: "linearly interpolated").
 *
 * The input's vertex attributes (the .node columns, pslg.vattr) define a piecewise-linear
 * function over the constrained Delaunay triangulation of the input; every other vertex of the
 * finished mesh takes its value there (the CDT triangle containing it, found exactly by tloc;
 * a vertex that rounding put just outside the domain, e.g. a split point of a boundary
 * segment, takes the nearest triangle's, weights clamped).  A vertex on a segment so gets the
 * linear interpolation along the segment's piece.  The result depends on the vertex's
 * position only, so ./mesh, ./pcdm and ./pbw give a vertex at the same place the same values,
 * and a rank can fill its part alone.
 */
#ifndef VATTR_H
#define VATTR_H

#include "geom/pslg.h"
#include "io/meshio.h"

/* Local.  Fills f->nattr and f->vattr (replacing any) from g (pslg_check'ed; f in the same
 * working scale): a vertex at the exact coordinates of an input vertex gets its attributes,
 * any other the interpolation above.  Nothing to do (returns 0, f unchanged) when g has no
 * attributes.  Returns 0, or -1 with a message in err (the input's CDT failed). */
int mesh_interpolate_attributes(const pslg *g, mesh_flat *f, char *err, size_t errlen);

#endif
