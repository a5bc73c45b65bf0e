/* validate_input: the validator's checks of a mesh against its input (validate.h).
 *
 * Input vertices are found by hashing their exact coordinates.  Each input segment, cut at the
 * input vertices on it (pslg_segment_pieces), must be a chain of the mesh's segment and
 * boundary edges from one end to the other: strictly monotone along the segment and within
 * rounding distance of its line (refinement splits segments at rounded points), and a piece
 * on no side of the domain must be absent instead; every boundary edge must lie on such a
 * chain.  Quality bounds exempt a triangle whose small angle the input forces: one at a small
 * input corner (two segments meeting below 60 degrees, pslg_input_angles), or one spanning
 * such a corner's wedge with vertices on both of its segments' chains (the exact rule in
 * validate.h).  Regions are found from the input alone (pslg_regions: the face of the segment
 * arrangement holding a point exactly inside each triangle), never from the mesher's labels.
 * Every side test is the exact geom_orient2d; rounded arithmetic only measures angles, areas
 * and distances against the bounds and tolerances validate.h states.
 */
#include "check/validate.h"

#include "base/base.h"
#include "check/validate_impl.h"
#include "geom/geom.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- small corners --------- */

static void gap_cb(void *ctx, int32_t v, int32_t s1, int32_t s2, double deg) {
    gaplist *L = ctx;
    if (L->n == L->cap) {
        L->cap = L->cap ? 2 * L->cap : 16;
        L->g = mesh_xrealloc(L->g, (size_t)L->cap, sizeof *L->g);
    }
    L->g[L->n++] = (gap){v, s1, s2};
}

static int cmp_vtag(const void *pa, const void *pb) {
    const vtag *a = pa, *b = pb;
    if (a->v != b->v) return a->v < b->v ? -1 : 1;
    if (a->k != b->k) return a->k < b->k ? -1 : 1;
    return a->side - b->side;
}

/* 6. input vertices: exact coordinates, by hash */
void validate_input_vertices(vctx *c) {
    const pslg *g = c->g;
    const double *xy = c->xy;
    int32_t gn = g ? g->nverts : 0;
    c->gmap = mesh_xmalloc((size_t)gn + 1, sizeof *c->gmap);
    size_t gns = 16;
    while (gns < 2 * (size_t)gn + 2)
        gns *= 2;
    int32_t *gslot = mesh_xmalloc(gns, sizeof *gslot), *gmap = c->gmap;
    memset(gslot, 0xff, gns * sizeof *gslot);
    for (int32_t i = 0; i < gn; i++) {
        double x = g->xy[2 * i] + 0.0, y = g->xy[2 * i + 1] + 0.0;
        uint64_t bx, by;
        memcpy(&bx, &x, 8);
        memcpy(&by, &y, 8);
        size_t h = mesh_hash64(bx ^ mesh_hash64(by)) & (gns - 1);
        gmap[i] = -1;
        while (gslot[h] >= 0 && !(g->xy[2 * gslot[h]] == x && g->xy[2 * gslot[h] + 1] == y))
            h = (h + 1) & (gns - 1);
        if (gslot[h] < 0)
            gslot[h] = i;
        else
            gmap[i] = -2 - gslot[h]; /* duplicate input vertex: resolved below */
    }
    for (int32_t i = 0; i < c->nv; i++) {
        double x = xy[2 * i] + 0.0, y = xy[2 * i + 1] + 0.0;
        uint64_t bx, by;
        memcpy(&bx, &x, 8);
        memcpy(&by, &y, 8);
        size_t h = mesh_hash64(bx ^ mesh_hash64(by)) & (gns - 1);
        while (gslot[h] >= 0) {
            int32_t gi = gslot[h];
            if (g->xy[2 * gi] == x && g->xy[2 * gi + 1] == y) {
                if (gmap[gi] == -1) gmap[gi] = i;
                break;
            }
            h = (h + 1) & (gns - 1);
        }
    }
    free(gslot);
    for (int32_t i = 0; i < gn; i++) {
        if (gmap[i] <= -2) gmap[i] = gmap[-2 - gmap[i]];
        if (gmap[i] < 0 && !c->o->part) {
            c->r->missing_verts++;
            validate_problem(
                c->r, "input vertex %d (line %d) at (%.17g, %.17g) is not a mesh vertex",
                i + g->first_index, g->vline ? g->vline[i] : 0, g->xy[2 * i], g->xy[2 * i + 1]);
        }
    }
}

/* 7. small input corners and the segments that form them */
void validate_small_corners(vctx *c) {
    const pslg *g = c->g;
    c->vflag = mesh_xcalloc((size_t)c->nv + 1, 1);
    gaplist *gl = &c->gl;
    if (g && g->nsegs > 0) pslg_input_angles(g, 60.0, gap_cb, gl);
    int32_t gsn = g ? g->nsegs : 0;
    c->tstart = mesh_xcalloc((size_t)gsn + 2, sizeof *c->tstart);
    c->tags = mesh_xmalloc((size_t)gl->n * 2 + 1, sizeof *c->tags);
    int32_t *tstart = c->tstart;
    for (int32_t k = 0; k < gl->n; k++) {
        tstart[gl->g[k].s1 + 1]++;
        tstart[gl->g[k].s2 + 1]++;
        if (c->gmap[gl->g[k].v] >= 0) c->vflag[c->gmap[gl->g[k].v]] |= 1;
    }
    for (int32_t s = 0; s < gsn; s++)
        tstart[s + 1] += tstart[s];
    for (int32_t k = 0; k < gl->n; k++) {
        int32_t *p1 = c->tags[tstart[gl->g[k].s1]++], *p2 = c->tags[tstart[gl->g[k].s2]++];
        p1[0] = k;
        p1[1] = 0;
        p2[0] = k;
        p2[1] = 1;
    }
    for (int32_t s = gsn; s > 0; s--)
        tstart[s] = tstart[s - 1];
    tstart[0] = 0;
}

/* Records that mesh vertex v lies on side `side` of small corner k. */
static void tag_vertex(vctx *c, int32_t v, int32_t k, int32_t side) {
    if (c->nvt == c->capvt) {
        c->capvt = c->capvt ? 2 * c->capvt : 256;
        c->vt = mesh_xrealloc(c->vt, c->capvt, sizeof *c->vt);
    }
    c->vt[c->nvt++] = (vtag){v, k, side};
    c->vflag[v] |= 2;
}

/* The chain of mesh edges (indices into T) along input segment s: from the mesh vertex of its
 * first endpoint, each step to a neighbour farther along the segment that lies within rounding
 * distance of it; among those, the step whose direction deviates least from the segment's (so
 * a neighbouring segment at a tiny angle, whose vertices are also within rounding distance,
 * does not lure the walk away), then the nearest.  Returns the number of edges, or -1 if the
 * chain does not reach the other endpoint.  chainv gets the chain's vertices. */
static int32_t trace_chain(const vctx *c, int32_t S0, int32_t S1, int32_t A, int32_t B,
                           const int32_t *astart, const int32_t (*adj)[2], int32_t *chain,
                           int32_t *chainv) {
    const double *xy = c->xy;
    const double *pa = xy + 2 * S0, *pb = xy + 2 * S1;
    double dx = pb[0] - pa[0], dy = pb[1] - pa[1], L2 = dx * dx + dy * dy, L = sqrt(L2);
    double mag = fmax(fmax(fabs(pa[0]), fabs(pa[1])), fmax(fabs(pb[0]), fabs(pb[1])));
    double tol = (1e-9 * L + 8 * DBL_EPSILON * mag) * L; /* bound on |cross| */
    int32_t cur = A, nch = 0;
    double tcur = ((xy[2 * A] - pa[0]) * dx + (xy[2 * A + 1] - pa[1]) * dy) / L2;
    chainv[0] = A;
    while (cur != B && nch < c->T.n) {
        int32_t best = -1, brec = -1;
        double bt = INFINITY, bdev = INFINITY;
        const double *pc = xy + 2 * cur;
        for (int32_t i = astart[cur]; i < astart[cur + 1]; i++) {
            int32_t w = adj[i][0];
            const double *q = xy + 2 * w;
            double t;
            double qx = q[0] - pa[0], qy = q[1] - pa[1];
            if (w == B) { /* the piece's end, through a segment or boundary edge: the chain
                           * ends here (a sliver's far vertex may also pass the distance test,
                           * e.g. two hull edges 1e-50 radians apart: never detour through it) */
                best = w;
                brec = adj[i][1];
                bt = (qx * dx + qy * dy) / L2;
                break;
            }
            if (fabs(dx * qy - dy * qx) > tol) continue;
            t = (qx * dx + qy * dy) / L2;
            if (!(t > tcur && t < 1)) continue;
            double sx = q[0] - pc[0], sy = q[1] - pc[1];
            double dev = fabs(dx * sy - dy * sx) / (L * sqrt(sx * sx + sy * sy));
            if (dev < bdev || (dev == bdev && t < bt)) {
                bdev = dev;
                bt = t;
                best = w;
                brec = adj[i][1];
            }
        }
        if (best < 0) break;
        chain[nch++] = brec;
        chainv[nch] = best;
        cur = best;
        tcur = bt;
    }
    return cur == B ? nch : -1;
}

/* Part mode (validate.h): the chain of input segment s is not whole in this part, so its
 * corner tags go to every vertex of a segment or boundary edge that lies on s, by the chain's
 * own distance test. */
static void tag_partial_chain(vctx *c, int32_t s, const int32_t *astart) {
    if (c->tstart[s] == c->tstart[s + 1]) return; /* s forms no small corner */
    const double *pa = c->g->xy + 2 * c->g->seg[2 * s], *pb = c->g->xy + 2 * c->g->seg[2 * s + 1];
    double dx = pb[0] - pa[0], dy = pb[1] - pa[1], L2 = dx * dx + dy * dy, L = sqrt(L2);
    double mag = fmax(fmax(fabs(pa[0]), fabs(pa[1])), fmax(fabs(pb[0]), fabs(pb[1])));
    double tol = (1e-9 * L + 8 * DBL_EPSILON * mag) * L;
    for (int32_t v = 0; v < c->nv; v++) {
        if (astart[v] == astart[v + 1]) continue; /* on no segment or boundary edge */
        double qx = c->xy[2 * v] - pa[0], qy = c->xy[2 * v + 1] - pa[1];
        double t = (qx * dx + qy * dy) / L2;
        if (fabs(dx * qy - dy * qx) > tol || t < 0 || t > 1) continue;
        for (int32_t q = c->tstart[s]; q < c->tstart[s + 1]; q++)
            tag_vertex(c, v, c->tags[q][0], c->tags[q][1]);
    }
}

/* 8. input segments as chains over segment and boundary edges */
void validate_input_segments(vctx *c) {
    const pslg *g = c->g;
    validate_report *r = c->r;
    const double *xy = c->xy;
    etab *T = &c->T;
    int32_t nv = c->nv, gsn = g ? g->nsegs : 0;
    int32_t *astart = mesh_xcalloc((size_t)nv + 2, sizeof *astart);
    int32_t(*adj)[2] = mesh_xmalloc((size_t)T->n * 2 + 1, sizeof *adj);
    int32_t *chain = mesh_xmalloc((size_t)T->n + 1, sizeof *chain);
    int32_t *chainv = mesh_xmalloc((size_t)T->n + 2, sizeof *chainv);
    for (int32_t k = 0; k < T->n; k++) { /* chains use real mesh edges only */
        if (!(T->rec[k].flags & E_INMESH)) continue;
        astart[T->rec[k].u + 1]++;
        astart[T->rec[k].v + 1]++;
    }
    for (int32_t v = 0; v < nv; v++)
        astart[v + 1] += astart[v];
    for (int32_t k = 0; k < T->n; k++) {
        if (!(T->rec[k].flags & E_INMESH)) continue;
        int32_t *p = adj[astart[T->rec[k].u]++];
        p[0] = T->rec[k].v;
        p[1] = k;
        p = adj[astart[T->rec[k].v]++];
        p[0] = T->rec[k].u;
        p[1] = k;
    }
    for (int32_t v = nv; v > 0; v--)
        astart[v] = astart[v - 1];
    astart[0] = 0;
    if (g) pslg_segment_pieces(g, &c->pc);
    for (int32_t s = 0; s < gsn; s++) {
        int32_t A = c->gmap[g->seg[2 * s]], B = c->gmap[g->seg[2 * s + 1]];
        if (c->o->part && (A < 0 || B < 0)) { /* an endpoint in another part */
            tag_partial_chain(c, s, astart);
            continue;
        }
        if (A < 0 || B < 0 || A == B) {
            r->missing_segs++;
            validate_problem(
                r, "input segment %d (line %d) is missing: an endpoint is not in the mesh",
                s + g->first_index, g->sline ? g->sline[s] : 0);
            continue;
        }
        /* each piece that borders the domain (pieces inside the removed region have no edges):
         * its chain's edges are input edges, its vertices lie on s (tags of s's corners) */
        int ok = 1;
        for (int32_t i = c->pc.start[s]; i + 1 < c->pc.start[s + 1] && ok; i++) {
            if (!c->pc.border[i]) continue;
            int32_t P = c->gmap[c->pc.vert[i]], Q = c->gmap[c->pc.vert[i + 1]];
            int32_t nch = P < 0 || Q < 0 ? -1
                                         : trace_chain(c, A, B, P, Q, astart,
                                                       (const int32_t(*)[2])adj, chain, chainv);
            if (nch < 0) {
                ok = 0;
                break;
            }
            for (int32_t j = 0; j < nch; j++)
                T->rec[chain[j]].flags |= E_INPUT;
            for (int32_t q = c->tstart[s]; q < c->tstart[s + 1]; q++)
                for (int32_t j = 0; j <= nch; j++)
                    tag_vertex(c, chainv[j], c->tags[q][0], c->tags[q][1]);
        }
        if (!ok && c->o->part) { /* the chain leaves this part */
            tag_partial_chain(c, s, astart);
            continue;
        }
        if (!ok) {
            const double *pa = xy + 2 * A, *pb = xy + 2 * B;
            r->missing_segs++;
            validate_problem(
                r,
                "input segment %d (line %d) from (%.17g, %.17g) to (%.17g, %.17g) is not "
                "a chain of mesh segment/boundary edges",
                s + g->first_index, g->sline ? g->sline[s] : 0, pa[0], pa[1], pb[0], pb[1]);
        }
    }
    for (int32_t k = 0; k < T->n; k++)
        if ((T->rec[k].flags & E_BND) && !(T->rec[k].flags & E_INPUT) && !c->o->part) {
            r->stray_boundary++;
            const double *p = xy + 2 * T->rec[k].u, *q = xy + 2 * T->rec[k].v;
            validate_problem(
                r,
                "boundary edge (%d, %d) from (%.17g, %.17g) to (%.17g, %.17g) lies on no "
                "input segment",
                T->rec[k].u, T->rec[k].v, p[0], p[1], q[0], q[1]);
        }
    if (c->nvt > 1) { /* sort and drop repeats */
        qsort(c->vt, c->nvt, sizeof *c->vt, cmp_vtag);
        size_t w = 1;
        for (size_t i = 1; i < c->nvt; i++)
            if (cmp_vtag(&c->vt[i], &c->vt[w - 1]) != 0) c->vt[w++] = c->vt[i];
        c->nvt = w;
    }
    free(astart);
    free(adj);
    free(chain);
    free(chainv);
}
/* Smallest angle of abc in degrees: the angle opposite the shortest edge, by atan2. */
static double tri_min_angle(const double *a, const double *b, const double *c) {
    const double *p[3] = {a, b, c};
    double l[3]; /* l[i]: squared length of the edge opposite p[i] */
    for (int i = 0; i < 3; i++) {
        const double *q = p[(i + 1) % 3], *s = p[(i + 2) % 3];
        l[i] = (q[0] - s[0]) * (q[0] - s[0]) + (q[1] - s[1]) * (q[1] - s[1]);
    }
    int k = l[0] <= l[1] ? (l[0] <= l[2] ? 0 : 2) : (l[1] <= l[2] ? 1 : 2);
    const double *o = p[k], *q = p[(k + 1) % 3], *s = p[(k + 2) % 3];
    double ux = q[0] - o[0], uy = q[1] - o[1], vx = s[0] - o[0], vy = s[1] - o[1];
    return atan2(fabs(ux * vy - uy * vx), ux * vx + uy * vy) * (180 / 3.14159265358979323846);
}

/* The first entry of the sorted tags not below key. */
static size_t vtag_lower_bound(const vctx *c, const vtag *key) {
    size_t lo = 0, hi = c->nvt;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (cmp_vtag(&c->vt[mid], key) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* 1 iff triangle tv's small angle is forced by the input (rule in validate.h). */
static int angle_exempt(const vctx *c, const int32_t *tv) {
    const uint8_t *vflag = c->vflag;
    int exempt = (vflag[tv[0]] | vflag[tv[1]] | vflag[tv[2]]) & 1;
    for (int x = 0; x < 3 && !exempt; x++) {
        int32_t p = tv[x], q = tv[(x + 1) % 3];
        if (!(vflag[p] & 2) || !(vflag[q] & 2)) continue;
        vtag key = {p, -1, 0};
        for (size_t i1 = vtag_lower_bound(c, &key); i1 < c->nvt && c->vt[i1].v == p && !exempt;
             i1++) {
            vtag k2 = {q, c->vt[i1].k, 1 - c->vt[i1].side};
            size_t l2 = vtag_lower_bound(c, &k2);
            exempt = l2 < c->nvt && cmp_vtag(&c->vt[l2], &k2) == 0;
        }
    }
    return exempt;
}

/* 10. quality */
void validate_quality(vctx *c) {
    validate_report *r = c->r;
    const validate_opts *o = c->o;
    double abound = o->max_area > 0 ? o->max_area * (1 + 1e-12) : INFINITY;
    double qbound = o->min_angle > 0 ? o->min_angle - 1e-6 : -INFINITY;
    r->max_area = 0;
    for (int32_t t = 0; t < c->nt; t++) {
        if (c->tbad[t]) continue;
        const int32_t *tv = c->tri + 3 * t;
        const double *a = c->xy + 2 * tv[0], *b = c->xy + 2 * tv[1], *p = c->xy + 2 * tv[2];
        double ar = 0.5 * ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]));
        double ang = tri_min_angle(a, b, p);
        if (ar > r->max_area) r->max_area = ar;
        if (ang < r->min_angle) r->min_angle = ang;
        if (ar > abound) {
            r->bad_area++;
            validate_problem(r, "triangle %d has area %.6g > %.6g", t, ar, o->max_area);
        }
        if (angle_exempt(c, tv)) {
            r->nexempt++;
            continue;
        }
        if (ang < r->min_angle_unforced) r->min_angle_unforced = ang;
        if (ang < qbound) {
            r->bad_angle++;
            validate_problem(r, "triangle %d has smallest angle %.6g < %.6g degrees", t, ang,
                             o->min_angle);
        }
    }
}

/* A point strictly inside triangle (a, b, p), decided by exact orient2d: the centroid, or when
 * rounding puts it on an edge (a sliver) another barycentric point.  0, or -1 if none is. */
static int interior_point(const double *a, const double *b, const double *p, double out[2]) {
    static const double w[4][3] = {
        {1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.5, 0.25, 0.25}, {0.25, 0.5, 0.25}, {0.25, 0.25, 0.5}};
    for (int k = 0; k < 4; k++) {
        out[0] = w[k][0] * a[0] + w[k][1] * b[0] + w[k][2] * p[0];
        out[1] = w[k][0] * a[1] + w[k][1] * b[1] + w[k][2] * p[1];
        if (geom_orient2d(a, b, out) > 0 && geom_orient2d(b, p, out) > 0 &&
            geom_orient2d(p, a, out) > 0)
            return 0;
    }
    return -1;
}

/* 10b. regions: attributes and per-region area bounds (rule in validate.h) */
void validate_regions(vctx *c) {
    const validate_opts *o = c->o;
    validate_report *r = c->r;
    if (!(o->region_attr || o->region_area) || !c->g) return;
    if (o->region_attr && !c->m->tattr) {
        r->bad_region++;
        validate_problem(r, "the mesh has no regional attributes (expected one per triangle)");
        return;
    }
    pslg_regions *R = pslg_regions_build(c->g);
    const double *reg = c->g->regions;
    for (int32_t t = 0; t < c->nt; t++) {
        if (c->tbad[t]) continue;
        const int32_t *tv = c->tri + 3 * t;
        const double *a = c->xy + 2 * tv[0], *b = c->xy + 2 * tv[1], *p = c->xy + 2 * tv[2];
        double q[2];
        if (interior_point(a, b, p, q)) continue;
        int32_t k = c->g->nregions ? pslg_region_at(R, q) : -1;
        if (o->region_attr) {
            double want = k >= 0 ? reg[4 * k + 2] : 0;
            if (c->m->tattr[t] != want) {
                r->bad_region++;
                validate_problem(r, "triangle %d has attribute %.17g, its region's is %.17g", t,
                                 c->m->tattr[t], want);
            }
        }
        if (o->region_area && k >= 0 && reg[4 * k + 3] > 0 &&
            !(o->max_area > 0 && o->max_area < reg[4 * k + 3])) {
            double ar = 0.5 * ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]));
            if (ar > reg[4 * k + 3] * (1 + 1e-12)) {
                r->bad_area++;
                validate_problem(r, "triangle %d has area %.6g > %.6g, its region's bound", t, ar,
                                 reg[4 * k + 3]);
            }
        }
    }
    pslg_regions_free(R);
}
