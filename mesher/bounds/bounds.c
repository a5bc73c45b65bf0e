/* bounds.c: the bounds as one value (bounds.h) and what the kernel takes derived from it.
 *
 * The margin: the refiners decide "smallest angle below the bound" from rounded cosines of
 * rounded coordinates, so a triangle exactly at the bound may come out either side.  Testing a
 * bound a relative 1e-9 (and an absolute 1e-12 degrees) above the one asked for lets refinement
 * split such a triangle, so no triangle is left a few ulps below the user's bound, which the
 * validator holds the mesh to exactly.  The margin is far below anything a user can ask for.
 */
#include "bounds/bounds.h"

#include <math.h>
#include <stdio.h>

double bounds_refine_angle(double deg) {
    return deg > 0 ? deg * (1 + 1e-9) + 1e-12 : 0;
}

int bounds_check(double min_angle, double max_area, const char *angle_name, const char *area_name,
                 char *err, size_t errlen) {
    if (!(min_angle >= 0 && min_angle < BOUNDS_ANGLE_LIMIT)) {
        snprintf(err, errlen, "%s %g: must be at least 0 and below %g", angle_name, min_angle,
                 BOUNDS_ANGLE_LIMIT);
        return -1;
    }
    if (!(max_area >= 0) || isinf(max_area)) {
        snprintf(err, errlen, "%s %g: must be 0 (none) or a positive number", area_name, max_area);
        return -1;
    }
    return 0;
}

mesh_bounds bounds_make(double min_angle, double max_area, int64_t max_steiner, int circumcenters,
                        int lens) {
    mesh_bounds b = {0};
    b.min_angle = min_angle > 0 ? min_angle : 0;
    b.refine_angle = bounds_refine_angle(min_angle);
    b.max_area = max_area > 0 ? max_area : 0;
    b.max_steiner = max_steiner < 0 ? -1 : max_steiner;
    b.offcenter = !circumcenters;
    b.lens = lens;
    return b;
}

void bounds_set_size(mesh_bounds *b, bounds_size_fn fn, void *ctx) {
    b->size = fn;
    b->size_ctx = fn ? ctx : 0;
}

mesh_quality bounds_quality(const mesh_bounds *b) {
    mesh_quality q = {b->refine_angle, b->max_area, b->max_steiner, b->offcenter, b->lens};
    return q;
}

void bounds_apply(const mesh_bounds *b, mesh *m) {
    mesh_quality q = bounds_quality(b);
    mesh_set_quality(m, &q);
    if (b->size) mesh_set_size_rule(m, b->size, b->size_ctx);
}

void bounds_rules(const mesh_bounds *b, double area, mesh_rules *R) {
    mesh_rules_init(R, b->refine_angle, area, b->offcenter, b->lens);
    R->unsuitable = b->size;
    R->unsuitable_ctx = b->size_ctx;
}
