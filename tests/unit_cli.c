/* unit_cli: Check suite for the front end's parser (apps/cli.c), without MPI.
 *
 * Every program's defaults as the tables state them; the accepted spellings (-q30, -q 30,
 * --vtk=F, "--"); the edges of every number kind (largest int64 for -S and one more, the
 * largest uint64 seed and one more, --subdomains 1 and 1000001, --imbalance just above 0);
 * what strict reading refuses (blanks, hexadecimal, NaN, infinities, trailing characters,
 * empty strings); the usage-error status and its one line; --help's status and its text (exit
 * statuses, every option of the program and none of another program's).
 */
#include "../apps/cli.h"

#include <check.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Parses the NULL-terminated argument list for p; returns -1 when parsing goes on, else the
 * exit status; *msg (if not NULL) gets what went to stderr or stdout. */
static int parse(const cli_prog *p, cli_opts *o, char *msg, size_t msglen, ...) {
    char *argv[32];
    int argc = 0;
    argv[argc++] = (char *)p->name;
    va_list ap;
    va_start(ap, msglen);
    for (char *a; (a = va_arg(ap, char *)) != NULL;)
        argv[argc++] = a;
    va_end(ap);
    argv[argc] = NULL;
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    ck_assert_ptr_nonnull(f);
    int status = -7;
    int stop = cli_parse(p, argc, argv, f, f, o, &status);
    fclose(f);
    if (msg) snprintf(msg, msglen, "%s", buf ? buf : "");
    free(buf);
    return stop ? status : -1;
}

START_TEST(test_defaults) {
    cli_opts o;
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "in.poly", NULL), -1);
    ck_assert_str_eq(o.par.prog, "mesh");
    ck_assert_str_eq(o.par.input, "in.poly");
    ck_assert(o.par.min_angle == 20.7);
    ck_assert(o.par.max_area == 0);
    ck_assert_int_eq(o.par.max_steiner, -1);
    ck_assert_ptr_null(o.par.out_prefix);
    ck_assert_int_eq(o.par.stats + o.par.check + o.par.circumcenters + o.lens + o.cdt_only, 0);
    ck_assert_int_eq(parse(&cli_pbw, &o, NULL, 0, "in.poly", NULL), -1);
    ck_assert(o.par.min_angle == 20.7);
    ck_assert(o.par.imbalance == 1);
    ck_assert_int_eq(o.par.nsub, 0);
    ck_assert_int_eq(o.par.max_steiner, -1);
    ck_assert_uint_eq(o.par.perturb, 0);
    ck_assert_int_eq(parse(&cli_meshcheck, &o, NULL, 0, "in.poly", "out", NULL), -1);
    ck_assert(o.par.min_angle == 0); /* the validator checks no bound unless told */
    ck_assert(o.par.max_area == 0);
    ck_assert_str_eq(o.mesh_prefix, "out");
}
END_TEST

START_TEST(test_spellings) {
    cli_opts o;
    char msg[512];
    ck_assert_int_eq(parse(&cli_pcdm, &o, msg, sizeof msg, "-q30", "-a", "0.5", "--vtk=v.vtk",
                           "--svg", "s.svg", "-oout", "--stats", "--check", "--progress",
                           "--subdomains=8", "--imbalance", "2.5", "--perturb", "7", "--",
                           "-x.poly", NULL),
                     -1);
    ck_assert(o.par.min_angle == 30 && o.par.max_area == 0.5);
    ck_assert_str_eq(o.par.vtk, "v.vtk");
    ck_assert_str_eq(o.par.svg, "s.svg");
    ck_assert_str_eq(o.par.out_prefix, "out");
    ck_assert_int_eq(o.par.stats + o.par.check + o.par.progress, 3);
    ck_assert_int_eq(o.par.nsub, 8);
    ck_assert(o.par.imbalance == 2.5);
    ck_assert_uint_eq(o.par.perturb, 7);
    ck_assert_str_eq(o.par.input, "-x.poly");
    ck_assert_str_eq(msg, "");
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "--circumcenters", "--lens", "--cdt-only",
                           "in.poly", "-q", "0", NULL),
                     -1);
    ck_assert_int_eq(o.par.circumcenters + o.lens + o.cdt_only, 3);
    ck_assert(o.par.min_angle == 0);
}
END_TEST

START_TEST(test_number_edges) {
    cli_opts o;
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-S", "9223372036854775807", "i", NULL), -1);
    ck_assert_int_eq(o.par.max_steiner, INT64_MAX);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-S", "9223372036854775808", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pbw, &o, NULL, 0, "--perturb", "18446744073709551615", "i", NULL),
                     -1);
    ck_assert_uint_eq(o.par.perturb, UINT64_MAX);
    ck_assert_int_eq(parse(&cli_pbw, &o, NULL, 0, "--perturb", "18446744073709551616", "i", NULL),
                     2);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--subdomains", "1", "i", NULL), -1);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--subdomains", "1000000", "i", NULL), -1);
    ck_assert_int_eq(o.par.nsub, 1000000);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--subdomains", "1000001", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--subdomains", "0", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--imbalance", "1e-9", "i", NULL), -1);
    ck_assert(o.par.imbalance == 1e-9);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-q", "60", "-a", "1e300", "i", NULL), -1);
    ck_assert(o.par.min_angle == 60 && o.par.max_area == 1e300);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-q", "60.000001", "i", NULL), 2);
}
END_TEST

START_TEST(test_strict) {
    static const char *const bad_reals[] = {"nan", "NAN", "-nan", "inf",  "+Inf",  "infinity",
                                            " 30", "30 ", "30x",  "0x1e", "1e400", "-1",
                                            "",    ".",   "e5",   "1e",   "--1",   "1,5"};
    cli_opts o;
    char msg[512];
    for (size_t k = 0; k < sizeof bad_reals / sizeof *bad_reals; k++) {
        for (int opt = 0; opt < 2; opt++) {
            const char *name = opt ? "-a" : "-q";
            int st = parse(&cli_mesh, &o, msg, sizeof msg, name, bad_reals[k], "i", NULL);
            ck_assert_msg(st == 2, "%s '%s' gave status %d", name, bad_reals[k], st);
            ck_assert_msg(strchr(msg, '\n') == msg + strlen(msg) - 1, "not one line: %s", msg);
            ck_assert_msg(strstr(msg, "(try --help)") && !strncmp(msg, "mesh: ", 6), "%s", msg);
        }
    }
    static const char *const bad_ints[] = {"1.0", "1e3", " 5", "5 ", "0x10", "-", "+", ""};
    for (size_t k = 0; k < sizeof bad_ints / sizeof *bad_ints; k++)
        ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-S", bad_ints[k], "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--perturb", "+5", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-o", "", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "--vtk=", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "+1.5e1", "i", NULL), 2); /* two inputs */
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "-q", "+1.5e1", "i", NULL), -1);
    ck_assert(o.par.min_angle == 15);
}
END_TEST

START_TEST(test_usage_errors) {
    cli_opts o;
    char msg[512];
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, NULL), 2);
    ck_assert_str_eq(msg,
                     "mesh: missing input.poly; usage: ./mesh [options] input.poly (try --help)\n");
    ck_assert_int_eq(parse(&cli_meshcheck, &o, msg, sizeof msg, "in", NULL), 2);
    ck_assert_ptr_nonnull(strstr(msg, "missing PREFIX"));
    ck_assert_int_eq(parse(&cli_meshcheck, &o, msg, sizeof msg, "in", "out", "more", NULL), 2);
    ck_assert_ptr_nonnull(strstr(msg, "unexpected argument 'more'"));
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "i", "-q", NULL), 2);
    ck_assert_str_eq(msg, "mesh: option -q needs a value (DEG) (try --help)\n");
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "--stats=yes", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "--stat", "i", NULL), 2);
    ck_assert_str_eq(msg, "mesh: unknown option '--stat' (try --help)\n");
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "-hq", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pcdm, &o, NULL, 0, "--phases", "i", NULL), 2);
    ck_assert_int_eq(parse(&cli_pbw, &o, NULL, 0, "--phases", "i", NULL), -1);
    ck_assert_int_eq(o.par.phases, 1);
    ck_assert_int_eq(parse(&cli_meshcheck, &o, NULL, 0, "-S", "5", "i", "o", NULL), 2);
    ck_assert_int_eq(parse(&cli_mesh, &o, NULL, 0, "--interfaces-delaunay", "i", NULL), 2);
    /* a warning is not an error */
    ck_assert_int_eq(parse(&cli_mesh, &o, msg, sizeof msg, "-q", "35", "i", NULL), -1);
    ck_assert_str_eq(msg, "mesh: warning: -q 35 above about 34 degrees may not terminate\n");
    ck_assert_int_eq(parse(&cli_meshcheck, &o, msg, sizeof msg, "-q", "35", "i", "o", NULL), -1);
    ck_assert_str_eq(msg, "");
}
END_TEST

START_TEST(test_help) {
    const cli_prog *progs[] = {&cli_mesh, &cli_meshcheck, &cli_pcdm, &cli_pbw};
    /* options that belong to one program only must appear in its --help alone */
    const char *only[] = {"--cdt-only", "--interfaces-delaunay", NULL, "--phases"};
    for (int k = 0; k < 4; k++) {
        cli_opts o;
        char msg[8192];
        ck_assert_int_eq(parse(progs[k], &o, msg, sizeof msg, "--help", NULL), 0);
        ck_assert_msg(!strncmp(msg, "usage: ", 7), "%s", msg);
        ck_assert_ptr_nonnull(strstr(msg, "Exit status: 0 success; 1 bad input"));
        ck_assert_ptr_nonnull(strstr(msg, "2 usage error"));
        ck_assert_ptr_nonnull(strstr(msg, "-h, --help"));
        for (int j = 0; j < 4; j++)
            if (only[j])
                ck_assert_msg(!strstr(msg, only[j]) == (j != k), "%s --help and %s", progs[k]->name,
                              only[j]);
        ck_assert_int_eq(parse(progs[k], &o, msg, sizeof msg, "-h", NULL), 0);
    }
    cli_opts o;
    char msg[8192];
    parse(&cli_pcdm, &o, msg, sizeof msg, "--help", NULL);
    ck_assert_ptr_nonnull(strstr(msg, "(default: 20.7)"));
    ck_assert_ptr_nonnull(strstr(msg, "--subdomains K"));
    ck_assert_ptr_nonnull(strstr(msg, "Every rank exits with the same status."));
}
END_TEST

int main(void) {
    Suite *s = suite_create("cli");
    TCase *tc = tcase_create("core");
    tcase_add_test(tc, test_defaults);
    tcase_add_test(tc, test_spellings);
    tcase_add_test(tc, test_number_edges);
    tcase_add_test(tc, test_strict);
    tcase_add_test(tc, test_usage_errors);
    tcase_add_test(tc, test_help);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int nf = srunner_ntests_failed(sr);
    srunner_free(sr);
    return nf ? 1 : 0;
}
