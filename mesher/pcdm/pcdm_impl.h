/* pcdm_impl.h: what pcdm.c (the asynchronous protocol) and pcdm_det.c (the deterministic
 * rounds) share; private to mesher/pcdm. */
#ifndef PCDM_IMPL_H
#define PCDM_IMPL_H

#include "pcdm/pcdm.h"

/* Local.  Builds the coarse CDT of d->g into m (initialised here) and keeps the regions of
 * subdomain only_sub (>= 0), or, when only_sub < 0, of every subdomain d->sub_owner gives to
 * rank.  The length floor comes from the whole coarse CDT, and so do the input's region labels
 * (regions: PCDM_REGIONS_*, pcdm_part_build_regions).  Returns 0, or -1 with a message in err
 * (m then holds nothing). */
int pcdm_build_mesh(mesh *m, const pcdm_decomp *d, int rank, int32_t only_sub, int regions,
                    char *err, size_t errlen);

/* Local.  Lawson's flips (exact incircle) of the edges of m that are not locally Delaunay,
 * until none is left: m is a constrained Delaunay triangulation again.  Bowyer-Watson leaves
 * such an edge only at a subsegment's split point rounded off its line, so the edges at the
 * vertices on segments (vseg >= 0) are the seeds, and the edges each flip exposes are tested in
 * turn: a pass over the vertices, nothing near the cost of refinement.  A constraint edge, input
 * or interface, is never flipped (the subdomains still conform to each other); no vertex is
 * added; the refinement queues are not updated (call it when refinement is over).  Returns the
 * flips made (0 on a mesh that already was one: it is then unchanged, bit for bit). */
int64_t pcdm_mesh_restore_delaunay(mesh *m);

/* pcdm_det.c: registration (called by pcdm_register), build, refine, figures, output. */
int pcdm_det_register(void);
int pcdm_det_build(pcdm_part *p, char *err, size_t errlen);
void pcdm_det_refine(pcdm_part *p, const mesh_quality *q);
void pcdm_det_figures(pcdm_part *p, pcdm_figures *f);
void pcdm_det_free(pcdm_part *p);
/* The deterministic part's meshes (one per owned subdomain, ascending subdomain number): their
 * number, and mesh i with its subdomain in *sub. */
int32_t pcdm_det_nmesh(const pcdm_part *p);
mesh *pcdm_det_mesh(pcdm_part *p, int32_t i, int32_t *sub);

/* pcdm_flat.c: pcdm_part_take for deterministic parts (merges the meshes). */
void pcdm_det_take(pcdm_part *p, mesh_flat *f, uint8_t **artificial, int32_t **tsub,
                   uint8_t **topen);

#endif
