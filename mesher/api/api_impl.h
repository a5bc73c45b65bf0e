/* api_impl: what the sequential (api.c) and parallel (api_par.c) halves of the public
 * interface (include/pcdm.h) share.  Internal: never installed.  All functions are Local. */
#ifndef API_IMPL_H
#define API_IMPL_H

#include "pcdm.h"

#include "geom/pslg.h"
#include "seq/mesh.h"

#define PCDM_STRINGIFY_(x) #x
#define PCDM_STRINGIFY(x) PCDM_STRINGIFY_(x)
#define PCDM_VERSION_STRING                                                                        \
    PCDM_STRINGIFY(PCDM_VERSION_MAJOR)                                                             \
    "." PCDM_STRINGIFY(PCDM_VERSION_MINOR) "." PCDM_STRINGIFY(PCDM_VERSION_PATCH)

/* The caller's size rule and the scaling to undo before calling it (api_quality). */
typedef struct api_rule {
    pcdm_unsuitable_fn fn;
    void *ctx;
    int scale_exp;
} api_rule;

/* Sets st (code and printf-style message); returns code. */
int api_fail(pcdm_status *st, int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Checks counts, pointers, segment endpoints and the bounds.  Returns PCDM_OK or an error code
 * (st set). */
int api_check_args(const pcdm_input *in, const pcdm_options *o, pcdm_status *st);

/* Copies in into *g and runs pslg_check quietly (no warnings printed); with o->convex_hull
 * the convex hull is enclosed by segments (PSLG_HULL).  Returns PCDM_OK (*g owned by the
 * caller: pslg_free) or PCDM_EINPUT (st set, *g holds nothing). */
int api_make_pslg(const pcdm_input *in, const pcdm_options *o, pslg *g, pcdm_status *st);

/* The mesher's bounds from o (the angle bound raised by a hair, as ./mesh). */
void api_quality(const pcdm_options *o, mesh_quality *q);

/* With o->unsuitable, sets it as m's size rule (mesh_set_size_rule) through *u (which must
 * outlive the refinement), which shows it the caller's coordinates (the mesh's are scaled by
 * 2^scale_exp). */
void api_size_rule(mesh *m, const pcdm_options *o, api_rule *u, int scale_exp);

/* out->points[i] = xy scaled back by 2^-scale_exp (exact). */
void api_copy_points(pcdm_mesh *out, int32_t i, const double *xy, int scale_exp);

#endif
