/* unit_decomp: Check suite for mesher/pcdm_decomp (automatic decomposition and cuts files).
 *
 * Every decomposition is verified independently of the module's own bookkeeping: the augmented
 * PSLG passes pslg_check and has no two segments crossing (exact orient2d); every angle
 * between an interface piece and another segment at a shared vertex is >= the bound; each
 * subdomain's area is recomputed from the segments and their left/right labels (Green's
 * theorem over its boundary) and must match the domain area in total and the target within
 * 10% each; seeds have winding number 1 in their own subdomain only; owners are contiguous.
 */
#include "decomp/decomp.h"
#include "geom/geom.h"
#include "geom/pslg.h"

#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define BOUND 30.0
#define BALANCE 0.10

static const char *const domains[] = {"square", "lshape", "wedge", "lake", "holes", "channel"};
#define NDOM 6

static void load(const char *name, pslg *g) {
    char path[256], err[512];
    snprintf(path, sizeof path, "data/%s.poly", name);
    ck_assert_msg(pslg_read(path, g, err, sizeof err) == 0, "%s", err);
    ck_assert_msg(pslg_check(g, err, sizeof err) == 0, "%s", err);
}

static void copy_pslg(const pslg *a, pslg *b) {
    memset(b, 0, sizeof *b);
    b->nverts = a->nverts;
    b->xy = malloc(2 * (size_t)a->nverts * sizeof *b->xy);
    memcpy(b->xy, a->xy, 2 * (size_t)a->nverts * sizeof *b->xy);
    b->vmarker = malloc((size_t)a->nverts * sizeof *b->vmarker);
    memcpy(b->vmarker, a->vmarker, (size_t)a->nverts * sizeof *b->vmarker);
    b->vline = malloc((size_t)a->nverts * sizeof *b->vline);
    memcpy(b->vline, a->vline, (size_t)a->nverts * sizeof *b->vline);
    b->nsegs = a->nsegs;
    b->seg = malloc(2 * (size_t)a->nsegs * sizeof *b->seg);
    memcpy(b->seg, a->seg, 2 * (size_t)a->nsegs * sizeof *b->seg);
    b->smarker = malloc((size_t)a->nsegs * sizeof *b->smarker);
    memcpy(b->smarker, a->smarker, (size_t)a->nsegs * sizeof *b->smarker);
    b->sline = malloc((size_t)a->nsegs * sizeof *b->sline);
    memcpy(b->sline, a->sline, (size_t)a->nsegs * sizeof *b->sline);
    b->nholes = a->nholes;
    b->holes = malloc((2 * (size_t)a->nholes + 1) * sizeof *b->holes);
    memcpy(b->holes, a->holes, 2 * (size_t)a->nholes * sizeof *b->holes);
    b->first_index = a->first_index;
    memcpy(b->path, a->path, sizeof b->path);
}

/* 1 if segments ab and cd cross, or overlap along a shared endpoint (exact orientation). */
static int segs_conflict(const double *a, const double *b, const double *c, const double *d,
                         int shared) {
    double o1 = geom_orient2d(a, b, c), o2 = geom_orient2d(a, b, d);
    double o3 = geom_orient2d(c, d, a), o4 = geom_orient2d(c, d, b);
    if (shared) {
        if (!(o1 == 0 && o2 == 0)) return 0;
        /* collinear with a common endpoint s: they overlap if the other ends lie on the same
         * side of s */
        const double *s = (a == c || a == d) ? a : b, *p = s == a ? b : a, *q = s == c ? d : c;
        return (p[0] - s[0]) * (q[0] - s[0]) + (p[1] - s[1]) * (q[1] - s[1]) > 0;
    }
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
        return 1;
    return 0;
}

typedef struct stats {
    double min_angle, max_dev, rank0_frac;
    int n60, nangles;
} stats;

/* Winding number of p with respect to the directed boundary of subdomain s. */
static int winding(const pcdm_decomp *d, int32_t s, const double *p) {
    int w = 0;
    for (int32_t i = 0; i < d->g.nsegs; i++)
        for (int side = 0; side < 2; side++) {
            if (d->seg_sub[2 * i + side] != s) continue;
            const double *a = d->g.xy + 2 * d->g.seg[2 * i + side];
            const double *b = d->g.xy + 2 * d->g.seg[2 * i + 1 - side];
            if (a[1] <= p[1]) {
                if (b[1] > p[1] && geom_orient2d(a, b, p) > 0) w++;
            } else if (b[1] <= p[1] && geom_orient2d(a, b, p) < 0) {
                w--;
            }
        }
    return w;
}

static void verify(const pslg *in, const pcdm_decomp *d, int32_t K, int32_t P, double R,
                   stats *st) {
    const pslg *g = &d->g;
    char err[512];
    ck_assert_int_eq(d->nsub, K);
    ck_assert_int_eq(d->ninput_verts, in->nverts);
    /* input vertices and segments kept */
    for (int32_t i = 0; i < in->nverts; i++)
        ck_assert(g->xy[2 * i] == in->xy[2 * i] && g->xy[2 * i + 1] == in->xy[2 * i + 1]);
    for (int32_t s = 0; s < d->nboundary; s++) {
        ck_assert(!d->seg_iface[s]);
        ck_assert_int_eq(g->smarker[s], in->smarker[d->seg_parent[s]]);
    }
    for (int32_t s = d->nboundary; s < g->nsegs; s++)
        ck_assert(d->seg_iface[s]);
    if (K == 1) ck_assert_int_eq(g->nsegs, in->nsegs);
    /* pslg_check on a copy: no crossings, no merges */
    pslg cp;
    copy_pslg(g, &cp);
    ck_assert_msg(pslg_check(&cp, err, sizeof err) == 0, "pslg_check: %s", err);
    ck_assert_int_eq(cp.nverts, g->nverts);
    ck_assert_int_eq(cp.nsegs, g->nsegs);
    pslg_free(&cp);
    /* exact crossing test of every interface piece against every segment */
    for (int32_t s = d->nboundary; s < g->nsegs; s++)
        for (int32_t t = 0; t < g->nsegs; t++) {
            if (t == s) continue;
            int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1], c = g->seg[2 * t],
                    e = g->seg[2 * t + 1];
            int shared = a == c || a == e || b == c || b == e;
            ck_assert_msg(
                !segs_conflict(g->xy + 2 * a, g->xy + 2 * b, g->xy + 2 * c, g->xy + 2 * e, shared),
                "interface piece %d crosses segment %d", s, t);
        }
    /* angles at shared vertices */
    st->min_angle = 180;
    st->n60 = st->nangles = 0;
    for (int32_t s = d->nboundary; s < g->nsegs; s++)
        for (int end = 0; end < 2; end++) {
            int32_t v = g->seg[2 * s + end], o = g->seg[2 * s + 1 - end];
            for (int32_t t = 0; t < g->nsegs; t++) {
                if (t == s || (g->seg[2 * t] != v && g->seg[2 * t + 1] != v)) continue;
                int32_t o2 = g->seg[2 * t] == v ? g->seg[2 * t + 1] : g->seg[2 * t];
                double ang = geom_angle_deg(g->xy + 2 * o, g->xy + 2 * v, g->xy + 2 * o2);
                st->min_angle = fmin(st->min_angle, ang);
                st->nangles++;
                st->n60 += ang >= 60;
                ck_assert_msg(ang >= BOUND, "angle %.3f at vertex %d below %.1f", ang, v, BOUND);
            }
        }
    /* sides, and areas from the labelled segments (Green) */
    double *area = calloc((size_t)K, sizeof *area), total = 0;
    for (int32_t s = 0; s < g->nsegs; s++) {
        int32_t l = d->seg_sub[2 * s], r = d->seg_sub[2 * s + 1];
        ck_assert(l >= -1 && l < K && r >= -1 && r < K);
        if (d->seg_iface[s])
            ck_assert_msg(l >= 0 && r >= 0 && l != r, "interface piece %d sides %d %d", s, l, r);
        else
            ck_assert_msg((l >= 0) != (r >= 0), "boundary piece %d sides %d %d", s, l, r);
        const double *a = g->xy + 2 * g->seg[2 * s], *b = g->xy + 2 * g->seg[2 * s + 1];
        double cr = 0.5 * (a[0] * b[1] - a[1] * b[0]);
        if (l >= 0) area[l] += cr;
        if (r >= 0) area[r] -= cr;
    }
    for (int32_t k = 0; k < K; k++) {
        ck_assert_msg(area[k] > 0, "subdomain %d area %g", k, area[k]);
        ck_assert(fabs(area[k] - d->sub_area[k]) <= 1e-9 * fabs(area[k]) + 1e-15);
        total += area[k];
    }
    double dom = pslg_domain_area(in);
    ck_assert_msg(fabs(total - dom) <= 1e-9 * dom, "total %.17g domain %.17g", total, dom);
    /* balance: area against target (no area bound: weight = area) */
    st->max_dev = 0;
    double tsum = 0;
    for (int32_t k = 0; k < K; k++) {
        double dev = fabs(area[k] / total / d->sub_target[k] - 1);
        st->max_dev = fmax(st->max_dev, dev);
        ck_assert_msg(dev <= BALANCE, "subdomain %d: area fraction %.4f target %.4f", k,
                      area[k] / total, d->sub_target[k]);
        tsum += d->sub_target[k];
    }
    ck_assert(fabs(tsum - 1) < 1e-12);
    /* seeds */
    for (int32_t k = 0; k < K; k++)
        for (int32_t j = 0; j < K; j++)
            ck_assert_int_eq(winding(d, j, d->sub_seed + 2 * k), j == k);
    /* owners: contiguous, every rank, rank 0's share */
    double *rw = calloc((size_t)P, sizeof *rw);
    for (int32_t k = 0; k < K; k++) {
        ck_assert(d->sub_owner[k] >= 0 && d->sub_owner[k] < P);
        if (k)
            ck_assert(d->sub_owner[k] == d->sub_owner[k - 1] ||
                      d->sub_owner[k] == d->sub_owner[k - 1] + 1);
        rw[d->sub_owner[k]] += area[k];
    }
    ck_assert_int_eq(d->sub_owner[0], 0);
    ck_assert_int_eq(d->sub_owner[K - 1], P - 1);
    st->rank0_frac = rw[0] / total;
    for (int32_t r = 0; r < P; r++) {
        double want = (r == 0 ? R : 1) / (R + P - 1);
        ck_assert_msg(fabs(rw[r] / total / want - 1) <= BALANCE, "rank %d share %.4f want %.4f", r,
                      rw[r] / total, want);
    }
    free(rw);
    free(area);
}

static void run_one(const char *name, int32_t K, int32_t P, double R) {
    pslg in;
    load(name, &in);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = K;
    o.nranks = P;
    o.imbalance = R;
    o.min_angle = BOUND;
    pcdm_decomp d, d2;
    char err[1024];
    ck_assert_msg(pcdm_decomp_auto(&in, &o, &d, err, sizeof err) == 0, "%s K=%d: %s", name, K, err);
    stats st;
    verify(&in, &d, K, P, R, &st);
    printf("decomp %-8s K=%-2d P=%d R=%g: cuts=%d pieces=%d max-dev=%5.2f%% min-angle=%6.2f "
           "(>=60: %d/%d) rank0=%.4f\n",
           name, (int)K, (int)P, R, (int)d.ncuts, (int)(d.g.nsegs - d.nboundary), 100 * st.max_dev,
           st.min_angle, st.n60, st.nangles, st.rank0_frac);
    /* determinism: a second run is bitwise identical */
    ck_assert(pcdm_decomp_auto(&in, &o, &d2, err, sizeof err) == 0);
    ck_assert_int_eq(d.g.nverts, d2.g.nverts);
    ck_assert_int_eq(d.g.nsegs, d2.g.nsegs);
    ck_assert(!memcmp(d.g.xy, d2.g.xy, 2 * (size_t)d.g.nverts * sizeof(double)));
    ck_assert(!memcmp(d.g.seg, d2.g.seg, 2 * (size_t)d.g.nsegs * sizeof(int32_t)));
    ck_assert(!memcmp(d.seg_sub, d2.seg_sub, 2 * (size_t)d.g.nsegs * sizeof(int32_t)));
    ck_assert(!memcmp(d.sub_seed, d2.sub_seed, 2 * (size_t)K * sizeof(double)));
    ck_assert(!memcmp(d.sub_weight, d2.sub_weight, (size_t)K * sizeof(double)));
    ck_assert(!memcmp(d.sub_owner, d2.sub_owner, (size_t)K * sizeof(int32_t)));
    pcdm_decomp_free(&d2);
    /* the cuts written out read back to the same subdomains */
    if (K > 1) {
        char path[] = "/tmp/unit_decomp_cutsXXXXXX";
        int fd = mkstemp(path);
        ck_assert(fd >= 0);
        close(fd);
        ck_assert_msg(pcdm_decomp_write_cuts(&d, path, err, sizeof err) == 0, "%s", err);
        pcdm_decomp_opts oc = o;
        oc.min_angle = 0;
        ck_assert_msg(pcdm_decomp_read_cuts(path, &in, &oc, &d2, err, sizeof err) == 0,
                      "%s K=%d cuts read back: %s", name, K, err);
        ck_assert_int_eq(d2.nsub, K);
        double a1 = 0, a2 = 0;
        for (int32_t k = 0; k < K; k++) {
            a1 += d.sub_area[k];
            a2 += d2.sub_area[k];
        }
        ck_assert(fabs(a1 - a2) <= 1e-9 * a1);
        pcdm_decomp_free(&d2);
        unlink(path);
    }
    pcdm_decomp_free(&d);
    pslg_free(&in);
}

START_TEST(test_auto_sweep) {
    const int32_t ks[] = {1, 2, 4, 8};
    for (int k = 0; k < 4; k++)
        run_one(domains[_i], ks[k], 1, 1);
}
END_TEST

START_TEST(test_auto_16) {
    const char *const names[] = {"lake", "channel", "holes", "square", "lshape", "wedge"};
    run_one(names[_i], 16, 1, 1);
}
END_TEST

START_TEST(test_ranks) {
    run_one(domains[_i], 4, 4, 1);
    run_one(domains[_i], 8, 4, 1);
    run_one(domains[_i], 6, 4, 1);
}
END_TEST

START_TEST(test_imbalance) {
    run_one(domains[_i], 4, 4, 2);
    run_one(domains[_i], 8, 4, 2);
}
END_TEST

START_TEST(test_too_many) {
    pslg in;
    load("wedge", &in);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = 4096;
    pcdm_decomp d;
    char err[1024];
    ck_assert_int_eq(pcdm_decomp_auto(&in, &o, &d, err, sizeof err), -1);
    ck_assert_msg(strstr(err, "too many subdomains") != NULL, "%s", err);
    ck_assert_ptr_null(d.g.xy);
    printf("expected error: %s\n", err);
    o.nsub = 2;
    o.nranks = 4;
    ck_assert_int_eq(pcdm_decomp_auto(&in, &o, &d, err, sizeof err), -1);
    ck_assert_msg(strstr(err, "at least one per rank") != NULL, "%s", err);
    pslg_free(&in);
}
END_TEST

START_TEST(test_empty) {
    /* a square whose only face is a hole: zero area */
    pslg in;
    load("square", &in);
    in.nholes = 1;
    free(in.holes);
    in.holes = malloc(2 * sizeof *in.holes);
    in.holes[0] = in.holes[1] = 0.5;
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = 2;
    pcdm_decomp d;
    char err[1024];
    ck_assert_int_eq(pcdm_decomp_auto(&in, &o, &d, err, sizeof err), -1);
    ck_assert_msg(strstr(err, "empty domain") != NULL, "%s", err);
    printf("expected error: %s\n", err);
    pslg_free(&in);
}
END_TEST

static int cuts_try(const char *domain, const char *text, int32_t K, pcdm_decomp *d, char *err,
                    size_t errlen) {
    char path[] = "/tmp/unit_decomp_cXXXXXX";
    int fd = mkstemp(path);
    ck_assert(fd >= 0);
    ck_assert(write(fd, text, strlen(text)) == (ssize_t)strlen(text));
    close(fd);
    pslg in;
    load(domain, &in);
    pcdm_decomp_opts o;
    pcdm_decomp_opts_default(&o);
    o.nsub = K;
    o.min_angle = BOUND;
    int rc = pcdm_decomp_read_cuts(path, &in, &o, d, err, errlen);
    if (rc == 0) {
        ck_assert(d->nsub >= 1);
        ck_assert(fabs(d->total_weight - pslg_domain_area(&in)) < 1e-9);
    }
    pslg_free(&in);
    unlink(path);
    if (rc) {
        /* message names the temporary file: replace it for the caller */
        char *p = strstr(err, path);
        if (p) {
            size_t n = strlen(path);
            memmove(p + 4, p + n, strlen(p + n) + 1);
            memcpy(p, "FILE", 4);
        }
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
    ck_assert_msg(cuts_try("square", txt, 4, &d, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(d.nsub, 4);
    ck_assert_int_eq(d.ncuts, 3);
    for (int32_t k = 0; k < 4; k++)
        ck_assert(fabs(d.sub_area[k] - 0.25) < 1e-12);
    pslg in;
    load("square", &in);
    stats st;
    verify(&in, &d, 4, 1, 1, &st);
    ck_assert(fabs(st.min_angle - 90) < 1e-9);
    pslg_free(&in);
    pcdm_decomp_free(&d);
    /* a cut through the channel's hole: two pieces, two subdomains */
    ck_assert_msg(cuts_try("channel", "1 0 1 1\n", 0, &d, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(d.nsub, 2);
    pcdm_decomp_free(&d);
    ck_assert_msg(cuts_try("channel", "0.5 0 0.5 0.4\n0.5 0.6 0.5 1\n", 2, &d, err, sizeof err) ==
                      0,
                  "%s", err);
    ck_assert_int_eq(d.nsub, 2);
    pcdm_decomp_free(&d);
}
END_TEST

static void expect_bad(const char *domain, const char *text, int32_t K, const char *want) {
    pcdm_decomp d;
    char err[1024];
    ck_assert_int_eq(cuts_try(domain, text, K, &d, err, sizeof err), -1);
    ck_assert_msg(strstr(err, want) != NULL, "got \"%s\", want \"%s\"", err, want);
    ck_assert_ptr_null(d.g.xy);
    printf("expected error: %s\n", err);
}

START_TEST(test_cuts_bad) {
    expect_bad("square", "0.5 0 0.5 1\n0.5 0.5 zz 1\n", 0, "FILE:2: expected four numbers");
    expect_bad("square", "0.5 0 0.5 1 7\n", 0, "FILE:1: expected four numbers");
    expect_bad("square", "# c\n0.5 0 0.5 0.7\n", 0, "FILE:2: endpoint (0.5, 0.69999");
    expect_bad("square", "0.5 0 0.5 1\n0 0.5 1 0.5\n", 0,
               "FILE:1: cut crosses or overlaps the cut on line 2");
    expect_bad("square", "0.5 0 0.5 1\n0.5 0.2 0.5 0.8\n", 0, "overlaps");
    expect_bad("square", "0 0 1 0.1\n", 0, "FILE:1: cut meets a segment at 5.71");
    expect_bad("square", "0.5 0 0.5 1\n", 3, "the cuts make 2 subdomains, but 3");
    expect_bad("square", "0.5 0 0.5 1\n0.5 0 0.5 0\n", 0, "FILE:2: cut has zero length");
    expect_bad("channel", "0.45 0.45 0.55 0.55\n", 0, "not on the domain boundary");
    expect_bad("channel", "0.4 0.5 0.6 0.5\n", 0, "FILE:1: cut lies (partly) outside");
    expect_bad("channel", "0.5 0 0.5 0.4\n", 0, "FILE:1: cut does not separate");
    expect_bad("square", "1e400 0 0.5 1\n", 0, "FILE:1: non-finite");
}
END_TEST

static Suite *decomp_suite(void) {
    Suite *s = suite_create("decomp");
    TCase *tc = tcase_create("auto");
    tcase_set_timeout(tc, 300);
    tcase_add_loop_test(tc, test_auto_sweep, 0, NDOM);
    tcase_add_loop_test(tc, test_auto_16, 0, 6);
    tcase_add_loop_test(tc, test_ranks, 0, NDOM);
    tcase_add_loop_test(tc, test_imbalance, 0, NDOM);
    tcase_add_test(tc, test_too_many);
    tcase_add_test(tc, test_empty);
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
    SRunner *sr = srunner_create(decomp_suite());
    srunner_run_all(sr, CK_NORMAL);
    int nf = srunner_ntests_failed(sr);
    srunner_free(sr);
    return nf ? EXIT_FAILURE : EXIT_SUCCESS;
}
