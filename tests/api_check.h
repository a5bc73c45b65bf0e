/* api_check.h: what the library's tests (unit_api.c, mpi_api.c) share -- a plate with a hole
 * in non-dyadic coordinates (so the meshers scale it inside), a size rule that wants small
 * triangles near the origin and records the coordinates it was shown, and the validator run
 * on a pcdm_mesh (a mesh is correct only when mesh_validate says so). */
#ifndef API_CHECK_H
#define API_CHECK_H

#include "api/api_impl.h"
#include "check/validate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double plate_pts[] = {0,   0,   10,  0,   10,  6,   0,   6,
                                   4.1, 2.3, 5.7, 2.3, 5.7, 3.9, 4.1, 3.9};
static const int32_t plate_segs[] = {0, 1, 1, 2, 2, 3, 3, 0, 4, 5, 5, 6, 6, 7, 7, 4};
static const int32_t plate_smk[] = {1, 1, 1, 1, 2, 2, 2, 2};
static const int32_t plate_vmk[] = {5, 5, 5, 5, 6, 6, 6, 6};
static const double plate_hole[] = {4.9, 3.1};

static pcdm_input plate(void) {
    return (pcdm_input){.npoints = 8,
                        .points = plate_pts,
                        .pointmarkers = plate_vmk,
                        .nsegments = 8,
                        .segments = plate_segs,
                        .segmentmarkers = plate_smk,
                        .nholes = 1,
                        .holes = plate_hole};
}

/* Segments that enclose nothing but a hole (tests/inputs/hull/regions.poly): the domain is
 * there only with convex_hull (Triangle's -c): the 8 x 4 hull minus the 1 x 1 hole. */
static const double dangle_pts[] = {0, 0, 4, 0, 8, 0, 8, 2, 8, 4, 0, 4, 0,   1,
                                    8, 1, 2, 2, 3, 2, 3, 3, 2, 3, 5, 3, 6.5, 2.5};
static const int32_t dangle_segs[] = {6, 7, 0, 2, 4, 5, 8, 9, 9, 10, 10, 11, 11, 8, 12, 13};
static const int32_t dangle_smk[] = {0, 7, 3, 0, 0, 0, 0, 0};
static const double dangle_hole[] = {2.5, 2.5};
#define DANGLE_AREA (8.0 * 4.0 - 1.0)

static pcdm_input dangle(void) {
    return (pcdm_input){.npoints = 14,
                        .points = dangle_pts,
                        .nsegments = 8,
                        .segments = dangle_segs,
                        .segmentmarkers = dangle_smk,
                        .nholes = 1,
                        .holes = dangle_hole};
}

/* Returns the area of m's triangles (a mesh of dangle() with convex_hull); *ones counts its
 * segments on the hull's left and right edges (new: marker 1), *kept those on the bottom and
 * top (the input's segments there: markers 7 and 3); a wrong marker makes *ones negative. */
static double dangle_area(const pcdm_mesh *m, int32_t *ones, int32_t *kept) {
    double a = 0;
    for (int32_t t = 0; t < m->ntriangles; t++) {
        const int32_t *v = m->triangles + 3 * (size_t)t;
        const double *p = m->points + 2 * v[0], *q = m->points + 2 * v[1],
                     *r = m->points + 2 * v[2];
        a += 0.5 * ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
    }
    *ones = *kept = 0;
    for (int32_t s = 0; s < m->nsegments; s++) {
        const double *p = m->points + 2 * m->segments[2 * s],
                     *q = m->points + 2 * m->segments[2 * s + 1];
        int bottom = p[1] == 0 && q[1] == 0, top = p[1] == 4 && q[1] == 4;
        int side = (p[0] == 0 && q[0] == 0) || (p[0] == 8 && q[0] == 8);
        int mk = m->segmentmarkers[s];
        if (side && mk == 1) (*ones)++;
        if ((bottom && mk == 7) || (top && mk == 3)) (*kept)++;
        if ((bottom && mk != 7) || (top && mk != 3) || (side && mk != 1)) *ones = -1000000;
    }
    return a;
}

#define NEAR_R 1.0
#define NEAR_AREA 1e-3

typedef struct seen {
    double maxabs; /* largest coordinate the rule was shown */
    long calls;
} seen;

static int near_origin(const double *const c[3]) {
    for (int i = 0; i < 3; i++)
        if (c[i][0] * c[i][0] + c[i][1] * c[i][1] < NEAR_R * NEAR_R) return 1;
    return 0;
}

/* Too big: a corner within NEAR_R of the origin and an area above NEAR_AREA.  (Records what it
 * saw: only used where one thread refines.) */
static int small_near_origin(void *ctx, const double *const c[3], double area) {
    seen *s = ctx;
    if (s) {
        s->calls++;
        for (int i = 0; i < 3; i++)
            s->maxabs = fmax(s->maxabs, fmax(fabs(c[i][0]), fabs(c[i][1])));
    }
    return near_origin(c) && area > NEAR_AREA;
}

static double tri_area(const pcdm_mesh *m, int32_t t, const double *c[3]) {
    for (int k = 0; k < 3; k++)
        c[k] = m->points + 2 * (size_t)m->triangles[3 * (size_t)t + k];
    return 0.5 *
           ((c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[1][1] - c[0][1]) * (c[2][0] - c[0][0]));
}

/* Largest area of a triangle with a corner near the origin, and elsewhere. */
static void areas(const pcdm_mesh *m, double *near, double *far) {
    *near = *far = 0;
    for (int32_t t = 0; t < m->ntriangles; t++) {
        const double *c[3];
        double a = tri_area(m, t, c);
        if (near_origin(c))
            *near = fmax(*near, a);
        else
            *far = fmax(*far, a);
    }
}

/* 1 iff mesh_validate accepts m (a whole mesh) as a mesh of in within the bounds, in enclosed
 * by its convex hull if convex_hull (pcdm_options.convex_hull). */
static int valid_hull(const pcdm_input *in, const pcdm_mesh *m, double min_angle, double max_area,
                      int convex_hull) {
    pcdm_status st;
    pslg g;
    pcdm_options po;
    pcdm_options_default(&po);
    po.convex_hull = convex_hull;
    if (api_make_pslg(in, &po, &g, &st) != PCDM_OK) return 0;
    mesh_flat f;
    memset(&f, 0, sizeof f);
    f.nverts = m->npoints;
    f.xy = malloc(2 * (size_t)m->npoints * sizeof(double) + 8);
    for (size_t i = 0; i < 2 * (size_t)m->npoints; i++)
        f.xy[i] = ldexp(m->points[i], g.scale_exp); /* exact: the mesher's working units */
    f.scale_exp = g.scale_exp;
    f.ntris = m->ntriangles;
    f.tri = m->triangles;
    f.nsegs = m->nsegments;
    f.seg = m->segments;
    f.smarker = m->segmentmarkers;
    validate_opts o = {.min_angle = min_angle, .max_area = max_area};
    validate_report r;
    int ok = mesh_validate(&g, &f, &o, &r);
    if (!ok) validate_report_print(&r, stderr);
    free(f.xy);
    pslg_free(&g);
    return ok;
}

/* valid_hull without the hull: the domain the segments enclose. */
static int valid(const pcdm_input *in, const pcdm_mesh *m, double min_angle, double max_area) {
    return valid_hull(in, m, min_angle, max_area, 0);
}

#endif
