/* validate: the mesh validator.  A mesh is "correct" only when this says so.
 *
 * Checks, all topological ones with exact predicates:
 *  - every triangle counter-clockwise and non-degenerate; every vertex index in range;
 *  - conforming: every edge shared by at most two triangles, with opposite orientations; no
 *    two triangles overlap (total area equals the area enclosed by the boundary edges);
 *  - every input vertex present (as a mesh vertex with the same coordinates);
 *  - every input segment present as a chain of mesh edges along it (piece by piece, cut at
 *    the input vertices on it; a piece inside the removed region, both sides outside the
 *    domain, must be absent instead: pslg_segment_pieces);
 *  - a point set (no segments) is checked against its convex hull, whose edges are then its
 *    segments (the mesher makes them so);
 *  - every boundary edge of the mesh (one triangle) lies on an input segment;
 *  - area equal to the domain's (pslg_domain_area), to a relative 1e-9;
 *  - every interior edge that is not on an input segment (or on an interface constraint
 *    listed in the mesh's segments) is locally Delaunay (exact incircle, strict);
 *  - smallest angle >= min_angle (degrees) and area <= max_area, except triangles whose small
 *    angle is forced by the input (a triangle angle at an input vertex where two input
 *    segments meet at less than 60 degrees, or at a vertex on such a corner's segments).
 *
 * The exemption rule exactly: a "small corner" is an input vertex v with two angularly
 * consecutive input segments s1, s2 meeting at less than 60 degrees (pslg_input_angles).  A
 * triangle is exempt from the angle bound (never from the area bound) when (a) one of its
 * vertices is a small corner, or (b) two of its vertices lie on the two different segments s1
 * and s2 of the same small corner (on their chains of mesh edges, endpoints included): such a
 * triangle spans the narrow wedge.  Domains without input angles below 60 degrees get no
 * exemption at all.  Tolerances: an angle counts as below the bound when it is smaller than
 * min_angle - 1e-6 degrees, an area as above when it exceeds max_area * (1 + 1e-12): the
 * mesher measures with its own rounding.  Segment chains: intermediate vertices within
 * 1e-9 * |ab| (plus a few ulps of the coordinates) of the line ab, strictly monotone from a to
 * b.  Chains are walked over the mesh's listed segments (m->seg) and its boundary edges.  A
 * listed segment edge that lies on no input segment counts as an interface constraint
 * (sinterface may be NULL, e.g. after meshio_read_triangle).
 *
 * Regions (region_attr, region_area): the validator finds each triangle's region itself, from
 * the input alone (pslg_regions: the face of the segment arrangement strictly containing a
 * point strictly inside the triangle -- its centroid, or another barycentric point when
 * rounding puts the centroid on or outside an edge, checked by exact orient2d; a triangle with
 * no such point is not checked), never from the mesher's labels.  The attribute must equal the
 * region's exactly (0 outside every region); the area bound is the smaller of max_area and the
 * region's positive bound.
 */
#ifndef VALIDATE_H
#define VALIDATE_H

#include "geom/pslg.h"
#include "io/meshio.h"

#include <stdio.h>

typedef struct validate_opts {
    double min_angle;              /* degrees; 0 to skip */
    double max_area;               /* 0 to skip */
    int check_delaunay_interfaces; /* 1: edges on sinterface segments must be locally Delaunay */
    int part; /* 1: m is one rank's part of a distributed mesh (par_check_parts): input vertices
               * and segments whose endpoints or chains lie partly elsewhere are not required,
               * boundary edges may be interface edges (compared across ranks by the caller),
               * and the domain area is the caller's check (a sum over the parts) */
    int region_attr; /* 1: every triangle's attribute (m->tattr) is its region's (-A) */
    int region_area; /* 1: every triangle's area within its region's bound too (--region-areas) */
} validate_opts;

typedef struct validate_report {
    int ok;
    long ntris, nverts;
    double min_angle, max_area; /* measured over all triangles */
    double min_angle_unforced;  /* measured over triangles not exempted */
    double mesh_area, domain_area;
    /* the same two in the working scale of pslg_check (times 2^(2 scale_exp)): sums of parts'
     * areas are taken there, where tiny or huge inputs keep their precision */
    double mesh_area_w, domain_area_w;
    /* what rounded split points may move the area by, in the working scale (part of
     * validate_area_ok's tolerance; from the input alone, the same in every part) */
    double area_slack_w;
    long bad_orient, bad_conform, missing_verts, missing_segs, stray_boundary, non_delaunay,
        bad_angle, bad_area;
    long bad_region;         /* triangles whose attribute is not their region's (region_attr) */
    long area_mismatch;      /* 1 if the mesh area differs from the domain's (validate_area_ok) */
    long nexempt;            /* triangles exempted from the angle bound (not a failure) */
    char first_problem[256]; /* description of the first failure found */
} validate_report;

/* The part of the area tolerance that rounding alone explains, for an input whose largest
 * coordinate magnitude is mag and whose segments are seglen long in all (domain area dom): the
 * meshers keep the area's drift through rounded split points within 2^-49 mag times the
 * boundary's length, and use that allowance only while it is at most 2^-8 dom
 * (mesh_rules_area_drift); this is twice both, 2^-48 mag seglen capped at 2^-7 dom. */
static inline double validate_area_slack(double dom, double mag, double seglen) {
    double r = 0x1p-48 * mag * seglen, cap = 0x1p-7 * (dom < 0 ? -dom : dom);
    return r < cap ? r : cap;
}

/* 1 iff the mesh's area matches the domain's: within a relative 1e-9 plus slack
 * (validate_area_slack). */
static inline int validate_area_ok(double mesh_area, double dom, double slack) {
    double d = mesh_area - dom, a = mesh_area < 0 ? -mesh_area : mesh_area,
           b = dom < 0 ? -dom : dom;
    return (d < 0 ? -d : d) <= 1e-9 * (a > b ? a : b) + slack;
}

/* The cheap net the meshers run before they report success, without --check: 1 iff mesh_area,
 * the sum of the mesh's triangle areas in g's working scale (pslg_check), matches the area of
 * g's domain (*dom, working scale; validate_area_ok with validate_area_slack).  A point set
 * (no segments) passes: its domain is the hull the mesher made.  O(input) plus the input's
 * arrangement (pslg_domain_area).  Local. */
int validate_area_net(const pslg *g, double mesh_area, double *dom);

/* validate_area_net with the domain's area dom already known (pslg_domain_area of g, e.g.
 * computed ahead on another thread).  Local. */
int validate_area_net_at(const pslg *g, double mesh_area, double dom);

/* Validates m against input g.  Returns 1 if the mesh passes, else 0; r filled either way. */
int mesh_validate(const pslg *g, const mesh_flat *m, const validate_opts *o, validate_report *r);

/* One summary line: "meshcheck: OK triangles=N ..." or "meshcheck: FAIL ...". */
void validate_report_print(const validate_report *r, FILE *f);

#endif
