/* check_run.h: how every test program builds and runs its Check suite, written once.
 *
 * A unit test's main is a line or a few:
 *
 *     int main(void) {
 *         geom_init();
 *         return ck_run(ck_suite("hull", 0, CK_TESTS(test_grid_hull, test_enclose)));
 *     }
 *
 * ck_suite makes a suite of one test case (both named after the module); ck_case adds another
 * case to a suite, and returns it for Check's loop and signal tests (tcase_add_loop_test,
 * tcase_add_test_raise_signal).  ck_run forks every test (Check's default, so a crash fails that
 * test alone); ck_run_nofork runs them in the process (tests that share state).
 *
 * An MPI test program owns MPI (MPI_Init or rt_init in main, MPI_Finalize or rt_finalize after)
 * and runs its suite with ck_run_mpi in between: without fork (MPI does not survive one; the
 * outer `timeout` of tests/run.sh stands in for Check's timeouts), the report printed by rank
 * 0 and the failures of any other rank by that rank, and the failure count reduced over the
 * communicator, so every rank returns the same exit status.
 *
 * Each runner returns the process's exit status: EXIT_SUCCESS iff every test passed. */
#ifndef CHECK_RUN_H
#define CHECK_RUN_H

#include <check.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

/* A NULL-terminated list of tests (START_TEST names) for ck_suite and ck_case. */
#define CK_TESTS(...) ((const TTest *const[]){__VA_ARGS__, NULL})

/* Adds to s a test case called name holding tests (CK_TESTS), with Check's per-test timeout
 * set to timeout_s seconds when it is positive (else Check's default); returns the case. */
static inline TCase *ck_case(Suite *s, const char *name, double timeout_s,
                             const TTest *const *tests) {
    TCase *tc = tcase_create(name);
    if (timeout_s > 0) tcase_set_timeout(tc, timeout_s);
    for (; *tests; tests++)
        tcase_add_test(tc, *tests);
    suite_add_tcase(s, tc);
    return tc;
}

/* A suite called name of one test case of the same name (see ck_case). */
static inline Suite *ck_suite(const char *name, double timeout_s, const TTest *const *tests) {
    Suite *s = suite_create(name);
    ck_case(s, name, timeout_s, tests);
    return s;
}

/* Runs s with fork status fork (CK_FORK_GETENV: Check's default, CK_FORK=no turns it off),
 * printing as print; returns the number of failed tests. */
static inline int ck_run_count(Suite *s, enum fork_status fork, enum print_output print) {
    SRunner *sr = srunner_create(s);
    if (fork != CK_FORK_GETENV) srunner_set_fork_status(sr, fork);
    srunner_run_all(sr, print);
    int nf = srunner_ntests_failed(sr);
    if (nf && print == CK_SILENT) srunner_print(sr, CK_NORMAL);
    srunner_free(sr);
    return nf;
}

/* Runs s, each test in a child process; the exit status. */
static inline int ck_run(Suite *s) {
    return ck_run_count(s, CK_FORK_GETENV, CK_NORMAL) ? EXIT_FAILURE : EXIT_SUCCESS;
}

/* Runs s in this process, test after test; the exit status. */
static inline int ck_run_nofork(Suite *s) {
    return ck_run_count(s, CK_NOFORK, CK_NORMAL) ? EXIT_FAILURE : EXIT_SUCCESS;
}

/* Collective over comm: runs s on every rank without fork; rank 0 prints the report, another
 * rank only its failures (under a line naming it); the exit status, the same on every rank:
 * EXIT_SUCCESS iff no test failed on any rank. */
static inline int ck_run_mpi(Suite *s, MPI_Comm comm) {
    int rank = 0, nf, any = 0;
    MPI_Comm_rank(comm, &rank);
    if (rank != 0) fflush(stdout);
    nf = ck_run_count(s, CK_NOFORK, rank == 0 ? CK_NORMAL : CK_SILENT);
    if (nf && rank != 0) printf("(the failures above are rank %d's)\n", rank);
    MPI_Allreduce(&nf, &any, 1, MPI_INT, MPI_MAX, comm);
    return any ? EXIT_FAILURE : EXIT_SUCCESS;
}

#endif
