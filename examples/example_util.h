/* example_util.h: what the two examples share -- the domain they mesh and a writer of
 * Triangle's files (so ./meshcheck can validate the result).  Not part of the library. */
#ifndef EXAMPLE_UTIL_H
#define EXAMPLE_UTIL_H

#include <pcdm.h>

#include <stdio.h>

/* A 10 x 6 plate with a square hole (markers: 1 outside, 2 on the hole), a region attribute 7
 * and the hole point; coordinates that are not dyadic, so the library scales them inside. */
static const double ex_points[] = {0,   0,   10,  0,   10,  6,   0,   6,
                                   4.1, 2.3, 5.7, 2.3, 5.7, 3.9, 4.1, 3.9};
static const int32_t ex_segments[] = {0, 1, 1, 2, 2, 3, 3, 0, 4, 5, 5, 6, 6, 7, 7, 4};
static const int32_t ex_segmarkers[] = {1, 1, 1, 1, 2, 2, 2, 2};
static const double ex_holes[] = {4.9, 3.1};
static const double ex_regions[] = {1, 1, 7, 0};

static void ex_input(pcdm_input *in) {
    *in = (pcdm_input){.npoints = 8,
                       .points = ex_points,
                       .nsegments = 8,
                       .segments = ex_segments,
                       .segmentmarkers = ex_segmarkers,
                       .nholes = 1,
                       .holes = ex_holes,
                       .nregions = 1,
                       .regions = ex_regions};
}

/* The size rule: triangles with a corner within 1 of (0, 0) must be smaller than 0.005. */
static int ex_small_near_origin(void *ctx, const double *const c[3], double area) {
    (void)ctx;
    for (int i = 0; i < 3; i++)
        if (c[i][0] * c[i][0] + c[i][1] * c[i][1] < 1 && area > 0.005) return 1;
    return 0;
}

/* NAME.poly (the input) and NAME.1.node/.ele/.poly (the mesh), 1-based as Triangle's.
 * Returns 0, or -1 when a file cannot be written. */
static int ex_write(const char *name, const pcdm_mesh *m) {
    char path[1024];
    FILE *f;
    snprintf(path, sizeof path, "%s.poly", name);
    if (!(f = fopen(path, "w"))) return -1;
    fprintf(f, "8 2 0 0\n");
    for (int i = 0; i < 8; i++)
        fprintf(f, "%d %.17g %.17g\n", i + 1, ex_points[2 * i], ex_points[2 * i + 1]);
    fprintf(f, "8 1\n");
    for (int s = 0; s < 8; s++)
        fprintf(f, "%d %d %d %d\n", s + 1, ex_segments[2 * s] + 1, ex_segments[2 * s + 1] + 1,
                ex_segmarkers[s]);
    fprintf(f, "1\n1 %.17g %.17g\n", ex_holes[0], ex_holes[1]);
    if (fclose(f)) return -1;
    snprintf(path, sizeof path, "%s.1.node", name);
    if (!(f = fopen(path, "w"))) return -1;
    fprintf(f, "%d 2 0 1\n", m->npoints);
    for (int32_t i = 0; i < m->npoints; i++)
        fprintf(f, "%d %.17g %.17g %d\n", i + 1, m->points[2 * i], m->points[2 * i + 1],
                m->pointmarkers[i]);
    if (fclose(f)) return -1;
    snprintf(path, sizeof path, "%s.1.ele", name);
    if (!(f = fopen(path, "w"))) return -1;
    fprintf(f, "%d 3 %d\n", m->ntriangles, m->triangleattr ? 1 : 0);
    for (int32_t t = 0; t < m->ntriangles; t++) {
        fprintf(f, "%d %d %d %d", t + 1, m->triangles[3 * t] + 1, m->triangles[3 * t + 1] + 1,
                m->triangles[3 * t + 2] + 1);
        if (m->triangleattr) fprintf(f, " %.17g", m->triangleattr[t]);
        fprintf(f, "\n");
    }
    if (fclose(f)) return -1;
    snprintf(path, sizeof path, "%s.1.poly", name);
    if (!(f = fopen(path, "w"))) return -1;
    fprintf(f, "0 2 0 1\n%d 1\n", m->nsegments);
    for (int32_t s = 0; s < m->nsegments; s++)
        fprintf(f, "%d %d %d %d\n", s + 1, m->segments[2 * s] + 1, m->segments[2 * s + 1] + 1,
                m->segmentmarkers[s]);
    fprintf(f, "1\n1 %.17g %.17g\n", ex_holes[0], ex_holes[1]);
    return fclose(f) ? -1 : 0;
}

#endif
