/* unit_decomp: Check suite for mesher/decomp (coarse mesh + METIS, and cuts files).
 *
 * Every decomposition is verified independently of the module's own bookkeeping: the augmented
 * PSLG passes pslg_check unchanged (no crossings, no merged vertices, no vertex inside a
 * segment); every interface edge has two different subdomains on its sides; every angle
 * between an interface and another segment at a shared vertex is at least 30 degrees (measured
 * with atan2: a quality figure, not a topological decision); the subdomain areas add up to the
 * domain's; work is balanced against the targets; every rank owns a subdomain; the result is the
 * same bits when computed twice (the second time keeping the input's CDT, which is checked to be
 * the one mesh_build_cdt makes, refining alike).  Inputs: data/ and tests/inputs/ (every input
 * class).
 */
#include "bounds/bounds.h"
#include "check_run.h"
#include "decomp/decomp.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "seq/mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *const inputs[] = {"data/square.poly",
                                     "data/lshape.poly",
                                     "data/wedge.poly",
                                     "data/lake.poly",
                                     "data/holes.poly",
                                     "data/channel.poly",
                                     "tests/inputs/letter_a.poly",
                                     "tests/inputs/inclusion.poly",
                                     "tests/inputs/map.poly",
                                     "tests/inputs/segments.poly",
                                     "tests/inputs/grid.poly",
                                     "tests/inputs/far.poly",
                                     "tests/inputs/sliver.poly",
                                     "tests/inputs/angles.poly",
                                     "tests/inputs/points.node"};
#define NIN ((int)(sizeof inputs / sizeof inputs[0]))

static void load(const char *path, pslg *g) {
    char err[512];
    ck_assert_msg(pslg_read(path, g, err, sizeof err) == 0, "%s", err);
    ck_assert_msg(pslg_check(g, err, sizeof err) == 0, "%s", err);
}

static double domain_area(const pslg *in) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int32_t v = 0; v < in->nverts; v++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], in->xy[2 * v + k]);
            hi[k] = fmax(hi[k], in->xy[2 * v + k]);
        }
    return (hi[0] - lo[0]) * (hi[1] - lo[1]);
}

typedef struct dir {
    double ang;
    int iface;
} dir;

static int cmp_dir(const void *x, const void *y) {
    const dir *a = x, *b = y;
    return (a->ang > b->ang) - (a->ang < b->ang);
}

/* Independent checks of d (see the file comment); returns the smallest interface angle. */
static double verify(const pslg *in, const pcdm_decomp *d, int32_t K, int32_t P) {
    char err[1024];
    ck_assert_int_eq(d->nsub, K);
    ck_assert_int_eq(d->nranks, P);
    ck_assert_int_eq(d->ninput_verts, in->nverts);
    ck_assert(!memcmp(d->g.xy, in->xy, 2 * (size_t)in->nverts * sizeof(double)));
    /* pslg_check changes nothing */
    pslg c;
    memset(&c, 0, sizeof c);
    c = d->g;
    int32_t nv = c.nverts, ns = c.nsegs;
    c.xy = malloc(2 * (size_t)nv * sizeof(double) + 1);
    memcpy(c.xy, d->g.xy, 2 * (size_t)nv * sizeof(double));
    c.seg = malloc(2 * (size_t)ns * sizeof(int32_t) + 1);
    memcpy(c.seg, d->g.seg, 2 * (size_t)ns * sizeof(int32_t));
    c.vmarker = calloc((size_t)nv + 1, sizeof(int32_t));
    c.vline = calloc((size_t)nv + 1, sizeof(int32_t));
    c.smarker = calloc((size_t)ns + 1, sizeof(int32_t));
    c.sline = calloc((size_t)ns + 1, sizeof(int32_t));
    c.vattr = NULL;
    c.nattr = 0;
    c.holes = NULL;
    c.nholes = 0;
    c.regions = NULL;
    c.nregions = 0;
    ck_assert_msg(pslg_check(&c, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(c.nverts, nv);
    ck_assert_int_eq(c.nsegs, ns);
    for (int32_t s = 0; s < ns; s++) /* no vertex lies inside a segment */
        for (int32_t v = 0; v < nv; v++) {
            const double *a = d->g.xy + 2 * (size_t)d->g.seg[2 * s],
                         *b = d->g.xy + 2 * (size_t)d->g.seg[2 * s + 1], *p = d->g.xy + 2 * v;
            if (v == d->g.seg[2 * s] || v == d->g.seg[2 * s + 1]) continue;
            if (geom_orient2d(a, b, p) == 0)
                ck_assert_msg(geom_diametral(a, b, p) > 0, "vertex %d inside segment %d", v, s);
        }
    pslg_free(&c);
    /* sides, owners, work */
    for (int32_t s = 0; s < ns; s++) {
        int32_t l = d->seg_sub[2 * s], r = d->seg_sub[2 * s + 1];
        ck_assert(l >= -1 && l < K && r >= -1 && r < K);
        ck_assert_int_eq(d->seg_iface[s], l >= 0 && r >= 0 && l != r);
        if (s >= d->nboundary) ck_assert(d->seg_iface[s]);
    }
    int32_t *own = calloc((size_t)P, sizeof(int32_t));
    double wsum = 0, tsum = 0, asum = 0;
    for (int32_t k = 0; k < K; k++) {
        ck_assert(d->sub_owner[k] >= 0 && d->sub_owner[k] < P);
        own[d->sub_owner[k]]++;
        ck_assert(d->sub_area[k] > 0 && d->sub_weight[k] > 0);
        wsum += d->sub_weight[k];
        tsum += d->sub_target[k];
        asum += d->sub_area[k];
    }
    for (int32_t r = 0; r < P; r++)
        ck_assert_msg(own[r] > 0, "rank %d owns no subdomain", r);
    free(own);
    ck_assert(fabs(wsum - d->total_weight) <= 1e-9 * wsum);
    ck_assert(fabs(tsum - 1) < 1e-9);
    ck_assert(asum > 0 && asum <= domain_area(in) * (1 + 1e-9));
    /* angles between an interface and its angular neighbours at each vertex */
    dir *dv = malloc(2 * (size_t)ns * sizeof(dir) + 1);
    double amin = 360;
    for (int32_t v = 0; v < nv; v++) {
        int32_t n = 0, ni = 0;
        for (int32_t s = 0; s < ns; s++)
            for (int e = 0; e < 2; e++)
                if (d->g.seg[2 * s + e] == v) {
                    const double *p = d->g.xy + 2 * v, *q = d->g.xy + 2 * d->g.seg[2 * s + 1 - e];
                    dv[n++] = (dir){atan2(q[1] - p[1], q[0] - p[0]), s >= d->nboundary};
                    ni += s >= d->nboundary;
                }
        if (ni == 0 || n < 2) continue;
        qsort(dv, (size_t)n, sizeof *dv, cmp_dir);
        for (int32_t i = 0; i < n; i++) {
            const dir *a = &dv[i], *b = &dv[(i + 1) % n];
            if (!a->iface && !b->iface) continue;
            double g = (b->ang - a->ang) * 180 / M_PI;
            if (g <= 0) g += 360;
            if (g < amin) amin = g;
        }
    }
    free(dv);
    ck_assert_msg(amin >= 30 - 1e-6, "an interface makes a %.3f degree angle", amin);
    return amin;
}

/* d->cdt is the CDT of in as mesh_build_cdt makes it (bits, and the state the kernel goes on
 * from): refining it gives the very mesh refining a fresh build gives. */
static void mesh_same(const mesh *a, const mesh *b) {
    ck_assert_int_eq(a->nv, b->nv);
    ck_assert_int_eq(a->nt, b->nt);
    ck_assert_int_eq(a->nlive, b->nlive);
    ck_assert_int_eq(a->nseg, b->nseg);
    ck_assert_int_eq(a->nss, b->nss);
    ck_assert(a->rng == b->rng && a->last == b->last);
    ck_assert(!memcmp(a->xy, b->xy, 2 * (size_t)a->nv * sizeof(double)));
    ck_assert(!memcmp(a->tv, b->tv, 3 * (size_t)a->nt * sizeof(int32_t)));
    ck_assert(!memcmp(a->tn, b->tn, 3 * (size_t)a->nt * sizeof(int32_t)));
    ck_assert(!memcmp(a->tf, b->tf, (size_t)a->nt));
    ck_assert(!memcmp(a->seg, b->seg, 2 * (size_t)a->nseg * sizeof(int32_t)));
}

static void check_kept_cdt(const pslg *in, pcdm_decomp *d, double area) {
    ck_assert_ptr_nonnull(d->cdt);
    mesh fresh;
    mesh_init(&fresh);
    char err[256];
    ck_assert_msg(mesh_build_cdt(&fresh, in, NULL, err, sizeof err) == 0, "%s", err);
    mesh_same(d->cdt, &fresh);
    mesh_quality q;
    memset(&q, 0, sizeof q);
    q.min_angle = 30;
    q.max_area = area;
    q.max_steiner = -1;
    q.offcenter = 1;
    mesh_set_quality(d->cdt, &q);
    mesh_set_quality(&fresh, &q);
    ck_assert_int_eq(mesh_refine(d->cdt), mesh_refine(&fresh));
    mesh_same(d->cdt, &fresh);
    mesh_free(&fresh);
}

static void run_auto(const char *path, int32_t K, int32_t P, double R, double area) {
    pslg in;
    load(path, &in);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = K;
    o.nranks = P;
    o.imbalance = R;
    o.max_area = area;
    pcdm_decomp d, d2;
    char err[1024];
    ck_assert_msg(pcdm_decomp_auto(&in, &o, &d, err, sizeof err) == 0, "%s K=%d P=%d: %s", path,
                  (int)K, (int)P, err);
    double amin = verify(&in, &d, K, P);
    /* balance: each rank's work against its target share */
    double dev = 0, r0 = 0;
    for (int32_t r = 0; r < P; r++) {
        double w = 0, t = 0;
        for (int32_t k = 0; k < K; k++)
            if (d.sub_owner[k] == r) {
                w += d.sub_weight[k];
                t += d.sub_target[k];
            }
        dev = fmax(dev, fabs(w / d.total_weight - t) / t);
        if (r == 0) r0 = w / d.total_weight;
    }
    printf("%-28s K=%-3d P=%-3d R=%g coarse=%d iface=%d min_angle=%.2f max_rank_dev=%.1f%% "
           "rank0=%.3f\n",
           path, (int)K, (int)P, R, (int)d.ncoarse, (int)(d.g.nsegs - d.nboundary), amin, 100 * dev,
           r0);
    if (area > 0 && K <= 16) ck_assert_msg(dev <= 0.10, "rank work off its target by %.3f", dev);
    ck_assert_ptr_null(d.cdt); /* not asked for */
    /* determinism, and keep_cdt changes nothing but the kept CDT */
    o.keep_cdt = 1;
    ck_assert(pcdm_decomp_auto(&in, &o, &d2, err, sizeof err) == 0);
    check_kept_cdt(&in, &d2, area);
    ck_assert_int_eq(d.g.nverts, d2.g.nverts);
    ck_assert_int_eq(d.g.nsegs, d2.g.nsegs);
    ck_assert(!memcmp(d.g.xy, d2.g.xy, 2 * (size_t)d.g.nverts * sizeof(double)));
    ck_assert(!memcmp(d.seg_sub, d2.seg_sub, 2 * (size_t)d.g.nsegs * sizeof(int32_t)));
    ck_assert(!memcmp(d.sub_owner, d2.sub_owner, (size_t)K * sizeof(int32_t)));
    pcdm_decomp_free(&d2);
    pcdm_decomp_free(&d);
    ck_assert_ptr_null(d.g.xy);
    pslg_free(&in);
}

START_TEST(test_auto_inputs) {
    const char *p = inputs[_i];
    pslg in;
    load(p, &in);
    double a = domain_area(&in) / 3000;
    pslg_free(&in);
    run_auto(p, 1, 1, 1, a);
    run_auto(p, 2, 2, 1, a);
    run_auto(p, 3, 3, 1, a);
    run_auto(p, 8, 8, 1, a);
    run_auto(p, 16, 4, 1, a);
    run_auto(p, 8, 8, 1, 0);
}
END_TEST

START_TEST(test_auto_many) {
    run_auto("data/lake.poly", 64, 64, 1, 0.0002);
    run_auto("data/holes.poly", 128, 2, 1, 0.0001);
}
END_TEST

START_TEST(test_imbalance) {
    pslg in;
    load("data/square.poly", &in);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nranks = 4;
    o.imbalance = 2;
    o.max_area = 0.0001;
    pcdm_decomp d;
    char err[1024];
    ck_assert_msg(pcdm_decomp_auto(&in, &o, &d, err, sizeof err) == 0, "%s", err);
    verify(&in, &d, 4, 4);
    double w0 = 0;
    for (int32_t k = 0; k < d.nsub; k++)
        if (d.sub_owner[k] == 0) w0 += d.sub_weight[k];
    printf("imbalance 2 on 4 ranks: rank 0 has %.3f of the work (target 0.4)\n",
           w0 / d.total_weight);
    ck_assert(fabs(w0 / d.total_weight - 0.4) < 0.04);
    pcdm_decomp_free(&d);
    run_auto("data/lake.poly", 12, 3, 3, 0.0005);
    run_auto("data/lake.poly", 6, 1, 1, 0.0005); /* several subdomains, one rank */
    pslg_free(&in);
}
END_TEST

START_TEST(test_errors) {
    pslg in;
    load("data/wedge.poly", &in);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = 2;
    o.nranks = 4;
    pcdm_decomp d;
    char err[1024];
    ck_assert_int_eq(pcdm_decomp_auto(&in, &o, &d, err, sizeof err), -1);
    ck_assert_msg(strstr(err, "fewer than the 4 ranks") != NULL, "%s", err);
    ck_assert_ptr_null(d.g.xy);
    printf("expected error: %s\n", err);
    /* a square whose only face is a hole: nothing to mesh */
    pslg_free(&in);
    load("data/square.poly", &in);
    free(in.holes);
    in.nholes = 1;
    in.holes = malloc(2 * sizeof *in.holes);
    in.holes[0] = in.holes[1] = 0.5;
    o.nranks = 2;
    ck_assert_int_eq(pcdm_decomp_auto(&in, &o, &d, err, sizeof err), -1);
    printf("expected error: %s\n", err);
    ck_assert_ptr_null(d.g.xy);
    pslg_free(&in);
}
END_TEST

static int cuts_try(const char *input, const char *text, int32_t K, int32_t P, pcdm_decomp *d,
                    char *err, size_t errlen) {
    char path[] = "/tmp/unit_decomp_cXXXXXX";
    int fd = mkstemp(path);
    ck_assert(fd >= 0);
    ck_assert(write(fd, text, strlen(text)) == (ssize_t)strlen(text));
    close(fd);
    pslg in;
    load(input, &in);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = K;
    o.nranks = P;
    int rc = pcdm_decomp_read_cuts(path, &in, &o, d, err, errlen);
    if (rc == 0) verify(&in, d, d->nsub, P);
    pslg_free(&in);
    unlink(path);
    char *p = rc ? strstr(err, path) : NULL;
    if (p) { /* the message names the temporary file: call it FILE */
        size_t n = strlen(path);
        memmove(p + 4, p + n, strlen(p + n) + 1);
        memcpy(p, "FILE", 4);
    }
    return rc;
}

START_TEST(test_cuts_good) {
    pcdm_decomp d;
    char err[1024];
    const char *txt = "# a cross of four quarters, with a T-junction\n"
                      "0.5 0 0.5 1   # vertical\n"
                      "\n"
                      "0 0.5 0.5 0.5\n"
                      "0.5 0.5 1 0.5\n";
    ck_assert_msg(cuts_try("data/square.poly", txt, 4, 2, &d, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(d.nsub, 4);
    for (int32_t k = 0; k < 4; k++)
        ck_assert_msg(fabs(d.sub_area[k] - 0.25) < 1e-12, "%.17g", d.sub_area[k]);
    pcdm_decomp_free(&d);
    /* an endpoint a hair off the boundary is moved onto it */
    ck_assert_msg(cuts_try("data/square.poly", "0.5 1e-9 0.5 1\n", 0, 2, &d, err, sizeof err) == 0,
                  "%s", err);
    ck_assert_int_eq(d.nsub, 2);
    pcdm_decomp_free(&d);
    /* the inclusion: its circle already separates two faces; two cuts make three */
    ck_assert_msg(cuts_try("tests/inputs/inclusion.poly", "0 0.5 0.25 0.5\n0.75 0.5 1 0.5\n", 3, 3,
                           &d, err, sizeof err) == 0,
                  "%s", err);
    pcdm_decomp_free(&d);
}
END_TEST

static void expect_bad(const char *input, const char *text, int32_t K, const char *want) {
    pcdm_decomp d;
    char err[1024];
    ck_assert_int_eq(cuts_try(input, text, K, 1, &d, err, sizeof err), -1);
    ck_assert_msg(strstr(err, want) != NULL, "got \"%s\", want \"%s\"", err, want);
    ck_assert_ptr_null(d.g.xy);
    printf("expected error: %s\n", err);
}

START_TEST(test_cuts_bad) {
    const char *sq = "data/square.poly";
    expect_bad(sq, "0.5 0 0.5 1\n0.5 0.5 zz 1\n", 0, "FILE:2: expected four finite numbers");
    expect_bad(sq, "0.5 0 0.5 1 7\n", 0, "FILE:1: trailing text");
    expect_bad(sq, "1e400 0 0.5 1\n", 0, "FILE:1: expected four finite numbers");
    expect_bad(sq, "0.5 0 0.5 1\n0.5 0 0.5 0\n", 0, "FILE:2: zero-length cut");
    expect_bad(sq, "# nothing\n", 0, "FILE: no cuts");
    expect_bad(sq, "# c\n0.5 0 0.5 0.7\n", 0, "FILE:2: the cut does not separate");
    expect_bad(sq, "0.5 0 0.5 1\n0 0.5 1 0.5\n", 0, "crosses");
    expect_bad(sq, "0 0 1 0.1\n", 0, "FILE:1: the cut meets an input segment at 5.71");
    expect_bad(sq, "0.5 0 0.5 1\n", 3, "the cuts make 2 subdomains, not the 3");
    expect_bad("data/holes.poly", "0.26 0.27 0.28 0.27\n", 0, "outside the domain");
    expect_bad(sq, "1.5 0 1.5 1\n", 0, "outside the domain");
}
END_TEST

/* ---- the exact preview and the wide sectors ------------------------------------------------ */

/* Refines the CDT of g (iface: the interface flags, may be NULL) at the bounds as ./mesh and
 * ./pcdm do; returns the triangles, or -1 if the bounds were not met. */
static int64_t mesh_at(const pslg *g, const uint8_t *iface, double q, double a) {
    mesh m;
    mesh_init(&m);
    char err[512];
    ck_assert_msg(mesh_build_cdt(&m, g, iface, err, sizeof err) == 0, "%s", err);
    mesh_quality mq;
    memset(&mq, 0, sizeof mq);
    mq.min_angle = bounds_refine_angle(q);
    mq.max_area = a;
    mq.max_steiner = -1;
    mq.offcenter = 1;
    mesh_set_quality(&m, &mq);
    int64_t n =
        mesh_refine(&m) == MESH_REFINE_DONE && mesh_count_unmet(&m, NULL) == 0 ? m.nlive : -1;
    mesh_free(&m);
    return n;
}

/* Decomposes path into K subdomains on P ranks at the bounds; checks the mesh PCDM makes on it
 * (one sequential refinement of the augmented PSLG: the mesh does not depend on the ranks)
 * meets the bounds; returns its triangles, ./mesh's in *nseq, the largest rank's work over the
 * mean in *bal, and whether the exact preview was used in *exact. */
static int64_t decomp_mesh(const char *path, int32_t K, int32_t P, double q, double a,
                           int32_t exact_per_sub, int64_t *nseq, double *bal, int *exact) {
    pslg in;
    load(path, &in);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = K;
    o.nranks = P;
    o.min_angle = q;
    o.max_area = a;
    o.exact_per_sub = exact_per_sub;
    pcdm_decomp d;
    char err[1024];
    ck_assert_msg(pcdm_decomp_auto(&in, &o, &d, err, sizeof err) == 0, "%s K=%d: %s", path, (int)K,
                  err);
    *nseq = mesh_at(&in, NULL, q, a);
    int64_t n = mesh_at(&d.g, d.seg_iface, q, a);
    double *w = calloc((size_t)P, sizeof(double)), mx = 0;
    for (int32_t k = 0; k < K; k++)
        w[d.sub_owner[k]] += d.sub_weight[k];
    for (int32_t r = 0; r < P; r++)
        mx = fmax(mx, w[r]);
    *bal = mx / (d.total_weight / P);
    *exact = d.exact;
    printf("%-22s K=%-3d P=%-2d -q %g -a %g: exact=%d coarse=%d pcdm=%lld ./mesh=%lld (%+.2f%%) "
           "balance %.3f\n",
           path, (int)K, (int)P, q, a, d.exact, (int)d.ncoarse, (long long)n, (long long)*nseq,
           100.0 * ((double)n / (double)*nseq - 1), *bal);
    free(w);
    pcdm_decomp_free(&d);
    pslg_free(&in);
    ck_assert_msg(n > 0, "%s K=%d: the bounds are not met on the decomposition", path, (int)K);
    return n;
}

/* Angle bound alone, 8 ranks: the final mesh is small, so the decomposition is drawn on the
 * exact preview: PCDM's triangles within 3% of ./mesh's (in fact equal), the ranks' triangles
 * within 10% of the mean. */
START_TEST(test_exact_angle_only) {
    static const char *const small[] = {"data/lake.poly", "data/channel.poly", "data/holes.poly"};
    int64_t nseq;
    double bal;
    int exact;
    const char *p = small[_i];
    int64_t n = decomp_mesh(p, 8, 8, 20.7, 0, 0, &nseq, &bal, &exact);
    ck_assert_int_eq(exact, 1);
    ck_assert_msg(n <= nseq * 1.03 && n >= nseq * 0.97, "%s: %lld triangles, ./mesh %lld", p,
                  (long long)n, (long long)nseq);
    ck_assert_msg(bal <= 1.10, "%s: balance %.3f", p, bal);
    /* with an area bound, small: the same */
    n = decomp_mesh(p, 8, 8, 30, 0.002, 0, &nseq, &bal, &exact);
    ck_assert_int_eq(exact, 1);
    ck_assert_msg(n <= nseq * 1.03 && n >= nseq * 0.97, "%s: %lld triangles, ./mesh %lld", p,
                  (long long)n, (long long)nseq);
    ck_assert_msg(bal <= 1.10, "%s: balance %.3f", p, bal);
}
END_TEST

/* Many subdomains: the coarse route (exact preview off) at 128 subdomains used to leave
 * interfaces meeting at 30-45 degrees whose dyadic pieces split each other down to precision
 * ("cannot meet the bounds"); the wide sectors prevent it.  The exact preview at 128
 * subdomains on a 390-triangle mesh must also meet the bounds (its trial falls back). */
START_TEST(test_many_subdomains) {
    int64_t nseq;
    double bal;
    int exact;
    int64_t n = decomp_mesh("data/lake.poly", 128, 2, 20.7, 0.001, -1, &nseq, &bal, &exact);
    ck_assert_int_eq(exact, 0);
    ck_assert_msg(n <= nseq * 1.10, "%lld triangles, ./mesh %lld", (long long)n, (long long)nseq);
    n = decomp_mesh("data/holes.poly", 100, 2, 20.7, 0.0002, -1, &nseq, &bal, &exact);
    ck_assert_int_eq(exact, 0);
    n = decomp_mesh("data/lake.poly", 128, 2, 20.7, 0.001, 0, &nseq, &bal, &exact);
    ck_assert_int_eq(exact, 1);
    ck_assert_msg(n <= nseq * 1.03, "%lld triangles, ./mesh %lld", (long long)n, (long long)nseq);
    n = decomp_mesh("data/lake.poly", 128, 2, 20.7, 0, 0, &nseq, &bal, &exact);
    n = decomp_mesh("data/channel.poly", 128, 2, 30, 0, 0, &nseq, &bal, &exact);
    (void)n;
}
END_TEST

/* Subdomains mapped to ranks: the busiest rank's predicted work at most 5% above the mean for
 * 64 subdomains on 8 ranks and 256 on 64 (METIS alone left 12% and 26% on lake at 10M
 * triangles' bound; the greedy repair after it fixes that). */
START_TEST(test_owner_balance) {
    static const int32_t kp[][2] = {{64, 8}, {256, 64}, {64, 2}, {128, 8}};
    pslg in;
    load("data/lake.poly", &in);
    for (int i = 0; i < 4; i++) {
        pcdm_decomp_opts o;
        pcdm_decomp_opts_default(&o);
        o.nsub = kp[i][0];
        o.nranks = kp[i][1];
        o.min_angle = 20.7;
        o.max_area = 3.5e-7;
        pcdm_decomp d;
        char err[1024];
        ck_assert_msg(pcdm_decomp_auto(&in, &o, &d, err, sizeof err) == 0, "%s", err);
        int32_t P = kp[i][1];
        double *w = calloc((size_t)P, sizeof(double)), mx = 0;
        for (int32_t k = 0; k < d.nsub; k++)
            w[d.sub_owner[k]] += d.sub_weight[k];
        for (int32_t r = 0; r < P; r++)
            mx = fmax(mx, w[r]);
        double bal = mx / (d.total_weight / P);
        printf("lake -a 3.5e-7 K=%d P=%d: exact=%d busiest rank / mean = %.4f\n", (int)d.nsub,
               (int)P, d.exact, bal);
        ck_assert_msg(bal <= 1.05, "K=%d P=%d: balance %.4f", (int)d.nsub, (int)P, bal);
        free(w);
        pcdm_decomp_free(&d);
    }
    pslg_free(&in);
}
END_TEST

/* The predicted cost of d (decomp_seeds.c) recomputed from its interfaces, for a uniform area
 * bound whose coarse triangles are all larger than it: each subdomain's work plus cost times
 * its interface length over sqrt(area); the costliest subdomain's. */
static double iface_cost(const pcdm_decomp *d, double cost, double area) {
    double *c = calloc((size_t)d->nsub, sizeof(double)), worst = 0;
    for (int32_t k = 0; k < d->nsub; k++)
        c[k] = d->sub_weight[k];
    for (int32_t s = d->nboundary; s < d->g.nsegs; s++) {
        const double *a = d->g.xy + 2 * (size_t)d->g.seg[2 * s],
                     *b = d->g.xy + 2 * (size_t)d->g.seg[2 * s + 1];
        double l = hypot(a[0] - b[0], a[1] - b[1]) / sqrt(area);
        for (int side = 0; side < 2; side++)
            if (d->seg_sub[2 * s + side] >= 0) c[d->seg_sub[2 * s + side]] += cost * l;
    }
    for (int32_t k = 0; k < d->nsub; k++)
        worst = fmax(worst, c[k]);
    free(c);
    return worst;
}

typedef struct pick_log {
    int calls, fail;
    double cost;
} pick_log;

static int pick_local(void *ctx, double cost, int32_t n, int32_t *part) {
    pick_log *l = ctx;
    l->calls++;
    l->cost = cost;
    ck_assert_int_gt(n, 0);
    ck_assert_int_ge(part[0], -1);
    return l->fail ? -1 : 0;
}

/* pcdm_decomp_pack / unpack (what rank 0 sends the other ranks): the same decomposition field
 * for field; every shorter buffer and a corrupt count refused; a kept CDT not packed. */
START_TEST(test_pack) {
    pslg in;
    load("data/holes.poly", &in);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = 6;
    o.nranks = 3;
    o.max_area = 0.001;
    pcdm_decomp d, e;
    char err[1024];
    ck_assert_msg(pcdm_decomp_auto(&in, &o, &d, err, sizeof err) == 0, "%s", err);
    void *buf = NULL;
    size_t len = 0;
    ck_assert_int_eq(pcdm_decomp_pack(&d, &buf, &len), 0);
    ck_assert_int_eq(pcdm_decomp_unpack(buf, len, &e), 0);
    ck_assert_int_eq(e.g.nverts, d.g.nverts);
    ck_assert_int_eq(e.g.nsegs, d.g.nsegs);
    ck_assert_int_eq(e.nsub, d.nsub);
    ck_assert_int_eq(e.nboundary, d.nboundary);
    ck_assert_int_eq(e.g.scale_exp, d.g.scale_exp);
    ck_assert(e.floor2 == d.floor2);
    ck_assert_str_eq(e.g.path, d.g.path);
    size_t nv = (size_t)d.g.nverts, ns = (size_t)d.g.nsegs, K = (size_t)d.nsub;
    ck_assert(!memcmp(e.g.xy, d.g.xy, 2 * nv * sizeof(double)));
    ck_assert(!memcmp(e.g.seg, d.g.seg, 2 * ns * sizeof(int32_t)));
    ck_assert(!memcmp(e.seg_sub, d.seg_sub, 2 * ns * sizeof(int32_t)));
    ck_assert(!memcmp(e.seg_iface, d.seg_iface, ns));
    ck_assert(!memcmp(e.vert_sub, d.vert_sub, nv * sizeof(int32_t)));
    ck_assert(!memcmp(e.sub_owner, d.sub_owner, K * sizeof(int32_t)));
    ck_assert(!memcmp(e.sub_weight, d.sub_weight, K * sizeof(double)));
    ck_assert(!memcmp(e.g.holes, d.g.holes, 2 * (size_t)d.g.nholes * sizeof(double)));
    pcdm_decomp_free(&e);
    for (size_t cut = 0; cut < len; cut += 1 + cut / 7) { /* every prefix (sampled): refused */
        ck_assert_int_eq(pcdm_decomp_unpack(buf, cut, &e), -1);
        ck_assert_ptr_null(e.g.xy);
    }
    int64_t bad = -5; /* a negative vertex count in place of the first field */
    int32_t nvert = d.g.nverts;
    memcpy(buf, &bad, sizeof nvert);
    ck_assert_int_eq(pcdm_decomp_unpack(buf, len, &e), -1);
    free(buf);
    pcdm_decomp_free(&d);
    o.keep_cdt = 1; /* ./pbw's: not carried */
    ck_assert(pcdm_decomp_auto(&in, &o, &d, err, sizeof err) == 0);
    ck_assert_int_eq(pcdm_decomp_pack(&d, &buf, &len), -1);
    pcdm_decomp_free(&d);
    pslg_free(&in);
}
END_TEST

/* The fast route (an input of FAST_MIN_VERTS vertices or more: a wavy ring of 9000) keeps its
 * triangles by subdomain: every subdomain has some, every one is counter-clockwise and in g's
 * vertices, they cover the domain's area, and they travel in the pack, in one buffer and as a
 * head and arrays (a count of triangles that disagrees with the offsets refused); the input
 * alone packs and unpacks field for field (pslg_pack, pslg_pack_head), and a cut buffer or
 * head is refused. */
START_TEST(test_pack_fast) {
    enum { N = 9000 };
    double *xy = malloc(2 * N * sizeof(double));
    int32_t *seg = malloc(2 * N * sizeof(int32_t));
    for (int i = 0; i < N; i++) {
        double t = 2 * M_PI * i / N, r = 1 + 0.1 * sin(7 * t);
        xy[2 * i] = r * cos(t);
        xy[2 * i + 1] = r * sin(t);
        seg[2 * i] = i;
        seg[2 * i + 1] = (i + 1) % N;
    }
    pslg in;
    memset(&in, 0, sizeof in);
    in.nverts = N;
    in.xy = xy;
    in.vmarker = calloc(N, sizeof(int32_t));
    in.vline = calloc(N, sizeof(int32_t));
    in.nsegs = N;
    in.seg = seg;
    in.smarker = calloc(N, sizeof(int32_t));
    in.sline = calloc(N, sizeof(int32_t));
    char err[1024];
    ck_assert_msg(pslg_check(&in, err, sizeof err) == 0, "%s", err);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = 8;
    o.nranks = 2;
    o.max_area = 1e-4;
    pcdm_decomp d, e;
    ck_assert_msg(pcdm_decomp_auto(&in, &o, &d, err, sizeof err) == 0, "%s", err);
    ck_assert_msg(d.tri_off && d.tri, "the fast route kept no triangles");
    double area = 0;
    for (int32_t k = 0; k < d.nsub; k++) {
        ck_assert_int_gt(d.tri_off[k + 1], d.tri_off[k]);
        for (int32_t t = d.tri_off[k]; t < d.tri_off[k + 1]; t++) {
            const int32_t *v = d.tri + 3 * (size_t)t;
            for (int j = 0; j < 3; j++)
                ck_assert(v[j] >= 0 && v[j] < d.g.nverts);
            double a = geom_area(d.g.xy + 2 * v[0], d.g.xy + 2 * v[1], d.g.xy + 2 * v[2]);
            ck_assert_msg(a > 0, "triangle %d of subdomain %d is not counter-clockwise", t, k);
            area += a;
        }
    }
    ck_assert_msg(fabs(area - pslg_domain_area(&in)) <= 1e-9 * area, "area %.17g, domain %.17g",
                  area, pslg_domain_area(&in));
    void *buf = NULL;
    size_t len = 0;
    ck_assert_int_eq(pcdm_decomp_pack(&d, &buf, &len), 0);
    ck_assert_int_eq(pcdm_decomp_unpack(buf, len, &e), 0);
    size_t nt = (size_t)d.tri_off[d.nsub];
    ck_assert(!memcmp(e.tri_off, d.tri_off, ((size_t)d.nsub + 1) * sizeof(int32_t)));
    ck_assert(!memcmp(e.tri, d.tri, 3 * nt * sizeof(int32_t)));
    pcdm_decomp_free(&e);
    ck_assert_int_eq(pcdm_decomp_unpack(buf, len - 4, &e), -1);
    free(buf);
    /* the ranks' form: a head, then the arrays copied from where they lie into the receiver's
     * (as the broadcasts do); a triangle count that disagrees with the offsets is refused */
    void *head = NULL;
    size_t hlen = 0;
    pcdm_pack_arr sa[PCDM_PACK_MAX_ARRS], ra[PCDM_PACK_MAX_ARRS];
    int sn = 0, rn = 0;
    ck_assert_int_eq(pcdm_decomp_pack_head(&d, &head, &hlen, sa, &sn), 0);
    for (int bad = 0; bad < 2; bad++) {
        ck_assert_int_eq(pcdm_decomp_unpack_head(head, hlen, &e, ra, &rn), 0);
        ck_assert_int_eq(rn, sn);
        for (int i = 0; i < rn; i++) {
            ck_assert_uint_eq(ra[i].len, sa[i].len);
            memcpy(ra[i].p, sa[i].p, sa[i].len);
        }
        if (bad) e.tri_off[e.nsub] -= 1; /* one triangle fewer than sent */
        ck_assert_int_eq(pcdm_decomp_unpack_done(&e, ra, rn), bad ? -1 : 0);
        if (bad) {
            ck_assert_ptr_null(e.g.xy);
            continue;
        }
        ck_assert(!memcmp(e.tri, d.tri, 3 * nt * sizeof(int32_t)));
        ck_assert(!memcmp(e.g.xy, d.g.xy, 2 * (size_t)d.g.nverts * sizeof(double)));
        ck_assert_ptr_nonnull(e.sub_seg_off); /* the per-subdomain lists made again */
        pcdm_decomp_free(&e);
    }
    ck_assert_int_eq(pcdm_decomp_unpack_head(head, hlen - 1, &e, ra, &rn), -1);
    free(head);
    pslg g;
    pslg_pack(&in, &buf, &len);
    ck_assert_int_eq(pslg_unpack(buf, len, &g), 0);
    ck_assert_int_eq(g.nverts, in.nverts);
    ck_assert_int_eq(g.nsegs, in.nsegs);
    ck_assert_int_eq(g.scale_exp, in.scale_exp);
    ck_assert(!memcmp(g.xy, in.xy, 2 * (size_t)N * sizeof(double)));
    ck_assert(!memcmp(g.seg, in.seg, 2 * (size_t)in.nsegs * sizeof(int32_t)));
    pslg_free(&g);
    pslg_pack_head(&in, &head, &hlen, sa, &sn);
    ck_assert_int_eq(pslg_unpack_head(head, hlen, &g, ra, &rn), 0);
    ck_assert_int_eq(rn, sn);
    for (int i = 0; i < rn; i++)
        memcpy(ra[i].p, sa[i].p, sa[i].len);
    ck_assert_int_eq(pslg_unpack_done(&g), 0);
    ck_assert(!memcmp(g.xy, in.xy, 2 * (size_t)N * sizeof(double)));
    pslg_free(&g);
    ck_assert_int_eq(pslg_unpack_head(head, hlen - 1, &g, ra, &rn), -1);
    free(head);
    for (size_t cut = 0; cut < len; cut += 1 + cut / 5) {
        ck_assert_int_eq(pslg_unpack(buf, cut, &g), -1);
        ck_assert_ptr_null(g.xy);
    }
    free(buf);
    pcdm_decomp_free(&d);
    pslg_free(&in);
}
END_TEST

/* ./pbw's decomposition: the best of several METIS seeds by predicted cost (boundary_cost). */
START_TEST(test_boundary_seeds) {
    pslg in;
    load("data/lake.poly", &in);
    const double area = 3.356e-7, bc = 26;
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nranks = 8;
    o.min_angle = 20.7;
    o.max_area = area;
    o.coarse_route = 1; /* as ./pbw's */
    pcdm_decomp d1, dc, d16;
    char err[1024];
    ck_assert_msg(pcdm_decomp_auto(&in, &o, &d1, err, sizeof err) == 0, "%s", err);
    /* a cost with seed 1 alone: METIS's own partition */
    o.boundary_cost = bc;
    o.seed_first = 1;
    o.seed_step = 1;
    o.seed_count = 1;
    ck_assert_msg(pcdm_decomp_auto(&in, &o, &dc, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(dc.g.nsegs, d1.g.nsegs);
    ck_assert(!memcmp(dc.seg_sub, d1.seg_sub, 2 * (size_t)d1.g.nsegs * sizeof(int32_t)));
    /* seeds 2..17 one by one: they differ, so the choice among them matters */
    double lo = INFINITY, hi = 0;
    for (int32_t s = 2; s < 18; s++) {
        pcdm_decomp ds;
        o.seed_first = s;
        ck_assert_msg(pcdm_decomp_auto(&in, &o, &ds, err, sizeof err) == 0, "%s", err);
        double c = iface_cost(&ds, bc, area);
        lo = c < lo ? c : lo;
        hi = c > hi ? c : hi;
        pcdm_decomp_free(&ds);
    }
    ck_assert_msg(hi > 1.01 * lo, "seeds 2..17 all cost %.0f", lo);
    /* the same sixteen at once: the cheapest is kept, and pick sees its cost */
    pick_log log = {0, 0, 0};
    o.seed_first = 2;
    o.seed_count = 16;
    o.pick = pick_local;
    o.pick_ctx = &log;
    ck_assert_msg(pcdm_decomp_auto(&in, &o, &d16, err, sizeof err) == 0, "%s", err);
    verify(&in, &d16, 8, 8);
    double c1 = iface_cost(&d1, bc, area), c16 = iface_cost(&d16, bc, area);
    printf("lake -a %g, 8 parts: predicted cost of the costliest part %.0f with seed 1, %.0f with "
           "the best of seeds 2..17 (pick saw %.0f; one by one %.0f to %.0f)\n",
           area, c1, c16, log.cost, lo, hi);
    ck_assert_int_eq(log.calls, 1);
    ck_assert_msg(c16 < 1.002 * lo, "seed choice: %.0f against the cheapest %.0f", c16, lo);
    /* widen and merge_corners may move a few triangles after the choice */
    ck_assert_msg(fabs(log.cost - c16) < 0.01 * c16, "pick saw %.0f, decomposition %.0f", log.cost,
                  c16);
    pcdm_decomp_free(&d16);
    /* a pick that finds no partition anywhere fails the decomposition */
    log.fail = 1;
    ck_assert(pcdm_decomp_auto(&in, &o, &d16, err, sizeof err) != 0);
    ck_assert_msg(strstr(err, "METIS") != NULL, "%s", err);
    pcdm_decomp_free(&d1);
    pcdm_decomp_free(&dc);
    pslg_free(&in);
}
END_TEST

static Suite *decomp_suite(void) {
    Suite *s = suite_create("decomp");
    TCase *tc = tcase_create("auto");
    tcase_set_timeout(tc, 300);
    tcase_add_loop_test(tc, test_auto_inputs, 0, NIN);
    tcase_add_test(tc, test_auto_many);
    tcase_add_test(tc, test_imbalance);
    tcase_add_test(tc, test_errors);
    tcase_add_loop_test(tc, test_exact_angle_only, 0, 3);
    tcase_add_test(tc, test_many_subdomains);
    tcase_add_test(tc, test_owner_balance);
    tcase_add_test(tc, test_boundary_seeds);
    tcase_add_test(tc, test_pack);
    tcase_add_test(tc, test_pack_fast);
    suite_add_tcase(s, tc);
    TCase *tf = tcase_create("cuts");
    tcase_set_timeout(tf, 60);
    tcase_add_test(tf, test_cuts_good);
    tcase_add_test(tf, test_cuts_bad);
    suite_add_tcase(s, tf);
    return s;
}

int main(void) {
    geom_init();
    setvbuf(stdout, NULL, _IOLBF, 0);
    return ck_run(decomp_suite());
}
