/* rules: the refinement rules every mesher shares -- what is a bad triangle, where its Steiner
 * point goes, when a point encroaches a subsegment, where a subsegment at a small input corner
 * is split, and which small angles the input forces.  Pure functions of coordinates and of the
 * few facts a mesh must supply (which vertex is a small corner, the other segments there); no
 * mesh type, no state, so ./mesh (refine.c) and the parallel meshers can call the same code
 * and agree bit for bit.  (Like CGAL Mesh_2's Face_badness, kept apart from the refiner.)
 *
 * All functions are Local and thread-safe; the topological parts (encroachment, the wedge
 * test) use the exact predicates of geom/geom.h, the rest is rounded arithmetic that decides
 * only where points go and whether to split.
 */
#ifndef RULES_H
#define RULES_H

#include <stdint.h>

/* The bounds and the derived constants (mesh_rules_init). */
typedef struct mesh_rules {
    double min_angle; /* degrees, clamped to [0, 60] */
    double max_area;  /* 0: no area bound */
    int offcenter;    /* 1: Ungor's off-centers when closer than the circumcenter */
    int lens;         /* 1: diametral lenses (Shewchuk 2002 sec. 4) instead of circles */
    double cosb;      /* cos(min_angle); 1 when there is no angle bound */
    double offfac;    /* off-center height / shortest edge (with a 5% margin) */
    double cos2b;     /* cos(2 * min_angle) for lenses; 1: circles */
} mesh_rules;

/* Fills R from the bounds (min_angle in degrees, <= 0: none; max_area <= 0: none). */
void mesh_rules_init(mesh_rules *R, double min_angle, double max_area, int offcenter, int lens);

/* Bits of mesh_rules_bad. */
enum { MESH_BAD_ANGLE = 1, MESH_BAD_AREA = 2 };

/* Quality of the counter-clockwise triangle p[0] p[1] p[2]: MESH_BAD_ANGLE if its smallest
 * angle is below the bound, MESH_BAD_AREA if its area is above the bound, 0 if good.
 * *sh (may be NULL): index j of the shortest edge (p[j] -> p[j+1]); *short2 (may be NULL): its
 * squared length. */
int mesh_rules_bad(const mesh_rules *R, const double *const p[3], int *sh, double *short2);

/* Steiner point of bad triangle p[0] p[1] p[2] whose shortest edge is sh: the circumcenter,
 * or with R->offcenter Ungor's off-center on the shortest edge's bisector when it is closer
 * (Ungor, "Off-centers", LATIN 2004).  Returns 0, or -1 if the triangle is degenerate. */
int mesh_rules_steiner(const mesh_rules *R, const double *const p[3], int sh, double out[2]);

/* Does p encroach subsegment ab?  The diametral circle (exact, geom_encroaches), or with
 * R->lens the diametral lens: the angle apb exceeds 180 - 2 * min_angle. */
int mesh_rules_encroaches(const mesh_rules *R, const double a[2], const double b[2],
                          const double p[2]);

/* Split point of the subsegment from small input corner a to w on the concentric shells of
 * radius unit * 2^j around a (Ruppert 1995; Shewchuk 2002 sec. 5): the largest shell radius
 * at most 2/3 |aw|, or the midpoint when that falls outside (0.3, 0.7) of the length. */
void mesh_rules_shell_point(const double a[2], const double w[2], double unit, double out[2]);

/* 1 iff the ray from a through o3 lies strictly inside the wedge o1-a-o2 (< 180 degrees), by
 * exact orientation tests: segment a-o3 separates a-o1 from a-o2, so those two are not angular
 * neighbours at a. */
int mesh_rules_in_wedge(const double a[2], const double o1[2], const double o2[2],
                        const double o3[2]);

/* 1 iff the small angle of a triangle whose shortest edge is uv is forced by the input corner
 * a between segments a-o1 (u on it) and a-o2 (v on it): the corner is below 60 degrees and u, v
 * are at the same distance from a (within 1%), so no split can improve it. */
int mesh_rules_corner_forced(const double a[2], const double o1[2], const double o2[2],
                             const double u[2], const double v[2]);

#endif
