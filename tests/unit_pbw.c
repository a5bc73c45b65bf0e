/* unit_pbw.c - the parts of ./pbw that need no MPI (issue 13): the store (vertex table, triangle
 * slots, the bad-triangle queue on the shared rules), the work items and locks (deferral,
 * wakes, refused splits, holds), the cavity state's wire format, and the rules PBW shares with
 * refine.c (the forced-angle rule with its consecutive-segment test, the queue priority, the
 * length floor), and the ghosts (conflict decided on a remote neighbour's ghost, tombstones
 * forwarding stale links), and the local fast path (pbw_local.c).  Each
 * test builds a context by hand, as pbw_setup would, with rank 0 of 1. */
#include "check_run.h"
#include "pbw/pbw_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static pbw_ctx *ctx_new(double min_angle, double max_area) {
    geom_init();
    pbw_ctx *C = mesh_xcalloc(1, sizeof *C);
    mesh_init(&C->M);
    for (int i = 0; i < 32; i++) /* segment ids for the constraints the tests name */
        mesh_seg_add(&C->M, 0, 0, 0, 0);
    C->rank = 0;
    C->size = 1;
    C->confree = -1;
    C->cursor = NBUCKET + 1;
    C->qhi = -1;
    mesh_rules_init(&C->R, min_angle, max_area, 1, 0);
    C->steiner_limit = -1;
    pbw_vt_rehash(C, 16);
    return C;
}

/* A live triangle on vertex slots a, b, c (counter-clockwise), no neighbours or constraints. */
static int32_t tri(pbw_ctx *C, int32_t a, int32_t b, int32_t c) {
    int32_t s = pbw_slot_alloc(C);
    int32_t v[3] = {a, b, c};
    for (int j = 0; j < 3; j++) {
        C->M.tv[3 * s + j] = v[j];
        pbw_tn_set(C, 3 * s + j, NOREF);
        pbw_con_set(C, 3 * (size_t)s + (size_t)j, -1, -1, 0);
    }
    C->nlive++;
    return s;
}

START_TEST(test_vertex_table) {
    pbw_ctx *C = ctx_new(0, 0);
    enum { N = 5000 };
    for (int32_t i = 0; i < N; i++) {
        int64_t gid = i < 100 ? i : ((int64_t)(1 + i % 7) << 32) | i;
        int32_t v = pbw_vt_add(C, gid, i * 0.5, -i * 0.25, i % 3 - 1);
        ck_assert_int_eq(v, i);
    }
    ck_assert_int_eq(C->M.nv, N);
    ck_assert_uint_ge(C->vhcap, 2 * (uint32_t)N);
    for (int32_t i = 0; i < N; i++) {
        int64_t gid = i < 100 ? i : ((int64_t)(1 + i % 7) << 32) | i;
        int32_t v = pbw_vt_find(C, gid);
        ck_assert_int_eq(v, i);
        ck_assert(VX(C, v)[0] == i * 0.5 && VX(C, v)[1] == -i * 0.25);
        ck_assert_int_eq(C->M.vseg[v], i % 3 - 1);
        /* adding a known id again returns its slot and keeps its coordinates */
        ck_assert_int_eq(pbw_vt_add(C, gid, 1e9, 1e9, 5), i);
        ck_assert(VX(C, v)[0] == i * 0.5);
    }
    ck_assert_int_eq(pbw_vt_find(C, (int64_t)9 << 32), -1);
    ck_assert_int_eq(pbw_vt_find(C, N + 1000), -1);
    pbw_ctx_free(C);
}
END_TEST

START_TEST(test_slots_reuse) {
    pbw_ctx *C = ctx_new(0, 0);
    pbw_vt_add(C, 0, 0, 0, -1);
    pbw_vt_add(C, 1, 1, 0, -1);
    pbw_vt_add(C, 2, 0, 1, -1);
    int32_t s[3];
    for (int i = 0; i < 3; i++) {
        s[i] = tri(C, 0, 1, 2);
        ck_assert_int_eq(s[i], i);
        ck_assert(alive(C, s[i]));
        ck_assert_int_eq(TG(C, s[i], 1), 1);
    }
    ck_assert_int_eq(pbw_find_edge(C, s[0], 1, 2), 1);
    ck_assert_int_eq(pbw_find_edge(C, s[0], 2, 1), -1);
    pbw_slot_free(C, s[1]);
    ck_assert(!alive(C, s[1]));
    ck_assert(!alive(C, -1) && !alive(C, 99));
    ck_assert_int_eq(pbw_slot_alloc(C), s[1]); /* the free list first */
    ck_assert_int_eq(LK(C, s[1]), -1);
    ck_assert_int_eq(ROLE(C, s[1]), ROLE_NONE);
    ck_assert_int_eq(pbw_slot_alloc(C), 3);
    pbw_ctx_free(C);
}
END_TEST

START_TEST(test_bad_queue_order) {
    /* -q 30 -a 1: a good triangle is not queued; the bad ones come out shortest edge first */
    pbw_ctx *C = ctx_new(30, 1.0);
    const double p[][2] = {{0, 0},  {1, 0},  {0.5, 0.866}, {4, 0},  {4.5, 0.1}, {0, 1},
                           {10, 0}, {12, 0}, {11, 1.7},    {20, 0}, {20.01, 0}, {20.005, 1}};
    for (int32_t i = 0; i < 12; i++)
        pbw_vt_add(C, i, p[i][0], p[i][1], -1);
    int32_t good = tri(C, 0, 1, 2);     /* equilateral, area 0.43 */
    int32_t sliver = tri(C, 1, 3, 4);   /* skinny, shortest edge ~0.51 */
    int32_t big = tri(C, 6, 7, 8);      /* well shaped, area 1.7 > 1 */
    int32_t needle = tri(C, 9, 10, 11); /* skinny, shortest edge 0.01 */
    (void)tri(C, 0, 1, 5);              /* right isosceles, area 0.5: good */
    int sh = -1;
    ck_assert_int_eq(pbw_quality(C, good, NULL, &sh), 0);
    ck_assert_int_eq(pbw_quality(C, sliver, NULL, &sh), MESH_BAD_ANGLE);
    ck_assert_int_eq(pbw_quality(C, big, NULL, &sh), MESH_BAD_AREA);
    ck_assert_int_eq(pbw_quality(C, needle, NULL, &sh), MESH_BAD_ANGLE);
    ck_assert_int_eq(sh, 0); /* edge 9-10 */
    for (int32_t t = 0; t < C->M.nt; t++)
        pbw_push_bad(C, t);
    ck_assert_int_eq(pbw_pop_bad(C), needle);
    ck_assert_int_eq(pbw_pop_bad(C), sliver);
    ck_assert_int_eq(pbw_pop_bad(C), big);
    ck_assert_int_eq(pbw_pop_bad(C), -1);
    pbw_ctx_free(C);
}
END_TEST

START_TEST(test_deferred_wakes) {
    pbw_ctx *C = ctx_new(0, 0);
    pbw_item it;
    memset(&it, 0, sizeof it);
    it.kind = IT_BAD;
    it.t = 7;
    /* two splits asked for: back to work after both wakes */
    pbw_defer_item(C, &it, W_WAKE, 42, 2);
    ck_assert(pbw_iv_empty(&C->retryq));
    pbw_wake_key(C, 42, 0);
    ck_assert(pbw_iv_empty(&C->retryq));
    pbw_wake_key(C, 41, 0); /* another key: nothing */
    ck_assert(pbw_iv_empty(&C->retryq));
    pbw_notify(C, 0, 42, 0); /* to this rank: no message */
    pbw_item got;
    ck_assert(pbw_iv_pop(&C->retryq, &got));
    ck_assert_int_eq(got.t, 7);
    ck_assert(!pbw_iv_pop(&C->retryq, &got));
    /* one of two splits refused: the item is dropped, not retried */
    it.t = 8;
    pbw_defer_item(C, &it, W_WAKE, 43, 2);
    pbw_wake_key(C, 43, 1);
    pbw_wake_key(C, 43, 0);
    ck_assert(pbw_iv_empty(&C->retryq));
    ck_assert_int_eq(C->deferred.n - C->deferred.head, 0);
    /* waiting for a hold that does not exist: retried at once */
    it.t = 9;
    pbw_defer_item(C, &it, W_HOLD, 77, 1);
    ck_assert(pbw_iv_pop(&C->retryq, &got));
    ck_assert_int_eq(got.t, 9);
    pbw_ctx_free(C);
}
END_TEST

/* A cavity rejected for encroachment waits for its splits' WAKEs under its split ticket, not
 * under its key: a WAKE naming the key (it released somewhere, sent to the cavities that died
 * on it) must not send it back to work before its splits are done (the retry storm). */
START_TEST(test_split_ticket) {
    pbw_ctx *C = ctx_new(0, 0);
    pbw_cav *c = pbw_cav_new(C);
    c->h.key = ((int64_t)1 << 40) | 5;
    c->h.kind = K_INSERT;
    c->h.status = ST_OK;
    c->it.kind = IT_BAD;
    c->it.t = 3;
    pbw_bnd b;
    memset(&b, 0, sizeof b);
    b.ga = 1;
    b.gb = 2;
    b.cseg = 0;
    b.flags = BF_ENC;
    b.inref = mkref(0, 3); /* the member on the subsegment: here, so the split is queued here */
    c->b = mesh_xmalloc(1, sizeof b);
    c->b[0] = b;
    c->nb = c->bcap = 1;
    pbw_finish(C, c);
    ck_assert_int_eq(C->res.rejected, 1);
    pbw_item got;
    ck_assert(pbw_iv_pop(&C->splitq, &got));
    ck_assert(got.ticket == split_ticket(c->h.key) && got.ticket != c->h.key);
    ck_assert(pbw_iv_empty(&C->retryq));
    pbw_wake_key(C, c->h.key, 0); /* released somewhere: not what it waits for */
    ck_assert(pbw_iv_empty(&C->retryq));
    pbw_wake_key(C, got.ticket, 0); /* its split is done */
    ck_assert(pbw_iv_pop(&C->retryq, &got));
    ck_assert_int_eq(got.t, 3);
    pbw_cav_free(c);
    pbw_ctx_free(C);
}
END_TEST

START_TEST(test_holds) {
    pbw_ctx *C = ctx_new(0, 0);
    pbw_vt_add(C, 0, 0, 0, -1);
    pbw_vt_add(C, 1, 1, 0, -1);
    pbw_vt_add(C, 2, 0, 1, -1);
    int32_t a = tri(C, 0, 1, 2), b = tri(C, 0, 1, 2);
    int32_t hi = pbw_hold_new(C, 5, 100, 0);
    ck_assert_int_eq(pbw_hold_find(C, 5), hi);
    ck_assert_int_eq(pbw_hold_find(C, 6), -1);
    pbw_lock_slot(C, a, hi, ROLE_MEMBER);
    pbw_lock_slot(C, b, hi, ROLE_HALO);
    pbw_lock_slot(C, a, hi, ROLE_MEMBER); /* once */
    int32_t r = pbw_slot_alloc(C);
    pbw_lock_slot(C, r, hi, ROLE_RES);
    ck_assert_int_eq(C->hd[hi].n, 3);
    ck_assert_int_eq(LK(C, a), hi);
    /* an item deferred on the hold comes back when a distributed hold ends */
    pbw_item it;
    memset(&it, 0, sizeof it);
    it.t = a;
    C->hd[hi].distributed = 1;
    pbw_defer_item(C, &it, W_HOLD, 5, 1);
    ck_assert(pbw_iv_empty(&C->retryq));
    pbw_release_local(C, hi, 0);
    ck_assert_int_eq(pbw_hold_find(C, 5), -1);
    ck_assert_int_eq(LK(C, a), -1);
    ck_assert_int_eq(LK(C, b), -1);
    ck_assert(alive(C, a) && alive(C, b));
    ck_assert(!alive(C, r)); /* the reserved slot went back to the free list */
    ck_assert_int_eq(pbw_slot_alloc(C), r);
    ck_assert(!pbw_iv_empty(&C->retryq));
    /* the hold's entry is reused */
    ck_assert_int_eq(pbw_hold_new(C, 9, 1, 0), hi);
    pbw_ctx_free(C);
}
END_TEST

START_TEST(test_cavity_wire_format) {
    pbw_ctx *C = ctx_new(0, 0);
    pbw_cav *c = pbw_cav_new(C);
    ck_assert_ptr_eq(c->C, C);
    c->h.key = 12345;
    c->h.p[0] = 0.1;
    c->h.p[1] = -3e-300;
    c->h.cycle = 1;
    pbw_part_add(c, 3);
    pbw_part_add(c, 1);
    pbw_part_add(c, 3);
    ck_assert_int_eq(c->np, 2);
    for (int i = 0; i < 5; i++) {
        MESH_GROW(c->b, c->nb, c->bcap);
        memset(&c->b[c->nb], 0, sizeof c->b[0]);
        c->b[c->nb].ga = i;
        c->b[c->nb].cseg = -1;
        c->nb++;
    }
    pbw_push_seed(C, c, mkref(2, 17), mkref(0, 1), NOREF, 4, 5, SEED_NORMAL); /* remote: pending */
    pbw_push_seed(C, c, mkref(0, 3), mkref(0, 1), NOREF, 5, 6, SEED_HALO);    /* local: stack */
    ck_assert_int_eq(c->ntodo, 1);
    ck_assert_int_eq(c->nstk, 1);
    uint32_t len;
    void *buf = pbw_cav_pack(c, 1, &len);
    pbw_cav *d = pbw_cav_new(C);
    pbw_cav_unpack_into(d, buf, len);
    ck_assert_int_eq(d->h.key, 12345);
    ck_assert(d->h.p[0] == 0.1 && d->h.p[1] == -3e-300);
    ck_assert_int_eq(d->h.cycle, 1);
    ck_assert_int_eq(d->np, 2);
    ck_assert_int_eq(d->nb, 5);
    ck_assert_int_eq(d->b[4].ga, 4);
    ck_assert_int_eq(d->ntodo, 1);
    ck_assert_int_eq(ref_rank(d->todo[0].target), 2);
    ck_assert_int_eq(ref_idx(d->todo[0].target), 17);
    free(buf);
    /* a header-only pack (a reply that died) carries no edges or seeds */
    buf = pbw_cav_pack(c, 0, &len);
    ck_assert_uint_eq(len, sizeof(pbw_whdr) + 8);
    pbw_cav_unpack_into(d, buf, len);
    ck_assert_int_eq(d->nb, 0);
    ck_assert_int_eq(d->ntodo, 0);
    free(buf);
    pbw_part_remove(c, 3);
    ck_assert_int_eq(c->np, 1);
    ck_assert_int_eq(c->parts[0], 1);
    pbw_cav_free(c);
    pbw_cav_free(d);
    pbw_cav_free(NULL);
    pbw_ctx_free(C);
}
END_TEST

/* The input of the forced-angle tests: corner a = 0 at the origin with segments to 1 (along
 * x) and 2 (at 20 degrees); with `third`, a segment to 3 at 10 degrees lies between them. */
typedef struct corner_input {
    double xy[8];
    int32_t seg[6], inc_off[5], inc_seg[6];
    uint8_t corner[4], siface[3];
    mesh_rules_input I;
} corner_input;

static void corner_setup(corner_input *c, int third, int third_iface) {
    double r = M_PI / 180.0;
    double xy[8] = {0, 0, 1, 0, cos(20 * r), sin(20 * r), cos(10 * r), sin(10 * r)};
    memcpy(c->xy, xy, sizeof xy);
    int32_t seg[6] = {0, 1, 0, 2, 0, 3};
    memcpy(c->seg, seg, sizeof seg);
    int ns = third ? 3 : 2;
    /* CSR: vertex 0 has every segment, vertex k has segment k-1 */
    c->inc_off[0] = 0;
    c->inc_off[1] = ns;
    c->inc_off[2] = ns + 1;
    c->inc_off[3] = ns + 2;
    c->inc_off[4] = ns + 2 + (third ? 1 : 0);
    for (int i = 0; i < ns; i++)
        c->inc_seg[i] = i;
    c->inc_seg[ns] = 0;
    c->inc_seg[ns + 1] = 1;
    if (third) c->inc_seg[ns + 2] = 2;
    memset(c->corner, 0, sizeof c->corner);
    c->corner[0] = 1;
    memset(c->siface, 0, sizeof c->siface);
    c->siface[2] = (uint8_t)third_iface;
    c->I.ninput = third ? 4 : 3;
    c->I.xy = c->xy;
    c->I.seg = c->seg;
    c->I.inc_off = c->inc_off;
    c->I.inc_seg = c->inc_seg;
    c->I.corner = c->corner;
    c->I.siface = third_iface ? c->siface : NULL;
}

START_TEST(test_rules_edge_forced) {
    geom_init();
    corner_input c;
    double r = M_PI / 180.0;
    double u[2] = {0.5, 0}, v[2] = {0.5 * cos(20 * r), 0.5 * sin(20 * r)};
    double w[2] = {0.3 * cos(20 * r), 0.3 * sin(20 * r)};
    /* Steiner vertices on segments 0 and 1, at the same distance from the corner: forced */
    corner_setup(&c, 0, 0);
    ck_assert_int_eq(mesh_rules_edge_forced(&c.I, -1, 0, u, -1, 1, v), 1);
    ck_assert_int_eq(mesh_rules_edge_forced(&c.I, -1, 1, v, -1, 0, u), 1);
    /* not at the same distance, on one segment, or on no segment: not forced */
    ck_assert_int_eq(mesh_rules_edge_forced(&c.I, -1, 0, u, -1, 1, w), 0);
    ck_assert_int_eq(mesh_rules_edge_forced(&c.I, -1, 0, u, -1, 0, u), 0);
    ck_assert_int_eq(mesh_rules_edge_forced(&c.I, -1, -1, u, -1, 1, v), 0);
    /* an input vertex at the far end of a segment counts by its incident segments */
    double one[2] = {1, 0}, vv[2] = {cos(20 * r), sin(20 * r)};
    ck_assert_int_eq(mesh_rules_edge_forced(&c.I, 1, -1, one, 2, -1, vv), 1);
    /* no corners known: never forced */
    c.I.corner = NULL;
    ck_assert_int_eq(mesh_rules_edge_forced(&c.I, -1, 0, u, -1, 1, v), 0);
    /* a third input segment between them: 0 and 1 are not consecutive (refine.c's test that
     * PBW's old copy lacked) */
    corner_setup(&c, 1, 0);
    ck_assert_int_eq(mesh_rules_edge_forced(&c.I, -1, 0, u, -1, 1, v), 0);
    /* ... unless it is an interface segment, which is not the input's */
    corner_setup(&c, 1, 1);
    ck_assert_int_eq(mesh_rules_edge_forced(&c.I, -1, 0, u, -1, 1, v), 1);
}
END_TEST

START_TEST(test_rules_priority_floor) {
    geom_init();
    /* shortest edge first: the bucket grows with the squared length, by binary exponent */
    ck_assert_int_lt(mesh_rules_bucket(1e-6), mesh_rules_bucket(1e-3));
    ck_assert_int_lt(mesh_rules_bucket(1.0), mesh_rules_bucket(4.0));
    ck_assert_int_eq(mesh_rules_bucket(1.0), mesh_rules_bucket(1.5));
    ck_assert_int_lt(mesh_rules_bucket(1e-300), mesh_rules_bucket(1e-6));
    ck_assert_int_lt(mesh_rules_bucket(1e300), MESH_RULES_NBUCKET);
    /* the floor of one right triangle with legs 1: smallest altitude^2 = 1/2, magnitude 1 */
    double xy[] = {0, 0, 1, 0, 0, 1, 5, 5};
    int32_t tv[] = {0, 1, 2, -2, 0, 0};
    double f = mesh_rules_length_floor2(xy, 3, tv, 2);
    ck_assert(f == fmax(0.5 * 0x1p-48, 0x1p-88));
    /* far from the origin the magnitude term wins */
    double xy2[] = {1e6, 0, 1e6 + 1, 0, 1e6, 1};
    ck_assert(mesh_rules_length_floor2(xy2, 3, tv, 1) == (1e6 + 1) * (1e6 + 1) * 0x1p-88);
    ck_assert_int_eq(mesh_rules_unresolved_budget(0), 256);
    ck_assert_int_eq(mesh_rules_unresolved_budget(1000), 506);
}
END_TEST

/* The caller's size rule (Triangle's triunsuitable): asked with the triangle and its area, its
 * answer makes the triangle MESH_BAD_AREA; without it the same triangle is good. */
static int too_big_right_of(void *ctx, const double *const p[3], double area) {
    double x = *(const double *)ctx;
    return area > 0.25 && p[0][0] + p[1][0] + p[2][0] > 3 * x;
}

START_TEST(test_rules_unsuitable) {
    geom_init();
    mesh_rules R;
    mesh_rules_init(&R, 20, 0, 1, 0);
    double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0.5, 0.9};
    const double *p[3] = {a, b, c};
    ck_assert_int_eq(mesh_rules_bad(&R, p, NULL, NULL), 0);
    double x = 0.1;
    R.unsuitable = too_big_right_of;
    R.unsuitable_ctx = &x;
    ck_assert_int_eq(mesh_rules_bad(&R, p, NULL, NULL), MESH_BAD_AREA); /* area 0.45 */
    x = 0.9;
    ck_assert_int_eq(mesh_rules_bad(&R, p, NULL, NULL), 0); /* centroid left of x */
}
END_TEST

/* Ghosts (GHOSTS in pbw.c): triangle x = (0, 1, 2) on rank r has a neighbour n on rank 1 across
 * 1->2 whose apex, vertex 3 at (2, 2), x's edge keeps as its ghost.  Vertex slots 0..3. */
static int32_t ghost_setup(pbw_ctx *C, int rank) {
    C->rank = rank;
    C->size = 3;
    C->gside = mesh_xcalloc((size_t)C->size, 1); /* the lower rank of each pair keeps ghosts */
    for (int r = rank + 1; r < C->size; r++)
        C->gside[r] = 1;
    const double xy[4][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 2}};
    for (int i = 0; i < 4; i++)
        pbw_vt_add(C, i, xy[i][0], xy[i][1], -1);
    int32_t x = tri(C, 0, 1, 2);
    pbw_tn_set(C, 3 * x + 1, mkref(1, 7));
    pbw_gx_set(C, 3 * (size_t)x + 1, 3);
    return x;
}

/* The cavity of p started at x, expanded on this rank (then released): its boundary and
 * pending seeds. */
static pbw_cav *ghost_cavity(pbw_ctx *C, int32_t x, double px, double py) {
    pbw_cav *c = pbw_cav_new(C);
    c->h.key = 99;
    c->h.p[0] = px;
    c->h.p[1] = py;
    int32_t hi = pbw_hold_new(C, c->h.key, 1, C->rank);
    pbw_push_seed(C, c, mkref(C->rank, x), NOREF, NOREF, -1, -1, SEED_START);
    ck_assert_int_eq(pbw_process(C, c, hi, 1), PR_DONE);
    pbw_release_local(C, hi, 0); /* the state keeps what the expansion found */
    return c;
}

START_TEST(test_ghost_conflict) {
    /* (0.2, 0.2) is in x's circumcircle, not in n's (centre (7/6, 7/6), r^2 = 50/36): the lower
     * rank reports the edge with n as its unlocked outside, no RSR needed */
    pbw_ctx *C = ctx_new(0, 0);
    int32_t x = ghost_setup(C, 0);
    pbw_cav *c = ghost_cavity(C, x, 0.2, 0.2);
    ck_assert_int_eq(c->ntodo, 0);
    ck_assert_int_eq(c->nb, 3);
    int found = 0;
    for (int32_t i = 0; i < c->nb; i++)
        if (c->b[i].out == mkref(1, 7)) {
            found++;
            ck_assert_int_eq(c->b[i].ga, 1);
            ck_assert_int_eq(c->b[i].gb, 2);
            ck_assert_int_eq(c->b[i].oapex, 3);
            ck_assert_int_eq(ref_rank(c->b[i].newref), 0); /* the new triangle stays here */
            ck_assert_int_eq(c->b[i].inref, mkref(0, x));
        } else {
            ck_assert_int_eq(c->b[i].oapex, -1);
        }
    ck_assert_int_eq(found, 1);
    pbw_cav_free(c);
    /* (0.45, 0.45) is in n's circle too: n is a member, it must be locked (a seed for rank 1) */
    c = ghost_cavity(C, x, 0.45, 0.45);
    ck_assert_int_eq(c->ntodo, 1);
    ck_assert(c->todo[0].target == mkref(1, 7) && c->todo[0].mode == SEED_NORMAL);
    ck_assert_int_eq(c->nb, 2);
    pbw_cav_free(c);
    /* across a constraint edge the lower rank reports it with no incircle test at all */
    pbw_con_set(C, 3 * (size_t)x + 1, 0, -1, 0);
    c = ghost_cavity(C, x, 0.45, 0.45);
    ck_assert_int_eq(c->ntodo, 0);
    ck_assert_int_eq(c->nb, 3);
    pbw_cav_free(c);
    pbw_ctx_free(C);
    /* the higher rank of the two, or an unknown ghost, locks as before */
    C = ctx_new(0, 0);
    x = ghost_setup(C, 2);
    c = ghost_cavity(C, x, 0.2, 0.2);
    ck_assert_int_eq(c->ntodo, 1);
    ck_assert(c->todo[0].target == mkref(1, 7));
    pbw_cav_free(c);
    pbw_ctx_free(C);
    C = ctx_new(0, 0);
    x = ghost_setup(C, 0);
    pbw_gx_set(C, 3 * (size_t)x + 1, -1);
    c = ghost_cavity(C, x, 0.2, 0.2);
    ck_assert_int_eq(c->ntodo, 1);
    pbw_cav_free(c);
    pbw_ctx_free(C);
}
END_TEST

START_TEST(test_tombstones) {
    /* x = (0, 1, 2) died by a ghost commit: it forwards across 1->2 to t1 = (1, 2, 4), which
     * died the same way and forwards to t2 = (1, 2, 5); a stale seed from the other rank's
     * member n (its edge 2->1) reaches t2 */
    pbw_ctx *C = ctx_new(0, 0);
    int32_t x = ghost_setup(C, 0);
    pbw_vt_add(C, 4, 0.2, 0.2, -1);
    pbw_vt_add(C, 5, 0.1, 0.1, -1);
    int32_t t1 = tri(C, 1, 2, 4), t2 = tri(C, 1, 2, 5);
    pbw_tn_set(C, 3 * (size_t)t1, mkref(1, 7));
    pbw_tn_set(C, 3 * (size_t)t2, mkref(1, 7));
    ck_assert_int_eq(pbw_resolve_tomb(C, x, 2, 1), -1); /* not a tombstone */
    pbw_forward_set(C, 3 * (size_t)x + 1, t1);
    pbw_role_set(C, x, ROLE_TOMB);
    pbw_forward_set(C, 3 * (size_t)t1, t2);
    pbw_role_set(C, t1, ROLE_TOMB);
    C->nlive -= 2;
    ck_assert(!alive(C, x) && !alive(C, t1) && alive(C, t2));
    ck_assert_int_eq(pbw_resolve_tomb(C, x, 2, 1), t2);
    ck_assert_int_eq(pbw_resolve_tomb(C, t1, 2, 1), t2);
    /* a tombstone is never reused */
    int32_t s = pbw_slot_alloc(C);
    ck_assert(s != x && s != t1);
    /* the expansion through the stale link visits t2 */
    pbw_cav *c = pbw_cav_new(C);
    c->h.key = 5;
    c->h.p[0] = 0.15;
    c->h.p[1] = 0.15;
    int32_t hi = pbw_hold_new(C, c->h.key, 1, 1);
    pbw_push_seed(C, c, mkref(0, x), mkref(1, 7), NOREF, 2, 1, SEED_HALO);
    ck_assert_int_eq(pbw_process(C, c, hi, 0), PR_DONE);
    ck_assert_int_eq(LK(C, t2), hi);
    ck_assert_int_eq(LK(C, x), -1);
    ck_assert_int_eq(c->nb, 1);
    ck_assert(c->b[0].out == mkref(0, t2) && c->b[0].ga == 2 && c->b[0].gb == 1);
    pbw_release_local(C, hi, 0);
    pbw_cav_free(c);
    /* ... unless t2 is the triangle n was reached from: that is the edge it came in through */
    c = pbw_cav_new(C);
    c->h.key = 6;
    hi = pbw_hold_new(C, c->h.key, 1, 1);
    pbw_push_seed(C, c, mkref(0, x), mkref(1, 7), mkref(0, t2), 2, 1, SEED_NORMAL);
    ck_assert_int_eq(pbw_process(C, c, hi, 0), PR_DONE);
    ck_assert_int_eq(c->nb, 0);
    ck_assert_int_eq(LK(C, t2), -1);
    pbw_release_local(C, hi, 0);
    pbw_cav_free(c);
    pbw_ctx_free(C);
}
END_TEST

START_TEST(test_ghost_commit) {
    /* the cavity of (0.2, 0.2) is x alone, its edge 1->2 borders ghost n on rank 1: it commits
     * here with no RSR; x becomes a tombstone forwarding to the new triangle on 1->2, which
     * links n with n's apex as its ghost; nothing is sent to rank 1 (n keeps its link to x) */
    pbw_ctx *C = ctx_new(0, 0);
    int32_t x = ghost_setup(C, 0);
    pbw_cav *c = pbw_cav_new(C);
    c->h.key = 77;
    c->h.p[0] = 0.2;
    c->h.p[1] = 0.2;
    c->h.origin = 0;
    c->it.notify = -1;
    int32_t hi = pbw_hold_new(C, c->h.key, 1, 0);
    pbw_part_add(c, 0);
    pbw_push_seed(C, c, mkref(0, x), NOREF, NOREF, -1, -1, SEED_START);
    ck_assert_int_eq(pbw_process(C, c, hi, 1), PR_DONE);
    ck_assert_int_eq(c->ntodo, 0);
    pbw_finish(C, c);
    ck_assert_int_eq(C->res.cavities_local, 1);
    ck_assert_int_eq(C->res.ghosted, 1);
    ck_assert_int_eq(C->nlive, 3);
    ck_assert(!alive(C, x) && ROLE(C, x) == ROLE_TOMB && LK(C, x) == -1);
    int32_t t = pbw_resolve_tomb(C, x, 2, 1);
    ck_assert(alive(C, t));
    int j = pbw_find_edge(C, t, 1, 2);
    ck_assert_int_ge(j, 0);
    ck_assert(TN(C, 3 * t + j) == mkref(1, 7));
    ck_assert_int_eq(GX(C, 3 * (size_t)t + (size_t)j), 3);
    ck_assert_int_eq(pbw_hold_find(C, 77), -1);
    pbw_cav_free(c);
    pbw_ctx_free(C);
}
END_TEST

/* The local fast path (pbw_local.c): an equilateral triangle T = (0, 1, 2) with an outer
 * triangle on each edge whose apex lies 3 units out (not in conflict with T's centre); the
 * outer triangles' other edges are domain boundary (constrained).  Returns T. */
static int32_t fan_setup(pbw_ctx *C, int32_t outer[3]) {
    const double h = sqrt(3.0);
    const double xy[3][2] = {{0, 0}, {2, 0}, {1, h}};
    for (int i = 0; i < 3; i++)
        pbw_vt_add(C, i, xy[i][0], xy[i][1], -1);
    int32_t t = tri(C, 0, 1, 2);
    for (int j = 0; j < 3; j++) {
        int a = j, b = (j + 1) % 3;
        double mx = (xy[a][0] + xy[b][0]) / 2, my = (xy[a][1] + xy[b][1]) / 2;
        double nx = xy[b][1] - xy[a][1], ny = -(xy[b][0] - xy[a][0]); /* outward, length 2 */
        pbw_vt_add(C, 3 + j, mx + 1.5 * nx, my + 1.5 * ny, -1);
        int32_t o = tri(C, b, a, 3 + j);
        outer[j] = o;
        pbw_tn_set(C, 3 * t + j, mkref(0, o));
        pbw_tn_set(C, 3 * o, mkref(0, t));
        pbw_con_set(C, 3 * (size_t)o + 1, 10 + 2 * j, -1, 0);
        pbw_con_set(C, 3 * (size_t)o + 2, 11 + 2 * j, -1, 0);
    }
    return t;
}

/* Every live triangle is counter-clockwise and each local link is mutual, across the same
 * edge reversed. */
static void check_links(pbw_ctx *C) {
    for (int32_t s = 0; s < C->M.nt; s++) {
        if (!alive(C, s)) continue;
        const int32_t *v = C->M.tv + 3 * s;
        ck_assert(geom_orient2d(VX(C, v[0]), VX(C, v[1]), VX(C, v[2])) > 0);
        for (int j = 0; j < 3; j++) {
            int64_t n = TN(C, 3 * s + j);
            if (n == NOREF) continue;
            int32_t y = ref_idx(n);
            ck_assert(alive(C, y));
            int jy = pbw_find_edge(C, y, TG(C, s, (j + 1) % 3), TG(C, s, j));
            ck_assert_int_ge(jy, 0);
            ck_assert(TN(C, 3 * y + jy) == mkref(0, s));
        }
    }
}

START_TEST(test_local_fast_path) {
    pbw_ctx *C = ctx_new(0, 0);
    int32_t outer[3];
    int32_t t = fan_setup(C, outer);
    const double p[2] = {1.0, 0.55};
    ck_assert_int_eq(C->nlive, 4);
    ck_assert_int_eq(pbw_local_insert(C, p, t), 1);
    ck_assert_int_eq(C->nlive, 6);
    ck_assert_int_eq(C->res.inserted, 1);
    ck_assert_int_eq(C->res.cavities_local, 1);
    check_links(C);
    /* the fan: three triangles on the new vertex, one on each old edge of T */
    int32_t pv = pbw_vt_find(C, ((int64_t)1 << 32) | 0);
    ck_assert_int_ge(pv, 0);
    int on_p = 0, cons = 0;
    for (int32_t s = 0; s < C->M.nt; s++) {
        if (!alive(C, s)) continue;
        for (int j = 0; j < 3; j++) {
            on_p += C->M.tv[3 * s + j] == pv;
            cons += SSEG(C, 3 * (size_t)s + (size_t)j) != NULL;
        }
    }
    ck_assert_int_eq(on_p, 3);
    ck_assert_int_eq(cons, 6); /* the outer triangles' boundary edges, untouched */
    for (int j = 0; j < 3; j++)
        ck_assert(ROLE(C, outer[j]) == ROLE_NONE && LK(C, outer[j]) == -1);
    pbw_ctx_free(C);

    /* what the general path must decide: nothing is written, no mark is left */
    for (int k = 0; k < 4; k++) {
        C = ctx_new(0, 0);
        t = fan_setup(C, outer);
        double q[2] = {1.0, 0.55};
        if (k == 0) { /* a locked member */
            pbw_lk_set(C, t, 0);
            pbw_role_set(C, t, ROLE_MEMBER);
        }
        if (k == 1) { /* a locked halo */
            pbw_lk_set(C, outer[1], 0);
            pbw_role_set(C, outer[1], ROLE_HALO);
        }
        if (k == 2) pbw_tn_set(C, 3 * t + 2, mkref(1, 9)); /* a remote neighbour */
        if (k == 3) { /* p encroaches a constrained edge of T (both sides) */
            pbw_con_set(C, 3 * (size_t)t, 0, -1, 0);
            pbw_con_set(C, 3 * (size_t)outer[0], 0, -1, 0);
            q[1] = 0.3;
        }
        int32_t nv = C->M.nv, nt = C->M.nt;
        ck_assert_int_eq(pbw_local_insert(C, q, t), 0);
        ck_assert_int_eq(C->M.nv, nv);
        ck_assert_int_eq(C->M.nt, nt);
        ck_assert_int_eq(C->nlive, 4);
        for (int32_t s = 0; s < C->M.nt; s++)
            ck_assert(ROLE(C, s) == (s == t && k == 0          ? ROLE_MEMBER
                                     : s == outer[1] && k == 1 ? ROLE_HALO
                                                               : ROLE_NONE));
        ck_assert_int_eq(C->res.inserted, 0);
        pbw_ctx_free(C);
    }
}
END_TEST

/* The lock table (slot -> hold, open addressing with backward-shift deletion) agrees with a
 * plain array through growth and interleaved deletions. */
START_TEST(test_lock_table) {
    pbw_ctx *C = ctx_new(0, 0);
    enum { N = 5000 };
    int32_t *ref = mesh_xcalloc(N, sizeof(int32_t));
    for (int i = 0; i < N; i++)
        ref[i] = -1;
    uint64_t x = 12345;
    for (int step = 0; step < 40000; step++) {
        x = x * 6364136223846793005ULL + 1442695040888963407ULL;
        int32_t s = (int32_t)((x >> 33) % N);
        int32_t hi = (x >> 20) % 3 == 0 ? -1 : (int32_t)((x >> 40) % 97);
        pbw_lk_set(C, s, hi);
        ref[s] = hi;
        if (step % 1000 == 0)
            for (int k = 0; k < N; k++)
                ck_assert_int_eq(pbw_lk_find(C, k), ref[k]);
    }
    uint32_t n = 0;
    for (int k = 0; k < N; k++) {
        ck_assert_int_eq(pbw_lk_find(C, k), ref[k]);
        n += ref[k] >= 0;
    }
    ck_assert_uint_eq(C->lkn, n);
    free(ref);
    pbw_ctx_free(C);
}
END_TEST

/* The ghost side of each pair of ranks (pbw_ghosts.c): three ranks around a point, each pair
 * sharing one edge.  The lower rank of each pair would make rank 0 the ghost side towards both
 * others and rank 2 towards none; the orientation gives each rank one pair of each kind, and
 * the two sides of every pair agree. */
START_TEST(test_ghost_sides) {
    mesh m0;
    mesh_init(&m0);
    /* c = 0, outer a, b, d = 1, 2, 3: t0 = (c, a, b), t1 = (c, b, d), t2 = (c, d, a) */
    const int32_t tv[9] = {0, 1, 2, 0, 2, 3, 0, 3, 1};
    const int32_t tn[9] = {8, -1, 3, 2, -1, 6, 5, -1, 0};
    m0.nt = 3;
    m0.tv = mesh_xmalloc(9, sizeof(int32_t));
    m0.tn = mesh_xmalloc(9, sizeof(int32_t));
    memcpy(m0.tv, tv, sizeof tv);
    memcpy(m0.tn, tn, sizeof tn);
    const int32_t own[3] = {0, 1, 2};
    uint8_t side[3][3];
    for (int r = 0; r < 3; r++) {
        pbw_ctx *C = ctx_new(0, 0);
        C->rank = r;
        C->size = 3;
        pbw_ghost_sides(C, &m0, own);
        memcpy(side[r], C->gside, 3);
        pbw_ctx_free(C);
    }
    for (int r = 0; r < 3; r++) {
        ck_assert_int_eq(side[r][r], 0);
        ck_assert_int_eq(side[r][(r + 1) % 3] + side[r][(r + 2) % 3], 1);
        for (int q = 0; q < 3; q++)
            if (q != r) ck_assert_int_eq(side[r][q] + side[q][r], 1);
    }
    /* two ranks: the lower one, as before */
    const int32_t own2[3] = {0, 1, 1};
    for (int r = 0; r < 2; r++) {
        pbw_ctx *C = ctx_new(0, 0);
        C->rank = r;
        C->size = 2;
        pbw_ghost_sides(C, &m0, own2);
        ck_assert_int_eq(C->gside[1 - r], r == 0);
        pbw_ctx_free(C);
    }
    free(m0.tv), free(m0.tn);
}
END_TEST

/* The end game's shuffle of the slot queue: the waiting items (not the ones already taken) in
 * another order, each exactly once, the same order for the same seed. */
START_TEST(test_queue_shuffle) {
    ivec q, r;
    memset(&q, 0, sizeof q);
    memset(&r, 0, sizeof r);
    pbw_item it, got;
    memset(&it, 0, sizeof it);
    for (int32_t i = 0; i < 100; i++) {
        it.t = i;
        pbw_iv_push(&q, &it);
        pbw_iv_push(&r, &it);
    }
    for (int i = 0; i < 10; i++) { /* taken already: stay taken */
        ck_assert(pbw_iv_pop(&q, &got));
        ck_assert(pbw_iv_pop(&r, &got));
    }
    pbw_iv_shuffle(&q, 3);
    pbw_iv_shuffle(&r, 3);
    int seen[100] = {0}, moved = 0;
    for (int32_t i = 10; i < 100; i++) {
        ck_assert(pbw_iv_pop(&q, &got));
        ck_assert_int_ge(got.t, 10);
        ck_assert_int_eq(seen[got.t]++, 0);
        moved += got.t != i;
        pbw_item g2;
        ck_assert(pbw_iv_pop(&r, &g2));
        ck_assert_int_eq(g2.t, got.t);
    }
    ck_assert(pbw_iv_empty(&q));
    ck_assert_int_gt(moved, 45); /* not the identity, nor close to it */
    pbw_iv_free(&q);
    pbw_iv_free(&r);
}
END_TEST

int main(void) {
    return ck_run(ck_suite("pbw", 0,
                           CK_TESTS(test_vertex_table, test_slots_reuse, test_bad_queue_order,
                                    test_deferred_wakes, test_split_ticket, test_holds,
                                    test_cavity_wire_format, test_ghost_conflict, test_tombstones,
                                    test_ghost_commit, test_local_fast_path, test_lock_table,
                                    test_rules_edge_forced, test_rules_priority_floor,
                                    test_rules_unsuitable, test_ghost_sides, test_queue_shuffle)));
}
