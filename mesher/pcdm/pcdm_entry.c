/* pcdm_entry.c: PCDM's entry for the driver (pcdm.h: pcdm_part_start, pcdm_part_run) -- the
 * part built for the mode asked for and refined to the bounds as one value (bounds/bounds.h).
 *
 * The Steiner limit: in rounds every subdomain is its own mesh and the limit is shared by them
 * (pcdm_det.c); in the asynchronous mode each rank gets the share of the limit its subdomains'
 * target weights give it (the decomposition's), so the ranks together stay within it.
 */
#include "pcdm/pcdm.h"

#include "rt.h"

int pcdm_part_start(pcdm_part *p, const pcdm_decomp *d, const mesh_bounds *b, const par_config *c,
                    char *err, size_t errlen) {
    int regions = b->region_area ? PCDM_REGIONS_AREA
                  : c->regions   ? PCDM_REGIONS_LABEL
                                 : PCDM_REGIONS_NONE;
    /* subdomains move only as whole meshes, and threads refine whole subdomains */
    int det = c->deterministic || c->balance || c->threads > 1;
    int rank = rt_rank();
    return det ? pcdm_part_build_det(p, d, rank, regions, c->threads, err, errlen)
               : pcdm_part_build_regions(p, d, rank, regions, err, errlen);
}

void pcdm_part_run(pcdm_part *p, const mesh_bounds *b, const par_config *c) {
    const pcdm_decomp *d = p->d;
    p->progress = c->progress && p->rank == 0;
    mesh_quality q = bounds_quality(b);
    q.lens = 0; /* diametral circles: interface subsegments stay Delaunay edges */
    if (b->max_steiner >= 0 && !p->det) { /* the global budget shared by target weight */
        double share = 0;
        for (int32_t s = 0; s < d->nsub; s++)
            if (d->sub_owner[s] == p->rank) share += d->sub_target[s];
        q.max_steiner = (int64_t)((double)b->max_steiner * share);
    }
    rt_stats_reset();
    if (b->size) mesh_set_size_rule(&p->m, b->size, b->size_ctx);
    p->balance = c->balance;
    p->threads = c->threads;
    pcdm_part_refine(p, &q, c->poll_every > 0 ? c->poll_every : 300);
}
