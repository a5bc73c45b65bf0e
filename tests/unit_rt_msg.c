/* unit_rt_msg.c - wire format and aggregation (rt_msg.c): several RSRs packed into one
 * buffer and unpacked again, alignment, the full-buffer case, malformed buffers; the
 * termination decision rule (rt_term.c) and the perturbation pool (rt_perturb.c). */
#include "check_run.h"
#include "rt_internal.h"

#include <stdlib.h>
#include <string.h>

START_TEST(test_pack_unpack_many) {
    unsigned char buf[4096];
    size_t used = 0;
    int n = 0;
    for (uint32_t len = 0; len < 40; len++) {
        unsigned char pay[64];
        for (uint32_t i = 0; i < len; i++)
            pay[i] = (unsigned char)(len * 13 + i);
        rt_hdr h = {.handler = (uint16_t)(len % 7),
                    .flags = (uint16_t)(len % 3),
                    .src = (int32_t)len,
                    .len = len,
                    .tok_rank = -1,
                    .tok_slot = len * 2,
                    .tok_gen = len * 3};
        if (rt_pack(buf, sizeof buf, &used, &h, pay) != RT_OK) break;
        n++;
        ck_assert_uint_eq(used % 8, 0);
    }
    ck_assert_int_eq(n, 40);
    size_t off = 0;
    rt_hdr h;
    const unsigned char *p;
    int k = 0, rc;
    while ((rc = rt_unpack(buf, used, &off, &h, &p)) == 1) {
        ck_assert_uint_eq(h.len, (uint32_t)k);
        ck_assert_int_eq(h.src, k);
        ck_assert_uint_eq(h.handler, (unsigned)(k % 7));
        ck_assert_uint_eq(h.flags, (unsigned)(k % 3));
        ck_assert_uint_eq(h.tok_slot, (uint32_t)k * 2);
        ck_assert_uint_eq(h.tok_gen, (uint32_t)k * 3);
        ck_assert_uint_eq((uintptr_t)p % 8, 0);
        for (int i = 0; i < k; i++)
            ck_assert_uint_eq(p[i], (unsigned char)(k * 13 + i));
        k++;
    }
    ck_assert_int_eq(rc, 0);
    ck_assert_int_eq(k, 40);
    ck_assert_uint_eq(off, used);
}
END_TEST

START_TEST(test_wire_size_and_full) {
    ck_assert_uint_eq(rt_wire_size(0), 24);
    ck_assert_uint_eq(rt_wire_size(1), 32);
    ck_assert_uint_eq(rt_wire_size(8), 32);
    ck_assert_uint_eq(rt_wire_size(9), 40);
    unsigned char buf[64];
    size_t used = 0;
    unsigned char pay[48] = {0};
    rt_hdr h = {.len = 8};
    ck_assert_int_eq(rt_pack(buf, sizeof buf, &used, &h, pay), RT_OK); /* 32 */
    ck_assert_int_eq(rt_pack(buf, sizeof buf, &used, &h, pay), RT_OK); /* 64 */
    ck_assert_uint_eq(used, 64);
    h.len = 0;
    ck_assert_int_eq(rt_pack(buf, sizeof buf, &used, &h, pay), RT_ENOSPC);
    ck_assert_uint_eq(used, 64);
    used = 0;
    h.len = 41; /* 24 + 48 > 64 */
    ck_assert_int_eq(rt_pack(buf, sizeof buf, &used, &h, pay), RT_ENOSPC);
    ck_assert_uint_eq(used, 0);
    h.len = 40; /* 24 + 40 == 64 fits exactly */
    ck_assert_int_eq(rt_pack(buf, sizeof buf, &used, &h, pay), RT_OK);
    ck_assert_uint_eq(used, 64);
}
END_TEST

START_TEST(test_malformed) {
    unsigned char buf[128];
    size_t used = 0;
    unsigned char pay[16] = {1, 2, 3};
    rt_hdr h = {.handler = 1, .len = 16};
    rt_pack(buf, sizeof buf, &used, &h, pay);
    rt_hdr out;
    const unsigned char *p;
    size_t off = 0;
    ck_assert_int_eq(rt_unpack(buf, used - 8, &off, &out, &p), RT_EPROTO); /* cut payload */
    off = 0;
    ck_assert_int_eq(rt_unpack(buf, 10, &off, &out, &p), RT_EPROTO); /* cut header */
    h.len = 1000;                                                    /* lying length */
    memcpy(buf, &h, sizeof h);
    off = 0;
    ck_assert_int_eq(rt_unpack(buf, used, &off, &out, &p), RT_EPROTO);
    off = 0;
    ck_assert_int_eq(rt_unpack(buf, 0, &off, &out, &p), 0);
}
END_TEST

START_TEST(test_item_copy) {
    char pay[5] = "abcd";
    rt_hdr h = {.handler = 3, .len = 5};
    rt_item *it = rt_item_new(&h, pay);
    pay[0] = 'z';
    ck_assert_str_eq((char *)it->data, "abcd");
    ck_assert_uint_eq((uintptr_t)it->data % 8, 0);
    ck_assert_uint_eq(it->h.handler, 3);
    rt_xfree(it);
}
END_TEST

START_TEST(test_term_decide) {
    int64_t quiet[3] = {100, 100, 0}, active[3] = {100, 100, 1}, inflight[3] = {101, 100, 0};
    ck_assert(rt_term_decide(quiet));
    ck_assert(!rt_term_decide(active));
    ck_assert(!rt_term_decide(inflight));
}
END_TEST

/* One rank: the token is back at once, so a round opened while passive is decided at the
 * next passive step; activity or an unprocessed RSR in between makes it fail. */
START_TEST(test_term_ring_one_rank) {
    rt_term t;
    rt_term_init(&t, 0);
    ck_assert(t.have_token);
    ck_assert(rt_term_pass(&t, 0, 1, 5, 5, 0, false) ==
              RT_TERM_GOING); /* no round before the quiet delay */
    ck_assert(rt_term_pass(&t, 0, 1, 5, 5, 0, true) ==
              RT_TERM_GOING); /* opens a round, rank turns white */
    ck_assert(t.round_open && !t.active);
    t.active = true; /* activity during the round */
    ck_assert(rt_term_pass(&t, 0, 1, 6, 6, 0, true) == RT_TERM_GOING); /* fails, opens another */
    ck_assert(rt_term_pass(&t, 0, 1, 7, 6, 0, true) ==
              RT_TERM_GOING); /* an RSR not yet processed */
    ck_assert(rt_term_pass(&t, 0, 1, 7, 7, 0, false) ==
              RT_TERM_DONE); /* quiet and balanced: declared */
    ck_assert(t.active && !t.round_open && t.have_token);
}
END_TEST

static int released[64], nrel;

static void collect(rt_item *it) {
    released[nrel++] = (int)it->h.src * 100 + (int)it->h.tok_slot;
    rt_xfree(it);
}

START_TEST(test_perturb_keeps_source_order) {
    rt_perturb p;
    rt_perturb_init(&p, 42, 3);
    nrel = 0;
    for (int k = 0; k < 10; k++)
        for (int src = 0; src < 3; src++) {
            rt_hdr h = {.src = src, .tok_slot = (uint32_t)k};
            rt_perturb_hold(&p, rt_item_new(&h, NULL), src);
        }
    ck_assert_uint_eq(p.nheld, 30);
    for (int i = 0; i < 1000 && p.nheld; i++)
        rt_perturb_release(&p, collect);
    ck_assert_uint_eq(p.nheld, 0);
    ck_assert_int_eq(nrel, 30);
    int last[3] = {-1, -1, -1}, interleaved = 0;
    for (int i = 0; i < nrel; i++) {
        int src = released[i] / 100, k = released[i] % 100;
        ck_assert_int_gt(k, last[src]); /* FIFO per source */
        last[src] = k;
        if (i > 0 && released[i - 1] / 100 != src) interleaved++;
    }
    ck_assert_int_gt(interleaved, 0);
    rt_perturb_destroy(&p);
}
END_TEST

/* The single-node point-to-point choice: only when every rank is local (or a singleton), never
 * over the user's own choice. */
START_TEST(test_prefer_local_pml) {
    unsetenv("OMPI_MCA_pml");
    setenv("OMPI_COMM_WORLD_SIZE", "8", 1);
    setenv("OMPI_COMM_WORLD_LOCAL_SIZE", "4", 1); /* two nodes */
    ck_assert_int_eq(rt_prefer_local_pml(), 0);
    ck_assert_ptr_null(getenv("OMPI_MCA_pml"));
    setenv("OMPI_COMM_WORLD_LOCAL_SIZE", "8", 1); /* one node */
    ck_assert_int_eq(rt_prefer_local_pml(), 1);
    ck_assert_str_eq(getenv("OMPI_MCA_pml"), "ob1");
    setenv("OMPI_MCA_pml", "cm", 1); /* the user's choice stands */
    ck_assert_int_eq(rt_prefer_local_pml(), 0);
    ck_assert_str_eq(getenv("OMPI_MCA_pml"), "cm");
    unsetenv("OMPI_MCA_pml");
    unsetenv("OMPI_COMM_WORLD_SIZE");
    unsetenv("OMPI_COMM_WORLD_LOCAL_SIZE"); /* a singleton */
    ck_assert_int_eq(rt_prefer_local_pml(), 1);
    unsetenv("OMPI_MCA_pml");
}
END_TEST

/* The topology without I/O devices: only when every rank is local (or a singleton), never over
 * the user's own choice. */
START_TEST(test_prefer_cpu_topology) {
    unsetenv("HWLOC_COMPONENTS");
    setenv("OMPI_COMM_WORLD_SIZE", "8", 1);
    setenv("OMPI_COMM_WORLD_LOCAL_SIZE", "4", 1); /* two nodes */
    ck_assert_int_eq(rt_prefer_cpu_topology(), 0);
    ck_assert_ptr_null(getenv("HWLOC_COMPONENTS"));
    setenv("OMPI_COMM_WORLD_LOCAL_SIZE", "8", 1); /* one node */
    ck_assert_int_eq(rt_prefer_cpu_topology(), 1);
    ck_assert_str_eq(getenv("HWLOC_COMPONENTS"), "-linuxio,-pci");
    setenv("HWLOC_COMPONENTS", "x86", 1); /* the user's choice stands */
    ck_assert_int_eq(rt_prefer_cpu_topology(), 0);
    ck_assert_str_eq(getenv("HWLOC_COMPONENTS"), "x86");
    unsetenv("HWLOC_COMPONENTS");
    unsetenv("OMPI_COMM_WORLD_SIZE");
    unsetenv("OMPI_COMM_WORLD_LOCAL_SIZE"); /* a singleton */
    ck_assert_int_eq(rt_prefer_cpu_topology(), 1);
    unsetenv("HWLOC_COMPONENTS");
}
END_TEST

/* A singleton runs without Open MPI's daemon; under a launcher, or by the user's choice, the
 * setting is left alone. */
START_TEST(test_prefer_isolated_singleton) {
    unsetenv("OMPI_MCA_ess_singleton_isolated");
    unsetenv("PMIX_RANK");
    unsetenv("PMI_RANK");
    setenv("OMPI_COMM_WORLD_SIZE", "2", 1); /* mpirun */
    ck_assert_int_eq(rt_prefer_isolated_singleton(), 0);
    ck_assert_ptr_null(getenv("OMPI_MCA_ess_singleton_isolated"));
    unsetenv("OMPI_COMM_WORLD_SIZE");
    setenv("PMIX_RANK", "0", 1); /* another launcher */
    ck_assert_int_eq(rt_prefer_isolated_singleton(), 0);
    ck_assert_ptr_null(getenv("OMPI_MCA_ess_singleton_isolated"));
    unsetenv("PMIX_RANK");
    setenv("OMPI_MCA_ess_singleton_isolated", "0", 1); /* the user's choice stands */
    ck_assert_int_eq(rt_prefer_isolated_singleton(), 0);
    ck_assert_str_eq(getenv("OMPI_MCA_ess_singleton_isolated"), "0");
    unsetenv("OMPI_MCA_ess_singleton_isolated"); /* a singleton */
    ck_assert_int_eq(rt_prefer_isolated_singleton(), 1);
    ck_assert_str_eq(getenv("OMPI_MCA_ess_singleton_isolated"), "1");
    unsetenv("OMPI_MCA_ess_singleton_isolated");
}
END_TEST

int main(void) {
    return ck_run(
        ck_suite("rt_msg", 0,
                 CK_TESTS(test_pack_unpack_many, test_prefer_local_pml, test_prefer_cpu_topology,
                          test_prefer_isolated_singleton, test_wire_size_and_full, test_malformed,
                          test_item_copy, test_term_decide, test_term_ring_one_rank,
                          test_perturb_keeps_source_order)));
}
