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

/* A subdomain mesh built alone (pcdm_build_sub) numbers its own vertices and segments: its
 * input vertex v (v < m->ninput) is vertex gv[v] of d->g and its segment s is segment gs[s] of
 * d->g, both ascending.  gv == NULL: the mesh numbers them as d->g does (built whole). */
typedef struct pcdm_sub_map {
    int32_t nv, ns;
    int32_t *gv, *gs; /* owned */
} pcdm_sub_map;

static inline int32_t pcdm_map_seg_global(const pcdm_sub_map *mp, int32_t s) {
    return mp->gs ? mp->gs[s] : s;
}
static inline int32_t pcdm_map_vert_global(const pcdm_sub_map *mp, int32_t v) {
    return mp->gv ? mp->gv[v] : v;
}
/* Local.  The mesh's segment for d->g's segment g, or -1 if it has none. */
int32_t pcdm_map_seg_local(const pcdm_sub_map *mp, int32_t g);
void pcdm_sub_map_free(pcdm_sub_map *mp);

/* Local.  The initial mesh of subdomain sub alone (pcdm_build.c): the CDT of its own boundary
 * pieces and free vertices, its map in *mp (owned; freed on failure).  With input regions
 * (regions != PCDM_REGIONS_NONE: their labels come from the whole CDT) or a decomposition that
 * does not say which subdomain holds each free vertex, pcdm_build_mesh of sub instead (identity
 * map).  The same mesh on every rank and thread.  Returns 0, or -1 with a message in err. */
int pcdm_build_sub(mesh *m, pcdm_sub_map *mp, const pcdm_decomp *d, int32_t sub, int regions,
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
 * number, and mesh i with its subdomain in *sub and its numbering in *map. */
int32_t pcdm_det_nmesh(const pcdm_part *p);
mesh *pcdm_det_mesh(pcdm_part *p, int32_t i, int32_t *sub, const pcdm_sub_map **map);

/* pcdm_flat.c: pcdm_part_take for deterministic parts (merges the meshes). */
void pcdm_det_take(pcdm_part *p, mesh_flat *f, uint8_t **artificial, int32_t **tsub,
                   uint8_t **topen);

#endif
