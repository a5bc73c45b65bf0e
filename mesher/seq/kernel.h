/* kernel: the sequential kernel's operations below mesh.h that the parallel meshers build on
 * (mesher/pcdm/, mesher/pbw/, and the tests that build meshes by hand) -- a named interface,
 * so they need not reach into the kernel's internals (mesh_impl.h).  PBW keeps its own state
 * in a mesh's tf bits 5..7 and in tn values below -1 (MESH_FENCE, mesh.h); the cavity
 * operations report reaching them (CAV_FENCED).  All functions are Local and leave the
 * invariants of mesh.h in place: live non-ghost triangles counter-clockwise, tn an involution
 * on live edges, a constraint bit on both sides of a constraint edge.
 */
#ifndef SEQ_KERNEL_H
#define SEQ_KERNEL_H

#include "base/base.h"
#include "seq/mesh.h"

#include <stdio.h>
#include <stdlib.h>

#define MESH_MARK 8u    /* tf scratch bit */
#define MESH_QUEUED 16u /* tf: queued as a bad triangle since the slot was last written */

/* One boundary edge of a cavity, in counter-clockwise order around it. */
typedef struct mesh_bedge {
    int32_t org, dest;
    int32_t twin;  /* edge code outside the cavity, or -1 */
    uint8_t cons;  /* 1 if a constraint edge */
    uint8_t split; /* 1 if this is the edge being split (one-sided split) */
    int32_t reg;   /* region of the cavity triangle inside this edge (treg; -1: none) */
} mesh_bedge;

/* Cavity outcome (CAV_FENCED: the cavity reached a triangle with a MESH_FENCE bit, or an edge
 * whose tn is below -1: only a caller that sets them, PBW, sees it). */
enum { CAV_OK = 0, CAV_NOT_STAR = -1, CAV_CYCLE = -2, CAV_FENCED = -3 };

/* ---- triangles and vertices (mesh.c) ---- */

int32_t mesh_vert_add(mesh *m, double x, double y, int32_t vseg);
int32_t mesh_tri_new(mesh *m);
void mesh_tri_kill(mesh *m, int32_t t);

/* ---- Bowyer-Watson cavities and flips (mesh.c) ---- */

/* Collects the cavity of p (not yet a vertex).  t0 contains p (or is a ghost in conflict);
 * split_e >= 0 is a constraint edge code of t0 that p splits (both its triangles join the
 * cavity).  On CAV_NOT_STAR *bad is the offending boundary edge code (constraint or not).
 * The cavity stays marked until mesh_cavity_commit or mesh_cavity_abort. */
int mesh_cavity_collect(mesh *m, const double p[2], int32_t t0, int32_t split_e, int32_t *bad);
void mesh_cavity_abort(mesh *m);
/* Joins vertex v to the collected cavity's boundary.  New triangle ids in m->newt.  When
 * split_u/split_v are >= 0 (the endpoints of the split subsegment), the spokes v-split_u and
 * v-split_v become constraint edges. */
void mesh_cavity_commit(mesh *m, int32_t v, int32_t split_u, int32_t split_v);

/* Flips edge e (both triangles live, quadrilateral strictly convex: caller checks). */
void mesh_flip(mesh *m, int32_t e);

/* ---- the subsegment side table (mesh_subseg.c) ---- */

int32_t mesh_ss_add(mesh *m, int32_t u, int32_t v, int32_t seg, int32_t level, int64_t k);
void mesh_ss_del(mesh *m, int32_t r);
int32_t mesh_ss_find_pair(const mesh *m, int32_t u, int32_t v);
/* A hint: the table slots mesh_ss_add(m, u, v, seg, level, k) will touch, read into the cache
 * now (no effect on the tables). */
void mesh_ss_prefetch(const mesh *m, int32_t u, int32_t v, int32_t seg, int32_t level, int64_t k);
/* Room for n live records at once: the record array and both tables grown now to the sizes
 * that adding records one by one up to n would reach, so no table is rebuilt on the way. */
void mesh_ss_reserve(mesh *m, int32_t n);

/* Adds an original segment; returns its id. */
int32_t mesh_seg_add(mesh *m, int32_t a, int32_t b, int32_t marker, uint8_t iface);

/* Sets vtri for every vertex from the live triangles. */
void mesh_rebuild_vtri(mesh *m);

/* refine.c, for the parallel meshers (Local).  The interface subsegments (siface) that do not
 * conform: the named splits (a neighbour's, which it made) this mesh could not make (the split
 * point off its line for the triangles on this side), plus those still encroached (a vertex of
 * a triangle beside them strictly inside the diametral circle) and not locally Delaunay (exact
 * incircle) with both sides in this mesh.  *remote (if not NULL) gets the encroached ones whose
 * other side is not in this mesh: only the two apexes together decide those (the caller asks
 * the other side: par_check_interface_delaunay).  Refinement leaves none unless a split was
 * refused (precision, the interface piece cap). */
int64_t mesh_iface_defects(mesh *m, int64_t *remote);

/* Makes *dst (uninitialised or freed; overwritten) a deep copy of src, which has no refinement
 * state (mesh_refine not started, or mesh_refine_free since): every array and every scalar
 * (walk memory, random state, quality, hooks, statistics), so the copy behaves as src would.
 * A caller's size-rule context is shared, not copied.  Local. */
void mesh_copy(mesh *dst, const mesh *src);

/* refine.c: called after every committed cavity when refinement is active. */
void mesh_refine_free(mesh *m);

#endif
