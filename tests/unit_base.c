/* unit_base: Check suite for mesher/base's bug report (base.h).  Without an environment (the
 * sequential library: no MPI) a bug is reported on rank "-" and the process aborts; with one (the
 * parallel layers install MPI's, base_mpi.c) the report names the rank the environment gives and
 * the environment's stop ends every rank with exit code 70.  Each case runs the bug in a child
 * process and reads its stderr and exit status.  The radix sort (mesh_sort_u64) is held to
 * qsort's order. */
#include "base/base.h"
#include "check_run.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static int fake_rank(void) {
    return 3;
}

static void fake_stop(int code) {
    fflush(stderr);
    _exit(code + 1); /* 71: tells the stop apart from a plain exit */
}

static const mesh_bug_env fake = {fake_rank, fake_stop};

/* Runs MESH_BUG in a child with env e (NULL: none); its stderr into buf, its wait status. */
static int bug_in_child(const mesh_bug_env *e, char *buf, size_t n) {
    int fd[2];
    ck_assert_int_eq(pipe(fd), 0);
    pid_t pid = fork();
    ck_assert_int_ge(pid, 0);
    if (pid == 0) {
        dup2(fd[1], 2);
        close(fd[0]);
        signal(SIGABRT, SIG_DFL);
        mesh_bug_set_env(e);
        MESH_BUG("broken invariant %d", 42);
    }
    close(fd[1]);
    size_t got = 0;
    ssize_t r;
    while (got + 1 < n && (r = read(fd[0], buf + got, n - 1 - got)) > 0)
        got += (size_t)r;
    buf[got] = '\0';
    close(fd[0]);
    int st = 0;
    waitpid(pid, &st, 0);
    return st;
}

START_TEST(test_bug_without_env) {
    char buf[512];
    int st = bug_in_child(NULL, buf, sizeof buf);
    ck_assert_msg(strstr(buf, "pcdm: bug on rank - (") && strstr(buf, "broken invariant 42"),
                  "stderr: %s", buf);
    ck_assert_msg(WIFSIGNALED(st) && WTERMSIG(st) == SIGABRT, "status %d", st);
}
END_TEST

START_TEST(test_bug_with_env) {
    char buf[512];
    int st = bug_in_child(&fake, buf, sizeof buf);
    ck_assert_msg(strstr(buf, "pcdm: bug on rank 3 (") && strstr(buf, "unit_base.c:"), "stderr: %s",
                  buf);
    ck_assert_msg(WIFEXITED(st) && WEXITSTATUS(st) == 71, "status %d", st);
}
END_TEST

static int cmp_u64(const void *a, const void *b) {
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* mesh_sort_u64 against qsort: short arrays (insertion sort), long ones (radix passes) whose
 * keys share some digits (passes skipped) or differ in every digit, repeats included. */
START_TEST(test_sort_u64) {
    size_t sizes[] = {0, 1, 2, 255, 256, 1000, 100003};
    uint64_t masks[] = {~0ULL, 0xffff0000ffffULL, 0xff00000000000000ULL, 7};
    uint64_t x = 88172645463325252ULL;
    for (size_t si = 0; si < sizeof sizes / sizeof *sizes; si++)
        for (size_t mi = 0; mi < sizeof masks / sizeof *masks; mi++) {
            size_t n = sizes[si];
            uint64_t *a = malloc((n + 1) * sizeof *a), *b = malloc((n + 1) * sizeof *b);
            for (size_t i = 0; i < n; i++) {
                x ^= x << 13, x ^= x >> 7, x ^= x << 17; /* xorshift64 */
                a[i] = b[i] = x & masks[mi];
            }
            mesh_sort_u64(a, n);
            qsort(b, n, sizeof *b, cmp_u64);
            ck_assert_msg(n == 0 || memcmp(a, b, n * sizeof *a) == 0,
                          "mesh_sort_u64: %zu keys under mask %llx not sorted as qsort sorts them",
                          n, (unsigned long long)masks[mi]);
            free(a);
            free(b);
        }
}
END_TEST

int main(void) {
    return ck_run(
        ck_suite("base", 0, CK_TESTS(test_bug_without_env, test_bug_with_env, test_sort_u64)));
}
