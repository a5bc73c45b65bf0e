/* par_check: the interface checks of a mesh distributed over ranks, each rank holding its
 * part as a mesh_flat in local numbering (par_check.c).  They compare what the two sides of an
 * interface hold, exactly (coordinate bits), moving O(interface) data and never the mesh.
 * All functions are Collective over rt_app_comm(): every rank calls them, in the same order,
 * whatever its part holds.
 */
#ifndef CHECK_PAR_CHECK_H
#define CHECK_PAR_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "io/meshio.h"

/* Collective.  The cheap check that always runs before any output: every open edge of a
 * rank's piece (an edge of exactly one local triangle) that is not a non-interface constraint
 * (a domain-boundary subsegment) must be the open edge of exactly one other rank's piece, with
 * the same vertex coordinates bit for bit; so both sides of every interface agree on its
 * subsegments and vertices.  Each open edge travels once, to the rank its coordinates hash to
 * (O(interface) data, two all-to-all calls).  Returns 0, or -1 on the ranks that found a
 * disagreement, with a message in msg (callers agree through par_fail_any).  The open edges
 * come from the mesher's mask (topen: mesh_take_flat's, one byte per triangle; NULL: found
 * through vertex rows). */
int par_check_interfaces_open(const mesh_flat *local, const uint8_t *topen, char *msg,
                              size_t msglen);

/* Collective.  The interface local-Delaunay test of the distributed --check: every open edge
 * of local that is not an input constraint is sent with the apex of its local triangle to a
 * rendezvous rank (hash of the edge's coordinates); where the two sides of an interface edge
 * meet (two ranks), the edge must be locally Delaunay (geom_incircle, exact, strictly inside =
 * bad), as the sequential validator asks of every non-constraint edge.  topen: as
 * par_check_interfaces_open.  Returns the number of bad edges found on this rank (sum over
 * ranks for the total), the first described in msg. */
long par_check_interface_delaunay(const mesh_flat *local, const uint8_t *topen, char *msg,
                                  size_t msglen);

#endif
