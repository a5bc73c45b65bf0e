/* api_impl: what the sequential (api.c) and parallel (api_par.c) halves of the public
 * interface (include/pcdm.h) share.  Internal: never installed.  All functions are Local. */
#ifndef API_IMPL_H
#define API_IMPL_H

#include "pcdm.h"

#include "geom/pslg.h"
#include "run/run.h"
#include "seq/mesh.h"

#define PCDM_STRINGIFY_(x) #x
#define PCDM_STRINGIFY(x) PCDM_STRINGIFY_(x)
#define PCDM_VERSION_STRING                                                                        \
    PCDM_STRINGIFY(PCDM_VERSION_MAJOR)                                                             \
    "." PCDM_STRINGIFY(PCDM_VERSION_MINOR) "." PCDM_STRINGIFY(PCDM_VERSION_PATCH)

/* Sets st (code and printf-style message); returns code. */
int api_fail(pcdm_status *st, int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* msg without the "input:LINE: " or "input: " the driver's load stage puts before a problem
 * with the arrays (they have no file name or lines; the message names the point or segment). */
const char *api_unpath(const char *msg);

/* Checks counts, pointers, segment endpoints and the bounds.  Returns PCDM_OK or an error code
 * (st set). */
int api_check_args(const pcdm_input *in, const pcdm_options *o, pcdm_status *st);

/* Copies in into *g (owned by the caller: pslg_free), unchecked: the driver's load stage
 * checks it (run_load). */
void api_copy_input(const pcdm_input *in, pslg *g);

/* The input as the driver loads it (run_load: checked, crossing segments split, Triangle's
 * boundary markers; with o->convex_hull the hull enclosed).  Returns PCDM_OK (*g the caller's:
 * pslg_free) or PCDM_EINPUT (st set, *g holds nothing). */
int api_make_pslg(const pcdm_input *in, const pcdm_options *o, pslg *g, pcdm_status *st);

/* A job (run/run.h) for the library's options o and method (run_method), the input g (taken
 * over by the driver); nothing printed. */
void api_job(const pcdm_options *o, int method, pslg *g, run_job *j);

/* pcdm_triangulate with o->threads >= 1 (api_thr.c; only in the builds that define
 * PCDM_THREADS): the subdomain mesher of ./pcdm on a one-rank communicator, the whole mesh in
 * out.  Returns st->code. */
int api_triangulate_threads(const pcdm_input *in, const pcdm_options *o, pcdm_mesh *out,
                            pcdm_status *st);

/* out->points[i] = xy scaled back by 2^-scale_exp (exact). */
void api_copy_points(pcdm_mesh *out, int32_t i, const double *xy, int scale_exp);

#endif
