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

/* Inline on every mesher's hot path, whatever the compiler's estimate of its size. */
#if defined(__GNUC__)
#define MESH_RULES_INLINE static inline __attribute__((always_inline))
#else
#define MESH_RULES_INLINE static inline
#endif

/* The bounds and the derived constants (mesh_rules_init). */
typedef struct mesh_rules {
    double min_angle; /* degrees, clamped to [0, 60] */
    double max_area;  /* 0: no area bound */
    int offcenter;    /* 1: Ungor's off-centers when closer than the circumcenter */
    int lens;         /* 1: diametral lenses (Shewchuk 2002 sec. 4) instead of circles */
    double cosb;      /* cos(min_angle); 1 when there is no angle bound */
    double offfac;    /* off-center height / shortest edge (with a 5% margin) */
    double cos2b;     /* cos(2 * min_angle) for lenses; 1: circles */
    /* A caller's size rule (Triangle's triunsuitable, without recompiling; NULL: none): called
     * by mesh_rules_bad with the counter-clockwise triangle's vertices (in the mesher's internal
     * coordinates: the input's times 2^scale_exp, see pslg.h) and its area; nonzero: too big
     * (MESH_BAD_AREA).  Must be a pure function of its arguments and thread-safe (the parallel
     * meshers call it on every rank). */
    int (*unsuitable)(void *ctx, const double *const p[3], double area);
    void *unsuitable_ctx;
} mesh_rules;

/* Fills R from the bounds (min_angle in degrees, <= 0: none; max_area <= 0: none). */
void mesh_rules_init(mesh_rules *R, double min_angle, double max_area, int offcenter, int lens);

/* Bits of mesh_rules_bad. */
enum { MESH_BAD_ANGLE = 1, MESH_BAD_AREA = 2 };

/* Quality of the counter-clockwise triangle p[0] p[1] p[2]: MESH_BAD_ANGLE if its smallest
 * angle is below the bound, MESH_BAD_AREA if its area is above the bound or R->unsuitable says
 * it is too big, 0 if good.
 * *sh (may be NULL): index j of the shortest edge (p[j] -> p[j+1]); *short2 (may be NULL): its
 * squared length. */
int mesh_rules_bad(const mesh_rules *R, const double *const p[3], int *sh, double *short2);

/* mesh_rules_bad with the area bound max_area (<= 0: none) in place of R->max_area: a triangle
 * in a region with its own bound (the .poly's regional area constraints, Triangle's -a without
 * a number) is tested against mesh_rules_area_bound(R->max_area, region bound). */
MESH_RULES_INLINE int mesh_rules_bad_bound(const mesh_rules *R, double max_area,
                                           const double *const p[3], int *sh, double *short2);

/* The area bound of a triangle in a region with bound region (<= 0: none) when the global bound
 * is global (<= 0: none): the smaller of the positive ones, 0 if neither. */
static inline double mesh_rules_area_bound(double global, double region) {
    if (!(region > 0)) return global > 0 ? global : 0;
    return global > 0 && global < region ? global : region;
}

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

/* Split point of the interface subsegment named (level, k) of interface segment ab (the k-th of
 * the 2^level pieces of its binary split tree).  The tree: the whole segment is split on the
 * power-of-two shell around a (the largest 2^j at most 2/3 |ab|), the piece left beside b on
 * the power-of-two shell around b, every other piece at its midpoint.  So every piece touching
 * an end of an interface segment is a power of two long, and at a vertex where interface
 * segments (or an interface and a boundary segment split on the same shells) bend, the pieces
 * on both sides can become equal: a corner triangle between two pieces in a length ratio that
 * is not a power of two keeps its smallest angle at every scale, and refinement runs into the
 * length floor there (Ruppert 1995's concentric shells, applied to the artificial corners of a
 * decomposition).  A function of its arguments only, so both sides of an interface compute the
 * same bits. */
void mesh_rules_iface_point(const double a[2], const double b[2], int32_t level, int64_t k,
                            double out[2]);

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

/* Number of priority buckets of mesh_rules_bucket. */
#define MESH_RULES_NBUCKET 4096

/* Queue priority of a bad triangle whose squared shortest edge is short2 (mesh_rules_bad's
 * *short2): the binary exponent of short2, offset into [0, MESH_RULES_NBUCKET), smallest
 * first -- shortest edges first, as refine.c orders them (and Triangle). */
int mesh_rules_bucket(double short2);

/* The squared length floor below which refinement refuses to make an edge, from the initial
 * triangulation (xy: 2 per vertex, nv vertices; tv: 3 vertex indices per triangle, nt
 * triangles, a triangle with tv[3t] < 0 is skipped): the larger of 2^-48 times its smallest
 * squared altitude and 2^-88 times the coordinates' squared magnitude (README, Robustness).
 * Every mesher computes it from the same initial CDT, so they all refuse alike. */
double mesh_rules_length_floor2(const double *xy, int32_t nv, const int32_t *tv, int32_t nt);

/* How many refusals (new edges below the length floor) refinement accepts before it decides
 * that it diverges and stops (refine.c's MESH_REFINE_UNRESOLVED): 256 + ninput / 4. */
int64_t mesh_rules_unresolved_budget(int32_t ninput);

/* 1 iff the split point p of the subsegment (pu, pv) lies off the segment's line by more than
 * a sixteenth of the height over it of w1 or w2 (the apexes of the triangles beside it; NULL:
 * none): a region thinner there than the precision of its coordinates (a fuzzed triangle 8e19
 * long and at most 821 wide, whose rounded midpoint of one side lay beyond it: the mesh grew
 * outside the domain and another segment's chain ran through the new vertex).  Rounding moves a
 * split point by about an ulp, so this refuses only splits beside triangles a few ulps high; a
 * refused split counts as failed (precision exhausted).  Deciding whether to refine, not
 * topology (the cavity's orientation tests stay exact), so rounded magnitudes do. */
int mesh_rules_off_line(const double pu[2], const double pv[2], const double p[2], const double *w1,
                        const double *w2);

/* mesh_rules_off_line, or a point off the line that makes the new edge from w1 or w2 to p not
 * locally Delaunay in the two-triangle fan (pu, p, w), (p, pv, w) (exact incircle: the other
 * end of the subsegment inside the circle through p, w and this end), which the heights alone
 * miss beside a triangle obtuse at an end of the subsegment (its apex far along the line).
 * For ./pbw, where each side's owner decides a split with its own apex and a cavity across
 * ranks commits that fan (a 2.8e-17 offset made a non-Delaunay edge there).  refine.c keeps
 * mesh_rules_off_line: its Bowyer-Watson cavity takes every triangle whose circumcircle holds
 * p, often more than the one triangle, so this fan is not what it commits, and the test refused
 * good splits (on a 49,152-vertex coastline ./pcdm at 3-8 ranks refused interface pieces on
 * one side and could not finish). */
int mesh_rules_off_line_fan(const double pu[2], const double pv[2], const double p[2],
                            const double *w1, const double *w2);

/* A rounded split point lies within 2^-MESH_RULES_ULP_EXP times the coordinates' magnitude
 * of its segment's line (each coordinate of a + (b - a) f is off by at most about an ulp of the
 * larger of |a|, |b|: 2^-52 of it).  The validator's chain test accepts as much (8 ulps), its
 * area test twice the area that explains (validate_area_slack). */
#define MESH_RULES_ULP_EXP 49

/* The domain's area may drift by at most this much in all through split points of boundary
 * subsegments (a side outside the domain) that rounding put off their line: 2^-30 of the area
 * (just under the validator's relative tolerance of 1e-9), plus what rounding alone explains:
 * every vertex of a boundary segment's chain within 2^-MESH_RULES_ULP_EXP mag of its line
 * (mag: the largest coordinate magnitude) moves the area by at most that times the segment's
 * length, so that times bperim, the length of the domain's boundary.  That second term counts
 * only when it is at most 2^-8 of the area, i.e. the domain is on average wider than about
 * 2^-40 mag (the precision model, README, Robustness); a thinner domain, a sliver along which
 * rounded split points move by more than its width, keeps the relative budget alone, which
 * stops its refinement early (a fuzzed point set 6.7e21 long and a few units wide).  The
 * validator's tolerance is at least twice each term (validate_area_slack). */
double mesh_rules_area_drift(double area, double mag, double bperim);

/* Split point p of the boundary subsegment (pu, pv), whose inside triangle has apex w, moves
 * the domain's area by |orient2d(pu, pv, p)| / 2: down if p is on w's side, up otherwise.
 * *drift is the signed sum of the moves so far (rounding puts split points on either side, so
 * on ordinary inputs it stays near 0 while the moves' magnitudes add up).  1 iff this move
 * would take |*drift| past budget (the split is refused: precision exhausted on a sliver,
 * counted as a refusal); otherwise it is added to *drift and 0 returned.  Deciding whether to
 * refine, not topology: rounded magnitudes do (the side of p is exact). */
int mesh_rules_drift_spend(const double pu[2], const double pv[2], const double p[2],
                           const double w[2], double budget, double *drift);

/* At most this many pieces per input segment (interface segments of the decomposition have
 * their own, name-based rule): near a small feature splits shrink the pieces geometrically,
 * but along a sliver of width w and length L every piece stays encroached by the other side
 * until the segment has about L / w pieces (8e29 for a fuzzed quadrilateral 8e29 long and 2
 * wide, which split until memory ran out).  Past the limit (a region of aspect ratio above a
 * million, or a mesh of about 10^12 triangles) a split is refused like one below the length
 * floor: the refusal budget then ends refinement with "cannot meet the bounds". */
#define MESH_RULES_MAX_PIECES ((int32_t)1 << 20)

/* At most this many pieces an interface segment of a parallel decomposition splits itself into
 * (its own decisions; a neighbour's requests are always applied).  Two segments meeting at an
 * angle t (radians) encroach each other's pieces until they are shorter than about t times
 * their distance from the vertex: about 1 / t pieces per doubling of that distance, which a
 * decomposition of a degenerate input (cuts 1e-10 degrees apart) makes practically endless.
 * Room for a cut through 10^9 triangles; PCDM refuses decompositions with interfaces meeting
 * below 1 / MESH_RULES_IFACE_MAX_PIECES radians (pcdm_part_build). */
#define MESH_RULES_IFACE_MAX_PIECES ((int32_t)1 << 16)

/* The input facts the forced-angle rule needs (pointers borrowed from the caller). */
typedef struct mesh_rules_input {
    int32_t ninput;                   /* input vertices are 0 .. ninput-1 */
    const double *xy;                 /* input vertex i at xy[2i], xy[2i+1] */
    const int32_t *seg;               /* segment s joins input vertices seg[2s], seg[2s+1] */
    const int32_t *inc_off, *inc_seg; /* CSR: the segments at each input vertex */
    const uint8_t *corner;            /* ninput: 1 at a corner below 60 degrees (NULL: none) */
    const uint8_t *siface;            /* per segment: 1 = interface, not input (NULL: none) */
} mesh_rules_input;

/* 1 iff the small angle of a skinny triangle whose shortest edge is uv is forced by the input:
 * u and v lie on two angularly consecutive input segments (mesh_rules_in_wedge: no other input
 * segment between them) of a corner below 60 degrees, at the same distance from it
 * (mesh_rules_corner_forced).  A vertex is given as its input id (u < I->ninput) or as -1 and
 * useg, the original segment a Steiner vertex lies on (-1: none, then the answer is 0); pu is
 * its position.  Interface segments never count: their corners are not the input's. */
int mesh_rules_edge_forced(const mesh_rules_input *I, int32_t u, int32_t useg, const double pu[2],
                           int32_t v, int32_t vseg, const double pv[2]);

/* mesh_rules_bad_bound, inline: it runs on every new triangle of every mesher (about 8 per
 * inserted vertex).  The test as stated: edge j runs p[j] -> p[j+1]; the smallest angle is at
 * the apex of the shortest edge j, between edges j+1 and j+2, and it is below the bound iff
 * its cosine d / sqrt(l[j+1] l[j+2]) exceeds cos b, on squared lengths: d > 0 and
 * d^2 > cos^2 b l[j+1] l[j+2] (no sqrt, no acos).  Which edge is shortest, and which side of
 * the bound a triangle falls, are coin flips on a mesh, and the mispredicted branches cost more
 * than the arithmetic; so the test is evaluated at all three apexes with the same operations
 * in the same order, and the shortest edge's verdict is picked by its index: no branch on the
 * data, and every decision bit for bit the one of the plain statement. */
MESH_RULES_INLINE int mesh_rules_bad_bound(const mesh_rules *R, double max_area,
                                           const double *const p[3], int *sh, double *short2) {
    const double *p0 = p[0], *p1 = p[1], *p2 = p[2];
    double l[3];
    double x0 = p1[0] - p0[0], y0 = p1[1] - p0[1];
    double x1 = p2[0] - p1[0], y1 = p2[1] - p1[1];
    double x2 = p0[0] - p2[0], y2 = p0[1] - p2[1];
    l[0] = x0 * x0 + y0 * y0;
    l[1] = x1 * x1 + y1 * y1;
    l[2] = x2 * x2 + y2 * y2;
    /* j = (l0 <= l1 && l0 <= l2) ? 0 : (l1 <= l2) ? 1 : 2, from flags */
    unsigned first = (l[0] <= l[1]) & (l[0] <= l[2]), second = l[1] <= l[2];
    unsigned j = (1u - first) * (2u - second);
    if (sh) *sh = (int)j;
    if (short2) *short2 = l[j];
    /* apex of edge 0 (edges 1, 2), of edge 1 (edges 2, 0), of edge 2 (edges 0, 1) */
    double cb2 = R->cosb * R->cosb;
    double d0 = -(x1 * x2 + y1 * y2), d1 = -(x2 * x0 + y2 * y0), d2 = -(x0 * x1 + y0 * y1);
    unsigned b0 = (d0 > 0) & (d0 * d0 > cb2 * l[1] * l[2]);
    unsigned b1 = (d1 > 0) & (d1 * d1 > cb2 * l[2] * l[0]);
    unsigned b2 = (d2 > 0) & (d2 * d2 > cb2 * l[0] * l[1]);
    unsigned verdict = b0 | b1 << 1 | b2 << 2;
    int res = (int)((verdict >> j) & (R->cosb < 1.0)); /* MESH_BAD_ANGLE */
    if (max_area > 0 || R->unsuitable) {
        double area = 0.5 * (x0 * -y2 - y0 * -x2);
        res |= (int)((max_area > 0) & (area > max_area)) << 1; /* MESH_BAD_AREA */
        if (R->unsuitable && !(res & MESH_BAD_AREA) && R->unsuitable(R->unsuitable_ctx, p, area))
            res |= MESH_BAD_AREA;
    }
    return res;
}

#endif
