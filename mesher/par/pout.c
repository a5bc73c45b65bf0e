/* pout.c: output, the distributed check and quality figures of a distributed mesh, each rank
 * working on its own part (pout.h; design.md "output").
 *
 * Output: the Triangle files come from meshio_pwrite_triangle (MPI-IO, byte ranges from prefix
 * sums), fed with each rank's part in global numbering (par_number): rank 0 writes the input
 * vertices first (numbers 0..nin-1, from the input every rank holds), then every rank its
 * owned vertices in number order, its triangles and the input subsegments it owns.  VTK: one
 * XML piece per rank under a .pvtu index (meshio_pwrite_pvtu), in local numbering.  The SVG
 * picture is the one thing collected on rank 0 (triangle corners and subsegment ends as
 * coordinates, no numbering), refused above PAR_SVG_MAX_TRIS triangles.
 *
 * Check: the exact validator runs on every part in part mode (validate.h); what a part alone
 * cannot show is decided over all parts: the sum of the parts' areas against the input's
 * domain area (validate_area_ok, as the validator), and every endpoint of an input segment that
 * piece that borders the domain (every vertex of a point set) used by some part (an MPI_MAX
 * reduction of one byte per input vertex), and every edge between two ranks' triangles that is
 * not an input constraint must be locally Delaunay (par_check_interface_delaunay: the two
 * apexes meet at a rendezvous rank, exact incircle), so the distributed check asks what
 * ./meshcheck asks of the merged mesh.  Interfaces were compared across ranks before (the
 * always-on par_check_interfaces_open).  Output and check use the mesher's open-edge mask when it
 * hands one over (topen: no vertex-to-triangle rows).  Invariant: every function returns the
 * same result on every rank.
 */
#include "par/pout.h"

#include "base/base.h"
#include "base/pfor.h"
#include "geom/geom.h"
#include "io/oset.h"
#include "io/ptext.h"
#include "io/pwrite.h"
#include "par/pextra.h"
#include "rt.h"
#include "seq/vattr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the distributed check ----------------------------------------------------------------- */

/* need[i] = 1 if input vertex i must be a vertex of some part's triangles. */
static uint8_t *needed_inputs(const pslg *in) {
    uint8_t *need = mesh_xcalloc((size_t)in->nverts + 1, 1);
    if (in->nsegs == 0) {
        memset(need, 1, (size_t)in->nverts);
        return need;
    }
    pslg_pieces pc;
    pslg_segment_pieces(in, &pc);           /* returns 0 (the allocation funnel never fails) */
    for (int32_t s = 0; s < in->nsegs; s++) /* both ends of every bordering piece */
        for (int32_t i = pc.start[s]; i + 1 < pc.start[s + 1]; i++)
            if (pc.border[i]) need[pc.vert[i]] = need[pc.vert[i + 1]] = 1;
    pslg_pieces_free(&pc);
    return need;
}

int par_check_parts(const par_opts *o, const pslg *in, mesh_flat *local, const par_numbering *num,
                    int print, validate_report *r) {
    MPI_Comm c = rt_app_comm();
    int rank = rt_rank(), P = rt_size();
    const char *brk = getenv("PCDM_TEST_BREAK_PIECE");
    if (brk && atoi(brk) == rank && local->ntris > 0) { /* test-only fault: reverse a triangle */
        int32_t t = local->tri[1];
        local->tri[1] = local->tri[2];
        local->tri[2] = t;
    }
    validate_opts vo;
    memset(&vo, 0, sizeof vo);
    vo.min_angle = o->min_angle;
    vo.max_area = o->max_area;
    vo.check_delaunay_interfaces = 1;
    vo.part = 1;
    vo.region_attr = o->region_attr;
    vo.region_area = o->region_area;
    validate_report lr;
    mesh_validate(in, local, &vo, &lr);
    /* the edges between parts: locally Delaunay across ranks (the part's validator cannot see
     * the other side) */
    char imsg[sizeof lr.first_problem];
    long ibad = par_check_interface_delaunay(local, num->topen, imsg, sizeof imsg);
    lr.non_delaunay += ibad;
    if (ibad && !lr.first_problem[0]) memcpy(lr.first_problem, imsg, sizeof imsg);

    /* input vertices: used by some part */
    uint8_t *need = needed_inputs(in), *have = mesh_xcalloc((size_t)in->nverts + 1, 1);
    uint8_t *used = mesh_xcalloc((size_t)local->nverts + 1, 1);
    for (size_t i = 0; i < 3 * (size_t)local->ntris; i++)
        if (local->tri[i] >= 0 && local->tri[i] < local->nverts) used[local->tri[i]] = 1;
    for (int32_t v = 0; v < local->nverts; v++)
        if (used[v] && num->gid[v] >= 0 && num->gid[v] < num->nin) have[num->gid[v]] = 1;
    free(used);
    if (in->nverts > 0)
        MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, have, in->nverts, MPI_UINT8_T, MPI_MAX, c));
    long missing = 0;
    int32_t first_missing = -1;
    for (int32_t i = 0; i < in->nverts; i++)
        if (need[i] && !have[i]) {
            if (first_missing < 0) first_missing = i;
            missing++;
        }
    free(need);
    free(have);

    /* reduce the reports */
    long cnt[11] = {lr.bad_orient,
                    lr.bad_conform,
                    lr.missing_verts,
                    lr.missing_segs,
                    lr.stray_boundary,
                    lr.non_delaunay,
                    lr.bad_angle,
                    lr.bad_area,
                    lr.nexempt,
                    lr.ntris,
                    lr.first_problem[0] != 0};
    long tot[11];
    MESH_MPI(MPI_Allreduce(cnt, tot, 11, MPI_LONG, MPI_SUM, c));
    double mn[2] = {lr.min_angle, lr.min_angle_unforced}, mx = lr.max_area, area = lr.mesh_area_w;
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, mn, 2, MPI_DOUBLE, MPI_MIN, c));
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, &mx, 1, MPI_DOUBLE, MPI_MAX, c));
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, &area, 1, MPI_DOUBLE, MPI_SUM, c));
    memset(r, 0, sizeof *r);
    r->bad_orient = tot[0];
    r->bad_conform = tot[1];
    r->missing_verts = tot[2] + missing;
    r->missing_segs = tot[3];
    r->stray_boundary = tot[4];
    r->non_delaunay = tot[5];
    r->bad_angle = tot[6];
    r->bad_area = tot[7];
    r->nexempt = tot[8];
    r->ntris = tot[9];
    r->nverts = (long)num->nverts;
    r->min_angle = mn[0];
    r->min_angle_unforced = mn[1];
    r->max_area = mx;
    /* compared in the working scale; reported in input units */
    double dom = lr.domain_area_w; /* the input's, the same on every rank */
    if (!validate_area_ok(area, dom, lr.area_slack_w)) r->area_mismatch = 1;
    r->mesh_area = ldexp(area, -2 * in->scale_exp);
    r->domain_area = lr.domain_area;

    /* the first problem: the lowest failing rank's, else the global ones */
    int mine = lr.first_problem[0] ? rank : P, first = P;
    MESH_MPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, c));
    if (first < P) {
        char buf[sizeof r->first_problem];
        if (rank == first) snprintf(buf, sizeof buf, "rank %d: %.230s", rank, lr.first_problem);
        MESH_MPI(MPI_Bcast(buf, (int)sizeof buf, MPI_CHAR, first, c));
        memcpy(r->first_problem, buf, sizeof buf);
    } else if (missing) {
        snprintf(r->first_problem, sizeof r->first_problem,
                 "input vertex %d at (%.17g, %.17g) is in no part of the mesh",
                 (int)(first_missing + in->first_index), in->xy[2 * (size_t)first_missing],
                 in->xy[2 * (size_t)first_missing + 1]);
    } else if (r->area_mismatch) {
        snprintf(r->first_problem, sizeof r->first_problem,
                 "the parts' areas sum to %.17g, the domain's area is %.17g", r->mesh_area,
                 r->domain_area);
    }
    r->ok = !(r->bad_orient || r->bad_conform || r->missing_verts || r->missing_segs ||
              r->stray_boundary || r->non_delaunay || r->bad_angle || r->bad_area ||
              r->area_mismatch || r->first_problem[0]);
    if (print && rank == 0 && (!o->quiet || !r->ok)) validate_report_print(r, stdout);
    return r->ok;
}

/* ---- Triangle files ------------------------------------------------------------------------ */

static int write_triangle(const par_opts *o, meshio_set *set, const pslg *in, const mesh_flat *f,
                          const par_numbering *num, char *err, size_t errlen) {
    int rank = rt_rank();
    int64_t nin = rank == 0 ? num->nin : 0;
    /* only the written segments are copied (few); vertices and triangles are read in place */
    int64_t *seg = mesh_xmalloc(2 * (size_t)num->nwseg + 1, sizeof(int64_t));
    int32_t *smk = mesh_xmalloc((size_t)num->nwseg + 1, sizeof(int32_t));
    for (int32_t k = 0; k < num->nwseg; k++) {
        int32_t s = num->wseg[k];
        seg[2 * (size_t)k] = num->gid[f->seg[2 * (size_t)s]];
        seg[2 * (size_t)k + 1] = num->gid[f->seg[2 * (size_t)s + 1]];
        smk[k] = f->smarker ? f->smarker[s] : 0;
    }
    mesh_part p = {.nverts = nin + num->nowned,
                   .nhead = nin,
                   .hxy = in->xy,
                   .hvmarker = in->vmarker,
                   .nattr = f->vattr ? in->nattr : 0,
                   .hvattr = f->vattr ? in->vattr : NULL,
                   .vattr = f->vattr,
                   .xy = f->xy,
                   .vmarker = f->vmarker,
                   .vsel = num->owned,
                   .ntris = f->ntris,
                   .ltri = f->tri,
                   .gid = num->gid,
                   .nlocal = f->nverts,
                   .trank = NULL, /* the .ele's attribute is Triangle's: the region's with -A,
                                   * else none (the rank is VTK cell data) */
                   .tattr = f->tattr,
                   .nsegs = num->nwseg,
                   .seg = seg,
                   .smarker = smk,
                   .scale_exp = in->scale_exp,
                   .nholes = in->nholes,
                   .holes = in->holes,
                   .nregions = in->nregions,
                   .regions = in->regions,
                   /* pass 1 formats up to 8 bytes per triangle ahead and keeps them, about
                    * half a rank's .node text: the part, its numbering and the digit cache
                    * hold about 38 bytes per triangle here, so this stays near the refining
                    * mesh's peak (about 45) and saves half the second formatting of the
                    * coordinates */
                   .keep = 8 * (size_t)f->ntris,
                   .skip = par_skip_linear(o),
                   /* the rank's workers are idle now: they format the text */
                   .threads = o->threads};
    int rc = meshio_pwrite_triangle(rt_app_comm(), set, &p, o->out_prefix, err, errlen);
    free(seg);
    free(smk);
    return rc;
}

/* ---- SVG, collected on rank 0 -------------------------------------------------------------- */

/* Collective.  Gathers n records of k doubles from every rank to rank 0 (*out there, with the
 * total in *ntot; NULL elsewhere). */
static double *gather_doubles(const double *mine, int64_t n, int k, int64_t *ntot) {
    MPI_Comm c = rt_app_comm();
    int rank = rt_rank(), P = rt_size();
    int cnt = (int)(n * k), *cnts = NULL, *dsp = NULL;
    if (rank == 0) {
        cnts = mesh_xmalloc((size_t)P, sizeof(int));
        dsp = mesh_xmalloc((size_t)P + 1, sizeof(int));
    }
    MESH_MPI(MPI_Gather(&cnt, 1, MPI_INT, cnts, 1, MPI_INT, 0, c));
    double *out = NULL;
    if (rank == 0) {
        dsp[0] = 0;
        for (int r = 0; r < P; r++)
            dsp[r + 1] = dsp[r] + cnts[r];
        out = mesh_xmalloc((size_t)dsp[P] + 1, sizeof(double));
        *ntot = dsp[P] / k;
    }
    MESH_MPI(MPI_Gatherv(mine, cnt, MPI_DOUBLE, out, cnts, dsp, MPI_DOUBLE, 0, c));
    free(cnts);
    free(dsp);
    return out;
}

static int write_svg(const par_opts *o, meshio_set *set, const mesh_flat *f,
                     const par_numbering *num, char *err, size_t errlen) {
    if (num->ntris > PAR_SVG_MAX_TRIS) {
        snprintf(err, errlen,
                 "%s: the mesh has %lld triangles; --svg pictures are collected on rank 0 and "
                 "limited to %d",
                 o->svg, (long long)num->ntris, PAR_SVG_MAX_TRIS);
        return -1;
    }
    /* a triangle: its corners and its rank; a subsegment: its ends, marker and interface flag */
    double *t = mesh_xmalloc(7 * (size_t)f->ntris + 1, sizeof(double));
    for (int32_t i = 0; i < f->ntris; i++) {
        for (int j = 0; j < 3; j++) {
            const double *p = f->xy + 2 * (size_t)f->tri[3 * (size_t)i + (size_t)j];
            t[7 * (size_t)i + 2 * (size_t)j] = p[0];
            t[7 * (size_t)i + 2 * (size_t)j + 1] = p[1];
        }
        t[7 * (size_t)i + 6] = f->trank ? f->trank[i] : rt_rank();
    }
    double *s = mesh_xmalloc(6 * (size_t)f->nsegs + 1, sizeof(double));
    for (int32_t i = 0; i < f->nsegs; i++) {
        for (int j = 0; j < 2; j++) {
            const double *p = f->xy + 2 * (size_t)f->seg[2 * (size_t)i + (size_t)j];
            s[6 * (size_t)i + 2 * (size_t)j] = p[0];
            s[6 * (size_t)i + 2 * (size_t)j + 1] = p[1];
        }
        s[6 * (size_t)i + 4] = f->smarker ? f->smarker[i] : 0;
        s[6 * (size_t)i + 5] = f->sinterface ? f->sinterface[i] : 0;
    }
    int64_t nt = 0, ns = 0;
    double *T = gather_doubles(t, f->ntris, 7, &nt), *S = gather_doubles(s, f->nsegs, 6, &ns);
    free(t);
    free(s);
    int rc = 0;
    if (rt_rank() == 0) { /* a triangle soup: the picture needs no shared vertices */
        mesh_flat g;
        memset(&g, 0, sizeof g);
        g.nverts = (int32_t)(3 * nt + 2 * ns);
        g.xy = mesh_xmalloc(2 * (size_t)g.nverts + 1, sizeof(double));
        g.ntris = (int32_t)nt;
        g.tri = mesh_xmalloc(3 * (size_t)nt + 1, sizeof(int32_t));
        g.trank = mesh_xmalloc((size_t)nt + 1, sizeof(int32_t));
        g.nsegs = (int32_t)ns;
        g.seg = mesh_xmalloc(2 * (size_t)ns + 1, sizeof(int32_t));
        g.smarker = mesh_xmalloc((size_t)ns + 1, sizeof(int32_t));
        g.sinterface = mesh_xmalloc((size_t)ns + 1, sizeof(int32_t));
        for (int64_t i = 0; i < nt; i++) {
            memcpy(g.xy + 6 * (size_t)i, T + 7 * (size_t)i, 6 * sizeof(double));
            for (int j = 0; j < 3; j++)
                g.tri[3 * (size_t)i + (size_t)j] = (int32_t)(3 * i + j);
            g.trank[i] = (int32_t)T[7 * (size_t)i + 6];
        }
        for (int64_t i = 0; i < ns; i++) {
            memcpy(g.xy + 6 * (size_t)nt + 4 * (size_t)i, S + 6 * (size_t)i, 4 * sizeof(double));
            g.seg[2 * (size_t)i] = (int32_t)(3 * nt + 2 * i);
            g.seg[2 * (size_t)i + 1] = (int32_t)(3 * nt + 2 * i + 1);
            g.smarker[i] = (int32_t)S[6 * (size_t)i + 4];
            g.sinterface[i] = (int32_t)S[6 * (size_t)i + 5];
        }
        rc = meshio_write_svg(&g, set, o->svg, err, errlen);
        mesh_flat_free(&g);
    }
    free(T);
    free(S);
    return rc;
}

/* ---- all outputs --------------------------------------------------------------------------- */

int par_write_parts(const par_opts *o, meshio_set *set, const pslg *in, const mesh_flat *local,
                    const int32_t *tsub, const par_numbering *num) {
    char err[1024] = "", msg[1200];
    if (o->out_prefix && par_skip_linear(o) != MESHIO_SKIP_ALL) { /* collective: one status */
        if (write_triangle(o, set, in, local, num, err, sizeof err) != 0) {
            if (rt_rank() == 0) fprintf(stderr, "%s: %s\n", o->prog, err);
            return -1;
        }
    }
    if (o->vtk && !o->order2) { /* -o2: one quadratic VTK file (pextra.c) */
        char prefix[1024];
        snprintf(prefix, sizeof prefix, "%s", o->vtk);
        size_t n = strlen(prefix);
        static const char *const ext[3] = {".pvtu", ".vtu", ".vtk"};
        for (int k = 0; k < 3; k++) {
            size_t e = strlen(ext[k]);
            if (n > e && !strcmp(prefix + n - e, ext[k])) {
                prefix[n - e] = '\0';
                break;
            }
        }
        if (meshio_pwrite_pvtu(rt_app_comm(), set, local, tsub, !o->vtk_ascii, prefix, err,
                               sizeof err) != 0) {
            if (rt_rank() == 0) fprintf(stderr, "%s: %s\n", o->prog, err);
            return -1;
        }
    }
    if (o->svg) {
        int bad = write_svg(o, set, local, num, err, sizeof err) != 0;
        snprintf(msg, sizeof msg, "%s: %s", o->prog, err);
        if (par_fail_any(bad, msg)) return -1;
    }
    return 0;
}

/* One pass over a part's triangles (the slowest part of the end on a large mesh is waiting on
 * the coordinates, so every figure is taken at once), on the rank's threads, each a range of
 * blocks of 256 triangles:
 *  - the area: doubled areas summed plainly in each block, the blocks' sums then with
 *    Neumaier's compensation in block order (as mesh_area): the same value for any thread count;
 *  - the mesh hash's part (with hash): the sum of meshio_tri_hash mod 2^64;
 *  - the quality (with quality): the smallest angle and largest area without three atan2 per
 *    triangle -- the smallest angle (at most 60 degrees, opposite the shortest edge a) has
 *    sin^2 = (2 area)^2 / (b^2 c^2), monotone in the angle there, so only the triangle minimising
 *    it gets geom_min_angle_deg; the lowest value wins, the first triangle on ties, as in one
 *    pass. */
typedef struct survey {
    double area;       /* the part's area, working scale */
    uint64_t hash;     /* its share of the mesh hash (with hash) */
    double kmin, amax; /* (with quality) the smallest sin^2 figure, the largest area */
    int64_t tmin;      /* the triangle of kmin, -1 if none */
} survey;

typedef struct survey_job {
    const mesh_flat *f;
    int hash, quality;
    double *blk;
    uint64_t hsum[MESH_PFOR_MAXTHR];
    double kmin[MESH_PFOR_MAXTHR], amax[MESH_PFOR_MAXTHR];
    int64_t tmin[MESH_PFOR_MAXTHR];
} survey_job;

static void survey_range(void *arg, int part, int64_t b0, int64_t b1) {
    survey_job *j = arg;
    const mesh_flat *f = j->f;
    double kmin = 2, amax = 0;
    int64_t tmin = -1;
    uint64_t hs = 0;
    for (int64_t k = b0; k < b1; k++) {
        int64_t t0 = 256 * k, t1 = f->ntris - t0 < 256 ? f->ntris : t0 + 256;
        double x = 0;
        for (int64_t t = t0; t < t1; t++) {
            const int32_t *v = f->tri + 3 * (size_t)t;
            const double *a = f->xy + 2 * (size_t)v[0], *b = f->xy + 2 * (size_t)v[1],
                         *c = f->xy + 2 * (size_t)v[2];
            x += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            if (j->hash) hs += meshio_tri_hash(f, t);
            if (!j->quality) continue;
            double ab = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]);
            double bc = (c[0] - b[0]) * (c[0] - b[0]) + (c[1] - b[1]) * (c[1] - b[1]);
            double ca = (a[0] - c[0]) * (a[0] - c[0]) + (a[1] - c[1]) * (a[1] - c[1]);
            double ar = geom_area(a, b, c), lo = fmin(ab, fmin(bc, ca));
            double prod = lo == ab ? bc * ca : lo == bc ? ab * ca : ab * bc;
            double q = prod > 0 ? 4 * ar * ar / prod : 0;
            if (q < kmin) {
                kmin = q;
                tmin = t;
            }
            if (ar > amax) amax = ar;
        }
        j->blk[k] = x;
    }
    j->hsum[part] = hs;
    j->kmin[part] = kmin;
    j->tmin[part] = tmin;
    j->amax[part] = amax;
}

static void part_survey(const mesh_flat *f, int threads, int hash, int quality, survey *s) {
    int64_t nb = ((int64_t)f->ntris + 255) / 256;
    survey_job j = {.f = f, .hash = hash, .quality = quality};
    j.blk = mesh_xmalloc((size_t)nb + 1, sizeof(double));
    int n = mesh_pfor_ranges(nb, threads, 64, survey_range, &j);
    double a = 0, c = 0;
    for (int64_t k = 0; k < nb; k++) {
        double x = j.blk[k], sum = a + x;
        c += fabs(a) >= fabs(x) ? (a - sum) + x : (x - sum) + a;
        a = sum;
    }
    free(j.blk);
    s->area = 0.5 * (a + c);
    s->hash = 0;
    s->kmin = 2;
    s->amax = 0;
    s->tmin = -1;
    for (int k = 0; k < n; k++) { /* parts in order: the first triangle on ties */
        s->hash += j.hsum[k];
        if (j.kmin[k] < s->kmin) {
            s->kmin = j.kmin[k];
            s->tmin = j.tmin[k];
        }
        if (j.amax[k] > s->amax) s->amax = j.amax[k];
    }
}

int par_area_agrees(const pslg *in, double part_area, const double *dom, char *why, size_t len) {
    double area = part_area, v[2] = {0, 0}; /* rank 0's verdict and the domain's area */
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, &area, 1, MPI_DOUBLE, MPI_SUM, rt_app_comm()));
    if (rt_rank() == 0) {
        if (dom) {
            v[1] = *dom;
            v[0] = validate_area_net_at(in, area, v[1]);
        } else {
            v[0] = validate_area_net(in, area, &v[1]);
        }
    }
    MESH_MPI(MPI_Bcast(v, 2, MPI_DOUBLE, 0, rt_app_comm()));
    if (v[0] != 0) return 1;
    snprintf(why, len,
             "the parts' areas sum to %.17g, the domain's area is %.17g: more apart than rounding "
             "explains (features below the precision of the coordinates)",
             ldexp(area, -2 * in->scale_exp), ldexp(v[1], -2 * in->scale_exp));
    return 0;
}

static void *dom_ahead_run(void *arg) {
    par_dom_ahead *a = arg;
    mesh_thread_spread(a->cpus);
    a->area = pslg_domain_area(a->in);
    return NULL;
}

void par_dom_ahead_start(par_dom_ahead *a, const pslg *in, const uint8_t *cpus) {
    memset(a, 0, sizeof *a);
    a->in = in;
    a->cpus = cpus;
    if (!in || in->nsegs == 0) return; /* a point set: no area to compute */
    a->started = pthread_create(&a->thr, NULL, dom_ahead_run, a) == 0;
}

const double *par_dom_ahead_get(par_dom_ahead *a) {
    if (!a->started) return NULL;
    if (!a->joined) {
        pthread_join(a->thr, NULL);
        a->joined = 1;
    }
    return &a->area;
}

double par_part_area(const mesh_flat *f, int threads) {
    survey sv;
    part_survey(f, threads, 0, 0, &sv);
    return sv.area;
}

/* Collective.  The smallest angle and largest area over every rank's part, from each rank's
 * survey (the same on every rank). */
static void quality_all(const mesh_flat *f, const survey *s, double *min_angle, double *max_area) {
    double mn = 180, mx = s->amax;
    if (s->tmin >= 0) {
        const int32_t *v = f->tri + 3 * (size_t)s->tmin;
        mn = geom_min_angle_deg(f->xy + 2 * (size_t)v[0], f->xy + 2 * (size_t)v[1],
                                f->xy + 2 * (size_t)v[2]);
    }
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, &mn, 1, MPI_DOUBLE, MPI_MIN, rt_app_comm()));
    MESH_MPI(MPI_Allreduce(MPI_IN_PLACE, &mx, 1, MPI_DOUBLE, MPI_MAX, rt_app_comm()));
    *min_angle = mn;
    *max_area = mx;
}

int par_output_sub(const par_opts *o, const pslg *in, const double *dom, mesh_flat *local,
                   const uint8_t *artificial, const int32_t *tsub, const uint8_t *topen,
                   par_summary *sum) {
    memset(sum, 0, sizeof *sum);
    /* the parts are in the input's working scale (pslg_check); the writers undo it */
    local->scale_exp = in->scale_exp;
    if (!o->region_attr) { /* labels kept only for the region bounds: not written, not checked */
        free(local->tattr);
        local->tattr = NULL;
    }
    /* never a silent broken mesh: both sides of every interface must agree first */
    char imsg[600] = "", msg[1300];
    int ibad = par_check_interfaces_open(local, topen, imsg, sizeof imsg) != 0;
    snprintf(msg, sizeof msg, "%s: %s: rank %d: %s", o->prog, in->path[0] ? in->path : "mesh",
             rt_rank(), imsg);
    if (par_fail_any(ibad, msg)) return 1;
    /* ... and the parts' areas sum to the domain's (the cheap net ./mesh runs too); the hash
     * and the quality figures in the same pass */
    survey sv;
    int quality = o->stats || o->verbose; /* only printed there */
    part_survey(local, o->threads, o->stats, quality, &sv);
    sum->hash = sv.hash;
    const char *skew = getenv("PCDM_TEST_AREA_SKEW"); /* test-only fault: rank R's area off */
    if (skew && atoi(skew) == rt_rank()) sv.area *= 1 + 1e-6;
    if (!par_area_agrees(in, sv.area, dom, imsg,
                         sizeof imsg)) { /* the same verdict on every rank */
        if (rt_rank() == 0)
            fprintf(stderr, "%s: %s: %s; none written\n", o->prog, in->path[0] ? in->path : "mesh",
                    imsg);
        return 1;
    }
    double t0 = rt_wtime();
    par_numbering num;
    char err[512];
    if (par_number_open(local, in, artificial, topen, o->threads, &num, err, sizeof err) != 0) {
        if (rt_rank() == 0) fprintf(stderr, "%s: %s\n", o->prog, err);
        return 1;
    }
    double t1 = rt_wtime();
    int status = 0;
    if (o->check) {
        validate_report vr;
        if (!par_check_parts(o, in, local, &num, 1, &vr)) status = 1;
    }
    double t2 = rt_wtime();
    if (status == 0 && o->out_prefix && in->nattr > 0) { /* attributes of the new vertices */
        int bad = mesh_interpolate_attributes(in, local, err, sizeof err) != 0;
        snprintf(msg, sizeof msg, "%s: %s: %s", o->prog, in->path, err);
        if (par_fail_any(bad, msg)) status = 1;
    }
    /* the run's files as one set (io/oset.h): committed together once all are written */
    meshio_set set;
    meshio_set_init(&set);
    if (status == 0 && par_write_parts(o, &set, in, local, tsub, &num) != 0) status = 1;
    if (status == 0 && par_write_extras(o, &set, in, local, artificial, &num) != 0) status = 1;
    if (status == 0 && meshio_pset_commit(rt_app_comm(), &set, err, sizeof err) != 0) {
        if (rt_rank() == 0) fprintf(stderr, "%s: %s\n", o->prog, err);
        status = 1;
    }
    meshio_set_free(&set);
    double t3 = rt_wtime();
    sum->ntris = num.ntris;
    sum->nverts = num.nverts;
    sum->nsegs = num.nsegs;
    sum->nshared = num.nshared;
    par_numbering_free(&num);
    if (quality) quality_all(local, &sv, &sum->min_angle, &sum->max_area);
    sum->number_s = t1 - t0;
    sum->check_s = t2 - t1;
    sum->write_s = t3 - t2;
    return status;
}

double *par_stats_collect(const double *mine, int n, int on, double *tot, double *mx) {
    if (!on) return NULL;
    int rank = rt_rank(), P = rt_size();
    double *all = rank == 0 ? mesh_xmalloc((size_t)n * (size_t)P, sizeof(double)) : NULL;
    MESH_MPI(MPI_Gather(mine, n, MPI_DOUBLE, all, n, MPI_DOUBLE, 0, rt_app_comm()));
    if (rank != 0) return NULL;
    for (int k = 0; k < n; k++)
        tot[k] = mx[k] = 0;
    for (int r = 0; r < P; r++)
        for (int k = 0; k < n; k++) {
            double x = all[(size_t)r * (size_t)n + (size_t)k];
            tot[k] += x;
            if (x > mx[k]) mx[k] = x;
        }
    return all;
}
