/* bounds: what a mesh must meet, as one value -- the smallest angle, the largest area, the
 * Steiner point limit, the choice of Steiner points (off-centres or circumcentres), the
 * encroachment test (circles or lenses) and a size rule (Triangle's triunsuitable: -r's .area,
 * --size, the library's callback; bounds/sizefield.h).
 *
 * One constructor, bounds_make, takes the bounds as the user states them; it alone raises the
 * angle bound by the small margin the refiners test (bounds_refine_angle), so rounding in the
 * quality test can never leave a triangle a few ulps below the bound the user asked for.  What
 * the kernel takes (mesh_quality, mesh_rules) derives from it here; the validator's options
 * derive from it in the driver (run/run.h), which knows whether the bounds were met.
 *
 * Layer: above seq (it fills seq's structs), below decomp, par, pcdm, pbw and run, which take
 * it.  All functions are Local; a mesh_bounds is a plain value (the size rule's ctx is the
 * caller's and must outlive every mesh refined with it).
 */
#ifndef BOUNDS_H
#define BOUNDS_H

#include <stdint.h>

#include "seq/mesh.h"
#include "seq/rules.h"

/* A size rule: 1 iff the counter-clockwise triangle p (the mesher's internal coordinates) of
 * the given area is too big (mesh_rules.unsuitable). */
/* The default angle bound (degrees): Triangle's -q without a number is 20; this is the largest
 * bound Chew's and Ruppert's refinement with off-centres reaches on any input in practice. */
#define BOUNDS_DEFAULT_ANGLE 20.7
/* Angle bounds are below it: no triangle but the equilateral one has all angles at 60. */
#define BOUNDS_ANGLE_LIMIT 60.0

typedef int (*bounds_size_fn)(void *ctx, const double *const p[3], double area);

typedef struct mesh_bounds {
    double min_angle;    /* degrees, as asked (0: none): what messages name and --check holds */
    double refine_angle; /* degrees the refiners test: min_angle raised by the margin */
    double max_area;     /* the input's units (0: none) */
    int64_t max_steiner; /* Steiner points at most (< 0: no limit) */
    int offcenter;       /* 1: Ungor's off-centres where closer than the circumcentre */
    int lens;            /* 1: diametral lenses instead of circles (./mesh --lens) */
    int region_area;     /* 1: each region's own area bound too (--region-areas) */
    bounds_size_fn size; /* the size rule (NULL: none) */
    void *size_ctx;
} mesh_bounds;

/* The angle the refiners test for a bound of deg degrees (<= 0: none, 0): deg raised by a
 * relative 1e-9 and an absolute 1e-12 degrees.  The one place the margin is added. */
double bounds_refine_angle(double deg);

/* The bounds as stated (min_angle in degrees, <= 0: none; max_area <= 0: none; max_steiner < 0:
 * no limit; circumcenters: 1 for circumcentres only; lens: 1 for diametral lenses); no region
 * bounds, no size rule (set b.region_area, bounds_set_size). */
mesh_bounds bounds_make(double min_angle, double max_area, int64_t max_steiner, int circumcenters,
                        int lens);

/* The one check of the bounds as stated, for every entry (command line, library, Python): 0
 * iff 0 <= min_angle < BOUNDS_ANGLE_LIMIT and max_area is 0 (none) or positive and finite;
 * else -1 with "NAME VALUE: must be ..." in err, each bound named as the caller's user knows it
 * (angle_name "-q" or "min_angle"). */
int bounds_check(double min_angle, double max_area, const char *angle_name, const char *area_name,
                 char *err, size_t errlen);

/* Sets b's size rule (fn NULL: none). */
void bounds_set_size(mesh_bounds *b, bounds_size_fn fn, void *ctx);

/* What mesh_set_quality takes (the refining angle, the other bounds as they are). */
mesh_quality bounds_quality(const mesh_bounds *b);

/* Sets m's quality (bounds_quality) and size rule (mesh_set_quality, mesh_set_size_rule). */
void bounds_apply(const mesh_bounds *b, mesh *m);

/* Fills R (mesh_rules_init with the refining angle and area, the size rule) -- for meshers that
 * test triangles themselves (pbw).  area: the area bound in the mesher's working scale. */
void bounds_rules(const mesh_bounds *b, double area, mesh_rules *R);

#endif
