/* pextra: the derived outputs of a distributed mesh (-e .edge, -n .neigh, -o2 quadratic
 * .node/.ele and VTK, --msh Gmsh 4.1), each one file written by every rank from its own part with
 * MPI-IO (io/xwrite.h for the formats).  No gather: what crosses a rank interface is settled by
 * O(interface) messages.
 */
#ifndef PAR_PEXTRA_H
#define PAR_PEXTRA_H

#include <stdint.h>

#include "geom/pslg.h"
#include "io/meshio.h"
#include "par/par.h"
#include "par/pout.h"

/* Collective.  Writes what o asks for among -e, -n, -o2 (with -o) and --msh from every rank's
 * part local (numbered by num, par_number; artificial: as par_number's).  With -o2 the .node
 * and .ele that meshio_pwrite_triangle wrote are replaced by their quadratic form, and --vtk F
 * (F.pvtu, F.vtu or F.vtk) is one legacy VTK file F.vtk of quadratic triangles (cell type 22,
 * cell data rank, point data marker) instead of the .pvtu pieces.  The files go into set (the
 * run's output set, io/oset.h: the caller commits it; NULL: each renamed at once).  Returns 0,
 * or -1 on every rank (the message printed by rank 0). */
struct meshio_set;
int par_write_extras(const par_opts *o, struct meshio_set *set, const pslg *in,
                     const mesh_flat *local, const uint8_t *artificial, const par_numbering *num);

#endif
