/* unit_rt_handler.c - the handler table (rt_handler.c): deterministic ids in registration
 * order, validation at registration, the fatal stub in unregistered slots, payload length
 * checks, and the table comparison rt_start uses to name the first mismatching handler. */
#include "check_run.h"
#include "rt_internal.h"

#include <signal.h>
#include <string.h>

static void h_a(const rt_msg *m, void *arg) {
    (void)m;
    (void)arg;
}

static void h_b(const rt_msg *m, void *arg) {
    (void)m;
    (void)arg;
}

START_TEST(test_ids_in_order) {
    rt_htable t;
    rt_htable_init(&t);
    ck_assert_int_eq(rt_htable_add(&t, "split_edge", h_a, NULL, RT_NONTHREADED, 16), 0);
    ck_assert_int_eq(rt_htable_add(&t, "expand", h_b, &t, RT_THREADED, 8), 1);
    ck_assert_int_eq(rt_htable_add(&t, "var", h_a, NULL, RT_VARSIZE, 100), 2);
    ck_assert_int_eq(t.n, 3);
    ck_assert_str_eq(t.e[1].name, "expand");
    ck_assert_ptr_eq(t.e[1].arg, &t);
    ck_assert_uint_eq(t.e[1].flags, RT_THREADED);
    t.frozen = true;
    ck_assert_int_eq(rt_htable_add(&t, "late", h_a, NULL, 0, 0), RT_ESTATE);
}
END_TEST

START_TEST(test_registration_validation) {
    rt_htable t;
    rt_htable_init(&t);
    ck_assert_int_eq(rt_htable_add(&t, NULL, h_a, NULL, 0, 0), RT_EINVAL);
    ck_assert_int_eq(rt_htable_add(&t, "", h_a, NULL, 0, 0), RT_EINVAL);
    ck_assert_int_eq(rt_htable_add(&t, "x", NULL, NULL, 0, 0), RT_EINVAL);
    ck_assert_int_eq(rt_htable_add(&t, "x", h_a, NULL, 0x80, 0), RT_EINVAL);
    char longname[RT_NAME_MAX + 1];
    memset(longname, 'a', RT_NAME_MAX);
    longname[RT_NAME_MAX] = 0;
    ck_assert_int_eq(rt_htable_add(&t, longname, h_a, NULL, 0, 0), RT_EINVAL);
    longname[RT_NAME_MAX - 1] = 0;
    ck_assert_int_eq(rt_htable_add(&t, longname, h_a, NULL, 0, 0), 0);
    for (int i = 1; i < RT_MAX_HANDLERS; i++)
        ck_assert_int_eq(rt_htable_add(&t, "h", h_a, NULL, 0, 0), i);
    ck_assert_int_eq(rt_htable_add(&t, "h", h_a, NULL, 0, 0), RT_ENOSPC);
}
END_TEST

START_TEST(test_payload_checks) {
    rt_htable t;
    rt_htable_init(&t);
    rt_htable_add(&t, "fixed", h_a, NULL, RT_NONTHREADED, 16);
    rt_htable_add(&t, "var", h_a, NULL, RT_VARSIZE | RT_THREADED, 100);
    rt_htable_add(&t, "null", h_a, NULL, RT_NONTHREADED, 0);
    ck_assert_int_eq(rt_htable_check(&t, 0, 16), RT_OK);
    ck_assert_int_eq(rt_htable_check(&t, 0, 15), RT_ELEN);
    ck_assert_int_eq(rt_htable_check(&t, 0, 17), RT_ELEN);
    ck_assert_int_eq(rt_htable_check(&t, 1, 0), RT_OK);
    ck_assert_int_eq(rt_htable_check(&t, 1, 100), RT_OK);
    ck_assert_int_eq(rt_htable_check(&t, 1, 101), RT_ELEN);
    ck_assert_int_eq(rt_htable_check(&t, 2, 0), RT_OK);
    ck_assert_int_eq(rt_htable_check(&t, 2, 1), RT_ELEN);
    ck_assert_int_eq(rt_htable_check(&t, 3, 0), RT_EHANDLER); /* unregistered slot */
    ck_assert_int_eq(rt_htable_check(&t, RT_MAX_HANDLERS, 0), RT_EHANDLER);
    ck_assert_int_eq(rt_htable_check(&t, 65535, 0), RT_EHANDLER);
}
END_TEST

START_TEST(test_unregistered_stub_aborts) {
    rt_htable t;
    rt_htable_init(&t);
    rt_htable_add(&t, "only", h_a, NULL, 0, 0);
    ck_assert_ptr_eq(t.e[5].fn, rt_handler_unregistered);
    rt_msg m = {.src = 3, .handler = 5};
    t.e[5].fn(&m, t.e[5].arg); /* aborts: SIGABRT */
}
END_TEST

START_TEST(test_compare_tables) {
    rt_htable a, b;
    rt_htable_init(&a);
    rt_htable_init(&b);
    const char *names[] = {"split_edge", "expand", "reply"};
    for (int i = 0; i < 3; i++) {
        rt_htable_add(&a, names[i], h_a, NULL, 0, 8);
        rt_htable_add(&b, names[i], h_b, NULL, 0, 8); /* functions may differ, names not */
    }
    rt_hsig sa[RT_MAX_HANDLERS], sb[RT_MAX_HANDLERS];
    rt_htable_sig(&a, sa);
    rt_htable_sig(&b, sb);
    ck_assert_int_eq(rt_hsig_compare(sa, sb), -1);

    rt_htable_init(&b); /* same names, other order */
    rt_htable_add(&b, "split_edge", h_a, NULL, 0, 8);
    rt_htable_add(&b, "reply", h_a, NULL, 0, 8);
    rt_htable_add(&b, "expand", h_a, NULL, 0, 8);
    rt_htable_sig(&b, sb);
    ck_assert_int_eq(rt_hsig_compare(sa, sb), 1);
    ck_assert_str_eq(sb[1].name, "reply");

    rt_htable_init(&b); /* one handler fewer */
    rt_htable_add(&b, "split_edge", h_a, NULL, 0, 8);
    rt_htable_add(&b, "expand", h_a, NULL, 0, 8);
    rt_htable_sig(&b, sb);
    ck_assert_int_eq(rt_hsig_compare(sa, sb), 2);

    rt_htable_init(&b); /* same names, different size / flags */
    rt_htable_add(&b, "split_edge", h_a, NULL, 0, 8);
    rt_htable_add(&b, "expand", h_a, NULL, 0, 12);
    rt_htable_sig(&b, sb);
    ck_assert_int_eq(rt_hsig_compare(sa, sb), 1);
    rt_htable_init(&b);
    rt_htable_add(&b, "split_edge", h_a, NULL, RT_THREADED, 8);
    rt_htable_sig(&b, sb);
    ck_assert_int_eq(rt_hsig_compare(sa, sb), 0);
}
END_TEST

int main(void) {
    Suite *s = suite_create("rt_handler");
    TCase *tc = ck_case(s, "rt_handler", 0,
                        CK_TESTS(test_ids_in_order, test_registration_validation,
                                 test_payload_checks, test_compare_tables));
    tcase_add_test_raise_signal(tc, test_unregistered_stub_aborts, SIGABRT);
    return ck_run(s);
}
